"""Does any single OpenPBR input, set away from its default, make ``eval`` or ``sample`` much
more expensive than the default material? Writes ``docs/parameter_cost.md``.

    python -m benchmarks.parameter_cost [--smoke] [--out DIR] [--pairs N]

The sweep (``configurations``): the default ``OpenPBRSurface``; for every input of v1.1.1
(``PARAMETERS``), the default with that input alone set to a typical value that turns its
feature on (``VALUES``; an input that acts only with another, coat_roughness without
coat_weight say, is swept alone all the same); the default under ``spec="dev_1.2"`` and each
of that branch's inputs (``DEV_1_2``) against it; and a few pairs that act together
(``PAIRS``). Each row's ratios are to the default material of its own ``spec``. Then the
thin film's own cost (``film_rows``): over each base of ``FILM_BASES`` (dielectric, metal,
glass bulk, thin-walled and dispersive, rough and anisotropic), the base with the film
against the same base without it.

Timing: ``eval`` and ``sample`` of each material on the same N random pairs
(``throughput.directions``, seed 0: ``wo`` above the surface, ``wi`` anywhere; N = 10 000,
``--smoke`` 1000), on one thread (``config.options(threads=1)``). Each call is first made
twice on ``WARM`` pairs: the first builds what a lobe builds on first use (its ``eval`` is
the "first call" column), the second predicts the time on N pairs. Then the material's two
calls and the same two calls of the default material of its ``spec`` (built once, before the
sweep) are timed in alternating rounds (``material_cost._interleaved``: the median of
``RUNS`` rounds, smoke 2, at most 3 where a call is predicted over ``SLOW_SECONDS``; a call
under 5 ms repeats within a round and takes the mean), so that a slow spell of the machine
falls on both alike: the ratios are of these medians. The default row itself is a fresh
build of the default against that reference: its ratios show the noise. Where a call is
predicted over ``LONG_SECONDS`` on N pairs, the row is timed on fewer pairs (about
``TARGET_SECONDS`` per call; the default too, so the ratio is per pair) and its seconds are
scaled to N (the row says so). Build: the seconds of the first construction of the
material in the process, in the order of the sweep (tables that an earlier row or the
reference loaded are not loaded again). A material that fails to build or to run is listed
with its error.
"""

from __future__ import annotations

import argparse
import datetime
import functools
import time
import warnings
from pathlib import Path

import numpy as np

from adobe_bsdf.config import options
from adobe_bsdf.materials import OpenPBRSurface
from adobe_bsdf.materials.openpbr.parameters import DEV_1_2, PARAMETERS
from benchmarks import machine, write_page
from benchmarks import throughput as tp
from benchmarks.material_cost import _interleaved

__all__ = ["VALUES", "PAIRS", "configurations", "measure", "markdown", "run", "main"]

PAGE = "parameter_cost.md"
#: pairs per call (smoke: SMOKE_N) and rounds per median (smoke: SMOKE_RUNS)
N, SMOKE_N = 10_000, 1_000
RUNS, SMOKE_RUNS = 11, 2
#: pairs of the warm-up call, which also predicts the time of the timed one
WARM = 100
#: a call predicted to take longer is timed over 3 rounds at most
SLOW_SECONDS = 2.0
#: a call predicted to take longer on N pairs is timed on fewer (about TARGET_SECONDS) and
#: scaled to N
LONG_SECONDS, TARGET_SECONDS = 60.0, 10.0
CALLS = ("eval", "sample")
#: the ratios the summary counts rows above
THRESHOLDS = (20.0, 5.0)

