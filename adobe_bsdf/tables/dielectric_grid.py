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
``GRID``, ``PATCH``, ``MATCHED``, ``GRIDS``
                           the whole grid (``SliceGrid``) and its refined patches, read first.
``THIN``, ``PENDING``      the patch of nearly one-dimensional interfaces, on its own axis in
                           ``thin_coordinate``, and the grids baked but not yet read.
``read_slice(columns_of, alpha, ratio, eta)``
                           the slice the library reads: the first grid that holds it.
``stored_columns(folder)`` / ``array_columns(grid)``
                           the grid's columns, read from files (each when first needed) or
                           from arrays.

The grid is stored one column a file (``write_column``, ``encode``): an interface reads the
four columns about its index ratio, and a bake that stops keeps what it finished.

The refined patch (``PATCH``). Where a very rough interface is nearly index-matched, its
energy seen from the dense side peaks near mu = 1 / eta, where the grid's layout has few
nodes: there the grid misses by up to 1.3e-2. The patch holds the grid's own points about
that corner (alpha_max from 0.46, index ratios up to 1.3, every roughness ratio) in the
refined layout (``dielectric_slices.layout``, twice the nodes), baked and stored as the grid
is (files ``refined-below_<k>.npz``), and is read wherever an interface's stencils lie
inside it; its error is measured in ``docs/anisotropic_grid_measured.md``.

The patch of nearly one-dimensional interfaces (``THIN``, in ``PENDING`` until it is
shipped whole): the refined layout at every roughness and index-ratio node of the grid, on
an axis in ln(ratio + ``THIN_OFFSET``), where their energy at fixed slice coordinates is
smooth (below).

The nearly index-matched patch (``MATCHED``). Between index ratios 1.01 and 1.03 the
energy, from both sides, turns faster in eta than the grid's one cell there follows (the
critical cosine mu_c = sqrt(1 - 1 / eta^2) ~ sqrt(2 (eta - 1)) sweeps the dense side); on
an axis uniform in mu_c at a step of 0.05, in the refined layout, it is read as the others
(files ``matched-below_<k>.npz``).

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
  (the node values tend to a limit, which the first node holds: ``ALPHA_LIMIT``);
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
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from adobe_bsdf.tables.dielectric_slices import (
    DielectricSlice,
    assembled,
    filled,
    layout,
    light_share,
    node_directions,
    node_energy,
)
from adobe_bsdf.tables.table import Axis

__all__ = ["NAME", "HALVES", "grid_points", "slice_values", "bake", "encode", "decode",
           "columns", "column_file", "write_column", "read_column", "stored_columns",
           "array_columns", "shipped", "grid_slice", "interpolated_slice", "ETA_MIN",
           "interpolated", "ETA_INTERPOLATED", "RATIO_INTERPOLATED", "ALPHA_REFLECTION",
           "ETA_MAX", "ALPHA_MAX", "SliceGrid", "GRID", "PATCH", "GRIDS", "point_values",
           "read_slice", "folder_columns", "ALPHA_LIMIT", "MATCHED", "critical_cosine",
           "THIN", "PENDING", "thin_coordinate", "THIN_OFFSET", "THIN_STEP"]

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
#: where the grid's interpolation starts: its second index ratio and third roughness ratio.
#: Across the cells below them the energy turns too fast for the cubic stencil at grazing
#: cosines (mu ~ 1e-3), that of a nearly index-matched interface and of a nearly
#: one-dimensional one (by up to 1e-2 and 2.6e-2: ``benchmarks.anisotropic_grid``'s column
#: "the grid alone"), and the white furnace misses by several times 2e-3. A nearly
#: index-matched interface reads ``MATCHED`` instead; a nearly one-dimensional one computes
#: its own slice, as one below ``ETA_MIN`` does. (Nearly smooth interfaces read E_R + E_T
#: from the grid down to alpha 0: its first roughness node holds the limit alpha -> 0+,
#: ``ALPHA_LIMIT``; their E_R alone they compute, ``ALPHA_REFLECTION``.)
ETA_INTERPOLATED = float(1.0 + np.exp(HALVES["below"][2].nodes()[1]) - ETA_OFFSET)
RATIO_INTERPOLATED = float(np.exp(HALVES["below"][1].nodes()[2]) - RATIO_OFFSET)
#: the least alpha_max whose E_R alone the library reads from the grid (the grid's third
#: roughness node). The grid interpolates the light side's E_R less its Fresnel share
#: (``dielectric_slices.fresnel_share``: E_R of a nearly smooth interface follows F, which
#: falls from 1 at grazing faster than the layout's nodes resolve), but near grazing, at
#: fixed slice coordinates, that residual grows from alpha 0 as about alpha^0.8, which the
#: cubic stencil from the first node does not follow (E_R + E_T, smooth there, it does):
#: below the third node it misses E_R by up to several times 1e-3 at cos theta 1e-3
#: (``benchmarks.anisotropic_grid``, "The light side's Fresnel share"), and the white opaque ASM
#: dielectric, whose diffuse takes 1 - E_R, would lose as much. There E_R (and its average)
#: comes from the computed slice.
ALPHA_REFLECTION = float(np.exp(HALVES["below"][0].nodes()[2]) - ALPHA_OFFSET)


