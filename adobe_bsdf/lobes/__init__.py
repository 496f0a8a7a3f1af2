"""Lobes: one small class per BSDF lobe, each with ``eval``, ``pdf``, ``sample``, ``albedo``.

``Lambert(albedo)``                                         ideal diffuse reflection
``Conductor(alpha_x, alpha_y=None, fresnel=None, masking)`` rough GGX reflection
``Dielectric(eta, alpha_x, alpha_y=None, masking)``         rough GGX reflection + refraction
"""

from adobe_bsdf.lobes.conductor import Conductor
from adobe_bsdf.lobes.dielectric import Dielectric
from adobe_bsdf.lobes.lambert import Lambert

__all__ = ["Lambert", "Conductor", "Dielectric"]
