"""Speed against accuracy of every quantity the library computes by more than one path.

    python -m benchmarks.tradeoff [--smoke] [--figures DIR] [--json FILE]

Measured (``run``; ``markdown`` renders the section of ``docs/performance.md``):

* **directional albedo**, ``Lobe.albedo`` by ``"quadrature"`` (per ``tol``), ``"mc"`` (per
  ``n_samples``) and ``"table"``, at a grid of (mu, alpha) points: time per query (one
  direction per call; for ``"mc"`` and ``"table"`` also many directions in one call), the
  largest true error over the points, and the path's own error estimate (``return_error``)
  beside it, so that one can see whether the estimate is honest. Lobes and references:

  - ``Conductor(alpha)``, F = 1: ``tables.ggx_energy(mu, alpha)`` (node quadrature over
    microfacet normals, independent of the direction-space cubature), at two high orders
    whose difference is reported (converged when below 1e-12);
  - ``Dielectric(eta, alpha)``, eta = 1.5 and 1 / 1.5, E_R + E_T seen from ``wo`` above the
    surface: ``ggx_energy(mu, alpha, eta)`` (its ``eta`` is n_t / n_i seen from ``wo``, which
    for ``wo`` above is the lobe's ``eta``, n_below / n_above; checked below for ``wo`` under
    the surface against ``ggx_energy(mu, alpha, 1 / eta)``);
  - ``ConductorMultipleScattering(alpha)``, the Kulla–Conty term alone: its albedo is
    1 - E(mu_o) exactly for the tabulated E, i.e. its own table path (checked against
    quadrature at tol 1e-10); its integrand is only C1 (cubic interpolation of E in mu_i);
  - ``ConductorMS(alpha)`` (Kulla–Conty, F = 1): its albedo is 1 only up to the tables'
    interpolation error, so the reference is the quadrature path itself at tol 1e-10.

* **table throughput**: queries per second of ``Conductor(alpha).albedo(wo, "table")`` on
  10^6 random ``wo`` (mu uniform in (0, 1]), for one alpha and for a texture of alphas, at
  the default threads and at one, with and without ``return_error``, and the largest error
  against ``albedo(wo)`` (quadrature, default tol) on ~50 of those directions with
  mu >= 0.01, alpha >= 0.0025 (the project's target: >= 10^6 queries/s at error <= 1e-4).
* **chi-square test** (``validation.chi2_test``) of a Conductor with alpha = 0.3: time and
  p-value against the number of samples and the grid resolution.
* **white furnace**: cost of the quadrature albedo of ``ConductorMS`` and ``DielectricMS``
  against ``tol``, with |E - 1| and the estimate.

Timings: ``time.perf_counter``; median of 3 runs for calls under 0.25 s, one run otherwise.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import time
import warnings
from pathlib import Path

import numpy as np

from adobe_bsdf import config, lobes, tables
from adobe_bsdf.tables import ggx_energy
from adobe_bsdf.validation import chi2_test

__all__ = ["run", "markdown"]

DOCS = Path(__file__).resolve().parents[1] / "docs"
#: a call faster than this is repeated (median of REPEATS)
FAST, REPEATS = 0.25, 3
#: errors below this are drawn at this value on the log plots
ERROR_FLOOR = 1e-16


def _settings(smoke: bool) -> dict:
    if smoke:
        return dict(mu=(0.5,), alpha=(0.3,), etas=(1.5,), ref_orders=(28, 40),
                    tols=(1e-3, 1e-6), samples=(100, 1000), mc_batch=100, table_batch=10_000,
                    ms_ref_tol=1e-8, throughput_n=10_000, throughput_check=4,
                    chi2_samples=(10_000,), chi2_grids=((16, 32),), furnace_tols=(1e-4,),
                    furnace_batch_tol=1e-4)
    return dict(mu=(1.0, 0.5, 0.1), alpha=(0.05, 0.3, 1.0), etas=(1.5, 1 / 1.5),
                ref_orders=(80, 96), tols=(1e-3, 1e-4, 1e-5, 1e-6, 1e-8, 1e-10),
                samples=(100, 1000, 10_000, 100_000, 1_000_000), mc_batch=1000,
                table_batch=1_000_000, ms_ref_tol=1e-10, throughput_n=1_000_000,
                throughput_check=50, chi2_samples=(10_000, 100_000, 1_000_000, 10_000_000),
                chi2_grids=((16, 32), (32, 64), (64, 128), (128, 256)),
                furnace_tols=(1e-4, 1e-6, 1e-8), furnace_batch_tol=1e-6)


def _timed(fn, *args, **kwargs):
    """(median seconds, first result) of ``fn(*args, **kwargs)``; repeated only when fast."""
    start = time.perf_counter()
    result = fn(*args, **kwargs)
    times = [time.perf_counter() - start]
    if times[0] < FAST:
        for _ in range(REPEATS - 1):
            start = time.perf_counter()
            fn(*args, **kwargs)
            times.append(time.perf_counter() - start)
    return float(np.median(times)), result


def _directions(mu, phi=0.0):
    mu = np.asarray(mu, dtype=np.float64)
    s = np.sqrt(np.maximum(1.0 - mu * mu, 0.0))
    return np.stack([s * np.cos(phi), s * np.sin(phi), mu], -1)


def _ratio(error, estimate):
    """|error| / estimate elementwise: 0 for 0 / 0, inf for x / 0."""
    error, estimate = np.abs(error), np.asarray(estimate, dtype=np.float64)
    safe = np.where(estimate > 0.0, estimate, 1.0)
    return np.where(estimate > 0.0, error / safe, np.where(error > 0.0, np.inf, 0.0))


def _floats(x):
    """JSON-safe copy: numpy scalars and arrays to Python floats / lists, inf and NaN to None."""
    if isinstance(x, dict):
        return {k: _floats(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_floats(v) for v in x]
    if isinstance(x, np.ndarray):
        return _floats(x.tolist())
    if isinstance(x, bool | np.bool_):
        return bool(x)
    if isinstance(x, int | np.integer):
        return int(x)
    if isinstance(x, float | np.floating):
        return float(x) if math.isfinite(x) else None
    return x


# -- directional albedo: every path at every point ------------------------------------------
def _albedo_model(label, kind, make, mu, alpha, reference, reference_note, reference_check,
                  s, quad_tols, reference_is_table=False):
    """Rows (one per path and setting) for one lobe family at the points (mu[k], alpha[k]);
    ``kind``: "analytic" (closed-form eval) or "tabulated" (eval reads the tables)."""
    n = len(mu)
    wo = _directions(mu)
    rows = []

    def row(path, setting, batch, seconds, error, estimates, n_warnings=0, **extra):
        """``error``, ``estimates``: per point, or per batch element (then ``point`` maps
        elements to points and the per-point maxima are kept)."""
        error, estimates = np.abs(error), np.asarray(estimates)
        ratio = _ratio(error, estimates)
        point = extra.pop("point", None)
        if point is not None:
            error, estimates = (np.array([x[point == k].max() for k in range(n)])
                                for x in (error, estimates))
        out = dict(path=path, setting=setting, batch=batch,
                   time_per_query=float(np.mean(seconds)), times=np.atleast_1d(seconds),
                   errors=error, estimates=estimates, max_error=float(error.max()),
                   max_estimate=float(estimates.max()), max_ratio=float(ratio.max()),
                   warnings=n_warnings)
        out.update(extra)
        rows.append(out)

    for tol in quad_tols:
        seconds, values, estimates, caught = [], [], [], 0
        for k in range(n):
            with warnings.catch_warnings(record=True) as w:
                warnings.simplefilter("always")
                t, (v, e) = _timed(make(alpha[k]).albedo, wo[k], tol=tol, return_error=True)
            caught += len(w)
            seconds.append(t)
            values.append(v[0])
            estimates.append(e[0])
        row("quadrature", f"tol {_sci(tol)}", 1, np.array(seconds), np.array(values) - reference,
            estimates, caught, tol=tol)

    def mc_stats(values, estimates, ref):
        z = _ratio(values - ref, estimates)
        return dict(max_z=float(z.max()), rms_z=float(np.sqrt(np.mean(z**2))),
                    share_z_above_3=float(np.mean(z > 3.0)), n_z=int(z.size))

    for n_samples in s["samples"]:
        seconds, values, estimates = [], [], []
        for k in range(n):
            t, (v, e) = _timed(make(alpha[k]).albedo, wo[k], "mc", n_samples=n_samples, rng=k,
                               return_error=True)
            seconds.append(t)
            values.append(v[0])
            estimates.append(e[0])
        values, estimates = np.array(values), np.array(estimates)
        row("mc", f"{_sci(n_samples)} samples", 1, np.array(seconds), values - reference,
            estimates, n_samples=n_samples, **mc_stats(values, estimates, reference))
        if n_samples * s["mc_batch"] > 10_000_000:
            continue  # the whole batch's samples are held in memory at once
        # many directions in one call: the points repeated, each with its own draws
        pick = np.resize(np.arange(n), s["mc_batch"])
        lobe = make(np.asarray(alpha)[pick])
        t, (v, e) = _timed(lobe.albedo, wo[pick], "mc", n_samples=n_samples, rng=0,
                           return_error=True)
        row("mc", f"{_sci(n_samples)} samples", s["mc_batch"], t / s["mc_batch"],
            v[:, 0] - reference[pick], e[:, 0], n_samples=n_samples, point=pick,
            **mc_stats(v[:, 0], e[:, 0], reference[pick]))

    t_one, values, estimates = [], [], []
    for k in range(n):
        lobe = make(alpha[k])
        t, _ = _timed(lobe.albedo, wo[k], "table")  # timed without the error interpolation
        v, e = lobe.albedo(wo[k], "table", return_error=True)
        t_one.append(t)
        values.append(v[0])
        estimates.append(e[0])
    values, estimates = np.array(values), np.array(estimates)
    row("table", "", 1, np.array(t_one), values - reference, estimates)
    pick = np.resize(np.arange(n), s["table_batch"])
    lobe = make(np.asarray(alpha)[pick])
    t, _ = _timed(lobe.albedo, wo[pick], "table")
    v, e = lobe.albedo(wo[pick], "table", return_error=True)
    row("table", "", s["table_batch"], t / s["table_batch"], v[:, 0] - reference[pick],
        e[:, 0], point=pick)
    return dict(model=label, kind=kind, points=np.stack([mu, alpha], -1), reference=reference,
                reference_note=reference_note, reference_check=reference_check,
                reference_is_table=reference_is_table, rows=rows)


def _grid(s):
    m, a = np.meshgrid(s["mu"], s["alpha"], indexing="ij")
    return m.ravel(), a.ravel()


def _ggx_reference(mu, alpha, eta, orders):
    """E_R + E_T at the higher order, and |difference| to the lower one (max)."""
    values = []
    for order in orders:
        e = ggx_energy(mu, alpha, eta, order=order)
        values.append(e.reflection + e.transmission)
    return values[-1], float(np.abs(values[-1] - values[0]).max())


def _albedo_section(s):
    mu, alpha = _grid(s)
    lo, hi = s["ref_orders"]
    models = []
    ref, conv = _ggx_reference(mu, alpha, None, (lo, hi))
    models.append(_albedo_model(
        "Conductor, F = 1", "analytic", lambda a: lobes.Conductor(a), mu, alpha, ref,
        f"`tables.ggx_energy(mu, alpha, order={hi})`; |order {hi} - order {lo}| = {conv:.1e}"
        + (" (converged)" if conv < 1e-12 else " (**not** below 1e-12)"), conv, s, s["tols"]))
    side_checks = []
    for eta in s["etas"]:
        ref, conv = _ggx_reference(mu, alpha, eta, (lo, hi))
        label = f"Dielectric, eta = {'1/1.5' if eta < 1 else f'{eta:g}'}"
        models.append(_albedo_model(
            label, "analytic", lambda a, eta=eta: lobes.Dielectric(eta, a), mu, alpha, ref,
            f"E_R + E_T of `tables.ggx_energy(mu, alpha, eta, order={hi})`, `wo` above the "
            f"surface; |order {hi} - order {lo}| = {conv:.1e}"
            + (" (converged)" if conv < 1e-12 else " (**not** below 1e-12)"), conv, s,
            s["tols"]))
        # side convention: wo below the surface sees the relative index 1 / eta
        below = lobes.Dielectric(eta, alpha[0]).albedo(-_directions(mu[0]), tol=1e-9)[0]
        e = ggx_energy(mu[0], alpha[0], 1.0 / eta, order=hi)
        side_checks.append(dict(eta=eta, mu=mu[0], alpha=alpha[0],
                                difference=abs(below - (e.reflection + e.transmission))))
    # Kulla-Conty term alone: its albedo is 1 - E(mu_o) exactly for the tabulated E (E_avg is
    # the exact average of the interpolant), so the table path is the reference
    ref = np.array([lobes.ConductorMultipleScattering(a).albedo(_directions(m), "table")[0]
                    for m, a in zip(mu, alpha, strict=True)])
    check = max(abs(lobes.ConductorMultipleScattering(a).albedo(_directions(m),
                                                                tol=s["ms_ref_tol"])[0] - r)
                for m, a, r in zip(mu, alpha, ref, strict=True))
    models.append(_albedo_model(
        "Kulla–Conty term alone (ConductorMultipleScattering)", "tabulated",
        lambda a: lobes.ConductorMultipleScattering(a), mu, alpha, ref,
        "its table path, 1 - E(mu_o), exact for the tabulated E (the term's E_avg is the exact "
        "average of the interpolated E); |reference - quadrature at tol "
        f"{_sci(s['ms_ref_tol'])}| = {check:.1e}. The integrand is only C1 in mu_i (cubic "
        "interpolation of E between table nodes)", check, s,
        [t for t in s["tols"] if t > s["ms_ref_tol"]], reference_is_table=True))
    # ConductorMS: reference is the direction-space quadrature at a tight tol
    ref, est = [], []
    for k in range(len(mu)):
        v, e = lobes.ConductorMS(alpha[k]).albedo(_directions(mu[k]), tol=s["ms_ref_tol"],
                                                  return_error=True)
        ref.append(v[0])
        est.append(e[0])
    ref = np.array(ref)
    deviation = float(np.abs(ref - 1.0).max())
    models.append(_albedo_model(
        "ConductorMS, F = 1", "tabulated", lambda a: lobes.ConductorMS(a), mu, alpha, ref,
        f"`albedo(method='quadrature', tol={_sci(s['ms_ref_tol'])})` itself (its estimate "
        f"{max(est):.1e}); the reference's |E - 1| reaches {deviation:.1e}: the tables' "
        "interpolation error, which the table path cannot see (it returns E + (1 - E) = 1)",
        float(max(est)), s, [t for t in s["tols"] if t > s["ms_ref_tol"]]))
    models[-1]["furnace_deviation"] = deviation
    return models, side_checks


# -- table throughput ----------------------------------------------------------------------
def _throughput(s):
    """``Conductor(alpha).albedo(wo, "table")`` on random ``wo``: queries per second at the
    default threads and at 1 thread, the cost of ``return_error``, the generic 2-D table
    interpolation for comparison, and the error on a subsample against quadrature."""
    rng = np.random.default_rng(2026)
    n = s["throughput_n"]
    mu = 1.0 - rng.random(n)  # (0, 1]
    wo = _directions(mu, 2.0 * np.pi * rng.random(n))
    alpha_tex = np.exp(rng.uniform(np.log(0.0025), np.log(tables.ALPHA_MAX), n))
    out = {"n": n, "threads": config.get_options().threads}
    table = tables.get("ggx_conductor")
    check = np.flatnonzero(mu >= 0.01)[:s["throughput_check"]]
    for key, alpha in (("scalar", 0.3), ("texture", alpha_tex)):
        lobe = lobes.Conductor(alpha)
        t, values = _timed(lobe.albedo, wo, "table")
        with config.options(threads=1):
            t_one, _ = _timed(lobe.albedo, wo, "table")
        t_error, _ = _timed(lobe.albedo, wo, "table", return_error=True)
        t_generic, _ = _timed(table, mu, alpha)
        a = np.broadcast_to(alpha, mu.shape)
        quad = np.array([lobes.Conductor(a[i]).albedo(wo[i])[0] for i in check])
        exact = ggx_energy(mu[check], a[check], order=48).reflection
        out[key] = dict(seconds=t, queries_per_second=n / t, one_thread=t_one,
                        with_error=t_error, generic_interpolation=t_generic,
                        n_check=len(check), max_error=float(np.abs(values[check, 0] - quad).max()),
                        quadrature_vs_ggx=float(np.abs(quad - exact).max()),
                        alpha_range=[float(a.min()), float(a.max())])
    return out


# -- chi-square test and white furnace -----------------------------------------------------
def _chi2(s):
    lobe, wo = lobes.Conductor(0.3), _directions(0.5)
    rows = []
    for n_samples in s["chi2_samples"]:
        for n_theta, n_phi in s["chi2_grids"]:
            t, r = _timed(chi2_test, lobe, wo, n_samples=n_samples, n_theta=n_theta,
                          n_phi=n_phi)
            rows.append(dict(n_samples=n_samples, grid=[n_theta, n_phi], seconds=t,
                             p_value=r.p_value, passed=r.passed, dof=r.dof, n_evals=r.n_evals,
                             n_pooled=r.n_pooled))
    return rows


def _furnace(s):
    """Quadrature white furnace of the Kulla–Conty models, one direction per call, per tol;
    and all directions in one call at ``furnace_batch_tol`` (one grid shared by the batch)."""
    up = _directions(np.array(s["mu"]), 0.4)
    cases = [("ConductorMS, alpha 0.3", lobes.ConductorMS(0.3), up),
             ("DielectricMS, eta 1.5, alpha 0.3", lobes.DielectricMS(1.5, 0.3),
              np.concatenate([up, -up]))]
    rows = []
    for label, lobe, wo in cases:
        for tol in s["furnace_tols"]:
            timed = [_timed(lobe.albedo, w, tol=tol, return_error=True) for w in wo]
            v = np.array([r[0][0] for _, r in timed])
            e = np.array([r[1][0] for _, r in timed])
            rows.append(dict(lobe=label, tol=tol, directions=len(wo), per_call=1,
                             seconds=sum(t for t, _ in timed),
                             deviation=float(np.abs(v - 1.0).max()), estimate=float(e.max())))
        tol = s["furnace_batch_tol"]
        t, (v, e) = _timed(lobe.albedo, wo, tol=tol, return_error=True)
        rows.append(dict(lobe=label, tol=tol, directions=len(wo), per_call=len(wo), seconds=t,
                         deviation=float(np.abs(v - 1.0).max()), estimate=float(e.max())))
    return rows


def run(smoke: bool = False) -> dict:
    """Every measurement, as JSON-serialisable raw numbers (``markdown`` renders them)."""
    start = time.perf_counter()
    load_before = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    s = _settings(smoke)
    for name in tables.SPECS:  # load (and hash-check) outside the timings
        tables.get(name)
    with np.errstate(all="ignore"):
        models, side_checks = _albedo_section(s)
        out = dict(smoke=smoke, settings=s, albedo=models, side_checks=side_checks,
                   throughput=_throughput(s), chi2=_chi2(s), furnace=_furnace(s))
    out["machine"] = dict(cpus=os.cpu_count(), python=platform.python_version(),
                          numpy=np.__version__, processor=platform.machine(),
                          load_average=[load_before, os.getloadavg()[0] if hasattr(
                              os, "getloadavg") else None])
    out["seconds"] = time.perf_counter() - start
    return _floats(out)


# -- rendering -----------------------------------------------------------------------------
def _sci(x):
    """1e-03 -> 1e-3, 1e+04 -> 1e4."""
    mantissa, exponent = f"{x:.0e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def _fmt_time(seconds):
    if seconds is None:
        return "–"
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6), ("ns", 1e-9)):
        if seconds >= scale:
            return f"{seconds / scale:.3g} {unit}"
    return f"{seconds / 1e-9:.3g} ns"


def _num(x):
    """A ratio from the JSON (None: infinite)."""
    return np.inf if x is None else x


def _ratio_text(x):
    return "∞" if x is None else f"{x:.2g}"


def _worst(model, row, key):
    """(mu, alpha, value) of the point where per-point ``key`` ("errors" or "ratio") peaks."""
    errors, estimates = np.array(row["errors"]), np.array(row["estimates"])
    values = errors if key == "errors" else _ratio(errors, estimates)
    k = int(np.argmax(values))
    return model["points"][k][0], model["points"][k][1], float(values[k])


def _albedo_findings(results):
    """Sentences on the default quadrature, the honesty of the estimates and mc's z."""
    lines = []
    for kind, what in (("analytic", "lobes with a closed-form eval (Conductor, Dielectric)"),
                       ("tabulated", "lobes whose eval reads the tables (Kulla–Conty)")):
        rows = [(m, r) for m in results["albedo"] if m["kind"] == kind for r in m["rows"]
                if r["path"] == "quadrature" and r.get("tol") == 1e-8]
        if not rows:
            continue
        m, r = max(rows, key=lambda mr: mr[1]["max_error"])
        mu, alpha, err = _worst(m, r, "errors")
        mr, rr = max(rows, key=lambda mr: _num(mr[1]["max_ratio"]))
        mu2, alpha2, ratio = _worst(mr, rr, "ratio")
        lines.append(
            f"Quadrature at its default tol = 1e-8, {what}: true error at most {err:.1e} "
            f"({m['model']}, mu = {mu:g}, alpha = {alpha:g}); its own estimate at most "
            f"{max(r['max_estimate'] for _, r in rows):.1e}; largest true error / estimate "
            f"{ratio:.2g} ({mr['model']}, mu = {mu2:g}, alpha = {alpha2:g})"
            + (" — the estimate undershoots there." if ratio > 1 else "."))
    under = []
    for m in results["albedo"]:
        for r in m["rows"]:
            if r["path"] == "mc" and r["batch"] == 1 and _num(r["max_ratio"]) > 5:
                mu, alpha, z = _worst(m, r, "ratio")
                under.append(f"{m['model']}, {r['setting']}: z = {z:.3g} at mu = {mu:g}, "
                             f"alpha = {alpha:g}")
    if under:
        lines.append(
            "mc's standard error is dishonest where the lost energy comes from rare samples "
            "(an albedo within ~1/n of 1, or a loss concentrated in few directions): with no "
            "such sample among the n drawn, the weights look constant and the standard error "
            "collapses. Single-direction cases with z > 5: " + "; ".join(under) + ". The "
            "batched rows show the same over many draws.")
    tables_ = [(m, r) for m in results["albedo"] for r in m["rows"]
               if r["path"] == "table" and r["batch"] == 1 and not m["reference_is_table"]]
    if tables_:
        m, r = max(tables_, key=lambda mr: _num(mr[1]["max_ratio"]))
        mu, alpha, ratio = _worst(m, r, "ratio")
        lines.append(
            "The table path's `return_error` is the quadrature error of the table nodes "
            "carried through the interpolation, not the interpolation error "
            + (f"(`docs/tables.md`): it undershoots the true error by up to {ratio:.3g}x "
               if ratio > 1 else "(`docs/tables.md`); here it happened to cover the true "
               f"error (largest ratio {ratio:.2g}) ")
            + f"({m['model']}, mu = {mu:g}, alpha = {alpha:g}).")
    return lines


