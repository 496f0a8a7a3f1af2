"""Cost model of whole materials: what each material case costs against the standalone cost
of the lobes it is built from (the ``materials`` section of ``python -m benchmarks``).

Cases (``material_cases``): the default ``AdobeStandardMaterial`` and ``OpenPBRSurface``,
every registered check case whose lobe is a ``Material`` (``validation.cases.cases()``),
the OpenPBR preset "everything", and a fully loaded ASM with an isotropic and with an
anisotropic coat (the pair that prices the anisotropic coat's albedo).

For each case, on the same ``n`` random pairs (``throughput.directions``, seed 0; 2·10^5,
smoke 2000), all threads, the median of ``runs`` timings (5, smoke 2; the library before:
3) of the material's ``eval``, ``pdf``, ``eval_pdf`` and ``sample``, and of ``eval`` and
``sample`` of every lobe in ``material.lobes`` alone (the active lobes: zero-weight lobes are
never built), taken in rounds of one run of each (``_interleaved``), so that a slow spell
of the machine slows all of a case's calls alike and their ratios hold. Times are
given in *memory passes*: the time of one ``np.add(a, b, out=c)`` over float64 ``(n, 3)``
arrays, taken per element at 10^6 pairs (where the arrays leave the caches; at 2·10^5 the
same add runs ~25 % faster per element) times n: the unit of the headline section.

The ratios of the acceptance: eval / Σ lobes' eval, sample / Σ lobes' eval, sample / eval;
and sample / Σ lobes' sample, what a material's sample costs against its lobes' own samples
(each lobe sampled on every pair, where the material samples each on its share of them but
evaluates the others at the sampled directions).
At the sampled directions (``sampled_directions``): the material's ``eval`` and every
lobe's ``eval_pdf`` there, and the floor sum_i min(sample_i, eval_pdf_i there): what the
lobes' own work costs a sample, whatever composes them (``sampled_summary``); and the
mixture floor sum_i P_i sample_i + (1 - P_i) eval_pdf_i there, with P_i the share of the
pairs the material sampled lobe i on (``sample_shares``, ``mixture_floor``): what its lobes
cost a sample chosen as the material chooses, with nothing spent on composing them.
``before`` repeats the measurement on ``BASELINE`` (the library before the material-cost
work) in a subprocess of the same run (``benchmarks.baseline.run_script``), on the first
``BEFORE_N`` of the pairs. ``unretained`` repeats the materials' eval and sample (one run)
in a subprocess with ``ADOBE_BSDF_RETAINED_MEMORY=0`` (glibc's own allocator thresholds,
``config`` ``retained_memory``). Every measurement also counts the minor page faults of one
further call of eval and of sample (``resource.getrusage``; 0 where unavailable).
"""

from __future__ import annotations

import time

import numpy as np

from benchmarks import throughput as tp

__all__ = ["BASELINE", "CALLS", "material_cases", "sample_shares", "mixture_floor", "measure",
           "run", "markdown"]

#: the library before the work on whole materials' cost (the "before" column)
BASELINE = "edb2db5"
CALLS = ("eval", "pdf", "eval_pdf", "sample")
#: pairs per call (smoke: 2000) and runs per median; the library before is timed on the
#: first BEFORE_N pairs (its anisotropic top albedo was a quadrature per direction: minutes
#: per call at N)
N, SMOKE_N, RUNS, BEFORE_N = 200_000, 2_000, 5, 20_000
#: runs per median of the library before (its calls are the slow ones)
BEFORE_RUNS = 3
#: the unit's reference size
UNIT_N = 10**6

_FULL_ASM = {"metallic": 0.3, "translucency": 0.5, "dispersion": 1.0,
             "anisotropy_level": 0.5, "anisotropy_angle": 0.2, "coat_opacity": 0.7,
             "coat_color": (0.9, 0.8, 0.6), "sheen_opacity": 0.5, "sheen_roughness": 0.4}


