"""The grid of anisotropic dielectric slices (``tables.dielectric_grid``): its declaration
covers the stated ranges at the stated step, a grid point's values are the slice's, and the
bake keeps finished slices, resumes, and assembles them in grid order."""

from dataclasses import replace

import numpy as np
import pytest

from adobe_bsdf.__main__ import main
from adobe_bsdf.tables import dielectric_grid as grid
from adobe_bsdf.tables import dielectric_slices
from adobe_bsdf.tables.dielectric_slices import dielectric_slice
from adobe_bsdf.tables.executors import open_executor


def test_the_grid_spans_its_ranges_at_its_step():
    """Every axis uniform in its q at a step of at most 0.3; the grid reaches alpha 0 and 2,
    ratio 0 and 1, eta 1.01 and 3, and its halves stay on their side of sqrt 2."""
    root2 = np.sqrt(2.0)
    below, above = grid.grid_points("below"), grid.grid_points("above")
    for half, points in (("below", below), ("above", above)):
        for axis in grid.HALVES[half]:
            assert np.all(np.diff(axis.nodes()) <= grid.STEP + 1e-12), axis
        assert points[:, 0].min() == 0.0 and points[:, 0].max() == pytest.approx(2.0, abs=1e-12)
        assert points[:, 1].min() == 0.0 and points[:, 1].max() == pytest.approx(1.0, abs=1e-12)
    assert below[:, 2].min() == pytest.approx(1.01, abs=1e-12)
    assert above[:, 2].max() == pytest.approx(3.0, abs=1e-12)
    assert below[:, 2].max() < root2 < above[:, 2].min()
    assert above[:, 2].min() / root2 - 1.0 == pytest.approx(grid.SQRT2_GAP, rel=1e-6)


@pytest.mark.parametrize("index", [100, 40])
def test_a_grid_point_holds_its_slice(index):
    """``slice_values`` is the node values of ``dielectric_slice`` in the grid's layout (not
    refined), part after part (float32); at alpha = 0 (point 40) those at ``ALPHA_LIMIT``."""
    point = tuple(grid.grid_points("above")[index])
    assert (point[0] == 0.0) == (index == 40)
    values = grid.slice_values(point)
    piece = dielectric_slice(max(point[0], grid.ALPHA_LIMIT), *point[1:], refined=False)
    want = np.concatenate([p.table.values.reshape(-1, 2) for p in piece.parts])
    share = dielectric_slices.light_share(piece.alpha, piece.ratio, piece.eta, False)
    want[:len(share)] += share  # the light side's table holds E - (g, -g)
    assert values.dtype == np.float32 and values.shape == want.shape
    np.testing.assert_allclose(values, want, rtol=0, atol=1e-7)


def test_the_first_roughness_node_stays_above_the_floor():
    """At ``ALPHA_LIMIT`` the projected roughness of every roughness ratio that the grid's
    read stencils reach (from its second node up) stays above ``ALPHA_FLOOR``, so the first
    node's slices sit at the same cos theta / alpha_phi as those of any alpha > 0."""
    from adobe_bsdf.tables.anisotropic_energy import ALPHA_FLOOR, projected_alpha

    ratios = np.unique(grid.grid_points("below")[:, 1])
    assert ratios[2] == pytest.approx(grid.RATIO_INTERPOLATED)
    c = np.linspace(0.0, 1.0, 101)
    assert np.all(projected_alpha(c, grid.ALPHA_LIMIT, ratios[1]) > ALPHA_FLOOR)


@pytest.mark.parametrize("interface", [(0.003, 0.5, 1.5), (0.0004, 0.2, 2.5)])
def test_a_nearly_smooth_interface_reads_the_grid(interface):
    """Below the grid's third roughness node (alpha 0.0156) the default reads the grid, whose
    first node holds the limit alpha -> 0+: E_R + E_T within 2e-3 of the node integrator
    (order 12) from both sides, grazing to normal, along and across the rough axis (with the
    first node at alpha = 0 itself, the grid missed by 1.6e-2 to 1.8e-2 here)."""
    from adobe_bsdf.tables.anisotropic_energy import ggx_anisotropic_dielectric_energy

    alpha, ratio, eta = interface
    assert grid.interpolated(*interface)
    piece = grid.grid_slice(*interface)
    mu, c = (a.ravel() for a in np.meshgrid([1e-3, 2e-3, 5e-3, 0.01, 0.03, 0.2, 0.8],
                                            [0.0, 0.3, 0.7, 1.0], indexing="ij"))
    for on_light in (True, False):
        e = ggx_anisotropic_dielectric_energy(mu, np.arccos(c), alpha, ratio * alpha,
                                              eta if on_light else 1.0 / eta, 12,
                                              estimate=False)
        got = piece(on_light, mu, c).sum(-1)
        np.testing.assert_allclose(got, e.reflection + e.transmission, rtol=0, atol=2e-3)


