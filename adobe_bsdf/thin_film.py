"""Thin-film iridescence: the reflectance of a thin non-absorbing film on a substrate.

Public API
----------
``airy_reflectance(wavelength_nm, cos_theta, thickness_nm, film_ior, substrate_eta,
substrate_k=0, outside_ior=1)``       spectral reflectance R of outside / film / substrate by
                                      the Airy sum of the film's multiple reflections
``airy_transmittance(...)``           the fraction T of the power that enters the substrate
                                      (same arguments; R + T = 1: the film does not absorb)
``ThinFilm(thickness_nm, film_ior, substrate, outside_ior=1, wavelengths_nm=None,
model="spectral")``                   the film as a ``fresnel.Fresnel`` model: linear Rec. 709
                                      RGB of the spectral reflectance, for any lobe that takes
                                      a Fresnel model; ``model="three_wavelengths"``: the
                                      reflectance at one wavelength per channel instead
``ThinFilm.over_f82_tint(thickness_nm, film_ior, f0, tint, outside_ior=1)``
                                      the film on an F82-tint metal, through an effective
                                      complex index per channel
``ThinFilm.spectral_rgb(cos_theta)``  the direct spectral evaluation (the reference of the
                                      film's table in cos theta)
``AdaptiveCubic(f, tol)``             a piecewise-cubic table of a function on [0, 1], its
                                      nodes refined until it meets a tolerance
``WAVELENGTHS_NM``                    the default wavelength grid of ``ThinFilm``
``CHANNEL_WAVELENGTHS_NM``            the default wavelengths (R, G, B) of its three-wavelength
                                      model

The stack is: a non-absorbing outside medium (index n1: air, or the coat), a non-absorbing
film (n2, thickness d) and a substrate of complex index n3 = eta + i k (a dielectric base,
k = 0, or a metal). Indices are absolute (or all relative to one reference medium). OpenPBR
puts the film inside the Fresnel factor of the metal and the dielectric base [OpenPBR2026,
§Thin-film iridescence] and recommends [Belcour2017]; this module evaluates the exact Airy
sum per wavelength, the spectral reference that [Belcour2017]'s RGB approximation (its
§Spectral integration) is checked against.

References
----------
[Belcour2017, §Thin-film interference] the Airy summation of the film's reflections, R = |r|^2
with r = r12 + t12 t21 r23 e^{i dphi} / (1 - r21 r23 e^{i dphi}) (r21 = -r12, t12 t21 =
1 - r12^2), unpolarised light as the mean of s and p.
[BornWolf1980, §1.5.2] the Fresnel amplitudes; [§1.6.4] the homogeneous film,
r = (r12 + r23 e^{2 i beta}) / (1 + r12 r23 e^{2 i beta}), beta = k0 n2 d cos theta2;
[§13.4] the same with an absorbing substrate (complex n3).
[OpenPBR2026, §Thin-film iridescence] the film in the Fresnel factor of both bases; the metal
through an effective complex index from its F82-tint colours ([Gulbrandsen2014]).
"""

from __future__ import annotations

import functools
import threading

import numpy as np

from adobe_bsdf import _params, config, fresnel, spectral
from adobe_bsdf.fresnel import _COS_SLACK, Fresnel

__all__ = ["airy_reflectance", "airy_transmittance", "ThinFilm", "AdaptiveCubic",
           "WAVELENGTHS_NM", "CHANNEL_WAVELENGTHS_NM", "MODELS", "TABLE_TOL"]

#: default wavelength grid of ``ThinFilm`` (nm): 380-780 nm in steps of ``_STEP_NM`` (its
#: error against the 1 nm grid is in the ``ThinFilm`` docstring)
_STEP_NM = 2.0
WAVELENGTHS_NM = np.arange(spectral.RANGE_NM[0], spectral.RANGE_NM[1] + 0.5 * _STEP_NM,
                           _STEP_NM)
WAVELENGTHS_NM.setflags(write=False)
#: the colour models of ``ThinFilm``: the spectral sum turned into RGB (the reference), or
#: the reflectance at one wavelength per channel (what RGB renderers evaluate)
MODELS = ("spectral", "three_wavelengths")
#: the default wavelengths (nm) of the red, green and blue channels of the
#: ``"three_wavelengths"`` model
CHANNEL_WAVELENGTHS_NM = (620.0, 540.0, 450.0)
#: the tolerance of ``ThinFilm``'s table in cos theta at the midpoints of its nodes
#: (``AdaptiveCubic``; the measured error between the nodes is in the ``ThinFilm`` docstring)
TABLE_TOL = 1e-6
#: guards the lazy construction of the tables (one build per owner, whichever thread asks;
#: reentrant: a lobe's table is built from its film's)
_LOCK = threading.RLock()


def built_once(owner, make):
    """``owner._table``: ``make()``'s ``AdaptiveCubic``, built on the first call under the
    module's lock and kept (``False`` where it did not converge); None where there is none."""
    if owner._table is None:
        with _LOCK:
            if owner._table is None:
                table = make()
                owner._table = table if table.converged else False
    return owner._table if owner._table is not False else None


# --- the Airy sum ------------------------------------------------------------------------
def _complex(re, im) -> np.ndarray:
    """re + i im with the sign of a zero imaginary part kept (+0: the principal square root
    of a negative real is then +i sqrt, the evanescent wave)."""
    re, im = np.broadcast_arrays(np.asarray(re, dtype=np.float64),
                                 np.asarray(im, dtype=np.float64))
    z = np.empty(re.shape, dtype=np.complex128)
    z.real = re
    z.imag = im
    return z


