"""The draft v0.1 inputs [Andersson2023] onto the released v1.1.1 ones [OpenPBR2026]
(``OpenPBRSurface.from_draft``; every mapping and every formula that differs is listed in
``docs/openpbr.md``).

Public API
----------
``released_parameters(**draft_params) -> (params, differences)``
    ``params`` the v1.1.1 inputs, ``differences`` one line for each place where the released
    model cannot reproduce the draft's formula exactly for these values.
``draft_diffusion_scale(A)``   S(A) of [Andersson2023, §Subsurface] (Burley's fit)
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf.materials.openpbr.mapping import reflectance_at_normal, specular_ior_modulation
from adobe_bsdf.materials.openpbr.parameters import DRAFT_PARAMETERS

__all__ = ["released_parameters", "draft_diffusion_scale", "RENAMED", "SAME"]

#: draft names that became other released names, meaning unchanged
RENAMED = {"base_roughness": "base_diffuse_roughness",
           "specular_anisotropy": "specular_roughness_anisotropy",
           "subsurface_anisotropy": "subsurface_scatter_anisotropy",
           "coat_anisotropy": "coat_roughness_anisotropy"}
#: draft names kept as they are
SAME = ("base_weight", "base_color", "base_metalness", "specular_roughness",
        "transmission_weight", "transmission_color", "transmission_depth",
        "transmission_scatter_anisotropy", "transmission_dispersion_scale",
        "transmission_dispersion_abbe_number", "subsurface_weight", "subsurface_color",
        "coat_weight", "coat_color", "coat_roughness", "fuzz_weight", "fuzz_color",
        "fuzz_roughness", "emission_luminance", "emission_color", "thin_film_ior",
        "geometry_opacity", "geometry_thin_walled")


def draft_diffusion_scale(A):
    """S(A) = 4.012 - 15.21 A + 32.34 A^2 - 34.68 A^3 + 13.91 A^4 [Andersson2023,
    §Subsurface]: mu_t = 1 / (S(A) r) for a diffusion radius r and multiple-scattering albedo
    A, so the mean free path is S(A) r."""
    return 4.012 + A * (-15.21 + A * (32.34 + A * (-34.68 + 13.91 * A)))


def _draft_ior_level(eta, level):
    """eta' of [Andersson2023, §Dielectric base eq. modulated_ior]: F0 times 2 level, level
    clamped to [0, min(1, 1 / (2 F_s))] (the released modulation with xi = 2 level)."""
    level = np.minimum(level, np.minimum(1.0, 0.5 / np.maximum(reflectance_at_normal(eta),
                                                               1e-300)))
    return specular_ior_modulation(eta, 2.0 * level)


def _tangent(rotation):
    """The tangent turned by 2 pi ``rotation`` about the normal [Andersson2023, §Anisotropy]."""
    angle = 2.0 * np.pi * rotation
    return np.stack([np.cos(angle), np.sin(angle), np.zeros_like(angle)], axis=-1)


def released_parameters(**draft_params):
    """The v1.1.1 inputs for the draft's ``draft_params`` (validated against
    ``DRAFT_PARAMETERS``; defaults are the draft's), and the list of differences.

    Mappings [Andersson2023 -> OpenPBR2026]:
    - the renamed inputs (``RENAMED``) and the unchanged ones (``SAME``) as they are;
    - coat_ior_level: folded into coat_ior, n_c = eta'_c with F_c times 2 level;
    - specular_ior_level and the draft's dielectric specular_weight w: specular_weight =
      2 level w (the draft's w multiplies the Fresnel factor at every angle; the released
      weight scales F0 through the index: a difference where w != 1);
    - the draft's metal edge w specular_color at cos 82 deg: specular_color = w
      specular_color at mu_bar = 1/7 where the base is all metal (a difference always: the
      tint's angle moved), the dielectric mapping above where it is not;
    - specular_rotation, coat_rotation: geometry_tangent, geometry_coat_tangent =
      (cos 2 pi theta, sin 2 pi theta, 0); the (roughness, anisotropy) -> alphas mapping
      the draft left open is v1.1.1's;
    - subsurface radius (a diffusion radius r times subsurface_scale, here
      subsurface_radius_scale): the mean free path S(A) r per channel, as subsurface_radius
      (its largest channel) times subsurface_radius_scale;
    - transmission_scatter (a scattering albedo s): -s ln(transmission_color), so that
      mu_s = S / d of v1.1.1 equals the draft's s mu_t (clipped to [0, 1]);
    - thin_film_thickness in nm: / 1000 (micrometres), thin_film_weight = 1 where it is > 0.
    """
    p = DRAFT_PARAMETERS.validate(draft_params)
    out = {name: p[name] for name in SAME}
    out.update({new: p[old] for old, new in RENAMED.items()})
    differences = []
    C, M = p["coat_weight"], p["base_metalness"]
    out["coat_ior"] = n_c = _draft_ior_level(p["coat_ior"], p["coat_ior_level"])
    w, level = p["specular_weight"], p["specular_ior_level"]
    all_metal = bool(np.all(M == 1.0))
    if all_metal:
        out["specular_weight"] = np.ones_like(w)
        out["specular_color"] = p["specular_color"] * w[..., None]
    else:
        out["specular_weight"] = 2.0 * level * w
        out["specular_color"] = p["specular_color"]
        if np.any(w != 1.0):
            differences.append("specular_weight != 1: the draft scales the dielectric's "
                               "Fresnel factor at every angle, the released model its F0 "
                               "through the index (specular_weight = 2 level w)")
        if np.any(M > 0.0) and np.any((2.0 * level * w != 1.0) | (w != 1.0)):
            differences.append("a partly metallic base with specular_ior_level != 0.5 or "
                               "specular_weight != 1: the released specular_weight also "
                               "scales the metal's Fresnel")
    if np.any(M > 0.0):
        differences.append("metal: the edge tint is placed at mu_bar = 1/7 (81.8 deg) in "
                           "the released model, at cos 82 deg in the draft")
    n_b = p["specular_ior"]
    if np.any((C > 0.0) & (C < 1.0)) or np.any((C > 0.0) & (n_c > n_b)):
        differences.append("coat: the draft divides specular_ior by lerp(1, n_c, C); the "
                           "released model blends the ratios, lerp(n_b, n_b / n_c, C), and "
                           "inverts n_b / n_c where n_c > n_b (its TIR fix)")
    out["geometry_tangent"] = _tangent(p["specular_rotation"])
    out["geometry_coat_tangent"] = _tangent(p["coat_rotation"])
    A, r = p["subsurface_color"], p["subsurface_radius"]
    mfp = draft_diffusion_scale(A) * r[..., None] * p["subsurface_radius_scale"]
    radius = mfp.max(axis=-1)
    out["subsurface_radius"] = radius
    out["subsurface_radius_scale"] = np.where(radius[..., None] > 0.0,
                                              mfp / np.where(radius > 0.0, radius, 1.0)[
                                                  ..., None], 1.0)
    if np.any(p["subsurface_anisotropy"] != 0.0):
        differences.append("subsurface anisotropy: the draft rescales the albedo and the "
                           "extinction by similarity theory; the released extinction does "
                           "not depend on g")
    with np.errstate(divide="ignore"):
        scatter = -p["transmission_scatter"] * np.log(p["transmission_color"])
    scatter = np.nan_to_num(scatter, nan=0.0, posinf=1.0)
    if np.any(scatter > 1.0):
        differences.append("transmission_scatter: -s ln(transmission_color) exceeds 1 and is "
                           "clipped")
    out["transmission_scatter"] = np.minimum(scatter, 1.0)
    thickness = p["thin_film_thickness"]
    out["thin_film_thickness"] = thickness / 1000.0
    out["thin_film_weight"] = (thickness > 0.0).astype(np.float64)
    return out, differences