@pytest.mark.parametrize("interface", [(0.0157, 0.037, 3.0), (0.05, 0.04, 1.5),
                                       (0.02, 0.5, 1.05)])
def test_the_light_sides_reflection_reads_the_grid(interface):
    """From alpha_max ``ALPHA_REFLECTION`` up, E_R alone of the light side (an opaque
    dielectric's specular albedo) read from the grid is within 2e-3 of the node integrator
    (order 12), grazing to normal, along and across the rough axis: the grid interpolates it
    less its Fresnel share (``dielectric_slices.fresnel_share``); interpolated as it is, it
    missed by 2.1e-2, 9.1e-3 and 2.1e-3 here."""
    from adobe_bsdf.tables.anisotropic_energy import ggx_anisotropic_dielectric_energy

    alpha, ratio, eta = interface
    assert grid.interpolated(*interface, "reflection")
    piece = grid.grid_slice(*interface, "reflection")
    mu, c = (a.ravel() for a in np.meshgrid([1e-3, 2e-3, 5e-3, 0.01, 0.03, 0.05, 0.1, 0.2,
                                             0.5, 0.8, 1.0], [0.0, 0.1, 0.3, 0.7, 1.0],
                                            indexing="ij"))
    e = ggx_anisotropic_dielectric_energy(mu, np.arccos(c), alpha, ratio * alpha, eta, 12,
                                          estimate=False)
    np.testing.assert_allclose(piece.channel("reflection", True, mu, c), e.reflection,
                               rtol=0, atol=2e-3)


