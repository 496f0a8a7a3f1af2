"""Coat darkening [OpenPBR2026, §Coat darkening; Portsmouth2025]: the Fresnel average, the
coat's internal reflectance, Delta and the base factor, against quadrature, a random walk of
light between a smooth coat and a Lambertian base, and the properties the specification
states."""

import numpy as np
import pytest

from adobe_bsdf import darkening as dk
from adobe_bsdf import fresnel
from adobe_bsdf.composition import Layer, Sum
from adobe_bsdf.lobes import DielectricReflection, Lambert

ETAS = np.array([1.01, 1.3, 1.5, 2.0, 3.0])


def test_fresnel_average_is_the_integral():
    """Against the trapezoidal rule on 2e6 + 1 cosines (both sides of the interface)."""
    mu = np.linspace(0.0, 1.0, 2_000_001)
    for eta in np.concatenate([ETAS, 1.0 / ETAS]):
        g = 2.0 * fresnel.dielectric(mu, eta) * mu
        reference = np.sum(0.5 * (g[1:] + g[:-1]) * np.diff(mu))
        assert abs(float(dk.fresnel_average(eta)) - reference) <= 1e-7, eta


def test_fresnel_average_limits():
    assert dk.fresnel_average(1.0) == 0.0  # index matched
    assert dk.fresnel_average(1e-6) == pytest.approx(1.0, abs=1e-9)  # almost all TIR


def test_internal_reflectance_is_the_average_seen_from_inside():
    """K = 1 - (1 - E_F(eta)) / eta^2 equals E_F(1 / eta), integrated on the side of total
    internal reflection (the reciprocity the specification's formula rests on)."""
    np.testing.assert_allclose(dk.internal_reflectance(ETAS), dk.fresnel_average(1.0 / ETAS),
                               rtol=0, atol=1e-12)


def test_the_specification_fit_is_within_its_stated_accuracy():
    """Within 0.2 % (absolute) of the quadrature on [1, 3], both sides."""
    eta = np.linspace(1.0, 3.0, 401)
    assert np.abs(dk.fresnel_average_fit(eta) - dk.fresnel_average(eta)).max() <= 2e-3
    assert np.abs(dk.fresnel_average_fit(1 / eta) - dk.fresnel_average(1 / eta)).max() <= 2e-3


def _random_walk_albedo(eta, E_b, n=2_000_000, seed=1):
    """Light at normal incidence on a smooth coat of index ``eta`` over a Lambertian base of
    albedo ``E_b``: enters with 1 - F0, then alternates diffuse reflection at the base and
    Fresnel reflection (from inside) at the coat until it leaves or is absorbed. Returns the
    albedo (F0 plus what leaves) and its standard error."""
    rng = np.random.default_rng(seed)
    F0 = float(fresnel.dielectric(1.0, eta))
    alive = np.ones(n, dtype=bool)
    out = np.zeros(n)
    while alive.any():
        idx = np.flatnonzero(alive)
        survives = rng.random(idx.size) < E_b  # the base reflects ...
        mu = np.sqrt(rng.random(idx.size))  # ... diffusely (cosine-distributed)
        leaves = survives & (rng.random(idx.size) >= fresnel.dielectric(mu, 1.0 / eta))
        out[idx[leaves]] = 1.0
        alive[idx[~survives | leaves]] = False
    mean = out.mean()
    return F0 + (1.0 - F0) * mean, (1.0 - F0) * out.std() / np.sqrt(n)


@pytest.mark.parametrize("eta", [1.3, 1.5, 2.0])
@pytest.mark.parametrize("E_b", [0.2, 0.8, 1.0])
def test_physical_darkening_of_a_clear_coat_is_the_random_walk(eta, E_b):
    """delta = 1, clear coat: F0 + (1 - F0) E_b Delta, Delta = (1 - K) / (1 - E_b K), is the
    albedo of the light bouncing between a smooth coat and a Lambertian base (4 sigma)."""
    F0 = float(fresnel.dielectric(1.0, eta))
    K = dk.internal_reflectance(eta)
    Delta = dk.darkening(E_b, K)[0]
    walk, sigma = _random_walk_albedo(eta, E_b)
    assert abs(F0 + (1.0 - F0) * E_b * Delta - walk) <= 4.0 * sigma + 1e-12, (walk, sigma)


