"""The multiply scattered reflection of a rough dielectric against the microsurface random
walk [Heitz2016ms], the choice of ``kulla_conty.GLOSSY_SHARE`` it makes, and the accuracy of
the glossy term's table; writes ``docs/ms_reflection_measured.md``.

    python -m benchmarks.ms_reflection [--walks N] [--smoke] [--out DIR]

* The fit: over a grid of roughness, index and reflection pairs on the light side (the
  pairs about and away from the mirror direction; not the pairs of the OpenPBR peer
  comparison), the reflection f of ``DielectricMS`` with the light side's multiply reflected
  energy split g : 1 - g between ``DielectricMultipleReflection`` (glossy) and the separable
  term, against the walk's (the walk's single scattering in reflection is ``Dielectric``'s
  exactly, so the single-scattering part is the library's and only the multiple part is
  walked). The log-RMS of f_model / f_walk per g; ``GLOSSY_SHARE`` is the g of the least.
* The dense side, for the record: the separable term's reflection there against the walk
  (the library keeps it; ``docs/energy_models.md``).
* The glossy term's energy: its albedo by quadrature of ``eval`` against what its table
  makes it reflect, w (1 - E_L(mu)), at random held-out (alpha, eta, mu).
"""

from __future__ import annotations

import argparse
import datetime
import time
from pathlib import Path

import numpy as np

from adobe_bsdf.lobes import Dielectric, DielectricMultipleReflection
from adobe_bsdf.lobes.kulla_conty import GLOSSY_SHARE, SeparableDielectricMS
from adobe_bsdf.validation.microsurface import MicrosurfaceDielectric

DOCS = Path(__file__).resolve().parents[1] / "docs"
ALPHAS = (0.03, 0.12, 0.3, 0.6)
ETAS = (1.33, 1.6, 2.2)
MU_O, MU_I = (0.15, 0.4, 0.7, 0.95), (0.1, 0.3, 0.6, 0.9)
#: azimuth of wi from wo's (wo at azimuth 0): pi is the mirror plane
DPHI = (0.2, 1.2, 2.2, 2.8, 3.1)
SHARES = (0.0, 0.25, 0.5, 0.75, 0.8, 0.85, 0.9, 0.95, 1.0)
WALKS, HELD_OUT = 20_000, 200
SMOKE = {"walks": 500, "held_out": 6}


def _direction(mu, phi, side=1.0):
    mu = np.asarray(mu, dtype=np.float64)
    s = np.sqrt(1.0 - mu * mu)
    return np.stack(np.broadcast_arrays(s * np.cos(phi), s * np.sin(phi), side * mu), -1)


def _pairs(side):
    rows = [(o, i, p) for o in MU_O for i in MU_I for p in DPHI]
    wo = np.stack([_direction(o, 0.0, side) for o, _, _ in rows])
    wi = np.stack([_direction(i, p, side) for _, i, p in rows])
    return wo, wi


def _parts(eta, alpha, wo, wi):
    """(single scattering, separable reflection at the full share r_s, glossy reflection at
    the full share r_L) at light-side reflection pairs; on the dense side the glossy part
    is 0 and the separable term is the library's."""
    separable = SeparableDielectricMS(eta, alpha)
    ss = Dielectric(eta, alpha).eval(wo, wi)[:, 0]
    light = (wo[:, 2] > 0) == (eta >= 1.0)
    kept = np.where(light, 1.0 - GLOSSY_SHARE, 1.0)
    sep = separable.eval(wo, wi)[:, 0] / kept
    r_L = 1.0 - separable.transmitted_share[0]
    glossy = DielectricMultipleReflection(eta, alpha, weight=r_L).eval(wo, wi)[:, 0]
    return ss, sep, glossy


def _log_rms(model, walk):
    ok = (walk > 0) & (model > 0)
    return float(np.sqrt(np.mean(np.log(model[ok] / walk[ok]) ** 2)))


def fit(walks):
    """``(rows, per_share, dense)``: per (alpha, eta) the log-RMS of the separable (g = 0)
    and the chosen split; the log-RMS over the whole grid per g; the dense side's."""
    collected, dense, rows = [], [], []
    for alpha in ALPHAS:
        for eta in ETAS:
            walk = MicrosurfaceDielectric(eta, alpha)
            wo, wi = _pairs(1.0)
            ss, sep, glossy = _parts(eta, alpha, wo, wi)
            f_walk = ss + walk.eval(wo, wi, n_walks=walks, seed=7, order="multiple")[:, 0]
            collected.append((ss, sep, glossy, f_walk))
            rows.append((alpha, eta, _log_rms(ss + sep, f_walk),
                         _log_rms(ss + (1 - GLOSSY_SHARE) * sep + GLOSSY_SHARE * glossy,
                                  f_walk)))
            wo, wi = _pairs(-1.0)
            ss_d, sep_d, _ = _parts(eta, alpha, wo, wi)
            f_d = ss_d + walk.eval(wo, wi, n_walks=walks, seed=8, order="multiple")[:, 0]
            dense.append((alpha, eta, _log_rms(ss_d + sep_d, f_d)))
    per_share = []
    for g in SHARES:
        model = np.concatenate([ss + (1 - g) * sep + g * gl for ss, sep, gl, _ in collected])
        walk = np.concatenate([w for *_, w in collected])
        per_share.append((g, _log_rms(model, walk)))
    return rows, per_share, dense


