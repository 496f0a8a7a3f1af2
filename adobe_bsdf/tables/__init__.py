"""Energy tables: declared once, baked with scipy quadrature, shipped, interpolated.

Public API
----------
``get(name)``          the baked table ``name`` (loaded and hash-checked once), callable as
                       ``table(*coords) -> (..., n_outputs)`` (multilinear interpolation).
``SPECS``              every declared table (``catalog``).
``Axis``, ``TableSpec``, ``Table``, ``TableError``  the mechanism (``table``).
``bake``, ``check``    compute a table's nodes / re-bake sample nodes (``bake``).
``ggx_energy``         the node integrator (``energy``).

Command line: ``python -m adobe_bsdf bake [NAMES...] [--check]``. ``docs/tables.md`` lists the
tables, their sizes, bake times and measured interpolation errors.
"""

from adobe_bsdf.tables.catalog import ALPHA_MAX, ETA_MAX, IOR_MAX, SPECS
from adobe_bsdf.tables.energy import Energy, ggx_energy
from adobe_bsdf.tables.store import data_dir, get, path, spec
from adobe_bsdf.tables.table import Axis, Table, TableError, TableSpec, load, save

__all__ = ["ALPHA_MAX", "ETA_MAX", "IOR_MAX", "SPECS", "Energy", "ggx_energy", "data_dir", "get",
           "path", "spec", "Axis", "Table", "TableError", "TableSpec", "load", "save"]
