"""Colour arithmetic channel by channel and row selection by whole rows: ``x[..., None] * c``,
``rgb * c``, ``rgb * x[..., None]``, ``np.where(mask[..., None], a, b)`` and the gathers and
scatters of rows, bit for bit, without NumPy's broadcast over a last axis of length 3.

NumPy broadcasts ``(n, 1) * (3,)`` by calling its inner loop once per row, three elements
at a time: 5-15 times slower per element than a plain ``(n, 3) + (n, 3)``. Writing each
channel as one strided loop over n elements, ``out[..., k] = x * c[k]``, performs the same
operation on every element (the same results) at the speed of one-channel arithmetic.
Selections only copy values, so they are done on whole rows: a C-contiguous float64
``(..., 3)`` array viewed as one 24-byte item per row is copied with ``take`` and ``put``,
which move each row with one copy (``a[index]`` and ``np.where`` over a broadcast mask
work element by element). ``pick`` is ``np.where`` on float64 values as a bitwise select:
NumPy's ``where`` branches per element, 7-12 times the cost of an add where the mask is
unpredictable (a support mask of random directions, the wedge of the concentric map).
Below ``SMALL`` elements, or for shapes other than those named, the plain NumPy expression
is used.
"""

from __future__ import annotations

import numpy as np

__all__ = ["tinted", "scaled", "shifted", "weighted", "divided", "masked", "selected", "pick",
           "picks", "take_rows", "put_rows", "zero_rows", "SMALL"]

#: below this many pairs the plain broadcast is as fast (three calls cost ~1 us more)
SMALL = 2048
#: the shares of set elements of a mask between which ``pick`` selects bits: outside them
#: NumPy's branching ``where`` is faster (its branches are predicted), inside several times
#: slower (``benchmarks/pick.py`` measures the crossover)
BITWISE_SHARES = (0.15, 0.8)


def _fast(batch: np.ndarray) -> bool:
    """Whether a batch of this one-channel shape is large enough to go channel by channel."""
    return batch.ndim >= 1 and batch.size >= SMALL


def tinted(x, colour) -> np.ndarray:
    """``x[..., None] * colour`` for ``x`` (...) and ``colour`` (3,), ``(..., 3)``."""
    x, colour = np.asarray(x), np.asarray(colour)
    if not (_fast(x) and colour.shape == (3,)):
        return x[..., None] * colour
    out = np.empty(x.shape + (3,), dtype=np.result_type(x, colour))
    for k in range(3):
        np.multiply(x, colour[k], out=out[..., k])
    return out


def scaled(rgb, colour, out=None) -> np.ndarray:
    """``rgb * colour`` for ``rgb`` (..., 3) (any other last axis broadcasts) and ``colour``
    (3,); ``out`` may be ``rgb``."""
    return _per_channel(np.multiply, rgb, colour, out)


def shifted(rgb, colour, out=None) -> np.ndarray:
    """``rgb + colour``, as ``scaled``."""
    return _per_channel(np.add, rgb, colour, out)


def _per_channel(op, rgb, colour, out):
    """``op(rgb, colour)``, channel by channel where fast."""
    rgb, colour = np.asarray(rgb), np.asarray(colour)
    if not (rgb.ndim >= 2 and rgb.shape[-1] == 3 and _fast(rgb[..., 0])
            and colour.shape == (3,)):
        return op(rgb, colour, out=out)
    out = np.empty(rgb.shape, dtype=np.result_type(rgb, colour)) if out is None else out
    for k in range(3):
        op(rgb[..., k], colour[k], out=out[..., k])
    return out


def weighted(rgb, x, out=None) -> np.ndarray:
    """``rgb * x[..., None]`` for ``rgb`` (..., 3) and ``x`` of its batch shape (...);
    ``out`` may be ``rgb``."""
    return _per_row(np.multiply, rgb, x, out)


def divided(rgb, x, out=None) -> np.ndarray:
    """``rgb / x[..., None]``, as ``weighted``."""
    return _per_row(np.divide, rgb, x, out)


def _per_row(op, rgb, x, out):
    """``op(rgb, x[..., None])``, channel by channel where fast."""
    rgb, x = np.asarray(rgb), np.asarray(x)
    if not (_fast(x) and rgb.shape == x.shape + (3,)):
        return op(rgb, x[..., None], out=out)
    out = np.empty(rgb.shape, dtype=np.result_type(rgb, x)) if out is None else out
    for k in range(3):
        op(rgb[..., k], x, out=out[..., k])
    return out


def _row_view(a):
    """``a`` (..., 3) float64, C-contiguous, as a flat array of one 24-byte item per row,
    else None."""
    if (isinstance(a, np.ndarray) and a.dtype == np.float64 and a.ndim >= 1
            and a.shape[-1] == 3 and a.flags.c_contiguous):
        return a.view(_ROW).reshape(-1)
    return None


_ROW = np.dtype((np.void, 24))
_ZERO_ROW = np.zeros((), _ROW)


