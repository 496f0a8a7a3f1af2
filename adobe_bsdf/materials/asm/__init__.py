"""The Adobe Standard Material [Kutz2021]: its parameter mappings, its lobes and the material.

Public API
----------
``AdobeStandardMaterial(**params)``  the whole ASM as one BSDF; ``PARAMETERS`` its inputs.
``asm_metal``, ``asm_dielectric``, ``asm_coat``         its specular lobes (``lobes``)
``ASMSpecular``, ``ASMDiffuse``, ``asm_dielectric_base``  its energy-conserving diffuse
                                                        under the specular (``diffuse``)
``asm_alpha``, ``table_roughness``, ``anisotropy_rotation``, ``base_ior_under_coat``,
``CoatTransmittance``, ``coat_transmittance``, ``COAT_IOR_RANGE``   its mappings (``mapping``)
"""

from adobe_bsdf.materials.asm.diffuse import ASMDiffuse, ASMSpecular, asm_dielectric_base
from adobe_bsdf.materials.asm.lobes import asm_coat, asm_dielectric, asm_metal
from adobe_bsdf.materials.asm.mapping import (
    COAT_IOR_RANGE,
    CoatTransmittance,
    anisotropy_rotation,
    asm_alpha,
    base_ior_under_coat,
    coat_transmittance,
    table_roughness,
)
from adobe_bsdf.materials.asm.material import PARAMETERS, AdobeStandardMaterial

__all__ = ["AdobeStandardMaterial", "PARAMETERS", "asm_metal", "asm_dielectric", "asm_coat",
           "ASMSpecular", "ASMDiffuse", "asm_dielectric_base", "asm_alpha", "table_roughness",
           "anisotropy_rotation", "base_ior_under_coat", "CoatTransmittance",
           "coat_transmittance", "COAT_IOR_RANGE"]
