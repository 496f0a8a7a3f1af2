"""The bad-input policy (``docs/conventions.md``): invalid parameters and shapes raise
``ValueError`` naming the user's parameter, its value and what is allowed; nothing is
clamped silently. One test (or group) per class of bad input, each with a worked example and,
where the class has many members, a hypothesis strategy over them."""

from __future__ import annotations

import math
import threading

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import adobe_bsdf as ab
from adobe_bsdf import _params, hazy, tables
from adobe_bsdf.lobes import energy_lookup
from adobe_bsdf.materials import AdobeStandardMaterial, presets
from adobe_bsdf.materials.asm import PARAMETERS
from adobe_bsdf.tables import Axis, Table, TableError, TableSpec
from adobe_bsdf.tables import table as table_module

FAST = settings(max_examples=25, deadline=None)
UP = np.array([0.0, 0.0, 1.0])


def _directions(n: int, seed: int = 0) -> np.ndarray:
    return ab.frame.normalize(np.abs(np.random.default_rng(seed).normal(size=(n, 3))))


def _message(excinfo) -> str:
    return str(excinfo.value)


# -- 1. values that are not real numbers ----------------------------------------------------
#: not real numbers: text, bytes, objects, complex numbers, sequences holding any of them
NOT_REAL = st.one_of(
    st.text(max_size=12), st.binary(max_size=12), st.builds(object),
    st.complex_numbers(allow_nan=False, allow_infinity=False, max_magnitude=1.0),
    st.lists(st.sampled_from(["0.5", None, b"1"]), min_size=1, max_size=3))


def test_a_string_roughness_is_rejected_not_parsed():
    with pytest.raises(ValueError, match=r"^roughness = '0\.5' is not a real number"):
        AdobeStandardMaterial(roughness="0.5")
    with pytest.raises(ValueError, match=r"^roughness = None"):
        AdobeStandardMaterial(roughness=None)


@FAST
@given(name=st.sampled_from([p.name for p in PARAMETERS]), value=NOT_REAL)
def test_every_asm_parameter_rejects_what_is_not_a_real_number(name, value):
    with pytest.raises(ValueError) as excinfo:
        AdobeStandardMaterial(**{name: value})
    assert _message(excinfo).startswith(f"{name} = {value!r}")


@pytest.mark.parametrize("name", [p.name for p in PARAMETERS if p.default is not None])
def test_none_is_rejected_where_the_parameter_has_a_default(name):
    with pytest.raises(ValueError, match=rf"^{name} = None"):
        AdobeStandardMaterial(**{name: None})


@FAST
@given(value=NOT_REAL)
def test_every_array_entry_point_rejects_what_is_not_a_real_number(value):
    for check in (lambda v: _params.real("x", v), lambda v: _params.color("x", v),
                  lambda v: _params.direction_shape("x", v),
                  lambda v: _params.uniforms_shape("x", v, 3), lambda v: _params.vectors("x", v)):
        with pytest.raises(ValueError) as excinfo:
            check(value)
        assert _message(excinfo).startswith(f"x = {value!r}")


def test_booleans_and_exact_reals_are_numbers():
    """The documented decision (``_params``): booleans are 0 and 1, as in NumPy (a mask is a
    texture of a 0/1 parameter), and ``numbers.Real`` objects are real numbers."""
    from fractions import Fraction

    wo = _directions(4)
    mask = np.array([True, False, True, False])
    metal = AdobeStandardMaterial(metallic=mask, roughness=Fraction(1, 2))
    expected = AdobeStandardMaterial(metallic=mask.astype(float), roughness=0.5)
    np.testing.assert_array_equal(metal.eval(wo, wo), expected.eval(wo, wo))


# -- 2. vectors of the frame functions ------------------------------------------------------
def test_frame_takes_any_array_like_of_three_vectors():
    frame = ab.Frame((0, 0, 1))
    np.testing.assert_array_equal(frame.to_local([0, 0, 1]), [0.0, 0.0, 1.0])
    np.testing.assert_array_equal(frame.to_world([[1, 0, 0]]), [[1.0, 0.0, 0.0]])
    for bad in ([0, 1], [0, 0, 1, 0]):
        with pytest.raises(ValueError, match=rf"^v has shape \({len(bad)},\); allowed: shape "
                                             r"\(\.\.\., 3\)"):
            frame.to_local(bad)


