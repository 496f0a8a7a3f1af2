"""Fresnel reflectance models, vectorised, with colour broadcasting.

Public API
----------
``dielectric(cos_theta_i, eta)``                       exact unpolarised, both sides, TIR
``conductor(cos_theta_i, eta, k)``                     exact unpolarised, complex IOR eta + i k
``schlick(cos_theta, f0, f90=1, exponent=5)``          [Schlick1994], generalized
                                                       [Hoffman2023, eq. 4]
``f82(cos_theta, f0, f82)``                            Hoffman's original F82 [Kutz2021, eqs. 2-5]
``f82_tint(cos_theta, f0, tint, f90=1, exponent=5)``   ASM F82-tint [Kutz2021, eqs. 2-8],
                                                       generalized [Hoffman2023, eqs. 5-6]
``gulbrandsen_to_ior(r, g)``, ``ior_to_gulbrandsen(eta, k)``
                                                       Gulbrandsen's artist-friendly conductor
                                                       parameters (reflectivity, edge tint) and
                                                       back
``Fresnel``                                            the protocol of a model with fixed
                                                       parameters, as lobes use it
``ExactConductor(eta, k)``, ``ExactDielectric(eta)``, ``F82Tint(f0, tint, f90, exponent)``
                                                       the models above as ``Fresnel`` objects
``FresnelFunction(function)``                          any callable cos theta -> reflectance
                                                       as a ``Fresnel``
``Weighted(fresnel, weight)``                          clamp(weight F, 0, 1) of a model

Shapes: ``cos_theta`` is ``(...)``; the colour models return ``(..., 3)`` with colour
parameters given as scalars or ``(..., 3)`` arrays. ``dielectric`` returns ``(...)`` for a
scalar/``(...)`` ``eta``.

References
----------
[Kutz2021, §2] F82 and F82-tint. [Hoffman2023] the generalized F82-tint (r90, exponent).
[BornWolf1980, §1.5, §13.2] Fresnel equations, absorbing media.
[Gulbrandsen2014] artist-friendly metallic Fresnel; used for coloured conductors by
[Barla2018, §4].
"""

from __future__ import annotations

import functools

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf._channels import pick, shifted, tinted, weighted

__all__ = ["dielectric", "conductor", "schlick", "f82", "f82_tint", "COS_THETA_MAX",
           "gulbrandsen_to_ior", "ior_to_gulbrandsen",
           "ExactConductor", "ExactDielectric", "F82Tint", "Weighted"]

#: cos of the angle of the Lazányi dip extremum with beta = 6: 1/(beta + 1) [Kutz2021, eq. 2]
COS_THETA_MAX = 1.0 / 7.0

#: rounding slack accepted on |cos theta| <= 1 before it is rejected
_COS_SLACK = 1e-9


def _cos(name: str, value) -> np.ndarray:
    c = _params.real(name, value, -1.0 - _COS_SLACK, 1.0 + _COS_SLACK)
    return np.clip(c, -1.0, 1.0)  # removes rounding only (|excess| <= 1e-9)


# --- dielectric --------------------------------------------------------------------------
def dielectric(cos_theta_i, eta) -> np.ndarray:
    """Exact unpolarised Fresnel reflectance of a dielectric interface.

    Parameters
    ----------
    cos_theta_i : array_like (...)
        Cosine between the incident direction and the interface normal, in [-1, 1]. A
        negative value means the incident direction lies on the transmitted side; the
        interface is then seen with relative index ``1 / eta``.
    eta : array_like (...)
        Relative index n_t / n_i for ``cos_theta_i > 0``, in (0, inf).

    Returns
    -------
    ndarray (...): reflectance in [0, 1]; 1 under total internal reflection; 0 for eta = 1.

    Notes
    -----
    R = (r_s^2 + r_p^2) / 2 with r_s = (c_i - eta c_t) / (c_i + eta c_t),
    r_p = (eta c_i - c_t) / (eta c_i + c_t) [BornWolf1980, §1.5.2], evaluated in a form free of
    cancellation so that the relative accuracy holds as eta -> 1.
    """
    return _dielectric(_cos("cos_theta_i", cos_theta_i),
                       _params.real("eta", eta, 0.0, np.inf, lo_open=True))


