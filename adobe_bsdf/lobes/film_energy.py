"""What a thin film changes in the single-scattering energy of a rough dielectric interface.

Public API
----------
``film_energy_difference(mu, light, alpha, ratio, film, order=FILM_ORDER, light_above=True)``
    Delta(mu) = E_film(mu) - E(mu), per channel, of the interface seen from the light side
    or the dense side, and its reflected part Delta_R, by a Gauss rule over the visible
    normals.
``FilmEnergy(alpha, ratio, film)``
    Delta and Delta_R of both sides tabulated in mu (``thin_film.AdaptiveCubic``), and
    Delta's hemispherical averages: what ``lobes.DielectricMS(film=)``'s multiple-scattering terms
    read to restore exactly 1 - E_film.

A non-absorbing film keeps R + T = 1 at every facet, but it moves energy between reflection
and refraction, whose masking differs. Per visible normal m of wo [Heitz2018, eq. 3],

    Delta(wo) = int D_wo(m) (F_film(c) - F(c)) (G2(wo, wr) - G2(wo, wt)) / G1(wo) dm,

with F at the facet cosine on the less dense side and F_film at the one above the interface
(where the film lies and its model is read; the two agree for a lossless film at
corresponding angles; 0 difference under total internal reflection), wr and wt the
reflected and refracted directions. ``FILM_ORDER`` = 64 Gauss-Legendre nodes per
dimension of the sampler's square; against direction-space cubature of
``Dielectric(film=)`` minus ``Dielectric``, the rule is within 5e-5 at order 64 (1e-5 at
128) for alpha 0.3, and within 4.9e-4 over held-out lobes up to alpha 1 (the worst a rough
lobe seen from the dense side, 1.3e-4 at order 128; docs/film_albedo_measured.md).
"""

from __future__ import annotations

import numpy as np
from numpy.polynomial.legendre import leggauss

from adobe_bsdf.fresnel import _dielectric_k, _k_of_indices
from adobe_bsdf.microfacet import GGX
from adobe_bsdf.thin_film import AdaptiveCubic

__all__ = ["film_energy_difference", "FilmEnergy", "FILM_ORDER", "FILM_TOL"]

#: Gauss-Legendre nodes per dimension of the visible-normal rule
FILM_ORDER = 64
#: the tables' tolerance at the midpoints of their nodes (``thin_film.AdaptiveCubic``)
FILM_TOL = 5e-5
#: cosines integrated at once (memory: FILM_ORDER^2 normals each)
_CHUNK = 16
#: Gauss-Legendre nodes of the hemispherical averages of the tables
_AVERAGE_ORDER = 64


def film_energy_difference(mu, light: bool, alpha: float, ratio: float, film,
                           order: int = FILM_ORDER, light_above: bool = True) -> np.ndarray:
    """``(n, 6)``: Delta, then Delta_R (the reflection's part, F_film - F times G2(wo, wr) /
    G1(wo) alone), per channel, at the cosines ``mu`` ``(n,)`` in (0, 1] seen from the light side
    (``light``) or the dense side of an isotropic GGX interface of roughness ``alpha`` and
    index ratio ``ratio`` = n_dense / n_light >= 1; ``film`` a ``fresnel.Fresnel`` model of
    the cosine above the interface, the light side where ``light_above`` (module
    docstring)."""
    mu = np.asarray(mu, dtype=np.float64).ravel()
    x, w = leggauss(order)
    u1, u2 = np.meshgrid(0.5 * (x + 1.0), 0.5 * (x + 1.0), indexing="ij")
    weights = np.outer(0.5 * w, 0.5 * w)
    d = GGX(alpha)
    eta = ratio if light else 1.0 / ratio  # n on the far side / n on wo's side
    k, eta2 = _k_of_indices(ratio), ratio * ratio
    out = np.zeros((mu.size, 6))
    for start in range(0, mu.size, _CHUNK):
        m = mu[start:start + _CHUNK, None, None]
        oz = np.broadcast_to(m, (m.shape[0],) + u1.shape)
        ox = np.sqrt(np.maximum(1.0 - oz * oz, 0.0))
        oy = np.zeros_like(ox)
        mx, my, mz, s_o = d.visible_and_projected(ox, oy, oz, u1, u2)
        c = ox * mx + oy * my + oz * mz
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            rz = 2.0 * c * mz - oz
            rx, ry = 2.0 * c * mx - ox, 2.0 * c * my - oy
            g_r = np.where(rz > 0.0, d.G2_over_G1_of(oz, s_o, np.abs(rz),
                                                      d.projected(rx, ry, rz)), 0.0)
            sin2_t = (1.0 - c * c) / (eta * eta)
            refracted = sin2_t < 1.0
            cos_t = np.sqrt(np.maximum(1.0 - sin2_t, 0.0))
            a = c / eta - cos_t
            tx, ty, tz = a * mx - ox / eta, a * my - oy / eta, a * mz - oz / eta
            g_t = np.where(refracted & (tz < 0.0),
                           d.G2_over_G1_of(oz, s_o, np.abs(tz), d.projected(tx, ty, tz)), 0.0)
        c_light = c if light else cos_t
        c_above = c if light == light_above else cos_t
        F = _dielectric_k(c_light, k, eta2)
        F_film = np.asarray(film.from_cos2(c_above * c_above), dtype=np.float64)
        difference = np.where(refracted[..., None], F_film - F[..., None], 0.0)
        out[start:start + _CHUNK, :3] = np.einsum("nijc,nij,ij->nc", difference, g_r - g_t,
                                                  weights)
        out[start:start + _CHUNK, 3:] = np.einsum("nijc,nij,ij->nc", difference, g_r, weights)
    return out


class FilmEnergy:
    """Delta(mu) of both sides of one interface (scalar ``alpha`` > 0, ``ratio`` > 1, the
    light side above where ``light_above``) under ``film``, tabulated in mu to ``FILM_TOL``
    (built at construction), and the averages 2 int Delta mu dmu of each side.

    Attributes
    ----------
    light, dense : AdaptiveCubic
    average_light, average_dense : ndarray (3,)
    """

    def __init__(self, alpha: float, ratio: float, film, light_above: bool = True):
        def side(light):
            def f(mu):
                value = np.zeros((np.size(mu), 6))
                inside = np.asarray(mu) > 0.0
                value[inside] = film_energy_difference(np.asarray(mu)[inside], light, alpha,
                                                       ratio, film, FILM_ORDER, light_above)
                return value
            return AdaptiveCubic(f, FILM_TOL, start=16, max_nodes=512)

        self.light, self.dense = side(True), side(False)
        x, w = leggauss(_AVERAGE_ORDER)
        mu, w = 0.5 * (x + 1.0), 0.5 * w
        self.average_light = 2.0 * (w * mu) @ self.light(mu)[:, :3]
        self.average_dense = 2.0 * (w * mu) @ self.dense(mu)[:, :3]

    def __call__(self, mu, light, reflected: bool = False) -> np.ndarray:
        """Delta ``(..., 3)`` at the cosines ``mu`` on the light side where ``light``, else
        the dense side's; with ``reflected``, Delta_R."""
        mu = np.asarray(mu, dtype=np.float64)
        part = slice(3, 6) if reflected else slice(0, 3)
        shape = mu.shape
        flat = mu.ravel()
        value = np.where(np.broadcast_to(light, shape).ravel()[:, None],
                         self.light(flat)[:, part], self.dense(flat)[:, part])
        return value.reshape(shape + (3,))
