"""Thin-film reflectance against closed forms, an independent characteristic-matrix
implementation, colour-science's transfer-matrix method and the film-free Fresnel models."""

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import adobe_bsdf as ab
from adobe_bsdf import config, spectral, thin_film
from tests.tolerances import EXACT

F = ab.fresnel
airy_R, airy_T, ThinFilm = (thin_film.airy_reflectance, thin_film.airy_transmittance,
                            thin_film.ThinFilm)
GOLD_ETA = np.array([0.143, 0.374, 1.442])
GOLD_K = np.array([3.983, 2.385, 1.603])
#: the library's own colour integral: 1 nm samples (the grid of ``spectral``)
GRID_1NM = np.arange(380.0, 781.0, 1.0)
#: the acceptance of ``ThinFilm``'s table in cos theta against the spectral sum (max |RGB
#: error|; measured up to 2.2e-6, the ``ThinFilm`` docstring)
TABLE_ERROR = 1e-5


# --- independent references --------------------------------------------------------------
def _decaying(z):
    """The root of z^2 whose wave decays into the medium: Im > 0, or Re >= 0 if real."""
    flip = (z.imag < 0) | ((z.imag == 0) & (z.real < 0))
    return np.where(flip, -z, z)


def characteristic_matrix_r_t(lam, cos1, d, n1, n2, n3, pol):
    """(r, t, p1, p3) of one homogeneous layer by its characteristic matrix [BornWolf1980,
    §1.6.2-§1.6.3]: M = [[cos b, -i sin b / p2], [-i p2 sin b, cos b]], b = 2 pi n2 d
    cos theta2 / lam, with p_j = n_j cos theta_j (s, TE) or cos theta_j / n_j (p, TM);
    r = ((m11 + m12 p3) p1 - (m21 + m22 p3)) / ((m11 + m12 p3) p1 + (m21 + m22 p3)),
    t = 2 p1 / (the same denominator). The layer is split into two halves whose matrices
    are multiplied, as for a stratified medium. sin b / p2 is evaluated as a sinc so that
    the film's critical angle (p2 = 0) is regular."""
    lam, cos1, d = (np.asarray(x, dtype=complex) for x in (lam, cos1, d))
    n1, n2, n3 = (np.asarray(x, dtype=complex) for x in (n1, n2, n3))
    sin2 = (n1 * n1) * (1 - cos1 * cos1)  # n1^2 sin^2 theta1, the invariant
    ncos = [_decaying(np.sqrt(n * n - sin2)) for n in (n1, n2, n3)]  # n_j cos theta_j
    if pol == "s":
        p1, p2, p3 = ncos
    else:
        p1, p2, p3 = (nc / (n * n) for nc, n in zip(ncos, (n1, n2, n3), strict=True))
    k0 = 2 * np.pi / lam

    def layer(thickness):
        b = k0 * ncos[1] * thickness
        sinc = np.sinc(b / np.pi) * k0 * thickness  # sin(b) / (n2 cos theta2)
        sin_over_p2 = sinc if pol == "s" else sinc * n2 * n2
        return np.array([[np.cos(b), -1j * sin_over_p2], [-1j * p2 * np.sin(b), np.cos(b)]])

    half = layer(d / 2)
    M = np.einsum("ij...,jk...->ik...", half, half)
    u = M[0, 0] + M[0, 1] * p3
    v = M[1, 0] + M[1, 1] * p3
    return (u * p1 - v) / (u * p1 + v), 2 * p1 / (u * p1 + v), p1, p3


def characteristic_matrix_R(lam, cos1, d, n1, n2, n3):
    """Unpolarised reflectance of ``characteristic_matrix_r_t``."""
    return np.mean([np.abs(characteristic_matrix_r_t(lam, cos1, d, n1, n2, n3, pol)[0]) ** 2
                    for pol in "sp"], axis=0)


def characteristic_matrix_T(lam, cos1, d, n1, n2, n3):
    """Unpolarised transmittance Re(p3) / Re(p1) |t|^2 (real outside and substrate)."""
    out = []
    for pol in "sp":
        _, t, p1, p3 = characteristic_matrix_r_t(lam, cos1, d, n1, n2, n3, pol)
        out.append(p3.real / p1.real * np.abs(t) ** 2)
    return np.mean(out, axis=0)


def _colour():
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message='"Matplotlib" related API features')
        return pytest.importorskip("colour", reason="colour-science provides the TMM check")


