"""The declared tables: every energy table the library ships, with its node function.

| name | axes | outputs | source |
|---|---|---|---|
| ``ggx_conductor`` | mu, alpha | E | [KullaConty2017]; [Kutz2021, §1.2] |
| ``ggx_conductor_avg`` | alpha | E_avg | the mu-average 2 int E mu dmu of the above |
| ``ggx_dielectric_outside`` | mu, alpha, eta | E_R, E_T | [Kutz2021, §1.2], light side |
| ``ggx_dielectric_inside`` | mu, alpha, eta | E_R, E_T | the same from the dense side (1 / eta) |
| ``ggx_dielectric_*_avg`` | alpha, eta | E_R_avg, E_T_avg | mu-averages of the two above |
| ``ggx_dielectric_ms_reflection`` | mu, alpha, eta | a | scale of the glossy multiple reflection |
| ``asm_diffuse_L`` | mu, roughness, ior | L | [Kutz2021, §1.1 eq. 1], lobe integral L |
| ``asm_diffuse_T`` | roughness, ior | T | [Kutz2021, §1.1 eq. 1], total integral T |
| ``ggx_conductor_anisotropic`` | s, cos_phi, alpha, ratio | E | the anisotropic E(wo) |
| ``ggx_conductor_anisotropic_avg`` | alpha, ratio | E_avg | its hemispherical average |
| ``ggx_reflection_moments`` | v, cos_phi, alpha, ratio | M_0..M_16 | anisotropic Fresnel moments |
| ``sheen_albedo`` | mu, roughness | E | [Kutz2021, §6 eqs. 15-18] (c = a = p = 1) |

Node values come from ``energy.ggx_energy`` (piecewise Gauss–Legendre, error estimate per
node); roughness 0 is the smooth interface in closed form. Averages are not integrated
afresh: they are the exact average of the mu-interpolant of their parent table, so that a
Kulla–Conty or ASM diffuse term built from the interpolated tables integrates to exactly the
energy it is meant to restore (``docs/tables.md``).

The sheen table's nodes come from ``sheen_energy``, its own quadrature in direction space
(``docs/sheen.md``).
"""

from __future__ import annotations

import numpy as np
from scipy.special import roots_legendre

from adobe_bsdf.fresnel import _dielectric
from adobe_bsdf.tables.anisotropic_energy import (
    ALPHA_FLOOR,
    blended,
    cosine,
    fresnel_coefficients,
    ggx_anisotropic_energy,
    ggx_anisotropic_moments,
    projected_alpha,
    similarity,
    unblended,
)
from adobe_bsdf.tables.energy import ggx_energy, ggx_reflection_transfer
from adobe_bsdf.tables.table import Axis, Table, TableSpec

__all__ = ["SPECS", "ETA_MAX", "IOR_MAX", "ALPHA_MAX", "sheen_energy", "anisotropic_average",
           "MOMENT_DEGREE"]

#: largest index ratio n_dense / n_light of the dielectric tables (the ior range of ASM and
#: OpenPBR, [1, 3]); from the dense side the relative index goes down to 1 / ETA_MAX
ETA_MAX = 3.0
#: largest ior of the ASM diffuse tables
IOR_MAX = 4.0
#: largest GGX alpha covered (ASM anisotropy reaches alpha_x = 2)
ALPHA_MAX = 2.0

_QUADRATURE = ("piecewise Gauss-Legendre over microfacet normals (scipy.special.roots_legendre), "
               "split at the horizon / visibility / critical-angle breakpoints; error = |Q(n) - "
               "Q(2n/3)|")
_AVERAGE = "exact 2 int f mu dmu of the parent's mu-interpolant (Gauss-Legendre per cell)"


