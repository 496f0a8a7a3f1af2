"""Measure the shipped tables and write ``docs/tables.md`` and ``docs/accuracy.md``.

    python -m benchmarks.tables_report [--queries 10000] [--quadrature-queries 200]

* interpolation error of every table at random off-node points against fresh node quadrature
  (``tables.ggx_energy`` at order 28), max and RMS, over the whole domain and over the
  region mu >= 0.01, alpha >= 0.0025 (roughness >= 0.05);
* the anisotropic conductor table against the stretched quadrature, and the isotropic table at
  sqrt(alpha_x alpha_y) that anisotropic lobes read before it (conductor, F = 1);
* the band of nearly index-matched, grazing queries (``energy_lookup.near_matched``): the raw
  tables there, the table path (which integrates there) and the tables just outside it;
* table sizes, bake times (from the files' metadata) and the time to load every table;
* ``albedo(method="table")`` against ``method="quadrature"`` on the same random queries: time
  per query and error against the node integrator.
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import os
import time
from pathlib import Path

import numpy as np

from adobe_bsdf import config, lobes, tables
from adobe_bsdf.composition import Rotated
from adobe_bsdf.lobes import energy_lookup as near
from adobe_bsdf.materials import AdobeStandardMaterial, OpenPBRSurface
from adobe_bsdf.materials.asm.diffuse import ASMSpecular, _lobe_integral
from adobe_bsdf.materials.asm.mapping import alphas, effective_roughness
from adobe_bsdf.microfacet import GGX
from adobe_bsdf.tables import bake as baking
from adobe_bsdf.tables import dielectric_slices, ggx_energy
from adobe_bsdf.tables.anisotropic_energy import (
    fresnel_coefficients,
    ggx_anisotropic_dielectric_energy,
    ggx_anisotropic_energy,
    ggx_anisotropic_moments,
)
from adobe_bsdf.tables.catalog import CHECK_ETAS, MOMENT_DEGREE
from adobe_bsdf.tables.executors import open_executor

DOCS = Path(__file__).resolve().parents[1] / "docs"
ORDER = 28


#: tables whose interpolation error is measured elsewhere, through the lobe's own lookup (the
#: sheen rescales small roughness: docs/sheen_measured.md; the anisotropic conductor is
#: looked up in its similarity coordinate: ``anisotropy_rows``; the glossy multiple
#: reflection's scaling, by the energy it makes its lobe reflect:
#: docs/ms_reflection_measured.md)
OWN_REPORT = ("sheen_albedo", "ggx_conductor_anisotropic", "ggx_reflection_moments",
              "ggx_dielectric_ms_reflection")


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


#: points of the anisotropic table's report and the reference quadrature order
ANISO_POINTS, ANISO_ORDER = 400, 20


def anisotropy_rows(rng, n=ANISO_POINTS):
    """Conductor, F = 1, random wo and anisotropic alphas: |E| error of the anisotropic table
    (``conductor_energy``) and of the isotropic table at sqrt(alpha_x alpha_y) (the lookup
    before the anisotropic table) against the stretched quadrature at ``ANISO_ORDER``; per
    range of alpha_max, whole domain and mu >= 0.01."""
    mu = rng.random(n) ** 2
    phi = 2.0 * np.pi * rng.random(n)
    alpha_max = np.exp(rng.uniform(np.log(1e-3), np.log(tables.ALPHA_MAX), n))
    alpha_min = alpha_max * rng.random(n)
    swap = rng.random(n) < 0.5
    ax, ay = np.where(swap, alpha_min, alpha_max), np.where(swap, alpha_max, alpha_min)
    d = GGX(ax, ay)
    s = np.sqrt(1.0 - mu * mu)
    wo = np.stack([s * np.cos(phi), s * np.sin(phi), mu], -1)
    ref = ggx_anisotropic_energy(mu, phi, d.alpha_x, d.alpha_y, order=ANISO_ORDER,
                                 estimate=False).reflection
    table = np.abs(near.conductor_energy(d, wo)[0] - ref)
    iso = np.abs(tables.get("ggx_conductor")(mu, np.sqrt(d.alpha_x * d.alpha_y))[:, 0] - ref)
    rows = []
    for lo, hi in [(1e-3, 0.05), (0.05, 0.5), (0.5, tables.ALPHA_MAX), (1e-3, tables.ALPHA_MAX)]:
        sel = (alpha_max >= lo) & (alpha_max <= hi)
        region = sel & (mu >= 0.01)
        rows.append((lo, hi, sel.sum(), table[sel].max(), np.sqrt(np.mean(table[sel] ** 2)),
                     table[region].max(), iso[sel].max()))
    return rows


#: smallest ior at which the degree-16 Fresnel quadrature is a reference for L
MOMENTS_IOR_LOW = 1.05


def _asm_points(rng, n, ior_low, ior_high):
    """Random ASM roughness, anisotropy (>= 0.05), ior = low + (high - low) u^2 and wo (mu =
    u^2): (r, a, ior, mu, phi, wo)."""
    r, a = rng.uniform(0.0, 1.0, n), rng.uniform(0.05, 1.0, n)
    ior = ior_low + (ior_high - ior_low) * rng.uniform(0.0, 1.0, n) ** 2
    mu, phi = rng.uniform(0.0, 1.0, n) ** 2, rng.uniform(0.0, 2.0 * np.pi, n)
    s = np.sqrt(1.0 - mu * mu)
    return r, a, ior, mu, phi, np.stack([s * np.cos(phi), s * np.sin(phi), mu], -1)


def moments_rows(rng, n=200):
    """The ASM's anisotropic lobe integral L (``materials.asm.diffuse._lobe_integral``: the
    isotropic table plus the moments' correction) against the moments quadrature at order 16
    with the exact Fresnel's Legendre coefficients, ior in [MOMENTS_IOR_LOW, 4]; max, 90th
    and 50th percentile, whole domain and mu >= 0.02."""
    r, a, ior, mu, phi, wo = _asm_points(rng, n, MOMENTS_IOR_LOW, tables.IOR_MAX)
    d = GGX(r * r + a**4, r * r)
    L = _lobe_integral(effective_roughness(r, a), ior, wo, microfacets=d)[0]
    M = ggx_anisotropic_moments(mu, phi, d.alpha_x, d.alpha_y, MOMENT_DEGREE, order=16,
                                estimate=False)[0]
    ref = np.einsum("nk,nk->n", M, fresnel_coefficients(ior, MOMENT_DEGREE))
    e = np.abs(L - ref)
    high = mu >= 0.02
    return [("all", n, e.max(), np.percentile(e, 90), np.percentile(e, 50)),
            ("mu >= 0.02", int(high.sum()), e[high].max(), np.percentile(e[high], 90),
             np.percentile(e[high], 50))]


def moments_near_one_rows(rng, n=24, n_samples=40_000):
    """Below MOMENTS_IOR_LOW: L of ``ASMSpecular``'s table albedo against the MC albedo of
    its own sampler (exact Fresnel), ``n`` random points; the worst |L - MC| and the largest
    standard error."""
    r, a, ior, mu, phi, wo = _asm_points(rng, n, 1.0, MOMENTS_IOR_LOW)
    worst, sigma_max = 0.0, 0.0
    for i in range(n):
        lobe = ASMSpecular(r[i], ior[i], a[i])
        E, sigma = lobe.albedo(wo[i], method="mc", n_samples=n_samples, rng=i,
                               return_error=True)
        L = lobe.albedo(wo[i], method="table")
        worst, sigma_max = max(worst, abs(L[0] - E[0])), max(sigma_max, sigma[0])
    return n, worst, sigma_max


def anisotropic_node_rows(seeds=(0, 7, 11), n=48):
    """``bake --check`` of the anisotropic conductor at ``n`` random nodes per seed: nodes,
    the check's order, the largest difference and the largest stored error estimate."""
    spec = tables.spec("ggx_conductor_anisotropic")
    results = [baking.check(spec, tables.get(spec.name), n_nodes=n, seed=seed)
               for seed in seeds]
    return (n * len(seeds), results[0].order, max(r.max_difference for r in results),
            max(r.max_stored_error for r in results))