# --- airy_reflectance --------------------------------------------------------------------
def test_normal_incidence_closed_form():
    """500 nm of n = 1.33 in air on glass: R = (r12^2 + r23^2 + 2 r12 r23 cos delta) /
    (1 + r12^2 r23^2 + 2 r12 r23 cos delta), delta = 4 pi n d / lambda [BornWolf1980,
    §1.6.4], with the normal-incidence amplitudes r_ij = (n_i - n_j) / (n_i + n_j)."""
    lam = np.linspace(380.0, 780.0, 10)
    n1, n2, n3, d = 1.0, 1.33, 1.5, 500.0
    r12, r23 = (n1 - n2) / (n1 + n2), (n2 - n3) / (n2 + n3)
    cos_delta = np.cos(4 * np.pi * n2 * d / lam)
    expected = ((r12**2 + r23**2 + 2 * r12 * r23 * cos_delta)
                / (1 + r12**2 * r23**2 + 2 * r12 * r23 * cos_delta))
    np.testing.assert_allclose(airy_R(lam, 1.0, d, n2, n3), expected, rtol=0, atol=1e-10)
    # the fringes are real: R swings by more than 0.02 over the visible range
    assert np.ptp(expected) > 0.02


@pytest.mark.parametrize(("n1", "n2", "n3"), [
    (1.0, 1.33, 1.5), (1.0, 1.8, 1.5), (1.5, 1.2, 1.0),  # the last has TIR in film and base
    (1.0, 2.9, 1.0), (1.6, 1.3, 1.45),
])
def test_oblique_incidence_against_characteristic_matrix(n1, n2, n3):
    lam = np.array([380.0, 455.0, 532.0, 610.0, 780.0])[:, None, None]
    mu = np.linspace(0.0, 1.0, 41)[None, :, None]
    d = np.array([0.0, 80.0, 300.0, 1000.0])
    with np.errstate(invalid="ignore", divide="ignore"):  # its 0/0 at mu = 0
        expected = characteristic_matrix_R(lam, mu, d, n1, n2, n3)
    # grazing: R = 1 (the matrix form divides 0 by 0), but 0 without film on n3 = n1
    expected[:, 0, :] = 1.0
    expected[:, 0, 0] = F.dielectric(0.0, n3 / n1)
    value = airy_R(lam, mu, d, n2, n3, outside_ior=n1)
    assert value.shape == (5, 41, 4)
    np.testing.assert_allclose(value, expected, rtol=0, atol=1e-10)


@pytest.mark.parametrize("n2", [1.33, 1.6, 2.4])
def test_gold_substrate_against_characteristic_matrix(n2):
    """An absorbing substrate: gold's measured n + i k at a few wavelengths (the shipped
    data), both polarisations averaged, against the matrix form with complex p3."""
    lam_data, n_data, k_data = spectral.metal_ior("Au")
    pick = np.searchsorted(lam_data, [400.0, 500.0, 600.0, 700.0])
    lam, n3, k3 = lam_data[pick], n_data[pick], k_data[pick]
    mu = np.linspace(0.01, 1.0, 50)[:, None, None]
    d = np.array([0.0, 120.0, 450.0, 1000.0])[:, None]
    expected = characteristic_matrix_R(lam, mu, d, 1.0, n2, n3 + 1j * k3)
    value = airy_R(lam, mu, d, n2, n3, k3)
    np.testing.assert_allclose(value, expected, rtol=0, atol=1e-10)
    # thickness 0 is the bare conductor
    for i in range(lam.size):
        np.testing.assert_allclose(value[:, 0, i], F.conductor(mu[:, 0, 0], n3[i], k3[i])[:, 0],
                                   rtol=0, atol=EXACT)


def test_both_polarisations_against_colour_science_tmm():
    """colour-science's transfer-matrix method (after Byrnes 2016) per polarisation:
    the unpolarised mean and the R + T of both agree with ours."""
    colour = _colour()
    lam = np.array([400.0, 520.0, 650.0])
    for n1, n2, n3, d, theta in [(1.0, 1.33, 1.5, 500.0, 35.0), (1.0, 2.2, 1.5, 250.0, 70.0),
                                 (1.5, 1.3, 1.7, 700.0, 55.0)]:
        R, T = colour.phenomena.thin_film_tmm([n1, n2, n3], d, lam, theta)
        mu = np.cos(np.radians(theta))
        np.testing.assert_allclose(airy_R(lam, mu, d, n2, n3, outside_ior=n1),
                                   R[:, 0, 0, :].mean(axis=-1), rtol=0, atol=1e-10)
        np.testing.assert_allclose(airy_T(lam, mu, d, n2, n3, outside_ior=n1),
                                   T[:, 0, 0, :].mean(axis=-1), rtol=0, atol=1e-10)


