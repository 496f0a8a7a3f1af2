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
#: nodes processed at once (memory ~ CHUNK x 40 MB at order 16)
CHUNK = 2
#: the same for the dielectric's coarser grids (~ DIELECTRIC_CHUNK x 10 MB at order 8)
DIELECTRIC_CHUNK = 4


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
    """The fixed quantities of a batch of nodes, shaped to broadcast against (n, ...), and
    the root-finding grids used for them."""

    psi_grid, t_grid, steps_psi, steps_t = PSI_GRID, T_GRID, STEPS_PSI, STEPS_T

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

    def _facet(self, t, psi):
        """(q, wo'.m', n, N, k) at m'(t, psi): q the node parameters, n = (nx, ny, nz) the
        rough surface's unnormalised normal, N = |n|^2 and k with the mirror direction
        wi = k n - wo."""
        q = self._params(max(np.ndim(t), np.ndim(psi)))
        st, ct = np.sin(t), np.cos(t)
        mx, my = st * np.cos(psi), st * np.sin(psi)
        c = q["px"] * mx + q["py"] * my + q["pz"] * ct
        nx, ny = q["ax"] * mx, q["ay"] * my
        N = nx * nx + ny * ny + ct * ct
        k = 2.0 * q["S_o"] * c / np.where(N > 0.0, N, 1.0)
        return q, c, (nx, ny, ct), N, k

    def fields(self, t, psi):
        """(wo'.m', mu_i, S_i, mu_o, S_o) at m'(t, psi); the result's first axis is the
        node's."""
        q, c, (nx, ny, nz), _, k = self._facet(t, psi)
        ix, iy, iz = k * nx - q["wx"], k * ny - q["wy"], k * nz - q["mu"]
        S_i = np.sqrt(iz * iz + (q["ax"] * ix) ** 2 + (q["ay"] * iy) ** 2)
        return c, iz, S_i, q["mu"], q["S_o"]

    def conditions(self, t, psi):
        """The functions whose roots split the psi integral, stacked on a last axis."""
        c, iz, _, mu, _ = self.fields(t, psi)
        return np.stack([c] + [iz - (k - 1.0) * mu for k in LAYER], axis=-1)

    def condition(self, t, psi, f):
        """Condition number ``f`` (an integer array broadcasting against the result)."""
        return np.take_along_axis(self.conditions(t, psi), f[..., None], -1)[..., 0]

    def integrand(self, t, psi):
        c, iz, S_i, mu, S_o = self.fields(t, psi)
        den = iz * S_o + mu * S_i
        g = np.where((iz > 0.0) & (den > 0.0),
                     2.0 * iz * S_o / np.where(den > 0.0, den, 1.0), 0.0)
        return np.where(c > 0.0, c, 0.0) * g

    def cos_om(self, t, psi):
        """wo.m = S_o (wo'.m') / |(alpha_x m'_x, alpha_y m'_y, m'_z)| in [0, 1] where the
        facet is visible."""
        q = self._params(max(np.ndim(t), np.ndim(psi)))
        c = self.fields(t, psi)[0]
        st, ct = np.sin(t), np.cos(t)
        n2 = (q["ax"] * st * np.cos(psi)) ** 2 + (q["ay"] * st * np.sin(psi)) ** 2 + ct * ct
        return np.clip(q["S_o"] * c / np.sqrt(n2), 0.0, 1.0)


