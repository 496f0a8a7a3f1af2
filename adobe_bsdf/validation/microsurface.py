"""Brute-force multiple scattering on a rough interface: light followed on the Smith
microsurface, bounce after bounce, until it leaves [Heitz2016ms]. Anisotropic GGX with
uncorrelated heights; the physical reference that the energy-compensated lobes
(``DielectricMS``, ``ConductorMS``) are measured against (``benchmarks.microsurface_peer``),
slow on purpose.

Public API
----------
``MicrosurfaceDielectric(eta, alpha_x, alpha_y=None, max_bounces=MAX_BOUNCES)``
    a rough dielectric interface, relative index ``eta`` = n_below / n_above, lit from either
    side: ``eval``, ``eval_orders``, ``albedo``.
``MicrosurfaceConductor(alpha_x, alpha_y=None, fresnel=None, max_bounces=MAX_BOUNCES)``
    a rough conductor lit from above (``fresnel`` None: F = 1, a white furnace): the same calls.
``Orders``
    what ``eval_orders`` returns: the estimate of f of all orders, of the first order only and
    of the higher orders only, with their standard errors.
``Albedo``
    what ``albedo(split=True)`` returns: reflected and transmitted energy, their standard
    errors and the share of walks cut at ``max_bounces``.
``ORDERS``
    the scattering orders a call can keep: ``"all"``, ``"single"``, ``"multiple"``.
``visible_normal(distribution, w, u2)``
    GGX visible normals of a direction on either side of the mean plane (the walk's sampler).
``MAX_BOUNCES``, ``WALK_CHUNK``
    the default cut of a walk, and the walks run at once (memory).

The microsurface as a volume
----------------------------
Smith's microsurface with uncorrelated heights is a half-space medium that a ray can never
cross [Heitz2016ms, §volumetric analogy]. Heights h have the density P1, here uniform on
[-1, 1], C1(h) = (1 + h) / 2 (the choice of P1 does not change the BSDF: only C1(h) enters, and
it is uniform in [0, 1] for any P1). A ray leaving height h in direction w
[Heitz2016ms, §free paths]:

- going up (w_z > 0) meets no facet below height h' with probability
  (C1(h) / C1(h'))^Lambda(w): it escapes with probability G1(w, h) = C1(h)^Lambda(w) [Heitz2014];
- going down meets no facet above h' with probability (C1(h') / C1(h))^(1 + Lambda(w)): it
  always hits (C1 -> 0 at the bottom).

With V uniform in (0, 1], the next height is log C1(h') = log C1(h) - log(V) / Lambda(w) up (an
escape if that is >= 0), log C1(h) + log(V) / (1 + Lambda(w)) down. The walk keeps log C1, so
that C1 near 0 and 1 - C1 near 0 both keep their precision; it starts at C1 = 1 (the light
comes from above every facet).

At a hit the facet's normal m is a visible normal of w_in = -d, the direction the ray came
from (d its direction of travel), D_w_in(m) = <w_in, m>+ D(m) / A(w_in), with the projected
area A(w) = int <w, m>+ D(m) dm = w_z (1 + Lambda(w)) above the horizon and |w_z| Lambda(w)
below (int <w, m> D(m) dm = w_z). The ray then reflects on the facet with probability
F(w_in.m), else refracts: this is the microflake phase function of the interface
[Heitz2016ms, §phase functions]; its density over the new direction w is

- reflection, m = (w_in + w) / |w_in + w|: F(w_in.m) D(m) / (4 A(w_in)) [Walter2007, eq. 14];
- refraction into the medium of relative index eta' = n_t / n_i, m = -(w_in + eta' w) / |...|
  turned up (it must face w_in and be crossed by w):
  (1 - F(w_in.m)) (w_in.m) D(m) eta'^2 |w.m| / (A(w_in) (w_in.m + eta' w.m)^2)
  [Walter2007, eq. 17].

Below the interface the walk goes on along the lower side of the microsurface, which, mirrored
through the mean plane (z -> -z, h -> -h), is again an uncorrelated GGX microsurface seen from
above (GGX's D is even in the slopes, P1 in h), with index 1 / eta and C1 -> 1 - C1
[Heitz2016ms, §dielectric]: a refraction mirrors the walk's direction and height. A walk
ends when it escapes, upwards in the frame of its side (leaving above or below the surface).

Estimators
----------
A walk from ``wo`` carries the energy of light arriving along ``wo`` (a dielectric walk has
weight 1 throughout: Fresnel only picks the branch). ``albedo`` is the share of walks leaving
on each side. The density of the direction a walk leaves along is
p(wi | wo) = f(wo, wi) (eta_i / eta_o)^2 |cos theta_i|, the integrand of the energy albedo of
design.md (generalized reciprocity f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2 [Veach1997, §5.3]).
``eval`` estimates it by connecting the walk's vertices to wi [Heitz2016ms, §evaluation]:
at a vertex, the phase function's density towards wi (reflection if wi lies on the walk's side,
refraction otherwise) times the probability that wi escapes from the vertex's height,
C1(h)^Lambda(wi) on the walk's side and (1 - C1(h))^Lambda(wi) across. Summed over a walk's
vertices this next-event estimate is unbiased (the walk never depends on wi), and
f = (eta_o / eta_i)^2 p / |cos theta_i|. On a glossy interface it is unbiased but, for the
higher orders, all but useless: a vertex contributes much only where the segment that reached
it lies within ~alpha of the one direction that D sends to wi, which the walk almost never
samples (at alpha = 0.01, 10^6 walks miss nearly all of the multiple scattering at some pairs:
``benchmarks.microsurface_peer``), and a ray going up hits again with probability ~Lambda,
rarely but then with a density ~1 / Lambda. So ``eval`` (i) lets rays going up hit at least
half the time, with the weight that keeps the expectation (``_free_path``), and (ii) counts
each vertex after the first by two strategies, next-event estimation (the segment that reached
it sampled by the walk) and the adjoint connection (that segment sampled from wi through the
vertex's phase function, ``_connect``), weighed by the balance heuristic [Veach1997, §9.2].
``eval_orders(mis=False)`` keeps next-event estimation alone. ``albedo`` runs analog walks.
Both are unbiased up to the walks cut at ``max_bounces`` (``Albedo.lost`` counts them; none in
the tests).

First order in closed form (tests/test_microsurface.py checks it): the first height has
C1^(1 + Lambda(wo)) as its distribution, so the first vertex gives, on average,

- reflection: F D / (4 A(wo)) * (1 + Lambda_o) / (1 + Lambda_o + Lambda_i) =
  F D G2 / (4 |cos theta_o|) with the height-correlated G2 = 1 / (1 + Lambda_o + Lambda_i)
  [Heitz2014, eq. 99]: ``Dielectric``'s and ``Conductor``'s reflection, exactly;
- transmission: (1 + Lambda_o) int C1^Lambda_o (1 - C1)^Lambda_i dC1 / A(wo), i.e. Walter's
  transmission with G = B(1 + Lambda_o, 1 + Lambda_i), the Beta function: the height-correlated
  masking of refraction [Heitz2014], below the 1 / (1 + Lambda_o + Lambda_i) that the library's
  ``Dielectric`` uses for transmission (design.md) wherever both Lambdas are positive.

Random numbers come from ``numpy.random.default_rng`` seeded by ``seed``, the directions' bytes
and the chunk's number: the same call gives the same result, and f(wo, wi), f(wi, wo) draw
independent walks. Walks run in chunks of ``WALK_CHUNK`` (bounded memory; vectorised over the
walks of a chunk, one Python step per bounce of the walks still on the surface).
"""

