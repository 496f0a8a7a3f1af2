"""The stochastic layered reference against closed forms and independent random walks."""

import numpy as np
import pytest
from scipy import integrate

from adobe_bsdf.bsdf import Flags
from adobe_bsdf.fresnel import _dielectric
from adobe_bsdf.layered import LayeredReference, henyey_greenstein, sample_henyey_greenstein
from adobe_bsdf.lobes import Conductor, Dielectric, DielectricMS, Lambert, Sheen
from adobe_bsdf.media import half_space_albedo
from adobe_bsdf.phase import FibreMicroflakes

#: agreement within this many standard errors (the estimates are seeded: each check is fixed)
SIGMAS = 3.0


def sph(mu, phi):
    mu = np.asarray(mu, dtype=float)
    s = np.sqrt(1.0 - mu * mu)
    return np.stack(np.broadcast_arrays(s * np.cos(phi), s * np.sin(phi), mu), -1)


PAIRS = [(1.0, 1.0, 0.0), (0.5, 0.8, 2.0), (0.1, 0.9, 1.0), (0.9, 0.05, 3.0), (0.3, 0.3, np.pi)]


def pairs():
    mo, mi, phi = np.array(PAIRS).T
    return sph(mo, 0.0), sph(mi, phi)


def assert_within(estimate, error, expected, sigmas=SIGMAS):
    estimate, error, expected = np.broadcast_arrays(estimate, error, expected)
    bad = np.abs(estimate - expected) > sigmas * error
    assert not np.any(bad), (estimate[bad], error[bad], expected[bad])


def internal_average(eta, tau=0.0):
    """2 int_0^1 F(mu, 1/eta) exp(-2 tau / mu) mu d mu by scipy quadrature: the share of
    diffuse light inside a smooth coat of index eta (over an absorbing slab of optical
    thickness tau, both ways) that the coat sends back down."""
    mu_c = np.sqrt(1.0 - 1.0 / eta**2)
    value, _ = integrate.quad(lambda m: 2.0 * _dielectric(m, 1.0 / eta) * np.exp(-2.0 * tau / m)
                              * m, 0.0, 1.0, points=[mu_c], limit=200, epsabs=1e-13)
    return value


def refracted(mu, eta):
    return np.sqrt(1.0 - (1.0 - mu * mu) / eta**2)


def test_index_matched_coat_is_the_base():
    """Every walk goes straight in and out (no Monte-Carlo error to allow for)."""
    wo, wi = pairs()
    for base in (Lambert(0.7), Conductor(0.3)):
        f = LayeredReference(Dielectric(1.0, 0.0), base, n_samples=16).eval(wo, wi)
        np.testing.assert_allclose(f, base.eval(wo, wi), rtol=1e-12, atol=0)


def test_index_matched_absorbing_slab_is_beer_lambert():
    """No reflection at the top: one bounce off the base, exp(-tau / mu) each way."""
    wo, wi = pairs()
    tau, rho = 0.4, 0.6
    layer = LayeredReference(Dielectric(1.0, 0.0), Lambert(rho), thickness=tau, n_samples=8)
    f, err = layer.eval_with_error(wo, wi)
    expected = rho / np.pi * np.exp(-tau * (1.0 / wo[:, 2] + 1.0 / wi[:, 2]))
    np.testing.assert_allclose(f, np.repeat(expected[:, None], 3, 1), rtol=1e-12)


@pytest.mark.parametrize("eta, rho, tau", [(1.5, 0.8, 0.0), (1.33, 0.3, 0.0), (2.0, 1.0, 0.0),
                                           (1.5, 0.9, 0.3), (1.5, 1.0, (0.0, 0.3, 1.2))])
def test_smooth_coat_over_lambert_is_the_plastic_formula(eta, rho, tau):
    """f = (1 - F(wo))(1 - F(wi)) rho T(wo) T(wi) / (pi eta^2 (1 - rho F_int)), the internal
    reflections summed as a geometric series (T = exp(-tau / mu_t) along the refracted
    cosines; F_int the hemispherical average of internal reflection, times T^2); per channel
    where the absorbing slab is coloured."""
    wo, wi = pairs()
    layer = LayeredReference(Dielectric(eta, 0.0), Lambert(rho), thickness=tau, n_samples=4096)
    f, err = layer.eval_with_error(wo, wi)
    mo, mi = wo[:, 2:3], wi[:, 2:3]
    tau = np.broadcast_to(tau, (3,))
    T = np.exp(-tau * (1.0 / refracted(mo, eta) + 1.0 / refracted(mi, eta)))
    expected = ((1.0 - _dielectric(mo, eta)) * (1.0 - _dielectric(mi, eta)) * rho * T
                / (np.pi * eta**2 * (1.0 - rho * np.array([internal_average(eta, t)
                                                           for t in tau]))))
    assert np.all(err > 0.0)
    assert_within(f, err, expected)