def material_cases() -> list:
    """``[(label, make)]``: the defaults first, then the registered material cases, the
    OpenPBR preset "everything" and the coat pair."""
    from adobe_bsdf.materials import AdobeStandardMaterial, OpenPBRSurface, presets
    from adobe_bsdf.materials.material import Material
    from adobe_bsdf.validation.cases import cases

    out = [("ASM default", AdobeStandardMaterial), ("OpenPBR default", OpenPBRSurface)]
    out += [(c.name, c.make) for c in cases() if isinstance(c.make(), Material)]
    out += [("OpenPBR everything (preset)",
             lambda: OpenPBRSurface(**presets.openpbr["everything"])),
            ("ASM fully loaded, isotropic coat", lambda: AdobeStandardMaterial(
                **_FULL_ASM, coat_roughness=0.3)),
            ("ASM fully loaded, anisotropic coat", lambda: AdobeStandardMaterial(
                **_FULL_ASM, coat_roughness=0.3, coat_anisotropy_level=0.5))]
    return out


def _faults(lobe, call, n, wo, wi, u) -> int:
    """Minor page faults of one ``call`` on the first n pairs (0 without ``resource``)."""
    try:
        import resource
    except ImportError:  # pragma: no cover - not on Unix
        return 0
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    tp.time_call(lobe, call, wo[:n], wi[:n], u[:n])
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before


def sampled_directions(material, wo, wi, u):
    """The directions ``material.sample(wo, u)`` returns (``wi`` where a sample fails): the
    pairs on which a material's sample evaluates its lobes."""
    s = material.sample(wo, u)
    return np.where((s.pdf > 0.0)[:, None], s.wi, wi)


def sample_shares(material, wo, u) -> dict:
    """``{name: share}``: the share of the pairs of ``material.sample(wo, u)`` (after one
    warm-up call: tables built on first use sample their lobes) that each lobe of
    ``material.lobes`` was sampled on (the rows handed to its own sampler; a lobe that a
    composition samples on every pair, textured parameters for one, counts them all)."""
    from adobe_bsdf.config import options

    material.sample(wo, u)
    counts = dict.fromkeys(material.lobes, 0)
    inside = set()  # lobes in one of their counted calls (a hook calling another)

    def counter(name, call):
        def counting(w, v, *rest):
            outer = name not in inside
            if outer:
                counts[name] += int(np.prod(np.broadcast_shapes(w.shape, v.shape)[:-1]))
                inside.add(name)
            try:
                return call(w, v, *rest)
            finally:
                if outer:
                    inside.discard(name)
        return counting

    patched = []
    for name, lobe in material.lobes.items():
        for hook in ("_sample", "_sample_t", "_sample_directions"):
            # an instance attribute over the method
            setattr(lobe, hook, counter(name, getattr(lobe, hook)))
            patched.append((lobe, hook))
    try:
        with options(threads=1):  # (the count is not shared between threads)
            material.sample(wo, u)
    finally:
        for lobe, hook in patched:
            delattr(lobe, hook)
    return {name: count / len(u) for name, count in counts.items()}


def _interleaved(timers, n, wo, u, runs) -> list:
    """Median seconds of each timer ``(lobe, call, wi)`` on the first n pairs over ``runs``
    rounds of one run of every timer: a slow spell of the machine falls on all of a case's
    calls alike rather than on one of them, which keeps their ratios. Each timer is first
    warmed up and called once to calibrate: a call shorter than ``MIN_RUN_SECONDS`` repeats
    within a run, which takes the mean."""
    def once(lobe, call, wi):
        return tp.time_call(lobe, call, wo[:n], wi[:n], u[:n])

    repeats = []
    for lobe, call, wi in timers:
        tp._call(lobe, call, wo[:100], wi[:100], u[:100])  # warm-up (tables, caches)
        repeats.append(tp.repeats_for(once(lobe, call, wi)))
    times = [[] for _ in timers]
    for _ in range(runs):
        for k, ((lobe, call, wi), r) in enumerate(zip(timers, repeats, strict=True)):
            times[k].append(sum(once(lobe, call, wi) for _ in range(r)) / r)
    return [float(np.median(t)) for t in times]


