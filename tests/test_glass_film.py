"""A thin film on a rough dielectric interface (``Dielectric(film=)``, ``DielectricMS(film=)``,
``OpenPBRSurface`` translucent with ``thin_film_weight``): the film-free limit, generalized
reciprocity, the white furnace, the film's energy table against direction-space cubature,
the smooth interface against the brute-force spectral reference, and sampling."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.lobes import Dielectric, DielectricMS, TintedRefraction
from adobe_bsdf.lobes.film_energy import FilmEnergy
from adobe_bsdf.thin_film import ThinFilm
from adobe_bsdf.validation import spectral_film
from tests.sampling_checks import assert_sampling_matches
from tests.tolerances import FURNACE_TABLE_DIELECTRIC

COSINES = np.array([0.95, 0.6, 0.3, 0.08])


def _views(cosines=COSINES):
    mu = np.concatenate([cosines, -cosines])
    return np.stack([np.sqrt(1.0 - mu * mu), np.zeros_like(mu), mu], -1)


@pytest.mark.parametrize("eta", [1.5, 1 / 1.5])
def test_thickness_zero_is_the_plain_interface(eta):
    rng = np.random.default_rng(0)
    wo, wi = ab.frame.normalize(rng.normal(size=(2, 2000, 3)))
    plain = Dielectric(eta, 0.3).eval(wo, wi)
    filmed = Dielectric(eta, 0.3, film=ThinFilm(0.0, 1.33, eta)).eval(wo, wi)
    np.testing.assert_allclose(filmed, plain, rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("eta", [1.5, 1 / 1.5])
def test_generalized_reciprocity(eta):
    """f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2 per channel (the film is read at the facet
    cosine above the interface for both directions of a pair)."""
    rng = np.random.default_rng(1)
    wo, wi = ab.frame.normalize(rng.normal(size=(2, 2000, 3)))
    lobe = Dielectric(eta, 0.25, film=ThinFilm(380.0, 1.33, eta))
    n_o = np.where(wo[:, 2] > 0, 1.0, eta)[:, None]
    n_i = np.where(wi[:, 2] > 0, 1.0, eta)[:, None]
    f = lobe.eval(wo, wi)
    np.testing.assert_allclose(f / n_o**2, lobe.eval(wi, wo) / n_i**2, rtol=1e-10, atol=0)
    assert np.all(np.isfinite(f)) and np.all(f >= 0.0)


@pytest.mark.parametrize("eta, alpha, thickness, n_film", [
    (1.5, 0.3, 400.0, 1.33), (1 / 1.5, 0.3, 400.0, 1.33), (1.8, 0.08, 250.0, 2.2),
    (1.33, 0.7, 900.0, 1.5)])
def test_white_furnace(eta, alpha, thickness, n_film):
    """A non-absorbing film keeps the white glass's energy: the albedo by quadrature of eval
    is 1 within the dielectric tables' furnace tolerance per channel from both sides (the
    film-free glass's own), the table albedo 1."""
    lobe = DielectricMS(eta, alpha, film=ThinFilm(thickness, n_film, eta))
    wo = _views(np.array([0.9, 0.3, 0.08]))
    np.testing.assert_allclose(lobe.albedo(wo, tol=1e-5), 1.0, atol=FURNACE_TABLE_DIELECTRIC)
    np.testing.assert_allclose(lobe.albedo(wo, method="table"), 1.0, atol=1e-12)


def test_film_energy_table_against_cubature():
    """Delta(mu) = E_film - E of the single scattering, tabulated, against direction-space
    cubature of ``Dielectric(film=)`` minus ``Dielectric`` at held-out cosines, both sides:
    within 1e-4 per channel."""
    eta, alpha = 1.5, 0.3
    film = ThinFilm(400.0, 1.33, eta)
    energy = FilmEnergy(alpha, eta, film)
    wo = _views(np.array([0.83, 0.41, 0.17]))
    cubature = (Dielectric(eta, alpha, film=film).albedo(wo, tol=1e-7)
                - Dielectric(eta, alpha).albedo(wo, tol=1e-7))
    table = energy(np.abs(wo[:, 2]), wo[:, 2] > 0)
    assert np.abs(table - cubature).max() <= 1e-4, np.abs(table - cubature).max()