#: every public function of ``frame`` with its vector arguments' names
FRAME_CALLS = {
    "dot": (lambda a, b: ab.frame.dot(a, b), ("a", "b")),
    "normalize": (lambda v: ab.frame.normalize(v), ("v",)),
    "reflect": (lambda w, m: ab.frame.reflect(w, m), ("w", "m")),
    "refract": (lambda w, m: ab.frame.refract(w, m, 1.5), ("w", "m")),
    "coordinate_system": (lambda n: ab.frame.coordinate_system(n), ("n",)),
    "rotate_tangent": (lambda t, n: ab.frame.rotate_tangent(t, n, 0.1), ("t", "n")),
    "Frame": (lambda n, t: ab.Frame(n, t), ("n", "t")),
    "Frame.to_local": (lambda v: ab.Frame(UP).to_local(v), ("v",)),
    "Frame.to_world": (lambda v: ab.Frame(UP).to_world(v), ("v",)),
}
#: a valid value of every vector argument (unit, perpendicular where it matters)
GOOD = {"a": UP, "b": UP, "v": UP, "w": UP, "m": UP, "n": UP, "t": np.array([1.0, 0, 0])}


@FAST
@given(call=st.sampled_from(sorted(FRAME_CALLS)), which=st.integers(0, 1),
       shape=st.lists(st.integers(0, 4), min_size=1, max_size=3).filter(lambda s: s[-1] != 3))
def test_every_frame_function_names_a_vector_of_the_wrong_shape(call, which, shape):
    fn, names = FRAME_CALLS[call]
    name = names[which % len(names)]
    args = [np.ones(shape) if n == name else GOOD[n] for n in names]
    with pytest.raises(ValueError) as excinfo:
        fn(*args)
    assert _message(excinfo).startswith(f"{name} has shape {tuple(shape)}; allowed: shape "
                                        "(..., 3)")


@FAST
@given(call=st.sampled_from(["dot", "reflect", "refract", "rotate_tangent", "Frame"]),
       sizes=st.tuples(st.integers(2, 5), st.integers(2, 5)).filter(lambda s: s[0] != s[1]))
def test_frame_functions_name_vectors_whose_batches_do_not_broadcast(call, sizes):
    fn, names = FRAME_CALLS[call]
    args = [np.broadcast_to(GOOD[n], (k, 3)) for n, k in zip(names, sizes, strict=True)]
    with pytest.raises(ValueError) as excinfo:
        fn(*args)
    first, second = names
    assert _message(excinfo) == (f"{first} has shape ({sizes[0]}, 3) and {second} has shape "
                                 f"({sizes[1]}, 3): their batch shapes ({sizes[0]},) and "
                                 f"({sizes[1]},) do not broadcast")


def test_a_frame_names_vectors_that_do_not_broadcast_with_it():
    frame = ab.Frame(np.broadcast_to(UP, (2, 3)))
    with pytest.raises(ValueError, match=r"^v has shape \(4, 3\): its batch shape \(4,\) does "
                                         r"not broadcast with the frame's vectors \(shape "
                                         r"\(2,\)\)"):
        frame.to_world(np.ones((4, 3)))
    with pytest.raises(ValueError, match=r"^n = array\(\[0\., 0\., 0\.\]\) is not a finite "
                                         "non-zero vector"):
        ab.Frame([0, 0, 0])
    with pytest.raises(ValueError, match=r"^eta has shape|^w has shape"):
        ab.frame.refract(np.broadcast_to(UP, (3, 3)), UP, [1.5, 1.2])
    with pytest.raises(ValueError, match=r"^m = .* is not a unit vector"):
        ab.frame.reflect(UP, [0, 0, 2])


# -- 3. batch shapes that do not broadcast in the lobe protocol -----------------------------
def test_mismatched_direction_batches_are_named():
    lobe = ab.lobes.Conductor(0.3)
    wo, wi = _directions(5), _directions(4, seed=1)
    with pytest.raises(ValueError) as excinfo:
        lobe.eval(wo, wi)
    assert _message(excinfo) == ("wo has shape (5, 3) and wi has shape (4, 3): their batch "
                                 "shapes (5,) and (4,) do not broadcast")


@FAST
@given(sizes=st.tuples(st.integers(2, 6), st.integers(2, 6)).filter(lambda s: s[0] != s[1]),
       lead=st.integers(1, 3), call=st.sampled_from(["eval", "pdf", "eval_pdf", "sample",
                                                      "pdf_t", "sample_t"]))
