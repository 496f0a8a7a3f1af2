"""Parameter specifications: a material's inputs declared once, as data.

Public API
----------
``Parameter(name, kind, default, hard, soft=None, doc="")``   one input
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

#: the kinds of input: a colour (scalar or trailing axis 3) or a real number
KINDS = ("color", "real")


@dataclass(frozen=True)
class Parameter:
    """One input of a material.

    Attributes
    ----------
    name : str
        Keyword name (snake_case).
    kind : {"color", "real"}
    default : float, tuple of 3 floats, or None
        The value where the user gives none; None: derived from other parameters by the
        material (the user may still give it, or pass None for the derived value).
    hard : (lo, hi)
        Allowed closed range; values outside raise.
    soft : (lo, hi) or None
        The range a user interface offers (None: the hard range).
    doc : str
        One line: meaning, source, what implements it.
    """

    name: str
    kind: str
    default: float | tuple | None
    hard: tuple
    soft: tuple | None = None
    doc: str = ""

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"kind = {self.kind!r} of parameter {self.name!r} is not one of "
                             f"{KINDS}")

    def validate(self, value) -> np.ndarray:
        """``value`` checked against the hard range, as float64 (a colour as ``(..., 3)``)."""
        lo, hi = self.hard
        check = _params.color if self.kind == "color" else _params.real
        return check(self.name, value, lo, hi)


def _number(x) -> str:
    if isinstance(x, tuple):
        return "(" + ", ".join(_number(v) for v in x) + ")"
    if x == math.inf:
        return "∞"
    if x == -math.inf:
        return "−∞"
    return f"{x:g}".replace("-", "−")


def _interval(r) -> str:
    lo, hi = r
    left, right = "(" if math.isinf(lo) else "[", ")" if math.isinf(hi) else "]"
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
                                     f"{_interval(p.hard)} (default {_number(p.default)})")
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
            rows.append(f"| `{p.name}` | {p.kind} | {_interval(p.hard)} | {soft} | {default} | "
                        f"{p.doc} |")
        return "\n".join(rows) + "\n"
