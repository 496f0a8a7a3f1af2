"""``ThinFilm``'s three-wavelength model (one wavelength per RGB channel) against the Airy
reflectance at each channel's wavelength, closed forms at normal incidence and the film-free
Fresnel; the default spectral model unchanged; bad arguments."""

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf import spectral, thin_film
from tests.tolerances import EXACT

F = ab.fresnel
ThinFilm, airy_R = thin_film.ThinFilm, thin_film.airy_reflectance
THREE = "three_wavelengths"
RGB_NM = np.array([620.0, 540.0, 450.0])
#: the film's table in cos theta against its direct evaluation (max |error|; measured up to
#: 2.1e-6, the ``ThinFilm`` docstring)
TABLE_ERROR = 1e-5
GOLD = (np.array([0.944, 0.776, 0.373]), 1.0)
MU = np.concatenate([np.linspace(0.0, 1.0, 201), np.random.default_rng(7).random(200)])


def _expected(mu, d, n2, eta, k=(0.0, 0.0, 0.0), n1=1.0, lam=RGB_NM):
    """``(N, 3)``: channel c is ``airy_reflectance`` at lam[c] with the index eta[c] + i k[c],
    one call per channel."""
    eta, k = np.broadcast_to(eta, 3), np.broadcast_to(k, 3)
    return np.stack([airy_R(lam[c], mu, d, n2, eta[c], k[c], n1) for c in range(3)], axis=-1)


def _normal_incidence(lam, d, n1, n2, n3):
    """The Airy reflectance of a film on a dielectric at normal incidence in closed form:
    (r12^2 + r23^2 + 2 r12 r23 cos delta) / (1 + r12^2 r23^2 + 2 r12 r23 cos delta),
    delta = 4 pi n2 d / lambda [BornWolf1980, §1.6.4]."""
    r12, r23 = (n1 - n2) / (n1 + n2), (n2 - n3) / (n2 + n3)
    cross = 2.0 * r12 * r23 * np.cos(4.0 * np.pi * n2 * d / np.asarray(lam))
    return (r12**2 + r23**2 + cross) / (1.0 + (r12 * r23) ** 2 + cross)


@pytest.mark.parametrize("d, n2, substrate, n1", [
    (500.0, 1.4, 1.5, 1.0),
    (350.0, 1.3, [1.3, 1.5, 1.7], 1.0),
    (400.0, 1.33, 1.0, 1.0),                        # a free film (soap bubble)
    (800.0, 1.2, 1.5, 1.45),                        # under a coat; film below the coat
    (300.0, 2.0, (np.array([0.143, 0.374, 1.442]), np.array([3.983, 2.385, 1.603])), 1.0),
])
def test_each_channel_is_the_airy_reflectance_at_its_wavelength(d, n2, substrate, n1):
    eta, k = substrate if isinstance(substrate, tuple) else (substrate, 0.0)
    expected = _expected(MU, d, n2, eta, k, n1)
    direct = ThinFilm(d, n2, substrate, n1, model=THREE, tabulated=False)
    np.testing.assert_allclose(direct(MU), expected, rtol=0, atol=EXACT)
    np.testing.assert_allclose(direct.spectral_rgb(MU), expected, rtol=0, atol=EXACT)
    tabulated = ThinFilm(d, n2, substrate, n1, model=THREE)
    assert tabulated.table() is not None
    np.testing.assert_allclose(tabulated(MU), expected, rtol=0, atol=TABLE_ERROR)
    np.testing.assert_allclose(tabulated.from_cos2(MU * MU), tabulated(MU), rtol=0, atol=0)


def test_over_f82_tint_sees_each_channel_index_at_its_wavelength():
    f0, tint = GOLD
    eta, k, _ = spectral.conductor_from_f82_tint(f0, tint)  # relative to the outside
    for n1 in (1.0, 1.5):
        expected = _expected(MU, 500.0, 1.5 * n1, eta * n1, k * n1, n1)
        film = ThinFilm.over_f82_tint(500.0, 1.5 * n1, f0, tint, n1, model=THREE,
                                      tabulated=False)
        np.testing.assert_allclose(film(MU), expected, rtol=0, atol=EXACT)
        tabulated = ThinFilm.over_f82_tint(500.0, 1.5 * n1, f0, tint, n1, model=THREE)
        np.testing.assert_allclose(tabulated(MU), expected, rtol=0, atol=TABLE_ERROR)
    # a perfect reflector channel (f0 = 1) stays 1
    mirror = ThinFilm.over_f82_tint(500.0, 1.5, [1.0, 0.5, 0.5], 1.0, model=THREE)
    np.testing.assert_array_equal(mirror(MU)[:, 0], 1.0)


