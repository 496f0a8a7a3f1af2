"""Quantities of one direction array computed once per call.

In one ``eval_pdf`` or ``sample`` of a composed material, several levels ask for the same
quantity of the same ``wo``: a ``Layer`` weighs its base by the base's sampling weight,
which the base ``Sum`` computes again for its own probabilities, and a lobe's energy term
looks up the same table at ``wo`` in both. ``once(owner, name, w, compute)`` returns
``compute(w)`` and, inside a ``scope`` (one chunk of one public call, on one thread), keeps
it for later requests with the same owner, name and the same array object ``w``; outside a
scope it just computes. The entries hold ``w`` and ``owner``, so their ids stay theirs for
the scope's life, and the values are made read-only, so a caller that would change one in
place fails instead of corrupting the next request. Nothing changes a result: a value is
the one ``compute`` gives.

``rows(w, index)`` gathers rows of ``w`` for a part of the batch (a mixture's elements that
chose one component, a lobe's support): a later ``once`` on the gathered array takes the rows
of the value already kept for ``w`` instead of computing it again (the quantities are per
row, so these are the values ``compute`` would give on the rows). Rows of gathered rows are
linked to the array first gathered from, and rows taken of a kept value to that value (the
rows of a turned ``wo`` find the quantities kept for the whole turned batch).
"""

from __future__ import annotations

import threading
from contextlib import contextmanager

import numpy as np

__all__ = ["scope", "once", "rows"]

#: below this many rows a gathered array is not linked to its source (a per-row value of a
#: small batch could not be told from a colour by its shape)
ROWS_MIN = 64

_local = threading.local()


@contextmanager
def scope():
    """Remember ``once`` values until the block ends (nested scopes start afresh)."""
    outer = getattr(_local, "table", None)
    _local.table = {}
    try:
        yield
    finally:
        _local.table = outer


def once(owner, name: str, w, compute):
    """``compute(w)``, computed once per scope for ``owner``, ``name`` and the array ``w``."""
    table = getattr(_local, "table", None)
    if table is None:
        return compute(w)
    key = (id(owner), name, id(w))
    entry = table.get(key)
    if entry is not None and entry[0] is w and entry[1] is owner:
        return entry[2]
    value = _gathered(table, owner, name, w)
    if value is None:
        value = compute(w)
    for part in value if isinstance(value, tuple) else (value,):
        if isinstance(part, np.ndarray):
            part.flags.writeable = False
    table[key] = (w, owner, value)
    return value


def rows(w, index):
    """``w[index]`` (rows of an ``(n, ...)`` array), remembered in the scope as rows of
    ``w`` so that ``once`` values kept for ``w`` serve it."""
    part = np.asarray(w).take(index, axis=0)
    table = getattr(_local, "table", None)
    if table is not None and len(w) >= ROWS_MIN:
        sources = [(w, index)]
        link = table.get(("rows", id(w)))
        if link is not None and link[0] is w:  # rows of rows: also the first array's rows
            sources += [(source, rows_of[index]) for source, rows_of in link[1]]
        table[("rows", id(part))] = (part, sources)
    return part


def _gathered(table, owner, name, w):
    """The rows of the value kept for an array ``w`` was gathered from, or None."""
    link = table.get(("rows", id(w)))
    if link is None or link[0] is not w:
        return None
    kept = [(source, index, table.get((id(owner), name, id(source))))
            for source, index in link[1]]
    kept = [(s, i, e) for s, i, e in kept if e is not None and e[0] is s and e[1] is owner]
    if not kept:
        return None
    source, index, entry = kept[0]  # the nearest array with a kept value
    n = len(source)

    def take(part):
        if isinstance(part, np.ndarray) and part.ndim >= 1 and part.shape[0] == n:
            # rows of the kept array, linked to it: what is kept for it (the turned wo of
            # a ``Rotated`` and its lobe's quantities) serves them in turn
            return rows(part, index)
        return part  # broadcast over the rows

    value = entry[2]
    return tuple(map(take, value)) if isinstance(value, tuple) else take(value)
