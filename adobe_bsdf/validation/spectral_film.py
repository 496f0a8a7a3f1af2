"""Brute-force spectral reference for thin-film interference, written from the physics.

The stack is a non-absorbing outside medium (index n1), a homogeneous non-absorbing film
(index n2, thickness d in nm) and a semi-infinite substrate of complex index
n3 = n + i k (a dielectric for k = 0, a metal for k > 0, a perfect reflector for
|n3| = inf). Every reflectance is the unpolarised mean of the s and p polarisations. The module is a
reference for ``adobe_bsdf.thin_film``: it shares no code with it (nor with
``adobe_bsdf.spectral``'s colour computation), so that the two can be compared.

Public API
----------
``film_reflectance_spectrum(wavelength_nm, cos_theta, thickness_nm, film_ior, substrate_n,
substrate_k=0, outside_ior=1)``       R(lambda) by the Airy summation
``film_transmittance_spectrum(wavelength_nm, cos_theta, thickness_nm, film_ior, substrate_n,
outside_ior=1)``                      T(lambda), the power transmitted into a dielectric
                                      substrate, from the transmitted amplitude
``film_rgb(cos_theta, thickness_nm, film_ior, substrate_n, substrate_k=0, outside_ior=1)``
                                      linear Rec. 709 RGB ``(..., 3)`` of R(lambda)
``film_transmittance_rgb(cos_theta, thickness_nm, film_ior, substrate_n, outside_ior=1)``
                                      linear Rec. 709 RGB ``(..., 3)`` of T(lambda)
``film_rgb_per_channel(cos_theta, thickness_nm, film_ior, n_rgb, k_rgb, outside_ior=1)``
                                      the film on a substrate of one complex index per colour
                                      channel: channel j of the RGB of R(lambda) computed
                                      with the index of channel j
``spectrum_to_rgb(spectrum)``         linear Rec. 709 RGB of spectra sampled on
                                      ``WAVELENGTHS_NM``
``WAVELENGTHS_NM``                    the spectral grid: 380-780 nm in 1 nm steps

Physics. With the invariant n1 sin theta1 = n_j sin theta_j (Snell's law at complex angles),
q_j = n_j cos theta_j = sqrt(n_j^2 - n1^2 sin^2 theta1) on the principal branch
(Re, Im >= 0: the wave that decays away from the interface, in a metal or beyond a critical
angle). The Fresnel amplitudes of the interface i -> j [BornWolf1980, §1.5.2, §13.2] are

    r_s = (n_i cos_i - n_j cos_j) / (n_i cos_i + n_j cos_j),  t_s = 2 n_i cos_i / (same),
    r_p = (n_j cos_i - n_i cos_j) / (n_j cos_i + n_i cos_j),  t_p = 2 n_i cos_i / (same),

and the film's multiple reflections sum to [BornWolf1980, §1.6.4; §13.4 for complex n3]

    r = (r12 + r23 e^{2 i beta}) / (1 + r12 r23 e^{2 i beta}),
    t = t12 t23 e^{i beta} / (1 + r12 r23 e^{2 i beta}),   beta = 2 pi n2 d cos theta2 / lambda,

with R = (|r_s|^2 + |r_p|^2) / 2 and, for a dielectric substrate,
T = Re(n3 cos theta3) / (n1 cos theta1) (|t_s|^2 + |t_p|^2) / 2. The same Airy sum is the
film model of [Belcour2017, §Thin-film interference].

Colour. On the 1 nm grid of 380-780 nm, XYZ = sum R S xyz / sum S ybar with the CIE 1931
2-degree standard observer xyz and the CIE standard illuminant D65 S (colour-science's
tables, linearly interpolated onto the grid), then linear Rec. 709 RGB (sRGB primaries,
D65 white, no transfer function) by colour-science's sRGB XYZ -> RGB matrix. No white
balance is applied: a white reflector (R = 1) maps to (0.99996, 1.00011, 0.99960), (1, 1, 1)
to within 5e-4 (the computed D65 white against the matrix's rounded white point).

References
----------
[BornWolf1980, §1.5.2] the Fresnel amplitudes; [§1.6.4] the homogeneous film;
[§13.4] the absorbing substrate.
[Belcour2017, §Thin-film interference] the Airy reflectance of a film in place of the
Fresnel factor.
"""