from __future__ import annotations

import math
import zlib
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf.fresnel import _dielectric
from adobe_bsdf.microfacet import ALPHA_MIN, GGX

__all__ = ["MicrosurfaceDielectric", "MicrosurfaceConductor", "Orders", "Albedo", "ORDERS",
           "MAX_BOUNCES", "WALK_CHUNK", "visible_normal"]

#: the scattering orders a result can keep: every vertex, the first only, the second onwards
ORDERS = ("all", "single", "multiple")
#: vertices after which a walk is cut (and counted in ``Albedo.lost``)
MAX_BOUNCES = 4096
#: walks per chunk: a chunk's state is a few dozen floats per walk (about 30 MB)
WALK_CHUNK = 2**17
#: the smallest probability with which ``eval``'s walks hit again going up (``_walk``)
HIT_MIN = 0.5
#: default walks per evaluated pair and per albedo direction
EVAL_WALKS, ALBEDO_WALKS = 4096, 100_000
#: the largest log C1 of a walk on the surface (C1 < 1 strictly: a vertex lies below the top)
_LOG_C1_MAX = -float(np.finfo(np.float64).smallest_subnormal)
_LN2 = math.log(2.0)


class Orders(NamedTuple):
    """Estimates of f(wo, wi), RGB ``(..., 3)``, by scattering order, and their standard
    errors (one standard deviation of the mean over the walks)."""

    all: np.ndarray
    single: np.ndarray
    multiple: np.ndarray
    all_error: np.ndarray
    single_error: np.ndarray
    multiple_error: np.ndarray


class Albedo(NamedTuple):
    """Energy leaving on the side of ``wo`` (``reflected``) and on the other
    (``transmitted``), RGB ``(..., 3)``, their standard errors, and the share ``(...)`` of walks
    cut at ``max_bounces`` (their energy is in neither)."""

    reflected: np.ndarray
    transmitted: np.ndarray
    reflected_error: np.ndarray
    transmitted_error: np.ndarray
    lost: np.ndarray


def visible_normal(distribution: GGX, w, u2) -> np.ndarray:
    """A normal m ``(..., 3)`` with density D_w(m) = <w, m>+ D(m) / A(w) for ``w`` on either
    side of the mean plane (``GGX.sample_visible`` turns a direction below it up first).

    The spherical caps of [DupuyBenyoub2023, Listing 3] with the sign of w kept: stretched to
    alpha = 1 the upper hemisphere of normals has D = 1 / pi, so D_w is the clamped cosine about
    the stretched direction v restricted to m_z > 0. The clamped cosine is v + q normalised, q
    uniform on the unit sphere; m_z > 0 is q_z > -v_z, a cap of the sphere for either sign of
    v_z (below the horizon the cap is smaller). Unstretching the normal gives D_w(m).

    Parameters
    ----------
    distribution : GGX, scalar alphas
    w : array_like (..., 3), unit vectors, any but straight down (0, 0, -1), from where no
        facet is visible (A = 0)
    u2 : array_like (..., 2), uniforms in [0, 1)
    """
    if type(distribution) is not GGX or distribution.param_shape != ():
        raise ValueError(f"distribution = {distribution!r} is not allowed (allowed: a GGX with "
                         "scalar alphas)")
    w = _params.direction("w", w)
    u2 = _params.uniforms("u2", u2, 2)
    down = (w[..., 0] == 0.0) & (w[..., 1] == 0.0) & (w[..., 2] < 0.0)
    if np.any(down):
        raise ValueError(f"w = {w[down][0]!r} sees no facet (allowed: any unit vector but "
                         "straight down)")
    return _visible_normal(distribution, w, u2[..., 0], u2[..., 1])


