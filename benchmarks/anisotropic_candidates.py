"""Representations of an anisotropic rough dielectric's single-scattering energy, measured
before one is chosen; writes ``docs/anisotropic_candidates_measured.md``.

    python -m benchmarks.anisotropic_candidates [--smoke] [--out DIR]

The quantity: E(wo) = E_R + E_T of an anisotropic GGX dielectric interface (exact Fresnel,
height-correlated Smith), the energy a Kulla–Conty term restores to 1, over five coordinates
per side (mu, phi, alpha_x, alpha_y, eta). The reference is the stretched node quadrature
``tables.anisotropic_energy.ggx_anisotropic_dielectric_energy`` at ``REFERENCE_ORDER`` (at
``CHECK`` points also at ``CHECK_ORDER``: the reference's own error).

Held-out points (seed 20261206): mu uniform in [0.01, 1], phi in [0, pi / 2], alpha_x in
[0.02, 1], alpha_y = ratio alpha_x with ratio in [0, 1], eta log-uniform in [1.01, 3], seen
from the light side (eta) and from the dense side (1 / eta).

Candidates:

* **isotropic proxies**: the isotropic node quadrature ``tables.energy.ggx_energy`` (what the
  isotropic tables hold) at one roughness: the geometric mean sqrt(alpha_x alpha_y) (the
  default table mode today), wo's projected roughness, the RMS of the two;
* **isotropic proxy + the conductor's anisotropy**: the same, corrected by the F = 1
  conductor's anisotropic energy against its isotropic energy at that roughness, added or
  as a ratio of the losses;
* **a per-lobe rule**: the order x order Gauss product rule over the two uniforms of the
  visible-normal sampler [Heitz2018], both branches (the cost of a per-lobe slice at first
  use, in ms per view);
* **a grid of slices**: ``tables.dielectric_slices`` slices (the exact mode's tables, in
  coordinates aligned with the critical angle and the kinks of a nearly one-dimensional
  surface) at neighbouring (alpha, ratio, eta), interpolated across them (Catmull-Rom, the
  target midway) at the target slice's nodes and cell midpoints: the error of a five-
  dimensional table of slices at that spacing, per axis (log alpha, log ratio,
  log(eta - 1)).

Measured on the shipped grid of slices itself (``grid_studies``): one reduced basis (SVD)
per half of the grid, against held-out slices; and a residual over the isotropic energy at
the projected roughness, interpolated across grid points at twice and four times the grid's
step, against the energy interpolated itself.
"""

from __future__ import annotations

import datetime
import time
from pathlib import Path

import numpy as np

from adobe_bsdf.microfacet import GGX
from adobe_bsdf.tables.anisotropic_energy import (
    ggx_anisotropic_dielectric_energy,
    ggx_anisotropic_energy,
)
from adobe_bsdf.tables.dielectric_slices import dielectric_slice
from adobe_bsdf.tables.energy import ggx_energy
from benchmarks import machine, report_main, write_page

NAME = "anisotropic_candidates_measured.md"
SEED = 20261206
POINTS, SMOKE_POINTS = 300, 8
REFERENCE_ORDER, CHECK_ORDER, CHECK = 12, 20, 24
ISO_ORDER = 16
RULE_ORDERS = (32, 64, 128)
#: (axis, (alpha, ratio, eta), log step) of the slice-grid measurements
SLICE_CASES = [("alpha", (0.3, 0.3, 1.5), 0.3), ("alpha", (0.3, 0.3, 1.5), 0.6),
               ("alpha", (0.05, 0.2, 1.5), 0.3), ("ratio", (0.3, 0.3, 1.5), 0.3),
               ("ratio", (0.3, 0.3, 1.5), 0.6), ("ratio", (0.3, 0.05, 1.5), 0.3),
               ("eta", (0.3, 0.3, 1.2), 0.3), ("eta", (0.3, 0.3, 2.2), 0.3),
               ("eta", (0.3, 0.3, 1.5), 0.3),
               # the corners of the grid: low and high roughness, a nearly one-dimensional
               # surface, an index near 1
               ("alpha", (0.01, 0.3, 1.5), 0.3), ("alpha", (1.2, 0.3, 1.5), 0.3),
               ("ratio", (0.3, 0.015, 1.5), 0.3), ("eta", (0.3, 0.3, 1.02), 0.3)]
