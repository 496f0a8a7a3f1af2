"""Fuzz: the multiple-scattering sheen of a linearly transformed cosine [Zeltner2022].

Public API
----------
``LTCSheen(color, roughness)``
    The fuzz lobe that [OpenPBR2026, §Fuzz] recommends: mu_i f(wi, wo) = color E(mu_o, alpha)
    D(wi | wo, alpha), D a normalised linearly transformed cosine [Heitz2016], sampled
    exactly; ``albedo(wo, "table")`` is the fit color E.
``albedo_fit(mu, roughness)``
    The fit E(mu, alpha) of the directional albedo.
``ltc_coefficients(mu, roughness)``
    The fitted entries (aInv, bInv) of the inverse transform M^-1.

[Zeltner2022] fits R_i (the albedo E here) and the transform to a volumetric layer of
fibre-like SGGX microflakes with multiple scattering, tabulated on a 32 x 32 grid of
(cos theta, alpha) with alpha >= 0.01; the closed forms below (a Gaussian in cos theta plus an
offset for E, rational functions for aInv and bInv) are fits of those tables, the ones used
for [OpenPBR2026, §Fuzz]. The lobe is a fit, not a scattering model: it is not reciprocal
(measured in ``docs/fuzz_measured.md``).

References
----------
[Zeltner2022] the lobe: mu_i f = C R_i D_o(M^-1 w / |M^-1 w|) |M^-1| / |M^-1 w|^3, with
M^-1 = [[A, 0, B], [0, A, 0], [0, 0, 1]] in a frame whose X axis is wo projected onto the
surface.
[Heitz2016, §3] the density of a linearly transformed distribution and its sampling.
[OpenPBR2026, §Fuzz] the fuzz layer F f_fuzz + (1 - F E) f_below, E that of white fuzz.
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _memo, _params
from adobe_bsdf._channels import pick, tinted
from adobe_bsdf.bsdf import Flags, SupportLobe, finished_sample, luminance
from adobe_bsdf.microfacet import saturated
from adobe_bsdf.sampling import cosine_hemisphere

__all__ = ["LTCSheen", "albedo_fit", "ltc_coefficients"]

_SQRT_2PI = float(np.sqrt(2.0 * np.pi))


# -- the fits of [OpenPBR2026, §Fuzz]; x = cos theta_o, y = alpha, both in [0, 1] ---------------
def _albedo_fit(x, y):
    """E(x, y) = exp(-((x - m) / s)^2 / 2) / (s sqrt(2 pi)) + o, clamped to [0, 1].

    s, m and o vanish with y; they are written s = y s^, m = y m^, o = y o^, so that
    (x - m) / s = (x / y - m^) / s^ stays finite (or +inf, giving the Gaussian 0) for subnormal
    y. E(x, 0) = 0, the limit y -> 0 of the formula at every x > 0 (0 / 0 at y = 0)."""
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    # the coefficients on y as given (a scalar roughness: computed once, not per element)
    s_hat = (0.0206607 + 1.58491 * y) / (0.0379424 + y * (1.32227 + y))
    m_hat = (-0.193854 + y * (-1.14885 + y * (1.7932 - 0.95943 * y * y))) / (0.046391 + y)
    o_hat = (0.000654023 + (-0.0207818 + 0.119681 * y) * y) / (1.26264 + y * (-1.92021 + y))
    live = y > 0.0
    y_live = np.where(live, y, 1.0)
    with np.errstate(over="ignore", divide="ignore"):
        t = (x / y_live - m_hat) / s_hat
        gauss = np.exp(-0.5 * (t * t)) / (s_hat * _SQRT_2PI) / y_live
    E = np.clip(gauss + y * o_hat, 0.0, 1.0)
    shape = np.broadcast_shapes(x.shape, y.shape)
    return np.broadcast_to(E, shape).copy() if live.all() else pick(
        np.broadcast_to(live, shape), np.broadcast_to(E, shape), 0.0)


def _ltc(x, y):
    """``(aInv, bInv)``: aInv = (2.58126 x + 0.813703 y) y / (1 + 0.310327 x^2 + 2.60994 x y),
    bInv = sqrt(1 - x) (y - 1) y^3 / (0.0000254053 + 1.71228 x - 1.71506 x y + 1.34174 y^2).

    aInv > 0 for y > 0 and 0 at y = 0; bInv <= 0 (its denominator is positive on [0, 1]^2),
    0 at x = 1, y = 0 and y = 1."""
    a = (2.58126 * x + 0.813703 * y) * y / (1.0 + 0.310327 * x * x + 2.60994 * x * y)
    b = (np.sqrt(1.0 - x) * (y - 1.0) * (y * y * y)
         / (0.0000254053 + 1.71228 * x - 1.71506 * x * y + 1.34174 * y * y))
    return a, b


def albedo_fit(mu, roughness) -> np.ndarray:
    """The fit E(mu, alpha) of the fuzz's directional albedo [OpenPBR2026, §Fuzz] (``(...)``,
    the broadcast of both), in [0, 1].

    Parameters
    ----------
    mu : array_like in [0, 1]
        cos theta_o.
    roughness : array_like in [0, 1]
        alpha; E(mu, 0) = 0 (the limit alpha -> 0 at every mu > 0).
    """
    return _albedo_fit(_params.real("mu", mu, 0.0, 1.0),
                       _params.real("roughness", roughness, 0.0, 1.0))


def ltc_coefficients(mu, roughness) -> tuple[np.ndarray, np.ndarray]:
    """The fitted entries ``(aInv, bInv)`` of M^-1 = [[aInv, 0, bInv], [0, aInv, 0], [0, 0, 1]]
    [OpenPBR2026, §Fuzz] at cos theta_o = ``mu`` and alpha = ``roughness`` (both in [0, 1])."""
    x = _params.real("mu", mu, 0.0, 1.0)
    y = _params.real("roughness", roughness, 0.0, 1.0)
    return _ltc(*np.broadcast_arrays(x, y))


# -- the lobe -------------------------------------------------------------------------------------
def _frame(wo):
    """``(c, s)``: the lobe frame's X axis (c, s, 0), wo projected onto the surface and
    normalised; (1, 0) where that projection is 0 (wo = n, where bInv = 0 and every frame
    gives the same lobe)."""
    r = np.hypot(wo[..., 0], wo[..., 1])
    live = r > 0.0
    r = pick(live, r, 1.0)
    return pick(live, wo[..., 0] / r, 1.0), pick(live, wo[..., 1] / r, 0.0)


def _ratio(a, b, lx, ly, lz):
    """aInv / |M^-1 w|^2 at w = (lx, ly, lz) of the lobe frame, lz > 0, aInv > 0.

    M^-1 w = (aInv lx + bInv lz, aInv ly, lz) is divided by c = max(aInv, lz) first: its
    length is then of order 1 however small aInv and lz are; the ratio is saturated at the
    largest float (where it exceeds it, at lz, aInv < ~1e-308)."""
    c = np.maximum(a, lz)
    ra, rz = a / c, lz / c
    px, py = ra * lx + b * rz, ra * ly
    return saturated(ra / (px * px + py * py + rz * rz) / c)


class LTCSheen(SupportLobe):
    """The fuzz of [Zeltner2022]: f(wi, wo) = color E(mu_o, alpha) D(wi) / mu_i, reflection only.

    D is the clamped cosine D_o(w) = max(w_z, 0) / pi transformed by M^-1 = [[aInv, 0, bInv],
    [0, aInv, 0], [0, 0, 1]] in the frame (X, Y, n), X the projection of wo onto the surface
    [Heitz2016, §3]: with w' = M^-1 w = (aInv w_x + bInv w_z, aInv w_y, w_z),

        D(w) = D_o(w' / |w'|) |det M^-1| / |w'|^3 = (w_z / pi) (aInv / |w'|^2)^2,

    since D_o(w' / |w'|) = w'_z / (pi |w'|), w'_z = w_z and det M^-1 = aInv^2. M^-1 maps the
    upper hemisphere onto itself (w'_z = w_z), so D integrates to exactly 1 over it and
    mu_i f integrates to color E: E is the lobe's albedo, not an estimate of it. The cosine
    cancels: f = color E (aInv / |w'|^2)^2 / pi. The fits aInv(mu_o, alpha), bInv(mu_o, alpha)
    and E(mu_o, alpha) are those of ``ltc_coefficients`` and ``albedo_fit``.

    Parameters
    ----------
    color : colour in [0, 1], scalar or (..., 3)
        C_sheen of [Zeltner2022], fuzz_color of [OpenPBR2026, §Fuzz] (whose fuzz_weight
        scales the layer).
    roughness : array_like in [0, 1]
        alpha of [Zeltner2022], the square root of the fibres' SGGX cross section;
        fuzz_roughness of [OpenPBR2026, §Fuzz].

    Notes
    -----
    Small roughness: as alpha -> 0, aInv -> 0 and D concentrates on the horizon (w_z of order
    aInv), while E(mu_o, alpha) -> 0 at every mu_o > 0 (the Gaussian vanishes and the offset
    falls as ~5e-4 alpha; not uniformly: at mu_o = 0 the Gaussian grows as ~1.2e-13 / alpha).
    At alpha = 0 exactly (aInv = 0, where D = 0 / 0) the lobe is this limit, 0: f = 0, no
    sample succeeds, the albedo is 0. For 0 < alpha < 0.01 the fits are extrapolated below
    the grid they were fitted on; clamping alpha to [0.01, 1] instead would give alpha = 0 a
    fuzz. Where aInv underflows to 0 (alpha below ~1e-154) the lobe is 0 as at alpha = 0, and
    so is its albedo.

    Sampling [Heitz2016, §3]: a clamped-cosine direction v mapped by M = (M^-1)^-1 and
    normalised, computed as aInv M v = (v_x - bInv v_z, v_y, aInv v_z) (no division by aInv);
    pdf = D(wi), so weight = f mu_i / pdf = color E(mu_o, alpha) exactly, for every sample.

    ``albedo(wo, "table")`` is color E (with error 0: it is exact, as above); as the top of a
    layer the fuzz's albedo is that of white fuzz, E ones(3) [OpenPBR2026, §Fuzz]: the layer
    below is attenuated by 1 - E, untinted by the fuzz colour.

    Not reciprocal: E and M^-1 depend on mu_o alone (the fitted lobe bakes in the cosine of
    wi [Zeltner2022]); ``docs/fuzz_measured.md`` measures f(wo, wi) against f(wi, wo).
    """

    flags = Flags.REFLECTION | Flags.GLOSSY

    def __init__(self, color=1.0, roughness=0.5):
        self._init(_params.color("color", color, 0.0, 1.0),
                   _params.real("roughness", roughness, 0.0, 1.0))

    def _init(self, color, roughness):
        self.color, self.roughness = color, roughness
        self._param_shape()  # the parameters must broadcast together

    def __repr__(self) -> str:
        return f"LTCSheen(color={self.color}, roughness={self.roughness})"

    def _param_shape(self):
        try:
            return np.broadcast_shapes(self.color.shape[:-1], self.roughness.shape)
        except ValueError as exc:
            raise ValueError(f"color {self.color.shape} and roughness {self.roughness.shape} "
                             "do not broadcast") from exc

    # -- the fits at wo ---------------------------------------------------------------------
    def _fit(self, wo):
        """``(E, aInv, bInv)`` at cos theta_o = wo_z (clipped to [0, 1]); E = 0 where aInv = 0
        (alpha = 0, or aInv underflows: the lobe is 0 there). Once per call for this ``wo``
        (``_memo``): the layer's E_top, the sampling weight and f all need it."""
        return _memo.once(self, "fit", wo, self._fit_now)

    def _fit_now(self, wo):
        x = np.clip(wo[..., 2], 0.0, 1.0)
        a, b = _ltc(x, self.roughness)
        return pick(a > 0.0, _albedo_fit(x, self.roughness), 0.0), a, b

    def _albedo(self, wo):
        """The white lobe's albedo E ``(...)``: 0 where wo is not above the surface."""
        return pick(wo[..., 2] > 0.0, self._fit(wo)[0], 0.0)

    # -- eval and pdf -----------------------------------------------------------------------
    def _support(self, wo, wi):
        """Both directions above the surface, alpha > 0 (where aInv underflows to 0 the
        ratio of ``_ratio`` is 0: f = D = 0)."""
        return (wo[..., 2] > 0.0) & (wi[..., 2] > 0.0) & (self.roughness > 0.0)

    def _terms(self, wo, wi):
        """``(E, aInv / |M^-1 wi|^2)`` with wi in the lobe frame."""
        E, a, b = self._fit(wo)
        c, s = _frame(wo)
        lx = c * wi[..., 0] + s * wi[..., 1]
        ly = c * wi[..., 1] - s * wi[..., 0]
        return E, _ratio(a, b, lx, ly, wi[..., 2])

    def _f(self, E, t, up):
        """color E t^2 / pi, 0 outside ``up`` (E t first: E = 0 gives 0 at any t)."""
        f = saturated(E * t * t / np.pi)
        return tinted(f if up is None else pick(up, f, 0.0), self.color)

    @staticmethod
    def _D(wz, t, up):
        """D = w_z t^2 / pi, 0 outside ``up``."""
        D = saturated(wz * t * t / np.pi)
        return D if up is None else pick(up, D, 0.0)

    def _eval_kernel(self, wo, wi, up):
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            return self._f(*self._terms(wo, wi), up)

    def _pdf_kernel(self, wo, wi, up):
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            return self._D(wi[..., 2], self._terms(wo, wi)[1], up)

    def _eval_pdf_kernel(self, wo, wi, up):
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            E, t = self._terms(wo, wi)
            return self._f(E, t, up), self._D(wi[..., 2], t, up)

    # -- sampling ---------------------------------------------------------------------------
    def _sample(self, wo, u):
        E, a, b = self._fit(wo)
        v = cosine_hemisphere(u[..., 1:3])
        # aInv M v, normalised: the direction of M v
        px, py, pz = v[..., 0] - b * v[..., 2], v[..., 1], a * v[..., 2]
        norm = np.hypot(np.hypot(px, py), pz)
        ok = (wo[..., 2] > 0.0) & (pz > 0.0)
        norm = pick(ok, norm, 1.0)
        lx, ly, lz = px / norm, py / norm, pz / norm
        ok = ok & (lz > 0.0)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            pdf = self._D(lz, _ratio(a, b, lx, ly, lz), ok)
        c, s = _frame(wo)
        wi = np.stack(np.broadcast_arrays(c * lx - s * ly, s * lx + c * ly, lz), axis=-1)
        weight = tinted(E, self.color)
        return finished_sample(wi, weight, pdf, pick(ok, int(self.flags), int(Flags.NONE)))

    # -- albedo -----------------------------------------------------------------------------
    def _albedo_table(self, wo, with_error=True):
        """color E(cos theta_o, alpha), exact (the error is 0)."""
        E = self.color * self._albedo(wo)[..., None]
        return E, (np.zeros_like(E) if with_error else None)

    def _top_albedo(self, wo):
        """E of white fuzz, ``(..., 3)`` [OpenPBR2026, §Fuzz]: the fuzz colour does not tint
        the layer below."""
        return tinted(self._albedo(wo), np.ones(3))

    def _sampling_weight(self, wo):
        """luminance(color) E, the lobe's albedo."""
        return luminance(self.color) * self._albedo(wo)
