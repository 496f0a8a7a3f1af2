"""The albedo-scaling forms of ``Layer`` [Andersson2023, §Layering] and its coat darkening
[OpenPBR2026, §Coat darkening; Portsmouth2025]: "transmittance" (the coat's view-dependent
two-way absorption T^((1/mu_o^t + 1/mu_i^t) / 2)), a constant colour T in "albedo" and
"reciprocal", and ``darkening.Darkening``. Expected values are closed forms (Fresnel,
Beer's law, the bounces between a smooth coat and a Lambertian base) or quadrature."""

import functools
import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import adobe_bsdf as ab
from adobe_bsdf import fresnel
from adobe_bsdf.composition import SCALINGS, Layer, coat_absorption
from adobe_bsdf.darkening import VARIANTS, Darkening
from adobe_bsdf.lobes import (
    Conductor,
    ConductorMS,
    DielectricMS,
    DielectricReflection,
    Lambert,
    Sheen,
)
from adobe_bsdf.materials.asm import CoatTransmittance
from adobe_bsdf.validation import checks
from tests.sampling_checks import assert_sampling_matches
from tests.tolerances import FURNACE_TABLE

#: white furnace of a form that promises it: 1 +- 2e-3
FURNACE_TOL = 2e-3
COSINES = np.array([1.0, 0.7, 0.3, 0.1, 0.02])
#: (coat eta, coat alpha): index 1, smooth, below and above the dielectric base's 1.5, rough
COATS = [(1.0, 0.3), (1.5, 0.0), (1.3, 0.2), (2.0, 0.8)]
COLOUR = np.array([0.9, 0.6, 0.3])
NORMAL = np.array([0.0, 0.0, 1.0])


def _wo(cosines, phi=0.0):
    s = np.sqrt(1.0 - cosines**2)
    return np.stack([s * np.cos(phi), s * np.sin(phi), cosines], -1)


def _random_pairs(n, seed):
    rng = np.random.default_rng(seed)
    wo, wi = ab.frame.normalize(rng.normal(size=(2, n, 3)))
    return np.where(wo[..., 2:] < 0, -wo, wo), np.where(wi[..., 2:] < 0, -wi, wi)


def _refracted_cosine(mu, eta):
    """Snell's law: cos theta_t of |cos theta| = ``mu`` into a medium of relative index eta."""
    return np.sqrt(1.0 - (1.0 - mu**2) / eta**2)


@functools.cache
def _white_base(kind):
    return {"lambert": Lambert(1.0), "conductor": ConductorMS(0.3),
            "dielectric": DielectricMS(1.5, 0.3)}[kind]


# -- the coat's view-dependent transmittance --------------------------------------------------


def test_coat_absorption_is_beers_law():
    """t(w) = exp(ln T / (2 mu_t)): Beer's law with the optical depth fixed by T at normal
    incidence, where the pair t t is T; symmetric in the side of w."""
    mu = np.array([1.0, 0.8, 0.4, 0.05])
    for eta in (1.0 + 1e-9, 1.5, 2.5):
        t = coat_absorption(COLOUR, np.asarray(eta), _wo(mu))
        expected = np.exp(np.log(COLOUR) / (2.0 * _refracted_cosine(mu, eta))[:, None])
        np.testing.assert_allclose(t, expected, rtol=1e-14)
        np.testing.assert_array_equal(coat_absorption(COLOUR, np.asarray(eta), -_wo(mu)), t)
    np.testing.assert_allclose(coat_absorption(COLOUR, np.asarray(1.5), NORMAL) ** 2, COLOUR,
                               rtol=1e-15)