SMOKE_SLICE_CASES: list = []


def points(n: int, seed: int = SEED) -> dict:
    rng = np.random.default_rng(seed)
    alpha_x = rng.uniform(0.02, 1.0, n)
    return {"mu": rng.uniform(0.01, 1.0, n), "phi": rng.uniform(0.0, np.pi / 2, n),
            "alpha_x": alpha_x, "alpha_y": alpha_x * rng.uniform(0.0, 1.0, n),
            "eta": np.exp(rng.uniform(np.log(1.01), np.log(3.0), n))}


def _total(energy) -> np.ndarray:
    return energy.reflection + energy.transmission


def reference(p: dict, eta, order: int = REFERENCE_ORDER) -> np.ndarray:
    return _total(ggx_anisotropic_dielectric_energy(p["mu"], p["phi"], p["alpha_x"],
                                                    p["alpha_y"], eta, order, estimate=False))


def _proxies(p: dict) -> dict:
    ax, ay, phi = p["alpha_x"], p["alpha_y"], p["phi"]
    return {"geometric mean sqrt(alpha_x alpha_y) (the default today)": np.sqrt(ax * ay),
            "roughness projected on wo's azimuth": np.sqrt((ax * np.cos(phi)) ** 2
                                                 + (ay * np.sin(phi)) ** 2),
            "RMS sqrt((alpha_x^2 + alpha_y^2) / 2)": np.sqrt(0.5 * (ax * ax + ay * ay))}


def proxy_errors(p: dict, eta, E: np.ndarray) -> list:
    """``[(candidate, errors)]`` of the isotropic proxies and their conductor corrections."""
    conductor = ggx_anisotropic_energy(p["mu"], p["phi"], p["alpha_x"], p["alpha_y"],
                                       REFERENCE_ORDER, estimate=False).reflection
    out = []
    for name, alpha in _proxies(p).items():
        iso = _total(ggx_energy(p["mu"], alpha, eta, ISO_ORDER, estimate=False))
        iso_conductor = ggx_energy(p["mu"], alpha, None, ISO_ORDER, estimate=False).reflection
        out.append((f"isotropic at the {name}", iso - E))
        out.append(("... + the conductor's anisotropy, added", iso + conductor - iso_conductor
                    - E))
        loss = (1.0 - iso) * (1.0 - conductor) / np.maximum(1.0 - iso_conductor, 1e-12)
        out.append(("... + the conductor's anisotropy, ratio of losses", 1.0 - loss - E))
    return out


def rule_energy(mu, phi, alpha_x, alpha_y, eta, order: int) -> np.ndarray:
    """E_R + E_T ``(n,)`` at views (mu, phi) of one interface by the order x order Gauss
    product rule over the visible-normal sampler's uniforms (both branches)."""
    x, w = np.polynomial.legendre.leggauss(order)
    x, w = 0.5 * (x + 1.0), 0.5 * w
    u = np.stack(np.meshgrid(x, x, indexing="ij"), -1).reshape(-1, 2)
    weights = np.outer(w, w).ravel()
    s = np.sqrt(1.0 - mu * mu)
    wo = np.stack([s * np.cos(phi), s * np.sin(phi), mu], -1)[:, None, :]
    wo = np.broadcast_to(wo, (len(mu), len(u), 3))
    ggx = GGX(alpha_x, alpha_y)
    m = ggx.sample_visible(wo, np.broadcast_to(u, wo.shape[:-1] + (2,)))
    c = np.sum(wo * m, -1)
    sin2_t = (1.0 - c * c) / (eta * eta)
    tir = sin2_t >= 1.0
    cos_t = np.sqrt(np.maximum(1.0 - sin2_t, 0.0))
    r_s = (c - eta * cos_t) / (c + eta * cos_t)
    r_p = (eta * c - cos_t) / (eta * c + cos_t)
    F = np.where(tir, 1.0, 0.5 * (r_s * r_s + r_p * r_p))
    lambda_o = ggx.lambda_(wo)

    def kept(wi, above):
        ok = wi[..., 2] > 0.0 if above else wi[..., 2] < 0.0
        return np.where(ok, (1.0 + lambda_o) / (1.0 + lambda_o + ggx.lambda_(wi)), 0.0)
    reflected = 2.0 * c[..., None] * m - wo
    refracted = -wo / eta + (c / eta - cos_t)[..., None] * m
    value = F * kept(reflected, True) + np.where(tir, 0.0, (1.0 - F) * kept(refracted, False))
    return value @ weights


