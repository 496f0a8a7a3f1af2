"""The Adobe Standard Material's energy-conserving diffuse under its dielectric specular
[Kutz2021, §1.1 eq. 1]."""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params, tables
from adobe_bsdf._channels import pick
from adobe_bsdf.bsdf import Flags, luminance
from adobe_bsdf.composition import Sum
from adobe_bsdf.fresnel import ExactDielectric
from adobe_bsdf.lobes.energy_lookup import (
    anisotropic_reflection,
    anisotropic_reflection_average,
    grey,
    is_anisotropic,
    reflected_energy,
    slice_average,
    slice_energy,
    slice_source,
)
from adobe_bsdf.lobes.reflection import MicrofacetReflection
from adobe_bsdf.lobes.separable import Separable
from adobe_bsdf.materials.asm.mapping import alphas, effective_roughness
from adobe_bsdf.microfacet import GGX

__all__ = ["ASMSpecular", "ASMDiffuse", "asm_dielectric_base"]


def _roughness(roughness):
    return _params.real("roughness", roughness, 0.0, 1.0)


def _ior(ior):
    return _params.real("ior", ior, 1.0, tables.IOR_MAX)


def _anisotropic(microfacets):
    """Where ``microfacets`` (a GGX or None) is rough and anisotropic."""
    if microfacets is None:
        return np.asarray(False)
    return is_anisotropic(microfacets)


def _lobe_integral(roughness, ior, w, with_error=False, microfacets=None, slices=""):
    """``(L, error)``: L(w) of [Kutz2021, §1.1 eq. 1] (0 below the surface) and its node error
    (None unless ``with_error``): "asm_diffuse_L" at ``roughness``, plus, where the
    ``microfacets`` are anisotropic, what they reflect beyond the isotropic lobe at
    alpha = roughness^2 (``anisotropic_reflection``, the Fresnel moments), or, with
    ``slices`` (``slice_source``), E_R of their slice (``slice_energy``)."""
    up = w[..., 2] > 0.0
    aniso = _anisotropic(microfacets)
    if slices and np.all(aniso):  # every element reads its slice
        if microfacets.param_shape == () and np.ndim(ior) == 0 and w.ndim > 1:
            return _upper(ior, microfacets, w, up, with_error, slices)
        L, error = slice_energy(ior, microfacets, w, with_error, "reflection", slices)
        return pick(up, L, 0.0), None if error is None else pick(up, error, 0.0)
    L, error = reflected_energy("asm_diffuse_L", np.maximum(w[..., 2], 0.0),
                                roughness * roughness, ior, {"roughness": roughness, "ior": ior},
                                ior, with_error)
    if slices:
        E, error_s = slice_energy(ior, microfacets, w, with_error, "reflection", slices)
        L = pick(aniso, E, L)
        error = pick(aniso, error_s, error) if with_error else None
    elif np.any(aniso):
        dL, error_d = anisotropic_reflection(microfacets, _reference(roughness), ior, w,
                                             with_error)
        L = pick(aniso, np.clip(L + dL, 0.0, 1.0), L)
        error = pick(aniso, error + error_d, error) if with_error else None
    return pick(up, L, 0.0), None if error is None else pick(up, error, 0.0)


def _upper(ior, microfacets, w, up, with_error, slices):
    """``_lobe_integral`` of one anisotropic interface read from its slice at the directions
    above the surface only (0 below)."""
    if up.all():
        return slice_energy(ior, microfacets, w, with_error, "reflection", slices)
    index = np.nonzero(up)
    L = np.zeros(up.shape)
    error = np.zeros(up.shape) if with_error else None
    E, error_s = slice_energy(ior, microfacets, w[index], with_error, "reflection", slices)
    L[index] = E
    if with_error:
        error[index] = error_s
    return L, error


def _reference(roughness):
    """The isotropic GGX of the tables' roughness (alpha = roughness^2)."""
    return GGX._new(roughness * roughness, roughness * roughness)


def _lobe_average(roughness, ior, microfacets, slices=""):
    """T = (1/pi) int L cos: "asm_diffuse_T", plus the anisotropic part's exact average (or,
    with ``slices``, the slice's average of E_R)."""
    T = tables.get("asm_diffuse_T")(roughness, ior)[..., 0]
    aniso = _anisotropic(microfacets)
    if slices:
        T = pick(aniso, slice_average(ior, microfacets, slices, "reflection")[0][..., 0], T)
    elif np.any(aniso):
        T = pick(aniso, T + anisotropic_reflection_average(
            microfacets, _reference(roughness), ior), T)
    return T


