"""Anisotropic GGX (Trowbridge–Reitz) microfacet distribution with Smith masking.

Public API
----------
``GGX(alpha_x, alpha_y=None, masking="correlated")`` with ``D(m)``, ``lambda_(w)``, ``G1(w)``,
``G2(wo, wi)``, ``sample_visible(w, u2)``, ``pdf_visible(w, m)``.
``Beckmann(alpha_x, alpha_y=None, masking="correlated")``: the same interface.
``Mixture(narrow, wide, beta)``: (1 - beta) D_n + beta D_w with its compound Smith masking.
``distribution(model, alpha_x, alpha_y=None, masking="correlated")``: one of ``MODELS``.
``ALPHA_MIN``: alphas below it are smooth (see ``GGX``).

All functions take local-frame unit vectors ``(..., 3)`` (normal +z, alpha_x along +x) and
broadcast against the distribution's parameters.

References
----------
[Walter2007] microfacet models for refraction through rough surfaces.
[Heitz2014, eqs. 72 and 86] anisotropic GGX Lambda; [Heitz2014, eq. 99] height-correlated G2;
[Heitz2014, eq. 43] G1 G1.
[Heitz2018, eq. 3] the visible-normal density D_wo.
[DupuyBenyoub2023, Listing 3] visible-normal sampling with spherical caps.
"""

from __future__ import annotations

import numpy as np
from scipy import special

from adobe_bsdf import _params
from adobe_bsdf._channels import pick
from adobe_bsdf.frame import dot
from adobe_bsdf.sampling import azimuth

__all__ = ["GGX", "Beckmann", "Mixture", "MODELS", "distribution", "ALPHA_MIN",
           "MASKING"]

#: smallest alpha of a rough lobe. Where both alphas are below it the lobe is smooth (a delta
#: lobe); where only one is, that axis is raised to ALPHA_MIN (docs/conventions.md).
ALPHA_MIN = 1e-8

#: masking-shadowing forms: height-correlated Smith (pbrt-v4) or separable G1 G1 (Mitsuba 3)
MASKING = ("correlated", "separable")


#: |h|^2 below which ``D_of_sum`` rescales h: the fourth powers of smaller components would
#: leave the normal float64 range (grazing pairs of cosine ~1e-85 and below)
SMALL_LENGTH2 = 2.0**-400


#: the largest finite float64: values beyond it saturate there (``saturated``)
FLOAT_MAX = float(np.finfo(np.float64).max)
#: the smallest denominator whose reciprocal is finite (1 / FLOAT_MAX rounds down, and its
#: reciprocal overflows): denominators are clamped to it, so 1 / den <= FLOAT_MAX
DEN_MIN = float(np.nextafter(1.0 / FLOAT_MAX, 1.0))


def saturated(x):
    """``x`` with values beyond the float64 range rounded to ``FLOAT_MAX`` (in place where
    ``x`` is a writeable array). At grazing pairs with tiny roughness a BSDF value can exceed
    1.8e308 (f ~ 1 / (4 pi alpha^3 cos) for a mirror pair) while f cos stays finite; the
    lobe then returns the largest finite float64, as round-toward-zero would, never inf."""
    if isinstance(x, np.ndarray) and x.flags.writeable:
        return np.minimum(x, FLOAT_MAX, out=x)
    return np.minimum(x, FLOAT_MAX)


def rescaled(hx, hy, hz, length2):
    """``(hx, hy, hz, |h|^2)`` with h multiplied by a power of two (exactly) where
    |h|^2 < ``SMALL_LENGTH2``, so that its largest component lies in [0.5, 1): D depends on the
    direction of h only. Unchanged (the same objects) where no element is that small."""
    small = length2 < SMALL_LENGTH2
    if not np.any(small):
        return hx, hy, hz, length2
    largest = np.maximum(np.maximum(np.abs(hx), np.abs(hy)), np.abs(hz))
    exponent = pick(small, -np.frexp(largest)[1], 0)
    hx, hy, hz = (np.ldexp(c, exponent) for c in (hx, hy, hz))
    return hx, hy, hz, pick(small, hx * hx + hy * hy + hz * hz, length2)


def _stack(x, y, z) -> np.ndarray:
    """Components (broadcast against each other) to vectors ``(..., 3)``."""
    return np.stack(np.broadcast_arrays(x, y, z), axis=-1)


