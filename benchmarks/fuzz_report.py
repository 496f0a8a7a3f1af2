"""Measure the LTC fuzz [Zeltner2022] beside the ASM sheen and write ``docs/fuzz_measured.md``
(with ``docs/figures/fuzz_albedo.png``).

    python -m benchmarks.fuzz_report [--smoke] [--out DIR]

- the directional albedo E(mu) of ``LTCSheen(1, alpha)`` (the fit ``albedo_fit``) and of the
  ASM's ``Sheen(1, r)`` (c = 2, its table) at r = alpha and at r = alpha^2, the same SGGX
  fibres (S = diag(1, 1, alpha^4));
- where the fit's clamp makes E = 0, and E and aInv at small roughness;
- the library's quadrature and Monte Carlo albedo of the lobe against the fit;
- how far the lobe is from reciprocal, on a grid of direction pairs.
"""

from __future__ import annotations

import time
import warnings
from pathlib import Path

import numpy as np

from adobe_bsdf.lobes.ltc_sheen import LTCSheen, albedo_fit, ltc_coefficients
from adobe_bsdf.lobes.sheen import Sheen
from benchmarks import generated_by, pyplot, report_main

DOCS = Path(__file__).resolve().parents[1] / "docs"
#: the page that documents the lobe (its docstring, in the API reference)
METHOD_PAGE = "reference.md"
ROUGHNESS = (0.1, 0.3, 0.5, 0.7, 1.0)
VALUE_MU = (1.0, 0.7, 0.5, 0.3, 0.1, 0.05, 0.02, 0.01)
SMALL_ALPHA = (1e-6, 1e-3, 0.01, 0.03, 0.05)
SMALL_MU = (1e-4, 1e-3, 0.01, 0.05, 0.2, 1.0)
RECIPROCITY_ALPHA = (0.05, 0.1, 0.3, 0.5, 0.7, 1.0)
METHOD_MU = (1.0, 0.5, 0.1, 0.02)


def _wo(mu):
    mu = np.asarray(mu, dtype=np.float64)
    return np.stack([np.sqrt(1.0 - mu * mu), np.zeros_like(mu), mu], -1)


def _asm(mu, r):
    """Albedo of ``Sheen(1, r)`` (c = 2) from its table."""
    return Sheen(1.0, r).albedo(_wo(mu), "table")[..., 0]


# -- measurements ------------------------------------------------------------------------------
def curves(smoke):
    """Albedo curves over cos theta_o in (0, 1] (both lobes are 0 at the horizon): the fuzz's
    ``albedo(wo, "table")``, the ASM sheen at r = alpha and r = alpha^2."""
    mu = np.linspace(0.0, 1.0, 21 if smoke else 401)[1:]
    return mu, {a: (LTCSheen(1.0, a).albedo(_wo(mu), "table")[..., 0], _asm(mu, a),
                    _asm(mu, a * a)) for a in ROUGHNESS}


def values():
    mu = np.array(VALUE_MU)
    return {a: (albedo_fit(mu, a), _asm(mu, a), _asm(mu, a * a)) for a in ROUGHNESS}


def clamp(smoke):
    """The fit's range on a (mu, alpha) grid, alpha > 0: the share of E = 0 (the clamp), the
    largest E and where; per alpha of ``ROUGHNESS`` the smallest mu of the grid with E = 0."""
    n = 101 if smoke else 1001
    mu, alpha = np.linspace(0.0, 1.0, n), np.linspace(0.0, 1.0, n)[1:]
    E = albedo_fit(mu[:, None], alpha[None, :])
    k = np.unravel_index(np.argmax(E), E.shape)
    first_zero = {}
    for a in ROUGHNESS:
        zero = albedo_fit(mu, a) == 0.0
        first_zero[a] = float(mu[np.argmax(zero)]) if zero.any() else None
    # o = y o^(y) < 0 between the roots of o^'s numerator 0.119681 y^2 - 0.0207818 y + ...
    roots = np.sort(np.roots([0.119681, -0.0207818, 0.000654023]).real)
    return {"n": (n, n - 1), "zero": float(np.mean(E == 0.0)), "max": (float(E[k]), mu[k[0]],
            alpha[k[1]]), "first_zero": first_zero, "o_negative": tuple(roots)}


def small():
    M, A = np.meshgrid(SMALL_MU, SMALL_ALPHA, indexing="ij")
    return albedo_fit(M, A), ltc_coefficients(M, A)[0]


