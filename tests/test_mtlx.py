"""MaterialX import and export of OpenPBR Surface (``adobe_bsdf.io``): values as the file says
them (after the documented colour conversion, checked against published and independently
computed matrices), errors naming the file, node and input, warnings naming the input and the
value used, bit-exact round trips, finite outputs of every material read, and every example
of a folder named ``openpbr_examples`` beside the checkout."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import MaterialX as mx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adobe_bsdf.io import MtlxResult, MtlxWarning, load_mtlx, mtlx, save_mtlx
from adobe_bsdf.materials.openpbr import DEV_1_2, PARAMETERS, OpenPBRSurface
from tests.sweeps import sweep

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"
EXAMPLES = sorted(f for folder in ROOT.parent.glob("*/openpbr_examples")
                  for f in folder.glob("*.mtlx"))

#: ACEScg -> linear Rec. 709 with the Bradford adaptation, as MaterialX's cmlib publishes it
#: (ND_acescg_to_lin_rec709_color3, written there transposed for row vectors)
ACESCG_TO_REC709 = np.array([[1.705050992658, -0.621792120657, -0.083258872001],
                             [-0.130256417507, 1.140804736575, -0.010548319068],
                             [-0.024003356805, -0.128968976065, 1.15297233287]])
WO = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, 0.96, 0.28]])
WI = np.array([[0.0, 0.6, 0.8], [-0.6, 0.0, 0.8], [0.28, 0.0, -0.96]])
U = np.array([[0.1, 0.2, 0.3], [0.5, 0.5, 0.5], [0.9, 0.7, 0.05]])
#: the documents of tests/data that read, and those that raise (tested one by one below)
READABLE = ["mtlx_minimal.mtlx", "mtlx_acescg.mtlx", "mtlx_textured.mtlx", "mtlx_nodedef.mtlx",
            "mtlx_duplicates.mtlx"]
UNREADABLE = ["mtlx_malformed.mtlx", "mtlx_unknown_node.mtlx", "mtlx_out_of_range.mtlx"]


def _load(path, **kwargs):
    """``load_mtlx`` with its warnings caught: (result, messages)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = load_mtlx(path, **kwargs)
    return result, [str(w.message) for w in caught]


def _bits(value) -> bytes:
    return np.asarray(value, dtype=np.float64).tobytes()


def _assert_identical(a: dict, b: dict) -> None:
    assert a.keys() == b.keys()
    for name in a:
        if isinstance(a[name], bool):
            assert a[name] is b[name], name
        else:
            assert np.shape(a[name]) == np.shape(b[name]), name
            assert _bits(a[name]) == _bits(b[name]), (name, a[name], b[name])


def _assert_finite(material) -> None:
    f = material.eval(WO, WI)
    s = material.sample(WO, U)
    E = material.albedo(WO, method="table")
    for what, x in (("eval", f), ("sample weight", s.weight), ("sample pdf", s.pdf),
                    ("albedo", E)):
        assert np.all(np.isfinite(x)), (what, x)
    assert f.shape == E.shape == (3, 3)
    assert np.all(f >= 0.0) and np.all(E >= 0.0)


# -- reading -----------------------------------------------------------------------------------
def test_minimal_document_reads_the_values_it_writes():
    result, messages = _load(DATA / "mtlx_minimal.mtlx")
    assert isinstance(result, MtlxResult) and list(result) == ["Red_Plastic"]
    assert messages == []
    record = result.records["Red_Plastic"]
    assert record.node == "SR_red_plastic" and record.conversion == "none"
    p = result["Red_Plastic"].params
    np.testing.assert_array_equal(p["base_color"], [0.7, 0.1, 0.05])
    assert p["specular_roughness"] == 0.25 and p["specular_ior"] == 1.45
    assert p["coat_weight"] == 0.5 and p["coat_roughness"] == 0.125
    # an input the file does not set keeps OpenPBR's default
    assert p["fuzz_roughness"] == 0.5 and p["specular_color"].tolist() == [1.0, 1.0, 1.0]
    assert record.colorspaces == {"base_color": "lin_rec709"} and record.original == {}


