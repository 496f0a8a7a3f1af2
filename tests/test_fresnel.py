"""Fresnel models against closed forms, independent formulations and published values."""

import numpy as np
import pytest
from scipy.integrate import quad

import adobe_bsdf as ab
from tests.tolerances import EXACT, PUBLISHED_5

F = ab.fresnel
GOLD_ETA = np.array([0.143, 0.374, 1.442])
GOLD_K = np.array([3.983, 2.385, 1.603])


def born_wolf_conductor(mu, n, k):
    """Complex-amplitude form of the absorbing-medium Fresnel equations [BornWolf1980, §13.2]:
    n c_t = sqrt(n^2 - sin^2) on the principal branch, r_s = (c - n c_t) / (c + n c_t),
    r_p = (n^2 c - n c_t) / (n^2 c + n c_t), R = (|r_s|^2 + |r_p|^2) / 2. (The library
    computes the real-arithmetic form of the same moduli.)"""
    c = np.asarray(mu, dtype=np.complex128)
    n2 = (n + 1j * k) ** 2
    n_cos_t = np.sqrt(n2 - (1.0 - c * c))
    r_s = (c - n_cos_t) / (c + n_cos_t)
    r_p = (n2 * c - n_cos_t) / (n2 * c + n_cos_t)
    return 0.5 * (np.abs(r_s) ** 2 + np.abs(r_p) ** 2)


# --- dielectric --------------------------------------------------------------------------
@pytest.mark.parametrize("eta", [1.01, 1.33, 1.5, 2.4, 1 / 1.5])
def test_dielectric_normal_incidence(eta):
    assert F.dielectric(1.0, eta) == pytest.approx(((eta - 1) / (eta + 1)) ** 2, abs=EXACT)


@pytest.mark.parametrize("eta", [1.33, 1.5, 2.0])
def test_dielectric_both_sides(eta):
    mu = np.linspace(0.0, 1.0, 101)
    # from below, the interface is seen with relative index 1/eta
    np.testing.assert_allclose(F.dielectric(-mu, eta), F.dielectric(mu, 1.0 / eta), atol=EXACT)
    # Stokes reciprocity: R at the incident angle equals R at the refracted angle, other side
    cos_t = np.sqrt(1.0 - (1.0 - mu**2) / eta**2)
    np.testing.assert_allclose(F.dielectric(mu, eta), F.dielectric(-cos_t, eta), atol=1e-12)


def test_dielectric_total_internal_reflection():
    eta = 1 / 1.5
    critical = np.sqrt(1.0 - eta**2)
    assert F.dielectric(critical * 0.999, eta) == 1.0
    assert F.dielectric(critical * 1.001, eta) < 1.0
    assert F.dielectric(0.0, eta) == 1.0


def test_dielectric_index_matched_and_limits():
    mu = np.array([0.0, 1e-8, 0.3, 1.0])
    np.testing.assert_array_equal(F.dielectric(mu, 1.0), 0.0)
    # eta -> 1: reflectance -> 0 away from grazing, continuously
    assert 0.0 < F.dielectric(0.5, 1.0 + 1e-9) < 1e-17  # O((eta - 1)^2)
    assert F.dielectric(0.0, 1.5) == pytest.approx(1.0, abs=EXACT)


@pytest.mark.parametrize(("eta", "expected"), [(1.33, 0.06593), (1.5, 0.09178), (1.6, 0.10625),
                                               (2.0, 0.16060), (1 / 1.5, 0.59635)])
def test_dielectric_hemispherical_albedo_published(eta, expected):
    """E_F(eta) = 2 int F mu dmu against values integrated independently (5 significant digits)."""
    value = 2.0 * quad(lambda m: F.dielectric(m, eta) * m, 0, 1, epsabs=1e-13, limit=200)[0]
    assert value == pytest.approx(expected, abs=PUBLISHED_5)


# --- conductor ---------------------------------------------------------------------------
def test_conductor_against_complex_amplitudes():
    mu = np.linspace(0.0, 1.0, 257)
    value = F.conductor(mu, GOLD_ETA, GOLD_K)
    expected = born_wolf_conductor(mu[:, None], GOLD_ETA, GOLD_K)
    np.testing.assert_allclose(value, expected, rtol=1e-12, atol=EXACT)