def methods(smoke):
    """The library's adaptive quadrature (tol 1e-8) and Monte Carlo of ``LTCSheen(1, alpha)``
    against the fit, with the time per call."""
    n_mc = 1000 if smoke else 100_000
    rows = []
    for a in (ROUGHNESS[1:2] if smoke else ROUGHNESS):
        lobe = LTCSheen(1.0, a)
        for mu in (METHOD_MU[:2] if smoke else METHOD_MU):
            wo = _wo(mu)
            E = float(albedo_fit(mu, a))
            start = time.perf_counter()
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                quad, quad_err = (v[0] for v in lobe.albedo(wo, return_error=True))
            t_quad = time.perf_counter() - start
            mc, mc_err = (v[0] for v in lobe.albedo(wo, "mc", n_samples=n_mc, rng=len(rows),
                                                    return_error=True))
            rows.append((a, mu, E, quad - E, quad_err, t_quad, len(caught), mc - E, mc_err))
    return rows, n_mc


def reciprocity(smoke):
    """Per alpha, on pairs of cos theta in [0.05, 1] (both) x relative azimuth in [0, pi]:
    the largest |f(wo, wi) - f(wi, wo)| / max(f(wo, wi), f(wi, wo)) and where, the largest
    difference over the grid's largest f, the median relative difference where f > 0 and the
    share of pairs where only one of the two values is 0 (the clamp of E)."""
    mu = np.linspace(0.05, 1.0, 6 if smoke else 20)
    phi = np.linspace(0.0, np.pi, 5 if smoke else 13)
    Mo, Mi, P = np.meshgrid(mu, mu, phi, indexing="ij")
    wo = _wo(Mo)
    si = np.sqrt(1.0 - Mi * Mi)
    wi = np.stack([si * np.cos(P), si * np.sin(P), Mi], axis=-1)
    rows = []
    for a in RECIPROCITY_ALPHA:
        lobe = LTCSheen(1.0, a)
        forward, backward = lobe.eval(wo, wi)[..., 0], lobe.eval(wi, wo)[..., 0]
        difference, larger = np.abs(forward - backward), np.maximum(forward, backward)
        relative = difference / np.where(larger > 0.0, larger, 1.0)
        k = np.unravel_index(np.argmax(relative), relative.shape)
        live = larger > 0.0
        one_zero = np.mean((forward == 0.0) != (backward == 0.0))
        rows.append((a, float(relative[k]), Mo[k], Mi[k], np.degrees(P[k]),
                     float(difference.max() / larger.max()), float(np.median(relative[live])),
                     float(one_zero)))
    return rows, (len(mu), len(phi))


# -- figure and Markdown -----------------------------------------------------------------------
def figure(plt, path: Path, mu, data):
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8), sharey=True)
    titles = ("LTC fuzz E(μ, α)", "ASM sheen, r = α (c = 2)", "ASM sheen, r = α² (c = 2)")
    for i, (ax, title) in enumerate(zip(axes, titles, strict=True)):
        for a, curves_a in data.items():
            ax.plot(mu, curves_a[i], lw=1.3, label=f"α = {a:g}")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(r"$\mu_o = \cos\theta_o$")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("directional albedo")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _value_table(title, vals, which):
    out = [title, "", "| cos θo \\ α | " + " | ".join(f"{a:g}" for a in ROUGHNESS) + " |",
           "|---|" + "---|" * len(ROUGHNESS)]
    out += [f"| {m:g} | " + " | ".join(f"{vals[a][which][i]:.4f}" for a in ROUGHNESS) + " |"
            for i, m in enumerate(VALUE_MU)]
    return out + [""]


