"""adobe_bsdf: a pure-NumPy reference implementation of the Adobe Standard Material, the
generalized F82 Fresnel model, hazy gloss and OpenPBR Surface v1.1.1.

Layers, each importing only those below it (``docs/architecture.md``): core maths
(``fresnel``, ``microfacet``, ``frame``, ``spectral``, ``haze``, ...) ← ``tables`` and
``quadrature`` ← ``bsdf`` (the protocol) ← ``composition`` ← ``lobes`` ← ``materials``;
``layered`` (the stochastic layered reference) beside ``materials``; ``validation``,
``render``, ``plot``, ``paper_figures``, ``explorer`` (``explore``: sliders from a parameter
specification, in Jupyter) and the command line beside them.
The validation toolkit, the conformance of a BSDF written elsewhere and the MaterialX reader
are imported on their own: ``import adobe_bsdf.validation``, ``import adobe_bsdf.conformance``,
``import adobe_bsdf.io``.
"""

from adobe_bsdf import (
    composition,
    config,
    darkening,
    dispersion,
    frame,
    fresnel,
    haze,
    hazy,
    layered,
    lobes,
    materials,
    media,
    microfacet,
    paper_figures,
    phase,
    plot,
    quadrature,
    render,
    spectral,
    tables,
    thin_film,
)
from adobe_bsdf._version import __version__
from adobe_bsdf.bsdf import BSDFSample, Flags, Lobe
from adobe_bsdf.explorer import explore
from adobe_bsdf.frame import Frame
from adobe_bsdf.layered import LayeredReference
from adobe_bsdf.microfacet import GGX, Beckmann

__all__ = ["composition", "config", "darkening", "dispersion", "frame", "fresnel", "haze", "hazy",
           "layered", "lobes", "materials", "media", "microfacet", "paper_figures", "phase", "plot",
           "quadrature", "render", "spectral", "tables", "thin_film",
           "explore", "BSDFSample", "Flags", "Lobe", "LayeredReference", "Frame", "GGX", "Beckmann",
           "__version__"]
