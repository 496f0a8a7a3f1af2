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
[GenzMalik1980] the degree-7 rule with its embedded degree-5 rule, and the choice of the
axis to split by the larger fourth difference.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from adobe_bsdf import _params

__all__ = ["sampled_albedo", "CellIntegral", "SphereGrid", "albedo", "integrate_cells"]

#: largest number of integrand values (points times channels) computed in one call
BATCH = 1 << 20
#: the allowed range of ``SphereGrid``'s ``warp``
WARP_RANGE = (1.0, 8.0)

# -- Genz–Malik degree-7 rule on [-1, 1]^2 with its embedded degree-5 rule -----------------------
# Nodes and weights from [GenzMalik1980] for dimension 2; weights are normalised to the mean
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
    with the larger fourth difference (largest over the channels; [GenzMalik1980]) and
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
    s = ``lobe._energy_scale_rgb`` is (eta_i / eta_o)^2 for transmission (per colour channel
    where the index depends on it) and 1 for reflection (the energy convention of
    ``docs/conventions.md``); the edges of the map below follow ``lobe._energy_scale``; the
    delta branches, on which ``eval`` is 0, are added in closed form by
    ``lobe._delta_albedo(wo)``.

    The grid: the cells of one ``SphereGrid(n_theta, n_phi)`` about the pole +z, a rectangle
    ``(t, phi)`` shared by the whole batch, mapped to directions by a map of each batch
    element's own (``_DirectionMap``) that puts every edge of the integrand on cell edges, so
    that the integrand is smooth inside every cell (the Genz–Malik estimate of a cell that an
    edge crosses can be orders of magnitude too small). The horizon, where the integrand jumps
    from reflection to transmission, is the grid's horizon edge. Across a refracting interface
    (energy scale s = (eta_i / eta_o)^2 != 1 for transmission), the other edges are:

    - the *refraction horizon* z_i = -z_o / sqrt(s), where eta_o z_o + eta_i z_i = 0: the
      facets with h_z = 0 refract ``wo`` there, and beyond it only facets facing down could,
      so ``eval`` is 0; GGX's D(h) does not vanish as h_z -> 0 (it tends to alpha^2 / pi), so
      the transmitted lobe *jumps* to 0 on that ring (by ~0.1 for glass with alpha = 0.3);
    - the cone about ``-wo`` outside which no facet both faces ``wo`` and refracts into
      ``wi`` (``eval`` vanishes there);
    - for s < 1, the cone about ``wo`` of the critical angle of total internal reflection,
      where reflection has a square-root edge.

    All directions of the batch and the three colour channels share one call of
    ``integrate_cells``: every (batch element, channel) pair is a channel of the vector
    integrand, and a cell is refined while any of them exceeds its tolerance ``tol / n_cells``.

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
    where = _DirectionMap(lobe, wo, grid)

    def integrand(x):
        wi, jacobian = where.directions(x[:, 0], x[:, 1])
        wi = wi.reshape(x.shape[0], *(shape if wi.shape[1] > 1 else (1,) * len(shape)), 3)
        weight = np.abs(wi[..., 2]) * jacobian.reshape(wi.shape[:-1])
        f = lobe._eval(wo[None], wi) * (weight[..., None] * lobe._energy_scale_rgb(wo[None], wi))
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
        t, phi, cell = where.coordinates(wi, element)
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
    if n_guides > 1:
        _check_against_guides(lobe, wo, s, value, tol)
    return value, cells.error.sum(axis=0).reshape(shape + (3,))


#: standard errors beyond which ``albedo`` warns that its guard samples disagree
GUIDE_SIGMAS = 6.0
#: successful guard samples a direction needs before they are compared (a sampler that
#: rarely succeeds, e.g. the sheen far above its roughness, says nothing with fewer)
GUIDE_MIN_SUCCESSES = 10


