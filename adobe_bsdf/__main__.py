"""Command line: ``python -m adobe_bsdf check`` validates every registered lobe, ``bake`` bakes
the energy tables, ``conform`` judges a BSDF written elsewhere (``conformance.cli``).

``check`` runs every case of ``adobe_bsdf.validation.cases`` in its fixed order (the random
seeds derive from the case's index and the incident angle's index) and measures, per case:

* ``reciprocity`` max relative error of f(wo, wi)/eta_o^2 = f(wi, wo)/eta_i^2 over random pairs
                  (differences of subnormal values, which keep fewer significant bits, are
                  measured against the smallest normal float64); for a case that is not
                  reciprocal by design (``CheckCase.reciprocal``), the same figure is listed
                  as "non-reciprocity" and not judged;

and, per selected incident angle:

* ``chi2``        sampling against the pdf (p-value; Šidák-corrected over the chi-square tests
                  of the run);
* ``weight``      max relative error of weight = f |cos| / pdf over samples;
* ``furnace``     energy albedo by quadrature against an independent value: the case's closed
                  form, else the Monte-Carlo estimate (|difference| in standard errors).

Two suites (``SUITES``)
-----------------------
=====================  ============================================  =======================
                       ``quick`` (default; about 20 s on two cores)  ``--full`` (about 4 min)
=====================  ============================================  =======================
incident angles        per case: the first oblique view from above   every ``cos_theta_o``
                       (0 < cos θo < 1) and the first from below
chi-square             50 000 samples on 32 x 64 cells               200 000 on 64 x 128
weights                5 000 samples                                 20 000
reciprocity            5 000 random pairs                            20 000
furnace vs MC          50 000 samples; quadrature tol 1e-5           200 000; tol 1e-8
furnace vs closed      quadrature tol min(1e-5, threshold / 10)      tol 1e-8
=====================  ============================================  =======================

Both cover every registered case; ``--full`` is the table of ``docs/check_results.md``. Before
the quick suite existed, the full one took 220 s on two cores: 54 % of it in the quadrature
albedo at tol 1e-8 (three angles of two ASM materials took 81 s), 28 % in the chi-square tests,
17 % in the Monte-Carlo albedo. The summary states each run's chi-square power: the error
±ε of the sampled density on two halves of its mass that its least sensitive test finds with
90 % probability (``detectable_deviation``). With a quarter of the samples on a quarter of the
cells, that is about ±7 % (median ±6 %) for the quick suite against ±5.4 % (±4.4 %) for the
full one; an error that only moves density within a cell is invisible to either, and quick
cells are twice as wide (5.6° on an unwarped grid instead of 2.8°).

A warning raised while a row is measured is listed under the table as a note of that row.
"""

from __future__ import annotations

import argparse
import datetime
import os
import shlex
import sys
import textwrap
import time
import warnings
from collections.abc import Callable
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize, stats

#: thresholds of the check table
RECIPROCITY_RTOL = 1e-12
#: the smallest normal float64: below it values are subnormal (the Beckmann tail reaches it)
RECIPROCITY_ATOL = float(np.finfo(np.float64).tiny)
WEIGHT_RTOL = 1e-9
FURNACE_TOL = 1e-6
MC_SIGMAS = 4.0
CHI2_ALPHA = 0.01
#: detection probability at which the chi-square's power is stated
CHI2_POWER = 0.9
#: the lobe column of the terminal table is cut to this many characters (Markdown: full names)
NAME_WIDTH = 40


def _all_angles(case) -> tuple:
    return tuple(case.cos_theta_o)


def _quick_angles(case) -> tuple:
    """One oblique view from above (the first 0 < cos < 1: at normal incidence the masking of
    ``wo`` is 1 and hides its errors), else the first view from above, and the first view from
    below if the case has one; in the case's order."""
    cos = tuple(case.cos_theta_o)
    above = [c for c in cos if 0.0 < c < 1.0] or [c for c in cos if c > 0.0]
    chosen = above[:1] + [c for c in cos if c < 0.0][:1]
    return tuple(c for c in cos if c in chosen)


