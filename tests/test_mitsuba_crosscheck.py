"""Cross-check of the GGX conductor and dielectric lobes against Mitsuba 3 (``scalar_rgb``).

Two groups of tests:

- *adapter checks* validate ``adobe_bsdf.validation.mitsuba`` on its own, independently of
  the lobes: a closed-form albedo, a float64 transcription of the GGX formulas, the
  generalized reciprocity of the converted dielectric and its energy balance;
- *cross-checks* compare ``ab.lobes.Conductor`` and ``ab.lobes.Dielectric`` (with
  ``masking="separable"``, Mitsuba's G1·G1) with Mitsuba's ``roughconductor`` and
  ``roughdielectric`` at ``N_PAIRS`` random direction pairs per configuration: eval and pdf
  must agree to ``RTOL`` relative where both are non-zero, and be zero at the same pairs.

Exclusion: Mitsuba computes in float32, so the pairs come from ``crosscheck_pairs``, which
draws directions that are float32 numbers (both libraries see the same input) and rejects the
pairs where float32 is ill conditioned (``well_conditioned``): ``|cos|`` of ``wo``, ``wi`` or
the microfacet normal ``m`` with the normal below ``MIN_COS`` (1e-3), ``|wo.m|`` or ``|wi.m|``
below ``MIN_COS_M`` (0.05), a float32 vector's deviation from unit length amplified by a small
``wo.m`` beyond ``MAX_UNIT_DEFECT``, and, for the dielectric, ``|cos^2 theta_t|`` below
``MIN_COS2_T`` (0.1; near total internal reflection). Inside those sets Mitsuba's float32
error grows to 1e-4 and, within about 1e-6 of the critical angle, to O(1) (the module
docstring of ``adobe_bsdf.validation.mitsuba`` has the measurements); outside them it stays
below 5e-6.

The measured maximum relative differences are kept in ``MEASURED`` (configuration ->
``{"eval": ..., "pdf": ..., "pairs": ...}``), attached to the JUnit report with
``record_property`` and printed (``pytest -s``).
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.validation import mitsuba as mts
from tests.tolerances import MITSUBA as RTOL

mi = pytest.importorskip("mitsuba", reason="the Mitsuba cross-check needs mitsuba (test extra)")

#: direction pairs drawn per configuration
N_PAIRS = 2000
#: pairs per configuration at which both libraries must be non-zero
MIN_NONZERO = 1000
#: values below the smallest normal float32 count as zero when comparing zero patterns
FLOAT32_TINY = float(np.finfo(np.float32).tiny)

#: (alpha_x, alpha_y): three isotropic roughnesses and two anisotropic pairs
ALPHAS = [(0.05, 0.05), (0.3, 0.3), (1.0, 1.0), (0.05, 0.3), (0.5, 0.1)]
#: RGB complex indices (eta, k): gold-like values, and copper (pbrt-v4's data) and iron
#: [JohnsonChristy1974] at 650/550/450 nm; ``None``: a perfect mirror (F = 1)
METALS = {
    "gold": ((0.143, 0.374, 1.442), (3.983, 2.385, 1.603)),
    "copper": ((0.2166, 0.9582, 1.1658), (3.6377, 2.5771, 2.3939)),
    "iron": ((2.9114, 2.9497, 2.5845), (3.0893, 2.9318, 2.767)),
    "mirror": None,
}
#: dielectrics as (eta = n_below / n_above, Mitsuba's ext_ior): glass below air, and air
#: below glass told to Mitsuba as int_ior = 1, ext_ior = 1.5
DIELECTRICS = {"eta=1.5": (1.5, 1.0), "eta=1/1.5": (1.0 / 1.5, 1.5)}

#: measured maximum relative differences, per configuration
MEASURED: dict[str, dict[str, float]] = {}


# -- an independent float64 transcription of the GGX formulas --------------------------------
def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def _ggx_d(m, ax, ay):
    return 1.0 / (
        np.pi * ax * ay * ((m[..., 0] / ax) ** 2 + (m[..., 1] / ay) ** 2 + m[..., 2] ** 2) ** 2
    )


def _smith_g1(v, m, ax, ay):
    tan2 = ((ax * v[..., 0]) ** 2 + (ay * v[..., 1]) ** 2) / v[..., 2] ** 2
    return np.where(_dot(v, m) * v[..., 2] > 0, 2.0 / (1.0 + np.sqrt(1.0 + tan2)), 0.0)


def _fresnel_dielectric(cos_o, ratio):
    """Unpolarised Fresnel reflectance at |cos_o| into the medium ``ratio = eta_t / eta_o``."""
    cos_o = np.abs(cos_o)
    cos2_t = 1.0 - (1.0 - cos_o**2) / ratio**2
    cos_t = np.sqrt(np.maximum(cos2_t, 0.0))
    r_s = (cos_o - ratio * cos_t) / (cos_o + ratio * cos_t)
    r_p = (ratio * cos_o - cos_t) / (ratio * cos_o + cos_t)
    return np.where(cos2_t > 0, 0.5 * (r_s**2 + r_p**2), 1.0)


def _reference(wo, wi, ax, ay, eta=None):
    """Radiance-mode f (no cosine) and pdf: a mirror conductor (F = 1) or a dielectric.

    [Walter2007] with separable Smith masking, visible-normal sampling [Heitz2018] and
    pbrt-v4's radiance-mode transmission ``eta_o^2 (1 - F) D G |wo.m wi.m| /
    (|wo_z wi_z| (eta_o wo.m + eta_i wi.m)^2)``.
    """
    reflect = wo[..., 2] * wi[..., 2] > 0
    ratio = np.where(wo[..., 2] > 0, 1.0 if eta is None else eta, 1.0 if eta is None else 1 / eta)
    h = wo + np.where(reflect, 1.0, ratio)[..., None] * wi
    m = h / np.linalg.norm(h, axis=-1, keepdims=True)
    m = m * np.sign(m[..., 2:])
    cos_o, cos_i = _dot(wo, m), _dot(wi, m)
    fresnel = 1.0 if eta is None else _fresnel_dielectric(cos_o, ratio)
    d = _ggx_d(m, ax, ay)
    g1_o = _smith_g1(wo, m, ax, ay)
    g = g1_o * _smith_g1(wi, m, ax, ay)
    abs_o, abs_i = np.abs(wo[..., 2]), np.abs(wi[..., 2])
    denominator = cos_o + ratio * cos_i
    f_r = fresnel * d * g / (4.0 * abs_o * abs_i)
    f_t = (1.0 - fresnel) * d * g * np.abs(cos_o * cos_i) / (abs_o * abs_i * denominator**2)
    visible = g1_o * np.abs(cos_o) * d / abs_o
    jacobian = np.where(
        reflect, 1.0 / (4.0 * np.abs(cos_i)), ratio**2 * np.abs(cos_i) / denominator**2
    )
    pdf = visible * jacobian * np.where(reflect, fresnel, 1.0 - fresnel)
    if eta is None:
        valid = reflect & (wo[..., 2] > 0)
        return np.where(valid, f_r, 0.0), np.where(valid, pdf, 0.0)
    return np.where(reflect, f_r, f_t), np.where(g > 0, pdf, 0.0)


# -- comparison --------------------------------------------------------------------------------
def _compare(name, ours, theirs, wo, wi):
    """Max relative difference where both are non-zero; fail on a differing zero pattern."""
    ours, theirs = np.broadcast_arrays(np.asarray(ours, float), np.asarray(theirs, float))
    assert np.all(np.isfinite(ours)) and np.all(np.isfinite(theirs)), f"{name}: not finite"
    big = np.maximum(np.abs(ours), np.abs(theirs))
    both = (ours != 0) & (theirs != 0)
    one = ((ours == 0) != (theirs == 0)) & (big > FLOAT32_TINY)
    one_pair = one.reshape(len(wo), -1).any(axis=-1)
    assert not one_pair.any(), (
        f"{name}: zero at {one_pair.sum()} pairs in one library only, e.g. "
        + "; ".join(
            f"wo={wo[j]}, wi={wi[j]}: ours={ours[j]}, mitsuba={theirs[j]}"
            for j in np.flatnonzero(one_pair)[:3]
        )
    )
    rel = np.zeros_like(big)
    rel[both] = np.abs(ours[both] - theirs[both]) / big[both]
    worst = np.unravel_index(np.argmax(rel), rel.shape)[0]
    detail = (
        f"{name}: max relative difference {rel.max():.3e} at wo={wo[worst]}, "
        f"wi={wi[worst]}: ours={ours[worst]}, mitsuba={theirs[worst]}"
    )
    return float(rel.max()), int(both.reshape(len(wo), -1).all(axis=-1).sum()), detail


def _crosscheck(key, ours, theirs, wo, wi, record_property):
    eval_rel, nonzero, eval_detail = _compare(
        f"{key} eval", ours.eval(wo, wi), theirs.eval(wo, wi), wo, wi
    )
    pdf_rel, _, pdf_detail = _compare(f"{key} pdf", ours.pdf(wo, wi), theirs.pdf(wo, wi), wo, wi)
    MEASURED[key] = {"eval": eval_rel, "pdf": pdf_rel, "pairs": nonzero}
    record_property("max_rel_eval", eval_rel)
    record_property("max_rel_pdf", pdf_rel)
    record_property("nonzero_pairs", nonzero)
    print(f"\n{key}: max rel eval {eval_rel:.2e}, pdf {pdf_rel:.2e} over {nonzero} pairs")
    assert nonzero >= MIN_NONZERO, f"{key}: only {nonzero} non-zero pairs"
    assert eval_rel <= RTOL, eval_detail
    assert pdf_rel <= RTOL, pdf_detail


# -- adapter checks (independent of the lobes) ---------------------------------------------------
def test_adapter_imports_without_mitsuba():
    code = "import sys; sys.modules['mitsuba'] = None; import adobe_bsdf.validation.mitsuba"
    subprocess.run([sys.executable, "-c", code], check=True)


def test_adapter_mirror_conductor_albedo_at_normal_incidence():
    """alpha = 1, F = 1, wo = n: integral of f cos over the hemisphere is 1 - ln 2."""
    bsdf = mts.mitsuba_conductor(1.0)
    x, weights = np.polynomial.legendre.leggauss(64)
    mu = 0.5 * (x + 1.0)
    wi = np.stack([np.sqrt(1.0 - mu**2), np.zeros_like(mu), mu], axis=-1)
    f = bsdf.eval(np.array([0.0, 0.0, 1.0]), wi)
    albedo = 2.0 * np.pi * 0.5 * np.sum(weights[:, None] * f * mu[:, None], axis=0)
    np.testing.assert_allclose(albedo, 1.0 - np.log(2.0), rtol=RTOL)


@pytest.mark.parametrize("alpha", [(0.05, 0.3), (0.5, 0.1), (1.0, 1.0)], ids=str)
@pytest.mark.parametrize("eta", [None, *DIELECTRICS], ids=str)
def test_adapter_matches_float64_formulas(alpha, eta):
    """Converted Mitsuba values = float64 GGX formulas (so alpha_u is our alpha_x)."""
    if eta is None:
        bsdf, eta_value = mts.mitsuba_conductor(*alpha), None
    else:
        eta_value, ext_ior = DIELECTRICS[eta]
        bsdf = mts.mitsuba_dielectric(eta_value, *alpha, ext_ior=ext_ior)
    wo, wi = mts.crosscheck_pairs(N_PAIRS, *alpha, eta_value, rng=1)
    f, pdf = _reference(wo, wi, *alpha, eta_value)
    eval_rel, nonzero, detail = _compare("eval", f[:, None], bsdf.eval(wo, wi), wo, wi)
    assert nonzero >= MIN_NONZERO
    assert eval_rel <= RTOL, detail
    pdf_rel, _, detail = _compare("pdf", pdf, bsdf.pdf(wo, wi), wo, wi)
    assert pdf_rel <= RTOL, detail


@pytest.mark.parametrize("eta", DIELECTRICS)
def test_adapter_dielectric_generalized_reciprocity(eta):
    """f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2 for the converted values."""
    eta_value, ext_ior = DIELECTRICS[eta]
    bsdf = mts.mitsuba_dielectric(eta_value, 0.3, 0.1, ext_ior=ext_ior)
    wo, wi = mts.crosscheck_pairs(N_PAIRS, 0.3, 0.1, eta_value, rng=2)
    keep = mts.well_conditioned(wi, wo, eta_value)
    wo, wi = wo[keep], wi[keep]
    assert np.any(wo[:, 2] * wi[:, 2] < 0)

    def index(w):
        return np.where(w[:, 2] > 0, 1.0, eta_value)[:, None]

    forward = bsdf.eval(wo, wi) / index(wo) ** 2
    backward = bsdf.eval(wi, wo) / index(wi) ** 2
    rel, _, detail = _compare("reciprocity", forward, backward, wo, wi)
    assert rel <= RTOL, detail


@pytest.mark.parametrize(
    ("eta", "theta", "side"),
    [
        ("eta=1.5", 0.0, 1.0),
        ("eta=1.5", 1.0, -1.0),
        ("eta=1/1.5", 1.0, 1.0),
        ("eta=1/1.5", 0.0, -1.0),
    ],
)
def test_adapter_dielectric_energy(eta, theta, side):
    """Energy R + T = integral of f (eta_i/eta_o)^2 |cos theta_i| is <= 1 and matches
    Mitsuba's own sampling weights (times ``bs.eta^2``, as its integrators undo the radiance
    scale). Leaving an eta^2 in or out of the conversion would change T by a factor 2.25."""
    eta_value, ext_ior = DIELECTRICS[eta]
    bsdf = mts.mitsuba_dielectric(eta_value, 0.3, 0.1, ext_ior=ext_ior)
    wo = np.array([np.sin(theta), 0.0, side * np.cos(theta)])
    n = 160
    x, weights = np.polynomial.legendre.leggauss(n)
    mu = np.concatenate([0.5 * (x + 1.0), -0.5 * (x + 1.0)])
    weights = np.concatenate([weights, weights]) * 0.5 * 2.0 * np.pi / n
    phi = (np.arange(n) + 0.5) * 2.0 * np.pi / n
    sin = np.sqrt(1.0 - mu**2)[:, None]
    wi = np.stack(np.broadcast_arrays(sin * np.cos(phi), sin * np.sin(phi), mu[:, None]), -1)
    ratio = np.where(wo[2] * wi[..., 2] > 0, 1.0, eta_value if side > 0 else 1.0 / eta_value)
    f = bsdf.eval(wo, wi)[..., 0]
    quadrature = np.sum(weights[:, None] * f * ratio**2 * np.abs(wi[..., 2]))

    rng = np.random.default_rng(3)
    ctx, si = mi.BSDFContext(), mi.SurfaceInteraction3f()
    si.wi = mi.ScalarVector3f(wo.tolist())
    samples = []
    for u1, u2, u3 in rng.random((20_000, 3)).tolist():
        bs, weight = bsdf.bsdf.sample(ctx, si, u1, mi.ScalarPoint2f(u2, u3))
        samples.append(weight[0] * bs.eta**2)
    mean, error = np.mean(samples), np.std(samples) / np.sqrt(len(samples))
    assert 0.8 < quadrature <= 1.0
    assert abs(quadrature - mean) <= 4.0 * error + 1e-3, (quadrature, mean, error)


# -- cross-checks of the lobes -------------------------------------------------------------------
@pytest.mark.parametrize("alpha", ALPHAS, ids=str)
@pytest.mark.parametrize("metal", METALS)
def test_conductor_matches_mitsuba(metal, alpha, record_property):
    if METALS[metal] is None:
        ours = ab.lobes.Conductor(*alpha, masking="separable")
        theirs = mts.mitsuba_conductor(*alpha)
    else:
        eta, k = (np.array(v) for v in METALS[metal])
        ours = ab.lobes.Conductor(
            *alpha, fresnel=lambda c: ab.fresnel.conductor(c, eta, k), masking="separable"
        )
        theirs = mts.mitsuba_conductor(*alpha, eta=eta, k=k)
    wo, wi = mts.crosscheck_pairs(N_PAIRS, *alpha, rng=10)
    _crosscheck(f"conductor {metal} alpha={alpha}", ours, theirs, wo, wi, record_property)


@pytest.mark.parametrize("alpha", ALPHAS, ids=str)
@pytest.mark.parametrize("eta", DIELECTRICS)
def test_dielectric_matches_mitsuba(eta, alpha, record_property):
    eta_value, ext_ior = DIELECTRICS[eta]
    ours = ab.lobes.Dielectric(eta_value, *alpha, masking="separable")
    theirs = mts.mitsuba_dielectric(eta_value, *alpha, ext_ior=ext_ior)
    wo, wi = mts.crosscheck_pairs(N_PAIRS, *alpha, eta_value, rng=11)
    reflect = wo[:, 2] * wi[:, 2] > 0
    assert reflect.any() and (~reflect).any() and (wo[:, 2] < 0).any()
    _crosscheck(f"dielectric {eta} alpha={alpha}", ours, theirs, wo, wi, record_property)


#: the Beckmann lobes against Mitsuba's ``distribution = "beckmann"`` [Barla2018, Table 2]
BECKMANN_ALPHAS = [(0.05, 0.05), (0.3, 0.3), (0.5, 0.1)]
#: largest exponent e = ((mx/ax)^2 + (my/ay)^2) / mz^2 of a compared pair: float32's exp(-e)
#: carries a relative error ~ e 2^-24 (1e-5 at e = 45, measured), and Mitsuba drops D in the
#: far tail (zeros measured at D(m) cos^2 theta_m up to 8e-21, e > 40)
BECKMANN_MAX_EXPONENT = 20.0


class _WalterMasking:
    """Mitsuba's Beckmann G1 is the rational approximation of [Walter2007, eq. 27],
    (3.535 a + 2.181 a^2) / (1 + 2.276 a + 2.577 a^2) for a = 1 / (alpha tan theta) < 1.6,
    else 1 (0.35% from the exact Smith G1). Our values are multiplied by G1_Walter / G1 of
    each direction (``rescale``) so that the comparison tests everything else exactly."""

    def __init__(self, alpha):
        self.alpha, self.exact = alpha, ab.Beckmann(*alpha)

    def ratio(self, w):
        a = np.abs(w[:, 2]) / np.hypot(self.alpha[0] * w[:, 0], self.alpha[1] * w[:, 1])
        walter = np.where(a < 1.6, (3.535 * a + 2.181 * a * a) / (1 + 2.276 * a + 2.577 * a * a),
                          1.0)
        return walter / self.exact.G1(w)

    def rescale(self, lobe):
        ratio = self.ratio

        class Rescaled:
            def eval(self, wo, wi):
                return lobe.eval(wo, wi) * (ratio(wo) * ratio(wi))[:, None]

            def pdf(self, wo, wi):
                return lobe.pdf(wo, wi) * ratio(wo)

        return Rescaled()


def _beckmann_pairs(alpha, eta, rng):
    """``crosscheck_pairs`` with exponent e <= ``BECKMANN_MAX_EXPONENT``."""
    wo, wi = mts.crosscheck_pairs(2 * N_PAIRS, *alpha, eta, rng=rng)
    m, _ = mts._half_vector(wo, wi, 1.0 if eta is None else eta)
    e = ((m[:, 0] / alpha[0]) ** 2 + (m[:, 1] / alpha[1]) ** 2) / m[:, 2] ** 2
    kept = e <= BECKMANN_MAX_EXPONENT
    return wo[kept], wi[kept]


def test_walter_masking_is_close_to_smith():
    """The rescaling is small: Walter's approximation is within 0.4% of the exact G1."""
    w = mts.crosscheck_pairs(N_PAIRS, 0.3, 0.3, rng=14)[0]
    ratio = _WalterMasking((0.3, 0.3)).ratio(w)
    assert np.all(np.abs(ratio - 1.0) < 4e-3)


