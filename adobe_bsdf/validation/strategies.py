"""Hypothesis strategies for BSDF inputs, weighted towards the edge cases that break lobes.

Public API
----------
``directions``       unit vectors on the sphere or a hemisphere: exact normals, grazing angles
                     down to ``min_abs_cos``, optionally exactly on the horizon, and random ones.
``direction_pairs``  ``(wo, wi)`` pairs: reflection, transmission or either, with the mirror,
                     retro-reflection and straight-through pairs as special cases.
``roughness``        GGX alpha or roughness in [0, 1]: 0, 1, tiny values, random.
``alpha_pairs``      ``(alpha_x, alpha_y)``: isotropic and anisotropic.
``iors``             relative refractive index: 1, 1 +- 1e-6, 1.01, below 1, up to 3.
``uniform_triples``  ``u`` of shape (3,) in [0, 1): 0, 1/2 and the largest double below 1.

This is the only module of ``adobe_bsdf`` that imports ``hypothesis``.
Directions are built in float64 and normalised, so ``| |w| - 1 | <= 1e-12``.
"""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

from adobe_bsdf import _params

__all__ = [
    "alpha_pairs",
    "direction_pairs",
    "directions",
    "iors",
    "roughness",
    "uniform_triples",
]

HEMISPHERES = ("sphere", "upper", "lower")
PAIR_KINDS = ("any", "reflection", "transmission")
#: the largest double below 1
JUST_BELOW_ONE = float(np.nextafter(1.0, 0.0))
#: the named refractive indices every IOR property should meet
SPECIAL_IORS = (1.0, 1.0 + 1e-6, 1.0 - 1e-6, 1.01, 1.0 / 1.01, 1.5, 1.0 / 1.5, 2.4, 1.0 / 2.4, 3.0)


def _unit(x: float, y: float, z: float) -> np.ndarray:
    w = np.array([x, y, z], dtype=np.float64)
    return w / np.linalg.norm(w)


def _direction(abs_cos: float, phi: float, sign: float) -> np.ndarray:
    sin_theta = np.sqrt((1.0 - abs_cos) * (1.0 + abs_cos))
    return _unit(sin_theta * np.cos(phi), sin_theta * np.sin(phi), sign * abs_cos)


def _abs_cos(min_abs_cos: float, allow_horizon: bool) -> st.SearchStrategy[float]:
    """|cos theta|: exactly 1, exactly ``min_abs_cos``, log-uniform grazing, uniform."""
    grazing = st.floats(np.log10(min_abs_cos), max(np.log10(min_abs_cos), -2.0))
    options = [
        st.just(1.0),
        st.just(min_abs_cos),
        grazing.map(lambda e: max(float(10.0**e), min_abs_cos)),
        st.floats(min_abs_cos, 1.0),
    ]
    if allow_horizon:
        options.append(st.just(0.0))
    return st.one_of(options)


def directions(
    hemisphere: str = "sphere",
    *,
    min_abs_cos: float = 1e-8,
    allow_horizon: bool = False,
) -> st.SearchStrategy[np.ndarray]:
    """Unit directions ``(3,)`` in the local shading frame (normal ``+z``).

    Parameters
    ----------
    hemisphere : {"sphere", "upper", "lower"}
        Where the directions lie: anywhere, ``z > 0`` or ``z < 0``.
    min_abs_cos : float
        Smallest ``|cos theta| = |z|`` generated (grazing), in (0, 1].
    allow_horizon : bool
        Also generate ``z = 0`` exactly.

    Returns
    -------
    SearchStrategy of ndarray (3,)
        Exactly ``(0, 0, +-1)``, ``|z| = min_abs_cos``, log-uniform grazing ``|z|`` in
        ``[min_abs_cos, 1e-2]``, and ``|z|`` uniform in ``[min_abs_cos, 1]`` (uniform on the
        sphere), with the azimuth 0 or uniform.
    """
    _params.choice("hemisphere", hemisphere, HEMISPHERES)
    min_abs_cos = float(_params.real("min_abs_cos", min_abs_cos, 0.0, 1.0, lo_open=True))
    signs = {"sphere": st.sampled_from([1.0, -1.0]), "upper": st.just(1.0),
             "lower": st.just(-1.0)}[hemisphere]
    phi = st.one_of(st.just(0.0), st.floats(0.0, 2.0 * np.pi, exclude_max=True))
    return st.builds(_direction, _abs_cos(min_abs_cos, allow_horizon), phi, signs)


def _partners(wo: np.ndarray, kind: str, min_abs_cos: float, allow_horizon: bool):
    same = "upper" if wo[2] >= 0.0 else "lower"
    other = "lower" if same == "upper" else "upper"
    mirror = np.array([-wo[0], -wo[1], wo[2]])
    reflected = [directions(same, min_abs_cos=min_abs_cos, allow_horizon=allow_horizon),
                 st.just(mirror), st.just(wo.copy())]
    transmitted = [directions(other, min_abs_cos=min_abs_cos, allow_horizon=allow_horizon),
                   st.just(-wo), st.just(-mirror)]
    options = {"reflection": reflected, "transmission": transmitted,
               "any": reflected + transmitted}[kind]
    return st.tuples(st.just(wo), st.one_of(options))