def _visible_normal(d: GGX, w, u0, u1):
    ax, ay = d.alpha_x, d.alpha_y
    vx, vy, vz = ax * w[..., 0], ay * w[..., 1], w[..., 2]
    inv = 1.0 / np.sqrt(vx * vx + vy * vy + vz * vz)
    vx, vy, vz = vx * inv, vy * inv, vz * inv
    phi = 2.0 * np.pi * u0
    cz = (1.0 - u1) * (1.0 + vz) - vz  # uniform in [-v_z, 1]
    sin_t = np.sqrt(np.clip(1.0 - cz * cz, 0.0, 1.0))
    mx = ax * (sin_t * np.cos(phi) + vx)
    my = ay * (sin_t * np.sin(phi) + vy)
    mz = cz + vz
    inv = 1.0 / np.sqrt(mx * mx + my * my + mz * mz)
    return np.stack([mx * inv, my * inv, mz * inv], axis=-1)


def _free_path(lam, up, log_c1, u, q_min=0.0):
    """The next vertex of rays leaving the height log C1 = ``log_c1`` with Lambda = ``lam``,
    going up where ``up``, from uniforms ``u`` in [0, 1) [Heitz2016ms, §free paths]: returns
    ``(out, log_c1', weight)``, whether the ray escapes and, where not, log C1 of its next
    vertex (``log_c1`` where it escapes).

    Going up it hits with probability 1 - G1, G1 = C1^Lambda (never where Lambda = 0); given a
    hit, V = C1 / C1' is uniform in (G1, 1], log C1' = log C1 - log(V) / Lambda. Going down
    it always hits, log C1' = log C1 + log(V) / (1 + Lambda), V uniform in (0, 1]. With
    ``q_min`` > 0 a ray going up hits with probability q = max(1 - G1, q_min) instead, and
    ``weight`` = (1 - G1) / q on a hit (1 elsewhere) keeps the expectation of what follows the
    hit; ``q_min`` = 1 forces every possible hit, weighed by its probability."""
    with np.errstate(invalid="ignore"):  # straight up (Lambda = 0): always escapes
        p_hit = np.where(up & (lam > 0.0), -np.expm1(lam * log_c1), 0.0)
    q = p_hit if q_min == 0.0 else np.where(p_hit > 0.0, np.maximum(p_hit, q_min), 0.0)
    out = up & (u >= q)
    hit = up & ~out
    with np.errstate(divide="ignore", invalid="ignore"):
        # given a hit going up, u / q is uniform in [0, 1): V = 1 - (1 - G1) u / q
        log_v = np.where(hit, np.log1p(-p_hit * u / np.where(hit, q, 1.0)), np.log1p(-u))
        step = np.where(up, -log_v / lam, log_v / (1.0 + lam))
        weight = np.where(hit, p_hit / np.where(hit, q, 1.0), 1.0)
    return out, np.minimum(log_c1 + np.where(out, 0.0, step), _LOG_C1_MAX), weight


def _log1mexp(x):
    """log(1 - e^x) for x <= 0 without cancellation: expm1 above -ln 2, log1p below;
    -inf at x = 0."""
    with np.errstate(divide="ignore"):
        return np.where(x > -_LN2, np.log(-np.expm1(np.minimum(x, 0.0))),
                        np.log1p(-np.exp(np.minimum(x, -_LN2))))


def _mirrored(w, where):
    """``w`` ``(n, 3)`` with z negated where ``where`` (a new array)."""
    out = w.copy()
    out[:, 2] = np.where(where, -w[:, 2], w[:, 2])
    return out


def _dot(a, b):
    return a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1] + a[:, 2] * b[:, 2]


def _unit(v):
    """``(v / |v|, |v|^2)`` of rows ``(n, 3)``; rows of length 0 stay 0."""
    length2 = _dot(v, v)
    with np.errstate(divide="ignore", invalid="ignore"):
        unit = np.where(length2[:, None] > 0.0, v / np.sqrt(length2)[:, None], 0.0)
    return unit, length2


class _State:
    """The walks of a chunk still on the microsurface: each one's row ``k``, its direction of
    travel ``d`` in the frame of its side, log C1 of its height in that frame, whether it is
    below the interface (``inside``), its throughput ``beta`` (None: 1 throughout) and the
    density ``pdf`` with which its last segment was sampled (None before the first vertex)."""

    def __init__(self, k, d, log_c1, inside, beta):
        self.k, self.d, self.log_c1, self.inside, self.beta = k, d, log_c1, inside, beta
        self.pdf = None

    def keep(self, mask):
        for name in ("k", "d", "log_c1", "inside", "beta", "pdf"):
            value = getattr(self, name)
            if value is not None:
                setattr(self, name, value[mask])

    def __len__(self):
        return len(self.k)

    def weight(self, mask=None):
        """The throughput of the walks ``mask`` as ``(n, C)`` (1 where not carried)."""
        if self.beta is None:
            return 1.0
        return self.beta if mask is None else self.beta[mask]


