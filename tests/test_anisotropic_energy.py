"""Anisotropic GGX conductor energy: the stretched-space quadrature, its table and the
energy-exact anisotropic Kulla–Conty term built on them.

Expected values come from independent computations: the isotropic quadrature
``tables.ggx_energy`` (another parameterisation and breakpoint scheme), Monte Carlo over the
lobes' own visible-normal samplers, a symmetry of the one-dimensional rough surface, and
direct quadrature of the interpolated tables.
"""

import numpy as np
import pytest

from adobe_bsdf import lobes, tables
from adobe_bsdf.fresnel import _dielectric
from adobe_bsdf.lobes.energy_lookup import (
    conductor_average,
    conductor_energy,
)
from adobe_bsdf.materials import AdobeStandardMaterial
from adobe_bsdf.materials.asm.diffuse import _lobe_integral
from adobe_bsdf.materials.asm.mapping import effective_roughness
from adobe_bsdf.microfacet import GGX
from adobe_bsdf.tables.anisotropic_energy import (
    fresnel_coefficients,
    ggx_anisotropic_energy,
    ggx_anisotropic_moments,
)
from adobe_bsdf.tables.catalog import MOMENT_DEGREE, anisotropic_average

#: measured (docs/tables.md): interpolation errors of the shipped anisotropic tables at
#: random points of their domains
TABLE_BOUND = 1e-3
#: largest |L - quadrature| of the ASM's anisotropic lobe integral (docs/tables.md measures
#: it), from ior IOR_LOW up
MOMENTS_BOUND = 2e-2
IOR_LOW = 1.05


def _direction(mu, phi):
    s = np.sqrt(1.0 - mu * mu)
    return np.stack([s * np.cos(phi), s * np.sin(phi), mu], -1)


@pytest.mark.parametrize("alpha", [0.01, 0.1, 0.5, 2.0])
def test_quadrature_reduces_to_isotropic(alpha):
    mu = np.array([1.0, 0.7, 0.3, 0.05, 0.01, 1e-3, 0.0])
    e = ggx_anisotropic_energy(mu, 0.3, alpha, alpha, order=16, estimate=False).reflection
    ref = tables.ggx_energy(mu, alpha, order=28).reflection
    np.testing.assert_allclose(e, ref, rtol=0, atol=5e-6)


@pytest.mark.parametrize("alpha_x, alpha_y, phi", [(0.5, 0.0, 0.3), (0.3, 0.03, 0.7),
                                                   (2.0, 0.2, 1.2), (0.05, 1e-4, 1.5)])
def test_quadrature_converges(alpha_x, alpha_y, phi):
    """Order 12 (the tables') within its error estimate and 2e-5 of order 32."""
    mu = np.array([1.0, 0.7, 0.3, 0.05, 0.01, 1e-3])
    e = ggx_anisotropic_energy(mu, phi, alpha_x, alpha_y, order=12)
    ref = ggx_anisotropic_energy(mu, phi, alpha_x, alpha_y, order=32, estimate=False)
    error = np.abs(e.reflection - ref.reflection)
    assert np.all(error <= 2e-5)
    assert np.all(error <= e.error_reflection + 1e-9)


def test_quadrature_matches_monte_carlo():
    """E of the sampled Conductor (F = 1): mean sample weight of its VNDF sampler."""
    cases = [(0.5, 0.02, 0.6, 0.0), (0.5, 0.02, 0.2, np.pi / 2), (1.0, 0.1, 0.1, 0.8),
             (0.2, 0.6, 0.05, 0.4)]
    for alpha_x, alpha_y, mu, phi in cases:
        wo = _direction(np.array([mu]), np.array([phi]))
        lobe = lobes.Conductor(alpha_x, alpha_y)
        mc, sigma = lobe.albedo(wo, method="mc", n_samples=400_000, rng=7, return_error=True)
        E = ggx_anisotropic_energy(mu, phi, alpha_x, alpha_y, order=16).reflection
        assert abs(mc[0, 0] - E) < 5.0 * sigma[0, 0] + 1e-6, (alpha_x, alpha_y, mu, phi)


