"""``Sum``: weights, zero-weight components dropped, the empty sum, bad weights."""

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.composition import Sum
from adobe_bsdf.lobes import Conductor, Lambert
from tests import tolerances


def _pairs(n=2000, seed=3):
    rng = np.random.default_rng(seed)
    w = rng.normal(size=(2, n, 3))
    wo, wi = w / np.linalg.norm(w, axis=-1, keepdims=True)
    wo[:, 2] = np.abs(wo[:, 2])
    return wo, wi, rng.random((n, 3))


def test_weighted_sum_is_the_weighted_components():
    a, b = Lambert(0.8), Conductor(0.4, 0.1)
    w_a, w_b = np.array([0.2, 0.5, 0.1]), 0.7
    mix = Sum(a, b, weights=[w_a, w_b])
    wo, wi, _ = _pairs()
    expected = w_a * a.eval(wo, wi) + w_b * b.eval(wo, wi)
    np.testing.assert_allclose(mix.eval(wo, wi), expected, rtol=tolerances.EXACT, atol=0)
    wo1 = np.array([0.0, 0.6, 0.8])
    np.testing.assert_allclose(mix.albedo(wo1, method="quadrature"),
                               w_a * a.albedo(wo1) + w_b * b.albedo(wo1),
                               atol=tolerances.FURNACE)


def test_zero_weight_components_are_dropped():
    a, b, c = Lambert(), Conductor(0.3), Conductor(0.05)
    mix = Sum(a, b, c, weights=[1.0, 0.0, (0.0, 0.0, 0.0)])
    assert mix.components == (a,)
    wo, wi, u = _pairs()
    np.testing.assert_array_equal(mix.eval(wo, wi), a.eval(wo, wi))
    np.testing.assert_array_equal(mix.pdf(wo, wi), a.pdf(wo, wi))


def test_sum_of_nothing_is_black():
    mix = Sum(Lambert(), weights=[0.0])
    wo, wi, u = _pairs(50)
    assert not mix.components
    assert np.all(mix.eval(wo, wi) == 0.0) and np.all(mix.pdf(wo, wi) == 0.0)
    s = mix.sample(wo, u)
    assert np.all(s.weight == 0.0) and np.all(s.pdf == 0.0)
    assert np.all(s.flags == int(ab.Flags.NONE))
    assert np.all(mix.albedo(wo[:2]) == 0.0)


@pytest.mark.parametrize("weights, message", [([1.0], "weights has 1 entries"),
                                              ([1.0, -0.5], "weights = -0.5"),
                                              ([1.0, np.nan], "weights = nan")])
def test_bad_weights_are_rejected(weights, message):
    with pytest.raises(ValueError, match=message):
        Sum(Lambert(), Conductor(0.3), weights=weights)


def test_non_lobe_components_are_rejected():
    with pytest.raises(ValueError, match="components"):
        Sum(Lambert(), "metal")


def test_one_direction_with_a_batch_of_uniforms():
    """sample(wo (3,), u (n, 3)) is the same as with wo repeated n times."""
    mix = Sum(Lambert(0.5), Conductor(0.2), weights=[0.4, 0.6])
    wo = np.array([0.3, 0.0, np.sqrt(0.91)])
    _, _, u = _pairs(500)
    one, many = mix.sample(wo, u), mix.sample(np.broadcast_to(wo, u.shape), u)
    for a, b in zip(one, many, strict=True):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("weight", [None, (0.9, 0.4, 0.2)])
def test_single_component_samples_as_the_component(weight):
    """One active component is picked with probability 1: eval and pdf are its own (times
    the weight) bit for bit, and sample is its own sample with the weight applied, whose
    weight and pdf agree with f |cos| / pdf and pdf(wo, wi) evaluated at the sampled
    direction to rounding."""
    lobe = ab.lobes.ConductorMS(0.3, 0.1, ab.fresnel.F82Tint((0.9, 0.6, 0.3), (0.9, 0.9, 0.8)))
    mix = Sum(lobe) if weight is None else Sum(lobe, Lambert(), weights=[weight, 0.0])
    w = np.ones(3) if weight is None else np.array(weight)
    wo, wi, u = _pairs(20_000)
    np.testing.assert_array_equal(mix.eval(wo, wi), lobe.eval(wo, wi) * w)
    np.testing.assert_array_equal(mix.pdf(wo, wi), lobe.pdf(wo, wi))
    s, own = mix.sample(wo, u), lobe.sample(wo, u)
    np.testing.assert_array_equal(s.wi, own.wi)
    np.testing.assert_array_equal(s.weight, own.weight * w)
    ok = s.pdf > 0.0
    assert np.count_nonzero(ok) > 15_000
    f, pdf = mix.eval_pdf(wo[ok], s.wi[ok])
    np.testing.assert_allclose(s.pdf[ok], pdf, rtol=1e-13, atol=0)
    np.testing.assert_allclose(s.weight[ok], f * np.abs(s.wi[ok, 2:]) / pdf[:, None],
                               rtol=1e-14, atol=0)


