"""A small Monte-Carlo renderer for figures: a unit sphere of any BSDF under an environment.

Public API
----------
``sphere(bsdf, env="furnace", size=128, spp=64, seed=0, light=None, max_depth=16)``
    (size, size, 3) linear radiance, background included.
``Uniform(radiance)``, ``Sun(direction, irradiance, ambient)``, ``EquirectMap(image)``
    environments: L(w) for directions w pointing away from the scene, with sampling.
``sky(height=64)``     a synthetic equirectangular sky (made in code, nothing downloaded).
``studio(height=128)``  a synthetic studio: grey room, vertical light strips (made in code).
``tone_map(image, exposure=0, tonemap="clip")``  linear radiance to display values in [0, 1]:
                       ``exposure`` stops, then ``"clip"`` (clip to [0, 1]) or ``"aces"`` (the
                       fitted ACES filmic curve of [Narkowicz2016], per channel).
``to_srgb8(image, exposure=0, tonemap="clip")``  the same, then 8-bit sRGB;
                       ``write_png(path, image, exposure=0, tonemap="clip")`` saves it.

The camera is orthographic, looking down -z at the unit sphere; y is up in the image. Each
pixel that hits the sphere traces paths: at a point p the shading normal is p and the
tangent runs around the vertical axis (so anisotropy shows as brushed rings). At every
vertex outside the sphere the light is sampled (next-event estimation) and the BSDF is
sampled; both are combined with the power heuristic [Veach1997, §9.2]. A delta light (the
sun) is only sampled; a delta BSDF sample only hits the environment. Transmitted rays cross
the sphere (its far side from inside: t = -2 p.d) until they leave it or ``max_depth``
vertices have been traced. The path throughput is passed to ``sample`` (dispersion). The
sphere is convex, so a direction above the surface at p is never blocked by the sphere.
"""

from __future__ import annotations

import struct
import zlib

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf.bsdf import Flags, Lobe, luminance
from adobe_bsdf.frame import Frame, normalize

__all__ = ["sphere", "Uniform", "Sun", "EquirectMap", "sky", "studio", "tone_map", "to_srgb8",
           "write_png"]

#: the tone curves of ``tone_map``, ``to_srgb8`` and ``write_png``
TONEMAPS = ("clip", "aces")


class Uniform:
    """Constant radiance from every direction (``"furnace"``: 1), sampled uniformly."""

    delta = False

    def __init__(self, radiance=1.0):
        self.value = _params.color("radiance", radiance, 0.0, np.inf)

    def radiance(self, w):
        return np.broadcast_to(self.value, w.shape[:-1] + (3,))

    def sample(self, u):
        z = 1.0 - 2.0 * u[..., 0]
        r = np.sqrt(np.maximum(0.0, 1.0 - z * z))
        phi = 2.0 * np.pi * u[..., 1]
        w = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)
        return w, np.full(w.shape[:-1], 1.0 / (4.0 * np.pi))

    def pdf(self, w):
        return np.full(w.shape[:-1], 1.0 / (4.0 * np.pi))


class Sun:
    """A directional light of ``irradiance`` (W/m^2 on a surface facing it) from
    ``direction``, plus a uniform ``ambient`` radiance."""

    delta = True

    def __init__(self, direction=(1.0, 1.0, 1.0), irradiance=3.0, ambient=0.2):
        self.direction = normalize(_params.real("direction", direction))
        self.irradiance = _params.color("irradiance", irradiance, 0.0, np.inf)
        self.ambient = Uniform(ambient)

    def radiance(self, w):
        return self.ambient.radiance(w)


