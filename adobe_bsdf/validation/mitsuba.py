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
``well_conditioned(wo, wi, eta)``
    Whether float32 evaluation is well conditioned at each pair (the excluded sets).
``crosscheck_pairs(n, alpha_x, alpha_y, eta, rng)``
    Random well-conditioned direction pairs, concentrated on the lobe and spread over it.

Mitsuba is imported lazily (this module imports without it) and the ``scalar_rgb`` variant is
selected on first use; pairs are evaluated one by one in a Python loop (a few µs per pair).

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
cancels the ``eta^2`` of [Walter2007], so after dividing by ``|wi_z|``::

    f(wo, wi) = eta_o^2 (1 - F) D G |(wo.m)(wi.m)| / (|wo_z| |wi_z| (eta_o wo.m + eta_i wi.m)^2)

which is pbrt-v4's radiance-mode BTDF and ``adobe_bsdf``'s convention: ``f(wo, wi) / eta_o^2``
is symmetric in ``wo`` and ``wi`` (the Fresnel transmittance of the refraction pair is the same
from both sides), i.e. ``f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2``. ``tests/
test_mitsuba_crosscheck.py`` confirms this numerically: the converted values satisfy that
generalized reciprocity, agree with a float64 transcription of the formula above, and the
energy ``integral of f (eta_i / eta_o)^2 |cos theta_i|`` over both hemispheres is ``<= 1``
and equals the mean of Mitsuba's own sampling weights times ``bs.eta^2`` (an ``eta^2`` left
in or out would change the transmitted part by a factor 2.25).
Reflection is ``F D G / (4 |wo_z| |wi_z|)`` in both libraries.

``pdf`` is Mitsuba's solid-angle density unchanged: for the conductor the visible-normal
density ``G1(wo, m) D(m) / (4 |wo_z|)``; for the dielectric the visible-normal density of ``m``
times the Jacobian of the (generalized) half-vector map, times ``F(wo.m)`` for reflection or
``1 - F(wo.m)`` for transmission.

Float32
-------
Mitsuba's ``scalar_rgb`` variant computes in float32, and ``MitsubaBSDF`` rounds directions to
the nearest float32 (without renormalising). To give both libraries identical input, pass
directions that are already float32 numbers: ``float32_directions`` makes such vectors, with
``|w|^2`` as close to 1 as it can. On identical input Mitsuba agrees with float64 to about
``1.5e-6`` relative for the conductor and ``4.5e-6`` for the dielectric (measured on 10^5
pairs per configuration, roughness 0.02 to 1), except where the model is ill conditioned:

- near the critical angle of total internal reflection the float32 ``cos^2 theta_t`` has an
  absolute error of about ``1e-7``, so Fresnel and the transmitted value have a relative
  error of about ``1e-7 / cos^2 theta_t`` (measured: ``2e-5`` at ``|cos^2 theta_t|`` in
  [0.01, 0.03), ``2e-4`` below ``1e-4``; within about ``1e-6`` of the critical angle Mitsuba
  is off by O(1) and may return 0 where the transmission is not 0);
- directions grazing the microfacet (``|wo.m|`` or ``|wi.m|`` small): measured ``4e-5`` at
  [0.01, 0.03), ``1e-4`` at [0.001, 0.01), ``1e-2`` below ``1e-5``; for reflection pairs
  close to ``wi = -wo`` this is made worse by the float32 vectors not being exactly unit;
- directions or microfacet normals at a horizon, where side tests may flip.