def test_float_values_are_read_as_float64_not_float32(tmp_path):
    text = (DATA / "mtlx_minimal.mtlx").read_text().replace('"0.25"', '"0.1234567890123456"')
    (tmp_path / "digits.mtlx").write_text(text)
    result, _ = _load(tmp_path / "digits.mtlx")
    assert result["Red_Plastic"].params["specular_roughness"] == 0.1234567890123456


def test_acescg_colours_are_converted_with_the_bradford_matrix():
    import colour

    result, messages = _load(DATA / "mtlx_acescg.mtlx")
    record = result.records["Tinted_Coat"]
    assert record.colorspaces == {"base_color": "acescg", "specular_color": "acescg",
                                  "coat_color": "lin_rec709"}
    assert "acescg -> lin_rec709" in record.conversion and "Bradford" in record.conversion
    # colour-science's matrix, computed here, agrees with the published one
    M = colour.matrix_RGB_to_RGB(colour.RGB_COLOURSPACES["ACEScg"],
                                 colour.RGB_COLOURSPACES["ITU-R BT.709"], "Bradford")
    np.testing.assert_allclose(M, ACESCG_TO_REC709, atol=1e-11)
    base = np.array([0.45, 0.35, 0.25])
    np.testing.assert_allclose(record.params["base_color"], ACESCG_TO_REC709 @ base,
                               rtol=0, atol=1e-11)
    np.testing.assert_allclose(result["Tinted_Coat"].params["base_color"], M @ base,
                               rtol=0, atol=1e-15)
    assert record.original["base_color"] == (0.45, 0.35, 0.25)
    # a per-input colorspace override is not converted
    assert result["Tinted_Coat"].params["coat_color"].tolist() == [0.9, 0.8, 0.7]
    # the node's own srgb_texture: the sRGB decoding (IEC 61966-2-1), no matrix
    velvet = result.records["Velvet_Texture_Space"]
    assert velvet.colorspaces == {"fuzz_color": "srgb_texture"}
    assert velvet.conversion == "srgb_texture -> lin_rec709 (sRGB decoding)"
    srgb = np.array([0.5, 0.25, 0.03])
    expected = np.where(srgb <= 0.04045, srgb / 12.92, ((srgb + 0.055) / 1.055) ** 2.4)
    np.testing.assert_allclose(velvet.params["fuzz_color"], expected, rtol=1e-14)
    assert len(messages) == 1  # the clipped green below, and nothing else


def test_out_of_gamut_colour_is_clipped_with_a_warning_naming_input_and_values():
    result, messages = _load(DATA / "mtlx_acescg.mtlx")
    green = ACESCG_TO_REC709 @ np.array([0.1, 0.9, 0.1])
    assert green[0] < 0.0 and green[1] > 1.0  # the test's premise: outside [0, 1]
    np.testing.assert_array_equal(result["Tinted_Coat"].params["specular_color"],
                                  np.clip(green, 0.0, 1.0))
    (message,) = messages
    assert "mtlx_acescg.mtlx" in message and "'SR_tinted'" in message
    assert "'specular_color'" in message and "(0.1, 0.9, 0.1) in acescg" in message
    assert f"{green[0]:.6g}" in message and "clipped to (0, 1, 0)" in message
    assert result.records["Tinted_Coat"].warnings == (message,)


def test_colour_beyond_its_range_in_the_file_is_clipped_a_real_one_raises(tmp_path):
    text = (DATA / "mtlx_minimal.mtlx").read_text().replace("0.7, 0.1, 0.05", "1.25, 0.1, 0")
    (tmp_path / "bright.mtlx").write_text(text)
    result, messages = _load(tmp_path / "bright.mtlx")
    assert result["Red_Plastic"].params["base_color"].tolist() == [1.0, 0.1, 0.0]
    assert any("'base_color' = (1.25, 0.1, 0) is outside" in m for m in messages)


