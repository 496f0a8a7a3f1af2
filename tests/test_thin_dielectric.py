"""``ThinDielectric``: the thin-walled translucent sheet, smooth and rough, both sides.

Expected values come from an explicit sum of the bounces inside the sheet with the textbook
Fresnel equations written here, from ``fresnel.dielectric``, and from conservation (the
white furnace), never from the module under test."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import adobe_bsdf as ab
from adobe_bsdf.bsdf import Flags
from adobe_bsdf.lobes import ThinDielectric
from adobe_bsdf.lobes.thin_dielectric import SheetReflectance, SheetTransmittance
from adobe_bsdf.validation import checks
from adobe_bsdf.validation import strategies as vs
from tests.sampling_checks import assert_no_energy_gain, assert_sampling_matches
from tests.tolerances import EXACT, FURNACE_TABLE_DIELECTRIC, RECIPROCITY

#: bounces summed by the reference (each pass through the sheet and back)
BOUNCES = 200
#: one-pass transmittances of the reference grid: clear, coloured, opaque
TRANSMITTANCES = [(1.0, 1.0, 1.0), (0.9, 0.5, 0.1), (0.0, 0.0, 0.0)]
#: a coloured absorbing sheet
TINT = (0.9, 0.6, 0.3)


def _textbook_fresnel(c, eta):
    """Unpolarised reflectance at cos theta = c from the amplitudes r_s, r_p; 1 beyond the
    critical angle."""
    sin2_t = (1.0 - c * c) / (eta * eta)
    if sin2_t >= 1.0:
        return 1.0
    ct = np.sqrt(1.0 - sin2_t)
    r_s = (c - eta * ct) / (c + eta * ct)
    r_p = (eta * c - ct) / (eta * c + ct)
    return 0.5 * (r_s * r_s + r_p * r_p)


def _bounced(c, eta, A):
    """(R, T, energy left inside) of a smooth sheet after ``BOUNCES`` round trips, following
    the light: into the sheet, across, out of the far face or back, across, out of the near
    face or back again."""
    F = _textbook_fresnel(c, eta)
    sin2_t = (1.0 - c * c) / (eta * eta)
    ct = np.sqrt(max(1.0 - sin2_t, 0.0))
    tau = np.where(np.asarray(A) == 1.0, 1.0, np.asarray(A, dtype=float) ** (1.0 / ct)
                   if ct > 0 else 0.0)
    R, T = np.full(3, F), np.zeros(3)
    inside = np.full(3, 1.0 - F)
    for _ in range(BOUNCES):
        inside = inside * tau
        T = T + inside * (1.0 - F)
        inside = inside * F
        inside = inside * tau
        R = R + inside * (1.0 - F)
        inside = inside * F
    return R, T, inside


def _wo(cos_theta, azimuth=0.3):
    s = np.sqrt(max(1.0 - cos_theta * cos_theta, 0.0))
    return np.array([s * np.cos(azimuth), s * np.sin(azimuth), cos_theta])


GRID = [(c, eta, A) for c in (1.0, 0.99, 0.6, 0.3) for eta in (1 / 3, 0.7, 1.2, 1.5, 3.0)
        for A in TRANSMITTANCES]


@pytest.mark.parametrize(("c", "eta", "A"), GRID)
def test_smooth_sheet_matches_the_sum_of_bounces(c, eta, A):
    """R and T of the Fresnel models, and the smooth lobe's delta albedo R + T from either
    side, against 200 explicit bounces (to 1e-12)."""
    R, T, left = _bounced(c, eta, A)
    assert np.all(left < 1e-15)  # the reference has converged
    np.testing.assert_allclose(SheetReflectance(eta, A)(c), R, rtol=EXACT, atol=1e-15)
    np.testing.assert_allclose(SheetTransmittance(eta, A)(c), T, rtol=EXACT, atol=1e-15)
    np.testing.assert_allclose(SheetReflectance(eta, A)(-c), R, rtol=EXACT, atol=1e-15)
    sheet = ThinDielectric(eta, 0.0, transmittance=A)
    for side in (1.0, -1.0):
        wo = _wo(side * c)
        for method in ("quadrature", "table"):
            np.testing.assert_allclose(sheet.albedo(wo, method=method), R + T, rtol=EXACT,
                                       atol=1e-15)


@settings(max_examples=100, deadline=None)
@given(eta=vs.iors(), c=st.one_of(st.sampled_from([1.0, 1e-9, 5e-324, 0.0]),
                                  st.floats(0.0, 1.0)))
def test_opaque_sheet_reflects_as_one_face(eta, c):
    """A = 0: nothing crosses, R is the first face's Fresnel ``fresnel.dielectric``."""
    np.testing.assert_allclose(SheetReflectance(eta, 0.0)(c), ab.fresnel.dielectric(c, eta),
                               rtol=EXACT, atol=0.0)
    assert np.all(SheetTransmittance(eta, 0.0)(c) == 0.0)