def _normalize(x, y, z):
    """(x, y, z) / |(x, y, z)| on components; ``x`` and ``y`` are scaled in place."""
    return _normalized(x, y, z)[:3]


def _normalized(x, y, z):
    """``_normalize`` and the length |(x, y, z)|: ``(x, y, z, length)``."""
    length = x * x
    length += y * y
    length += z * z
    length = np.sqrt(length, out=length if isinstance(length, np.ndarray) else None)
    inv = 1.0 / length
    x *= inv
    y *= inv
    return x, y, z * inv, length


class _Distribution(_params.Validated):
    """What every microfacet distribution shares: validated anisotropic alphas, the smooth
    (delta) limit below ``ALPHA_MIN``, the masking form, and safe alphas for divisions."""

    def __init__(self, alpha_x, alpha_y=None, masking: str = "correlated"):
        ax = _params.real("alpha_x", alpha_x, 0.0, np.inf)
        ay = ax if alpha_y is None else _params.real("alpha_y", alpha_y, 0.0, np.inf)
        self._init(ax, ay, _params.choice("masking", masking, MASKING))

    def _init(self, ax, ay, masking: str = "correlated"):
        """Store validated alphas (float64 arrays) and derive the smooth limit."""
        ax, ay = np.broadcast_arrays(ax, ay)
        self.smooth = (ax < ALPHA_MIN) & (ay < ALPHA_MIN)
        self.alpha_x = pick(self.smooth, ax, np.maximum(ax, ALPHA_MIN))
        self.alpha_y = pick(self.smooth, ay, np.maximum(ay, ALPHA_MIN))
        self.masking = masking
        # safe alphas for the divisions below (the smooth elements are masked afterwards)
        self._ax = pick(self.smooth, 1.0, self.alpha_x)
        self._ay = pick(self.smooth, 1.0, self.alpha_y)
        self._pi_ax_ay = np.pi * self._ax * self._ay

    def __repr__(self) -> str:
        return (f"{type(self).__name__}(alpha_x={self.alpha_x}, alpha_y={self.alpha_y}, "
                f"masking={self.masking!r})")

    @property
    def param_shape(self) -> tuple:
        """Batch shape of the alphas."""
        return self.alpha_x.shape

    @property
    def alpha_max(self) -> np.ndarray:
        """max(alpha_x, alpha_y): the lobe's widest extent, in slope."""
        return np.maximum(self.alpha_x, self.alpha_y)

    _ARRAYS = ("alpha_x", "alpha_y", "smooth", "_ax", "_ay", "_pi_ax_ay")

    def take(self, shape: tuple, index) -> _Distribution:
        """The distribution at the elements ``index`` of its parameters broadcast to
        ``shape`` and flattened; ``self`` if the parameters are scalars."""
        if self.param_shape == ():
            return self
        part = object.__new__(type(self))
        part.masking = self.masking
        for name in self._ARRAYS:
            value = np.broadcast_to(getattr(self, name), shape).reshape(-1)
            setattr(part, name, value[index])
        return part

    def _stretched_direction(self, wx, wy, wz):
        """w' = sign(w.z) w stretched to the alpha = 1 configuration and normalised, on
        components: (ax w'x, ay w'y, |w.z|) / |...|, the first step of visible-normal
        sampling (smooth elements use alpha = 1; their samples are replaced); and the
        length |...|, which is GGX's S(w) where the surface is rough: ``(x, y, z, length)``."""
        x = self._ax * wx
        y = self._ay * wy
        below = wz < 0.0
        if np.any(below):  # (times 1 elsewhere: exact)
            sign = pick(below, -1.0, 1.0)
            x *= sign
            y *= sign
        return _normalized(x, y, np.abs(wz))

    def _stretched(self, w):
        """|w.z| and the projected roughness term t = sqrt(ax^2 wx^2 + ay^2 wy^2), so that
        alpha(w) tan(theta) = t / |w.z| [Heitz2014, eq. 80]."""
        z = np.abs(w[..., 2])
        return z, np.hypot(self.alpha_x * w[..., 0], self.alpha_y * w[..., 1])

    # -- Smith masking through S(w) = |wz| (1 + 2 Lambda(w)) -------------------------------
    # Every Smith form below is a rational function of |wz| and S, exact for any
    # distribution whose ``projected`` returns S: G1 = 2 |wz| / (|wz| + S) and
    # 1 + Lambda(wo) + Lambda(wi) = (|zi| S_o + |zo| S_i) / (2 |zo| |zi|).
    def projected(self, x, y, abs_z):
        """S(w) = |wz| (1 + 2 Lambda(w)) from the components of w (|wz| given)."""
        raise NotImplementedError

    def D_of_sum(self, hx, hy, hz, length2, upper: bool = False):
        """D(h / |h|) of an unnormalised h with |h|^2 = ``length2``; 0 where hz <= 0 unless
        ``upper`` (the caller knows hz > 0, or masks). Inf or NaN where h = 0."""
        raise NotImplementedError

    def sample_visible_xyz(self, wx, wy, wz, u0, u1):
        """``sample_visible`` on components: returns (mx, my, mz)."""
        raise NotImplementedError

    def visible_and_projected(self, wx, wy, wz, u0, u1):
        """``(mx, my, mz, S(w))``: ``sample_visible_xyz`` and ``projected(wx, wy, |wz|)``
        (GGX shares the work)."""
        return (*self.sample_visible_xyz(wx, wy, wz, u0, u1), self.projected(wx, wy,
                                                                              np.abs(wz)))

    def _projected_alpha(self, w):
        """|w.z| and S(w) (``projected``)."""
        z = np.abs(w[..., 2])
        return z, self.projected(w[..., 0], w[..., 1], z)

    def G1(self, w) -> np.ndarray:
        """Smith masking G1(w) = 1 / (1 + Lambda(w)) = 2 |wz| / (|wz| + S(w)); 0 at wz = 0."""
        w = np.asarray(w, dtype=np.float64)
        z, s = self._projected_alpha(w)
        return pick(z > 0.0, 2.0 * z / pick(z > 0.0, z + s, 1.0), 0.0)

    def G2(self, wo, wi) -> np.ndarray:
        """Masking-shadowing of the pair (reflection or transmission; |cos| is used).

        correlated: 1 / (1 + Lambda(wo) + Lambda(wi)) = 2 |zo| |zi| / (|zi| S_o + |zo| S_i);
        separable: G1(wo) G1(wi).
        """
        if self.masking == "separable":
            return self.G1(wo) * self.G1(wi)
        zo, so = self._projected_alpha(np.asarray(wo, dtype=np.float64))
        zi, si = self._projected_alpha(np.asarray(wi, dtype=np.float64))
        den = zi * so + zo * si
        return pick(den > 0.0, 2.0 * zo * zi / pick(den > 0.0, den, 1.0), 0.0)

    def V(self, wo, wi) -> np.ndarray:
        """Visibility V = G2(wo, wi) / (4 |cos theta_o| |cos theta_i|), without cancellation.

        correlated: 1 / (2 (|zi| S_o + |zo| S_i)); separable: 1 / ((|zo| + S_o)(|zi| + S_i)).
        Finite at grazing angles (0 only if both directions are grazing and the surface
        smooth).
        """
        zo, so = self._projected_alpha(np.asarray(wo, dtype=np.float64))
        zi, si = self._projected_alpha(np.asarray(wi, dtype=np.float64))
        if self.masking == "separable":
            den = (zo + so) * (zi + si)
        else:
            den = 2.0 * (zi * so + zo * si)
        return pick(den > 0.0, 1.0 / pick(den > 0.0, den, 1.0), 0.0)

    def G2_over_G1(self, wo, wi) -> np.ndarray:
        """G2(wo, wi) / G1(wo): the weight of visible-normal sampling without Fresnel.

        correlated: |zi| (|zo| + S_o) / (|zi| S_o + |zo| S_i); separable: G1(wi).
        """
        if self.masking == "separable":
            return self.G1(wi)
        zo, so = self._projected_alpha(np.asarray(wo, dtype=np.float64))
        zi, si = self._projected_alpha(np.asarray(wi, dtype=np.float64))
        den = zi * so + zo * si
        return pick(den > 0.0, zi * (zo + so) / pick(den > 0.0, den, 1.0), 0.0)

    def V_of(self, abs_zo, s_o, abs_zi, s_i):
        """Visibility G2 / (4 |cos o| |cos i|) from |wz| and S of both directions (``V``), at
        most ``FLOAT_MAX`` (``saturated``)."""
        if self.masking == "separable":
            den = (abs_zo + s_o) * (abs_zi + s_i)
        else:
            den = abs_zi * s_o
            den += abs_zo * s_i
            den *= 2.0
        den = np.maximum(den, DEN_MIN, out=den if isinstance(den, np.ndarray) else None)
        return np.divide(1.0, den, out=den if isinstance(den, np.ndarray) else None)

    def G2_over_G1_of(self, abs_zo, s_o, abs_zi, s_i):
        """G2(wo, wi) / G1(wo) from |wz| and S of both directions (``G2_over_G1``)."""
        if self.masking == "separable":
            return 2.0 * abs_zi / (abs_zi + s_i)
        return abs_zi * (abs_zo + s_o) / (abs_zi * s_o + abs_zo * s_i)

    def pdf_visible(self, w, m) -> np.ndarray:
        """Density of visible normals D_w(m) = G1(w) max(0, w.m) D(m) / |wz| [Heitz2018, eq. 3].

        Written as 2 max(0, w'.m) D(m) / (|wz| + S(w)), finite at grazing ``w``. ``w`` is
        first turned to the upper hemisphere (w' = sign(wz) w), as ``sample_visible`` does.
        """
        w = np.asarray(w, dtype=np.float64)
        m = np.asarray(m, dtype=np.float64)
        z, s = self._projected_alpha(w)
        sign = pick(w[..., 2] < 0.0, -1.0, 1.0)
        cos_wm = np.maximum(0.0, sign * dot(w, m))
        return pick(s > 0.0, 2.0 * cos_wm * self.D(m) / pick(s > 0.0, z + s, 1.0), 0.0)

    def sample_visible(self, w, u2) -> np.ndarray:
        """Sample a microfacet normal m with density ``pdf_visible(w, m)`` (``u2`` of shape
        ``(..., 2)``; see ``sample_visible_xyz``)."""
        w = np.asarray(w, dtype=np.float64)
        u2 = np.asarray(u2, dtype=np.float64)
        return _stack(*self.sample_visible_xyz(w[..., 0], w[..., 1], w[..., 2],
                                               u2[..., 0], u2[..., 1]))


