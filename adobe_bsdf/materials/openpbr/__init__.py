"""OpenPBR Surface [OpenPBR2026; Andersson2023]: its inputs, its parameter mappings and the
material (``docs/openpbr.md``).

Public API
----------
``OpenPBRSurface(spec="1.1.1", **params)``
                               the whole surface as one BSDF; ``OpenPBRSurface.from_draft``
                               for the draft v0.1 inputs
``SPECS``, ``DEV_1_2``         the versions followed, the development branch's own inputs
``PARAMETERS``, ``DRAFT_PARAMETERS``, ``STATUS``, ``PLANNED``   its inputs (``parameters``)
``mapping``                    v1.1.1's mappings (alphas, indices, roughening, metal Fresnel)
``draft``                      the draft's inputs onto the released ones
"""

from adobe_bsdf.materials.openpbr import draft, mapping
from adobe_bsdf.materials.openpbr.material import ETA_RANGE, OpenPBRSurface
from adobe_bsdf.materials.openpbr.parameters import (
    DEV_1_2,
    DRAFT_PARAMETERS,
    PARAMETERS,
    PLANNED,
    SPECS,
    STATUS,
)

__all__ = ["OpenPBRSurface", "PARAMETERS", "DRAFT_PARAMETERS", "STATUS", "PLANNED",
           "ETA_RANGE", "SPECS", "DEV_1_2", "mapping", "draft"]