def _energy(mu, alpha, eta, order):
    """(E_R, E_T) values and errors ``(n, 2)``; alpha = 0 is the smooth interface."""
    smooth = alpha == 0.0
    values, errors = np.zeros((len(mu), 2)), np.zeros((len(mu), 2))
    rough = ~smooth
    if np.any(rough):
        e = ggx_energy(mu[rough], alpha[rough], None if eta is None else eta[rough], order)
        values[rough] = np.stack([e.reflection, e.transmission], -1)
        errors[rough] = np.stack([e.error_reflection, e.error_transmission], -1)
    if np.any(smooth):
        F = 1.0 if eta is None else _dielectric(mu[smooth], eta[smooth])
        values[smooth, 0] = F
        values[smooth, 1] = 0.0 if eta is None else 1.0 - F
    return values, errors


#: Sinkhorn iterations of ``_ms_reflection`` (it stops earlier once a column has converged)
_SINKHORN_STEPS = 4000


def _symmetric_scaling(M, X):
    """a >= 0 with a_k (M a)_k = X_k for every k with X_k > 0 (a_k = 0 where X_k = 0): the
    symmetric matrix scaling of the positive kernel M by the fixed-point iteration
    a <- sqrt(a X / (M a)) [Sinkhorn1967]; returns (a, |a (M a) - X|)."""
    a = np.sqrt(X)
    for _ in range(_SINKHORN_STEPS):
        Ma = M @ a
        new = np.sqrt(a * X / np.where(Ma > 0.0, Ma, 1.0))
        new = np.where(X > 0.0, new, 0.0)
        done = np.max(np.abs(new - a), initial=0.0) <= 1e-15 * np.max(new, initial=1.0)
        a = new
        if done:
            break
    return a, np.abs(a * (M @ a) - X)


def _ms_reflection(spec, mu, alpha, eta, parent: Table):
    """a(mu) of every (alpha, eta) column: the F = 1 GGX reflection at alpha, scaled by
    a(mu_o) a(mu_i), reflects exactly X(mu_o) = 1 - E_R - E_T of the light side (``parent``,
    at its nodes) for the cubic interpolant of a on the mu axis (``ggx_reflection_transfer``
    and ``_symmetric_scaling``). Error: the residual of that equation."""
    axis = spec.axes[0]
    mu_nodes, alphas, etas = (a.nodes() for a in spec.axes)
    grid = np.meshgrid(mu_nodes, alphas, etas, indexing="ij")
    X = np.maximum(1.0 - parent(*grid).sum(-1), 0.0)  # (mu, alpha, eta): its interpolant
    values, errors = np.zeros(X.shape), np.zeros(X.shape)
    for i, a in enumerate(alphas):
        if a == 0.0:
            continue  # the smooth interface scatters once: no multiple reflection
        M = ggx_reflection_transfer(mu_nodes, np.full(len(mu_nodes), a), axis, spec.order)
        for j in range(len(etas)):
            values[:, i, j], errors[:, i, j] = _symmetric_scaling(M, X[:, i, j])
    full = Table(spec, values[..., None], errors[..., None])
    return full(mu, alpha, eta), full.error(mu, alpha, eta)


def _conductor(spec, mu, alpha):
    values, errors = _energy(mu, alpha, None, spec.order)
    return values[:, :1], errors[:, :1]


def _dielectric_outside(spec, mu, alpha, eta):
    return _energy(mu, alpha, eta, spec.order)


def _dielectric_inside(spec, mu, alpha, eta):
    return _energy(mu, alpha, 1.0 / eta, spec.order)


def _asm_lobe_integral(spec, mu, roughness, ior):
    values, errors = _energy(mu, roughness * roughness, ior, spec.order)
    return values[:, :1], errors[:, :1]


def _average(spec, *coords, parent: Table):
    """mu-average of the ``parent`` table at the nodes ``coords`` of the remaining axes."""
    w = parent.spec.axes[0].average_weights()
    full = Table(spec, np.einsum("k,k...->...", w, parent.values),
                 np.einsum("k,k...->...", w, parent.errors))
    # the nodes asked for are nodes of the parent: interpolation returns them exactly
    return full(*coords), full.error(*coords)


