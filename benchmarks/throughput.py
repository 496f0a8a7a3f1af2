"""Throughput of ``eval``, ``pdf``, ``eval_pdf`` and ``sample`` of every registered lobe case.

Inputs: ``wo``, ``wi`` uniform on the unit sphere with ``wo.z`` made positive (so the lobes see
both reflection and transmission), uniforms ``u`` in [0, 1); seed 0, the first n of one set.
Sizes 10^4, 10^6, 10^7 pairs (``--smoke``: 10^3, 10^4). A timing is the median of 5 runs
(smoke: 2) of ``time.perf_counter`` around the call; a run of a small call repeats it until it
lasts ~5 ms and divides. A batch over 10^6 pairs is passed in slices of at most 10^6 pairs
whose times are summed, which caps the memory of the 10^7 runs (inputs, outputs and
temporaries of one slice). One "memory pass" is the median time of ``np.add(a, b, out=c)``
over float64 arrays of shape (n, 3) with the same n, measured in the same process: the cost
of reading two arrays and writing one of the batch's size.

Threads (``adobe_bsdf.config.options(threads=...)``): all CPUs of the process, and 1 thread
up to 10^6 pairs. Phase 1 measures every case at 10^4 (both thread counts) and 10^6 (all
CPUs). Phase 2 adds 10^6 pairs on 1 thread and 10^7 pairs, cheapest first by predicted time
(5 runs x the 10^6 time, x the CPU count for 1 thread, x 10 for 10^7), while they fit in a
time budget (``extra_seconds``, default 300 s); the others are listed as skipped with their
prediction. This keeps a full run near 15 minutes on 2 cores: the slowest lobes would need
minutes per size.

The ``headline`` section times a GGX conductor with exact conductor Fresnel (anisotropic,
alpha (0.5, 0.1), gold) and a rough dielectric (eta 1.5, alpha 0.3) on 10^6 pairs. It runs
on older commits of the library too (no ``adobe_bsdf.config``: default threads only; no
``eval_pdf``: skipped), for before/after comparisons.
"""

from __future__ import annotations

import contextlib
import functools
import math
import time

import numpy as np

from benchmarks import machine

try:
    from adobe_bsdf import config
except ImportError:  # older commits: no execution options
    config = None

__all__ = ["SIZES", "SMOKE_SIZES", "RUNS", "SMOKE_RUNS", "SLICE", "CALLS", "EXTRA_SECONDS",
           "GOLD_ETA", "GOLD_K", "directions", "memory_pass", "repeats_for", "time_call",
           "thread_variants",
           "headline_lobes", "headline", "run"]

SIZES = (10**4, 10**6, 10**7)
SMOKE_SIZES = (10**3, 10**4)
RUNS, SMOKE_RUNS = 5, 2
#: largest batch passed to one call
SLICE = 10**6
CALLS = ("eval", "pdf", "eval_pdf", "sample")
#: a run shorter than this repeats the call and divides
MIN_RUN_SECONDS = 5e-3
#: default time budget of the optional measurements (phase 2)
EXTRA_SECONDS = 300.0
GOLD_ETA = (0.143, 0.374, 1.442)
GOLD_K = (3.983, 2.385, 1.603)


def directions(n: int, seed: int = 0):
    """``(wo, wi, u)``, each ``(n, 3)`` float64: unit ``wo`` (z >= 0), unit ``wi``, uniforms."""
    rng = np.random.default_rng(seed)
    wo = rng.standard_normal((n, 3))
    wo /= np.linalg.norm(wo, axis=-1, keepdims=True)
    np.abs(wo[:, 2], out=wo[:, 2])
    wi = rng.standard_normal((n, 3))
    wi /= np.linalg.norm(wi, axis=-1, keepdims=True)
    return wo, wi, rng.random((n, 3))


def repeats_for(first: float) -> int:
    """How many calls make one run of a call that took ``first`` seconds: 1, or enough to
    last ``MIN_RUN_SECONDS`` (at most 1000), whose mean is the run's time."""
    if first >= MIN_RUN_SECONDS:
        return 1
    return min(1000, math.ceil(MIN_RUN_SECONDS / max(first, 1e-9)))


