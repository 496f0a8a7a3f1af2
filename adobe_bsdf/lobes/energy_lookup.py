"""Table lookups of single-scattering energy for lobes: the tables' isotropic alpha, the F = 1
conductor albedo and the dielectric's E_R + E_T from either side (``adobe_bsdf.tables``).

Where a dielectric is nearly index-matched and the view grazing (``near_matched``) the energy
has a boundary layer no tensor-product table resolves: it depends on mu / |eta - 1| and on
mu / sqrt|eta - 1|, and the tables miss it by up to 0.5. There the energy is integrated
directly by the tables' own node quadrature (``tables.energy.ggx_energy``, about 5 ms per
distinct direction), so every table path stays within the tables' stated error (docs/tables.md).
"""

from __future__ import annotations

import dataclasses
import functools
import sys
import threading
import warnings

import numpy as np

from adobe_bsdf import config, tables
from adobe_bsdf._channels import pick
from adobe_bsdf.fresnel import _dielectric
from adobe_bsdf.microfacet import GGX
from adobe_bsdf.tables import dielectric_grid
from adobe_bsdf.tables.anisotropic_energy import (
    blended,
    fresnel_coefficients,
    projected_alpha,
    similarity,
)
from adobe_bsdf.tables.catalog import anisotropic_average
from adobe_bsdf.tables.dielectric_slices import dielectric_slice
from adobe_bsdf.tables.energy import ggx_energy
from adobe_bsdf.tables.table import Table

__all__ = ["table_alpha", "lookup", "grey", "conductor_energy", "conductor_average",
           "is_anisotropic", "anisotropic_coordinates", "anisotropic_reflection",
           "anisotropic_reflection_average",
           "dielectric_energy", "sides", "slice_source", "slice_energy", "slice_average",
           "checked_ratio", "reflected_energy", "near_matched", "passes_through",
           "MIN_TRANSMISSION_WIDTH", "MATCHED_ETA", "MATCHED_MU", "ISOTROPIC_FALLBACK_ERROR",
           "AnisotropicEnergyWarning", "within_tables", "BEYOND_TABLES_ERROR",
           "EnergyRangeWarning"]

#: narrowest transmitted lobe (radians) kept as a lobe: a rough interface whose refraction
#: is narrower passes light straight through (``passes_through``, docs/conventions.md)
MIN_TRANSMISSION_WIDTH = 1e-12
#: below |eta - 1| = MATCHED_ETA (index ratio) and cos theta_o = MATCHED_MU the dielectric
#: energy is integrated, not looked up (``near_matched``; the bound measured in
#: tests/test_near_matched.py)
MATCHED_ETA = 1e-2
MATCHED_MU = 0.05
#: Gauss-Legendre order of the direct integration: 7.5e-6 from order 20 over the region
#: (400 random points), ~5 ms per direction (~8 ms with the error estimate, order 8)
_ORDER = 12
#: below this alpha the band's energy is the smooth interface's (``_integrated``)
_ALPHA_SMOOTH = 1e-12


#: the isotropic tables at sqrt(alpha_x alpha_y) against the stretched node quadrature: the
#: largest |E_R + E_T| error at held-out anisotropic interfaces (alpha_x in [0.02, 1], any
#: ratio, ior 1.01-3) seen from the light and from the dense side, measured by
#: ``benchmarks.anisotropic_candidates`` (docs/anisotropic_candidates_measured.md)
ISOTROPIC_FALLBACK_ERROR = (0.18, 0.37)
_FALLBACK_WARNED = threading.Event()


class AnisotropicEnergyWarning(UserWarning):
    """An anisotropic dielectric's energy read from the isotropic tables (the default
    ``anisotropic_energy = "table"``): its Kulla–Conty terms restore the energy of another
    roughness, so its white furnace misses by up to ``ISOTROPIC_FALLBACK_ERROR``."""


def _warn_isotropic_fallback() -> None:
    """``AnisotropicEnergyWarning``, once per process."""
    if _FALLBACK_WARNED.is_set():
        return
    _FALLBACK_WARNED.set()
    light, dense = ISOTROPIC_FALLBACK_ERROR
    warnings.warn(AnisotropicEnergyWarning(
        "an anisotropic rough dielectric's energy (E_R + E_T, which its multiple-scattering "
        "term restores) is read from the isotropic tables at sqrt(alpha_x alpha_y): its white "
        f"furnace misses by up to {light:.2g} seen from the less dense side and {dense:.2g} "
        "from the dense side (measured: docs/anisotropic_candidates_measured.md). "
        "ab.config.options(anisotropic_energy='exact') computes the lobe's own slice "
        "(seconds per distinct interface; within 2e-3)"), stacklevel=_outside_package())


