"""``ab.explore``: controls generated from parameter specifications, driven in Python; the
data behind the panels follows the controls; the registry of explorable lobes builds at
every corner of its soft ranges."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

import adobe_bsdf as ab  # noqa: E402
from adobe_bsdf import explorer as explorer_module  # noqa: E402
from adobe_bsdf.explorables import EXPLORABLES, Explorable, explorable  # noqa: E402
from adobe_bsdf.explorer import Explorer  # noqa: E402
from adobe_bsdf.materials import AdobeStandardMaterial  # noqa: E402
from adobe_bsdf.materials.spec import Parameter, ParameterSpec  # noqa: E402


def _slice_directions(theta_i, theta_o):
    """wi along the slice at azimuth 0, as ``plot.polar_slice`` defines it."""
    return np.stack([-np.sin(theta_i), np.zeros_like(theta_i), np.cos(theta_i)], axis=-1)


@pytest.mark.parametrize("name", list(EXPLORABLES))
def test_every_control_comes_from_the_spec(name):
    explorer = Explorer(name, size="small")
    spec = explorable(name).parameters
    assert list(explorer.controls) == [p.name for p in spec]
    for p in spec:
        control = explorer._controls[p.name]
        if p.default is None:
            assert control.auto.value and all(part.disabled for part in control.parts)
            assert p.name not in explorer.values()
            continue
        value = explorer.values()[p.name]
        if p.kind == "real":
            slider = control.widget
            lo, hi = p.soft or p.hard
            assert np.isfinite(slider.min) and np.isfinite(slider.max)  # JSON has no inf
            assert p.hard[0] <= slider.min and slider.max <= p.hard[1]
            assert slider.min == pytest.approx(lo, abs=(hi - lo) / 199)
            assert slider.max == pytest.approx(hi, abs=(hi - lo) / 199)
            assert (slider.min > p.hard[0]) if p.lo_open else True
            assert (slider.max < p.hard[1]) if p.hi_open else True
            assert value == min(max(p.default, slider.min), slider.max)
        elif p.kind == "color":
            assert type(control.widget).__name__ == "ColorPicker"
            assert value == tuple(np.broadcast_to(p.default, 3).tolist())  # exact
        elif p.kind == "bool":
            assert type(control.widget).__name__ == "Checkbox" and value is p.default
        elif p.kind == "choice":
            assert tuple(control.widget.options) == p.choices and value == p.default
        else:
            np.testing.assert_allclose(value, p.default, atol=1e-12)
    spec.validate(explorer.values())  # what the controls hold is always valid


def test_controls_cannot_leave_the_hard_range():
    explorer = Explorer("OpenPBRSurface", size="small")
    spec = explorable("OpenPBRSurface").parameters
    for p in spec:
        control = explorer._controls[p.name]
        if p.kind != "real" or control.auto is not None:
            continue
        control.widget.value = p.hard[1] + 10.0 if np.isfinite(p.hard[1]) else 1e300
        assert control.widget.value == control.widget.max <= p.hard[1]
        control.widget.value = p.hard[0] - 10.0
        assert control.widget.value == control.widget.min >= p.hard[0]
    spec.validate(explorer.values())
    from traitlets import TraitError
    with pytest.raises(TraitError):
        Explorer("Dielectric", size="small")._controls["model"].widget.value = "phong"


def test_a_control_changes_the_material_the_panels_draw():
    explorer = Explorer("AdobeStandardMaterial", size="small", theta_o=30.0)
    before = explorer.update()
    slice_before = before["slice"].copy()
    explorer._controls["base_color"].widget.value = "#ff0000"  # no event loop: at once
    after = explorer.data
    assert explorer.values()["base_color"] == (1.0, 0.0, 0.0)
    assert not np.array_equal(after["slice"], slice_before)
    # the data are those of the material built directly, along the slice's own angles
    material = AdobeStandardMaterial(base_color=(1.0, 0.0, 0.0))
    theta_o = np.radians(30.0)
    wo = np.array([np.sin(theta_o), 0.0, np.cos(theta_o)])
    wi = _slice_directions(after["theta_i"], theta_o)
    expected = material.eval(np.broadcast_to(wo, wi.shape), wi) * np.abs(wi[:, 2:])
    np.testing.assert_allclose(after["slice"], expected, rtol=1e-12, atol=0)
    np.testing.assert_allclose(after["albedo_at"], material.albedo(wo, method="table"),
                               rtol=1e-12)
    # the view angle moves the panels too
    explorer.view.value = 60.0
    assert not np.array_equal(explorer.data["hemisphere"], after["hemisphere"])
    # the active lobes follow the parameters (coat built only when it has weight)
    assert "coat" not in explorer.data["active"]
    explorer._controls["coat_opacity"].widget.value = 1.0
    assert "coat" in explorer.data["active"]


def test_rest_adds_the_sphere_and_the_quadrature_with_its_error():
    explorer = Explorer("HazyGloss", size="small")
    fast = explorer.update()
    assert "quadrature" not in fast and "sphere" not in fast
    data = explorer.update(slow=True)
    lobe = explorer.lobe()
    wo = np.array([np.sin(np.radians(45.0)), 0.0, np.cos(np.radians(45.0))])
    value = lobe.albedo(wo, method="quadrature")
    np.testing.assert_allclose(data["quadrature"], value, rtol=1e-12)
    np.testing.assert_allclose(data["table_error"],
                               np.abs(lobe.albedo(wo, method="table") - value), rtol=1e-9)
    assert data["sphere"].shape == (16, 16, 3) and np.all(np.isfinite(data["sphere"]))
    assert data["eval_ns"] > 0.0 and data["active"] == ["HazyGloss"]


def test_a_parameter_added_to_a_spec_is_a_control():
    spec = ParameterSpec(Parameter("albedo", "color", (0.5, 0.5, 0.5), (0.0, 1.0)),
                         Parameter("gain", "real", 0.25, (0.0, 1.0), (0.0, 0.5), "new"),
                         Parameter("flavour", "choice", "b", None, choices=("a", "b")),
                         Parameter("reach", "real", 2.0, (0.0, np.inf)))  # no soft range
    target = Explorable("Gained", spec, lambda albedo, gain, flavour, reach: ab.lobes.Lambert(
        np.asarray(albedo) * gain))
    explorer = Explorer(target, size="small")
    assert list(explorer.controls) == ["albedo", "gain", "flavour", "reach"]
    reach = explorer._controls["reach"].widget
    assert (reach.min, reach.max, reach.value) == (0.0, 20.0, 2.0)  # ten times the default
    assert (explorer._controls["gain"].widget.min, explorer._controls["gain"].widget.max) \
        == (0.0, 0.5)
    assert explorer._controls["flavour"].widget.options == ("a", "b")
    explorer._controls["gain"].widget.value = 0.5
    assert np.allclose(explorer.lobe().reflectance, 0.25)


def test_fixed_parameters_have_no_control_and_are_checked():
    explorer = Explorer("Lambert", {"albedo": (0.2, 0.4, 0.6)}, size="small")
    assert not explorer.controls and explorer.values() == {"albedo": (0.2, 0.4, 0.6)}
    with pytest.raises(ValueError, match="colour"):
        Explorer("Lambert", {"colour": 0.5})
    with pytest.raises(ValueError, match="albedo"):
        Explorer("Lambert", {"albedo": 1.5})
    with pytest.raises(ValueError, match="target"):
        Explorer("Phong")
    with pytest.raises(ValueError, match="size"):
        Explorer("Lambert", size="huge")


def test_without_a_front_end_explore_draws_a_static_figure(capsys):
    figure = ab.explore("Lambert", size="small", albedo=0.5)
    assert "no widget front end" in capsys.readouterr().out
    assert len(figure.axes) >= 4


@pytest.mark.parametrize("name", [n for n, e in EXPLORABLES.items()
                                  if n not in ab.materials.MATERIALS])
def test_every_lobe_builds_at_its_soft_range_ends(name):
    target = EXPLORABLES[name]
    defaults = target.parameters.validate({})
    assert isinstance(target.build(**defaults), ab.Lobe)
    for p in target.parameters:
        if p.kind not in ("real", "color"):
            continue
        lo, hi = p.soft or p.hard
        for end in (lo, hi):
            if (end == p.hard[0] and p.lo_open) or (end == p.hard[1] and p.hi_open):
                continue
            values = target.parameters.validate({p.name: end})
            assert isinstance(target.build(**values), ab.Lobe), (p.name, end)


def test_without_ipywidgets_the_controls_are_plain_values(monkeypatch):
    """Where ipywidgets is missing the same controls exist as plain value holders, so the
    static figure still shows the spec's defaults and the given values."""
    monkeypatch.setattr(explorer_module, "_widgets", explorer_module._StaticWidgets)
    explorer = Explorer("EnergyPreservingOrenNayar", {"roughness": 0.7}, size="small")
    assert type(explorer._controls["albedo"].widget).__name__ == "_StaticWidget"
    assert explorer.values() == {"albedo": (0.8, 0.8, 0.8), "compensation": True,
                                 "roughness": 0.7}
    data = explorer.update(slow=True)
    assert data["slice"].shape == (91, 3) and np.all(np.isfinite(data["slice"]))


