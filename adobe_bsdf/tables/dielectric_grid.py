"""The grid of anisotropic GGX dielectric slices: its declaration and its bake.

Public API
----------
``HALVES``                 the grid's axes, per half: index ratio below and above sqrt 2.
``grid_points(half)``      ``(n, 3)`` (alpha, ratio, eta) of every grid point, in C order.
``slice_values(point)``    the node values of the slice there, as ``dielectric_slice`` holds
                           them (``(n_nodes, 2)`` E_R, E_T, float32).
``bake(folder, executor)`` every grid point's slice, resumably: one file per finished slice
                           in ``<folder>/<NAME>.partial``, then ``<folder>/<NAME>.npz``.
``shipped()`` / ``load()``  whether the library ships the baked grid / its values (decoded
                           once per process).
``grid_slice(alpha, ratio, eta)``
                           ``interpolated_slice`` of the shipped grid (cached).
``interpolated_slice(grid, alpha, ratio, eta)``
                           the ``DielectricSlice`` of any interface on the grid: its node
                           values interpolated across the grid points (cubic convolution
                           per axis, ``Axis.stencil``); None where eta is off the grid.

Why a grid of slices (``docs/anisotropic_candidates_measured.md``): node for node, a slice's
values (in coordinates aligned with the critical angle and the kinks of a nearly
one-dimensional surface) are smooth in the interface (alpha, ratio, eta), and cubic
convolution across neighbouring slices at a log step of 0.3 per axis misses by at most
7.2e-4; the isotropic proxies miss by up to 0.37, a residual over the projected roughness is
no smoother on the dense side, and one reduced basis for the whole grid misses held-out
slices by 0.1.

Axes, each uniform in q = ln(x + offset) at a step of at most ``STEP``:

* alpha = alpha_max in [0, ``ALPHA_MAX``], offset ``ALPHA_OFFSET``: 0.3 in ln alpha above
  alpha ~ 0.3, coarser towards 0, where the slices' coordinates scale with the roughness
  and the measured error is 1e-6 (alpha 0 is the slice's own limit);
* ratio = alpha_min / alpha_max in [0, 1], offset ``RATIO_OFFSET`` (0: the one-dimensional
  surface);
* eta, the index ratio in [``ETA_MIN``, ``ETA_MAX``], q = ln(eta - 1 + ``ETA_OFFSET``), in
  two grids that end ``SQRT2_GAP`` (relative) either side of sqrt 2, where the dense side's
  segments change their order (``dielectric_slices._segments``).
"""

from __future__ import annotations

import functools
import os
from pathlib import Path

import numpy as np

from adobe_bsdf.tables.dielectric_slices import (
    DielectricSlice,
    assembled,
    filled,
    layout,
    node_directions,
    node_energy,
)
from adobe_bsdf.tables.table import Axis

__all__ = ["NAME", "HALVES", "grid_points", "slice_values", "bake", "encode", "decode",
           "shipped", "load", "grid_slice", "interpolated_slice", "ETA_MIN", "ETA_MAX",
           "ALPHA_MAX"]

NAME = "ggx_dielectric_anisotropic"
ALPHA_MAX, ETA_MIN, ETA_MAX = 2.0, 1.01, 3.0
ALPHA_OFFSET, RATIO_OFFSET, ETA_OFFSET = 0.02, 0.05, 0.05
SQRT2_GAP = 1e-5
STEP = 0.3
_ROOT2 = float(np.sqrt(2.0))


def _axis(name: str, lo: float, hi: float, offset: float) -> Axis:
    q0, q1 = np.log(lo + offset), np.log(hi + offset)
    return Axis(name, q0, q1, int(np.ceil((q1 - q0) / STEP)) + 1, "linear", "cubic")


def _axes(eta_lo: float, eta_hi: float) -> tuple[Axis, Axis, Axis]:
    return (_axis("q_alpha", 0.0, ALPHA_MAX, ALPHA_OFFSET),
            _axis("q_ratio", 0.0, 1.0, RATIO_OFFSET),
            _axis("q_eta", eta_lo - 1.0, eta_hi - 1.0, ETA_OFFSET))


#: the two grids' axes (q_alpha, q_ratio, q_eta)
HALVES = {"below": _axes(ETA_MIN, _ROOT2 * (1.0 - SQRT2_GAP)),
          "above": _axes(_ROOT2 * (1.0 + SQRT2_GAP), ETA_MAX)}


def _physical(q_alpha, q_ratio, q_eta):
    """(alpha, ratio, eta) of grid coordinates (the ends exact to rounding, clipped)."""
    def at(q, offset, hi):
        x = np.clip(np.exp(q) - offset, 0.0, hi)
        return np.where(x < 1e-12, 0.0, x)  # the first node is 0, not its rounding
    return (at(q_alpha, ALPHA_OFFSET, ALPHA_MAX), at(q_ratio, RATIO_OFFSET, 1.0),
            1.0 + np.exp(q_eta) - ETA_OFFSET)


def grid_points(half: str) -> np.ndarray:
    """``(n, 3)`` (alpha, ratio, eta) of every point of ``half``'s grid, in C order."""
    q = np.meshgrid(*[a.nodes() for a in HALVES[half]], indexing="ij")
    return np.stack(_physical(*[x.ravel() for x in q]), -1)


def slice_values(point) -> np.ndarray:
    """``(n_nodes, 2)`` float32 node values (E_R, E_T) of the slice at ``point`` = (alpha,
    ratio, eta), in ``dielectric_slices.node_directions``' order: those of
    ``dielectric_slice(*point)``."""
    point = tuple(float(x) for x in point)
    return node_energy(*point, *node_directions(layout(*point))).astype(np.float32)


