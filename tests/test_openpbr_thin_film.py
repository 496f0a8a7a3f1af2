"""OpenPBR Surface's thin film [OpenPBR2026, §Thin-film iridescence]: the Airy reflectance of
``thin_film.ThinFilm`` inside the Fresnel factor of the metal and of the glossy-diffuse
reflection, blended by thin_film_weight."""

from __future__ import annotations

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.materials.openpbr import OpenPBRSurface
from tests.sampling_checks import assert_sampling_matches

FILM = dict(thin_film_weight=1.0, thin_film_thickness=0.35, thin_film_ior=1.33)
METAL = dict(base_metalness=1.0, base_color=(0.9, 0.6, 0.3), specular_roughness=0.3)
PLASTIC = dict(base_color=(0.2, 0.3, 0.6), specular_roughness=0.25)


def _pairs(n=100, seed=8):
    wo, wi = ab.frame.normalize(np.random.default_rng(seed).normal(size=(2, n, 3)))
    return np.abs(wo) * [1, 1, 1], wi


@pytest.mark.parametrize("p", [METAL, PLASTIC, dict(PLASTIC, coat_weight=1.0)])
def test_no_film_is_the_film_free_material_bit_for_bit(p):
    wo, wi = _pairs()
    plain = OpenPBRSurface(**p).eval(wo, wi)
    for film in (dict(FILM, thin_film_weight=0.0), dict(FILM, thin_film_thickness=0.0)):
        np.testing.assert_array_equal(OpenPBRSurface(**p, **film).eval(wo, wi), plain)


@pytest.mark.parametrize("coat", [{}, dict(coat_weight=0.6, coat_ior=1.5)])
def test_a_vanishing_film_on_the_dielectric_is_film_free(coat):
    """d -> 0: the Airy sum tends to the substrate's Fresnel (to 1e-12 at d = 1e-6 nm)."""
    wo, wi = _pairs()
    plain = OpenPBRSurface(**PLASTIC, **coat).eval(wo, wi)
    thin = OpenPBRSurface(**PLASTIC, **coat, **dict(FILM, thin_film_thickness=1e-9)).eval(wo, wi)
    np.testing.assert_allclose(thin, plain, rtol=1e-12, atol=1e-300)


def test_the_film_changes_the_colour_and_the_weight_blends():
    """A 350 nm film makes the reflection iridescent; thin_film_weight w is the linear blend
    (1 - w) f_plain + w f_film of the two surfaces."""
    wo, wi = _pairs()
    plain, film = OpenPBRSurface(**METAL), OpenPBRSurface(**METAL, **FILM)
    half = OpenPBRSurface(**METAL, **dict(FILM, thin_film_weight=0.3))
    f0, f1 = plain.eval(wo, wi), film.eval(wo, wi)
    assert np.max(np.abs(f1 - f0) / np.maximum(f0, 1e-3)) > 0.05
    np.testing.assert_allclose(half.eval(wo, wi), 0.7 * f0 + 0.3 * f1, rtol=1e-12, atol=1e-300)


@pytest.mark.parametrize("p", [dict(base_color=1.0, specular_color=1.0, specular_roughness=0.3),
                               dict(base_color=1.0, specular_color=1.0, specular_roughness=0.3,
                                    coat_weight=1.0, coat_roughness=0.1),
                               dict(base_metalness=1.0, base_color=1.0, specular_color=1.0)])
def test_white_furnace_with_a_film(p):
    """The film is not absorbing: the white cases of the specification keep 1 (Monte Carlo,
    energy albedo, 2e-3 + 4 sigma)."""
    m = OpenPBRSurface(**p, **FILM)
    wo = np.array([[0.0, 0.6, 0.8], [0.9, 0.0, np.sqrt(1 - 0.81)]])
    E, sigma = m.albedo(wo, method="mc", n_samples=20_000, rng=3, return_error=True)
    assert np.all(np.abs(E - 1.0) <= 2e-3 + 4 * sigma), (E, sigma)


def test_coloured_film_never_gains():
    m = OpenPBRSurface(**METAL, **FILM)
    wo = np.array([[0.0, 0.6, 0.8], [0.9, 0.0, np.sqrt(1 - 0.81)]])
    E, sigma = m.albedo(wo, method="mc", n_samples=8_000, rng=4, return_error=True)
    assert np.all(E <= 1.0 + 1e-3 + 4 * sigma)


@pytest.mark.parametrize("p", [METAL, PLASTIC])
def test_film_sampling(p):
    assert_sampling_matches(OpenPBRSurface(**p, **FILM), 0.6, 0.3, seed=2, n_tests=2,
                            n_samples=40_000)


def test_the_translucent_base_warns_and_the_hazy_gloss_refuses():
    with pytest.warns(UserWarning, match="thin film is not applied to the translucent"):
        OpenPBRSurface(transmission_weight=0.5, **FILM)
    with pytest.raises(ValueError, match="thin_film_weight"):
        with pytest.warns(DeprecationWarning):
            OpenPBRSurface(specular_haze=0.5, haze_model="barla2018", **FILM)
