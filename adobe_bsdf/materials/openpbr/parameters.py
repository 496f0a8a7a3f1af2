"""The inputs of OpenPBR Surface: the 41 of the released v1.1.1 [OpenPBR2026, §Parameter
reference], the four the development branch dev_1.2 adds, and the draft v0.1 inputs
[Andersson2023] that ``OpenPBRSurface.from_draft`` maps onto them.

Public API
----------
``PARAMETERS``        ``spec.ParameterSpec`` of the released inputs and dev_1.2's four
``SPECS``             the versions ``OpenPBRSurface(spec=...)`` follows: "1.1.1", "dev_1.2"
``DEV_1_2``           the inputs of dev_1.2 alone (refused under spec "1.1.1")
``DRAFT_PARAMETERS``  ``spec.ParameterSpec`` of the draft's inputs (names, defaults, ranges)
``STATUS``            ``{name: (status, how)}`` for both: "implemented", "implemented with a
                      documented choice", "planned" (accepted, stored; a warning when set
                      away from its default), "dev_1.2" (under spec "dev_1.2") or "removed"
                      (draft inputs with no released counterpart)
``PLANNED``           the released inputs accepted but not yet modelled
``GATES``             ``{planned input: the weight without which it has no effect}``
``status_markdown(spec)``  the ``docs/openpbr.md`` table of ``spec`` with each input's status
``VERSIONS``          ``{behaviour: (under "1.1.1", under "dev_1.2")}``: what ``spec`` changes
``versions_markdown()``   that table for ``docs/openpbr.md``
"""

from __future__ import annotations

from adobe_bsdf.materials.spec import Parameter, ParameterSpec, _number

__all__ = ["PARAMETERS", "SPECS", "DEV_1_2", "DRAFT_PARAMETERS", "STATUS", "PLANNED", "GATES",
           "status_markdown", "VERSIONS", "versions_markdown"]

#: the versions of the specification the surface follows: the release [OpenPBR2026] (the
#: default) and its development branch [OpenPBR2026dev]
SPECS = ("1.1.1", "dev_1.2")

_UNIT = (0.0, 1.0)
_INF = float("inf")
_POS = (0.0, _INF)
_SIGNED = (-1.0, 1.0)
_NORMAL, _TANGENT = (0.0, 0.0, 1.0), (1.0, 0.0, 0.0)


def _p(name, kind, default, hard, soft=None, doc="", lo_open=False):
    return Parameter(name, kind, default, hard, soft, doc, lo_open)


