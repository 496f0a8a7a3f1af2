"""The ASM sheen [Kutz2021, §6, eqs. 15-18]: formulas, the SGGX fibre normalisation, sampling,
reciprocity, the albedo table and the energy claim of c = 2."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate

from adobe_bsdf import tables
from adobe_bsdf.lobes.sheen import R_SIMILAR, Sheen
from adobe_bsdf.tables.catalog import sheen_energy
from adobe_bsdf.validation import checks
from adobe_bsdf.validation import strategies as vs
from adobe_bsdf.validation.chi2 import chi2_test
from tests.tolerances import CHI2_ALPHA, EXACT, QUADRATURE, RECIPROCITY, WEIGHT

#: |table - fresh quadrature| for c a = 1 where cos theta_o >= 1e-4 (measured max 4.9e-6 over
#: 8000 random points, docs/sheen_measured.md)
TABLE = 2e-5
#: ... and anywhere: the first mu cell (cos theta_o < ~1e-5) cannot follow E's dependence on
#: mu / r (measured max 2.5e-4 on a sweep of that corner)
TABLE_GRAZING = 4e-4
#: Monte Carlo against quadrature, in standard errors
MC_SIGMAS = 5.0


def _wo(c, phi=0.4):
    s = np.sqrt(1.0 - c * c)
    return np.array([s * np.cos(phi), s * np.sin(phi), c])


def _upper(rng, n, min_z=1e-3):
    w = rng.normal(size=(n, 3))
    w[:, 2] = np.abs(w[:, 2])
    w /= np.linalg.norm(w, axis=-1, keepdims=True)
    w[:, 2] = np.maximum(w[:, 2], min_z)
    return w / np.linalg.norm(w, axis=-1, keepdims=True)


def _eqs_15_to_18(wo, wi, a, r, c=2.0, p=1.0):
    """Eqs. 15-18 transcribed as printed (for directions away from the horizon)."""
    h = wo + wi
    h = h / np.linalg.norm(h, axis=-1, keepdims=True)
    t = h[..., 0] ** 2 + h[..., 1] ** 2 + (h[..., 2] / r) ** 2
    D = 1.0 / (np.pi * r * t**2)

    def lam(w):
        return np.sqrt(w[..., 0] ** 2 + w[..., 1] ** 2 + (r * w[..., 2]) ** 2) / w[..., 2]

    L = lam(wi) + lam(wo)
    G = (1.0 - np.exp(-p * L)) / L
    return c * np.asarray(a) * (D * G / (4.0 * wi[..., 2] * wo[..., 2]))[..., None]


# -- formulas ---------------------------------------------------------------------------------
@pytest.mark.parametrize(("r", "c", "p"), [(0.02, 2.0, 1.0), (0.3, 2.0, 1.0), (1.0, 1.0, 0.5),
                                           (0.7, 3.0, 4.0)])
def test_eval_is_eqs_15_to_18(r, c, p):
    rng = np.random.default_rng(1)
    wo, wi = _upper(rng, 2000), _upper(rng, 2000)
    a = np.array([0.9, 0.5, 0.2])
    np.testing.assert_allclose(Sheen(a, r, c, p).eval(wo, wi), _eqs_15_to_18(wo, wi, a, r, c, p),
                               rtol=EXACT)


def _D(r, h):
    """The lobe's D (eq. 16) at unit normals h ``(..., 3)``: D at wo = wi = h."""
    return Sheen(1.0, r)._D(h, h)


@pytest.mark.parametrize("r", [0.05, 0.3, 0.8, 1.0])
def test_fibre_distribution_normalisation(r):
    """SGGX normalisation [Heitz2015]: int <w, h>_+ D(h) dh = sigma(w), the projected
    area; int D over the sphere is the fibre ellipsoid's area over pi, 2 r + 2 acos(r) /
    sqrt(1 - r^2) (4 at r = 1), not 1. By scipy quadrature over cos theta_h, with the
    azimuthal integral of max(<w, h>, 0) in closed form."""
    def D(mu):
        return float(_D(r, np.array([np.sqrt(1.0 - mu * mu), 0.0, mu])))

    total = 2.0 * np.pi * integrate.quad(D, -1.0, 1.0, points=[0.0], epsabs=1e-12,
                                         epsrel=1e-12, limit=200)[0]
    area = 4.0 if r == 1.0 else 2.0 * r + 2.0 * np.arccos(r) / np.sqrt(1.0 - r * r)
    assert total == pytest.approx(area, rel=QUADRATURE)
    for cos_o in (1.0, 0.6, 0.1, 0.0):
        s_o = np.sqrt(1.0 - cos_o * cos_o)

        def visible(mu, s_o=s_o, cos_o=cos_o):
            # int over phi of max(A cos phi + B, 0), A = s_o sin theta_h, B = cos_o mu
            A, B = s_o * np.sqrt(1.0 - mu * mu), cos_o * mu
            if B >= A:
                ring = 2.0 * np.pi * B
            elif B <= -A:
                ring = 0.0
            else:
                phi0 = np.arccos(-B / A)
                ring = 2.0 * (A * np.sin(phi0) + B * phi0)
            return ring * D(mu)

        value = integrate.quad(visible, -1.0, 1.0, points=[-s_o, 0.0, s_o], epsabs=1e-12,
                               epsrel=1e-12, limit=400)[0]
        sigma = np.sqrt(s_o * s_o + (r * cos_o) ** 2)
        assert value == pytest.approx(sigma, rel=QUADRATURE), cos_o


