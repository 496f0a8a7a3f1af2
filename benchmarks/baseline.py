"""Before and after: the headline lobes timed on an earlier commit of the library, in the
same run as the current code, so that the speed-ups are measured on one machine at one time.

``run(revision)`` extracts ``adobe_bsdf/`` of that git revision (``git archive``) into a
temporary folder beside a copy of the current ``benchmarks/`` package, and times
``benchmarks.throughput.headline`` there in a subprocess (the current timing code on the old
library; ``headline`` runs on commits without ``adobe_bsdf.config`` with their default
threading). ``BASELINE`` is the last commit before the performance work: the library as the
energy-tables work left it.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

__all__ = ["BASELINE", "run", "run_script"]

#: the library before the performance work (table lookups moved into lobes/energy_lookup.py)
BASELINE = "420f74c"

ROOT = Path(__file__).resolve().parents[1]

_SCRIPT = """
import json, sys
from benchmarks import throughput as tp
wo, wi, u = tp.directions(tp.SMOKE_SIZES[-1] if {smoke} else tp.SLICE)
result = tp.headline(wo, wi, u, {smoke})
json.dump(result, open(sys.argv[1], "w"))
"""


def _git(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, timeout=120,
                          check=True)


def run_script(script: str, revision: str, paths=("adobe_bsdf",)) -> dict:
    """The JSON that ``script`` (Python run with ``sys.argv[1]`` its output path) writes when
    run on the folders ``paths`` of ``revision`` beside the current ``benchmarks/``, in a
    subprocess; raises if git, the revision or the script fails."""
    commit = _git("rev-parse", "--verify", f"{revision}^{{commit}}").stdout.decode().strip()
    with tempfile.TemporaryDirectory(prefix="adobe_bsdf_baseline_") as tmp:
        archive = _git("archive", "--format=tar", commit, *paths).stdout
        subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
        shutil.copytree(ROOT / "benchmarks", Path(tmp) / "benchmarks",
                        ignore=shutil.ignore_patterns("__pycache__", "results.json"))
        out = Path(tmp) / "result.json"
        env = {**os.environ, "PYTHONPATH": tmp}
        proc = subprocess.run([sys.executable, "-c", script, str(out)],
                              cwd=tmp, env=env, capture_output=True, text=True, timeout=3600)
        if proc.returncode != 0:
            raise RuntimeError(f"the script failed on {revision}:\n{proc.stderr[-4000:]}")
        return json.loads(out.read_text())


def run(smoke: bool = False, revision: str = BASELINE) -> dict:
    """``{"revision", "commit", "subject", "headline"}``: ``throughput.headline`` of the
    library at ``revision``; raises if git or the revision is not available."""
    commit = _git("rev-parse", "--verify", f"{revision}^{{commit}}").stdout.decode().strip()
    subject = _git("log", "-1", "--format=%s", commit).stdout.decode().strip()
    headline = run_script(_SCRIPT.format(smoke=smoke), commit)
    return {"revision": revision, "commit": commit, "subject": subject, "headline": headline}