def _physical(q_alpha, q_ratio, q_eta):
    """(alpha, ratio, eta) of grid coordinates (the ends exact to rounding, clipped)."""
    def at(q, offset, hi):
        x = np.clip(np.exp(q) - offset, 0.0, hi)
        return np.where(x < 1e-12, 0.0, x)  # the first node is 0, not its rounding
    return (at(q_alpha, ALPHA_OFFSET, ALPHA_MAX), at(q_ratio, RATIO_OFFSET, 1.0),
            1.0 + np.exp(q_eta) - ETA_OFFSET)


def critical_cosine(eta):
    """mu_c = sqrt(1 - 1 / eta^2), the cosine of total internal reflection of index ratio
    ``eta``: the coordinate of ``MATCHED``'s index-ratio axis."""
    return np.sqrt(1.0 - 1.0 / np.square(eta))


@dataclass(frozen=True, eq=False)  # each grid is itself (hashed by identity)
class SliceGrid:
    """Slices at the points of ``HALVES`` whose node indices lie in ``spans`` (per half, per
    axis (q_alpha, q_ratio, q_eta), the first and last index), in the grid's layout or the
    refined one (``dielectric_slices.layout``); stored in files whose names start with
    ``prefix``. ``GRID`` is the whole grid; ``PATCH`` a refined part of it. A grid with its
    own ``mu_c`` axis (nodes in ``critical_cosine``) takes its index ratios from there
    instead of q_eta, one with its own ``thin`` axis (nodes in ``thin_coordinate``) its
    roughness ratios instead of q_ratio. A grid is read for the index ratios in ``etas`` =
    [lo, hi) and the roughness ratios in ``ratios`` = [lo, hi)."""

    spans: dict
    refined: bool = False
    prefix: str = ""
    mu_c: Axis | None = None
    etas: tuple = (ETA_INTERPOLATED, np.inf)
    thin: Axis | None = None
    ratios: tuple = (0.0, np.inf)

    def shape(self, half: str) -> tuple[int, int, int]:
        return tuple(hi - lo + 1 for lo, hi in self.spans[half])

    def axes(self, half: str) -> tuple[Axis, Axis, Axis]:
        """(q_alpha, q_ratio or ``thin``, q_eta or ``mu_c``): the axes of the node indices."""
        return HALVES[half][0], self.thin or HALVES[half][1], self.mu_c or HALVES[half][2]

    def points(self, half: str) -> np.ndarray:
        """``(n, 3)`` (alpha, ratio, eta) of every point, in C order."""
        q = np.meshgrid(*[a.nodes()[lo:hi + 1] for a, (lo, hi)
                          in zip(self.axes(half), self.spans[half], strict=True)],
                        indexing="ij")
        alpha, ratio, eta = _physical(*[x.ravel() for x in q])
        if self.mu_c is not None:
            eta = 1.0 / np.sqrt(1.0 - q[2].ravel() ** 2)
        if self.thin is not None:
            ratio = np.exp(q[1].ravel()) - THIN_OFFSET
            ratio[q[1].ravel() == self.thin.lo] = 0.0  # the first node is 0, not its rounding
        return np.stack([alpha, ratio, eta], -1)

    def columns(self) -> list[tuple[str, int]]:
        """(half, k) of every column: the slices at one index ratio."""
        return [(half, k) for half in self.spans for k in range(self.shape(half)[2])]

    def stencils(self, alpha: float, ratio: float, eta: float):
        """(half, [(indices, weights)] per axis, q_eta) of the interpolant at the interface,
        the indices this grid's own; None where the stencil leaves the grid."""
        half, q_eta = _half(eta)
        if (half not in self.spans or not self.etas[0] <= eta < self.etas[1]
                or not self.ratios[0] <= ratio < self.ratios[1]):
            return None
        if self.mu_c is not None:
            q_eta = float(critical_cosine(eta))
        ratio = min(max(ratio, 0.0), 1.0)
        coords = (np.log(min(alpha, ALPHA_MAX) + ALPHA_OFFSET),
                  np.log(ratio + (RATIO_OFFSET if self.thin is None else THIN_OFFSET)), q_eta)
        out = []
        for axis, q, (lo, hi) in zip(self.axes(half), coords, self.spans[half], strict=True):
            index, weights = axis.stencil(np.clip(q, axis.lo, axis.hi))
            if index.min() < lo or index.max() > hi:
                return None
            out.append((index - lo, weights))
        return half, out, q_eta


