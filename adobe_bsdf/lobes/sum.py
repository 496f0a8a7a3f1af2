"""Weighted sum of lobes, sampled as a mixture; zero-weight lobes cost nothing."""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf.bsdf import BSDFSample, Flags, Lobe, finished_sample, luminance
from adobe_bsdf.registry import CheckCase, register

__all__ = ["Sum", "choose", "sample_where"]


class Sum(Lobe):
    """f = sum_k w_k f_k of lobes that share one surface (and, for transmission, one
    interface).

    Parameters
    ----------
    *components : Lobe
    weights : sequence of colours in [0, inf), optional
        One weight w_k per component (scalar or ``(..., 3)``, a texture allowed); default 1.
        A component whose weight is 0 everywhere is dropped at construction: it is never
        evaluated or sampled (``components`` holds the active ones only).

    Notes
    -----
    Sampling picks component k with probability P_k(wo) proportional to
    lum(w_k) ``_sampling_weight_k(wo)`` (an albedo estimate), samples it, and weighs a
    non-delta sample by the whole sum, weight = f |cos| / pdf with pdf = sum_k P_k pdf_k (the
    one-sample balance heuristic, Veach 1997 §9.2.4), so ``pdf`` and ``sample`` agree
    whatever the estimates. A delta sample of component k has probability P_k times its
    own. The first uniform is re-used inside the chosen interval, so components that branch
    on it (the dielectric's reflect/refract choice) stay stratified. Where a component's
    parameters are scalars, it is sampled only for the elements that chose it.
    """

    def __init__(self, *components: Lobe, weights=None):
        if not all(isinstance(c, Lobe) for c in components):
            raise ValueError(f"components = {components!r}: a Sum takes lobes")
        if weights is None:
            weights = [None] * len(components)
        elif len(weights) != len(components):
            raise ValueError(f"weights has {len(weights)} entries for {len(components)} "
                             "components; allowed: one weight per component")
        else:
            weights = [_params.color("weights", w, 0.0, np.inf) for w in weights]
        active = [(c, w) for c, w in zip(components, weights, strict=True)
                  if w is None or np.any(w != 0.0)]
        self.components = tuple(c for c, _ in active)
        #: the active components' weights (None: 1)
        self.weights = tuple(w for _, w in active)
        flags = Flags.NONE
        for c in self.components:
            flags |= c.flags
        self.flags = flags

    def __repr__(self) -> str:
        parts = [repr(c) if w is None else f"{w!r} * {c!r}"
                 for c, w in zip(self.components, self.weights, strict=True)]
        return f"{type(self).__name__}({', '.join(parts)})"

    def _param_shape(self):
        shapes = [c._param_shape() for c in self.components]
        if any(s is None for s in shapes):
            return None
        shapes += [w.shape[:-1] for w in self.weights if w is not None]
        return np.broadcast_shapes(*shapes)

    def _terms(self, method, *args):
        """Weighted per-component results of ``method`` (a colour-valued private method)."""
        for c, w in zip(self.components, self.weights, strict=True):
            value = getattr(c, method)(*args)
            yield value if w is None else value * w

    @staticmethod
    def _total(parts, shape):
        total = None
        for p in parts:
            total = p if total is None else total + p
        return np.zeros(shape) if total is None else total

    def _probabilities(self, wo):
        w = [c._sampling_weight(wo) * (1.0 if k is None else luminance(k))
             for c, k in zip(self.components, self.weights, strict=True)]
        w = np.stack(np.broadcast_arrays(*w))
        total = w.sum(axis=0)
        return np.where(total > 0.0, w / np.where(total > 0.0, total, 1.0), 1.0 / len(w))

    def _batch(self, wo, wi):
        return np.broadcast_shapes(wo.shape, wi.shape)[:-1]

    def _eval(self, wo, wi):
        return self._total(self._terms("_eval", wo, wi), self._batch(wo, wi) + (3,))

    def _pdf(self, wo, wi):
        return self._pdf_t(wo, wi, None)

    def _pdf_t(self, wo, wi, throughput):
        if not self.components:
            return np.zeros(self._batch(wo, wi))
        P = self._probabilities(wo)
        return sum(P[k] * c._pdf_t(wo, wi, throughput) for k, c in enumerate(self.components))

    def _eval_pdf(self, wo, wi):
        return self._eval_pdf_t(wo, wi, None)

    def _eval_pdf_t(self, wo, wi, throughput):
        if not self.components:
            batch = self._batch(wo, wi)
            return np.zeros(batch + (3,)), np.zeros(batch)
        P = self._probabilities(wo)
        f, pdf = None, None
        for k, (c, w) in enumerate(zip(self.components, self.weights, strict=True)):
            fk, pk = c._eval_pdf_t(wo, wi, throughput)
            fk = fk if w is None else fk * w
            f = fk if f is None else f + fk
            pdf = P[k] * pk if pdf is None else pdf + P[k] * pk
        return f, pdf

    def _sample(self, wo, u):
        return self._sample_t(wo, u, None)

    def _sample_t(self, wo, u, throughput):
        batch = np.broadcast_shapes(wo.shape, u.shape)[:-1]
        if not self.components:
            return BSDFSample(np.zeros(batch + (3,)), np.zeros(batch + (3,)), np.zeros(batch),
                              np.full(batch, int(Flags.NONE)))
        wo = np.broadcast_to(wo, batch + (3,))  # one wo for a batch of uniforms
        k, Pk, u = choose(self._probabilities(wo), u)
        wi = np.zeros(batch + (3,))
        weight = np.zeros(batch + (3,))
        pdf = np.zeros(batch)
        flags = np.full(batch, int(Flags.NONE))
        for j, w in enumerate(self.weights):
            chosen = k == j
            s = sample_where(self.components[j], wo, u, throughput, chosen)
            sw = s.weight if w is None else s.weight * w
            wi = np.where(chosen[..., None], s.wi, wi)
            weight = np.where(chosen[..., None], sw, weight)
            pdf = np.where(chosen, s.pdf, pdf)
            flags = np.where(chosen, s.flags, flags)
        delta = (flags & int(Flags.DELTA)) != 0
        f, mix_pdf = self._eval_pdf_t(wo, wi, throughput)
        smooth_weight = f * np.abs(wi[..., 2:3]) / np.where(mix_pdf > 0.0, mix_pdf, 1.0)[..., None]
        weight = np.where(delta[..., None], weight / np.where(Pk > 0, Pk, 1.0)[..., None],
                          np.where((mix_pdf > 0.0)[..., None], smooth_weight, 0.0))
        return finished_sample(wi, weight, np.where(delta, Pk * pdf, mix_pdf), flags)

    def _delta_albedo(self, wo):
        return self._total(self._terms("_delta_albedo", wo), wo.shape[:-1] + (3,))

    @property
    def eta(self):
        """The shared interface's index (for generalized reciprocity): the transmitting
        component's, else None."""
        return getattr(self._interface(), "eta", None)

    @property
    def eta_per_channel(self) -> bool:
        return getattr(self._interface(), "eta_per_channel", False)

    def _interface(self) -> Lobe:
        """The component whose interface sets the energy scale: the first that transmits
        (the components share one interface), else any."""
        for c in self.components:
            if c.flags & Flags.TRANSMISSION:
                return c
        return self.components[0] if self.components else Lobe()

    def _energy_scale(self, wo, wi):
        return self._interface()._energy_scale(wo, wi)

    def _energy_scale_rgb(self, wo, wi):
        return self._interface()._energy_scale_rgb(wo, wi)

    def _albedo_table(self, wo, with_error=True):
        values, errors = [], []
        for c, w in zip(self.components, self.weights, strict=True):
            value, error = c._albedo_table(wo, with_error)
            values.append(value if w is None else value * w)
            errors.append(error if w is None or error is None else error * w)
        shape = wo.shape[:-1] + (3,)
        return (self._total(values, shape),
                self._total(errors, shape) if with_error else None)

    def _sampling_weight(self, wo):
        if not self.components:
            return np.zeros(wo.shape[:-1])
        return sum(c._sampling_weight(wo) * (1.0 if w is None else luminance(w))
                   for c, w in zip(self.components, self.weights, strict=True))


