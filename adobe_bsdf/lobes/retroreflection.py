"""Retroreflection: a reflection lobe mixed with its copy turned back towards the viewer,
f_R -> (1 - w) f_R(wo, wi) + w f_R(wo, reflect(wi, n)) [OpenPBR2026dev, §Retroreflectivity]."""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf.bsdf import Flags, Lobe, finished_sample
from adobe_bsdf.composition import Wrapper

__all__ = ["Retroreflective"]

_R, _DELTA = int(Flags.REFLECTION), int(Flags.DELTA)


def _turned(w):
    """reflect(w, n) = 2 (w.n) n - w of a direction about the normal: (-x, -y, z), the turn by
    pi about the normal."""
    return w * np.array([-1.0, -1.0, 1.0])


def _same_side(wo, wi):
    """Reflection pairs (by the signs: a subnormal cosine cannot underflow the test)."""
    zo, zi = wo[..., 2], wi[..., 2]
    return ((zo > 0.0) & (zi > 0.0)) | ((zo < 0.0) & (zi < 0.0))


class Retroreflective(Wrapper):
    """``lobe`` whose reflection is mixed with its retroreflective copy, transmission left as it
    is [OpenPBR2026dev, §Retroreflectivity]:

        f(wo, wi) = (1 - w) f_lobe(wo, wi) + w f_lobe(wo, R wi)   (wo, wi on one side),
        f(wo, wi) = f_lobe(wo, wi)                                 (across),

    R = reflect(., n) the turn by pi about the normal, w = specular_retroreflectivity: the
    copy's peak lies about wo instead of its mirror (w = 1: a glossy retroreflector).

    R keeps cosines and solid angles, so the albedo, the tables and the delta energy are the
    lobe's; the pdf is the same mixture of the lobe's pdfs, and sampling draws the copy with
    probability w (the first uniform, re-used). Reciprocity: for a lobe invariant under the
    turn of both directions (every GGX lobe, anisotropic included: the ellipse is symmetric
    under a turn by pi), f_lobe(wo, R wi) = f_lobe(R wo, wi) = f_lobe(wi, R wo), so the copy
    is reciprocal where the lobe is.

    Parameters
    ----------
    lobe : Lobe
    weight : array_like in [0, 1]
        w.
    """

    def __init__(self, lobe: Lobe, weight):
        if not isinstance(lobe, Lobe):
            raise ValueError(f"lobe = {lobe!r}: allowed a Lobe")
        self._init(lobe, _params.real("weight", weight, 0.0, 1.0))

    def _init(self, lobe, weight):
        self.lobe, self.weight = lobe, np.asarray(weight, dtype=np.float64)
        self.flags = lobe.flags

    def __repr__(self) -> str:
        return f"Retroreflective({self.lobe!r}, weight={self.weight!r})"

    def _inner(self):
        return self.lobe

    def _param_shape(self):
        shape = self.lobe._param_shape()
        return None if shape is None else np.broadcast_shapes(shape, self.weight.shape)

    def _mixed(self, wo, wi, plain, turned):
        """(1 - w) plain + w turned on reflection pairs, plain across (colours or densities)."""
        reflection = _same_side(wo, wi)
        w = self.weight
        if plain.ndim > reflection.ndim:  # colours
            reflection, w = reflection[..., None], w[..., None]
        return np.where(reflection, (1.0 - w) * plain + w * turned, plain)

    def _eval(self, wo, wi):
        return self._mixed(wo, wi, self.lobe._eval(wo, wi), self.lobe._eval(wo, _turned(wi)))

    def _pdf(self, wo, wi):
        return self._mixed(wo, wi, self.lobe._pdf(wo, wi), self.lobe._pdf(wo, _turned(wi)))

    def _pdf_t(self, wo, wi, throughput):
        return self._mixed(wo, wi, self.lobe._pdf_t(wo, wi, throughput),
                           self.lobe._pdf_t(wo, _turned(wi), throughput))

    def _eval_pdf(self, wo, wi):
        return self._eval_pdf_t(wo, wi, None)

    def _eval_pdf_t(self, wo, wi, throughput):
        if throughput is None:
            (f, p), (fr, pr) = (self.lobe._eval_pdf(wo, wi),
                                self.lobe._eval_pdf(wo, _turned(wi)))
        else:
            (f, p), (fr, pr) = (self.lobe._eval_pdf_t(wo, wi, throughput),
                                self.lobe._eval_pdf_t(wo, _turned(wi), throughput))
        return self._mixed(wo, wi, f, fr), self._mixed(wo, wi, p, pr)

    def _sample(self, wo, u):
        return self._sample_t(wo, u, None)

    def _sample_directions(self, wo, u, throughput):
        return self._sample_t(wo, u, throughput)

    def _sample_t(self, wo, u, throughput):
        """The lobe's sample, its reflections turned with probability w (the first uniform
        split at w and re-used); a glossy sample weighed by the mixture, f |cos| / pdf, a
        delta one keeping the lobe's weight with its probability times w or 1 - w."""
        w = np.broadcast_to(self.weight, u.shape[:-1])
        u0 = u[..., 0]
        copy = u0 < w
        with np.errstate(divide="ignore", invalid="ignore"):
            u0 = np.where(copy, u0 / np.where(w > 0.0, w, 1.0),
                          (u0 - w) / np.where(w < 1.0, 1.0 - w, 1.0))
        u = np.concatenate([np.minimum(u0, np.nextafter(1.0, 0.0))[..., None], u[..., 1:]], -1)
        s = (self.lobe._sample(wo, u) if throughput is None
             else self.lobe._sample_t(wo, u, throughput))
        reflected = (s.flags & _R) != 0
        delta = (s.flags & _DELTA) != 0
        turn = copy & reflected
        wi = np.where(turn[..., None], _turned(s.wi), s.wi)
        f, pdf = self._eval_pdf_t(wo, wi, throughput)
        with np.errstate(divide="ignore", invalid="ignore"):
            glossy = f * (np.abs(wi[..., 2]) / np.where(pdf > 0.0, pdf, 1.0))[..., None]
        share = np.where(reflected, np.where(turn, w, 1.0 - w), 1.0)
        weight = np.where(delta[..., None], s.weight, glossy)
        pdf = np.where(delta, s.pdf * share, pdf)
        return finished_sample(wi, weight, pdf, s.flags)
