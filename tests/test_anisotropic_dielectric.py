"""Anisotropic GGX dielectric energy: the node integrator with refraction, the per-lobe
slices, and the exact anisotropic Kulla–Conty terms, coat albedo and ASM lobe integral built
on them (``config.options(anisotropic_energy="exact")``).

Expected values come from independent computations: the isotropic integrator
``tables.ggx_energy`` (another parameterisation and breakpoint scheme), Monte Carlo over the
lobes' own visible-normal samplers, the integrator itself at a higher order (for the slices'
interpolation), and a midpoint rule over the slices' interpolants (for their averages).
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import adobe_bsdf as ab
from adobe_bsdf import lobes, tables
from adobe_bsdf.composition import Rotated
from adobe_bsdf.lobes.energy_lookup import slice_energy
from adobe_bsdf.materials import AdobeStandardMaterial, OpenPBRSurface
from adobe_bsdf.materials.asm.mapping import alphas
from adobe_bsdf.microfacet import GGX
from adobe_bsdf.tables import anisotropic_energy, dielectric_slices
from adobe_bsdf.tables.anisotropic_energy import ggx_anisotropic_dielectric_energy
from adobe_bsdf.tables.dielectric_slices import dielectric_slice
from tests.sampling_checks import assert_sampling_matches

#: the acceptance of the white furnace (seen from the light side): 1 +- FURNACE
FURNACE = 2e-3
#: the furnace's case for the default run: ASM roughness 0.2, anisotropy 0.8 (ratio 0.09)
ALPHA_X, ALPHA_Y = (float(a) for a in alphas(np.asarray(0.2), np.asarray(0.8)))
ETA = 1.5


def _direction(mu, phi, side=1.0):
    s = np.sqrt(1.0 - mu * mu)
    return np.stack([s * np.cos(phi), s * np.sin(phi), side * mu], -1)


def _exact(factory, *args, **kwargs):
    with ab.config.options(anisotropic_energy="exact"):
        return factory(*args, **kwargs)


@pytest.mark.parametrize("alpha", [0.02, 0.3, 1.5])
@pytest.mark.parametrize("eta", [1.5, 1 / 1.5, 1.02, 2.8])
def test_integrator_reduces_to_isotropic(alpha, eta):
    mu = np.array([1.0, 0.7, 0.3, 0.05, 0.01, 1e-3])
    e = ggx_anisotropic_dielectric_energy(mu, 0.4, alpha, alpha, eta, order=12,
                                          estimate=False)
    ref = tables.ggx_energy(mu, alpha, eta, order=28)
    np.testing.assert_allclose(e.reflection, ref.reflection, rtol=0, atol=2e-5)
    np.testing.assert_allclose(e.transmission, ref.transmission, rtol=0, atol=2e-5)


@pytest.mark.parametrize("eta, mu, phi, alpha_x, alpha_y", [
    (1.5, 0.3, 0.7, 0.6, 0.05), (1 / 1.5, 0.5, 0.2, 0.3, 0.02),
    (1.33, 0.05, 1.2, 1.0, 0.0025), (1 / 1.33, 0.2, 1.4, 0.8, 0.1)])
def test_integrator_matches_the_sampler(eta, mu, phi, alpha_x, alpha_y):
    """E_R and E_T against the mean weight of ``Dielectric.sample`` (its transmitted
    weights carry the radiance scale 1 / eta^2, undone here)."""
    e = ggx_anisotropic_dielectric_energy(mu, phi, alpha_x, alpha_y, eta, order=16,
                                          estimate=False)
    lobe = lobes.Dielectric(max(eta, 1 / eta), alpha_x, alpha_y)
    wo = _direction(mu, phi, 1.0 if eta > 1 else -1.0)
    n = 200_000
    rng = np.random.default_rng(3)
    s = lobe.sample(np.broadcast_to(wo, (n, 3)), rng.random((n, 3)))
    w = s.weight[..., 0]
    reflected = s.wi[..., 2] * wo[2] > 0.0
    for value, x in ((e.reflection, w * reflected), (e.transmission, w * ~reflected * eta**2)):
        assert abs(x.mean() - value) <= 4.0 * x.std() / np.sqrt(n) + 1e-4


def test_integrator_index_matched_is_closed_form():
    mu = np.array([1.0, 0.5, 0.01])
    e = ggx_anisotropic_dielectric_energy(mu, 0.3, 0.5, 0.1, 1.0)
    S_o = np.sqrt(mu**2 + (1 - mu**2) * ((0.5 * np.cos(0.3)) ** 2 + (0.1 * np.sin(0.3)) ** 2))
    np.testing.assert_allclose(e.transmission, 1.0 / (2.0 - 2.0 * mu / (mu + S_o)), rtol=1e-14)
    assert np.all(e.reflection == 0.0)


def test_dielectric_root_grids_agree_with_the_conductors():
    """The dielectric's coarser root-finding grids change no value by more than 1e-5."""
    rng = np.random.default_rng(7)
    n = 16
    args = (np.exp(rng.uniform(np.log(0.005), 0, n)), rng.uniform(0, 1.57, n),
            np.exp(rng.uniform(np.log(0.003), np.log(1.5), n)))
    ratio, eta = rng.uniform(0, 1, n) ** 3, np.exp(rng.uniform(-1.1, 1.1, n))
    node = anisotropic_energy._DielectricNode
    fine = dict(psi_grid=anisotropic_energy.PSI_GRID, t_grid=anisotropic_energy.T_GRID,
                steps_psi=anisotropic_energy.STEPS_PSI, steps_t=anisotropic_energy.STEPS_T)
    coarse = ggx_anisotropic_dielectric_energy(*args, args[2] * ratio, eta, order=8,
                                               estimate=False)
    saved = {k: getattr(node, k) for k in fine}
    try:
        for k, v in fine.items():
            setattr(node, k, v)
        ref = ggx_anisotropic_dielectric_energy(*args, args[2] * ratio, eta, order=8,
                                                estimate=False)
    finally:
        for k, v in saved.items():
            setattr(node, k, v)
    np.testing.assert_allclose(coarse.reflection, ref.reflection, rtol=0, atol=1e-5)
    np.testing.assert_allclose(coarse.transmission, ref.transmission, rtol=0, atol=1e-5)


