"""Rough dielectric interface: GGX microfacet reflection and refraction, both sides."""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf.bsdf import BSDFSample, Flags, Lobe
from adobe_bsdf.fresnel import _dielectric_k, _k_of_indices
from adobe_bsdf.lobes.energy_lookup import dielectric_energy, grey
from adobe_bsdf.microfacet import GGX
from adobe_bsdf.registry import CheckCase, register

__all__ = ["Dielectric", "interface_energy_scale"]


def _mirror_z(w, s):
    """Mirror ``w`` through the tangent plane where ``s < 0`` (s = +-1, shape (...))."""
    return np.concatenate([w[..., :2] * np.ones_like(s)[..., None], (w[..., 2] * s)[..., None]],
                          axis=-1)


class Dielectric(Lobe):
    """Rough dielectric boundary (Walter et al. 2007) between index 1 above and ``eta`` below.

    Reflection f_r = F(wo.h) D(h) G2 / (4 |cos o| |cos i|) (Walter eq. 20) and, for
    radiance transport, refraction (Walter eq. 21 with eta_o on the side of ``wo``)

        f_t = |wi.h| |wo.h| eta_o^2 (1 - F) D(h) G2 / (|cos o| |cos i| (eta_i wi.h + eta_o wo.h)^2)

    with the generalized half vector h = -(eta_o wo + eta_i wi). Light may arrive from
    either side: below the surface the interface has relative index 1 / eta. Sampling picks
    visible normals of ``wo`` and then reflection with probability F(wo.m), else refraction.
    Generalized reciprocity f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2 holds.

    Special cases: where both alphas are below ``ALPHA_MIN`` it is a smooth (delta)
    interface; where ``eta == 1`` there is no interface at all, and every sample passes
    straight through (wi = -wo, weight 1, a delta), at any roughness.

    Parameters
    ----------
    eta : array_like in (0, inf)
        n_below / n_above (e.g. 1.5 for glass under air, 1/1.5 for air under glass).
    alpha_x, alpha_y : array_like in [0, inf)
        GGX roughness (``alpha_y`` defaults to ``alpha_x``).
    masking : {"correlated", "separable"}
        See ``GGX``; the same G2 is used for reflection and transmission (design.md).
    """

    flags = Flags.REFLECTION | Flags.TRANSMISSION | Flags.GLOSSY | Flags.DELTA

    def __init__(self, eta, alpha_x, alpha_y=None, masking: str = "correlated"):
        self.eta = _params.real("eta", eta, 0.0, np.inf, lo_open=True)
        self.distribution = GGX(alpha_x, alpha_y, masking)

    def __repr__(self) -> str:
        d = self.distribution
        return (f"Dielectric(eta={self.eta}, alpha_x={d.alpha_x}, alpha_y={d.alpha_y}, "
                f"masking={d.masking!r})")

    def _fresnel_constants(self):
        """k = eta^2 - 1 and eta^2 of the interface seen from above, from below, and from
        the less dense side (where refraction's F is evaluated), each formed from the two
        indices (``fresnel._k_of_indices``)."""
        above = (_k_of_indices(self.eta, 1.0), self.eta * self.eta)
        below = (_k_of_indices(1.0, self.eta), 1.0 / (self.eta * self.eta))
        dense = self.eta >= 1.0
        light = tuple(np.where(dense, a, b) for a, b in zip(above, below, strict=True))
        return above, below, light

    def _F_from_light_side(self, cos_light):
        """F seen from the less dense side (no total internal reflection there)."""
        _, _, (k, eta2) = self._fresnel_constants()
        return _dielectric_k(cos_light, k, eta2)

    def _on_light_side(self, side):
        """Whether the side ``side`` (+1 above, -1 below) is the less dense one."""
        return (side > 0.0) == (self.eta >= 1.0)

    def _param_shape(self):
        return np.broadcast_shapes(self.eta.shape, self.distribution.param_shape)

    # -- geometry shared by eval and pdf --------------------------------------------------
    def _terms(self, wo, wi):
        """Everything eval and pdf need, computed on components in the frame where ``wo``
        is above (z mirrored where it is not). Call under ``np.errstate``.

        The indices of the two sides are kept apart (eta_o on the side of ``wo``, eta_i on
        the other) rather than as a ratio, so that f(wo, wi) and f(wi, wo) run through
        bitwise the same arithmetic: near eta = 1 the ratio 1/eta would carry a rounding
        error that the transmission denominator amplifies by 1 / |eta - 1|. The half vector
        is h = wo + wi for reflection and -(eta_o wo + eta_i wi) for transmission,
        unnormalised; h / |h| is turned to the upper side.

        Returns (valid, reflection, F, D(h), S(wo), T) with T = 4 (wo.h) |wi.h| (1 - F) /
        (eta_o wo.h + eta_i wi.h)^2 and eta_o, eta_i.
        """
        d = self.distribution
        ox, oy, oz = wo[..., 0], wo[..., 1], wo[..., 2]
        ix, iy, iz = wi[..., 0], wi[..., 1], wi[..., 2]
        below = oz < 0.0
        zo = np.abs(oz)
        zi = np.where(below, -iz, iz)
        eta_o = np.where(below, self.eta, 1.0)
        eta_i = np.where(below, 1.0, self.eta)
        reflection = zi > 0.0
        a = np.where(reflection, 1.0, -eta_o)
        b = np.where(reflection, 1.0, -eta_i)
        hx = a * ox
        hx += b * ix
        hy = a * oy
        hy += b * iy
        hz = a * zo
        hz += b * zi
        length2 = hx * hx
        length2 += hy * hy
        length2 += hz * hz
        length = np.sqrt(length2)
        inv = np.where(hz < 0.0, -1.0, 1.0) / length
        cos_oh = (ox * hx + oy * hy + zo * hz) * inv
        cos_ih = (ix * hx + iy * hy + zi * hz) * inv
        # facets must face wo (and, for refraction, be seen from below by wi)
        valid = (zo > 0.0) & (cos_oh > 0.0) & (self.eta != 1.0)
        valid &= np.where(reflection, cos_ih > 0.0, (cos_ih < 0.0) & (zi < 0.0))
        if np.any(d.smooth):
            valid = valid & ~d.smooth
        # The Fresnel term is ill-conditioned near eta = 1 and, seen from the denser side,
        # near the critical angle. So that it is bitwise the same for (wo, wi) and (wi, wo),
        # and matches the sampler, reflection uses wo.h = wi.h = |wo + wi| / 2 and refraction
        # the cosine on the less dense side (Stokes: the same value as from the other side;
        # there F is smooth, with no total-internal-reflection edge).
        light = self._on_light_side(np.where(below, -1.0, 1.0))
        cos_F = np.where(reflection, 0.5 * length, np.abs(np.where(light, cos_oh, cos_ih)))
        (k_a, eta2_a), (k_b, eta2_b), (k_l, eta2_l) = self._fresnel_constants()
        F = _dielectric_k(cos_F, np.where(reflection, np.where(below, k_b, k_a), k_l),
                          np.where(reflection, np.where(below, eta2_b, eta2_a), eta2_l))
        den_t = eta_o * cos_oh
        den_t += eta_i * cos_ih
        T = 4.0 * cos_oh * np.abs(cos_ih) * (1.0 - F) / (den_t * den_t)
        D = d.D_of_sum(hx, hy, np.abs(hz), length2)
        return valid, reflection, F, D, d.projected(ox, oy, zo), T, zi, eta_o, eta_i

    def _f(self, wo, wi, valid, reflection, F, D, s_o, T, zi, eta_o):
        d = self.distribution
        V = d.V_of(np.abs(wo[..., 2]), s_o, np.abs(zi), d.projected(wi[..., 0], wi[..., 1], zi))
        f = np.where(valid, np.where(reflection, F, eta_o * eta_o * T) * D * V, 0.0)
        return np.broadcast_to(f[..., None], f.shape + (3,))

    @staticmethod
    def _p(wo, valid, reflection, F, D, s_o, T, eta_i):
        """pdf_r = F D_wo(h) / (4 wo.h), pdf_t = (1 - F) D_wo(h) eta_i^2 |wi.h| / den_t^2
        with D_wo(h) / (4 wo.h) = D(h) / (2 (|cos o| + S(wo))) (Heitz 2018 eq. 3)."""
        P = D / (2.0 * (np.abs(wo[..., 2]) + s_o))
        return np.where(valid, P * np.where(reflection, F, eta_i * eta_i * T), 0.0)

    def _eval(self, wo, wi):
        with np.errstate(divide="ignore", invalid="ignore"):
            valid, reflection, F, D, s_o, T, zi, eta_o, _ = self._terms(wo, wi)
            return self._f(wo, wi, valid, reflection, F, D, s_o, T, zi, eta_o)

    def _pdf(self, wo, wi):
        with np.errstate(divide="ignore", invalid="ignore"):
            valid, reflection, F, D, s_o, T, _, _, eta_i = self._terms(wo, wi)
            return self._p(wo, valid, reflection, F, D, s_o, T, eta_i)

    def _eval_pdf(self, wo, wi):
        with np.errstate(divide="ignore", invalid="ignore"):
            valid, reflection, F, D, s_o, T, zi, eta_o, eta_i = self._terms(wo, wi)
            return (self._f(wo, wi, valid, reflection, F, D, s_o, T, zi, eta_o),
                    self._p(wo, valid, reflection, F, D, s_o, T, eta_i))

    def _energy_scale(self, wo, wi):
        return interface_energy_scale(self.eta, wo, wi)

    def _albedo_table(self, wo, with_error=True):
        """E_R + E_T of the tables of ``adobe_bsdf.tables`` at alpha = sqrt(alpha_x alpha_y)
        (1 where the interface is smooth or index-matched)."""
        return tuple(map(grey, dielectric_energy(self.eta, self.distribution, wo, with_error)))

    # -- sampling -------------------------------------------------------------------------
    def _sample(self, wo, u):
        """Visible normal m of ``wo`` (mirrored above), then reflection with probability
        F(wo.m), else refraction (Snell's law in vector form, pbrt-v4 §9.3); only the chosen
        branch's direction, masking and density are computed."""
        d = self.distribution
        ox, oy, oz = wo[..., 0], wo[..., 1], wo[..., 2]
        below = oz < 0.0
        zo = np.abs(oz)
        eta = np.where(below, 1.0 / self.eta, self.eta)  # n on the far side / n on wo's side
        shape = np.broadcast_shapes(eta.shape, u.shape[:-1], d.smooth.shape)
        smooth = np.broadcast_to(d.smooth, shape)
        mx, my, mz = d.sample_visible_xyz(ox, oy, zo, u[..., 1], u[..., 2])
        cos_om = ox * mx + oy * my + zo * mz
        inv_eta = 1.0 / eta
        sin2_t = inv_eta * inv_eta * np.maximum(0.0, 1.0 - cos_om * cos_om)
        refracted = sin2_t < 1.0
        cos_t = np.sqrt(np.maximum(0.0, 1.0 - sin2_t))  # |wt.m|
        # F as _terms computes it: from the less dense side (TIR where nothing refracts)
        light = self._on_light_side(np.where(below, -1.0, 1.0))
        F = np.where(refracted, self._F_from_light_side(np.where(light, cos_om, cos_t)), 1.0)
        choose_r = u[..., 0] < F
        # wi = a m - b wo: reflection 2 (wo.m) m - wo, refraction (cos_om / eta - cos_t) m
        # - wo / eta
        a = np.where(choose_r, 2.0 * cos_om, inv_eta * cos_om - cos_t)
        b = np.where(choose_r, 1.0, inv_eta)
        ix, iy, iz = a * mx - b * ox, a * my - b * oy, a * mz - b * zo
        ok = (zo > 0.0) & (cos_om > 0.0) & np.where(choose_r, iz > 0.0, refracted & (iz < 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            s_o = d.projected(ox, oy, zo)
            g = np.where(smooth, 1.0,
                         d.G2_over_G1_of(zo, s_o, np.abs(iz), d.projected(ix, iy, iz)))
            P = d.D_of_sum(mx, my, mz, 1.0) / (2.0 * (zo + s_o))  # D_wo(m) / (4 wo.m)
            den_t = cos_om - eta * cos_t  # 0 only for eta = 1 (handled below)
            pdf_t = (1.0 - F) * 4.0 * cos_om * P * eta * eta * cos_t / (den_t * den_t)
            pdf = np.where(smooth, np.where(choose_r, F, 1.0 - F),
                           np.where(choose_r, F * P, pdf_t))
        weight = np.where(choose_r, g, g / (eta * eta))  # radiance: eta_o^2 / eta_i^2
        lobe = np.where(smooth, int(Flags.DELTA), int(Flags.GLOSSY))
        flags = lobe | np.where(choose_r, int(Flags.REFLECTION), int(Flags.TRANSMISSION))
        # index-matched boundary: no interface, the light passes straight through
        matched = eta == 1.0
        if np.any(matched):
            ix, iy, iz = (np.where(matched, -c, i) for c, i in ((ox, ix), (oy, iy), (zo, iz)))
            ok = np.where(matched, zo != 0.0, ok)
            weight = np.where(matched, 1.0, weight)
            pdf = np.where(matched, 1.0, pdf)
            flags = np.where(matched, int(Flags.TRANSMISSION | Flags.DELTA), flags)
        ok = ok & (pdf > 0.0)
        wi = np.stack(np.broadcast_arrays(ix, iy, np.where(below, -iz, iz)), axis=-1)
        weight = np.where(ok, weight, 0.0)
        return BSDFSample(
            wi=np.where(ok[..., None], wi, 0.0),
            weight=np.repeat(weight[..., None], 3, axis=-1),
            pdf=np.where(ok, pdf, 0.0),
            flags=np.where(ok, flags, int(Flags.NONE)),
        )

    def _delta_albedo(self, wo):
        """1 where the interface is smooth or index-matched (and ``wo`` not grazing), else 0.

        A smooth interface reflects F and transmits (1 - F) of the energy (radiance
        (eta_o/eta_i)^2 (1 - F) times the energy factor (eta_i/eta_o)^2), F + (1 - F) = 1 (F = 1
        under total internal reflection); an index-matched one passes everything through.
        """
        delta = (self.distribution.smooth | (self.eta == 1.0)) & (wo[..., 2] != 0.0)
        return np.where(delta[..., None], 1.0, np.zeros(wo.shape[:-1] + (3,)))


def interface_energy_scale(eta, wo, wi):
    """(eta_i / eta_o)^2 for transmission pairs across an interface of relative index
    ``eta`` = n_below / n_above, 1 for reflection pairs (design.md)."""
    eta = np.where(wo[..., 2] < 0.0, 1.0 / eta, eta)
    return np.where(wo[..., 2] * wi[..., 2] < 0.0, eta * eta, 1.0)


def _straight_through(wo):
    return -np.asarray(wo, dtype=np.float64)


register(
    CheckCase("Dielectric eta=1.5 a=0.3", lambda: Dielectric(1.5, 0.3),
              cos_theta_o=(1.0, 0.5, 0.05, -0.5)),
    CheckCase("Dielectric eta=1/1.5 a=(0.5,0.2)", lambda: Dielectric(1 / 1.5, 0.5, 0.2),
              cos_theta_o=(0.9, 0.3, -0.7)),
    CheckCase("Dielectric eta=1.01 a=0.5", lambda: Dielectric(1.01, 0.5),
              cos_theta_o=(0.8, -0.8), width=0.01, peak=_straight_through),
    CheckCase("Dielectric eta=1 a=0.5", lambda: Dielectric(1.0, 0.5), cos_theta_o=(0.8, -0.3),
              expected_albedo=lambda wo: 1.0),
    CheckCase("Dielectric eta=1.5 smooth", lambda: Dielectric(1.5, 0.0),
              cos_theta_o=(0.8, -0.8), expected_albedo=lambda wo: 1.0),
)
