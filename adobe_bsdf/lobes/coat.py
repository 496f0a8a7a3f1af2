"""The ASM coat: a rough dielectric reflection that does not bend rays, its view-dependent
absorption tint, and the base's relative index under it (seed 000 §7, Table 4)."""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params, quadrature, tables
from adobe_bsdf.fresnel import ExactDielectric
from adobe_bsdf.lobes.conductor import Conductor
from adobe_bsdf.lobes.energy_lookup import checked_ratio, grey, sides, table_alpha
from adobe_bsdf.lobes.rotated import Rotated, anisotropy_rotation
from adobe_bsdf.microfacet import asm_alpha
from adobe_bsdf.registry import CheckCase, register

__all__ = ["DielectricReflection", "asm_coat", "coat_transmittance", "base_ior_under_coat",
           "COAT_IOR_RANGE"]

#: the coat's index (over air), the range of the dielectric tables
COAT_IOR_RANGE = (1.0, tables.ETA_MAX)


class DielectricReflection(Conductor):
    """The reflection of a rough dielectric interface alone: GGX microfacet reflection with
    the exact dielectric Fresnel of relative index ``eta`` (Walter et al. 2007 eq. 20), no
    refraction. Its albedo table is E_R of the dielectric tables (seen from the light side
    for eta >= 1, from the dense side for eta < 1) at sqrt(alpha_x alpha_y).

    Parameters
    ----------
    eta : array_like in [1/3, 3]
        n below / n above.
    alpha_x, alpha_y : array_like in [0, 2]
    """

    def __init__(self, eta, alpha_x, alpha_y=None):
        super().__init__(alpha_x, alpha_y, fresnel=ExactDielectric(eta))
        self.eta = self.fresnel.eta

    def __repr__(self) -> str:
        return f"DielectricReflection(eta={self.eta!r}, {self.distribution!r})"

    def _top_albedo(self, wo):
        """The table where isotropic; where anisotropic, the table at sqrt(alpha_x alpha_y)
        misses the true albedo by up to ~0.04 at grazing angles (either way), so a layer
        under it would gain energy: there E is ``quadrature.sampled_albedo`` (32 x 32
        visible normals per distinct ``wo``)."""
        d = self.distribution
        if np.all((d.alpha_x == d.alpha_y) | d.smooth):
            return super()._top_albedo(wo)
        return quadrature.sampled_albedo(self, wo)

    def _albedo_table(self, wo, with_error=True):
        alpha, ratio = table_alpha(self.distribution), checked_ratio(self.eta)
        mu = np.maximum(wo[..., 2], 0.0)
        outside = tables.get("ggx_dielectric_outside")
        inside = tables.get("ggx_dielectric_inside")
        light = sides(self.eta)[0]
        E = np.where(light, outside(mu, alpha, ratio)[..., 0], inside(mu, alpha, ratio)[..., 0])
        error = (np.where(light, outside.error(mu, alpha, ratio)[..., 0],
                          inside.error(mu, alpha, ratio)[..., 0]) if with_error else None)
        up = wo[..., 2] > 0.0
        return grey(np.where(up, E, 0.0)), grey(None if error is None else np.where(up, error, 0))


def asm_coat(coat_ior=1.6, coat_roughness=0.0, coat_anisotropy_level=0.0,
             coat_anisotropy_angle=0.0) -> Rotated:
    """The ASM coat's own reflection (Table 4): ``DielectricReflection`` of ``coat_ior`` with
    the ASM alphas of the coat's roughness and anisotropy (eqs. 9-10), turned by
    2 pi ``coat_anisotropy_angle``; independent of the base's roughness. Light through the coat
    keeps its direction (Table 4: rays do not bend), so the coat contributes no refraction
    lobe: the base is seen through ``layering.Layer``."""
    coat_ior = _params.real("coat_ior", coat_ior, *COAT_IOR_RANGE)
    roughness = _params.real("coat_roughness", coat_roughness, 0.0, 1.0)
    level = _params.real("coat_anisotropy_level", coat_anisotropy_level, 0.0, 1.0)
    angle = _params.real("coat_anisotropy_angle", coat_anisotropy_angle, 0.0, 1.0)
    return Rotated(DielectricReflection(coat_ior, *asm_alpha(roughness, level)),
                   anisotropy_rotation(angle))


def coat_transmittance(coat_color, coat_ior, w, view_dependent: bool = True) -> np.ndarray:
    """One-way transmittance t(w) ``(..., 3)`` of the coat's absorbing medium along ``w``.

    Beer's law over the path through a coat of thickness d and absorption sigma, at the
    refracted cosine mu_t = sqrt(1 - (1 - mu^2) / coat_ior^2): t = exp(-sigma d / mu_t). The
    ASM's coat colour is "the colour that should be reached by volumetric absorption"
    (seed 000 §7): we fix sigma d so that the way in and out at normal incidence gives it,
    exp(-2 sigma d) = coat_color, hence

        t(w) = coat_color ** (1 / (2 mu_t(w))).

    The pair t(wo) t(wi) is darker and more saturated at grazing angles, lighter in the
    middle (Fig. 18), symmetric in wo and wi, and coat_color at normal incidence; mu_t >=
    sqrt(1 - 1/coat_ior^2) bounds the darkening. Directions below the surface use |mu|.
    ``view_dependent=False`` gives the uniform tint sqrt(coat_color) (Fig. 18, left).
    """
    color = _params.color("coat_color", coat_color, 0.0, 1.0)
    if not view_dependent:
        return np.broadcast_to(np.sqrt(color), np.broadcast_shapes(color.shape,
                                                                   np.shape(w)[:-1] + (3,)))
    eta = _params.real("coat_ior", coat_ior, *COAT_IOR_RANGE)
    mu = np.abs(np.asarray(w)[..., 2])
    mu_t = np.sqrt(1.0 - (1.0 - mu * mu) / (eta * eta))
    with np.errstate(divide="ignore"):
        exponent = np.where(mu_t > 0.0, 0.5 / mu_t, np.inf)  # mu_t = 0: grazing, coat_ior 1
    with np.errstate(divide="ignore", invalid="ignore"):
        t = color ** exponent[..., None]
    return np.where(color == 1.0, 1.0, np.where(color == 0.0, 0.0, t))


def base_ior_under_coat(ior, coat_ior, coat_opacity):
    """Relative index of the base surface with the coat above it (seed 000 §7, Table 4):
    lerp(ior, ior / coat_ior, coat_opacity) (the blend over the coverage is OpenPBR
    v1.1.1's, ``shared/reference/openpbr_settled_choices.md``), inverted where it falls below
    1, so that rays that do not bend show no total internal reflection (Fig. 17)."""
    ior = _params.real("ior", ior, 1.0, tables.ETA_MAX)
    coat_ior = _params.real("coat_ior", coat_ior, *COAT_IOR_RANGE)
    c = _params.real("coat_opacity", coat_opacity, 0.0, 1.0)
    eta = (1.0 - c) * ior + c * ior / coat_ior
    return np.where(eta < 1.0, 1.0 / eta, eta)


register(
    CheckCase("ASM coat ior=1.6 r=0.2 a=0.5 angle=0.1", lambda: asm_coat(1.6, 0.2, 0.5, 0.1)),
    CheckCase("DielectricReflection eta=1/1.5 a=0.3", lambda: DielectricReflection(1 / 1.5, 0.3),
              cos_theta_o=(1.0, 0.5, 0.1)),
)
