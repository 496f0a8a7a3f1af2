"""The energy-preserving Oren–Nayar lobe (EON) [PortsmouthEON2025, Fujii2012]: the FON albedo
in closed form against independent quadrature, the white furnace of the compensation, the
Lambert limit, reciprocity, exact sampling of the CLTC mixture, extremes and bad input."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate

from adobe_bsdf.bsdf import Flags
from adobe_bsdf.lobes.lambert import Lambert
from adobe_bsdf.lobes.oren_nayar import (
    EON,
    EnergyPreservingOrenNayar,
    fon_albedo,
    fon_average_albedo,
)
from adobe_bsdf.validation import checks
from adobe_bsdf.validation import strategies as vs
from tests.sampling_checks import assert_sampling_matches
from tests.tolerances import EXACT, QUADRATURE, RECIPROCITY, WEIGHT

SIGMAS = [0.1, 0.5, 1.0]
#: closed forms against ``_hemisphere_integral``, which is accurate to rounding here (measured
#: max 1.6e-15); far inside the acceptance of 1e-6 (``tolerances.QUADRATURE``)
CLOSED_FORM = EXACT
MUS = [1e-3, 0.1, 0.5, 0.9, 1.0]
#: Gauss–Legendre nodes for the azimuth: on each half of [0, pi] (s > 0 and s <= 0) the
#: integrand is a polynomial of degree 1 in cos(phi), which 24 nodes integrate to rounding
PHI_NODES, PHI_WEIGHTS = np.polynomial.legendre.leggauss(24)


def _wo(mu, phi=0.0):
    s = np.sqrt((1.0 - mu) * (1.0 + mu))
    return np.array([s * np.cos(phi), s * np.sin(phi), mu])


def _f_fon(wo, wi, sigma):
    """f_FON of [Fujii2012] for rho = 1, as printed: (A + B s / t) / pi."""
    A = 1.0 / (1.0 + (0.5 - 2.0 / (3.0 * np.pi)) * sigma)
    B = sigma * A
    s = np.sum(wo * wi, axis=-1) - wo[..., 2] * wi[..., 2]
    t = np.where(s > 0.0, np.maximum(wo[..., 2], wi[..., 2]), 1.0)
    return (A + B * s / t) / np.pi


def _hemisphere_integral(f, mu_o, phi_o=0.0):
    """int f(wi) cos theta_i dwi over the upper hemisphere for f of (n, 3) directions,
    symmetric about the azimuth ``phi_o`` of wo (of cosine ``mu_o``): scipy ``quad`` in mu_i
    (broken at mu_i = mu_o, where t switches) of Gauss–Legendre sums in the relative azimuth
    over [0, pi/2] and [pi/2, pi] (broken where s changes sign), times 2."""
    def ring(mu_i):
        sin_i = np.sqrt((1.0 - mu_i) * (1.0 + mu_i))
        total = 0.0
        for lo, hi in ((0.0, np.pi / 2), (np.pi / 2, np.pi)):
            phi = 0.5 * (hi - lo) * PHI_NODES + 0.5 * (hi + lo) + phi_o
            wi = np.stack([sin_i * np.cos(phi), sin_i * np.sin(phi), np.full_like(phi, mu_i)],
                          axis=-1)
            total += 0.5 * (hi - lo) * PHI_WEIGHTS @ f(wi)
        return 2.0 * total * mu_i

    points = [mu_o] if 0.0 < mu_o < 1.0 else None
    return integrate.quad(ring, 0.0, 1.0, points=points, epsabs=1e-13, epsrel=1e-13,
                          limit=400)[0]


# -- the FON albedo in closed form ------------------------------------------------------------
@pytest.mark.parametrize("sigma", SIGMAS)
def test_fon_albedo_is_the_quadrature_of_f_fon(sigma):
    lobe = EnergyPreservingOrenNayar(0.6, sigma, compensation=False)
    for mu in MUS:
        wo = _wo(mu)
        expected = _hemisphere_integral(lambda wi, wo=wo: _f_fon(wo, wi, sigma), mu)
        assert abs(fon_albedo(mu, sigma) - expected) < CLOSED_FORM, (mu, sigma)
        np.testing.assert_allclose(lobe.albedo(wo, "table"), 0.6 * expected, atol=CLOSED_FORM)


@pytest.mark.parametrize("sigma", [0.0] + SIGMAS)
def test_average_albedo_is_the_cosine_weighted_mean(sigma):
    expected = 2.0 * integrate.quad(lambda mu: fon_albedo(mu, sigma) * mu, 0.0, 1.0,
                                    epsabs=1e-13, epsrel=1e-13)[0]
    assert abs(fon_average_albedo(sigma) - expected) < CLOSED_FORM


def test_fon_albedo_limits():
    """E_hat = 1 at grazing (every sigma) and for sigma = 0 (every mu); below 1 otherwise."""
    mu = np.array([0.0, 1e-310, 1e-8, 0.3, 1.0])
    np.testing.assert_allclose(fon_albedo(mu[:2], np.array(SIGMAS)[:, None]), 1.0, rtol=EXACT)
    np.testing.assert_array_equal(fon_albedo(mu, 0.0), 1.0)
    assert np.all(fon_albedo(mu[3:], 1.0) < 1.0)


# -- compensation: furnace and albedo --------------------------------------------------------
@pytest.mark.parametrize("sigma", SIGMAS)
def test_white_furnace_by_quadrature_of_eval(sigma):
    """rho = 1: int f cos dwi = 1, integrating the lobe's own eval (not its albedo)."""
    lobe = EON(1.0, sigma)
    for mu in (1e-3, 0.3, 0.8, 1.0):
        wo = _wo(mu)
        value = _hemisphere_integral(lambda wi, wo=wo: lobe.eval(wo, wi)[:, 0], mu)
        assert abs(value - 1.0) < CLOSED_FORM, (mu, sigma, value)
        np.testing.assert_allclose(lobe.albedo(wo, "table"), 1.0, atol=1e-15)


