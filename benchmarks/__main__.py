"""Speed of adobe_bsdf: ``python -m benchmarks [--smoke] [--out DIR]``.

Sections (each in its module; a failing section is recorded, not fatal):

* ``headline``: GGX gold conductor (exact Fresnel) and rough dielectric on 10^6 pairs,
  1 thread and all threads (``benchmarks.throughput.headline``);
* ``mitsuba``: the same lobes in Mitsuba 3's ``llvm_ad_rgb`` variant, in a subprocess
  (``benchmarks.mitsuba_bench``);
* ``baseline``: the headline on the library before the performance work, in a subprocess
  (``benchmarks.baseline``);
* ``chunks``: the headline ``eval`` as the chunk size varies, 1 thread and all threads, and
  two processes on half the batch each (``benchmarks.chunks``);
* ``throughput``: every registered case, 10^4 / 10^6 / 10^7 pairs (``benchmarks.throughput``);
* ``active_lobes``: ``Sum`` cost against the number of non-zero weights
  (``benchmarks.active_lobes``);
* ``materials``: every material case against the summed cost of its lobes, before and after
  (``benchmarks.material_cost``);
* ``tradeoff``: speed against accuracy (``benchmarks.tradeoff``, if it imports);
* ``conformance``: the time of ``conformance.compare``'s verdict on materials at 10^6
  samples per view (``benchmarks.conformance_cost``).

A full run writes ``benchmarks/results.json``, ``docs/performance.md`` and
``docs/figures/performance_*.png`` (about 15 minutes on 2 cores); ``--smoke`` uses tiny sizes
and writes into ``--out`` (default: a new temporary folder), never into the repository. A
run of some ``--sections`` into the repository keeps the other sections of the existing
``benchmarks/results.json`` (the page says when each part was measured).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import traceback
from pathlib import Path

import adobe_bsdf  # noqa: F401  (registers the lobes)
from benchmarks import (
    active_lobes,
    baseline,
    chunks,
    conformance_cost,
    machine,
    material_cost,
    mitsuba_bench,
    report,
)
from benchmarks import throughput as tp

SECTIONS = ("headline", "mitsuba", "baseline", "chunks", "throughput", "active_lobes",
            "materials", "tradeoff", "conformance")


def _log(message: str) -> None:
    print(f"[benchmarks] {message}", file=sys.stderr, flush=True)


def _section(name: str, fn, results: dict, seconds: dict) -> None:
    _log(f"{name} ...")
    start = time.perf_counter()
    try:
        results[name] = fn()
    except Exception:  # recorded in the report; the other sections still run
        results[name] = {"error": traceback.format_exc()}
        print(results[name]["error"], file=sys.stderr)
    seconds[name] = time.perf_counter() - start
    _log(f"{name}: {seconds[name]:.0f} s")


def _tradeoff(smoke: bool) -> dict:
    try:
        from benchmarks import tradeoff
    except ImportError as exc:
        return {"error": f"benchmarks.tradeoff does not import: {exc}"}
    return tradeoff.run(smoke)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(prog="python -m benchmarks",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true",
                        help="tiny sizes, 2 runs, output into --out (a temp dir by default)")
    parser.add_argument("--out", type=Path,
                        help="write results.json, performance.md and figures/ here instead "
                             "of benchmarks/ and docs/")
    parser.add_argument("--sections", default=",".join(SECTIONS),
                        help=f"comma-separated subset of {','.join(SECTIONS)}")
    parser.add_argument("--extra-seconds", type=float, default=tp.EXTRA_SECONDS,
                        help="time budget of the optional throughput measurements (1 thread "
                             "at 10^6, 10^7 pairs; default %(default)s; 'inf': all of them)")
    args = parser.parse_args(argv)
    sections = [s.strip() for s in args.sections.split(",") if s.strip()]
    unknown = set(sections) - set(SECTIONS)
    if unknown:
        parser.error(f"unknown sections {sorted(unknown)}; choose from {SECTIONS}")
    out = args.out
    if args.smoke and out is None:
        out = Path(tempfile.mkdtemp(prefix="adobe_bsdf_bench_"))

    start = time.perf_counter()
    smoke = args.smoke
    sizes = tp.SMOKE_SIZES if smoke else tp.SIZES
    ref = tp.SMOKE_SIZES[-1] if smoke else tp.SLICE
    results = {"smoke": smoke, "machine": machine.facts(), "sections": sections}
    seconds = {}
    wo, wi, u = tp.directions(max(sizes))
    runners = {
        "headline": lambda: tp.headline(wo, wi, u, smoke),
        "mitsuba": lambda: mitsuba_bench.run(wo[:ref], wi[:ref], u[:ref], smoke),
        "baseline": lambda: baseline.run(smoke),
        "chunks": lambda: chunks.run(smoke),
        "throughput": lambda: tp.run(wo, wi, u, smoke, args.extra_seconds, log=_log),
        "active_lobes": lambda: active_lobes.run(wo, wi, u, smoke),
        "materials": lambda: material_cost.run(smoke, log=_log),
        "tradeoff": lambda: _tradeoff(smoke),
        "conformance": lambda: {"rows": conformance_cost.measure(smoke)},
    }
    for name in SECTIONS:
        if name in sections:
            _section(name, runners[name], results, seconds)
    results["section_seconds"] = seconds
    results["total_seconds"] = time.perf_counter() - start
    results["load_average_1min_end"] = machine.facts()["load_average_1min"]
    if out is None and not smoke and set(sections) != set(SECTIONS):
        results = report.merged(results)  # a part: the other sections as they were
    paths = report.write(results, out, smoke)
    print(f"[benchmarks] {results['total_seconds']:.0f} s; wrote {paths['json']} and "
          f"{paths['markdown']}", file=sys.stderr)
    return results


if __name__ == "__main__":
    main()