def moments_node_rows(n_nodes=48, high=40):
    """Accuracy of the moments' nodes in their Fresnel combinations (what ``bake --check``
    compares, ``catalog.CHECK_ETAS``) and of the raw moments: the shipped order against
    ``high`` at random nodes."""
    spec = tables.spec("ggx_reflection_moments")
    n_total = int(np.prod(spec.shape[:-1]))
    index = np.sort(np.random.default_rng(3).choice(n_total, size=n_nodes, replace=False))
    coords = [c[index] for c in spec.grid()]
    fresh, _ = baking.compute(dataclasses.replace(spec, order=high), coords, 1,
                              progress=False)
    diff = fresh - tables.get(spec.name).values.reshape(n_total, -1)[index]
    return (n_nodes, spec.order, high, np.abs(diff @ spec.checked()).max(), np.abs(diff).max(),
            spec.check_tol)


#: the white furnace of anisotropic lobes: ASM alphas (alpha_x = r^2 + a^4, alpha_y = r^2)
FURNACE_ROUGHNESS = (0.05, 0.2, 0.5, 1.0)
FURNACE_ANISOTROPY = (0.5, 0.8, 1.0)
FURNACE_ROTATIONS = (0.0, 0.3)
FURNACE_COSINES = (1.0, 0.5, 0.1, 0.03, 0.01)
FURNACE_AZIMUTHS = (0.0, 0.3, np.pi / 4, 1.2, np.pi / 2, 2.5)
FURNACE_SAMPLES = 200_000
#: the dielectric of the furnace: index ratio
FURNACE_ETA = 1.5


