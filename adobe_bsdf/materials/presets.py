"""Named parameter sets from the source papers, as keyword arguments of the library's lobes.

``hazy``         ``ab.hazy.HazyGloss(**hazy[name])``: the materials of seed 002 Table 3
                 (Figs. 1 and 11) and of the captions that fix every parameter (Fig. 9).
``hazy_sweeps``  captions that vary one parameter with the others fixed:
                 ``(fixed keyword arguments, swept parameter, (first, last) value)``.
``dispersion``   seed 000 Table 2: ``{"ior": n_d, "abbe": V_d}`` of real materials
                 (``ab.dispersion.abbe_to_dispersion(abbe)`` is their "Dispersion").

Table 3 names its reflectivity column r_p, the peak (core) reflectivity r_c of §2.2.

References
----------
[000] Adobe Standard Material (``shared/seeds/000_dc1170558b4eb881.txt``): Table 2.
[002] Barla, Pacanowski, Vangorp 2018 (``shared/seeds/002_01cff37cda6a7899.txt``): Table 3,
      captions of Figs. 8, 9, 10.
"""

from __future__ import annotations

__all__ = ["hazy", "hazy_sweeps", "dispersion"]

dispersion = {
    # seed 000 Table 2: IOR n_d and Abbe number V_d
    "N-FK58": {"ior": 1.456, "abbe": 90.90},
    "N-BK7": {"ior": 1.517, "abbe": 64.17},
    "N-BAK4": {"ior": 1.569, "abbe": 55.98},
    "water": {"ior": 1.333, "abbe": 55.78},
    "diamond": {"ior": 2.417, "abbe": 55.30},
    "F2": {"ior": 1.620, "abbe": 36.37},
    "N-SF66": {"ior": 1.923, "abbe": 20.88},
}

hazy = {
    # Table 3 (Figs. 1 and 11): r_p, g, alpha_n, beta_h, lambda_h^{x,y}
    "probe_a": {"core_reflectivity": 0.02, "edge_tint": 0.0, "alpha_x": 0.01,
                "haziness": 0.1, "haze_extent": 5.0},
    "probe_b": {"core_reflectivity": 0.5, "edge_tint": 1.0, "alpha_x": 0.01,
                "haziness": 0.99, "haze_extent": 5.0},
    "fertility": {"core_reflectivity": (0.5, 0.28, 0.1), "edge_tint": (0.8, 0.06, 0.03),
                  "alpha_x": 0.03, "haziness": 0.99, "haze_extent": 5.0},
    "vase": {"core_reflectivity": 0.05, "edge_tint": 0.0, "alpha_x": 0.01,
             "haziness": 0.15, "haze_extent": 7.0},
    "teapot": {"core_reflectivity": (0.5, 0.12, 0.12), "edge_tint": (0.0, 0.85, 1.0),
               "alpha_x": 0.01, "haziness": 0.99, "haze_extent": 10.0,
               "haze_extent_y": 1.0},
    # Fig. 9 (Speedshape, over a purple Lambertian base that is not part of the lobe)
    "speedshape": {"core_reflectivity": 0.04, "alpha_x": 0.03, "haziness": 0.1,
                   "haze_extent": 5.0},
}

hazy_sweeps = {
    # Fig. 8, bottom row: beta_h uniformly in [0, 0.95]; alpha_w = 0.088 <=> lambda_h = 6.4
    "fig8": ({"core_reflectivity": 0.5, "alpha_x": 0.012, "haze_extent": 6.4},
             "haziness", (0.0, 0.95)),
    # Fig. 10: beta_h in [0, 0.99]
    "fig10": ({"core_reflectivity": 0.5, "edge_tint": 0.0, "alpha_x": 0.026,
               "haze_extent": 5.0}, "haziness", (0.0, 0.99)),
}
