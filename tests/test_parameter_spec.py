"""Parameter specifications: the one record a material's constructor validates against and
its docs table is written from."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from adobe_bsdf.materials import MATERIALS, AdobeStandardMaterial, Material, ParameterSpec
from adobe_bsdf.materials.asm import PARAMETERS
from adobe_bsdf.materials.spec import Parameter

ROOT = Path(__file__).resolve().parents[1]


def _tables_script():
    spec = importlib.util.spec_from_file_location("parameter_tables",
                                                  ROOT / "docs" / "parameter_tables.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_registry_holds_every_material_with_its_spec():
    for name, cls in MATERIALS.items():
        assert cls.__name__ == name and issubclass(cls, Material)
        assert isinstance(cls.parameters, ParameterSpec) and len(cls.parameters) > 0


def test_docs_tables_are_written_from_the_specs():
    module = _tables_script()
    assert set(MATERIALS) <= set(module.PAGES)
    assert module.main(["--check"]) == 0
    text = (ROOT / "docs" / module.PAGES["AdobeStandardMaterial"]).read_text(encoding="utf-8")
    assert PARAMETERS.markdown() in text
    for p in PARAMETERS:
        assert f"| `{p.name}` |" in text


def test_docs_check_notices_a_stale_table():
    module = _tables_script()
    text = (ROOT / "docs" / "asm.md").read_text(encoding="utf-8")
    stale = text.replace("| `roughness` | real | [0, 1] |", "| `roughness` | real | [0, 2] |")
    assert stale != text and module.updated("AdobeStandardMaterial", stale) == text


def test_asm_spec_is_the_constructors():
    """The material reads its defaults from the spec: no arguments and every default given
    explicitly build the same BSDF."""
    explicit = {p.name: p.default for p in PARAMETERS if p.default is not None}
    rng = np.random.default_rng(3)
    w = rng.normal(size=(2, 200, 3))
    w /= np.linalg.norm(w, axis=-1, keepdims=True)
    np.testing.assert_array_equal(AdobeStandardMaterial().eval(w[0], w[1]),
                                  AdobeStandardMaterial(**explicit).eval(w[0], w[1]))
    assert set(AdobeStandardMaterial().params) == set(explicit) | {"scattering_color"}


@pytest.mark.parametrize("p", list(PARAMETERS), ids=lambda p: p.name)
def test_hard_ranges_raise_naming_the_parameter(p):
    lo, hi = p.hard
    for bad in ([lo - 0.5] if np.isfinite(lo) else []) + ([hi + 0.5] if np.isfinite(hi) else []) \
            + [np.nan]:
        with pytest.raises(ValueError, match=p.name):
            AdobeStandardMaterial(**{p.name: bad})


def test_soft_ranges_lie_inside_the_hard_ones():
    for p in PARAMETERS:
        if p.soft is not None:
            assert p.hard[0] <= p.soft[0] < p.soft[1] <= p.hard[1], p.name
            AdobeStandardMaterial(**{p.name: p.soft[1]})  # allowed


def test_validate_rejects_unknown_and_missing_values():
    spec = ParameterSpec(Parameter("a", "real", 0.5, (0.0, 1.0)),
                         Parameter("c", "color", None, (0.0, 1.0)))
    assert spec.validate({}) == {"a": 0.5}
    np.testing.assert_array_equal(spec.validate({"c": 0.2})["c"], [0.2, 0.2, 0.2])
    with pytest.raises(ValueError, match=r"unknown parameter\(s\) \['b'\]"):
        spec.validate({"b": 1.0})
    with pytest.raises(ValueError, match=r"a = None: allowed a real in \[0, 1\]"):
        spec.validate({"a": None})
    with pytest.raises(ValueError, match="c has shape"):
        spec.validate({"c": [0.1, 0.2]})
    with pytest.raises(ValueError, match="kind"):
        Parameter("x", "texture", 0.0, (0.0, 1.0))
    with pytest.raises(ValueError, match="unique"):
        ParameterSpec(Parameter("a", "real", 0.0, (0.0, 1.0)),
                      Parameter("a", "real", 0.0, (0.0, 1.0)))


def test_asm_validates_each_parameter_once(monkeypatch):
    """Building a loaded ASM checks each user parameter once, at the spec; the lobes are
    assembled from the validated arrays (the only other checks are the tables' own range
    checks of the coordinates they are looked up at)."""
    import inspect

    from adobe_bsdf import _params

    calls = []
    real = _params.real

    def counting(name, *args, **kwargs):
        caller = Path(inspect.stack()[1].filename)
        calls.append((name, "tables" in caller.parts or caller.name == "energy_lookup.py"))
        return real(name, *args, **kwargs)

    monkeypatch.setattr(_params, "real", counting)
    AdobeStandardMaterial(metallic=0.5, translucency=0.5, roughness=0.4, dispersion=0.5,
                          anisotropy_level=0.3, anisotropy_angle=0.2, coat_opacity=0.5,
                          coat_color=(0.9, 0.8, 0.7), sheen_opacity=0.5)
    outside_tables = sorted(name for name, in_tables in calls if not in_tables)
    expected = sorted(p.name for p in PARAMETERS if p.default is not None)
    assert outside_tables == expected
    assert sum(in_tables for _, in_tables in calls) <= 6


def test_choices_and_open_upper_bounds():
    model = Parameter("model", "choice", "ggx", None, choices=("ggx", "beckmann"))
    assert model.validate("beckmann") == "beckmann" and model.range_text == "{ggx, beckmann}"
    with pytest.raises(ValueError, match="model = 'phong' is not one of"):
        model.validate("phong")
    r = Parameter("r", "real", 0.5, (0.0, 1.0), hi_open=True)
    assert r.range_text == "[0, 1)" and r.validate(0.999) == 0.999
    with pytest.raises(ValueError, match="r = 1"):
        r.validate(1.0)
    with pytest.raises(ValueError, match="choices"):
        Parameter("model", "choice", "ggx", None)
    with pytest.raises(ValueError, match="choices"):
        Parameter("x", "real", 0.5, (0.0, 1.0), choices=("a",))
    with pytest.raises(ValueError, match="hi_open"):
        Parameter("c", "color", 0.5, (0.0, 1.0), hi_open=True)
