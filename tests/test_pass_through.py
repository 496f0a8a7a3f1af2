"""A dielectric whose index is within rounding of 1: the pass-through collapse
(``lobes.dielectric.passes_through``, docs/conventions.md)."""

import warnings

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.lobes.dielectric import MIN_TRANSMISSION_WIDTH, passes_through
from adobe_bsdf.microfacet import GGX

ULP = np.finfo(np.float64).eps
NEAR_ONE = [1.0 + ULP, 1.0 - ULP / 2, 1.0 + 3 * ULP, 1.0 + 100 * ULP, 1.0 + 1e-13, 1 / (1 + 1e-13)]
ALPHAS = [(1.0, 1e-8), (0.3, 0.3), (1e-4, 1e-4), (0.5, 0.2)]


def _directions(n, seed=0):
    """Uniform directions on the sphere plus the grazing and normal ones."""
    rng = np.random.default_rng(seed)
    z = rng.uniform(-1.0, 1.0, n)
    phi = rng.uniform(0.0, 2.0 * np.pi, n)
    r = np.sqrt(1.0 - z * z)
    wo = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)
    extra = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [np.sqrt(1 - 1e-20), 0.0, 1e-10]]
    return np.concatenate([wo, extra])


@pytest.mark.parametrize("eta", NEAR_ONE)
@pytest.mark.parametrize("alpha", ALPHAS + [(0.0, 0.0)])
def test_near_one_is_finite_and_consistent(eta, alpha):
    lobe = ab.lobes.Dielectric(eta, *alpha)
    wo = _directions(3000)
    u = np.random.default_rng(1).random((len(wo), 3))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = lobe.sample(wo, u)
        wi = np.where((s.pdf > 0.0)[:, None], s.wi, -wo)
        f, pdf = lobe.eval_pdf(wo, wi)
        albedo = lobe.albedo(wo[:50], method="quadrature", tol=1e-6)
    for value in (s.wi, s.weight, s.pdf, f, pdf, albedo):
        assert np.isfinite(value).all()
    assert (s.weight >= 0.0).all() and (f >= 0.0).all()
    assert (albedo <= 1.0 + 1e-6).all()


def test_threshold_is_the_transmitted_lobe_width():
    """A rough interface passes through exactly where alpha_max |eta - 1| < 1e-12; a smooth
    one only at eta = 1."""
    for alpha in (1.0, 1e-4, 1e-8):
        delta = MIN_TRANSMISSION_WIDTH / alpha
        d = GGX(alpha)
        assert passes_through(np.float64(1.0 + 0.9 * delta), d)
        assert not passes_through(np.float64(1.0 + 1.1 * delta), d)
        assert passes_through(np.float64(1.0 - 0.9 * delta), d)
    assert passes_through(np.float64(1.0), GGX(0.0))
    assert not passes_through(np.float64(1.0 + ULP), GGX(0.0))
    assert not passes_through(np.float64(1.0 + 1e-10), GGX(1e-8, 1.0))  # the wide axis decides
    assert passes_through(np.float64(1.0 + 1e-5), GGX(1e-8, 1e-8))


def _ggx_lambda(alpha_x, alpha_y, wo):
    """[Heitz2014, eq. 86]: (-1 + sqrt(1 + alpha(phi)^2 tan^2)) / 2 with
    alpha(phi)^2 = alpha_x^2 cos^2 phi + alpha_y^2 sin^2 phi."""
    x, y, z = wo
    tan2_alpha2 = (alpha_x**2 * x * x + alpha_y**2 * y * y) / (z * z)
    return 0.5 * (-1.0 + np.sqrt(1.0 + tan2_alpha2))


