"""Chunk size and threads: ``eval`` of the headline lobes on one batch of 10^6 pairs as
``adobe_bsdf.config.chunk_size`` varies, on 1 thread and on every CPU, and the parallel limit
of the machine for the same work.

Rounds: every (chunk size, threads, lobe) is timed twice per round, over 5 rounds (smoke: 1
round, 10^4 pairs), so that slow phases of a shared machine spread over all configurations;
the median is reported.

*Two processes*: the same call on half of the batch in each of two processes started
together (1 thread each, default chunk size), timed inside each; the slower median is the
time the batch would take with no interpreter lock between the two halves. It separates what
the hardware gives (two cores sharing caches and memory) from what the thread hand-overs of
one process cost.

    python -m benchmarks.chunks
"""

from __future__ import annotations

import collections
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from adobe_bsdf import config
from benchmarks import machine
from benchmarks import throughput as tp

__all__ = ["SIZES", "run", "markdown"]

SIZES = (4096, 16384, 32768, 65536, 131072, 262144)
SMOKE_SIZES = (4096, 65536)
ROOT = Path(__file__).resolve().parents[1]

_HALF = """
import json, sys, time
import numpy as np
from adobe_bsdf import config
from benchmarks import throughput as tp
n, key, rounds, delay = int(sys.argv[1]), sys.argv[2], int(sys.argv[3]), float(sys.argv[4])
wo, wi, _ = tp.directions(2 * n)
wo, wi = wo[int(sys.argv[5]) * n:][:n].copy(), wi[int(sys.argv[5]) * n:][:n].copy()
lobe = tp.headline_lobes()[key][1]
config.set_options(threads=1)
lobe.eval(wo, wi)
time.sleep(max(0.0, delay - time.time()))
times = []
for _ in range(rounds):
    t = time.perf_counter()
    lobe.eval(wo, wi)
    times.append(time.perf_counter() - t)
print(json.dumps(times))
"""


def _two_processes(n: int, key: str, rounds: int) -> float:
    """Slower of the median times of two processes evaluating one half each, together."""
    start = time.time() + 3.0  # both have imported and warmed up by then
    procs = [subprocess.Popen([sys.executable, "-c", _HALF, str(n // 2), key, str(rounds),
                               str(start), str(j)], cwd=ROOT, stdout=subprocess.PIPE,
                              text=True) for j in range(2)]
    medians = []
    for p in procs:
        out, _ = p.communicate(timeout=600)
        if p.returncode != 0:
            raise RuntimeError(f"two-process run failed ({p.returncode})")
        medians.append(float(np.median(json.loads(out))))
    return max(medians)


def run(smoke: bool = False) -> dict:
    n = tp.SMOKE_SIZES[-1] if smoke else tp.SLICE
    rounds = 1 if smoke else 5
    sizes = SMOKE_SIZES if smoke else SIZES
    wo, wi, _ = tp.directions(n)
    lobes = {key: lobe for key, (_, lobe) in tp.headline_lobes().items()}
    cpus = machine.cores()
    threads = sorted({1, cpus})
    times = collections.defaultdict(list)
    for _ in range(rounds):
        for size in sizes:
            for t in threads:
                with config.options(threads=t, chunk_size=size):
                    for key, lobe in lobes.items():
                        lobe.eval(wo[:1000], wi[:1000])
                        for _ in range(2):
                            start = time.perf_counter()
                            lobe.eval(wo, wi)
                            times[(size, t, key)].append(time.perf_counter() - start)
    rows = [{"chunk_size": size, "threads": t, "lobe": key,
             "seconds": float(np.median(times[(size, t, key)]))}
            for size in sizes for t in threads for key in lobes]
    two = {key: _two_processes(n, key, 3 if smoke else 15) for key in lobes} if cpus > 1 \
        else {}
    return {"n": n, "rounds": rounds, "cpus": cpus, "threads": threads, "sizes": list(sizes),
            "default": config.DEFAULT_CHUNK_SIZE, "rows": rows, "two_processes": two}


def markdown(results: dict) -> list:
    """Lines of the chunk-size table (time per pair in ns)."""
    n, threads = results["n"], results["threads"]
    lobes = list(dict.fromkeys(r["lobe"] for r in results["rows"]))
    rows = {(r["chunk_size"], r["threads"], r["lobe"]): r["seconds"] for r in results["rows"]}
    head = [f"{key}, {t} thread{'s' if t > 1 else ''}" for key in lobes for t in threads]
    out = [f"`eval` of the headline lobes on {n:,} pairs: nanoseconds per pair, median over "
           f"{results['rounds']} rounds of 2 calls, as `chunk_size` varies (default "
           f"{results['default']}).", "",
           "| chunk_size | " + " | ".join(head) + " |", "|---|" + "---|" * len(head)]
    for size in results["sizes"]:
        out.append(f"| {size} | " + " | ".join(
            f"{rows[(size, t, key)] / n * 1e9:.1f}" for key in lobes for t in threads) + " |")
    two = results.get("two_processes") or {}
    if two:
        out += ["", "*Two processes* (no interpreter lock between the halves; see "
                "`benchmarks/chunks.py`): " + "; ".join(
                    f"{key} {two[key] / n * 1e9:.1f} ns per pair" for key in lobes
                    if key in two) + ". Against the best single-thread time this is the "
                "speed-up two cores of this machine give to NumPy code at all; the "
                "threaded rows above show how much of it the thread pool keeps."]
    return out + [""]


if __name__ == "__main__":
    print("\n".join(markdown(run())))