``well_conditioned`` defines the excluded sets and ``crosscheck_pairs`` draws pairs outside
them.
"""

from __future__ import annotations

import re

import numpy as np

__all__ = [
    "MitsubaBSDF",
    "mitsuba_conductor",
    "mitsuba_dielectric",
    "float32_directions",
    "well_conditioned",
    "crosscheck_pairs",
    "FLOAT32_SEARCH",
    "MIN_COS",
    "MIN_COS_M",
    "MIN_COS2_T",
    "MAX_UNIT_DEFECT",
]

#: float32 neighbours searched on each side, per component, by ``float32_directions``
FLOAT32_SEARCH = 2
#: smallest ``|cos|`` of ``wo``, ``wi`` and the microfacet normal with the normal, in
#: ``well_conditioned``
MIN_COS = 1e-3
#: smallest ``|cos|`` between ``wo`` or ``wi`` and the microfacet normal, in ``well_conditioned``
MIN_COS_M = 5e-2
#: smallest ``|cos^2 theta_t|`` of the refraction of ``wo`` at the microfacet (the distance from
#: the critical angle of total internal reflection, on either side), in ``well_conditioned``
MIN_COS2_T = 1e-1
#: largest ``|1 - |w|^2| / min(|wo.m|, |wi.m|)^2`` for ``w = wo, wi``, in ``well_conditioned``
#: (how much a float32 vector's deviation from unit length is amplified)
MAX_UNIT_DEFECT = 1e-6


#: the index of Mitsuba's "air", its default ``ext_ior``
MITSUBA_AIR = 1.000277


def _mitsuba():
    """Import Mitsuba and select its float32 ``scalar_rgb`` variant."""
    import mitsuba as mi

    if mi.variant() != "scalar_rgb":
        mi.set_variant("scalar_rgb")
    return mi


def float32_directions(w) -> np.ndarray:
    """Float32 approximations of the directions of ``w``, as close to unit length as possible.

    Each vector is normalised in float64 and rounded to float32; then, among the float32
    vectors within ``FLOAT32_SEARCH`` units in the last place of that rounding in every
    component (zero components stay zero), the one whose squared length is closest to 1 is
    kept. Nearest rounding alone leaves ``|w|^2 - 1`` of order ``3e-8``; the search lowers the
    median to about ``2e-9``, so that formulas which are equivalent for unit vectors (say
    ``wo.m`` and ``wi.m`` for a reflection pair) agree. The direction moves by less than
    ``3 * FLOAT32_SEARCH * 6e-8``.

    Parameters
    ----------
    w : array_like (..., 3)
        Non-zero vectors.

    Returns
    -------
    ndarray (..., 3), float64
        Vectors whose components are float32 numbers, so that Mitsuba and ``adobe_bsdf`` see
        exactly the same directions.
    """
    w = np.asarray(w, dtype=np.float64)
    shape = w.shape
    w32 = (w / np.linalg.norm(w, axis=-1, keepdims=True)).astype(np.float32).reshape(-1, 3)
    offsets = np.arange(-FLOAT32_SEARCH, FLOAT32_SEARCH + 1, dtype=np.float32)
    steps = np.spacing(np.abs(w32)) * (w32 != 0)
    x, y, z = ((w32[:, c, None] + offsets * steps[:, c, None]).astype(np.float64) for c in range(3))
    defect = np.abs(
        x[:, :, None, None] ** 2 + y[:, None, :, None] ** 2 + z[:, None, None, :] ** 2 - 1.0
    )
    n = offsets.size
    i, j, k = np.unravel_index(defect.reshape(len(w32), -1).argmin(axis=-1), (n, n, n))
    rows = np.arange(len(w32))
    return np.stack([x[rows, i], y[rows, j], z[rows, k]], axis=-1).reshape(shape)


class MitsubaBSDF:
    """A Mitsuba ``scalar_rgb`` BSDF plugin behind ``adobe_bsdf``'s ``eval``/``pdf``/``sample``
    protocol (a ``validation.Candidate``).

    Parameters
    ----------
    plugin : dict or str
        Mitsuba scene dictionary of the BSDF, passed to ``mitsuba.load_dict``, or its XML
        (``<bsdf type="roughconductor">...</bsdf>``), passed to ``mitsuba.load_string``.

    Attributes
    ----------
    plugin : dict
        The dictionary.
    bsdf : mitsuba.BSDF
        The loaded plugin, for calls in Mitsuba's own conventions (e.g. ``sample``).

    Notes
    -----
    See the module docstring for the conversion between the two libraries' conventions.
    """

    def __init__(self, plugin):
        mi = _mitsuba()
        self.plugin = plugin
        if isinstance(plugin, str):
            xml = plugin.strip()
            if "version=" not in xml.split(">", 1)[0]:  # the root element needs a version
                xml = re.sub(r"^<(\w+)", r'<\1 version="3.0.0"', xml, count=1)
            try:
                self.bsdf = mi.load_string(xml)
            except Exception as exc:  # Mitsuba's parser: say which plugin text failed
                raise ValueError(f"plugin = {plugin!r}: Mitsuba could not load it: "
                                 f"{exc}") from None
            found = re.search(r'type="(\w+)"', xml)
            kind = found.group(1) if found else "bsdf"
            indices = {k: float(v) for k, v in re.findall(
                r'name="(int_ior|ext_ior)"\s+value="([0-9.eE+-]+)"', xml)}
        elif isinstance(plugin, dict):
            self.bsdf = mi.load_dict(plugin)
            kind = plugin.get("type", "bsdf")
            indices = {k: plugin[k] for k in ("int_ior", "ext_ior")
                       if isinstance(plugin.get(k), (int, float))}
        else:
            raise ValueError(f"plugin = {plugin!r}: allowed a Mitsuba plugin dictionary or "
                             "its XML string")
        self.name = f"Mitsuba {kind}"
        #: n_below / n_above where the plugin states its inner index as a number (its outer
        #: one defaults to Mitsuba's "air", ``MITSUBA_AIR``)
        self.eta = (float(indices["int_ior"]) / float(indices.get("ext_ior", MITSUBA_AIR))
                    if "int_ior" in indices else None)

    def __repr__(self) -> str:
        return f"MitsubaBSDF({self.plugin!r})"

    def sample(self, wo, u):
        """``(wi, weight, pdf)`` of Mitsuba's ``sample`` from uniforms ``u`` ``(..., 3)``
        (``u[..., 0]`` its 1-D sample, ``u[..., 1:]`` its 2-D one): the weight is Mitsuba's
        (f |cos| / pdf in its radiance mode, our convention), 0 where it failed."""
        mi = _mitsuba()
        wo = np.asarray(wo, dtype=np.float64).astype(np.float32).astype(np.float64)
        u = np.asarray(u, dtype=np.float64)
        wo, u = np.broadcast_arrays(wo, u)
        ctx = mi.BSDFContext(mi.TransportMode.Radiance)
        si = mi.SurfaceInteraction3f()
        n = wo[..., 0].size
        wi, weight, pdf = np.zeros((n, 3)), np.zeros((n, 3)), np.zeros(n)
        rows = zip(wo.reshape(-1, 3).tolist(), u.reshape(-1, 3).tolist(), strict=True)
        for j, (a, b) in enumerate(rows):
            si.wi = mi.ScalarVector3f(a)
            bs, w = self.bsdf.sample(ctx, si, b[0], mi.ScalarPoint2f(b[1], b[2]))
            if bs.pdf > 0.0 and any(x != 0.0 for x in w):  # else failed: pdf 0 here
                wi[j], weight[j], pdf[j] = bs.wo, w, bs.pdf
        shape = wo.shape[:-1]
        return wi.reshape(shape + (3,)), weight.reshape(shape + (3,)), pdf.reshape(shape)

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
                raise ValueError(
                    f"{name} has shape {w.shape}; directions need a trailing axis of 3"
                )
        wo, wi = np.broadcast_arrays(wo, wi)
        return wo.astype(np.float32).astype(np.float64), wi.astype(np.float32).astype(np.float64)

    def _loop(self, wo, wi, method: str, channels: int) -> np.ndarray:
        mi = _mitsuba()
        ctx = mi.BSDFContext(mi.TransportMode.Radiance)
        si = mi.SurfaceInteraction3f()
        call = getattr(self.bsdf, method)
        out = np.empty((wo[..., 0].size, channels))
        pairs = zip(wo.reshape(-1, 3).tolist(), wi.reshape(-1, 3).tolist(), strict=True)
        for j, (a, b) in enumerate(pairs):
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


def _microfacets(model, alpha_x, alpha_y) -> dict:
    """The plugin properties of a rough Mitsuba BSDF: distribution, visible-normal sampling,
    validated alphas."""
    if model not in ("ggx", "beckmann"):
        raise ValueError(f"model = {model!r} is not one of ('ggx', 'beckmann')")
    alpha_x, alpha_y = _alphas(alpha_x, alpha_y)
    return {"distribution": model, "sample_visible": True, "alpha_u": alpha_x,
            "alpha_v": alpha_y}


def mitsuba_conductor(alpha_x, alpha_y=None, eta=(0.0, 0.0, 0.0), k=(1.0, 1.0, 1.0),
                      model: str = "ggx") -> MitsubaBSDF:
    """Mitsuba's ``roughconductor``: GGX (or Beckmann, ``model``), visible-normal sampling,
    complex IOR ``eta + i k``.

    Parameters
    ----------
    alpha_x, alpha_y : float
        GGX roughness along the tangent ``+x`` (Mitsuba's ``alpha_u``) and the bitangent
        (``alpha_v``); ``alpha_y = None`` means isotropic.
    eta, k : float or array_like (3,)
        Real and imaginary parts of the RGB refractive index relative to the outside. The
        default ``eta = 0`` makes Mitsuba's conductor Fresnel exactly 1 for every ``k``.
    model : {"ggx", "beckmann"}
        Mitsuba's ``distribution``.

    Returns
    -------
    MitsubaBSDF
    """
    return MitsubaBSDF(
        {
            "type": "roughconductor",
            **_microfacets(model, alpha_x, alpha_y),
            "eta": _rgb("eta", eta),
            "k": _rgb("k", k),
        }
    )


def mitsuba_dielectric(eta, alpha_x, alpha_y=None, ext_ior=1.0,
                       model: str = "ggx") -> MitsubaBSDF:
    """Mitsuba's ``roughdielectric``: GGX (or Beckmann, ``model``), visible-normal sampling,
    reflection + transmission.

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
    model : {"ggx", "beckmann"}
        Mitsuba's ``distribution``.

    Returns
    -------
    MitsubaBSDF
    """
    props = _microfacets(model, alpha_x, alpha_y)
    for name, v in (("eta", eta), ("ext_ior", ext_ior)):
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{name} = {v!r} is outside the allowed range (0, inf)")
    return MitsubaBSDF(
        {
            "type": "roughdielectric",
            **props,
            "int_ior": float(eta) * float(ext_ior),
            "ext_ior": float(ext_ior),
        }
    )


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
        - ``|wo.m|, |wi.m| >= MIN_COS_M``;
        - ``|1 - |w|^2| <= MAX_UNIT_DEFECT min(|wo.m|, |wi.m|)^2`` for ``w = wo, wi``:
          directions that are float32 numbers are not exactly unit, and for a reflection pair
          close to ``wi = -wo`` formulas that agree for unit vectors (``wo.m`` and ``wi.m``)
          differ by about ``(|wo|^2 - |wi|^2) / (2 (wo.m)^2)``;
        - for a dielectric, ``|cos^2 theta_t| >= MIN_COS2_T`` with
          ``cos^2 theta_t = 1 - (1 - (wo.m)^2) (eta_o/eta_i)^2``, i.e. not near the critical
          angle, where Fresnel's float32 rounding error grows like ``1e-7 / cos^2 theta_t``.

    Notes
    -----
    The thresholds were chosen by comparing Mitsuba 3.9.1 ``scalar_rgb`` with float64 (a
    transcription of the same formulas, and ``adobe_bsdf``'s lobes) on random pairs: outside
    the excluded sets the relative difference of eval and pdf stayed below ``5e-6`` (10^5
    pairs per configuration); inside them it grows as the module docstring describes. Random
    pairs uniform on the sphere are kept with probability 0.996 for a conductor and 0.86 for
    a dielectric of index ratio 1.5 (the band around the critical angle is most of the rest).
    """
    wo = np.asarray(wo, dtype=np.float64)
    wi = np.asarray(wi, dtype=np.float64)
    m, ratio = _half_vector(wo, wi, 1.0 if eta is None else eta)
    ok = (np.abs(wo[..., 2]) >= MIN_COS) & (np.abs(wi[..., 2]) >= MIN_COS)
    ok &= np.abs(m[..., 2]) >= MIN_COS
    cos_o, cos_i = _dot(wo, m), _dot(wi, m)
    ok &= (np.abs(cos_o) >= MIN_COS_M) & (np.abs(cos_i) >= MIN_COS_M)
    defect = np.maximum(np.abs(1.0 - _dot(wo, wo)), np.abs(1.0 - _dot(wi, wi)))
    ok &= defect <= MAX_UNIT_DEFECT * np.minimum(cos_o**2, cos_i**2)
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
    m = np.stack(
        [alpha_x * tan_theta * np.cos(phi), alpha_y * tan_theta * np.sin(phi), np.ones(n)], axis=-1
    )
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

    ``wo`` is uniform on the upper hemisphere for a conductor and on the whole sphere for a
    dielectric (viewer and light on both sides). ``wi`` is, in equal shares: uniform on the
    sphere (so that pairs below the horizon, the far tails of the lobe and, for a dielectric,
    microfacets seen from their back, all of value 0, occur); ``wo`` reflected at a
    microfacet normal spread like GGX (the peak of the lobe); and, for a dielectric, ``wo``
    refracted at such a normal, for a conductor, uniform on the upper hemisphere.
    Pairs that are not ``well_conditioned`` are rejected and redrawn.

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
    pairs_wo, pairs_wi, found = [], [], 0
    while found < n:
        size = 2 * (n - found) + 16
        wo = _uniform_sphere(rng, size)
        if eta is None:
            wo[:, 2] = np.abs(wo[:, 2])
        m = _ggx_normals(rng, size, alpha_x, alpha_y)
        kind = rng.integers(3, size=size)[:, None]
        wi = _uniform_sphere(rng, size)
        if eta is None:
            third = wi.copy()
            third[:, 2] = np.abs(wi[:, 2])
        else:
            third = _refract(wo, m, np.where(wo[:, 2] > 0, eta, 1.0 / eta))
        wi = np.where(kind == 1, 2.0 * _dot(wo, m)[:, None] * m - wo, wi)
        wi = np.where(kind == 2, third, wi)
        keep = np.all(np.isfinite(wi), axis=-1)
        wo, wi = float32_directions(wo[keep]), float32_directions(wi[keep])
        keep = well_conditioned(wo, wi, eta)
        pairs_wo.append(wo[keep])
        pairs_wi.append(wi[keep])
        found += int(keep.sum())
    return np.concatenate(pairs_wo)[:n], np.concatenate(pairs_wi)[:n]
