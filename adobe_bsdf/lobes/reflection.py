"""Microfacet reflection (GGX, Beckmann or a mixture) with a Fresnel model: the generic lobe,
a conductor's, and a dielectric interface's reflection alone."""

from __future__ import annotations

import functools

import numpy as np

from adobe_bsdf import _params, quadrature
from adobe_bsdf._channels import pick, weighted
from adobe_bsdf.bsdf import Flags, SupportLobe, finished_sample, luminance
from adobe_bsdf.fresnel import ExactConductor, ExactDielectric, Fresnel, FresnelFunction
from adobe_bsdf.lobes.energy_lookup import (
    checked_ratio,
    conductor_energy,
    grey,
    is_anisotropic,
    reflected_energy,
    sides,
    slice_energy,
    slice_source,
    table_alpha,
)
from adobe_bsdf.lobes.top_albedo import TopAlbedoGrid
from adobe_bsdf.microfacet import GGX, distribution, saturated
from adobe_bsdf.tables.energy import _breakpoints, _g, _outer_knots, _rule
from adobe_bsdf.thin_film import AdaptiveCubic, ThinFilm, _cubic_coefficients, built_once

__all__ = ["MicrofacetReflection", "Conductor", "DielectricReflection", "ReferencedReflection"]

#: the tolerance of ``ReferencedReflection``'s table of the albedo difference in cos theta_o
#: at the midpoints of its nodes (``thin_film.AdaptiveCubic``)
DIFFERENCE_TOL = 1e-5
#: Gauss-Legendre nodes per piece and dimension of the node rule of that table
#: (``_fresnel_energy``; its error against direction-space cubature is in the class docstring
#: of ``ReferencedReflection``)
DIFFERENCE_ORDER = 16
#: the most nodes of that table (a few ms each); a lobe that would need more (a film tens
#: of micrometres thick on a nearly smooth lobe) keeps the sampled rule at every wo
DIFFERENCE_MAX_NODES = 1024
#: directions integrated at once by ``_fresnel_energy`` (memory: ~1e5 nodes each)
_ENERGY_CHUNK = 8
#: the anisotropic table of that difference (``ReferencedReflection``, ``AzimuthalTable``):
#: its azimuth nodes, equally spaced in u on [0, pi / 2] with tan u = k tan phi,
#: k = r^AZIMUTH_STRETCH and r = alpha_y / alpha_x clipped to [AZIMUTH_RATIO_FLOOR,
#: 1 / AZIMUTH_RATIO_FLOOR] (they gather towards the axis of the smaller roughness)
AZIMUTH_NODES = 13
AZIMUTH_STRETCH = 0.3
AZIMUTH_RATIO_FLOOR = 0.01
#: its tolerance in cos theta_o at the midpoints of its nodes (every azimuth node), and
#: nodes it starts from besides 16 equal steps (the kinks, and these towards grazing views)
ANISOTROPIC_TOL = 1e-4
GRAZING_NODES = 2.0 ** -np.arange(5, 9)
#: the columns equally spaced in cos 2u between which a lookup interpolates linearly
AZIMUTH_GRID = 129
#: the error its table albedo carries: above every miss of its E_F - E_reference measured
#: (class docstring of ``ReferencedReflection``; 7.6e-4 at most)
ANISOTROPIC_ERROR = 1e-3
#: the most nodes in cos theta_o of that table (each costs 2 x ``AZIMUTH_NODES`` integrals
#: of ~0.5 ms); a lobe that would need more keeps the sampled rule at every wo
ANISOTROPIC_MAX_NODES = 192
#: Gauss-Legendre nodes per piece of ``_anisotropic_fresnel_energy``: of the stretched
#: azimuth psi (``AZIMUTH_PANELS`` equal panels, split further) and of theta_m
ANISOTROPIC_ORDERS = (8, 6)
AZIMUTH_PANELS = 8
#: directions integrated at once by ``_anisotropic_fresnel_energy`` (~0.5 MB each)
_ANISOTROPIC_CHUNK = 32
#: multiples k of the reflected direction's horizon, 2 c cos theta_m = k mu_o: the horizon
#: and its boundary layer (``tables.energy._breakpoints``)
_LAYERS = (1.0, 3.0, 21.0)
#: the steps in c on which ``_clip_cosines`` brackets the kinks of a clipped film
_CLIP_GRID = 4096


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
    metal), as pbrt-v4's ``ConductorBxDF`` and Mitsuba 3's ``roughconductor``.

    With a ``thin_film.ThinFilm`` (a film over the metal) its albedo is that of
    ``ReferencedReflection(Conductor(alpha), film)``, the same ``eval``: the F = 1 table plus
    the film's difference tabulated in cos theta_o (within 2.5e-5 of cubature, where the
    sampled rule of other Fresnel models misses an oscillating film by up to 1.2e-3;
    ``docs/film_albedo_measured.md``)."""

    def _albedo_table(self, wo, with_error=True):
        if isinstance(self.fresnel, ThinFilm):
            return self._filmed._albedo_table(wo, with_error)
        return super()._albedo_table(wo, with_error)

    @functools.cached_property
    def _filmed(self) -> ReferencedReflection:
        """The ``ReferencedReflection`` of this lobe's film over the white conductor, built
        on first use and kept (its table with it)."""
        return ReferencedReflection._new(Conductor._new(self.distribution, None), self.fresnel)


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

    The rule is linear in the Fresnel factor, so Q_F - Q_reference is the rule of one lobe
    whose "Fresnel" is the difference F - F_reference, over the same samples (``_signed``;
    the reference samples the visible normals of the same microfacets, as this lobe).

    The table (isotropic GGX with height-correlated masking, scalar parameters, and
    ``tabulated``): the difference depends on mu_o = cos theta_o alone, and is then
    tabulated once per lobe, on first use, as a ``thin_film.AdaptiveCubic`` in mu_o of
    ``DIFFERENCE_TOL`` = 1e-5 at its midpoints (the kinks below are nodes), from a node
    rule in place of the 32 x 32 one: E_F - E_reference integrated over the microfacet
    normals by the piecewise Gauss-Legendre rule of the tables (``tables.energy``, at
    ``DIFFERENCE_ORDER`` = 16; ``_fresnel_energy``), its pieces split also where c = wo.m
    crosses a kink of either Fresnel model (a critical angle of the film or the substrate,
    or a cosine where a clipped film's colour enters or leaves 0 in some channel,
    ``_clip_cosines``: without these the table missed by up to 2.5e-4).
    The sampled rule is not smooth in mu_o (its nodes cross those kinks and the horizon as
    mu_o moves) and misses the difference by up to 5e-3 (rough lobes at grazing views, and
    across total internal reflection); the node rule converges geometrically (order 12:
    2.5e-5, 16: 8e-7 in the worst case found).

    Measured against direction-space cubature (``albedo(method="quadrature", tol=1e-7)``
    of this lobe and of the reference), at 24 random lobes (thickness 0-2000 nm, film index
    1-3, base index 1/3-3 log-uniform, roughness r in [0.05, 1], alpha = r^2) times 5
    random views (one grazing, mu_o < 0.1), the slow test ``test_film_albedo_table_sweep``:
    the table's E_F - E_reference within 8.6e-6 (RMS 1.6e-6); within 3e-6 at views
    1e-4..3e-2 from the critical angle of lobes of alpha 0.0025-0.02. The lobe's whole
    table albedo adds the reference's own table error: up to 0.1 for nearly smooth lobes
    seen from the dense side near the critical angle (alpha < 0.02, index below 1),
    elsewhere within 6.1e-4 (RMS 1.3e-4). A table holds 34-94 nodes (51 on average), built
    in 0.1-0.5 s on one core (besides the film's own table).

    The anisotropic table (alpha_x != alpha_y, otherwise as above): the difference depends
    on wo's azimuth phi_o too, through cos^2 phi_o (GGX is symmetric under phi -> -phi and
    phi -> pi - phi). ``AzimuthalTable`` holds it at ``AZIMUTH_NODES`` = 13 azimuths, each a
    column of one ``AdaptiveCubic`` in mu_o of ``ANISOTROPIC_TOL`` = 1e-4, interpolated in
    the azimuth through all 13 (a cosine series), built once per lobe on first use. Its node
    rule, ``_anisotropic_fresnel_energy``, integrates over the normals of the stretched
    alpha = 1 surface [Heitz2014, §5.3], where GGX has no peak: along each stretched azimuth
    the polar angle has the isotropic profile, and where the integrand stops being smooth
    (the facet turns away, the reflected direction's horizon, a kink of either Fresnel model
    or of the film's clipped colour) is in closed form, so plain Gauss-Legendre serves every
    piece (8 x 6 nodes). Candidates against the cubature above at 144 views of 24 lobes of
    the ranges below: that rule within 1.0e-5 (RMS 1e-6, 0.4 ms per view on one core); the
    sampled rule at 32 x 32 within 5.5e-4, at 64 x 64 6.3e-5 (1.3 ms), not smooth in mu_o;
    the isotropic node rule at wo's projected roughness plus the sampled rules' difference
    no closer (5.0e-4, 6.5e-5); the piecewise rule of ``tables.anisotropic_energy`` 13 ms
    per view for F = 1 alone.

    Measured against the cubature (as above) at 44 random lobes (thickness 100-1500 nm, film
    index 1.2-2.5, base index 1.3-2.5 or an F82-tint metal, ``ThinFilm.over_f82_tint``;
    alpha 0.05-1 and alpha_y / alpha_x 0.1-0.8, either axis the rougher) times 5 random views
    (one to three grazing, mu_o < 0.1): the table's E_F - E_reference within 6.3e-5 (RMS
    8e-6); against the converged node rule at 2000 views of 20 such lobes (a tenth at
    mu_o < 0.01, and ratio 0.1 at alpha 0.2-1) within 1.3e-4. Beyond those ranges, against
    the node rule: ratios below 0.1 down to 0 (a one-dimensional rough surface) within
    7.6e-4 at alpha 1 (6.7e-5 at alpha <= 0.13), at grazing views; critical angles (an index
    below the medium above, as under a coat) within 3.5e-4. The table albedo carries
    ``ANISOTROPIC_ERROR`` = 1e-3. A table holds 21-37 nodes, built in 0.15-0.6 s on one core
    (critical angles: 30-100 nodes, up to 2.6 s); a lookup reads 24 coefficients per wo.

    A textured lobe, another distribution (or ``tabulated=False``) evaluates the 32 x 32 rule
    at every distinct wo.

    Parameters
    ----------
    reference : MicrofacetReflection
        The reflection whose tables serve (its distribution is this lobe's).
    fresnel : fresnel.Fresnel
    tabulated : bool
        Tabulate the difference in mu_o (and the azimuth where anisotropic) where the lobe
        allows it (default).
    """

    def __init__(self, reference: MicrofacetReflection, fresnel, tabulated: bool = True):
        if not isinstance(reference, MicrofacetReflection):
            raise ValueError(f"reference = {reference!r}: allowed a MicrofacetReflection")
        self._init(reference, _fresnel_model(fresnel), _params.flag("tabulated", tabulated))

    def _init(self, reference, fresnel, tabulated: bool = True):
        super()._init(reference.distribution, fresnel)
        self.reference = reference
        self.tabulated = tabulated
        #: the lobe of Fresnel F - F_reference: its sampled albedo is Q_F - Q_reference
        self._signed = MicrofacetReflection._new(self.distribution,
                                                 _Difference(fresnel, reference.fresnel))
        self._table = None  # the difference in mu_o, built on first use (``table``)

    def __repr__(self) -> str:
        return f"ReferencedReflection({self.reference!r}, fresnel={self.fresnel!r})"

    def _difference(self, wo, order):
        """E_F - E_reference ``(..., 3)`` at ``wo``: the lobe's table in mu_o (and the
        azimuth where anisotropic), else the ``order`` x ``order`` sampled rule at every
        distinct wo."""
        table = self.table()
        if table is None:
            return quadrature.sampled_albedo(self._signed, wo, order)
        mu = wo[..., 2]
        value = table(wo) if isinstance(table, AzimuthalTable) else table(mu)
        return pick((mu > 0.0)[..., None], value, 0.0)

    def table(self) -> AdaptiveCubic | AzimuthalTable | None:
        """The difference tabulated in mu_o, or in mu_o and the azimuth where anisotropic
        (class docstring), built on the first call; None where the lobe has no table (or it
        would need more than ``DIFFERENCE_MAX_NODES``, ``ANISOTROPIC_MAX_NODES``)."""
        d = self.distribution
        if not (self.tabulated and self._signed._param_shape() == () and isinstance(d, GGX)
                and d.masking == "correlated" and not d.smooth):
            return None
        return built_once(self, self._make_table)

    def _make_table(self) -> AdaptiveCubic | AzimuthalTable:
        """``table``'s construction."""
        d = self.distribution
        if d.alpha_x != d.alpha_y:
            return AzimuthalTable(float(d.alpha_x), float(d.alpha_y), self._signed.fresnel)
        model = self._signed.fresnel
        kinks = np.union1d(_kinks(model), _clip_cosines(model))
        alpha = np.asarray(self.distribution.alpha_x, dtype=np.float64)

        def difference(mu):
            return np.concatenate([
                _fresnel_energy(mu[i:i + _ENERGY_CHUNK], alpha, self._signed.fresnel.from_cos2,
                                kinks, DIFFERENCE_ORDER)
                for i in range(0, mu.size, _ENERGY_CHUNK)])
        return AdaptiveCubic(difference, DIFFERENCE_TOL, kinks, max_nodes=DIFFERENCE_MAX_NODES)

    def _albedo_table(self, wo, with_error=True):
        """The reference's table plus the difference; its error: the reference's plus, from
        the table, ``DIFFERENCE_TOL`` (the node rule's own error is below it), else the
        change of the sampled rule at order 16."""
        if self.distribution.smooth.all():
            return self._delta_albedo(wo), np.zeros(wo.shape[:-1] + (3,))
        E, error = self.reference._albedo_table(wo, with_error)
        value = self._difference(wo, 32)
        if with_error:
            table = self.table()
            error = error + (np.abs(value - self._difference(wo, 16)) if table is None
                             else ANISOTROPIC_ERROR if isinstance(table, AzimuthalTable)
                             else DIFFERENCE_TOL)
        return np.maximum(E + value, 0.0), error

    def _top_albedo(self, wo):
        if self.distribution.smooth.all():
            return self._delta_albedo(wo)
        return np.maximum(self.reference._top_albedo(wo) + self._difference(wo, 32), 0.0)