def test_conductor_model_object_and_texture_parameters():
    """``ExactConductor`` (scalar constants, one channel at a time) and per-element
    parameters (channel-major broadcasting) give the function's values."""
    mu = np.linspace(-1.0, 1.0, 101)
    model = F.ExactConductor(GOLD_ETA, GOLD_K)
    np.testing.assert_array_equal(model(mu), F.conductor(mu, GOLD_ETA, GOLD_K))
    np.testing.assert_allclose(model.from_cos2(mu * mu), model(mu), rtol=0, atol=EXACT)
    eta = np.stack([GOLD_ETA, np.array([1.0, 0.2, 2.5])])[:, None, :]  # (2, 1, 3)
    k = np.stack([GOLD_K, np.array([0.0, 3.0, 0.1])])[:, None, :]
    value = F.conductor(mu, eta, k)
    assert value.shape == (2, 101, 3)
    with np.errstate(invalid="ignore", divide="ignore"):  # 0/0 of eta = 1, k = 0 at mu = 0
        expected = born_wolf_conductor(np.abs(mu)[None, :, None], eta, k)
    expected[1, :, 0] = 0.0  # eta = 1, k = 0: no interface
    np.testing.assert_allclose(value, expected, rtol=1e-12, atol=EXACT)


def test_conductor_normal_incidence_and_dielectric_limit():
    n, k = GOLD_ETA, GOLD_K
    expected = ((n - 1) ** 2 + k**2) / ((n + 1) ** 2 + k**2)
    np.testing.assert_allclose(F.conductor(1.0, n, k), expected, atol=EXACT)
    mu = np.linspace(0, 1, 33)
    for eta in (1.5, 1 / 1.5):
        np.testing.assert_allclose(F.conductor(mu, eta, 0.0)[:, 0], F.dielectric(mu, eta),
                                   atol=1e-14)
    np.testing.assert_array_equal(F.conductor(mu, 1.0, 0.0), 0.0)


# --- Schlick, F82, F82-tint --------------------------------------------------------------
@pytest.mark.parametrize("f0", [0.04, 0.5, 0.9])
def test_schlick_average_closed_form(f0):
    """2 int F_Schlick mu dmu = F0 + (1 - F0)/21 (closed form: 2 B(2, 6) = 1/21)."""
    value = 2 * quad(lambda m: F.schlick(m, f0)[0] * m, 0, 1, epsabs=1e-14)[0]
    assert value == pytest.approx(f0 + (1 - f0) / 21, abs=1e-12)


@pytest.mark.parametrize(("f0", "tint", "expected"), [(0.9, 0.8, 0.878249), (0.5, 0.9, 0.513564)])
def test_f82_tint_average_published(f0, tint, expected):
    """2 int F mu dmu of F82-tint: the closed form F0 + (1 - F0)/21 - b/126 (2 B(3, 7) = 1/126)."""
    value = 2 * quad(lambda m: F.f82_tint(m, f0, tint)[0] * m, 0, 1, epsabs=1e-14)[0]
    assert value == pytest.approx(expected, abs=1e-6)
    b = (f0 + (1 - f0) * (6 / 7) ** 5) * (1 - tint) / ((1 / 7) * (6 / 7) ** 6)
    assert value == pytest.approx(f0 + (1 - f0) / 21 - b / 126, abs=1e-12)


def test_f82_tint_matches_the_reference_listing_form():
    """[Kutz2021, §2.4] factorises F = r + (1 - r - b mu (1 - mu)) (1 - mu)^5."""
    mu = np.linspace(0, 1, 101)[:, None]
    r = np.array([0.9868, 0.7099, 0.3148])
    t = np.array([0.9929, 0.9636, 0.9099])
    b = (r + (1 - r) * (6 / 7) ** 5) * (1 - t) / ((1 / 7) * (6 / 7) ** 6)
    listing = np.clip(r + (1 - r - b * mu * (1 - mu)) * (1 - mu) ** 5, 0, 1)
    np.testing.assert_allclose(F.f82_tint(mu[:, 0], r, t), listing, atol=EXACT)