def test_emission_color_may_exceed_one(tmp_path):
    (tmp_path / "lamp.mtlx").write_text(_document(
        '<input name="emission_color" type="color3" value="4, 2, 1" />'
        '<input name="emission_luminance" type="float" value="100" />'))
    result, messages = _load(tmp_path / "lamp.mtlx")
    assert result["M"].params["emission_color"].tolist() == [4.0, 2.0, 1.0]
    assert not any("clipped" in m for m in messages)


def test_warning_of_an_input_not_modelled_surfaces_and_is_recorded(tmp_path):
    (tmp_path / "bumped.mtlx").write_text(_document(
        '<input name="geometry_coat_normal" type="vector3" value="0, 0.6, 0.8" />'))
    with pytest.warns(UserWarning, match=r"bumped\.mtlx: node 'S': .*geometry_coat_normal"):
        result = load_mtlx(tmp_path / "bumped.mtlx")
    np.testing.assert_array_equal(result["M"].params["geometry_coat_normal"], [0, 0.6, 0.8])
    (message,) = result.records["M"].warnings
    assert "geometry_coat_normal" in message and "not modelled" in message


def test_connected_inputs_warn_with_the_value_used():
    result, messages = _load(DATA / "mtlx_textured.mtlx")
    p = result["Textured"].params
    np.testing.assert_array_equal(p["base_color"], [0.2, 0.4, 0.6])  # its own value
    assert p["specular_roughness"] == 0.3  # the nodedef's default
    assert p["base_metalness"] == 0.25
    image = [m for m in messages if "'base_color'" in m]
    graph = [m for m in messages if "'specular_roughness'" in m]
    assert len(image) == len(graph) == 1 and len(messages) == 2
    assert 'nodename="albedo_map"' in image[0] and "0.2, 0.4, 0.6 is used" in image[0]
    assert 'nodegraph="NG_roughness"' in graph[0] and "default 0.3 is used" in graph[0]
    assert all("mtlx_textured.mtlx" in m and "'SR_textured'" in m for m in messages)


def test_warnings_have_the_importer_category():
    with pytest.warns(MtlxWarning, match="not evaluated"):
        load_mtlx(DATA / "mtlx_textured.mtlx")


def test_document_nodedef_defaults_are_used_and_reported():
    result, messages = _load(DATA / "mtlx_nodedef.mtlx")
    p = result["Studio_Coat"].params
    assert p["coat_weight"] == 0.75
    assert p["coat_roughness"] == 0.2  # the document's nodedef, not the library's 0
    assert p["base_color"].tolist() == [0.5, 0.5, 0.5]
    assert p["specular_roughness"] == 0.3  # not declared there: OpenPBR's default
    assert len(messages) == 2
    assert any("'coat_roughness'" in m and "0.2" in m and "nodedef" in m for m in messages)


def _library_defaults():
    """{input: default} of MaterialX's own ND_open_pbr_surface_surfaceshader, parsed here
    from its value strings."""
    lib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), lib)
    nodedef = lib.getNodeDef("ND_open_pbr_surface_surfaceshader")
    assert nodedef is not None
    out = {}
    for inp in nodedef.getActiveInputs():
        text = inp.getValueString()
        if inp.getType() == "boolean":
            out[inp.getName()] = text == "true"
        elif text:
            out[inp.getName()] = tuple(float(v) for v in text.split(","))
        else:
            out[inp.getName()] = inp.getAttribute("defaultgeomprop")
    return out


def test_standard_nodedef_defaults_agree_with_the_parameter_spec():
    defaults = _library_defaults()
    released = [p for p in PARAMETERS if p.name not in DEV_1_2]
    assert set(defaults) == {p.name for p in released}
    geomprop = {"geometry_normal": "Nworld", "geometry_coat_normal": "Nworld",
                "geometry_tangent": "Tworld", "geometry_coat_tangent": "Tworld"}
    for p in released:
        if p.kind == "vector":  # world normal / tangent: the local frame's n and x
            assert defaults[p.name] == geomprop[p.name]
        elif p.kind == "bool":
            assert defaults[p.name] is p.default
        else:
            np.testing.assert_array_equal(np.broadcast_to(defaults[p.name], 3),
                                          np.broadcast_to(p.default, 3), err_msg=p.name)


