"""The albedos of lobes with a thin film from their tables (or closed forms) against
direction-space quadrature, at random held-out lobes and views; writes
``docs/film_albedo_measured.md``.

    python -m benchmarks.film_albedo [--lobes N] [--jobs J] [--smoke] [--out DIR]

Three families, each at N random lobes (default 24; ``--smoke``: 3, at a loose quadrature
tolerance) times 4 random views (one grazing, |cos theta_o| < 0.1), from one fixed seed:
film thickness uniform in [0, 1500] nm, film index in [1.2, 2.5], roughness r uniform in
[0.05, 1] with alpha = r^2 (isotropic GGX).

* (a) The film over a dielectric base's reflection, as the OpenPBR surface builds it:
  ``ReferencedReflection(DielectricReflection(eta, alpha), ThinFilm(d, n_film, eta))``, base
  index eta in [1.3, 2.5]. Its table albedo against quadrature; the film's albedo difference
  alone (its table albedo minus the film-free ``DielectricReflection``'s, against the
  difference of the two lobes' quadratures), which leaves out the film-free table's own
  interpolation error; and that film-free table against quadrature, for the record.
* (b) The film over an F82-tint metal (f0 in [0.3, 1)^3, tint in [0.6, 1]^3):
  ``ThinFilm.over_f82_tint(d, n_film, f0, tint)`` as the Fresnel model of the
  single-scattering ``Conductor`` and of ``ConductorMS`` with the multiple-scattering colour
  the OpenPBR surface gives it (``mapping.metal_multiple_scattering`` of the film's
  hemispherical average, 48-point Gauss-Legendre, and the white conductor's E_avg), whose
  table albedo is the F = 1 table plus the film's difference tabulated in cos theta_o as in
  (a); for comparison, the F = 1 table plus the 32 x 32 visible-normal rule of the film's
  effect at each view (a conductor's albedo under other Fresnel models).
* (c) The film on a rough glass: ``DielectricMS(eta, alpha, film=ThinFilm(d, n_film, eta))``,
  eta in [1.3, 2.5] (every fourth lobe: its reciprocal, the light side below), views on both
  sides. Its table albedo against quadrature (and, a white glass, |quadrature - 1|); the
  film's single-scattering energy difference Delta of ``film_energy.FilmEnergy`` against the
  quadrature of ``Dielectric(eta, alpha, film=film)`` minus that of ``Dielectric(eta,
  alpha)``; and the single-scattering ``Dielectric(film=)``'s table against quadrature.

Quadrature is ``albedo(wo, tol=...)`` (adaptive cubature of ``eval`` over the sphere): 1e-7
in (a) and (b), 1e-6 in (c) (the glasses' cubature is several times slower). At each
quantity's worst point the quadrature is repeated at a tenth of its tolerance (a check of
its own error beyond its estimate), and the error of a conductor's visible-normal rule and
of ``FilmEnergy``'s rule is taken apart there.
"""

from __future__ import annotations

import argparse
import datetime
import multiprocessing
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from adobe_bsdf import quadrature
from adobe_bsdf.lobes import Dielectric
from adobe_bsdf.lobes.energy_lookup import conductor_average
from adobe_bsdf.lobes.film_energy import FILM_ORDER, FilmEnergy, film_energy_difference
from adobe_bsdf.lobes.kulla_conty import ConductorMS, DielectricMS
from adobe_bsdf.lobes.reflection import Conductor, DielectricReflection, ReferencedReflection
from adobe_bsdf.materials.openpbr import mapping
from adobe_bsdf.microfacet import GGX
from adobe_bsdf.thin_film import ThinFilm