@pytest.fixture(scope="module")
def piece():
    return dielectric_slice(ALPHA_X, ALPHA_Y / ALPHA_X, ETA)


def test_slice_interpolation(piece):
    """The slice against the integrator at order 12 at random directions: the sum within
    the furnace's bound from either side."""
    rng = np.random.default_rng(11)
    n = 120
    mu, phi = np.exp(rng.uniform(np.log(0.01), 0.0, n)), rng.uniform(0.0, np.pi / 2, n)
    for on_light, eta, bound in ((True, ETA, FURNACE), (False, 1 / ETA, FURNACE)):
        ref = ggx_anisotropic_dielectric_energy(mu, phi, ALPHA_X, ALPHA_Y, eta, order=12,
                                                estimate=False)
        E = piece(on_light, mu, np.cos(phi)).sum(-1)
        assert np.abs(E - ref.reflection - ref.transmission).max() <= bound, on_light


@settings(max_examples=60, deadline=None)
@given(eta=st.floats(1.0, 3.0), mu=st.floats(0.0, 1.0), cos_phi=st.floats(0.0, 1.0))
def test_slice_parts_tile_the_dense_side(eta, mu, cos_phi):
    """Every direction of the dense side belongs to exactly one of its tables, and each
    table's coordinates map it back to itself (the segments and bands are a partition)."""
    mu_c = float(np.sqrt(1.0 - 1.0 / eta**2))
    parts = [dielectric_slices._Part(segment, band, mu_c, ALPHA_X, ALPHA_Y / ALPHA_X, lo, hi)
             for segment, lo, hi in dielectric_slices._segments(mu_c)
             for band in ("near", "mid", "far")]
    mu_, c_ = np.array([mu]), np.array([cos_phi])
    owners = [p for p in parts if p.covers(mu_, c_)[0]]
    assert len(owners) == 1, [(p.segment, p.band) for p in owners]
    back = owners[0].directions(*owners[0].coordinates(mu_, c_))
    np.testing.assert_allclose(back, (mu_, c_), rtol=0, atol=1e-9)


