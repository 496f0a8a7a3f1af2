"""Batch shapes and directions that fail name the culprit (the bad-input policy,
``docs/conventions.md``): a parameter whose batch shape does not broadcast with the directions
is named with its shape and the directions' batch shape, for every lobe and material and in
every call of the protocol; a direction that is not finite, or not of unit length, is named
with its batch index."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adobe_bsdf import _params, config
from adobe_bsdf import composition as C
from adobe_bsdf import fresnel as F
from adobe_bsdf import lobes as L
from adobe_bsdf.materials import MATERIALS, AdobeStandardMaterial, Material, OpenPBRSurface
from adobe_bsdf.materials.asm import ASMDiffuse, ASMSpecular
from adobe_bsdf.materials.openpbr.parameters import DEV_1_2
from adobe_bsdf.thin_film import ThinFilm

FAST = settings(max_examples=20, deadline=None)
WO = np.array([0.0, 0.6, 0.8])
WI = np.array([0.0, -0.6, 0.8])


def _batch(w, n: int) -> np.ndarray:
    return np.tile(w, (n, 1))


def _calls(obj, n: int = 3, lead: tuple = ()) -> dict:
    """Each protocol call of ``obj`` on directions of batch shape ``lead + (n,)``."""
    shape = lead + (n, 3)
    wo, wi = np.broadcast_to(WO, shape), np.broadcast_to(WI, shape)
    u = np.full(shape, 0.3)
    return {"eval": lambda: obj.eval(wo, wi), "pdf": lambda: obj.pdf(wo, wi),
            "eval_pdf": lambda: obj.eval_pdf(wo, wi), "sample": lambda: obj.sample(wo, u),
            "albedo": lambda: obj.albedo(wo), "albedo_table": lambda: obj.albedo(wo, "table"),
            "albedo_mc": lambda: obj.albedo(wo, "mc", n_samples=2)}


def _message(call) -> str:
    with pytest.raises(ValueError) as excinfo:
        call()
    return str(excinfo.value)


def _names(text: str, owner: str, name: str, shape: tuple, batch: tuple = (3,)) -> bool:
    """Whether ``text`` says the batch shape ``batch`` does not broadcast with ``owner``'s
    parameter ``name`` of ``shape``."""
    return (f"batch shape {batch} does not broadcast with the {owner}'s parameter {name} "
            f"(shape {shape}" in text)


# -- 1. lobes, fresnel models and compositions ---------------------------------------------
def R4(lo=0.2, hi=0.5):  # noqa: N802 - a texture of a real parameter, shape (4,)
    return np.linspace(lo, hi, 4)


def C4(lo=0.2, hi=0.8):  # noqa: N802 - a texture of a colour, shape (4, 3)
    return np.linspace(lo, hi, 12).reshape(4, 3)


#: case -> (class named in the message, parameter named, make(value), value)
LOBES = {
    "Lambert.albedo": ("Lambert", "albedo", lambda v: L.Lambert(albedo=v), C4()),
    "Conductor.alpha_x": ("Conductor", "alpha_x", lambda v: L.Conductor(alpha_x=v), R4()),
    "Conductor.alpha_y": ("Conductor", "alpha_y",
                          lambda v: L.Conductor(alpha_x=0.3, alpha_y=v), R4()),
    "MicrofacetReflection.alpha_x": ("MicrofacetReflection", "alpha_x",
                                     lambda v: L.MicrofacetReflection(v, model="beckmann"),
                                     R4()),
    "DielectricReflection.eta": ("DielectricReflection", "eta",
                                 lambda v: L.DielectricReflection(eta=v, alpha_x=0.3),
                                 R4(1.2, 1.6)),
    "Dielectric.eta": ("Dielectric", "eta", lambda v: L.Dielectric(eta=v, alpha_x=0.3),
                       R4(1.2, 1.6)),
    "Dielectric.alpha_x": ("Dielectric", "alpha_x", lambda v: L.Dielectric(1.5, alpha_x=v),
                           R4()),
    "Dispersive.dispersion": ("Dispersive", "dispersion",
                              lambda v: L.Dispersive(1.5, dispersion=v, alpha_x=0.3),
                              R4(0.1, 0.5)),
    "ConductorMS.base_color": ("ConductorMS", "base_color",
                               lambda v: L.ConductorMS(alpha_x=0.3, base_color=v), C4()),
    "DielectricMS.eta": ("DielectricMS", "eta", lambda v: L.DielectricMS(eta=v, alpha_x=0.3),
                         R4(1.2, 1.6)),
    "DielectricMultipleReflection.weight": (
        "DielectricMultipleReflection", "weight",
        lambda v: L.DielectricMultipleReflection(1.5, 0.3, weight=v), R4()),
    "Sheen.color": ("Sheen", "color", lambda v: L.Sheen(color=v, roughness=0.5), C4()),
    "Sheen.roughness": ("Sheen", "roughness", lambda v: L.Sheen(color=1.0, roughness=v),
                        R4()),
    "EON.albedo": ("EnergyPreservingOrenNayar", "albedo",
                   lambda v: L.EnergyPreservingOrenNayar(albedo=v, roughness=0.5), C4()),
    "EON.roughness": ("EnergyPreservingOrenNayar", "roughness",
                      lambda v: L.EnergyPreservingOrenNayar(albedo=0.5, roughness=v), R4()),
    "LTCSheen.roughness": ("LTCSheen", "roughness",
                           lambda v: L.LTCSheen(color=1.0, roughness=v), R4()),
    "HazyGloss.haziness": ("HazyGloss", "haziness",
                           lambda v: L.HazyGloss(0.5, haziness=v, haze_extent=0.5, alpha_x=0.1),
                           R4()),
    "HazyDielectric.haze_extent": (
        "HazyDielectric", "haze_extent",
        lambda v: L.HazyDielectric(0.04, haziness=0.5, haze_extent=v, alpha_x=0.1), R4()),
    "ThinDielectric.eta": ("ThinDielectric", "eta", lambda v: L.ThinDielectric(v, 0.3),
                           R4(1.2, 1.6)),
    "ThinDielectric.transmittance": (
        "ThinDielectric", "transmittance",
        lambda v: L.ThinDielectric(1.5, 0.3, transmittance=v), C4()),
    "TintedRefraction.tint": ("TintedRefraction", "tint",
                              lambda v: L.TintedRefraction(L.DielectricMS(1.5, 0.3), tint=v),
                              C4()),
    "Retroreflective.weight": ("Retroreflective", "weight",
                               lambda v: L.Retroreflective(L.Conductor(0.3), weight=v), R4()),
    "ExactConductor.eta": ("Conductor", "fresnel.eta",
                           lambda v: L.Conductor(0.3, fresnel=F.ExactConductor(eta=v, k=3.0)),
                           C4(0.2, 1.5)),
    "F82Tint.f0": ("Conductor", "fresnel.f0",
                   lambda v: L.Conductor(0.3, fresnel=F.F82Tint(f0=v, tint=1.0)), C4()),
    "ThinFilm.thickness_nm": ("Dielectric", "film.thickness_nm",
                              lambda v: L.Dielectric(1.5, 0.3, film=ThinFilm(v, 1.4, 1.5)),
                              R4(300.0, 500.0)),
    "ASMDiffuse.roughness": ("ASMDiffuse", "roughness",
                             lambda v: ASMDiffuse(albedo=0.5, roughness=v, ior=1.5), R4()),
    "ASMSpecular.ior": ("ASMSpecular", "ior", lambda v: ASMSpecular(roughness=0.3, ior=v),
                        R4(1.2, 1.6)),
    # compositions: their own parameters, then the path to a component's
    "Sum.weights": ("Sum", "weights[1]",
                    lambda v: C.Sum(L.Conductor(0.3), L.Lambert(0.5), weights=[0.5, v]),
                    C4(0.0, 0.5)),
    "Sum.components": ("Sum", "components[1].albedo",
                       lambda v: C.Sum(L.Conductor(0.3), L.Lambert(v)), C4()),
    "Mix.weight": ("Mix", "weight", lambda v: C.Mix(L.Conductor(0.3), L.Lambert(0.5), v),
                   C4()),
    "Tinted.color": ("Tinted", "color", lambda v: C.Tinted(L.Conductor(0.3), color=v), C4()),
    "Layer.coverage": ("Layer", "coverage",
                       lambda v: C.Layer(L.DielectricReflection(1.5, 0.2), L.Lambert(0.5),
                                         coverage=v), R4()),
    "Layer.transmittance": ("Layer", "transmittance",
                            lambda v: C.Layer(L.DielectricReflection(1.5, 0.2), L.Lambert(0.5),
                                              transmittance=v), C4()),
    "Layer.top": ("Layer", "top.eta",
                  lambda v: C.Layer(L.DielectricReflection(v, 0.2), L.Lambert(0.5)),
                  R4(1.2, 1.6)),
    "Rotated.phi": ("Rotated", "phi", lambda v: C.Rotated(L.Conductor(0.3, 0.1), phi=v), R4()),
    "Flipped.lobe": ("Flipped", "lobe.albedo", lambda v: C.Flipped(L.Lambert(v)), C4()),
    "Material.bsdf": ("Material", "bsdf.alpha_x", lambda v: Material(L.Conductor(v)), R4()),
}


@pytest.mark.parametrize("case", sorted(LOBES))
def test_every_lobe_names_its_parameter_that_does_not_broadcast(case):
    owner, name, make, value = LOBES[case]
    lobe = make(value)
    for method, call in _calls(lobe).items():
        text = _message(call)
        assert _names(text, owner, name, value.shape), (method, text)
        if value.ndim == 2:  # a colour: its batch shape too
            assert f"batch shape {value.shape[:-1]})" in text


def test_the_parameters_of_a_textured_lobe_still_broadcast():
    lobe = L.Conductor(R4()[:, None])  # (4, 1) against a batch (3,): (4, 3)
    assert lobe.eval(_batch(WO, 3), _batch(WI, 3)).shape == (4, 3, 3)
    assert LOBES["Sum.components"][2](C4()).eval(_batch(WO, 4), _batch(WI, 4)).shape == (4, 3)


def test_only_the_conflicting_parameters_are_named():
    lobe = L.Conductor(alpha_x=R4(), alpha_y=np.full((2, 1), 0.3))  # (2, 4): (2, 1) fits (3,)
    text = _message(lambda: lobe.eval(_batch(WO, 3), _batch(WI, 3)))
    assert _names(text, "Conductor", "alpha_x", (4,)) and "alpha_y" not in text
    both = L.Conductor(alpha_x=R4(), alpha_y=R4(0.1, 0.3))
    text = _message(lambda: both.eval(_batch(WO, 3), _batch(WI, 3)))
    assert "parameters alpha_x (shape (4,)) and alpha_y (shape (4,))" in text


def test_components_whose_parameters_do_not_broadcast_together_are_named():
    lobe = C.Sum(L.Conductor(R4()), L.Lambert(np.full((5, 3), 0.5)))
    text = _message(lambda: lobe.eval(_batch(WO, 3), _batch(WI, 3)))
    assert text == ("the Sum's parameters components[0].alpha_x (shape (4,)) and "
                    "components[1].albedo (shape (5, 3), batch shape (5,)) do not broadcast "
                    "together")
    filmed = C.Sum(L.Dielectric(1.5, 0.3, film=ThinFilm(R4(300.0, 500.0), 1.4, 1.5)),
                   L.Lambert(np.full((5, 3), 0.5)), weights=[C4(), 1.0])
    text = _message(lambda: filmed.pdf(_batch(WO, 3), _batch(WI, 3)))
    assert text == ("the Sum's parameters weights[0] (shape (4, 3), batch shape (4,)), "
                    "components[0].film.thickness_nm (shape (4,)) and components[1].albedo "
                    "(shape (5, 3), batch shape (5,)) do not broadcast together")


def test_a_failed_constructor_leaves_no_recording_scope():
    with pytest.raises(ValueError):
        L.Conductor(alpha_x=[0.1, -1.0])
    with pytest.raises(ValueError):
        AdobeStandardMaterial(roughness=[0.1, 2.0])
    assert not getattr(_params._LOCAL, "frames", [])
    lobe = L.Conductor(alpha_x=R4())  # and the next one records as before
    assert _names(_message(_calls(lobe)["eval"]), "Conductor", "alpha_x", (4,))


def test_objects_assembled_internally_fall_back_to_the_parameter_shape():
    lobe = C.Rotated._new(L.Lambert(0.5), R4())  # no constructor: no names
    text = _message(_calls(lobe)["eval"])
    assert text.endswith("does not broadcast with the Rotated's parameters (shape (4,))")


# -- 2. materials ------------------------------------------------------------------------------
#: per material: the lobes switched on (so that each parameter shapes a lobe that is built)
#: and the parameters that do not shape the BSDF under that configuration (the medium, the
#: emission, the normal maps not modelled, what the configuration leaves off); every other
#: real, colour or vector input does (OpenPBR's dev_1.2 inputs: below)
MATERIAL_CASES = {
    "AdobeStandardMaterial": (
        dict(metallic=0.5, translucency=0.5, coat_opacity=0.5, sheen_opacity=0.5,
             anisotropy_level=0.5, anisotropy_angle=0.2, coat_anisotropy_level=0.5,
             coat_anisotropy_angle=0.2, dispersion=0.5, coat_color=0.8),
        ("scattering_color", "scattering_distance", "scattering_distance_scale",
         "scatter_rayleigh", "scattering_red_shift", "emissive_color", "emissive_intensity")),
    "OpenPBRSurface": (
        dict(transmission_weight=0.5, coat_weight=0.5, fuzz_weight=0.5, subsurface_weight=0.5,
             geometry_opacity=0.5, specular_roughness_anisotropy=0.5,
             coat_roughness_anisotropy=0.5, transmission_depth=1.0,
             geometry_tangent=(0.8, 0.6, 0.0), geometry_coat_tangent=(0.6, 0.8, 0.0)),
        ("transmission_color", "transmission_depth", "transmission_scatter",
         "transmission_scatter_anisotropy", "transmission_dispersion_abbe_number",
         "subsurface_radius", "subsurface_radius_scale", "subsurface_scatter_anisotropy",
         "emission_luminance", "emission_color", "thin_film_thickness", "thin_film_ior",
         "geometry_normal", "geometry_coat_normal")),
}


def _texture(parameter, base, n: int = 4) -> np.ndarray:
    """A texture of ``n`` values of ``parameter`` near ``base`` inside its hard range (a
    colour or vector ``(n, 3)``, else ``(n,)``)."""
    if parameter.kind == "vector":
        return np.broadcast_to(np.asarray(base, dtype=float), (n, 3)).copy()
    if parameter.kind == "color":
        base = 0.5 if base is None else base
        return np.broadcast_to(0.9 * np.asarray(base, dtype=float), (n, 3)).copy()
    lo, hi = parameter.hard
    base = 0.5 if base is None else float(base)
    values = base * np.linspace(1.0, 0.85, n) + np.linspace(0.0, 0.03, n)
    return np.clip(values, lo + 1e-3 if lo > -1e9 else -1e9, hi - 1e-3 if hi < 1e9 else 1e9)


def _shaping(material: str) -> list:
    on, others = MATERIAL_CASES[material]
    spec = MATERIALS[material].parameters
    return [p.name for p in spec if p.kind in ("color", "real", "vector")
            and p.name not in others and p.name not in DEV_1_2]


def _textured(material: str, name: str, n: int = 4):
    cls = MATERIALS[material]
    on = dict(MATERIAL_CASES[material][0])
    parameter = cls.parameters[name]
    value = _texture(parameter, on.get(name, parameter.default), n)
    on[name] = value
    return cls(**on), value


def test_every_material_is_covered():
    assert sorted(MATERIALS) == sorted(MATERIAL_CASES)
    for material, (_, others) in MATERIAL_CASES.items():
        spec = MATERIALS[material].parameters
        assert set(others) <= set(spec.defaults)
        assert {p.name for p in spec if p.kind in ("color", "real", "vector")} \
            - set(_shaping(material)) - set(DEV_1_2) == set(others)


@pytest.mark.filterwarnings("ignore::UserWarning")
@pytest.mark.parametrize("material, name",
                         [(m, n) for m in sorted(MATERIAL_CASES) for n in _shaping(m)])
def test_every_material_parameter_that_does_not_broadcast_is_named(material, name):
    obj, value = _textured(material, name)
    for method in ("eval", "pdf", "sample", "albedo_table"):
        text = _message(_calls(obj)[method])
        assert _names(text, material, name, value.shape), (method, text)


@pytest.mark.parametrize("kwargs, name", [
    (dict(thin_film_weight=0.5, thin_film_thickness=R4(300.0, 500.0)), "thin_film_thickness"),
    (dict(transmission_weight=0.5, transmission_color=C4()), "transmission_color"),
    (dict(transmission_weight=0.5, transmission_dispersion_scale=R4()),
     "transmission_dispersion_scale"),
    (dict(spec="dev_1.2", specular_haze=R4()), "specular_haze"),
    (dict(spec="dev_1.2", specular_haze=0.5, specular_haze_spread=R4()),
     "specular_haze_spread"),
    (dict(spec="dev_1.2", specular_retroreflectivity=R4()), "specular_retroreflectivity"),
    (dict(geometry_thin_walled=True, transmission_weight=0.5, specular_roughness=R4()),
     "specular_roughness"),
])
def test_openpbr_configurations_name_the_parameter(kwargs, name):
    obj = OpenPBRSurface(**kwargs)
    text = _message(_calls(obj)["eval"])
    assert _names(text, "OpenPBRSurface", name, kwargs[name].shape)


def test_the_user_parameter_is_named_not_the_internal_lobe():
    asm = AdobeStandardMaterial(roughness=[0.1, 0.2, 0.3, 0.4])
    text = _message(lambda: asm.eval(_batch(WO, 3), _batch(WI, 3)))
    assert text == ("wo has shape (3, 3) and wi has shape (3, 3): their batch shape (3,) does "
                    "not broadcast with the AdobeStandardMaterial's parameter roughness (shape "
                    "(4,))")
    pbr = OpenPBRSurface(base_color=np.ones((4, 3)))
    text = _message(lambda: pbr.sample(_batch(WO, 3), np.full((3, 3), 0.5)))
    assert text.endswith("does not broadcast with the OpenPBRSurface's parameter base_color "
                         "(shape (4, 3), batch shape (4,))")
    assert "alpha" not in text and "albedo" not in text


def test_a_material_names_every_conflicting_parameter_and_only_those():
    asm = AdobeStandardMaterial(roughness=R4(), metallic=np.full((2, 1), 0.5),
                                base_color=C4())
    text = _message(lambda: asm.albedo(_batch(WO, 3)))
    assert text == ("wo has shape (3, 3): its batch shape (3,) does not broadcast with the "
                    "AdobeStandardMaterial's parameters base_color (shape (4, 3), batch shape "
                    "(4,)) and roughness (shape (4,))")


@FAST
@given(material=st.sampled_from(sorted(MATERIAL_CASES)), data=st.data(),
       sizes=st.tuples(st.integers(2, 6), st.integers(2, 6)).filter(lambda s: s[0] != s[1]),
       lead=st.sampled_from([(), (2,)]),
       method=st.sampled_from(["eval", "pdf", "eval_pdf", "sample", "albedo", "albedo_table",
                               "albedo_mc"]))
def test_a_drawn_material_parameter_and_batch_are_named(material, data, sizes, lead, method):
    k, n = sizes
    name = data.draw(st.sampled_from(_shaping(material)), label="parameter")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        obj, value = _textured(material, name, k)
    text = _message(_calls(obj, n, lead)[method])
    assert _names(text, material, name, value.shape, lead + (n,)), text


# -- 3. directions -------------------------------------------------------------------------
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
@pytest.mark.parametrize("arg", ["wo", "wi"])
@pytest.mark.parametrize("index", [0, 2, 4])
def test_a_direction_that_is_not_finite_is_named_with_its_index(bad, arg, index):
    w = {"wo": _batch(WO, 5), "wi": _batch(WI, 5)}
    w[arg][index, (index + 1) % 3] = bad
    lobe = L.Conductor(0.3)
    for call in (lambda: lobe.eval(w["wo"], w["wi"]), lambda: lobe.pdf(w["wo"], w["wi"])):
        text = _message(call)
        assert text.startswith(f"{arg}[{index}] = array(") and "is not finite" in text, text
    if arg == "wo":
        for call in (lambda: lobe.sample(w["wo"], np.full((5, 3), 0.5)),
                     lambda: lobe.albedo(w["wo"]), lambda: lobe.albedo(w["wo"], "table")):
            text = _message(call)
            assert text.startswith(f"wo[{index}] = array(") and "is not finite" in text


def test_a_material_names_a_direction_that_is_not_finite():
    wo = _batch(WO, 3)
    wo[2] = [np.nan, 0.0, 1.0]
    text = _message(lambda: AdobeStandardMaterial().eval(wo, _batch(WI, 3)))
    assert text.startswith("wo[2] = array([nan,") and "is not finite" in text


def test_a_direction_that_is_not_a_unit_vector_is_named_with_its_index():
    wi = _batch(WI, 4)
    wi[1] = [0.0, 1.0, 1.0]
    text = _message(lambda: L.Lambert(0.5).eval(_batch(WO, 4), wi))
    assert text == ("wi[1] = array([0., 1., 1.]) is not a unit vector (allowed: |wi| = 1 "
                    "within 1e-06)")


def test_the_index_of_a_bad_direction_in_a_batch_of_several_axes():
    wo = np.broadcast_to(WO, (2, 3, 3)).copy()
    wo[1, 2] = [0.0, np.inf, 1.0]
    text = _message(lambda: L.Lambert(0.5).eval(wo, WI))
    assert text.startswith("wo[1, 2] = array([ 0., inf,  1.]) is not finite")
    text = _message(lambda: L.Lambert(0.5).eval(WO, [0.0, 0.0, 2.0]))  # one vector: no index
    assert text.startswith("wi = array([0., 0., 2.]) is not a unit vector")


def test_a_bad_direction_of_a_chunked_batch_has_its_own_index():
    wo = _batch(WO, 1000)
    wo[777] = [np.nan, 0.0, 1.0]
    with config.options(chunk_size=64):
        text = _message(lambda: L.Conductor(0.3).eval(wo, _batch(WI, 1000)))
        assert text.startswith("wo[777] = array([nan,") and "is not finite" in text
        wi = np.array([[0.0, 0.0, 3.0]])  # broadcast against the batch: its own index
        text = _message(lambda: L.Conductor(0.3).eval(_batch(WO, 1000), wi))
        assert text.startswith("wi[0] = array([0., 0., 3.]) is not a unit vector")