def test_thickness_zero_is_the_bare_interface():
    mu = np.linspace(0.0, 1.0, 257)
    for eta in (1.5, 1 / 1.5, 1.0, 2.4):
        np.testing.assert_allclose(airy_R(550.0, mu, 0.0, 1.33, eta), F.dielectric(mu, eta),
                                   rtol=0, atol=EXACT)
    np.testing.assert_allclose(airy_R(550.0, mu[:, None], 0.0, 1.8, GOLD_ETA, GOLD_K),
                               F.conductor(mu, GOLD_ETA, GOLD_K), rtol=0, atol=EXACT)
    # under a coat (outside index 1.5) the relative index is eta / 1.5
    np.testing.assert_allclose(airy_R(550.0, mu, 0.0, 1.33, 2.0, outside_ior=1.5),
                               F.dielectric(mu, 2.0 / 1.5), rtol=0, atol=EXACT)


def test_index_matched_film_and_substrate_are_no_interface():
    mu = np.linspace(0.0, 1.0, 65)
    # film = outside: the bare substrate whatever the thickness
    np.testing.assert_allclose(airy_R(480.0, mu, 350.0, 1.0, 1.5), F.dielectric(mu, 1.5),
                               rtol=0, atol=EXACT)
    # film = substrate: the interface outside / film
    np.testing.assert_allclose(airy_R(480.0, mu, 350.0, 1.4, 1.4), F.dielectric(mu, 1.4),
                               rtol=0, atol=EXACT)
    # all three the same: nothing reflects, everything is transmitted
    np.testing.assert_array_equal(airy_R(480.0, mu, 350.0, 1.2, 1.2, outside_ior=1.2), 0.0)
    np.testing.assert_array_equal(airy_T(480.0, mu, 350.0, 1.2, 1.2, outside_ior=1.2), 1.0)


def test_critical_angle_of_the_film_is_regular():
    """Outside 1.25, film 0.75: the film's critical angle is at cos theta = 0.8, where
    n2^2 - n1^2 sin^2 is exactly 0 in float64; R there equals the matrix form's limit and
    is continuous on both sides."""
    n1, n2, n3, d = 1.25, 0.75, 1.5, 300.0
    assert (n2 - n1) * (n2 + n1) + (n1 * 0.8) ** 2 == 0.0
    lam = np.array([400.0, 550.0, 700.0])
    for mu in (0.8, 0.8 - 1e-9, 0.8 + 1e-9, 0.8 - 1e-4, 0.8 + 1e-4):
        expected = characteristic_matrix_R(lam, mu, d, n1, n2, n3)
        np.testing.assert_allclose(airy_R(lam, mu, d, n2, n3, outside_ior=n1), expected,
                                   rtol=0, atol=1e-10)
        total = airy_R(lam, mu, d, n2, n3, outside_ior=n1) + airy_T(lam, mu, d, n2, n3,
                                                                    outside_ior=n1)
        np.testing.assert_allclose(total, 1.0, rtol=0, atol=EXACT)


_IOR = st.floats(0.3, 3.5)
_COS = st.one_of(st.floats(0.0, 1.0), st.sampled_from([0.0, 5e-324, 1e-310, 1e-160, 1.0]))


@settings(max_examples=300, deadline=None)
@given(lam=st.floats(380.0, 780.0), mu=_COS, d=st.floats(0.0, 3000.0), n1=_IOR, n2=_IOR,
       n3=_IOR, k=st.one_of(st.just(0.0), st.floats(0.0, 8.0)))
def test_energy_conservation_and_range(lam, mu, d, n1, n2, n3, k):
    """The film does not absorb: R + T = 1 (T the power entering the substrate, absorbed
    there for k > 0); 0 <= R, T <= 1 and both finite, total internal reflection and
    subnormal cosines included."""
    R = airy_R(lam, mu, d, n2, n3, k, outside_ior=n1)
    T = airy_T(lam, mu, d, n2, n3, k, outside_ior=n1)
    assert np.isfinite(R) and np.isfinite(T)
    assert 0.0 <= R <= 1.0 and 0.0 <= T <= 1.0
    assert abs(R + T - 1.0) <= EXACT