def test_one_dimensional_surface_is_blind_to_the_smooth_axis():
    """alpha_y = 0 seen across the grooves (wo in the y-z plane): the normals lie in the x-z
    plane, the problem is the cross-section at normal incidence, E does not depend on mu."""
    mu = np.array([1.0, 0.6, 0.2, 0.02])
    e = ggx_anisotropic_energy(mu, np.pi / 2, 0.5, 0.0, order=20, estimate=False).reflection
    np.testing.assert_allclose(e, e[0], rtol=0, atol=2e-6)


def test_table_interpolation_error():
    """The shipped table against direct quadrature at random points of its domain."""
    rng = np.random.default_rng(3)
    n = 48
    mu = rng.uniform(0.0, 1.0, n) ** 2
    phi = rng.uniform(0.0, 2.0 * np.pi, n)
    alpha_x = np.exp(rng.uniform(np.log(1e-3), np.log(2.0), n))
    alpha_y = alpha_x * rng.uniform(0.0, 1.0, n)
    swap = rng.uniform(size=n) < 0.5
    alpha_x, alpha_y = np.where(swap, alpha_y, alpha_x), np.where(swap, alpha_x, alpha_y)
    wo = _direction(mu, phi)
    d = GGX(alpha_x, alpha_y)
    E = conductor_energy(d, wo)[0]
    ref = ggx_anisotropic_energy(mu, phi, d.alpha_x, d.alpha_y, order=16,
                                 estimate=False).reflection
    assert np.abs(E - ref).max() <= TABLE_BOUND


def test_isotropic_lookup_unchanged():
    """alpha_x == alpha_y reads the isotropic table: its interpolant at (mu, alpha)."""
    wo = _direction(np.linspace(0.01, 1.0, 7), np.linspace(0.0, 3.0, 7))
    E = conductor_energy(GGX(0.3, 0.3), wo)[0]
    iso = tables.get("ggx_conductor")(wo[..., 2], np.full(7, 0.3))[..., 0]
    np.testing.assert_allclose(E, iso, rtol=1e-14, atol=0)


@pytest.mark.parametrize("alpha_x, alpha_y", [(0.6, 0.15), (0.05, 0.01), (0.2, 1e-3),
                                              (1.0, 0.0), (0.01, 0.005)])
def test_average_is_the_average_of_the_lookup(alpha_x, alpha_y):
    """E_avg against a graded Gauss rule over the hemisphere of the looked-up E (independent
    of the bake's cell rule): the loss 1 - E_avg, which normalises the Kulla-Conty term, to
    2e-3 relative."""
    d = GGX(alpha_x, alpha_y)
    x, w = np.polynomial.legendre.leggauss(16)
    x, w = 0.5 * (x + 1.0), 0.5 * w
    edges = np.concatenate([[0.0], np.geomspace(1e-9, 1.0, 60)])
    mu = (edges[:-1, None] + np.diff(edges)[:, None] * x).ravel()
    w_mu = (np.diff(edges)[:, None] * w).ravel()
    xp, wp = np.polynomial.legendre.leggauss(96)
    phi, w_phi = 0.25 * np.pi * (xp + 1.0), 0.25 * np.pi * wp
    M, P = np.meshgrid(mu, phi, indexing="ij")
    E = conductor_energy(d, _direction(M, P))[0]
    avg = 4.0 / np.pi * np.einsum("i,j,ij->", w_mu * mu, w_phi, E)  # 4 quarters of 2 pi
    E_avg = conductor_average(d)
    assert abs(avg - E_avg) <= 2e-3 * (1.0 - E_avg)


@pytest.mark.parametrize("roughness, anisotropy", [(0.05, 1.0), (0.2, 0.8), (0.5, 0.5),
                                                    (1.0, 1.0), (0.0, 1.0)])
