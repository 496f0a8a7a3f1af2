"""Valid input never crashes, never gives NaN, Inf or a negative value, and batched paths run
in bounded memory: each test is one class of input that once failed, with its example and a
hypothesis strategy over the class."""

from __future__ import annotations

import tracemalloc
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import adobe_bsdf as ab
from adobe_bsdf.composition import Sum
from adobe_bsdf.lobes import (
    Conductor,
    ConductorMS,
    Dielectric,
    DielectricMS,
    Dispersive,
    HazyDielectric,
    HazyGloss,
    Sheen,
)
from adobe_bsdf.materials import AdobeStandardMaterial

ONE_ULP = np.nextafter(1.0, 2.0)


def _lobes():
    """One of each lobe family, GGX and Beckmann, and loaded materials."""
    return {
        "Conductor": Conductor(0.3), "Conductor beckmann": Conductor(0.3, model="beckmann"),
        "ConductorMS": ConductorMS(1.0), "ConductorMS aniso": ConductorMS(0.8, 0.05),
        "Dielectric": Dielectric(1.5, 0.3), "Dielectric beckmann": Dielectric(
            1.5, 0.3, model="beckmann"), "DielectricMS": DielectricMS(1 / 1.4, 0.4),
        "Dispersive": Dispersive(1.5, 1.0, 0.2), "Sheen": Sheen(1.0, 0.3),
        "HazyGloss": HazyGloss(0.04, 0.5, 4.0, 0.05),
        "HazyDielectric": HazyDielectric(0.04, 0.1, 2.0, 0.05),
        "ASM": AdobeStandardMaterial(),
        "ASM loaded": AdobeStandardMaterial(base_color=1.0, roughness=0.2, metallic=0.3,
                                            translucency=0.3, anisotropy_level=1.0,
                                            coat_opacity=1.0, coat_color=(0.9, 0.8, 0.7),
                                            sheen_opacity=0.5, dispersion=0.5),
        "ASM r=0 a=1": AdobeStandardMaterial(roughness=0.0, anisotropy_level=1.0,
                                             metallic=1.0, base_color=1.0),
    }


LOBES = _lobes()


def _finite_non_negative(lobe, wo, wi, u):
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        f, p = lobe.eval(wo, wi), lobe.pdf(wo, wi)
        s = lobe.sample(wo, u)
    for name, value in (("eval", f), ("pdf", p), ("weight", s.weight), ("sample pdf", s.pdf)):
        assert np.all(np.isfinite(value)), (name, value)
        assert np.all(value >= 0.0), (name, value)


# -- a direction an ulp off the unit sphere -------------------------------------------------
@pytest.mark.parametrize("name", ["ConductorMS", "DielectricMS", "ASM", "ASM loaded", "Sheen"])
def test_a_cosine_one_ulp_above_one_reaches_no_table_out_of_range(name):
    lobe = LOBES[name]
    up = np.array([0.0, 0.0, ONE_ULP])
    _finite_non_negative(lobe, up, up, np.zeros(3))
    lobe.albedo(up, method="table")
    frame = ab.Frame((1.0, 1.0, 1.0))
    _finite_non_negative(lobe, frame.to_local(frame.n), np.array([0.6, 0.0, 0.8]),
                         np.array([0.5, 0.5, 0.5]))


def test_own_samplers_at_u_zero():
    """The examples: the library's own samplers at u = 0 produced z > 1 by rounding."""
    wo = np.array([0.6, 0.0, 0.8])
    for lobe in (ConductorMS(1.0), AdobeStandardMaterial(base_color=1.0, roughness=1.0)):
        s = lobe.sample(wo, np.zeros(3))
        assert np.all(np.isfinite(s.weight)) and s.pdf > 0.0


@settings(max_examples=60, deadline=None)
@given(st.sampled_from(sorted(LOBES)),
       st.lists(st.floats(-9e-7, 9e-7), min_size=2, max_size=2),
       st.floats(0.0, np.pi / 2), st.floats(0.0, 2 * np.pi))
def test_directions_within_the_unit_tolerance(name, scale, theta, phi):
    w = np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])
    wo, wi = w * (1.0 + scale[0]), w[[1, 0, 2]] * (1.0 + scale[1])
    _finite_non_negative(LOBES[name], wo, wi, np.array([0.3, 0.6, 0.9]))


# -- normal incidence, grazing and subnormal cosines ---------------------------------------
def test_beckmann_transmission_at_normal_incidence_is_finite():
    """Beckmann's S(w) took the sign of wz at normal incidence: eval was inf at (0, 0, -1)."""
    for lobe in (Dielectric(1.5, 0.3, model="beckmann"),
                 HazyDielectric(0.04, 0.1, 2.0, 0.05, model="beckmann")):
        f = lobe.eval((0.0, 0.0, 1.0), (0.0, 0.0, -1.0))
        near = lobe.eval((0.0, 0.0, 1.0), (1e-6, 0.0, -np.sqrt(1.0 - 1e-12)))
        assert np.all(np.isfinite(f)) and np.all(f > 0.0)
        np.testing.assert_allclose(f, near, rtol=1e-6)  # continuous there