def _directions_by_steps(part, x, u):
    """``_Part.directions`` as declared: ``_STEPS`` fixed-point steps over every point."""
    c = np.asarray(u, dtype=np.float64)
    t = dielectric_slices._two_sided_inverse(c, part._u_edges)
    for _ in range(1 if part.segment == "plain" else dielectric_slices._STEPS):
        mu = part._mu(x, c)
        lo, hi = part._band(mu)
        c = lo + t * (hi - lo)
    return mu, c


def test_slice_reproduces_its_node_values(piece):
    """At the light side's nodes the slice reads the integrator's own values (the table
    through its nodes, the Fresnel share taken out and put back), E_R and E_T apart."""
    part = piece.parts[0]
    mu, c = (a.ravel() for a in part.directions(*part.table.spec.grid()))
    want = dielectric_slices.node_energy(piece.alpha, piece.ratio, piece.eta, mu, c,
                                         np.ones(mu.shape, bool))
    np.testing.assert_allclose(piece(True, mu, c), want, rtol=0, atol=1e-12)
    np.testing.assert_allclose(piece.channel("reflection", True, mu, c), want[:, 0], rtol=0,
                               atol=1e-12)


def test_slice_directions_stop_at_their_fixed_points(piece):
    """The node directions stop iterating where a point has reached its fixed point: the
    same bits as every step over every point."""
    for part in piece.parts[1:]:
        X, U = np.meshgrid(*[np.linspace(0.0, 1.0, 23)] * 2, indexing="ij")
        for got, want in zip(part.directions(X, U), _directions_by_steps(part, X, U),
                             strict=True):
            np.testing.assert_array_equal(got, want)


def test_slice_lookup_reads_the_covering_part(piece):
    """One pass that assigns each direction its part reads, bit for bit, the table of the
    part whose ``covers`` holds (the declared partition; the light side's plus its Fresnel
    share); the one-output channels are the sum and E_R of the two-output lookup, to
    rounding."""
    rng = np.random.default_rng(5)
    n = 4000
    mu, c = rng.uniform(0.0, 1.0, n), rng.uniform(0.0, 1.0, n)
    mu[:40], mu[40:80] = 0.0, 1.0
    mu[80:120] = piece.parts[1].mu_c
    c[120:160], c[160:200] = 0.0, 1.0
    on_light = rng.uniform(size=n) < 0.3
    want = np.zeros((n, 2))
    for part in piece.parts:
        mask = on_light if part.segment == "outside" else ~on_light & part.covers(mu, c)
        want[mask] = part.table(*part.coordinates(mu[mask], c[mask]))
    g = dielectric_slices.fresnel_share(piece.alpha, piece.ratio, piece.eta, mu, c)
    want[on_light] += g[on_light, None] * np.array([1.0, -1.0])
    got = piece(on_light, mu, c)
    np.testing.assert_array_equal(got, want)
    np.testing.assert_allclose(piece.channel("total", on_light, mu, c), want.sum(-1),
                               rtol=0, atol=1e-14)
    np.testing.assert_allclose(piece.channel("reflection", on_light, mu, c), want[:, 0],
                               rtol=0, atol=1e-14)
    assert piece(True, 0.5, 0.5).shape == (2,)
    assert piece.channel("total", np.ones((2, 3), bool), 0.5, 0.2).shape == (2, 3)


