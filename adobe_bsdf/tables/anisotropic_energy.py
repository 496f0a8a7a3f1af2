"""Directional energy of an anisotropic GGX conductor (F = 1), by piecewise Gauss–Legendre
quadrature in the stretched configuration.

Public API
----------
``ggx_anisotropic_energy(mu, phi, alpha_x, alpha_y, order=16)``
    E(wo) = int D_wo(m) G2(wo, wi) / G1(wo) dm of the GGX conductor with F = 1 seen from
    wo = (sin theta_o cos phi, sin theta_o sin phi, mu), and an error estimate per value.
``ggx_anisotropic_moments(mu, phi, alpha_x, alpha_y, degree, order=16)``
    Its Fresnel moments M_k (the same integral weighted by P_k(2 wo.m - 1)).
``fresnel_coefficients(eta, degree)``
    The Legendre coefficients a_k of a dielectric Fresnel: it reflects sum_k a_k M_k.
``ggx_anisotropic_dielectric_energy(mu, phi, alpha_x, alpha_y, eta, order=16)``
    E_R and E_T of an anisotropic GGX dielectric interface (exact Fresnel) seen from wo with
    relative index ``eta`` beyond it (< 1: from the dense side), and error estimates.

GGX with roughness (alpha_x, alpha_y) is the alpha = 1 microsurface stretched
[Heitz2014, §5.3]: a normal m' of the alpha = 1 surface is the normal m ~ (alpha_x m'_x,
alpha_y m'_y, m'_z) of the rough one, and wo is seen as wo' = (alpha_x wo_x, alpha_y wo_y,
mu) / S_o with S_o = |(alpha_x wo_x, alpha_y wo_y, mu)|; the visible-normal densities agree,
D_wo(m) dm = D'_wo'(m') dm' [Heitz2018, §3], and G1(wo) = G1'(wo'). The alpha = 1 GGX has
D' = 1 / pi, so with m' = (sin t cos psi, sin t sin psi, cos t)

    E = (1 / pi) int_0^{pi/2} sin t dt int_0^{2 pi} (wo'.m')^+ g dpsi,
    g = G2(wo, wi) / wo'_z = 2 mu_i S_o / (mu_i S_o + mu S_i)   for mu_i > 0, else 0,

wi the mirror direction of wo about m, mu_i its cosine and S_i = |(alpha_x wi_x, alpha_y
wi_y, mu_i)| (height-correlated Smith [Heitz2014, eq. 99]; finite at mu = 0). The alpha = 1
density has no peak at any roughness, and alpha_y = 0 (the one-dimensional limit) is
regular: the stretch moves every difficulty into where the integrand stops being smooth.

The dielectric interface weighs the mirror direction by F(wo.m) and adds the refracted
direction wt = -wo / eta + (c / eta - cos_t) m (c = wo.m) with 1 - F and g(wt) [Walter2007,
eq. 40]: its pieces add the refracted direction's horizon and boundary layer (-wt_z = (k - 1)
mu) and, seen from the dense side, the critical angle c = sqrt(1 - eta^2).

Pieces (``docs/tables.md``): at fixed t the integrand is analytic in psi except where
wo'.m' = 0 or mu_i = (k - 1) mu for k in ``LAYER`` (the horizon of wi and its boundary layer
at grazing wo, as in ``energy.ggx_energy``). Each is a trigonometric polynomial of degree
<= 2 in psi, so it has at most four roots: they are bracketed on a grid and bisected, and the
psi integral is split there. In t the number of roots changes at tangencies, located by
bisection on the root count; the t integral is split there and on ``T_PANELS`` uniform
panels. Every piece gets Gauss–Legendre nodes after the sigmoidal change of variable of
``energy._rule``. The error estimate is the difference to the same rule at two thirds of the
order.

Cost: only the brackets found are bisected, each on its own condition; the roots of several
chunks of nodes and of both orders are found at once (``ROOT_CHUNKS``), and the integrand is
evaluated on the pieces of nonzero width only (the others pad the knots to one count).
"""

from __future__ import annotations

import functools

import numpy as np

from adobe_bsdf.fresnel import _dielectric
from adobe_bsdf.tables.energy import Energy, _rule

