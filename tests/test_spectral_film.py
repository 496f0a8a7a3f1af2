"""The brute-force spectral thin-film reference (``validation.spectral_film``) against closed
forms, then the library's ``ThinFilm`` against the reference.

Expected values come from closed forms written here (the Fresnel equations, the quarter- and
half-wave films, energy conservation), never from the code under test.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adobe_bsdf.spectral import conductor_from_f82_tint
from adobe_bsdf.thin_film import ThinFilm
from adobe_bsdf.validation import spectral_film as sf

LAM = sf.WAVELENGTHS_NM
VIEWS = np.array([1.0, 0.7, 0.3, 0.05])
#: library against reference: the largest per-channel RGB difference accepted
RGB_TOL = 0.01


def fresnel_dielectric(c1, n1, n3):
    """Unpolarised Fresnel reflectance of the interface n1 / n3 (real indices), 1 beyond the
    critical angle [BornWolf1980, §1.5.2]."""
    sin_t2 = (n1 / n3) ** 2 * (1.0 - c1 * c1)
    tir = sin_t2 >= 1.0
    ct = np.sqrt(np.where(tir, 0.0, 1.0 - sin_t2))
    rs = (n1 * c1 - n3 * ct) / (n1 * c1 + n3 * ct)
    rp = (n3 * c1 - n1 * ct) / (n3 * c1 + n1 * ct)
    return np.where(tir, 1.0, 0.5 * (rs * rs + rp * rp))


# --- the reference against closed forms ---------------------------------------------------
def test_white_reflector_is_white():
    np.testing.assert_allclose(sf.spectrum_to_rgb(np.ones(LAM.size)), 1.0, atol=1e-3)
    np.testing.assert_allclose(sf.spectrum_to_rgb(np.zeros((2, LAM.size))), 0.0, atol=0.0)


@pytest.mark.parametrize("n1, n3", [(1.0, 1.5), (1.0, 2.4), (1.5, 1.0), (1.33, 1.8)])
def test_zero_thickness_is_the_bare_interface(n1, n3):
    """d = 0: r = (r12 + r23) / (1 + r12 r23) = r13 whatever the film index (the film
    vanishes), including total internal reflection for n1 > n3."""
    c = np.array([1.0, 0.9, 0.7, 0.5, 0.3, 0.1, 0.02])[:, None]
    expected = fresnel_dielectric(c, n1, n3)
    for n2 in (1.2, 1.5, 2.4):
        R = sf.film_reflectance_spectrum(LAM, c, 0.0, n2, n3, outside_ior=n1)
        np.testing.assert_allclose(R, np.broadcast_to(expected, R.shape), rtol=0, atol=1e-14)


@pytest.mark.parametrize("n1, n3, lam0", [(1.0, 1.52, 550.0), (1.0, 2.0, 450.0),
                                          (1.33, 1.9, 620.0)])
def test_quarter_wave_film_cancels_the_reflection(n1, n3, lam0):
    """n2 = sqrt(n1 n3), d = lam0 / (4 n2): r12 = r23 and e^{2 i beta} = -1 at lam0, so
    R(lam0) = 0 at normal incidence, the minimum over the visible range."""
    n2 = np.sqrt(n1 * n3)
    d = lam0 / (4.0 * n2)
    R = sf.film_reflectance_spectrum(LAM, 1.0, d, n2, n3, outside_ior=n1)
    at = sf.film_reflectance_spectrum(lam0, 1.0, d, n2, n3, outside_ior=n1)
    assert at < 1e-12
    assert LAM[np.argmin(R)] == lam0
    near = sf.film_reflectance_spectrum(lam0 + np.array([-2.0, -0.5, 0.5, 2.0]), 1.0, d,
                                        n2, n3, outside_ior=n1)
    assert np.all(near > at)
    # without the film the same substrate reflects ((n3 - n1) / (n3 + n1))^2
    assert R.max() < ((n3 - n1) / (n3 + n1)) ** 2


@pytest.mark.parametrize("n2", [1.2, 1.45, 1.8, 2.4])
def test_half_wave_film_is_absent(n2):
    """d = lam0 / (2 n2): e^{2 i beta} = 1 at lam0, r = r13 at normal incidence."""
    lam0 = 500.0
    for n1, n3 in ((1.0, 1.5), (1.0, 2.0), (1.5, 1.2)):
        R = sf.film_reflectance_spectrum(lam0, 1.0, lam0 / (2.0 * n2), n2, n3, outside_ior=n1)
        assert R == pytest.approx(((n3 - n1) / (n3 + n1)) ** 2, abs=1e-14)


def test_perfect_reflector_under_a_film_reflects_everything():
    """|r23| = 1 and a lossless film: |r| = 1 at every wavelength and angle."""
    c = VIEWS[:, None]
    for n2, d in ((1.2, 100.0), (1.5, 400.0), (2.4, 700.0)):
        R = sf.film_reflectance_spectrum(LAM, c, d, n2, np.inf)
        np.testing.assert_allclose(R, 1.0, rtol=0, atol=1e-13)


@pytest.mark.parametrize("n, k", [(0.2, 3.0), (1.04, 3.84), (2.5, 0.5), (1.5, 0.0)])
def test_zero_thickness_on_a_conductor_at_normal_incidence(n, k):
    expected = ((n - 1.0) ** 2 + k * k) / ((n + 1.0) ** 2 + k * k)
    R = sf.film_reflectance_spectrum(LAM, 1.0, 0.0, 1.45, n, k)
    np.testing.assert_allclose(R, expected, rtol=0, atol=1e-14)
    # a flat spectrum keeps its value in colour (up to the white's rounding)
    np.testing.assert_allclose(sf.film_rgb(1.0, 0.0, 1.45, n, k), expected, atol=1e-3)


def test_transmittance_conserves_energy():
    """R + T = 1 for a lossless film on a dielectric, T being the transmitted power
    Re(n3 cos theta3) / (n1 cos theta1) |t|^2: below and beyond the film's critical angle
    (frustrated total reflection) and beyond the substrate's (T = 0)."""
    c = np.array([1.0, 0.8, 0.5, 0.3, 0.1, 0.01])[:, None, None]
    d = np.array([0.0, 50.0, 250.0, 700.0])[:, None]
    for n1, n2, n3 in ((1.0, 1.45, 1.5), (1.0, 2.4, 1.3), (1.5, 1.0, 1.6), (1.6, 1.2, 1.0),
                       (1.0, 1.2, 2.0)):
        R = sf.film_reflectance_spectrum(LAM, c, d, n2, n3, outside_ior=n1)
        T = sf.film_transmittance_spectrum(LAM, c, d, n2, n3, outside_ior=n1)
        np.testing.assert_allclose(R + T, 1.0, rtol=0, atol=1e-12)
        assert np.all(T >= 0.0)
        if n3 < n1:  # beyond the substrate's critical angle nothing is transmitted
            beyond = (n1 / n3) ** 2 * (1.0 - c[:, 0, 0] ** 2) > 1.0
            assert np.all(T[beyond] == 0.0)
        rgb = sf.film_rgb(c[..., 0], d[..., 0], n2, n3, outside_ior=n1)
        rgb_t = sf.film_transmittance_rgb(c[..., 0], d[..., 0], n2, n3, outside_ior=n1)
        white = np.broadcast_to(sf.spectrum_to_rgb(np.ones(LAM.size)), rgb.shape)
        np.testing.assert_allclose(rgb + rgb_t, white, rtol=0, atol=1e-12)