def test_coat_absorption_is_the_power_to_rounding():
    """A constant colour is raised as exp(exponent ln T) channel by channel: within
    (1 + |ln t|) eps (relative) of T ** exponent over random directions (the rounding of the
    optical depth), exactly 1 and 0 for white and black channels, and
    the same values for one direction as for a batch; a textured colour gets the power."""
    w = _random_pairs(3000, 4)[0]
    w[:5, 2] = [0.0, 1e-300, 1.0, -1.0, 0.3]
    for eta in (1.0, 1.2, 1.6, 3.0):
        for colour in (np.array([0.9, 0.8, 0.5]), np.array([1.0, 0.0, 0.02])):
            t = coat_absorption(colour, np.asarray(eta), w)
            mu = np.abs(w[:, 2])
            mu_t = np.sqrt(np.maximum(1.0 - (1.0 - mu * mu) / eta**2, 0.0))
            with np.errstate(divide="ignore", invalid="ignore"):
                power = colour ** np.where(mu_t > 0, 0.5 / mu_t, np.inf)[:, None]
            power = np.where(colour == 1.0, 1.0, np.where(colour == 0.0, 0.0, power))
            with np.errstate(divide="ignore"):  # the bound grows with the optical depth
                depth = np.where(power > 0.0, -np.log(power), 0.0)
            assert np.all(np.abs(t - power) <= 2.3e-16 * (1.0 + depth) * power)
            assert np.all(t[:, colour == 1.0] == 1.0) and np.all(t[:, colour == 0.0] == 0.0)
            np.testing.assert_array_equal(coat_absorption(colour, np.asarray(eta), w[7]), t[7])
    textured = np.broadcast_to([0.9, 0.8, 0.5], w.shape)
    np.testing.assert_array_equal(coat_absorption(textured, np.asarray(1.6), w),
                                  textured ** (0.5 / np.sqrt(1.0 - (1.0 - w[:, 2:] ** 2)
                                                              / 1.6**2)))


def test_the_asm_tint_is_the_coat_absorption():
    """``materials.asm.CoatTransmittance`` computes its t(w) with ``coat_absorption``."""
    w = _random_pairs(500, 1)[0]
    for eta in (1.0, 1.6, 3.0):
        np.testing.assert_array_equal(CoatTransmittance(COLOUR, eta)(w),
                                      coat_absorption(COLOUR, np.asarray(eta), w))


@pytest.mark.parametrize(("eta", "alpha"), [(1.5, 0.3), (2.0, 0.05)])
@pytest.mark.parametrize("coverage", [1.0, 0.4])
def test_transmittance_form_is_the_closed_form(eta, alpha, coverage):
    """f = c f_top + (1 - c + c T^((1/mu_o^t + 1/mu_i^t)/2) (1 - E_top(wo))) f_base, with the
    refracted cosines of Snell's law; at normal incidence the factor is T."""
    top, base = DielectricReflection(eta, alpha), Lambert((0.9, 0.5, 0.2))
    layer = Layer(top, base, coverage, COLOUR, scaling="transmittance")
    wo, wi = _random_pairs(2000, 2)
    mu_t = _refracted_cosine(wo[:, 2], eta), _refracted_cosine(wi[:, 2], eta)
    T_coat = COLOUR ** ((1.0 / mu_t[0] + 1.0 / mu_t[1]) / 2.0)[:, None]
    W = 1.0 - coverage + coverage * T_coat * (1.0 - top.albedo(wo, method="table"))
    expected = coverage * top.eval(wo, wi) + W * base.eval(wo, wi)
    np.testing.assert_allclose(layer.eval(wo, wi), expected, rtol=1e-12)
    W0 = 1.0 - coverage + coverage * COLOUR * (1.0 - top.albedo(NORMAL, method="table"))
    np.testing.assert_allclose(layer.eval(NORMAL, NORMAL),
                               coverage * top.eval(NORMAL, NORMAL) + W0 * base.eval(NORMAL,
                                                                                     NORMAL),
                               rtol=1e-14)


