"""Rough glass against the physical random walk: the library's energy-compensated
``DielectricMS`` and Adobe's OpenPBR implementation, both compared with the microsurface walk
of ``adobe_bsdf.validation.microsurface`` [Heitz2016ms].

    python -m benchmarks.microsurface_peer [--walks N] [--albedo-walks N] [--smoke]

Prints markdown tables (nothing is written):

* reflection f(wo, wi) of two OpenPBR glasses (specular_ior, specular_roughness r; GGX
  alpha = r^2) at three pairs, wo = (sin t cos 0.2, sin t sin 0.2, mu_o), wi at azimuth 2.1:
  the walk (all orders, its single- and multiple-scattering parts; the multiple part also by
  next-event estimation alone), the library's single-scattering ``Dielectric`` and
  ``DielectricMS``, and Adobe's values;
* the reflected and transmitted energy R(mu), T(mu) of ``DielectricMS`` (its single
  scattering by the tables' node quadrature, ``tables.energy.ggx_energy``; its
  multiple-scattering term by the mean of that term's own sample weights, split by the
  hemisphere of the sampled direction) against the walk's (analog walks, by order).

The walk's single scattering in reflection is ``Dielectric``'s exactly (height-correlated
masking), so the difference between ``DielectricMS`` and the walk at a reflection pair is the
difference of their multiple-scattering terms.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from adobe_bsdf.lobes import Dielectric, DielectricMS, DielectricMultipleScattering
from adobe_bsdf.tables.energy import ggx_energy
from adobe_bsdf.validation.microsurface import MicrosurfaceDielectric

#: the glasses: OpenPBR (specular_ior, specular_roughness)
GLASSES = {"A": (1.5, 0.35), "B": (1.6, 0.1)}
#: (mu_o, mu_i) of the reflection pairs, and the azimuths of wo and wi
PAIRS = ((0.8, 0.6), (0.5, 0.3), (0.3, 0.9))
PHI_O, PHI_I = 0.2, 2.1
#: Adobe's OpenPBR implementation at PAIRS (grey), as reported for this comparison
ADOBE = {"A": (0.0014816, 0.0015553, 0.0015098), "B": (1.3917e-05, 9.5153e-06, 1.3297e-05)}
#: the cosines of the energy table
MUS = (0.9, 0.5, 0.2)
#: walks per pair, analog walks per albedo direction, samples of the library's MS term
WALKS, ALBEDO_WALKS, MS_SAMPLES = 1_000_000, 4_000_000, 1_000_000
SMOKE = {"walks": 2_000, "albedo_walks": 20_000, "ms_samples": 20_000}


def sph(mu, phi):
    mu = np.asarray(mu, dtype=float)
    s = np.sqrt(1.0 - mu * mu)
    return np.stack(np.broadcast_arrays(s * np.cos(phi), s * np.sin(phi), mu), -1)


def glass(name):
    """``(eta, alpha)`` of an OpenPBR glass: alpha = roughness^2."""
    ior, roughness = GLASSES[name]
    return ior, roughness * roughness


def reflection_rows(name, walks):
    """One row per pair: the walk's estimates and the library's and Adobe's values."""
    eta, alpha = glass(name)
    mu_o, mu_i = np.array(PAIRS).T
    wo, wi = sph(mu_o, PHI_O), sph(mu_i, PHI_I)
    walk = MicrosurfaceDielectric(eta, alpha)
    mis = walk.eval_orders(wo, wi, n_walks=walks, seed=1)
    nee = walk.eval_orders(wo, wi, n_walks=walks, seed=2, mis=False)
    single = Dielectric(eta, alpha).eval(wo, wi)[:, 0]
    ms = DielectricMS(eta, alpha).eval(wo, wi)[:, 0]
    rows = []
    for k, (o, i) in enumerate(PAIRS):
        rows.append({"pair": (o, i), "walk": mis.all[k, 0], "walk_err": mis.all_error[k, 0],
                     "walk_ss": mis.single[k, 0], "walk_ss_err": mis.single_error[k, 0],
                     "walk_ms": mis.multiple[k, 0], "walk_ms_err": mis.multiple_error[k, 0],
                     "nee_ms": nee.multiple[k, 0], "nee_ms_err": nee.multiple_error[k, 0],
                     "single": single[k], "library": ms[k], "adobe": ADOBE[name][k]})
    return rows


def library_split(eta, alpha, mu, samples):
    """``(R, T, R_ms_err, T_ms_err)`` of ``DielectricMS`` at cos theta_o = ``mu``: single
    scattering by ``ggx_energy``, the multiple-scattering term by its sample weights."""
    E = ggx_energy(mu, alpha, eta)
    wo = np.broadcast_to(sph(mu, 0.0), (samples, 3))
    term = DielectricMultipleScattering(eta, alpha)
    s = term.sample(wo, np.random.default_rng(3).random((samples, 3)))
    up = s.wi[:, 2] > 0.0
    r = np.where(up & (s.pdf > 0.0), s.weight[:, 0], 0.0)
    t = np.where(~up & (s.pdf > 0.0), s.weight[:, 0] * eta * eta, 0.0)  # energy: (eta_i/eta_o)^2
    se = np.sqrt(samples)
    return (float(E.reflection) + r.mean(), float(E.transmission) + t.mean(), r.std() / se,
            t.std() / se, float(E.reflection), float(E.transmission))