#: OpenPBR Surface v1.1.1: names, kinds, defaults, hard and soft ranges of its parameter
#: reference (the MaterialX nodedef's order), and the inputs of the development branch
PARAMETERS = ParameterSpec(
    _p("base_weight", "real", 1.0, _UNIT, doc="multiplier of base_color (metal F0, diffuse ρ)"),
    _p("base_color", "color", 0.8, _UNIT, doc="metal F0; albedo of the glossy-diffuse base"),
    _p("base_diffuse_roughness", "real", 0.0, _UNIT, doc="σ of the EON diffuse"),
    _p("base_metalness", "real", 0.0, _UNIT, doc="mix weight of the metal"),
    _p("specular_weight", "real", 1.0, _POS, soft=_UNIT,
       doc="dielectric: F0 multiplier through the IOR; metal: Fresnel multiplier (≤ 1)"),
    _p("specular_color", "color", 1.0, _UNIT,
       doc="metal: F82 edge tint; dielectric: tint of the reflection from above"),
    _p("specular_roughness", "real", 0.3, _UNIT, doc="r, α = r² (metal and dielectric)"),
    _p("specular_roughness_anisotropy", "real", 0.0, _UNIT, doc="a of (α_t, α_b)"),
    _p("specular_ior", "real", 1.5, _POS, soft=(1.0, 3.0), lo_open=True,
       doc="n_b of the dielectric base"),
    _p("transmission_weight", "real", 0.0, _UNIT, doc="mix weight of the translucent base"),
    _p("transmission_color", "color", 1.0, _UNIT, doc="tint of the refraction (depth 0)"),
    _p("transmission_depth", "real", 0.0, _POS, soft=_UNIT, doc="medium: μ_t = −ln(T)/d"),
    _p("transmission_scatter", "color", 0.0, _UNIT, doc="medium: μ_s = S/d"),
    _p("transmission_scatter_anisotropy", "real", 0.0, _SIGNED, doc="medium: HG g"),
    _p("transmission_dispersion_scale", "real", 0.0, _UNIT, doc="V_d = Abbe / scale"),
    _p("transmission_dispersion_abbe_number", "real", 20.0, _POS, soft=(9.0, 91.0),
       lo_open=True, doc="Abbe number V_d"),
    _p("subsurface_weight", "real", 0.0, _UNIT, doc="mix weight of the subsurface slab"),
    _p("subsurface_color", "color", 0.8, _UNIT, doc="observed multiple-scattering albedo"),
    _p("subsurface_radius", "real", 1.0, _POS, soft=_UNIT, doc="mean free path scale"),
    _p("subsurface_radius_scale", "color", (1.0, 0.5, 0.25), _UNIT,
       doc="per-channel mean free path"),
    _p("subsurface_scatter_anisotropy", "real", 0.0, _SIGNED, doc="HG g of the subsurface"),
    _p("coat_weight", "real", 0.0, _UNIT, doc="coverage of the coat"),
    _p("coat_color", "color", 1.0, _UNIT, doc="two-way transmittance at normal incidence"),
    _p("coat_roughness", "real", 0.0, _UNIT, doc="r_C of the coat"),
    _p("coat_roughness_anisotropy", "real", 0.0, _UNIT, doc="a of the coat's (α_t, α_b)"),
    _p("coat_ior", "real", 1.6, _POS, soft=(1.0, 3.0), lo_open=True, doc="n_c"),
    _p("coat_darkening", "real", 1.0, _UNIT, doc="δ of the coat darkening"),
    _p("fuzz_weight", "real", 0.0, _UNIT, doc="coverage of the fuzz"),
    _p("fuzz_color", "color", 1.0, _UNIT, doc="tint of the fuzz reflection"),
    _p("fuzz_roughness", "real", 0.5, _UNIT, doc="α of the LTC sheen"),
    _p("emission_luminance", "real", 0.0, _POS, soft=(0.0, 1000.0), doc="nits"),
    _p("emission_color", "color", 1.0, _POS, doc="HDR multiplier of the luminance"),
    _p("thin_film_weight", "real", 0.0, _UNIT, doc="coverage of the thin film"),
    _p("thin_film_thickness", "real", 0.5, _POS, soft=_UNIT, doc="µm"),
    _p("thin_film_ior", "real", 1.4, _POS, soft=(1.0, 3.0), lo_open=True, doc="film index"),
    _p("geometry_opacity", "real", 1.0, _UNIT, doc="presence of the surface"),
    _p("geometry_thin_walled", "bool", False, None, doc="thin-walled mode"),
    _p("geometry_normal", "vector", _NORMAL, None, doc="shading normal of the base"),
    _p("geometry_tangent", "vector", _TANGENT, None,
       doc="anisotropy direction (α_t) of the base, local frame"),
    _p("geometry_coat_normal", "vector", _NORMAL, None, doc="shading normal of the coat"),
    _p("geometry_coat_tangent", "vector", _TANGENT, None,
       doc="anisotropy direction of the coat, local frame"),
    # dev_1.2 only (``DEV_1_2``)
    _p("specular_haze", "real", 0.0, _UNIT, doc="weight of a second, rougher base lobe"),
    _p("specular_haze_spread", "real", 0.3, _UNIT,
       doc="haze roughness lerp(specular_roughness, 1, spread)"),
    _p("specular_retroreflectivity", "real", 0.0, _UNIT,
       doc="weight of the retroreflective copy of the metal's and dielectric's reflection"),
    _p("emission_weight", "real", 0.0, _UNIT, doc="multiplier of the emission"),
)