@pytest.mark.parametrize("masking", ["correlated", "separable"])
@pytest.mark.parametrize("alpha", [(0.1, 0.1), (0.5, 0.5), (1.0, 1.0), (1.0, 1e-8)])
@pytest.mark.parametrize("cos_theta", [1.0, 0.5, 0.1, -0.3])
def test_pass_through_carries_the_rough_limit(masking, alpha, cos_theta):
    """The collapsed lobe's energy is the rough model's eta -> 1 limit G2(wo, -wo) / G1(wo)
    (closed form from Lambda), and the Monte-Carlo energy of the still-resolved lobe tends
    to it linearly: at |eta - 1| = 1e-9 (reflection F < 1e-18, the lobe ~1e-9 rad wide)
    within 100 |eta - 1| (slope measured at most 15)."""
    s_theta = np.sqrt(1.0 - cos_theta**2)
    wo = np.array([s_theta * np.cos(0.4), s_theta * np.sin(0.4), cos_theta])
    lam = _ggx_lambda(*alpha, wo)
    limit = (1 + lam) / (1 + 2 * lam) if masking == "correlated" else 1 / (1 + lam)
    collapsed = ab.lobes.Dielectric(1.0 + 0.9e-12, *alpha, masking=masking)
    assert collapsed.passes
    np.testing.assert_allclose(collapsed.albedo(wo, method="quadrature"), limit, rtol=1e-12)
    s = collapsed.sample(wo, np.array([0.4, 0.2, 0.7]))
    np.testing.assert_array_equal(s.wi, -wo)
    assert s.flags == ab.Flags.TRANSMISSION | ab.Flags.DELTA
    delta = 1e-9
    resolved = ab.lobes.Dielectric(1.0 + delta, *alpha, masking=masking)
    assert not resolved.passes
    mc, error = resolved.albedo(wo, method="mc", n_samples=100_000, return_error=True)
    assert np.all(np.abs(mc - limit) < 5 * error + 100 * delta), (mc, error, limit)


def test_exact_index_match_is_still_no_interface():
    lobe = ab.lobes.Dielectric(1.0, 0.5)
    wo = np.array([0.6, 0.0, 0.8])
    np.testing.assert_array_equal(lobe.albedo(wo, method="quadrature"), 1.0)


def test_texture_mixes_pass_through_and_rough_elements():
    """Per-element parameters: the pass-through elements equal the scalar lobe's values."""
    etas = np.array([1.5, 1.0 + ULP, 1.0, 1.0 - 1e-13])
    lobe = ab.lobes.Dielectric(etas, 0.3)
    wo = np.broadcast_to([0.6, 0.0, 0.8], (4, 3))
    u = np.broadcast_to([0.9, 0.3, 0.6], (4, 3))
    s = lobe.sample(wo, u)
    for j, eta in enumerate(etas):
        one = ab.lobes.Dielectric(eta, 0.3).sample(wo[j], u[j])
        np.testing.assert_array_equal(s.wi[j], one.wi)
        np.testing.assert_array_equal(s.weight[j], one.weight)
    wi = np.broadcast_to([-0.6, 0.0, -0.8], (4, 3))
    f = lobe.eval(wo, wi)
    np.testing.assert_array_equal(f[1:], 0.0)
    assert (f[0] > 0.0).all()


@pytest.mark.parametrize("eta, dispersion", [(1.0 + 1e-9, 1e-3), (1.0 + ULP, 0.5),
                                             (1.0 + 1e-5, 1e-4)])
def test_dispersive_near_one_is_finite(eta, dispersion):
    lobe = ab.lobes.Dispersive(eta, dispersion, 1e-3)
    wo = _directions(3000, seed=2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = lobe.sample(wo, np.random.default_rng(3).random((len(wo), 3)))
    assert np.isfinite(s.weight).all() and np.isfinite(s.pdf).all()
    assert (s.weight >= 0.0).all()


def test_material_at_ior_one_ulp_above_one():
    """The corner hypothesis found: roughness 0, anisotropy 1 (alpha_y = 1e-8), a
    transmitted lobe ~1e-24 rad wide."""
    material = ab.materials.AdobeStandardMaterial(base_color=0.0, roughness=0.0,
                                                  ior=1.0 + ULP, anisotropy_level=1.0,
                                                  translucency=1.0)
    wo = _directions(4000, seed=4)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = material.sample(wo, np.random.default_rng(5).random((len(wo), 3)))
        albedo = material.albedo(wo[:20], method="table")
    assert np.isfinite(s.weight).all() and np.isfinite(s.pdf).all()
    assert (albedo <= 1.0 + 1e-3).all()
