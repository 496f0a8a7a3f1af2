"""Phase functions: densities on the sphere, sampled exactly, with the extinction they imply;
the fibre microflakes against closed forms and independent quadrature."""

import numpy as np
import pytest
from scipy import integrate

from adobe_bsdf.phase import FibreMicroflakes, HenyeyGreenstein
from adobe_bsdf.validation import FunctionCandidate, chi2_test

WO = [np.array([0.6, 0.0, 0.8]), np.array([0.3, -0.2, -np.sqrt(0.87)]),
      np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])]


def _sphere_integral(fn):
    """int over the sphere of ``fn(w)`` (w (..., 3)) by scipy's adaptive quadrature in
    (cos theta, phi)."""
    def integrand(phi, c):
        s = np.sqrt(max(0.0, 1.0 - c * c))
        return float(fn(np.array([s * np.cos(phi), s * np.sin(phi), c])))
    value, _ = integrate.dblquad(integrand, -1.0, 1.0, 0.0, 2.0 * np.pi, epsabs=1e-8,
                                 epsrel=1e-8)
    return value


@pytest.mark.parametrize("r", [0.3, 0.7])
@pytest.mark.parametrize("k", range(3))
def test_fibre_phase_is_a_density(r, k):
    phase = FibreMicroflakes(r)
    assert _sphere_integral(lambda w: phase.eval(WO[k], w)) == pytest.approx(1.0, abs=2e-6)


@pytest.mark.parametrize("r", [0.2, 0.6])
def test_projected_area_is_the_flakes_visible_area(r):
    """sigma(w) = int <w, m>_+ D(m) dm [Heitz2015, eq. 4], D integrated independently."""
    phase = FibreMicroflakes(r)
    for w in WO:
        area = _sphere_integral(lambda m, w=w: max(float(m @ w), 0.0) * phase._D(m))
        assert area == pytest.approx(float(phase.sigma(w)), rel=1e-6)


def test_spherical_flakes_scatter_uniformly():
    """r = 1: S = I, a medium of mirror spheres, whose phase function is 1 / (4 pi)."""
    phase = FibreMicroflakes(1.0)
    rng = np.random.default_rng(1)
    wi = rng.normal(size=(100, 3))
    wi /= np.linalg.norm(wi, axis=-1)[:, None]
    for wo in WO:
        np.testing.assert_allclose(phase.eval(wo, wi), 1.0 / (4.0 * np.pi), rtol=1e-12)
        np.testing.assert_allclose(phase.sigma(wo), 1.0, rtol=1e-15)


def test_sigma_times_phase_is_reciprocal():
    phase = FibreMicroflakes(0.35)
    rng = np.random.default_rng(2)
    a, b = (x / np.linalg.norm(x, axis=-1)[:, None] for x in rng.normal(size=(2, 200, 3)))
    np.testing.assert_allclose(phase.sigma(a) * phase.eval(a, b),
                               phase.sigma(b) * phase.eval(b, a), rtol=1e-12)


def _candidate(phase):
    def sample(wo, u):
        wi, pdf = phase.sample(wo, u[..., :2])
        return wi, np.ones(wi.shape[:-1]), pdf
    return FunctionCandidate(lambda wo, wi: phase.eval(wo, wi), phase.eval, sample,
                             name=repr(phase))


@pytest.mark.parametrize("phase", [FibreMicroflakes(0.1), FibreMicroflakes(0.5),
                                   HenyeyGreenstein(0.6)], ids=repr)
def test_phase_samples_follow_the_density(phase):
    """Pearson's chi-square over the sphere (Sidak over the views), and each sample's pdf is
    the density at its direction."""
    for k, wo in enumerate(WO):
        result = chi2_test(_candidate(phase), wo, n_samples=200_000, n_theta=32, n_phi=64,
                           seed=k, n_tests=len(WO))
        assert result.passed, result
        wi, pdf = phase.sample(np.broadcast_to(wo, (1000, 3)),
                               np.random.default_rng(k).random((1000, 2)))
        np.testing.assert_allclose(np.linalg.norm(wi, axis=-1), 1.0, atol=1e-12)
        np.testing.assert_allclose(pdf, phase.eval(wo, wi), rtol=1e-12)


def test_bad_input():
    for r in (0.0, -0.1, 1.5, np.nan):
        with pytest.raises(ValueError, match="roughness = "):
            FibreMicroflakes(r)
    with pytest.raises(ValueError, match="g = 1.0"):
        HenyeyGreenstein(1.0)