def _markdown(vals, clamps, small_fit, meth, recip, figures, seconds):
    out = [
        "# Fuzz: measurements",
        "",
        generated_by("benchmarks.fuzz_report", seconds, METHOD_PAGE),
        "",
        "The fuzz lobe `LTCSheen(color, α)` of `adobe_bsdf.lobes.ltc_sheen` [Zeltner2022] "
        "(OpenPBR's fuzz, [OpenPBR2026, §Fuzz]) beside the microflake sheen of the ASM, "
        "`Sheen(color, r)` [Kutz2021, §6] with its default c = 2, p = 1. α of [Zeltner2022] "
        "is the square root of the SGGX fibre cross section σ, the fibres' "
        "S = diag(1, 1, σ²); the ASM's S = diag(1, 1, r²) [Kutz2021, eq. 16]: the fibres are "
        "the same at r = α². The fuzz is a fit to the multiple scattering of a volume of such "
        "fibres; the ASM sheen is their single scattering, brightened by c = 2.",
        "",
        "## Directional albedo",
        "",
    ]
    if figures:
        out += ["![directional albedo](figures/fuzz_albedo.png)", ""]
    out += _value_table("LTC fuzz, E(cos θo, α) (the fit `albedo_fit`, which is the lobe's "
                        "albedo):", vals, 0)
    out += _value_table("ASM sheen at r = α, `Sheen(1, r).albedo(wo, \"table\")`:", vals, 1)
    out += _value_table("ASM sheen at r = α² (the same fibres):", vals, 2)
    (n_mu, n_alpha), (Emax, mu_max, a_max) = clamps["n"], clamps["max"]
    lo, hi = clamps["o_negative"]
    out += [
        "## The fit's clamp and small roughness",
        "",
        f"On a grid of {n_mu} cos θo × {n_alpha} α in (0, 1]: E = 0 (clamped from below) on "
        f"{100 * clamps['zero']:.1f} % of the points; the largest E is {Emax:.4f} (cos θo = "
        f"{mu_max:g}, α = {a_max:g}), so E never reaches the clamp at 1 there. The offset o of "
        f"the fit is negative for α in ({lo:.4f}, {hi:.4f}), where E is 0 wherever the "
        "Gaussian has died out. Smallest cos θo of the grid with E = 0, per α:",
        "",
        "| α | " + " | ".join(f"{a:g}" for a in ROUGHNESS) + " |",
        "|---|" + "---|" * len(ROUGHNESS),
        "| cos θo | " + " | ".join("none" if m is None else f"{m:g}"
                                   for m in clamps["first_zero"].values()) + " |",
        "",
        "Below α = 0.01 (the smallest α of the table the fits were made on) the fits are "
        "extrapolated. E and aInv, the width in w_z of the lobe's peak on the horizon:",
        "",
        "| cos θo \\ α | " + " | ".join(f"{a:g}" for a in SMALL_ALPHA) + " |",
        "|---|" + "---|" * len(SMALL_ALPHA),
    ]
    E, a = small_fit
    out += [f"| {m:g} | " + " | ".join(f"E {e:.2e}, aInv {x:.1e}" for e, x in
                                       zip(E[i], a[i], strict=True)) + " |"
            for i, m in enumerate(SMALL_MU)]
    rows, n_mc = meth
    out += [
        "",
        "## The lobe's albedo by quadrature and Monte Carlo",
        "",
        "D is a normalised distribution, so the lobe's albedo is the fit E exactly; here the "
        "library's adaptive quadrature (`albedo(wo)`, tol 1e-8) and Monte Carlo (`albedo(wo, "
        f"\"mc\")`, {n_mc} samples) against it, for color 1. Every sample weighs color E "
        "(exact importance sampling): the Monte Carlo estimate has no variance.",
        "",
        "| α | cos θo | E | quadrature − E | its error estimate | time | warnings | MC − E | "
        "MC σ |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    out += [f"| {a:g} | {mu:g} | {E:.6f} | {dq:+.1e} | {eq:.1e} | {tq * 1e3:.0f} ms | {nw} | "
            f"{dm:+.1e} | {em:.1e} |" for a, mu, E, dq, eq, tq, nw, dm, em in rows]
    rows, (n_mu, n_phi) = recip
    out += [
        "",
        "## Reciprocity",
        "",
        "E and M⁻¹ depend on cos θo alone, so f(wo, wi) ≠ f(wi, wo) [Zeltner2022]. Pairs: "
        f"{n_mu} cos θo × {n_mu} cos θi in [0.05, 1] × {n_phi} relative azimuths in [0°, 180°]; "
        "relative difference |f(wo, wi) − f(wi, wo)| / max(f(wo, wi), f(wi, wo)).",
        "",
        "| α | largest relative difference | at cos θo, cos θi, Δφ | largest difference / "
        "largest f | median relative difference (f > 0) | pairs with one value 0 |",
        "|---|---|---|---|---|---|",
    ]
    out += [f"| {a:g} | {r:.3f} | {mo:.2f}, {mi:.2f}, {p:.0f}° | {g:.3f} | {med:.3f} | "
            f"{100 * z:.1f} % |" for a, r, mo, mi, p, g, med, z in rows]
    out += ["", "Where E(cos θo) or E(cos θi) is clamped to 0 and the other is not, the "
            "relative difference is 1.", ""]
    return "\n".join(out)


def run(out: Path | None = None, smoke: bool = False) -> Path:
    start = time.perf_counter()
    docs = DOCS if out is None else Path(out)
    (docs / "figures").mkdir(parents=True, exist_ok=True)
    mu, data = curves(smoke)
    parts = (values(), clamp(smoke), small(), methods(smoke), reciprocity(smoke))
    figures = []
    plt = pyplot()
    if plt is not None:
        figure(plt, docs / "figures" / "fuzz_albedo.png", mu, data)
        figures = ["fuzz_albedo.png"]
    path = docs / "fuzz_measured.md"
    path.write_text(_markdown(*parts, figures, time.perf_counter() - start), encoding="utf-8")
    return path


def main(argv=None) -> int:
    return report_main(run, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    raise SystemExit(main())