def _airy(lam, c, d, n1, n2, eta, k, transmittance=True):
    """(R, T) of the stack n1 / n2 (thickness d) / eta + i k at cos theta1 = c and
    wavelength lam, all validated and broadcasting; see ``airy_reflectance``. T is None
    unless ``transmittance``.

    With the invariant n1 sin theta1 = n_j sin theta_j, q_j = n_j cos theta_j =
    sqrt(n_j^2 - n1^2 + (n1 c)^2) on the principal branch (Re, Im >= 0: the wave that
    decays away from the interface, in a metal or beyond a critical angle). The
    admittances are y_j = q_j (s) and q_j / n_j^2 (p), so that for both polarisations
    r_ij = (y_i - y_j) / (y_i + y_j) and 1 + r_ij = 2 y_i / (y_i + y_j) [BornWolf1980,
    §1.5.2, §13.2]; the round trip in the film has the phase delta = 2 beta =
    4 pi d q2 / lambda (complex beyond the film's critical angle: the film then damps).

    The Airy sum r = (r12 + r23 E) / (1 + r12 r23 E), E = e^{i delta} [BornWolf1980, §1.6.4]
    is evaluated as

        num = b - a - r23 m,   den = a + b - a b - r12 r23 m,   r = num / den,

    with a = 1 - r12, b = 1 + r23 and m = 1 - E = -expm1(i delta), each formed directly
    (a = 2 y2 / (y1 + y2), b = 2 y2 / (y2 + y3)): the same quantities, but free of the
    cancellation of r12 -> 1, r23 -> -1, E -> 1 at the film's critical angle (q2 -> 0),
    where the textbook form loses all digits. At q2 = 0 exactly every term vanishes like
    q2 and the limit of num / q2 and den / q2 is taken (a / q2 -> 2 g / y1, b / q2 ->
    2 g / y3, m / q2 -> -4 pi i d / lambda, with y2 = g q2).

    Where r12 -> -1 and r23 -> 1 instead (grazing incidence on a substrate of the outside's
    index, as a soap film in air), the small quantities are u = 1 + r12 and v = 1 - r23,
    and r12 + r23 = u - v, 1 + r12 r23 = u + v - u v; each element takes the pair that is
    smaller.

    The power entering the substrate is T = Re(y3) / y1 |t|^2 with
    t = (1 + r12)(1 + r23) e^{i delta / 2} / den [BornWolf1980, §1.6.3] (fields tangential
    to the interfaces), written with (1 + r12) / sqrt(y1) = 2 sqrt(y1) / (y1 + y2) so that
    nothing is divided by a grazing y1; the quotients are complex divisions of both terms
    scaled by a power of two (``_quotient``), so that subnormal numerators and denominators
    keep their ratio.

    Index-matched interfaces are no interfaces: n2 = n1 (or d = 0) leaves the interface
    n1 / n3 and n3 = n2 the interface n1 / n2, evaluated directly; with no interface left
    R = 0, T = 1, and otherwise R = 1, T = 0 at c = 0.
    """
    with np.errstate(all="ignore"):  # the masked special cases divide by zero
        n1c = n1 * c
        n1c2 = n1c * n1c
        q1 = n1c
        q2 = np.sqrt(_complex((n2 - n1) * (n2 + n1) + n1c2, 0.0))
        q3 = np.sqrt(_complex((eta - n1) * (eta + n1) - k * k + n1c2, 2.0 * eta * k))
        n3_2 = _complex((eta - k) * (eta + k), 2.0 * eta * k)
        match12 = n2 == n1
        match23 = (eta == n2) & (k == 0.0)
        # q_j = n1 c exactly where n_j = n1 (where (n1 c)^2 underflows, the formula gives 0)
        q2 = np.where(match12, q1, q2)
        q3 = np.where((eta == n1) & (k == 0.0), q1, np.where(match23, q2, q3))
        phase = (4.0 * np.pi) * (d / lam)  # delta / q2
        bare = match12 | (phase == 0.0)  # no film (or one too thin for float64): n1 / n3
        single = bare | match23
        delta = phase * q2
        m = -np.expm1(1j * delta)  # 1 - E
        E_abs = np.exp(-delta.imag) if transmittance else None  # |e^{i delta / 2}|^2
        critical = (q2 == 0.0) & ~single
        R = T = 0.0
        for g1, g2, g3 in ((1.0, 1.0, 1.0), (1.0 / (n1 * n1), 1.0 / (n2 * n2), 1.0 / n3_2)):
            y1, y2, y3 = g1 * q1, g2 * q2, g3 * q3  # s, then p
            r12 = (y1 - y2) / (y1 + y2)
            r23 = (y2 - y3) / (y2 + y3)
            a = 2.0 * y2 / (y1 + y2)  # 1 - r12
            b = 2.0 * y2 / (y2 + y3)  # 1 + r23
            u = 2.0 * y1 / (y1 + y2)  # 1 + r12
            v = 2.0 * y3 / (y2 + y3)  # 1 - r23
            # r12 + r23 and 1 + r12 r23 from the small ones of (a, b) or (u, v)
            by_uv = _abs2(u) + _abs2(v) < _abs2(a) + _abs2(b)
            num0 = np.where(by_uv, u - v, b - a)
            den0 = np.where(by_uv, u + v - u * v, a + b - a * b)
            num = num0 - r23 * m
            den = den0 - (r12 * r23) * m
            tau = 2.0 * np.sqrt(y1) / (y1 + y2) * b  # |tau|^2 = |t12 t23|^2 / y1
            if np.any(critical):  # q2 = 0: the limits of num / q2 and den / q2
                A, B, M = 2.0 * g2 / y1, 2.0 * g2 / y3, -1j * phase
                num = np.where(critical, B - A + M, num)
                den = np.where(critical, A + B + M, den)
                tau = np.where(critical, 2.0 / np.sqrt(y1) * B, tau)
            if np.any(single):  # the film (or the substrate) matches its neighbour
                yj = np.where(bare, y3, y2)
                num = np.where(single, y1 - yj, num)
                den = np.where(single, y1 + yj, den)
                tau = np.where(single, 2.0 * np.sqrt(y1), tau)
            R = R + 0.5 * _abs2(_quotient(num, den))
            if transmittance:
                # |tau / den| reaches 1e154 where y3 is subnormal: square after the product
                T = T + 0.5 * (np.abs(_quotient(tau, den)) * np.sqrt(y3.real * E_abs)) ** 2
    # no interface at all (R = 0, T = 1), else R = 1 at grazing incidence (where the
    # quotients above are 0 / 0 for a bare interface n1 / n1 + i k seen at c = 0)
    none = bare & (eta == n1) & (k == 0.0)
    grazing = c == 0.0
    if np.any(none) or np.any(grazing):
        R = np.where(none, 0.0, np.where(grazing, 1.0, R))
        T = np.where(none, 1.0, np.where(grazing, 0.0, T)) if transmittance else None
    # |r| <= 1 and R + T = 1 hold exactly; the bounds only remove rounding (a few ulp)
    return (np.asarray(np.minimum(R, 1.0)),
            np.asarray(np.minimum(T, 1.0)) if transmittance else None)


