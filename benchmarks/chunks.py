"""Chunk size and threads: time of the GGX conductor's ``eval`` (exact Fresnel, anisotropic)
on one batch as ``adobe_bsdf.config.chunk_size`` varies, on 1 thread and on every CPU.

    python -m benchmarks.chunks
"""

from __future__ import annotations

import os
import time

import numpy as np

from adobe_bsdf import config, fresnel
from adobe_bsdf.lobes import Conductor

SIZES = (512, 1024, 2048, 4096, 8192, 16384, 65536)
GOLD = ((0.143, 0.374, 1.442), (3.983, 2.385, 1.603))


def _pairs(n: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    w = rng.normal(size=(2, n, 3))
    wo, wi = w / np.linalg.norm(w, axis=-1, keepdims=True)
    wo[:, 2] = np.abs(wo[:, 2])
    return wo, wi


def _median(fn, runs: int) -> float:
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def run(smoke: bool = False) -> dict:
    n, runs = (20_000, 2) if smoke else (1_000_000, 5)
    wo, wi = _pairs(n)
    lobe = Conductor(0.5, 0.1, fresnel=fresnel.ExactConductor(*GOLD))
    cpus = len(os.sched_getaffinity(0))
    rows = []
    for size in SIZES[:3] if smoke else SIZES:
        row = {"chunk_size": size}
        for threads in sorted({1, cpus}):
            with config.options(threads=threads, chunk_size=size):
                row[f"threads_{threads}_s"] = _median(lambda: lobe.eval(wo, wi), runs)
        rows.append(row)
    return {"n": n, "runs": runs, "cpus": cpus, "rows": rows}


def markdown(results: dict) -> str:
    cpus = results["cpus"]
    threads = sorted({1, cpus})
    head = " | ".join(f"{t} thread{'s' if t > 1 else ''}: ns / pair" for t in threads)
    lines = [f"GGX conductor `eval` (exact Fresnel, alpha 0.5 x 0.1) on {results['n']:,} pairs, "
             f"median of {results['runs']} runs, as `chunk_size` varies (default "
             f"{config.DEFAULT_CHUNK_SIZE}).", "",
             f"| chunk_size | {head} |", "|---|" + "---|" * len(threads)]
    for row in results["rows"]:
        cells = " | ".join(f"{row[f'threads_{t}_s'] / results['n'] * 1e9:.1f}" for t in threads)
        lines.append(f"| {row['chunk_size']} | {cells} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    print(markdown(run()))
