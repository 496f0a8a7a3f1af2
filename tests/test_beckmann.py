"""Beckmann distribution: normalisation, Smith masking, visible-normal sampling (chi-square),
extremes; and the Conductor and Dielectric lobes built on it (chi-square, reciprocity, sample
weights, furnace). [Barla2018, Table 2] uses it beside GGX for hazy gloss; the comparison with
Mitsuba 3's Beckmann lobes is in ``test_mitsuba_crosscheck.py``."""

import numpy as np
import pytest
from scipy import special

import adobe_bsdf as ab
from adobe_bsdf.microfacet import Beckmann, _beckmann_visible_slope
from adobe_bsdf.validation import checks
from adobe_bsdf.validation.chi2 import chi2_test, suggest_grid
from tests.test_microfacet import ALPHAS, hemisphere_integral, sph, visible_integral
from tests.tolerances import CHI2_ALPHA, EXACT, FURNACE, QUADRATURE, RECIPROCITY, SUBNORMAL, WEIGHT


@pytest.mark.parametrize(("ax", "ay"), ALPHAS)
def test_projected_area_normalisation(ax, ay):
    """int D(m) cos theta_m dm = 1 [Heitz2014, eq. 2]."""
    b = Beckmann(ax, ay)
    assert hemisphere_integral(lambda m: b.D(m) * m[..., 2]) == pytest.approx(1.0, abs=QUADRATURE)


@pytest.mark.parametrize(("ax", "ay"), ALPHAS)
@pytest.mark.parametrize("w", [(0.5, -0.3, 0.4), (0.0, 0.0, 1.0), (0.9, 0.1, 0.05)])
def test_visible_normals_normalised(ax, ay, w):
    """int D_w(m) dm = 1: Lambda is the Smith masking of this D [Heitz2014, eq. 11]."""
    b = Beckmann(ax, ay)
    w = ab.frame.normalize(np.array(w))
    assert visible_integral(lambda m: b.pdf_visible(w, m), w) == pytest.approx(1.0, abs=QUADRATURE)


def test_D_and_lambda_closed_forms():
    """D in angles [Walter2007, eq. 25] and Lambda in its textbook erf form
    [Heitz2014, eq. 83] where that form is well conditioned."""
    ax, ay = 0.3, 0.7
    b = Beckmann(ax, ay)
    t, p = np.meshgrid(np.linspace(0, 1.5, 7), np.linspace(0, 6, 9))
    exponent = np.tan(t) ** 2 * (np.cos(p) ** 2 / ax**2 + np.sin(p) ** 2 / ay**2)
    expected = np.exp(-exponent) / (np.pi * ax * ay * np.cos(t) ** 4)
    # exp(-E) carries the rounding of E times E: the tolerance grows with the exponent
    value = b.D(np.moveaxis(sph(t, p), 0, -1))
    assert np.all(np.abs(value - expected) <= 1e-14 * (1.0 + exponent) * expected)
    w = np.moveaxis(sph(np.linspace(0.05, 1.55, 31), 0.4), 0, -1)
    a = w[:, 2] / np.hypot(ax * w[:, 0], ay * w[:, 1])
    textbook = (special.erf(a) - 1) / 2 + np.exp(-a * a) / (2 * a * np.sqrt(np.pi))
    np.testing.assert_allclose(b.lambda_(w), textbook, rtol=1e-9, atol=1e-15)
    rng = np.random.default_rng(3)
    wo, wi = (ab.frame.normalize(rng.normal(size=(100, 3))) for _ in range(2))
    np.testing.assert_allclose(b.G2(wo, wi), 1 / (1 + b.lambda_(wo) + b.lambda_(wi)), rtol=EXACT)
    np.testing.assert_allclose(b.G2_over_G1(wo, wi), b.G2(wo, wi) / b.G1(wo), rtol=EXACT)
    np.testing.assert_allclose(b.V(wo, wi), b.G2(wo, wi) / (4 * abs(wo[:, 2] * wi[:, 2])),
                               rtol=EXACT)
    s = Beckmann(ax, ay, masking="separable")
    np.testing.assert_allclose(s.G2(wo, wi), b.G1(wo) * b.G1(wi), rtol=EXACT)
    np.testing.assert_allclose(s.G2_over_G1(wo, wi), b.G1(wi), rtol=EXACT)