def test_white_furnace_anisotropic_metal(roughness, anisotropy):
    """ConductorMS at the ASM alphas (alpha_x = r^2 + a^4, alpha_y = r^2): single scattering
    by quadrature of the lobe, compensation by its exact table albedo; and the whole lobe by
    MC."""
    alpha_x, alpha_y = roughness**2 + anisotropy**4, roughness**2
    mu = np.array([1.0, 0.5, 0.1, 0.01])
    phi = np.array([0.0, 0.7, np.pi / 2, 2.5])
    M, P = np.meshgrid(mu, phi, indexing="ij")
    wo = _direction(M.ravel(), P.ravel())
    lobe = lobes.ConductorMS(alpha_x, alpha_y)
    E_ss = ggx_anisotropic_energy(M.ravel(), P.ravel(), lobe.components[0].distribution.alpha_x,
                                  lobe.components[0].distribution.alpha_y, order=16,
                                  estimate=False).reflection
    ms = lobe.components[1].albedo(wo, method="table")[..., 0]
    assert np.abs(E_ss + ms - 1.0).max() <= 2e-3
    mc, sigma = lobe.albedo(wo[::4], method="mc", n_samples=100_000, rng=1, return_error=True)
    assert np.all(np.abs(mc[..., 0] - 1.0) <= 2e-3 + 5.0 * sigma[..., 0])


def test_white_furnace_near_the_smooth_axis_at_grazing():
    """The table's hardest corner: a nearly one-dimensional surface (ASM roughness 0.05,
    anisotropy 0.8: ratio 0.006) seen at grazing angles just off its smooth axis, where E is
    a function of |cos phi| / ratio (12 nodes per axis missed 2e-3 there by 1e-3)."""
    alpha_x, alpha_y = 0.05**2 + 0.8**4, 0.05**2
    M, C = np.meshgrid([0.01, 0.02, 0.05], [0.002, 0.005, 0.008, 0.014, 0.02, 0.03, 0.045],
                       indexing="ij")
    phi = np.arccos(C.ravel())
    lobe = lobes.ConductorMS(alpha_x, alpha_y)
    E_ss = ggx_anisotropic_energy(M.ravel(), phi, alpha_x, alpha_y, order=16,
                                  estimate=False).reflection
    ms = lobe.components[1].albedo(_direction(M.ravel(), phi), method="table")[..., 0]
    assert np.abs(E_ss + ms - 1.0).max() <= 2e-3


def test_compensation_is_reciprocal():
    rng = np.random.default_rng(0)
    wo = _direction(rng.uniform(0.01, 1, 50), rng.uniform(0, 2 * np.pi, 50))
    wi = _direction(rng.uniform(0.01, 1, 50), rng.uniform(0, 2 * np.pi, 50))
    term = lobes.ConductorMultipleScattering(0.7, 0.1)
    np.testing.assert_allclose(term.eval(wo, wi), term.eval(wi, wo), rtol=1e-12, atol=0)


def _legendre_fit(eta, degree):
    """Legendre coefficients of the exact Fresnel, by a 400-point Gauss rule (independent of
    the library's 256-point projector)."""
    x, w = np.polynomial.legendre.leggauss(400)
    F = _dielectric(0.5 * (x + 1.0), eta)
    V = np.polynomial.legendre.legvander(x, degree)
    return (np.arange(degree + 1) + 0.5) * np.einsum("q,q,qk->k", w, F, V)


@pytest.mark.parametrize("alpha", [0.05, 0.3, 1.0])
def test_fresnel_moments_give_the_dielectric_reflection(alpha):
    """sum_k a_k M_k against the isotropic integrator's exact-Fresnel E_R (alpha_x =
    alpha_y), ior down to 1.01."""
    mu = np.array([1.0, 0.7, 0.3, 0.05, 0.01, 1e-3])
    M = ggx_anisotropic_moments(mu, 0.3, alpha, alpha, MOMENT_DEGREE, order=16,
                                estimate=False)[0]
    for eta in (1.01, 1.05, 1.5, 4.0):
        ref = tables.ggx_energy(mu, alpha, eta, order=28).reflection
        np.testing.assert_allclose(M @ _legendre_fit(eta, MOMENT_DEGREE), ref, rtol=0,
                                   atol=3e-5)
    np.testing.assert_allclose(fresnel_coefficients(1.3, MOMENT_DEGREE),
                               _legendre_fit(1.3, MOMENT_DEGREE), rtol=0, atol=1e-12)