DOCS = Path(__file__).resolve().parents[1] / "docs"
NAME = "film_albedo_measured.md"
SEED = 20261206
LOBES, VIEWS = 24, 4
SMOKE_LOBES = 3
#: the acceptance bound on |table - quadrature| per channel
BOUND = 1e-3
#: quadrature tolerance per family (the glasses' cubature is several times slower: their
#: per-channel multiple-scattering terms, transmission and both sides)
TOL = {"a": 1e-7, "b": 1e-7, "c": 1e-6}
#: ``--smoke`` multiplies the tolerances by this (structure only)
SMOKE_SCALE = 1e3
THICKNESS_NM, FILM_IOR, ROUGHNESS, BASE_IOR = (0.0, 1500.0), (1.2, 2.5), (0.05, 1.0), (1.3, 2.5)
F0, TINT = (0.3, 1.0), (0.6, 1.0)
#: cosines of the ordinary views and of the grazing one
MU, MU_GRAZING = (0.1, 1.0), (0.01, 0.1)
FAMILIES = {
    "a": "film over a dielectric base's reflection",
    "b": "film over an F82-tint metal",
    "c": "film on a rough glass",
}
#: ``name -> (family, label, table terms, quadrature terms)``; a term is (lobe key, sign);
#: the table term "one" is the constant 1, "delta" the ``FilmEnergy`` Delta
QUANTITIES = {
    "a_lobe": ("a", "ReferencedReflection: table vs quadrature",
               [("filmed", 1)], [("filmed", 1)]),
    "a_diff": ("a", "film's difference: (table - film-free table) vs (quadrature - film-free "
                    "quadrature)", [("filmed", 1), ("plain", -1)],
               [("filmed", 1), ("plain", -1)]),
    "a_plain": ("a", "film-free DielectricReflection: table vs quadrature (for the record)",
                [("plain", 1)], [("plain", 1)]),
    "b_ss": ("b", "Conductor(fresnel=film): table vs quadrature",
             [("conductor", 1)], [("conductor", 1)]),
    "b_ms": ("b", "ConductorMS(fresnel=film), as the OpenPBR metal: table vs quadrature",
             [("metal", 1)], [("metal", 1)]),
    "b_rule": ("b", "for comparison: F = 1 table + the 32 x 32 visible-normal rule of the "
                    "film's effect at each view (a conductor's albedo under other Fresnel "
                    "models): vs quadrature", [("rule", 1)], [("conductor", 1)]),
    "c_ms": ("c", "DielectricMS(film=): table vs quadrature", [("glass", 1)], [("glass", 1)]),
    "c_white": ("c", "DielectricMS(film=): |quadrature - 1|", [("one", 1)], [("glass", 1)]),
    "c_delta": ("c", "FilmEnergy Delta vs quadrature of Dielectric(film=) - Dielectric",
                [("delta", 1)], [("single", 1), ("single_plain", -1)]),
    "c_ss": ("c", "Dielectric(film=), single scattering: table vs quadrature (for the record)",
             [("single", 1)], [("single", 1)]),
}
#: quantities that are not the library's lobes as built (not part of the acceptance)
COMPARISONS = ("a_plain", "b_rule", "c_ss")
#: Gauss orders of the attribution at the worst points: the 32 x 32 visible-normal rule of a
#: conductor with a Fresnel model, the visible-normal rule of ``FilmEnergy``
SAMPLED_ORDERS = (32, 64, 128)
FILM_ORDERS = (FILM_ORDER, 2 * FILM_ORDER, 4 * FILM_ORDER)


# -- the held-out points ---------------------------------------------------------------------
def draw(n: int) -> dict[str, list[dict]]:
    """``family -> [parameters of each lobe]``, from ``SEED`` (the same draws for any ``n``
    prefix: each family has its own stream, each lobe a fixed number of draws)."""
    points = {}
    for k, family in enumerate(FAMILIES):
        rng = np.random.default_rng([SEED, k])
        lobes = []
        for i in range(n):
            p = {"d": rng.uniform(*THICKNESS_NM), "n_film": rng.uniform(*FILM_IOR),
                 "r": rng.uniform(*ROUGHNESS), "eta": rng.uniform(*BASE_IOR),
                 "f0": rng.uniform(*F0, 3), "tint": rng.uniform(*TINT, 3)}
            p["alpha"], p["lobe"] = p["r"] ** 2, i
            mu = np.concatenate([rng.uniform(*MU, VIEWS - 1), rng.uniform(*MU_GRAZING, 1)])
            phi = rng.uniform(0.0, 2.0 * np.pi, VIEWS)
            side = np.where(rng.random(VIEWS) < 0.5, 1.0, -1.0)
            if family == "c":
                side[:2] = (1.0, -1.0)  # both sides in every lobe
                if i % 4 == 1:
                    p["eta"] = 1.0 / p["eta"]
            else:
                side[:] = 1.0
                del p["f0" if family == "a" else "eta"]
            if family != "b":
                del p["tint"]
                p.pop("f0", None)
            s = np.sqrt(1.0 - mu * mu)
            p["wo"] = np.stack([s * np.cos(phi), s * np.sin(phi), side * mu], axis=-1)
            lobes.append(p)
        points[family] = lobes
    return points


