"""Layering by albedo scaling: a lobe on top of another that never adds energy.

Public API
----------
``Layer(top, base, coverage=1, transmittance=None)``
    f = c f_top + W(wo, wi) f_base with W = (1 - c) + c t(wo) t(wi) (1 - E_top(wo)).

This is the non-reciprocal albedo scaling of OpenPBR (seed 003, section Layering, the
"general albedo scaling" equation, with a coverage c as its v1.1.1 writes it) and of the ASM's
sheen and coat (seed 000 §6-7): the energy the top layer reflects, E_top(wo), is taken from
what reaches the base, and t(w) is a one-way transmittance of the top layer's medium (the
coat's absorption). With E_top, E_base <= 1 and t <= 1,

    E(wo) = c E_top + (1 - c) E_base + c t(wo) (1 - E_top) int t(wi) f_base |cos| <= 1,

and with a white base and t = 1 the layer keeps all the energy (the white furnace).

Why not the reciprocal form ``C (1 - E_top(wi)) (1 - E_top(wo)) f_base`` (seed 003)? Its
normalisation C is an integral of the base BSDF weighted by 1 - E_top, a new table for every
base: the ASM's "albedo scaling technique" and OpenPBR both use the form above. Its
non-reciprocity, f(wo, wi) - f(wi, wo) = c t t (E_top(wi) - E_top(wo)) f_base, is measured in
``docs/asm_measured.md``.
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf.bsdf import Flags, Lobe, Wrapper, finished_sample, luminance
from adobe_bsdf.lobes.sum import choose, sample_where

__all__ = ["Layer"]


class Layer(Wrapper):
    """``top`` over ``base`` by albedo scaling (module docstring).

    Parameters
    ----------
    top, base : Lobe
        E_top(wo) is the top's ``_top_albedo`` on every call: its albedo tables, or where
        they would underestimate (an anisotropic coat), a quadrature.
    coverage : array_like in [0, 1]
        c, how much of the surface the top layer covers (the ASM coat's opacity).
    transmittance : callable or None
        ``transmittance(w) -> (..., 3)``, t(w) in [0, 1]; None is 1.

    Notes
    -----
    Sampling picks the top with probability proportional to c lum(E_top(wo)) and the base
    with lum(W(wo, wo')) times the base's albedo estimate (wo' the mirror of wo), and weighs
    non-delta samples by the one-sample balance heuristic, as ``Sum``. The base's delta
    branches (a smooth interface) carry W at their own direction; their closed-form energy
    (``albedo``) uses t(wi) = t(wo), exact for mirror reflection. The table albedo makes the
    same approximation for the base's whole lobe; it is exact where t = 1.
    """

    def __init__(self, top: Lobe, base: Lobe, coverage=1.0, transmittance=None):
        if not isinstance(top, Lobe) or not isinstance(base, Lobe):
            raise ValueError(f"top = {top!r}, base = {base!r}: a Layer takes two lobes")
        if transmittance is not None and not callable(transmittance):
            raise ValueError(f"transmittance = {transmittance!r}: allowed None or a callable")
        self.top, self.base = top, base
        self.coverage = _params.real("coverage", coverage, 0.0, 1.0)
        self.transmittance = transmittance
        self.flags = top.flags | base.flags

    def __repr__(self) -> str:
        return f"Layer({self.top!r}, {self.base!r}, coverage={self.coverage!r})"

    def _inner(self):
        return self.base  # the interface is the base's: the top reflects only

    def exit_weight(self, wo):
        """(1 - c) + c t(wo) (1 - E_top(wo)) ``(..., 3)``: the share of light leaving the base
        towards ``wo`` that passes the top layer once (emission from below it)."""
        return (1.0 - self.coverage)[..., None] + self._scaled(wo)[0]

    def _param_shape(self):
        shapes = (self.top._param_shape(), self.base._param_shape())
        if any(s is None for s in shapes) or self.transmittance is not None:
            return None
        return np.broadcast_shapes(*shapes, self.coverage.shape)

    # -- the weights ------------------------------------------------------------------------
    def _t(self, w):
        return 1.0 if self.transmittance is None else self.transmittance(w)

    def _scaled(self, wo):
        """c t(wo) (1 - E_top(wo)) ``(..., 3)`` and E_top(wo)."""
        E_top = self.top._top_albedo(wo)
        return self.coverage[..., None] * self._t(wo) * (1.0 - E_top), E_top

    def _weight(self, wo, wi, scaled):
        """W(wo, wi) = (1 - c) + c t(wo) t(wi) (1 - E_top(wo)), ``(..., 3)``."""
        return (1.0 - self.coverage)[..., None] + scaled * self._t(wi)

    def _probabilities(self, wo, scaled, E_top):
        top = np.asarray(self.coverage * luminance(E_top))
        base = luminance(self._weight(wo, wo, scaled)) * self.base._sampling_weight(wo)
        top, base = np.broadcast_arrays(top, base)
        total = top + base
        P_top = np.where(total > 0.0, top / np.where(total > 0.0, total, 1.0), 0.5)
        return np.stack([P_top, 1.0 - P_top])

    # -- protocol ---------------------------------------------------------------------------
    def _eval(self, wo, wi):
        scaled, _ = self._scaled(wo)
        return (self.coverage[..., None] * self.top._eval(wo, wi)
                + self._weight(wo, wi, scaled) * self.base._eval(wo, wi))

    def _pdf(self, wo, wi):
        return self._pdf_t(wo, wi, None)

    def _eval_pdf(self, wo, wi):
        return self._eval_pdf_t(wo, wi, None)

    def _pdf_t(self, wo, wi, throughput):
        P = self._probabilities(wo, *self._scaled(wo))
        return (P[0] * self.top._pdf_t(wo, wi, throughput)
                + P[1] * self.base._pdf_t(wo, wi, throughput))

    def _eval_pdf_t(self, wo, wi, throughput, scaled_top=None):
        """(f, pdf); ``scaled_top`` is ``_scaled(wo)`` where the caller has it already (the
        top's albedo can be a quadrature per direction: an anisotropic coat)."""
        scaled, E_top = self._scaled(wo) if scaled_top is None else scaled_top
        P = self._probabilities(wo, scaled, E_top)
        f_top, p_top = self.top._eval_pdf_t(wo, wi, throughput)
        f_base, p_base = self.base._eval_pdf_t(wo, wi, throughput)
        f = self.coverage[..., None] * f_top + self._weight(wo, wi, scaled) * f_base
        return f, P[0] * p_top + P[1] * p_base

    def _sample(self, wo, u):
        return self._sample_t(wo, u, None)

    def _sample_t(self, wo, u, throughput):
        batch = np.broadcast_shapes(wo.shape, u.shape)[:-1]
        wo = np.broadcast_to(wo, batch + (3,))
        scaled, E_top = self._scaled(wo)
        k, P_k, u = choose(self._probabilities(wo, scaled, E_top), u)
        s_top = sample_where(self.top, wo, u, throughput, k == 0)
        s_base = sample_where(self.base, wo, u, throughput, k == 1)
        top = (k == 0)[..., None]
        wi = np.where(top, s_top.wi, s_base.wi)
        flags = np.where(k == 0, s_top.flags, s_base.flags)
        delta = (flags & int(Flags.DELTA)) != 0
        f, pdf = self._eval_pdf_t(wo, wi, throughput, (scaled, E_top))
        with np.errstate(divide="ignore", invalid="ignore"):
            weight = f * np.abs(wi[..., 2:3]) / pdf[..., None]
            own = np.where(top, self.coverage[..., None] * s_top.weight,
                           self._weight(wo, wi, scaled) * s_base.weight) / P_k[..., None]
        weight = np.where(delta[..., None], own, weight)
        pdf = np.where(delta, P_k * np.where(k == 0, s_top.pdf, s_base.pdf), pdf)
        return finished_sample(wi, weight, pdf, flags)

    def _delta_albedo(self, wo):
        scaled, _ = self._scaled(wo)
        return (self.coverage[..., None] * self.top._delta_albedo(wo)
                + self._weight(wo, wo, scaled) * self.base._delta_albedo(wo))

    def _albedo_table(self, wo, with_error=True):
        E_top, err_top = self.top._albedo_table(wo, with_error)
        E_base, err_base = self.base._albedo_table(wo, with_error)
        c = self.coverage[..., None]
        W = (1.0 - c) + c * self._t(wo) ** 2 * (1.0 - E_top)
        value = c * E_top + W * E_base
        # |d value / d E_top| = c |1 - t^2 E_base| <= c
        return value, (c * err_top + W * err_base) if with_error else None

    def _sampling_weight(self, wo):
        scaled, E_top = self._scaled(wo)
        return (self.coverage * luminance(E_top)
                + luminance(self._weight(wo, wo, scaled)) * self.base._sampling_weight(wo))

    def _energy_scale(self, wo, wi):
        return self.base._energy_scale(wo, wi)  # the top reflects only

    def _energy_scale_rgb(self, wo, wi):
        return self.base._energy_scale_rgb(wo, wi)