__all__ = ["ggx_anisotropic_energy", "ggx_anisotropic_moments",
           "ggx_anisotropic_dielectric_energy", "projected_alpha", "similarity",
           "cosine", "blended", "unblended", "fresnel_coefficients", "ALPHA_FLOOR"]

#: smallest projected roughness of the similarity coordinate (alpha_x = 0 rows and the
#: smooth axis of a one-dimensional rough surface hold the limit alpha -> 0)
ALPHA_FLOOR = 1e-7

#: mu_i = (k - 1) mu_o knots: the horizon (k = 1) and the graded boundary layer above it
LAYER = (1.0, 3.0, 21.0)
#: uniform panels in t = theta' on [0, pi / 2] (the tangencies are added to them)
T_PANELS = 8
#: uniform panels in psi on [0, 2 pi] (the roots are added to them)
PSI_PANELS = 8
#: grid bracketing the roots in psi, and the t grid bracketing changes of their number
PSI_GRID = 129
T_GRID = 65
#: bisection steps (then one secant step in psi; t to ~2e-8 rad)
STEPS_PSI, STEPS_T = 24, 20
#: nodes whose knots are padded to one count and whose integrals are summed at once
CHUNK = 2
#: the same for the dielectric
DIELECTRIC_CHUNK = 4
#: chunks whose roots are found at once (larger, fewer array operations), on at most
#: ROOT_ROWS t nodes at a time (memory ~ ROOT_ROWS x 20 kB)
ROOT_CHUNKS, ROOT_ROWS = 4, 2048


def projected_alpha(cos_phi, alpha, ratio):
    """Roughness seen along the azimuth of wo, sqrt(alpha_x^2 cos^2 phi + alpha_y^2 sin^2 phi)
    with alpha_x = ``alpha``, alpha_y = ``ratio`` alpha and ``cos_phi`` = |cos phi|, at
    least ``ALPHA_FLOOR``: the alpha of G1(wo) [Heitz2014, eq. 86]."""
    c2 = cos_phi * cos_phi
    return np.maximum(alpha * np.sqrt(c2 + ratio * ratio * (1.0 - c2)), ALPHA_FLOOR)


def similarity(mu, alpha_phi):
    """s = mu (1 + a) / (mu + a) in [0, 1], a the projected roughness: at small a the energy
    near grazing is a function of mu / a, so a table in s needs no nodes at mu ~ a."""
    return mu * (1.0 + alpha_phi) / (mu + alpha_phi)


def cosine(s, alpha_phi):
    """mu of the similarity coordinate ``s`` (the inverse of ``similarity``)."""
    return np.minimum(s * alpha_phi / (1.0 + alpha_phi - s), 1.0)


def blended(mu, alpha_phi):
    """v = (s + mu) / 2 in [0, 1]: the similarity coordinate near grazing (v ~ mu / 2a) and
    mu itself above it (v ~ (1 + mu) / 2), for energies that vary with mu everywhere (the
    Fresnel moments), where s alone crowds mu >> a into s ~ 1."""
    return 0.5 * (similarity(mu, alpha_phi) + mu)


def unblended(v, alpha_phi):
    """mu of the blended coordinate ``v``: the positive root of
    mu^2 + (1 + 2a - 2v) mu - 2 v a = 0, in its cancellation-free form."""
    b = 1.0 + 2.0 * alpha_phi - 2.0 * v
    return np.minimum(4.0 * v * alpha_phi / (b + np.sqrt(b * b + 8.0 * v * alpha_phi)), 1.0)


