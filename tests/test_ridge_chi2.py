"""Chi-square of razor-thin anisotropic lobes (ASM roughness 0, anisotropy 1) through
``validation.stretch``.

alpha_x = r^2 + a^4 = 1, alpha_y = ALPHA_MIN = 1e-8 [Kutz2021, eqs. 9-10]: the lobe's directions
lie within ~1e-8 rad of the plane spanned by its tangent and the normal. ``Stretched`` maps the
sphere by w -> A w / |A w| with the exact Jacobian |det A| / |A w|^3, so a chi-square test of the
mapped lobe is a test of the lobe; ``ridge_stretch(phi, 1e7)`` makes the ridge ~0.2 rad wide.
"""

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.validation import checks
from adobe_bsdf.validation.chi2 import chi2_test
from adobe_bsdf.validation.stretch import Stretched, ridge_stretch
from tests.tolerances import CHI2_ALPHA, EXACT, WEIGHT

GOLD = ab.materials.presets.metals["Au"]
F0, TINT = GOLD["base_color"], GOLD["specular_edge_color"]
#: across-ridge stretch: alpha_y = 1e-8 becomes a slope width of 0.1
FACTOR = 1e7
#: a general invertible matrix (shear, scale, tilt of z) for the Jacobian tests
MATRIX = np.array([[1.0, 0.4, 0.2], [-0.3, 2.0, 0.1], [0.1, -0.2, 0.7]])
#: p-value below which a deliberately wrong pdf must be rejected
REJECT = 1e-6

# (kind, ASM anisotropy_angle, cos theta_o); phi = 2 pi angle in {0, pi/3, pi/2}
RIDGE_CASES = ([("metal", angle, c) for angle in (0.0, 1 / 6, 0.25) for c in (0.9, 0.4)]
               + [("dielectric", angle, c) for angle in (0.0, 1 / 6, 0.25)
                  for c in (0.9, 0.4, -0.6)])
#: chi-square tests of this file that must pass: the Šidák family
N_CHI2 = len(RIDGE_CASES) + 1


def _in_plane(phi, cos_theta):
    """wo = (sin t cos phi, sin t sin phi, cos t): in the lobe's stretched plane."""
    s = np.sqrt(1.0 - cos_theta**2)
    return np.array([s * np.cos(phi), s * np.sin(phi), cos_theta])


def _ridge_lobe(kind, angle):
    if kind == "metal":
        return ab.materials.asm.asm_metal(F0, TINT, roughness=0.0,
                                          anisotropy_level=1.0, anisotropy_angle=angle)
    phi = float(ab.materials.asm.anisotropy_rotation(angle))
    alphas = ab.materials.asm.asm_alpha(0.0, 1.0)
    return ab.composition.Rotated(ab.lobes.Dielectric(1.5, *alphas), phi)


class _NoJacobian(Stretched):
    """Deliberately wrong: the mapped pdf without the factor |A w|^3 / |det A|."""

    def pdf(self, wo, wi):
        w, _ = self._preimage(np.asarray(wi, dtype=np.float64))
        return self.lobe.pdf(wo, w)


class _Mismatched:
    """Samples of one lobe, pdf of another (duck-typed)."""

    def __init__(self, sampler, density):
        self.sampler, self.density = sampler, density

    def sample(self, wo, u):
        return self.sampler.sample(wo, u)

    def pdf(self, wo, wi):
        return self.density.pdf(wo, wi)


def _triangle_solid_angle(a, b, c):
    """Solid angle of the spherical triangle of unit vectors a, b, c [VanOosteromStrackee1983]."""
    num = np.abs(np.einsum("...i,...i", a, np.cross(b, c)))
    den = 1.0 + np.einsum("...i,...i", a, b) + np.einsum("...i,...i", b, c) + np.einsum(
        "...i,...i", c, a)
    return 2.0 * np.arctan2(num, den)