def direction_pairs(
    kind: str = "any",
    *,
    side: str = "sphere",
    min_abs_cos: float = 1e-8,
    allow_horizon: bool = False,
) -> st.SearchStrategy[tuple[np.ndarray, np.ndarray]]:
    """Pairs ``(wo, wi)`` of unit directions.

    Parameters
    ----------
    kind : {"any", "reflection", "transmission"}
        ``wi`` on the same side as ``wo`` (reflection), the other side (transmission), or
        either. Besides random partners: the mirror direction and ``wo`` itself (reflection);
        ``-wo`` and the mirrored ``-wo`` (transmission).
    side : {"sphere", "upper", "lower"}
        Where ``wo`` lies.
    min_abs_cos, allow_horizon
        As in ``directions``.

    Returns
    -------
    SearchStrategy of (ndarray (3,), ndarray (3,))
    """
    _params.choice("kind", kind, PAIR_KINDS)
    outgoing = directions(side, min_abs_cos=min_abs_cos, allow_horizon=allow_horizon)
    return outgoing.flatmap(lambda wo: _partners(wo, kind, min_abs_cos, allow_horizon))


def roughness(min_value: float = 0.0, max_value: float = 1.0) -> st.SearchStrategy[float]:
    """Roughness or GGX alpha: exactly 0 and 1, tiny values (1e-6, log-uniform to 1e-2), random.

    Parameters
    ----------
    min_value, max_value : float
        Range of the values, ``0 <= min_value <= max_value <= 1``; special values outside it
        are left out.

    Returns
    -------
    SearchStrategy of float
    """
    min_value = float(_params.real("min_value", min_value, 0.0, 1.0))
    max_value = float(_params.real("max_value", max_value, min_value, 1.0))
    options = [st.just(v) for v in (0.0, 1e-6, 1.0) if min_value <= v <= max_value]
    options.append(st.floats(min_value, max_value))
    lo, hi = max(min_value, 1e-6), min(max_value, 1e-2)
    if lo <= hi:
        options.append(st.floats(np.log10(lo), np.log10(hi)).map(
            lambda e: float(np.clip(10.0**e, lo, hi))))
    return st.one_of(options)


def alpha_pairs(min_value: float = 0.0,
                max_value: float = 1.0) -> st.SearchStrategy[tuple[float, float]]:
    """Anisotropic roughness ``(alpha_x, alpha_y)``: equal pairs and independent pairs.

    Parameters
    ----------
    min_value, max_value : float
        As in ``roughness``.

    Returns
    -------
    SearchStrategy of (float, float)
    """
    alpha = roughness(min_value, max_value)
    return st.one_of(alpha.map(lambda a: (a, a)), st.tuples(alpha, alpha))


def iors(min_value: float = 1.0 / 3.0, max_value: float = 3.0) -> st.SearchStrategy[float]:
    """Relative refractive index ``eta = n_below / n_above``.

    Generates ``SPECIAL_IORS`` (1, 1 +- 1e-6, 1.01, 1/1.01, 1.5, 1/1.5, 2.4, 1/2.4, 3),
    ``1 +- 10**e`` for ``e`` in [-8, -1], and uniform values, all inside the range.

    Parameters
    ----------
    min_value, max_value : float
        Range of the values, ``0 < min_value <= max_value``.

    Returns
    -------
    SearchStrategy of float
    """
    min_value = float(_params.real("min_value", min_value, 0.0, np.inf, lo_open=True))
    max_value = float(_params.real("max_value", max_value, min_value, np.inf))
    inside = [v for v in SPECIAL_IORS if min_value <= v <= max_value]
    near_one = st.tuples(st.floats(-8.0, -1.0), st.sampled_from([1.0, -1.0])).map(
        lambda p: 1.0 + p[1] * 10.0 ** p[0])
    options = [st.floats(min_value, max_value),
               near_one.filter(lambda v: min_value <= v <= max_value)]
    if inside:
        options.insert(0, st.sampled_from(inside))
    return st.one_of(options)


def uniform_triples() -> st.SearchStrategy[np.ndarray]:
    """Uniforms ``u`` of shape (3,) in [0, 1), each component 0, 1/2, just below 1, or random.

    Returns
    -------
    SearchStrategy of ndarray (3,)
    """
    component = st.one_of(st.sampled_from([0.0, 0.5, JUST_BELOW_ONE, 1.0 - 1e-9]),
                          st.floats(0.0, 1.0, exclude_max=True))
    return st.tuples(component, component, component).map(
        lambda u: np.array(u, dtype=np.float64))
