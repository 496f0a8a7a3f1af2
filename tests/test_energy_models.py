"""The table-based models: ASM energy-conserving diffuse [Kutz2021, §1.1 eq. 1] and
Kulla–Conty multiple scattering for conductors and dielectrics [Kutz2021, §1.2].

Acceptance (the white furnace of [Kutz2021, Fig. 2], as numbers): every albedo below is
integrated from ``eval`` by direction-space cubature, independently of the tables' own
consistency, and must be 1 within the stated tolerance.
"""

import itertools
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import adobe_bsdf as ab
from adobe_bsdf.lobes import ConductorMS, DielectricMS
from adobe_bsdf.materials.asm import ASMDiffuse, asm_dielectric_base
from adobe_bsdf.validation import checks
from adobe_bsdf.validation import strategies as vs
from adobe_bsdf.validation.chi2 import chi2_test, suggest_grid
from tests.tolerances import (
    CHI2_ALPHA,
    FURNACE_TABLE,
    FURNACE_TABLE_DIELECTRIC,
    RECIPROCITY_TABLE,
    WEIGHT,
)

SETTINGS = settings(max_examples=int(os.environ.get("HYPOTHESIS_EXAMPLES", 200)), deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])
ROUGHNESS = [0.05, 0.3, 0.7, 1.0]
IORS = [1.1, 1.5, 2.5]
COSINES = [1.0, 0.5, 0.1, 0.02]


def direction(cos_theta, phi=0.4):
    s = np.sqrt(1.0 - cos_theta**2)
    return np.array([s * np.cos(phi), s * np.sin(phi), cos_theta])


def quadrature_albedo(lobe, directions, tol=1e-5):
    """Direction-space cubature of ``eval``, one direction per call (a batch shares one grid,
    which is slower for directions with different edges); tol far below the furnace bound."""
    return np.stack([lobe.albedo(w, tol=tol) for w in directions])


# -- acceptance 1: white furnace -------------------------------------------------------------
@pytest.mark.parametrize(("roughness", "ior"), list(itertools.product(ROUGHNESS, IORS)))
def test_asm_diffuse_plus_specular_white_furnace(roughness, ior):
    lobe = asm_dielectric_base(1.0, roughness, ior)
    wo = np.stack([direction(c) for c in COSINES])
    np.testing.assert_allclose(quadrature_albedo(lobe, wo), 1.0, atol=FURNACE_TABLE)


@pytest.mark.parametrize("roughness", [0.05, 0.1, 0.3, 0.5, 0.7, 1.0])
def test_conductor_kulla_conty_white_furnace(roughness):
    lobe = ConductorMS(roughness**2)
    wo = np.stack([direction(c) for c in COSINES])
    np.testing.assert_allclose(quadrature_albedo(lobe, wo), 1.0, atol=FURNACE_TABLE)


@pytest.mark.parametrize(("roughness", "eta"), list(itertools.product([0.1, 0.3, 0.7, 1.0],
                                                                 [1.5, 1 / 1.5, 1.1, 2.5])))
def test_dielectric_kulla_conty_white_furnace_both_sides(roughness, eta):
    lobe = DielectricMS(eta, roughness**2)
    wo = np.stack([s * direction(c) for c in (1.0, 0.5, 0.1) for s in (1, -1)])
    np.testing.assert_allclose(quadrature_albedo(lobe, wo), 1.0, atol=FURNACE_TABLE_DIELECTRIC)


def test_coloured_metal_multiple_scattering_is_scaled_by_base_colour_squared():
    base = np.array([0.9, 0.6, 0.3])
    ms = ab.lobes.ConductorMultipleScattering(0.5, base_color=base)
    white = ab.lobes.ConductorMultipleScattering(0.5)
    wo, wi = direction(0.6), direction(0.3, 2.0)
    np.testing.assert_allclose(ms.eval(wo, wi), white.eval(wo, wi) * base**2, rtol=1e-14)


# -- acceptance 2: reciprocity and separability ------------------------------------------------
@SETTINGS
@given(roughness=st.floats(0.0, 1.0), ior=st.floats(1.0, 4.0), albedo=st.floats(0.0, 1.0),
       pair=vs.direction_pairs("reflection"))
def test_asm_base_reciprocity(roughness, ior, albedo, pair):
    lobe = asm_dielectric_base(albedo, roughness, ior)
    result = checks.reciprocity_error(lobe, *pair, rtol=RECIPROCITY_TABLE)
    assert result.passed, result