class _Node:
    """The fixed quantities of a batch of nodes and the root-finding grids used for them.
    Quantities at m'(t, psi) take the node parameters ``q`` (``_params``: shaped to broadcast
    against (n, ...); ``_at``: one row per entry) and m = (sin t, cos t, cos psi, sin psi),
    computed once for all the quantities at the same points."""

    psi_grid, t_grid, steps_psi, steps_t = PSI_GRID, T_GRID, STEPS_PSI, STEPS_T
    #: k - 1 of the layer of each condition (0 where it is no layer)
    _shift = np.array([0.0] + [k - 1.0 for k in LAYER])
    #: the first condition of each group the root finders evaluate apart (``_groups``)
    groups = (0,)
    #: the integrand's channels
    channels = 1

    def __init__(self, mu, phi, alpha_x, alpha_y):
        s = np.sqrt(np.maximum(1.0 - mu * mu, 0.0))
        wx, wy = s * np.cos(phi), s * np.sin(phi)
        S_o = np.sqrt(mu * mu + (alpha_x * wx) ** 2 + (alpha_y * wy) ** 2)
        # wo' (the stretched direction); at mu = 0 with S_o = 0 (alpha_y = 0 along y) the
        # direction is (0, 1, 0) in the limit
        safe = np.where(S_o > 0.0, S_o, 1.0)
        px = np.where(S_o > 0.0, alpha_x * wx / safe, 0.0)
        py = np.where(S_o > 0.0, alpha_y * wy / safe, 1.0)
        pz = np.where(S_o > 0.0, mu / safe, 0.0)
        self._p = dict(mu=mu, ax=alpha_x, ay=alpha_y, wx=wx, wy=wy, S_o=S_o, px=px, py=py,
                       pz=pz)

    def _params(self, ndim):
        """The node parameters shaped ``(n, 1, ...)`` for results of ``ndim`` dimensions."""
        return {k: v.reshape(v.shape + (1,) * (ndim - 1)) for k, v in self._p.items()}

    def _at(self, index, ndim=1):
        """The parameters of the nodes ``index`` (one per entry), shaped ``(E, 1, ...)``."""
        return {k: v[index].reshape(index.shape + (1,) * (ndim - 1))
                for k, v in self._p.items()}

    def _facet(self, q, m):
        """(wo'.m', n, N, k): n = (nx, ny, nz) the rough surface's unnormalised normal,
        N = |n|^2 and k with the mirror direction wi = k n - wo."""
        st, ct, cp, sp = m
        mx, my = st * cp, st * sp
        c = q["px"] * mx + q["py"] * my + q["pz"] * ct
        nx, ny = q["ax"] * mx, q["ay"] * my
        N = nx * nx + ny * ny + ct * ct
        k = 2.0 * q["S_o"] * c / np.where(N > 0.0, N, 1.0)
        return c, (nx, ny, ct), N, k

    def fields(self, q, m):
        """(wo'.m', mu_i, S_i, mu_o, S_o)."""
        c, (nx, ny, nz), _, k = self._facet(q, m)
        ix, iy, iz = k * nx - q["wx"], k * ny - q["wy"], k * nz - q["mu"]
        S_i = np.sqrt(iz * iz + (q["ax"] * ix) ** 2 + (q["ay"] * iy) ** 2)
        return c, iz, S_i, q["mu"], q["S_o"]

    def conditions(self, q, m):
        """The functions whose roots split the psi integral: wo'.m' and mu_i - (k - 1) mu."""
        c, _, _, k = self._facet(q, m)
        iz = k * m[1] - q["mu"]
        return [c] + [iz - shift * q["mu"] for shift in self._shift[1:]]

    def condition(self, q, m, f):
        """Condition number ``f`` (an integer array broadcasting against the points)."""
        c, _, _, k = self._facet(q, m)
        iz = k * m[1] - q["mu"]
        return np.where(f == 0, c, iz - self._shift[f] * q["mu"])

    def integrand(self, q, m):
        """The integrand's channels (a tuple)."""
        c, iz, S_i, mu, S_o = self.fields(q, m)
        den = iz * S_o + mu * S_i
        g = np.where((iz > 0.0) & (den > 0.0),
                     2.0 * iz * S_o / np.where(den > 0.0, den, 1.0), 0.0)
        return (np.where(c > 0.0, c, 0.0) * g,)

    def cos_om(self, q, m):
        """wo.m = S_o (wo'.m') / |(alpha_x m'_x, alpha_y m'_y, m'_z)| in [0, 1] where the
        facet is visible."""
        st, ct, cp, sp = m
        c = self._facet(q, m)[0]
        n2 = (q["ax"] * st * cp) ** 2 + (q["ay"] * st * sp) ** 2 + ct * ct
        return np.clip(q["S_o"] * c / np.sqrt(n2), 0.0, 1.0)


