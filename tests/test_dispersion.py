"""ASM dispersion [Kutz2021, §4]: eqs. 11-13, Table 2, Cauchy's equation per channel."""

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf import dispersion as D
from tests.tolerances import EXACT

#: [Kutz2021, Table 2], the "Dispersion" column as printed (4 decimals)
TABLE_2 = {"N-FK58": 0.2200, "N-BK7": 0.3117, "N-BAK4": 0.3573, "water": 0.3586,
           "diamond": 0.3617, "F2": 0.5499, "N-SF66": 0.9579}


@pytest.mark.parametrize("name", TABLE_2)
def test_table_2_reproduced_to_four_digits(name):
    preset = ab.materials.presets.dispersion[name]
    assert round(float(D.abbe_to_dispersion(preset["abbe"])), 4) == TABLE_2[name]


def test_eqs_12_and_13_are_inverse():
    v = np.array([20.0, 36.37, 90.9, 1e6])
    np.testing.assert_allclose(D.dispersion_to_abbe(D.abbe_to_dispersion(v)), v, rtol=EXACT)
    assert D.dispersion_to_abbe(0.0) == np.inf
    assert D.dispersion_to_abbe(5e-324) == np.inf  # overflows to the same limit, no warning
    assert D.dispersion_to_abbe(1.0) == 20.0  # Dispersion 1: the most dispersive real glass


@pytest.mark.parametrize("name", TABLE_2)
def test_cauchy_indices_have_the_materials_abbe_number(name):
    """At the Fraunhofer lines the Cauchy indices give back n_d and V_d (eq. 11)."""
    preset = ab.materials.presets.dispersion[name]
    lines = [D.FRAUNHOFER_NM[k] for k in ("d", "F", "C")]
    n_d, n_F, n_C = D.cauchy_iors(preset["ior"], D.abbe_to_dispersion(preset["abbe"]), lines)
    assert n_d == pytest.approx(preset["ior"], rel=EXACT)
    assert D.abbe_number(n_d, n_F, n_C) == pytest.approx(preset["abbe"], rel=1e-10)
    rgb = D.cauchy_iors(preset["ior"], D.abbe_to_dispersion(preset["abbe"]))
    assert rgb[0] < preset["ior"] < rgb[2] and rgb[0] < rgb[1] < rgb[2]  # blue bends most


def test_zero_dispersion_is_exactly_the_ior_and_textures_broadcast():
    np.testing.assert_array_equal(D.cauchy_iors(1.5, 0.0), [1.5, 1.5, 1.5])
    np.testing.assert_array_equal(D.cauchy_iors(1.0, 3.0), [1.0, 1.0, 1.0])
    n = D.cauchy_iors(np.array([1.3, 1.5, 2.4]), np.array([[0.0], [1.0]]))
    assert n.shape == (2, 3, 3) and np.all(np.isfinite(n))
    np.testing.assert_array_equal(n[0], np.repeat([[1.3], [1.5], [2.4]], 3, axis=1))
    # the spread grows linearly with the parameter [Kutz2021, §4], beyond 1 too
    spread = [np.ptp(D.cauchy_iors(1.5, d)) for d in (0.5, 1.0, 2.0)]
    np.testing.assert_allclose(spread, [spread[0], 2 * spread[0], 4 * spread[0]], rtol=EXACT)


def test_channel_wavelengths_are_the_dominant_wavelengths_of_the_srgb_primaries():
    colour = pytest.importorskip("colour")
    space = colour.RGB_COLOURSPACES["sRGB"]
    expected = [float(colour.dominant_wavelength(p, space.whitepoint)[0])
                for p in space.primaries]
    assert list(D.RGB_WAVELENGTHS_NM) == expected


@pytest.mark.parametrize(("call", "name"), [
    (lambda: D.abbe_to_dispersion(0.0), "abbe"),
    (lambda: D.dispersion_to_abbe(-0.1), "dispersion"),
    (lambda: D.cauchy_iors(0.0, 0.5), "ior"),
    (lambda: D.cauchy_iors(1.5, -1.0), "dispersion"),
    (lambda: D.cauchy_iors(1.5, 0.5, [500.0, -1.0]), "wavelengths_nm"),
    (lambda: D.abbe_number(1.5, 1.5, 1.6), "n_F"),
])
def test_bad_input_names_the_parameter(call, name):
    with pytest.raises(ValueError, match=name):
        call()