def test_the_bake_resumes_and_stores_column_by_column(tmp_path, monkeypatch):
    """With a stand-in for the slices: slices and columns already finished are kept (not
    computed again), the rest computed, each column stored as soon as its slices are done
    (the finished slices then removed), and every point's values are at its index; a
    refined patch is baked in the refined layout into files of its own."""
    calls, refined_calls = [], []

    def fake(point):
        calls.append(point)
        return np.full((3, 2), (point[0] + point[1] + point[2] - 1.0) / 6.0,
                       dtype=np.float32)

    def fake_refined(point, refined=False):
        assert refined
        refined_calls.append(point)
        return np.full((5, 2), point[0] / 4.0, dtype=np.float32)

    patch = grid.SliceGrid({"below": ((1, 2), (3, 4), (2, 4))}, refined=True, prefix="r-")
    thin = grid.SliceGrid({"above": ((0, 1), (0, 1), (1, 2))}, refined=True, prefix="t-",
                          thin=grid.THIN.thin, ratios=grid.THIN.ratios)
    monkeypatch.setattr(grid, "GRIDS", (patch, grid.GRID))
    monkeypatch.setattr(grid, "PENDING", (thin,))
    monkeypatch.setattr(grid, "slice_values", fake)
    monkeypatch.setattr(grid, "point_values", fake_refined)
    partial = tmp_path / f"{grid.NAME}.partial"
    partial.mkdir()
    n_eta = grid.HALVES["below"][2].n
    np.save(partial / f"below_{n_eta + 2:05d}.npy", np.full((3, 2), 0.25, dtype=np.float32))
    kept = np.full(tuple(a.n for a in grid.HALVES["above"][:2]) + (3, 2), 0.5)
    grid.write_column(tmp_path / grid.NAME, "above", 4, kept)
    stored = []
    monkeypatch.setattr(grid, "write_column", lambda *a, _w=grid.write_column: (
        stored.append(a[1:3]), _w(*a))[1])
    with open_executor(1) as ex:
        out = grid.bake(tmp_path, ex, progress=False)
    n = sum(len(grid.grid_points(h)) for h in grid.HALVES)
    n_column = len(grid.grid_points("above")) // grid.HALVES["above"][2].n
    assert len(calls) == n - 1 - n_column
    assert len(refined_calls) == 2 * 2 * 3 + 2 * 2 * 2
    assert stored == [c for c in grid.columns() if c != ("above", 4)] + [
        ("below", k) for k in range(3)] + [("above", 0), ("above", 1)]  # the grid's first
    assert sorted({p[1] for p in refined_calls[-8:]}) == [
        0.0, pytest.approx(np.exp(grid.THIN.thin.nodes()[1]) - grid.THIN_OFFSET, rel=1e-12)]
    assert not partial.exists()
    column = grid.stored_columns(out)
    for half in grid.HALVES:
        points = grid.grid_points(half).reshape(tuple(a.n for a in grid.HALVES[half]) + (3,))
        for k in range(grid.HALVES[half][2].n):
            values = column(half, k)
            want = (points[:, :, k].sum(-1) - 1.0) / 6.0
            if (half, k) == ("above", 4):
                want = np.full_like(want, 0.5)
            if (half, k) == ("below", 2):
                want[0, 1] = 0.25  # the file found, not recomputed
            assert values.shape == want.shape + (3, 2)
            assert np.abs(values - want[..., None, None]).max() <= 0.5 / grid.QUANTUM + 1e-7
    refined = grid.stored_columns(out, patch)
    points = grid.grid_points("below").reshape(tuple(a.n for a in grid.HALVES["below"]) + (3,))
    for k in range(3):
        values = refined("below", k)
        want = points[1:3, 3:5, 2 + k, 0] / 4.0
        assert values.shape == (2, 2, 5, 2)
        assert np.abs(values - want[..., None, None]).max() <= 0.5 / grid.QUANTUM + 1e-7
    alphas = np.unique(grid.grid_points("above")[:, 0])[:2]
    for k in range(2):
        values = grid.stored_columns(out, thin)("above", k)
        assert values.shape == (2, 2, 5, 2)
        assert np.abs(values - alphas[:, None, None, None] / 4.0).max() <= 0.5 / grid.QUANTUM


def test_the_grid_is_baked_at_its_points_only(capsys):
    """The command refuses the grid with --check or --resolution."""
    for option in (["--check"], ["--resolution", "4"]):
        assert main(["bake", grid.NAME, *option]) == 2
        err = capsys.readouterr().err
        assert grid.NAME in err, option



def _plus_shares(patch, half: str, values):
    """``values`` (node values at ``patch``'s points of ``half``) plus, on the light side,
    each point's own Fresnel share: what a grid's node values hold beyond what it
    interpolates."""
    points = patch.points(half).reshape(*values.shape[:3], 3)
    for index in np.ndindex(*values.shape[:3]):
        alpha, ratio, eta = points[index]
        share = dielectric_slices.light_share(max(alpha, grid.ALPHA_LIMIT), ratio, eta,
                                              patch.refined)
        values[index][:len(share)] += share
    return values


def _quadratic_grid(n_nodes: int, seed: int = 3, patch=grid.GRID):
    """A grid whose every node value is a quadratic in (q_alpha, q_ratio, q_eta), which
    cubic convolution (with its quadratic end extrapolation) reproduces exactly, plus on the
    light side each point's Fresnel share (``patch``'s points: its own slices), and the
    quadratic itself: what the slice interpolated between the points holds."""
    coefficients = np.random.default_rng(seed).normal(size=(10, n_nodes, 2))

    def basis(qa, qr, qe):
        return np.stack([np.ones_like(qa), qa, qr, qe, qa * qa, qr * qr, qe * qe, qa * qr,
                         qa * qe, qr * qe], -1)
    values = {}
    for half, axes in grid.HALVES.items():
        Q = np.meshgrid(*[a.nodes() for a in axes], indexing="ij")
        values[half] = np.einsum("abcj,jnk->abcnk", basis(*Q), coefficients)
        if half in patch.spans:
            (a0, a1), (r0, r1), (e0, e1) = patch.spans[half]
            _plus_shares(patch, half, values[half][a0:a1 + 1, r0:r1 + 1, e0:e1 + 1])

    def exact(alpha, ratio, eta):
        q = (np.log(alpha + grid.ALPHA_OFFSET), np.log(ratio + grid.RATIO_OFFSET),
             np.log(eta - 1.0 + grid.ETA_OFFSET))
        return np.tensordot(basis(*map(np.asarray, q)), coefficients, axes=(0, 0))
    return values, exact