def _film_average(film) -> np.ndarray:
    """2 int_0^1 F(mu) mu dmu ``(3,)`` of a Fresnel model, 48-point Gauss-Legendre (the
    OpenPBR metal's average of its film)."""
    x, w = np.polynomial.legendre.leggauss(48)
    mu, w = 0.5 * (x + 1.0), 0.5 * w
    return 2.0 * (w * mu) @ np.asarray(film.from_cos2(mu * mu))


#: the lobes built in this process, by (family, lobe): the worst points' second look reuses
#: them (and their tables) where the same process measured the lobe
_BUILT: dict = {}


def lobes(family: str, p: dict) -> dict:
    """The lobes (and the ``FilmEnergy``) of one held-out point, by key (built once per
    process)."""
    key = (family, p["lobe"])
    if key not in _BUILT:
        _BUILT[key] = _build(family, p)
    return _BUILT[key]


def _build(family: str, p: dict) -> dict:
    alpha = p["alpha"]
    if family == "a":
        film = ThinFilm(p["d"], p["n_film"], p["eta"])
        return {"filmed": ReferencedReflection(DielectricReflection(p["eta"], alpha), film),
                "plain": DielectricReflection(p["eta"], alpha)}
    if family == "b":
        film = ThinFilm.over_f82_tint(p["d"], p["n_film"], p["f0"], p["tint"])
        f_ms = mapping.metal_multiple_scattering(_film_average(film),
                                                 conductor_average(GGX(alpha)))
        return {"conductor": Conductor(alpha, fresnel=film),
                "metal": ConductorMS(alpha, fresnel=film, base_color=np.sqrt(f_ms)),
                "white": Conductor(alpha)}
    eta = p["eta"]
    film = ThinFilm(p["d"], p["n_film"], eta)
    glass = DielectricMS(eta, alpha, film=film)
    single = glass.components[0]  # Dielectric(eta, alpha, film=film), its film energy built
    assert isinstance(single, Dielectric) and single.film is film
    return {"glass": glass, "single": single, "single_plain": Dielectric(eta, alpha),
            "energy": FilmEnergy(alpha, max(eta, 1.0 / eta), film, light_above=eta >= 1.0)}


def _table(key, built, p, wo):
    if key == "one":
        return np.ones(wo.shape[:-1] + (3,))
    if key == "rule":
        white = built["white"]
        return (white.albedo(wo, method="table")
                + quadrature.sampled_albedo(built["conductor"], wo, 32)
                - quadrature.sampled_albedo(white, wo, 32))
    if key == "delta":
        mu = wo[..., 2]
        return built["energy"](np.abs(mu), (mu > 0.0) == (p["eta"] >= 1.0))
    return built[key].albedo(wo, method="table")