def _check_against_guides(lobe, wo, s, value, tol):
    """Warn where the cubature and the Monte-Carlo mean of the guard samples' weights (energy
    convention) differ by more than ``GUIDE_SIGMAS`` standard errors plus ``10 tol`` plus
    ``GUIDE_SIGMAS`` times the largest weight over the number of samples (events rarer than
    1 / n_guides, e.g. the energy a narrow lobe loses at the horizon, leave no trace in the
    sample's standard error): support narrower than any cell the refinement reaches (an
    alpha of ~1e-5 or less across a ridge, e.g. ASM roughness 0 with anisotropy 1), which
    the error estimate cannot see."""
    energy = s.weight * lobe._energy_scale_rgb(np.broadcast_to(wo, s.wi.shape), s.wi)
    n = energy.shape[0]
    informed = (s.pdf > 0.0).sum(axis=0) >= GUIDE_MIN_SUCCESSES
    energy = np.where(np.broadcast_to(informed, energy.shape[1:-1])[..., None], energy, 0.0)
    value = np.where(np.broadcast_to(informed, value.shape[:-1])[..., None], value, 0.0)
    mean = energy.mean(axis=0)
    sigma = energy.std(axis=0, ddof=1) / np.sqrt(n)
    rare = np.abs(energy).max(axis=0) / n
    gap = np.abs(np.broadcast_to(value, mean.shape) - mean)
    if np.any(gap > GUIDE_SIGMAS * (sigma + rare) + 10.0 * tol):
        worst = float(np.max(gap))
        warnings.warn(f"albedo quadrature differs from the Monte-Carlo mean of its guard "
                      f"samples by {worst:.2e} (over {GUIDE_SIGMAS:g} standard errors): the lobe "
                      "has support narrower than the grid resolves; use method='mc'",
                      stacklevel=4)