def test_zero_roughness_is_the_limit():
    """D -> 0 off the horizon as r -> 0 (D <= r^3 / (pi h_z^4)): r = 0 is f = 0, no sample
    succeeds, every albedo is 0."""
    rng = np.random.default_rng(2)
    wo, wi = _upper(rng, 500), _upper(rng, 500)
    h = (wo + wi) / np.linalg.norm(wo + wi, axis=-1, keepdims=True)
    for r in (1e-2, 1e-4, 1e-8):
        assert np.all(_D(r, h) <= r**3 / (np.pi * h[:, 2] ** 4) * (1 + EXACT))
    lobe = Sheen(1.0, 0.0)
    assert not np.any(lobe.eval(wo, wi)) and not np.any(lobe.pdf(wo, wi))
    s = lobe.sample(wo, rng.random((500, 3)))
    assert not np.any(s.pdf) and not np.any(s.weight) and not np.any(s.flags)
    for method in ("table", "quadrature", "mc"):
        assert not np.any(lobe.albedo(wo[:4], method=method, n_samples=100))


# -- reciprocity, sampling ----------------------------------------------------------------------
@settings(max_examples=80, deadline=None)
@given(r=vs.roughness(), pair=vs.direction_pairs("any"), c=st.floats(0.0, 4.0),
       p=st.floats(0.01, 10.0))
def test_reciprocity(r, pair, c, p):
    lobe = Sheen((0.8, 0.4, 0.1), r, c, p)
    result = checks.reciprocity_error(lobe, *pair, rtol=RECIPROCITY)
    assert result.passed, result


CHI2 = [(r, c) for r in (0.1, 0.5, 1.0) for c in (0.5, 0.15, 0.02)]


@pytest.mark.parametrize(("r", "cos_theta"), CHI2)
def test_chi2(r, cos_theta):
    """Visible-normal sampling against the pdf D(h) / (4 sigma(wo)); samples below the
    horizon fail and form the chi-square test's extra bin."""
    lobe = Sheen((1.0, 0.6, 0.3), r)
    result = chi2_test(lobe, _wo(cos_theta), n_samples=500_000, seed=CHI2.index((r, cos_theta)),
                       alpha=CHI2_ALPHA, n_tests=len(CHI2))
    assert result.passed, str(result)
    assert result.n_histogram > 2000 and result.n_failed > 0


@pytest.mark.parametrize(("r", "cos_theta"), CHI2)
def test_weight_consistency(r, cos_theta):
    result = checks.weight_consistency(Sheen((1.0, 0.6, 0.3), r), _wo(cos_theta), 20_000,
                                       seed=1, rtol=WEIGHT)
    assert result.passed, str(result)


@settings(max_examples=80, deadline=None)
@given(r=vs.roughness(), wo=vs.directions("upper"), u=vs.uniform_triples())
def test_weight_consistency_at_edge_uniforms(r, wo, u):
    result = checks.weight_consistency(Sheen(0.7, r), wo, u=u[None], rtol=WEIGHT)
    assert result.passed, str(result)


def test_weight_is_the_closed_form():
    """weight = c a G sigma(wo) / cos theta_o (eqs. 17-18) for every successful sample."""
    rng = np.random.default_rng(3)
    r, wo = 0.4, _upper(rng, 20_000, min_z=1e-2)
    s = Sheen(0.5, r, c=2.0).sample(wo, rng.random((20_000, 3)))
    ok = s.pdf > 0
    wo, wi = wo[ok], s.wi[ok]

    def sigma(w):
        return np.sqrt(w[:, 0] ** 2 + w[:, 1] ** 2 + (r * w[:, 2]) ** 2)

    L = sigma(wi) / wi[:, 2] + sigma(wo) / wo[:, 2]
    G = (1.0 - np.exp(-L)) / L
    np.testing.assert_allclose(s.weight[ok, 1], 2.0 * 0.5 * G * sigma(wo) / wo[:, 2],
                               rtol=1e-12)
    assert ok.mean() > 0.1