@pytest.mark.parametrize("T2", [1.0, (0.9, 0.6, 0.2)])
def test_no_darkening_is_the_naive_albedo(T2):
    """delta = 0: the base is only tinted by T^2, and the coated albedo at normal incidence
    is E_spec + T^2 E_b (1 - E_spec) (cubature of the layered lobe)."""
    E_b = np.array([0.7, 0.4, 0.9])
    Delta = dk.darkening(E_b, dk.internal_reflectance(1.5), T2)
    factor = dk.base_factor(Delta, 0.0, T2)
    np.testing.assert_allclose(factor, np.broadcast_to(np.asarray(T2, float), (3,)), rtol=1e-15)
    coat = DielectricReflection(1.5, 0.0)
    layer = Layer(coat, Sum(Lambert(E_b), weights=[factor]))
    E = layer.albedo(np.array([0.0, 0.0, 1.0]), tol=1e-9)
    E_spec = float(fresnel.dielectric(1.0, 1.5))
    np.testing.assert_allclose(E, E_spec + np.asarray(T2) * E_b * (1.0 - E_spec), atol=1e-8)


def test_coat_reflectance_ends():
    """r = 0: the Fresnel at the view; r = 1: the internal average."""
    for eta in ETAS:
        assert dk.coat_reflectance(eta, 0.0, 0.6) == fresnel.dielectric(0.6, eta)
        assert dk.coat_reflectance(eta, 1.0, 0.6) == dk.internal_reflectance(eta)


def test_white_base_under_a_clear_coat_shows_no_colour_shift():
    for delta in (0.0, 0.5, 1.0):
        for eta in ETAS:
            f = dk.base_factor(dk.darkening(1.0, dk.internal_reflectance(eta)), delta)
            assert np.ptp(f) == 0.0 and 0.0 < f[0] <= 1.0


def test_darkening_variants_and_coverage():
    """The two variants agree without absorption; coverage 0 leaves the base alone; delta
    scales linearly between no and full darkening."""
    E_b, T2, K = np.array([0.8, 0.5, 0.3]), np.array([0.9, 0.7, 0.5]), 0.4
    np.testing.assert_allclose(dk.darkening(E_b, K, 1.0), dk.darkening(E_b, K, 1.0, "v1.1.1"),
                               rtol=1e-15)
    # the bounces through an absorbing coat give back less light: darker than v1.1.1's Delta
    assert np.all(dk.darkening(E_b, K, T2) < dk.darkening(E_b, K, T2, "v1.1.1"))
    Delta = dk.darkening(E_b, K, T2)
    np.testing.assert_array_equal(dk.base_factor(Delta, 0.7, T2, coverage=0.0), 1.0)
    half = dk.base_factor(Delta, 0.5, T2)
    np.testing.assert_allclose(half, 0.5 * (dk.base_factor(Delta, 0.0, T2)
                                            + dk.base_factor(Delta, 1.0, T2)), rtol=1e-14)


def test_fully_reflecting_coat_over_a_lossless_base():
    """K = 1 and E_b T^2 = 1 is 0 / 0: taken as no darkening, and finite."""
    assert dk.darkening(1.0, 1.0)[0] == 1.0
    assert np.all(np.isfinite(dk.darkening(np.array([1.0, 0.5, 0.0]), 1.0)))


@pytest.mark.parametrize(("call", "message"), [
    (lambda: dk.darkening(1.5, 0.3), "E_b = 1.5"),
    (lambda: dk.darkening(0.5, -0.1), "K = -0.1"),
    (lambda: dk.darkening(0.5, 0.3, variant="v2"), "variant = 'v2'"),
    (lambda: dk.base_factor(0.5, 2.0), "delta = 2.0"),
    (lambda: dk.fresnel_average(0.0), "eta = 0.0")])
def test_bad_input(call, message):
    with pytest.raises(ValueError, match=message):
        call()