class _DirectionMap:
    """``albedo``'s map from the ``(t, phi)`` cells of a ``SphereGrid`` about +z to directions,
    one for each batch element, that puts the integrand's edges on cell edges.

    Each hemisphere of rings (``t`` below or above the grid's horizon edge) maps onto the
    hemisphere of directions on that side, so the horizon is a ring edge. Within a hemisphere
    the map is one of

    - *polar*: polar angle ``theta(t)`` about +z, piecewise linear in ``t`` with knots on ring
      edges, and azimuth ``phi`` (the grid's own map). Across an interface, the refraction
      horizon is a knot (``_ring_angles``);
    - *ray*, about a centre ``c`` in the hemisphere: polar coordinates (psi, beta) about ``c``,
      psi from 0 on the pole ring to the horizon psi_hor(beta) on the horizon ring (every
      great circle from ``c`` meets it once), with a knot psi = a(beta) on an inner ring edge
      and beta piecewise linear in ``phi`` with knots on sector edges. a(beta) is an edge of
      the integrand: the smallest of a cone psi = psi_k about ``c`` and the distances to at
      most two planes z = const; the beta knots are the rays on which the cone meets a plane
      (there a(beta) has a kink). Towards the knot and away from it psi is quadratic in the
      ring coordinate, so that a square-root edge sqrt(a - psi) becomes smooth.

    Ray maps are used for the two edges of a refracting interface (energy scale of
    transmission s = (eta_i / eta_o)^2 != 1, seen from ``wo``) that are not rings about +z:

    - *transmission*, centre ``-wo``: facets must face ``wo`` and be seen from behind by
      ``wi``, so the transmitted lobe lives in the cone about ``-wo`` of cos psi_k =
      min(sqrt(s), 1 / sqrt(s)) (for s > 1 its edge is where the facet turns away from
      ``wo``, for s < 1 where refraction ends in TIR), cut by the refraction horizon
      z = -z_o / sqrt(s) (``albedo``) and, for s < 1, by the horizon. There ``eval`` vanishes
      (like a square) or jumps; a cell that such an edge only clips at a corner can hold
      support that no node sees (1e-9 of energy at alpha = 0.5, read as 0 with error 0).
    - *reflection with total internal reflection* (s < 1), centre ``wo``: F(c) = 1 for
      c = wo.h = cos(psi / 2) below c_c = sqrt(1 - s) and 1 - F ~ sqrt(c - c_c) above it, a
      square-root edge on the cone psi_k = 2 asin(sqrt(s)) about ``wo``, cut by the horizon;
      the Genz–Malik estimate of a cell straddling it is 10-20 times too small.

    All maps cover the whole sphere (so any lobe integrates correctly); where a grid has too
    few rings or sectors for a ray map (fewer than 2 rings in the hemisphere, fewer than 5
    sectors), the polar map is kept.
    """

    def __init__(self, lobe, wo, grid):
        shape = wo.shape[:-1]
        self.grid = grid
        n, k_h, m = grid.n_theta, grid.horizon_edge, grid.n_phi
        self.t_h = grid.t_edges[k_h]
        z_o = wo[..., 2]
        side = np.where(z_o < 0.0, -1.0, 1.0)
        across = np.zeros(shape + (3,))
        across[..., 2] = -side
        scale = np.broadcast_to(lobe._energy_scale(wo, across), shape).astype(np.float64)
        z_o, side, scale = z_o.ravel(), side.ravel(), scale.ravel()
        size = z_o.size
        self.size = size
        self.rings = _ring_angles(z_o, scale, grid)
        if np.all(self.rings == self.rings[:1]):
            self.rings = self.rings[:1]  # one map for the whole batch: directions broadcast
        # -- ray maps, in the frame where wo is above (z mirrored where it is below) ---------
        wo1 = wo.reshape(size, 3) * np.stack([np.ones(size), np.ones(size), side], -1)
        cos_o = np.clip(wo1[:, 2], 0.0, 1.0)
        theta_o = np.arccos(cos_o)
        with np.errstate(divide="ignore", invalid="ignore"):
            root = np.sqrt(np.where(np.isfinite(scale) & (scale > 0.0), scale, 1.0))
            z_d = -cos_o / root  # the refraction horizon, mirrored frame
        interface = (z_o != 0.0) & (root != 1.0) & (m >= 5)
        rings_own = np.where(side > 0.0, k_h, n - k_h)
        rings_other = n - rings_own
        psi_c = 2.0 * np.arcsin(np.minimum(root, 1.0))
        tir = interface & (root < 1.0) & (psi_c < 0.5 * np.pi + theta_o) & (rings_own >= 2)
        transmits = interface & (rings_other >= 2)
        nan = np.full(size, np.nan)
        groups = []
        for chosen, centre_sign, psi_k, z_lo, z_hi in (
            (tir, 1.0, psi_c, np.zeros(size), nan),
            (transmits, -1.0, np.arccos(np.minimum(root, 1.0 / root)),
             np.where((root < 1.0) & (z_d > -1.0), z_d, np.nan),
             np.where(root < 1.0, 0.0, z_d)),
        ):
            elem = np.flatnonzero(chosen)
            if elem.size:
                groups.append(_Rays(elem, side[elem], centre_sign * wo1[elem], psi_k[elem],
                                    z_lo[elem], z_hi[elem], grid))
        self.groups = groups

    def _polar(self, t, phi):
        """Directions ``(M, rows, 3)`` and Jacobians ``(M, rows)`` of the polar maps."""
        t_edges, rings = self.grid.t_edges, self.rings
        ring = np.clip(np.searchsorted(t_edges, t, side="right") - 1, 0, self.grid.n_theta - 1)
        below, above = rings[:, ring].T, rings[:, ring + 1].T
        slope = (above - below) / (t_edges[ring + 1] - t_edges[ring])[:, None]
        theta = below + (t - t_edges[ring])[:, None] * slope
        sin_theta, phi = np.sin(theta), phi[:, None]
        wi = np.stack([sin_theta * np.cos(phi), sin_theta * np.sin(phi), np.cos(theta)], -1)
        # the solid angle per unit t per unit phi, sin(theta) dtheta/dt
        return wi, sin_theta * slope

    def directions(self, t, phi):
        """Directions ``(M, E, 3)`` and Jacobians ``(M, E)`` (solid angle per unit ``t`` per
        unit ``phi``) of grid points ``t, phi`` ``(M,)``; E is 1 where every batch element
        shares one map, else the batch size."""
        wi, jacobian = self._polar(t, phi)
        if not self.groups:
            return wi, jacobian
        wi = np.broadcast_to(wi, (t.shape[0], self.size, 3)).copy()
        jacobian = np.broadcast_to(jacobian, (t.shape[0], self.size)).copy()
        for rays in self.groups:
            ray_wi, ray_jacobian, inside = rays.directions(t, phi)
            cols = rays.elem
            wi[:, cols] = np.where(inside[..., None], ray_wi, wi[:, cols])
            jacobian[:, cols] = np.where(inside, ray_jacobian, jacobian[:, cols])
        return wi, jacobian

    def coordinates(self, w, element):
        """``(t, phi)`` and flat cell index of unit directions ``w`` ``(P, 3)`` of batch elements
        ``element`` ``(P,)``; a direction above (below) the horizon is kept in a ring above
        (below) its edge, against rounding."""
        grid, n = self.grid, self.grid.n_theta
        rings = self.rings
        row = element if rings.shape[0] > 1 else np.zeros_like(element)
        theta = np.arctan2(np.hypot(w[:, 0], w[:, 1]), w[:, 2])
        phi = np.mod(np.arctan2(w[:, 1], w[:, 0]), 2.0 * np.pi)
        # polar: one sorted array for all rows, row r's edges shifted by 4 pi r
        shift = 4.0 * np.pi * np.arange(rings.shape[0])
        flat = (rings + shift[:, None]).ravel()
        ring = np.searchsorted(flat, theta + shift[row], side="right") - 1 - row * (n + 1)
        ring = np.clip(ring, 0, n - 1)
        a0, a1 = rings[row, ring], rings[row, ring + 1]
        t0, t1 = grid.t_edges[ring], grid.t_edges[ring + 1]
        t = t0 + np.clip((theta - a0) / np.where(a1 > a0, a1 - a0, 1.0), 0.0, 1.0) * (t1 - t0)
        for rays in self.groups:
            index = np.full(self.size, -1)
            index[rays.elem] = np.arange(rays.elem.size)
            k = index[element]
            mine = (k >= 0) & (w[:, 2] * rays.hemisphere[np.maximum(k, 0)] > 0.0)
            t[mine], phi[mine] = rays.coordinates(w[mine], k[mine])
        ring = np.clip(np.searchsorted(grid.t_edges, t, side="right") - 1, 0, n - 1)
        k_h = grid.horizon_edge
        ring = np.where(w[:, 2] > 0.0, np.minimum(ring, k_h - 1), np.maximum(ring, k_h))
        sector = np.clip((phi * (grid.n_phi / (2.0 * np.pi))).astype(np.int64), 0,
                         grid.n_phi - 1)
        return t, phi, ring * grid.n_phi + sector