def _median(run, runs: int) -> tuple[float, list]:
    """Median and all of ``runs`` timings; ``run()`` returns the seconds of one call. A first
    call shorter than ``MIN_RUN_SECONDS`` only calibrates the repeats; a longer one counts."""
    first = run()
    repeats = repeats_for(first)
    if repeats == 1:
        times = [first] + [run() for _ in range(runs - 1)]
    else:
        times = [sum(run() for _ in range(repeats)) / repeats for _ in range(runs)]
    return float(np.median(times)), times


@functools.cache
def memory_pass(n: int, runs: int) -> tuple[float, list]:
    """Median (and all) times of ``np.add(a, b, out=c)`` over float64 arrays (n, 3)."""
    rng = np.random.default_rng(1)
    a, b = rng.random((n, 3)), rng.random((n, 3))
    c = np.empty_like(a)

    def run():
        start = time.perf_counter()
        np.add(a, b, out=c)
        return time.perf_counter() - start

    return _median(run, runs)


def _call(lobe, call, wo, wi, u):
    if call == "sample":
        return lobe.sample(wo, u)
    return getattr(lobe, call)(wo, wi)


def time_call(lobe, call: str, wo, wi, u) -> float:
    """Seconds of one ``call`` over all pairs, in slices of at most ``SLICE`` (times summed)."""
    total = 0.0
    for start in range(0, len(wo), SLICE):
        s = slice(start, start + SLICE)
        t0 = time.perf_counter()
        result = _call(lobe, call, wo[s], wi[s], u[s])
        total += time.perf_counter() - t0
        del result
    return total


def thread_variants() -> list:
    """Thread counts to compare: all CPUs first, then 1 (``[None]`` without ``config``)."""
    if config is None:
        return [None]
    cpus = machine.cores()
    return [cpus, 1] if cpus > 1 else [1]


def _threads(threads):
    return contextlib.nullcontext() if threads is None else config.options(threads=threads)


def _measure(lobe, call, n, threads, wo, wi, u, runs) -> dict:
    """One row: median seconds, evaluations/s and memory passes (or the error)."""
    row = {"call": call, "n": n, "threads": threads, "sliced": n > SLICE}
    try:
        with _threads(threads):
            seconds, times = _median(lambda: time_call(lobe, call, wo[:n], wi[:n], u[:n]), runs)
    except Exception as exc:  # a failing lobe is reported, not fatal
        return {**row, "error": f"{type(exc).__name__}: {exc}"}
    add = memory_pass(n, runs)[0]
    return {**row, "seconds": seconds, "times": times, "evals_per_s": n / seconds,
            "memory_passes": seconds / add}


def _calls(lobe) -> list:
    return [c for c in CALLS if hasattr(lobe, c)]


def headline_lobes(masking: str | None = None) -> dict:
    """``{key: (label, lobe)}`` of the headline conductor and dielectric (``masking``: the
    lobes' masking form, default theirs: height-correlated Smith)."""
    from adobe_bsdf import fresnel, lobes

    extra = {} if masking is None else {"masking": masking}

    eta, k = np.array(GOLD_ETA), np.array(GOLD_K)
    if hasattr(fresnel, "ExactConductor"):
        F, how = fresnel.ExactConductor(eta, k), "fresnel.ExactConductor(eta, k)"
    else:
        F = functools.partial(fresnel.conductor, eta=eta, k=k)
        how = "functools.partial(fresnel.conductor, eta=eta, k=k)"
    return {
        "conductor": (f"GGX conductor, alpha (0.5, 0.1), gold, exact Fresnel [{how}]",
                      lobes.Conductor(0.5, 0.1, fresnel=F, **extra)),
        "dielectric": ("GGX rough dielectric, eta 1.5, alpha 0.3",
                       lobes.Dielectric(1.5, 0.3, **extra)),
    }