def test_a_constant_colour_is_the_normal_incidence_factor():
    """"albedo" and "reciprocal" with a colour T: the base's covered weight times T at every
    pair of directions (not view dependent)."""
    top, base = DielectricReflection(1.5, 0.3), Lambert((0.9, 0.5, 0.2))
    wo, wi = _random_pairs(2000, 3)
    E_o, E_i = top.albedo(wo, method="table"), top.albedo(wi, method="table")
    albedo = Layer(top, base, 0.7, COLOUR)
    expected = 0.7 * top.eval(wo, wi) + (0.3 + 0.7 * COLOUR * (1.0 - E_o)) * base.eval(wo, wi)
    np.testing.assert_allclose(albedo.eval(wo, wi), expected, rtol=1e-12)
    reciprocal = Layer(top, base, 0.7, COLOUR, scaling="reciprocal")
    C = Layer(top, base, 0.7, scaling="reciprocal").normalisation[0]  # T stays outside C
    np.testing.assert_array_equal(reciprocal.normalisation[0], C)
    W = 0.3 + 0.7 * C * COLOUR * (1.0 - E_o) * (1.0 - E_i)
    np.testing.assert_allclose(reciprocal.eval(wo, wi), 0.7 * top.eval(wo, wi)
                               + W * base.eval(wo, wi), rtol=1e-12)


@pytest.mark.parametrize("darkening", [None, Darkening(0.6, 0.3)])
def test_transmittance_at_one_is_the_albedo_form(darkening):
    """T = 1: "transmittance" is "albedo" bit for bit (eval, pdf, samples, table albedo)."""
    wo, wi = _random_pairs(3000, 4)
    u = np.random.default_rng(5).random((3000, 3))
    for top, base in ((DielectricReflection(1.5, 0.3), Lambert((0.9, 0.5, 0.2))),
                      (DielectricReflection(2.0, 0.0), ConductorMS(0.2, base_color=COLOUR))):
        a = Layer(top, base, 0.8, darkening=darkening)
        t = Layer(top, base, 0.8, 1.0, scaling="transmittance", darkening=darkening)
        np.testing.assert_array_equal(t.eval(wo, wi), a.eval(wo, wi))
        np.testing.assert_array_equal(t.pdf(wo, wi), a.pdf(wo, wi))
        for x, y in zip(t.sample(wo, u), a.sample(wo, u), strict=True):
            np.testing.assert_array_equal(x, y)
        method = "quadrature" if isinstance(base, Lambert) else "table"  # Lambert: no table
        np.testing.assert_array_equal(t.albedo(wo[:5], method=method),
                                      a.albedo(wo[:5], method=method))


# -- energy ------------------------------------------------------------------------------------

FURNACE_CASES = ([(form, kind) for form in ("albedo", "transmittance")
                  for kind in ("lambert", "conductor", "dielectric")]
                 + [("reciprocal", "lambert")])


@pytest.mark.parametrize(("form", "kind"), FURNACE_CASES)
@pytest.mark.parametrize(("eta", "alpha"), COATS)
def test_white_furnace(form, kind, eta, alpha):
    """A white base under a white (T = 1) coat keeps all the energy, 1 +- 2e-3 (quadrature
    albedo), in every form that promises it: "albedo" and "transmittance" over any white
    base (diffuse, multiple-scattering conductor, dielectric of index 1.5 below or above the
    coat's), "reciprocal" over a Lambertian one."""
    T = 1.0 if form == "transmittance" else None
    layer = Layer(DielectricReflection(eta, alpha), _white_base(kind), transmittance=T,
                  scaling=form)
    E = layer.albedo(_wo(COSINES), tol=1e-6)
    np.testing.assert_allclose(E, 1.0, rtol=0, atol=FURNACE_TOL)


_unit = st.floats(0.0, 1.0)
_edge = st.sampled_from([0.0, 1.0]) | _unit
_colour = st.tuples(_unit, _unit, _unit)