def rule_errors(p: dict, eta, E: np.ndarray) -> list:
    """``[(order, errors, ms per view)]``."""
    out = []
    for order in RULE_ORDERS:
        start = time.perf_counter()
        value = np.array([rule_energy(p["mu"][i:i + 1], p["phi"][i:i + 1], p["alpha_x"][i],
                                      p["alpha_y"][i], np.atleast_1d(eta)[i], order)[0]
                          for i in range(len(E))])
        out.append((order, value - E, 1e3 * (time.perf_counter() - start) / len(E)))
    return out


def _catmull_rom(t: float) -> np.ndarray:
    return 0.5 * np.array([-t ** 3 + 2 * t ** 2 - t, 3 * t ** 3 - 5 * t ** 2 + 2,
                           -3 * t ** 3 + 4 * t ** 2 + t, t ** 3 - t ** 2])


#: the slices built by ``slice_case``, by (alpha, ratio, eta)
_SLICES: dict = {}


def _slice(alpha: float, ratio: float, eta: float):
    """``dielectric_slice`` of the arguments, its build time kept (``_SLICES``)."""
    key = (float(alpha), float(ratio), float(eta))
    if key not in _SLICES:
        start = time.perf_counter()
        _SLICES[key] = (dielectric_slice(*key), time.perf_counter() - start)
    return _SLICES[key][0]


def slice_case(axis: str, target: tuple, step: float) -> dict:
    """Cubic interpolation across four slices at log offsets -1.5, -0.5, 0.5, 1.5 steps
    around ``target`` along ``axis``, against the target slice, at its parts' nodes and cell
    midpoints: max |error| of E_R + E_T per side (and of E_R alone), seconds."""
    alpha, ratio, eta = target

    def at(k):
        f = np.exp(k * step)
        return {"alpha": (alpha * f, ratio, eta), "ratio": (alpha, min(ratio * f, 1.0), eta),
                "eta": (alpha, ratio, 1.0 + (eta - 1.0) * f)}[axis]
    start = time.perf_counter()
    exact = _slice(*target)
    neighbours = [_slice(*at(k)) for k in (-1.5, -0.5, 0.5, 1.5)]
    weights = _catmull_rom(0.5)
    # the dense side's segments swap their order at eta = sqrt(2) (mu_c = 1 / eta there)
    above = {s.eta > np.sqrt(2.0) for s in (exact, *neighbours)}

    def layout(s):
        return [(q.segment, q.band) for q in s.parts]
    same = len(above) == 1 and all(layout(s) == layout(exact) for s in neighbours)
    out = {"light": 0.0, "dense": 0.0, "reflection": 0.0, "layout": same}
    for i, part in enumerate(exact.parts):
        if not same and part.segment != "outside":
            continue
        axes = [a.nodes() for a in part.table.spec.axes]
        grids = [np.concatenate([n, 0.5 * (n[:-1] + n[1:])]) for n in axes]
        X, U = np.meshgrid(*grids, indexing="ij")
        value = part.table(X, U)
        guess = sum(wk * s.parts[i].table(X, U) for wk, s in zip(weights, neighbours,
                                                                   strict=True))
        side = "light" if part.segment == "outside" else "dense"
        out[side] = max(out[side], float(np.abs(guess.sum(-1) - value.sum(-1)).max()))
        out["reflection"] = max(out["reflection"],
                                float(np.abs(guess[..., 0] - value[..., 0]).max()))
    out["seconds"] = time.perf_counter() - start
    out["nodes"] = exact.n_nodes
    return out