class GGX(_Distribution):
    """Anisotropic GGX normal distribution with Smith masking-shadowing.

    Parameters
    ----------
    alpha_x, alpha_y : array_like, in [0, inf)
        Roughness along the tangent (x) and bitangent (y); ``alpha_y`` defaults to ``alpha_x``.
    masking : {"correlated", "separable"}
        ``G2`` form: height-correlated 1 / (1 + Lambda(wo) + Lambda(wi)) ([Heitz2014, eq. 99];
        pbrt-v4) or separable G1(wo) G1(wi) ([Heitz2014, eq. 43]; Mitsuba 3).

    Notes
    -----
    ``smooth`` marks elements whose alphas are both below ``ALPHA_MIN``: there D is a Dirac
    delta, so ``D`` and ``pdf_visible`` return 0, ``sample_visible`` returns the normal and
    ``G1`` / ``G2`` are 1 (0 at exactly grazing directions).
    """

    # -- distribution ---------------------------------------------------------------------
    def D(self, m) -> np.ndarray:
        """Normal distribution D(m) ([Walter2007, eq. 33], anisotropic form).

        D(m) = 1 / (pi ax ay ((mx/ax)^2 + (my/ay)^2 + mz^2)^2) for mz > 0, else 0.
        """
        m = np.asarray(m, dtype=np.float64)
        e = (m[..., 0] / self._ax) ** 2 + (m[..., 1] / self._ay) ** 2 + m[..., 2] ** 2
        ok = (m[..., 2] > 0.0) & ~self.smooth
        return pick(ok, 1.0 / (np.pi * self._ax * self._ay * pick(ok, e * e, 1.0)), 0.0)

    def lambda_(self, w) -> np.ndarray:
        """Smith Lambda(w) = (sqrt(1 + (ax^2 wx^2 + ay^2 wy^2)/wz^2) - 1) / 2 [Heitz2014, eq. 86].

        Written without cancellation as (S - |wz|) / (2 |wz|) = s^2 / (2 |wz| (|wz| + S)).
        +inf at wz = 0 (the exact limit); 0 where the distribution is smooth.
        """
        w = np.asarray(w, dtype=np.float64)
        z, s = self._projected_alpha(w)
        s2 = s * s - z * z
        lam = pick(z > 0.0, s2 / pick(z > 0.0, 2.0 * z * (z + s), 1.0), np.inf)
        return pick(self.smooth & (z > 0.0), 0.0, lam)

    # -- component forms for the lobes' kernels (no validation, no stacking) ---------------
    def projected(self, x, y, abs_z):
        """S(w) = sqrt(wz^2 + ax^2 wx^2 + ay^2 wy^2) from the components of w (|wz| given),
        so that Lambda(w) = (S / |wz| - 1) / 2 [Heitz2014, eq. 86]."""
        s = self.alpha_x * x
        s *= s
        t = self.alpha_y * y
        t *= t
        s += t
        s += abs_z * abs_z
        return np.sqrt(s, out=s if isinstance(s, np.ndarray) else None)

    def D_of_sum(self, hx, hy, hz, length2, upper: bool = False):
        """D(h / |h|) of an unnormalised h with |h|^2 = ``length2`` ([Walter2007, eq. 33]
        rewritten: D = |h|^4 / (pi ax ay Q^2), Q = (hx/ax)^2 + (hy/ay)^2 + hz^2);
        0 where hz <= 0 unless ``upper`` (the caller knows hz > 0, or masks). Inf or NaN
        where h = 0 (the caller masks those); h of any length down to subnormal components
        (``rescaled``)."""
        hx, hy, hz, length2 = rescaled(hx, hy, hz, length2)
        q = hx / self._ax
        q *= q
        t = hy / self._ay
        t *= t
        q += t
        q += hz * hz
        q *= q
        q *= self._pi_ax_ay
        D = np.divide(length2 * length2, q)
        return D if upper else pick(hz > 0.0, D, 0.0)

    # -- visible normals ------------------------------------------------------------------
    def sample_visible_xyz(self, wx, wy, wz, u0, u1):
        """Visible normal (mx, my, mz) by the spherical-cap method of [DupuyBenyoub2023]:
        stretch w' = sign(wz) w to the hemisphere configuration, sample the cap of the unit
        sphere cut by the plane z = -w_h.z, add w_h, unstretch."""
        return self.visible_and_projected(wx, wy, wz, u0, u1)[:3]

    def visible_and_projected(self, wx, wy, wz, u0, u1):
        """``(mx, my, mz, S(w))``: the stretch of w's length is S(w) = |(ax wx, ay wy, wz)|
        (``projected``, the same operations in the same order: bit for bit), computed once;
        where an element is smooth S is ``projected``'s own."""
        ax, ay = self._ax, self._ay
        x, y, z, s = self._stretched_direction(wx, wy, wz)
        cos_p, sin_p = azimuth(u0)
        cz = (1.0 - u1) * (1.0 + z) - z
        sin_t = np.sqrt(np.clip(1.0 - cz * cz, 0.0, 1.0))  # the clip removes rounding only
        mx = (sin_t * cos_p + x) * ax
        my = (sin_t * sin_p + y) * ay
        mx, my, mz = _normalize(mx, my, cz + z)
        if np.any(self.smooth):
            mx, my, mz = (pick(self.smooth, v, c) for v, c in ((0.0, mx), (0.0, my),
                                                                   (1.0, mz)))
            s = pick(self.smooth, self.projected(wx, wy, np.abs(wz)), s)
        return mx, my, mz, s