def test_colour_fresnel_is_the_broadcast_formula_bit_for_bit():
    """Large batches with (3,) colours go channel by channel: the same arithmetic, so the
    same bits as the broadcast formula of [Schlick1994] and [Kutz2021, §2.4]."""
    mu = np.random.default_rng(5).random(4096)
    f0, f90 = np.array([0.9, 0.7, 0.3]), np.array([1.0, 0.95, 0.9])
    tint = np.array([0.99, 0.9, 0.8])
    m = mu[:, None]
    schlick = f0 + (f90 - f0) * (1.0 - m) ** 5.0
    np.testing.assert_array_equal(F.schlick(mu, f0, f90), schlick)
    c = F.COS_THETA_MAX
    a = (f0 + (f90 - f0) * (1.0 - c) ** 5.0) * (1.0 - tint) / (c * (1.0 - c) ** 6)
    np.testing.assert_array_equal(F.f82_tint(mu, f0, tint, f90),
                                  np.clip(schlick - a * m * (1.0 - m) ** 6, 0.0, 1.0))
    # one cosine at a time: the same bits as in the batch (NumPy's power of a scalar can
    # differ from its array power in the last bit)
    for x in mu[:400]:
        np.testing.assert_array_equal(F.schlick(x, f0, f90), F.schlick(np.array([x]), f0, f90)[0])
        np.testing.assert_array_equal(F.f82_tint(x, f0, tint, f90),
                                      F.f82_tint(np.array([x]), f0, tint, f90)[0])


def test_f82_tint_defining_properties():
    mu = np.linspace(0, 1, 65)
    f0, tint = np.array([0.95, 0.64, 0.54]), np.array([0.8, 0.9, 0.7])
    # white tint is Schlick; the value at mu_max is tint x Schlick [Kutz2021, eq. 6]
    np.testing.assert_allclose(F.f82_tint(mu, f0, 1.0), F.schlick(mu, f0), atol=EXACT)
    np.testing.assert_allclose(F.f82_tint(1 / 7, f0, tint), tint * F.schlick(1 / 7, f0), atol=EXACT)
    # generalized [Hoffman2023, eqs. 5-6]: same property with r90 and exponent
    f90, alpha = np.array([0.9, 0.8, 1.0]), 3.0
    np.testing.assert_allclose(F.f82_tint(1 / 7, f0, tint, f90, alpha),
                               tint * F.schlick(1 / 7, f0, f90, alpha), atol=EXACT)
    np.testing.assert_allclose(F.f82_tint(mu, f0, 1.0, f90, alpha), F.schlick(mu, f0, f90, alpha),
                               atol=EXACT)
    np.testing.assert_allclose(F.f82_tint(1.0, f0, tint, f90, alpha), f0, atol=EXACT)
    np.testing.assert_allclose(F.f82_tint(0.0, f0, tint, f90, alpha), f90, atol=EXACT)


def test_f82_original_model():
    f0, h = np.array([0.9, 0.6, 0.3]), np.array([0.85, 0.55, 0.35])
    np.testing.assert_allclose(F.f82(1 / 7, f0, h), h, atol=EXACT)
    np.testing.assert_allclose(F.f82(1.0, f0, h), f0, atol=EXACT)
    # [Kutz2021, Fig. 4]: with a white F82 the original model exceeds 1 ("glowing edges")
    assert F.f82(0.05, 0.5, 1.0).max() > 1.0


def test_f82_tint_is_clamped_where_the_polynomial_leaves_unit_interval():
    assert F.f82_tint(0.5, 0.0, 0.0)[0] == 0.0  # polynomial value is negative there


# --- broadcasting and bad input ----------------------------------------------------------
@pytest.mark.parametrize("shape", [(), (6,), (2, 3)])
def test_broadcasting(shape):
    mu = np.full(shape, 0.3)
    assert F.dielectric(mu, 1.5).shape == shape
    assert F.conductor(mu, GOLD_ETA, GOLD_K).shape == (*shape, 3)
    assert F.schlick(mu, 0.04).shape == (*shape, 3)
    assert F.f82_tint(mu, np.full((*shape, 3), 0.9), 0.8).shape == (*shape, 3)
    assert F.dielectric(0.3, np.full(shape, 1.5)).shape == shape


@pytest.mark.parametrize(("call", "name"), [
    (lambda: F.dielectric(0.5, 0.0), "eta"),
    (lambda: F.dielectric(0.5, np.nan), "eta"),
    (lambda: F.dielectric(1.5, 1.5), "cos_theta_i"),
    (lambda: F.conductor(0.5, -1.0, 1.0), "eta"),
    (lambda: F.conductor(0.5, 1.0, -1.0), "k"),
    (lambda: F.schlick(0.5, 1.2), "f0"),
    (lambda: F.schlick(0.5, 0.5, exponent=0.0), "exponent"),
    (lambda: F.f82_tint(0.5, 0.5, -0.1), "tint"),
    (lambda: F.f82_tint(0.5, [0.5, 0.5], 1.0), "f0"),
])
def test_bad_input_names_parameter(call, name):
    with pytest.raises(ValueError, match=name):
        call()


