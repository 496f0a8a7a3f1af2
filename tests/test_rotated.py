"""``Rotated``: the ASM anisotropy rotation [Kutz2021, §3] of the conductor and dielectric."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import adobe_bsdf as ab
from adobe_bsdf.composition import Rotated
from adobe_bsdf.lobes import Conductor, Dielectric
from adobe_bsdf.validation import checks
from adobe_bsdf.validation import strategies as vs
from adobe_bsdf.validation.chi2 import chi2_test
from tests.tolerances import CHI2_ALPHA, EXACT, RECIPROCITY, WEIGHT


def _pairs(n=2000, seed=1):
    rng = np.random.default_rng(seed)
    return ab.frame.normalize(rng.normal(size=(2, n, 3)))


def test_zero_rotation_is_the_lobe_bit_for_bit():
    """phi = 0 passes directions unturned: eval, pdf and every field of sample are the
    lobe's own bits, signed zeros included, and the caller's arrays stay writeable."""
    wo, wi = _pairs()
    wo[:3, :2] = [[-0.0, 0.6], [0.6, -0.0], [-0.0, -0.0]]
    wo[:3] = ab.frame.normalize(np.where(np.arange(3)[:, None] == 2, [[-0.0, -0.0, 1.0]], wo[:3]))
    u = np.random.default_rng(2).random((len(wo), 3))
    for lobe in (Conductor(0.5, 0.1), Dielectric(1.5, 0.3, 0.05)):
        turned = Rotated(lobe, 0.0)
        np.testing.assert_array_equal(turned.eval(wo, wi), lobe.eval(wo, wi))
        np.testing.assert_array_equal(turned.pdf(wo, wi), lobe.pdf(wo, wi))
        for a, b in zip(turned.sample(wo, u), lobe.sample(wo, u), strict=True):
            assert a.tobytes() == b.tobytes()
    assert wo.flags.writeable and wi.flags.writeable


def test_quarter_turn_swaps_the_alphas():
    """Turning the x axis by pi/2 is the lobe with alpha_x and alpha_y exchanged."""
    wo, wi = _pairs()
    for make in (lambda ax, ay: Conductor(ax, ay), lambda ax, ay: Dielectric(1 / 1.3, ax, ay)):
        turned, swapped = Rotated(make(0.5, 0.1), np.pi / 2), make(0.1, 0.5)
        np.testing.assert_allclose(turned.eval(wo, wi), swapped.eval(wo, wi), rtol=EXACT)
        np.testing.assert_allclose(turned.pdf(wo, wi), swapped.pdf(wo, wi), rtol=EXACT)


def test_full_turn_leaves_eval_unchanged():
    """Acceptance 4: rotation by 2 pi (and by the ASM parameter 1) changes eval by < 1e-12."""
    wo, wi = _pairs()
    for lobe in (Conductor(0.5, 0.1), Dielectric(1.5, 0.3, 0.05)):
        for phi in (2 * np.pi, float(ab.materials.asm.anisotropy_rotation(1.0))):
            np.testing.assert_allclose(Rotated(lobe, phi).eval(wo, wi), lobe.eval(wo, wi),
                                       rtol=1e-12)


@settings(max_examples=100, deadline=None)
@given(alpha=vs.alpha_pairs(), phi=st.floats(-10.0, 10.0), eta=vs.iors(),
       pair=vs.direction_pairs("any"))
def test_reciprocity(alpha, phi, eta, pair):
    """Reciprocity to 1e-12, generalized across the dielectric interface."""
    for lobe in (Conductor(*alpha), Dielectric(eta, *alpha)):
        result = checks.reciprocity_error(Rotated(lobe, phi), *pair, rtol=RECIPROCITY)
        assert result.passed, result


CHI2_CASES = [(kind, phi, c) for kind in ("conductor", "dielectric")
              for phi in (0.0, np.pi / 3, np.pi / 2) for c in (0.9, 0.3, -0.6)
              if not (kind == "conductor" and c < 0)]


@pytest.mark.parametrize(("kind", "phi", "cos_theta"), CHI2_CASES)
def test_chi2_at_three_rotations(kind, phi, cos_theta):
    """sample against pdf at rotations 0, pi/3, pi/2 (p > 0.01 after Šidák)."""
    lobe = Rotated(Conductor(0.5, 0.08) if kind == "conductor" else Dielectric(1.5, 0.4, 0.08),
                   phi)
    s = np.sqrt(1 - cos_theta**2)
    wo = np.array([s * np.cos(0.3), s * np.sin(0.3), cos_theta])
    result = chi2_test(lobe, wo, n_samples=500_000, seed=CHI2_CASES.index((kind, phi, cos_theta)),
                       alpha=CHI2_ALPHA, n_tests=len(CHI2_CASES))
    assert result.passed, str(result)
    weights = checks.weight_consistency(lobe, wo, n_samples=20_000, rtol=WEIGHT)
    assert weights.passed, weights


def test_albedo_does_not_depend_on_the_rotation():
    """Turning the lobe and wo together keeps the albedo: the cubature of the turned lobe's
    own eval (``quadrature.albedo``; ``Rotated.albedo`` itself integrates the inner lobe)."""
    lobe = Conductor(0.6, 0.05)
    wo = np.array([0.6, 0.0, 0.8])
    phi = 0.7
    turned = np.array([0.6 * np.cos(phi), 0.6 * np.sin(phi), 0.8])
    direct = ab.quadrature.albedo(Rotated(lobe, phi), turned, tol=1e-9)[0]
    np.testing.assert_allclose(direct, lobe.albedo(wo, tol=1e-9), atol=1e-8)
    np.testing.assert_allclose(Rotated(lobe, phi).albedo(turned, tol=1e-9), direct, atol=1e-8)


def test_bad_input():
    with pytest.raises(ValueError, match="phi"):
        Rotated(Conductor(0.3), np.nan)
    with pytest.raises(ValueError, match="lobe"):
        Rotated("conductor", 0.0)
    with pytest.raises(ValueError, match="anisotropy_angle"):
        ab.materials.asm.anisotropy_rotation(1.5)
