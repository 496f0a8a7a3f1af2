"""Batched execution (``adobe_bsdf.config``): chunks and threads change nothing but speed.

Every registered lobe gives bit-identical ``eval``, ``pdf``, ``eval_pdf`` and ``sample``
whether a batch runs in one piece, in chunks on one thread, or in chunks on a thread pool;
``eval_pdf`` equals ``eval`` and ``pdf`` bit for bit; float32 input is computed in float64.
"""

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf import _allocator, config
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


_FAULTS = """
import resource, sys
import numpy as np
import adobe_bsdf as ab
rng = np.random.default_rng(0)
wo = rng.normal(size=(200_000, 3))
wo /= np.linalg.norm(wo, axis=-1, keepdims=True)
wo[:, 2] = np.abs(wo[:, 2])
u = rng.random((200_000, 3))
material = ab.materials.AdobeStandardMaterial(coat_opacity=0.5, sheen_opacity=0.5)
faults = []
for _ in range(3):
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    material.sample(wo, u)
    faults.append(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
print(ab.config.get_options().retained_memory, min(faults[1:]))
"""


def _faults(env):
    import os
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", _FAULTS], capture_output=True, text=True,
                         env={**os.environ, **env}, check=True, timeout=300).stdout.split()
    return int(out[0]), int(out[1])


@pytest.mark.skipif(not _allocator.supported(), reason="glibc's allocator only")
def test_retained_memory_spares_a_repeated_call_its_page_faults():
    """Default: the second and third ``sample`` of 2·10^5 pairs reuse the first one's pages
    (its temporaries and outputs, ~100 MB, are ~25 000 pages of 4 KiB); with
    ADOBE_BSDF_RETAINED_MEMORY=0 (glibc's own thresholds) each call takes fresh pages."""
    retained, kept = _faults({"ADOBE_BSDF_RETAINED_MEMORY": ""})
    assert retained == config.RETAINED_MEMORY
    off, given_back = _faults({"ADOBE_BSDF_RETAINED_MEMORY": "0"})
    assert off == 0
    assert kept < 500 < 5000 < given_back


def test_retained_memory_is_validated():
    before = config.get_options()
    for bad in (-1, 2**31, 1.5, True):
        with pytest.raises(ValueError, match="retained_memory"):
            config.set_options(retained_memory=bad)
    assert config.get_options() == before
    assert config.set_options(retained_memory=before.retained_memory) == before
