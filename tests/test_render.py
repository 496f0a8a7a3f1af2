"""``adobe_bsdf.render``: the sphere renderer against closed forms and the energy tables."""

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf import render
from adobe_bsdf.bsdf import BSDFSample, Flags
from adobe_bsdf.validation.chi2 import chi2_test
from tests.tolerances import CHI2_ALPHA, FURNACE_TABLE

SIZE = 40


def _rings(image, n_rings=5):
    """(mu, mask) of the sphere's pixels in rings of equal width in radius."""
    c = (np.arange(SIZE) + 0.5) / SIZE * 2.0 - 1.0
    x, y = np.meshgrid(c, -c)
    r = np.sqrt(x * x + y * y)
    mu = np.sqrt(np.clip(1.0 - r * r, 0.0, 1.0))
    edges = np.linspace(0.0, 1.0, n_rings + 1)
    return mu, [(r >= lo) & (r < hi) for lo, hi in zip(edges[:-1], edges[1:], strict=True)]


@pytest.mark.parametrize("roughness", [0.1, 0.5, 1.0])
def test_white_asm_sphere_vanishes_in_the_furnace(roughness):
    """Acceptance 2: a white ASM dielectric renders as the background, 1, within Monte-Carlo
    noise (3 standard errors per ring) plus the tables' interpolation error."""
    material = ab.materials.AdobeStandardMaterial(base_color=1.0, roughness=roughness)
    image = render.sphere(material, "furnace", size=SIZE, spp=32, seed=1, progress=False)
    _, rings = _rings(image)
    for ring in rings:
        values = image[ring][:, 1]
        error = values.std(ddof=1) / np.sqrt(values.size)
        assert abs(values.mean() - 1.0) <= 3.0 * error + FURNACE_TABLE, (roughness, values.mean())
    np.testing.assert_array_equal(image[0, 0], 1.0)  # background


def test_ggx_metal_without_multiple_scattering_darkens_as_its_albedo():
    """Acceptance 2: a rough GGX mirror (F = 1, no Kulla–Conty) renders at its single-
    scattering albedo E(mu) of the tables, visibly below the background."""
    image = render.sphere(ab.lobes.Conductor(1.0), size=SIZE, spp=32, seed=2, progress=False)
    mu, rings = _rings(image)
    wo = np.stack([np.sqrt(1 - mu**2), np.zeros_like(mu), mu], axis=-1)
    E = ab.lobes.Conductor(1.0).albedo(wo.reshape(-1, 3), method="table").reshape(image.shape)
    for ring in rings:
        d = (image - E)[ring][:, 0]
        assert abs(d.mean()) <= 3.0 * d.std(ddof=1) / np.sqrt(d.size) + 1e-4
    assert image[rings[0]].mean() < 0.4  # E(1, alpha = 1) = 0.307


def test_sun_on_a_lambert_sphere_is_the_cosine_law():
    """Without ambient light only the sun is seen, sampled exactly: rho / pi E max(n.l, 0)."""
    light = ((0.3, 0.8, 0.5), 2.0, 0.0)
    image = render.sphere(ab.lobes.Lambert((0.8, 0.5, 0.2)), "sun", size=SIZE, spp=2,
                          light=light, progress=False)
    c = (np.arange(SIZE) + 0.5) / SIZE * 2.0 - 1.0
    x, y = np.meshgrid(c, -c)
    hit = x * x + y * y < 1.0
    n = np.stack([x[hit], y[hit], np.sqrt(1.0 - x[hit] ** 2 - y[hit] ** 2)], axis=-1)
    l_dir = np.array(light[0]) / np.linalg.norm(light[0])
    expected = np.array([0.8, 0.5, 0.2]) / np.pi * 2.0 * np.maximum(n @ l_dir, 0.0)[:, None]
    np.testing.assert_allclose(image[hit], expected, rtol=1e-12, atol=1e-15)


