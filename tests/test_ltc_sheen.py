"""The LTC fuzz [Zeltner2022] [OpenPBR2026, §Fuzz]: the definition, the normalisation of its
linearly transformed cosine [Heitz2016], the albedo fit against the authors' simulated
albedo, exact sampling, its non-reciprocity (measured), extremes and bad input."""

import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from scipy import integrate

from adobe_bsdf.composition import Layer
from adobe_bsdf.lobes.lambert import Lambert
from adobe_bsdf.lobes.ltc_sheen import LTCSheen, albedo_fit, ltc_coefficients
from adobe_bsdf.validation import strategies as vs
from adobe_bsdf.validation.chi2 import chi2_test
from tests.sampling_checks import assert_sampling_matches
from tests.tolerances import CHI2_ALPHA, EXACT, QUADRATURE

COLOR = np.array([0.9, 0.5, 0.2])


def _wo(c, phi=0.4):
    s = np.sqrt((1.0 - c) * (1.0 + c))
    return np.array([s * np.cos(phi), s * np.sin(phi), c])


def _upper(rng, n):
    w = rng.normal(size=(n, 3))
    w[:, 2] = np.abs(w[:, 2]) + 1e-3
    return w / np.linalg.norm(w, axis=-1, keepdims=True)


# -- the definition, written out as printed ---------------------------------------------------
def _E(x, y):
    """E(x, y) of [OpenPBR2026, §Fuzz] as printed, clamped to [0, 1] (y > 0)."""
    s = y * (0.0206607 + 1.58491 * y) / (0.0379424 + y * (1.32227 + y))
    m = y * (-0.193854 + y * (-1.14885 + y * (1.7932 - 0.95943 * y**2))) / (0.046391 + y)
    o = y * (0.000654023 + (-0.0207818 + 0.119681 * y) * y) / (1.26264 + y * (-1.92021 + y))
    return np.clip(np.exp(-0.5 * ((x - m) / s) ** 2) / (s * np.sqrt(2.0 * np.pi)) + o, 0.0, 1.0)


def _ab(x, y):
    """aInv and bInv of [OpenPBR2026, §Fuzz] as printed."""
    a = (2.58126 * x + 0.813703 * y) * y / (1.0 + 0.310327 * x**2 + 2.60994 * x * y)
    b = np.sqrt(1.0 - x) * (y - 1.0) * y**3 / (0.0000254053 + 1.71228 * x - 1.71506 * x * y
                                                + 1.34174 * y**2)
    return a, b


def _M_inv(x, y):
    """M^-1 of [Zeltner2022] with the fitted entries."""
    a, b = _ab(x, y)
    return np.array([[a, 0.0, b], [0.0, a, 0.0], [0.0, 0.0, 1.0]])


def _definition(wo, wi, color, alpha):
    """mu_i f = color E D with D(w) = D_o(M^-1 w / |M^-1 w|) |det M^-1| / |M^-1 w|^3
    [Heitz2016, §3], D_o the clamped cosine / pi, in the frame that turns wo to azimuth 0
    [Zeltner2022]; one pair at a time, the matrix by NumPy."""
    phi = np.arctan2(wo[1], wo[0])
    c, s = np.cos(-phi), np.sin(-phi)
    w = np.array([c * wi[0] - s * wi[1], s * wi[0] + c * wi[1], wi[2]])
    M_inv = _M_inv(wo[2], alpha)
    v = M_inv @ w
    length = np.linalg.norm(v)
    D = max(v[2] / length, 0.0) / np.pi * abs(np.linalg.det(M_inv)) / length**3
    return color * _E(wo[2], alpha) * D / wi[2]


