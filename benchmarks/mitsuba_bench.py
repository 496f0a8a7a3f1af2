"""Mitsuba 3 reference timings of the headline lobes (``llvm_ad_rgb`` variant).

The same GGX conductor (``roughconductor``, ggx, alpha_u 0.5, alpha_v 0.1, gold eta and k,
visible-normal sampling) and rough dielectric (``roughdielectric``, int_ior 1.5, ext_ior 1,
alpha 0.3) as the headline NumPy lobes, ``eval``, ``pdf`` and ``sample`` on the same pairs
(converted to float32). Mitsuba computes in float32 on all cores (Dr.Jit's LLVM backend
vectorises and runs the JIT-compiled kernels on its own thread pool).

A timing is ``bsdf.eval(mi.BSDFContext(), si, wi)`` (resp. ``pdf``, ``sample``) followed by
``dr.eval(result); dr.sync_thread()``: tracing, kernel launch and the computation. The first
call (JIT compilation + run) is reported separately from the median of 10 later calls
(smoke: 2). Then the worker serves single calls on request, and ``_interleaved`` times NumPy
and Mitsuba in alternation (the ratios compared with the targets).
Dr.Jit caches compiled kernels on disk (``~/.drjit``), and a first call whose kernel is in that
cache skips the LLVM compilation; the worker therefore runs with ``HOME`` pointing at a fresh
temporary folder, so that its cache starts empty and the first call includes the compilation
(the number of kernels it wrote is reported). Later calls reuse the kernels in memory.

The measurement runs in a subprocess (``python -m benchmarks.mitsuba_bench --worker``): the
LLVM backend needs a shared libLLVM >= 16 found through ``DRJIT_LIBLLVM_PATH`` (LLVM 14/15
abort its JIT with ``LLVM ERROR: Cannot select ... fmaximum``), and a crash there must not end
the benchmark. Without Mitsuba or a suitable libLLVM the section is ``{"available": false,
"reason": ...}``.
"""

from __future__ import annotations

import argparse
import glob
import importlib.util
import json
import os
import re
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

__all__ = ["find_libllvm", "run", "INSTALL_HINT"]

ROOT = Path(__file__).resolve().parents[1]
VARIANT = "llvm_ad_rgb"
LIBLLVM_DIRS = ("/usr/lib/x86_64-linux-gnu", "/usr/lib/llvm-*/lib", "/usr/lib64",
                "/usr/local/lib")
_LIBLLVM = re.compile(r"libLLVM-(1[6-9]|2[0-9])(\.[0-9]+)*\.so(\.[0-9]+)*$")
INSTALL_HINT = ("install a shared libLLVM >= 16 (Debian/Ubuntu: `apt-get install libllvm19`) "
                "and set DRJIT_LIBLLVM_PATH to it, e.g. "
                "DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so")
TIMEOUT = 900
#: timed calls after the first (cheap: Mitsuba takes milliseconds per call)
RUNS = 10
#: pairs on which Mitsuba's eval is compared with the NumPy lobes
CHECK = 1000


def find_libllvm() -> tuple[str | None, str]:
    """``(path, how)`` of a shared libLLVM >= 16, or ``(None, why not)``."""
    env = os.environ.get("DRJIT_LIBLLVM_PATH")
    if env:
        if os.path.exists(env):
            return env, "DRJIT_LIBLLVM_PATH"
        return None, f"DRJIT_LIBLLVM_PATH={env} does not exist"
    found = []
    for pattern in LIBLLVM_DIRS:
        for folder in glob.glob(pattern):
            for path in glob.glob(os.path.join(folder, "libLLVM*.so*")):
                m = _LIBLLVM.search(os.path.basename(path))
                if m:
                    found.append((int(m.group(1)), path))
    if not found:
        return None, f"no libLLVM-16..29 shared library in {', '.join(LIBLLVM_DIRS)}"
    return max(found)[1], "searched " + ", ".join(LIBLLVM_DIRS)


def _installed(name: str) -> bool:
    try:
        return importlib.util.find_spec(name) is not None
    except (ImportError, ValueError, AttributeError):  # e.g. sys.modules[name] = None
        return False


def _cache_files(folder: Path) -> int:
    return sum(1 for p in folder.iterdir() if p.is_file()) if folder.is_dir() else 0