@dataclass(frozen=True)
class Suite:
    """How much ``check`` measures per case.

    Attributes
    ----------
    name : str
    angles : callable
        ``angles(case) -> tuple`` of the incident cosines tested (a subset of
        ``case.cos_theta_o``, in its order).
    chi2_samples : int
        Samples per chi-square test.
    chi2_grid : tuple of int
        ``(n_theta, n_phi)`` cells of the chi-square grid.
    weight_samples, mc_samples : int
        Samples of the weight test and of the Monte-Carlo albedo.
    pairs : int
        Random direction pairs of the reciprocity test.
    quadrature_tol : float or None
        ``tol`` of the quadrature albedo against Monte Carlo (``None``: the default of
        ``Lobe.albedo``); against a closed form it is at most a tenth of the threshold.
    """

    name: str
    angles: Callable
    chi2_samples: int
    chi2_grid: tuple
    weight_samples: int
    mc_samples: int
    pairs: int
    quadrature_tol: float | None


SUITES = {
    "quick": Suite("quick", _quick_angles, chi2_samples=50_000, chi2_grid=(32, 64),
                   weight_samples=5_000, mc_samples=50_000, pairs=5_000, quadrature_tol=1e-5),
    "full": Suite("full", _all_angles, chi2_samples=200_000, chi2_grid=(64, 128),
                  weight_samples=20_000, mc_samples=200_000, pairs=20_000, quadrature_tol=None),
}


@dataclass
class Row:
    """One line of the check table, with what the summary needs."""

    name: str
    test: str
    cos: str
    figure: str
    threshold: str
    passed: bool | None
    kind: str
    value: float
    notes: list = field(default_factory=list)
    detectable: float | None = None  # chi2 only: the deviation found with CHI2_POWER

    @property
    def verdict(self) -> str:
        return "info" if self.passed is None else "pass" if self.passed else "FAIL"


def _direction(cos_theta: float, phi: float = 0.7) -> np.ndarray:
    s = np.sqrt(1.0 - cos_theta * cos_theta)
    return np.array([s * np.cos(phi), s * np.sin(phi), cos_theta])


def _random_pairs(n: int, seed: int):
    rng = np.random.default_rng(seed)
    w = rng.normal(size=(2, n, 3))
    return w / np.linalg.norm(w, axis=-1, keepdims=True)


@contextmanager
def _recorded():
    """Collect the warnings raised inside as ``"Category: message"`` strings."""
    notes = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield notes
    for w in caught:
        text = f"{w.category.__name__}: {w.message}"
        if text not in notes:
            notes.append(text)


def detectable_deviation(dof: int, significance: float, n_samples: int,
                         power: float = CHI2_POWER) -> float:
    """Smallest ``eps`` that a chi-square test finds with probability ``power``.

    The sampler draws ``(1 + eps)`` times the density of the pdf on one half of its mass and
    ``(1 - eps)`` times on the other. Pearson's statistic then follows a noncentral chi-square
    with ``dof`` degrees of freedom and noncentrality ``n_samples eps**2``; the test fails it
    when it exceeds the upper ``significance`` quantile of the central one.

    Parameters
    ----------
    dof : int
        Degrees of freedom of the test (bins after pooling minus one), in [1, inf).
    significance : float
        The test's (corrected) significance level, in (0, 1).
    n_samples : int
        Samples drawn, in [1, inf).
    power : float
        Detection probability, in (significance, 1).

    Returns
    -------
    float
    """
    critical = stats.chi2.isf(significance, dof)
    hi = critical + 20.0 * np.sqrt(2.0 * dof) + 100.0
    lam = optimize.brentq(lambda nc: stats.ncx2.sf(critical, dof, nc) - power, 1e-9, hi)
    return float(np.sqrt(lam / n_samples))


