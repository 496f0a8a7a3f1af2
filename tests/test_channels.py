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
    for got, expected in [(ch.tinted(x, colour), x[:, None] * colour),
                          (ch.scaled(rgb, colour), rgb * colour),
                          (ch.weighted(rgb, x), rgb * x[:, None]),
                          (ch.masked(mask, rgb), np.where(mask[:, None], rgb, 0.0))]:
        assert got.shape == expected.shape
        np.testing.assert_array_equal(_bits(got), _bits(expected))
    out = rgb.copy()
    assert ch.weighted(out, x, out=out) is out
    np.testing.assert_array_equal(_bits(out), _bits(rgb * x[:, None]))


def test_other_shapes_broadcast_as_numpy_does():
    rng = np.random.default_rng(3)
    grey, texture = rng.random((N, 1)), rng.random((N, 3))
    np.testing.assert_array_equal(ch.scaled(grey, [1.0, 0.5, 0.0]), grey * [1.0, 0.5, 0.0])
    np.testing.assert_array_equal(ch.tinted(grey[:, 0], texture), grey * texture)
    np.testing.assert_array_equal(ch.weighted(texture[:1], grey[:, 0]), texture[:1] * grey)
