"""Materials and their parameter presets.

Public API
----------
``presets``                        named parameter sets from the source papers.
``AdobeStandardMaterial(**params)``  the whole ASM as one BSDF (seed 000; ``docs/asm.md``).
``Material``                       base of the materials: a lobe tree with ``emission`` and
                                   ``medium``.
"""

from adobe_bsdf.materials import presets
from adobe_bsdf.materials.asm import AdobeStandardMaterial
from adobe_bsdf.materials.material import Material

__all__ = ["presets", "AdobeStandardMaterial", "Material"]
