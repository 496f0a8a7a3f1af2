"""Baking tables: node blocks computed in parallel (locally or on Dask), resumably and
deterministically, with a progress bar.

Public API
----------
``open_executor(workers, scheduler, dask_workers)``  where node blocks run: in this process,
    a local process pool, or a Dask cluster (``Executor``).
``compute(spec, coords, workers, progress, ...)``  node values and errors at ``coords``.
``bake(spec, workers, progress, ...)``  the whole table, with its metadata.
``check(spec, table, n_nodes, seed, workers)``  re-bake random nodes at a higher quadrature
    order and compare.
``run(names, ..., out=None, in_place=False)``  the ``bake`` command: into ``out`` (default
    ``user_folder()``), or over the shipped tables with ``in_place``.

Nodes are cut into fixed blocks of ``BLOCK`` whatever the executor and the number of workers,
and the blocks are assembled in node order, so a table is bit-for-bit the same on any machine
with the same NumPy/SciPy (and CPU features). With ``partial`` (the ``bake`` command: the
folder ``<out>/<name>.partial``) every finished block is written as soon as it arrives, and
a bake that was interrupted or killed resumes from the blocks it had finished.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import platform
import shutil
import sys
import time
from datetime import datetime, timezone
from pathlib import Path
from typing import NamedTuple

import numpy as np
import scipy
from tqdm import tqdm

from adobe_bsdf._version import __version__
from adobe_bsdf.tables.catalog import SPECS
from adobe_bsdf.tables.executors import BakeError, Executor, open_executor
from adobe_bsdf.tables.partial import PartialBake, partial_folder
from adobe_bsdf.tables.table import Table, TableSpec

__all__ = ["BLOCK", "BakeError", "CheckResult", "Executor", "bake", "check", "compute",
           "open_executor", "run", "user_folder"]

#: nodes per task (and per file of a partial bake): fixed, so results never depend on it
BLOCK = 32


def _block(task):
    spec, coords = task
    return spec.compute(spec, *coords)


def _using(ex: Executor | None, workers: int | None):
    """``ex`` left open, or a new local executor of ``workers`` closed after use."""
    return contextlib.nullcontext(ex) if ex is not None else open_executor(workers)


def compute(spec: TableSpec, coords, workers: int | None = None, progress: bool = True,
            parent: Table | None = None, *, executor: Executor | None = None,
            partial=None):
    """Values and errors ``(n_nodes, n_outputs)`` of ``spec`` at node coordinates ``coords``.

    Parameters
    ----------
    spec : TableSpec
    coords : sequence of array_like
        One 1-D array of node coordinates per axis.
    workers : int, optional
        Local worker processes when no ``executor`` is given (default ``os.cpu_count()``).
    progress : bool
        Show a progress bar (nodes), advanced as blocks finish.
    parent : Table, optional
        The baked parent of a derived table (computed at once, without executor).
    executor : Executor, optional
        Where the blocks run (see ``open_executor``); left open.
    partial : str or Path, optional
        Folder of finished blocks: those found there (for this same declaration, nodes,
        ``BLOCK`` and library versions) are loaded, every other one is written there as it
        finishes. The caller removes the folder once the result is safe.
    """
    coords = [np.asarray(c, dtype=np.float64) for c in coords]
    if spec.depends:  # derived tables are cheap: no executor
        return spec.compute(spec, *coords, parent=parent)
    blocks = [[c[s:s + BLOCK] for c in coords] for s in range(0, len(coords[0]), BLOCK)]
    store = None if partial is None else PartialBake(partial, spec, coords, BLOCK)
    results = [None] * len(blocks) if store is None else store.resume(blocks)
    try:
        with _using(executor, workers) as ex:
            _fill(results, spec, blocks, ex, store, progress)
    except KeyboardInterrupt:
        if store is not None:
            print(f"\n{spec.name}: interrupted; {len(store)} of {len(blocks)} blocks are kept "
                  f"in {store.folder}: bake again to resume", file=sys.stderr, flush=True)
        raise
    values = np.concatenate([r[0] for r in results])  # in block order, however computed
    errors = np.concatenate([r[1] for r in results])
    return values, errors


def _fill(results, spec, blocks, ex, store, progress):
    """Compute the blocks whose ``results`` are None on executor ``ex``, store each (if
    ``store``) as it arrives, and advance a progress bar."""
    todo = [i for i, r in enumerate(results) if r is None]
    n = sum(len(b[0]) for b in blocks)
    with (tqdm(total=n, initial=n - sum(len(blocks[i][0]) for i in todo), desc=spec.name,
               unit="node", disable=not progress, leave=False) as bar,
          contextlib.closing(ex.map(_block, [(spec, blocks[i]) for i in todo])) as done):
        for k, result in done:
            i = todo[k]
            results[i] = result
            if store is not None:
                store.store(i, blocks[i], *result)
            bar.update(len(blocks[i][0]))


def bake(spec: TableSpec, workers: int | None = None, progress: bool = True,
         parent: Table | None = None, *, executor: Executor | None = None,
         partial=None) -> Table:
    """Compute every node of ``spec`` (a derived table from its baked ``parent``); the
    metadata records how, how long, and the parent's content hash. ``workers``,
    ``executor`` and ``partial`` are those of ``compute``."""
    start = time.perf_counter()
    with _using(executor, workers) as ex:
        values, errors = compute(spec, spec.grid(), progress=progress, parent=parent,
                                 executor=ex, partial=partial)
    seconds = time.perf_counter() - start
    meta = {"bake_seconds": round(seconds, 2), "workers": ex.workers, "executor": ex.kind,
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
    tolerance: float

    @property
    def passed(self) -> bool:
        """Within the table's ``check_tol``."""
        return self.max_difference <= self.tolerance


