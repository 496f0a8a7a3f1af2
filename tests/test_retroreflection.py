"""``lobes.Retroreflective``: (1 - w) f(wo, wi) + w f(wo, reflect(wi, n)) on reflection pairs
[OpenPBR2026dev, §Retroreflectivity]; expected values from the wrapped lobe's own eval and
pdf at the turned direction (a different lobe call), closed forms and quadrature."""

from __future__ import annotations

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.lobes import Conductor, DielectricMS, Retroreflective
from adobe_bsdf.validation import checks
from tests.sampling_checks import assert_sampling_matches

TURN = np.array([-1.0, -1.0, 1.0])


def _pairs(seed, n=400):
    return ab.frame.normalize(np.random.default_rng(seed).normal(size=(2, n, 3)))


@pytest.mark.parametrize("lobe", [Conductor(0.3, 0.1), DielectricMS(1.5, 0.4)])
def test_eval_and_pdf_are_the_mixture(lobe):
    wo, wi = _pairs(1)
    w = 0.35
    retro = Retroreflective(lobe, w)
    same = wo[:, 2] * wi[:, 2] > 0.0
    expected = np.where(same[:, None], (1 - w) * lobe.eval(wo, wi) + w * lobe.eval(wo, wi * TURN),
                        lobe.eval(wo, wi))
    np.testing.assert_allclose(retro.eval(wo, wi), expected, rtol=1e-13, atol=1e-300)
    expected = np.where(same, (1 - w) * lobe.pdf(wo, wi) + w * lobe.pdf(wo, wi * TURN),
                        lobe.pdf(wo, wi))
    np.testing.assert_allclose(retro.pdf(wo, wi), expected, rtol=1e-13, atol=1e-300)
    np.testing.assert_array_equal(Retroreflective(lobe, 0.0).eval(wo, wi), lobe.eval(wo, wi))


def test_a_full_retroreflector_peaks_at_the_viewer():
    """w = 1: the smooth-ish conductor's peak is wo itself, not its mirror."""
    lobe = Retroreflective(Conductor(0.05), 1.0)
    wo = np.array([0.6, 0.0, 0.8])
    assert lobe.eval(wo, wo)[0] > 100.0 * lobe.eval(wo, wo * [-1, -1, 1])[0]
    s = lobe.sample(wo, np.array([0.3, 0.4, 0.6]))
    assert s.wi @ wo > 0.95


@pytest.mark.parametrize("lobe", [Conductor(0.3, 0.1), DielectricMS(1.5, 0.4)])
def test_albedo_is_the_lobe_s(lobe):
    """The turn keeps cosines and solid angles: the same energy (quadrature of each)."""
    wo = np.array([[0.3, 0.2, np.sqrt(0.87)], [0.8, 0.1, np.sqrt(0.35)],
                   [0.1, 0.0, -np.sqrt(0.99)]])
    np.testing.assert_allclose(Retroreflective(lobe, 0.6).albedo(wo, tol=1e-7),
                               lobe.albedo(wo, tol=1e-7), atol=2e-6)


@pytest.mark.parametrize("cos_theta", [0.9, 0.3, -0.6])
def test_sampling(cos_theta):
    assert_sampling_matches(Retroreflective(DielectricMS(1.5, 0.3, 0.15), 0.4), cos_theta, 0.7,
                            seed=11, n_tests=3)


def test_smooth_retroreflection_is_a_delta_back_to_the_viewer():
    lobe = Retroreflective(ab.lobes.Dielectric(1.5, 0.0), 1.0)
    wo = np.array([0.6, 0.0, 0.8])
    u = np.array([[0.5, 0.01, 0.5]] * 4)
    u[:, 0] = [0.1, 0.3, 0.6, 0.9]
    s = lobe.sample(wo, u)
    reflected = s.wi[:, 2] > 0
    np.testing.assert_allclose(s.wi[reflected], np.broadcast_to(wo, s.wi[reflected].shape),
                               atol=1e-15)


def test_reciprocal():
    """Reciprocal where the lobe is (a GGX lobe is symmetric under the turn of both
    directions), anisotropic included."""
    wo, wi = _pairs(3, 2000)
    for lobe in (Conductor(0.3, 0.1), DielectricMS(1.5, 0.4, 0.2)):
        assert checks.reciprocity_error(Retroreflective(lobe, 0.5), wo, wi,
                                        rtol=1e-10).passed


def test_bad_input():
    with pytest.raises(ValueError, match="weight = 1.5"):
        Retroreflective(Conductor(0.3), 1.5)
    with pytest.raises(ValueError, match="lobe = 0.3"):
        Retroreflective(0.3, 0.5)
