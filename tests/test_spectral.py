"""Spectral metals [Kutz2021, §2, Table 1]: measured n + i k to F0 and F82 tint."""

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf import spectral
from tests.tolerances import EXACT

#: Table 1 metals and the shipped data set that reproduces them. [Werner2009] give n, k
#: at 9 wavelengths (354-827 nm), linearly interpolated: the RGB integrals then carry an
#: interpolation error of several 1e-3, the size of the differences measured here (max 6.2e-3
#: for F0, 2.0e-3 for the tint, docs/asm_measured.md)
REPRODUCED = {"Fe": "Fe-Werner2009", "Pt": "Pt", "Zn": "Zn"}
TABLE_1_TOL = 0.01


@pytest.mark.parametrize("metal", REPRODUCED)
def test_table_1_reproduced_from_measured_spectra(metal):
    fit = spectral.fit_f82_tint(*spectral.metal_ior(REPRODUCED[metal]))
    table = ab.materials.presets.metals[metal]
    np.testing.assert_allclose(fit.f0, table["base_color"], atol=TABLE_1_TOL)
    np.testing.assert_allclose(fit.tint, table["specular_edge_color"], atol=TABLE_1_TOL)


def test_white_spectrum_is_white_and_the_colour_is_linear():
    lam = np.linspace(370.0, 790.0, 43)
    for illuminant in ("D65", "E", "A"):
        np.testing.assert_allclose(spectral.reflectance_to_rgb(lam, np.ones(43), illuminant),
                                   [1.0, 1.0, 1.0], rtol=EXACT)
    rng = np.random.default_rng(0)
    a, b = rng.random((2, 43))
    np.testing.assert_allclose(spectral.reflectance_to_rgb(lam, 0.3 * a + 0.5 * b),
                               0.3 * spectral.reflectance_to_rgb(lam, a)
                               + 0.5 * spectral.reflectance_to_rgb(lam, b), rtol=EXACT)


def test_flat_spectrum_fit_is_the_exact_fresnel():
    """A wavelength-independent n + i k: F0 and h are the exact Fresnel values, the tint is
    h / Schlick(F0, 1/7) (eq. 6), and the F82-tint curve meets the exact one at cos = 1 and
    cos = 1/7."""
    lam = np.array([370.0, 500.0, 790.0])
    n, k = np.full(3, 0.8), np.full(3, 3.0)
    fit = spectral.fit_f82_tint(lam, n, k)
    F = ab.fresnel.conductor
    np.testing.assert_allclose(fit.f0, F(1.0, 0.8, 3.0), rtol=1e-12)
    h = F(1 / 7, 0.8, 3.0)
    np.testing.assert_allclose(fit.tint, h / ab.fresnel.schlick(1 / 7, fit.f0), rtol=1e-12)
    np.testing.assert_allclose(ab.fresnel.f82_tint(1 / 7, fit.f0, fit.tint), h, rtol=1e-12)
    assert np.all(fit.max_error < 0.05) and np.all(fit.rms_error <= fit.max_error)


@pytest.mark.parametrize("name", spectral.METALS)
def test_every_shipped_metal_fits_within_its_range(name):
    fit = spectral.fit_f82_tint(*spectral.metal_ior(name))
    for value in (fit.f0, fit.tint, fit.max_error):
        assert value.shape == (3,) and np.all(np.isfinite(value))
    assert np.all((fit.f0 >= 0) & (fit.f0 <= 1) & (fit.tint >= 0) & (fit.tint <= 1))
    assert np.all(fit.max_error < 0.05)  # the F82-tint curve follows the exact colour


def test_bad_input():
    lam, n, k = spectral.metal_ior("Au")
    with pytest.raises(ValueError, match="name"):
        spectral.metal_ior("Unobtainium")
    with pytest.raises(ValueError, match="illuminant"):
        spectral.fit_f82_tint(lam, n, k, illuminant="D99")
    with pytest.raises(ValueError, match="wavelengths_nm"):
        spectral.reflectance_to_rgb(lam[5:], n[5:])  # does not cover 380 nm
    with pytest.raises(ValueError, match="k"):
        spectral.fit_f82_tint(lam, n, -k)


def test_conductor_from_f82_tint_passes_through_both_points():
    """For every Table 1 channel with F0 < 1: the effective n + i k reflects F0 at normal
    incidence and tint Schlick(F0, 1/7) at cos = 1/7 (to rounding); F0 = 1 is the mirror."""
    metals = ab.materials.presets.metals
    f0 = np.array([m["base_color"] for m in metals.values()])
    tint = np.array([m["specular_edge_color"] for m in metals.values()])
    eta, k, residual = spectral.conductor_from_f82_tint(f0, tint)
    finite = f0 < 1.0
    ones = np.ones(len(f0))
    np.testing.assert_allclose(ab.fresnel.conductor(ones, np.where(finite, eta, 1.0),
                                                    np.where(finite, k, 0.0))[finite],
                               f0[finite], atol=1e-12)
    assert np.all(np.abs(residual[finite]) < 1e-12)
    assert np.all(np.isinf(eta[~finite])) and np.all(residual[~finite] >= 0)
    h = tint * ab.fresnel.schlick(1 / 7, f0)
    np.testing.assert_allclose(ab.fresnel.conductor(ones / 7, np.where(finite, eta, 1.0),
                                                    np.where(finite, k, 0.0))[finite],
                               h[finite], atol=1e-12)
