"""The command line: ``check`` (quick and full suites, table, notes, summary, exit code) and
``bake`` (output folder, table names, errors, program name)."""

import hashlib
import os
import re
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

import adobe_bsdf.__main__ as cli
from adobe_bsdf.tables import SPECS
from adobe_bsdf.tables.store import data_dir
from adobe_bsdf.validation import checks
from adobe_bsdf.validation.cases import cases

ROOT = Path(__file__).resolve().parents[1]
#: cheap cases: a closed-form furnace, a Monte-Carlo furnace, a delta lobe, a long name
CHEAP = ["Lambert", "Conductor a=1 F=1", "Dielectric eta=1.5 smooth", "Sum 0.3 Lambert"]


def _run(argv, capsys):
    code = cli.main(argv, prog="adobe-bsdf")
    out = capsys.readouterr()
    return code, out.out, out.err


# -- the suites


def test_quick_suite_covers_every_case_at_one_or_two_of_its_angles():
    for case in cases():
        angles = cli.SUITES["quick"].angles(case)
        assert 1 <= len(angles) <= 2, case.name
        assert all(a in case.cos_theta_o for a in angles)
        assert list(angles) == sorted(angles, key=case.cos_theta_o.index)  # the case's order
        if any(c < 0 for c in case.cos_theta_o):  # both sides of a two-sided lobe
            assert any(a < 0 for a in angles), case.name
        if any(0 < c < 1 for c in case.cos_theta_o):  # an oblique view, not normal incidence
            assert any(0 < a < 1 for a in angles), case.name
    assert cli.SUITES["full"].angles(cases()[0]) == cases()[0].cos_theta_o


def test_full_suite_measures_as_much_as_before():
    full = cli.SUITES["full"]
    assert (full.chi2_samples, full.chi2_grid, full.weight_samples, full.mc_samples,
            full.pairs, full.quadrature_tol) == (200_000, (64, 128), 20_000, 200_000, 20_000,
                                                 None)


def _rows_before(indices, n_samples=200_000):
    """The rows of ``check`` before the quick suite existed (its whole loop, for the cases at
    ``indices``; the Šidák family is every angle of every case, as it was)."""
    from adobe_bsdf.validation.chi2 import chi2_test, suggest_grid

    selected = cases("fast")
    n_chi2 = sum(len(c.cos_theta_o) for c in selected)
    for index in indices:
        case = selected[index]
        lobe = case.make()
        wo_pairs, wi_pairs = cli._random_pairs(20_000, index)
        rec = checks.reciprocity_error(lobe, wo_pairs, wi_pairs, rtol=1e-12,
                                       atol=float(np.finfo(np.float64).tiny))
        yield case.name, "reciprocity", "random", f"{rec.max_error:.1e}", "<= 1e-12", rec.passed
        for cos_theta in case.cos_theta_o:
            wo = cli._direction(cos_theta)
            grid = suggest_grid(case.width, case.peak(wo)) if case.width else {}
            seed = 100 * index + case.cos_theta_o.index(cos_theta)
            chi = chi2_test(lobe, wo, n_samples=n_samples, seed=seed, alpha=0.01,
                            n_tests=n_chi2, **grid)
            if chi.n_histogram:
                yield case.name, "chi2 p-value", f"{cos_theta:g}", f"{chi.p_value:.3f}", \
                    f">= {chi.significance:.1e}", chi.passed
            wc = checks.weight_consistency(lobe, wo, n_samples=20_000, seed=seed, rtol=1e-9)
            yield case.name, "weight rel. err", f"{cos_theta:g}", \
                f"{wc.max_weight_error:.1e}", "<= 1e-09", wc.passed
            quad, quad_err = lobe.albedo(wo, method="quadrature", return_error=True)
            expected = case.expected_albedo(wo) if case.expected_albedo else None
            if expected is not None:
                err = float(np.max(np.abs(quad - expected)))
                tol = max(1e-6, case.furnace_tol)
                yield case.name, "furnace |E-exact|", f"{cos_theta:g}", \
                    f"{err:.1e} (E={quad[0]:.6f})", f"<= {tol:.0e}", err <= tol
            else:
                mc, mc_err = lobe.albedo(wo, method="mc", n_samples=200_000, rng=seed,
                                         return_error=True)
                z = float(np.max(np.abs(quad - mc) / np.maximum(mc_err + quad_err, 1e-300)))
                yield case.name, "furnace quad-vs-MC", f"{cos_theta:g}", \
                    f"{z:.2f} sigma (E={quad[0]:.6f})", "<= 4 sigma", z <= 4.0


def test_full_suite_reproduces_the_rows_of_before():
    """``--full`` yields the rows the command printed before the quick suite, figure for
    figure (here for a cheap case with a closed-form and a Monte-Carlo furnace; the Šidák
    family is the whole suite's)."""
    names = ["Conductor a=1 F=1"]
    selected = [(i, c) for i, c in enumerate(cases()) if c.name in names]
    n_all = sum(len(c.cos_theta_o) for c in cases())
    new = [(r.name, r.test, r.cos, r.figure, r.threshold, r.passed)
           for r in cli._rows(selected, cli.SUITES["full"], 200_000, n_all)]
    assert new == list(_rows_before([i for i, _ in selected]))