def test_visible_slope_solver_reaches_rounding():
    """The root of N(x) = u N(mu) to rounding of N (mu from grazing to near-normal)."""
    mu, u = (a.ravel() for a in np.meshgrid([0.0, 1e-3, 0.3, 1.0, 3.0, 30.0, 1e4],
                                            [1e-12, 1e-3, 0.2, 0.5, 0.9, 1 - 1e-12]))
    x = _beckmann_visible_slope(mu, u)

    def n_of(x):
        return mu * np.sqrt(np.pi) / 2 * special.erfc(-x) + np.exp(-x * x) / 2

    np.testing.assert_allclose(n_of(x), u * n_of(mu), rtol=1e-13)
    assert np.all(x <= mu)


class _VisibleNormals(ab.Lobe):
    """Test adaptor: a 'lobe' whose samples are the visible normals of ``wo``."""

    flags = ab.Flags.REFLECTION | ab.Flags.GLOSSY

    def __init__(self, distribution):
        self.distribution = distribution

    def _pdf(self, wo, wi):
        return self.distribution.pdf_visible(wo, wi)

    def _eval(self, wo, wi):
        return np.repeat(self._pdf(wo, wi)[..., None], 3, axis=-1)

    def _sample(self, wo, u):
        m = self.distribution.sample_visible(wo, u[..., 1:])
        pdf = self.distribution.pdf_visible(wo, m)
        ok = pdf > 0.0
        return ab.BSDFSample(np.where(ok[..., None], m, 0.0),
                             np.where(ok[..., None], np.abs(m[..., 2:3]), 0.0) * np.ones(3),
                             pdf, np.where(ok, int(self.flags), 0))


CHI2_CASES = [((a, b), c) for a, b in [(0.05, 0.05), (0.3, 0.3), (1.0, 1.0), (0.5, 0.1)]
              for c in (1.0, 0.5, 0.05, -0.4)]


@pytest.mark.parametrize(("alpha", "cos_theta"), CHI2_CASES)
def test_chi2_visible_normals(alpha, cos_theta):
    """sample_visible draws normals with density pdf_visible (p > 0.01 after Šidák)."""
    s = np.sqrt(1 - cos_theta**2)
    w = np.array([s * np.cos(0.7), s * np.sin(0.7), cos_theta])
    lobe = _VisibleNormals(Beckmann(*alpha))
    seed = CHI2_CASES.index((alpha, cos_theta))
    grid = suggest_grid(2.0 * max(alpha), np.array([0.0, 0.0, 1.0])) if max(alpha) < 0.3 \
        else {}
    result = chi2_test(lobe, w, n_samples=300_000, seed=seed, alpha=CHI2_ALPHA,
                       n_tests=len(CHI2_CASES), **grid)
    assert result.passed, str(result)


def test_extremes_and_smooth_limit():
    b = Beckmann([0.0, 1e-9, 0.3, 1.0, 3.0], [0.0, 0.0, 1e-12, 1.0, 0.1])
    w = np.array([[0, 0, 1.0], [1.0, 0, 0], [0, 1.0, 0], [np.sqrt(1 - 1e-16), 0, 1e-8],
                  [0.6, 0.0, -0.8]])
    for f in (b.D, b.G1, b.lambda_):
        assert not np.any(np.isnan(f(w)))
    assert np.all(np.isfinite(b.D(w))) and np.all(np.isfinite(b.G1(w)))
    assert np.all(np.isfinite(b.pdf_visible(w, w))) and np.all(np.isfinite(b.V(w, w[::-1])))
    assert b.lambda_(np.array([1.0, 0, 0]))[3] == np.inf  # the exact grazing limit
    assert b.lambda_(np.array([0, 0, 1.0]))[3] == 0.0
    u = np.array([[0.0, 0.0], [0.5, 0.5], [1 - 2**-53, 1 - 2**-53], [0.0, 0.9], [0.3, 0.0]])
    m = b.sample_visible(w, u)
    assert np.all(np.isfinite(m))
    np.testing.assert_allclose(np.linalg.norm(m, axis=-1), 1.0, atol=1e-14)
    np.testing.assert_array_equal(m[:2], [[0, 0, 1.0], [0, 0, 1.0]])  # smooth: the normal
    assert np.all(m[:, 2] >= 0.0)


def test_bad_input():
    with pytest.raises(ValueError, match="alpha_x"):
        Beckmann(-0.1)
    with pytest.raises(ValueError, match="masking"):
        Beckmann(0.1, masking="uncorrelated")