#: the white furnace of a dispersive channel whose index lies beyond the tables (an ior near
#: 3 spread by dispersion: 3.0915 at ior 3, dispersion 1), its Kulla–Conty term reading them
#: at the range's end: the largest |E(eta_c) - E(3)| (E = E_R + E_T, the stretched node
#: quadrature) over alpha_x in [0.02, 2], ratios 1, 0.1 and 0, every view and both sides at
#: eta_c = 3.0915, measured by ``benchmarks.anisotropic_grid``
#: (docs/anisotropic_grid_measured.md, "Dispersive channels beyond the tables")
BEYOND_TABLES_ERROR = 0.016
_BEYOND_WARNED = threading.Event()


class EnergyRangeWarning(UserWarning):
    """A dispersive channel's index beyond the energy tables: its Kulla–Conty term reads
    them at the range's end, so its white furnace misses by up to ``BEYOND_TABLES_ERROR``."""


def within_tables(eta_c, dispersion) -> np.ndarray:
    """The channel indices ``eta_c`` ``(..., 3)`` of a dispersive interface (``dispersion``
    its own), those whose index ratio max(eta, 1/eta) exceeds ``tables.ETA_MAX`` moved to
    the range's end on their side (``EnergyRangeWarning`` once per process, naming the
    furthest channel, its index and the dispersion): the indices its energy terms read."""
    eta_c = np.asarray(eta_c, dtype=np.float64)
    top = tables.ETA_MAX
    beyond = (eta_c > top) | (eta_c < 1.0 / top)
    if not np.any(beyond):
        return eta_c
    if not _BEYOND_WARNED.is_set():
        _BEYOND_WARNED.set()
        index = np.unravel_index(np.argmax(np.abs(np.log(eta_c))), eta_c.shape)  # furthest
        d = np.broadcast_to(dispersion, eta_c.shape[:-1])[index[:-1]].item()
        warnings.warn(EnergyRangeWarning(
            f"dispersion = {d!r} spreads the {_COLOURS[index[-1]]} channel's index to "
            f"{eta_c[index]:.6g}, beyond the energy tables' [{1 / top:.4g}, {top:g}]: its "
            f"multiple-scattering term reads them at {1 / top if eta_c[index] < 1 else top:.4g},"
            f" so its white furnace misses by up to {BEYOND_TABLES_ERROR:g} (measured: "
            "docs/anisotropic_grid_measured.md); lower ior or dispersion to stay within them"),
            stacklevel=_outside_package())
    return np.clip(eta_c, 1.0 / top, top)


def _outside_package() -> int:
    """The ``stacklevel`` of the first caller outside ``adobe_bsdf`` (where the user called
    the library), counted from ``_warn_isotropic_fallback``'s ``warnings.warn``."""
    frame, level = sys._getframe(2), 2
    while frame is not None and frame.f_globals.get("__name__", "").startswith("adobe_bsdf"):
        frame, level = frame.f_back, level + 1
    return level


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
    alpha = pick(d.smooth, 0.0, np.sqrt(d.alpha_x * d.alpha_y))
    bad = ~(alpha <= tables.ALPHA_MAX)
    if np.any(bad):
        def first(a):
            return np.broadcast_to(a, bad.shape)[bad].flat[0].item()
        raise ValueError(f"alpha_x = {first(d.alpha_x)!r}, alpha_y = {first(d.alpha_y)!r} "
                         f"give the coordinate alpha = sqrt(alpha_x alpha_y) = "
                         f"{first(alpha)!r}, outside [0, {tables.ALPHA_MAX:g}], the range of "
                         f"{_tables(table, _ALPHA_TABLES)}: {_INSTEAD}")
    return alpha


def passes_through(eta, microfacets) -> np.ndarray:
    """Where a dielectric of index ``eta`` over ``microfacets`` is a pass-through (a delta
    from ``wo`` to ``-wo``): ``eta == 1`` (no interface), or a rough interface whose
    transmitted lobe, about alpha_max |eta - 1| radians wide in its widest direction, is
    narrower than ``MIN_TRANSMISSION_WIDTH``.

    Such a lobe lies within 1e4 roundings of a float64 direction (~1e-16) of ``-wo`` in every
    direction; at |eta - 1| of a few ulps the half vector of a sampled pair cancels to 0 and
    ``eval`` overflows. The collapse drops the reflection, F <= ((eta - 1) / 2)^2 <=
    (MIN_TRANSMISSION_WIDTH / (2 ALPHA_MIN))^2 = 2.5e-9 of the energy, and the lobe's width;
    the transmitted energy of the rough model tends to the pass-through's linearly in
    |eta - 1| (measured in tests/test_pass_through.py).
    """
    narrow = microfacets.alpha_max * np.abs(eta - 1.0) < MIN_TRANSMISSION_WIDTH
    return (eta == 1.0) | (~microfacets.smooth & narrow)


