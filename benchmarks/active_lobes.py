"""Cost of a ``Sum`` of K lobes against the number k of lobes with a non-zero weight.

``Sum(*components, weights=w)`` over K = 4 reflection lobes (Lambert, GGX conductor alpha 0.1
with F = 1, anisotropic GGX gold conductor with exact Fresnel, Kulla–Conty
``ConductorMultipleScattering`` alpha 0.5), where the first k weights are 1/k and the other
K - k are exactly 0.0, for k = 0..K: the median of 5 runs (smoke: 2) of ``eval`` and ``sample``
on 10^6 pairs (smoke: 10^4), all threads, the same pairs as the throughput section. A
component whose weight is 0 everywhere is dropped when the ``Sum`` is built, so the cost
should follow the active lobes only; the column "plain Sum" times ``Sum(*active)`` built
without the zero-weight components, for comparison.

Without the ``weights`` keyword (older code) every row is the plain ``Sum(*active)`` (no row
for k = 0) and the section says so.
"""

from __future__ import annotations

import functools

import numpy as np

from benchmarks import throughput as tp

__all__ = ["components", "run"]

CALLS = ("eval", "sample")


def components() -> list:
    """``[(label, lobe)]`` of the K components, cheapest first."""
    from adobe_bsdf import fresnel, lobes

    eta, k = np.array(tp.GOLD_ETA), np.array(tp.GOLD_K)
    if hasattr(fresnel, "ExactConductor"):
        F = fresnel.ExactConductor(eta, k)
    else:
        F = functools.partial(fresnel.conductor, eta=eta, k=k)
    return [("Lambert 0.5", lobes.Lambert(0.5)),
            ("Conductor a=0.1 F=1", lobes.Conductor(0.1)),
            ("Conductor a=(0.5,0.1) gold", lobes.Conductor(0.5, 0.1, fresnel=F)),
            ("ConductorMS a=0.5", lobes.ConductorMultipleScattering(0.5))]


def _weighted_sum(parts, weights):
    """``Sum(*parts, weights=weights)``, or ``None`` if ``Sum`` has no ``weights`` keyword."""
    from adobe_bsdf.composition import Sum

    try:
        return Sum(*parts, weights=weights)
    except TypeError as exc:
        if "weights" in str(exc):
            return None
        raise


def _time(lobe, call, n, wo, wi, u, runs) -> dict:
    tp._call(lobe, call, wo[:1000], wi[:1000], u[:1000])  # warm-up
    seconds, times = tp._median(lambda: tp.time_call(lobe, call, wo[:n], wi[:n], u[:n]), runs)
    return {"seconds": seconds, "times": times, "evals_per_s": n / seconds}


def run(wo, wi, u, smoke: bool = False) -> dict:
    from adobe_bsdf.composition import Sum

    n = tp.SMOKE_SIZES[-1] if smoke else tp.SLICE
    runs = tp.SMOKE_RUNS if smoke else tp.RUNS
    parts = components()
    K = len(parts)
    lobes = [lobe for _, lobe in parts]
    api = "weights" if _weighted_sum(lobes, [1.0] * K) is not None else "fallback"
    rows = []
    for k in range(K + 1):
        weights = [1.0 / max(k, 1)] * k + [0.0] * (K - k)
        row = {"k": k, "active": [label for label, _ in parts[:k]], "weights": weights}
        try:
            if api == "weights":
                lobe = _weighted_sum(lobes, weights)
                for call in CALLS:
                    row[call] = _time(lobe, call, n, wo, wi, u, runs)
                if k:
                    row["plain_eval"] = _time(Sum(*lobes[:k]), "eval", n, wo, wi, u, runs)
            elif k:
                for call in CALLS:
                    row[call] = _time(Sum(*lobes[:k]), call, n, wo, wi, u, runs)
            else:
                row["skipped"] = "Sum() of no lobe: needs the weights keyword"
        except Exception as exc:  # reported, not fatal
            row["error"] = f"{type(exc).__name__}: {exc}"
        rows.append(row)
    return {"n": n, "runs": runs, "K": K, "components": [label for label, _ in parts],
            "api": api, "memory_pass_seconds": tp.memory_pass(n, runs)[0], "rows": rows}
