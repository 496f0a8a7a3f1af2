"""Measure coat darkening [OpenPBR2026, §Coat darkening; Portsmouth2025] and write
``docs/coat_darkening_measured.md``.

    python -m benchmarks.darkening_report [--out DIR]

- the specification's fit of the Fresnel average E_F against its quadrature;
- K, Delta (both variants), the base factor and the coated albedo at normal incidence for a
  white and a coloured base, coat IOR 1.3 / 1.5 / 2, a smooth and a rough base, a clear and a
  tinted coat, coat_darkening 0 and 1.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from adobe_bsdf import darkening as dk
from adobe_bsdf import fresnel
from benchmarks import generated_by

DOCS = Path(__file__).resolve().parents[1] / "docs"
COAT_IORS = (1.3, 1.5, 2.0)
BASES = {"white": (1.0, 1.0, 1.0), "coloured": (0.8, 0.3, 0.1)}
COATS = {"clear": (1.0, 1.0, 1.0), "tinted": (0.9, 0.7, 0.4)}
FIT_ETAS = (1.0, 1.1, 1.3, 1.5, 2.0, 2.5, 3.0)


def _rgb(c):
    return "(" + ", ".join(f"{x:.4f}" for x in np.ravel(c)) + ")"


def fit_rows():
    eta = np.array(FIT_ETAS)
    exact, fit = dk.fresnel_average(eta), dk.fresnel_average_fit(eta)
    grid = np.linspace(1.0, 3.0, 2001)
    worst = np.abs(dk.fresnel_average_fit(grid) - dk.fresnel_average(grid))
    return list(zip(eta, exact, fit, strict=True)), worst.max(), grid[np.argmax(worst)]


def value_rows():
    rows = []
    for base, E_b in BASES.items():
        for coat, T2 in COATS.items():
            for eta in COAT_IORS:
                F0 = float(fresnel.dielectric(1.0, eta))
                for r_b in (0.0, 1.0):
                    K = float(dk.coat_reflectance(eta, r_b))
                    Delta = dk.darkening(E_b, K, T2)
                    old = dk.darkening(E_b, K, T2, "v1.1.1")
                    E = [F0 + (1.0 - F0) * dk.base_factor(Delta, d, T2) * np.asarray(E_b)
                         for d in (0.0, 1.0)]
                    rows.append((base, coat, eta, r_b, K, Delta, old, E[0], E[1]))
    return rows


def run(out: Path | None = None) -> Path:
    start = time.perf_counter()
    docs = DOCS if out is None else Path(out)
    docs.mkdir(parents=True, exist_ok=True)
    fits, worst, where = fit_rows()
    values = value_rows()
    lines = ["# Coat darkening: measured", "",
             generated_by("benchmarks.darkening_report", time.perf_counter() - start,
                          "api.md"), "",
             "`adobe_bsdf.darkening` [OpenPBR2026, §Coat darkening; Portsmouth2025]. "
             "Its tests check Delta against a random walk of light between a smooth coat and "
             "a Lambertian base (`tests/test_darkening.py`).", "",
             "## The Fresnel average and the specification's fit", "",
             "E_F(eta) = 2 int F(mu, eta) mu d mu by Gauss–Legendre (`fresnel_average`) "
             "against the closed-form fit the specification gives (`fresnel_average_fit`).", "",
             "| eta | E_F, quadrature | fit | fit - quadrature |", "|---|---|---|---|"]
    lines += [f"| {e:g} | {x:.6f} | {f:.6f} | {f - x:+.1e} |" for e, x, f in fits]
    lines += ["", f"Over eta in [1, 3] (2001 points) the fit is within **{worst:.1e}** "
              f"(worst at eta = {where:.3f}).", "",
              "## Values at normal incidence", "",
              "K = `coat_reflectance(eta, r_b)` (r_b = 0: smooth base, K = F0; r_b = 1: rough "
              "base, the internal average), Delta = `darkening(E_b, K, T2)` ([Portsmouth2025]) "
              "and the released specification's (`variant=\"v1.1.1\"`), and the coated albedo "
              "at normal incidence F0 + (1 - F0) `base_factor(Delta, delta, T2)` E_b for "
              "coat_darkening delta = 0 (naive: the base tinted by T2) and 1 (physical), "
              "coverage 1.", "",
              "| base E_b | coat T2 | coat IOR | r_b | K | Delta | Delta, v1.1.1 | "
              "albedo, delta = 0 | albedo, delta = 1 |", "|---|---|---|---|---|---|---|---|---|"]
    lines += [f"| {b} | {c} | {eta:g} | {r:g} | {K:.4f} | {_rgb(D)} | {_rgb(o)} | {_rgb(e0)} | "
              f"{_rgb(e1)} |" for b, c, eta, r, K, D, o, e0, e1 in values]
    path = docs / "coat_darkening_measured.md"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="write into DIR instead of docs/")
    args = parser.parse_args(argv)
    print(run(args.out))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