from __future__ import annotations

import functools

import numpy as np

from adobe_bsdf.spectral import colour_science

__all__ = ["WAVELENGTHS_NM", "film_reflectance_spectrum", "film_transmittance_spectrum",
           "film_rgb", "film_transmittance_rgb", "film_rgb_per_channel", "spectrum_to_rgb"]

#: the spectral grid of the colour integrals (nm): 380-780 nm in 1 nm steps (401 samples)
WAVELENGTHS_NM = np.arange(380.0, 781.0, 1.0)
WAVELENGTHS_NM.setflags(write=False)


def _real(name: str, value, lo: float, *, lo_open: bool = False, hi: float = np.inf,
          infinite: bool = False) -> np.ndarray:
    """``value`` as float64, checked to be a number in [lo, hi] (or (lo, hi]; +inf allowed
    where ``infinite``)."""
    arr = np.asarray(value, dtype=np.float64)
    bad = np.isnan(arr) | (arr <= lo if lo_open else arr < lo) | (arr > hi)
    if not infinite:
        bad |= np.isinf(arr)
    if np.any(bad):
        left = "(" if lo_open else "["
        raise ValueError(f"{name} = {arr[bad].flat[0]!r} is outside the allowed range "
                         f"{left}{lo}, {hi}]")
    return arr


def _q(n_sq, n1_sin_sq):
    """q = n cos theta = sqrt(n^2 - (n1 sin theta1)^2), principal branch (Re, Im >= 0)."""
    return np.sqrt(np.asarray(n_sq, dtype=np.complex128) - n1_sin_sq)


def _interface(ni, qi, nj, qj):
    """Fresnel amplitudes (r_s, t_s, r_p, t_p) of the interface i -> j [BornWolf1980,
    §1.5.2], from the indices n and q = n cos theta (cos = q / n)."""
    ci, cj = qi / ni, qj / nj
    den_s = ni * ci + nj * cj
    den_p = nj * ci + ni * cj
    return ((ni * ci - nj * cj) / den_s, 2.0 * ni * ci / den_s,
            (nj * ci - ni * cj) / den_p, 2.0 * ni * ci / den_p)


def _airy(lam, c, d, n2, n, k, n1, transmitted: bool):
    """(R, T) of the stack n1 / n2 (thickness d) / n + i k at wavelength ``lam`` and
    cos theta1 = ``c``; T only where ``transmitted`` (k = 0). An infinite n or k is a
    perfect reflector (r23_s = -1, r23_p = +1, the limit |n3| -> inf)."""
    mirror = np.isinf(n) | np.isinf(k)
    n3 = np.where(mirror, 1.0, n) + 1j * np.where(mirror, 0.0, k)
    n1_sin_sq = n1 * n1 * (1.0 - c * c)  # (n1 sin theta1)^2, Snell's invariant
    q1 = n1 * c + 0j
    q2 = _q(n2 * n2, n1_sin_sq)
    q3 = _q(n3 * n3, n1_sin_sq)
    beta = 2.0 * np.pi * d * q2 / lam  # beta = 2 pi n2 d cos theta2 / lambda
    phase2 = np.exp(2j * beta)  # e^{2 i beta}
    r12_s, t12_s, r12_p, t12_p = _interface(n1, q1, n2, q2)
    r23_s, t23_s, r23_p, t23_p = _interface(n2, q2, n3, q3)
    r23_s = np.where(mirror, -1.0, r23_s)
    r23_p = np.where(mirror, 1.0, r23_p)
    R, T = 0.0, 0.0
    for r12, r23, t12, t23 in ((r12_s, r23_s, t12_s, t23_s), (r12_p, r23_p, t12_p, t23_p)):
        den = 1.0 + r12 * r23 * phase2
        r = (r12 + r23 * phase2) / den
        R = R + 0.5 * np.abs(r) ** 2
        if transmitted:
            t = t12 * t23 * np.exp(1j * beta) / den
            T = T + 0.5 * np.abs(t) ** 2
    if transmitted:
        T = T * q3.real / q1.real  # Re(n3 cos theta3) / (n1 cos theta1)
    return R, T