@settings(max_examples=150, deadline=None)
@given(lam=st.floats(380.0, 780.0), mu=st.floats(0.05, 1.0),
       d=st.one_of(st.just(0.0), st.floats(1e-3, 2000.0)),  # the matrix form overflows below
       n1=st.floats(1.0, 2.0), n2=_IOR, n3=_IOR, k=st.floats(0.0, 5.0))
def test_random_stacks_against_characteristic_matrix(lam, mu, d, n1, n2, n3, k):
    expected = characteristic_matrix_R(lam, mu, d, n1, n2, n3 + 1j * k)
    assert airy_R(lam, mu, d, n2, n3, k, outside_ior=n1) == pytest.approx(expected, abs=1e-10)


def test_transmittance_against_characteristic_matrix():
    lam = np.array([400.0, 600.0])[:, None]
    mu = np.linspace(0.05, 1.0, 20)
    for n1, n2, n3 in [(1.0, 1.33, 1.5), (1.0, 2.0, 1.2), (1.4, 1.1, 1.6)]:
        expected = characteristic_matrix_T(lam, mu, 400.0, n1, n2, n3)
        np.testing.assert_allclose(airy_T(lam, mu, 400.0, n2, n3, outside_ior=n1), expected,
                                   rtol=0, atol=1e-10)


def test_grazing_and_total_internal_reflection_extremes():
    mu = np.array([0.0, 5e-324, 1e-310, 1e-160, 1e-8])
    for n1, n2, n3, k in [(1.0, 1.5, 1.5, 0.0), (1.0, 1.33, 1.0, 0.0), (1.5, 1.0, 1.2, 0.0),
                          (1.0, 0.5, 0.7, 0.0), (1.0, 1.3, 0.2, 3.0), (1.0, 1.0, 1.5, 0.0)]:
        for d in (0.0, 300.0, 1e5):
            R = airy_R(550.0, mu, d, n2, n3, k, outside_ior=n1)
            T = airy_T(550.0, mu, d, n2, n3, k, outside_ior=n1)
            assert np.all(np.isfinite(R)) and np.all(np.isfinite(T))
            np.testing.assert_allclose(R + T, 1.0, rtol=0, atol=EXACT)
            if d == 0.0 and n3 == n1 and k == 0.0:  # no interface at all
                np.testing.assert_array_equal(R, 0.0)
            else:  # R = 1 at grazing incidence, continuously
                assert R[0] == 1.0 and T[0] == 0.0
                np.testing.assert_allclose(R[:4], 1.0, rtol=0, atol=1e-7)
    # past the substrate's critical angle with a thick film nothing enters the substrate
    assert airy_T(550.0, 0.2, 5000.0, 1.2, 1.0, outside_ior=1.5) == 0.0
    assert airy_R(550.0, 0.2, 5000.0, 1.2, 1.0, outside_ior=1.5) == pytest.approx(1.0, abs=EXACT)


@pytest.mark.parametrize("shape", [(), (6,), (2, 3)])
def test_airy_broadcasting(shape):
    mu = np.full(shape, 0.6)
    assert airy_R(550.0, mu, 300.0, 1.33, 1.5).shape == shape
    assert airy_T(np.full(shape, 550.0), 0.6, 300.0, 1.33, 1.5).shape == shape
    assert airy_R(550.0, 0.6, np.full(shape, 300.0), 1.33, 0.2, np.full(shape, 3.0)).shape \
        == shape
    value = airy_R(np.array([450.0, 650.0])[:, None], mu.reshape(-1), 300.0, 1.33, 1.5)
    assert value.shape == (2, mu.size)


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"thickness_nm": -1.0}, "thickness_nm"),
    ({"thickness_nm": np.inf}, "thickness_nm"),
    ({"film_ior": 0.0}, "film_ior"),
    ({"film_ior": np.nan}, "film_ior"),
    ({"substrate_eta": -1.5}, "substrate_eta"),
    ({"substrate_k": -0.1}, "substrate_k"),
    ({"outside_ior": 0.0}, "outside_ior"),
    ({"wavelength_nm": 0.0}, "wavelength_nm"),
    ({"cos_theta": 1.5}, "cos_theta"),
    ({"cos_theta": -0.5}, "cos_theta"),
    ({"cos_theta": np.zeros(4), "thickness_nm": np.zeros(3)}, "cos_theta"),
])
def test_airy_bad_input_names_parameter(kwargs, name):
    args = {"wavelength_nm": 550.0, "cos_theta": 0.5, "thickness_nm": 300.0, "film_ior": 1.33,
            "substrate_eta": 1.5} | kwargs
    with pytest.raises(ValueError, match=name):
        airy_R(**args)