# -- albedo --------------------------------------------------------------------------------------
def _r1_albedo(mu, p=1.0):
    """E(mu, r = 1) for c a = 1: D = 1 / pi and sigma = 1 reduce eq. 15 to
    (1/2) int_0^1 z (1 - exp(-p (1/z + 1/mu))) / (mu + z) dz."""
    def f(z):
        return z * -np.expm1(-p * (1.0 / z + 1.0 / mu)) / (mu + z)

    return 0.5 * integrate.quad(f, 0.0, 1.0, epsabs=1e-13, epsrel=1e-13, limit=200)[0]


@pytest.mark.parametrize("p", [1.0, 0.3])
def test_albedo_at_roughness_one_is_a_1d_integral(p):
    mu = np.array([1.0, 0.5, 0.1, 0.01])
    expected = np.array([_r1_albedo(m, p) for m in mu])
    np.testing.assert_allclose(sheen_energy(mu, 1.0, p)[0], expected, atol=1e-12)
    wo = np.stack([_wo(m) for m in mu])
    np.testing.assert_allclose(Sheen(1.0, 1.0, c=1.0, p=p).albedo(wo)[:, 0], expected,
                               atol=QUADRATURE)


def test_grazing_albedo_is_c_over_2():
    """As cos theta_o -> 0, G / cos theta_o -> 1 / sigma(wo) and the albedo becomes
    int_{h_z > 0} <wo, h>_+ D(h) dh / sigma(wo) = 1/2 for every r > 0 and p (docs/sheen.md)."""
    r = np.array([1e-3, 0.05, 0.3, 1.0])
    np.testing.assert_allclose(sheen_energy(0.0, r)[0], 0.5, atol=1e-12)
    np.testing.assert_allclose(sheen_energy(0.0, r, p=3.0)[0], 0.5, atol=1e-12)
    table = tables.get("sheen_albedo")
    np.testing.assert_allclose(table.values[0, 1:, 0], 0.5, atol=1e-12)
    wo = _wo(1e-7)
    for rr in (0.05, 1.0):
        assert Sheen(1.0, rr).albedo(wo)[0] == pytest.approx(1.0, abs=1e-4)


def test_table_nodes_are_the_node_quadrature():
    table = tables.get("sheen_albedo")
    mu, r = (a.nodes() for a in table.spec.axes)
    assert r[0] == 0.0 and np.all(table.values[1:, 0, 0] == 0.0)  # r = 0: f = 0
    rng = np.random.default_rng(4)
    i, j = rng.integers(0, len(mu), 8), rng.integers(1, len(r), 8)
    np.testing.assert_allclose(table.values[i, j, 0], sheen_energy(mu[i], r[j])[0],
                               atol=1e-12)


def test_table_interpolation_error():
    """The lookup (through the similarity below R_SIMILAR) against fresh quadrature at random
    off-node points, a third of them in the small (mu, r) corner."""
    rng = np.random.default_rng(5)
    u = rng.random((2, 300))
    u[:, :100] = u[:, :100] ** 4
    mu, r = u
    wo = np.stack([np.sqrt(1.0 - mu * mu), np.zeros_like(mu), mu], -1)
    err = np.abs(Sheen(1.0, r, c=1.0).albedo(wo, "table")[:, 0] - sheen_energy(mu, r)[0])
    assert err[mu >= 1e-4].max() <= TABLE
    assert err.max() <= TABLE_GRAZING
    assert np.any(r < R_SIMILAR)


@pytest.mark.parametrize("r", [0.05, 0.3, 1.0])
def test_albedo_methods_agree(r):
    """Table, the library's direction-space quadrature, this module's node quadrature and
    Monte Carlo, for a tinted sheen with c = 2."""
    a = np.array([0.9, 0.5, 0.2])
    lobe = Sheen(a, r)
    mu = np.array([1.0, 0.5, 0.1, 0.02])
    wo = np.stack([_wo(m) for m in mu])
    node = 2.0 * a * sheen_energy(mu, r)[0][:, None]
    quad = lobe.albedo(wo)
    np.testing.assert_allclose(quad, node, atol=QUADRATURE)
    np.testing.assert_allclose(lobe.albedo(wo, "table"), node, atol=2.0 * TABLE)
    mc, err = lobe.albedo(wo, "mc", n_samples=200_000, rng=6, return_error=True)
    assert np.all(np.abs(mc - quad) <= MC_SIGMAS * err + 1e-12)


def test_table_method_needs_p_one():
    with pytest.raises(ValueError, match="p = 1"):
        Sheen(1.0, 0.5, p=2.0).albedo(_wo(0.5), "table")


