"""Sheen: a single-scattering layer of SGGX fibre microflakes [Kutz2021, §6].

Public API
----------
``Sheen(color, roughness, c=2.0, p=1.0)``
    The sheen BRDF of [Kutz2021, eqs. 15-18], sampled exactly by the visible normals of its
    fibre distribution; ``albedo`` by ``"quadrature"``, ``"mc"`` or ``"table"``
    (``tables`` "sheen_albedo").

The derivations (the r = 0 limit, the sampler, the grazing albedo c / 2) are in
``docs/sheen.md``; the measured albedo and table error in ``docs/sheen_measured.md``.

References
----------
[Kutz2021, §6, eqs. 15-18] the BRDF, D, G, Lambda and sigma.
[Heitz2015] the SGGX microflake distribution: D(w) = 1 / (pi sqrt|S| (w^T S^-1 w)^2),
projected area sigma(w) = sqrt(w^T S w); [Kutz2021, eq. 16] is S = diag(1, 1, r^2).
[Heitz2018] visible normals of a linearly transformed sphere.
[DupuyBenyoub2023] a unit vector plus a uniform point of the unit sphere is
cosine-distributed about it.
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf._channels import pick, tinted
from adobe_bsdf.bsdf import Flags, SupportLobe, finished_sample, luminance
from adobe_bsdf.lobes.energy_lookup import lookup
from adobe_bsdf.microfacet import DEN_MIN, rescaled, saturated

__all__ = ["Sheen", "R_SIMILAR"]

#: below this roughness the albedo table is read through the similarity E(mu, r) ~ F(mu / r)
#: of the small-roughness limit, at (min(mu R / r, 1), R): the table's nodes cannot follow
#: the structure of width mu ~ r below ~1e-4 (``docs/sheen.md``; error measured in
#: ``docs/sheen_measured.md``)
R_SIMILAR = 5e-3


#: the defaults of c and p (validated arrays, for ``Sheen._new``)
DEFAULT_C, DEFAULT_P = np.asarray(2.0), np.asarray(1.0)


class Sheen(SupportLobe):
    """Microflake sheen f = c a D(h) G(wi, wo) / (4 cos theta_i cos theta_o) [Kutz2021, eq. 15].

    0 unless both directions are above the surface. With h = (wo + wi) / |wo + wi|:

    - D(h) = 1 / (pi r t^2), t = h_x^2 + h_y^2 + (h_z / r)^2 (eq. 16): the SGGX fibre
      distribution with S = diag(1, 1, r^2), normalised as SGGX is, int <w, h>_+ D(h) dh =
      sigma(w) (not int D = 1: int D over the sphere is 2 r + 2 acos(r) / sqrt(1 - r^2), the
      area of the fibre ellipsoid over pi);
    - G = (1 - exp(-p (Lambda_i + Lambda_o))) / (Lambda_i + Lambda_o) (eq. 17),
      Lambda(w) = sigma(w) / w_z, sigma(w) = sqrt(w_x^2 + w_y^2 + (r w_z)^2) (eq. 18).

    Computed as D = 1 / (pi r w^2) with w = (h_z / r)^2 + 1 - h_z^2 (eq. 16 divided through
    by r^4, which nothing can underflow to 0 / 0) and G / (4 cos_i cos_o) =
    (1 - exp(-p Lambda)) / (4 K) with K = sigma_i cos_o + sigma_o cos_i and Lambda =
    K / (cos_i cos_o) (finite at grazing angles); every term is symmetric in (wo, wi), so
    f is reciprocal bit for bit. At r = 0, D vanishes wherever h_z != 0, which is all of
    the upper hemisphere: f = 0, sampling fails, the albedo is 0.

    Parameters
    ----------
    color : colour in [0, inf), scalar or (..., 3)
        a = sheen amount x sheen colour.
    roughness : array_like in [0, 1]
        Sheen roughness r (not squared, eq. 16).
    c : array_like in [0, inf)
        Brightness constant of eq. 15; [Kutz2021, §6] uses 2 (the largest albedo is then
        c / 2 = 1, at grazing ``wo``).
    p : array_like in (0, inf)
        Optical thickness of the fibre layer (eq. 17); [Kutz2021, §6] uses 1. The albedo
        table holds p = 1 only.

    Notes
    -----
    Sampling (``docs/sheen.md``): the visible normals of D seen from ``wo`` are the normals
    of the ellipsoid diag(1, 1, 1 / r) (unit sphere) (whose projected area is
    proportional to sigma) at points uniform in its projected area. The map diag(1, 1, r)
    takes that ellipsoid to the unit sphere and ``wo`` to v = diag(1, 1, r) wo / sigma(wo);
    there the normal at a point uniform in projected area is cosine-distributed about v,
    and the ellipsoid's normal is h ~ diag(1, 1, r) x. With wi = 2 (wo.h) h - wo,
    pdf(wi) = D(h) / (4 sigma(wo)) and weight = c a sigma(wo) cos_i (1 - exp(-p Lambda)) / K
    = c a G sigma(wo) / cos_o. A sample below the horizon fails (weight and pdf 0): the pdf
    integrates to the success probability, below 1 (at r -> 0, to 0).
    """

    flags = Flags.REFLECTION | Flags.GLOSSY

    def __init__(self, color, roughness, c=2.0, p=1.0):
        self._init(_params.color("color", color, 0.0, np.inf),
                   _params.real("roughness", roughness, 0.0, 1.0),
                   _params.real("c", c, 0.0, np.inf),
                   _params.real("p", p, 0.0, np.inf, lo_open=True))

    def _init(self, color, roughness, c=DEFAULT_C, p=DEFAULT_P):
        self.color, self.roughness, self.c, self.p = color, roughness, c, p
        self._param_shape()  # the parameters must broadcast together
        self._scale = self.c[..., None] * self.color

    def __repr__(self) -> str:
        return (f"Sheen(color={self.color}, roughness={self.roughness}, c={self.c}, "
                f"p={self.p})")

    def _param_shape(self):
        try:
            return np.broadcast_shapes(self.color.shape[:-1], self.roughness.shape,
                                       self.c.shape, self.p.shape)
        except ValueError as exc:
            raise ValueError(f"color {self.color.shape}, roughness {self.roughness.shape}, c "
                             f"{self.c.shape} and p {self.p.shape} do not broadcast") from exc

    # -- the terms of eqs. 15-18 --------------------------------------------------------------
    def _sigma(self, w):
        """sigma(w) = sqrt(w_x^2 + w_y^2 + (r w_z)^2) (eq. 18), without underflow."""
        return np.hypot(np.hypot(w[..., 0], w[..., 1]), self.roughness * w[..., 2])

    def _D(self, wo, wi):
        """D(h) of eq. 16 at h = (wo + wi) / |wo + wi|, from the sum s = wo + wi (symmetric in
        (wo, wi) bit for bit); r > 0. Call under ``np.errstate``: w^2 may overflow (D = 0)."""
        sx = wo[..., 0] + wi[..., 0]
        sy = wo[..., 1] + wi[..., 1]
        sz = wo[..., 2] + wi[..., 2]
        sx, sy, sz, _ = rescaled(sx, sy, sz, sx * sx + sy * sy + sz * sz)  # tiny sums
        horizontal = sx * sx + sy * sy
        length2 = horizontal + sz * sz
        r = self.roughness
        hz_r = sz / (np.sqrt(length2) * r)
        w = hz_r * hz_r + horizontal / length2
        return 1.0 / (np.pi * r * (w * w))

    def _shadowing(self, oz, iz, s_o, s_i):
        """``(1 - exp(-p Lambda), K)``: G / (4 cos_i cos_o) = (1 - exp(-p Lambda)) / (4 K)
        with K = sigma_i cos_o + sigma_o cos_i > 0 and Lambda = Lambda_i + Lambda_o =
        K / (cos_i cos_o) (eqs. 17-18); Lambda = inf at grazing gives 1."""
        K = s_i * oz + s_o * iz
        return -np.expm1(-self.p * (K / (oz * iz))), K

    # -- eval and pdf ---------------------------------------------------------------------
    def _support(self, wo, wi):
        return (wo[..., 2] > 0.0) & (wi[..., 2] > 0.0) & (self.roughness > 0.0)

    def _f(self, wo, wi, up, D):
        """D G / (4 cos_i cos_o) (eq. 15 without c a), 0 outside ``up``."""
        e, K = self._shadowing(wo[..., 2], wi[..., 2], self._sigma(wo), self._sigma(wi))
        DG = saturated(D * e / np.maximum(4.0 * K, DEN_MIN))
        return DG if up is None else pick(up, DG, 0.0)

    def _p(self, wo, up, D):
        """pdf = D(h) / (4 sigma(wo)), 0 outside ``up``; saturated at the largest float (a
        subnormal roughness's D ~ 1 / (pi r) exceeds it)."""
        pdf = saturated(D / (4.0 * self._sigma(wo)))
        return pdf if up is None else pick(up, pdf, 0.0)

    def _eval_kernel(self, wo, wi, up):
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            return saturated(tinted(self._f(wo, wi, up, self._D(wo, wi)), self._scale))

    def _pdf_kernel(self, wo, wi, up):
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            return self._p(wo, up, self._D(wo, wi))

    def _eval_pdf_kernel(self, wo, wi, up):
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            D = self._D(wo, wi)
            return saturated(tinted(self._f(wo, wi, up, D), self._scale)), self._p(wo, up, D)

    # -- sampling ---------------------------------------------------------------------------
    def _sample(self, wo, u):
        return self._drawn(wo, u, weigh=True)

    def _sample_directions(self, wo, u, throughput):
        return self._drawn(wo, u, weigh=False)

    def _drawn(self, wo, u, weigh: bool):
        """The sample; without ``weigh`` its weight is 0 (``_sample_directions``)."""
        r = self.roughness
        ox, oy, oz = wo[..., 0], wo[..., 1], wo[..., 2]
        s_o = self._sigma(wo)
        # a direction x cosine-distributed about v = diag(1, 1, r) wo / sigma(wo): v plus a
        # uniform point of the unit sphere (zero with probability 0)
        uz = 1.0 - 2.0 * u[..., 1]
        ur = np.sqrt(np.maximum(1.0 - uz * uz, 0.0))
        phi = 2.0 * np.pi * u[..., 2]
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            x0 = ox / s_o + ur * np.cos(phi)
            x1 = oy / s_o + ur * np.sin(phi)
            x2 = r * oz / s_o + uz
            # the ellipsoid's normal there, h ~ diag(1, 1, r) x, and the mirror direction
            mz = r * x2
            norm = np.sqrt(x0 * x0 + x1 * x1 + mz * mz)
            hx, hy, hz = x0 / norm, x1 / norm, mz / norm
            two_cos = 2.0 * (ox * hx + oy * hy + oz * hz)
            wi = np.stack([two_cos * hx - ox, two_cos * hy - oy, two_cos * hz - oz], axis=-1)
            ok = (oz > 0.0) & (r > 0.0) & (norm > 0.0) & (wi[..., 2] > 0.0)
            wi[~ok] = (0.0, 0.0, 1.0)  # (a fresh array) the normal where the sample failed
            iz = wi[..., 2]
            pdf, weight = self._p(wo, ok, self._D(wo, wi)), None
            if weigh:
                e, K = self._shadowing(pick(ok, oz, 1.0), iz, s_o, self._sigma(wi))
                weight = tinted(pick(ok, s_o * iz * e / K, 0.0), self._scale)
        return finished_sample(wi, weight, pdf, pick(ok, int(self.flags), int(Flags.NONE)))

    # -- albedo -----------------------------------------------------------------------------
    def _table_E(self, wo, with_error):
        """``(E, error)`` ``(...)`` of the c a = 1 sheen from ``tables`` "sheen_albedo" at
        (cos theta_o, r), through the similarity below ``R_SIMILAR``; 0 where ``wo`` is not
        above the surface or r = 0."""
        r = self.roughness
        mu = np.clip(wo[..., 2], 0.0, 1.0)
        small = r < R_SIMILAR
        with np.errstate(over="ignore"):  # r subnormal: mu R / r is inf, its minimum 1 exact
            mu = pick(small, np.minimum(
                mu * R_SIMILAR / pick(small & (r > 0.0), r, 1.0), 1.0), mu)
        E, error = lookup("sheen_albedo", mu, with_error, roughness=np.maximum(r, R_SIMILAR))
        live = (wo[..., 2] > 0.0) & (r > 0.0)
        return pick(live, E, 0.0), None if error is None else pick(live, error, 0.0)

    def _albedo_table(self, wo, with_error=True):
        """c a E(cos theta_o, r) of the table (p = 1 only); the error is the carried node
        quadrature error."""
        if np.any(self.p != 1.0):
            raise ValueError(f"p = {self.p!r}: method = 'table' needs p = 1 (the table holds "
                             "the albedo of p = 1); use 'quadrature' or 'mc'")
        E, error = self._table_E(wo, with_error)
        return (tinted(E, self._scale),
                None if error is None else tinted(error, self._scale))

    def _sampling_weight(self, wo):
        """luminance(c a) E: the table's albedo (of p = 1 whatever p is; any positive
        estimate keeps ``Sum`` exact)."""
        return luminance(self._scale) * self._table_E(wo, False)[0]
