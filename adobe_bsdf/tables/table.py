"""A baked table: its declaration (axes, outputs, how nodes are computed), storage and lookup.

Public API
----------
``Axis``        one input of a table: physical range, node count and parameterisation.
``TableSpec``   the declaration of a table: name, axes, output channels and node function.
``Table``       a baked table (node values and error estimates) with vectorised multilinear
                interpolation in the axes' parameters, ``Table(*coords) -> (..., n_outputs)``.
``TableError``  a missing, corrupt or mismatched table file, or a table with a non-finite
                node (a ``ValueError``).
``save``, ``load``  ``.npz`` files with metadata and a content hash checked on load; both
                reject non-finite values and errors, naming the file and the node.
"""

from __future__ import annotations

import hashlib
import itertools
import json
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
from scipy.special import lambertw

from adobe_bsdf import _params

__all__ = ["Axis", "TableSpec", "Table", "TableError", "save", "load", "PARAMETERISATIONS",
           "horner"]


#: batches above this size whose coordinates are all one point are looked up once
_CONSTANT_BATCH = 64


class TableError(ValueError):
    """A table file that is missing, corrupt, or baked for another declaration, or a table
    whose values or errors are not all finite."""


def _ior_to(x):
    return (x - 1.0) / (x + 1.0)


def _ior_from(p):
    return (1.0 + p) / (1.0 - p)


#: "log-linear": p = x + C ln(x + X0): uniform in ln x near 0 (resolves structure that scales
#: with x, e.g. grazing features of width ~ alpha), nearly uniform in x towards 1
LOGLIN_C, LOGLIN_X0 = 0.1, 1e-4


def _loglin_to(x, c=LOGLIN_C):
    return x + c * np.log(x + LOGLIN_X0)


def _loglin_from(p, c=LOGLIN_C):
    # y + C ln y = p + X0 with y = x + X0, solved by the Lambert W function
    q = (np.asarray(p, dtype=np.float64) + LOGLIN_X0) / c
    y = c * lambertw(np.exp(q) / c).real
    return y - LOGLIN_X0


def _loglin_dfrom(p, c=LOGLIN_C):
    x = _loglin_from(p, c)
    return 1.0 / (1.0 + c / (x + LOGLIN_X0))


#: name -> (physical -> parameter, parameter -> physical, d physical / d parameter); nodes
#: are uniform in the parameter
PARAMETERISATIONS: dict[str, tuple[Callable, Callable, Callable]] = {
    "linear": (lambda x: x, lambda p: p, np.ones_like),
    "sqrt": (np.sqrt, np.square, lambda p: 2.0 * p),
    "ior": (_ior_to, _ior_from, lambda p: 2.0 / (1.0 - p) ** 2),  # p = (eta - 1) / (eta + 1)
    "log-linear": (_loglin_to, _loglin_from, _loglin_dfrom),
}


