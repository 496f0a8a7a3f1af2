"""Deterministic and Monte Carlo consistency checks of a lobe, each with its measured figures.

Public API
----------
``pdf_integral``            integral of ``pdf`` over the sphere against the non-delta probability.
``reciprocity_error``       (generalized) reciprocity f(wo, wi)/eta_o^2 = f(wi, wo)/eta_i^2.
``weight_consistency``      sample weight and pdf against ``eval`` and ``pdf`` at the sample.
``furnace``                 directional albedo against an expected value (white furnace).
``mc_albedo_consistency``   Monte Carlo albedo against quadrature albedo, in standard errors.

Every check returns a frozen dataclass with the measured figures and ``passed``; ``str()`` of a
result is a one-line summary (used by ``python -m adobe_bsdf check``).

Relative differences are ``|a - b| / max(|a|, |b|)``, 0 where both are 0, and infinite where
either is not finite, so a NaN can never pass.

References
----------
[Veach1997, §5.3] reciprocity of BSDFs with refraction: f(wo, wi)/eta_o^2 = f(wi, wo)/eta_i^2.
[Pharr2023] pbrt-v4, ``src/pbrt/bsdfs_test.cpp`` (energy conservation and sampling consistency
tests).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from adobe_bsdf import _params
from adobe_bsdf.bsdf import ALBEDO_METHODS, Flags, Lobe
from adobe_bsdf.validation.candidate import as_lobe
from adobe_bsdf.validation.chi2 import (
    SphereGrid,
    classify_samples,
    draw_samples,
    integrate_pdf,
    sidak_alpha,
)

__all__ = [
    "FurnaceResult",
    "McAlbedoResult",
    "PdfIntegralResult",
    "ReciprocityResult",
    "WeightConsistencyResult",
    "furnace",
    "mc_albedo_consistency",
    "pdf_integral",
    "reciprocity_error",
    "weight_consistency",
]

#: default relative tolerance of the deterministic identities (reciprocity, sample weights)
RTOL = 1e-8


def _verdict(passed: bool) -> str:
    return "pass" if passed else "FAIL"


def _relative_difference(a, b, atol: float = 0.0) -> np.ndarray:
    """``|a - b| / max(|a|, |b|, atol)``; 0 where ``a == b``; inf where either is not finite."""
    a, b = np.broadcast_arrays(np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64))
    finite = np.isfinite(a) & np.isfinite(b)
    a, b = np.where(finite, a, 0.0), np.where(finite, b, 0.0)
    diff = np.abs(a - b)
    scale = np.maximum(np.maximum(np.abs(a), np.abs(b)), atol)
    rel = np.divide(diff, scale, out=np.zeros_like(diff), where=diff > 0)
    return np.where(finite, rel, np.inf)


def _same_side(wo, wi, opposite: bool = False) -> np.ndarray:
    """Whether ``wo`` and ``wi`` lie strictly on the same (or opposite) side of the surface.

    Compares signs, not ``wo.z * wi.z``: that product underflows to 0 for subnormal cosines.
    """
    zo, zi = wo[..., 2], wi[..., 2]
    return (zo != 0) & (zi != 0) & ((np.signbit(zo) == np.signbit(zi)) != opposite)


def _max(values) -> float:
    values = np.asarray(values, dtype=np.float64)
    return float(values.max()) if values.size else 0.0


# -- integral of the pdf ---------------------------------------------------------------------
@dataclass(frozen=True)
class PdfIntegralResult:
    """Result of ``pdf_integral``.

    Attributes
    ----------
    passed : bool
        ``abs_error + integration_error <= tolerance`` and the pdf returned no negative or
        non-finite value.
    value : float
        Integral of ``pdf(wo, .)`` over the sphere.
    expected : float
        What it was compared with: the given value, or ``sampled_mass``.
    abs_error : float
        ``|value - expected|``.
    tolerance : float
        Allowed ``abs_error``: ``tol``, plus ``n_sigma`` standard errors when ``expected`` is
        estimated by sampling.
    integration_error : float
        Estimated absolute error of ``value``.
    integration_converged : bool
        Whether the cubature met its tolerance in every cell.
    sampled_mass : float
        Fraction of samples that carry a direction density (not delta, not failed, valid).
    sampled_error : float
        Standard error of ``sampled_mass``.
    n_bad_pdf : int
        Negative or non-finite pdf values met.
    n_evals : int
        pdf evaluations spent.
    """

    passed: bool
    value: float
    expected: float
    abs_error: float
    tolerance: float
    integration_error: float
    integration_converged: bool
    sampled_mass: float
    sampled_error: float
    n_bad_pdf: int
    n_evals: int

    def __str__(self) -> str:
        return (f"pdf integral {_verdict(self.passed)}: {self.value:.9f} vs {self.expected:.9f} "
                f"(|error| {self.abs_error:.2e}, tolerance {self.tolerance:.1e}, "
                f"cubature error {self.integration_error:.1e})")


def pdf_integral(
    lobe: Lobe,
    wo,
    *,
    expected: float | None = 1.0,
    tol: float = 1e-6,
    n_samples: int = 100_000,
    seed: int | np.random.Generator = 0,
    n_sigma: float = 4.0,
    n_theta: int = 32,
    n_phi: int = 64,
    axis=None,
    warp: float = 1.0,
    max_evals: int = 20_000_000,
) -> PdfIntegralResult:
    """Integral of ``lobe.pdf(wo, wi)`` over all ``wi`` on the sphere, by adaptive cubature.

    It should equal the probability that ``sample`` takes a non-delta branch and succeeds:
    1 for a lobe without delta branches whose samples never fail.

    Parameters
    ----------
    lobe : Lobe
        A lobe with scalar parameters.
    wo : array_like (3,)
        Outgoing direction.
    expected : float or None
        The probability to compare with, in [0, 1]; ``None`` compares with the fraction of
        ``n_samples`` samples that carry a density (for lobes whose samples can fail).
    tol : float
        Allowed absolute difference, in (0, 1]. The cubature is run to about ``tol / 50``.
    n_samples : int
        Samples drawn, in [1, inf): for ``sampled_mass`` and to guard the cubature against
        support it would miss (see ``integrate_cells``).
    seed : int or numpy.random.Generator
        Source of the sample uniforms.
    n_sigma : float
        Standard errors of ``sampled_mass`` added to the tolerance when ``expected`` is None,
        in [0, inf).
    n_theta, n_phi, axis, warp
        The cubature grid (see ``SphereGrid``; ``suggest_grid`` for narrow lobes).
    max_evals : int
        pdf evaluations allowed.

    Returns
    -------
    PdfIntegralResult
    """
    lobe = as_lobe(lobe)  # a library lobe, or any Candidate
    wo = _params.direction("wo", wo)
    if wo.shape != (3,):
        raise ValueError(f"wo has shape {wo.shape}; pdf_integral takes one direction of shape (3,)")
    if expected is not None:
        expected = float(_params.real("expected", expected, 0.0, 1.0))
    tol = float(_params.real("tol", tol, 0.0, 1.0, lo_open=True))
    n_sigma = float(_params.real("n_sigma", n_sigma, 0.0))
    grid = SphereGrid(n_theta, n_phi, axis, warp)
    draws = draw_samples(lobe, wo, n_samples, seed)
    n_cells = grid.n_theta * grid.n_phi

    def tolerance(values):
        return 1e-2 * tol * (np.abs(values) + 1.0 / n_cells)

    cells, n_bad = integrate_pdf(lobe, wo, grid, tolerance, guide=draws.sample.wi[draws.live],
                                 max_evals=max_evals)
    value, integration_error = float(cells.value.sum()), float(cells.error.sum())
    sampled = float(np.mean(draws.live))
    sampled_error = float(np.sqrt(sampled * (1.0 - sampled) / draws.live.size))
    allowed = tol if expected is not None else tol + n_sigma * sampled_error
    target = sampled if expected is None else expected
    abs_error = abs(value - target)
    return PdfIntegralResult(
        passed=bool(abs_error + integration_error <= allowed and not n_bad), value=value,
        expected=target, abs_error=abs_error, tolerance=allowed,
        integration_error=integration_error, integration_converged=cells.converged,
        sampled_mass=sampled, sampled_error=sampled_error, n_bad_pdf=n_bad,
        n_evals=cells.n_evals)


# -- reciprocity -----------------------------------------------------------------------------
@dataclass(frozen=True)
class ReciprocityResult:
    """Result of ``reciprocity_error``.

    Attributes
    ----------
    passed : bool
        ``max_error <= rtol``.
    max_error : float
        Largest relative difference between f(wo, wi)/eta_o^2 and f(wi, wo)/eta_i^2 over pairs
        and colour channels.
    rtol : float
        The tolerance.
    n_pairs, n_transmission : int
        Pairs checked, and how many of them are transmission pairs.
    worst_wo, worst_wi : ndarray (3,)
        The pair with the largest error.
    errors : ndarray (...)
        Per-pair error (maximum over channels).
    """

    passed: bool
    max_error: float
    rtol: float
    n_pairs: int
    n_transmission: int
    worst_wo: np.ndarray = field(repr=False)
    worst_wi: np.ndarray = field(repr=False)
    errors: np.ndarray = field(repr=False)

    def __str__(self) -> str:
        return (f"reciprocity {_verdict(self.passed)}: max relative error {self.max_error:.2e} "
                f"(rtol {self.rtol:.0e}) over {self.n_pairs} pairs, "
                f"{self.n_transmission} transmission")


def reciprocity_error(
    lobe: Lobe,
    wo,
    wi,
    eta_o=None,
    eta_i=None,
    *,
    rtol: float = RTOL,
    atol: float = 0.0,
) -> ReciprocityResult:
    """Relative error of the (generalized) reciprocity of ``lobe.eval`` over pairs of directions.

    Checks f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2, where eta_o and eta_i are the refractive
    indices on the sides of ``wo`` and ``wi`` ([Veach1997, §5.3]; ``design.md``); for
    reflection pairs, or lobes without an interface, this is plain reciprocity.

    Parameters
    ----------
    lobe : Lobe
    wo, wi : array_like (..., 3)
        Pairs of unit directions (broadcast).
    eta_o, eta_i : array_like (...), optional
        Refractive index on the side of ``wo`` and of ``wi`` per pair, in (0, inf); both or
        neither. If neither is given and ``lobe`` has an attribute ``eta`` (n_below / n_above,
        as ``Dielectric``), the side above (z >= 0) has index 1 and the side below ``eta``
        (per colour channel, ``(..., 3)``, if the lobe's ``eta_per_channel`` is true, as
        ``Dispersive``); otherwise all indices are 1.
    rtol : float
        Allowed relative error, in [0, inf).
    atol : float
        Values below which differences are measured absolutely: the relative error is
        ``|a - b| / max(|a|, |b|, atol)``; in [0, inf).

    Returns
    -------
    ReciprocityResult
    """
    lobe = as_lobe(lobe)  # a library lobe, or any Candidate
    wo = _params.direction("wo", wo)
    wi = _params.direction("wi", wi)
    try:
        wo, wi = np.broadcast_arrays(wo, wi)
    except ValueError as exc:
        raise ValueError(f"wo has shape {wo.shape} and wi {wi.shape}; they must broadcast") from exc
    rtol = float(_params.real("rtol", rtol, 0.0))
    atol = float(_params.real("atol", atol, 0.0))
    if (eta_o is None) != (eta_i is None):
        raise ValueError(f"eta_o = {eta_o!r}, eta_i = {eta_i!r}: give both or neither")
    if eta_o is None:
        eta = getattr(lobe, "eta", None)
        eta = 1.0 if eta is None else np.asarray(eta, dtype=np.float64)
        channel = getattr(lobe, "eta_per_channel", False)
        eta_o = np.where(wo[..., 2:] >= 0.0 if channel else wo[..., 2] >= 0.0, 1.0, eta)
        eta_i = np.where(wi[..., 2:] >= 0.0 if channel else wi[..., 2] >= 0.0, 1.0, eta)
    else:
        eta_o = _params.real("eta_o", eta_o, 0.0, np.inf, lo_open=True)
        eta_i = _params.real("eta_i", eta_i, 0.0, np.inf, lo_open=True)
        channel = False
    eta_o, eta_i = ((e if channel else e[..., None]) for e in (np.asarray(eta_o),
                                                                np.asarray(eta_i)))
    forward = lobe.eval(wo, wi) / eta_o**2
    backward = lobe.eval(wi, wo) / eta_i**2
    errors = _relative_difference(forward, backward, atol).max(axis=-1)
    wo, wi = (np.broadcast_to(w, (*errors.shape, 3)) for w in (wo, wi))
    worst = np.unravel_index(int(np.argmax(errors)), errors.shape) if errors.size else ()
    max_error = _max(errors)
    return ReciprocityResult(
        passed=max_error <= rtol, max_error=max_error, rtol=rtol, n_pairs=int(errors.size),
        n_transmission=int(np.count_nonzero(_same_side(wo, wi, opposite=True))),
        worst_wo=wo[worst], worst_wi=wi[worst], errors=errors)


# -- sample weights --------------------------------------------------------------------------
@dataclass(frozen=True)
class WeightConsistencyResult:
    """Result of ``weight_consistency``.

    Attributes
    ----------
    passed : bool
        Both maximum errors are within ``rtol``, no sample is invalid and no flag contradicts
        the geometry.
    max_weight_error : float
        Largest relative difference between ``weight`` and ``eval(wo, wi) |wi.z| / pdf(wo, wi)``.
    max_pdf_error : float
        Largest relative difference between the sample's ``pdf`` and ``lobe.pdf(wo, wi)``.
    rtol : float
        The tolerance.
    n_samples, n_checked : int
        Samples drawn, and non-delta, non-failed, valid samples checked.
    n_delta, n_failed, n_invalid : int
        See ``Draws``.
    n_flag_mismatch : int
        Checked samples whose REFLECTION / TRANSMISSION flag disagrees with
        ``sign(wo.z * wi.z)``.
    worst_wo, worst_wi : ndarray (3,)
        The sample with the largest weight error (NaN if none was checked).
    cause : str
        The likely cause of a failure where a simple one fits (``weight_cause``), else "".
    """

    passed: bool
    max_weight_error: float
    max_pdf_error: float
    rtol: float
    n_samples: int
    n_checked: int
    n_delta: int
    n_failed: int
    n_invalid: int
    n_flag_mismatch: int
    worst_wo: np.ndarray = field(repr=False)
    worst_wi: np.ndarray = field(repr=False)
    cause: str = ""

    def __str__(self) -> str:
        text = (f"sample weights {_verdict(self.passed)}: max relative error weight "
                f"{self.max_weight_error:.2e}, pdf {self.max_pdf_error:.2e} (rtol "
                f"{self.rtol:.0e}) over {self.n_checked} samples; {self.n_invalid} invalid, "
                f"{self.n_flag_mismatch} flag mismatches")
        if not self.passed and np.all(np.isfinite(self.worst_wi)):
            text += (f"; worst at wo = {np.round(self.worst_wo, 4).tolist()}, wi = "
                     f"{np.round(self.worst_wi, 4).tolist()}")
        return f"{text}; likely cause: {self.cause}" if self.cause else text


def weight_cause(weight, expected, cos_i, sample_pdf, pdf, rtol: float) -> str:
    """The likely cause of sample weights that differ from f |cos theta_i| / pdf
    (``expected``, from the lobe's own ``eval`` and ``pdf``), where a simple one fits:
    ``eval`` returning f |cos theta_i| (the weights then match with f / |cos theta_i|),
    a sample pdf that differs from ``pdf()``, or a constant factor; else ""."""
    weight, expected = np.asarray(weight, float), np.asarray(expected, float)
    cos_i = np.asarray(cos_i, float).reshape(len(weight), -1)
    with np.errstate(divide="ignore", invalid="ignore"):
        big = (expected > 0) & np.isfinite(weight) & np.isfinite(expected)
        if not big.any():
            return ""
        folded = np.abs(weight * cos_i - expected)[big] / expected[big]
        if np.median(folded) < 1e-3:
            return ("eval has the cosine folded in: the weights are f |cos theta_i| / pdf "
                    "with f = eval / |cos theta_i|")
        pdf_error = np.abs(np.asarray(sample_pdf) - np.asarray(pdf)) / np.maximum(
            np.asarray(pdf), 1e-300)
        if np.median(pdf_error) > rtol:
            return "sample()'s pdf differs from pdf() at the sampled directions"
        ratio = np.median((weight / expected)[big])
        if np.median(np.abs((weight / expected)[big] - ratio)) < 1e-3 * abs(ratio):
            return f"the weights are {ratio:.4g} x f |cos theta_i| / pdf everywhere"
    return ""


def weight_consistency(
    lobe: Lobe,
    wo,
    n_samples: int = 100_000,
    seed: int | np.random.Generator = 0,
    *,
    u=None,
    rtol: float = RTOL,
) -> WeightConsistencyResult:
    """Check every sample against the lobe's own ``eval`` and ``pdf`` at the sampled direction.

    For each sample that is not delta, not failed and valid: ``weight`` should equal
    ``eval(wo, wi) |wi.z| / pdf(wo, wi)`` and the sample's ``pdf`` should equal
    ``pdf(wo, wi)``; its flags should say REFLECTION exactly when ``wo.z wi.z > 0``.

    Parameters
    ----------
    lobe : Lobe
    wo : array_like (..., 3)
        Outgoing direction(s).
    n_samples : int
        Samples per direction, in [1, inf) (ignored when ``u`` is given).
    seed : int or numpy.random.Generator
        Source of the uniforms (ignored when ``u`` is given).
    u : array_like (n, ..., 3), optional
        Explicit uniforms in [0, 1), e.g. edge cases from ``strategies.uniform_triples``.
    rtol : float
        Allowed relative difference, in [0, inf).

    Returns
    -------
    WeightConsistencyResult
    """
    lobe = as_lobe(lobe)  # a library lobe, or any Candidate
    wo = _params.direction("wo", wo)
    rtol = float(_params.real("rtol", rtol, 0.0))
    draws = draw_samples(lobe, wo, n_samples, seed) if u is None else classify_samples(lobe, wo, u)
    s, live = draws.sample, draws.live
    wo_live, wi_live = np.broadcast_to(wo, s.wi.shape)[live], s.wi[live]
    pdf = lobe.pdf(wo_live, wi_live)
    with np.errstate(divide="ignore", invalid="ignore"):
        # |wi.z| / pdf first: a subnormal cosine times f underflows where the ratio does not
        weight = lobe.eval(wo_live, wi_live) * (np.abs(wi_live[:, 2:]) / pdf[:, None])
    weight_errors = _relative_difference(s.weight[live], weight).max(axis=-1, initial=0.0)
    pdf_errors = _relative_difference(s.pdf[live], pdf)
    flags = np.asarray(s.flags)[live]
    reflection = _same_side(wo_live, wi_live)
    says_reflection = (flags & Flags.REFLECTION) != 0
    says_transmission = (flags & Flags.TRANSMISSION) != 0
    mismatch = (says_reflection != reflection) | (says_transmission == reflection)
    n_mismatch, n_invalid = int(np.count_nonzero(mismatch)), int(np.count_nonzero(draws.invalid))
    max_weight, max_pdf = _max(weight_errors), _max(pdf_errors)
    worst = int(np.argmax(weight_errors)) if weight_errors.size else None
    nan3 = np.full(3, np.nan)
    passed = bool(max_weight <= rtol and max_pdf <= rtol and not n_mismatch and not n_invalid)
    cause = "" if passed else weight_cause(s.weight[live], weight, np.abs(wi_live[:, 2:]),
                                           s.pdf[live], pdf, rtol)
    return WeightConsistencyResult(
        passed=passed, cause=cause,
        max_weight_error=max_weight, max_pdf_error=max_pdf, rtol=rtol,
        n_samples=int(live.size), n_checked=int(np.count_nonzero(live)),
        n_delta=int(np.count_nonzero(draws.delta)), n_failed=int(np.count_nonzero(draws.failed)),
        n_invalid=n_invalid, n_flag_mismatch=n_mismatch,
        worst_wo=nan3 if worst is None else wo_live[worst],
        worst_wi=nan3 if worst is None else wi_live[worst])


# -- albedo ----------------------------------------------------------------------------------
@dataclass(frozen=True)
class FurnaceResult:
    """Result of ``furnace``.

    Attributes
    ----------
    passed : bool
        ``abs_error <= tol``.
    method : str
        The albedo method used.
    abs_error, rel_error : float
        Largest absolute and relative difference from the expected value.
    estimated_error : float
        Largest error estimate the lobe reported with its albedo.
    tol : float
        The tolerance on ``abs_error``.
    value, expected : ndarray (..., 3)
        The albedo and the expected value.
    """

    passed: bool
    method: str
    abs_error: float
    rel_error: float
    estimated_error: float
    tol: float
    value: np.ndarray = field(repr=False)
    expected: np.ndarray = field(repr=False)

    def __str__(self) -> str:
        return (f"furnace ({self.method}) {_verdict(self.passed)}: |E - expected| = "
                f"{self.abs_error:.2e} (tol {self.tol:.0e}), lobe's error estimate "
                f"{self.estimated_error:.1e}")


def furnace(
    lobe: Lobe,
    wo,
    expected,
    method: str = "quadrature",
    tol: float = 1e-6,
    **albedo_options,
) -> FurnaceResult:
    """Compare ``lobe.albedo(wo, method=method)`` with an expected albedo.

    With ``expected = 1`` and a lossless lobe this is the white-furnace test.

    Parameters
    ----------
    lobe : Lobe
    wo : array_like (..., 3)
        Outgoing direction(s).
    expected : array_like
        Expected energy albedo, broadcast against ``(..., 3)``.
    method : {"quadrature", "mc", "table"}
        Passed to ``albedo``.
    tol : float
        Allowed absolute difference, in [0, inf).
    **albedo_options
        Further keywords of ``albedo`` (``tol``, ``n_samples``, ``rng``).

    Returns
    -------
    FurnaceResult
    """
    lobe = as_lobe(lobe)  # a library lobe, or any Candidate
    method = _params.choice("method", method, ALBEDO_METHODS)
    tol = float(_params.real("tol", tol, 0.0))
    value, error = lobe.albedo(wo, method=method, return_error=True, **albedo_options)
    expected = _params.real("expected", expected)
    try:
        expected = np.broadcast_to(expected, np.shape(value))
    except ValueError as exc:
        raise ValueError(f"expected has shape {expected.shape}; it must broadcast to the albedo's "
                         f"shape {np.shape(value)}") from exc
    diff = _relative_difference(value, expected)
    abs_error = _max(np.where(np.isfinite(value), np.abs(value - expected), np.inf))
    return FurnaceResult(
        passed=abs_error <= tol, method=method, abs_error=abs_error, rel_error=_max(diff),
        estimated_error=_max(error), tol=tol, value=value, expected=expected)


@dataclass(frozen=True)
class McAlbedoResult:
    """Result of ``mc_albedo_consistency``.

    Attributes
    ----------
    passed : bool
        ``max_z <= threshold``.
    max_z : float
        Largest ``max(|mc - quadrature| - rtol max(|mc|, |quadrature|), 0) /
        sqrt(mc_error^2 + quadrature_error^2)`` over directions and channels (0/0 counts as 0).
    threshold : float
        Two-sided normal quantile of the Šidák-corrected level over all compared values.
    mc, mc_error, quadrature, quadrature_error : ndarray (..., 3)
        The two albedos and their error estimates (one standard error for ``mc``).
    """

    passed: bool
    max_z: float
    threshold: float
    mc: np.ndarray = field(repr=False)
    mc_error: np.ndarray = field(repr=False)
    quadrature: np.ndarray = field(repr=False)
    quadrature_error: np.ndarray = field(repr=False)

    def __str__(self) -> str:
        return (f"MC vs quadrature albedo {_verdict(self.passed)}: max |z| = {self.max_z:.2f} "
                f"(threshold {self.threshold:.2f})")


def mc_albedo_consistency(
    lobe: Lobe,
    wo,
    *,
    n_samples: int = 100_000,
    seed: int | np.random.Generator = 0,
    alpha: float = 0.01,
    n_tests: int = 1,
    rtol: float = 1e-9,
) -> McAlbedoResult:
    """Check that ``albedo(method="mc")`` agrees with ``albedo(method="quadrature")``.

    The Monte Carlo estimate averages the sample weights, the quadrature integrates ``eval``
    in direction space (plus the delta branches' closed-form energy); they agree within their
    standard errors when ``sample`` and ``eval`` describe the same energy.

    Parameters
    ----------
    lobe : Lobe
    wo : array_like (..., 3)
        Outgoing direction(s).
    n_samples : int
        Monte Carlo samples per direction, in [2, inf).
    seed : int or numpy.random.Generator
        Passed to ``albedo`` as ``rng``.
    alpha : float
        Family-wise significance level, in (0, 1); corrected (Šidák) over ``n_tests`` times the
        number of compared values.
    n_tests : int
        Number of such checks in the family, in [1, inf).
    rtol : float
        Relative differences up to ``rtol`` count as 0, in [0, inf): the rounding error of a
        zero-variance estimate (a lobe whose weights are constant, as Lambert) is not noise.

    Returns
    -------
    McAlbedoResult
    """
    lobe = as_lobe(lobe)  # a library lobe, or any Candidate
    rtol = float(_params.real("rtol", rtol, 0.0))
    mc, mc_error = lobe.albedo(wo, method="mc", n_samples=n_samples, rng=seed, return_error=True)
    quad, quad_error = lobe.albedo(wo, method="quadrature", return_error=True)
    mc, quad = np.broadcast_arrays(mc, quad)
    level = sidak_alpha(alpha, n_tests * mc.size)
    threshold = float(stats.norm.isf(level / 2.0))
    excess = np.maximum(np.abs(mc - quad) - rtol * np.maximum(np.abs(mc), np.abs(quad)), 0.0)
    excess = np.where(np.isfinite(excess), excess, np.inf)
    sigma = np.hypot(mc_error, quad_error)
    z = np.divide(excess, sigma, out=np.where(excess > 0, np.inf, 0.0), where=sigma > 0)
    max_z = _max(z)
    return McAlbedoResult(
        passed=max_z <= threshold, max_z=max_z, threshold=threshold, mc=mc, mc_error=mc_error,
        quadrature=quad, quadrature_error=quad_error)