def _quotient(num, den):
    """num / den, both first scaled by the power of two that brings |den| near 1: NumPy's
    complex division overflows or gives NaN where den is subnormal (0 / 5e-309 is NaN),
    which a film of subnormal thickness seen at a subnormal cosine reaches."""
    _, e = np.frexp(np.maximum(np.abs(den.real), np.abs(den.imag)))
    half = np.ldexp(1.0, -(e // 2))  # two steps: 2^1074 alone overflows
    rest = np.ldexp(1.0, e // 2 - e)
    return (num * half * rest) / (den * half * rest)


def _abs2(z):
    """|z|^2 of a complex array (without the square root of ``abs``)."""
    return z.real * z.real + z.imag * z.imag


def _stack(wavelength_nm, cos_theta, thickness_nm, film_ior, substrate_eta, substrate_k,
           outside_ior):
    """The validated arguments of ``airy_reflectance`` in the order of ``_airy``."""
    lam = _params.real("wavelength_nm", wavelength_nm, 0.0, np.inf, lo_open=True)
    c = _params.real("cos_theta", cos_theta, 0.0, 1.0 + _COS_SLACK)
    d = _params.real("thickness_nm", thickness_nm, 0.0, np.inf)
    n2 = _params.real("film_ior", film_ior, 0.0, np.inf, lo_open=True)
    eta = _params.real("substrate_eta", substrate_eta, 0.0, np.inf, lo_open=True)
    k = _params.real("substrate_k", substrate_k, 0.0, np.inf)
    n1 = _params.real("outside_ior", outside_ior, 0.0, np.inf, lo_open=True)
    named = [("wavelength_nm", lam), ("cos_theta", c), ("thickness_nm", d), ("film_ior", n2),
             ("substrate_eta", eta), ("substrate_k", k), ("outside_ior", n1)]
    _params.batch_shape(named, trailing=0)
    return lam, np.minimum(c, 1.0), d, n1, n2, eta, k  # the minimum removes rounding only


def airy_reflectance(wavelength_nm, cos_theta, thickness_nm, film_ior, substrate_eta,
                     substrate_k=0.0, outside_ior=1.0) -> np.ndarray:
    """Reflectance of a thin film on a substrate, by the Airy sum of its multiple reflections.

    Parameters
    ----------
    wavelength_nm : array_like, in (0, inf)
        Vacuum wavelength lambda (nm; the unit of ``thickness_nm``).
    cos_theta : array_like, in [0, 1]
        Cosine of the angle of incidence in the outside medium.
    thickness_nm : array_like, in [0, inf)
        Film thickness d (nm).
    film_ior : array_like, in (0, inf)
        Film index n2 (non-absorbing).
    substrate_eta, substrate_k : array_like, in (0, inf) and [0, inf)
        Substrate index n3 = eta + i k (k = 0: a dielectric; k > 0: an absorbing base).
    outside_ior : array_like, in (0, inf)
        Index n1 of the (non-absorbing) medium the light comes from.

    Returns
    -------
    ndarray, the broadcast shape: the unpolarised reflectance R = (|r_s|^2 + |r_p|^2) / 2,
    in [0, 1].

    Notes
    -----
    Every argument broadcasts against the others (e.g. wavelengths ``(L,)`` against
    cosines ``(N, 1)``).

    r = (r12 + r23 e^{i delta}) / (1 + r12 r23 e^{i delta}), delta = 4 pi n2 d cos theta2 /
    lambda, the geometric series of the reflections inside the film summed in closed form
    [Belcour2017, §Thin-film interference], [BornWolf1980, §1.6.4]; r_ij are the Fresnel
    amplitudes of each interface, complex for the absorbing substrate and beyond a critical
    angle (an evanescent wave in the film or the substrate) [BornWolf1980, §1.5.2, §13.2].
    It is evaluated in a rearranged form that keeps full accuracy at the film's critical
    angle (``_airy``).

    Special values: d = 0 is the bare interface n1 / n3 (``fresnel.dielectric``,
    ``fresnel.conductor`` to rounding); n2 = n1 or n3 = n2 (k = 0) remove that interface;
    cos theta = 0 gives R = 1, except for n1 = n2 = n3 (no interface at all: R = 0, as
    ``fresnel.dielectric`` with eta = 1). Large d / lambda only adds phase; nothing
    overflows for d / lambda below about 1e300.
    """
    return _airy(*_stack(wavelength_nm, cos_theta, thickness_nm, film_ior, substrate_eta,
                         substrate_k, outside_ior))[0]


def airy_transmittance(wavelength_nm, cos_theta, thickness_nm, film_ior, substrate_eta,
                       substrate_k=0.0, outside_ior=1.0) -> np.ndarray:
    """Fraction of the incident power that enters the substrate (``airy_reflectance``'s
    arguments).

    T = (Re(y3) / y1) |t|^2, unpolarised (the mean of s and p), with the Airy sum of the
    transmitted amplitudes t = t12 t23 e^{i delta / 2} / (1 + r12 r23 e^{i delta})
    [BornWolf1980, §1.6.3-§1.6.4] and the admittances y_j = n_j cos theta_j (s),
    cos theta_j / n_j (p) (for the amplitudes of the tangential fields). The film does not
    absorb, so R + T = 1 for any substrate: for a dielectric T is the transmitted
    fraction (0 under total internal reflection), for an absorbing substrate the absorbed
    one. In [0, 1].
    """
    return _airy(*_stack(wavelength_nm, cos_theta, thickness_nm, film_ior, substrate_eta,
                         substrate_k, outside_ior))[1]


# --- a piecewise-cubic table on [0, 1] ---------------------------------------------------
class AdaptiveCubic:
    """A function f(x) on [0, 1] with values ``(m,)`` per point as a piecewise cubic, on nodes
    refined until the interpolant meets ``tol`` at the midpoint of every interval.

    ``f(x)`` takes an array ``(n,)`` of abscissas and returns ``(n, m)``. The nodes start as
    ``start`` equal steps and the ``breaks`` (points where f has a kink or a branch point,
    such as a critical angle: a midpoint check could miss a feature narrower than the
    steps); each round evaluates f at the midpoints of all intervals (each midpoint once)
    and halves every interval where the interpolant misses f there by more than ``tol`` (in
    any component), or which is more than twice as wide as a neighbour (a graded mesh: no
    stencil spans steps of very different widths), until none is left or the interval
    reaches ``min_width`` (a branch point is approached to that width).

    Interpolation: on the interval [x_i, x_i+1], the cubic through the four nodes
    x_i-1 .. x_i+2 (the first and last interval take the four nodes at their end), stored as
    power-series coefficients in t = x - x_i: continuous, and exact for cubics. Its error
    is the midpoint check's (a cubic stencil's error peaks near the middle of its interval);
    the measured figures over whole families of functions are where the tables are used
    (``ThinFilm``, ``lobes.reflection.ReferencedReflection``).

    Where refining would pass ``max_nodes``, it stops: ``converged`` is then False, and the
    caller keeps its direct evaluation.

    Parameters
    ----------
    f : callable ``(n,) -> (n, m)``
    tol : float
        The largest |interpolated - f| accepted at a midpoint.
    breaks : sequence of float
        Points of (0, 1) that start as nodes.
    start : int
        The number of equal intervals to start from.
    min_width : float
        The narrowest interval.
    max_nodes : int
    """

    def __init__(self, f, tol: float, breaks=(), start: int = 32,
                 min_width: float = 2.0**-40, max_nodes: int = 1 << 15):
        x = np.unique(np.concatenate([np.linspace(0.0, 1.0, start + 1),
                                      np.asarray(breaks, dtype=np.float64).ravel()]))
        x = x[(x >= 0.0) & (x <= 1.0)]
        y = np.asarray(f(x), dtype=np.float64)
        known = {}  # f at midpoints already evaluated
        self.converged = True
        while True:
            coefficients = _cubic_coefficients(x, y)
            mid = 0.5 * (x[1:] + x[:-1])
            new = np.array([m for m in mid.tolist() if m not in known])
            if new.size:
                known.update(zip(new.tolist(), np.asarray(f(new), dtype=np.float64), strict=True))
            truth = np.array([known[m] for m in mid.tolist()])
            error = np.abs(_horner(coefficients, np.arange(mid.size), 0.5 * np.diff(x))
                           - truth).max(axis=-1)
            width = np.diff(x)
            narrowest = np.minimum(np.concatenate([width[1:], [np.inf]]),
                                   np.concatenate([[np.inf], width[:-1]]))
            split = ((error > tol) | (width > 2.0 * narrowest)) & (width > min_width)
            if not np.any(split):
                break
            if x.size + np.count_nonzero(split) > max_nodes:
                self.converged = False
                break
            order = np.argsort(np.concatenate([x, mid[split]]), kind="stable")
            x = np.concatenate([x, mid[split]])[order]
            y = np.concatenate([y, truth[split]])[order]
        self.nodes, self.values = x, y
        #: the largest midpoint miss of the final nodes (at most ``tol`` where converged)
        self.midpoint_error = float(np.max(error))
        self._coefficients = coefficients
        # a lookup of the interval by a uniform grid of 2^b bins: the interval at each bin's
        # start, and whether a node lies inside the bin (then the nodes are searched)
        bins = 1 << int(np.clip(np.ceil(np.log2(x.size)) + 3, 6, 16))
        edges = np.arange(bins + 1) / bins
        last = x.size - 2
        first = np.clip(np.searchsorted(x, edges[:-1], side="right") - 1, 0, last)
        final = np.clip(np.searchsorted(x, edges[1:], side="left") - 1, 0, last)
        self._bins, self._first, self._crowded = bins, first, final != first

    def __len__(self) -> int:
        return self.nodes.size

    def __call__(self, x) -> np.ndarray:
        """The interpolant ``x.shape + (m,)`` at ``x`` (clamped to [0, 1])."""
        x = np.clip(np.asarray(x, dtype=np.float64), 0.0, 1.0)
        flat = x.ravel()
        b = np.minimum((flat * self._bins).astype(np.intp), self._bins - 1)
        i = np.take(self._first, b)
        crowded = np.flatnonzero(np.take(self._crowded, b))
        if crowded.size:
            i[crowded] = np.clip(np.searchsorted(self.nodes, flat[crowded], side="right") - 1,
                                 0, self.nodes.size - 2)
        out = _horner(self._coefficients, i, flat - np.take(self.nodes, i))
        return out.reshape(x.shape + out.shape[-1:])


def _cubic_coefficients(x, y):
    """``[c0, c1, c2, c3]``, each ``(n - 1, m)``: the cubic of ``AdaptiveCubic`` on each
    interval, sum_k c_k t^k with t = x - x_i. Solved in s = t / h_i (h_i the interval's
    width; the graded mesh keeps the nodes at s in [-2, 7]), then scaled by h_i^-k."""
    n = x.size
    i = np.arange(n - 1)
    stencil = np.clip(i - 1, 0, n - 4)[:, None] + np.arange(4)
    h = (x[1:] - x[:-1])[:, None]
    s = (x[stencil] - x[i, None]) / h
    vandermonde = s[..., None] ** np.arange(4)
    c = np.linalg.solve(vandermonde, y[stencil])  # (n - 1, 4, m)
    return [np.ascontiguousarray(c[:, k] / h ** k) for k in range(4)]


def _horner(coefficients, i, t):
    """sum_k c_k[i] t^k ``(len(i), m)``, every operation on contiguous arrays."""
    c0, c1, c2, c3 = coefficients
    T = np.repeat(t, c0.shape[-1]).reshape(-1, c0.shape[-1])
    out = np.take(c3, i, axis=0)
    for c in (c2, c1, c0):
        out *= T
        out += np.take(c, i, axis=0)
    return out


# --- the film as a Fresnel model (RGB) ---------------------------------------------------
@functools.lru_cache(maxsize=16)
def _rgb_weights(wavelengths: tuple, illuminant: str) -> np.ndarray:
    """``(L, 3)`` weights W with RGB = R(wavelengths) @ W: the RGB of each hat function of
    the grid, i.e. ``spectral.reflectance_to_rgb`` of the spectrum interpolated linearly
    between the samples (the same colour conversion, as one matrix)."""
    lam = np.array(wavelengths)
    W = spectral.reflectance_to_rgb(lam, np.eye(lam.size), illuminant)
    W.setflags(write=False)
    return W


def _wavelengths(wavelengths_nm) -> tuple:
    """A validated wavelength grid as a tuple (increasing, covering ``spectral.RANGE_NM``;
    ``reflectance_to_rgb`` checks the cover)."""
    if wavelengths_nm is None:
        return tuple(WAVELENGTHS_NM.tolist())
    lam = _params.real("wavelengths_nm", wavelengths_nm, 0.0, np.inf, lo_open=True)
    if lam.ndim != 1 or lam.size < 2 or np.any(np.diff(lam) <= 0.0):
        raise ValueError(f"wavelengths_nm has shape {lam.shape}: allowed an increasing "
                         "sequence of at least 2 wavelengths")
    return tuple(lam.tolist())


def _channel_wavelengths(channel_wavelengths_nm) -> np.ndarray:
    """Validated wavelengths ``(3,)`` of the three-wavelength model: three numbers in
    (0, inf)."""
    lam = _params.real("channel_wavelengths_nm", channel_wavelengths_nm, 0.0, np.inf,
                       lo_open=True, hi_open=True)
    if lam.shape != (3,):
        raise ValueError(f"channel_wavelengths_nm = {_params._show(channel_wavelengths_nm)} "
                         f"has shape {lam.shape}: allowed three wavelengths in (0, inf) nm, "
                         "one per channel (R, G, B)")
    lam = lam.copy()
    lam.setflags(write=False)
    return lam


def _model(model, channel_wavelengths_nm) -> tuple:
    """Validated ``(model, channel wavelengths)`` of ``ThinFilm``."""
    return (_params.choice("model", model, MODELS),
            _channel_wavelengths(channel_wavelengths_nm))


class ThinFilm(Fresnel):
    """A thin non-absorbing film on a dielectric or conducting base, as a Fresnel model.

    ``ThinFilm(...)(cos_theta)`` and ``from_cos2(c2)`` return linear Rec. 709 RGB
    ``(..., 3)``: for each channel the spectral reflectance of the stack
    (``airy_reflectance``) with that channel's substrate index, turned into colour, the
    channel kept. A spectrally flat reflectance keeps its value, so ``thickness_nm = 0``
    gives the film-free Fresnel of each channel (``fresnel.dielectric``,
    ``fresnel.conductor``) to rounding. The film is seen from the outside medium (only
    c^2 enters, as for the other two-sided Fresnel models).

    A film of scalar parameters (one material) is looked up in a table in cos theta, built
    on first use; ``spectral_rgb`` is the direct spectral evaluation, the reference. A
    texture of films (array parameters) is evaluated directly (Notes, the table).

    ``model="three_wavelengths"`` reproduces RGB renderers that evaluate the film at one
    wavelength per channel: channel c is ``airy_reflectance`` at ``channel_wavelengths_nm[c]``
    with that channel's substrate index, with no colour integral (each value is a
    reflectance in [0, 1]; the grid and the illuminant do not apply). It is not the colour
    of the spectral reference, but what such a renderer computes.

    Parameters
    ----------
    thickness_nm : array_like (...), in [0, inf)
        Film thickness d in nm (OpenPBR's ``thin_film_thickness`` is in um: times 1000).
    film_ior : array_like (...), in (0, inf)
        Film index n2.
    substrate : colour, or a pair ``(eta, k)`` of colours
        The base: a real index (a dielectric; a scalar or ``(..., 3)`` for one index per
        channel) or, as a tuple of two, the complex index eta + i k of a conductor (each a
        scalar or ``(..., 3)``; eta in (0, inf), k in [0, inf)).
    outside_ior : array_like (...), in (0, inf)
        Index n1 of the medium above the film (1: air; the coat's index under a coat).
    wavelengths_nm : sequence of float, optional
        The spectral samples, increasing and covering 380-780 nm; default
        ``WAVELENGTHS_NM``, 380-780 nm in 2 nm steps (201 samples).
    illuminant : str
        A colour-science illuminant for the white balance (default "D65").
    clip : bool
        Clip the colour to [0, 1] (default). Linear Rec. 709 cannot hold the saturated
        colours of some fringes: their RGB leaves [0, 1] by up to about 0.2 (e.g. a free
        film of n2 = 1.2 in air), and a Fresnel factor outside [0, 1] would make a lobe
        negative or gain energy. ``clip=False`` returns the conversion as it is.
    tabulated : bool
        Look a film of scalar parameters up in its table in cos theta (default); False
        evaluates the spectral sum on every call (``spectral_rgb``).
    model : {"spectral", "three_wavelengths"}
        The colour of the film: the spectral sum in linear Rec. 709 (default, the
        reference), or the reflectance at one wavelength per channel (``MODELS``).
    channel_wavelengths_nm : three floats in (0, inf)
        The wavelengths (nm) of the red, green and blue channels of the
        ``"three_wavelengths"`` model (default ``CHANNEL_WAVELENGTHS_NM``, 620, 540 and
        450 nm).

    Notes
    -----
    Every parameter broadcasts (a texture of thicknesses evaluates in one call);
    ``param_shape`` is their batch shape. Indices are absolute (or all relative to the
    same medium).

    Colour (``spectral.reflectance_to_rgb``): the samples are interpolated linearly onto a
    1 nm grid and integrated against the CIE 1931 2-degree colour matching functions
    (colour-science) times the illuminant, then converted to linear Rec. 709 by the BT.709
    matrix and divided by the RGB of the perfect reflector (a white spectrum is (1, 1, 1)).
    The linear map is one ``(L, 3)`` matrix per grid and illuminant.

    Default grid: the fringes of R(lambda) have the period lambda^2 / (2 n2 d cos theta2)
    (48 nm at 380 nm for n2 = 1.5, d = 1000 nm; 24 nm for n2 = 3). Against the 1 nm grid
    (the colour integral's own grid, the reference), the 2 nm default differs by at most
    2.1e-4 in any RGB channel for films up to d = 1000 nm with n2 <= 2, at any angle,
    over dielectric bases of index 1, 1.5 and 2.5 and gold, and by 5.8e-3 for n2 = 3 (the
    top of OpenPBR's soft range); a 5 nm grid (81 samples, 2.5 times faster) gives
    1.5e-3 for n2 <= 1.5, 7.9e-3 for n2 <= 2 and 3.6e-2 for n2 = 3. Pass
    ``wavelengths_nm=numpy.arange(380, 781)`` for the reference itself.

    The table (scalar parameters, ``tabulated``): the film's colour minus the film-free
    Fresnel of each channel, F(c) - F_bare(c) (c = cos theta; F_bare the exact
    ``fresnel.conductor`` of the substrate's index relative to the outside, 1 for a perfect
    reflector), as an ``AdaptiveCubic`` in c of ``TABLE_TOL`` = 1e-6 at its midpoints,
    built on the first call from the spectral sum (unclipped); a call then adds F_bare and
    clips. The difference vanishes with the film (thickness 0, an index-matched film), and
    with it the table's error, so a vanishing film tends to the film-free Fresnel exactly;
    F_bare's own kinks (the substrate's critical angle) are exact. The cubic is in c, not
    c^2 (R - 1 is linear in c at grazing incidence). The branch points of the difference
    (``critical_cosines``: the film's and the substrate's critical angles) are nodes, and
    the nodes crowd towards them down to steps of 2^-40.

    Measured against ``spectral_rgb`` at 8001 held-out cosines (a 4001-point even grid and
    4000 random ones), max |RGB error| (RMS): 210 dielectric films (thickness 0, 1, 50, 200,
    500, 1000, 2000 nm x film index 0.7, 1, 1.05, 1.33, 2, 3 x base index 1/3, 0.9, 1, 1.5,
    3) 2.2e-6 (1.3e-7); 60 F82-tint metals of random f0 and tint (thickness 0-2000 nm, film
    index 1-3, outside index 1-2) 1.1e-6 (1.9e-7); 150 random films with nearly matched
    indices, under coats and on per-channel bases, plus points 1e-2..1e-12 either side of
    each critical angle, 1.9e-6 (1.0e-7). A table holds 110-180 nodes on average (at most
    745), built in 20-55 ms on average (at most 0.2 s) on one core; a call costs about 40 ns
    per element (the spectral sum: 22-32 us). Thicker films need more nodes (5 um: 301,
    100 um: 8755, built in 0.6 s); where the refinement would need more than 2^15 the film
    is evaluated directly.

    The ``"three_wavelengths"`` model uses the same table of its three reflectances (F_bare
    is the same): measured as above on the 210 dielectric films and 60 F82-tint metals,
    2.1e-6 (2.7e-7), 190 nodes on average (at most 1270), built in 15 ms on average (at
    most 0.09 s); the direct evaluation costs about 1.4 us per element.

    Cost and memory of the spectral sum: the spectral axis multiplies the batch.
    ``spectral_rgb`` (and ``from_cos2`` of a texture) evaluates the batch in chunks of
    ``config`` ``chunk_size`` / L elements (L = number of samples), so its temporaries
    stay bounded for any batch, one channel at a time (one spectrum for all three where the
    substrate is grey). Measured on one core: about 22 us per element for a dielectric
    base and 32 us for a coloured metal on the default grid (twice that on the 1 nm grid).

    References
    ----------
    [Belcour2017, §Thin-film interference] (the Airy reflectance of the film in place of
    the Fresnel factor); [OpenPBR2026, §Thin-film iridescence]; [BornWolf1980, §1.6.4].
    """

    def __init__(self, thickness_nm, film_ior, substrate, outside_ior=1.0,
                 wavelengths_nm=None, illuminant: str = "D65", clip: bool = True,
                 tabulated: bool = True, model: str = "spectral",
                 channel_wavelengths_nm=CHANNEL_WAVELENGTHS_NM):
        d, n2, n1 = _film_params(thickness_nm, film_ior, outside_ior)
        if isinstance(substrate, tuple) and len(substrate) == 2:
            eta = _params.color("substrate eta", substrate[0], 0.0, np.inf)
            k = _params.color("substrate k", substrate[1], 0.0, np.inf)
        else:
            eta = _params.color("substrate", substrate, 0.0, np.inf)
            k = np.zeros(3)
        if np.any(eta <= 0.0):
            raise ValueError(f"substrate eta = {eta[eta <= 0.0].flat[0]!r} is outside the "
                             "allowed range (0, inf)")
        self._init(d, n2, n1, eta, k, np.zeros(3, dtype=bool), _wavelengths(wavelengths_nm),
                   illuminant, _params.flag("clip", clip), _params.flag("tabulated", tabulated),
                   *_model(model, channel_wavelengths_nm))

    @classmethod
    def over_f82_tint(cls, thickness_nm, film_ior, f0, tint, outside_ior=1.0,
                      wavelengths_nm=None, illuminant: str = "D65", clip: bool = True,
                      tabulated: bool = True, model: str = "spectral",
                      channel_wavelengths_nm=CHANNEL_WAVELENGTHS_NM) -> ThinFilm:
        """The film on an F82-tint metal [Kutz2021, eqs. 6-8] of colours ``f0`` in [0, 1]
        and ``tint`` in [0, inf) (``(..., 3)`` or scalars).

        OpenPBR maps the metal's F82-tint colours to an effective complex index for the
        film ([OpenPBR2026, §Thin-film iridescence], "e.g. with Gulbrandsen 2014"): per
        channel, ``spectral.conductor_from_f82_tint`` finds on Gulbrandsen's curve of
        reflectivity ``f0`` [Gulbrandsen2014] the conductor whose exact Fresnel passes
        through F82-tint's values at cos theta = 1 and 1/7, nearest where the tint lies
        outside the curve's range. That index is relative to the outside medium (the
        colours are what is seen from it): the substrate is outside_ior (eta + i k), so
        thickness 0 gives f0 at normal incidence whatever the outside index. A channel
        with f0 = 1 is a perfect reflector (infinite index): 1 at every angle, film or
        not. The other arguments are ``ThinFilm``'s (with ``model="three_wavelengths"``,
        channel c sees the channel's effective index at ``channel_wavelengths_nm[c]``).
        """
        d, n2, n1 = _film_params(thickness_nm, film_ior, outside_ior)
        model, channel_wavelengths = _model(model, channel_wavelengths_nm)
        eta, k, _ = spectral.conductor_from_f82_tint(f0, tint)
        mirror = np.isinf(eta)
        eta = np.where(mirror, 1.0, eta) * n1[..., None]
        k = np.where(mirror, 0.0, k) * n1[..., None]
        return cls._new(d, n2, n1, eta, k, mirror, _wavelengths(wavelengths_nm), illuminant,
                        _params.flag("clip", clip), _params.flag("tabulated", tabulated),
                        model, channel_wavelengths)

    def _init(self, d, n2, n1, eta, k, mirror, wavelengths: tuple, illuminant: str,
              clip: bool, tabulated: bool = True, model: str = "spectral",
              channel_wavelengths=None):
        self.thickness_nm, self.film_ior, self.outside_ior = d, n2, n1
        self.clip = clip
        self.model = model
        self.channel_wavelengths_nm = (np.array(CHANNEL_WAVELENGTHS_NM)
                                       if channel_wavelengths is None else channel_wavelengths)
        self.eta, self.k = eta, k
        self.mirror = mirror
        self.wavelengths_nm = np.array(wavelengths)
        self.illuminant = illuminant
        self._weights = _rgb_weights(wavelengths, illuminant)
        #: batch shape of the parameters (beyond the colour axis)
        self.param_shape = np.broadcast_shapes(d.shape, n2.shape, n1.shape, eta.shape[:-1],
                                               k.shape[:-1], mirror.shape[:-1])
        #: one spectrum serves the three channels (a grey substrate)
        self._grey = bool(np.all(eta == eta[..., :1]) and np.all(k == k[..., :1])
                          and np.all(mirror == mirror[..., :1]))
        #: whether calls look the film up in its table (scalar parameters only)
        self.tabulated = tabulated and self.param_shape == ()
        self._table = None  # built on first use (``table``)

    def __repr__(self) -> str:
        three = (f", model='three_wavelengths', channel_wavelengths_nm="
                 f"{tuple(self.channel_wavelengths_nm.tolist())}"
                 if self.model == "three_wavelengths" else "")
        return (f"ThinFilm(thickness_nm={self.thickness_nm}, film_ior={self.film_ior}, "
                f"substrate=({self.eta}, {self.k}), outside_ior={self.outside_ior}{three})")

    def from_cos2(self, c2) -> np.ndarray:
        c2 = np.asarray(c2, dtype=np.float64)
        table = self.table()
        if table is None:
            return self._direct(c2)
        c = np.sqrt(c2)
        out = table(c)
        out += self._bare(c2, c)
        return np.clip(out, 0.0, 1.0, out=out) if self.clip else out

    def spectral_rgb(self, cos_theta) -> np.ndarray:
        """The colour ``(..., 3)`` by the spectral sum at every cosine (the reference the
        table is measured against; ``from_cos2`` of ``tabulated=False``); of the
        ``"three_wavelengths"`` model, its three reflectances evaluated directly."""
        c = fresnel._cos("cos_theta", cos_theta)
        return self._direct(c * c)

    def table(self) -> AdaptiveCubic | None:
        """The table of F - F_bare in cos theta (Notes) that calls use, built on the first
        call; None for a texture of films, without ``tabulated`` and where the refinement did
        not converge."""
        if not self.tabulated:
            return None
        return built_once(self, self._make_table)

    def _make_table(self) -> AdaptiveCubic:
        """``table``'s construction."""
        def difference(c):
            c2 = c * c
            return self._spectral(c2, clip=False) - self._bare(c2)
        return AdaptiveCubic(difference, TABLE_TOL, self.critical_cosines())

    def critical_cosines(self) -> np.ndarray:
        """The cosines of the critical angles ``(K,)`` (scalar parameters), where the
        reflectance has a branch point: of the film (n2 < n1) and of a non-absorbing
        substrate (eta < n1)."""
        n1 = self.outside_ior
        indices = np.concatenate([np.ravel(self.film_ior),
                                  self.eta[(self.k == 0.0) & ~self.mirror]])
        ratio = indices[indices < n1] / n1
        return np.sqrt((1.0 - ratio) * (1.0 + ratio))

    def _bare(self, c2, c=None) -> np.ndarray:
        """The film-free Fresnel of each channel, ``(..., 3)`` (``(..., 1)`` for a grey real
        substrate): the exact conductor of the substrate's index relative to the outside
        (``fresnel.dielectric`` where it is real and grey), 1 for a perfect reflector; ``c``
        is sqrt(c2) where the caller has it."""
        if self._grey and np.all(self.k == 0.0):
            c = np.sqrt(c2) if c is None else c
            out = fresnel._dielectric(c, self.eta[..., 0], self.outside_ior)[..., None]
        else:
            n1 = self.outside_ior[..., None]
            eta, k = self.eta / n1, self.k / n1
            out = fresnel._conductor_cos2(c2, eta * eta - k * k, 4.0 * eta * eta * k * k,
                                          (eta == 1.0) & (k == 0.0))
        return np.where(self.mirror, 1.0, out) if np.any(self.mirror) else out

    def _direct(self, c2) -> np.ndarray:
        """``from_cos2`` by the spectral sum, each distinct angle once for scalar
        parameters (a Monte-Carlo batch repeats its wo)."""
        if self.param_shape == () and c2.size > 1:
            distinct, inverse = np.unique(c2.ravel(), return_inverse=True)
            if distinct.size < c2.size:
                return self._spectral(distinct)[inverse.ravel()].reshape(c2.shape + (3,))
        return self._spectral(c2)

    def _spectral(self, c2, clip: bool | None = None) -> np.ndarray:
        """The spectral sum at every element (clipped as ``clip``, default the film's), or
        the three channels' reflectances (``model``)."""
        batch = np.broadcast_shapes(c2.shape, self.param_shape)
        n = int(np.prod(batch))

        def flat(x, colour=False):
            shape = batch + (3,) if colour else batch
            return np.broadcast_to(x, shape).reshape((n, 3) if colour else (n,))

        c = flat(np.sqrt(c2))
        d, n2, n1 = flat(self.thickness_nm), flat(self.film_ior), flat(self.outside_ior)
        eta, k = flat(self.eta, True), flat(self.k, True)
        three = self.model == "three_wavelengths"
        lam, W = (self.channel_wavelengths_nm, None) if three else (self.wavelengths_nm,
                                                                     self._weights)
        out = np.empty((n, 3))
        step = max(1, config.get_options().chunk_size // lam.size)
        for start in range(0, n, step):
            s = slice(start, min(start + step, n))
            args = (lam, c[s, None], d[s, None], n1[s, None], n2[s, None])
            if three:  # channel c at its wavelength, with its index: a reflectance
                out[s] = _airy(*args, eta[s], k[s], False)[0]
            elif self._grey:
                out[s] = _airy(*args, eta[s, :1], k[s, :1], False)[0] @ W
            else:
                for ch in range(3):
                    R = _airy(*args, eta[s, ch, None], k[s, ch, None], False)[0]
                    out[s, ch] = R @ W[:, ch]
        out = out.reshape(batch + (3,))
        if np.any(self.mirror):
            out = np.where(self.mirror, 1.0, out)
        return np.clip(out, 0.0, 1.0) if (self.clip if clip is None else clip) else out


def _film_params(thickness_nm, film_ior, outside_ior):
    """Validated (d, n2, n1) of ``ThinFilm``."""
    return (_params.real("thickness_nm", thickness_nm, 0.0, np.inf),
            _params.real("film_ior", film_ior, 0.0, np.inf, lo_open=True),
            _params.real("outside_ior", outside_ior, 0.0, np.inf, lo_open=True))