#: the whole grid, in the layout it was baked in, read from ``RATIO_INTERPOLATED`` up
GRID = SliceGrid({half: tuple((0, a.n - 1) for a in axes) for half, axes in HALVES.items()},
                 ratios=(RATIO_INTERPOLATED, np.inf))
#: the rough, nearly index-matched corner in the refined layout: there, seen from the dense
#: side near mu = 1 / eta where the energy peaks, the grid's layout misses by up to 1.3e-2
#: (alpha 2, ratio 1, eta 1.031; ``benchmarks.anisotropic_grid``'s extremes). Read for
#: alpha_max >= 0.617 and index ratios up to 1.21 (where its stencils lie inside it).
PATCH = SliceGrid({"below": ((11, 16), (1, 11), (0, 6))}, refined=True, prefix="refined-")
#: nearly index-matched interfaces (index ratio ``ETA_MIN`` to ``ETA_INTERPOLATED``), where
#: the energy turns too fast in q_eta for the grid's one cell there (it missed by up to
#: 1e-2): the refined layout on an axis uniform in the critical cosine, whose step of 0.05
#: interpolates within 1e-3 seen from the light side (``benchmarks.anisotropic_grid``), at
#: every roughness and the roughness ratios the grid reads (from its second node)
MATCHED = SliceGrid({"below": ((0, 16), (1, 11), (0, 3))}, refined=True, prefix="matched-",
                    mu_c=Axis("mu_c", float(critical_cosine(ETA_MIN)),
                              float(critical_cosine(ETA_MIN)) + 0.15, 4, "linear", "cubic"),
                    etas=(ETA_MIN, ETA_INTERPOLATED))
#: every grid the library reads, the patches first
GRIDS = (MATCHED, PATCH, GRID)


#: ``THIN``'s axis: q = ln(ratio + THIN_OFFSET), uniform at a step of at most THIN_STEP
THIN_OFFSET, THIN_STEP = 1e-5, 0.6


def thin_coordinate(ratio):
    """q = ln(ratio + ``THIN_OFFSET``): the coordinate of ``THIN``'s roughness-ratio axis."""
    return np.log(np.asarray(ratio, dtype=np.float64) + THIN_OFFSET)


def _thin_axis() -> Axis:
    """From ratio 0 to the grid's fourth ratio node (so that every ratio below
    ``RATIO_INTERPOLATED`` has its stencil inside), uniform in ``thin_coordinate``."""
    top = float(np.exp(HALVES["below"][1].nodes()[3]) - RATIO_OFFSET)
    q0, q1 = float(thin_coordinate(0.0)), float(thin_coordinate(top))
    return Axis("q_thin", q0, q1, int(np.ceil((q1 - q0) / THIN_STEP)) + 1, "linear", "cubic")


