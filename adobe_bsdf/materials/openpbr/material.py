"""OpenPBR Surface as one BSDF, following the released v1.1.1 [OpenPBR2026] or, with
``spec="dev_1.2"``, its development branch [OpenPBR2026dev] (the parameter table, every choice
and the behaviours that depend on the version are in ``docs/openpbr.md``)
[Andersson2023, §Model]:

    surface     = layer(coated-base, fuzz, fuzz_weight)
    coated-base = layer(base, coat, coat_weight)
    PBR         = mix(ambient, surface, geometry_opacity)
    base        = mix(dielectric-base, metal, base_metalness)
    dielectric  = mix(opaque-base, translucent-base, transmission_weight)
    opaque-base = mix(glossy-diffuse, subsurface, subsurface_weight)

Each mix is ``composition.Mix``; each layer ``composition.Layer`` by albedo scaling, the
coat's with its absorption ("transmittance") and darkening. The glossy-diffuse
slab is the dielectric's reflection over the energy-preserving Oren–Nayar diffuse (the
reflection ``Tinted`` by specular_color), so a white diffuse keeps all the energy
E_spec + (1 - E_spec) = 1 and a Lambertian one reflects E_diffuse = (1 - E_spec) C. Lobes of
zero weight everywhere are never built (``OpenPBRSurface.lobes`` lists the ones that were).
The ambient medium of the opacity mix is ``lobes.PassThrough``; ``emission(wo)`` is the
substrate's emission through the coat and the fuzz, ``shadow_transmittance(wo)`` v1.1.1's
T_pbr for transparent shadows.
"""

from __future__ import annotations

import warnings

import numpy as np

from adobe_bsdf import _params, media
from adobe_bsdf.composition import Facing, Flipped, Layer, Mix, Rotated, Sum, Tinted
from adobe_bsdf.darkening import Darkening
from adobe_bsdf.fresnel import ExactDielectric, F82Tint, Weighted
from adobe_bsdf.lobes.energy_lookup import conductor_average
from adobe_bsdf.lobes.hazy import HazyDielectric, HazyGloss
from adobe_bsdf.lobes.kulla_conty import ConductorMS, DielectricMS, DispersiveMS
from adobe_bsdf.lobes.ltc_sheen import LTCSheen
from adobe_bsdf.lobes.oren_nayar import EnergyPreservingOrenNayar
from adobe_bsdf.lobes.pass_through import PassThrough
from adobe_bsdf.lobes.reflection import DielectricReflection, ReferencedReflection
from adobe_bsdf.lobes.retroreflection import Retroreflective
from adobe_bsdf.lobes.thin_dielectric import ThinDielectric
from adobe_bsdf.lobes.tinted_refraction import TintedRefraction
from adobe_bsdf.materials.material import Material
from adobe_bsdf.materials.openpbr import draft, mapping
from adobe_bsdf.materials.openpbr.parameters import DEV_1_2, GATES, PARAMETERS, PLANNED, SPECS
from adobe_bsdf.microfacet import GGX
from adobe_bsdf.tables import ETA_MAX
from adobe_bsdf.thin_film import MODELS, ThinFilm

__all__ = ["OpenPBRSurface", "ETA_RANGE", "HAZE_MODELS", "SPECS", "versions"]

#: the specular haze (deprecated ``haze_model``): the development branch's blend of two
#: roughnesses, or the hazy gloss of [Barla2018]
HAZE_MODELS = ("dev_1.2", "barla2018")
#: what each deprecated ``darkening_variant`` and ``haze_model`` now means: the ``spec``
_ALIASES = {"darkening_variant": {"v1.1.1": "1.1.1", "pr253": "dev_1.2"},
            "haze_model": {"dev_1.2": "dev_1.2", "barla2018": "dev_1.2"}}

#: relative indices the energy tables hold (dielectric reflection, Kulla–Conty, darkening)
ETA_RANGE = (1.0 / ETA_MAX, ETA_MAX)
_F90, _EXPONENT = np.ones(3), np.asarray(5.0)


def _any(x) -> bool:
    return bool(np.any(np.asarray(x) != 0.0))


def _c(x):
    """A per-element weight ``(...)`` as a colour ``(..., 3)``."""
    return _params.as_color(np.asarray(x, dtype=np.float64)[..., None])


def _turned(lobe, phi):
    return Rotated._new(lobe, phi) if _any(phi) else lobe


def _in_tables(name: str, eta) -> None:
    lo, hi = ETA_RANGE
    bad = (eta < lo) | (eta > hi)
    if np.any(bad):
        raise ValueError(f"{name} gives a relative index {np.asarray(eta)[bad].flat[0]!r} at "
                         f"the interface; allowed: [{lo:.6g}, {hi:g}] (the range of the "
                         "energy tables)")


