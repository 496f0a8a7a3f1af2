"""``adobe_bsdf.conformance``: a candidate written elsewhere judged against the library.

The candidate here is a GGX conductor written for the test from the papers (anisotropic
D and height-correlated Smith masking [Heitz2014, eqs. 85-86, 99], visible-normal sampling
[Heitz2018, Listing 1]), not from the library's code: correct, it conforms to
``lobes.Conductor``; each deliberate fault fails the check that should catch it.
"""

import json

import numpy as np
import pytest

from adobe_bsdf import lobes, validation
from adobe_bsdf.conformance import (
    CandidateError,
    FunctionCandidate,
    Report,
    as_lobe,
    assert_conforms,
    compare,
)

ALPHA_X, ALPHA_Y = 0.3, 0.1
N = 100_000


class HandGGX:
    """An anisotropic GGX conductor with a constant Fresnel, and optional faults."""

    name = "hand-written GGX"

    def __init__(self, fresnel=1.0, pdf_scale=1.0, fold=False, isotropic_sampler=False,
                 nan_grazing=False, nonreciprocal=False):
        self.fresnel, self.pdf_scale, self.fold = fresnel, pdf_scale, fold
        self.isotropic_sampler, self.nan_grazing = isotropic_sampler, nan_grazing
        self.nonreciprocal = nonreciprocal

    @staticmethod
    def _lambda(w, ax, ay):
        a2 = (ax * ax * w[..., 0] ** 2 + ay * ay * w[..., 1] ** 2) / w[..., 2] ** 2
        return 0.5 * (np.sqrt(1.0 + a2) - 1.0)

    @staticmethod
    def _D(m, ax, ay):
        t = (m[..., 0] / ax) ** 2 + (m[..., 1] / ay) ** 2 + m[..., 2] ** 2
        return 1.0 / (np.pi * ax * ay * t * t)

    def _f(self, wo, wi):
        up = (wo[..., 2] > 0) & (wi[..., 2] > 0)
        h = wo + wi
        h = h / np.maximum(np.linalg.norm(h, axis=-1, keepdims=True), 1e-300)
        with np.errstate(divide="ignore", invalid="ignore"):
            G2 = 1.0 / (1.0 + self._lambda(wo, ALPHA_X, ALPHA_Y)
                        + self._lambda(wi, ALPHA_X, ALPHA_Y))
            f = self.fresnel * self._D(h, ALPHA_X, ALPHA_Y) * G2 / (
                4.0 * wo[..., 2] * wi[..., 2])
        return np.where(up, f, 0.0)

    def _pdf(self, wo, wi, ax, ay):
        up = (wo[..., 2] > 0) & (wi[..., 2] > 0)
        h = wo + wi
        h = h / np.maximum(np.linalg.norm(h, axis=-1, keepdims=True), 1e-300)
        with np.errstate(divide="ignore", invalid="ignore"):
            G1 = 1.0 / (1.0 + self._lambda(wo, ax, ay))
            p = G1 * self._D(h, ax, ay) / (4.0 * wo[..., 2])
        return np.where(up, p * self.pdf_scale, 0.0)

    def eval(self, wo, wi):
        f = self._f(wo, wi)
        if self.fold:
            f = f * np.abs(wi[..., 2])
        if self.nonreciprocal:
            f = f * (1.0 + 0.2 * (wo[..., 2] - wi[..., 2]))
        if self.nan_grazing:
            f = np.where(np.abs(wi[..., 2]) < 0.02, np.nan, f)
        return f  # grey: the library widens it

    def pdf(self, wo, wi):
        return self._pdf(wo, wi, ALPHA_X, ALPHA_Y)

    def sample(self, wo, u):
        ax, ay = ((np.sqrt(ALPHA_X * ALPHA_Y),) * 2 if self.isotropic_sampler
                  else (ALPHA_X, ALPHA_Y))
        # [Heitz2018]: the hemisphere configuration, the projected disk, back
        v = np.stack([ax * wo[..., 0], ay * wo[..., 1], wo[..., 2]], -1)
        v /= np.linalg.norm(v, axis=-1, keepdims=True)
        lensq = v[..., 0] ** 2 + v[..., 1] ** 2
        t1 = np.where(lensq[..., None] > 0,
                      np.stack([-v[..., 1], v[..., 0], np.zeros_like(lensq)], -1)
                      / np.sqrt(np.where(lensq > 0, lensq, 1.0))[..., None],
                      np.array([1.0, 0.0, 0.0]))
        t2 = np.cross(v, t1)
        r, phi = np.sqrt(u[..., 1]), 2.0 * np.pi * u[..., 2]
        p1, p2 = r * np.cos(phi), r * np.sin(phi)
        s = 0.5 * (1.0 + v[..., 2])
        p2 = (1.0 - s) * np.sqrt(1.0 - p1 * p1) + s * p2
        n = (p1[..., None] * t1 + p2[..., None] * t2
             + np.sqrt(np.maximum(0.0, 1.0 - p1 * p1 - p2 * p2))[..., None] * v)
        m = np.stack([ax * n[..., 0], ay * n[..., 1], np.maximum(1e-12, n[..., 2])], -1)
        m /= np.linalg.norm(m, axis=-1, keepdims=True)
        wi = 2.0 * np.sum(wo * m, -1, keepdims=True) * m - wo
        pdf = self._pdf(wo, wi, ax, ay)
        with np.errstate(divide="ignore", invalid="ignore"):
            weight = np.where(pdf > 0, self._f(wo, wi) * np.abs(wi[..., 2]) / pdf, 0.0)
        return wi, weight, pdf


