"""Measure the ASM sheen [Kutz2021, §6] and write ``docs/sheen_measured.md``.

    python -m benchmarks.sheen_report [--smoke] [--out DIR]

- the largest directional albedo with c = 1 and c = 2 over a fine (cos theta_o, r) grid of
  fresh node quadrature (``tables.catalog.sheen_energy``), where it occurs, and whether every
  roughness's albedo falls monotonically from grazing;
- E(mu, r) at a few values, and albedo curves over theta_o for c = 2;
- the interpolation error of ``albedo(method="table")`` (``tables`` "sheen_albedo", read through
  the small-roughness similarity of ``lobes.sheen``) at random off-node points and on a sweep of
  the grazing / small-roughness corner, against fresh quadrature;
- the library's quadrature, Monte Carlo and the table against the node quadrature, with
  timings;
- the fraction of visible-normal samples that succeed (land above the horizon).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from adobe_bsdf import tables
from adobe_bsdf.lobes.sheen import R_SIMILAR, Sheen
from adobe_bsdf.tables.catalog import sheen_energy
from benchmarks import generated_by, report_main, write_page


def _wo(mu):
    mu = np.asarray(mu, dtype=np.float64)
    return np.stack([np.sqrt(1.0 - mu * mu), np.zeros_like(mu), mu], -1)


def _table(lobe, mu):
    return lobe.albedo(_wo(mu), "table")[..., 0]


# -- measurements ------------------------------------------------------------------------------
def largest_albedo(smoke):
    """E of c a = 1 on a (mu, r) grid by fresh node quadrature."""
    n = 8 if smoke else 60
    mu = np.unique(np.concatenate([[0.0], np.logspace(-7, -2, n // 2 + 1),
                                   np.linspace(0.01, 1.0, n)]))
    r = np.unique(np.concatenate([np.logspace(-4, -1, n // 3 + 1), np.linspace(0.1, 1.0, n)]))
    M, R = np.meshgrid(mu, r, indexing="ij")
    E = sheen_energy(M.ravel(), R.ravel())[0].reshape(M.shape)
    off = mu > 0
    k, m = np.unravel_index(np.argmax(E[off]), E[off].shape)
    far = mu >= 0.01
    a, b = np.unravel_index(np.argmax(E[far]), E[far].shape)
    rises = float(np.max(np.diff(E[off], axis=0)))
    at_first = bool(np.all(np.argmax(E[off], axis=0) == 0))
    node = tables.get("sheen_albedo").values[..., 0]
    return {"n_mu": len(mu), "n_r": len(r), "max": float(E.max()),
            "grazing": float(np.max(np.abs(E[0] - 0.5))),
            "max_positive": (E[off][k, m], mu[off][k], r[m]),
            "max_far": (E[far][a, b], mu[far][a], r[b]), "largest_rise": rises,
            "first_mu": float(mu[off][0]), "largest_at_first": at_first,
            "table_max": float(node.max()),
            "table_rise": float(np.max(np.diff(node[:, 1:], axis=0)))}


NORMAL_R = (1e-3, 0.01, 0.03, 0.05, 0.08, 0.1, 0.15, 0.2, 0.5, 1.0)


def near_normal(smoke):
    """The minimum of E over cos theta_o in [0.9, 1] per roughness, against E(1)."""
    mu = np.linspace(0.9, 1.0, 11 if smoke else 201)
    rows = []
    for r in NORMAL_R:
        E = sheen_energy(mu, r)[0]
        i = int(np.argmin(E))
        rows.append((r, mu[i], E[i], E[-1], (E[-1] - E[i]) / E[-1]))
    return rows, len(mu)


VALUE_MU = (1.0, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01, 0.001)
VALUE_R = (0.05, 0.1, 0.2, 0.4, 0.6, 0.8, 1.0)


def values():
    M, R = np.meshgrid(VALUE_MU, VALUE_R, indexing="ij")
    return sheen_energy(M, R)[0]


CURVE_THETA = (0, 15, 30, 45, 60, 70, 80, 85, 88, 89, 89.9)
CURVE_R = (0.1, 0.3, 0.5, 0.8, 1.0)


def curves():
    """E(theta_o) of c = 2, a = 1 by node quadrature."""
    T, R = np.meshgrid(np.radians(CURVE_THETA), CURVE_R, indexing="ij")
    return 2.0 * sheen_energy(np.cos(T), R)[0]


def interpolation(smoke):
    """|table lookup - fresh quadrature| for c a = 1: random points (half pushed into the
    small-(mu, r) corner, fractions to the fourth power) and a sweep of that corner."""
    rng = np.random.default_rng(5)
    n = 200 if smoke else 8000
    u = rng.random((2, n))
    corner = rng.random(n) < 0.5
    mu, r = np.where(corner, u**4, u)
    ref = sheen_energy(mu, r)[0]
    err = np.abs(_table(Sheen(1.0, r, c=1.0), mu) - ref)
    small = r < R_SIMILAR
    direct = np.abs(tables.get("sheen_albedo")(mu[small], r[small])[:, 0] - ref[small])
    regions = [("all points", np.ones(n, bool)), ("cos θo ≥ 1e-4", mu >= 1e-4),
               ("cos θo ≥ 1e-2", mu >= 1e-2), (f"r ≥ R_SIMILAR = {R_SIMILAR:g}", ~small),
               (f"r < {R_SIMILAR:g} (similarity)", small)]
    rows = [(name, int(m.sum()), float(err[m].max()), float(np.sqrt(np.mean(err[m] ** 2))))
            for name, m in regions if m.any()]
    worst = int(np.argmax(err))
    k = 6 if smoke else 41
    sweep_mu = np.concatenate([[1e-12], np.logspace(-9, -3, k)])
    sweep_r = np.logspace(-7, 0, k + 10)
    M, R = np.meshgrid(sweep_mu, sweep_r, indexing="ij")
    sweep = np.abs(_table(Sheen(1.0, R.ravel(), c=1.0), M.ravel())
                   - sheen_energy(M.ravel(), R.ravel())[0]).reshape(M.shape)
    s = np.unravel_index(np.argmax(sweep), sweep.shape)
    above = sweep[sweep_mu >= 1e-4]
    return {"n": n, "rows": rows, "worst": (float(err[worst]), mu[worst], r[worst]),
            "direct": (float(direct.max()) if direct.size else float("nan"), int(small.sum())),
            "sweep": (float(sweep.max()), M[s], R[s], M.size),
            "sweep_above": float(above.max()) if above.size else float("nan")}


def table_facts():
    t = tables.get("sheen_albedo")
    path = tables.path("sheen_albedo")
    return {"shape": t.values.shape[:-1], "kib": path.stat().st_size / 1024,
            "bake": t.meta.get("bake_seconds"), "node_error": float(t.errors.max()),
            "axes": [(a.name, a.n, a.parameterisation, a.log_scale) for a in t.spec.axes]}


def methods(smoke):
    """The library's quadrature, Monte Carlo (n samples) and the table against node
    quadrature for c = 2, a = 1, with the time per call."""
    n_mc = 20_000 if smoke else 1_000_000
    rows = []
    for r in (0.1, 0.5, 1.0):
        lobe = Sheen(1.0, r)
        for mu in (1.0, 0.5, 0.1, 0.01):
            seed = len(rows)
            wo = _wo(mu)
            start = time.perf_counter()
            node = 2.0 * float(sheen_energy(mu, r)[0])
            t_node = time.perf_counter() - start
            start = time.perf_counter()
            quad, quad_err = (v[0] for v in lobe.albedo(wo, return_error=True))
            t_quad = time.perf_counter() - start
            start = time.perf_counter()
            mc, mc_err = (v[0] for v in lobe.albedo(wo, "mc", n_samples=n_mc, rng=seed,
                                                    return_error=True))
            t_mc = time.perf_counter() - start
            table = float(lobe.albedo(wo, "table")[0])
            rows.append((r, mu, node, quad - node, quad_err, t_quad, mc - node, mc_err, t_mc,
                         table - node, t_node))
    n = 10_000 if smoke else 1_000_000
    rng = np.random.default_rng(2)
    wo = _wo(rng.random(n))
    lobe = Sheen(1.0, 0.4)
    lobe.albedo(wo[:10], "table")  # load the table outside the timing
    start = time.perf_counter()
    lobe.albedo(wo, "table")
    per_lookup = (time.perf_counter() - start) / n
    return rows, n_mc, per_lookup, n


SUCCESS_MU = (1.0, 0.5, 0.2, 0.05, 0.01)
SUCCESS_R = (0.01, 0.1, 0.3, 0.5, 1.0)


def success(smoke):
    """Fraction of visible-normal samples above the horizon (the integral of the pdf)."""
    n = 20_000 if smoke else 400_000
    rng = np.random.default_rng(3)
    out = np.zeros((len(SUCCESS_MU), len(SUCCESS_R)))
    for j, r in enumerate(SUCCESS_R):
        wo = _wo(np.repeat(SUCCESS_MU, n))
        s = Sheen(1.0, r).sample(wo, rng.random((wo.shape[0], 3)))
        out[:, j] = (s.pdf > 0).reshape(len(SUCCESS_MU), n).mean(axis=1)
    return out, n


# -- Markdown ----------------------------------------------------------------------------------
def _markdown(big, normal, vals, curve, interp, facts, meth, succ, seconds):
    Ep, mup, rp = big["max_positive"]
    Ef, muf, rf = big["max_far"]
    out = [
        "# Sheen: measurements",
        "",
        generated_by("benchmarks.sheen_report", seconds, "sheen.md"),
        "",
        "## Largest albedo",
        "",
        f"Fresh node quadrature (`tables.catalog.sheen_energy`, order 16) of the albedo E of "
        f"c a = 1 on {big['n_mu']} values of cos θo (0, i.e. the grazing limit, log-spaced "
        f"from 1e-7 and uniform to 1) × {big['n_r']} roughnesses (log-spaced from 1e-4 and "
        "uniform to 1). With c = 2 every value doubles.",
        "",
        "| | E (c = 1) | E (c = 2) | cos θo | r |",
        "|---|---|---|---|---|",
        f"| grazing limit cos θo → 0 (every r; max \\|E − 1/2\\| = {big['grazing']:.0e}) "
        f"| {big['max']:.12f} | {2 * big['max']:.12f} | 0 | all |",
        f"| largest at cos θo > 0 | {Ep:.12f} | {2 * Ep:.12f} | {mup:.1e} | {rp:.3g} |",
        f"| largest at cos θo ≥ 0.01 | {Ef:.6f} | {2 * Ef:.6f} | {muf:.3g} | {rf:.3g} |",
        "",
        ("At every roughness the largest E over cos θo > 0 is at the smallest cos θo of the "
         f"grid ({big['first_mu']:g}), " if big["largest_at_first"] else
         "At some roughness the largest E over cos θo > 0 is NOT at the smallest cos θo of "
         "the grid, ")
        + f"and no table node exceeds 1/2 by more than rounding (largest: "
        f"{big['table_max']:.15f}): with c = 2 the largest albedo is the grazing limit 1, "
        "reached by no direction above the horizon, so the sheen conserves energy with no "
        "margin at grazing.",
        "",
    ]
    rows, n_normal = normal
    rising = [r for r, _, _, _, rel in rows if rel > 0.0]
    out += [
        f"Largest change of E from one cos θo of the grid to the next larger: "
        f"{big['largest_rise']:+.1e} (over the table's nodes, r > 0: "
        f"{big['table_rise']:+.1e}). "
        + (f"E is not monotonic everywhere: for r ≤ {max(rising):g} of the roughnesses below it "
           "has a shallow minimum short of normal incidence and rises again towards it."
           if rising else "Near normal incidence too, E falls monotonically:"),
        "",
        f"| r | cos θo of the minimum over [0.9, 1] ({n_normal} values) | E there | E(1) | "
        "(E(1) − min) / E(1) |",
        "|---|---|---|---|---|",
    ]
    out += [f"| {r:g} | {m:.4f} | {e:.4e} | {e1:.4e} | {rel:.1e} |" for r, m, e, e1, rel in rows]
    out += [
        "",
        "## E(cos θo, r), c a = 1",
        "",
        "| cos θo \\ r | " + " | ".join(f"{x:g}" for x in VALUE_R) + " |",
        "|---|" + "---|" * len(VALUE_R),
    ]
    out += [f"| {m:g} | " + " | ".join(f"{v:.6f}" for v in row) + " |"
            for m, row in zip(VALUE_MU, vals, strict=True)]
    out += [
        "",
        "## Albedo curves, c = 2, a = 1",
        "",
        "| θo (degrees) \\ r | " + " | ".join(f"{x:g}" for x in CURVE_R) + " |",
        "|---|" + "---|" * len(CURVE_R),
    ]
    out += [f"| {t:g} | " + " | ".join(f"{v:.4f}" for v in row) + " |"
            for t, row in zip(CURVE_THETA, curve, strict=True)]
    (mu_name, n_mu, p_mu, c_mu), (r_name, n_r, p_r, c_r) = facts["axes"]
    w_err, w_mu, w_r = interp["worst"]
    s_err, s_mu, s_r, s_n = interp["sweep"]
    out += [
        "",
        "## The table `sheen_albedo`",
        "",
        f"{n_mu} × {n_r} nodes ({mu_name} and {r_name}, {p_mu} with log_scale {c_mu:g} and "
        f"{c_r:g}, cubic), {facts['kib']:.0f} KiB, baked in {facts['bake']} s (2 workers); "
        f"largest node error estimate |Q(16) − Q(10)|: {facts['node_error']:.1e}.",
        "",
        f"Interpolation error of `Sheen(1, r, c=1).albedo(wo, \"table\")` against fresh "
        f"quadrature at {interp['n']} random points (half of them with both coordinates "
        "raised to the fourth power, into the grazing / small-roughness corner); below "
        f"r = {R_SIMILAR:g} the lookup goes through the similarity E(μ, r) ≈ "
        "E(min(μ R / r, 1), R).",
        "",
        "| points | count | max | RMS |",
        "|---|---|---|---|",
    ]
    out += [f"| {name} | {k} | {mx:.1e} | {rms:.1e} |" for name, k, mx, rms in interp["rows"]]
    direct, n_small = interp["direct"]
    out += [
        "",
        f"Worst random point: {w_err:.1e} at cos θo = {w_mu:.1e}, r = {w_r:.1e}. Reading the "
        f"table directly at the {n_small} points with r < {R_SIMILAR:g} instead: max "
        f"{direct:.1e}.",
        "",
        f"Sweep of the corner ({s_n} points, cos θo ∈ {{1e-12}} ∪ [1e-9, 1e-3], r ∈ [1e-7, 1], "
        f"log-spaced): max {s_err:.1e} at cos θo = {s_mu:.1e}, r = {s_r:.1e}; at "
        f"cos θo ≥ 1e-4: max {interp['sweep_above']:.1e}.",
        "",
        "## Albedo methods against the node quadrature (c = 2, a = 1)",
        "",
    ]
    rows, n_mc, per_lookup, n_lookup = meth
    out += [
        f"E: node quadrature. Differences of the library's adaptive quadrature (`tol = 1e-8`), "
        f"Monte Carlo ({n_mc} samples, ± one standard error) and the table; times per call "
        "(one direction).",
        "",
        "| r | cos θo | E | quadrature − E | its error estimate | time | MC − E | MC σ | "
        "time | table − E | node quadrature time |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    out += [f"| {r:g} | {mu:g} | {E:.8f} | {dq:+.1e} | {eq:.1e} | {tq * 1e3:.0f} ms | "
            f"{dm:+.1e} | {em:.1e} | {tm * 1e3:.0f} ms | {dt:+.1e} | {tn * 1e3:.1f} ms |"
            for r, mu, E, dq, eq, tq, dm, em, tm, dt, tn in rows]
    out += [
        "",
        f"Table lookups with scalar roughness: {per_lookup * 1e9:.0f} ns per direction "
        f"({n_lookup} directions in one call).",
        "",
        "## Success of the visible-normal sampler",
        "",
    ]
    fractions, n = succ
    out += [
        f"Fraction of samples that land above the horizon ({n} samples each; the rest fail "
        "with weight and pdf 0). It is the integral of the pdf over the hemisphere. Where it "
        "is small the Monte Carlo albedo is noisy although E is small too.",
        "",
        "| cos θo \\ r | " + " | ".join(f"{x:g}" for x in SUCCESS_R) + " |",
        "|---|" + "---|" * len(SUCCESS_R),
    ]
    out += [f"| {m:g} | " + " | ".join(f"{v:.4f}" for v in row) + " |"
            for m, row in zip(SUCCESS_MU, fractions, strict=True)]
    out.append("")
    return "\n".join(out)


def run(out: Path | None = None, smoke: bool = False) -> Path:
    return write_page(out, "sheen_measured.md",
                      lambda: (largest_albedo(smoke), near_normal(smoke), values(), curves(),
                               interpolation(smoke), table_facts(), methods(smoke),
                               success(smoke)), _markdown)


def main(argv=None) -> int:
    return report_main(run, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    raise SystemExit(main())