def _anisotropic_conductor(spec, s, cos_phi, alpha, ratio):
    """E at the similarity coordinate s (``anisotropic_energy.similarity``); alpha = 0 holds
    the limit alpha -> 0 at fixed s (the lobe itself is then a mirror, E = 1, and is never
    looked up)."""
    alpha = np.maximum(alpha, ALPHA_FLOOR)
    mu = cosine(s, projected_alpha(cos_phi, alpha, ratio))
    e = ggx_anisotropic_energy(mu, np.arccos(cos_phi), alpha, ratio * alpha, spec.order)
    return e.reflection[:, None], e.error_reflection[:, None]


#: highest Legendre degree of the Fresnel moments (L within 2e-5 of the exact Fresnel's for
#: ior >= 1.01, tests/test_anisotropic_energy.py)
MOMENT_DEGREE = 16


def _reflection_moments(spec, v, cos_phi, alpha, ratio):
    """Fresnel moments M_k at the blended coordinate v (``anisotropic_energy.blended``), as
    ``_anisotropic_conductor``."""
    alpha = np.maximum(alpha, ALPHA_FLOOR)
    mu = unblended(v, projected_alpha(cos_phi, alpha, ratio))
    return ggx_anisotropic_moments(mu, np.arccos(cos_phi), alpha, ratio * alpha,
                                   MOMENT_DEGREE, spec.order)


#: relative indices at which ``bake --check`` compares the moments' Fresnel combinations
#: sum_k a_k M_k: the high moments alone converge slowly with the order (their differences
#: between orders cancel in every Fresnel combination; ``docs/tables.md``)
CHECK_ETAS = (1.01, 1.1, 1.5, 2.0, 3.0, IOR_MAX)
#: accuracy of the moments' nodes in those combinations (measured in ``docs/tables.md``;
#: far below their interpolation error)
MOMENTS_CHECK_TOL = 3e-5


def _fresnel_combinations():
    """``(K + 1, len(CHECK_ETAS))``: the Fresnel coefficients a_k at ``CHECK_ETAS``."""
    return fresnel_coefficients(np.array(CHECK_ETAS), MOMENT_DEGREE).T


#: accuracy of the anisotropic conductor's nodes (order 12) that ``bake --check`` accepts:
#: against order 18 they differ by up to 2.8e-5 at 144 random nodes, where the stored
#: |Q(n) - Q(2n/3)| estimates reach 9e-5 (docs/tables.md); far below the interpolation error
ANISOTROPIC_CHECK_TOL = 5e-5


#: Gauss points per cell and dimension of the anisotropic average
_AVERAGE_ORDER = 8


#: the cosine coordinates of the anisotropic tables: name -> (from mu, to mu)
_COSINE_MAPS = {"s": (similarity, cosine), "v": (blended, unblended)}


def anisotropic_average(parent: Table, alpha, ratio, order: int = _AVERAGE_ORDER):
    """(1 / pi) int f(wo) mu_o d wo of every channel f of the anisotropic table ``parent``'s
    interpolant at each (alpha, ratio): Gauss–Legendre in phi on every cell of |cos phi| and
    in mu on every cell of the cosine coordinate (mapped to mu at that phi: the coordinate is
    smooth in mu there, mu steep in it). The cosine coordinate depends on (alpha, ratio), so
    between nodes the average of the interpolant is not the interpolated average (a
    Kulla-Conty term's normalisation must match its E: ``docs/energy_models.md``). A table
    over the first two axes alone (a slice at one (alpha, ratio),
    ``tables.dielectric_slices``) is averaged at the (alpha, ratio) it was taken at. Returns
    ``(values, errors)``, ``(n, n_outputs)``; ``order`` Gauss points per cell and
    dimension."""
    axis, c_axis = parent.spec.axes[:2]
    to_coordinate, to_mu = _COSINE_MAPS[axis.name]
    x, w = roots_legendre(order)
    x, w = 0.5 * (x + 1.0), 0.5 * w
    phi_edges = np.arccos(c_axis.nodes())[::-1]
    phi_q = (phi_edges[:-1, None] + np.diff(phi_edges)[:, None] * x).ravel()
    w_phi = (np.diff(phi_edges)[:, None] * w).ravel() * (2.0 / np.pi)
    c_q = np.cos(phi_q)
    alpha, ratio = np.atleast_1d(alpha), np.atleast_1d(ratio)
    values = np.zeros((len(alpha), len(parent.spec.outputs)))
    errors = np.zeros_like(values)
    for k, (a, r) in enumerate(zip(alpha, ratio, strict=True)):
        a_phi = projected_alpha(c_q, max(a, ALPHA_FLOOR), r)  # (P,)
        mu_edges = to_mu(axis.nodes()[:, None], a_phi)  # (S, P)
        lo, width = mu_edges[:-1, None, :], np.diff(mu_edges, axis=0)[:, None, :]
        mu = lo + width * x[None, :, None]  # (S - 1, order, P)
        weight = (2.0 * mu * width * w[None, :, None] * w_phi).ravel()
        coords = [c.ravel() for c in np.broadcast_arrays(
            np.minimum(to_coordinate(mu, a_phi), 1.0), c_q, a, r)][:len(parent.spec.axes)]
        values[k] = weight @ parent(*coords)
        errors[k] = weight @ parent.error(*coords)
    return values, errors


