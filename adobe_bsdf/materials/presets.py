"""Named parameter sets from the source papers (and example materials), each a dict of
keyword arguments of the constructor it is for, so that it builds its material or lobe
directly.

``metals``       ``ab.materials.AdobeStandardMaterial(**metals[name])``: [Kutz2021, Table 1] as
                 ``{"metallic": 1.0, "base_color": F0, "specular_edge_color": F82 tint}`` in
                 linear Rec. 709 (the ASM's "Base Color" and "Specular Edge Color"); the two
                 colours are also the arguments of ``ab.fresnel.F82Tint(f0, tint)`` and of
                 ``ab.materials.asm.asm_metal(base_color, specular_edge_color, ...)``.
``hazy``         ``ab.hazy.HazyGloss(**hazy[name])``: the materials of [Barla2018, Table 3]
                 (Figs. 1 and 11) and of the captions that fix every parameter (Fig. 9).
``hazy_sweeps``  captions that vary one parameter with the others fixed:
                 ``(fixed keyword arguments, swept parameter, (first, last) value)``; the fixed
                 ones with a value of the swept one build ``ab.hazy.HazyGloss``.
``media``        ``ab.media.asm_medium(**media[name])``: [Kutz2021, Table 3], measured
                 materials [Jensen2001] (scattering distance, colour, Rayleigh); the same
                 names are ``AdobeStandardMaterial`` keywords.
``dispersion``   [Kutz2021, Table 2]: ``{"ior": n_d, "abbe": V_d}`` of real materials, for
                 ``AdobeStandardMaterial(ior=d["ior"],
                 dispersion=ab.dispersion.abbe_to_dispersion(d["abbe"]))``: the Abbe number is
                 not an ASM keyword; ``abbe_to_dispersion`` gives its "Dispersion".
``openpbr``      ``ab.materials.OpenPBRSurface(**openpbr[name])``: example materials that
                 together use every lobe and option of the surface (the sampling tests and
                 ``benchmarks/openpbr_report.py`` run each), among them six measured with
                 another implementation ("default", "white metal", "copper", "coated blue",
                 "fuzz grey", "EON white").

[Barla2018, Table 3] names its reflectivity column r_p: the peak (core) reflectivity r_c of
[Barla2018, §2.2].

References
----------
[Kutz2021, Tables 1, 2, 3] metals, dispersive materials, subsurface media.
[Barla2018, Table 3] hazy materials, and the captions of its Figs. 8, 9, 10.
[Jensen2001] the measured media of [Kutz2021, Table 3].
"""

from __future__ import annotations

__all__ = ["hazy", "hazy_sweeps", "metals", "dispersion", "media", "openpbr"]


def _medium(distance, color, rayleigh):
    return {"scattering_distance": distance, "scattering_color": color,
            "scatter_rayleigh": rayleigh}


media = {
    # [Kutz2021, Table 3]: "Scattering Distance", "Scattering Color", "Rayleigh Scattering"
    "Apple": _medium(0.04374, (1.0, 0.9168, 0.7063), 0.0),
    "Chicken1": _medium(0.4118, (0.4947, 0.2785, 0.2320), 0.7311),
    "Chicken2": _medium(0.3758, (0.5036, 0.2849, 0.2011), 0.3979),
    "Cream": _medium(0.01762, (0.9881, 0.9492, 0.8478), 0.0),
    "Ketchup": _medium(0.7588, (0.2909, 0.01392, 0.004071), 0.0),
    "Marble": _medium(0.03920, (0.9312, 0.9130, 0.8941), 0.2430),
    "Potato": _medium(0.1494, (0.8724, 0.7717, 0.3631), 0.0),
    "Skimmilk": _medium(0.08511, (0.9022, 0.9011, 0.8203), 0.7501),
    "Skin1": _medium(0.1117, (0.6250, 0.3836, 0.2394), 0.2397),
    "Skin2": _medium(0.06750, (0.7790, 0.6224, 0.5291), 0.3844),
    "Spectralon": _medium(0.006030, (1.0, 1.0, 1.0), 0.2535),
    "Wholemilk": _medium(0.03228, (0.9532, 0.9389, 0.8694), 0.3016),
}


def _metal(f0, tint):
    return {"metallic": 1.0, "base_color": f0, "specular_edge_color": tint}


metals = {
    # [Kutz2021, Table 1]: F0 ("Base Color") and F82 tint ("Specular Edge Color"), linear Rec. 709
    "Ag": _metal((0.9868, 0.9830, 0.9667), (0.9929, 0.9961, 1.0000)),
    "Al": _metal((0.9157, 0.9226, 0.9236), (0.9090, 0.9365, 0.9596)),
    "Au": _metal((1.0000, 0.7099, 0.3148), (0.9408, 0.9636, 0.9099)),
    "Cr": _metal((0.5496, 0.5561, 0.5531), (0.7372, 0.7511, 0.8170)),
    "Cu": _metal((1.0000, 0.6504, 0.5274), (0.9755, 0.9349, 0.9301)),
    "Fe": _metal((0.8951, 0.8755, 0.8154), (0.8551, 0.8800, 0.8966)),
    "Hg": _metal((0.7815, 0.7795, 0.7783), (0.8103, 0.8532, 0.9046)),
    "Mg": _metal((0.8918, 0.8821, 0.8948), (0.8949, 0.9147, 0.9504)),
    "Ni": _metal((0.7014, 0.6382, 0.5593), (0.8134, 0.8352, 0.8725)),
    "Pd": _metal((0.7363, 0.7023, 0.6602), (0.8095, 0.8369, 0.8739)),
    "Pt": _metal((0.9602, 0.9317, 0.8260), (0.9501, 0.9461, 0.9352)),
    "Ti": _metal((0.4432, 0.3993, 0.3599), (0.8627, 0.9066, 0.9481)),
    "Zn": _metal((0.8759, 0.8685, 0.8542), (0.8769, 0.9037, 0.9341)),
}