def _refracted(w_in, m, c, n_t, n_i):
    """``(w, ok)``: ``w_in`` refracted through the facet ``m`` (c = w_in.m >= 0) from index
    n_i into n_t, Snell's law in vector form [Pharr2023, §9.3]; ``ok`` False under total
    internal reflection."""
    inv = n_i / n_t
    sin2 = inv * inv * (1.0 - c * c)
    cos_t = np.sqrt(np.maximum(0.0, 1.0 - sin2))
    return (inv * c - cos_t)[:, None] * m - inv[:, None] * w_in, sin2 < 1.0


class _Microsurface:
    """The walk shared by the interfaces (module docstring). A subclass supplies its phase
    function: ``_phase`` (value and sampling density towards a direction), ``_scatter`` (a
    sample) and, for the adjoint sample of ``_connect``, ``_indices`` and ``BELOW_SHARE``."""

    #: colour channels of the walk's throughput (1: grey)
    channels = 1
    #: whether the analog walk carries a throughput (a Fresnel colour)
    _carries_weight = False
    #: probability that ``_connect`` puts the last vertex below the interface
    BELOW_SHARE = 0.0

    def _init_surface(self, alpha_x, alpha_y, max_bounces):
        ax = _params.scalar("alpha_x", alpha_x, ALPHA_MIN, np.inf, hi_open=True)
        ay = ax if alpha_y is None else _params.scalar("alpha_y", alpha_y, ALPHA_MIN, np.inf,
                                                       hi_open=True)
        self.distribution = GGX(ax, ay)
        self.max_bounces = _params.integer("max_bounces", max_bounces, 1)

    # -- the phase function's pieces --------------------------------------------------------
    def _area(self, w):
        """A(w): the projected area of the facets visible from ``w`` ``(n, 3)``, either side
        of the horizon (module docstring), without cancellation."""
        d = self.distribution
        z = np.abs(w[:, 2])
        t2 = (d.alpha_x * w[:, 0]) ** 2 + (d.alpha_y * w[:, 1]) ** 2
        s = np.sqrt(t2 + z * z)  # S(w) = |w_z| (1 + 2 Lambda(w))
        return np.where(w[:, 2] > 0.0, 0.5 * (z + s), 0.5 * t2 / (z + s))

    def _reflection_pdf(self, w_in, w):
        """``(D(m) / (4 A(w_in)), w_in.m)``, m = (w_in + w) / |w_in + w|: the density over w of
        a reflection on a visible normal of w_in [Walter2007, eq. 14] (0 where m faces down)."""
        m, length2 = _unit(w_in + w)
        with np.errstate(divide="ignore", invalid="ignore"):
            pdf = self.distribution.D(m) / (4.0 * self._area(w_in))
        pdf = np.where((length2 > 0.0) & np.isfinite(pdf), pdf, 0.0)
        return pdf, np.clip(_dot(w_in, m), 0.0, 1.0)

    def _refraction_pdf(self, w_in, w, eta):
        """``(pdf, w_in.m)``: the density over w of a refraction on a visible normal m of
        w_in into relative index ``eta`` = n_t / n_i, (w_in.m) D(m) eta^2 |w.m| /
        (A(w_in) |w_in + eta w|^2) [Walter2007, eq. 17], m = -(w_in + eta w) / |...| turned
        up; 0 unless m faces w_in and w leaves through it."""
        m, length2 = _unit(-(w_in + eta[:, None] * w))
        m *= np.where(m[:, 2] < 0.0, -1.0, 1.0)[:, None]
        c_in, c_out = _dot(w_in, m), _dot(w, m)
        with np.errstate(divide="ignore", invalid="ignore"):
            pdf = (c_in * self.distribution.D(m) * eta * eta * np.abs(c_out)
                   / (self._area(w_in) * length2))
        valid = (length2 > 0.0) & (c_in > 0.0) & (c_out < 0.0) & np.isfinite(pdf)
        return np.where(valid, pdf, 0.0), np.clip(c_in, 0.0, 1.0)

    def _escape(self, target, log_c1, same):
        """The probability that ``target`` (frame of the walk's side, pointing up where
        ``same``) leaves without a hit from the height log C1: C1^Lambda on this side,
        (1 - C1)^Lambda across."""
        log_c = np.where(same, log_c1, _log1mexp(log_c1))
        lam = self.distribution.lambda_(target)
        with np.errstate(invalid="ignore"):
            return np.where(lam == 0.0, 1.0, np.exp(lam * log_c))

    # -- the adjoint sample of a walk's last segment ----------------------------------------
    def _adjoint_sample(self, wi, below, u0, u1):
        """``(w_a, pdf)``: a direction w_a from which light reaching a vertex on the side
        ``below`` leaves along ``wi`` (physical frame), in the frame of that side, and its
        density: a reflection of wi on one of its visible normals where wi is on that side,
        else a refraction of wi (seen from its side) through one of its visible normals."""
        t = _mirrored(wi, below)
        w_a, pdf = np.zeros_like(t), np.zeros(len(t))
        r = np.flatnonzero(t[:, 2] > 0.0)
        if len(r):
            m = _visible_normal(self.distribution, t[r], u0[r], u1[r])
            w_a[r] = 2.0 * _dot(t[r], m)[:, None] * m - t[r]
            pdf[r] = self._reflection_pdf(t[r], w_a[r])[0]
        x = np.flatnonzero(t[:, 2] < 0.0)
        if len(x):
            tp = _mirrored(t[x], True)  # wi in the frame of its own side: up
            n_t, n_i = self._indices(~below[x])
            m = _visible_normal(self.distribution, tp, u0[x], u1[x])
            w, ok = _refracted(tp, m, np.clip(_dot(tp, m), 0.0, 1.0), n_t, n_i)
            w_a[x] = _mirrored(w, True)
            pdf[x] = np.where(ok, self._refraction_pdf(tp, w, n_t / n_i)[0], 0.0)
        return w_a, pdf

    def _adjoint_pdf(self, wi, below, w_a):
        """The density with which ``_adjoint_sample`` gives ``w_a`` (its side's frame)."""
        t = _mirrored(wi, below)
        pdf = np.zeros(len(t))
        r = np.flatnonzero(t[:, 2] > 0.0)
        if len(r):
            pdf[r] = self._reflection_pdf(t[r], w_a[r])[0]
        x = np.flatnonzero(t[:, 2] < 0.0)
        if len(x):
            n_t, n_i = self._indices(~below[x])
            pdf[x] = self._refraction_pdf(_mirrored(t[x], True), _mirrored(w_a[x], True),
                                          n_t / n_i)[0]
        return pdf

    def _side_share(self, below):
        return np.where(below, self.BELOW_SHARE, 1.0 - self.BELOW_SHARE)

    def _connect(self, s: _State, w_in, wi, rng, nee):
        """The second strategy of the multiple orders: the segment from this vertex to the
        next one sampled backwards from ``wi`` (``_adjoint_sample``, the next vertex's side
        drawn with ``BELOW_SHARE``), its height drawn from the free path given a hit, and the
        path weighed by the balance heuristic [Veach1997, §9.2] against the walk's own
        sample of that segment (``_walk``)."""
        u = rng.random((len(s), 4))
        below = u[:, 0] < self.BELOW_SHARE
        w_a, pdf_dir = self._adjoint_sample(wi, below, u[:, 1], u[:, 2])
        same = below == s.inside
        d = -w_a  # the segment's direction, in the frame of the next vertex's side
        value_a, pdf_a = self._phase(w_in, _mirrored(d, ~same), same, s.inside)
        out, log_c, p_hit = _free_path(self.distribution.lambda_(d), d[:, 2] > 0.0,
                                       np.where(same, s.log_c1, _log1mexp(s.log_c1)),
                                       u[:, 3], 1.0)  # a hit, weighed by its probability
        p_hit = np.where(out, 0.0, p_hit)
        target = _mirrored(wi, below)
        same_t = target[:, 2] > 0.0
        value_j, _ = self._phase(w_a, target, same_t, below)
        escape = self._escape(target, log_c, same_t)
        den = pdf_a + self._side_share(below) * pdf_dir
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            scale = p_hit * escape / den
        ok = (pdf_dir > 0.0) & (p_hit > 0.0) & (den > 0.0) & np.isfinite(scale)
        nee[s.k, 1] += (s.weight() * value_a * value_j
                        * np.where(ok, scale, 0.0)[:, None])

    # -- the walk ---------------------------------------------------------------------------
    def _walk(self, wo, wi, rng, q_min=0.0, mis=True):
        """Walks from ``wo`` ``(n, 3)`` (physical frame), one per row. Returns ``(exits, nee,
        lost)``: the energy ``(n, 2, 2, C)`` leaving by order (first vertex, later) and side
        (of ``wo``, the other) of analog walks (zeros otherwise); the estimates ``(n, 2, C)``
        of p(wi | wo) by order (None where ``wi`` is None); and the walks cut at
        ``max_bounces`` ``(n,)``.

        ``q_min`` = 0 is the analog walk. Above 0 (for ``wi``), a ray going up hits with
        probability q = max(1 - G1, q_min) rather than 1 - G1 (G1 its escape probability),
        and its throughput is multiplied by (1 - G1) / q on a hit: every next-event sum keeps
        its expectation (an escape ends the walk and adds nothing to them), and the hits that
        G1 ~ 1 makes rare (glossy interfaces, where the next vertex's density
        ~ 1 / A(w_in) ~ 1 / Lambda is large) become common with a small weight instead of
        rare with a large contribution.

        Towards ``wi``: the first vertex by next-event estimation; each later vertex by two
        strategies, next-event estimation (the segment that reached it sampled by the walk)
        and ``_connect`` (that segment sampled from ``wi``), weighed by the balance
        heuristic where ``mis``, else next-event estimation alone."""
        n, C = len(wo), self.channels
        exits = np.zeros((n, 2, 2, C))
        nee = None if wi is None else np.zeros((n, 2, C))
        lost = np.zeros(n, dtype=bool)
        start = wo[:, 2] < 0.0  # lit from below: the walk starts in the mirrored frame
        s = _State(np.arange(n), _mirrored(-wo, start), np.zeros(n), start.copy(),
                   np.ones((n, C)) if q_min > 0.0 or self._carries_weight else None)
        vertices = 0
        lambda_ = self.distribution.lambda_
        mis = mis and wi is not None
        while len(s):
            # the free path: an escape, or the height of the next vertex
            out, log_c1, factor = _free_path(lambda_(s.d), s.d[:, 2] > 0.0, s.log_c1,
                                             rng.random(len(s)), q_min)
            if q_min > 0.0:
                s.beta = s.beta * factor[:, None]
            elif np.any(out):
                j = s.k[out]
                side = (s.inside[out] != start[j]).astype(np.intp)
                exits[j, 0 if vertices == 1 else 1, side] += s.weight(out)
            s.log_c1 = log_c1
            s.keep(~out)
            if not len(s):
                break
            if vertices == self.max_bounces:
                lost[s.k] = True
                break
            vertices += 1
            w_in = -s.d
            if wi is not None:
                w = wi[s.k]
                target = _mirrored(w, s.inside)  # in the frame of the walk's side
                same = target[:, 2] > 0.0
                value, _ = self._phase(w_in, target, same, s.inside)
                value = s.weight() * value * self._escape(target, s.log_c1, same)[:, None]
                if mis and vertices > 1:
                    pdf_b = self._side_share(s.inside) * self._adjoint_pdf(w, s.inside, w_in)
                    den = s.pdf + pdf_b
                    value *= np.where(den > 0.0, s.pdf / np.where(den > 0.0, den, 1.0),
                                      0.0)[:, None]
                nee[s.k, 0 if vertices == 1 else 1] += value
                if mis and vertices < self.max_bounces:
                    self._connect(s, w_in, w, rng, nee)
            s.pdf = self._scatter(s, w_in, rng, mis)
        return exits, nee, lost

    # -- statistics over chunks -------------------------------------------------------------
    def _rng(self, seed, chunk, *arrays):
        return np.random.default_rng(
            [seed, chunk] + [zlib.crc32(np.ascontiguousarray(a).tobytes()) for a in arrays])

    def _run(self, wo, wi, n_walks, seed, series, mis=True):
        """Mean and standard error over ``n_walks`` walks per row of ``wo`` (and ``wi``) of
        the per-walk values ``series(exits, nee)`` ``(n, S)``, and the share of walks lost
        per row. Chunks of ``WALK_CHUNK`` walks, their moments merged by the pairwise update
        of [Chan1983]."""
        rows = len(wo)
        count, lost = np.zeros(rows), np.zeros(rows)
        mean = m2 = None
        total = rows * n_walks
        for chunk, first in enumerate(range(0, total, WALK_CHUNK)):
            row = np.arange(first, min(first + WALK_CHUNK, total)) // n_walks
            rng = self._rng(seed, chunk, wo, np.zeros(0) if wi is None else wi)
            if wi is None:
                exits, nee, cut = self._walk(wo[row], None, rng)
            else:
                exits, nee, cut = self._walk(wo[row], wi[row], rng, HIT_MIN, mis)
            values = series(exits, nee)
            if mean is None:
                mean, m2 = np.zeros((rows, values.shape[1])), np.zeros((rows, values.shape[1]))
            here, starts, n_b = np.unique(row, return_index=True, return_counts=True)
            mean_b = np.add.reduceat(values, starts, axis=0) / n_b[:, None]
            dev = values - np.repeat(mean_b, n_b, axis=0)
            m2_b = np.add.reduceat(dev * dev, starts, axis=0)
            n_a = count[here]
            n = n_a + n_b
            delta = mean_b - mean[here]
            mean[here] += delta * (n_b / n)[:, None]
            m2[here] += m2_b + delta * delta * (n_a * n_b / n)[:, None]
            count[here] = n
            lost[here] += np.add.reduceat(cut.astype(np.float64), starts)
        error = np.sqrt(m2 / (count * (count - 1.0))[:, None])
        return mean, error, lost / n_walks

    def _pairs(self, wo, wi):
        """Validated ``(batch, wo (n, 3), wi (n, 3))``."""
        wo, wi = _params.direction("wo", wo), _params.direction("wi", wi)
        batch = _params.batch_shape([("wo", wo), ("wi", wi)])
        return (batch, *(np.broadcast_to(w, batch + (3,)).reshape(-1, 3) for w in (wo, wi)))

    # -- public calls -----------------------------------------------------------------------
    def eval_orders(self, wo, wi, n_walks: int = EVAL_WALKS, seed: int = 0,
                    mis: bool = True) -> Orders:
        """f(wo, wi) in the library's conventions (radiance, no cosine; design.md), RGB
        ``(..., 3)``, estimated from ``n_walks`` walks per pair, by order: all, the first
        vertex only (single scattering), the second onwards (multiple scattering), with
        standard errors (module docstring, Estimators). 0 where a direction lies in the
        tangent plane (or, for the conductor, below it).

        Parameters
        ----------
        wo, wi : array_like (..., 3), unit vectors; broadcast together
        n_walks : int in [2, inf)
        seed : int in [0, inf)
        mis : bool
            True: the later vertices by two strategies weighed by the balance heuristic
            (``_walk``), far less noisy on glossy interfaces; False: next-event estimation
            alone [Heitz2016ms, §evaluation]. Both are unbiased.
        """
        batch, wo, wi = self._pairs(wo, wi)
        n_walks = _params.integer("n_walks", n_walks, 2)
        seed = _params.integer("seed", seed, 0)
        mis = _params.flag("mis", mis)
        index = np.flatnonzero(self._connects(wo, wi))
        out = np.zeros((6, len(wo), 3))

        def series(exits, nee):  # single, multiple, all: (n, 3 C)
            return np.concatenate([nee[:, 0], nee[:, 1], nee[:, 0] + nee[:, 1]], axis=1)

        if len(index):
            o, i = wo[index], wi[index]
            mean, error, _ = self._run(o, i, n_walks, seed, series, mis)
            scale = (self._energy_ratio(o, i) / np.abs(i[:, 2]))[:, None]
            C = self.channels
            for slot, col in ((1, 0), (2, 1), (0, 2)):  # Orders: all, single, multiple
                part = slice(col * C, (col + 1) * C)
                out[slot, index] = scale * mean[:, part]
                out[slot + 3, index] = scale * error[:, part]
        return Orders(*(a.reshape(batch + (3,)) for a in out))

    def eval(self, wo, wi, n_walks: int = EVAL_WALKS, seed: int = 0, order: str = "all",
             return_error: bool = False):
        """f(wo, wi), RGB ``(..., 3)``, of the scattering orders ``order`` (one of ``ORDERS``);
        with ``return_error``, ``(f, standard error)``. See ``eval_orders``."""
        order = _params.choice("order", order, ORDERS)
        return_error = _params.flag("return_error", return_error)
        result = self.eval_orders(wo, wi, n_walks, seed)
        value = getattr(result, order)
        return (value, getattr(result, order + "_error")) if return_error else value

    def albedo(self, wo, n_walks: int = ALBEDO_WALKS, seed: int = 0, split: bool = True,
               order: str = "all"):
        """Directional energy albedo from ``n_walks`` analog walks per direction (module
        docstring): the energy of the walks that leave after their first vertex
        (``order="single"``), after more (``"multiple"``) or either (``"all"``).

        Returns ``Albedo(reflected, transmitted, reflected_error, transmitted_error, lost)``
        (``split``), else ``(E, E_error)`` with E = R + T (design.md's energy albedo), RGB
        ``(..., 3)`` each. For a lossless interface every walk not ``lost`` leaves with its
        energy 1: then E = 1 exactly, with error 0.

        Parameters
        ----------
        wo : array_like (..., 3), unit vectors (in the tangent plane, or below the surface of
            a conductor: 0)
        n_walks : int in [2, inf)
        seed : int in [0, inf)
        split : bool
        order : one of ``ORDERS``
        """
        wo = _params.direction("wo", wo)
        n_walks = _params.integer("n_walks", n_walks, 2)
        seed = _params.integer("seed", seed, 0)
        split = _params.flag("split", split)
        order = _params.choice("order", order, ORDERS)
        batch = wo.shape[:-1]
        wo = wo.reshape(-1, 3)
        orders = {"all": [0, 1], "single": [0], "multiple": [1]}[order]

        def series(exits, nee):  # R, T, R + T: (n, 3 C)
            e = exits[:, orders].sum(axis=1)
            return np.concatenate([e[:, 0], e[:, 1], e[:, 0] + e[:, 1]], axis=1)

        index = np.flatnonzero(self._lit(wo))
        out = np.zeros((6, len(wo), 3))
        lost = np.zeros(len(wo))
        if len(index):
            mean, error, lost[index] = self._run(wo[index], None, n_walks, seed, series)
            C = self.channels
            for col in range(3):
                part = slice(col * C, (col + 1) * C)
                out[col, index], out[col + 3, index] = mean[:, part], error[:, part]
        R, T, E, R_err, T_err, E_err = (a.reshape(batch + (3,)) for a in out)
        if split:
            return Albedo(R, T, R_err, T_err, lost.reshape(batch))
        return E, E_err