# --- ThinFilm (RGB) ----------------------------------------------------------------------
def test_thin_film_thickness_zero_is_film_free_fresnel():
    mu = np.linspace(0.0, 1.0, 101)
    film = ThinFilm(0.0, 1.33, 1.5)
    assert isinstance(film, F.Fresnel)
    np.testing.assert_allclose(film(mu), np.repeat(F.dielectric(mu, 1.5)[:, None], 3, -1),
                               rtol=0, atol=EXACT)
    metal = ThinFilm(0.0, 1.6, (GOLD_ETA, GOLD_K))
    np.testing.assert_allclose(metal(mu), F.conductor(mu, GOLD_ETA, GOLD_K), rtol=0,
                               atol=EXACT)
    np.testing.assert_allclose(metal.from_cos2(mu * mu), metal(mu), rtol=0, atol=0)
    # one index per channel for a dielectric base
    per_channel = ThinFilm(0.0, 1.4, [1.3, 1.5, 1.7])
    expected = np.stack([F.dielectric(mu, eta) for eta in (1.3, 1.5, 1.7)], axis=-1)
    np.testing.assert_allclose(per_channel(mu), expected, rtol=0, atol=EXACT)


def test_thin_film_index_matched_film_is_the_bare_substrate():
    mu = np.linspace(0.0, 1.0, 33)
    film = ThinFilm(400.0, 1.5, 2.0, outside_ior=1.5)  # film = coat above it
    np.testing.assert_allclose(film(mu)[:, 1], F.dielectric(mu, 2.0 / 1.5), rtol=0, atol=EXACT)


def test_thin_film_rgb_is_the_colour_of_the_independent_spectrum():
    """On the 1 nm grid the RGB of the spectral sum (``spectral_rgb``, and the film built
    with ``tabulated=False``) is ``spectral.reflectance_to_rgb`` of the characteristic-
    matrix spectrum (each channel with its own substrate index); the film's table is within
    its tolerance of it."""
    mu = np.array([1.0, 0.7, 0.3])
    gold = GOLD_ETA + 1j * GOLD_K
    for substrate, n3 in [(1.5, np.full(3, 1.5 + 0j)), ((GOLD_ETA, GOLD_K), gold)]:
        film = ThinFilm(420.0, 1.45, substrate, wavelengths_nm=GRID_1NM, clip=False)
        direct = ThinFilm(420.0, 1.45, substrate, wavelengths_nm=GRID_1NM, clip=False,
                          tabulated=False)
        for ch in range(3):
            spectrum = characteristic_matrix_R(GRID_1NM, mu[:, None], 420.0, 1.0, 1.45, n3[ch])
            expected = spectral.reflectance_to_rgb(GRID_1NM, spectrum)[:, ch]
            np.testing.assert_allclose(film.spectral_rgb(mu)[:, ch], expected, rtol=0,
                                       atol=1e-10)
            np.testing.assert_allclose(direct(mu)[:, ch], expected, rtol=0, atol=1e-10)
            np.testing.assert_allclose(film(mu)[:, ch], expected, rtol=0, atol=TABLE_ERROR)


def test_soap_film_is_coloured_and_changes_with_thickness():
    """A 300 nm soap film (n = 1.33 in air, air behind it) is not grey, and its colour
    changes with the thickness; thickness 0 is (0, 0, 0): nothing to reflect."""
    thickness = np.array([0.0, 300.0, 400.0, 550.0])
    rgb = ThinFilm(thickness, 1.33, 1.0)(1.0)
    assert rgb.shape == (4, 3)
    np.testing.assert_array_equal(rgb[0], 0.0)
    assert np.ptp(rgb[1]) > 0.5 * np.mean(rgb[1])  # measured: (0.043, 0.078, 0.033)
    chroma = rgb[1:] / rgb[1:].sum(axis=-1, keepdims=True)
    assert np.min(np.abs(chroma[:, None] - chroma[None, :]).sum(-1) + np.eye(3)) > 0.05