def near_matched(ratio, mu) -> np.ndarray:
    """Where the dielectric tables are not used: index ratio max(eta, 1/eta) within
    ``MATCHED_ETA`` of 1 and 0 < cos theta_o < ``MATCHED_MU``.

    There a rough interface's energy has boundary layers in the (mu, eta) corner: refraction
    through a facet turns a grazing ``wo`` by ~|eta - 1|, so whether the refracted direction
    clears the horizon depends on mu / |eta - 1|, and Fresnel reflection at facets seen under
    cos < sqrt(2 |eta - 1|) on mu / sqrt|eta - 1|. The energy at cos 1e-8 goes from 0.50
    (|eta - 1| = 1e-12) to 0.92 (1e-7) to 1.00 (1e-3) for alpha = 0.3; the tables, whose first
    eta node is 1 + 9e-5, returned 0.50 throughout.
    """
    close = ratio - 1.0 < MATCHED_ETA
    if np.ndim(close) == 0 and not close:  # one index, not nearly matched: nowhere
        return np.zeros(np.shape(mu), dtype=bool)
    return close & (mu > 0.0) & (mu < MATCHED_MU)


def _integrated(mask, mu, alpha, eta_seen, with_error):
    """``(E_R, E_T, error_R, error_T)`` at the elements ``mask`` of the broadcast inputs:
    ``ggx_energy`` where rough (errors 0 unless ``with_error``), the smooth interface's
    Fresnel reflectance in closed form where alpha < ``_ALPHA_SMOOTH`` (the rough energy
    differs from it only at cosines within ~10 alpha of 0, and the quadrature's change of
    variable loses accuracy below it)."""
    arrays = np.broadcast_arrays(mu, alpha, eta_seen, mask)
    # each distinct (mu, alpha, eta) once: a Monte-Carlo batch repeats its wo
    rows, inverse = np.unique(np.stack([a[arrays[-1]] for a in arrays[:-1]], -1), axis=0,
                              return_inverse=True)
    mu, alpha, eta_seen = rows.T
    rough = alpha >= _ALPHA_SMOOTH
    out = np.zeros((4,) + mu.shape)
    e = ggx_energy(mu[rough], alpha[rough], eta_seen[rough], _ORDER, estimate=with_error)
    out[:, rough] = e
    F = _dielectric(mu[~rough], eta_seen[~rough])
    out[0, ~rough], out[1, ~rough] = F, 1.0 - F
    return tuple(out[:, inverse.ravel()])


def grey(value):
    """A grey value ``(...)`` as a colour ``(..., 3)`` view; None stays None."""
    return None if value is None else np.broadcast_to(value[..., None], value.shape + (3,))


def lookup(name: str, mu, with_error: bool = False, channel: int | None = None, **params):
    """``(value, error)`` of table ``name`` (summed over its output channels, or output
    ``channel`` alone) at ``mu`` and its other axes' ``params`` (in the table's axis order);
    error None unless ``with_error``. The scalar ``params`` are fixed (``Table.fix``, cached):
    the same interpolant at 4 gathers per lookup and remaining cubic axis (4^d with every
    axis), equal to the full lookup to rounding."""
    if np.max(mu, initial=0.0) > 1.0:  # |w| = 1 within rounding: a cosine may exceed 1
        mu = np.minimum(mu, 1.0)
    fixed = {k: float(v) for k, v in params.items() if np.ndim(v) == 0}
    if fixed:
        table = _fixed(name, channel, **fixed)
        coords = (mu, *(v for v in params.values() if np.ndim(v)))
        channel = None if channel is None else 0
    else:
        table, coords = tables.get(name), (mu, *params.values())

    def of_channel(error):
        if channel is None:
            return table.total(*coords, error=error)
        return (table.error if error else table)(*coords)[..., channel]

    return of_channel(False), (of_channel(True) if with_error else None)


