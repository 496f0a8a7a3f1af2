"""Validation of parameters and directions (the bad-input policy of ``docs/conventions.md``).

Every check raises ``ValueError`` naming the parameter, the offending value and the allowed
range. Nothing is clamped.

Parameters are validated once, where the user hands them in: a public constructor checks
its arguments and calls ``_init``, which only stores them and derives what it needs; code
that assembles objects from values it has validated already calls ``cls._new(...)``
(``Validated``), which runs ``_init`` alone.

What counts as a real number (``real``, ``color``, ``direction_shape``, ``uniforms_shape``,
``vectors``): anything NumPy holds with a boolean, integer or floating-point dtype, and
sequences or object arrays of ``numbers.Real`` (or ``decimal.Decimal``) values. Booleans are
accepted as 0 and 1, as NumPy treats them: a boolean mask is a natural texture of a 0/1
parameter (``metallic``). Rejected, with a ``ValueError`` naming the parameter and its value:
strings and bytes (even ``"0.5"``, which ``np.asarray(value, float)`` would parse), ``None``,
complex numbers (whose imaginary part a float conversion would drop), dates and times, ragged
sequences and any other object.
"""

from __future__ import annotations

import decimal
import numbers

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


def _show(value, limit: int = 80) -> str:
    """``repr(value)``, shortened to about ``limit`` characters for messages."""
    text = repr(value)
    return text if len(text) <= limit else text[:limit - 3] + "..."


#: dtype kinds that are real numbers: boolean, signed and unsigned integer, floating point
_REAL_KINDS = frozenset("biuf")


def _is_real(x) -> bool:
    return isinstance(x, (numbers.Real, np.bool_, decimal.Decimal))


def as_float(name: str, value, what: str = "a real number or array of them") -> np.ndarray:
    """``value`` as a float64 array if it holds real numbers only (see the module docstring);
    else ``ValueError`` "``name`` = value is not ``what``"."""
    if type(value) is np.ndarray and value.dtype == np.float64:
        return value  # the fast path of validated arrays
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:  # ragged sequences, failing __array__
        raise ValueError(f"{name} = {_show(value)} is not {what}") from exc
    kind = arr.dtype.kind
    if kind == "O" and all(_is_real(x) for x in arr.flat):
        try:
            return arr.astype(np.float64)
        except (TypeError, ValueError, OverflowError) as exc:
            raise ValueError(f"{name} = {_show(value)} is not {what}") from exc
    if kind not in _REAL_KINDS:
        detail = (f"type {type(value).__name__}" if arr.ndim == 0 or kind == "O"
                  else f"dtype {arr.dtype}")
        raise ValueError(f"{name} = {_show(value)} is not {what} ({detail})")
    return arr.astype(np.float64, copy=False)


def real(name: str, value, lo: float = -np.inf, hi: float = np.inf, *,
         lo_open: bool = False, hi_open: bool = False) -> np.ndarray:
    """``value`` as a float64 array, checked to be finite and inside [lo, hi] (or open ends).

    ``value`` must hold real numbers (module docstring): strings, bytes, ``None``, complex
    numbers and other objects raise ``ValueError`` "``name`` = value is not a real number".
    """
    arr = as_float(name, value)
    below = arr <= lo if lo_open else arr < lo
    above = arr >= hi if hi_open else arr > hi
    bad = ~np.isfinite(arr) | below | above
    if np.any(bad):
        left = "(" if lo_open else "["
        right = ")" if hi_open else "]"
        raise ValueError(f"{name} = {_first_bad(arr, bad)!r} is outside the allowed range "
                         f"{left}{lo}, {hi}{right}")
    return arr


def scalar(name: str, value, lo: float = -np.inf, hi: float = np.inf, *,
           lo_open: bool = False, hi_open: bool = False) -> float:
    """``real`` of a single number, as a Python float (an array of several raises)."""
    arr = real(name, value, lo, hi, lo_open=lo_open, hi_open=hi_open)
    if arr.ndim:
        raise ValueError(f"{name} has shape {arr.shape}; allowed: a single number")
    return float(arr)


def integer(name: str, value, lo: int, hi: float = np.inf) -> int:
    """An integer count in [lo, hi] (booleans are rejected: a count is never True)."""
    if (isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer))
            or not lo <= value <= hi):
        upper = "inf)" if hi == np.inf else f"{hi}]"
        raise ValueError(f"{name} = {_show(value)} must be an integer in [{lo}, {upper}")
    return int(value)


