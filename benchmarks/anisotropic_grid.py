"""The shipped grid of anisotropic dielectric slices against the exact mode, and what it
costs; writes ``docs/anisotropic_grid_measured.md``.

    python -m benchmarks.anisotropic_grid [--smoke] [--out DIR] [--grid DIR]

Accuracy. Held-out interfaces (seed 20261207): alpha_max log-uniform in [0.005, 2], ratio
uniform in [0, 1], the index ratio eta with eta - 1 log-uniform in [0.01, 2], plus fixed
extremes (the grid's corners, eta either side of sqrt 2, the one-dimensional surface). At
each, the slice interpolated from the grid (``tables.dielectric_grid.interpolated_slice``)
against the slice the exact mode computes (``tables.dielectric_slices.dielectric_slice``:
the reference), at random directions on both sides (mu log-uniform in [1e-3, 1], any
azimuth): E_R + E_T and E_R, max and RMS, and the hemispherical averages that the
Kulla-Conty terms divide by. ``--grid DIR`` measures a baked grid (the folder ``bake
ggx_dielectric_anisotropic --out DIR`` writes) instead of the shipped one.

Run without ``--out``, it also rewrites the summary block of ``docs/energy_models.md``.

Cost (one thread, the same batch, alternating rounds, the best of each): ``eval`` and
``sample`` of an anisotropic ``DielectricMS`` and of white translucent and opaque
anisotropic ASM dielectrics against their isotropic counterparts; the first use in a fresh
process (the first anisotropic lobe built and evaluated, the columns it needs loaded); the files'
size. The bake: one slice's time at random grid points, and the whole grid's on N workers.

Computed slices (``SLICE_CHECKS``: where the library computes the slice instead of reading
the grid): their error against the node integrator, in the grid's layout and refined. A
dispersive channel beyond the tables (``measure_beyond_tables``): what its term misses.
"""

from __future__ import annotations

import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from adobe_bsdf.tables import dielectric_grid
from adobe_bsdf.tables.dielectric_slices import dielectric_slice
from benchmarks import DOCS, generated_by, machine, report_main, with_block, write_page

NAME = "anisotropic_grid_measured.md"
SEED = 20261207
INTERFACES, SMOKE_INTERFACES = 24, 1
DIRECTIONS = 4000
#: (alpha, ratio, eta) always measured
EXTREMES = [(2.0, 0.0, 3.0), (2.0, 1.0, 1.011), (0.005, 0.0, 1.011), (1.2, 0.02, 1.4142),
            (1.2, 0.02, 1.4143), (0.6, 0.0, 1.9), (0.02, 0.5, 2.99),
            # nearly smooth: below the grid's third roughness node, read across its first
            # (the limit alpha -> 0+)
            (0.005, 0.037, 3.0), (0.003, 0.05, 2.0), (0.01, 0.3, 3.0), (0.0004, 0.5, 1.5),
            (0.001, 0.8, 1.2), (0.0005, 0.1, 1.05), (0.012, 0.06, 1.04),
            # the corners of what the library reads from the grid
            (2.0, 0.037, 1.031), (0.0157, 0.037, 3.0), (0.0157, 1.0, 1.031), (2.0, 1.0, 1.031),
            # nearly index-matched and very rough, seen from the dense side near mu = 1 / eta
            (2.0, 0.99, 1.045), (2.0, 0.5, 1.045), (1.0, 0.9, 1.06), (2.0, 0.99, 1.12),
            # the refined patch's edges
            (0.62, 0.5, 1.2), (0.7, 0.04, 1.035), (1.3, 0.25, 1.09), (0.6, 0.9, 1.06),
            # nearly index-matched: the patch on the critical cosine's axis
            (1.0, 0.5, 1.02), (0.05, 0.3, 1.015), (0.3, 0.04, 1.02), (0.004, 0.5, 1.02),
            (2.0, 0.99, 1.025)]
PAIRS, ROUNDS = 20000, 7


def interfaces(n: int, seed: int = SEED) -> list[tuple[float, float, float]]:
    rng = np.random.default_rng(seed)
    alpha = np.exp(rng.uniform(np.log(0.005), np.log(2.0), n))
    ratio = rng.uniform(0.0, 1.0, n)
    eta = 1.0 + np.exp(rng.uniform(np.log(0.01), np.log(2.0), n))
    return [(float(a), float(r), float(e)) for a, r, e in zip(alpha, ratio, eta, strict=True)]


def _directions(rng, n):
    return np.exp(rng.uniform(np.log(1e-3), 0.0, n)), rng.uniform(0.0, 1.0, n)