class _Rays:
    """Ray maps (see ``_DirectionMap``) of the hemisphere of the centres ``c`` of batch
    elements ``elem``, given in the frame mirrored by ``side`` (the side of ``wo``), with cones
    ``psi_k`` and planes ``z_lo`` below and ``z_hi`` above ``c`` (NaN: none) in that frame."""

    def __init__(self, elem, side, c, psi_k, z_lo, z_hi, grid):
        self.elem, self.side, self.c, self.psi_k = elem, side, c, psi_k
        self.z_lo, self.z_hi = z_lo, z_hi
        n, k_h, m = grid.n_theta, grid.horizon_edge, grid.n_phi
        t_edges = grid.t_edges
        self.t_h = t_h = t_edges[k_h]
        up = c[:, 2] > 0.0  # the hemisphere of the rings, in the mirrored frame
        self.hemisphere = np.where(up, side, -side)  # ... and in the true one
        self.upper = self.hemisphere > 0.0  # the rings above the grid's horizon edge
        self.cos_c = c[:, 2]
        self.sin_c = np.sqrt(np.maximum(1.0 - c[:, 2] ** 2, 0.0))
        # frame about c: e1 the tangent pointing down (to decreasing z), e2 = c x e1
        tilted = self.sin_c > 0.0
        e1 = np.where(tilted[:, None],
                      (self.cos_c[:, None] * c - np.array([0.0, 0.0, 1.0]))
                      / np.where(tilted, self.sin_c, 1.0)[:, None], np.array([1.0, 0.0, 0.0]))
        self.e1, self.e2 = e1, np.cross(c, e1)
        # the rays on which the cone meets a plane: z at psi_k along beta equals the plane's
        with np.errstate(divide="ignore", invalid="ignore"):
            den = np.sin(psi_k) * self.sin_c
            cos_lo = (np.cos(psi_k) * self.cos_c - z_lo) / den
            cos_hi = (np.cos(psi_k) * self.cos_c - z_hi) / den
        has_lo, has_hi = np.abs(cos_lo) < 1.0, np.abs(cos_hi) < 1.0
        b_lo = np.arccos(np.where(has_lo, cos_lo, 0.0))
        b_hi = np.arccos(np.where(has_hi, cos_hi, 0.0))
        # fill a missing knot with any value between its neighbours (no kink there)
        b1 = np.where(has_lo, b_lo, np.where(has_hi, 0.5 * b_hi, np.pi / 3.0))
        b2 = np.where(has_hi, b_hi, 0.5 * (b1 + np.pi))
        half = (m - 1) // 2
        j1 = np.clip(np.rint(b1 / (2.0 * np.pi) * m), 1, half - 1)
        j2 = np.clip(np.rint(b2 / (2.0 * np.pi) * m), j1 + 1, half)
        zero, full = np.zeros_like(b1), np.full_like(b1, 2.0 * np.pi)
        self.phi_knots = np.stack([zero, j1, j2, m - j2, m - j1, m + zero], -1) * (2 * np.pi / m)
        self.beta_knots = np.stack([zero, b1, b2, full - b2, full - b1, full], -1)
        # the ring edge of the knot psi = a(beta), in u (0 on the pole ring, 1 on the horizon)
        n_rings = np.where(self.upper, k_h, n - k_h)
        theta_c = np.arccos(np.abs(self.cos_c))
        i_c = np.clip(np.rint(psi_k / (0.5 * np.pi + theta_c) * n_rings), 1, n_rings - 1)
        i_c = i_c.astype(np.int64)
        self.u_c = np.where(self.upper, t_edges[np.minimum(i_c, k_h)] / t_h,
                            (1.0 - t_edges[np.maximum(n - i_c, k_h)]) / (1.0 - t_h))
        self.dudt = np.where(self.upper, 1.0 / t_h, 1.0 / (1.0 - t_h))

    def _to_plane(self, z_p, beta, k):
        """Angle along the rays ``beta`` from the centres of maps ``k`` to the planes
        ``z = z_p`` (inf: never)."""
        a, b = self.cos_c[k], -np.cos(beta) * self.sin_c[k]  # z(psi) = a cos psi + b sin psi
        r = np.hypot(a, b)
        phase = np.arctan2(b, a)
        with np.errstate(invalid="ignore"):
            q = z_p / r
            psi = np.mod(phase + np.where(z_p < a, 1.0, -1.0) * np.arccos(np.clip(q, -1, 1)),
                         2.0 * np.pi)
        return np.where(np.abs(q) <= 1.0, psi, np.inf)  # NaN planes compare False: inf

    def _edges(self, beta, k=slice(None)):
        """The knot a(beta) and the horizon psi_hor(beta) along the rays ``beta`` of maps
        ``k``."""
        horizon = self._to_plane(0.0, beta, k)
        knot = np.minimum(self.psi_k[k], np.minimum(self._to_plane(self.z_lo[k], beta, k),
                                                    self._to_plane(self.z_hi[k], beta, k)))
        return np.minimum(knot, horizon), horizon

    def directions(self, t, phi):
        """Directions ``(M, n, 3)``, Jacobians ``(M, n)`` and whether ``t`` is in the
        hemisphere of the map ``(M, n)``, for ``t, phi`` ``(M,)``."""
        t = t[:, None]
        inside = (t < self.t_h) == self.upper
        u = np.clip(np.where(self.upper, t / self.t_h, (1.0 - t) / (1.0 - self.t_h)), 0.0, 1.0)
        beta, dbeta = _piecewise_linear(phi[:, None], self.phi_knots, self.beta_knots)
        a, end = self._edges(beta)
        u_c = self.u_c
        x = np.minimum(u / u_c, 1.0)
        y = np.maximum((u - u_c) / (1.0 - u_c), 0.0)
        first = u <= u_c
        psi = np.where(first, a * x * (2.0 - x), a + (end - a) * y * y)
        dpsi = np.where(first, 2.0 * a * (1.0 - x) / u_c, 2.0 * (end - a) * y / (1.0 - u_c))
        cos_b, sin_b, cos_p, sin_p = np.cos(beta), np.sin(beta), np.cos(psi), np.sin(psi)
        wi = (cos_p[..., None] * self.c
              + sin_p[..., None] * (cos_b[..., None] * self.e1 + sin_b[..., None] * self.e2))
        wi[..., 2] *= self.side
        return wi, sin_p * dpsi * self.dudt * dbeta, inside

    def coordinates(self, w, k):
        """``(t, phi)`` of directions ``w`` ``(P, 3)`` in the hemispheres of maps ``k``."""
        w = w * np.stack([np.ones(k.size), np.ones(k.size), self.side[k]], -1)
        along = np.sum(w * self.c[k], -1)
        across_1, across_2 = np.sum(w * self.e1[k], -1), np.sum(w * self.e2[k], -1)
        psi = np.arctan2(np.hypot(across_1, across_2), along)
        beta = np.mod(np.arctan2(across_2, across_1), 2.0 * np.pi)
        phi = _piecewise_linear(beta[None], self.beta_knots[k], self.phi_knots[k])[0][0]
        a, end = self._edges(beta, k)
        u_c = self.u_c[k]
        x = 1.0 - np.sqrt(np.clip(1.0 - psi / np.where(a > 0.0, a, 1.0), 0.0, 1.0))
        y = np.sqrt(np.clip((psi - a) / np.where(end > a, end - a, 1.0), 0.0, 1.0))
        u = np.where(psi <= a, u_c * x, u_c + (1.0 - u_c) * y)
        t = np.where(self.upper[k], u * self.t_h, 1.0 - u * (1.0 - self.t_h))
        return t, phi