#: the inputs dev_1.2 adds [OpenPBR2026dev, §Parameter reference]: refused under spec "1.1.1"
DEV_1_2 = ("specular_haze", "specular_haze_spread", "specular_retroreflectivity",
           "emission_weight")

#: the inputs of the v0.1 draft [Andersson2023, parameter tables] (its own defaults and
#: ranges; its ranges with an open upper end, [0, 1), are written closed here: a value is
#: accepted at the end, as the released model does)
DRAFT_PARAMETERS = ParameterSpec(
    _p("base_weight", "real", 1.0, _UNIT),
    _p("base_color", "color", 0.8, _UNIT),
    _p("base_roughness", "real", 0.0, _UNIT),
    _p("base_metalness", "real", 0.0, _UNIT),
    _p("specular_weight", "real", 1.0, _UNIT),
    _p("specular_color", "color", 1.0, _UNIT),
    _p("specular_roughness", "real", 0.3, _UNIT),
    _p("specular_ior", "real", 1.5, (1.0, 3.0)),
    _p("specular_ior_level", "real", 0.5, _UNIT),
    _p("specular_anisotropy", "real", 0.0, _UNIT),
    _p("specular_rotation", "real", 0.0, _UNIT),
    _p("transmission_weight", "real", 0.0, _UNIT),
    _p("transmission_color", "color", 1.0, _UNIT),
    _p("transmission_depth", "real", 0.0, _POS),
    _p("transmission_scatter", "color", 0.0, _UNIT),
    _p("transmission_scatter_anisotropy", "real", 0.0, _SIGNED),
    _p("transmission_dispersion_scale", "real", 0.0, _UNIT),
    _p("transmission_dispersion_abbe_number", "real", 20.0, (10.0, 70.0)),
    _p("subsurface_weight", "real", 0.0, _UNIT),
    _p("subsurface_color", "color", 1.0, _UNIT),
    _p("subsurface_radius", "real", 1.0, _POS),
    _p("subsurface_radius_scale", "color", 1.0, _UNIT),
    _p("subsurface_anisotropy", "real", 0.0, _SIGNED),
    _p("coat_weight", "real", 0.0, _UNIT),
    _p("coat_color", "color", 1.0, _UNIT),
    _p("coat_roughness", "real", 0.3, _UNIT),
    _p("coat_ior", "real", 1.6, (1.0, 3.0)),
    _p("coat_ior_level", "real", 0.5, _UNIT),
    _p("coat_anisotropy", "real", 0.0, _UNIT),
    _p("coat_rotation", "real", 0.0, _UNIT),
    _p("fuzz_weight", "real", 0.0, _UNIT),
    _p("fuzz_color", "color", 1.0, _UNIT),
    _p("fuzz_roughness", "real", 0.5, _UNIT),
    _p("emission_luminance", "real", 0.0, _POS),
    _p("emission_color", "color", 1.0, _UNIT),
    _p("thin_film_thickness", "real", 0.0, (0.0, 1000.0)),
    _p("thin_film_ior", "real", 1.5, (1.0, 3.0)),
    _p("geometry_opacity", "real", 1.0, _UNIT),
    _p("geometry_thin_walled", "bool", False, None),
)

_DONE, _CHOICE, _PLANNED = ("implemented", "implemented with a documented choice", "planned")