@functools.lru_cache(maxsize=512)
def _fixed(name: str, channel: int | None, **fixed) -> Table:
    """Table ``name`` fixed at the scalar axes ``fixed``, its output ``channel`` alone
    (None: all)."""
    table = tables.get(name).fix(**fixed)
    if channel is None:
        return table
    keep = slice(channel, channel + 1)
    spec = dataclasses.replace(table.spec, outputs=table.spec.outputs[keep])
    return Table(spec, table.values[..., keep], table.errors[..., keep], table.meta)


def _where(mask, value, fill):
    return None if value is None else pick(mask, value, fill)


def is_anisotropic(distribution: GGX) -> np.ndarray:
    """Where ``distribution`` is rough with alpha_x != alpha_y: the anisotropic tables'
    domain (isotropic lobes read the isotropic tables unchanged). The tables hold GGX only:
    another distribution raises ``ValueError`` (``table_alpha``)."""
    d = distribution
    if not isinstance(d, GGX):
        table_alpha(d)  # raises
    return ~d.smooth & (d.alpha_x != d.alpha_y)


def _alpha_ratio(distribution: GGX):
    """(alpha, ratio) of the anisotropic tables for ``distribution``."""
    _, _, alpha, ratio = anisotropic_coordinates(distribution, _NORMAL)
    return alpha, ratio


_NORMAL = np.array([0.0, 0.0, 1.0])


def conductor_energy(distribution: GGX, wo, with_error: bool = False):
    """``(E, error)``: single-scattering albedo E(wo) (F = 1), 0 below the surface, and its
    carried node error (None unless ``with_error``). Isotropic lobes read "ggx_conductor";
    anisotropic ones "ggx_conductor_anisotropic" at wo's azimuth (``anisotropic_coordinates``).
    """
    d = distribution
    up = wo[..., 2] > 0.0
    aniso = is_anisotropic(d)
    if np.any(aniso):
        s, cos_phi, alpha_max, ratio = anisotropic_coordinates(d, wo)
        E, error = lookup("ggx_conductor_anisotropic", s, with_error, cos_phi=cos_phi,
                          alpha=alpha_max, ratio=ratio)
    if not np.all(aniso):
        mu = np.maximum(wo[..., 2], 0.0)
        E_i, error_i = lookup("ggx_conductor", mu, with_error,
                              alpha=table_alpha(d, "ggx_conductor"))
        if np.any(aniso):
            E, error = pick(aniso, E, E_i), _where(aniso, error, error_i)
        else:
            E, error = E_i, error_i
    return pick(up, E, 0.0), _where(up, error, 0.0)


def conductor_average(distribution: GGX):
    """E_avg = (1 / pi) int E(w) mu dw of the F = 1 conductor: "ggx_conductor_avg" where
    isotropic, "ggx_conductor_anisotropic_avg" where not."""
    d = distribution
    E_avg = tables.get("ggx_conductor_avg")(table_alpha(d, "ggx_conductor"))[..., 0]
    aniso = np.broadcast_to(is_anisotropic(d), np.shape(E_avg))
    if np.any(aniso):
        E_avg = pick(aniso, tables.get("ggx_conductor_anisotropic_avg")(
            *_alpha_ratio(d))[..., 0], E_avg)
    return E_avg


def anisotropic_reflection(distribution: GGX, reference: GGX, eta, wo,
                           with_error: bool = False):
    """``(Delta E_R, error)``: how much more the anisotropic GGX dielectric ``distribution``
    (seen from above, eta >= 1, exact Fresnel) reflects than the isotropic ``reference``,
    sum_k a_k (M_k(wo) - M_k,reference(wo)) of the Fresnel moments "ggx_reflection_moments"
    (0 below the surface). Added to the reference's own table the moments' interpolation
    errors largely cancel where the lobe is nearly isotropic, and vanish where it is."""
    E, error = _fresnel_moments(distribution, eta, wo, with_error)
    E_ref, error_ref = _fresnel_moments(reference, eta, wo, with_error)
    up = wo[..., 2] > 0.0
    return (pick(up, E - E_ref, 0.0),
            pick(up, error + error_ref, 0.0) if with_error else None)


