"""OpenPBR Surface's presence and light: ``geometry_opacity`` as a mix with the pass-through
interface (``lobes.PassThrough``), ``shadow_transmittance`` (v1.1.1's T_pbr) and
``emission`` (luminance in nits through the coat and the fuzz). Expected values are closed
forms: the exact dielectric Fresnel, Beer's law in the coat, the candela's 683 lm/W."""

from __future__ import annotations

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.bsdf import Flags
from adobe_bsdf.materials.openpbr import OpenPBRSurface
from tests.sampling_checks import assert_sampling_matches

REC709_Y = np.array([0.2126, 0.7152, 0.0722])  # ITU-R BT.709 luminance weights
MU = np.array([1.0, 0.8, 0.45, 0.1, 0.01])
WHITE_DIFFUSE = dict(base_color=1.0, specular_color=1.0, base_diffuse_roughness=0.5)
WHITE_METAL = dict(base_color=1.0, specular_color=1.0, base_metalness=1.0)


def _wo(mu, phi=0.4):
    mu = np.asarray(mu, dtype=np.float64)
    s = np.sqrt((1.0 - mu) * (1.0 + mu))
    return np.stack([s * np.cos(phi), s * np.sin(phi), mu], axis=-1)


def _pairs(n=500, seed=3):
    return ab.frame.normalize(np.random.default_rng(seed).normal(size=(2, n, 3)))


# -- opacity -----------------------------------------------------------------------------------
def test_opacity_zero_is_an_invisible_surface():
    m = OpenPBRSurface(coat_weight=1.0, fuzz_weight=0.5, geometry_opacity=0.0,
                       emission_luminance=100.0)
    wo, wi = _pairs()
    np.testing.assert_array_equal(m.eval(wo, wi), 0.0)
    np.testing.assert_array_equal(m.pdf(wo, wi), 0.0)
    s = m.sample(wo, np.random.default_rng(1).random(wo.shape))
    np.testing.assert_array_equal(s.wi, -wo)
    np.testing.assert_array_equal(s.weight, 1.0)
    assert np.all(s.flags == int(Flags.TRANSMISSION | Flags.DELTA | Flags.NULL))
    both = np.concatenate([_wo(MU), -_wo(MU)])
    np.testing.assert_allclose(m.albedo(both, tol=1e-6), 1.0, atol=1e-12)
    np.testing.assert_array_equal(m.shadow_transmittance(both), 1.0)
    np.testing.assert_array_equal(m.emission(both), 0.0)
    assert "pass-through" in m.lobes


@pytest.mark.parametrize("p", [{}, WHITE_METAL, dict(transmission_weight=1.0, coat_weight=0.7)])
def test_opacity_one_is_the_opaque_material_bit_for_bit(p):
    opaque, explicit = OpenPBRSurface(**p), OpenPBRSurface(**p, geometry_opacity=1.0)
    assert "pass-through" not in explicit.lobes
    wo, wi = _pairs()
    u = np.random.default_rng(2).random(wo.shape)
    np.testing.assert_array_equal(explicit.eval(wo, wi), opaque.eval(wo, wi))
    np.testing.assert_array_equal(explicit.pdf(wo, wi), opaque.pdf(wo, wi))
    for a, b in zip(explicit.sample(wo, u), opaque.sample(wo, u), strict=True):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("alpha", [0.3, 0.85])
def test_partial_opacity_is_the_linear_blend(alpha):
    """f = alpha f_surface (the pass-through is a delta); E = (1 - alpha) + alpha E_surface."""
    p = dict(base_color=(0.7, 0.4, 0.2), coat_weight=0.5, specular_roughness=0.4)
    surface, m = OpenPBRSurface(**p), OpenPBRSurface(**p, geometry_opacity=alpha)
    wo, wi = _pairs()
    np.testing.assert_allclose(m.eval(wo, wi), alpha * surface.eval(wo, wi), rtol=1e-14,
                               atol=1e-300)
    wo = _wo(MU[:3])
    np.testing.assert_allclose(m.albedo(wo, tol=1e-6),
                               (1.0 - alpha) + alpha * surface.albedo(wo, tol=1e-6), atol=2e-6)


@pytest.mark.parametrize("p", [WHITE_DIFFUSE, WHITE_METAL,
                               dict(WHITE_DIFFUSE, coat_weight=1.0, coat_roughness=0.2,
                                    fuzz_weight=1.0)])
def test_white_furnace_holds_at_any_opacity(p):
    for alpha in (0.0, 0.4, 1.0):
        E = OpenPBRSurface(**p, geometry_opacity=alpha).albedo(_wo(MU[:4]), tol=1e-6)
        np.testing.assert_allclose(E, 1.0, atol=2e-3)


@pytest.mark.parametrize("cos_theta", [0.8, 0.3, -0.6])
def test_partial_opacity_sampling(cos_theta):
    """Chi-square of the non-delta part and sample weights, both sides of a glass."""
    m = OpenPBRSurface(transmission_weight=0.5, specular_roughness=0.4, coat_weight=0.5,
                       geometry_opacity=0.6)
    assert_sampling_matches(m, cos_theta, 0.9, seed=5, n_tests=3)


