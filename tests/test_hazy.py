"""Haze mapping of hazy gloss [Barla2018]: the paper's claims as tests."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import adobe_bsdf as ab
from adobe_bsdf import hazy
from tests.tolerances import EXACT

N = np.array([0.0, 0.0, 1.0])


def _composite_peak(m: hazy.HazeMapping):
    """f_r(n, n) of eq. 1 built from two GGX Conductor lobes sharing the mapped Fresnel."""
    fresnel = ab.fresnel.ExactConductor(m.eta, m.kappa)
    narrow = ab.lobes.Conductor(*m.alpha_n, fresnel=fresnel).eval(N, N)
    wide = ab.lobes.Conductor(*m.alpha_w, fresnel=fresnel).eval(N, N)
    return (1.0 - m.beta) * narrow + m.beta * wide


@pytest.mark.parametrize("r_c, g", [(0.04, 0.0), ([0.9, 0.6, 0.3], 0.4), (0.5, 1.0)])
@pytest.mark.parametrize("alpha", [(0.01, 0.01), (0.05, 0.2)])
@pytest.mark.parametrize("smooth_weight", [None, 4.0])
def test_core_peak_is_independent_of_haziness(r_c, g, alpha, smooth_weight):
    """Fig. 2 e-f / Fig. 8: the composite's value in the mirror direction at normal
    incidence is r_c f_n(n, n) for every haziness beta_h (the halo vanishes there)."""
    core = np.asarray(r_c) * ab.lobes.Conductor(*alpha).eval(N, N)  # F = 1: f_n(n, n)
    for beta_h in (0.0, 0.1, 0.5, 0.9):
        m = hazy.haze_mapping(r_c, beta_h, 5.0, *alpha, edge_tint=g,
                              smooth_weight=smooth_weight)
        np.testing.assert_allclose(_composite_peak(m), core, rtol=1e-9)


_RC = st.floats(0.0, 1.0)
_P = st.floats(1e-6, 1.0)
_BH = st.floats(0.0, 1.0)


@given(r_c=_RC, p=_P, beta_h=_BH, w=st.one_of(st.none(), st.floats(0.05, 1e3)))
def test_haze_intensity_within_positivity_and_energy(r_c, p, beta_h, w):
    """Eq. 6: 0 <= k_h <= r_c / p and k_h <= (1 - r_c) / (1 - p), for eq. 7 and eq. 15."""
    k_h = (hazy.haze_intensity(r_c, p, beta_h) if w is None
           else hazy.haze_intensity_smooth(r_c, p, beta_h, w))
    slack = 1e-12
    assert 0.0 <= k_h <= r_c / p + slack
    if p < 1.0:
        assert k_h <= (1.0 - r_c) / (1.0 - p) + slack


@given(p=st.floats(0.01, 0.99), beta_h=st.floats(0.05, 1.0), w=st.floats(0.1, 50.0))
def test_bezier_is_c1_at_the_kink_and_matches_eq7_at_the_ends(p, beta_h, w):
    h = 1e-6

    def k(r):
        return hazy.haze_intensity_smooth(r, p, beta_h, w)

    left, right = (k(p) - k(p - h)) / h, (k(p + h) - k(p)) / h
    assert abs(left - right) <= 1e-4 * max(1.0, abs(left)) / min(p, 1 - p)
    for r in (0.0, 1.0):
        assert k(r) == pytest.approx(hazy.haze_intensity(r, p, beta_h), abs=1e-15)


def test_bezier_root_is_on_the_curve_and_tends_to_eq7():
    """The computed k_h is the second coordinate of C(u) whose first is r_c (the inversion,
    independently), equals the paper's eq. 12 root away from b = 1, and tends to eq. 7 as
    w -> inf."""
    r = np.linspace(0.0, 1.0, 201)
    p, beta_h = 0.3, 0.8
    for w in (0.5, 1.0, 2.0, 8.0):
        b = 2.0 * (r * (1.0 - w) + w * p)
        u = ab.haze._bezier_parameter(r, p, w)
        den = (1 - u) ** 2 + 2 * (1 - u) * u * w + u * u
        np.testing.assert_allclose((2 * (1 - u) * u * w * p + u * u) / den, r, atol=1e-14)
        np.testing.assert_allclose(hazy.haze_intensity_smooth(r, p, beta_h, w),
                                   2 * (1 - u) * u * w * beta_h / den, rtol=EXACT, atol=1e-15)
        far = np.abs(b - 1.0) > 1e-3
        with np.errstate(divide="ignore", invalid="ignore"):  # 0 / 0 at b = 1 (not compared)
            paper = (b - np.sqrt(b * b - 4 * (b - 1) * r)) / (2 * (b - 1))
        np.testing.assert_allclose(u[far], paper[far], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(hazy.haze_intensity_smooth(r, p, beta_h, 1e9),
                               hazy.haze_intensity(r, p, beta_h), atol=1e-6)


def test_bezier_near_b_equal_one_matches_the_papers_taylor_window():
    """Near r_c* = (1/2 - w p) / (1 - w) (b = 1) the paper switches to a Taylor expansion of
    u; the closed form used here agrees with it to second order."""
    p, w, beta_h = 0.3, 2.0, 1.0
    r_star = (0.5 - w * p) / (1 - w)
    for d in (1e-4, 1e-5, -1e-5):
        r = r_star + d
        u_taylor = (2 * w * p - 1 - (4 * w * w * p * p - 4 * w * w * p + 1) * d) / (2 * (w - 1))
        u = ab.haze._bezier_parameter(r, p, w)
        assert abs(u - u_taylor) <= 10 * d * d
    assert np.isfinite(hazy.haze_intensity_smooth(r_star, p, beta_h, w))


def test_wide_roughness_eq8():
    np.testing.assert_allclose(hazy.wide_roughness(0.02, 0.02, 7.0), (0.16, 0.16), rtol=EXACT)
    ax, ay, lx, ly = 0.04, 0.01, 3.0, 0.5
    np.testing.assert_allclose(hazy.wide_roughness(ax, ay, lx, ly),
                               (ax + lx * 0.02, ay + ly * 0.02), rtol=EXACT)


@pytest.mark.parametrize("alpha", [0.01, 1e-100, 1e-300, 2.2e-311, 5e-324])
def test_peak_ratio_is_scale_free_down_to_subnormal_alphas(alpha):
    """Eq. 8 scales with alpha_n, so p = 1 / (1 + lambda_h)^2 (isotropic) at every scale; a
    hazy lobe with such an alpha is finite (hypothesis-style extremes, RuntimeWarnings are
    errors)."""
    alpha_w = hazy.wide_roughness(alpha, alpha, 7.0)
    np.testing.assert_allclose(hazy.peak_ratio((alpha, alpha), alpha_w), 1.0 / 64.0,
                               rtol=EXACT)
    lobe = hazy.HazyGloss(0.5, 0.5, 7.0, alpha)
    wo = np.array([0.6, 0.0, 0.8])
    s = lobe.sample(np.broadcast_to(wo, (64, 3)), np.random.default_rng(0).random((64, 3)))
    assert np.all(np.isfinite(s.weight)) and np.all(np.isfinite(s.pdf))


@pytest.mark.parametrize("alpha_n, alpha_w", [((0.01, 0.01), (0.08, 0.08)),
                                              ((0.05, 0.2), (0.3, 0.25))])
@pytest.mark.parametrize("model", hazy.PEAK_MODELS)
def test_peak_ratio_is_the_ratio_of_the_lobes_peaks(alpha_n, alpha_w, model):
    """Table 2 against the ratio of the Conductor lobes' actual values at (n, n)."""
    def peak(alpha):
        return ab.lobes.Conductor(*alpha, model=model).eval(N, N)

    np.testing.assert_allclose(peak(alpha_w) / peak(alpha_n),
                               hazy.peak_ratio(alpha_n, alpha_w, model), rtol=EXACT)


