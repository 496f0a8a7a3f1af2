"""The development branch's physical coat darkening ("dev_1.2", ``darkening.physical_darkening``)
against independent references: random walks of light through an absorbing coat
(``layered.LayeredReference`` over the energy-conserving ``DielectricMS``) onto a Lambertian
or a mirror base, and the closed forms of a smooth coat integrated by scipy."""

import functools
import itertools

import numpy as np
import pytest
from scipy import integrate

from adobe_bsdf import darkening as dk
from adobe_bsdf import fresnel
from adobe_bsdf.composition import Layer
from adobe_bsdf.darkening import Darkening, physical_darkening
from adobe_bsdf.fresnel import F82Tint, Weighted
from adobe_bsdf.layered import LayeredReference
from adobe_bsdf.lobes import Conductor, DielectricMS, DielectricReflection, Lambert
from adobe_bsdf.lobes.kulla_conty import DielectricMultipleScattering

#: the coat colour of the walks (two-way transmittance at normal incidence)
TINT = (0.3, 0.55, 0.85)
#: the model against the walks: its own error (measured within 4e-3,
#: docs/coat_darkening_measured.md) plus this many standard errors of the walk
MODEL_TOL, SIGMAS = 1e-2, 3.0
#: the layer built as the material builds it (its top is the single-scattering reflection,
#: the walk's the energy-conserving interface's)
LAYER_TOL = 2e-2
#: walks per colour channel
WALKS = 60_000


def _wo(mu):
    mu = np.asarray(mu, dtype=float)
    return np.stack([np.sqrt(1.0 - mu * mu), np.zeros_like(mu), mu], -1)


@functools.cache
def _walk(eta, alpha, E_b, mu, base="lambert", walks=WALKS):
    """``(albedo, standard error)`` ``(3,)`` of random walks entering at cos theta_o = ``mu``
    through an energy-conserving rough interface (``DielectricMS``) over a slab that only
    absorbs, of optical depth -ln(T) / 2 per channel (two-way transmittance T at normal
    incidence), over a Lambertian or a mirror base of albedo ``E_b``."""
    out, err = np.zeros(3), np.zeros(3)
    w = np.broadcast_to(_wo(mu), (walks, 3))
    for c, T in enumerate(TINT):
        bottom = (Lambert(E_b) if base == "lambert" else
                  Conductor(0.0, fresnel=Weighted(F82Tint(1.0, 1.0), E_b)))
        ref = LayeredReference(DielectricMS(eta, alpha), bottom, thickness=-np.log(T) / 2.0)
        s = ref.walk(w, np.random.default_rng([7, c]).random((walks, 3)))
        assert np.all(s.wi[s.pdf > 0.0, 2] > 0.0)  # an opaque base: every exit is upwards
        e = s.weight[:, 0]
        out[c], err[c] = e.mean(), e.std() / np.sqrt(walks)
    return out, err


def _top_reflection(eta, alpha, mu):
    """The energy the walk's top reflects at cos theta_o = ``mu``: the GGX single scattering
    plus the reflected share of the Kulla–Conty term (``DielectricMS``'s own split)."""
    wo = _wo(mu)
    E = DielectricReflection(eta, alpha).albedo(wo, method="table")
    if alpha == 0.0:
        return E
    ms = DielectricMultipleScattering(eta, alpha)
    return E + ms._albedo_table(wo)[0] * ms._reflect_probability(wo)[..., None]


def _assert_model_is_the_walk(eta, alpha, E_b, mu, base):
    """E_top + (1 - E_top) T2 Delta_phys E_b, with the walk's own top reflection E_top, is the
    walk's albedo."""
    r_b = 1.0 if base == "lambert" else 0.0
    walk, sigma = _walk(eta, alpha, E_b, mu, base)
    R = _top_reflection(eta, alpha, mu)
    model = R + (1.0 - R) * np.asarray(TINT) * E_b * physical_darkening(
        E_b, eta, alpha, TINT, mu, r_b)
    assert np.all(np.abs(model - walk) <= MODEL_TOL + SIGMAS * sigma), (model, walk, sigma)


