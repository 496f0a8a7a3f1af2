"""Measure the hazy-gloss lobes and write ``docs/hazy_measured.md`` and its figures.

    python -m benchmarks.hazy_report [--smoke] [--out DIR]

* [Barla2018, Fig. 3 (left)]: k_h against r_c, the positivity and energy bounds (eq. 6), eq. 7
  for several beta_h and the rational Bézier curves (eq. 15) for w in {1, 2, 4, 8};
* Table 2: the peak ratio p of each model against the ratio of the two Conductor lobes'
  actual values at (n, n), over a grid of narrow and wide roughnesses;
* the core peak of the composite lobes (both models, both maskings) across beta_h in [0, 1];
* compound against separate masking (§3): the albedo difference of the two readings (F = 1);
* the two-component BTDF (§4.2, Fig. 13 left): index, reflected and transmitted energy as the
  haziness grows;
* polar slices of HazyGloss in the plane of incidence (the halo grows, the core stays).

``--smoke`` runs every section at tiny sizes into ``--out`` (used by the test suite). Without
matplotlib the figures are left out and the Markdown says so.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

import adobe_bsdf as ab
from adobe_bsdf import hazy
from adobe_bsdf.bsdf import Flags
from benchmarks import generated_by, pyplot, report_main

DOCS = Path(__file__).resolve().parents[1] / "docs"
N = np.array([0.0, 0.0, 1.0])


def _direction(cos_theta, phi=0.0):
    s = np.sqrt(1.0 - cos_theta**2)
    return np.array([s * np.cos(phi), s * np.sin(phi), cos_theta])


# -- measurements ---------------------------------------------------------------------------
def peak_ratio_agreement(smoke: bool):
    """Max |lobe ratio / Table 2 - 1| per model over narrow alphas x extents (isotropic and
    anisotropic)."""
    alphas = [(0.01, 0.01), (0.1, 0.1)] if smoke else [
        (0.002, 0.002), (0.01, 0.01), (0.05, 0.05), (0.2, 0.2), (0.5, 0.5), (0.05, 0.01),
        (0.3, 0.02)]
    extents = [(1.0, 1.0), (7.0, 2.0)] if smoke else [
        (0.5, 0.5), (2.0, 2.0), (7.0, 7.0), (20.0, 20.0), (7.0, 1.0), (0.0, 5.0)]
    rows = []
    for model in hazy.PEAK_MODELS:
        worst, count = 0.0, 0
        for ax, ay in alphas:
            for lx, ly in extents:
                aw = hazy.wide_roughness(ax, ay, lx, ly)
                narrow = ab.lobes.Conductor(ax, ay, model=model).eval(N, N)[0]
                wide = ab.lobes.Conductor(*aw, model=model).eval(N, N)[0]
                p = float(hazy.peak_ratio((ax, ay), aw, model))
                worst = max(worst, abs(wide / narrow / p - 1.0))
                count += 1
        rows.append((model, count, worst))
    return rows


def core_peak_invariance(smoke: bool):
    """Max relative change of the composite's value at (n, n) over beta_h in [0, 1]."""
    betas = np.linspace(0.0, 1.0, 5 if smoke else 41)
    r_c, g, alpha = [0.9, 0.6, 0.3], 0.3, (0.02, 0.01)
    rows = []
    for model in hazy.PEAK_MODELS:
        for compound in (False, True):
            core = np.asarray(r_c) * ab.lobes.Conductor(*alpha, model=model).eval(N, N)
            worst = 0.0
            for beta_h in betas:
                lobe = hazy.HazyGloss(r_c, beta_h, 6.0, *alpha, edge_tint=g, model=model,
                                      compound_masking=compound)
                worst = max(worst, float(np.max(np.abs(lobe.eval(N, N) / core - 1.0))))
            rows.append((model, "compound" if compound else "separate", len(betas), worst))
    return rows


def masking_energy(smoke: bool):
    """E_compound - E_separate (F = 1) for the mixture (1 - beta) D_n + beta D_w."""
    configs = [(0.05, 4.0)] if smoke else [(0.02, 5.0), (0.1, 4.0), (0.3, 2.0)]
    betas = [0.5] if smoke else [0.2, 0.5, 0.8]
    mus = [1.0, 0.1] if smoke else [1.0, 0.5, 0.2, 0.05]
    tol = 1e-5 if smoke else 1e-8
    rows = []
    for model in hazy.PEAK_MODELS:
        make = ab.microfacet.MODELS[model]
        for alpha_n, extent in configs:
            alpha_w = alpha_n * (1.0 + extent)
            narrow, wide = make(alpha_n), make(alpha_w)
            for beta in betas:
                separate = ab.composition.Sum(ab.lobes.Conductor.over(narrow),
                                        ab.lobes.Conductor.over(wide),
                                        weights=[1.0 - beta, beta])
                compound = ab.lobes.Conductor.over(ab.microfacet.Mixture(narrow, wide, beta))
                for mu in mus:
                    wo = _direction(mu)
                    e_s = float(separate.albedo(wo, tol=tol)[0])
                    e_c = float(compound.albedo(wo, tol=tol)[0])
                    rows.append((model, alpha_n, alpha_w, beta, mu, e_s, e_c))
    return rows


