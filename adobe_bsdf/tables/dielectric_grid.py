"""The grid of anisotropic GGX dielectric slices: its declaration and its bake.

Public API
----------
``HALVES``                 the grid's axes, per half: index ratio below and above sqrt 2.
``grid_points(half)``      ``(n, 3)`` (alpha, ratio, eta) of every grid point, in C order.
``slice_values(point)``    the node values of the slice there, as ``dielectric_slice`` holds
                           them (``(n_nodes, 2)`` E_R, E_T, float32).
``bake(folder, executor)`` every grid point's slice into ``<folder>/<NAME>/``, one file per
                           column (the slices at one index ratio), resumably.
``shipped()``              whether the library ships the whole baked grid.
``grid_slice(alpha, ratio, eta)``
                           ``interpolated_slice`` of the shipped grid (cached).
``interpolated_slice(column, alpha, ratio, eta)``
                           the ``DielectricSlice`` of any interface on the grid: its node
                           values interpolated across the grid points (cubic convolution
                           per axis, ``Axis.stencil``); None where eta is off the grid.
``stored_columns(folder)`` / ``array_columns(grid)``
                           the grid's columns, read from files (each when first needed) or
                           from arrays.

The grid is stored one column a file (``write_column``, ``encode``): an interface reads the
four columns about its index ratio, and a bake that stops keeps what it finished.

Why a grid of slices (measured in ``docs/anisotropic_candidates_measured.md``): node for
node, a slice's values (in coordinates aligned with the critical angle and the kinks of a
nearly one-dimensional surface) are smooth in the interface (alpha, ratio, eta), so cubic
convolution across neighbouring slices at a log step of 0.3 per axis is accurate; the
isotropic proxies are far off, a residual over the isotropic energy at the projected
roughness is no smoother on the dense side, and one reduced basis for a whole half of the
grid needs a high rank (that page's last sections, measured on this grid).

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
import lzma
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
           "columns", "column_file", "write_column", "read_column", "stored_columns",
           "array_columns", "shipped", "grid_slice", "interpolated_slice", "ETA_MIN",
           "interpolated", "ETA_INTERPOLATED", "RATIO_INTERPOLATED", "ALPHA_INTERPOLATED",
           "ETA_MAX", "ALPHA_MAX"]

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
#: where the interpolation starts: the grid's second index ratio, third roughness ratio and
#: third roughness. Across the cells below them the energy turns too fast for the cubic
#: stencil at grazing cosines (mu ~ 1e-3), that of a nearly index-matched interface, of a
#: nearly one-dimensional one and of a nearly smooth one (1e-2 to 2.6e-2 at alpha 0.003 to
#: 0.005, 4e-3 to 6e-3 at alpha 0.01: ``benchmarks.anisotropic_grid``'s extremes), and the
#: white furnace misses by several times 2e-3. An interface there computes its own slice,
#: as one below ``ETA_MIN`` does.
ETA_INTERPOLATED = float(1.0 + np.exp(HALVES["below"][2].nodes()[1]) - ETA_OFFSET)
RATIO_INTERPOLATED = float(np.exp(HALVES["below"][1].nodes()[2]) - RATIO_OFFSET)
ALPHA_INTERPOLATED = float(np.exp(HALVES["below"][0].nodes()[2]) - ALPHA_OFFSET)


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
    ``dielectric_slice(*point, refined=False)`` (the grid's layout)."""
    point = tuple(float(x) for x in point)
    return node_energy(*point, *node_directions(layout(*point))).astype(np.float32)


def _task(task):
    half, index, point = task
    return half, index, slice_values(point)


def _shape(half: str) -> tuple[int, int, int]:
    return tuple(a.n for a in HALVES[half])


def column_file(folder, half: str, k: int) -> Path:
    """``<folder>/<half>_<k>.npz``: the stored slices of ``half``'s k-th index ratio."""
    return Path(folder) / f"{half}_{k:02d}.npz"


def columns() -> list[tuple[str, int]]:
    """(half, k) of every column of the grid: the slices at one index ratio."""
    return [(half, k) for half in HALVES for k in range(_shape(half)[2])]


