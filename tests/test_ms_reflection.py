"""``lobes.DielectricMultipleReflection``: the glossy multiple reflection of a rough dielectric
interface's light side, and its place in ``DielectricMultipleScattering``. Expected values:
closed forms (the symmetric scaling of a rank-one kernel), the independent quadrature of
``tables.ggx_energy`` for the energy it must restore, and the microsurface random walk
[Heitz2016ms] for its shape."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import adobe_bsdf as ab
from adobe_bsdf.lobes import DielectricMS, DielectricMultipleReflection
from adobe_bsdf.lobes.kulla_conty import (
    GLOSSY_SHARE,
    DielectricMultipleScattering,
    SeparableDielectricMS,
)
from adobe_bsdf.tables.catalog import _symmetric_scaling
from adobe_bsdf.tables.energy import ggx_energy
from adobe_bsdf.validation.microsurface import MicrosurfaceDielectric
from tests.sampling_checks import assert_sampling_matches


def _direction(mu, phi, side=1.0):
    mu = np.asarray(mu, dtype=np.float64)
    s = np.sqrt(1.0 - mu * mu)
    return np.stack(np.broadcast_arrays(s * np.cos(phi), s * np.sin(phi), side * mu), -1)


def test_symmetric_scaling_of_a_rank_one_kernel():
    """M = v v^T: a_k v_k (v . a) = X_k has the closed form a_k = X_k / (v_k sqrt(sum X))."""
    rng = np.random.default_rng(0)
    v, X = rng.uniform(0.2, 2.0, 12), rng.uniform(0.0, 0.3, 12)
    X[3] = 0.0
    a, residual = _symmetric_scaling(np.outer(v, v), X)
    np.testing.assert_allclose(a, X / (v * np.sqrt(X.sum())), rtol=1e-12, atol=0)
    assert residual.max() < 1e-15


@pytest.mark.parametrize("eta, alpha", [(1.5, 0.3), (1 / 1.33, 0.12), (2.4, 0.9)])
def test_reciprocal(eta, alpha):
    """A reflection term: f(wo, wi) = f(wi, wo) on either side, to rounding."""
    rng = np.random.default_rng(1)
    wo, wi = ab.frame.normalize(rng.normal(size=(2, 500, 3)))
    lobe = DielectricMultipleReflection(eta, alpha, weight=0.7)
    f = lobe.eval(wo, wi)
    np.testing.assert_allclose(f, lobe.eval(wi, wo), rtol=1e-14, atol=0)
    light = np.sign(eta - 1.0)
    on_light = (wo[:, 2] * light > 0) & (wi[:, 2] * light > 0)
    assert np.all(f[~on_light] == 0.0) and np.all(f[on_light] > 0.0)


@settings(max_examples=12, deadline=None)
@given(alpha=st.floats(0.03, 1.5), eta=st.floats(1.05, 3.0), mu=st.floats(0.02, 1.0),
       below=st.booleans())
def test_reflects_what_single_scattering_loses(alpha, eta, mu, below):
    """Its albedo (quadrature of eval) is w (1 - E_R - E_T) of the light side, off the
    table's nodes: within 2e-4 of that loss read from the energy tables (the error of the
    scaling's interpolation between alpha nodes, largest for the narrow lobes, alpha ~ 0.03:
    ``docs/energy_models.md``), and within 2e-3 of the loss by the independent quadrature of
    ``ggx_energy`` (the energy tables' own interpolation error, ``docs/tables.md``)."""
    w = 0.8
    side = -1.0 if below else 1.0
    lobe = DielectricMultipleReflection(eta if not below else 1.0 / eta, alpha, weight=w)
    wo = _direction(mu, 0.4, side)
    E = lobe.albedo(wo, tol=1e-7)[0]
    assert abs(E - lobe.albedo(wo, method="table")[0]) <= 2e-4
    e = ggx_energy(mu, alpha, eta)
    lost = 1.0 - float(e.reflection + e.transmission)
    assert abs(E - w * lost) <= 2e-3, (E, w * lost)


@pytest.mark.parametrize("eta, alpha, cos_theta", [(1.5, 0.3, 0.7), (1.5, 0.3, 0.15),
                                                   (1 / 1.33, 0.15, -0.5)])
def test_sampling(eta, alpha, cos_theta):
    assert_sampling_matches(DielectricMultipleReflection(eta, alpha, weight=0.5), cos_theta,
                            0.3, seed=3, n_tests=3)


@pytest.mark.parametrize("cos_theta", [0.8, 0.2, -0.6])
def test_dielectric_ms_sampling(cos_theta):
    assert_sampling_matches(DielectricMS(1.5, 0.12), cos_theta, 0.9, seed=4, n_tests=3)


def test_the_terms_restore_the_loss_exactly():
    """DielectricMS's white furnace (quadrature), both sides: the glossy share moves energy
    between the terms, it adds none (anisotropic roughness keeps the separable term alone,
    ``test_the_split_of_the_light_side``)."""
    for eta, alpha in [(1.5, 0.12), (1 / 1.6, 0.4), (2.2, 0.8)]:
        lobe = DielectricMS(eta, alpha)
        wo = _direction(np.array([0.9, 0.4, 0.1, 0.9, 0.4, 0.1]), 0.3,
                        np.array([1, 1, 1, -1, -1, -1.0]))
        E = lobe.albedo(wo, tol=1e-7)[:, 0]
        np.testing.assert_allclose(E, 1.0, atol=1e-4)


def test_the_split_of_the_light_side():
    """Of the light side's multiply scattered energy X, the glossy term reflects g r_L X, the
    separable term (1 - g) r_L X and transmits t_L X (its table albedo X (1 - g r_L));
    anisotropic roughness keeps the separable term alone."""
    eta, alpha = 1.5, 0.3
    terms = DielectricMultipleScattering(eta, alpha)
    separable, glossy = terms.components
    t_L = terms.transmitted_share[0]
    wo = _direction(0.5, 0.0)
    X = terms.albedo(wo, method="table")[0]
    np.testing.assert_allclose(glossy.albedo(wo, method="table")[0],
                               GLOSSY_SHARE * (1 - t_L) * X, rtol=1e-12)
    np.testing.assert_allclose(separable.albedo(wo, method="table")[0],
                               (1 - GLOSSY_SHARE * (1 - t_L)) * X, rtol=1e-12)
    np.testing.assert_allclose(terms._reflect_probability(wo), 1 - t_L, rtol=1e-12)
    assert len(DielectricMultipleScattering(eta, alpha, 0.1).components) == 1


def test_closer_to_the_random_walk_than_the_separable_term():
    """At alpha 0.12, eta 1.5, over pairs about and away from the mirror direction, the
    reflection f of DielectricMS is within a log-RMS 0.2 of the microsurface walk's, and at
    most half the separable term's log-RMS (measured: ``benchmarks/ms_reflection.py``)."""
    eta, alpha = 1.5, 0.12
    pairs = [(o, i, p) for o in (0.3, 0.7) for i in (0.2, 0.5, 0.9) for p in (1.0, 2.4, 3.0)]
    wo = np.stack([_direction(o, 0.0) for o, _, _ in pairs])
    wi = np.stack([_direction(i, p) for _, i, p in pairs])
    walk = MicrosurfaceDielectric(eta, alpha).eval(wo, wi, n_walks=8000, seed=2)[:, 0]
    ours = DielectricMS(eta, alpha).eval(wo, wi)[:, 0]
    separable = SeparableDielectricMS(eta, alpha)
    # every pair reflects on the light side: the separable term alone reflects 1 / (1 - g)
    # times what it keeps there
    old = (ab.lobes.Dielectric(eta, alpha).eval(wo, wi)[:, 0]
           + separable.eval(wo, wi)[:, 0] / (1 - GLOSSY_SHARE))
    log_new = np.sqrt(np.mean(np.log(ours / walk) ** 2))
    log_old = np.sqrt(np.mean(np.log(old / walk) ** 2))
    assert log_new < 0.2 and log_new < 0.5 * log_old, (log_new, log_old)