def compare(columns_of, interface, seed: int = SEED) -> dict:
    """Errors against the exact slice at ``interface`` of the slice that the library reads
    from the grids ``columns_of`` gives (``dielectric_grid.read_slice``), or where it reads
    none, of the whole grid's."""
    exact = dielectric_slice(*interface)
    # the whole grid at every index ratio on it, below those it is read at too
    whole = replace(dielectric_grid.GRID, etas=(dielectric_grid.ETA_MIN, np.inf),
                    ratios=(0.0, np.inf))
    coarse = dielectric_grid.interpolated_slice(columns_of(dielectric_grid.GRID), *interface,
                                                grid=whole)
    piece = dielectric_grid.read_slice(columns_of, *interface) or coarse
    rng = np.random.default_rng(seed)
    out = {}
    for side, on_light in (("light", True), ("dense", False)):
        mu, cos_phi = _directions(rng, DIRECTIONS)
        d = piece(on_light, mu, cos_phi) - exact(on_light, mu, cos_phi)
        out[side + " grid alone"] = (coarse(on_light, mu, cos_phi)
                                     - exact(on_light, mu, cos_phi)).sum(-1)
        out[side] = d.sum(-1)
        out[side + " E_R"] = d[..., 0]
        out[side + " average"] = (piece.average(on_light) - exact.average(on_light)).sum()
    return out


def _lobes():
    """(name, anisotropic, isotropic) factories of the cost rows."""
    from adobe_bsdf.lobes import DielectricMS
    from adobe_bsdf.materials import AdobeStandardMaterial

    def asm(translucency, level):
        return lambda: AdobeStandardMaterial(base_color=1.0, translucency=translucency,
                                             ior=1.45, roughness=0.5, anisotropy_level=level)
    return [("DielectricMS(1.5, 0.3, 0.06)", lambda: DielectricMS(1.5, 0.3, 0.06),
             lambda: DielectricMS(1.5, 0.3, 0.3)),
            ("ASM translucent, roughness 0.5, anisotropy 0.8", asm(1.0, 0.8), asm(1.0, 0.0)),
            ("ASM opaque dielectric, roughness 0.5, anisotropy 0.8", asm(0.0, 0.8),
             asm(0.0, 0.0))]


def costs(pairs: int = PAIRS, rounds: int = ROUNDS) -> list:
    """``[(name, eval ratio, sample ratio)]``: best-of-``rounds`` times, one thread."""
    import adobe_bsdf as ab

    rng = np.random.default_rng(SEED)
    v = rng.normal(size=(2, pairs, 3))
    wo, wi = v / np.linalg.norm(v, axis=-1, keepdims=True)
    u = rng.uniform(size=(pairs, 3))
    out = []
    with ab.config.options(threads=1):
        for name, aniso, iso in _lobes():
            lobes = {"aniso": aniso(), "iso": iso()}
            best = {}
            for _ in range(rounds):
                for key, lobe in lobes.items():
                    for what, call, args in (("eval", lobe.eval, (wo, wi)),
                                             ("sample", lobe.sample, (wo, u))):
                        start = time.perf_counter()
                        call(*args)
                        t = time.perf_counter() - start
                        best[key, what] = min(best.get((key, what), t), t)
            out.append((name, best["aniso", "eval"] / best["iso", "eval"],
                        best["aniso", "sample"] / best["iso", "sample"]))
    return out


_FIRST_USE = """
import time, numpy as np
import adobe_bsdf
from adobe_bsdf.lobes import DielectricMS
start = time.perf_counter()
lobe = DielectricMS({eta}, {alpha_x}, {alpha_y})
lobe.eval(np.array([0.0, 0.6, 0.8]), np.array([0.0, -0.6, 0.8]))
print(time.perf_counter() - start)
"""
#: the lobes (eta, alpha_x, alpha_y) whose first use is timed: an ordinary one, a nearly
#: smooth one (read from the grid across its first roughness node), a nearly index-matched
#: one (``MATCHED``) and a nearly one-dimensional one (roughness ratio below
#: ``RATIO_INTERPOLATED``: its slice computed)
FIRST_USES = {"ordinary": (1.5, 0.3, 0.06), "nearly smooth": (1.5, 0.01, 0.006),
              "nearly index-matched": (1.02, 0.3, 0.15),
              "nearly one-dimensional": (1.5, 0.3, 0.006)}


def first_use(eta: float = 1.5, alpha_x: float = 0.3, alpha_y: float = 0.06) -> float:
    """Seconds from a fresh process's first anisotropic lobe to its first ``eval``."""
    script = _FIRST_USE.format(eta=eta, alpha_x=alpha_x, alpha_y=alpha_y)
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         check=True)
    return float(run.stdout.split()[-1])


#: (ratio, eta) at which ``limit_rows`` measures the first roughness node
LIMIT_CHECKS = ((0.5, 1.5), (0.2, 1.031), (1.0, 3.0))