CASES = list(itertools.product([1.3, 1.5, 2.0], [0.0, 0.09, 0.25], [1.0, 0.5])) + [
    (1.0 / 1.5, 0.25, 1.0), (1.0 / 1.5, 0.09, 0.5)]


@pytest.mark.parametrize(("eta", "alpha", "E_b"), CASES)
def test_lambertian_base_is_the_random_walk(eta, alpha, E_b):
    """Near normal incidence (cos 0.95), coat IOR 1.3 / 1.5 / 2 / 1 / 1.5, smooth and rough
    (coat roughness 0.3, 0.5), tinted: the model is the walk; and where the coat is the
    denser side, the layer built as the material builds it (DielectricReflection top,
    transmittance T2, scaling "albedo") is within 0.02 of it. (Seen from the dense side
    the single-scattering top reflects far less than the energy-conserving interface, a
    difference of the top, not of the darkening.)"""
    mu = 0.95
    _assert_model_is_the_walk(eta, alpha, E_b, mu, "lambert")
    if eta < 1.0:  # the single-scattering top misses what the walk's reflects (0.06 here)
        return
    layer = Layer(DielectricReflection(eta, alpha), Lambert(E_b), transmittance=TINT,
                  darkening=Darkening(1.0, 1.0, "dev_1.2", coat_alpha=alpha))
    walk, _ = _walk(eta, alpha, E_b, mu)
    assert np.all(np.abs(layer.albedo(_wo(mu), tol=1e-6) - walk) <= LAYER_TOL)


@pytest.mark.parametrize(("alpha", "E_b"), itertools.product([0.0, 0.09, 0.25], [1.0, 0.5]))
def test_mirror_base_is_the_random_walk(alpha, E_b):
    """A mirror base (r_b = 0) of albedo E_b under a smooth or rough tinted coat of IOR 1.5."""
    _assert_model_is_the_walk(1.5, alpha, E_b, 0.95, "mirror")


@pytest.mark.slow
@pytest.mark.parametrize(("eta", "alpha", "E_b", "mu", "base"), itertools.product(
    [1.3, 1.5, 2.0, 1.0 / 1.5, 0.5], [0.0, 0.09, 0.25, 1.0], [1.0, 0.5, 0.2], [0.95, 0.6, 0.3],
    ["lambert", "mirror"]))
def test_sweep_is_the_random_walk(eta, alpha, E_b, mu, base):
    """Every angle, roughness up to alpha 1, both sides of the interface."""
    _assert_model_is_the_walk(eta, alpha, E_b, mu, base)


def _internal(eta, g):
    """int_0^1 g(mu, F(mu, 1 / eta)) d mu by scipy quadrature (split at the critical
    cosine)."""
    points = [np.sqrt(1.0 - 1.0 / eta**2)] if eta > 1.0 else None
    value, _ = integrate.quad(lambda m: g(m, float(fresnel.dielectric(m, 1.0 / eta))), 0.0,
                              1.0, points=points, limit=400, epsabs=1e-13, epsrel=1e-12)
    return value


@pytest.mark.parametrize("eta", [1.3, 2.0, 1.0 / 1.5])
def test_smooth_coat_is_the_summed_series(eta):
    """A smooth coat, T2 and E_b coloured, t(mu) = T2^(1 / (2 mu)) one way: over a
    Lambertian base Delta = t(mu_t) A / (T2 (1 - E_b K_T)), A = int 2 mu t (1 - R),
    K_T = int 2 mu t^2 R; over a mirror T2^(1 / mu_t - 1) (1 - F) / (1 - F E_b T2^(1 / mu_t))
    (scipy quadrature, both sides of the interface)."""
    T2, E_b = np.array(TINT), np.array([0.9, 0.5, 0.2])
    mu_o = np.array([1.0, 0.9, 0.5, 0.2])
    mu_t = np.sqrt(np.maximum(1.0 - (1.0 - mu_o**2) / eta**2, 0.0))
    F = fresnel.dielectric(mu_o, eta)[:, None]
    for c in range(3):
        A = _internal(eta, lambda m, R, c=c: 2.0 * m * T2[c] ** (0.5 / m) * (1.0 - R))
        K = _internal(eta, lambda m, R, c=c: 2.0 * m * T2[c] ** (1.0 / m) * R)
        with np.errstate(divide="ignore"):
            lam = T2[c] ** (0.5 / mu_t) * A / (T2[c] * (1.0 - E_b[c] * K))
            t2 = T2[c] ** (1.0 / mu_t)
        mirror = t2 / T2[c] * (1.0 - F[:, 0]) / (1.0 - F[:, 0] * E_b[c] * t2)
        np.testing.assert_allclose(physical_darkening(E_b, eta, 0.0, T2, mu_o, 1.0)[:, c],
                                   lam, rtol=0, atol=1e-10)
        np.testing.assert_allclose(physical_darkening(E_b, eta, 0.0, T2, mu_o, 0.0)[:, c],
                                   mirror, rtol=0, atol=1e-12)
        np.testing.assert_allclose(physical_darkening(E_b, eta, 0.0, T2, mu_o, 0.3)[:, c],
                                   0.7 * mirror + 0.3 * lam, rtol=0, atol=1e-10)


