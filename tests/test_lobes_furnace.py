"""White-furnace and albedo tests: closed forms, independent quadrature, Monte Carlo.

Acceptance: a Conductor with F = 1 matches an independent closed form or quadrature to 1e-6
(alpha = 1, normal incidence, height-correlated: 1 - ln 2); a Dielectric with eta = 1 (or
smooth, eta -> 1) transmits everything.
"""

from functools import partial

import numpy as np
import pytest
from scipy.integrate import cubature

import adobe_bsdf as ab
from adobe_bsdf.validation import checks
from tests.tolerances import FURNACE

NORMAL = np.array([0.0, 0.0, 1.0])


def direction(cos_theta, phi=0.4):
    s = np.sqrt(1.0 - cos_theta**2)
    return np.array([s * np.cos(phi), s * np.sin(phi), cos_theta])


def hemisphere_albedo(lobe, wo):
    """Independent reference: scipy cubature of f |cos theta_i| over the upper hemisphere in
    (theta_i, phi_i) (smooth there for a conductor: f cos -> 0 at the horizon)."""
    def g(x):
        s = np.sin(x[:, 0])
        wi = np.stack([s * np.cos(x[:, 1]), s * np.sin(x[:, 1]), np.cos(x[:, 0])], -1)
        return lobe.eval(np.broadcast_to(wo, wi.shape), wi) * (wi[:, 2] * s)[:, None]
    return cubature(g, [0, 0], [np.pi / 2, 2 * np.pi], rtol=1e-10, atol=1e-12).estimate


@pytest.mark.parametrize("masking", ["correlated", "separable"])
def test_conductor_alpha_one_normal_incidence_is_one_minus_ln2(masking):
    lobe = ab.lobes.Conductor(1.0, masking=masking)
    value, error = lobe.albedo(NORMAL, method="quadrature", return_error=True)
    np.testing.assert_allclose(value, 1.0 - np.log(2.0), atol=FURNACE)
    assert np.all(error < FURNACE)


@pytest.mark.parametrize("alpha", [(0.3, 0.3), (0.5, 0.5), (1.0, 1.0), (0.5, 0.1)])
@pytest.mark.parametrize("cos_theta", [1.0, 0.5, 0.05])
def test_conductor_white_furnace_against_independent_quadrature(alpha, cos_theta):
    lobe = ab.lobes.Conductor(*alpha)
    wo = direction(cos_theta)
    value = lobe.albedo(wo, method="quadrature")
    np.testing.assert_allclose(value, hemisphere_albedo(lobe, wo), atol=FURNACE)
    assert np.all(value <= 1.0)


@pytest.mark.parametrize("alpha", [0.01, 0.1])
def test_conductor_narrow_lobes_quadrature_agrees_with_monte_carlo(alpha):
    """Narrow lobes lose energy only in a sliver near the horizon: quadrature must find it."""
    lobe = ab.lobes.Conductor(alpha)
    for cos_theta in (1.0, 0.5, 0.05):
        result = checks.mc_albedo_consistency(lobe, direction(cos_theta), n_samples=1_000_000)
        assert result.passed, result


def test_lambert_albedo_is_exact():
    lobe = ab.lobes.Lambert([0.2, 0.5, 1.0])
    for cos_theta in (1.0, 0.3, 1e-6):
        np.testing.assert_allclose(lobe.albedo(direction(cos_theta)), [0.2, 0.5, 1.0],
                                   atol=1e-12)
    np.testing.assert_array_equal(lobe.albedo(-NORMAL), 0.0)


@pytest.mark.parametrize("alpha", [0.0, 0.1, 0.5, 1.0])
@pytest.mark.parametrize("cos_theta", [1.0, 0.3, -0.6])
def test_index_matched_dielectric_transmits_everything(alpha, cos_theta):
    lobe = ab.lobes.Dielectric(1.0, alpha)
    wo = direction(cos_theta)
    np.testing.assert_allclose(lobe.albedo(wo, method="quadrature"), 1.0, atol=FURNACE)
    np.testing.assert_allclose(lobe.albedo(wo, method="mc", n_samples=1000), 1.0, atol=1e-15)
    s = lobe.sample(wo, np.array([0.3, 0.6, 0.9]))
    np.testing.assert_allclose(s.wi, -wo, atol=0)
    assert s.flags == ab.Flags.TRANSMISSION | ab.Flags.DELTA


@pytest.mark.parametrize("eta", [1.0 + 1e-9, 1.0 - 1e-9, 1.5, 1 / 1.5, 2.4])
@pytest.mark.parametrize("cos_theta", [1.0, 0.5, 0.05, -0.05, -0.5, -1.0])
def test_smooth_dielectric_is_lossless(eta, cos_theta):
    """R + T = 1 for a smooth interface at every angle, TIR included; T -> 1 as eta -> 1."""
    lobe = ab.lobes.Dielectric(eta, 0.0)
    wo = direction(cos_theta)
    np.testing.assert_allclose(lobe.albedo(wo, method="quadrature"), 1.0, atol=FURNACE)
    mc = lobe.albedo(wo, method="mc", n_samples=20_000)
    np.testing.assert_allclose(mc, 1.0, atol=1e-12)
    if abs(eta - 1.0) < 1e-6:
        s = lobe.sample(np.broadcast_to(wo, (1000, 3)), np.random.default_rng(0).random((1000, 3)))
        assert np.mean(s.flags & ab.Flags.TRANSMISSION > 0) > 0.99


@pytest.mark.parametrize(("eta", "alpha"), [(1.5, 0.1), (1.5, (0.5, 0.1)), (1 / 1.5, 0.3),
                                            (1.01, 0.5)])
@pytest.mark.parametrize("cos_theta", [0.9, 0.2, -0.4])
def test_rough_dielectric_quadrature_agrees_with_monte_carlo(eta, alpha, cos_theta):
    alpha = np.broadcast_to(alpha, 2)
    lobe = ab.lobes.Dielectric(eta, *alpha)
    result = checks.mc_albedo_consistency(lobe, direction(cos_theta), n_samples=400_000)
    assert result.passed, result
    assert np.all(result.quadrature <= 1.0)


def test_albedo_broadcasts_over_a_texture():
    alpha = np.array([0.2, 0.6, 1.0])
    gold = partial(ab.fresnel.conductor, eta=[0.143, 0.374, 1.442], k=[3.983, 2.385, 1.603])
    lobe = ab.lobes.Conductor(alpha, fresnel=gold)
    wo = np.stack([direction(c) for c in (1.0, 0.5, 0.2)])
    value = lobe.albedo(wo)
    assert value.shape == (3, 3)
    for i in range(3):
        single = ab.lobes.Conductor(alpha[i], fresnel=gold).albedo(wo[i])
        np.testing.assert_allclose(value[i], single, atol=FURNACE)
