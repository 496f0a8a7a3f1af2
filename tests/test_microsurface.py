"""The microsurface random walk [Heitz2016ms] against closed forms, the library's lobes and
itself: its first order is the analytic single scattering, its walks conserve energy, its
estimate of f integrates to its albedo and is reciprocal, and bad input is refused.

Every estimate is seeded: each check is a fixed computation, compared within SIGMAS standard
errors (the errors are honest at these roughnesses: the measured scatter between seeds is in
the tests that compare two independent estimates)."""

import numpy as np
import pytest
from scipy import special

from adobe_bsdf import fresnel
from adobe_bsdf.lobes import Conductor, Dielectric
from adobe_bsdf.microfacet import GGX
from adobe_bsdf.tables.energy import ggx_energy
from adobe_bsdf.validation.microsurface import (
    ORDERS,
    Albedo,
    MicrosurfaceConductor,
    MicrosurfaceDielectric,
    _free_path,
    visible_normal,
)

#: agreement within this many standard errors
SIGMAS = 4.0


def sph(mu, phi):
    mu = np.asarray(mu, dtype=float)
    s = np.sqrt(1.0 - mu * mu)
    return np.stack(np.broadcast_arrays(s * np.cos(phi), s * np.sin(phi), mu), -1)


def assert_within(estimate, error, expected, sigmas=SIGMAS, rtol=0.0):
    estimate, error, expected = np.broadcast_arrays(estimate, error, expected)
    bad = np.abs(estimate - expected) > sigmas * error + rtol * np.abs(expected)
    assert not np.any(bad), (estimate[bad], error[bad], expected[bad])


#: (mu_o, phi_o, mu_i, phi_i): reflection and transmission, from above and from below
PAIRS = [(0.5, 0.2, 0.7, 2.5), (0.9, 0.0, 0.3, 3.0), (0.3, 1.0, 0.8, 1.2),
         (0.5, 0.2, -0.7, 2.5), (0.8, 0.4, -0.7, 3.6), (-0.6, 0.3, -0.9, 2.0),
         (-0.9, 0.3, 0.5, 3.0)]


def pairs():
    mo, po, mi, pi = np.array(PAIRS).T
    return sph(mo, po), sph(mi, pi)


def beta_masking(distribution, wo, wi):
    """B(1 + Lambda_o, 1 + Lambda_i) (1 + Lambda_o + Lambda_i): the walk's first-order
    transmission over the library's (module docstring of validation.microsurface)."""
    lo, li = distribution.lambda_(wo), distribution.lambda_(wi)
    return special.beta(1.0 + lo, 1.0 + li) * (1.0 + lo + li)


# -- the free paths --------------------------------------------------------------------------
@pytest.mark.parametrize("lam, q_min", [(0.7, 0.0), (0.7, 0.5), (1e-3, 0.5), (1e-3, 1.0)])
def test_free_path_going_up(lam, q_min):
    """From C1 = 0.6 going up: P(hit below C1' = x) = 1 - (0.6 / x)^Lambda [Heitz2016ms],
    escape C1^Lambda; with q_min the hits, weighed, keep that expectation (rare hits made
    common: Lambda = 1e-3 hits with probability 5e-4)."""
    n, c1 = 400_000, 0.6
    u = np.random.default_rng(17).random(n)
    out, log_c1, weight = _free_path(np.full(n, lam), np.ones(n, bool), np.full(n, np.log(c1)),
                                     u, q_min)
    assert np.all(log_c1[~out] >= np.log(c1)) and np.all(log_c1 < 0.0)
    if q_min == 0.0:
        assert_within(out.mean(), out.std() / np.sqrt(n), c1**lam)
        assert np.all(weight == 1.0)
    for x in (0.65, 0.8, 0.95):
        g = np.where(~out & (log_c1 <= np.log(x)), weight, 0.0)
        assert_within(g.mean(), g.std() / np.sqrt(n), 1.0 - (c1 / x) ** lam)