@pytest.mark.parametrize("eta", [1.3, 1.5, 2.0, 1.0 / 1.5])
def test_smooth_clear_coat_is_the_released_formula(eta):
    """T2 = 1: Delta = (1 - K) / (1 - E_b K) with K the internal average (rough base) or
    F(mu_o) (smooth base), the released specification's [OpenPBR2026, §Coat darkening]."""
    K = _internal(eta, lambda m, R: 2.0 * m * R)
    mu = np.array([1.0, 0.7, 0.3, 0.05])
    F = fresnel.dielectric(mu, eta)
    for E_b in (0.0, 0.4, 1.0):
        np.testing.assert_allclose(physical_darkening(E_b, eta, 0.0, 1.0, mu, 1.0),
                                   (1.0 - K) / (1.0 - E_b * K), rtol=0, atol=1e-10)
        with np.errstate(invalid="ignore"):
            smooth = np.where(F < 1.0, (1.0 - F) / (1.0 - E_b * F), 0.0)
        np.testing.assert_allclose(physical_darkening(E_b, eta, 0.0, 1.0, mu, 0.0)[F < 1.0],
                                   np.repeat(smooth[F < 1.0, None], 3, 1), rtol=0, atol=1e-12)


@pytest.mark.parametrize("alpha", [0.0, 0.01, 0.25, 1.0])
def test_a_lossless_base_under_a_clear_coat_loses_nothing(alpha):
    """E_b = 1, T2 = 1: Delta = 1 for any base roughness (the interface conserves energy):
    the white furnace holds at coat_darkening 1."""
    mu, r_b = np.linspace(0.0, 1.0, 21), np.array([[0.0], [0.4], [1.0]])
    for eta in (1.5, 1.0 / 1.5, 3.0):
        np.testing.assert_allclose(physical_darkening(1.0, eta, alpha, 1.0, mu, r_b), 1.0,
                                   rtol=0, atol=1e-9)
    layer = Layer(DielectricReflection(1.5, alpha), Lambert(1.0),
                  darkening=Darkening(1.0, 1.0, "dev_1.2", coat_alpha=alpha))
    np.testing.assert_allclose(layer.albedo(_wo(np.array([1.0, 0.5])), tol=1e-7), 1.0,
                               atol=2e-3)


def test_no_darkening_is_the_naive_albedo():
    """coat_darkening 0: the layer is the one without darkening, bit for bit, and its albedo
    E_coat + T2 E_b (1 - E_coat) [Portsmouth2025]."""
    T2, E_b = np.array(TINT), np.array([0.7, 0.4, 0.9])
    rng = np.random.default_rng(3)
    wo, wi = rng.normal(size=(2, 500, 3))
    wo[:, 2], wi[:, 2] = np.abs(wo[:, 2]), np.abs(wi[:, 2])
    wo, wi = (v / np.linalg.norm(v, axis=-1, keepdims=True) for v in (wo, wi))
    for alpha in (0.0, 0.09):
        top = DielectricReflection(1.5, alpha)
        plain = Layer(top, Lambert(E_b), 0.8, T2)
        dark = Layer(top, Lambert(E_b), 0.8, T2,
                     darkening=Darkening(0.0, 0.5, "dev_1.2", coat_alpha=alpha))
        np.testing.assert_array_equal(dark.eval(wo, wi), plain.eval(wo, wi))
    layer = Layer(DielectricReflection(1.5, 0.0), Lambert(E_b), transmittance=T2,
                  darkening=Darkening(0.0, 1.0, "dev_1.2"))
    n = np.array([0.0, 0.0, 1.0])
    F0 = float(fresnel.dielectric(1.0, 1.5))
    np.testing.assert_allclose(layer.albedo(n, tol=1e-9), F0 + T2 * E_b * (1.0 - F0),
                               atol=1e-8)