@SETTINGS
@given(alpha=vs.alpha_pairs(), pair=vs.direction_pairs("reflection"))
def test_conductor_kulla_conty_reciprocity(alpha, pair):
    lobe = ConductorMS(*alpha, base_color=(1.0, 0.7, 0.3))
    result = checks.reciprocity_error(lobe, *pair, rtol=RECIPROCITY_TABLE)
    assert result.passed, result


@SETTINGS
@given(eta=st.floats(1 / 3, 3.0), alpha=vs.alpha_pairs(), pair=vs.direction_pairs("any"))
def test_dielectric_kulla_conty_generalized_reciprocity(eta, alpha, pair):
    lobe = DielectricMS(eta, *alpha)
    result = checks.reciprocity_error(lobe, *pair, rtol=RECIPROCITY_TABLE)
    assert result.passed, result


def test_asm_diffuse_is_separable():
    """D(a, b) D(c, d) = D(a, d) D(c, b): D = rho X(wi) X(wo) [Kutz2021, §1.1]."""
    rng = np.random.default_rng(3)
    w = rng.normal(size=(4, 2000, 3))
    w[..., 2] = np.abs(w[..., 2])
    a, b, c, d = w / np.linalg.norm(w, axis=-1, keepdims=True)
    lobe = ASMDiffuse(0.8, 0.4, 1.6)
    lhs = lobe.eval(a, b) * lobe.eval(c, d)
    rhs = lobe.eval(a, d) * lobe.eval(c, b)
    np.testing.assert_allclose(lhs, rhs, rtol=1e-12)


def test_asm_diffuse_is_lambert_where_the_specular_vanishes():
    wo, wi = direction(0.7), direction(0.2, 1.0)
    np.testing.assert_allclose(ASMDiffuse(0.6, 0.5, 1.0).eval(wo, wi), 0.6 / np.pi, rtol=1e-14)


# -- acceptance 4 (the model side): the table albedo is the quadrature albedo -------------------
@pytest.mark.parametrize("make", [lambda: ConductorMS(0.3, base_color=0.7),
                                  lambda: asm_dielectric_base(0.5, 0.4, 1.5),
                                  lambda: DielectricMS(1 / 1.4, 0.6),
                                  lambda: ab.lobes.Dielectric(1.4, 0.6)])
def test_table_albedo_matches_quadrature(make):
    lobe = make()
    wo = np.stack([s * direction(c) for c in (0.9, 0.4, 0.08) for s in (1, -1)])
    np.testing.assert_allclose(lobe.albedo(wo, "table"), quadrature_albedo(lobe, wo),
                               atol=FURNACE_TABLE)


# -- acceptance 5: sampling, and finite values at the extremes -----------------------------------
CHI2_CASES = [
    ("ConductorMS", lambda: ConductorMS(0.5, 0.2, base_color=(0.9, 0.6, 0.3)), 0.7),
    ("ConductorMS", lambda: ConductorMS(0.02), 0.3),
    ("ASM base", lambda: asm_dielectric_base(0.7, 0.5, 1.5), 0.5),
    ("ASM base", lambda: asm_dielectric_base(0.9, 0.2, 2.5), 0.1),
    ("ASMDiffuse", lambda: ASMDiffuse(1.0, 0.3, 1.5), 0.6),
    ("DielectricMS", lambda: DielectricMS(1.5, 0.3), 0.8),
    ("DielectricMS", lambda: DielectricMS(1.5, 0.3), -0.4),
    ("DielectricMS", lambda: DielectricMS(1 / 1.33, 0.7), 0.2),
]


@pytest.mark.parametrize(("name", "make", "cos_theta"), CHI2_CASES,
                         ids=[f"{c[0]}-{i}" for i, c in enumerate(CHI2_CASES)])
def test_chi2(name, make, cos_theta):
    lobe = make()
    wo = direction(cos_theta)
    narrow = name == "ConductorMS" and cos_theta == 0.3
    grid = suggest_grid(0.04, np.array([-wo[0], -wo[1], wo[2]])) if narrow else {}
    seed = [c[0] for c in CHI2_CASES].index(name) + 100 * int(abs(cos_theta) * 10)
    result = chi2_test(lobe, wo, n_samples=500_000, seed=seed, alpha=CHI2_ALPHA,
                       n_tests=len(CHI2_CASES), **grid)
    assert result.passed, str(result)