def write_column(folder, half: str, k: int, values) -> Path:
    """Store ``values`` ``(n_alpha, n_ratio, n_nodes, 2)``, the slices of column (``half``,
    ``k``): ``encode``'s integers, xz-compressed (written under a temporary name, then
    renamed)."""
    out = column_file(folder, half, k)
    out.parent.mkdir(parents=True, exist_ok=True)
    stored = encode(values)
    packed = np.frombuffer(lzma.compress(stored.astype("<i4").tobytes(), preset=9), np.uint8)
    part = out.with_suffix(".part.npz")
    np.savez(part, xz=packed, shape=np.array(stored.shape))
    os.replace(part, out)
    return out


def read_column(path) -> np.ndarray:
    """The values ``(n_alpha, n_ratio, n_nodes, 2)`` of a column stored by ``write_column``."""
    with np.load(path) as arrays:
        raw = lzma.decompress(arrays["xz"].tobytes())
        return decode(np.frombuffer(raw, "<i4").reshape(tuple(arrays["shape"])))


def bake(folder, executor, progress: bool = True) -> Path:
    """Compute every grid point's slice on ``executor`` (``executors.open_executor``) into
    ``<folder>/<NAME>/``, one file per column (``write_column``) as soon as its slices are
    done; finished slices wait in ``<folder>/<NAME>.partial`` until then. A bake that stops
    resumes from both: columns already written are not computed again."""
    from tqdm import tqdm

    folder = Path(folder)
    out, partial = folder / NAME, folder / f"{NAME}.partial"
    partial.mkdir(parents=True, exist_ok=True)

    def done(half, i):
        return partial / f"{half}_{i:05d}.npy"

    def store_if_complete(half, k):
        n_alpha, n_ratio, n_eta = _shape(half)
        files = [done(half, i) for i in range(k, n_alpha * n_ratio * n_eta, n_eta)]
        if column_file(out, half, k).exists() or not all(f.exists() for f in files):
            return
        values = np.stack([np.load(f) for f in files])
        write_column(out, half, k, values.reshape((n_alpha, n_ratio) + values.shape[1:]))
        for f in files:
            f.unlink()

    for half, k in columns():
        store_if_complete(half, k)
    tasks = [(half, i, tuple(p)) for half in HALVES for i, p in enumerate(grid_points(half))
             if not column_file(out, half, i % _shape(half)[2]).exists()
             and not done(half, i).exists()]
    tasks.sort(key=lambda t: (t[0] == "above", t[1] % _shape(t[0])[2]))  # column by column
    n = sum(int(np.prod(_shape(h))) for h in HALVES)
    with tqdm(total=n, initial=n - len(tasks), desc=NAME, unit="slice",
              disable=not progress) as bar:
        for _, (half, i, values) in executor.map(_task, tasks):
            np.save(done(half, i).with_suffix(".part.npy"), values)
            os.replace(done(half, i).with_suffix(".part.npy"), done(half, i))
            store_if_complete(half, i % _shape(half)[2])
            bar.update()
    if not any(partial.iterdir()):
        partial.rmdir()
    return out


#: the stored values: E in [0, 1] rounded to multiples of 1 / QUANTUM (error <= 7.6e-6),
#: differenced along the ratio axis and then the alpha axis (neighbours differ little: the
#: differences compress; xz halves what zlib leaves)
QUANTUM = 65535


def encode(values) -> np.ndarray:
    """A column's stored integers: ``values`` ``(n_alpha, n_ratio, ...)`` rounded to
    multiples of 1 / ``QUANTUM``, differenced along the ratio axis (1), then the alpha axis
    (0); int32."""
    q = np.rint(np.clip(np.asarray(values, dtype=np.float64), 0.0, 1.0) * QUANTUM)
    q = q.astype(np.int32)
    return np.diff(np.diff(q, axis=1, prepend=0), axis=0, prepend=0)


def decode(stored) -> np.ndarray:
    """The float64 values of ``encode``'s integers."""
    return np.cumsum(np.cumsum(stored, axis=0), axis=1) / QUANTUM