def test_thin_film_over_f82_tint():
    """Thickness 0 reproduces F82-tint where the exact conductor is fitted to it (cos theta =
    1 and 1/7), also under a coat; f0 = 1 is a perfect reflector with or without film."""
    f0, tint = np.array([0.95, 0.64, 0.54]), np.array([0.9, 0.85, 0.8])
    for outside in (1.0, 1.5):
        film = ThinFilm.over_f82_tint(0.0, 1.4, f0, tint, outside_ior=outside)
        np.testing.assert_allclose(film(np.array([1.0, 1 / 7])),
                                   F.f82_tint(np.array([1.0, 1 / 7]), f0, tint), atol=1e-9)
    mirror = ThinFilm.over_f82_tint(500.0, 1.4, [1.0, 0.5, 0.5], 1.0)
    assert np.all(mirror(np.linspace(0, 1, 9))[:, 0] == 1.0)
    coloured = ThinFilm.over_f82_tint(350.0, 1.8, f0, tint)(np.linspace(0.0, 1.0, 9))
    assert np.all((coloured >= 0.0) & (coloured <= 1.0))
    assert np.abs(coloured - F.f82_tint(np.linspace(0.0, 1.0, 9), f0, tint)).max() > 0.05


@pytest.mark.parametrize("shape", [(), (6,), (2, 3)])
def test_thin_film_broadcasting(shape):
    thickness = np.full(shape, 250.0)
    film = ThinFilm(thickness, 1.33, 1.5)
    assert film.param_shape == shape
    assert film(0.5).shape == (*shape, 3)
    assert film.from_cos2(np.full(shape, 0.25)).shape == (*shape, 3)
    metal = ThinFilm(300.0, np.full(shape, 1.4), (np.full((*shape, 3), 0.3), 3.0))
    assert metal.param_shape == shape
    assert metal(np.full(shape, 0.5)).shape == (*shape, 3)
    assert ThinFilm(300.0, 1.4, 1.5)(np.full(shape, 0.5)).shape == (*shape, 3)


def test_thin_film_texture_equals_one_call_per_texel_and_chunks_do_not_matter():
    """A texture of films is the spectral sum per texel (no table): one texel's film gives
    the same by ``spectral_rgb`` to rounding, and by its table to the table's error."""
    rng = np.random.default_rng(7)
    thickness = rng.uniform(0.0, 1000.0, 40)
    mu = rng.uniform(0.0, 1.0, 40)
    textured = ThinFilm(thickness, 1.5, (GOLD_ETA, GOLD_K))
    assert textured.table() is None and not textured.tabulated
    texture = textured(mu)
    for i in (0, 17, 39):
        texel = ThinFilm(thickness[i], 1.5, (GOLD_ETA, GOLD_K))
        np.testing.assert_allclose(texture[i], texel.spectral_rgb(mu[i]), rtol=0, atol=1e-15)
        np.testing.assert_allclose(texture[i], texel(mu[i]), rtol=0, atol=TABLE_ERROR)
    with config.options(chunk_size=500):  # chunks of 2 texels on the 201-sample grid
        np.testing.assert_allclose(ThinFilm(thickness, 1.5, (GOLD_ETA, GOLD_K))(mu), texture,
                                   rtol=0, atol=1e-15)


def test_thin_film_rgb_stays_in_unit_interval_unless_unclipped():
    """Linear Rec. 709 of a saturated fringe leaves [0, 1]; the Fresnel model clips it (a
    lobe's F must stay in [0, 1]); ``clip=False`` gives the conversion as it is."""
    thickness = np.linspace(0.0, 1000.0, 101)[:, None]
    mu = np.linspace(0.0, 1.0, 11)
    raw = ThinFilm(thickness, 1.2, 1.0, clip=False)(mu)
    assert raw.min() < -0.05 and raw.max() > 1.05
    clipped = ThinFilm(thickness, 1.2, 1.0)(mu)
    np.testing.assert_array_equal(clipped, np.clip(raw, 0.0, 1.0))