@st.composite
def layers(draw):
    """A layer of any form with colours <= 1: coat index 1, below and above the base's,
    weights and roughness at their ends often; with and without darkening."""
    form = draw(st.sampled_from(SCALINGS))
    low = 1.1 if form == "reciprocal" else 1.0  # near 1 the reciprocal C is slow (no table)
    eta = draw(st.sampled_from([low, 1.5]) | st.floats(low, 3.0))
    top = DielectricReflection(eta, draw(_edge))
    base = draw(st.sampled_from(["lambert", "conductor", "sheen over lambert"]))
    colour = draw(_colour)
    base = {"lambert": lambda: Lambert(colour),
            "conductor": lambda: ConductorMS(draw(st.floats(0.05, 1.0)), base_color=colour),
            "sheen over lambert": lambda: Layer(Sheen(1.0, 0.5), Lambert(colour))}[base]()
    T = draw(st.none() | _colour) if form != "transmittance" else draw(_colour)
    darkening = None
    if form != "reciprocal" and draw(st.booleans()):
        darkening = Darkening(draw(_edge), draw(_edge), draw(st.sampled_from(VARIANTS)),
                              draw(st.none() | _colour))
    return Layer(top, base, draw(_edge), T, scaling=form, darkening=darkening)


@settings(max_examples=30, deadline=None, derandomize=True)
@given(layer=layers())
def test_no_form_gains_energy(layer):
    """With colours <= 1 the albedo (quadrature) is at most 1 + 1e-3 in every form, with and
    without darkening."""
    E = layer.albedo(_wo(np.array([1.0, 0.5, 0.1])), tol=1e-5)
    assert np.all(E <= 1.0 + FURNACE_TABLE), (layer, E)
    assert np.all(np.isfinite(E)) and np.all(E >= 0.0), (layer, E)


def test_non_reciprocity_is_measured():
    """"albedo" and "transmittance" are not reciprocal by design (c tau (E_top(wi) -
    E_top(wo)) f_base); "reciprocal" is, also with a colour T. Reported, as ``check`` does."""
    wo, wi = _random_pairs(5000, 6)
    top, base = DielectricReflection(1.5, 0.3), Lambert((0.9, 0.5, 0.2))
    measured = {}
    for name, layer in (("albedo", Layer(top, base, 0.8, COLOUR)),
                        ("transmittance", Layer(top, base, 0.8, COLOUR, "transmittance")),
                        ("albedo, darkening", Layer(top, base, 0.8, darkening=Darkening())),
                        ("reciprocal", Layer(top, base, 0.8, COLOUR, "reciprocal"))):
        measured[name] = checks.reciprocity_error(layer, wo, wi).max_error
    print("largest relative non-reciprocity:", measured)
    assert all(measured[k] > 1e-2 for k in ("albedo", "transmittance", "albedo, darkening"))
    assert measured["reciprocal"] <= 1e-12


# -- darkening ---------------------------------------------------------------------------------


@functools.cache
def _internal_reflectance(eta, n=2_000_001):
    """K = 2 int_0^1 F(mu, 1/eta) mu d mu, the coat's Fresnel average seen from inside
    (trapezoidal rule)."""
    mu = np.linspace(0.0, 1.0, n)
    g = 2.0 * fresnel.dielectric(mu, 1.0 / eta) * mu
    return float(np.sum(0.5 * (g[1:] + g[:-1]) * np.diff(mu)))


