"""Coat darkening: a base looks darker under a coat because the coat reflects part of the
light leaving the base back down onto it, where the base absorbs some more
[OpenPBR2026, §Coat darkening; Portsmouth2025].

Public API
----------
``fresnel_average(eta)``        E_F = 2 int_0^1 F(mu, eta) mu d mu, by quadrature.
``fresnel_average_fit(eta)``    the specification's closed-form fit of E_F.
``internal_reflectance(eta)``   K = 1 - (1 - E_F(eta)) / eta^2: the share of diffuse light
                                inside a coat of index eta that its top reflects back down.
``coat_reflectance(eta, base_roughness, cos_theta=1)``
                                K interpolated from a smooth to a rough base's estimate.
``darkening(E_b, K, T2=1, variant="pr253")``
                                Delta, the darkening of a base of albedo E_b.
``base_factor(Delta, delta, T2=1, coverage=1)``
                                the colour that multiplies the base's BSDF.
``physical_darkening(E_b, eta, coat_alpha, T2, cos_theta=1, base_roughness=1)``
                                Delta_phys(wo) of the development branch ("dev_1.2"): the
                                light that an absorbing, smooth or rough coat lets out of a
                                base, over what the naive layering lets out.
``CoatTransport(eta, coat_alpha, T2, E_b)``
                                its per-material constants (computed once), ``.darkening``.
``Darkening(delta=1, base_roughness=1, variant="pr253", base_albedo=None, coat_alpha=0)``
                                the darkening as a parameter of ``composition.Layer``: its
                                base is multiplied by D(wo) = lerp(1, Delta(wo), delta).

A Lambertian base of albedo E_b under a smooth clear coat reflects, summing the bounces
between the two, E = F(mu_o) + (1 - F(mu_o)) E_b (1 - K) / (1 - E_b K) [OpenPBR2026,
§Coat darkening]: the albedo-scaled layer's base times Delta = (1 - K) / (1 - E_b K). With
the coat's two-way transmittance at normal incidence T^2 (``coat_color``) on every path
through it, [Portsmouth2025] writes Delta = (1 - K) / (1 - K E_b T^2) and multiplies the base
by lerp(1, lerp(1, Delta, delta) T^2, C) (coat_darkening delta, coverage C): at delta = 0 the
coat is layered naively on the base tinted by T^2 (the albedo E_spec + T^2 E_b (1 - E_spec),
no shift of hue), at delta = 1 the darkening is physical. ``variant="v1.1.1"`` is the
released specification's Delta = (1 - K) / (1 - E_b K), with T^2 outside.

``variant="dev_1.2"`` keeps [Portsmouth2025]'s definition, the albedo
E = E_spec + (1 - E_spec) lerp(T^2 E_b, E'_c, delta) with E'_c the physical albedo of what
lies under the coat per unit energy entering it, but computes E'_c from the transport in an
absorbing coat, smooth or rough, instead of [Portsmouth2025]'s first-order Delta, which
misses the longer paths of the light the base spreads (``physical_darkening``: the
derivation, and the measured agreement with random walks in
``docs/coat_darkening_measured.md``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf._channels import pick
from adobe_bsdf.fresnel import _dielectric
from adobe_bsdf.microfacet import ALPHA_MIN, GGX

__all__ = ["fresnel_average", "fresnel_average_fit", "internal_reflectance", "coat_reflectance",
           "darkening", "base_factor", "physical_darkening", "CoatTransport", "Darkening",
           "VARIANTS", "PHYSICAL", "ALL_VARIANTS"]

#: the darkening formulas of ``darkening``: [Portsmouth2025] (T^2 inside) and [OpenPBR2026]
#: (outside)
VARIANTS = ("pr253", "v1.1.1")
#: the development branch's physical darkening (``physical_darkening``)
PHYSICAL = "dev_1.2"
#: every variant of ``Darkening``
ALL_VARIANTS = VARIANTS + (PHYSICAL,)
#: Gauss–Legendre points of ``fresnel_average`` (per piece)
_POINTS = 96


def fresnel_average(eta) -> np.ndarray:
    """E_F(eta) = 2 int_0^1 F(mu, eta) mu d mu, the hemispherical average of the exact
    dielectric Fresnel seen from the side of relative index ``eta`` in (0, inf) (eta < 1: the
    dense side, total internal reflection below the critical cosine). Gauss–Legendre in
    s = sqrt(mu - mu_c) from the critical cosine mu_c (0 for eta >= 1), where F has its square
    root; F = 1 below it."""
    eta = _params.real("eta", eta, 0.0, np.inf, lo_open=True)
    x, w = np.polynomial.legendre.leggauss(_POINTS)
    s, w = 0.5 * (x + 1.0), 0.5 * w
    mu_c = np.sqrt(np.maximum(1.0 - eta * eta, 0.0))[..., None]
    mu = mu_c + (1.0 - mu_c) * s * s  # d mu = 2 (1 - mu_c) s ds
    F = _dielectric(mu, eta[..., None])
    return mu_c[..., 0] ** 2 + np.sum(w * 2.0 * mu * F * 2.0 * (1.0 - mu_c) * s, -1)


def fresnel_average_fit(eta) -> np.ndarray:
    """The specification's fit of E_F [OpenPBR2026, §Coat darkening]:
    ln((10893 eta - 1438.2) / (-774.4 eta^2 + 10212 eta + 1)) for eta >= 1, and
    1 - eta^2 (1 - E_F(1 / eta)) below (measured against ``fresnel_average`` in
    ``docs/coat_darkening.md``)."""
    eta = _params.real("eta", eta, 0.0, np.inf, lo_open=True)
    n = pick(eta >= 1.0, eta, 1.0 / eta)
    fit = np.log((10893.0 * n - 1438.2) / (-774.4 * n * n + 10212.0 * n + 1.0))
    return pick(eta >= 1.0, fit, 1.0 - eta * eta * (1.0 - fit))


def internal_reflectance(eta) -> np.ndarray:
    """K = 1 - (1 - E_F(eta)) / eta^2: of diffuse light inside a coat of relative index
    ``eta`` = n_coat / n_outside, the share its top reflects back down [OpenPBR2026, §Coat
    darkening]; by reciprocity it is E_F(1 / eta), the average seen from inside."""
    eta = _params.real("eta", eta, 0.0, np.inf, lo_open=True)
    return 1.0 - (1.0 - fresnel_average(eta)) / (eta * eta)


def coat_reflectance(eta, base_roughness, cos_theta=1.0) -> np.ndarray:
    """K = lerp(F(cos_theta, eta), internal_reflectance(eta), r) [OpenPBR2026, §Coat
    darkening]: a smooth base (r = 0) sends the light back up along the mirror direction,
    where the coat reflects F(cos_theta); a rough one (r = 1) diffusely, where it reflects the
    internal average."""
    eta = _params.real("eta", eta, 0.0, np.inf, lo_open=True)
    r = _params.real("base_roughness", base_roughness, 0.0, 1.0)
    c = _params.real("cos_theta", cos_theta, 0.0, 1.0)
    return _coat_reflectance(eta, r, c, internal_reflectance(eta))


def _coat_reflectance(eta, r, c, K_rough):
    """``coat_reflectance`` of validated arrays, ``K_rough`` its ``internal_reflectance``."""
    return (1.0 - r) * _dielectric(c, eta) + r * K_rough


def darkening(E_b, K, T2=1.0, variant: str = "pr253") -> np.ndarray:
    """Delta = (1 - K) / (1 - K E_b T2) [Portsmouth2025] or, ``variant="v1.1.1"``,
    (1 - K) / (1 - E_b K) [OpenPBR2026, §Coat darkening]; ``E_b`` the base's albedo (colour
    in [0, 1]), ``K`` the coat's internal reflectance in [0, 1], ``T2`` its two-way
    transmittance at normal incidence (colour in [0, 1]). 1 where K = 1 and E_b T2 = 1 (the
    limit of a lossless base under a fully reflecting coat is taken as no darkening)."""
    E_b = _params.color("E_b", E_b, 0.0, 1.0)
    K = np.asarray(_params.real("K", K, 0.0, 1.0))[..., None]
    T2 = _params.color("T2", T2, 0.0, 1.0)
    _params.choice("variant", variant, VARIANTS)
    return _darkening(E_b, K, T2, variant)


def _darkening(E_b, K, T2, variant):
    """``darkening`` of validated arrays (``K`` with a trailing axis of 1 or 3); for a batch
    of K ``(..., 1)`` and constant colours, channel by channel (the same operations)."""
    T2 = T2 if variant == "pr253" else 1.0
    if K.shape[-1:] == (1,) and np.shape(E_b) == (3,) and np.shape(T2) in ((), (3,)):
        k = K[..., 0]
        E_b, T2 = np.asarray(E_b), np.broadcast_to(T2, (3,))
        out = np.empty(k.shape + (3,))
        for c in range(3):
            den = 1.0 - k * E_b[c] * T2[c]
            out[..., c] = pick(den > 0.0, (1.0 - k) / pick(den > 0.0, den, 1.0), 1.0)
        return out
    loop = K * E_b * T2
    den = 1.0 - loop
    return pick(den > 0.0, (1.0 - K) / pick(den > 0.0, den, 1.0), 1.0)


def base_factor(Delta, delta, T2=1.0, coverage=1.0) -> np.ndarray:
    """lerp(1, lerp(1, Delta, delta) T2, C) [Portsmouth2025]: the colour that multiplies the
    base's BSDF under a coat of coverage C = ``coverage``, coat_darkening delta = ``delta``
    (both in [0, 1]) and two-way transmittance ``T2``."""
    Delta = _params.color("Delta", Delta, 0.0, 1.0)
    delta = np.asarray(_params.real("delta", delta, 0.0, 1.0))[..., None]
    T2 = _params.color("T2", T2, 0.0, 1.0)
    C = np.asarray(_params.real("coverage", coverage, 0.0, 1.0))[..., None]
    return 1.0 + C * (_lerp_from_one(Delta, delta) * T2 - 1.0)


def _lerp_from_one(x, t):
    """lerp(1, x, t) = 1 + t (x - 1)."""
    return 1.0 + t * (x - 1.0)


# -- the physical darkening (dev_1.2) -----------------------------------------------------

#: Gauss–Legendre points of each piece, [0, mu_c] and [mu_c, 1], of the cosine integrals
_COSINE_POINTS = 48
#: cosines of wo at which a rough coat's entry is integrated, uniform in
#: v = sign(mu - mu_c) sqrt|mu - mu_c| (``_entry_nodes``; linear interpolation in v)
_ENTRY_NODES = 65
#: the visible-normal rule of a rough interface: midpoint azimuths on the half circle (wo in
#: the xz plane: the integrand is even in the azimuth) times Gauss–Legendre heights
_AZIMUTHS, _HEIGHTS = 24, 32
#: the cosine at which the entry's grazing node (cos 0) is integrated
_GRAZING = 1e-4
#: elements whose colour sums are taken at once (about 15 MB of temporaries)
_BLOCK = 64
#: a mirror base's round trip D = E_b t^2 is taken times this: a lossless trap (E_b = T2 = 1,
#: light that the top reflects forever) is then a regular system, changed by 1e-12
_DAMPING = 1.0 - 1e-12


def physical_darkening(E_b, eta, coat_alpha, T2, cos_theta=1.0,
                       base_roughness=1.0) -> np.ndarray:
    """Delta_phys(wo) ``(..., 3)`` = E'_c(wo) / (T2 E_b): the physical albedo E'_c of what
    lies under a coat, per unit energy entering it, over the naive albedo T2 E_b
    [Portsmouth2025, eqs. 61-63], lerped from a smooth (mirror) base's estimate to a rough
    (Lambertian) one's by ``base_roughness`` r_b:

        Delta_phys = lerp(Delta_s, Delta_r, r_b).

    The coat has relative index ``eta`` = n_coat / n_outside in (0, inf) (below 1: the coat
    is the less dense side), GGX roughness ``coat_alpha`` in [0, 1] (0 smooth) and the
    two-way transmittance ``T2`` at normal incidence (a colour in [0, 1]: OpenPBR's
    coat_color), so that light crossing it along an internal cosine mu keeps
    t(mu) = T2^(1 / (2 mu)) per channel (an absorbing, non-scattering slab, as
    [OpenPBR2026, §Coat] makes the absorption view dependent); ``E_b`` is the base's albedo
    (a colour in [0, 1]) and ``cos_theta`` = |cos theta_o| in [0, 1].

    Derivation (a smooth coat first). Light from wo enters with 1 - F(mu_o) and refracts to
    the internal cosine mu_t (``mu_t`` = sqrt(1 - (1 - mu_o^2) / eta^2)), reaching the base
    with t(mu_t).

    - A Lambertian base reflects E_b, cosine-distributed. Of that light a share
      A = int_0^1 2 mu t(mu) (1 - R(mu)) d mu escapes through the top and a share
      K_T = int_0^1 2 mu t(mu)^2 R(mu) d mu comes back to the base (R the internal Fresnel
      reflectance at internal cosine mu, 1 beyond the critical angle; a specular reflection
      keeps mu), where it is again cosine-distributed. Summing the bounces,
      E'_c = t(mu_t) E_b A / (1 - E_b K_T) and
      Delta_r = t(mu_t) A / (T2 (1 - E_b K_T)). For a clear coat (T2 = 1),
      A = 1 - K and K_T = K = ``internal_reflectance(eta)``: Delta_r = (1 - K) / (1 - E_b K),
      the released specification's [OpenPBR2026, §Coat darkening].
    - A mirror base of albedo E_b sends the light back up along mu_t, where the top lets
      1 - F(mu_o) out and reflects F(mu_o) down again (F is the same from both sides of a
      refracted pair): E'_c = t^2 E_b (1 - F) / (1 - F E_b t^2), t^2 = T2^(1 / mu_t), and
      Delta_s = T2^(1 / mu_t - 1) (1 - F) / (1 - F E_b T2^(1 / mu_t)) -- at normal incidence
      (1 - F0) / (1 - F0 E_b T2), [Portsmouth2025]'s Delta with K = F0, and at T2 = 1 the
      released specification's smooth-base Delta.

    A rough coat (``coat_alpha`` >= ``microfacet.ALPHA_MIN``, eta != 1) is an
    energy-conserving rough interface: the GGX single scattering (height-correlated
    masking), integrated over the visible normals [Heitz2018; DupuyBenyoub2023], plus the
    Kulla–Conty energy [KullaConty2017], split between reflection and transmission on each
    side as ``lobes.DielectricMS`` splits it (the light side's share from its single
    scattering, the dense side's from reciprocity) and sent in its cosine-weighted
    (1 - E(mu)) directions. The same sums then run over the light's direction inside the
    coat, kept as a distribution over the internal cosine rule (``_cosine_rule``, whose
    nodes are the bins): the entering light's (each visible normal's refracted direction,
    so t(mu_t) becomes its mean of t), and the internal reflection as a matrix P between
    bins, which spreads the light. Over a Lambertian base K_T = sum rho_q t_q (P t)_q
    (rho the cosine distribution); over a mirror the bounces are a linear system,
    what leaves = y . D s with (I - P D) y = 1 - R, D = diag(E_b t^2) and s the entering
    light. Measured against random walks (``layered.LayeredReference`` over ``DielectricMS``)
    in ``docs/coat_darkening_measured.md``: within 0.002 of the albedo at cos theta_o 0.95
    and 0.5, coat roughness up to 0.5, coat IOR 1.3-2 (and within 0.01, about the walks'
    noise, at coat alpha 1, cos theta_o 0.3 and coats less dense than the ambient:
    ``tests/test_darkening_physical.py``, marked slow). A smooth coat has everything in
    closed form; a rough one is interpolated between ``_ENTRY_NODES`` cosines of wo (within
    3e-3 of the albedo, except within about alpha of the critical angle of a coat less
    dense than the ambient: 1.4e-2 at alpha 0.0025).

    Between the two bases the estimates are lerped by r_b, as the specification lerps K
    between F(mu_o) and the internal average [OpenPBR2026, §Coat darkening]: a base that is
    partly a mirror and partly diffuse sums its parts' E'_c. (For a clear smooth coat the
    ends are the specification's; between them its lerp of K is not linear in Delta, so
    the two differ there.) Delta_phys is in [0, 1] (clipped against rounding): the coat
    never gives back more than the naive layering.

    The constants (A, K_T and, for a rough coat, the entry at ``_ENTRY_NODES`` cosines) are
    computed by ``CoatTransport`` for every call of this function; a layer keeps them
    (``Darkening.coat_constants``). A layer whose top is the single-scattering
    ``DielectricReflection`` (OpenPBR's coat) reflects E_top without the Kulla–Conty
    reflection the energy-conserving interface adds, so its albedo differs from the walks'
    by that as well (at most 0.006 in the measured cases, coat IOR >= 1).
    """
    E_b = _params.color("E_b", E_b, 0.0, 1.0)
    T2 = _params.color("T2", T2, 0.0, 1.0)
    c = _params.real("cos_theta", cos_theta, 0.0, 1.0)
    r = _params.real("base_roughness", base_roughness, 0.0, 1.0)
    return CoatTransport(eta, coat_alpha, T2, E_b).darkening(c, r)


def _entry_nodes(mu_c):
    """The cosines mu_c + sign(v) v^2 of ``_ENTRY_NODES`` values of v uniform on
    [-sqrt(mu_c), sqrt(1 - mu_c)]: dense at grazing (mu_c = 0, eta >= 1) or about the
    critical cosine mu_c = sqrt(1 - eta^2) where the light enters from the dense side, where
    a rough coat's entry changes over a width of about its alpha."""
    v = np.linspace(-np.sqrt(mu_c), np.sqrt(1.0 - mu_c), _ENTRY_NODES)
    return np.clip(mu_c + np.sign(v) * v * v, 0.0, 1.0)


def _entry_position(mu, mu_c, n):
    """``(i, f)``: the interval i in [0, n - 2] of ``_entry_nodes(mu_c, n)`` holding ``mu`` and
    the fraction f of the way through it, in v."""
    d = mu - mu_c
    v = np.sign(d) * np.sqrt(np.abs(d))
    lo, hi = -np.sqrt(mu_c), np.sqrt(1.0 - mu_c)
    x = np.clip((v - lo) / (hi - lo), 0.0, 1.0) * (n - 1)
    i = np.minimum(x.astype(np.int64), n - 2)
    return i, x - i


def _powers(lnT, y):
    """T2^y = exp(ln(T2) y) with 0^0 = 1 and 1^inf = 1 (the products 0 inf and -inf 0 are
    taken as 0): T2 = 0 and grazing cosines stay finite."""
    with np.errstate(invalid="ignore"):
        p = lnT * y
    return np.exp(np.where(np.isnan(p), 0.0, p))


def _cosine_rule(eta_seen: float):
    """``(mu, w)``: nodes and weights of int_0^1 g(mu) d mu on the side where the interface
    has relative index ``eta_seen``: Gauss–Legendre on [0, mu_c] (total internal
    reflection, where there is any) and in s on [mu_c, 1], mu = mu_c + (1 - mu_c) s^2 (the
    square root of a smooth interface's Fresnel at the critical cosine mu_c, as
    ``fresnel_average``)."""
    x, w = np.polynomial.legendre.leggauss(_COSINE_POINTS)
    s, w = 0.5 * (x + 1.0), 0.5 * w
    mu_c = float(np.sqrt(max(1.0 - eta_seen * eta_seen, 0.0)))
    mu, weight = mu_c + (1.0 - mu_c) * s * s, 2.0 * (1.0 - mu_c) * s * w
    if mu_c > 0.0:
        mu, weight = np.concatenate([mu_c * s, mu]), np.concatenate([mu_c * w, weight])
    return mu, weight


def _rough_interface(mu, eta_seen: float, alpha: float):
    """The GGX single scattering of an interface of relative index ``eta_seen`` seen at
    the cosines ``mu`` ``(K,)``, by the visible-normal rule (``_AZIMUTHS`` x ``_HEIGHTS``
    normals per cosine): ``(reflected, transmitted)``, each a pair ``(e, cos)`` ``(K, J)`` of
    every normal's energy and the |cosine| of its direction (energy: F G2 / G1 and
    (1 - F) G2 / G1 of a visible normal [Walter2007; Heitz2018], height-correlated)."""
    d = GGX(alpha)
    x, w = np.polynomial.legendre.leggauss(_HEIGHTS)
    u0 = (np.arange(_AZIMUTHS) + 0.5) / (2 * _AZIMUTHS)
    u0, u1 = (a.ravel() for a in np.meshgrid(u0, 0.5 * (x + 1.0), indexing="ij"))
    W = np.outer(np.full(_AZIMUTHS, 1.0 / _AZIMUTHS), 0.5 * w).ravel()
    z = np.maximum(np.asarray(mu, dtype=np.float64), _GRAZING)[:, None]
    ox, oz = np.sqrt(1.0 - z * z) + 0.0 * u0, z + 0.0 * u0
    oy = np.zeros_like(ox)
    mx, my, mz, s_o = d.visible_and_projected(ox, oy, oz, u0, u1)
    c = ox * mx + oy * my + oz * mz
    F = _dielectric(c, eta_seen)
    rx, ry, rz = 2.0 * c * mx - ox, 2.0 * c * my - oy, 2.0 * c * mz - oz
    sin2 = (1.0 - c * c) / (eta_seen * eta_seen)
    cos_t = np.sqrt(np.maximum(1.0 - sin2, 0.0))
    a = c / eta_seen - cos_t
    tx, ty, tz = a * mx - ox / eta_seen, a * my - oy / eta_seen, a * mz - oz / eta_seen
    with np.errstate(divide="ignore", invalid="ignore"):
        g_r = d.G2_over_G1_of(oz, s_o, np.abs(rz), d.projected(rx, ry, np.abs(rz)))
        g_t = d.G2_over_G1_of(oz, s_o, np.abs(tz), d.projected(tx, ty, np.abs(tz)))
    e_r = W * F * np.where((rz > 0.0) & np.isfinite(g_r), g_r, 0.0)
    e_t = W * (1.0 - F) * np.where((sin2 < 1.0) & (tz < 0.0) & np.isfinite(g_t), g_t, 0.0)
    return (e_r, np.minimum(np.abs(rz), 1.0)), (e_t, np.minimum(np.abs(tz), 1.0))


def _binned(e, cos, nodes):
    """``(K, Q)``: the energies ``e`` ``(K, J)`` of each row gathered on the increasing
    cosines ``nodes`` ``(Q,)``, each split linearly between the two nodes about its cosine
    (clamped to the end nodes); the rows' sums are kept."""
    K, Q = e.shape[0], len(nodes)
    c = np.clip(cos, nodes[0], nodes[-1])
    j = np.clip(np.searchsorted(nodes, c), 1, Q - 1)
    f = (c - nodes[j - 1]) / (nodes[j] - nodes[j - 1])
    first = np.arange(K)[:, None] * Q + j
    out = np.bincount((first - 1).ravel(), (e * (1.0 - f)).ravel(), minlength=K * Q)
    out += np.bincount(first.ravel(), (e * f).ravel(), minlength=K * Q)
    return out.reshape(K, Q)


def _kulla_conty_shares(light, dense, ratio: float):
    """(t_L, t_D): the shares of the multiply scattered energy that each side transmits, as
    ``lobes.DielectricMultipleScattering`` takes them [KullaConty2017; Kutz2021, §1.2]:
    t_L = E_T,avg / E_avg of the light side's single scattering, t_D from reciprocity
    (1 - r_L)(1 - E_avg,L) = eta^2 (1 - r_D)(1 - E_avg,D) (capped at 1, t_L following).
    ``light``, ``dense``: each side's (E_R,avg, E_T,avg)."""
    E_L, E_D = sum(light), sum(dense)
    t_L = min(max(light[1] / E_L, 0.0), 1.0) if E_L > 0.0 else 0.0
    loss_L, loss_D, eta2 = 1.0 - E_L, 1.0 - E_D, ratio * ratio
    t_D = max(t_L * loss_L / (eta2 * loss_D), 0.0) if eta2 * loss_D > 0.0 else 0.0
    if t_D > 1.0:
        t_L, t_D = eta2 * loss_D / loss_L, 1.0
    return t_L, t_D


class _Geometry:
    """What a coat of index ``eta`` and roughness ``alpha`` (scalars) does to light, whatever
    its colour, on the internal cosine rule ``mu``, ``w`` (``_cosine_rule``, the nodes also
    the bins of the light's direction inside): ``R``, ``T`` the reflectance and
    transmittance seen from inside at the nodes; for a rough coat also ``P`` ``(Q, Q)``, the
    energy reflected inside from each node's bin to each bin, ``ms`` ``(Q,)`` the bins of the
    Kulla–Conty light (a distribution) and, at each of the ``_ENTRY_NODES`` cosines of wo
    (``_entry_nodes`` about ``edge``), the entering energy in bins ``S`` ``(N, Q)`` (each
    visible normal's refracted direction and the Kulla–Conty term's) and its total
    ``entered`` ``(N,)``."""

    def __init__(self, eta: float, alpha: float):
        self.smooth = alpha < ALPHA_MIN or eta == 1.0
        self.mu, self.w = _cosine_rule(1.0 / eta)
        if self.smooth:
            self.R = _dielectric(self.mu, 1.0 / eta)
            self.T = 1.0 - self.R
            return
        ratio = max(eta, 1.0 / eta)
        inside = _rough_interface(self.mu, 1.0 / eta, alpha)
        R_i, T_i = (part[0].sum(-1) for part in inside)
        mu_e, w_e = _cosine_rule(eta)
        R_e, T_e = (part[0].sum(-1) for part in _rough_interface(mu_e, eta, alpha))

        def average(E, mu, w):
            return float(np.sum(2.0 * mu * w * E))

        sides = ((average(R_e, mu_e, w_e), average(T_e, mu_e, w_e)),
                 (average(R_i, self.mu, self.w), average(T_i, self.mu, self.w)))
        t_L, t_D = _kulla_conty_shares(*(sides if eta >= 1.0 else sides[::-1]), ratio)
        t_e, t_i = (t_L, t_D) if eta >= 1.0 else (t_D, t_L)
        lost = np.maximum(1.0 - R_i - T_i, 0.0)
        self.R, self.T = R_i + (1.0 - t_i) * lost, T_i + t_i * lost
        ms = 2.0 * self.mu * self.w * lost
        self.ms = ms / ms.sum() if ms.sum() > 0.0 else ms
        self.P = _binned(*inside[0], self.mu) + np.outer((1.0 - t_i) * lost, self.ms)
        #: the entry side's critical cosine (0 for eta >= 1)
        self.edge = float(np.sqrt(max(1.0 - eta * eta, 0.0)))
        (e_r, _), (e, cos) = _rough_interface(_entry_nodes(self.edge), eta, alpha)
        M = t_e * np.maximum(1.0 - e_r.sum(-1) - e.sum(-1), 0.0)
        self.S = _binned(e, cos, self.mu) + np.outer(M, self.ms)
        self.entered = self.S.sum(-1)

    def constants(self, lnT, E_b):
        """``(a, K, g_r, g_s)`` of elements with ln(T2) ``lnT`` and base albedo ``E_b``
        ``(n, 3)``: a = A / sqrt(T2) and K = K_T ``(n, 3)`` and, for a rough coat, at the
        entry nodes ``(n, N, 3)``, the mean one-way transmittance of the entering light over
        sqrt(T2) and the mirror base's Delta_s (None for a smooth coat: closed forms); the
        light's direction taken at the bins' cosines throughout (within 1e-3 of the exact
        directions' sums, measured)."""
        mu, rho = self.mu[:, None], (2.0 * self.mu * self.w)[:, None]
        lnT, E_b = lnT[:, None, :], E_b[:, None, :]
        t1 = _powers(lnT, 0.5 / mu - 0.5)  # t / sqrt(T2) along each node's cosine
        t2 = _powers(lnT, 1.0 / mu)  # t^2
        a = np.sum(rho * t1 * self.T[:, None], -2)
        if self.smooth:
            return a, np.sum(rho * t2 * self.R[:, None], -2), None, None
        t = _powers(lnT, 0.5 / mu)
        K = np.sum(rho * t * np.einsum("qr,nrc->nqc", self.P, t), -2)
        # the Lambertian base: the entering light's mean t over sqrt(T2)
        g_r = np.einsum("kq,nqc->nkc", self.S, t1)
        # the mirror base: light in bin q comes back to the top with E_b t^2 (D), leaves with
        # T or is reflected into the bins by P: what leaves is y . D s, (I - P D) y = T
        D = np.moveaxis(E_b * t2, -1, 1) * _DAMPING  # (n, 3, Q)
        y = np.linalg.solve(np.eye(len(self.mu)) - self.P * D[..., None, :],
                            np.broadcast_to(self.T, D.shape)[..., None])[..., 0]
        first = np.moveaxis(_powers(lnT, 1.0 / mu - 1.0), -1, 1)  # D / (E_b T2)
        g_s = np.einsum("kq,ncq->nkc", self.S, y * first)
        entered = self.entered[:, None]

        def per_entered(x):  # nothing enters: 0 (the layer's 1 - E_top is 0 there too)
            return np.where(entered > 0.0, x / np.where(entered > 0.0, entered, 1.0), 0.0)

        return a, K, per_entered(g_r), per_entered(g_s)


def _mirror(t2, lnT, mu, R, T, E_b):
    """T2^(1 / mu - 1) T / (1 - E_b R t^2), t^2 = ``t2`` = T2^(1 / mu): a mirror base's
    Delta_s for light entering along the internal cosine ``mu`` (1 where the series is 0 / 0,
    a lossless trap: E_b t^2 R = 1, T = 0)."""
    den = 1.0 - E_b * R * t2
    with np.errstate(divide="ignore"):
        num = _powers(lnT, 1.0 / mu - 1.0) * T
    return np.where(den > 0.0, num / np.where(den > 0.0, den, 1.0), 1.0)


class CoatTransport:
    """The per-material constants of ``physical_darkening``: a coat of relative index
    ``eta`` in (0, inf), GGX roughness ``coat_alpha`` in [0, 1] and two-way transmittance
    ``T2`` at normal incidence (colour in [0, 1]) over a base of albedo ``E_b`` (colour in
    [0, 1]); the parameters broadcast (textures).

    ``darkening(cos_theta, base_roughness)`` is then Delta_phys at |cos theta_o|: closed
    forms for a smooth coat, a linear interpolation between ``_ENTRY_NODES`` cosines for a
    rough one. Constructing it integrates, per distinct (eta, coat_alpha) pair, the
    interface over the visible normals (``_AZIMUTHS`` x ``_HEIGHTS`` normals at each of
    about 260 cosines: both sides of the internal rule and the entry nodes), then per
    element the colour sums and, for a rough coat, three 96 x 96 linear systems (the mirror
    base): about 40 ms for a scalar rough coat, 2 ms for a smooth one, and about 1 ms more per
    element of a texture (of the base albedo or coat colour) of a rough coat. No random
    numbers.

    Attributes
    ----------
    A, K : ndarray ``(..., 3)``
        The shares of light leaving a Lambertian base (cosine-distributed, at the base) that
        escape through the top and that come back to the base (``physical_darkening``).
    """

    def __init__(self, eta, coat_alpha, T2, E_b):
        eta = _params.real("eta", eta, 0.0, np.inf, lo_open=True)
        alpha = _params.real("coat_alpha", coat_alpha, 0.0, 1.0)
        T2 = _params.color("T2", T2, 0.0, 1.0)
        E_b = _params.color("E_b", E_b, 0.0, 1.0)
        shape = np.broadcast_shapes(eta.shape, alpha.shape, T2.shape[:-1], E_b.shape[:-1])
        flat = [np.broadcast_to(x, shape).reshape(-1) for x in (eta, alpha)]
        T2, E_b = (np.broadcast_to(x, shape + (3,)).reshape(-1, 3) for x in (T2, E_b))
        with np.errstate(divide="ignore"):
            lnT = np.log(T2)
        smooth = (flat[1] < ALPHA_MIN) | (flat[0] == 1.0)
        keys, inverse = np.unique(np.stack([flat[0], np.where(smooth, 0.0, flat[1])], -1),
                                  axis=0, return_inverse=True)
        n = len(flat[0])
        a, K, edge = np.empty((n, 3)), np.empty((n, 3)), np.zeros(n)
        grids = None
        for k, (eta_k, alpha_k) in enumerate(keys):
            geometry = _Geometry(eta_k, alpha_k)
            of_k = np.flatnonzero(inverse.ravel() == k)
            for start in range(0, len(of_k), _BLOCK):
                rows = of_k[start:start + _BLOCK]
                a[rows], K[rows], g_r, g_s = geometry.constants(lnT[rows], E_b[rows])
                if g_r is not None:
                    if grids is None:
                        grids = np.zeros((2, n) + g_r.shape[1:])
                    grids[0, rows], grids[1, rows], edge[rows] = g_r, g_s, geometry.edge
        den = 1.0 - E_b * K
        ratio = np.where(den > 0.0, a / np.where(den > 0.0, den, 1.0), 1.0)

        def shaped(x):
            return x.reshape(shape + x.shape[1:])

        self.shape = shape
        self.A, self.K = shaped(a * np.sqrt(T2)), shaped(K)
        self._eta, self._lnT, self._E_b = shaped(flat[0]), shaped(lnT), shaped(E_b)
        self._smooth, self._ratio, self._edge = shaped(smooth), shaped(ratio), shaped(edge)
        self._grids = None if grids is None else (shaped(grids[0]), shaped(grids[1]))

    def darkening(self, cos_theta, base_roughness) -> np.ndarray:
        """Delta_phys ``(..., 3)`` at the validated |cos theta_o| ``cos_theta`` and base
        roughness r_b (arrays broadcasting against the parameters)."""
        mu = np.clip(np.asarray(cos_theta, dtype=np.float64), 0.0, 1.0)
        shape = np.broadcast_shapes(mu.shape, self.shape)
        smooth = np.broadcast_to(self._smooth, shape)[..., None]
        if self._grids is None:
            Delta_s, g_r = self._smooth_coat(mu)
        elif not np.any(smooth):
            Delta_s, g_r = self._interpolated(mu, shape)
        else:
            (s_s, s_r), (r_s, r_r) = self._smooth_coat(mu), self._interpolated(mu, shape)
            Delta_s, g_r = np.where(smooth, s_s, r_s), np.where(smooth, s_r, r_r)
        r = np.asarray(base_roughness, dtype=np.float64)[..., None]
        return np.clip(Delta_s + r * (g_r * self._ratio - Delta_s), 0.0, 1.0)

    def _smooth_coat(self, mu):
        """(Delta_s, t(mu_t) / sqrt(T2)) of a smooth coat in closed form."""
        eta, lnT, E_b = self._eta, self._lnT, self._E_b
        mu_t = np.sqrt(np.maximum(1.0 - (1.0 - mu * mu) / (eta * eta), 0.0))
        F = _dielectric(mu, eta)[..., None]
        with np.errstate(divide="ignore"):
            y = 1.0 / mu_t[..., None]
        t2 = _powers(lnT, y)
        return _mirror(t2, lnT, mu_t[..., None], F, 1.0 - F, E_b), _powers(lnT, 0.5 * y - 0.5)

    def _interpolated(self, mu, shape):
        """(Delta_s, t-mean / sqrt(T2)) of a rough coat: linear in v between the entry nodes
        (``_entry_nodes``)."""
        i, f = _entry_position(mu, self._edge, self._grids[0].shape[-2])
        f = f[..., None]
        out = []
        for grid in self._grids[1], self._grids[0]:
            if self.shape == ():
                lo, hi = grid[i], grid[i + 1]
            else:
                g = np.broadcast_to(grid, shape + grid.shape[-2:])
                j = np.broadcast_to(i, shape)[..., None, None]
                lo = np.take_along_axis(g, j, -2)[..., 0, :]
                hi = np.take_along_axis(g, j + 1, -2)[..., 0, :]
            out.append(lo + f * (hi - lo))
        return out



@dataclass(frozen=True, eq=False)
class Darkening:
    """Coat darkening as a parameter of ``composition.Layer`` [OpenPBR2026, §Coat darkening;
    Portsmouth2025]: the layer's base is multiplied by

        D(wo) = lerp(1, Delta(wo), delta),

    with, for ``variant`` "pr253" and "v1.1.1", Delta = Delta(E_b, K(wo), T2, variant) of
    ``darkening`` and K(wo) = coat_reflectance(eta_c, base_roughness, |cos theta_o|), eta_c the
    top's index and T2 the layer's two-way transmittance at normal incidence; for
    "dev_1.2", Delta = ``physical_darkening``(E_b, eta_c, coat_alpha, T2, |cos theta_o|,
    base_roughness), so that in a layer of constant transmittance T2 (scaling "albedo")
    the coated albedo is [Portsmouth2025]'s E_top + (1 - E_top) lerp(T2 E_b, E'_c, delta):
    the naive albedo at delta = 0, the physical one at delta = 1.
    0 <= D <= 1: darkening never adds energy; delta = 0 is no darkening, a white base
    (E_b = 1, T2 grey) is darkened without a shift of hue.

    Attributes
    ----------
    delta : array_like in [0, 1]
        coat_darkening.
    base_roughness : array_like in [0, 1]
        r_b: from the smooth base's estimate (0) to the rough one's (1); for "pr253" and
        "v1.1.1" K goes from F(wo, eta_c) to the internal reflectance, for "dev_1.2" Delta
        from the mirror base's to the Lambertian base's.
    variant : one of ``ALL_VARIANTS``
    base_albedo : colour in [0, 1] or None
        E_b; None: the base's own energy albedo at normal incidence (its table where it has
        one, else a quadrature), computed once by the layer.
    coat_alpha : array_like in [0, 1]
        "dev_1.2" only: the coat's GGX alpha (0: smooth; OpenPBR's coat_roughness^2).
    """

    delta: object = 1.0
    base_roughness: object = 1.0
    variant: str = "pr253"
    base_albedo: object = None
    coat_alpha: object = 0.0

    @_params.records  # its parameters are its own, not those of the material that builds it
    def __post_init__(self):
        checked = {"delta": _params.real("delta", self.delta, 0.0, 1.0),
                   "base_roughness": _params.real("base_roughness", self.base_roughness,
                                                  0.0, 1.0),
                   "variant": _params.choice("variant", self.variant, ALL_VARIANTS),
                   "base_albedo": (None if self.base_albedo is None else
                                   _params.color("base_albedo", self.base_albedo, 0.0, 1.0)),
                   "coat_alpha": _params.real("coat_alpha", self.coat_alpha, 0.0, 1.0)}
        for name, value in checked.items():
            object.__setattr__(self, name, value)

    def coat_constants(self, eta, E_b, T2):
        """What ``factor`` takes as ``coat``, computed once per layer from the coat's index
        ``eta``, the base albedo ``E_b`` and ``T2`` (validated): the internal reflectance
        K of a rough base (``internal_reflectance(eta)``) for "pr253" and "v1.1.1", the
        ``CoatTransport`` for "dev_1.2"."""
        if self.variant == PHYSICAL:
            return CoatTransport(eta, self.coat_alpha, T2, E_b)
        return internal_reflectance(eta)

    def factor(self, eta, cos_theta, E_b, T2, coat) -> np.ndarray:
        """D ``(..., 3)`` at the validated |cos theta_o| ``cos_theta`` under a coat of index
        ``eta`` with the constants ``coat`` (``coat_constants``), over a base of albedo
        ``E_b`` with the two-way transmittance ``T2`` (colours in [0, 1])."""
        if self.variant == PHYSICAL:
            Delta = coat.darkening(cos_theta, self.base_roughness)
        else:
            K = _coat_reflectance(eta, self.base_roughness, cos_theta, coat)
            Delta = _darkening(E_b, K[..., None], T2, self.variant)
        return _lerp_from_one(Delta, self.delta[..., None])
