"""``AdobeStandardMaterial``, its coat and ``layering.Layer`` [Kutz2021, §1, §6, §7]."""


import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import adobe_bsdf as ab
from adobe_bsdf.composition import Layer
from adobe_bsdf.materials import AdobeStandardMaterial as ASM
from adobe_bsdf.materials.asm import coat_transmittance
from adobe_bsdf.validation import checks
from adobe_bsdf.validation.chi2 import chi2_test
from tests.sampling_checks import assert_no_energy_gain
from tests.sweeps import sweep
from tests.tolerances import (
    CHI2_ALPHA,
    EXACT,
    FURNACE_TABLE,
    RECIPROCITY_TABLE,
    SUBNORMAL,
    WEIGHT,
)

GOLD = ab.materials.presets.metals["Au"]
COSINES = (1.0, 0.5, 0.1, 0.02)


def _wo(c, phi=0.4):
    s = np.sqrt(1.0 - c * c)
    return np.array([s * np.cos(phi), s * np.sin(phi), c])


WO = np.stack([_wo(c) for c in COSINES])


def _pairs(n=4000, seed=1):
    return ab.frame.normalize(np.random.default_rng(seed).normal(size=(2, n, 3)))


# -- acceptance 1: Fig. 2 ----------------------------------------------------------------------
@pytest.mark.parametrize("roughness", [0.05, 0.3, 0.7, 1.0])
@pytest.mark.parametrize("ior", [1.1, 1.5, 2.5])
def test_white_diffuse_and_specular_disappear_in_the_furnace(roughness, ior):
    """A white ASM dielectric (no coat, no sheen) reflects everything: the quadrature of its
    eval is 1 within the tables' interpolation error at every angle (Fig. 2)."""
    material = ASM(base_color=1.0, roughness=roughness, ior=ior)
    np.testing.assert_allclose(material.albedo(WO, tol=1e-7), 1.0, atol=FURNACE_TABLE)


@pytest.mark.parametrize("roughness", [0.05, 0.3, 0.7, 1.0])
def test_white_metal_disappears_in_the_furnace(roughness):
    material = ASM(metallic=1.0, base_color=1.0, specular_edge_color=1.0, roughness=roughness)
    np.testing.assert_allclose(material.albedo(WO, tol=1e-7), 1.0, atol=FURNACE_TABLE)


def test_a_white_coat_over_a_white_base_keeps_the_energy_and_a_coloured_one_absorbs():
    white = ASM(base_color=1.0, roughness=0.4, coat_opacity=1.0, coat_roughness=0.2)
    np.testing.assert_allclose(white.albedo(WO, tol=1e-7), 1.0, atol=FURNACE_TABLE)
    tinted = ASM(base_color=1.0, roughness=0.4, coat_opacity=1.0, coat_roughness=0.2,
                 coat_color=(0.9, 0.6, 0.3))
    E = tinted.albedo(WO, tol=1e-7)
    assert np.all(E <= 1.0 + FURNACE_TABLE)
    assert np.all(E[:, 2] < E[:, 1]) and np.all(E[:, 1] < E[:, 0])


# -- acceptance 2 and 5: energy and finite values over the parameter range ---------------------
_unit = st.floats(0.0, 1.0)
_colour = st.tuples(_unit, _unit, _unit)


@st.composite
def asm_parameters(draw, with_sheen=True):
    """Any parameter set with colours <= 1; weights, roughness and bounds drawn at their ends
    often (hypothesis); coat ior below and above the base's."""
    edge = st.sampled_from([0.0, 1.0]) | _unit
    p = {"base_color": draw(_colour), "roughness": draw(edge), "metallic": draw(edge),
         "specular_edge_color": draw(_colour), "ior": draw(st.floats(1.0, 3.0)),
         "anisotropy_level": draw(edge), "anisotropy_angle": draw(_unit),
         "dispersion": draw(st.sampled_from([0.0, 1.0]) | st.floats(0.0, 3.0)),
         "translucency": draw(edge), "coat_opacity": draw(edge), "coat_color": draw(_colour),
         "coat_roughness": draw(edge), "coat_ior": draw(st.floats(1.0, 3.0)),
         "coat_anisotropy_level": draw(edge), "coat_anisotropy_angle": draw(_unit)}
    if with_sheen:
        p.update(sheen_opacity=draw(edge), sheen_color=draw(_colour), sheen_roughness=draw(edge))
    return p