def test_delta_lerps_and_the_darkening_never_adds_energy():
    """D = lerp(1, Delta, delta) <= 1; a white base under a grey coat is not shifted in hue."""
    mu = np.linspace(0.0, 1.0, 41)
    for alpha, eta in itertools.product([0.0, 0.25], [1.5, 1.0 / 1.3]):
        coat = dk.CoatTransport(eta, alpha, TINT, (0.9, 0.5, 0.1))
        ends = [Darkening(d, 0.6, "dev_1.2", coat_alpha=alpha).factor(
            eta, mu, None, None, coat) for d in (0.0, 0.5, 1.0)]
        np.testing.assert_array_equal(ends[0], 1.0)
        np.testing.assert_allclose(ends[1], 0.5 * (ends[0] + ends[2]), rtol=1e-15)
        assert np.all((ends[2] >= 0.0) & (ends[2] <= 1.0))
        grey = physical_darkening(1.0, eta, alpha, 0.6, mu, 0.6)
        assert np.all(np.ptp(grey, axis=-1) == 0.0) and np.all(grey <= 1.0)


def test_textures_are_the_elements():
    """Parameters as arrays (textures) give each element's scalar result."""
    eta = np.array([[1.5], [1.0 / 1.3]])
    alpha = np.array([0.0, 0.09, 0.3])
    T2 = np.array([[0.2, 0.6, 0.9], [1.0, 0.5, 0.0], [0.3, 0.3, 0.3]])
    E_b, mu, r_b = 0.7, np.array([[0.9], [0.4]]), np.array([0.0, 0.5, 1.0])
    D = physical_darkening(E_b, eta, alpha, T2, mu, r_b)
    assert D.shape == (2, 3, 3)
    for i, j in itertools.product(range(2), range(3)):
        np.testing.assert_allclose(D[i, j], physical_darkening(
            E_b, eta[i, 0], alpha[j], T2[j], mu[i, 0], r_b[j]), rtol=1e-13, atol=1e-15)


def test_a_textured_layer_is_its_elements():
    """A layer whose coat, base and darkening parameters are arrays evaluates as the layers of
    each element (E_b given: the layer's own quadrature of a textured base's albedo at the
    normal does not broadcast, whatever the variant)."""
    eta, alpha = np.array([1.5, 1.3, 2.0, 1.5]), np.array([0.0, 0.09, 0.25, 0.25])
    E_b = np.array([[0.9, 0.5, 0.1], [0.2, 0.4, 0.6], [1.0, 1.0, 1.0], [0.5, 0.5, 0.5]])
    T2 = np.array([TINT, (1.0, 0.8, 0.6), TINT, (0.1, 0.1, 0.1)])
    r_b = np.array([1.0, 0.0, 0.5, 0.8])
    wo, wi = _wo(np.array([0.95, 0.5, 0.2, 0.7])), _wo(np.array([0.3, 0.9, 0.6, 0.99]))

    def layer(i):
        return Layer(DielectricReflection(eta[i], alpha[i]), Lambert(E_b[i]), 0.9, T2[i],
                     darkening=Darkening(0.8, r_b[i], "dev_1.2", base_albedo=E_b[i],
                                         coat_alpha=alpha[i]))

    f = layer(slice(None)).eval(wo, wi)
    for i in range(4):
        np.testing.assert_allclose(f[i], layer(i).eval(wo[i], wi[i]), rtol=1e-13)


