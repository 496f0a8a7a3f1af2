"""Rough conductor: GGX microfacet reflection with any Fresnel model."""

from __future__ import annotations

from functools import partial

import numpy as np

from adobe_bsdf import fresnel
from adobe_bsdf.bsdf import BSDFSample, Flags, Lobe, luminance
from adobe_bsdf.frame import dot, normalize, reflect
from adobe_bsdf.lobes.energy_lookup import conductor_energy
from adobe_bsdf.microfacet import GGX
from adobe_bsdf.registry import CheckCase, register

__all__ = ["Conductor"]


class Conductor(Lobe):
    """Microfacet reflection f = F(wo.h) D(h) G2(wo, wi) / (4 |cos o| |cos i|).

    Walter et al. 2007 eq. 20 with the anisotropic GGX of ``adobe_bsdf.microfacet``; sampled
    by visible normals (weight F G2 / G1(wo)). One-sided: 0 unless both directions are
    above the surface. Where both alphas are below ``ALPHA_MIN`` it is a perfect mirror (a
    delta lobe with weight F(cos theta_o)).

    Parameters
    ----------
    alpha_x, alpha_y : array_like in [0, inf)
        GGX roughness along the tangent and the bitangent (``alpha_y`` defaults to ``alpha_x``).
    fresnel : callable or None
        ``fresnel(cos_theta) -> (..., 3)`` or ``(...)``, e.g.
        ``functools.partial(ab.fresnel.conductor, eta=eta, k=k)``; ``None`` is F = 1.
    masking : {"correlated", "separable"}
        See ``GGX``.
    """

    flags = Flags.REFLECTION | Flags.GLOSSY | Flags.DELTA

    def __init__(self, alpha_x, alpha_y=None, fresnel=None, masking: str = "correlated"):
        if fresnel is not None and not callable(fresnel):
            raise ValueError(f"fresnel = {fresnel!r} is not callable (allowed: None or a "
                             "callable cos_theta -> reflectance)")
        self.distribution = GGX(alpha_x, alpha_y, masking)
        self.fresnel = fresnel

    def __repr__(self) -> str:
        d = self.distribution
        return (f"Conductor(alpha_x={d.alpha_x}, alpha_y={d.alpha_y}, "
                f"fresnel={self.fresnel!r}, masking={d.masking!r})")

    def _F(self, cos_theta):
        if self.fresnel is None:
            return np.ones(np.shape(cos_theta) + (3,))
        value = np.asarray(self.fresnel(cos_theta), dtype=np.float64)
        if value.shape == np.shape(cos_theta):
            value = value[..., None]
        return np.broadcast_to(value, np.broadcast_shapes(value.shape, np.shape(cos_theta) + (3,)))

    def _eval(self, wo, wi):
        d = self.distribution
        up = (wo[..., 2] > 0.0) & (wi[..., 2] > 0.0) & ~d.smooth
        h = normalize(wo + wi)
        # wo.h = |wo + wi| / 2, symmetric in (wo, wi) bit for bit (exact reciprocity)
        cos_oh = 0.5 * np.sqrt(dot(wo + wi, wo + wi))
        f = self._F(cos_oh) * (d.D(h) * d.V(wo, wi))[..., None]
        return np.where(up[..., None], f, 0.0)

    def _pdf(self, wo, wi):
        d = self.distribution
        up = (wo[..., 2] > 0.0) & (wi[..., 2] > 0.0) & ~d.smooth
        h = normalize(wo + wi)
        cos_oh = dot(wo, h)
        pdf = d.pdf_visible(wo, h) / (4.0 * np.where(up, cos_oh, 1.0))
        return np.where(up, pdf, 0.0)

    def _sample(self, wo, u):
        d = self.distribution
        m = d.sample_visible(wo, u[..., 1:3])
        wi = reflect(wo, m)
        cos_om = dot(wo, m)
        ok = (wo[..., 2] > 0.0) & (wi[..., 2] > 0.0) & (cos_om > 0.0)
        smooth = np.broadcast_to(d.smooth, ok.shape)
        pdf = np.where(smooth, 1.0, d.pdf_visible(wo, m) / (4.0 * np.where(ok, cos_om, 1.0)))
        weight = self._F(cos_om) * np.where(smooth, 1.0, d.G2_over_G1(wo, wi))[..., None]
        flags = np.where(smooth, int(Flags.REFLECTION | Flags.DELTA),
                         int(Flags.REFLECTION | Flags.GLOSSY))
        return BSDFSample(
            wi=np.where(ok[..., None], wi, 0.0),
            weight=np.where(ok[..., None], weight, 0.0),
            pdf=np.where(ok, pdf, 0.0),
            flags=np.where(ok, flags, int(Flags.NONE)),
        )


    def _albedo_table(self, wo):
        """E(mu_o, sqrt(alpha_x alpha_y)) of ``tables`` "ggx_conductor"; F = 1 only."""
        if self.fresnel is not None:
            raise ValueError("method = 'table' needs fresnel = None (F = 1) for a Conductor: "
                             "the tables hold the F = 1 albedo")
        E, error = conductor_energy(self.distribution, wo, with_error=True)
        return (np.broadcast_to(E[..., None], E.shape + (3,)),
                np.broadcast_to(error[..., None], error.shape + (3,)))

    def _sampling_weight(self, wo):
        return luminance(self._F(np.abs(wo[..., 2])))

    def _delta_albedo(self, wo):
        """F(cos theta_o) where the lobe is a perfect mirror and ``wo`` is above, else 0."""
        delta = self.distribution.smooth & (wo[..., 2] > 0.0)
        return np.where(delta[..., None], self._F(np.maximum(wo[..., 2], 0.0)), 0.0)


def _mirror(wo):
    return np.array([-wo[0], -wo[1], wo[2]])


def _one_minus_ln2(wo):
    """alpha = 1, F = 1, normal view: albedo 1 - ln 2 (shared/reference/published_values.md §3)."""
    return 1.0 - np.log(2.0) if wo[2] == 1.0 else None


register(
    CheckCase("Conductor a=1 F=1", lambda: Conductor(1.0), cos_theta_o=(1.0, 0.5, 0.05),
              expected_albedo=_one_minus_ln2),
    CheckCase("Conductor a=0.1 F=1", lambda: Conductor(0.1), width=0.2, peak=_mirror),
    CheckCase("Conductor a=(0.5,0.1) gold", lambda: Conductor(
        0.5, 0.1, fresnel=partial(fresnel.conductor, eta=(0.143, 0.374, 1.442),
                                  k=(3.983, 2.385, 1.603)))),
)