#: nearly one-dimensional interfaces (roughness ratio below ``RATIO_INTERPOLATED``). Near
#: the smooth axis their energy turns where |cos phi| ~ ratio (and, in the boundary layer,
#: cos theta ~ ratio alpha), so at fixed slice coordinates it is a smooth function of
#: ln(ratio), not of the grid's q_ratio, nearly linear in the ratio below its offset 0.05:
#: across the grid's nodes 0, 0.016 and 0.037 it missed by up to 2.6e-2. The refined layout
#: at every roughness and index-ratio node of the grid (read from ``ETA_INTERPOLATED``) on an
#: axis in ln(ratio + 1e-5) at a step of 0.6 (16 nodes, 3808 slices). Probed before choosing
#: it (alpha 0.3 to 2, eta 1.05 and 1.5): at fixed slice coordinates within 5e-4 of the node
#: values (a step of 1.0: up to 4.7e-3), and its slices as close to the node integrator as the
#: computed ones. Baked by ``bake`` with the others (files ``thin-<half>_<k>.npz``); the
#: library reads it once it is shipped whole (``PENDING``).
_THIN_AXIS = _thin_axis()
THIN = SliceGrid({half: ((0, axes[0].n - 1), (0, _THIN_AXIS.n - 1), (0, axes[2].n - 1))
                  for half, axes in HALVES.items()}, refined=True, prefix="thin-",
                 thin=_THIN_AXIS, ratios=(0.0, RATIO_INTERPOLATED))
#: grids declared and baked (``bake``) that the library does not read yet: each joins
#: ``GRIDS`` once every column of it is shipped
PENDING = (THIN,)


def grid_points(half: str) -> np.ndarray:
    """``(n, 3)`` (alpha, ratio, eta) of every grid point, in C order."""
    return GRID.points(half)


#: the roughness at which the slices of the first roughness node (alpha_max = 0) are
#: computed: the limit alpha -> 0+ of every node's value. At alpha = 0 itself the projected
#: roughness of the slice's coordinates is ``ALPHA_FLOOR``, which puts the nodes at other
#: mu / alpha_phi than at any alpha > 0, and interpolating across that node missed by
#: several times 1e-2 at alpha 0.003 to 0.005; the node values at ``ALPHA_LIMIT`` differ
#: from those at a tenth of it by 1.8e-5 to 3.4e-5, a sixth of the node integrator's own error
#: or less (``benchmarks.anisotropic_grid``, "The nearly smooth limit").
ALPHA_LIMIT = 1e-5


def point_values(point, refined: bool = False) -> np.ndarray:
    """``(n_nodes, 2)`` float32 node values (E_R, E_T) of the slice at ``point`` = (alpha,
    ratio, eta), in ``dielectric_slices.node_directions``' order: those of
    ``dielectric_slice(*point, refined=refined)``, at alpha = 0 those at ``ALPHA_LIMIT``."""
    point = tuple(float(x) for x in point)
    point = (max(point[0], ALPHA_LIMIT),) + point[1:]
    parts = layout(*point, refined=refined)
    return node_energy(*point, *node_directions(parts)).astype(np.float32)


def slice_values(point) -> np.ndarray:
    """``point_values`` in the grid's layout (not refined)."""
    return point_values(point)


def _task(task):
    refined, key, index, point = task
    return key, index, point_values(point, True) if refined else slice_values(point)


def column_file(folder, half: str, k: int, grid: SliceGrid = GRID) -> Path:
    """``<folder>/<prefix><half>_<k>.npz``: the stored slices of ``grid``'s column (``half``,
    ``k``), its k-th index ratio."""
    return Path(folder) / f"{grid.prefix}{half}_{k:02d}.npz"


def columns() -> list[tuple[str, int]]:
    """(half, k) of every column of the grid: the slices at one index ratio."""
    return GRID.columns()