def _fresnel_energy(mu_o, alpha, fresnel, kinks, order):
    """E_R ``(n, 3)`` of isotropic GGX reflection (height-correlated masking) at the cosines
    ``mu_o`` ``(n,)``, with the Fresnel factor ``fresnel(c^2)`` (c = wo.m; any values, signed
    included) and ``kinks`` ``(K,)`` the cosines c where that factor is not analytic.

    The piecewise Gauss-Legendre rule of ``tables.energy`` (``order`` nodes per piece and
    dimension, over theta_m and phi of the microfacet normal, weighted by D cos_m and the
    visible-normal density [Heitz2018, eq. 3]) for F = 1, with the Fresnel factor inside the
    integrand: its pieces in phi are also split where c crosses a kink, and its panels in
    theta_m also end where a kink meets an end of the range [cos(theta_o + theta_m),
    cos(theta_o - theta_m)] of c or the reflection horizon c = mu_o / (2 cos theta_m), so that
    the integrand is smooth on every piece."""
    kinks = np.asarray(kinks, dtype=np.float64).ravel()
    alpha = np.broadcast_to(alpha, mu_o.shape)
    s_o = np.sqrt(np.maximum(1.0 - mu_o * mu_o, 0.0))
    x, wx = _rule(order)
    knots = _outer_knots(mu_o, alpha, None)  # (n, K), sorted, padded with pi / 2
    if kinks.size:
        t = np.arccos(mu_o)[:, None]
        theta_k = np.arccos(kinks)[None, :]
        with np.errstate(divide="ignore", invalid="ignore"):
            horizon = np.arccos(mu_o[:, None] / (2.0 * kinks[None, :]))  # NaN: never
        extra = np.concatenate([theta_k - t, t - theta_k, t + theta_k, horizon], axis=1)
        extra = np.where((extra > 0.0) & (extra < np.pi / 2), extra, np.pi / 2)
        knots = np.sort(np.concatenate([knots, extra], axis=1), axis=1)
    a, b = knots[:, :-1], knots[:, 1:]
    # the variable of each panel: v = asinh(tan theta_m / alpha) below 45 degrees, theta_m
    # above (``tables.energy``)
    al = alpha[:, None, None]
    use_v = 0.5 * (a + b) < np.pi / 4
    va = np.arcsinh(np.tan(a) / alpha[:, None])
    vb = np.arcsinh(np.tan(np.minimum(b, np.pi / 4)) / alpha[:, None])
    lo = np.where(use_v, va, a)[..., None]
    hi = np.where(use_v, vb, b)[..., None]
    var = lo + (hi - lo) * x
    theta = np.where(use_v[..., None], np.arctan(al * np.sinh(var)), var)
    sin_t, cos_t = np.sin(theta), np.cos(theta)
    dxi_v = 2.0 * np.tanh(var) / np.cosh(var) ** 2
    dxi_t = 2.0 * al * al * sin_t * cos_t / (al * al * cos_t * cos_t + sin_t * sin_t) ** 2
    w_outer = (hi - lo) * wx * np.where(use_v[..., None], dxi_v, dxi_t)  # (n, P, order)
    # phi in [0, pi], split where c = wo.m crosses a breakpoint or a kink
    mu, so = mu_o[:, None, None], s_o[:, None, None]
    c_star = _breakpoints(mu, cos_t, None)
    if kinks.size:
        c_star = np.concatenate([c_star, np.broadcast_to(kinks, c_star.shape[:-1]
                                                         + kinks.shape)], axis=-1)
    amp = (so * sin_t)[..., None]
    ratio = np.where(amp > 0.0, (c_star - (mu * cos_t)[..., None])
                     / np.where(amp > 0.0, amp, 1.0), 2.0)
    phi_star = np.arccos(np.clip(np.nan_to_num(ratio, nan=2.0), -1.0, 1.0))
    knots_phi = np.sort(np.concatenate([np.zeros_like(phi_star[..., :1]), phi_star,
                                        np.full_like(phi_star[..., :1], np.pi)], -1), -1)
    pa, pb = knots_phi[..., :-1, None], knots_phi[..., 1:, None]
    phi = pa + (pb - pa) * x  # (n, P, order, J + 1, order)
    weight = w_outer[..., None, None] * ((pb - pa) * wx / np.pi)
    # the nodes of pieces of non-zero width only (most pieces are empty), then those where
    # the facet faces wo and the reflected direction is above the horizon
    i, p, o, j, k = np.nonzero(weight)
    weight = weight[i, p, o, j, k]
    cos_t, sin_t = cos_t[i, p, o], sin_t[i, p, o]
    c = s_o[i] * sin_t * np.cos(phi[i, p, o, j, k]) + mu_o[i] * cos_t
    wr_z = 2.0 * c * cos_t - mu_o[i]  # the reflected direction's cosine
    ok = np.flatnonzero((c > 0.0) & (wr_z > 0.0))
    i, c = i[ok], c[ok]
    weight = weight[ok] * c / cos_t[ok] * _g(mu_o[i], s_o[i], alpha[i], wr_z[ok])
    F = np.asarray(fresnel(c * c), dtype=np.float64)
    F = F[:, None] if F.ndim == 1 else F
    return np.stack([np.bincount(i, weights=weight * F[:, ch], minlength=mu_o.size)
                     for ch in range(F.shape[-1])], axis=-1)