def test_closed_forms_at_normal_incidence():
    n3 = 1.5
    # any film on a dielectric, at the three wavelengths
    for d, n2 in ((500.0, 1.4), (123.0, 2.2), (1000.0, 1.1)):
        film = ThinFilm(d, n2, n3, model=THREE, tabulated=False)
        np.testing.assert_allclose(film(1.0), _normal_incidence(RGB_NM, d, 1.0, n2, n3),
                                   rtol=0, atol=EXACT)
    # a quarter-wave film at 540 nm of index sqrt(n1 n3): an anti-reflection coating, green 0
    n2 = np.sqrt(n3)
    for tabulated in (False, True):
        film = ThinFilm(540.0 / (4.0 * n2), n2, n3, model=THREE, tabulated=tabulated)
        rgb = film(1.0)
        assert abs(rgb[1]) < (EXACT if not tabulated else TABLE_ERROR)
        assert rgb[0] > 1e-3 and rgb[2] > 1e-3
    # a quarter wave of another index: ((n3 - n2^2) / (n3 + n2^2))^2
    film = ThinFilm(540.0 / (4.0 * 2.0), 2.0, n3, model=THREE, tabulated=False)
    assert film(1.0)[1] == pytest.approx(((n3 - 4.0) / (n3 + 4.0)) ** 2, abs=EXACT)
    # a half-wave film at 450 nm is absent in blue: the bare interface ((1 - n3) / (1 + n3))^2
    film = ThinFilm(450.0 / (2.0 * 1.38), 1.38, n3, model=THREE, tabulated=False)
    assert film(1.0)[2] == pytest.approx(((1.0 - n3) / (1.0 + n3)) ** 2, abs=EXACT)


def test_thickness_zero_is_the_film_free_fresnel():
    film = ThinFilm(0.0, 1.33, [1.3, 1.5, 1.7], model=THREE)
    expected = np.stack([F.dielectric(MU, eta) for eta in (1.3, 1.5, 1.7)], axis=-1)
    np.testing.assert_allclose(film(MU), expected, rtol=0, atol=EXACT)
    f0, tint = GOLD
    eta, k, _ = spectral.conductor_from_f82_tint(f0, tint)
    metal = ThinFilm.over_f82_tint(0.0, 1.5, f0, tint, model=THREE)
    np.testing.assert_allclose(metal(MU), F.conductor(MU, eta, k), rtol=0, atol=EXACT)
    np.testing.assert_allclose(metal(1.0), f0, rtol=0, atol=1e-9)  # F82-tint's f0
    # the two models agree where the film vanishes
    np.testing.assert_allclose(film(MU), ThinFilm(0.0, 1.33, [1.3, 1.5, 1.7])(MU), rtol=0,
                               atol=EXACT)


def test_channel_wavelengths_and_textures():
    lam = np.array([700.0, 550.0, 400.0])
    film = ThinFilm(420.0, 1.45, 1.6, model=THREE, channel_wavelengths_nm=lam)
    np.testing.assert_allclose(film(MU), _expected(MU, 420.0, 1.45, 1.6, lam=lam), rtol=0,
                               atol=TABLE_ERROR)
    np.testing.assert_array_equal(film.channel_wavelengths_nm, lam)
    # a grey substrate with the wavelengths reversed reverses the channels
    flipped = ThinFilm(420.0, 1.45, 1.6, model=THREE, channel_wavelengths_nm=lam[::-1],
                       tabulated=False)
    np.testing.assert_allclose(flipped(MU)[:, ::-1], _expected(MU, 420.0, 1.45, 1.6, lam=lam),
                               rtol=0, atol=EXACT)
    # a texture of films: one Airy reflectance per texel and channel
    d = np.linspace(0.0, 1000.0, MU.size)
    texture = ThinFilm(d, 1.4, 1.5, model=THREE)
    assert texture.param_shape == MU.shape and texture.table() is None
    np.testing.assert_allclose(texture(MU), _expected(MU, d, 1.4, 1.5), rtol=0, atol=EXACT)
    with ab.config.options(chunk_size=64):  # the chunks do not matter
        np.testing.assert_array_equal(texture(MU), texture(MU.copy()))
    assert "three_wavelengths" in repr(texture) and "model" not in repr(ThinFilm(1, 1.4, 1.5))


