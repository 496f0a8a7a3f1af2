"""Table lookups of single-scattering energy for lobes: the tables' isotropic alpha, the F = 1
conductor albedo and the dielectric's E_R + E_T from either side (``adobe_bsdf.tables``)."""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params, tables
from adobe_bsdf.microfacet import GGX

__all__ = ["table_alpha", "conductor_energy", "dielectric_energy", "sides", "checked_ratio"]


def table_alpha(distribution: GGX) -> np.ndarray:
    """The isotropic alpha of the tables: sqrt(alpha_x alpha_y), 0 where smooth; checked to
    lie within the tables' range."""
    d = distribution
    alpha = np.where(d.smooth, 0.0, np.sqrt(d.alpha_x * d.alpha_y))
    return _params.real("sqrt(alpha_x alpha_y)", alpha, 0.0, tables.ALPHA_MAX)


def grey(value):
    """A grey value ``(...)`` as a colour ``(..., 3)`` view; None stays None."""
    return None if value is None else np.broadcast_to(value[..., None], value.shape + (3,))


def conductor_energy(distribution: GGX, wo, with_error: bool = False):
    """``(E, error)``: single-scattering albedo E(mu_o) (F = 1), 0 below the surface, and
    its carried node error (None unless ``with_error``)."""
    table = tables.get("ggx_conductor")
    alpha = table_alpha(distribution)
    mu = np.maximum(wo[..., 2], 0.0)
    up = wo[..., 2] > 0.0
    E = np.where(up, table(mu, alpha)[..., 0], 0.0)
    if not with_error:
        return E, None
    return E, np.where(up, table.error(mu, alpha)[..., 0], 0.0)


def sides(eta):
    """(eta >= 1, index ratio dense / light)."""
    light_above = eta >= 1.0
    return light_above, np.where(light_above, eta, 1.0 / eta)


def checked_ratio(eta):
    """max(eta, 1/eta), checked to lie within the dielectric tables' range."""
    return _params.real("max(eta, 1/eta)", sides(eta)[1], 1.0, tables.ETA_MAX)


def dielectric_energy(eta, distribution: GGX, wo, with_error: bool = False):
    """``(E, error)``: E_R + E_T of a rough interface seen from ``wo`` (either side), 1 where
    the interface is smooth or index-matched, and the carried node error (None unless
    ``with_error``)."""
    alpha = table_alpha(distribution)
    light_above = sides(eta)[0]
    ratio = checked_ratio(eta)
    mu = np.abs(wo[..., 2])
    on_light = (wo[..., 2] > 0.0) == light_above
    total, error = 0.0, 0.0
    for name, here in (("ggx_dielectric_outside", on_light),
                       ("ggx_dielectric_inside", ~on_light)):
        t = tables.get(name)
        total = total + np.where(here, t(mu, alpha, ratio).sum(-1), 0.0)
        if with_error:
            error = error + np.where(here, t.error(mu, alpha, ratio).sum(-1), 0.0)
    exact = (distribution.smooth | (eta == 1.0)) & (wo[..., 2] != 0.0)
    if not with_error:
        return np.where(exact, 1.0, total), None
    return np.where(exact, 1.0, total), np.where(exact, 0.0, error)