class _DielectricNode(_Node):
    """``_Node`` of a dielectric interface of relative index ``eta`` seen from wo: two
    channels (reflection, transmission) and the refraction's conditions. Its roots are
    bracketed on half the conductor's grids and bisected fewer times: the same values to
    2e-6 at order 8 (``tests/test_anisotropic_energy.py``), at two thirds of the cost."""

    psi_grid, t_grid, steps_psi, steps_t = 65, 33, 16, 12

    def __init__(self, mu, phi, alpha_x, alpha_y, eta):
        super().__init__(mu, phi, alpha_x, alpha_y)
        self._p["eta"] = eta
        self._p["c_crit"] = np.sqrt(np.maximum(1.0 - eta * eta, 0.0))

    def _refraction(self, t, psi, lengths=True):
        """(wo'.m', wo.m, mu_i, S_i, mu_t, S_t, q) at m'(t, psi), q the node parameters;
        mu_t = -wt_z (positive where wt leaves below), continuous through total internal
        reflection; S_i, S_t None unless ``lengths``."""
        q, c1, (nx, ny, ct), N, k = self._facet(t, psi)
        root = np.sqrt(N)
        iz = k * ct - q["mu"]
        c = q["S_o"] * c1 / root  # wo.m
        eta = q["eta"]
        cos_t = np.sqrt(np.maximum(1.0 - (1.0 - c * c) / (eta * eta), 0.0))
        b = (c / eta - cos_t) / root  # wt = -wo / eta + b n
        mu_t = q["mu"] / eta - b * ct
        if not lengths:
            return c1, c, iz, None, mu_t, None, q
        ix, iy = k * nx - q["wx"], k * ny - q["wy"]
        S_i = np.sqrt(iz * iz + (q["ax"] * ix) ** 2 + (q["ay"] * iy) ** 2)
        tx, ty = b * nx - q["wx"] / eta, b * ny - q["wy"] / eta
        S_t = np.sqrt(mu_t * mu_t + (q["ax"] * tx) ** 2 + (q["ay"] * ty) ** 2)
        return c1, c, iz, S_i, mu_t, S_t, q

    def conditions(self, t, psi):
        c1, c, iz, _, mu_t, _, q = self._refraction(t, psi, lengths=False)
        mu = q["mu"]
        rows = [c1] + [iz - (k - 1.0) * mu for k in LAYER] + [mu_t - (k - 1.0) * mu
                                                               for k in LAYER]
        rows.append(c - q["c_crit"])  # the critical angle (a no-root constant below it)
        return np.stack(rows, axis=-1)

    def integrand(self, t, psi):
        c1, c, iz, S_i, mu_t, S_t, q = self._refraction(t, psi)
        mu, S_o = q["mu"], q["S_o"]
        visible = c1 > 0.0
        F = _dielectric(np.where(visible, np.minimum(c, 1.0), 1.0), q["eta"])

        def g(mu_w, S_w):
            den = mu_w * S_o + mu * S_w
            ok = visible & (mu_w > 0.0) & (den > 0.0)
            return np.where(ok, 2.0 * mu_w * S_o / np.where(ok, den, 1.0), 0.0)

        refracts = (1.0 - c * c) < q["eta"] * q["eta"]
        c1 = np.where(visible, c1, 0.0)
        return np.stack([c1 * F * g(iz, S_i),
                         np.where(refracts, c1 * (1.0 - F) * g(mu_t, S_t), 0.0)], -1)


def _crossings(values, grid, limit):
    """Brackets [a, b] on ``grid`` (last axis) where ``values`` changes sign, at most
    ``limit`` per row: (a, b, valid), each ``(..., limit)``."""
    change = np.signbit(values[..., 1:]) != np.signbit(values[..., :-1])
    first = np.argsort(~change, axis=-1, kind="stable")[..., :limit]
    valid = np.take_along_axis(change, first, -1)
    return grid[first], grid[first + 1], valid


def _psi_roots(node, t):
    """Sorted psi knots ``(n, T, K)`` at the t nodes ``(n, T)`` (0, the roots, 2 pi)."""
    psi = np.linspace(0.0, 2.0 * np.pi, node.psi_grid)
    values = node.conditions(t[..., None], psi)  # (n, T, G, F)
    values = np.moveaxis(values, -1, -2)  # (n, T, F, G)
    a, b, valid = _crossings(values, psi, 4)  # (n, T, F, 4)
    t4 = t[..., None, None]
    f = np.broadcast_to(np.arange(values.shape[-2])[:, None], a.shape)
    sign_a = np.signbit(node.condition(t4, a, f))
    for _ in range(node.steps_psi):
        mid = 0.5 * (a + b)
        same = np.signbit(node.condition(t4, mid, f)) == sign_a
        a, b = np.where(same, mid, a), np.where(same, b, mid)
    f_a = node.condition(t4, a, f)
    f_b = node.condition(t4, b, f)
    # a last secant step in the final bracket
    den = f_a - f_b
    root = np.where(den != 0.0, a + (b - a) * f_a / np.where(den != 0.0, den, 1.0), a)
    root = np.clip(root, a, b)
    roots = np.where(valid, root, np.nan).reshape(t.shape + (-1,))
    fixed = np.broadcast_to(np.arange(PSI_PANELS + 1) * (2.0 * np.pi / PSI_PANELS),
                            t.shape + (PSI_PANELS + 1,))
    return _compact(np.concatenate([fixed, roots], -1), 2.0 * np.pi)