class EquirectMap:
    """Radiance from an equirectangular image (rows: polar angle from +y, 0 to pi; columns:
    azimuth about +y from +z towards +x, 0 to 2 pi), sampled in proportion to pixel
    luminance times sin(theta) (a piecewise-constant 2-D distribution)."""

    delta = False

    def __init__(self, image):
        img = _params.real("image", image, 0.0, np.inf)
        if img.ndim != 3 or img.shape[-1] != 3:
            raise ValueError(f"image has shape {img.shape}; allowed (height, width, 3)")
        self.image = img
        h, w = img.shape[:2]
        theta = (np.arange(h) + 0.5) / h * np.pi
        weight = luminance(img) * np.sin(theta)[:, None] + 1e-12 * np.max(img)
        self._p = (weight / weight.sum()).ravel()
        self._cdf = np.cumsum(self._p)
        self._cdf[-1] = 1.0

    def _pixel(self, w):
        h, wd = self.image.shape[:2]
        theta = np.arccos(np.clip(w[..., 1], -1.0, 1.0))
        phi = np.mod(np.arctan2(w[..., 0], w[..., 2]), 2.0 * np.pi)
        i = np.minimum((theta / np.pi * h).astype(int), h - 1)
        j = np.minimum((phi / (2.0 * np.pi) * wd).astype(int), wd - 1)
        return i, j, theta

    def radiance(self, w):
        i, j, _ = self._pixel(w)
        return self.image[i, j]

    def pdf(self, w):
        h, wd = self.image.shape[:2]
        i, j, theta = self._pixel(w)
        sin = np.maximum(np.sin(theta), 1e-12)
        return self._p[i * wd + j] * h * wd / (2.0 * np.pi**2 * sin)

    def sample(self, u):
        h, wd = self.image.shape[:2]
        k = np.minimum(np.searchsorted(self._cdf, u[..., 0], side="right"), h * wd - 1)
        i, j = np.divmod(k, wd)
        theta = (i + u[..., 1]) / h * np.pi
        phi = (j + u[..., 2]) / wd * 2.0 * np.pi
        s = np.sin(theta)
        w = np.stack([s * np.sin(phi), np.cos(theta), s * np.cos(phi)], axis=-1)
        return w, self.pdf(w)


def sky(height: int = 64, sun=(0.5, 0.6, 0.62), sun_radiance: float = 400.0) -> np.ndarray:
    """A synthetic equirectangular sky ``(height, 2 height, 3)``: a blue gradient above the
    horizon, a warm grey ground below, and a small sun disk (about 2 pixels) towards
    ``sun``. For figures; made in code."""
    height = _params.integer("height", height, 4)
    h, w = height, 2 * height
    theta = (np.arange(h) + 0.5) / h * np.pi
    phi = (np.arange(w) + 0.5) / w * 2.0 * np.pi
    T, P = np.meshgrid(theta, phi, indexing="ij")
    d = np.stack([np.sin(T) * np.sin(P), np.cos(T), np.sin(T) * np.cos(P)], axis=-1)
    up = np.clip(d[..., 1], 0.0, 1.0)[..., None]
    zenith, horizon = np.array([0.25, 0.45, 0.9]), np.array([0.9, 0.95, 1.0])
    image = np.where(d[..., 1:2] >= 0.0, horizon + (zenith - horizon) * np.sqrt(up),
                     np.array([0.35, 0.3, 0.25]))
    s = normalize(np.asarray(sun, dtype=np.float64))
    disk = (d @ s) > np.cos(2.0 * np.pi / h)
    return np.where(disk[..., None], sun_radiance * np.array([1.0, 0.95, 0.85]), image)


def studio(height: int = 128, bars: int = 4, radiance: float = 1.5) -> np.ndarray:
    """A synthetic equirectangular studio ``(height, 2 height, 3)``: a grey room (lighter
    above the horizon) with ``bars`` tall vertical light strips of ``radiance`` spaced
    evenly in azimuth; sharp edges that show refraction and dispersion. Made in code."""
    height = _params.integer("height", height, 4)
    bars = _params.integer("bars", bars, 1)
    h, w = height, 2 * height
    theta = (np.arange(h) + 0.5) / h * np.pi
    phi = (np.arange(w) + 0.5) / w * 2.0 * np.pi
    y, P = np.meshgrid(np.cos(theta), phi, indexing="ij")
    strip = (np.mod(P * bars / (2.0 * np.pi) + 0.1, 1.0) < 0.2) & (np.abs(y) < 0.7)
    room = np.where(y >= 0.0, 0.3 + 0.2 * y, 0.15)
    return np.repeat(np.where(strip, radiance, room)[..., None], 3, axis=-1)


def _environment(env, light):
    if isinstance(env, (Uniform, Sun, EquirectMap)):
        return env
    if isinstance(env, str):
        if env == "furnace":
            return Uniform(1.0)
        if env == "sun":
            return Sun() if light is None else Sun(*light)
        if env == "sky":
            return EquirectMap(sky())
        if env == "studio":
            return EquirectMap(studio())
        raise ValueError(f"env = {env!r}: allowed 'furnace', 'sun', 'sky', 'studio', an image "
                         "(h, w, 3) or an environment object")
    return EquirectMap(env)