@pytest.mark.parametrize("interface", [(0.37, 0.21, 1.23), (1.9, 0.003, 2.9),
                                       (0.0, 1.0, 1.0304), (0.004, 0.6, 1.6)])
def test_interpolated_slice_between_grid_points(interface):
    """Off the grid points, every node's value is the interpolant's: a quadratic in the
    grid's coordinates comes back to rounding, laid out at the interface's own parts."""
    n_nodes = sum(int(np.prod(p.table.spec.shape[:-1])) for p in _layout(interface))
    values, exact = _quadratic_grid(n_nodes)
    whole = replace(grid.GRID, ratios=(0.0, np.inf))  # its first cells too
    piece = grid.interpolated_slice(grid.array_columns(values), *interface, grid=whole)
    got = np.concatenate([p.table.values.reshape(-1, 2) for p in piece.parts])
    np.testing.assert_allclose(got, exact(*interface), rtol=0, atol=1e-9)
    assert [(p.segment, p.band, p.lo, p.hi) for p in piece.parts] == [
        (p.segment, p.band, p.lo, p.hi) for p in _layout(interface)]


@pytest.mark.parametrize("interface", [(0.9, 0.3, 1.07), (2.0, 1.0, 1.031),
                                       (0.62, 0.04, 1.2)])
def test_the_refined_patch_interpolates_in_its_own_layout(interface):
    """Inside the refined patch (alpha >= 0.617, eta <= 1.21) every node's value is the
    interpolant's over the patch's own points, laid out refined: a quadratic comes back to
    rounding."""
    patch = grid.PATCH
    n_nodes = sum(int(np.prod(p.table.spec.shape[:-1]))
                  for p in _layout(interface, refined=True))
    values, exact = _quadratic_grid(n_nodes, patch=patch)
    (a0, a1), (r0, r1), (e0, e1) = patch.spans["below"]
    own = {"below": values["below"][a0:a1 + 1, r0:r1 + 1, e0:e1 + 1]}
    piece = grid.interpolated_slice(grid.array_columns(own), *interface, grid=patch)
    got = np.concatenate([p.table.values.reshape(-1, 2) for p in piece.parts])
    np.testing.assert_allclose(got, exact(*interface), rtol=0, atol=1e-9)
    assert piece.n_nodes == n_nodes > grid.interpolated_slice(
        grid.array_columns(values), *interface).n_nodes


def _reproduces_a_quadratic(patch, interface, coordinates):
    """The slice that ``patch`` interpolates at ``interface`` from node values quadratic in
    its axes' coordinates (``coordinates(alpha, ratio, eta)``: the three) plus, on the
    light side, each point's own Fresnel share, holds that quadratic to rounding (what it
    interpolates: the share taken out), laid out refined at the interface's own parameters."""
    half = "below" if interface[2] < np.sqrt(2.0) else "above"
    n_nodes = sum(int(np.prod(p.table.spec.shape[:-1]))
                  for p in _layout(interface, refined=True))
    coefficients = np.random.default_rng(5).normal(size=(9, n_nodes, 2))

    def basis(x, y, z):
        return np.stack([np.ones_like(x), x, y, z, x * x, y * y, z * z, x * y, y * z], -1)
    q = np.meshgrid(*[a.nodes()[lo:hi + 1] for a, (lo, hi)
                      in zip(patch.axes(half), patch.spans[half], strict=True)], indexing="ij")
    values = {half: _plus_shares(patch, half, np.einsum("abcj,jnk->abcnk", basis(*q),
                                                        coefficients))}
    piece = grid.interpolated_slice(grid.array_columns(values), *interface, grid=patch)
    want = np.tensordot(basis(*map(np.asarray, coordinates(*interface))), coefficients,
                        axes=(0, 0))
    got = np.concatenate([p.table.values.reshape(-1, 2) for p in piece.parts])
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-9)
    assert [(p.segment, p.band, p.lo, p.hi, p.ratio) for p in piece.parts] == [
        (p.segment, p.band, p.lo, p.hi, p.ratio) for p in _layout(interface, refined=True)]


