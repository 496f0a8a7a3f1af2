"""The check cases: every lobe and material configuration that ``python -m adobe_bsdf check``,
the benchmarks and the execution tests run, declared here as data.

Public API
----------
``CheckCase``     one configuration and what to expect of it.
``cases(tag)``    the cases, optionally only those carrying ``tag``.

The order is part of the record: ``check`` derives each case's random seeds from its index,
so new cases are appended at the end.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from adobe_bsdf import fresnel
from adobe_bsdf.composition import Layer, Mix, Rotated, Sum
from adobe_bsdf.darkening import Darkening
from adobe_bsdf.frame import refract
from adobe_bsdf.lobes import (
    Conductor,
    ConductorMS,
    Dielectric,
    DielectricMS,
    DielectricReflection,
    Dispersive,
    Lambert,
    Sheen,
)
from adobe_bsdf.lobes.hazy import HazyDielectric, HazyGloss
from adobe_bsdf.lobes.ltc_sheen import LTCSheen
from adobe_bsdf.lobes.oren_nayar import EnergyPreservingOrenNayar
from adobe_bsdf.lobes.pass_through import PassThrough
from adobe_bsdf.lobes.thin_dielectric import ThinDielectric
from adobe_bsdf.materials.asm import (
    AdobeStandardMaterial,
    ASMDiffuse,
    asm_coat,
    asm_dielectric,
    asm_dielectric_base,
    asm_metal,
)
from adobe_bsdf.materials.openpbr import OpenPBRSurface

__all__ = ["CheckCase", "cases", "FURNACE_TOL", "FURNACE_TOL_DIELECTRIC",
           "FURNACE_TOL_ANISOTROPIC"]

FURNACE_TOL = 1e-3
"""White-furnace bound of the table-based terms: the tables' interpolation error
(``docs/tables.md``)."""
FURNACE_TOL_DIELECTRIC = 2e-3
"""The same for a dielectric's R + T."""
FURNACE_TOL_ANISOTROPIC = 2e-3
"""The same for the anisotropic tables (``docs/tables.md``)."""


@dataclass(frozen=True)
class CheckCase:
    """One lobe configuration to validate.

    Attributes
    ----------
    name : str
        Short label, e.g. ``"Conductor a=0.1"``.
    make : callable
        ``make() -> Lobe``.
    cos_theta_o : tuple of float
        Incident cosines at which the chi-square and furnace tests run (negative: ``wo``
        below the surface, for two-sided lobes).
    expected_albedo : callable or None
        ``expected_albedo(wo) -> float``: an independent closed form of the energy albedo;
        ``None`` means the check compares with direction-space quadrature of ``eval``.
    width : float
        Characteristic angular width (radians) of the sharpest sampled peak, used to focus
        the chi-square grid (0: broad lobe).
    peak : callable or None
        ``peak(wo) -> (3,)``: direction of that peak (e.g. the mirror direction).
    tags : tuple of str
        Free-form tags (e.g. ``"fast"`` for the cases the command runs by default).
    furnace_tol : float
        Allowed |quadrature albedo - expected_albedo| (table-based models: their measured
        interpolation error, ``docs/tables.md``).
    reciprocal : bool
        False for a BSDF that is not reciprocal by design (albedo-scaled layers): its
        reciprocity error is listed, not judged.
    """

    name: str
    make: Callable
    cos_theta_o: tuple = (1.0, 0.5, 0.05)
    expected_albedo: Callable | None = None
    width: float = 0.0
    peak: Callable | None = None
    tags: tuple = field(default=("fast",))
    furnace_tol: float = 1e-6
    reciprocal: bool = True


def _one(wo):
    return 1.0


def _mirror(wo):
    return np.array([-wo[0], -wo[1], wo[2]])


def _straight_through(wo):
    return -np.asarray(wo, dtype=np.float64)


def _refracted(wo, eta=1.5):
    cos_t = np.sqrt(1.0 - (1.0 - wo[2] ** 2) / eta**2)
    return np.array([-wo[0] / eta, -wo[1] / eta, -cos_t])