def measure(smoke: bool = False) -> dict:
    n = SMOKE_POINTS if smoke else POINTS
    p = points(n)
    result = {"n": n, "sides": {}, "slices": []}
    for side, eta in (("light", p["eta"]), ("dense", 1.0 / p["eta"])):
        start = time.perf_counter()
        E = reference(p, eta)
        seconds = (time.perf_counter() - start) / n
        k = min(CHECK, n)
        sub = {key: value[:k] for key, value in p.items()}
        check = np.abs(reference(sub, eta[:k], CHECK_ORDER) - E[:k]).max()
        result["sides"][side] = {"reference_seconds": seconds, "reference_check": check,
                                 "proxies": proxy_errors(p, eta, E),
                                 "rules": rule_errors(p, eta, E)}
    for axis, target, step in (SMOKE_SLICE_CASES if smoke else SLICE_CASES):
        result["slices"].append((axis, target, step, slice_case(axis, target, step)))
    if _SLICES:
        result["grid"] = grid_cost(GRID_STEP)
        result["rank"] = rank_study()
    if not smoke:
        result["grid_studies"] = grid_studies()
    return result


#: the log step of the grid of slices whose cost ``grid_cost`` estimates, and its ranges:
#: alpha_max (below ``GRID_ALPHA[0]`` the slice's coordinates make it the alpha -> 0 limit,
#: one more slice), alpha_min / alpha_max (ratio 0, the one-dimensional surface, one more),
#: eta - 1 (in two grids that meet at eta = sqrt 2, where the dense side's segments swap)
GRID_STEP = 0.3
GRID_ALPHA, GRID_RATIO, GRID_ETA = (0.005, 2.0), (0.01, 1.0), (0.01, 2.0)
WORKERS = (8, 32, 128)


def grid_cost(step: float) -> dict:
    """Slices of the five-dimensional grid at ``step`` (log) per axis and what they cost:
    the mean build time of this run's slices (one core), the raw size in float32."""
    def count(lo, hi):
        return int(np.ceil(np.log(hi / lo) / step)) + 1
    n_alpha = count(*GRID_ALPHA) + 1
    n_ratio = count(*GRID_RATIO) + 1
    n_eta = count(*GRID_ETA) + 1  # one node twice, at sqrt 2
    slices = n_alpha * n_ratio * n_eta
    built = list(_SLICES.values())
    seconds = float(np.mean([t for _, t in built]))
    nodes = int(np.mean([s.n_nodes for s, _ in built]))
    return {"step": step, "counts": (n_alpha, n_ratio, n_eta), "slices": slices,
            "nodes": nodes, "seconds": seconds, "core_hours": slices * seconds / 3600.0,
            "megabytes": slices * nodes * 2 * 4 / 2 ** 20}


def rank_study() -> dict:
    """The singular values of this run's slices of one layout (eta = 1.5: E_R + E_T at every
    part's nodes, one row per slice): the rank a truncated SVD of a grid of slices needs
    for a given error (its largest entry error), as a first look at how compressible the
    grid is."""
    rows = [s for (_, _, eta), (s, _) in _SLICES.items() if eta == 1.5]
    if len(rows) < 3:
        return {}
    matrix = np.stack([np.concatenate([p.table.values.sum(-1).ravel() for p in s.parts])
                       for s in rows])
    U, sigma, Vt = np.linalg.svd(matrix, full_matrices=False)
    errors = []
    for k in range(1, len(sigma) + 1):
        approx = (U[:, :k] * sigma[:k]) @ Vt[:k]
        errors.append(float(np.abs(approx - matrix).max()))
    return {"slices": len(rows), "columns": matrix.shape[1], "errors": errors}


#: the grid studies: held-out share of the reduced basis, its ranks, the targets of the
#: residual study per axis, and the grid steps (in the grid's own nodes) between neighbours
BASIS_HELD_OUT, BASIS_RANKS = 0.2, (8, 16, 32, 64, 128, 256)
RESIDUAL_TARGETS, RESIDUAL_SPACINGS = 6, (1, 2)


def _grid_totals(column, half: str) -> np.ndarray:
    """``(n_slices, n_nodes)``: E_R + E_T at every node of every slice of ``half``'s grid."""
    from adobe_bsdf.tables import dielectric_grid

    n_eta = dielectric_grid.HALVES[half][2].n
    return np.concatenate([column(half, k).sum(-1).reshape(-1, column(half, k).shape[2])
                           for k in range(n_eta)])