def test_as_the_fresnel_factor_of_a_lobe():
    film = ThinFilm.over_f82_tint(500.0, 1.5, *GOLD, model=THREE)
    wo = np.array([[0.3, 0.1, 0.9], [0.0, 0.6, 0.5], [-0.2, 0.0, 0.7]])
    wi = np.array([[-0.2, 0.0, 0.8], [0.1, -0.4, 0.6], [0.5, 0.3, 0.4]])
    wo, wi = (w / np.linalg.norm(w, axis=-1, keepdims=True) for w in (wo, wi))
    h = wo + wi
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    ratio = ab.lobes.Conductor(0.3, fresnel=film).eval(wo, wi) / ab.lobes.Conductor(0.3).eval(
        wo, wi)
    np.testing.assert_allclose(ratio, film(np.sum(wo * h, axis=-1)), rtol=1e-12)


def test_default_is_the_spectral_model():
    for make in (lambda **kw: ThinFilm(500.0, 1.4, 1.5, **kw),
                 lambda **kw: ThinFilm.over_f82_tint(500.0, 1.5, *GOLD, **kw)):
        default, spectral_model = make(), make(model="spectral")
        assert default.model == "spectral"
        np.testing.assert_array_equal(default(MU), spectral_model(MU))
        # the channel wavelengths belong to the other model only
        np.testing.assert_array_equal(
            default(MU), make(model="spectral", channel_wavelengths_nm=(600, 500, 400))(MU))
        np.testing.assert_array_equal(default.spectral_rgb(MU[:20]),
                                      make(tabulated=False)(MU[:20]))
        # a 500 nm film is coloured differently by the two models
        assert np.max(np.abs(default(MU) - make(model=THREE)(MU))) > 1e-3


@pytest.mark.parametrize("kwargs, pattern", [
    ({"model": "rgb"}, r"model = 'rgb' is not one of \('spectral', 'three_wavelengths'\)"),
    ({"model": None}, r"model = None is not one of"),
    ({"model": THREE, "channel_wavelengths_nm": (620.0, 540.0)},
     r"channel_wavelengths_nm = \(620.0, 540.0\) has shape \(2,\): allowed three"),
    ({"model": THREE, "channel_wavelengths_nm": 540.0},
     r"channel_wavelengths_nm = 540.0 has shape \(\): allowed three"),
    ({"model": THREE, "channel_wavelengths_nm": (620.0, -540.0, 450.0)},
     r"channel_wavelengths_nm = -540.0 is outside the allowed range \(0.0, inf\)"),
    ({"model": THREE, "channel_wavelengths_nm": (620.0, 0.0, 450.0)},
     r"channel_wavelengths_nm = 0.0 is outside the allowed range"),
    ({"model": THREE, "channel_wavelengths_nm": (620.0, np.nan, 450.0)},
     r"channel_wavelengths_nm = nan is outside the allowed range"),
    ({"model": THREE, "channel_wavelengths_nm": "red"},
     r"channel_wavelengths_nm = 'red' is not a real number"),
    ({"channel_wavelengths_nm": (620.0, 540.0, 450.0, 400.0)},
     r"channel_wavelengths_nm = .* has shape \(4,\)"),
])
def test_bad_arguments_name_parameter_value_and_allowed(kwargs, pattern):
    with pytest.raises(ValueError, match=pattern):
        ThinFilm(500.0, 1.4, 1.5, **kwargs)
    with pytest.raises(ValueError, match=pattern):
        ThinFilm.over_f82_tint(500.0, 1.5, *GOLD, **kwargs)
