"""Shared assertion of the lobes' sampling tests."""

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