def _timers(material, calls, n, wo, wi, u, lobes: bool, sampled: bool) -> dict:
    """``{path: (lobe, call, wi)}``: what ``measure`` times for one case, keyed by where the
    seconds go in its row."""
    timers = {}
    if lobes:
        for name, lobe in material.lobes.items():
            timers["lobes", name] = (lobe, "eval", wi)
            timers["lobe_samples", name] = (lobe, "sample", wi)
        if sampled:
            ws = sampled_directions(material, wo[:n], wi[:n], u[:n])
            timers["sampled", "eval"] = (material, "eval", ws)
            for name, lobe in material.lobes.items():
                timers["sampled", "lobes", name] = (lobe, "eval_pdf", ws)
    for call in calls:
        timers[(call,)] = (material, call, wi)
    return timers


def measure(n: int, runs: int, log=None, calls=CALLS, lobes: bool = True,
            sampled: bool = True) -> dict:
    """``{"n", "runs", "pass_seconds", "rows"}``: per case, the material's ``calls`` (and,
    with ``lobes``, its lobes' ``eval`` and ``sample``, and with ``sampled`` too,
    ``"sampled"``: the material's eval and its lobes' eval_pdf at its sampled directions)
    in seconds, timed interleaved (``_interleaved``), or the error; and ``"faults"``: minor
    page faults of one eval and one sample."""
    wo, wi, u = tp.directions(n)
    unit = tp.memory_pass(UNIT_N, runs)[0] / UNIT_N * n
    rows = []
    start = time.perf_counter()
    for label, make in material_cases():
        row = {"case": label}
        try:
            material = make()
            timers = _timers(material, calls, n, wo, wi, u, lobes, sampled)
            for path, seconds in zip(timers, _interleaved(list(timers.values()), n, wo, u,
                                                          runs), strict=True):
                place = row
                for key in path[:-1]:
                    place = place.setdefault(key, {})
                place[path[-1]] = seconds
            if lobes and sampled:
                row["shares"] = sample_shares(material, wo[:n], u[:n])
            row["faults"] = {c: _faults(material, c, n, wo, wi, u) for c in ("eval", "sample")}
        except Exception as exc:  # reported, not fatal
            row["error"] = f"{type(exc).__name__}: {exc}"
        rows.append(row)
        if log:
            log(f"{label}: {time.perf_counter() - start:.0f} s")
    return {"n": n, "runs": runs, "pass_seconds": unit, "rows": rows}


_SCRIPT = """
import json, sys
from benchmarks import material_cost
json.dump(material_cost.measure({n}, {runs}, **{options}), open(sys.argv[1], "w"))
"""


def _unretained(n: int) -> dict:
    """Eval and sample (one run) of this library with ``ADOBE_BSDF_RETAINED_MEMORY=0``, in a
    subprocess (the option is read at import)."""
    import json
    import os
    import subprocess
    import sys
    import tempfile
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    with tempfile.TemporaryDirectory(prefix="adobe_bsdf_unretained_") as tmp:
        out = Path(tmp) / "result.json"
        script = _SCRIPT.format(n=n, runs=1, options={"calls": ("eval", "sample"),
                                                       "lobes": False})
        env = {**os.environ, "ADOBE_BSDF_RETAINED_MEMORY": "0",
               "PYTHONPATH": os.pathsep.join([str(root), os.environ.get("PYTHONPATH", "")])}
        subprocess.run([sys.executable, "-c", script, str(out)], cwd=root, env=env,
                       check=True, capture_output=True, timeout=3600)
        return json.loads(out.read_text())


def run(smoke: bool = False, log=None) -> dict:
    """This library's cost model, the same without retained memory, and ``BASELINE``'s,
    measured in one run."""
    from benchmarks import baseline

    n, runs = (SMOKE_N, 2) if smoke else (N, RUNS)
    after = measure(n, runs, log)
    try:
        unretained = _unretained(n)
    except Exception as exc:  # reported in the page
        unretained = {"error": f"{type(exc).__name__}: {exc}"}
    try:
        before = baseline.run_script(_SCRIPT.format(n=min(n, BEFORE_N),
                                                    runs=min(runs, BEFORE_RUNS),
                                                    options={"sampled": False}),
                                     BASELINE, ("adobe_bsdf", "tables"))
    except Exception as exc:  # git or the old library unavailable: said in the page
        before = {"error": f"{type(exc).__name__}: {exc}"}
    return {**after, "unretained": unretained, "before": before}


