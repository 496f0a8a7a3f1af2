"""Render the gallery (``docs/figures/gallery.png``), time the renderer and measure the tone
curves on the README's sphere (``docs/figures/tonemap.png``); writes ``docs/render.md``.

    python -m benchmarks.render_report [--size N] [--spp S] [--out DIR]

Gallery: six ASM spheres under the synthetic sky of ``render.sky`` (white diffuse, gold
metal, coated red plastic with a tinted coat, dispersive rough glass, anisotropic brushed
steel, velvet sheen over dark blue). Timing: the seconds ``render.sphere`` takes for each at
``--size`` x ``--size`` pixels and ``--spp`` paths per pixel (256 x 256 at 64 by default),
measured in this one run on this machine. Tone mapping: the README's coated red sphere
(``README_SPHERE``, 128 x 128 at 32 paths per pixel, or the gallery's size and paths if
smaller), written with each of ``TONEMAPS``; the page gives the fraction of its pixels whose
red channel is clipped (encodes to 255).
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
    ("gold", {**GOLD, "roughness": 0.25}),  # metallic 1, F0 and F82 tint of [Kutz2021, Table 1]
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


#: the material of the README's "A whole material, rendered" example
README_SPHERE = {"base_color": (0.7, 0.05, 0.05), "roughness": 0.5, "coat_opacity": 1.0,
                 "coat_roughness": 0.05}
#: (exposure, tonemap) compared on it: the defaults, then the README's choice
TONEMAPS = [(0.0, "clip"), (-1.5, "aces")]


def _sphere_mask(size: int) -> np.ndarray:
    """Pixels of ``render.sphere``'s image that see the sphere."""
    c = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    x, y = np.meshgrid(c, -c)
    return x * x + y * y < 1.0


def clipped_fraction(image: np.ndarray, exposure: float = 0.0, tonemap: str = "clip") -> float:
    """Fraction of the sphere's pixels of ``image`` whose red channel encodes to 255 with
    ``render.to_srgb8(image, exposure, tonemap)``."""
    red = render.to_srgb8(image, exposure, tonemap)[..., 0]
    return float(np.mean(red[_sphere_mask(image.shape[0])] == 255))


def readme_sphere(size: int = 128, spp: int = 32) -> np.ndarray:
    """The README's sphere: ``render.sphere(AdobeStandardMaterial(**README_SPHERE), env="sky",
    size=128, spp=32)`` (linear radiance)."""
    return render.sphere(AdobeStandardMaterial(**README_SPHERE), env="sky", size=size, spp=spp,
                         progress=False)


def _tonemap_section(docs: Path, size: int, spp: int) -> list[str]:
    image = readme_sphere(size, spp)
    strips = [render.tone_map(image, exposure, tonemap) for exposure, tonemap in TONEMAPS]
    # tone_map's display values through write_png's clip, which leaves [0, 1] unchanged
    render.write_png(docs / "figures" / "tonemap.png", np.concatenate(strips, axis=1))
    lines = ["## Exposure and tone mapping", "",
             "The README's coated red sphere, `render.sphere(AdobeStandardMaterial("
             "base_color=(0.7, 0.05, 0.05), roughness=0.5, coat_opacity=1.0, "
             f"coat_roughness=0.05), env=\"sky\", size={size}, spp={spp})`, written with "
             "`render.write_png(path, image, exposure, tonemap)`; left to right as in the "
             "table:", "",
             "![tone curves](figures/tonemap.png)", "",
             "| exposure (stops) | tonemap | sphere pixels with red clipped (255) |",
             "|---|---|---|"]
    lines += [f"| {exposure:g} | `{tonemap}` | {clipped_fraction(image, exposure, tonemap):.1%} |"
              for exposure, tonemap in TONEMAPS]
    lines += ["", "`clip` cuts every channel at 1: where red is above 1 and green and blue are "
              "not, the hue moves towards pink. `aces` is the fitted ACES filmic curve "
              "[Narkowicz2016], per channel: it maps 0 to 0 and 1 to 0.80 and reaches 1 only "
              "at 7.24, so highlights roll off; 1.5 stops down keeps the red of the base colour "
              "below its shoulder.", ""]
    return lines


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
    tonemaps = _tonemap_section(docs, min(size, 128), min(spp, 32))
    lines = ["# Renderer: gallery and timing", "",
             generated_by("benchmarks.render_report", time.perf_counter() - start, "api.md"),
             "", "![gallery](figures/gallery.png)", "",
             f"`render.sphere(material, EquirectMap(sky(64)), size={size}, spp={spp})`, "
             f"{os.cpu_count()} CPUs, seconds per sphere measured in this run:", "",
             "| material | seconds |", "|---|---|"]
    lines += [f"| {label} | {seconds:.1f} |" for label, seconds in rows]
    lines.append("")
    lines += tonemaps
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