#: how each input is implemented (released and draft names; ``docs/openpbr.md`` prints it)
STATUS = {
    "base_weight": (_DONE, "F0 = base_weight base_color; ρ = base_weight base_color"),
    "base_color": (_DONE, "`fresnel.F82Tint` F0; `lobes.EON` ρ"),
    "base_diffuse_roughness": (_DONE, "σ of `lobes.EON` (energy-preserving Oren–Nayar)"),
    "base_metalness": (_DONE, "`composition.Mix` of dielectric and metal"),
    "specular_weight": (_CHOICE, "`specular_ior_modulation` (dielectric); metal: "
                                 "min(ξ, 1) × F82 (1.1.1), clamp(ξ F82, 0, 1) (dev_1.2)"),
    "specular_color": (_CHOICE, "metal: F82 tint at μ̄ = 1/7; dielectric: `Tinted` reflection "
                                "of the opaque base (the layer below sees the untinted "
                                "remainder); the translucent base's reflection "
                                "(`lobes.TintedRefraction`) from above (1.1.1) or both sides "
                                "(dev_1.2); not the thin-walled sheet's"),
    "specular_roughness": (_DONE, "`anisotropic_alphas`; under a coat `base_roughening`"),
    "specular_roughness_anisotropy": (_DONE, "`anisotropic_alphas`"),
    "specular_ior": (_CHOICE, "`effective_ior` (coat blend, TIR fix); the energy tables "
                              "limit the relative index to [1/3, 3]"),
    "transmission_weight": (_DONE, "`composition.Mix` of opaque and translucent bases; "
                                   "`lobes.DielectricMS`"),
    "transmission_color": (_DONE, "depth 0: `lobes.TintedRefraction`; depth > 0: the "
                                  "medium's Beer's law (`medium()`); thin walls: the sheet's "
                                  "transmittance"),
    "transmission_depth": (_DONE, "`media.openpbr_transmission_medium` (`medium()`)"),
    "transmission_scatter": (_CHOICE, "1.1.1: σ_s = S/d with the negative-absorption shift; "
                                      "dev_1.2: the single-scattering albedo, σ_s = S σ_t"),
    "transmission_scatter_anisotropy": (_DONE, "HG g of the translucent medium"),
    "transmission_dispersion_scale": (_DONE, "V_d = abbe / scale: `lobes.Dispersive` and a "
                                             "Kulla–Conty term per channel (bulk only)"),
    "transmission_dispersion_abbe_number": (_DONE, "Cauchy's equation through n_d = η' and "
                                                   "V_d"),
    "subsurface_weight": (_CHOICE, "the dense limit: glossy-diffuse of ρ = subsurface_color "
                                   "under the same interface; its medium is `medium()`"),
    "subsurface_color": (_CHOICE, "ρ of that limit: E = (1 − E_spec) C at normal incidence, "
                                  "as v1.1.1 defines the colour"),
    "subsurface_radius": (_CHOICE, "`media.openpbr_subsurface_medium`: mean free path "
                                   "r = radius × scale, σ_t = 1/r (`medium()`; the BSDF is "
                                   "the slab's dense limit)"),
    "subsurface_radius_scale": (_DONE, "per-channel factor of the mean free path"),
    "subsurface_scatter_anisotropy": (_CHOICE, "HG g; the albedo inversion with g "
                                               "(van de Hulst), error in docs/media.md"),
    "coat_weight": (_DONE, "coverage of `composition.Layer`; η_s blend; base roughening"),
    "coat_color": (_DONE, "Layer scaling 'transmittance': T^((1/μ_o^t + 1/μ_i^t)/2)"),
    "coat_roughness": (_DONE, "`anisotropic_alphas` of the coat"),
    "coat_roughness_anisotropy": (_DONE, "`anisotropic_alphas` of the coat"),
    "coat_ior": (_CHOICE, "coat reflection over the ambient (n_a = 1); the tables limit it to "
                          "[1/3, 3]"),
    "coat_darkening": (_CHOICE, "`darkening.Darkening`: 1.1.1's Δ = (1 − K)/(1 − E_b K); "
                                "dev_1.2: lerp from the naive albedo to the physical one "
                                "[Portsmouth2025], Δ from the transport through the coat"),
    "fuzz_weight": (_DONE, "F of F f_fuzz + (1 − F E_fuzz) f_below"),
    "fuzz_color": (_DONE, "`Tinted` LTC sheen: E_fuzz white for the layer below"),
    "fuzz_roughness": (_DONE, "α of `lobes.LTCSheen`"),
    "emission_luminance": (_CHOICE, "`emission(wo)`: L_v / 683 lm/W (Rec. 709 white has "
                                    "Y = 1), uniform, through the coat and fuzz "
                                    "(`Layer.exit_weight`)"),
    "emission_color": (_DONE, "multiplier of the radiance (may exceed 1)"),
    "thin_film_weight": (_CHOICE, "`Mix` of the base without and with the film, on the metal, "
                                  "the glossy-diffuse reflection and the translucent base, bulk "
                                  "or thin-walled (not with dispersion: a warning)"),
    "thin_film_thickness": (_DONE, "d = 1000 × thickness nm of `thin_film.ThinFilm` (the exact "
                                   "Airy sum, integrated to linear Rec. 709)"),
    "thin_film_ior": (_CHOICE, "relative to lerp(1, coat_ior, coat_weight) above it; the metal "
                               "by `ThinFilm.over_f82_tint` (Gulbrandsen's index)"),
    "geometry_opacity": (_DONE, "`composition.Mix` with `lobes.PassThrough`; "
                                "`shadow_transmittance(wo)`"),
    "geometry_thin_walled": (_CHOICE, "always-facing sheet (`composition.Facing`): metal and "
                                      "glossy-diffuse double-sided, `lobes.ThinDielectric`, "
                                      "subsurface f_R / f_T with g; no media"),
    "geometry_normal": (_PLANNED, "the caller's frame is the shading frame: left to the "
                                  "caller (docs/openpbr.md, Inputs not yet modelled)"),
    "geometry_tangent": (_DONE, "`composition.Rotated` by its azimuth in the local frame"),
    "geometry_coat_normal": (_PLANNED, "a shading normal of the coat: left to the caller "
                                       "(docs/openpbr.md, Inputs not yet modelled)"),
    "geometry_coat_tangent": (_DONE, "`composition.Rotated` by its azimuth"),
    "specular_haze": ("dev_1.2", "(1 − w) f_core + w f_haze on metal and dielectric base, each "
                                 "compensated"),
    "specular_haze_spread": ("dev_1.2", "r_haze = lerp(r, 1, spread)"),
    "specular_retroreflectivity": ("dev_1.2", "(1 − w) f_R + w f_R(reflect(ω_i, n), ω_o) of the "
                                              "metal and the dielectric's reflection "
                                              "(`lobes.Retroreflective`); not the BTDF"),
    "emission_weight": ("dev_1.2", "multiplier of emission_color × emission_luminance "
                                   "(1.1.1 has no such input: it emits fully)"),
    # draft names without a released counterpart (``from_draft`` maps them)
    "base_roughness": ("renamed", "base_diffuse_roughness"),
    "specular_ior_level": ("removed", "ξ = 2 level scales F0: specular_weight = 2 level with "
                                      "the draft's clamp"),
    "specular_anisotropy": ("renamed", "specular_roughness_anisotropy (the draft's mapping "
                                       "to alphas was open: v1.1.1's is used)"),
    "specular_rotation": ("removed", "geometry_tangent = (cos 2πθ, sin 2πθ, 0)"),
    "subsurface_anisotropy": ("renamed", "subsurface_scatter_anisotropy"),
    "coat_ior_level": ("removed", "folded into coat_ior by the same modulation"),
    "coat_anisotropy": ("renamed", "coat_roughness_anisotropy"),
    "coat_rotation": ("removed", "geometry_coat_tangent = (cos 2πθ, sin 2πθ, 0)"),
}