def _piecewise_linear(x, x_knots, y_knots):
    """Piecewise linear interpolation ``(M, E)`` and its slope at ``x`` ``(M, E)`` or ``(M, 1)``,
    with increasing knots ``x_knots`` and values ``y_knots``, ``(E, K)``, per column."""
    inner = x_knots[:, 1:-1]
    seg = np.sum(x[..., None] >= inner, axis=-1)
    seg = np.broadcast_to(seg, np.broadcast_shapes(seg.shape, x_knots.shape[:1]))
    cols = np.arange(x_knots.shape[0])
    x0, x1 = x_knots[cols, seg], x_knots[cols, seg + 1]
    y0, y1 = y_knots[cols, seg], y_knots[cols, seg + 1]
    slope = (y1 - y0) / np.where(x1 > x0, x1 - x0, 1.0)
    return y0 + (x - x0) * slope, slope


def _ring_angles(z_o, scale, grid):
    """Polar angles ``(E, n_theta + 1)`` of the ring edges of the polar maps of
    ``_DirectionMap``, for ``wo`` with z components ``z_o`` ``(E,)`` and energy scales of
    transmission ``scale`` ``(E,)``.

    ``pi t`` (the grid's own map) with the horizon on ``grid.horizon_edge``, except where
    ``scale`` != 1: there the refraction horizon ``z_i = -z_o / sqrt(scale)``, where it lies
    strictly inside the other hemisphere, is moved onto the ring edge of that hemisphere
    nearest to it, and the map is linear in ``t`` between the pole, that edge, the horizon and
    the other pole.
    """
    n, k_h = grid.n_theta, grid.horizon_edge
    t_edges = grid.t_edges
    with np.errstate(divide="ignore", invalid="ignore"):
        z_i = -z_o / np.sqrt(scale)
    theta_i = np.arccos(np.clip(np.where(np.isfinite(z_i), z_i, 0.0), -1.0, 1.0))
    # the ring edges allowed for it: inside the hemisphere of the ring, at least one ring away
    # from the horizon and from the pole
    lower = z_i < 0.0
    first = np.where(lower, k_h + 1, 1)
    last = np.where(lower, n - 1, k_h - 1)
    k_i = np.clip(np.rint(theta_i / np.pi * n), first, last).astype(np.int64)
    moved = ((scale != 1.0) & (z_o != 0.0) & np.isfinite(z_i) & (np.abs(z_i) < 1.0)
             & (first <= last))
    k_i = np.where(moved, k_i, k_h)  # a repeated knot: no change to the map
    theta_i = np.where(moved, theta_i, 0.5 * np.pi)
    # knots (t, theta) in increasing t: pole, horizon and refraction horizon in either order
    t_h, zero, one = t_edges[k_h], np.zeros_like(theta_i), np.ones_like(theta_i)
    t_knots = np.stack([zero, np.where(lower, t_h, t_edges[k_i]),
                        np.where(lower, t_edges[k_i], t_h), one], axis=-1)
    th_knots = np.stack([zero, np.where(lower, 0.5 * np.pi, theta_i),
                         np.where(lower, theta_i, 0.5 * np.pi), np.pi * one], axis=-1)
    rings, _ = _piecewise_linear(np.broadcast_to(t_edges[:, None], (n + 1, z_o.size)),
                                 t_knots, th_knots)
    rings = np.ascontiguousarray(rings.T)
    rings[:, 0], rings[:, -1] = 0.0, np.pi
    return rings


