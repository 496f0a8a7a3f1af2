"""The verdict of ``conformance.compare``: one ``Check`` per test, gathered in a ``Report``
that prints as a table, as markdown and as JSON."""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field

__all__ = ["Check", "Report"]


@dataclass(frozen=True)
class Check:
    """One test of a candidate against its reference.

    ``name`` the test; ``passed`` True, False, or None where it does not apply (``note``
    says why); ``statistic`` the measured figure and ``threshold`` what it was held to (its
    meaning in ``measure``); ``p_value`` where the test is statistical; ``worst`` where it
    is worst (view, direction, values); ``cause`` the likely cause of a failure."""

    name: str
    passed: bool | None
    measure: str
    statistic: float | None = None
    threshold: float | None = None
    p_value: float | None = None
    worst: dict = field(default_factory=dict)
    cause: str = ""
    note: str = ""

    @property
    def verdict(self) -> str:
        return {True: "pass", False: "FAIL", None: "n/a"}[self.passed]


def _number(x) -> str:
    return "—" if x is None else f"{x:.3g}"


def _where(worst: dict) -> str:
    def fmt(v):
        if isinstance(v, (list, tuple)):
            return "(" + ", ".join(f"{x:.4g}" if isinstance(x, float) else str(x)
                                   for x in v) + ")"
        return f"{v:.4g}" if isinstance(v, float) else str(v)
    return "; ".join(f"{k} {fmt(v)}" for k, v in worst.items())


@dataclass
class Report:
    """Every ``Check`` of one comparison, with what was compared and how."""

    reference: str
    candidate: str
    checks: list
    settings: dict = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        """No applicable check failed."""
        return all(c.passed is not False for c in self.checks)

    @property
    def tests(self) -> list:
        return self.checks

    def failures(self) -> list:
        return [c for c in self.checks if c.passed is False]

    def rows(self) -> list[list[str]]:
        """One row per check: test, verdict, statistic, threshold, p-value, worst case and
        likely cause (or note)."""
        return [[c.name, c.verdict, f"{_number(c.statistic)} ({c.measure})",
                 _number(c.threshold), _number(c.p_value), _where(c.worst),
                 c.cause or c.note] for c in self.checks]

    HEADER = ["test", "verdict", "statistic", "threshold", "p-value", "worst case",
              "likely cause / note"]

    def markdown(self) -> str:
        out = [f"# {self.candidate} against {self.reference}: "
               f"{'conforms' if self.passed else 'does not conform'}", "",
               "| " + " | ".join(self.HEADER) + " |", "|" + "---|" * len(self.HEADER)]
        out += ["| " + " | ".join(cell.replace("|", "\\|") for cell in row) + " |"
                for row in self.rows()]
        if self.settings:
            out += ["", "Settings: " + ", ".join(f"{k} = {v}" for k, v in
                                                 self.settings.items()) + "."]
        return "\n".join(out) + "\n"

    def __str__(self) -> str:
        rows = [self.HEADER] + self.rows()
        widths = [min(max(len(r[i]) for r in rows), 60) for i in range(len(self.HEADER))]
        lines = [f"{self.candidate} against {self.reference}: "
                 f"{'conforms' if self.passed else 'DOES NOT CONFORM'}"]
        for row in rows:
            lines.append("  ".join(cell.ljust(w) if len(cell) <= w else cell
                                   for cell, w in zip(row, widths, strict=True)).rstrip())
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {"reference": self.reference, "candidate": self.candidate,
                "passed": self.passed, "settings": self.settings,
                "tests": [asdict(c) | {"verdict": c.verdict} for c in self.checks]}

    def to_json(self, indent: int | None = 2) -> str:
        return json.dumps(self.to_dict(), indent=indent, default=float)
