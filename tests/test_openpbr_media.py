"""``OpenPBRSurface.media()`` / ``medium()``: the interior media of the translucent and
subsurface bases with their presence weights [OpenPBR2026, §Subsurface, §Translucent base]."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from adobe_bsdf import media
from adobe_bsdf.materials.openpbr import OpenPBRSurface


def test_opaque_materials_have_no_medium():
    for p in ({}, dict(base_metalness=1.0, subsurface_weight=1.0),
              dict(transmission_weight=1.0)):  # depth 0: a tint, no medium
        m = OpenPBRSurface(**p)
        assert m.media() == {} and m.medium() is None


def test_media_are_the_mappings_with_their_presence_weights():
    p = dict(base_metalness=0.2, transmission_weight=0.25, transmission_depth=0.5,
             transmission_color=(0.9, 0.5, 0.2), transmission_scatter=(0.1, 0.1, 0.1),
             transmission_scatter_anisotropy=0.3, subsurface_weight=0.6,
             subsurface_radius=0.4, subsurface_radius_scale=(1.0, 0.5, 0.25),
             subsurface_color=(0.8, 0.6, 0.4), subsurface_scatter_anisotropy=-0.2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing here is "not modelled yet"
        m = OpenPBRSurface(**p)
    found = m.media()
    w_t, tr = found["transmission"]
    w_s, ss = found["subsurface"]
    assert w_t == pytest.approx(0.8 * 0.25, rel=1e-15)
    assert w_s == pytest.approx(0.8 * 0.75 * 0.6, rel=1e-15)
    np.testing.assert_allclose(np.exp(-tr.sigma_t * 0.5), (0.9, 0.5, 0.2), rtol=1e-12)
    np.testing.assert_allclose(tr.sigma_s, 0.2, rtol=1e-15)
    assert tr.g == 0.3
    expected = media.openpbr_subsurface_medium(0.4, (1.0, 0.5, 0.25), (0.8, 0.6, 0.4), -0.2)
    for a, b in zip(ss, expected, strict=True):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_allclose(ss.sigma_t, 1.0 / (0.4 * np.array([1.0, 0.5, 0.25])),
                               rtol=1e-15)
    for a, b in zip(m.medium(), ss, strict=True):  # the larger presence
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("p", [
    dict(subsurface_weight=1.0, subsurface_color=1.0, specular_color=1.0,
         subsurface_radius=0.3, subsurface_scatter_anisotropy=0.5),
    dict(transmission_weight=1.0, transmission_color=1.0, specular_roughness=0.3),
    dict(transmission_weight=1.0, transmission_depth=0.5, transmission_scatter=1.0,
         transmission_color=1.0, specular_roughness=0.3)])
def test_white_furnace_of_the_media_cases(p):
    """The specification's furnace cases of this kind: the surface's energy albedo (both
    sides of a glass) is 1 +- 2e-3, and the medium behind it (where there is one) is
    lossless, so the walk inside returns all the light it is given."""
    m = OpenPBRSurface(**p)
    mu = np.array([0.9, 0.4])
    s = np.sqrt(1 - mu**2)
    up = np.stack([s, 0 * s, mu], -1)
    wo = np.concatenate([up, -up]) if p.get("transmission_weight") else up
    np.testing.assert_allclose(m.albedo(wo, tol=1e-6), 1.0, atol=2e-3)
    for _, medium in m.media().values():
        np.testing.assert_allclose(medium.albedo, 1.0, rtol=1e-12)
