"""``TintedRefraction``: a rough dielectric whose refraction is tinted, f = f_R + t f_T
(OpenPBR's transmission_color at depth 0). Expected values: the exact Fresnel of a smooth
interface, the untinted lobe, and linearity in the tint."""

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.lobes import DielectricMS
from adobe_bsdf.lobes.tinted_refraction import TintedRefraction
from adobe_bsdf.materials.openpbr import OpenPBRSurface
from adobe_bsdf.validation import checks
from tests.sampling_checks import assert_sampling_matches

TINT = np.array([0.3, 0.7, 1.0])
M = np.array([1.0, 1.0, -1.0])


def _wo(mu, phi=0.5):
    mu = np.asarray(mu, dtype=np.float64)
    s = np.sqrt((1.0 - mu) * (1.0 + mu))
    return np.stack([s * np.cos(phi), s * np.sin(phi), mu], axis=-1)


def test_reflection_is_the_lobe_and_refraction_is_tinted():
    glass = DielectricMS(1.5, 0.3, 0.2)
    tinted = TintedRefraction(glass, TINT)
    wo, wi = ab.frame.normalize(np.random.default_rng(1).normal(size=(2, 3000, 3)))
    wo[:5, 2], wi[:5, 2] = 1e-200, -1e-200  # across, though the product underflows to 0
    wo, wi = ab.frame.normalize(wo), ab.frame.normalize(wi)
    across = (np.sign(wo[:, 2]) * np.sign(wi[:, 2]) < 0)[:, None]
    np.testing.assert_array_equal(tinted.eval(wo, wi),
                                  np.where(across, glass.eval(wo, wi) * TINT, glass.eval(wo, wi)))
    np.testing.assert_array_equal(tinted.pdf(wo, wi), glass.pdf(wo, wi))
    np.testing.assert_array_equal(TintedRefraction(glass, 1.0).eval(wo, wi), glass.eval(wo, wi))


@pytest.mark.parametrize("eta", [1.5, 1 / 1.33])
def test_smooth_tinted_glass_is_f_plus_t_one_minus_f(eta):
    """E = F + t (1 - F) from either side, F the exact Fresnel (1 under total internal
    reflection), by quadrature (delta branches) and by the tables."""
    tinted = TintedRefraction(DielectricMS(eta, 0.0), TINT)
    mu = np.array([1.0, 0.7, 0.3, 0.05])
    wo = np.concatenate([_wo(mu), _wo(mu) * M])
    F = ab.fresnel.dielectric(np.concatenate([mu, -mu]), eta)[:, None]
    expected = F + TINT * (1.0 - F)
    np.testing.assert_allclose(tinted.albedo(wo), expected, rtol=1e-12)
    np.testing.assert_allclose(tinted.albedo(wo, method="table"), expected, rtol=1e-12)


def test_rough_energy_is_linear_in_the_tint_and_the_table_agrees():
    """E(t) = E(0) + t (E(1) - E(0)) (quadrature), and the table's split matches within the
    tables' 2e-3."""
    glass = DielectricMS(1.5, 0.35)
    wo = np.concatenate([_wo([0.9, 0.4]), _wo([0.9, 0.4]) * M])
    E0 = TintedRefraction(glass, 0.0).albedo(wo, tol=1e-7)
    E1 = glass.albedo(wo, tol=1e-7)
    Et = TintedRefraction(glass, TINT).albedo(wo, tol=1e-7)
    np.testing.assert_allclose(Et, E0 + TINT * (E1 - E0), atol=5e-6)
    np.testing.assert_allclose(TintedRefraction(glass, TINT).albedo(wo, method="table"), Et,
                               atol=2e-3)
    assert np.all(Et <= 1.0 + 1e-5)


@pytest.mark.parametrize("cos_theta", [0.8, -0.5])
def test_sampling(cos_theta):
    assert_sampling_matches(TintedRefraction(DielectricMS(1.5, 0.3), TINT), cos_theta, 0.2,
                            seed=6, n_tests=2)


def test_generalized_reciprocity():
    lobe = TintedRefraction(DielectricMS(1.5, 0.4), TINT)
    wo, wi = ab.frame.normalize(np.random.default_rng(2).normal(size=(2, 300, 3)))
    for a, b in zip(wo, wi, strict=True):
        result = checks.reciprocity_error(lobe, a, b, rtol=1e-10)
        assert result.passed, result


def test_openpbr_transmission_colour_at_depth_zero():
    """The bulk translucent base tints its refraction; nothing warns any more."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = OpenPBRSurface(transmission_weight=1.0, transmission_color=TINT,
                           specular_roughness=0.0)
    wo = _wo(np.array([0.8]))
    F = ab.fresnel.dielectric(0.8, 1.5)
    np.testing.assert_allclose(m.albedo(wo)[0], F + TINT * (1 - F), rtol=1e-12)


def test_bad_input():
    with pytest.raises(ValueError, match="lobe"):
        TintedRefraction(ab.lobes.Lambert(0.5), 0.5)
    with pytest.raises(ValueError, match="tint"):
        TintedRefraction(DielectricMS(1.5, 0.3), 1.5)