# -- the change of variables ------------------------------------------------------------------
def test_ridge_stretch_matrix():
    phi = 0.7
    a = ridge_stretch(phi, 5.0)
    in_plane = np.array([np.cos(phi), np.sin(phi), 0.0])
    across = np.array([-np.sin(phi), np.cos(phi), 0.0])
    np.testing.assert_allclose(a @ in_plane, in_plane, atol=EXACT)
    np.testing.assert_allclose(a @ across, 5.0 * across, atol=EXACT)
    np.testing.assert_allclose(a @ [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], atol=EXACT)
    np.testing.assert_allclose(np.linalg.det(a), 5.0, rtol=EXACT)


def test_jacobian_against_small_triangles():
    """|det A| / |A w|^3 is the ratio of the solid angles of small triangles and their images."""
    rng = np.random.default_rng(0)
    w = ab.frame.normalize(rng.normal(size=(200, 3)))
    t1 = ab.frame.normalize(np.cross(w, rng.normal(size=(200, 3))))
    t2 = np.cross(w, t1)
    eps = 1e-4
    corners = [w, ab.frame.normalize(w + eps * t1), ab.frame.normalize(w + eps * t2)]
    images = [ab.frame.normalize(c @ MATRIX.T) for c in corners]
    ratio = _triangle_solid_angle(*images) / _triangle_solid_angle(*corners)
    expected = abs(np.linalg.det(MATRIX)) / np.linalg.norm(w @ MATRIX.T, axis=-1) ** 3
    np.testing.assert_allclose(ratio, expected, rtol=1e-3)  # O(eps) from the triangles' size


def test_stretched_lambert_keeps_its_mass():
    """The mapped pdf of Lambert (cos / pi) integrates to 1, as the original."""
    result = checks.pdf_integral(Stretched(ab.lobes.Lambert(), MATRIX), _in_plane(0.3, 0.8),
                                 expected=1.0, tol=1e-6)
    assert result.passed, result


def test_stretched_lambert_chi2_passes():
    """sample against pdf of Stretched(Lambert, general A): the Jacobian is right."""
    result = chi2_test(Stretched(ab.lobes.Lambert(), MATRIX), _in_plane(0.3, 0.8),
                       n_samples=300_000, seed=1000, alpha=CHI2_ALPHA, n_tests=N_CHI2)
    assert result.passed, str(result)


def test_chi2_rejects_the_missing_jacobian():
    """The same setup without the Jacobian factor is rejected by the statistic itself."""
    result = chi2_test(_NoJacobian(ab.lobes.Lambert(), MATRIX), _in_plane(0.3, 0.8),
                       n_samples=300_000, seed=1000)
    assert result.p_value < REJECT, str(result)
    assert result.n_invalid == result.n_zero_hits == result.n_bad_pdf == 0, str(result)


def test_chi2_resolves_the_ridge_width():
    """Power at the ridge's scale: samples with alpha_y = 1e-8 against the pdf of
    alpha_y = 1.05e-8 (a difference of 5e-10 in slope) are rejected."""
    phi = np.pi / 3
    sampler, density = (ab.composition.Rotated(ab.lobes.Dielectric(1.5, 1.0, ay), phi)
                        for ay in (1e-8, 1.05e-8))
    result = chi2_test(Stretched(_Mismatched(sampler, density), ridge_stretch(phi, FACTOR)),
                       _in_plane(phi, 0.8), n_samples=400_000, seed=1001)
    assert result.p_value < REJECT, str(result)


def test_stretched_sample_is_consistent_with_pdf_and_eval():
    """weight = eval |cos| / pdf and sample.pdf = pdf(wo, wi) hold for the mapped lobe."""
    lobe = Stretched(ab.lobes.Lambert(0.7), ridge_stretch(0.4, 3.0))
    result = checks.weight_consistency(lobe, _in_plane(0.3, 0.8), n_samples=20_000, rtol=WEIGHT)
    assert result.passed, result


def test_failed_samples_stay_failed():
    """Lambert fails for wo below the surface: zero wi, pdf 0, weight 0, flags kept."""
    u = np.random.default_rng(2).random((1000, 3))
    wo = _in_plane(0.0, -0.5)
    inner = ab.lobes.Lambert().sample(wo, u)
    s = Stretched(ab.lobes.Lambert(), MATRIX).sample(wo, u)
    for mapped in (s.wi, s.pdf, s.weight):
        assert np.all(mapped == 0.0)
    np.testing.assert_array_equal(s.flags, inner.flags)


