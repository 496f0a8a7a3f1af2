"""OpenPBR v1.1.1's parameter mappings [OpenPBR2026]: roughness and anisotropy onto GGX
alphas, the tangent's rotation, the base's index under a partial coat, the specular-weight
modulation of that index, the base's roughening by the coat, and the metal's F82-tint
Fresnel with its Kulla–Conty colour.

Public API
----------
``anisotropic_alphas(roughness, anisotropy)``   (alpha_t, alpha_b) [§Microfacet model]
``tangent_rotation(tangent)``                   phi of a tangent in the local frame
``effective_ior(specular_ior, coat_ior, coat_weight)``   eta_s with the TIR fix [§Coat]
``specular_ior_modulation(eta_s, specular_weight)``      eta'_s [§Dielectric base]
``base_roughening(roughness, coat_roughness, coat_weight)``   r'_B [§Coat]
``f82_average(f0, tint)``                       hemispherical average of F82-tint (exact)
``metal_multiple_scattering(f_avg, E_avg)``      Kulla–Conty's colour of the metal's
                                                multiple scattering [KullaConty2017]
``emission_radiance(luminance, color)``         radiometric RGB of emission_luminance (nits)
                                                and emission_color [§Emission]
``LUMINOUS_EFFICACY``                           683 lm/W, the photometric conversion

Each function takes validated float64 arrays (the material has checked its parameters
once); colours are ``(..., 3)``.
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf.fresnel import COS_THETA_MAX

__all__ = ["anisotropic_alphas", "tangent_rotation", "effective_ior",
           "specular_ior_modulation", "base_roughening", "f82_average",
           "metal_multiple_scattering", "reflectance_at_normal", "emission_radiance",
           "LUMINOUS_EFFICACY"]

#: lm/W: the luminous efficacy that defines the candela (radiation of 540 THz), by which a
#: luminance in nits becomes a radiance in W m^-2 sr^-1 [BIPM2019, §2.3.1]
LUMINOUS_EFFICACY = 683.0


def anisotropic_alphas(roughness, anisotropy):
    """alpha_t = r^2 sqrt(2 / (1 + (1 - a)^2)), alpha_b = (1 - a) alpha_t
    [OpenPBR2026, §Microfacet model]: alpha_t^2 + alpha_b^2 = 2 r^4 whatever a, so the mean
    squared slope does not change with the anisotropy; a = 0 is alpha = r^2, a = 1 a pure
    groove (alpha_b = 0, which ``microfacet.GGX`` raises to ``ALPHA_MIN``)."""
    r2 = roughness * roughness
    b = 1.0 - anisotropy
    alpha_t = r2 * np.sqrt(2.0 / (1.0 + b * b))
    return alpha_t, b * alpha_t


def tangent_rotation(tangent):
    """phi = atan2(t_y, t_x): the angle about the normal from the local frame's x axis to the
    tangent ``(..., 3)`` (its normal component does not turn the lobe); a tangent along the
    normal leaves the frame as it is (phi = 0). Flipping the tangent turns by pi, which
    leaves every lobe as it is (the GGX distribution is symmetric)."""
    return np.arctan2(tangent[..., 1], tangent[..., 0])


def effective_ior(specular_ior, coat_ior, coat_weight, ambient_ior=1.0):
    """eta_s = lerp(n_b / n_a, n_b / n_c, C) [OpenPBR2026, §Coat], with the TIR fix of
    [OpenPBR2026, §Total internal reflection; Kutz2021, §7]: where n_c > n_b the ratio under
    the coat is n_c / n_b, so a dense coat never makes the base interface totally reflect."""
    n_b, n_c = specular_ior, coat_ior
    under = np.where(n_c > n_b, n_c / n_b, n_b / n_c)
    return (1.0 - coat_weight) * (n_b / ambient_ior) + coat_weight * under


def reflectance_at_normal(eta):
    """F_s = ((1 - eta) / (1 + eta))^2."""
    return ((1.0 - eta) / (1.0 + eta)) ** 2


def specular_ior_modulation(eta_s, specular_weight):
    """eta'_s = (1 + eps) / (1 - eps), eps = sgn(eta_s - 1) sqrt(xi F_s), xi clamped to
    0 <= xi <= 1 / F_s ([OpenPBR2026, §Dielectric base]): the relative index whose normal-incidence
    reflectance is specular_weight times that of eta_s (xi = 0: eta' = 1, no reflection;
    xi F_s = 1 would be an infinite index: it is kept below 1 by one part in 1e12, an index
    of ~4e6, which the caller's range check refuses)."""
    F_s = reflectance_at_normal(eta_s)
    xi_F = np.minimum(specular_weight * F_s, 1.0 - 1e-12)
    eps = np.sign(eta_s - 1.0) * np.sqrt(xi_F)
    return (1.0 + eps) / (1.0 - eps)


def base_roughening(roughness, coat_roughness, coat_weight):
    """r'_B = lerp(r_B, min(1, r_B^4 + 2 r_C^4)^(1/4), C) [OpenPBR2026, §Coat]: a rough coat
    widens the lobes of the base seen through it."""
    rough = np.minimum(1.0, roughness**4 + 2.0 * coat_roughness**4) ** 0.25
    return (1.0 - coat_weight) * roughness + coat_weight * rough


def f82_average(f0, tint):
    """2 int_0^1 F82(mu) mu dmu = F0 + (1 - F0) / 21 - b / 126, b = (F_Schlick(mu_bar) -
    F(mu_bar)) / (mu_bar (1 - mu_bar)^6), mu_bar = 1/7 [OpenPBR2026, §Metal, footnote on the
    average of F82] (the beta integrals 2 B(2, 6) = 1/21 and 2 B(3, 7) = 1/126), for the
    unclamped polynomial ``fresnel.f82_tint`` clamps to [0, 1] only for extreme tints."""
    mu = COS_THETA_MAX
    schlick = f0 + (1.0 - f0) * (1.0 - mu) ** 5
    b = schlick * (1.0 - tint) / (mu * (1.0 - mu) ** 6)
    return f0 + (1.0 - f0) / 21.0 - b / 126.0


def metal_multiple_scattering(f_avg, E_avg):
    """F_ms = F_avg^2 E_avg / (1 - F_avg (1 - E_avg)) [KullaConty2017]: the colour of the
    energy a metal of average Fresnel ``f_avg`` reflects after two or more bounces, relative
    to a white metal's (1 - E_avg); 1 for a white metal, so it keeps the white furnace."""
    f_avg = np.clip(f_avg, 0.0, 1.0)
    E_avg = np.asarray(E_avg)[..., None]
    return f_avg * f_avg * E_avg / (1.0 - f_avg * (1.0 - E_avg))


def emission_radiance(luminance, color):
    """RGB radiance (W m^-2 sr^-1 per unit of linear Rec. 709) L_e = L_v / K_m · C of
    emission_luminance L_v (nits) and emission_color C [OpenPBR2026, §Emission]: the colour
    (1, 1, 1), whose Rec. 709 luminance Y is 1, emits luminance K_m Y L_e = L_v exactly, with
    K_m = ``LUMINOUS_EFFICACY`` (the library's convention: the specification leaves the
    conversion to the renderer)."""
    return color * (luminance / LUMINOUS_EFFICACY)[..., None]