@pytest.mark.parametrize("name", ["Conductor", "Conductor beckmann", "Dielectric",
                                  "Dielectric beckmann", "HazyGloss", "ASM", "ASM loaded"])
@pytest.mark.parametrize("z", [1e-85, 1e-150, 1e-200, 1e-300])
def test_grazing_pairs_of_opposite_azimuth(name, z):
    """h = wo + wi is vertical and tiny: D(h) once underflowed to 0 / 0."""
    s = np.sqrt(1.0 - z * z)
    _finite_non_negative(LOBES[name], np.array([s, 0.0, z]), np.array([-s, 0.0, z]),
                         np.array([0.5, 0.5, 0.5]))


def test_grazing_opposite_limit_is_continuous():
    """D depends on the direction of h only: at 1e-300 the value follows the 1 / cos law of
    the same pair at 1e-20 (f ~ D / (4 z S) for z -> 0)."""
    lobe = Conductor(0.3)
    f = [lobe.eval((1.0, 0.0, z), (-1.0, 0.0, z))[0] * z for z in (1e-20, 1e-300)]
    np.testing.assert_allclose(f[0], f[1], rtol=1e-12)


# -- tables: sums, the tangent plane ----------------------------------------------------------
def test_table_albedo_of_sums_of_dielectrics():
    """The dielectric's error estimate was an object array of None that ``Sum`` multiplied."""
    wo = np.array([0.0, 0.0, 1.0])
    pair = Sum(Dielectric(1.5, 0.3), Dielectric(1.5, 0.5), weights=[0.5, 0.5])
    np.testing.assert_allclose(pair.albedo(wo, method="table"),
                               0.5 * (Dielectric(1.5, 0.3).albedo(wo, method="table")
                                      + Dielectric(1.5, 0.5).albedo(wo, method="table")),
                               rtol=1e-15)
    hazy = HazyDielectric(0.04, 0.1, 2.0, 0.05).albedo(wo, method="table")
    quadrature = HazyDielectric(0.04, 0.1, 2.0, 0.05).albedo(wo, tol=1e-6)
    np.testing.assert_allclose(hazy, quadrature, atol=2e-3)


@pytest.mark.parametrize("lobe", [Dielectric(1.5, 0.3), Dielectric(1 / 1.5, 0.3),
                                  DielectricMS(1.5, 0.3), ConductorMS(0.5), Conductor(0.5)],
                         ids=repr)
def test_table_albedo_in_the_tangent_plane_is_zero(lobe):
    """At cos = 0 exactly nothing is scattered (the quadrature and MC say so too)."""
    wo = np.array([1.0, 0.0, 0.0])
    np.testing.assert_array_equal(lobe.albedo(wo, method="table"), 0.0)
    np.testing.assert_array_equal(lobe.albedo(wo, method="mc", n_samples=100), 0.0)


# -- layers never weigh the base negatively --------------------------------------------------
@settings(max_examples=200, deadline=None)
@given(st.floats(1e-300, 1e-3), st.floats(0.0, 2 * np.pi), st.floats(0.0, 1.0),
       st.floats(0.0, 1.0))
def test_coated_material_is_never_negative(z, phi, roughness, coat_roughness):
    """The coat's top albedo can exceed 1 by rounding at grazing angles; the layer weight
    1 - E_top then went negative (-1.3e-16)."""
    lobe = AdobeStandardMaterial(coat_opacity=1.0, roughness=roughness,
                                 coat_roughness=coat_roughness)
    s = np.sqrt(1.0 - z * z)
    wo = np.array([s * np.cos(phi), s * np.sin(phi), z])
    for wi in (np.array([0.0, 0.0, 1.0]), np.array([0.6, 0.0, 0.8])):
        _finite_non_negative(lobe, wo, wi, np.array([0.5, 0.5, 0.5]))


def test_values_beyond_the_float64_range_saturate():
    """f of a grazing mirror pair, ~1 / (4 pi alpha^3 cos), exceeds 1.8e308 for alpha ~ 1e-4
    and cos ~ 1e-300: it rounds to the largest finite float64, never inf (nor NaN where D or
    a weight is 0)."""
    z = 1e-300
    for lobe in (Conductor(2.4e-4), Dielectric(1.5, 2.4e-4), Sheen(1.0, 1e-3)):
        f = lobe.eval((1.0, 0.0, z), (-1.0, 0.0, z))
        assert np.all(np.isfinite(f)) and np.all(f > 0.0), (lobe, f)
    coated = AdobeStandardMaterial(roughness=0.015625, coat_opacity=1.0)
    _finite_non_negative(coated, np.array([1.0, 0.0, z]), np.array([-1.0, 0.0, z]),
                         np.array([0.5, 0.5, 0.5]))
    assert np.all(Conductor(2.4e-4).eval((1.0, 0.0, z), (-1.0, 0.0, z))
                  == ab.microfacet.FLOAT_MAX)
    for z in (1e-310, 5e-324):  # subnormal cosines
        for name in ("Conductor", "Dielectric", "Sheen", "ASM loaded"):
            _finite_non_negative(LOBES[name], np.array([1.0, 0.0, z]), np.array([1.0, 0.0, z]),
                                 np.array([0.5, 0.5, 0.5]))
    s = Dielectric(1.0 + 1e-15, 0.3).sample((1.0, 0.0, 5e-324), (0.5, 0.5, 0.5))
    assert np.all(np.isfinite(s.weight)) and np.isfinite(s.pdf)


