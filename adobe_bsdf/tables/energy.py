"""Directional energy of an isotropic GGX interface, by piecewise Gauss–Legendre quadrature.

Public API
----------
``ggx_energy(mu, alpha, eta=None, order=20)``
    Reflected and transmitted energy E_R, E_T of a GGX conductor (F = 1, ``eta=None``) or
    dielectric interface seen at cos theta_o = ``mu``, with an error estimate per value.
``ggx_reflection_transfer(mu, alpha, axis, order=20)``
    The same rule for the F = 1 reflection weighted by a tabulated function of the reflected
    direction's cosine: a matrix on that table axis's nodes.

The integral is taken over microfacet normals m = (theta_m, phi), weighted by the visible-normal
density [Heitz2018, eq. 3], i.e. the single-scattering energy of the sampler of
``lobes.Conductor`` / ``lobes.Dielectric``:

    E_R = int D_wo(m) F G2(wo, wr) / G1(wo) dm
        = int dxi dphi / (2 pi) F (wo.m / cos_m) G2(wo, wr) / mu
    E_T = int dxi dphi / (2 pi) (1 - F) (wo.m / cos_m) G2(wo, wt) / mu

where xi = tan^2 theta_m / (alpha^2 + tan^2 theta_m) is the GGX cdf of D cos (so D(m) cos_m
d omega_m = dxi dphi / (2 pi)), wr / wt are the reflected / refracted directions, and G2 is the
height-correlated Smith term [Heitz2014, eq. 99], written as G2 / mu to stay finite at mu = 0.

Why this form (``docs/tables.md``): the integrand is analytic except where a direction
crosses the horizon, where the facet turns away from ``wo``, and at the critical angle of
total internal reflection. All of these are conditions on c = wo.m, which is linear in
cos phi at fixed theta_m; so the phi integral is split exactly at those c and each piece is
smooth. In theta_m the pieces appear and vanish at angles located by a scan and bisection,
and the theta_m integral is split there too. Each piece gets Gauss–Legendre nodes
(``scipy.special.roots_legendre``) after a sigmoidal change of variable that removes the
square-root behaviour at piece ends. The narrow GGX peak is flattened by the variable
v = asinh(tan theta_m / alpha) (xi = tanh^2 v) up to 45 degrees, theta_m itself beyond.
The error estimate is the difference to the same rule at two thirds of the order.
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import numpy as np
from scipy.special import roots_legendre

from adobe_bsdf.fresnel import _dielectric

__all__ = ["Energy", "ggx_energy", "ggx_reflection_transfer"]

#: panels in v = asinh(tan theta_m / alpha) between theta_m = 0 and 45 degrees
V_PANELS = 10
#: sigmoidal change of variable x = t^p / (t^p + (1 - t)^p) on every piece
SIGMOID_P = 2.0
#: largest number of nodes processed at once (memory)
CHUNK = 16


class Energy(NamedTuple):
    """E_R, E_T and their error estimates, each shaped like the broadcast inputs."""

    reflection: np.ndarray
    transmission: np.ndarray
    error_reflection: np.ndarray
    error_transmission: np.ndarray


@functools.lru_cache(maxsize=32)
def _rule(order: int):
    """Gauss–Legendre nodes and weights on [0, 1] after the sigmoidal map (cached: the
    roots cost more than a node's integrand; read-only)."""
    t, w = roots_legendre(order)
    t, w = 0.5 * (t + 1.0), 0.5 * w
    p = SIGMOID_P
    a, b = t**p, (1.0 - t) ** p
    x = a / (a + b)
    dx = p * (t * (1.0 - t)) ** (p - 1.0) / (a + b) ** 2
    weights = w * dx
    x.flags.writeable = weights.flags.writeable = False
    return x, weights


def _g(mu_o, s_o, alpha, wz):
    """Height-correlated G2(wo, w) / mu_o for wo = (s_o, 0, mu_o), |w_z| = wz (finite at
    mu_o = 0)."""
    wz = np.minimum(wz, 1.0)  # rounding (and the masked-out points of invalid refraction)
    S_o = np.sqrt(mu_o * mu_o + alpha * alpha * s_o * s_o)
    S_i = np.sqrt(wz * wz + alpha * alpha * (1.0 - wz * wz))
    den = wz * S_o + mu_o * S_i
    return np.where(den > 0.0, 2.0 * wz / np.where(den > 0.0, den, 1.0), 0.0)


def _breakpoints(mu_o, cos_m, eta):
    """Values of c = wo.m where the integrand stops being analytic, ``(..., 4)`` (NaN: none).

    0 (facet turns away), mu_o / (2 cos_m) (reflected direction at the horizon),
    sqrt(1 - eta^2) (critical angle, eta < 1) and the c where the refracted direction reaches
    the horizon: wt_z = 0 solves to c = (mu^2 - (eta^2 - 1) cos_m^2) / (2 mu cos_m), valid
    where cos_t = c / eta - mu / (eta cos_m) >= 0.
    """
    nan = np.full(np.broadcast_shapes(np.shape(mu_o), np.shape(cos_m)), np.nan)
    zero = np.zeros_like(nan)
    den = 2.0 * cos_m
    c_r = np.where(den > 0.0, mu_o / np.where(den > 0.0, den, 1.0), nan)
    # G2 / mu rises from 0 to its plateau within ~c_r of the reflection horizon (a boundary
    # layer that becomes thin at grazing mu): graded knots resolve it
    layer = [3.0 * c_r, 21.0 * c_r]
    if eta is None:
        return np.stack([zero, c_r, *layer], axis=-1)
    c_crit = np.where(eta < 1.0, np.sqrt(np.maximum(1.0 - eta * eta, 0.0)), np.nan) + zero
    den = 2.0 * mu_o * cos_m
    safe = np.where(den > 0.0, den, 1.0)
    with np.errstate(over="ignore", invalid="ignore"):  # |c_t| > 1 (none) at subnormal mu
        c_t = (mu_o * mu_o - (eta * eta - 1.0) * cos_m * cos_m) / safe
        cos_t = c_t / eta - mu_o / (eta * np.where(cos_m > 0.0, cos_m, 1.0))
    c_t = np.where((den > 0.0) & (cos_t >= 0.0) & (np.abs(c_t) <= 1.0), c_t, nan)
    return np.stack([zero, c_r, *layer, c_crit, c_t], axis=-1)


def _outer_knots(mu_o, alpha, eta):
    """Panel ends in theta_m, ``(B, K)`` sorted: the v panels, 45/67.5/90 degrees, and every
    angle where the pieces of the phi integral change: an inner breakpoint meets an end of
    the range [cos(theta_o + theta_m), cos(theta_o - theta_m)] of c = wo.m, or two
    breakpoints meet. All are closed forms; a spurious root only adds a panel."""
    theta_o = np.arccos(mu_o)
    v45 = np.arcsinh(1.0 / alpha)
    v = v45[:, None] * np.linspace(0.0, 1.0, V_PANELS + 1)
    knots = [np.arctan(alpha[:, None] * np.sinh(v[:, :-1])),
             np.broadcast_to([np.pi / 4, 3 * np.pi / 8, np.pi / 2], (len(mu_o), 3))]
    t = theta_o[:, None]
    # c = 0 meets cos(theta_o + theta); k c_r = k mu / (2 cos) (k = 1 and the boundary-layer
    # knots) meets cos(theta_o -+ theta): cos(2 theta -+ theta_o) = (k - 1) mu
    knots.append(np.pi / 2 - t)
    for k in (1.0, 3.0, 21.0):
        arg = (k - 1.0) * mu_o[:, None]
        A = np.arccos(np.where(arg <= 1.0, arg, np.nan))
        knots.append(np.concatenate([(A - t) / 2, (A + t) / 2, (t - A) / 2], 1))
    if eta is not None:
        k = eta * eta - 1.0
        mu = mu_o
        theta_c = np.where(eta < 1.0, np.arccos(np.sqrt(np.maximum(-k, 0.0))), np.nan)[:, None]
        c_crit = np.cos(theta_c[:, 0])
        knots.append(np.concatenate([theta_c - t, t - theta_c, t + theta_c], 1))
        # c_t = (mu^2 - k C) / (2 mu c) meets cos(theta_o -+ theta), C = cos^2 theta:
        # (K^2 + 4 mu^2 s^2) C^2 - (2 mu^2 K + 4 mu^2 s^2) C + mu^4 = 0 with K = k + 2 mu^2
        s2 = 1.0 - mu * mu
        K = k + 2.0 * mu * mu
        roots_C = [_quadratic(K * K + 4 * mu * mu * s2, -(2 * mu * mu * K + 4 * mu * mu * s2),
                              mu**4)]
        # coincidences: c_t = c_crit, c_r = c_crit, c_t = 0 (as equations in c = cos theta)
        c_roots = [_quadratic(k, 2.0 * mu * c_crit, -mu * mu),
                   np.stack([mu / (2.0 * np.where(c_crit > 0, c_crit, np.nan))] * 2, -1),
                   np.stack([mu / np.sqrt(np.where(k > 0, k, np.nan))] * 2, -1)]
        roots_C += [np.where(np.isfinite(c) & (c >= 0), c * c, np.nan) for c in c_roots]
        for C in roots_C:
            ok = np.isfinite(C) & (C >= 0.0) & (C <= 1.0)
            knots.append(np.where(ok, np.arccos(np.sqrt(np.where(ok, C, 0.0))), np.nan))
    knots = np.concatenate(knots, axis=1)
    knots = np.where((knots > 0.0) & (knots < np.pi / 2), knots, np.nan)
    ends = np.broadcast_to([0.0, np.pi / 2], (len(mu_o), 2))
    knots = np.sort(np.concatenate([ends, knots], 1), axis=1)  # NaN last
    count = int(np.isfinite(knots).sum(axis=1).max())
    return np.where(np.isfinite(knots[:, :count]), knots[:, :count], np.pi / 2)


def _quadratic(a, b, c):
    """Real roots of a x^2 + b x + c = 0, ``(..., 2)`` (NaN where none)."""
    a, b, c = np.broadcast_arrays(*(np.asarray(x, dtype=np.float64) for x in (a, b, c)))
    disc = b * b - 4.0 * a * c
    real = disc >= 0.0
    sq = np.sqrt(np.where(real, disc, 0.0))
    # q = -(b + sign(b) sqrt(disc)) / 2 avoids cancellation; roots q / a and c / q
    q = -0.5 * (b + np.where(b >= 0.0, sq, -sq))
    r1 = np.where(real & (a != 0.0), q / np.where(a != 0.0, a, 1.0), np.nan)
    r2 = np.where(real & (q != 0.0), c / np.where(q != 0.0, q, 1.0), np.nan)
    return np.stack([r1, r2], axis=-1)


def _integrate(mu_o, alpha, eta, order, transfer=None):
    """E_R, E_T for 1-D node arrays at one quadrature order; with ``transfer`` (an ``Axis``
    of cos theta, ``eta`` None) the reflection's rule carried onto that axis's nodes instead
    (``ggx_reflection_transfer``)."""
    n = len(mu_o)
    s_o = np.sqrt(np.maximum(1.0 - mu_o * mu_o, 0.0))
    x, wx = _rule(order)
    knots = _outer_knots(mu_o, alpha, eta)  # (n, K)
    a, b = knots[:, :-1], knots[:, 1:]  # (n, P)
    al = alpha[:, None, None]
    # change of variable per panel: v = asinh(tan / alpha) below 45 degrees, theta above
    use_v = 0.5 * (a + b) < np.pi / 4
    va, vb = np.arcsinh(np.tan(a) / alpha[:, None]), np.arcsinh(np.tan(np.minimum(b, np.pi / 4))
                                                                  / alpha[:, None])
    lo = np.where(use_v, va, a)[..., None]
    hi = np.where(use_v, vb, b)[..., None]
    var = lo + (hi - lo) * x  # (n, P, order)
    theta = np.where(use_v[..., None], np.arctan(al * np.sinh(var)), var)
    sin_t, cos_t = np.sin(theta), np.cos(theta)
    dxi_v = 2.0 * np.tanh(var) / np.cosh(var) ** 2
    dxi_t = 2.0 * al * al * sin_t * cos_t / (al * al * cos_t * cos_t + sin_t * sin_t) ** 2
    w_outer = (hi - lo) * wx * np.where(use_v[..., None], dxi_v, dxi_t)  # (n, P, order)

    # inner integral over phi in [0, pi], split where c = wo.m crosses a breakpoint
    mu = mu_o[:, None, None]
    so = s_o[:, None, None]
    et = None if eta is None else eta[:, None, None]
    c_star = _breakpoints(mu, cos_t, et)  # (n, P, order, J)
    amp = (so * sin_t)[..., None]
    base = (mu * cos_t)[..., None]
    ratio = np.where(amp > 0.0, (c_star - base) / np.where(amp > 0.0, amp, 1.0), 2.0)
    phi_star = np.arccos(np.clip(np.nan_to_num(ratio, nan=2.0), -1.0, 1.0))
    knots_phi = np.sort(np.concatenate([np.zeros_like(phi_star[..., :1]), phi_star,
                                        np.full_like(phi_star[..., :1], np.pi)], -1), -1)
    pa, pb = knots_phi[..., :-1, None], knots_phi[..., 1:, None]
    phi = pa + (pb - pa) * x  # (n, P, order, J+1, order)
    w_phi = (pb - pa) * wx / np.pi
    ct = cos_t[..., None, None]
    st = sin_t[..., None, None]
    mu5, so5 = mu[..., None, None], so[..., None, None]
    c = so5 * st * np.cos(phi) + mu5 * ct  # wo.m
    front = c > 0.0
    ratio_cm = c / ct
    al5 = alpha[:, None, None, None, None]
    # reflection: wr_z = 2 c cos_m - mu
    wr_z = 2.0 * c * ct - mu5
    if eta is None:
        F = 1.0
    else:
        eta5 = eta[:, None, None, None, None]
        F = _dielectric(np.where(front, c, 1.0), eta5)
    val_r = np.where(front & (wr_z > 0.0), F * ratio_cm * _g(mu5, so5, al5, np.abs(wr_z)), 0.0)
    if transfer is not None:
        weight = (w_outer[..., None, None] * w_phi * val_r).reshape(n, -1)
        mu_r = np.clip(wr_z, 0.0, 1.0).reshape(n, -1)
        return np.stack([transfer.rule_weights(m, w) for m, w in zip(mu_r, weight, strict=True)])
    e_r = np.einsum("npo,npojk,npojk->n", w_outer, w_phi, val_r)
    if eta is None:
        return e_r, np.zeros(n)
    # refraction: wt = -wo / eta + (c / eta - cos_t) m
    sin2 = (1.0 - c * c) / (eta5 * eta5)
    refracts = front & (sin2 < 1.0)
    cos_tr = np.sqrt(np.maximum(1.0 - sin2, 0.0))
    wt_z = -mu5 / eta5 + (c / eta5 - cos_tr) * ct
    val_t = np.where(refracts & (wt_z < 0.0),
                     (1.0 - F) * ratio_cm * _g(mu5, so5, al5, np.abs(wt_z)), 0.0)
    e_t = np.einsum("npo,npojk,npojk->n", w_outer, w_phi, val_t)
    return e_r, e_t


def ggx_reflection_transfer(mu, alpha, axis, order: int = 20) -> np.ndarray:
    """``(n, axis.n)``: the matrix M with sum_j M_kj a_j = int D_wo(m) G2(wo, wr) / G1(wo)
    a(wr_z) dm at cos theta_o = ``mu[k]``, for the interpolant a of node values a_j on
    ``axis`` (a cos theta axis of ``tables.table``): the F = 1 GGX reflection of
    isotropic roughness ``alpha`` applied to a function of the reflected direction's cosine,
    by the rule of ``ggx_energy`` (row sums: E of the white conductor). ``mu``, ``alpha``:
    1-D, alpha > 0."""
    mu, alpha = np.broadcast_arrays(np.asarray(mu, dtype=np.float64).ravel(),
                                    np.asarray(alpha, dtype=np.float64).ravel())
    return np.concatenate([_integrate(mu[k:k + CHUNK], alpha[k:k + CHUNK], None, order, axis)
                           for k in range(0, len(mu), CHUNK)])


def ggx_energy(mu, alpha, eta=None, order: int = 20, estimate: bool = True) -> Energy:
    """Single-scattering energy of an isotropic GGX interface at cos theta_o = ``mu``.

    Parameters
    ----------
    mu : array_like in [0, 1]
        Cosine of the viewing direction (0 is the grazing limit, computed exactly).
    alpha : array_like in (0, inf)
        GGX roughness.
    eta : array_like in (0, inf) or None
        Relative index n_t / n_i of the interface seen from ``wo`` (< 1: from the dense
        side); ``None`` for a conductor with F = 1 (no transmission).
    order : int
        Gauss–Legendre nodes per piece and per dimension.
    estimate : bool
        False skips the error estimate (returned as 0), saving the second rule.

    Returns
    -------
    Energy: E_R, E_T and error estimates |Q(order) - Q(2 order / 3)| (the error of the lower
    order: conservative, the rule converges geometrically). ``eta == 1`` is the closed form
    E_R = 0, E_T = 1 / (2 - G1(wo)).
    """
    arrays = [mu, alpha] + ([] if eta is None else [eta])
    arrays = np.broadcast_arrays(*[np.asarray(a, dtype=np.float64) for a in arrays])
    shape = arrays[0].shape
    flat = [a.ravel() for a in arrays]
    out = np.zeros((4, flat[0].size))
    low = max(2, (2 * order) // 3)
    for start in range(0, flat[0].size, CHUNK):
        part = [a[start:start + CHUNK] for a in flat]
        args = (part[0], part[1], None if eta is None else part[2])
        hi_r, hi_t = _integrate(*args, order)
        lo_r, lo_t = _integrate(*args, low) if estimate else (hi_r, hi_t)
        out[:, start:start + CHUNK] = hi_r, hi_t, np.abs(hi_r - lo_r), np.abs(hi_t - lo_t)
    if eta is not None:
        # index-matched: no reflection, wt = -wo for every facet, so E_T = G2(wo, -wo) / G1(wo)
        # = 1 / (2 - G1(wo)) in closed form (1/2 in the grazing limit, where the refracted
        # direction lies on the horizon for every facet and the quadrature is degenerate)
        mu_f, alpha_f = flat[0], flat[1]
        matched = flat[2] == 1.0
        G1 = 2.0 * mu_f / (mu_f + np.sqrt(mu_f * mu_f + alpha_f * alpha_f * (1.0 - mu_f * mu_f)))
        out[:, matched] = 0.0
        out[1, matched] = 1.0 / (2.0 - G1[matched])
    return Energy(*(o.reshape(shape) for o in out))
