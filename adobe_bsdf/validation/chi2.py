"""Chi-square goodness-of-fit test of a lobe's ``sample`` against its ``pdf`` on a sphere grid.

Public API
----------
``chi2_test``        the test for one ``wo``; returns a ``Chi2Result``.
``Chi2Result``       p-value, threshold, statistic, both histograms, integrated pdf mass, ...
``SphereGrid``       the (t, phi) grid about a pole, with warped rings (from
                     ``adobe_bsdf.quadrature``, re-exported).
``integrate_cells``  vectorised adaptive Genz–Malik cubature over many 2-D cells (likewise).
``CellIntegral``     its result: per-cell estimate and error (likewise).
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
[Jakob2022] Mitsuba 3, ``src/python/python/chi2.py`` (``ChiSquareTest``); [Pharr2023]
pbrt-v4, ``src/pbrt/bsdfs_test.cpp`` (``ChiSquareTest``).
[GenzMalik1980] adaptive cubature of the expected counts.
[Sidak1967] the correction for a family of tests.
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
from adobe_bsdf.quadrature import (
    BATCH,
    WARP_RANGE,
    CellIntegral,
    SphereGrid,
    _unit_axis,
    integrate_cells,
)
from adobe_bsdf.validation.candidate import as_lobe

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
    n_tests = _params.integer("n_tests", n_tests, 1)
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
    lobe = as_lobe(lobe, needs=("pdf", "sample"))  # a library lobe, or any sampler
    start = time.perf_counter()
    wo = _params.direction("wo", wo)
    if wo.shape != (3,):
        raise ValueError(f"wo has shape {wo.shape}; chi2_test takes one direction of shape (3,)")
    n_samples = _params.integer("n_samples", n_samples, 1)
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
        messages.append(
            f"sampled directions do not follow the pdf: p = {p_value:.3g} is below "
            f"{significance:.3g}, the threshold of a family of "
            f"{n_tests} test{'s' if n_tests > 1 else ''} at a false-alarm rate of {alpha:g} "
            f"(a correct sampler fails this way with probability {alpha:g}; another seed "
            "tells a false alarm from a fault, which fails again)")
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
    n_samples = _params.integer("n_samples", n_samples, 1)
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