def test_smooth_coat_over_white_lambert_conserves_energy():
    layer = LayeredReference(Dielectric(1.5, 0.0), Lambert(1.0))
    for mu in (1.0, 0.5, 0.05):
        E, err = layer.albedo(sph(mu, 0.3), method="mc", n_samples=20_000, return_error=True)
        assert_within(E, err + 1e-12, 1.0)


def test_rough_energy_conserving_coat_over_white_lambert_conserves_energy():
    """An energy-conserving rough coat (Kulla–Conty compensated, to its tables' 2e-3) over a
    white base: every walk ends outside."""
    layer = LayeredReference(DielectricMS(1.5, 0.5), Lambert(1.0))
    E, err = layer.albedo(sph(np.array([0.9, 0.4]), 0.0), method="mc", n_samples=20_000,
                          return_error=True)
    assert np.all(np.abs(E - 1.0) <= 2e-3 + SIGMAS * err)


def test_thickness_zero_is_no_slab():
    wo, wi = pairs()
    top, base = Dielectric(1.5, 0.3), Lambert(0.8)
    plain = LayeredReference(top, base, n_samples=512)
    f0, e0 = plain.eval_with_error(wo, wi)
    zero = LayeredReference(top, base, thickness=0.0, medium_albedo=0.7, g=0.5, n_samples=512)
    np.testing.assert_array_equal(zero.eval(wo, wi), f0)
    thin = LayeredReference(top, base, thickness=1e-9, medium_albedo=0.7, g=0.5, n_samples=512,
                            seed=1)
    f1, e1 = thin.eval_with_error(wo, wi)
    assert_within(f1 - f0, np.hypot(e0, e1), 0.0)


def test_thick_scattering_slab_is_the_half_space():
    """An index-matched slab 40 mean free paths deep over a black base reflects as the
    half-space of ``media.half_space_albedo`` (an independent random walk)."""
    a = 0.8
    layer = LayeredReference(Dielectric(1.0, 0.0), Lambert(0.0), thickness=40.0,
                             medium_albedo=a)
    E, err = layer.albedo(np.array([0.0, 0.0, 1.0]), method="mc", n_samples=100_000,
                          return_error=True)
    ref = half_space_albedo(a, n_paths=200_000, incidence="normal", seed=3)
    assert_within(E[0], np.hypot(err[0], ref.std_error), ref.value)


def _band_integral(layer, wo, lo, hi, n=24):
    """int over mu_i in (lo, hi] of eval |cos| d omega by Gauss–Legendre x midpoint azimuths,
    with its Monte-Carlo standard error."""
    x, w = np.polynomial.legendre.leggauss(n)
    mu, w = lo + (hi - lo) * (x + 1.0) / 2.0, w * (hi - lo) / 2.0
    phi = (np.arange(n) + 0.5) * 2.0 * np.pi / n
    M, P = np.meshgrid(mu, phi, indexing="ij")
    f, err = layer.eval_with_error(wo, sph(M, P).reshape(-1, 3))
    weight = (w[:, None] * M * 2.0 * np.pi / n).reshape(-1, 1)
    return (f * weight).sum(0), np.sqrt(((err * weight) ** 2).sum(0))


@pytest.mark.parametrize("layer", [
    LayeredReference(Dielectric(1.5, 0.0), Conductor(0.4), n_samples=32),
    LayeredReference(Dielectric(1.5, 0.0), Lambert(0.0), thickness=1.0, medium_albedo=0.9,
                     g=-0.3, n_samples=32),
    LayeredReference(Dielectric(1.3, 0.5), Lambert(0.5), thickness=0.5, medium_albedo=0.8,
                     g=0.5, n_samples=32),
    LayeredReference(Dielectric(2.0, 0.36), Lambert(1.0), n_samples=32),
], ids=["smooth coat, rough metal", "smooth coat, scattering slab", "rough coat, slab, Lambert",
        "rough coat of index 2, white Lambert"])
