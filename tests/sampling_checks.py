"""Shared assertions of the lobes' and materials' sampling and energy tests."""

import warnings

import numpy as np

from adobe_bsdf.validation import checks
from adobe_bsdf.validation.chi2 import chi2_test
from tests.tolerances import CHI2_ALPHA, WEIGHT


def assert_sampling_matches(lobe, cos_theta, azimuth, seed, n_tests, n_samples=300_000):
    """At wo of ``cos_theta`` and ``azimuth``: the chi-square of ``sample`` against ``pdf``
    passes (p above the Šidák-corrected CHI2_ALPHA for ``n_tests`` tests), and every sample's
    weight is f |cos| / pdf."""
    s = np.sqrt(1.0 - cos_theta**2)
    wo = np.array([s * np.cos(azimuth), s * np.sin(azimuth), cos_theta])
    result = chi2_test(lobe, wo, n_samples=n_samples, seed=seed, alpha=CHI2_ALPHA,
                       n_tests=n_tests)
    assert result.passed, str(result)
    weights = checks.weight_consistency(lobe, wo, n_samples=20_000, rtol=WEIGHT)
    assert weights.passed, weights


def assert_no_energy_gain(material, wo, bound, context=None, mc_samples=40_000):
    """The albedo at ``wo`` (quadrature of eval plus the delta branches, energy convention) is
    at most ``bound``; where the quadrature reports a lobe narrower than its grid resolves
    (a warning about its guard samples), Monte Carlo with 5 standard errors of slack."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        E, sigma = material.albedo(wo, tol=1e-5), 0.0
    if any("guard samples" in str(w.message) for w in caught):
        E, sigma = material.albedo(wo, method="mc", n_samples=mc_samples, return_error=True)
    assert np.all(E <= bound + 5.0 * sigma), (context, E)
