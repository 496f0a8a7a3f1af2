"""Rough conductor: microfacet reflection (GGX, Beckmann or a mixture) with any Fresnel model."""

from __future__ import annotations

import numpy as np

from adobe_bsdf import fresnel, quadrature
from adobe_bsdf.bsdf import BSDFSample, Flags, SupportLobe, luminance
from adobe_bsdf.lobes.energy_lookup import conductor_energy, grey
from adobe_bsdf.microfacet import distribution
from adobe_bsdf.registry import CheckCase, register

__all__ = ["Conductor"]


class Conductor(SupportLobe):
    """Microfacet reflection f = F(wo.h) D(h) G2(wo, wi) / (4 |cos o| |cos i|).

    Walter et al. 2007 eq. 20 with an anisotropic distribution of ``adobe_bsdf.microfacet``
    (GGX by default; ``Conductor.over`` takes any, e.g. a ``Mixture``); sampled by visible
    normals (weight F G2 / G1(wo)). One-sided: 0 unless both directions are
    above the surface. Where both alphas are below ``ALPHA_MIN`` it is a perfect mirror (a
    delta lobe with weight F(cos theta_o)).

    Parameters
    ----------
    alpha_x, alpha_y : array_like in [0, inf)
        Roughness along the tangent and the bitangent (``alpha_y`` defaults to ``alpha_x``).
    fresnel : callable or None
        ``fresnel(cos_theta) -> (..., 3)`` or ``(...)``, e.g.
        ``ab.fresnel.ExactConductor(eta, k)``; ``None`` is F = 1. The models of
        ``adobe_bsdf.fresnel`` are fastest (they take cos^2 and declare their parameter
        shape, so large batches run in chunks on threads); any other callable works too.
    masking : {"correlated", "separable"}
        See ``GGX``.
    model : {"ggx", "beckmann"}
        The microfacet distribution (``adobe_bsdf.microfacet.MODELS``). The energy tables
        (``albedo(method="table")``) exist for GGX only.
    """

    flags = Flags.REFLECTION | Flags.GLOSSY | Flags.DELTA

    def __init__(self, alpha_x, alpha_y=None, fresnel=None, masking: str = "correlated",
                 model: str = "ggx"):
        self._init(distribution(model, alpha_x, alpha_y, masking), fresnel)

    @classmethod
    def over(cls, microfacets, fresnel=None) -> Conductor:
        """The lobe over ``microfacets``, any distribution of ``adobe_bsdf.microfacet``."""
        lobe = object.__new__(cls)
        lobe._init(microfacets, fresnel)
        return lobe

    def _init(self, microfacets, fresnel):
        if fresnel is not None and not callable(fresnel):
            raise ValueError(f"fresnel = {fresnel!r} is not callable (allowed: None or a "
                             "callable cos_theta -> reflectance)")
        self.distribution = microfacets
        self.fresnel = fresnel

    def __repr__(self) -> str:
        return f"{type(self).__name__}.over({self.distribution!r}, fresnel={self.fresnel!r})"

    def _param_shape(self):
        if self.fresnel is None:
            return self.distribution.param_shape
        if not hasattr(self.fresnel, "param_shape"):
            return None  # a plain callable: its parameters are unknown
        return np.broadcast_shapes(self.distribution.param_shape, self.fresnel.param_shape)

    def _F(self, cos_theta):
        if self.fresnel is None:
            return np.ones(np.shape(cos_theta) + (3,))
        return self._F2(cos_theta * cos_theta)

    def _F2(self, cos2):
        """Fresnel ``(..., 3)`` from cos^2 theta (the models of ``adobe_bsdf.fresnel`` take it
        directly; a plain callable gets the cosine); ``None`` for F = 1."""
        if self.fresnel is None:
            return None
        from_cos2 = getattr(self.fresnel, "from_cos2", None)
        value = np.asarray(from_cos2(cos2) if from_cos2 is not None
                           else self.fresnel(np.sqrt(cos2)), dtype=np.float64)
        if value.shape == np.shape(cos2):
            value = value[..., None]
        shape = np.broadcast_shapes(value.shape, np.shape(cos2) + (3,))
        return value if value.shape == shape else np.broadcast_to(value, shape)

    # -- eval and pdf share the half vector, D(h) and S(wo) --------------------------------
    def _half(self, wo, wi, up):
        """(D(h), |wo + wi|^2, S(wo)) with h = (wo + wi) / |wo + wi|; wo.h = |wo + wi| / 2,
        symmetric in (wo, wi) bit for bit (exact reciprocity). ``up``: the support mask, or
        None where every pair is in it (``on_support``). Call under ``np.errstate``: pairs
        outside the support may divide by zero; they are masked by ``up``."""
        d = self.distribution
        ox, oy, oz = wo[..., 0], wo[..., 1], wo[..., 2]
        hx = ox + wi[..., 0]
        hy = oy + wi[..., 1]
        hz = oz + wi[..., 2]
        length2 = hx * hx
        length2 += hy * hy
        length2 += hz * hz
        D = d.D_of_sum(hx, hy, hz, length2, upper=up is None)
        return D, length2, d.projected(ox, oy, oz)

    def _f(self, wo, wi, up, D, length2, s_o):
        """f = F D V (``GGX.V_of``), 0 outside ``up``."""
        d = self.distribution
        iz = wi[..., 2]
        DV = D * d.V_of(wo[..., 2], s_o, iz, d.projected(wi[..., 0], wi[..., 1], iz))
        if up is not None:
            DV = np.where(up, DV, 0.0)
        F = self._F2(0.25 * length2)
        if F is None:
            return np.repeat(DV[..., None], 3, axis=-1)
        if F.flags.writeable and F.shape == DV.shape + (3,):
            F *= DV[..., None]
            return F
        return F * DV[..., None]

    @staticmethod
    def _p(wo, up, D, s_o):
        """pdf = D_wo(h) / (4 wo.h) = D(h) / (2 (|cos o| + S(wo))) (Heitz 2018 eq. 3),
        0 outside ``up``."""
        pdf = D / (2.0 * (wo[..., 2] + s_o))
        return pdf if up is None else np.where(up, pdf, 0.0)

    def _support(self, wo, wi):
        """Both directions above a rough surface."""
        inside = (wo[..., 2] > 0.0) & (wi[..., 2] > 0.0)
        if np.any(self.distribution.smooth):
            inside = inside & ~self.distribution.smooth  # may broadcast to the alphas
        return inside

    def _eval_kernel(self, wo, wi, up):
        with np.errstate(divide="ignore", invalid="ignore"):
            D, length2, s_o = self._half(wo, wi, up)
            return self._f(wo, wi, up, D, length2, s_o)

    def _pdf_kernel(self, wo, wi, up):
        with np.errstate(divide="ignore", invalid="ignore"):
            D, _, s_o = self._half(wo, wi, up)
            return self._p(wo, up, D, s_o)

    def _eval_pdf_kernel(self, wo, wi, up):
        with np.errstate(divide="ignore", invalid="ignore"):
            D, length2, s_o = self._half(wo, wi, up)
            pdf = self._p(wo, up, D, s_o)
            return self._f(wo, wi, up, D, length2, s_o), pdf

    def _sample(self, wo, u):
        d = self.distribution
        ox, oy, oz = wo[..., 0], wo[..., 1], wo[..., 2]
        mx, my, mz = d.sample_visible_xyz(ox, oy, oz, u[..., 1], u[..., 2])
        cos_om = ox * mx + oy * my + oz * mz
        two_cos = 2.0 * cos_om
        wi = np.stack([two_cos * mx - ox, two_cos * my - oy, two_cos * mz - oz], axis=-1)
        iz = wi[..., 2]
        ok = (oz > 0.0) & (iz > 0.0) & (cos_om > 0.0)
        smooth = np.broadcast_to(d.smooth, ok.shape)
        with np.errstate(divide="ignore", invalid="ignore"):
            s_o = d.projected(ox, oy, oz)
            s_i = d.projected(wi[..., 0], wi[..., 1], iz)
            D = d.D_of_sum(mx, my, mz, 1.0)
            pdf = np.where(smooth, 1.0, self._p(wo, ok, D, s_o))
            g = np.where(smooth | ~ok, 1.0, d.G2_over_G1_of(oz, s_o, iz, s_i))
        F = self._F2(cos_om * cos_om)
        weight = np.repeat(g[..., None], 3, axis=-1) if F is None else F * g[..., None]
        flags = np.where(smooth, int(Flags.REFLECTION | Flags.DELTA),
                         int(Flags.REFLECTION | Flags.GLOSSY))
        return BSDFSample(
            wi=np.where(ok[..., None], wi, 0.0),
            weight=np.where(ok[..., None], weight, 0.0),
            pdf=np.where(ok, pdf, 0.0),
            flags=np.where(ok, flags, int(Flags.NONE)),
        )

    def _albedo_table(self, wo, with_error=True):
        """E(mu_o, sqrt(alpha_x alpha_y)) of ``tables`` "ggx_conductor" for F = 1. With a
        Fresnel the albedo has no table: it is ``quadrature.sampled_albedo``, the 32 x 32
        Gauss rule over the visible-normal sampler (error: |Q_32 - Q_16|)."""
        if self.fresnel is None:
            return tuple(map(grey, conductor_energy(self.distribution, wo, with_error)))
        if self.distribution.smooth.all():
            return self._delta_albedo(wo), np.zeros(wo.shape[:-1] + (3,))
        value = quadrature.sampled_albedo(self, wo)
        error = (np.abs(value - quadrature.sampled_albedo(self, wo, order=16))
                 if with_error else None)
        return value, error

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
    CheckCase("Conductor Beckmann a=0.3 F=1", lambda: Conductor(0.3, model="beckmann")),
    CheckCase("Conductor a=(0.5,0.1) gold", lambda: Conductor(
        0.5, 0.1, fresnel=fresnel.ExactConductor(eta=(0.143, 0.374, 1.442),
                                                 k=(3.983, 2.385, 1.603)))),
)
