"""Energy of an anisotropic GGX dielectric interface, one (alpha, ratio, eta) at a time.

Public API
----------
``dielectric_slice(alpha, ratio, eta)``
    A ``DielectricSlice``: E_R and E_T seen from either side of the interface as functions
    of wo's cosine and azimuth, with their exact hemispherical averages; computed on first
    use and kept (``functools.lru_cache``).
``SLICE_ORDER``, ``SLICE_NODES``
    The node integrator's order and the slice's nodes.

Why slices and not one shipped table (``docs/tables.md``): the energy of a rough dielectric
depends on five coordinates (mu, phi, alpha, ratio, eta) and needs, along mu, alpha and eta,
the resolution of the isotropic tables (24 to 48 nodes each, measured in the tables report):
some 10^7 nodes, beyond any package size. A lobe holds one (alpha_x, alpha_y, eta), so it
needs only the two-dimensional slice through it: a few hundred nodes by
``anisotropic_energy.ggx_anisotropic_dielectric_energy`` (seconds), then lookups as fast as a
shipped table's. The slice is exact in alpha, ratio and eta; its error is the interpolation's
in (mu, phi), measured in the report.

Coordinates. In |cos phi| (from the axis of alpha_max) the nodes are those of
"ggx_conductor_anisotropic", log-spaced towards the smooth axis. In mu: seen from the less
dense side, the blended coordinate v (``anisotropic_energy.blended``: the grazing boundary
layer and mu itself). Seen from the dense side, total internal reflection sets in at the
critical cosine mu_c = sqrt(1 - 1 / eta^2), where the energy of a smooth interface has a
kink and a rough one a transition as narrow as the roughness: the slice is two tables, below
mu_c (in 1 - v / v_c, nodes crowded towards mu_c) and above it (in (mu - mu_c) / (1 - mu_c),
likewise), so that no stencil straddles it. The dense side stays the less accurate: at
grazing angles a nearly one-dimensional surface (ratio -> 0) has a second such kink along
|cos phi| = sqrt((mu_c^2 - mu^2) / (1 - mu^2)), which the tensor grid does not follow
(docs/tables.md).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from scipy.special import roots_legendre

from adobe_bsdf.tables.anisotropic_energy import (
    ALPHA_FLOOR,
    blended,
    ggx_anisotropic_dielectric_energy,
    projected_alpha,
    unblended,
)
from adobe_bsdf.tables.table import Axis, Table, TableSpec

__all__ = ["DielectricSlice", "dielectric_slice", "SLICE_ORDER", "SLICE_NODES",
           "SLICE_NODE_ERROR"]

#: Gauss–Legendre order of the slice's nodes
SLICE_ORDER = 8
#: the node integrator's error at ``SLICE_ORDER``: the largest difference to order 20 over
#: 200 random nodes (mu >= 0.005, alpha in [0.003, 1.5], ratio, eta in [1/3, 3]), measured
#: by ``benchmarks.tables_report`` and carried as every node's error estimate
SLICE_NODE_ERROR = 2e-4
#: nodes: (mu coordinate, |cos phi|) of the light side's table and of the dense side's two
SLICE_NODES = {"outside": (24, 14), "below": (16, 14), "above": (12, 14)}
#: slices kept in memory (each ~30 KB)
CACHED_SLICES = 256
#: Gauss points per cell and dimension of the averages
_AVERAGE_ORDER = 8


def _cos_phi_axis(n: int) -> Axis:
    return Axis("cos_phi", 0.0, 1.0, n, "log-linear", "cubic", log_scale=0.05)


@dataclass(frozen=True)
class _Part:
    """One table of a slice over (x, |cos phi|): x the mu coordinate of ``kind``
    ("outside": v; "below": 1 - v / v_c; "above": (mu - mu_c) / (1 - mu_c)), its nodes
    log-spaced towards x = 0 (grazing; mu_c from either side)."""

    kind: str
    mu_c: float
    table: Table

    def to_x(self, mu, a_phi):
        if self.kind == "outside":
            return np.minimum(blended(mu, a_phi), 1.0)
        if self.kind == "below":
            return np.clip(1.0 - blended(mu, a_phi) / blended(self.mu_c, a_phi), 0.0, 1.0)
        return np.clip((mu - self.mu_c) / (1.0 - self.mu_c), 0.0, 1.0)

    def to_mu(self, x, a_phi):
        if self.kind == "outside":
            return unblended(x, a_phi)
        if self.kind == "below":
            return np.minimum(unblended((1.0 - x) * blended(self.mu_c, a_phi), a_phi),
                              self.mu_c)
        return self.mu_c + x * (1.0 - self.mu_c)


def _part(kind: str, alpha: float, ratio: float, eta_seen: float, mu_c: float) -> _Part:
    n_x, n_phi = SLICE_NODES[kind]
    axes = (Axis("x", 0.0, 1.0, n_x, "log-linear", "cubic"), _cos_phi_axis(n_phi))
    spec = TableSpec(f"ggx_dielectric_anisotropic[{kind}, alpha={alpha:g}, ratio={ratio:g}, "
                     f"eta={eta_seen:g}]", axes, ("E_R", "E_T"), None,
                     "anisotropic_energy.ggx_anisotropic_dielectric_energy", SLICE_ORDER)
    x, cos_phi = spec.grid()
    a = max(alpha, ALPHA_FLOOR)
    empty = _Part(kind, mu_c, None)
    mu = empty.to_mu(x, projected_alpha(cos_phi, a, ratio))
    e = ggx_anisotropic_dielectric_energy(mu, np.arccos(cos_phi), a, ratio * a, eta_seen,
                                          SLICE_ORDER, estimate=False)
    values = np.stack([e.reflection, e.transmission], -1).reshape(spec.shape)
    return _Part(kind, mu_c, Table(spec, values, np.full(spec.shape, SLICE_NODE_ERROR)))


def _average(part: _Part, alpha: float, ratio: float) -> np.ndarray:
    """(1 / pi) int E cos dw over the directions of ``part``, ``(2,)``: Gauss–Legendre on
    every cell of its interpolant (exact for it to ~1e-9)."""
    x_axis, c_axis = part.table.spec.axes
    x, w = roots_legendre(_AVERAGE_ORDER)
    x, w = 0.5 * (x + 1.0), 0.5 * w
    phi_edges = np.arccos(c_axis.nodes())[::-1]
    phi = (phi_edges[:-1, None] + np.diff(phi_edges)[:, None] * x).ravel()
    w_phi = (np.diff(phi_edges)[:, None] * w).ravel() * (2.0 / np.pi)
    c = np.cos(phi)
    a_phi = projected_alpha(c, max(alpha, ALPHA_FLOOR), ratio)  # (P,)
    mu_edges = part.to_mu(x_axis.nodes()[:, None], a_phi)  # (S, P)
    lo, width = mu_edges[:-1, None, :], np.diff(mu_edges, axis=0)[:, None, :]
    mu = lo + width * x[None, :, None]
    weight = (2.0 * mu * width * w[None, :, None] * w_phi).ravel()
    coords = np.broadcast_arrays(part.to_x(mu, a_phi), c)
    return np.abs(weight) @ part.table(*(k.ravel() for k in coords))


@dataclass(frozen=True)
class DielectricSlice:
    """E_R, E_T of the anisotropic interface (alpha_max ``alpha``, alpha_min ``ratio``
    alpha, index ratio ``eta`` >= 1) seen from either side, and their averages."""

    alpha: float
    ratio: float
    eta: float
    parts: tuple
    average_outside: np.ndarray
    average_inside: np.ndarray

    def __call__(self, on_light, mu, cos_phi) -> np.ndarray:
        """``(..., 2)`` (E_R, E_T) at cosine ``mu`` and |cos phi| ``cos_phi`` (broadcast),
        seen from the light side where ``on_light``."""
        return self._lookup(on_light, mu, cos_phi, False)

    def error(self, on_light, mu, cos_phi) -> np.ndarray:
        """The node error carried to the same points (``Table.error``)."""
        return self._lookup(on_light, mu, cos_phi, True)

    def average(self, on_light) -> np.ndarray:
        """``(..., 2)`` averages of the side ``on_light``."""
        return np.where(np.asarray(on_light)[..., None], self.average_outside,
                        self.average_inside)

    def _lookup(self, on_light, mu, cos_phi, error):
        on_light, mu, cos_phi = np.broadcast_arrays(on_light, mu, cos_phi)
        out = np.zeros(mu.shape + (2,))
        a_phi = projected_alpha(cos_phi, max(self.alpha, ALPHA_FLOOR), self.ratio)
        outside, below, above = self.parts
        masks = (on_light, ~on_light & (mu < below.mu_c), ~on_light & (mu >= below.mu_c))
        for part, mask in zip(self.parts, masks, strict=True):
            if np.any(mask):
                coords = (part.to_x(mu[mask], a_phi[mask]), cos_phi[mask])
                out[mask] = part.table.error(*coords) if error else part.table(*coords)
        return out


@functools.lru_cache(maxsize=CACHED_SLICES)
def dielectric_slice(alpha: float, ratio: float, eta: float) -> DielectricSlice:
    """The slice of the interface with alpha_max = ``alpha``, alpha_min = ``ratio`` alpha
    and index ratio ``eta`` >= 1 (dense / light)."""
    alpha, ratio, eta = float(alpha), float(ratio), float(eta)
    mu_c = float(np.sqrt(1.0 - 1.0 / (eta * eta)))
    parts = (_part("outside", alpha, ratio, eta, mu_c),
             _part("below", alpha, ratio, 1.0 / eta, mu_c),
             _part("above", alpha, ratio, 1.0 / eta, mu_c))
    inside = _average(parts[1], alpha, ratio) + _average(parts[2], alpha, ratio)
    return DielectricSlice(alpha, ratio, eta, parts, _average(parts[0], alpha, ratio), inside)
