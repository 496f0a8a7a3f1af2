"""Energy-preserving Oren–Nayar rough diffuse reflection (EON) [PortsmouthEON2025].

Public API
----------
``EnergyPreservingOrenNayar(albedo, roughness, compensation=True)`` (alias ``EON``)
    The Fujii form of the Oren–Nayar BRDF (FON) [Fujii2012] plus the analytic energy
    compensation of [PortsmouthEON2025] (the glossy-diffuse base of
    [OpenPBR2026, §Glossy-diffuse]); sampled exactly by the clipped-LTC / uniform mixture
    of [PortsmouthEON2025]; ``albedo`` in closed form by ``"table"``.
``fon_albedo(mu, sigma)``
    E_hat(mu, sigma), the directional albedo of the white FON lobe, in closed form.
``fon_average_albedo(sigma)``
    <E_hat>(sigma) = 2 int_0^1 E_hat(mu) mu dmu, in closed form.

References
----------
[Fujii2012] f_FON = (rho / pi)(A + B s / t), A = 1 / (1 + (1/2 - 2 / (3 pi)) sigma),
B = sigma A, s = wi.wo - (n.wi)(n.wo), t = max(n.wi, n.wo) where s > 0, else 1.
[PortsmouthEON2025] the closed forms of E_hat and <E_hat>; the compensation lobe
f_ms = (rho_ms / pi)(1 - E_hat(wi))(1 - E_hat(wo)) / (1 - <E_hat>) with
rho_ms = rho^2 <E_hat> / (1 - rho (1 - <E_hat>)); the clipped linearly transformed cosine
(CLTC) sampler, its fitted matrix coefficients and uniform-mixture probability.
[OpenPBR2026, §Glossy-diffuse] adopts EON for the diffuse base.
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _memo, _params
from adobe_bsdf._channels import masked, pick, put_rows, selected, take_rows, tinted, weighted
from adobe_bsdf.bsdf import Flags, SupportLobe, finished_sample, luminance
from adobe_bsdf.microfacet import saturated
from adobe_bsdf.sampling import azimuth, cosine_hemisphere, disk_xy

__all__ = ["EnergyPreservingOrenNayar", "EON", "fon_albedo", "fon_average_albedo"]

#: A = 1 / (1 + C1 sigma) [Fujii2012]; also G(0) / pi, so E_hat(0) = 1
C1 = 0.5 - 2.0 / (3.0 * np.pi)
#: <E_hat> = A (1 + C2 sigma) [PortsmouthEON2025]
C2 = 2.0 / 3.0 - 28.0 / (15.0 * np.pi)


# -- the FON albedo ---------------------------------------------------------------------------
def _G_over_pi(mu):
    """G(mu) / pi, where E_hat = A + B G / pi [PortsmouthEON2025]:
    G = sin(theta) (theta - sin(theta) mu) + (2/3) ((sin(theta) / mu)(1 - sin^3(theta)) -
    sin(theta)), mu = cos(theta) in [0, 1]. Written with 1 - sin^3 = (1 - sin)(1 + sin +
    sin^2) and 1 - sin = mu^2 / (1 + sin), which is finite at mu = 0 (G(0) = pi C1)."""
    sin = np.sqrt((1.0 - mu) * (1.0 + mu))
    cubic = sin * mu * (1.0 + sin + sin * sin) / (1.0 + sin)
    return (sin * (np.arccos(mu) - sin * mu) + (2.0 / 3.0) * (cubic - sin)) / np.pi


def _A(sigma):
    return 1.0 / (1.0 + C1 * sigma)


def _E_hat(mu, sigma):
    return _A(sigma) * (1.0 + sigma * _G_over_pi(mu))


def _deficit(mu):
    """(1 - E_hat) / B = C1 - G(mu) / pi >= 0 (as 1 / A = 1 + C1 sigma): 1 - E_hat without
    its cancellation at small sigma; clamped at 0 where rounding puts G / pi above C1
    (mu ~ 0)."""
    return _deficit_of(_G_over_pi(mu))


def _deficit_of(G_over_pi):
    """``_deficit`` from G(mu) / pi."""
    return np.maximum(C1 - G_over_pi, 0.0)


def fon_albedo(mu, sigma) -> np.ndarray:
    """E_hat(mu, sigma) = A + B G(mu) / pi: the directional albedo int f_FON cos dwi of the
    FON lobe with rho = 1 at cos theta_o = ``mu`` in [0, 1], roughness ``sigma`` in [0, 1]
    [PortsmouthEON2025]. 1 at mu = 0 and at sigma = 0; shapes broadcast."""
    return _E_hat(_params.real("mu", mu, 0.0, 1.0), _params.real("sigma", sigma, 0.0, 1.0))


def fon_average_albedo(sigma) -> np.ndarray:
    """<E_hat>(sigma) = 2 int_0^1 E_hat(mu) mu dmu = A (1 + C2 sigma) [PortsmouthEON2025],
    ``sigma`` in [0, 1]."""
    sigma = _params.real("sigma", sigma, 0.0, 1.0)
    return _A(sigma) * (1.0 + C2 * sigma)


# -- the sampler's fits -------------------------------------------------------------------------
def _ltc(mu, sigma):
    """(a, b, c, d) of the LTC matrix M = [[a, 0, b], [0, c, 0], [d, 0, 1]] (in the frame of
    ``_frame``) fitted to the FON lobe [PortsmouthEON2025]; M = I at sigma = 0. Over
    [0, 1]^2: det M = c (a - b d) >= 0.91; d < 0 except for mu > 0.9998, where d <= 0.0035."""
    a = 1.0 + sigma * (0.303392 + (-0.518982 + 0.111709 * mu) * mu
                       + (-0.276266 + 0.335918 * mu) * sigma)
    b = sigma * (-1.16407 + 1.15859 * mu + (0.150815 - 0.150105 * mu) * sigma) / (mu**3 - 1.43545)
    c = 1.0 + (0.20013 + (-0.506373 + 0.261777 * mu) * mu) * sigma
    d = (0.540852 + (-1.01625 + 0.475392 * mu) * mu) * sigma / (-1.0743 + mu * (0.0725628 + mu))
    return a, b, c, d


def _uniform_share(mu, sigma):
    """P_u, the probability of the uniform branch of the mixture [PortsmouthEON2025]: in
    [0.02, 0.17] for sigma > 0, 0 at sigma = 0."""
    return sigma**0.1 * (0.162925 + mu * (-0.372058 + (0.538233 - 0.290822 * mu) * mu))


def _frame(wo):
    """(cos phi_o, sin phi_o): the LTC frame's x axis is wo's azimuth ((1, 0) at the normal)."""
    r = np.hypot(wo[..., 0], wo[..., 1])
    safe = pick(r > 0.0, r, 1.0)
    return pick(r > 0.0, wo[..., 0] / safe, 1.0), pick(r > 0.0, wo[..., 1] / safe, 0.0)


def _clip_scale(d):
    """s = (1 + v_z) / 2, v_z = 1 / sqrt(1 + d^2): the plane d x + z = 0 (the horizon's
    pre-image under M) meets the disk of projected directions on the half-ellipse
    x = -sign(d) v_z sqrt(1 - y^2), and the part of the disk above it has area pi s."""
    return 0.5 * (1.0 + 1.0 / np.sqrt(1.0 + d * d))


class EnergyPreservingOrenNayar(SupportLobe):
    """EON: f = f_FON + f_ms, one-sided (0 unless both directions are above the surface).

    - f_FON = (rho / pi) A (1 + sigma s / t) [Fujii2012] (B = sigma A), with
      s = wi.wo - (n.wi)(n.wo) computed as wi_x wo_x + wi_y wo_y (the same, without
      cancellation) and t = max(n.wi, n.wo) where s > 0, else 1;
    - f_ms = (rho_ms / pi)(1 - E_hat(wi))(1 - E_hat(wo)) / (1 - <E_hat>) and
      rho_ms = rho^2 <E_hat> / (1 - rho (1 - <E_hat>)) [PortsmouthEON2025], computed as
      (rho_ms / pi) B (C1 - G_i / pi)(C1 - G_o / pi) / (C1 - C2), since 1 - E_hat =
      B (C1 - G / pi) and 1 - <E_hat> = B (C1 - C2): no 0 / 0 as sigma -> 0.

    The albedo is E(wo) = rho E_hat(mu_o) + rho_ms (1 - E_hat(mu_o)), which is 1 for rho = 1
    (white furnace): int (1 - E_hat(wi)) cos dwi = pi (1 - <E_hat>). At sigma = 0, f is
    Lambert's rho / pi. Every term is symmetric in (wo, wi) operation by operation, so f is
    reciprocal bit for bit. Where s / t exceeds the float64 range (both cosines below
    ~1e-308) it saturates at the largest float, and f stays finite.

    Parameters
    ----------
    albedo : colour in [0, 1], scalar or (..., 3)
        Single-scattering albedo rho.
    roughness : array_like in [0, 1]
        Oren–Nayar roughness sigma (0: Lambert).
    compensation : bool
        Add f_ms (EON); False gives the FON lobe alone, whose albedo is rho E_hat.

    Notes
    -----
    Sampling [PortsmouthEON2025]: with probability P_u (``_uniform_share``, chosen by u[0])
    wi is uniform on the hemisphere; otherwise it is a clipped linearly transformed cosine:
    in the frame whose x axis is wo's azimuth, w_h is cosine-distributed on the part of the
    hemisphere with (M w_h)_z > 0 (an affine squeeze of the unit disk onto the half-disk plus
    half-ellipse of ``_clip_scale``, density w_h,z / (pi s)) and wi = M w_h / |M w_h|, so
    pdf_c(wi) = (|M| / |v|^2)^2 max(v_z, 0) / (pi s) with v = adj(M) wi, and
    pdf = P_u / (2 pi) + (1 - P_u) pdf_c, exact. The clipped side follows the sign of d (the
    fit's d turns positive for mu_o > 0.9998). ``weight = f cos / pdf``.

    At sigma = 0 (everywhere) the lobe is Lambert's and is computed as such: f = rho / pi and
    pdf = cos / pi, the bits the general formulas give there (A = 1, M = I, P_u = 0), and
    Lambert's cosine-hemisphere sample, from the same concentric disk point that the CLTC map
    turns into the frame of wo and back (within 1e-15 of it).
    """

    flags = Flags.REFLECTION | Flags.DIFFUSE

    def __init__(self, albedo, roughness, compensation=True):
        self._init(_params.color("albedo", albedo, 0.0, 1.0),
                   _params.real("roughness", roughness, 0.0, 1.0),
                   _params.flag("compensation", compensation))

    def _init(self, albedo, roughness, compensation=True):
        self.reflectance, self.roughness, self.compensation = albedo, roughness, compensation
        self._param_shape()  # the parameters must broadcast together
        sigma = roughness[..., None]
        deficit = sigma * _A(sigma) * (C1 - C2)  # 1 - <E_hat>
        rho_ms = albedo * albedo * (1.0 - deficit) / (1.0 - albedo * deficit)
        self._rho_ms = rho_ms if compensation else np.zeros_like(rho_ms)
        #: sigma = 0 everywhere: computed as Lambert's lobe (see Notes)
        self._lambert = not np.any(roughness)

    def __repr__(self) -> str:
        return (f"EnergyPreservingOrenNayar(albedo={self.reflectance}, "
                f"roughness={self.roughness}, compensation={self.compensation})")

    def _param_shape(self):
        try:
            return np.broadcast_shapes(self.reflectance.shape[:-1], self.roughness.shape)
        except ValueError as exc:
            raise ValueError(f"albedo {self.reflectance.shape} and roughness "
                             f"{self.roughness.shape} do not broadcast") from exc

    # -- the quantities of wo, once per call (``_memo``: sampling, eval and pdf share them) ----
    def _G_at(self, wo):
        """G(mu_o) / pi."""
        return _memo.once(self, "G", wo, lambda w: _G_over_pi(np.clip(w[..., 2], 0.0, 1.0)))

    def _frame_at(self, wo):
        return _memo.once(self, "frame", wo, _frame)

    def _ltc_at(self, wo):
        """``(a, b, c, d, s, P_u)``: the LTC matrix, its clip scale and the uniform share."""
        def compute(w):
            mu_o = np.clip(w[..., 2], 0.0, 1.0)
            a, b, c, d = _ltc(mu_o, self.roughness)
            return a, b, c, d, _clip_scale(d), _uniform_share(mu_o, self.roughness)
        return _memo.once(self, "ltc", wo, compute)

    # -- eval and pdf ---------------------------------------------------------------------------
    def _support(self, wo, wi):
        return (wo[..., 2] > 0.0) & (wi[..., 2] > 0.0)

    def _f(self, wo, wi, up):
        """f(wo, wi) (..., 3), 0 outside ``up`` (None: all pairs are on the support)."""
        sigma = self.roughness
        if self._lambert:  # fon = A (1 + 0) = 1 and ms = 0: f = rho / pi, the same bits
            f = self._rho(np.broadcast_shapes(wo.shape[:-1], wi.shape[:-1], sigma.shape))
            f /= np.pi
            return f if up is None else masked(up, f)
        mu_o, mu_i = np.clip(wo[..., 2], 0.0, 1.0), np.clip(wi[..., 2], 0.0, 1.0)
        s = wo[..., 0] * wi[..., 0] + wo[..., 1] * wi[..., 1]
        t = pick(s > 0.0, np.maximum(mu_o, mu_i), 1.0)
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            s_over_t = saturated(pick(t > 0.0, s / t, 0.0))
        fon = _A(sigma) * (1.0 + sigma * s_over_t)
        ms = sigma * _A(sigma) * (_deficit_of(self._G_at(wo)) * _deficit(mu_i)) / (C1 - C2)
        f = tinted(fon, self.reflectance)
        f += tinted(ms, self._rho_ms)
        f /= np.pi
        return f if up is None else masked(up, f)

    def _p(self, wo, wi, up):
        """The mixture's density (...), 0 outside ``up``."""
        sigma = self.roughness
        if self._lambert:  # M = I, s = 1, P_u = 0: pdf = pdf_c = wi_z / pi, the same bits
            shape = np.broadcast_shapes(wo.shape[:-1], wi.shape[:-1], sigma.shape)
            pdf = np.broadcast_to(wi[..., 2], shape) / np.pi
            return pdf if up is None else pick(up, pdf, 0.0)
        a, b, c, d, s, share = self._ltc_at(wo)
        cx, cy = self._frame_at(wo)
        x = cx * wi[..., 0] + cy * wi[..., 1]  # wi in the LTC frame
        y = cx * wi[..., 1] - cy * wi[..., 0]
        z = wi[..., 2]
        det = c * (a - b * d)
        # v = adj(M) wi = det wi + D wi, D = adj(M) - det I (exactly 0 at sigma = 0), and for a
        # unit wi |v|^2 = det^2 + D wi . (2 det wi + D wi): at sigma = 0, pdf_c = wi_z / pi
        Dx, Dy, Dz = (c - det) * x - b * c * z, (a - b * d - det) * y, (a * c - det) * z - c * d * x
        length2 = det * det + Dx * (2.0 * det * x + Dx) + Dy * (2.0 * det * y + Dy) + Dz * (
            2.0 * det * z + Dz)
        pdf_c = (det / length2) ** 2 * np.maximum(det * z + Dz, 0.0) / (np.pi * s)
        pdf = share / (2.0 * np.pi) + (1.0 - share) * pdf_c
        return pdf if up is None else pick(up, pdf, 0.0)

    def _eval_kernel(self, wo, wi, up):
        return self._f(wo, wi, up)

    def _pdf_kernel(self, wo, wi, up):
        return self._p(wo, wi, up)

    def _eval_pdf_kernel(self, wo, wi, up):
        return self._f(wo, wi, up), self._p(wo, wi, up)

    # -- sampling ---------------------------------------------------------------------------------
    def _sample(self, wo, u):
        return self._drawn(wo, u, weigh=True)

    def _sample_directions(self, wo, u, throughput):
        return self._drawn(wo, u, weigh=False)

    def _drawn(self, wo, u, weigh: bool):
        """The sample; without ``weigh`` its weight is 0 (``_sample_directions``)."""
        wi = cosine_hemisphere(u[..., 1:3]) if self._lambert else self._directions(wo, u)
        ok = self._support(wo, wi)
        shape = np.broadcast_shapes(ok.shape, self._param_shape())
        ok = np.broadcast_to(ok, shape)
        pdf, weight = self._p(wo, wi, ok), None
        if weigh:
            with np.errstate(divide="ignore", invalid="ignore"):  # pdf 0: failed, zeroed below
                weight = weighted(self._f(wo, wi, ok), wi[..., 2] / pdf)
        return finished_sample(wi, weight, pdf, pick(ok, int(self.flags), int(Flags.NONE)),
                               fresh=True)

    def _directions(self, wo, u):
        """wi of the CLTC / uniform mixture (sigma > 0 somewhere)."""
        a, b, c, d, s, share = self._ltc_at(wo)
        cx, cy = self._frame_at(wo)
        # clipped LTC: a point (x, y) of the unit disk in the LTC frame, squeezed onto the
        # clipped part, x_c = s x - (1 - s) r in [-r, v_z r] (r = sqrt(1 - y^2); mirrored
        # where d > 0), lifted to the hemisphere and mapped by M. The height is
        # 1 - x_c^2 - y^2 = (1 - |p|^2) + (1 - s)(x + r)(x + x_c): the disk's own, which is
        # Lambert's at sigma = 0 (s = 1), plus the squeeze
        px, py = disk_xy(u[..., 1], u[..., 2])
        x = cx * px + cy * py
        y = cx * py - cy * px
        r = np.sqrt(np.maximum(1.0 - y * y, 0.0))
        x_c = s * x - (1.0 - s) * r
        z = np.sqrt(np.maximum(0.0, (1.0 - px ** 2 - py ** 2)
                               + (1.0 - s) * (x + r) * (x + x_c)))
        x = pick(d > 0.0, -x_c, x_c)
        mx, my, mz = a * x + b * z, c * y, d * x + z
        norm = np.sqrt(mx * mx + my * my + mz * mz)  # |m|, as np.linalg.norm sums it
        mx, my, mz = mx / norm, my / norm, mz / norm
        wi = np.stack(np.broadcast_arrays(cx * mx - cy * my, cy * mx + cx * my, mz), axis=-1)
        # the uniform hemisphere where u[0] < P_u: the rows that chose it (a flat batch),
        # else every row
        uniform = u[..., 0] < share
        if wi.ndim == 2 and u.shape == wi.shape:
            index = np.flatnonzero(uniform)
            put_rows(wi, index, _uniform_hemisphere(take_rows(u, index)))
        else:
            wi = selected(uniform, _uniform_hemisphere(u), wi)
        return wi

    # -- albedo -----------------------------------------------------------------------------------
    def _albedo(self, wo):
        """E(wo) = rho E_hat(mu_o) + rho_ms (1 - E_hat(mu_o)) (..., 3); 0 below the surface."""
        up = wo[..., 2] > 0.0
        if self._lambert:  # E_hat = 1 and the multiple-scattering term 0: E = rho
            return masked(up, self._rho(np.broadcast_shapes(up.shape, self.roughness.shape)))
        sigma, G = self.roughness, self._G_at(wo)
        E = tinted(_A(sigma) * (1.0 + sigma * G), self.reflectance)  # rho E_hat(mu_o)
        E += tinted(sigma * _A(sigma) * _deficit_of(G), self._rho_ms)
        return masked(up, E)

    def _rho(self, batch):
        """rho over ``batch`` (a new (..., 3) array): 1 * rho, the bits of fon rho at sigma = 0."""
        return tinted(np.ones(batch), self.reflectance)

    def _albedo_quadrature(self, wo, tol):
        """Gauss–Legendre quadrature of f cos over the hemisphere, split where f has kinks:
        at theta_i = theta_o (1/t switches between 1/mu_o and 1/mu_i) and at the azimuths
        phi_i - phi_o = +-pi/2 (s changes sign), in (theta, phi) so that every piece is smooth
        (the generic cubature's grid does not follow these edges and loses ~1e-5 at grazing
        views). ``error`` is the difference from the rule of half the order. Lobes with
        textured parameters use the generic cubature."""
        if self._param_shape() != ():
            return super()._albedo_quadrature(wo, tol)
        flat = wo.reshape(-1, 3)
        full, half = (_split_quadrature(self, flat, n) for n in (_QUAD_ORDER, _QUAD_ORDER // 2))
        shape = wo.shape[:-1] + (3,)
        return full.reshape(shape), np.abs(full - half).reshape(shape)

    def _albedo_table(self, wo, with_error=True):
        """The closed form (no table): error 0."""
        E = self._albedo(wo)
        return E, np.zeros_like(E) if with_error else None

    def _top_albedo(self, wo):
        return self._albedo(wo)

    def _sampling_weight(self, wo):
        return luminance(self._albedo(wo))


def _uniform_hemisphere(u):
    """The uniform hemisphere's direction of ``u`` (..., 3) (u[1]: 1 - cos theta, u[2]: the
    azimuth)."""
    cos = 1.0 - u[..., 1]
    sin = np.sqrt(np.maximum(0.0, (1.0 - cos) * (1.0 + cos)))
    cos_p, sin_p = azimuth(u[..., 2])
    return np.stack([sin * cos_p, sin * sin_p, cos], axis=-1)


#: short name
EON = EnergyPreservingOrenNayar

#: Gauss–Legendre nodes per piece and axis of ``_albedo_quadrature``; views per block
_QUAD_ORDER, _QUAD_BLOCK = 48, 32


def _gauss(a, b, n):
    """Nodes ``(..., n)`` and weights of the n-point Gauss–Legendre rule on [a, b]."""
    x, w = np.polynomial.legendre.leggauss(n)
    a, b = np.asarray(a)[..., None], np.asarray(b)[..., None]
    return 0.5 * (b - a) * x + 0.5 * (b + a), 0.5 * (b - a) * w


def _split_quadrature(lobe, wo, n):
    """int f(wo, wi) cos theta_i dwi for the rows of ``wo`` ``(m, 3)``, ``(m, 3)``: theta on
    [0, theta_o] and [theta_o, pi/2], phi - phi_o on [-pi, -pi/2], [-pi/2, pi/2],
    [pi/2, pi], n nodes each way per piece."""
    out = np.zeros((len(wo), 3))
    for start in range(0, len(wo), _QUAD_BLOCK):
        w = wo[start:start + _QUAD_BLOCK]
        up = w[:, 2] > 0.0
        theta_o = np.arccos(np.clip(w[:, 2], 0.0, 1.0))
        phi_o = np.arctan2(w[:, 1], w[:, 0])
        t_parts = [_gauss(0.0 * theta_o, theta_o, n), _gauss(theta_o, 0.5 * np.pi + 0 * theta_o, n)]
        theta = np.concatenate([t for t, _ in t_parts], -1)
        w_theta = np.concatenate([q for _, q in t_parts], -1)
        p_parts = [_gauss(a, b, n) for a, b in ((-np.pi, -0.5 * np.pi), (-0.5 * np.pi, 0.5 * np.pi),
                                                (0.5 * np.pi, np.pi))]
        phi = np.concatenate([t for t, _ in p_parts])
        w_phi = np.concatenate([q for _, q in p_parts])
        sin_t, cos_t = np.sin(theta)[:, :, None], np.cos(theta)[:, :, None]
        angle = phi_o[:, None, None] + phi[None, None, :]
        shape = np.broadcast_shapes(sin_t.shape, angle.shape)
        wi = np.stack([sin_t * np.cos(angle), sin_t * np.sin(angle),
                       np.broadcast_to(cos_t, shape)], -1)
        f = lobe._eval(np.broadcast_to(w[:, None, None, :], wi.shape), wi)
        weight = (w_theta * np.sin(theta) * np.cos(theta))[:, :, None] * w_phi[None, None, :]
        out[start:start + len(w)] = pick(up[:, None],
                                             np.einsum("mtpc,mtp->mc", f, weight), 0.0)
    return out