@settings(max_examples=12, deadline=None)
@given(p=asm_parameters())
def test_albedo_never_exceeds_one(p):
    """Acceptance 2: for colours <= 1, the material's albedo (quadrature of eval plus delta
    branches, energy convention) is <= 1 + 1e-3 above and below the surface."""
    material = ASM(**p)
    wo = np.concatenate([WO, -WO[:2]])
    assert_no_energy_gain(material, wo, 1.0 + FURNACE_TABLE, p, mc_samples=100_000)


def _outputs_finite(p):
    """Acceptance 5: no NaN or Inf anywhere in the parameter range, grazing angles included."""
    material = ASM(**p)
    wo, wi = _pairs(300)
    wo[:20, 2] = 1e-9
    wo = ab.frame.normalize(wo)
    u = np.random.default_rng(2).random(wo.shape)
    s = material.sample(wo, u)
    values = [*material.eval_pdf(wo, wi), s.weight, s.pdf, s.wi, material.emission(wo)]
    if _tables_cover(p) and "metal" not in material.lobes:  # tables: see docs/asm.md
        values.append(material.albedo(wo[:5], method="table"))
    for v in values:
        assert np.all(np.isfinite(v)), p


test_outputs_are_finite = sweep(_outputs_finite, 10, p=asm_parameters())
test_outputs_are_finite_exhaustively = sweep(_outputs_finite, 60, p=asm_parameters(), slow=True)


def _tables_cover(p):
    """The dispersive channel indices stay inside the dielectric tables (index <= 3)."""
    n = ab.dispersion.cauchy_iors(p["ior"], p["dispersion"])
    return bool(np.all(n <= ab.tables.ETA_MAX))


# -- acceptance 3: sampling ---------------------------------------------------------------------
MATERIALS = {
    "metal": dict(GOLD, roughness=0.3),
    "dielectric + diffuse": dict(base_color=(0.8, 0.2, 0.1), roughness=0.4),
    "anisotropic half metal": dict(base_color=(0.3, 0.5, 0.7), metallic=0.5, roughness=0.3,
                                   anisotropy_level=0.8, anisotropy_angle=0.2),
    "dispersive glass": dict(translucency=1.0, roughness=0.2, dispersion=1.0),
    "coat": dict(base_color=(0.8, 0.1, 0.1), roughness=0.5, coat_opacity=0.8,
                 coat_roughness=0.1, coat_color=(0.9, 0.7, 0.4), coat_anisotropy_level=0.5),
    "coat over glass, coat ior above": dict(translucency=0.6, base_color=0.5, roughness=0.3,
                                            coat_opacity=1.0, coat_ior=1.8, ior=1.4,
                                            coat_color=(0.8, 0.9, 1.0)),
}
MATERIALS["sheen"] = dict(base_color=(0.2, 0.3, 0.6), roughness=0.6, sheen_opacity=1.0,
                          sheen_color=(1.0, 0.8, 0.6), sheen_roughness=0.3)
MATERIALS["everything"] = dict(base_color=(0.6, 0.5, 0.4), roughness=0.35, metallic=0.3,
                               translucency=0.4, dispersion=0.5, anisotropy_level=0.4,
                               sheen_opacity=0.5, sheen_roughness=0.5, coat_opacity=0.5,
                               coat_color=(0.9, 0.9, 0.7), emissive_intensity=1.0)
CHI2_CASES = [(name, c) for name in MATERIALS for c in (0.8, 0.3, -0.6)
              if c > 0 or MATERIALS[name].get("translucency")]


@pytest.mark.parametrize(("name", "cos_theta"), CHI2_CASES)
def test_chi2(name, cos_theta):
    """sample against the mixture pdf of the whole material (p > 0.01 after Šidák)."""
    material = ASM(**MATERIALS[name])
    wo = _wo(cos_theta)
    result = chi2_test(material, wo, n_samples=300_000, alpha=CHI2_ALPHA,
                       n_tests=len(CHI2_CASES), seed=CHI2_CASES.index((name, cos_theta)))
    assert result.passed, str(result)
    weights = checks.weight_consistency(material, wo, n_samples=20_000, rtol=WEIGHT)
    assert weights.passed, weights


# -- acceptance 4: reciprocity, and the measured non-reciprocity of the layers -----------------
@settings(max_examples=40, deadline=None)
@given(p=asm_parameters(with_sheen=False))
@example(p={"base_color": 0.0, "roughness": 0.0, "ior": 3.0, "anisotropy_level": 1.0,
            "dispersion": 1.0, "translucency": 1.0})  # a channel beyond the energy tables