#: released inputs accepted and stored but not yet modelled: setting one away from its
#: default warns where it would act (``OpenPBRSurface.planned`` lists them)
PLANNED = tuple(name for name in PARAMETERS.parameters if STATUS[name][0] == _PLANNED)

#: the weight without which a planned input has no effect in the released model
GATES = {"transmission_color": "transmission_weight", "transmission_depth": "transmission_weight",
         "transmission_scatter": "transmission_depth",
         "transmission_scatter_anisotropy": "transmission_depth",
         "transmission_dispersion_abbe_number": "transmission_dispersion_scale",
         "subsurface_radius": "subsurface_weight", "subsurface_radius_scale": "subsurface_weight",
         "subsurface_scatter_anisotropy": "subsurface_weight",
         "emission_color": "emission_luminance", "thin_film_thickness": "thin_film_weight",
         "thin_film_ior": "thin_film_weight"}


def status_markdown(spec: ParameterSpec) -> str:
    """The table of ``docs/openpbr.md``: name, kind, default, hard and soft range, status and
    how it is implemented (draft inputs: where ``from_draft`` puts them)."""
    rows = ["| parameter | kind | default | range | soft range | status | how |",
            "|---|---|---|---|---|---|---|"]
    for p in spec:
        status, how = STATUS.get(p.name, ("implemented", "as in v1.1.1"))
        soft = "—" if p.soft is None else Parameter(p.name, "real", 0.0, p.soft).range_text
        rows.append(f"| `{p.name}` | {p.kind} | {_number(p.default)} | {p.range_text} | {soft} "
                    f"| {status} | {how} |")
    return "\n".join(rows) + "\n"


