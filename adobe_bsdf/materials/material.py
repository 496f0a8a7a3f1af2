"""A material: a tree of lobes seen as one lobe, plus its emission and interior medium."""

from __future__ import annotations

import numpy as np

from adobe_bsdf.bsdf import Lobe
from adobe_bsdf.composition import Wrapper

__all__ = ["Material"]


class Material(Wrapper):
    """One BSDF made of the lobe tree ``bsdf``, with the whole protocol forwarded to it
    (``composition.Wrapper``), ``emission(wo)`` and ``medium()``.

    ``lobes`` lists the leaf lobes the material was built with (zero-weight lobes are never
    built, so a material costs only what it uses).

    Parameters
    ----------
    bsdf : Lobe
        The material's lobe tree (a subclass builds it from its parameters).
    lobes : dict of str to Lobe, optional
        Its named leaf lobes.
    """

    #: the material's inputs (``materials.spec.ParameterSpec``); None for a bare lobe tree
    parameters = None

    def __init__(self, bsdf: Lobe, lobes: dict | None = None):
        if not isinstance(bsdf, Lobe):
            raise ValueError(f"bsdf = {bsdf!r}: allowed a Lobe")
        self.bsdf = bsdf
        self.lobes = dict(lobes or {})

    @property
    def flags(self):
        return self.bsdf.flags

    def _inner(self):
        return self.bsdf

    def emission(self, wo) -> np.ndarray:
        """Emitted radiance towards ``wo``, RGB ``(..., 3)`` (none by default)."""
        wo = np.asarray(wo, dtype=np.float64)
        return np.zeros(wo.shape[:-1] + (3,))

    def medium(self):
        """The interior ``media.Medium``, or None for an opaque material."""
        return None
