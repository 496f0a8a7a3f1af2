"""``Flipped`` (a lobe's scattered side mirrored through the plane) and ``Facing`` (a lobe
always seen from its top side): the operators of thin sheets [OpenPBR2026, §Thin-walled
mode]. Expected values are the inner lobe's, at the mirrored directions."""

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.bsdf import Flags
from adobe_bsdf.composition import Facing, Flipped, Sum
from adobe_bsdf.lobes import EON, Conductor, Lambert
from tests.sampling_checks import assert_sampling_matches

M = np.array([1.0, 1.0, -1.0])


def _pairs(n=2000, seed=1):
    return ab.frame.normalize(np.random.default_rng(seed).normal(size=(2, n, 3)))


def _sheet(rho_r=0.3, rho_t=0.6, sigma=0.5):
    """The thin-walled subsurface of [OpenPBR2026]: unit-albedo diffuse lobes f+ and f-
    weighted by S (1 -+ g) / 2."""
    return Facing(Sum._new((EON(1.0, sigma), Flipped(EON(1.0, sigma))),
                           [np.full(3, rho_r), np.full(3, rho_t)]))


def test_flipped_is_the_lobe_at_the_mirrored_incident_direction():
    wo, wi = _pairs()
    lobe = Conductor(0.4, 0.2)
    flipped = Flipped(lobe)
    np.testing.assert_array_equal(flipped.eval(wo, wi), lobe.eval(wo, wi * M))
    np.testing.assert_array_equal(flipped.pdf(wo, wi), lobe.pdf(wo, wi * M))
    assert flipped.flags == lobe.flags & ~Flags.REFLECTION | Flags.TRANSMISSION
    u = np.random.default_rng(2).random(wo.shape)
    s, t = flipped.sample(wo, u), lobe.sample(wo, u)
    np.testing.assert_array_equal(s.wi, t.wi * M)
    np.testing.assert_array_equal(s.weight, t.weight)
    ok = t.flags != 0
    assert np.all(s.flags[ok] == int(Flags.TRANSMISSION | Flags.GLOSSY))
    assert np.all(s.flags[~ok] == 0)
    np.testing.assert_array_equal(flipped.albedo(wo[:5], method="table"),
                                  lobe.albedo(wo[:5], method="table"))


def test_facing_mirrors_both_directions_below():
    wo, wi = _pairs()
    lobe = Lambert(0.7)
    facing = Facing(lobe)
    below = wo[:, 2] < 0.0
    expected = np.where(below[:, None], lobe.eval(wo * M, wi * M), lobe.eval(wo, wi))
    np.testing.assert_array_equal(facing.eval(wo, wi), expected)
    u = np.random.default_rng(3).random(wo.shape)
    s = facing.sample(wo, u)
    assert np.all(s.wi[below, 2] <= 0.0) and np.all(s.wi[~below, 2] >= 0.0)
    np.testing.assert_allclose(facing.albedo(np.array([[0.0, 0.6, -0.8]]), tol=1e-9),
                               0.7, rtol=1e-12)


def test_thin_diffuse_sheet_is_reciprocal_across_and_keeps_its_energy():
    """f(wo, wi) = f(wi, wo) for every pair, both sides; R + T = rho_r + rho_t from either
    side (quadrature)."""
    wo, wi = _pairs()
    sheet = _sheet()
    np.testing.assert_allclose(sheet.eval(wo, wi), sheet.eval(wi, wo), rtol=1e-15, atol=0)
    up = np.array([[0.0, 0.6, 0.8], [0.99, 0.0, np.sqrt(1 - 0.99**2)]])
    E = sheet.albedo(np.concatenate([up, up * M]), tol=1e-8)
    np.testing.assert_allclose(E, 0.9, atol=1e-6)
    white = _sheet(0.5, 0.5)
    np.testing.assert_allclose(white.albedo(np.concatenate([up, up * M]), tol=1e-8), 1.0,
                               atol=1e-6)


@pytest.mark.parametrize("cos_theta", [0.7, -0.4])
def test_thin_diffuse_sheet_sampling(cos_theta):
    assert_sampling_matches(_sheet(), cos_theta, 0.2, seed=4, n_tests=2)


def test_bad_input():
    with pytest.raises(ValueError, match="lobe"):
        Flipped("lambert")
    with pytest.raises(ValueError, match="lobe"):
        Facing(None)