def test_eval_agrees_with_sample(layer):
    """The walk's estimate of f (next events weighed by the power heuristic) and the walk
    sampler's weights integrate to the same energy in two bands of mu_i."""
    wo = sph(0.6, 0.3)
    n = 200_000
    s = layer.sample(np.broadcast_to(wo, (n, 3)), np.random.default_rng(1).random((n, 3)))
    smooth = (s.flags & int(Flags.DELTA)) == 0
    for lo, hi in ((0.0, 0.5), (0.5, 1.0)):
        f_int, f_err = _band_integral(layer, wo, lo, hi)
        inside = smooth & (s.wi[:, 2] > lo) & (s.wi[:, 2] <= hi)
        v = np.where(inside[:, None], s.weight, 0.0)
        mc, mc_err = v.mean(0), v.std(0) / np.sqrt(n)
        # the 24 x 24 rule of a lobe of roughness 0.5: below 1e-3 relative (measured in the
        # test's development at 48 x 48)
        assert_within(f_int, np.hypot(f_err, mc_err) + 1e-3 * mc, mc)


def test_reciprocal_within_its_error():
    layer = LayeredReference(Dielectric(1.5, 0.3), Lambert(0.8), thickness=0.3,
                             medium_albedo=0.6, n_samples=2048)
    wo, wi = pairs()
    f, e = layer.eval_with_error(wo, wi)
    r, er = layer.eval_with_error(wi, wo)
    assert_within(f - r, np.hypot(e, er), 0.0)


def test_a_plate_transmits_and_reflects_everything():
    """Two smooth interfaces (into glass and out of it): R + T = 1, and at normal incidence
    T = (1 - F)^2 / (1 - F^2) = (1 - F) / (1 + F) (the sum of internal reflections)."""
    plate = LayeredReference(Dielectric(1.5, 0.0), Dielectric(1.0 / 1.5, 0.0), n_samples=4000)
    assert plate.flags & Flags.TRANSMISSION and plate.flags & Flags.DELTA
    assert not plate.flags & Flags.GLOSSY
    assert plate.eta == pytest.approx(1.0)
    normal = np.array([[0.0, 0.0, 1.0]])
    np.testing.assert_allclose(plate._delta_albedo(normal), 1.0, atol=1e-12)
    n = 100_000
    s = plate.sample(np.broadcast_to(normal, (n, 3)), np.random.default_rng(2).random((n, 3)))
    T = np.where(s.wi[:, 2] < 0.0, s.weight[:, 0], 0.0)
    F = ((1.5 - 1.0) / 2.5) ** 2
    assert abs(T.mean() - (1.0 - F) / (1.0 + F)) <= SIGMAS * T.std() / np.sqrt(n)


@pytest.mark.parametrize("g", [-0.7, 0.0, 0.4, 0.95])
def test_henyey_greenstein_is_a_density_sampled_exactly(g):
    wo = np.array([0.3, -0.2, np.sqrt(1 - 0.13)])
    value, _ = integrate.dblquad(
        lambda phi, c: henyey_greenstein(wo, _about(-wo, c, phi), g), -1.0, 1.0, 0.0,
        2.0 * np.pi, epsabs=1e-10)
    assert value == pytest.approx(1.0, abs=1e-7)
    n = 200_000
    wi, pdf = sample_henyey_greenstein(np.broadcast_to(wo, (n, 3)),
                                       np.random.default_rng(4).random((n, 2)), g)
    np.testing.assert_allclose(np.linalg.norm(wi, axis=-1), 1.0, atol=1e-12)
    np.testing.assert_allclose(pdf, henyey_greenstein(wo, wi, g), rtol=1e-12)
    c = wi @ -wo  # the mean cosine about the travel direction is g
    assert abs(c.mean() - g) <= 4.0 * c.std() / np.sqrt(n)


def _about(d, c, phi):
    """The direction at cosine c and azimuth phi about unit d."""
    t = np.cross(d, [1.0, 0.0, 0.0] if abs(d[0]) < 0.9 else [0.0, 1.0, 0.0])
    t /= np.linalg.norm(t)
    b = np.cross(d, t)
    s = np.sqrt(max(0.0, 1.0 - c * c))
    return s * np.cos(phi) * t + s * np.sin(phi) * b + c * d