def film_reflectance_spectrum(wavelength_nm, cos_theta, thickness_nm, film_ior, substrate_n,
                              substrate_k=0.0, outside_ior=1.0) -> np.ndarray:
    """Unpolarised reflectance R of outside / film / substrate by the Airy summation
    [BornWolf1980, §1.6.4, §13.4] (module docstring).

    Every argument broadcasts; indices are absolute (or all relative to one medium).
    ``cos_theta`` in (0, 1] is the cosine of the incidence angle in the outside medium,
    ``thickness_nm`` >= 0, ``film_ior`` = n2 > 0, ``substrate_n`` + i ``substrate_k`` = n3
    (n > 0, k >= 0; either infinite: a perfect reflector), ``outside_ior`` = n1 > 0.
    Returns R in [0, 1], shaped as the broadcast arguments.
    """
    lam = _real("wavelength_nm", wavelength_nm, 0.0, lo_open=True)
    c = _real("cos_theta", cos_theta, 0.0, lo_open=True, hi=1.0)
    d = _real("thickness_nm", thickness_nm, 0.0)
    n2 = _real("film_ior", film_ior, 0.0, lo_open=True)
    n = _real("substrate_n", substrate_n, 0.0, lo_open=True, infinite=True)
    k = _real("substrate_k", substrate_k, 0.0, infinite=True)
    n1 = _real("outside_ior", outside_ior, 0.0, lo_open=True)
    return _airy(lam, c, d, n2, n, k, n1, False)[0]


def film_transmittance_spectrum(wavelength_nm, cos_theta, thickness_nm, film_ior, substrate_n,
                                outside_ior=1.0) -> np.ndarray:
    """Unpolarised fraction T of the incident power transmitted into a dielectric substrate
    (real index n3 = ``substrate_n``): T = Re(n3 cos theta3) / (n1 cos theta1) |t|^2 with
    t = t12 t23 e^{i beta} / (1 + r12 r23 e^{2 i beta}) [BornWolf1980, §1.6.4], the mean of
    s and p; 0 beyond the substrate's critical angle. The film does not absorb, so
    R + T = 1. Arguments as ``film_reflectance_spectrum``.
    """
    lam = _real("wavelength_nm", wavelength_nm, 0.0, lo_open=True)
    c = _real("cos_theta", cos_theta, 0.0, lo_open=True, hi=1.0)
    d = _real("thickness_nm", thickness_nm, 0.0)
    n2 = _real("film_ior", film_ior, 0.0, lo_open=True)
    n = _real("substrate_n", substrate_n, 0.0, lo_open=True)
    n1 = _real("outside_ior", outside_ior, 0.0, lo_open=True)
    return _airy(lam, c, d, n2, n, 0.0, n1, True)[1]


@functools.lru_cache(maxsize=1)
def _colour_matrix() -> np.ndarray:
    """``(L, 3)`` matrix W with RGB = spectrum @ W on ``WAVELENGTHS_NM``:
    W = (S xyz / sum S ybar) M^T with M the sRGB XYZ -> RGB matrix (module docstring)."""
    colour = colour_science()

    lam = WAVELENGTHS_NM
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    xyz = np.stack([np.interp(lam, cmfs.wavelengths, cmfs.values[:, i]) for i in range(3)],
                   axis=-1)  # (L, 3): xbar, ybar, zbar
    d65 = colour.SDS_ILLUMINANTS["D65"]
    S = np.interp(lam, d65.wavelengths, d65.values)
    to_xyz = S[:, None] * xyz / np.sum(S * xyz[:, 1])
    M = np.asarray(colour.RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB, dtype=np.float64)
    W = to_xyz @ M.T
    W.setflags(write=False)
    return W