def limit_rows(checks=LIMIT_CHECKS) -> list:
    """``[((ratio, eta), at alpha 0, beyond)]``: the largest difference over the grid layout's
    nodes of E_R + E_T at ``dielectric_grid.ALPHA_LIMIT`` from that at alpha = 0 itself
    (``ALPHA_FLOOR`` in the coordinates) and from that at a tenth of ``ALPHA_LIMIT``."""
    from adobe_bsdf.tables.dielectric_slices import layout, node_directions, node_energy

    def total(alpha, ratio, eta):
        return node_energy(alpha, ratio, eta,
                           *node_directions(layout(alpha, ratio, eta))).sum(-1)
    rows = []
    for ratio, eta in checks:
        at = total(dielectric_grid.ALPHA_LIMIT, ratio, eta)
        rows.append(((ratio, eta), float(np.abs(total(0.0, ratio, eta) - at).max()),
                     float(np.abs(total(dielectric_grid.ALPHA_LIMIT / 10, ratio, eta)
                                  - at).max())))
    return rows


def _limit_lines(rows) -> list[str]:
    if not rows:
        return []
    out = ["", "## The nearly smooth limit", "",
           "The grid's first roughness node holds the slices at alpha_max = "
           f"{dielectric_grid.ALPHA_LIMIT:g} (`dielectric_grid.ALPHA_LIMIT`), the limit "
           "alpha -> 0+ of every node's value. At alpha = 0 itself the slice's coordinates "
           "floor the projected roughness, so its nodes sit at other cos θ / alpha_phi than "
           "at any alpha > 0. Largest difference of E_R + E_T over the grid layout's nodes:", "",
           "| (ratio, eta) | at alpha 0 itself | at a tenth of ALPHA_LIMIT |", "|---|---|---|"]
    for (r, e), at_zero, beyond in rows:
        out.append(f"| ({r:g}, {e:g}) | {at_zero:.1e} | {beyond:.1e} |")
    return out


#: interfaces (alpha, ratio, eta) whose computed slices are measured against the node
#: integrator: nearly one-dimensional (the ASM's anisotropy 1 at roughness 0 and 0.02), nearly
#: index-matched, and two ordinary ones; the (mu, |cos phi|) grid and the integrator's order
SLICE_CHECKS = [(1.0, 0.0, 1.5), (1.0, 1e-5, 1.5), (1.0004, 4e-4, 1.5), (1.0, 4e-4, 3.0),
                (0.3, 1e-3, 1.5), (1.0, 1e-3, 1.01), (0.6661, 0.015, 1.45),
                (0.05, 0.01, 2.0), (2.0, 0.02, 1.2), (2.0, 0.5, 1.02),
                # where the dense side's kinks meet at grazing (|cos phi| = mu_c) on a nearly
                # one-dimensional surface, the refined layout misses most
                (2.0, 0.005, 1.06), (1.0, 0.0133, 2.5), (1.0, 0.003, 1.05), (1.0, 0.0, 1.03)]
CHECK_MU = (1e-3, 2e-3, 5e-3, 0.01, 0.02, 0.03, 0.05, 0.1, 0.2, 0.4, 0.6, 0.75, 0.9, 1.0)
CHECK_COS_PHI = (0.0, 1e-4, 3e-4, 1e-3, 3e-3, 0.01, 0.03, 0.1, 0.3, 0.6, 0.9, 1.0)
CHECK_ORDER = 12
#: seen from the dense side, also |cos phi| = mu_c + these: across the kinks, which meet at
#: mu_c at grazing (``dielectric_slices``), where the energy of a nearly one-dimensional
#: surface turns within |cos phi| ~ alpha_min
CHECK_KINK_OFFSETS = tuple(np.round(np.linspace(-0.03, 0.06, 31), 6))


def _checked(alpha: float, ratio: float, eta_seen: float):
    """``(mu, |cos phi|, energy)``: the stretched node integrator at order ``CHECK_ORDER``
    over ``CHECK_MU`` x ``CHECK_COS_PHI`` (seen from the dense side, with
    ``CHECK_KINK_OFFSETS`` about the critical cosine), seen through index ratio
    ``eta_seen``."""
    from adobe_bsdf.tables.anisotropic_energy import ggx_anisotropic_dielectric_energy

    cos_phi = np.array(CHECK_COS_PHI)
    if eta_seen < 1.0:
        kinks = np.sqrt(1.0 - eta_seen * eta_seen) + np.array(CHECK_KINK_OFFSETS)
        cos_phi = np.union1d(cos_phi, kinks[(kinks >= 0.0) & (kinks <= 1.0)])
    mu, c = (a.ravel() for a in np.meshgrid(CHECK_MU, cos_phi, indexing="ij"))
    return mu, c, ggx_anisotropic_dielectric_energy(mu, np.arccos(c), alpha, alpha * ratio,
                                                    eta_seen, CHECK_ORDER, estimate=False)