def test_reciprocity_without_the_layers(p):
    """Metal, diffuse, specular, transmission: reciprocal to 1e-10 (tables: their terms are
    symmetric products)."""
    p.update(coat_opacity=0.0)
    result = checks.reciprocity_error(ASM(**p), *_pairs(500), rtol=RECIPROCITY_TABLE,
                                      atol=SUBNORMAL)  # a weight of 2e-309 makes subnormals
    assert result.passed, result


def test_layer_non_reciprocity_is_exactly_the_albedo_scaling_term():
    """f(wo, wi) - f(wi, wo) = c t(wo) t(wi) (E_top(wi) - E_top(wo)) f_base for reflection pairs:
    the only non-reciprocal term of the coat (its tint is symmetric)."""
    coat = ab.materials.asm.asm_coat(1.5, 0.3)
    base = ab.lobes.Lambert((0.9, 0.5, 0.2))
    tint = lambda w: coat_transmittance((0.7, 0.8, 0.9), 1.5, w)  # noqa: E731
    layer = Layer(coat, base, 0.7, tint)
    wo, wi = _pairs()
    up = (wo[:, 2] > 0) & (wi[:, 2] > 0)
    wo, wi = wo[up], wi[up]
    E = lambda w: coat.albedo(w, method="table")  # noqa: E731
    expected = 0.7 * tint(wo) * tint(wi) * (E(wi) - E(wo)) * base.eval(wo, wi)
    np.testing.assert_allclose(layer.eval(wo, wi) - layer.eval(wi, wo), expected, atol=1e-15)


# -- the coat ---------------------------------------------------------------------------------
def test_coat_tint_is_beer_law_through_the_refracted_path():
    color, eta = np.array([0.9, 0.5, 0.1]), 1.5
    normal = coat_transmittance(color, eta, np.array([0.0, 0.0, 1.0]))
    np.testing.assert_allclose(normal**2, color, rtol=EXACT)  # two-way = coat colour
    mu = np.linspace(0.0, 1.0, 11)
    w = np.stack([np.sqrt(1 - mu**2), np.zeros(11), mu], -1)
    t = coat_transmittance(color, eta, w)
    mu_t = np.sqrt(1 - (1 - mu**2) / eta**2)
    np.testing.assert_allclose(t, np.exp(np.log(color) / (2 * mu_t[:, None])), rtol=EXACT)
    assert np.all(np.diff(t, axis=0) >= 0)  # darker towards grazing
    np.testing.assert_allclose(coat_transmittance(color, eta, w, view_dependent=False),
                               np.broadcast_to(np.sqrt(color), (11, 3)), rtol=EXACT)
    assert np.all(np.isfinite(coat_transmittance((0.0, 0.5, 1.0), 1.0, w)))


def test_base_index_under_the_coat_is_inverted_below_one():
    """Fig. 17: ior 1.3 under a 1.6 coat is 1.3/1.6 < 1, used as 1.6/1.3."""
    np.testing.assert_allclose(ab.materials.asm.base_ior_under_coat(1.3, 1.6, 1.0), 1.6 / 1.3,
                               rtol=EXACT)
    np.testing.assert_allclose(ab.materials.asm.base_ior_under_coat(2.0, 1.6, 1.0), 2.0 / 1.6,
                               rtol=EXACT)
    np.testing.assert_allclose(ab.materials.asm.base_ior_under_coat(1.5, 1.6, 0.0), 1.5, rtol=EXACT)
    m = ASM(ior=1.3, coat_opacity=1.0, coat_ior=1.6)
    np.testing.assert_allclose(m.lobes["specular"].ior, 1.6 / 1.3, rtol=EXACT)


def test_anisotropic_coat_albedo_is_the_quadrature_of_its_visible_normals():
    """Under an anisotropic coat the layer needs the coat's true albedo (the isotropic table
    misses it by up to ~0.04): the 32 x 32 Gauss rule over visible normals against the
    direction-space cubature, within the 1e-3 the energy acceptance allows (the rule
    converges slowly at grazing angles, where the reflected direction's horizon crosses the
    square: 6.6e-4 at cos 0.1 here)."""
    coat = ab.materials.asm.asm_coat(1.6, 0.6, 1.0, 0.2)
    np.testing.assert_allclose(coat._top_albedo(WO[:3]), coat.albedo(WO[:3], tol=1e-8),
                               atol=FURNACE_TABLE)


def test_coat_reflection_albedo_table_matches_quadrature():
    for lobe in (ab.materials.asm.asm_coat(1.6, 0.3, 0.0, 0.1),
                 ab.lobes.DielectricReflection(1 / 1.5, 0.2)):
        np.testing.assert_allclose(lobe.albedo(WO[:3], method="table"),
                                   lobe.albedo(WO[:3], tol=1e-8), atol=2e-3)