def _fresnel_moments(distribution: GGX, eta, wo, with_error: bool):
    """sum_k a_k M_k(wo) of ``distribution`` under the Fresnel of ``eta``, and its node
    error (None unless ``with_error``). A single (alpha, ratio, eta) reads a cached
    ``_fresnel_slice``: the same interpolant, 16 gathers of one channel a lookup."""
    v, cos_phi, alpha, ratio = anisotropic_coordinates(distribution, wo, blend=True)
    if np.size(alpha) == 1 and np.size(eta) == 1:  # ratio has alpha's shape
        table = _fresnel_slice(float(alpha.flat[0]), float(ratio.flat[0]),
                               float(np.asarray(eta).flat[0]))
        return (table(v, cos_phi)[..., 0],
                table.error(v, cos_phi)[..., 0] if with_error else None)
    table = tables.get("ggx_reflection_moments")
    a = fresnel_coefficients(eta, len(table.spec.outputs) - 1)
    coords = (v, cos_phi, alpha, ratio)
    return (np.sum(a * table(*coords), -1),
            np.sum(np.abs(a) * table.error(*coords), -1) if with_error else None)


@functools.lru_cache(maxsize=256)
def _fresnel_slice(alpha: float, ratio: float, eta: float) -> Table:
    """"ggx_reflection_moments" held at (``alpha``, ``ratio``) (``Table.fix``) and its
    channels contracted with the Fresnel coefficients of ``eta``: a (v, cos_phi) table of
    sum_k a_k M_k, the same function as the full lookup (the interpolation is linear in the
    values and a tensor product), errors carried through |a_k|."""
    fixed = tables.get("ggx_reflection_moments").fix(alpha=alpha, ratio=ratio)
    a = fresnel_coefficients(eta, len(fixed.spec.outputs) - 1)
    spec = dataclasses.replace(fixed.spec, name=f"{fixed.spec.name}[eta={eta:g}]",
                               outputs=("E_R",))
    return Table(spec, fixed.values @ a[:, None], fixed.errors @ np.abs(a)[:, None],
                 fixed.meta)


def anisotropic_reflection_average(distribution: GGX, reference: GGX, eta):
    """(1 / pi) int Delta E_R(w) cos d w of ``anisotropic_reflection``: sum_k a_k of the
    moments' hemispherical averages, integrated from the interpolant at the lobes' own
    (alpha, ratio) (``tables.catalog.anisotropic_average``, ~0.1 s per distinct pair,
    cached), so that a diffuse normalised by it conserves exactly the energy its L leaves."""
    moments = _averages(distribution) - _averages(reference)
    return np.sum(fresnel_coefficients(eta, moments.shape[-1] - 1) * moments, -1)


def _averages(distribution: GGX) -> np.ndarray:
    """The moments' averages ``(..., K + 1)`` per element of ``distribution``."""
    alpha, ratio = _alpha_ratio(distribution)
    pairs = np.stack(np.broadcast_arrays(alpha, ratio), -1)
    unique, inverse = np.unique(pairs.reshape(-1, 2), axis=0, return_inverse=True)
    averages = np.array([_moment_averages(float(a), float(r)) for a, r in unique])
    return averages[inverse.ravel()].reshape(pairs.shape[:-1] + (-1,))


#: Gauss points per cell of the moments' averages at build time (within 1e-7 of 8 points,
#: a quarter of the cost: ~0.1 s per distinct (alpha, ratio))
_AVERAGE_ORDER = 4


@functools.lru_cache(maxsize=1024)
def _moment_averages(alpha: float, ratio: float) -> np.ndarray:
    return anisotropic_average(tables.get("ggx_reflection_moments"), alpha, ratio,
                               _AVERAGE_ORDER)[0][0]


def anisotropic_coordinates(distribution: GGX, w, blend: bool = False):
    """Coordinates (s, |cos phi|, alpha, ratio) of "ggx_conductor_anisotropic" for ``w``:
    alpha = max(alpha_x, alpha_y) (checked against the tables' range), ratio = min / max,
    phi the azimuth of ``w`` from the axis of alpha (0 at normal incidence, where E does not
    depend on it) and s the similarity coordinate of mu = |w_z| (``blend``: the blended
    coordinate v of the moments table instead)."""
    d = distribution
    alpha_x, alpha_y = np.broadcast_arrays(d.alpha_x, d.alpha_y)
    alpha = np.maximum(alpha_x, alpha_y)
    bad = ~(alpha <= tables.ALPHA_MAX)
    if np.any(bad):
        raise ValueError(f"alpha_x = {alpha_x[bad].flat[0].item()!r}, alpha_y = "
                         f"{alpha_y[bad].flat[0].item()!r}: max(alpha_x, alpha_y) is outside "
                         f"[0, {tables.ALPHA_MAX:g}], the range of table "
                         f"ggx_conductor_anisotropic: {_INSTEAD}")
    safe = pick(alpha > 0.0, alpha, 1.0)
    ratio = pick(alpha > 0.0, np.minimum(alpha_x, alpha_y) / safe, 1.0)
    cos_phi = _cos_phi(alpha_x >= alpha_y, w)
    mu = np.minimum(np.abs(w[..., 2]), 1.0)
    a_phi = projected_alpha(cos_phi, alpha, ratio)
    s = blended(mu, a_phi) if blend else similarity(mu, a_phi)
    return np.minimum(s, 1.0), cos_phi, alpha, ratio