_COS = st.one_of(st.sampled_from([1.0, 1e-9, 5e-324, 0.0, -5e-324, -0.5]),
                 st.floats(-1.0, 1.0))


@settings(max_examples=200, deadline=None)
@given(eta=vs.iors(), c=_COS)
def test_clear_sheet_keeps_all_energy(eta, c):
    """A = 1: R + T = 1 to 1e-12 at every angle, subnormal cosines included."""
    total = SheetReflectance(eta)(c) + SheetTransmittance(eta)(c)
    np.testing.assert_allclose(total, 1.0, rtol=0.0, atol=EXACT)


@settings(max_examples=200, deadline=None)
@given(eta=vs.iors(), c=_COS, A=st.tuples(*[st.floats(0.0, 1.0, exclude_max=True)] * 3))
def test_absorbing_sheet_loses_energy(eta, c, A):
    """A < 1: R, T in [0, 1] and R + T <= 1 (up to 2 ulps of rounding)."""
    R, T = SheetReflectance(eta, A)(c), SheetTransmittance(eta, A)(c)
    assert np.all(np.isfinite(R) & np.isfinite(T))
    assert np.all((R >= 0.0) & (T >= 0.0) & (R <= 1.0) & (T <= 1.0))
    assert np.all(R + T <= 1.0 + 4.5e-16)


def test_eta_one_is_a_straight_transmission():
    """No faces: every sample goes to -wo with weight tau = A^(1 / |cos|), eval is 0, the
    albedo is tau, at any roughness."""
    rng = np.random.default_rng(7)
    wo = ab.frame.normalize(rng.normal(size=(200, 3)))
    u = rng.random((200, 3))
    A = np.array(TINT)
    tau = A ** (1.0 / np.abs(wo[:, 2:]))
    for alpha in (0.0, 0.3, 1.0):
        sheet = ThinDielectric(1.0, alpha, transmittance=TINT)
        s = sheet.sample(wo, u)
        np.testing.assert_array_equal(s.wi, -wo)
        assert np.all(s.flags == int(Flags.TRANSMISSION | Flags.DELTA))
        np.testing.assert_allclose(s.weight, tau, rtol=EXACT)
        np.testing.assert_array_equal(sheet.eval(wo, -wo), 0.0)
        np.testing.assert_allclose(sheet.albedo(wo[:20]), tau[:20], rtol=EXACT)
        np.testing.assert_allclose(sheet.albedo(wo, method="table"), tau, rtol=EXACT)


def test_smooth_sampling_picks_by_luminance():
    """The smooth sheet reflects with probability lum(R) / (lum(R) + lum(T)), weight R / P,
    and transmits to -wo otherwise, weight T / (1 - P)."""
    c = 0.6
    R, T, _ = _bounced(c, 1.5, TINT)
    lum = ab.bsdf.LUMINANCE
    P = R @ lum / (R @ lum + T @ lum)
    sheet = ThinDielectric(1.5, 0.0, transmittance=TINT)
    for side in (1.0, -1.0):
        wo = _wo(side * c)
        u = np.array([[0.5 * P, 0.3, 0.7], [0.5 * (1.0 + P), 0.3, 0.7]])
        s = sheet.sample(wo, u)
        np.testing.assert_allclose(s.wi, [[-wo[0], -wo[1], wo[2]], -wo], rtol=EXACT)
        np.testing.assert_allclose(s.pdf, [P, 1.0 - P], rtol=EXACT)
        np.testing.assert_allclose(s.weight, [R / P, T / (1.0 - P)], rtol=EXACT)
        assert list(s.flags) == [int(Flags.REFLECTION | Flags.DELTA),
                                 int(Flags.TRANSMISSION | Flags.DELTA)]


ROUGH = [(alpha, eta) for alpha in (0.05, 0.3, 1.0) for eta in (1.1, 1.5, 2.4)]
FURNACE_COS = np.array([1.0, 0.5, 0.2, 0.05])


def _furnace_directions():
    wo = np.stack([_wo(c) for c in FURNACE_COS])
    return np.concatenate([wo, wo * np.array([1.0, 1.0, -1.0])])