def test_bad_input_is_named():
    lambert = ab.lobes.Lambert()
    for matrix in (np.zeros((3, 3)), [[1, 0, 0], [0, 1, 0], [1, 0, 0]], np.eye(2),
                   np.diag([1.0, np.nan, 1.0]), np.diag([1.0, 1e-20, 1.0])):
        with pytest.raises(ValueError, match="matrix"):
            Stretched(lambert, matrix)
    with pytest.raises(ValueError, match="lobe"):
        Stretched("lambert", np.eye(3))
    for factor in (0.0, -1.0, np.inf, np.nan):
        with pytest.raises(ValueError, match="factor"):
            ridge_stretch(0.0, factor)
    with pytest.raises(ValueError, match="phi"):
        ridge_stretch(np.nan, 2.0)
    with pytest.raises(ValueError, match="wi"):
        Stretched(lambert, np.eye(3)).pdf([0.0, 0.0, 1.0], [0.0, 0.0, 2.0])


# -- acceptance: roughness 0, anisotropy 1 ----------------------------------------------------
@pytest.mark.parametrize(("kind", "angle", "cos_theta"), RIDGE_CASES)
def test_ridge_chi2(kind, angle, cos_theta):
    """sample against pdf at r = 0, a = 1 (p > 0.01 after Šidák over the file), and the sample
    weights against eval / pdf of the unstretched lobe."""
    lobe = _ridge_lobe(kind, angle)
    phi = float(ab.materials.asm.anisotropy_rotation(angle))
    wo = _in_plane(phi, cos_theta)
    result = chi2_test(Stretched(lobe, ridge_stretch(phi, FACTOR)), wo, n_samples=400_000,
                       seed=RIDGE_CASES.index((kind, angle, cos_theta)), alpha=CHI2_ALPHA,
                       n_tests=N_CHI2)
    assert result.passed, str(result)
    assert result.dof > 500, f"the stretched ridge covers too few cells: {result}"

    weights = checks.weight_consistency(lobe, wo, n_samples=20_000, seed=1, rtol=WEIGHT)
    assert weights.max_weight_error <= WEIGHT, weights
    assert weights.n_invalid == weights.n_flag_mismatch == 0, weights
    assert weights.n_checked > 10_000, weights
    # sample.pdf = pdf(wo, wi) is checked in the lobe's own frame (where wo is
    # (sin t, 0, cos t)): through Rotated it holds only to ~eps / alpha_y, since wi stored in
    # the turned frame carries ~1e-16 absolute rounding on its ~1e-9 across-ridge component,
    # which moves the pdf by up to ~1e-7 relative (the weight, a ratio of eval and pdf at the
    # same wi, is unaffected).
    inner = checks.weight_consistency(lobe.lobe, _in_plane(0.0, cos_theta), n_samples=20_000,
                                      seed=1, rtol=WEIGHT)
    assert inner.passed, inner


def test_quadrature_albedo_warns_on_the_ridge():
    """The cubature cannot resolve a 1e-8 wide ridge; it says so (its guard samples' Monte-Carlo
    mean disagrees) instead of returning ~0 silently, and method="mc" sees the energy.

    The single-scattering term carries the ridge; the Kulla–Conty term beside it is smooth
    (1 - E(mu_o, phi_o)) and is not what this test is about."""
    metal = ab.materials.asm.asm_metal(1.0, 1.0, roughness=0.0, anisotropy_level=1.0)  # F = 1
    single = metal.lobe.components[0]
    assert isinstance(single, ab.lobes.Conductor)
    wo = _in_plane(0.0, 0.9)
    with pytest.warns(UserWarning, match="guard samples"):
        quad = single.albedo(wo)
    mc = single.albedo(wo, method="mc", n_samples=50_000)
    assert np.all(mc > 0.3) and np.all(quad < 1e-3)
