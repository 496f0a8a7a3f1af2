"""Render the gallery (``docs/figures/gallery.png``) and time the renderer; writes
``docs/render.md``.

    python -m benchmarks.render_report [--size N] [--spp S] [--out DIR]

Gallery: six ASM spheres under the synthetic sky of ``render.sky`` (white diffuse, gold
metal, coated red plastic with a tinted coat, dispersive rough glass, anisotropic brushed
steel, velvet sheen over dark blue). Timing: the seconds ``render.sphere`` takes for each at
``--size`` x ``--size`` pixels and ``--spp`` paths per pixel (256 x 256 at 64 by default),
measured in this one run on this machine.
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

from adobe_bsdf import render
from adobe_bsdf.materials import AdobeStandardMaterial, presets
from benchmarks import generated_by

DOCS = Path(__file__).resolve().parents[1] / "docs"
GOLD = presets.metals["Au"]

#: (label, parameters) of the gallery, left to right
GALLERY = [
    ("white diffuse", {"base_color": 1.0, "roughness": 0.5}),
    ("gold", {"metallic": 1.0, "roughness": 0.25, "base_color": GOLD["f0"],
              "specular_edge_color": GOLD["tint"]}),
    ("coated red plastic", {"base_color": (0.7, 0.05, 0.05), "roughness": 0.6,
                            "coat_opacity": 1.0, "coat_roughness": 0.05,
                            "coat_color": (1.0, 0.85, 0.6)}),
    ("dispersive glass", {"translucency": 1.0, "roughness": 0.1, "dispersion": 1.0,
                          "ior": 1.7}),
    ("brushed steel", {"metallic": 1.0, "roughness": 0.3, "anisotropy_level": 0.8,
                       "base_color": (0.56, 0.57, 0.58), "specular_edge_color": 0.9}),
    ("velvet", {"base_color": (0.05, 0.05, 0.25), "roughness": 0.8, "sheen_opacity": 1.0,
                "sheen_color": (0.9, 0.7, 1.0), "sheen_roughness": 0.3}),
]


def run(out: Path | None = None, size: int = 256, spp: int = 64) -> Path:
    start = time.perf_counter()
    docs = DOCS if out is None else Path(out)
    (docs / "figures").mkdir(parents=True, exist_ok=True)
    env = render.EquirectMap(render.sky(64))
    images, rows = [], []
    for label, params in GALLERY:
        t0 = time.perf_counter()
        image = render.sphere(AdobeStandardMaterial(**params), env, size=size, spp=spp,
                              seed=0, progress=False)
        rows.append((label, time.perf_counter() - t0))
        images.append(image)
    render.write_png(docs / "figures" / "gallery.png", np.concatenate(images, axis=1))
    lines = ["# Renderer: gallery and timing", "",
             generated_by("benchmarks.render_report", time.perf_counter() - start, "api.md"),
             "", "![gallery](figures/gallery.png)", "",
             f"`render.sphere(material, EquirectMap(sky(64)), size={size}, spp={spp})`, "
             f"{os.cpu_count()} CPUs, seconds per sphere measured in this run:", "",
             "| material | seconds |", "|---|---|"]
    lines += [f"| {label} | {seconds:.1f} |" for label, seconds in rows]
    lines.append("")
    page = docs / "render.md"
    page.write_text("\n".join(lines), encoding="utf-8")
    return page


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--out", type=Path, help="write into DIR instead of docs/")
    args = parser.parse_args(argv)
    print(run(args.out, args.size, args.spp))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