def _rows(selected, suite: Suite, n_samples: int, n_chi2: int, advance=lambda name: None):
    """Yield the ``Row`` of every test of the ``(index, case)`` pairs of ``selected``."""
    from adobe_bsdf.validation import checks
    from adobe_bsdf.validation.chi2 import chi2_test, suggest_grid

    n_theta, n_phi = suite.chi2_grid
    for index, case in selected:
        lobe = case.make()
        advance(case.name)
        with _recorded() as notes:
            wo_pairs, wi_pairs = _random_pairs(suite.pairs, index)
            rec = checks.reciprocity_error(lobe, wo_pairs, wi_pairs, rtol=RECIPROCITY_RTOL,
                                           atol=RECIPROCITY_ATOL)
        if case.reciprocal:
            yield Row(case.name, "reciprocity", "random", f"{rec.max_error:.1e}",
                      f"<= {RECIPROCITY_RTOL:.0e}", rec.passed, "reciprocity", rec.max_error,
                      notes)
        else:  # measured and listed, not required (e.g. albedo scaling, docs/asm.md)
            yield Row(case.name, "non-reciprocity", "random", f"{rec.max_error:.1e}",
                      "by design", None, "non-reciprocity", rec.max_error, notes)
        for cos_theta in suite.angles(case):
            advance(case.name)
            cos = f"{cos_theta:g}"
            wo = _direction(cos_theta)
            grid = suggest_grid(case.width, case.peak(wo)) if case.width else {}
            seed = 100 * index + case.cos_theta_o.index(cos_theta)
            with _recorded() as notes:
                chi = chi2_test(lobe, wo, n_samples=n_samples, n_theta=n_theta, n_phi=n_phi,
                                seed=seed, alpha=CHI2_ALPHA, n_tests=n_chi2, **grid)
            if chi.n_histogram:
                found = (detectable_deviation(chi.dof, chi.significance, n_samples)
                         if chi.dof >= 1 else None)
                yield Row(case.name, "chi2 p-value", cos, f"{chi.p_value:.3f}",
                          f">= {chi.significance:.1e}", chi.passed, "chi2", chi.p_value, notes,
                          found)
                notes = []
            with _recorded() as more:
                wc = checks.weight_consistency(lobe, wo, n_samples=suite.weight_samples,
                                               seed=seed, rtol=WEIGHT_RTOL)
            yield Row(case.name, "weight rel. err", cos, f"{wc.max_weight_error:.1e}",
                      f"<= {WEIGHT_RTOL:.0e}", wc.passed, "weight", wc.max_weight_error,
                      notes + more)
            expected = case.expected_albedo(wo) if case.expected_albedo else None
            if expected is not None:
                tol = max(FURNACE_TOL, case.furnace_tol)
                options = ({} if suite.quadrature_tol is None
                           else {"tol": min(suite.quadrature_tol, tol / 10.0)})
                with _recorded() as notes:
                    quad, _ = lobe.albedo(wo, method="quadrature", return_error=True, **options)
                err = float(np.max(np.abs(quad - expected)))
                yield Row(case.name, "furnace |E-exact|", cos, f"{err:.1e} (E={quad[0]:.6f})",
                          f"<= {tol:.0e}", err <= tol, "furnace-exact", err / tol, notes)
            else:
                options = ({} if suite.quadrature_tol is None
                           else {"tol": suite.quadrature_tol})
                with _recorded() as notes:
                    quad, quad_err = lobe.albedo(wo, method="quadrature", return_error=True,
                                                 **options)
                    mc, mc_err = lobe.albedo(wo, method="mc", n_samples=suite.mc_samples,
                                             rng=seed, return_error=True)
                z = float(np.max(np.abs(quad - mc) / np.maximum(mc_err + quad_err, 1e-300)))
                yield Row(case.name, "furnace quad-vs-MC", cos,
                          f"{z:.2f} sigma (E={quad[0]:.6f})", f"<= {MC_SIGMAS:g} sigma",
                          z <= MC_SIGMAS, "furnace-mc", z, notes)


def _short(name: str, width: int = NAME_WIDTH) -> str:
    return name if len(name) <= width else name[:width - 1] + "…"


def _numbered(rows):
    """Number the notes in row order; return ``(marker per row, [(number, row, note)])``."""
    markers, listed = [], []
    for row in rows:
        numbers = []
        for note in row.notes:
            listed.append((len(listed) + 1, row, note))
            numbers.append(f"[{len(listed)}]")
        markers.append(" ".join(numbers))
    return markers, listed


def _where(row: Row, full_name: bool = True, test: bool = True) -> str:
    """``"name, test at cos θo c"``: which row."""
    name = row.name if full_name else _short(row.name)
    return (name + (f", {row.test}" if test else "")
            + ("" if row.cos == "random" else f" at cos θo {row.cos}"))