def _load(machine):
    return " / ".join("?" if x is None else f"{x:.1f}" for x in machine["load_average"])


def _e(x):
    return "∞" if x is None else f"{x:.1e}"


def _plots(results, figure_dir, smoke):
    """Write the PNGs; return {name: file name} (empty without matplotlib)."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return {}
    figure_dir.mkdir(parents=True, exist_ok=True)
    files = {}
    models = results["albedo"]
    cols = 2 if len(models) > 1 else 1
    rows_ = math.ceil(len(models) / cols)
    fig, axes = plt.subplots(rows_, cols, figsize=(6.2 * cols, 4.8 * rows_), squeeze=False)
    styles = {("quadrature", 1): ("C0", "o", "quadrature, 1 direction/call (tol)"),
              ("mc", 1): ("C1", "s", "mc, 1 direction/call (samples)"),
              ("mc", 0): ("C1", "D", "mc, batched (samples)"),
              ("table", 1): ("C2", "^", "table, 1 direction/call"),
              ("table", 0): ("C2", "v", "table, batched")}
    for ax, model in zip(axes.ravel(), models, strict=False):
        for (path, single), (color, marker, label) in styles.items():
            rows = [r for r in model["rows"] if r["path"] == path and (r["batch"] == 1) == single]
            if not rows:
                continue
            x = [r["time_per_query"] for r in rows]
            y = [max(r["max_error"], ERROR_FLOOR) for r in rows]
            ax.plot(x, y, marker=marker, color=color, ls="-" if path != "table" else "",
                    mfc=color if single else "none", label=label)
            ax.plot(x, [max(r["max_estimate"], ERROR_FLOOR) for r in rows], marker="x",
                    color=color, ls="", ms=5, alpha=0.6)
            for r, xi, yi in zip(rows, x, y, strict=True):
                if path == "quadrature":
                    text = _sci(r["tol"])
                elif path == "mc":
                    text = _sci(r["n_samples"])
                else:
                    continue
                ax.annotate(text, (xi, yi), fontsize=7, xytext=(3, 3),
                            textcoords="offset points", color=color)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(model["model"])
        ax.set_xlabel("time per query [s]")
        ax.set_ylabel("max |error| over the points (x: own estimate)")
        ax.grid(True, which="major", alpha=0.3)
    for ax in axes.ravel()[len(models):]:
        ax.axis("off")
    axes[0, 0].legend(fontsize=7, loc="best")
    fig.suptitle("Directional albedo: time per query against error" + (" (smoke)" if smoke
                                                                         else ""))
    fig.tight_layout(rect=(0, 0, 1, 0.98))
    files["albedo"] = "performance_tradeoff_albedo.png"
    fig.savefig(figure_dir / files["albedo"], dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6.2, 4.4))
    grids = sorted({tuple(r["grid"]) for r in results["chi2"]})
    for g in grids:
        rows = [r for r in results["chi2"] if tuple(r["grid"]) == g]
        ax.plot([r["n_samples"] for r in rows], [r["seconds"] for r in rows], "o-",
                label=f"{g[0]} x {g[1]} cells")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("samples")
    ax.set_ylabel("time of chi2_test [s]")
    ax.set_title("Chi-square test, Conductor alpha = 0.3, cos theta_o = 0.5")
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    files["chi2"] = "performance_tradeoff_chi2.png"
    fig.savefig(figure_dir / files["chi2"], dpi=110)
    plt.close(fig)
    return files


def _link(figure_dir, name):
    """Link to a figure from a Markdown file in ``figure_dir``'s parent (as ``docs/`` holds
    ``performance.md`` and ``figures/``)."""
    return f"{Path(figure_dir).name}/{name}"


def markdown(results: dict, figure_dir: Path, smoke: bool = False) -> str:
    """The Markdown section (tables, and links to the PNGs it writes into ``figure_dir``)."""
    figure_dir = Path(figure_dir)
    files = _plots(results, figure_dir, smoke)
    s = results["settings"]
    machine = results["machine"]
    out = ["## Speed versus accuracy", ""]
    if smoke:
        out += ["*Smoke run: one point, loose tolerances, few samples; the numbers only show "
                "that the benchmark runs.*", ""]
    out += [f"Measured by `benchmarks/tradeoff.py` in {results['seconds']:.0f} s on "
            f"{machine['cpus']} CPUs ({machine['processor']}, Python {machine['python']}, "
            f"NumPy {machine['numpy']}; 1-minute load average {_load(machine)} before / "
            f"after). Times are medians of {REPEATS} runs for calls under {FAST} s, else one "
            "run.", "",
            "### Directional albedo", "",
            f"Points: mu in {list(s['mu'])} x alpha in {list(s['alpha'])} (wo in the x-z "
            "plane). *Time per query*: mean over the points of the time of one call with one "
            f"direction (*1 / call*), or the time of one call on {s['mc_batch']} (mc) / "
            f"{s['table_batch']} (table) directions divided by their number (the points "
            "repeated). *Max error*: over the points (over every direction of the batch for "
            "mc). *Estimate*: the path's own error estimate (`return_error=True`: cubature "
            "sum of |I7 - I5|, mc standard error, table carried node error); *err / est* is "
            "the largest ratio of true error to estimate, above 1 where the estimate was "
            "smaller than the true error (for mc this is the largest z = |error| / standard "
            "error: a correct standard error gives about 3 at most, an RMS z of about 1 and "
            "0.3 % of z above 3).", ""]
    for model in results["albedo"]:
        out += [f"**{model['model']}.** Reference: {model['reference_note']}.", "",
                "| path | setting | directions / call | time per query | max error | "
                "max estimate | max err / est | mc: RMS z, share of z > 3 |",
                "|---|---|---|---|---|---|---|---|"]
        for r in model["rows"]:
            z = (f"{r['rms_z']:.2g}, {r['share_z_above_3']:.1%} of {r['n_z']}"
                 if r["path"] == "mc" else "")
            warn = f" ({r['warnings']} warnings)" if r.get("warnings") else ""
            out.append(f"| {r['path']} | {r['setting']}{warn} | {r['batch']} | "
                       f"{_fmt_time(r['time_per_query'])} | {_e(r['max_error'])} | "
                       f"{_e(r['max_estimate'])} | {_ratio_text(r['max_ratio'])} | {z} |")
        out.append("")
    for c in results["side_checks"]:
        out.append(f"Side convention: `Dielectric({c['eta']:.4g}, {c['alpha']:g})` seen from "
                   f"below at mu = {c['mu']:g} (quadrature, tol 1e-9) against "
                   f"`ggx_energy(mu, alpha, 1/eta)`: |difference| = {c['difference']:.1e}.")
    out += ["", "**Findings.**", ""] + [f"- {line}" for line in _albedo_findings(results)]
    out.append("")
    if "albedo" in files:
        out += [f"![time per query against error]({_link(figure_dir, files['albedo'])})", "",
                "Filled markers: one direction per call; hollow: batched; x: the path's own "
                f"error estimate at the same time. Errors below {ERROR_FLOOR:.0e} are drawn "
                "at it.", ""]

    tp = results["throughput"]
    out += ["### Table path throughput", "",
            f"`Conductor(alpha).albedo(wo, method=\"table\")` on {tp['n']} random `wo` (mu "
            "uniform in (0, 1]) in one call; *texture*: one alpha per query, log-uniform in "
            f"[{tp['texture']['alpha_range'][0]:.4g}, {tp['texture']['alpha_range'][1]:.3g}]. "
            f"Columns: time of that call at the default {tp['threads']} threads and its "
            "queries per second; the same at 1 thread (`config.options(threads=1)`); with "
            "`return_error=True` (node errors interpolated too); and, for comparison, the "
            "generic 2-D interpolation `tables.get(\"ggx_conductor\")(mu, alpha)` alone. "
            "Error: against `albedo(wo)` (quadrature, default tol) on the first "
            f"{tp['scalar']['n_check']} directions with mu >= 0.01; *quadrature vs "
            "ggx_energy* checks that reference.", "",
            "| alpha | time | queries / s | 1 thread: queries / s | with return_error | "
            "generic interpolation | max error | quadrature vs ggx_energy |",
            "|---|---|---|---|---|---|---|---|"]
    for key, label in (("scalar", "0.3"), ("texture", "texture")):
        r = tp[key]
        out.append(f"| {label} | {_fmt_time(r['seconds'])} | {r['queries_per_second']:.3g} | "
                   f"{tp['n'] / r['one_thread']:.3g} | {_fmt_time(r['with_error'])} | "
                   f"{_fmt_time(r['generic_interpolation'])} | {_e(r['max_error'])} | "
                   f"{_e(r['quadrature_vs_ggx'])} |")
    ok = all(tp[k]["queries_per_second"] >= 1e6 and tp[k]["max_error"] <= 1e-4
             for k in ("scalar", "texture"))
    out += ["", "Target (>= 10^6 queries/s at error <= 1e-4 against quadrature): "
            + ("met." if ok else "**not met**."), ""]

    out += ["### Chi-square test cost", "",
            "`validation.chi2_test(Conductor(0.3), wo, n_samples, n_theta, n_phi)`, cos "
            "theta_o = 0.5, seed 0 (one p-value per row: under a correct sampler it is "
            "uniform in [0, 1]).", "",
            "| samples | grid | time | p-value | dof | pooled cells | pdf evaluations |",
            "|---|---|---|---|---|---|---|"]
    for r in results["chi2"]:
        out.append(f"| {_sci(r['n_samples'])} | {r['grid'][0]} x {r['grid'][1]} | "
                   f"{_fmt_time(r['seconds'])} | {r['p_value']:.3f} | {r['dof']} | "
                   f"{r['n_pooled']} | {r['n_evals']} |")
    if "chi2" in files:
        out += ["", f"![chi-square time against samples]({_link(figure_dir, files['chi2'])})"]
    out += ["", "### White furnace cost", "",
            f"Quadrature albedo of the Kulla–Conty models at cos theta_o in {list(s['mu'])} "
            "(both sides for the dielectric): one direction per call (time summed over the "
            "directions), or all in one call (one grid shared by the batch, refined wherever "
            "any direction needs it). |E - 1| converges to the tables' interpolation error, "
            "not to 0. `validation.furnace(lobe, wo, expected, method, tol)` always runs the "
            "albedo at its default tol 1e-8: its own `tol` is the pass threshold, so an albedo "
            "`tol` cannot reach `albedo` through `**albedo_options` (a `TypeError`).", "",
            "| lobe | albedo tol | directions | per call | time | max \\|E - 1\\| | "
            "max estimate |", "|---|---|---|---|---|---|---|"]
    for r in results["furnace"]:
        out.append(f"| {r['lobe']} | {_sci(r['tol'])} | {r['directions']} | {r['per_call']} | "
                   f"{_fmt_time(r['seconds'])} | {_e(r['deviation'])} | {_e(r['estimate'])} |")
    return "\n".join(out) + "\n"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true")
    parser.add_argument("--figures", type=Path, default=DOCS / "figures")
    parser.add_argument("--json", type=Path, help="also write the raw numbers here")
    args = parser.parse_args(argv)
    results = run(args.smoke)
    if args.json:
        args.json.write_text(json.dumps(results, indent=1), encoding="utf-8")
    print(markdown(results, args.figures, args.smoke))


if __name__ == "__main__":
    main()
