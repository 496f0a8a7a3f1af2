"""adobe_bsdf: a pure-NumPy reference implementation of the Adobe Standard Material,
the generalized F82 Fresnel model, hazy gloss and OpenPBR Surface.

The validation toolkit is imported on its own: ``import adobe_bsdf.validation``.
"""

from adobe_bsdf import (
    config,
    dispersion,
    frame,
    fresnel,
    hazy,
    layering,
    lobes,
    materials,
    media,
    microfacet,
    paper_figures,
    plot,
    quadrature,
    registry,
    render,
    spectral,
    tables,
)
from adobe_bsdf.bsdf import BSDFSample, Flags, Lobe
from adobe_bsdf.frame import Frame
from adobe_bsdf.microfacet import GGX, Beckmann, asm_alpha

__all__ = ["config", "dispersion", "frame", "fresnel", "hazy", "layering", "lobes", "materials",
           "media", "microfacet", "paper_figures", "plot", "quadrature", "registry", "render",
           "spectral", "tables",
           "BSDFSample", "Flags", "Lobe", "Frame", "GGX", "Beckmann", "asm_alpha"]
__version__ = "0.1.0"
