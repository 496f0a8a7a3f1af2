"""The ASM metal lobe: F82-tint Fresnel, anisotropy, rotation, Kulla–Conty [Kutz2021, §1-3]."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import adobe_bsdf as ab
from adobe_bsdf.validation import checks
from adobe_bsdf.validation import strategies as vs
from adobe_bsdf.validation.chi2 import chi2_test
from tests.tolerances import CHI2_ALPHA, FURNACE_TABLE, RECIPROCITY_TABLE

GOLD = ab.materials.presets.metals["Au"]
F0, TINT = GOLD["base_color"], GOLD["specular_edge_color"]


def _wo(c, phi=0.4):
    s = np.sqrt(1 - c * c)
    return np.array([s * np.cos(phi), s * np.sin(phi), c])


def test_f82_tint_object_is_the_function():
    F = ab.fresnel.F82Tint(F0, TINT, 0.9, 4.0)
    mu = np.linspace(0.0, 1.0, 101)
    np.testing.assert_array_equal(F(mu), ab.fresnel.f82_tint(mu, F0, TINT, 0.9, 4.0))
    np.testing.assert_allclose(F.from_cos2(mu * mu), F(mu), rtol=1e-15)


@pytest.mark.parametrize("roughness", [0.05, 0.3, 0.7, 1.0])
def test_white_metal_furnace(roughness):
    """Base and edge colour 1 (F = 1): single + Kulla–Conty multiple scattering is 1 within
    the tables' interpolation error ([Kutz2021, Fig. 2]; acceptance 1e-3)."""
    lobe = ab.materials.asm.asm_metal(1.0, 1.0, roughness)
    for c in (1.0, 0.5, 0.1, 0.02):
        np.testing.assert_allclose(lobe.albedo(_wo(c), tol=1e-8), 1.0, atol=FURNACE_TABLE)


@settings(max_examples=60, deadline=None)
@given(r=st.floats(0.0, 1.0), a=st.floats(0.0, 1.0), angle=st.floats(0.0, 1.0),
       pair=vs.direction_pairs("reflection"))
def test_reciprocity(r, a, angle, pair):
    lobe = ab.materials.asm.asm_metal(F0, TINT, r, a, angle)
    result = checks.reciprocity_error(lobe, *pair, rtol=RECIPROCITY_TABLE)
    assert result.passed, result


CASES = [(0.4, 0.6, 0.15, 0.8), (0.3, 1.0, 0.25, 0.4), (0.7, 0.3, 0.0, 0.1)]


@pytest.mark.parametrize(("r", "a", "angle", "cos_theta"), CASES)
def test_chi2(r, a, angle, cos_theta):
    lobe = ab.materials.asm.asm_metal(F0, TINT, r, a, angle)
    result = chi2_test(lobe, _wo(cos_theta), n_samples=500_000, seed=CASES.index((r, a, angle,
                                                                                  cos_theta)),
                       alpha=CHI2_ALPHA, n_tests=len(CASES))
    assert result.passed, str(result)


def test_extremes_are_finite_and_bad_input_is_named():
    rng = np.random.default_rng(0)
    wo, wi = ab.frame.normalize(rng.normal(size=(2, 500, 3)))
    for r in (0.0, 1.0):
        for a in (0.0, 1.0):
            lobe = ab.materials.asm.asm_metal(0.0, 0.0, r, a, 1.0)
            s = lobe.sample(wo, rng.random((500, 3)))
            for v in (lobe.eval(wo, wi), lobe.pdf(wo, wi), s.weight, s.pdf):
                assert np.all(np.isfinite(v))
    for kwargs, name in (({"roughness": 1.5}, "roughness"),
                         ({"anisotropy_level": -1}, "anisotropy_level"),
                         ({"anisotropy_angle": 2.0}, "anisotropy_angle"),
                         ({"specular_edge_color": 1.1}, "specular_edge_color"),
                         ({"base_color": -0.1}, "base_color")):
        with pytest.raises(ValueError, match=name):
            ab.materials.asm.asm_metal(**{"base_color": 0.5, **kwargs})