def _furnace_directions(side=1.0):
    c, p = np.meshgrid(FURNACE_COSINES, FURNACE_AZIMUTHS, indexing="ij")
    c, p = c.ravel(), p.ravel()
    s = np.sqrt(1.0 - c * c)
    return c, p, np.stack([s * np.cos(p), s * np.sin(p), side * c], -1)


def _worst(E, sigma):
    """(E - 1, its standard error) where |E - 1| is largest (channel 0)."""
    k = int(np.argmax(np.abs(E[:, 0] - 1.0)))
    return E[k, 0] - 1.0, sigma[k, 0]


#: the ``anisotropic_energy`` modes compared: the isotropic proxy (sqrt(alpha_x alpha_y)), the
#: default (the shipped grid of slices), and the slice computed for the lobe
MODES = ("isotropic", "table", "exact")


def anisotropic_furnace_rows(n_samples=FURNACE_SAMPLES):
    """White anisotropic ``ConductorMS`` and ``DielectricMS`` (index ratio ``FURNACE_ETA``, both
    sides) at the ASM alphas, turned by 2 pi x ``FURNACE_ROTATIONS``: max |E - 1| over
    ``FURNACE_COSINES`` x ``FURNACE_AZIMUTHS``. *Quadrature*: single scattering by the
    stretched node integrators (order 16 / 12) at the lobe's own azimuth, plus the
    compensation's table albedo (exact for its E); the dielectric built with each of
    ``MODES`` of ``anisotropic_energy``; *MC*: the whole lobe's albedo (the default mode),
    the worst E - 1 and its standard error, ``n_samples`` per direction."""
    rows = []
    for r in FURNACE_ROUGHNESS:
        for a in FURNACE_ANISOTROPY:
            ax, ay = (float(x) for x in alphas(np.asarray(r), np.asarray(a)))
            metal = lobes.ConductorMS(ax, ay)
            glass = {}
            for mode in MODES:
                with config.options(anisotropic_energy=mode):
                    glass[mode] = lobes.DielectricMS(FURNACE_ETA, ax, ay)
            metal_q, glass_q = 0.0, {(mode, side): 0.0 for mode in MODES for side in (1, -1)}
            for rotation in FURNACE_ROTATIONS:
                phi0 = 2.0 * np.pi * rotation
                c, p, wo = _furnace_directions()
                E = ggx_anisotropic_energy(c, p - phi0, ax, ay, order=16,
                                           estimate=False).reflection
                ms = Rotated(metal.components[1], phi0).albedo(wo, "table")[:, 0]
                metal_q = max(metal_q, np.abs(E + ms - 1.0).max())
                for side, eta in ((1, FURNACE_ETA), (-1, 1.0 / FURNACE_ETA)):
                    c, p, wo = _furnace_directions(side)
                    e = ggx_anisotropic_dielectric_energy(c, p - phi0, ax, ay, eta, order=12,
                                                          estimate=False)
                    for mode, lobe in glass.items():
                        ms = Rotated(lobe.components[1], phi0).albedo(wo, "table")[:, 0]
                        error = np.abs(e.reflection + e.transmission + ms - 1.0).max()
                        glass_q[mode, side] = max(glass_q[mode, side], error)
            c, p, wo = _furnace_directions()
            wo = np.concatenate([wo, wo * np.array([1.0, 1.0, -1.0])])[::3]
            metal_mc = _worst(*metal.albedo(wo[: len(wo) // 2], "mc", n_samples=n_samples,
                                            rng=5, return_error=True))
            glass_mc = _worst(*glass["table"].albedo(wo, "mc", n_samples=n_samples, rng=5,
                                                     return_error=True))
            rows.append((r, a, metal_q, *metal_mc,
                         *[glass_q[mode, side] for mode in MODES for side in (1, -1)],
                         *glass_mc))
    return rows


#: white anisotropic materials of the material furnace: (label, class, parameters)
MATERIAL_FURNACE = [
    ("ASM glass, r 0.35, a 0.6", AdobeStandardMaterial,
     dict(base_color=1.0, translucency=1.0, ior=1.45, roughness=0.35, anisotropy_level=0.6,
          anisotropy_angle=0.3)),
    ("ASM metal, r 0.2, a 0.8", AdobeStandardMaterial,
     dict(metallic=1.0, base_color=1.0, specular_edge_color=1.0, roughness=0.2,
          anisotropy_level=0.8, anisotropy_angle=0.3)),
    ("ASM dielectric, r 0.2, a 0.8, under a coat r 0.2, a 0.8", AdobeStandardMaterial,
     dict(base_color=1.0, roughness=0.2, anisotropy_level=0.8, anisotropy_angle=0.3,
          coat_opacity=1.0, coat_roughness=0.2, coat_anisotropy_level=0.8)),
    ("OpenPBR metal, r 0.3, a 0.8", OpenPBRSurface,
     dict(base_metalness=1.0, base_color=1.0, specular_color=1.0, specular_roughness=0.3,
          specular_roughness_anisotropy=0.8)),
    ("OpenPBR glossy-diffuse, r 0.3, a 0.8, under a coat r 0.2, a 0.6", OpenPBRSurface,
     dict(base_color=1.0, specular_roughness=0.3, specular_roughness_anisotropy=0.8,
          coat_weight=1.0, coat_roughness=0.2, coat_roughness_anisotropy=0.6)),
    ("OpenPBR glass, r 0.3, a 0.6, under a coat r 0.2, a 0.6", OpenPBRSurface,
     dict(base_color=1.0, transmission_weight=1.0, specular_roughness=0.3,
          specular_roughness_anisotropy=0.6, coat_weight=1.0, coat_roughness=0.2,
          coat_roughness_anisotropy=0.6)),
]
MATERIAL_SAMPLES = 100_000


def material_furnace_rows(n_samples=MATERIAL_SAMPLES):
    """Monte-Carlo albedo of the white anisotropic ``MATERIAL_FURNACE`` materials from above,
    built with each of ``MODES`` of ``anisotropic_energy``: the worst E - 1 and its
    standard error over every third direction of ``FURNACE_COSINES`` x
    ``FURNACE_AZIMUTHS``, and the build time."""
    wo = _furnace_directions()[2][::3]
    rows = []
    for label, cls, params in MATERIAL_FURNACE:
        row = [label]
        for mode in MODES:
            start = time.perf_counter()
            with config.options(anisotropic_energy=mode):
                material = cls(**params)
            built = time.perf_counter() - start
            row += [*_worst(*material.albedo(wo, "mc", n_samples=n_samples, rng=7,
                                             return_error=True)), built]
        rows.append(tuple(row))
    return rows


#: (alpha_max, ratio, eta) of the slices measured at random directions: the ASM grid's corners
#: and middle, and other indices
SLICE_CASES = [(0.4496, 0.04 / 0.4496, 1.5), (2.0, 0.5, 1.5), (1.0025, 0.0025 / 1.0025, 1.5),
               (0.0641, 0.0016 / 0.0641, 1.5), (0.5, 0.3, 1.2), (0.05, 0.3, 2.5),
               (0.3, 0.1, 3.0), (1.5, 0.05, 1.05)]
SLICE_POINTS = 300


def slice_rows(rng, n=SLICE_POINTS):
    """For each of ``SLICE_CASES``: build time, and the slice against the integrator at order
    12 at ``n`` random directions per side (mu log-uniform in [0.01, 1], phi uniform): max
    error of E_R + E_T and of E_R."""
    rows = []
    for alpha, ratio, eta in SLICE_CASES:
        dielectric_slices.dielectric_slice.cache_clear()
        start = time.perf_counter()
        piece = dielectric_slices.dielectric_slice(alpha, ratio, eta)
        seconds = time.perf_counter() - start
        row = [alpha, ratio, eta, seconds]
        for on_light, seen in ((True, eta), (False, 1.0 / eta)):
            mu = np.exp(rng.uniform(np.log(0.01), 0.0, n))
            phi = rng.uniform(0.0, np.pi / 2, n)
            ref = ggx_anisotropic_dielectric_energy(mu, phi, alpha, alpha * ratio, seen,
                                                    order=12, estimate=False)
            E = piece(on_light, mu, np.cos(phi))
            row += [np.abs(E.sum(-1) - ref.reflection - ref.transmission).max(),
                    np.abs(E[:, 0] - ref.reflection).max()]
        rows.append(tuple(row))
    return rows


def slice_node_rows(rng, n=200):
    """The slices' node integrator (order ``SLICE_ORDER``) against order 20 at ``n`` random
    nodes: mu log-uniform in [0.005, 1], alpha log-uniform in [0.003, 1.5], ratio = u^3,
    eta log-uniform in [1/3, 3]; max and median |error| of E_R + E_T, and the time per node."""
    mu = np.exp(rng.uniform(np.log(0.005), 0.0, n))
    phi = rng.uniform(0.0, np.pi / 2, n)
    alpha = np.exp(rng.uniform(np.log(0.003), np.log(1.5), n))
    ratio, eta = rng.uniform(0.0, 1.0, n) ** 3, np.exp(rng.uniform(-np.log(3), np.log(3), n))
    start = time.perf_counter()
    e = ggx_anisotropic_dielectric_energy(mu, phi, alpha, alpha * ratio, eta,
                                          dielectric_slices.SLICE_ORDER, estimate=False)
    seconds = (time.perf_counter() - start) / n
    ref = ggx_anisotropic_dielectric_energy(mu, phi, alpha, alpha * ratio, eta, 20,
                                            estimate=False)
    error = np.abs(e.reflection + e.transmission - ref.reflection - ref.transmission)
    return n, error.max(), np.median(error), seconds


#: the scaling bake: ggx_conductor at this many nodes per axis
SCALE_NODES = 32


def bake_scale_rows():
    """Bake time of ``ggx_conductor`` at ``SCALE_NODES`` x ``SCALE_NODES`` nodes in this
    process, on a pool over all local cores, and on a 2-worker Dask ``LocalCluster`` (its
    start-up excluded), with the SHA-256 of each result's values and errors."""
    base = tables.spec("ggx_conductor")
    spec = dataclasses.replace(base, axes=tuple(dataclasses.replace(a, n=SCALE_NODES)
                                                for a in base.axes))
    rows = []
    for label, how in [("1 worker, in process", dict(workers=1)),
                       (f"process pool, all {os.cpu_count()} cores", dict()),
                       ("Dask LocalCluster, 2 workers", dict(dask_workers=2))]:
        with open_executor(**how) as ex:
            start = time.perf_counter()
            table = baking.bake(spec, progress=False, executor=ex)
            seconds = time.perf_counter() - start
        digest = hashlib.sha256(table.values.tobytes() + table.errors.tobytes()).hexdigest()
        rows.append((label, seconds, digest[:16]))
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
           "bake time (workers) | max node error estimate |", "|---|---|---|---|---|---|"]
    total = 0
    for name, spec in tables.SPECS.items():
        t = tables.get(name)
        size = tables.path(name).stat().st_size
        total += size
        axes = ", ".join(f"{a.name} {a.n} {a.parameterisation} {a.interpolation}"
                         for a in spec.axes)
        out.append(f"| `{name}` | {axes} | {', '.join(spec.outputs)} | {size / 1024:.0f} KiB | "
                   f"{t.meta['bake_seconds']:.1f} s ({t.meta.get('workers', 2)}) | "
                   f"{t.errors.max():.1e} |")
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
    aniso = tables.spec("ggx_conductor_anisotropic")
    out += ["", "## Anisotropic conductor", "",
            "E(wo) of an anisotropic GGX conductor (F = 1) is tabulated over (s, |cos phi|, "
            "alpha, ratio): alpha = max(alpha_x, alpha_y), ratio = min / max, phi the azimuth "
            "of wo from the axis of alpha (the symmetries phi -> -phi, pi - phi leave "
            "|cos phi|), and s = mu (1 + a) / (mu + a) with a = the roughness projected on "
            "wo's azimuth (at small a the energy near grazing is a function of mu / a: the "
            f"table needs {aniso.axes[0].n} nodes in s where the isotropic one has 128 in mu). "
            "Nodes: the stretched-space quadrature ``tables.anisotropic_energy`` at order "
            f"{aniso.order}. Below: {ANISO_POINTS} random wo (mu = u^2, phi uniform), "
            "alpha_max log-uniform in [1e-3, 2], ratio uniform, either axis the rough one, "
            f"against that quadrature at order {ANISO_ORDER}; last column, the isotropic "
            "table at sqrt(alpha_x alpha_y), which anisotropic lobes read before.", "",
            "| alpha_max in | points | max error | RMS error | max error, mu >= 0.01 | "
            "isotropic table at sqrt(alpha_x alpha_y): max error |", "|---|---|---|---|---|---|"]
    for lo, hi, count, emax, erms, eregion, eiso in anisotropy_rows(rng):
        out.append(f"| [{lo:g}, {hi:g}] | {count} | {emax:.1e} | {erms:.1e} | {eregion:.1e} | "
                   f"{eiso:.1e} |")
    n_nodes, high, worst, estimate = anisotropic_node_rows()
    out += ["", f"Node accuracy: at {n_nodes} random nodes re-integrated at order {high} "
            f"(`bake --check`), the shipped order {aniso.order} is within {worst:.1e} (the "
            f"stored estimates |Q(n) - Q(2n/3)| reach {estimate:.1e}; `bake --check` accepts "
            f"{aniso.check_tol:g})."]
    low = MOMENTS_IOR_LOW
    out += ["", "## Anisotropic dielectric reflection: the Fresnel moments", "",
            "The ASM's lobe integral L of an anisotropic specular (`ggx_reflection_moments`, "
            "read as a correction to the isotropic `asm_diffuse_L`) at 200 random points: ASM "
            f"roughness uniform, anisotropy in [0.05, 1], ior = {low:g} + "
            f"{tables.IOR_MAX - low:g} u^2, mu = u^2, phi uniform; reference: the moments "
            "quadrature at order 16 with the exact Fresnel's Legendre coefficients.", "",
            "| points | count | max error | 90th percentile | median |", "|---|---|---|---|---|"]
    for label, count, emax, e90, e50 in moments_rows(rng):
        out.append(f"| {label} | {count} | {emax:.1e} | {e90:.1e} | {e50:.1e} |")
    count, worst, sigma = moments_near_one_rows(rng)
    out += ["", f"Below ior {low:g} the Fresnel is a step of width ~sqrt(ior^2 - 1) in "
            "wo.m that 17 Legendre coefficients do not follow, and the large alternating "
            "coefficients multiply the moments' interpolation error: against the Monte-Carlo "
            f"albedo of `ASMSpecular`'s own sampler at {count} random points with ior in "
            f"(1, {low:g}], the worst |L - MC| is **{worst:.1e}** (standard error <= "
            f"{sigma:.1e}). This is a known limitation of the anisotropic ASM dielectric "
            "near ior 1."]
    n_nodes, order, high, e_fresnel, e_raw, tol = moments_node_rows()
    out += ["", f"Node accuracy: at {n_nodes} random nodes re-integrated at order {high}, the "
            f"shipped order {order} is within {e_fresnel:.1e} in every Fresnel combination "
            "sum_k a_k M_k that `bake --check` compares (relative indices "
            f"{', '.join(f'{x:g}' for x in CHECK_ETAS)}; accepted: {tol:g}), while the raw "
            f"high moments differ by up to {e_raw:.1e}: they converge slowly with the order, "
            "but their differences cancel in every Fresnel combination."]
    cosines = ", ".join(f"{x:g}" for x in FURNACE_COSINES)
    azimuths = ", ".join(f"{x:.2g}" for x in FURNACE_AZIMUTHS)
    n_nodes, e_max, e_median, per_node = slice_node_rows(rng)
    example = dielectric_slices.dielectric_slice(*SLICE_CASES[0])
    iso = [tables.spec(n) for n in ("ggx_dielectric_outside", "ggx_dielectric_inside")]
    iso_nodes = int(np.prod([a.n for a in iso[0].axes]))
    cos_phi, ratio = aniso.axes[1].n, aniso.axes[3].n
    out += ["", "## Anisotropic dielectric: slices", "",
            "The energy of a rough dielectric depends on five coordinates (mu, phi, alpha, "
            "ratio, eta) per side. The isotropic tables already hold "
            f"{' x '.join(str(a.n) for a in iso[0].axes)} = {iso_nodes} nodes per side for "
            "~1e-3; with the anisotropic conductor's "
            f"{cos_phi} x {ratio} nodes in (|cos phi|, ratio) added that is "
            f"{2 * iso_nodes * cos_phi * ratio:.1e} nodes, "
            f"{2 * iso_nodes * cos_phi * ratio * 16 / 2**20:.0f} MiB of values and errors "
            "and, at the node "
            f"integrator's {per_node * 1e3:.0f} ms per node, "
            f"{2 * iso_nodes * cos_phi * ratio * per_node / 86400 / (os.cpu_count() or 1):.1f} "
            f"days on this machine's {os.cpu_count()} cores. A lobe holds one (alpha_x, "
            "alpha_y, eta), so under `config.options(anisotropic_energy=\"exact\")` it "
            "computes only the slice through it (`tables.dielectric_slices`): E_R and E_T "
            "over wo's cosine and azimuth, exact in alpha, ratio and eta, by "
            "`tables.anisotropic_energy.ggx_anisotropic_dielectric_energy` (the stretched "
            "quadrature with the refracted direction) at order "
            f"{dielectric_slices.SLICE_ORDER}; at index ratio {SLICE_CASES[0][2]:g}, "
            f"{example.n_nodes} nodes in {len(example.parts)} tables (mu x |cos phi|): "
            + "; ".join(example.layout())
            + " (the dense side split at the critical cosine, at 1 / eta and along the two "
            "kinks of a nearly one-dimensional surface, `tables.dielectric_slices`): a slice "
            "costs seconds, once per distinct (alpha_x, alpha_y, eta) in a process. The "
            "default (`\"table\"`) interpolates the slice from the shipped grid of slices "
            "(`tables.dielectric_grid`, [anisotropic_grid_measured.md]"
            "(anisotropic_grid_measured.md)).",
            "", f"Node accuracy: at {n_nodes} random nodes (mu >= 0.005, alpha in [0.003, "
            "1.5], ratio = u^3, eta in [1/3, 3]) the slices' order is within "
            f"{e_max:.1e} of order 20 in E_R + E_T (median {e_median:.1e}; every node "
            f"carries {dielectric_slices.SLICE_NODE_ERROR:g} as its error estimate).", "",
            f"Interpolation: {SLICE_POINTS} random directions per side (mu log-uniform in "
            "[0.01, 1], phi uniform) against the integrator at order 12.", "",
            "| alpha_max | ratio | eta | build time | light side: E_R + E_T | light side: "
            "E_R | dense side: E_R + E_T | dense side: E_R |", "|---|---|---|---|---|---|---|---|"]
    for alpha, ratio_, eta, seconds, *errors in slice_rows(rng):
        out.append(f"| {alpha:.4g} | {ratio_:.3g} | {eta:g} | {seconds:.1f} s | "
                   + " | ".join(f"{e:.1e}" for e in errors) + " |")
    out += ["", "The dense side is the harder one: total internal reflection sets in at the "
            "critical cosine, and a nearly one-dimensional surface has two further kinks, "
            "where the facet facing wo and where the vertical facets leave total internal "
            "reflection; the tables are split along them. Only E_R + E_T enters the "
            "Kulla–Conty terms; E_R alone (a coat's albedo) is the less accurate, at grazing "
            "angles of a smooth axis most.",
            "", "## White furnace of anisotropic lobes", "",
            f"White `ConductorMS` (F = 1) and `DielectricMS` (index ratio {FURNACE_ETA:g}, "
            "from the light and the dense side) at the ASM alphas alpha_x = r^2 + a^4, "
            f"alpha_y = r^2, turned by 2 pi x {{{', '.join(f'{x:g}' for x in FURNACE_ROTATIONS)}}}"
            f", over cos theta_o in {{{cosines}}} and azimuths {{{azimuths}}}. "
            "*Quadrature*: single scattering by the stretched node integrators (order 16 for "
            "the conductor, 12 for the dielectric) at the lobe's own azimuth plus the "
            "compensation's albedo (exact for the E it reads); the dielectric built with "
            "`anisotropic_energy=\"isotropic\"` (the isotropic tables at "
            "sqrt(alpha_x alpha_y)), `\"table\"` (the default: the grid of slices) and "
            "`\"exact\"` (its own slice). *MC*: the whole default lobe's "
            f"albedo with {FURNACE_SAMPLES} samples per direction (the dielectric a third of "
            "the directions from either side): the worst E - 1 ± one standard error.", "",
            "| roughness | anisotropy | conductor: max abs(E - 1), quadrature | conductor: "
            "worst E - 1, MC | dielectric, isotropic: light side | isotropic: dense side | "
            "dielectric, default: light side | default: dense side | dielectric, exact: "
            "light side | exact: dense side | default: worst E - 1, MC |",
            "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r, a, quad, e_mc, s_mc, *sides, e_d, s_d in anisotropic_furnace_rows():
        out.append(f"| {r:g} | {a:g} | {quad:.1e} | {e_mc:+.4f} ± {s_mc:.4f} | "
                   + " | ".join(f"{x:.1e}" for x in sides) + f" | {e_d:+.4f} ± {s_d:.4f} |")
    out += ["", "### Materials", "",
            "White anisotropic ASM and OpenPBR materials (coats white, base colours 1) built "
            "with `anisotropic_energy=\"isotropic\"`, `\"table\"` (the default) and "
            f"`\"exact\"`: Monte-Carlo albedo from above with {MATERIAL_SAMPLES} samples per "
            "direction over every third of the same directions, "
            "the worst E - 1 ± one standard error, and the time to build the material (the "
            "exact one computes its slices: one per distinct anisotropic interface).", "",
            "| material | isotropic: worst E - 1 | build | default: worst E - 1 | build | "
            "exact: worst E - 1 | build |", "|---|---|---|---|---|---|---|"]
    for label, *cells in material_furnace_rows():
        out.append(f"| {label} | " + " | ".join(
            f"{cells[k]:+.4f} ± {cells[k + 1]:.4f} | {cells[k + 2]:.2f} s"
            for k in range(0, len(cells), 3)) + " |")
    scale = bake_scale_rows()
    out += ["", "## Baking at scale", "",
            f"`ggx_conductor` re-declared at {SCALE_NODES} x {SCALE_NODES} nodes, baked by "
            "`tables.bake.bake` on each executor of `tables.executors.open_executor` (the Dask "
            "cluster's start-up is not timed). The digest is SHA-256 of the values and errors: "
            "the same bytes on every executor. This machine's cores are measured, not assumed: "
            "the pool's time against the single process's shows what they give.", "",
            "| executor | bake time | digest |", "|---|---|---|"]
    for label, seconds, digest in scale:
        out.append(f"| {label} | {seconds:.2f} s | `{digest}` |")
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
