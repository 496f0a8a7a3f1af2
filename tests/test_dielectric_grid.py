"""The grid of anisotropic dielectric slices (``tables.dielectric_grid``): its declaration
covers the stated ranges at the stated step, a grid point's values are the slice's, and the
bake keeps finished slices, resumes, and assembles them in grid order."""

import numpy as np
import pytest

from adobe_bsdf.__main__ import main
from adobe_bsdf.tables import dielectric_grid as grid
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


def test_a_grid_point_holds_its_slice():
    """``slice_values`` is the node values of ``dielectric_slice`` in the grid's layout (not
    refined), part after part (float32)."""
    point = tuple(grid.grid_points("above")[40])
    values = grid.slice_values(point)
    piece = dielectric_slice(*point, refined=False)
    want = np.concatenate([p.table.values.reshape(-1, 2) for p in piece.parts])
    assert values.dtype == np.float32 and values.shape == want.shape
    np.testing.assert_allclose(values, want, rtol=0, atol=1e-7)


def test_the_bake_resumes_and_stores_column_by_column(tmp_path, monkeypatch):
    """With a stand-in for the slices: slices and columns already finished are kept (not
    computed again), the rest computed, each column stored as soon as its slices are done
    (the finished slices then removed), and every point's values are at its index."""
    calls = []

    def fake(point):
        calls.append(point)
        return np.full((3, 2), (point[0] + point[1] + point[2] - 1.0) / 6.0,
                       dtype=np.float32)

    monkeypatch.setattr(grid, "slice_values", fake)
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
    assert stored == [c for c in grid.columns() if c != ("above", 4)]  # in column order
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


def test_the_grid_is_baked_at_its_points_only(capsys):
    """The command refuses the grid with --check or --resolution."""
    for option in (["--check"], ["--resolution", "4"]):
        assert main(["bake", grid.NAME, *option]) == 2
        err = capsys.readouterr().err
        assert grid.NAME in err, option



def _quadratic_grid(n_nodes: int, seed: int = 3):
    """A grid whose every node value is a quadratic in (q_alpha, q_ratio, q_eta), which
    cubic convolution (with its quadratic end extrapolation) reproduces exactly, and the
    quadratic itself."""
    coefficients = np.random.default_rng(seed).normal(size=(10, n_nodes, 2))

    def basis(qa, qr, qe):
        return np.stack([np.ones_like(qa), qa, qr, qe, qa * qa, qr * qr, qe * qe, qa * qr,
                         qa * qe, qr * qe], -1)
    values = {}
    for half, axes in grid.HALVES.items():
        Q = np.meshgrid(*[a.nodes() for a in axes], indexing="ij")
        values[half] = np.einsum("abcj,jnk->abcnk", basis(*Q), coefficients)

    def exact(alpha, ratio, eta):
        q = (np.log(alpha + grid.ALPHA_OFFSET), np.log(ratio + grid.RATIO_OFFSET),
             np.log(eta - 1.0 + grid.ETA_OFFSET))
        return np.tensordot(basis(*map(np.asarray, q)), coefficients, axes=(0, 0))
    return values, exact


@pytest.mark.parametrize("interface", [(0.37, 0.21, 1.23), (1.9, 0.003, 2.9),
                                       (0.0, 1.0, 1.01), (0.004, 0.6, 1.6)])
def test_interpolated_slice_between_grid_points(interface):
    """Off the grid points, every node's value is the interpolant's: a quadratic in the
    grid's coordinates comes back to rounding, laid out at the interface's own parts."""
    n_nodes = sum(int(np.prod(p.table.spec.shape[:-1])) for p in _layout(interface))
    values, exact = _quadratic_grid(n_nodes)
    piece = grid.interpolated_slice(grid.array_columns(values), *interface)
    got = np.concatenate([p.table.values.reshape(-1, 2) for p in piece.parts])
    np.testing.assert_allclose(got, exact(*interface), rtol=0, atol=1e-9)
    assert [(p.segment, p.band, p.lo, p.hi) for p in piece.parts] == [
        (p.segment, p.band, p.lo, p.hi) for p in _layout(interface)]


def _layout(interface):
    from adobe_bsdf.tables.dielectric_slices import layout
    return layout(*interface)


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
    E_T = 0.75 (exact in the rounding of ``encode``)."""
    import adobe_bsdf.tables.dielectric_grid as module

    values = {}
    for half, axes in module.HALVES.items():
        n = sum(int(np.prod(p.table.spec.shape[:-1]))
                for p in _layout((0.3, 0.3, 1.2 if half == "below" else 2.0)))
        v = np.empty(tuple(a.n for a in axes) + (n, 2))
        v[..., 0], v[..., 1] = 0.125, 0.75
        values[half] = v
    module.grid_slice.cache_clear()
    monkeypatch.setattr(module, "shipped", lambda: True)
    monkeypatch.setattr(module, "_shipped_columns", lambda: module.array_columns(values))
    yield
    module.grid_slice.cache_clear()


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


def test_the_grid_benchmark_measures_a_baked_file(tmp_path):
    """``benchmarks.anisotropic_grid --smoke --grid FILE`` compares a grid file with the
    exact slices: a grid of constant E_R and E_T misses by what the exact slices differ from
    them, which the page reports."""
    from benchmarks import anisotropic_grid

    values = {}
    for half, axes in grid.HALVES.items():
        n = sum(int(np.prod(p.table.spec.shape[:-1]))
                for p in _layout((0.3, 0.3, 1.2 if half == "below" else 2.0)))
        v = np.empty(tuple(a.n for a in axes) + (n, 2))
        v[..., 0], v[..., 1] = 8192 / grid.QUANTUM, 49151 / grid.QUANTUM  # stored exactly
        values[half] = v
    path = tmp_path / grid.NAME
    for half, k in grid.columns():
        grid.write_column(path, half, k, values[half][:, :, k])
    result = anisotropic_grid.measure(smoke=True, path=path)
    (alpha, ratio, eta), errors = result["rows"][0]
    piece = dielectric_slice(alpha, ratio, eta)
    mu, cos_phi = anisotropic_grid._directions(np.random.default_rng(anisotropic_grid.SEED),
                                              anisotropic_grid.DIRECTIONS)
    want = (8192 + 49151) / grid.QUANTUM - piece(True, mu, cos_phi).sum(-1)
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