def test_quadrature_albedo_near_index_one_at_grazing():
    """The cubature met f = inf at nodes next to a grazing wo and returned NaN."""
    for lobe in (Dielectric(1.0000001, 0.3),):
        value = lobe.albedo((1.0, 0.0, 1e-300), tol=1e-5)
        mc, error = lobe.albedo((1.0, 0.0, 1e-300), method="mc", n_samples=20_000,
                                return_error=True)
        assert np.all(np.isfinite(value)) and np.all(value <= 1.0 + 1e-5)
        np.testing.assert_allclose(value, mc, atol=5 * error.max() + 1e-5)


def test_coat_example():
    lobe = AdobeStandardMaterial(coat_opacity=1.0)
    assert np.all(lobe.eval((0.0, 1.0, 1e-20), (0.0, 0.0, 1.0)) >= 0.0)
    assert lobe.pdf((0.0, 1.0, 1e-20), (0.0, 0.0, 1.0)) >= 0.0


# -- a sample agrees with its pdf, uniforms at the ends of [0, 1) ---------------------------
LAST = 1.0 - 2.0**-53


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(["Dielectric", "Dielectric beckmann", "DielectricMS", "Conductor",
                        "Dispersive", "HazyDielectric"]),
       st.floats(0.05, 1.0), st.floats(0.0, 2 * np.pi),
       st.tuples(*[st.sampled_from([0.0, LAST, 0.5, 1e-300, 0.25])] * 3),
       st.booleans())
def test_sample_agrees_with_its_pdf(name, z, phi, u, below):
    """A refracted sample through a facet with mz ~ 1e-16 had pdf 2.41 where pdf(wo, wi),
    recomputed, was 0: the recomputed half vector rounded into the tangent plane."""
    lobe = LOBES[name]
    s = np.sqrt(1.0 - z * z)
    wo = np.array([s * np.cos(phi), s * np.sin(phi), -z if below else z])
    sample = lobe.sample(wo, np.array(u))
    if sample.pdf == 0.0 or sample.flags & ab.Flags.DELTA:
        return
    np.testing.assert_allclose(lobe.pdf(wo, sample.wi), sample.pdf, rtol=1e-6)


def test_sample_pdf_example():
    wo = np.array([0.8273456687450108, 0.25592800630034734, 0.5])
    lobe = Dielectric(1.5, 1.0)
    s = lobe.sample(wo, np.array([0.5, 0.0, LAST]))
    np.testing.assert_allclose(lobe.pdf(wo, s.wi), s.pdf, rtol=1e-12)
    assert lobe.eval(wo, s.wi)[0] > 0.0


# -- bounded memory ---------------------------------------------------------------------------
def test_monte_carlo_albedo_of_1000_directions_in_bounded_memory():
    """All samples of all directions were allocated at once (killed at 23 GB for an ASM);
    they are drawn in blocks of the execution options' chunk size."""
    rng = np.random.default_rng(1)
    wo = rng.normal(size=(1000, 3))
    wo[:, 2] = np.abs(wo[:, 2])
    wo /= np.linalg.norm(wo, axis=1, keepdims=True)
    lobe = Conductor(0.3)
    tracemalloc.start()
    try:
        value, error = lobe.albedo(wo, method="mc", n_samples=20_000, return_error=True)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 1e9, peak
    assert peak < 20_000 * 1000 * 3 * 8  # less than the uniforms alone would take
    np.testing.assert_allclose(value[:3], lobe.albedo(wo[:3], tol=1e-6), atol=5 * error.max())


def test_monte_carlo_blocks_are_one_draw():
    """Blocks draw the same uniforms in the same order as one draw: mean and error agree to
    rounding whatever the block size."""
    lobe, wo = Conductor(0.3), np.tile([0.6, 0.0, 0.8], (20, 1))
    with ab.config.options(chunk_size=10**9):
        whole = lobe.albedo(wo, method="mc", n_samples=2000, return_error=True)
    with ab.config.options(chunk_size=97):
        blocks = lobe.albedo(wo, method="mc", n_samples=2000, return_error=True)
    for a, b in zip(whole, blocks, strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-12)
