"""Measure the shipped tables and write ``docs/tables.md`` and ``docs/accuracy.md``.

    python -m benchmarks.tables_report [--queries 10000] [--quadrature-queries 200]

* interpolation error of every table at random off-node points against fresh node quadrature
  (``tables.ggx_energy`` at order 28), max and RMS, over the whole domain and over the
  region mu >= 0.01, alpha >= 0.0025 (roughness >= 0.05);
* the error of the anisotropic lookup alpha = sqrt(alpha_x alpha_y) (conductor, F = 1);
* the band of nearly index-matched, grazing queries (``energy_lookup.near_matched``): the raw
  tables there, the table path (which integrates there) and the tables just outside it;
* table sizes, bake times (from the files' metadata) and the time to load every table;
* ``albedo(method="table")`` against ``method="quadrature"`` on the same random queries: time
  per query and error against the node integrator.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from adobe_bsdf import lobes, tables
from adobe_bsdf.lobes import energy_lookup as near
from adobe_bsdf.tables import ggx_energy

DOCS = Path(__file__).resolve().parents[1] / "docs"
ORDER = 28


#: tables whose interpolation error another report measures, through the lobe's own lookup
#: (the sheen rescales small roughness: docs/sheen_measured.md)
OWN_REPORT = ("sheen_albedo",)


def _reference(name, coords):
    """Fresh values of table ``name`` at physical ``coords`` (summed channels kept apart)."""
    spec = tables.spec(name)
    if name == "ggx_conductor":
        return ggx_energy(*coords, order=ORDER).reflection[:, None]
    if name.startswith("ggx_dielectric"):
        mu, alpha, eta = coords
        e = ggx_energy(mu, alpha, eta if "outside" in name else 1.0 / eta, order=ORDER)
        return np.stack([e.reflection, e.transmission], -1)
    if name == "asm_diffuse_L":
        mu, r, ior = coords
        return ggx_energy(mu, r * r, ior, order=ORDER).reflection[:, None]
    raise ValueError(spec)


def interpolation_rows(n, rng):
    rows = []
    for name, spec in tables.SPECS.items():
        if spec.depends or name in OWN_REPORT:
            continue
        # uniform in each axis's range; half the points pushed into the small-mu /
        # small-alpha corner (fractions cubed), where the tables are hardest
        u = rng.random((len(spec.axes), n))
        corner = rng.random(n) < 0.5
        u[:2] = np.where(corner, u[:2] ** 3, u[:2])
        coords = [a.lo + (a.hi - a.lo) * f for a, f in zip(spec.axes, u, strict=True)]
        error = tables.get(name)(*coords) - _reference(name, coords)
        region = (coords[0] >= 0.01) & (coords[1] >= (0.05 if name == "asm_diffuse_L"
                                                      else 0.0025))
        channels = [(c, error[:, k]) for k, c in enumerate(spec.outputs)]
        if len(spec.outputs) == 2:
            channels.append(("E_R + E_T", error.sum(-1)))
        for channel, signed in channels:
            e = np.abs(signed)
            rows.append((name, channel, e.max(), np.sqrt(np.mean(e**2)), e[region].max(),
                         np.sqrt(np.mean(e[region] ** 2))))
    return rows


def anisotropy_rows(rng, n=50):
    """|E_table(sqrt(ax ay)) - quadrature of the anisotropic lobe| for F = 1."""
    rows = []
    for ax, ay in [(0.5, 0.1), (0.3, 0.05), (1.0, 0.25), (0.2, 0.02)]:
        lobe = lobes.Conductor(ax, ay)
        mu = rng.random(n) * 0.98 + 0.02
        phi = 2 * np.pi * rng.random(n)
        s = np.sqrt(1 - mu * mu)
        wo = np.stack([s * np.cos(phi), s * np.sin(phi), mu], -1)
        quad = np.array([lobe.albedo(w, tol=1e-7)[0] for w in wo])  # one grid per direction
        err = np.abs(lobe.albedo(wo, "table")[:, 0] - quad)
        rows.append((ax, ay, err.max(), np.sqrt(np.mean(err**2))))
    return rows


def speed_rows(n_table, n_quad, rng):
    """Conductor (F = 1) and dielectric single scattering: random (mu, alpha, eta) queries."""
    rows = []
    mu = 0.02 + 0.98 * rng.random(n_table)
    alpha = 0.01 + 0.99 * rng.random(n_table)
    eta = 1.05 + 1.95 * rng.random(n_table)
    side = np.where(rng.random(n_table) < 0.5, 1.0, -1.0)
    s = np.sqrt(1 - mu * mu)
    wo = np.stack([s, 0 * s, mu], -1)
    cases = [("Conductor, F = 1", lambda sel: lobes.Conductor(alpha[sel]), wo,
              lambda sel: ggx_energy(mu[sel], alpha[sel], order=ORDER).reflection),
             ("Dielectric, both sides", lambda sel: lobes.Dielectric(eta[sel], alpha[sel]),
              wo * side[:, None],
              lambda sel: _dielectric_reference(mu[sel], alpha[sel], eta[sel], side[sel]))]
    for label, make, directions, reference in cases:
        everything = np.arange(n_table)
        ref = reference(everything)
        start = time.perf_counter()
        table = make(everything).albedo(directions, "table")[:, 0]
        t_table = (time.perf_counter() - start) / n_table
        e_table = np.abs(table - ref)
        subset = everything[:n_quad]
        start = time.perf_counter()
        quad = np.array([make(i).albedo(directions[i], tol=1e-6)[0] for i in subset])
        t_quad = (time.perf_counter() - start) / n_quad
        e_quad = np.abs(quad - ref[subset])
        rows.append((label, "table", n_table, t_table, e_table.max(),
                     np.sqrt(np.mean(e_table**2))))
        rows.append((label, "table (same subset)", n_quad, t_table, e_table[subset].max(),
                     np.sqrt(np.mean(e_table[subset] ** 2))))
        rows.append((label, "quadrature, tol 1e-6", n_quad, t_quad, e_quad.max(),
                     np.sqrt(np.mean(e_quad**2))))
    return rows


def _band_points(rng, n, inside=True):
    """(mu, alpha, eps) log-uniform in the band (``inside``) or in the strips just outside it
    (cosine or |eta - 1| up to 10^0.5 times the band's bound, the other in the band)."""
    eps = 10.0 ** rng.uniform(-12, np.log10(near.MATCHED_ETA), n)
    mu = 10.0 ** rng.uniform(-12, np.log10(near.MATCHED_MU), n)
    if not inside:
        edge = rng.random(n) < 0.5
        mu = np.where(edge, near.MATCHED_MU * 10.0 ** rng.uniform(0, 0.5, n), mu)
        eps = np.where(edge, eps, near.MATCHED_ETA * 10.0 ** rng.uniform(0, 0.5, n))
    alpha = 10.0 ** rng.uniform(-3, np.log10(2.0), n)
    return mu, alpha, eps


def band_rows(rng, n):
    """Per side: max |error| of the raw tables in the band, of the table path there (E_R + E_T
    and E_R alone), of the tables just outside it, and the band's time per query."""
    rows = []
    for side, name in ((1, "ggx_dielectric_outside"), (-1, "ggx_dielectric_inside")):
        mu, alpha, eps = _band_points(rng, n)
        eta = 1.0 + eps if side > 0 else 1.0 / (1.0 + eps)
        ref = ggx_energy(mu, alpha, eta, order=ORDER)
        raw = tables.get(name)(mu, alpha, 1.0 + eps)
        wo = np.stack([np.sqrt(1.0 - mu * mu), np.zeros(n), mu], -1)
        keep = alpha * eps >= 2e-12  # pass-through lobes have no band
        start = time.perf_counter()
        total = np.array([lobes.Dielectric(e, a).albedo(w, method="table")[0]
                          for e, a, w in zip(eta[keep], alpha[keep], wo[keep], strict=True)])
        seconds = (time.perf_counter() - start) / keep.sum()
        reflected = np.array([lobes.DielectricReflection(e, a).albedo(w, method="table")[0]
                              for e, a, w in zip(eta[keep], alpha[keep], wo[keep],
                                                 strict=True)])
        mu_o, alpha_o, eps_o = _band_points(rng, n, inside=False)
        ref_o = ggx_energy(mu_o, alpha_o, 1.0 + eps_o if side > 0 else 1.0 / (1.0 + eps_o),
                           order=ORDER)
        out = tables.get(name)(mu_o, alpha_o, 1.0 + eps_o).sum(-1)
        rows.append((name, np.abs(raw.sum(-1) - ref.reflection - ref.transmission).max(),
                     np.abs(raw[:, 0] - ref.reflection).max(),
                     np.abs(total - (ref.reflection + ref.transmission)[keep]).max(),
                     np.abs(reflected - ref.reflection[keep]).max(),
                     np.abs(out - ref_o.reflection - ref_o.transmission).max(), seconds))
    return rows


def _dielectric_reference(mu, alpha, eta, side):
    rel = np.where(side > 0, eta, 1.0 / eta)
    e = ggx_energy(mu, alpha, rel, order=ORDER)
    return e.reflection + e.transmission


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--queries", type=int, default=10_000)
    parser.add_argument("--quadrature-queries", type=int, default=200)
    parser.add_argument("--points", type=int, default=4000, help="off-node points per table")
    parser.add_argument("--band-points", type=int, default=300,
                        help="points per side in the nearly index-matched band")
    args = parser.parse_args(argv)
    rng = np.random.default_rng(2026)

    tables.get.cache_clear()
    start = time.perf_counter()
    for name in tables.SPECS:
        tables.get(name)
    load_seconds = time.perf_counter() - start

    out = ["<!-- written by `python -m benchmarks.tables_report`; do not edit by hand -->", "",
           "# Energy tables: sizes, bake times, interpolation error", "",
           "| table | axes (nodes, parameterisation, interpolation) | outputs | file size | "
           "bake time (2 workers) | max node error estimate |", "|---|---|---|---|---|---|"]
    total = 0
    for name, spec in tables.SPECS.items():
        t = tables.get(name)
        size = tables.path(name).stat().st_size
        total += size
        axes = ", ".join(f"{a.name} {a.n} {a.parameterisation} {a.interpolation}"
                         for a in spec.axes)
        out.append(f"| `{name}` | {axes} | {', '.join(spec.outputs)} | {size / 1024:.0f} KiB | "
                   f"{t.meta['bake_seconds']:.1f} s | {t.errors.max():.1e} |")
    out += ["", f"All tables: {total / 2**20:.2f} MiB; loading and verifying all of them (hash "
            f"and declaration) takes {load_seconds:.2f} s.", "",
            "## Interpolation error at off-node points", "",
            f"{args.points} random points per table, half of them pushed into the small-mu / "
            "small-alpha corner (coordinates cubed), compared with fresh node quadrature "
            f"(order {ORDER}). *Region*: mu >= 0.01 and alpha >= 0.0025 (ASM roughness >= "
            "0.05), where the furnace acceptance is stated.", "",
            "| table | channel | max (all) | RMS (all) | max (region) | RMS (region) |",
            "|---|---|---|---|---|---|"]
    for row in interpolation_rows(args.points, rng):
        out.append("| `{}` | {} | {:.1e} | {:.1e} | {:.1e} | {:.1e} |".format(*row))
    out += ["", "## Anisotropic lookup", "",
            "Conductor, F = 1: albedo from the isotropic table at alpha = sqrt(alpha_x alpha_y) "
            "against direction-space quadrature of the anisotropic lobe (50 random wo, "
            "mu >= 0.02).", "", "| alpha_x | alpha_y | max error | RMS error |",
            "|---|---|---|---|"]
    for row in anisotropy_rows(rng):
        out.append("| {} | {} | {:.1e} | {:.1e} |".format(*row))
    out += ["", "## Nearly index-matched, grazing: the band integrated directly", "",
            f"Where max(eta, 1/eta) - 1 < {near.MATCHED_ETA:g} and cos theta_o < "
            f"{near.MATCHED_MU:g} a rough interface's energy depends on mu / |eta - 1| and "
            "mu / sqrt|eta - 1| (docs/conventions.md), which the tables' grid does not resolve: "
            "the table paths integrate there (``lobes.energy_lookup.near_matched``). "
            f"{args.band_points} points per side, log-uniform in mu in [1e-12, "
            f"{near.MATCHED_MU:g}], |eta - 1| in [1e-12, {near.MATCHED_ETA:g}], alpha in "
            f"[1e-3, 2]; *outside*: as many points with the cosine or |eta - 1| up to 10^0.5 "
            f"times beyond the band. Reference: the node integrator at order {ORDER}.", "",
            "| table | raw table, E_R + E_T | raw table, E_R | table path, E_R + E_T | "
            "table path, E_R | tables just outside | time per band query |",
            "|---|---|---|---|---|---|---|"]
    for name, *errors, seconds in band_rows(rng, args.band_points):
        out.append(f"| `{name}` | " + " | ".join(f"{e:.1e}" for e in errors)
                   + f" | {seconds * 1e3:.1f} ms |")
    (DOCS / "tables.md").write_text("\n".join(out) + "\n", encoding="utf-8")

    acc = ["<!-- written by `python -m benchmarks.tables_report`; do not edit by hand -->", "",
           "# Speed versus accuracy: directional albedo", "",
           f"Random queries: mu in [0.02, 1], alpha in [0.01, 1], eta in [1.05, 3], either "
           f"side for the dielectric. Reference: the node integrator at order {ORDER}. The "
           f"table path is timed on all {args.queries} queries in one vectorised call; the "
           f"quadrature path one query per call (its batch shares one grid) on the first "
           f"{args.quadrature_queries}.", "",
           "| lobe | method | queries | time per query | max error | RMS error |",
           "|---|---|---|---|---|---|"]
    rows = speed_rows(args.queries, args.quadrature_queries, rng)
    for label, method, n, t, emax, erms in rows:
        acc.append(f"| {label} | {method} | {n} | {t * 1e6:.3g} µs | {emax:.1e} | {erms:.1e} |")
    ratios = [rows[i + 2][3] / rows[i][3] for i in range(0, len(rows), 3)]
    acc += ["", "Quadrature / table time per query: " + ", ".join(
        f"{r:.0f}x ({rows[3 * k][0]})" for k, r in enumerate(ratios)) + "."]
    (DOCS / "accuracy.md").write_text("\n".join(acc) + "\n", encoding="utf-8")
    print("\n".join(out + [""] + acc))


if __name__ == "__main__":
    main()