@pytest.mark.parametrize(("rho", "sigma"), [((0.8, 0.4, 0.1), 0.5), ((0.3, 0.95, 0.0), 1.0),
                                            ((0.5, 0.5, 0.5), 0.05)])
def test_albedo_is_the_quadrature_of_eval(rho, sigma):
    lobe = EON(rho, sigma)
    for mu in (2e-3, 0.4, 1.0):
        wo = _wo(mu, phi=1.1)
        expected = [_hemisphere_integral(lambda wi, c=c, wo=wo: lobe.eval(wo, wi)[:, c], mu,
                                         phi_o=1.1) for c in range(3)]
        np.testing.assert_allclose(lobe.albedo(wo, "table"), expected, atol=CLOSED_FORM)


def test_eval_is_the_printed_formula():
    """f = f_FON + (rho_ms / pi)(1 - E_hat_i)(1 - E_hat_o) / (1 - <E_hat>), rho_ms =
    rho^2 <E_hat> / (1 - rho (1 - <E_hat>)) [PortsmouthEON2025], away from the horizon (where
    1 - E_hat, computed here as printed, cancels)."""
    rng = np.random.default_rng(2)
    w = rng.normal(size=(2, 2000, 3))
    w[..., 2] = np.abs(w[..., 2]) + 0.05
    wo, wi = w / np.linalg.norm(w, axis=-1, keepdims=True)
    rho = np.array([0.9, 0.5, 0.05])
    for sigma in (0.2, 1.0):
        E_o, E_i = fon_albedo(wo[:, 2], sigma), fon_albedo(wi[:, 2], sigma)
        E_avg = fon_average_albedo(sigma)
        rho_ms = rho**2 * E_avg / (1.0 - rho * (1.0 - E_avg))
        f_ms = rho_ms / np.pi * ((1.0 - E_o) * (1.0 - E_i) / (1.0 - E_avg))[:, None]
        expected = rho * _f_fon(wo, wi, sigma)[:, None] + f_ms
        np.testing.assert_allclose(EON(rho, sigma).eval(wo, wi), expected, rtol=1e-11)
        np.testing.assert_allclose(EON(rho, sigma, compensation=False).eval(wo, wi),
                                   expected - f_ms, rtol=EXACT)


