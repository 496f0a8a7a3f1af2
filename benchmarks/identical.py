"""Bit-identity of the library against an earlier commit: a change that moves code without
changing what it computes must give the same float64 values, bit for bit.

``python -m benchmarks.identical [REVISION]`` extracts ``adobe_bsdf/`` and ``tables/`` of
``REVISION`` (default: ``HEAD``) with ``git archive`` into a temporary folder (as
``benchmarks.baseline`` does), evaluates every registered check case there and in the working
tree, each in its own subprocess, on the same 10^4 fixed random pairs, and compares:
``eval``, ``pdf``, ``eval_pdf``, ``sample`` (white and coloured throughput) and the table
``albedo`` where the case has one. Equality is exact (NaN equal to NaN). Prints one line per
case that differs and a summary; exits 1 if any value differs or a case is missing.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

__all__ = ["dump", "compare", "main"]

ROOT = Path(__file__).resolve().parents[1]
#: pairs per case
N_PAIRS = 10_000


def _cases():
    """The registered check cases of whichever library is on the path (the registry moved
    from ``adobe_bsdf.registry`` to ``adobe_bsdf.validation.cases``)."""
    try:
        from adobe_bsdf.validation.cases import cases
    except ImportError:
        from adobe_bsdf.registry import cases

        import adobe_bsdf  # noqa: F401  (its lobe modules register their cases)
    return cases()


def _inputs(n: int):
    rng = np.random.default_rng(20261201)
    w = rng.normal(size=(2, n, 3))
    w /= np.linalg.norm(w, axis=-1, keepdims=True)
    u = rng.random((n, 3))
    throughput = rng.random((n, 3)) * 2.0
    return w[0], w[1], u, throughput


def dump(path: str, n: int = N_PAIRS) -> int:
    """Write every case's values to ``path`` (``.npz``); returns the number of cases."""
    wo, wi, u, throughput = _inputs(n)
    out = {}
    selected = _cases()
    for index, case in enumerate(selected):
        lobe = case.make()
        key = f"{case.name}|"
        out[key + "eval"] = lobe.eval(wo, wi)
        out[key + "pdf"] = lobe.pdf(wo, wi)
        f, p = lobe.eval_pdf(wo, wi, throughput)
        out[key + "eval_pdf.f"], out[key + "eval_pdf.pdf"] = f, p
        for label, t in (("sample", None), ("sample_t", throughput)):
            s = lobe.sample(wo, u, t)
            for field in s._fields:
                out[f"{key}{label}.{field}"] = np.asarray(getattr(s, field))
        try:
            out[key + "albedo_table"] = lobe.albedo(wo, method="table")
        except ValueError:  # no table for this case
            out[key + "albedo_table"] = np.array("none")
        print(f"[{index + 1}/{len(selected)}] {case.name}", file=sys.stderr, flush=True)
    np.savez(path, **out)
    return len(selected)


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    if a.dtype.kind in "US" or b.dtype.kind in "US":
        return a.dtype.kind == b.dtype.kind and bool(np.all(a == b))
    return a.shape == b.shape and bool(np.array_equal(a, b, equal_nan=True))


def compare(before: str, after: str) -> tuple[int, int, list[str]]:
    """``(cases, values compared, differences)`` of two dumps."""
    a, b = np.load(before), np.load(after)
    problems = [f"missing after: {k}" for k in sorted(set(a.files) - set(b.files))]
    problems += [f"new after: {k}" for k in sorted(set(b.files) - set(a.files))]
    values = 0
    for key in sorted(set(a.files) & set(b.files)):
        x, y = a[key], b[key]
        values += x.size
        if not _same(x, y):
            diff = "" if x.dtype.kind in "US" or x.shape != y.shape else \
                f", max |diff| {np.nanmax(np.abs(x.astype(float) - y.astype(float))):.3g}"
            problems.append(f"differs: {key} ({np.sum(x != y) if x.shape == y.shape else 'shape'}"
                            f" of {x.size}{diff})")
    cases = len({k.split("|")[0] for k in a.files})
    return cases, values, problems


def _run_dump(pythonpath: str, cwd: str, out: str) -> None:
    env = {**os.environ, "PYTHONPATH": pythonpath}
    script = (f"import sys; sys.path.insert(0, {str(ROOT)!r}); "
              f"from benchmarks.identical import dump; dump({out!r})")
    proc = subprocess.run([sys.executable, "-c", script], cwd=cwd, env=env, text=True,
                          capture_output=True, timeout=3600)
    if proc.returncode != 0:
        raise RuntimeError(f"dump in {pythonpath} failed:\n{proc.stderr[-4000:]}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.identical",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("revision", nargs="?", default="HEAD",
                        help="git revision to compare the working tree with (default HEAD)")
    parser.add_argument("--before", metavar="NPZ",
                        help="use this dump of the earlier library instead of extracting it")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="adobe_bsdf_identical_") as tmp:
        before = args.before
        if before is None:
            archive = subprocess.run(["git", "archive", "--format=tar", args.revision,
                                      "adobe_bsdf", "tables"], cwd=ROOT, check=True,
                                     capture_output=True).stdout
            subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
            before = str(Path(tmp) / "before.npz")
            _run_dump(tmp, tmp, before)
        after = str(Path(tmp) / "after.npz")
        _run_dump(str(ROOT), str(ROOT), after)
        cases, values, problems = compare(before, after)
    for line in problems:
        print(line)
    print(f"{cases} cases, {values} values compared with {args.revision}: "
          f"{len(problems)} differences")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
