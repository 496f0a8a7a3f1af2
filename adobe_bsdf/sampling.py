"""Warps from the unit square to directions (shared by lobes)."""

from __future__ import annotations

import numpy as np

__all__ = ["concentric_disk", "cosine_hemisphere", "henyey_greenstein_cos", "G_ISOTROPIC"]

#: below this |g| the Henyey–Greenstein cosine is drawn as the isotropic one (the inversion
#: divides by g)
G_ISOTROPIC = 1e-3


def concentric_disk(u2) -> np.ndarray:
    """[ShirleyChiu1997] concentric map of ``u2 in [0, 1)^2`` to the unit disk, ``(..., 2)``."""
    a = 2.0 * u2[..., 0] - 1.0
    b = 2.0 * u2[..., 1] - 1.0
    first = np.abs(a) > np.abs(b)
    r = np.where(first, a, b)
    safe_a = np.where(a == 0.0, 1.0, a)
    safe_b = np.where(b == 0.0, 1.0, b)
    phi = np.where(first, (np.pi / 4.0) * b / safe_a, np.pi / 2.0 - (np.pi / 4.0) * a / safe_b)
    return np.stack([r * np.cos(phi), r * np.sin(phi)], axis=-1)


def cosine_hemisphere(u2) -> np.ndarray:
    """Cosine-weighted direction on the upper hemisphere (Malley's method); pdf = z / pi."""
    d = concentric_disk(u2)
    z = np.sqrt(np.maximum(0.0, 1.0 - d[..., 0] ** 2 - d[..., 1] ** 2))
    return np.concatenate([d, z[..., None]], axis=-1)


def henyey_greenstein_cos(u, g) -> np.ndarray:
    """Cosine of the scattering angle (about the travel direction) drawn from the
    Henyey–Greenstein phase function of asymmetry ``g`` by inverting its cumulative
    distribution [Henyey1941; Pharr2023, §11.3.1]; uniform in [-1, 1] where |g| <
    ``G_ISOTROPIC``."""
    g = np.asarray(g, dtype=np.float64)
    small = np.abs(g) < G_ISOTROPIC
    safe = np.where(small, 1.0, g)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (1.0 - safe * safe) / (1.0 - safe + 2.0 * safe * u)
        cos = (1.0 + safe * safe - s * s) / (2.0 * safe)
    return np.clip(np.where(small, 1.0 - 2.0 * u, cos), -1.0, 1.0)