#: bracket of the stretched visible slope in ``Beckmann.sample_visible``: erfc(40) underflows
SLOPE_MIN = -40.0


class Beckmann(_Distribution):
    """Anisotropic Beckmann normal distribution with Smith masking-shadowing.

    D(m) = exp(-((mx/ax)^2 + (my/ay)^2) / mz^2) / (pi ax ay mz^4) ([Walter2007, eq. 25],
    anisotropic form), Lambda(w) = (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)) with
    a = 1 / (alpha(w) tan theta) [Heitz2014, eq. 83]. Parameters, masking forms and the smooth
    limit as ``GGX``; [Barla2018, Table 2] compares it with GGX as a hazy-gloss lobe.
    """

    def D(self, m) -> np.ndarray:
        """Normal distribution D(m); 0 for m.z <= 0."""
        m = np.asarray(m, dtype=np.float64)
        ok = (m[..., 2] > 0.0) & ~self.smooth
        length2 = np.sum(m * m, axis=-1)
        return pick(ok, self.D_of_sum(m[..., 0], m[..., 1], m[..., 2], length2), 0.0)

    def lambda_(self, w) -> np.ndarray:
        """Smith Lambda(w), written as exp(-a^2) (1 / (a sqrt(pi)) - erfcx(a)) / 2 (erfc(a) =
        exp(-a^2) erfcx(a)), finite for large a; +inf at w.z = 0, 0 at normal incidence
        and where the distribution is smooth."""
        z, t = self._stretched(np.asarray(w, dtype=np.float64))
        with np.errstate(divide="ignore", invalid="ignore"):
            a = z / t  # inf at normal incidence, 0 at grazing
            lam = 0.5 * np.exp(-a * a) * (1.0 / (a * np.sqrt(np.pi)) - special.erfcx(a))
        lam = pick(t == 0.0, 0.0, pick(z == 0.0, np.inf, lam))
        return pick(self.smooth & (z > 0.0), 0.0, lam)

    def projected(self, x, y, abs_z):
        """S(w) = |wz| erf(a) + t exp(-a^2) / sqrt(pi), with t = sqrt(ax^2 wx^2 + ay^2 wy^2)
        and a = |wz| / t: [Heitz2014, eq. 83] as S = |wz| (1 + 2 Lambda), a sum of
        non-negative terms; |wz| at normal incidence (t = 0), t / sqrt(pi) at grazing."""
        t = np.hypot(self.alpha_x * x, self.alpha_y * y)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # a = inf: erf 1
            a = abs_z / t
            s = abs_z * special.erf(a) + t * np.exp(-a * a) / np.sqrt(np.pi)
        return pick(t > 0.0, s, np.abs(abs_z))  # |wz| at normal incidence, either side

    def D_of_sum(self, hx, hy, hz, length2, upper: bool = False):
        """D(h / |h|) of an unnormalised h: exp(-((hx/ax)^2 + (hy/ay)^2) / hz^2) |h|^4 /
        (pi ax ay hz^4); 0 where hz <= 0 unless ``upper``; h of any length (``rescaled``)."""
        hx, hy, hz, length2 = rescaled(hx, hy, hz, length2)
        hz2 = hz * hz
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            g = np.exp(-((hx / self._ax) ** 2 + (hy / self._ay) ** 2) / hz2)
            # exp(-e) = 0 (underflow, or h in the tangent plane) is the limit D = 0: the
            # other factor, (1 + tan^2)^2 / (pi ax ay), may then overflow
            D = pick(g > 0.0, g * (length2 / hz2) ** 2 / self._pi_ax_ay, 0.0)
        return D if upper else pick(hz > 0.0, D, 0.0)

    def sample_visible_xyz(self, wx, wy, wz, u0, u1):
        """Visible normal (mx, my, mz) after [HeitzdEon2014].

        Stretch w' = sign(w.z) w to alpha = 1 and rotate it into the x-z plane,
        (sin theta, 0, cos theta). There the visible slopes are independent: the slope along
        y has density exp(-y^2) / sqrt(pi) (y = erfinv(2 u1 - 1)); the slope along x has
        density proportional to (mu - x) exp(-x^2) for x < mu = cot theta, with CDF
        N(x) / N(mu), N(x) = mu sqrt(pi) erfc(-x) / 2 + exp(-x^2) / 2, solved for u0 by
        Newton's method safeguarded by bisection on [SLOPE_MIN, mu] to rounding. The slopes
        are rotated back, unstretched and turned into the normal (-x, -y, 1) / |...|.
        A uniform below 2^-54 is raised to it (at 0 the slope would be infinite).
        """
        shape = np.broadcast_shapes(np.shape(wz), np.shape(u0), np.shape(u1), self.param_shape)
        sx, sy, sz, _ = self._stretched_direction(wx, wy, wz)
        sin_t = np.hypot(sx, sy)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # sin_t subnormal
            cos_p = pick(sin_t > 0.0, sx / sin_t, 1.0)
            sin_p = pick(sin_t > 0.0, sy / sin_t, 0.0)
            mu = sz / sin_t  # +inf at normal incidence
        tiny = 2.0**-54  # the smallest u with 2 u - 1 > -1
        u0 = np.broadcast_to(np.maximum(u0, tiny), shape)
        u1 = np.maximum(u1, tiny)
        y = special.erfinv(2.0 * u1 - 1.0)
        x = _beckmann_visible_slope(np.broadcast_to(mu, shape), u0)
        px = self.alpha_x * (cos_p * x - sin_p * y)
        py = self.alpha_y * (sin_p * x + cos_p * y)
        mx, my, mz = _normalize(-px, -py, np.ones(shape))
        if np.any(self.smooth):
            mx, my, mz = (pick(self.smooth, v, c) for v, c in ((0.0, mx), (0.0, my),
                                                                   (1.0, mz)))
        return mx, my, mz


