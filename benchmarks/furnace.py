"""White furnace of the table-based models on the acceptance grid (docs/energy_models.md):
max |albedo - 1| by direction-space quadrature of ``eval``, one direction per call.

    python -m benchmarks.furnace
"""

import itertools
import time

import numpy as np

from adobe_bsdf.lobes import ConductorMS, DielectricMS
from adobe_bsdf.materials.asm import asm_dielectric_base

COSINES = (1.0, 0.5, 0.1, 0.02)


def direction(c, phi=0.4):
    s = np.sqrt(1 - c * c)
    return np.array([s * np.cos(phi), s * np.sin(phi), c])


def worst(lobe, directions):
    return float(max(abs(lobe.albedo(w, tol=1e-6)[0] - 1.0) for w in directions))


def main():
    start = time.perf_counter()
    up = [direction(c) for c in COSINES]
    both = [s * w for w in up for s in (1, -1)]
    asm = {(r, n): worst(asm_dielectric_base(1.0, r, n), up)
           for r, n in itertools.product([0.05, 0.3, 0.7, 1.0], [1.1, 1.5, 2.5])}
    metal = {r: worst(ConductorMS(r * r), up) for r in [0.05, 0.1, 0.3, 0.5, 0.7, 1.0]}
    glass = {(r, n): worst(DielectricMS(n, r * r), both)
             for r, n in itertools.product([0.05, 0.1, 0.3, 0.7, 1.0], [1.5, 1 / 1.5, 1.1, 2.5])}
    for label, errors in (("ASM diffuse + specular, roughness x ior", asm),
                          ("ConductorMS (F = 1), roughness", metal),
                          ("DielectricMS R + T both sides, roughness x eta", glass)):
        key = max(errors, key=errors.get)
        print(f"{label}: max |E - 1| = {errors[key]:.1e} at {key} over cos {COSINES}")
    print(f"({time.perf_counter() - start:.0f} s)")


if __name__ == "__main__":
    main()