def _summary(rows, seconds: float, suite: Suite, n_samples: int, n_chi2: int,
             n_angles: int, n_cases: int):
    """The closing lines ``[(label, worst figure, its Row or a remark)]``, the failed rows and
    the count line."""
    lines = []

    def worst(kind, pick, label, fmt):
        judged = [r for r in rows if r.kind == kind]
        if judged:
            r = pick(judged, key=lambda r: r.value)
            lines.append((label, fmt(r), r))

    worst("chi2", min, "chi-square", lambda r: f"lowest p-value {r.figure} ({r.threshold})")
    worst("reciprocity", max, "reciprocity", lambda r: f"largest error {r.figure} "
          f"({r.threshold})")
    worst("non-reciprocity", max, "non-reciprocity", lambda r: f"largest {r.figure} "
          "(by design, not judged)")
    worst("weight", max, "weight", lambda r: f"largest relative error {r.figure} "
          f"({r.threshold})")
    worst("furnace-exact", max, "furnace, closed form",
          lambda r: f"largest |E - exact| {r.figure.split()[0]} ({r.threshold})")
    worst("furnace-mc", max, "furnace, vs MC", lambda r: f"largest {r.value:.2f} sigma "
          f"({r.threshold})")
    found = [r.detectable for r in rows if r.detectable is not None]
    if found:
        lines.append(("chi-square power", f"finds a ±{max(found):.1%} density error with "
                      f"{CHI2_POWER:.0%} probability", f"(least sensitive test; median "
                      f"±{np.median(found):.1%})"))
    failures = [r for r in rows if r.passed is False]
    passed = sum(r.passed is True for r in rows)
    info = sum(r.passed is None for r in rows)
    counts = (f"{passed} passed, {len(failures)} failed, {info} measured only in "
              f"{seconds:.1f} s ({suite.name} suite: {n_cases} cases, {n_angles} incident "
              f"angles, {n_chi2} chi-square tests of {n_samples} samples on "
              f"{suite.chi2_grid[0]} x {suite.chi2_grid[1]} cells)")
    return lines, failures, counts


def _explain_threshold(n_chi2: int) -> str:
    from adobe_bsdf.validation.chi2 import sidak_alpha

    return (f"chi2 threshold: p >= {sidak_alpha(CHI2_ALPHA, max(n_chi2, 1)):.1e} is the "
            f"Šidák-corrected per-test significance 1 - (1 - α)^(1/N) for a family-wise "
            f"α = {CHI2_ALPHA:g} over the N = {n_chi2} chi-square tests of this run "
            f"[Sidak1967]. Power: a test finds, with {CHI2_POWER:.0%} probability, a sampler "
            "whose density is 1 ± ε times the pdf on two halves of its mass (Pearson's "
            "statistic is then noncentral chi-square, noncentrality samples × ε²); the "
            "summary gives ε of the least sensitive test.")


def _row_or_text(item, full_name: bool) -> str:
    return item if isinstance(item, str) else _where(item, full_name, test=False)


def _terminal(rows, markers, listed, explanation, lines, failures, counts) -> str:
    header = ("lobe", "test", "cos θo", "measured", "threshold", "result")
    cells = [(_short(r.name), r.test, r.cos, r.figure, r.threshold,
              f"{r.verdict} {m}".rstrip()) for r, m in zip(rows, markers, strict=True)]
    widths = [max(len(c[i]) for c in [header, *cells]) for i in range(len(header))]

    def line(c):
        return "  ".join(str(x).ljust(w) for x, w in zip(c, widths, strict=True)).rstrip()

    out = [line(header), "  ".join("-" * w for w in widths)]
    out += [line(c) for c in cells]
    out += ["", textwrap.fill(explanation, 100)]
    if listed:
        out += ["", "notes:"]
        out += [textwrap.fill(f"  [{n}] {_where(r, False)}: {note}", 100,
                              subsequent_indent="      ") for n, r, note in listed]
    label_width = max((len(label) for label, _, _ in lines), default=0)
    figure_width = max((len(figure) for _, figure, _ in lines), default=0)
    out += ["", "summary:"]
    out += [f"  {label.ljust(label_width)}  {figure.ljust(figure_width)}  "
            f"{_row_or_text(where, False)}" for label, figure, where in lines]
    if failures:
        out += ["  failed:"] + [f"    {_where(r)}: {r.figure} ({r.threshold})"
                                for r in failures]
    out += ["", counts]
    return "\n".join(out)


