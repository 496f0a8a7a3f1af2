"""Warps from the unit square to directions (shared by lobes)."""

from __future__ import annotations

import numpy as np

from adobe_bsdf._channels import pick, picks

__all__ = ["unit_circle", "azimuth", "concentric_disk", "disk_xy", "cosine_hemisphere",
           "henyey_greenstein_cos", "G_ISOTROPIC"]

#: below this |g| the Henyey–Greenstein cosine is drawn as the isotropic one (the inversion
#: divides by g)
G_ISOTROPIC = 1e-3


def unit_circle(half_angle):
    """``(cos 2x, sin 2x)`` for ``half_angle`` x in [0, pi) or [-pi/2, pi/2], by the
    half-angle formulas of t = tan x: ((1 - t^2) / (1 + t^2), 2 t / (1 + t^2)). One tangent
    (vectorised in NumPy's SIMD library) instead of a cosine and a sine (scalar, several
    times slower on float64); within 2.3e-16 of np.cos and np.sin of 2x (the argument's
    own rounding). At x = fl(pi / 2), t = 1.6e16 and the point is (-1, 1.2e-16)."""
    t = np.tan(half_angle)
    t2 = t * t
    inv = 1.0 / (1.0 + t2)
    return (1.0 - t2) * inv, (2.0 * t) * inv


def azimuth(u):
    """``(cos phi, sin phi)`` of phi = 2 pi u, ``u`` in [0, 1) (``unit_circle``)."""
    return unit_circle(np.pi * u)


def concentric_disk(u2) -> np.ndarray:
    """[ShirleyChiu1997] concentric map of ``u2 in [0, 1)^2`` to the unit disk, ``(..., 2)``:
    with a, b = 2 u - 1, the point r (cos phi, sin phi) with r, phi = a, (pi/4) b / a where
    |a| > |b|, else b, pi/2 - (pi/4) a / b; cos and sin of the wedge angle (pi/4) ratio by
    ``unit_circle``."""
    u2 = np.asarray(u2, dtype=np.float64)
    out = np.empty(u2.shape[:-1] + (2,))
    out[..., 0], out[..., 1] = disk_xy(u2[..., 0], u2[..., 1])
    return out


def disk_xy(u0, u1):
    """``concentric_disk`` on components: ``(x, y)``."""
    a = 2.0 * u0 - 1.0
    b = 2.0 * u1 - 1.0
    first = np.abs(a) > np.abs(b)
    r, other = picks(first, a, b)
    ratio = other / pick(r == 0.0, 1.0, r)  # in [-1, 1]
    cos, sin = unit_circle((np.pi / 8.0) * ratio)
    x, y = picks(first, cos, sin)
    x *= r
    y *= r
    return x, y


def cosine_hemisphere(u2) -> np.ndarray:
    """Cosine-weighted direction on the upper hemisphere (Malley's method); pdf = z / pi."""
    u2 = np.asarray(u2, dtype=np.float64)
    out = np.empty(u2.shape[:-1] + (3,))
    x, y = disk_xy(u2[..., 0], u2[..., 1])
    out[..., 0], out[..., 1] = x, y
    np.sqrt(np.maximum(0.0, 1.0 - x ** 2 - y ** 2), out=out[..., 2])
    return out


def henyey_greenstein_cos(u, g) -> np.ndarray:
    """Cosine of the scattering angle (about the travel direction) drawn from the
    Henyey–Greenstein phase function of asymmetry ``g`` by inverting its cumulative
    distribution [Henyey1941; Pharr2023, §11.3.1]; uniform in [-1, 1] where |g| <
    ``G_ISOTROPIC``."""
    g = np.asarray(g, dtype=np.float64)
    small = np.abs(g) < G_ISOTROPIC
    safe = pick(small, 1.0, g)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (1.0 - safe * safe) / (1.0 - safe + 2.0 * safe * u)
        cos = (1.0 + safe * safe - s * s) / (2.0 * safe)
    return np.clip(pick(small, 1.0 - 2.0 * u, cos), -1.0, 1.0)
