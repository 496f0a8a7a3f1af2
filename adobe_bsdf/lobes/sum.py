"""Sum of lobes, sampled as a one-sample mixture."""

from __future__ import annotations

import numpy as np

from adobe_bsdf.bsdf import BSDFSample, Flags, Lobe

__all__ = ["Sum"]


class Sum(Lobe):
    """f = sum_k f_k of lobes that share one surface (and, for transmission, one interface).

    Sampling picks component k with probability P_k(wo) proportional to its
    ``_sampling_weight(wo)`` (an albedo estimate), samples it, and weighs a non-delta sample
    by the whole sum, weight = f |cos| / pdf with pdf = sum_k P_k pdf_k (the one-sample
    balance heuristic, Veach 1997 §9.2.4), so ``pdf`` and ``sample`` agree whatever the
    estimates. A delta sample of component k has probability P_k times its own. The first
    uniform is re-used inside the chosen interval, so components that branch on it (the
    dielectric's reflect/refract choice) stay stratified.
    """

    def __init__(self, *components: Lobe):
        if not components or not all(isinstance(c, Lobe) for c in components):
            raise ValueError(f"components = {components!r}: a Sum needs one or more lobes")
        self.components = components
        flags = Flags.NONE
        for c in components:
            flags |= c.flags
        self.flags = flags

    def __repr__(self) -> str:
        return f"{type(self).__name__}({', '.join(map(repr, self.components))})"

    def _probabilities(self, wo):
        w = np.stack(np.broadcast_arrays(*(c._sampling_weight(wo) for c in self.components)))
        total = w.sum(axis=0)
        return np.where(total > 0.0, w / np.where(total > 0.0, total, 1.0), 1.0 / len(w))

    def _eval(self, wo, wi):
        return sum(c._eval(wo, wi) for c in self.components)

    def _pdf(self, wo, wi):
        P = self._probabilities(wo)
        return sum(P[k] * c._pdf(wo, wi) for k, c in enumerate(self.components))

    def _sample(self, wo, u):
        P = self._probabilities(wo)
        P = np.broadcast_to(P, P.shape[:1] + np.broadcast_shapes(P.shape[1:], u.shape[:-1]))
        cdf = np.cumsum(P, axis=0)
        k = np.minimum((u[..., 0] >= cdf[:-1]).sum(axis=0), len(self.components) - 1)
        lo = np.where(k > 0, np.take_along_axis(cdf, np.maximum(k - 1, 0)[None], 0)[0], 0.0)
        Pk = np.take_along_axis(P, k[None], 0)[0]
        u0 = np.clip((u[..., 0] - lo) / np.where(Pk > 0.0, Pk, 1.0), 0.0, np.nextafter(1.0, 0))
        u = np.concatenate([u0[..., None], u[..., 1:]], axis=-1)
        samples = [c._sample(wo, u) for c in self.components]
        pick = [k == j for j in range(len(samples))]

        def choose(field):
            return sum(np.where(p[..., None] if getattr(s, field).ndim > p.ndim else p,
                                getattr(s, field), 0) for p, s in zip(pick, samples,
                                                                      strict=True))

        wi, weight, pdf, flags = (choose(f) for f in ("wi", "weight", "pdf", "flags"))
        delta = (flags & int(Flags.DELTA)) != 0
        ok = flags != int(Flags.NONE)
        mix_pdf = self._pdf(wo, wi)
        f = self._eval(wo, wi)
        smooth_weight = f * np.abs(wi[..., 2:3]) / np.where(mix_pdf > 0.0, mix_pdf, 1.0)[..., None]
        weight = np.where(delta[..., None], weight / np.where(Pk > 0, Pk, 1.0)[..., None],
                          np.where((mix_pdf > 0.0)[..., None], smooth_weight, 0.0))
        pdf = np.where(delta, Pk * pdf, mix_pdf)
        ok = ok & (pdf > 0.0)
        return BSDFSample(
            wi=np.where(ok[..., None], wi, 0.0),
            weight=np.where(ok[..., None], weight, 0.0),
            pdf=np.where(ok, pdf, 0.0),
            flags=np.where(ok, flags, int(Flags.NONE)),
        )

    def _delta_albedo(self, wo):
        return sum(c._delta_albedo(wo) for c in self.components)

    def _energy_scale(self, wo, wi):
        return self.components[0]._energy_scale(wo, wi)

    def _albedo_table(self, wo):
        parts = [c._albedo_table(wo) for c in self.components]
        return sum(p[0] for p in parts), sum(p[1] for p in parts)

    def _sampling_weight(self, wo):
        return sum(c._sampling_weight(wo) for c in self.components)
