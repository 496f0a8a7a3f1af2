"""A lobe seen through a linear map of the sphere, for chi-square tests of razor-thin lobes.

Public API
----------
``Stretched``      wrapper whose ``sample``/``pdf`` are a lobe's, mapped by w -> A w / |A w|.
``ridge_stretch``  the matrix that widens a ridge lying in a vertical plane.

Why
---
At ASM roughness 0 and anisotropy 1 (alpha_x = 1, alpha_y = ``ALPHA_MIN`` = 1e-8) a GGX lobe's
directions lie within ~1e-8 rad of a plane through the normal: no sphere grid of
``chi2_test`` resolves that ridge. The map w -> A w / |A w| is a bijection of the sphere with a
closed-form Jacobian, so testing the mapped samples against the mapped pdf is the same test,
exactly, of the original sampler against the original pdf; a matrix that stretches the
direction across the ridge by ~1e7 makes it a few tenths of a radian wide.

Jacobian
--------
Let g(w) = A w / |A w| on the unit sphere, A invertible. Place w in an orthonormal frame
(w, t1, t2). The differential of v -> v / |v| at v = A w projects onto the plane normal to
v and divides by |v|, so dg maps the tangent vectors t1, t2 to
P (A t1) / |A w| and P (A t2) / |A w| with P = I - v v^T / |v|^2. The area they span is
|(A t1 x A t2) . v| / (|v| |A w|^2) = |det A| |(A^-T w) . A w| / |A w|^3 = |det A| / |A w|^3
(cofactor identity A t1 x A t2 = det(A) A^-T (t1 x t2), t1 x t2 = w, and
(A^-T w) . (A w) = w . w = 1). Hence dw' = |det A| / |A w|^3 dw, and a density p of w
becomes the density of w' = g(w)

    p'(w') = p(w) |A w|^3 / |det A|,   w = A^-1 w' / |A^-1 w'|,

equivalently p(w) / (|det A| |A^-1 w'|^3), since |A^-1 w'| = 1 / |A w|.
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf.bsdf import BSDFSample, Flags

__all__ = ["Stretched", "ridge_stretch"]

#: matrices whose 2-norm condition number exceeds this are treated as singular
MAX_CONDITION = 1e12


def ridge_stretch(phi, factor) -> np.ndarray:
    """A = R(phi) diag(1, factor, 1) R(-phi), R(t) the rotation by t about z.

    Scales by ``factor`` the component of a direction normal to the vertical plane spanned by
    (cos phi, sin phi, 0) and z, and leaves the plane itself unchanged: with ``Stretched``, a
    ridge of directions lying within eps of that plane becomes about ``factor * eps`` wide.
    z is kept, so the map keeps each direction's hemisphere (and cos theta's sign).

    Parameters
    ----------
    phi : float
        Azimuth of the plane (radians, any finite value).
    factor : float
        Stretch across the plane, in (0, inf).

    Returns
    -------
    ndarray (3, 3)
    """
    phi = float(_params.real("phi", phi))
    factor = float(_params.real("factor", factor, 0.0, np.inf, lo_open=True, hi_open=True))
    c, s = np.cos(phi), np.sin(phi)
    rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return rotation @ np.diag([1.0, factor, 1.0]) @ rotation.T


class Stretched:
    """``lobe`` with its directions mapped by w -> w' = A w / |A w| (A an invertible 3x3).

    ``sample(wo, u)`` draws ``lobe.sample(wo, u)`` and maps ``wi``; ``pdf(wo, w')`` is the
    density of the mapped samples, lobe.pdf(wo, w) |A w|^3 / |det A| with
    w = A^-1 w' / |A^-1 w'| (module docstring). ``wo`` is passed to ``lobe`` unchanged. A
    chi-square test of ``Stretched(lobe, A)`` is therefore a test of ``lobe`` itself.

    Parameters
    ----------
    lobe : object
        Anything with ``sample(wo, u) -> BSDFSample`` and ``pdf(wo, wi)`` (and ``eval`` for
        ``Stretched.eval``), e.g. a ``Lobe``.
    matrix : array_like (3, 3)
        A, finite and invertible (2-norm condition number at most ``MAX_CONDITION``; for a
        general A the preimage w carries a relative error of order cond(A) eps).

    Notes
    -----
    Samples keep their ``weight`` and ``flags``; their ``pdf`` is mapped as above (delta
    samples keep their discrete probability). A failed sample (pdf 0, zero ``wi``) stays
    failed with a zero ``wi``. ``eval`` is defined so that ``eval(wo, w') |w'.z| dw'`` is
    ``lobe.eval(wo, w) |w.z| dw``, which keeps weight = eval |cos| / pdf; the reflection /
    transmission flags keep their meaning when A keeps the sign of z (as ``ridge_stretch``).
    """

    def __init__(self, lobe, matrix):
        if not (callable(getattr(lobe, "sample", None)) and callable(getattr(lobe, "pdf", None))):
            raise ValueError(f"lobe = {lobe!r}: allowed an object with sample and pdf methods")
        try:
            a = np.array(matrix, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"matrix = {matrix!r} is not a real 3x3 matrix") from exc
        if a.shape != (3, 3):
            raise ValueError(f"matrix has shape {a.shape}; allowed (3, 3)")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"matrix = {a.tolist()} has non-finite entries; allowed finite")
        condition = float(np.linalg.cond(a)) if np.any(a) else np.inf
        if not condition <= MAX_CONDITION:
            raise ValueError(f"matrix = {a.tolist()} is singular (condition number "
                             f"{condition:.3g}); allowed an invertible matrix with condition "
                             f"number in [1, {MAX_CONDITION:g}]")
        self.lobe = lobe
        self.matrix = a
        self.inverse = np.linalg.inv(a)
        self.abs_det = abs(float(np.linalg.det(a)))
        self.flags = getattr(lobe, "flags", Flags.NONE)

    def __repr__(self) -> str:
        return f"Stretched({self.lobe!r}, matrix={self.matrix.tolist()})"

    def _preimage(self, wi):
        """(w, |A^-1 w'|) for validated mapped directions w' = ``wi``."""
        v = wi @ self.inverse.T
        n = np.linalg.norm(v, axis=-1)
        return v / n[..., None], n

    def _jacobian_at_preimage(self, n):
        """dw / dw' = |A w|^3 / |det A| = 1 / (|det A| |A^-1 w'|^3)."""
        return 1.0 / (self.abs_det * n**3)

    def pdf(self, wo, wi) -> np.ndarray:
        """Density ``(...)`` of the mapped samples at w' = ``wi`` (solid angle)."""
        w, n = self._preimage(_params.direction("wi", wi))
        return self.lobe.pdf(wo, w) * self._jacobian_at_preimage(n)

    def eval(self, wo, wi) -> np.ndarray:
        """lobe.eval(wo, w) |w.z| (dw / dw') / |w'.z|, RGB ``(..., 3)``; 0 where w'.z = 0."""
        wi = _params.direction("wi", wi)
        w, n = self._preimage(wi)
        z = np.abs(wi[..., 2])
        scale = np.abs(w[..., 2]) * self._jacobian_at_preimage(n)
        scale = np.divide(scale, z, out=np.zeros_like(scale), where=z > 0.0)
        return self.lobe.eval(wo, w) * scale[..., None]

    def sample(self, wo, u) -> BSDFSample:
        """``lobe.sample(wo, u)`` with ``wi`` mapped to A wi / |A wi| and its density mapped."""
        s = self.lobe.sample(wo, u)
        wi = np.asarray(s.wi, dtype=np.float64)
        v = wi @ self.matrix.T
        n = np.linalg.norm(v, axis=-1)
        ok = n > 0.0  # failed samples have wi = 0
        mapped = v / np.where(ok, n, 1.0)[..., None]
        delta = (np.asarray(s.flags) & Flags.DELTA) != 0
        pdf = np.where(delta, s.pdf, s.pdf * n**3 / self.abs_det)
        return BSDFSample(np.where(ok[..., None], mapped, 0.0), s.weight, pdf, s.flags)