@pytest.mark.parametrize("interface", [(0.37, 0.21, 1.0101), (1.9, 0.04, 1.025),
                                       (0.0, 1.0, 1.01), (0.004, 0.6, 1.03)])
def test_the_matched_patch_interpolates_on_the_critical_cosine(interface):
    """Between index ratios 1.01 and ``ETA_INTERPOLATED`` ``MATCHED`` interpolates on its
    own axis, uniform in the critical cosine: a quadratic in (q_alpha, q_ratio, mu_c) over
    its points comes back to rounding, laid out refined at the interface's own index."""
    assert grid.MATCHED.stencils(*interface) is not None
    _reproduces_a_quadratic(grid.MATCHED, interface, lambda alpha, ratio, eta: (
        np.log(alpha + grid.ALPHA_OFFSET), np.log(ratio + grid.RATIO_OFFSET),
        grid.critical_cosine(eta)))


def test_the_library_reads_the_grids_where_they_hold_the_interface():
    """``interpolated``: while ``THIN`` is pending, the library reads an interface from the
    grids for E_R + E_T exactly where its index ratio is in [1.01, 3] and its roughness ratio
    at least ``RATIO_INTERPOLATED``, and for E_R where its alpha_max is also at least
    ``ALPHA_REFLECTION``."""
    assert grid.THIN in grid.PENDING and grid.THIN not in grid.GRIDS
    rng = np.random.default_rng(8)
    alpha = np.concatenate([[0.0, grid.ALPHA_REFLECTION, 2.0], 10 ** rng.uniform(-4, 0.3, 300)])
    ratio = np.concatenate([[0.0, grid.RATIO_INTERPOLATED, 1.0], 10 ** rng.uniform(-4, 0, 300)])
    eta = np.concatenate([[grid.ETA_MIN, grid.ETA_INTERPOLATED, grid.ETA_MAX],
                          rng.uniform(1.0, 3.2, 300)])
    for a, r, e in zip(alpha, ratio, eta, strict=True):
        total = bool(grid.ETA_MIN <= e <= grid.ETA_MAX and r >= grid.RATIO_INTERPOLATED)
        assert grid.interpolated(a, r, e) == total, (a, r, e)
        assert grid.interpolated(a, r, e, "reflection") == (
            total and a >= grid.ALPHA_REFLECTION), (a, r, e)


def test_the_thin_patch_spans_the_nearly_one_dimensional_ratios():
    """``THIN``: roughness ratios from 0 to the grid's fourth ratio node, uniform in
    ln(ratio + ``THIN_OFFSET``) at a step of at most ``THIN_STEP``, at every roughness and
    index-ratio node of the grid; read below ``RATIO_INTERPOLATED`` from
    ``ETA_INTERPOLATED`` up, nowhere else."""
    thin = grid.THIN
    ratios = np.unique(thin.points("below")[:, 1])
    grid_ratios = np.unique(grid.grid_points("below")[:, 1])
    assert ratios[0] == 0.0 and ratios[-1] == pytest.approx(grid_ratios[3], rel=1e-12)
    assert np.all(np.diff(np.log(ratios + grid.THIN_OFFSET)) <= grid.THIN_STEP + 1e-12)
    for half in grid.HALVES:
        for k in (0, 2):
            np.testing.assert_array_equal(np.unique(thin.points(half)[:, k]),
                                          np.unique(grid.grid_points(half)[:, k]))
    assert thin.stencils(0.9, 0.0, 1.5) is not None
    assert thin.stencils(0.9, 0.9 * grid.RATIO_INTERPOLATED, 2.9) is not None
    for interface in ((0.9, grid.RATIO_INTERPOLATED, 1.5), (0.9, 0.01, 1.02),
                      (0.9, 0.01, 1.005)):
        assert thin.stencils(*interface) is None