@pytest.mark.parametrize("alpha", [0.02, 0.3, 0.7, 1.0])
def test_eval_and_pdf_are_the_definition(alpha):
    """f and pdf against the LTC written out with a matrix (the lobe uses the simplified
    D = (w_z / pi) (aInv / |w'|^2)^2: the exponent 4 and det M^-1 = aInv^2 checked here)."""
    rng = np.random.default_rng(3)
    wo, wi = _upper(rng, 300), _upper(rng, 300)
    lobe = LTCSheen(COLOR, alpha)
    expected = np.array([_definition(o, i, COLOR, alpha) for o, i in zip(wo, wi, strict=True)])
    np.testing.assert_allclose(lobe.eval(wo, wi), expected, rtol=EXACT, atol=0.0)
    white = np.array([_definition(o, i, 1.0, alpha) for o, i in zip(wo, wi, strict=True)])
    E = _E(wo[:, 2], alpha)
    live = E > 0.0
    np.testing.assert_allclose(lobe.pdf(wo, wi)[live], (white * wi[:, 2] / E)[live], rtol=EXACT)
    np.testing.assert_allclose(albedo_fit(wo[:, 2], alpha), E, rtol=EXACT, atol=0.0)
    for got, printed in zip(ltc_coefficients(wo[:, 2], alpha), _ab(wo[:, 2], alpha),
                            strict=True):
        np.testing.assert_allclose(got, printed, rtol=EXACT, atol=0.0)


# -- normalisation ------------------------------------------------------------------------------
#: azimuths of the inner rule: the integrand is smooth and periodic in phi (M^-1 w never
#: vanishes above the horizon), so the trapezoid rule converges geometrically; 256 points
#: change no result by more than 7e-16
N_PHI = 128


def _hemisphere(fn, a):
    """int over the upper hemisphere of fn(wi) ``(n, k)`` dwi: scipy's adaptive quad_vec over
    cos theta_i (break points about aInv, the width of the lobe's grazing peak) of the
    trapezoid rule over phi_i."""
    phi = np.arange(N_PHI) * (2.0 * np.pi / N_PHI)

    def ring(mu):
        s = np.sqrt(1.0 - mu * mu)
        wi = np.stack([s * np.cos(phi), s * np.sin(phi), np.full(N_PHI, mu)], axis=-1)
        return 2.0 * np.pi * fn(wi).mean(axis=0)

    points = [p for p in (a / 8, a / 2, a, 2 * a, 8 * a) if p < 1.0]
    return integrate.quad_vec(ring, 0.0, 1.0, points=points, epsabs=1e-13, epsrel=1e-11,
                              limit=400)[0]


@pytest.mark.parametrize("alpha", [0.05, 0.3, 0.7, 1.0])
@pytest.mark.parametrize("mu", [0.05, 0.2, 0.5, 1.0])
def test_albedo_is_the_fit_and_the_lobe_is_normalised(alpha, mu):
    """int f cos dwi = color E(mu_o, alpha) and int pdf dwi = 1 (D is normalised), by scipy
    quadrature of eval and pdf; E from the fit as printed. Where the clamp makes E = 0
    (alpha = 0.05, mu_o >= 0.2) f is 0 everywhere and the pdf still integrates to 1."""
    lobe = LTCSheen(COLOR, alpha)
    wo = _wo(mu)
    a = float(ltc_coefficients(mu, alpha)[0])
    value = _hemisphere(lambda wi: np.concatenate(
        [lobe.eval(wo, wi) * wi[:, 2:], lobe.pdf(wo, wi)[:, None]], axis=-1), a)
    np.testing.assert_allclose(value[:3], COLOR * _E(mu, alpha), rtol=QUADRATURE, atol=0.0)
    assert value[3] == pytest.approx(1.0, rel=QUADRATURE)
    np.testing.assert_allclose(lobe.albedo(wo, "table"), COLOR * _E(mu, alpha), rtol=EXACT)