def test_extremes_are_finite():
    mu = np.array([-1.0, -1e-8, 0.0, 1e-8, 1.0])
    for eta in (1e-3, 1 / 1.5, 1.0, 1.0 + 1e-12, 1.5, 1e3):
        assert np.all(np.isfinite(F.dielectric(mu, eta)))
    assert np.all(np.isfinite(F.conductor(mu, [1e-3, 1.0, 50.0], [0.0, 1e-9, 100.0])))


def test_dielectric_never_exceeds_one_at_grazing():
    """At c = 0 the exact amplitudes are r_s = r_p = -1 (R = 1); the rounded c_t must not
    push R above 1 (a lobe multiplies F into a D V saturated at the float64 maximum, where
    1 + 1 ulp overflows to inf)."""
    eta = np.linspace(0.2, 4.0, 20001)
    for c in (0.0, 5e-324, 1e-310, 1e-160):
        R = F.dielectric(np.full_like(eta, c), eta)
        assert np.all(R <= 1.0)
        np.testing.assert_allclose(R[eta != 1.0], 1.0, atol=1e-15)


def _fresnel_decimal(c, eta):
    """Textbook dielectric Fresnel in 50-digit decimal arithmetic (independent reference)."""
    from decimal import Decimal, getcontext
    getcontext().prec = 50
    c, eta = Decimal(c), Decimal(eta)
    ct = (1 - (1 - c * c) / (eta * eta)).sqrt()
    rs = (c - eta * ct) / (c + eta * ct)
    rp = (eta * c - ct) / (eta * c + ct)
    return float((rs * rs + rp * rp) / 2)


@pytest.mark.parametrize(("eta", "cos_theta"), [
    (eta, c) for eta in (1 + 1e-8, 1 - 1e-8, 1 + 1e-4, 1.5, 1 / 1.5, 2.4)
    for c in (1.0, 0.7, 0.2, 0.01) if (1 - c**2) / eta**2 < 1  # TIR is tested separately
])
def test_dielectric_relative_accuracy_including_eta_near_one(eta, cos_theta):
    """Full float64 relative accuracy, also where the textbook form cancels (eta -> 1)."""
    expected = _fresnel_decimal(cos_theta, eta)
    assert F.dielectric(cos_theta, eta) == pytest.approx(expected, rel=1e-14)


@pytest.mark.parametrize("eta", [1.5, 1.0 / 1.5, 1.0, 1.0 + 1e-9, 3.0])
def test_dielectric_k_scalar_paths_match_the_array_path(eta):
    """The shortcuts for one interface (no TIR test from the less dense side, 0 when
    index-matched) give bit for bit the values of the general per-element path."""
    from adobe_bsdf.fresnel import _dielectric_k, _k_of_indices

    c = np.linspace(0.0, 1.0, 1001)
    k, eta2 = _k_of_indices(eta, 1.0), eta * eta
    general = _dielectric_k(c, np.full_like(c, k), np.full_like(c, eta2))
    np.testing.assert_array_equal(_dielectric_k(c, float(k), float(eta2)), general)


# --- Gulbrandsen's artist-friendly conductor parameters ------------------------------------
from hypothesis import assume, given  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_R = st.floats(0.0, 0.99)
_G = st.floats(0.0, 1.0)


@given(r=_R, g=_G)
def test_gulbrandsen_normal_incidence_reflectance_is_r(r, g):
    """The exact conductor Fresnel at normal incidence of the mapped (eta, k) is r."""
    eta, k = ab.fresnel.gulbrandsen_to_ior(r, g)
    np.testing.assert_allclose(ab.fresnel.conductor(1.0, eta, k)[0], r, rtol=EXACT, atol=1e-15)


@given(r=_R, g=_G)
def test_gulbrandsen_round_trip(r, g):
    r2, g2 = ab.fresnel.ior_to_gulbrandsen(*ab.fresnel.gulbrandsen_to_ior(r, g))
    np.testing.assert_allclose(r2, r, rtol=EXACT, atol=1e-15)
    if r > 1e-6:  # g is undefined at r = 0 and ill-conditioned just above it
        np.testing.assert_allclose(g2, g, rtol=0, atol=1e-9)


