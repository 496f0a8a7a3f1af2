"""The albedo of an anisotropic ``DielectricReflection`` as a layer's top: a grid over the
direction of ``wo``, built once per lobe from ``quadrature.sampled_albedo`` (the 32 x 32
visible-normal rule) and interpolated on every call.

E_top must not underestimate the top's albedo, or the layer's base would gain energy, so
the grid follows the two places where E varies fastest:

- grazing incidence, on the scale of the roughness projected on wo's azimuth a: the
  blended coordinate v of ``tables.anisotropic_energy`` (mu / 2a near grazing, (1 + mu) / 2
  above);
- seen from the dense side (index ratio eta < 1), the critical cosine mu_c = sqrt(1 - eta^2)
  of total internal reflection, blurred over ~a: there the node coordinate is
  u = (v + g) / 2, g an arctangent step of width a at mu_c, so that half the nodes lie
  around the kink.

The grid holds E / F(mu), F the smooth interface's Fresnel, or E itself. E / F is flat
where the lobe is nearly smooth (E = F above mu ~ a), and for eta >= 1, where F is smooth,
never worse than E (measured). For eta < 1, F has the kink itself: the grid builds both and
keeps the one closer to the rule at the cell centres.
"""

from __future__ import annotations

import threading

import numpy as np

from adobe_bsdf import quadrature
from adobe_bsdf.lobes.energy_lookup import anisotropic_coordinates
from adobe_bsdf.tables.anisotropic_energy import blended, projected_alpha, unblended
from adobe_bsdf.tables.table import Axis, Table, TableSpec

#: the nodes: the coordinate of mu (v for eta >= 1, u for eta < 1; module docstring) and
#: |cos phi| of ``energy_lookup.anisotropic_coordinates``, as the Fresnel moments' table
#: (``tables.catalog``), log-spaced towards the smooth axis
TOP_ALBEDO_AXES = (Axis("v", 0.0, 1.0, 48, "log-linear", "cubic"),
                   Axis("cos_phi", 0.0, 1.0, 32, "log-linear", "cubic", log_scale=0.3))
#: the same for eta < 1: u spends half its range around the critical cosine, evenly
DENSE_SIDE_AXES = (Axis("u", 0.0, 1.0, 48, "linear", "cubic"), TOP_ALBEDO_AXES[1])
#: the cosine standing for the limit mu -> 0+ at the nodes v = 0
MU_LIMIT = 1e-9
_LOCK = threading.Lock()


class TopAlbedoGrid:
    """E_top(wo) ``(...)`` of one anisotropic lobe with scalar parameters (``of``)."""

    def __init__(self, lobe):
        d = self.distribution = lobe.distribution
        self.fresnel = lobe.fresnel
        self.alpha_x_larger = bool(d.alpha_x >= d.alpha_y)
        self.alpha = max(float(d.alpha_x), float(d.alpha_y))
        self.ratio = min(float(d.alpha_x), float(d.alpha_y)) / self.alpha
        eta = float(lobe.eta)
        #: the critical cosine, None seen from the light side
        self.mu_c = np.sqrt(1.0 - eta * eta) if eta < 1.0 else None
        axes = TOP_ALBEDO_AXES if self.mu_c is None else DENSE_SIDE_AXES
        spec = TableSpec(f"top albedo of {lobe!r}", axes, ("E_R",), compute=None,
                         quadrature="quadrature.sampled_albedo, 32 x 32 Gauss-Legendre")
        coordinate, cos_phi = spec.grid()
        mu = self._cosine(coordinate, cos_phi)
        E, F = self._albedo(lobe, mu, cos_phi), self.fresnel(mu)
        candidates = {True: Table(spec, _over(E, F).reshape(spec.shape), np.zeros(spec.shape))}
        if self.mu_c is not None:  # keep the better of E / F and E at the cell centres
            candidates[False] = Table(spec, E.reshape(spec.shape), np.zeros(spec.shape))
            centre = [0.5 * (n[1:] + n[:-1]) for n in (a.nodes() for a in axes)]
            coordinate, cos_phi = (m.ravel() for m in np.meshgrid(*centre, indexing="ij"))
            mu = self._cosine(coordinate, cos_phi)
            E, F = self._albedo(lobe, mu, cos_phi)[:, 0], self.fresnel(mu)
            misses = {over: np.abs(table(coordinate, cos_phi)[..., 0] * (F if over else 1.0)
                                   - E).max() for over, table in candidates.items()}
            self.over_fresnel = min(misses, key=misses.get)
        else:
            self.over_fresnel = True
        self.table = candidates[self.over_fresnel]

    @classmethod
    def of(cls, lobe) -> TopAlbedoGrid:
        """The lobe's grid, built on first use (a fraction of a second) and kept."""
        with _LOCK:
            grid = lobe.__dict__.get("_top_grid")
            if grid is None:
                grid = lobe.__dict__["_top_grid"] = cls(lobe)
        return grid

    def __call__(self, wo) -> np.ndarray:
        """E_top at ``wo`` above the surface (``(...)``; callers zero it below)."""
        v, cos_phi, _, _ = anisotropic_coordinates(self.distribution, wo, blend=True)
        mu = np.maximum(wo[..., 2], 0.0)
        if self.mu_c is not None:
            v = 0.5 * (v + self._step(mu, projected_alpha(cos_phi, self.alpha, self.ratio)))
        E = self.table(v, cos_phi)[..., 0]
        return E * self.fresnel(mu) if self.over_fresnel else E

    def _step(self, mu, a):
        """g in [0, 1]: an arctangent step of width ``a`` at the critical cosine."""
        lo, hi = np.arctan(-self.mu_c / a), np.arctan((1.0 - self.mu_c) / a)
        return (np.arctan((mu - self.mu_c) / a) - lo) / (hi - lo)

    def _cosine(self, coordinate, cos_phi):
        """mu at the node ``coordinate`` (v, or u by bisection: u increases with mu), at
        least ``MU_LIMIT`` (at mu = 0 itself the lobe reflects nothing: the limit mu -> 0+
        is the lookup's case)."""
        a = projected_alpha(cos_phi, self.alpha, self.ratio)
        if self.mu_c is None:
            return np.maximum(unblended(coordinate, a), MU_LIMIT)
        lo, hi = np.zeros_like(coordinate), np.ones_like(coordinate)
        for _ in range(60):  # 2^-60: below the rounding of mu
            mid = 0.5 * (lo + hi)
            below = 0.5 * (blended(mid, a) + self._step(mid, a)) < coordinate
            lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
        return np.maximum(0.5 * (lo + hi), MU_LIMIT)

    def _albedo(self, lobe, mu, cos_phi):
        """``quadrature.sampled_albedo`` ``(n, 1)`` at cosines ``mu`` and |cos phi| from the
        axis of the larger roughness."""
        sin_theta = np.sqrt(1.0 - mu * mu)
        along = sin_theta * cos_phi
        across = sin_theta * np.sqrt(1.0 - cos_phi * cos_phi)
        x, y = (along, across) if self.alpha_x_larger else (across, along)
        return quadrature.sampled_albedo(lobe, np.stack([x, y, mu], -1))[:, :1]


def _over(E, F):
    """E / F ``(n, 1)`` (F ``(n,)`` is 0 only at eta = 1, where E = 0 too)."""
    F = F[:, None]
    return np.divide(E, F, out=np.zeros_like(E), where=F > 0.0)