@pytest.mark.parametrize("eta", [1.3, 1.5, 2.0])
@pytest.mark.parametrize("E_b", [0.2, 0.8, 1.0])
@pytest.mark.parametrize("delta", [1.0, 0.4])
def test_darkening_of_a_lambertian_base_is_the_closed_form(eta, E_b, delta):
    """A smooth clear coat over a Lambertian base E_b at normal incidence: the albedo is
    F0 + (1 - F0) E_b lerp(1, (1 - K) / (1 - E_b K), delta) with K the internal reflectance
    of a rough base (r_b = 1), or F0 of a smooth one (r_b = 0)."""
    F0 = float(fresnel.dielectric(1.0, eta))
    for r_b, K in ((1.0, _internal_reflectance(eta)), (0.0, F0)):
        layer = Layer(DielectricReflection(eta, 0.0), Lambert(E_b),
                      darkening=Darkening(delta, r_b))
        Delta = (1.0 - K) / (1.0 - E_b * K)
        expected = F0 + (1.0 - F0) * E_b * (1.0 + delta * (Delta - 1.0))
        np.testing.assert_allclose(layer.albedo(NORMAL, tol=1e-9), expected, rtol=0,
                                   atol=1e-8)


def test_darkening_with_a_coat_colour_is_the_specification_factor():
    """E_top = 0 (coat index 1): the base is multiplied by the specification's
    lerp(1, lerp(1, Delta, delta) T^2, C) [Portsmouth2025], Delta = (1 - K) / (1 - K E_b T^2)
    with the given E_b, K at the view (r_b = 0) of the smooth coat of index eta_c."""
    E_b, coverage, delta = np.array([0.7, 0.5, 0.2]), 0.8, 0.6
    wo, wi = _random_pairs(1000, 7)
    base = Lambert(E_b)
    for variant in VARIANTS:
        top = DielectricReflection(1.0, 0.0)  # no reflection: eta_c 1, K = F = 0
        layer = Layer(top, base, coverage, COLOUR,
                      darkening=Darkening(delta, 0.0, variant, base_albedo=E_b))
        # K = 0 at eta_c 1: Delta = 1 and the factor is lerp(1, T^2, C)
        np.testing.assert_allclose(layer.eval(wo, wi), (1.0 - coverage + coverage * COLOUR)
                                   * base.eval(wo, wi), rtol=1e-14)
    # eta_c = 1.5 with a table-free check at normal incidence: E_top(n) = F0 taken out
    F0 = float(fresnel.dielectric(1.0, 1.5))
    for variant in VARIANTS:
        layer = Layer(DielectricReflection(1.5, 0.0), base, coverage, COLOUR,
                      darkening=Darkening(delta, 0.0, variant, base_albedo=E_b))
        loop = F0 * E_b * (COLOUR if variant == "pr253" else 1.0)
        Delta = (1.0 - F0) / (1.0 - loop)
        W = 1.0 - coverage + coverage * COLOUR * (1.0 - F0) * (1.0 + delta * (Delta - 1.0))
        np.testing.assert_allclose(layer.eval(NORMAL, _wo(np.array([0.6]), 1.0)),
                                   W * base.eval(NORMAL, _wo(np.array([0.6]), 1.0)), rtol=1e-14)


def test_no_darkening_at_delta_zero():
    """delta = 0 is the layer without darkening, bit for bit."""
    wo, wi = _random_pairs(3000, 8)
    u = np.random.default_rng(9).random((3000, 3))
    for form, T in (("albedo", COLOUR), ("transmittance", COLOUR), ("albedo", None)):
        top, base = DielectricReflection(1.6, 0.2), ConductorMS(0.4, base_color=(0.9, 0.5, 0.2))
        plain = Layer(top, base, 0.7, T, form)
        dark = Layer(top, base, 0.7, T, form, Darkening(0.0, 0.5))
        np.testing.assert_array_equal(dark.eval(wo, wi), plain.eval(wo, wi))
        np.testing.assert_array_equal(dark.pdf(wo, wi), plain.pdf(wo, wi))
        for x, y in zip(dark.sample(wo, u), plain.sample(wo, u), strict=True):
            np.testing.assert_array_equal(x, y)