def albedo_rows(name, walks, samples):
    eta, alpha = glass(name)
    walk = MicrosurfaceDielectric(eta, alpha)
    rows = []
    for mu in MUS:
        wo = sph(mu, 0.0)
        every = walk.albedo(wo, n_walks=walks, seed=4)
        single = walk.albedo(wo, n_walks=walks, seed=4, order="single")  # the same walks
        R, T, R_err, T_err, R_ss, T_ss = library_split(eta, alpha, mu, samples)
        rows.append({"mu": mu, "walk_R": every.reflected[0], "walk_T": every.transmitted[0],
                     "walk_err": every.reflected_error[0], "walk_R1": single.reflected[0],
                     "walk_T1": single.transmitted[0], "walk_1_err": single.reflected_error[0],
                     "lib_R": R, "lib_T": T, "lib_R_err": R_err, "lib_T_err": T_err,
                     "lib_R1": R_ss, "lib_T1": T_ss, "lost": float(every.lost)})
    return rows


def _g(x, digits=5):
    return f"{x:.{digits}g}"


def _pm(x, e, digits=5):
    return f"{x:.{digits}g} ± {e:.2g}"


def _dev(x, ref, err):
    """(x - ref) / ref in percent and in standard errors of ref."""
    return f"{100.0 * (x - ref) / ref:+.1f}% ({(x - ref) / err:+.0f}σ)"


def reflection_table(name, rows):
    eta, alpha = glass(name)
    ior, r = GLASSES[name]
    lines = [f"**Glass {name}**: specular_ior {ior}, specular_roughness {r} (GGX alpha = "
             f"{alpha:g}); reflection f(wo, wi), grey.", "",
             "| (mu_o, mu_i) | walk, all orders | walk, single | walk, multiple | "
             "walk, multiple (NEE only) | `Dielectric` | `DielectricMS` | its MS term | "
             "Adobe | `DielectricMS` vs walk | Adobe vs walk | closer |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        walk, err = row["walk"], row["walk_err"]
        lib, adobe = row["library"], row["adobe"]
        closer = "library" if abs(lib - walk) < abs(adobe - walk) else "Adobe"
        lines.append(
            f"| {row['pair']} | {_pm(walk, err)} | {_pm(row['walk_ss'], row['walk_ss_err'])} | "
            f"{_pm(row['walk_ms'], row['walk_ms_err'], 4)} | "
            f"{_pm(row['nee_ms'], row['nee_ms_err'], 4)} | {_g(row['single'])} | {_g(lib)} | "
            f"{_g(lib - row['single'], 4)} | {_g(adobe)} | {_dev(lib, walk, err)} | "
            f"{_dev(adobe, walk, err)} | {closer} |")
    return "\n".join(lines)


def albedo_table(name, rows):
    lines = [f"**Glass {name}**: energy leaving above (R) and below (T) for light from above "
             "at cos theta_o = mu; 1 - (R + T) of the walk is 0 for every walk (lost: "
             f"{max(r['lost'] for r in rows):g}).", "",
             "| mu | walk R | `DielectricMS` R | walk T | `DielectricMS` T | walk R, single | "
             "`Dielectric` R | walk T, single | `Dielectric` T | walk R, multiple | "
             "MS term R | walk T, multiple | MS term T |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(
            f"| {r['mu']} | {_pm(r['walk_R'], r['walk_err'], 4)} | "
            f"{_pm(r['lib_R'], r['lib_R_err'], 4)} | {_pm(r['walk_T'], r['walk_err'], 4)} | "
            f"{_pm(r['lib_T'], r['lib_T_err'], 4)} | {_pm(r['walk_R1'], r['walk_1_err'], 4)} | "
            f"{_g(r['lib_R1'], 4)} | {_g(r['walk_T1'], 4)} | {_g(r['lib_T1'], 4)} | "
            f"{_g(r['walk_R'] - r['walk_R1'], 3)} | {_g(r['lib_R'] - r['lib_R1'], 3)} | "
            f"{_g(r['walk_T'] - r['walk_T1'], 3)} | {_g(r['lib_T'] - r['lib_T1'], 3)} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--walks", type=int, default=WALKS, help="walks per pair")
    parser.add_argument("--albedo-walks", type=int, default=ALBEDO_WALKS,
                        help="analog walks per albedo direction")
    parser.add_argument("--ms-samples", type=int, default=MS_SAMPLES,
                        help="samples of DielectricMS's multiple-scattering term")
    parser.add_argument("--smoke", action="store_true", help="tiny sizes")
    args = parser.parse_args(argv)
    walks, albedo_walks, samples = ((SMOKE["walks"], SMOKE["albedo_walks"], SMOKE["ms_samples"])
                                    if args.smoke else
                                    (args.walks, args.albedo_walks, args.ms_samples))
    start = time.perf_counter()
    print(f"## Rough glass reflection against the microsurface random walk\n\n"
          f"{walks} walks per pair (multiple orders: next-event estimation and the adjoint "
          f"connection, balance heuristic; and next-event estimation alone, independent walks), "
          f"{albedo_walks} analog walks per albedo direction, {samples} samples of the "
          f"library's multiple-scattering term; ± one standard error.\n")
    for name in GLASSES:
        print(reflection_table(name, reflection_rows(name, walks)) + "\n")
    for name in GLASSES:
        print(albedo_table(name, albedo_rows(name, albedo_walks, samples)) + "\n")
    print(f"*{time.perf_counter() - start:.0f} s*")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