def test_energy_claim_of_c_2():
    """[Kutz2021, §6]: with c = 2 the BRDF is still energy-conserving. Every table row is
    non-increasing in mu at the nodes (between them, small roughnesses have a shallow minimum
    near normal incidence, docs/sheen_measured.md), and no node exceeds the grazing limit
    c/2 = 1: the claim holds with no margin at grazing. Spot checks by both quadratures."""
    table = tables.get("sheen_albedo")
    E = table.values[..., 0]
    assert np.all(np.diff(E[:, 1:], axis=0) <= 1e-12)
    assert 2.0 * E.max() <= 1.0 + 1e-12
    mu = np.array([1e-6, 1e-4, 1e-2, 0.2])
    for r in (0.01, 0.2, 0.6, 1.0):
        assert np.all(2.0 * sheen_energy(mu, r)[0] < 1.0)
        assert np.all(Sheen(1.0, r).albedo(np.stack([_wo(m) for m in mu]))[:, 0] < 1.0)


# -- broadcasting, extremes, bad input ----------------------------------------------------------
def test_broadcasting_texture():
    rng = np.random.default_rng(7)
    color = rng.random((2, 3, 3))
    r = np.array([[0.0, 0.1, 0.5], [1.0, 1e-6, 0.3]])
    lobe = Sheen(color, r)
    wo, wi = _upper(rng, 6).reshape(2, 3, 3), _upper(rng, 6).reshape(2, 3, 3)
    u = rng.random((2, 3, 3))
    f, pdf, s, E = lobe.eval(wo, wi), lobe.pdf(wo, wi), lobe.sample(wo, u), lobe.albedo(wo, "table")
    assert f.shape == (2, 3, 3) and pdf.shape == (2, 3) and s.weight.shape == (2, 3, 3)
    for i in range(2):
        for j in range(3):
            one = Sheen(color[i, j], r[i, j])
            np.testing.assert_array_equal(f[i, j], one.eval(wo[i, j], wi[i, j]))
            np.testing.assert_array_equal(pdf[i, j], one.pdf(wo[i, j], wi[i, j]))
            np.testing.assert_array_equal(s.wi[i, j], one.sample(wo[i, j], u[i, j]).wi)
            np.testing.assert_allclose(E[i, j], one.albedo(wo[i, j], "table"), rtol=1e-14)
    assert Sheen(0.5, 0.3).eval(wo[0, 0], wi[0, 0]).shape == (3,)


def test_extremes_are_finite():
    rng = np.random.default_rng(8)
    w = rng.normal(size=(2, 400, 3))
    wo, wi = w / np.linalg.norm(w, axis=-1, keepdims=True)
    edge = np.array([[1.0, 0.0, 0.0], [0.6, 0.8, 0.0], [np.sqrt(1 - 1e-24), 0.0, 1e-12],
                     [0.0, 0.0, 1.0], [-np.sqrt(1 - 1e-24), 0.0, 1e-12], [0.0, 0.0, -1.0]])
    wo = np.concatenate([wo, edge, edge, edge])
    wi = np.concatenate([wi, edge, edge[::-1], np.roll(edge, 1, axis=0)])
    for r in (0.0, 5e-324, 2.2e-311, 1e-300, 1e-160, 1e-12, 1e-6, 1.0):  # subnormals included
        for color, c in ((0.0, 2.0), (1.0, 2.0), (1.0, 0.0)):
            lobe = Sheen(color, r, c)
            s = lobe.sample(wo, rng.random((len(wo), 3)))
            values = (lobe.eval(wo, wi), lobe.pdf(wo, wi), s.weight, s.pdf,
                      lobe.albedo(wo, "table"))
            for v in values:
                assert np.all(np.isfinite(v)) and np.all(v >= 0.0), (r, color, c)
            assert np.all(np.isfinite(s.wi))
    below = np.array([0.6, 0.0, -0.8])
    lobe = Sheen(1.0, 0.5)
    assert not np.any(lobe.eval(below, wi)) and not np.any(lobe.pdf(wi, below))


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"roughness": 1.5}, "roughness"), ({"roughness": -0.1}, "roughness"),
    ({"roughness": np.nan}, "roughness"), ({"color": -0.1}, "color"),
    ({"color": (0.1, 0.2)}, "color"), ({"c": -1.0}, "c ="), ({"p": 0.0}, "p ="),
    ({"roughness": np.zeros(2), "color": np.ones((3, 3))}, "broadcast")])
def test_bad_input_is_named(kwargs, name):
    with pytest.raises(ValueError, match=name):
        Sheen(**{"color": 1.0, "roughness": 0.5, **kwargs})