def stored_columns(folder):
    """``column(half, k)``: the decoded values of the columns stored in ``folder``, each read
    once (a grid for ``interpolated_slice``)."""
    @functools.cache
    def column(half: str, k: int) -> np.ndarray:
        return read_column(column_file(folder, half, k))
    return column


def array_columns(grid: dict):
    """``column(half, k)`` of a grid held whole, ``{half: values (n_alpha, n_ratio, n_eta,
    n_nodes, 2)}`` (a grid for ``interpolated_slice``)."""
    return lambda half, k: np.asarray(grid[half])[:, :, k]


def _half(eta: float) -> tuple[str, float]:
    """The half of index ratio ``eta`` and its q_eta (within ``SQRT2_GAP`` of sqrt 2, the
    nearer half's end)."""
    half = "below" if eta < _ROOT2 else "above"
    axis = HALVES[half][2]
    return half, float(np.clip(np.log(eta - 1.0 + ETA_OFFSET), axis.lo, axis.hi))


def interpolated_slice(column, alpha: float, ratio: float,
                       eta: float) -> DielectricSlice | None:
    """The slice of (alpha_max ``alpha`` in [0, ``ALPHA_MAX``], ``ratio`` in [0, 1], index
    ratio ``eta``) from the grid whose columns ``column(half, k)`` gives (``stored_columns``,
    ``array_columns``): every node's value interpolated across the 4 x 4 x 4 grid points
    around it (only those four columns read), the parts laid out at the grid's eta (the
    interface's own, except within ``SQRT2_GAP`` of sqrt 2); None where ``eta`` is outside
    [``ETA_MIN``, ``ETA_MAX``]."""
    alpha, ratio, eta = float(alpha), float(ratio), float(eta)
    if not ETA_MIN <= eta <= ETA_MAX:
        return None
    half, q_eta = _half(eta)
    coords = (np.log(min(alpha, ALPHA_MAX) + ALPHA_OFFSET),
              np.log(min(max(ratio, 0.0), 1.0) + RATIO_OFFSET), q_eta)
    (ia, wa), (ir, wr), (ie, we) = [axis.stencil(np.clip(q, axis.lo, axis.hi))
                                    for axis, q in zip(HALVES[half], coords, strict=True)]
    block = np.stack([column(half, int(k))[np.ix_(ia, ir)] for k in ie])
    values = np.einsum("e,a,r,earnc->nc", we, wa, wr, block)
    eta_grid = 1.0 + np.exp(q_eta) - ETA_OFFSET
    parts = filled(layout(alpha, ratio, eta_grid), values)
    return assembled(alpha, ratio, eta, parts)


def _path() -> Path:
    from adobe_bsdf.tables.store import data_dir
    return data_dir() / NAME


def shipped() -> bool:
    """Whether the library ships the whole baked grid (every column in
    ``tables/ggx_dielectric_anisotropic/``)."""
    return all(column_file(_path(), half, k).exists() for half, k in columns())


@functools.lru_cache(maxsize=1)
def _shipped_columns():
    return stored_columns(_path())


def interpolated(alpha: float, ratio: float, eta: float) -> bool:
    """Whether the library reads the slice of an interface of roughness ``alpha`` (alpha_max),
    roughness ratio ``ratio`` and index ratio ``eta`` from the grid: eta in
    [``ETA_INTERPOLATED``, ``ETA_MAX``], ratio >= ``RATIO_INTERPOLATED`` and alpha >=
    ``ALPHA_INTERPOLATED``; elsewhere it computes the slice."""
    return (ETA_INTERPOLATED <= eta <= ETA_MAX and ratio >= RATIO_INTERPOLATED
            and alpha >= ALPHA_INTERPOLATED)


@functools.lru_cache(maxsize=256)
def grid_slice(alpha: float, ratio: float, eta: float) -> DielectricSlice | None:
    """``interpolated_slice`` of the shipped grid (each column read from its file when
    first needed), kept for the 256 interfaces last read; None where the grid is not read
    (``interpolated``)."""
    if not interpolated(alpha, ratio, eta):
        return None
    return interpolated_slice(_shipped_columns(), alpha, ratio, eta)