@pytest.mark.parametrize(("alpha", "eta"), ROUGH)
def test_rough_clear_sheet_white_furnace(alpha, eta):
    """R + T = 1 within 2e-3 (the tables' accuracy) from both sides: direction-space
    quadrature of eval plus the delta branches."""
    E = ThinDielectric(eta, alpha).albedo(_furnace_directions(), tol=1e-5)
    np.testing.assert_allclose(E, 1.0, atol=FURNACE_TABLE_DIELECTRIC)


@pytest.mark.parametrize(("alpha", "eta"), ROUGH)
def test_rough_absorbing_sheet_gains_nothing(alpha, eta):
    """A < 1: the albedo stays below 1 + 1e-3 and below the clear sheet's."""
    wo = _furnace_directions()
    sheet = ThinDielectric(eta, alpha, transmittance=TINT)
    assert_no_energy_gain(sheet, wo, 1.0 + 1e-3, context=(alpha, eta))
    E, E_clear = sheet.albedo(wo, tol=1e-5), ThinDielectric(eta, alpha).albedo(wo, tol=1e-5)
    assert np.all(E <= E_clear + 1e-5)


@pytest.mark.parametrize("transmittance", [1.0, TINT])
@pytest.mark.parametrize(("alpha", "eta"), ROUGH)
def test_table_albedo_agrees_with_quadrature(alpha, eta, transmittance):
    """albedo(method="table") within the tables' dielectric accuracy (2e-3) of the
    quadrature, both sides, with a finite error estimate."""
    wo = _furnace_directions()
    sheet = ThinDielectric(eta, alpha, transmittance=transmittance)
    E_table, error = sheet.albedo(wo, method="table", return_error=True)
    np.testing.assert_allclose(E_table, sheet.albedo(wo, tol=1e-5),
                               atol=FURNACE_TABLE_DIELECTRIC)
    assert np.all(np.isfinite(error) & (error >= 0.0))


@pytest.mark.parametrize(("alpha", "eta"), ROUGH + [((0.7, 0.1), 0.8), (2.0, 1.5)])
def test_clear_sheet_table_albedo_is_one(alpha, eta):
    """The table albedo of a clear sheet is 1 to 1e-12 from both sides, grazing included:
    the single scattering's Fresnel lobes add up to the F = 1 lobe whose loss the
    multiple-scattering table restores."""
    alpha = alpha if isinstance(alpha, tuple) else (alpha,)
    c = np.array([1.0, 0.7, 0.3, 0.05, 1e-3])
    wo = np.concatenate([np.stack([_wo(x) for x in c]), np.stack([_wo(-x) for x in c])])
    E = ThinDielectric(eta, *alpha).albedo(wo, method="table")
    np.testing.assert_allclose(E, 1.0, rtol=0.0, atol=EXACT)


CHI2_CASES = [(alpha, c) for alpha in ((0.06, 0.03), (0.5, 0.5)) for c in (0.8, -0.35)]


@pytest.mark.parametrize(("alpha", "cos_theta"), CHI2_CASES)
def test_sampling_matches_pdf(alpha, cos_theta):
    """chi-square of sample against pdf (p above the Šidák-corrected 0.01), weights f|cos|/pdf
    to 1e-9, for a nearly smooth anisotropic and a rough coloured sheet, both sides."""
    sheet = ThinDielectric(1.5, *alpha, transmittance=TINT)
    assert_sampling_matches(sheet, cos_theta, 0.4, seed=CHI2_CASES.index((alpha, cos_theta)),
                            n_tests=len(CHI2_CASES))


@settings(max_examples=100, deadline=None)
@given(alpha=vs.alpha_pairs(), eta=vs.iors(), pair=vs.direction_pairs("any"),
       A=st.sampled_from(TRANSMITTANCES))
def test_reciprocity(alpha, eta, pair, A):
    """f(wo, wi) = f(wi, wo) to 1e-12 on one side and across the sheet (the same medium on
    both sides: no index scaling)."""
    result = checks.reciprocity_error(ThinDielectric(eta, *alpha, transmittance=A), *pair,
                                      rtol=RECIPROCITY)
    assert result.passed, result


