"""Facts about the machine and software a benchmark ran on: CPU model, usable cores, memory,
1-minute load average, versions of Python, NumPy, SciPy, adobe_bsdf and Mitsuba, the date
(UTC) and the git commit.

Everything is read without side effects; a fact that cannot be found is ``None``.
"""

from __future__ import annotations

import datetime
import importlib.metadata
import os
import platform
import subprocess
from pathlib import Path

__all__ = ["facts", "cpu_model", "cores"]

ROOT = Path(__file__).resolve().parents[1]


def cpu_model() -> str | None:
    """The CPU's model name from /proc/cpuinfo, else from ``lscpu``, else ``platform``."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.lower().startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, timeout=10).stdout
        for line in out.splitlines():
            if line.lower().startswith("model name"):
                return line.split(":", 1)[1].strip()
    except (OSError, subprocess.SubprocessError):
        pass
    return platform.processor() or None


def cores() -> int:
    """CPUs this process may run on (``os.sched_getaffinity``), else ``os.cpu_count()``."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        return os.cpu_count() or 1


def _version(distribution: str) -> str | None:
    try:
        return importlib.metadata.version(distribution)
    except importlib.metadata.PackageNotFoundError:
        return None


def _git(*args: str) -> str | None:
    try:
        out = subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True,
                             timeout=10)
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout.strip() if out.returncode == 0 else None


def facts() -> dict:
    """Machine facts as a JSON-ready dict."""
    import numpy

    try:
        import adobe_bsdf
        adobe_version = getattr(adobe_bsdf, "__version__", None)
    except ImportError:  # pragma: no cover - the benchmarks need the package anyway
        adobe_version = None
    status = _git("status", "--porcelain", "--untracked-files=no")
    memory = None
    try:
        memory = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):  # pragma: no cover
        pass
    return {
        "date_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "cpu_model": cpu_model(),
        "cores": cores(),
        "memory_bytes": memory,
        "platform": platform.platform(),
        "python": platform.python_version(),
        "numpy": numpy.__version__,
        "scipy": _version("scipy"),
        "adobe_bsdf": adobe_version,
        "mitsuba": _version("mitsuba"),
        "drjit": _version("drjit"),
        "matplotlib": _version("matplotlib"),
        "load_average_1min": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
        "git_commit": _git("rev-parse", "HEAD"),
        "git_dirty": None if status is None else bool(status),
    }


if __name__ == "__main__":
    import json

    print(json.dumps(facts(), indent=2))
