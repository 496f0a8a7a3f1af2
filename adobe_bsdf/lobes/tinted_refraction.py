"""A rough dielectric whose refracted light is tinted, and optionally its reflection:
f = r f_R + t f_T."""

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

_T, _REFLECTED = int(Flags.TRANSMISSION), int(Flags.REFLECTION)


class TintedRefraction(Wrapper):
    """``DielectricMS`` (or ``DispersiveMS``, channel by channel) with every refraction
    multiplied by the colour ``tint``, f = r f_R + t f_T: a constant tint on the refraction
    of an interface with no medium behind it [OpenPBR2026, §Translucent base]; t = 1 is the
    lobe. The reflection is multiplied by ``reflection_tint`` r, from above only ("the first
    reflection from above" [OpenPBR2026, §Dielectric base]) or, with ``reflection_below``,
    from both sides (the whole BRDF [OpenPBR2026dev, §Dielectric base]); r = 1 leaves it.

    Refraction pairs and refracted samples are multiplied by t, reflection pairs (both
    directions on one side) and reflected samples by r where it applies; pdfs and sampled
    directions are the lobe's, so sampling stays exact. The energy splits into what the lobe
    reflects, E_R, and what it refracts, E_T: E = r E_R + t E_T, with E_R the
    single-scattering reflection of the
    interface (``DielectricReflection`` of the same index and microfacets: its tables, or its
    exact Fresnel where smooth) plus the Kulla–Conty term's reflected share (its reflection
    probability times its albedo 1 - E_s), and E_T the rest of the lobe's albedo. A tint
    <= 1 never adds energy; the tinted lobe is reciprocal where the lobe is (t multiplies
    both directions of a refraction pair alike, r both of a reflection pair; r from above
    only tints the pairs above, which are each other's reverse).

    Parameters
    ----------
    lobe : DielectricMS or DispersiveMS
    tint : colour in [0, 1]
    reflection_tint : colour in [0, 1]
    reflection_below : bool
    """

    def __init__(self, lobe: DielectricMS | DispersiveMS, tint, reflection_tint=1.0,
                 reflection_below: bool = False):
        if not isinstance(lobe, (DielectricMS, DispersiveMS)):
            raise ValueError(f"lobe = {lobe!r}: allowed a DielectricMS or a DispersiveMS")
        self._init(lobe, _params.color("tint", tint, 0.0, 1.0),
                   _params.color("reflection_tint", reflection_tint, 0.0, 1.0),
                   bool(reflection_below))

    def _init(self, lobe, tint, reflection_tint=None, reflection_below=False):
        self.lobe, self.tint = lobe, tint
        #: r (None: 1, the reflection untouched) and whether it tints from below too
        self.reflection_tint = (None if reflection_tint is None
                                or not np.any(np.asarray(reflection_tint) != 1.0)
                                else np.asarray(reflection_tint, dtype=np.float64))
        self.reflection_below = reflection_below
        self.flags = lobe.flags
        single = lobe.components[0]
        #: the interface's thin film (``Dielectric(film=)``), or None
        self._single = single if getattr(single, "film", None) is not None else None
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
        extra = ("" if self.reflection_tint is None else
                 f", reflection_tint={self.reflection_tint!r}, "
                 f"reflection_below={self.reflection_below}")
        return f"TintedRefraction({self.lobe!r}, tint={self.tint!r}{extra})"

    def _inner(self):
        return self.lobe

    def _param_shape(self):
        shape = self.lobe._param_shape()
        if shape is None:
            return None
        r = () if self.reflection_tint is None else self.reflection_tint.shape[:-1]
        return np.broadcast_shapes(shape, self.tint.shape[:-1], r)

    # -- f: the tints on refraction and reflection pairs ----------------------------------
    def _reflection_tinted(self, wo):
        """Where a reflection at ``wo`` is tinted by r: every side, or wo above."""
        return np.full(wo.shape[:-1], True) if self.reflection_below else wo[..., 2] > 0.0

    def _tinted(self, f, wo, wi):
        zo, zi = wo[..., 2], wi[..., 2]
        across = ((zo < 0.0) != (zi < 0.0)) & (zo != 0.0) & (zi != 0.0)  # signs: no underflow
        out = selected(across, scaled(f, self.tint), f)
        if self.reflection_tint is None:
            return out
        return np.where((~across & self._reflection_tinted(wo))[..., None],
                        out * self.reflection_tint, out)

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
        weight = selected(refracted, scaled(sample.weight, self.tint), sample.weight)
        if self.reflection_tint is not None:
            reflected = ((sample.flags & _REFLECTED) != 0) & self._reflection_tinted(wo)
            weight = np.where(reflected[..., None], weight * self.reflection_tint, weight)
        return BSDFSample(sample.wi, weight, sample.pdf, sample.flags)

    # -- the energy: r E_R + t E_T --------------------------------------------------------
    def _split(self, E, E_R, wo):
        E_T = self.tint * np.maximum(E - E_R, 0.0)
        if self.reflection_tint is None:
            return E_R + E_T
        r = np.where(self._reflection_tinted(wo)[..., None], self.reflection_tint, 1.0)
        return r * E_R + E_T

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
        return self._split(self.lobe._delta_albedo(wo),
                           self._filmed(self._seen("_delta_albedo", wo), wo), wo)

    def _filmed(self, reflected, wo):
        """``reflected`` with the film's reflectance in place of F where the interface is
        smooth (no change without a film)."""
        if self._single is None:
            return reflected
        smooth = (np.broadcast_to(self._single.distribution.smooth, wo.shape[:-1])
                  & (wo[..., 2] != 0.0))
        return np.where(smooth[..., None], self._single.film_reflectance(wo), reflected)

    def _reflected(self, wo):
        """E_R(wo): the interface's reflection (its table, or its exact Fresnel where smooth;
        with a film, plus the film's Delta_R, ``film_energy.FilmEnergy``) plus the
        Kulla–Conty term's reflected share."""
        single = self._filmed(self._seen("_top_albedo", wo), wo)
        grazing = wo[..., 2] == 0.0
        energy = None if self._single is None else self._single.film_energy()
        if energy is not None:  # the film's change of the reflected energy, Delta_R
            light = (wo[..., 2] > 0.0) == (self._single.eta >= 1.0)
            single = single + np.where(grazing[..., None], 0.0,
                                       energy(np.abs(wo[..., 2]), light, reflected=True))
        multiple = [weighted(ms._albedo_table(wo, False)[0],
                             pick(grazing, 0.0, ms._reflect_probability(wo)))
                    for ms in self._multiple]
        return single + self._per_channel(multiple)

    def _albedo_table(self, wo, with_error=True):
        E, error = self.lobe._albedo_table(wo, with_error)
        return np.minimum(self._split(E, np.minimum(self._reflected(wo), E), wo), E), error

    def _top_albedo(self, wo):
        return self._albedo_table(wo, with_error=False)[0]

    def _albedo_quadrature(self, wo, tol):
        return quadrature.albedo(self, wo, tol=tol)