def held_out(n, seed=5):
    """``(max, RMS)`` of |albedo by quadrature - table albedo| of the glossy term (weight 1)
    at ``n`` random (alpha log-uniform in [0.01, 2], eta in [1.01, 3], mu in [0.01, 1],
    either side), and the largest relative to the table albedo."""
    rng = np.random.default_rng(seed)
    diffs, rel = [], []
    for _ in range(n):
        alpha = float(np.exp(rng.uniform(np.log(0.01), np.log(2.0))))
        eta = float(rng.uniform(1.01, 3.0))
        mu = float(rng.uniform(0.01, 1.0))
        below = rng.random() < 0.5
        lobe = DielectricMultipleReflection(1 / eta if below else eta, alpha)
        wo = _direction(mu, 0.3, -1.0 if below else 1.0)
        table = float(lobe.albedo(wo, method="table")[0])
        quad = float(lobe.albedo(wo, tol=1e-8)[0])
        diffs.append(abs(quad - table))
        rel.append(abs(quad - table) / max(table, 1e-300))
    d = np.array(diffs)
    return float(d.max()), float(np.sqrt(np.mean(d**2))), float(max(rel))


def report(rows, per_share, dense, errors, walks, n_held, seconds):
    best = min(per_share, key=lambda r: r[1])
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    out = ["# Multiply scattered reflection of a rough dielectric: measured",
           "",
           f"*Generated by `python -m benchmarks.ms_reflection` on {stamp} in {seconds:.0f} s "
           f"({walks} walks per pair); do not edit by hand. The model is in "
           "[energy_models.md](energy_models.md).*",
           "",
           "## The split of the light side's multiple reflection",
           "",
           f"Reflection f of `DielectricMS` against the microsurface random walk [Heitz2016ms] "
           f"at {len(MU_O) * len(MU_I) * len(DPHI)} pairs per (alpha, eta) on the light side "
           f"(cos theta_o in {MU_O}, cos theta_i in {MU_I}, wi at {DPHI} rad of azimuth from "
           "wo; pi is the mirror plane), with the multiply reflected energy split g : 1 - g "
           "between the glossy `DielectricMultipleReflection` and the separable term. "
           "Log-RMS of f_model / f_walk over the whole grid:",
           "",
           "| g | log-RMS |", "|---|---|"]
    out += [f"| {g:g} | {e:.3f} |" for g, e in per_share]
    out += ["", f"The least is at g = {best[0]:g}; `GLOSSY_SHARE` = {GLOSSY_SHARE:g}. Per "
            "(alpha, eta):", "",
            "| alpha | eta | separable alone | library |", "|---|---|---|---|"]
    out += [f"| {a:g} | {e:g} | {s:.3f} | {m:.3f} |" for a, e, s, m in rows]
    out += ["", "## The dense side", "",
            "The separable term's reflection inside the dense medium against the walk, the same "
            "pairs mirrored (log-RMS). The walk's reflection there is glossy too (about the "
            "mirror direction, with total internal reflection); the library keeps the "
            "separable term on this side.", "",
            "| alpha | eta | log-RMS |", "|---|---|---|"]
    out += [f"| {a:g} | {e:g} | {s:.3f} |" for a, e, s in dense]
    worst, rms, rel = errors
    out += ["", "## The glossy term's energy", "",
            f"Its albedo by quadrature of `eval` (tol 1e-8) against w (1 - E_L(mu)), what the "
            f"table's scaling makes it reflect, at {n_held} random held-out points (alpha "
            "log-uniform in [0.01, 2], eta in [1.01, 3], cos theta_o in [0.01, 1], either "
            f"side): max {worst:.2e}, RMS {rms:.2e} in energy; the largest relative "
            f"difference {rel:.2e}.", ""]
    return "\n".join(out)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--walks", type=int, default=WALKS)
    parser.add_argument("--smoke", action="store_true")
    parser.add_argument("--out", type=Path, default=DOCS)
    args = parser.parse_args(argv)
    walks = SMOKE["walks"] if args.smoke else args.walks
    n_held = SMOKE["held_out"] if args.smoke else HELD_OUT
    start = time.perf_counter()
    rows, per_share, dense = fit(walks)
    errors = held_out(n_held)
    text = report(rows, per_share, dense, errors, walks, n_held, time.perf_counter() - start)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "ms_reflection_measured.md").write_text(text, encoding="utf-8")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