def test_slice_averages(piece):
    """The averages the Kulla–Conty terms normalise by are those of the slice's own
    interpolant: a midpoint rule over (mu, phi) agrees to 2e-4."""
    n_mu, n_phi = 4000, 200
    mu = (np.arange(n_mu) + 0.5) / n_mu
    phi = (np.arange(n_phi) + 0.5) / n_phi * (np.pi / 2)
    M, P = np.meshgrid(mu, phi, indexing="ij")
    for on_light, average in ((True, piece.average_outside), (False, piece.average_inside)):
        E = piece(on_light, M, np.cos(P))
        midpoint = 2.0 * np.einsum("ij,ijk->k", M, E) / (n_mu * n_phi)
        np.testing.assert_allclose(average, midpoint, rtol=0, atol=2e-4)


def _furnace_directions(side):
    mu = np.array([1.0, 0.5, 0.1, 0.03, 0.01])
    phi = np.array([0.0, 0.3, 0.79, 1.6, 2.5])
    M, P = np.meshgrid(mu, phi, indexing="ij")
    return M.ravel(), P.ravel(), _direction(M.ravel(), P.ravel(), side)


@pytest.mark.parametrize("rotation", [0.0, 0.3])
def test_white_furnace_exact_dielectric(rotation):
    """White DielectricMS built exact, turned by 2 pi ``rotation``: single scattering by the
    integrator (order 12) at the lobe's own azimuth, the compensation by its albedo, from
    both sides; the isotropic proxy misses by far more."""
    lobe = _exact(lobes.DielectricMS, ETA, ALPHA_X, ALPHA_Y)
    turned = Rotated(lobe, 2.0 * np.pi * rotation)
    for side, eta in ((1.0, ETA), (-1.0, 1 / ETA)):
        mu, phi, wo = _furnace_directions(side)
        e = ggx_anisotropic_dielectric_energy(mu, phi - 2.0 * np.pi * rotation, ALPHA_X,
                                              ALPHA_Y, eta, order=12, estimate=False)
        ms = Rotated(lobe.components[1], 2.0 * np.pi * rotation).albedo(wo, method="table")
        error = np.abs(e.reflection + e.transmission + ms[..., 0] - 1.0)
        assert error.max() <= FURNACE, (side, error.max())
        assert np.all(turned.albedo(wo, method="table") <= 1.0 + 1e-12)
    with ab.config.options(anisotropic_energy="isotropic"):
        proxy = lobes.DielectricMS(ETA, ALPHA_X, ALPHA_Y).components[1]
    mu, phi, wo = _furnace_directions(1.0)
    e = ggx_anisotropic_dielectric_energy(mu, phi, ALPHA_X, ALPHA_Y, ETA, order=12,
                                          estimate=False)
    before = np.abs(e.reflection + e.transmission + proxy.albedo(wo, "table")[..., 0] - 1)
    assert before.max() > 10 * FURNACE


def test_white_furnace_exact_dielectric_monte_carlo():
    """The whole exact lobe's Monte-Carlo albedo, from both sides."""
    lobe = _exact(lobes.DielectricMS, ETA, ALPHA_X, ALPHA_Y)
    for side in (1.0, -1.0):
        wo = _direction(np.array([0.9, 0.3, 0.05]), np.array([0.2, 1.0, 0.6]), side)
        E, sigma = lobe.albedo(wo, method="mc", n_samples=200_000, rng=4, return_error=True)
        assert np.all(np.abs(E[..., 0] - 1.0) <= FURNACE + 4.0 * sigma[..., 0]), E[..., 0]


def test_exact_compensation_is_reciprocal():
    """Generalized reciprocity f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2 of the exact term,
    to 1e-10, over pairs on either side."""
    term = _exact(lobes.DielectricMultipleScattering, ETA, ALPHA_X, ALPHA_Y)
    rng = np.random.default_rng(2)
    n = 400
    wo = _direction(rng.uniform(0.01, 1, n), rng.uniform(0, 2 * np.pi, n),
                    np.where(rng.random(n) < 0.5, 1.0, -1.0))
    wi = _direction(rng.uniform(0.01, 1, n), rng.uniform(0, 2 * np.pi, n),
                    np.where(rng.random(n) < 0.5, 1.0, -1.0))
    n_o = np.where(wo[..., 2] > 0, 1.0, ETA)[..., None]
    n_i = np.where(wi[..., 2] > 0, 1.0, ETA)[..., None]
    np.testing.assert_allclose(term.eval(wo, wi) / n_o**2, term.eval(wi, wo) / n_i**2,
                               rtol=1e-10, atol=0)


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_exact_dielectric_sampling(side):
    lobe = _exact(lobes.DielectricMS, ETA, ALPHA_X, ALPHA_Y)
    assert_sampling_matches(lobe, side * 0.4, 0.9, seed=5, n_tests=2)