def _cell(text: str) -> str:
    """``text`` in a Markdown table cell (``|`` escaped)."""
    return text.replace("|", r"\|")


def _markdown(rows, markers, listed, explanation, lines, failures, counts, command) -> str:
    header = ("lobe", "test", "cos θo", "measured", "threshold", "result")
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    out = ["# Check results", "",
           f"*Written by `{command}` on {now}; do not edit by hand. What each test measures "
           "and why: `docs/validation.md`.*", "",
           "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(_cell(c) for c in (
        r.name, r.test, r.cos, r.figure, r.threshold, f"{r.verdict} {m}".rstrip())) + " |"
            for r, m in zip(rows, markers, strict=True)]
    out += ["", explanation]
    if listed:
        out += ["", "Notes:", ""] + [f"{n}. {_where(r)}: {note}" for n, r, note in listed]
    out += ["", "| check | worst figure | row |", "|---|---|---|"]
    out += [f"| {label} | {_cell(figure)} | {_cell(_row_or_text(where, True))} |"
            for label, figure, where in lines]
    if failures:
        out += ["", "Failed:", ""] + [f"- {_where(r)}: {r.figure} ({r.threshold})"
                                      for r in failures]
    out += ["", counts, ""]
    return "\n".join(out)


def select(patterns=()) -> list:
    """``(index, case)`` of the registered cases whose name contains one of ``patterns``
    (case-insensitive; all cases if none), in the registry's order."""
    from adobe_bsdf.validation.cases import cases

    wanted = [p.lower() for p in patterns]
    return [(i, c) for i, c in enumerate(cases("fast"))
            if not wanted or any(p in c.name.lower() for p in wanted)]


def check(suite: str = "quick", *, n_samples: int | None = None, markdown: str | None = None,
          patterns=(), progress: bool | None = None, command: str | None = None,
          out=None) -> int:
    """Run the checks, print the table, its notes and a summary (and write them as Markdown to
    ``markdown`` if given); return the number of failures.

    Parameters
    ----------
    suite : {"quick", "full"}
        ``SUITES[suite]``: which angles, how many samples.
    n_samples : int, optional
        Samples per chi-square test (default: the suite's).
    markdown : str, optional
        File to write the table to, with full case names.
    patterns : sequence of str
        Run only the cases whose name contains one of them (case-insensitive).
    progress : bool or None
        Show a tqdm bar on stderr (``None``: when stderr is a terminal).
    command : str, optional
        The command line recorded in the Markdown file's first line.
    out : file, optional
        Where the table goes (default ``sys.stdout``).
    """
    from tqdm import tqdm

    out = sys.stdout if out is None else out
    start = time.perf_counter()
    if suite not in SUITES:
        raise ValueError(f"suite = {suite!r} is not one of {tuple(SUITES)}")
    plan = SUITES[suite]
    n_samples = plan.chi2_samples if n_samples is None else n_samples
    selected = select(patterns)
    if not selected:
        raise ValueError(f"no check case matches {list(patterns)}")
    n_angles = sum(len(plan.angles(c)) for _, c in selected)
    n_chi2 = n_angles  # the family of the Šidák correction: every angle run
    print(f"{plan.name} suite: {len(selected)} cases, {n_angles} incident angles"
          + ("" if plan.name == "full" else "  (--full: every angle, 4x the samples)"),
          file=out, flush=True)
    # one step per case (its reciprocity) and per incident angle (chi2, weights, furnace)
    bar = tqdm(total=len(selected) + n_angles, unit="step", file=sys.stderr, leave=False,
               disable=None if progress is None else not progress, dynamic_ncols=True)
    rows, started = [], []

    def advance(name):  # a unit starts (a case's reciprocity, or one angle): the last one ended
        bar.update(1 if started else 0)
        started.append(name)
        bar.set_description(_short(name, 32))

    try:
        for row in _rows(selected, plan, n_samples, n_chi2, advance):
            rows.append(row)
            if row.passed is False:
                bar.set_postfix(failed=sum(r.passed is False for r in rows))
    finally:
        bar.update(bar.total - bar.n)
        bar.close()
    seconds = time.perf_counter() - start
    markers, listed = _numbered(rows)
    explanation = _explain_threshold(n_chi2)
    lines, failures, counts = _summary(rows, seconds, plan, n_samples, n_chi2, n_angles,
                                       len(selected))
    print(_terminal(rows, markers, listed, explanation, lines, failures, counts), file=out,
          flush=True)
    if markdown:
        command = command or f"python -m adobe_bsdf check --markdown {markdown}"
        with open(markdown, "w", encoding="utf-8") as f:
            f.write(_markdown(rows, markers, listed, explanation, lines, failures, counts,
                              command))
    return len(failures)