def test_free_path_going_down_and_straight_up():
    """Going down: P(C1' <= x) = (x / C1)^(1 + Lambda), always a hit; straight up
    (Lambda = 0): always out."""
    n, c1, lam = 400_000, 0.6, 0.4
    u = np.random.default_rng(18).random(n)
    out, log_c1, weight = _free_path(np.full(n, lam), np.zeros(n, bool), np.full(n, np.log(c1)),
                                     u, 0.5)
    assert not np.any(out) and np.all(weight == 1.0) and np.all(log_c1 <= np.log(c1))
    for x in (0.1, 0.3, 0.5):
        g = log_c1 <= np.log(x)
        assert_within(g.mean(), g.std() / np.sqrt(n), (x / c1) ** (1.0 + lam))
    out, _, _ = _free_path(np.zeros(4), np.ones(4, bool), np.full(4, -1.0), np.zeros(4), 0.5)
    assert np.all(out)


# -- the visible normals of either side ------------------------------------------------------
def test_visible_normal_above_is_the_library_sampler():
    """Above the horizon the spherical caps with a signed direction are GGX.sample_visible."""
    d = GGX(0.3, 0.7)
    rng = np.random.default_rng(0)
    w = sph(rng.uniform(0.01, 1.0, 500), rng.uniform(0.0, 2.0 * np.pi, 500))
    u = rng.random((500, 2))
    np.testing.assert_allclose(visible_normal(d, w, u), d.sample_visible(w, u), rtol=0,
                               atol=1e-12)


@pytest.mark.parametrize("mu", [-0.3, -0.8, 0.6])
def test_visible_normal_density(mu):
    """Sample means of m against int m <w, m>+ D(m) dm / A(w) by quadrature over the
    hemisphere of normals, and the quadrature's normalisation against A(w) = w_z (1 + Lambda)
    above the horizon, |w_z| Lambda below."""
    d = GGX(0.5, 0.3)
    w = sph(mu, 0.7)
    x, wx = np.polynomial.legendre.leggauss(200)
    t = 0.25 * np.pi * (x + 1.0)  # theta_m in (0, pi / 2)
    p = np.pi * (x + 1.0)
    T, P = np.meshgrid(t, p, indexing="ij")
    weight = np.outer(wx * 0.25 * np.pi * np.sin(t), wx * np.pi)
    m = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1)
    density = np.maximum(m @ w, 0.0) * d.D(m) * weight
    area = density.sum()
    lam = d.lambda_(w)
    expected_area = abs(mu) * (1.0 + lam) if mu > 0 else abs(mu) * lam
    np.testing.assert_allclose(area, expected_area, rtol=2e-4)
    moments = np.einsum("ij,ijk->k", density, m) / area
    rng = np.random.default_rng(1)
    n = 200_000
    sample = visible_normal(d, np.broadcast_to(w, (n, 3)), rng.random((n, 2)))
    assert np.all(sample @ w >= -1e-12) and np.all(sample[:, 2] >= 0.0)
    assert_within(sample.mean(0), sample.std(0) / np.sqrt(n), moments)


# -- the first order is the analytic single scattering ---------------------------------------
@pytest.mark.parametrize("eta, ax, ay", [(1.5, 0.3, 0.3), (1.33, 0.2, 0.6), (2.0, 0.7, 0.4)])
def test_single_scattering_is_the_analytic_lobe(eta, ax, ay):
    """First order = ``Dielectric`` (height-correlated G2) for reflection, and ``Dielectric``
    times B(1 + L_o, 1 + L_i)(1 + L_o + L_i) for transmission (the Beta form)."""
    wo, wi = pairs()
    walk = MicrosurfaceDielectric(eta, ax, ay)
    result = walk.eval_orders(wo, wi, n_walks=20_000, seed=1)
    lobe = Dielectric(eta, ax, ay)
    expected = lobe.eval(wo, wi)
    transmission = wo[:, 2] * wi[:, 2] < 0.0
    ratio = np.where(transmission, beta_masking(lobe.distribution, wo, wi), 1.0)[:, None]
    assert np.all(expected > 0.0)
    assert_within(result.single, result.single_error, expected * ratio, rtol=1e-12)
    assert np.all(result.single_error < 0.01 * result.single)


def test_first_order_transmission_is_not_the_correlated_g2():
    """The walk's first-order transmission differs from the library's 1 / (1 + L_o + L_i)
    masking by many standard errors where the Lambdas are large."""
    wo, wi = sph(0.3, 0.2), sph(-0.4, 2.5)
    result = MicrosurfaceDielectric(1.5, 0.8).eval_orders(wo, wi, n_walks=20_000, seed=2)
    correlated = Dielectric(1.5, 0.8).eval(wo, wi)
    assert np.all(correlated - result.single > 20.0 * result.single_error)