@pytest.mark.parametrize(("n2", "bound"), [(1.33, 2.5e-4), (2.0, 2.5e-4), (3.0, 6e-3)])
def test_default_wavelength_grid_convergence(n2, bound):
    """The default 2 nm grid against the 1 nm grid (the colour integral of ``spectral``),
    for films up to 1000 nm at all angles over dielectric and metal bases: the figures the
    ``ThinFilm`` docstring states."""
    thickness = np.linspace(0.0, 1000.0, 201)[:, None]
    mu = np.linspace(0.0, 1.0, 11)
    error = 0.0
    for substrate in (1.0, 1.5, 2.5, (GOLD_ETA, GOLD_K)):
        coarse = ThinFilm(thickness, n2, substrate, clip=False)(mu)
        fine = ThinFilm(thickness, n2, substrate, wavelengths_nm=GRID_1NM, clip=False)(mu)
        error = max(error, np.abs(coarse - fine).max())
    print(f"n2 = {n2}: max |RGB(2 nm) - RGB(1 nm)| = {error:.3g}")
    assert error <= bound


@pytest.mark.parametrize(("call", "name"), [
    (lambda: ThinFilm(-1.0, 1.33, 1.5), "thickness_nm"),
    (lambda: ThinFilm(np.nan, 1.33, 1.5), "thickness_nm"),
    (lambda: ThinFilm(300.0, 0.0, 1.5), "film_ior"),
    (lambda: ThinFilm(300.0, 1.33, 0.0), "substrate"),
    (lambda: ThinFilm(300.0, 1.33, [1.5, 1.5]), "substrate"),
    (lambda: ThinFilm(300.0, 1.33, (0.2, -3.0)), "substrate k"),
    (lambda: ThinFilm(300.0, 1.33, (-0.2, 3.0)), "substrate eta"),
    (lambda: ThinFilm(300.0, 1.33, 1.5, outside_ior=-1.0), "outside_ior"),
    (lambda: ThinFilm(300.0, 1.33, 1.5, wavelengths_nm=[400.0, 700.0]), "wavelengths_nm"),
    (lambda: ThinFilm(300.0, 1.33, 1.5, wavelengths_nm=[780.0, 380.0]), "wavelengths_nm"),
    (lambda: ThinFilm(300.0, 1.33, 1.5, clip=1), "clip"),
    (lambda: ThinFilm(300.0, 1.33, 1.5, tabulated=1), "tabulated"),
    (lambda: ThinFilm(300.0, 1.33, 1.5).spectral_rgb(1.5), "cos_theta"),
    (lambda: ThinFilm(300.0, 1.33, 1.5)(1.5), "cos_theta"),
    (lambda: ThinFilm.over_f82_tint(300.0, 1.33, 1.2, 0.5), "f0"),
    (lambda: ThinFilm.over_f82_tint(-300.0, 1.33, 0.5, 0.5), "thickness_nm"),
])
def test_thin_film_bad_input_names_parameter(call, name):
    with pytest.raises(ValueError, match=name):
        call()


def test_subnormal_film_at_a_subnormal_cosine():
    """A film of subnormal thickness seen at a subnormal cosine between equal media: NumPy's
    complex division of subnormals gave R = 1 and T = 1 (hypothesis found it). The result
    depends on d / mu only: the same at (2^-1022, 2^-1022) and (1e-300, 1e-300)."""
    tiny = 2.0**-1022
    R = airy_R(380.0, tiny, tiny, 2.0, 1.0, 0.0, outside_ior=1.0)
    T = airy_T(380.0, tiny, tiny, 2.0, 1.0, 0.0, outside_ior=1.0)
    assert abs(R + T - 1.0) <= EXACT
    np.testing.assert_allclose(R, airy_R(380.0, 1e-300, 1e-300, 2.0, 1.0, 0.0,
                                         outside_ior=1.0), rtol=1e-9)
    assert 0.0 < R < 1e-3



# --- the table in cos theta ----------------------------------------------------------------
def _held_out(film, n=1001, seed=0):
    """Cosines the table was not built on: an even grid, random ones and points 10^-k on
    either side of every critical angle."""
    rng = np.random.default_rng(seed)
    critical = film.critical_cosines()
    near = (critical[:, None, None] + np.array([-1.0, 1.0])[:, None]
            * 10.0 ** -np.arange(2, 13)).ravel()
    return np.concatenate([np.linspace(0.0, 1.0, n), rng.random(n), np.clip(near, 0.0, 1.0)])


_TABLE_FILMS = [  # (thickness nm, film index, substrate, outside index)
    (2000.0, 3.0, 1.5, 1.0), (2000.0, 1.05, 1 / 3, 1.0), (800.0, 1.2, 1.0, 1.0),
    (1.0, 0.7, 1 / 3, 1.0),  # a barely-there film: its colour is in a sliver by the critical angle
    (350.0, 1.33, 3.0, 1.0), (600.0, 1.0, 1.6, 1.5),  # under a coat: the film's critical angle
    (1200.0, 2.2, [0.8, 1.2, 2.0], 1.0), (950.0, 1.6, (GOLD_ETA, GOLD_K), 1.0),
]


