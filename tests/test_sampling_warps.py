"""The warps of ``adobe_bsdf.sampling`` against their closed forms in NumPy's cosine and
sine: the half-angle point of the unit circle and the concentric disk."""

import numpy as np

from adobe_bsdf import sampling

#: np.cos and np.sin round to within half an ulp of 1; the half-angle form to one ulp more
UNIT_CIRCLE_TOL = 2.3e-16


def _uniforms(n=200_000, seed=3):
    u = np.random.default_rng(seed).random(n)
    edges = [0.0, 0.125, 0.25, 0.5, 0.75, np.nextafter(0.5, 0.0), np.nextafter(0.5, 1.0),
             np.nextafter(1.0, 0.0), 1e-300, 5e-324]
    return np.concatenate([u, edges])


def test_azimuth_is_cos_and_sin_of_two_pi_u_to_rounding():
    u = _uniforms()
    cos, sin = sampling.azimuth(u)
    phi = 2.0 * np.pi * u
    assert np.all(np.isfinite(cos)) and np.all(np.isfinite(sin))
    assert np.abs(cos - np.cos(phi)).max() <= UNIT_CIRCLE_TOL
    assert np.abs(sin - np.sin(phi)).max() <= UNIT_CIRCLE_TOL
    assert np.abs(np.hypot(cos, sin) - 1.0).max() <= 4.5e-16
    # the quadrants and the exact points
    assert (cos[-10], sin[-10]) == (1.0, 0.0)
    assert np.all(np.sign(sin[u < 0.5][1:]) >= 0.0) and np.all(sin[u > 0.5] <= 0.0)


def test_unit_circle_takes_negative_half_angles():
    x = np.linspace(-np.pi / 2, np.pi / 2, 10_001)
    cos, sin = sampling.unit_circle(x)
    assert np.abs(cos - np.cos(2 * x)).max() <= UNIT_CIRCLE_TOL
    assert np.abs(sin - np.sin(2 * x)).max() <= UNIT_CIRCLE_TOL


def test_concentric_disk_is_the_polar_map_of_shirley_and_chiu():
    rng = np.random.default_rng(4)
    u2 = np.concatenate([rng.random((200_000, 2)),
                         [[0.5, 0.5], [0.0, 0.0], [0.5, 0.9], [0.1, 0.5], [0.75, 0.75],
                          [0.25, 0.75]]])
    a, b = 2.0 * u2[:, 0] - 1.0, 2.0 * u2[:, 1] - 1.0
    first = np.abs(a) > np.abs(b)
    r = np.where(first, a, b)
    with np.errstate(divide="ignore", invalid="ignore"):
        phi = np.where(first, np.pi / 4 * b / a, np.pi / 2 - np.pi / 4 * a / b)
    phi = np.where(r == 0.0, 0.0, phi)
    expected = np.stack([r * np.cos(phi), r * np.sin(phi)], axis=-1)
    p = sampling.concentric_disk(u2)
    assert np.abs(p - expected).max() <= 4.5e-16
    assert np.all(np.hypot(p[:, 0], p[:, 1]) <= 1.0 + 4.5e-16)
    np.testing.assert_array_equal(p[-6], [0.0, 0.0])