def write_column(folder, half: str, k: int, values, grid: SliceGrid = GRID) -> Path:
    """Store ``values`` ``(n_alpha, n_ratio, n_nodes, 2)``, the slices of ``grid``'s column
    (``half``, ``k``): ``encode``'s integers, xz-compressed (written under a temporary name,
    then renamed)."""
    out = column_file(folder, half, k, grid)
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
    """Compute every slice of every grid (``GRIDS``, ``PENDING``) on ``executor``
    (``executors.open_executor``) into ``<folder>/<NAME>/``, one file per column
    (``write_column``) as soon as its slices are done; finished slices wait in
    ``<folder>/<NAME>.partial`` until then. A bake that stops resumes from both: columns
    already written are not computed again."""
    from tqdm import tqdm

    folder = Path(folder)
    out, partial = folder / NAME, folder / f"{NAME}.partial"
    partial.mkdir(parents=True, exist_ok=True)

    def done(grid, half, i):
        return partial / f"{grid.prefix}{half}_{i:05d}.npy"

    def store_if_complete(grid, half, k):
        n_alpha, n_ratio, n_eta = grid.shape(half)
        files = [done(grid, half, i) for i in range(k, n_alpha * n_ratio * n_eta, n_eta)]
        if column_file(out, half, k, grid).exists() or not all(f.exists() for f in files):
            return
        values = np.stack([np.load(f) for f in files])
        write_column(out, half, k, values.reshape((n_alpha, n_ratio) + values.shape[1:]),
                     grid)
        for f in files:
            f.unlink()

    grids = {grid.prefix: grid for grid in GRIDS + PENDING}
    tasks = []
    for grid in grids.values():
        for half, k in grid.columns():
            store_if_complete(grid, half, k)
        n_eta = grid.shape  # column of point i: i % n_eta
        tasks += [(grid.refined, (grid.prefix, half), i, tuple(p))
                  for half in grid.spans for i, p in enumerate(grid.points(half))
                  if not column_file(out, half, i % n_eta(half)[2], grid).exists()
                  and not done(grid, half, i).exists()]
    # grid by grid, column by column
    tasks.sort(key=lambda t: (t[1][0] != "", t[1][1] == "above",
                              t[2] % grids[t[1][0]].shape(t[1][1])[2]))
    n = sum(int(np.prod(g.shape(h))) for g in grids.values() for h in g.spans)
    with tqdm(total=n, initial=n - len(tasks), desc=NAME, unit="slice",
              disable=not progress) as bar:
        for _, ((prefix, half), i, values) in executor.map(_task, tasks):
            grid = grids[prefix]
            np.save(done(grid, half, i).with_suffix(".part.npy"), values)
            os.replace(done(grid, half, i).with_suffix(".part.npy"), done(grid, half, i))
            store_if_complete(grid, half, i % grid.shape(half)[2])
            bar.update()
    if not any(partial.iterdir()):
        partial.rmdir()
    return out


#: the stored values: E in [0, 1] rounded to multiples of 1 / QUANTUM (error <= 0.5 / QUANTUM
#: = 3.1e-5, a sixth of the node integrator's own, ``SLICE_NODE_ERROR``), differenced along
#: the ratio axis and then the alpha axis (neighbours differ little: the differences compress;
#: xz halves what zlib leaves). At 1 / 65535 the grid took 10.5 MB, at 1 / 16383 7.8 MB
#: (``benchmarks.anisotropic_grid`` measures it). The shipped columns were rounded from
#: 1 / 65535 (within 0.5 / 16383 + 0.5 / 65535 = 3.8e-5 of their node values); a bake rounds
#: once, so its integers can differ from them by one.
QUANTUM = 16383


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


def stored_columns(folder, grid: SliceGrid = GRID):
    """``column(half, k)``: the decoded values of ``grid``'s columns stored in ``folder``,
    each read once (columns for ``interpolated_slice``)."""
    @functools.cache
    def column(half: str, k: int) -> np.ndarray:
        return read_column(column_file(folder, half, k, grid))
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


def interpolated_slice(column, alpha: float, ratio: float, eta: float,
                       grid: SliceGrid = GRID) -> DielectricSlice | None:
    """The slice of (alpha_max ``alpha`` in [0, ``ALPHA_MAX``], ``ratio`` in [0, 1], index
    ratio ``eta``) from ``grid``, whose columns ``column(half, k)`` gives
    (``stored_columns``, ``array_columns``): every node's value interpolated across the
    4 x 4 x 4 grid points around it (only those four columns read), on the light side less
    each point's own Fresnel share (``light_share``; the slice adds the interface's), the
    parts laid out at the grid's eta (the interface's own, except within ``SQRT2_GAP`` of
    sqrt 2); None where
    ``eta`` is outside [``ETA_MIN``, ``ETA_MAX``] or the stencil outside ``grid``."""
    alpha, ratio, eta = float(alpha), float(ratio), float(eta)
    if not ETA_MIN <= eta <= ETA_MAX:
        return None
    found = grid.stencils(alpha, ratio, eta)
    if found is None:
        return None
    half, ((ia, wa), (ir, wr), (ie, we)), q_eta = found
    block = np.stack([column(half, int(k))[np.ix_(ia, ir)] for k in ie]).astype(np.float64)
    shares = _light_shares(grid, half, ia, ir, ie)
    n = shares.shape[-2]
    block[..., :n, :] -= shares
    residual = np.einsum("e,a,r,earnc->nc", we, wa, wr, block)
    eta_grid = eta if grid.mu_c is not None else 1.0 + np.exp(q_eta) - ETA_OFFSET
    parts = filled(layout(alpha, ratio, eta_grid, refined=grid.refined), residual)
    return assembled(alpha, ratio, eta, parts, residual=True)