def computed_slices(checks=SLICE_CHECKS) -> list:
    """``[(interface, {layout: (light max, dense max, seconds)})]``: the largest |E_R + E_T|
    error of the slice computed in the grid's layout and in the refined one (the library's:
    ``dielectric_slices.layout``) against the stretched node integrator at order
    ``CHECK_ORDER`` over ``_checked``'s directions from both sides (the dense side's with
    ``CHECK_KINK_OFFSETS``), and the seconds each slice took (one thread)."""
    import adobe_bsdf as ab

    rows = []
    with ab.config.options(threads=1):
        for alpha, ratio, eta in checks:
            ref = {}
            for on_light in (True, False):
                mu, c, e = _checked(alpha, ratio, eta if on_light else 1.0 / eta)
                ref[on_light] = mu, c, e.reflection + e.transmission
            out = {}
            for name, refined in (("grid layout", False), ("refined", True)):
                start = time.perf_counter()
                piece = dielectric_slice.__wrapped__(alpha, ratio, eta, refined)
                seconds = time.perf_counter() - start
                out[name] = tuple(float(np.abs(piece(on_light, mu, c).sum(-1) - want).max())
                                  for on_light, (mu, c, want) in ref.items()) + (seconds,)
            rows.append(((alpha, ratio, eta), out))
    return rows


def _slice_lines(rows) -> list[str]:
    if not rows:
        return []
    out = ["", "## Computed slices against the node integrator", "",
           "Where the library computes a slice (and in the exact mode), it uses the refined "
           "layout (`dielectric_slices.layout(..., refined=True)`). Largest |E_R + E_T| error "
           f"over cos θ ∈ {{{', '.join(f'{m:g}' for m in CHECK_MU)}}} × |cos φ| ∈ "
           f"{{{', '.join(f'{x:g}' for x in CHECK_COS_PHI)}}} from each side (seen from the "
           f"dense side also |cos φ| from mu_c {CHECK_KINK_OFFSETS[0]:+g} to "
           f"{CHECK_KINK_OFFSETS[-1]:+g} in {len(CHECK_KINK_OFFSETS)} steps, across the "
           "kinks), against the "
           f"stretched node integrator at order {CHECK_ORDER}, and the time to compute the "
           "slice on one thread:", "",
           "| interface (alpha, ratio, eta) | grid layout: light | dense | s | refined: light "
           "| dense | s |", "|---|---|---|---|---|---|---|"]
    for (a, r, e), d in rows:
        g, f = d["grid layout"], d["refined"]
        out.append(f"| ({a:.5g}, {r:.3g}, {e:.4g}) | {g[0]:.1e} | {g[1]:.1e} | {g[2]:.1f} | "
                   f"{f[0]:.1e} | {f[1]:.1e} | {f[2]:.1f} |")
    worst = {k: max(max(d[k][:2]) for _, d in rows) for k in ("grid layout", "refined")}
    out += ["", f"Worst: {worst['grid layout']:.1e} in the grid's layout, "
            f"{worst['refined']:.1e} refined."]
    return out


#: interfaces (alpha, ratio, eta) whose light side's E_R alone is read from the grid with and
#: without its Fresnel share: from ``ALPHA_REFLECTION`` up (read), and below it (computed)
SHARE_CHECKS = [(0.0157, 0.037, 3.0), (0.02, 0.5, 1.05), (0.05, 0.04, 1.5), (0.1, 0.05, 2.0),
                (0.3, 0.3, 1.5), (1.0, 0.5, 1.2), (2.0, 0.9, 2.5), (0.002, 0.9, 1.05),
                (0.003, 0.5, 1.5), (0.008, 0.9, 1.05), (0.012, 0.05, 2.6)]


def share_rows(columns_of, checks=SHARE_CHECKS) -> list:
    """``[(interface, with share, without, E_R + E_T)]``: the largest error of the light
    side's E_R read from the grids ``columns_of`` gives (``dielectric_grid.read_slice``
    of E_R + E_T: the grid, wherever it holds the interface), interpolated less its Fresnel
    share and as it is (the share weighted to 0), and of E_R + E_T, against the stretched
    node integrator at order ``CHECK_ORDER`` over ``CHECK_MU`` x ``CHECK_COS_PHI``."""
    from adobe_bsdf.tables import dielectric_slices

    rows = []
    for alpha, ratio, eta in checks:
        mu, c, e = _checked(alpha, ratio, eta)
        errors = []
        for weight in (dielectric_slices.FRESNEL_SHARE_ROUGHNESS, 0.0):
            default, dielectric_slices.FRESNEL_SHARE_ROUGHNESS = (
                dielectric_slices.FRESNEL_SHARE_ROUGHNESS, weight)
            try:
                got = dielectric_grid.read_slice(columns_of, alpha, ratio, eta)(True, mu, c)
            finally:
                dielectric_slices.FRESNEL_SHARE_ROUGHNESS = default
            errors.append(float(np.abs(got[:, 0] - e.reflection).max()))
        total = float(np.abs(got.sum(-1) - e.reflection - e.transmission).max())
        rows.append(((alpha, ratio, eta), *errors, total))
    return rows