class _DielectricNode(_Node):
    """``_Node`` of a dielectric interface of relative index ``eta`` seen from wo: two
    channels (reflection, transmission) and the refraction's conditions. Its roots are
    bracketed on half the conductor's grids and bisected fewer times: the same values to
    2e-6 at order 8 (``tests/test_anisotropic_energy.py``), at two thirds of the cost."""

    psi_grid, t_grid, steps_psi, steps_t = 65, 33, 16, 12
    #: conditions: wo'.m', the layers of wi, those of wt, the critical angle; the first four
    #: (the mirror's) need no refraction
    _shift = np.array([0.0] + [k - 1.0 for k in LAYER] * 2 + [0.0])
    groups = (0, 4)
    channels = 2

    def __init__(self, mu, phi, alpha_x, alpha_y, eta):
        super().__init__(mu, phi, alpha_x, alpha_y)
        self._p["eta"] = eta
        self._p["c_crit"] = np.sqrt(np.maximum(1.0 - eta * eta, 0.0))

    def _refraction(self, q, m, lengths=True):
        """(wo'.m', wo.m, mu_i, S_i, mu_t, S_t): mu_t = -wt_z (positive where wt leaves
        below), continuous through total internal reflection; S_i, S_t None unless
        ``lengths``."""
        c1, (nx, ny, ct), N, k = self._facet(q, m)
        root = np.sqrt(N)
        iz = k * ct - q["mu"]
        c = q["S_o"] * c1 / root  # wo.m
        eta = q["eta"]
        cos_t = np.sqrt(np.maximum(1.0 - (1.0 - c * c) / (eta * eta), 0.0))
        b = (c / eta - cos_t) / root  # wt = -wo / eta + b n
        mu_t = q["mu"] / eta - b * ct
        if not lengths:
            return c1, c, iz, None, mu_t, None
        ix, iy = k * nx - q["wx"], k * ny - q["wy"]
        S_i = np.sqrt(iz * iz + (q["ax"] * ix) ** 2 + (q["ay"] * iy) ** 2)
        tx, ty = b * nx - q["wx"] / eta, b * ny - q["wy"] / eta
        S_t = np.sqrt(mu_t * mu_t + (q["ax"] * tx) ** 2 + (q["ay"] * ty) ** 2)
        return c1, c, iz, S_i, mu_t, S_t

    def conditions(self, q, m):
        c1, c, iz, _, mu_t, _ = self._refraction(q, m, lengths=False)
        mu, layers = q["mu"], self._shift[1:4]
        return ([c1] + [iz - shift * mu for shift in layers]
                + [mu_t - shift * mu for shift in layers]
                + [c - q["c_crit"]])  # the critical angle (a no-root constant below it)

    def condition(self, q, m, f):
        if np.all(f < 4):  # the mirror's conditions
            return super().condition(q, m, f)
        c1, c, iz, _, mu_t, _ = self._refraction(q, m, lengths=False)
        layer = np.where(f < 4, iz, mu_t) - self._shift[f] * q["mu"]
        return np.where(f == 0, c1, np.where(f == 7, c - q["c_crit"], layer))

    def integrand(self, q, m):
        c1, c, iz, S_i, mu_t, S_t = self._refraction(q, m)
        mu, S_o = q["mu"], q["S_o"]
        visible = c1 > 0.0
        F = _dielectric(np.where(visible, np.minimum(c, 1.0), 1.0), q["eta"])

        def g(mu_w, S_w):
            den = mu_w * S_o + mu * S_w
            ok = visible & (mu_w > 0.0) & (den > 0.0)
            return np.where(ok, 2.0 * mu_w * S_o / np.where(ok, den, 1.0), 0.0)

        refracts = (1.0 - c * c) < q["eta"] * q["eta"]
        c1 = np.where(visible, c1, 0.0)
        return c1 * F * g(iz, S_i), np.where(refracts, c1 * (1.0 - F) * g(mu_t, S_t), 0.0)