class ASMSpecular(MicrofacetReflection):
    """The specular term S of [Kutz2021, §1.1]: GGX reflection with the exact dielectric
    Fresnel of ``ior``, alpha_x = r^2 + a^4, alpha_y = r^2 [Kutz2021, §3 eqs. 9-10]. Its
    albedo is the lobe integral L, tabulated as ``asm_diffuse_L`` where isotropic and
    from the anisotropic Fresnel moments ``ggx_reflection_moments`` where not. Turn it with
    ``Rotated`` for the anisotropy angle.

    Parameters
    ----------
    roughness : array_like in [0, 1]
    ior : array_like in [1, 4]
        Index of the material under air.
    anisotropy_level : array_like in [0, 1]
    """

    def __init__(self, roughness, ior, anisotropy_level=0.0):
        self._init(_roughness(roughness), _ior(ior),
                   _params.real("anisotropy_level", anisotropy_level, 0.0, 1.0))

    def _init(self, roughness, ior, anisotropy_level):
        self.roughness, self.ior, self.anisotropy_level = roughness, ior, anisotropy_level
        super()._init(GGX._new(*alphas(roughness, anisotropy_level)), ExactDielectric._new(ior))
        self._table_r = effective_roughness(roughness, anisotropy_level)
        #: L from the lobe's slice where anisotropic (``config`` anisotropic_energy)
        self.slices = slice_source(self.distribution)

    def __repr__(self) -> str:
        return (f"ASMSpecular(roughness={self.roughness}, ior={self.ior}, "
                f"anisotropy_level={self.anisotropy_level})")

    def _albedo_table(self, wo, with_error=True):
        L, error = _lobe_integral(self._table_r, self.ior, wo, with_error, self.distribution,
                                  self.slices)
        return grey(L), grey(error)


class ASMDiffuse(Separable):
    """Energy-conserving diffuse of [Kutz2021, §1.1 eq. 1] after [Ashikhmin2000]:

        D(wi, wo) = rho / pi (1 - L(wi)) (1 - L(wo)) / (1 - T)

    L(w) = int S(w, w') dsigma_perp(w') is the albedo of ``ASMSpecular`` and
    T = (1/pi) int L dsigma_perp its average. Reciprocal, separable, and with rho = 1 the sum
    D + S scatters all energy (the white furnace of [Kutz2021, Fig. 2]). T is the exact
    average of the interpolated L (``tables``), so that property holds up to L's
    interpolation error. Under an anisotropic specular, L = L(wo) depends on the azimuth
    (the Fresnel moments) and T averages over it: the diffuse is then anisotropic too and
    is turned with the specular. Cosine-sampled; one-sided.

    Parameters
    ----------
    albedo : colour in [0, 1]
        rho, the diffuse base colour.
    roughness : array_like in [0, 1]
        Roughness of the specular lobe it sits under.
    ior : array_like in [1, 4]
        Index of the specular interface.
    anisotropy_level : array_like in [0, 1]
        That of the specular lobe (its alphas r^2 + a^4, r^2).
    """

    flags = Flags.REFLECTION | Flags.DIFFUSE

    def __init__(self, albedo, roughness, ior, anisotropy_level=0.0):
        self._init(_params.color("albedo", albedo, 0.0, 1.0), _roughness(roughness), _ior(ior),
                   _params.real("anisotropy_level", anisotropy_level, 0.0, 1.0))

    def _init(self, reflectance, roughness, ior, anisotropy_level=None):
        a = np.asarray(0.0) if anisotropy_level is None else anisotropy_level
        self.reflectance, self.roughness, self.ior, self.anisotropy_level = (
            reflectance, roughness, ior, a)
        self._table_r = effective_roughness(roughness, a)
        self.microfacets = GGX._new(*alphas(roughness, a)) if np.any(a > 0.0) else None
        #: L from the specular's slice where anisotropic (``config`` anisotropic_energy)
        self.slices = "" if self.microfacets is None else slice_source(self.microfacets)
        T = _lobe_average(self._table_r, self.ior, self.microfacets, self.slices)
        self._scale = self.reflectance / (np.pi * (1.0 - T))[..., None]

    def __repr__(self) -> str:
        return (f"ASMDiffuse(albedo={self.reflectance}, roughness={self.roughness}, "
                f"ior={self.ior}, anisotropy_level={self.anisotropy_level})")

    def _param_shape(self):
        return np.broadcast_shapes(self.roughness.shape, self.ior.shape,
                                   self.anisotropy_level.shape, self.reflectance.shape[:-1])

    def _L(self, w, with_error=False):
        return _lobe_integral(self._table_r, self.ior, w, with_error, self.microfacets,
                              self.slices)

    def _X(self, w):
        """1 - L(w), at least 0: the interpolated L can overshoot 1 by ~1e-8 at small
        roughness, which would make the diffuse term negative."""
        return np.maximum(1.0 - self._L(w)[0], 0.0)

    def _coefficient(self, wo, wi):
        return self._scale

    def _albedo_table(self, wo, with_error=True):
        """rho (1 - L(wo)), exact for the tabulated L."""
        L, error = self._L(wo, with_error)
        up = (wo[..., 2] > 0.0)[..., None]
        return (pick(up, self.reflectance * np.maximum(1.0 - L, 0.0)[..., None], 0.0),
                None if error is None else self.reflectance * error[..., None])

    def _sampling_weight(self, wo):
        return luminance(self.reflectance) * pick(wo[..., 2] > 0.0, self._X_at(wo), 0.0)


def asm_dielectric_base(albedo, roughness, ior) -> Sum:
    """``ASMSpecular`` + ``ASMDiffuse``: the ASM dielectric base [Kutz2021, §1.1]; with
    albedo 1 it scatters all energy at every angle."""
    albedo = _params.color("albedo", albedo, 0.0, 1.0)
    roughness, ior = _roughness(roughness), _ior(ior)
    return Sum._new((ASMSpecular._new(roughness, ior, _ZERO),
                     ASMDiffuse._new(albedo, roughness, ior)))


_ZERO = np.asarray(0.0)
