"""The Adobe Standard Material as one BSDF (seed 000; the parameter table is ``docs/asm.md``).

    sheen  over  coat  over  metallic * metal + (1 - metallic) * dielectric
    dielectric = (1 - translucency) (specular + energy-conserving diffuse)
                 + translucency * rough (dispersive) transmission, the medium below it

Each "over" is ``layering.Layer`` (albedo scaling: nothing above adds energy). Lobes whose
weight is zero everywhere are never built (``AdobeStandardMaterial.lobes`` lists the ones
that were), so a plain diffuse material costs a small fraction of a fully loaded one
(``benchmarks/active_lobes.py``).
"""

from __future__ import annotations

from functools import partial

import numpy as np

from adobe_bsdf import _params, media, tables
from adobe_bsdf.layering import Layer
from adobe_bsdf.lobes.asm_dielectric import asm_dielectric
from adobe_bsdf.lobes.asm_diffuse import ASMDiffuse, ASMSpecular, table_roughness
from adobe_bsdf.lobes.asm_metal import asm_metal
from adobe_bsdf.lobes.coat import (
    COAT_IOR_RANGE,
    asm_coat,
    base_ior_under_coat,
    coat_transmittance,
)
from adobe_bsdf.lobes.rotated import Rotated, anisotropy_rotation
from adobe_bsdf.lobes.sheen import Sheen
from adobe_bsdf.lobes.sum import Sum
from adobe_bsdf.materials.material import Material
from adobe_bsdf.registry import CheckCase, register

__all__ = ["AdobeStandardMaterial", "PARAMETERS"]

#: name: (kind, allowed range, default). Kinds: "color" (trailing axis 3 or scalar), "real".
PARAMETERS = {
    "base_color": ("color", (0.0, 1.0), 0.8),
    "roughness": ("real", (0.0, 1.0), 0.3),
    "metallic": ("real", (0.0, 1.0), 0.0),
    "specular_edge_color": ("color", (0.0, 1.0), 1.0),
    "ior": ("real", (1.0, tables.ETA_MAX), 1.5),
    "anisotropy_level": ("real", (0.0, 1.0), 0.0),
    "anisotropy_angle": ("real", (0.0, 1.0), 0.0),
    "dispersion": ("real", (0.0, np.inf), 0.0),
    "translucency": ("real", (0.0, 1.0), 0.0),
    "scattering_color": ("color", (0.0, 1.0), None),  # None: the base_color
    "scattering_distance": ("real", (0.0, np.inf), 1.0),
    "scattering_distance_scale": ("color", (0.0, np.inf), 1.0),
    "scatter_rayleigh": ("real", (-np.inf, np.inf), 0.0),
    "scattering_red_shift": ("real", (0.0, 1.0), 0.0),
    "sheen_opacity": ("real", (0.0, 1.0), 0.0),
    "sheen_color": ("color", (0.0, 1.0), 1.0),
    "sheen_roughness": ("real", (0.0, 1.0), 0.5),
    "coat_opacity": ("real", (0.0, 1.0), 0.0),
    "coat_color": ("color", (0.0, 1.0), 1.0),
    "coat_roughness": ("real", (0.0, 1.0), 0.0),
    "coat_ior": ("real", COAT_IOR_RANGE, 1.6),
    "coat_anisotropy_level": ("real", (0.0, 1.0), 0.0),
    "coat_anisotropy_angle": ("real", (0.0, 1.0), 0.0),
    "emissive_color": ("color", (0.0, 1.0), 1.0),
    "emissive_intensity": ("real", (0.0, np.inf), 0.0),
}


def _validated(params: dict) -> dict:
    unknown = set(params) - set(PARAMETERS)
    if unknown:
        raise ValueError(f"unknown parameter(s) {sorted(unknown)}; allowed: "
                         f"{sorted(PARAMETERS)}")
    p = {}
    for name, (kind, (lo, hi), default) in PARAMETERS.items():
        value = params.get(name, default)
        if value is None:
            continue
        p[name] = (_params.color if kind == "color" else _params.real)(name, value, lo, hi)
    p.setdefault("scattering_color", p["base_color"])
    return p


def _any(x) -> bool:
    return bool(np.any(x != 0.0))


def _c(x):
    """A per-element weight ``(...)`` as a colour weight ``(..., 1)``."""
    return np.asarray(x)[..., None]