@pytest.mark.parametrize("interface", [(0.37, 0.0, 1.2), (1.9, 0.003, 2.1),
                                       (0.004, 3e-5, 1.5), (0.7, 0.036, 1.06)])
def test_the_thin_patch_interpolates_in_the_log_of_the_ratio(interface):
    """A quadratic in (q_alpha, ln(ratio + 1e-5), q_eta) over ``THIN``'s points comes back to
    rounding, laid out refined at the interface's own roughness ratio."""
    _reproduces_a_quadratic(grid.THIN, interface, lambda alpha, ratio, eta: (
        np.log(alpha + grid.ALPHA_OFFSET), grid.thin_coordinate(ratio),
        np.log(eta - 1.0 + grid.ETA_OFFSET)))


@pytest.mark.parametrize("interface", [(0.5, 0.3, 1.031), (0.9, 0.02, 1.02),
                                       (0.9, 0.3, 1.005), (0.9, 0.3, 2.0)])
def test_the_matched_patch_holds_only_nearly_matched_interfaces(interface):
    """Outside index ratios [1.01, ``ETA_INTERPOLATED``) and below the grid's second
    roughness ratio it has no slice; the grid and the rough patch none below
    ``ETA_INTERPOLATED``."""
    assert grid.MATCHED.stencils(*interface) is None
    assert grid.GRID.stencils(0.5, 0.3, 1.02) is None
    assert grid.PATCH.stencils(0.9, 0.3, 1.02) is None


@pytest.mark.parametrize("interface", [(0.5, 0.3, 1.07), (0.9, 0.3, 1.25),
                                       (0.9, 0.02, 1.07), (0.9, 0.3, 2.0)])
def test_the_refined_patch_ends_where_its_stencils_do(interface):
    """Outside the cells whose stencils lie inside the patch it has no slice."""
    assert grid.PATCH.stencils(*interface) is None
    assert grid.interpolated_slice(lambda half, k: None, *interface, grid=grid.PATCH) is None


def _layout(interface, refined=False):
    from adobe_bsdf.tables.dielectric_slices import layout
    return layout(*interface, refined=refined)


def test_interpolated_slice_off_the_grid_and_at_sqrt2():
    """An index outside [1.01, 3] has no slice on the grid; within the gap about sqrt 2 the
    nearer half's end is read."""
    n = sum(int(np.prod(p.table.spec.shape[:-1])) for p in _layout((0.3, 0.3, 1.3)))
    values, _ = _quadratic_grid(n)
    values = grid.array_columns(values)
    assert grid.interpolated_slice(values, 0.3, 0.3, 1.005) is None
    assert grid.interpolated_slice(values, 0.3, 0.3, 3.01) is None
    at = grid.interpolated_slice(values, 0.3, 0.3, np.sqrt(2.0) * (1.0 - 1e-7))
    end = grid.interpolated_slice(values, 0.3, 0.3, grid.grid_points("below")[-1, 2])
    for a, b in zip(at.parts, end.parts, strict=True):
        np.testing.assert_array_equal(a.table.values, b.table.values)


@pytest.fixture
def synthetic_grid(monkeypatch):
    """The library as if it shipped a grid whose every slice holds E_R = 0.125 and
    E_T = 0.75, a refined patch whose every slice holds E_R = 0.25 and E_T = 0.5 and a nearly
    index-matched one of E_R = 0.0625 and E_T = 0.5 (exact in the rounding of ``encode``)."""
    import adobe_bsdf.tables.dielectric_grid as module

    def constant(grid, half, e_r, e_t, refined=False):
        n = sum(int(np.prod(p.table.spec.shape[:-1]))
                for p in _layout((0.7, 0.3, 1.2 if half == "below" else 2.0), refined))
        v = np.empty(grid.shape(half) + (n, 2))
        v[..., 0], v[..., 1] = e_r, e_t
        return v

    columns = {module.GRID: {h: constant(module.GRID, h, 0.125, 0.75) for h in module.HALVES},
               module.PATCH: {"below": constant(module.PATCH, "below", 0.25, 0.5, True)},
               module.MATCHED: {"below": constant(module.MATCHED, "below", 0.0625, 0.5,
                                                  True)}}
    module._grid_slice.cache_clear()
    monkeypatch.setattr(module, "shipped", lambda grid=module.GRID: True)
    monkeypatch.setattr(module, "_shipped_columns",
                        lambda grid=module.GRID: module.array_columns(columns[grid]))
    yield
    module._grid_slice.cache_clear()