def _power(a, b):
    """Power heuristic weight of the strategy with density ``a`` against ``b``."""
    a2, b2 = a * a, b * b
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(a2 > 0.0, a2 / (a2 + b2), 0.0)


def _frames(p):
    """Shading frames at sphere points: normal p, tangent around the vertical (y) axis."""
    return Frame(p, t=np.stack([-p[..., 2], np.zeros(p.shape[:-1]), p[..., 0]], axis=-1))


def _trace(bsdf, env, p, rng, max_depth):
    """Radiance ``(n, 3)`` of one path from each sphere point ``p`` towards the camera."""
    n = len(p)
    radiance = np.zeros((n, 3))
    throughput = np.ones((n, 3))
    wo_world = np.broadcast_to(np.array([0.0, 0.0, 1.0]), (n, 3)).copy()
    alive = np.arange(n)
    for _ in range(max_depth):
        if not len(alive):
            break
        frame = _frames(p)
        wo = frame.to_local(wo_world)
        outside = wo[:, 2] > 0.0
        T = throughput[alive]
        # next-event estimation from outside (a light below the surface is behind the sphere)
        if env.delta:
            wl = np.broadcast_to(env.direction, wo.shape)
            wi = frame.to_local(wl)
            f = bsdf.eval(wo, wi)
            lit = outside & (wi[:, 2] > 0.0)
            radiance[alive] += np.where(lit[:, None], T * f * wi[:, 2:3] * env.irradiance, 0.0)
        else:
            wl, pdf_l = env.sample(rng.random((len(alive), 3)))
            wi = frame.to_local(wl)
            f, pdf_b = bsdf.eval_pdf(wo, wi, throughput=T)
            lit = outside & (wi[:, 2] > 0.0) & (pdf_l > 0.0)
            with np.errstate(divide="ignore", invalid="ignore"):
                c = T * f * wi[:, 2:3] * env.radiance(wl) * (_power(pdf_l, pdf_b) / pdf_l)[:, None]
            radiance[alive] += np.where(lit[:, None], c, 0.0)
        # BSDF sampling
        s = bsdf.sample(wo, rng.random((len(alive), 3)), throughput=T)
        ok = s.pdf > 0.0
        T = T * s.weight
        wi_world = frame.to_world(s.wi)
        escapes = ok & (s.wi[:, 2] > 0.0)
        delta = (s.flags & int(Flags.DELTA)) != 0
        if env.delta:
            mis = np.ones(len(alive))
        else:
            mis = np.where(delta | ~outside, 1.0, _power(s.pdf, env.pdf(wi_world)))
        radiance[alive] += np.where(escapes[:, None],
                                    T * env.radiance(wi_world) * mis[:, None], 0.0)
        inward = ok & (s.wi[:, 2] < 0.0)
        throughput[alive] = T
        d = wi_world[inward]
        q = p[inward]
        p = normalize(q - 2.0 * np.sum(q * d, axis=-1)[:, None] * d)  # far side of the sphere
        wo_world = -d
        alive = alive[inward]
    return radiance


