"""The node integrator's batching (``tables.anisotropic_energy``): finding the roots of
several chunks at once, in blocks of t nodes, and sharing the roots of repeated t nodes
changes no bit of the results, and the brackets kept are the first four of every row."""

import numpy as np
import pytest

from adobe_bsdf.tables import anisotropic_energy as ae


def _nodes(n, seed):
    rng = np.random.default_rng(seed)
    mu = np.where(rng.uniform(size=n) < 0.2, 0.0, rng.uniform(0.0, 1.0, n))
    phi = rng.uniform(-3.2, 3.2, n)
    ax = np.exp(rng.uniform(np.log(0.003), np.log(1.5), n))
    ay = np.where(rng.uniform(size=n) < 0.2, 0.0, ax * rng.uniform(0.0, 1.0, n) ** 2)
    eta = np.exp(rng.uniform(-1.1, 1.1, n))
    return mu, phi, ax, ay, eta


def _all(args):
    e = ae.ggx_anisotropic_dielectric_energy(*args, order=5)
    moments = ae.ggx_anisotropic_moments(*args[:4], 2, order=5)
    return np.stack(list(e), -1), moments[0], moments[1]


@pytest.mark.parametrize(("chunks", "rows"), [(1, ae.ROOT_ROWS), (2, 7)])
def test_batching_changes_no_bit(monkeypatch, chunks, rows):
    args = _nodes(11, 5)
    reference = _all(args)
    monkeypatch.setattr(ae, "ROOT_CHUNKS", chunks)
    monkeypatch.setattr(ae, "ROOT_ROWS", rows)
    for a, b in zip(reference, _all(args), strict=True):
        np.testing.assert_array_equal(a, b)


def test_first_changes_of_every_row():
    rng = np.random.default_rng(2)
    change = rng.uniform(size=(3, 5, 40)) < rng.uniform(0.0, 0.5, (3, 5, 1))
    (f, i, g), rank = ae._first(change, 4)
    # the reference: the stable argsort of the old implementation
    first = np.argsort(~change, axis=-1, kind="stable")[..., :4]
    valid = np.take_along_axis(change, first, -1)
    expected = {(a, b, first[a, b, s], s) for a, b, s in zip(*np.nonzero(valid), strict=True)}
    assert set(zip(f, i, g, rank, strict=True)) == expected
