"""Materials and their parameter presets.

Public API
----------
``presets``   named parameter sets from the source papers (``presets.hazy``: seed 002).
"""

from adobe_bsdf.materials import presets

__all__ = ["presets"]