@settings(max_examples=60, deadline=None)
@given(c=st.floats(1e-3, 1.0), d=st.floats(0.0, 3000.0), n1=st.floats(1.0, 2.0),
       n2=st.floats(0.5, 3.5), n=st.floats(0.05, 5.0), k=st.floats(0.0, 8.0))
def test_reflectance_is_a_fraction(c, d, n1, n2, n, k):
    R = sf.film_reflectance_spectrum(LAM, c, d, n2, n, k, n1)
    assert np.all(np.isfinite(R))
    assert np.all(R >= 0.0)
    assert np.all(R <= 1.0 + 1e-12)


def test_arguments_are_validated():
    with pytest.raises(ValueError, match="cos_theta"):
        sf.film_reflectance_spectrum(LAM, 0.0, 100.0, 1.5, 1.5)
    with pytest.raises(ValueError, match="thickness_nm"):
        sf.film_rgb(1.0, -1.0, 1.5, 1.5)
    with pytest.raises(ValueError, match="spectrum"):
        sf.spectrum_to_rgb(np.ones(10))


# --- the library against the reference -----------------------------------------------------
# The library's default ``ThinFilm`` clips its colour to [0, 1]; the reference is clipped the
# same way before the comparison (none of these films leaves [0, 1]).
@pytest.mark.parametrize("d", [0.0, 100.0, 250.0, 400.0, 700.0])
def test_library_film_over_a_dielectric(d):
    worst = 0.0
    for n2 in (1.2, 1.45, 1.8, 2.4):
        for n3 in (1.3, 1.5, 2.0):
            reference = np.clip(sf.film_rgb(VIEWS, d, n2, n3), 0.0, 1.0)
            film = ThinFilm(d, n2, n3)
            worst = max(worst, np.abs(film(VIEWS) - reference).max(),
                        np.abs(film.from_cos2(VIEWS**2) - reference).max())
    assert worst <= RGB_TOL, f"worst per-channel difference {worst:.3g}"


METALS = {"gold-like": ((1.0, 0.78, 0.34), (1.0, 0.9, 0.75)), "grey": (0.5, 1.0)}


@pytest.mark.parametrize("metal", list(METALS))
@pytest.mark.parametrize("d", [0.0, 100.0, 250.0, 400.0, 700.0])
def test_library_film_over_an_f82_tint_metal(metal, d):
    """The film over the per-channel complex index the library infers from the F82-tint
    colours (an infinite index where f0 = 1: a perfect reflector), evaluated brute force."""
    f0, tint = METALS[metal]
    n, k, _ = conductor_from_f82_tint(f0, tint)
    worst = 0.0
    for n2 in (1.2, 1.45, 1.8, 2.4):
        reference = np.clip(sf.film_rgb_per_channel(VIEWS, d, n2, n, k), 0.0, 1.0)
        film = ThinFilm.over_f82_tint(d, n2, f0, tint)
        worst = max(worst, np.abs(film(VIEWS) - reference).max())
    assert worst <= RGB_TOL, f"worst per-channel difference {worst:.3g}"
