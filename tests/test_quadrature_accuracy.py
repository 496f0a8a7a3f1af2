"""Direction-space albedo quadrature against independent references, within its own estimate.

The rough dielectric's integrand has edges that are not rings about +z: the transmitted lobe
jumps to 0 on the refraction horizon (GGX's D(h) does not vanish at h_z = 0) and vanishes on a
cone about -wo, and reflection from the denser side has the square-root edge of total internal
reflection on a cone about wo. A cell straddling such an edge fooled the Genz–Malik estimate
(errors of 1e-6 reported as 1e-10). Here the value must agree with the reference within the
error it reports.

References: nested ``scipy.integrate.quad`` over (theta_i, phi_i) of the same ``eval``, with the
refraction horizon and the cone edges as breakpoints (without them quad itself errs by up to
4e-9 at the TIR edge and 6e-12 at the cone edge); the isotropic ones agree to 1e-13 with a
piecewise Gauss–Legendre integration over microfacet normals (E_R + E_T).
"""

import numpy as np
import pytest

import adobe_bsdf as ab

#: (cos theta_o, alpha_x, alpha_y, eta, phi_o) -> R + T
REFERENCES = [
    ((0.7, 0.3, 0.3, 1.5, 0.0), 0.9710631164694761),
    ((0.1, 0.5, 0.5, 1.5, 0.4), 0.8525545268837154),
    ((0.3, 0.1, 0.1, 1 / 1.5, 0.0), 0.9291959182490562),
    ((0.9, 0.3, 0.3, 1 / 1.5, 0.4), 0.879637562640512),
    ((0.5, 1.0, 1.0, 1.1, 0.0), 0.7557091567488219),
    ((0.8, 0.2, 0.2, 1 / 1.1, 0.0), 0.9731843133500266),
    ((0.7, 0.5, 0.1, 1.5, 1.0), 0.9639453461489703),
]
#: uncertainty of the references
REFERENCE = 1e-12


def direction(cos_theta, phi):
    s = np.sqrt(1.0 - cos_theta**2)
    return np.array([s * np.cos(phi), s * np.sin(phi), cos_theta])


@pytest.mark.parametrize(("case", "reference"), REFERENCES)
@pytest.mark.parametrize("tol", [1e-8, 1e-10])
def test_rough_dielectric_albedo_is_within_its_error_estimate(case, reference, tol):
    mu, alpha_x, alpha_y, eta, phi = case
    lobe = ab.lobes.Dielectric(eta, alpha_x, alpha_y)
    value, error = lobe.albedo(direction(mu, phi), tol=tol, return_error=True)
    assert np.all(error <= tol)
    assert np.all(np.abs(value - reference) <= error + REFERENCE), (value - reference, error)


def test_batch_of_interfaces_matches_single_directions():
    """Each batch element has its own map of the shared grid."""
    eta = np.array([1.5, 1 / 1.5, 1.01, 2.4])
    wo = np.stack([direction(c, 0.3 * i) for i, c in enumerate((0.7, 0.3, -0.8, -0.2))])
    value, error = ab.lobes.Dielectric(eta, 0.3).albedo(wo, tol=1e-8, return_error=True)
    for i in range(4):
        single, single_error = ab.lobes.Dielectric(eta[i], 0.3).albedo(wo[i], tol=1e-8,
                                                                       return_error=True)
        np.testing.assert_allclose(value[i], single, atol=error[i, 0] + single_error[0])
