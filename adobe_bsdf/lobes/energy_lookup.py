"""Table lookups of single-scattering energy for lobes: the tables' isotropic alpha, the F = 1
conductor albedo and the dielectric's E_R + E_T from either side (``adobe_bsdf.tables``)."""

from __future__ import annotations

import functools

import numpy as np

from adobe_bsdf import _params, tables
from adobe_bsdf.microfacet import GGX

__all__ = ["table_alpha", "lookup", "grey", "conductor_energy", "dielectric_energy", "sides",
           "checked_ratio"]


def table_alpha(distribution: GGX) -> np.ndarray:
    """The isotropic alpha of the tables: sqrt(alpha_x alpha_y), 0 where smooth; checked to
    lie within the tables' range. The tables hold GGX energy: other distributions raise."""
    d = distribution
    if not isinstance(d, GGX):
        raise ValueError(f"distribution = {d!r}: the energy tables hold GGX only (allowed: "
                         "a GGX distribution; use albedo method 'quadrature' or 'mc')")
    alpha = np.where(d.smooth, 0.0, np.sqrt(d.alpha_x * d.alpha_y))
    return _params.real("sqrt(alpha_x alpha_y)", alpha, 0.0, tables.ALPHA_MAX)


def grey(value):
    """A grey value ``(...)`` as a colour ``(..., 3)`` view; None stays None."""
    return None if value is None else np.broadcast_to(value[..., None], value.shape + (3,))


def lookup(name: str, mu, with_error: bool = False, **params):
    """``(value, error)`` of table ``name`` (summed over its output channels) at
    ``mu`` and its other axes' ``params`` (in the table's axis order); error None unless
    ``with_error``. Scalar ``params`` use the table fixed at them (``Table.fix``, cached):
    the same interpolant at 4 gathers per lookup."""
    if all(np.ndim(v) == 0 for v in params.values()):
        table, coords = _fixed(name, **{k: float(v) for k, v in params.items()}), (mu,)
    else:
        table, coords = tables.get(name), (mu, *params.values())
    value = table(*coords).sum(-1)
    return value, (table.error(*coords).sum(-1) if with_error else None)


@functools.lru_cache(maxsize=512)
def _fixed(name: str, **fixed):
    return tables.get(name).fix(**fixed)


def _where(mask, value, fill):
    return None if value is None else np.where(mask, value, fill)


def conductor_energy(distribution: GGX, wo, with_error: bool = False):
    """``(E, error)``: single-scattering albedo E(mu_o) (F = 1), 0 below the surface, and
    its carried node error (None unless ``with_error``)."""
    up = wo[..., 2] > 0.0
    E, error = lookup("ggx_conductor", np.maximum(wo[..., 2], 0.0), with_error,
                      alpha=table_alpha(distribution))
    return np.where(up, E, 0.0), _where(up, error, 0.0)


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
    ``with_error``). Each side's table is looked up only for the directions on that side
    (where the parameters are scalars)."""
    alpha = table_alpha(distribution)
    ratio = checked_ratio(eta)
    mu = np.abs(wo[..., 2])
    on_light = (wo[..., 2] > 0.0) == sides(eta)[0]
    exact = (distribution.smooth | (eta == 1.0)) & (wo[..., 2] != 0.0)
    shape = np.broadcast_shapes(mu.shape, alpha.shape, ratio.shape)
    total = np.zeros(shape)
    error = np.zeros(shape) if with_error else None
    scalar = alpha.ndim == 0 and ratio.ndim == 0 and mu.shape == shape and mu.ndim > 0
    for name, here in (("ggx_dielectric_outside", on_light),
                       ("ggx_dielectric_inside", ~on_light)):
        if scalar:  # only the directions on this side
            index = np.nonzero(here)
            E, err = lookup(name, mu[index], with_error, alpha=alpha, eta=ratio)
            total[index] = E
            if with_error:
                error[index] = err
        else:
            E, err = lookup(name, mu, with_error, alpha=alpha, eta=ratio)
            total = np.where(here, E, total)
            error = _where(here, err, error)
    return np.where(exact, 1.0, total), _where(exact, 0.0, error)