def _dielectric(cos_i: np.ndarray, eta_t, eta_i=1.0) -> np.ndarray:
    """Fresnel reflectance for relative index eta_t / eta_i; the two indices are taken
    apart so that k = eta^2 - 1 is formed without the rounding of the ratio (which, near
    eta = 1, would dominate the result)."""
    flip = cos_i < 0.0
    if np.any(flip):  # (else the indices stay as given: scalars keep the scalar path)
        eta_t, eta_i = pick(flip, eta_i, eta_t), pick(flip, eta_t, eta_i)
    eta = eta_t / eta_i
    return _dielectric_k(np.abs(cos_i), _k_of_indices(eta_t, eta_i), eta * eta)


def _k_of_indices(eta_t, eta_i=1.0):
    """k = (eta_t / eta_i)^2 - 1 formed as (eta_t - eta_i)(eta_t + eta_i) / eta_i^2."""
    return (eta_t - eta_i) * (eta_t + eta_i) / (eta_i * eta_i)


def _dielectric_k(c, k, eta2) -> np.ndarray:
    """Dielectric reflectance from c = |cos theta_i|, k = eta^2 - 1 and eta^2.

    eta c_t = sqrt(k + c^2) (total internal reflection where k + c^2 <= 0, which includes
    the grazing limit c = 0 for eta <= 1). The amplitudes are the textbook
    r_s = (c - eta c_t)/(c + eta c_t) and r_p = (eta c - c_t)/(eta c + c_t) with their
    numerators rewritten free of cancellation, r_s = -k / (c + eta c_t)^2 and
    r_p = k (c^2 (eta^2 + 1) - 1) / (eta^2 (eta c + c_t)^2), accurate as eta -> 1.
    """
    scalar = np.ndim(k) == 0
    if scalar and k == 0.0:  # index-matched: no interface
        return np.zeros(np.shape(c))
    c2 = c * c
    e2 = k + c2
    if scalar and k > 0.0:  # seen from the less dense side: no total internal reflection
        tir = None
        eta_cos_t = np.sqrt(e2)
    else:
        tir = e2 <= 0.0
        eta_cos_t = np.sqrt(np.maximum(e2, 0.0))
    den_s = c + eta_cos_t
    den_s *= den_s
    den_p = eta2 * c + eta_cos_t  # eta (eta c + c_t)
    den_p *= den_p
    # masked below: under total internal reflection at a grazing c the denominators vanish
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        r_s = k / den_s
        r_p = k * (c2 * (eta2 + 1.0) - 1.0) / den_p
        R = r_s * r_s
        R += r_p * r_p
        R *= 0.5
    # |r_s|, |r_p| <= 1, so R <= 1; where c_t is rounded (grazing c, c^2 underflowing) the
    # squares can exceed 1 by an ulp, and F > 1 times a saturated D V would overflow to inf
    R = np.minimum(R, 1.0)
    if scalar:
        return R if tir is None else pick(tir, 1.0, R)
    return pick(k == 0.0, 0.0, pick(tir, 1.0, R))


# --- conductor ---------------------------------------------------------------------------
def conductor(cos_theta_i, eta, k) -> np.ndarray:
    """Exact unpolarised Fresnel reflectance of an absorbing medium with index eta + i k.

    Parameters
    ----------
    cos_theta_i : array_like (...), in [-1, 1]; the surface is two-sided (|cos| is used).
    eta : array_like, scalar or (..., 3); real part of the relative index, in (0, inf).
    k : array_like, scalar or (..., 3); extinction coefficient, in [0, inf).

    Returns
    -------
    ndarray (..., 3)

    Notes
    -----
    With n = eta + i k, s^2 = 1 - c^2 and n c_t = sqrt(n^2 - s^2) on the principal branch
    (Re, Im >= 0: the attenuating wave),
    r_s = (c - n c_t) / (c + n c_t), r_p = (n^2 c - n c_t) / (n^2 c + n c_t),
    R = (|r_s|^2 + |r_p|^2) / 2 [BornWolf1980, §13.2]. k = 0 reduces to ``dielectric``.
    """
    c = _cos("cos_theta_i", cos_theta_i)
    eta = _params.color("eta", eta, 0.0, np.inf)
    k = _params.color("k", k, 0.0, np.inf)
    if np.any(eta <= 0.0):
        raise ValueError(f"eta = {eta[eta <= 0.0].flat[0]!r} is outside the allowed range (0, inf)")
    return _conductor(c, eta, k)


