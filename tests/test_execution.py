"""Batched execution (``adobe_bsdf.config``): chunks and threads change nothing but speed.

Every registered lobe gives bit-identical ``eval``, ``pdf``, ``eval_pdf`` and ``sample``
whether a batch runs in one piece, in chunks on one thread, or in chunks on a thread pool;
``eval_pdf`` equals ``eval`` and ``pdf`` bit for bit; float32 input is computed in float64.
"""

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf import config
from adobe_bsdf.validation.cases import cases

N = 5000


def _inputs(seed=0):
    rng = np.random.default_rng(seed)
    w = rng.normal(size=(2, N, 3))
    wo, wi = w / np.linalg.norm(w, axis=-1, keepdims=True)
    return wo, wi, rng.random((N, 3))


def _calls(lobe, wo, wi, u):
    s = lobe.sample(wo, u)
    f, p = lobe.eval_pdf(wo, wi)
    return [lobe.eval(wo, wi), lobe.pdf(wo, wi), f, p, *s]


@pytest.mark.parametrize("case", cases(), ids=lambda c: c.name)
def test_chunks_and_threads_are_bit_identical(case):
    lobe = case.make()
    wo, wi, u = _inputs()
    with config.options(threads=1, chunk_size=10 * N):
        whole = _calls(lobe, wo, wi, u)
    for threads in (1, 2):
        with config.options(threads=threads, chunk_size=777):
            chunked = _calls(lobe, wo, wi, u)
        for a, b in zip(whole, chunked, strict=True):
            assert a.shape == b.shape and a.dtype == b.dtype
            np.testing.assert_array_equal(a, b)
    f, p, f2, p2 = whole[:4]
    np.testing.assert_array_equal(f, f2)
    np.testing.assert_array_equal(p, p2)


def test_float32_input_is_computed_in_float64():
    lobe = ab.lobes.Conductor(0.3)
    wo, wi, _ = _inputs()
    wo32, wi32 = wo.astype(np.float32), wi.astype(np.float32)
    value = lobe.eval(wo32, wi32)
    assert value.dtype == np.float64
    np.testing.assert_array_equal(value, lobe.eval(wo32.astype(np.float64),
                                                   wi32.astype(np.float64)))


def test_invalid_direction_inside_a_later_chunk_is_reported():
    lobe = ab.lobes.Conductor(0.3)
    wo, wi, _ = _inputs()
    wi[N - 3] = [0.0, 0.0, 2.0]
    with config.options(threads=2, chunk_size=512), pytest.raises(ValueError, match="wi"):
        lobe.eval(wo, wi)


def test_options_are_validated_and_scoped():
    before = config.get_options()
    with pytest.raises(ValueError, match="threads"):
        config.set_options(threads=0)
    with pytest.raises(ValueError, match="chunk_size"):
        with config.options(chunk_size=-1):
            pass
    with config.options(threads=1, chunk_size=100) as inside:
        assert config.get_options() == inside
    assert config.get_options() == before


@pytest.mark.parametrize("make", [
    lambda a: ab.lobes.Conductor(a, 0.5 * a),
    lambda a: ab.lobes.Conductor(a, fresnel=ab.fresnel.ExactConductor(
        eta=(0.143, 0.374, 1.442), k=(3.983, 2.385, 1.603))),
    lambda a: ab.lobes.Dielectric(1.0 + a, a),
    lambda a: ab.lobes.Dielectric(1.0 / (1.0 + a), a, 0.3 * a),
], ids=["conductor", "gold", "dielectric", "dielectric-inside"])
def test_parameter_texture_matches_scalar_lobes(make):
    """A lobe whose parameters are arrays over the batch (a texture) gives, pair by pair, the
    values of the lobe with those parameters as scalars (the batch is not compacted or
    chunked against the parameters)."""
    wo, wi, _ = _inputs(seed=3)
    n = 64
    wo, wi = wo[:n], wi[:n]
    wo[:, 2] = np.abs(wo[:, 2])
    alpha = np.linspace(0.0, 1.0, n)  # includes a smooth element
    lobe = make(alpha)
    f, p = lobe.eval(wo, wi), lobe.pdf(wo, wi)
    for j in range(n):
        one = make(alpha[j])
        np.testing.assert_allclose(f[j], one.eval(wo[j], wi[j]), rtol=1e-13, atol=0)
        np.testing.assert_allclose(p[j], one.pdf(wo[j], wi[j]), rtol=1e-13, atol=0)