class MicrosurfaceDielectric(_Microsurface):
    """A rough dielectric interface between index 1 above and ``eta`` below, as the random
    walk on its Smith microsurface (module docstring): every order of scattering, reflection
    and transmission, light from either side.

    Parameters
    ----------
    eta : float in (0, inf)
        n_below / n_above (1.5: glass under air; 1 / 1.5: air under glass; 1: no interface,
        every walk passes straight through and ``eval`` is 0, as for a delta lobe).
    alpha_x, alpha_y : float in [ALPHA_MIN, inf)
        GGX roughness along the tangent and the bitangent (``alpha_y`` defaults to
        ``alpha_x``).
    max_bounces : int in [1, inf)
        Vertices after which a walk is cut (``Albedo.lost``).
    """

    BELOW_SHARE = 0.5

    def __init__(self, eta, alpha_x, alpha_y=None, max_bounces: int = MAX_BOUNCES):
        self.eta = _params.scalar("eta", eta, 0.0, np.inf, lo_open=True, hi_open=True)
        self._init_surface(alpha_x, alpha_y, max_bounces)

    def __repr__(self) -> str:
        d = self.distribution
        return (f"MicrosurfaceDielectric(eta={self.eta}, alpha_x={float(d.alpha_x)}, "
                f"alpha_y={float(d.alpha_y)})")

    def _indices(self, inside):
        """(n_t, n_i): the index across the interface and on the walk's side."""
        return np.where(inside, 1.0, self.eta), np.where(inside, self.eta, 1.0)

    def _phase(self, w_in, w, same, inside):
        """The phase function from w_in to w (frame of the walk's side) staying on this side
        (``same``: a reflection) or crossing (a refraction): ``(value (n, 1), pdf (n,))``,
        equal (Fresnel picks the branch)."""
        pdf = np.zeros(len(w_in))
        n_t, n_i = self._indices(inside)
        r = np.flatnonzero(same)
        if len(r):
            p, c = self._reflection_pdf(w_in[r], w[r])
            pdf[r] = _dielectric(c, n_t[r], n_i[r]) * p
        t = np.flatnonzero(~same)
        if len(t):
            p, c = self._refraction_pdf(w_in[t], w[t], n_t[t] / n_i[t])
            pdf[t] = (1.0 - _dielectric(c, n_t[t], n_i[t])) * p
        return pdf[:, None], pdf

    def _scatter(self, s: _State, w_in, rng, want_pdf):
        """A visible normal of w_in, then reflection with probability F, else refraction; a
        refraction moves the walk to the other side: its direction and height are mirrored.
        Returns the density of the sampled segment (``_phase``) if ``want_pdf``."""
        u = rng.random((len(s), 3))
        m = _visible_normal(self.distribution, w_in, u[:, 0], u[:, 1])
        c = np.clip(_dot(w_in, m), 0.0, 1.0)
        n_t, n_i = self._indices(s.inside)
        refract = u[:, 2] >= _dielectric(c, n_t, n_i)  # (F = 1 under total reflection)
        w, _ = _refracted(w_in, m, c, n_t, n_i)
        d = np.where(refract[:, None], w, 2.0 * c[:, None] * m - w_in)
        pdf = self._phase(w_in, d, ~refract, s.inside)[1] if want_pdf else None
        s.d = _mirrored(d, refract)
        s.log_c1 = np.where(refract, np.minimum(_log1mexp(s.log_c1), _LOG_C1_MAX), s.log_c1)
        s.inside = s.inside ^ refract
        return pdf

    def _connects(self, wo, wi):
        return (wo[:, 2] != 0.0) & (wi[:, 2] != 0.0)

    def _lit(self, wo):
        return wo[:, 2] != 0.0

    def _energy_ratio(self, wo, wi):
        """(eta_o / eta_i)^2 of each pair: 1 for reflection."""
        eta_o = np.where(wo[:, 2] > 0.0, 1.0, self.eta)
        eta_i = np.where(wi[:, 2] > 0.0, 1.0, self.eta)
        return (eta_o / eta_i) ** 2