def test_default_lobes_read_the_shipped_grid(synthetic_grid):
    """Built with no option, an anisotropic rough dielectric reads its energy from the
    grid: from either side its E_R + E_T is the grid's 0.875; under "exact" and
    "isotropic" it does not."""
    import adobe_bsdf as ab
    from adobe_bsdf import lobes

    wo = np.array([[0.3, 0.4, np.sqrt(0.75)], [0.6, 0.0, -0.8], [0.0, 0.99, 0.1411]])
    wo /= np.linalg.norm(wo, axis=-1, keepdims=True)
    for eta in (1.2, 1 / 1.45, 2.5):
        lobe = lobes.Dielectric(eta, 0.4, 0.1)
        assert lobe.slices == "grid"
        np.testing.assert_allclose(lobe.albedo(wo, method="table")[..., 0], 0.875,
                                   rtol=0, atol=1e-12)
    with ab.config.options(anisotropic_energy="isotropic"):
        assert lobes.Dielectric(1.45, 0.4, 0.1).slices == ""
    with ab.config.options(anisotropic_energy="exact"):
        assert lobes.Dielectric(1.45, 0.4, 0.1).slices == "exact"
    assert lobes.Dielectric(1.45, 0.4, 0.4).slices == ""  # isotropic: the tables


@pytest.mark.parametrize("eta", [1.02, 1 / 1.012, 1.0301])
def test_nearly_matched_interfaces_read_their_patch(synthetic_grid, eta):
    """Index ratios 1.01 to ``ETA_INTERPOLATED`` read ``MATCHED`` (E_R + E_T 0.5625) at
    every roughness from either side; just above, the grid (0.875) or the rough patch
    (0.75)."""
    from adobe_bsdf import lobes

    wo = np.array([[0.3, 0.4, np.sqrt(0.75)], [0.6, 0.0, -0.8]])
    for alpha_x, alpha_y in ((0.9, 0.3), (0.01, 0.006), (2.0, 1.9)):
        albedo = lobes.Dielectric(eta, alpha_x, alpha_y).albedo(wo, method="table")
        np.testing.assert_allclose(albedo[..., 0], 0.5625, rtol=0, atol=1e-12)
    for alpha_x, want in ((0.3, 0.875), (0.9, 0.75)):
        albedo = lobes.Dielectric(1.031, alpha_x, 0.5 * alpha_x).albedo(wo, method="table")
        np.testing.assert_allclose(albedo[..., 0], want, rtol=0, atol=1e-12)


def test_nearly_smooth_interfaces_read_only_their_total_from_the_grid(synthetic_grid):
    """Below alpha_max ``ALPHA_REFLECTION`` a lobe reads E_R + E_T from the grid (0.875),
    while E_R alone comes from the computed slice; above it both from the grid."""
    from adobe_bsdf import lobes

    assert grid.grid_slice(0.004, 0.5, 1.5) is not None
    assert grid.grid_slice(0.004, 0.5, 1.5, "reflection") is None
    assert grid.grid_slice(0.03, 0.5, 1.5, "reflection") is grid.grid_slice(0.03, 0.5, 1.5)
    wo = np.array([[0.3, 0.4, np.sqrt(0.75)], [0.6, 0.0, -0.8]])
    albedo = lobes.Dielectric(1.5, 0.004, 0.002).albedo(wo, method="table")
    np.testing.assert_allclose(albedo[..., 0], 0.875, rtol=0, atol=1e-12)


