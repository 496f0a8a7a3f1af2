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
    """``slice_values`` is ``dielectric_slice``'s node values, part after part (float32)."""
    point = tuple(grid.grid_points("above")[40])
    values = grid.slice_values(point)
    piece = dielectric_slice(*point)
    want = np.concatenate([p.table.values.reshape(-1, 2) for p in piece.parts])
    assert values.dtype == np.float32 and values.shape == want.shape
    np.testing.assert_allclose(values, want, rtol=0, atol=1e-7)


def test_the_bake_resumes_and_assembles_in_grid_order(tmp_path, monkeypatch):
    """With a stand-in for the slices: the files already finished are kept (not computed
    again), the rest computed, and the result holds each point's values at its index."""
    calls = []

    def fake(point):
        calls.append(point)
        return np.full((3, 2), sum(point), dtype=np.float32)

    monkeypatch.setattr(grid, "slice_values", fake)
    partial = tmp_path / f"{grid.NAME}.partial"
    partial.mkdir()
    np.save(partial / "below_00007.npy", np.full((3, 2), -1.0, dtype=np.float32))
    with open_executor(1) as ex:
        path = grid.bake(tmp_path, ex, progress=False)
    n = sum(len(grid.grid_points(h)) for h in grid.HALVES)
    assert len(calls) == n - 1
    data = np.load(path)
    for half in grid.HALVES:
        values = data[f"{half}_values"]
        assert values.shape == tuple(a.n for a in grid.HALVES[half]) + (3, 2)
        flat = values.reshape(-1, 3, 2)
        points = grid.grid_points(half)
        for i in (0, 5, len(points) - 1):
            if (half, i) != ("below", 7):
                np.testing.assert_allclose(flat[i], points[i].sum(), rtol=1e-6)
    assert np.all(data["below_values"].reshape(-1, 3, 2)[7] == -1.0)


def test_the_grid_is_baked_into_a_folder_only(capsys):
    """The command refuses the grid with --check, --in-place or --resolution."""
    for option in (["--check"], ["--in-place"], ["--resolution", "4"]):
        assert main(["bake", grid.NAME, *option]) == 2
        err = capsys.readouterr().err
        assert grid.NAME in err, option