def test_isotropic_lobes_unchanged_bit_for_bit():
    """Exact mode reads slices only where alpha_x != alpha_y."""
    rng = np.random.default_rng(9)
    wo = _direction(rng.uniform(0.01, 1, 64), rng.uniform(0, 6, 64), 1.0)
    wi = _direction(rng.uniform(0.01, 1, 64), rng.uniform(0, 6, 64), -1.0)
    for make in (lambda: lobes.DielectricMS(ETA, 0.3),
                 lambda: lobes.DielectricReflection(ETA, 0.3),
                 lambda: AdobeStandardMaterial(base_color=1.0, roughness=0.4)):
        exact, table = _exact(make), make()
        np.testing.assert_array_equal(exact.eval(wo, wi), table.eval(wo, wi))
        np.testing.assert_array_equal(exact.albedo(wo, method="table"),
                                      table.albedo(wo, method="table"))


def test_exact_mode_builds_lobes_without_tables():
    """A Beckmann interface has no slices (nor tables): built exact it is the same lobe."""
    exact = _exact(lobes.Dielectric, ETA, ALPHA_X, ALPHA_Y, model="beckmann")
    table = lobes.Dielectric(ETA, ALPHA_X, ALPHA_Y, model="beckmann")
    wo = _direction(np.array([0.8, 0.3]), np.array([0.1, 2.0]))
    wi = _direction(np.array([0.5, 0.9]), np.array([1.0, 4.0]), -1.0)
    assert not exact.slices
    np.testing.assert_array_equal(exact.eval(wo, wi), table.eval(wo, wi))


def test_coat_albedo_from_the_slice():
    """An exact anisotropic coat's albedo is the slice's E_R: the integrator's to the
    slice's accuracy from above, and nothing below."""
    coat = _exact(lobes.DielectricReflection, ETA, ALPHA_X, ALPHA_Y)
    mu, phi, wo = _furnace_directions(1.0)
    ref = ggx_anisotropic_dielectric_energy(mu, phi, ALPHA_X, ALPHA_Y, ETA, order=12,
                                            estimate=False).reflection
    E = coat.albedo(wo, method="table")[..., 0]
    assert np.abs(E - ref).max() <= FURNACE
    np.testing.assert_array_equal(coat._top_albedo(wo), coat.albedo(wo, method="table"))
    assert np.all(coat.albedo(_direction(mu, phi, -1.0), method="table") == 0.0)


def test_slice_energy_groups_distinct_parameters():
    """Arrays of parameters: each distinct (alpha, ratio, eta) reads its own slice."""
    d = GGX(np.array([ALPHA_X, 0.3, ALPHA_X]), np.array([ALPHA_Y, 0.3, ALPHA_Y]))
    wo = _direction(np.array([0.5, 0.5, 0.2]), np.array([0.3, 0.3, 1.0]))
    E = slice_energy(ETA, d, wo)[0]
    assert np.all(E[1] == 0.0)  # isotropic: not a slice's
    single = slice_energy(ETA, GGX(ALPHA_X, ALPHA_Y), wo[[0, 2]])[0]
    np.testing.assert_array_equal(E[[0, 2]], single)