# --- the page ------------------------------------------------------------------------------
def _passes(section: dict, seconds) -> float:
    return seconds / section["pass_seconds"]


def _fault_table(section: dict) -> list:
    """Page faults per 1000 pairs of one eval and one sample, and eval and sample in passes,
    with and without retained memory (and the faults before)."""
    other = section.get("unretained", {})
    if "rows" not in other:
        return ["", f"Without retained memory: not measured ({other.get('error')})."]
    before = section.get("before", {})
    old = {r["case"]: r for r in before.get("rows", []) if "faults" in r}
    off = {r["case"]: r for r in other["rows"] if "faults" in r}

    def per_k(row, section, call):
        return f"{1000 * row['faults'][call] / section['n']:.0f}"

    out = ["", "Page faults (minor, per 1000 pairs, of one further call) and passes, with the "
           "default `retained_memory` and with `ADOBE_BSDF_RETAINED_MEMORY=0` (glibc's own "
           "thresholds; eval and sample, one run, in a subprocess of this run, in this run's "
           "memory pass; docs/execution.md, \"Memory the allocator keeps\"):", "",
           "| case | faults eval, sample | passes eval, sample | =0: faults eval, sample | "
           "=0: passes eval, sample | before: faults eval, sample |", "|---|---|---|---|---|---|"]
    for row in section["rows"]:
        label = row["case"]
        if "faults" not in row or label not in off:
            continue
        cells = [label, f"{per_k(row, section, 'eval')}, {per_k(row, section, 'sample')}",
                 f"{_passes(section, row['eval']):.0f}, {_passes(section, row['sample']):.0f}",
                 f"{per_k(off[label], other, 'eval')}, {per_k(off[label], other, 'sample')}",
                 f"{_passes(section, off[label]['eval']):.0f}, "
                 f"{_passes(section, off[label]['sample']):.0f}",
                 f"{per_k(old[label], before, 'eval')}, {per_k(old[label], before, 'sample')}"
                 if label in old else "–"]
        out.append("| " + " | ".join(cells) + " |")
    return out + [""]


def summary(section: dict) -> list:
    """Per measured case: ``(label, k, lobes, {call: passes}, {ratio: value})``."""
    out = []
    for row in section["rows"]:
        if "error" in row:
            continue
        lobes = _passes(section, sum(row["lobes"].values()))
        calls = {c: _passes(section, row[c]) for c in CALLS}
        ratios = {"eval / lobes": calls["eval"] / lobes, "sample / lobes":
                  calls["sample"] / lobes, "sample / eval": calls["sample"] / calls["eval"]}
        if "lobe_samples" in row:  # (not measured by the library before)
            calls["lobe samples"] = _passes(section, sum(row["lobe_samples"].values()))
            ratios["sample / lobe samples"] = calls["sample"] / calls["lobe samples"]
        out.append((row["case"], len(row["lobes"]), lobes, calls, ratios))
    return out


def sampled_summary(section: dict) -> list:
    """Per case measured at its sampled directions: ``(label, {name: passes})`` with the
    material's eval on the uniform pairs ("eval") and at the sampled directions ("eval
    there"), its sample, and "floor": sum over its lobes of min(sample, eval_pdf there)."""
    out = []
    for row in section["rows"]:
        there = row.get("sampled")
        if "error" in row or not there:
            continue
        floor = sum(min(row["lobe_samples"][k], there["lobes"][k]) for k in there["lobes"])
        p = {"eval": _passes(section, row["eval"]),
             "eval there": _passes(section, there["eval"]),
             "sample": _passes(section, row["sample"]), "floor": _passes(section, floor)}
        if "shares" in row:
            p["mixture floor"] = _passes(section, mixture_floor(row))
        out.append((row["case"], p))
    return out


def mixture_floor(row: dict) -> float:
    """Seconds of sum_k P_k sample_k + (1 - P_k) eval_pdf_k there, P_k the share of the pairs
    the material sampled lobe k on (at most 1): each pair needs its chosen lobe's sample
    and every other lobe's value and pdf at the sampled direction, with the material's own
    choices (its selection probabilities, computed for free)."""
    there = row["sampled"]["lobes"]
    total = 0.0
    for k, share in row["shares"].items():
        share = min(share, 1.0)
        total += share * row["lobe_samples"][k] + (1.0 - share) * there[k]
    return total


