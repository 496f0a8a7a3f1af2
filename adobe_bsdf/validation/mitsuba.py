"""Mitsuba 3 GGX plugins seen through ``adobe_bsdf``'s conventions (for cross-checks).

Public API
----------
``mitsuba_conductor(alpha_x, alpha_y, eta, k)``
    Mitsuba's ``roughconductor`` (GGX, visible-normal sampling, complex IOR ``eta + i k``).
``mitsuba_dielectric(eta, alpha_x, alpha_y, ext_ior)``
    Mitsuba's ``roughdielectric`` (GGX, visible-normal sampling, reflection + transmission).
``MitsubaBSDF``
    The wrapper both return: ``eval(wo, wi) -> (..., 3)`` and ``pdf(wo, wi) -> (...)``.
``float32_directions(w)``
    Unit vectors rounded to float32, so both libraries can be fed identical directions.
``crosscheck_pairs(n, alpha_x, alpha_y, eta, rng)``
    Random direction pairs on which a float32 renderer is well conditioned.

Mitsuba is imported lazily (this module imports without it) and the ``scalar_rgb`` variant is
selected on first use; pairs are evaluated one by one in a Python loop (about 1 µs per call).

Naming
------
Mitsuba calls the direction towards the viewer ``si.wi`` and the argument of ``eval``/``pdf``
(towards the light) ``wo``. Here, as everywhere in ``adobe_bsdf``, ``wo`` is the viewer and ``wi``
the light, so ``MitsubaBSDF.eval(wo, wi)`` sets ``si.wi = wo`` and passes ``wi`` as Mitsuba's
``wo``. Both libraries use the local frame with normal ``+z``; Mitsuba's ``alpha_u`` is the
roughness along the tangent ``+x`` (its GGX density is
``1 / (pi a_u a_v ((m_x/a_u)^2 + (m_y/a_v)^2 + m_z^2)^2)``), i.e. our ``alpha_x``, and
``alpha_v`` is our ``alpha_y``. Mitsuba's ``int_ior`` is the index below the surface
(``z < 0``, the side the normal points away from) and ``ext_ior`` the one above, so our
``eta = n_below / n_above`` is ``int_ior / ext_ior``.

Conversion of the values
------------------------
Mitsuba's ``eval`` returns ``f |cos theta|`` with the cosine of *its* ``wo``, our ``wi``; the
wrapper divides by ``|wi_z|`` (in float64) and returns 0 where ``wi_z = 0``. No other factor is
needed, in reflection or in transmission:

Mitsuba's ``roughdielectric`` evaluates transmission (``TransportMode.Radiance``, its default
and the only mode used here) as ::

    scale (1 - F) D G eta^2 |(wo.m)(wi.m)| / (|wo_z| (wo.m + eta wi.m)^2),   scale = 1 / eta^2

where ``eta = eta_i / eta_o`` is the index on the light's side over the index on the viewer's
side (its ``m_eta`` or ``m_inv_eta`` depending on the sign of ``wo_z``), ``m`` is the
generalized half vector ``normalize(wo + eta wi)`` turned to ``m_z > 0``, ``F`` the dielectric
Fresnel reflectance at ``wo.m``, ``D`` GGX and ``G = G1(wo, m) G1(wi, m)``. The radiance scale
cancels the ``eta^2`` of Walter et al. (2007), so after dividing by ``|wi_z|``::

    f(wo, wi) = eta_o^2 (1 - F) D G |(wo.m)(wi.m)| / (|wo_z| |wi_z| (eta_o wo.m + eta_i wi.m)^2)

which is pbrt-v4's radiance-mode BTDF and ``adobe_bsdf``'s convention: ``f(wo, wi) / eta_o^2``
is symmetric in ``wo`` and ``wi`` (the Fresnel transmittance of the refraction pair is the same
from both sides), i.e. ``f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2``. ``tests/
test_mitsuba_crosscheck.py`` confirms this numerically: the converted values satisfy that
generalized reciprocity, agree with a float64 transcription of the formula above, and the
energy ``integral of f (eta_i / eta_o)^2 |cos theta_i|`` over both hemispheres is ``<= 1``
and close to 1 at low roughness (an ``eta^2`` factor left in or out would be off by 2.25).
Reflection is ``F D G / (4 |wo_z| |wi_z|)`` in both libraries.

``pdf`` is Mitsuba's solid-angle density unchanged: for the conductor the visible-normal
density ``G1(wo, m) D(m) / (4 |wo_z|)``; for the dielectric the visible-normal density of ``m``
times the Jacobian of the (generalized) half-vector map, times ``F(wo.m)`` for reflection or
``1 - F(wo.m)`` for transmission.

Float32
-------
Mitsuba's ``scalar_rgb`` variant computes in float32. Directions are rounded to the nearest
float32 (without renormalising: a unit vector rounded componentwise stays unit within
``1e-7``); pass directions that are already float32 numbers (``float32_directions``) to give
both libraries the same input. The result is then exact up to Mitsuba's float32 arithmetic,
which is accurate to a few ``1e-7`` relative except where the model is ill conditioned:
near the critical angle of total internal reflection (``F`` depends on ``sqrt(cos^2 theta_t)``,
whose float32 rounding error grows like ``1e-7 / cos^2 theta_t``), for microfacet normals or
directions close to a horizon (the masking and side tests flip sign), and for reflection pairs
with ``wo`` almost opposite ``wi`` (the half vector is lost to cancellation).
``crosscheck_pairs`` rejects such pairs; its docstring gives the thresholds and the test
module the errors measured with them.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "MIN_COS",
    "MIN_COS2_T",
    "MIN_COS_M",
    "MitsubaBSDF",
    "crosscheck_pairs",
    "float32_directions",
    "mitsuba_conductor",
    "mitsuba_dielectric",
    "well_conditioned",
]

#: smallest ``|cos|`` of ``wo``, ``wi`` and the microfacet normal with the normal, in
#: ``well_conditioned``
MIN_COS = 1e-3
#: smallest ``|cos|`` between ``wo`` or ``wi`` and the microfacet normal, in ``well_conditioned``
MIN_COS_M = 5e-2
#: smallest ``|cos^2 theta_t|`` of the refraction of ``wo`` at the microfacet (the distance from
#: the critical angle of total internal reflection, on either side), in ``well_conditioned``
MIN_COS2_T = 1e-1


def _mitsuba():
    """Import Mitsuba and select its float32 ``scalar_rgb`` variant."""
    import mitsuba as mi

    if mi.variant() != "scalar_rgb":
        mi.set_variant("scalar_rgb")
    return mi


def float32_directions(w) -> np.ndarray:
    """Normalise ``w`` in float64, round to float32 and return the result as float64.

    Parameters
    ----------
    w : array_like (..., 3)
        Non-zero vectors.

    Returns
    -------
    ndarray (..., 3), float64
        Unit vectors (within ``1e-7``) whose components are float32 numbers, so that Mitsuba
        and ``adobe_bsdf`` see exactly the same directions.
    """
    w = np.asarray(w, dtype=np.float64)
    return (w / np.linalg.norm(w, axis=-1, keepdims=True)).astype(np.float32).astype(np.float64)


class MitsubaBSDF:
    """A Mitsuba ``scalar_rgb`` BSDF plugin behind ``adobe_bsdf``'s ``eval``/``pdf`` protocol.

    Parameters
    ----------
    plugin : dict
        Mitsuba scene dictionary of the BSDF, passed to ``mitsuba.load_dict``.

    Notes
    -----
    See the module docstring for the conversion between the two libraries' conventions.
    """

    def __init__(self, plugin: dict):
        mi = _mitsuba()
        self.plugin = plugin
        self._bsdf = mi.load_dict(plugin)

    def eval(self, wo, wi) -> np.ndarray:
        """Radiance-mode BSDF value f(wo, wi) without the cosine factor, RGB ``(..., 3)``.

        Parameters
        ----------
        wo, wi : array_like (..., 3)
            Unit vectors towards the viewer and the light (broadcast against each other),
            rounded to float32 before Mitsuba sees them.
        """
        wo, wi = self._directions(wo, wi)
        value = self._loop(wo, wi, "eval", 3)
        cos_i = np.abs(wi[..., 2:])
        return np.divide(value, cos_i, out=np.zeros_like(value), where=cos_i > 0)

    def pdf(self, wo, wi) -> np.ndarray:
        """Solid-angle density ``(...)`` with which Mitsuba samples ``wi`` given ``wo``.

        Parameters
        ----------
        wo, wi : array_like (..., 3)
            As for ``eval``.
        """
        wo, wi = self._directions(wo, wi)
        return self._loop(wo, wi, "pdf", 1)[..., 0]

    @staticmethod
    def _directions(wo, wi):
        wo = np.asarray(wo, dtype=np.float64)
        wi = np.asarray(wi, dtype=np.float64)
        for name, w in (("wo", wo), ("wi", wi)):
            if w.ndim == 0 or w.shape[-1] != 3:
                raise ValueError(f"{name} has shape {w.shape}; directions need a trailing axis of 3")
        wo, wi = np.broadcast_arrays(wo, wi)
        return wo.astype(np.float32).astype(np.float64), wi.astype(np.float32).astype(np.float64)

    def _loop(self, wo, wi, method: str, channels: int) -> np.ndarray:
        mi = _mitsuba()
        ctx = mi.BSDFContext(mi.TransportMode.Radiance)
        si = mi.SurfaceInteraction3f()
        call = getattr(self._bsdf, method)
        out = np.empty((wo[..., 0].size, channels))
        for j, (a, b) in enumerate(zip(wo.reshape(-1, 3).tolist(), wi.reshape(-1, 3).tolist())):
            si.wi = mi.ScalarVector3f(a)
            out[j] = call(ctx, si, mi.ScalarVector3f(b))
        return out.reshape(*wo.shape[:-1], channels)


def _alphas(alpha_x, alpha_y):
    alpha_y = alpha_x if alpha_y is None else alpha_y
    for name, a in (("alpha_x", alpha_x), ("alpha_y", alpha_y)):
        if not (np.isfinite(a) and a > 0):
            raise ValueError(f"{name} = {a!r} is outside the allowed range (0, inf)")
    return float(alpha_x), float(alpha_y)


def _rgb(name, value):
    arr = np.broadcast_to(np.asarray(value, dtype=np.float64), (3,))
    if not np.all(np.isfinite(arr) & (arr >= 0)):
        raise ValueError(f"{name} = {value!r} is outside the allowed range [0, inf)")
    return {"type": "rgb", "value": arr.tolist()}


def mitsuba_conductor(alpha_x, alpha_y=None, eta=(0.0, 0.0, 0.0), k=(1.0, 1.0, 1.0)) -> MitsubaBSDF:
    """Mitsuba's ``roughconductor``: GGX, visible-normal sampling, complex IOR ``eta + i k``.

    Parameters
    ----------
    alpha_x, alpha_y : float
        GGX roughness along the tangent ``+x`` (Mitsuba's ``alpha_u``) and the bitangent
        (``alpha_v``); ``alpha_y = None`` means isotropic.
    eta, k : float or array_like (3,)
        Real and imaginary parts of the RGB refractive index relative to the outside. The
        default ``eta = 0`` makes Mitsuba's conductor Fresnel exactly 1 for every ``k``.

    Returns
    -------
    MitsubaBSDF
    """
    alpha_x, alpha_y = _alphas(alpha_x, alpha_y)
    return MitsubaBSDF({
        "type": "roughconductor",
        "distribution": "ggx",
        "sample_visible": True,
        "alpha_u": alpha_x,
        "alpha_v": alpha_y,
        "eta": _rgb("eta", eta),
        "k": _rgb("k", k),
    })


def mitsuba_dielectric(eta, alpha_x, alpha_y=None, ext_ior=1.0) -> MitsubaBSDF:
    """Mitsuba's ``roughdielectric``: GGX, visible-normal sampling, reflection + transmission.

    Parameters
    ----------
    eta : float
        ``n_below / n_above``, as ``adobe_bsdf.lobes.Dielectric``; Mitsuba receives
        ``int_ior = eta * ext_ior``.
    alpha_x, alpha_y : float
        As for ``mitsuba_conductor``.
    ext_ior : float
        Index above the surface (Mitsuba's ``ext_ior``); only ``eta`` matters, this chooses
        how Mitsuba is told it (e.g. ``eta = 1/1.5`` as ``int_ior = 1``, ``ext_ior = 1.5``).

    Returns
    -------
    MitsubaBSDF
    """
    alpha_x, alpha_y = _alphas(alpha_x, alpha_y)
    for name, v in (("eta", eta), ("ext_ior", ext_ior)):
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{name} = {v!r} is outside the allowed range (0, inf)")
    return MitsubaBSDF({
        "type": "roughdielectric",
        "distribution": "ggx",
        "sample_visible": True,
        "alpha_u": alpha_x,
        "alpha_v": alpha_y,
        "int_ior": float(eta) * float(ext_ior),
        "ext_ior": float(ext_ior),
    })


def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def _half_vector(wo, wi, eta):
    """Generalized half vector (turned to ``m_z >= 0``) and the index ratio ``eta_i / eta_o``."""
    reflect = wo[..., 2] * wi[..., 2] > 0
    ratio = np.where(wo[..., 2] > 0, eta, 1.0 / eta)
    h = wo + np.where(reflect, 1.0, ratio)[..., None] * wi
    norm = np.linalg.norm(h, axis=-1, keepdims=True)
    m = np.divide(h, norm, out=np.zeros_like(h), where=norm > 0)
    return np.where(m[..., 2:] < 0, -m, m), ratio


def well_conditioned(wo, wi, eta=None) -> np.ndarray:
    """Whether float32 evaluation of a GGX lobe is well conditioned at each pair.

    Parameters
    ----------
    wo, wi : array_like (..., 3)
        Unit direction pairs (viewer, light).
    eta : float, optional
        ``n_below / n_above`` of a dielectric; ``None`` for a conductor.

    Returns
    -------
    ndarray (...) of bool
        True where all of these hold, with ``m`` the generalized half vector
        ``normalize(wo + (eta_i/eta_o) wi)`` (``wo + wi`` for reflection):

        - ``|wo_z|, |wi_z|, |m_z| >= MIN_COS`` (no direction at a horizon, where the
          side tests of masking change sign);
        - ``|wo.m|, |wi.m| >= MIN_COS_M``; for reflection ``|wo + wi| = 2 |wo.m|``, so this
          also keeps the half vector clear of cancellation;
        - for a dielectric, ``|cos^2 theta_t| >= MIN_COS2_T`` with
          ``cos^2 theta_t = 1 - (1 - (wo.m)^2) (eta_o/eta_i)^2``, i.e. not near the critical
          angle, where Fresnel's float32 rounding error grows like ``1e-7 / cos^2 theta_t``.

    Notes
    -----
    The thresholds were chosen by comparing Mitsuba 3.9.1 ``scalar_rgb`` with a float64
    transcription of the same formulas on 10^5 random pairs per configuration: outside the
    excluded sets the relative error of eval and pdf stayed below ``5e-6``; inside, it
    reaches ``1e-4`` (``|wo.m| < 0.003``) and ``3e-4`` (``|cos^2 theta_t| < 0.003``).
    """
    wo = np.asarray(wo, dtype=np.float64)
    wi = np.asarray(wi, dtype=np.float64)
    m, ratio = _half_vector(wo, wi, 1.0 if eta is None else eta)
    ok = (np.abs(wo[..., 2]) >= MIN_COS) & (np.abs(wi[..., 2]) >= MIN_COS)
    ok &= np.abs(m[..., 2]) >= MIN_COS
    cos_o, cos_i = _dot(wo, m), _dot(wi, m)
    ok &= (np.abs(cos_o) >= MIN_COS_M) & (np.abs(cos_i) >= MIN_COS_M)
    if eta is not None:
        ok &= np.abs(1.0 - (1.0 - cos_o**2) / ratio**2) >= MIN_COS2_T
    return ok


def _uniform_sphere(rng, n):
    w = rng.normal(size=(n, 3))
    return w / np.linalg.norm(w, axis=-1, keepdims=True)


def _ggx_normals(rng, n, alpha_x, alpha_y):
    """Microfacet normals spread like GGX (its alpha = 1 normals, stretched), ``m_z > 0``."""
    u = rng.random((n, 2))
    tan_theta = np.sqrt(u[:, 0] / (1.0 - u[:, 0]))
    phi = 2.0 * np.pi * u[:, 1]
    m = np.stack([alpha_x * tan_theta * np.cos(phi), alpha_y * tan_theta * np.sin(phi),
                  np.ones(n)], axis=-1)
    return m / np.linalg.norm(m, axis=-1, keepdims=True)


def _refract(wo, m, ratio):
    """Refraction of ``wo`` at ``m`` into the medium ``ratio = eta_i / eta_o``; NaN at TIR."""
    cos_o = _dot(wo, m)
    m = np.where(cos_o[..., None] < 0, -m, m)
    cos_o = np.abs(cos_o)
    with np.errstate(invalid="ignore"):
        cos_t = np.sqrt(1.0 - (1.0 - cos_o**2) / ratio**2)
    return -wo / ratio[..., None] + (cos_o / ratio - cos_t)[..., None] * m


def crosscheck_pairs(n: int, alpha_x, alpha_y=None, eta=None, *, rng=None):
    """Random well-conditioned direction pairs for comparing a GGX lobe with Mitsuba.

    A third of the pairs (a half for a conductor) has ``wi`` uniform on the sphere, so
    pairs below the horizon, the far tails of the lobe and, for a dielectric, pairs whose
    microfacet is seen from its back (value 0) occur; the others have ``wi`` reflected
    (or, for a dielectric, refracted, in equal numbers) at a microfacet normal spread like
    GGX, so that the peak of the lobe is well covered. ``wo`` is uniform on the upper
    hemisphere for a conductor and on the whole sphere for a dielectric (light and viewer on
    both sides). Pairs that are not ``well_conditioned`` are rejected and redrawn.

    Parameters
    ----------
    n : int
        Number of pairs.
    alpha_x, alpha_y : float
        GGX roughness along the tangent and the bitangent (``alpha_y = None``: isotropic).
    eta : float, optional
        ``n_below / n_above`` of a dielectric; ``None`` for a conductor.
    rng : numpy.random.Generator or int, optional
        Random source or seed.

    Returns
    -------
    wo, wi : ndarray (n, 3), float64
        Unit vectors whose components are float32 numbers (``float32_directions``).
    """
    rng = np.random.default_rng(rng)
    alpha_y = alpha_x if alpha_y is None else alpha_y
    kinds = 2 if eta is None else 3
    pairs_wo, pairs_wi, found = [], [], 0
    while found < n:
        size = 2 * (n - found) + 16
        wo = _uniform_sphere(rng, size)
        if eta is None:
            wo[:, 2] = np.abs(wo[:, 2])
        m = _ggx_normals(rng, size, alpha_x, alpha_y)
        kind = rng.integers(kinds, size=size)
        wi = _uniform_sphere(rng, size)
        wi = np.where((kind == 1)[:, None], 2.0 * _dot(wo, m)[:, None] * m - wo, wi)
        if eta is not None:
            ratio = np.where(wo[:, 2] > 0, eta, 1.0 / eta)
            wi = np.where((kind == 2)[:, None], _refract(wo, m, ratio), wi)
        keep = np.all(np.isfinite(wi), axis=-1)
        wo, wi = float32_directions(wo[keep]), float32_directions(wi[keep])
        keep = well_conditioned(wo, wi, eta)
        pairs_wo.append(wo[keep])
        pairs_wi.append(wi[keep])
        found += int(keep.sum())
    return np.concatenate(pairs_wo)[:n], np.concatenate(pairs_wi)[:n]