def choose(P, u):
    """Pick component k with probability ``P[k]`` (``P`` (K, ...), summing to 1 over its
    first axis) by the first uniform of ``u`` (..., 3), and re-use that uniform inside the
    chosen interval (so a component that branches on it stays stratified).

    Returns ``(k (...), P_k (...), u (..., 3))``, broadcast over ``P.shape[1:]`` and
    ``u.shape[:-1]``.
    """
    batch = np.broadcast_shapes(P.shape[1:], u.shape[:-1])
    P = np.broadcast_to(P, P.shape[:1] + batch)
    cdf = np.cumsum(P, axis=0)
    k = np.minimum((u[..., 0] >= cdf[:-1]).sum(axis=0), len(P) - 1)
    lo = np.where(k > 0, np.take_along_axis(cdf, np.maximum(k - 1, 0)[None], 0)[0], 0.0)
    Pk = np.take_along_axis(P, k[None], 0)[0]
    u0 = np.clip((u[..., 0] - lo) / np.where(Pk > 0.0, Pk, 1.0), 0.0, np.nextafter(1.0, 0))
    u = np.concatenate([u0[..., None], np.broadcast_to(u[..., 1:], batch + (2,))], axis=-1)
    return k, Pk, u


def sample_where(lobe: Lobe, wo, u, throughput, chosen) -> BSDFSample:
    """``lobe._sample_t(wo, u, throughput)`` computed for the elements ``chosen`` only (for
    all of them if the lobe's parameters are not scalars or the batch is not flat), scattered
    into full-size arrays (zero elsewhere)."""
    if lobe._param_shape() != () or wo.ndim != 2 or u.ndim != 2:
        return lobe._sample_t(wo, u, throughput)
    index = np.flatnonzero(chosen)
    if throughput is not None:
        throughput = np.broadcast_to(throughput, u.shape)[index]
    part = lobe._sample_t(np.broadcast_to(wo, u.shape)[index], u[index], throughput)
    n = u.shape[0]
    full = []
    for field in part:
        out = np.zeros((n,) + field.shape[1:], dtype=field.dtype)
        out[index] = field
        full.append(out)
    return BSDFSample(*full)


def _weighted_example():
    from adobe_bsdf.lobes.conductor import Conductor
    from adobe_bsdf.lobes.lambert import Lambert

    return Sum(Lambert(), Conductor(0.2), Conductor(0.6, 0.1),
               weights=[(0.3, 0.2, 0.1), 0.0, (0.7, 0.8, 0.9)])


register(CheckCase("Sum 0.3 Lambert + 0 + 0.7 Conductor a=(0.6,0.1)", _weighted_example))