def _share_lines(rows) -> list[str]:
    if not rows:
        return []
    from adobe_bsdf.tables import dielectric_slices

    out = ["", "## The light side's Fresnel share", "",
           "E_R alone of the light side (an opaque dielectric's specular albedo) is "
           "interpolated, across the grid's points and within a slice, less its Fresnel share "
           "g = F(cos θ) / (1 + (alpha_phi / "
           f"{dielectric_slices.FRESNEL_SHARE_ROUGHNESS:g})^2) "
           "(`dielectric_slices.fresnel_share`), which the slice adds back. Largest error "
           f"over the directions of the section below, against the node integrator at order "
           f"{CHECK_ORDER}; the library reads E_R from the grid from alpha_max "
           f"{dielectric_grid.ALPHA_REFLECTION:.3g} (`dielectric_grid.ALPHA_REFLECTION`) and "
           "computes it below:", "",
           "| interface (alpha, ratio, eta) | E_R read by the library | E_R, share taken out "
           "| E_R as it is | E_R + E_T |", "|---|---|---|---|---|"]
    for (a, r, e), share, plain, total in rows:
        read = "grid" if a >= dielectric_grid.ALPHA_REFLECTION else "computed"
        out.append(f"| ({a:g}, {r:g}, {e:g}) | {read} | {share:.1e} | {plain:.1e} | "
                   f"{total:.1e} |")
    return out


#: where a dispersive glass's channel index is largest (ior 3, dispersion 1), and the alphas,
#: ratios and cosines of ``measure_beyond_tables``
BEYOND_IOR, BEYOND_DISPERSION = 3.0, 1.0
BEYOND_ALPHAS = (0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 1.5, 2.0)
BEYOND_RATIOS = (1.0, 0.1, 0.0)
BEYOND_COSINES = (1e-3, 0.01, 0.05, 0.1, 0.2, 0.35, 0.5, 0.65, 0.8, 0.9, 1.0)


def measure_beyond_tables(order: int = 12):
    """The largest |E(eta_c) - E(end)| (E = E_R + E_T by the stretched node quadrature),
    eta_c the largest channel index at ``BEYOND_IOR`` and ``BEYOND_DISPERSION``, end the
    tables' (3), per side, over
    ``BEYOND_ALPHAS``, ``BEYOND_RATIOS``, ``BEYOND_COSINES`` and azimuths 0, pi/4, pi/2 from
    the rough axis: what the term of a channel beyond the tables misses
    (``energy_lookup.BEYOND_TABLES_ERROR``). Rows (side, eta_c, worst, alpha, ratio, mu)."""
    from adobe_bsdf import dispersion, tables
    from adobe_bsdf.tables.anisotropic_energy import ggx_anisotropic_dielectric_energy
    eta_c = float(dispersion.cauchy_iors(BEYOND_IOR, BEYOND_DISPERSION).max())
    mu, phi = (a.ravel() for a in np.meshgrid(BEYOND_COSINES, (0.0, np.pi / 4, np.pi / 2)))
    rows = []
    for side, sign in (("light", 1.0), ("dense", -1.0)):
        worst = (0.0, None, None, None)
        for alpha in BEYOND_ALPHAS:
            for ratio in BEYOND_RATIOS:
                e = [ggx_anisotropic_dielectric_energy(mu, phi, alpha, alpha * ratio,
                                                       eta ** sign, order, estimate=False)
                     for eta in (eta_c, tables.ETA_MAX)]
                d = np.abs(e[0].reflection + e[0].transmission
                           - e[1].reflection - e[1].transmission)
                if d.max() > worst[0]:
                    worst = (float(d.max()), alpha, ratio, float(mu[d.argmax()]))
        rows.append((side, eta_c, *worst))
    return rows


def markdown_beyond_tables(rows):
    from adobe_bsdf.lobes.energy_lookup import BEYOND_TABLES_ERROR
    if not rows:
        return []
    out = ["", "## Dispersive channels beyond the tables", "",
           f"At ior {BEYOND_IOR:g} and dispersion {BEYOND_DISPERSION:g} the blue channel's "
           f"index is {rows[0][1]:.5g}, beyond the energy tables' index ratio 3; its "
           "Kulla–Conty term reads the tables at 3 (`energy_lookup.within_tables`), so its "
           "white furnace misses by |E(η_c) − E(3)|, E = E_R + E_T by the stretched node "
           "quadrature. Largest over α_x ∈ {" + ", ".join(f"{a:g}" for a in BEYOND_ALPHAS)
           + "}, α_y/α_x ∈ {" + ", ".join(f"{r:g}" for r in BEYOND_RATIOS) + "}, cos θ_o ∈ {"
           + ", ".join(f"{m:g}" for m in BEYOND_COSINES) + "} and azimuths 0, π/4, π/2:", "",
           "| side | η_c | largest abs(E(η_c) − E(3)) | at α_x | α_y/α_x | cos θ_o |",
           "|---|---|---|---|---|---|"]
    out += [f"| {side} | {eta:.5g} | {worst:.2e} | {a:g} | {r:g} | {m:g} |"
            for side, eta, worst, a, r, m in rows]
    worst = max(r[2] for r in rows)
    out += ["", f"The warning states {BEYOND_TABLES_ERROR:g} "
            f"(`BEYOND_TABLES_ERROR`); measured here: {worst:.4f}"
            + ("." if worst <= BEYOND_TABLES_ERROR else " — ABOVE the stated bound."), ""]
    return out