@pytest.mark.parametrize("form", ["albedo", "transmittance"])
def test_darkening_never_adds_energy(form):
    """D <= 1: eval and albedo with darkening are at most those without, everywhere."""
    wo, wi = _random_pairs(3000, 10)
    top = DielectricReflection(1.5, 0.3)
    for base in (Lambert((1.0, 0.5, 0.2)), ConductorMS(0.3, base_color=(1.0, 0.8, 0.4))):
        plain = Layer(top, base, 0.9, COLOUR, form)
        for darkening in (Darkening(), Darkening(0.5, 0.0, "v1.1.1"),
                          Darkening(1.0, 0.3, base_albedo=0.0)):
            dark = Layer(top, base, 0.9, COLOUR, form, darkening)
            assert np.all(dark.eval(wo, wi) <= plain.eval(wo, wi))
            assert np.all(dark.albedo(wo[:3], tol=1e-6) <= plain.albedo(wo[:3], tol=1e-6))


def test_a_white_base_shows_no_colour_shift():
    """E_b = 1 and a grey (or no) coat colour: the darkened albedo is grey; under a clear
    coat Delta = (1 - K) / (1 - K) = 1, so the white furnace still holds (a lossless base
    loses nothing to the bounces), and a grey coat colour darkens it."""
    wo = _wo(COSINES)
    for base in (Lambert(1.0), ConductorMS(0.3)):
        for T in (None, 0.7):
            for delta, r_b in ((1.0, 1.0), (0.5, 0.0), (1.0, 0.4)):
                layer = Layer(DielectricReflection(1.5, 0.2), base, 0.9, T,
                              darkening=Darkening(delta, r_b))
                method = "quadrature" if isinstance(base, Lambert) else "table"
                E = layer.albedo(wo, method=method)
                assert np.all(np.ptp(E, axis=-1) <= 1e-15), E
                if T is None:
                    np.testing.assert_allclose(E, 1.0, rtol=0, atol=FURNACE_TABLE)
                else:
                    plain = Layer(DielectricReflection(1.5, 0.2), base, 0.9, T)
                    assert np.all(E < plain.albedo(wo, method=method))


def test_the_base_albedo_is_the_bases_own_at_normal_incidence():
    """E_b = None: the base's energy albedo at normal incidence, from its table where it has
    one (ConductorMS: the same layer as with its table value given), else a quadrature
    (Lambert: its albedo, to the quadrature's rounding)."""
    top = DielectricReflection(1.5, 0.0)
    wo, wi = _random_pairs(200, 12)
    conductor = ConductorMS(0.3, base_color=COLOUR)
    for base, E_b, rtol in ((Lambert(COLOUR), COLOUR, 1e-12),
                            (conductor, conductor.albedo(NORMAL, method="table"), 0.0)):
        own = Layer(top, base, darkening=Darkening())
        given_ = Layer(top, base, darkening=Darkening(base_albedo=E_b))
        np.testing.assert_allclose(own.eval(wo, wi), given_.eval(wo, wi), rtol=rtol)


# -- sampling ----------------------------------------------------------------------------------

CHI2_CASES = [("transmittance", "coloured", 0.9), ("transmittance", "glossy", 0.3),
              ("darkening", "coloured", 0.2), ("darkening", "glossy", 0.7)]


@functools.cache
def _chi2_layer(kind, base):
    bases = {"coloured": Lambert((0.9, 0.5, 0.2)),
             "glossy": Conductor(0.3, fresnel=ab.fresnel.F82Tint((0.9, 0.6, 0.3), 1.0))}
    top = DielectricReflection(1.5, 0.3)
    if kind == "transmittance":
        return Layer(top, bases[base], 0.8, COLOUR, scaling="transmittance")
    return Layer(top, bases[base], 0.8, COLOUR, darkening=Darkening(0.8, 0.5))


@pytest.mark.parametrize(("kind", "base", "cos_theta"), CHI2_CASES)
def test_chi2_and_sample_weights(kind, base, cos_theta):
    assert_sampling_matches(_chi2_layer(kind, base), cos_theta, 0.2,
                            CHI2_CASES.index((kind, base, cos_theta)), len(CHI2_CASES))


