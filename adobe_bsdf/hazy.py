"""Hazy gloss [Barla2018], everything in one namespace: the haze mapping
(``adobe_bsdf.haze``) and the lobes built on it (``lobes.HazyGloss``,
``lobes.HazyDielectric``).

Public API
----------
``HazyGloss(core_reflectivity, haziness, haze_extent, alpha_x, alpha_y=None, edge_tint=0, ...)``
``HazyDielectric(core_reflectivity, haziness, haze_extent, alpha_x, alpha_y=None, ...)``
``haze_mapping``, ``HazeMapping``, ``wide_roughness``, ``peak_ratio``, ``haze_intensity``,
``haze_intensity_smooth``, ``PEAK_MODELS``: see ``adobe_bsdf.haze``.
"""

from adobe_bsdf.haze import (
    PEAK_MODELS,
    HazeMapping,
    haze_intensity,
    haze_intensity_smooth,
    haze_mapping,
    peak_ratio,
    wide_roughness,
)
from adobe_bsdf.lobes.hazy import HazyDielectric, HazyGloss

__all__ = ["HazyGloss", "HazyDielectric", "PEAK_MODELS", "wide_roughness", "peak_ratio",
           "haze_intensity", "haze_intensity_smooth", "HazeMapping", "haze_mapping"]
