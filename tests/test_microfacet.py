"""GGX distribution, Smith masking and visible normals against closed forms and quadrature."""

import numpy as np
import pytest
from scipy.integrate import cubature

import adobe_bsdf as ab
from adobe_bsdf.microfacet import ALPHA_MIN
from tests.tolerances import EXACT, QUADRATURE

ALPHAS = [(0.1, 0.1), (0.5, 0.5), (1.0, 1.0), (0.5, 0.1), (0.05, 0.8)]


def sph(theta, phi):
    return np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])


def hemisphere_integral(f):
    """int f(w) dw over the upper hemisphere, adaptive cubature in (cos theta, phi)."""
    def g(x):
        mu, phi = x[:, 0], x[:, 1]
        s = np.sqrt(1 - mu**2)
        return f(np.stack([s * np.cos(phi), s * np.sin(phi), mu], -1))
    return cubature(g, [0, 0], [1, 2 * np.pi], rtol=1e-8, atol=1e-10).estimate


def visible_integral(f, w):
    """int over {m: m.z > 0, w.m > 0} of f(m) dm, in polar coordinates about w with the
    polar angle scaled to the region's boundary, so the integrand has no kink."""
    t1, t2 = ab.frame.coordinate_system(w)

    def g(x):
        t, phi = x[:, 0:1], x[:, 1:2]
        c = np.cos(phi) * t1[2] + np.sin(phi) * t2[2]
        limit = np.where(c >= 0, np.pi / 2, np.arctan2(w[2], -c))
        theta = t * limit
        m = np.cos(theta) * w + np.sin(theta) * (np.cos(phi) * t1 + np.sin(phi) * t2)
        return f(m) * (np.sin(theta) * limit)[:, 0]
    return cubature(g, [0, 0], [1, 2 * np.pi], rtol=1e-8, atol=1e-10).estimate


@pytest.mark.parametrize(("ax", "ay"), ALPHAS)
def test_projected_area_normalisation(ax, ay):
    """int D(m) cos theta_m dm = 1 [Heitz2014, eq. 2]."""
    g = ab.GGX(ax, ay)
    assert hemisphere_integral(lambda m: g.D(m) * m[..., 2]) == pytest.approx(1.0, abs=QUADRATURE)


@pytest.mark.parametrize(("ax", "ay"), ALPHAS)
def test_visible_normals_normalised(ax, ay):
    """int D_w(m) dm = 1, i.e. G1 is the Smith masking of this D [Heitz2014, eq. 11]."""
    g = ab.GGX(ax, ay)
    w = ab.frame.normalize(np.array([0.5, -0.3, 0.4]))
    value = visible_integral(lambda m: g.pdf_visible(w, m), w)
    assert value == pytest.approx(1.0, abs=QUADRATURE)


def test_D_closed_form_in_angles():
    """D = 1 / (pi ax ay cos^4 (1 + tan^2 (cos^2 phi / ax^2 + sin^2 phi / ay^2))^2)."""
    ax, ay = 0.3, 0.7
    g = ab.GGX(ax, ay)
    t, p = np.meshgrid(np.linspace(0, 1.5, 7), np.linspace(0, 6, 9))
    expected = 1 / (np.pi * ax * ay * np.cos(t) ** 4 *
                    (1 + np.tan(t) ** 2 * (np.cos(p) ** 2 / ax**2 + np.sin(p) ** 2 / ay**2)) ** 2)
    np.testing.assert_allclose(g.D(np.moveaxis(sph(t, p), 0, -1)), expected, rtol=1e-13)


