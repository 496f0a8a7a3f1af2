"""Rough dielectric interface: microfacet reflection and refraction, both sides."""

from __future__ import annotations

import math

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf._channels import pick
from adobe_bsdf.bsdf import Flags, Lobe, finished_sample
from adobe_bsdf.fresnel import Fresnel, _dielectric_k, _k_of_indices
from adobe_bsdf.lobes.energy_lookup import (
    MIN_TRANSMISSION_WIDTH,
    checked_ratio,
    dielectric_energy,
    grey,
    passes_through,
    slice_source,
    table_alpha,
)
from adobe_bsdf.lobes.film_energy import FilmEnergy
from adobe_bsdf.microfacet import distribution, saturated

__all__ = ["Dielectric", "interface_energy_scale", "passes_through", "MIN_TRANSMISSION_WIDTH"]

def _eta(eta) -> np.ndarray:
    """A relative index n_below / n_above, validated: (0, inf)."""
    return _params.real("eta", eta, 0.0, np.inf, lo_open=True)


def _film(film):
    """``film``, checked to be None or a ``fresnel.Fresnel`` model of known parameter shape."""
    if film is None or (isinstance(film, Fresnel) and film.param_shape is not None):
        return film
    raise ValueError(f"film = {film!r}: allowed None or a fresnel.Fresnel model, e.g. "
                     "thin_film.ThinFilm(thickness_nm, film_ior, eta)")


def _mirror_z(w, s):
    """Mirror ``w`` through the tangent plane where ``s < 0`` (s = +-1, shape (...)), into a
    new array of the broadcast shape."""
    out = np.empty(np.broadcast_shapes(w.shape[:-1], np.shape(s)) + (3,))
    out[..., 0], out[..., 1] = w[..., 0], w[..., 1]
    np.multiply(w[..., 2], s, out=out[..., 2])
    return out


def _seen_from(eta, side):
    """Fresnel constants (k = eta_rel^2 - 1, eta_rel^2) of the interface of relative index
    ``eta`` = n_below / n_above seen from the side ``side`` (+1 above, -1 below), each
    formed from the two indices (``fresnel._k_of_indices``)."""
    if side > 0.0:
        return _k_of_indices(eta, 1.0), eta * eta
    return _k_of_indices(1.0, eta), 1.0 / (eta * eta)


def _light_side(eta, side):
    """(Fresnel constants seen from the less dense side, whether ``side`` is that side)."""
    dense = eta >= 1.0
    if np.ndim(eta) == 0:
        return _seen_from(eta, 1.0 if dense else -1.0), (side > 0.0) == dense
    above, below = _seen_from(eta, 1.0), _seen_from(eta, -1.0)
    return (tuple(pick(dense, a, b) for a, b in zip(above, below, strict=True)),
            (side > 0.0) == dense)