def _program() -> str:
    """The name the command was invoked as: the console script's name, else
    ``python -m adobe_bsdf``."""
    name = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else ""
    if not name or name in ("__main__.py", "-c", "-m") or name.startswith("python"):
        return "python -m adobe_bsdf"
    return name


def _positive(text: str) -> int:
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text} is not a positive integer")
    return value


def _bake_epilog() -> str:
    from adobe_bsdf.tables import SPECS
    from adobe_bsdf.tables.bake import user_folder
    from adobe_bsdf.tables.store import data_dir

    width = max(len(n) for n in SPECS)
    lines = ["tables (in baking order; naming one re-derives the tables derived from it):"]
    for name, spec in SPECS.items():
        text = (f"[from {', '.join(spec.depends)}] " if spec.depends else "") + spec.description
        lines.append(f"  {name.ljust(width)}  "
                     + textwrap.shorten(text, 96 - width, placeholder=" ..."))
    lines += ["", f"default folder (--out): {user_folder()}",
              f"shipped tables, read by the library (--in-place): {data_dir()}", "",
              *textwrap.wrap("Finished node blocks stay in <folder>/<name>.partial until the "
                             "table is saved: after an interruption, the same command "
                             "resumes. Dask (--scheduler, --dask-workers) is optional: "
                             'pip install -e ".[dask]".', 88)]
    return "\n".join(lines)


def _parser(prog: str) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=prog,
                                     description="adobe_bsdf reference BSDF library")
    sub = parser.add_subparsers(dest="command", required=True)
    p_check = sub.add_parser(
        "check", help="validate every registered lobe and print a table",
        description="Validate every registered check case (chi-square sampling test, "
        "reciprocity, sample weights, white furnace) and print a table with notes and a "
        "summary. By default a quick suite: every case at one oblique view from above and "
        "one from below (if it has one), 50000 samples per chi-square on a 32 x 64 grid, "
        "about 20 s on two cores. Exit code 1 if any test fails.")
    p_check.add_argument("--full", action="store_true",
                         help="every incident angle of every case, 200000 samples per "
                         "chi-square on a 64 x 128 grid, 4x the other sample counts, "
                         "quadrature tol 1e-8 (about 4 minutes; docs/check_results.md)")
    p_check.add_argument("--samples", type=_positive, metavar="N",
                         help="samples per chi-square test (default 50000; 200000 with "
                         "--full)")
    p_check.add_argument("--cases", action="append", default=[], metavar="TEXT",
                         help="run only the cases whose name contains TEXT (case-insensitive; "
                         "repeat for several); seeds stay those of the whole suite")
    p_check.add_argument("--list", action="store_true", help="list the cases and exit")
    p_check.add_argument("--markdown", metavar="FILE",
                         help="also write the table (full case names) as Markdown to FILE")
    from adobe_bsdf.conformance.cli import add_parser as add_conform

    add_conform(sub)
    p_bake = sub.add_parser(
        "bake", help="bake the energy tables (or check them)",
        description=textwrap.fill(
            "Bake energy tables into a folder of your own (--out, default below), or with "
            "--in-place over the shipped tables that the library reads. --check re-bakes "
            "random nodes and compares them with the shipped tables (or those in --out); it "
            "writes nothing.", 88),
        epilog=_bake_epilog(), formatter_class=argparse.RawDescriptionHelpFormatter)
    p_bake.add_argument("names", nargs="*", metavar="NAME",
                        help="tables to bake (default: all the shipped ones); tables derived "
                        "from them are re-derived. ggx_dielectric_anisotropic, the grid of "
                        "anisotropic dielectric slices (hours of compute; resumes column by "
                        "column), is baked only when named")
    p_bake.add_argument("--out", metavar="DIR",
                        help="write the tables to DIR (default: the folder shown below)")
    p_bake.add_argument("--in-place", action="store_true",
                        help="overwrite the shipped tables that the library reads")
    p_bake.add_argument("--check", action="store_true",
                        help="re-bake random nodes at a higher order and compare with the "
                        "shipped tables, or those in --out (fails above 1e-6)")
    p_bake.add_argument("--nodes", type=_positive, default=16, metavar="N",
                        help="nodes per table for --check (default 16)")
    p_bake.add_argument("--seed", type=int, default=0, metavar="N",
                        help="seed of the --check nodes (default 0)")
    where = p_bake.add_mutually_exclusive_group()
    where.add_argument("--workers", type=_positive, metavar="N",
                       help="local worker processes (default: all cores, "
                       f"{os.cpu_count() or 1} here)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run the node blocks on the Dask cluster of this scheduler, e.g. "
                       "tcp://host:8786 (its workers need adobe_bsdf installed)")
    where.add_argument("--dask-workers", type=_positive, metavar="N",
                       help="run the node blocks on a local Dask cluster of N single-threaded "
                       "worker processes, started and closed by the command")
    p_bake.add_argument("--resolution", type=_positive, metavar="N",
                        help="nodes per axis instead of the declared ones (not with "
                        "--in-place)")
    return parser


