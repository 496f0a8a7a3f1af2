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
``Darkening(delta=1, base_roughness=1, variant="pr253", base_albedo=None)``
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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf._channels import pick
from adobe_bsdf.fresnel import _dielectric

__all__ = ["fresnel_average", "fresnel_average_fit", "internal_reflectance", "coat_reflectance",
           "darkening", "base_factor", "Darkening", "VARIANTS"]

#: the darkening formulas: [Portsmouth2025] (T^2 inside) and [OpenPBR2026] (outside)
VARIANTS = ("pr253", "v1.1.1")
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


@dataclass(frozen=True, eq=False)
class Darkening:
    """Coat darkening as a parameter of ``composition.Layer`` [OpenPBR2026, §Coat darkening;
    Portsmouth2025]: the layer's base is multiplied by

        D(wo) = lerp(1, Delta(E_b, K(wo), T2, variant), delta),
        K(wo) = coat_reflectance(eta_c, base_roughness, |cos theta_o|),

    with eta_c the top's index and T2 the layer's two-way transmittance at normal incidence.
    0 <= D <= 1 (Delta is, for E_b T2 <= 1): darkening never adds energy; delta = 0 is no
    darkening, a white base (E_b = 1, T2 grey) is darkened without a shift of hue.

    Attributes
    ----------
    delta : array_like in [0, 1]
        coat_darkening.
    base_roughness : array_like in [0, 1]
        r_b: K from the smooth base's estimate F(wo, eta_c) (0) to the rough one's internal
        reflectance (1).
    variant : one of ``VARIANTS``
    base_albedo : colour in [0, 1] or None
        E_b; None: the base's own energy albedo at normal incidence (its table where it has
        one, else a quadrature), computed once by the layer.
    """

    delta: object = 1.0
    base_roughness: object = 1.0
    variant: str = "pr253"
    base_albedo: object = None

    def __post_init__(self):
        checked = {"delta": _params.real("delta", self.delta, 0.0, 1.0),
                   "base_roughness": _params.real("base_roughness", self.base_roughness,
                                                  0.0, 1.0),
                   "variant": _params.choice("variant", self.variant, VARIANTS),
                   "base_albedo": (None if self.base_albedo is None else
                                   _params.color("base_albedo", self.base_albedo, 0.0, 1.0))}
        for name, value in checked.items():
            object.__setattr__(self, name, value)

    def factor(self, eta, cos_theta, E_b, T2, K_rough) -> np.ndarray:
        """D ``(..., 3)`` at the validated |cos theta_o| ``cos_theta`` under a coat of index
        ``eta`` with internal reflectance ``K_rough`` (``internal_reflectance(eta)``), over a
        base of albedo ``E_b`` with the two-way transmittance ``T2`` (colours in [0, 1])."""
        K = _coat_reflectance(eta, self.base_roughness, cos_theta, K_rough)
        Delta = _darkening(E_b, K[..., None], T2, self.variant)
        return _lerp_from_one(Delta, self.delta[..., None])