def run(wo, wi, u, smoke: bool = False) -> dict:
    """Time the Mitsuba lobes on ``(wo, wi, u)`` in a worker subprocess; never raises."""
    runs = 2 if smoke else RUNS
    result = {"variant": VARIANT, "n": len(wo), "runs": runs, "precision": "float32",
              "threads": "all cores (Dr.Jit thread pool)"}
    if not (_installed("mitsuba") and _installed("drjit")):
        return {**result, "available": False,
                "reason": "mitsuba is not installed (pip install 'adobe_bsdf[bench]' or "
                          f"pip install mitsuba); its LLVM backend also needs: {INSTALL_HINT}"}
    lib, how = find_libllvm()
    if lib is None:
        return {**result, "available": False,
                "reason": f"Mitsuba's {VARIANT} variant needs a shared libLLVM >= 16 "
                          f"({how}); {INSTALL_HINT}"}
    result.update(libllvm=lib, libllvm_found_by=how)
    with tempfile.TemporaryDirectory(prefix="adobe_bsdf_mitsuba_") as tmp:
        data, out = Path(tmp) / "pairs.npy", Path(tmp) / "result.json"
        np.save(data, np.stack([wo, wi, u]).astype(np.float32))
        # HOME=tmp: an empty Dr.Jit kernel cache (tmp/.drjit), so first calls compile
        env = {**os.environ, "DRJIT_LIBLLVM_PATH": lib, "HOME": tmp}
        start = time.perf_counter()
        err = Path(tmp) / "stderr.txt"
        with open(err, "w+") as stderr:
            proc = subprocess.Popen(
                [sys.executable, "-m", "benchmarks.mitsuba_bench", "--worker", str(data),
                 str(out), "--runs", str(runs), "--serve"],
                cwd=ROOT, env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                stderr=stderr, text=True)
            watchdog = threading.Timer(TIMEOUT, proc.kill)  # a hung worker is ended
            watchdog.start()
            try:
                if proc.stdout.readline().strip() == "ready":
                    result["interleaved"] = _interleaved(proc, wo, wi, u, smoke)
                    proc.stdin.write("quit\n")
                proc.communicate()
            except (OSError, ValueError) as exc:  # the worker died while serving
                proc.kill()
                proc.communicate()
                return {**result, "available": False,
                        "reason": f"the Mitsuba worker stopped while serving: {exc}"}
            finally:
                watchdog.cancel()
            stderr.seek(0)
            stderr_text = stderr.read()
        result["worker_seconds"] = time.perf_counter() - start
        result["kernel_cache"] = {"state": "empty at start (HOME = a fresh temporary folder)",
                                  "kernels_written": _cache_files(Path(tmp) / ".drjit")}
        if proc.returncode != 0 or not out.exists():
            lines = stderr_text.strip().splitlines()
            llvm = [line.strip() for line in lines if "LLVM ERROR" in line][:1]
            detail = " / ".join(llvm or [line.strip() for line in lines[-3:]])
            hint = (f" (this libLLVM does not work with Dr.Jit's JIT, which needs LLVM >= 16; "
                    f"{INSTALL_HINT})") if llvm else ""
            return {**result, "available": False, "stderr": "\n".join(lines[-40:]),
                    "reason": f"the Mitsuba worker failed with exit code {proc.returncode} "
                              f"using {lib}{hint}: {detail}"}
        worker = json.loads(out.read_text())
        values = dict(np.load(Path(tmp) / "check.npz"))
    result.update(worker, available=True)
    result["agreement"] = _agreement(wo, wi, values)
    return result


#: rounds of the interleaved NumPy / Mitsuba timing
ROUNDS = 9
#: seconds of rest before each timed call, so that neither side's worker threads are still
#: busy (Dr.Jit's pool spins for a while after a kernel) when the other side starts
PAUSE = 0.05


def _interleaved(proc, wo, wi, u, smoke: bool) -> dict:
    """NumPy and Mitsuba timed in alternation: in each round every (lobe, call) runs twice in
    NumPy (this process, all threads; the first call untimed, so that the second finds its
    memory as a loop of calls would) and then once in the serving Mitsuba worker. A slow
    phase of a shared machine then slows both alike, and the ratio of the medians compares
    like with like."""
    from benchmarks.throughput import _call, headline_lobes

    lobes = {key: lobe for key, (_, lobe) in headline_lobes().items()}
    rounds = 2 if smoke else ROUNDS
    times = {(key, call): ([], []) for key in lobes for call in ("eval", "pdf", "sample")}
    for lobe in lobes.values():  # warm-up
        for call in ("eval", "pdf", "sample"):
            _call(lobe, call, wo[:1000], wi[:1000], u[:1000])
    for _ in range(rounds):
        for (key, call), (ours, theirs) in times.items():
            time.sleep(PAUSE)
            _call(lobes[key], call, wo, wi, u)  # untimed: memory as in a loop of calls
            start = time.perf_counter()
            result = _call(lobes[key], call, wo, wi, u)
            ours.append(time.perf_counter() - start)
            del result
            proc.stdin.write(f"{key} {call}\n")
            proc.stdin.flush()
            theirs.append(float(proc.stdout.readline()))
            time.sleep(PAUSE)
    rows = []
    for (key, call), (ours, theirs) in times.items():
        a, b = float(np.median(ours)), float(np.median(theirs))
        rows.append({"lobe": key, "call": call, "numpy_seconds": a, "mitsuba_seconds": b,
                     "ratio": a / b, "numpy_times": ours, "mitsuba_times": theirs})
    return {"rounds": rounds, "rows": rows}


