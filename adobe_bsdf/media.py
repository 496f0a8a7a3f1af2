"""Participating media: the ASM subsurface mapping [Kutz2021, §5] to absorption and scattering.

Public API
----------
``Medium(sigma_a, sigma_s, g)``                     a homogeneous medium record (RGB coefficients)
``single_scattering_albedo(multiple_albedo, g=0)``  Kulla & Conty's inversion
``asm_medium(scattering_distance, scattering_color, ...) -> Medium``
                                                    the ASM mapping
``openpbr_subsurface_medium(radius, radius_scale, color, g) -> Medium``
                                                    OpenPBR v1.1.1's subsurface mapping
``openpbr_transmission_medium(color, depth, scatter, g) -> Medium | None``
                                                    OpenPBR v1.1.1's translucent medium
``half_space_albedo(albedo, n_paths, seed, g=0) -> HalfSpaceAlbedo``
                                                    the albedo a medium really reflects, by a
                                                    random walk (beyond the paper)

The mapping ([Kutz2021, §5], in order):

1. the single-scattering albedo of each channel from the "Scattering Color" (the albedo of the
   whole medium, multiple scattering included) by the inversion of [KullaConty2017];
2. the extinction of the brightest channel is 1 / scattering_distance, and every other
   channel's extinction is multiplied by max_albedo / max(albedo, max_albedo / 1e3), so that
   all channels share one scattering coefficient and the colour comes from absorption only
   (``max_multiplier`` = 1e3 bounds the ratio of extinctions);
3. the extinction is divided by the RGB "Scattering Distance Scale" (a longer distance is a
   thinner medium);
4. "Rayleigh Scattering" rho, clamped to [-1, 2]: red and blue extinctions are multiplied by
   mix(1, (540/640)^4, rho) and mix(1, (540/460)^4, rho) (green fixed);
5. "Scattering Red Shift" s in [0, 1]: the paper gives no formula ("decreases the extinction
   of the red channel"). Ours halves the red extinction per unit shift, sigma_t,r *= 2^-s:
   monotonic, never zero or negative, the identity at s = 0.

Then sigma_s = albedo sigma_t and sigma_a = sigma_t - sigma_s; the phase function is
isotropic (g = 0) unless given.

A scattering distance of 0 is raised to ``DISTANCE_MIN`` (the listing's
``clamped_scattering_distance``; the paper does not give its bound): extinction stays finite.

References
----------
[Kutz2021, §5] the mapping, its listings, Table 3.
[KullaConty2017] the albedo inversion
alpha = 1 - (4.09712 + 4.20863 A - sqrt(9.59217 + 41.6808 A + 17.7126 A^2))^2.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf.sampling import henyey_greenstein_cos

__all__ = ["Medium", "single_scattering_albedo", "asm_medium", "openpbr_subsurface_medium",
           "openpbr_transmission_medium", "HalfSpaceAlbedo", "half_space_albedo",
           "DISTANCE_MIN", "MAX_MULTIPLIER", "RAYLEIGH_NM", "TRANSMITTANCE_MIN"]

#: smallest scattering distance (scene units): 0 is raised to it
DISTANCE_MIN = 1e-9
#: largest ratio of the extinctions of two channels [Kutz2021, §5 listing]
MAX_MULTIPLIER = 1e3
#: smallest transmittance of OpenPBR's transmission_color (0 is raised to it: the extinction
#: -ln(T) / d stays finite, about 27.6 / d)
TRANSMITTANCE_MIN = 1e-12
#: wavelengths (nm) of the Rayleigh control, red, green, blue [Kutz2021, §5 listing]
RAYLEIGH_NM = (640.0, 540.0, 460.0)


class Medium(NamedTuple):
    """A homogeneous medium: absorption and scattering coefficients ``(..., 3)`` (per unit
    length) and the Henyey–Greenstein asymmetry ``g`` (0: isotropic)."""

    sigma_a: np.ndarray
    sigma_s: np.ndarray
    g: np.ndarray

    @property
    def sigma_t(self) -> np.ndarray:
        """Extinction sigma_a + sigma_s."""
        return self.sigma_a + self.sigma_s

    @property
    def albedo(self) -> np.ndarray:
        """Single-scattering albedo sigma_s / sigma_t (0 where sigma_t = 0)."""
        t = self.sigma_t
        return np.divide(self.sigma_s, t, out=np.zeros_like(t), where=t > 0.0)


def single_scattering_albedo(multiple_albedo, g=0.0):
    """Single-scattering albedo from the multiple-scattering albedo A in [0, 1] (Kulla & Conty
    2017): s = 4.09712 + 4.20863 A - sqrt(9.59217 + 41.6808 A + 17.7126 A^2), clamped to
    [0, 1], and alpha = (1 - s^2) / (1 - g s^2) (g = 0: 1 - s^2)."""
    A = _params.real("multiple_albedo", multiple_albedo, 0.0, 1.0)
    g = _params.real("g", g, -1.0, 1.0, lo_open=True, hi_open=True)
    s = 4.09712 + 4.20863 * A - np.sqrt(9.59217 + 41.6808 * A + 17.7126 * A * A)
    s2 = np.clip(s, 0.0, 1.0) ** 2
    return (1.0 - s2) / (1.0 - g * s2)


def asm_medium(scattering_distance, scattering_color, scattering_distance_scale=1.0,
               scatter_rayleigh=0.0, scattering_red_shift=0.0, g=0.0) -> Medium:
    """The ASM subsurface medium ([Kutz2021, §5]; the steps are in the module docstring).

    Parameters
    ----------
    scattering_distance : array_like in [0, inf)        mean free path of the brightest channel.
    scattering_color : colour in [0, 1]                 the medium's multiple-scattering albedo.
    scattering_distance_scale : colour in (0, inf)      per-channel distance multiplier.
    scatter_rayleigh : array_like, clamped to [-1, 2]   0 uniform, 1 Rayleigh-like.
    scattering_red_shift : array_like in [0, 1]         decreases the red extinction.
    g : array_like in (-1, 1)                           phase-function asymmetry.
    """
    d = _params.real("scattering_distance", scattering_distance, 0.0, np.inf)
    color = _params.color("scattering_color", scattering_color, 0.0, 1.0)
    scale = _params.color("scattering_distance_scale", scattering_distance_scale, 0.0, np.inf)
    if np.any(scale <= 0.0):
        raise ValueError(f"scattering_distance_scale = {scale[scale <= 0.0].flat[0]!r} is "
                         "outside the allowed range (0, inf)")
    rho = np.clip(_params.real("scatter_rayleigh", scatter_rayleigh), -1.0, 2.0)  # spec clamp
    shift = _params.real("scattering_red_shift", scattering_red_shift, 0.0, 1.0)
    g = _params.real("g", g, -1.0, 1.0, lo_open=True, hi_open=True)

    albedo = single_scattering_albedo(color, g)
    min_extinction = 1.0 / np.maximum(d, DISTANCE_MIN)
    max_albedo = albedo.max(axis=-1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        multiplier = np.where(max_albedo > 0.0,
                              max_albedo / np.maximum(albedo, max_albedo / MAX_MULTIPLIER), 1.0)
    sigma_t = min_extinction[..., None] * multiplier / scale
    red, green, blue = RAYLEIGH_NM
    rayleigh = np.stack(np.broadcast_arrays(1.0 + rho * ((green / red) ** 4 - 1.0),
                                            np.ones_like(rho),
                                            1.0 + rho * ((green / blue) ** 4 - 1.0)), -1)
    red_shift = np.stack(np.broadcast_arrays(2.0**-shift, np.ones_like(shift),
                                             np.ones_like(shift)), -1)
    sigma_t = sigma_t * rayleigh * red_shift
    sigma_s = albedo * sigma_t
    return Medium(sigma_t - sigma_s, sigma_s, np.asarray(g))


def openpbr_subsurface_medium(radius, radius_scale, color, g=0.0) -> Medium:
    """OpenPBR v1.1.1's subsurface medium [OpenPBR2026, §Subsurface]: r = radius
    radius_scale is the mean free path, sigma_t = 1 / r (r raised to ``DISTANCE_MIN``, so
    r = 0 is a very dense medium, not an infinite one); the single-scattering albedo is the
    van de Hulst inversion of the colour C with the asymmetry g (``single_scattering_albedo``,
    the example the specification gives: s = 4.09712 + 4.20863 C - sqrt(9.59217 + 41.6808 C
    + 17.7126 C^2), alpha = (1 - s^2) / (1 - g s^2)), so that the medium's multiple-scattering
    albedo is about C; sigma_t does not depend on g. The phase function is Henyey–Greenstein
    of asymmetry g.

    Parameters
    ----------
    radius : array_like in [0, inf)           subsurface_radius (scene units).
    radius_scale : colour in [0, 1]           subsurface_radius_scale.
    color : colour in [0, 1]                  subsurface_color.
    g : array_like in (-1, 1)                 subsurface_scatter_anisotropy (the open ends,
                                              a delta phase function, are excluded).
    """
    r = _params.real("radius", radius, 0.0, np.inf)
    scale = _params.color("radius_scale", radius_scale, 0.0, 1.0)
    color = _params.color("color", color, 0.0, 1.0)
    g = _params.real("g", g, -1.0, 1.0, lo_open=True, hi_open=True)
    sigma_t = 1.0 / np.maximum(r[..., None] * scale, DISTANCE_MIN)
    sigma_s = single_scattering_albedo(color, g[..., None]) * sigma_t
    return Medium(sigma_t - sigma_s, sigma_s, g)


def openpbr_transmission_medium(color, depth, scatter=0.0, g=0.0,
                                spec: str = "1.1.1") -> Medium | None:
    """OpenPBR's translucent-base medium [OpenPBR2026, §Translucent base]: with T = color
    (raised to ``TRANSMITTANCE_MIN``), d = depth and S = scatter, under v1.1.1 (``spec``
    "1.1.1")

        sigma_t = -ln(T) / d,  sigma_s = S / d,  sigma_a = sigma_t - sigma_s,

    and where min(sigma_a) < 0 that minimum is subtracted from every channel's sigma_a (the
    specification's shift, which keeps the hue of the scattering). So light that travels d
    through the medium without scattering keeps exp(-sigma_t d) = T (Beer's law) when
    S <= -ln T in every channel. Under the development branch (``spec`` "dev_1.2",
    [OpenPBR2026dev, §Translucent base]) S is the single-scattering albedo: sigma_s =
    S sigma_t, sigma_a = (1 - S) sigma_t, with no shift (Beer's law always holds). ``None``
    at d = 0, where the specification has no medium and the colour is a tint on the
    refraction (the material applies it)."""
    T = _params.color("color", color, 0.0, 1.0)
    d = _params.real("depth", depth, 0.0, np.inf)
    S = _params.color("scatter", scatter, 0.0, 1.0)
    g = _params.real("g", g, -1.0, 1.0, lo_open=True, hi_open=True)
    _params.choice("spec", spec, ("1.1.1", "dev_1.2"))
    if np.all(d == 0.0):
        return None
    if np.any(d == 0.0):
        raise ValueError(f"depth = {d[d == 0.0].flat[0]!r} beside positive depths: a texture of "
                         "depths has a medium everywhere or nowhere (allowed: all > 0 or all 0)")
    sigma_t = -np.log(np.maximum(T, TRANSMITTANCE_MIN)) / d[..., None]
    if spec == "dev_1.2":
        return Medium((1.0 - S) * sigma_t, S * sigma_t, g)
    sigma_s = S / d[..., None]
    sigma_a = sigma_t - sigma_s
    shift = np.minimum(sigma_a.min(axis=-1, keepdims=True), 0.0)
    return Medium(sigma_a - shift, sigma_s, g)


class HalfSpaceAlbedo(NamedTuple):
    """Result of ``half_space_albedo`` (all ``(..., 3)`` like the input albedo).

    Attributes
    ----------
    value : the escaped energy (a lower bound when paths were cut).
    std_error : its Monte-Carlo standard error.
    truncated : the weight still inside after ``max_bounces`` (value + truncated bounds it
        from above).
    """

    value: np.ndarray
    std_error: np.ndarray
    truncated: np.ndarray


def half_space_albedo(albedo, n_paths: int = 100_000, seed=0, max_bounces: int = 20_000,
                      weight_min: float = 1e-6, incidence: str = "diffuse",
                      g=0.0) -> HalfSpaceAlbedo:
    """Diffuse reflectance of a homogeneous half-space of single-scattering ``albedo`` by a
    random walk: index-matched boundary (no Fresnel), Henyey–Greenstein phase function of
    asymmetry ``g`` in (-1, 1) (0: isotropic; the scattering turns the direction about a
    uniform azimuth, [Henyey1941]), absorption as a weight alpha^bounces. ``incidence``:
    "diffuse" (uniform radiance over the hemisphere: cosine-distributed entry directions, the
    albedo Kulla & Conty's inversion is fitted to, as measured in docs/asm_measured.md) or
    "normal" (a beam along the normal).

    The half-space has no length scale, so the result depends on the albedo alone (not on
    sigma_t): this measures what ``asm_medium`` makes of a Scattering Color (and
    ``openpbr_subsurface_medium`` of a subsurface_color, docs/media.md). Vectorised over
    paths; the loop runs over bounces, and paths leave the arrays when they escape or their
    weight falls below ``weight_min`` (their remaining weight is counted in ``truncated``).
    """
    alpha = _params.real("albedo", albedo, 0.0, 1.0)
    n_paths = _params.integer("n_paths", n_paths, 2)
    max_bounces = _params.integer("max_bounces", max_bounces, 1)
    _params.choice("incidence", incidence, ("normal", "diffuse"))
    g = float(_params.scalar("g", g, -1.0, 1.0, lo_open=True, hi_open=True))
    rng = np.random.default_rng(seed)
    flat = alpha.reshape(-1)
    total = np.zeros((flat.size, n_paths))  # escaped energy of every path
    cut = np.zeros(flat.size)
    channel = np.repeat(np.arange(flat.size), n_paths)
    path = np.tile(np.arange(n_paths), flat.size)
    z = np.zeros(channel.size)  # depth below the surface (optical units), z > 0 inside
    # cosine of the direction with the inward normal
    mu = np.ones(channel.size) if incidence == "normal" else np.sqrt(rng.random(channel.size))
    weight = np.ones(channel.size)
    for _ in range(max_bounces):
        z += mu * -np.log1p(-rng.random(z.size))  # free flight of unit optical length
        out = z < 0.0
        np.add.at(total, (channel[out], path[out]), weight[out])
        weight = weight * flat[channel]  # the scattering event
        faint = weight < weight_min
        np.add.at(cut, channel[faint & ~out], weight[faint & ~out])
        keep = ~out & ~faint
        channel, path, z, weight = channel[keep], path[keep], z[keep], weight[keep]
        if not channel.size:
            break
        if g == 0.0:
            mu = 2.0 * rng.random(channel.size) - 1.0  # isotropic
        else:  # turn the direction by the scattering angle, about a uniform azimuth
            cos = henyey_greenstein_cos(rng.random(channel.size), g)
            sin = np.sqrt((1.0 - cos) * (1.0 + cos))
            mu = (mu[keep] * cos + np.sqrt(np.maximum(1.0 - mu[keep] ** 2, 0.0)) * sin
                  * np.cos(2.0 * np.pi * rng.random(channel.size)))
    np.add.at(cut, channel, weight)
    shape = alpha.shape
    value = total.mean(axis=1)
    std = total.std(axis=1) / np.sqrt(n_paths)
    return HalfSpaceAlbedo(value.reshape(shape), std.reshape(shape),
                           (cut / n_paths).reshape(shape))