def _conductor(cos_i: np.ndarray, eta: np.ndarray, k: np.ndarray) -> np.ndarray:
    c = np.abs(cos_i)
    return _conductor_cos2(c * c, eta * eta - k * k, 4.0 * eta * eta * k * k,
                           (eta == 1.0) & (k == 0.0))


def _conductor_cos2(c2, A, B, matched) -> np.ndarray:
    """Exact conductor reflectance ``(..., 3)`` from c^2 = cos^2 theta ``(...)`` in real
    arithmetic, with A = eta^2 - k^2 and B = 4 eta^2 k^2 (``(..., 3)``); see
    ``_conductor_channel``. ``matched`` (eta = 1, k = 0: no interface) gives 0.

    The result is computed channel-major (memory order (3, ...)), so that every loop runs
    over the long batch axis: NumPy would iterate a (..., 3) array with an inner loop of 3.
    """
    c2 = np.asarray(c2, dtype=np.float64)
    s2 = 1.0 - c2
    two_c2, s4 = 2.0 * c2, s2 * s2  # shared by the channels
    if np.ndim(A) == 1:  # one interface: a channel at a time with scalar constants
        if c2.ndim == 0:  # (in-place operations need arrays)
            return _conductor_cos2(c2[None], A, B, matched)[0]
        out = np.empty((3,) + c2.shape)
        for ch in range(3):
            if matched[ch]:
                out[ch] = 0.0
            else:
                _conductor_channel(c2, s2, two_c2, s4, A[ch].item(), B[ch].item(),
                                   out=out[ch, ...])
        return np.moveaxis(out, 0, -1)
    ndim = max(c2.ndim, np.ndim(A) - 1)
    A, B, matched = (_channel_major(x, ndim) for x in (A, B, matched))
    with np.errstate(divide="ignore", invalid="ignore"):
        R = _conductor_channel(c2, s2, two_c2, s4, A, B)
    return np.moveaxis(pick(matched, 0.0, R), 0, -1)


def _conductor_channel(c2, s2, two_c2, s4, A, B, out=None):
    """One channel (or channel-major channels) of the exact conductor reflectance, from
    c^2, s^2 = 1 - c^2, 2 c^2 and s^4.

    With n c_t = a + i b (a, b >= 0): t0 = A - s^2, a^2 + b^2 = t1 = sqrt(t0^2 + B),
    a^2 = (t1 + t0) / 2, and

        R_s = (t1 + c^2 - 2 a c) / (t1 + c^2 + 2 a c)
        R_p = R_s (t1 c^2 - 2 a c s^2 + s^4) / (t1 c^2 + 2 a c s^2 + s^4),

    the moduli |r_s|^2, |r_p|^2 of the complex amplitudes of ``conductor``. Then
    R = (R_s + R_p) / 2 = R_s q / (q + 2 a c s^2) with q = t1 c^2 + s^4, one division. The
    denominators vanish only for an index-matched interface at grazing incidence.
    """
    t0 = A - s2
    t1 = t0 * t0
    t1 += B
    np.sqrt(t1, out=t1)
    ac2 = t1 + t0  # 2 a^2, then 2 a c
    ac2 *= two_c2
    np.sqrt(ac2, out=ac2)
    p = t1 + c2
    num_s = p - ac2
    p += ac2  # den_s
    q = t1 * c2
    q += s4
    ac2 *= s2  # 2 a c s^2
    ac2 += q  # den_p
    ac2 *= p
    num_s *= q
    return np.divide(num_s, ac2, out=num_s if out is None else out)