def _beckmann_visible_slope(mu, u):
    """The x in [SLOPE_MIN, mu] with N(x) = u N(mu), N(x) = mu sqrt(pi) erfc(-x) / 2 +
    exp(-x^2) / 2 (``Beckmann.sample_visible``); x = erfinv(2 u - 1) where mu = inf. Newton
    steps that leave the bracket are replaced by bisection; at most 100 steps (bisection
    alone would reach rounding in 60). Each element stops at its own convergence and the
    steps run on the elements not yet converged only, so its result does not depend on the
    rest of the batch (chunking is bit-identical) and a batch costs the steps its elements
    take, not the slowest element's count times the batch."""
    mu = np.asarray(mu, dtype=np.float64)
    u = np.asarray(u, dtype=np.float64)
    normal = np.isinf(mu)
    x0 = special.erfinv(2.0 * u - 1.0)
    if normal.all():
        return x0
    shape = np.broadcast_shapes(mu.shape, u.shape)
    root_pi_2 = 0.5 * np.sqrt(np.pi)

    def n_of(m, x):
        with np.errstate(over="ignore"):  # x^2 = inf near normal incidence: exp(-x^2) = 0
            return m * root_pi_2 * special.erfc(-x) + 0.5 * np.exp(-x * x)

    active = np.flatnonzero(~np.broadcast_to(normal, shape))  # the elements still iterating
    m = np.broadcast_to(mu, shape).reshape(-1)[active]
    target = np.broadcast_to(u, shape).reshape(-1)[active] * n_of(m, m)
    lo, hi = np.full(m.shape, SLOPE_MIN), m.copy()
    x = np.clip(np.broadcast_to(x0, shape).reshape(-1)[active], lo, hi)
    out = np.array(np.broadcast_to(x0, shape)).reshape(-1)
    for _ in range(100):
        g = n_of(m, x) - target
        lo = pick(g < 0.0, x, lo)
        hi = pick(g > 0.0, x, hi)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            step = x - g / ((m - x) * np.exp(-x * x))  # not finite: bisection instead
        inside = (step > lo) & (step < hi)
        new = pick(inside, step, 0.5 * (lo + hi))
        going = ~((g == 0.0) | (np.abs(new - x) <= 4e-16 * np.maximum(1.0, np.abs(x))))
        x = pick(g != 0.0, new, x)
        if not going.all():  # the converged elements are final: set aside
            done, keep = np.flatnonzero(~going), np.flatnonzero(going)
            np.put(out, active.take(done), x.take(done))
            active, m, target, lo, hi, x = (a.take(keep) for a in (active, m, target, lo, hi, x))
            if not active.size:
                break
    out[active] = x  # (any left after 100 steps)
    return out.reshape(shape)


