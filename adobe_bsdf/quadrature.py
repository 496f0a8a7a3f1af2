"""Adaptive cubature over the sphere, and the direction-space energy albedo of a lobe.

Public API
----------
``SphereGrid``        the (t, phi) grid about a pole, with warped rings.
``integrate_cells``   vectorised adaptive Genz–Malik cubature of a scalar or vector integrand
                      over many 2-D cells, each to its own tolerance, with guard points.
``CellIntegral``      its result: per-cell (per-channel) estimate and error.
``albedo``            energy albedo of a lobe for a batch of ``wo`` by cubature of ``eval``.

The albedo is integrated in *direction* space, from ``eval`` alone: sample-space integration
(of sample weights over the uniforms) cannot see energy that the sampler maps into a sliver of
the unit square (a GGX lobe with alpha = 0.01 loses 1e-4 of its energy in u in (1 - 1e-4, 1)),
and then reports convergence with a false error estimate.

References
----------
- A. C. Genz, A. A. Malik, "An adaptive algorithm for numerical integration over an
  n-dimensional rectangular region", J. Comput. Appl. Math. 6(4), 1980.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from adobe_bsdf import _params

__all__ = ["CellIntegral", "SphereGrid", "albedo", "integrate_cells"]

#: largest number of integrand values (points times channels) computed in one call
BATCH = 1 << 20
#: the allowed range of ``SphereGrid``'s ``warp``
WARP_RANGE = (1.0, 8.0)

# -- Genz–Malik degree-7 rule on [-1, 1]^2 with its embedded degree-5 rule -----------------------
# Nodes and weights from Genz & Malik (1980) for dimension 2; weights are normalised to the mean
# over the square (they sum to 1), so a region's integral is its area times the weighted sum.
_L2, _L3, _L4, _L5 = np.sqrt(9 / 70), np.sqrt(9 / 10), np.sqrt(9 / 10), np.sqrt(9 / 19)
_NODES = np.array(
    [(0.0, 0.0)]
    + [(_L2, 0.0), (-_L2, 0.0), (0.0, _L2), (0.0, -_L2)]
    + [(_L3, 0.0), (-_L3, 0.0), (0.0, _L3), (0.0, -_L3)]
    + [(_L4, _L4), (_L4, -_L4), (-_L4, _L4), (-_L4, -_L4)]
    + [(_L5, _L5), (_L5, -_L5), (-_L5, _L5), (-_L5, -_L5)]
)
_FAMILY = [1, 4, 4, 4, 4]
_W7 = np.repeat([-3816 / 19683, 980 / 6561, 1020 / 19683, 200 / 19683, 6859 / 78732], _FAMILY)
_W5 = np.repeat([-971 / 729, 245 / 486, 65 / 1458, 25 / 729, 0.0], _FAMILY)
#: ratio of the squared offsets of the two axial node families, for the fourth differences
_FOURTH = _L2**2 / _L3**2



class SphereGrid:
    """Grid over the whole sphere in rings and sectors about a pole.

    A cell is a rectangle in ``(t, phi)``: ``t`` in [0, 1] indexes rings, with polar angle from
    the pole ``theta' = pi t**warp``, and ``phi`` in [0, 2 pi) is the azimuth about the pole.
    Rings are uniform in ``t``, except that when the pole is ``+z`` or ``-z`` the ring edge
    nearest the horizon is moved onto it (and samples are binned by the sign of ``z``), so that
    no cell straddles the reflection/transmission boundary, where pdfs are discontinuous.

    Parameters
    ----------
    n_theta : int
        Number of rings, in [2, inf).
    n_phi : int
        Number of sectors, in [1, inf).
    axis : array_like (3,), optional
        Pole; normalised. Default ``+z``.
    warp : float
        Ring warp exponent, in ``WARP_RANGE``; 1 is uniform in polar angle.
    """

    def __init__(self, n_theta: int, n_phi: int, axis=None, warp: float = 1.0):
        self.n_theta = _params.integer("n_theta", n_theta, 2)
        self.n_phi = _params.integer("n_phi", n_phi, 1)
        self.warp = float(_params.real("warp", warp, *WARP_RANGE))
        self.axis = np.array([0.0, 0.0, 1.0]) if axis is None else _unit_axis(axis)
        helper = np.array([0.0, 0.0, 1.0]) if abs(self.axis[2]) < 0.9 else np.array([1.0, 0, 0])
        e1 = helper - (helper @ self.axis) * self.axis
        e1 /= np.linalg.norm(e1)
        #: rows: first and second tangent, pole
        self.frame = np.stack([e1, np.cross(self.axis, e1), self.axis])
        self.t_edges = np.linspace(0.0, 1.0, self.n_theta + 1)
        #: index of the ring edge on the horizon, or None when the pole is not +-z
        self.horizon_edge = None
        if self.axis[0] == 0.0 and self.axis[1] == 0.0:
            t_horizon = 0.5 ** (1.0 / self.warp)
            k = int(np.clip(np.rint(t_horizon * self.n_theta), 1, self.n_theta - 1))
            self.t_edges[k] = t_horizon
            self.horizon_edge = k
        self.phi_edges = np.linspace(0.0, 2.0 * np.pi, self.n_phi + 1)

    @property
    def shape(self) -> tuple[int, int]:
        """``(n_theta, n_phi)``."""
        return self.n_theta, self.n_phi

    @property
    def theta_edges(self) -> np.ndarray:
        """Polar angles from the pole of the ring edges, ``(n_theta + 1,)``."""
        return np.pi * self.t_edges**self.warp

    def cell_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper ``(t, phi)`` corners of every cell, each ``(n_theta * n_phi, 2)``."""
        t0, p0 = np.meshgrid(self.t_edges[:-1], self.phi_edges[:-1], indexing="ij")
        t1, p1 = np.meshgrid(self.t_edges[1:], self.phi_edges[1:], indexing="ij")
        return (np.stack([t0.ravel(), p0.ravel()], axis=-1),
                np.stack([t1.ravel(), p1.ravel()], axis=-1))

    def direction(self, t: np.ndarray, phi: np.ndarray) -> np.ndarray:
        """Unit direction ``(..., 3)`` of grid coordinates ``(t, phi)``."""
        theta = np.pi * t**self.warp
        sin_theta = np.sin(theta)
        e1, e2, pole = self.frame
        return ((sin_theta * np.cos(phi))[..., None] * e1
                + (sin_theta * np.sin(phi))[..., None] * e2 + np.cos(theta)[..., None] * pole)

    def jacobian(self, t: np.ndarray) -> np.ndarray:
        """Solid angle per unit ``t`` per unit ``phi``: ``sin(theta') dtheta'/dt``."""
        return np.sin(np.pi * t**self.warp) * np.pi * self.warp * t ** (self.warp - 1.0)

    def coordinates(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Grid coordinates ``(t, phi)`` of unit directions ``w`` ``(..., 3)``, and ``w``'s
        component along the pole."""
        # explicit sums: a (N, 3) @ (3, 3) matmul is an order of magnitude slower in NumPy
        x, y, height = (w[..., 0] * e[0] + w[..., 1] * e[1] + w[..., 2] * e[2] for e in self.frame)
        theta = np.arctan2(np.hypot(x, y), height)
        phi = np.mod(np.arctan2(y, x), 2.0 * np.pi)
        return (theta / np.pi) ** (1.0 / self.warp), phi, height

    def locate(self, w: np.ndarray) -> np.ndarray:
        """Flat cell index (ring * n_phi + sector) of unit directions ``w`` ``(..., 3)``."""
        t, phi, height = self.coordinates(w)
        ring = np.clip(np.searchsorted(self.t_edges, t, side="right") - 1, 0, self.n_theta - 1)
        if self.horizon_edge is not None:
            ring = np.where(height > 0.0, np.minimum(ring, self.horizon_edge - 1),
                            np.maximum(ring, self.horizon_edge))
        sector = np.clip((phi * (self.n_phi / (2.0 * np.pi))).astype(np.int64), 0, self.n_phi - 1)
        return ring * self.n_phi + sector


class CellIntegral(NamedTuple):
    """Result of ``integrate_cells``.

    Attributes
    ----------
    value : ndarray (n_cells,) or (n_cells, C)
        Integral over each cell (of each channel, for a vector integrand).
    error : ndarray (n_cells,) or (n_cells, C)
        Estimated absolute error of each cell (sum of its regions' ``|I7 - I5|``).
    converged : bool
        Whether every cell met its tolerance in every channel.
    n_evals : int
        Number of integrand evaluations (points; a vector integrand counts once per point).
    n_rounds : int
        Number of refinement rounds after the first evaluation.
    """

    value: np.ndarray
    error: np.ndarray
    converged: bool
    n_evals: int
    n_rounds: int


def integrate_cells(
    integrand: Callable[[np.ndarray], np.ndarray],
    lo: np.ndarray,
    hi: np.ndarray,
    tolerance: Callable[[np.ndarray], np.ndarray],
    *,
    points: np.ndarray | None = None,
    point_cells: np.ndarray | None = None,
    point_channels: np.ndarray | None = None,
    max_rounds: int = 60,
    max_evals: int = 20_000_000,
) -> CellIntegral:
    """Integrate ``integrand`` over many rectangles, each to its own absolute tolerance.

    Every cell starts as one region, integrated with the 17-point Genz–Malik degree-7 rule and
    its embedded degree-5 rule (error estimate ``|I7 - I5|``). While a cell's summed error
    exceeds ``tolerance(values)`` of that cell in any channel, its regions whose error in such a
    channel exceeds the tolerance divided by the cell's region count are halved along the axis
    with the larger fourth difference (largest over the channels; Genz & Malik 1980) and
    re-integrated. Each round evaluates the integrand once on the nodes of all new regions.

    A rule only sees the integrand at its nodes, so a sliver of support between the nodes (a
    discontinuity such as the horizon cutting a corner of a cell) reads as exactly 0 with error
    0. ``points`` where the integrand is known to be positive guard against this: a region that
    contains one and whose nodes are all 0 (in the point's channel) is split as well.

    Parameters
    ----------
    integrand : callable
        ``f(x) -> (M,)`` (scalar) or ``(M, C)`` (``C`` channels) for points ``x`` ``(M, 2)``.
    lo, hi : ndarray (n_cells, 2)
        Lower and upper corners of the cells.
    tolerance : callable
        ``tol(values)``: allowed absolute error per cell given the current estimates
        ``values``, ``(n_cells,)`` for a scalar integrand, ``(n_cells, C)`` for a vector one;
        it returns an array of that shape or one broadcasting to it.
    points : ndarray (P, 2), optional
        Points at which the integrand is positive (in some channel).
    point_cells : ndarray (P,) of int, optional
        The cell of each point (required with ``points``).
    point_channels : ndarray (P,) of int, optional
        The channel in which the integrand is positive at each point; default 0.
    max_rounds : int
        Refinement rounds at most, in [0, inf).
    max_evals : int
        Integrand evaluations at most, in [17 n_cells, inf); when the next round would exceed
        it, only the regions with the largest errors that fit are split, and refinement stops.

    Returns
    -------
    CellIntegral
        With ``value`` and ``error`` of shape ``(n_cells,)`` for a scalar integrand and
        ``(n_cells, C)`` for a vector one.
    """
    lo = np.asarray(lo, dtype=np.float64)
    hi = np.asarray(hi, dtype=np.float64)
    n_cells = lo.shape[0]
    max_rounds = _params.integer("max_rounds", max_rounds, 0)
    max_evals = _params.integer("max_evals", max_evals, _NODES.shape[0] * n_cells)
    if points is None:
        points, point_cells = np.empty((0, 2)), np.empty(0, dtype=np.int64)
    if point_channels is None:
        point_channels = np.zeros(points.shape[0], dtype=np.int64)
    center, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    cell = np.arange(n_cells)
    value, error, split, scalar = _genz_malik(integrand, center, half)
    n_channels = value.shape[1]
    n_evals, n_rounds = _NODES.shape[0] * n_cells, 0
    while True:
        cell_value = _cell_sums(cell, value, n_cells)
        cell_error = _cell_sums(cell, error, n_cells)
        shaped = cell_value[:, 0] if scalar else cell_value
        cell_tol = np.broadcast_to(tolerance(shaped), shaped.shape).reshape(n_cells, n_channels)
        bad = cell_error > cell_tol
        share = cell_tol / np.bincount(cell, minlength=n_cells)[:, None]
        chosen = (bad[cell] & (error > share[cell])).any(axis=1)
        blind = (value == 0) & (error == 0)
        candidate = np.flatnonzero(blind.any(axis=1))
        owner, region = _containing(points, point_cells, center[candidate], half[candidate],
                                    cell[candidate])
        region = candidate[region]
        chosen[region[blind[region, point_channels[owner]]]] = True
        chosen = np.flatnonzero(chosen)
        budget = (max_evals - n_evals) // (2 * _NODES.shape[0])  # regions we can still split
        if not chosen.size or n_rounds == max_rounds or budget < 1:
            break
        if chosen.size > budget:
            excess = (error[chosen] / np.maximum(share[cell[chosen]], 1e-300)).max(axis=1)
            chosen = chosen[np.argpartition(excess, -budget)[-budget:]]
        keep = np.ones(value.shape[0], dtype=bool)
        keep[chosen] = False
        rows = np.arange(chosen.size)
        child_half = half[chosen].copy()
        child_half[rows, split[chosen]] *= 0.5
        offset = np.zeros_like(child_half)
        offset[rows, split[chosen]] = child_half[rows, split[chosen]]
        child_center = np.concatenate([center[chosen] - offset, center[chosen] + offset])
        child_half = np.concatenate([child_half, child_half])
        child_value, child_error, child_split, _ = _genz_malik(integrand, child_center,
                                                               child_half)
        center = np.concatenate([center[keep], child_center])
        half = np.concatenate([half[keep], child_half])
        cell = np.concatenate([cell[keep], np.tile(cell[chosen], 2)])
        value = np.concatenate([value[keep], child_value])
        error = np.concatenate([error[keep], child_error])
        split = np.concatenate([split[keep], child_split])
        n_evals += child_center.shape[0] * _NODES.shape[0]
        n_rounds += 1
    if scalar:
        cell_value, cell_error = cell_value[:, 0], cell_error[:, 0]
    return CellIntegral(cell_value, cell_error, not bad.any(), n_evals, n_rounds)


def _cell_sums(cell, x, n_cells):
    """Sum the rows of ``x`` (n_regions, C) by their ``cell``: (n_cells, C)."""
    n_channels = x.shape[1]
    index = (cell[:, None] * n_channels + np.arange(n_channels)).ravel()
    return np.bincount(index, x.ravel(), n_cells * n_channels).reshape(n_cells, n_channels)


def _containing(points, point_cells, center, half, cell):
    """Pairs ``(point, region)`` of points and the regions (of their own cells) holding them."""
    order = np.argsort(cell, kind="stable")
    first = np.searchsorted(cell[order], point_cells, side="left")
    count = np.searchsorted(cell[order], point_cells, side="right") - first
    owner = np.repeat(np.arange(points.shape[0]), count)
    within = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    region = order[np.repeat(first, count) + within]
    inside = np.all(np.abs(points[owner] - center[region]) <= half[region], axis=1)
    return owner[inside], region[inside]


def _genz_malik(integrand, center, half):
    """Degree-7 estimate ``(n, C)``, ``|I7 - I5|`` ``(n, C)``, split axis ``(n,)`` and whether
    the integrand is scalar, for regions ``center +- half``."""
    x = (center[:, None, :] + half[:, None, :] * _NODES).reshape(-1, 2)
    parts, start, step = [], 0, min(x.shape[0], 4096)
    while start < x.shape[0]:
        part = np.asarray(integrand(x[start:start + step]), dtype=np.float64)
        parts.append(part.reshape(part.shape[0], -1))
        start += step
        step = max(1, BATCH // parts[0].shape[1])
    scalar = part.ndim == 1
    f = np.concatenate(parts).reshape(center.shape[0], _NODES.shape[0], -1)
    area = (4.0 * half[:, 0] * half[:, 1])[:, None]
    value = area * np.einsum("rnc,n->rc", f, _W7)
    error = area * np.abs(np.einsum("rnc,n->rc", f, _W7 - _W5))
    f0 = f[:, :1]
    fourth = np.abs(f[:, [1, 3]] + f[:, [2, 4]] - 2 * f0
                    - _FOURTH * (f[:, [5, 7]] + f[:, [6, 8]] - 2 * f0)).max(axis=2)
    # where the integrand shows no curvature at all (e.g. 0 at every node), halve the wider side
    split = np.where(fourth.max(axis=1) > 0, np.argmax(fourth, axis=1), np.argmax(half, axis=1))
    return value, error, split, scalar


def albedo(lobe, wo: np.ndarray, *, tol: float = 1e-8, n_theta: int = 16, n_phi: int = 32,
           n_guides: int = 4096, seed: int = 0,
           max_evals: int = 20_000_000) -> tuple[np.ndarray, np.ndarray]:
    """Energy albedo of ``lobe`` for a batch of ``wo`` by adaptive cubature of ``eval``.

    What is integrated: f(wo, wi) |cos theta_i| s(wo, wi) over the whole sphere of ``wi``, where
    s = ``lobe._energy_scale`` is (eta_i / eta_o)^2 for transmission and 1 for reflection (the
    energy convention of ``docs/conventions.md``); the delta branches, on which ``eval`` is 0,
    are added in closed form by ``lobe._delta_albedo(wo)``.

    The grid: the cells of one ``SphereGrid(n_theta, n_phi)`` about the pole +z, a rectangle
    ``(t, phi)`` shared by the whole batch, mapped to directions with a polar angle
    ``theta(t)`` of each batch element's own: piecewise linear in ``t``, its knots on ring
    edges, with the horizon on the grid's horizon edge (where the integrand jumps from
    reflection to transmission) and, across a refracting interface, the *refraction horizon*
    on a ring edge of the other hemisphere as well (see below). So no cell straddles a
    discontinuity of the integrand. All directions of the batch and the three colour channels
    share one call of ``integrate_cells``: every (batch element, channel) pair is a channel of
    the vector integrand, and a cell is refined while any of them exceeds its tolerance
    ``tol / n_cells``.

    The refraction horizon: a microfacet normal h with h_z = 0 refracts ``wo`` into the ring
    ``eta_o z_o + eta_i z_i = 0`` of ``wi``, i.e. ``z_i = -z_o / sqrt(s)`` with the energy scale
    s = (eta_i / eta_o)^2 of the transmission pair. Beyond it lie only directions that need
    facets facing down, so ``eval`` is 0 there; but GGX's D(h) does not vanish as h_z -> 0
    (it tends to alpha^2 / pi), so the transmitted lobe *jumps* to 0 on that ring (by ~0.1 for
    glass with alpha = 0.3). A cell straddling the ring sees the jump only through its nodes,
    and its ``|I7 - I5|`` can be orders of magnitude below its error (1e-6 true error against
    a claimed 1e-10), so the ring is made an edge. Lobes whose transmission has s = 1 (no
    index change), or reflect only, get no such edge.

    Guard points: for each ``wo``, ``n_guides`` directions drawn with ``lobe._sample`` (uniforms
    from ``numpy.random.default_rng(seed)``, so the result is deterministic) at which ``eval``
    is positive; one per (cell, batch element) is a guard point of ``integrate_cells`` for that
    element's channel, which forces refinement of a region whose nodes all miss that element's
    narrow lobe (even where other elements are non-zero). They only steer the
    refinement: the value is the cubature's alone.

    The error is the sum over cells of the Genz–Malik estimates ``|I7 - I5|`` (of the final
    regions), an estimate and in practice an overestimate of the error of the degree-7 value
    where the integrand is smooth within each cell; it cannot see support that neither the
    nodes nor the guard points touch, nor a discontinuity inside a cell.

    Parameters
    ----------
    lobe : Lobe
        Any lobe; its parameters may be arrays broadcasting against ``wo.shape[:-1]``.
    wo : ndarray (..., 3)
        Unit outgoing directions (validated by the caller).
    tol : float
        Target absolute error of each albedo value (each batch element and channel), in (0, 1).
    n_theta, n_phi : int
        Rings and sectors of the initial grid.
    n_guides : int
        Sampled directions per ``wo`` used as guard points, in [0, inf).
    seed : int
        Seed of the guard samples.
    max_evals : int
        Integrand evaluations (points) at most; if the summed error estimate still exceeds
        ``tol`` after them, a ``UserWarning`` is issued and the estimate is returned as it is.

    Returns
    -------
    value, error : ndarray (..., 3)
        The albedo and the estimated absolute error, over the batch broadcast with the lobe's
        parameter shape.
    """
    tol = float(_params.real("tol", tol, 0.0, 1.0, lo_open=True, hi_open=True))
    n_guides = _params.integer("n_guides", n_guides, 0)
    grid = SphereGrid(n_theta, n_phi)
    lo, hi = grid.cell_bounds()
    u = np.random.default_rng(seed).random((n_guides, *wo.shape[:-1], 3))
    s = lobe._sample(np.broadcast_to(wo, u.shape), u)
    shape = np.broadcast_shapes(s.pdf.shape[1:], wo.shape[:-1])
    size = int(np.prod(shape))
    wo = np.broadcast_to(wo, shape + (3,))
    rings = _ring_angles(lobe, wo, grid).reshape(size, grid.n_theta + 1)
    if np.all(rings == rings[:1]):
        rings = rings[:1]  # one map for the whole batch: directions broadcast over it
    t_edges = grid.t_edges

    def polar(t):
        """Polar angle ``(M, rows)`` of ``t`` ``(M,)`` and its derivative in ``t``."""
        ring = np.clip(np.searchsorted(t_edges, t, side="right") - 1, 0, grid.n_theta - 1)
        below, above = rings[:, ring].T, rings[:, ring + 1].T
        slope = (above - below) / (t_edges[ring + 1] - t_edges[ring])[:, None]
        return below + (t - t_edges[ring])[:, None] * slope, slope

    def integrand(x):
        theta, slope = polar(x[:, 0])
        sin_theta, phi = np.sin(theta), x[:, 1:2]
        wi = np.stack([sin_theta * np.cos(phi), sin_theta * np.sin(phi), np.cos(theta)], -1)
        wi = wi.reshape(x.shape[0], *(shape if rings.shape[0] > 1 else (1,) * len(shape)), 3)
        # |cos theta_i| times the solid angle per unit t per unit phi, sin(theta) dtheta/dt
        jacobian = (np.abs(wi[..., 2]) * (sin_theta * slope).reshape(wi.shape[:-1]))
        weight = jacobian * lobe._energy_scale(wo[None], wi)
        f = lobe._eval(wo[None], wi) * weight[..., None]
        return np.broadcast_to(f, (x.shape[0], *shape, 3)).reshape(x.shape[0], 3 * size)

    if n_guides:
        wi = np.broadcast_to(s.wi, (n_guides, *shape, 3))
        f = np.broadcast_to(lobe._eval(wo[None], wi), (n_guides, *shape, 3))
        f = f.reshape(n_guides, size, 3)
        live = np.broadcast_to(s.pdf > 0, (n_guides, *shape)).reshape(n_guides, size)
        live = live & (f > 0).any(axis=-1)
        element = np.nonzero(live)[1]
        channel = 3 * element + np.argmax(f[live], axis=-1)
        wi = wi.reshape(n_guides, size, 3)[live]
        t, phi, cell = _grid_coordinates(wi, element if rings.shape[0] > 1 else 0 * element,
                                         rings, grid)
        key, first = np.unique(cell * size + element, return_index=True)
        points, point_cells = np.stack([t[first], phi[first]], axis=-1), key // size
        point_channels = channel[first]
    else:
        points = point_cells = point_channels = None
    cells = integrate_cells(integrand, lo, hi, lambda v: tol / lo.shape[0], points=points,
                            point_cells=point_cells, point_channels=point_channels,
                            max_evals=max_evals)
    if not cells.converged and cells.error.sum(axis=0).max() > tol:
        warnings.warn(f"albedo quadrature did not reach tol = {tol:.1e} within max_evals = "
                      f"{max_evals}; estimated error {cells.error.sum(axis=0).max():.1e}",
                      stacklevel=3)
    value = cells.value.sum(axis=0).reshape(shape + (3,)) + lobe._delta_albedo(wo)
    return value, cells.error.sum(axis=0).reshape(shape + (3,))


def _ring_angles(lobe, wo, grid):
    """Polar angles ``(..., n_theta + 1)`` of the ring edges of ``albedo``'s map for each ``wo``.

    ``pi t`` (the grid's own map) with the horizon on ``grid.horizon_edge``, except where the
    transmission pair has s = ``lobe._energy_scale`` != 1: there the refraction horizon
    ``z_i = -z_o / sqrt(s)``, where it lies strictly inside the other hemisphere, is moved onto
    the ring edge of that hemisphere nearest to it, and the map is linear in ``t`` between the
    pole, that edge, the horizon and the other pole.
    """
    n, k_h = grid.n_theta, grid.horizon_edge
    t_edges = grid.t_edges
    z_o = wo[..., 2]
    below = np.array([0.0, 0.0, -1.0])
    across = np.where((z_o > 0.0)[..., None], below, -below)
    scale = np.broadcast_to(lobe._energy_scale(wo, across), z_o.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        z_i = -z_o / np.sqrt(scale)
    theta_i = np.arccos(np.clip(z_i, -1.0, 1.0))
    # the ring edges allowed for it: inside the hemisphere of the ring, at least one ring away
    # from the horizon and from the pole
    first = np.where(z_i < 0.0, k_h + 1, 1)
    last = np.where(z_i < 0.0, n - 1, k_h - 1)
    k_i = np.clip(np.rint(theta_i / np.pi * n), first, last).astype(np.int64)
    moved = ((scale != 1.0) & (z_o != 0.0) & (np.abs(z_i) < 1.0) & (first <= last)
             & np.isfinite(z_i))
    k_i = np.where(moved, k_i, k_h)  # a repeated knot: no change to the map
    theta_i = np.where(moved, theta_i, 0.5 * np.pi)
    # knots (t, theta) in increasing t: pole, horizon and refraction horizon in either order
    t_h = t_edges[k_h]
    lower = z_i < 0.0
    t_knots = np.stack([np.zeros_like(theta_i), np.where(lower, t_h, t_edges[k_i]),
                        np.where(lower, t_edges[k_i], t_h), np.ones_like(theta_i)], axis=-1)
    th_knots = np.stack([np.zeros_like(theta_i), np.where(lower, 0.5 * np.pi, theta_i),
                         np.where(lower, theta_i, 0.5 * np.pi), np.full_like(theta_i, np.pi)],
                        axis=-1)
    # piecewise linear interpolation at every ring edge, vectorised over the batch
    seg = np.clip(np.sum(t_edges[:, None] >= t_knots[..., None, 1:3], axis=-1), 0, 2)
    t0 = np.take_along_axis(t_knots, seg, -1)
    t1 = np.take_along_axis(t_knots, seg + 1, -1)
    a0 = np.take_along_axis(th_knots, seg, -1)
    a1 = np.take_along_axis(th_knots, seg + 1, -1)
    span = t1 - t0
    frac = np.where(span > 0.0, (t_edges - t0) / np.where(span > 0.0, span, 1.0), 0.0)
    rings = a0 + frac * (a1 - a0)
    rings[..., 0], rings[..., -1] = 0.0, np.pi
    return rings


def _grid_coordinates(w, row, rings, grid):
    """``(t, phi)`` and flat cell index of unit directions ``w`` ``(P, 3)`` under the map of
    ``albedo`` with ring-edge angles ``rings[row]``; directions above (below) the horizon are
    kept in the rings above (below) its edge, against rounding."""
    n = grid.n_theta
    theta = np.arctan2(np.hypot(w[:, 0], w[:, 1]), w[:, 2])
    phi = np.mod(np.arctan2(w[:, 1], w[:, 0]), 2.0 * np.pi)
    # one sorted array for all rows: row r's edges shifted by 4 pi r
    shift = 4.0 * np.pi * np.arange(rings.shape[0])
    flat = (rings + shift[:, None]).ravel()
    ring = np.searchsorted(flat, theta + shift[row], side="right") - 1 - row * (n + 1)
    ring = np.clip(ring, 0, n - 1)
    k_h = grid.horizon_edge
    ring = np.where(w[:, 2] > 0.0, np.minimum(ring, k_h - 1), np.maximum(ring, k_h))
    a0, a1 = rings[row, ring], rings[row, ring + 1]
    t0, t1 = grid.t_edges[ring], grid.t_edges[ring + 1]
    t = t0 + np.clip((theta - a0) / (a1 - a0), 0.0, 1.0) * (t1 - t0)
    sector = np.clip((phi * (grid.n_phi / (2.0 * np.pi))).astype(np.int64), 0, grid.n_phi - 1)
    return t, phi, ring * grid.n_phi + sector


def _unit_axis(axis) -> np.ndarray:
    arr = _params.real("axis", axis)
    norm = np.linalg.norm(arr) if arr.shape == (3,) else 0.0
    if norm == 0.0:
        raise ValueError(f"axis = {axis!r} must be a non-zero 3-vector")
    return arr / norm