dispersion = {
    # [Kutz2021, Table 2]: IOR n_d and Abbe number V_d
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


_HAZE = {"specular_haze": 0.5, "specular_haze_spread": 0.6}
openpbr = {
    "default": {},
    "white metal": {"base_metalness": 1.0, "base_color": 1.0, "specular_color": 1.0,
                    "specular_roughness": 0.2},
    "copper": {"base_metalness": 1.0, "base_color": (0.955, 0.638, 0.538),
               "specular_color": 1.0, "specular_roughness": 0.3},
    "coated blue": {"base_color": (0.1, 0.2, 0.7), "specular_roughness": 0.3,
                    "coat_weight": 1.0, "coat_roughness": 0.05, "coat_ior": 1.5},
    "fuzz grey": {"base_color": 0.5, "specular_roughness": 0.5, "fuzz_weight": 1.0,
                  "fuzz_color": 0.8, "fuzz_roughness": 0.7},
    "EON white": {"base_color": 1.0, "specular_color": 1.0, "base_diffuse_roughness": 1.0,
                  "specular_roughness": 0.4},
    "rough diffuse, tinted specular": {"base_color": (0.8, 0.3, 0.2),
                                       "base_diffuse_roughness": 0.8, "specular_roughness": 0.6,
                                       "specular_color": (1.0, 0.8, 0.6)},
    "copper anisotropic": {"base_metalness": 1.0, "base_color": (0.955, 0.638, 0.538),
                           "specular_color": (1.0, 0.9, 0.8), "specular_roughness": 0.35,
                           "specular_roughness_anisotropy": 0.8,
                           "geometry_tangent": (0.6, 0.8, 0.0)},
    "tinted anisotropic coat": {"base_color": (0.1, 0.2, 0.7), "coat_weight": 1.0,
                                "coat_roughness": 0.3, "coat_color": (0.9, 0.8, 0.6),
                                "coat_roughness_anisotropy": 0.5,
                                "geometry_coat_tangent": (0.0, 1.0, 0.0)},
    "glass": {"transmission_weight": 1.0, "specular_roughness": 0.2},
    "coated glass, denser coat": {"transmission_weight": 1.0, "specular_roughness": 0.4,
                                  "specular_ior": 1.4, "coat_weight": 1.0, "coat_ior": 1.8,
                                  "coat_roughness": 0.2},
    "subsurface half": {"subsurface_weight": 0.5, "subsurface_color": (0.9, 0.6, 0.4),
                        "base_diffuse_roughness": 0.3},
    "half metal, coat, fuzz": {
        "base_metalness": 0.5, "base_color": (0.6, 0.5, 0.4), "specular_roughness": 0.3,
        "coat_weight": 0.7, "coat_roughness": 0.1, "fuzz_weight": 0.4, "fuzz_roughness": 0.3,
        "base_diffuse_roughness": 0.5},
    "dev_1.2 haze, glass": {"spec": "dev_1.2", "transmission_weight": 1.0,
                            "specular_roughness": 0.1, **_HAZE},
    "dev_1.2 haze, retroreflective half metal, tinted coat": {
        "spec": "dev_1.2", "base_metalness": 0.5, "base_color": (0.9, 0.7, 0.3),
        "specular_roughness": 0.15, "specular_retroreflectivity": 0.4,
        "coat_weight": 1.0, "coat_roughness": 0.2, "coat_color": (0.8, 0.9, 0.6), **_HAZE},
    "everything": {"base_metalness": 0.3, "transmission_weight": 0.4, "subsurface_weight": 0.3,
                   "base_diffuse_roughness": 0.6, "specular_roughness": 0.35,
                   "specular_roughness_anisotropy": 0.4, "coat_weight": 0.5,
                   "coat_color": (0.9, 0.9, 0.7), "fuzz_weight": 0.5, "fuzz_roughness": 0.5,
                   "specular_weight": 0.7},
    "tinted dispersive glass": {"transmission_weight": 1.0, "specular_roughness": 0.15,
                                "transmission_color": (0.7, 0.9, 0.8),
                                "transmission_dispersion_scale": 0.5,
                                "transmission_dispersion_abbe_number": 30.0},
    "thin-walled leaf": {"geometry_thin_walled": True, "subsurface_weight": 1.0,
                         "subsurface_color": (0.35, 0.6, 0.15),
                         "subsurface_scatter_anisotropy": 0.3, "specular_roughness": 0.45,
                         "base_diffuse_roughness": 0.5, "geometry_opacity": 0.9},
    "thin-walled tinted glass, coat": {"geometry_thin_walled": True, "transmission_weight": 1.0,
                                       "transmission_color": (0.9, 0.8, 0.6),
                                       "specular_roughness": 0.2, "coat_weight": 0.5},
    "iridescent metal": {"base_metalness": 1.0, "base_color": (0.9, 0.9, 0.9),
                         "specular_roughness": 0.25, "thin_film_weight": 1.0,
                         "thin_film_thickness": 0.4, "thin_film_ior": 1.45},
}
