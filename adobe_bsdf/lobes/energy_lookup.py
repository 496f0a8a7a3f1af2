"""Table lookups of single-scattering energy for lobes: the tables' isotropic alpha, the F = 1
conductor albedo and the dielectric's E_R + E_T from either side (``adobe_bsdf.tables``)."""

from __future__ import annotations

import functools

import numpy as np

from adobe_bsdf import tables
from adobe_bsdf.microfacet import GGX

__all__ = ["table_alpha", "lookup", "grey", "conductor_energy", "dielectric_energy", "sides",
           "checked_ratio"]


#: the GGX energy tables with an alpha and with an eta axis, for messages where the lookup's
#: table is not named
_ALPHA_TABLES = ("the GGX energy tables (ggx_conductor, ggx_dielectric_outside, "
                 "ggx_dielectric_inside and their averages)")
_ETA_TABLES = ("the GGX dielectric energy tables (ggx_dielectric_outside, "
               "ggx_dielectric_inside and their averages)")
#: what a user can do where a lobe's parameters are outside its tables
_INSTEAD = ("for an albedo, use method 'quadrature' or 'mc', which need no tables (a lobe "
            "built on the tables, as the Kulla-Conty terms, cannot be used there)")


def _tables(table: str | None, default: str) -> str:
    if table is None:
        return default
    return f"tables {table}" if " and " in table else f"table {table}"


def table_alpha(distribution: GGX, table: str | None = None) -> np.ndarray:
    """The isotropic alpha of the tables: sqrt(alpha_x alpha_y), 0 where smooth; checked to
    lie within the tables' range (``ValueError`` naming ``alpha_x``, ``alpha_y``, the table
    ``table``, default all GGX tables, and the range). The tables hold GGX energy: other
    distributions raise."""
    d = distribution
    if not isinstance(d, GGX):
        raise ValueError(f"distribution = {d!r}: the energy tables hold GGX only (allowed: "
                         "a GGX distribution; use albedo method 'quadrature' or 'mc')")
    alpha = np.where(d.smooth, 0.0, np.sqrt(d.alpha_x * d.alpha_y))
    bad = ~(alpha <= tables.ALPHA_MAX)
    if np.any(bad):
        def first(a):
            return np.broadcast_to(a, bad.shape)[bad].flat[0].item()
        raise ValueError(f"alpha_x = {first(d.alpha_x)!r}, alpha_y = {first(d.alpha_y)!r} "
                         f"give the coordinate alpha = sqrt(alpha_x alpha_y) = "
                         f"{first(alpha)!r}, outside [0, {tables.ALPHA_MAX:g}], the range of "
                         f"{_tables(table, _ALPHA_TABLES)}: {_INSTEAD}")
    return alpha


def grey(value):
    """A grey value ``(...)`` as a colour ``(..., 3)`` view; None stays None."""
    return None if value is None else np.broadcast_to(value[..., None], value.shape + (3,))


def lookup(name: str, mu, with_error: bool = False, **params):
    """``(value, error)`` of table ``name`` (summed over its output channels) at
    ``mu`` and its other axes' ``params`` (in the table's axis order); error None unless
    ``with_error``. Scalar ``params`` use the table fixed at them (``Table.fix``, cached):
    the same interpolant at 4 gathers per lookup."""
    mu = np.minimum(mu, 1.0)  # |w| = 1 within rounding: a cosine may exceed 1 by an ulp
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
                      alpha=table_alpha(distribution, "ggx_conductor"))
    return np.where(up, E, 0.0), _where(up, error, 0.0)


def sides(eta):
    """(eta >= 1, index ratio dense / light)."""
    light_above = eta >= 1.0
    return light_above, np.where(light_above, eta, 1.0 / eta)


_COLOURS = ("red", "green", "blue")


def checked_ratio(eta, table: str | None = None, dispersion=None):
    """max(eta, 1/eta), checked to lie within the dielectric tables' range [1, ETA_MAX]
    (``ValueError`` naming ``eta``, the table ``table``, default all GGX tables, and the
    range). With ``dispersion`` (a ``Dispersive``'s, ``eta`` then its channel indices
    ``(..., 3)``) the message names the channel, the index and the dispersion."""
    eta = np.asarray(eta, dtype=np.float64)
    ratio = sides(eta)[1]
    bad = ~(ratio <= tables.ETA_MAX)
    if not np.any(bad):
        return ratio
    top = tables.ETA_MAX
    where = (f"outside [{1 / top:.4g}, {top:g}] (index ratio max(eta, 1/eta) in [1, "
             f"{top:g}]), the range of {_tables(table, _ETA_TABLES)}")
    if dispersion is None:
        raise ValueError(f"eta = {eta[bad].flat[0].item()!r} is {where}: {_INSTEAD}")
    index = tuple(int(i) for i in np.argwhere(bad)[0])
    channels = ", ".join(f"{x:.6g}" for x in eta[index[:-1]])
    d = np.broadcast_to(dispersion, eta.shape[:-1])[index[:-1]].item()
    raise ValueError(f"dispersion = {d!r} about the d-line index (eta: a material's ior, "
                     "relative to a coat above it) spreads the channel indices by Cauchy's "
                     "equation to "
                     f"eta_c = ({channels}): the {_COLOURS[index[-1]]} channel's "
                     f"{eta[index]:.6g} is {where}: lower ior or dispersion; {_INSTEAD}")


def dielectric_energy(eta, distribution: GGX, wo, with_error: bool = False):
    """``(E, error)``: E_R + E_T of a rough interface seen from ``wo`` (either side), 1 where
    the interface is smooth or index-matched, and the carried node error (None unless
    ``with_error``). Each side's table is looked up only for the directions on that side
    (where the parameters are scalars)."""
    names = "ggx_dielectric_outside and ggx_dielectric_inside"
    alpha = table_alpha(distribution, names)
    ratio = checked_ratio(eta, names)
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
    # in the tangent plane (cos = 0) nothing is reflected or transmitted (docs/conventions.md)
    grazing = wo[..., 2] == 0.0
    total = np.where(exact, 1.0, np.where(grazing, 0.0, total))
    return total, None if error is None else np.where(exact | grazing, 0.0, error)
