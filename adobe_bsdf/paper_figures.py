"""The sphere figures of the source papers as scenes: which materials, which light, which grid.

One definition serves the notebooks (``notebooks/04``, ``05``), the theory pages
(``docs/figures.py``) and anyone checking a renderer against the papers: a ``Scene`` names
the figure it reproduces, and ``plot.sphere_grid(scene)`` renders it with ``render.sphere``.

Public API
----------
``Scene(title, source, env, ncols, materials, caption)``
``SCENES``  name -> function returning its ``Scene``:

=================  ==========================================================================
``asm_fig3``       [Kutz2021, Fig. 3]: the Table 1 metals (F0, F82 tint), roughness 0.25
``asm_fig6``       [Kutz2021, Fig. 6]: anisotropy level (rows) x roughness (columns), aluminium
``asm_fig9``       [Kutz2021, Fig. 9]: Dispersion 0 ... 1 on a rough glass
``asm_fig15``      [Kutz2021, Fig. 15]: sheen with c = 1 (top) and c = 2 (bottom) over a dark base
``asm_fig18``      [Kutz2021, Fig. 18]: coat tint, uniform and view-dependent
``hazy_fig3``      [Barla2018, Fig. 3 (right)]: haziness on a dielectric and on a conductor
``hazy_fig8``      [Barla2018, Fig. 8]: physical mixture weight beta against perceptual beta_h
=================  ==========================================================================

Where a caption does not give a value (a colour, a roughness), the scene's ``caption`` says
which one is ours.

References
----------
[Kutz2021, Figs. 3, 6, 9, 15, 18] the Adobe Standard Material scenes.
[Barla2018, Figs. 3 and 8] the hazy-gloss scenes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from adobe_bsdf import composition, fresnel, hazy, lobes
from adobe_bsdf.bsdf import Lobe
from adobe_bsdf.materials import AdobeStandardMaterial, presets
from adobe_bsdf.materials.asm import CoatTransmittance

__all__ = ["Scene", "SCENES", "coat_tint_pair"]


@dataclass(frozen=True)
class Scene:
    """Spheres to render side by side (``plot.sphere_grid``)."""

    title: str
    #: citation of the figure, e.g. "[Kutz2021, Fig. 9]"
    source: str
    #: ``render.sphere``'s environment: "furnace", "sun", "sky" or "studio"
    env: str
    ncols: int
    #: label -> lobe or material, in reading order
    materials: dict[str, Lobe]
    caption: str = ""
    #: panel size relative to ``plot.sphere_grid``'s default (pixels and inches)
    zoom: float = 1.0


def asm_fig3() -> Scene:
    metals = {name: AdobeStandardMaterial(**m, roughness=0.25)
              for name, m in presets.metals.items()}
    return Scene("Table 1 metals, roughness 0.25", "[Kutz2021, Fig. 3]", "sky", 7, metals,
                 "Base colour F0 and specular edge colour (F82 tint) of Table 1; the "
                 "roughness 0.25 is ours.")


#: anisotropy levels (rows) and roughnesses (columns) of ``asm_fig6``
FIG6_LEVELS, FIG6_ROUGHNESS = (0.0, 0.5, 0.75, 1.0), (0.1, 0.25, 0.4, 0.6)


def asm_fig6() -> Scene:
    al = presets.metals["Al"]
    grid = {f"a = {a:g}, r = {r:g}": AdobeStandardMaterial(**al, roughness=r, anisotropy_level=a)
            for a in FIG6_LEVELS for r in FIG6_ROUGHNESS}
    return Scene("anisotropy level (rows) x roughness (columns)", "[Kutz2021, Fig. 6]", "sun",
                 len(FIG6_ROUGHNESS), grid,
                 "Aluminium of Table 1 under the sun; alpha_x = r^2 + a^4, alpha_y = r^2. The "
                 "grid starts at r = 0.1: a highlight alpha_y -> 0 wide is too thin to show.")


def asm_fig9() -> Scene:
    glass = {f"dispersion {d:g}": AdobeStandardMaterial(translucency=1.0, ior=1.5,
                                                         roughness=0.0, dispersion=d)
             for d in (0.0, 0.25, 0.5, 0.75, 1.0)}
    return Scene("Dispersion on a smooth glass", "[Kutz2021, Fig. 9]", "studio", 5, glass,
                 "ior 1.5, roughness 0 and the studio's light strips are ours: the channels "
                 "separate at the strips' edges; single paths carry one channel, so few paths "
                 "per pixel give coloured noise (Fig. 10).", zoom=1.6)


#: sheen roughnesses of ``asm_fig15``
FIG15_ROUGHNESS = (0.2, 0.4, 0.6, 0.8)


def asm_fig15() -> Scene:
    dark = AdobeStandardMaterial(base_color=(0.02, 0.02, 0.03), roughness=0.5)
    sheens = {f"c = {c:g}, r = {r:g}": composition.Layer(lobes.Sheen(1.0, r, c=c), dark)
              for c in (1.0, 2.0) for r in FIG15_ROUGHNESS}
    return Scene("sheen c = 1 (top) and c = 2 (bottom) over a dark base", "[Kutz2021, Fig. 15]",
                 "sun", len(FIG15_ROUGHNESS), sheens,
                 "White sheen layered by albedo scaling; the dark base is ours.")


#: coat colour and index of ``asm_fig18``
FIG18_COAT, FIG18_COAT_IOR = (0.9, 0.6, 0.3), 1.6


def coat_tint_pair(coat_color, coat_ior, **base) -> tuple[Lobe, Lobe]:
    """(uniform tint, view-dependent tint): the same ASM coat (roughness 0.1) over the ASM
    base ``base``; the uniform one swaps the coat's transmittance for
    ``CoatTransmittance(..., view_dependent=False)`` [Kutz2021, §7, Fig. 18]."""
    coated = AdobeStandardMaterial(coat_opacity=1.0, coat_ior=coat_ior, coat_roughness=0.1,
                                   coat_color=coat_color, **base)
    uniform = composition.Layer(coated.lobes["coat"], coated.bsdf.base, 1.0,
                                CoatTransmittance(coat_color, coat_ior, view_dependent=False))
    return uniform, coated


def asm_fig18() -> Scene:
    coats = {}
    for name, base in (("diffuse", {"base_color": 1.0, "roughness": 0.5}),
                       ("rough glass", {"translucency": 1.0, "roughness": 0.3})):
        coats[f"{name}, uniform"], coats[f"{name}, view-dep."] = coat_tint_pair(
            FIG18_COAT, FIG18_COAT_IOR, **base)
    return Scene("coat tint: uniform (left), view-dependent (right)", "[Kutz2021, Fig. 18]", "sun",
                 2, coats, zoom=1.6,
                 caption=f"Coat colour {FIG18_COAT}, ior {FIG18_COAT_IOR}, roughness 0.1 "
                 "(ours) over a white diffuse base and a white rough glass.")


def hazy_fig3() -> Scene:
    green = lobes.Lambert((0.04, 0.18, 0.04))
    spheres = {}
    for b in np.linspace(0.0, 0.1, 5):
        spheres[f"dielectric β_h = {b:.3f}"] = composition.Sum(hazy.HazyGloss(0.04, b, 7.0, 0.01),
                                                         green)
    for b in (0.0, 0.25, 0.5, 0.75, 0.95):
        spheres[f"conductor β_h = {b:g}"] = hazy.HazyGloss((0.9, 0.6, 0.3), b, 7.0, 0.01,
                                                           edge_tint=0.5)
    return Scene("haziness grows to the right", "[Barla2018, Fig. 3 (right)]", "sky", 5, spheres,
                 "alpha_n = 0.01, lambda_h = 7 as the caption; r_c, the edge tint and the "
                 "greenish Lambertian term are ours. Dielectric beta_h in [0, 0.1] (§2.3).")


def hazy_fig8() -> Scene:
    fixed, swept, (first, last) = presets.hazy_sweeps["fig8"]
    alpha_n, extent = fixed["alpha_x"], fixed["haze_extent"]
    alpha_w = hazy.wide_roughness(alpha_n, alpha_n, extent)[0]
    F = fresnel.ExactConductor(*fresnel.gulbrandsen_to_ior(fixed["core_reflectivity"], 0.0))
    spheres = {}
    for beta in np.linspace(first, last, 5):
        spheres[f"β = {beta:.2f}"] = composition.Sum(lobes.Conductor(alpha_n, fresnel=F),
                                               lobes.Conductor(alpha_w, fresnel=F),
                                               weights=[1.0 - beta, beta])
    for value in np.linspace(first, last, 5):
        spheres[f"β_h = {value:.2f}"] = hazy.HazyGloss(**fixed, **{swept: value})
    return Scene("physical β (top) against perceptual β_h (bottom)", "[Barla2018, Fig. 8]", "sky",
                 5, spheres, "r_c = 0.5, alpha_n = 0.012, lambda_h = 6.4 as the caption.")


#: every scene, by name
SCENES = {"asm_fig3": asm_fig3, "asm_fig6": asm_fig6, "asm_fig9": asm_fig9,
          "asm_fig15": asm_fig15, "asm_fig18": asm_fig18, "hazy_fig3": hazy_fig3,
          "hazy_fig8": hazy_fig8}