def test_duplicate_and_unreferenced_shaders_get_deterministic_names():
    result, messages = _load(DATA / "mtlx_duplicates.mtlx")
    assert list(result) == ["Shiny", "Shiny_Copy", "Matte", "Shiny_2"] and messages == []
    assert result["Shiny"] is result["Shiny_Copy"]
    assert result.records["Shiny_2"].node == "NG_library/Shiny"
    assert result["Shiny"].params["specular_roughness"] == 0.05
    assert result["Matte"].params["specular_roughness"] == 0.95
    assert result["Shiny_2"].params["base_metalness"] == 1.0


# -- errors ------------------------------------------------------------------------------------
def _document(inputs: str, colorspace: str = "") -> str:
    attr = f' colorspace="{colorspace}"' if colorspace else ""
    return (f'<?xml version="1.0"?>\n<materialx version="1.39"{attr}>\n'
            '<surfacematerial name="M" type="material"><input name="surfaceshader" '
            'type="surfaceshader" nodename="S" /></surfacematerial>\n'
            f'<open_pbr_surface name="S" type="surfaceshader">{inputs}</open_pbr_surface>\n'
            '</materialx>\n')


def test_malformed_xml_names_the_file_and_the_parser_message():
    path = DATA / "mtlx_malformed.mtlx"
    with pytest.raises(ValueError, match=re.escape(str(path))) as info:
        load_mtlx(path)
    assert "parse error" in str(info.value)


def test_unknown_shader_node_names_file_material_and_node():
    path = DATA / "mtlx_unknown_node.mtlx"
    with pytest.raises(ValueError) as info:
        load_mtlx(path)
    text = str(info.value)
    assert str(path) in text and "'Other_Model'" in text and "'SR_standard'" in text
    assert "standard_surface" in text and "open_pbr_surface" in text


def test_out_of_range_value_names_file_node_input_value_and_range():
    path = DATA / "mtlx_out_of_range.mtlx"
    with pytest.raises(ValueError) as info:
        load_mtlx(path)
    text = str(info.value)
    assert str(path) in text and "'SR_rough'" in text and "'specular_roughness'" in text
    assert "1.5" in text and "[0.0, 1.0]" in text


@pytest.mark.parametrize("inputs, colorspace, expected", [
    ('<input name="base_colour" type="color3" value="1, 0, 0" />', "", "base_colour"),
    ('<input name="base_color" type="float" value="0.5" />', "", "type 'float'"),
    ('<input name="base_color" type="color3" value="0.5, 0.5" />', "", "not a color3"),
    ('<input name="coat_ior" type="float" value="1,5" />', "", "'1,5' is not a float"),
    ('<input name="coat_ior" type="float" value="nan" />', "", "'nan' is not a float"),
    ('<input name="coat_weight" type="float" value="-0.5" />', "", "coat_weight = -0.5"),
    ('<input name="geometry_thin_walled" type="boolean" value="yes" />', "",
     "'yes' is not a boolean"),
    ('<input name="geometry_tangent" type="vector3" value="0, 0, 0" />', "",
     "geometry_tangent"),
    ('<input name="base_color" type="color3" value="0.5, 0.5, 0.5" />', "xyz_d50",
     "colorspace 'xyz_d50' is unknown"),
])
def test_bad_inputs_raise_naming_file_node_and_input(tmp_path, inputs, colorspace, expected):
    path = tmp_path / "bad.mtlx"
    path.write_text(_document(inputs, colorspace))
    with pytest.raises(ValueError) as info:
        load_mtlx(path)
    text = str(info.value)
    assert str(path) in text and "node 'S'" in text and expected in text, text


def test_document_without_open_pbr_surface(tmp_path):
    path = tmp_path / "none.mtlx"
    path.write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n<standard_surface '
                    'name="SR" type="surfaceshader" />\n</materialx>\n')
    with pytest.raises(ValueError, match=r"none\.mtlx: no open_pbr_surface node .*"
                                         r"standard_surface"):
        load_mtlx(path)


