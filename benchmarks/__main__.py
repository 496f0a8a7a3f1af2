"""Throughput of ``eval``, ``pdf`` and ``sample`` for the registered lobes on 10^6 pairs.

Prints evaluations per second (median of 5 runs) and the cost in "memory passes": the time
of one ``np.add`` over three arrays of 10^6 float64 triples, measured in the same run.
"""

from __future__ import annotations

import time

import numpy as np

import adobe_bsdf  # noqa: F401  (registers the lobes)
from adobe_bsdf.registry import cases

N = 1_000_000
RUNS = 5


def _median_time(fn) -> float:
    times = []
    for _ in range(RUNS):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def main() -> None:
    rng = np.random.default_rng(0)
    w = rng.normal(size=(2, N, 3))
    wo, wi = w / np.linalg.norm(w, axis=-1, keepdims=True)
    wo[:, 2] = np.abs(wo[:, 2])
    u = rng.random((N, 3))
    a, b = rng.random((N, 3)), rng.random((N, 3))
    out = np.empty_like(a)
    add = _median_time(lambda: np.add(a, b, out=out))
    print(f"np.add over {N} x 3 float64: {add * 1e3:.2f} ms (one memory pass)")
    print(f"{'lobe':34s} {'call':7s} {'ms':>9s} {'Meval/s':>9s} {'passes':>8s}")
    for case in cases():
        lobe = case.make()
        for name, call in (("eval", lambda lobe=lobe: lobe.eval(wo, wi)),
                           ("pdf", lambda lobe=lobe: lobe.pdf(wo, wi)),
                           ("sample", lambda lobe=lobe: lobe.sample(wo, u))):
            t = _median_time(call)
            print(f"{case.name:34s} {name:7s} {t * 1e3:9.1f} {N / t / 1e6:9.2f} {t / add:8.0f}")


if __name__ == "__main__":
    main()
