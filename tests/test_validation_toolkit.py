"""The validation toolkit can fail as well as pass.

Each check runs on small toy lobes defined here, with known answers: a correct lobe passes,
and the same lobe with one planted bug (a sampler drawing cos^1.1 while the pdf says cos, a
wrong branch probability, a weight 1 % off, a NaN, a sample below the horizon, a
non-reciprocal value, a missing eta^2) fails with the figure that names the bug.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adobe_bsdf.bsdf import BSDFSample, Flags, Lobe
from adobe_bsdf.validation import (
    SphereGrid,
    chi2_test,
    classify_samples,
    furnace,
    integrate_cells,
    mc_albedo_consistency,
    pdf_integral,
    reciprocity_error,
    sidak_alpha,
    suggest_grid,
    weight_consistency,
)
from adobe_bsdf.validation import strategies as bst
from adobe_bsdf.validation.chi2 import _pooled_statistic

WO = np.array([0.3, 0.2, np.sqrt(1.0 - 0.13)])
TILTED = np.array([0.5, 0.0, np.sqrt(0.75)])


# -- toy lobes -------------------------------------------------------------------------------
def _frame(axis):
    """Rows: two tangents and the unit ``axis``."""
    axis = np.asarray(axis, dtype=np.float64) / np.linalg.norm(axis)
    helper = np.array([0.0, 0.0, 1.0]) if abs(axis[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    e1 = helper - (helper @ axis) * axis
    e1 /= np.linalg.norm(e1)
    return np.stack([e1, np.cross(axis, e1), axis])


def _rgb(x):
    return np.repeat(np.asarray(x)[..., None], 3, axis=-1)


class PowerCosine(Lobe):
    """pdf = (n + 1) / (2 pi) cos^n about ``axis``; f = pdf / |cos theta_i|, so every weight is 1.

    ``sampled_exponent`` plants a bug: the sampler then draws cos^m while the pdf says cos^n.
    """

    flags = Flags.REFLECTION | Flags.GLOSSY

    def __init__(self, exponent=1.0, axis=(0.0, 0.0, 1.0), sampled_exponent=None):
        self.n = float(exponent)
        self.m = self.n if sampled_exponent is None else float(sampled_exponent)
        self.frame = _frame(axis)

    def _pdf(self, wo, wi):
        c = wi @ self.frame[2]
        return np.where(c > 0, (self.n + 1) / (2 * np.pi) * np.maximum(c, 0.0) ** self.n, 0.0)

    def _eval(self, wo, wi):
        cos_i = np.abs(wi[..., 2])
        safe = np.where(cos_i > 0, cos_i, 1.0)
        return _rgb(np.where(cos_i > 0, self._pdf(wo, wi) / safe, 0.0))

    def _direction(self, u1, u2):
        with np.errstate(divide="ignore"):
            one_minus_z = -np.expm1(np.log(u1) / (self.m + 1))
        z = 1.0 - one_minus_z
        s = np.sqrt(one_minus_z * (1.0 + z))
        phi = 2 * np.pi * u2
        e1, e2, a = self.frame
        return ((s * np.cos(phi))[..., None] * e1 + (s * np.sin(phi))[..., None] * e2
                + z[..., None] * a)

    def _sample(self, wo, u):
        wi = self._direction(u[..., 1], u[..., 2])
        pdf = self._pdf(wo, wi)
        weight = _rgb((pdf > 0).astype(np.float64))
        return BSDFSample(wi, weight, pdf, np.full(pdf.shape, int(self.flags)))


class DeltaMix(Lobe):
    """Mirror reflection (delta) with probability ``p_delta``, else cosine-weighted diffuse.

    ``p_claimed`` plants a bug: the pdf then assumes that delta probability instead.
    """

    flags = Flags.REFLECTION | Flags.DIFFUSE | Flags.DELTA

    def __init__(self, p_delta=0.3, p_claimed=None):
        self.p = p_delta
        self.q = p_delta if p_claimed is None else p_claimed

    def _pdf(self, wo, wi):
        return (1 - self.q) * np.maximum(wi[..., 2], 0.0) / np.pi

    def _eval(self, wo, wi):
        return _rgb(np.where(wi[..., 2] > 0, (1 - self.q) / np.pi, 0.0))

    def _sample(self, wo, u):
        delta = u[..., 0] < self.p
        r, phi = np.sqrt(1 - u[..., 1]), 2 * np.pi * u[..., 2]
        diffuse = np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(u[..., 1])], axis=-1)
        mirror = wo * np.array([-1.0, -1.0, 1.0])
        wi = np.where(delta[..., None], mirror, diffuse)
        pdf = np.where(delta, self.p, self._pdf(wo, wi))
        weight = _rgb((pdf > 0).astype(np.float64))
        flags = np.where(delta, int(Flags.DELTA | Flags.REFLECTION),
                         int(Flags.DIFFUSE | Flags.REFLECTION))
        return BSDFSample(wi, weight, pdf, flags)


class Clipped(PowerCosine):
    """Cosine lobe about a tilted axis whose samples below the horizon fail (as GGX's can).

    ``renormalised`` plants a bug: the pdf is divided by the surviving mass, so it integrates
    to 1 although some samples fail.
    """

    def __init__(self, axis, renormalised=False):
        super().__init__(1.0, axis)
        self.scale = 1.0 / (0.5 + 0.5 * self.frame[2, 2]) if renormalised else 1.0

    def _pdf(self, wo, wi):
        return np.where(wi[..., 2] > 0, self.scale * super()._pdf(wo, wi), 0.0)


class UniformHemisphere(Lobe):
    """Lambertian white lobe sampled uniformly (weight 2 cos); ``eval_scale`` plants a bug in
    ``eval`` (scaled by it) that the sample weights do not share."""

    flags = Flags.REFLECTION | Flags.DIFFUSE

    def __init__(self, eval_scale=1.0):
        self.scale = eval_scale

    def _pdf(self, wo, wi):
        return np.where(wi[..., 2] > 0, 1 / (2 * np.pi), 0.0)

    def _eval(self, wo, wi):
        return _rgb(np.where(wi[..., 2] > 0, self.scale / np.pi, 0.0))

    def _sample(self, wo, u):
        z, phi = u[..., 1], 2 * np.pi * u[..., 2]
        r = np.sqrt(1 - z * z)
        wi = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)
        pdf = self._pdf(wo, wi)
        return BSDFSample(wi, _rgb(2 * z * (pdf > 0)), pdf, np.full(pdf.shape, int(self.flags)))


class Interface(Lobe):
    """f(wo, wi) = eta_o^2 (1 + |cos o cos i|) / pi on both sides of an interface ``eta``.

    Generalized-reciprocal by construction; ``radiance_scaled=False`` drops the eta_o^2.
    """

    def __init__(self, eta, radiance_scaled=True):
        self.eta = eta
        self.scaled = radiance_scaled

    def _eval(self, wo, wi):
        eta_o = np.where(wo[..., 2] >= 0, 1.0, self.eta) if self.scaled else 1.0
        return _rgb(eta_o**2 * (1 + np.abs(wo[..., 2] * wi[..., 2])) / np.pi)


class Skewed(Lobe):
    """f(wo, wi) = (1 + wi.x / 2) / pi: not reciprocal."""

    def _eval(self, wo, wi):
        return _rgb((1 + 0.5 * wi[..., 0]) / np.pi * (wo[..., 2] * wi[..., 2] > 0))


class Planted(PowerCosine):
    """Cosine lobe with a planted sampling-record bug, chosen by name."""

    def __init__(self, bug):
        super().__init__(1.0)
        self.bug = bug

    def _sample(self, wo, u):
        s = super()._sample(wo, u)
        hit = u[..., 0] < 0.01
        if self.bug == "nan weight":
            return s._replace(weight=np.where(hit[..., None], np.nan, s.weight))
        if self.bug == "below horizon":
            return s._replace(wi=np.where(hit[..., None], s.wi * [1, 1, -1], s.wi))
        if self.bug == "weight 1% high":
            return s._replace(weight=s.weight * 1.01)
        return s._replace(flags=np.full(s.pdf.shape, int(Flags.TRANSMISSION | Flags.GLOSSY)))


# -- chi-square ------------------------------------------------------------------------------
def test_chi2_accepts_correct_cosine_sampler():
    result = chi2_test(PowerCosine(1.0), WO, n_samples=1_000_000)
    assert result.passed, str(result)
    assert result.dof > 4000
    assert result.integration_converged
    assert result.pdf_mass == pytest.approx(1.0, abs=1e-9)
    assert result.observed.shape == result.expected.shape == (64, 128)
    assert result.observed.sum() == result.n_histogram == 1_000_000
    assert result.expected.sum() == pytest.approx(1_000_000, rel=1e-9)
    assert result.theta_edges.shape == (65,) and result.phi_edges.shape == (129,)


def test_chi2_rejects_cos_1_1_sampler():
    result = chi2_test(PowerCosine(1.0, sampled_exponent=1.1), WO, n_samples=1_000_000)
    assert not result.passed
    assert result.p_value < 1e-6
    assert "do not follow the pdf" in result.message


def test_chi2_expected_counts_match_closed_form():
    """Cell integrals of cos / pi against (sin^2 theta1 - sin^2 theta0) dphi / (2 pi)."""
    result = chi2_test(PowerCosine(1.0), WO, n_samples=100_000, n_theta=16, n_phi=8)
    s2 = np.sin(np.minimum(result.theta_edges, np.pi / 2)) ** 2
    exact = np.outer(np.diff(s2), np.diff(result.phi_edges) / (2 * np.pi)) * 100_000
    np.testing.assert_allclose(result.expected, exact, rtol=1e-9, atol=1e-9)


def test_chi2_narrow_lobe_with_focused_grid():
    """A cos^10000 lobe (0.6 degrees wide) spreads over many cells about its axis."""
    grid = suggest_grid(1e-2, TILTED)
    assert grid["warp"] > 2.5
    good = chi2_test(PowerCosine(1e4, TILTED), WO, n_samples=1_000_000, **grid)
    assert good.passed, str(good)
    assert good.dof > 1000
    bad = chi2_test(PowerCosine(1e4, TILTED, sampled_exponent=1.05e4), WO,
                    n_samples=1_000_000, **grid)
    assert bad.p_value < 1e-6, str(bad)


def test_chi2_delta_branch_is_excluded_and_its_probability_tested():
    good = chi2_test(DeltaMix(0.3), WO, n_samples=1_000_000)
    assert good.passed, str(good)
    assert good.delta_fraction == pytest.approx(0.3, abs=3e-3)
    assert good.pdf_mass == pytest.approx(0.7, abs=1e-9)
    bad = chi2_test(DeltaMix(0.3, p_claimed=0.25), WO, n_samples=1_000_000)
    assert bad.p_value < 1e-6, str(bad)


@pytest.mark.parametrize("axis", [None, TILTED])
def test_chi2_failed_samples_and_horizon(axis):
    """Samples failing below the horizon are counted; the pdf must integrate to what survives.

    The pdf jumps to 0 at the horizon; with a tilted pole the horizon crosses cells.
    """
    lobe_axis = np.array([0.8, 0.0, 0.6])
    good = chi2_test(Clipped(lobe_axis), WO, n_samples=200_000, axis=axis)
    assert good.passed, str(good)
    assert good.failed_fraction == pytest.approx(0.2, abs=5e-3)
    assert abs(good.pdf_mass - 0.8) <= good.integration_error  # the estimate is honest
    bad = chi2_test(Clipped(lobe_axis, renormalised=True), WO, n_samples=200_000, axis=axis)
    assert bad.p_value < 1e-6, str(bad)


@pytest.mark.parametrize(("bug", "field"), [("nan weight", "n_invalid"),
                                            ("below horizon", "n_zero_hits")])
def test_chi2_hard_failures(bug, field):
    result = chi2_test(Planted(bug), WO, n_samples=100_000)
    assert not result.passed
    assert result.p_value == 0.0
    assert getattr(result, field) > 0, str(result)


def test_chi2_too_coarse_grid_fails_rather_than_passes():
    result = chi2_test(PowerCosine(1e4, TILTED), WO, n_samples=1000, n_theta=2, n_phi=1)
    assert not result.passed
    assert "dof < 1" in result.message


def test_chi2_bad_arguments():
    lobe = PowerCosine()
    for kwargs, name in [({"n_samples": 0}, "n_samples"), ({"warp": 0.5}, "warp"),
                         ({"alpha": 1.5}, "alpha"), ({"n_tests": 0}, "n_tests"),
                         ({"axis": (0, 0, 0)}, "axis"), ({"n_theta": 1}, "n_theta"),
                         ({"integration_tolerance": 0.0}, "integration_tolerance")]:
        with pytest.raises(ValueError, match=name):
            chi2_test(lobe, WO, **kwargs)
    with pytest.raises(ValueError, match="wo"):
        chi2_test(lobe, [0.0, 0.0, 2.0])
    with pytest.raises(ValueError, match="width"):
        suggest_grid(0.0)


def test_sidak_alpha():
    assert sidak_alpha(0.01, 1) == pytest.approx(0.01, rel=1e-14)
    assert sidak_alpha(0.01, 100) == pytest.approx(1 - 0.99 ** (1 / 100), rel=1e-12)


def test_pooling():
    statistic, dof, n_pooled = _pooled_statistic(np.array([0, 3, 10, 25]),
                                                 np.array([1.0, 2.0, 12.0, 25.0]))
    # the pool (3 observed, 3 expected) is below 5, so it joins the smallest regular bin
    assert (dof, n_pooled) == (1, 2)
    assert statistic == pytest.approx((13 - 15) ** 2 / 15)


# -- the grid and the cubature ---------------------------------------------------------------
def test_grid_locates_cell_centres_and_splits_at_the_horizon():
    grid = SphereGrid(9, 7, axis=(0, 0, -1), warp=2.5)
    lo, hi = grid.cell_bounds()
    centre = 0.5 * (lo + hi)
    cells = grid.locate(grid.direction(centre[:, 0], centre[:, 1]))
    np.testing.assert_array_equal(cells, np.arange(63))
    assert grid.theta_edges[grid.horizon_edge] == pytest.approx(np.pi / 2, abs=1e-15)
    ring = grid.locate(np.array([[1.0, 0.0, 1e-300], [1.0, 0.0, -1e-300]])) // 7
    # the pole is -z: the lower hemisphere lies before the horizon edge
    assert ring[1] == grid.horizon_edge - 1 and ring[0] == grid.horizon_edge


def test_integrate_cells_is_exact_for_degree_7():
    lo = np.array([[0.0, 0.0], [0.5, -1.0]])
    hi = np.array([[0.5, 1.0], [2.0, 0.25]])

    def f(x):
        return x[:, 0] ** 3 * x[:, 1] ** 4 + x[:, 0] ** 7 - 2 * x[:, 1] ** 5

    def exact(a, b):
        return ((b[0] ** 4 - a[0] ** 4) / 4 * (b[1] ** 5 - a[1] ** 5) / 5
                + (b[0] ** 8 - a[0] ** 8) / 8 * (b[1] - a[1])
                - 2 * (b[0] - a[0]) * (b[1] ** 6 - a[1] ** 6) / 6)

    result = integrate_cells(f, lo, hi, lambda v: 1e-12 * (1 + np.abs(v)))
    np.testing.assert_allclose(result.value, [exact(lo[0], hi[0]), exact(lo[1], hi[1])],
                               rtol=1e-13)
    assert result.converged


def test_integrate_cells_vector_integrand_refines_for_the_worst_channel():
    lo, hi = np.zeros((2, 2)), np.ones((2, 2))

    def f(x):  # channel 0 is exact for the rule, channel 1 has a kink at x = 0.3
        return np.stack([x[:, 0] ** 2, np.abs(x[:, 0] - 0.3)], axis=-1)

    result = integrate_cells(f, lo, hi, lambda v: np.array([1e-12, 1e-8]))
    assert result.value.shape == result.error.shape == (2, 2) and result.converged
    np.testing.assert_allclose(result.value, [[1 / 3, 0.29]] * 2, atol=1e-8)
    assert np.all(result.error[:, 1] <= 1e-8)


def test_integrate_cells_guard_points_find_support_between_nodes():
    """A bump of radius 0.004 inside [0, 1]^2 touches none of the 17 nodes."""
    centre, radius = np.array([0.305, 0.305]), 0.004

    def bump(x):
        r2 = np.sum((x - centre) ** 2, axis=-1) / radius**2
        return np.where(r2 < 1, (1 - r2) ** 2, 0.0)

    lo, hi = np.zeros((1, 2)), np.ones((1, 2))
    blind = integrate_cells(bump, lo, hi, lambda v: 1e-9 + 0 * v)
    assert blind.value[0] == 0.0
    guarded = integrate_cells(bump, lo, hi, lambda v: 1e-9 + 0 * v, points=centre[None],
                              point_cells=np.array([0]))
    assert guarded.value[0] == pytest.approx(np.pi * radius**2 / 3, abs=1e-8)
    assert guarded.converged


def test_integrate_cells_reports_an_exhausted_budget():
    def step(x):
        return (x[:, 0] > 0.3).astype(np.float64)

    lo, hi = np.zeros((4, 2)), np.ones((4, 2))
    starved = integrate_cells(step, lo, hi, lambda v: 1e-6 + 0 * v, max_evals=4 * 17 + 40)
    assert not starved.converged and starved.n_evals == 4 * 17 + 34
    full = integrate_cells(step, lo, hi, lambda v: 1e-6 + 0 * v)
    assert full.converged
    np.testing.assert_allclose(full.value, 0.7, atol=1e-6)


# -- consistency checks ----------------------------------------------------------------------
def test_pdf_integral():
    result = pdf_integral(PowerCosine(1.0), WO)
    assert result.passed, str(result)
    assert abs(result.value - 1.0) < 1e-6
    narrow = pdf_integral(PowerCosine(1e4, TILTED), WO, **suggest_grid(1e-2, TILTED))
    assert narrow.passed, str(narrow)
    assert pdf_integral(DeltaMix(0.3), WO, expected=0.7).passed
    assert not pdf_integral(DeltaMix(0.3, p_claimed=0.25), WO, expected=0.7).passed
    estimated = pdf_integral(Clipped(np.array([0.8, 0.0, 0.6])), WO, expected=None)
    assert estimated.passed and estimated.value == pytest.approx(0.8, abs=1e-6)
    with pytest.raises(ValueError, match="expected"):
        pdf_integral(PowerCosine(), WO, expected=1.5)


def test_reciprocity():
    rng = np.random.default_rng(3)
    wo, wi = rng.normal(size=(2, 500, 3))
    wo /= np.linalg.norm(wo, axis=-1, keepdims=True)
    wi /= np.linalg.norm(wi, axis=-1, keepdims=True)
    good = reciprocity_error(Interface(1.5), wo, wi)
    assert good.passed and good.max_error < 1e-15, str(good)
    assert good.n_transmission > 100
    missing_eta2 = reciprocity_error(Interface(1.5, radiance_scaled=False), wo, wi)
    assert missing_eta2.max_error == pytest.approx(1 - 1 / 1.5**2, rel=1e-12)
    assert not missing_eta2.passed
    assert reciprocity_error(Interface(1.5, radiance_scaled=False), wo, wi, 1.0, 1.0).passed
    skewed = reciprocity_error(Skewed(), wo, wi)
    assert not skewed.passed and skewed.max_error > 0.1
    assert skewed.errors.shape == (500,)
    with pytest.raises(ValueError, match="eta_o"):
        reciprocity_error(Skewed(), wo, wi, eta_o=1.0)


@settings(max_examples=60, deadline=None)
@given(pair=bst.direction_pairs(), eta=bst.iors())
def test_reciprocity_property(pair, eta):
    assert reciprocity_error(Interface(eta), *pair).passed


def test_weight_consistency():
    good = weight_consistency(DeltaMix(0.3), np.stack([WO, TILTED]), n_samples=20_000)
    assert good.passed, str(good)
    assert good.n_delta > 0 and good.n_checked > 0
    high = weight_consistency(Planted("weight 1% high"), WO, n_samples=1000)
    assert not high.passed and high.max_weight_error == pytest.approx(0.01 / 1.01)
    flags = weight_consistency(Planted("flags"), WO, n_samples=1000)
    assert not flags.passed and flags.n_flag_mismatch == flags.n_checked
    nan = weight_consistency(Planted("nan weight"), WO, n_samples=1000)
    assert not nan.passed and nan.n_invalid > 0


@settings(max_examples=60, deadline=None)
@given(wo=bst.directions("upper"), u=bst.uniform_triples())
def test_weight_consistency_edge_uniforms(wo, u):
    result = weight_consistency(PowerCosine(3.0), wo, u=u)
    assert result.passed, str(result)


def test_classify_samples():
    draws = classify_samples(DeltaMix(0.3), WO, [[0.1, 0.5, 0.5], [0.9, 0.5, 0.5],
                                                 [0.9, 0.0, 0.5]])
    np.testing.assert_array_equal(draws.delta, [True, False, False])
    np.testing.assert_array_equal(draws.failed, [False, False, True])
    np.testing.assert_array_equal(draws.live, [False, True, False])


def test_furnace():
    assert furnace(PowerCosine(4.0), WO, 1.0).passed
    grey = furnace(UniformHemisphere(0.9), WO, 1.0)
    assert not grey.passed and grey.abs_error == pytest.approx(0.1, abs=1e-9)
    mc = furnace(UniformHemisphere(), WO, 1.0, method="mc", tol=0.01, n_samples=10_000)
    assert mc.passed and mc.estimated_error > 0
    with pytest.raises(ValueError, match="method"):
        furnace(PowerCosine(), WO, 1.0, method="exact")


def test_mc_albedo_consistency():
    good = mc_albedo_consistency(UniformHemisphere(), np.stack([WO, TILTED]))
    assert good.passed, str(good)
    bad = mc_albedo_consistency(UniformHemisphere(1.02), WO)
    assert not bad.passed and bad.max_z > 5


# -- strategies ------------------------------------------------------------------------------
@settings(max_examples=300, deadline=None)
@given(w=bst.directions(min_abs_cos=1e-8),
       up=bst.directions("upper", allow_horizon=True),
       down=bst.directions("lower"))
def test_directions_are_unit_and_on_their_side(w, up, down):
    for v in (w, up, down):
        assert v.shape == (3,) and abs(np.linalg.norm(v) - 1) <= 1e-12
    assert abs(w[2]) >= 1e-8 * (1 - 1e-12)
    assert up[2] >= 0 and down[2] < 0


@settings(max_examples=200, deadline=None)
@given(r=bst.direction_pairs("reflection"), t=bst.direction_pairs("transmission", side="upper"))
def test_direction_pairs(r, t):
    assert r[0][2] * r[1][2] > 0
    assert t[0][2] > 0 > t[1][2]


@settings(max_examples=200, deadline=None)
@given(a=bst.roughness(), ax=bst.alpha_pairs(1e-3, 0.5), eta=bst.iors(), u=bst.uniform_triples())
def test_parameter_strategies_stay_in_range(a, ax, eta, u):
    assert 0 <= a <= 1
    assert all(1e-3 <= v <= 0.5 for v in ax)
    assert 1 / 3 <= eta <= 3
    assert u.shape == (3,) and np.all((u >= 0) & (u < 1))


@pytest.mark.parametrize(("strategy", "condition"), [
    (bst.directions(), lambda w: w[2] == -1.0),
    (bst.directions("upper"), lambda w: w[2] < 1.0001e-8),
    (bst.directions(allow_horizon=True), lambda w: w[2] == 0.0),
    (bst.direction_pairs("reflection"), lambda p: np.array_equal(p[1], p[0] * [-1, -1, 1])),
    (bst.roughness(), lambda a: a == 0.0),
    (bst.roughness(), lambda a: a == 1.0),
    (bst.roughness(), lambda a: 0 < a <= 1e-6),
    (bst.alpha_pairs(), lambda p: p[0] != p[1]),
    (bst.iors(), lambda e: e == 1.0),
    (bst.iors(), lambda e: 1 < e <= 1 + 1e-6),
    (bst.iors(), lambda e: e == 1 / 2.4),
    (bst.uniform_triples(), lambda u: u[0] == np.nextafter(1.0, 0.0) and u[1] == 0.0),
])
def test_strategies_reach_edge_cases(strategy, condition):
    from hypothesis import find

    find(strategy, condition, settings=settings(max_examples=2000, database=None))


def test_strategies_bad_arguments():
    for make, name in [(lambda: bst.directions("left"), "hemisphere"),
                       (lambda: bst.directions(min_abs_cos=0.0), "min_abs_cos"),
                       (lambda: bst.direction_pairs("both"), "kind"),
                       (lambda: bst.roughness(0.5, 0.2), "max_value"),
                       (lambda: bst.iors(0.0), "min_value")]:
        with pytest.raises(ValueError, match=name):
            make()


def test_strategies_compose_with_hypothesis():
    assert isinstance(bst.directions(), st.SearchStrategy)