def test_changes_are_debounced_and_the_slow_panels_wait_for_rest(monkeypatch):
    """On an event loop (a kernel's), a burst of changes gives one fast update DEBOUNCE s
    after the last change and one slow update REST s after it."""
    import asyncio

    from adobe_bsdf import explorer as module

    monkeypatch.setattr(module, "DEBOUNCE", 0.05)
    monkeypatch.setattr(module, "REST", 0.15)
    explorer = Explorer("Lambert", size="small")
    calls = []
    monkeypatch.setattr(explorer, "update", lambda slow=False: calls.append(
        (round(asyncio.get_running_loop().time() - start, 2), slow)))

    async def burst():
        nonlocal start
        start = asyncio.get_running_loop().time()
        for value in ("#101010", "#202020", "#303030"):
            explorer._controls["albedo"].widget.value = value
            await asyncio.sleep(0.01)
        assert calls == []  # nothing while the controls move
        await asyncio.sleep(0.3)

    start = 0.0
    asyncio.run(burst())
    assert [slow for _, slow in calls] == [False, True]
    fast_at, slow_at = calls[0][0], calls[1][0]
    assert 0.07 <= fast_at < slow_at and slow_at >= 0.17  # measured from the first change


def test_the_structure_itself_appears_at_rest():
    """``reference=True``: at rest the panels add the structure followed by full light
    transport; for a bare metal, whose structure is its lobe, its slice is the fast slice
    bit for bit (error 0) and its albedo agrees with the quadrature within 4 errors + 2e-3."""
    explorer = Explorer("OpenPBRSurface", {"base_metalness": 1.0}, size="small",
                        reference=True)
    assert "reference_albedo" not in explorer.update()
    data = explorer.update(slow=True)
    lobe = explorer.lobe()
    theta = data["reference_theta_i"]
    wo = np.array([np.sin(np.radians(45.0)), 0.0, np.cos(np.radians(45.0))])
    wi = np.stack([-np.sin(theta), np.zeros_like(theta), np.cos(theta)], -1)
    np.testing.assert_array_equal(data["reference_slice"],
                                  lobe.eval(wo, wi) * np.abs(np.cos(theta))[:, None])
    np.testing.assert_array_equal(data["reference_slice_error"], 0.0)
    assert np.all(np.abs(data["reference_albedo"] - data["quadrature"])
                  <= 2e-3 + 4.0 * data["reference_albedo_error"])
    assert "structure" in explorer.status.value


def test_a_target_without_a_structure_says_so():
    explorer = Explorer("HazyGloss", size="small", reference=True)
    assert "no structure" in explorer.update(slow=True)["reference_unavailable"]
