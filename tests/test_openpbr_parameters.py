"""OpenPBR Surface's inputs: the spec against the v1.1.1 parameter reference, the docs table
against the spec, the draft's inputs onto the released ones, the v1.1.1 mappings."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy import integrate

from adobe_bsdf import fresnel
from adobe_bsdf.materials import MATERIALS
from adobe_bsdf.materials.openpbr import (
    DEV_1_2,
    DRAFT_PARAMETERS,
    PARAMETERS,
    PLANNED,
    STATUS,
    OpenPBRSurface,
    draft,
    mapping,
)
from tests.test_parameter_spec import _tables_script
from tests.tolerances import EXACT, QUADRATURE

ROOT = Path(__file__).resolve().parents[1]
INF = math.inf
N, T = (0.0, 0.0, 1.0), (1.0, 0.0, 0.0)

#: OpenPBR Surface v1.1.1's parameter reference, typed from the specification's table
#: (name: default, hard range, lower bound excluded); the MaterialX nodedef has the same 41
V111 = {
    "base_weight": (1, (0, 1), False), "base_color": ((0.8,) * 3, (0, 1), False),
    "base_diffuse_roughness": (0, (0, 1), False), "base_metalness": (0, (0, 1), False),
    "specular_weight": (1, (0, INF), False), "specular_color": ((1,) * 3, (0, 1), False),
    "specular_roughness": (0.3, (0, 1), False),
    "specular_roughness_anisotropy": (0, (0, 1), False),
    "specular_ior": (1.5, (0, INF), True), "transmission_weight": (0, (0, 1), False),
    "transmission_color": ((1,) * 3, (0, 1), False), "transmission_depth": (0, (0, INF), False),
    "transmission_scatter": ((0,) * 3, (0, 1), False),
    "transmission_scatter_anisotropy": (0, (-1, 1), False),
    "transmission_dispersion_scale": (0, (0, 1), False),
    "transmission_dispersion_abbe_number": (20, (0, INF), True),
    "subsurface_weight": (0, (0, 1), False), "subsurface_color": ((0.8,) * 3, (0, 1), False),
    "subsurface_radius": (1, (0, INF), False),
    "subsurface_radius_scale": ((1.0, 0.5, 0.25), (0, 1), False),
    "subsurface_scatter_anisotropy": (0, (-1, 1), False),
    "coat_weight": (0, (0, 1), False), "coat_color": ((1,) * 3, (0, 1), False),
    "coat_roughness": (0, (0, 1), False), "coat_roughness_anisotropy": (0, (0, 1), False),
    "coat_ior": (1.6, (0, INF), True), "coat_darkening": (1, (0, 1), False),
    "fuzz_weight": (0, (0, 1), False), "fuzz_color": ((1,) * 3, (0, 1), False),
    "fuzz_roughness": (0.5, (0, 1), False), "emission_luminance": (0, (0, INF), False),
    "emission_color": ((1,) * 3, (0, INF), False), "thin_film_weight": (0, (0, 1), False),
    "thin_film_thickness": (0.5, (0, INF), False), "thin_film_ior": (1.4, (0, INF), True),
    "geometry_opacity": (1, (0, 1), False), "geometry_thin_walled": (False, None, False),
    "geometry_normal": (N, None, False), "geometry_tangent": (T, None, False),
    "geometry_coat_normal": (N, None, False), "geometry_coat_tangent": (T, None, False),
}


def test_spec_has_the_41_released_inputs_with_their_defaults_and_ranges():
    released = [p for p in PARAMETERS if STATUS[p.name][0] != "dev_1.2"]
    assert len(V111) == 41 and [p.name for p in released] == list(V111)
    for p in released:
        default, hard, lo_open = V111[p.name]
        if isinstance(default, tuple):
            np.testing.assert_array_equal(np.broadcast_to(p.default, 3), default, err_msg=p.name)
        else:
            assert p.default == default, p.name
        assert p.hard == (None if hard is None else tuple(float(v) for v in hard)), p.name
        assert p.lo_open == lo_open, p.name
    assert {p.name for p in PARAMETERS} - set(V111) == set(DEV_1_2) == {
        "specular_haze", "specular_haze_spread", "specular_retroreflectivity", "emission_weight"}


def test_every_input_has_a_status():
    for spec in (PARAMETERS, DRAFT_PARAMETERS):
        for p in spec:
            if p.name in STATUS:
                assert STATUS[p.name][0] in ("implemented", "implemented with a documented "
                                             "choice", "planned", "dev_1.2", "renamed",
                                             "removed"), p.name
            else:  # a draft input kept as it is
                assert p.name in PARAMETERS.parameters, p.name
    assert set(PLANNED) <= set(V111)


def test_docs_tables_are_the_specs():
    module = _tables_script()
    assert {"OpenPBRSurface", "OpenPBRDraft"} <= set(module.PAGES)
    assert set(MATERIALS) <= set(module.PAGES)
    assert module.main(["--check"]) == 0
    text = (ROOT / "docs" / "openpbr.md").read_text(encoding="utf-8")
    for spec in (PARAMETERS, DRAFT_PARAMETERS):
        for p in spec:
            assert f"| `{p.name}` |" in text


@pytest.mark.parametrize("name, value, allowed", [
    ("specular_ior", 0.0, "(0, inf]"), ("base_color", 1.5, "[0.0, 1.0]"),
    ("coat_weight", -0.1, "[0.0, 1.0]"), ("specular_weight", np.nan, "[0.0, inf]"),
    ("geometry_thin_walled", 1, "True or False"), ("geometry_tangent", (0, 0, 0), "non-zero"),
])
def test_hard_ranges_raise_naming_the_input(name, value, allowed):
    with pytest.raises(ValueError, match=name):
        OpenPBRSurface(**{name: value})


def test_soft_ranges_are_allowed():
    OpenPBRSurface(specular_weight=1.7)
    OpenPBRSurface(specular_ior=2.9, coat_ior=2.5, coat_weight=0.5)
    OpenPBRSurface(transmission_dispersion_abbe_number=5.0)


def test_indices_beyond_the_tables_raise_naming_the_input():
    with pytest.raises(ValueError, match=r"specular_ior .* \[0.333333, 3\]"):
        OpenPBRSurface(specular_ior=4.0)
    with pytest.raises(ValueError, match="coat_ior"):
        OpenPBRSurface(coat_ior=3.5, coat_weight=1.0)
    OpenPBRSurface(coat_ior=3.5)  # no coat: its index plays no part


def test_planned_inputs_are_stored_and_warn_only_where_they_act():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        OpenPBRSurface(subsurface_radius=0.2)  # subsurface_weight 0: no effect, no warning
        OpenPBRSurface()
    with pytest.warns(UserWarning, match="geometry_coat_normal"):
        m = OpenPBRSurface(geometry_coat_normal=(0.0, 0.6, 0.8))
    assert "geometry_coat_normal" in m.planned
    np.testing.assert_array_equal(m.params["geometry_coat_normal"], (0.0, 0.6, 0.8))


# -- v1.1.1's mappings ------------------------------------------------------------------------
def test_anisotropic_alphas_keep_the_mean_square_roughness():
    r = np.linspace(0.0, 1.0, 11)[:, None]
    a = np.linspace(0.0, 1.0, 11)[None, :]
    alpha_t, alpha_b = mapping.anisotropic_alphas(r, a)
    np.testing.assert_allclose(alpha_t**2 + alpha_b**2, 2 * r**4 + 0 * a, rtol=EXACT, atol=0)
    np.testing.assert_allclose(alpha_b, (1 - a) * alpha_t, rtol=EXACT)
    np.testing.assert_array_equal(mapping.anisotropic_alphas(r, 0.0 * r)[0], r * r)
    np.testing.assert_allclose(mapping.anisotropic_alphas(r, 1.0 + 0 * r)[0], np.sqrt(2) * r * r,
                               rtol=EXACT)


@pytest.mark.parametrize("eta_s", [1.5, 1.0 / 1.33, 2.5, 1.01])
@pytest.mark.parametrize("xi", [0.0, 0.3, 1.0, 1.8])
def test_specular_weight_scales_the_normal_reflectance(eta_s, xi):
    eta = mapping.specular_ior_modulation(np.asarray(eta_s), np.asarray(xi))
    F0 = float(fresnel.dielectric(1.0, eta))
    assert F0 == pytest.approx(xi * float(fresnel.dielectric(1.0, eta_s)), rel=1e-12, abs=1e-15)
    assert (eta - 1.0) * (eta_s - 1.0) >= 0.0  # the index stays on its side of 1


def test_effective_ior_blends_ratios_and_inverts_a_denser_coat():
    assert mapping.effective_ior(1.5, 1.6, 0.0) == 1.5
    assert mapping.effective_ior(1.5, 1.3, 1.0) == pytest.approx(1.5 / 1.3, rel=EXACT)
    assert mapping.effective_ior(1.5, 1.6, 1.0) == pytest.approx(1.6 / 1.5, rel=EXACT)  # TIR fix
    assert mapping.effective_ior(1.5, 1.3, 0.25) == pytest.approx(0.75 * 1.5 + 0.25 * 1.5 / 1.3)


def test_base_roughening():
    assert mapping.base_roughening(0.3, 0.0, 1.0) == pytest.approx(0.3, rel=EXACT)
    assert mapping.base_roughening(0.0, 0.5, 1.0) == pytest.approx(2**0.25 * 0.5, rel=EXACT)
    assert mapping.base_roughening(0.2, 1.0, 1.0) == 1.0
    assert mapping.base_roughening(0.2, 1.0, 0.0) == 0.2


@pytest.mark.parametrize("f0, tint", [(0.9, 1.0), (0.2, 0.5), (0.955, 0.8), (0.6, 0.3)])
def test_f82_average_is_the_hemispherical_average(f0, tint):
    value, _ = integrate.quad(lambda mu: 2 * mu * float(fresnel.f82_tint(mu, f0, tint)[0]), 0, 1,
                              epsabs=1e-13, epsrel=1e-12, limit=200)
    f82 = mapping.f82_average(np.full(3, f0), np.full(3, tint))[0]
    assert f82 == pytest.approx(value, abs=QUADRATURE)


def test_white_metal_multiple_scattering_is_white():
    np.testing.assert_allclose(mapping.metal_multiple_scattering(np.ones(3), 0.7), 1.0,
                               rtol=EXACT)


# -- the draft ---------------------------------------------------------------------------------
def test_draft_defaults_map_to_the_released_model():
    params, differences = draft.released_parameters()
    assert differences == []
    assert params["specular_weight"] == 1.0  # level 0.5 <-> weight 1
    assert params["coat_ior"] == pytest.approx(1.6, rel=EXACT)  # coat level 0.5 keeps it
    np.testing.assert_allclose(params["geometry_tangent"], T, atol=EXACT)
    assert params["thin_film_weight"] == 0.0 and params["coat_roughness"] == 0.3
    assert params["base_diffuse_roughness"] == 0.0


def test_draft_mappings():
    params, _ = draft.released_parameters(
        specular_ior_level=0.2, specular_rotation=0.125, coat_rotation=0.25,
        thin_film_thickness=400.0, base_roughness=0.6, coat_ior=1.5, coat_ior_level=1.0,
        subsurface_color=0.5, subsurface_radius=2.0, subsurface_radius_scale=(1.0, 0.5, 0.5))
    assert params["specular_weight"] == pytest.approx(0.4)
    np.testing.assert_allclose(params["geometry_tangent"], (0.5**0.5, 0.5**0.5, 0), atol=EXACT)
    np.testing.assert_allclose(params["geometry_coat_tangent"], (0, 1, 0), atol=EXACT)
    assert params["thin_film_thickness"] == pytest.approx(0.4) and params["thin_film_weight"] == 1
    assert params["base_diffuse_roughness"] == 0.6
    # coat level 1 doubles F0 of 1.5 (0.04 -> 0.08)
    assert float(fresnel.dielectric(1.0, params["coat_ior"])) == pytest.approx(0.08, rel=1e-12)
    S = 4.012 - 15.21 * 0.5 + 32.34 * 0.25 - 34.68 * 0.125 + 13.91 * 0.0625
    assert params["subsurface_radius"] == pytest.approx(2 * S, rel=EXACT)
    np.testing.assert_allclose(params["subsurface_radius_scale"], (1, 0.5, 0.5), rtol=EXACT)


def test_from_draft_reports_what_differs():
    with pytest.warns(UserWarning, match="cos 82"):
        m = OpenPBRSurface.from_draft(base_metalness=1.0, specular_weight=0.5,
                                      specular_color=0.8, base_color=0.9)
    np.testing.assert_allclose(m.params["specular_color"], 0.4, rtol=EXACT)
    assert m.params["specular_weight"] == 1.0 and len(m.draft_differences) == 1
    with pytest.raises(ValueError, match="specular_ior_level"):
        OpenPBRSurface.from_draft(specular_ior_level=2.0)
    with pytest.raises(ValueError, match="unknown"):
        OpenPBRSurface.from_draft(specular_roughness_anisotropy=0.5)  # a released name
