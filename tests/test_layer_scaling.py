"""``Layer(scaling="reciprocal")``: the reciprocal albedo scaling [Andersson2023, §Layering],
f = c f_top + ((1 - c) + c C (1 - E_top(wi)) (1 - E_top(wo))) f_base, and its normalisation C
(``composition.reciprocal_normalisation``)."""

import functools

import numpy as np
import pytest
from hypothesis import given, settings

import adobe_bsdf as ab
from adobe_bsdf.composition import Layer
from adobe_bsdf.lobes import Conductor, ConductorMS, Dielectric, DielectricReflection, Lambert
from adobe_bsdf.validation import checks
from adobe_bsdf.validation import strategies as vs
from tests.sampling_checks import assert_sampling_matches

#: (coat eta, coat alpha): smooth, glossy and rough coats of low and high index
COATS = [(1.3, 0.0), (1.5, 0.05), (1.5, 0.3), (2.0, 0.8)]
#: white furnace of a form that promises it: 1 +- 2e-3
FURNACE_TOL = 2e-3
COSINES = np.array([1.0, 0.7, 0.3, 0.1, 0.02])


def _wo(cosines):
    return np.stack([np.sqrt(1.0 - cosines**2), np.zeros_like(cosines), cosines], -1)


@functools.cache
def _layer(eta, alpha, base="white", coverage=1.0):
    bases = {"white": Lambert(1.0), "coloured": Lambert((0.9, 0.5, 0.2)),
             "glossy": Conductor(0.3, fresnel=ab.fresnel.F82Tint((0.9, 0.6, 0.3), 1.0))}
    return Layer(DielectricReflection(eta, alpha), bases[base], coverage, scaling="reciprocal")


def _average_top_albedo(top, n=96):
    """E_avg = 2 int E_top(mu) mu d mu by Gauss–Legendre of the top's table albedo."""
    x, w = np.polynomial.legendre.leggauss(n)
    mu = 0.5 * (x + 1.0)
    return float(np.sum(w * mu * top._top_albedo(_wo(mu))[:, 0]))


@pytest.mark.parametrize(("eta", "alpha"), COATS)
def test_normalisation_over_lambert_is_the_closed_form(eta, alpha):
    """Over a Lambertian base of albedo rho, I(wo) = rho (1 - E_avg) and E_base = rho at every
    wo, so C = 1 / (1 - E_avg) in every channel, whatever rho."""
    layer = _layer(eta, alpha, "coloured")
    C, error = layer.normalisation
    expected = np.full(3, 1.0 / (1.0 - _average_top_albedo(layer.top)))
    assert np.all(np.abs(C - expected) <= 5.0 * error + 1e-6 * expected), (C, expected, error)


@pytest.mark.parametrize(("eta", "alpha"), COATS)
@pytest.mark.parametrize("coverage", [1.0, 0.4])
def test_white_furnace_over_lambert(eta, alpha, coverage):
    layer = _layer(eta, alpha, "white", coverage)
    E = layer.albedo(_wo(COSINES), tol=1e-6)
    np.testing.assert_allclose(E, 1.0, rtol=0, atol=FURNACE_TOL)


@pytest.mark.parametrize(("eta", "alpha"), [(1.5, 0.05), (2.0, 0.5)])
@pytest.mark.parametrize("base_alpha", [0.05, 0.5])
def test_never_gains_over_a_white_glossy_base(eta, alpha, base_alpha):
    """C = 1 / max I(wo): over a white multiple-scattering conductor the layer loses energy
    where I(wo) is below its maximum, and never gains (MC, 5 sigma)."""
    layer = Layer(DielectricReflection(eta, alpha), ConductorMS(base_alpha), scaling="reciprocal")
    E, sigma = layer.albedo(_wo(COSINES), method="mc", n_samples=40_000, rng=3,
                            return_error=True)
    assert np.all(E <= 1.0 + 1e-3 + 5.0 * sigma), (E, sigma)
    assert np.all(E >= 0.75), E  # and keeps most of it: not a vanishing C