@pytest.mark.parametrize("channel", ["total", "reflection"])
def test_one_interface_reads_its_slice_as_arrays_of_it_do(channel):
    """One interface (scalar parameters, read without masks) gives what a parameter array
    holding it gives, bit for bit, from both sides, at grazing and rotated axes, errors
    included."""
    rng = np.random.default_rng(5)
    wo = rng.normal(size=(400, 3))
    wo[:20, 2] = 0.0  # in the tangent plane: 0
    wo /= np.linalg.norm(wo, axis=-1, keepdims=True)
    for eta in (ETA, 1.0 / ETA):
        for ax, ay in ((ALPHA_X, ALPHA_Y), (ALPHA_Y, ALPHA_X)):
            one = slice_energy(eta, GGX(ax, ay), wo, True, channel)
            many = slice_energy(np.array([eta]), GGX(np.array([ax]), np.array([ay])),
                                wo[:, None], True, channel)
            for a, b in zip(one, many, strict=True):
                np.testing.assert_array_equal(a, b[:, 0])
            assert np.all(one[0][:20] == 0.0) and np.all(one[0][20:] > 0.0)


def test_anisotropic_energy_option_is_checked():
    with pytest.raises(ValueError,
                       match="anisotropic_energy = 'fast'.*'table', 'exact', 'isotropic'"):
        ab.config.set_options(anisotropic_energy="fast")


def test_white_asm_exact():
    """White ASM opaque dielectric under a white anisotropic coat, built exact: its
    Monte-Carlo albedo 1 from normal to grazing incidence (its specular, diffuse and coat
    all read the slices)."""
    params = dict(base_color=1.0, roughness=0.2, anisotropy_level=0.8, anisotropy_angle=0.3,
                  coat_opacity=1.0, coat_roughness=0.2, coat_anisotropy_level=0.8)
    material = _exact(AdobeStandardMaterial, **params)
    wo = _direction(np.array([1.0, 0.5, 0.1, 0.02]), np.array([0.0, 0.5, 1.9, 0.4]))
    E, sigma = material.albedo(wo, method="mc", n_samples=100_000, rng=6, return_error=True)
    assert np.all(np.abs(E[..., 0] - 1.0) <= FURNACE + 4.0 * sigma[..., 0]), E[..., 0]


def test_white_openpbr_glass_exact():
    """White anisotropic OpenPBR glass (transmission 1) under a white coat, built exact:
    its Monte-Carlo albedo 1 from above."""
    params = dict(base_color=1.0, transmission_weight=1.0, specular_roughness=0.3,
                  specular_roughness_anisotropy=0.6, coat_weight=1.0, coat_roughness=0.2,
                  coat_roughness_anisotropy=0.6)
    material = _exact(OpenPBRSurface, **params)
    wo = _direction(np.array([1.0, 0.5, 0.1, 0.02]), np.array([0.0, 0.5, 1.9, 0.4]))
    E, sigma = material.albedo(wo, method="mc", n_samples=100_000, rng=8, return_error=True)
    assert np.all(np.abs(E[..., 0] - 1.0) <= FURNACE + 4.0 * sigma[..., 0]), E[..., 0]


@pytest.mark.slow
@pytest.mark.parametrize("roughness", [0.05, 0.2, 0.5, 1.0])
@pytest.mark.parametrize("anisotropy", [0.5, 0.8, 1.0])
def test_white_furnace_exact_dielectric_grid(roughness, anisotropy):
    """The acceptance grid, from both sides (rotations are azimuths: ``_furnace_directions``
    has five of them)."""
    alpha_x, alpha_y = (float(a) for a in alphas(np.asarray(roughness),
                                                  np.asarray(anisotropy)))
    lobe = _exact(lobes.DielectricMS, ETA, alpha_x, alpha_y)
    for side, eta in ((1.0, ETA), (-1.0, 1 / ETA)):
        mu, phi, wo = _furnace_directions(side)
        e = ggx_anisotropic_dielectric_energy(mu, phi, alpha_x, alpha_y, eta, order=12,
                                              estimate=False)
        ms = lobe.components[1].albedo(wo, method="table")[..., 0]
        assert np.abs(e.reflection + e.transmission + ms - 1.0).max() <= FURNACE, side


@pytest.mark.parametrize("alpha_x, alpha_y, eta", [(0.3, 0.05, 1.5), (0.0625, 1e-8, 1.6),
                                                   (0.01, 1e-4, 3.0), (2.0**-20, 1e-8, 1.6),
                                                   (1e-4, 1e-8, 1.05)])
