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
in (mu, phi), measured in the report. ``dielectric_grid`` holds slices at grid points of
(alpha, ratio, eta) and interpolates any other across them (``layout``, ``filled`` and
``assembled`` build a slice from given node values).

Coordinates. Seen from the less dense side, one table over (s, |cos phi|), |cos phi| (from
the axis of alpha_max) log-spaced towards the smooth axis and s = 1 - sqrt(1 - v) of the
blended coordinate v (``anisotropic_energy.blended``: the grazing boundary layer and mu),
log-spaced towards grazing, its nodes also crowding towards normal incidence (where a very
rough interface's energy goes as (1 - mu)^p, p ~ 1.3). Seen from the dense side, total
internal reflection sets in at the critical cosine mu_c = sqrt(1 - 1 / eta^2), where the
energy of a smooth interface has a kink and a rough one a transition as narrow as the
roughness. A nearly one-dimensional surface (ratio -> 0), whose facets all tilt in the plane
of the rough axis and the normal, has two more kinks along curves in (mu, |cos phi|), where
facets of that plane leave total internal reflection (wo.m = mu_c):

- k1(mu) = sqrt((mu_c^2 - mu^2) / (1 - mu^2)) (0 from mu_c up): the facet facing wo's
  projection on that plane, whose length then is mu_c;
- k2(mu) = mu_c / sqrt(1 - mu^2), up to mu = 1 / eta where it reaches |cos phi| = 1: the
  vertical facets, wo's component along the rough axis then being mu_c.

The dense side is therefore tiled by tables (``_Part``): in mu, the segments of
``_segments`` (the grazing boundary layer, the rest below min(mu_c, 1 / eta), then split at
mu_c and 1 / eta); in |cos phi|, the bands [0, k1], [k1, k2] and [k2, 1] ("near", "mid",
"far") that a segment has. Nodes crowd geometrically towards grazing, mu_c, the smooth axis
and both kinks (``_two_sided``), so that no interpolation stencil straddles a kink: eight
tables at eta = 1.5.

Refined layouts (``layout(..., refined=True)``, the slices computed on demand; the grid keeps
the layout it was baked in). A nearly one-dimensional surface (ratio -> 0) has, near the
smooth axis, a projected roughness far below its energy's own scale: its energy there still
varies with mu (by ~0.1 between mu 0 and 0.1 at alpha 1), but the blended coordinate of so
thin a boundary layer leaves two cells for that range, and across the smooth axis it turns
within |cos phi| ~ mu / alpha. Refined layouts floor the boundary layer's roughness smoothly
at ``_BLEND_FLOOR`` alpha (hypot), crowd the dense side's "near" bands towards the smooth
axis (``_REFINED_AXIS_EDGE``) and their mu nodes towards 1 / eta (where a very rough,
nearly index-matched interface's energy peaks), and carry more nodes (``REFINED_NODES``):
the largest error of E_R + E_T over mu >= 1e-3 drops from 2.3e-2 to 1.5e-3 at the nearly
one-dimensional and nearly index-matched interfaces that ``benchmarks.anisotropic_grid``
probes (twice the nodes, twice the time).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, replace

import numpy as np
from scipy.special import roots_legendre

from adobe_bsdf.fresnel import _dielectric
from adobe_bsdf.tables.anisotropic_energy import (
    ALPHA_FLOOR,
    blended,
    ggx_anisotropic_dielectric_energy,
    projected_alpha,
    unblended,
)
from adobe_bsdf.tables.table import Axis, Table, TableSpec, horner

__all__ = ["DielectricSlice", "dielectric_slice", "SLICE_ORDER", "SLICE_NODES",
           "SLICE_NODE_ERROR", "layout", "node_directions", "node_energy", "filled",
           "assembled", "fresnel_share", "light_share", "FRESNEL_SHARE_ROUGHNESS"]

#: Gauss–Legendre order of the slice's nodes
SLICE_ORDER = 8
#: the node integrator's error at ``SLICE_ORDER``: the largest difference to order 20 over
#: random nodes (mu >= 0.005, alpha in [0.003, 1.5], ratio, eta in [1/3, 3]), measured by
#: ``benchmarks.tables_report`` and carried as every node's error estimate
SLICE_NODE_ERROR = 2e-4
#: nodes (mu, |cos phi|) of the light side's table and, on the dense side, nodes in mu of the
#: grazing segment and of the others (``_segments``) and in |cos phi| of each band there
SLICE_NODES = {"outside": (32, 16),
               "grazing": {"mu": 12, "near": 14, "mid": 10, "far": 12},
               "segment": {"mu": 10, "near": 12, "mid": 10, "far": 10}}
#: the same of refined layouts (``layout``)
REFINED_NODES = {"outside": (64, 24),
                 "grazing": {"mu": 14, "near": 20, "mid": 14, "far": 12},
                 "segment": {"mu": 12, "near": 16, "mid": 16, "far": 12}}
#: slices kept in memory (each ~40 KB)
CACHED_SLICES = 256
#: Gauss points per cell and dimension of the averages
_AVERAGE_ORDER = 8
#: fixed-point steps from a part's coordinates to (mu, phi) (contracting: mu depends on phi
#: only through the projected roughness of the blended coordinate)
_STEPS = 60


#: relative node spacings of ``_two_sided`` at an end (t = 0 or 1): grazing, the critical
#: cosine and the smooth axis (structure on the scale of the roughness), a kink of a band, and
#: an end of nothing in particular
_GRAZING_EDGE, _CRITICAL_EDGE, _AXIS_EDGE, _KINK_EDGE, _PLAIN_EDGE = 0.01, 0.005, 0.003, 0.02, 0.2
_EDGES = (_KINK_EDGE, _KINK_EDGE)
#: refined layouts: the smooth axis's spacing and the least boundary-layer roughness, over
#: alpha (a nearly one-dimensional surface's energy turns at |cos phi| ~ mu / alpha, and
#: above a boundary layer thinner than that it still varies with mu)
_REFINED_AXIS_EDGE, _BLEND_FLOOR = 1e-4, 3e-4
#: the projected roughness at which the Fresnel share that the light side's tables hold E_R
#: and E_T less and more (``fresnel_share``) is weighted 1/2: chosen from 0.05, 0.1, 0.2 and
#: infinity as the least error over the grid's layout at alpha 0.005 to 1, ratio 0.03 to 0.7,
#: eta 1.05, 1.5 and 3 (nearly one-dimensional rough interfaces want it large, nearly
#: isotropic rough ones small)
FRESNEL_SHARE_ROUGHNESS = 0.2
#: log scale of the light side's axis in s = 1 - sqrt(1 - v) (``Axis``: the larger, the more
#: nodes towards grazing)
_OUTSIDE_LOG_SCALE = 0.03


def _two_sided(t, edges=_EDGES):
    """u in [0, 1] of t in [0, 1] whose uniform nodes crowd geometrically towards both ends
    of t: u = (ln((t + e0) / (1 - t + e1)) - y0) / (y1 - y0), y0, y1 its values at 0 and 1."""
    e0, e1 = edges
    y0, y1 = np.log(e0 / (1.0 + e1)), np.log((1.0 + e0) / e1)
    return (np.log((t + e0) / (1.0 - t + e1)) - y0) / (y1 - y0)


def _two_sided_inverse(u, edges=_EDGES):
    """t of ``_two_sided``."""
    e0, e1 = edges
    y0, y1 = np.log(e0 / (1.0 + e1)), np.log((1.0 + e0) / e1)
    q = np.exp(y0 + (y1 - y0) * np.asarray(u, dtype=np.float64))
    return np.clip((q * (1.0 + e1) - e0) / (1.0 + q), 0.0, 1.0)


def _kinks(mu, mu_c):
    """(k1, k2) of the dense side at cosine ``mu``: k1 = sqrt((mu_c^2 - mu^2) / (1 - mu^2)),
    0 from mu_c up; k2 = min(mu_c / sqrt(1 - mu^2), 1)."""
    sin2 = np.maximum(1.0 - mu * mu, 1e-300)
    k1 = np.sqrt(np.maximum(mu_c * mu_c - mu * mu, 0.0) / sin2)
    return k1, np.maximum(np.minimum(mu_c / np.sqrt(sin2), 1.0), k1)


def _segments(mu_c: float) -> list[tuple[str, float, float]]:
    """The dense side's ranges of mu, (kind, lo, hi): split at mu_c (total internal
    reflection) and at mu_s = sqrt(1 - mu_c^2) = 1 / eta (where k2 reaches |cos phi| = 1, so
    that the band "far" ends). Below m = min(mu_c, mu_s) the split is at the middle of the
    blended coordinate v (``blended``), whose lower half is the grazing boundary layer."""
    mu_s = float(np.sqrt(1.0 - mu_c * mu_c))
    cuts = sorted({mu_c, mu_s, 1.0} - {0.0})
    m = cuts[0]
    return [("grazing", 0.0, m), ("lower", 0.0, m),
            *(("plain", lo, hi) for lo, hi in zip(cuts[:-1], cuts[1:], strict=True))]


@dataclass(frozen=True)
class _Part:
    """One table of a slice over (x, u), both in [0, 1].

    "outside" (the light side): x = 1 - sqrt(1 - v) (v: ``blended``), u = |cos phi|.
    Dense side: mu in a segment (``_segments``) mapped to [0, 1], by t = 2 v / v(hi) on
    "grazing", 2 - 2 v / v(hi) on "lower" and (mu - lo) / (hi - lo) on "plain", then
    x = ``_two_sided``(t); |cos phi| in the band ("near": [0, k1], "mid": [k1, k2], "far":
    [k2, 1], ``_kinks``) mapped to [0, 1], then u = ``_two_sided`` of it.
    """

    segment: str
    band: str
    mu_c: float
    alpha: float
    ratio: float
    lo: float = 0.0
    hi: float = 1.0
    table: Table | None = None
    refined: bool = False

    def _a_phi(self, c):
        """The roughness that sets the grazing boundary layer of ``blended``: the projected
        roughness, in refined layouts smoothly floored: hypot(a, ``_BLEND_FLOOR`` alpha)."""
        a = projected_alpha(c, max(self.alpha, ALPHA_FLOOR), self.ratio)
        return np.hypot(a, _BLEND_FLOOR * self.alpha) if self.refined else a

    @property
    def _x_edges(self):
        """``_two_sided``'s end spacings in t: crowded towards grazing and mu_c (refined
        layouts also towards 1 / eta, where a very rough interface's energy peaks)."""
        def edge(mu):
            if mu == self.mu_c:
                return _CRITICAL_EDGE
            kink = self.refined and mu == np.sqrt(1.0 - self.mu_c**2)
            return _KINK_EDGE if kink else _PLAIN_EDGE
        return {"grazing": (_GRAZING_EDGE, _GRAZING_EDGE),
                "lower": (edge(self.hi), _GRAZING_EDGE)}.get(
                    self.segment, (edge(self.lo), edge(self.hi)))

    @property
    def _u_edges(self):
        """The same in |cos phi|: crowded towards the smooth axis and the kinks (k2 of the
        band "mid" is no kink where it is 1)."""
        if self.band == "near":
            return (_REFINED_AXIS_EDGE if self.refined else _AXIS_EDGE), _KINK_EDGE
        if self.band == "far":
            return _KINK_EDGE, _PLAIN_EDGE
        return _KINK_EDGE, (_KINK_EDGE if self.hi <= np.sqrt(1.0 - self.mu_c**2)
                            else _PLAIN_EDGE)

    def _t(self, mu, c):
        """The segment's coordinate t in [0, 1] (unclipped)."""
        if self.segment == "plain":
            return (mu - self.lo) / (self.hi - self.lo)
        a_phi = self._a_phi(c)
        t = 2.0 * blended(mu, a_phi) / blended(self.hi, a_phi)
        return t if self.segment == "grazing" else 2.0 - t

    def _x(self, mu, c):
        if self.segment == "outside":
            return 1.0 - np.sqrt(1.0 - np.minimum(blended(mu, self._a_phi(c)), 1.0))
        return _two_sided(np.clip(self._t(mu, c), 0.0, 1.0), self._x_edges)

    def _mu(self, x, c):
        if self.segment == "outside":
            return unblended(1.0 - (1.0 - x) ** 2, self._a_phi(c))
        t = _two_sided_inverse(x, self._x_edges)
        if self.segment == "plain":
            return self.lo + t * (self.hi - self.lo)
        a_phi = self._a_phi(c)
        t = t if self.segment == "grazing" else 2.0 - t
        return np.minimum(unblended(0.5 * t * blended(self.hi, a_phi), a_phi), self.hi)

    def _band(self, mu):
        k1, k2 = _kinks(mu, self.mu_c)
        return {"near": (0.0 * k1, k1), "mid": (k1, k2), "far": (k2, 1.0 + 0.0 * k2)}[self.band]

    def coordinates(self, mu, c):
        """(x, u) of directions (mu, |cos phi| = c) of this part."""
        x = self._x(mu, c)
        if self.segment == "outside":
            return x, c
        lo, hi = self._band(mu)
        width = hi - lo
        t = np.clip(np.divide(c - lo, width, out=np.zeros_like(width), where=width > 0.0),
                    0.0, 1.0)
        return x, _two_sided(t, self._u_edges)

    def directions(self, x, u):
        """(mu, |cos phi|) of the coordinates (x, u), by fixed-point steps where they depend
        on each other (mu on phi only through the projected roughness of ``blended``)."""
        c = np.asarray(u, dtype=np.float64)
        if self.segment == "outside":
            return self._mu(x, c), c
        x, c = np.broadcast_arrays(np.asarray(x, dtype=np.float64), c)
        shape, x, c = c.shape, x.ravel(), c.ravel().copy()
        t = _two_sided_inverse(c, self._u_edges)
        mu = np.empty_like(c)
        active = np.arange(c.size)
        for _ in range(1 if self.segment == "plain" else _STEPS):
            m = self._mu(x[active], c[active])
            lo, hi = self._band(m)
            step = lo + t[active] * (hi - lo)
            mu[active] = m
            moved = step != c[active]  # where a fixed point is reached, every step repeats it
            c[active] = step
            active = active[moved]
            if not active.size:
                break
        return mu.reshape(shape), c.reshape(shape)

    def covers(self, mu, c):
        """Where a direction (mu, |cos phi| = c) of the dense side belongs to this part: mu
        in its segment (the last one closed) and c < k1 ("near"), c > k2 ("far") or between."""
        here = (mu >= self.lo) & ((mu < self.hi) | (self.hi == 1.0))
        if self.segment != "plain":
            a_phi = self._a_phi(c)
            grazing = 2.0 * blended(mu, a_phi) < blended(self.hi, a_phi)
            here &= grazing == (self.segment == "grazing")
        k1, k2 = _kinks(mu, self.mu_c)
        inside = {"near": c < k1, "mid": (c >= k1) & (c <= k2), "far": c > k2}[self.band]
        return here & inside


def _axis(name: str, n: int, log_scale: float) -> Axis:
    return Axis(name, 0.0, 1.0, n, "log-linear", "cubic", log_scale=log_scale)


def _part(segment: str, band: str, alpha: float, ratio: float, eta_seen: float,
          mu_c: float, lo: float = 0.0, hi: float = 1.0, refined: bool = False) -> _Part:
    """The part's layout: its table's declaration, the values not yet computed (zeros)."""
    part = _Part(segment, band, mu_c, alpha, ratio, lo, hi, refined=refined)
    counts = REFINED_NODES if refined else SLICE_NODES
    if segment == "outside":
        n_x, n_u = counts["outside"]
    else:
        nodes = counts["grazing" if segment == "grazing" else "segment"]
        n_x, n_u = nodes["mu"], nodes[band]
    # |cos phi| of the light side crowds towards the smooth axis
    u_axis = (_axis("u", n_u, 0.1) if segment == "outside"
              else Axis("u", 0.0, 1.0, n_u, "linear", "cubic"))
    x_axis = (_axis("x", n_x, _OUTSIDE_LOG_SCALE) if segment == "outside"
              else Axis("x", 0.0, 1.0, n_x, "linear", "cubic"))
    spec = TableSpec(f"ggx_dielectric_anisotropic[{segment} mu in [{lo:.4g}, {hi:.4g}], "
                     f"{band}, alpha={alpha:g}, ratio={ratio:g}, eta={eta_seen:g}]",
                     (x_axis, u_axis), ("E_R", "E_T"), None,
                     "anisotropic_energy.ggx_anisotropic_dielectric_energy", SLICE_ORDER)
    zeros = np.zeros(spec.shape)
    return replace(part, table=Table(spec, zeros, zeros))


def layout(alpha: float, ratio: float, eta: float, refined: bool = False) -> tuple:
    """The parts of the slice of (``alpha``, ``ratio``, index ratio ``eta`` >= 1), their
    tables declared and not computed: the light side's, then the dense side's (``_segments``
    and their bands). ``refined``: the computed slices' layout, with more nodes towards the
    smooth axis and above the boundary layer (``REFINED_NODES``); the grid's slices are not
    refined."""
    alpha, ratio, eta = float(alpha), float(ratio), float(eta)
    mu_c = float(np.sqrt(1.0 - 1.0 / (eta * eta)))
    parts = [_part("outside", "outside", alpha, ratio, eta, mu_c, refined=refined)]
    for segment, lo, hi in _segments(mu_c):
        bands = ["near"] if hi <= mu_c else []
        bands += ["mid"] + (["far"] if hi <= np.sqrt(1.0 - mu_c * mu_c) else [])
        parts += [_part(segment, band, alpha, ratio, 1.0 / eta, mu_c, lo, hi, refined)
                  for band in bands]
    return tuple(parts)


def node_directions(parts) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(mu, cos_phi, on_light)``, each ``(n_nodes,)``: the directions of every node of
    ``parts`` (a ``layout``), part after part, each part's nodes in its table's order."""
    mu, c, light = [], [], []
    for part in parts:
        m, k = part.directions(*part.table.spec.grid())
        mu.append(m.ravel())
        c.append(k.ravel())
        light.append(np.full(m.size, part.segment == "outside"))
    return np.concatenate(mu), np.concatenate(c), np.concatenate(light)


def node_energy(alpha: float, ratio: float, eta: float, mu, cos_phi, on_light,
                order: int = SLICE_ORDER) -> np.ndarray:
    """``(n, 2)`` (E_R, E_T) of the interface at the directions given (``node_directions``),
    by the stretched node quadrature."""
    a = max(float(alpha), ALPHA_FLOOR)
    eta_seen = np.where(on_light, float(eta), 1.0 / float(eta))
    e = ggx_anisotropic_dielectric_energy(mu, np.arccos(np.clip(cos_phi, 0.0, 1.0)), a,
                                          float(ratio) * a, eta_seen, order, estimate=False)
    return np.stack([e.reflection, e.transmission], -1)


def filled(parts, values: np.ndarray, error: float = SLICE_NODE_ERROR) -> tuple:
    """``parts`` with their tables holding ``values`` ``(n_nodes, 2)`` (``node_directions``'
    order) and node error ``error``."""
    out, start = [], 0
    for part in parts:
        spec = part.table.spec
        n = int(np.prod(spec.shape[:-1]))
        v = np.asarray(values[start:start + n], dtype=np.float64).reshape(spec.shape)
        out.append(replace(part, table=Table(spec, v, np.full(spec.shape, error))))
        start += n
    return tuple(out)


def fresnel_share(alpha: float, ratio: float, eta: float, mu, cos_phi) -> np.ndarray:
    """g = F(mu) / (1 + (alpha_phi / ``FRESNEL_SHARE_ROUGHNESS``)^2): the reflectance of the
    smooth interface of index ratio ``eta`` seen from the light side, weighted down where the
    projected roughness alpha_phi (``projected_alpha``) smooths it. Of a nearly smooth
    interface E_R follows F above the boundary layer, and F falls from 1 at grazing faster
    than the light side's nodes there resolve (by several times 1e-2); E_R - g and E_T + g
    (E_T ~ 1 - F) vary only on the boundary layer's scale, which they resolve. Of a rough one
    E_R is smoother than F, and subtracting F would add its fall back (``benchmarks.
    anisotropic_grid``, "The light side's Fresnel share")."""
    c2 = np.square(cos_phi)  # alpha_phi^2 as ``projected_alpha`` has it, without its root
    a2 = np.maximum(np.square(max(float(alpha), ALPHA_FLOOR)) * (
        c2 + float(ratio) ** 2 * (1.0 - c2)), ALPHA_FLOOR ** 2)
    a0 = FRESNEL_SHARE_ROUGHNESS ** 2
    return _dielectric(np.asarray(mu, dtype=np.float64), float(eta)) * (a0 / (a0 + a2))


@functools.lru_cache(maxsize=1024)
def _light_nodes(alpha: float, ratio: float, refined: bool) -> tuple[np.ndarray, np.ndarray]:
    """(mu, |cos phi|) of the light side's nodes (they do not depend on eta), in C order."""
    part = _part("outside", "outside", alpha, ratio, 1.5, 0.0, refined=refined)
    mu, c = part.directions(*part.table.spec.grid())
    return mu.ravel(), np.broadcast_to(c, mu.shape).ravel()


def light_share(alpha: float, ratio: float, eta: float, refined: bool) -> np.ndarray:
    """``(n, 2)``: (g, -g), g the ``fresnel_share`` at the light side's nodes of the
    ``layout``, to add to its node values (E_R, E_T) (and subtract for what the slice
    interpolates)."""
    mu, c = _light_nodes(float(alpha), float(ratio), bool(refined))
    return fresnel_share(alpha, ratio, eta, mu, c)[:, None] * np.array([1.0, -1.0])


def _shifted(part: _Part, alpha: float, ratio: float, eta: float) -> _Part:
    """The light side's ``part`` with its tables holding (E_R - g, E_T + g), g the
    ``fresnel_share`` at its nodes: what the slice interpolates."""
    spec = part.table.spec
    values = part.table.values - light_share(alpha, ratio, eta, part.refined).reshape(
        spec.shape)
    return replace(part, table=Table(spec, values, part.table.errors))


def _computed(part: _Part, eta: float) -> _Part:
    """``part`` (of index ratio ``eta``) with its table's nodes computed."""
    spec = part.table.spec
    mu, c = part.directions(*spec.grid())
    values = node_energy(part.alpha, part.ratio, eta, mu, c, part.segment == "outside")
    return filled((part,), values.reshape(-1, 2))[0]


def _average(part: _Part, share=None) -> np.ndarray:
    """(1 / pi) int E cos dw over the directions of ``part``, ``(2,)``: Gauss–Legendre on
    every cell of its interpolant in (x, w = arccos u) (plus (g, -g), g = ``share(mu,
    |cos phi|)``), the Jacobian of (x, w) -> (mu, phi) by central differences (all smooth
    within a part)."""
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
    if share is not None:
        E = E + share(mu, np.cos(W))[..., None] * np.array([1.0, -1.0])
    return (4.0 / np.pi) * np.einsum("ij,ij,ij,ijk->k", weight, mu, jacobian, E)


@dataclass(frozen=True)
class DielectricSlice:
    """E_R, E_T of the anisotropic interface (alpha_max ``alpha``, alpha_min ``ratio``
    alpha, index ratio ``eta`` >= 1) seen from either side, and their averages. The light
    side's part holds (E_R - g, E_T + g), g = ``fresnel_share`` (``assembled``), which the
    lookups add back."""

    alpha: float
    ratio: float
    eta: float
    parts: tuple
    average_outside: np.ndarray
    average_inside: np.ndarray

    def __call__(self, on_light, mu, cos_phi) -> np.ndarray:
        """``(..., 2)`` (E_R, E_T) at cosine ``mu`` and |cos phi| ``cos_phi`` (broadcast),
        seen from the light side where ``on_light``."""
        E = self._lookup(on_light, mu, cos_phi, False)
        return E + self._share(on_light, mu, cos_phi)[..., None] * np.array([1.0, -1.0])

    def error(self, on_light, mu, cos_phi) -> np.ndarray:
        """The node error carried to the same points (``Table.error``)."""
        return self._lookup(on_light, mu, cos_phi, True)

    def channel(self, name: str, on_light, mu, cos_phi) -> np.ndarray:
        """``(...)``: E_R + E_T (``name`` "total") or E_R ("reflection") at the same points:
        the interpolant of the sum or of E_R (``__call__``'s, to rounding: it is linear in
        the values), evaluated as one polynomial per cell (``Table._polynomial``) whose
        coefficients, for every part's cells, sit in one array (``_cells``), so that the
        points of all parts are evaluated together, bit for bit as part by part."""
        shape = np.broadcast_shapes(*(np.shape(a) for a in (on_light, mu, cos_phi)))
        on_light, mu, cos_phi = (np.ravel(a) for a in np.broadcast_arrays(on_light, mu,
                                                                          cos_phi))
        offsets, coefficients = self._cells[name]

        def located(part, offset, mu, cos_phi):
            x_axis, u_axis = part.table.spec.axes
            x, u = part.coordinates(mu, cos_phi)
            # (x, u) in [0, 1] by construction (``_Part.coordinates``)
            (i, t_x), (j, t_u) = (x_axis.locate(x, checked=False),
                                  u_axis.locate(u, checked=False))
            return offset + i * (u_axis.n - 1) + j, t_x, t_u

        if on_light.all():  # the light side's one part: no part to find
            cell, t_x, t_u = located(self.parts[0], offsets[0], mu, cos_phi)
        else:
            which = self._which(on_light, mu, cos_phi)
            cell = np.full(mu.shape, offsets[-1])  # the last cell is 0: points of no part
            t_x, t_u = np.zeros(mu.shape), np.zeros(mu.shape)
            for k, part in enumerate(self.parts):
                here = np.flatnonzero(which == k)
                if here.size:
                    cell[here], t_x[here], t_u[here] = located(part, offsets[k], mu[here],
                                                               cos_phi[here])
        value = horner(lambda p: horner(lambda q: np.take(coefficients[p, q], cell), t_u),
                       t_x)
        if name == "reflection":
            value = value + self._share(on_light, mu, cos_phi)
        return value.reshape(shape)

    def _share(self, on_light, mu, cos_phi) -> np.ndarray:
        """``fresnel_share`` where ``on_light``, 0 elsewhere (broadcast)."""
        on_light, mu, cos_phi = np.broadcast_arrays(on_light, mu, cos_phi)
        if on_light.all():
            return fresnel_share(self.alpha, self.ratio, self.eta, mu, cos_phi)
        g = np.zeros(mu.shape)
        g[on_light] = fresnel_share(self.alpha, self.ratio, self.eta, mu[on_light],
                                    cos_phi[on_light])
        return g

    @functools.cached_property
    def _cells(self) -> dict:
        """``{"total" | "reflection": (offsets, coefficients (4, 4, n_cells + 1))}``: the
        cell polynomials of every part's one-output table (``Table._cells``), part ``k``'s
        from ``offsets[k]``, and a last cell of zeros."""
        def single(part, values):
            spec = replace(part.table.spec, outputs=("E",))
            table = Table(spec, values[..., None], np.zeros(values.shape + (1,)))
            strides, c = table._cells()
            assert strides == (part.table.spec.axes[1].n - 1, 1)
            return c
        out = {}
        for name, values in (("total", lambda p: p.table.values.sum(-1)),
                             ("reflection", lambda p: p.table.values[..., 0])):
            cells = [single(p, values(p)) for p in self.parts]
            offsets = np.cumsum([0] + [c.shape[-1] for c in cells])
            out[name] = (offsets, np.concatenate([*cells, np.zeros((4, 4, 1))], -1))
        return out

    @property
    def n_nodes(self) -> int:
        """Nodes of all its tables."""
        return sum(int(np.prod(part.table.spec.shape[:-1])) for part in self.parts)

    def layout(self) -> list[str]:
        """Each table as "segment [lo, hi] band: n_mu x n_phi"."""
        return [f"{p.segment}" + ("" if p.segment == "outside" else
                                  f" mu in [{p.lo:.3g}, {p.hi:.3g}] {p.band}")
                + " {} x {}".format(*p.table.spec.shape[:-1]) for p in self.parts]

    def average(self, on_light) -> np.ndarray:
        """``(..., 2)`` averages of the side ``on_light``."""
        return np.where(np.asarray(on_light)[..., None], self.average_outside,
                        self.average_inside)

    def _lookup(self, on_light, mu, cos_phi, error, tables=None):
        """(..., n_outputs) of the parts' tables (or of ``tables``, one per part)."""
        tables = tables or tuple(part.table for part in self.parts)
        shape = np.broadcast_shapes(*(np.shape(a) for a in (on_light, mu, cos_phi)))
        on_light, mu, cos_phi = (np.ravel(a) for a in np.broadcast_arrays(on_light, mu,
                                                                          cos_phi))
        n_outputs = tables[0].values.shape[-1]
        out = np.zeros(mu.shape + (n_outputs,))
        which = self._which(on_light, mu, cos_phi)
        for k, (part, table) in enumerate(zip(self.parts, tables, strict=True)):
            here = np.flatnonzero(which == k)
            if here.size:
                coords = part.coordinates(mu[here], cos_phi[here])
                out[here] = table.error(*coords) if error else table(*coords)
        return out.reshape(shape + (n_outputs,))

    def _which(self, on_light, mu, cos_phi) -> np.ndarray:
        """The index in ``parts`` of the part that holds each direction, -1 for none."""
        which = np.full(mu.shape, -1)
        which[on_light] = 0
        dense = np.flatnonzero(~on_light)
        if dense.size:
            which[dense] = self._dense_part(mu[dense], cos_phi[dense])
        return which

    def _dense_part(self, mu, c) -> np.ndarray:
        """The index in ``parts`` of the dense side's part that holds each direction (the
        one whose ``_Part.covers`` is true), -1 where none does."""
        index = {(p.segment, p.lo, p.band): k for k, p in enumerate(self.parts)}
        segments = [(p.segment, p.lo, p.hi) for p in self.parts[1:]]
        which = np.full(mu.shape, -1)
        k1, k2 = _kinks(mu, self.parts[1].mu_c)
        band = np.where(c < k1, 0, np.where(c > k2, 2, 1))
        names = ("near", "mid", "far")
        a_phi = None
        for segment, lo, hi in dict.fromkeys(segments):
            here = (mu >= lo) & ((mu < hi) | (hi == 1.0))
            if segment != "plain":
                if a_phi is None:
                    a_phi = self.parts[1]._a_phi(c)
                grazing = 2.0 * blended(mu, a_phi) < blended(hi, a_phi)
                here &= grazing == (segment == "grazing")
            # a band the segment lacks (k2 = 1 from mu = 1 / eta up, where "far" ends) is
            # reached only through rounding at its edge: the nearest band it has holds it
            present = [b for b, name in enumerate(names) if (segment, lo, name) in index]
            for b in range(len(names)):
                nearest = min(present, key=lambda q: (abs(q - b), q))
                which[here & (band == b)] = index[(segment, lo, names[nearest])]
        return which


def assembled(alpha: float, ratio: float, eta: float, parts,
              residual: bool = False) -> DielectricSlice:
    """The ``DielectricSlice`` of filled ``parts`` (the light side's ``_shifted``, unless
    ``residual``: it holds E - (g, -g) already), with their averages (``_average``)."""
    alpha, ratio, eta = float(alpha), float(ratio), float(eta)
    outside = parts[0] if residual else _shifted(parts[0], alpha, ratio, eta)
    inside = sum(_average(part) for part in parts[1:])
    return DielectricSlice(alpha, ratio, eta, (outside, *parts[1:]),
                           _average(outside, functools.partial(fresnel_share, alpha, ratio,
                                                               eta)), inside)


@functools.lru_cache(maxsize=CACHED_SLICES)
def dielectric_slice(alpha: float, ratio: float, eta: float,
                     refined: bool = True) -> DielectricSlice:
    """The slice of the interface with alpha_max = ``alpha``, alpha_min = ``ratio`` alpha
    and index ratio ``eta`` >= 1 (dense / light), in the refined ``layout`` (unless
    ``refined`` is False: the grid's)."""
    return assembled(alpha, ratio, eta, tuple(_computed(part, float(eta))
                                              for part in layout(alpha, ratio, eta, refined)))