REFERENCE = lobes.Conductor(ALPHA_X, ALPHA_Y)


def _failed(report: Report) -> set:
    return {c.name for c in report.checks if c.passed is False}


def test_a_correct_candidate_conforms():
    """Written independently from the papers, it passes every check."""
    report = compare(REFERENCE, HandGGX(), n_samples=N)
    assert report.passed, str(report)
    assert {c.name for c in report.checks} == {
        "finite", "eval", "pdf", "weight", "chi2 (own pdf)", "chi2 (reference pdf)",
        "albedo", "reciprocity"}
    assert all(c.passed for c in report.checks)


@pytest.mark.parametrize("fault, kwargs, catches, cause", [
    ("Fresnel 3 % low", dict(fresnel=0.97), {"eval", "albedo"}, "0.97 x reference"),
    ("pdf 5 % high", dict(pdf_scale=1.05), {"pdf", "chi2 (own pdf)", "albedo"}, ""),
    ("cosine folded into f", dict(fold=True), {"eval", "weight"}, "cosine folded in"),
    ("non-reciprocal f", dict(nonreciprocal=True), {"reciprocity"}, ""),
    ("NaN at grazing angles", dict(nan_grazing=True), {"finite"}, "grazing"),
    ("sampler ignores anisotropy", dict(isotropic_sampler=True),
     {"chi2 (own pdf)", "chi2 (reference pdf)"}, ""),
])
def test_a_deliberate_fault_fails_its_check(fault, kwargs, catches, cause):
    report = compare(REFERENCE, HandGGX(**kwargs), n_samples=N)
    assert not report.passed, fault
    failed = _failed(report)
    assert catches <= failed, (fault, failed)
    if cause:
        assert any(cause in c.cause for c in report.checks if c.passed is False), str(report)


def test_the_report_reads_as_table_markdown_and_json():
    report = compare(REFERENCE, HandGGX(fresnel=0.97), n_samples=20_000)
    text = str(report)
    assert "DOES NOT CONFORM" in text and "eval" in text and "FAIL" in text
    assert report.markdown().count("\n| ") == len(report.checks) + 1
    data = json.loads(report.to_json())
    assert data["passed"] is False
    assert {t["name"] for t in data["tests"] if t["verdict"] == "FAIL"} == _failed(report)
    with pytest.raises(AssertionError, match="(?s)eval.*FAIL.*0.97 x reference"):
        assert_conforms(REFERENCE, HandGGX(fresnel=0.97), n_samples=20_000)
    assert assert_conforms(REFERENCE, HandGGX(), n_samples=20_000).passed