def headline(wo, wi, u, smoke: bool = False) -> dict:
    """Headline lobes: every call at the reference size (10^6; smoke 10^4), all threads and
    one, and "eval_above": ``eval`` with ``wi`` mirrored above the surface (where a sample's
    directions lie; ``eval`` on the uniform pairs skips the half outside the support)."""
    n = SMOKE_SIZES[-1] if smoke else SLICE
    runs = SMOKE_RUNS if smoke else RUNS
    rows = []
    labels = {}
    above = wi[:n].copy()  # "eval_above": every pair in a one-sided lobe's support
    above[:, 2] = np.abs(above[:, 2])
    for key, (label, lobe) in headline_lobes().items():
        labels[key] = label
        for call in _calls(lobe):
            _call(lobe, call, wo[:1000], wi[:1000], u[:1000])  # warm-up
            for threads in thread_variants():
                rows.append({"lobe": key, **_measure(lobe, call, n, threads, wo, wi, u, runs)})
        for threads in thread_variants():
            rows.append({"lobe": key, **_measure(lobe, "eval", n, threads, wo, above, u, runs),
                         "call": "eval_above"})
    return {"n": n, "runs": runs, "labels": labels, "threads": thread_variants(),
            "memory_pass_seconds": memory_pass(n, runs)[0],
            "has_config": config is not None, "rows": rows}


def run(wo, wi, u, smoke: bool = False, extra_seconds: float = EXTRA_SECONDS,
        log=None) -> dict:
    """Every registered case x call x size x threads, in two phases (see the module doc)."""
    sizes = SMOKE_SIZES if smoke else SIZES
    runs = SMOKE_RUNS if smoke else RUNS
    ref = sizes[-1] if smoke else SLICE
    if smoke:
        extra_seconds = math.inf
    variants = thread_variants()
    cpus = variants[0]
    rows, pending = [], []
    start = time.perf_counter()
    from adobe_bsdf.validation.cases import cases  # (this library only: not the baseline's)

    for case in cases():
        try:
            lobe = case.make()
        except Exception as exc:
            rows.append({"case": case.name, "error": f"{type(exc).__name__}: {exc}"})
            continue
        for call in _calls(lobe):  # warm-up (tables, caches); _measure reports errors
            with contextlib.suppress(Exception):
                _call(lobe, call, wo[:1000], wi[:1000], u[:1000])
        for n in (n for n in sizes if n <= ref):
            for call in _calls(lobe):
                for threads in variants:
                    if n == ref and threads != cpus:
                        continue  # phase 2
                    row = {"case": case.name,
                           **_measure(lobe, call, n, threads, wo, wi, u, runs)}
                    rows.append(row)
                    if n == ref and "seconds" in row:  # predictions of phase 2
                        pending += [(runs * row["seconds"] * (cpus or 1), case.name, lobe,
                                     call, n, t) for t in variants[1:]]
                        pending += [(runs * row["seconds"] * big / ref, case.name, lobe, call,
                                     big, cpus) for big in sizes if big > ref]
        if log:
            log(f"{case.name}: {time.perf_counter() - start:.0f} s")
    phase1 = time.perf_counter() - start
    spent = 0.0
    for predicted, name, lobe, call, n, threads in sorted(pending, key=lambda p: p[0]):
        if spent + predicted > extra_seconds:
            rows.append({"case": name, "call": call, "n": n, "threads": threads,
                         "skipped": f"predicted {predicted:.0f} s for {runs} runs; "
                                    f"{spent:.0f} of the {extra_seconds:g} s budget spent",
                         "predicted_seconds": predicted})
            continue
        t0 = time.perf_counter()
        rows.append({"case": name, **_measure(lobe, call, n, threads, wo, wi, u, runs)})
        spent += time.perf_counter() - t0
    if log:
        log(f"phase 2: {spent:.0f} s")
    return {"sizes": list(sizes), "runs": runs, "slice": SLICE, "reference_size": ref,
            "threads": variants, "extra_seconds": extra_seconds, "phase1_seconds": phase1,
            "phase2_seconds": spent,
            "memory_pass_seconds": {str(n): memory_pass(n, runs)[0] for n in sizes},
            "rows": rows}