# -- the albedo fit -----------------------------------------------------------------------------
#: nodes (alpha index j, cos theta index i: alpha = j / 31, cos theta = i / 31) of the authors'
#: table of the SGGX fibre volume they fitted [Zeltner2022, the code release's
#: ltc_table_sheen_volume]: (j, i, A, B, R), R the volume's albedo by simulation
AUTHORS = [(10, 1, 0.13694, -0.16229, 0.62456), (10, 10, 0.28326, -0.02247, 0.11687),
           (16, 5, 0.37775, -0.12867, 0.48220), (16, 20, 0.51205, -0.04471, 0.09688),
           (22, 1, 0.45893, -0.14091, 0.67808), (22, 15, 0.66186, -0.08157, 0.32779),
           (22, 31, 0.72944, 0.00004, 0.11016), (31, 1, 0.74617, -0.00002, 0.73527),
           (31, 16, 0.86320, -0.00005, 0.49191), (31, 31, 0.87958, 0.00003, 0.34187)]
#: |fit - table| measured once over all 775 nodes of that table with alpha > 0.2 and
#: cos theta >= 1/31 (the region of these nodes): E 0.0111 (RMS 0.0037), aInv 0.095, bInv
#: 0.072. Over all 1024 nodes E is off by up to 0.17 (alpha = 2/31, cos theta = 0.01: the
#: grazing, low-roughness corner, where the table's albedo rises steeply; RMS 0.009).
AUTHORS_E, AUTHORS_A, AUTHORS_B = 0.012, 0.1, 0.075


def test_albedo_fit_against_the_authors_simulated_albedo():
    """The only independent evidence of what E approximates: the albedo R of the volumetric
    fibre layer, simulated by the authors, at nodes of their table; likewise their fitted
    transform entries A (aInv) and B (bInv), of which the closed forms are fits."""
    j, i, A, B, R = (np.array(c) for c in zip(*AUTHORS, strict=True))
    alpha, mu = j / 31.0, i / 31.0
    assert np.max(np.abs(albedo_fit(mu, alpha) - R)) <= AUTHORS_E
    a, b = ltc_coefficients(mu, alpha)
    assert np.max(np.abs(a - A)) <= AUTHORS_A
    assert np.max(np.abs(b - B)) <= AUTHORS_B


def test_albedo_fit_is_bounded_and_continuous():
    """E in [0, 1] everywhere (alpha = 0 and cos theta = 0 included); on the fitted range
    alpha in [0.01, 1] the largest step between neighbours of a grid halves with the grid's
    step (Lipschitz: no jump); E -> 0 as alpha -> 0 at every mu > 0 (the Gaussian vanishes
    there and the offset o falls as ~5e-4 alpha)."""
    x = np.linspace(0.0, 1.0, 801)
    E = albedo_fit(x[:, None], x[None, :])
    assert np.all(np.isfinite(E)) and E.min() >= 0.0 and E.max() <= 1.0
    assert not np.any(E[:, 0])  # alpha = 0

    def largest_step(n):
        mu, alpha = np.linspace(0.0, 1.0, n), np.linspace(0.01, 1.0, n)
        E = albedo_fit(mu[:, None], alpha[None, :])
        return max(np.abs(np.diff(E, axis=0)).max(), np.abs(np.diff(E, axis=1)).max())

    coarse, fine = largest_step(1001), largest_step(2001)
    assert 1.8 < coarse / fine < 2.2, (coarse, fine)
    small = albedo_fit(np.array([0.05, 0.2, 1.0])[:, None], [1e-2, 1e-3, 1e-6])
    assert np.all(small[:, 0] < 1e-5) and np.all(small[:, 1] < 1e-6)
    assert np.all(small[:, 2] < 1e-9)


# -- sampling -----------------------------------------------------------------------------------
CHI2 = [(0.05, 0.1), (0.05, 1.0), (0.3, 0.1), (0.3, 0.5), (0.7, 0.1), (0.7, 0.9), (1.0, 0.5),
        (1.0, 1.0)]
#: the tests of the family: CHI2 and the fine-ring test
N_CHI2 = len(CHI2) + 1


@pytest.mark.parametrize(("alpha", "cos_theta"), CHI2)
def test_sampling(alpha, cos_theta):
    assert_sampling_matches(LTCSheen((1.0, 0.6, 0.3), alpha), cos_theta, 0.4,
                            seed=CHI2.index((alpha, cos_theta)), n_tests=N_CHI2)


