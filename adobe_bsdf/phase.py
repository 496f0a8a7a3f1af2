"""Phase functions of the media inside a layered slab, with the extinction they imply.

Public API
----------
``henyey_greenstein(wo, wi, g)``, ``sample_henyey_greenstein(wo, u2, g)``
    the Henyey–Greenstein phase function [Henyey1941] and its exact sampler.
``HenyeyGreenstein(g)``
    a medium of particles: extinction the same along every direction.
``FibreMicroflakes(roughness)``
    a medium of specular fibre-like microflakes, the SGGX distribution S = diag(1, 1, r^2)
    [Heitz2015] of the ASM sheen [Kutz2021, eq. 16]: extinction proportional to the flakes'
    projected area sigma(w) = sqrt(w_x^2 + w_y^2 + r^2 w_z^2) [Kutz2021, eq. 18], phase
    function D(h) / (4 sigma(wo)) [Heitz2015, §4], sampled by its visible normals.

A phase object has ``sigma(w)`` (the extinction along the unit direction w, relative to a
medium of unit extinction: a slab of optical thickness tau transmits exp(-tau sigma(w) /
|w_z|) along w), ``eval(wo, wi)`` (per steradian, both directions pointing away from the
scattering point) and ``sample(wo, u2) -> (wi, pdf)``; ``eval`` integrates to 1 over wi and
``sample`` draws it exactly.
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf.frame import _coordinate_system
from adobe_bsdf.sampling import azimuth, henyey_greenstein_cos

__all__ = ["henyey_greenstein", "sample_henyey_greenstein", "HenyeyGreenstein",
           "FibreMicroflakes"]


def henyey_greenstein(wo, wi, g) -> np.ndarray:
    """p(wo, wi) = (1 - g^2) / (4 pi (1 + g^2 + 2 g wo.wi)^(3/2)) [Henyey1941], per steradian,
    with both directions pointing away from the scattering point (g > 0: forward, wi = -wo)."""
    cos = np.sum(np.asarray(wo) * np.asarray(wi), axis=-1)
    denom = 1.0 + g * g + 2.0 * g * cos
    return (1.0 - g * g) / (4.0 * np.pi * denom * np.sqrt(np.maximum(denom, 0.0)))


def sample_henyey_greenstein(wo, u2, g):
    """``(wi, pdf)``: wi drawn from ``henyey_greenstein(wo, ., g)`` by inverting its cumulative
    distribution in the cosine about the travel direction -wo [Pharr2023, §11.3.1]."""
    cos, v = henyey_greenstein_cos(u2[..., 0], g), u2[..., 1]
    sin = np.sqrt(1.0 - cos * cos)
    d = -np.asarray(wo)
    t, b = _coordinate_system(d)
    cos_p, sin_p = azimuth(v)
    wi = ((sin * cos_p)[..., None] * t + (sin * sin_p)[..., None] * b
          + cos[..., None] * d)
    return wi, henyey_greenstein(wo, wi, g)


class HenyeyGreenstein:
    """Particles of Henyey–Greenstein asymmetry ``g`` in (-1, 1): sigma(w) = 1."""

    def __init__(self, g=0.0):
        self.g = _params.scalar("g", g, -1.0, 1.0, lo_open=True, hi_open=True)

    def __repr__(self) -> str:
        return f"HenyeyGreenstein({self.g})"

    def sigma(self, w):
        return np.ones(np.shape(w)[:-1])

    def eval(self, wo, wi):
        return henyey_greenstein(wo, wi, self.g)

    def sample(self, wo, u2):
        return sample_henyey_greenstein(wo, u2, self.g)


class FibreMicroflakes:
    """Specular microflakes of the SGGX fibre distribution S = diag(1, 1, r^2), r =
    ``roughness`` in (0, 1] (module docstring): fibres along the normal, thinner for a
    smaller r.

    - sigma(w) = sqrt(w_x^2 + w_y^2 + r^2 w_z^2) [Kutz2021, eq. 18] (1 for a horizontal w);
    - D(m) = 1 / (pi r (m_x^2 + m_y^2 + m_z^2 / r^2)^2) [Kutz2021, eq. 16], which SGGX
      normalises by the projected area, int <w, m>_+ D(m) dm = sigma(w) [Heitz2015, eq. 4];
    - p(wo, wi) = D(h) / (4 sigma(wo)), h = (wo + wi) / |wo + wi| [Heitz2015, §4]: wo
      mirrored by a flake normal m drawn from the visible normals <wo, m>_+ D(m) / sigma(wo),
      which ``sample`` draws as ``lobes.Sheen`` does, from a linearly transformed sphere
      [Heitz2018; DupuyBenyoub2023], on either side of the surface (D is symmetric in m_z).
      p is not symmetric in (wo, wi): sigma(wo) p(wo, wi) is.
    """

    def __init__(self, roughness):
        self.roughness = _params.scalar("roughness", roughness, 0.0, 1.0, lo_open=True)

    def __repr__(self) -> str:
        return f"FibreMicroflakes({self.roughness})"

    def sigma(self, w):
        w = np.asarray(w)
        return np.hypot(np.hypot(w[..., 0], w[..., 1]), self.roughness * w[..., 2])

    def _D(self, m):
        """D at the unit normal(s) ``m``."""
        r = self.roughness
        t = m[..., 0] ** 2 + m[..., 1] ** 2 + (m[..., 2] / r) ** 2
        return 1.0 / (np.pi * r * t * t)

    def eval(self, wo, wi):
        wo, wi = np.asarray(wo), np.asarray(wi)
        h = wo + wi
        length = np.linalg.norm(h, axis=-1)
        with np.errstate(divide="ignore", invalid="ignore"):
            p = self._D(h / length[..., None]) / (4.0 * self.sigma(wo))
        return np.where(length > 0.0, p, 0.0)  # wi = -wo: no flake reflects straight on

    def sample(self, wo, u2):
        wo = np.asarray(wo)
        r = self.roughness
        side = np.where(wo[..., 2] < 0.0, -1.0, 1.0)
        ox, oy, oz = wo[..., 0], wo[..., 1], side * wo[..., 2]  # wo mirrored above
        s_o = self.sigma(wo)
        # a point cosine-distributed about v = diag(1, 1, r) wo / sigma(wo): v plus a uniform
        # point of the unit sphere; the ellipsoid's normal there is a visible normal
        uz = 1.0 - 2.0 * u2[..., 0]
        ur = np.sqrt(np.maximum(1.0 - uz * uz, 0.0))
        cos_p, sin_p = azimuth(u2[..., 1])
        x0 = ox / s_o + ur * cos_p
        x1 = oy / s_o + ur * sin_p
        mz = r * (r * oz / s_o + uz)
        norm = np.sqrt(x0 * x0 + x1 * x1 + mz * mz)
        norm = np.where(norm > 0.0, norm, 1.0)  # probability 0: the normal (0, 0, 0) -> wi = -wo
        m = np.stack([x0 / norm, x1 / norm, side * mz / norm], -1)
        wi = 2.0 * np.sum(wo * m, -1)[..., None] * m - wo
        wi = wi / np.linalg.norm(wi, axis=-1)[..., None]
        return wi, self.eval(wo, wi)