# -- cost only what is used, textures, emission, medium, bad input ----------------------------
def test_zero_weight_lobes_are_not_built():
    assert set(ASM().lobes) == {"specular", "diffuse"}
    assert set(ASM(metallic=1.0).lobes) == {"metal"}
    assert set(ASM(translucency=1.0).lobes) == {"transmission"}
    assert "coat" in ASM(coat_opacity=np.array([0.0, 0.5])).lobes
    assert ASM().medium() is None and ASM(translucency=0.5).medium() is not None


def test_textures_evaluate_per_element():
    wo, wi = _pairs(3)
    wo[:, 2], wi[:, 2] = np.abs(wo[:, 2]), np.abs(wi[:, 2])
    p = dict(roughness=np.array([0.2, 0.5, 0.9]), metallic=np.array([0.0, 0.5, 1.0]),
             base_color=np.array([[0.9, 0.1, 0.1], [0.2, 0.8, 0.2], [0.5, 0.5, 0.5]]),
             coat_opacity=np.array([0.0, 1.0, 0.3]), coat_color=(0.8, 0.8, 0.6))
    f = ASM(**p).eval(wo, wi)
    for j in range(3):
        one = {k: (v[j] if isinstance(v, np.ndarray) else v) for k, v in p.items()}
        np.testing.assert_allclose(f[j], ASM(**one).eval(wo[j], wi[j]), rtol=1e-12, atol=1e-300)


def test_a_coated_material_runs_in_chunks_and_samples_by_groups():
    """The coat's transmittance declares its parameter shape, so a coated ASM (here under a
    sheen) has scalar parameters: its calls run in chunks (bounded memory, threads) and
    each layer samples group by group, the chosen lobe's f |cos| its sample's weight times
    pdf; the samples agree with eval and pdf at the sampled directions to rounding. A
    textured coat colour keeps the per-element path."""
    from adobe_bsdf.composition import _by_groups

    m = ASM(base_color=(0.6, 0.5, 0.4), roughness=0.35, metallic=0.3, coat_opacity=0.7,
            coat_color=(0.9, 0.8, 0.6), coat_roughness=0.3, sheen_opacity=0.5,
            sheen_roughness=0.4)
    wo, _ = _pairs(6000, seed=3)
    u = np.random.default_rng(4).random((6000, 3))
    coat_layer = m.bsdf.base
    assert m.bsdf._param_shape() == () and coat_layer._param_shape() == ()
    assert _by_groups((m.bsdf.top, m.bsdf.base), wo, u)
    s = m.sample(wo, u)
    ok = (s.pdf > 0.0) & ((s.flags & int(ab.Flags.DELTA)) == 0)
    assert np.count_nonzero(ok) > 2000  # (wo below the surface: no sample)
    f, pdf = m.eval_pdf(wo[ok], s.wi[ok])
    np.testing.assert_allclose(s.pdf[ok], pdf, rtol=1e-12)
    np.testing.assert_allclose(s.weight[ok], f * np.abs(s.wi[ok, 2:]) / pdf[:, None],
                               rtol=1e-12)
    textured = ASM(coat_opacity=1.0, coat_color=np.full((4, 3), 0.8))
    assert textured.bsdf._param_shape() == (4,)


def test_emission_passes_the_layers_once():
    up = _wo(0.6)
    m = ASM(emissive_color=(1.0, 0.5, 0.25), emissive_intensity=2.0)
    np.testing.assert_allclose(m.emission(up), [2.0, 1.0, 0.5], rtol=EXACT)
    np.testing.assert_array_equal(m.emission(-up), 0.0)
    coated = ASM(emissive_color=1.0, emissive_intensity=1.0, coat_opacity=1.0, coat_ior=1.5)
    E_coat = coated.lobes["coat"].albedo(up, method="table")
    np.testing.assert_allclose(coated.emission(up), 1.0 - E_coat, rtol=EXACT)


def test_bad_input_names_the_parameter():
    for kwargs, name in (({"roughness": 1.5}, "roughness"), ({"metallic": -0.1}, "metallic"),
                         ({"ior": 0.9}, "ior"), ({"coat_ior": 4.0}, "coat_ior"),
                         ({"base_color": (1.2, 0, 0)}, "base_color"),
                         ({"sheen_roughness": np.nan}, "sheen_roughness"),
                         ({"coat_colour": 1.0}, "coat_colour")):
        with pytest.raises(ValueError, match=name):
            ASM(**kwargs)