def _cos_phi(x_rough, w):
    """|cos phi| of ``w``'s azimuth from the rough axis (x where ``x_rough``, else y); 1 at
    normal incidence."""
    x2, y2 = w[..., 0] ** 2, w[..., 1] ** 2
    along = (x2 if x_rough else y2) if np.ndim(x_rough) == 0 else pick(x_rough, x2, y2)
    horizontal = x2 + y2
    cos2 = np.divide(along, horizontal, where=horizontal > 0.0,
                     out=np.ones(np.broadcast_shapes(np.shape(along), horizontal.shape)))
    return np.sqrt(np.minimum(cos2, 1.0, out=cos2), out=cos2)


def slice_source(distribution: GGX) -> str:
    """Where a lobe over ``distribution`` built now reads an anisotropic dielectric's energy:
    "grid" (the ``config`` option ``anisotropic_energy``'s default "table", once the grid
    of slices is shipped: ``tables.dielectric_grid``), "exact" (the option "exact": the
    lobe's own slice, computed), or "" (the isotropic tables at sqrt(alpha_x alpha_y): the
    option "isotropic", or "table" without the grid; and where no element is anisotropic
    or the distribution is not GGX)."""
    mode = config.get_options().anisotropic_energy
    if (mode == "isotropic" or not isinstance(distribution, GGX)
            or not np.any(is_anisotropic(distribution))):
        return ""
    if mode == "table":
        return "grid" if dielectric_grid.shipped() else ""
    return "exact"


def _slice(alpha: float, ratio: float, eta: float, source: str, channel: str = "total"):
    """The slice of (``alpha``, ``ratio``, index ratio ``eta``) from ``source`` for
    ``channel`` ("total" or "reflection"): "grid" (``dielectric_grid.grid_slice``, or where
    the library does not read the grid, nearly one-dimensional interfaces, index ratios
    below its first and the E_R of nearly smooth interfaces (``dielectric_grid.interpolated``),
    the computed slice) or "exact" (``dielectric_slice``, computed once per process)."""
    if source == "grid":
        piece = dielectric_grid.grid_slice(alpha, ratio, eta, channel)
        if piece is not None:
            return piece
    return dielectric_slice(alpha, ratio, eta)


_SLICES = "ggx_dielectric_anisotropic (the slices)"


def _interface_slice(distribution: GGX, eta, source: str, channel: str = "total"):
    """The slice of one interface (scalar parameters) from ``source`` for ``channel``, None
    where it is isotropic; its coordinates checked as ``_slices`` checks them
    (``_interface``)."""
    alpha, ratio, index = _interface(float(distribution.alpha_x), float(distribution.alpha_y),
                                     bool(is_anisotropic(distribution)), float(eta))
    return None if alpha is None else _slice(alpha, ratio, index, source, channel)


@functools.lru_cache(maxsize=4096)
def _interface(alpha_x: float, alpha_y: float, anisotropic: bool, eta: float):
    """(alpha, ratio, index ratio) of one interface, or (None, None, None) where it is
    isotropic (checked: ``ValueError`` outside the tables, never kept)."""
    alpha, ratio = _alpha_ratio(GGX._new(alpha_x, alpha_y))
    index = checked_ratio(eta, _SLICES)
    if not anisotropic:
        return None, None, None
    return float(alpha), float(ratio), float(index)


def _slices(eta, distribution: GGX, shape, source: str, channel: str = "total"):
    """``(mask, slice)`` pairs covering the anisotropic elements of ``shape``: one slice per
    distinct (alpha, ratio, index ratio) of the parameters, from ``source`` for ``channel``
    (``_slice``), each mask of ``shape`` (a broadcast view of the parameters' mask)."""
    params = np.broadcast_shapes(np.shape(eta), distribution.param_shape)
    if params == ():  # one interface (anisotropic: the caller asked for its slice)
        piece = _interface_slice(distribution, eta, source, channel)
        if piece is not None:
            yield np.broadcast_to(True, shape), piece
        return
    alpha, ratio = _alpha_ratio(distribution)
    index = checked_ratio(eta, _SLICES)
    aniso, alpha, ratio, index = (np.broadcast_to(a, params) for a in (
        is_anisotropic(distribution), alpha, ratio, index))
    rows = np.stack([alpha[aniso], ratio[aniso], index[aniso]], -1)
    unique, inverse = np.unique(rows, axis=0, return_inverse=True)
    where = np.argwhere(aniso)
    for k, (a, r, e) in enumerate(unique):
        mask = np.zeros(params, dtype=bool)
        mask[tuple(where[inverse.ravel() == k].T)] = True
        yield np.broadcast_to(mask, shape), _slice(a, r, e, source, channel)


