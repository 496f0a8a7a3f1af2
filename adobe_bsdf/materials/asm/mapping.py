"""The ASM's parameter mappings: its roughness and anisotropy onto GGX alphas, its rotation,
the base's index under the coat and the coat's view-dependent tint [Kutz2021, §3, §7].

Public API
----------
``asm_alpha(roughness, anisotropy=0)``        (alpha_x, alpha_y) [Kutz2021, §3 eqs. 9-10]
``table_roughness(roughness, anisotropy)``    the isotropic roughness the tables stand in at
``anisotropy_rotation(anisotropy_angle)``     phi = 2 pi angle [Kutz2021, §3]
``base_ior_under_coat(ior, coat_ior, coat_opacity)``   [Kutz2021, §7 Table 4]
``CoatTransmittance(coat_color, coat_ior)``   t(w) of the coat's absorbing medium [Kutz2021, §7]
``coat_transmittance(coat_color, coat_ior, w)``        the same as a function
``COAT_IOR_RANGE``                            the coat's index range (the dielectric tables')

Each public function validates its arguments; the material, which has validated its
parameters once, calls the kernels (``alphas``, ``rotation``, ``ior_under_coat``) directly.
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params, tables
from adobe_bsdf.composition import coat_absorption

__all__ = ["asm_alpha", "table_roughness", "anisotropy_rotation", "base_ior_under_coat",
           "CoatTransmittance", "coat_transmittance", "COAT_IOR_RANGE"]

#: the coat's index (over air), the range of the dielectric tables
COAT_IOR_RANGE = (1.0, tables.ETA_MAX)


def alphas(r, a):
    """alpha_x = r^2 + a^4, alpha_y = r^2 of validated arrays (``asm_alpha``)."""
    return r * r + a**4, np.broadcast_to(r * r, np.broadcast_shapes(r.shape, a.shape)).copy()


def asm_alpha(roughness, anisotropy=0.0):
    """ASM anisotropic roughness: alpha_x = r^2 + a^4, alpha_y = r^2 [Kutz2021, §3 eqs. 9-10].

    ``roughness`` r and ``anisotropy`` a in [0, 1]. Returns ``(alpha_x, alpha_y)``.
    """
    return alphas(_params.real("roughness", roughness, 0.0, 1.0),
                  _params.real("anisotropy", anisotropy, 0.0, 1.0))


def effective_roughness(r, a):
    """``table_roughness`` of validated arrays."""
    alpha_x, alpha_y = alphas(r, a)
    r_eff = np.minimum(np.sqrt(np.sqrt(alpha_x * alpha_y)), 1.0)
    return np.where(np.asarray(a) == 0.0, r, r_eff)


def table_roughness(roughness, anisotropy_level):
    """The isotropic roughness at which the ASM tables stand in for an anisotropic lobe:
    r with r^2 = sqrt(alpha_x alpha_y) [Kutz2021, §3 eqs. 9-10], capped at the tables' 1
    (alpha_x reaches 2 at r = a = 1); r itself where the lobe is isotropic. An approximation
    for a > 0: its energy error is measured in ``docs/asm_measured.md``."""
    return effective_roughness(_params.real("roughness", roughness, 0.0, 1.0),
                               _params.real("anisotropy_level", anisotropy_level, 0.0, 1.0))


def rotation(angle):
    """``anisotropy_rotation`` of a validated array."""
    return 2.0 * np.pi * angle


def anisotropy_rotation(anisotropy_angle):
    """phi = 2 pi anisotropy_angle: the ASM rotation parameter is "normalized over the
    [0, 2 pi] domain" [Kutz2021, §3]; ``anisotropy_angle`` in [0, 1]."""
    return rotation(_params.real("anisotropy_angle", anisotropy_angle, 0.0, 1.0))


def ior_under_coat(ior, coat_ior, c):
    """``base_ior_under_coat`` of validated arrays."""
    eta = (1.0 - c) * ior + c * ior / coat_ior
    return np.where(eta < 1.0, 1.0 / eta, eta)


def base_ior_under_coat(ior, coat_ior, coat_opacity):
    """Relative index of the base surface with the coat above it [Kutz2021, §7 Table 4]:
    lerp(ior, ior / coat_ior, coat_opacity) (the blend over the coverage is the released
    OpenPBR's [OpenPBR2026, §Coat]), inverted where it falls below 1, so that rays that do
    not bend show no total internal reflection [Kutz2021, Fig. 17]."""
    return ior_under_coat(_params.real("ior", ior, 1.0, tables.ETA_MAX),
                          _params.real("coat_ior", coat_ior, *COAT_IOR_RANGE),
                          _params.real("coat_opacity", coat_opacity, 0.0, 1.0))


class CoatTransmittance(_params.Validated):
    """One-way transmittance t(w) ``(..., 3)`` of the coat's absorbing medium along ``w``.

    Beer's law over the path through a coat of thickness d and absorption sigma, at the
    refracted cosine mu_t = sqrt(1 - (1 - mu^2) / coat_ior^2): t = exp(-sigma d / mu_t). The
    ASM's coat colour is "the colour that should be reached by volumetric absorption"
    [Kutz2021, §7]: we fix sigma d so that the way in and out at normal incidence gives it,
    exp(-2 sigma d) = coat_color, hence (``composition.coat_absorption``, which OpenPBR's
    ``Layer(scaling="transmittance")`` shares)

        t(w) = coat_color ** (1 / (2 mu_t(w))).

    The pair t(wo) t(wi) is darker and more saturated at grazing angles, lighter in the
    middle [Kutz2021, Fig. 18], symmetric in wo and wi, and coat_color at normal incidence;
    mu_t >= sqrt(1 - 1/coat_ior^2) bounds the darkening. Directions below the surface use
    |mu|. ``view_dependent=False`` gives the uniform tint sqrt(coat_color) [Kutz2021,
    Fig. 18, left].

    Parameters
    ----------
    coat_color : colour in [0, 1]
    coat_ior : array_like in ``COAT_IOR_RANGE``
    view_dependent : bool
    """

    def __init__(self, coat_color, coat_ior, view_dependent: bool = True):
        self._init(_params.color("coat_color", coat_color, 0.0, 1.0),
                   _params.real("coat_ior", coat_ior, *COAT_IOR_RANGE), view_dependent)

    def _init(self, color, eta, view_dependent=True):
        self.color, self.eta, self.view_dependent = color, eta, bool(view_dependent)
        #: batch shape of the parameters (beyond the colour axis): a ``Layer`` over it
        #: samples group by group where it is ()
        self.param_shape = np.broadcast_shapes(np.shape(color)[:-1], np.shape(eta))

    def __repr__(self) -> str:
        return f"CoatTransmittance(coat_color={self.color}, coat_ior={self.eta})"

    def __call__(self, w) -> np.ndarray:
        color = self.color
        if not self.view_dependent:
            return np.broadcast_to(np.sqrt(color), np.broadcast_shapes(color.shape,
                                                                       np.shape(w)[:-1] + (3,)))
        return coat_absorption(color, self.eta, w)


def coat_transmittance(coat_color, coat_ior, w, view_dependent: bool = True) -> np.ndarray:
    """t(w) of ``CoatTransmittance(coat_color, coat_ior, view_dependent)``."""
    return CoatTransmittance(coat_color, coat_ior, view_dependent)(w)
