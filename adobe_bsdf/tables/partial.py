"""Resumable bakes: the finished node blocks of one table, kept on disk until it is saved.

Public API
----------
``PartialBake(folder, spec, coords, block)``  ``folder/manifest.json`` and one
    ``folder/block_<index>.npz`` per finished block; ``resume`` loads what verifies,
    ``store`` writes a block atomically.
``partial_folder(folder, name)``  where the ``bake`` command keeps them.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import tempfile
from pathlib import Path

import numpy as np
import scipy

from adobe_bsdf._version import __version__
from adobe_bsdf.tables.table import TableSpec

__all__ = ["PartialBake", "partial_folder"]


def _sha256(*parts) -> str:
    h = hashlib.sha256()
    for part in parts:
        h.update(part.encode() if isinstance(part, str)
                 else np.ascontiguousarray(part, dtype="<f8").tobytes())
    return h.hexdigest()


def _atomic_write(path: Path, write) -> None:
    """``write(file)`` into a temporary file beside ``path``, then rename it to ``path``: a
    kill mid-write leaves at most a stray ``*.tmp`` file, never a truncated ``path``."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


class PartialBake:
    """The finished blocks of one bake: ``folder/manifest.json`` and one
    ``folder/block_<index>.npz`` per block (values, errors and a digest tying them to the
    block's nodes and to the manifest)."""

    def __init__(self, folder, spec: TableSpec, coords, block: int):
        self.folder = Path(folder)
        declaration = spec.describe()
        self.manifest = {
            "format": 1, "table": spec.name, "description": spec.description,
            "declaration": declaration, "order": spec.order, "block": block,
            "declaration_hash": _sha256(json.dumps(declaration, sort_keys=True),
                                        spec.description),
            "n_nodes": len(coords[0]), "nodes_hash": _sha256(*coords),
            "library_version": __version__, "numpy": np.__version__,
            "scipy": scipy.__version__}
        self.key = json.dumps(self.manifest, sort_keys=True)

    def open(self) -> None:
        """Keep the blocks of a folder baked for this same manifest; discard (with a message)
        those of any other, and stray temporary files."""
        path = self.folder / "manifest.json"
        self.folder.mkdir(parents=True, exist_ok=True)
        for tmp in self.folder.glob(".*.tmp"):
            tmp.unlink()
        try:
            found = json.loads(path.read_text())
        except (OSError, ValueError):
            found = None
        if found == self.manifest:
            return
        stale = sorted(self.folder.glob("block_*.npz"))
        if stale:
            if isinstance(found, dict):
                differ = [k for k in self.manifest if found.get(k) != self.manifest[k]]
                why = f"another declaration or setup (differs in: {', '.join(differ)})"
            else:
                why = "an unknown declaration (no readable manifest.json)"
            print(f"ignoring {len(stale)} finished blocks in {self.folder}: they were baked "
                  f"for {why}; baking afresh", file=sys.stderr, flush=True)
        for block in stale:  # before the new manifest, so no old block outlives it
            block.unlink()
        _atomic_write(path, lambda f: f.write(self.key.encode()))

    def _path(self, index: int) -> Path:
        return self.folder / f"block_{index:06d}.npz"

    def _digest(self, index, coords, values, errors) -> str:
        return _sha256(self.key, str(index), *coords, values, errors)

    def load(self, index: int, coords):
        """``(values, errors)`` of block ``index`` at ``coords``, or None if it is missing or
        does not verify (then it is recomputed)."""
        path = self._path(index)
        if not path.exists():
            return None
        try:
            with open(path, "rb") as f, np.load(f, allow_pickle=False) as data:
                values, errors, digest = data["values"], data["errors"], str(data["digest"])
            if digest == self._digest(index, coords, values, errors):
                return values, errors
        except Exception:  # any damage means: recompute
            pass
        print(f"block {index} in {self.folder} does not verify: recomputing it",
              file=sys.stderr, flush=True)
        return None

    def store(self, index: int, coords, values, errors) -> None:
        """Write block ``index`` atomically."""
        digest = np.array(self._digest(index, coords, values, errors))
        _atomic_write(self._path(index),
                      lambda f: np.savez(f, values=values, errors=errors, digest=digest))

    def resume(self, blocks) -> list:
        """``open`` the folder and load the finished ``blocks``: their ``(values, errors)``,
        None for those still to compute."""
        self.open()
        results = [self.load(i, b) for i, b in enumerate(blocks)]
        resumed = sum(r is not None for r in results)
        if resumed:
            print(f"{self.manifest['table']}: resuming with {resumed} of {len(blocks)} "
                  f"blocks from {self.folder}", file=sys.stderr, flush=True)
        return results

    def __len__(self) -> int:
        return len(list(self.folder.glob("block_*.npz")))


def partial_folder(folder, name: str) -> Path:
    """Where the ``bake`` command keeps the finished blocks of table ``name`` baked into
    ``folder`` (removed once the table is saved)."""
    return Path(folder) / f"{name}.partial"