def _unit_axis(axis) -> np.ndarray:
    arr = _params.real("axis", axis)
    norm = np.linalg.norm(arr) if arr.shape == (3,) else 0.0
    if norm == 0.0:
        raise ValueError(f"axis = {axis!r} must be a non-zero 3-vector")
    return arr / norm


#: samples per chunk of ``sampled_albedo`` (memory: a few arrays of this many directions)
SAMPLED_CHUNK = 1 << 18


def sampled_albedo(lobe, wo: np.ndarray, order: int = 32) -> np.ndarray:
    """Albedo ``(..., 3)`` of a single-branch lobe as the integral of its sample weights over
    the unit square of its two direction uniforms, by an ``order`` x ``order``
    Gauss–Legendre product rule.

    For a lobe whose ``_sample(wo, (u0, u1, u2))`` maps (u1, u2) one-to-one onto directions
    with density pdf (a microfacet reflection sampled by visible normals, the first uniform
    unused), E(wo) = int f |cos| dw = int weight(u1, u2) du1 du2 exactly. The weight of a
    visible-normal sampler is smooth except where the reflected direction crosses the
    horizon (G2 -> 0 there), so the rule converges slowly at grazing angles: the error is
    measured in ``docs/asm_measured.md``. Each distinct ``wo`` (rows compared exactly)
    costs ``order**2`` samples.
    """
    order = _params.integer("order", order, 1)
    x, w = np.polynomial.legendre.leggauss(order)
    x, w = 0.5 * (x + 1.0), 0.5 * w
    u1, u2 = (a.ravel() for a in np.meshgrid(x, x, indexing="ij"))
    weights = np.outer(w, w).ravel()
    u = np.stack([np.full(u1.size, 0.5), u1, u2], axis=-1)
    if lobe._param_shape() == ():  # one lobe: each distinct direction once, in chunks
        flat = np.ascontiguousarray(wo.reshape(-1, 3))
        unique, inverse = np.unique(flat, axis=0, return_inverse=True)
        step = max(1, SAMPLED_CHUNK // len(u))
        value = np.concatenate([_weighted_samples(lobe, unique[i:i + step], u, weights)
                                for i in range(0, len(unique), step)] or [np.zeros((0, 3))])
        return value[inverse.ravel()].reshape(wo.shape[:-1] + (3,))
    return _weighted_samples(lobe, wo, u, weights)


def _weighted_samples(lobe, wo, u, weights):
    """sum_k weights_k lobe._sample(wo, u_k).weight over the nodes k (first axis)."""
    nodes = u.reshape((len(u),) + (1,) * (wo.ndim - 1) + (3,))
    s = lobe._sample(np.broadcast_to(wo, (len(u),) + wo.shape), nodes)
    return np.tensordot(weights, s.weight, axes=(0, 0))