#: grid points timed for the bake's cost, and the cluster sizes it is estimated for
BAKE_POINTS, SMOKE_BAKE_POINTS = 8, 1
WORKERS = (1, 2, 8, 32, 128)


def bake_cost(n: int = BAKE_POINTS, seed: int = SEED) -> dict:
    """Seconds to compute one slice (``dielectric_grid.point_values``, one thread) at ``n``
    grid points drawn at random and at ``n`` points of the refined patches (their layout),
    and the size of each in slices and in columns."""
    import adobe_bsdf as ab

    rng = np.random.default_rng(seed)
    kinds = {"grid": [g for g in dielectric_grid.GRIDS if not g.refined],
             "patches": [g for g in dielectric_grid.GRIDS if g.refined]}
    out = {}
    with ab.config.options(threads=1):
        for kind, grids in kinds.items():
            points = np.concatenate([g.points(h) for g in grids for h in g.spans])
            seconds = []
            for point in points[rng.choice(len(points), n, replace=False)]:
                start = time.perf_counter()
                dielectric_grid.point_values(point, refined=kind == "patches")
                seconds.append(time.perf_counter() - start)
            out[kind] = {"seconds": seconds, "slices": len(points),
                         "columns": sum(len(g.columns()) for g in grids)}
    return out


def _bake_lines(cost: dict) -> list[str]:
    mean = {k: float(np.mean(c["seconds"])) for k, c in cost.items()}
    core_hours = sum(mean[k] * c["slices"] for k, c in cost.items()) / 3600.0
    grid, patches = cost["grid"], cost["patches"]
    out = ["", "## The bake", "",
           f"One slice takes {mean['grid']:.1f} s on one core here (mean of "
           f"{len(grid['seconds'])} random grid points, {min(grid['seconds']):.1f}–"
           f"{max(grid['seconds']):.1f} s), one of the refined patches {mean['patches']:.1f} s"
           f" (mean of {len(patches['seconds'])}); the grid's {grid['slices']} slices and the "
           f"patches' {patches['slices']} take {core_hours:.1f} core-hours. Slices are "
           "independent tasks, so the bake (`python -m adobe_bsdf bake "
           "ggx_dielectric_anisotropic --workers N`, or `--dask-workers N` / `--scheduler "
           "ADDRESS` on a Dask cluster) scales with the workers until each has one slice; "
           f"it writes {grid['columns'] + patches['columns']} columns, each as soon as its "
           "slices are done.", "", "| workers | estimated wall-clock |", "|---|---|"]
    for n in WORKERS:
        hours = core_hours / n
        out.append(f"| {n} | {hours:.2f} h |" if hours >= 1.0 else
                   f"| {n} | {hours * 60.0:.0f} min |")
    return out


def measure(smoke: bool = False, path: Path | None = None) -> dict:
    path = Path(path) if path is not None else dielectric_grid._path()
    grid = dielectric_grid.folder_columns(path)
    if grid(dielectric_grid.GRID) is None:
        raise FileNotFoundError(f"{path} does not hold the whole grid")
    cases = interfaces(SMOKE_INTERFACES if smoke else INTERFACES)
    extremes = EXTREMES[:1] if smoke else EXTREMES
    rows = [(c, compare(grid, c)) for c in cases + extremes]
    result = {"rows": rows, "n_random": len(cases), "path": path.name,
              "bytes": _bytes(path, dielectric_grid.GRIDS),
              "pending": _bytes(path, dielectric_grid.PENDING)}
    result["bake"] = bake_cost(SMOKE_BAKE_POINTS if smoke else BAKE_POINTS)
    result["slices"] = [] if smoke else computed_slices()  # minutes: not in the smoke run
    result["beyond"] = [] if smoke else measure_beyond_tables()
    if not smoke:
        result["costs"] = costs()
        result["first_use"] = {name: first_use(*lobe) for name, lobe in FIRST_USES.items()}
        result["limit"] = limit_rows()
    result["share"] = share_rows(grid, SHARE_CHECKS[:2] if smoke else SHARE_CHECKS)
    return result