def test_material_naming_a_missing_shader(tmp_path):
    path = tmp_path / "dangling.mtlx"
    path.write_text(_document("").replace('nodename="S"', 'nodename="Gone"'))
    with pytest.raises(ValueError, match=r"dangling\.mtlx: surfacematerial 'M'.*'Gone'"):
        load_mtlx(path)


def test_missing_file():
    with pytest.raises(FileNotFoundError, match="nowhere.mtlx"):
        load_mtlx(DATA / "nowhere.mtlx")


# -- writing -----------------------------------------------------------------------------------
def test_saved_document_is_valid_and_writes_only_inputs_off_default(tmp_path):
    material = OpenPBRSurface(base_color=(0.1, 0.2, 0.3), specular_roughness=0.1 + 0.2)
    path = save_mtlx(material, tmp_path / "one.mtlx")
    doc = mx.createDocument()
    mx.readFromXmlFile(doc, str(path))
    lib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), lib)
    doc.setDataLibrary(lib)
    assert doc.validate() == (True, "")
    (shader,) = doc.getNodes("open_pbr_surface")
    assert sorted(i.getName() for i in shader.getInputs()) == ["base_color",
                                                               "specular_roughness"]
    # repr precision: 0.1 + 0.2 is 0.30000000000000004, which MaterialX's own formatting
    # would write as 0.3
    assert shader.getInput("specular_roughness").getValueString() == "0.30000000000000004"
    assert [m.getName() for m in doc.getMaterialNodes()] == ["material"]


def test_save_rejects_bad_arguments(tmp_path):
    material = OpenPBRSurface()
    with pytest.raises(ValueError, match="colorspace = 'rgb'"):
        save_mtlx(material, tmp_path / "x.mtlx", colorspace="rgb")
    with pytest.raises(ValueError, match="material name 'two words'"):
        save_mtlx({"two words": material}, tmp_path / "x.mtlx")
    with pytest.raises(ValueError, match=r"base_color has shape \(2, 3\)"):
        save_mtlx(OpenPBRSurface(base_color=np.full((2, 3), 0.5)), tmp_path / "x.mtlx")
    with pytest.raises(ValueError, match="allowed an OpenPBRSurface"):
        save_mtlx({"a": "not a material"}, tmp_path / "x.mtlx")


def _params_strategy():
    """Random values of every input inside its hard range (indices where the energy tables
    hold them; the large reals up to 10)."""
    def one(p):
        if p.kind == "bool":
            return st.booleans()
        if p.kind == "vector":
            return st.tuples(*[st.floats(-1.0, 1.0)] * 3).filter(
                lambda v: np.linalg.norm(v) > 1e-3)
        if p.name.endswith("_ior"):
            return st.floats(1.05, 2.5)
        if p.name == "transmission_dispersion_abbe_number":  # its soft range: the channels'
            return st.floats(*p.soft)                         # indices stay in the tables
        lo, hi = p.hard
        real = st.floats(lo, min(hi, 10.0), exclude_min=p.lo_open)
        return st.tuples(real, real, real) if p.kind == "color" else real
    skip = {"specular_weight"}  # its modulation of the index can leave the tables
    released = {p.name: one(p) for p in PARAMETERS if p.name not in skip | set(DEV_1_2)}
    dev = {p.name: one(p) for p in PARAMETERS if p.name not in skip}
    return (st.fixed_dictionaries(released)
            | st.fixed_dictionaries(dev).map(lambda d: dict(d, spec="dev_1.2")))


def _material(params) -> OpenPBRSurface:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return OpenPBRSurface(**params)


@settings(max_examples=400, deadline=None)
@given(params=_params_strategy())
def test_every_input_reads_back_bit_exactly(params):
    """What ``save_mtlx`` writes for an input (``_format`` of the validated value) is read
    back by ``load_mtlx``'s parser to the same validated bits, for every input at once:
    the values' part of the round trip, on many more draws than the whole documents below
    (whose materials take seconds each to build)."""
    for name, value in params.items():
        if name == "spec":
            continue
        p = PARAMETERS[name]
        written = p.validate(value)
        text = mtlx._format(p, written, mtlx.WORKING_SPACE, "Random")
        read = mtlx._parse(text, mtlx._TYPES[p.kind], name)
        assert mtlx._same(p.validate(read), written), (name, value, text)


