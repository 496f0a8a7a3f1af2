"""Chi-square goodness-of-fit test of a lobe's ``sample`` against its ``pdf`` on a sphere grid.

Public API
----------
``chi2_test``        the test for one ``wo``; returns a ``Chi2Result``.
``Chi2Result``       p-value, threshold, statistic, both histograms, integrated pdf mass, ...
``SphereGrid``       the (t, phi) grid about a pole, with warped rings.
``integrate_cells``  vectorised adaptive Genz–Malik cubature of a density over many 2-D cells.
``CellIntegral``     its result: per-cell estimate and error.
``integrate_pdf``    ``integrate_cells`` of a lobe's pdf over a ``SphereGrid``, guided by samples.
``draw_samples``     samples of a lobe, sorted into delta / failed / invalid / live (``Draws``).
``classify_samples`` the same for given uniforms ``u``.
``suggest_grid``     pole ``axis`` and ring ``warp`` for a lobe of a given angular width.
``sidak_alpha``      significance level corrected for several tests.

Method
------
As the chi-square tests of Mitsuba 3 (``src/python/python/chi2.py``) and pbrt-v4
(``src/pbrt/bsdfs_test.cpp``): draw directions with ``sample``, histogram them on a grid over the
whole sphere, integrate ``pdf`` over every cell for the expected counts, pool the cells whose
expectation is below 5, and compare with Pearson's statistic. Beyond those harnesses:

- the pdf is integrated *adaptively* per cell (Genz–Malik degree-7 rule with its embedded
  degree-5 error estimate, splitting only the cells whose error is too large), to a tolerance set
  by the test's own statistical resolution (see ``chi2_test`` Notes);
- the samples that produce no direction density (delta branches and failed samples) form one
  more bin whose expectation is ``N (1 - integral of pdf)``, so that a pdf whose total mass
  disagrees with the sampler's branch probabilities is rejected too (a multinomial test over
  the grid cells plus that bin);
- rings may be warped towards the pole (``theta' = pi t**warp``) and the pole put on a narrow
  lobe's peak, so that a lobe a hundredth of a degree wide still spreads over many cells.

References
----------
- Mitsuba 3, ``src/python/python/chi2.py`` (``ChiSquareTest``); pbrt-v4,
  ``src/pbrt/bsdfs_test.cpp`` (``ChiSquareTest``).
- A. C. Genz, A. A. Malik, "An adaptive algorithm for numerical integration over an
  n-dimensional rectangular region", J. Comput. Appl. Math. 6(4), 1980.
- Z. Šidák, "Rectangular confidence regions for the means of multivariate normal
  distributions", J. Amer. Statist. Assoc. 62, 1967.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from scipy import stats

from adobe_bsdf import _params
from adobe_bsdf.bsdf import BSDFSample, Flags, Lobe

__all__ = [
    "Chi2Result",
    "CellIntegral",
    "Draws",
    "SphereGrid",
    "chi2_test",
    "classify_samples",
    "draw_samples",
    "integrate_cells",
    "integrate_pdf",
    "sidak_alpha",
    "suggest_grid",
]

#: cells whose expected count is below this are pooled into one bin (Mitsuba 3, pbrt-v4)
MIN_EXPECTED = 5.0
#: default cubature tolerance: a fraction of each cell's Poisson standard deviation
INTEGRATION_TOLERANCE = 0.01
#: largest number of directions handed to one ``sample`` or ``pdf`` call (memory bound)
BATCH = 1 << 20
#: the allowed range of ``warp``
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


def sidak_alpha(alpha: float, n_tests: int) -> float:
    """Per-test significance level that keeps the family-wise level ``alpha`` over ``n_tests``.

    Šidák's correction ``1 - (1 - alpha)**(1 / n_tests)``, as Mitsuba 3's ``ChiSquareTest.run``.

    Parameters
    ----------
    alpha : float
        Family-wise significance level, in (0, 1).
    n_tests : int
        Number of independent tests run, in [1, inf).

    Returns
    -------
    float
        The corrected per-test level.
    """
    alpha = float(_params.real("alpha", alpha, 0.0, 1.0, lo_open=True, hi_open=True))
    n_tests = _integer("n_tests", n_tests, 1)
    return float(-np.expm1(np.log1p(-alpha) / n_tests))


def suggest_grid(width: float, peak=None) -> dict:
    """Pole ``axis`` and ring ``warp`` for ``chi2_test`` on a lobe of angular ``width``.

    The warp is chosen so that the inner quarter of the rings covers about three widths about
    the pole (``pi (1/4)**warp = 3 width``), clipped to ``WARP_RANGE``. For broad lobes
    (``warp`` = 1) the pole is ``+z``, which puts a ring edge on the horizon; otherwise it is
    ``peak``.

    Parameters
    ----------
    width : float
        Characteristic angular radius of the lobe in radians, in (0, pi]: about ``2 alpha``
        for a GGX reflection lobe, ``2 alpha |1 - 1/eta|`` for a rough dielectric's
        transmission lobe (narrow as ``eta`` -> 1), ``1 / sqrt(n)`` for a cosine power ``n``.
    peak : array_like (3,), optional
        Direction of the lobe's peak (the mirror direction ``(-wo_x, -wo_y, wo_z)``, the
        refracted direction, ...). Default ``+z``.

    Returns
    -------
    dict
        ``{"axis": ndarray (3,), "warp": float}``, to pass as ``chi2_test(..., **grid)``.
    """
    width = float(_params.real("width", width, 0.0, np.pi, lo_open=True))
    warp = float(np.clip(np.log(3.0 * width / np.pi) / np.log(0.25), *WARP_RANGE))
    if warp == WARP_RANGE[0] or peak is None:
        return {"axis": np.array([0.0, 0.0, 1.0]), "warp": warp}
    return {"axis": _unit_axis(peak), "warp": warp}


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
        self.n_theta = _integer("n_theta", n_theta, 2)
        self.n_phi = _integer("n_phi", n_phi, 1)
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
    value : ndarray (n_cells,)
        Integral over each cell.
    error : ndarray (n_cells,)
        Estimated absolute error of each cell (sum of its regions' ``|I7 - I5|``).
    converged : bool
        Whether every cell met its tolerance.
    n_evals : int
        Number of integrand evaluations.
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
    max_rounds: int = 60,
    max_evals: int = 20_000_000,
) -> CellIntegral:
    """Integrate ``integrand`` over many rectangles, each to its own absolute tolerance.

    Every cell starts as one region, integrated with the 17-point Genz–Malik degree-7 rule and
    its embedded degree-5 rule (error estimate ``|I7 - I5|``). While a cell's summed error
    exceeds ``tolerance(values)`` of that cell, its regions whose error exceeds the tolerance
    divided by the cell's region count are halved along the axis with the larger fourth
    difference (Genz & Malik 1980) and re-integrated. Each round evaluates the integrand once on
    the nodes of all new regions.

    A rule only sees the integrand at its nodes, so a sliver of support between the nodes (a
    discontinuity such as the horizon cutting a corner of a cell) reads as exactly 0 with error
    0. ``points`` where the integrand is known to be positive guard against this: a region that
    contains one and whose nodes are all 0 is split as well.

    Parameters
    ----------
    integrand : callable
        ``f(x) -> (M,)`` for points ``x`` of shape ``(M, 2)``.
    lo, hi : ndarray (n_cells, 2)
        Lower and upper corners of the cells.
    tolerance : callable
        ``tol(values) -> (n_cells,)``: allowed absolute error per cell given the current
        estimates ``values`` ``(n_cells,)``.
    points : ndarray (P, 2), optional
        Points at which the integrand is positive.
    point_cells : ndarray (P,) of int, optional
        The cell of each point (required with ``points``).
    max_rounds : int
        Refinement rounds at most, in [0, inf).
    max_evals : int
        Integrand evaluations at most, in [17 n_cells, inf); when the next round would exceed
        it, only the regions with the largest errors that fit are split, and refinement stops.

    Returns
    -------
    CellIntegral
    """
    lo = np.asarray(lo, dtype=np.float64)
    hi = np.asarray(hi, dtype=np.float64)
    n_cells = lo.shape[0]
    max_rounds = _integer("max_rounds", max_rounds, 0)
    max_evals = _integer("max_evals", max_evals, _NODES.shape[0] * n_cells)
    if points is None:
        points, point_cells = np.empty((0, 2)), np.empty(0, dtype=np.int64)
    center, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    cell = np.arange(n_cells)
    value, error, split = _genz_malik(integrand, center, half)
    n_evals, n_rounds = _NODES.shape[0] * n_cells, 0
    while True:
        cell_value = np.bincount(cell, value, n_cells)
        cell_error = np.bincount(cell, error, n_cells)
        cell_tol = tolerance(cell_value)
        bad = cell_error > cell_tol
        share = cell_tol / np.bincount(cell, minlength=n_cells)
        chosen = bad[cell] & (error > share[cell])
        blind = np.flatnonzero((value == 0) & (error == 0))
        hit = _containing(points, point_cells, center[blind], half[blind], cell[blind])
        chosen[blind[hit]] = True
        chosen = np.flatnonzero(chosen)
        budget = (max_evals - n_evals) // (2 * _NODES.shape[0])  # regions we can still split
        if not chosen.size or n_rounds == max_rounds or budget < 1:
            break
        if chosen.size > budget:
            chosen = chosen[np.argpartition(error[chosen], -budget)[-budget:]]
        keep = np.ones(value.size, dtype=bool)
        keep[chosen] = False
        rows = np.arange(chosen.size)
        child_half = half[chosen].copy()
        child_half[rows, split[chosen]] *= 0.5
        offset = np.zeros_like(child_half)
        offset[rows, split[chosen]] = child_half[rows, split[chosen]]
        child_center = np.concatenate([center[chosen] - offset, center[chosen] + offset])
        child_half = np.concatenate([child_half, child_half])
        child_value, child_error, child_split = _genz_malik(integrand, child_center, child_half)
        center = np.concatenate([center[keep], child_center])
        half = np.concatenate([half[keep], child_half])
        cell = np.concatenate([cell[keep], np.tile(cell[chosen], 2)])
        value = np.concatenate([value[keep], child_value])
        error = np.concatenate([error[keep], child_error])
        split = np.concatenate([split[keep], child_split])
        n_evals += child_center.shape[0] * _NODES.shape[0]
        n_rounds += 1
    return CellIntegral(cell_value, cell_error, not bad.any(), n_evals, n_rounds)


def _containing(points, point_cells, center, half, cell):
    """Indices of the regions (of the points' own cells) that contain any of ``points``."""
    order = np.argsort(cell, kind="stable")
    first = np.searchsorted(cell[order], point_cells, side="left")
    count = np.searchsorted(cell[order], point_cells, side="right") - first
    owner = np.repeat(np.arange(points.shape[0]), count)
    within = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    region = order[np.repeat(first, count) + within]
    inside = np.all(np.abs(points[owner] - center[region]) <= half[region], axis=1)
    return np.unique(region[inside])


def _genz_malik(integrand, center, half):
    """Degree-7 estimate, ``|I7 - I5|`` and split axis for regions ``center +- half``."""
    x = (center[:, None, :] + half[:, None, :] * _NODES).reshape(-1, 2)
    f = np.concatenate([integrand(x[i:i + BATCH]) for i in range(0, x.shape[0], BATCH)])
    f = f.reshape(center.shape[0], _NODES.shape[0])
    area = 4.0 * half[:, 0] * half[:, 1]
    value = area * (f @ _W7)
    error = area * np.abs(f @ (_W7 - _W5))
    f0 = f[:, :1]
    fourth = np.abs(f[:, [1, 3]] + f[:, [2, 4]] - 2 * f0
                    - _FOURTH * (f[:, [5, 7]] + f[:, [6, 8]] - 2 * f0))
    # where the integrand shows no curvature at all (e.g. 0 at every node), halve the wider side
    split = np.where(fourth.max(axis=1) > 0, np.argmax(fourth, axis=1), np.argmax(half, axis=1))
    return value, error, split


@dataclass(frozen=True)
class Chi2Result:
    """Result of ``chi2_test``.

    Attributes
    ----------
    passed : bool
        ``p_value >= significance`` and no hard failure.
    p_value : float
        Upper tail of the chi-square distribution at ``statistic`` (0 on a hard failure).
    significance : float
        The Šidák-corrected threshold the p-value is compared with.
    statistic : float
        Pearson's statistic over the pooled bins.
    dof : int
        Degrees of freedom: number of bins after pooling minus one.
    n_samples : int
        Samples drawn.
    n_histogram : int
        Samples with a direction density (not delta, not failed), histogrammed.
    n_delta, n_failed, n_invalid : int
        Samples with the DELTA flag; failed samples (pdf 0, weight 0); invalid samples
        (non-finite or negative pdf, weight or direction, non-unit direction, or pdf 0 with a
        non-zero weight).
    n_zero_hits : int
        Histogrammed samples in cells whose expected count is ~0 (below ``zero_count``).
    n_bad_pdf : int
        Non-finite or negative values returned by ``pdf`` on the integration nodes.
    n_pooled : int
        Bins pooled because their expected count was below ``MIN_EXPECTED``.
    pdf_mass : float
        Integral of the pdf over the sphere: the expected non-delta, non-failed probability.
    integration_error : float
        Estimated absolute error of ``pdf_mass`` (sum over cells).
    integration_converged : bool
        Whether every cell met its integration tolerance.
    n_evals : int
        pdf evaluations spent on the integration.
    seconds : float
        Wall-clock time of the whole test.
    message : str
        Why the test failed, or ``""``.
    observed, expected : ndarray (n_theta, n_phi)
        Histogram of the samples and expected counts ``n_samples * integral of pdf`` per cell.
    theta_edges, phi_edges : ndarray
        Polar angle from the pole and azimuth of the cell edges.
    axis : ndarray (3,)
        Pole of the grid.
    warp : float
        Ring warp exponent.
    """

    passed: bool
    p_value: float
    significance: float
    statistic: float
    dof: int
    n_samples: int
    n_histogram: int
    n_delta: int
    n_failed: int
    n_invalid: int
    n_zero_hits: int
    n_bad_pdf: int
    n_pooled: int
    pdf_mass: float
    integration_error: float
    integration_converged: bool
    n_evals: int
    seconds: float
    message: str
    observed: np.ndarray = field(repr=False)
    expected: np.ndarray = field(repr=False)
    theta_edges: np.ndarray = field(repr=False)
    phi_edges: np.ndarray = field(repr=False)
    axis: np.ndarray = field(repr=False)
    warp: float = 1.0

    @property
    def failed_fraction(self) -> float:
        """Fraction of the samples that failed."""
        return self.n_failed / self.n_samples

    @property
    def delta_fraction(self) -> float:
        """Fraction of the samples that took a delta branch."""
        return self.n_delta / self.n_samples

    def __str__(self) -> str:
        verdict = "pass" if self.passed else "FAIL"
        text = (f"chi2 {verdict}: p = {self.p_value:.3g} (threshold {self.significance:.3g}), "
                f"chi2 = {self.statistic:.1f}, dof = {self.dof}, pdf mass = {self.pdf_mass:.6f}, "
                f"failed = {self.failed_fraction:.2%}, delta = {self.delta_fraction:.2%}, "
                f"{self.seconds:.2f} s")
        return f"{text}; {self.message}" if self.message else text


def chi2_test(
    lobe: Lobe,
    wo,
    *,
    n_samples: int = 1_000_000,
    n_theta: int = 64,
    n_phi: int = 128,
    seed: int | np.random.Generator = 0,
    alpha: float = 0.01,
    n_tests: int = 1,
    axis=None,
    warp: float = 1.0,
    integration_tolerance: float = INTEGRATION_TOLERANCE,
    max_evals: int = 20_000_000,
) -> Chi2Result:
    """Chi-square test that ``lobe.sample(wo, u)`` draws directions with density ``lobe.pdf``.

    Parameters
    ----------
    lobe : Lobe
        The lobe; its parameters must be scalars (one distribution).
    wo : array_like (3,)
        Outgoing direction (unit vector).
    n_samples : int
        Samples to draw, in [1, inf).
    n_theta, n_phi : int
        Rings (in [2, inf)) and sectors (in [1, inf)) of the grid.
    seed : int or numpy.random.Generator
        Source of the uniforms ``u``.
    alpha : float
        Family-wise significance level, in (0, 1).
    n_tests : int
        Number of tests in the family (Šidák correction), in [1, inf).
    axis : array_like (3,), optional
        Pole of the grid, e.g. the peak of a narrow lobe. Default ``+z``.
    warp : float
        Ring warp, in ``WARP_RANGE``: ``theta' = pi t**warp``; 2-3 concentrates rings at the
        pole. ``suggest_grid`` picks ``axis`` and ``warp`` from a lobe's width.
    integration_tolerance : float
        ``tau`` below, in (0, 1].
    max_evals : int
        pdf evaluations allowed to the integration, in [17 n_theta n_phi, inf).

    Returns
    -------
    Chi2Result

    Notes
    -----
    Hard failures (``p_value = 0``): any invalid sample; any pdf value that is negative or not
    finite; any sample in a bin whose expected count, plus its integration error, is below
    ``zero_count = 1e-3 alpha_c / (n_cells + 1)`` (so a correct lobe trips it with a
    probability of order ``alpha_c / 1000``), including failed or delta samples when the pdf
    integrates to 1. Too few bins to test (``dof < 1``) also fails. A cubature that did not
    converge is reported (``integration_converged``, ``message``) but is no failure by itself.

    Expected counts are ``n_samples`` times the cell integrals of the pdf, which includes the
    probability of the non-delta branches; delta and failed samples are one extra bin.
    Each cell is integrated to an absolute error of at most
    ``tau E / sqrt(max(E, 5)) + zero_count`` counts (``E`` its expected count): a fraction
    ``tau`` of its Poisson standard deviation (of ``sqrt 5`` for the small cells that get
    pooled). The bias this adds to Pearson's statistic is at most ``tau**2`` per cell, under
    ``0.82`` for the default ``tau = 0.01`` on the default 8192-cell grid, against the
    statistic's standard deviation ``sqrt(2 dof)``, about 128: the integration error is
    negligible beside the statistical error.
    """
    start = time.perf_counter()
    wo = _params.direction("wo", wo)
    if wo.shape != (3,):
        raise ValueError(f"wo has shape {wo.shape}; chi2_test takes one direction of shape (3,)")
    n_samples = _integer("n_samples", n_samples, 1)
    significance = sidak_alpha(alpha, n_tests)
    tau = float(_params.real("integration_tolerance", integration_tolerance, 0.0, 1.0,
                             lo_open=True))
    grid = SphereGrid(n_theta, n_phi, axis, warp)
    n_cells = grid.n_theta * grid.n_phi
    zero_count = 1e-3 * significance / (n_cells + 1)
    messages = []

    draws = draw_samples(lobe, wo, n_samples, seed)
    wi = draws.sample.wi[draws.live]
    observed = np.bincount(grid.locate(wi), minlength=n_cells)
    n_invalid = int(np.count_nonzero(draws.invalid))
    if n_invalid:
        messages.append(f"{n_invalid} invalid samples (non-finite or negative weight or pdf, "
                        "bad direction, or pdf 0 with non-zero weight)")

    def tolerance(prob):
        counts = n_samples * np.maximum(prob, 0.0)
        return (tau * counts / np.sqrt(np.maximum(counts, MIN_EXPECTED)) + zero_count) / n_samples

    cells, n_bad_pdf = integrate_pdf(lobe, wo, grid, tolerance, guide=wi, max_evals=max_evals)
    expected = n_samples * np.maximum(cells.value, 0.0)
    mass = float(cells.value.sum())
    if n_bad_pdf:
        messages.append(f"pdf returned {n_bad_pdf} negative or non-finite values")
    if not cells.converged:
        messages.append(f"pdf integration did not converge within {cells.n_evals} evaluations")

    # a bin is empty when even its expectation plus its integration error is below zero_count
    zero_hits = int(observed[expected + n_samples * cells.error < zero_count].sum())
    other_observed = n_samples - wi.shape[0] - n_invalid
    other_expected = max(n_samples * (1.0 - mass), 0.0)
    if other_observed and other_expected + n_samples * cells.error.sum() < zero_count:
        zero_hits += other_observed
    if zero_hits:
        messages.append(f"{zero_hits} samples where the integrated pdf is ~0")
    statistic, dof, n_pooled = _pooled_statistic(np.append(observed, other_observed),
                                                 np.append(expected, other_expected))
    if dof < 1:
        messages.append("too few bins with expected counts >= 5 to test (dof < 1): "
                        "refine the grid about the lobe (see suggest_grid)")
    hard_failure = bool(n_invalid or n_bad_pdf or zero_hits or dof < 1)
    p_value = 0.0 if hard_failure else float(stats.chi2.sf(statistic, dof))
    passed = not hard_failure and p_value >= significance
    if not hard_failure and not passed:
        messages.append("sampled directions do not follow the pdf")
    return Chi2Result(
        passed=passed, p_value=p_value, significance=significance, statistic=float(statistic),
        dof=dof, n_samples=n_samples, n_histogram=wi.shape[0],
        n_delta=int(np.count_nonzero(draws.delta)), n_failed=int(np.count_nonzero(draws.failed)),
        n_invalid=n_invalid, n_zero_hits=zero_hits, n_bad_pdf=n_bad_pdf, n_pooled=n_pooled,
        pdf_mass=mass, integration_error=float(cells.error.sum()),
        integration_converged=cells.converged, n_evals=cells.n_evals,
        seconds=time.perf_counter() - start, message="; ".join(messages),
        observed=observed.reshape(grid.shape), expected=expected.reshape(grid.shape),
        theta_edges=grid.theta_edges, phi_edges=grid.phi_edges, axis=grid.axis, warp=grid.warp)


class Draws(NamedTuple):
    """Samples of a lobe, sorted into the kinds the tests treat differently.

    Attributes
    ----------
    sample : BSDFSample
        The raw samples, leading axis ``n_samples``.
    delta : ndarray of bool
        Valid samples with the DELTA flag.
    failed : ndarray of bool
        Valid non-delta samples with pdf 0 (and weight 0).
    invalid : ndarray of bool
        Samples that break the ``BSDFSample`` contract: non-finite or negative pdf, weight or
        direction; a non-unit direction; or pdf 0 with a non-zero weight.
    """

    sample: BSDFSample
    delta: np.ndarray
    failed: np.ndarray
    invalid: np.ndarray

    @property
    def live(self) -> np.ndarray:
        """Samples with a direction density: valid, not delta, not failed."""
        return ~(self.delta | self.failed | self.invalid)


def draw_samples(lobe: Lobe, wo, n_samples: int, seed: int | np.random.Generator = 0) -> Draws:
    """Draw ``n_samples`` samples of ``lobe`` for every direction of ``wo`` and classify them.

    Parameters
    ----------
    lobe : Lobe
    wo : array_like (..., 3)
        Outgoing direction(s).
    n_samples : int
        Samples per direction, in [1, inf).
    seed : int or numpy.random.Generator
        Source of the uniforms ``u``, of shape ``(n_samples, *wo.shape[:-1], 3)``.

    Returns
    -------
    Draws
    """
    wo = _params.direction("wo", wo)
    n_samples = _integer("n_samples", n_samples, 1)
    return classify_samples(lobe, wo, np.random.default_rng(seed).random((n_samples,
                                                                         *wo.shape[:-1], 3)))


def classify_samples(lobe: Lobe, wo, u) -> Draws:
    """Call ``lobe.sample(wo, u)`` (in batches of ``BATCH`` along the first axis) and classify.

    Parameters
    ----------
    lobe : Lobe
    wo : array_like (..., 3)
        Outgoing direction(s), broadcast against ``u``.
    u : array_like (n, ..., 3)
        Uniforms in [0, 1); a single triple is treated as ``n = 1``.

    Returns
    -------
    Draws
        With arrays of the broadcast shape of ``wo`` and ``u``.
    """
    wo = _params.direction("wo", wo)
    u = np.atleast_2d(_params.uniforms("u", u, 3))
    try:
        u = np.broadcast_to(u, np.broadcast_shapes(u.shape, wo.shape))
    except ValueError as exc:
        raise ValueError(f"u has shape {u.shape} and wo {wo.shape}; they must broadcast") from exc
    step = max(1, BATCH // int(np.prod(u.shape[1:-1])))
    parts = [lobe.sample(np.broadcast_to(wo, u[i:i + step].shape), u[i:i + step])
             for i in range(0, u.shape[0], step)]
    sample = BSDFSample(*(np.concatenate(x) for x in zip(*parts, strict=True)))
    wi, weight, pdf, flags = sample
    is_delta = (np.asarray(flags) & Flags.DELTA) != 0
    finite = np.isfinite(pdf) & np.isfinite(weight).all(-1) & np.isfinite(wi).all(-1)
    with np.errstate(invalid="ignore"):
        unit = np.abs(np.linalg.norm(wi, axis=-1) - 1.0) <= _params.UNIT_TOLERANCE
        negative = (pdf < 0) | (weight < 0).any(-1)
    zero_pdf_weight = (pdf == 0) & (weight != 0).any(-1)
    invalid = ~finite | negative | zero_pdf_weight | ((is_delta | (pdf > 0)) & ~unit)
    return Draws(sample, is_delta & ~invalid, ~is_delta & (pdf == 0) & ~invalid, invalid)


def integrate_pdf(
    lobe: Lobe,
    wo: np.ndarray,
    grid: SphereGrid,
    tolerance: Callable[[np.ndarray], np.ndarray],
    *,
    guide: np.ndarray | None = None,
    max_evals: int = 20_000_000,
) -> tuple[CellIntegral, int]:
    """Integrate ``lobe.pdf(wo, .)`` over every cell of ``grid`` with ``integrate_cells``.

    Parameters
    ----------
    lobe : Lobe
        A lobe with scalar parameters.
    wo : ndarray (3,)
    grid : SphereGrid
    tolerance : callable
        Allowed absolute error per cell given the cell integrals (see ``integrate_cells``).
    guide : ndarray (G, 3), optional
        Sampled directions; in every cell they occupy, the first one at which the pdf is
        positive becomes a guard point of ``integrate_cells``, so that support the cubature
        nodes would miss is found.
    max_evals : int
        pdf evaluations allowed.

    Returns
    -------
    cells : CellIntegral
        Per-cell probabilities (flattened ring-major, as ``SphereGrid.locate``).
    n_bad_pdf : int
        pdf values that were negative or not finite (integrated as 0).
    """
    n_bad = 0

    def integrand(x):
        nonlocal n_bad
        density = lobe.pdf(np.broadcast_to(wo, (x.shape[0], 3)), grid.direction(x[:, 0], x[:, 1]))
        if density.shape != (x.shape[0],):
            raise ValueError(f"lobe.pdf returned shape {density.shape} for {x.shape[0]} "
                             "directions; the sphere tests need a lobe with scalar parameters")
        bad = ~np.isfinite(density) | (density < 0)
        n_bad += int(np.count_nonzero(bad))
        return np.where(bad, 0.0, density) * grid.jacobian(x[:, 0])

    guide = np.empty((0, 3)) if guide is None else guide
    occupied, first = np.unique(grid.locate(guide), return_index=True)
    positive = lobe.pdf(np.broadcast_to(wo, guide[first].shape), guide[first]) > 0
    t, phi, _ = grid.coordinates(guide[first][positive])
    lo, hi = grid.cell_bounds()
    cells = integrate_cells(integrand, lo, hi, tolerance, points=np.stack([t, phi], axis=-1),
                            point_cells=occupied[positive], max_evals=max_evals)
    return cells, n_bad


def _pooled_statistic(observed, expected):
    """Pearson's statistic after pooling bins with expectation below ``MIN_EXPECTED``.

    The pooled bin is merged into the smallest regular bin if its own expectation is still
    below ``MIN_EXPECTED``, and dropped if it is exactly empty. Returns
    ``(statistic, dof, n_pooled)``.
    """
    order = np.argsort(expected, kind="stable")
    observed, expected = observed[order].astype(np.float64), expected[order]
    small = expected < MIN_EXPECTED
    n_small = int(np.count_nonzero(small))
    pooled_o, pooled_e = observed[small].sum(), expected[small].sum()
    observed, expected = observed[~small], expected[~small]
    if n_small and pooled_e < MIN_EXPECTED and expected.size:
        observed[0] += pooled_o
        expected[0] += pooled_e
    elif pooled_e > 0:
        observed = np.append(observed, pooled_o)
        expected = np.append(expected, pooled_e)
    statistic = float(np.sum((observed - expected) ** 2 / expected)) if expected.size else 0.0
    return statistic, expected.size - 1, n_small


def _unit_axis(axis) -> np.ndarray:
    arr = _params.real("axis", axis)
    norm = np.linalg.norm(arr) if arr.shape == (3,) else 0.0
    if norm == 0.0:
        raise ValueError(f"axis = {axis!r} must be a non-zero 3-vector")
    return arr / norm


def _integer(name: str, value, lo: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < lo:
        raise ValueError(f"{name} = {value!r} must be an integer in [{lo}, inf)")
    return int(value)
