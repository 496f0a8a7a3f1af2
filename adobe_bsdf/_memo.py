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
"""

from __future__ import annotations

import threading
from contextlib import contextmanager

import numpy as np

__all__ = ["scope", "once"]

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
    value = compute(w)
    for part in value if isinstance(value, tuple) else (value,):
        if isinstance(part, np.ndarray):
            part.flags.writeable = False
    table[key] = (w, owner, value)
    return value
