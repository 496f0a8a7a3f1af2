"""``render.tone_map`` / ``to_srgb8`` / ``write_png``: exposure and the tone curves."""

import ast
import re
from pathlib import Path

import numpy as np
import pytest

from adobe_bsdf import render
from benchmarks import render_report

ROOT = Path(__file__).resolve().parents[1]


def _srgb8_before_tone_mapping(image):
    """``to_srgb8`` as it was before exposure and tone curves: clip, IEC 61966-2-1, round."""
    c = np.clip(np.asarray(image, dtype=np.float64), 0.0, 1.0)
    s = np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)
    return np.round(s * 255.0).astype(np.uint8)


def _images():
    rng = np.random.default_rng(7)
    return [rng.random((9, 11, 3)) * 4.0, rng.normal(size=(5, 3)) * 3.0,
            np.array([0.0, 0.0031308, 0.5, 1.0, 1e300])[:, None].repeat(3, 1)]


@pytest.mark.parametrize("tonemap", render.TONEMAPS)
def test_curves_are_monotone_map_0_to_0_and_stay_in_0_1(tonemap):
    x = np.concatenate([np.linspace(0.0, 20.0, 200_001), np.geomspace(20.0, 1e12, 1000)])
    y = render.tone_map(np.repeat(x[:, None], 3, 1), tonemap=tonemap)[:, 0]
    assert np.all(np.diff(y) >= 0.0)
    assert y[0] == 0.0
    assert np.all((y >= 0.0) & (y <= 1.0))
    assert y[-1] == 1.0
    assert np.all(render.tone_map(-np.abs(x[:, None]).repeat(3, 1), tonemap=tonemap) == 0.0)


def test_aces_is_the_fitted_curve_increasing_until_it_saturates():
    """[Narkowicz2016]: x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), saturated."""
    x = np.linspace(0.0, 7.2, 10_001)
    y = render.tone_map(np.repeat(x[:, None], 3, 1), tonemap="aces")[:, 0]
    np.testing.assert_allclose(y, x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14),
                               rtol=1e-15, atol=0)
    assert np.all(np.diff(y) > 0.0)  # strictly increasing below the saturation at 7.24
    assert abs(y[np.searchsorted(x, 1.0)] - 0.8038) < 1e-3  # 1 maps to about 0.8
    assert render.tone_map(np.full(3, 7.25), tonemap="aces")[0] == 1.0


@pytest.mark.parametrize("image", _images(), ids=["uniform", "negative", "edges"])
def test_clip_reproduces_the_output_before_tone_mapping_exactly(image):
    expected = _srgb8_before_tone_mapping(image)
    np.testing.assert_array_equal(render.to_srgb8(image), expected)
    np.testing.assert_array_equal(render.to_srgb8(image, exposure=0.0, tonemap="clip"),
                                  expected)


def test_write_png_defaults_are_the_clip_of_before(tmp_path):
    image = _images()[0]
    render.write_png(tmp_path / "a.png", image)
    render.write_png(tmp_path / "b.png", image, exposure=0, tonemap="clip")
    assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()


@pytest.mark.parametrize("tonemap", render.TONEMAPS)
def test_one_stop_doubles_linear_values_before_the_curve(tonemap):
    for image in _images()[:2]:
        np.testing.assert_array_equal(render.tone_map(image, exposure=1.0, tonemap=tonemap),
                                      render.tone_map(2.0 * image, tonemap=tonemap))
        np.testing.assert_array_equal(render.to_srgb8(image, -1.5, tonemap),
                                      render.to_srgb8(image * 2.0**-1.5, 0.0, tonemap))


@pytest.mark.parametrize("kwargs, match", [
    ({"tonemap": "filmic"}, r"tonemap = 'filmic' is not one of \('clip', 'aces'\)"),
    ({"tonemap": None}, r"tonemap = None is not one of"),
    ({"exposure": np.nan}, r"exposure = nan is outside the allowed range"),
    ({"exposure": np.inf}, r"exposure = inf is outside the allowed range"),
    ({"exposure": "1"}, r"exposure"),
    ({"exposure": [0.0, 1.0]}, r"exposure has shape \(2,\); allowed: a single number"),
])
def test_bad_exposure_or_tonemap_names_parameter_value_and_allowed(kwargs, match):
    for call in (render.tone_map, render.to_srgb8):
        with pytest.raises(ValueError, match=match):
            call(np.ones((2, 2, 3)), **kwargs)
    with pytest.raises(ValueError, match=match):
        render.write_png("never-written.png", np.ones((2, 2, 3)), **kwargs)
    assert not Path("never-written.png").exists()


def _readme_calls():
    """Keyword arguments of every call in the README's Python example that renders."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    block = next(b for b in re.findall(r"```python\n(.*?)```", text, re.S) if "write_png" in b)
    calls = {}
    for node in ast.walk(ast.parse(block)):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            calls[node.func.attr] = {k.arg: ast.literal_eval(k.value) for k in node.keywords}
    return calls


def test_readme_example_is_the_measured_sphere_and_choice():
    """The README example renders ``render_report.README_SPHERE`` and writes it with the
    (exposure, tonemap) that ``benchmarks.render_report`` measures as its choice."""
    calls = _readme_calls()
    assert calls["AdobeStandardMaterial"] == render_report.README_SPHERE
    assert calls["sphere"] == {"env": "sky", "size": 128, "spp": 32}
    write = calls["write_png"]
    assert (write["exposure"], write["tonemap"]) == render_report.TONEMAPS[-1]


def test_readme_sphere_keeps_its_red_with_the_filmic_curve(capsys):
    """The README's sphere (smaller, fewer paths): with the defaults most of its pixels clip
    red; with the README's exposure and curve almost none do."""
    image = render_report.readme_sphere(size=48, spp=8)
    before = render_report.clipped_fraction(image)
    exposure, tonemap = render_report.TONEMAPS[-1]
    after = render_report.clipped_fraction(image, exposure, tonemap)
    with capsys.disabled():
        print(f"\nREADME sphere (48 px, 8 spp): red clipped on {before:.1%} of its pixels "
              f"(clip), {after:.1%} (exposure {exposure:g}, {tonemap})")
    assert before > 0.5
    assert after < 0.02
    rgb = render.to_srgb8(image, exposure, tonemap)[render_report._sphere_mask(48)]
    median = np.median(rgb.astype(float), axis=0)
    assert median[0] > 2.5 * median[1] and median[0] > 2.5 * median[2]  # red, not pink