#: every behaviour of the surface that depends on ``spec``: {behaviour: (under "1.1.1" (the
#: default) [OpenPBR2026], under "dev_1.2" [OpenPBR2026dev])}
VERSIONS = {
    "coat_color": (
        "two-way transmittance at normal incidence, made view dependent: "
        "T^((1/μ_o^t + 1/μ_i^t)/2) (`Layer(scaling=\"transmittance\")`); the tint "
        "(f_c − f_s)/(f_1 − f_s) at normal incidence is coat_color exactly",
        "T² = coat_color multiplies the base (PR 253's albedo scaling of the tinted base); "
        "the view dependence comes from the physical darkening"),
    "coat_darkening": (
        "Δ = (1 − K)/(1 − E_b K), base × lerp(1, Δ, δ) (`Darkening(variant=\"v1.1.1\")`)",
        "δ = 0: the naive albedo E_coat + T² E_b (1 − E_coat); δ = 1: the physical albedo of "
        "the light bouncing in the absorbing coat [Portsmouth2025] "
        "(`Darkening(variant=\"dev_1.2\")`)"),
    "transmission_scatter": (
        "σ_s = S/d, the negative-absorption shift",
        "single-scattering albedo: σ_s = S σ_t, σ_a = (1 − S) σ_t"),
    "specular_weight ξ on a metal": (
        "min(ξ, 1) × F82", "clamp(ξ F82, 0, 1), ξ above 1 allowed"),
    "specular_color on the translucent base": (
        "tints its reflection from above", "tints its reflection from both sides"),
    "specular_haze, specular_haze_spread": (
        "refused (not inputs of 1.1.1)",
        "(1 − w) f_core + w f_haze, r_haze = lerp(r, 1, spread)"),
    "specular_retroreflectivity": (
        "refused", "(1 − w) f_R + w f_R(reflect(ω_i, n), ω_o) on the metal and the "
                   "dielectric's reflection (`lobes.Retroreflective`)"),
    "emission_weight": (
        "refused; the emission is emission_color × emission_luminance",
        "multiplies the emission (default 0, as the branch's parameter table)"),
    ".mtlx": ("nodes without a version, or of version < 1.2",
              "nodes of version 1.2 (`save_mtlx` writes it)"),
}


def versions_markdown() -> str:
    """The table of ``VERSIONS`` for ``docs/openpbr.md``."""
    rows = ["| behaviour | `spec=\"1.1.1\"` (default) | `spec=\"dev_1.2\"` |", "|---|---|---|"]
    rows += [f"| {name} | {a} | {b} |" for name, (a, b) in VERSIONS.items()]
    return "\n".join(rows) + "\n"
