"""Where the node blocks of a bake run: in this process, a local process pool, or a Dask
cluster (``dask.distributed``, an optional dependency imported on demand).

Public API
----------
``open_executor(workers, scheduler, dask_workers)``  a context manager giving an ``Executor``.
``Executor``    ``map(fn, tasks)`` yields ``(index, result)`` as tasks finish, in any order.
``BakeError``   an executor that cannot start (no Dask, unreachable scheduler).
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

__all__ = ["BakeError", "Executor", "open_executor"]


class BakeError(RuntimeError):
    """A bake that cannot start: Dask is missing, or its scheduler cannot be reached."""


class Executor:
    """Where node blocks run. ``map(fn, tasks)`` yields ``(index, fn(tasks[index]))`` as the
    tasks finish, in any order; an abandoned ``map`` cancels the tasks not yet finished.

    Attributes
    ----------
    kind : str
        ``"in process"``, ``"process pool"`` or ``"dask"`` (recorded in the metadata).
    workers : int
        Number of processes computing blocks.
    """

    kind = "in process"

    def __init__(self):
        self.workers = 1

    def map(self, fn, tasks):
        for index, task in enumerate(tasks):
            yield index, fn(task)

    def close(self) -> None:
        """Release the processes or the cluster connection."""

    def __str__(self) -> str:
        return f"{self.kind} ({self.workers} worker{'' if self.workers == 1 else 's'})"


class _ProcessPool(Executor):
    kind = "process pool"

    def __init__(self, workers: int):
        self.workers = workers
        self.pool = ProcessPoolExecutor(max_workers=workers, initializer=_worker_start,
                                        initargs=(os.getpid(),))

    def map(self, fn, tasks):
        pending = {self.pool.submit(fn, task): index for index, task in enumerate(tasks)}
        try:
            while pending:
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for future in done:
                    yield pending.pop(future), future.result()
        finally:
            for future in pending:
                future.cancel()

    def close(self) -> None:
        self.pool.shutdown(wait=True, cancel_futures=True)


def _worker_start(parent: int) -> None:
    """In a pool process: leave Ctrl-C to the ``parent`` process (which keeps the finished
    blocks and stops the pool), and exit if the parent is killed."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    threading.Thread(target=_exit_with, args=(parent,), daemon=True).start()


def _exit_with(parent: int) -> None:
    while os.getppid() == parent:
        time.sleep(1.0)
    os._exit(1)


@contextlib.contextmanager
def _interrupts_ignored():
    """Ignore Ctrl-C while starting processes that should leave it to this one (only the
    main thread can change signal handlers; elsewhere, do nothing)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def _distributed():
    """``dask.distributed``, imported on demand (an optional dependency)."""
    try:
        import distributed
    except ImportError as exc:
        raise BakeError('baking on Dask needs dask.distributed: pip install -e ".[dask]"'
                        ) from exc
    return distributed


class _Dask(Executor):
    kind = "dask"

    def __init__(self, scheduler: str | None = None, n_workers: int | None = None):
        distributed = _distributed()
        self.cluster = self.client = None
        if scheduler is None:
            with _interrupts_ignored():  # inherited by the worker processes
                self.cluster = distributed.LocalCluster(
                    n_workers=n_workers, threads_per_worker=1, processes=True,
                    host="127.0.0.1", dashboard_address=":0")
            scheduler = self.cluster.scheduler_address
        try:
            self.client = distributed.Client(scheduler)
        except OSError as exc:
            self.close()
            raise BakeError(f"cannot reach the Dask scheduler at {scheduler}: {exc}") from exc
        self.workers = len(self.client.scheduler_info()["workers"])
        self.address = scheduler

    def map(self, fn, tasks):
        distributed = _distributed()
        futures = self.client.map(fn, tasks, pure=False)
        index = {future.key: i for i, future in enumerate(futures)}
        try:
            for future, result in distributed.as_completed(futures, with_results=True):
                yield index[future.key], result
        finally:
            self.client.cancel(futures)

    def close(self) -> None:
        for part in (self.client, self.cluster):
            if part is not None:
                part.close()

    def __str__(self) -> str:
        return f"{super().__str__()} at {self.address}"


@contextlib.contextmanager
def open_executor(workers: int | None = None, scheduler: str | None = None,
                  dask_workers: int | None = None):
    """Context manager giving the ``Executor`` of node blocks, closed on exit.

    Parameters
    ----------
    workers : int, optional
        Local worker processes (default ``os.cpu_count()``); 1 computes in this process.
    scheduler : str, optional
        Address of a running Dask scheduler to connect to (its workers need
        ``adobe_bsdf`` installed).
    dask_workers : int, optional
        Start a local Dask cluster of this many single-threaded worker processes.
    """
    if scheduler is not None and dask_workers is not None:
        raise ValueError("give a Dask scheduler or a number of Dask workers, not both")
    if scheduler is not None or dask_workers is not None:
        ex = _Dask(scheduler, dask_workers)
    else:
        workers = workers or os.cpu_count() or 1
        ex = Executor() if workers == 1 else _ProcessPool(workers)
    try:
        yield ex
    finally:
        ex.close()