def slice_energy(eta, distribution: GGX, wo, with_error: bool = False,
                 channel: str = "total", source: str = "exact"):
    """``(E, error)``, each ``(...)``: E_R + E_T (``channel`` "total") or E_R ("reflection")
    of the anisotropic elements' slices (``tables.dielectric_slices``, from ``source``:
    ``_slice``) seen from ``wo``'s side, 0 elsewhere and in the tangent plane; error None
    unless ``with_error``."""
    cos_phi = _cos_phi(distribution.alpha_x >= distribution.alpha_y, wo)
    mu = np.minimum(np.abs(wo[..., 2]), 1.0)
    on_light = (wo[..., 2] > 0.0) == sides(eta)[0]
    shape = np.broadcast_shapes(mu.shape, np.shape(eta), distribution.param_shape)
    if shape == mu.shape and np.ndim(eta) == 0 and distribution.param_shape == ():
        piece = _interface_slice(distribution, eta, source, channel)  # one: no masks
        if piece is not None:
            E = piece.channel(channel, on_light, mu, cos_phi)
            error = piece.error(on_light, mu, cos_phi) if with_error else None
            if error is not None:
                error = error.sum(-1) if channel == "total" else error[..., 0]
            grazing = wo[..., 2] == 0.0
            E[grazing] = 0.0
            if error is not None:
                error[grazing] = 0.0
            return E, error
    E = np.zeros(shape)
    error = np.zeros(shape) if with_error else None
    mu, cos_phi, on_light = (np.broadcast_to(a, shape) for a in (mu, cos_phi, on_light))

    def errors(piece, *args):
        e = piece.error(*args)
        return e.sum(-1) if channel == "total" else e[..., 0]
    for mask, piece in _slices(eta, distribution, shape, source, channel):
        if mask.strides == (0,) * mask.ndim:  # every element: one scalar interface
            E[...] = piece.channel(channel, on_light, mu, cos_phi)
            if with_error:
                error[...] = errors(piece, on_light, mu, cos_phi)
            continue
        E[mask] = piece.channel(channel, on_light[mask], mu[mask], cos_phi[mask])
        if with_error:
            error[mask] = errors(piece, on_light[mask], mu[mask], cos_phi[mask])
    grazing = np.broadcast_to(wo[..., 2], shape) == 0.0
    return pick(grazing, 0.0, E), None if error is None else pick(grazing, 0.0, error)


def slice_average(eta, distribution: GGX, source: str = "exact", channel: str = "total"):
    """``(light, dense)``: each ``(..., 2)``, the (E_R, E_T) averages of the anisotropic
    elements' slices seen from the light and the dense side (0 elsewhere), of the slices
    that serve ``channel`` (``_slice``: "reflection" for a reader of E_R alone)."""
    shape = np.broadcast_shapes(np.shape(eta), distribution.param_shape)
    light, dense = np.zeros(shape + (2,)), np.zeros(shape + (2,))
    for mask, piece in _slices(eta, distribution, shape, source, channel):
        light[mask], dense[mask] = piece.average_outside, piece.average_inside
    return light, dense


def sides(eta):
    """(eta >= 1, index ratio dense / light)."""
    light_above = eta >= 1.0
    return light_above, pick(light_above, eta, 1.0 / eta)


_COLOURS = ("red", "green", "blue")


def checked_ratio(eta, table: str | None = None, dispersion=None):
    """max(eta, 1/eta), checked to lie within the dielectric tables' range [1, ETA_MAX]
    (``ValueError`` naming ``eta``, the table ``table``, default all GGX tables, and the
    range). With ``dispersion`` (a ``Dispersive``'s, ``eta`` then its channel indices
    ``(..., 3)``) the message names the channel, the index and the dispersion."""
    eta = np.asarray(eta, dtype=np.float64)
    ratio = sides(eta)[1]
    # 1 / (1/3) is 3 plus an ulp: the range's end, by rounding
    ratio = np.where((ratio > tables.ETA_MAX) & (ratio <= tables.ETA_MAX * (1.0 + 1e-12)),
                     tables.ETA_MAX, ratio)
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