def test_another_sampling_strategy_is_not_held_to_the_reference_pdf():
    """Cosine-weighted sampling of a correct f: with ``same_sampling=False`` its pdf and
    samples are checked against its own pdf only."""
    hand = HandGGX()

    def sample(wo, u):
        r, phi = np.sqrt(u[..., 1]), 2.0 * np.pi * u[..., 2]
        wi = np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(1.0 - u[..., 1])], -1)
        pdf = wi[..., 2] / np.pi
        return wi, hand.eval(wo, wi) * np.pi, pdf

    cosine = FunctionCandidate(hand.eval, lambda wo, wi: np.where(
        (wo[..., 2] > 0) & (wi[..., 2] > 0), wi[..., 2] / np.pi, 0.0), sample, "cosine")
    report = compare(REFERENCE, cosine, n_samples=N, same_sampling=False)
    assert report.passed, str(report)
    assert {c.name for c in report.checks if c.passed is None} == {
        "pdf", "chi2 (reference pdf)"}
    assert not compare(REFERENCE, cosine, n_samples=20_000).passed


def test_a_candidate_that_raises_or_answers_wrongly_is_reported():
    hand = HandGGX()
    broken = FunctionCandidate(hand.eval, hand.pdf, lambda wo, u: (wo[..., :2], 1.0, 1.0),
                               "wrong shape")
    report = compare(REFERENCE, broken, n_samples=20_000)
    assert not report.passed
    assert "sample() returned directions of shape" in report.checks[-1].cause

    def fails(wo, wi):
        raise RuntimeError("device lost")
    report = compare(REFERENCE, FunctionCandidate(fails, hand.pdf, hand.sample, "raises"),
                     n_samples=20_000)
    assert "eval() of" in report.checks[-1].cause and "device lost" in report.checks[-1].cause
    with pytest.raises(ValueError, match="no method eval"):
        as_lobe(object())
    with pytest.raises(CandidateError, match="not numbers"):
        as_lobe(FunctionCandidate(lambda wo, wi: "x", hand.pdf, hand.sample)).eval(
            np.array([0, 0, 1.0]), np.array([0, 0, 1.0]))


def test_every_validation_check_takes_a_candidate():
    """No subclassing: the toolkit's checks run on an object with eval, pdf and sample."""
    hand = HandGGX()
    wo = np.array([0.3, 0.2, np.sqrt(0.87)])
    assert validation.chi2_test(hand, wo, n_samples=N).passed
    assert validation.weight_consistency(hand, wo, n_samples=20_000).passed
    assert validation.pdf_integral(hand, wo, expected=None, tol=1e-3).passed
    pairs = np.random.default_rng(3).normal(size=(2, 200, 3))
    pairs /= np.linalg.norm(pairs, axis=-1, keepdims=True)
    pairs[..., 2] = np.abs(pairs[..., 2])
    assert validation.reciprocity_error(hand, *pairs).passed
    E = REFERENCE.albedo(wo, method="quadrature", tol=1e-6)[..., 0]
    assert validation.furnace(hand, wo, E, method="quadrature", tol=1e-4).passed
    assert validation.mc_albedo_consistency(hand, wo, n_samples=N).passed
    wrong = validation.chi2_test(HandGGX(isotropic_sampler=True), wo, n_samples=N)
    assert not wrong.passed
    assert f"p = {wrong.p_value:.3g}" in str(wrong) and "false-alarm rate of 0.01" in str(wrong)
    folded = validation.weight_consistency(HandGGX(fold=True), wo, n_samples=20_000)
    assert not folded.passed and "likely cause: eval has the cosine folded in" in str(folded)
    assert "worst at wo = " in str(folded)


def _mitsuba_views():
    return np.array([[0.3, 0.2, np.sqrt(0.87)], [0.5, 0.6, -np.sqrt(0.39)]])