def test_pass_through_lobe():
    lobe = ab.lobes.PassThrough()
    wo = np.concatenate([_wo(MU), -_wo(MU), [[1.0, 0.0, 0.0]]])
    s = lobe.sample(wo, np.full(wo.shape, 0.5))
    np.testing.assert_array_equal(s.wi[:-1], -wo[:-1])
    np.testing.assert_array_equal(s.weight[:-1], 1.0)
    assert s.flags[-1] == 0 and s.pdf[-1] == 0.0  # the tangent plane: nothing leaves
    np.testing.assert_array_equal(lobe.albedo(wo, method="table")[:-1], 1.0)
    np.testing.assert_array_equal(lobe.albedo(wo, method="mc", n_samples=8)[:-1], 1.0)
    np.testing.assert_array_equal(lobe.eval(wo, -wo), 0.0)


# -- shadow transmittance ------------------------------------------------------------------------
@pytest.mark.filterwarnings("ignore:OpenPBRSurface. transmission_color not modelled")
@pytest.mark.parametrize("alpha", [1.0, 0.6, 0.0])
def test_shadow_transmittance_of_a_smooth_glass(alpha):
    """T_pbr = 1 - alpha (1 - (1 - M) T_d), T_d = w (1 - F(mu, eta)) transmission_color."""
    color, M, w = np.array([0.9, 0.6, 0.3]), 0.25, 0.8
    m = OpenPBRSurface(transmission_weight=w, transmission_color=color, base_metalness=M,
                       specular_roughness=0.0, specular_ior=1.5, geometry_opacity=alpha)
    wo = np.concatenate([_wo(MU), -_wo(MU)])
    F = ab.fresnel.dielectric(np.abs(wo[:, 2]), 1.5)[:, None] * np.ones(3)
    expected = 1.0 - alpha * (1.0 - (1.0 - M) * w * (1.0 - F) * color)
    np.testing.assert_allclose(m.shadow_transmittance(wo), expected, rtol=1e-13, atol=1e-15)


def test_shadow_transmittance_through_a_clear_coat_and_of_opaque_bases():
    """A coat of the base's index leaves one interface, the coat's; a metal, a diffuse base
    and a subsurface base are opaque."""
    m = OpenPBRSurface(transmission_weight=1.0, specular_roughness=0.0, specular_ior=1.4,
                       coat_weight=1.0, coat_ior=1.4, coat_roughness=0.0)
    wo = _wo(MU)
    F = ab.fresnel.dielectric(MU, 1.4)[:, None] * np.ones(3)
    np.testing.assert_allclose(m.shadow_transmittance(wo), 1.0 - F, rtol=1e-13, atol=1e-15)
    for p in ({}, WHITE_METAL, dict(subsurface_weight=1.0)):
        np.testing.assert_array_equal(OpenPBRSurface(**p).shadow_transmittance(wo), 0.0)
        np.testing.assert_allclose(OpenPBRSurface(**p, geometry_opacity=0.3)
                                   .shadow_transmittance(wo), np.full(wo.shape, 0.7),
                                   rtol=1e-15)


# -- emission ----------------------------------------------------------------------------------
def test_emission_is_the_luminance_in_radiometric_units():
    """K_m Y(L_e) = emission_luminance for a white colour (K_m = 683 lm/W, Y of Rec. 709),
    uniform above the surface, nothing below; the colour multiplies, and may exceed 1."""
    L = 250.0
    m = OpenPBRSurface(emission_luminance=L)
    up, down = _wo(MU), -_wo(MU)
    Le = m.emission(up)
    np.testing.assert_allclose(683.0 * Le @ REC709_Y, L, rtol=1e-14)
    np.testing.assert_array_equal(Le, np.broadcast_to(Le[:1], Le.shape))
    np.testing.assert_array_equal(m.emission(down), 0.0)
    color = np.array([2.0, 0.5, 0.0])
    np.testing.assert_allclose(OpenPBRSurface(emission_luminance=L, emission_color=color)
                               .emission(up), L / 683.0 * color * np.ones((len(MU), 1)),
                               rtol=1e-15)
    np.testing.assert_array_equal(OpenPBRSurface().emission(up), 0.0)


@pytest.mark.parametrize("C", [1.0, 0.4])
def test_emission_through_a_smooth_tinted_coat(C):
    """lerp(1, sqrt(T)^(1/mu_t) (1 - F(mu, n_c)), C): the light crosses the coat once, with
    Beer's law over the refracted path mu_t = sqrt(1 - (1 - mu^2) / n_c^2)."""
    T, n_c = np.array([0.81, 0.49, 0.25]), 1.6
    m = OpenPBRSurface(emission_luminance=683.0, coat_weight=C, coat_color=T, coat_ior=n_c,
                       coat_roughness=0.0, geometry_opacity=0.7)
    mu_t = np.sqrt(1.0 - (1.0 - MU**2) / n_c**2)[:, None]
    F = ab.fresnel.dielectric(MU, n_c)[:, None]
    through = np.sqrt(T) ** (1.0 / mu_t) * (1.0 - F)
    expected = 0.7 * ((1.0 - C) + C * through)
    np.testing.assert_allclose(m.emission(_wo(MU)), expected, rtol=1e-12)


def test_emission_under_fuzz_loses_what_the_fuzz_reflects():
    """(1 - F E_fuzz(wo)), E_fuzz by an independent quadrature of the white fuzz lobe."""
    F, r = 0.8, 0.6
    m = OpenPBRSurface(emission_luminance=683.0, fuzz_weight=F, fuzz_roughness=r)
    wo = _wo(MU[:4])
    E = ab.lobes.LTCSheen(1.0, r).albedo(wo, tol=1e-7)
    np.testing.assert_allclose(m.emission(wo), 1.0 - F * E, atol=2e-3)
    assert np.all(m.emission(wo) < 1.0)
