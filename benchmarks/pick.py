"""``_channels.pick`` against ``np.where`` by the share of the mask that is set: the
crossover behind ``_channels.BITWISE_SHARES``. ``python -m benchmarks.pick`` prints a table
(median microseconds of one call on 65536 float64 elements, three masks per share)."""

from __future__ import annotations

import time

import numpy as np

from adobe_bsdf import _channels

N = 65536
SHARES = (0.0, 0.05, 0.1, 0.15, 0.2, 0.3, 0.5, 0.7, 0.8, 0.85, 0.9, 0.95, 1.0)


def _median_us(f, runs: int = 50) -> float:
    f()
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return float(np.median(times)) * 1e6


def _bitwise(mask, a, b):
    """The bitwise select alone, whatever the share (as ``pick`` computes it)."""
    k = mask.view(np.uint8).astype(np.int64)
    np.negative(k, out=k)
    out = np.bitwise_xor(a.view(np.int64), b.view(np.int64))
    out &= k
    out ^= b.view(np.int64)
    return out.view(np.float64)


def measure(n: int = N) -> list:
    """``[(share, np.where us, bitwise us, pick us)]``, each the largest of three masks."""
    rng = np.random.default_rng(0)
    a, b = rng.random((2, n))
    rows = []
    for share in SHARES:
        worst = np.zeros(3)
        for seed in range(3):
            mask = np.random.default_rng(seed).random(n) < share
            worst = np.maximum(worst, [_median_us(lambda m=mask, f=f: f(m, a, b))
                                       for f in (np.where, _bitwise, _channels.pick)])
        rows.append((share, *worst))
    return rows


def main() -> None:
    print(f"share set | np.where | bitwise | pick (us, {N} elements; bitwise between "
          f"{_channels.BITWISE_SHARES})")
    for share, where, bitwise, pick in measure():
        print(f"{share:9.2f} | {where:8.1f} | {bitwise:7.1f} | {pick:5.1f}")


if __name__ == "__main__":
    main()