def test_mitsuba_conductor_conforms_with_its_masking_stated():
    """Mitsuba 3's anisotropic ``roughconductor`` (a plugin dictionary) conforms to
    ``lobes.Conductor`` with Mitsuba's separable masking; against the default
    height-correlated masking its f differs where the masking does."""
    pytest.importorskip("mitsuba")
    from adobe_bsdf.validation.mitsuba import MitsubaBSDF

    conductor = MitsubaBSDF({"type": "roughconductor", "distribution": "ggx",
                             "alpha_u": ALPHA_X, "alpha_v": ALPHA_Y, "sample_visible": True,
                             "eta": {"type": "rgb", "value": [0, 0, 0]},
                             "k": {"type": "rgb", "value": [1, 1, 1]}})
    report = compare(lobes.Conductor(ALPHA_X, ALPHA_Y, masking="separable"), conductor,
                     views=_mitsuba_views()[:1], n_samples=N)
    assert report.passed, str(report)
    correlated = compare(REFERENCE, conductor, views=_mitsuba_views()[:1], n_samples=20_000)
    assert "eval" in _failed(correlated)


@pytest.mark.slow  # Mitsuba's pdf one pair at a time under the chi-square's cubature: 90 s
def test_mitsuba_dielectric_conforms_from_both_sides_in_float32():
    """Mitsuba 3's anisotropic ``roughdielectric`` (its XML), seen from both sides,
    conforms to ``lobes.Dielectric`` with separable masking, its float32 ill-conditioned
    pairs left out and counted."""
    pytest.importorskip("mitsuba")
    from adobe_bsdf.validation.mitsuba import MitsubaBSDF

    dielectric = MitsubaBSDF(
        '<bsdf type="roughdielectric"><string name="distribution" value="ggx"/>'
        f'<float name="alpha_u" value="{ALPHA_X}"/><float name="alpha_v" value="{ALPHA_Y}"/>'
        '<float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>')
    assert dielectric.eta == 1.5
    separable = lobes.Dielectric(1.5, ALPHA_X, ALPHA_Y, masking="separable")
    report = compare(separable, dielectric, views=_mitsuba_views(), n_samples=N,
                     float32=True)
    assert report.passed, str(report)
    assert "ill-conditioned in float32 left out" in next(
        c.note for c in report.checks if c.name == "eval")


