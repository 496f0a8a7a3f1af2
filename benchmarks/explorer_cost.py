"""How long ``ab.explore`` takes to redraw; writes ``docs/explorer_cost.md``.

    python -m benchmarks.explorer_cost [--smoke] [--out DIR]

For the default ASM, the default OpenPBR Surface and ``HazyGloss`` at the "normal" panel
sizes: the time of an update of the three fast panels (polar slice, hemisphere image,
albedo curve) after a control moved, and of the update at rest (sphere and quadrature as
well), median of ``RUNS`` after one warm-up, on this machine's threads. Each timed update
follows a change of a slider (the material is rebuilt, as in use) and includes drawing the
figure to a PNG, as Jupyter's inline display does.
"""

from __future__ import annotations

import io
import os
import time

import numpy as np

from benchmarks import generated_by, report_main, write_page

TARGETS = ("AdobeStandardMaterial", "OpenPBRSurface", "HazyGloss")
#: the slider moved before each timed update
MOVED = {"AdobeStandardMaterial": "roughness", "OpenPBRSurface": "specular_roughness",
         "HazyGloss": "haziness"}
RUNS = 5
#: the interaction target of the fast panels, seconds
RESPONSIVE = 0.3


def measure(smoke: bool = False) -> list:
    """``[(target, fast seconds, rest seconds, active lobes)]``."""
    import matplotlib

    matplotlib.use("Agg")
    from adobe_bsdf.explorer import Explorer

    size, runs = ("small", 2) if smoke else ("normal", RUNS)
    rows = []
    for name in TARGETS:
        explorer = Explorer(name, size=size)
        explorer.update(slow=True)  # warm-up: tables load, the figure is made
        explorer.live = False  # time update() alone, the material rebuilt each time
        slider = explorer._controls[MOVED[name]].widget
        values = np.linspace(slider.min, slider.max, 2 * runs + 2)[1:-1]
        fast, rest = [], []
        for i in range(runs):
            for moved, slow, times in ((values[2 * i], False, fast),
                                       (values[2 * i + 1], True, rest)):
                slider.value = float(moved)
                start = time.perf_counter()
                explorer.update(slow=slow)
                explorer.figure.savefig(io.BytesIO(), format="png")  # as the inline display
                times.append(time.perf_counter() - start)
        rows.append((name, float(np.median(fast)), float(np.median(rest)),
                     explorer.data["active"]))
    return rows


def markdown(rows, smoke, seconds) -> str:
    out = ["# ab.explore: time of an update", "",
           generated_by("benchmarks.explorer_cost", seconds, "explore.md"), "",
           f"Median of {2 if smoke else RUNS} updates after a slider moved, "
           f"{'small' if smoke else 'normal'} panel sizes, {os.cpu_count()} CPUs. *Fast*: "
           "polar slice, hemisphere image and albedo curve (what follows the controls); "
           "*at rest*: those and the sphere and the quadrature albedo. Both include drawing "
           "the figure to a PNG, as the notebook's display does.", "",
           "| target | active lobes | fast panels (s) | at rest (s) | fast under "
           f"{RESPONSIVE} s |", "|---|---|---|---|---|"]
    for name, fast, rest, active in rows:
        out.append(f"| {name} | {', '.join(active)} | {fast:.3f} | {rest:.2f} | "
                   f"{'yes' if fast < RESPONSIVE else 'no'} |")
    return "\n".join(out) + "\n"


def run(out=None, smoke: bool = False):
    return write_page(out, "explorer_cost.md", lambda: (measure(smoke), smoke), markdown)


if __name__ == "__main__":
    raise SystemExit(report_main(run, __doc__.splitlines()[0]))