def basis_study(column, seed: int = SEED) -> dict:
    """One reduced basis for a whole half of the grid of slices (``tables.dielectric_grid``):
    the SVD of a random ``1 - BASIS_HELD_OUT`` of its slices (node values of E_R + E_T, the
    mean removed), and the largest error of the held-out slices projected on its first k
    singular vectors, per ``BASIS_RANKS``."""
    out = {}
    for half in ("below", "above"):
        M = _grid_totals(column, half)
        order = np.random.default_rng(seed).permutation(len(M))
        n_test = int(round(BASIS_HELD_OUT * len(M)))
        test, train = M[order[:n_test]], M[order[n_test:]]
        mean = train.mean(0)
        _, sigma, Vt = np.linalg.svd(train - mean, full_matrices=False)
        errors = []
        for k in BASIS_RANKS:
            if k > len(sigma):
                break
            V = Vt[:k]
            errors.append((k, float(np.abs((test - mean) @ V.T @ V + mean - test).max())))
        out[half] = {"slices": len(M), "held_out": n_test, "nodes": M.shape[1],
                     "errors": errors, "sigma": (sigma / sigma[0]).tolist()}
    return out


def _proxy_at_nodes(point) -> np.ndarray:
    """E_R + E_T of the isotropic interface at each node's projected roughness (the
    isotropic tables), at the nodes of the grid slice at ``point`` = (alpha, ratio, eta)."""
    from adobe_bsdf.lobes.energy_lookup import dielectric_energy
    from adobe_bsdf.tables.anisotropic_energy import projected_alpha
    from adobe_bsdf.tables.dielectric_slices import layout, node_directions

    alpha, ratio, eta = (float(x) for x in point)
    mu, cos_phi, light = node_directions(layout(alpha, ratio, eta))
    a_phi = projected_alpha(cos_phi, alpha, ratio)
    mu = np.clip(mu, 1e-9, 1.0)
    wo = np.stack([np.sqrt(1.0 - mu * mu), np.zeros_like(mu), np.where(light, mu, -mu)], -1)
    return dielectric_energy(eta, GGX(a_phi, a_phi), wo)[0]


def residual_study(column, seed: int = SEED) -> list:
    """Interpolating the residual over the isotropic proxy at the projected roughness
    (``_proxy_at_nodes``) against interpolating E_R + E_T itself: at ``RESIDUAL_TARGETS``
    random interior grid points per axis and half, cubic convolution (the target midway)
    from the grid points ``spacing`` (1, 2) grid steps either side of it, at the grid's
    step times 2 ``spacing`` (a coarser grid); the largest error of each per side.
    ``[(half, axis, spacing, {"E": (light, dense), "residual": (light, dense)})]``."""
    from adobe_bsdf.tables import dielectric_grid
    from adobe_bsdf.tables.dielectric_slices import layout, node_directions

    rng = np.random.default_rng(seed)
    weights = _catmull_rom(0.5)
    out = []
    for half in ("below", "above"):
        shape = tuple(a.n for a in dielectric_grid.HALVES[half])
        points = dielectric_grid.grid_points(half).reshape(shape + (3,))
        for axis in range(3):
            for spacing in RESIDUAL_SPACINGS:
                reach = 3 * spacing
                if shape[axis] <= 2 * reach:
                    continue
                worst = {"E": [0.0, 0.0], "residual": [0.0, 0.0]}
                for _ in range(RESIDUAL_TARGETS):
                    at = [int(rng.integers(0, n)) for n in shape]
                    at[axis] = int(rng.integers(reach, shape[axis] - reach))
                    # neighbours -3, -1, 1, 3 spacings away: a grid of step 2 spacings with
                    # the target midway
                    index = [tuple(at[:axis] + [at[axis] + k * spacing] + at[axis + 1:])
                             for k in (-3, -1, 1, 3)]
                    target = tuple(at)

                    def values(i, half=half):
                        return column(half, i[2])[i[0], i[1]].sum(-1)
                    light = node_directions(layout(*points[target]))[2]
                    E = values(target)
                    guess = sum(w * values(i) for w, i in zip(weights, index, strict=True))
                    residual = sum(w * (values(i) - _proxy_at_nodes(points[i]))
                                   for w, i in zip(weights, index, strict=True))
                    guess_r = residual + _proxy_at_nodes(points[target])
                    for key, g in (("E", guess), ("residual", guess_r)):
                        for s, side in enumerate((light, ~light)):
                            worst[key][s] = max(worst[key][s],
                                                float(np.abs(g - E)[side].max()))
                out.append((half, ("alpha", "ratio", "eta")[axis], spacing,
                            {k: tuple(v) for k, v in worst.items()}))
    return out


