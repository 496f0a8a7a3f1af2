"""``Mix``: OpenPBR's mix, (1 - w) f_a + w f_b [Andersson2023, §Mixing]."""

import numpy as np
import pytest
from hypothesis import given, settings

import adobe_bsdf as ab
from adobe_bsdf.composition import Mix
from adobe_bsdf.lobes import Conductor, Dielectric, Lambert
from adobe_bsdf.validation import checks
from adobe_bsdf.validation import strategies as vs
from tests.sampling_checks import assert_sampling_matches
from tests.tolerances import EXACT, FURNACE, RECIPROCITY

WEIGHTS = np.array([0.2, 0.5, 0.7])


def _pairs(n=2000, seed=4):
    rng = np.random.default_rng(seed)
    return ab.frame.normalize(rng.normal(size=(2, n, 3)))


def test_mix_is_the_weighted_components():
    a, b = Lambert(0.8), Conductor(0.3, 0.1)
    mix = Mix(a, b, WEIGHTS)
    wo, wi = _pairs()
    expected = (1.0 - WEIGHTS) * a.eval(wo, wi) + WEIGHTS * b.eval(wo, wi)
    np.testing.assert_allclose(mix.eval(wo, wi), expected, rtol=EXACT, atol=0)


@pytest.mark.parametrize("weight", [0.0, 1.0])
def test_weight_at_an_end_is_that_component(weight):
    """eval, pdf and the sampled directions bit for bit; sample weights and pdfs to rounding."""
    a, b = Dielectric(1.5, 0.3), Conductor(0.2)
    mix, alone = Mix(a, b, weight), (a if weight == 0.0 else b)
    assert mix.components == (alone,)
    wo, wi = _pairs()
    u = np.random.default_rng(2).random(wo.shape)
    np.testing.assert_array_equal(mix.eval(wo, wi), alone.eval(wo, wi))
    np.testing.assert_array_equal(mix.pdf(wo, wi), alone.pdf(wo, wi))
    mixed, own = mix.sample(wo, u), alone.sample(wo, u)
    np.testing.assert_array_equal(mixed.wi, own.wi)
    np.testing.assert_array_equal(mixed.flags, own.flags)
    # the mixture re-weighs by the whole sum: the same numbers to rounding
    np.testing.assert_allclose(mixed.weight, own.weight, rtol=EXACT, atol=0)
    np.testing.assert_allclose(mixed.pdf, own.pdf, rtol=EXACT, atol=0)


def test_white_furnace():
    """Two lossless lobes (white Lambert, the index-matched dielectric) mix to a lossless
    one at any weight: the cubature of eval gives 1."""
    wo = ab.frame.normalize(np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.99, 0.0, 0.1]]))
    for w in (0.3, WEIGHTS):
        E = Mix(Lambert(1.0), Dielectric(1.0, 0.5), w).albedo(wo, tol=1e-9)
        np.testing.assert_allclose(E, 1.0, rtol=0, atol=FURNACE)


def test_albedo_is_the_weighted_albedos():
    a, b = Lambert(0.8), Dielectric(1.5, 0.3)
    wo = ab.frame.normalize(np.array([[0.3, 0.0, 0.9], [0.0, 0.8, -0.6]]))
    expected = (1.0 - WEIGHTS) * a.albedo(wo, tol=1e-8) + WEIGHTS * b.albedo(wo, tol=1e-8)
    np.testing.assert_allclose(Mix(a, b, WEIGHTS).albedo(wo, tol=1e-8), expected, atol=1e-7)


CHI2_CASES = [("lambert/conductor", 0.9), ("lambert/conductor", 0.2),
              ("dielectric/conductor", 0.8), ("dielectric/conductor", -0.6)]


def _lobe(kind):
    if kind == "lambert/conductor":
        return Mix(Lambert(0.8), Conductor(0.3, 0.1), WEIGHTS)
    return Mix(Dielectric(1.5, 0.4, 0.2), Conductor(0.2), 0.4)


@pytest.mark.parametrize(("kind", "cos_theta"), CHI2_CASES)
def test_chi2_and_sample_weights(kind, cos_theta):
    """sample against pdf (p > 0.01 after Šidák), and every sample's weight = f |cos| / pdf."""
    assert_sampling_matches(_lobe(kind), cos_theta, 0.4, CHI2_CASES.index((kind, cos_theta)),
                            len(CHI2_CASES))


@settings(max_examples=100, deadline=None)
@given(alpha=vs.alpha_pairs(), eta=vs.iors(), pair=vs.direction_pairs("any"))
def test_reciprocity(alpha, eta, pair):
    """A mix of reciprocal lobes is reciprocal (generalized across the interface)."""
    lobe = Mix(Dielectric(eta, *alpha), Conductor(*alpha), WEIGHTS)
    result = checks.reciprocity_error(lobe, *pair, rtol=RECIPROCITY)
    assert result.passed, result


@pytest.mark.parametrize(("args", "message"), [
    ((Lambert(), Conductor(0.3), 1.5), "weight = 1.5"),
    ((Lambert(), Conductor(0.3), -0.1), "weight = -0.1"),
    ((Lambert(), Conductor(0.3), np.nan), "weight = nan"),
    (("lambert", Conductor(0.3), 0.5), "a = 'lambert'"),
    ((Lambert(), None, 0.5), "b = None")])
def test_bad_input(args, message):
    with pytest.raises(ValueError, match=message):
        Mix(*args)