def test_detectable_deviation_is_where_the_test_has_its_power():
    eps = cli.detectable_deviation(dof=1000, significance=1e-4, n_samples=50_000)
    critical = stats.chi2.isf(1e-4, 1000)
    assert stats.ncx2.sf(critical, 1000, 50_000 * eps**2) == pytest.approx(0.9, abs=1e-6)
    assert cli.detectable_deviation(1000, 1e-4, 200_000) == pytest.approx(eps / 2, rel=1e-6)
    assert cli.detectable_deviation(100, 1e-4, 50_000) < eps  # fewer bins, more power


# -- the check command


def test_check_prints_an_aligned_table_the_threshold_and_a_summary(capsys, tmp_path):
    md = tmp_path / "check.md"
    code, out, err = _run(["check", *sum((["--cases", c] for c in CHEAP), []),
                           "--markdown", str(md)], capsys)
    assert code == 0
    lines = out.splitlines()
    header = next(i for i, line in enumerate(lines) if line.startswith("lobe"))
    starts = [m.start() for m in re.finditer(r"-+", lines[header + 1])]
    assert len(starts) == 6
    table = lines[header + 2:lines.index("", header)]
    assert len(table) > 10
    for line in table:  # every cell starts at its column, after two blanks
        for s in starts[1:]:
            assert line[s - 2:s] == "  " and line[s] != " ", line
    long = [line for line in table if line.startswith("Sum 0.3 Lambert")]
    assert long and all(len(line[:starts[1]].rstrip()) == cli.NAME_WIDTH for line in long)
    assert all("…" in line[:starts[1]] for line in long)
    assert re.search(r"chi2 threshold: p >= \S+ is the Šidák-corrected per-test significance"
                     r" 1 - \(1 - α\)\^\(1/N\) for a family-wise α = 0.01 over the N = 5 "
                     r"chi-square", " ".join(lines))
    summary = "\n".join(lines[lines.index("summary:"):])
    for label in ("chi-square ", "reciprocity ", "weight ", "furnace, closed form ",
                  "furnace, vs MC ", "chi-square power "):
        assert f"  {label}" in summary, label
    assert re.search(r"\d+ passed, 0 failed, 0 measured only in [\d.]+ s \(quick suite: 4 "
                     r"cases, 5 incident angles, 5 chi-square tests of 50000 samples", summary)
    text = md.read_text(encoding="utf-8")
    assert text.startswith("# Check results\n\n*Written by `adobe-bsdf check --cases Lambert")
    assert "| Sum 0.3 Lambert + 0 + 0.7 Conductor a=(0.6,0.1) | reciprocity |" in text
    assert r"| furnace \|E-exact\| |" in text  # a pipe inside a cell is escaped
    assert "Šidák-corrected" in text and "| chi-square power |" in text


def test_the_chi2_family_is_the_tests_run_and_seeds_stay_the_suites(capsys):
    rows = list(cli._rows(cli.select(["Lambert"]), cli.SUITES["quick"], 1000, 3))
    chi = next(r for r in rows if r.kind == "chi2" and r.name == "Lambert")
    assert chi.threshold == f">= {1 - 0.99 ** (1 / 3):.1e}"
    index = next(i for i, c in enumerate(cases()) if c.name == "Lambert")
    alone = list(cli._rows([(index, cases()[index])], cli.SUITES["quick"], 1000, 3))
    assert [r.figure for r in alone] == [r.figure for r in rows if r.name == "Lambert"]


def test_a_warning_is_a_note_of_the_row_that_raised_it(capsys, monkeypatch, tmp_path):
    measure = checks.weight_consistency

    def warning_weights(lobe, wo, **kwargs):
        warnings.warn("weights measured on a test double", UserWarning, stacklevel=2)
        return measure(lobe, wo, **kwargs)

    monkeypatch.setattr(checks, "weight_consistency", warning_weights)
    md = tmp_path / "check.md"
    code, out, err = _run(["check", "--cases", "Conductor a=1 F=1", "--markdown", str(md)],
                          capsys)
    assert code == 0
    rows = [line for line in out.splitlines() if line.startswith("Conductor a=1 F=1  ")]
    assert [line.endswith("pass [1]") for line in rows] == [False, False, True, False]
    notes = " ".join(out[out.index("notes:"):].split())  # long notes are wrapped
    assert ("notes: [1] Conductor a=1 F=1, weight rel. err at cos θo 0.5: UserWarning: "
            "weights measured on a test double summary:") in notes
    assert "weights measured" not in err  # not loose on stderr
    assert ("1. Conductor a=1 F=1, weight rel. err at cos θo 0.5: UserWarning: weights measured"
            " on a test double") in md.read_text(encoding="utf-8")
    assert "| Conductor a=1 F=1 | weight rel. err | 0.5 | " in md.read_text(encoding="utf-8")