@pytest.mark.parametrize("alpha", BECKMANN_ALPHAS, ids=str)
def test_beckmann_conductor_matches_mitsuba(alpha, record_property):
    eta, k = (np.array(v) for v in METALS["gold"])
    ours = ab.lobes.Conductor(*alpha, fresnel=ab.fresnel.ExactConductor(eta, k),
                              masking="separable", model="beckmann")
    theirs = mts.mitsuba_conductor(*alpha, eta=eta, k=k, model="beckmann")
    wo, wi = _beckmann_pairs(alpha, None, rng=12)
    _crosscheck(f"beckmann conductor gold alpha={alpha}", _WalterMasking(alpha).rescale(ours),
                theirs, wo, wi, record_property)


@pytest.mark.parametrize("alpha", BECKMANN_ALPHAS, ids=str)
@pytest.mark.parametrize("eta", DIELECTRICS)
def test_beckmann_dielectric_matches_mitsuba(eta, alpha, record_property):
    eta_value, ext_ior = DIELECTRICS[eta]
    ours = ab.lobes.Dielectric(eta_value, *alpha, masking="separable", model="beckmann")
    theirs = mts.mitsuba_dielectric(eta_value, *alpha, ext_ior=ext_ior, model="beckmann")
    wo, wi = _beckmann_pairs(alpha, eta_value, rng=13)
    _crosscheck(f"beckmann dielectric {eta} alpha={alpha}", _WalterMasking(alpha).rescale(ours),
                theirs, wo, wi, record_property)
