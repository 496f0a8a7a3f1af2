"""Warps from the unit square to directions (shared by lobes)."""

from __future__ import annotations

import numpy as np

__all__ = ["concentric_disk", "cosine_hemisphere"]


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