def _anisotropic_average(spec, alpha, ratio, parent: Table):
    """The derived average table: ``anisotropic_average`` at its nodes (4x denser than the
    parent's in alpha and ratio)."""
    return anisotropic_average(parent, alpha, ratio)


#: sheen quadrature: geometric panels (ratio 4) towards each end where the integrand has
#: structure on small scales, this many levels deep (the finest panel is 4^-12 of the range)
SHEEN_LEVELS = 12
#: nodes processed at once by ``sheen_energy`` (memory)
_SHEEN_CHUNK = 8


def _graded(lo, hi, levels, ratio=4.0):
    """Panel edges on [lo, hi], geometric towards ``lo``: lo, lo + w ratio^-levels, ..., hi."""
    return np.concatenate([[lo], lo + (hi - lo) * ratio ** -np.arange(levels, -1.0, -1.0)])


def _panels(edges, order):
    """Gauss–Legendre nodes and weights of ``order`` points on every panel of ``edges``."""
    x, w = roots_legendre(order)
    a, b = edges[:-1, None], edges[1:, None]
    return (0.5 * (a + b) + 0.5 * (b - a) * x).ravel(), (0.5 * (b - a) * w).ravel()


def _sheen_rule(mu, r, p, order):
    """E(mu, r) of the sheen BRDF (c = a = 1) at one quadrature order, for 1-D arrays."""
    # wi = (cos t cos phi, cos t sin phi, sin t), wo = (s_o, 0, mu); by symmetry 2 x phi in
    # [0, pi], written psi = pi - phi. t: graded towards the horizon (D's peak, G's boundary
    # layer z_i ~ mu, exp(-p Lambda)) and towards the normal (sigma_i ~ sqrt(theta^2 + r^2)
    # has branch points at theta = +-i r); psi: graded towards wi = -wo's azimuth, where
    # |wo + wi| is smallest and h turns fastest.
    quarter = _graded(0.0, np.pi / 4, SHEEN_LEVELS)
    t, w_t = _panels(np.concatenate([quarter, (np.pi / 2 - quarter[::-1])[1:]]), order)
    psi, w_psi = _panels(_graded(0.0, np.pi, SHEEN_LEVELS), order)
    z_i, s_i = np.sin(t), np.cos(t)
    half2 = np.sin(0.5 * psi) ** 2
    z_o, r = mu[:, None], r[:, None]
    s_o = np.sqrt(1.0 - z_o * z_o)
    # eqs. 15, 17, 18: f cos_i = D G / (4 z_o) = D (1 - exp(-p Lambda)) z_i / (4 K) with
    # K = sigma_i z_o + sigma_o z_i and Lambda = K / (z_i z_o) (finite at z_o = 0)
    sigma_i = np.sqrt(s_i * s_i + r * r * z_i * z_i)
    sigma_o = np.sqrt(s_o * s_o + r * r * z_o * z_o)
    K = sigma_i * z_o + sigma_o * z_i
    with np.errstate(divide="ignore"):
        lam = K / (z_i * z_o)
    g = -np.expm1(-p * lam) * z_i / (4.0 * K)  # (n, T)
    # eq. 16 with h = s / |s|, s = wo + wi: D = r^3 |s|^4 / (pi (s_z^2 + r^2 (s_x^2 + s_y^2))^2)
    sz2 = ((z_o + z_i) ** 2)[..., None]
    horizontal = ((s_o - s_i) ** 2)[..., None] + 4.0 * (s_o * s_i)[..., None] * half2
    length2 = horizontal + sz2
    r3 = r[..., None]
    D = r3**3 * length2**2 / (np.pi * (sz2 + r3 * r3 * horizontal) ** 2)  # (n, T, P)
    return 2.0 * np.einsum("t,nt,ntp,p->n", w_t * s_i, g, D, w_psi)