def test_sampling_of_the_grazing_peak_on_fine_rings():
    """alpha = 0.05, cos theta_o = 0.1: D lies within w_z ~ aInv = 0.015 of the horizon, in
    the last ring of the default grid; 1024 rings resolve it."""
    result = chi2_test(LTCSheen((1.0, 0.6, 0.3), 0.05), _wo(0.1), n_samples=300_000,
                       n_theta=1024, n_phi=32, seed=len(CHI2), alpha=CHI2_ALPHA,
                       n_tests=N_CHI2)
    assert result.passed, str(result)


def test_every_sample_weighs_the_albedo():
    """Exact importance sampling: weight = color E(mu_o, alpha) for every sample (so the Monte
    Carlo albedo has no variance), and no sample fails for alpha > 0."""
    rng = np.random.default_rng(4)
    for alpha, mu in ((0.05, 0.02), (0.4, 0.3), (1.0, 1.0)):
        lobe = LTCSheen(COLOR, alpha)
        s = lobe.sample(_wo(mu), rng.random((20_000, 3)))
        assert np.all(s.pdf > 0.0) and np.all(s.wi[:, 2] > 0.0)
        np.testing.assert_allclose(s.weight, np.broadcast_to(COLOR * _E(mu, alpha), (20_000, 3)),
                                   rtol=EXACT, atol=0.0)
        mc, error = lobe.albedo(_wo(mu), "mc", n_samples=1000, return_error=True)
        np.testing.assert_allclose(mc, COLOR * _E(mu, alpha), rtol=EXACT)
        assert np.all(error < 1e-15)


# -- reciprocity ----------------------------------------------------------------------------------
#: measured once on the grid of ``_reciprocity``: per alpha, the largest |f(wo, wi) -
#: f(wi, wo)| / max(f(wo, wi), f(wi, wo)) and the largest |f(wo, wi) - f(wi, wo)| over the
#: largest f of the grid (also in docs/fuzz_measured.md). E and M^-1 depend on cos theta_o
#: alone: the fit is not reciprocal. The bounds are these figures rounded up; a larger value
#: means the fits or the lobe's frame changed.
RECIPROCITY_MEASURED = {0.3: (0.690, 0.120), 0.5: (0.504, 0.265), 0.7: (0.454, 0.358),
                        1.0: (0.248, 0.204)}


def _reciprocity(alpha):
    mu = np.linspace(0.05, 1.0, 20)
    phi = np.linspace(0.0, np.pi, 13)
    Mo, Mi, P = np.meshgrid(mu, mu, phi, indexing="ij")
    so, si = np.sqrt(1.0 - Mo**2), np.sqrt(1.0 - Mi**2)
    wo = np.stack([so, 0.0 * so, Mo], axis=-1)
    wi = np.stack([si * np.cos(P), si * np.sin(P), Mi], axis=-1)
    lobe = LTCSheen(1.0, alpha)
    forward, backward = lobe.eval(wo, wi)[..., 0], lobe.eval(wi, wo)[..., 0]
    difference, larger = np.abs(forward - backward), np.maximum(forward, backward)
    return (np.max(difference / np.where(larger > 0.0, larger, 1.0)),
            difference.max() / larger.max())


@pytest.mark.parametrize("alpha", sorted(RECIPROCITY_MEASURED))
def test_it_is_not_reciprocal_by_this_much(alpha):
    pairwise, overall = _reciprocity(alpha)
    bound_pairwise, bound_overall = RECIPROCITY_MEASURED[alpha]
    assert 0.1 < pairwise <= bound_pairwise and 0.1 < overall <= bound_overall