class OpenPBRSurface(Material):
    """OpenPBR Surface [OpenPBR2026] (module docstring): keyword arguments are the
    specification's 41 inputs (``PARAMETERS``: kind, default, hard and soft range) and, under
    ``spec="dev_1.2"``, the four the development branch adds (``DEV_1_2``); each broadcasts,
    so a texture of parameters evaluates in one call. The inputs not modelled (``PLANNED``:
    the normal maps, left to the caller, ``docs/openpbr.md``) are accepted and stored;
    setting one away from its default warns.

    Lobes (``lobes`` names the ones built):
    - "metal": ``ConductorMS`` (Kulla–Conty) with ``fresnel.F82Tint`` of F0 = base_weight
      base_color and tint specular_color at mu_bar = 1/7, times min(specular_weight, 1)
      (1.1.1) or clamped to [0, 1] after the product (dev_1.2); its multiple scattering
      coloured by ``mapping.metal_multiple_scattering``;
    - "specular": the dielectric's reflection at the modulated index
      (``mapping.effective_ior``, ``mapping.specular_ior_modulation``), ``Tinted`` by
      specular_color, over "diffuse" (``EnergyPreservingOrenNayar`` of base_weight
      base_color) and "subsurface" (the same of subsurface_color: the slab's dense limit);
    - "transmission": ``DielectricMS`` at the modulated index (``DispersiveMS`` with
      dispersion, ``TintedRefraction`` by transmission_color at depth 0; thin-walled:
      ``ThinDielectric``);
    - "coat": the coat's reflection (index coat_ior) over the base, with coverage
      coat_weight, coat_color its two-way transmittance at normal incidence, the base
      roughened (``mapping.base_roughening``) and darkened (``darkening.Darkening``) as the
      ``spec`` says (``docs/openpbr.md``, the versions);
    - "fuzz": ``LTCSheen`` of fuzz_roughness, ``Tinted`` by fuzz_color, coverage fuzz_weight;
    - "pass-through": ``PassThrough`` of weight 1 - geometry_opacity (the ambient medium).
    Anisotropy: ``mapping.anisotropic_alphas``, turned to ``geometry_tangent`` (base) and
    ``geometry_coat_tangent`` (coat). Under dev_1.2, specular_haze blends a rougher copy of
    the metal and dielectric lobes and specular_retroreflectivity their retroreflective copy
    (``lobes.Retroreflective``, the reflection only).

    Parameters
    ----------
    spec : one of ``SPECS``
        "1.1.1" (the default): the released specification [OpenPBR2026], as MaterialX 1.39
        and Adobe's implementation follow it; "dev_1.2": the development branch
        [OpenPBR2026dev]: its four inputs, the coat darkening of [Portsmouth2025] (from the
        naive albedo at coat_darkening 0 to the physical one at 1, ``darkening.Darkening``
        "dev_1.2"), transmission_scatter as a single-scattering albedo, a metal's
        specular_weight above 1.
    **params
        The inputs, named as in ``docs/openpbr.md``.
    thin_film_model : one of ``thin_film.MODELS``
        "spectral" (the default): the film's colour integrated over the spectrum, the
        reference; "three_wavelengths": each channel's reflectance at one wavelength
        (``thin_film.CHANNEL_WAVELENGTHS_NM``), as RGB renderers that evaluate the film so
        compute it (``docs/thin_film_wavelengths.md``).
    darkening_variant, haze_model : deprecated
        Aliases of ``spec`` for one release (a ``DeprecationWarning``): darkening_variant
        "v1.1.1" is spec "1.1.1", "pr253" is "dev_1.2"; haze_model "dev_1.2" is spec
        "dev_1.2", and "barla2018" the same with specular_haze as the composite hazy gloss of
        [Barla2018] (haziness = specular_haze, haze extent = specular_haze_spread).
    """

    #: the inputs, their ranges and defaults
    parameters = PARAMETERS

    def __init__(self, *, spec: str | None = None, darkening_variant: str | None = None,
                 haze_model: str | None = None, thin_film_model: str = "spectral", **params):
        self.spec, barla = _version(spec, darkening_variant, haze_model, params)
        #: how the thin film's colour is evaluated (``thin_film.MODELS``)
        self.thin_film_model = _params.choice("thin_film_model", thin_film_model, MODELS)
        self.haze_model = "barla2018" if barla else "dev_1.2"
        p = self.params = PARAMETERS.validate(params)
        if self.spec == "1.1.1":  # dev_1.2's inputs are not the release's
            for name in DEV_1_2:
                del p[name]
        self._hazy = _any(p.get("specular_haze", 0.0))
        self.thin_walled = _thin_walled(p["geometry_thin_walled"])
        self.planned = tuple(name for name in PLANNED if _acts(p, name))
        if self.planned:
            warnings.warn(f"OpenPBRSurface: {', '.join(self.planned)} not modelled yet: the "
                          "values are stored and have no effect (docs/openpbr.md)",
                          stacklevel=2)
        built = {}
        C, M = p["coat_weight"], p["base_metalness"]
        coat = _any(C)
        r = mapping.base_roughening(p["specular_roughness"], p["coat_roughness"], C) \
            if coat else p["specular_roughness"]
        self._roughness = r
        if self._hazy and barla and np.any(r == 0.0):
            raise ValueError("specular_roughness = 0 with specular_haze > 0 and haze_model = "
                             "'barla2018': allowed a roughness in (0, 1] (a smooth core has "
                             "no halo)")
        self._film = self._thin_film(C if coat else None)
        phi = mapping.tangent_rotation(p["geometry_tangent"])
        metal = self._metal(r, phi) if _any(M) else None
        #: the dielectric base's modulated relative index (None without a dielectric base)
        eta_s = dielectric = self._eta = None
        if _any(1.0 - M):
            eta_s = mapping.effective_ior(p["specular_ior"], p["coat_ior"], C)
            eta = mapping.specular_ior_modulation(eta_s, p["specular_weight"])
            _in_tables("specular_ior (with specular_weight and the coat)", eta)
            self._eta = eta
            dielectric = self._dielectric(eta, r, phi, built)
        if metal is not None:
            built["metal"] = metal
        bsdf = _mix(dielectric, metal, M)
        #: the layers above the substrate, lowest first (its emission passes them)
        self._layers = []
        if coat:
            bsdf = self._coat(bsdf, eta_s, built)
            self._layers.append(bsdf)
        F = p["fuzz_weight"]
        if _any(F):
            built["fuzz"] = LTCSheen(1.0, p["fuzz_roughness"])
            bsdf = Layer._new(Tinted._new(built["fuzz"], p["fuzz_color"]), bsdf, F)
            self._layers.append(bsdf)
        if self.thin_walled:
            bsdf = Facing(bsdf)
        alpha = p["geometry_opacity"]
        if _any(1.0 - alpha):
            built["pass-through"] = PassThrough()
            bsdf = Mix(built["pass-through"], bsdf, _c(alpha))
        super().__init__(bsdf, built)

    def __repr__(self) -> str:
        return f"OpenPBRSurface(lobes={list(self.lobes)})"

    @classmethod
    def from_draft(cls, *, spec: str | None = None, **draft_params):
        """The surface of the draft v0.1 inputs [Andersson2023] (``draft.released_parameters``
        maps them; ``draft_differences`` lists where the released formulas differ for these
        values, and a warning says so)."""
        params, differences = draft.released_parameters(**draft_params)
        if differences:
            warnings.warn("OpenPBRSurface.from_draft: " + "; ".join(differences),
                          stacklevel=2)
        material = cls(spec=spec, **params)
        material.draft_differences = tuple(differences)
        return material

    def reference(self, n_samples: int = 64, seed: int = 0):
        """The material as the structure of slabs the specification describes, its light
        followed by random walks (``transport.reference``; the choices are in
        ``docs/openpbr.md``, "The structure itself"): a lobe with ``eval`` (an unbiased
        estimate from ``n_samples`` walks per pair; ``eval_with_error``), ``pdf``, ``sample``
        and ``albedo(method="mc")``, against which this fast model and any other OpenPBR
        implementation can be measured. Slow on purpose; scalar parameters only."""
        from adobe_bsdf.materials.openpbr import transport
        return transport.reference(self, n_samples, seed)

    # -- the interior ----------------------------------------------------------------------
    def media(self) -> dict:
        """The interior media with their presence weights, ``{name: (weight, Medium)}``:
        "transmission", of weight (1 - M) T, the translucent base's medium
        (``media.openpbr_transmission_medium`` of transmission_color, _depth, _scatter and
        _scatter_anisotropy, the scatter as the ``spec`` defines it; absent at depth 0, where
        the colour tints the refraction), and
        "subsurface", of weight (1 - M)(1 - T) S, ``media.openpbr_subsurface_medium`` of
        subsurface_radius x subsurface_radius_scale, subsurface_color and
        subsurface_scatter_anisotropy [OpenPBR2026, §Subsurface, §Translucent base]. Only
        media of non-zero weight somewhere are listed; the weights are ``(...)`` arrays. A
        thin-walled material has none."""
        p = self.params
        dielectric = 1.0 - p["base_metalness"]
        T, S = p["transmission_weight"], p["subsurface_weight"]
        out = {}
        if self.thin_walled:  # a sheet has no interior
            return out
        if _any(dielectric * T):
            m = media.openpbr_transmission_medium(p["transmission_color"],
                                                  p["transmission_depth"],
                                                  p["transmission_scatter"],
                                                  p["transmission_scatter_anisotropy"],
                                                  spec=self.spec)
            if m is not None:
                out["transmission"] = (dielectric * T, m)
        if _any(dielectric * (1.0 - T) * S):
            out["subsurface"] = (dielectric * (1.0 - T) * S, media.openpbr_subsurface_medium(
                p["subsurface_radius"], p["subsurface_radius_scale"], p["subsurface_color"],
                p["subsurface_scatter_anisotropy"]))
        return out

    def medium(self):
        """The interior ``media.Medium`` of largest presence weight (``media``; the
        translucent one where the two weigh the same), or None for an opaque material."""
        found = self.media()
        if not found:
            return None
        return max(found.values(), key=lambda wm: float(np.max(wm[0])))[1]

    # -- emission and transparent shadows ------------------------------------------------
    def emission(self, wo) -> np.ndarray:
        """Emitted radiance towards ``wo``, RGB ``(..., 3)`` in W m^-2 sr^-1
        [OpenPBR2026, §Emission]: ``mapping.emission_radiance`` of emission_luminance and
        emission_color (times emission_weight under dev_1.2 [OpenPBR2026dev, §Emission]),
        uniform over the upper hemisphere (0 below), leaving the substrate
        through the coat and then the fuzz with the weight each layer gives the light under
        it along ``wo`` (``Layer.exit_weight``: lerp(1, t(wo) (1 - E_top(wo)), w), t the
        coat's one-way view-dependent transmittance sqrt(coat_color)^(1/mu_o^t)), times the
        presence geometry_opacity. A thin wall emits the same from both sides (it always
        faces ``wo``)."""
        wo = _params.direction("wo", wo)
        if self.thin_walled:
            wo = wo * np.where(wo[..., 2:3] < 0.0, -1.0, 1.0)
        p = self.params
        luminance = p["emission_luminance"] * p.get("emission_weight", 1.0)
        Le = mapping.emission_radiance(luminance, p["emission_color"])
        Le = np.where((wo[..., 2] > 0.0)[..., None], Le * _c(p["geometry_opacity"]), 0.0)
        for layer in self._layers:
            Le = Le * layer.exit_weight(wo)
        return Le

    def shadow_transmittance(self, wo) -> np.ndarray:
        """Transparent-shadow transmittance along the straight line through ``wo``, RGB
        ``(..., 3)`` [OpenPBR2026, §Opacity / Transparency]:

            T_pbr = 1 - alpha (1 - (1 - M) T_dielectric),

        alpha = geometry_opacity, M = base_metalness (the metal is opaque). T_dielectric is
        transmission_weight times the translucent base's straight transmittance
        (1 - E_R(mu)) transmission_color, E_R the energy its rough interface reflects at
        mu = |cos theta_o| (the line crosses it from outside whichever way it runs; the
        glossy-diffuse and subsurface bases are opaque), times the share that crosses the
        coat and the fuzz (``Layer.exit_weight``), as the draft's
        w_dielectric T_dielectric [Andersson2023, §Opacity / Transparency] with v1.1.1's
        Fresnel factor made explicit."""
        wo = _params.direction("wo", wo)
        up = wo * np.where(wo[..., 2:3] < 0.0, -1.0, 1.0)  # the line's side from outside
        p = self.params
        T = p["transmission_weight"] * (1.0 - p["base_metalness"])
        T_d = np.zeros(up.shape[:-1] + (3,))
        if self._eta is not None and _any(T):
            interface = DielectricReflection._new(GGX._new(*self._alphas(self._roughness)),
                                                  _fresnel(self._eta))
            E_R = interface._albedo_table(up, with_error=False)[0]
            T_d = _c(T) * p["transmission_color"] * (1.0 - E_R)
            for layer in self._layers:
                T_d = T_d * layer.exit_weight(up)
        return 1.0 - _c(p["geometry_opacity"]) * (1.0 - T_d)

    # -- the slabs --------------------------------------------------------------------------
    def _thin_film(self, coat_weight):
        """``(w, d, n)`` of the thin film [OpenPBR2026, §Thin-film iridescence], or None where
        thin_film_weight w or the thickness is 0 everywhere (the film-free material exactly):
        d = 1000 thin_film_thickness (nm), n = thin_film_ior / n_above its index relative to
        the medium above it, n_above =
        lerp(1, coat_ior, coat_weight) (the blend the base's own index takes under a partial
        coat, ``mapping.effective_ior``). Not with the hazy gloss of [Barla2018] (its
        Fresnel is its own). On the bulk translucent base it is the interface's
        (``DielectricMS(film=)``, ``DispersiveMS(film=)`` per channel index), on the
        thin-walled one on the sheet's faces (``ThinDielectric(film=)``)."""
        p = self.params
        w = p["thin_film_weight"]
        if not _any(w * p["thin_film_thickness"]):  # no film, or one of thickness 0
            return None
        if self._hazy and self.haze_model == "barla2018":
            raise ValueError("thin_film_weight > 0 with haze_model = 'barla2018': allowed "
                             "thin_film_weight = 0 (the hazy gloss has a Fresnel of its own)")
        n_above = 1.0 if coat_weight is None else 1.0 + coat_weight * (p["coat_ior"] - 1.0)
        return w, 1000.0 * p["thin_film_thickness"], p["thin_film_ior"] / n_above

    def _alphas(self, r):
        return mapping.anisotropic_alphas(r, self.params["specular_roughness_anisotropy"])

    def _hazed(self, make, r):
        """``make(alphas)`` at roughness ``r``, blended with the development branch's haze
        where specular_haze w > 0: (1 - w) f_core + w f_haze, the haze at
        r_haze = lerp(r, 1, specular_haze_spread) with the same anisotropy, each lobe
        compensated on its own [OpenPBR2026 dev_1.2, §Specular haze]."""
        core = make(self._alphas(r))
        if not self._hazy:
            return core
        p = self.params
        w, spread = p["specular_haze"], p["specular_haze_spread"]
        haze = make(self._alphas(r + (1.0 - r) * spread))
        return Sum._new((core, haze), [_c(1.0 - w), _c(w)])

    def _barla(self, lobe, core_reflectivity, r, **kwargs):
        """The hazy-gloss alternative [Barla2018]: ``lobe`` (``HazyGloss`` or
        ``HazyDielectric``) of haziness specular_haze and haze extent specular_haze_spread
        over the core alphas of ``r``."""
        p = self.params
        return lobe(core_reflectivity, p["specular_haze"], p["specular_haze_spread"],
                    *self._alphas(r), **kwargs)

    def _metal(self, r, phi):
        """xi F82-tint conductor with Kulla–Conty multiple scattering [OpenPBR2026, §Metal]:
        min(xi, 1) F82 (1.1.1), or clamp(xi F82, 0, 1) (dev_1.2, where some xi > 1: its
        multiple scattering coloured by min(xi F_avg, 1), within 0.01 of the clamped average
        [OpenPBR2026dev, §Metal]); with haze, the blend of ``_hazed`` or the hazy gloss of
        [Barla2018] (Gulbrandsen's exact conductor of F0 and edge tint specular_color; no
        compensation); with retroreflectivity, ``_retro``."""
        p = self.params
        f0 = _c(p["base_weight"]) * p["base_color"]
        tint = p["specular_color"]
        xi = p["specular_weight"]
        boosted = self.spec == "dev_1.2" and np.any(xi > 1.0)

        def conductor(fresnel, f_avg):
            if boosted:
                fresnel, f_avg = Weighted._new(fresnel, xi), np.minimum(_c(xi) * f_avg, 1.0)

            def make(alphas):
                microfacets = GGX._new(*alphas)
                f_ms = mapping.metal_multiple_scattering(f_avg, conductor_average(microfacets))
                return ConductorMS._new(microfacets, fresnel, np.sqrt(f_ms))
            return make

        if self._hazy and self.haze_model == "barla2018":
            lobe = self._barla(HazyGloss, f0, r, edge_tint=tint)
        else:
            lobe = self._hazed(conductor(F82Tint._new(f0, tint, _F90, _EXPONENT),
                                         mapping.f82_average(f0, tint)), r)
            if self._film is not None:
                w, d, n_film = self._film
                film = ThinFilm.over_f82_tint(d, n_film, f0, tint,
                                              model=self.thin_film_model)
                lobe = _mix(lobe, self._hazed(conductor(film, _hemispherical_average(film)),
                                              r), w)
        if not boosted and np.any(xi != 1.0):
            lobe = Sum._new((lobe,), [_c(np.minimum(xi, 1.0))])
        return _turned(self._retro(lobe), phi)

    def _retro(self, lobe):
        """``lobe`` mixed with its retroreflective copy by specular_retroreflectivity
        (``lobes.Retroreflective``: its reflection only) [OpenPBR2026dev,
        §Retroreflectivity]; the lobe itself where that is 0 (and under 1.1.1)."""
        w = self.params.get("specular_retroreflectivity", 0.0)
        return Retroreflective._new(lobe, w) if _any(w) else lobe

    def _dielectric(self, eta, r, phi, built):
        """mix(mix(glossy-diffuse, subsurface, S), translucent, T) under one interface; with
        haze, each interface lobe as ``_metal``'s (the hazy gloss of [Barla2018] with the
        core reflectivity F0(eta'): ``HazyGloss`` with no edge tint, an exact Fresnel of a
        real index, for the reflection over the diffuse, ``HazyDielectric`` for the
        translucent base)."""
        p = self.params
        S, T = p["subsurface_weight"], p["transmission_weight"]
        barla = self._hazy and self.haze_model == "barla2018"
        if barla and np.any(eta < 1.0):
            raise ValueError("specular_ior below the index above it with haze_model = "
                             "'barla2018': allowed a relative index >= 1 (the hazy-gloss "
                             "mapping's index is n_below / n_above >= 1)")
        if barla and _any(T * p["transmission_dispersion_scale"]):
            raise ValueError("transmission_dispersion_scale > 0 with haze_model = 'barla2018': "
                             "allowed 0 (the hazy dielectric has one index)")
        opaque = None
        if _any(1.0 - T):
            if barla:
                reflection = self._barla(HazyGloss, _c(mapping.reflectance_at_normal(eta)), r,
                                         edge_tint=0.0)
            else:
                reflection = self._hazed(
                    lambda alphas: DielectricReflection._new(GGX._new(*alphas),
                                                             _fresnel(eta)), r)
                if self._film is not None:
                    w, d, n_film = self._film
                    film = ThinFilm(d, n_film, eta, model=self.thin_film_model)
                    reflection = _mix(reflection, self._hazed(
                        lambda alphas: ReferencedReflection._new(
                            DielectricReflection._new(GGX._new(*alphas), _fresnel(eta)),
                            film), r), w)
            built["specular"] = _turned(self._retro(reflection), phi)
            sigma = p["base_diffuse_roughness"]
            if _any(1.0 - S):
                rho = _c(p["base_weight"]) * p["base_color"]
                built["diffuse"] = EnergyPreservingOrenNayar(rho, sigma)
            if _any(S):
                built["subsurface"] = (self._thin_subsurface(sigma) if self.thin_walled else
                                       EnergyPreservingOrenNayar(p["subsurface_color"], sigma))
            under = _mix(built.get("diffuse"), built.get("subsurface"), S)
            top = built["specular"]
            if np.any(p["specular_color"] != 1.0):
                top = Tinted._new(top, p["specular_color"])
            opaque = Layer._new(top, under)
        if _any(T):
            if barla:
                glass = self._barla(HazyDielectric, mapping.reflectance_at_normal(eta), r)
            elif self.thin_walled:
                glass = self._hazed(self._sheet(eta, None), r)
                if self._film is not None:
                    w, d, n_film = self._film
                    film = ThinFilm(d, n_film, eta, model=self.thin_film_model)
                    glass = _mix(glass, self._hazed(self._sheet(eta, film), r), w)
            else:
                glass = self._bulk_glass(eta, r)
            built["transmission"] = _turned(self._retro(glass), phi)
        return _mix(opaque, built.get("transmission"), T)

    def _bulk_glass(self, eta, r):
        """The bulk translucent base at roughness ``r`` (``_glass``), hazed (``_hazed``) and
        mixed with its filmed copy by thin_film_weight where there is a film."""
        glass = self._hazed(lambda alphas: self._glass(eta, GGX._new(*alphas)), r)
        if self._film is None:
            return glass
        w, d, n_film = self._film

        def film(eta_c):
            return ThinFilm(d, n_film, eta_c, model=self.thin_film_model)
        return _mix(glass, self._hazed(
            lambda alphas: self._glass(eta, GGX._new(*alphas), film), r), w)

    def _sheet(self, eta, film):
        """``make(alphas)`` of the thin-walled translucent base: ``ThinDielectric`` of
        transmission_color, with the thin film ``film`` on its faces (None: none)
        [OpenPBR2026, §Thin-walled mode, §Thin-film iridescence]."""
        color = self.params["transmission_color"]
        return lambda alphas: ThinDielectric(eta, *alphas, transmittance=color, film=film)

    def _glass(self, eta, microfacets, film=None):
        # film: None, or film(eta_c) -> the thin film over an index (the channels' with
        # dispersion)
        """The bulk translucent base: ``DielectricMS`` at ``eta``, its refraction tinted by
        transmission_color where transmission_depth is 0 (``lobes.TintedRefraction``: "a
        constant tint on the refraction", [OpenPBR2026, §Translucent base]; at depth > 0 the
        colour is the medium's, ``media()``), its reflection by specular_color: from above
        (1.1.1, [OpenPBR2026, §Dielectric base]) or from both sides (dev_1.2).

        With dispersion [OpenPBR2026, §Dispersion]: V_d = transmission_dispersion_abbe_number
        / transmission_dispersion_scale, n_d = ``eta`` (the modulated index), one index per
        RGB channel by Cauchy's equation (``lobes.DispersiveMS``: ``lobes.Dispersive`` at the
        Dispersion 20 / V_d of [Kutz2021, eq. 12] with each channel's own Kulla–Conty term):
        a white glass keeps its energy in every channel."""
        p = self.params
        T = p["transmission_color"]
        tint = np.where((p["transmission_depth"] == 0.0)[..., None], T, 1.0)
        color = p["specular_color"]

        if not _any(p["transmission_dispersion_scale"]):
            lobe = DielectricMS._new(eta, microfacets, None if film is None else film(eta))
        else:
            D = (20.0 * p["transmission_dispersion_scale"]
                 / p["transmission_dispersion_abbe_number"])
            names = "transmission_dispersion_abbe_number / transmission_dispersion_scale"
            try:
                lobe = DispersiveMS._new(eta, D, microfacets, film)
            except ValueError as error:  # a channel's index at 1 or below, or out of tables
                raise ValueError(f"{names} = V_d {np.min(20.0 / D)!r}: {error}") from None
            _in_tables(f"{names} (the channels' Cauchy indices)", lobe.eta)
        if not (np.any(tint != 1.0) or np.any(color != 1.0)):
            return lobe
        return TintedRefraction._new(lobe, tint, color, self.spec == "dev_1.2")

    def _thin_subsurface(self, sigma):
        """The thin-walled subsurface [OpenPBR2026, §Thin-walled mode]: f_R = S (1 - g) / 2 f_+
        and f_T = S (1 + g) / 2 f_-, S = subsurface_color, g = subsurface_scatter_anisotropy,
        f_+ the unit-albedo EON diffuse of roughness ``sigma`` and f_- the same ``Flipped``
        into the other hemisphere (its radius and radius scale are ignored, as v1.1.1 says)."""
        p = self.params
        S, g = p["subsurface_color"], _c(p["subsurface_scatter_anisotropy"])
        diffuse = EnergyPreservingOrenNayar(1.0, sigma)
        return Sum._new((diffuse, Flipped._new(diffuse)), [0.5 * S * (1.0 - g),
                                                          0.5 * S * (1.0 + g)])

    def _coat(self, base, eta_s, built):
        """The coat over ``base`` [OpenPBR2026, §Coat]: coat_color C_c the two-way
        transmittance at normal incidence. 1.1.1: made view dependent, C_c^((1/mu_o^t +
        1/mu_i^t) / 2) (``composition.coat_absorption``), the base darkened by
        lerp(1, Delta, delta), Delta = (1 - K) / (1 - E_b K), so the tint at normal incidence
        is C_c whatever coat_darkening. dev_1.2 [Portsmouth2025]: the naive albedo-scaled
        layer over the base tinted by C_c at coat_darkening 0, E_coat + C_c E_b (1 - E_coat),
        and the physical transport through the absorbing coat at 1
        (``darkening.Darkening`` "dev_1.2")."""
        p = self.params
        n_c = p["coat_ior"]
        _in_tables("coat_ior", n_c)
        alphas = mapping.anisotropic_alphas(p["coat_roughness"],
                                            p["coat_roughness_anisotropy"])
        reflection = DielectricReflection._new(GGX._new(*alphas), _fresnel(n_c))
        built["coat"] = _turned(reflection, mapping.tangent_rotation(
            p["geometry_coat_tangent"]))
        color = p["coat_color"]
        clear = not np.any(color != 1.0)
        dev = self.spec == "dev_1.2"
        darkening = None
        if _any(p["coat_darkening"]):
            darkening = Darkening(p["coat_darkening"], self._darkening_roughness(eta_s),
                                  "dev_1.2" if dev else "v1.1.1",
                                  **({"coat_alpha": p["coat_roughness"] ** 2} if dev else {}))
        scaling = "albedo" if clear or dev else "transmittance"
        return Layer._new(built["coat"], base, p["coat_weight"], None if clear else color,
                          scaling, darkening)

    def _darkening_roughness(self, eta_s):
        """r_b = lerp(r_d, r_m, M), r_d = lerp(1, r, clamp(xi F_s, 0, 1)), r_m = r, with r =
        specular_roughness [OpenPBR2026, §Coat darkening]: how specular the base looks
        through the coat."""
        p = self.params
        M, r = p["base_metalness"], p["specular_roughness"]
        if eta_s is None:
            return np.clip(r, 0.0, 1.0)
        t = np.clip(p["specular_weight"] * mapping.reflectance_at_normal(eta_s), 0.0, 1.0)
        r_d = (1.0 - t) + t * r
        return np.clip((1.0 - M) * r_d + M * r, 0.0, 1.0)