def sheen_energy(mu, roughness, p: float = 1.0, order: int = 16):
    """Directional albedo E = int f(wi, wo) cos theta_i d wi of the sheen BRDF with c a = 1
    [Kutz2021, §6 eqs. 15-18] and its error estimate, by piecewise Gauss–Legendre quadrature
    in the direction of ``wi``.

    Parameters
    ----------
    mu : array_like in [0, 1]
        cos theta_o; 0 is the grazing limit mu -> 0, which is 1/2 for every roughness > 0.
    roughness : array_like in [0, 1]
        Sheen roughness r (not squared). At r = 0 the BRDF vanishes on the open hemisphere:
        E = 0, except at the corner (0, 0), which holds the grazing limit 1/2 of the mu = 0
        edge (``docs/sheen.md``).
    p : float
        Optical thickness p of the microflake layer (eq. 17), in (0, inf).
    order : int
        Gauss–Legendre points per panel and dimension.

    Returns
    -------
    value, error : ndarray
        E and |Q(order) - Q(2 order / 3)|, shaped like the broadcast inputs.
    """
    mu, r = np.broadcast_arrays(np.asarray(mu, dtype=np.float64),
                                np.asarray(roughness, dtype=np.float64))
    shape, mu, r = mu.shape, mu.ravel(), r.ravel()
    value, error = np.zeros(mu.size), np.zeros(mu.size)
    rough = np.flatnonzero(r > 0.0)
    low = max(2, (2 * order) // 3)
    for start in range(0, rough.size, _SHEEN_CHUNK):
        k = rough[start:start + _SHEEN_CHUNK]
        hi = _sheen_rule(mu[k], r[k], p, order)
        value[k], error[k] = hi, np.abs(hi - _sheen_rule(mu[k], r[k], p, low))
    value[(r == 0.0) & (mu == 0.0)] = 0.5
    return value.reshape(shape), error.reshape(shape)


def _sheen(spec, mu, roughness):
    value, error = sheen_energy(mu, roughness, order=spec.order)
    return value[:, None], error[:, None]


_MU = Axis("mu", 0.0, 1.0, 48, "log-linear", "cubic")
_ALPHA = Axis("alpha", 0.0, ALPHA_MAX, 48, "log-linear", "cubic")
_ALPHA_128 = Axis("alpha", 0.0, ALPHA_MAX, 128, "log-linear", "cubic")
# the scaling of the glossy multiple reflection changes with alpha faster than the energy
# (a narrow lobe's kernel): twice the nodes of the energy tables (docs/energy_models.md)
_ALPHA_MS = Axis("alpha", 0.0, ALPHA_MAX, 96, "log-linear", "cubic")
# near eta = 1 the energies have structure at eta - 1 ~ mu^2, alpha^2 (the Fresnel knee and
# the critical angle, ~sqrt(2 (eta - 1)), sweep the lobe): nodes log-spaced in eta - 1 down
# to 1e-4 (ASM's ior axis: 24 nodes to 4; the dielectric's: 32 nodes to 3, denser at
# eta - 1 ~ 0.05..0.3 where the energy seen from inside varies fastest)
_ETA = Axis("eta", 1.0, ETA_MAX, 32, "log-linear", "cubic", log_scale=0.2)
_ROUGHNESS = Axis("roughness", 0.0, 1.0, 48, "log-linear", "cubic")
_IOR = Axis("ior", 1.0, IOR_MAX, 24, "log-linear", "cubic", log_scale=0.3)
# near mu = 0 and r = 0 the sheen albedo is a function of mu / r (and has a mu ln mu term at
# mu = 0): log-spaced nodes down to ~1e-5 on both axes (below, ``lobes.Sheen`` maps small r
# onto the table by that similarity, ``docs/sheen.md``)
_SHEEN_MU = Axis("mu", 0.0, 1.0, 96, "log-linear", "cubic", log_scale=0.5)
_SHEEN_ROUGHNESS = Axis("roughness", 0.0, 1.0, 96, "log-linear", "cubic", log_scale=0.5)
# the anisotropic tables: s (``anisotropic_energy.similarity``), |cos phi| from the axis of
# alpha_max and ratio = alpha_min / alpha_max; near the smooth axis (|cos phi| -> 0) of a
# nearly one-dimensional surface (ratio -> 0) the energy is a function of |cos phi| / ratio:
# both log-spaced towards 0, 16 nodes each with log scale 0.3 (12 nodes at the default
# scale missed 1e-3 at |cos phi| ~ 0.01, ratio ~ 0.006: docs/tables.md)
_ANISOTROPIC_AXES = (Axis("s", 0.0, 1.0, 24, "log-linear", "cubic"),
                     Axis("cos_phi", 0.0, 1.0, 16, "log-linear", "cubic", log_scale=0.3),
                     Axis("alpha", 0.0, ALPHA_MAX, 24, "log-linear", "cubic"),
                     Axis("ratio", 0.0, 1.0, 16, "log-linear", "cubic", log_scale=0.3))
# the moments weigh the reflection by the ASM diffuse's 1 - L: a coarser grid than the
# conductor's (whose E is the whole albedo of a white metal)
_MOMENT_AXES = (Axis("v", 0.0, 1.0, 24, "log-linear", "cubic"),
                Axis("cos_phi", 0.0, 1.0, 9, "log-linear", "cubic"),
                Axis("alpha", 0.0, ALPHA_MAX, 16, "log-linear", "cubic"),
                Axis("ratio", 0.0, 1.0, 9, "log-linear", "cubic"))
_ANISOTROPIC_QUADRATURE = ("piecewise Gauss-Legendre over stretched microfacet normals "
                           "(scipy.special.roots_legendre), split at bisected horizon and "
                           "visibility roots; error = |Q(n) - Q(2n/3)|")
_SHEEN_QUADRATURE = ("piecewise Gauss-Legendre over (theta_i, phi_i) (scipy.special."
                     "roots_legendre), panels graded geometrically towards the horizon, the "
                     "normal and the azimuth of -wo; error = |Q(n) - Q(2n/3)|")


def _spec(name, axes, outputs, compute, description, depends=()):
    quadrature = _AVERAGE if depends else _QUADRATURE
    return TableSpec(name, axes, outputs, compute, quadrature, 20, depends, description)


SPECS: dict[str, TableSpec] = {s.name: s for s in [
    _spec("ggx_conductor", (Axis("mu", 0.0, 1.0, 128, "log-linear", "cubic"), _ALPHA_128), ("E",),
          _conductor,
          "directional albedo E(mu, alpha) of a GGX conductor with F = 1 (height-correlated "
          "Smith)"),
    _spec("ggx_conductor_avg", (_ALPHA_128,), ("E_avg",), _average,
          "E_avg(alpha) = 2 int E(mu, alpha) mu dmu", depends=("ggx_conductor",)),
    _spec("ggx_dielectric_outside", (_MU, _ALPHA, _ETA), ("E_R", "E_T"), _dielectric_outside,
          "reflected and transmitted energy of a rough dielectric interface seen from the "
          "less dense side, relative index eta >= 1"),
    _spec("ggx_dielectric_inside", (_MU, _ALPHA, _ETA), ("E_R", "E_T"), _dielectric_inside,
          "the same seen from the dense side: relative index 1 / eta"),
    _spec("ggx_dielectric_outside_avg", (_ALPHA, _ETA), ("E_R_avg", "E_T_avg"), _average,
          "mu-averages of ggx_dielectric_outside", depends=("ggx_dielectric_outside",)),
    _spec("ggx_dielectric_inside_avg", (_ALPHA, _ETA), ("E_R_avg", "E_T_avg"), _average,
          "mu-averages of ggx_dielectric_inside", depends=("ggx_dielectric_inside",)),
    _spec("ggx_dielectric_ms_reflection", (_MU, _ALPHA_MS, _ETA), ("a",), _ms_reflection,
          "a(mu, alpha, eta) with a(mu_o) int D G2 / (4 mu_o mu_i) a(mu_i) mu_i d wi = "
          "1 - E_R(mu_o) - E_T(mu_o) of ggx_dielectric_outside (the F = 1 GGX reflection at "
          "alpha, symmetrically scaled): the shape of lobes.DielectricMultipleReflection",
          depends=("ggx_dielectric_outside",)),
    _spec("asm_diffuse_L", (_MU, _ROUGHNESS, _IOR), ("L",), _asm_lobe_integral,
          "ASM lobe integral L(mu, roughness, ior) of the dielectric specular reflection "
          "(alpha = roughness^2, exact Fresnel): [Kutz2021, §1.1 eq. 1]"),
    _spec("asm_diffuse_T", (_ROUGHNESS, _IOR), ("T",), _average,
          "ASM total integral T = (1/pi) int L dsigma = 2 int L mu dmu",
          depends=("asm_diffuse_L",)),
    TableSpec("ggx_conductor_anisotropic", _ANISOTROPIC_AXES,
              ("E",), _anisotropic_conductor, _ANISOTROPIC_QUADRATURE, 12, (),
              "directional albedo E(wo) of an anisotropic GGX conductor with F = 1 "
              "(height-correlated Smith) at alpha_x = alpha >= alpha_y = ratio alpha, wo at "
              "azimuth phi from the x axis, mu = cosine(s, projected alpha)",
              check_tol=ANISOTROPIC_CHECK_TOL),
    TableSpec("ggx_conductor_anisotropic_avg",
              (Axis("alpha", 0.0, ALPHA_MAX, 96, "log-linear", "cubic"),
               Axis("ratio", 0.0, 1.0, 48, "log-linear", "cubic")),
              ("E_avg",), _anisotropic_average, _AVERAGE, 20, ("ggx_conductor_anisotropic",),
              "E_avg(alpha, ratio) = (1/pi) int E(wo) mu_o d wo"),
    TableSpec("ggx_reflection_moments", _MOMENT_AXES,
              tuple(f"M_{k}" for k in range(MOMENT_DEGREE + 1)), _reflection_moments,
              _ANISOTROPIC_QUADRATURE, 12, (),
              "Fresnel moments M_k = int D_wo(m) P_k(2 wo.m - 1) G2 / G1 dm of an anisotropic "
              "GGX reflection (P_k Legendre): a dielectric reflects sum_k a_k M_k with a_k "
              "the Legendre coefficients of its Fresnel; axes as ggx_conductor_anisotropic",
              checked=_fresnel_combinations, check_tol=MOMENTS_CHECK_TOL),
    TableSpec("sheen_albedo", (_SHEEN_MU, _SHEEN_ROUGHNESS), ("E",), _sheen, _SHEEN_QUADRATURE,
              16, (), "directional albedo E(mu, r) = int f cos theta_i d wi of the sheen BRDF "
              "with c = a = p = 1: [Kutz2021, §6 eqs. 15-18]"),
]}