def test_every_protocol_method_names_its_mismatched_arguments(sizes, lead, call):
    lobe = ab.lobes.Dielectric(1.5, 0.2)
    n, m = sizes
    wo = np.broadcast_to(UP, (lead, n, 3))
    other = np.broadcast_to(UP, (m, 3))
    u = np.full((m, 3), 0.5)
    white = np.ones((m, 3))
    run = {"eval": lambda: lobe.eval(wo, other), "pdf": lambda: lobe.pdf(wo, other),
           "eval_pdf": lambda: lobe.eval_pdf(wo, other), "sample": lambda: lobe.sample(wo, u),
           "pdf_t": lambda: lobe.pdf(wo, wo, throughput=white),
           "sample_t": lambda: lobe.sample(wo, np.full((n, 3), 0.5), throughput=white)}[call]
    second = {"eval": "wi", "pdf": "wi", "eval_pdf": "wi", "sample": "u"}.get(call, "throughput")
    with pytest.raises(ValueError) as excinfo:
        run()
    text = _message(excinfo)
    assert f"wo has shape {(lead, n, 3)}" in text and f"{second} has shape ({m}, 3)" in text
    assert text.endswith("do not broadcast")


@FAST
@given(sizes=st.tuples(st.integers(2, 6), st.integers(2, 6)).filter(lambda s: s[0] != s[1]),
       method=st.sampled_from(["eval", "sample", "table", "quadrature"]))
def test_parameters_that_do_not_broadcast_with_the_directions_are_named(sizes, method):
    k, n = sizes
    lobe = ab.lobes.Conductor(np.full(k, 0.3))
    wo = _directions(n)
    run = {"eval": lambda: lobe.eval(wo, wo), "sample": lambda: lobe.sample(wo, wo * 0.5),
           "table": lambda: lobe.albedo(wo, "table"),
           "quadrature": lambda: lobe.albedo(wo)}[method]
    with pytest.raises(ValueError) as excinfo:
        run()
    assert f"batch shape ({n},) does not broadcast with the Conductor's parameter alpha_x " \
           f"(shape ({k},))" in _message(excinfo)


def test_a_textured_material_still_broadcasts():
    wo = _directions(7)
    asm = AdobeStandardMaterial(roughness=np.linspace(0.1, 0.9, 7)[:, None],
                                base_color=np.full((7, 3), 0.5))
    assert asm.eval(wo, wo).shape == (7, 7, 3)


# -- 4. the arguments of albedo -------------------------------------------------------------
def test_a_bad_random_source_is_named():
    lobe = ab.lobes.Lambert(0.5)
    with pytest.raises(ValueError, match=r"^rng = 'x' is not a source of random numbers"):
        lobe.albedo(UP, method="mc", rng="x")
    generator = lobe.albedo(UP, "mc", n_samples=100, rng=np.random.default_rng(3))
    np.testing.assert_array_equal(generator, lobe.albedo(UP, "mc", n_samples=100, rng=3))


BAD_ALBEDO = {
    "rng": st.one_of(st.text(max_size=5), st.floats(), st.integers(max_value=-1), st.booleans(),
                     st.builds(object)),
    "tol": st.one_of(st.floats().filter(lambda x: not 0.0 < x < 1.0), st.text(max_size=5)),
    "n_samples": st.one_of(st.integers(max_value=1), st.floats(), st.booleans(),
                           st.text(max_size=5)),
    "method": st.text(max_size=12).filter(lambda m: m not in ab.bsdf.ALBEDO_METHODS),
    "return_error": st.one_of(st.integers(), st.text(max_size=5), st.none()),
}


@FAST
@given(data=st.data(), name=st.sampled_from(sorted(BAD_ALBEDO)),
       method=st.sampled_from(ab.bsdf.ALBEDO_METHODS))
def test_every_albedo_argument_is_checked_whatever_the_method(data, name, method):
    value = data.draw(BAD_ALBEDO[name])
    kwargs = {"method": method, name: value}
    with pytest.raises(ValueError) as excinfo:
        ab.lobes.Conductor(0.3).albedo(UP, **kwargs)
    shown = repr(float(value)) if name == "tol" and not isinstance(value, str) else repr(value)
    assert _message(excinfo).startswith(f"{name} = {shown}")


# -- 5. hazy gloss names the user's parameters ----------------------------------------------
def test_hazy_gloss_names_smooth_weight():
    with pytest.raises(ValueError, match=r"^smooth_weight = 0\.0 is outside"):
        hazy.HazyGloss(0.5, 0.5, 4.0, 0.05, smooth_weight=0)