@pytest.mark.parametrize("model", hazy.PEAK_MODELS)
@pytest.mark.parametrize("compound_masking", [False, True])
def test_hazy_lobes_keep_the_core_peak(model, compound_masking):
    """The HazyGloss lobe itself (either model, either masking) is r_c f_n at (n, n) for every
    haziness; HazyDielectric's reflection likewise, with F = r_c of its core index."""
    r_c, alpha = [0.9, 0.6, 0.3], (0.05, 0.02)
    core = np.asarray(r_c) * ab.lobes.Conductor(*alpha, model=model).eval(N, N)
    for beta_h in (0.0, 0.3, 0.8):
        lobe = hazy.HazyGloss(r_c, beta_h, 4.0, *alpha, edge_tint=0.2, model=model,
                              compound_masking=compound_masking)
        np.testing.assert_allclose(lobe.eval(N, N), core, rtol=1e-9)
        glass = hazy.HazyDielectric(0.04, beta_h, 4.0, *alpha, model=model,
                                    compound_masking=compound_masking)
        np.testing.assert_allclose(glass.eval(N, N), core[0] / 0.9 * 0.04, rtol=1e-9)


def test_dielectric_mapping_and_extremes():
    m = hazy.haze_mapping(0.04, 0.05, 7.0, 0.01)  # edge tint 0: a dielectric
    assert np.all(m.kappa == 0.0)
    r = m.reflectivity
    np.testing.assert_allclose(m.eta, (1 + np.sqrt(r)) / (1 - np.sqrt(r)), rtol=EXACT)
    for r_c in (0.0, 0.3, 1.0):
        for beta_h in (0.0, 1.0):
            for extent in (0.0, 1e3):
                for alpha in (1e-6, 1.0):
                    m = hazy.haze_mapping(r_c, beta_h, extent, alpha, edge_tint=0.5)
                    assert 0.0 <= m.beta <= 1.0 and np.all(m.reflectivity <= 1.0)
                    finite = m.reflectivity < 1.0
                    assert np.all(np.isfinite(m.eta[finite]) & np.isfinite(m.kappa[finite]))
                    assert np.all(np.isinf(m.eta[~finite]))  # r = 1: F = 1, no finite index


