"""Measure coat darkening [OpenPBR2026, §Coat darkening; Portsmouth2025] and write
``docs/coat_darkening_measured.md``.

    python -m benchmarks.darkening_report [--smoke] [--out DIR]

- the specification's fit of the Fresnel average E_F against its quadrature;
- K, Delta (both variants), the base factor and the coated albedo at normal incidence for a
  white and a coloured base, coat IOR 1.3 / 1.5 / 2, a smooth and a rough base, a clear and a
  tinted coat, coat_darkening 0 and 1;
- the coated albedo at coat_darkening 1 of the development branch's physical darkening
  (``physical_darkening``), of [Portsmouth2025]'s formula and of v1.1.1's against random walks
  through a tinted coat (``layered.LayeredReference``), smooth and rough, over a Lambertian
  and a mirror base.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from adobe_bsdf import darkening as dk
from adobe_bsdf import fresnel
from adobe_bsdf.composition import Layer
from adobe_bsdf.darkening import Darkening
from adobe_bsdf.fresnel import F82Tint, Weighted
from adobe_bsdf.layered import LayeredReference
from adobe_bsdf.lobes import Conductor, DielectricMS, DielectricReflection, Lambert
from adobe_bsdf.lobes.kulla_conty import DielectricMultipleScattering
from benchmarks import generated_by, report_main

DOCS = Path(__file__).resolve().parents[1] / "docs"
COAT_IORS = (1.3, 1.5, 2.0)
BASES = {"white": (1.0, 1.0, 1.0), "coloured": (0.8, 0.3, 0.1)}
COATS = {"clear": (1.0, 1.0, 1.0), "tinted": (0.9, 0.7, 0.4)}
FIT_ETAS = (1.0, 1.1, 1.3, 1.5, 2.0, 2.5, 3.0)
#: the random-walk comparison: the coat's colour (two-way transmittance at normal incidence),
#: its IORs and roughness (alpha = r^2), the bases' albedos and the views' cosines
WALK_TINT = (0.3, 0.55, 0.85)
WALK_IORS = (1.3, 1.5, 2.0)
WALK_ROUGHNESS = (0.0, 0.3, 0.5)
WALK_BASES = {"white": 1.0, "grey": 0.5}
WALK_COSINES = (0.95, 0.5)
#: walks per colour channel (and in ``--smoke``)
WALKS, SMOKE_WALKS = 200_000, 2_000


def _rgb(c):
    return "(" + ", ".join(f"{x:.4f}" for x in np.ravel(c)) + ")"


def fit_rows():
    eta = np.array(FIT_ETAS)
    exact, fit = dk.fresnel_average(eta), dk.fresnel_average_fit(eta)
    grid = np.linspace(1.0, 3.0, 2001)
    worst = np.abs(dk.fresnel_average_fit(grid) - dk.fresnel_average(grid))
    return list(zip(eta, exact, fit, strict=True)), worst.max(), grid[np.argmax(worst)]


def value_rows():
    rows = []
    for base, E_b in BASES.items():
        for coat, T2 in COATS.items():
            for eta in COAT_IORS:
                F0 = float(fresnel.dielectric(1.0, eta))
                for r_b in (0.0, 1.0):
                    K = float(dk.coat_reflectance(eta, r_b))
                    Delta = dk.darkening(E_b, K, T2)
                    old = dk.darkening(E_b, K, T2, "v1.1.1")
                    E = [F0 + (1.0 - F0) * dk.base_factor(Delta, d, T2) * np.asarray(E_b)
                         for d in (0.0, 1.0)]
                    rows.append((base, coat, eta, r_b, K, Delta, old, E[0], E[1]))
    return rows


def _walk(eta, alpha, E_b, mu, base, walks):
    """``(albedo, standard error)`` ``(3,)`` of random walks entering at cos theta_o = ``mu``
    through the energy-conserving rough interface (``DielectricMS``) over a slab that only
    absorbs, of optical depth -ln(T) / 2 per channel, over a Lambertian or a mirror base of
    albedo ``E_b``."""
    out, err = np.zeros(3), np.zeros(3)
    w = np.broadcast_to(_wo(mu), (walks, 3))
    for c, T in enumerate(WALK_TINT):
        ref = LayeredReference(DielectricMS(eta, alpha), _base(base, E_b),
                               thickness=-np.log(T) / 2.0)
        e = ref.walk(w, np.random.default_rng([11, c]).random((walks, 3))).weight[:, 0]
        out[c], err[c] = e.mean(), e.std() / np.sqrt(walks)
    return out, err


def _wo(mu):
    return np.array([np.sqrt(1.0 - mu * mu), 0.0, mu])


def _base(base, E_b):
    return (Lambert(E_b) if base == "Lambertian" else
            Conductor(0.0, fresnel=Weighted(F82Tint(1.0, 1.0), E_b)))


def _top_reflection(eta, alpha, wo):
    """What the walk's top reflects: the single scattering and the reflected share of the
    Kulla–Conty term."""
    E = DielectricReflection(eta, alpha).albedo(wo, method="table")
    if alpha == 0.0:
        return E
    ms = DielectricMultipleScattering(eta, alpha)
    return E + ms._albedo_table(wo)[0] * ms._reflect_probability(wo)[..., None]


def walk_rows(smoke: bool = False):
    """``(base, E_b name, eta, roughness, mu, walk, error, models)``: the walks' albedo and the
    layers' at coat_darkening 1, models = {name: albedo (3,)}."""
    cases = [("Lambertian", b, eta, r, mu) for b in WALK_BASES for eta in WALK_IORS
             for r in WALK_ROUGHNESS for mu in WALK_COSINES]
    cases += [("mirror", b, 1.5, r, 0.95) for b in WALK_BASES for r in WALK_ROUGHNESS]
    if smoke:
        cases = [cases[0], cases[-1]]
    rows = []
    for base, name, eta, r, mu in cases:
        E_b, alpha, wo = WALK_BASES[name], r * r, _wo(mu)
        r_b = 1.0 if base == "Lambertian" else 0.0
        walk, err = _walk(eta, alpha, E_b, mu, base, SMOKE_WALKS if smoke else WALKS)
        top = DielectricReflection(eta, alpha)

        def layer(variant, scaling, top=top, base=base, E_b=E_b, alpha=alpha, r_b=r_b,
                  wo=wo):
            return Layer(top, _base(base, E_b), transmittance=WALK_TINT, scaling=scaling,
                         darkening=Darkening(1.0, r_b, variant, coat_alpha=alpha)).albedo(
                             wo, tol=1e-6)

        R = _top_reflection(eta, alpha, wo)
        models = {"dev_1.2": layer("dev_1.2", "albedo"),
                  "dev_1.2, walk's top": R + (1.0 - R) * np.asarray(WALK_TINT) * E_b
                  * dk.physical_darkening(E_b, eta, alpha, WALK_TINT, mu, r_b),
                  "pr253": layer("pr253", "transmittance"),
                  "v1.1.1": layer("v1.1.1", "transmittance")}
        rows.append((base, name, eta, r, mu, walk, err, models))
    return rows


