"""Lambertian (ideal diffuse) reflection."""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf._channels import pick, tinted
from adobe_bsdf.bsdf import Flags, Lobe, finished_sample
from adobe_bsdf.sampling import cosine_hemisphere

__all__ = ["Lambert"]


class Lambert(Lobe):
    """Ideal diffuse reflection f = albedo / pi, one-sided (both directions above the surface).

    Parameters
    ----------
    albedo : colour in [0, 1], scalar or (..., 3)
        Directional albedo (constant in ``wo``).

    Notes
    -----
    Sampling is cosine-weighted (Malley's method on Shirley and Chiu's concentric disk),
    so ``weight = albedo`` exactly.
    """

    flags = Flags.REFLECTION | Flags.DIFFUSE

    def __init__(self, albedo=1.0):
        self.reflectance = _params.color("albedo", albedo, 0.0, 1.0)

    def __repr__(self) -> str:
        return f"Lambert(albedo={self.reflectance})"

    def _param_shape(self):
        return self.reflectance.shape[:-1]

    def _eval(self, wo, wi):
        up = (wo[..., 2] > 0.0) & (wi[..., 2] > 0.0)
        return tinted(up, self.reflectance / np.pi)  # 1 c and 0 c: c and 0 for c >= 0 finite

    def _pdf(self, wo, wi):
        up = (wo[..., 2] > 0.0) & (wi[..., 2] > 0.0)
        return pick(up, wi[..., 2] / np.pi, 0.0)

    def _sample(self, wo, u):
        wi = cosine_hemisphere(u[..., 1:3])
        ok = (wo[..., 2] > 0.0) & (wi[..., 2] > 0.0)
        shape = np.broadcast_shapes(ok.shape, self.reflectance.shape[:-1])
        ok = np.broadcast_to(ok, shape)
        weight = np.broadcast_to(self.reflectance, shape + (3,))
        return finished_sample(wi, weight, wi[..., 2] / np.pi,
                               pick(ok, int(self.flags), int(Flags.NONE)))