def _read(interface) -> bool:
    """Whether the library reads this interface's slice from the grid (elsewhere it
    computes it: ``dielectric_grid.interpolated``)."""
    return dielectric_grid.interpolated(*interface)


def _source(interface) -> str:
    """Where the library's slice of this interface comes from."""
    if not _read(interface):
        return "no: computed"
    if not dielectric_grid.interpolated(*interface, "reflection"):
        return "E_R + E_T (E_R computed)"
    if dielectric_grid.MATCHED.stencils(*interface):
        return "nearly matched patch"
    return "refined patch" if dielectric_grid.PATCH.stencils(*interface) else "yes"


def _split(rows, key: str = "light"):
    """``(read, computed)``: the rows whose slice the library reads from the grid for
    ``key``'s channel (E_R where the key names it), and the others."""
    channel = "reflection" if "E_R" in key else "total"
    read = [dielectric_grid.interpolated(*c, channel) for c, _ in rows]
    return ([r for (_, r), y in zip(rows, read, strict=True) if y],
            [r for (_, r), y in zip(rows, read, strict=True) if not y])


def _computed_line(rows) -> list[str]:
    """What the grid would miss where the library computes the slice instead."""
    _, computed = _split(rows)
    if not computed:
        return []
    worst = max(_stats([r[side] for r in computed])[0] for side in ("light", "dense"))
    return ["", f"At the {len(computed)} interfaces measured where the library computes the "
            "slice instead of reading the grid (index ratio below "
            f"{dielectric_grid.ETA_MIN:.4g} or roughness ratio below "
            f"{dielectric_grid.RATIO_INTERPOLATED:.3g}: `dielectric_grid.interpolated`), the "
            f"grid would miss E_R + E_T by up to {worst:.1e}; there the default's slice is "
            "the exact mode's."]


def _patch_alpha() -> float:
    """The least alpha_max read from the refined patch (its second roughness node)."""
    return float(np.unique(dielectric_grid.PATCH.points("below")[:, 0])[1])


def _patch_eta() -> float:
    """The largest index ratio read from the refined patch (its last but one)."""
    return float(np.unique(dielectric_grid.PATCH.points("below")[:, 2])[-2])


def _first_uses(seconds: dict) -> str:
    return "; ".join(f"{name} `DielectricMS{FIRST_USES[name]}` {t:.2f} s"
                     for name, t in seconds.items())


def _stats(values) -> tuple[float, float]:
    v = np.abs(np.concatenate([np.atleast_1d(x) for x in values]))
    return float(v.max()), float(np.sqrt(np.mean(v * v)))


def markdown(result: dict, seconds: float) -> str:
    rows = result["rows"]
    out = [generated_by("benchmarks.anisotropic_grid", seconds, "energy_models.md"), "",
           "# The grid of anisotropic dielectric slices, measured", "",
           f"{result['n_random']} random held-out interfaces and {len(rows) - result['n_random']}"
           f" fixed extremes, {DIRECTIONS} random directions per side each; the grid's slice "
           "against the exact mode's, over the interfaces whose slice the library reads from "
           "the grid. Machine: "
           f"{machine.cpu_model()}, {machine.cores()} cores.", "",
           "| quantity | max | RMS |", "|---|---|---|"]
    for key in ("light", "dense", "light E_R", "dense E_R", "light average",
                "dense average"):
        worst, rms = _stats([r[key] for r in _split(rows, key)[0]])
        out.append(f"| {key} (E_R + E_T unless named) | {worst:.1e} | {rms:.1e} |")
    out += _computed_line(rows)
    out += ["", "| interface (alpha, ratio, eta) | read from the grid | light | dense | "
            "light E_R | dense E_R | dense, the grid alone |", "|---|---|---|---|---|---|---|"]
    for c, r in rows:
        out.append(f"| ({c[0]:.4g}, {c[1]:.3g}, {c[2]:.5g}) | "
                   f"{_source(c)} | "
                   + " | ".join(f"{np.abs(r[k]).max():.1e}"
                                for k in ("light", "dense", "light E_R", "dense E_R",
                                          "dense grid alone")) + " |")
    out += ["", "The refined patch (`dielectric_grid.PATCH`: alpha_max >= "
            f"{_patch_alpha():.3g}, index ratios {dielectric_grid.ETA_INTERPOLATED:.4g} to "
            f"{_patch_eta():.3g}) and the nearly index-matched one (`dielectric_grid.MATCHED`:"
            f" index ratios {dielectric_grid.ETA_MIN:.4g} to "
            f"{dielectric_grid.ETA_INTERPOLATED:.4g}, on an axis uniform in the critical "
            "cosine) are read where the table says so; elsewhere the grid. Below "
            f"alpha_max {dielectric_grid.ALPHA_REFLECTION:.3g} "
            "(`dielectric_grid.ALPHA_REFLECTION`) the library reads only E_R + E_T from the "
            "grid and computes the slice for E_R alone (the E_R rows of the first table leave "
            "those interfaces out).", "",
            f"The grid's files ({result['path']}/, one per index ratio, the patches' too): "
            f"{_size(result['bytes'])}.{_pending(result)}"]
    if "costs" in result:
        out += ["", "## Cost", "", "| lobe | eval / isotropic | sample / isotropic |",
                "|---|---|---|"]
        for name, e, s in result["costs"]:
            out.append(f"| {name} | {e:.2f} | {s:.2f} |")
        out += ["", "First use in a fresh process (the columns it needs loaded, the lobe "
                "built and evaluated): " + _first_uses(result["first_use"]) + "."]
    out += _limit_lines(result.get("limit", []))
    out += _share_lines(result.get("share", []))
    out += _slice_lines(result["slices"])
    out += markdown_beyond_tables(result["beyond"])
    out += _bake_lines(result["bake"])
    return "\n".join(out) + "\n"