# -- Beckmann lobes: Conductor(model="beckmann") and Dielectric(model="beckmann") -----------
LOBE_ALPHAS = [(0.05, 0.05), (0.3, 0.3), (1.0, 1.0), (0.5, 0.1)]
LOBE_CASES = ([("Conductor", a, None, c) for a in LOBE_ALPHAS for c in (1.0, 0.5, 0.05)]
              + [("Dielectric", a, eta, c) for a in [(0.05, 0.05), (0.3, 0.3), (0.5, 0.1)]
                 for eta in (1.5, 1 / 1.5) for c in (0.8, -0.5)])


def _lobe(kind, alpha, eta, **kwargs):
    if kind == "Conductor":
        return ab.lobes.Conductor(*alpha, model="beckmann", **kwargs)
    return ab.lobes.Dielectric(eta, *alpha, model="beckmann", **kwargs)


def _direction(cos_theta, phi=0.7):
    s = np.sqrt(1.0 - cos_theta**2)
    return np.array([s * np.cos(phi), s * np.sin(phi), cos_theta])


@pytest.mark.parametrize(("kind", "alpha", "eta", "cos_theta"), LOBE_CASES, ids=str)
def test_chi2_beckmann_lobes(kind, alpha, eta, cos_theta):
    """``sample`` draws directions with density ``pdf`` (p > 0.01 after Šidák), the
    hazy-gloss acceptance 3."""
    from tests.test_lobes_chi2 import grid

    wo = _direction(cos_theta)
    seed = 100 + LOBE_CASES.index((kind, alpha, eta, cos_theta))
    result = chi2_test(_lobe(kind, alpha, eta), wo, n_samples=500_000, seed=seed,
                       alpha=CHI2_ALPHA, n_tests=len(LOBE_CASES), **grid(kind, alpha, eta, wo))
    assert result.passed, str(result)


@pytest.mark.parametrize("masking", ["correlated", "separable"])
def test_beckmann_lobes_reciprocity_and_weights(masking):
    """Reciprocity (generalized across the interface) to 1e-12 on 10^5 random pairs, and
    sample weights = f |cos| / pdf (``checks.weight_consistency``)."""
    rng = np.random.default_rng(21)
    wo, wi = ab.frame.normalize(rng.normal(size=(2, 100_000, 3)))
    for kind, alpha, eta in [("Conductor", (0.3, 0.3), None), ("Conductor", (0.5, 0.05), None),
                             ("Dielectric", (0.2, 0.2), 1.5), ("Dielectric", (0.6, 0.1), 1 / 1.3)]:
        lobe = _lobe(kind, alpha, eta, masking=masking)
        result = checks.reciprocity_error(lobe, wo, wi, rtol=RECIPROCITY, atol=SUBNORMAL)
        assert result.passed, result
        for cos_theta in (0.9, 0.2, -0.6):
            result = checks.weight_consistency(lobe, _direction(cos_theta), n_samples=20_000,
                                               rtol=WEIGHT)
            assert result.passed, result


@pytest.mark.parametrize("alpha", [(0.3, 0.3), (1.0, 1.0), (0.5, 0.1)])
@pytest.mark.parametrize("cos_theta", [1.0, 0.5, 0.05])
def test_beckmann_conductor_furnace_against_independent_quadrature(alpha, cos_theta):
    """F = 1 albedo (the library's adaptive quadrature) against scipy cubature in angles."""
    from tests.test_lobes_furnace import hemisphere_albedo

    lobe = ab.lobes.Conductor(*alpha, model="beckmann")
    wo = _direction(cos_theta)
    value = lobe.albedo(wo, method="quadrature")
    np.testing.assert_allclose(value, hemisphere_albedo(lobe, wo), atol=FURNACE)
    assert np.all(value <= 1.0)


def test_beckmann_lobes_have_no_tables():
    wo = np.array([0.0, 0.0, 1.0])
    with pytest.raises(ValueError, match="GGX"):
        ab.lobes.Conductor(0.3, model="beckmann").albedo(wo, method="table")
    with pytest.raises(ValueError, match="GGX"):
        ab.lobes.Dielectric(1.5, 0.3, model="beckmann").albedo(wo, method="table")
    with pytest.raises(ValueError, match="model"):
        ab.lobes.Conductor(0.3, model="phong")


def test_visible_slope_does_not_depend_on_the_batch():
    """Each element stops at its own convergence: solving a subset gives the same bits (what
    makes chunked sampling bit-identical, ``test_execution.py``)."""
    rng = np.random.default_rng(9)
    mu, u = rng.exponential(size=4000), rng.random(4000)
    whole = _beckmann_visible_slope(mu, u)
    for part in (slice(0, 1), slice(5, 777), slice(3000, None, 7)):
        np.testing.assert_array_equal(_beckmann_visible_slope(mu[part], u[part]), whole[part])