@pytest.mark.parametrize(("d", "n2", "substrate", "n1"), _TABLE_FILMS)
def test_thin_film_table_against_the_spectral_sum(d, n2, substrate, n1):
    """The table in cos theta against the spectral sum at held-out cosines, critical angles
    included: within ``TABLE_ERROR`` (the ``ThinFilm`` docstring's measurement covers the
    whole range), clipped and unclipped."""
    for clip in (False, True):
        film = ThinFilm(d, n2, substrate, outside_ior=n1, clip=clip)
        mu = _held_out(film)
        error = np.abs(film(mu) - film.spectral_rgb(mu)).max()
        print(f"d = {d}, n2 = {n2}, clip = {clip}: max |table - spectral| = {error:.2e}, "
              f"{len(film.table())} nodes")
        assert error <= TABLE_ERROR


@pytest.mark.parametrize("seed", [0, 1])
def test_thin_film_table_over_f82_tint_metals(seed):
    rng = np.random.default_rng(seed)
    for _ in range(3):
        film = ThinFilm.over_f82_tint(rng.uniform(0.0, 2000.0), rng.uniform(1.0, 3.0),
                                      rng.uniform(0.0, 1.0, 3), rng.uniform(0.0, 1.0, 3),
                                      outside_ior=rng.choice([1.0, 1.5]), clip=False)
        mu = _held_out(film, 501, seed)
        assert np.abs(film(mu) - film.spectral_rgb(mu)).max() <= TABLE_ERROR


def test_thin_film_table_is_built_once_and_vanishes_with_the_film():
    """One table per film, on first use; the table holds F - F_bare, so a vanishing film
    (thickness 1e-9 nm, an index-matched film) is the film-free Fresnel to rounding, and
    ``tabulated=False`` is the spectral sum itself."""
    film = ThinFilm(500.0, 1.4, 1.5)
    assert film._table is None
    table = film.table()
    assert film.table() is table and film._table is table
    mu = np.linspace(0.0, 1.0, 101)
    bare = np.repeat(F.dielectric(mu, 1.5)[:, None], 3, -1)
    for vanishing in (ThinFilm(1e-9, 1.4, 1.5), ThinFilm(700.0, 1.0, 1.5)):
        np.testing.assert_allclose(vanishing(mu), bare, rtol=0, atol=1e-12)
        assert np.abs(vanishing.table().values).max() <= 1e-12
    direct = ThinFilm(500.0, 1.4, 1.5, tabulated=False)
    assert direct.table() is None
    np.testing.assert_array_equal(direct(mu), film.spectral_rgb(mu))


def test_adaptive_cubic():
    """Exact for a cubic; meets its tolerance between the nodes of a smooth oscillating
    function and, with the branch point as a break, of a square root; stops at max_nodes
    (``converged`` False); clamps outside [0, 1]."""
    def cubic(x):
        return np.stack([1.0 - 2.0 * x + 3.0 * x**3, x * x], axis=-1)
    x = np.linspace(0.0, 1.0, 997)
    exact = thin_film.AdaptiveCubic(cubic, 1e-12)
    assert len(exact) == 33 and exact.converged
    np.testing.assert_allclose(exact(x), cubic(x), rtol=0, atol=1e-14)
    assert exact(np.array([-1.0, 2.0])).tolist() == cubic(np.array([0.0, 1.0])).tolist()

    def wave(x):
        return np.sin(40.0 * x)[:, None]
    table = thin_film.AdaptiveCubic(wave, 1e-7)
    assert table.converged and table.midpoint_error <= 1e-7
    assert np.abs(table(x) - wave(x)).max() <= 3e-7

    def root(x):
        return np.sqrt(np.abs(x - 0.3))[:, None]
    kinked = thin_film.AdaptiveCubic(root, 1e-5, breaks=[0.3])
    near = 0.3 + np.concatenate([-1.0, 1.0] * np.logspace(-12, -1, 45)[:, None])
    assert np.abs(kinked(near) - root(near)).max() <= 3e-5
    assert not thin_film.AdaptiveCubic(wave, 1e-12, max_nodes=40).converged
