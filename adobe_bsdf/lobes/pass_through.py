"""The pass-through (null) interface: light goes on unchanged, as if no surface were there."""

from __future__ import annotations

import numpy as np

from adobe_bsdf.bsdf import Flags, Lobe, finished_sample

__all__ = ["PassThrough"]


class PassThrough(Lobe):
    """A delta transmission from ``wo`` to ``-wo`` with throughput 1: no interface at all
    (Mitsuba 3's ``null`` BSDF). A surface of presence α is its mix with it,
    f = (1 - α) f_pass + α f_surface: the "ambient medium" of
    [Andersson2023, §Opacity / Transparency].

    ``eval`` and ``pdf`` are 0 (a delta); ``sample`` returns wi = -wo, weight 1, pdf 1 and
    the flags TRANSMISSION | DELTA | NULL, both sides alike; its energy is 1 from either side
    (0 in the tangent plane, where no direction leaves the surface). No index changes, so no
    radiance scaling, and it is reciprocal.
    """

    flags = Flags.TRANSMISSION | Flags.DELTA | Flags.NULL

    def __repr__(self) -> str:
        return "PassThrough()"

    def _param_shape(self):
        return ()

    def _eval(self, wo, wi):
        return np.zeros(np.broadcast_shapes(wo.shape, wi.shape))

    def _pdf(self, wo, wi):
        return np.zeros(np.broadcast_shapes(wo.shape, wi.shape)[:-1])

    def _sample(self, wo, u):
        shape = np.broadcast_shapes(wo.shape, u.shape)
        wo = np.broadcast_to(wo, shape)
        ok = wo[..., 2] != 0.0
        return finished_sample(-wo, np.ones(shape), np.ones(shape[:-1]),
                               np.where(ok, int(self.flags), int(Flags.NONE)))

    def _delta_albedo(self, wo):
        return np.repeat((wo[..., 2] != 0.0)[..., None].astype(np.float64), 3, axis=-1)

    def _albedo_table(self, wo, with_error=True):
        E = self._delta_albedo(wo)
        return E, (np.zeros_like(E) if with_error else None)