def _first(change, limit):
    """The first ``limit`` True entries of every row (last axis) of the boolean ``change``:
    their indices (a tuple, one array per axis) and their rank in the row."""
    at = np.flatnonzero(change)
    row, column = np.divmod(at, change.shape[-1])
    starts = np.ones(len(row), dtype=bool)
    starts[1:] = row[1:] != row[:-1]
    count = np.arange(len(row))
    rank = count - np.maximum.accumulate(np.where(starts, count, 0))
    keep = rank < limit
    return np.unravel_index(row[keep], change.shape[:-1]) + (column[keep],), rank[keep]


def _signs(rows):
    """np.signbit of the ``rows`` (arrays of one shape), stacked on a first axis."""
    negative = np.empty((len(rows),) + np.shape(rows[0]), dtype=bool)
    for r, row in enumerate(rows):
        np.signbit(row, out=negative[r])
    return negative


def _count(negative):
    """Root state along psi (last axis): twice the sign changes plus the sign at psi = 0 (a
    condition that changes sign for all psi at once changes no count)."""
    return 2 * (negative[..., 1:] != negative[..., :-1]).sum(-1) + negative[..., 0]


def _groups(node, f):
    """Slices of the entries (sorted by their condition ``f``) in each of ``node.groups``."""
    bounds = np.append(np.searchsorted(f, node.groups), len(f))
    return [slice(lo, hi) for lo, hi in zip(bounds[:-1], bounds[1:], strict=True)
            if hi > lo]


def _psi_root(node, q, st, ct, f, a, b, f_a, f_b):
    """The root in psi in [a, b] of condition ``f`` (``f_a``, ``f_b`` at a and b) at
    t = arctan(st / ct), one per entry: bisection, then one secant step in the final
    bracket."""
    sign_a = np.signbit(f_a)
    for _ in range(node.steps_psi):
        mid = 0.5 * (a + b)
        f_mid = node.condition(q, (st, ct, np.cos(mid), np.sin(mid)), f)
        same = np.signbit(f_mid) == sign_a
        a, b = np.where(same, mid, a), np.where(same, b, mid)
        f_a, f_b = np.where(same, f_mid, f_a), np.where(same, f_b, f_mid)
    den = f_a - f_b
    root = np.where(den != 0.0, a + (b - a) * f_a / np.where(den != 0.0, den, 1.0), a)
    return np.clip(root, a, b)


def _psi_roots(node, rows, t):
    """The psi roots ``(R, 4 F)`` (NaN: none) at the t nodes ``t`` ``(R,)`` of the nodes
    ``rows``: the first four sign changes of each of the F conditions on the grid, each
    bisected on its own condition only. Rows equal to the previous one (the zero-width t
    panels that pad the knots) share its roots."""
    new = np.ones(len(t), dtype=bool)
    new[1:] = (t[1:] != t[:-1]) | (rows[1:] != rows[:-1])
    rows, t = rows[new], t[new]
    psi = np.linspace(0.0, 2.0 * np.pi, node.psi_grid)
    cp, sp = np.cos(psi), np.sin(psi)
    roots = np.full((len(t), 4 * len(node._shift)), np.nan)
    for block in range(0, len(t), ROOT_ROWS):
        r = slice(block, block + ROOT_ROWS)
        st, ct, q = np.sin(t[r]), np.cos(t[r]), node._at(rows[r], 2)
        values = node.conditions(q, (st[:, None], ct[:, None], cp, sp))
        negative = _signs(values)
        (f, j, g), rank = _first(negative[..., 1:] != negative[..., :-1], 4)
        # the conditions at the ends of the brackets, read from the grid
        f_a, f_b = np.empty(len(f)), np.empty(len(f))
        bounds = np.searchsorted(f, np.arange(len(values) + 1))
        for k, row in enumerate(values):
            e = slice(bounds[k], bounds[k + 1])
            f_a[e], f_b[e] = row[j[e], g[e]], row[j[e], g[e] + 1]
        for e in _groups(node, f):
            je = j[e]
            roots[block + je, 4 * f[e] + rank[e]] = _psi_root(
                node, node._at(rows[r][je]), st[je], ct[je], f[e], psi[g[e]],
                psi[g[e] + 1], f_a[e], f_b[e])
    return roots[np.cumsum(new) - 1]


