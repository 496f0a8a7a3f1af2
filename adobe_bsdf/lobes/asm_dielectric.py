"""The ASM dielectric specular lobe: rough, anisotropic, rotated and dispersive reflection and
transmission (seed 000 §3, §4)."""

from __future__ import annotations

from adobe_bsdf import _params
from adobe_bsdf.lobes.dispersive import Dispersive
from adobe_bsdf.lobes.rotated import Rotated, anisotropy_rotation
from adobe_bsdf.microfacet import asm_alpha
from adobe_bsdf.registry import CheckCase, register

__all__ = ["asm_dielectric"]


def asm_dielectric(ior=1.5, roughness=0.5, anisotropy_level=0.0, anisotropy_angle=0.0,
                   dispersion=0.0) -> Rotated:
    """The specular reflection and transmission of the ASM's dielectric.

    ``Dispersive(ior, dispersion, alpha_x, alpha_y)`` (one index per channel by Cauchy's
    equation, eqs. 11-13; ``Dielectric`` exactly when ``dispersion`` is 0) with
    alpha_x = r^2 + a^4, alpha_y = r^2 (eqs. 9-10), turned by 2 pi ``anisotropy_angle`` (§3).
    At roughness 0 with anisotropy > 0 the lobe is anisotropic, not a delta: alpha_y is
    raised to ``microfacet.ALPHA_MIN``.

    Parameters
    ----------
    ior : array_like in (0, inf)
        Index of the material under air (n_d).
    roughness, anisotropy_level, anisotropy_angle : array_like in [0, 1]
    dispersion : array_like in [0, inf)
        20 / Abbe number (eq. 12); 0 none, 1 the most dispersive real glass.
    """
    ior = _params.real("ior", ior, 0.0, float("inf"), lo_open=True)
    roughness = _params.real("roughness", roughness, 0.0, 1.0)
    anisotropy_level = _params.real("anisotropy_level", anisotropy_level, 0.0, 1.0)
    alpha_x, alpha_y = asm_alpha(roughness, anisotropy_level)
    return Rotated(Dispersive(ior, dispersion, alpha_x, alpha_y),
                   anisotropy_rotation(anisotropy_angle))


register(
    CheckCase("ASM dielectric ior=1.5 r=0.4 a=0.7 angle=0.15 dispersion=0.5",
              lambda: asm_dielectric(1.5, 0.4, 0.7, 0.15, 0.5),
              cos_theta_o=(1.0, 0.5, -0.5)),
)
