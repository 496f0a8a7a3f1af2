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
kink and a rough one a transition as narrow as the roughness; and below mu_c a nearly
one-dimensional surface (ratio -> 0) has a second one where its steepest facets, tilted
along the rough axis, leave total internal reflection: wo's component in the plane of that
axis and the normal reaches mu_c, |cos phi| = k(mu) = sqrt((mu_c^2 - mu^2) / (1 - mu^2)).
That side is therefore five tables (``_Part``): grazing and below mu_c, each on either side
of k(mu), and above mu_c, their nodes crowded towards grazing, mu_c and k(mu), so that no
interpolation stencil straddles a kink.
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
#: random nodes (mu >= 0.005, alpha in [0.003, 1.5], ratio, eta in [1/3, 3]), measured by
#: ``benchmarks.tables_report`` and carried as every node's error estimate
SLICE_NODE_ERROR = 2e-4
#: nodes (mu coordinate, azimuth coordinate) of each part (``_Part``)
SLICE_NODES = {"outside": (24, 16), "grazing-near": (12, 12), "grazing-far": (12, 12),
               "below-near": (10, 12), "below-far": (14, 16), "above": (12, 14)}
#: slices kept in memory (each ~40 KB)
CACHED_SLICES = 256
#: Gauss points per cell and dimension of the averages
_AVERAGE_ORDER = 8
#: fixed-point steps from a part's coordinates to (mu, phi) (contracting: mu depends on phi
#: only through the projected roughness of the blended coordinate)
_STEPS = 60


#: smallest relative node spacing of ``_two_sided``
_EDGE = 0.01
_Y0 = float(np.log(_EDGE / (1.0 + _EDGE)))


def _two_sided(t):
    """u in [0, 1] of t in [0, 1] whose uniform nodes crowd geometrically towards both ends
    of t: u = (ln((t + e) / (1 - t + e)) - Y0) / (-2 Y0), e = ``_EDGE``."""
    return (np.log((t + _EDGE) / (1.0 - t + _EDGE)) - _Y0) / (-2.0 * _Y0)


def _two_sided_inverse(u):
    """t of ``_two_sided``."""
    q = np.exp(_Y0 * (1.0 - 2.0 * np.asarray(u, dtype=np.float64)))
    return np.clip((q * (1.0 + _EDGE) - _EDGE) / (1.0 + q), 0.0, 1.0)


def _kink(mu, mu_c):
    """k(mu) = sqrt((mu_c^2 - mu^2) / (1 - mu^2)), 0 from mu_c up."""
    return np.sqrt(np.maximum(mu_c * mu_c - mu * mu, 0.0) / np.maximum(1.0 - mu * mu, 1e-300))


@dataclass(frozen=True)
class _Part:
    """One table of a slice over (x, u), both in [0, 1], nodes log-spaced towards 0 or (the
    ``_two_sided`` coordinates) uniform.

    x, the cosine coordinate: "outside": v (``blended``); on the dense side, with v_c the v
    of mu_c: "grazing-*": ``_two_sided``(2 v / v_c), "below-*": ``_two_sided``(2 - 2 v /
    v_c), "above": (mu - mu_c) / (1 - mu_c). u, the azimuth coordinate (c = |cos phi|):
    "*-near": ``_two_sided``(c / k(mu)) (crowded towards the smooth axis and the kink),
    "*-far": (c - k) / (1 - k), else c itself.
    """

    kind: str
    mu_c: float
    alpha: float
    ratio: float
    table: Table | None = None

    def _a_phi(self, c):
        return projected_alpha(c, max(self.alpha, ALPHA_FLOOR), self.ratio)

    def coordinates(self, mu, c):
        """(x, u) of directions (mu, |cos phi| = c) of this part."""
        a_phi = self._a_phi(c)
        if self.kind == "outside":
            x = np.minimum(blended(mu, a_phi), 1.0)
        elif self.kind == "above":
            x = np.clip((mu - self.mu_c) / (1.0 - self.mu_c), 0.0, 1.0)
        else:
            t = 2.0 * blended(mu, a_phi) / blended(self.mu_c, a_phi)
            x = _two_sided(np.clip(t if self.kind.startswith("grazing") else 2.0 - t, 0.0, 1.0))
        k = _kink(mu, self.mu_c)
        if self.kind.endswith("near"):
            u = _two_sided(np.clip(np.where(k > 0.0, c / np.where(k > 0.0, k, 1.0), 1.0),
                                   0.0, 1.0))
        elif self.kind.endswith("far"):
            u = (c - k) / (1.0 - k)
        else:
            u = c
        return x, np.clip(u, 0.0, 1.0)

    def directions(self, x, u):
        """(mu, |cos phi|) of the coordinates (x, u), by fixed-point steps where they depend
        on each other."""
        c = np.asarray(u, dtype=np.float64)
        for _ in range(_STEPS if "-" in self.kind else 1):
            a_phi = self._a_phi(c)
            if self.kind == "outside":
                mu = unblended(x, a_phi)
            elif self.kind == "above":
                mu = self.mu_c + x * (1.0 - self.mu_c)
            else:
                t = _two_sided_inverse(x)
                t = t if self.kind.startswith("grazing") else 2.0 - t
                mu = np.minimum(unblended(0.5 * t * blended(self.mu_c, a_phi), a_phi),
                                self.mu_c)
            k = _kink(mu, self.mu_c)
            if self.kind.endswith("near"):
                c = _two_sided_inverse(u) * k
            elif self.kind.endswith("far"):
                c = k + u * (1.0 - k)
        return mu, c

    def covers(self, mu, c):
        """Where a direction (mu, |cos phi| = c) of the dense side belongs to this part."""
        if self.kind == "above":
            return mu >= self.mu_c
        a_phi = self._a_phi(c)
        t = 2.0 * blended(mu, a_phi) / blended(self.mu_c, a_phi)
        here = (mu < self.mu_c) & ((t < 1.0) if self.kind.startswith("grazing") else (t >= 1.0))
        near = c <= _kink(mu, self.mu_c)
        return here & (near if self.kind.endswith("near") else ~near)


