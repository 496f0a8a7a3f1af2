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

Which parameter a bad batch shape comes from (``culprits``): a public constructor of a
``Validated`` class records the name and shape of every array it validates (``real``,
``color``, ``vectors``; nothing else is kept, and nothing at all outside a constructor), so
that a call whose directions do not broadcast with the parameters can name them
(``broadcast_error``) — the work is done only when building that message.
"""

from __future__ import annotations

import decimal
import functools
import inspect
import numbers
import threading

import numpy as np

#: tolerance on |w| - 1 for direction arguments
UNIT_TOLERANCE = 1e-6


class Validated:
    """Mixin of the classes whose ``__init__`` validates and then calls ``_init``.

    Each subclass's ``__init__`` runs in a recording scope (``_constructing``): the arrays its
    parameters are validated as (``real``, ``color``, ``vectors``) are kept by name and shape
    on the instance, for ``culprits`` to name in an error message.
    """

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        init = cls.__dict__.get("__init__")
        if init is not None and not hasattr(init, "_recording"):
            cls.__init__ = _recording(init)

    def _init(self, *args, **kwargs):  # pragma: no cover - abstract
        raise NotImplementedError

    @classmethod
    def _new(cls, *args, **kwargs):
        """An instance of already-validated arguments: ``_init`` without the checks of
        ``__init__`` (internal assembly)."""
        obj = object.__new__(cls)
        if getattr(_LOCAL, "frames", None):  # inside a constructor: keep what _init records
            _constructing(obj, obj._init, args, kwargs)
        else:
            obj._init(*args, **kwargs)
        return obj


# -- the parameters a constructor validated, by name (for messages only) --------------------
#: the attribute under which an instance keeps ``(own, inner)``: the ``(name, shape, batch
#: shape)`` of each non-scalar array its own constructor validated, and of those validated
#: by the constructors it called (its inner objects'), in order
GIVEN = "_given_shapes"
_LOCAL = threading.local()


class _Frame:
    """The records of one constructor in progress."""

    __slots__ = ("obj", "own", "inner")

    def __init__(self, obj):
        self.obj, self.own, self.inner = obj, [], []


def _record(name: str, shape: tuple, batch: tuple, amend: bool = False) -> None:
    """Note that the constructor in progress (if any) validated ``name`` of ``shape``, whose
    batch shape (the axes that broadcast against the directions) is ``batch``; ``amend``:
    in place of the last note, if it is of ``name`` (``color`` after its ``real``)."""
    frames = getattr(_LOCAL, "frames", None)
    if frames:
        own = frames[-1].own
        if amend and own and own[-1][0] == name:
            own[-1] = (name, shape, batch)
        else:
            own.append((name, shape, batch))


def _recording(init):
    """``init`` run in a recording scope (``Validated.__init_subclass__``)."""
    @functools.wraps(init)
    def __init__(self, *args, **kwargs):
        _constructing(self, functools.partial(init, self), args, kwargs)

    __init__._recording = True
    return __init__


def _named(records: list) -> list:
    """``records`` with a name that occurs more than once numbered by occurrence (the items
    of a list validated one by one, e.g. ``weights[1]``), the scalar ones dropped."""
    if not records:
        return []
    counts: dict = {}
    for name, _, _ in records:
        counts[name] = counts.get(name, 0) + 1
    seen: dict = {}
    out = []
    for name, shape, batch in records:
        k = seen[name] = seen.get(name, -1) + 1
        if batch:
            out.append((f"{name}[{k}]" if counts[name] > 1 else name, shape, batch))
    return out


def records(init):
    """Decorator: the constructor ``init(self, ...)`` (e.g. a dataclass's ``__post_init__``)
    of a class that is not ``Validated`` runs in a recording scope of its own, as those of
    ``Validated`` classes do (its parameters are then its own, not its caller's)."""
    return _recording(init)


def _constructing(obj, build, args, kwargs) -> None:
    """``build(*args, **kwargs)`` (the construction of ``obj``) in a recording scope; then
    the records are kept on ``obj`` and passed on to the enclosing constructor's scope, whose
    inner records they become. A constructor called by another for the same object
    (``super().__init__``) gets a scope of its own whose records are the caller's inner ones:
    the subclass validated what the user gave, the base class what the subclass derived."""
    frames = getattr(_LOCAL, "frames", None)
    if frames is None:
        frames = _LOCAL.frames = []
    nested = bool(frames) and frames[-1].obj is obj
    frame = _Frame(obj)
    frames.append(frame)
    try:
        build(*args, **kwargs)
    finally:
        frames.pop()
    own, inner = _named(frame.own), frame.inner
    if (own or inner) and not nested:
        try:
            obj.__dict__[GIVEN] = (tuple(own), tuple(inner))
        except AttributeError:  # pragma: no cover - no instance dictionary
            pass
    if frames:
        frames[-1].inner.extend(own + inner)


def _children(obj):
    """``(path, child)`` of the ``Validated`` objects ``obj`` holds (in attributes, lists,
    tuples and dicts), public attributes first."""
    attrs = getattr(obj, "__dict__", None) or {}
    for name, value in sorted(attrs.items(), key=lambda item: item[0].startswith("_")):
        if name == GIVEN:
            continue
        if _holds(value):
            yield name, value
        elif isinstance(value, (list, tuple)):
            for i, v in enumerate(value):
                if _holds(v):
                    yield f"{name}[{i}]", v
        elif isinstance(value, dict):
            for k, v in value.items():
                if _holds(v):
                    yield f"{name}[{k!r}]", v


def _holds(value) -> bool:
    """Whether ``value`` may hold named parameters: a ``Validated`` object, or one whose
    constructor recorded some (``records``)."""
    return isinstance(value, Validated) or GIVEN in (getattr(value, "__dict__", None) or {})


def _arguments(cls) -> set | None:
    """The argument names of ``cls``'s constructor (None: any, as it takes ``**kwargs``):
    what a constructor validated under another name it derived."""
    try:
        parameters = inspect.signature(cls.__init__).parameters.values()
    except (TypeError, ValueError):  # pragma: no cover - no signature
        return None
    if any(p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters):
        return None
    return {p.name for p in parameters}


def _fits(shape: tuple, batch: tuple | None) -> bool:
    """Whether ``shape`` broadcasts with ``batch`` (None: whether it is a scalar's)."""
    if batch is None:
        return not shape
    try:
        np.broadcast_shapes(shape, batch)
    except ValueError:
        return False
    return True


def _within(shape: tuple, params: tuple | None) -> bool:
    """Whether ``shape`` broadcasts to ``params`` (None: unknown), the combined batch shape of
    an object's parameters, as each of them does (an array of another role, such as a film's
    wavelengths, or one of a lobe left unbuilt, need not)."""
    if params is None:
        return True
    try:
        return np.broadcast_shapes(shape, params) == tuple(params)
    except ValueError:
        return False


def _own_shape(obj) -> tuple | None:
    """The combined batch shape of ``obj``'s parameters where it says (a lobe's
    ``_param_shape()``, a distribution's or Fresnel model's ``param_shape``), else None."""
    try:
        method = getattr(obj, "_param_shape", None)
        shape = method() if callable(method) else getattr(obj, "param_shape", None)
    except ValueError:  # its parameters do not broadcast together
        return None
    return None if shape is None else tuple(shape)


def _own_culprits(obj, batch: tuple | None, params: tuple | None, prefix: str) -> list:
    """The records of ``obj`` itself for ``culprits``: those its constructor validated under
    the name of one of its arguments or, if none conflicts, the others."""
    own, inner = getattr(obj, "__dict__", {}).get(GIVEN, ((), ()))
    arguments = _arguments(type(obj))
    given = [r for r in own if arguments is None or r[0].partition("[")[0] in arguments]
    derived = [r for r in own if r not in given] + list(inner)
    for records in (given, derived):
        found, names = [], set()
        for n, s, b in records:
            # one per name: the first validated
            if n not in names and not _fits(b, batch) and _within(b, params):
                names.add(n)
                found.append((prefix + n, s, b))
        if found:
            return found
    return []


def culprits(obj, batch: tuple | None, params: tuple | None = None, _prefix: str = "",
             _seen: set | None = None) -> list:
    """``[(name, shape, batch shape), ...]`` of the parameters of ``obj`` whose batch shape
    does not broadcast with ``batch`` (None: every non-scalar one), named as the user gave
    them to the outermost object that has such parameters: first those ``obj``'s own
    constructor validated under the name of one of its arguments, then the others it
    validated and those of the constructors it called, then, recursively, those of the
    objects it holds (named by their path, e.g. ``components[0].alpha_x``). Only arrays whose
    shape broadcasts to the combined shape of their object's parameters count (``params``
    for ``obj``, where known; else what the object says, ``_own_shape``). Empty if none is
    known (objects assembled internally keep no names). Only error messages call this."""
    seen = set() if _seen is None else _seen
    if id(obj) in seen:
        return []
    seen.add(id(obj))
    found = _own_culprits(obj, batch, _own_shape(obj) if params is None else params, _prefix)
    if found:
        return found
    for path, child in _children(obj):
        found += culprits(child, batch, None, f"{_prefix}{path}.", seen)
    return found


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
    _record(name, arr.shape, arr.shape)
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
    _record(name, arr.shape, arr.shape[:-1], amend=True)
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
    _record(name, arr.shape, arr.shape[:-1])
    return arr


def vectors(name: str, value) -> np.ndarray:
    """``value`` as float64 of shape ``(..., 3)`` (any 3-vectors: nothing else is checked)."""
    arr = as_float(name, value, "an array of 3-vectors")
    if arr.ndim == 0 or arr.shape[-1] != 3:
        raise ValueError(f"{name} has shape {arr.shape}; allowed: shape (..., 3) (3-vectors)")
    _record(name, arr.shape, arr.shape[:-1])
    return arr


def _and(items: list) -> str:
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


def _batches(named, trailing) -> list[tuple]:
    cut = [trailing] * len(named) if isinstance(trailing, int) else list(trailing)
    return [a.shape[:a.ndim - k] for (_, a), k in zip(named, cut, strict=True)]


def batch_shape(named, params: tuple | None = None, params_name: str = "the parameters",
                trailing: int | list = 1, owner=None) -> tuple:
    """The broadcast batch shape of ``named`` ``[(name, array), ...]`` (each without its last
    ``trailing`` axes: one count, or one per array) and of ``params`` (a parameter batch
    shape; None: unknown); where they do not broadcast, ``ValueError`` naming every argument
    with its shape, e.g. "wo has shape (5, 3) and wi has shape (4, 3): their batch shapes
    (5,) and (4,) do not broadcast", and the parameters of ``owner`` (the object whose
    parameters ``params`` are, ``broadcast_error``) that conflict with them."""
    try:
        return np.broadcast_shapes(*_batches(named, trailing),
                                   *(() if params is None else (params,)))
    except ValueError:
        pass
    raise broadcast_error(named, params, params_name, trailing, owner) from None


def _parameter_text(name: str, shape: tuple, batch: tuple) -> str:
    """"name (shape S)", with the batch shape where it differs (a colour's)."""
    extra = "" if shape == batch else f", batch shape {batch}"
    return f"{name} (shape {shape}{extra})"


def _owner_parameters(owner, found: list) -> str:
    """"the Owner's parameter(s) a (shape ...) and b (shape ...)"."""
    noun = "parameter" if len(found) == 1 else "parameters"
    return (f"the {type(owner).__name__}'s {noun} "
            f"{_and([_parameter_text(*f) for f in found])}")


def broadcast_error(named, params: tuple | None = None, params_name: str = "the parameters",
                    trailing: int | list = 1, owner=None) -> ValueError:
    """The ``ValueError`` of ``batch_shape`` for arguments that do not broadcast (naming those
    with a batch: a single element broadcasts with anything). Where the arguments broadcast
    together but not with ``params``, the message names the parameters of ``owner`` (a
    ``Validated`` object, e.g. the lobe or material called) whose shapes conflict with the
    arguments' batch shape (``culprits``), e.g. "wo has shape (3, 3) and wi has shape
    (3, 3): their batch shape (3,) does not broadcast with the AdobeStandardMaterial's
    parameter roughness (shape (4,))"; else ``params_name`` and ``params``."""
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
    found = [] if owner is None else culprits(owner, batch, params)
    if found:
        return ValueError(f"{given}: {whose} {batch} does not broadcast with "
                          f"{_owner_parameters(owner, found)}")
    return ValueError(f"{given}: {whose} {batch} does not broadcast with {params_name} "
                      f"(shape {params})")


def parameters_error(owner) -> ValueError | None:
    """The ``ValueError`` naming the parameters of ``owner`` whose batch shapes do not
    broadcast together (where combining them failed: ``owner``'s own and those of the
    objects it holds, e.g. a ``Sum``'s weights and components), or None if none is known."""
    seen = {id(owner)}
    found = _own_culprits(owner, None, None, "")
    for path, child in _children(owner):
        found += culprits(child, None, None, f"{path}.", seen)
    found = [f for f in found if any(not _fits(f[2], g[2]) for g in found)]
    if len(found) < 2:
        return None
    return ValueError(f"{_owner_parameters(owner, found)} do not broadcast together")


#: |w|^2 bounds equivalent to ||w| - 1| <= UNIT_TOLERANCE
_NORM2_LO, _NORM2_HI = (1.0 - UNIT_TOLERANCE) ** 2, (1.0 + UNIT_TOLERANCE) ** 2


_ONES3 = np.ones(3)


def check_unit(name: str, arr: np.ndarray) -> None:
    """Raise unless every vector of ``arr`` ``(..., 3)`` is finite with unit length; the
    message names the first one that is not by its batch index, e.g. "wo[2] = array([nan,
    0., 1.]) is not finite"."""
    norm2 = np.square(arr) @ _ONES3  # one pass over (..., 3) and a BLAS reduction
    # min/max are NaN if any element is: the comparisons then fail as they should
    if norm2.size and norm2.min() >= _NORM2_LO and norm2.max() <= _NORM2_HI:
        return
    bad = ~((norm2 >= _NORM2_LO) & (norm2 <= _NORM2_HI))
    if np.any(bad):
        index = np.unravel_index(int(np.argmax(bad)), bad.shape)
        w = arr[index]
        at = f"{name}[{', '.join(str(int(i)) for i in index)}]" if index else name
        allowed = f"(allowed: |{name}| = 1 within {UNIT_TOLERANCE})"
        what = "is not a unit vector" if np.all(np.isfinite(w)) else "is not finite"
        raise ValueError(f"{at} = {w!r} {what} {allowed}")


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