def measure(task) -> dict:
    """One held-out lobe (``task`` = (family, index, parameters, tolerance scale)): per
    quantity of its family, the table value, the quadrature and its error estimate
    ``(VIEWS, 3)``; the wall-clock and CPU seconds it took and the warnings raised."""
    family, index, p, scale = task
    start, cpu = time.perf_counter(), time.process_time()
    wo = p["wo"]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        built = lobes(family, p)
        quad = {}
        out = {}
        for name, (fam, _, table_terms, quad_terms) in QUANTITIES.items():
            if fam != family:
                continue
            table = sum(sign * _table(key, built, p, wo) for key, sign in table_terms)
            value = error = 0.0
            for key, sign in quad_terms:
                if key not in quad:
                    quad[key] = built[key].albedo(wo, tol=TOL[family] * scale,
                                                  return_error=True)
                value = value + sign * quad[key][0]
                error = error + quad[key][1]
            out[name] = (np.asarray(table), np.asarray(value), np.asarray(error))
    return {"family": family, "index": index, "values": out,
            "seconds": time.perf_counter() - start, "cpu": time.process_time() - cpu,
            "warnings": _messages(caught, f"({family}) lobe {index}")}


def recheck(task) -> dict:
    """At one view (``task`` = (quantity, parameters, view, tolerance scale)): the quantity's
    quadrature at a tenth of its tolerance, and what its error is made of (``parts``:
    ``(label, error (3,))``): for a conductor with a film, the F = 1 table's error and the
    error of the visible-normal rule of the film's effect at ``SAMPLED_ORDERS`` (the table
    albedo's is the first); for Delta, the error of ``FilmEnergy``'s rule itself (no table)
    at ``FILM_ORDERS`` (its table's is the first)."""
    name, p, view, scale = task
    family, _, _, quad_terms = QUANTITIES[name]
    start, cpu = time.perf_counter(), time.process_time()
    tol = TOL[family] * scale / 10.0
    parts = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        built = lobes(family, p)
        wo = p["wo"][view:view + 1]
        quad = {key: built[key].albedo(wo, tol=tol)[0] for key, _ in quad_terms}
        value = sum(sign * quad[key] for key, sign in quad_terms)
        if name == "b_ss":
            white = built["white"].albedo(wo, tol=tol)[0]
            plain = built["white"].albedo(wo, method="table")[0]
            parts.append(("F = 1 table - quadrature", plain - white))
            parts.append(("F = 1 table + the film's difference tabulated in cos theta_o - "
                          "quadrature", built["conductor"].albedo(wo, method="table")[0]
                          - quad["conductor"]))
            for order in SAMPLED_ORDERS:
                rule = (quadrature.sampled_albedo(built["conductor"], wo, order)
                        - quadrature.sampled_albedo(built["white"], wo, order))[0]
                parts.append((f"{order} x {order} visible-normal rule of the film's effect - "
                              "quadrature", rule - (quad["conductor"] - white)))
        elif name == "c_delta":
            eta, mu = p["eta"], wo[0, 2]
            for order in FILM_ORDERS:
                rule = film_energy_difference([abs(mu)], bool((mu > 0.0) == (eta >= 1.0)),
                                              p["alpha"], max(eta, 1.0 / eta),
                                              built["single"].film, order, eta >= 1.0)[0, :3]
                parts.append((f"FilmEnergy's rule at order {order} (untabulated) - quadrature",
                              rule - value))
    return {"name": name, "value": np.asarray(value), "parts": parts,
            "seconds": time.perf_counter() - start, "cpu": time.process_time() - cpu,
            "warnings": _messages(caught, f"({family}) {name}, lobe {p['lobe']} at tol / 10")}


def _messages(caught, where: str) -> list[str]:
    """The distinct first lines of the warnings ``caught``, each prefixed with ``where``."""
    return sorted({f"{where}: {str(w.message).splitlines()[0]}" for w in caught})


def _run(fn, tasks, jobs):
    if jobs <= 1:
        return [fn(t) for t in tasks]
    with ProcessPoolExecutor(max_workers=jobs,
                             mp_context=multiprocessing.get_context("fork")) as pool:
        return list(pool.map(fn, tasks))


