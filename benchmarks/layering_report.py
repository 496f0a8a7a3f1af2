"""Measure the albedo-scaling forms of ``composition.Layer`` against the stochastic
``LayeredReference`` and write ``docs/layering.md`` (with ``docs/figures/layering_*.png``).

    python -m benchmarks.layering_report [--out DIR] [--smoke]

A coat of index eta and GGX roughness alpha = r^2 over a Lambertian base, clear or tinted
(two-way transmittance T at normal incidence), in each form with and without coat darkening,
against light followed between the coat and the base (an energy-conserving rough
``DielectricMS`` coat, an absorbing slab of optical thickness -ln(T) / 2 between them).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from adobe_bsdf.bsdf import luminance
from adobe_bsdf.composition import Layer
from adobe_bsdf.darkening import Darkening
from adobe_bsdf.layered import LayeredReference
from adobe_bsdf.lobes import ConductorMS, DielectricMS, DielectricReflection, Lambert
from benchmarks import generated_by, pyplot

DOCS = Path(__file__).resolve().parents[1] / "docs"
COAT_IORS = (1.3, 1.5, 2.0)
ROUGHNESSES = (0.0, 0.1, 0.3, 0.6)
#: the bases: a factory of the lobe and its roughness r_b for coat darkening
BASES = {"white": (lambda: Lambert(1.0), 1.0),
         "coloured": (lambda: Lambert((0.8, 0.3, 0.1)), 1.0),
         "glossy": (lambda: ConductorMS(0.25), 0.5)}
#: what the bases are, for the page
BASE_TEXT = ("a white `Lambert`, a coloured one (albedo (0.8, 0.3, 0.1)) and a glossy white "
             "metal (`ConductorMS(0.25)`: GGX alpha = 0.25, F = 1, energy-conserving)")
COATS = {"clear": 1.0, "tinted": 0.6}
COS_O = (1.0, 0.7, 0.4, 0.15)
#: the forms measured: (name, scaling, coat darkening delta or None)
FORMS = (("albedo", "albedo", None), ("reciprocal", "reciprocal", None),
         ("transmittance", "transmittance", None), ("albedo + darkening", "albedo", 1.0),
         ("transmittance + darkening", "transmittance", 1.0))
#: Gauss–Legendre cosines x midpoint azimuths of the hemisphere grid; walks per pair; samples
#: of each albedo
GRID, WALKS, MC = 16, 256, 40_000
SMOKE = {"grid": 6, "walks": 8, "iors": (1.5,), "roughnesses": (0.3,), "cos_o": (0.7,),
         "mc": 2000}


def sph(mu, phi):
    mu = np.asarray(mu, dtype=float)
    s = np.sqrt(1.0 - mu * mu)
    return np.stack(np.broadcast_arrays(s * np.cos(phi), s * np.sin(phi), mu), -1)


def hemisphere(n):
    """``(wi (n*n, 3), weights (n*n,))``: Gauss–Legendre in cos theta x n azimuths, the
    weights of int g |cos| d omega."""
    x, w = np.polynomial.legendre.leggauss(n)
    mu, w = (x + 1.0) / 2.0, w / 2.0
    phi = (np.arange(n) + 0.5) * 2.0 * np.pi / n
    M, P = np.meshgrid(mu, phi, indexing="ij")
    return sph(M, P).reshape(-1, 3), (w[:, None] * M * 2.0 * np.pi / n).reshape(-1)


def layers(eta, alpha, base, T):
    """The measured forms, ``{name: Layer}``, for one configuration, ``base`` a key of
    ``BASES`` (forms that coincide with an earlier one, the transmittance forms of a clear
    coat, left out)."""
    make, r_b = BASES[base]
    top, base = DielectricReflection(eta, alpha), make()
    out = {}
    for name, scaling, delta in FORMS:
        if scaling == "transmittance" and np.all(np.asarray(T) == 1.0):
            continue
        dark = None if delta is None else Darkening(delta, base_roughness=r_b)
        out[name] = Layer(top, base, transmittance=T, scaling=scaling, darkening=dark)
    return out


def reference(eta, alpha, base, T, walks):
    """The ground truth: a slab of optical thickness -ln(T) / 2 (T grey) between the coat's
    energy-conserving interface and the base."""
    tau = float(-np.log(T) / 2.0)
    return LayeredReference(DielectricMS(eta, alpha), BASES[base][0](), thickness=tau,
                            n_samples=walks)


def mc_albedo(sampler, lobe, wo, n, seed=5):
    """The energy albedo (luminance) from ``n`` samples of ``sampler(wo, u)`` (a lobe's
    ``sample``, or a reference's ``walk``): the mean energy weight, and its standard error."""
    w = np.broadcast_to(wo, (n, 3))
    s = sampler(w, np.random.default_rng(seed).random((n, 3)))
    e = luminance(s.weight * lobe._energy_scale_rgb(w, s.wi))
    return float(e.mean()), float(e.std() / np.sqrt(n))


def measure(smoke: bool = False):
    """Rows ``(coat, base, eta, r, cos_o, form, dE, rel_L1, noise, nonrecip, dE_err)``: the
    albedo error (luminance, Monte Carlo of both samplers) and its standard error, the
    relative L1 distance of the lobe through the coat on the grid, the reference's own noise in
    that distance, and the relative non-reciprocity."""
    grid = SMOKE["grid"] if smoke else GRID
    walks = SMOKE["walks"] if smoke else WALKS
    iors = SMOKE["iors"] if smoke else COAT_IORS
    rough = SMOKE["roughnesses"] if smoke else ROUGHNESSES
    cos_o = SMOKE["cos_o"] if smoke else COS_O
    n_mc = SMOKE["mc"] if smoke else MC
    wi, weight = hemisphere(grid)
    rows = []
    for coat, T in COATS.items():
        for base in BASES:
            for eta in iors:
                for r in rough:
                    alpha = r * r
                    forms = layers(eta, alpha, base, T)
                    ref = reference(eta, alpha, base, T, walks)
                    for mu in cos_o:
                        wo = sph(mu, 0.0)
                        f_ref, err = ref.eval_with_error(wo, wi)
                        f_ref = f_ref - ref.top.eval(wo, wi)  # through the coat only
                        lum_ref, lum_err = luminance(f_ref), luminance(err)
                        E_ref = np.sum(lum_ref * weight)
                        A_ref = mc_albedo(ref.walk, ref, wo, n_mc)
                        noise = np.sum(lum_err * weight) / E_ref
                        top = next(iter(forms.values())).top  # one coat for every form
                        top_o, top_i = top.eval(wo, wi), top.eval(wi, wo)
                        for name, layer in forms.items():
                            f = luminance(layer.eval(wo, wi) - top_o)
                            back = luminance(layer.eval(wi, wo) - top_i)
                            A = mc_albedo(layer.sample, layer, wo, n_mc, seed=6)
                            rows.append((coat, base, eta, r, mu, name, A[0] - A_ref[0],
                                         np.sum(np.abs(f - lum_ref) * weight) / E_ref, noise,
                                         np.sum(np.abs(f - back) * weight) / np.sum(f * weight),
                                         np.hypot(A[1], A_ref[1])))
    return rows


def summary(rows):
    """Per form: worst and median |dE|, worst and median L1, worst non-reciprocity."""
    out = []
    for name, _, _ in FORMS:
        mine = [r for r in rows if r[5] == name]
        if not mine:
            continue
        dE = np.array([r[6] for r in mine])
        L1 = np.array([r[7] for r in mine])
        nr = np.array([r[9] for r in mine])
        worst = mine[int(np.argmax(np.abs(dE)))]
        out.append((name, worst[6], np.median(np.abs(dE)), L1.max(), np.median(L1), nr.max(),
                    worst))
    return out


def figure_albedo(plt, path: Path, rows):
    fig, axes = plt.subplots(2, len(ROUGHNESSES), figsize=(12, 5.6), sharey="row")
    axes = np.atleast_2d(axes)
    for i, (coat, base) in enumerate((("clear", "white"), ("tinted", "coloured"))):
        for j, r in enumerate(ROUGHNESSES):
            ax = axes[i, j]
            for name, _, _ in FORMS:
                pts = sorted((row[4], row[6]) for row in rows if row[0] == coat
                             and row[1] == base and row[2] == 1.5 and row[3] == r
                             and row[5] == name)
                if pts:
                    x, y = zip(*pts, strict=True)
                    ax.plot(x, y, "o-", ms=3, label=name)
            ax.axhline(0.0, color="0.6", lw=0.8)
            ax.set_title(f"{coat} coat, {base} base, r = {r:g}, IOR 1.5", fontsize=8)
            ax.set_xlabel(r"$\cos\theta_o$")
        axes[i, 0].set_ylabel("albedo error dE")
    for ax in axes[:, 0]:
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def figure_slices(plt, path: Path, walks: int, n: int):
    """In-plane slices of f |cos| (through the coat) at theta_o = 45 degrees."""
    theta = np.linspace(-np.pi / 2 + 0.02, np.pi / 2 - 0.02, n)
    wi = np.stack([np.sin(theta), np.zeros_like(theta), np.cos(theta)], -1)
    wo = sph(np.cos(np.pi / 4), 0.0)
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
    for ax, (r, T) in zip(axes, ((0.0, 1.0), (0.6, 0.6)), strict=True):
        ref = reference(1.5, r * r, "coloured", T, 16 * walks)
        f, err = ref.eval_with_error(wo, wi)
        f, err = luminance(f - ref.top.eval(wo, wi)) * wi[:, 2], luminance(err) * wi[:, 2]
        ax.fill_between(np.degrees(theta), f - 3 * err, f + 3 * err, color="0.8")
        ax.plot(np.degrees(theta), f, color="black", lw=1.2, label="LayeredReference")
        for name, layer in layers(1.5, r * r, "coloured", T).items():
            g = luminance(layer.eval(wo, wi) - layer.top.eval(wo, wi)) * wi[:, 2]
            ax.plot(np.degrees(theta), g, lw=1.0, label=name)
        ax.set_title(f"IOR 1.5, r = {r:g}, T = {T:g}, coloured base, $\\theta_o$ = 45°",
                     fontsize=8)
        ax.set_xlabel(r"$\theta_i$ (degrees, plane of incidence)")
    axes[0].set_ylabel(r"$f\,\cos\theta_i$ through the coat (luminance)")
    for ax in axes:
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run(out: Path | None = None, smoke: bool = False) -> Path:
    start = time.perf_counter()
    docs = DOCS if out is None else Path(out)
    (docs / "figures").mkdir(parents=True, exist_ok=True)
    rows = measure(smoke)
    summ = summary(rows)
    figures = []
    plt = pyplot()
    if plt is not None:
        figure_albedo(plt, docs / "figures" / "layering_albedo.png", rows)
        figure_slices(plt, docs / "figures" / "layering_slices.png",
                      SMOKE["walks"] if smoke else WALKS, 31 if smoke else 181)
        figures = ["layering_albedo.png", "layering_slices.png"]
    path = docs / "layering.md"
    path.write_text(_markdown(rows, summ, figures, smoke, time.perf_counter() - start),
                    encoding="utf-8")
    return path


def _markdown(rows, summ, figures, smoke, seconds) -> str:
    grid = SMOKE["grid"] if smoke else GRID
    walks = SMOKE["walks"] if smoke else WALKS
    lines = [
        "# Layering: the albedo-scaling forms against light transport", "",
        generated_by("benchmarks.layering_report", seconds, "reference.md"), "",
        "OpenPBR builds a surface from two operators [Andersson2023, §Formalism]: `mix` "
        "(`composition.Mix`, patches side by side) and `layer` (`composition.Layer`, a coat "
        "over a base). A layer is approximated by *albedo scaling*: the coat's BSDF plus the "
        "base's, weighted by what the coat lets through. `composition.Layer` has the three "
        "forms of [Andersson2023, §Layering], selected by `scaling=` (c the coverage, "
        "E_top(w) the coat's directional albedo, T the coat's two-way transmittance at "
        "normal incidence):", "",
        "| form | f | white furnace | reciprocal |", "|---|---|---|---|",
        "| `\"albedo\"` (default) | c f_top + lerp(1, T (1 - E_top(wo)), c) f_base | "
        "exact (T = 1) | no |",
        "| `\"reciprocal\"` | c f_top + lerp(1, C T (1 - E_top(wi)) (1 - E_top(wo)), c) "
        "f_base, C = 1 / max_wo int (1 - E_top) f_base cos | exact over a Lambertian base; "
        "loses energy over a glossy one | yes |",
        "| `\"transmittance\"` | c f_top + lerp(1, T_coat(wi, wo) (1 - E_top(wo)), c) f_base, "
        "T_coat = T^((1/mu_i^t + 1/mu_o^t)/2) with mu^t the refracted cosines | exact "
        "(T = 1) | no |", "",
        "Coat darkening (`darkening.Darkening`, [Portsmouth2025]) multiplies the covered base "
        "weight by lerp(1, Delta(wo), delta), Delta = (1 - K) / (1 - K E_b T): the light the "
        "coat reflects back down onto the base, which absorbs part of it.", "",
        "**Why `\"albedo\"` is the default.** OpenPBR v1.1.1 settled on it [OpenPBR2026, "
        "§Layering], as the Adobe Standard Material did [Kutz2021]; a white base under a "
        "clear coat keeps exactly all the energy, and it costs one albedo lookup. The "
        "reciprocal form is reciprocal, but its normalisation must be the largest C that "
        "never gains energy, so over any base whose integral varies with wo it loses energy, "
        "and C must be computed per layer (`composition.reciprocal_normalisation`). The "
        "measurements below give the price of each.", "",
        "## How it is measured", "",
        f"A coat of index eta in {list(COAT_IORS)} and roughness r in {list(ROUGHNESSES)} "
        "(GGX alpha = r^2; `DielectricReflection` as the layer's top) over a base "
        f"({BASE_TEXT}; coat darkening with base_roughness 1 over the diffuse bases, 0.5 over "
        f"the metal), clear (T = 1) or tinted (a grey T = {COATS['tinted']}), seen from "
        f"cos theta_o in {list(COS_O)}. The ground truth is "
        "`layered.LayeredReference` [Guo2018]: random walks between an energy-conserving "
        "rough interface (`DielectricMS`, which transmits what it does not reflect, as the "
        "albedo scaling assumes) and the base, through an absorbing slab of optical "
        "thickness -ln(T) / 2 (so exp(-tau / mu_o^t - tau / mu_i^t) is T at normal "
        f"incidence). Every eval is {walks} walks on a {grid} x {grid} grid (Gauss–Legendre "
        "cos theta_i x azimuths) of the hemisphere.", "",
        "Every figure is in luminance:", "",
        f"- *albedo error* dE = E - E_ref of the whole directional albedo, each from {MC} "
        "samples (the layer's `sample`, the reference's `walk`); the worst |dE| is stated with "
        "its standard error;",
        "- *lobe error* L1 = int |f - f_ref| cos / int f_ref cos of the light through the "
        "coat (the coat's reflection, the same lobe in both, subtracted) on the grid; the "
        "reference's own Monte-Carlo noise adds up to the *noise* figure below (L1 under it "
        "is not resolved), and over the glossy base the grid resolves neither lobe, so its L1 "
        "is only indicative;",
        "- *non-reciprocity* int |f(wo, wi) - f(wi, wo)| cos / int f cos, the same light.", "",
        "## Summary per form", "",
        "| form | worst dE | median abs dE | worst L1 | median L1 | worst non-reciprocity | "
        "worst dE at |", "|---|---|---|---|---|---|---|"]
    for name, worst, med, L1, L1m, nr, at in summ:
        lines.append(f"| {name} | {worst:+.4f} ± {at[10]:.4f} | {med:.4f} | {L1:.3f} | "
                     f"{L1m:.3f} | {nr:.2e} | "
                     f"{at[0]} coat, {at[1]} base, IOR {at[2]:g}, r = {at[3]:g}, "
                     f"cos {at[4]:g} |")
    lines += ["", "## Per coat and base", "",
              "Worst dE (signed) / worst L1 over IORs, roughnesses and angles.", "",
              "| form | " + " | ".join(f"{c} coat, {b} base" for c in COATS for b in BASES)
              + " |", "|---|" + "---|" * (len(COATS) * len(BASES))]
    for name, _, _ in FORMS:
        cells = []
        for c in COATS:
            for b in BASES:
                mine = [row for row in rows if row[5] == name and row[0] == c and row[1] == b]
                if not mine:
                    cells.append("(= albedo)")
                    continue
                dE = max((m[6] for m in mine), key=abs)
                cells.append(f"{dE:+.4f} / {max(m[7] for m in mine):.3f}")
        if any(c != "(= albedo)" for c in cells):
            lines.append(f"| {name} | " + " | ".join(cells) + " |")
    lines += [""]
    if figures:
        lines += ["## Albedo error against the angle", "",
                  "![albedo error](figures/layering_albedo.png)", "",
                  "## Lobe shape", "",
                  "In-plane slices; the grey band is the reference's ±3 standard errors.", "",
                  "![slices](figures/layering_slices.png)", ""]
    lines += ["## Per roughness", "",
              "Worst |dE| and worst L1 over IORs, bases, coats and angles.", "",
              "| form | " + " | ".join(f"r = {r:g}" for r in sorted({r[3] for r in rows}))
              + " |", "|---|" + "---|" * len({r[3] for r in rows})]
    for name, _, _ in FORMS:
        cells = []
        for r in sorted({row[3] for row in rows}):
            mine = [row for row in rows if row[5] == name and row[3] == r]
            if mine:
                cells.append(f"{max(abs(m[6]) for m in mine):.4f} / "
                             f"{max(m[7] for m in mine):.3f}")
        if cells:
            lines.append(f"| {name} | " + " | ".join(cells) + " |")
    noise = max(r[8] for r in rows)
    lines += ["", f"The reference's noise in L1 is at most {noise:.3f}.", ""]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="write into DIR instead of docs/")
    parser.add_argument("--smoke", action="store_true", help="tiny sizes (a test)")
    args = parser.parse_args(argv)
    print(run(args.out, args.smoke))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