def _walk_section(rows):
    names = list(rows[0][-1])
    worst = {k: max(float(np.abs(m[k] - walk).max()) for *_, walk, _, m in rows)
             for k in names}
    sigma = max(float(e.max()) for *_, e, _ in rows)
    lines = ["", "## Physical darkening (dev_1.2) against random walks", "",
             "The coated albedo at coat_darkening 1 against random walks of light "
             "(`layered.LayeredReference`, seeded) through a coat of colour T2 = "
             f"{_rgb(WALK_TINT)} (an absorbing slab of optical depth -ln(T2) / 2 per channel) "
             "between the energy-conserving rough interface `DielectricMS` (GGX plus its "
             "Kulla–Conty term) and a Lambertian base (r_b = 1) or a mirror base (r_b = 0, "
             "`Conductor` of constant reflectance E_b). The layers are built as the material "
             "builds them: a `DielectricReflection` top (single scattering) and "
             "`Darkening(1, r_b, variant, coat_alpha=r^2)`; dev_1.2 with the constant T2 "
             "(scaling \"albedo\"), [Portsmouth2025]'s formula (\"pr253\") and v1.1.1's "
             "with the view-dependent absorption (scaling \"transmittance\"), as the "
             "material built them before. \"dev_1.2, walk's top\" is "
             "E_top + (1 - E_top) T2 Delta_phys E_b with the walk's own top reflection "
             "(the single scattering plus the reflected share of the Kulla–Conty term): the "
             "error of the darkening alone; the layer's differs from it by the top's "
             "multiple-scattering reflection it lacks. \"diff\" is the largest absolute "
             "difference from the walk over the channels.", "",
             "| base | E_b | coat IOR | coat roughness | cos θo | walk | dev_1.2 | diff | "
             "dev_1.2, walk's top | diff | PR 253 | diff | v1.1.1 | diff |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for base, name, eta, r, mu, walk, _, m in rows:
        cells = " | ".join(f"{_rgb3(m[k])} | {np.abs(m[k] - walk).max():.3f}" for k in names)
        lines.append(f"| {base} | {name} | {eta:g} | {r:g} | {mu:g} | {_rgb3(walk)} | "
                     f"{cells} |")
    lines += ["", "Largest |difference| from the walks: " + ", ".join(
        f"{k} **{v:.3f}**" for k, v in worst.items()) + f" (walks' standard error at most "
        f"{sigma:.4f}).", ""]
    return lines


def _rgb3(c):
    return "(" + ", ".join(f"{x:.3f}" for x in np.ravel(c)) + ")"


def run(out: Path | None = None, smoke: bool = False) -> Path:
    start = time.perf_counter()
    docs = DOCS if out is None else Path(out)
    docs.mkdir(parents=True, exist_ok=True)
    fits, worst, where = fit_rows()
    values = value_rows()
    walks = walk_rows(smoke)
    lines = ["# Coat darkening: measured", "",
             generated_by("benchmarks.darkening_report", time.perf_counter() - start,
                          "api.md"), "",
             "`adobe_bsdf.darkening` [OpenPBR2026, §Coat darkening; Portsmouth2025]. "
             "Its tests check Delta against a random walk of light between a smooth coat and "
             "a Lambertian base (`tests/test_darkening.py`), and the physical darkening "
             "against random walks through smooth and rough tinted coats "
             "(`tests/test_darkening_physical.py`).", "",
             "## The Fresnel average and the specification's fit", "",
             "E_F(eta) = 2 int F(mu, eta) mu d mu by Gauss–Legendre (`fresnel_average`) "
             "against the closed-form fit the specification gives (`fresnel_average_fit`).", "",
             "| eta | E_F, quadrature | fit | fit - quadrature |", "|---|---|---|---|"]
    lines += [f"| {e:g} | {x:.6f} | {f:.6f} | {f - x:+.1e} |" for e, x, f in fits]
    lines += ["", f"Over eta in [1, 3] (2001 points) the fit is within **{worst:.1e}** "
              f"(worst at eta = {where:.3f}).", "",
              "## Values at normal incidence", "",
              "K = `coat_reflectance(eta, r_b)` (r_b = 0: smooth base, K = F0; r_b = 1: rough "
              "base, the internal average), Delta = `darkening(E_b, K, T2)` ([Portsmouth2025]) "
              "and the released specification's (`variant=\"v1.1.1\"`), and the coated albedo "
              "at normal incidence F0 + (1 - F0) `base_factor(Delta, delta, T2)` E_b for "
              "coat_darkening delta = 0 (naive: the base tinted by T2) and 1, coverage 1.", "",
              "| base E_b | coat T2 | coat IOR | r_b | K | Delta | Delta, v1.1.1 | "
              "albedo, delta = 0 | albedo, delta = 1 |", "|---|---|---|---|---|---|---|---|---|"]
    lines += [f"| {b} | {c} | {eta:g} | {r:g} | {K:.4f} | {_rgb(D)} | {_rgb(o)} | {_rgb(e0)} | "
              f"{_rgb(e1)} |" for b, c, eta, r, K, D, o, e0, e1 in values]
    lines += _walk_section(walks)
    # the time line again, now that the walks are done
    lines[2] = generated_by("benchmarks.darkening_report", time.perf_counter() - start,
                            "api.md")
    path = docs / "coat_darkening_measured.md"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def main(argv=None) -> int:
    return report_main(run, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    raise SystemExit(main())
