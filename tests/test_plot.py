"""adobe_bsdf.plot: the data each figure draws, recomputed independently, and bad input."""

import re
import subprocess
import sys

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import adobe_bsdf as ab  # noqa: E402
from adobe_bsdf import plot, spectral  # noqa: E402
from adobe_bsdf.bsdf import luminance  # noqa: E402
from adobe_bsdf.validation import chi2_test  # noqa: E402
from tests.test_architecture import _bibliography_keys  # noqa: E402
from tests.tolerances import EXACT  # noqa: E402

#: a rough anisotropic dielectric: reflection, transmission and azimuth dependence
DIELECTRIC = ab.lobes.Dielectric(1.5, 0.3, 0.1)
#: a coloured rough metal
METAL = ab.lobes.Conductor(0.25, fresnel=ab.fresnel.F82Tint((0.9, 0.6, 0.4), 0.9))
#: an outgoing direction off the x-z plane (theta_o = 40 deg, phi_o = 30 deg)
WO = np.array([np.sin(np.radians(40.0)) * np.cos(np.radians(30.0)),
               np.sin(np.radians(40.0)) * np.sin(np.radians(30.0)), np.cos(np.radians(40.0))])


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _data_lines(ax):
    """The curves of an Axes, without the reference lines (labels starting with '_wo', ...)."""
    return [line for line in ax.get_lines() if line.get_label() not in ("_wo", "_furnace")]


def _spherical(theta, phi):
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)],
                    axis=-1)


