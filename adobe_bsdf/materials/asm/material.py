"""The Adobe Standard Material as one BSDF [Kutz2021] (the parameter table is ``docs/asm.md``).

    sheen  over  coat  over  metallic * metal + (1 - metallic) * dielectric
    dielectric = (1 - translucency) (specular + energy-conserving diffuse)
                 + translucency * rough (dispersive) transmission, the medium below it

Each "over" is ``composition.Layer`` (albedo scaling: nothing above adds energy). Lobes whose
weight is zero everywhere are never built (``AdobeStandardMaterial.lobes`` lists the ones
that were), so a plain diffuse material costs a small fraction of a fully loaded one
(``benchmarks/active_lobes.py``). The parameters are validated once, against ``PARAMETERS``;
the lobes are assembled from the validated arrays.
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params, media, tables
from adobe_bsdf.composition import Layer, Rotated, Sum
from adobe_bsdf.lobes.sheen import Sheen
from adobe_bsdf.materials.asm import lobes
from adobe_bsdf.materials.asm.diffuse import ASMDiffuse, ASMSpecular
from adobe_bsdf.materials.asm.mapping import (
    COAT_IOR_RANGE,
    CoatTransmittance,
    ior_under_coat,
    rotation,
)
from adobe_bsdf.materials.material import Material
from adobe_bsdf.materials.spec import Parameter, ParameterSpec

__all__ = ["AdobeStandardMaterial", "PARAMETERS"]

_UNIT = (0.0, 1.0)
_INF = float("inf")

#: the ASM's inputs [Kutz2021] (defaults marked "ours" are not given by the paper)
PARAMETERS = ParameterSpec(
    Parameter("base_color", "color", 0.8, _UNIT, doc=(
        "[Kutz2021, §1, §2] metal: F0 of `fresnel.F82Tint` and Kulla–Conty × base_color² "
        "(`materials.asm.asm_metal`); dielectric: ρ of `materials.asm.ASMDiffuse` (eq. 1); "
        "default ours")),
    Parameter("roughness", "real", 0.3, _UNIT, doc=(
        "[Kutz2021, §3 eqs. 9–10] `materials.asm.asm_alpha(roughness, anisotropy)` for every "
        "base lobe; default ours")),
    Parameter("metallic", "real", 0.0, _UNIT, doc=(
        "[Kutz2021, §1] weight of the metal against the dielectric (`composition.Sum`)")),
    Parameter("specular_edge_color", "color", 1.0, _UNIT, doc=(
        "[Kutz2021, §2 eqs. 6–8] tint of `fresnel.f82_tint`; white is 'a universal "
        "default'; Table 1 in `materials.presets.metals`; from spectra "
        "`spectral.fit_f82_tint`")),
    Parameter("ior", "real", 1.5, (1.0, tables.ETA_MAX), doc=(
        "[Kutz2021, §1, §4] `ASMSpecular`/`ASMDiffuse` (opaque), `asm_dielectric` "
        "(transmission); under a coat `materials.asm.base_ior_under_coat`; default ours")),
    Parameter("anisotropy_level", "real", 0.0, _UNIT, doc=(
        "[Kutz2021, §3 eqs. 9–10] α_x = r² + a⁴, α_y = r²; metal, specular and transmission")),
    Parameter("anisotropy_angle", "real", 0.0, _UNIT, doc=(
        "[Kutz2021, §3] φ = 2π angle (`materials.asm.anisotropy_rotation`) turns the lobes "
        "(`composition.Rotated`)")),
    Parameter("dispersion", "real", 0.0, (0.0, _INF), soft=_UNIT, doc=(
        "[Kutz2021, §4 eqs. 12–13] 20 / V_d; 1 is the most dispersive real glass; "
        "`dispersion.cauchy_iors`, `lobes.Dispersive`")),
    Parameter("translucency", "real", 0.0, _UNIT, doc=(
        "[Kutz2021, §4, §5] weight of the rough (dispersive) transmission against the opaque "
        "specular + diffuse; the medium below it is `medium()`")),
    Parameter("scattering_color", "color", None, _UNIT, doc=(
        "[Kutz2021, §5] `media.asm_medium` (Kulla & Conty inversion); derived: base_color "
        "(ours)")),
    Parameter("scattering_distance", "real", 1.0, (0.0, _INF), (0.0, 10.0), doc=(
        "[Kutz2021, §5] `media.asm_medium` (0 raised to 1e-9); default ours")),
    Parameter("scattering_distance_scale", "color", 1.0, (0.0, _INF), doc=(
        "[Kutz2021, §5] `media.asm_medium` (divides the extinction)")),
    Parameter("scatter_rayleigh", "real", 0.0, (-_INF, _INF), soft=(-1.0, 2.0), doc=(
        "[Kutz2021, §5 listing] `media.asm_medium`, clamped to [−1, 2] there")),
    Parameter("scattering_red_shift", "real", 0.0, _UNIT, doc=(
        "[Kutz2021, §5] (no formula given) `media.asm_medium`: σ_t,r × 2^−s (ours)")),
    Parameter("sheen_opacity", "real", 0.0, _UNIT, doc=(
        "[Kutz2021, §6] `lobes.Sheen` of colour sheen_opacity × sheen_color, layered over "
        "everything")),
    Parameter("sheen_color", "color", 1.0, _UNIT, doc="[Kutz2021, §6] as above; default ours"),
    Parameter("sheen_roughness", "real", 0.5, _UNIT, doc=(
        "[Kutz2021, §6 eqs. 16–18] r of `lobes.Sheen` (not squared); default ours")),
    Parameter("coat_opacity", "real", 0.0, _UNIT, doc=(
        "[Kutz2021, §7] coverage c of `composition.Layer`")),
    Parameter("coat_color", "color", 1.0, _UNIT, doc=(
        "[Kutz2021, §7, Fig. 18] `materials.asm.CoatTransmittance` (Beer's law, "
        "view-dependent)")),
    Parameter("coat_roughness", "real", 0.0, _UNIT, doc=(
        "[Kutz2021, §7 Table 4] `materials.asm.asm_coat` (ASM alphas, independent of the "
        "base); default ours")),
    Parameter("coat_ior", "real", 1.6, COAT_IOR_RANGE, doc=(
        "[Kutz2021, §7, Fig. 17] `materials.asm.asm_coat`; "
        "`materials.asm.base_ior_under_coat`; default ours")),
    Parameter("coat_anisotropy_level", "real", 0.0, _UNIT, doc=(
        "[Kutz2021, §7] `materials.asm.asm_coat` (ours: as §3)")),
    Parameter("coat_anisotropy_angle", "real", 0.0, _UNIT, doc=(
        "[Kutz2021, §7] `materials.asm.asm_coat` (ours: as §3)")),
    Parameter("emissive_color", "color", 1.0, _UNIT, doc="`AdobeStandardMaterial.emission(wo)`"),
    Parameter("emissive_intensity", "real", 0.0, (0.0, _INF), (0.0, 10.0), doc=(
        "`AdobeStandardMaterial.emission(wo)`")),
)


def _any(x) -> bool:
    return bool(np.any(x != 0.0))


def _c(x):
    """A per-element weight ``(...)`` as a colour weight ``(..., 3)``."""
    return _params.as_color(np.asarray(x)[..., None])


class AdobeStandardMaterial(Material):
    """The ASM [Kutz2021]: its lobes combined into one BSDF.

    Parameters are keyword arguments named as in ``docs/asm.md`` (``PARAMETERS`` holds kind,
    range, default and meaning); each broadcasts, so a texture of parameters evaluates in
    one call.

    Structure (module docstring):
    - metal: ``asm_metal`` (F82-tint, Kulla–Conty x base_color^2, anisotropy, rotation);
    - opaque dielectric: ``ASMSpecular`` turned by the anisotropy angle + ``ASMDiffuse`` of
      base_color (eq. 1; anisotropic lobes use the tables at ``table_roughness``);
    - transmissive dielectric: ``asm_dielectric`` (anisotropic, dispersive), and
      ``medium()`` from ``media.asm_medium``;
    - coat: ``asm_coat`` over the base with coverage coat_opacity, the view-dependent tint
      ``CoatTransmittance`` and the base's index ``base_ior_under_coat``; no darkening by
      internal reflection [Kutz2021, Table 4];
    - sheen: ``lobes.Sheen`` of colour sheen_opacity x sheen_color over everything;
    - emission: emissive_color x emissive_intensity, seen through the coat and the sheen.
    """

    #: the inputs, their ranges and defaults
    parameters = PARAMETERS

    def __init__(self, **params):
        p = self.params = PARAMETERS.validate(params)
        p.setdefault("scattering_color", p["base_color"])
        built = {}
        coat = _any(p["coat_opacity"])
        eta = ior_under_coat(p["ior"], p["coat_ior"], p["coat_opacity"]) if coat else p["ior"]
        r, a, angle = p["roughness"], p["anisotropy_level"], p["anisotropy_angle"]
        metal, clear = p["metallic"], p["translucency"]
        parts, weights = [], []
        if _any(metal):
            built["metal"] = lobes.metal(p["base_color"], p["specular_edge_color"], r, a,
                                              angle)
            parts.append(built["metal"])
            weights.append(_c(metal))
        opaque = (1.0 - metal) * (1.0 - clear)
        if _any(opaque):
            phi = rotation(angle)
            specular = ASMSpecular._new(r, eta, a)
            built["specular"] = Rotated._new(specular, phi) if _any(phi) else specular
            diffuse = ASMDiffuse._new(p["base_color"], r, eta, a)
            built["diffuse"] = Rotated._new(diffuse, phi) if _any(phi) and _any(a) else diffuse
            parts += [built["specular"], built["diffuse"]]
            weights += [_c(opaque), _c(opaque)]
        glass = (1.0 - metal) * clear
        if _any(glass):
            built["transmission"] = lobes.dielectric(eta, r, a, angle, p["dispersion"])
            parts.append(built["transmission"])
            weights.append(_c(glass))
        bsdf = Sum._new(parts, weights)
        self._layers = []
        if coat:
            built["coat"] = lobes.coat(p["coat_ior"], p["coat_roughness"],
                                            p["coat_anisotropy_level"],
                                            p["coat_anisotropy_angle"])
            tint = (None if not _any(p["coat_color"] - 1.0)
                    else CoatTransmittance._new(p["coat_color"], p["coat_ior"]))
            bsdf = Layer._new(built["coat"], bsdf, p["coat_opacity"], tint)
            self._layers.append(bsdf)
        sheen = _c(p["sheen_opacity"]) * p["sheen_color"]
        if _any(sheen):
            built["sheen"] = Sheen._new(sheen, p["sheen_roughness"])
            bsdf = Layer._new(built["sheen"], bsdf)
            self._layers.append(bsdf)
        super().__init__(bsdf, built)
        self._glass = _any(glass)

    def __repr__(self) -> str:
        return f"AdobeStandardMaterial(lobes={list(self.lobes)})"

    def emission(self, wo) -> np.ndarray:
        """emissive_color x emissive_intensity leaving towards ``wo`` (0 below the surface),
        through each layer above the base once (``Layer.exit_weight``)."""
        wo = _params.direction("wo", wo)
        Le = self.params["emissive_color"] * _c(self.params["emissive_intensity"])
        Le = np.where((wo[..., 2] > 0.0)[..., None], Le, 0.0)
        for layer in self._layers:
            Le = Le * layer.exit_weight(wo)
        return Le

    def medium(self):
        """The subsurface medium under the transmissive dielectric (``media.asm_medium``), or
        None where translucency (or metallic) leaves no transmission."""
        if not self._glass:
            return None
        p = self.params
        return media.asm_medium(p["scattering_distance"], p["scattering_color"],
                                p["scattering_distance_scale"], p["scatter_rayleigh"],
                                p["scattering_red_shift"])