def dielectric_energy(eta, distribution: GGX, wo, with_error: bool = False,
                      slices: str = ""):
    """``(E, error)``: E_R + E_T of a rough interface seen from ``wo`` (either side), 1 where
    the interface is smooth or index-matched, and the carried node error (None unless
    ``with_error``). Each side's table is looked up only for the directions on that side
    (where the parameters are scalars); ``near_matched`` directions are integrated.
    ``slices`` (``slice_source``): anisotropic elements read their slices from there
    (``slice_energy``) instead."""
    names = "ggx_dielectric_outside and ggx_dielectric_inside"
    alpha = table_alpha(distribution, names)
    ratio = checked_ratio(eta, names)
    matched = (distribution.smooth | (eta == 1.0)) & (wo[..., 2] != 0.0)
    if slices and np.all(is_anisotropic(distribution)):  # every element reads its slice
        total, error = slice_energy(eta, distribution, wo, with_error, source=slices)
    else:
        total, error = _tabulated(eta, distribution, wo, alpha, ratio, with_error, slices)
    # in the tangent plane (cos = 0) nothing is reflected or transmitted (docs/conventions.md)
    grazing = wo[..., 2] == 0.0
    total = pick(matched, 1.0, pick(grazing, 0.0, total))
    return total, None if error is None else pick(matched | grazing, 0.0, error)


def _tabulated(eta, distribution: GGX, wo, alpha, ratio, with_error: bool, slices: str):
    """``dielectric_energy`` before its smooth, index-matched and grazing directions: the
    tables, the integrated ``near_matched`` directions, and with ``slices`` the slices of the
    anisotropic elements."""
    mu = np.abs(wo[..., 2])
    on_light = (wo[..., 2] > 0.0) == sides(eta)[0]
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
            total = pick(here, E, total)
            error = _where(here, err, error)
    aniso = np.broadcast_to(is_anisotropic(distribution), shape) if slices else np.False_
    if not (slices or _FALLBACK_WARNED.is_set()) and np.any(
            is_anisotropic(distribution) & ~distribution.smooth
            & (eta != 1.0) & ~passes_through(eta, distribution)):
        _warn_isotropic_fallback()
    # the pass-through keeps the tables' eta = 1 limit, the lobe's own energy there; the
    # exact anisotropic elements read their slices below, so they integrate nothing here
    near = np.broadcast_to(near_matched(ratio, mu) & ~distribution.smooth
                           & ~passes_through(eta, distribution), shape) & ~aniso
    if np.any(near):
        E_R, E_T, err_R, err_T = _integrated(near, mu, alpha, pick(on_light, ratio,
                                                                         1.0 / ratio), with_error)
        total[near] = E_R + E_T
        if with_error:
            error[near] = err_R + err_T
    if slices:
        E_s, error_s = slice_energy(eta, distribution, wo, with_error, source=slices)
        total = pick(aniso, E_s, total)
        error = None if error is None else pick(aniso, error_s, error)
    return total, error


def reflected_energy(name: str, mu, alpha, ratio, table_axes: dict, eta_seen,
                     with_error: bool = False, where=True):
    """``(E_R, error)`` of the GGX reflection of a dielectric interface at cosine ``mu`` > 0:
    the reflection channel of table ``name`` at ``table_axes`` (the table's own coordinates),
    integrated where ``near_matched(ratio, mu)`` and ``where`` (``ratio`` the index ratio,
    ``eta_seen`` the relative index seen from ``wo``, ``alpha`` the GGX alpha, 0 smooth); 0
    where ``ratio`` is 1 (index-matched: no interface)."""
    E, error = lookup(name, mu, with_error, channel=0, **table_axes)
    E = np.maximum(E, 0.0)  # interpolation overshoot below 0 near eta = 1
    matched = ratio == 1.0  # no interface: F = 0, nothing is reflected, exactly
    if np.any(matched):
        E = pick(matched, 0.0, E)
        error = None if error is None else pick(matched, 0.0, error)
    near = near_matched(ratio, mu) & where & ~matched
    if np.any(near):
        shape = np.broadcast_shapes(E.shape, near.shape)
        E, near = np.array(np.broadcast_to(E, shape)), np.broadcast_to(near, shape)
        E_R, _, err_R, _ = _integrated(near, mu, alpha, eta_seen, with_error)
        E[near] = E_R
        if with_error:
            error = np.array(np.broadcast_to(error, shape))
            error[near] = err_R
    return E, error