#: the typical value of each input that turns its feature on (colours: a non-white colour)
VALUES = {
    "base_weight": 0.5,
    "base_color": (0.8, 0.3, 0.1),
    "base_diffuse_roughness": 0.5,
    "base_metalness": 1.0,
    "specular_weight": 0.5,
    "specular_color": (1.0, 0.8, 0.6),
    "specular_roughness": 0.6,
    "specular_roughness_anisotropy": 0.8,
    "specular_ior": 1.8,
    "transmission_weight": 1.0,
    "transmission_color": (0.8, 0.5, 0.3),
    "transmission_depth": 1.0,
    "transmission_scatter": (0.5, 0.5, 0.5),
    "transmission_scatter_anisotropy": 0.5,
    "transmission_dispersion_scale": 1.0,
    "transmission_dispersion_abbe_number": 40.0,
    "subsurface_weight": 1.0,
    "subsurface_color": (0.8, 0.4, 0.3),
    "subsurface_radius": 0.5,
    "subsurface_radius_scale": (1.0, 0.8, 0.5),
    "subsurface_scatter_anisotropy": 0.5,
    "coat_weight": 1.0,
    "coat_color": (0.9, 0.7, 0.5),
    "coat_roughness": 0.3,
    "coat_roughness_anisotropy": 0.8,
    "coat_ior": 1.4,
    "coat_darkening": 0.0,
    "fuzz_weight": 1.0,
    "fuzz_color": (0.9, 0.6, 0.4),
    "fuzz_roughness": 0.8,
    "emission_luminance": 100.0,
    "emission_color": (1.0, 0.5, 0.2),
    "thin_film_weight": 1.0,
    "thin_film_thickness": 0.3,
    "thin_film_ior": 1.6,
    "geometry_opacity": 0.5,
    "geometry_thin_walled": True,
    "geometry_normal": (0.6, 0.0, 0.8),
    "geometry_tangent": (0.6, 0.8, 0.0),
    "geometry_coat_normal": (0.6, 0.0, 0.8),
    "geometry_coat_tangent": (0.6, 0.8, 0.0),
    "specular_haze": 0.5,
    "specular_haze_spread": 0.6,
    "specular_retroreflectivity": 0.5,
    "emission_weight": 1.0,
}

_FILM = {"thin_film_weight": 1.0, "thin_film_thickness": 0.5}
#: inputs that act together (spec "1.1.1")
PAIRS = [
    {"base_metalness": 1.0, **_FILM},
    {"specular_roughness_anisotropy": 0.8, **_FILM},
    {"base_metalness": 1.0, "specular_roughness_anisotropy": 0.8},
    {"coat_weight": 1.0, "coat_roughness": 0.3, "coat_roughness_anisotropy": 0.8},
    {"transmission_weight": 1.0, "transmission_dispersion_scale": 1.0},
    {"transmission_weight": 1.0, "geometry_thin_walled": True},
    {"transmission_weight": 1.0, **_FILM},
    {"transmission_weight": 1.0, "geometry_thin_walled": True, **_FILM},
    {"transmission_weight": 1.0, "transmission_dispersion_scale": 1.0, **_FILM},
]
#: the bases of the thin film's own cost (``film_rows``): each timed with ``_FILM`` against
#: itself without it
FILM_BASES = {
    "dielectric (the default)": {},
    "rough dielectric": {"specular_roughness": 0.6},
    "anisotropic dielectric": {"specular_roughness_anisotropy": 0.8},
    "coated dielectric": {"coat_weight": 1.0},
    "metal": {"base_metalness": 1.0},
    "anisotropic metal": {"base_metalness": 1.0, "specular_roughness_anisotropy": 0.8},
    "glass": {"transmission_weight": 1.0},
    "rough glass": {"transmission_weight": 1.0, "specular_roughness": 0.6},
    "thin-walled glass": {"transmission_weight": 1.0, "geometry_thin_walled": True},
    "dispersive glass": {"transmission_weight": 1.0, "transmission_dispersion_scale": 1.0},
}


def _text(value) -> str:
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, tuple):
        return "(" + ", ".join(_text(v) for v in value) + ")"
    return f"{value:g}"


def configurations() -> list:
    """``[(inputs, values, spec, params)]``: the defaults, every input alone, then ``PAIRS``;
    ``inputs`` and ``values`` are the row's labels ("default" and "—" for a default)."""
    out = [("default", "—", "1.1.1", {})]
    for name in PARAMETERS.parameters:
        if name not in DEV_1_2:
            out.append((name, _text(VALUES[name]), "1.1.1", {name: VALUES[name]}))
    out.append(("default", "—", "dev_1.2", {}))
    out += [(name, _text(VALUES[name]), "dev_1.2", {name: VALUES[name]}) for name in DEV_1_2]
    out += [(" + ".join(p), ", ".join(_text(v) for v in p.values()), "1.1.1", p)
            for p in PAIRS]
    return out