def test_albedo_methods_agree():
    """The closed form against the generic cubature of eval, away from grazing (at grazing
    wo the lobe's ridge at mu_i = mu_o is not on the cubature's cell edges)."""
    lobe = EON((0.9, 0.5, 0.2), 0.7)
    wo = np.stack([_wo(mu, 0.3) for mu in (0.2, 0.6, 1.0)])
    np.testing.assert_allclose(lobe.albedo(wo), lobe.albedo(wo, "table"), atol=QUADRATURE)
    table, error = lobe.albedo(wo, "table", return_error=True)
    assert not np.any(error)
    np.testing.assert_array_equal(lobe._top_albedo(wo), table)


# -- the Lambert limit ------------------------------------------------------------------------
@pytest.mark.parametrize("compensation", [True, False])
def test_zero_roughness_is_lambert(compensation):
    """At sigma = 0 the lobe is Lambert's, bit for bit (computed as such), and the general
    formulas at the smallest positive sigma give the same within rounding."""
    rng = np.random.default_rng(3)
    w = rng.normal(size=(2, 20_000, 3))
    wo, wi = w / np.linalg.norm(w, axis=-1, keepdims=True)
    u = rng.random((20_000, 3))
    rho = (0.9, 0.5, 0.1)
    eon, lambert, general = EON(rho, 0.0, compensation), Lambert(rho), EON(rho, 5e-324,
                                                                             compensation)
    assert not general._lambert
    np.testing.assert_array_equal(eon.eval(wo, wi), lambert.eval(wo, wi))
    np.testing.assert_array_equal(eon.pdf(wo, wi), lambert.pdf(wo, wi))
    np.testing.assert_array_equal(general.eval(wo, wi), lambert.eval(wo, wi))
    np.testing.assert_array_equal(general.pdf(wo, wi), lambert.pdf(wo, wi))
    a, b, c = eon.sample(wo, u), lambert.sample(wo, u), general.sample(wo, u)
    for field in ("wi", "pdf", "flags"):
        np.testing.assert_array_equal(getattr(a, field), getattr(b, field))
    np.testing.assert_allclose(a.weight, b.weight, rtol=1e-15)
    np.testing.assert_array_equal(c.flags, b.flags)
    np.testing.assert_allclose(c.wi, b.wi, rtol=0.0, atol=1e-15)
    np.testing.assert_allclose(c.weight, b.weight, rtol=1e-15)
    np.testing.assert_allclose(c.pdf, b.pdf, rtol=1e-15)
    assert np.count_nonzero(a.pdf) > 9000
    np.testing.assert_array_equal(eon.albedo(wo, "table"),
                                  np.where(wo[:, 2:] > 0.0, np.array(rho), 0.0))


# -- reciprocity ----------------------------------------------------------------------------------
@settings(max_examples=200, deadline=None)
@given(rho=st.floats(0.0, 1.0), sigma=vs.roughness(), compensation=st.booleans(),
       pair=vs.direction_pairs("any", allow_horizon=True))
def test_reciprocity(rho, sigma, compensation, pair):
    lobe = EON((rho, 0.5 * rho, 1.0), sigma, compensation)
    result = checks.reciprocity_error(lobe, *pair, rtol=RECIPROCITY)
    assert result.passed, result


# -- sampling ---------------------------------------------------------------------------------
#: (sigma, cos theta_o): the fit's d > 0 above mu_o = 0.9998 (the mirrored clip) included
CHI2 = [(0.05, 0.7), (0.3, 1.0), (0.5, 0.4), (1.0, 0.99999), (1.0, 0.5), (1.0, 0.05),
        (0.7, 2e-3)]


@pytest.mark.parametrize(("sigma", "cos_theta"), CHI2)
def test_chi2(sigma, cos_theta):
    assert_sampling_matches(EON((1.0, 0.6, 0.3), sigma), cos_theta, azimuth=0.7,
                            seed=CHI2.index((sigma, cos_theta)), n_tests=len(CHI2),
                            n_samples=1_000_000)