@pytest.mark.parametrize("kwargs, name", [
    ({"haziness": 1.5}, "^haziness = 1.5"), ({"haze_extent": -1.0}, "^haze_extent = -1"),
    ({"core_reflectivity": 1.2}, "^core_reflectivity = 1.2"), ({"model": "phong"}, "^model"),
    ({"alpha_x": 0.0}, "^alpha_x = 0"), ({"smooth_weight": 0.0}, "^smooth_weight = 0")])
def test_bad_input(kwargs, name):
    args = {"core_reflectivity": 0.5, "haziness": 0.5, "haze_extent": 5.0, "alpha_x": 0.05,
            **kwargs}
    with pytest.raises(ValueError, match=name):
        hazy.haze_mapping(**args)


# --- the HazyGloss lobe ----------------------------------------------------------------------
from hypothesis import settings  # noqa: E402

from adobe_bsdf.validation import checks  # noqa: E402
from adobe_bsdf.validation.chi2 import chi2_test  # noqa: E402
from tests.tolerances import CHI2_ALPHA, RECIPROCITY, SUBNORMAL  # noqa: E402

HAZY = {
    "isotropic": lambda: hazy.HazyGloss([0.9, 0.6, 0.3], 0.5, 5.0, 0.05, edge_tint=0.3),
    "anisotropic-halo": lambda: hazy.HazyGloss(0.3, 0.7, 6.0, 0.08, haze_extent_y=1.0),
    "anisotropic-core": lambda: hazy.HazyGloss(0.04, 0.1, 3.0, 0.15, 0.05, smooth_weight=4.0),
    "beckmann": lambda: hazy.HazyGloss(0.5, 0.6, 4.0, 0.06, 0.1, edge_tint=0.8,
                                       model="beckmann"),
    "compound": lambda: hazy.HazyGloss([0.9, 0.6, 0.3], 0.5, 5.0, 0.05, edge_tint=0.3,
                                       compound_masking=True),
    "compound-beckmann-aniso": lambda: hazy.HazyGloss(
        0.3, 0.7, 6.0, 0.08, haze_extent_y=1.0, model="beckmann", compound_masking=True),
}
GLASS = {
    "glass": lambda: hazy.HazyDielectric(0.04, 0.3, 4.0, 0.05),
    "glass-compound-aniso": lambda: hazy.HazyDielectric(0.04, 0.5, 5.0, 0.1, 0.04,
                                                        compound_masking=True),
    "glass-beckmann": lambda: hazy.HazyDielectric(0.1, 0.8, 3.0, 0.1, model="beckmann"),
}
CHI2_CASES = ([(k, c) for k in HAZY for c in (1.0, 0.5, 0.1)]
              + [(k, c) for k in GLASS for c in (0.9, 0.3, -0.6)])