def test_the_command_line_names_references_and_judges_a_mitsuba_plugin(tmp_path, capsys):
    """``python -m adobe_bsdf conform``: a reference as words (material, lobe, .mtlx, check
    case), a Mitsuba candidate, the table printed, markdown and JSON written, exit 0 where
    it conforms, 1 where not, 2 with a one-line error for what it cannot read."""
    pytest.importorskip("mitsuba")
    from adobe_bsdf.__main__ import main
    from adobe_bsdf.conformance.cli import reference_from_words
    from adobe_bsdf.materials import AdobeStandardMaterial, OpenPBRSurface

    asm = reference_from_words(["ASM", "roughness=0.3", "metallic=1", "base_color=1,0.5,0.2"])
    assert isinstance(asm, AdobeStandardMaterial) and float(asm.params["roughness"]) == 0.3
    assert isinstance(reference_from_words(["OpenPBR", "coat_weight=1"]), OpenPBRSurface)
    lobe = reference_from_words(["Conductor", "alpha_x=0.3", "alpha_y=0.1",
                                 "masking=separable"])
    assert lobe.distribution.masking == "separable"
    assert reference_from_words(["Conductor a=0.1 F=1"]) is not None  # a check case
    plugin = json.dumps({"type": "roughconductor", "distribution": "ggx", "alpha_u": ALPHA_X,
                         "alpha_v": ALPHA_Y, "eta": {"type": "rgb", "value": [0, 0, 0]},
                         "k": {"type": "rgb", "value": [1, 1, 1]}})
    common = ["--candidate", f"mitsuba:{plugin}", "--view", "0.5", "0.3", "--samples",
              "20000"]
    code = main(["conform", "Conductor", f"alpha_x={ALPHA_X}", f"alpha_y={ALPHA_Y}",
                 "masking=separable", *common, "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert code == 0 and "conforms" in out and "chi2 (own pdf)" in out
    assert json.loads((tmp_path / "report.json").read_text())["passed"] is True
    assert (tmp_path / "report.md").read_text().startswith("# Mitsuba roughconductor")
    assert main(["conform", "Conductor", f"alpha_x={ALPHA_X}", f"alpha_y={ALPHA_Y}",
                 *common]) == 1  # height-correlated masking: eval differs
    capsys.readouterr()
    for words, candidate, says in (
            (["NoSuchThing"], f"mitsuba:{plugin}", "no material"),
            (["Conductor", "0.3"], f"mitsuba:{plugin}", "name=value"),
            (["Conductor", "alpha_x=0.3"], "renderer:x", "allowed mitsuba:JSON"),
            (["Conductor", "alpha_x=0.3"], "mitsuba:{bad", "not JSON")):
        assert main(["conform", *words, "--candidate", candidate]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and says in err, err


@pytest.mark.parametrize("suffix", [".jsonl", ".npz"])
def test_the_file_protocol_judges_a_renderers_answers(tmp_path, suffix):
    """Request written, answered as a renderer would (here by a Python candidate), read
    back: a correct candidate conforms, a 3 % low Fresnel fails on eval and albedo."""
    from adobe_bsdf.conformance import answer_request, read_answers, write_request

    request, answers = tmp_path / f"request{suffix}", tmp_path / f"answers{suffix}"
    write_request(request, REFERENCE, n_samples=20_000)
    answer_request(request, HandGGX(), answers)
    report = compare(REFERENCE, read_answers(answers, request))
    assert report.passed, str(report)
    assert next(c for c in report.checks if c.name == "chi2 (own pdf)").passed is None
    answer_request(request, HandGGX(fresnel=0.97), answers)
    assert {"eval", "albedo"} <= _failed(compare(REFERENCE, read_answers(answers, request)))


def test_answer_files_it_cannot_use_are_named_by_line_and_field(tmp_path):
    from adobe_bsdf.conformance import answer_request, read_answers, write_request

    request, answers = tmp_path / "request.jsonl", tmp_path / "answers.jsonl"
    write_request(request, REFERENCE, n_samples=2_000, views=[[0.3, 0.2, np.sqrt(0.87)]])
    answer_request(request, HandGGX(), answers)
    lines = answers.read_text().splitlines()
    bad = tmp_path / "bad.jsonl"

    def refused(text, *says):
        bad.write_text(text)
        with pytest.raises(ValueError) as info:
            read_answers(bad, request)
        for part in says:
            assert part in str(info.value), str(info.value)

    refused("\n".join(lines[:-10]) + "\n", "bad.jsonl", "unanswered", "truncated")
    refused("\n".join(lines[:2] + ['{"id": 2, "f": [1, 2], "pdf": 1}'] + lines[3:]),
            "line 3", "'f'", "list of 3 numbers")
    refused("\n".join(lines[:4] + ["{not json"] + lines[5:]), "line 5", "not JSON")
    refused("\n".join(lines + [lines[0]]), "answered twice")
    last = json.loads(lines[-1])
    last["wi"] = [0.0, 0.0, 2.0]
    last["pdf"] = 1.0
    refused("\n".join(lines[:-1] + [json.dumps(last)]), "off the sphere", "'wi'")
    npz = tmp_path / "answers.npz"
    np.savez(npz, eval_f=np.zeros((3, 3)))
    with pytest.raises(ValueError, match="no array 'eval_pdf'|shape"):
        read_answers(npz, request)
    text = request.read_text().splitlines()
    query = json.loads(text[1])
    query["wi"] = [0.0, 0.0, 1.0]
    changed = tmp_path / "changed.jsonl"
    changed.write_text("\n".join([text[0], json.dumps(query)] + text[2:]) + "\n")
    with pytest.raises(ValueError, match="the file was changed"):
        read_answers(answers, changed)


def test_the_documented_cpp_answerer_conforms(tmp_path):
    """The C++ answerer of docs/conformance.md, compiled and run on a request: its GGX
    conforms to lobes.Conductor."""
    import re
    import shutil
    import subprocess
    from pathlib import Path

    from adobe_bsdf.conformance import read_answers, write_request

    compiler = shutil.which("g++") or shutil.which("clang++")
    if compiler is None:
        pytest.skip("no C++ compiler (g++ or clang++) on this machine")
    page = (Path(__file__).resolve().parents[1] / "docs" / "conformance.md").read_text()
    code = re.search(r"<!-- answerer -->\n```cpp\n(.*?)```", page, re.S).group(1)
    (tmp_path / "answer.cpp").write_text(code)
    subprocess.run([compiler, "-O2", "-std=c++17", "answer.cpp", "-o", "answer"],
                   cwd=tmp_path, check=True)
    request, answers = tmp_path / "request.jsonl", tmp_path / "answers.jsonl"
    write_request(request, REFERENCE, n_samples=20_000)
    with request.open() as stdin, answers.open("w") as stdout:
        subprocess.run([str(tmp_path / "answer"), str(ALPHA_X), str(ALPHA_Y)], stdin=stdin,
                       stdout=stdout, check=True)
    report = compare(REFERENCE, read_answers(answers, request))
    assert report.passed, str(report)


def test_the_command_line_writes_a_request_and_judges_its_answers(tmp_path, capsys):
    from adobe_bsdf.__main__ import main
    from adobe_bsdf.conformance import answer_request

    words = ["conform", "Conductor", f"alpha_x={ALPHA_X}", f"alpha_y={ALPHA_Y}"]
    request, answers = tmp_path / "request.npz", tmp_path / "answers.npz"
    assert main([*words, "--write-request", str(request), "--samples", "5000"]) == 0
    answer_request(request, HandGGX(), answers)
    assert main([*words, "--candidate", str(answers), "--request", str(request)]) == 0
    assert "conforms" in capsys.readouterr().out
    assert main([*words, "--candidate", str(answers)]) == 2
    assert "needs --request" in capsys.readouterr().err
    assert main(words) == 2 and "one of them" in capsys.readouterr().err


def test_the_figure_shows_both_slices_and_their_difference():
    from adobe_bsdf.conformance import difference_map, figure

    wo = np.array([0.3, 0.2, np.sqrt(0.87)])
    assert np.abs(difference_map(REFERENCE, HandGGX(), wo, size=24)).max() < 1e-12
    low = difference_map(REFERENCE, HandGGX(fresnel=0.97), wo, size=24)
    # -0.03 |r| / (|r| + 1e-3 max |r|): -0.03 / 1.001 at the peak
    assert -0.03 < np.nanmin(low) < -0.0299 and np.nanmax(low) <= 0.0
    fig = figure(REFERENCE, HandGGX(fresnel=0.97), wo, size=24)
    assert len(fig.axes) == 4  # two polar slices, the map and its colourbar
    import matplotlib.pyplot as plt
    plt.close(fig)


def test_the_cost_page_smoke(tmp_path):
    from benchmarks import conformance_cost

    assert conformance_cost.main(["--smoke", "--out", str(tmp_path)]) == 0
    page = (tmp_path / conformance_cost.NAME).read_text()
    assert "| ASM dielectric" in page and "conforms |" in page


def test_a_random_walk_reference_judges_the_fast_openpbr_model():
    """The structure itself as the reference (``OpenPBRSurface.reference``): its eval within
    its Monte-Carlo error, its pdf not compared; a bare metal, where the fast model is the
    structure, conforms; a coat, whose fast layering differs at grazing light, does not."""
    from adobe_bsdf.materials import OpenPBRSurface, presets

    metal = OpenPBRSurface(**presets.openpbr["copper"])
    report = compare(metal.reference(), metal, n_samples=20_000, progress=False)
    assert report.passed, report
    checks = {c.name: c for c in report.checks}
    assert checks["pdf"].passed is None and "estimate" in checks["pdf"].note
    assert "Monte-Carlo estimate" in checks["eval"].note
    coated = OpenPBRSurface(**presets.openpbr["coated blue"])
    report = compare(coated.reference(), coated, n_samples=20_000, progress=False)
    assert not {c.name: c for c in report.checks}["eval"].passed