def _bake(args, prog: str) -> int:
    from adobe_bsdf.tables import SPECS, TableError
    from adobe_bsdf.tables.bake import BakeError, run
    from adobe_bsdf.tables.dielectric_grid import NAME as GRID

    def fail(message):
        print(f"{prog} bake: error: {message}", file=sys.stderr)
        return 2

    known = [*SPECS, GRID]
    unknown = [n for n in args.names if n not in known]
    if unknown:
        return fail(f"unknown table{'s' if len(unknown) > 1 else ''} "
                    f"{', '.join(map(repr, unknown))}; known tables: {', '.join(known)}")
    if args.in_place and args.out:
        return fail("--in-place writes the shipped tables; it does not take --out")
    if args.in_place and args.resolution:
        return fail("--resolution bakes tables that differ from the declarations; it cannot "
                    "replace the shipped tables (give --out DIR or no folder)")
    try:
        failures = run(args.names, do_check=args.check, n_nodes=args.nodes, seed=args.seed,
                       workers=args.workers, scheduler=args.scheduler,
                       dask_workers=args.dask_workers, resolution=args.resolution,
                       out=args.out, in_place=args.in_place)
    except (TableError, BakeError, ValueError) as exc:  # a bad table file, no Dask, options
        return fail(str(exc))                           # that do not combine: one line
    except KeyboardInterrupt:  # the finished blocks are kept (and said where)
        return 130
    return 1 if failures else 0


def main(argv=None, prog: str | None = None) -> int:
    """Run the command line ``argv`` (default ``sys.argv[1:]``); return the exit code."""
    prog = prog or _program()
    argv = sys.argv[1:] if argv is None else list(argv)
    args = _parser(prog).parse_args(argv)
    if args.command == "check":
        if args.list:
            for index, case in select(args.cases):
                print(f"{index:3d}  {case.name}")
            return 0
        suite = "full" if args.full else "quick"
        if not select(args.cases):
            print(f"{prog} check: error: no case name contains "
                  f"{' or '.join(map(repr, args.cases))} (--list shows them)", file=sys.stderr)
            return 2
        command = shlex.join([*prog.split(), *argv])
        return 1 if check(suite, n_samples=args.samples, markdown=args.markdown,
                          patterns=args.cases, command=command) else 0
    if args.command == "bake":
        return _bake(args, prog)
    if args.command == "conform":
        from adobe_bsdf.conformance.cli import run as conform

        return conform(args, prog)
    return 2  # pragma: no cover - argparse enforces the choices


if __name__ == "__main__":
    sys.exit(main())
