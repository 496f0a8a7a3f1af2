"""Execution options of batched evaluation (chunk size and threads) and the accuracy of
anisotropic dielectric energy.

Public API
----------
``get_options()``                         the current ``Options``.
``set_options(threads=..., chunk_size=..., anisotropic_energy=...)``  change them for the
                                          whole process.
``options(threads=..., chunk_size=..., anisotropic_energy=...)``  context manager: change
                                          them inside a ``with`` block.
``ANISOTROPIC_ENERGY``                    the values of ``anisotropic_energy``.

Large batches of ``eval``, ``pdf``, ``eval_pdf`` and ``sample`` are cut into chunks of
``chunk_size`` elements, small enough that a chunk's temporaries stay in the CPU cache, and
the chunks run on a pool of ``threads`` threads (NumPy releases the GIL inside its loops).
Every element is computed by the same operations whatever the chunk or thread it falls in,
so the results are bit-identical for any ``threads`` (docs/performance.md).

The default number of threads is the ``ADOBE_BSDF_THREADS`` environment variable, else the
number of CPUs this process may run on.

``anisotropic_energy`` is read when a lobe is built and kept by it: "table" (default) looks
up an anisotropic GGX dielectric's single-scattering energy in the isotropic tables at
sqrt(alpha_x alpha_y); "exact" computes the lobe's own slice of it
(``tables.dielectric_slices``: seconds per distinct (alpha_x, alpha_y, eta), then as fast),
which makes the Kulla-Conty terms, a coat's albedo and the ASM's lobe integral exact for
anisotropic roughness (docs/tables.md). Conductors are exact either way.
"""

from __future__ import annotations

import contextlib
import os
import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace

from adobe_bsdf import _params

__all__ = ["Options", "get_options", "set_options", "options", "map_chunks",
           "ANISOTROPIC_ENERGY"]

#: values of ``Options.anisotropic_energy``
ANISOTROPIC_ENERGY = ("table", "exact")

#: elements per chunk: each NumPy call of a kernel then runs long enough (tens of
#: microseconds) that the hand-over of the interpreter lock between threads costs little, and
#: a chunk's temporaries still fit the L2/L3 caches (the sweep in docs/performance.md)
DEFAULT_CHUNK_SIZE = 65536


def _default_threads() -> int:
    env = os.environ.get("ADOBE_BSDF_THREADS")
    if env:
        try:
            return _params.integer("ADOBE_BSDF_THREADS", int(env), 1)
        except ValueError as exc:
            raise ValueError(f"ADOBE_BSDF_THREADS = {env!r} must be an integer in [1, inf)") \
                from exc
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        return os.cpu_count() or 1


@dataclass(frozen=True)
class Options:
    """Execution options.

    Attributes
    ----------
    threads : int >= 1
        Threads evaluating chunks of one call (1: the calling thread only).
    chunk_size : int >= 1
        Elements per chunk.
    anisotropic_energy : {"table", "exact"}
        How lobes built now find an anisotropic dielectric's energy (module docstring).
    """

    threads: int
    chunk_size: int
    anisotropic_energy: str = "table"


_state = threading.local()
_global = Options(threads=_default_threads(), chunk_size=DEFAULT_CHUNK_SIZE)
_pools: dict[int, ThreadPoolExecutor] = {}
_pool_lock = threading.Lock()


def get_options() -> Options:
    """The options in force in this thread."""
    return getattr(_state, "options", None) or _global


def _validated(base: Options, threads, chunk_size, anisotropic_energy=None) -> Options:
    if threads is not None:
        base = replace(base, threads=_params.integer("threads", threads, 1))
    if chunk_size is not None:
        base = replace(base, chunk_size=_params.integer("chunk_size", chunk_size, 1))
    if anisotropic_energy is not None:
        if anisotropic_energy not in ANISOTROPIC_ENERGY:
            raise ValueError(f"anisotropic_energy = {anisotropic_energy!r}; allowed: "
                             f"{', '.join(repr(v) for v in ANISOTROPIC_ENERGY)}")
        base = replace(base, anisotropic_energy=anisotropic_energy)
    return base


def set_options(threads: int | None = None, chunk_size: int | None = None,
                anisotropic_energy: str | None = None) -> Options:
    """Set the process-wide options (``None`` leaves one unchanged); returns the new ones."""
    global _global
    _global = _validated(_global, threads, chunk_size, anisotropic_energy)
    return _global


@contextlib.contextmanager
def options(threads: int | None = None, chunk_size: int | None = None,
            anisotropic_energy: str | None = None):
    """Use other options inside a ``with`` block (in this thread only)."""
    previous = getattr(_state, "options", None)
    _state.options = _validated(get_options(), threads, chunk_size, anisotropic_energy)
    try:
        yield _state.options
    finally:
        _state.options = previous


def _pool(threads: int) -> ThreadPoolExecutor:
    with _pool_lock:
        if threads not in _pools:
            _pools[threads] = ThreadPoolExecutor(threads, thread_name_prefix="adobe_bsdf")
        return _pools[threads]


def map_chunks(fn, n: int) -> None:
    """Call ``fn(start, stop)`` for consecutive chunks covering ``range(n)``.

    The chunks are the same whatever the number of threads. With ``threads`` = T > 1 (and
    more than one chunk), worker j of T takes chunks j, j + T, j + 2T, ...: the calling
    thread is worker 0, the others run on a shared pool (one task per worker, not per chunk:
    every hand-over between threads costs a wake-up). The first exception is re-raised once
    every worker has stopped.
    """
    opts = get_options()
    bounds = [(s, min(s + opts.chunk_size, n)) for s in range(0, n, opts.chunk_size)]
    workers = min(opts.threads, len(bounds))
    if workers == 1:
        for start, stop in bounds:
            fn(start, stop)
        return

    def work(j):
        for start, stop in bounds[j::workers]:
            fn(start, stop)

    futures = [_pool(workers - 1).submit(work, j) for j in range(1, workers)]
    error = None
    try:
        work(0)
    except BaseException as exc:  # re-raised after the other workers stop
        error = exc
    for future in futures:
        try:
            future.result()
        except BaseException as exc:
            error = error or exc
    if error is not None:
        raise error