def _build(spec, params):
    """``(material, seconds, warnings' first clauses)`` of the first construction."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        start = time.perf_counter()
        material = OpenPBRSurface(spec=spec, **params)
        seconds = time.perf_counter() - start
    said = sorted({str(w.message).split(":")[1].strip() if ":" in str(w.message)
                   else str(w.message) for w in caught})
    return material, seconds, said


def _timed(material, default, wo, wi, u, runs) -> dict:
    """``eval`` and ``sample`` of ``material`` in seconds on all the pairs, their ratios to
    ``default`` timed in the same rounds (``material_cost._interleaved``), the pairs timed
    and the seconds of the first ``eval`` (on ``WARM`` pairs; a second call on them predicts
    the time on all the pairs)."""
    out, predicted = {"n": len(wo)}, 0.0
    for call in CALLS:
        first = tp.time_call(material, call, wo[:WARM], wi[:WARM], u[:WARM])
        out.setdefault("first", first)
        predicted = max(predicted, tp.time_call(material, call, wo[:WARM], wi[:WARM],
                                                u[:WARM]) * len(wo) / WARM)
    if predicted > LONG_SECONDS:
        out["n"] = max(WARM, int(len(wo) * TARGET_SECONDS / predicted))
    if predicted > SLOW_SECONDS:
        runs = min(runs, 3)
    seconds = _interleaved([(m, call, wi) for m in (material, default) for call in CALLS],
                           out["n"], wo, u, runs)
    for k, call in enumerate(CALLS):
        out[call] = seconds[k] * len(wo) / out["n"]
        out[f"{call}_ratio"] = seconds[k] / seconds[k + len(CALLS)]
    return out


def measure(pairs: int, runs: int, log=None) -> dict:
    """``{"pairs", "runs", "rows"}``; a row: inputs, values, spec, lobes, notes, the seconds
    of build, first call, eval and sample, the pairs timed and the ratios to the default, or
    its error."""
    wo, wi, u = tp.directions(pairs)
    rows = []
    with options(threads=1):
        defaults = {}  # the reference of each spec (the tables every material shares load)
        for spec in ("1.1.1", "dev_1.2"):
            defaults[spec] = OpenPBRSurface(spec=spec)
            for call in CALLS:
                tp._call(defaults[spec], call, wo[:WARM], wi[:WARM], u[:WARM])
        for inputs, values, spec, params in configurations():
            row = {"inputs": inputs, "values": values, "spec": spec, "notes": []}
            rows.append(_row(row, spec, params, functools.partial(defaults.get, spec), wo, wi,
                             u, runs, log, f"{inputs} ({spec})"))
    return {"pairs": pairs, "runs": runs, "rows": rows,
            "film_rows": film_rows(wo, wi, u, runs, log)}


def film_rows(wo, wi, u, runs, log=None) -> list:
    """The thin film's cost over each of ``FILM_BASES``: the base with ``_FILM`` timed against
    the base itself, as ``measure`` times a row against the default."""
    rows = []
    with options(threads=1):
        for name, params in FILM_BASES.items():
            row = {"base": name, "params": params, "notes": []}

            def base(params=params):
                material, _, _ = _build("1.1.1", params)
                for call in CALLS:
                    tp._call(material, call, wo[:WARM], wi[:WARM], u[:WARM])
                return material
            rows.append(_row(row, "1.1.1", {**params, **_FILM}, base, wo, wi, u, runs, log,
                             f"film over {name}"))
    return rows


def _row(row: dict, spec, params, reference, wo, wi, u, runs, log, label: str) -> dict:
    """``row`` with the build of the material of ``params`` and its timings against
    the material ``reference()`` returns (``_timed``), or the error either raised; logged as
    ``label``."""
    try:
        material, row["build"], said = _build(spec, params)
        row["lobes"] = list(material.lobes)
        row["notes"] += [f"warns: {s}" for s in said]
        row.update(_timed(material, reference(), wo, wi, u, runs))
        if row["n"] < len(wo):
            row["notes"].append(f"timed on {row['n']} pairs, scaled to {len(wo)}")
    except Exception as exc:  # reported in the page
        row["error"] = f"{type(exc).__name__}: {exc}"
    if log:
        log(f"{label}: eval ×{row.get('eval_ratio', float('nan')):.2f}, "
            f"sample ×{row.get('sample_ratio', float('nan')):.2f}")
    return row


def _worst(rows, key):
    row = max(rows, key=lambda r: r[key])
    return f"**{row[key]:.1f}×**, `{row['inputs']}` = {row['values']} (spec {row['spec']})"


def markdown(result: dict, seconds: float) -> str:
    timed = sorted((r for r in result["rows"] if "eval_ratio" in r),
                   key=lambda r: r["eval_ratio"], reverse=True)
    failed = [r for r in result["rows"] if "eval_ratio" not in r]
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    out = [f"*Generated by `python -m benchmarks.parameter_cost` on {now} in "
           f"{seconds:.1f} s; do not edit by hand. The method is the docstring of "
           "`benchmarks/parameter_cost.py`.*", "",
           "# OpenPBR Surface: the cost of each input", ""]
    if timed:
        out += [f"Worst `eval` ratio to the default material: {_worst(timed, 'eval_ratio')}. "
                f"Worst `sample` ratio: {_worst(timed, 'sample_ratio')}.", ""]
        counts = {key: ", ".join(f"{sum(r[key] > t for r in timed)} above {t:g}×"
                                 for t in THRESHOLDS) for key in ("eval_ratio", "sample_ratio")}
        out += [f"Of {len(timed)} rows: `eval` {counts['eval_ratio']}; `sample` "
                f"{counts['sample_ratio']}.", ""]
    out += [f"`eval` and `sample` on the same {result['pairs']} random pairs (`wo` above the "
            "surface, `wi` anywhere), one thread. Each row is the default material with only "
            "the listed inputs changed; its ratios are to the default of the same `spec`, the "
            "two timed in alternating rounds after a warm-up: the median of "
            f"{result['runs']} rounds (3 at most for a call over {SLOW_SECONDS:g} s; a call "
            "under 5 ms repeats within a round). The `default` rows are a second build of the "
            "default against the first: their ratios show the noise of the measurement. "
            "*Build*: the first construction of the material in this run, in the order of the "
            "sweep (tables an earlier row loaded are not loaded again). *First call*: `eval` "
            f"on {WARM} pairs right after the build (what a lobe builds on first use). "
            "*Lobes*: the lobes built (an input that acts only with another builds the "
            f"default's). A call predicted over {LONG_SECONDS:g} s is timed on fewer pairs and "
            f"scaled. Machine: {machine.cpu_model()}, {machine.cores()} cores, NumPy "
            f"{np.__version__}.", "",
            "| inputs | values | spec | eval (s) | eval ratio | sample (s) | sample ratio | "
            "build (s) | first call (s) | lobes | notes |",
            "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in timed:
        out.append(f"| `{r['inputs']}` | {r['values']} | {r['spec']} | {r['eval']:.3g} | "
                   f"{r['eval_ratio']:.2f} | {r['sample']:.3g} | {r['sample_ratio']:.2f} | "
                   f"{r['build']:.3g} | {r['first']:.3g} | {', '.join(r['lobes'])} | "
                   f"{'; '.join(r['notes']) or '—'} |")
    out += _film_markdown(result.get("film_rows", []))
    film_failed = [r for r in result.get("film_rows", []) if "eval_ratio" not in r]
    out += ["", "## Failed", ""]
    out += ([f"- `{r['inputs']}` = {r['values']} (spec {r['spec']}): "
             f"{r.get('error', 'its default failed')}" for r in failed]
            + [f"- thin film over the {r['base']}: {r['error']}" for r in film_failed]
            ) or ["None."]
    return "\n".join(out) + "\n"


def _film_markdown(rows) -> list:
    """The section of ``film_rows``."""
    timed = [r for r in rows if "eval_ratio" in r]
    if not timed:
        return []
    film = ", ".join(f"{k} = {_text(v)}" for k, v in _FILM.items())
    out = ["", "## The thin film's cost over each base", "",
           f"Each base (spec 1.1.1) with the film ({film}) against the same base without it, "
           "timed in alternating rounds on the pairs above, as the rows above against the "
           f"default. Worst `eval` ratio: **{max(r['eval_ratio'] for r in timed):.2f}×**; "
           f"worst `sample` ratio: **{max(r['sample_ratio'] for r in timed):.2f}×**.", "",
           "| base | inputs | eval with film (s) | eval ratio | sample with film (s) | "
           "sample ratio | build (s) | first call (s) | notes |",
           "|---|---|---|---|---|---|---|---|---|"]
    for r in timed:
        inputs = ", ".join(f"`{k}` = {_text(v)}" for k, v in r["params"].items()) or "—"
        out.append(f"| {r['base']} | {inputs} | {r['eval']:.3g} | {r['eval_ratio']:.2f} | "
                   f"{r['sample']:.3g} | {r['sample_ratio']:.2f} | {r['build']:.3g} | "
                   f"{r['first']:.3g} | {'; '.join(r['notes']) or '—'} |")
    return out


def run(out: Path | None = None, smoke: bool = False, pairs: int | None = None,
        log=None) -> Path:
    n = pairs or (SMOKE_N if smoke else N)
    runs = SMOKE_RUNS if smoke else RUNS
    return write_page(out, PAGE, lambda: (measure(n, runs, log),), markdown)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help="tiny sizes (for the tests)")
    parser.add_argument("--out", type=Path, help="write into DIR instead of docs/")
    parser.add_argument("--pairs", type=int, help=f"pairs per call (default {N}, smoke "
                                                   f"{SMOKE_N})")
    args = parser.parse_args(argv)
    print(run(args.out, args.smoke, args.pairs, log=print))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