def grid_studies(path=None) -> dict:
    """``basis_study`` and ``residual_study`` of the shipped grid (or the columns in
    ``path``); {} where it is not complete."""
    from adobe_bsdf.tables import dielectric_grid

    folder = dielectric_grid._path() if path is None else Path(path)
    if not all(dielectric_grid.column_file(folder, h, k).exists()
               for h, k in dielectric_grid.columns()):
        return {}
    column = dielectric_grid.stored_columns(folder)
    return {"basis": basis_study(column), "residual": residual_study(column)}


def _stats(errors) -> str:
    errors = np.abs(np.asarray(errors))
    return f"{errors.max():.2e} | {np.sqrt(np.mean(errors ** 2)):.2e}"


def markdown(result: dict, seconds: float) -> str:
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    out = [f"*Generated by `python -m benchmarks.anisotropic_candidates` on {now} in "
           f"{seconds:.0f} s; do not edit by hand. The method is the docstring of "
           "`benchmarks/anisotropic_candidates.py`.*", "",
           "# Anisotropic dielectric energy: the candidates measured", "",
           f"E_R + E_T of an anisotropic GGX dielectric at {result['n']} random held-out "
           "points per side (mu in [0.01, 1], phi in [0, pi/2], alpha_x in [0.02, 1], "
           "alpha_y / alpha_x in [0, 1], eta in [1.01, 3] log-uniform), against the "
           f"stretched node quadrature at order {REFERENCE_ORDER}. Machine: "
           f"{machine.cpu_model()}, {machine.cores()} cores.", "",
           "| side | reference: seconds per point (one core) | its change at order "
           f"{CHECK_ORDER} (first {CHECK} points) |", "|---|---|---|"]
    for side, s in result["sides"].items():
        out.append(f"| {side} | {s['reference_seconds']:.3f} | {s['reference_check']:.1e} |")
    out += ["", "## Closed-form proxies", "",
            "| candidate | light side: max | RMS | dense side: max | RMS |",
            "|---|---|---|---|---|"]
    light, dense = result["sides"]["light"], result["sides"]["dense"]
    for (name, e_light), (_, e_dense) in zip(light["proxies"], dense["proxies"], strict=True):
        out.append(f"| {name} | {_stats(e_light)} | {_stats(e_dense)} |")
    out += ["", "## A per-lobe rule over the visible normals", "",
            "| order | light side: max | RMS | ms per view | dense side: max | RMS | "
            "ms per view |", "|---|---|---|---|---|---|---|"]
    for (order, e_light, t_light), (_, e_dense, t_dense) in zip(light["rules"],
                                                                 dense["rules"], strict=True):
        out.append(f"| {order} x {order} | {_stats(e_light)} | {t_light:.1f} | "
                   f"{_stats(e_dense)} | {t_dense:.1f} |")
    if result["slices"]:
        out += ["", "## A grid of slices, interpolated across them", "",
                "| axis | target (alpha, ratio, eta) | log step | light side: max | dense "
                "side: max | E_R alone: max | same layout | nodes per slice | seconds |",
                "|---|---|---|---|---|---|---|---|---|"]
        for axis, target, step, r in result["slices"]:
            errors = ([f"{r[k]:.1e}" for k in ("light", "dense", "reflection")] if r["layout"]
                      else [f"{r['light']:.1e}", "—", "—"])
            out.append(f"| {axis} | {target} | {step:g} | {' | '.join(errors)} | "
                       f"{'yes' if r['layout'] else 'no (eta crosses sqrt 2)'} | "
                       f"{r['nodes']} | {r['seconds']:.0f} |")
    if result.get("grid"):
        g = result["grid"]
        within = max(max(r["light"], r["dense"]) for _, _, step, r in result["slices"]
                     if step == g["step"] and r["layout"])
        out += ["", "## What a five-dimensional table of slices would cost", "",
                f"At a log step of {g['step']:g} on every axis (the step of the rows above "
                f"that interpolate within {within:.1e}): alpha_max in [{GRID_ALPHA[0]:g}, "
                f"{GRID_ALPHA[1]:g}] and its limit 0, alpha_min / alpha_max in "
                f"[{GRID_RATIO[0]:g}, {GRID_RATIO[1]:g}] and 0, eta - 1 in [{GRID_ETA[0]:g}, "
                f"{GRID_ETA[1]:g}] in two grids meeting at sqrt 2: "
                f"{' x '.join(map(str, g['counts']))} = {g['slices']} slices of "
                f"{g['nodes']} nodes (E_R, E_T). This run built a slice in {g['seconds']:.1f} "
                f"s on average (one core): **{g['core_hours']:.1f} core-hours** to bake "
                f"({g['core_hours'] / machine.cores():.1f} h on this machine's "
                f"{machine.cores()} cores; "
                + ", ".join(f"{g['core_hours'] * 60 / w:.0f} min on {w} workers"
                            for w in WORKERS)
                + f"), **{g['megabytes']:.0f} MB** in float32 before any compression."]
    rank = result.get("rank")
    if rank:
        shown = [k for k in (1, 2, 4, 8, 12, 16, 20, 24) if k <= len(rank["errors"])]
        out += ["", f"How compressible: the {rank['slices']} slices of this run at eta = 1.5 "
                f"(E_R + E_T at their {rank['columns']} nodes) as a matrix, truncated to rank "
                "k by its SVD; the largest entry error:", "",
                "| k | " + " | ".join(map(str, shown)) + " |",
                "|---|" + "---|" * len(shown),
                "| max error | " + " | ".join(f"{rank['errors'][k - 1]:.1e}" for k in shown)
                + " |"]
    out += _grid_study_lines(result.get("grid_studies"))
    return "\n".join(out) + "\n"


