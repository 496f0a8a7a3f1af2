"""Write the theory pages' figures into ``docs/figures/`` (run from the repository root).

    python docs/figures.py [--out DIR] [--size N] [--spp S]

Every figure is drawn by ``adobe_bsdf.plot`` from the library itself:

* ``theory_lobes.png``     polar slices (plane of incidence, f |cos|) of a GGX conductor, a
                           rough glass from both sides, the ASM sheen and a hazy gloss lobe;
* ``theory_furnace.png``   white-furnace curves E(mu) - 1: GGX alone, with Kulla–Conty, and
                           the white ASM dielectric [Kutz2021, Fig. 2];
* ``theory_gold.png``      gold's exact spectral Fresnel against Schlick, F82 and F82-tint
                           [Kutz2021, §2];
* ``paper_<scene>.png``    the papers' sphere figures, one per ``adobe_bsdf.paper_figures``
                           scene, rendered by ``plot.sphere_grid`` at ``--size`` pixels and
                           ``--spp`` paths per pixel (96 and 64 by default).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

import adobe_bsdf as ab  # noqa: E402
from adobe_bsdf import paper_figures  # noqa: E402

FIGURES = Path(__file__).resolve().parent / "figures"
THETA_O = 0.6  # radians, for the slices


def lobes_figure(path: Path) -> None:
    lobes = {"GGX conductor, gold, alpha 0.2": ab.materials.asm.asm_metal(
                 ab.materials.presets.metals["Au"]["base_color"],
                 ab.materials.presets.metals["Au"]["specular_edge_color"], 0.45),
             "rough glass eta 1.5, alpha 0.1": ab.lobes.Dielectric(1.5, 0.1),
             "ASM sheen r 0.4": ab.lobes.Sheen(1.0, 0.4),
             "hazy gloss [Barla2018]": ab.hazy.HazyGloss(0.04, 0.5, 4.0, 0.05)}
    fig = plt.figure(figsize=(4 * len(lobes), 4))
    for k, (label, lobe) in enumerate(lobes.items()):
        ax = fig.add_subplot(1, len(lobes), k + 1, projection="polar")
        ab.plot.polar_slice(lobe, THETA_O, ax=ax, quantity="eval_cos", log=True)
        ax.set_title(label, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def furnace_figure(path: Path) -> None:
    lobes = {f"GGX alpha {a}": ab.lobes.Conductor(a) for a in (0.3, 1.0)}
    lobes |= {f"GGX + Kulla-Conty alpha {a}": ab.lobes.ConductorMS(a) for a in (0.3, 1.0)}
    lobes["ASM white diffuse + specular r 0.5"] = ab.materials.AdobeStandardMaterial(
        base_color=1.0, roughness=0.5)
    fig, ax = plt.subplots(figsize=(6, 4))
    ab.plot.furnace_curves(lobes, ax=ax)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def gold_figure(path: Path) -> None:
    fig, ax = plt.subplots(figsize=(6, 4))
    ab.plot.metal_fresnel("Au", ax=ax)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def scene_figure(path: Path, name: str, size: int, spp: int) -> None:
    fig = ab.plot.sphere_grid(paper_figures.SCENES[name](), size=size, spp=spp)
    fig.savefig(path, dpi=90)
    plt.close(fig)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=FIGURES)
    parser.add_argument("--size", type=int, default=96)
    parser.add_argument("--spp", type=int, default=64)
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    lobes_figure(args.out / "theory_lobes.png")
    furnace_figure(args.out / "theory_furnace.png")
    gold_figure(args.out / "theory_gold.png")
    for name in paper_figures.SCENES:
        scene_figure(args.out / f"paper_{name}.png", name, args.size, args.spp)
    print(args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