LOBES = {**HAZY, **GLASS}


def _wo(cos_theta, phi=0.7):
    s = np.sqrt(1.0 - cos_theta**2)
    return np.array([s * np.cos(phi), s * np.sin(phi), cos_theta])


@pytest.mark.parametrize(("kind", "cos_theta"), CHI2_CASES)
def test_hazy_gloss_chi2(kind, cos_theta):
    """sample against pdf (p > 0.01 after Šidák): isotropic and anisotropic halos, GGX and
    Beckmann, separate and compound masking, and the BTDF from both sides."""
    from tests.test_lobes_chi2 import grid

    lobe, wo = LOBES[kind](), _wo(cos_theta)
    alpha_n = (max(np.max(a) for a in lobe.mapping.alpha_n),)
    focus = (grid("Dielectric", alpha_n, float(lobe.eta), wo) if kind in GLASS
             else grid("Conductor", alpha_n, None, wo))  # the narrow core's peak
    result = chi2_test(lobe, wo, n_samples=500_000, seed=CHI2_CASES.index((kind, cos_theta)),
                       alpha=CHI2_ALPHA, n_tests=len(CHI2_CASES), **focus)
    assert result.passed, str(result)


@pytest.mark.parametrize("kind", LOBES)
def test_hazy_gloss_reciprocity_and_finiteness(kind):
    """Reciprocity to 1e-12 (generalized across the glass interface: ``eta``)."""
    rng = np.random.default_rng(1)
    wo, wi = (ab.frame.normalize(rng.normal(size=(2000, 3))) for _ in range(2))
    lobe = LOBES[kind]()
    result = checks.reciprocity_error(lobe, wo, wi, rtol=RECIPROCITY, atol=SUBNORMAL)
    assert result.passed, result
    s = lobe.sample(wo, rng.random((2000, 3)))
    for value in (lobe.eval(wo, wi), lobe.pdf(wo, wi), s.weight, s.pdf):
        assert np.all(np.isfinite(value)) and np.all(value >= 0.0)


@settings(max_examples=12, deadline=None)
@given(r_c=st.floats(0.0, 1.0), beta_h=st.floats(0.0, 1.0), extent=st.floats(0.0, 20.0),
       alpha=st.floats(0.1, 1.0), g=st.floats(0.0, 1.0), mu=st.floats(0.05, 1.0),
       model=st.sampled_from(hazy.PEAK_MODELS), compound=st.booleans())
def test_hazy_gloss_albedo_at_most_one(r_c, beta_h, extent, alpha, g, mu, model, compound):
    """Energy: the composite never reflects more than it receives (quadrature, tol 1e-7);
    with separate masking its albedo is the weighted sum of its two lobes' (eq. 1 is
    linear)."""
    lobe = hazy.HazyGloss(r_c, beta_h, extent, alpha, edge_tint=g, model=model,
                          compound_masking=compound)
    wo = _wo(mu)
    albedo = lobe.albedo(wo, tol=1e-7)
    assert np.all(albedo <= 1.0 + 1e-6)
    if compound:
        return
    parts = sum(w * c.albedo(wo, tol=1e-7) for c, w in zip(lobe.components, lobe.weights,
                                                          strict=True))
    np.testing.assert_allclose(albedo, parts, atol=1e-6)


def test_hazy_gloss_extremes_are_finite():
    rng = np.random.default_rng(2)
    wo, wi = (ab.frame.normalize(rng.normal(size=(500, 3))) for _ in range(2))
    wo[:3] = [[0, 0, 1.0], [1.0, 0, 0], [np.sqrt(1 - 1e-16), 0, 1e-8]]
    u = rng.random((500, 3))
    for r_c in (0.0, 1.0, 0.5):
        for beta_h in (0.0, 1.0):
            for extent in (0.0, 50.0):
                for alpha in (1e-6, 1.0):
                    for kw in ({}, {"model": "beckmann", "compound_masking": True}):
                        lobes = [hazy.HazyGloss(r_c, beta_h, extent, alpha, edge_tint=0.5,
                                                **kw)]
                        if r_c < 1.0 and beta_h < 1.0:
                            lobes.append(hazy.HazyDielectric(r_c, beta_h, extent, alpha, **kw))
                        for lobe in lobes:
                            s = lobe.sample(wo, u)
                            for value in (lobe.eval(wo, wi), lobe.pdf(wo, wi), s.weight,
                                          s.pdf):
                                assert np.all(np.isfinite(value)), (lobe, r_c, beta_h)


