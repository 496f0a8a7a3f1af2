"""Reading and writing materials in interchange formats (``docs/materialx.md``).

Public API
----------
``load_mtlx(path)``                  every ``open_pbr_surface`` of a MaterialX document, as a
                                     ``MtlxResult`` (a mapping of names to ``OpenPBRSurface``)
``save_mtlx(materials, path)``       a MaterialX document of one or more ``OpenPBRSurface``
``MtlxResult``, ``MtlxMaterial``     what ``load_mtlx`` returns: the materials and, per
                                     material, its parameters, colour spaces and warnings
``MtlxWarning``                      the category of the importer's own warnings
``COLOR_SPACES``                     the MaterialX colour spaces read and written

The MaterialX package (``pip install materialx``, or the ``mtlx`` extra) is imported only
when a function needs it.
"""

from adobe_bsdf.io.mtlx import (
    COLOR_SPACES,
    MtlxMaterial,
    MtlxResult,
    MtlxWarning,
    load_mtlx,
    save_mtlx,
)

__all__ = ["load_mtlx", "save_mtlx", "MtlxResult", "MtlxMaterial", "MtlxWarning",
           "COLOR_SPACES"]
