"""Lobes: one small class per generic BSDF lobe, each with ``eval``, ``pdf``, ``sample``,
``albedo``, parameterised physically (alphas, indices, colours, ``fresnel.Fresnel`` models).

``Lambert(albedo)``                                          ideal diffuse reflection
``MicrofacetReflection(alpha_x, alpha_y=None, fresnel=None, masking, model)``
                                                             rough reflection, any Fresnel
``Conductor(...)``                                           the same for a conductor
``DielectricReflection(eta, alpha_x, alpha_y=None)``         a dielectric's reflection alone
``ReferencedReflection(reference, fresnel)``                 any Fresnel, albedo by a reference
``Dielectric(eta, alpha_x, alpha_y=None, masking, model)``   rough reflection + refraction
                                                             (model "ggx" or "beckmann";
                                                             ``.over`` takes any distribution)
``Dispersive(eta, dispersion, alpha_x, alpha_y=None, ...)``  one index per RGB channel
``ConductorMultipleScattering`` / ``ConductorMS``            Kulla–Conty for metals
``DielectricMultipleScattering`` / ``DielectricMS``          Kulla–Conty for rough dielectrics
``DielectricMultipleReflection(eta, alpha_x, alpha_y, weight)``
                                                             its glossy multiple reflection
``Sheen(color, roughness, c=2, p=1)``                        microflake sheen
``EnergyPreservingOrenNayar(albedo, roughness)`` / ``EON``    rough diffuse [PortsmouthEON2025]
``LTCSheen(color, roughness)``                               LTC fuzz [Zeltner2022]
``HazyGloss(...)``, ``HazyDielectric(...)``                  hazy gloss [Barla2018]
``PassThrough()``                                            no interface (a null event)
``TintedRefraction(lobe, tint)``                             a DielectricMS, refraction tinted
``Retroreflective(lobe, weight)``                            reflection mixed with its copy
                                                             turned back towards the viewer
``ThinDielectric(eta, alpha_x, alpha_y=None, transmittance=1)``
                                                             thin translucent sheet, both sides

Operators that combine lobes (``Sum``, ``Mix``, ``Tinted``, ``Layer``, ``Rotated``) are in
``adobe_bsdf.composition``; material recipes (that of [Kutz2021]) under
``adobe_bsdf.materials``.
"""

from adobe_bsdf.lobes.dielectric import Dielectric
from adobe_bsdf.lobes.dispersive import Dispersive
from adobe_bsdf.lobes.hazy import HazyDielectric, HazyGloss
from adobe_bsdf.lobes.kulla_conty import (
    ConductorMS,
    ConductorMultipleScattering,
    DielectricMS,
    DielectricMultipleReflection,
    DielectricMultipleScattering,
)
from adobe_bsdf.lobes.lambert import Lambert
from adobe_bsdf.lobes.ltc_sheen import LTCSheen
from adobe_bsdf.lobes.oren_nayar import EON, EnergyPreservingOrenNayar
from adobe_bsdf.lobes.pass_through import PassThrough
from adobe_bsdf.lobes.reflection import (
    Conductor,
    DielectricReflection,
    MicrofacetReflection,
    ReferencedReflection,
)
from adobe_bsdf.lobes.retroreflection import Retroreflective
from adobe_bsdf.lobes.sheen import Sheen
from adobe_bsdf.lobes.thin_dielectric import ThinDielectric
from adobe_bsdf.lobes.tinted_refraction import TintedRefraction

__all__ = ["Lambert", "MicrofacetReflection", "Conductor", "DielectricReflection", "Dielectric",
           "ReferencedReflection", "Dispersive", "ConductorMultipleScattering", "ConductorMS",
           "DielectricMultipleScattering", "DielectricMultipleReflection", "DielectricMS",
           "Sheen", "HazyGloss",
           "HazyDielectric", "EnergyPreservingOrenNayar", "EON", "LTCSheen", "PassThrough",
           "ThinDielectric", "TintedRefraction", "Retroreflective"]
