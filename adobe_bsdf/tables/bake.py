"""Baking tables: nodes computed in a process pool, deterministically, with a progress bar.

Public API
----------
``compute(spec, coords, workers=2, progress=True)``  node values and errors at ``coords``.
``bake(spec, workers=2, progress=True)``             the whole table, with its metadata.
``check(spec, table, n_nodes, seed, workers)``       re-bake random nodes at a higher
                                                     quadrature order and compare.
``run(names, ..., out=None, in_place=False)``        the ``bake`` command: into ``out``
                                                     (default ``user_folder()``), or over
                                                     the shipped tables with ``in_place``.

Nodes are cut into fixed blocks of ``BLOCK`` whatever the number of workers, so a table is
bit-for-bit the same on any machine with the same NumPy/SciPy.
"""

from __future__ import annotations

import dataclasses
import os
import platform
import time
from concurrent.futures import ProcessPoolExecutor
from datetime import datetime, timezone
from pathlib import Path
from typing import NamedTuple

import numpy as np
import scipy
from tqdm import tqdm

from adobe_bsdf._version import __version__
from adobe_bsdf.tables.catalog import SPECS
from adobe_bsdf.tables.table import Table, TableSpec

__all__ = ["BLOCK", "CheckResult", "bake", "check", "compute", "run", "user_folder"]

#: nodes per task
BLOCK = 32


def _block(task):
    spec, coords = task
    return spec.compute(spec, *coords)


def compute(spec: TableSpec, coords, workers: int = 2, progress: bool = True,
            parent: Table | None = None):
    """Values and errors ``(n_nodes, n_outputs)`` of ``spec`` at node coordinates ``coords``
    (one 1-D array per axis); a derived table reads the baked ``parent``."""
    coords = [np.asarray(c, dtype=np.float64) for c in coords]
    n = len(coords[0])
    if spec.depends:  # derived tables are cheap: no pool
        return spec.compute(spec, *coords, parent=parent)
    tasks = [(spec, [c[s:s + BLOCK] for c in coords]) for s in range(0, n, BLOCK)]
    bar = tqdm(total=n, desc=spec.name, unit="node", disable=not progress, leave=False)
    results = []
    with ProcessPoolExecutor(max_workers=workers) as pool:
        for (_, part), result in zip(tasks, pool.map(_block, tasks), strict=True):
            results.append(result)
            bar.update(len(part[0]))
    bar.close()
    values = np.concatenate([r[0] for r in results])
    errors = np.concatenate([r[1] for r in results])
    return values, errors


def bake(spec: TableSpec, workers: int = 2, progress: bool = True,
         parent: Table | None = None) -> Table:
    """Compute every node of ``spec`` (a derived table from its baked ``parent``); the
    metadata records how, how long, and the parent's content hash."""
    start = time.perf_counter()
    values, errors = compute(spec, spec.grid(), workers, progress, parent)
    seconds = time.perf_counter() - start
    meta = {"bake_seconds": round(seconds, 2), "workers": workers,
            "baked_utc": datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
            "library_version": __version__, "numpy": np.__version__,
            "scipy": scipy.__version__, "python": platform.python_version(),
            "description": spec.description}
    if parent is not None:
        meta["parent_hash"] = parent.meta["content_hash"]
    return Table(spec, values.reshape(spec.shape), errors.reshape(spec.shape), meta)


class CheckResult(NamedTuple):
    """Outcome of ``check``: the largest |re-baked - stored| over the sampled nodes."""

    name: str
    n_nodes: int
    max_difference: float
    max_stored_error: float
    order: int


def check(spec: TableSpec, table: Table, n_nodes: int = 16, seed: int = 0,
          workers: int = 2, order: int | None = None, parent: Table | None = None
          ) -> CheckResult:
    """Re-bake ``n_nodes`` random nodes (seeded) at quadrature order ``order`` (default:
    1.5 times the table's) and compare with the stored values."""
    rng = np.random.default_rng(seed)
    n_total = int(np.prod(spec.shape[:-1]))
    index = np.sort(rng.choice(n_total, size=min(n_nodes, n_total), replace=False))
    coords = [c[index] for c in spec.grid()]
    order = order or (3 * spec.order) // 2
    fresh, _ = compute(dataclasses.replace(spec, order=order), coords, workers, progress=False,
                       parent=parent)
    stored = table.values.reshape(n_total, -1)[index]
    errors = table.errors.reshape(n_total, -1)[index]
    return CheckResult(spec.name, len(index), float(np.abs(fresh - stored).max()),
                       float(errors.max()), order)