@pytest.mark.parametrize("F", [None, fresnel.ExactConductor([0.2, 0.9, 1.1], [3.0, 2.5, 2.0])])
def test_conductor_single_scattering_is_conductor(F):
    wo, wi = pairs()
    up = (wo[:, 2] > 0.0) & (wi[:, 2] > 0.0)
    walk = MicrosurfaceConductor(0.4, 0.25, fresnel=F)
    result = walk.eval_orders(wo[up], wi[up], n_walks=20_000, seed=3)
    assert_within(result.single, result.single_error,
                  Conductor(0.4, 0.25, fresnel=F).eval(wo[up], wi[up]), rtol=1e-12)
    below = walk.eval_orders(wo[~up], wi[~up], n_walks=4, seed=3)
    assert np.all(below.all == 0.0)


# -- energy ----------------------------------------------------------------------------------
@pytest.mark.parametrize("eta, ax, ay", [(1.5, 0.4, 0.4), (1.33, 1.2, 0.3), (1 / 1.5, 0.6, 0.6)])
def test_every_walk_leaves(eta, ax, ay):
    """A lossless interface: each walk ends above or below, so R + T = 1 exactly."""
    wo = sph([0.9, 0.5, 0.1, -0.3, -0.95], [0.0, 1.0, 2.0, 3.0, 4.0])
    walk = MicrosurfaceDielectric(eta, ax, ay)
    a = walk.albedo(wo, n_walks=20_000, seed=4)
    assert isinstance(a, Albedo) and np.all(a.lost == 0.0)
    np.testing.assert_allclose(a.reflected + a.transmitted, 1.0, rtol=0, atol=1e-15)
    E, error = walk.albedo(wo, n_walks=20_000, seed=4, split=False)
    np.testing.assert_allclose(E, 1.0, rtol=0, atol=1e-15)
    assert np.all(error == 0.0)
    single = walk.albedo(wo, n_walks=20_000, seed=4, order="single")
    multiple = walk.albedo(wo, n_walks=20_000, seed=4, order="multiple")
    np.testing.assert_allclose(single.reflected + multiple.reflected, a.reflected, atol=1e-15)


def test_white_conductor_keeps_all_energy():
    wo = sph([1.0, 0.5, 0.05], 0.3)
    for alpha in (0.1, 1.0):
        a = MicrosurfaceConductor(alpha, 0.5 * alpha).albedo(wo, n_walks=20_000, seed=5)
        assert np.all(a.lost == 0.0) and np.all(a.reflected == 1.0)
        assert np.all(a.transmitted == 0.0)
    below = MicrosurfaceConductor(0.5).albedo(sph(-0.5, 0.0), n_walks=10)
    assert np.all(below.reflected == 0.0)


@pytest.mark.parametrize("mu", [0.9, 0.5, 0.2])
def test_reflected_energy_lies_between_single_scattering_and_one(mu):
    """R_single of the walk is the library's single-scattering E_R (the same reflection
    lobe); R of all orders lies above it and below 1; T_single lies below the library's
    E_T (the Beta masking is the smaller), measurably so away from normal incidence."""
    eta, alpha = 1.5, 0.6
    wo = sph(mu, 0.0)
    walk = MicrosurfaceDielectric(eta, alpha)
    single = walk.albedo(wo, n_walks=100_000, seed=6, order="single")
    every = walk.albedo(wo, n_walks=100_000, seed=7)
    E = ggx_energy(mu, alpha, eta)
    assert_within(single.reflected, single.reflected_error, E.reflection)
    assert np.all(every.reflected - E.reflection > SIGMAS * every.reflected_error)
    assert np.all(every.reflected < 1.0)
    margin = SIGMAS * single.transmitted_error
    assert np.all(single.transmitted < E.transmission + margin)
    if mu <= 0.5:
        assert np.all(single.transmitted < E.transmission - margin)


# -- the estimate of f -----------------------------------------------------------------------
@pytest.mark.parametrize("eta, alpha, mu", [(1.5, 0.5, 0.4), (1.5, 0.08, 0.3),
                                            (1.33, 0.4, -0.6)])
