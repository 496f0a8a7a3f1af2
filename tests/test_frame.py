"""Frames and vector helpers."""

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.frame import coordinate_system, reflect, refract, rotate_tangent


def test_coordinate_system_is_orthonormal():
    rng = np.random.default_rng(0)
    n = ab.frame.normalize(rng.normal(size=(1000, 3)))
    n[:2] = [[0, 0, 1.0], [0, 0, -1.0]]
    t, b = coordinate_system(n)
    for u, v in ((t, b), (t, n), (b, n)):
        np.testing.assert_allclose(np.einsum("ij,ij->i", u, v), 0, atol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(t, axis=1), 1, atol=1e-14)
    np.testing.assert_allclose(np.cross(t, b), n, atol=1e-14)


def test_frame_roundtrip_and_tangent_rotation():
    n = ab.frame.normalize(np.array([0.2, -0.3, 0.9]))
    f = ab.Frame(n, t=[1.0, 0, 0])
    v = ab.frame.normalize(np.array([0.3, 0.5, -0.2]))
    np.testing.assert_allclose(f.to_world(f.to_local(v)), v, atol=1e-15)
    np.testing.assert_allclose(f.to_local(n), [0, 0, 1], atol=1e-15)
    r = ab.Frame(n, t=[1.0, 0, 0], angle=np.pi / 2)
    np.testing.assert_allclose(r.t, f.b, atol=1e-15)  # x turns towards y
    np.testing.assert_allclose(rotate_tangent(f.t, n, 2 * np.pi), f.t, atol=1e-15)


def test_reflect_refract():
    m = np.array([0, 0, 1.0])
    w = ab.frame.normalize(np.array([0.6, 0.0, 0.8]))
    np.testing.assert_allclose(reflect(w, m), [-0.6, 0, 0.8], atol=1e-15)
    wt, ok = refract(w, m, 1.5)
    assert ok and wt[2] < 0
    assert np.linalg.norm(wt[:2]) == pytest.approx(0.6 / 1.5, abs=1e-15)  # Snell
    back, ok = refract(wt, m, 1 / 1.5)
    np.testing.assert_allclose(back, w, atol=1e-15)
    _, ok = refract(np.array([0.9, 0, np.sqrt(0.19)]), m, 1 / 1.5)
    assert not ok  # total internal reflection