# --- Gulbrandsen's artist-friendly conductor parameters ------------------------------------
def gulbrandsen_to_ior(reflectivity, edge_tint) -> tuple[np.ndarray, np.ndarray]:
    """Complex index (eta, k) of a conductor from its reflectivity r and edge tint g.

    [Gulbrandsen2014]: with s = sqrt(r), n_min = (1 - r) / (1 + r) and
    n_max = (1 + s) / (1 - s), eta = g n_min + (1 - g) n_max and k is the extinction for
    which the normal-incidence reflectance ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2) is r,
    k^2 = (r (eta + 1)^2 - (eta - 1)^2) / (1 - r). [Barla2018, §4] maps coloured hazy
    conductors through it: g = 0 gives k = 0, a dielectric of reflectance r.

    Parameters
    ----------
    reflectivity : array_like in [0, 1)
        r, the reflectance at normal incidence (r = 1 would need an infinite index).
    edge_tint : array_like in [0, 1]
        g, broadcast against ``reflectivity``; any shape (one value per colour channel).

    Returns
    -------
    (eta, k) : ndarrays of the broadcast shape.

    Notes
    -----
    k^2 is evaluated as the product of the two factors of r (eta + 1)^2 - (eta - 1)^2, each
    written as a sum of non-negative terms,
    k^2 = 4 g r / ((1 + r)(1 - s)) (g (1 - s) / (1 + r) + 2 (1 - g) / (1 - s)),
    so that it is accurate (and exactly 0 at g = 0) instead of a difference of large terms.
    """
    r = _params.real("reflectivity", reflectivity, 0.0, 1.0, hi_open=True)
    g = _params.real("edge_tint", edge_tint, 0.0, 1.0)
    r, g = np.broadcast_arrays(r, g)
    s = np.sqrt(r)
    n_min = (1.0 - r) / (1.0 + r)
    n_max = (1.0 + s) / (1.0 - s)
    eta = g * n_min + (1.0 - g) * n_max
    k2 = 4.0 * g * r / ((1.0 + r) * (1.0 - s)) * (g * (1.0 - s) / (1.0 + r)
                                                  + 2.0 * (1.0 - g) / (1.0 - s))
    return eta, np.sqrt(k2)


def ior_to_gulbrandsen(eta, k) -> tuple[np.ndarray, np.ndarray]:
    """Reflectivity r and edge tint g of a conductor with complex index eta + i k, the
    inverse of ``gulbrandsen_to_ior``.

    r = ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2) (the exact normal-incidence reflectance)
    and g = (n_max(r) - eta) / (n_max(r) - n_min(r)). A measured metal need not lie in
    Gulbrandsen's range: g is returned as computed, and is outside [0, 1] where eta is
    below n_min(r). At r = 0 (eta = 1, k = 0: no interface) g is undefined; 0 is returned.

    Parameters
    ----------
    eta : array_like in (0, inf)
    k : array_like in [0, inf), broadcast against ``eta``.

    Returns
    -------
    (r, g) : ndarrays of the broadcast shape.
    """
    eta = _params.real("eta", eta, 0.0, np.inf, lo_open=True)
    k = _params.real("k", k, 0.0, np.inf)
    eta, k = np.broadcast_arrays(eta, k)
    k2 = k * k
    r = ((eta - 1.0) ** 2 + k2) / ((eta + 1.0) ** 2 + k2)
    s = np.sqrt(r)
    n_max = (1.0 + s) / (1.0 - s)
    spread = 2.0 * s * (1.0 + s) / ((1.0 - s) * (1.0 + r))  # n_max - n_min
    with np.errstate(divide="ignore", invalid="ignore"):  # r = 0 is handled below
        g = (n_max - eta) / spread
    return r, pick(r > 0.0, g, 0.0)


def _channel_major(x, ndim: int) -> np.ndarray:
    """A colour array ``(..., 3)`` as ``(3, ...)`` broadcasting against batches of ``ndim``."""
    x = np.moveaxis(np.asarray(x), -1, 0)
    return x.reshape((3,) + (1,) * (ndim - (x.ndim - 1)) + x.shape[1:])