#: an invalid number for every parameter of ``HazyGloss``
BAD_HAZY = {"core_reflectivity": 1.5, "haziness": -0.1, "haze_extent": -1.0, "alpha_x": 0.0,
            "alpha_y": -1.0, "edge_tint": 2.0, "haze_extent_y": -1.0, "smooth_weight": 0.0}


@FAST
@given(name=st.sampled_from(sorted(BAD_HAZY)),
       value=st.one_of(st.just(None), st.text(max_size=5), st.just(math.nan)))
def test_every_hazy_gloss_parameter_is_named_as_the_user_wrote_it(name, value):
    args = {"core_reflectivity": 0.5, "haziness": 0.5, "haze_extent": 5.0, "alpha_x": 0.05}
    for bad in (BAD_HAZY[name], value):
        if bad is None and name in ("alpha_y", "haze_extent_y", "smooth_weight"):
            continue  # None is their documented default
        with pytest.raises(ValueError) as excinfo:
            hazy.HazyGloss(**{**args, name: bad})
        assert _message(excinfo).startswith(f"{name} = ")


def test_the_haze_functions_name_their_own_arguments():
    cases = [(lambda: hazy.haze_intensity(1.5, 0.5, 0.5), "r_c"),
             (lambda: hazy.haze_intensity(0.5, 0.0, 0.5), "p"),
             (lambda: hazy.haze_intensity_smooth(0.5, 0.5, 0.5, 0.0), "weight"),
             (lambda: hazy.wide_roughness(0.1, 0.1, -1.0), "extent_x"),
             (lambda: hazy.wide_roughness(0.1, 0.1, 1.0, -1.0), "extent_y"),
             (lambda: hazy.peak_ratio((0.1, 0.0), (0.2, 0.2)), r"alpha_n\[1\]"),
             (lambda: hazy.peak_ratio(0.1, (0.2, 0.2)), "alpha_n"),
             (lambda: hazy.HazyGloss(0.5, 0.5, 1e300, 1.0), "haze_extent"),
             (lambda: hazy.haze_mapping(np.full((3, 3), 0.5), np.full(2, 0.5), 4.0, 0.05),
              "core_reflectivity has shape")]
    for run, name in cases:
        with pytest.raises(ValueError, match=rf"^{name} "):
            run()


# -- 6. coordinates outside the energy tables -----------------------------------------------
def test_a_dispersive_channel_outside_the_tables_names_ior_and_dispersion(monkeypatch):
    """The ASM's glass builds (its Kulla-Conty terms read the tables at their end, with a
    warning: ``test_dispersive``); its table albedo is refused, naming ior and dispersion."""
    monkeypatch.setattr(energy_lookup, "_BEYOND_WARNED", threading.Event())
    with pytest.warns(energy_lookup.EnergyRangeWarning, match="dispersion = 1.0"):
        asm = AdobeStandardMaterial(ior=2.99, dispersion=1.0, translucency=1.0, roughness=0.3)
    with pytest.raises(ValueError) as excinfo:
        asm.albedo(UP, method="table")
    text = _message(excinfo)
    assert text.startswith("dispersion = 1.0")
    for part in ("ior", "green channel's 3.01195", "[0.3333, 3]", "ggx_dielectric_outside",
                 "'quadrature' or 'mc'"):
        assert part in text
    assert np.all(np.isfinite(asm.albedo(UP, method="quadrature")))


@FAST
@given(alpha=st.floats(2.01, 1e6), eta=st.floats(3.01, 1e6), below=st.booleans())
def test_lobe_parameters_outside_the_tables_are_named_with_the_range(alpha, eta, below):
    with pytest.raises(ValueError) as excinfo:
        ab.lobes.Conductor(alpha).albedo(UP, "table")
    text = _message(excinfo)
    assert text.startswith(f"alpha_x = {alpha!r}, alpha_y = {alpha!r}")
    assert "[0, 2]" in text and "ggx_conductor" in text and "'quadrature' or 'mc'" in text
    eta = 1.0 / eta if below else eta
    with pytest.raises(ValueError) as excinfo:
        ab.lobes.Dielectric(eta, 0.3).albedo(UP, "table")
    text = _message(excinfo)
    assert text.startswith(f"eta = {eta!r} is outside [0.3333, 3]")
    assert "ggx_dielectric_inside" in text and "'quadrature' or 'mc'" in text


