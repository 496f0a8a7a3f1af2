"""Execution options of batched evaluation (chunk size and threads) and the accuracy of
anisotropic dielectric energy.

Public API
----------
``get_options()``                         the current ``Options``.
``set_options(threads=..., chunk_size=..., anisotropic_energy=..., retained_memory=...)``
                                          change them for the whole process.
``options(threads=..., chunk_size=..., anisotropic_energy=...)``  context manager: change
                                          them inside a ``with`` block.
``ANISOTROPIC_ENERGY``                    the values of ``anisotropic_energy``.
``RETAINED_MEMORY``                       the default ``retained_memory`` (bytes).
``progress(blocks, total, desc)``         the blocks of a long call, with a progress bar.

Large batches of ``eval``, ``pdf``, ``eval_pdf`` and ``sample`` are cut into chunks of
``chunk_size`` elements, small enough that a chunk's temporaries stay in the CPU cache, and
the chunks run on a pool of ``threads`` threads (NumPy releases the GIL inside its loops).
Every element is computed by the same operations whatever the chunk or thread it falls in,
so the results are bit-identical for any ``threads`` (docs/performance.md).

The default number of threads is the ``ADOBE_BSDF_THREADS`` environment variable, else the
number of CPUs this process may run on.

``retained_memory`` (bytes, process-wide, set at import): how much freed memory the C
allocator keeps for reuse instead of giving it back to the system (``_allocator``; glibc only,
elsewhere it changes nothing). Chunks free and re-allocate their temporaries, and without it
glibc returns them to the kernel and takes fresh, page-faulting pages for the next chunk: the
faults cost up to half of a material's ``sample`` (docs/performance.md). The default,
``RETAINED_MEMORY`` (256 MiB), or the ``ADOBE_BSDF_RETAINED_MEMORY`` environment variable; 0
leaves glibc's own dynamic thresholds untouched at import (``set_options(retained_memory=0)``
later restores glibc's initial values). The process's resident memory then does not shrink
below what it used, up to that much more.

``anisotropic_energy`` is read when a lobe is built and kept by it. It says where an
anisotropic GGX dielectric's single-scattering energy comes from, which its Kulla-Conty
terms, a coat's albedo and the ASM's lobe integral restore or divide by: "table" (default)
reads the shipped grid of slices where the library has it (``tables.dielectric_grid``,
milliseconds per distinct (alpha_x, alpha_y, eta)), else the isotropic tables at
sqrt(alpha_x alpha_y); "exact" computes the lobe's own slice (``tables.dielectric_slices``:
seconds per distinct interface, then as fast; the reference the grid is measured against);
"isotropic" reads the isotropic tables at sqrt(alpha_x alpha_y), which miss by up to 0.37
(``AnisotropicEnergyWarning``, once). Conductors are exact in every mode.
"""

from __future__ import annotations

import contextlib
import os
import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace

from adobe_bsdf import _allocator, _params

__all__ = ["Options", "get_options", "set_options", "options", "map_chunks", "progress",
           "ANISOTROPIC_ENERGY", "RETAINED_MEMORY", "PROGRESS_DELAY"]

#: values of ``Options.anisotropic_energy``
ANISOTROPIC_ENERGY = ("table", "exact", "isotropic")

#: elements per chunk: each NumPy call of a kernel then runs long enough (tens of
#: microseconds) that the hand-over of the interpreter lock between threads costs little, and
#: a chunk's temporaries still fit the L2/L3 caches (the sweep in docs/performance.md)
DEFAULT_CHUNK_SIZE = 65536
#: default ``retained_memory``: 256 MiB, more than the temporaries and outputs of a call of
#: 2·10^5 pairs on a fully loaded material
RETAINED_MEMORY = 256 * 2**20
#: the C ``int`` of mallopt bounds ``retained_memory``
_RETAINED_MAX = 2**31 - 1


def _from_env(name: str, lo: int, hi: float = float("inf")) -> int | None:
    """The integer environment variable ``name`` in [lo, hi], None if unset or empty."""
    env = os.environ.get(name)
    if not env:
        return None
    try:
        value = int(env)
    except ValueError:
        value = env  # not an integer: the range check below names it
    return _params.integer(name, value, lo, hi)


def _default_threads() -> int:
    env = _from_env("ADOBE_BSDF_THREADS", 1)
    if env is not None:
        return env
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
    anisotropic_energy : {"table", "exact", "isotropic"}
        How lobes built now find an anisotropic dielectric's energy (module docstring).
    retained_memory : int in [0, 2^31 - 1]
        Bytes of freed memory the allocator keeps for reuse (module docstring).
    """

    threads: int
    chunk_size: int
    anisotropic_energy: str = "table"
    retained_memory: int = RETAINED_MEMORY


_state = threading.local()
_retained = _from_env("ADOBE_BSDF_RETAINED_MEMORY", 0, _RETAINED_MAX)
_global = Options(threads=_default_threads(), chunk_size=DEFAULT_CHUNK_SIZE,
                  retained_memory=RETAINED_MEMORY if _retained is None else _retained)
if _global.retained_memory:
    _allocator.retain(_global.retained_memory)
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
                anisotropic_energy: str | None = None,
                retained_memory: int | None = None) -> Options:
    """Set the process-wide options (``None`` leaves one unchanged); returns the new ones.
    ``retained_memory`` is set here only (it is the allocator's, for every thread)."""
    global _global
    _global = _validated(_global, threads, chunk_size, anisotropic_energy)
    if retained_memory is not None:
        retained_memory = _params.integer("retained_memory", retained_memory, 0, _RETAINED_MAX)
        _allocator.retain(retained_memory)
        _global = replace(_global, retained_memory=retained_memory)
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


#: seconds a call runs before its progress bar appears (``progress``)
PROGRESS_DELAY = 2.0
_progress_lock = threading.Lock()
_progress_open = 0


def progress(blocks, total: int, desc: str):
    """``blocks`` (an iterable of ``total`` items), shown as a progress bar on stderr
    (tqdm) once the call has run ``PROGRESS_DELAY`` seconds: the slow, chunked calls (a
    random-walk reference's ``eval``, any Monte-Carlo albedo) say how far they are. Only
    the outermost such call shows one; the calls it makes, in any thread, show none."""
    global _progress_open
    if total <= 1:  # nothing to show: the calls inside may show theirs
        yield from blocks
        return
    with _progress_lock:
        outer = _progress_open == 0
        _progress_open += 1
    try:
        if not outer:
            yield from blocks
            return
        from tqdm import tqdm
        yield from tqdm(blocks, total=total, desc=desc, delay=PROGRESS_DELAY, leave=False,
                        unit="block")
    finally:
        with _progress_lock:
            _progress_open -= 1