class Fresnel(_params.Validated):
    """A Fresnel model with fixed parameters, the protocol lobes dispatch on.

    ``model(cos_theta)`` validates the cosine and returns the reflectance, ``(..., 3)``
    (colour models) or ``(...)`` (grey); ``from_cos2(c2)`` is the same from cos^2 theta >= 0
    without checks (a lobe that knows it); ``param_shape`` is the batch shape of the
    parameters beyond the colour axis, or None where it is unknown (no chunked execution).
    """

    #: batch shape of the parameters (beyond the colour axis); None: unknown
    param_shape: tuple | None = None

    def __call__(self, cos_theta) -> np.ndarray:
        c = _cos("cos_theta", cos_theta)
        return self.from_cos2(c * c)

    def from_cos2(self, c2) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError


def _callable_repr(function) -> str:
    """A repr of a callable without memory addresses: ``module.name`` for a function,
    ``name(*args, **kwargs)`` for a ``functools.partial`` (stable across processes)."""
    if isinstance(function, functools.partial):
        args = [repr(a) for a in function.args]
        args += [f"{k}={v!r}" for k, v in function.keywords.items()]
        return f"partial({_callable_repr(function.func)}, {', '.join(args)})"
    name = getattr(function, "__qualname__", None)
    if name is None:  # a callable object: its own repr
        return repr(function)
    return f"{function.__module__}.{name}"  # lambdas and local functions included


class FresnelFunction(Fresnel):
    """A plain callable ``function(cos_theta) -> reflectance`` as a ``Fresnel`` (its
    parameters, and so their shape, are unknown)."""

    def __init__(self, function):
        if not callable(function):
            raise ValueError(f"fresnel = {function!r} is not callable (allowed: None, a "
                             "Fresnel model or a callable cos_theta -> reflectance)")
        self.function = function

    def __repr__(self) -> str:
        return _callable_repr(self.function)

    def __call__(self, cos_theta) -> np.ndarray:
        return self.function(cos_theta)

    def from_cos2(self, c2) -> np.ndarray:
        return self.function(np.sqrt(c2))


class ExactConductor(Fresnel):
    """Exact conductor Fresnel with fixed eta + i k (``conductor``), as an object for lobes.

    ``ExactConductor(eta, k)(cos_theta) -> (..., 3)``; ``from_cos2(c2)`` skips the
    validation and the square root (a lobe that knows cos^2 theta).
    """

    def __init__(self, eta, k):
        eta = _params.color("eta", eta, 0.0, np.inf)
        k = _params.color("k", k, 0.0, np.inf)
        if np.any(eta <= 0.0):
            raise ValueError(f"eta = {eta[eta <= 0.0].flat[0]!r} is outside the "
                             "allowed range (0, inf)")
        self._init(eta, k)

    def _init(self, eta, k):
        self.eta, self.k = np.broadcast_arrays(eta, k)
        self._A = self.eta * self.eta - self.k * self.k
        self._B = 4.0 * self.eta * self.eta * self.k * self.k
        self._matched = (self.eta == 1.0) & (self.k == 0.0)
        #: batch shape of the parameters (beyond the colour axis)
        self.param_shape = self.eta.shape[:-1]

    def __repr__(self) -> str:
        return f"ExactConductor(eta={self.eta}, k={self.k})"

    def from_cos2(self, c2) -> np.ndarray:
        return _conductor_cos2(c2, self._A, self._B, self._matched)