def _sampled_table(section: dict) -> list:
    rows = sampled_summary(section)
    if not rows:
        return []
    out = ["", "### Where a sample's time goes", "",
           "A sample returns, for every pair, a direction in the material's support with the "
           "weight and pdf of the whole mixture there; `eval` on the uniform pairs above "
           "skips the pairs outside the support (for a reflection, the half below the "
           "surface). *Eval there*: the material's `eval` at (wo, the direction its `sample` "
           "returned). *Floor*: the sum over the active lobes of the smaller of the lobe's "
           "own `sample` (on every pair) and its `eval_pdf` at the sampled directions: every "
           "pair needs, of each lobe, either its sample or its value and pdf there, so no "
           "composition of these lobes samples for less. *Mixture floor*: with the "
           "material's own choice of lobe, sum_k P_k sample_k + (1 - P_k) eval_pdf_k there, "
           "P_k the share of the pairs it sampled lobe k on (*shares*; counted in one "
           "`sample` call): every pair needs its chosen lobe's sample and the other lobes' "
           "value and pdf at the sampled direction, even with the selection probabilities "
           "free. Same pairs, runs and unit as above.", "",
           "| case | eval | eval there | sample | sample / eval | sample / eval there | "
           "floor | floor / eval | sample / floor | mixture floor | mixture floor / eval | "
           "sample / mixture floor | shares |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for label, p in rows:
        mixture = p.get("mixture floor")
        mixed = ("– | – | – | –" if mixture is None else
                 f"{mixture:.0f} | {mixture / p['eval']:.2f} | {p['sample'] / mixture:.2f} | "
                 + ", ".join(f"{k} {v:.2f}" for k, v in _shares(section, label).items()))
        out.append(f"| {label} | {p['eval']:.0f} | {p['eval there']:.0f} | {p['sample']:.0f} "
                   f"| {p['sample'] / p['eval']:.2f} | {p['sample'] / p['eval there']:.2f} | "
                   f"{p['floor']:.0f} | {p['floor'] / p['eval']:.2f} | "
                   f"{p['sample'] / p['floor']:.2f} | {mixed} |")
    bound = BOUNDS["sample / eval"]
    above = [label for label, p in rows if p["floor"] > bound * p["eval"]]
    out += ["", f"Floor above {bound:g}× the material's eval (where the bound sample / eval "
            "cannot be met by any composition of these lobes): "
            + (", ".join(above) if above else "none") + "."]
    above = [label for label, p in rows if p.get("mixture floor", 0.0) > bound * p["eval"]]
    out += ["", f"Mixture floor above {bound:g}× the material's eval (where these lobes, "
            "chosen as the material chooses them, cost a sample more than the bound "
            "allows): " + (", ".join(above) if above else "none") + "."]
    return out


def _shares(section: dict, label: str) -> dict:
    """The sampled shares of case ``label``'s lobes."""
    return next(row["shares"] for row in section["rows"] if row["case"] == label)


#: the acceptance bounds of the ratios
BOUNDS = {"eval / lobes": 1.5, "sample / lobes": 2.5, "sample / eval": 2.0}


def _plot(plt, section: dict, path) -> bool:
    rows = summary(section)
    before = {r[0]: r for r in summary(section["before"])} if "rows" in section.get(
        "before", {}) else {}
    if not rows:
        return False
    fig, ax = plt.subplots(figsize=(7, 4.5))
    jitter = {}
    for label, k, lobes, calls, _ in rows:
        x = k + 0.06 * jitter.setdefault(k, 0) - 0.15
        jitter[k] += 1
        ax.plot([x], [lobes], "k_", ms=10)
        ax.plot([x], [calls["eval"]], "o", color="C0", ms=4)
        ax.plot([x], [calls["sample"]], "s", color="C1", ms=4)
        if label in before:
            ax.plot([x, x], [before[label][3]["sample"], calls["sample"]], "-", color="C1",
                    alpha=0.25)
            ax.plot([x], [before[label][3]["sample"]], "s", color="C1", ms=4, alpha=0.25)
    ax.plot([], [], "k_", ms=10, label="Σ active lobes' eval")
    ax.plot([], [], "o", color="C0", label="material eval")
    ax.plot([], [], "s", color="C1", label="material sample")
    if before:
        ax.plot([], [], "s", color="C1", alpha=0.25, label=f"sample before ({BASELINE})")
    ax.set_yscale("log")
    ax.set_xlabel("active lobes (entries of material.lobes)")
    ax.set_ylabel(f"memory passes ({section['n']:,} pairs)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def markdown(section: dict, figure_dir, smoke: bool, link_prefix: str = "figures/") -> str:
    """The page's section "Whole materials against their lobes"."""
    from benchmarks import pyplot

    out = ["## Whole materials against their lobes", ""]
    if "rows" not in section:
        return "\n".join(out + [f"materials section failed: {section.get('error')}", ""])
    out += [f"Every material case on the same {section['n']:,} pairs, all threads, median of "
            f"{section['runs']} runs, in memory passes (one `np.add` over (n, 3) float64 "
            "arrays, per element as at 10^6 pairs, times n). *Σ lobes*: the sum of `eval` "
            "of every lobe in `material.lobes` timed alone on the same pairs (the active "
            "lobes; lobes whose weight is zero are never built). *Σ lobes' sample*: the "
            "same lobes' `sample`, each on every pair; a material samples each lobe on the "
            "pairs that chose it and evaluates the others at the sampled directions (all in "
            "their support, where `eval` on these pairs skips the half below the surface). "
            "Method: `benchmarks/material_cost.py`.", ""]
    plt = pyplot()
    name = "performance_materials.png"
    if plt is not None and _plot(plt, section, figure_dir / name):
        out += [f"![materials]({link_prefix}{name})", ""]
    before = section.get("before", {})
    old = {r[0]: r for r in summary(before)} if "rows" in before else {}
    out += ["| case | lobes | Σ lobes | eval | pdf | eval_pdf | sample | eval / Σ | "
            "sample / Σ | sample / eval | Σ lobes' sample | sample / Σ lobes' sample | "
            "before: eval, sample |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    rows = summary(section)
    for label, k, lobes, calls, ratios in rows:
        was = old.get(label)
        then = f"{was[3]['eval']:.0f}, {was[3]['sample']:.0f}" if was else "–"
        own = (f"{calls['lobe samples']:.0f} | {ratios['sample / lobe samples']:.2f}"
               if "lobe samples" in calls else "– | –")
        out.append(f"| {label} | {k} | {lobes:.0f} | "
                   + " | ".join(f"{calls[c]:.0f}" for c in CALLS) + " | "
                   + " | ".join(f"{ratios[r]:.2f}" for r in BOUNDS) + f" | {own} | {then} |")
    errors = [r for r in section["rows"] if "error" in r]
    if errors:
        out += [""] + [f"- {r['case']}: {r['error']}" for r in errors]
    if "rows" not in before:
        out += ["", f"Before ({BASELINE}): not measured ({before.get('error')})."]
    else:
        out += ["", f"*Before*: the library at {BASELINE} (before this work), the same code "
                f"timing it in a subprocess of this run, on the first {before['n']:,} of the "
                "pairs (in the same unit)."]
    out += ["", "Bounds: " + "; ".join(
        f"{r} ≤ {b}: met by {sum(x[4][r] <= b for x in rows)} of {len(rows)} cases"
        for r, b in BOUNDS.items()) + "."]
    out += _sampled_table(section)
    out += _fault_table(section)
    by = {r[0]: r for r in rows}
    iso, aniso = (by.get(f"ASM fully loaded, {c} coat") for c in ("isotropic", "anisotropic"))
    if iso and aniso:
        out.append(f"The anisotropic coat costs {aniso[3]['eval'] / iso[3]['eval']:.2f}× the "
                   f"isotropic coat in eval and {aniso[3]['sample'] / iso[3]['sample']:.2f}× "
                   "in sample (bound 2).")
    defaults = [f"{k} {by[k][3]['eval']:.0f} passes" for k in ("ASM default", "OpenPBR default")
                if k in by]
    if defaults:
        out.append("Default materials' eval: " + ", ".join(defaults) + " (bound 40).")
    return "\n".join(out + [""])
