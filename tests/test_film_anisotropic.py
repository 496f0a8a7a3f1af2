"""The anisotropic table of ``ReferencedReflection``: E_F - E_reference of a thin film's
microfacet reflection over (cos theta_o, phi_o) (``lobes.reflection.AzimuthalTable``)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from adobe_bsdf.fresnel import F82Tint
from adobe_bsdf.lobes import reflection
from adobe_bsdf.lobes.reflection import (
    ANISOTROPIC_ERROR,
    AzimuthalTable,
    Conductor,
    DielectricReflection,
    ReferencedReflection,
)
from adobe_bsdf.thin_film import AdaptiveCubic, ThinFilm

#: the table's E_F - E_reference against direction-space cubature in the documented ranges
#: (``ReferencedReflection``): measured within 6.3e-5 at 220 random views of 44 lobes, and
#: within 1.3e-4 of the converged node rule at 2000 views of 20 lobes, a tenth of them at
#: mu_o < 0.01 (where the cubature and that rule agree to 1e-8): the bound is that largest
#: miss, rounded up
TABLE_BOUND = 1.5e-4


def _views(mu, phi):
    mu, phi = np.asarray(mu, dtype=np.float64), np.asarray(phi, dtype=np.float64)
    s = np.sqrt(1.0 - mu * mu)
    return np.stack([s * np.cos(phi), s * np.sin(phi), mu], axis=-1)


def _film_lobe(d, n2, eta, alpha_x, alpha_y, tabulated=True):
    reference = DielectricReflection(eta, alpha_x, alpha_y)
    return reference, ReferencedReflection(reference, ThinFilm(d, n2, eta), tabulated=tabulated)


def _metal_lobe(d, n2, alpha_x, alpha_y):
    f0, tint = np.array([0.95, 0.64, 0.54]), np.array([0.9, 0.7, 0.6])
    reference = Conductor(alpha_x, alpha_y, fresnel=F82Tint(f0, tint))
    return reference, ReferencedReflection(reference, ThinFilm.over_f82_tint(d, n2, f0, tint))


def _cubature_difference(reference, lobe, wo):
    """E_F - E_reference by ``albedo(method="quadrature")`` (tol 1e-7) of both lobes."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the guard-sample note of the narrow lobes
        return (lobe.albedo(wo, method="quadrature", tol=1e-7)
                - reference.albedo(wo, method="quadrature", tol=1e-7))


@pytest.mark.parametrize(("make", "mu", "phi"), [
    (lambda: _film_lobe(880.0, 1.3, 1.6, 0.7, 0.07), [0.04, 0.45, 0.83], [1.45, 0.3, 2.4]),
    (lambda: _film_lobe(350.0, 2.2, 1.45, 0.06, 0.3), [0.08, 0.61], [0.2, -1.1]),
    (lambda: _metal_lobe(600.0, 1.5, 0.4, 0.12), [0.07, 0.35, 0.92], [-2.0, 0.9, 1.3]),
])
def test_anisotropic_table_against_direction_space_cubature(make, mu, phi):
    """At views off the table's nodes, E_F - E_reference of the table within TABLE_BOUND of
    the adaptive cubature of the two lobes' eval in direction space."""
    reference, lobe = make()
    assert isinstance(lobe.table(), AzimuthalTable)
    wo = _views(mu, phi)
    difference = lobe._difference(wo, 32) - _cubature_difference(reference, lobe, wo)
    print(f"max |table - cubature| = {np.abs(difference).max():.2e}")
    assert np.abs(difference).max() <= TABLE_BOUND
    # the albedo is the reference's table plus that difference
    E = lobe.albedo(wo, method="table")
    np.testing.assert_array_equal(E, np.maximum(reference.albedo(wo, method="table")
                                                + lobe._difference(wo, 32), 0.0))


def test_the_table_bound_covers_the_carried_error():
    assert TABLE_BOUND <= ANISOTROPIC_ERROR


def test_mirror_symmetric_views_have_the_same_albedo():
    """phi -> -phi and phi -> pi - phi (GGX's symmetries) give the same albedo bit for bit,
    as the table's own, the layer's (``_top_albedo``) and the error estimate."""
    _, lobe = _film_lobe(500.0, 1.7, 1.5, 0.3, 0.08)
    mu = np.array([0.03, 0.3, 0.7, 0.99])
    phi = np.array([0.2, 0.9, 1.3, 0.6])
    first = _views(mu, phi)  # and its exact mirrors: phi -> -phi, pi - phi, phi - pi
    views = [first * np.array(m) for m in ((1, 1, 1), (1, -1, 1), (-1, 1, 1), (-1, -1, 1))]
    for f in (lambda w: lobe.albedo(w, method="table"), lobe._top_albedo,
              lambda w: lobe._albedo_table(w)[1]):
        first = f(views[0])
        for wo in views[1:]:
            np.testing.assert_array_equal(f(wo), first)
    assert np.ptp(lobe.albedo(views[0], method="table")[:, 0]) > 0.0


def test_an_isotropic_lobe_keeps_its_table_in_cos_theta():
    """alpha_x = alpha_y: the table in mu_o alone (``AdaptiveCubic`` of ``_fresnel_energy``),
    the albedo the reference's plus it at every azimuth."""
    reference, lobe = _film_lobe(500.0, 1.4, 1.5, 0.2, 0.2)
    table = lobe.table()
    assert isinstance(table, AdaptiveCubic)
    kinks = reflection._kinks(lobe._signed.fresnel)
    nodes = table.nodes[:8]
    np.testing.assert_array_equal(
        table.values[:8], reflection._fresnel_energy(
            nodes, np.asarray(0.2), lobe._signed.fresnel.from_cos2, kinks,
            reflection.DIFFERENCE_ORDER))
    mu = np.array([0.05, 0.4, 0.8])
    for phi in (0.0, 0.7, 2.5):
        wo = _views(mu, np.full(3, phi))
        np.testing.assert_array_equal(
            lobe.albedo(wo, method="table"),
            np.maximum(reference.albedo(wo, method="table") + table(mu), 0.0))


def test_the_anisotropic_table_is_built_once(monkeypatch):
    """The first call builds the table (``built_once``); later calls reuse it and integrate
    nothing. Without ``tabulated`` the lobe keeps the sampled rule at every wo."""
    _, lobe = _film_lobe(700.0, 1.9, 1.6, 0.25, 0.05)
    assert lobe._table is None
    wo = _views([0.2, 0.6], [0.4, 1.2])
    first = lobe.albedo(wo, method="table")
    table = lobe.table()
    assert isinstance(table, AzimuthalTable) and table.converged
    calls = []
    integrate = reflection._anisotropic_fresnel_energy
    monkeypatch.setattr(reflection, "_anisotropic_fresnel_energy",
                        lambda *a, **k: calls.append(1) or integrate(*a, **k))
    np.testing.assert_array_equal(lobe.albedo(wo, method="table"), first)
    assert lobe.table() is table and not calls
    _, direct = _film_lobe(700.0, 1.9, 1.6, 0.25, 0.05, tabulated=False)
    assert direct.table() is None