def flag(name: str, value) -> bool:
    """A switch: ``True`` or ``False`` (also NumPy's booleans); numbers and strings raise."""
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} = {_show(value)} is not a bool (allowed: True or False)")
    return bool(value)


def seed(name: str, value):
    """A source of random numbers: ``None``, an integer seed in [0, inf) or a
    ``numpy.random.Generator``, returned unchanged (``np.random.default_rng`` takes each)."""
    if value is None or isinstance(value, np.random.Generator):
        return value
    if (isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))
            and value >= 0):
        return value
    raise ValueError(f"{name} = {_show(value)} is not a source of random numbers (allowed: "
                     "None, an integer seed in [0, inf) or a numpy.random.Generator)")


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
    arr = as_float(name, value, "an array of 3-vectors")
    if arr.ndim == 0 or arr.shape[-1] != 3:
        raise ValueError(f"{name} has shape {arr.shape}; allowed: shape (..., 3) (directions "
                         "need a trailing axis of 3)")
    return arr


def vectors(name: str, value) -> np.ndarray:
    """``value`` as float64 of shape ``(..., 3)`` (any 3-vectors: nothing else is checked)."""
    arr = as_float(name, value, "an array of 3-vectors")
    if arr.ndim == 0 or arr.shape[-1] != 3:
        raise ValueError(f"{name} has shape {arr.shape}; allowed: shape (..., 3) (3-vectors)")
    return arr


def _and(items: list) -> str:
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


def _batches(named, trailing) -> list[tuple]:
    cut = [trailing] * len(named) if isinstance(trailing, int) else list(trailing)
    return [a.shape[:a.ndim - k] for (_, a), k in zip(named, cut, strict=True)]


def batch_shape(named, params: tuple | None = None, params_name: str = "the parameters",
                trailing: int | list = 1) -> tuple:
    """The broadcast batch shape of ``named`` ``[(name, array), ...]`` (each without its last
    ``trailing`` axes: one count, or one per array) and of ``params`` (a parameter batch
    shape; None: unknown); where they do not broadcast, ``ValueError`` naming every argument
    with its shape, e.g. "wo has shape (5, 3) and wi has shape (4, 3): their batch shapes
    (5,) and (4,) do not broadcast"."""
    try:
        return np.broadcast_shapes(*_batches(named, trailing),
                                   *(() if params is None else (params,)))
    except ValueError:
        pass
    raise broadcast_error(named, params, params_name, trailing) from None


def broadcast_error(named, params: tuple | None = None, params_name: str = "the parameters",
                    trailing: int | list = 1) -> ValueError:
    """The ``ValueError`` of ``batch_shape`` for arguments that do not broadcast (naming those
    with a batch: a single element broadcasts with anything)."""
    shapes = _batches(named, trailing)
    kept = [i for i, s in enumerate(shapes) if s] or list(range(len(named)))
    named, shapes = [named[i] for i in kept], [shapes[i] for i in kept]
    given = _and([f"{n} has shape {a.shape}" for n, a in named])
    try:
        batch = np.broadcast_shapes(*shapes)
    except ValueError:
        return ValueError(f"{given}: their batch shapes {_and([str(s) for s in shapes])} do "
                          "not broadcast")
    whose = "its batch shape" if len(named) == 1 else "their batch shape"
    return ValueError(f"{given}: {whose} {batch} does not broadcast with {params_name} "
                      f"(shape {params})")


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
    arr = as_float(name, value)
    if arr.ndim == 0 or arr.shape[-1] != n:
        raise ValueError(f"{name} has shape {arr.shape}; allowed: shape (..., {n}) (a "
                         f"trailing axis of {n})")
    return arr


def check_uniform(name: str, arr: np.ndarray) -> None:
    """Raise unless every element of ``arr`` lies in [0, 1)."""
    if arr.size and arr.min() >= 0.0 and arr.max() < 1.0:
        return
    real(name, arr, 0.0, 1.0, hi_open=True)


def _same(a, b) -> bool:
    """``a == b`` where that is one truth value (an array compared elementwise is not)."""
    result = a == b
    return bool(result) if isinstance(result, (bool, np.bool_)) else False


def choice(name: str, value, allowed: tuple):
    """One of a fixed set of options (usually strings; an array is never one of them)."""
    if not any(_same(value, option) for option in allowed):
        raise ValueError(f"{name} = {_show(value)} is not one of {allowed}")
    return value