# -- as a layer ---------------------------------------------------------------------------------
def test_layer_attenuates_the_base_by_white_fuzz():
    """[OpenPBR2026, §Fuzz]: F f_fuzz + (1 - F E_fuzz) f_base with E_fuzz of white fuzz, so
    over a Lambertian base of albedo rho the layer's albedo is F color E + (1 - F E) rho."""
    rng = np.random.default_rng(5)
    wo, wi = _upper(rng, 50), _upper(rng, 50)
    fuzz = LTCSheen(COLOR, 0.5)
    E = _E(wo[:, 2], 0.5)[:, None]
    np.testing.assert_allclose(fuzz._top_albedo(wo), np.repeat(E, 3, axis=1), rtol=EXACT)
    layer = Layer(fuzz, Lambert(0.8), coverage=0.7)
    np.testing.assert_allclose(layer.eval(wo, wi),
                               0.7 * fuzz.eval(wo, wi) + (1.0 - 0.7 * E) * 0.8 / np.pi,
                               rtol=EXACT)
    np.testing.assert_allclose(layer.albedo(wo[:3]), 0.7 * COLOR * E[:3] + (1.0 - 0.7 * E[:3])
                               * 0.8, rtol=QUADRATURE)


# -- extremes, broadcasting, bad input ------------------------------------------------------------
def _finite_non_negative(lobe, wo, wi, u):
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        f, p = lobe.eval_pdf(wo, wi)
        s = lobe.sample(wo, u)
        E = lobe.albedo(wo, "table")
    for name, value in (("eval", f), ("pdf", p), ("weight", s.weight), ("sample pdf", s.pdf),
                        ("albedo", E), ("wi", np.abs(s.wi))):
        assert np.all(np.isfinite(value)) and np.all(value >= 0.0), (name, value)
    return f, p, s


EXTREME_COS = (5e-324, 1e-310, 1e-200, 1e-20, 1e-8, 0.5, 1.0 - 1e-16, 1.0, 0.0, -1e-310, -0.5)
EXTREME_ALPHA = (0.0, 5e-324, 1e-300, 1e-154, 1e-20, 1e-8, 1e-3, 0.01, 0.5, 1.0)


@pytest.mark.parametrize("alpha", EXTREME_ALPHA)
def test_extremes_are_finite_and_non_negative(alpha):
    w = np.array([_wo(c) for c in EXTREME_COS] + [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0],
                                                 [1e-9, 0.0, 1.0]])
    wo, wi = (a.reshape(-1, 3) for a in np.broadcast_arrays(w[:, None], w[None, :]))
    u = np.random.default_rng(6).random((len(wo), 3))
    u[:3] = [[0.0, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.999999, 0.999999]]
    for color in (0.0, COLOR):
        f, p, s = _finite_non_negative(LTCSheen(color, alpha), wo, wi, u)
        below = (wo[:, 2] <= 0.0) | (wi[:, 2] <= 0.0)
        assert not np.any(f[below]) and not np.any(p[below])
        assert not np.any(s.pdf[wo[:, 2] <= 0.0])


@settings(max_examples=150, deadline=None)
@given(alpha=vs.roughness(), pair=vs.direction_pairs("any"), u=vs.uniform_triples())
def test_any_valid_input_is_finite_and_non_negative(alpha, pair, u):
    _finite_non_negative(LTCSheen(COLOR, alpha), *pair, u)


def test_zero_roughness_is_no_fuzz():
    """alpha = 0 (aInv = 0): f = 0, no sample succeeds, every albedo is 0."""
    rng = np.random.default_rng(7)
    wo, wi = _upper(rng, 200), _upper(rng, 200)
    lobe = LTCSheen(1.0, 0.0)
    assert not np.any(lobe.eval(wo, wi)) and not np.any(lobe.pdf(wo, wi))
    s = lobe.sample(wo, rng.random((200, 3)))
    assert not np.any(s.pdf) and not np.any(s.weight) and not np.any(s.flags)
    for method in ("table", "mc", "quadrature"):
        assert not np.any(lobe.albedo(wo[:3], method, n_samples=100))
    assert not np.any(lobe._top_albedo(wo))