# -- import ---------------------------------------------------------------------------------
def test_library_imports_without_matplotlib():
    code = ("import sys; sys.modules['matplotlib'] = None\n"
            "import adobe_bsdf, adobe_bsdf.plot as p\n"
            "try:\n    p.fresnel_curves({'x': lambda mu: mu})\n"
            "except ImportError as e:\n    print('ImportError', e)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.startswith("ImportError") and "matplotlib" in out


# -- polar_slice ----------------------------------------------------------------------------
def test_polar_slice_draws_eval_in_the_plane_of_incidence():
    n = 181
    ax = plot.polar_slice(DIELECTRIC, WO, n=n)
    assert ax.name == "polar"
    lines = _data_lines(ax)
    assert [line.get_label() for line in lines] == ["R", "G", "B"]
    # independently: |theta_i| from the normal, azimuth phi_o + pi on the mirror side
    t = np.linspace(-np.pi, np.pi, n)
    phi_i = np.radians(30.0) + np.where(t > 0.0, np.pi, 0.0)
    expected = DIELECTRIC.eval(WO, _spherical(np.abs(t), phi_i))
    for c, line in enumerate(lines):
        np.testing.assert_allclose(line.get_xdata(), t, rtol=0, atol=EXACT)
        np.testing.assert_allclose(line.get_ydata(), expected[:, c], rtol=EXACT, atol=0)
    below = np.abs(t) > np.pi / 2
    assert lines[0].get_ydata()[below].max() > 0.0  # transmission is drawn
    # the refracted peak is on the mirror side, below the horizon
    assert np.pi / 2 < t[np.argmax(lines[0].get_ydata() * below)] < np.pi


def test_polar_slice_quantities_channels_and_theta_input():
    theta_o = np.radians(60.0)
    wo = np.array([np.sin(theta_o), 0.0, np.cos(theta_o)])
    n = 91
    t = np.linspace(-np.pi, np.pi, n)
    wi = _spherical(np.abs(t), np.where(t > 0.0, np.pi, 0.0))
    f = METAL.eval(wo, wi)
    cases = {"pdf": METAL.pdf(wo, wi), "eval_cos": luminance(f) * np.abs(np.cos(t)),
             "eval": f[:, 1]}
    channels = {"pdf": None, "eval_cos": "luminance", "eval": 1}
    for quantity, expected in cases.items():
        ax = plot.polar_slice(METAL, theta_o, quantity=quantity, channel=channels[quantity],
                              n=n)
        (line,) = _data_lines(ax)
        np.testing.assert_allclose(line.get_ydata(), expected, rtol=EXACT, atol=1e-300)
    ax = plot.polar_slice(METAL, wo, log=True, n=n)
    assert ax.get_yscale() == "log"
    np.testing.assert_allclose(_data_lines(ax)[0].get_ydata(), f[:, 0], rtol=EXACT, atol=0)
    # a delta lobe has nothing to show on a log axis: it stays linear, with zeros drawn
    ax = plot.polar_slice(ab.lobes.Conductor(0.0), wo, log=True, n=n)
    assert ax.get_yscale() == "linear" and not _data_lines(ax)[0].get_ydata().any()


# -- hemisphere_image -----------------------------------------------------------------------
@pytest.mark.parametrize("projection", plot.PROJECTIONS)
@pytest.mark.parametrize("lower", [False, True])
def test_hemisphere_image_centre_is_the_normal(projection, lower):
    ax = plot.hemisphere_image(DIELECTRIC, WO, size=33, projection=projection, lower=lower)
    image = ax.images[0].get_array()
    normal = np.array([0.0, 0.0, -1.0 if lower else 1.0])
    np.testing.assert_allclose(image[16, 16], luminance(DIELECTRIC.eval(WO, normal)),
                               rtol=EXACT)
    assert len(ax.figure.axes) == 2  # the image and its colourbar


def test_hemisphere_image_orthographic_pixels():
    size = 24
    ax = plot.hemisphere_image(METAL, WO, quantity="eval_cos", size=size,
                               projection="orthographic", channel=2)
    image = ax.images[0].get_array()
    centres = (np.arange(size) + 0.5) * 2.0 / size - 1.0
    y, x = np.meshgrid(centres, centres, indexing="ij")  # rows are y (origin lower)
    inside = x * x + y * y <= 1.0
    np.testing.assert_array_equal(np.ma.getmaskarray(image), ~inside)
    wi = np.stack([x, y, np.sqrt(np.maximum(1.0 - x * x - y * y, 0.0))], axis=-1)[inside]
    np.testing.assert_allclose(image[inside], METAL.eval(WO, wi)[:, 2] * wi[:, 2], rtol=EXACT)


def test_hemisphere_image_concentric_pixels_and_pdf():
    size = 16
    ax = plot.hemisphere_image(DIELECTRIC, WO, quantity="pdf", size=size, lower=True)
    centres = (np.arange(size) + 0.5) * 2.0 / size - 1.0
    xy = np.stack(np.meshgrid(centres, centres), axis=-1)
    wi, valid = plot.hemisphere_directions(xy, lower=True)
    assert valid.all() and (wi[..., 2] < 0).all()
    np.testing.assert_allclose(ax.images[0].get_array(), DIELECTRIC.pdf(WO, wi), rtol=EXACT)


def _triangle_solid_angle(a, b, c):
    """Solid angle of spherical triangles [VanOosteromStrackee1983]."""
    triple = np.abs(np.sum(a * np.cross(b, c), axis=-1))
    den = 1.0 + np.sum(a * b, -1) + np.sum(b * c, -1) + np.sum(c * a, -1)
    return 2.0 * np.arctan2(triple, den)


def test_concentric_projection_is_equal_area():
    size, sub = 8, 24  # pixels per side, sub-pixels per pixel side
    edges = np.linspace(-1.0, 1.0, size * sub + 1)
    w, _ = plot.hemisphere_directions(np.stack(np.meshgrid(edges, edges), axis=-1))
    np.testing.assert_allclose(np.linalg.norm(w, axis=-1), 1.0, rtol=EXACT)
    a, b, c, d = w[:-1, :-1], w[:-1, 1:], w[1:, 1:], w[1:, :-1]
    cells = _triangle_solid_angle(a, b, c) + _triangle_solid_angle(a, c, d)
    pixels = cells.reshape(size, sub, size, sub).sum(axis=(1, 3))
    assert pixels.sum() == pytest.approx(2.0 * np.pi, rel=1e-4)
    np.testing.assert_allclose(pixels, 2.0 * np.pi / size**2, rtol=2e-3)
    # orientation: x right, y up, the square's border on the horizon
    edge, _ = plot.hemisphere_directions([[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0]])
    s = np.sqrt(0.5)
    np.testing.assert_allclose(edge, [[1, 0, 0], [0, 1, 0], [-s, -s, 0]], atol=EXACT)


# -- chi2_histograms ------------------------------------------------------------------------
def test_chi2_histograms_show_the_result():
    result = chi2_test(ab.lobes.Lambert(0.8), WO, n_samples=20_000, n_theta=8, n_phi=16)
    figure = plot.chi2_histograms(result)
    panels = figure.axes[:2]
    for ax, counts in zip(panels, (result.observed, result.expected), strict=True):
        mesh = ax.collections[0]
        np.testing.assert_array_equal(np.asarray(mesh.get_array()).ravel(), counts.ravel())
        corners = mesh.get_coordinates()  # (n_theta + 1, n_phi + 1, 2) as (phi, theta)
        np.testing.assert_allclose(corners[0, :, 0], np.degrees(result.phi_edges))
        np.testing.assert_allclose(corners[:, 0, 1], np.degrees(result.theta_edges))
    assert panels[0].collections[0].get_clim() == panels[1].collections[0].get_clim()
    assert f"p = {result.p_value:.3g}" in figure.texts[0].get_text()


def test_chi2_histograms_on_given_axes():
    result = chi2_test(ab.lobes.Lambert(0.5), [0.0, 0.0, 1.0], n_samples=5_000, n_theta=6,
                       n_phi=8)
    figure, axes = plt.subplots(1, 2)
    assert plot.chi2_histograms(result, axes) is figure
    np.testing.assert_array_equal(np.asarray(axes[1].collections[0].get_array()).ravel(),
                                  result.expected.ravel())


# -- albedo and furnace ---------------------------------------------------------------------
def _mu_and_wo(n):
    mu = np.arange(1, n + 1) / n
    return mu, np.stack([np.sqrt(1.0 - mu**2), np.zeros(n), mu], axis=-1)


def test_albedo_curves_equal_lobe_albedo():
    lobes = {"metal": METAL, "glass": DIELECTRIC}
    n = 12
    mu, wo = _mu_and_wo(n)
    ax = plot.albedo_curves(lobes, n=n)
    lines = _data_lines(ax)
    assert [line.get_label() for line in lines] == ["metal", "glass"]
    for line, lobe in zip(lines, lobes.values(), strict=True):
        np.testing.assert_allclose(line.get_xdata(), mu, rtol=EXACT)
        np.testing.assert_allclose(line.get_ydata(), luminance(lobe.albedo(wo, method="table")),
                                   rtol=EXACT)
    ax = plot.albedo_curves({"metal": METAL}, n=n, channel=None)
    rgb = METAL.albedo(wo, method="table")
    for c, line in enumerate(_data_lines(ax)):
        np.testing.assert_allclose(line.get_ydata(), rgb[:, c], rtol=EXACT)


def test_albedo_curves_quadrature_of_lambert_is_its_albedo():
    ax = plot.albedo_curves({"Lambert": ab.lobes.Lambert((0.2, 0.5, 0.7))}, method="quadrature",
                            n=3, channel=None)
    for line, albedo in zip(_data_lines(ax), (0.2, 0.5, 0.7), strict=True):
        np.testing.assert_allclose(line.get_ydata(), albedo, rtol=1e-6)


def test_furnace_curves():
    lobes = {"alpha 0.2": ab.lobes.Conductor(0.2), "alpha 0.8": ab.lobes.Conductor(0.8)}
    n = 8
    _, wo = _mu_and_wo(n)
    for difference, offset in ((True, 1.0), (False, 0.0)):
        ax = plot.furnace_curves(lobes, n=n, difference=difference)
        for line, lobe in zip(_data_lines(ax), lobes.values(), strict=True):
            expected = luminance(lobe.albedo(wo, method="table")) - offset
            np.testing.assert_allclose(line.get_ydata(), expected, rtol=EXACT, atol=EXACT)
        (reference,) = [line for line in ax.get_lines() if line.get_label() == "_furnace"]
        assert tuple(reference.get_ydata()) == (1.0 - offset,) * 2


# -- Fresnel --------------------------------------------------------------------------------
def test_fresnel_curves_rgb_and_grey_models():
    n = 33
    mu = np.linspace(0.0, 1.0, n)
    ax = plot.fresnel_curves({"Schlick": lambda m: ab.fresnel.schlick(m, (0.9, 0.5, 0.2)),
                              "glass": ab.fresnel.ExactDielectric(1.5)}, n=n)
    lines = _data_lines(ax)
    assert [line.get_label() for line in lines] == ["Schlick R", "Schlick G", "Schlick B",
                                                    "glass"]
    f0 = np.array([0.9, 0.5, 0.2])
    for c in range(3):  # [Schlick1994] written out
        np.testing.assert_allclose(lines[c].get_ydata(), f0[c] + (1 - f0[c]) * (1 - mu) ** 5,
                                   rtol=EXACT)
    np.testing.assert_allclose(lines[3].get_ydata()[-1], (0.5 / 2.5) ** 2, rtol=EXACT)


def _exact_spectral_fresnel(mu, eta, k):
    """Conductor reflectance (angles, wavelengths) in complex arithmetic [BornWolf1980]."""
    n2 = (eta + 1j * k) ** 2
    c = mu[:, None]
    w = np.sqrt(n2 - (1.0 - c * c))  # n cos theta_t, principal branch
    r_s = (c - w) / (c + w)
    r_p = (n2 * c - w) / (n2 * c + w)
    return 0.5 * (np.abs(r_s) ** 2 + np.abs(r_p) ** 2)


@pytest.mark.parametrize("metal", ["Au", "Cr"])
def test_metal_fresnel(metal):
    n = 29  # cos theta = 1/7 is the 5th point
    mu = np.linspace(0.0, 1.0, n)
    ax = plot.metal_fresnel(metal, n=n)
    lines = {line.get_label(): line.get_ydata() for line in _data_lines(ax)}
    lam, eta, k = spectral.metal_ior(metal)
    fit = spectral.fit_f82_tint(lam, eta, k)
    exact = spectral.reflectance_to_rgb(lam, _exact_spectral_fresnel(mu, eta, k))
    for c, name in enumerate("RGB"):
        line = lines[f"exact (spectral) {name}"]
        np.testing.assert_allclose(line, exact[:, c], rtol=1e-10)
        np.testing.assert_allclose(line[-1], fit.f0_unclipped[c], rtol=1e-10)
        for model in ("Schlick", "F82-tint", "F82 (Hoffman)"):
            np.testing.assert_allclose(lines[f"{model} {name}"][-1], fit.f0[c], rtol=EXACT)
        # Hoffman's F82 passes through the exact value at 1/7, F82-tint through tint x Schlick
        np.testing.assert_allclose(lines[f"F82 (Hoffman) {name}"][4], min(exact[4, c], 1.0),
                                   rtol=1e-10)
        schlick = fit.f0[c] + (1.0 - fit.f0[c]) * (6.0 / 7.0) ** 5
        np.testing.assert_allclose(lines[f"F82-tint {name}"][4], fit.tint[c] * schlick,
                                   rtol=1e-10)


# -- bad input ------------------------------------------------------------------------------
def test_sphere_grid_shows_each_render_with_its_label():
    """Each panel is ``to_srgb8`` of ``render.sphere`` with the same seed; a scene brings its
    title, columns and zoom."""
    lobes = {"grey": ab.lobes.Lambert(0.5), "white": ab.lobes.Lambert(1.0),
             "metal": METAL}
    fig = plot.sphere_grid(lobes, size=8, spp=2, seed=3, env="sun", ncols=2)
    shown = [ax for ax in fig.axes if ax.images]
    assert [ax.get_title() for ax in shown] == list(lobes)
    assert len(fig.axes) == 4  # two rows of two, the empty panel hidden
    for ax, lobe in zip(shown, lobes.values(), strict=True):
        expected = ab.render.to_srgb8(ab.render.sphere(lobe, "sun", size=8, spp=2, seed=3,
                                                       progress=False))
        np.testing.assert_array_equal(ax.images[0].get_array(), expected)
    scene = ab.paper_figures.Scene("two greys", "[Kutz2021, Fig. 0]", "furnace", 2,
                                   {"a": ab.lobes.Lambert(0.5), "b": ab.lobes.Lambert(0.25)},
                                   zoom=1.5)
    fig = plot.sphere_grid(scene, size=8, spp=1)
    assert "[Kutz2021, Fig. 0]" in fig.texts[0].get_text()
    assert fig.axes[0].images[0].get_array().shape == (12, 12, 3)


def test_every_paper_scene_builds():
    for name, make in ab.paper_figures.SCENES.items():
        scene = make()
        key = re.match(r"\[([A-Z][A-Za-z'-]*\d{4}[a-z]?)[,\]]", scene.source)
        assert key and key[1] in _bibliography_keys(), (name, scene.source)
        assert scene.env in ("furnace", "sun", "sky", "studio")
        assert all(isinstance(m, ab.Lobe) for m in scene.materials.values())


@pytest.mark.parametrize("call, name", [
    (lambda: plot.polar_slice(METAL, 0.3, quantity="brdf"), "quantity"),
    (lambda: plot.hemisphere_image(METAL, WO, quantity="radiance"), "quantity"),
    (lambda: plot.hemisphere_image(METAL, WO, projection="stereographic"), "projection"),
    (lambda: plot.hemisphere_directions([0.0, 0.0], projection="mercator"), "projection"),
    (lambda: plot.hemisphere_image(METAL, WO, channel=None), "channel"),
    (lambda: plot.polar_slice(METAL, 0.3, channel="alpha"), "channel"),
    (lambda: plot.polar_slice(METAL, 4.0), "wo_or_theta_o"),
    (lambda: plot.polar_slice(METAL, [0.0, 0.0, 2.0]), "wo"),
    (lambda: plot.polar_slice(METAL, 0.3, n=1), "n"),
    (lambda: plot.polar_slice(METAL, 0.3, ax=plt.subplots()[1]), "ax"),
    (lambda: plot.hemisphere_image(METAL, WO, size=0), "size"),
    (lambda: plot.hemisphere_image(METAL, [WO, WO]), "wo"),
    (lambda: plot.hemisphere_directions([1.5, 0.0]), "xy"),
    (lambda: plot.albedo_curves({"m": METAL}, method="guess"), "method"),
    (lambda: plot.metal_fresnel("Unobtainium"), "name"),
])
def test_bad_input_names_the_parameter(call, name):
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        call()
