"""Lobes: one small class per BSDF lobe, each with ``eval``, ``pdf``, ``sample``, ``albedo``.

``Lambert(albedo)``                                         ideal diffuse reflection
``Conductor(alpha_x, alpha_y=None, fresnel=None, masking, model)`` rough reflection
``Dielectric(eta, alpha_x, alpha_y=None, masking, model)``  rough reflection + refraction
                                                            (model "ggx" or "beckmann"; ``.over``
                                                            takes any microfacet distribution)
``Sum(*lobes)``                                             sum, sampled as a mixture
``Dispersive(eta, dispersion, alpha_x, alpha_y=None, ...)``  one index per RGB channel (ASM §4)
``Rotated(lobe, phi)``                                      turned about the normal (ASM §3)
``ConductorMultipleScattering`` / ``ConductorMS``           Kulla–Conty for metals (x base colour^2)
``DielectricMultipleScattering`` / ``DielectricMS``         Kulla–Conty for rough dielectrics
``ASMSpecular``, ``ASMDiffuse``, ``asm_dielectric_base``    ASM energy-conserving diffuse (eq. 1)
``asm_metal(base_color, specular_edge_color, roughness, anisotropy_level, anisotropy_angle)``
                                                            ASM metal (F82-tint, §2-3)
``DielectricReflection(eta, alpha_x, alpha_y=None)``        a dielectric's reflection alone
``Sheen(color, roughness, c=2, p=1)``                         ASM microflake sheen (§6)
``asm_coat(coat_ior, coat_roughness, ...)``, ``coat_transmittance``, ``base_ior_under_coat``
                                                            the ASM coat (§7, Table 4)
``asm_dielectric(ior, roughness, anisotropy_level, anisotropy_angle, dispersion)``
                                                            ASM dielectric specular (§3-4)
"""

from adobe_bsdf.lobes.asm_dielectric import asm_dielectric
from adobe_bsdf.lobes.asm_diffuse import ASMDiffuse, ASMSpecular, asm_dielectric_base
from adobe_bsdf.lobes.asm_metal import asm_metal
from adobe_bsdf.lobes.coat import (
    DielectricReflection,
    asm_coat,
    base_ior_under_coat,
    coat_transmittance,
)
from adobe_bsdf.lobes.conductor import Conductor
from adobe_bsdf.lobes.dielectric import Dielectric
from adobe_bsdf.lobes.dispersive import Dispersive
from adobe_bsdf.lobes.kulla_conty import (
    ConductorMS,
    ConductorMultipleScattering,
    DielectricMS,
    DielectricMultipleScattering,
)
from adobe_bsdf.lobes.lambert import Lambert
from adobe_bsdf.lobes.rotated import Rotated, anisotropy_rotation
from adobe_bsdf.lobes.sheen import Sheen
from adobe_bsdf.lobes.sum import Sum

__all__ = ["Lambert", "Conductor", "Dielectric", "Sum", "ConductorMultipleScattering",
           "ConductorMS", "DielectricMultipleScattering", "DielectricMS", "ASMSpecular",
           "ASMDiffuse", "asm_dielectric_base", "Rotated", "anisotropy_rotation", "asm_metal",
           "Dispersive", "asm_dielectric", "DielectricReflection", "asm_coat",
           "coat_transmittance", "base_ior_under_coat", "Sheen"]
