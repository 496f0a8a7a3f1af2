"""Spectral metals: measured n + i k to the ASM's F0 and F82-tint colours [Kutz2021, §2].

Public API
----------
``metal_ior(name) -> (wavelengths_nm, n, k)``   the shipped measured data (``METALS``)
``reflectance_to_rgb(wavelengths_nm, R, illuminant="D65")``
                                                linear Rec. 709 colour of a reflectance spectrum
``fit_f82_tint(wavelengths_nm, n, k, illuminant="D65") -> F82TintFit``
                                                F0 and F82 tint the way [Kutz2021, §2] derives
                                                Table 1, and the fit error over all angles

Colour: a reflectance spectrum R(lambda) lit by the illuminant S(lambda) has
XYZ = sum R S cmf / sum S ybar (CIE 1931 2-degree observer, 1 nm steps over 380-780 nm, the
range of the data, linear interpolation of the data), then linear Rec. 709 RGB by the BT.709
matrix, divided channel-wise by the RGB of the perfect reflector (R = 1) so that a white
spectrum is exactly (1, 1, 1) whatever the illuminant (a von Kries white balance in RGB; with
D65, the Rec. 709 white, this changes the colour by less than 1e-3).

References
----------
[Kutz2021, §2] eqs. 2, 3, 6 and Table 1 ("calculated using measured spectral data and the
full Fresnel equations").
[Gulbrandsen2014] the conductor curve ``conductor_from_f82_tint`` searches.
"""

from __future__ import annotations

import csv
import functools
import warnings
from importlib import resources
from typing import NamedTuple

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf.fresnel import (
    COS_THETA_MAX,
    _conductor_channel,
    _f82_tint,
    _schlick,
    conductor,
    gulbrandsen_to_ior,
)

__all__ = ["METALS", "metal_ior", "reflectance_to_rgb", "F82TintFit", "fit_f82_tint",
           "conductor_from_f82_tint"]

#: the visible range of the colour integrals (nm)
RANGE_NM = (380.0, 780.0)


@functools.lru_cache(maxsize=1)
def _table():
    rows = {}
    text = resources.files("adobe_bsdf").joinpath("data/metal_ior.csv").read_text("utf-8")
    for row in csv.DictReader(text.splitlines()):
        rows.setdefault(row["metal"], []).append(
            (float(row["wavelength_nm"]), float(row["n"]), float(row["k"])))
    return {m: np.array(sorted(v)) for m, v in rows.items()}


#: names of the shipped measured metals (``metal_ior``)
METALS = ("Ag", "Al", "Au", "Cr", "Cu", "CuZn", "Fe", "Fe-Werner2009", "Ni", "Ni-Werner2009",
          "Pt", "Ti", "Ti-Werner2009", "Zn")


def metal_ior(name: str):
    """``(wavelengths_nm, n, k)`` of a shipped metal (``METALS``; sources in
    ``adobe_bsdf/data/README.md``)."""
    _params.choice("name", name, METALS)
    data = _table()[name]
    return data[:, 0].copy(), data[:, 1].copy(), data[:, 2].copy()


def colour_science():
    """The colour-science module, imported on first use, with numpy's print options as they
    were: its import sets legacy printing ("1.13") for every caller (and it notes that its
    optional plotting is unavailable: silenced)."""
    options = np.get_printoptions()
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message='"Matplotlib" related API features')
        import colour
    np.set_printoptions(**options)
    return colour


@functools.lru_cache(maxsize=8)
def _weights(illuminant: str):
    """(1 nm grid, S cmf / sum S ybar (3, n), BT.709 XYZ -> RGB, RGB of the white)."""
    colour = colour_science()

    if illuminant not in colour.SDS_ILLUMINANTS:
        raise ValueError(f"illuminant = {illuminant!r} is not a colour-science illuminant "
                         "(e.g. 'D65', 'D50', 'A', 'E')")
    grid = np.arange(RANGE_NM[0], RANGE_NM[1] + 0.5, 1.0)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    cmf = np.array([np.interp(grid, cmfs.wavelengths, cmfs.values[:, i]) for i in range(3)])
    sd = colour.SDS_ILLUMINANTS[illuminant]
    S = np.interp(grid, sd.wavelengths, sd.values)
    w = S * cmf / np.sum(S * cmf[1])
    matrix = colour.RGB_COLOURSPACES["ITU-R BT.709"].matrix_XYZ_to_RGB
    white = matrix @ w.sum(axis=1)
    return grid, w, matrix, white


def reflectance_to_rgb(wavelengths_nm, reflectance, illuminant: str = "D65") -> np.ndarray:
    """Linear Rec. 709 RGB ``(..., 3)`` of reflectance spectra ``(..., n)`` sampled at
    ``wavelengths_nm`` ``(n,)`` (increasing, covering 380-780 nm), white-balanced so that
    R = 1 gives (1, 1, 1) (module docstring). Not clipped."""
    lam = _params.real("wavelengths_nm", wavelengths_nm, 0.0, np.inf, lo_open=True)
    R = _params.real("reflectance", reflectance)
    if lam.ndim != 1 or R.shape[-1] != lam.size or np.any(np.diff(lam) <= 0):
        raise ValueError(f"wavelengths_nm has shape {lam.shape} and reflectance "
                         f"{R.shape}: allowed increasing wavelengths (n,) and spectra (..., n)")
    if lam[0] > RANGE_NM[0] or lam[-1] < RANGE_NM[1]:
        raise ValueError(f"wavelengths_nm spans [{lam[0]}, {lam[-1]}]: allowed a range that "
                         f"covers [{RANGE_NM[0]}, {RANGE_NM[1]}] nm")
    grid, w, matrix, white = _weights(illuminant)
    flat = R.reshape(-1, lam.size)
    on_grid = np.stack([np.interp(grid, lam, r) for r in flat])  # (m, g): a few spectra
    rgb = (on_grid @ w.T) @ matrix.T / white
    return rgb.reshape(R.shape[:-1] + (3,))