def _one_minus_ln2(wo):
    """alpha = 1, F = 1, normal view: the closed-form albedo 1 - ln 2 of GGX."""
    return 1.0 - np.log(2.0) if wo[2] == 1.0 else None


def _hazy_glass():
    return HazyDielectric(0.04, 0.3, 4.0, 0.05, compound_masking=True)


def _hazy_glass_peak(wo):
    """The refracted direction of the mean normal (the mirror one under total reflection)."""
    eta = float(_hazy_glass().eta)
    wt, ok = refract(np.asarray(wo), np.array([0.0, 0.0, 1.0]), eta if wo[2] > 0 else 1 / eta)
    return wt if ok else _mirror(wo)


def _glass_peak(wo, eta=1.5):
    """The refracted direction of the mean normal through an interface of relative index
    ``eta`` (n_below / n_above), the mirror one under total internal reflection."""
    wt, ok = refract(np.asarray(wo), np.array([0.0, 0.0, 1.0]), eta if wo[2] > 0 else 1 / eta)
    return wt if ok else _mirror(wo)


_GOLD = fresnel.ExactConductor(eta=(0.143, 0.374, 1.442), k=(3.983, 2.385, 1.603))
_ASM_GOLD = {"base_color": (1.0, 0.7099, 0.3148),
             "specular_edge_color": (0.9408, 0.9636, 0.9099)}
#: the transmitted lobe's spread 2 alpha |1 - 1/eta| at alpha = 0.05, eta = 1.5
_DISPERSIVE_SPREAD = 0.05 * 0.9
_TABLES = ("fast", "tables")
#: OpenPBR's glass: specular_roughness 0.3 (alpha 0.09), specular_ior 1.5; its sharpest peak
#: is the transmitted one, of spread 2 alpha |1 - 1/eta|
_OPENPBR_GLASS = {"transmission_weight": 1.0, "specular_roughness": 0.3, "specular_ior": 1.5}
_OPENPBR_GLASS_SPREAD = 2 * 0.09 * (1 - 1 / 1.5)