class AdobeStandardMaterial(Material):
    """The ASM (seed 000): every lobe of ``adobe_bsdf.lobes`` for it, combined into one BSDF.

    Parameters are keyword arguments named as in ``docs/asm.md`` (``PARAMETERS`` holds kind,
    range and default); each broadcasts, so a texture of parameters evaluates in one call.

    Structure (module docstring):
    - metal: ``asm_metal`` (F82-tint, Kulla–Conty x base_color^2, anisotropy, rotation);
    - opaque dielectric: ``ASMSpecular`` turned by the anisotropy angle + ``ASMDiffuse`` of
      base_color (eq. 1; anisotropic lobes use the tables at ``table_roughness``);
    - transmissive dielectric: ``asm_dielectric`` (anisotropic, dispersive), and
      ``medium()`` from ``media.asm_medium``;
    - coat: ``asm_coat`` over the base with coverage coat_opacity, the view-dependent tint
      ``coat_transmittance`` and the base's index ``base_ior_under_coat``; no darkening by
      internal reflection (Table 4);
    - sheen: ``lobes.Sheen`` of colour sheen_opacity x sheen_color over everything;
    - emission: emissive_color x emissive_intensity, seen through the coat and the sheen.
    """

    def __init__(self, **params):
        p = self.params = _validated(params)
        self.lobes = {}
        coat = _any(p["coat_opacity"])
        eta = (base_ior_under_coat(p["ior"], p["coat_ior"], p["coat_opacity"]) if coat
               else p["ior"])
        r, a, angle = p["roughness"], p["anisotropy_level"], p["anisotropy_angle"]
        phi = anisotropy_rotation(angle)
        metal, clear = p["metallic"], p["translucency"]
        parts, weights = [], []
        if _any(metal):
            self.lobes["metal"] = asm_metal(p["base_color"], p["specular_edge_color"], r, a, angle)
            parts.append(self.lobes["metal"])
            weights.append(_c(metal))
        opaque = (1.0 - metal) * (1.0 - clear)
        if _any(opaque):
            specular = ASMSpecular(r, eta, a)
            self.lobes["specular"] = Rotated(specular, phi) if _any(phi) else specular
            self.lobes["diffuse"] = ASMDiffuse(p["base_color"], table_roughness(r, a), eta)
            parts += [self.lobes["specular"], self.lobes["diffuse"]]
            weights += [_c(opaque), _c(opaque)]
        glass = (1.0 - metal) * clear
        if _any(glass):
            self.lobes["transmission"] = asm_dielectric(eta, r, a, angle, p["dispersion"])
            parts.append(self.lobes["transmission"])
            weights.append(_c(glass))
        bsdf = Sum(*parts, weights=weights)
        self._layers = []
        if coat:
            self.lobes["coat"] = asm_coat(p["coat_ior"], p["coat_roughness"],
                                          p["coat_anisotropy_level"], p["coat_anisotropy_angle"])
            tint = (None if not _any(p["coat_color"] - 1.0)
                    else partial(coat_transmittance, p["coat_color"], p["coat_ior"]))
            bsdf = Layer(self.lobes["coat"], bsdf, p["coat_opacity"], tint)
            self._layers.append(bsdf)
        sheen = _c(p["sheen_opacity"]) * p["sheen_color"]
        if _any(sheen):
            self.lobes["sheen"] = Sheen(sheen, p["sheen_roughness"])
            bsdf = Layer(self.lobes["sheen"], bsdf)
            self._layers.append(bsdf)
        self.bsdf = bsdf
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


def _check_cases():
    gold = {"base_color": (1.0, 0.7099, 0.3148), "specular_edge_color": (0.9408, 0.9636, 0.9099)}
    return (
        CheckCase("ASM white diffuse + specular r=0.5 ior=1.5",
                  lambda: AdobeStandardMaterial(base_color=1.0, roughness=0.5, ior=1.5),
                  expected_albedo=lambda wo: 1.0, furnace_tol=1e-3, tags=("fast", "tables")),
        CheckCase("ASM gold metal r=0.3 anisotropic",
                  lambda: AdobeStandardMaterial(metallic=1.0, roughness=0.3, anisotropy_level=0.5,
                                                anisotropy_angle=0.1, **gold),
                  tags=("fast", "tables")),
        CheckCase("ASM coated red plastic",
                  lambda: AdobeStandardMaterial(base_color=(0.8, 0.1, 0.1), roughness=0.5,
                                                coat_opacity=1.0, coat_roughness=0.1,
                                                coat_color=(0.9, 0.8, 0.5)),
                  tags=("fast", "tables"), reciprocal=False),
        CheckCase("ASM fully loaded",
                  lambda: AdobeStandardMaterial(base_color=(0.6, 0.5, 0.4), roughness=0.35,
                                                metallic=0.3, translucency=0.4, dispersion=0.5,
                                                anisotropy_level=0.4, sheen_opacity=0.5,
                                                sheen_roughness=0.5, coat_opacity=0.5,
                                                coat_color=(0.9, 0.9, 0.7)),
                  cos_theta_o=(0.9, 0.3, -0.6), tags=("fast", "tables"), reciprocal=False),
        CheckCase("ASM dispersive glass r=0.3",
                  lambda: AdobeStandardMaterial(translucency=1.0, roughness=0.3, dispersion=1.0),
                  cos_theta_o=(1.0, 0.5, -0.5), tags=("fast", "tables")),
    )


register(*_check_cases())