def _t_knot(node, q, f, a, b, count_a):
    """Where the root count of condition ``f`` changes in t in [a, b], one per entry
    (``count_a`` at a): bisection."""
    psi = np.linspace(0.0, 2.0 * np.pi, node.psi_grid)
    cp, sp, f = np.cos(psi), np.sin(psi), f[:, None]
    for _ in range(node.steps_t):
        mid = 0.5 * (a + b)
        m = (np.sin(mid)[:, None], np.cos(mid)[:, None], cp, sp)
        same = _count(np.signbit(node.condition(q, m, f))) == count_a
        a, b = np.where(same, mid, a), np.where(same, b, mid)
    return 0.5 * (a + b)


def _t_roots(node):
    """Where the root counts change in t, ``(n, 4 F)`` (NaN: none): the first four changes
    of each condition on the grid, each bisected on its own count only."""
    grid = np.linspace(0.0, 0.5 * np.pi, node.t_grid)
    psi = np.linspace(0.0, 2.0 * np.pi, node.psi_grid)
    m = (np.sin(grid)[:, None], np.cos(grid)[:, None], np.cos(psi), np.sin(psi))
    counts = _count(_signs(node.conditions(node._params(3), m)))  # (F, n, G)
    (f, i, g), rank = _first(counts[..., 1:] != counts[..., :-1], 4)
    found = np.full((counts.shape[1], 4 * len(counts)), np.nan)
    for e in _groups(node, f):
        found[i[e], 4 * f[e] + rank[e]] = _t_knot(node, node._at(i[e], 2), f[e], grid[g[e]],
                                                  grid[g[e] + 1], counts[f[e], i[e], g[e]])
    return found


def _compact(knots, end):
    """``knots`` sorted along the last axis, NaN (none) moved to the end as ``end`` and the
    columns that are ``end`` in every row dropped."""
    knots = np.sort(knots, -1)
    count = int(np.isfinite(knots).sum(-1).max())
    return np.where(np.isfinite(knots[..., :count]), knots[..., :count], end)


def _pieces(knots, order):
    """Gauss–Legendre nodes and weights ``(n, K order)`` of the pieces between ``knots``
    ``(n, K + 1)``, flattened."""
    x, wx = _rule(order)
    a, b = knots[..., :-1, None], knots[..., 1:, None]
    shape = knots.shape[:-1] + (-1,)
    return (a + (b - a) * x).reshape(shape), ((b - a) * wx).reshape(shape)


def _live(node, first, t, psi, live, degree):
    """The integrand ``(n, T, P, channels)`` of the nodes ``first`` + 0 .. n - 1 at the
    points (t, psi) where ``live`` (and, for ``degree`` > 0, 2 wo.m - 1 there), zero
    elsewhere: the pieces of zero width, which pad the knots to the same count, weigh zero
    (and the integrand is finite)."""
    st, ct = np.sin(t), np.cos(t)
    n, T, P = psi.shape
    values = np.zeros((n, T * P, node.channels))
    x_om = np.zeros((n, T * P)) if degree else None
    for k in range(n):
        at = np.flatnonzero(live[k])
        j, ps = at // P, psi[k].ravel()[at]
        q = node._at(np.array([first + k]))
        m = (st[k, j], ct[k, j], np.cos(ps), np.sin(ps))
        for c, v in enumerate(node.integrand(q, m)):
            values[k, at, c] = v
        if degree:
            x_om[k, at] = 2.0 * node.cos_om(q, m) - 1.0
    return values.reshape(psi.shape + (-1,)), x_om


def _integrate(node, first, t, w_t, psi_knots, order, degree):
    """The integrals ``(n, channels or degree + 1)`` of the nodes ``first`` + 0 .. n - 1
    on the t nodes ``t`` (weights ``w_t``, ``(n, T)``) split at ``psi_knots`` (``(n, T,
    J)``)."""
    n = len(t)
    psi, w_psi = _pieces(psi_knots, order)  # (n, T, P)
    live = (w_t[..., None] != 0.0) & (w_psi != 0.0)
    values, x_om = _live(node, first, t, psi, live, degree)
    if node.channels > 1:
        return np.einsum("nt,ntp,ntpc->nc", w_t, w_psi, values)
    values = values[..., 0]
    if degree == 0:
        return np.einsum("nt,ntp,ntp->n", w_t, w_psi, values)[:, None]
    weighted = (w_t[..., None] * w_psi * values).reshape(n, 1, -1)
    legendre = np.polynomial.legendre.legvander(x_om.reshape(n, -1), degree)
    return (weighted @ legendre)[:, 0]