# -- the summary -------------------------------------------------------------------------------
def summarize(points, results) -> dict:
    """Per quantity: max and RMS of |table - quadrature| per channel, the worst point, the
    largest quadrature error estimate."""
    by_family = {f: sorted((r for r in results if r["family"] == f), key=lambda r: r["index"])
                 for f in FAMILIES}
    summary = {}
    for name, (family, label, _, _) in QUANTITIES.items():
        rows = by_family[family]
        if not rows:
            continue
        table = np.stack([r["values"][name][0] for r in rows])  # (N, VIEWS, 3)
        quad = np.stack([r["values"][name][1] for r in rows])
        error = np.stack([r["values"][name][2] for r in rows])
        diff = np.abs(table - quad)
        i, v, c = np.unravel_index(int(np.argmax(diff)), diff.shape)
        summary[name] = {
            "family": family, "label": label, "points": diff.shape[0] * diff.shape[1],
            "max": diff.reshape(-1, 3).max(axis=0),
            "rms": np.sqrt(np.mean(diff.reshape(-1, 3) ** 2, axis=0)),
            "quad_error": float(error.max()),
            "worst": {"lobe": int(rows[i]["index"]), "view": int(v), "channel": int(c),
                      "table": float(table[i, v, c]), "quad": float(quad[i, v, c]),
                      "params": points[family][rows[i]["index"]]},
            "lobes": points[family],
            "beyond": [(int(rows[a]["index"]), int(b), int(ch), float(diff[a, b, ch]))
                       for a, b, ch in zip(*np.nonzero(diff > BOUND), strict=True)],
        }
    return summary


def cell(text: str) -> str:
    """``text`` for a markdown table cell (its bars escaped)."""
    return text.replace("|", "\\|")


def _fmt(x) -> str:
    return f"{x:.1e}"


def _rgb(v) -> str:
    return ", ".join(_fmt(x) for x in v)


def _describe(family, p, view=None) -> str:
    """The parameters of a held-out point in words."""
    parts = [f"d = {p['d']:.0f} nm", f"n_film = {p['n_film']:.3f}"]
    if "eta" in p:
        parts.append(f"eta = {p['eta']:.3f}")
    if "f0" in p:
        parts.append("f0 = (" + ", ".join(f"{x:.3f}" for x in p["f0"]) + ")")
        parts.append("tint = (" + ", ".join(f"{x:.3f}" for x in p["tint"]) + ")")
    parts.append(f"r = {p['r']:.3f} (alpha = {p['alpha']:.4f})")
    if view is not None:
        parts.append(f"cos theta_o = {p['wo'][view, 2]:+.4f}")
    return ", ".join(parts)