def masked(mask, rgb) -> np.ndarray:
    """``np.where(mask[..., None], rgb, 0.0)`` for ``mask`` (...) and ``rgb`` (..., 3) of its
    batch shape."""
    mask, rgb = np.asarray(mask), np.asarray(rgb)
    if not (_fast(mask) and rgb.shape == mask.shape + (3,) and rgb.dtype == np.float64):
        return np.where(mask[..., None], rgb, 0.0)
    out = np.array(rgb, order="C")  # a copy; rows outside set to 0
    np.put(_row_view(out), np.flatnonzero(~mask), _ZERO_ROW)
    return out


def selected(mask, a, b) -> np.ndarray:
    """``np.where(mask[..., None], a, b)`` for ``mask`` (...) and ``a``, ``b`` (..., 3) of its
    batch shape: a copy of the side that fills more rows, with the other side's rows put
    in."""
    mask, a, b = np.asarray(mask), np.asarray(a), np.asarray(b)
    shape = mask.shape + (3,)
    if not (_fast(mask) and a.shape == shape and b.shape == shape
            and a.dtype == np.float64 and b.dtype == np.float64):
        return np.where(mask[..., None], a, b)
    index = np.flatnonzero(mask)
    if 2 * index.size > mask.size:  # fewer rows from b
        mask, a, b = ~mask, b, a
        index = np.flatnonzero(mask)
    out = np.array(b, order="C")
    put_rows(out.reshape(-1, 3), index, take_rows(a.reshape(-1, 3), index))
    return out


def pick(mask, a, b) -> np.ndarray:
    """``np.where(mask, a, b)`` bit for bit, for ``a``, ``b`` float64 arrays of the shape of
    the boolean array ``mask`` or Python / NumPy float scalars: where the share of the mask
    that is set lies in ``BITWISE_SHARES`` (an unpredictable branch), the bits are selected
    without branching, b ^ ((a ^ b) & -mask), up to four times faster; otherwise NumPy's
    own (faster where the mask is nearly uniform)."""
    bits_a, bits_b = _bits(a, np.shape(mask)), _bits(b, np.shape(mask))
    ones = (None if bits_a is None or bits_b is None or (bits_a.ndim == 0 and bits_b.ndim == 0)
            else _all_ones(mask))
    if ones is None:
        return np.where(mask, a, b)
    ones &= bits_a ^ bits_b
    ones ^= bits_b
    return ones.view(np.float64)


def picks(mask, a, b) -> tuple[np.ndarray, np.ndarray]:
    """``(pick(mask, a, b), pick(mask, b, a))`` for float64 arrays ``a``, ``b`` of the shape of
    ``mask``, sharing one select: with d = (a ^ b) & -mask, b ^ d and a ^ d."""
    d = (_all_ones(mask) if all(isinstance(x, np.ndarray) and x.dtype == np.float64
                                and x.shape == np.shape(mask) for x in (a, b)) else None)
    if d is None:
        return np.where(mask, a, b), np.where(mask, b, a)
    bits_a, bits_b = a.view(np.int64), b.view(np.int64)
    d &= bits_a ^ bits_b
    return (d ^ bits_b).view(np.float64), np.bitwise_xor(d, bits_a, out=d).view(np.float64)


def _all_ones(mask):
    """-mask as int64 (all bits set where ``mask``), where a bitwise select pays: a large
    boolean array with its set share in ``BITWISE_SHARES``; else None."""
    if not (isinstance(mask, np.ndarray) and mask.dtype == np.bool_ and mask.size >= SMALL
            and BITWISE_SHARES[0] * mask.size < np.count_nonzero(mask)
            < BITWISE_SHARES[1] * mask.size):
        return None
    ones = mask.view(np.uint8).astype(np.int64)
    return np.negative(ones, out=ones)


def _bits(x, shape):
    """``x`` as int64 bits: a float64 array of ``shape`` viewed, a float scalar converted;
    None otherwise."""
    if isinstance(x, np.ndarray):
        return x.view(np.int64) if x.dtype == np.float64 and x.shape in (shape, ()) else None
    if isinstance(x, (float, np.float64)):
        return np.float64(x).view(np.int64)
    return None


def take_rows(a, index) -> np.ndarray:
    """``a[index]`` for ``a`` (n, ...) and an integer ``index`` (m,)."""
    return np.asarray(a).take(index, axis=0)


def zero_rows(out, index) -> None:
    """``out[index] = 0`` for ``out`` (n, ...) and an integer ``index`` (m,) (a (n, 3)
    float64 array by whole rows)."""
    rows = _row_view(out)
    if rows is not None and out.ndim == 2:
        np.put(rows, index, _ZERO_ROW)
    else:
        out[index] = 0


def put_rows(out, index, values) -> None:
    """``out[index] = values`` for ``out`` (n, ...) and an integer ``index`` (m,) of distinct
    rows."""
    rows, given = _row_view(out), _row_view(np.asarray(values))
    if rows is not None and given is not None and out.ndim == 2 and given.size == len(index):
        np.put(rows, index, given)
    else:
        out[index] = values