class _EnvironmentAsLobe:
    """An environment's sampler seen as a lobe (what ``chi2_test`` calls)."""

    def __init__(self, env):
        self.env = env

    def sample(self, wo, u):
        w, pdf = self.env.sample(u)
        flags = np.full(pdf.shape, int(Flags.REFLECTION | Flags.GLOSSY))
        return BSDFSample(w, np.ones(w.shape), pdf, flags)

    def pdf(self, wo, wi):
        return self.env.pdf(wi)


ENVIRONMENTS = [render.Uniform(1.0), render.EquirectMap(render.sky(16)),
                render.EquirectMap(render.studio(16))]


@pytest.mark.parametrize("env", ENVIRONMENTS)
def test_environment_sampling_matches_its_pdf(env):
    result = chi2_test(_EnvironmentAsLobe(env), np.array([0.0, 0.0, 1.0]), n_samples=300_000,
                       n_theta=32, n_phi=64, alpha=CHI2_ALPHA, n_tests=len(ENVIRONMENTS))
    assert result.passed, str(result)


def test_studio_has_its_strips():
    image = render.studio(32, bars=4, radiance=1.5)
    assert image.shape == (32, 64, 3)
    lit = image[16, :, 0] == 1.5  # along the horizon
    starts = lit & ~np.roll(lit, 1)
    assert starts.sum() == 4  # four strips (runs of lit pixels, around the circle)
    assert abs(lit.mean() - 0.2) < 1.0 / 16  # each 0.2 of its period, to a pixel
    np.testing.assert_array_equal(image[0], 0.3 + 0.2 * np.cos(np.pi / 64))  # above the strips


def test_equirect_lookup_and_background():
    image = render.sky(16)
    env = render.EquirectMap(image)
    up = env.radiance(np.array([0.0, 1.0, 0.0]))
    np.testing.assert_array_equal(up, image[0, 0])
    img = render.sphere(ab.lobes.Lambert(0.5), image, size=8, spp=1, progress=False)
    np.testing.assert_array_equal(img[0, 0], env.radiance(np.array([0.0, 0.0, -1.0])))


def test_seeded_and_finite_for_every_kind_of_lobe():
    material = ab.materials.AdobeStandardMaterial(
        translucency=0.7, roughness=0.2, dispersion=1.0, coat_opacity=0.5, sheen_opacity=0.5,
        anisotropy_level=0.5, metallic=0.2)
    a = render.sphere(material, "sky", size=12, spp=2, seed=5, progress=False)
    b = render.sphere(material, "sky", size=12, spp=2, seed=5, progress=False)
    np.testing.assert_array_equal(a, b)
    assert np.all(np.isfinite(a)) and np.all(a >= 0.0)
    smooth = render.sphere(ab.lobes.Dielectric(1.5, 0.0), "sky", size=12, spp=2,
                           progress=False)
    assert np.all(np.isfinite(smooth))


def test_srgb_encoding_and_png(tmp_path):
    values = np.array([0.0, 0.0031308, 0.5, 1.0, 2.0])
    expected = [0, 10, 188, 255, 255]  # 12.92 x, 1.055 x^(1/2.4) - 0.055, x 255
    np.testing.assert_array_equal(render.to_srgb8(np.repeat(values[:, None], 3, 1))[:, 0],
                                  expected)
    image = np.random.default_rng(0).random((5, 7, 3))
    path = tmp_path / "a.png"
    render.write_png(path, image)
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    import zlib

    raw = zlib.decompress(data[data.index(b"IDAT") + 4:-16])  # IHDR, one IDAT, IEND
    rows = np.frombuffer(raw, np.uint8).reshape(5, 1 + 7 * 3)
    assert np.all(rows[:, 0] == 0)  # filter type 0 on every row
    np.testing.assert_array_equal(rows[:, 1:].reshape(5, 7, 3), render.to_srgb8(image))


def test_bad_input_names_the_parameter():
    with pytest.raises(ValueError, match="env"):
        render.sphere(ab.lobes.Lambert(), "garage")
    with pytest.raises(ValueError, match="bsdf"):
        render.sphere("lambert")
    with pytest.raises(ValueError, match="spp"):
        render.sphere(ab.lobes.Lambert(), spp=0)
    with pytest.raises(ValueError, match="image"):
        render.EquirectMap(np.ones((4, 4)))
