"""Parameter specifications: a material's inputs declared once, as data.

Public API
----------
``Parameter(name, kind, default, hard, soft=None, doc="", lo_open=False, choices=None,
hi_open=False)``                                               one input
``ParameterSpec(*parameters)``                                 a material's inputs, in order

The constructor of a material validates its keyword arguments with ``ParameterSpec.validate``
(unknown names and values outside the hard range raise ``ValueError`` naming the parameter,
its value and the range; soft ranges are only advice); its ``docs/`` parameter table is
``ParameterSpec.markdown()`` (``docs/parameter_tables.py`` writes it); importers (MaterialX)
and interactive front ends read names, defaults and ranges from the same record.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from adobe_bsdf import _params

__all__ = ["Parameter", "ParameterSpec", "KINDS"]

#: the kinds of input: a colour (scalar or trailing axis 3), a real number, a switch, a
#: 3-vector of the local shading frame (normalised; MaterialX's vector3) or one of a fixed set
#: of options (a model's name)
KINDS = ("color", "real", "bool", "vector", "choice")


@dataclass(frozen=True)
class Parameter:
    """One input of a material.

    Attributes
    ----------
    name : str
        Keyword name (snake_case).
    kind : one of ``KINDS``
    default : float, tuple of 3 floats, bool, str, or None
        The value where the user gives none; None: derived from other parameters by the
        material (the user may still give it, or pass None for the derived value).
    hard : (lo, hi) or None
        Allowed range, closed unless ``lo_open``; values outside raise (None for a switch, a
        vector or a choice).
    soft : (lo, hi) or None
        The range a user interface offers (None: the hard range).
    doc : str
        One line: meaning, source, what implements it.
    lo_open, hi_open : bool
        The lower (an index of refraction in (0, inf)) or upper bound is excluded; real
        inputs only.
    choices : tuple or None
        The options of a choice (and only of a choice).
    """

    name: str
    kind: str
    default: float | tuple | bool | None
    hard: tuple | None
    soft: tuple | None = None
    doc: str = ""
    lo_open: bool = False
    choices: tuple | None = None
    hi_open: bool = False

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"kind = {self.kind!r} of parameter {self.name!r} is not one of "
                             f"{KINDS}")
        if (self.kind == "choice") != (self.choices is not None):
            raise ValueError(f"choices of parameter {self.name!r}: given for a choice, and "
                             "only for a choice")
        if (self.lo_open or self.hi_open) and self.kind != "real":
            raise ValueError(f"lo_open, hi_open of parameter {self.name!r}: allowed for real "
                             "inputs")

    def validate(self, value):
        """``value`` checked against the hard range, as float64 (a colour as ``(..., 3)``); a
        switch as a bool; a vector as a non-zero ``(..., 3)``, normalised."""
        if self.kind == "bool":
            return _params.flag(self.name, value)
        if self.kind == "choice":
            return _params.choice(self.name, value, self.choices)
        if self.kind == "vector":
            v = _params.vectors(self.name, value)
            length = np.linalg.norm(v, axis=-1, keepdims=True)
            if not np.all(np.isfinite(length) & (length > 0.0)):
                raise ValueError(f"{self.name} = {_params._show(v)}: allowed finite, non-zero "
                                 "3-vectors of the local shading frame")
            return v / length
        lo, hi = self.hard
        if self.kind == "color":
            return _params.color(self.name, value, lo, hi)
        return _params.real(self.name, value, lo, hi, lo_open=self.lo_open,
                            hi_open=self.hi_open)

    @property
    def range_text(self) -> str:
        """The hard range as ``docs/`` writes it."""
        if self.kind == "bool":
            return "{false, true}"
        if self.kind == "choice":
            return "{" + ", ".join(map(str, self.choices)) + "}"
        if self.kind == "vector":
            return "unit 3-vector"
        return _interval(self.hard, self.lo_open, self.hi_open)


def _number(x) -> str:
    if isinstance(x, bool):
        return str(x).lower()
    if isinstance(x, tuple):
        return "(" + ", ".join(_number(v) for v in x) + ")"
    if x == math.inf:
        return "∞"
    if x == -math.inf:
        return "−∞"
    return f"{x:g}".replace("-", "−")


def _interval(r, lo_open: bool = False, hi_open: bool = False) -> str:
    lo, hi = r
    left = "(" if math.isinf(lo) or lo_open else "["
    right = ")" if math.isinf(hi) or hi_open else "]"
    return f"{left}{_number(lo)}, {_number(hi)}{right}"


class ParameterSpec:
    """The ordered inputs of one material."""

    def __init__(self, *parameters: Parameter):
        self.parameters = {p.name: p for p in parameters}
        if len(self.parameters) != len(parameters):
            raise ValueError("parameter names must be unique")

    def __iter__(self):
        return iter(self.parameters.values())

    def __len__(self) -> int:
        return len(self.parameters)

    def __getitem__(self, name: str) -> Parameter:
        return self.parameters[name]

    @property
    def defaults(self) -> dict:
        """``{name: default}`` (None where the material derives the value)."""
        return {p.name: p.default for p in self}

    def validate(self, params: dict) -> dict:
        """``{name: float64 array}`` of every parameter with a value: the given ones checked,
        the others at their defaults; derived parameters left unset (None)."""
        unknown = set(params) - set(self.parameters)
        if unknown:
            raise ValueError(f"unknown parameter(s) {sorted(unknown)}; allowed: "
                             f"{sorted(self.parameters)}")
        out = {}
        for p in self:
            value = params.get(p.name, p.default)
            if value is None:
                if p.default is not None:
                    raise ValueError(f"{p.name} = None: allowed a {p.kind} in "
                                     f"{p.range_text} (default {_number(p.default)})")
                continue
            out[p.name] = p.validate(value)
        return out

    def markdown(self) -> str:
        """The parameter table of ``docs/``: name, kind, hard and soft range, default, doc."""
        rows = ["| parameter | kind | range | soft range | default | meaning |",
                "|---|---|---|---|---|---|"]
        for p in self:
            default = "derived" if p.default is None else _number(p.default)
            soft = "—" if p.soft is None else _interval(p.soft)
            rows.append(f"| `{p.name}` | {p.kind} | {p.range_text} | {soft} | {default} | "
                        f"{p.doc} |")
        return "\n".join(rows) + "\n"