@dataclass(frozen=True)
class Axis:
    """One input of a table.

    Attributes
    ----------
    name : str
        Physical quantity, e.g. ``"mu"`` (cos theta), ``"alpha"``, ``"eta"``.
    lo, hi : float
        Physical range covered (lookups outside raise ``ValueError``).
    n : int
        Number of nodes, uniform in the parameter.
    parameterisation : str
        Key of ``PARAMETERISATIONS``: ``"linear"``, ``"sqrt"``, ``"ior"`` or ``"log-linear"``.
    log_scale : float
        C of the "log-linear" parameterisation p = (x - lo) + C ln(x - lo + 1e-4): the larger,
        the more nodes go close to ``lo``.
    interpolation : {"linear", "cubic"}
        Along this axis: linear, or Catmull–Rom cubic convolution ([Keys1981], a = -1/2) with
        quadratic extrapolation for the ghost nodes beyond the ends.
    """

    name: str
    lo: float
    hi: float
    n: int
    parameterisation: str = "linear"
    interpolation: str = "linear"
    log_scale: float = LOGLIN_C

    def _maps(self):
        if self.parameterisation != "log-linear":
            return PARAMETERISATIONS[self.parameterisation]
        lo, c = self.lo, self.log_scale
        # (x - 0 is x, bit for bit: the subtraction is skipped where lo = 0)
        return (lambda x: _loglin_to(x - lo if lo else x, c), lambda p: _loglin_from(p, c) + lo,
                lambda p: _loglin_dfrom(p, c))

    def nodes(self) -> np.ndarray:
        """Physical node values ``(n,)``; the ends are exactly ``lo`` and ``hi``."""
        to, back, _ = self._maps()
        x = back(np.linspace(to(self.lo), to(self.hi), self.n))
        x[0], x[-1] = self.lo, self.hi
        return x

    def check(self, x, table: str | None = None) -> np.ndarray:
        """``x`` as float64, checked to lie in [lo, hi]; otherwise ``ValueError`` naming the
        table ``table`` (where given), this coordinate, the value, the range and what to do."""
        x = _params.as_float(self.name, x)
        if x.size and x.min() >= self.lo and x.max() <= self.hi:  # NaN fails both
            return x
        bad = ~((x >= self.lo) & (x <= self.hi))
        if np.any(bad):
            where = "a table" if table is None else f"table {table}"
            raise ValueError(f"{where}: coordinate {self.name} = {x[bad].flat[0].item()!r} is "
                             f"outside the table's range [{self.lo:g}, {self.hi:g}]; where "
                             "the tables do not reach, use albedo method 'quadrature' or 'mc'")
        return x

    def locate(self, x, table: str | None = None,
               checked: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """Cell index ``i`` in [0, n - 2] and fraction in [0, 1] of physical values ``x``
        (``check``-ed, unless ``checked`` is False for values known to lie in the range;
        ``table`` names the table in its message)."""
        x = self.check(x, table) if checked else np.asarray(x, dtype=np.float64)
        to = self._maps()[0]
        p0, p1 = to(self.lo), to(self.hi)
        t = (to(x) - p0) / (p1 - p0) * (self.n - 1)
        if np.ndim(t) == 0:
            i = np.intp(min(max(np.floor(t), 0), self.n - 2))
            return i, t - i
        # t > -1 (x >= lo, the map increasing: a negative t is rounding only), so truncation
        # is floor clipped to 0: the same cell as np.clip(np.floor(t), 0, n - 2)
        i = t.astype(np.intp)
        np.minimum(i, self.n - 2, out=i)
        return i, t - i

    def stencil(self, x, table: str | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Node indices and weights ``(..., k)`` of the interpolant at ``x`` (k = 2 or 4)."""
        start, weights = self.stencil_parts(x, table)
        return start[..., None] + np.arange(len(weights)), np.stack(weights, -1)

    def stencil_parts(self, x, table: str | None = None) -> tuple[np.ndarray, list]:
        """``(start, [w_0, ..., w_{k-1}])``: the interpolant at ``x`` is
        sum_j w_j f[start + j] (k = 2 linear, 4 cubic Catmull–Rom)."""
        i, t = self.locate(x, table)
        if self.interpolation == "linear":
            return i, [1.0 - t, t]
        t2 = t * t
        t3 = t2 * t
        w = [-0.5 * t3 + t2 - 0.5 * t, 1.5 * t3 - 2.5 * t2 + 1.0,
             -1.5 * t3 + 2.0 * t2 + 0.5 * t, 0.5 * t3 - 0.5 * t2]
        # ghost nodes by quadratic extrapolation, f(-1) = 3 f0 - 3 f1 + f2 (and mirrored at
        # the end), folded into a stencil shifted inside the table
        # (set where needed only: the same values as selecting over the whole batch)
        for edge, folded in ((i == 0, _fold_first), (i == self.n - 2, _fold_last)):
            if np.ndim(edge) == 0:
                if edge:
                    w = [np.asarray(x, dtype=np.float64) for x in folded(w)]
                continue
            at = np.flatnonzero(edge)
            if len(at):  # the weights are fresh contiguous arrays of t's shape
                values = folded([x.reshape(-1)[at] for x in w])
                for x, value in zip(w, values, strict=True):
                    x.reshape(-1)[at] = value
        return np.clip(i - 1, 0, self.n - 4), w

    def average_weights(self, order: int = 8) -> np.ndarray:
        """Weights ``(n,)`` with sum_k w_k f_k = 2 int f(x) x dx over the axis, exactly for the
        interpolant that is linear in the parameter (Gauss–Legendre per cell; exact when x
        is a polynomial in the parameter, as for "linear" and "sqrt")."""
        to, back, dback = self._maps()
        p = np.linspace(to(self.lo), to(self.hi), self.n)
        t, w = np.polynomial.legendre.leggauss(order)
        t, w = 0.5 * (t + 1.0), 0.5 * w
        h = p[1] - p[0]
        q = (p[:-1, None] + h * t).ravel()  # Gauss points of every cell
        density = 2.0 * back(q) * dback(q) * h * np.tile(w, self.n - 1)
        return self.rule_weights(np.clip(back(q), self.lo, self.hi), density)

    def rule_weights(self, x, w) -> np.ndarray:
        """Weights ``(n,)`` with sum_k W_k f_k = sum_q w_q f(x_q) for the interpolant f of
        node values f_k: the quadrature rule (``x``, ``w``) carried onto the nodes."""
        index, weight = self.stencil(np.asarray(x, dtype=np.float64))
        out = np.zeros(self.n)
        np.add.at(out, index, np.asarray(w, dtype=np.float64)[:, None] * weight)
        return out

    def describe(self) -> dict:
        out = {"name": self.name, "lo": self.lo, "hi": self.hi, "n": self.n,
               "parameterisation": self.parameterisation, "interpolation": self.interpolation}
        if self.parameterisation == "log-linear" and self.log_scale != LOGLIN_C:
            out["log_scale"] = self.log_scale
        return out


def _fold_first(w):
    """Catmull–Rom weights at the first cell with the ghost node f(-1) = 3 f0 - 3 f1 + f2
    folded into a stencil shifted one node inside the table."""
    wm, w0, w1, w2 = w
    return (w0 + 3 * wm, w1 - 3 * wm, w2 + wm, 0.0 * wm)


def _fold_last(w):
    """The same at the last cell (ghost f(n) = 3 f_{n-1} - 3 f_{n-2} + f_{n-3})."""
    wm, w0, w1, w2 = w
    return (0.0 * w2, wm + w2, w0 - 3 * w2, w1 + 3 * w2)


#: coefficients of 1, t, t^2, t^3 in the Catmull-Rom weights of nodes -1, 0, 1, 2
#: (``Axis.stencil_parts``)
_CATMULL_ROM = np.array([[0.0, -0.5, 1.0, -0.5], [1.0, 0.0, -2.5, 1.5],
                         [0.0, 0.5, 2.0, -1.5], [0.0, 0.0, -0.5, 0.5]])

#: largest |re-baked - stored| ``bake --check`` accepts by default
CHECK_TOL = 1e-6


@dataclass(frozen=True)
class TableSpec:
    """Declaration of a table.

    Attributes
    ----------
    name : str
        File stem (``tables/<name>.npz``) and the name used by ``python -m adobe_bsdf bake``.
    axes : tuple of Axis
    outputs : tuple of str
        Output channels, e.g. ``("E_R", "E_T")``.
    compute : callable
        ``compute(spec, *node_arrays) -> (values, errors)`` for 1-D arrays of node
        coordinates (one per axis, physical units); both results ``(n_nodes, n_outputs)``.
        A module-level function, so that worker processes can run it.
    quadrature : str
        One-line description of the method, stored in the metadata.
    order : int
        Quadrature order passed to ``compute`` (``bake --check`` re-bakes at a higher one).
    depends : tuple of str
        Tables whose baked values ``compute`` reads (derived tables, e.g. averages).
    description : str
        What the table holds, with the source equation.
    checked : callable or None
        ``checked() -> A``, ``(n_outputs, m)``: ``bake --check`` compares the combinations
        ``values @ A`` its users form instead of the channels themselves (None: the
        channels), the stored errors carried through ``|A|``.
    check_tol : float
        Largest |re-baked - stored| ``bake --check`` accepts: the nodes' accuracy.
    """

    name: str
    axes: tuple
    outputs: tuple
    compute: Callable = field(compare=False)
    quadrature: str = ""
    order: int = 20
    depends: tuple = ()
    description: str = ""
    checked: Callable | None = field(default=None, compare=False)
    check_tol: float = field(default=CHECK_TOL, compare=False)

    @property
    def shape(self) -> tuple:
        return tuple(a.n for a in self.axes) + (len(self.outputs),)

    def grid(self) -> list[np.ndarray]:
        """Node coordinates, one flattened array per axis (C order)."""
        mesh = np.meshgrid(*[a.nodes() for a in self.axes], indexing="ij")
        return [m.ravel() for m in mesh]

    def describe(self) -> dict:
        return {"name": self.name, "axes": [a.describe() for a in self.axes],
                "outputs": list(self.outputs), "quadrature": self.quadrature,
                "order": self.order, "depends": list(self.depends)}


class Table:
    """Baked node values of a ``TableSpec`` and their interpolation.

    ``table(*coords)`` interpolates multilinearly in the axes' parameters (e.g. sqrt(mu)),
    broadcasting the coordinates; it returns ``(..., n_outputs)``. Coordinates outside an
    axis's range raise ``ValueError`` naming the table, the axis, the value and the range.
    """

    def __init__(self, spec: TableSpec, values: np.ndarray, errors: np.ndarray,
                 meta: dict | None = None):
        if values.shape != spec.shape or errors.shape != spec.shape:
            raise TableError(f"table {spec.name}: values have shape {values.shape}, the "
                             f"declaration needs {spec.shape}")
        self.spec = spec
        self.values = values
        self.errors = errors
        self.meta = meta or {}

    def __repr__(self) -> str:
        return f"Table({self.spec.name!r}, shape={self.values.shape})"

    def __call__(self, *coords) -> np.ndarray:
        return self._interpolate(self.values, coords, absolute=False)

    def error(self, *coords) -> np.ndarray:
        """Quadrature error estimate carried to ``coords``: sum of |weight| x node error
        (the interpolation error itself is measured separately, ``docs/tables.md``)."""
        return self._interpolate(self.errors, coords, absolute=True)

    def fix(self, **fixed) -> Table:
        """The table with some axes held at scalar values: a table over the other axes
        whose interpolant is the same function, since the interpolation is a tensor
        product. The fixed axes' stencil weights are contracted with the nodes once, so a
        lookup then costs 4 (not 4^d) gathers per remaining cubic axis. Errors are carried
        with |weights| as in ``error``."""
        names = [a.name for a in self.spec.axes]
        unknown = set(fixed) - set(names)
        if unknown:
            raise ValueError(f"table {self.spec.name} has no axis {sorted(unknown)} "
                             f"(axes: {', '.join(names)})")
        values, errors, kept = self.values, self.errors, []
        for j in reversed(range(len(names))):  # last first: the indices of the rest hold
            axis = self.spec.axes[j]
            if axis.name not in fixed:
                kept.insert(0, axis)
                continue
            value = axis.check(fixed[axis.name], self.spec.name)
            if value.ndim:
                raise ValueError(f"table {self.spec.name}: {axis.name} has shape "
                                 f"{value.shape}; allowed: a single value to fix the axis at")
            index, weight = axis.stencil(value.item(), self.spec.name)
            full = np.zeros(axis.n)
            np.add.at(full, index, weight)
            values = np.tensordot(values, full, axes=([j], [0]))
            errors_weight = np.zeros(axis.n)
            np.add.at(errors_weight, index, np.abs(weight))
            errors = np.tensordot(errors, errors_weight, axes=([j], [0]))
        label = ", ".join(f"{k}={float(v):g}" for k, v in fixed.items())
        spec = replace(self.spec, name=f"{self.spec.name}[{label}]", axes=tuple(kept))
        return Table(spec, values, errors, self.meta)

    def _cells(self):
        """The interpolant of a one-output table with one or two cubic axes as a polynomial
        per cell, computed on first use: ``(index strides, coefficients)``, the coefficients
        ``(4,) * d`` of flat arrays over the cells, of t_0^p (t_1^q) with t the fractions in
        the cell (the ghost nodes folded in as ``Axis.stencil_parts`` does)."""
        cells = self.__dict__.get("_cubic_cells")
        if cells is None:
            f = self.values[..., 0]
            bases, starts = [], []
            for axis in self.spec.axes:
                n = axis.n
                start = np.clip(np.arange(n - 1) - 1, 0, n - 4)
                basis = np.broadcast_to(_CATMULL_ROM, (n - 1, 4, 4)).copy()  # cell, node, power
                basis[0], basis[-1] = _fold_first(_CATMULL_ROM), _fold_last(_CATMULL_ROM)
                bases.append(basis)
                starts.append(start[:, None] + np.arange(4))  # (cell, node)
            if len(bases) == 1:
                coefficients = np.einsum("ca,cap->cp", f[starts[0]], bases[0])
            else:
                nodes = f[starts[0][:, None, :, None], starts[1][None, :, None, :]]
                coefficients = np.einsum("ijab,iap,jbq->ijpq", nodes, *bases)
            cells_shape = coefficients.shape[:len(bases)]
            flat = coefficients.reshape((-1,) + (4,) * len(bases))
            strides = (cells_shape[1], 1) if len(bases) == 2 else (1,)
            cells = self.__dict__["_cubic_cells"] = (strides, np.ascontiguousarray(
                np.moveaxis(flat, 0, -1)))
        return cells

    def _polynomial(self, coords):
        """The interpolant at ``coords`` by the cells' polynomials (``_cells``), Horner's
        rule along each axis: the stencil's value to rounding, with 4^d gathers and no
        weights."""
        located = [a.locate(c, self.spec.name) for a, c in zip(self.spec.axes, coords,
                                                                 strict=True)]
        strides, c = self._cells()
        cell = None
        for (i, _), stride in zip(located, strides, strict=True):
            part = i if stride == 1 else i * stride
            cell = part if cell is None else cell + part
        t = [x for _, x in located]

        if len(t) == 1:
            return horner(lambda p: np.take(c[p], cell), t[0])
        return horner(lambda p: horner(lambda q: np.take(c[p, q], cell), t[1]), t[0])

    def total(self, *coords, error: bool = False) -> np.ndarray:
        """The lookup summed over the outputs, ``(...)`` (of ``error``'s estimate if
        ``error``): bit for bit ``table(*coords).sum(-1)``, without forming the
        ``(..., n_outputs)`` array where the outputs are gathered one by one."""
        data = self.errors if error else self.values
        if data.shape[-1] != 2:
            return self._interpolate(data, coords, absolute=error).sum(-1)
        a, b = self._outputs(data, coords, absolute=error)
        a += b
        a += 0.0  # NumPy's sum starts from +0: its -0 + -0 is +0
        return a

    def _interpolate(self, data, coords, absolute):
        outs = self._outputs(data, coords, absolute)
        return outs[0][..., None] if len(outs) == 1 else np.stack(outs, axis=-1)

    def _outputs(self, data, coords, absolute) -> list:
        """The lookup of ``data`` (the values, or with ``absolute`` weights the errors) at
        ``coords``: one array ``(...)`` per output."""
        axes = self.spec.axes
        if len(coords) != len(axes):
            raise ValueError(f"table {self.spec.name} takes {len(axes)} coordinates "
                             f"({', '.join(a.name for a in axes)}), got {len(coords)}")
        coords = [np.asarray(c) for c in coords]
        shape = np.broadcast_shapes(*(c.shape for c in coords))
        if np.prod(shape, dtype=np.int64) > _CONSTANT_BATCH and all(
                c.size and c.min() == c.max() for c in coords):
            # one point repeated (a batch of one view direction): looked up once, the same
            # arithmetic, so the same bits, broadcast back
            one = self._outputs(data, [c.reshape(-1)[:1] for c in coords], absolute)
            return [np.broadcast_to(x[0], shape).copy() for x in one]
        if (len(axes) <= 2 and all(a.interpolation == "cubic" for a in axes)
                and data.shape[-1] == 1 and not absolute and data is self.values):
            return [self._polynomial(coords)]
        stencils = [a.stencil_parts(c, self.spec.name) for a, c in zip(axes, coords, strict=True)]
        strides = np.cumprod((1,) + tuple(a.n for a in axes[:0:-1]))[::-1]
        base = None  # flat index of every lookup's first stencil node
        for (start, _), stride in zip(stencils, strides, strict=True):
            base = start * stride if base is None else base + start * stride
        flats = self._flat_outputs(data)
        outs = [None] * len(flats)
        for corner in itertools.product(*(range(len(w)) for _, w in stencils)):
            offset, weight = 0, None
            for c, stride, (_, w) in zip(corner, strides, stencils, strict=True):
                offset += c * stride
                weight = w[c] if weight is None else weight * w[c]
            weight = np.abs(weight) if absolute else weight
            index = base + offset
            for k, flat in enumerate(flats):
                term = np.take(flat, index) * weight
                if outs[k] is None:
                    outs[k] = term
                else:
                    outs[k] += term
        return outs

    def _flat_outputs(self, data):
        """``data`` (the values or the errors) as one contiguous flat array per output,
        made on first use: the lookup gathers each output by ``np.take`` (a gather of rows
        of several outputs costs several times more; the products and sums per output are
        the same)."""
        key = {id(self.values): "_flat_values", id(self.errors): "_flat_errors"}.get(id(data))
        flats = self.__dict__.get(key)
        if flats is None:
            flats = [np.ascontiguousarray(data[..., k]).reshape(-1)
                     for k in range(data.shape[-1])]
            if key is not None:
                self.__dict__[key] = flats
        return flats

    def channel(self, name: str) -> int:
        """Index of output channel ``name``."""
        return self.spec.outputs.index(name)


# -- storage ---------------------------------------------------------------------------------
def horner(coefficients, x):
    """sum_p coefficients(p) x^p for p <= 3 by Horner's rule (``coefficients(p)`` an
    array, or a scalar, per power)."""
    value = coefficients(3) * x
    for p in (2, 1):
        value += coefficients(p)
        value *= x
    value += coefficients(0)
    return value


def _digest(spec_json: str, values: np.ndarray, errors: np.ndarray) -> str:
    h = hashlib.sha256(spec_json.encode())
    h.update(np.ascontiguousarray(values, dtype="<f8").tobytes())
    h.update(np.ascontiguousarray(errors, dtype="<f8").tobytes())
    return h.hexdigest()


def _first_non_finite(table: Table) -> str | None:
    """Where ``table`` first holds a non-finite value or error: "its values hold nan at mu =
    0.5 (node 3), ..., output E_R", or None if every node is finite."""
    for label, data in (("values", table.values), ("errors", table.errors)):
        finite = np.isfinite(data)
        if finite.all():
            continue
        index = tuple(int(i) for i in np.argwhere(~finite)[0])
        axes = table.spec.axes
        at = ", ".join(f"{a.name} = {a.nodes()[i]:.6g} (node {i})"
                       for a, i in zip(axes, index[:len(axes)], strict=True))
        return (f"its {label} hold {float(data[index])!r} at {at}, output "
                f"{table.spec.outputs[index[-1]]}")
    return None


def save(table: Table, path: Path) -> None:
    """Write ``table`` to ``path`` (``.npz``): values, errors and JSON metadata with a hash.

    Every value and error must be finite: otherwise ``TableError`` naming the file and the
    first bad node's coordinates, and nothing is written."""
    bad = _first_non_finite(table)
    if bad is not None:
        raise TableError(f"table {table.spec.name} cannot be saved to {path}: {bad}; every "
                         "node must be finite")
    spec_json = json.dumps(table.spec.describe(), sort_keys=True)
    meta = dict(table.meta)
    meta.update(spec=json.loads(spec_json),
                max_error=float(table.errors.max()), mean_error=float(table.errors.mean()),
                content_hash=_digest(spec_json, table.values, table.errors))
    np.savez_compressed(path, values=table.values, errors=table.errors,
                        meta=np.array(json.dumps(meta, sort_keys=True)))


def load(spec: TableSpec, path: Path) -> Table:
    """Read and verify ``path`` against ``spec``: declaration, content hash, shape and finite
    nodes; raise ``TableError`` naming the file (and the first non-finite node)."""
    path = Path(path)
    if not path.is_file():
        raise TableError(f"table file {path} is missing; bake it with "
                         f"`python -m adobe_bsdf bake {spec.name} --in-place`")
    try:
        with np.load(path, allow_pickle=False) as data:
            values, errors = data["values"], data["errors"]
            meta = json.loads(str(data["meta"]))
    except Exception as exc:  # zip, key or JSON errors: all mean a damaged file
        raise TableError(f"table file {path} cannot be read ({exc}); re-bake it with "
                         f"`python -m adobe_bsdf bake {spec.name} --in-place`") from exc
    spec_json = json.dumps(spec.describe(), sort_keys=True)
    if meta.get("spec") != json.loads(spec_json):
        raise TableError(f"table file {path} was baked for another declaration of "
                         f"{spec.name} (axes, outputs or quadrature differ); re-bake it")
    if meta.get("content_hash") != _digest(spec_json, values, errors):
        raise TableError(f"table file {path} is corrupt: its content hash does not match")
    table = Table(spec, values, errors, meta)
    bad = _first_non_finite(table)
    if bad is not None:
        raise TableError(f"table file {path} is unusable: {bad}; re-bake it with "
                         f"`python -m adobe_bsdf bake {spec.name} --in-place`")
    return table