@pytest.mark.parametrize("thickness", [150.0, 400.0, 650.0])
def test_smooth_glass_reflects_the_film(thickness):
    """A smooth glass with a film: the energy of its reflected delta (the branch's discrete
    probability, its pdf, times its weight) is the spectral reference's reflectance of
    air / film / glass (clipped to [0, 1] as the film's colour is) within 0.01 per channel,
    and the refracted delta carries the complement: R + T = 1."""
    eta = 1.5
    lobe = DielectricMS(eta, 0.0, film=ThinFilm(thickness, 1.33, eta))
    mu = np.array([1.0, 0.6, 0.2])
    wo = np.stack([np.sqrt(1 - mu * mu), np.zeros(3), mu], -1)
    reflect = lobe.sample(wo, np.array([[0.0, 0.5, 0.5]] * 3))
    refract = lobe.sample(wo, np.array([[1.0 - 1e-12, 0.5, 0.5]] * 3))
    assert np.all(reflect.wi[:, 2] > 0) and np.all(refract.wi[:, 2] < 0)
    R = reflect.pdf[:, None] * reflect.weight
    T = refract.pdf[:, None] * refract.weight * eta * eta  # energy: (eta_i / eta_o)^2
    reference = np.clip(spectral_film.film_rgb(mu, thickness, 1.33, eta), 0.0, 1.0)
    assert np.abs(R - reference).max() <= 0.01, np.abs(R - reference).max()
    np.testing.assert_allclose(R + T, 1.0, atol=1e-12)


@pytest.mark.parametrize("cos_theta", [0.8, 0.25, -0.5, -0.9])
def test_sampling(cos_theta):
    lobe = DielectricMS(1.5, 0.3, film=ThinFilm(400.0, 1.33, 1.5))
    assert_sampling_matches(lobe, cos_theta, 0.4, seed=7, n_tests=4)


def test_tinted_glass_with_a_film():
    """The tinted refraction splits the film's energy: table albedo within 3e-4 of
    quadrature (rough) and sampling passes."""
    lobe = TintedRefraction(DielectricMS(1.5, 0.3, film=ThinFilm(400.0, 1.33, 1.5)),
                            (0.5, 0.7, 1.0))
    wo = _views(np.array([0.8, 0.2]))
    np.testing.assert_allclose(lobe.albedo(wo, method="table"), lobe.albedo(wo, tol=1e-5),
                               atol=3e-4)
    assert_sampling_matches(lobe, 0.6, 0.2, seed=8, n_tests=1)


def test_the_material_applies_it_without_a_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = ab.materials.OpenPBRSurface(transmission_weight=1.0, specular_roughness=0.3,
                                        thin_film_weight=1.0, thin_film_thickness=0.4,
                                        thin_film_ior=1.33)
    np.testing.assert_allclose(m.albedo(_views(), method="table"), 1.0, atol=1e-12)
    plain = ab.materials.OpenPBRSurface(transmission_weight=1.0, specular_roughness=0.3)
    wo = _views()[:2]
    assert np.abs(m.eval(wo, wo * [-1, -1, 1]) - plain.eval(wo, wo * [-1, -1, 1])).max() > 0.01


def test_a_textured_film_on_rough_glass_is_refused():
    with pytest.raises(ValueError, match="film"):
        DielectricMS(1.5, np.array([0.2, 0.3]), film=ThinFilm(400.0, 1.33, 1.5))


@pytest.mark.parametrize("roughness", [0.3, 0.0])
def test_dispersive_glass_with_a_film(roughness):
    """Dispersion: each channel's index carries its own film (``DispersiveMS(film=)``); the
    white glass keeps its energy (table albedo 1; Monte Carlo within 5 standard errors and
    the dielectric furnace tolerance) and no warning drops the film."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = ab.materials.OpenPBRSurface(transmission_weight=1.0, specular_roughness=roughness,
                                        transmission_dispersion_scale=1.0,
                                        thin_film_weight=1.0, thin_film_thickness=0.4,
                                        thin_film_ior=1.33)
    wo = _views(np.array([0.9, 0.3]))
    np.testing.assert_allclose(m.albedo(wo, method="table"), 1.0, atol=1e-12)
    E, sigma = m.albedo(wo, method="mc", n_samples=300_000, rng=3, return_error=True)
    assert np.all(np.abs(E - 1.0) <= FURNACE_TABLE_DIELECTRIC + 5.0 * sigma), (E, sigma)


def test_dispersive_glass_with_a_film_sampling():
    from adobe_bsdf.lobes.kulla_conty import DispersiveMS

    lobe = DispersiveMS(1.5, 0.05, 0.3, film=lambda eta: ThinFilm(400.0, 1.33, eta))
    assert_sampling_matches(lobe, 0.7, 0.3, seed=9, n_tests=2, n_samples=100_000)
    assert_sampling_matches(lobe, -0.6, 0.3, seed=9, n_tests=2, n_samples=100_000)