def glass_energy(smoke: bool):
    """HazyDielectric (Fig. 13 left: r_c = 0.04, alpha_n = 0.02, lambda_h = 4): eta and the
    reflected / transmitted energy at normal incidence and at 60 degrees, by Monte Carlo."""
    n = 20_000 if smoke else 2_000_000
    betas = [0.0, 0.5] if smoke else [0.0, 0.02, 0.05, 0.1, 0.3, 0.6, 0.9]
    rng = np.random.default_rng(13)
    rows = []
    for beta_h in betas:
        glass = hazy.HazyDielectric(0.04, beta_h, 4.0, 0.02)
        for mu in (1.0, 0.5):
            wo = _direction(mu)
            s = glass.sample(wo, rng.random((n, 3)))
            energy = s.weight[:, 0] * glass._energy_scale(np.broadcast_to(wo, s.wi.shape), s.wi)
            reflected = (s.flags & int(Flags.REFLECTION)) != 0
            r, t = energy * reflected, energy * ~reflected
            rows.append((beta_h, float(glass.eta), float(glass.mapping.beta), mu,
                         r.mean(), r.std() / np.sqrt(n), t.mean(), t.std() / np.sqrt(n)))
    return rows


# -- figures --------------------------------------------------------------------------------


def figure_kh(plt, path: Path, p: float):
    r_c = np.linspace(0.0, 1.0, 801)
    fig, ax = plt.subplots(figsize=(5.2, 3.6))
    with np.errstate(divide="ignore"):
        ax.plot(r_c, r_c / p, color="tab:red", lw=1.2, label="positivity $r_c/p$")
        ax.plot(r_c, (1 - r_c) / (1 - p), color="tab:red", lw=1.2, ls="--",
                label="energy $(1-r_c)/(1-p)$")
    for beta_h in (0.25, 0.5, 0.75, 1.0):
        ax.plot(r_c, hazy.haze_intensity(r_c, p, beta_h), color="black", lw=1.0)
    for w in (1.0, 2.0, 4.0, 8.0):
        ax.plot(r_c, hazy.haze_intensity_smooth(r_c, p, 1.0, w), color="0.55", lw=1.0)
    ax.plot([0, p, 1], [0, 1, 0], "o", color="tab:blue", ms=4, label=r"$p_0, p_1, p_2$")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1.1)
    ax.set_xlabel("core reflectivity $r_c$")
    ax.set_ylabel("haze intensity $k_h$")
    ax.set_title(f"eq. 7 (black, $\\beta_h$ = 0.25..1), eq. 15 (grey, w = 1, 2, 4, 8), p = {p:g}",
                 fontsize=8)
    ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def figure_slices(plt, path: Path, smoke: bool):
    theta_o = np.radians(30.0)
    wo = np.array([np.sin(theta_o), 0.0, np.cos(theta_o)])
    theta = np.linspace(-np.pi / 2 + 1e-3, np.pi / 2 - 1e-3, 181 if smoke else 1441)
    wi = np.stack([np.sin(theta), np.zeros_like(theta), np.cos(theta)], -1)
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.4), sharey=True)
    for ax, model in zip(axes, hazy.PEAK_MODELS, strict=True):
        for beta_h in (0.0, 0.25, 0.5, 0.75, 1.0):
            lobe = hazy.HazyGloss(0.5, beta_h, 7.0, 0.05, edge_tint=0.5, model=model)
            ax.semilogy(np.degrees(theta), lobe.eval(wo, wi)[:, 0] * wi[:, 2],
                        label=f"$\\beta_h$ = {beta_h:g}")
        ax.set_title(f"{model}: r_c = 0.5, $\\alpha_n$ = 0.05, $\\lambda_h$ = 7, "
                     "$\\theta_o$ = 30°", fontsize=8)
        ax.set_xlabel(r"$\theta_i$ (degrees, plane of incidence)")
        ax.set_ylim(1e-3, None)
    axes[0].set_ylabel(r"$f \cos\theta_i$ (red channel)")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# -- Markdown -------------------------------------------------------------------------------