def test_moments_table_interpolation_error():
    """The ASM's anisotropic lobe integral L (isotropic table plus the moments' correction)
    against direct quadrature of the moments at random points (ASM alphas, ior >= IOR_LOW:
    below it a degree-16 Fresnel is no reference, ``docs/tables.md``)."""
    rng = np.random.default_rng(5)
    n = 32
    r, a = rng.uniform(0.0, 1.0, n), rng.uniform(0.05, 1.0, n)
    ior = IOR_LOW + (tables.IOR_MAX - IOR_LOW) * rng.uniform(0.0, 1.0, n) ** 2
    mu, phi = rng.uniform(0.0, 1.0, n) ** 2, rng.uniform(0.0, 2.0 * np.pi, n)
    d = GGX(r * r + a**4, r * r)
    L = _lobe_integral(effective_roughness(r, a), ior, _direction(mu, phi), microfacets=d)[0]
    M = ggx_anisotropic_moments(mu, phi, d.alpha_x, d.alpha_y, MOMENT_DEGREE, order=16,
                                estimate=False)[0]
    ref = np.einsum("nk,nk->n", M, np.array([_legendre_fit(e, MOMENT_DEGREE) for e in ior]))
    assert np.abs(L - ref).max() <= MOMENTS_BOUND


@pytest.mark.parametrize("roughness, anisotropy, angle", [(0.3, 1.0, 0.0), (0.05, 0.5, 0.3)])
def test_white_furnace_anisotropic_asm(roughness, anisotropy, angle):
    """White ASM metal and opaque dielectric, anisotropic and turned: MC albedo 1 down to
    cos 0.02, the metal to 2e-3, the dielectric to the moments' interpolation error
    (MOMENTS_BOUND: its diffuse takes what L leaves), and no gain beyond 2e-3 at any cos
    (docs/tables.md)."""
    mu = np.array([1.0, 0.3, 0.02, 1e-3])
    phi = np.array([0.0, 2.0 * np.pi * angle + np.pi / 2])
    M, P = np.meshgrid(mu, phi, indexing="ij")
    wo = _direction(M.ravel(), P.ravel())
    common = dict(roughness=roughness, anisotropy_level=anisotropy, anisotropy_angle=angle)
    for params in (dict(metallic=1.0, base_color=1.0, specular_edge_color=1.0),
                   dict(base_color=1.0, ior=1.5)):
        material = AdobeStandardMaterial(**params, **common)
        E, sigma = material.albedo(wo, method="mc", n_samples=40_000, rng=2,
                                   return_error=True)
        bound = 2e-3 + 5.0 * sigma[:, 0]
        loss = (2e-3 if "metallic" in params else MOMENTS_BOUND) + 5.0 * sigma[:, 0]
        above = M.ravel() >= 0.02
        assert np.all(1.0 - E[above, 0] <= loss[above]), (params, E[:, 0])
        assert np.all(E[:, 0] <= 1.0 + bound), (params, E[:, 0])
        table = material.albedo(wo, method="table")
        assert np.all(table <= 1.0 + 1e-12)


def test_build_time_average_order():
    """The moments' averages at build time (4 Gauss points per cell) within 1e-7 of 8."""
    table = tables.get("ggx_reflection_moments")
    for alpha, ratio in [(0.3, 0.2), (1.2, 0.05)]:
        low = anisotropic_average(table, alpha, ratio, 4)[0]
        high = anisotropic_average(table, alpha, ratio, 8)[0]
        np.testing.assert_allclose(low, high, rtol=0, atol=1e-7)