def _quadrature(make, args, chunk, orders, degree):
    """The integrals ``(N, len(orders), channels or degree + 1)`` at each of ``orders`` of
    the nodes ``make(*args)`` (N each) by chunks of ``chunk`` nodes, whose knots are padded
    to one count; the roots of ``ROOT_CHUNKS`` chunks at all orders are found at once."""
    uniform = np.linspace(0.0, 0.5 * np.pi, T_PANELS + 1)
    fixed = np.arange(PSI_PANELS + 1) * (2.0 * np.pi / PSI_PANELS)
    out = np.empty((len(args[0]), len(orders), make.channels if degree == 0 else degree + 1))
    for start in range(0, len(args[0]), chunk * ROOT_CHUNKS):
        node = make(*[a[start:start + chunk * ROOT_CHUNKS] for a in args])
        found = _t_roots(node)
        parts = []  # (first node, order index, t, w_t), t (chunk, T)
        for first in range(0, len(found), chunk):
            part = found[first:first + chunk]
            knots = _compact(np.concatenate(
                [np.broadcast_to(uniform, (len(part), T_PANELS + 1)), part], -1), 0.5 * np.pi)
            for k, order in enumerate(orders):
                t, w_t = _pieces(knots, order)
                parts.append((first, k, t, w_t * np.sin(t) / np.pi))
        rows = np.concatenate([np.repeat(first + np.arange(len(t)), t.shape[1])
                               for first, _, t, _ in parts])
        roots = _psi_roots(node, rows, np.concatenate([t.ravel() for _, _, t, _ in parts]))
        at = 0
        for first, k, t, w_t in parts:
            part = roots[at:at + t.size].reshape(t.shape + (-1,))
            at += t.size
            psi_knots = _compact(np.concatenate(
                [np.broadcast_to(fixed, t.shape + (PSI_PANELS + 1,)), part], -1), 2.0 * np.pi)
            out[start + first:start + first + len(t), k] = _integrate(
                node, first, t, w_t, psi_knots, orders[k], degree)
    return out


def ggx_anisotropic_moments(mu, phi, alpha_x, alpha_y, degree: int, order: int = 16,
                            estimate: bool = True):
    """Fresnel moments M_k = int D_wo(m) P_k(2 wo.m - 1) G2(wo, wi) / G1(wo) dm, k = 0 ..
    ``degree`` (P_k Legendre polynomials; M_0 = E) of the anisotropic GGX reflection, with
    error estimates: a Fresnel F(wo.m) = sum_k a_k P_k(2 wo.m - 1) reflects sum_k a_k M_k.
    Arguments as ``ggx_anisotropic_energy``; returns ``(values, errors)``, each shaped like
    the broadcast inputs plus ``(degree + 1,)``."""
    return _run(mu, phi, alpha_x, alpha_y, order, estimate, degree)


