"""Smoke test of ``python -m benchmarks --smoke``: it runs (tiny sizes) in a subprocess, writes
``results.json`` and ``performance.md`` into a temporary folder only, and every section has
its expected structure with positive timings. Speed itself is not asserted. Passes with or
without Mitsuba / a shared libLLVM (the Mitsuba section then says why it is unavailable) and
without matplotlib (no plots)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from adobe_bsdf import paper_figures

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def smoke(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    before = {p: p.stat().st_mtime_ns for p in (ROOT / "benchmarks" / "results.json",
                                                ROOT / "docs" / "performance.md") if p.exists()}
    proc = subprocess.run([sys.executable, "-m", "benchmarks", "--smoke", "--out", str(out)],
                          cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-4000:]
    after = {p: p.stat().st_mtime_ns for p in before}
    assert after == before, "the smoke run touched the repository's results"
    results = json.loads((out / "results.json").read_text(encoding="utf-8"))
    return out, results, (out / "performance.md").read_text(encoding="utf-8")


def _positive(row):
    assert row["seconds"] > 0 and row["evals_per_s"] > 0 and row["memory_passes"] > 0, row
    assert len(row["times"]) >= 2 and all(t > 0 for t in row["times"]), row


def test_machine_facts(smoke):
    _, results, _ = smoke
    m = results["machine"]
    assert results["smoke"] is True
    assert m["cores"] >= 1 and m["python"] and m["numpy"] and m["date_utc"]
    assert results["total_seconds"] > 0


def test_throughput_covers_every_case(smoke):
    import adobe_bsdf  # noqa: F401  (registers the cases)
    from adobe_bsdf.validation.cases import cases

    _, results, _ = smoke
    tp = results["throughput"]
    assert "error" not in tp, tp.get("error")
    assert tp["sizes"] == [10**3, 10**4] and tp["runs"] == 2
    measured = {(r["case"], r["call"], r["n"]) for r in tp["rows"] if "seconds" in r}
    for case in cases():
        for call in ("eval", "pdf", "sample"):
            for n in tp["sizes"]:
                assert (case.name, call, n) in measured, (case.name, call, n)
    for row in tp["rows"]:
        assert "error" not in row, row
        _positive(row)
    assert all(v > 0 for v in tp["memory_pass_seconds"].values())


def test_headline(smoke):
    _, results, _ = smoke
    hl = results["headline"]
    assert "error" not in hl, hl.get("error")
    assert set(hl["labels"]) == {"conductor", "dielectric"}
    keys = {(r["lobe"], r["call"], r["threads"]) for r in hl["rows"]}
    for lobe in ("conductor", "dielectric"):
        for call in ("eval", "pdf", "sample"):
            for threads in hl["threads"]:
                assert (lobe, call, threads) in keys
    for row in hl["rows"]:
        _positive(row)


def test_mitsuba_section_available_or_explained(smoke):
    _, results, text = smoke
    mi = results["mitsuba"]
    assert "error" not in mi, mi.get("error")
    if not mi["available"]:
        assert mi["reason"]
        assert "Not available" in text
        return
    rows = {(r["lobe"], r["call"]): r for r in mi["rows"]}
    assert set(rows) == {(lobe, call) for lobe in ("conductor", "dielectric")
                         for call in ("eval", "pdf", "sample")}
    for r in rows.values():
        assert r["first_seconds"] > 0 and r["median_seconds"] > 0
    inter = {(r["lobe"], r["call"]): r for r in mi["interleaved"]["rows"]}
    assert set(inter) == set(rows)
    for r in inter.values():
        assert len(r["numpy_times"]) == len(r["mitsuba_times"]) == mi["interleaved"]["rounds"]
        assert r["numpy_seconds"] > 0 and r["mitsuba_seconds"] > 0 and r["ratio"] > 0
    agreement = mi["agreement"]
    if "error" not in agreement:  # older lobes without a masking option
        assert all(v["max_relative_difference"] < 1e-3 for v in agreement.values())


def test_baseline_before_after(smoke):
    """The headline of the library before the performance work, timed in the same run."""
    _, results, text = smoke
    base = results["baseline"]
    assert "error" not in base, base.get("error")
    assert len(base["commit"]) == 40 and base["subject"]
    rows = {(r["lobe"], r["call"]) for r in base["headline"]["rows"] if "seconds" in r}
    assert {("conductor", "eval"), ("dielectric", "eval")} <= rows
    for row in base["headline"]["rows"]:
        _positive(row)
    assert "## Before and after" in text and "conductor `eval`:" in text


def test_chunks(smoke):
    _, results, text = smoke
    ch = results["chunks"]
    assert "error" not in ch, ch.get("error")
    assert {(r["chunk_size"], r["threads"], r["lobe"]) for r in ch["rows"]} == {
        (size, t, key) for size in ch["sizes"] for t in ch["threads"]
        for key in ("conductor", "dielectric")}
    assert all(r["seconds"] > 0 for r in ch["rows"])
    if ch["cpus"] > 1:
        assert all(ch["two_processes"][key] > 0 for key in ("conductor", "dielectric"))
    assert "## Chunk size and threads" in text


def test_active_lobes(smoke):
    _, results, _ = smoke
    al = results["active_lobes"]
    assert "error" not in al, al.get("error")
    assert [r["k"] for r in al["rows"]] == list(range(al["K"] + 1))
    for r in al["rows"]:
        assert "error" not in r, r
        for call in ("eval", "sample"):
            if call in r:
                assert r[call]["seconds"] > 0
    assert sum("eval" in r for r in al["rows"]) >= al["K"]


def test_markdown_written(smoke):
    out, results, text = smoke
    assert text.startswith("<!-- written by python -m benchmarks; do not edit by hand -->")
    for heading in ("## Headline", "## Before and after", "## Mitsuba 3 reference", "## Threads",
                    "## Chunk size and threads",
                    "## Throughput of every registered case",
                    "## Cost against the number of active lobes", "## Speed versus accuracy",
                    "## Conformance: the time of a verdict"):
        assert heading in text
    assert "| ASM dielectric" in text
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return
    for name in ("performance_throughput.png", "performance_active_lobes.png"):
        assert (out / "figures" / name).stat().st_size > 0
        assert f"figures/{name}" in text


def test_hazy_report_smoke(tmp_path):
    """``python -m benchmarks.hazy_report --smoke`` writes its page into the given folder
    only, with every section."""
    page = ROOT / "docs" / "hazy_measured.md"
    before = page.stat().st_mtime_ns if page.exists() else None
    proc = subprocess.run([sys.executable, "-m", "benchmarks.hazy_report", "--smoke", "--out",
                           str(tmp_path)], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-4000:]
    assert (page.stat().st_mtime_ns if page.exists() else None) == before
    text = (tmp_path / "hazy_measured.md").read_text(encoding="utf-8")
    for heading in ("Peak ratio", "core peak", "Compound against separate", "two-component BTDF",
                    "Polar slices"):
        assert heading in text, heading
    assert "| ggx |" in text and "| beckmann |" in text


def test_asm_report_writes_the_table_1_comparison(tmp_path):
    from benchmarks import asm_report

    page = asm_report.run(tmp_path, n_paths=200, aniso_samples=500)
    text = page.read_text(encoding="utf-8")
    assert page.parent == tmp_path and "closest data set" in text
    rows = [line for line in text.splitlines() if line.startswith("| Fe-Werner2009 |")]
    assert len(rows) == len(asm_report.ILLUMINANTS)
    assert "| Skimmilk" in text and "Table 3 media" in text


def test_darkening_report_writes_its_page(tmp_path):
    """``benchmarks.darkening_report`` (tiny walks) writes every section into the given
    folder: two random-walk rows in smoke mode, a Lambertian and a mirror base."""
    from benchmarks import darkening_report

    text = darkening_report.run(tmp_path, smoke=True).read_text(encoding="utf-8")
    assert "Values at normal incidence" in text
    assert text.count("| coloured | tinted |") == 2 * len(darkening_report.COAT_IORS)
    assert "## Physical darkening (dev_1.2) against random walks" in text
    assert text.count("| Lambertian | ") == 1 and text.count("| mirror | ") == 1
    assert "Largest |difference| from the walks: dev_1.2 **" in text


def test_sheen_report_smoke(tmp_path):
    """``benchmarks.sheen_report`` (tiny sizes) writes its page into the given folder only,
    with every section."""
    from benchmarks import sheen_report

    page = ROOT / "docs" / "sheen_measured.md"
    before = page.stat().st_mtime_ns if page.exists() else None
    path = sheen_report.run(tmp_path, smoke=True)
    assert path.parent == tmp_path
    assert (page.stat().st_mtime_ns if page.exists() else None) == before
    text = path.read_text(encoding="utf-8")
    assert "Generated by `python -m benchmarks.sheen_report`" in text
    for heading in ("## Largest albedo", "## E(cos θo, r)", "## Albedo curves",
                    "## The table `sheen_albedo`", "## Albedo methods",
                    "## Success of the visible-normal sampler"):
        assert heading in text, heading


def test_render_report_writes_the_gallery_and_timings(tmp_path):
    from benchmarks import render_report

    page = render_report.run(tmp_path, size=12, spp=1)
    text = page.read_text(encoding="utf-8")
    assert (tmp_path / "figures" / "gallery.png").read_bytes()[:4] == b"\x89PNG"
    for label, _ in render_report.GALLERY:
        assert f"| {label} |" in text


def test_asm_cost_lists_every_material(tmp_path):
    from benchmarks import asm_cost

    text = asm_cost.run(tmp_path, pairs=200, runs=1).read_text(encoding="utf-8")
    for label, _ in asm_cost.MATERIALS:
        assert f"| {label} |" in text
    assert "costs" in text


def test_explorer_cost_times_every_target(tmp_path):
    from benchmarks import explorer_cost

    text = explorer_cost.run(tmp_path, smoke=True).read_text(encoding="utf-8")
    for name in explorer_cost.TARGETS:
        row = next(line for line in text.splitlines() if line.startswith(f"| {name} |"))
        fast, rest = (float(cell) for cell in row.split("|")[3:5])
        assert fast > 0.0 and rest > 0.0


def test_docs_figures_script_draws_every_figure(tmp_path):
    proc = subprocess.run([sys.executable, str(ROOT / "docs" / "figures.py"), "--out",
                           str(tmp_path), "--size", "12", "--spp", "1"], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-4000:]
    scenes = [f"paper_{name}.png" for name in paper_figures.SCENES]
    for name in ("theory_lobes.png", "theory_furnace.png", "theory_gold.png", *scenes):
        assert (tmp_path / name).read_bytes()[:4] == b"\x89PNG"


def test_layering_report_writes_its_page(tmp_path):
    from benchmarks import layering_report

    text = layering_report.run(tmp_path, smoke=True).read_text(encoding="utf-8")
    for name, _, _ in layering_report.FORMS:
        assert f"| {name} |" in text
    assert (tmp_path / "figures" / "layering_albedo.png").exists()
    assert (tmp_path / "figures" / "layering_slices.png").exists()


def test_openpbr_report_writes_its_page(tmp_path):
    from benchmarks import openpbr_report

    text = openpbr_report.run(tmp_path, smoke=True).read_text(encoding="utf-8")
    for section in ("White furnace", "Sampling", "Reciprocity",
                    "Against Adobe's OpenPBR implementation", "Cost"):
        assert f"## {section}" in text
    assert "| material | lobes | eval (s) | passes |" in text
    for name in openpbr_report.PEER:
        assert f"| {name} | 0.9 |" in text


def test_openpbr_transport_writes_its_page(tmp_path):
    from benchmarks import openpbr_transport

    text = openpbr_transport.run(tmp_path, smoke=True).read_text(encoding="utf-8")
    for section in ("Example materials", "Sweeps of the parameters the approximations touch",
                    "eval at pairs and reciprocity", "Polar slices", "Cost"):
        assert f"## {section}" in text
    assert "| default | 1 |" in text and "| coat_weight | 0.0 |" in text
    assert (tmp_path / "figures" / "openpbr_transport_slices.png").exists()


def test_media_report_writes_its_page(tmp_path):
    from benchmarks import media_report

    text = media_report.run(tmp_path, smoke=True).read_text(encoding="utf-8")
    for section in ("Subsurface: the colour a mapped medium really has", "Translucent medium",
                    "The ASM's and OpenPBR's media for the same inputs"):
        assert f"## {section}" in text
    assert "| 0.5 | 0.5 | normal |" in text


def test_material_cost(smoke):
    """Every material case measured (material calls and each active lobe alone), before and
    after, and the section and its plot in the page."""
    out, results, text = smoke
    from benchmarks import material_cost

    section = results["materials"]
    assert "error" not in section, section.get("error")
    labels = [label for label, _ in material_cost.material_cases()]
    assert [r["case"] for r in section["rows"]] == labels
    for row in section["rows"]:
        assert "error" not in row, row
        assert row["lobes"] and all(t > 0 for t in row["lobes"].values()), row
        assert row["lobe_samples"].keys() == row["lobes"].keys(), row
        assert all(t > 0 for t in row["lobe_samples"].values()), row
        assert all(row[call] > 0 for call in material_cost.CALLS), row
        # each pair is sampled by exactly one lobe (a flat batch of scalar parameters)
        assert row["shares"].keys() == row["lobes"].keys(), row
        assert abs(sum(row["shares"].values()) - 1.0) < 1e-12, row["shares"]
        # a time: positive (its bound by the lobes' sample times is no law, eval_pdf may
        # cost more than sample, and under load either is noise)
        assert material_cost.mixture_floor(row) > 0.0
    assert section["pass_seconds"] > 0
    assert "rows" in section["before"], section["before"].get("error")
    assert "## Whole materials against their lobes" in text and "sample / eval" in text
    assert "Mixture floor above" in text


def test_pick_crossover_runs():
    """``benchmarks.pick`` times np.where, the bitwise select and ``pick`` for every share
    (tiny size; speed not asserted)."""
    from benchmarks import pick

    rows = pick.measure(n=4096)
    assert [r[0] for r in rows] == list(pick.SHARES)
    assert all(t > 0 for r in rows for t in r[1:])


def test_a_partial_run_keeps_the_other_sections(tmp_path, monkeypatch):
    """``report.merged``: the sections run now over those of the results file, each with its
    date."""
    from benchmarks import report

    old = {"machine": {"date_utc": "2026-01-01"}, "sections": ["headline", "tradeoff"],
           "headline": {"x": 1}, "tradeoff": {"y": 2}, "section_seconds": {"headline": 3.0,
                                                                            "tradeoff": 4.0}}
    path = tmp_path / "results.json"
    path.write_text(json.dumps(old))
    monkeypatch.setattr(report, "RESULTS", path)
    new = {"machine": {"date_utc": "2026-02-02"}, "sections": ["conformance"],
           "conformance": {"rows": []}, "section_seconds": {"conformance": 5.0}}
    merged = report.merged(new)
    assert merged["headline"] == {"x": 1} and merged["conformance"] == {"rows": []}
    assert merged["sections"] == ["headline", "tradeoff", "conformance"]
    assert merged["measured"] == {"headline": "2026-01-01", "tradeoff": "2026-01-01",
                                  "conformance": "2026-02-02"}
    assert merged["section_seconds"]["tradeoff"] == 4.0