def report(summary, checks, results, n, scale, seconds, jobs, smoke) -> str:
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    ch = "RGB"
    tol = {f: TOL[f] * scale for f in FAMILIES}
    out = [f"*Generated by `python -m benchmarks.film_albedo` on {stamp} in {seconds:.0f} s "
           f"({jobs} process{'es' if jobs > 1 else ''}{'; smoke run' if smoke else ''}); do "
           "not edit by hand.*",
           "",
           "# Thin-film albedos: tables against quadrature",
           "",
           "The directional albedo of lobes with a thin film from their tables (or closed "
           "forms), `albedo(wo, method=\"table\")`, against direction-space quadrature, "
           "`albedo(wo, tol=...)` (adaptive cubature of `eval` over the sphere), at "
           f"{n} random held-out lobes per family times {VIEWS} random views (one grazing, "
           f"|cos theta_o| in [{MU_GRAZING[0]}, {MU_GRAZING[1]}), the others in "
           f"[{MU[0]}, {MU[1]}]), seed {SEED}: film thickness d uniform in "
           f"[{THICKNESS_NM[0]:.0f}, {THICKNESS_NM[1]:.0f}] nm, film index n_film in "
           f"[{FILM_IOR[0]}, {FILM_IOR[1]}], roughness r in [{ROUGHNESS[0]}, {ROUGHNESS[1]}] "
           "with alpha = r^2 (isotropic GGX). The films use the default spectral model.",
           "",
           f"- **(a) {FAMILIES['a']}**: `ReferencedReflection(DielectricReflection(eta, alpha), "
           f"ThinFilm(d, n_film, eta))`, eta in [{BASE_IOR[0]}, {BASE_IOR[1]}], the OpenPBR "
           "surface's filmed specular reflection. The film's difference alone subtracts "
           "the film-free lobe on both sides, so the film-free table's own interpolation "
           "error drops out.",
           f"- **(b) {FAMILIES['b']}**: `ThinFilm.over_f82_tint(d, n_film, f0, tint)`, f0 in "
           f"[{F0[0]}, {F0[1]})^3, tint in [{TINT[0]}, {TINT[1]}]^3, as the Fresnel model of "
           "the single-scattering `Conductor` and of `ConductorMS` with the OpenPBR metal's "
           "multiple-scattering colour (`mapping.metal_multiple_scattering` of the film's "
           "48-point hemispherical average and the white conductor's E_avg). With a film "
           "the conductor's table albedo is the F = 1 table plus the film's difference "
           "tabulated in cos theta_o, as (a) does it (`ReferencedReflection(Conductor(alpha), "
           "film)`). For comparison, the F = 1 table plus a 32 x 32 visible-normal rule of "
           "the film's effect at each view, a conductor's table albedo under Fresnel models "
           "other than a film (the same quadrature).",
           f"- **(c) {FAMILIES['c']}**: `DielectricMS(eta, alpha, film=ThinFilm(d, n_film, "
           f"eta))`, eta in [{BASE_IOR[0]}, {BASE_IOR[1]}] and, every fourth lobe, its "
           "reciprocal (the light side below); two views above and two below the surface in "
           "each lobe (the grazing one on either). A white glass, so its table albedo is 1. "
           "Delta is `FilmEnergy(alpha, max(eta, 1/eta), film, light_above=eta >= 1)` "
           "against the quadrature of `Dielectric(eta, alpha, film=film)` minus that of "
           "`Dielectric(eta, alpha)`.",
           "",
           f"Quadrature tolerance: {tol['a']:.0e} in (a) and (b), {tol['c']:.0e} in (c) (the "
           "glasses' cubature, with transmission, both sides and per-channel "
           "multiple-scattering terms, is several times slower). The largest error estimate "
           "of each quantity is in the table; at each quantity's worst point the quadrature "
           "was repeated at a tenth of its tolerance (below).",
           "",
           f"## |table - quadrature| per channel (R, G, B) over {n * VIEWS} points per family",
           "",
           "| family | quantity | max | RMS | quadrature error estimate (max) | "
           f"max within {BOUND:g} |",
           "|---|---|---|---|---|---|"]
    for s in summary.values():
        ok = "yes" if s["max"].max() <= BOUND else "**no**"
        out.append(f"| ({s['family']}) | {cell(s['label'])} | {_rgb(s['max'])} | "
                   f"{_rgb(s['rms'])} | {_fmt(s['quad_error'])} | {ok} |")
    accepted = [name for name in summary if name not in COMPARISONS]
    failed = [name for name in accepted if summary[name]["max"].max() > BOUND]
    out += ["", f"The library's lobes as built ({', '.join(accepted)}; the rows marked for "
            "the record or for comparison aside): "
            + ("every point within " + f"{BOUND:g}." if not failed else
               f"beyond {BOUND:g} in {', '.join(failed)} (the points below).")]
    out += ["", "## Worst points", "",
            "The point of each quantity's maximum (channel, table value, quadrature), and the "
            "quadrature there repeated at a tenth of its tolerance:", "",
            "| quantity | parameters | channel | table | quadrature | quadrature at tol / 10 |",
            "|---|---|---|---|---|---|"]
    for name, s in summary.items():
        w = s["worst"]
        again = checks.get(name)
        again_text = ("-" if again is None else
                      f"{again['value'][w['channel']]:.6f} (moved "
                      f"{_fmt(abs(again['value'][w['channel']] - w['quad']))})")
        out.append(f"| ({s['family']}) {name} | lobe {w['lobe']}: "
                   f"{_describe(s['family'], w['params'], w['view'])} | {ch[w['channel']]} | "
                   f"{w['table']:.6f} | {w['quad']:.6f} | {again_text} |")
    parts = [(name, label, error) for name, c in checks.items() for label, error in c["parts"]]
    if parts:
        out += ["", "What the error at those points is made of (R, G, B; against the "
                "quadrature at a tenth of its tolerance):", "",
                "| quantity | part | error (R, G, B) |", "|---|---|---|"]
        out += [f"| ({QUANTITIES[name][0]}) {name} | {label} | "
                + ", ".join(f"{x:+.1e}" for x in error) + " |" for name, label, error in parts]
    beyond = [(name, b) for name, s in summary.items() for b in s["beyond"]]
    out += ["", f"## Points beyond {BOUND:g}", ""]
    if not beyond:
        out.append("None.")
    else:
        out += ["| quantity | lobe | parameters | channel | \\|table - quadrature\\| |",
                "|---|---|---|---|---|"]
        for name, (lobe, view, c, d) in beyond:
            family = QUANTITIES[name][0]
            params = _describe(family, summary[name]["lobes"][lobe], view)
            out.append(f"| ({family}) {name} | {lobe} | {params} | {ch[c]} | {_fmt(d)} |")
    kinds = (*FAMILIES, "recheck")
    cpu = {f: sum(r["cpu"] for r in results if r["family"] == f) for f in kinds}
    wall = {f: sum(r["seconds"] for r in results if r["family"] == f) for f in kinds}
    warned = sorted({m for r in results for m in r["warnings"]})
    out += ["", "## Cost", "",
            "CPU seconds per family (lobe construction, tables and quadrature; in brackets "
            "the seconds its tasks took, which include waiting for a core): "
            + ", ".join(f"({f}) {cpu[f]:.0f} s [{wall[f]:.0f} s]" for f in FAMILIES)
            + f"; the repeated quadratures at the worst points {cpu['recheck']:.0f} s "
            f"[{wall['recheck']:.0f} s]; {seconds:.0f} s wall-clock in all with {jobs} "
            "process" + ("es" if jobs > 1 else "") + ".", ""]
    out.append("Quadrature warnings: " + ("none." if not warned else
                                          "; ".join(warned) + "."))
    out.append("")
    return "\n".join(out)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lobes", type=int, default=None,
                        help=f"held-out lobes per family (default {LOBES}; smoke "
                             f"{SMOKE_LOBES})")
    parser.add_argument("--jobs", type=int, default=None,
                        help="worker processes (default 2; smoke 1)")
    parser.add_argument("--smoke", action="store_true",
                        help=f"{SMOKE_LOBES} lobes per family, tolerances times {SMOKE_SCALE:g}")
    parser.add_argument("--out", type=Path, default=DOCS)
    args = parser.parse_args(argv)
    n = args.lobes or (SMOKE_LOBES if args.smoke else LOBES)
    jobs = args.jobs or (1 if args.smoke else 2)
    scale = SMOKE_SCALE if args.smoke else 1.0
    start = time.perf_counter()
    points = draw(n)
    # the glasses first: the slowest tasks, so that the processes end together
    tasks = [(f, i, p, scale) for f in ("c", "b", "a") for i, p in enumerate(points[f])]
    results = _run(measure, tasks, jobs)
    summary = summarize(points, results)
    # (the glasses first, as above; |quadrature - 1| shares the glass's quadrature, the
    # metal's its conductor's where the worst point is the same)
    todo = sorted([(name, s["worst"]["params"], s["worst"]["view"], scale)
                   for name, s in summary.items() if name != "c_white"],
                  key=lambda t: t[0] < "c")
    checks = {}
    for r in _run(recheck, todo, jobs):
        checks[r["name"]] = r
        results.append({"family": "recheck", "seconds": r["seconds"], "cpu": r["cpu"],
                        "warnings": r["warnings"]})
    if "c_white" in summary:
        checks["c_white"] = {"value": checks["c_ms"]["value"], "parts": []}
    text = report(summary, checks, results, n, scale, time.perf_counter() - start, jobs,
                  args.smoke)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / NAME).write_text(text, encoding="utf-8")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