def sphere(bsdf: Lobe, env="furnace", size: int = 128, spp: int = 64, seed: int = 0,
           light=None, max_depth: int = 16, progress: bool = True) -> np.ndarray:
    """Render the unit sphere of ``bsdf`` (any lobe or material) seen from +z.

    Parameters
    ----------
    bsdf : Lobe
    env : "furnace", "sun", "sky", "studio", ndarray (h, w, 3) or an environment object
        "furnace": uniform radiance 1; "sun": ``Sun()`` (or ``Sun(*light)``) plus ambient;
        "sky": ``EquirectMap(sky())``; "studio": ``EquirectMap(studio())``; an array: an
        equirectangular radiance map.
    size : int        pixels per side, in [1, inf).
    spp : int         paths per pixel, in [1, inf).
    seed : int        seed of ``numpy.random.default_rng``.
    light : tuple     (direction, irradiance, ambient) for ``env="sun"``.
    max_depth : int   vertices per path, in [1, inf).
    progress : bool   show a tqdm bar over the samples per pixel.

    Returns
    -------
    ndarray (size, size, 3): mean radiance per pixel, linear; the background is the
    environment seen along -z.
    """
    if not isinstance(bsdf, Lobe):
        raise ValueError(f"bsdf = {bsdf!r}: allowed a Lobe (a lobe or a material)")
    size = _params.integer("size", size, 1)
    spp = _params.integer("spp", spp, 1)
    max_depth = _params.integer("max_depth", max_depth, 1)
    environment = _environment(env, light)
    rng = np.random.default_rng(seed)
    centres = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    x, y = np.meshgrid(centres, -centres)  # row 0 at the top (+y)
    r2 = x * x + y * y
    hit = r2 < 1.0
    p = np.stack([x[hit], y[hit], np.sqrt(1.0 - r2[hit])], axis=-1)
    total = np.zeros((len(p), 3))
    samples = range(spp)
    if progress:  # imported here: in a notebook without ipywidgets tqdm.auto warns on import
        from tqdm.auto import tqdm

        samples = tqdm(samples, desc="render", leave=False)
    for _ in samples:
        total += _trace(bsdf, environment, p, rng, max_depth)
    image = np.empty((size, size, 3))
    image[...] = environment.radiance(np.array([0.0, 0.0, -1.0]))
    image[hit] = total / spp
    return image


def _aces(x: np.ndarray) -> np.ndarray:
    """The fitted ACES curve [Narkowicz2016]: x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14),
    saturated to [0, 1] as in the reference listing (negative inputs give 0)."""
    x = np.maximum(x, 0.0)
    return np.minimum(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 1.0)


def tone_map(image, exposure: float = 0.0, tonemap: str = "clip") -> np.ndarray:
    """Linear radiance ``(..., 3)`` to linear display values in [0, 1].

    Parameters
    ----------
    image : array_like (..., 3)
        Linear radiance, finite.
    exposure : float
        Stops: the radiance is multiplied by ``2**exposure`` before the curve; finite.
    tonemap : {"clip", "aces"}
        ``"clip"`` (default): values are clipped to [0, 1]; a saturated colour brighter
        than 1 loses its hue (a red whose red channel is cut at 1 turns pink). ``"aces"``:
        the fitted ACES filmic curve of [Narkowicz2016], per channel,
        ``f(x) = x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)`` saturated to [0, 1]:
        increasing, ``f(0) = 0``, ``f(1) = 0.80``, ``f(x) = 1`` from x = 7.24 on; it
        compresses highlights instead of cutting them. Negative values give 0 in both.

    Returns
    -------
    ndarray (..., 3)
        Display-linear values in [0, 1] (before the sRGB transfer function).
    """
    img = _params.real("image", image, -np.inf, np.inf)
    ev = _params.real("exposure", exposure, -np.inf, np.inf)
    if ev.ndim:
        raise ValueError(f"exposure has shape {ev.shape}; allowed: a single number (stops)")
    curve = _params.choice("tonemap", tonemap, TONEMAPS)
    if float(ev) != 0.0:
        img = img * 2.0 ** float(ev)
    return np.clip(img, 0.0, 1.0) if curve == "clip" else _aces(img)


def to_srgb8(image, exposure: float = 0.0, tonemap: str = "clip") -> np.ndarray:
    """Linear radiance ``(..., 3)`` to 8-bit sRGB: ``tone_map(image, exposure, tonemap)``, then
    the IEC 61966-2-1 transfer function. With the defaults the values are clipped to [0, 1]."""
    c = tone_map(image, exposure, tonemap)
    s = np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)
    return np.round(s * 255.0).astype(np.uint8)


def write_png(path, image, exposure: float = 0.0, tonemap: str = "clip") -> None:
    """Save a linear image ``(h, w, 3)`` as an 8-bit sRGB PNG (zlib, no extra dependency),
    through ``to_srgb8(image, exposure, tonemap)``."""
    rgb = to_srgb8(image, exposure, tonemap)
    if rgb.ndim != 3 or rgb.shape[-1] != 3:
        raise ValueError(f"image has shape {rgb.shape}; allowed (height, width, 3)")
    h, w = rgb.shape[:2]
    raw = b"".join(b"\x00" + rgb[i].tobytes() for i in range(h))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)
    with open(path, "wb") as out:
        out.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
                  + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