def _spectral_fresnel(mu, n, k):
    """Exact conductor reflectance ``(angles, wavelengths)`` at cosines ``mu`` of the
    spectra n + i k (``fresnel._conductor_channel``, one channel per wavelength)."""
    c2 = (mu * mu)[:, None]
    s2 = 1.0 - c2
    return _conductor_channel(c2, s2, 2.0 * c2, s2 * s2, n * n - k * k, 4.0 * n * n * k * k)


class F82TintFit(NamedTuple):
    """Result of ``fit_f82_tint``.

    Attributes
    ----------
    f0 : ndarray (3,)          "Base Color": RGB of F(cos = 1), clipped to [0, 1].
    tint : ndarray (3,)        "Specular Edge Color": RGB of F(cos = 1/7) over the Schlick
                               value of ``f0`` there (eq. 6), clipped to [0, 1].
    f0_unclipped : ndarray (3,)
    max_error, rms_error : ndarray (3,)
        |F82-tint(f0, tint) - RGB of the exact spectral Fresnel| over cos theta in [0, 1].
    """

    f0: np.ndarray
    tint: np.ndarray
    f0_unclipped: np.ndarray
    max_error: np.ndarray
    rms_error: np.ndarray


def fit_f82_tint(wavelengths_nm, n, k, illuminant: str = "D65", n_angles: int = 1001):
    """F0 and F82 tint of a measured metal [Kutz2021, §2, Table 1].

    The exact unpolarised conductor Fresnel reflectance of n + i k is computed per
    wavelength at cos theta = 1 and at cos theta_max = 1/7 (eq. 2) and turned into linear
    Rec. 709 colours (``reflectance_to_rgb``); F0 is the first, clipped to [0, 1] as Table 1
    is (its Au and Cu red channels are 1.0000); the tint is h / (F0 + (1 - F0)(6/7)^5)
    (eq. 6) with h the second, clipped to [0, 1]. The fit error compares the F82-tint curve
    of (F0, tint) with the colour of the exact spectral Fresnel at ``n_angles`` cosines.
    """
    lam = _params.real("wavelengths_nm", wavelengths_nm, 0.0, np.inf, lo_open=True)
    n = _params.real("n", n, 0.0, np.inf, lo_open=True)
    k = _params.real("k", k, 0.0, np.inf)
    mu = np.linspace(0.0, 1.0, _params.integer("n_angles", n_angles, 2))
    exact = reflectance_to_rgb(lam, _spectral_fresnel(mu, n, k), illuminant)  # (angles, 3)
    f0_raw, h = reflectance_to_rgb(
        lam, _spectral_fresnel(np.array([1.0, COS_THETA_MAX]), n, k), illuminant)
    f0 = np.clip(f0_raw, 0.0, 1.0)
    tint = np.clip(h / _schlick(COS_THETA_MAX, f0, 1.0, 5.0), 0.0, 1.0)
    model = _f82_tint(mu, f0, tint, 1.0, 5.0)
    error = np.abs(model - exact)
    return F82TintFit(f0, tint, f0_raw, error.max(axis=0), np.sqrt((error**2).mean(axis=0)))


def conductor_from_f82_tint(f0, tint, iterations: int = 64):
    """An effective complex index per channel for an F82-tint metal: the exact conductor
    whose reflectance is ``f0`` at cos theta = 1 and h = tint Schlick(f0, 1/7) at cos theta =
    1/7 [Kutz2021, eq. 6], so that the exact Fresnel passes through both points F82-tint
    fixes.

    It is searched on Gulbrandsen's curve of reflectivity ``f0`` (every point has F(1) =
    f0): F(1/7) increases with Gulbrandsen's edge tint g in [0, 1], so g is found by
    bisection. Where h lies outside the curve's range, the nearest end is returned and
    ``residual`` = F(1/7) - h says by how much. Where f0 = 1 the index is infinite (F = 1 at
    every angle; residual 1 - h).

    Returns ``(eta, k, residual)``, each ``(..., 3)``.
    """
    f0 = _params.color("f0", f0, 0.0, 1.0)
    tint = _params.color("tint", tint, 0.0, np.inf)
    f0, tint = np.broadcast_arrays(f0, tint)
    h = tint * _schlick(COS_THETA_MAX, f0, 1.0, 5.0)
    mirror = f0 >= 1.0
    r = np.where(mirror, 0.5, f0)

    def at(g):
        eta, k = gulbrandsen_to_ior(r, g)
        return eta, k, conductor(np.full(r.shape[:-1], COS_THETA_MAX), eta, k)

    lo, hi = np.zeros_like(r), np.ones_like(r)
    for _ in range(_params.integer("iterations", iterations, 1)):
        mid = 0.5 * (lo + hi)
        below = at(mid)[2] < h
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    g = np.where(at(hi)[2] - h < h - at(lo)[2], hi, lo)
    eta, k, value = at(g)
    return (np.where(mirror, np.inf, eta), np.where(mirror, np.inf, k),
            np.where(mirror, 1.0 - h, value - h))
