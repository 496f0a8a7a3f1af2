"""Where the shipped tables live, and cached access to them by name.

The ``.npz`` files sit in the repository's top-level ``tables/`` folder, which the package
installs as ``adobe_bsdf.tables.data`` (``pyproject.toml``), so ``pip install .`` anywhere
finds them; an editable install reads the folder directly.
"""

from __future__ import annotations

import functools
import importlib.util
from pathlib import Path

from adobe_bsdf.tables.catalog import SPECS
from adobe_bsdf.tables.table import Table, TableError, load

__all__ = ["data_dir", "get", "path"]


def data_dir() -> Path:
    """Folder of the shipped tables."""
    spec = importlib.util.find_spec("adobe_bsdf.tables.data")
    if spec is not None and spec.submodule_search_locations:
        return Path(list(spec.submodule_search_locations)[0])
    return Path(__file__).resolve().parents[2] / "tables"  # editable install: the repository


def path(name: str) -> Path:
    """File of table ``name``."""
    return data_dir() / f"{name}.npz"


def spec(name: str):
    """Declaration of table ``name`` (``ValueError`` listing the known names otherwise)."""
    if name not in SPECS:
        raise ValueError(f"table {name!r} is not declared; known tables: {sorted(SPECS)}")
    return SPECS[name]


@functools.cache
def get(name: str) -> Table:
    """Table ``name``, read and verified once per process (a derived table also against the
    content hash of the table it was derived from)."""
    table = load(spec(name), path(name))
    for parent in table.spec.depends:
        if table.meta.get("parent_hash") != get(parent).meta["content_hash"]:
            raise TableError(f"table file {path(name)} was derived from another version of "
                             f"{parent}; re-bake it with "
                             f"`python -m adobe_bsdf bake {name} --in-place`")
    return table