def test_pdf_is_positive_where_eval_is_and_zero_below_an_opaque_base():
    layer = LayeredReference(Dielectric(1.5, 0.3), Lambert(0.8), n_samples=16)
    wo, wi = pairs()
    f, pdf = layer.eval_pdf(wo, wi)
    assert np.all(pdf > 0.0) and np.all(np.isfinite(pdf))
    below = wi * np.array([1.0, 1.0, -1.0])
    np.testing.assert_array_equal(layer.pdf(wo, below), 0.0)
    np.testing.assert_array_equal(layer.eval(wo, below), 0.0)
    np.testing.assert_array_equal(layer.eval(below, wi), 0.0)


def test_extreme_directions_give_finite_values():
    layer = LayeredReference(Dielectric(1.5, 0.2), Conductor(0.1), thickness=0.2,
                             medium_albedo=0.5, n_samples=8)
    tiny = 5e-324
    wo = np.array([[1.0, 0.0, tiny], [0.0, 0.0, 1.0], [1.0, 0.0, 1e-8], [0.6, 0.0, 0.8]])
    wi = np.array([[-1.0, 0.0, tiny], [0.0, 0.0, 1.0], [-1.0, 0.0, 1e-8], [0.0, 0.0, -1.0]])
    f, pdf = layer.eval_pdf(wo, wi)
    assert np.all(np.isfinite(f)) and np.all(f >= 0.0)
    assert np.all(np.isfinite(pdf)) and np.all(pdf >= 0.0)
    s = layer.sample(wo, np.random.default_rng(0).random((4, 3)))
    assert np.all(np.isfinite(s.weight)) and np.all(s.weight >= 0.0)


def test_quadrature_albedo_is_refused():
    layer = LayeredReference(Dielectric(1.5, 0.3), Lambert(0.8))
    with pytest.raises(ValueError, match="method='mc'"):
        layer.albedo(np.array([0.0, 0.0, 1.0]))


