"""Materials: recipes that assemble lobes into one BSDF from a parameter specification.

Public API
----------
``AdobeStandardMaterial(**params)``  the whole ASM as one BSDF [Kutz2021] (``docs/asm.md``);
                                   its recipes in ``materials.asm``.
``OpenPBRSurface(**params)``         OpenPBR Surface v1.1.1 [OpenPBR2026] (``docs/openpbr.md``);
                                   its inputs and mappings in ``materials.openpbr``.
``MATERIALS``                      the registry: ``{name: material class}``; each class's
                                   ``parameters`` is its ``spec.ParameterSpec``.
``Material``                       base of the materials: a lobe tree with ``emission`` and
                                   ``medium``.
``Parameter``, ``ParameterSpec``   parameter specifications (``materials.spec``).
``presets``                        named parameter sets from the source papers.
"""

from adobe_bsdf.materials import asm, openpbr, presets
from adobe_bsdf.materials.asm import AdobeStandardMaterial
from adobe_bsdf.materials.material import Material
from adobe_bsdf.materials.openpbr import OpenPBRSurface
from adobe_bsdf.materials.spec import Parameter, ParameterSpec

#: every material by name; ``MATERIALS[name].parameters`` is its parameter specification
MATERIALS = {"AdobeStandardMaterial": AdobeStandardMaterial, "OpenPBRSurface": OpenPBRSurface}

__all__ = ["asm", "openpbr", "presets", "AdobeStandardMaterial", "OpenPBRSurface", "Material",
           "MATERIALS", "Parameter", "ParameterSpec"]