def _anisotropic_fresnel_energy(mu_o, phi_o, alpha_x, alpha_y, fresnel, kinks, splits=(),
                                orders=None):
    """E_R ``(n, C)`` of anisotropic GGX reflection (height-correlated masking, scalar
    ``alpha_x`` != ``alpha_y``) seen from wo = (sin theta_o cos phi_o, sin theta_o sin phi_o,
    mu_o), ``(n,)`` each, with the Fresnel factor ``fresnel(c^2)`` (c = wo.m; ``(m, C)``, signed
    included), ``kinks`` the cosines c where it is not analytic and ``splits`` more cosines
    c that only the theta_m integral splits at (``_clip_cosines``).

    The GGX of (alpha_x, alpha_y) is the alpha = 1 surface stretched [Heitz2014, §5.3]: a
    normal m of azimuth phi_m has the stretched azimuth psi, tan phi_m = (alpha_y / alpha_x)
    tan psi, and along phi_m the isotropic profile of roughness
    alpha_m^2 = alpha_x^2 cos^2 psi + alpha_y^2 sin^2 psi, so D(m) cos theta_m d omega_m =
    dxi dpsi / (2 pi) with xi = tan^2 theta_m / (alpha_m^2 + tan^2 theta_m), and

        E_R = int dpsi / (2 pi) int dxi F(c) (c / cos theta_m) G2(wo, wi) / mu_o,

    wi the mirror direction of wo about m. At fixed psi, c = A sin theta_m + mu_o cos theta_m
    (A = wo's tangential component along phi_m), so where the integrand stops being smooth in
    theta_m is in closed form: c = 0 (the facet turns away), 2 c cos theta_m = k mu_o (the
    reflected direction's horizon and boundary layer, k in ``_LAYERS``) and c at a kink; the
    theta_m integral is split there and at 45 degrees (the variable v = asinh(tan theta_m /
    alpha_m) below, theta_m above, as ``_fresnel_energy``), the psi integral into
    ``AZIMUTH_PANELS`` equal panels and where those roots appear or vanish: A = 0,
    A^2 = k (k - 2) mu_o^2 and, per kink c_k, A = c_k and A^2 = c_k^2 - mu_o^2. Plain
    Gauss-Legendre on every piece (``orders``: psi, theta_m; default ``ANISOTROPIC_ORDERS``):
    each integrand is smooth up to its ends (but for the square root of a critical angle).
    """
    kinks = np.asarray(kinks, dtype=np.float64).ravel()
    order_psi, order_theta = ANISOTROPIC_ORDERS if orders is None else orders
    n = mu_o.size
    s_o = np.sqrt(np.maximum(1.0 - mu_o * mu_o, 0.0))
    wx, wy = s_o * np.cos(phi_o), s_o * np.sin(phi_o)
    S_o = np.sqrt(mu_o * mu_o + (alpha_x * wx) ** 2 + (alpha_y * wy) ** 2)
    # the psi knots: the values of A = s_o cos(phi_m - phi_o) where the theta_m roots change
    A_knots = [np.zeros(n)]
    for k in _LAYERS[1:]:
        A_knots += [mu_o * np.sqrt(k * (k - 2.0)), -mu_o * np.sqrt(k * (k - 2.0))]
    with np.errstate(divide="ignore", invalid="ignore"):
        for c_k in kinks:
            tangent = np.where(c_k > mu_o, np.sqrt(np.maximum(c_k * c_k - mu_o * mu_o, 0.0)),
                               np.nan)
            A_knots += [np.full(n, c_k), tangent, -tangent]
        ratio = np.stack(A_knots, axis=-1) / s_o[:, None]
    turn = np.arccos(np.where(np.abs(ratio) <= 1.0, ratio, np.nan))
    phi_m = np.concatenate([phi_o[:, None] + turn, phi_o[:, None] - turn], axis=-1)
    psi_m = np.mod(np.arctan2(alpha_x * np.sin(phi_m), alpha_y * np.cos(phi_m)), 2.0 * np.pi)
    knots = np.sort(np.concatenate([
        np.broadcast_to(np.linspace(0.0, 2.0 * np.pi, AZIMUTH_PANELS + 1), (n, AZIMUTH_PANELS + 1)),
        np.where(np.isfinite(psi_m), psi_m, 2.0 * np.pi)], axis=-1), axis=-1)
    x, w = _gauss_legendre(order_psi)
    i, j = np.nonzero(knots[:, 1:] > knots[:, :-1])
    lo, hi = knots[i, j][:, None], knots[i, j + 1][:, None]
    psi = (lo + (hi - lo) * x).ravel()
    w_psi = ((hi - lo) * (w / (2.0 * np.pi))).ravel()
    direction = np.repeat(i, order_psi)
    # along each node psi: the azimuth of m, its roughness, and c = R sin(theta_m + delta)
    cos_psi, sin_psi = np.cos(psi), np.sin(psi)
    alpha = np.sqrt((alpha_x * cos_psi) ** 2 + (alpha_y * sin_psi) ** 2)
    cos_m, sin_m = alpha_x * cos_psi / alpha, alpha_y * sin_psi / alpha
    mu, ox, oy = mu_o[direction], wx[direction], wy[direction]
    A = ox * cos_m + oy * sin_m
    R = np.hypot(A, mu)
    delta = np.arctan2(mu, A)
    v45 = np.arcsinh(1.0 / alpha)
    theta = [np.broadcast_to([0.0, np.pi / 4, np.pi / 2], (psi.size, 3)),
             np.arctan(alpha * np.sinh(0.5 * v45))[:, None]]  # two panels in v below 45
    with np.errstate(divide="ignore", invalid="ignore"):
        for c_star in np.concatenate([[0.0], kinks, np.ravel(splits)]):
            root = np.arcsin(np.where(c_star <= R, c_star / R, np.nan))
            theta += [(root - delta)[:, None], (np.pi - root - delta)[:, None]]
        for k in _LAYERS:
            root = np.arcsin(np.where((k - 1.0) * mu <= R, (k - 1.0) * mu / R, np.nan))
            theta += [(0.5 * (root - delta))[:, None], (0.5 * (np.pi - root - delta))[:, None]]
    theta = np.mod(np.concatenate(theta, axis=-1), np.pi)  # NaN (no root) stays NaN
    theta = np.sort(np.where(theta <= np.pi / 2, theta, np.pi / 2), axis=-1)
    # the pieces of non-zero width where the facet faces wo and reflects above the horizon
    ta, tb = theta[:, :-1], theta[:, 1:]
    middle = 0.5 * (ta + tb)
    c_mid = A[:, None] * np.sin(middle) + mu[:, None] * np.cos(middle)
    node, piece = np.nonzero((tb > ta) & (c_mid > 0.0) & (2.0 * c_mid * np.cos(middle)
                                                          > mu[:, None]))
    ta, tb = ta[node, piece], tb[node, piece]
    use_v = (middle[node, piece] < np.pi / 4)[:, None]
    al, A, mu, cos_m, sin_m, ox, oy = (q[node, None] for q in (alpha, A, mu, cos_m, sin_m,
                                                               ox, oy))
    with np.errstate(divide="ignore"):  # tan(0) / alpha = 0
        lo = np.where(use_v, np.arcsinh(np.tan(ta)[:, None] / al), ta[:, None])
        hi = np.where(use_v, np.arcsinh(np.tan(np.minimum(tb, np.pi / 4))[:, None] / al),
                      tb[:, None])
    x, w_theta = _gauss_legendre(order_theta)
    var = lo + (hi - lo) * x
    use_theta = ~use_v
    use_v, use_theta = (np.broadcast_to(u, var.shape) for u in (use_v, use_theta))
    # sin, cos theta_m and dxi / dvar: of v (tan theta_m = alpha sinh v), else of theta_m
    sinh_v = np.sinh(var, where=use_v, out=np.zeros_like(var))
    cos_t = 1.0 / np.sqrt(1.0 + (al * sinh_v) ** 2)
    sin_t = al * sinh_v * cos_t
    np.sin(var, where=use_theta, out=sin_t)
    np.cos(var, where=use_theta, out=cos_t)
    cosh2 = 1.0 + sinh_v * sinh_v
    dxi = 2.0 * sinh_v / (cosh2 * np.sqrt(cosh2))
    a2 = al * al
    np.divide(2.0 * a2 * sin_t * cos_t, (a2 * cos_t * cos_t + sin_t * sin_t) ** 2,
              where=use_theta, out=dxi)
    c = A * sin_t + mu * cos_t
    wi_z = 2.0 * c * cos_t - mu
    wi_x = 2.0 * c * sin_t * cos_m - ox
    wi_y = 2.0 * c * sin_t * sin_m - oy
    S_i = np.sqrt(wi_z * wi_z + (alpha_x * wi_x) ** 2 + (alpha_y * wi_y) ** 2)
    g = 2.0 * wi_z / (wi_z * S_o[direction[node], None] + mu * S_i)  # G2 / mu_o
    weight = ((hi - lo) * w_psi[node, None]) * w_theta * dxi * (c / cos_t) * g
    F = np.asarray(fresnel(c * c), dtype=np.float64)
    F = F[..., None] if F.ndim == 2 else F
    per_piece = np.einsum("pq,pqc->pc", weight, F)
    owner = direction[node]
    return np.stack([np.bincount(owner, weights=per_piece[:, ch], minlength=n)
                     for ch in range(per_piece.shape[-1])], axis=-1)