SMALL = TableSpec("small", (Axis("mu", 0.0, 1.0, 3), Axis("alpha", 0.0, 2.0, 3)), ("E",),
                  lambda spec, *nodes: None)


def _small(values=None) -> Table:
    values = np.zeros(SMALL.shape) if values is None else values
    return Table(SMALL, values, np.zeros(SMALL.shape))


@FAST
@given(axis=st.integers(0, 1), value=st.one_of(st.floats(-1e9, -1e-9), st.floats(2.01, 1e9),
                                               st.just(math.nan)))
def test_a_table_names_itself_its_coordinate_the_value_and_its_range(axis, value):
    table = _small()
    coords = [0.5, 0.5]
    if axis == 0 and value > 1.0:
        value -= 1.0  # mu's range is [0, 1]
    coords[axis] = value
    name, hi = ("mu", 1) if axis == 0 else ("alpha", 2)
    expected = (f"table small: coordinate {name} = {value!r} is outside the table's range "
                f"[0, {hi}]")
    for run in (lambda: table(*coords), lambda: table.fix(**{name: value})):
        with pytest.raises(ValueError) as excinfo:
            run()
        assert _message(excinfo).startswith(expected)


# -- 7. tables with non-finite nodes ----------------------------------------------------------
def test_table_error_is_a_value_error():
    assert issubclass(TableError, ValueError)


@FAST
@given(i=st.integers(0, 2), j=st.integers(0, 2), bad=st.sampled_from([math.nan, math.inf]),
       errors=st.booleans())
def test_save_rejects_a_non_finite_node_naming_the_file_and_the_node(i, j, bad, errors):
    values, errs = np.zeros(SMALL.shape), np.zeros(SMALL.shape)
    (errs if errors else values)[i, j, 0] = bad
    table = Table(SMALL, values, errs)
    with pytest.raises(TableError) as excinfo:
        tables.save(table, "never_written.npz")
    mu, alpha = SMALL.axes[0].nodes()[i], SMALL.axes[1].nodes()[j]
    assert _message(excinfo) == (
        f"table small cannot be saved to never_written.npz: its "
        f"{'errors' if errors else 'values'} hold {bad!r} at mu = {mu:.6g} (node {i}), "
        f"alpha = {alpha:.6g} (node {j}), output E; every node must be finite")


def test_load_rejects_a_file_with_a_non_finite_node(tmp_path, monkeypatch):
    values = np.zeros(SMALL.shape)
    values[1, 2, 0] = math.nan
    path = tmp_path / "small.npz"
    with monkeypatch.context() as patch:  # a file written before save checked its nodes
        patch.setattr(table_module, "_first_non_finite", lambda table: None)
        tables.save(_small(values), path)
    with pytest.raises(TableError) as excinfo:
        tables.load(SMALL, path)
    assert _message(excinfo).startswith(f"table file {path} is unusable: its values hold nan at "
                                        "mu = 0.5 (node 1), alpha = 2 (node 2), output E")
    tables.save(_small(), path)
    assert np.all(tables.load(SMALL, path).values == 0.0)


# -- 8. presets build the constructor they are for ------------------------------------------
def test_a_metal_preset_is_a_material():
    gold = AdobeStandardMaterial(**presets.metals["Au"])
    np.testing.assert_allclose(gold.eval(UP, UP),
                               AdobeStandardMaterial(metallic=1.0, base_color=(1.0, 0.7099,
                                                                               0.3148),
                                                     specular_edge_color=(0.9408, 0.9636,
                                                                          0.9099)).eval(UP, UP))


def test_every_preset_builds_its_material_or_lobe():
    wo = _directions(3)
    built = [AdobeStandardMaterial(**m) for m in presets.metals.values()]
    built += [AdobeStandardMaterial(**m, translucency=1.0) for m in presets.media.values()]
    built += [hazy.HazyGloss(**h) for h in presets.hazy.values()]
    for fixed, swept, ends in presets.hazy_sweeps.values():
        built += [hazy.HazyGloss(**fixed, **{swept: v}) for v in ends]
    built += [AdobeStandardMaterial(ior=d["ior"], translucency=1.0,
                                    dispersion=ab.dispersion.abbe_to_dispersion(d["abbe"]))
              for d in presets.dispersion.values()]
    for lobe in built:
        assert np.all(np.isfinite(lobe.eval(wo, wo)))
    for m in presets.media.values():
        assert isinstance(ab.media.asm_medium(**m), ab.media.Medium)