_CASES = (
    # -- dielectric interfaces
    CheckCase("Dielectric eta=1.5 a=0.3", lambda: Dielectric(1.5, 0.3),
              cos_theta_o=(1.0, 0.5, 0.05, -0.5)),
    CheckCase("Dielectric eta=1/1.5 a=(0.5,0.2)", lambda: Dielectric(1 / 1.5, 0.5, 0.2),
              cos_theta_o=(0.9, 0.3, -0.7)),
    CheckCase("Dielectric Beckmann eta=1.5 a=(0.3,0.1)",
              lambda: Dielectric(1.5, 0.3, 0.1, model="beckmann"),
              cos_theta_o=(1.0, 0.5, 0.05, -0.5)),
    CheckCase("Dielectric eta=1.01 a=0.5", lambda: Dielectric(1.01, 0.5),
              cos_theta_o=(0.8, -0.8), width=0.01, peak=_straight_through),
    CheckCase("Dielectric eta=1 a=0.5", lambda: Dielectric(1.0, 0.5), cos_theta_o=(0.8, -0.3),
              expected_albedo=_one),
    CheckCase("Dielectric eta=1.5 smooth", lambda: Dielectric(1.5, 0.0),
              cos_theta_o=(0.8, -0.8), expected_albedo=_one),
    # -- composition
    CheckCase("Sum 0.3 Lambert + 0 + 0.7 Conductor a=(0.6,0.1)",
              lambda: Sum(Lambert(), Conductor(0.2), Conductor(0.6, 0.1),
                          weights=[(0.3, 0.2, 0.1), 0.0, (0.7, 0.8, 0.9)])),
    CheckCase("Mix w=(0.2,0.5,0.7) diffuse 0.8 / Dielectric eta=1.5 a=0.3",
              lambda: Mix(Lambert(0.8), Dielectric(1.5, 0.3), (0.2, 0.5, 0.7)),
              cos_theta_o=(0.5, -0.5)),
    # -- dispersion
    CheckCase("Dispersive eta=1.5 dispersion=1 a=0.3", lambda: Dispersive(1.5, 1.0, 0.3),
              cos_theta_o=(1.0, 0.5, 0.05, -0.5)),
    CheckCase("Dispersive eta=1/1.5 dispersion=0.3 a=(0.3,0.1)",
              lambda: Dispersive(1 / 1.5, 0.3, 0.3, 0.1), cos_theta_o=(0.9, -0.6)),
    CheckCase("Dispersive eta=1.5 dispersion=1 a=0.05",
              lambda: Dispersive(1.5, 1.0, 0.05), cos_theta_o=(0.9,), width=_DISPERSIVE_SPREAD,
              peak=_refracted),
    # -- rotation
    CheckCase("Rotated Conductor a=(0.5,0.1) phi=pi/3",
              lambda: Rotated(Conductor(0.5, 0.1), np.pi / 3)),
    CheckCase("Rotated Dielectric eta=1.5 a=(0.4,0.05) phi=pi/2",
              lambda: Rotated(Dielectric(1.5, 0.4, 0.05), np.pi / 2),
              cos_theta_o=(1.0, 0.5, 0.05, -0.5)),
    CheckCase("ASM dielectric ior=1.5 r=0.4 a=0.7 angle=0.15 dispersion=0.5",
              lambda: asm_dielectric(1.5, 0.4, 0.7, 0.15, 0.5),
              cos_theta_o=(1.0, 0.5, -0.5)),
    # -- conductors
    CheckCase("Conductor a=1 F=1", lambda: Conductor(1.0), cos_theta_o=(1.0, 0.5, 0.05),
              expected_albedo=_one_minus_ln2),
    CheckCase("Conductor a=0.1 F=1", lambda: Conductor(0.1), width=0.2, peak=_mirror),
    CheckCase("Conductor Beckmann a=0.3 F=1", lambda: Conductor(0.3, model="beckmann")),
    CheckCase("Conductor a=(0.5,0.1) gold", lambda: Conductor(0.5, 0.1, fresnel=_GOLD)),
    # -- the ASM's energy-conserving diffuse
    CheckCase("ASMDiffuse r=0.3 ior=1.5", lambda: ASMDiffuse((0.9, 0.5, 0.2), 0.3, 1.5),
              tags=_TABLES),
    CheckCase("ASM base white r=0.5 ior=1.5", lambda: asm_dielectric_base(1.0, 0.5, 1.5),
              expected_albedo=_one, furnace_tol=1e-3,  # tables' interpolation error
              tags=_TABLES),
    CheckCase("ASM base r=0.05 ior=2.5", lambda: asm_dielectric_base(0.5, 0.05, 2.5),
              width=0.01, peak=_mirror, tags=_TABLES),
    # -- Kulla-Conty multiple scattering
    CheckCase("ConductorMS a=0.5 F=1", lambda: ConductorMS(0.5), expected_albedo=_one,
              furnace_tol=FURNACE_TOL, tags=_TABLES),
    CheckCase("ConductorMS a=(0.8,0.05) F=1", lambda: ConductorMS(0.8, 0.05),
              expected_albedo=_one, furnace_tol=FURNACE_TOL_ANISOTROPIC, tags=_TABLES),
    CheckCase("ConductorMS a=(0.8,0.3) gold-ish", lambda: ConductorMS(
        0.8, 0.3, base_color=(1.0, 0.71, 0.31)), tags=_TABLES),
    CheckCase("DielectricMS eta=1.5 a=0.5", lambda: DielectricMS(1.5, 0.5),
              cos_theta_o=(0.9, 0.3, -0.5), expected_albedo=_one,
              furnace_tol=FURNACE_TOL_DIELECTRIC, tags=_TABLES),
    CheckCase("DielectricMS eta=1/1.33 a=0.3", lambda: DielectricMS(1 / 1.33, 0.3),
              cos_theta_o=(0.7, -0.2, -0.8), expected_albedo=_one,
              furnace_tol=FURNACE_TOL_DIELECTRIC, tags=_TABLES),
    CheckCase("ASM metal gold r=0.4 a=0.6 angle=0.15",
              lambda: asm_metal((1.0, 0.7099, 0.3148), (0.9408, 0.9636, 0.9099), 0.4, 0.6, 0.15),
              furnace_tol=1e-3),
    # -- coat
    CheckCase("ASM coat ior=1.6 r=0.2 a=0.5 angle=0.1", lambda: asm_coat(1.6, 0.2, 0.5, 0.1)),
    CheckCase("DielectricReflection eta=1/1.5 a=0.3", lambda: DielectricReflection(1 / 1.5, 0.3),
              cos_theta_o=(1.0, 0.5, 0.1)),
    # -- diffuse and sheen
    CheckCase("Lambert", lambda: Lambert(1.0), expected_albedo=_one),
    CheckCase("Sheen r=0.3 c=2", lambda: Sheen(1.0, 0.3)),
    CheckCase("Sheen r=1 c=2", lambda: Sheen(1.0, 1.0)),
    CheckCase("Sheen r=0.1 c=2 tinted", lambda: Sheen((0.9, 0.5, 0.2), 0.1)),
    # -- hazy gloss
    CheckCase("HazyGloss rc=(.9,.6,.3) bh=0.5",
              lambda: HazyGloss([0.9, 0.6, 0.3], 0.5, 5.0, 0.05, edge_tint=0.3), width=0.1,
              peak=_mirror),
    CheckCase("HazyGloss rc=0.04 bh=0.1 aniso",
              lambda: HazyGloss(0.04, 0.1, 4.0, 0.1, 0.05, haze_extent_y=1.0), width=0.1,
              peak=_mirror),
    CheckCase("HazyGloss Beckmann compound bh=0.6",
              lambda: HazyGloss(0.5, 0.6, 4.0, 0.06, edge_tint=0.8, model="beckmann",
                                compound_masking=True), width=0.12, peak=_mirror),
    CheckCase("HazyDielectric rc=0.04 bh=0.3 compound", _hazy_glass,
              cos_theta_o=(1.0, 0.5, 0.05, -0.5), width=0.05, peak=_hazy_glass_peak),
    # -- the Adobe Standard Material
    CheckCase("ASM white diffuse + specular r=0.5 ior=1.5",
              lambda: AdobeStandardMaterial(base_color=1.0, roughness=0.5, ior=1.5),
              expected_albedo=_one, furnace_tol=1e-3, tags=_TABLES),
    CheckCase("ASM white dielectric r=0.4 anisotropic",
              lambda: AdobeStandardMaterial(base_color=1.0, roughness=0.4, ior=1.5,
                                            anisotropy_level=0.8, anisotropy_angle=0.1),
              expected_albedo=_one, furnace_tol=FURNACE_TOL_ANISOTROPIC, tags=_TABLES),
    CheckCase("ASM gold metal r=0.3 anisotropic",
              lambda: AdobeStandardMaterial(metallic=1.0, roughness=0.3, anisotropy_level=0.5,
                                            anisotropy_angle=0.1, **_ASM_GOLD),
              tags=_TABLES),
    CheckCase("ASM coated red plastic",
              lambda: AdobeStandardMaterial(base_color=(0.8, 0.1, 0.1), roughness=0.5,
                                            coat_opacity=1.0, coat_roughness=0.1,
                                            coat_color=(0.9, 0.8, 0.5)),
              tags=_TABLES, reciprocal=False),
    CheckCase("ASM fully loaded",
              lambda: AdobeStandardMaterial(base_color=(0.6, 0.5, 0.4), roughness=0.35,
                                            metallic=0.3, translucency=0.4, dispersion=0.5,
                                            anisotropy_level=0.4, sheen_opacity=0.5,
                                            sheen_roughness=0.5, coat_opacity=0.5,
                                            coat_color=(0.9, 0.9, 0.7)),
              cos_theta_o=(0.9, 0.3, -0.6), tags=_TABLES, reciprocal=False),
    CheckCase("ASM dispersive glass r=0.3",
              lambda: AdobeStandardMaterial(translucency=1.0, roughness=0.3, dispersion=1.0),
              cos_theta_o=(1.0, 0.5, -0.5), tags=_TABLES),
    # -- the forms of Layer (appended: a case's seeds follow its index)
    CheckCase("Layer reciprocal DielectricReflection eta=1.5 a=0.3 / diffuse (0.9,0.5,0.2)",
              lambda: Layer(DielectricReflection(1.5, 0.3), Lambert((0.9, 0.5, 0.2)),
                            scaling="reciprocal"), cos_theta_o=(1.0, 0.5, 0.1)),
    CheckCase("Layer transmittance T=(0.9,0.6,0.3) eta=1.5 a=0.2 c=0.9 / diffuse 0.8",
              lambda: Layer(DielectricReflection(1.5, 0.2), Lambert(0.8), 0.9, (0.9, 0.6, 0.3),
                            scaling="transmittance"), cos_theta_o=(1.0, 0.5, 0.1),
              reciprocal=False),
    CheckCase("Layer albedo darkened eta=1.5 a=0.3 / ConductorMS a=0.3 (0.9,0.5,0.2)",
              lambda: Layer(DielectricReflection(1.5, 0.3),
                            ConductorMS(0.3, base_color=(0.9, 0.5, 0.2)),
                            darkening=Darkening()), cos_theta_o=(1.0, 0.5, 0.1),
              reciprocal=False),
    # -- the lobes and the material of OpenPBR Surface
    CheckCase("EON white sigma=1", lambda: EnergyPreservingOrenNayar(1.0, 1.0),
              cos_theta_o=(1.0, 0.5, 0.05), expected_albedo=_one),
    CheckCase("EON (0.9,0.5,0.2) sigma=0.5",
              lambda: EnergyPreservingOrenNayar((0.9, 0.5, 0.2), 0.5)),
    CheckCase("LTCSheen (1,0.8,0.6) alpha=0.5", lambda: LTCSheen((1.0, 0.8, 0.6), 0.5),
              cos_theta_o=(1.0, 0.5, 0.1), reciprocal=False),
    CheckCase("OpenPBR white rough diffuse + coat + fuzz",
              lambda: OpenPBRSurface(base_color=1.0, base_diffuse_roughness=1.0,
                                     specular_roughness=0.4, coat_weight=1.0,
                                     coat_roughness=0.2, fuzz_weight=1.0),
              expected_albedo=_one, furnace_tol=FURNACE_TOL_DIELECTRIC, tags=_TABLES,
              reciprocal=False),
    CheckCase("OpenPBR white metal r=0.3 anisotropic",
              lambda: OpenPBRSurface(base_metalness=1.0, base_color=1.0,
                                     specular_roughness=0.3,
                                     specular_roughness_anisotropy=0.8,
                                     geometry_tangent=(0.6, 0.8, 0.0)),
              expected_albedo=_one, furnace_tol=FURNACE_TOL_ANISOTROPIC, tags=_TABLES),
    CheckCase("PassThrough", PassThrough, cos_theta_o=(0.8, -0.3), expected_albedo=_one),
    CheckCase("OpenPBR white diffuse, opacity 0.4",
              lambda: OpenPBRSurface(base_color=1.0, specular_roughness=0.5,
                                     geometry_opacity=0.4),
              cos_theta_o=(1.0, 0.5, 0.1), expected_albedo=_one,
              furnace_tol=FURNACE_TOL_DIELECTRIC, tags=_TABLES, reciprocal=False),
    # -- the thin-walled sheet (both sides: a negative cosine)
    CheckCase("ThinDielectric clear eta=1.5 a=0.3",
              lambda: ThinDielectric(1.5, 0.3), cos_theta_o=(1.0, 0.5, -0.3),
              expected_albedo=_one, furnace_tol=FURNACE_TOL_DIELECTRIC, tags=_TABLES),
    CheckCase("ThinDielectric absorbing (0.9,0.6,0.3) eta=1.33 a=0.15,0.08",
              lambda: ThinDielectric(1.33, 0.15, 0.08, transmittance=(0.9, 0.6, 0.3)),
              cos_theta_o=(0.8, -0.4), width=0.3, peak=_straight_through, tags=_TABLES),
    # -- OpenPBR's translucent, subsurface and thin-walled bases
    CheckCase("OpenPBR white glass r=0.3 ior=1.5",
              lambda: OpenPBRSurface(**_OPENPBR_GLASS, transmission_color=1.0),
              cos_theta_o=(1.0, 0.5, 0.05, -0.5), expected_albedo=_one,
              furnace_tol=FURNACE_TOL_DIELECTRIC, width=_OPENPBR_GLASS_SPREAD,
              peak=_glass_peak, tags=_TABLES),
    CheckCase("OpenPBR tinted glass (0.5,0.7,1) r=0.3 ior=1.5",
              lambda: OpenPBRSurface(**_OPENPBR_GLASS, transmission_color=(0.5, 0.7, 1.0)),
              cos_theta_o=(0.8, -0.8), width=_OPENPBR_GLASS_SPREAD, peak=_glass_peak,
              tags=_TABLES),
    CheckCase("OpenPBR white subsurface r=0.4",
              lambda: OpenPBRSurface(subsurface_weight=1.0, subsurface_color=1.0,
                                     specular_color=1.0, specular_roughness=0.4,
                                     base_diffuse_roughness=0.5),
              cos_theta_o=(1.0, 0.5, 0.1), expected_albedo=_one,
              furnace_tol=FURNACE_TOL_DIELECTRIC, tags=_TABLES, reciprocal=False),
    CheckCase("OpenPBR thin-walled clear sheet r=0.4 ior=1.5",
              lambda: OpenPBRSurface(geometry_thin_walled=True, transmission_weight=1.0,
                                     specular_roughness=0.4, transmission_color=1.0),
              cos_theta_o=(1.0, 0.5, -0.3), expected_albedo=_one,
              furnace_tol=FURNACE_TOL_DIELECTRIC, tags=_TABLES),
    CheckCase("OpenPBR thin-walled white subsurface g=0.4",
              lambda: OpenPBRSurface(geometry_thin_walled=True, subsurface_weight=1.0,
                                     subsurface_color=1.0, specular_color=1.0,
                                     subsurface_scatter_anisotropy=0.4),
              cos_theta_o=(1.0, 0.5, -0.3), expected_albedo=_one,
              furnace_tol=FURNACE_TOL_DIELECTRIC, tags=_TABLES, reciprocal=False),
    CheckCase("OpenPBR thin-film metal d=0.4um n=1.5",
              lambda: OpenPBRSurface(base_metalness=1.0, base_color=(0.9, 0.6, 0.3),
                                     specular_roughness=0.4, thin_film_weight=1.0,
                                     thin_film_thickness=0.4, thin_film_ior=1.5),
              cos_theta_o=(1.0, 0.5, 0.1), tags=_TABLES),
    CheckCase("OpenPBR thin-film dielectric d=0.3um n=1.33",
              lambda: OpenPBRSurface(base_color=(0.2, 0.3, 0.5), specular_roughness=0.3,
                                     thin_film_weight=1.0, thin_film_thickness=0.3,
                                     thin_film_ior=1.33),
              cos_theta_o=(1.0, 0.5, 0.1), tags=_TABLES, reciprocal=False),
    CheckCase("OpenPBR thin-film white glass r=0.3 d=0.4um",
              lambda: OpenPBRSurface(**_OPENPBR_GLASS, transmission_color=1.0,
                                     thin_film_weight=1.0, thin_film_thickness=0.4,
                                     thin_film_ior=1.33),
              cos_theta_o=(1.0, 0.3, -0.5), expected_albedo=_one,
              furnace_tol=FURNACE_TOL_DIELECTRIC, width=_OPENPBR_GLASS_SPREAD,
              peak=_glass_peak, tags=_TABLES),
    CheckCase("OpenPBR soap bubble r=0.2 d=0.4um",
              lambda: OpenPBRSurface(geometry_thin_walled=True, transmission_weight=1.0,
                                     transmission_color=1.0, specular_ior=1.0,
                                     specular_roughness=0.2, thin_film_weight=1.0,
                                     thin_film_thickness=0.4, thin_film_ior=1.33),
              cos_theta_o=(1.0, 0.5, -0.3), expected_albedo=_one,
              furnace_tol=FURNACE_TOL_DIELECTRIC, tags=_TABLES),
)


def cases(tag: str | None = None) -> list[CheckCase]:
    """The check cases in their fixed order, optionally only those with ``tag``."""
    return [c for c in _CASES if tag is None or tag in c.tags]