@pytest.mark.parametrize("sigma", [0.0, 0.4, 1.0])
@pytest.mark.parametrize("cos_theta", [1.0, 0.99999, 0.3, 1e-4])
def test_pdf_integrates_to_one(sigma, cos_theta):
    """Every sample succeeds: the density is normalised over the upper hemisphere."""
    result = checks.pdf_integral(EON(0.5, sigma), _wo(cos_theta, 2.0))
    assert result.passed and abs(result.value - 1.0) < 1e-6, str(result)


@pytest.mark.parametrize("cos_theta", [1.0, 0.99999, 0.99985, 0.5])
def test_clipped_side_follows_the_sign_of_d(cos_theta):
    """Uniforms on the u_1 = 0 edge of the square give disk points on the x < 0 rim of the
    LTC frame (wo has azimuth 0); where d > 0 (mu_o > 0.9998) the horizon's pre-image cuts
    that side of the disk, so the clipped map must mirror, else these samples fall below the
    horizon. None may fail, and weight = f cos / pdf."""
    n = 2000
    u = np.stack([np.full(n, 0.999), np.full(n, 1e-9), np.linspace(0.0, 1.0, n,
                                                                    endpoint=False)], -1)
    lobe = EON(0.8, 1.0)
    s = lobe.sample(_wo(cos_theta), u)
    assert np.all(s.pdf > 0.0) and np.all(s.wi[:, 2] > 0.0)
    result = checks.weight_consistency(lobe, _wo(cos_theta), u=u[:, None], rtol=WEIGHT)
    assert result.passed, str(result)


@settings(max_examples=100, deadline=None)
@given(sigma=vs.roughness(), wo=vs.directions("upper"), u=vs.uniform_triples())
def test_weight_consistency_at_edge_uniforms(sigma, wo, u):
    result = checks.weight_consistency(EON(0.7, sigma), wo, u=u[None], rtol=WEIGHT)
    assert result.passed, str(result)


def test_weight_consistency_at_a_subnormal_sampled_cosine():
    """Found by hypothesis: grazing wo and sigma = 5e-324 sample wi.z = 5e-324. The check
    must neither call that pair transmission (wo.z wi.z underflows to 0) nor compute the
    expected weight as f |wi.z| / pdf (f |wi.z| underflows to 0); the sample itself is right.
    u = (0, 1/2) is the disk's point (-1, 0) exactly, on the rim."""
    wo, u = np.array([1.0, 0.0, 1e-8]), np.array([[0.5, 0.0, 0.5]])
    lobe = EON(0.7, 5e-324)
    s = lobe.sample(wo, u[0])
    assert 0.0 < s.wi[2] < 1e-300 and s.flags & Flags.REFLECTION
    result = checks.weight_consistency(lobe, wo, u=u, rtol=WEIGHT)
    assert result.passed and result.n_checked == 1, str(result)


# -- parameters, extremes, bad input --------------------------------------------------------------
def test_broadcasting_texture():
    rng = np.random.default_rng(5)
    rho, sigma = rng.random((2, 3, 3)), rng.random((2, 3))
    w = rng.normal(size=(2, 2, 3, 3))
    w[..., 2] = np.abs(w[..., 2])
    wo, wi = w / np.linalg.norm(w, axis=-1, keepdims=True)
    u = rng.random((2, 3, 3))
    lobe = EON(rho, sigma)
    f, pdf, s, E = lobe.eval(wo, wi), lobe.pdf(wo, wi), lobe.sample(wo, u), lobe.albedo(wo,
                                                                                        "table")
    assert f.shape == (2, 3, 3) and pdf.shape == (2, 3) and s.weight.shape == (2, 3, 3)
    for i in range(2):
        for j in range(3):
            one = EON(rho[i, j], sigma[i, j])
            np.testing.assert_array_equal(f[i, j], one.eval(wo[i, j], wi[i, j]))
            np.testing.assert_array_equal(pdf[i, j], one.pdf(wo[i, j], wi[i, j]))
            np.testing.assert_array_equal(s.wi[i, j], one.sample(wo[i, j], u[i, j]).wi)
            np.testing.assert_array_equal(E[i, j], one.albedo(wo[i, j], "table"))