def _markdown(peaks, invariance, masking, glass, figures, seconds):
    out = [
        "# Hazy gloss: measurements",
        "",
        generated_by("benchmarks.hazy_report", seconds, "hazy.md"),
        "",
        "## k_h against r_c [Barla2018, Fig. 3, left]",
        "",
    ]
    if not figures:
        out += ["*Figures left out: matplotlib is not installed (`pip install -e \".[bench]\"`).*",
                ""]
    for name, p in figures.get("kh", ()):
        out.append(f"![k_h against r_c, p = {p:g}](figures/{name})")
        out.append("")
    out += [
        "The red lines are the bounds of eq. 6, black is eq. 7 (`hazy.haze_intensity`) for "
        "β_h ∈ {0.25, 0.5, 0.75, 1}, grey is the rational Bézier form of eq. 15 "
        "(`hazy.haze_intensity_smooth`, β_h = 1) for w ∈ {1, 2, 4, 8}. The second plot has "
        "the p of Fig. 3's spheres (α_n = 0.01, λ_h = 7).",
        "",
        "## Peak ratio (Table 2) against the lobes",
        "",
        "p from `hazy.peak_ratio` against the ratio of the wide and narrow `Conductor` lobes' "
        "values at (n, n), F = 1.",
        "",
        "| model | (α_n, λ_h) pairs | max relative difference |",
        "|---|---|---|",
    ]
    out += [f"| {m} | {c} | {w:.1e} |" for m, c, w in peaks]
    out += [
        "",
        "## The core peak across haziness",
        "",
        "Max relative change of the composite's value at (n, n) against r_c f_n(n, n) over "
        "β_h ∈ [0, 1] (r_c = (0.9, 0.6, 0.3), g = 0.3, α_n = (0.02, 0.01), λ_h = 6).",
        "",
        "| model | masking | β_h values | max relative change |",
        "|---|---|---|---|",
    ]
    out += [f"| {m} | {k} | {n} | {w:.1e} |" for m, k, n, w in invariance]
    out += [
        "",
        "## Compound against separate masking (§3)",
        "",
        "Albedo with F = 1 of (1 − β) f_n + β f_w with separate Smith masking per lobe "
        "(E_sep) and of the same mixture with the compound Λ = (1 − β) Λ_n + β Λ_w (E_comp), "
        "by the library's adaptive quadrature.",
        "",
        "| model | α_n | α_w | β | cos θ_o | E_sep | E_comp | E_comp − E_sep |",
        "|---|---|---|---|---|---|---|---|",
    ]
    out += [f"| {m} | {an:g} | {aw:g} | {b:g} | {mu:g} | {es:.6f} | {ec:.6f} | {ec - es:+.2e} |"
            for m, an, aw, b, mu, es, ec in masking]
    diffs = np.array([ec - es for *_, es, ec in masking])
    out += [
        "",
        f"Largest |E_comp − E_sep|: {np.max(np.abs(diffs)):.2e}; the compound reading keeps "
        f"more energy in {int(np.sum(diffs > 0))} of {len(diffs)} cases.",
        "",
        "## The two-component BTDF (§4.2, Fig. 13 left)",
        "",
        "`HazyDielectric(0.04, β_h, 4, 0.02)`: the index grows with the haziness, so the "
        "interface reflects more and transmits less. Energies by Monte Carlo (± one standard "
        "error).",
        "",
        "| β_h | η | β | cos θ_o | reflected | transmitted |",
        "|---|---|---|---|---|---|",
    ]
    out += [f"| {b:g} | {eta:.4f} | {beta:.4f} | {mu:g} | {r:.4f} ± {re:.1e} | "
            f"{t:.4f} ± {te:.1e} |" for b, eta, beta, mu, r, re, t, te in glass]
    out += [
        "",
        "## Polar slices",
        "",
        f"![HazyGloss slices](figures/{figures['slices']})" if figures else "(left out)",
        "",
        "f cos θ_i in the plane of incidence: the halo rises with β_h while the value in "
        "the mirror direction of the narrow core hardly moves (exactly at normal incidence).",
        "",
    ]
    return "\n".join(out)


def run(smoke: bool = False, out: Path | None = None) -> Path:
    start = time.perf_counter()
    docs = DOCS if out is None else Path(out)
    (docs / "figures").mkdir(parents=True, exist_ok=True)
    peaks = peak_ratio_agreement(smoke)
    invariance = core_peak_invariance(smoke)
    masking = masking_energy(smoke)
    glass = glass_energy(smoke)
    figures = {}
    plt = pyplot()
    if plt is not None:
        figures = {"kh": [], "slices": "hazy_slices.png"}
        p_fig3 = float(hazy.peak_ratio((0.01, 0.01), hazy.wide_roughness(0.01, 0.01, 7.0)))
        for name, p in (("hazy_kh.png", 0.3), ("hazy_kh_fig3.png", p_fig3)):
            figure_kh(plt, docs / "figures" / name, p)
            figures["kh"].append((name, p))
        figure_slices(plt, docs / "figures" / figures["slices"], smoke)
    path = docs / "hazy_measured.md"
    path.write_text(_markdown(peaks, invariance, masking, glass, figures,
                              time.perf_counter() - start), encoding="utf-8")
    return path


def main(argv=None) -> int:
    return report_main(lambda out, smoke: run(smoke, out), __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    raise SystemExit(main())