def test_a_failure_gives_exit_code_1_and_is_listed(capsys, monkeypatch):
    monkeypatch.setattr(cli, "WEIGHT_RTOL", 0.0)  # any rounding fails
    code, out, err = _run(["check", "--cases", "Conductor a=1 F=1"], capsys)
    assert code == 1
    assert re.search(r"weight rel. err\s+0.5\s+\S+\s+<= 0e\+00\s+FAIL", out)
    assert "  failed:\n    Conductor a=1 F=1, weight rel. err at cos θo 0.5" in out
    assert re.search(r"\d+ passed, 1 failed", out)


def test_progress_bar_goes_to_stderr(capsys):
    failures = cli.check(patterns=["Lambert"], progress=True)
    out = capsys.readouterr()
    assert failures == 0
    assert "Lambert" in out.err and "step" in out.err  # the tqdm bar: case name and unit
    assert "\r" not in out.out


def test_check_list_and_unknown_cases(capsys):
    code, out, err = _run(["check", "--list"], capsys)
    assert code == 0 and len(out.splitlines()) == len(cases())
    assert out.splitlines()[0].split(None, 1) == ["0", cases()[0].name]
    code, out, err = _run(["check", "--cases", "no such lobe"], capsys)
    assert code == 2 and out == ""
    assert err == ("adobe-bsdf check: error: no case name contains 'no such lobe' (--list "
                   "shows them)\n")
    with pytest.raises(SystemExit) as exc:
        cli.main(["check", "--samples", "0"])
    assert exc.value.code == 2


# -- the bake command


def _digest(folder: Path) -> dict:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.glob("*.npz"))}


def test_bake_help_lists_every_table_and_the_folders(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["bake", "--help"], prog="adobe-bsdf")
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith("usage: adobe-bsdf bake")
    listed = re.findall(r"^  (\w+)  ", out.split("tables (in baking order")[1], re.M)
    assert listed == list(SPECS)
    assert "--in-place" in out and str(data_dir()) in out


def test_bake_unknown_name_is_one_line_with_the_known_names(capsys):
    code, out, err = _run(["bake", "ggx_conductor", "nope"], capsys)
    assert code == 2 and out == ""
    assert err == (f"adobe-bsdf bake: error: unknown table 'nope'; known tables: "
                   f"{', '.join(SPECS)}, ggx_dielectric_anisotropic\n")


def test_bake_in_place_takes_no_other_folder(capsys, tmp_path):
    code, _, err = _run(["bake", "--in-place", "--out", str(tmp_path)], capsys)
    assert code == 2 and err.count("\n") == 1 and "--in-place" in err
    code, _, err = _run(["bake", "--in-place", "--resolution", "3"], capsys)
    assert code == 2 and err.count("\n") == 1 and "--resolution" in err


def test_bake_writes_a_user_folder_and_leaves_the_shipped_tables(capsys, tmp_path,
                                                                 monkeypatch):
    shipped = _digest(data_dir())
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    code, out, _ = _run(["bake", "ggx_conductor_avg", "--workers", "1"], capsys)  # derived
    assert code == 0
    folder = tmp_path / "cache" / "adobe_bsdf" / "tables"
    assert f"baking into {folder}" in out and "--in-place" in out
    assert list(_digest(folder)) == ["ggx_conductor_avg.npz"]
    code, out, _ = _run(["bake", "ggx_conductor", "--resolution", "3", "--workers", "1",
                         "--out", str(tmp_path / "small")], capsys)
    assert code == 0
    assert list(_digest(tmp_path / "small")) == ["ggx_conductor.npz", "ggx_conductor_avg.npz"]
    assert _digest(data_dir()) == shipped


def test_bake_check_reads_the_shipped_tables(capsys):
    code, out, _ = _run(["bake", "ggx_conductor_avg", "--check", "--nodes", "2",
                         "--workers", "1"], capsys)
    assert code == 0
    assert re.match(r"ggx_conductor_avg\s+2 nodes re-baked at order \d+: .* pass$", out.strip())


def test_usage_names_the_program_it_was_invoked_as():
    env = {**os.environ, "COLUMNS": "200"}
    proc = subprocess.run([sys.executable, "-m", "adobe_bsdf", "bake", "nope"], cwd=ROOT,
                          capture_output=True, text=True, env=env, timeout=120)
    assert proc.returncode == 2 and proc.stderr.startswith("python -m adobe_bsdf bake: error")
    script = shutil.which("adobe-bsdf", path=str(Path(sys.executable).parent))
    if script is None:
        pytest.skip("the adobe-bsdf console script is not installed")
    proc = subprocess.run([script, "--help"], capture_output=True, text=True, env=env,
                          timeout=120)
    assert proc.returncode == 0 and proc.stdout.startswith("usage: adobe-bsdf ")


@pytest.mark.slow
def test_default_check_runs_in_30_seconds():
    import time

    start = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "adobe_bsdf", "check"], cwd=ROOT,
                          capture_output=True, text=True, timeout=600)
    seconds = time.perf_counter() - start
    assert proc.returncode == 0, proc.stdout[-3000:]
    assert seconds < 30.0, seconds