# --- presets ---------------------------------------------------------------------------------
@pytest.mark.parametrize("name", list(ab.materials.presets.hazy))
def test_presets_build_finite_lobes(name):
    lobe = hazy.HazyGloss(**ab.materials.presets.hazy[name])
    wo = _wo(0.6)
    f = lobe.eval(wo, np.array([-wo[0], -wo[1], wo[2]]))
    assert np.all(np.isfinite(f)) and np.all(f > 0.0)
    assert 0.0 <= lobe.mapping.beta <= 1.0


def test_fig8_sweep_matches_its_caption():
    """Fig. 8: alpha_n = 0.012 with lambda_h = 6.4 gives the caption's alpha_w = 0.088 (to
    its printed digits), and the sweep's lobes keep the core peak (the bottom row)."""
    fixed, name, (first, last) = ab.materials.presets.hazy_sweeps["fig8"]
    alpha_w = hazy.wide_roughness(fixed["alpha_x"], fixed["alpha_x"], fixed["haze_extent"])
    assert alpha_w[0] == pytest.approx(0.088, abs=1e-3)
    peaks = [_composite_peak(hazy.haze_mapping(**fixed, **{name: b}))
             for b in np.linspace(first, last, 5)]
    np.testing.assert_allclose(peaks, np.broadcast_to(peaks[0], np.shape(peaks)), rtol=1e-9)


# --- compound masking and the transmission variant --------------------------------------------
@pytest.mark.parametrize("model", hazy.PEAK_MODELS)
def test_compound_lambda_is_the_smith_lambda_of_the_mixture(model):
    """[Barla2018, §3]: Lambda = (1 - beta) Lambda_n + beta Lambda_w is the Smith Lambda of the
    mixed distribution: its visible normals integrate to 1 [Heitz2014, eq. 11], its
    projected area is 1, and sample_visible draws them (chi-square)."""
    from tests.test_beckmann import _VisibleNormals
    from tests.test_microfacet import hemisphere_integral, visible_integral
    from tests.tolerances import QUADRATURE

    make = ab.microfacet.MODELS[model]
    mix = ab.microfacet.Mixture(make(0.1, 0.05), make(0.5, 0.4), 0.3)
    assert hemisphere_integral(lambda m: mix.D(m) * m[..., 2]) == pytest.approx(
        1.0, abs=QUADRATURE)
    for w in ((0.5, -0.3, 0.4), (0.9, 0.1, 0.05)):
        w = ab.frame.normalize(np.array(w))
        assert visible_integral(lambda m, w=w: mix.pdf_visible(w, m), w) == pytest.approx(
            1.0, abs=QUADRATURE)
        result = chi2_test(_VisibleNormals(mix), w, n_samples=300_000, seed=5,
                           alpha=CHI2_ALPHA, n_tests=4)
        assert result.passed, str(result)


def test_compound_masking_differs_from_separate_only_by_masking():
    """At normal incidence and the mirror direction G = 1 in both readings (§3), so the two
    agree there; elsewhere the compound lobe is the separate one with each lobe's masking
    replaced by the compound masking (computed here from the parts' Lambdas)."""
    args = ([0.9, 0.6, 0.3], 0.5, 5.0, 0.05)
    separate = hazy.HazyGloss(*args)
    compound = hazy.HazyGloss(*args, compound_masking=True)
    np.testing.assert_allclose(compound.eval(N, N), separate.eval(N, N), rtol=1e-12)
    rng = np.random.default_rng(4)
    wo, wi = ab.frame.normalize(np.abs(rng.normal(size=(2, 1000, 3))))
    narrow, wide = (c.distribution for c in separate.components)
    beta = separate.mapping.beta
    g_c = 1.0 / (1.0 + (1 - beta) * (narrow.lambda_(wo) + narrow.lambda_(wi))
                 + beta * (wide.lambda_(wo) + wide.lambda_(wi)))
    expected = sum(w * c.eval(wo, wi) * (g_c / c.distribution.G2(wo, wi))[:, None]
                   for c, w in zip(separate.components, separate.weights, strict=True))
    np.testing.assert_allclose(compound.eval(wo, wi), expected, rtol=1e-12)