def _light_shares(grid: SliceGrid, half: str, ia, ir, ie) -> np.ndarray:
    """``(e, a, r, n_light, 2)``: ``light_share`` of the grid points (node indices ``ia``,
    ``ir``, ``ie`` of ``grid``'s half) at their light side's nodes: what their node values
    hold beyond what the grid interpolates (the light side's Fresnel share,
    ``dielectric_slices.fresnel_share``, a function of each point's own coordinates)."""
    alphas, ratios, etas = _axis_values(grid, half)
    return np.stack([np.stack([np.stack([
        light_share(max(alphas[i], ALPHA_LIMIT), ratios[j], etas[k], grid.refined)
        for j in ir]) for i in ia]) for k in ie])


@functools.cache
def _axis_values(grid: SliceGrid, half: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(alpha, ratio, eta) of ``grid``'s node indices along each axis of ``half``."""
    points = grid.points(half).reshape(*grid.shape(half), 3)
    return points[:, 0, 0, 0], points[0, :, 0, 1], points[0, 0, :, 2]


def _path() -> Path:
    from adobe_bsdf.tables.store import data_dir
    return data_dir() / NAME


def shipped(grid: SliceGrid = GRID) -> bool:
    """Whether the library ships every column of ``grid`` (in
    ``tables/ggx_dielectric_anisotropic/``)."""
    return all(column_file(_path(), half, k, grid).exists() for half, k in grid.columns())


@functools.cache
def _shipped_columns(grid: SliceGrid = GRID):
    return stored_columns(_path(), grid)


def interpolated(alpha: float, ratio: float, eta: float, channel: str = "total") -> bool:
    """Whether the library reads the slice of an interface of roughness ``alpha``
    (alpha_max), roughness ratio ``ratio`` and index ratio ``eta`` from the grids for
    ``channel`` (E_R + E_T "total" or E_R "reflection"): eta in [``ETA_MIN``, ``ETA_MAX``],
    one of ``GRIDS`` holds it (``SliceGrid.stencils``: below ``ETA_INTERPOLATED``
    ``MATCHED``, from ``RATIO_INTERPOLATED`` up the grid) and, for E_R, alpha >=
    ``ALPHA_REFLECTION``; elsewhere it computes the slice."""
    return ((channel == "total" or alpha >= ALPHA_REFLECTION)
            and _held(float(alpha), float(ratio), float(eta)))


@functools.lru_cache(maxsize=4096)
def _held(alpha: float, ratio: float, eta: float) -> bool:
    return ETA_MIN <= eta <= ETA_MAX and any(
        grid.stencils(alpha, ratio, eta) is not None for grid in GRIDS)


def read_slice(columns_of, alpha: float, ratio: float, eta: float,
               channel: str = "total") -> DielectricSlice | None:
    """The slice that the library reads for the interface and ``channel``:
    ``interpolated_slice`` of the first of ``GRIDS`` whose columns ``columns_of(grid)``
    gives (None: not there) and whose stencils hold the interface; None where the grid is
    not read (``interpolated``)."""
    if not interpolated(alpha, ratio, eta, channel):
        return None
    for grid in GRIDS:
        column = columns_of(grid)
        piece = None if column is None else interpolated_slice(column, alpha, ratio, eta, grid)
        if piece is not None:
            return piece
    return None


def folder_columns(folder):
    """``columns_of(grid)`` for ``read_slice``: ``stored_columns`` of the grids whose every
    column is in ``folder``, None for the others."""
    folder = Path(folder)
    found = {grid: stored_columns(folder, grid) for grid in GRIDS
             if all(column_file(folder, h, k, grid).exists() for h, k in grid.columns())}
    return found.get


def grid_slice(alpha: float, ratio: float, eta: float,
               channel: str = "total") -> DielectricSlice | None:
    """``read_slice`` of the shipped grids (each column read from its file when first
    needed), kept for the 256 interfaces last read (one slice for both channels); None
    where the grid is not read (``interpolated``)."""
    return _grid_slice(alpha, ratio, eta) if interpolated(alpha, ratio, eta, channel) else None


@functools.lru_cache(maxsize=256)
def _grid_slice(alpha: float, ratio: float, eta: float) -> DielectricSlice | None:
    return read_slice(lambda grid: _shipped_columns(grid) if shipped(grid) else None,
                      alpha, ratio, eta)