def test_eval_integrates_to_the_albedo(eta, alpha, mu):
    """int f(wo, wi) (eta_i / eta_o)^2 |cos theta_i| d wi over each side, estimated with wi
    drawn from the single-scattering lobe and cosines on both sides, equals the energy the
    analog walks leave on that side with, for each order: next-event estimation, the
    adjoint connection and their weights against the sampling of the walks themselves."""
    walk, lobe = MicrosurfaceDielectric(eta, alpha), Dielectric(eta, alpha)
    wo = sph(mu, 0.3)
    n = 60_000
    rng = np.random.default_rng(8)
    u, choice = rng.random((n, 3)), rng.random(n)
    sampled = lobe.sample(np.broadcast_to(wo, (n, 3)), u)
    cosine = sph(np.sqrt(u[:, 1]) * np.where(choice < 0.75, 1.0, -1.0), 2.0 * np.pi * u[:, 2])
    wi = np.where((choice < 0.5)[:, None] & (sampled.pdf > 0.0)[:, None], sampled.wi, cosine)
    pdf = (0.5 * lobe.pdf(np.broadcast_to(wo, wi.shape), wi)
           + 0.25 * np.abs(wi[:, 2]) / np.pi)
    result = walk.eval_orders(wo, wi, n_walks=2, seed=9)
    energy = np.where(wo[2] * wi[:, 2] < 0.0, (eta if wo[2] > 0.0 else 1.0 / eta) ** 2, 1.0)
    for order in ("single", "multiple"):
        albedo = walk.albedo(wo, n_walks=200_000, seed=10, order=order)
        for side, value, error in ((1.0, albedo.reflected, albedo.reflected_error),
                                   (-1.0, albedo.transmitted, albedo.transmitted_error)):
            here = wo[2] * wi[:, 2] * side > 0.0
            g = np.where(here, getattr(result, order)[:, 0] * energy * np.abs(wi[:, 2]) / pdf,
                         0.0)
            estimate, spread = g.mean(), g.std() / np.sqrt(n)
            assert abs(estimate - value[0]) < SIGMAS * np.hypot(spread, error[0]), (
                order, side, estimate, spread, value[0], error[0])


@pytest.mark.parametrize("eta, ax, ay", [(1.5, 0.5, 0.5), (1.33, 0.3, 0.6)])
def test_reciprocity(eta, ax, ay):
    """f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2, all orders, from independent walks."""
    wo, wi = pairs()
    walk = MicrosurfaceDielectric(eta, ax, ay)
    f, f_err = walk.eval(wo, wi, n_walks=20_000, seed=11, return_error=True)
    g, g_err = walk.eval(wi, wo, n_walks=20_000, seed=11, return_error=True)
    eta_o = np.where(wo[:, 2] > 0.0, 1.0, eta)[:, None] ** 2
    eta_i = np.where(wi[:, 2] > 0.0, 1.0, eta)[:, None] ** 2
    assert_within(f / eta_o - g / eta_i, np.hypot(f_err / eta_o, g_err / eta_i), 0.0)


def test_next_event_estimation_alone_agrees():
    """The two estimators of the multiple orders (mis=True, False) agree where the surface is
    rough enough for next-event estimation alone to be reliable."""
    wo, wi = pairs()
    walk = MicrosurfaceDielectric(1.5, 0.7)
    a = walk.eval_orders(wo, wi, n_walks=20_000, seed=12)
    b = walk.eval_orders(wo, wi, n_walks=20_000, seed=13, mis=False)
    assert_within(a.multiple - b.multiple, np.hypot(a.multiple_error, b.multiple_error), 0.0)
    assert np.all(a.multiple > 0.0)


def test_orders_add_up_and_eval_picks_them():
    wo, wi = sph(0.6, 0.0), sph([0.5, -0.5], 2.0)
    walk = MicrosurfaceDielectric(1.5, 0.5)
    result = walk.eval_orders(wo, wi, n_walks=2000, seed=14)
    np.testing.assert_allclose(result.single + result.multiple, result.all, rtol=1e-12)
    for order in ORDERS:
        value, error = walk.eval(wo, wi, n_walks=2000, seed=14, order=order, return_error=True)
        np.testing.assert_array_equal(value, getattr(result, order))
        np.testing.assert_array_equal(error, getattr(result, order + "_error"))
    np.testing.assert_array_equal(walk.eval(wo, wi, n_walks=2000, seed=14), result.all)