@pytest.mark.parametrize("alpha", [0.01, 0.25, 1.0])
def test_kulla_conty_split_is_the_lobes(alpha):
    """The shares of the multiply scattered energy that each side transmits, from the
    darkening's own quadrature, are ``DielectricMultipleScattering``'s (from its tables), to
    1e-3 of the energy they split."""
    for eta in (1.5, 1.0 / 1.5, 2.5):
        g = dk._Geometry(eta, alpha)
        # the completed interface: what is not reflected inside (into the bins) leaves
        np.testing.assert_allclose(g.P.sum(-1), g.R, rtol=0, atol=1e-12)
        np.testing.assert_allclose(g.R + g.T, 1.0, rtol=0, atol=1e-12)
        shares = DielectricMultipleScattering(eta, alpha).transmitted_share
        sides = _averages(eta, alpha)
        mine = dk._kulla_conty_shares(*sides, max(eta, 1.0 / eta))
        for side, t_mine, t_lobe in zip(sides, mine, shares, strict=True):
            # the energies the shares split (a share of a vanishing loss is ill-conditioned)
            assert abs(t_mine - float(t_lobe)) * (1.0 - sum(side)) <= 1e-3


def _averages(eta, alpha):
    """(E_R,avg, E_T,avg) of the light and the dense side from the darkening's quadrature."""
    sides = []
    for seen in (max(eta, 1.0 / eta), min(eta, 1.0 / eta)):
        mu, w = dk._cosine_rule(seen)
        (e_r, _), (e_t, _) = dk._rough_interface(mu, seen, alpha)
        sides.append(tuple(float(np.sum(2.0 * mu * w * e.sum(-1))) for e in (e_r, e_t)))
    return sides


def test_extremes_are_finite():
    """T2 = 0, E_b = 0 or 1, eta at and about 1, far from 1, alpha 0, tiny and 1, grazing
    and normal views: finite, in [0, 1], no warnings (they are errors in this suite)."""
    mu = np.array([0.0, 1e-12, 0.3, 1.0])
    for eta, alpha, T2, E_b in itertools.product(
            [1.0, 1.0 + 1e-9, 1.0 - 1e-9, 3.0, 1.0 / 3.0, 0.05], [0.0, 1e-9, 1e-4, 1.0],
            [0.0, 1.0, (0.0, 0.5, 1.0)], [0.0, 1.0]):
        D = physical_darkening(E_b, eta, alpha, T2, mu, np.array([[0.0], [0.5], [1.0]]))
        assert np.all(np.isfinite(D)) and np.all((D >= 0.0) & (D <= 1.0)), (eta, alpha, T2,
                                                                             E_b)
    layer = Layer(DielectricReflection(1.5, 1.0), Lambert(0.0), transmittance=0.0,
                  darkening=Darkening(1.0, 0.5, "dev_1.2", coat_alpha=1.0))
    assert np.all(np.isfinite(layer.eval(_wo(np.array([1.0, 1e-9])), _wo(0.5))))


@pytest.mark.parametrize(("call", "message"), [
    (lambda: Darkening(1.0, coat_alpha=1.5), "coat_alpha = 1.5"),
    (lambda: Darkening(variant="dev_1.3"), "variant = 'dev_1.3'"),
    (lambda: physical_darkening(0.5, 0.0, 0.1, 0.5), "eta = 0.0"),
    (lambda: physical_darkening(0.5, 1.5, 0.1, 1.2), "T2 = 1.2"),
    (lambda: Layer(DielectricReflection(1.5, 0.1), Lambert(0.5), transmittance=TINT,
                   scaling="transmittance", darkening=Darkening(variant="dev_1.2")),
     "view-dependent transmittance"),
    (lambda: Layer(DielectricReflection(1.5, 0.1), Lambert(0.5),
                   transmittance=lambda w: np.ones(w.shape), darkening=Darkening(
                       variant="dev_1.2")), "view-dependent transmittance")])
def test_bad_input(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_variants():
    """The K-formula variants of ``darkening`` are unchanged; the Darkening takes all."""
    assert dk.VARIANTS == ("pr253", "v1.1.1")
    assert dk.ALL_VARIANTS == ("pr253", "v1.1.1", "dev_1.2")
    with pytest.raises(ValueError, match="variant = 'dev_1.2'"):
        dk.darkening(0.5, 0.3, variant="dev_1.2")