def versions(spec=None, darkening_variant=None, haze_model=None,
             stacklevel: int = 2) -> tuple[str | None, bool]:
    """``(spec, barla)``: the version asked for by ``spec`` or the deprecated aliases (a
    ``DeprecationWarning`` each, at ``stacklevel`` above the caller; a conflict is a
    ``ValueError``), None where none says one, and whether specular_haze is the hazy gloss of
    [Barla2018] (haze_model "barla2018")."""
    implied = None
    for name, value in (("darkening_variant", darkening_variant), ("haze_model", haze_model)):
        if value is None:
            continue
        _params.choice(name, value, tuple(_ALIASES[name]))
        version = _ALIASES[name][value]
        warnings.warn(f"OpenPBRSurface: {name} = {value!r} is deprecated and goes in the next "
                      f"release: pass spec = {version!r} (docs/openpbr.md, the versions)",
                      DeprecationWarning, stacklevel=stacklevel + 1)
        if version != (spec or implied or version):
            raise ValueError(f"{name} = {value!r} means spec = {version!r}, against spec = "
                             f"{spec or implied!r}: allowed one version (pass spec alone)")
        implied = version
    if spec is not None:
        _params.choice("spec", spec, SPECS)
    return spec or implied, haze_model == "barla2018"


def _version(spec, darkening_variant, haze_model, params) -> tuple[str, bool]:
    """``versions`` for the material of ``params`` ("1.1.1" where none is asked for): under
    "1.1.1" an input of dev_1.2 alone is refused."""
    spec, barla = versions(spec, darkening_variant, haze_model, stacklevel=3)
    spec = spec or "1.1.1"
    given = [name for name in DEV_1_2 if name in params]
    if spec == "1.1.1" and given:
        raise ValueError(f"{given[0]} = {params[given[0]]!r} is an input of dev_1.2, not of "
                         "OpenPBR 1.1.1 (spec = '1.1.1', the default): allowed with "
                         "spec = 'dev_1.2'")
    return spec, barla


