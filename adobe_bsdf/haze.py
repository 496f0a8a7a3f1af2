"""The perceptual-to-physical haze mapping of hazy gloss [Barla2018]; the lobes built on it
are ``lobes.HazyGloss`` and ``lobes.HazyDielectric`` (both also in ``adobe_bsdf.hazy``).

The composite specular BRDF f_r = (1 - beta) F_r f_n + beta F_r f_w [Barla2018, eq. 1], two
microfacet lobes of narrow and wide roughness sharing one Fresnel term, is controlled through
its perceptual decomposition into a specular core and a halo (eqs. 2-5): the core keeps its
reflectivity r_c whatever the haziness, and the halo has intensity k_h and extent lambda_h.

Public API
----------
``wide_roughness(alpha_x, alpha_y, extent_x, extent_y)``   eq. 8
``peak_ratio(alpha_n, alpha_w, model)``                    Table 2 (GGX [Walter2007], Beckmann)
``haze_intensity(r_c, p, haziness)``                       eq. 7 (piecewise linear)
``haze_intensity_smooth(r_c, p, haziness, w)``             appendix eqs. 12-15 (rational Bézier)
``haze_mapping(...) -> HazeMapping``                       the HAZEMAPPING algorithm (§2.4)

References
----------
[Barla2018] eqs. 1-8, Table 2, §2.4, appendix.
[Gulbrandsen2014] artist-friendly metallic Fresnel (``fresnel.gulbrandsen_to_ior``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf._channels import pick
from adobe_bsdf.fresnel import gulbrandsen_to_ior

__all__ = ["PEAK_MODELS", "wide_roughness", "peak_ratio", "haze_intensity",
           "haze_intensity_smooth", "HazeMapping", "haze_mapping"]

#: microfacet models whose peak ratio is implemented: both have D(n) = 1 / (pi ax ay)
PEAK_MODELS = ("ggx", "beckmann")


def _wide(ax, ay, lx, ly):
    """``wide_roughness`` of validated arrays."""
    unit = np.sqrt(ax) * np.sqrt(ay)  # not sqrt(ax ay): that underflows for tiny alphas
    return ax + lx * unit, ay + ly * unit


def wide_roughness(alpha_x, alpha_y, extent_x, extent_y=None):
    """Roughness of the wide lobe, alpha_w = alpha_n + lambda_h sqrt(alpha_n^x alpha_n^y)
    per axis [Barla2018, eq. 8]: the haze extents lambda_h^{x,y} >= 0 in the same units along
    both axes; isotropic, alpha_w = alpha_n (1 + lambda_h). Returns ``(alpha_w^x, alpha_w^y)``.

    ``alpha_x``, ``alpha_y`` in [0, inf); ``extent_x`` in [0, inf) and ``extent_y`` (default
    ``extent_x``) in [0, inf).
    """
    ax = _params.real("alpha_x", alpha_x, 0.0, np.inf)
    ay = _params.real("alpha_y", alpha_y, 0.0, np.inf)
    lx = _params.real("extent_x", extent_x, 0.0, np.inf)
    ly = lx if extent_y is None else _params.real("extent_y", extent_y, 0.0, np.inf)
    return _wide(ax, ay, lx, ly)


def _pair(name: str, value) -> tuple:
    """``value`` as an (x, y) pair (a ``ValueError`` naming ``name`` otherwise)."""
    if isinstance(value, (str, bytes)) or np.ndim(value) == 0 or len(value) != 2:
        raise ValueError(f"{name} = {value!r} is not an (alpha_x, alpha_y) pair")
    return value[0], value[1]


def _peak(nx, ny, wx, wy):
    """``peak_ratio`` of validated arrays."""
    return (nx / wx) * (ny / wy)  # each ratio in (0, 1]: no underflow for tiny alphas


def peak_ratio(alpha_n, alpha_w, model: str = "ggx"):
    """p = f_w(n, n) / f_n(n, n), the ratio of the wide and narrow lobes' values in the
    mirror direction at normal incidence [Barla2018, §2.2, Table 2].

    There G = 1 and the Fresnel terms cancel, so p = D_w(n) / D_n(n); for GGX [Walter2007]
    and Beckmann (Cook-Torrance) D(n) = 1 / (pi ax ay), so p = (a_n^x a_n^y) / (a_w^x a_w^y)
    (isotropic: a_n^2 / a_w^2).

    Parameters
    ----------
    alpha_n, alpha_w : (alpha_x, alpha_y) pairs of array_like > 0
    model : {"ggx", "beckmann"}
    """
    _params.choice("model", model, PEAK_MODELS)
    (nx, ny), (wx, wy) = _pair("alpha_n", alpha_n), _pair("alpha_w", alpha_w)
    return _peak(_params.real("alpha_n[0]", nx, 0.0, np.inf, lo_open=True),
                 _params.real("alpha_n[1]", ny, 0.0, np.inf, lo_open=True),
                 _params.real("alpha_w[0]", wx, 0.0, np.inf, lo_open=True),
                 _params.real("alpha_w[1]", wy, 0.0, np.inf, lo_open=True))


def _ratio_and_haziness(r_c, p, haziness):
    r_c = _params.real("r_c", r_c, 0.0, 1.0)
    p = _params.real("p", p, 0.0, 1.0, lo_open=True)
    haziness = _params.real("haziness", haziness, 0.0, 1.0)
    return r_c, p, haziness


def _intensity(r_c, p, haziness):
    """``haze_intensity`` of validated arrays."""
    with np.errstate(divide="ignore", invalid="ignore"):  # p = 1: only the first branch
        return haziness * pick(r_c <= p, r_c / p, (1.0 - r_c) / (1.0 - p))


def haze_intensity(r_c, p, haziness):
    """k_h = beta_h r_c / p for r_c <= p, beta_h (1 - r_c) / (1 - p) otherwise
    [Barla2018, eq. 7]: the haziness beta_h in [0, 1] is the share of the haze allowed by
    positivity (k_h <= r_c / p) and energy conservation (k_h <= (1 - r_c) / (1 - p)), eq. 6.
    r_c in [0, 1], p in (0, 1] (p = 1, haze extent 0, is the limit of one lobe)."""
    return _intensity(*_ratio_and_haziness(r_c, p, haziness))


def _intensity_smooth(r_c, p, haziness, w):
    """``haze_intensity_smooth`` of validated arrays."""
    u = _bezier_parameter(r_c, p, w)
    v = _bezier_parameter(1.0 - r_c, 1.0 - p, w)  # 1 - u
    return 2.0 * v * u * w * haziness / (v * v + 2.0 * v * u * w + u * u)


def haze_intensity_smooth(r_c, p, haziness, weight):
    """k_h on the quadratic rational Bézier curve through (0, 0), (p, beta_h), (1, 0) with
    weights (1, w, 1) [Barla2018, appendix]: smooth in r_c, inside the triangle of eq. 7's
    bounds, and eq. 7 in the limit w -> inf.

    The curve parameter u of r_c is the root in [0, 1] of (1 - b) u^2 + b u - r_c = 0 with
    b = 2 (r_c (1 - w) + w p) (eq. 14). The paper's root u = (b - sqrt(D)) / (2 (b - 1)),
    D = b^2 - 4 (b - 1) r_c (eqs. 12-13), is 0 / 0 at b = 1, where the paper switches to a
    Taylor expansion. We use the same root in the form free of cancellation for the sign of
    b (``_bezier_parameter``), and 1 - u from the mirrored curve (r_c -> 1 - r_c, p -> 1 - p),
    so that both ends are exact. Then
    k_h = 2 (1 - u) u w beta_h / ((1 - u)^2 + 2 (1 - u) u w + u^2) (eq. 15).
    ``r_c``, ``p``, ``haziness`` as ``haze_intensity``; ``weight`` w in (0, inf).
    """
    r_c, p, haziness = _ratio_and_haziness(r_c, p, haziness)
    w = _params.real("weight", weight, 0.0, np.inf, lo_open=True)
    return _intensity_smooth(r_c, p, haziness, w)


def _bezier_parameter(x, p, w):
    """The root u in [0, 1] of (1 - b) u^2 + b u - x = 0, b = 2 (x (1 - w) + w p): for b > 0
    u = 2 x / (b + sqrt(D)), else u = (b - sqrt(D)) / (2 (b - 1)) (both eq. 12, the first
    multiplied through by b + sqrt(D)), with D = (b - 2 x)^2 + 4 x (1 - x) (eq. 13 as a sum
    of non-negative terms). Neither form cancels or divides by zero where it is used."""
    b = 2.0 * (x * (1.0 - w) + w * p)
    root = np.sqrt((b - 2.0 * x) ** 2 + 4.0 * x * (1.0 - x))
    positive = b > 0.0
    with np.errstate(divide="ignore", invalid="ignore"):  # each form where it is regular
        u = pick(positive, 2.0 * x / (b + root), (b - root) / (2.0 * (b - 1.0)))
    return np.clip(u, 0.0, 1.0)  # removes rounding only


class HazeMapping(NamedTuple):
    """Physical parameters of [Barla2018, eq. 1] from the perceptual ones (``haze_mapping``).

    Attributes
    ----------
    reflectivity : ndarray (..., 3)
        Global reflectivity r = F_r(0) per channel, r_c scaled to keep its chroma (§2.4).
    eta, kappa : ndarray (..., 3)
        Complex index of the shared Fresnel term (Gulbrandsen's mapping of r and the edge
        tint; kappa = 0 where the edge tint is 0, a dielectric). Where r = 1 the index is
        infinite (eta = kappa = inf): the Fresnel term is 1 at every angle.
    beta : ndarray (...)
        Weight of the wide lobe, k_h / r (a scalar per element: both lobes share F_r).
    alpha_n, alpha_w : tuple of ndarray
        (alpha_x, alpha_y) of the narrow (unchanged) and wide lobes.
    peak_ratio, haze_intensity : ndarray (...)
        p and k_h (of the largest channel of r_c).
    """

    reflectivity: np.ndarray
    eta: np.ndarray
    kappa: np.ndarray
    beta: np.ndarray
    alpha_n: tuple
    alpha_w: tuple
    peak_ratio: np.ndarray
    haze_intensity: np.ndarray


def haze_mapping(core_reflectivity, haziness, haze_extent, alpha_x, alpha_y=None,
                 edge_tint=0.0, haze_extent_y=None, smooth_weight=None,
                 model: str = "ggx") -> HazeMapping:
    """The HAZEMAPPING algorithm of [Barla2018, §2.4].

    alpha_w from eq. 8, p from Table 2, k_h of the largest channel r^_c of r_c by eq. 7 (or
    eq. 15 with ``smooth_weight`` w), r^ = r^_c + (1 - p) k_h (eq. 5), r = (r^ / r^_c) r_c,
    (eta, kappa) from Gulbrandsen's mapping of (r, g), beta = k_h / r^ (eq. 4). Where r^_c = 0
    there is no haze (k_h = 0) and beta = 0.

    Parameters
    ----------
    core_reflectivity : colour in [0, 1]      r_c, the specular core's reflectivity F_c(0).
    haziness : array_like in [0, 1]           beta_h.
    haze_extent : array_like in [0, inf)      lambda_h (along x; ``haze_extent_y`` along y,
                                              default the same).
    alpha_x, alpha_y : array_like in (0, inf) narrow roughness (``alpha_y`` default alpha_x).
    edge_tint : colour in [0, 1]              g (0: a dielectric).
    smooth_weight : float in (0, inf) or None w of the smooth form (None: eq. 7).
    model : {"ggx", "beckmann"}               the lobes' distribution (for p).
    """
    r_c = _params.color("core_reflectivity", core_reflectivity, 0.0, 1.0)
    g = _params.color("edge_tint", edge_tint, 0.0, 1.0)
    h = _params.real("haziness", haziness, 0.0, 1.0)
    lx = _params.real("haze_extent", haze_extent, 0.0, np.inf)
    ly = lx if haze_extent_y is None else _params.real("haze_extent_y", haze_extent_y, 0.0,
                                                       np.inf)
    ax = _params.real("alpha_x", alpha_x, 0.0, np.inf, lo_open=True)
    ay = ax if alpha_y is None else _params.real("alpha_y", alpha_y, 0.0, np.inf,
                                                 lo_open=True)
    w = (None if smooth_weight is None
         else _params.real("smooth_weight", smooth_weight, 0.0, np.inf, lo_open=True))
    _params.choice("model", model, PEAK_MODELS)
    named = [("core_reflectivity", r_c, 1), ("edge_tint", g, 1), ("haziness", h, 0),
             ("haze_extent", lx, 0), ("haze_extent_y", ly, 0), ("alpha_x", ax, 0),
             ("alpha_y", ay, 0)] + ([] if w is None else [("smooth_weight", w, 0)])
    _params.batch_shape([(n, a) for n, a, _ in named], trailing=[t for *_, t in named])
    alpha_w = _wide(ax, ay, lx, ly)
    p = _peak(ax, ay, *alpha_w)
    _check_derived(alpha_w, p, lx, ly, ax, ay)
    r_hat_c = r_c.max(axis=-1)
    k_h = _intensity(r_hat_c, p, h) if w is None else _intensity_smooth(r_hat_c, p, h, w)
    r_hat = r_hat_c + (1.0 - p) * k_h
    with np.errstate(divide="ignore", invalid="ignore"):  # r^_c = 0: no haze
        scale = pick(r_hat_c > 0.0, r_hat / r_hat_c, 1.0)
        beta = pick(r_hat > 0.0, np.minimum(k_h / r_hat, 1.0), 0.0)  # (rounding: eq. 6)
    r = np.minimum(r_c * scale[..., None], 1.0)  # (1 + rounding: r <= 1 by eq. 6)
    mirror = r >= 1.0
    eta, kappa = gulbrandsen_to_ior(pick(mirror, 0.0, r), g)
    eta = pick(mirror, np.inf, eta)
    kappa = pick(mirror, np.inf, kappa)
    return HazeMapping(r, eta, kappa, beta, (ax, ay), alpha_w, p, k_h)


def _check_derived(alpha_w, p, lx, ly, ax, ay):
    """Raise, naming the user's parameters, where huge haze extents overflow alpha_w or
    underflow p to 0 (alpha_w / alpha_n beyond ~1e154 per axis)."""
    bad = ~(np.isfinite(alpha_w[0]) & np.isfinite(alpha_w[1]) & (p > 0.0))
    if np.any(bad):
        def first(a):
            return np.broadcast_to(a, bad.shape)[bad].flat[0].item()
        raise ValueError(f"haze_extent = {first(lx)!r} (haze_extent_y = {first(ly)!r}) with "
                         f"alpha_x = {first(ax)!r}, alpha_y = {first(ay)!r} makes the wide "
                         "lobe's roughness alpha_w = alpha_n + haze_extent sqrt(alpha_x "
                         "alpha_y) overflow or its peak ratio p (eq. 8, Table 2) underflow "
                         "to 0; allowed: haze extents with alpha_w finite and p > 0")