class _Counted(Lambert):
    """A Lambert that records the rows each eval_pdf is asked for."""

    def __init__(self, *args):
        super().__init__(*args)
        self.rows = []

    def _eval_pdf_t(self, wo, wi, throughput):
        self.rows.append(len(wo))
        return super()._eval_pdf_t(wo, wi, throughput)


def test_a_sample_evaluates_only_the_components_it_did_not_draw_from():
    """Each component is sampled on the elements that chose it and evaluated only on the
    others; the chosen one's f |cos| is its sample's weight times pdf, so the mixture's
    samples agree with its eval and pdf to rounding."""
    lambert, conductor = _Counted(0.5), Conductor(0.3, 0.1)
    mix = Sum(lambert, conductor, weights=[0.4, (0.9, 0.6, 0.3)])
    wo, _, u = _pairs(6000)
    P = mix._probabilities(wo)
    chose_conductor = u[:, 0] >= P[0]
    s = mix.sample(wo, u)
    assert lambert.rows == [np.count_nonzero(chose_conductor)]
    ok = s.pdf > 0
    assert np.count_nonzero(ok) > 4000
    f, pdf = mix.eval(wo[ok], s.wi[ok]), mix.pdf(wo[ok], s.wi[ok])
    np.testing.assert_allclose(s.pdf[ok], pdf, rtol=1e-12)
    np.testing.assert_allclose(s.weight[ok], f * np.abs(s.wi[ok, 2:]) / pdf[:, None],
                               rtol=1e-12)


def test_a_stochastic_component_is_evaluated_at_its_own_samples():
    """A component whose sample weight is an estimate (``weight_is_ratio`` False: the
    layered reference) is weighed by its eval, as every component is with textures."""
    from adobe_bsdf.composition import Layer, _by_groups
    from adobe_bsdf.layered import LayeredReference
    from adobe_bsdf.lobes import Dielectric

    walk = LayeredReference(Dielectric(1.5, 0.3), Lambert(0.5), n_samples=2)
    wo, _, u = _pairs(10)
    for mixture in (Sum(walk, Lambert()), Layer(Conductor(0.2), walk)):
        assert not mixture.weight_is_ratio
    assert not _by_groups((walk, Lambert()), wo, u)
    assert _by_groups((Conductor(0.2), Lambert()), wo, u)


def test_a_one_sided_composition_is_evaluated_on_its_side_only():
    """At another component's samples, a ``Sum`` or ``Layer`` that only reflects (only
    transmits) is evaluated on the pairs of its side alone and is 0 on the others: the
    same bits as evaluating it on every pair, pairs in the tangent plane included; and a
    pass-through (transmission) mixed with a reflecting layer samples to the same bits as
    the mixture whose layer is evaluated on every pair."""
    from adobe_bsdf import composition
    from adobe_bsdf.composition import Flipped, Layer
    from adobe_bsdf.lobes import DielectricReflection, PassThrough

    wo, wi, u = _pairs(5000)
    wi[:7, 2] = 0.0  # the tangent plane: on neither side
    wi[:7] /= np.linalg.norm(wi[:7], axis=1)[:, None]
    reflecting = Layer(DielectricReflection(1.5, 0.3), Lambert(0.7))
    transmitting = Sum(Flipped(Lambert(0.4)), Flipped(Conductor(0.3)))
    assert not reflecting.flags & ab.Flags.TRANSMISSION
    assert not transmitting.flags & ab.Flags.REFLECTION
    for lobe in (reflecting, transmitting):
        f, pdf = composition._on_its_side(lobe, wo, wi, None)
        f_all, pdf_all = lobe._eval_pdf_t(wo, wi, None)
        assert np.array_equal(f, f_all) and np.array_equal(pdf, pdf_all)
        assert np.any(pdf == 0.0) and np.any(pdf > 0.0)  # both sides present
    mix = Sum(PassThrough(), reflecting, weights=[0.6, 0.4])
    s = mix.sample(wo, u)
    plain = lambda lobe, wo, wi, t: lobe._eval_pdf_t(wo, wi, t)  # noqa: E731
    original, composition._on_its_side = composition._on_its_side, plain
    try:
        every = mix.sample(wo, u)
    finally:
        composition._on_its_side = original
    for a, b in zip(s, every, strict=True):
        assert np.array_equal(a, b)
