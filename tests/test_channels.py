"""``adobe_bsdf._channels``: colour arithmetic channel by channel is bit for bit NumPy's
broadcast, for the shapes it speeds up and for those it passes on."""

import numpy as np
import pytest

from adobe_bsdf import _channels as ch

N = 3 * ch.SMALL  # above the threshold: the channel-by-channel path


def _bits(x):
    return np.ascontiguousarray(x).view(np.uint8)


@pytest.mark.parametrize("n", [N, 10])
def test_channel_by_channel_is_the_broadcast_bit_for_bit(n):
    rng = np.random.default_rng(2)
    x, rgb, colour = rng.normal(size=n), rng.normal(size=(n, 3)), rng.normal(size=3)
    x[:4] = [np.inf, -0.0, np.nan, 5e-324]
    rgb[4] = [np.inf, -np.inf, np.nan]
    mask = rng.random(n) > 0.5
    with np.errstate(all="ignore"):  # the special values
        pairs = [(ch.tinted(x, colour), x[:, None] * colour),
                 (ch.scaled(rgb, colour), rgb * colour),
                 (ch.shifted(rgb, colour), rgb + colour),
                 (ch.weighted(rgb, x), rgb * x[:, None]),
                 (ch.divided(rgb, x), rgb / x[:, None]),
                 (ch.masked(mask, rgb), np.where(mask[:, None], rgb, 0.0)),
                 (ch.selected(mask, rgb, rgb[::-1]), np.where(mask[:, None], rgb, rgb[::-1]))]
    for got, expected in pairs:
        assert got.shape == expected.shape
        np.testing.assert_array_equal(_bits(got), _bits(expected))
    out = rgb.copy()
    assert ch.weighted(out, x, out=out) is out
    np.testing.assert_array_equal(_bits(out), _bits(rgb * x[:, None]))


def test_other_shapes_broadcast_as_numpy_does():
    rng = np.random.default_rng(3)
    grey, texture = rng.random((N, 1)), rng.random((N, 3))
    np.testing.assert_array_equal(ch.scaled(grey, [1.0, 0.5, 0.0]), grey * [1.0, 0.5, 0.0])
    np.testing.assert_array_equal(ch.shifted(grey, [1.0, 0.5, 0.0]), grey + [1.0, 0.5, 0.0])
    np.testing.assert_array_equal(ch.tinted(grey[:, 0], texture), grey * texture)
    np.testing.assert_array_equal(ch.weighted(texture[:1], grey[:, 0]), texture[:1] * grey)


@pytest.mark.parametrize("share", [0.0, 0.1, 0.5, 0.9, 1.0])
def test_row_selection_is_numpys_whatever_the_share(share):
    """``selected`` copies the side with more rows and puts the other's in; ``take_rows`` and
    ``put_rows`` are ``a[index]`` and ``out[index] = values``: the same bits for every share
    of chosen rows, for batches of any rank and for non-contiguous inputs."""
    rng = np.random.default_rng(4)
    a, b = rng.normal(size=(2, N, 3))
    a[0] = [np.nan, -0.0, np.inf]
    mask = rng.random(N) < share
    for m, x, y in [(mask, a, b), (mask.reshape(3, -1), a.reshape(3, -1, 3), b.reshape(3, -1, 3)),
                    (mask, a[:, ::-1], b)]:
        np.testing.assert_array_equal(_bits(ch.selected(m, x, y)),
                                      _bits(np.where(m[..., None], x, y)))
        np.testing.assert_array_equal(_bits(ch.masked(m, x)), _bits(np.where(m[..., None], x, 0.0)))
    index = np.flatnonzero(mask)
    np.testing.assert_array_equal(_bits(ch.take_rows(a, index)), _bits(a[index]))
    for values in (a[: len(index)], a[: len(index), :2]):
        out, expected = np.zeros((N, values.shape[1])), np.zeros((N, values.shape[1]))
        ch.put_rows(out, index, values)
        expected[index] = values
        np.testing.assert_array_equal(_bits(out), _bits(expected))


@pytest.mark.parametrize("share", [0.0, 0.03, 0.5, 0.97, 1.0])
def test_pick_is_numpys_where_bit_for_bit(share):
    """``pick`` selects bits (NaN payloads, signed zeros, infinities kept) where the mask is
    unpredictable and is ``np.where`` elsewhere: the same bits and dtype for arrays,
    strided views, scalars and small batches."""
    rng = np.random.default_rng(7)
    a, b = rng.normal(size=(2, N))
    a[::7], b[::5], a[::11] = -0.0, np.nan, np.inf
    mask = rng.random(N) < share
    strided = rng.normal(size=(N, 3))[:, 2]
    cases = [(a, b), (a, 0.0), (1.0, b), (np.float64(-0.0), strided), (strided, a),
             (np.asarray(2.5), b)]
    for x, y in cases:
        for m, xx, yy in [(mask, x, y), (mask[:10], *(v[:10] if np.ndim(v) else v
                                                        for v in (x, y)))]:
            got, expected = ch.pick(m, xx, yy), np.where(m, xx, yy)
            assert got.dtype == expected.dtype and got.shape == expected.shape
            np.testing.assert_array_equal(_bits(got), _bits(expected))
    # what it passes on: integer values, both scalars, a broadcast mask
    for args in [(mask, np.arange(N), 0), (mask, 1.0, 0.0), (mask[:, None], a[:, None], b)]:
        np.testing.assert_array_equal(ch.pick(*args), np.where(*args))