class F82Tint(Fresnel):
    """The F82-tint metal Fresnel (``f82_tint``) with fixed parameters, as an object for lobes:
    ``F82Tint(f0, tint, f90=1, exponent=5)(cos_theta) -> (..., 3)``; ``from_cos2(c2)`` for
    c = sqrt(c2) >= 0 ([Kutz2021, eqs. 6-8], [Hoffman2023, eqs. 5-6])."""

    def __init__(self, f0, tint, f90=1.0, exponent=5.0):
        self._init(_params.color("f0", f0, 0.0, 1.0), _params.color("tint", tint, 0.0, np.inf),
                   _params.color("f90", f90, 0.0, 1.0),
                   _params.real("exponent", exponent, 0.0, np.inf, lo_open=True))

    def _init(self, f0, tint, f90, exponent):
        self.f0, self.tint, self.f90, self.exponent = f0, tint, f90, exponent
        #: batch shape of the parameters (beyond the colour axis)
        self.param_shape = np.broadcast_shapes(self.f0.shape[:-1], self.tint.shape[:-1],
                                               self.f90.shape[:-1], self.exponent.shape)

    def __repr__(self) -> str:
        return (f"F82Tint(f0={self.f0}, tint={self.tint}, f90={self.f90}, "
                f"exponent={self.exponent})")

    def __call__(self, cos_theta) -> np.ndarray:
        return _f82_tint(np.abs(_cos("cos_theta", cos_theta)), self.f0, self.tint, self.f90,
                         self.exponent)

    def from_cos2(self, c2) -> np.ndarray:
        return _f82_tint(np.sqrt(c2), self.f0, self.tint, self.f90, self.exponent)


class Weighted(Fresnel):
    """``fresnel`` times a weight, clamped to [0, 1]: clamp(xi F, 0, 1) (OpenPBR dev_1.2's
    metal with specular_weight xi above 1 [OpenPBR2026dev, §Metal]); ``(..., 3)`` or grey as
    ``fresnel``, ``weight`` ``(...)`` in [0, inf)."""

    def __init__(self, fresnel: Fresnel, weight):
        if not isinstance(fresnel, Fresnel):
            raise ValueError(f"fresnel = {fresnel!r}: allowed a Fresnel model")
        self._init(fresnel, _params.real("weight", weight, 0.0, np.inf))

    def _init(self, fresnel, weight):
        self.fresnel, self.weight = fresnel, weight
        inner = fresnel.param_shape
        self.param_shape = None if inner is None else np.broadcast_shapes(inner, weight.shape)

    def __repr__(self) -> str:
        return f"Weighted({self.fresnel!r}, weight={self.weight})"

    def from_cos2(self, c2) -> np.ndarray:
        F = self.fresnel.from_cos2(c2)
        w = self.weight if F.ndim == np.ndim(c2) else self.weight[..., None]
        return np.clip(w * F, 0.0, 1.0)


class ExactDielectric(Fresnel):
    """Exact dielectric Fresnel with fixed relative index ``eta`` (``dielectric``), as an
    object for lobes; returns ``(...)`` (grey). ``from_cos2(c2)`` is for c = sqrt(c2) >= 0."""

    def __init__(self, eta):
        self._init(_params.real("eta", eta, 0.0, np.inf, lo_open=True))

    def _init(self, eta):
        self.eta = eta
        self.param_shape = eta.shape

    def __repr__(self) -> str:
        return f"ExactDielectric(eta={self.eta})"

    def __call__(self, cos_theta) -> np.ndarray:
        return _dielectric(_cos("cos_theta", cos_theta), self.eta)

    def from_cos2(self, c2) -> np.ndarray:
        return _dielectric(np.sqrt(c2), self.eta)


# --- Schlick family ----------------------------------------------------------------------
def schlick(cos_theta, f0, f90=1.0, exponent=5.0) -> np.ndarray:
    """Generalized Schlick reflectance F = f0 + (f90 - f0)(1 - |cos theta|)^exponent.

    [Hoffman2023, eq. 4] (eq. 1 for f90 = 1, exponent = 5). ``f0``, ``f90`` colours in [0, 1];
    ``exponent`` in (0, inf). Returns ``(..., 3)``.
    """
    c = _cos("cos_theta", cos_theta)
    f0 = _params.color("f0", f0, 0.0, 1.0)
    f90 = _params.color("f90", f90, 0.0, 1.0)
    exponent = _params.real("exponent", exponent, 0.0, np.inf, lo_open=True)
    return _schlick(np.abs(c), f0, f90, exponent)