def test_lambda_G1_G2_identities():
    g = ab.GGX(0.4, 0.2)
    rng = np.random.default_rng(3)
    wo = ab.frame.normalize(rng.normal(size=(100, 3)))
    wi = ab.frame.normalize(rng.normal(size=(100, 3)))
    # [Heitz2014, eq. 86] in its textbook form
    a2 = (0.4**2 * wo[:, 0] ** 2 + 0.2**2 * wo[:, 1] ** 2) / wo[:, 2] ** 2
    np.testing.assert_allclose(g.lambda_(wo), (np.sqrt(1 + a2) - 1) / 2, rtol=1e-12)
    np.testing.assert_allclose(g.G1(wo), 1 / (1 + g.lambda_(wo)), rtol=1e-13)
    np.testing.assert_allclose(g.G2(wo, wi), 1 / (1 + g.lambda_(wo) + g.lambda_(wi)), rtol=1e-13)
    np.testing.assert_allclose(g.V(wo, wi), g.G2(wo, wi) / (4 * abs(wo[:, 2] * wi[:, 2])),
                               rtol=1e-13)
    np.testing.assert_allclose(g.G2_over_G1(wo, wi), g.G2(wo, wi) / g.G1(wo), rtol=1e-13)
    s = ab.GGX(0.4, 0.2, masking="separable")
    np.testing.assert_allclose(s.G2(wo, wi), g.G1(wo) * g.G1(wi), rtol=EXACT)
    np.testing.assert_allclose(s.V(wo, wi), s.G2(wo, wi) / (4 * abs(wo[:, 2] * wi[:, 2])),
                               rtol=1e-13)
    np.testing.assert_allclose(s.G2_over_G1(wo, wi), g.G1(wi), rtol=EXACT)


def test_alpha_one_normal_view_albedo_is_one_minus_ln2():
    """Closed form: alpha = 1, mu_o = 1 -> G = 2 mu_i / (1 + mu_i) (both forms)."""
    mu = np.linspace(0.01, 1, 50)
    wi = np.stack([np.sqrt(1 - mu**2), 0 * mu, mu], -1)
    for masking in ("correlated", "separable"):
        g = ab.GGX(1.0, masking=masking)
        np.testing.assert_allclose(g.G2(np.array([0, 0, 1.0]), wi), 2 * mu / (1 + mu), rtol=1e-14)


def test_sample_visible_is_unit_and_visible():
    g = ab.GGX(0.3, 0.05)
    rng = np.random.default_rng(0)
    for w in (np.array([0, 0, 1.0]), np.array([1.0, 0, 0]), np.array([0.6, 0, -0.8])):
        m = g.sample_visible(np.broadcast_to(w, (10000, 3)), rng.random((10000, 2)))
        np.testing.assert_allclose(np.linalg.norm(m, axis=-1), 1, atol=1e-14)
        assert np.all(m[:, 2] >= 0) and np.all(np.sign(w[2] or 1) * m @ w >= -1e-15)


def test_extremes_and_smooth_limit():
    g = ab.GGX([0.0, 1e-9, 1e-9, 1.0], [0.0, 0.0, 0.3, 1e-12])
    np.testing.assert_array_equal(g.smooth, [True, True, False, False])
    np.testing.assert_array_equal(g.alpha_y[2:], [0.3, ALPHA_MIN])
    w = np.array([[0, 0, 1.0], [1.0, 0, 0], [0, 1.0, 0], [np.sqrt(1 - 1e-16), 0, 1e-8]])
    for f in (g.D, g.G1, g.lambda_):
        assert not np.any(np.isnan(f(w)))
    assert np.all(np.isfinite(g.D(w))) and np.all(np.isfinite(g.G1(w)))
    assert np.all(np.isfinite(g.pdf_visible(w, w))) and np.all(np.isfinite(g.V(w, w[::-1])))
    assert g.lambda_(np.array([1.0, 0, 0]))[2] == np.inf  # the exact grazing limit


@pytest.mark.parametrize(("r", "a", "ax", "ay"), [(0.5, 0.0, 0.25, 0.25), (0.5, 0.5, 0.3125, 0.25),
                                                  (0.5, 1.0, 1.25, 0.25), (0.3, 0.8, 0.4996, 0.09)])
def test_asm_alpha_published(r, a, ax, ay):
    """[Kutz2021, eqs. 9-10], alpha_x = r^2 + a^4, alpha_y = r^2, at values worked out by hand."""
    assert ab.materials.asm.asm_alpha(r, a) == pytest.approx((ax, ay), abs=1e-12)


def test_bad_input():
    with pytest.raises(ValueError, match="alpha_x"):
        ab.GGX(-0.1)
    with pytest.raises(ValueError, match="alpha_y"):
        ab.GGX(0.1, np.inf)
    with pytest.raises(ValueError, match="masking"):
        ab.GGX(0.1, masking="uncorrelated")
    with pytest.raises(ValueError, match="anisotropy"):
        ab.materials.asm.asm_alpha(0.5, 1.5)