def _task(task):
    half, index, point = task
    return half, index, slice_values(point)


def bake(folder, executor, progress: bool = True) -> Path:
    """Compute every grid point's slice on ``executor`` (``executors.open_executor``),
    keeping each finished one in ``<folder>/<NAME>.partial`` (a bake that stops resumes
    there), then write ``<folder>/<NAME>.npz`` (``encode``)."""
    from tqdm import tqdm

    folder = Path(folder)
    partial = folder / f"{NAME}.partial"
    partial.mkdir(parents=True, exist_ok=True)
    tasks = [(half, i, tuple(p)) for half in HALVES for i, p in enumerate(grid_points(half))]
    todo = [t for t in tasks if not (partial / f"{t[0]}_{t[1]:05d}.npy").exists()]
    with tqdm(total=len(tasks), initial=len(tasks) - len(todo), desc=NAME, unit="slice",
              disable=not progress) as bar:
        for _, (half, i, values) in executor.map(_task, todo):
            done = partial / f"{half}_{i:05d}.npy"
            np.save(done.with_suffix(".part.npy"), values)
            os.replace(done.with_suffix(".part.npy"), done)  # a stopped bake leaves no half file
            bar.update()
    grid = {}
    for half, axes in HALVES.items():
        n = int(np.prod([a.n for a in axes]))
        values = np.stack([np.load(partial / f"{half}_{i:05d}.npy") for i in range(n)])
        grid[half] = values.reshape(tuple(a.n for a in axes) + values.shape[1:])
    out = folder / f"{NAME}.npz"
    np.savez_compressed(out, **encode(grid))
    return out


#: the stored values: E in [0, 1] rounded to multiples of 1 / QUANTUM (error <= 7.6e-6),
#: differenced along the ratio axis (neighbours differ little: the differences compress)
QUANTUM = 65535


def encode(grid: dict) -> dict:
    """The arrays of the stored grid: per half, ``<half>`` int32 differences along the
    ratio axis of the values rounded to multiples of 1 / ``QUANTUM``."""
    out = {}
    for half, values in grid.items():
        q = np.rint(np.clip(np.asarray(values, dtype=np.float64), 0.0, 1.0) * QUANTUM)
        out[half] = np.diff(q.astype(np.int32), axis=1, prepend=0)
    return out


def decode(arrays) -> dict:
    """``{half: values (n_alpha, n_ratio, n_eta, n_nodes, 2)}`` float64 of ``encode``'s
    arrays."""
    return {half: np.cumsum(arrays[half], axis=1) / QUANTUM for half in HALVES}


def _half(eta: float) -> tuple[str, float]:
    """The half of index ratio ``eta`` and its q_eta (within ``SQRT2_GAP`` of sqrt 2, the
    nearer half's end)."""
    half = "below" if eta < _ROOT2 else "above"
    axis = HALVES[half][2]
    return half, float(np.clip(np.log(eta - 1.0 + ETA_OFFSET), axis.lo, axis.hi))


def interpolated_slice(grid: dict, alpha: float, ratio: float,
                       eta: float) -> DielectricSlice | None:
    """The slice of (alpha_max ``alpha`` in [0, ``ALPHA_MAX``], ``ratio`` in [0, 1], index
    ratio ``eta``) from ``grid`` (``{half: values (n_alpha, n_ratio, n_eta, n_nodes, 2)}``,
    as ``bake`` writes them): every node's value interpolated across the 4 x 4 x 4 grid
    points around it, the parts laid out at the grid's eta (the interface's own, except
    within ``SQRT2_GAP`` of sqrt 2); None where ``eta`` is outside [``ETA_MIN``,
    ``ETA_MAX``]."""
    alpha, ratio, eta = float(alpha), float(ratio), float(eta)
    if not ETA_MIN <= eta <= ETA_MAX:
        return None
    half, q_eta = _half(eta)
    coords = (np.log(min(alpha, ALPHA_MAX) + ALPHA_OFFSET),
              np.log(min(max(ratio, 0.0), 1.0) + RATIO_OFFSET), q_eta)
    values = np.asarray(grid[half])
    for axis, q in zip(HALVES[half], coords, strict=True):
        index, weight = axis.stencil(np.clip(q, axis.lo, axis.hi))
        values = np.tensordot(weight, values[index], axes=(0, 0))  # the axis contracted
    eta_grid = 1.0 + np.exp(q_eta) - ETA_OFFSET
    parts = filled(layout(alpha, ratio, eta_grid), values.astype(np.float64))
    return assembled(alpha, ratio, eta, parts)


def _path() -> Path:
    from adobe_bsdf.tables.store import data_dir
    return data_dir() / f"{NAME}.npz"


def shipped() -> bool:
    """Whether the library ships the baked grid (``tables/ggx_dielectric_anisotropic.npz``)."""
    return _path().exists()


@functools.lru_cache(maxsize=1)
def load() -> dict:
    """The shipped grid's values (``decode``), read once per process."""
    with np.load(_path()) as arrays:
        return decode(arrays)


@functools.lru_cache(maxsize=256)
def grid_slice(alpha: float, ratio: float, eta: float) -> DielectricSlice | None:
    """``interpolated_slice`` of the shipped grid, kept for the 256 interfaces last read."""
    return interpolated_slice(load(), alpha, ratio, eta)
