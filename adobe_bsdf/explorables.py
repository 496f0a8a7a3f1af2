"""What ``explore`` can open, by name: every material, and every generic lobe with a parameter
specification of its inputs.

Public API
----------
``Explorable(name, parameters, build, doc)``   one target: its ``ParameterSpec`` and how to
                                               build it from validated values
``EXPLORABLES``                                ``{name: Explorable}``: the materials of
                                               ``materials.MATERIALS`` and the generic lobes
``explorable(target)``                         the ``Explorable`` of a name, a material class
                                               or a lobe class

A material's specification is its own (``materials.spec``). A lobe's constructor takes
models as well as numbers (a ``fresnel.Fresnel``, a distribution), so its specification
lists the numbers a user turns (the F82-tint colours of a metal's Fresnel, an index, the
alphas) and ``build`` assembles the lobe from them. Hard ranges are those the constructors
accept; soft ranges those an interface offers, inside the energy tables' ranges.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from adobe_bsdf import fresnel, lobes
from adobe_bsdf.bsdf import Lobe
from adobe_bsdf.materials import MATERIALS, OpenPBRSurface
from adobe_bsdf.materials.openpbr import DEV_1_2, SPECS
from adobe_bsdf.materials.spec import Parameter, ParameterSpec
from adobe_bsdf.microfacet import MASKING
from adobe_bsdf.tables import ALPHA_MAX

__all__ = ["Explorable", "EXPLORABLES", "explorable"]

_INF = float("inf")


@dataclass(frozen=True)
class Explorable:
    """A target of ``explore``: ``build(**values)`` makes the lobe from values that
    ``parameters.validate`` accepted."""

    name: str
    parameters: ParameterSpec
    build: Callable[..., Lobe]
    doc: str = ""


# -- the parameters the lobes share ---------------------------------------------------------
def _alpha(name: str, default: float, hi: float) -> Parameter:
    """A GGX alpha; ``hi``: tables.ALPHA_MAX for a lobe whose energy terms are tabulated."""
    return Parameter(name, "real", default, (0.0, hi), (0.0, 1.0),
                     f"GGX roughness {name} (alpha = r^2 of a perceptual roughness r)")


def _alphas(hi: float = _INF, default_y: float = 0.3) -> tuple:
    return _alpha("alpha_x", 0.3, hi), _alpha("alpha_y", default_y, hi)


def _eta(default: float = 1.5) -> Parameter:
    return Parameter("eta", "real", default, (0.0, _INF), (1.0, 3.0),
                     "relative index n_below / n_above", lo_open=True)


def _color(name: str, default, doc: str, hi: float = 1.0) -> Parameter:
    return Parameter(name, "color", default, (0.0, hi), (0.0, 1.0), doc)


_MASKING = Parameter("masking", "choice", "correlated", None,
                     doc="Smith masking-shadowing: height-correlated or separable",
                     choices=MASKING)
_MODEL = Parameter("model", "choice", "ggx", None, doc="microfacet distribution",
                   choices=("ggx", "beckmann"))
_F0 = _color("f0", (0.95, 0.64, 0.54), "F82-tint reflectance at normal incidence (copper)")
_TINT = _color("tint", (0.96, 0.91, 0.83), "F82-tint: reflectance at 82 degrees over Schlick's",
               hi=_INF)


#: the hazy-gloss inputs after the core reflectivity [Barla2018, §2.4], and its models
_HAZE = (
    Parameter("haziness", "real", 0.5, (0.0, 1.0), doc="share of the halo"),
    Parameter("haze_extent", "real", 4.0, (0.0, _INF), (0.0, 10.0),
              "halo roughness over core roughness"),
    Parameter("alpha_x", "real", 0.1, (0.0, _INF), (0.01, 0.5), "core roughness along x",
              lo_open=True),
    Parameter("alpha_y", "real", 0.1, (0.0, _INF), (0.01, 0.5), "core roughness along y",
              lo_open=True))
_HAZE_MODEL = (_MODEL, Parameter("compound_masking", "bool", False, None,
                                 doc="one Smith masking of the mixed distribution"))


def _metal(cls):
    def build(alpha_x, alpha_y, f0, tint, **rest):
        return cls(alpha_x, alpha_y, fresnel.F82Tint(f0, tint), **rest)
    return build


def _lobe(name, build, doc, *parameters) -> Explorable:
    return Explorable(name, ParameterSpec(*parameters), build, doc)


_LOBES = [
    _lobe("Lambert", lobes.Lambert, "ideal diffuse reflection",
          _color("albedo", (0.8, 0.8, 0.8), "directional albedo")),
    _lobe("EnergyPreservingOrenNayar", lobes.EnergyPreservingOrenNayar,
          "energy-preserving Oren-Nayar rough diffuse",
          _color("albedo", (0.8, 0.8, 0.8), "single-scattering albedo rho"),
          Parameter("roughness", "real", 0.5, (0.0, 1.0), doc="Oren-Nayar sigma"),
          Parameter("compensation", "bool", True, None, doc="add the multiple-scattering lobe")),
    _lobe("Conductor", _metal(lobes.Conductor), "GGX conductor, F82-tint Fresnel",
          *_alphas(default_y=0.15), _F0, _TINT, _MASKING),
    _lobe("ConductorMS", _metal(lobes.ConductorMS),
          "GGX conductor with Kulla-Conty multiple scattering",
          *_alphas(ALPHA_MAX, 0.15), _F0, _TINT,
          _color("base_color", (0.95, 0.64, 0.54), "colour of the multiple-scattering term")),
    _lobe("DielectricReflection", lobes.DielectricReflection,
          "the reflection of a rough dielectric interface alone",
          _eta(), *_alphas()),
    _lobe("Dielectric", lobes.Dielectric, "rough dielectric: reflection and refraction",
          _eta(), *_alphas(), _MASKING, _MODEL),
    _lobe("DielectricMS", lobes.DielectricMS,
          "rough dielectric with Kulla-Conty multiple scattering",
          _eta(), *_alphas(ALPHA_MAX)),
    _lobe("Dispersive", lobes.Dispersive, "rough dielectric with one index per channel",
          _eta(), Parameter("dispersion", "real", 0.5, (0.0, _INF), (0.0, 1.0),
                            "20 / Abbe number"),
          *_alphas()),
    _lobe("ThinDielectric", lobes.ThinDielectric, "thin translucent sheet, both sides",
          _eta(), *_alphas(ALPHA_MAX),
          _color("transmittance", (1.0, 1.0, 1.0), "one-way transmittance of the sheet")),
    _lobe("Sheen", lobes.Sheen, "microflake sheen",
          _color("color", (1.0, 1.0, 1.0), "sheen colour", hi=_INF),
          Parameter("roughness", "real", 0.5, (0.0, 1.0), doc="sheen roughness"),
          Parameter("c", "real", 2.0, (0.0, _INF), (0.0, 4.0), "microflake shape constant c"),
          Parameter("p", "real", 1.0, (0.0, _INF), (0.1, 4.0), "microflake exponent p",
                    lo_open=True)),
    _lobe("LTCSheen", lobes.LTCSheen, "LTC fuzz",
          _color("color", (1.0, 1.0, 1.0), "fuzz colour"),
          Parameter("roughness", "real", 0.5, (0.0, 1.0), doc="fuzz roughness")),
    _lobe("HazyGloss", lobes.HazyGloss, "hazy gloss of a metal",
          Parameter("core_reflectivity", "color", (0.9, 0.6, 0.3), (0.0, 1.0), (0.0, 0.99),
                    "reflectivity of the core lobe at normal incidence"),
          *_HAZE, _color("edge_tint", (0.0, 0.0, 0.0), "Gulbrandsen edge tint"), *_HAZE_MODEL),
    _lobe("HazyDielectric", lobes.HazyDielectric, "hazy gloss of a dielectric",
          Parameter("core_reflectivity", "real", 0.04, (0.0, 1.0), (0.0, 0.2),
                    "reflectivity at normal incidence", hi_open=True),
          *_HAZE, *_HAZE_MODEL),
]

def _openpbr(spec, **values) -> OpenPBRSurface:
    """OpenPBR Surface of the version ``spec``: the development branch's own inputs only
    under it (the release refuses them)."""
    if spec != "dev_1.2":
        values = {k: v for k, v in values.items() if k not in DEV_1_2}
    return OpenPBRSurface(spec=spec, **values)


def _material(name, cls) -> Explorable:
    doc = (cls.__doc__ or "").split("\n")[0]
    if cls is not OpenPBRSurface:
        return Explorable(name, cls.parameters, cls, doc)
    version = Parameter("spec", "choice", SPECS[0], None, choices=SPECS,
                        doc="the version of the specification (dev_1.2: its own inputs act)")
    return Explorable(name, ParameterSpec(version, *cls.parameters), _openpbr, doc)


#: every target of ``explore`` by name: the materials, then the generic lobes
EXPLORABLES: dict[str, Explorable] = {
    **{name: _material(name, cls) for name, cls in MATERIALS.items()},
    **{e.name: e for e in _LOBES},
}


def explorable(target) -> Explorable:
    """The ``Explorable`` of ``target``: a name of ``EXPLORABLES``, a material class, or a
    lobe class registered under its class name; ``ValueError`` otherwise."""
    if isinstance(target, Explorable):
        return target
    name = target if isinstance(target, str) else getattr(target, "__name__", None)
    if name in EXPLORABLES:
        return EXPLORABLES[name]
    raise ValueError(f"target = {target!r}: allowed one of {sorted(EXPLORABLES)}, or the "
                     "class of one of them")
