"""Microfacet reflection (GGX, Beckmann or a mixture) with a Fresnel model: the generic lobe,
a conductor's, and a dielectric interface's reflection alone."""

from __future__ import annotations

import numpy as np

from adobe_bsdf import quadrature
from adobe_bsdf._channels import pick, weighted
from adobe_bsdf.bsdf import Flags, SupportLobe, finished_sample, luminance
from adobe_bsdf.fresnel import ExactDielectric, Fresnel, FresnelFunction
from adobe_bsdf.lobes.energy_lookup import (
    checked_ratio,
    conductor_energy,
    exact_anisotropic,
    grey,
    is_anisotropic,
    reflected_energy,
    sides,
    slice_energy,
    table_alpha,
)
from adobe_bsdf.lobes.top_albedo import TopAlbedoGrid
from adobe_bsdf.microfacet import distribution, saturated

__all__ = ["MicrofacetReflection", "Conductor", "DielectricReflection", "ReferencedReflection"]


class MicrofacetReflection(SupportLobe):
    """Microfacet reflection f = F(wo.h) D(h) G2(wo, wi) / (4 |cos o| |cos i|).

    [Walter2007, eq. 20] with an anisotropic distribution of ``adobe_bsdf.microfacet``
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
        self._init(distribution(model, alpha_x, alpha_y, masking), _fresnel_model(fresnel))

    @classmethod
    def over(cls, microfacets, fresnel=None) -> MicrofacetReflection:
        """The lobe over ``microfacets``, any distribution of ``adobe_bsdf.microfacet``."""
        return cls._new(microfacets, _fresnel_model(fresnel))

    def _init(self, microfacets, fresnel: Fresnel | None):
        self.distribution = microfacets
        self.fresnel = fresnel

    def __repr__(self) -> str:
        return f"{type(self).__name__}.over({self.distribution!r}, fresnel={self.fresnel!r})"

    def _param_shape(self):
        if self.fresnel is None:
            return self.distribution.param_shape
        if self.fresnel.param_shape is None:
            return None  # a plain callable: its parameters are unknown
        return np.broadcast_shapes(self.distribution.param_shape, self.fresnel.param_shape)

    def _F(self, cos_theta):
        if self.fresnel is None:
            return np.ones(np.shape(cos_theta) + (3,))
        return self._F2(cos_theta * cos_theta)

    def _F2(self, cos2):
        """Fresnel ``(..., 3)`` from cos^2 theta (``Fresnel.from_cos2``); ``None`` for F = 1."""
        if self.fresnel is None:
            return None
        value = np.asarray(self.fresnel.from_cos2(cos2), dtype=np.float64)
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
        DV = saturated(D * d.V_of(wo[..., 2], s_o, iz, d.projected(wi[..., 0], wi[..., 1], iz)))
        if up is not None:
            DV = pick(up, DV, 0.0)
        F = self._F2(0.25 * length2)
        if F is None:
            return np.repeat(DV[..., None], 3, axis=-1)
        if F.flags.writeable and F.shape == DV.shape + (3,):
            return weighted(F, DV, out=F)
        return F * DV[..., None]

    @staticmethod
    def _p(wo, up, D, s_o):
        """pdf = D_wo(h) / (4 wo.h) = D(h) / (2 (|cos o| + S(wo))) [Heitz2018, eq. 3],
        0 outside ``up``."""
        pdf = D / (2.0 * (wo[..., 2] + s_o))
        return pdf if up is None else pick(up, pdf, 0.0)

    def _support(self, wo, wi):
        """Both directions above a rough surface."""
        inside = (wo[..., 2] > 0.0) & (wi[..., 2] > 0.0)
        if np.any(self.distribution.smooth):
            inside = inside & ~self.distribution.smooth  # may broadcast to the alphas
        return inside

    def _eval_kernel(self, wo, wi, up):
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            D, length2, s_o = self._half(wo, wi, up)
            return self._f(wo, wi, up, D, length2, s_o)

    def _pdf_kernel(self, wo, wi, up):
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            D, _, s_o = self._half(wo, wi, up)
            return self._p(wo, up, D, s_o)

    def _eval_pdf_kernel(self, wo, wi, up):
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            D, length2, s_o = self._half(wo, wi, up)
            pdf = self._p(wo, up, D, s_o)
            return self._f(wo, wi, up, D, length2, s_o), pdf

    def _sample(self, wo, u):
        return self._drawn(wo, u, weigh=True)

    def _sample_directions(self, wo, u, throughput):
        # the weight where a sample can be a delta (a smooth element)
        return self._drawn(wo, u, weigh=bool(np.any(self.distribution.smooth)))

    def _drawn(self, wo, u, weigh: bool):
        """The sample; without ``weigh`` (no element smooth) its weight is 0
        (``_sample_directions``). The pdf and weight of a failed element (``ok`` false) are
        whatever the arithmetic gives there: ``finished_sample`` zeroes them by its flags."""
        d = self.distribution
        ox, oy, oz = wo[..., 0], wo[..., 1], wo[..., 2]
        mx, my, mz, s_o = d.visible_and_projected(ox, oy, oz, u[..., 1], u[..., 2])
        cos_om = ox * mx + oy * my + oz * mz
        two_cos = 2.0 * cos_om
        wi = np.stack([two_cos * mx - ox, two_cos * my - oy, two_cos * mz - oz], axis=-1)
        iz = wi[..., 2]
        ok = (oz > 0.0) & (iz > 0.0) & (cos_om > 0.0)
        smooth = np.broadcast_to(d.smooth, ok.shape)
        any_smooth = bool(np.any(smooth))  # (else the selections by it are the identity)
        weight = None
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            D = d.D_of_sum(mx, my, mz, 1.0, upper=True)  # (mz > 0 wherever ok)
            pdf = self._p(wo, None, D, s_o)
            if any_smooth:
                pdf = pick(smooth, 1.0, pdf)
            if weigh:
                s_i = d.projected(wi[..., 0], wi[..., 1], iz)
                g = d.G2_over_G1_of(oz, s_o, iz, s_i)
                if any_smooth:
                    g = pick(smooth, 1.0, g)
                F = self._F2(cos_om * cos_om)
                if F is None:
                    weight = np.repeat(g[..., None], 3, axis=-1)
                elif F.flags.writeable and F.shape == g.shape + (3,):
                    weight = weighted(F, g, out=F)
                else:
                    weight = F * g[..., None]
        flags = (pick(smooth, int(Flags.REFLECTION | Flags.DELTA),
                      int(Flags.REFLECTION | Flags.GLOSSY)) if any_smooth
                 else int(Flags.REFLECTION | Flags.GLOSSY))
        return finished_sample(wi, weight, pdf, pick(ok, flags, int(Flags.NONE)), fresh=True)

    def _albedo_table(self, wo, with_error=True):
        """E(wo) of ``tables`` "ggx_conductor" (isotropic) or "ggx_conductor_anisotropic" for
        F = 1. With a Fresnel the albedo has no table: it is ``quadrature.sampled_albedo`` Q_F,
        the 32 x 32 Gauss rule over the visible-normal sampler, with the F = 1 lobe as its
        control variate on the same nodes: E_F = E_table + Q_F - Q_1 (at least 0), exact
        for F = 1 and at most E_table for F <= 1, so that with the Kulla-Conty term a white
        metal's table albedo is 1 and no metal's exceeds it (the plain rule overshoots by up
        to 2e-3 at grazing angles). Error: the change of Q_F - Q_1 at order 16."""
        if self.fresnel is None:
            return tuple(map(grey, conductor_energy(self.distribution, wo, with_error)))
        d = self.distribution
        if d.smooth.all():
            return self._delta_albedo(wo), np.zeros(wo.shape[:-1] + (3,))
        white = Conductor._new(d, None)

        def rule(order):
            return (quadrature.sampled_albedo(self, wo, order)
                    - quadrature.sampled_albedo(white, wo, order))

        value = rule(32)
        error = np.abs(value - rule(16)) if with_error else None
        E = grey(conductor_energy(d, wo)[0])
        return np.maximum(E + value, 0.0), error

    def _sampling_weight(self, wo):
        return luminance(self._F(np.abs(wo[..., 2])))

    def _delta_albedo(self, wo):
        """F(cos theta_o) where the lobe is a perfect mirror and ``wo`` is above, else 0."""
        delta = self.distribution.smooth & (wo[..., 2] > 0.0)
        return pick(delta[..., None], self._F(np.maximum(wo[..., 2], 0.0)), 0.0)


def _fresnel_model(fresnel) -> Fresnel | None:
    """``fresnel`` as a ``Fresnel`` (a plain callable wrapped), None for F = 1."""
    if fresnel is None or isinstance(fresnel, Fresnel):
        return fresnel
    return FresnelFunction(fresnel)


class Conductor(MicrofacetReflection):
    """A conductor's microfacet reflection: ``MicrofacetReflection`` with any Fresnel model
    (typically ``fresnel.ExactConductor`` or ``fresnel.F82Tint``; None is F = 1, a white
    metal), as pbrt-v4's ``ConductorBxDF`` and Mitsuba 3's ``roughconductor``."""


class ReferencedReflection(MicrofacetReflection):
    """``MicrofacetReflection`` with a Fresnel model that has no table (a thin film), next to
    a ``reference`` reflection of the same microfacets that has one (the film-free
    interface). Its table albedo, and its albedo as a layer's top, are the reference's plus
    the difference of the two lobes' ``quadrature.sampled_albedo`` on the same 32 x 32
    visible-normal nodes (a control variate, as ``Conductor``'s with F = 1):

        E(wo) = E_reference(wo) + Q_F(wo) - Q_reference(wo)  (at least 0),

    so where the two Fresnel models agree (a film of vanishing thickness) the albedo is the
    reference's to rounding, and a layer over it sees the same E_top. Error: the change of
    Q_F - Q_reference at order 16.

    Parameters
    ----------
    reference : MicrofacetReflection
        The reflection whose tables serve (its distribution is this lobe's).
    fresnel : fresnel.Fresnel
    """

    def __init__(self, reference: MicrofacetReflection, fresnel):
        if not isinstance(reference, MicrofacetReflection):
            raise ValueError(f"reference = {reference!r}: allowed a MicrofacetReflection")
        self._init(reference, _fresnel_model(fresnel))

    def _init(self, reference, fresnel):
        super()._init(reference.distribution, fresnel)
        self.reference = reference

    def __repr__(self) -> str:
        return f"ReferencedReflection({self.reference!r}, fresnel={self.fresnel!r})"

    def _difference(self, wo, order):
        return (quadrature.sampled_albedo(self, wo, order)
                - quadrature.sampled_albedo(self.reference, wo, order))

    def _albedo_table(self, wo, with_error=True):
        if self.distribution.smooth.all():
            return self._delta_albedo(wo), np.zeros(wo.shape[:-1] + (3,))
        E, error = self.reference._albedo_table(wo, with_error)
        value = self._difference(wo, 32)
        if with_error:
            error = error + np.abs(value - self._difference(wo, 16))
        return np.maximum(E + value, 0.0), error

    def _top_albedo(self, wo):
        if self.distribution.smooth.all():
            return self._delta_albedo(wo)
        return np.maximum(self.reference._top_albedo(wo) + self._difference(wo, 32), 0.0)


class DielectricReflection(MicrofacetReflection):
    """The reflection of a rough dielectric interface alone: GGX microfacet reflection with
    the exact dielectric Fresnel of relative index ``eta`` [Walter2007, eq. 20], no
    refraction. Its albedo table is E_R of the dielectric tables (seen from the light side
    for eta >= 1, from the dense side for eta < 1) at sqrt(alpha_x alpha_y); where
    anisotropic and built under ``config.options(anisotropic_energy="exact")``, E_R of its
    own slice (``tables.dielectric_slices``).

    Parameters
    ----------
    eta : array_like in [1/3, 3]
        n below / n above.
    alpha_x, alpha_y : array_like in [0, 2]
    """

    def __init__(self, eta, alpha_x, alpha_y=None):
        super().__init__(alpha_x, alpha_y, fresnel=ExactDielectric(eta))

    def _init(self, microfacets, fresnel: ExactDielectric):
        super()._init(microfacets, fresnel)
        self.eta = fresnel.eta
        #: E_R from the lobe's slice where anisotropic (``config`` anisotropic_energy)
        self.exact = exact_anisotropic(self.distribution)

    def __repr__(self) -> str:
        return f"DielectricReflection(eta={self.eta!r}, {self.distribution!r})"

    def _top_albedo(self, wo):
        """The table where isotropic; where anisotropic, the table at sqrt(alpha_x alpha_y)
        misses the true albedo by up to ~0.04 at grazing angles (either way), so a layer
        under it would gain energy: there E is ``quadrature.sampled_albedo`` (32 x 32
        visible normals per direction), interpolated from a grid over wo built once per lobe
        (``top_albedo.TopAlbedoGrid``; textured parameters: the rule at every distinct
        ``wo``), or, built exact, the slice's."""
        d = self.distribution
        if np.all((d.alpha_x == d.alpha_y) | d.smooth) or self.exact:
            return super()._top_albedo(wo)
        if self._param_shape() != ():
            return quadrature.sampled_albedo(self, wo)
        return grey(pick(wo[..., 2] > 0.0, TopAlbedoGrid.of(self)(wo), 0.0))

    def _albedo_table(self, wo, with_error=True):
        alpha, ratio = table_alpha(self.distribution), checked_ratio(self.eta)
        mu = np.clip(wo[..., 2], 0.0, 1.0)  # 1 + an ulp by rounding is 1
        light = sides(self.eta)[0]
        # exact anisotropic elements read their slices below: none integrates here
        aniso = is_anisotropic(self.distribution) if self.exact else np.False_
        sides_seen = (("ggx_dielectric_outside", ratio, light),
                      ("ggx_dielectric_inside", 1.0 / ratio, ~light))
        if np.ndim(light) == 0:  # one index: only its side's table
            sides_seen = [side for side in sides_seen if side[2]]
        parts = [reflected_energy(name, mu, alpha, ratio, {"alpha": alpha, "eta": ratio}, seen,
                                  with_error, where & ~aniso)
                 for name, seen, where in sides_seen]
        if len(parts) == 1:
            E, error = parts[0]
        else:
            E = pick(light, parts[0][0], parts[1][0])
            error = pick(light, parts[0][1], parts[1][1]) if with_error else None
        up = wo[..., 2] > 0.0
        E = grey(pick(up, E, 0.0))
        error = grey(None if error is None else pick(up, error, 0.0))
        if self.exact:
            E_s, error_s = slice_energy(self.eta, self.distribution, wo, with_error)
            aniso = np.asarray(aniso)[..., None]
            E = pick(aniso, grey(pick(up, E_s[..., 0], 0.0)), E)
            if with_error:
                error = pick(aniso, grey(pick(up, error_s[..., 0], 0.0)), error)
        smooth = self.distribution.smooth
        if np.any(smooth):  # the exact Fresnel, not its interpolation in eta
            smooth = smooth[..., None]
            E = pick(smooth, self._delta_albedo(wo), E)
            error = None if error is None else pick(smooth, 0.0, error)
        return E, error