def spectrum_to_rgb(spectrum) -> np.ndarray:
    """Linear Rec. 709 RGB ``(..., 3)`` of spectra ``(..., L)`` sampled on ``WAVELENGTHS_NM``:
    XYZ = sum R S xyz / sum S ybar (CIE 1931 2-degree observer, D65), then the sRGB matrix.
    Not clipped."""
    spectrum = np.asarray(spectrum, dtype=np.float64)
    if spectrum.shape[-1:] != WAVELENGTHS_NM.shape:
        raise ValueError(f"spectrum has shape {spectrum.shape}: allowed (..., "
                         f"{WAVELENGTHS_NM.size}), sampled on WAVELENGTHS_NM")
    return spectrum @ _colour_matrix()


def _on_grid(x) -> np.ndarray:
    """An argument with a trailing axis for the wavelengths."""
    return np.asarray(x, dtype=np.float64)[..., None]


def film_rgb(cos_theta, thickness_nm, film_ior, substrate_n, substrate_k=0.0,
             outside_ior=1.0) -> np.ndarray:
    """Linear Rec. 709 RGB ``(..., 3)`` of the film's reflectance spectrum
    (``film_reflectance_spectrum`` on ``WAVELENGTHS_NM``, then ``spectrum_to_rgb``).
    Arguments broadcast, as ``film_reflectance_spectrum``. Not clipped."""
    R = film_reflectance_spectrum(WAVELENGTHS_NM, _on_grid(cos_theta), _on_grid(thickness_nm),
                                  _on_grid(film_ior), _on_grid(substrate_n),
                                  _on_grid(substrate_k), _on_grid(outside_ior))
    return spectrum_to_rgb(R)


def film_transmittance_rgb(cos_theta, thickness_nm, film_ior, substrate_n,
                           outside_ior=1.0) -> np.ndarray:
    """Linear Rec. 709 RGB ``(..., 3)`` of the transmittance spectrum into a dielectric
    substrate (``film_transmittance_spectrum``). Not clipped."""
    T = film_transmittance_spectrum(WAVELENGTHS_NM, _on_grid(cos_theta),
                                    _on_grid(thickness_nm), _on_grid(film_ior),
                                    _on_grid(substrate_n), _on_grid(outside_ior))
    return spectrum_to_rgb(T)


def film_rgb_per_channel(cos_theta, thickness_nm, film_ior, n_rgb, k_rgb,
                         outside_ior=1.0) -> np.ndarray:
    """The film on a substrate given by one complex index per colour channel, ``n_rgb`` +
    i ``k_rgb`` (each a scalar or ``(..., 3)``; absolute indices, infinite for a perfect
    reflector): channel j of the result is channel j of ``film_rgb`` with the substrate
    index n_rgb[j] + i k_rgb[j], constant over the wavelengths. This is the brute-force
    value of a film over a metal known only by per-channel effective indices (such as those
    inferred from F82-tint colours). Returns ``(..., 3)``, not clipped.
    """
    n_rgb = np.asarray(n_rgb, dtype=np.float64)
    k_rgb = np.asarray(k_rgb, dtype=np.float64)
    n_rgb, k_rgb = (np.broadcast_to(x, x.shape if x.ndim else (3,)) for x in (n_rgb, k_rgb))
    channels = [film_rgb(cos_theta, thickness_nm, film_ior, n_rgb[..., j], k_rgb[..., j],
                         outside_ior)[..., j] for j in range(3)]
    return np.stack(channels, axis=-1)