@pytest.mark.parametrize("make", [lambda: ConductorMS(0.4, base_color=0.8),
                                  lambda: asm_dielectric_base(0.6, 0.4, 1.5),
                                  lambda: DielectricMS(1.33, 0.5)])
def test_weight_is_f_cos_over_pdf(make):
    result = checks.weight_consistency(make(), direction(0.6), n_samples=20_000, seed=1,
                                       rtol=WEIGHT)
    assert result.passed, result


EXTREMES = [
    lambda: ConductorMS(0.0), lambda: ConductorMS(2.0), lambda: ConductorMS(1.0, 0.0),
    lambda: asm_dielectric_base(1.0, 0.0, 1.5), lambda: asm_dielectric_base(1.0, 1.0, 4.0),
    lambda: asm_dielectric_base(1.0, 0.5, 1.0), lambda: asm_dielectric_base(1.0, 0.5, 1 + 1e-9),
    lambda: DielectricMS(1.0, 0.5), lambda: DielectricMS(1 + 1e-9, 0.5),
    lambda: DielectricMS(1 / 3, 2.0), lambda: DielectricMS(1.5, 0.0),
    lambda: DielectricMS(3.0, 1e-9),
]


@pytest.mark.parametrize("make", EXTREMES)
def test_finite_and_non_negative_at_the_extremes(make):
    lobe = make()
    rng = np.random.default_rng(5)
    w = rng.normal(size=(2, 4000, 3))
    w[:, :50, 2] = 0.0  # exactly grazing
    w[:, 50:100, 2] = 1e-9
    wo, wi = w / np.linalg.norm(w, axis=-1, keepdims=True)
    f = lobe.eval(wo, wi)
    pdf = lobe.pdf(wo, wi)
    s = lobe.sample(wo, rng.random((4000, 3)))
    for x in (f, pdf, s.weight, s.pdf):
        assert np.all(np.isfinite(x)) and np.all(x >= 0.0)
    for method in ("table",):
        assert np.all(np.isfinite(lobe.albedo(wo, method)))


def test_parameters_out_of_the_tables_raise_naming_them():
    with pytest.raises(ValueError, match="alpha"):
        ConductorMS(2.5)
    with pytest.raises(ValueError, match="eta"):
        DielectricMS(5.0, 0.3)
    with pytest.raises(ValueError, match="ior"):
        ASMDiffuse(0.5, 0.3, 0.9)
    with pytest.raises(ValueError, match="roughness"):
        asm_dielectric_base(0.5, 1.2, 1.5)


def test_dielectric_kulla_conty_reciprocal_where_the_dense_side_loses_nothing():
    """Near-smooth alpha: the dense side's loss 1 - E_avg,D is below what 1 / loss resolves,
    the transmitted shares are capped, and L -> D must still be D -> L / eta^2 (found by
    the property test above: grazing wo and wi on opposite sides)."""
    from adobe_bsdf.validation.strategies import _direction

    lobe = DielectricMS(2.0, 4.869675251658631e-05)
    wo, wi = _direction(1e-08, 0.0, 1.0), np.array([1.0, 0.0, -1e-08])
    forward, backward = lobe.eval(wo, wi), lobe.eval(wi, wo)
    assert np.all(backward > 0.0)
    np.testing.assert_allclose(forward, backward / 4.0, rtol=1e-12)
    result = checks.reciprocity_error(lobe, wo, wi, rtol=RECIPROCITY_TABLE)
    assert result.passed, result


def test_dielectric_multiple_scattering_alone_is_a_colour_lobe():
    """The term on its own returns (..., 3) like every lobe (its coefficient is grey), so its
    quadrature albedo works and matches the table's 1 - E_s(mu_o) it restores."""
    from adobe_bsdf.lobes import DielectricMultipleScattering

    lobe = DielectricMultipleScattering(1.5, 0.3)
    wo = np.array([0.3, 0.0, np.sqrt(0.91)])
    wi = np.array([[-0.3, 0.1, np.sqrt(0.9)], [0.2, 0.1, -np.sqrt(0.95)]])
    assert lobe.eval(wo, wi[0]).shape == (3,) and lobe.eval(wo, wi).shape == (2, 3)
    np.testing.assert_allclose(lobe.albedo(wo, method="quadrature"),
                               lobe.albedo(wo, method="table"), atol=1e-6)
