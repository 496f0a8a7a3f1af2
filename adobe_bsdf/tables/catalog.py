"""The declared tables: every energy table the library ships, with its node function.

| name | axes | outputs | source |
|---|---|---|---|
| ``ggx_conductor`` | mu, alpha | E | Kulla & Conty 2017; seed ``000`` §1.2 |
| ``ggx_conductor_avg`` | alpha | E_avg | the mu-average 2 int E mu dmu of the above |
| ``ggx_dielectric_outside`` | mu, alpha, eta | E_R, E_T | seed ``000`` §1.2, light side |
| ``ggx_dielectric_inside`` | mu, alpha, eta | E_R, E_T | the same from the dense side (1 / eta) |
| ``ggx_dielectric_*_avg`` | alpha, eta | E_R_avg, E_T_avg | mu-averages of the two above |
| ``asm_diffuse_L`` | mu, roughness, ior | L | seed ``000`` §1.1 eq. 1, lobe integral L |
| ``asm_diffuse_T`` | roughness, ior | T | seed ``000`` §1.1 eq. 1, total integral T |

Node values come from ``energy.ggx_energy`` (piecewise Gauss–Legendre, error estimate per
node); roughness 0 is the smooth interface in closed form. Averages are not integrated
afresh: they are the exact average of the mu-interpolant of their parent table, so that a
Kulla–Conty or ASM diffuse term built from the interpolated tables integrates to exactly the
energy it is meant to restore (``docs/tables.md``).
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf.fresnel import _dielectric
from adobe_bsdf.tables.energy import ggx_energy
from adobe_bsdf.tables.table import Axis, Table, TableSpec

__all__ = ["SPECS", "ETA_MAX", "IOR_MAX", "ALPHA_MAX"]

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


_MU = Axis("mu", 0.0, 1.0, 48, "log-linear", "cubic")
_ALPHA = Axis("alpha", 0.0, ALPHA_MAX, 48, "log-linear", "cubic")
_ALPHA_128 = Axis("alpha", 0.0, ALPHA_MAX, 128, "log-linear", "cubic")
# near eta = 1 the energies have structure at eta - 1 ~ mu^2, alpha^2 (the Fresnel knee and
# the critical angle, ~sqrt(2 (eta - 1)), sweep the lobe): nodes log-spaced in eta - 1 down
# to 1e-4 (ASM's ior axis: 24 nodes to 4; the dielectric's: 32 nodes to 3, denser at
# eta - 1 ~ 0.05..0.3 where the energy seen from inside varies fastest)
_ETA = Axis("eta", 1.0, ETA_MAX, 32, "log-linear", "cubic", log_scale=0.2)
_ROUGHNESS = Axis("roughness", 0.0, 1.0, 48, "log-linear", "cubic")
_IOR = Axis("ior", 1.0, IOR_MAX, 24, "log-linear", "cubic", log_scale=0.3)


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
    _spec("asm_diffuse_L", (_MU, _ROUGHNESS, _IOR), ("L",), _asm_lobe_integral,
          "ASM lobe integral L(mu, roughness, ior) of the dielectric specular reflection "
          "(alpha = roughness^2, exact Fresnel): seed 000 §1.1 eq. 1"),
    _spec("asm_diffuse_T", (_ROUGHNESS, _IOR), ("T",), _average,
          "ASM total integral T = (1/pi) int L dsigma = 2 int L mu dmu",
          depends=("asm_diffuse_L",)),
]}