@functools.lru_cache(maxsize=4)
def _gauss_legendre(order: int):
    """Gauss-Legendre nodes and weights on [0, 1] (read-only)."""
    x, w = np.polynomial.legendre.leggauss(order)
    x, w = 0.5 * (x + 1.0), 0.5 * w
    x.flags.writeable = w.flags.writeable = False
    return x, w


class AzimuthalTable:
    """E_F - E_reference ``(..., 3)`` of an anisotropic ``ReferencedReflection`` over wo:
    ``AZIMUTH_NODES`` azimuths, each a column of one ``thin_film.AdaptiveCubic`` in mu_o of
    ``ANISOTROPIC_TOL`` (shared nodes, the kinks of the Fresnel factor among them), from
    ``_anisotropic_fresnel_energy``.

    The difference depends on phi only through cos^2 phi (the GGX is symmetric under
    phi -> -phi and phi -> pi - phi): the nodes are equally spaced in u on [0, pi / 2],
    tan u = k tan phi (``AZIMUTH_STRETCH``), and interpolated through all of them as a
    polynomial in cos 2u (Chebyshev-Lobatto, barycentric). A lookup interpolates linearly
    between ``AZIMUTH_GRID`` columns equally spaced in cos 2u, resampled from that
    polynomial at construction (a cubic in mu_o each; cos 2u is rational in wo), reading
    2 x 12 coefficients per wo. ``converged`` is False where mu_o would need more than
    ``ANISOTROPIC_MAX_NODES`` nodes.
    """

    def __init__(self, alpha_x: float, alpha_y: float, fresnel):
        kinks = _kinks(fresnel)
        splits = _clip_cosines(fresnel)
        self.stretch = np.clip(alpha_y / alpha_x, AZIMUTH_RATIO_FLOOR,
                               1.0 / AZIMUTH_RATIO_FLOOR) ** AZIMUTH_STRETCH
        u = np.linspace(0.0, np.pi / 2, AZIMUTH_NODES)
        phi = np.arctan2(np.sin(u), self.stretch * np.cos(u))

        def columns(mu):
            mu_all, phi_all = np.repeat(mu, phi.size), np.tile(phi, mu.size)
            return np.concatenate([
                _anisotropic_fresnel_energy(mu_all[i:i + _ANISOTROPIC_CHUNK],
                                            phi_all[i:i + _ANISOTROPIC_CHUNK], alpha_x, alpha_y,
                                            fresnel.from_cos2, kinks, splits)
                for i in range(0, mu_all.size, _ANISOTROPIC_CHUNK)]).reshape(mu.size, -1)
        #: the columns at the azimuth nodes (``AdaptiveCubic``)
        self.cubic = AdaptiveCubic(columns, ANISOTROPIC_TOL,
                                   np.concatenate([kinks, GRAZING_NODES]), start=16,
                                   max_nodes=ANISOTROPIC_MAX_NODES)
        self.converged = self.cubic.converged
        nodes = self.nodes = self.cubic.nodes
        y = np.linspace(-1.0, 1.0, AZIMUTH_GRID)
        values = np.einsum("gk,nkc->ngc", _lobatto_weights(np.cos(2.0 * u), y),
                           self.cubic.values.reshape(nodes.size, u.size, -1))
        channels = values.shape[-1]
        coefficients = np.stack(_cubic_coefficients(nodes, values.reshape(nodes.size, -1)),
                                axis=-1)  # (interval, column x channel, power)
        #: row (interval, column): its cubics in mu_o - node, channel by channel
        self._rows = coefficients.reshape(-1, channels * 4)
        # the interval of mu_o by a uniform grid of bins, as ``AdaptiveCubic``
        last = nodes.size - 2
        self._bins = 1 << int(np.clip(np.ceil(np.log2(nodes.size)) + 3, 6, 16))
        edges = np.arange(self._bins + 1) / self._bins
        self._first = np.clip(np.searchsorted(nodes, edges[:-1], side="right") - 1, 0, last)
        self._crowded = self._first != np.clip(np.searchsorted(nodes, edges[1:], side="left")
                                               - 1, 0, last)

    def __len__(self) -> int:
        return self.nodes.size

    def __call__(self, wo) -> np.ndarray:
        """The difference ``wo.shape[:-1] + (3,)`` at ``wo`` (mu_o clamped to [0, 1]); the
        caller zeroes it below the surface."""
        shape = wo.shape[:-1]
        wo = wo.reshape(-1, 3)
        mu = np.clip(wo[:, 2], 0.0, 1.0)
        # cos 2u = (w_x^2 - k^2 w_y^2) / (w_x^2 + k^2 w_y^2) as a column coordinate
        along, across = wo[:, 0] * wo[:, 0], self.stretch ** 2 * (wo[:, 1] * wo[:, 1])
        total = along + across
        y = np.divide(along - across, total, out=np.ones_like(total), where=total > 0.0)
        y += 1.0
        y *= 0.5 * (AZIMUTH_GRID - 1)
        column = np.minimum(y.astype(np.intp), AZIMUTH_GRID - 2)
        share = (y - column)[:, None]
        bin_ = np.minimum((mu * self._bins).astype(np.intp), self._bins - 1)
        interval = np.take(self._first, bin_)
        crowded = np.flatnonzero(np.take(self._crowded, bin_))
        if crowded.size:
            interval[crowded] = np.clip(np.searchsorted(self.nodes, mu[crowded],
                                                        side="right") - 1, 0, self.nodes.size - 2)
        t = mu - np.take(self.nodes, interval)
        row = interval * AZIMUTH_GRID + column
        left = np.take(self._rows, row, axis=0)
        c = np.take(self._rows, row + 1, axis=0)
        c -= left
        c *= share
        c += left
        powers = np.stack([np.ones_like(t), t, t * t, t * t * t], axis=-1)
        out = np.einsum("nck,nk->nc", c.reshape(t.size, -1, 4), powers)
        return out.reshape(shape + out.shape[-1:])