class Dielectric(Lobe):
    """Rough dielectric boundary [Walter2007] between index 1 above and ``eta`` below.

    Reflection f_r = F(wo.h) D(h) G2 / (4 |cos o| |cos i|) [Walter2007, eq. 20] and, for
    radiance transport, refraction ([Walter2007, eq. 21] with eta_o on the side of ``wo``)

        f_t = |wi.h| |wo.h| eta_o^2 (1 - F) D(h) G2 / (|cos o| |cos i| (eta_i wi.h + eta_o wo.h)^2)

    with the generalized half vector h = -(eta_o wo + eta_i wi). Light may arrive from
    either side: below the surface the interface has relative index 1 / eta. Sampling picks
    visible normals of ``wo`` and then reflection with probability F(wo.m), else refraction.
    Generalized reciprocity f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2 holds.

    Special cases: where both alphas are below ``ALPHA_MIN`` it is a smooth (delta)
    interface; where ``eta == 1`` there is no interface at all, and every sample passes
    straight through (wi = -wo, weight 1, a delta), at any roughness. A rough interface
    whose transmitted lobe is too narrow for float64 (``passes_through``) passes straight
    through too, with the energy of the lobe it stands for: the limit G2(wo, -wo) / G1(wo)
    of the rough model as eta -> 1 (``_pass_energy``).

    Parameters
    ----------
    eta : array_like in (0, inf)
        n_below / n_above (e.g. 1.5 for glass under air, 1/1.5 for air under glass).
    alpha_x, alpha_y : array_like in [0, inf)
        Roughness (``alpha_y`` defaults to ``alpha_x``).
    masking : {"correlated", "separable"}
        See ``GGX``; the same G2 is used for reflection and transmission (design.md).
    model : {"ggx", "beckmann"}
        The microfacet distribution (GGX by default; ``Dielectric.over`` takes any of
        ``adobe_bsdf.microfacet``, e.g. a ``Mixture``). The energy tables exist for GGX only.
    """

    flags = Flags.REFLECTION | Flags.TRANSMISSION | Flags.GLOSSY | Flags.DELTA

    def __init__(self, eta, alpha_x, alpha_y=None, masking: str = "correlated",
                 model: str = "ggx", film=None):
        self._init(_eta(eta), distribution(model, alpha_x, alpha_y, masking), _film(film))

    @classmethod
    def over(cls, eta, microfacets, film=None) -> Dielectric:
        """The interface of index ``eta`` over ``microfacets``, any distribution of
        ``adobe_bsdf.microfacet``."""
        return cls._new(_eta(eta), microfacets, _film(film))

    def _init(self, eta, microfacets, film=None):
        self.eta = eta
        self.distribution = microfacets
        #: the thin film on the interface (a ``fresnel.Fresnel`` model of the cosine above
        #: it), or None
        self.film = film
        self._film_energy = None  # its energy difference, built on first use
        #: where the interface is a pass-through (``passes_through``)
        self.passes = passes_through(self.eta, microfacets)
        #: table albedo from the lobe's slice where anisotropic (``config`` anisotropic_energy)
        self.slices = slice_source(microfacets)

    def __repr__(self) -> str:
        film = "" if self.film is None else f", film={self.film!r}"
        return f"{type(self).__name__}.over({self.eta!r}, {self.distribution!r}{film})"

    def _param_shape(self):
        film = () if self.film is None else self.film.param_shape
        return np.broadcast_shapes(self.eta.shape, self.distribution.param_shape, film)

    # -- the thin film: its reflectance in place of F, per channel -------------------------
    def _film_ratio(self, F, cos_above, reflection, batch=None, index=None):
        """``(..., 3)``: F_film / F (reflection) or (1 - F_film) / (1 - F) (refraction), the
        factor that turns the film-free f and sample weights into the film's, F_film the
        film's reflectance at the facet cosine above the interface ``cos_above`` (NaN where
        the light reflects totally: F_film = F = 1 there, the factor 1; a lossless film
        reflects alike from both sides at corresponding angles, so either side's light
        reads it there). With ``index``, the pairs ``index`` of the flattened ``batch`` (a
        film of array parameters is evaluated on the whole batch and gathered)."""
        c2 = np.square(np.nan_to_num(cos_above, nan=1.0))
        film = self.film
        if index is not None and film.param_shape != ():
            full = np.ones(math.prod(batch))
            full[index] = c2
            F_film = np.asarray(film.from_cos2(full.reshape(batch))).reshape(-1, 3)[index]
        else:
            F_film = np.asarray(film.from_cos2(c2), dtype=np.float64)
        total = np.isnan(cos_above)[..., None]
        F = np.asarray(F, dtype=np.float64)[..., None]
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = (F_film / F) if reflection else (1.0 - F_film) / (1.0 - F)
        return np.where(total, 1.0, np.where(np.isfinite(ratio), ratio, 0.0))

    # -- eval and pdf: the pairs in four groups, each with its side's constants ----------
    def _eval(self, wo, wi):
        return self._grouped(wo, wi, True, False)[0]

    def _pdf(self, wo, wi):
        return self._grouped(wo, wi, False, True)[1]

    def _eval_pdf(self, wo, wi):
        return self._grouped(wo, wi, True, True)

    def _grouped(self, wo, wi, want_f: bool, want_pdf: bool):
        """``(f (..., 3) or None, pdf (...) or None)``.

        The pairs fall into four groups by the side of ``wo`` and by reflection (``wi`` on
        the same side) or refraction (the other side); pairs with a direction in the
        tangent plane are 0. Each group is gathered and evaluated in the frame where ``wo``
        is above (z mirrored below), with the indices and Fresnel constants of its side as
        scalars when the lobe's parameters are scalars (else gathered with the pairs).
        """
        batch = np.broadcast_shapes(wo.shape[:-1], wi.shape[:-1], self._param_shape())
        n = math.prod(batch)
        wo = np.broadcast_to(wo, batch + (3,)).reshape(n, 3)
        wi = np.broadcast_to(wi, batch + (3,)).reshape(n, 3)
        f = (np.zeros(n) if self.film is None else np.zeros((n, 3))) if want_f else None
        pdf = np.zeros(n) if want_pdf else None
        scalar = self._param_shape() == ()
        if not (scalar and (self.passes or self.distribution.smooth)):
            oz, iz = wo[:, 2], wi[:, 2]
            o_up, i_up, i_down = oz > 0.0, iz > 0.0, iz < 0.0
            if o_up.all():  # (as in a renderer's batches) no pair needs the other side
                groups = [(1.0, i_up, True), (1.0, i_down, False)]
            else:
                o_down = oz < 0.0
                groups = [(1.0, o_up & i_up, True), (1.0, o_up & i_down, False),
                          (-1.0, o_down & i_down, True), (-1.0, o_down & i_up, False)]
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                for side, mask, reflection in groups:
                    index = np.flatnonzero(mask)
                    if len(index):
                        self._group(wo, wi, batch, index, side, reflection, f, pdf)
        if f is not None:
            f = (np.broadcast_to(f.reshape(batch)[..., None], batch + (3,)) if f.ndim == 1
                 else f.reshape(batch + (3,)))
        return f, None if pdf is None else pdf.reshape(batch)

    def _group(self, wo, wi, batch, index, side, reflection, f, pdf):
        """Write f and pdf of the pairs ``index`` (``wo`` on the side ``side``: +1 above,
        -1 below; reflection or refraction) into ``f`` and ``pdf`` (None: not wanted).

        The indices of the two sides are kept apart (eta_o on the side of ``wo``, eta_i on
        the other) rather than as a ratio, so that f(wo, wi) and f(wi, wo) run through
        bitwise the same arithmetic: near eta = 1 the ratio 1/eta would carry a rounding
        error that the transmission denominator amplifies by 1 / |eta - 1|.
        """
        d = self.distribution.take(batch, index)
        eta = self.eta if self.eta.ndim == 0 else np.broadcast_to(
            self.eta, batch).reshape(-1)[index]
        wo, wi = np.take(wo, index, axis=0), np.take(wi, index, axis=0)
        if side < 0.0:
            wo[:, 2] *= -1.0
            wi[:, 2] *= -1.0
        ox, oy, zo = wo[:, 0], wo[:, 1], wo[:, 2]
        ix, iy, zi = wi[:, 0], wi[:, 1], wi[:, 2]
        s_o = d.projected(ox, oy, zo)
        if reflection:
            value, P, F, cos_above = self._reflect(d, eta, side, ox, oy, zo, ix, iy, zi, s_o)
        else:
            value, P, F, cos_above = self._refract(d, eta, side, ox, oy, zo, ix, iy, zi, s_o,
                                                   f is not None, pdf is not None)
        if d.smooth.ndim or self.eta.ndim:  # a texture: smooth or pass-through elements
            off = d.smooth | (self.passes if self.passes.ndim == 0 else np.broadcast_to(
                self.passes, batch).reshape(-1)[index])
            value = [None if v is None else pick(off, 0.0, v) for v in value]
        if f is not None:
            V = saturated(value[0] * d.V_of(zo, s_o, np.abs(zi), d.projected(ix, iy, zi)))
            if self.film is not None:
                V = V[:, None] * self._film_ratio(F, cos_above, reflection, batch, index)
            f[index] = V
        if pdf is not None:
            pdf[index] = P * value[1]

    @staticmethod
    def _reflect(d, eta, side, ox, oy, zo, ix, iy, zi, s_o):
        """Reflection (both directions above, after mirroring): ``([F D, F], P, F,
        cos_light)`` with h = wo + wi, F at wo.h = |wo + wi| / 2 (bitwise symmetric in wo,
        wi) from the side of ``wo`` (total internal reflection included),
        P = D_wo(h) / (4 wo.h) = D(h) / (2 (|cos o| + S(wo))) [Heitz2018, eq. 3] and
        cos_above the cosine at the facet above the interface (Snell's law; NaN under total
        internal reflection), where a film's reflectance is read."""
        hx = ox + ix
        hy = oy + iy
        hz = zo + zi
        length2 = hx * hx
        length2 += hy * hy
        length2 += hz * hz
        k, eta2 = _seen_from(eta, side)
        c = 0.5 * np.sqrt(length2)
        F = _dielectric_k(c, k, eta2)
        D = d.D_of_sum(hx, hy, hz, length2, upper=True)
        # c^2 on the other side: 1 - (1 - c^2) / eta_rel^2 = (k + c^2) / eta_rel^2
        if side > 0.0:
            cos_above = c
        else:
            other2 = (k + c * c) / eta2
            with np.errstate(invalid="ignore"):
                cos_above = np.where(other2 > 0.0, np.sqrt(other2), np.nan)
        return [F * D, F], D / (2.0 * (zo + s_o)), F, cos_above

    def _refract(self, d, eta, side, ox, oy, zo, ix, iy, zi, s_o, want_f, want_pdf):
        """Refraction (``wo`` above, ``wi`` below, after mirroring): ``([eta_o^2 T D,
        eta_i^2 T], P, F, cos_above)`` (cos_above: the facet cosine above) with the
        generalized half vector h = -(eta_o wo + eta_i wi) turned up,
        T = 4 (wo.h) |wi.h| (1 - F) / (eta_o wo.h + eta_i wi.h)^2 and F at the cosine on
        the less dense side (Stokes: the same value as from the other side; there F is
        smooth, with no total-internal-reflection edge). Facets must face ``wo`` and be
        seen from below by ``wi``."""
        eta_o, eta_i = (1.0, eta) if side > 0.0 else (eta, 1.0)
        hx = -eta_o * ox
        hx -= eta_i * ix
        hy = -eta_o * oy
        hy -= eta_i * iy
        hz = -eta_o * zo
        hz -= eta_i * zi
        length2 = hx * hx
        length2 += hy * hy
        length2 += hz * hz
        # h turned up; a facet in the tangent plane (hz = 0, a sampled normal with mz ~ 1e-16
        # rounds there) is turned to face wo, as the sampler's normal did
        inv = np.copysign(1.0 / np.sqrt(length2), pick(hz != 0.0, hz, ox * hx + oy * hy))
        cos_oh = ox * hx + oy * hy + zo * hz
        cos_oh *= inv
        cos_ih = ix * hx + iy * hy + zi * hz
        cos_ih *= inv
        (k, eta2), light = _light_side(eta, side)
        F = _dielectric_k(np.abs(pick(light, cos_oh, cos_ih)) if np.ndim(light)
                          else np.abs(cos_oh if light else cos_ih), k, eta2)
        den_t = eta_o * cos_oh
        den_t += eta_i * cos_ih
        T = 4.0 * cos_oh * np.abs(cos_ih) * (1.0 - F) / (den_t * den_t)
        valid = (cos_oh > 0.0) & (cos_ih < 0.0)
        T = pick(valid, T, 0.0)
        D = d.D_of_sum(hx, hy, np.abs(hz), length2, upper=True)  # the horizon's limit at hz = 0
        cos_above = np.abs(cos_oh if side > 0.0 else cos_ih)
        return ([eta_o * eta_o * T * D if want_f else None,
                 eta_i * eta_i * T if want_pdf else None], D / (2.0 * (zo + s_o)), F,
                cos_above)

    def _energy_scale(self, wo, wi):
        return interface_energy_scale(self.eta, wo, wi)

    def _albedo_table(self, wo, with_error=True):
        """E_R + E_T of the tables of ``adobe_bsdf.tables`` at alpha = sqrt(alpha_x alpha_y),
        or of the lobe's slice where anisotropic and built exact (1 where the interface is
        smooth or index-matched); with a film, plus its Delta (``film_energy``)."""
        E, error = map(grey, dielectric_energy(self.eta, self.distribution, wo, with_error,
                                               self.slices))
        energy = self.film_energy()
        if energy is not None:
            light = (wo[..., 2] > 0.0) == (self.eta >= 1.0)
            rough = (wo[..., 2] != 0.0) & ~self.distribution.smooth & ~self.passes
            E = E + np.where(rough[..., None], energy(np.abs(wo[..., 2]), light), 0.0)
        return E, error

    def film_reflectance(self, wo) -> np.ndarray:
        """``(..., 3)``: the film's reflectance for light along ``wo`` meeting the mean plane
        (a smooth interface's F), read at the cosine above the interface (1 under total
        internal reflection)."""
        mu = np.abs(wo[..., 2])
        below = wo[..., 2] < 0.0
        with np.errstate(invalid="ignore"):
            # from below, index eta: 1 - eta^2 (1 - mu^2) above
            above2 = 1.0 - self.eta * self.eta * (1.0 - mu * mu)
        c2 = np.where(below, np.maximum(above2, 0.0), mu * mu)
        F_film = np.asarray(self.film.from_cos2(c2), dtype=np.float64)
        return np.where((below & (above2 <= 0.0))[..., None], 1.0, F_film)

    def film_energy(self):
        """The film's ``film_energy.FilmEnergy`` (built on the first call), or None without
        a film, where the interface is smooth or index-matched, or its parameters are
        arrays (``ValueError``: the energy is tabulated once per lobe)."""
        if self.film is None or np.all(self.distribution.smooth) or np.all(self.passes):
            return None
        if self._film_energy is None:
            if not (np.ndim(self.eta) == 0 and self.film.param_shape == ()
                    and self.distribution.param_shape == ()):
                raise ValueError(
                    "film: a thin film on a rough translucent interface needs scalar "
                    "parameters (its energy is tabulated once per lobe); allowed scalar "
                    f"eta, alphas and film, got eta shape {np.shape(self.eta)}, alphas "
                    f"{self.distribution.param_shape}, film {self.film.param_shape}")
            self._film_energy = FilmEnergy(float(table_alpha(self.distribution)),
                                           float(checked_ratio(self.eta)), self.film,
                                           bool(self.eta >= 1.0))
        return self._film_energy

    # -- sampling -------------------------------------------------------------------------
    def _sample(self, wo, u):
        """Visible normal m of ``wo`` (mirrored above), then reflection with probability
        F(wo.m), else refraction (Snell's law in vector form, [Pharr2023, §9.3]); only the chosen
        branch's direction, masking and density are computed."""
        d = self.distribution
        ox, oy, oz = wo[..., 0], wo[..., 1], wo[..., 2]
        below = oz < 0.0
        any_below = bool(np.any(below))  # else eta and the side stay scalars (same values)
        zo = np.abs(oz)
        # n on the far side / n on wo's side
        eta = pick(below, 1.0 / self.eta, self.eta) if any_below else self.eta
        shape = np.broadcast_shapes(eta.shape, u.shape[:-1], d.smooth.shape)
        smooth = np.broadcast_to(d.smooth, shape)
        any_smooth = bool(np.any(smooth))  # (else the selections by it are the identity)
        mx, my, mz, s_o = d.visible_and_projected(ox, oy, zo, u[..., 1], u[..., 2])
        cos_om = ox * mx + oy * my + zo * mz
        inv_eta = 1.0 / eta
        sin2_t = inv_eta * inv_eta * np.maximum(0.0, 1.0 - cos_om * cos_om)
        refracted = sin2_t < 1.0
        cos_t = np.sqrt(np.maximum(0.0, 1.0 - sin2_t))  # |wt.m|
        # F as _refract computes it: from the less dense side (TIR where nothing refracts)
        (k, eta2), light = _light_side(self.eta, pick(below, -1.0, 1.0) if any_below else 1.0)
        F = _dielectric_k(pick(light, cos_om, cos_t) if np.ndim(light) else
                          (cos_om if light else cos_t), k, eta2)
        if not refracted.all():
            F = pick(refracted, F, 1.0)
        choose_r = u[..., 0] < F
        # wi = a m - b wo: reflection 2 (wo.m) m - wo, refraction (cos_om / eta - cos_t) m
        # - wo / eta
        a = pick(choose_r, 2.0 * cos_om, inv_eta * cos_om - cos_t)
        b = pick(choose_r, 1.0, inv_eta)
        ix, iy, iz = a * mx - b * ox, a * my - b * oy, a * mz - b * zo
        ok = (zo > 0.0) & (cos_om > 0.0) & pick(choose_r, iz > 0.0, refracted & (iz < 0.0))
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            g = d.G2_over_G1_of(zo, s_o, np.abs(iz), d.projected(ix, iy, iz))
            if any_smooth:
                g = pick(smooth, 1.0, g)
            P = d.D_of_sum(mx, my, mz, 1.0) / (2.0 * (zo + s_o))  # D_wo(m) / (4 wo.m)
            den_t = cos_om - eta * cos_t  # 0 only for eta = 1 (handled below)
            pdf_t = (1.0 - F) * 4.0 * cos_om * P * eta * eta * cos_t / (den_t * den_t)
            pdf = pick(choose_r, F * P, pdf_t)
            if any_smooth:
                pdf = pick(smooth, pick(choose_r, F, 1.0 - F), pdf)
        weight = pick(choose_r, g, g / (eta * eta))  # radiance: eta_o^2 / eta_i^2
        if self.film is not None:  # chosen by the film-free F: weigh by the film's factor
            c_above = pick(below, cos_t, cos_om) if any_below else cos_om
            c_above = pick(refracted | ~below, c_above, np.nan)
            weight = (np.broadcast_to(weight, shape)[..., None]
                      * np.where(choose_r[..., None],
                                 self._film_ratio(F, c_above, True),
                                 self._film_ratio(F, c_above, False)))
        lobe = pick(smooth, int(Flags.DELTA), int(Flags.GLOSSY)) if any_smooth else int(
            Flags.GLOSSY)
        flags = lobe | pick(choose_r, int(Flags.REFLECTION), int(Flags.TRANSMISSION))
        # a pass-through: the light goes straight on, with the energy of the lobe
        passes = np.broadcast_to(self.passes, shape)
        if np.any(passes):
            ix, iy, iz = (pick(passes, -c, i) for c, i in ((ox, ix), (oy, iy), (zo, iz)))
            ok = pick(passes, zo != 0.0, ok)
            weight = pick(passes, self._pass_energy(ox, oy, zo) / (eta * eta), weight)
            pdf = pick(passes, 1.0, pdf)
            flags = pick(passes, int(Flags.TRANSMISSION | Flags.DELTA), flags)
        wi = np.empty(shape + (3,))
        wi[..., 0], wi[..., 1], wi[..., 2] = ix, iy, pick(below, -iz, iz) if any_below else iz
        flags = pick(ok, flags, int(Flags.NONE))
        pdf, flags = (x if x.shape == shape else np.array(np.broadcast_to(x, shape))
                      for x in (pdf, flags))  # (the arrays are this call's own)
        weight = (np.repeat(np.broadcast_to(weight, shape)[..., None], 3, axis=-1)
                  if np.ndim(weight) == len(shape) or np.shape(weight)[-1:] != (3,)
                  or self.film is None else np.array(np.broadcast_to(weight, shape + (3,))))
        return finished_sample(wi, weight, pdf, flags, fresh=True)

    def _pass_energy(self, ox, oy, zo):
        """Energy a pass-through carries from ``wo`` (``zo`` = |cos o| > 0): 1 where
        ``eta == 1`` or smooth, else the rough transmission's limit as eta -> 1, where every
        refracted direction tends to -wo and 1 - F to 1: G2(wo, -wo) / G1(wo) (the sampling
        weight; (1 + Lambda) / (1 + 2 Lambda) for height-correlated masking, G1 separable)."""
        d = self.distribution
        s_o = d.projected(ox, oy, zo)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            # G2_over_G1_of(zo, s_o, zo, s_o) with zo cancelled: zo^2 underflows for
            # subnormal cosines (0 / 0); correlated (1 + L) / (1 + 2 L) = (zo + S) / (2 S)
            limit = (2.0 * zo / (zo + s_o) if d.masking == "separable"
                     else (zo + s_o) / (2.0 * s_o))
        return pick((self.eta == 1.0) | d.smooth, 1.0, limit)

    def _delta_albedo(self, wo):
        """The delta branches' energy (0 where ``wo`` is grazing): 1 where the interface is
        smooth, the pass-through's energy (``_pass_energy``) where it passes through, else 0.

        A smooth interface reflects F and transmits (1 - F) of the energy (radiance
        (eta_o/eta_i)^2 (1 - F) times the energy factor (eta_i/eta_o)^2), F + (1 - F) = 1 (F = 1
        under total internal reflection).
        """
        delta = (self.distribution.smooth | self.passes) & (wo[..., 2] != 0.0)
        energy = (self._pass_energy(wo[..., 0], wo[..., 1], np.abs(wo[..., 2]))
                  if np.any(self.passes) else 1.0)  # else only smooth elements: 1
        return pick(delta, energy, 0.0)[..., None] * np.ones(3)


def interface_energy_scale(eta, wo, wi):
    """(eta_i / eta_o)^2 for transmission pairs across an interface of relative index
    ``eta`` = n_below / n_above, 1 for reflection pairs (design.md)."""
    eta = pick(wo[..., 2] < 0.0, 1.0 / eta, eta)
    return pick(wo[..., 2] * wi[..., 2] < 0.0, eta * eta, 1.0)