def check(spec: TableSpec, table: Table, n_nodes: int = 16, seed: int = 0,
          workers: int | None = None, order: int | None = None, parent: Table | None = None,
          *, executor: Executor | None = None) -> CheckResult:
    """Re-bake ``n_nodes`` random nodes (seeded) at quadrature order ``order`` (default:
    1.5 times the table's) and compare with the stored values (or the combinations
    ``spec.checked`` names)."""
    rng = np.random.default_rng(seed)
    n_total = int(np.prod(spec.shape[:-1]))
    index = np.sort(rng.choice(n_total, size=min(n_nodes, n_total), replace=False))
    coords = [c[index] for c in spec.grid()]
    order = order or (3 * spec.order) // 2
    fresh, _ = compute(dataclasses.replace(spec, order=order), coords, workers, progress=False,
                       parent=parent, executor=executor)
    difference = fresh - table.values.reshape(n_total, -1)[index]
    errors = table.errors.reshape(n_total, -1)[index]
    if spec.checked is not None:
        A = spec.checked()
        difference, errors = difference @ A, errors @ np.abs(A)
    return CheckResult(spec.name, len(index), float(np.abs(difference).max()),
                       float(errors.max()), order, spec.check_tol)



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


def run(names=(), *, do_check=False, n_nodes=16, seed=0, workers=None, scheduler=None,
        dask_workers=None, resolution=None, out=None, in_place=False) -> int:
    """The ``bake`` command: bake (or with ``do_check`` verify) tables; returns the number of
    failed checks.

    Parameters
    ----------
    names : sequence of str
        Tables to bake (default: all); the tables derived from them are re-derived.
    do_check : bool
        Re-bake ``n_nodes`` random nodes (seeded by ``seed``) of the tables in ``out`` (default:
        the shipped ones) and compare; nothing is written.
    workers, scheduler, dask_workers
        Where the blocks run, as in ``open_executor``: ``workers`` local processes (default all
        cores), the Dask scheduler at address ``scheduler``, or a local Dask cluster of
        ``dask_workers`` processes.
    resolution : int, optional
        Nodes per axis instead of the declared ones (not with ``in_place``).
    out : str or Path, optional
        Folder to write to (default ``user_folder()``). Finished blocks of the table being
        baked are kept in ``<name>.partial`` there until it is saved, so that running the
        same command again after an interruption resumes.
    in_place : bool
        Write over the shipped tables that the library reads (``store.data_dir()``).
    """
    from adobe_bsdf.tables import dielectric_grid
    from adobe_bsdf.tables.store import data_dir, spec
    from adobe_bsdf.tables.table import TableError, load, save

    grid = dielectric_grid.NAME in names
    names = [n for n in names if n != dielectric_grid.NAME]
    only_grid = grid and not names
    for name in names:
        spec(name)  # unknown names raise before any work
    if grid and (do_check or resolution):
        raise ValueError(f"{dielectric_grid.NAME} (the grid of anisotropic dielectric "
                         "slices) is baked at its declared points: without --check or "
                         "--resolution")
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

    with open_executor(workers, scheduler, dask_workers) as ex:
        if ex.kind != "in process":
            print(f"computing on {ex}", flush=True)
        if grid:
            path = dielectric_grid.bake(folder, ex, progress=True)
            size = sum(f.stat().st_size for f in path.glob("*.npz"))
            print(f"{dielectric_grid.NAME:28s} {size / 2**20:8.1f} MB", flush=True)
        for name in [] if only_grid else _ordered(list(names) or list(SPECS)):
            s = spec(name)
            if resolution:
                s = _resized(name, resolution)
            parent = parent_of(s) if s.depends else None
            if do_check:
                table = load(s, folder / f"{name}.npz")
                r = check(s, table, n_nodes, seed, parent=parent, executor=ex)
                ok = r.passed
                failures += not ok
                print(f"{name:28s} {r.n_nodes:4d} nodes re-baked at order {r.order}: "
                      f"max |diff| = {r.max_difference:.1e} (stored error estimate <= "
                      f"{r.max_stored_error:.1e})  {'pass' if ok else 'FAIL'}", flush=True)
                continue
            partial = None if s.depends else partial_folder(folder, name)
            table = bake(s, progress=True, parent=parent, executor=ex, partial=partial)
            save(table, folder / f"{name}.npz")
            baked[name] = load(s, folder / f"{name}.npz")
            if partial is not None:
                shutil.rmtree(partial, ignore_errors=True)
            print(f"{name:28s} {table.values.size:8d} values, "
                  f"{table.meta['bake_seconds']:8.1f} s, "
                  f"max error estimate {table.errors.max():.1e}", flush=True)
    return failures


def _resized(name, resolution):
    from adobe_bsdf.tables.store import spec

    s = spec(name)
    return dataclasses.replace(s, axes=tuple(dataclasses.replace(a, n=resolution)
                                             for a in s.axes))