def _root_state(node, t):
    """Number of psi roots of every condition at ``t`` ``(n, M)``, and its sign at psi = 0:
    ``(n, M, F)`` (a condition that changes sign for all psi at once changes no count)."""
    psi = np.linspace(0.0, 2.0 * np.pi, node.psi_grid)
    negative = np.signbit(np.moveaxis(node.conditions(t[..., None], psi), -1, -2))
    return 2 * (negative[..., 1:] != negative[..., :-1]).sum(-1) + negative[..., 0]


def _t_knots(node, n):
    """Sorted t knots ``(n, K)``: uniform panels and where a root count changes."""
    grid = np.linspace(0.0, 0.5 * np.pi, node.t_grid)
    counts = _root_state(node, np.broadcast_to(grid, (n, node.t_grid)))  # (n, G, F)
    counts = np.moveaxis(counts, -1, -2)  # (n, F, G)
    change = counts[..., 1:] != counts[..., :-1]
    first = np.argsort(~change, axis=-1, kind="stable")[..., :4]  # (n, F, 4)
    valid = np.take_along_axis(change, first, -1)
    a, b = grid[first], grid[first + 1]
    count_a = np.take_along_axis(counts, first, -1)
    f = np.broadcast_to(np.arange(counts.shape[1])[None, :, None], a.shape)
    for _ in range(node.steps_t):
        mid = 0.5 * (a + b)
        c_mid = _root_state(node, mid.reshape(n, -1)).reshape(mid.shape + (-1,))
        c_mid = np.take_along_axis(c_mid, f[..., None], -1)[..., 0]
        same = c_mid == count_a
        a, b = np.where(same, mid, a), np.where(same, b, mid)
    found = np.where(valid, 0.5 * (a + b), np.nan).reshape(n, -1)
    uniform = np.broadcast_to(np.linspace(0.0, 0.5 * np.pi, T_PANELS + 1), (n, T_PANELS + 1))
    return _compact(np.concatenate([uniform, found], -1), 0.5 * np.pi)


def _compact(knots, end):
    """``knots`` sorted along the last axis, NaN (none) moved to the end as ``end`` and the
    columns that are ``end`` in every row dropped."""
    knots = np.sort(knots, -1)
    count = int(np.isfinite(knots).sum(-1).max())
    return np.where(np.isfinite(knots[..., :count]), knots[..., :count], end)


def _integrate(node, n, order, degree):
    x, wx = _rule(order)
    knots = _t_knots(node, n)  # (n, K)
    ta, tb = knots[:, :-1, None], knots[:, 1:, None]
    t = (ta + (tb - ta) * x).reshape(n, -1)  # (n, T)
    w_t = ((tb - ta) * wx).reshape(n, -1) * np.sin(t) / np.pi
    psi_knots = _psi_roots(node, t)  # (n, T, J)
    pa, pb = psi_knots[..., :-1, None], psi_knots[..., 1:, None]
    psi = (pa + (pb - pa) * x).reshape(t.shape + (-1,))  # (n, T, P)
    w_psi = ((pb - pa) * wx).reshape(psi.shape)
    values = node.integrand(t[..., None], psi)
    if values.ndim == 4:  # channels
        return np.einsum("nt,ntp,ntpc->nc", w_t, w_psi, values)
    if degree == 0:
        return np.einsum("nt,ntp,ntp->n", w_t, w_psi, values)[:, None]
    weighted = (w_t[..., None] * w_psi * values).reshape(n, 1, -1)
    x_om = (2.0 * node.cos_om(t[..., None], psi) - 1.0).reshape(n, -1)
    legendre = np.polynomial.legendre.legvander(x_om, degree)  # (n, T P, degree + 1)
    return (weighted @ legendre)[:, 0]


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
    value, error = np.zeros((flat[0].size, degree + 1)), np.zeros((flat[0].size, degree + 1))
    low = max(2, (2 * order) // 3)
    for start in range(0, len(value), CHUNK):
        part = [a[start:start + CHUNK] for a in flat]
        n = len(part[0])
        node = _Node(*part)
        hi = _integrate(node, n, order, degree)
        value[start:start + n] = hi
        if estimate:
            error[start:start + n] = np.abs(hi - _integrate(node, n, low, degree))
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
    value, error = np.zeros((flat[0].size, 2)), np.zeros((flat[0].size, 2))
    low = max(2, (2 * order) // 3)
    for start in range(0, len(value), DIELECTRIC_CHUNK):
        part = [a[start:start + DIELECTRIC_CHUNK] for a in flat]
        n = len(part[0])
        node = _DielectricNode(*part)
        hi = _integrate(node, n, order, 0)
        value[start:start + n] = hi
        if estimate:
            error[start:start + n] = np.abs(hi - _integrate(node, n, low, 0))
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