#: largest |re-baked - stored| accepted by ``bake --check``
CHECK_TOL = 1e-6


def _ordered(names):
    """``names`` plus every table derived from them, parents first."""
    wanted = set(names)
    changed = True
    while changed:
        extra = {n for n, s in SPECS.items() if set(s.depends) & wanted} - wanted
        wanted |= extra
        changed = bool(extra)
    return [n for n in SPECS if n in wanted]  # SPECS lists parents before children


def user_folder() -> Path:
    """Where ``bake`` writes by default: ``$XDG_CACHE_HOME/adobe_bsdf/tables`` (``~/.cache``
    when ``XDG_CACHE_HOME`` is unset), never the shipped tables."""
    cache = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(cache) / "adobe_bsdf" / "tables"


def run(names=(), *, do_check=False, n_nodes=16, seed=0, workers=2, resolution=None,
        out=None, in_place=False) -> int:
    """The ``bake`` command: bake (or with ``do_check`` verify) tables; returns the number of
    failed checks.

    Parameters
    ----------
    names : sequence of str
        Tables to bake (default: all); the tables derived from them are re-derived.
    do_check : bool
        Re-bake ``n_nodes`` random nodes (seeded by ``seed``) of the tables in ``out`` (default:
        the shipped ones) and compare; nothing is written.
    workers : int
        Worker processes.
    resolution : int, optional
        Nodes per axis instead of the declared ones (not with ``in_place``).
    out : str or Path, optional
        Folder to write to (default ``user_folder()``).
    in_place : bool
        Write over the shipped tables that the library reads (``store.data_dir()``).
    """
    from adobe_bsdf.tables.store import data_dir, spec
    from adobe_bsdf.tables.table import TableError, load, save

    for name in names:
        spec(name)  # unknown names raise before any work
    if in_place and (out is not None or resolution):
        raise ValueError("in_place writes the shipped tables: it takes neither out nor "
                         "resolution")
    shipped = data_dir()
    if do_check:
        folder = Path(out) if out is not None else shipped
    else:
        folder = shipped if in_place else Path(out) if out is not None else user_folder()
        folder.mkdir(parents=True, exist_ok=True)
        print(f"baking into {folder}" + ("" if in_place else
              f" (the library reads the shipped tables in {shipped}; --in-place replaces "
              "them)"), flush=True)
    failures = 0
    baked = {}

    def parent_of(s):
        """The baked parent of derived table ``s``: from this run, else from ``folder``, else
        (declared resolution only) the shipped one."""
        name = s.depends[0]
        if name in baked:
            return baked[name]
        declared = spec(name) if not resolution else _resized(name, resolution)
        for where in (folder, None if resolution else shipped):
            if where is not None and (where / f"{name}.npz").exists():
                return load(declared, where / f"{name}.npz")
        raise TableError(f"table {s.name} is derived from {name}, which is not in {folder}: "
                         f"bake {name} too")

    for name in _ordered(list(names) or list(SPECS)):
        s = spec(name)
        if resolution:
            s = _resized(name, resolution)
        parent = parent_of(s) if s.depends else None
        if do_check:
            table = load(s, folder / f"{name}.npz")
            r = check(s, table, n_nodes, seed, workers, parent=parent)
            ok = r.max_difference <= CHECK_TOL
            failures += not ok
            print(f"{name:28s} {r.n_nodes:4d} nodes re-baked at order {r.order}: "
                  f"max |diff| = {r.max_difference:.1e} (stored error estimate <= "
                  f"{r.max_stored_error:.1e})  {'pass' if ok else 'FAIL'}", flush=True)
            continue
        table = bake(s, workers, progress=True, parent=parent)
        save(table, folder / f"{name}.npz")
        baked[name] = load(s, folder / f"{name}.npz")
        print(f"{name:28s} {table.values.size:8d} values, {table.meta['bake_seconds']:8.1f} s, "
              f"max error estimate {table.errors.max():.1e}", flush=True)
    return failures


def _resized(name, resolution):
    from adobe_bsdf.tables.store import spec

    s = spec(name)
    return dataclasses.replace(s, axes=tuple(dataclasses.replace(a, n=resolution)
                                             for a in s.axes))
