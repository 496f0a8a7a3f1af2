"""The ASM's specular lobes assembled from the generic ones: the metal [Kutz2021, §1.2, §2, §3],
the dielectric's reflection and transmission [Kutz2021, §1.2, §3, §4] and the coat's
reflection [Kutz2021, §7 Table 4].

Each public factory validates its arguments and calls its kernel (``metal``, ``dielectric``,
``coat``), which the material calls directly with the parameters it has validated.
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf.composition import Rotated
from adobe_bsdf.fresnel import ExactDielectric, F82Tint
from adobe_bsdf.lobes.kulla_conty import ConductorMS, DielectricMS, DispersiveMS
from adobe_bsdf.lobes.reflection import DielectricReflection
from adobe_bsdf.materials.asm.mapping import COAT_IOR_RANGE, alphas, rotation
from adobe_bsdf.microfacet import GGX

__all__ = ["asm_metal", "asm_dielectric", "asm_coat"]

#: F82-tint's f90 and exponent in the ASM (the original model, [Kutz2021, eqs. 6-8])
_F90, _EXPONENT = np.ones(3), np.asarray(5.0)


def _unit(name: str, value) -> np.ndarray:
    return _params.real(name, value, 0.0, 1.0)


def metal(base_color, edge, roughness, level, angle) -> Rotated:
    """``asm_metal`` of validated arrays."""
    lobe = ConductorMS._new(GGX._new(*alphas(roughness, level)),
                            F82Tint._new(base_color, edge, _F90, _EXPONENT), base_color)
    return Rotated._new(lobe, rotation(angle))


def asm_metal(base_color, specular_edge_color=1.0, roughness=0.5, anisotropy_level=0.0,
              anisotropy_angle=0.0) -> Rotated:
    """The metallic lobe of the ASM.

    ``ConductorMS`` with alpha_x = r^2 + a^4, alpha_y = r^2 [Kutz2021, eqs. 9-10], the
    F82-tint Fresnel of F0 = ``base_color`` and tint = ``specular_edge_color``
    [Kutz2021, eqs. 6-8], the multiple scattering scaled by ``base_color``^2
    [Kutz2021, §1.2], turned by 2 pi ``anisotropy_angle`` [Kutz2021, §3].

    Parameters
    ----------
    base_color, specular_edge_color : colours in [0, 1]
    roughness, anisotropy_level, anisotropy_angle : array_like in [0, 1]
    """
    return metal(_params.color("base_color", base_color, 0.0, 1.0),
                 _params.color("specular_edge_color", specular_edge_color, 0.0, 1.0),
                 _unit("roughness", roughness), _unit("anisotropy_level", anisotropy_level),
                 _unit("anisotropy_angle", anisotropy_angle))


def dielectric(ior, roughness, level, angle, dispersion) -> Rotated:
    """``asm_dielectric`` of validated arrays."""
    microfacets = GGX._new(*alphas(roughness, level))
    if not np.any(dispersion):
        return Rotated._new(DielectricMS._new(ior, microfacets), rotation(angle))
    return Rotated._new(DispersiveMS._new(ior, dispersion, microfacets), rotation(angle))


def asm_dielectric(ior=1.5, roughness=0.5, anisotropy_level=0.0, anisotropy_angle=0.0,
                   dispersion=0.0) -> Rotated:
    """The specular reflection and transmission of the ASM's dielectric, with the Kulla–Conty
    multiple scattering that [Kutz2021, §1.2] applies to "refractive dielectrics (e.g.
    glass)" as to metals: a white one keeps its energy.

    ``DispersiveMS(ior, dispersion, alpha_x, alpha_y)`` (one index per channel by Cauchy's
    equation [Kutz2021, eqs. 11-13], each channel with its own term; ``DielectricMS`` where
    ``dispersion`` is 0 everywhere) with alpha_x = r^2 + a^4, alpha_y = r^2 [Kutz2021,
    eqs. 9-10], turned by 2 pi ``anisotropy_angle`` [Kutz2021, §3]. At roughness 0 with
    anisotropy > 0 the lobe is anisotropic, not a delta: alpha_y is raised to
    ``microfacet.ALPHA_MIN``. The terms read the energy tables: a channel's index beyond
    them (ior near 3 with a large dispersion) reads them at their end, with an
    ``EnergyRangeWarning`` giving the measured error (``energy_lookup.within_tables``).

    Parameters
    ----------
    ior : array_like in (0, inf)
        Index of the material under air (n_d).
    roughness, anisotropy_level, anisotropy_angle : array_like in [0, 1]
    dispersion : array_like in [0, inf)
        20 / Abbe number [Kutz2021, eq. 12]; 0 none, 1 the most dispersive real glass.
    """
    return dielectric(_params.real("ior", ior, 0.0, np.inf, lo_open=True),
                      _unit("roughness", roughness), _unit("anisotropy_level", anisotropy_level),
                      _unit("anisotropy_angle", anisotropy_angle),
                      _params.real("dispersion", dispersion, 0.0, np.inf))


def coat(coat_ior, roughness, level, angle) -> Rotated:
    """``asm_coat`` of validated arrays."""
    reflection = DielectricReflection._new(GGX._new(*alphas(roughness, level)),
                                           ExactDielectric._new(coat_ior))
    return Rotated._new(reflection, rotation(angle))


def asm_coat(coat_ior=1.6, coat_roughness=0.0, coat_anisotropy_level=0.0,
             coat_anisotropy_angle=0.0) -> Rotated:
    """The ASM coat's own reflection [Kutz2021, §7 Table 4]: ``DielectricReflection`` of
    ``coat_ior`` with the ASM alphas of the coat's roughness and anisotropy
    [Kutz2021, eqs. 9-10], turned by 2 pi ``coat_anisotropy_angle``; independent of the base's
    roughness. Light through the coat keeps its direction (Table 4: rays do not bend), so the
    coat contributes no refraction lobe: the base is seen through ``composition.Layer``."""
    return coat(_params.real("coat_ior", coat_ior, *COAT_IOR_RANGE),
                _unit("coat_roughness", coat_roughness),
                _unit("coat_anisotropy_level", coat_anisotropy_level),
                _unit("coat_anisotropy_angle", coat_anisotropy_angle))