@given(r=_R, g=st.floats(0.05, 1.0))
def test_gulbrandsen_k_equals_the_textbook_form(r, g):
    """The cancellation-free k^2 equals (r (eta + 1)^2 - (eta - 1)^2) / (1 - r) where the
    latter is well conditioned: g away from 0, and its numerator's rounding (a few eps times
    the magnitudes of its terms; near r = 0, eta - 1 itself is at rounding level) below 1e-9
    of its value."""
    eta, k = ab.fresnel.gulbrandsen_to_ior(r, g)
    numerator = r * (eta + 1.0) ** 2 - (eta - 1.0) ** 2
    rounding = 4.0 * np.finfo(float).eps * (r * (eta + 1.0) ** 2 + (eta - 1.0) ** 2
                                            + 2.0 * eta * abs(eta - 1.0))
    assume(numerator > 1e9 * rounding)
    textbook = np.sqrt(numerator / (1.0 - r))
    np.testing.assert_allclose(k, textbook, rtol=1e-9, atol=1e-12)


def test_gulbrandsen_zero_edge_tint_is_a_dielectric():
    """g = 0: k = 0 exactly and eta = (1 + sqrt r) / (1 - sqrt r), whose dielectric Fresnel
    at normal incidence is r ([Barla2018, §4]: kappa vanishes with g)."""
    r = np.linspace(0.0, 0.95, 20)
    eta, k = ab.fresnel.gulbrandsen_to_ior(r, 0.0)
    assert np.all(k == 0.0)
    np.testing.assert_allclose(ab.fresnel.dielectric(1.0, eta), r, rtol=EXACT, atol=1e-15)


def test_gulbrandsen_broadcasting_and_measured_metal():
    r = np.array([0.9, 0.6, 0.3])
    for shape in [(), (3,), (2, 3)]:
        g = np.full(shape, 0.4)
        eta, k = ab.fresnel.gulbrandsen_to_ior(r if shape else 0.5, g)
        assert eta.shape == k.shape == (shape or ())
    # gold (the RGB n, k of the lobe tests): its (r, g) maps back to its (eta, k) where g is
    # in [0, 1]
    eta, k = np.array([0.143, 0.374, 1.442]), np.array([3.983, 2.385, 1.603])
    r, g = ab.fresnel.ior_to_gulbrandsen(eta, k)
    inside = (g >= 0.0) & (g <= 1.0)
    assert inside.any()
    eta2, k2 = ab.fresnel.gulbrandsen_to_ior(r[inside], g[inside])
    np.testing.assert_allclose(eta2, eta[inside], rtol=1e-10)
    np.testing.assert_allclose(k2, k[inside], rtol=1e-10)
    assert ab.fresnel.ior_to_gulbrandsen(1.0, 0.0) == (0.0, 0.0)


@pytest.mark.parametrize("call, args, name", [
    (ab.fresnel.gulbrandsen_to_ior, (1.0, 0.5), "reflectivity"),
    (ab.fresnel.gulbrandsen_to_ior, (-0.1, 0.5), "reflectivity"),
    (ab.fresnel.gulbrandsen_to_ior, (0.5, 1.5), "edge_tint"),
    (ab.fresnel.gulbrandsen_to_ior, (np.nan, 0.5), "reflectivity"),
    (ab.fresnel.ior_to_gulbrandsen, (0.0, 1.0), "eta"),
    (ab.fresnel.ior_to_gulbrandsen, (1.5, -1.0), "k"),
])
def test_gulbrandsen_bad_input(call, args, name):
    with pytest.raises(ValueError, match=name):
        call(*args)


def test_fresnel_function_repr_has_no_memory_address():
    """Reprs name the callable (stable across processes, e.g. as pytest-xdist test ids)."""
    import functools

    from adobe_bsdf.fresnel import FresnelFunction, conductor

    text = repr(FresnelFunction(functools.partial(conductor, eta=[0.2, 0.4, 1.4], k=3.0)))
    assert text == "partial(adobe_bsdf.fresnel.conductor, eta=[0.2, 0.4, 1.4], k=3.0)"
    assert "0x" not in repr(FresnelFunction(lambda c: c))