def _schlick(mu, f0, f90, exponent):
    """f0 + (f90 - f0)(1 - mu)^exponent, ``(..., 3)``, by the colour helpers of ``_channels``
    (channel by channel where the colours are (3,), else NumPy's broadcast): the same
    arithmetic whatever the shapes."""
    # the power of (..., 1) arrays: NumPy's array power, which can differ in the last bit
    # from the scalar power a 0-d operand would take
    mu, exponent = np.asarray(mu)[..., None], np.asarray(exponent)[..., None]
    return shifted(tinted(((1.0 - mu) ** exponent)[..., 0], np.subtract(f90, f0)), f0)


def f82(cos_theta, f0, f82) -> np.ndarray:
    """Hoffman's original F82 model [Kutz2021, eqs. 2-5], unclamped.

    ``f82`` is the reflectance h at cos theta = 1/7 (eq. 3); a = (r + (1 - r)(1 - 1/7)^5 - h)
    / ((1/7)(1 - 1/7)^6) (eq. 4); F = r + (1 - r)(1 - mu)^5 - a mu (1 - mu)^6 (eq. 5). With a
    white ``f82`` it exceeds 1 near grazing [Kutz2021, Fig. 4]: it is returned as is so that
    the comparison can be shown.
    """
    mu = np.abs(_cos("cos_theta", cos_theta))
    r = _params.color("f0", f0, 0.0, 1.0)
    h = _params.color("f82", f82, 0.0, 1.0)
    schlick_max = _schlick(COS_THETA_MAX, r, 1.0, 5.0)
    a = (schlick_max - h) / (COS_THETA_MAX * (1.0 - COS_THETA_MAX) ** 6)
    mu = mu[..., None]
    return r + (1.0 - r) * (1.0 - mu) ** 5 - a * mu * (1.0 - mu) ** 6


def f82_tint(cos_theta, f0, tint, f90=1.0, exponent=5.0) -> np.ndarray:
    """ASM F82-tint metal reflectance [Kutz2021, §2], in the generalized form of [Hoffman2023].

    F = r0 + (r90 - r0)(1 - mu)^alpha - a mu (1 - mu)^6 [Hoffman2023, eq. 5] with
    a = (r0 + (r90 - r0)(1 - mu_max)^alpha)(1 - t) / (mu_max (1 - mu_max)^6) (eq. 6),
    mu_max = 1/7 [Kutz2021, eq. 2]. With f90 = 1 and exponent = 5 this is [Kutz2021, eqs. 6-8];
    with a white tint it is the (generalized) Schlick model.

    Parameters
    ----------
    cos_theta : array_like (...), in [-1, 1] (|cos| is used).
    f0 : colour in [0, 1]          reflectance at normal incidence r0 ("base color").
    tint : colour in [0, inf)      multiplier t of the Schlick value at mu_max
                                   ("specular edge color"; <= 1 for real metals, [Kutz2021, §2]).
    f90 : colour in [0, 1]         reflectance at grazing incidence r90.
    exponent : (...) in (0, inf)   interpolation exponent alpha.

    Returns
    -------
    ndarray (..., 3), clamped to [0, 1] as the reference listing of [Kutz2021, §2.4] does (the
    polynomial can leave [0, 1] for extreme tints, e.g. f0 = tint = 0 at mu = 1/2).
    """
    mu = np.abs(_cos("cos_theta", cos_theta))
    f0 = _params.color("f0", f0, 0.0, 1.0)
    tint = _params.color("tint", tint, 0.0, np.inf)
    f90 = _params.color("f90", f90, 0.0, 1.0)
    exponent = _params.real("exponent", exponent, 0.0, np.inf, lo_open=True)
    return _f82_tint(mu, f0, tint, f90, exponent)


def _f82_tint(mu, f0, tint, f90, exponent):
    schlick_max = _schlick(np.full(np.shape(exponent), COS_THETA_MAX), f0, f90, exponent)
    a = schlick_max * (1.0 - tint) / (COS_THETA_MAX * (1.0 - COS_THETA_MAX) ** 6)
    mu = np.asarray(mu)
    pow6 = ((1.0 - mu[..., None]) ** 6)[..., 0]  # (the power on arrays, as in _schlick)
    value = _schlick(mu, f0, f90, exponent) - weighted(tinted(mu, a), pow6)
    return np.clip(value, 0.0, 1.0, out=value)
