"""Shading frames: local <-> world, and rotation of the tangent (anisotropy angle).

Public API
----------
``dot``, ``normalize``, ``reflect``, ``refract``: vector helpers on arrays ``(..., 3)``.
``Frame(n, t=None)``: orthonormal frame (t, b, n); ``to_local`` / ``to_world``.
``coordinate_system(n)``: a tangent and bitangent for a normal.
``rotate_tangent(t, n, angle)``: rotate ``t`` counter-clockwise about ``n`` by ``angle`` radians.

Conventions (``docs/conventions.md``): local frame x = tangent, y = bitangent, z = normal;
anisotropic ``alpha_x`` lies along the tangent; a positive angle turns x towards y.

Every function takes array_like vectors of shape ``(..., 3)`` (lists too) whose batch shapes
``...`` broadcast together (and with the frame's, for ``Frame.to_local`` / ``to_world``);
otherwise it raises ``ValueError`` naming the argument and its shape. The arguments documented
as unit vectors (``m`` of ``reflect``, ``w`` and ``m`` of ``refract``, ``n`` of
``coordinate_system``) must have unit length within ``_params.UNIT_TOLERANCE``: they are not
normalised silently (``Frame`` normalises its ``n``, built from any finite non-zero vector).

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


def _vectors(*named) -> list[np.ndarray]:
    """``[(name, value), ...]`` as float64 ``(..., 3)`` arrays whose batch shapes broadcast."""
    arrays = [_params.vectors(name, value) for name, value in named]
    if len(arrays) > 1:
        _params.batch_shape([(name, a) for (name, _), a in zip(named, arrays, strict=True)])
    return arrays


def _unit(name: str, arr: np.ndarray) -> np.ndarray:
    _params.check_unit(name, arr)
    return arr


def _dot(a, b) -> np.ndarray:
    """``dot`` of validated arrays."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def _normalize(v) -> np.ndarray:
    n = np.sqrt(_dot(v, v))
    return v / np.where(n > 0, n, 1.0)[..., None]


def dot(a, b) -> np.ndarray:
    """Dot product over the trailing axis of vectors ``(..., 3)`` (a plain multiply-add:
    faster than einsum)."""
    a, b = _vectors(("a", a), ("b", b))
    return _dot(a, b)


def normalize(v) -> np.ndarray:
    """``v / |v|`` of vectors ``(..., 3)``; the zero vector stays zero (never NaN)."""
    (v,) = _vectors(("v", v))
    return _normalize(v)


def reflect(w, m) -> np.ndarray:
    """Mirror ``w`` about the unit normal ``m``: ``2 (w.m) m - w`` (both point away)."""
    w, m = _vectors(("w", w), ("m", m))
    _unit("m", m)
    return 2.0 * _dot(w, m)[..., None] * m - w


def refract(w, m, eta):
    """Refract the unit vector ``w`` through a facet with unit normal ``m``.

    ``eta`` (in (0, inf), broadcasting with the vectors' batch) is the relative index
    n_t / n_i where the incident side is the one ``w`` lies on (with respect to ``m``).
    Returns ``(wt, valid)``; ``valid`` is False under total internal reflection, where ``wt``
    is 0. Snell's law in vector form ([Pharr2023, §9.3], ``Refract``).
    """
    w, m = _vectors(("w", w), ("m", m))
    _unit("w", w)
    _unit("m", m)
    eta = _params.real("eta", eta, 0.0, np.inf, lo_open=True)
    _params.batch_shape([("w", w), ("m", m)], eta.shape, "eta")
    cos_i = _dot(w, m)
    inv = 1.0 / eta
    sin2_t = inv * inv * np.maximum(0.0, 1.0 - cos_i * cos_i)
    valid = sin2_t < 1.0
    cos_t = np.sqrt(np.maximum(0.0, 1.0 - sin2_t))
    # the transmitted direction lies on the other side of m from w
    wt = -inv[..., None] * w + (inv * cos_i - np.sign(cos_i) * cos_t)[..., None] * m
    return np.where(valid[..., None], wt, 0.0), valid


