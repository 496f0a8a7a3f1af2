"""The ASM metal: F82-tint Fresnel on a rough, anisotropic, rotated GGX conductor with
Kulla–Conty multiple scattering (seed 000 §1.2, §2, §3)."""

from __future__ import annotations

from adobe_bsdf import _params
from adobe_bsdf.fresnel import F82Tint
from adobe_bsdf.lobes.kulla_conty import ConductorMS
from adobe_bsdf.lobes.rotated import Rotated, anisotropy_rotation
from adobe_bsdf.microfacet import asm_alpha
from adobe_bsdf.registry import CheckCase, register

__all__ = ["asm_metal"]


def asm_metal(base_color, specular_edge_color=1.0, roughness=0.5, anisotropy_level=0.0,
              anisotropy_angle=0.0) -> Rotated:
    """The metallic lobe of the ASM.

    ``ConductorMS`` with alpha_x = r^2 + a^4, alpha_y = r^2 (eqs. 9-10), the F82-tint Fresnel
    of F0 = ``base_color`` and tint = ``specular_edge_color`` (eqs. 6-8), the multiple
    scattering scaled by ``base_color``^2 (§1.2), turned by 2 pi ``anisotropy_angle`` (§3).

    Parameters
    ----------
    base_color, specular_edge_color : colours in [0, 1]
    roughness, anisotropy_level, anisotropy_angle : array_like in [0, 1]
    """
    base_color = _params.color("base_color", base_color, 0.0, 1.0)
    edge = _params.color("specular_edge_color", specular_edge_color, 0.0, 1.0)
    roughness = _params.real("roughness", roughness, 0.0, 1.0)
    anisotropy_level = _params.real("anisotropy_level", anisotropy_level, 0.0, 1.0)
    alpha_x, alpha_y = asm_alpha(roughness, anisotropy_level)
    lobe = ConductorMS(alpha_x, alpha_y, fresnel=F82Tint(base_color, edge),
                       base_color=base_color)
    return Rotated(lobe, anisotropy_rotation(anisotropy_angle))


register(
    CheckCase("ASM metal gold r=0.4 a=0.6 angle=0.15",
              lambda: asm_metal((1.0, 0.7099, 0.3148), (0.9408, 0.9636, 0.9099), 0.4, 0.6, 0.15),
              furnace_tol=1e-3),
)