def _acts(p, name) -> bool:
    """Whether the planned input ``name`` is away from its default where its gate is on."""
    default = PARAMETERS[name].default
    if PARAMETERS[name].kind == "vector":
        changed = np.any(np.abs(p[name] - np.asarray(default)) > 1e-12, axis=-1)
    elif PARAMETERS[name].kind == "bool":
        changed = np.asarray(p[name] != default)
    else:
        changed = p[name] != np.asarray(default)
        if PARAMETERS[name].kind == "color":
            changed = np.any(changed, axis=-1)
    gate = GATES.get(name)
    if gate is not None:
        changed = changed & (p[gate] != 0.0)
    return bool(np.any(changed))


def _fresnel(eta):
    return ExactDielectric._new(np.asarray(eta, dtype=np.float64))


def _thin_walled(flag) -> bool:
    """geometry_thin_walled as one switch (a texture of it must not mix the two modes)."""
    flag = np.asarray(flag)
    if flag.size and np.any(flag != flag.flat[0]):
        raise ValueError("geometry_thin_walled differs across the texture: allowed one value "
                         "for the whole material (thin walls and a bulk interior do not mix)")
    return bool(flag.flat[0]) if flag.size else False


#: Gauss-Legendre nodes and weights on [0, 1] for hemispherical averages of a Fresnel model
_X, _W = np.polynomial.legendre.leggauss(48)
_MU, _MU_WEIGHTS = 0.5 * (_X + 1.0), 0.5 * _W


def _hemispherical_average(fresnel):
    """F_avg = 2 int_0^1 F(mu) mu dmu ``(..., 3)`` of a Fresnel model by 48-point
    Gauss-Legendre (the Kulla–Conty colour of a metal whose Fresnel has no closed-form
    average: the thin film's fringes vary slowly with the angle)."""
    mu = _MU.reshape((-1,) + (1,) * len(fresnel.param_shape))
    F = fresnel.from_cos2(mu * mu)
    w = (_MU_WEIGHTS * _MU).reshape(mu.shape + (1,))
    return 2.0 * np.sum(w * F, axis=0)


def _mix(a, b, w):
    """``Mix(a, b, w)``, or the one of them that was built (the other's weight is 0)."""
    if a is None or b is None:
        return b if a is None else a
    return Mix(a, b, _c(w))