def _lobatto_weights(nodes, x) -> np.ndarray:
    """``(len(x), len(nodes))``: the weights of the polynomial interpolant through the
    Chebyshev-Lobatto ``nodes`` (cos(j pi / (K - 1)), any order) at ``x`` (barycentric form)."""
    w = (-1.0) ** np.arange(nodes.size)
    w[0] *= 0.5
    w[-1] *= 0.5
    difference = x[:, None] - nodes
    exact = difference == 0.0
    q = w / np.where(exact, 1.0, difference)
    q = np.where(exact.any(axis=-1, keepdims=True), exact.astype(np.float64), q)
    return q / q.sum(axis=-1, keepdims=True)


def _clip_cosines(model) -> np.ndarray:
    """The cosines ``(K,)`` where a clipped ``ThinFilm`` of scalar parameters enters or leaves
    0 in some channel (a colour outside linear Rec. 709): kinks of its colour that ``_kinks``
    does not list, bracketed on ``_CLIP_GRID`` steps in c and bisected to rounding."""
    if isinstance(model, _Difference):
        return np.unique(np.concatenate([_clip_cosines(model.a), _clip_cosines(model.b)]))
    if not (isinstance(model, ThinFilm) and model.clip and model.param_shape == ()):
        return np.zeros(0)

    def clipped(c):
        return np.asarray(model.from_cos2(c * c), dtype=np.float64).reshape(c.size, -1) <= 0.0
    c = np.linspace(0.0, 1.0, _CLIP_GRID + 1)
    state = clipped(c)
    step, channel = np.nonzero(state[1:] != state[:-1])
    if step.size == 0:
        return np.zeros(0)
    lo, hi, inside = c[step], c[step + 1], state[step, channel]
    for _ in range(48):
        mid = 0.5 * (lo + hi)
        same = clipped(mid)[np.arange(mid.size), channel] == inside
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    return np.unique(0.5 * (lo + hi))