class MicrosurfaceConductor(_Microsurface):
    """A rough conductor lit from above, as the random walk on its Smith microsurface: every
    order of reflection, the throughput multiplied by F at each facet.

    Parameters
    ----------
    alpha_x, alpha_y : float in [ALPHA_MIN, inf)
    fresnel : callable or None
        cos theta (``(n,)`` in [0, 1]) -> reflectance ``(n, 3)`` in [0, 1], e.g.
        ``lambda c: adobe_bsdf.fresnel.conductor(c, eta, k)``; None: F = 1 (no absorption:
        every walk leaves, the albedo is 1).
    max_bounces : int in [1, inf)
    """

    def __init__(self, alpha_x, alpha_y=None, fresnel: Callable | None = None,
                 max_bounces: int = MAX_BOUNCES):
        if fresnel is not None and not callable(fresnel):
            raise ValueError(f"fresnel = {fresnel!r} is not allowed (allowed: None or a "
                             "callable cos_theta -> reflectance (..., 3))")
        self.fresnel = fresnel
        self.channels = 1 if fresnel is None else 3
        self._carries_weight = fresnel is not None
        self._init_surface(alpha_x, alpha_y, max_bounces)

    def __repr__(self) -> str:
        d = self.distribution
        return (f"MicrosurfaceConductor(alpha_x={float(d.alpha_x)}, "
                f"alpha_y={float(d.alpha_y)}, fresnel={self.fresnel!r})")

    def _reflectance(self, c):
        if self.fresnel is None:
            return np.ones((len(c), 1))
        return np.broadcast_to(np.asarray(self.fresnel(c), dtype=np.float64), (len(c), 3))

    def _phase(self, w_in, w, same, inside):
        """Reflection only: ``(F D(m) / (4 A(w_in)), D(m) / (4 A(w_in)))``."""
        pdf, c = self._reflection_pdf(w_in, w)
        pdf = np.where(same, pdf, 0.0)
        return self._reflectance(c) * pdf[:, None], pdf

    def _scatter(self, s: _State, w_in, rng, want_pdf):
        u = rng.random((len(s), 2))
        m = _visible_normal(self.distribution, w_in, u[:, 0], u[:, 1])
        c = np.clip(_dot(w_in, m), 0.0, 1.0)
        d = 2.0 * c[:, None] * m - w_in
        pdf = self._reflection_pdf(w_in, d)[0] if want_pdf else None
        if s.beta is not None:
            s.beta = s.beta * self._reflectance(c)
        s.d = d
        return pdf

    def _connects(self, wo, wi):
        return (wo[:, 2] > 0.0) & (wi[:, 2] > 0.0)

    def _lit(self, wo):
        return wo[:, 2] > 0.0

    def _energy_ratio(self, wo, wi):
        return np.ones(len(wo))
