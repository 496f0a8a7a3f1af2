"""A rough dielectric whose refracted light is tinted: f = f_R + t f_T."""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params, quadrature
from adobe_bsdf._channels import pick, scaled, selected, weighted
from adobe_bsdf.bsdf import BSDFSample, Flags
from adobe_bsdf.composition import Wrapper
from adobe_bsdf.fresnel import ExactDielectric
from adobe_bsdf.lobes.kulla_conty import DielectricMS, DispersiveMS
from adobe_bsdf.lobes.reflection import DielectricReflection

__all__ = ["TintedRefraction"]

_T = int(Flags.TRANSMISSION)


class TintedRefraction(Wrapper):
    """``DielectricMS`` (or ``DispersiveMS``, channel by channel) with every refraction
    multiplied by the colour ``tint``, f = f_R + t f_T: a constant tint on the refraction of
    an interface with no medium behind it [OpenPBR2026, §Translucent base]; t = 1 is the
    lobe.

    Reflection pairs (both directions on one side) are the lobe's, refraction pairs and
    refracted samples are multiplied by t; pdfs and sampled directions are the lobe's, so
    sampling stays exact. The energy splits into what the lobe reflects, E_R, and what it
    refracts, E_T: E = E_R + t E_T, with E_R the single-scattering reflection of the
    interface (``DielectricReflection`` of the same index and microfacets: its tables, or its
    exact Fresnel where smooth) plus the Kulla–Conty term's reflected share (its reflection
    probability times its albedo 1 - E_s), and E_T the rest of the lobe's albedo. A tint
    <= 1 never adds energy; the tinted lobe is reciprocal where the lobe is (t multiplies
    both directions of a refraction pair alike).

    Parameters
    ----------
    lobe : DielectricMS or DispersiveMS
    tint : colour in [0, 1]
    """

    def __init__(self, lobe: DielectricMS | DispersiveMS, tint):
        if not isinstance(lobe, (DielectricMS, DispersiveMS)):
            raise ValueError(f"lobe = {lobe!r}: allowed a DielectricMS or a DispersiveMS")
        self._init(lobe, _params.color("tint", tint, 0.0, 1.0))

    def _init(self, lobe, tint):
        self.lobe, self.tint = lobe, tint
        self.flags = lobe.flags
        single = lobe.components[0]
        if isinstance(lobe, DispersiveMS):  # channel c: its index and its own term
            etas, self._multiple = [single.eta[..., c] for c in range(3)], lobe.channels
        else:
            etas, self._multiple = [single.eta], lobe.components[1:]
        #: per channel (one for all if they share it): the interface's reflection seen
        #: from above and, mirrored, from below
        self._reflections = [tuple(
            DielectricReflection._new(single.distribution, ExactDielectric._new(e))
            for e in (np.asarray(eta, dtype=np.float64), 1.0 / np.asarray(eta)))
            for eta in etas]

    def __repr__(self) -> str:
        return f"TintedRefraction({self.lobe!r}, tint={self.tint!r})"

    def _inner(self):
        return self.lobe

    def _param_shape(self):
        shape = self.lobe._param_shape()
        return None if shape is None else np.broadcast_shapes(shape, self.tint.shape[:-1])

    # -- f: the tint on refraction pairs --------------------------------------------------
    def _tinted(self, f, wo, wi):
        zo, zi = wo[..., 2], wi[..., 2]
        across = ((zo < 0.0) != (zi < 0.0)) & (zo != 0.0) & (zi != 0.0)  # signs: no underflow
        return selected(across, scaled(f, self.tint), f)

    def _eval(self, wo, wi):
        return self._tinted(self.lobe._eval(wo, wi), wo, wi)

    def _eval_pdf(self, wo, wi):
        f, pdf = self.lobe._eval_pdf(wo, wi)
        return self._tinted(f, wo, wi), pdf

    def _eval_pdf_t(self, wo, wi, throughput):
        f, pdf = self.lobe._eval_pdf_t(wo, wi, throughput)
        return self._tinted(f, wo, wi), pdf

    def _from_inner(self, sample, wo):
        refracted = (sample.flags & _T) != 0
        return BSDFSample(sample.wi, selected(refracted, scaled(sample.weight, self.tint),
                                              sample.weight), sample.pdf, sample.flags)

    # -- the energy: E_R + t E_T ----------------------------------------------------------
    def _split(self, E, E_R):
        return E_R + self.tint * np.maximum(E - E_R, 0.0)

    def _per_channel(self, parts):
        """Channel c of the c-th of ``parts`` (one part: itself)."""
        if len(parts) == 1:
            return parts[0]
        return np.stack([np.broadcast_to(p, np.broadcast_shapes(*(q.shape for q in parts)))
                         [..., c] for c, p in enumerate(parts)], axis=-1)

    def _seen(self, method, wo):
        """``method`` of the interface's reflection on the side of ``wo`` (from below: the
        reflection of index 1 / eta at the mirrored direction), per channel."""
        below = wo[..., 2] < 0.0
        up = weighted(wo, pick(below, -1.0, 1.0))
        parts = []
        for pair in self._reflections:
            above, under = (getattr(r, method)(up) for r in pair)
            parts.append(selected(below, under, above))
        return self._per_channel(parts)

    def _delta_albedo(self, wo):
        """A smooth interface reflects F(wo) (``DielectricReflection``'s delta, total
        internal reflection included) and refracts the rest of its delta energy; a
        pass-through only refracts."""
        return self._split(self.lobe._delta_albedo(wo), self._seen("_delta_albedo", wo))

    def _reflected(self, wo):
        """E_R(wo): the interface's reflection (its table, or its exact Fresnel where smooth)
        plus the Kulla–Conty term's reflected share."""
        single = self._seen("_top_albedo", wo)
        grazing = wo[..., 2] == 0.0
        multiple = [weighted(ms._albedo_table(wo, False)[0],
                             pick(grazing, 0.0, ms._reflect_probability(wo)))
                    for ms in self._multiple]
        return single + self._per_channel(multiple)

    def _albedo_table(self, wo, with_error=True):
        E, error = self.lobe._albedo_table(wo, with_error)
        return np.minimum(self._split(E, np.minimum(self._reflected(wo), E)), E), error

    def _top_albedo(self, wo):
        return self._albedo_table(wo, with_error=False)[0]

    def _albedo_quadrature(self, wo, tol):
        return quadrature.albedo(self, wo, tol=tol)