def _kinks(model) -> np.ndarray:
    """The cosines ``(K,)`` where a Fresnel model is not analytic (critical angles of total
    internal reflection), as far as its type tells."""
    if isinstance(model, _Difference):
        return np.unique(np.concatenate([_kinks(model.a), _kinks(model.b)]))
    if isinstance(model, ThinFilm):
        return model.critical_cosines()
    if isinstance(model, ExactDielectric):
        eta = np.ravel(model.eta)
    elif isinstance(model, ExactConductor):
        eta = model.eta[model.k == 0.0]
    else:
        return np.zeros(0)
    eta = eta[eta < 1.0]
    return np.sqrt((1.0 - eta) * (1.0 + eta))


class _Difference(Fresnel):
    """F_a - F_b ``(..., 3)`` of two Fresnel models (None: F = 1), a signed factor for the
    linear rule of ``ReferencedReflection`` only."""

    def __init__(self, a: Fresnel | None, b: Fresnel | None):
        self.a, self.b = a, b
        shapes = [() if m is None else m.param_shape for m in (a, b)]
        self.param_shape = None if None in shapes else np.broadcast_shapes(*shapes)

    def from_cos2(self, c2) -> np.ndarray:
        def rgb(model):
            if model is None:
                return np.ones(np.shape(c2) + (1,))
            value = np.asarray(model.from_cos2(c2), dtype=np.float64)
            return value[..., None] if value.shape == np.shape(c2) else value
        return rgb(self.a) - rgb(self.b)


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
        #: E_R from the lobe's slice where anisotropic, under ``config`` anisotropic_energy
        #: "exact" only: E_R alone is the coarsest part of a slice, which the default grid
        #: reads for the energy E_R + E_T of the Kulla-Conty terms
        source = slice_source(self.distribution)
        self.slices = source if source == "exact" else ""

    def __repr__(self) -> str:
        return f"DielectricReflection(eta={self.eta!r}, {self.distribution!r})"

    def _top_albedo(self, wo):
        """The table where isotropic; where anisotropic, the table at sqrt(alpha_x alpha_y)
        misses the true albedo by up to ~0.04 at grazing angles (either way), so a layer
        under it would gain energy: there E is ``quadrature.sampled_albedo`` (32 x 32
        visible normals per direction), interpolated from a grid over wo built once per lobe
        (``top_albedo.TopAlbedoGrid``; textured parameters: the rule at every distinct
        ``wo``), or, built exact, the slice's (a slice read from the grid is not used here:
        E_R alone is the coarsest part of a slice, ``docs/energy_models.md``)."""
        d = self.distribution
        if np.all((d.alpha_x == d.alpha_y) | d.smooth) or self.slices == "exact":
            return super()._top_albedo(wo)
        if self._param_shape() != ():
            return quadrature.sampled_albedo(self, wo)
        return grey(pick(wo[..., 2] > 0.0, TopAlbedoGrid.of(self)(wo), 0.0))

    def _albedo_table(self, wo, with_error=True):
        alpha, ratio = table_alpha(self.distribution), checked_ratio(self.eta)
        mu = np.clip(wo[..., 2], 0.0, 1.0)  # 1 + an ulp by rounding is 1
        light = sides(self.eta)[0]
        # exact anisotropic elements read their slices below: none integrates here
        aniso = is_anisotropic(self.distribution) if self.slices else np.False_
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
        if self.slices:
            E_s, error_s = slice_energy(self.eta, self.distribution, wo, with_error,
                                         "reflection", self.slices)
            aniso = np.asarray(aniso)[..., None]
            E = pick(aniso, grey(pick(up, E_s, 0.0)), E)
            if with_error:
                error = pick(aniso, grey(pick(up, error_s, 0.0)), error)
        smooth = self.distribution.smooth
        if np.any(smooth):  # the exact Fresnel, not its interpolation in eta
            smooth = smooth[..., None]
            E = pick(smooth, self._delta_albedo(wo), E)
            error = None if error is None else pick(smooth, 0.0, error)
        return E, error
