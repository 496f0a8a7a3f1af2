"""A lobe turned about the normal: the ASM anisotropy rotation (seed 000 §3)."""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf.bsdf import BSDFSample, Lobe, Wrapper
from adobe_bsdf.registry import CheckCase, register

__all__ = ["Rotated", "anisotropy_rotation"]


def anisotropy_rotation(anisotropy_angle):
    """phi = 2 pi anisotropy_angle: the ASM rotation parameter is "normalized over the
    [0, 2 pi] domain" (seed 000 §3); ``anisotropy_angle`` in [0, 1]."""
    return 2.0 * np.pi * _params.real("anisotropy_angle", anisotropy_angle, 0.0, 1.0)


class Rotated(Wrapper):
    """``lobe`` with its tangent x axis (alpha_x) turned by ``phi`` about the normal.

    f(wo, wi) = lobe.f(R(-phi) wo, R(-phi) wi), with R(t) the rotation by t about z; samples
    are drawn in the lobe's frame and turned back by R(phi). A rotation about the normal keeps
    cosines, solid angles and the side of every direction, so the pdf, the sample weights,
    the albedo and (generalized) reciprocity carry over unchanged.

    Parameters
    ----------
    lobe : Lobe
    phi : array_like, radians (any real; ``anisotropy_rotation`` maps the ASM parameter).
    """

    def __init__(self, lobe: Lobe, phi):
        if not isinstance(lobe, Lobe):
            raise ValueError(f"lobe = {lobe!r}: allowed a Lobe")
        self.lobe = lobe
        self.phi = _params.real("phi", phi)
        self.flags = lobe.flags
        self._cos, self._sin = np.cos(self.phi), np.sin(self.phi)

    def __repr__(self) -> str:
        return f"Rotated({self.lobe!r}, phi={self.phi})"

    def _inner(self):
        return self.lobe

    def _param_shape(self):
        shape = self.lobe._param_shape()
        return None if shape is None else np.broadcast_shapes(shape, self.phi.shape)

    def _turn(self, w, sign):
        """R(sign phi) w."""
        c, s = self._cos, sign * self._sin
        x, y = w[..., 0], w[..., 1]
        return np.stack(np.broadcast_arrays(c * x - s * y, s * x + c * y, w[..., 2]), axis=-1)

    def _into(self, w):
        return self._turn(w, -1.0)

    def _eval(self, wo, wi):
        return self.lobe._eval(self._into(wo), self._into(wi))

    def _pdf(self, wo, wi):
        return self.lobe._pdf(self._into(wo), self._into(wi))

    def _eval_pdf(self, wo, wi):
        return self.lobe._eval_pdf(self._into(wo), self._into(wi))

    def _pdf_t(self, wo, wi, throughput):
        return self.lobe._pdf_t(self._into(wo), self._into(wi), throughput)

    def _eval_pdf_t(self, wo, wi, throughput):
        return self.lobe._eval_pdf_t(self._into(wo), self._into(wi), throughput)

    def _sample(self, wo, u):
        return self._sample_t(wo, u, None)

    def _sample_t(self, wo, u, throughput):
        s = self.lobe._sample_t(self._into(wo), u, throughput)
        return BSDFSample(self._turn(s.wi, 1.0), s.weight, s.pdf, s.flags)

    def _energy_scale(self, wo, wi):
        return self.lobe._energy_scale(wo, wi)  # depends on the sides only

    def _energy_scale_rgb(self, wo, wi):
        return self.lobe._energy_scale_rgb(wo, wi)

    def _albedo_quadrature(self, wo, tol):
        return self.lobe._albedo_quadrature(self._into(wo), tol)

    def _albedo_table(self, wo, with_error=True):
        return self.lobe._albedo_table(self._into(wo), with_error)

    def _top_albedo(self, wo):
        return self.lobe._top_albedo(self._into(wo))

    def _sampling_weight(self, wo):
        return self.lobe._sampling_weight(self._into(wo))

    def _delta_albedo(self, wo):
        return self.lobe._delta_albedo(self._into(wo))


def _rotated_conductor():
    from adobe_bsdf.lobes.conductor import Conductor

    return Rotated(Conductor(0.5, 0.1), np.pi / 3)


def _rotated_dielectric():
    from adobe_bsdf.lobes.dielectric import Dielectric

    return Rotated(Dielectric(1.5, 0.4, 0.05), np.pi / 2)


register(
    CheckCase("Rotated Conductor a=(0.5,0.1) phi=pi/3", _rotated_conductor),
    CheckCase("Rotated Dielectric eta=1.5 a=(0.4,0.05) phi=pi/2", _rotated_dielectric,
              cos_theta_o=(1.0, 0.5, 0.05, -0.5)),
)