@pytest.mark.parametrize("eta", [1.05, 1 / 1.05, 1.2])
def test_the_rough_nearly_matched_corner_reads_the_refined_patch(synthetic_grid, eta):
    """A rough (alpha_max >= 0.62), nearly index-matched interface (ratio 1.03 to 1.21)
    reads the refined patch (E_R + E_T 0.75 from either side); a smoother one or one of a
    higher index the grid (0.875)."""
    from adobe_bsdf import lobes

    wo = np.array([[0.3, 0.4, np.sqrt(0.75)], [0.6, 0.0, -0.8]])
    for alpha_x, alpha_y, want in ((0.9, 0.3, 0.75), (1.5, 1.2, 0.75), (0.5, 0.2, 0.875)):
        albedo = lobes.Dielectric(eta, alpha_x, alpha_y).albedo(wo, method="table")
        np.testing.assert_allclose(albedo[..., 0], want, rtol=0, atol=1e-12)
    albedo = lobes.Dielectric(1.5, 0.9, 0.3).albedo(wo, method="table")
    np.testing.assert_allclose(albedo[..., 0], 0.875, rtol=0, atol=1e-12)


def test_the_grid_benchmark_measures_a_baked_file(tmp_path):
    """``benchmarks.anisotropic_grid --smoke --grid FILE`` compares a grid file with the
    exact slices: a grid of constant E_R and E_T misses by what the exact slices differ from
    them, which the page reports."""
    from benchmarks import anisotropic_grid

    R, T = (grid.QUANTUM + 1) // 8, 3 * (grid.QUANTUM + 1) // 4 - 1  # E_R 1/8, E_T 3/4
    values = {}
    for half, axes in grid.HALVES.items():
        n = sum(int(np.prod(p.table.spec.shape[:-1]))
                for p in _layout((0.3, 0.3, 1.2 if half == "below" else 2.0)))
        v = np.empty(tuple(a.n for a in axes) + (n, 2))
        v[..., 0], v[..., 1] = R / grid.QUANTUM, T / grid.QUANTUM  # stored exactly
        values[half] = v
    path = tmp_path / grid.NAME
    for half, k in grid.columns():
        grid.write_column(path, half, k, values[half][:, :, k])
    result = anisotropic_grid.measure(smoke=True, path=path)
    (alpha, ratio, eta), errors = result["rows"][0]
    piece = dielectric_slice(alpha, ratio, eta)
    mu, cos_phi = anisotropic_grid._directions(np.random.default_rng(anisotropic_grid.SEED),
                                              anisotropic_grid.DIRECTIONS)
    want = (R + T) / grid.QUANTUM - piece(True, mu, cos_phi).sum(-1)
    np.testing.assert_allclose(errors["light"], want, rtol=0, atol=1e-12)
    page = anisotropic_grid.markdown(result, 1.0)
    assert "| light (E_R + E_T unless named) |" in page and grid.NAME in page
    assert "## The bake" in page and "| 128 |" in page
    from benchmarks import with_block
    text = "intro\n<!-- measured: anisotropic_grid (written by x) -->\nold\n" \
           "<!-- end measured -->\nafter\n"
    new = with_block(text, anisotropic_grid.SUMMARY, anisotropic_grid.summary(result))
    assert "old" not in new and new.startswith("intro\n<!-- measured") and new.endswith(
        "<!-- end measured -->\nafter\n")
    worst = max(np.abs(r["light"]).max() for c, r in result["rows"]
                if anisotropic_grid._read(c))
    assert f"| the light side | {worst:.1e} |" in new
    with pytest.raises(ValueError, match="no <!-- measured: anisotropic_grid"):
        with_block("no block", anisotropic_grid.SUMMARY, "x")


@pytest.mark.parametrize("interface", [(0.8725, 0.928, 1.06), (0.3, 0.5, 1.2),
                                       (1.5, 0.2, 2.5)])
def test_every_dense_direction_finds_its_part_at_the_kinks(interface):
    """At exactly mu = 1 / eta and mu = mu_c, along either axis (|cos phi| 0 and 1), where a
    segment or a band ends, the slice's value is its neighbours' (a direction once fell
    between the parts there and read 0)."""
    alpha, ratio, eta = interface
    piece = grid.grid_slice(*interface)
    mu_c = np.sqrt(1.0 - 1.0 / eta**2)
    for mu in (1.0 / eta, mu_c, 1.0):
        for c in (0.0, 1.0):
            at = piece(False, np.array([mu]), np.array([c]))
            near = piece(False, np.array([mu * (1.0 - 1e-9)]), np.array([c]))
            np.testing.assert_allclose(at, near, rtol=0.0, atol=1e-6)
            assert at.sum() > 0.1  # not the 0 of no part