def _axis(name: str, n: int, log_scale: float) -> Axis:
    return Axis(name, 0.0, 1.0, n, "log-linear", "cubic", log_scale=log_scale)


def _part(kind: str, alpha: float, ratio: float, eta_seen: float, mu_c: float) -> _Part:
    n_x, n_u = SLICE_NODES[kind]
    # |cos phi| crowds towards the smooth axis as in "ggx_conductor_anisotropic", u of the
    # far parts towards k(mu)
    u_axis = (Axis("u", 0.0, 1.0, n_u, "linear", "cubic") if kind.endswith("near")
              else _axis("u", n_u, 0.1))
    x_axis = (_axis("x", n_x, 0.1) if kind in ("outside", "above")
              else Axis("x", 0.0, 1.0, n_x, "linear", "cubic"))
    axes = (x_axis, u_axis)
    spec = TableSpec(f"ggx_dielectric_anisotropic[{kind}, alpha={alpha:g}, ratio={ratio:g}, "
                     f"eta={eta_seen:g}]", axes, ("E_R", "E_T"), None,
                     "anisotropic_energy.ggx_anisotropic_dielectric_energy", SLICE_ORDER)
    part = _Part(kind, mu_c, alpha, ratio)
    mu, c = part.directions(*spec.grid())
    a = max(alpha, ALPHA_FLOOR)
    e = ggx_anisotropic_dielectric_energy(mu, np.arccos(np.clip(c, 0.0, 1.0)), a, ratio * a,
                                          eta_seen, SLICE_ORDER, estimate=False)
    values = np.stack([e.reflection, e.transmission], -1).reshape(spec.shape)
    table = Table(spec, values, np.full(spec.shape, SLICE_NODE_ERROR))
    return _Part(kind, mu_c, alpha, ratio, table)


def _average(part: _Part) -> np.ndarray:
    """(1 / pi) int E cos dw over the directions of ``part``, ``(2,)``: Gauss–Legendre on
    every cell of its interpolant in (x, w = arccos u), the Jacobian of (x, w) -> (mu, phi)
    by central differences (both smooth within a part)."""
    x_axis, u_axis = part.table.spec.axes
    g, w = roots_legendre(_AVERAGE_ORDER)
    g, w = 0.5 * (g + 1.0), 0.5 * w
    x_edges = x_axis.nodes()
    w_edges = np.arccos(u_axis.nodes())[::-1]  # increasing
    X = (x_edges[:-1, None] + np.diff(x_edges)[:, None] * g).ravel()
    W = (w_edges[:-1, None] + np.diff(w_edges)[:, None] * g).ravel()
    weight = np.outer((np.diff(x_edges)[:, None] * w).ravel(),
                      (np.diff(w_edges)[:, None] * w).ravel())
    X, W = np.meshgrid(X, W, indexing="ij")
    h = 1e-6

    def angles(x, w):
        mu, c = part.directions(np.clip(x, 0.0, 1.0), np.cos(np.clip(w, 0.0, np.pi / 2)))
        return mu, np.arccos(np.clip(c, 0.0, 1.0))

    (m1, p1), (m0, p0) = angles(X + h, W), angles(X - h, W)
    (n1, q1), (n0, q0) = angles(X, W + h), angles(X, W - h)
    jacobian = np.abs((m1 - m0) * (q1 - q0) - (p1 - p0) * (n1 - n0)) / (4.0 * h * h)
    mu, _ = angles(X, W)
    E = part.table(X, np.cos(W))
    return (4.0 / np.pi) * np.einsum("ij,ij,ij,ijk->k", weight, mu, jacobian, E)


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
        for part in self.parts:
            mask = on_light if part.kind == "outside" else ~on_light & part.covers(mu, cos_phi)
            if np.any(mask):
                coords = part.coordinates(mu[mask], cos_phi[mask])
                out[mask] = part.table.error(*coords) if error else part.table(*coords)
        return out


@functools.lru_cache(maxsize=CACHED_SLICES)
def dielectric_slice(alpha: float, ratio: float, eta: float) -> DielectricSlice:
    """The slice of the interface with alpha_max = ``alpha``, alpha_min = ``ratio`` alpha
    and index ratio ``eta`` >= 1 (dense / light)."""
    alpha, ratio, eta = float(alpha), float(ratio), float(eta)
    mu_c = float(np.sqrt(1.0 - 1.0 / (eta * eta)))
    parts = (_part("outside", alpha, ratio, eta, mu_c),
             *(_part(kind, alpha, ratio, 1.0 / eta, mu_c) for kind in SLICE_NODES
               if kind != "outside"))
    inside = sum(_average(part) for part in parts[1:])
    return DielectricSlice(alpha, ratio, eta, parts, _average(parts[0]), inside)