def _coordinate_system(n):
    x, y, z = n[..., 0], n[..., 1], n[..., 2]
    sign = np.where(z >= 0.0, 1.0, -1.0)
    a = -1.0 / (sign + z)
    b = x * y * a
    t = np.stack([1.0 + sign * x * x * a, sign * b, -sign * x], axis=-1)
    bt = np.stack([b, sign + y * y * a, -y], axis=-1)
    return t, bt


def coordinate_system(n):
    """Tangent and bitangent ``(t, b)`` completing the unit normal(s) ``n`` ``(..., 3)``
    [Duff2017]."""
    (n,) = _vectors(("n", n))
    return _coordinate_system(_unit("n", n))


def _rotate_tangent(t, n, angle):
    return np.cos(angle) * t + np.sin(angle) * np.cross(n, t)


def rotate_tangent(t, n, angle):
    """Rotate tangent ``t`` about normal ``n`` by ``angle`` radians, counter-clockwise seen
    from the tip of ``n`` (Rodrigues' formula, ``t`` perpendicular to ``n``). ``t`` and ``n``
    are ``(..., 3)``; ``angle`` broadcasts with their batch shape."""
    t, n = _vectors(("t", t), ("n", n))
    angle = _params.real("angle", angle)
    _params.batch_shape([("t", t), ("n", n)], angle.shape, "angle")
    return _rotate_tangent(t, n, angle[..., None])


class Frame:
    """Orthonormal shading frame from a normal and (optionally) a tangent.

    The tangent is made orthogonal to ``n`` by Gram–Schmidt; without a tangent (or with one
    parallel to ``n``) ``coordinate_system`` supplies one. ``angle`` rotates the tangent
    about ``n`` (ASM anisotropy rotation, [Kutz2021, §3]).

    Parameters
    ----------
    n : array_like (..., 3)
        Normal(s), any non-zero length (normalised here: the frame is built from them).
    t : array_like (..., 3) or None
        Tangent(s), broadcasting with ``n``.
    angle : array_like
        Rotation of the tangent in radians, broadcasting with the batch shape of ``n``.

    Attributes
    ----------
    n, t, b : ndarray (..., 3)
        The frame's normal, tangent and bitangent; ``t`` and ``b`` have the frame's batch
        shape, against which ``to_local`` and ``to_world`` broadcast their vectors.
    """

    def __init__(self, n, t=None, angle=0.0):
        (n,) = _vectors(("n", n))
        bad = ~np.isfinite(n).all(axis=-1) | (_dot(n, n) == 0.0)
        if np.any(bad):
            raise ValueError(f"n = {n[bad][0]!r} is not a finite non-zero vector; allowed: "
                             "finite, non-zero 3-vectors")
        n = _normalize(n)
        angle = _params.real("angle", angle)
        t_auto, _ = _coordinate_system(n)
        if t is None:
            _params.batch_shape([("n", n)], angle.shape, "angle")
            t = t_auto
        else:
            (t,) = _vectors(("t", t))
            _params.batch_shape([("n", n), ("t", t)], angle.shape, "angle")
            if not np.all(np.isfinite(t)):
                raise ValueError(f"t = {t[~np.isfinite(t).all(axis=-1)][0]!r} is not finite; "
                                 "allowed: finite 3-vectors")
            t = t - _dot(t, n)[..., None] * n
            length = np.sqrt(_dot(t, t))
            t = np.where((length > 1e-12)[..., None], t / np.maximum(length, 1e-300)[..., None],
                         t_auto)
        self.n = n
        self.t = _rotate_tangent(t, n, angle[..., None])
        self.b = np.cross(n, self.t)

    def _batch(self, name, v) -> np.ndarray:
        (v,) = _vectors((name, v))
        _params.batch_shape([(name, v)], self.t.shape[:-1], "the frame's vectors")
        return v

    def to_local(self, v) -> np.ndarray:
        """World vector(s) ``v`` ``(..., 3)`` to local coordinates (x along t, y along b, z
        along n)."""
        v = self._batch("v", v)
        return np.stack([_dot(v, self.t), _dot(v, self.b), _dot(v, self.n)], axis=-1)

    def to_world(self, v) -> np.ndarray:
        """Local vector(s) ``v`` ``(..., 3)`` to world coordinates."""
        v = self._batch("v", v)
        return v[..., 0:1] * self.t + v[..., 1:2] * self.b + v[..., 2:3] * self.n