@settings(max_examples=100, deadline=None)
@given(alpha=vs.alpha_pairs(), eta=vs.iors(), pair=vs.direction_pairs("any"))
def test_same_from_both_sides(alpha, eta, pair):
    """Mirroring both directions through the sheet changes nothing."""
    wo, wi = pair
    M = np.array([1.0, 1.0, -1.0])
    sheet = ThinDielectric(eta, *alpha, transmittance=TINT)
    np.testing.assert_array_equal(sheet.eval(wo * M, wi * M), sheet.eval(wo, wi))
    np.testing.assert_array_equal(sheet.pdf(wo * M, wi * M), sheet.pdf(wo, wi))


EXTREMES = [(1.5, 0.0, 0.0), (1.5, 1.0, 1.0), (1.5, 0.5, 0.0), (1.0, 1.0, 0.0),
            (1 / 3, 0.2, 0.2), (3.0, 2.0, 2.0), (1.0 + 1e-12, 0.3, 0.3)]


@pytest.mark.parametrize(("eta", "ax", "ay"), EXTREMES)
def test_extremes_are_finite(eta, ax, ay):
    """Roughness 0 and 1 (and the tables' 2), anisotropy 1, eta at 1 and near it, subnormal
    and horizon cosines: eval, pdf, samples and albedos finite and non-negative."""
    rng = np.random.default_rng(3)
    cos = np.array([5e-324, -5e-324, 1e-300, 1e-9, 0.0, 1.0, -1.0])
    s = np.sqrt(1.0 - cos * cos)
    wo = np.concatenate([np.stack([s, 0 * s, cos], -1),
                         ab.frame.normalize(rng.normal(size=(50, 3)))])
    wi = np.concatenate([wo[::-1], -wo[:7], wo[:7] * [-1.0, -1.0, 1.0]])[:len(wo)]
    u = np.concatenate([rng.random((len(wo) - 2, 3)), [[0.0, 0.0, 0.0],
                                                        [1 - 1e-16, 1 - 1e-16, 1 - 1e-16]]])
    for A in (1.0, TINT, 0.0):
        sheet = ThinDielectric(eta, ax, ay, transmittance=A)
        f, pdf = sheet.eval(wo, wi), sheet.pdf(wo, wi)
        sample = sheet.sample(wo, u)
        E = sheet.albedo(wo, method="table")
        for x in (f, pdf, sample.weight, sample.pdf, E):
            assert np.all(np.isfinite(x) & (x >= 0.0)), (A, x)
        assert np.all(E <= 1.0 + FURNACE_TABLE_DIELECTRIC)


def test_parameters_broadcast_as_a_texture():
    """Arrays of parameters evaluate elementwise, as the lobes built one by one."""
    rng = np.random.default_rng(5)
    wo, wi = ab.frame.normalize(rng.normal(size=(2, 4, 3)))
    eta, alpha = np.array([1.0, 1.3, 0.8, 2.0]), np.array([0.0, 0.2, 0.5, 0.05])
    A = np.array([(1.0, 1.0, 1.0), TINT, (0.5, 0.5, 0.5), (0.0, 0.2, 0.9)])
    sheet = ThinDielectric(eta, alpha, transmittance=A)
    f, E = sheet.eval(wo, wi), sheet.albedo(wo, method="table")
    for k in range(4):
        one = ThinDielectric(eta[k], alpha[k], transmittance=A[k])
        np.testing.assert_allclose(f[k], one.eval(wo[k], wi[k]), rtol=EXACT)
        np.testing.assert_allclose(E[k], one.albedo(wo[k], method="table"), rtol=1e-9)


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"eta": 0.0}, "eta"), ({"eta": -1.5}, "eta"), ({"eta": np.nan}, "eta"),
    ({"eta": np.inf}, "eta"), ({"eta": "1.5"}, "eta"),
    ({"alpha_x": -0.1}, "alpha_x"), ({"alpha_x": np.nan}, "alpha_x"),
    ({"alpha_x": 5.0}, "alpha_x"), ({"alpha_y": -1.0}, "alpha_y"),
    ({"transmittance": 1.5}, "transmittance"), ({"transmittance": -0.1}, "transmittance"),
    ({"transmittance": (0.5, np.nan, 0.5)}, "transmittance"),
    ({"transmittance": (0.5, 0.5)}, "transmittance"),
])
def test_bad_input(kwargs, name):
    args = {"eta": 1.5, "alpha_x": 0.3, **kwargs}
    with pytest.raises(ValueError, match=name):
        ThinDielectric(**args)
    if name in ("eta", "transmittance"):
        fresnel_args = {"eta": args["eta"], "transmittance": args.get("transmittance", 1.0)}
        for model in (SheetReflectance, SheetTransmittance):
            with pytest.raises(ValueError, match=name):
                model(**fresnel_args)
