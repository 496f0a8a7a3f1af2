"""OpenPBR Surface's dispersion [OpenPBR2026, §Dispersion]: the translucent base's index per
RGB channel by Cauchy's equation through n_d and V_d = abbe / scale, each channel with its own
Kulla–Conty compensation."""

from __future__ import annotations

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.dispersion import FRAUNHOFER_NM, RGB_WAVELENGTHS_NM
from adobe_bsdf.materials.openpbr import OpenPBRSurface
from tests.sampling_checks import assert_sampling_matches

GLASS = dict(transmission_weight=1.0, specular_roughness=0.3, specular_ior=1.5)
DISPERSION = dict(transmission_dispersion_scale=0.8, transmission_dispersion_abbe_number=25.0)


def test_no_dispersion_is_the_plain_glass_bit_for_bit():
    wo, wi = ab.frame.normalize(np.random.default_rng(1).normal(size=(2, 500, 3)))
    plain = OpenPBRSurface(**GLASS)
    zero = OpenPBRSurface(**GLASS, transmission_dispersion_scale=0.0,
                          transmission_dispersion_abbe_number=25.0)
    np.testing.assert_array_equal(zero.eval(wo, wi), plain.eval(wo, wi))


def test_channel_indices_follow_cauchy():
    """n(lambda) = A + B / lambda^2 with n(lambda_d) = 1.5 and (n_d - 1) / (n_F - n_C) =
    V_d = 25 / 0.8, at the channels' wavelengths (written out here)."""
    m = OpenPBRSurface(**GLASS, **DISPERSION)
    eta = m.lobes["transmission"].eta
    V = 25.0 / 0.8
    lam_d, lam_F, lam_C = (FRAUNHOFER_NM[k] for k in "dFC")
    B = (1.5 - 1.0) / (V * (lam_F**-2 - lam_C**-2))
    A = 1.5 - B / lam_d**2
    np.testing.assert_allclose(eta, A + B / np.array(RGB_WAVELENGTHS_NM) ** 2, rtol=1e-14)
    assert eta[0] < eta[1] < eta[2]


@pytest.mark.parametrize("r", [0.0, 0.3, pytest.param(1.0, marks=pytest.mark.slow)])
def test_white_dispersive_glass_keeps_its_energy_in_every_channel(r):
    """Quadrature of eval plus the delta branches, both sides (roughness 1 is slow: 2 min)."""
    m = OpenPBRSurface(**dict(GLASS, specular_roughness=r), **DISPERSION)
    mu = np.array([0.7, 0.15])
    s = np.sqrt(1 - mu**2)
    up = np.stack([s, 0 * s, mu], -1)
    wo = np.concatenate([up, up * [1, 1, -1]])
    np.testing.assert_allclose(m.albedo(wo, tol=1e-6), 1.0, atol=2e-3)


@pytest.mark.parametrize("cos_theta", [0.8, -0.5])
def test_dispersive_glass_sampling(cos_theta):
    assert_sampling_matches(OpenPBRSurface(**GLASS, **DISPERSION), cos_theta, 0.4, seed=3,
                            n_tests=2)


def test_dispersion_needs_one_index_model():
    with pytest.raises(ValueError, match="transmission_dispersion_scale"):
        with pytest.warns(DeprecationWarning):
            OpenPBRSurface(**GLASS, **DISPERSION, specular_haze=0.3, haze_model="barla2018")


def test_dispersion_beyond_the_tables_names_the_inputs():
    """A very low Abbe number takes the blue channel's index of a dense glass beyond the
    energy tables (or the red one to 1): ValueError naming the inputs."""
    with pytest.raises(ValueError, match="transmission_dispersion_abbe_number"):
        OpenPBRSurface(transmission_weight=1.0, specular_ior=2.9,
                       transmission_dispersion_scale=1.0, transmission_dispersion_abbe_number=2.0)
    with pytest.raises(ValueError, match="transmission_dispersion_abbe_number"):
        OpenPBRSurface(transmission_weight=1.0, specular_ior=1.02,
                       transmission_dispersion_scale=1.0, transmission_dispersion_abbe_number=0.05)
