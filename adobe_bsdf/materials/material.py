"""A material: a tree of lobes seen as one lobe, plus its emission and interior medium."""

from __future__ import annotations

import numpy as np

from adobe_bsdf.bsdf import Lobe, Wrapper

__all__ = ["Material"]


class Material(Wrapper):
    """One BSDF made of the lobe tree ``bsdf`` (built by a subclass), with the full protocol
    forwarded to it, ``emission(wo)`` and ``medium()``.

    ``lobes`` lists the leaf lobes the material was built with (zero-weight lobes are never
    built, so a material costs only what it uses).
    """

    bsdf: Lobe

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

    # -- forwarded protocol -------------------------------------------------------------------
    def _param_shape(self):
        return self.bsdf._param_shape()

    def _eval(self, wo, wi):
        return self.bsdf._eval(wo, wi)

    def _pdf(self, wo, wi):
        return self.bsdf._pdf(wo, wi)

    def _eval_pdf(self, wo, wi):
        return self.bsdf._eval_pdf(wo, wi)

    def _pdf_t(self, wo, wi, throughput):
        return self.bsdf._pdf_t(wo, wi, throughput)

    def _eval_pdf_t(self, wo, wi, throughput):
        return self.bsdf._eval_pdf_t(wo, wi, throughput)

    def _sample(self, wo, u):
        return self.bsdf._sample(wo, u)

    def _sample_t(self, wo, u, throughput):
        return self.bsdf._sample_t(wo, u, throughput)

    def _delta_albedo(self, wo):
        return self.bsdf._delta_albedo(wo)

    def _energy_scale(self, wo, wi):
        return self.bsdf._energy_scale(wo, wi)

    def _energy_scale_rgb(self, wo, wi):
        return self.bsdf._energy_scale_rgb(wo, wi)

    def _albedo_table(self, wo, with_error=True):
        return self.bsdf._albedo_table(wo, with_error)

    def _albedo_quadrature(self, wo, tol):
        return self.bsdf._albedo_quadrature(wo, tol)

    def _sampling_weight(self, wo):
        return self.bsdf._sampling_weight(wo)