@settings(max_examples=200, deadline=None)
@given(pair=vs.direction_pairs("reflection"))
def test_reciprocity(pair):
    """f(wo, wi) = f(wi, wo) to 1e-8 (relative), coloured Lambert and glossy bases."""
    for layer in (_layer(1.5, 0.3, "coloured", 0.7), _layer(2.0, 0.05, "glossy")):
        result = checks.reciprocity_error(layer, *pair, rtol=1e-8)
        assert result.passed, result


def test_the_albedo_form_is_not_reciprocal():
    """The default form's f(wo, wi) - f(wi, wo) = c t t (E_top(wi) - E_top(wo)) f_base: what
    the reciprocal form removes."""
    top, base = DielectricReflection(1.5, 0.3), Lambert((0.9, 0.5, 0.2))
    wo, wi = _wo(np.array([0.9])), _wo(np.array([0.1])) * np.array([-1.0, 1.0, 1.0])
    f = Layer(top, base)
    difference = f.eval(wo, wi) - f.eval(wi, wo)
    expected = (top._top_albedo(wi) - top._top_albedo(wo)) * base.eval(wo, wi)
    np.testing.assert_allclose(difference, expected, rtol=1e-10)
    assert np.all(np.abs(difference) > 1e-3)


CHI2_CASES = [("coloured", 0.9), ("coloured", 0.2), ("glossy", 0.6)]


@pytest.mark.parametrize(("base", "cos_theta"), CHI2_CASES)
def test_chi2_and_sample_weights(base, cos_theta):
    assert_sampling_matches(_layer(1.5, 0.3, base, 0.8), cos_theta, 0.2,
                            CHI2_CASES.index((base, cos_theta)), len(CHI2_CASES))


def test_finite_at_the_extremes():
    """Smooth and roughest coats, index 1 (E_top = 0), a black base, grazing and subnormal
    cosines: finite, non-negative eval and pdf."""
    rng = np.random.default_rng(0)
    wo, wi = ab.frame.normalize(rng.normal(size=(2, 2000, 3)))
    wo[:4] = [[1.0, 0.0, 5e-324], [1.0, 0.0, 1e-300], [0.0, 0.0, 1.0], [1.0, 0.0, 1e-8]]
    wo = ab.frame.normalize(wo)
    for top, base in ((DielectricReflection(1.5, 0.0), Lambert(1.0)),
                      (DielectricReflection(1.0, 0.5), Lambert(0.5)),
                      (DielectricReflection(3.0, 1.0), Lambert(0.0)),
                      (DielectricReflection(1.5, 0.3), Dielectric(1.5, 0.2))):
        layer = Layer(top, base, scaling="reciprocal")
        f, pdf = layer.eval_pdf(wo, wi)
        assert np.all(np.isfinite(f)) and np.all(f >= 0.0)
        assert np.all(np.isfinite(pdf)) and np.all(pdf >= 0.0)


def test_bad_input():
    top, base = DielectricReflection(1.5, 0.3), Lambert(0.5)
    with pytest.raises(ValueError, match="scaling = 'physical'"):
        Layer(top, base, scaling="physical")
    with pytest.raises(ValueError, match="scaling = 'reciprocal' with base"):
        Layer(top, Lambert(np.full((4, 3), 0.5)), scaling="reciprocal")
    with pytest.raises(ValueError, match="no table"):
        Layer(top, base, scaling="reciprocal").albedo(_wo(np.array([0.5])), method="table")


@pytest.mark.parametrize(("eta", "alpha"), COATS)
def test_a_coloured_lambertian_base_keeps_its_colour(eta, alpha):
    """Over a Lambertian base of albedo rho the reciprocal layer reflects what the albedo form
    does, E_top + (1 - E_top) rho, at every wo: C normalises the coat's share, not the base's
    colour."""
    layer = _layer(eta, alpha, "coloured")
    wo = _wo(COSINES)
    E_top = layer.top.albedo(wo, method="table")
    expected = E_top + (1.0 - E_top) * np.array([0.9, 0.5, 0.2])
    np.testing.assert_allclose(layer.albedo(wo, tol=1e-6), expected, rtol=0, atol=FURNACE_TOL)