def _run(mu, phi, alpha_x, alpha_y, order, estimate, degree):
    arrays = np.broadcast_arrays(*[np.asarray(a, dtype=np.float64)
                                   for a in (mu, phi, alpha_x, alpha_y)])
    shape = arrays[0].shape
    flat = [a.ravel() for a in arrays]
    orders = (order, max(2, (2 * order) // 3)) if estimate else (order,)
    result = _quadrature(_Node, flat, CHUNK, orders, degree)
    value = result[:, 0]
    error = np.abs(value - result[:, 1]) if estimate else np.zeros_like(value)
    return value.reshape(shape + (-1,)), error.reshape(shape + (-1,))


def ggx_anisotropic_energy(mu, phi, alpha_x, alpha_y, order: int = 16,
                           estimate: bool = True) -> Energy:
    """Single-scattering energy of an anisotropic GGX conductor (F = 1) seen from
    wo = (sin theta cos ``phi``, sin theta sin ``phi``, ``mu``).

    Parameters
    ----------
    mu : array_like in [0, 1]
        cos theta_o (0: the grazing limit).
    phi : array_like
        Azimuth of wo from the alpha_x axis.
    alpha_x, alpha_y : array_like in [0, inf), not both 0
        GGX roughness along x and y (alpha_y = 0: the one-dimensional rough limit).
    order : int
        Gauss–Legendre nodes per piece and dimension.
    estimate : bool
        False skips the error estimate (returned as 0).

    Returns
    -------
    Energy with E_R = E, E_T = 0 and the error estimate |Q(order) - Q(2 order / 3)|.
    """
    value, error = _run(mu, phi, alpha_x, alpha_y, order, estimate, 0)
    value, error = value[..., 0], error[..., 0]
    shape = value.shape
    zero = np.zeros(shape)
    return Energy(value, zero, error, zero)


def ggx_anisotropic_dielectric_energy(mu, phi, alpha_x, alpha_y, eta, order: int = 16,
                                      estimate: bool = True) -> Energy:
    """Single-scattering reflected and transmitted energy of an anisotropic GGX dielectric
    interface (exact Fresnel, height-correlated Smith) seen from wo at cosine ``mu`` and
    azimuth ``phi`` with relative index ``eta`` = n beyond / n of wo's side (< 1: seen from
    the dense side). Other arguments and the error estimate as ``ggx_anisotropic_energy``.
    ``eta`` = 1 is the closed form E_R = 0, E_T = 1 / (2 - G1(wo)) [Heitz2014, eq. 99]."""
    arrays = np.broadcast_arrays(*[np.asarray(a, dtype=np.float64)
                                   for a in (mu, phi, alpha_x, alpha_y, eta)])
    shape = arrays[0].shape
    flat = [a.ravel() for a in arrays]
    orders = (order, max(2, (2 * order) // 3)) if estimate else (order,)
    result = _quadrature(_DielectricNode, flat, DIELECTRIC_CHUNK, orders, 0)
    value = result[:, 0]
    error = np.abs(value - result[:, 1]) if estimate else np.zeros_like(value)
    mu_f, eta_f = flat[0], flat[4]
    matched = eta_f == 1.0
    if np.any(matched):
        S_o = _Node(*[a[matched] for a in flat[:4]])._p["S_o"]
        G1 = 2.0 * mu_f[matched] / (mu_f[matched] + S_o)
        value[matched] = np.stack([np.zeros_like(G1), 1.0 / (2.0 - G1)], -1)
        error[matched] = 0.0
    value, error = value.reshape(shape + (2,)), error.reshape(shape + (2,))
    return Energy(value[..., 0], value[..., 1], error[..., 0], error[..., 1])


#: Gauss–Legendre points of the Legendre coefficients of a Fresnel curve
_FRESNEL_POINTS = 256


@functools.lru_cache(maxsize=4)
def _legendre_projector(degree: int) -> np.ndarray:
    """``(c, P)``: Gauss points c in [0, 1] and the matrix P with a = F(c) @ P the Legendre
    coefficients of F(c) = sum_k a_k P_k(2 c - 1) up to ``degree`` (orthogonal projection)."""
    x, w = np.polynomial.legendre.leggauss(_FRESNEL_POINTS)
    V = np.polynomial.legendre.legvander(x, degree)
    return 0.5 * (x + 1.0), (w[:, None] * V) * (np.arange(degree + 1) + 0.5)


def fresnel_coefficients(eta, degree: int) -> np.ndarray:
    """Legendre coefficients ``(..., degree + 1)`` of the exact dielectric Fresnel F(c) of
    relative index ``eta`` >= 1 on c = wo.m in [0, 1]: the weights of the moments of
    "ggx_reflection_moments". Their absolute sum is ~1 (the moments' errors add, not grow)."""
    c, P = _legendre_projector(degree)
    F = _dielectric(c, np.asarray(eta, dtype=np.float64)[..., None])
    return F @ P