def _agreement(wo, wi, values: dict) -> dict:
    """Max relative difference of Mitsuba's eval (cosine included) and the NumPy lobes with
    Mitsuba's separable masking, on the first ``CHECK`` pairs where the value is > 1e-3."""
    try:
        from benchmarks.throughput import headline_lobes

        lobes = headline_lobes(masking="separable")
    except Exception as exc:  # older commits: no masking option
        return {"error": f"{type(exc).__name__}: {exc}"}
    out = {}
    for key, mitsuba in values.items():
        n = len(mitsuba)
        ours = lobes[key][1].eval(wo[:n], wi[:n]) * np.abs(wi[:n, 2:3])
        big = np.abs(ours) > 1e-3
        out[key] = {"pairs": n, "max_relative_difference":
                    float(np.max(np.abs(mitsuba - ours)[big] / np.abs(ours)[big]))}
    return out


# --- worker (runs in the subprocess) ---------------------------------------------------------
GOLD_ETA = (0.143, 0.374, 1.442)
GOLD_K = (3.983, 2.385, 1.603)


def _bsdfs(mi) -> dict:
    return {
        "conductor": mi.load_dict({
            "type": "roughconductor", "distribution": "ggx", "alpha_u": 0.5, "alpha_v": 0.1,
            "eta": {"type": "rgb", "value": list(GOLD_ETA)},
            "k": {"type": "rgb", "value": list(GOLD_K)}, "sample_visible": True}),
        "dielectric": mi.load_dict({
            "type": "roughdielectric", "distribution": "ggx", "alpha": 0.3, "int_ior": 1.5,
            "ext_ior": 1.0, "sample_visible": True}),
    }


def _worker(data: str, out: str, runs: int, serve: bool = False) -> None:
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(VARIANT)
    wo, wi, u = np.load(data)
    n = len(wo)
    si = dr.zeros(mi.SurfaceInteraction3f)
    si.wi = mi.Vector3f(np.ascontiguousarray(wo.T))
    wi_ = mi.Vector3f(np.ascontiguousarray(wi.T))
    u1 = mi.Float(np.ascontiguousarray(u[:, 0]))
    u2 = mi.Point2f(np.ascontiguousarray(u[:, 1:].T))
    dr.eval(si.wi, wi_, u1, u2)
    dr.sync_thread()
    ctx = mi.BSDFContext()
    rows, check, calls_of = [], {}, {}
    for key, bsdf in _bsdfs(mi).items():
        calls = calls_of[key] = {"eval": lambda b=bsdf: b.eval(ctx, si, wi_),
                                 "pdf": lambda b=bsdf: b.pdf(ctx, si, wi_),
                                 "sample": lambda b=bsdf: b.sample(ctx, si, u1, u2)}
        for call, fn in calls.items():
            times = []
            for _ in range(runs + 1):
                start = time.perf_counter()
                result = fn()
                dr.eval(result)
                dr.sync_thread()
                times.append(time.perf_counter() - start)
                del result
            later = times[1:]
            median = float(np.median(later))
            rows.append({"lobe": key, "call": call, "first_seconds": times[0],
                         "median_seconds": median, "times": later, "evals_per_s": n / median})
        check[key] = np.array(bsdf.eval(ctx, si, wi_)).T[:CHECK].astype(np.float64)
    np.savez(Path(out).parent / "check.npz", **check)
    Path(out).write_text(json.dumps({
        "rows": rows, "dr_threads": dr.thread_count(), "mitsuba": mi.__version__,
        "drjit": dr.__version__}))
    if serve:  # one timed call per request "<lobe> <call>" on stdin, until "quit"
        print("ready", flush=True)
        for line in sys.stdin:
            if line.strip() == "quit":
                break
            key, call = line.split()
            start = time.perf_counter()
            result = calls_of[key][call]()
            dr.eval(result)
            dr.sync_thread()
            print(time.perf_counter() - start, flush=True)
            del result


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worker", nargs=2, metavar=("PAIRS_NPY", "OUT_JSON"))
    parser.add_argument("--runs", type=int, default=RUNS)
    parser.add_argument("--serve", action="store_true",
                        help="with --worker: then time one call per stdin line '<lobe> <call>'")
    parser.add_argument("--n", type=int, default=10**6, help="pairs (without --worker)")
    args = parser.parse_args(argv)
    if args.worker:
        _worker(*args.worker, args.runs, args.serve)
        return
    from benchmarks.throughput import directions

    print(json.dumps(run(*directions(args.n)), indent=2))


if __name__ == "__main__":
    main()
