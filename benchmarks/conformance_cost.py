"""How long ``conformance.compare`` takes to judge a candidate; writes
``docs/conformance_measured.md``.

    python -m benchmarks.conformance_cost [--smoke] [--out DIR]

Each material judged against itself given as a plain candidate (``FunctionCandidate`` of its
``eval``, ``pdf`` and ``sample``: the cost of the checks, not of a slow candidate) at
``SAMPLES`` samples per view and the default views; and Mitsuba 3's ``roughconductor``
(Python calls one pair at a time) at ``MITSUBA_SAMPLES``. Wall-clock seconds of one run on
this machine, with the time of each check.
"""

from __future__ import annotations

import time
from pathlib import Path

from benchmarks import generated_by, machine, report_main, write_page

NAME = "conformance_measured.md"
SAMPLES, MITSUBA_SAMPLES, SMOKE_SAMPLES = 1_000_000, 100_000, 5_000


def _cases(smoke: bool):
    import adobe_bsdf as ab
    from adobe_bsdf.conformance import FunctionCandidate

    def itself(material, name):
        return material, FunctionCandidate(material.eval, material.pdf, material.sample, name)
    asm = ab.materials.AdobeStandardMaterial(roughness=0.4, base_color=(0.8, 0.5, 0.2),
                                             anisotropy_level=0.5)
    openpbr = ab.materials.OpenPBRSurface(base_color=(0.8, 0.5, 0.2), specular_roughness=0.4,
                                          coat_weight=1.0, coat_roughness=0.1)
    cases = [("ASM dielectric, roughness 0.4, anisotropy 0.5", *itself(asm, "ASM"),
              SMOKE_SAMPLES if smoke else SAMPLES),
             ("OpenPBR, coated", *itself(openpbr, "OpenPBR"),
              SMOKE_SAMPLES if smoke else SAMPLES)]
    try:
        from adobe_bsdf.validation.mitsuba import MitsubaBSDF

        plugin = {"type": "roughconductor", "distribution": "ggx", "alpha_u": 0.3,
                  "alpha_v": 0.1, "eta": {"type": "rgb", "value": [0, 0, 0]},
                  "k": {"type": "rgb", "value": [1, 1, 1]}}
        cases.append(("Mitsuba roughconductor (one pair a call)",
                      ab.lobes.Conductor(0.3, 0.1, masking="separable"), MitsubaBSDF(plugin),
                      SMOKE_SAMPLES if smoke else MITSUBA_SAMPLES))
    except ImportError:
        pass
    return cases


def measure(smoke: bool = False) -> list:
    from adobe_bsdf.conformance import compare

    rows = []
    for label, reference, candidate, n in _cases(smoke):
        start = time.perf_counter()
        report = compare(reference, candidate, n_samples=n)
        rows.append((label, n, report.settings["views"], time.perf_counter() - start,
                     report.passed))
    return rows


def markdown(rows: list, seconds: float) -> str:
    out = [generated_by("benchmarks.conformance_cost", seconds, "conformance.md"), "",
           "# Conformance: the time of a verdict", "",
           f"Machine: {machine.cpu_model()}, {machine.cores()} cores. One run of "
           "`conformance.compare` per row, the default views.", "",
           "| candidate | samples per view | views | seconds | verdict |",
           "|---|---|---|---|---|"]
    for label, n, views, t, passed in rows:
        out.append(f"| {label} | {n} | {views} | {t:.1f} | "
                   f"{'conforms' if passed else 'does not conform'} |")
    return "\n".join(out) + "\n"


def run(out: Path | None = None, smoke: bool = False) -> Path:
    return write_page(out, NAME, lambda: (measure(smoke),), markdown)


def main(argv=None) -> int:
    return report_main(run, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    raise SystemExit(main())
