"""Chi-square goodness-of-fit test of a lobe's ``sample`` against its ``pdf`` on a sphere grid.

Public API
----------
``chi2_test``        the test for one ``wo``; returns a ``Chi2Result``.
``Chi2Result``       p-value, threshold, statistic, both histograms, integrated pdf mass, ...
``SphereGrid``       the (t, phi) grid about a pole, with warped rings.
``integrate_cells``  vectorised adaptive Genz–Malik cubature of a density over many 2-D cells.
``CellIntegral``     its result: per-cell estimate and error.
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
from adobe_bsdf.bsdf import Flags, Lobe

__all__ = [
    "Chi2Result",
    "CellIntegral",
    "SphereGrid",
    "chi2_test",
    "integrate_cells",
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
_W7 = np.repeat([-3816 / 19683, 980 / 6561, 1020 / 19683, 200 / 19683, 6859 / 78732], [1, 4, 4, 4, 4])
_W5 = np.repeat([-971 / 729, 245 / 486, 65 / 1458, 25 / 729, 0.0], [1, 4, 4, 4, 4])
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
        Characteristic angular radius of the lobe in radians, in (0, pi]; e.g. about
        ``2 alpha`` for a GGX reflection lobe, ``1 / sqrt(n)`` for a cosine power ``n``.
    peak : array_like (3,), optional
        Direction of the lobe's peak (e.g. the mirror direction). Default ``+z``.

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
        local = np.stack([sin_theta * np.cos(phi), sin_theta * np.sin(phi), np.cos(theta)], -1)
        return local @ self.frame

    def jacobian(self, t: np.ndarray) -> np.ndarray:
        """Solid angle per unit ``t`` per unit ``phi``: ``sin(theta') dtheta'/dt``."""
        return np.sin(np.pi * t**self.warp) * np.pi * self.warp * t ** (self.warp - 1.0)

    def locate(self, w: np.ndarray) -> np.ndarray:
        """Flat cell index (ring * n_phi + sector) of unit directions ``w`` ``(..., 3)``."""
        local = w @ self.frame.T
        theta = np.arctan2(np.hypot(local[..., 0], local[..., 1]), local[..., 2])
        t = (theta / np.pi) ** (1.0 / self.warp)
        ring = np.clip(np.searchsorted(self.t_edges, t, side="right") - 1, 0, self.n_theta - 1)
        if self.horizon_edge is not None:
            above = local[..., 2] > 0.0
            ring = np.where(above, np.minimum(ring, self.horizon_edge - 1),
                            np.maximum(ring, self.horizon_edge))
        phi = np.mod(np.arctan2(local[..., 1], local[..., 0]), 2.0 * np.pi)
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

    Parameters
    ----------
    integrand : callable
        ``f(x) -> (M,)`` for points ``x`` of shape ``(M, 2)``.
    lo, hi : ndarray (n_cells, 2)
        Lower and upper corners of the cells.
    tolerance : callable
        ``tol(values) -> (n_cells,)``: allowed absolute error per cell given the current
        estimates ``values`` ``(n_cells,)``.
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
    center, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    cell = np.arange(n_cells)
    value, error, split = _genz_malik(integrand, center, half)
    n_evals, n_rounds = _NODES.shape[0] * n_cells, 0
    while True:
        cell_value = np.bincount(cell, value, n_cells)
        cell_error = np.bincount(cell, error, n_cells)
        cell_tol = tolerance(cell_value)
        bad = cell_error > cell_tol
        if not bad.any() or n_rounds == max_rounds or n_evals >= max_evals:
            break
        share = cell_tol / np.bincount(cell, minlength=n_cells)
        chosen = np.flatnonzero(bad[cell] & (error > share[cell]))
        budget = (max_evals - n_evals) // (2 * _NODES.shape[0])
        if chosen.size > budget:
            chosen = chosen[np.argpartition(error[chosen], -budget)[-budget:]]
        keep = np.ones(value.size, dtype=bool)
        keep[chosen] = False
        child_half = half[chosen].copy()
        child_half[np.arange(chosen.size), split[chosen]] *= 0.5
        offset = np.zeros_like(child_half)
        offset[np.arange(chosen.size), split[chosen]] = child_half[np.arange(chosen.size),
                                                                  split[chosen]]
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
    return value, error, np.argmax(fourth, axis=1)


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
    finite; any sample in a cell whose expected count is below ``zero_count = 1e-3 alpha_c /
    (n_cells + 1)`` (so a correct lobe trips it with probability below ``alpha_c / 1000``).
    Too few bins to test (``dof < 1``) also fails.

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

    # -- histogram of the samples ---------------------------------------------------------
    u = np.random.default_rng(seed).random((n_samples, 3))
    parts = [lobe.sample(np.broadcast_to(wo, (min(BATCH, n_samples - i), 3)), u[i:i + BATCH])
             for i in range(0, n_samples, BATCH)]
    wi, weight, pdf, flags = (np.concatenate(x) for x in zip(*parts, strict=True))
    delta = (flags & Flags.DELTA) != 0
    failed = ~delta & (pdf == 0)
    invalid = _invalid_samples(wi, weight, pdf, delta)
    histogrammed = ~delta & ~failed & ~invalid
    observed = np.bincount(grid.locate(wi[histogrammed]), minlength=n_cells)
    n_delta, n_invalid = int(np.count_nonzero(delta & ~invalid)), int(np.count_nonzero(invalid))
    n_failed = int(np.count_nonzero(failed & ~invalid))
    if n_invalid:
        messages.append(f"{n_invalid} invalid samples (non-finite or negative weight or pdf, "
                        "bad direction, or pdf 0 with non-zero weight)")

    # -- expected counts --------------------------------------------------------------------
    bad_pdf = [0]

    def integrand(x):
        density = lobe.pdf(np.broadcast_to(wo, (x.shape[0], 3)), grid.direction(x[:, 0], x[:, 1]))
        if density.shape != (x.shape[0],):
            raise ValueError(f"lobe.pdf returned shape {density.shape} for {x.shape[0]} "
                             "directions; chi2_test needs a lobe with scalar parameters")
        bad = ~np.isfinite(density) | (density < 0)
        bad_pdf[0] += int(np.count_nonzero(bad))
        return np.where(bad, 0.0, density) * grid.jacobian(x[:, 0])

    def tolerance(prob):
        counts = n_samples * np.maximum(prob, 0.0)
        return (tau * counts / np.sqrt(np.maximum(counts, MIN_EXPECTED)) + zero_count) / n_samples

    lo, hi = grid.cell_bounds()
    cells = integrate_cells(integrand, lo, hi, tolerance, max_evals=max_evals)
    expected = n_samples * np.maximum(cells.value, 0.0)
    mass = float(cells.value.sum())
    if bad_pdf[0]:
        messages.append(f"pdf returned {bad_pdf[0]} negative or non-finite values")
    if not cells.converged:
        messages.append(f"pdf integration did not converge within {cells.n_evals} evaluations")

    # -- the test ---------------------------------------------------------------------------
    zero_hits = int(observed[expected < zero_count].sum())
    other_observed = n_samples - int(observed.sum()) - n_invalid
    other_expected = max(n_samples * (1.0 - mass), 0.0)
    if other_observed and other_expected < zero_count:
        zero_hits += other_observed
    if zero_hits:
        messages.append(f"{zero_hits} samples where the integrated pdf is ~0")
    statistic, dof, n_pooled = _pooled_statistic(np.append(observed, other_observed),
                                                 np.append(expected, other_expected))
    if dof < 1:
        messages.append("too few bins with expected counts >= 5 to test (dof < 1): "
                        "refine the grid about the lobe (see suggest_grid)")
    hard_failure = bool(n_invalid or bad_pdf[0] or zero_hits or dof < 1)
    p_value = 0.0 if hard_failure else float(stats.chi2.sf(statistic, dof))
    passed = not hard_failure and p_value >= significance
    if not hard_failure and not passed:
        messages.append("sampled directions do not follow the pdf")
    return Chi2Result(
        passed=passed, p_value=p_value, significance=significance, statistic=float(statistic),
        dof=dof, n_samples=n_samples, n_histogram=int(observed.sum()), n_delta=n_delta,
        n_failed=n_failed, n_invalid=n_invalid, n_zero_hits=zero_hits, n_bad_pdf=bad_pdf[0],
        n_pooled=n_pooled, pdf_mass=mass, integration_error=float(cells.error.sum()),
        integration_converged=cells.converged, n_evals=cells.n_evals,
        seconds=time.perf_counter() - start, message="; ".join(messages),
        observed=observed.reshape(grid.shape), expected=expected.reshape(grid.shape),
        theta_edges=grid.theta_edges, phi_edges=grid.phi_edges, axis=grid.axis, warp=grid.warp)


def _invalid_samples(wi, weight, pdf, delta):
    """Samples that break the ``BSDFSample`` contract."""
    finite = np.isfinite(pdf) & np.isfinite(weight).all(-1) & np.isfinite(wi).all(-1)
    with np.errstate(invalid="ignore"):
        unit = np.abs(np.linalg.norm(wi, axis=-1) - 1.0) <= _params.UNIT_TOLERANCE
        negative = (pdf < 0) | (weight < 0).any(-1)
    zero_pdf_weight = (pdf == 0) & (weight != 0).any(-1)
    live = delta | (pdf > 0)
    return ~finite | negative | zero_pdf_weight | (live & ~unit)


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