#: the page whose measured block ``summary`` rewrites, and the block's name
SUMMARY_PAGE, SUMMARY = "energy_models.md", "anisotropic_grid"


def _bytes(path: Path, grids) -> int:
    """Bytes of the columns of ``grids`` stored in ``path`` (of a pending grid, those baked
    so far)."""
    files = [dielectric_grid.column_file(path, h, k, g) for g in grids for h, k in g.columns()]
    return sum(f.stat().st_size for f in files if f.exists())


def _pending(result: dict) -> str:
    """What the pending grids' columns shipped so far add (the wheel carries them too)."""
    if not result.get("pending"):
        return ""
    return (f" The pending grids' columns baked so far (`dielectric_grid.PENDING`, not yet "
            f"read) add {result['pending'] / 1e6:.2f} MB.")


def _size(n_bytes: int) -> str:
    """The files' size, in MB and MiB, and how their values are stored."""
    q = dielectric_grid.QUANTUM
    return (f"{n_bytes / 1e6:.2f} MB ({n_bytes / 2**20:.2f} MiB), the node values stored as "
            f"multiples of 1/{q} (rounded within {0.5 / q:.1e}; `dielectric_grid.QUANTUM`)")


def summary(result: dict) -> str:
    """The block of ``SUMMARY_PAGE``: the held-out errors (max and RMS per side), the file
    size, the cost against isotropic lobes and the first use."""
    rows = result["rows"]
    read, _ = _split(rows)
    out = [f"Measured against the exact mode at {result['n_random']} held-out interfaces and "
           f"{len(rows) - result['n_random']} extremes ({len(read)} of them read from the "
           f"grid), {DIRECTIONS} random directions per side each ([{NAME}]({NAME})):", "",
           "| E_R + E_T seen from | max error | RMS error |", "|---|---|---|"]
    for side in ("light", "dense"):
        worst, rms = _stats([r[side] for r in read])
        out.append(f"| the {side} side | {worst:.1e} | {rms:.1e} |")
    out += _computed_line(rows)
    if result["slices"]:
        worst = max(max(d["refined"][:2]) for _, d in result["slices"])
        slowest = max(d["refined"][2] for _, d in result["slices"])
        out += ["", f"A computed slice (refined layout) against the node integrator at "
                f"{len(result['slices'])} interfaces, nearly one-dimensional and nearly "
                f"index-matched among them: E_R + E_T within {worst:.1e} for cos θ ≥ 1e-3 "
                f"(across the dense side's kinks included); "
                f"it takes up to {slowest:.0f} s, once per interface."]
    out += ["", f"The grid's files: {_size(result['bytes'])}.{_pending(result)}"]
    if "costs" in result:
        out[-1] += (" Cost against the isotropic counterparts, `eval` / `sample`: "
                    + "; ".join(f"{name} {e:.2f}× / {s:.2f}×"
                                for name, e, s in result["costs"])
                    + ". First use in a fresh process: " + _first_uses(result["first_use"])
                    + ".")
    return "\n".join(out) + "\n"


def run(out: Path | None = None, smoke: bool = False, grid: Path | None = None) -> Path:
    result = {}

    def compute():
        result.update(measure(smoke, grid))
        return (result,)
    path = write_page(out, NAME, compute, markdown)
    if out is None:  # the docs themselves: their summary too
        page = DOCS / SUMMARY_PAGE
        page.write_text(with_block(page.read_text(encoding="utf-8"), SUMMARY,
                                   summary(result)), encoding="utf-8")
    return path


def main(argv=None) -> int:
    return report_main(run, __doc__.splitlines()[0], argv, [
        ("--grid", {"type": Path, "help": "a baked grid's folder instead of the shipped one"})])


if __name__ == "__main__":
    raise SystemExit(main())
