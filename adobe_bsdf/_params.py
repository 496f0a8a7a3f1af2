"""Validation of parameters and directions (the bad-input policy of ``docs/conventions.md``).

Every check raises ``ValueError`` naming the parameter, the offending value and the allowed
range. Nothing is clamped.

Parameters are validated once, where the user hands them in: a public constructor checks
its arguments and calls ``_init``, which only stores them and derives what it needs; code
that assembles objects from values it has validated already calls ``cls._new(...)``
(``Validated``), which runs ``_init`` alone.
"""

from __future__ import annotations

import numpy as np

#: tolerance on |w| - 1 for direction arguments
UNIT_TOLERANCE = 1e-6


class Validated:
    """Mixin of the classes whose ``__init__`` validates and then calls ``_init``."""

    def _init(self, *args, **kwargs):  # pragma: no cover - abstract
        raise NotImplementedError

    @classmethod
    def _new(cls, *args, **kwargs):
        """An instance of already-validated arguments: ``_init`` without the checks of
        ``__init__`` (internal assembly)."""
        obj = object.__new__(cls)
        obj._init(*args, **kwargs)
        return obj


def _first_bad(value: np.ndarray, bad: np.ndarray):
    return value[bad].flat[0].item() if np.any(bad) else None


def real(name: str, value, lo: float = -np.inf, hi: float = np.inf, *,
         lo_open: bool = False, hi_open: bool = False) -> np.ndarray:
    """``value`` as a float64 array, checked to be finite and inside [lo, hi] (or open ends)."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} = {value!r} is not a real number or array of them") from exc
    below = arr <= lo if lo_open else arr < lo
    above = arr >= hi if hi_open else arr > hi
    bad = ~np.isfinite(arr) | below | above
    if np.any(bad):
        left = "(" if lo_open else "["
        right = ")" if hi_open else "]"
        raise ValueError(f"{name} = {_first_bad(arr, bad)!r} is outside the allowed range "
                         f"{left}{lo}, {hi}{right}")
    return arr


def integer(name: str, value, lo: int) -> int:
    """An integer count in [lo, inf) (booleans are rejected)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < lo:
        raise ValueError(f"{name} = {value!r} must be an integer in [{lo}, inf)")
    return int(value)


def color(name: str, value, lo: float = -np.inf, hi: float = np.inf) -> np.ndarray:
    """A colour parameter: a scalar or an array with a trailing axis of 3, as ``(..., 3)``."""
    arr = real(name, value, lo, hi)
    if arr.ndim and arr.shape[-1] not in (1, 3):
        raise ValueError(f"{name} has shape {arr.shape}; a colour is a scalar or has a "
                         "trailing axis of 3")
    return as_color(arr)


def as_color(arr: np.ndarray) -> np.ndarray:
    """A validated float64 scalar or array with a trailing axis of 1 or 3 as ``(..., 3)``."""
    if arr.ndim == 0 or arr.shape[-1] == 1:
        return np.repeat(arr[..., None] if arr.ndim == 0 else arr, 3, axis=-1)
    return arr


def direction(name: str, value) -> np.ndarray:
    """A batch of unit direction vectors ``(..., 3)``, float64."""
    arr = direction_shape(name, value)
    check_unit(name, arr)
    return arr


def direction_shape(name: str, value) -> np.ndarray:
    """``value`` as float64 with a trailing axis of 3 (the lengths are not checked)."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} = {value!r} is not an array of 3-vectors") from exc
    if arr.ndim == 0 or arr.shape[-1] != 3:
        raise ValueError(f"{name} has shape {arr.shape}; directions need a trailing axis of 3")
    return arr


#: |w|^2 bounds equivalent to ||w| - 1| <= UNIT_TOLERANCE
_NORM2_LO, _NORM2_HI = (1.0 - UNIT_TOLERANCE) ** 2, (1.0 + UNIT_TOLERANCE) ** 2


_ONES3 = np.ones(3)


def check_unit(name: str, arr: np.ndarray) -> None:
    """Raise unless every vector of ``arr`` ``(..., 3)`` is finite with unit length."""
    norm2 = np.square(arr) @ _ONES3  # one pass over (..., 3) and a BLAS reduction
    # min/max are NaN if any element is: the comparisons then fail as they should
    if norm2.size and norm2.min() >= _NORM2_LO and norm2.max() <= _NORM2_HI:
        return
    bad = ~((norm2 >= _NORM2_LO) & (norm2 <= _NORM2_HI))
    if np.any(bad):
        raise ValueError(f"{name} = {arr[bad][0]!r} is not a unit vector "
                         f"(allowed: |{name}| = 1 within {UNIT_TOLERANCE})")


def uniforms(name: str, value, n: int) -> np.ndarray:
    """Uniform random numbers in [0, 1) with a trailing axis of ``n``."""
    arr = uniforms_shape(name, value, n)
    check_uniform(name, arr)
    return arr


def uniforms_shape(name: str, value, n: int) -> np.ndarray:
    """``value`` as float64 with a trailing axis of ``n`` (the range is not checked)."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} = {value!r} is not a real number or array of them") from exc
    if arr.ndim == 0 or arr.shape[-1] != n:
        raise ValueError(f"{name} has shape {arr.shape}; it needs a trailing axis of {n}")
    return arr


def check_uniform(name: str, arr: np.ndarray) -> None:
    """Raise unless every element of ``arr`` lies in [0, 1)."""
    if arr.size and arr.min() >= 0.0 and arr.max() < 1.0:
        return
    real(name, arr, 0.0, 1.0, hi_open=True)


def choice(name: str, value, allowed: tuple) -> str:
    """One of a fixed set of option strings."""
    if value not in allowed:
        raise ValueError(f"{name} = {value!r} is not one of {allowed}")
    return value