def test_reproducible_and_seeded():
    wo, wi = pairs()
    walk = MicrosurfaceDielectric(1.5, 0.5)
    a = walk.eval(wo, wi, n_walks=500, seed=15)
    np.testing.assert_array_equal(a, walk.eval(wo, wi, n_walks=500, seed=15))
    assert np.any(a != walk.eval(wo, wi, n_walks=500, seed=16))


def test_shapes_grazing_and_index_matched():
    walk = MicrosurfaceDielectric(1.5, 0.5)
    wo = sph(np.full((2, 3), 0.5), 0.0)
    assert walk.eval(wo, sph(0.7, 2.0), n_walks=4).shape == (2, 3, 3)
    grazing = np.array([1.0, 0.0, 0.0])
    assert np.all(walk.eval(grazing, sph(0.5, 1.0), n_walks=4) == 0.0)
    assert np.all(walk.eval(sph(0.5, 1.0), grazing, n_walks=4) == 0.0)
    assert np.all(walk.albedo(grazing, n_walks=4).reflected == 0.0)
    matched = MicrosurfaceDielectric(1.0, 0.5)
    a = matched.albedo(sph([0.9, 0.2, -0.4], 0.0), n_walks=1000)
    assert np.all(a.transmitted == 1.0) and np.all(a.reflected == 0.0)
    f = matched.eval(sph(0.5, 0.0), sph([-0.5, 0.5, -0.6], [np.pi, 0.0, 1.0]), n_walks=100)
    assert np.all(np.isfinite(f)) and np.all(f == 0.0)


# -- bad input -------------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs, name", [
    ({"eta": 0.0}, "eta"), ({"eta": np.nan}, "eta"), ({"eta": -1.5}, "eta"),
    ({"eta": [1.5, 1.6]}, "eta"), ({"eta": "1.5"}, "eta"),
    ({"alpha_x": 0.0}, "alpha_x"), ({"alpha_x": np.inf}, "alpha_x"),
    ({"alpha_y": -0.1}, "alpha_y"), ({"max_bounces": 0}, "max_bounces"),
    ({"max_bounces": 2.5}, "max_bounces")])
def test_bad_parameters(kwargs, name):
    args = {"eta": 1.5, "alpha_x": 0.3} | kwargs
    with pytest.raises(ValueError, match=name):
        MicrosurfaceDielectric(**args)


def test_bad_conductor_fresnel():
    with pytest.raises(ValueError, match="fresnel"):
        MicrosurfaceConductor(0.3, fresnel=0.9)


@pytest.mark.parametrize("call, name", [
    (lambda w: w.eval([0, 0, 2.0], [0, 0, 1.0]), "wo"),
    (lambda w: w.eval([0, 0, 1.0], [np.nan, 0, 1.0]), "wi"),
    (lambda w: w.eval([0, 1.0], [0, 0, 1.0]), "wo"),
    (lambda w: w.eval(sph([0.5] * 3, 0.0), sph([0.5] * 2, 0.0)), "wi"),
    (lambda w: w.eval([0, 0, 1.0], [0, 0, 1.0], n_walks=1), "n_walks"),
    (lambda w: w.eval([0, 0, 1.0], [0, 0, 1.0], seed=-1), "seed"),
    (lambda w: w.eval([0, 0, 1.0], [0, 0, 1.0], order="double"), "order"),
    (lambda w: w.eval([0, 0, 1.0], [0, 0, 1.0], return_error=1), "return_error"),
    (lambda w: w.eval_orders([0, 0, 1.0], [0, 0, 1.0], mis="yes"), "mis"),
    (lambda w: w.albedo([0, 0, 1.0], n_walks=0), "n_walks"),
    (lambda w: w.albedo([0, 0, 1.0], split="no"), "split"),
    (lambda w: w.albedo([0, 0, 1.0], order=2), "order"),
    (lambda w: visible_normal(w.distribution, [0, 0, 1.0], [0.5, 1.0]), "u2"),
    (lambda w: visible_normal(w.distribution, [0, 0, -1.0], [0.5, 0.5]), "w"),
    (lambda w: visible_normal(GGX([0.1, 0.2]), [0, 0, 1.0], [0.5, 0.5]), "distribution")])
def test_bad_arguments(call, name):
    with pytest.raises(ValueError, match=name):
        call(MicrosurfaceDielectric(1.5, 0.3))