def test_top_albedo_table_against_the_dielectric_energy(alpha_x, alpha_y, eta):
    """An anisotropic reflection as a layer's top reads its albedo from a (v, |cos phi|)
    table of the 32 x 32 visible-normal rule over F(mu), built once per lobe: at random
    directions (cosines crowded to grazing, and 1e-3 .. 1e-2) within 4e-3 of the reflected
    energy integrated independently (``ggx_anisotropic_dielectric_energy``, order 24), as
    the rule itself (2.3e-3 measured), and never more than 4e-3 below it. Nearly smooth
    coats (alpha_x 2^-20, ASM coat_anisotropy_level 1/32 at roughness 0) were 0.017 and
    0.054 (eta 1.05) off with a table of E itself."""
    rng = np.random.default_rng(7)
    _assert_top_albedo_near(np.concatenate([rng.random(60) ** 3, [1e-3, 3e-3, 1e-2]]), rng,
                            alpha_x, alpha_y, eta)


def _assert_top_albedo_near(mu, rng, alpha_x, alpha_y, eta):
    """The lobe's top albedo (grey) within 4e-3 of ``ggx_anisotropic_dielectric_energy`` at
    order 24, at cosines ``mu`` and random azimuths."""
    phi = rng.random(mu.size) * 2.0 * np.pi
    s = np.sqrt(1.0 - mu * mu)
    wo = np.stack([s * np.cos(phi), s * np.sin(phi), mu], -1)
    lobe = ab.lobes.DielectricReflection(eta, alpha_x, alpha_y)
    reference = ggx_anisotropic_dielectric_energy(mu, phi, alpha_x, alpha_y, eta, order=24,
                                                  estimate=False)[0]
    top = lobe._top_albedo(wo)
    assert np.all(top[:, 0] == top[:, 2])
    np.testing.assert_allclose(top[:, 0], reference, atol=4e-3)


@pytest.mark.parametrize("alpha_x, alpha_y, eta", [(2.0**-20, 1e-8, 0.8), (0.05, 5e-4, 1 / 1.5),
                                                   (0.01, 0.0025, 1 / 1.05),
                                                   (0.05, 0.0125, 1 / 3)])
def test_top_albedo_grid_seen_from_the_dense_side(alpha_x, alpha_y, eta):
    """Seen from the dense side (eta < 1) the albedo has the kink of total internal
    reflection at mu_c = sqrt(1 - eta^2): the grid spends half its nodes around it and keeps
    E or E / F, whichever the rule at the cell centres prefers. At random directions crowded
    to grazing and around mu_c, within 4e-3 of the independent integration (a grid in v
    alone missed by 0.2-0.45 here: a layer under it gained energy)."""
    rng = np.random.default_rng(11)
    mu_c = np.sqrt(1.0 - eta * eta)
    mu = np.concatenate([rng.random(40) ** 3,
                         np.clip(mu_c + 0.2 * (rng.random(40) - 0.5), 0.0, 1.0)])
    _assert_top_albedo_near(mu, rng, alpha_x, alpha_y, eta)


def test_a_coat_seen_from_its_dense_side_gains_no_energy():
    """OpenPBR's coat_ior is any positive number: at 0.8 with an anisotropic coat over a
    white base the layer's Monte Carlo albedo near the critical cosine 0.6 was 1.093."""
    mu = np.array([0.95, 0.6, 0.3])
    wo = np.stack([np.sqrt(1.0 - mu * mu), np.zeros(3), mu], -1)
    material = OpenPBRSurface(base_color=1.0, specular_weight=0.0, coat_weight=1.0,
                              coat_ior=0.8, coat_roughness=0.1, coat_roughness_anisotropy=0.9)
    albedo, sigma = material.albedo(wo, method="mc", n_samples=20000, rng=3, return_error=True)
    assert np.all(albedo <= 1.0 + 1e-3 + 5.0 * sigma), (albedo, sigma)