def test_extremes_are_finite():
    rng = np.random.default_rng(8)
    w = rng.normal(size=(2, 400, 3))
    wo, wi = w / np.linalg.norm(w, axis=-1, keepdims=True)
    edge = np.array([[1.0, 0.0, 0.0], [0.6, 0.8, 0.0], [1.0, 0.0, 1e-310], [0.0, 1.0, 1e-310],
                     [np.sqrt(1 - 1e-24), 0.0, 1e-12], [0.0, 0.0, 1.0],
                     [-np.sqrt(1 - 1e-24), 0.0, 1e-12], [-1.0, 0.0, 1e-310], [0.0, 0.0, -1.0],
                     [0.6, 0.0, -0.8]])
    wo = np.concatenate([wo, edge, edge, edge])
    wi = np.concatenate([wi, edge, edge[::-1], np.roll(edge, 1, axis=0)])
    u = np.concatenate([rng.random((400, 3)), np.tile([[0.0, 0.0, 0.0], [0.5, 0.5, 0.5],
                                                       [vs.JUST_BELOW_ONE] * 3], (10, 1))])
    for sigma in (0.0, 5e-324, 1e-300, 1e-6, 0.5, 1.0):
        for rho in (0.0, 1.0):
            for compensation in (True, False):
                lobe = EON(rho, sigma, compensation)
                s = lobe.sample(wo, u)
                values = (lobe.eval(wo, wi), lobe.pdf(wo, wi), s.weight, s.pdf,
                          lobe.albedo(wo, "table"))
                for v in values:
                    assert np.all(np.isfinite(v)) and np.all(v >= 0.0), (sigma, rho)
                assert np.all(np.isfinite(s.wi))
    below = np.array([0.6, 0.0, -0.8])
    lobe = EON(1.0, 0.5)
    assert not np.any(lobe.eval(below, wi)) and not np.any(lobe.pdf(below, wi))
    assert not np.any(lobe.eval(below, below)) and not np.any(lobe.sample(below, u).pdf)
    assert not np.any(lobe.albedo(below, "table"))


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"roughness": -0.1}, "roughness = -0.1"), ({"roughness": 1.5}, "roughness = 1.5"),
    ({"roughness": np.nan}, "roughness = nan"), ({"albedo": 1.5}, "albedo = 1.5"),
    ({"albedo": (0.1, 0.2)}, "albedo"), ({"compensation": 1}, "compensation"),
    ({"roughness": np.zeros(2), "albedo": np.ones((3, 3))}, "broadcast")])
def test_bad_input_is_named(kwargs, name):
    with pytest.raises(ValueError, match=name):
        EON(**{"albedo": 0.5, "roughness": 0.5, **kwargs})


@pytest.mark.parametrize(("call", "name"), [
    (lambda: fon_albedo(1.5, 0.5), "mu = 1.5"), (lambda: fon_albedo(0.5, -1.0), "sigma = -1.0"),
    (lambda: fon_average_albedo(np.nan), "sigma = nan")])
def test_bad_albedo_arguments_are_named(call, name):
    with pytest.raises(ValueError, match=name):
        call()


@pytest.mark.parametrize("sigma", [0.0, 0.5, 1.0])
def test_the_lobes_quadrature_follows_its_kinks(sigma):
    """``albedo(method="quadrature")`` splits at theta_i = theta_o and at s = 0: it equals the
    closed form to 1e-12 down to grazing views, and its error estimate is that small too."""
    mu = np.array([1.0, 0.5, 0.05, 1e-3])
    wo = np.stack([np.sqrt(1 - mu**2), 0 * mu, mu], -1)
    lobe = EnergyPreservingOrenNayar((0.9, 0.5, 0.2), sigma)
    E, error = lobe.albedo(wo, method="quadrature", return_error=True)
    np.testing.assert_allclose(E, lobe.albedo(wo, method="table"), rtol=0, atol=1e-12)
    assert np.all(error < 1e-12)