def test_hazy_dielectric_is_two_dielectric_lobes_of_the_mapped_index():
    glass = hazy.HazyDielectric(0.04, 0.5, 4.0, 0.05)
    m = glass.mapping
    r = m.reflectivity[0]
    assert glass.eta == pytest.approx((1 + np.sqrt(r)) / (1 - np.sqrt(r)), rel=EXACT)
    assert r > 0.04  # the haze raises the index (§5)
    rng = np.random.default_rng(6)
    wo, wi = ab.frame.normalize(rng.normal(size=(2, 1000, 3)))
    expected = ((1 - m.beta) * ab.lobes.Dielectric(glass.eta, *m.alpha_n).eval(wo, wi)
                + m.beta * ab.lobes.Dielectric(glass.eta, *m.alpha_w).eval(wo, wi))
    np.testing.assert_allclose(glass.eval(wo, wi), expected, rtol=1e-14)
    with pytest.raises(ValueError, match="haziness"):
        hazy.HazyDielectric(0.1, 1.0, 4.0, 0.05)  # r_c > p = 0.04: r = 1
    with pytest.raises(ValueError, match="core_reflectivity"):
        hazy.HazyDielectric(1.0, 0.0, 4.0, 0.05)
    with pytest.raises(ValueError, match="narrow"):
        hazy.HazyGloss(0.5, 0.5, 4.0, 1e-9, compound_masking=True)  # a smooth core


@settings(max_examples=6, deadline=None)
@given(r_c=st.floats(0.0, 0.5), beta_h=st.floats(0.0, 0.95), extent=st.floats(0.0, 10.0),
       alpha=st.floats(0.05, 0.8), mu=st.floats(0.05, 1.0), glass=st.booleans())
def test_furnace_is_the_weighted_sum_of_independent_component_energies(r_c, beta_h, extent,
                                                                     alpha, mu, glass):
    """Acceptance 2: with F = 1 (HazyGloss) or the interface's own R + T (HazyDielectric),
    the composite's albedo by the library's direction-space quadrature equals (1 - beta) E_n
    + beta E_w with E from the independent node quadrature of ``tables.ggx_energy``, and is
    at most 1 + 1e-6."""
    from adobe_bsdf.tables.energy import ggx_energy

    wo = _wo(mu)
    if glass:
        lobe = hazy.HazyDielectric(r_c, beta_h, extent, alpha)
        eta = float(lobe.eta)
    else:
        mapped = hazy.HazyGloss(r_c, beta_h, extent, alpha)
        lobe = ab.composition.Sum(*(ab.lobes.Conductor.over(c.distribution)
                              for c in mapped.components), weights=mapped.weights)
        eta = None
    m = (lobe if glass else mapped).mapping

    def energy(a):
        if eta == 1.0:  # r_c = 0: no interface at all, everything passes (``Dielectric``)
            return 1.0
        e = ggx_energy(mu, a, eta, order=28)
        return float(e.reflection + e.transmission) if glass else float(e.reflection)

    expected = (1.0 - m.beta) * energy(m.alpha_n[0]) + m.beta * energy(m.alpha_w[0])
    albedo = lobe.albedo(wo, tol=1e-8)
    np.testing.assert_allclose(albedo, expected, atol=1e-6)
    assert np.all(albedo <= 1.0 + 1e-6)


def test_compound_masking_has_no_table_albedo():
    """The energy tables hold GGX: the compound-masking mixture raises ValueError (use the
    quadrature), as any other distribution does."""
    lobe = ab.lobes.HazyGloss(0.5, 0.3, 0.4, 0.1, compound_masking=True)
    with pytest.raises(ValueError, match="GGX only"):
        lobe.albedo(np.array([0.0, 0.6, 0.8]), method="table")
