"""A thin film on the thin-walled translucent base (``ThinDielectric(film=)``,
``OpenPBRSurface`` thin-walled with ``thin_film_weight``): the soap bubble against the
brute-force spectral reference of ``validation.spectral_film`` (the Airy sum on a 1 nm grid,
CIE 1931 2°, D65, linear Rec. 709), R + T = 1 for clear sheets, the white furnace of rough
ones, reciprocity and sampling."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.lobes import ThinDielectric
from adobe_bsdf.lobes.thin_dielectric import sheet_coefficients
from adobe_bsdf.thin_film import ThinFilm
from adobe_bsdf.validation import spectral_film
from tests.sampling_checks import assert_sampling_matches

COSINES = np.array([1.0, 0.8, 0.5, 0.25, 0.08])


def _direction(mu, phi=0.3, side=1.0):
    mu = np.asarray(mu, dtype=np.float64)
    s = np.sqrt(1.0 - mu * mu)
    return np.stack(np.broadcast_arrays(s * np.cos(phi), s * np.sin(phi), side * mu), -1)


@pytest.mark.parametrize("thickness, film_ior", [(250.0, 1.33), (400.0, 1.33), (700.0, 1.45),
                                                 (120.0, 1.8)])
def test_soap_bubble_is_the_film(thickness, film_ior):
    """An index-1 clear sheet with a film reflects the film's R and transmits 1 - R: within
    0.01 per channel of the spectral reference's reflectance and transmittance (computed
    from the transmitted amplitude), and R + T = 1 within 1e-3. The reference's colours are
    clipped to [0, 1] as the film's are (``ThinFilm(clip=True)``): a saturated fringe lies
    outside linear Rec. 709 (here by up to 0.06 at grazing views), and a Fresnel factor
    outside [0, 1] would make the lobe negative or gain energy."""
    film = ThinFilm(thickness, film_ior, 1.0)
    R, T = sheet_coefficients(COSINES**2, np.array(1.0), np.ones(3), film)
    R_ref = np.clip(spectral_film.film_rgb(COSINES, thickness, film_ior, 1.0), 0.0, 1.0)
    T_ref = np.clip(spectral_film.film_transmittance_rgb(COSINES, thickness, film_ior, 1.0),
                    0.0, 1.0)
    assert np.abs(R - R_ref).max() <= 0.01, np.abs(R - R_ref).max()
    assert np.abs(T - T_ref).max() <= 0.01, np.abs(T - T_ref).max()
    assert np.abs(R + T - 1.0).max() <= 1e-3


def test_the_material_s_soap_bubble():
    """``OpenPBRSurface`` thin-walled, specular_ior 1, transmission 1, a film: the sampled
    energy reflected and transmitted at normal incidence is the reference's R and T (Monte
    Carlo, 5 standard errors and 0.01), and no warning drops the film."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = ab.materials.OpenPBRSurface(
            geometry_thin_walled=True, transmission_weight=1.0, specular_ior=1.0,
            specular_roughness=0.0, thin_film_weight=1.0, thin_film_thickness=0.4,
            thin_film_ior=1.33)
    n = 200_000
    wo = np.broadcast_to(_direction(1.0), (n, 3))
    s = m.sample(wo, np.random.default_rng(3).random((n, 3)))
    up = (s.wi[:, 2] > 0)[:, None]
    for part, ref in ((np.where(up, s.weight, 0.0),
                       spectral_film.film_rgb(1.0, 400.0, 1.33, 1.0)),
                      (np.where(~up, s.weight, 0.0),
                       spectral_film.film_transmittance_rgb(1.0, 400.0, 1.33, 1.0))):
        error = part.std(0) / np.sqrt(n)
        assert np.all(np.abs(part.mean(0) - ref) <= 0.01 + 5.0 * error), (part.mean(0), ref)


@pytest.mark.parametrize("eta", [1.5, 1 / 1.3])
def test_a_clear_sheet_with_a_film_keeps_its_energy(eta):
    """Any clear sheet with a non-absorbing film: R + T = 1 at every angle (the transmitted
    colour is the complement of the reflected one), and a film of thickness 0 is no film."""
    c2 = np.linspace(0.0, 1.0, 101)
    film = ThinFilm(350.0, 1.4, eta)
    R, T = sheet_coefficients(c2, np.array(eta), np.ones(3), film)
    np.testing.assert_allclose(R + T, 1.0, atol=1e-12)
    bare = sheet_coefficients(c2, np.array(eta), np.ones(3))
    zero = sheet_coefficients(c2, np.array(eta), np.ones(3), ThinFilm(0.0, 1.4, eta))
    for a, b in zip(bare, zero, strict=True):
        np.testing.assert_allclose(a, b, atol=1e-12)


def test_a_tinted_sheet_with_a_film_never_gains():
    """An absorbing sheet: R + T <= 1, and T is the same from either face (the formula is
    symmetric in the faces' reflectances)."""
    c2 = np.linspace(0.0, 1.0, 41)
    R, T = sheet_coefficients(c2, np.array(1.5), np.array([0.9, 0.5, 0.2]),
                              ThinFilm(300.0, 1.33, 1.5))
    assert np.all(R + T <= 1.0 + 1e-12) and np.all(R >= 0) and np.all(T >= 0)


@pytest.mark.parametrize("eta, alpha", [(1.0, 0.2), (1.5, 0.35)])
def test_rough_sheet_with_a_film_white_furnace_and_reciprocity(eta, alpha):
    """Rough clear sheet with a film: albedo (quadrature) 1 within 1e-3 from both sides, the
    table albedo 1 exactly (R + T = 1); f(wo, wi) = f(wi, wo) on either side and across."""
    lobe = ThinDielectric(eta, alpha, film=ThinFilm(450.0, 1.33, eta))
    wo = np.concatenate([_direction(COSINES[:4]), _direction(COSINES[:4], side=-1.0)])
    np.testing.assert_allclose(lobe.albedo(wo, tol=1e-6), 1.0, atol=1e-3)
    np.testing.assert_allclose(lobe.albedo(wo, method="table"), 1.0, atol=1e-12)
    rng = np.random.default_rng(4)
    a, b = ab.frame.normalize(rng.normal(size=(2, 300, 3)))
    np.testing.assert_allclose(lobe.eval(a, b), lobe.eval(b, a), rtol=1e-12, atol=0)


@pytest.mark.parametrize("cos_theta", [0.8, 0.3, -0.6])
def test_rough_sheet_with_a_film_sampling(cos_theta):
    lobe = ThinDielectric(1.0, 0.25, film=ThinFilm(400.0, 1.33, 1.0))
    assert_sampling_matches(lobe, cos_theta, 0.4, seed=6, n_tests=3)


def test_film_must_be_a_fresnel_model():
    with pytest.raises(ValueError, match="film"):
        ThinDielectric(1.5, 0.2, film=lambda c: c)
