"""What an ``AdobeStandardMaterial`` costs against the lobes it uses; writes
``docs/asm_cost.md``.

    python -m benchmarks.asm_cost [--pairs N] [--runs R] [--out DIR]

Materials from a plain diffuse (specular + diffuse) up to a fully loaded one (metal, opaque
and transmissive dielectric with dispersion and anisotropy, coat with a colour, sheen): for
each, the lobes built (``AdobeStandardMaterial.lobes``) and the median of ``runs`` timings
of ``eval`` and ``sample`` on the same ``pairs`` random pairs, all measured in this one run,
with the ratio to the plain diffuse material. An anisotropic coat is a separate row: its
albedo (under which the base is scaled) is a 32 x 32 Gauss rule tabulated once per coat
(``lobes.top_albedo.TopAlbedoGrid``), built by the warm-up call.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from adobe_bsdf.materials import AdobeStandardMaterial
from benchmarks import generated_by
from benchmarks import throughput as tp

DOCS = Path(__file__).resolve().parents[1] / "docs"

#: (label, parameters), cheapest first
MATERIALS = [
    ("plain diffuse", {}),
    ("metal only", {"metallic": 1.0}),
    ("half metal", {"metallic": 0.5}),
    ("+ transmission", {"metallic": 0.3, "translucency": 0.5}),
    ("+ dispersion, anisotropy", {"metallic": 0.3, "translucency": 0.5, "dispersion": 1.0,
                                  "anisotropy_level": 0.5, "anisotropy_angle": 0.2}),
    ("+ coat", {"metallic": 0.3, "translucency": 0.5, "dispersion": 1.0,
                "anisotropy_level": 0.5, "anisotropy_angle": 0.2, "coat_opacity": 0.7,
                "coat_color": (0.9, 0.8, 0.6)}),
    ("fully loaded (+ sheen)", {"metallic": 0.3, "translucency": 0.5, "dispersion": 1.0,
                                "anisotropy_level": 0.5, "anisotropy_angle": 0.2,
                                "coat_opacity": 0.7, "coat_color": (0.9, 0.8, 0.6),
                                "sheen_opacity": 0.5, "sheen_roughness": 0.4}),
    ("fully loaded + anisotropic coat", {"metallic": 0.3, "translucency": 0.5,
                                         "dispersion": 1.0, "anisotropy_level": 0.5,
                                         "anisotropy_angle": 0.2, "coat_opacity": 0.7,
                                         "coat_color": (0.9, 0.8, 0.6), "sheen_opacity": 0.5,
                                         "sheen_roughness": 0.4,
                                         "coat_anisotropy_level": 0.5}),
]


def measure(pairs: int, runs: int):
    """Rows ``(label, lobes, pairs timed, {call: seconds per pair})``."""
    wo, wi, u = tp.directions(pairs, seed=3)
    rows = []
    for label, params in MATERIALS:
        material = AdobeStandardMaterial(**params)
        n = pairs
        times = {}
        for call in ("eval", "sample"):
            tp._call(material, call, wo[:100], wi[:100], u[:100])  # warm-up (tables load)
            times[call] = tp._median(lambda c=call, m=material, n=n: tp.time_call(
                m, c, wo[:n], wi[:n], u[:n]), runs)[0] / n
        rows.append((label, list(material.lobes), n, times))
    return rows


def markdown(rows, pairs, runs, seconds):
    base = rows[0][3]
    out = ["# ASM: cost against the lobes in use", "",
           generated_by("benchmarks.asm_cost", seconds, "asm.md"), "",
           f"Median of {runs} runs over the same random pairs (`wo` above the surface, `wi` "
           "anywhere), all threads, in µs per pair; ratios to the plain diffuse material "
           "measured in this run. Lobes whose weight is zero are not built.", "",
           "| material | lobes built | pairs | eval (µs/pair) | sample (µs/pair) | eval ratio "
           "| sample ratio |", "|---|---|---|---|---|---|---|"]
    for label, lobes, n, t in rows:
        out.append(f"| {label} | {', '.join(lobes)} | {n} | {t['eval'] * 1e6:.2f} | "
                   f"{t['sample'] * 1e6:.2f} | {t['eval'] / base['eval']:.2f} | "
                   f"{t['sample'] / base['sample']:.2f} |")
    full = next(t for label, _, _, t in rows if label.startswith("fully loaded ("))
    out += ["", f"A plain diffuse material costs {base['eval'] / full['eval']:.2f} of a fully "
            f"loaded one in `eval` and {base['sample'] / full['sample']:.2f} in `sample`.", ""]
    return "\n".join(out)


def run(out: Path | None = None, pairs: int = 100_000, runs: int = 3) -> Path:
    start = time.perf_counter()
    rows = measure(pairs, runs)
    docs = DOCS if out is None else Path(out)
    docs.mkdir(parents=True, exist_ok=True)
    path = docs / "asm_cost.md"
    path.write_text(markdown(rows, pairs, runs, time.perf_counter() - start), encoding="utf-8")
    return path


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=100_000)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--out", type=Path, help="write into DIR instead of docs/")
    args = parser.parse_args(argv)
    print(run(args.out, args.pairs, args.runs))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