def test_normal_incidence_takes_any_frame():
    """wo = n has no projection on the surface: bInv = 0 there and the lobe is symmetric
    about n, so every frame gives the same values."""
    rng = np.random.default_rng(8)
    wi = _upper(rng, 100)
    turn = np.array([[0.6, -0.8, 0.0], [0.8, 0.6, 0.0], [0.0, 0.0, 1.0]])
    lobe = LTCSheen(COLOR, 0.4)
    n = np.array([0.0, 0.0, 1.0])
    np.testing.assert_allclose(lobe.eval(n, wi @ turn.T), lobe.eval(n, wi), rtol=EXACT)
    np.testing.assert_allclose(lobe.eval([1e-9, 0.0, 1.0], wi), lobe.eval(n, wi), rtol=1e-8)
    assert ltc_coefficients(1.0, 0.4)[1] == 0.0


def test_parameters_broadcast():
    rng = np.random.default_rng(9)
    wo, wi = _upper(rng, 4), _upper(rng, 4)
    alpha = np.array([0.0, 0.1, 0.5, 1.0])
    colors = rng.random((4, 3))
    lobe = LTCSheen(colors, alpha)
    u = rng.random((4, 3))
    s = lobe.sample(wo, u)
    for k in range(4):
        one = LTCSheen(colors[k], alpha[k])
        np.testing.assert_allclose(lobe.eval(wo, wi)[k], one.eval(wo[k], wi[k]), rtol=EXACT)
        np.testing.assert_allclose(lobe.pdf(wo, wi)[k], one.pdf(wo[k], wi[k]), rtol=EXACT)
        np.testing.assert_allclose(lobe.albedo(wo, "table")[k], one.albedo(wo[k], "table"),
                                   rtol=EXACT)
        np.testing.assert_allclose(s.weight[k], one.sample(wo[k], u[k]).weight, rtol=EXACT)
    assert lobe.albedo(wo, "table").shape == (4, 3)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"roughness": -0.1}, r"roughness = -0\.1 is outside the allowed range \[0\.0, 1\.0\]"),
    ({"roughness": 1.5}, r"roughness = 1\.5 is outside"),
    ({"roughness": np.nan}, r"roughness = nan is outside"),
    ({"color": 1.2}, r"color = 1\.2 is outside the allowed range \[0\.0, 1\.0\]"),
    ({"color": (0.5, -0.1, 0.2)}, r"color = -0\.1 is outside"),
    ({"color": "red"}, r"color = 'red' is not a real number"),
    ({"color": np.ones((2, 3)), "roughness": np.ones(3) * 0.5}, r"do not broadcast"),
])
def test_bad_parameters_raise(kwargs, match):
    with pytest.raises(ValueError, match=match):
        LTCSheen(**{"color": 1.0, "roughness": 0.5, **kwargs})


def test_bad_fit_arguments_raise():
    with pytest.raises(ValueError, match=r"mu = 1\.5 is outside"):
        albedo_fit(1.5, 0.5)
    with pytest.raises(ValueError, match=r"roughness = -1\.0 is outside"):
        ltc_coefficients(0.5, -1.0)


def test_fuzz_report_smoke(tmp_path):
    """``benchmarks.fuzz_report`` (tiny sizes) writes its page and figure into the given folder
    only, with every section."""
    from benchmarks import fuzz_report

    page = Path(__file__).resolve().parents[1] / "docs" / "fuzz_measured.md"
    before = page.stat().st_mtime_ns if page.exists() else None
    path = fuzz_report.run(tmp_path, smoke=True)
    assert path.parent == tmp_path and (tmp_path / "figures" / "fuzz_albedo.png").exists()
    assert (page.stat().st_mtime_ns if page.exists() else None) == before
    text = path.read_text(encoding="utf-8")
    assert "Generated by `python -m benchmarks.fuzz_report`" in text
    for heading in ("## Directional albedo", "## The fit's clamp and small roughness",
                    "## The lobe's albedo by quadrature and Monte Carlo", "## Reciprocity"):
        assert heading in text, heading
