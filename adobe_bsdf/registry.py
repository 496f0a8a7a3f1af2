"""Registry of validation cases: each lobe module registers the configurations that
``python -m adobe_bsdf check`` (and the benchmarks) run, so the command grows with the library
without importing lobes by name.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

__all__ = ["CheckCase", "register", "cases"]


@dataclass(frozen=True)
class CheckCase:
    """One lobe configuration to validate.

    Attributes
    ----------
    name : str
        Short label, e.g. ``"Conductor a=0.1"``.
    make : callable
        ``make() -> Lobe``.
    cos_theta_o : tuple of float
        Incident cosines at which the chi-square and furnace tests run (negative: ``wo``
        below the surface, for two-sided lobes).
    expected_albedo : callable or None
        ``expected_albedo(wo) -> float``: an independent closed form of the energy albedo;
        ``None`` means the check compares with direction-space quadrature of ``eval``.
    width : float
        Characteristic angular width (radians) of the sharpest sampled peak, used to focus
        the chi-square grid (0: broad lobe).
    peak : callable or None
        ``peak(wo) -> (3,)``: direction of that peak (e.g. the mirror direction).
    tags : tuple of str
        Free-form tags (e.g. ``"fast"`` for the cases the command runs by default).
    furnace_tol : float
        Allowed |quadrature albedo - expected_albedo| (table-based models: their measured
        interpolation error, ``docs/tables.md``).
    reciprocal : bool
        False for a BSDF that is not reciprocal by design (albedo-scaled layers): its
        reciprocity error is listed, not judged.
    """

    name: str
    make: Callable
    cos_theta_o: tuple = (1.0, 0.5, 0.05)
    expected_albedo: Callable | None = None
    width: float = 0.0
    peak: Callable | None = None
    tags: tuple = field(default=("fast",))
    furnace_tol: float = 1e-6
    reciprocal: bool = True


_CASES: list[CheckCase] = []


def register(*new: CheckCase) -> None:
    """Add cases (a module calls this once at import)."""
    _CASES.extend(new)


def cases(tag: str | None = None) -> list[CheckCase]:
    """Registered cases, optionally only those with ``tag``."""
    return [c for c in _CASES if tag is None or tag in c.tags]
