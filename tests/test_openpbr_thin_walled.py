"""OpenPBR Surface's thin-walled mode [OpenPBR2026, §Thin-walled mode]: an always-facing
sheet (``composition.Facing``) whose metal and glossy-diffuse bases are double-sided, whose
translucent base is ``lobes.ThinDielectric`` and whose subsurface is the f_R / f_T split with
g. Energy by quadrature of eval plus the delta branches (R + T)."""

from __future__ import annotations

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.materials.openpbr import OpenPBRSurface
from tests.sampling_checks import assert_sampling_matches

THIN = dict(geometry_thin_walled=True)
M = np.array([1.0, 1.0, -1.0])
MU = np.array([1.0, 0.6, 0.2])


def _wo(mu, phi=0.3):
    s = np.sqrt((1.0 - mu) * (1.0 + mu))
    return np.stack([s * np.cos(phi), s * np.sin(phi), mu], axis=-1)


BOTH_SIDES = np.concatenate([_wo(MU), _wo(MU) * M])
WHITE_WALLS = {
    "clear sheet r=0": dict(transmission_weight=1.0, specular_roughness=0.0),
    "clear sheet r=0.3": dict(transmission_weight=1.0, specular_roughness=0.3),
    "clear sheet r=1": dict(transmission_weight=1.0, specular_roughness=1.0),
    "subsurface g=-0.5": dict(subsurface_weight=1.0, subsurface_color=1.0,
                              subsurface_scatter_anisotropy=-0.5, base_diffuse_roughness=0.5),
    "subsurface g=0.6": dict(subsurface_weight=1.0, subsurface_color=1.0,
                             subsurface_scatter_anisotropy=0.6),
    "white metal": dict(base_metalness=1.0, base_color=1.0, specular_color=1.0),
    "white diffuse": dict(base_color=1.0, specular_color=1.0, base_diffuse_roughness=1.0),
    "clear sheet + coat + fuzz": dict(transmission_weight=1.0, specular_roughness=0.4,
                                      coat_weight=1.0, coat_roughness=0.2, fuzz_weight=0.5),
}


@pytest.mark.parametrize("name", list(WHITE_WALLS))
def test_white_walls_keep_their_energy_from_both_sides(name):
    """R + T = 1 +- 2e-3 for a white, non-absorbing wall, seen from either side."""
    m = OpenPBRSurface(**WHITE_WALLS[name], **THIN)
    np.testing.assert_allclose(m.albedo(BOTH_SIDES, tol=1e-6), 1.0, atol=2e-3)


def test_an_absorbing_wall_never_gains():
    m = OpenPBRSurface(transmission_weight=1.0, transmission_color=(0.9, 0.5, 0.1),
                       specular_roughness=0.3, coat_weight=0.5, **THIN)
    E = m.albedo(BOTH_SIDES, tol=1e-6)
    assert np.all(E <= 1.0 + 1e-3) and np.all(E[..., 2] < E[..., 0])


@pytest.mark.parametrize("p", [WHITE_WALLS["clear sheet r=0.3"], WHITE_WALLS["subsurface g=0.6"],
                               dict(base_color=(0.8, 0.4, 0.2), base_metalness=0.5,
                                    coat_weight=1.0)])
def test_the_wall_is_the_same_from_both_sides(p):
    m = OpenPBRSurface(**p, **THIN)
    wo, wi = ab.frame.normalize(np.random.default_rng(5).normal(size=(2, 500, 3)))
    np.testing.assert_array_equal(m.eval(wo, wi), m.eval(wo * M, wi * M))


def test_the_clear_sheet_is_reciprocal_across_the_wall():
    """The translucent wall alone (no layer above) is reciprocal for pairs across it."""
    m = OpenPBRSurface(transmission_weight=1.0, specular_roughness=0.35, **THIN)
    wo, wi = ab.frame.normalize(np.random.default_rng(6).normal(size=(2, 2000, 3)))
    wi[:, 2] = -np.sign(wo[:, 2]) * np.abs(wi[:, 2])  # across
    f, g = m.eval(wo, wi), m.eval(wi, wo)
    np.testing.assert_allclose(f, g, rtol=1e-10, atol=1e-300)
    assert f.max() > 0.0


def test_subsurface_transmits_its_share():
    """What passes the subsurface wall is (1 - E_spec(wo)) S (1 + g) / 2 (the unit-albedo
    flipped diffuse under the interface's albedo scaling; E_spec by quadrature of the
    interface alone)."""
    S, g, r = np.array([0.9, 0.6, 0.3]), 0.4, 0.3
    m = OpenPBRSurface(subsurface_weight=1.0, subsurface_color=S,
                       subsurface_scatter_anisotropy=g, specular_roughness=r, **THIN)
    wo = _wo(np.array([0.8, 0.4]))
    E_spec = ab.lobes.DielectricReflection(1.5, r * r).albedo(wo, tol=1e-8)
    lower = m.albedo(wo, tol=1e-7) - (E_spec + (1.0 - E_spec) * S * (1.0 - g) / 2)
    np.testing.assert_allclose(lower, (1.0 - E_spec) * S * (1.0 + g) / 2, atol=5e-4)


@pytest.mark.parametrize("p", [WHITE_WALLS["clear sheet r=0.3"], WHITE_WALLS["subsurface g=0.6"],
                               dict(transmission_weight=0.5, specular_roughness=0.2,
                                    coat_weight=1.0, transmission_color=0.7)])
@pytest.mark.parametrize("cos_theta", [0.7, -0.4])
def test_sampling_on_both_sides(p, cos_theta):
    assert_sampling_matches(OpenPBRSurface(**p, **THIN), cos_theta, 0.8, seed=9, n_tests=12)


def test_no_interior_and_emission_on_both_sides():
    m = OpenPBRSurface(transmission_weight=1.0, transmission_depth=0.5, subsurface_weight=0.5,
                       emission_luminance=100.0, **THIN)
    assert m.media() == {} and m.medium() is None
    np.testing.assert_array_equal(m.emission(_wo(MU)), m.emission(_wo(MU) * M))
    assert np.all(m.emission(_wo(MU)) > 0.0)


def test_a_mixed_texture_of_modes_is_refused():
    with pytest.raises(ValueError, match="geometry_thin_walled"):
        OpenPBRSurface(geometry_thin_walled=np.array([True, False]))