# -- extremes and bad input --------------------------------------------------------------------


def test_finite_at_the_extremes():
    """Zero weights (coverage, T, delta, E_b 0), smooth and roughest coats, index 1 and a coat
    below its surroundings (critical angle), grazing and subnormal cosines: finite,
    non-negative eval, pdf and samples."""
    rng = np.random.default_rng(11)
    wo, wi = ab.frame.normalize(rng.normal(size=(2, 2000, 3)))
    wo[:4] = [[1.0, 0.0, 5e-324], [1.0, 0.0, 1e-300], [0.0, 0.0, 1.0], [1.0, 0.0, 1e-8]]
    wo = ab.frame.normalize(wo)
    u = rng.random((2000, 3))
    bases = (Lambert((1.0, 0.0, 0.5)), ConductorMS(0.3, base_color=(1.0, 0.0, 0.5)))
    for eta, alpha in ((1.5, 0.0), (1.0, 0.5), (3.0, 1.0), (1 / 1.5, 0.3)):
        for coverage, T, darkening in ((0.0, 0.0, Darkening(0.0, 0.0)),
                                       (1.0, 0.0, Darkening(1.0, 1.0, base_albedo=0.0)),
                                       (1.0, (1.0, 0.0, 0.5), Darkening(1.0, 0.0, "v1.1.1")),
                                       (0.5, 1.0, None)):
            for form, base in itertools.product(("albedo", "transmittance"), bases):
                layer = Layer(DielectricReflection(eta, alpha), base, coverage, T, form,
                              darkening)
                f, pdf = layer.eval_pdf(wo, wi)
                s = layer.sample(wo, u)
                for x in (f, pdf, s.weight, s.pdf):
                    assert np.all(np.isfinite(x)) and np.all(x >= 0.0), layer
                if isinstance(base, ConductorMS):  # a base with tables
                    E = layer.albedo(wo, method="table")
                    assert np.all(np.isfinite(E)) and np.all(E >= 0.0), layer


@pytest.mark.parametrize(("call", "message"), [
    (lambda: Layer(DielectricReflection(1.5, 0.3), Lambert(), transmittance=1.5),
     "transmittance = 1.5"),
    (lambda: Layer(DielectricReflection(1.5, 0.3), Lambert(), transmittance="red"),
     "transmittance = 'red'"),
    (lambda: Layer(DielectricReflection(1.5, 0.3), Lambert(), scaling="transmittance"),
     "transmittance = None with scaling = 'transmittance'"),
    (lambda: Layer(DielectricReflection(1.5, 0.3), Lambert(), scaling="transmittance",
                   transmittance=lambda w: 1.0), "with scaling = 'transmittance'"),
    (lambda: Layer(Sheen(1.0, 0.5), Lambert(), transmittance=0.5, scaling="transmittance"),
     "top = Sheen"),
    (lambda: Layer(Lambert(0.2), Lambert(), darkening=Darkening()), "top = Lambert"),
    (lambda: Layer(DielectricReflection(1.5, 0.3), Lambert(), darkening=0.5),
     "darkening = 0.5"),
    (lambda: Layer(DielectricReflection(1.5, 0.3), Lambert(), scaling="reciprocal",
                   darkening=Darkening()), "darkening = .* with scaling = 'reciprocal'"),
    (lambda: Darkening(delta=2.0), "delta = 2.0"),
    (lambda: Darkening(base_roughness=-0.5), "base_roughness = -0.5"),
    (lambda: Darkening(variant="v2"), "variant = 'v2'"),
    (lambda: Darkening(base_albedo=(0.5, 1.2, 0.5)), "base_albedo = 1.2")])
def test_bad_input(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_darkening_is_frozen():
    with pytest.raises(AttributeError):
        Darkening().delta = 0.5