def _round_trip(tmp_path_factory, params):
    """Whole documents: every input of random materials (both versions) back bit for bit."""
    material = _material(params)
    path = save_mtlx({"Random": material}, tmp_path_factory.mktemp("rt") / "random.mtlx")
    result, _ = _load(path)
    assert result["Random"].spec == material.spec
    _assert_identical(material.params, result["Random"].params)


# each random material may compute its anisotropic energy slices (seconds each)
test_round_trip_is_bit_exact = sweep(_round_trip, 4, params=_params_strategy())
test_round_trip_is_bit_exact_exhaustively = sweep(_round_trip, 10, params=_params_strategy(),
                                                  slow=True)


def test_round_trip_through_another_colour_space(tmp_path):
    material = _material({"base_color": (0.2, 0.5, 0.9), "coat_color": (1.0, 0.9, 0.8),
                          "fuzz_color": (0.3, 0.3, 0.3)})
    for space in ("acescg", "srgb_texture", "adobergb", "srgb_displayp3"):
        path = save_mtlx(material, tmp_path / f"{space}.mtlx", colorspace=space)
        assert f'colorspace="{space}"' in path.read_text()
        result, messages = _load(path)
        assert messages == []
        for name in ("base_color", "coat_color", "fuzz_color", "specular_color"):
            np.testing.assert_allclose(result["material"].params[name],
                                       material.params[name], rtol=0, atol=1e-13)


def test_every_data_file_is_tested():
    assert {p.name for p in DATA.glob("*.mtlx")} == set(READABLE) | set(UNREADABLE)


@pytest.mark.parametrize("name", READABLE)
def test_every_readable_data_file_round_trips_and_evaluates(tmp_path, name):
    result, _ = _load(DATA / name)
    _check_round_trip_and_outputs(result, tmp_path)


def _check_round_trip_and_outputs(result: MtlxResult, tmp_path: Path) -> None:
    path = save_mtlx(dict(result), tmp_path / "again.mtlx")
    again, _ = _load(path)
    assert list(again) == list(result)
    for name, material in result.items():
        _assert_identical(material.params, again[name].params)
        _assert_finite(material)


# -- the examples beside the checkout ----------------------------------------------------------
@pytest.mark.parametrize("path", EXAMPLES or [None],
                         ids=lambda p: p.name if p is not None else "none")
def test_example_loads_evaluates_and_round_trips(tmp_path, path):
    if path is None:
        pytest.skip("no folder named openpbr_examples beside the checkout (looked for "
                    "../*/openpbr_examples/*.mtlx); the logic is covered by tests/data")
    result, _ = _load(path)
    assert len(result) >= 1
    for record in result.records.values():
        assert record.conversion != "" and isinstance(record.material, OpenPBRSurface)
    _check_round_trip_and_outputs(result, tmp_path)


def test_the_readme_example_loads_and_renders():
    """The README's MaterialX example: the document shipped in ``adobe_bsdf.data`` loads
    without a warning into the coated paint it writes, and renders (tiny) to finite
    radiance."""
    from importlib.resources import files

    import adobe_bsdf as ab

    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert 'load_mtlx(files("adobe_bsdf.data") / "openpbr_coated_paint.mtlx")' in readme
    result = load_mtlx(files("adobe_bsdf.data") / "openpbr_coated_paint.mtlx")
    assert list(result) == ["Coated_Red_Paint"] and not result.warnings
    paint = result["Coated_Red_Paint"]
    np.testing.assert_array_equal(paint.params["base_color"], [0.62, 0.06, 0.04])
    assert set(paint.lobes) == {"specular", "diffuse", "coat"}
    image = ab.render.sphere(paint, env="sky", size=8, spp=2, progress=False)
    assert image.shape == (8, 8, 3) and np.all(np.isfinite(image)) and image.max() > 0.0
