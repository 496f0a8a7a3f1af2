"""Dispersion: the ASM "Dispersion" parameter, the Abbe number and one IOR per RGB channel.

Public API
----------
``abbe_to_dispersion(abbe)``                      Dispersion = 20 / V_d [Kutz2021, eq. 12]
``dispersion_to_abbe(dispersion)``                V_d = 20 / Dispersion [Kutz2021, eq. 13]
``cauchy_iors(ior, dispersion, wavelengths_nm)``  n(lambda) = A + B / lambda^2 per channel
``abbe_number(n_d, n_F, n_C)``                    V_d = (n_d - 1) / (n_F - n_C) (eq. 11)
``RGB_WAVELENGTHS_NM``                            the wavelengths of the RGB channels
``FRAUNHOFER_NM``                                 the d, F and C lines of eq. 11

The ASM maps the Abbe number to wavelength-dependent indices with "the basic form of
Cauchy's equation" [Kutz2021, §4]. Fixing n(lambda_d) = n_d and (n_d - 1) / (n(lambda_F) -
n(lambda_C)) = V_d gives B = (n_d - 1) / (V_d (lambda_F^-2 - lambda_C^-2)) and
A = n_d - B / lambda_d^2. Dispersion 0 (V_d = inf) gives B = 0: every channel gets n_d
exactly.

Wavelengths: the renderer of [Kutz2021, §4] samples "a wavelength for each RGB color channel"
without saying which; we use one fixed wavelength per channel, the dominant wavelengths of the
Rec. 709 / sRGB primaries against D65 (611, 549, 464 nm, as ``colour.dominant_wavelength``
gives them; ``tests/test_dispersion.py`` recomputes them).

References
----------
[Kutz2021, §4] eqs. 11-13, Table 2: the Dispersion parameter and Cauchy's equation.
Fraunhofer lines: He d 587.5618 nm, H F 486.1327 nm, H C 656.2725 nm (ISO 7944).
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params

__all__ = ["abbe_to_dispersion", "dispersion_to_abbe", "abbe_number", "cauchy_iors",
           "RGB_WAVELENGTHS_NM", "FRAUNHOFER_NM"]

#: wavelength (nm) of each RGB channel: dominant wavelengths of the sRGB primaries (D65)
RGB_WAVELENGTHS_NM = (611.0, 549.0, 464.0)

#: Fraunhofer lines of eq. 11 (nm)
FRAUNHOFER_NM = {"d": 587.5618, "F": 486.1327, "C": 656.2725}


def abbe_to_dispersion(abbe):
    """Dispersion = 20 / V_d [Kutz2021, eq. 12]; ``abbe`` V_d finite in (0, inf) (no
    dispersion is Dispersion 0, V_d = inf in eq. 13)."""
    v = _params.real("abbe", abbe, 0.0, np.inf, lo_open=True)
    return 20.0 / v


def dispersion_to_abbe(dispersion):
    """V_d = 20 / Dispersion [Kutz2021, eq. 13]; ``dispersion`` in [0, inf), 0 -> inf (no
    dispersion), as for a subnormal dispersion, where 20 / d overflows."""
    d = _params.real("dispersion", dispersion, 0.0, np.inf)
    with np.errstate(divide="ignore", over="ignore"):
        return 20.0 / d


def abbe_number(n_d, n_F, n_C):
    """V_d = (n_d - 1) / (n_F - n_C) [Kutz2021, eq. 11]; indices with n_F > n_C."""
    n_d = _params.real("n_d", n_d, 0.0, np.inf, lo_open=True)
    n_F = _params.real("n_F", n_F, 0.0, np.inf, lo_open=True)
    n_C = _params.real("n_C", n_C, 0.0, np.inf, lo_open=True)
    if np.any(n_F <= n_C):
        raise ValueError(f"n_F = {n_F!r}, n_C = {n_C!r}: allowed n_F > n_C (normal "
                         "dispersion)")
    return (n_d - 1.0) / (n_F - n_C)


def cauchy_iors(ior, dispersion, wavelengths_nm=RGB_WAVELENGTHS_NM):
    """One index per channel from Cauchy's equation n(lambda) = A + B / lambda^2 through
    (n_d, V_d = 20 / dispersion) (see the module docstring).

    Parameters
    ----------
    ior : array_like in (0, inf)            n_d, the index at the d line.
    dispersion : array_like in [0, inf)     the ASM parameter (0: none; 1: V_d = 20).
    wavelengths_nm : sequence of float > 0  the channels' wavelengths (default RGB).

    Returns
    -------
    ndarray (..., len(wavelengths_nm)). Indices of 1 stay 1 (B = 0 when n_d = 1).
    """
    return cauchy(_params.real("ior", ior, 0.0, np.inf, lo_open=True),
                  _params.real("dispersion", dispersion, 0.0, np.inf),
                  wavelengths(wavelengths_nm))


def wavelengths(wavelengths_nm) -> np.ndarray:
    """Channel wavelengths (nm), validated: (0, inf)."""
    return _params.real("wavelengths_nm", wavelengths_nm, 0.0, np.inf, lo_open=True)


def cauchy(n_d, d, lam) -> np.ndarray:
    """``cauchy_iors`` of validated arrays."""
    f, c, line_d = FRAUNHOFER_NM["F"], FRAUNHOFER_NM["C"], FRAUNHOFER_NM["d"]
    B = (n_d - 1.0) * (d / 20.0) / (f**-2 - c**-2)  # (n_d - 1) / V_d over the F-C span
    B = np.asarray(B)[..., None]
    return n_d[..., None] + B * (lam**-2 - line_d**-2)
