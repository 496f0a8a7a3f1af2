"""Keep freed memory in the process for reuse (glibc's ``mallopt``): the mechanism behind
``config`` ``retained_memory``.

A batched call allocates and frees its temporaries chunk after chunk. With glibc's default,
dynamic thresholds, the top of a heap is given back to the system as soon as more than twice
the largest recent block is free, and the next chunk gets fresh pages from the kernel: a page
fault for every 4 KiB touched, often more time than the arithmetic. Fixing both thresholds,
``M_MMAP_THRESHOLD`` (blocks below it come from the heaps) and ``M_TRIM_THRESHOLD`` (free
memory kept at the top of a heap), lets the chunks reuse the same pages.

Elsewhere than glibc (macOS, musl, Windows) nothing is changed.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools
import platform

__all__ = ["supported", "retain", "MMAP_THRESHOLD_MAX", "GLIBC_DEFAULT"]

#: mallopt parameters (glibc's malloc.h)
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
#: the largest M_MMAP_THRESHOLD glibc accepts on 64-bit systems (HEAP_MAX_SIZE / 2)
MMAP_THRESHOLD_MAX = 32 * 2**20
#: glibc's initial thresholds (128 KiB), restored by ``retain(0)``
GLIBC_DEFAULT = 128 * 2**10


@functools.cache
def _mallopt():
    if platform.libc_ver()[0] != "glibc":
        return None
    try:
        return ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6").mallopt
    except (OSError, AttributeError):  # pragma: no cover - a glibc without mallopt
        return None


def supported() -> bool:
    """Whether this process's C library is glibc (whose allocator ``retain`` sets)."""
    return _mallopt() is not None


def retain(nbytes: int) -> bool:
    """Keep up to ``nbytes`` of freed memory at the top of each heap and serve blocks below
    min(nbytes, ``MMAP_THRESHOLD_MAX``) from the heaps; 0 restores glibc's initial values
    (``GLIBC_DEFAULT``; its dynamic adjustment stays off once set). Returns whether the
    allocator was changed (False off glibc)."""
    mallopt = _mallopt()
    if mallopt is None:
        return False
    trim, mmap = (nbytes, min(nbytes, MMAP_THRESHOLD_MAX)) if nbytes else (GLIBC_DEFAULT,) * 2
    return bool(mallopt(_M_MMAP_THRESHOLD, mmap)) and bool(mallopt(_M_TRIM_THRESHOLD, trim))