def _grid_study_lines(studies) -> list[str]:
    """The sections of ``grid_studies``, measured on the baked grid itself."""
    if not studies:
        return []
    from adobe_bsdf.tables.dielectric_grid import STEP

    out = ["", "## Measured on the baked grid of slices", "",
           "Two more candidates, measured on the slices of the grid that ships "
           "(`tables.dielectric_grid`, every node at its grid point: no further bake).", "",
           "### One reduced basis for each half of the grid", "",
           f"The SVD of a random {1 - BASIS_HELD_OUT:.0%} of a half's slices (E_R + E_T at "
           "every node, the mean removed); the largest error of the held-out slices "
           "projected on its first k singular vectors:", ""]
    basis = studies["basis"]
    ranks = [k for k, _ in basis["below"]["errors"]]
    out += ["| half | slices (held out) | nodes | " + " | ".join(f"k = {k}" for k in ranks)
            + " |", "|---|---|---|" + "---|" * len(ranks)]
    for half, b in basis.items():
        out.append(f"| {half} sqrt 2 | {b['slices']} ({b['held_out']}) | {b['nodes']} | "
                   + " | ".join(f"{e:.1e}" for _, e in b["errors"]) + " |")
    out += ["", "### A residual over the isotropic energy at the projected roughness", "",
            "E_R + E_T minus the isotropic interface's at each node's projected roughness "
            "(the isotropic tables), interpolated across grid points (cubic convolution, the "
            f"target grid point midway) at {' and '.join(str(2 * s) for s in RESIDUAL_SPACINGS)}"
            f" times the grid's step of {STEP:g}, against E_R + E_T interpolated itself; the "
            f"largest error over {RESIDUAL_TARGETS} random targets per row:", "",
            "| half | axis | log step | E: light | E: dense | residual: light | residual: "
            "dense |", "|---|---|---|---|---|---|---|"]
    for half, axis, spacing, r in studies["residual"]:
        out.append(f"| {half} sqrt 2 | {axis} | {2 * spacing * STEP:.1f} | "
                   + " | ".join(f"{x:.1e}" for x in (*r["E"], *r["residual"])) + " |")
    return out


def run(out: Path | None = None, smoke: bool = False) -> Path:
    return write_page(out, NAME, lambda: (measure(smoke),), markdown)


def main(argv=None) -> int:
    return report_main(run, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    raise SystemExit(main())