#: the microfacet models a lobe can be built on (``distribution``)
MODELS = {"ggx": GGX, "beckmann": Beckmann}


def distribution(model: str, alpha_x, alpha_y=None, masking: str = "correlated"):
    """The distribution ``MODELS[model]`` with these alphas and masking form."""
    return MODELS[_params.choice("model", model, tuple(MODELS))](alpha_x, alpha_y, masking)


class Mixture(_Distribution):
    """The mixed distribution D = (1 - beta) D_n + beta D_w of two rough distributions
    ([Barla2018, §3], "intertwined" microsurfaces).

    Its Smith Lambda is linear in D, so Lambda = (1 - beta) Lambda_n + beta Lambda_w: the
    compound masking-shadowing of [Barla2018, §3], and S(w) = |wz| (1 + 2 Lambda) mixes with
    the same weights. Its visible normals are the mixture of the parts' visible normals with
    weights P_n = (1 - beta) (|wz| + S_n) / (|wz| + S), P_w = 1 - P_n ([Heitz2018, eq. 3] with
    G1 = 2 |wz| / (|wz| + S)); ``sample_visible_xyz`` picks the part with ``u0``.

    Parameters
    ----------
    narrow, wide : GGX or Beckmann
        Rough everywhere (no smooth elements), with the same masking form.
    beta : array_like in [0, 1]
        Weight of ``wide``.
    """

    def __init__(self, narrow: _Distribution, wide: _Distribution, beta):
        for name, part in (("narrow", narrow), ("wide", wide)):
            if not isinstance(part, (GGX, Beckmann)) or np.any(part.smooth):
                raise ValueError(f"{name} = {part!r}: allowed a GGX or Beckmann distribution "
                                 f"with every alpha >= ALPHA_MIN = {ALPHA_MIN}")
        if narrow.masking != wide.masking:
            raise ValueError(f"wide.masking = {wide.masking!r}: allowed the narrow part's "
                             f"{narrow.masking!r}")
        self.narrow, self.wide = narrow, wide
        self.beta = _params.real("beta", beta, 0.0, 1.0)
        self.masking = narrow.masking
        self.smooth = np.zeros(self.param_shape, dtype=bool)

    def __repr__(self) -> str:
        return f"Mixture({self.narrow!r}, {self.wide!r}, beta={self.beta})"

    @property
    def param_shape(self) -> tuple:
        return np.broadcast_shapes(self.narrow.param_shape, self.wide.param_shape,
                                   self.beta.shape)

    @property
    def alpha_max(self) -> np.ndarray:
        return np.maximum(self.narrow.alpha_max, self.wide.alpha_max)

    def take(self, shape: tuple, index) -> Mixture:
        if self.param_shape == ():
            return self
        part = object.__new__(Mixture)
        part.narrow = self.narrow.take(shape, index)
        part.wide = self.wide.take(shape, index)
        part.beta = np.broadcast_to(self.beta, shape).reshape(-1)[index]
        part.masking = self.masking
        part.smooth = np.zeros(np.shape(part.beta), dtype=bool)
        return part

    def _mix(self, narrow, wide):
        return (1.0 - self.beta) * narrow + self.beta * wide

    def D(self, m) -> np.ndarray:
        return self._mix(self.narrow.D(m), self.wide.D(m))

    def lambda_(self, w) -> np.ndarray:
        return self._mix(self.narrow.lambda_(w), self.wide.lambda_(w))

    def projected(self, x, y, abs_z):
        return self._mix(self.narrow.projected(x, y, abs_z), self.wide.projected(x, y, abs_z))

    def D_of_sum(self, hx, hy, hz, length2, upper: bool = False):
        return self._mix(self.narrow.D_of_sum(hx, hy, hz, length2, upper),
                         self.wide.D_of_sum(hx, hy, hz, length2, upper))

    def sample_visible_xyz(self, wx, wy, wz, u0, u1):
        """The narrow part's visible normal where u0 < P_n (``u0`` rescaled to [0, 1) inside
        the chosen interval), else the wide part's."""
        z = np.abs(wz)
        p_n = (1.0 - self.beta) * (z + self.narrow.projected(wx, wy, z))
        p_n /= z + self.projected(wx, wy, z)
        narrow = u0 < p_n
        with np.errstate(divide="ignore", invalid="ignore"):
            u0 = pick(narrow, u0 / p_n, (u0 - p_n) / (1.0 - p_n))
        u0 = np.clip(u0, 0.0, np.nextafter(1.0, 0.0))  # removes rounding only
        m_n = self.narrow.sample_visible_xyz(wx, wy, wz, u0, u1)
        m_w = self.wide.sample_visible_xyz(wx, wy, wz, u0, u1)
        return tuple(pick(narrow, a, b) for a, b in zip(m_n, m_w, strict=True))
