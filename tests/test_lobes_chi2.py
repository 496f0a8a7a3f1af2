"""Sampling correctness: chi-square tests of ``sample`` against ``pdf`` for every lobe.

Acceptance: p > 0.01 after the Šidák correction over every chi-square test of this module,
for Lambert, Conductor and Dielectric at alpha in {0.01, 0.1, 0.5, 1}, two anisotropic pairs,
incident cosines down to 0.05, both sides of the dielectric and eta in {1.5, 1/1.5, 1.01}.
The grid is focused on the sharpest peak (mirror or refracted direction) for narrow lobes so
that they spread over many cells; a seed per case is fixed (no re-drawing).
"""

import itertools

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.frame import refract
from adobe_bsdf.validation.chi2 import chi2_test, suggest_grid
from tests.tolerances import CHI2_ALPHA

ALPHAS = [(0.01, 0.01), (0.1, 0.1), (0.5, 0.5), (1.0, 1.0), (0.5, 0.1), (0.05, 0.3)]
COSINES = [1.0, 0.5, 0.05]
ETAS = [1.5, 1 / 1.5, 1.01]
PHI = 0.7  # azimuth of wo, off the anisotropy axes


def direction(cos_theta, phi=PHI):
    s = np.sqrt(1.0 - cos_theta**2)
    return np.array([s * np.cos(phi), s * np.sin(phi), cos_theta])


def mirror(wo):
    return np.array([-wo[0], -wo[1], wo[2]])


CASES = (
    [("Lambert", None, None, c) for c in COSINES]
    + [("Conductor", a, None, c) for a, c in itertools.product(ALPHAS, COSINES)]
    + [("Dielectric", a, eta, side * c)
       for a, eta, c, side in itertools.product(ALPHAS, ETAS, COSINES, (1, -1))]
)
N_TESTS = len(CASES)


def case_id(case):
    kind, alpha, eta, c = case
    a = "" if alpha is None else f"-a{alpha[0]:g},{alpha[1]:g}"
    e = "" if eta is None else f"-eta{eta:.4g}"
    return f"{kind}{a}{e}-cos{c:g}"


def make(kind, alpha, eta):
    if kind == "Lambert":
        return ab.lobes.Lambert(1.0)
    if kind == "Conductor":
        return ab.lobes.Conductor(*alpha)
    return ab.lobes.Dielectric(eta, *alpha)


def grid(kind, alpha, eta, wo):
    """Focus the grid on the narrowest strong peak of the lobe."""
    if kind == "Lambert":
        return {}
    width = 2.0 * max(alpha)
    if kind == "Conductor":
        return suggest_grid(width, mirror(wo))
    eta_rel = eta if wo[2] > 0 else 1.0 / eta
    wt, ok = refract(wo, np.array([0.0, 0.0, 1.0]), eta_rel)
    if not ok:  # total internal reflection about the mean normal: reflection dominates
        return suggest_grid(width, mirror(wo))
    return suggest_grid(width * abs(1.0 - 1.0 / eta_rel) + 1e-4, wt)


@pytest.mark.parametrize(("kind", "alpha", "eta", "cos_theta"), CASES, ids=map(case_id, CASES))
def test_chi2(kind, alpha, eta, cos_theta):
    wo = direction(cos_theta)
    lobe = make(kind, alpha, eta)
    seed = CASES.index((kind, alpha, eta, cos_theta))
    result = chi2_test(lobe, wo, n_samples=1_000_000, seed=seed, alpha=CHI2_ALPHA,
                       n_tests=N_TESTS, **grid(kind, alpha, eta, wo))
    assert result.passed, str(result)
    assert result.integration_converged, str(result)
