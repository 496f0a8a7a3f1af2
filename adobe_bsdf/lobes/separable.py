"""Separable lobes f(wo, wi) = c X(wo) X(wi), cosine-sampled: the form shared by the
energy-conserving diffuse [Kutz2021, §1.1] and the Kulla–Conty multiple-scattering terms
[KullaConty2017]."""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _memo
from adobe_bsdf._channels import pick, tinted, weighted
from adobe_bsdf.bsdf import Flags, Lobe, finished_sample, on_support
from adobe_bsdf.lobes.dielectric import _mirror_z
from adobe_bsdf.sampling import cosine_hemisphere

__all__ = ["Separable"]


class Separable(Lobe):
    """f(wo, wi) = c(wo, wi) X(wo) X(wi), with c constant on each pair of sides.

    Subclasses give ``_X(w) -> (...)`` and ``_coefficient(wo, wi) -> (..., 3)``; a two-sided
    lobe (``two_sided = True``) also gives ``_reflect_probability(wo)``, the chance that
    ``sample`` stays on the side of ``wo``. ``wi`` is cosine-distributed on the chosen side,
    so pdf = P(side) |cos theta_i| / pi exactly. A one-sided lobe is 0 unless both
    directions are above the surface.
    """

    two_sided = False

    def _X(self, w):  # pragma: no cover - abstract
        raise NotImplementedError

    def _coefficient(self, wo, wi):  # pragma: no cover - abstract
        raise NotImplementedError

    def _X_at(self, w):
        """``_X(w)``, once per call for this ``w`` (``_memo``): the sampling weight and f at
        ``wo`` both need X(wo)."""
        return _memo.once(self, "X", w, self._X)

    def _reflect_probability(self, wo):
        return np.ones(wo.shape[:-1])

    def _support(self, wo, wi):
        if self.two_sided:
            return (wo[..., 2] != 0.0) & (wi[..., 2] != 0.0)
        return (wo[..., 2] > 0.0) & (wi[..., 2] > 0.0)

    def _eval(self, wo, wi):
        # X(wo) X(wi) on the support only (``on_support``: the tables are not looked up
        # where f is 0), 0 elsewhere
        g = on_support(self._g, self._support(wo, wi), wo, wi,
                       compact=self._param_shape() == ())
        return tinted(g, self._coefficient(wo, wi))  # c >= 0 finite: c 0 = 0 off the support

    def _g(self, wo, wi, up):
        """X(wo) X(wi), 0 outside ``up`` (None: every pair is in the support)."""
        g = self._X_at(wo) * self._X_at(wi)
        return g if up is None else pick(up, g, 0.0)

    def _pdf(self, wo, wi):
        p_r = self._reflect_probability(wo)
        p = pick(wo[..., 2] * wi[..., 2] > 0.0, p_r, 1.0 - p_r)
        return pick(self._support(wo, wi), p * np.abs(wi[..., 2]) / np.pi, 0.0)

    def _sample(self, wo, u):
        return self._drawn(wo, u, weigh=True)

    def _sample_directions(self, wo, u, throughput):
        return self._drawn(wo, u, weigh=False)

    def _drawn(self, wo, u, weigh: bool):
        """The sample; without ``weigh`` its weight is 0 (``_sample_directions``)."""
        local = cosine_hemisphere(u[..., 1:3])
        stay = u[..., 0] < self._reflect_probability(wo)
        side = pick(wo[..., 2] < 0.0, -1.0, 1.0) * pick(stay, 1.0, -1.0)
        wi = _mirror_z(local, side)
        pdf = self._pdf(wo, wi)
        ok = pdf > 0.0
        weight = (weighted(self._eval(wo, wi), np.abs(wi[..., 2]) / pick(ok, pdf, 1.0))
                  if weigh else None)
        flags = int(Flags.DIFFUSE) | pick(wo[..., 2] * wi[..., 2] > 0.0,
                                              int(Flags.REFLECTION), int(Flags.TRANSMISSION))
        if weigh:
            pdf = np.broadcast_to(pdf, weight.shape[:-1])
        return finished_sample(wi, weight, pdf, np.broadcast_to(flags, np.broadcast_shapes(
            flags.shape, pdf.shape)))