@pytest.mark.parametrize("kwargs, message", [
    ({"thickness": -1.0}, "thickness = -1.0"),
    ({"thickness": np.inf}, "thickness = inf"),
    ({"medium_albedo": 1.5}, "medium_albedo = 1.5"),
    ({"g": 1.0}, "g = 1.0"),
    ({"n_samples": 0}, "n_samples = 0"),
    ({"max_depth": 2.5}, "max_depth = 2.5"),
    ({"seed": -1}, "seed = -1"),
    ({"medium_albedo": np.ones((2, 3))}, "medium_albedo has shape"),
    ({"thickness": np.ones((2, 3))}, "thickness has shape"),
    ({"thickness": (0.1, 0.2, 0.3), "medium_albedo": 0.5},
     "thickness = .0.1, 0.2, 0.3. is a colour; allowed: a colour only where the slab does "
     "not scatter"),
])
def test_bad_input(kwargs, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(")):
        LayeredReference(Dielectric(1.5, 0.3), Lambert(0.8), **kwargs)


def test_bad_lobes():
    with pytest.raises(ValueError, match="top = 'glass'"):
        LayeredReference("glass", Lambert(0.8))
    with pytest.raises(ValueError, match=r"has parameters of shape \(4,\)"):
        LayeredReference(Dielectric(1.5, 0.3), Lambert(np.full((4, 3), 0.5)))


def test_memory_is_bounded_whatever_the_batch():
    """The walks run in blocks of about ``config`` ``chunk_size``: four times the pairs, the
    same peak."""
    import tracemalloc

    layer = LayeredReference(Dielectric(1.5, 0.3), Lambert(0.8), thickness=0.2,
                             medium_albedo=0.5, n_samples=64)
    rng = np.random.default_rng(0)
    peaks = []
    for n in (2000, 8000):
        wo, wi = (sph(rng.random(n), 2.0 * np.pi * rng.random(n)) for _ in range(2))
        tracemalloc.start()
        layer.eval(wo, wi)
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    assert peaks[1] < 1.2 * peaks[0] + 2e6, peaks


def test_eval_keeps_the_energy_of_an_energy_conserving_coat():
    """int eval |cos| over the hemisphere (the light through the coat) plus the coat's own
    reflection (its samples) is 1 for a white base under a lossless rough coat of index 2
    (mostly internally reflected: many bounces), to the coat's tables (2e-3) and the
    estimates' errors."""
    top = DielectricMS(2.0, 0.36)
    layer = LayeredReference(top, Lambert(1.0), n_samples=1024)
    wo = sph(1.0, 0.0)
    through, err = _band_integral(layer, wo, 0.0, 1.0)
    x, w = np.polynomial.legendre.leggauss(24)
    mu = (x + 1.0) / 2.0
    M, P = np.meshgrid(mu, (np.arange(24) + 0.5) * 2.0 * np.pi / 24, indexing="ij")
    wi = sph(M, P).reshape(-1, 3)
    weight = (w[:, None] / 2.0 * M * 2.0 * np.pi / 24).reshape(-1, 1)
    through = through - (top.eval(wo, wi) * weight).sum(0)
    n = 400_000
    s = top.sample(np.broadcast_to(wo, (n, 3)), np.random.default_rng(7).random((n, 3)))
    r = np.where(s.wi[:, 2:3] > 0.0, s.weight, 0.0)
    R, R_err = r.mean(0), r.std(0) / np.sqrt(n)
    assert np.all(np.abs(through + R - 1.0) <= 2e-3 + SIGMAS * np.hypot(err, R_err)), (
        through + R, err, R_err)


def test_walk_is_sample_without_the_pdf_estimate():
    layer = LayeredReference(Dielectric(1.5, 0.3), Lambert(0.8), thickness=0.2,
                             medium_albedo=0.5, n_samples=8)
    wo = np.broadcast_to(sph(0.7, 0.2), (500, 3))
    u = np.random.default_rng(9).random((500, 3))
    s, w = layer.sample(wo, u), layer.walk(wo, u)
    np.testing.assert_array_equal(w.wi, s.wi)
    np.testing.assert_array_equal(w.weight, s.weight)
    np.testing.assert_array_equal(w.flags, s.flags)
    assert np.all((w.pdf > 0.0) == (s.pdf > 0.0))


# -- a slab of fibre microflakes (the fuzz) -----------------------------------------------------
@pytest.mark.parametrize("r", [0.2, 0.6, 1.0])
def test_single_scattering_by_fibre_flakes_is_the_sheen_formula(r):
    """One scattering in a slab of optical thickness 1 over a black base, the walks cut after
    their first event: f = D(h) G / (4 cos_i cos_o), G = (1 - exp(-(Lambda_i + Lambda_o))) /
    (Lambda_i + Lambda_o), the single scattering [Kutz2021, eqs. 15-18] writes in closed form
    (``Sheen`` with c = 1, p = 1)."""
    wo, wi = pairs()
    layer = LayeredReference(Dielectric(1.0, 0.0), Lambert(0.0), thickness=1.0,
                             medium_albedo=1.0, phase=FibreMicroflakes(r), max_depth=1,
                             n_samples=4096)
    f, err = layer.eval_with_error(wo, wi)
    expected = Sheen(1.0, r, c=1.0, p=1.0).eval(wo, wi)
    assert np.all(err > 0.0)
    assert_within(f, err, expected)


@pytest.mark.parametrize("r", [0.1, 0.5])
def test_white_fibre_flakes_over_a_white_base_keep_the_energy(r):
    layer = LayeredReference(Dielectric(1.0, 0.0), Lambert(1.0), thickness=1.0,
                             medium_albedo=1.0, phase=FibreMicroflakes(r))
    E, err = layer.albedo(sph(np.array([1.0, 0.3, 0.02]), 0.4), method="mc", n_samples=20_000,
                          return_error=True)
    assert_within(E, err + 1e-12, 1.0)


def test_a_phase_object_is_checked():
    with pytest.raises(ValueError, match="phase = 'fog'"):
        LayeredReference(Dielectric(1.5, 0.3), Lambert(0.8), phase="fog")
    with pytest.raises(ValueError, match="g = 0.3 with phase"):
        LayeredReference(Dielectric(1.5, 0.3), Lambert(0.8), g=0.3,
                         phase=FibreMicroflakes(0.5))


# -- layers over layers: a stochastic base ------------------------------------------------------
def _stochastic_lambert(rho):
    """Lambert(rho) under an index-matched smooth top: the same BSDF, as a random walk."""
    return LayeredReference(Dielectric(1.0, 0.0), Lambert(rho), n_samples=1)


def test_a_smooth_coat_over_a_stochastic_base_is_the_plastic_formula():
    wo, wi = pairs()
    eta, rho = 1.5, 0.8
    layer = LayeredReference(Dielectric(eta, 0.0), _stochastic_lambert(rho), n_samples=4096)
    assert not layer.base.weight_is_ratio
    f, err = layer.eval_with_error(wo, wi)
    mo, mi = wo[:, 2:3], wi[:, 2:3]
    expected = ((1.0 - _dielectric(mo, eta)) * (1.0 - _dielectric(mi, eta)) * rho
                / (np.pi * eta**2 * (1.0 - rho * internal_average(eta))))
    assert np.all(err > 0.0)
    assert_within(f, err, expected)


def test_a_rough_coat_over_a_stochastic_base_is_the_same_layer():
    """The two estimates (one over the lobe, one over the same lobe as a walk) agree within
    their combined errors; a white one keeps the energy, its walks nested."""
    wo, wi = pairs()
    top = DielectricMS(1.5, 0.3)
    direct = LayeredReference(top, Lambert(0.7), n_samples=2048)
    nested = LayeredReference(top, _stochastic_lambert(0.7), n_samples=2048, seed=5)
    (f1, e1), (f2, e2) = direct.eval_with_error(wo, wi), nested.eval_with_error(wo, wi)
    assert_within(f2 - f1, np.hypot(e1, e2), 0.0)
    white = LayeredReference(top, _stochastic_lambert(1.0))
    E, err = white.albedo(sph(np.array([0.9, 0.2]), 0.0), method="mc", n_samples=20_000,
                          return_error=True)
    assert np.all(np.abs(E - 1.0) <= 2e-3 + SIGMAS * err)


def _hemisphere_rule(sign, n_mu=24, n_phi=48):
    """Directions ``(n, 3)`` on the hemisphere of ``sign`` and weights |cos| dw of a
    Gauss–Legendre rule in mu times the midpoint rule in phi."""
    x, w = np.polynomial.legendre.leggauss(n_mu)
    mu, phi = sign * (x + 1.0) / 2.0, (np.arange(n_phi) + 0.5) * 2.0 * np.pi / n_phi
    M, P = np.meshgrid(mu, phi, indexing="ij")
    weights = np.abs(M) * (w / 2.0)[:, None] * 2.0 * np.pi / n_phi
    return sph(M, P).reshape(-1, 3), weights.reshape(-1, 1)


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_transmission_eval_integrates_to_the_walks_transmission(side):
    """Through two rough interfaces and a scattering slab, entered from above or (through
    the base: ``twin``) from below: the transmitted energy integrated from ``eval`` over the
    other hemisphere (a 24 x 48 rule, whose error against 48 x 96 is below 3e-3) equals the
    walks' (``walk``). Both strategies of the path that crosses once (TT) count: without
    them ``eval`` missed 0.64 of the 0.75 here."""
    layer = LayeredReference(DielectricMS(1.5, 0.5, 0.5), DielectricMS(1.3, 0.4, 0.7),
                             thickness=0.3, medium_albedo=0.5, n_samples=256)
    wo = np.array([0.6, 0.0, 0.8 * side])
    wi, weights = _hemisphere_rule(-side)
    wo_b = np.broadcast_to(wo, wi.shape)
    f, err = layer.eval_with_error(wo_b, wi)
    scale = layer._energy_scale_rgb(wo_b, wi)
    T, se = (f * scale * weights).sum(0), np.sqrt(((err * scale * weights) ** 2).sum(0))
    n = 200_000
    s = layer.walk(np.broadcast_to(wo, (n, 3)), np.random.default_rng(4).random((n, 3)))
    through = (s.wi[:, 2] * side < 0.0)[:, None]
    x = np.where(through, s.weight * layer._energy_scale_rgb(np.broadcast_to(wo, (n, 3)),
                                                             s.wi), 0.0)
    walks, walks_se = x.mean(0), x.std(0) / np.sqrt(n)
    assert walks[0] > 0.1  # 0.75 from above, 0.2 from the dense side below
    assert np.all(np.abs(T - walks) <= 3e-3 + 4.0 * np.hypot(se, walks_se)), (T, walks, se)
