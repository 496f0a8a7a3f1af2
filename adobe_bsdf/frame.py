"""Shading frames: local <-> world, and rotation of the tangent (anisotropy angle).

Public API
----------
``dot``, ``normalize``, ``reflect``, ``refract``: vector helpers on arrays ``(..., 3)``.
``Frame(n, t=None)``: orthonormal frame (t, b, n); ``to_local`` / ``to_world``.
``coordinate_system(n)``: a tangent and bitangent for a normal.
``rotate_tangent(t, n, angle)``: rotate ``t`` counter-clockwise about ``n`` by ``angle`` radians.

Conventions (``docs/conventions.md``): local frame x = tangent, y = bitangent, z = normal;
anisotropic ``alpha_x`` lies along the tangent; a positive angle turns x towards y.

References
----------
[Duff2017] the orthonormal basis of ``coordinate_system``.
[Pharr2023, §9.3] Snell's law in vector form (``refract``).
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params

__all__ = ["dot", "normalize", "reflect", "refract", "coordinate_system", "rotate_tangent",
           "Frame"]


def dot(a, b) -> np.ndarray:
    """Dot product over the trailing axis (a plain multiply-add: faster than einsum)."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def normalize(v) -> np.ndarray:
    """``v / |v|``; the zero vector stays zero (never NaN)."""
    v = np.asarray(v, dtype=np.float64)
    n = np.sqrt(dot(v, v))
    return v / np.where(n > 0, n, 1.0)[..., None]


def reflect(w, m) -> np.ndarray:
    """Mirror ``w`` about the unit normal ``m``: ``2 (w.m) m - w`` (both point away)."""
    return 2.0 * dot(w, m)[..., None] * m - w


def refract(w, m, eta):
    """Refract ``w`` through a facet with unit normal ``m``.

    ``eta`` is the relative index n_t / n_i where the incident side is the one ``w`` lies on
    (with respect to ``m``). Returns ``(wt, valid)``; ``valid`` is False under total internal
    reflection, where ``wt`` is 0. Snell's law in vector form ([Pharr2023, §9.3], ``Refract``).
    """
    cos_i = dot(w, m)
    inv = 1.0 / np.asarray(eta, dtype=np.float64)
    sin2_t = inv * inv * np.maximum(0.0, 1.0 - cos_i * cos_i)
    valid = sin2_t < 1.0
    cos_t = np.sqrt(np.maximum(0.0, 1.0 - sin2_t))
    # the transmitted direction lies on the other side of m from w
    wt = -inv[..., None] * w + (inv * cos_i - np.sign(cos_i) * cos_t)[..., None] * m
    return np.where(valid[..., None], wt, 0.0), valid


def coordinate_system(n):
    """Tangent and bitangent ``(t, b)`` completing the unit normal ``n`` [Duff2017]."""
    n = np.asarray(n, dtype=np.float64)
    x, y, z = n[..., 0], n[..., 1], n[..., 2]
    sign = np.where(z >= 0.0, 1.0, -1.0)
    a = -1.0 / (sign + z)
    b = x * y * a
    t = np.stack([1.0 + sign * x * x * a, sign * b, -sign * x], axis=-1)
    bt = np.stack([b, sign + y * y * a, -y], axis=-1)
    return t, bt


def rotate_tangent(t, n, angle):
    """Rotate tangent ``t`` about normal ``n`` by ``angle`` radians, counter-clockwise seen
    from the tip of ``n`` (Rodrigues' formula, ``t`` perpendicular to ``n``)."""
    t = np.asarray(t, dtype=np.float64)
    n = np.asarray(n, dtype=np.float64)
    angle = _params.real("angle", angle)[..., None]
    return np.cos(angle) * t + np.sin(angle) * np.cross(n, t)


class Frame:
    """Orthonormal shading frame from a normal and (optionally) a tangent.

    The tangent is made orthogonal to ``n`` by Gram–Schmidt; without a tangent (or with one
    parallel to ``n``) ``coordinate_system`` supplies one. ``angle`` rotates the tangent
    about ``n`` (ASM anisotropy rotation, [Kutz2021, §3]).
    """

    def __init__(self, n, t=None, angle=0.0):
        n = normalize(_params.real("n", n))
        if np.any(dot(n, n) == 0.0):
            raise ValueError("n contains a zero vector; allowed: non-zero 3-vectors")
        t_auto, _ = coordinate_system(n)
        if t is None:
            t = t_auto
        else:
            t = _params.real("t", t)
            t = t - dot(t, n)[..., None] * n
            length = np.sqrt(dot(t, t))
            t = np.where((length > 1e-12)[..., None], t / np.maximum(length, 1e-300)[..., None],
                         t_auto)
        self.n = n
        self.t = rotate_tangent(t, n, angle)
        self.b = np.cross(n, self.t)

    def to_local(self, v) -> np.ndarray:
        """World vector(s) ``v`` to local coordinates (x along t, y along b, z along n)."""
        return np.stack([dot(v, self.t), dot(v, self.b), dot(v, self.n)], axis=-1)

    def to_world(self, v) -> np.ndarray:
        """Local vector(s) ``v`` to world coordinates."""
        v = np.asarray(v, dtype=np.float64)
        return v[..., 0:1] * self.t + v[..., 1:2] * self.b + v[..., 2:3] * self.n
