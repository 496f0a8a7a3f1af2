"""Hazy gloss as lobes: the composite BRDF of two microfacet lobes sharing one Fresnel term
[Barla2018, eq. 1], and its two-component BTDF [Barla2018, §4.2], driven by the haze mapping
(``adobe_bsdf.haze``).

Both lobes take ``model`` ("ggx", "beckmann") and ``compound_masking`` [Barla2018, §3].
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf._channels import pick
from adobe_bsdf.composition import Sum
from adobe_bsdf.fresnel import ExactConductor, Fresnel
from adobe_bsdf.haze import HazeMapping, haze_mapping
from adobe_bsdf.lobes.dielectric import Dielectric
from adobe_bsdf.lobes.reflection import Conductor
from adobe_bsdf.microfacet import Mixture, distribution

__all__ = ["HazyGloss", "HazyDielectric"]


class _MappedFresnel(Fresnel):
    """Exact conductor Fresnel of the mapped index, 1 on the channels whose reflectivity is 1
    (infinite index). A Fresnel model for ``Conductor`` (``from_cos2``, ``param_shape``)."""

    def __init__(self, eta, kappa):
        self.mirror = np.isinf(eta)
        self._exact = ExactConductor(pick(self.mirror, 1.0, eta),
                                     pick(self.mirror, 0.0, kappa))
        self.param_shape = self._exact.param_shape

    def __repr__(self) -> str:
        return f"_MappedFresnel({self._exact!r}, mirror={self.mirror})"

    def __call__(self, cos_theta):
        return pick(self.mirror, 1.0, self._exact(cos_theta))

    def from_cos2(self, c2):
        return pick(self.mirror, 1.0, self._exact.from_cos2(c2))


def _narrow_and_wide(mapping: HazeMapping, model: str, compound_masking: bool, make):
    """``(components, weights)`` of a ``Sum`` for eq. 1 with ``make(distribution) -> Lobe``.

    Separate masking (the "large patches" reading of §3): two lobes weighted 1 - beta and
    beta. Compound masking (the "intertwined" reading, Lambda = (1 - beta) Lambda_n +
    beta Lambda_w): one lobe over the ``Mixture`` of the two distributions, whose Smith
    Lambda is that compound Lambda.
    """
    narrow = distribution(model, *mapping.alpha_n)
    wide = distribution(model, *mapping.alpha_w)
    if compound_masking:
        return [make(Mixture(narrow, wide, mapping.beta))], None
    beta = np.asarray(mapping.beta)[..., None]  # a grey colour weight (..., 1)
    return [make(narrow), make(wide)], [1.0 - beta, beta]


class HazyGloss(Sum):
    """Hazy gloss [Barla2018, eq. 1]: (1 - beta) F_r f_n + beta F_r f_w with microfacet lobes
    f_n, f_w of narrow and wide roughness sharing the exact conductor Fresnel F_r, all from
    the perceptual parameters through ``haze_mapping`` (kept as ``mapping``).

    Sampling picks the narrow or the wide lobe with probability proportional to its weight
    times its albedo estimate, and weighs by the whole mixture (``Sum``); with compound
    masking the one lobe samples the visible normals of the mixed distribution. Reciprocal.

    Parameters
    ----------
    core_reflectivity, haziness, haze_extent, alpha_x, alpha_y, edge_tint, haze_extent_y,
    smooth_weight, model : see ``haze_mapping`` (alpha in (0, inf): a smooth core has no
        halo shape).
    compound_masking : bool
        False: separate Smith masking per lobe (§3, "large patches"); True: the compound
        Lambda = (1 - beta) Lambda_n + beta Lambda_w (§3, "intertwined"; alphas >=
        ``microfacet.ALPHA_MIN``).
    """

    def __init__(self, core_reflectivity, haziness, haze_extent, alpha_x, alpha_y=None,
                 edge_tint=0.0, haze_extent_y=None, smooth_weight=None, model: str = "ggx",
                 compound_masking: bool = False):
        self.mapping = haze_mapping(core_reflectivity, haziness, haze_extent, alpha_x,
                                    alpha_y, edge_tint, haze_extent_y, smooth_weight, model)
        m = self.mapping
        fresnel = (_MappedFresnel(m.eta, m.kappa) if np.any(np.isinf(m.eta))
                   else ExactConductor(m.eta, m.kappa))
        components, weights = _narrow_and_wide(
            m, model, compound_masking, lambda d: Conductor.over(d, fresnel))
        super().__init__(*components, weights=weights)


class HazyDielectric(Sum):
    """Hazy gloss on a dielectric interface [Barla2018, §4.2, Fig. 13 left]: "the same physical
    parameters (beta, eta + i kappa, alpha_{n,w}) in a two-component BTDF of a form similar
    to Equation 1", (1 - beta) f_n + beta f_w with rough ``Dielectric`` lobes (reflection and
    refraction) of narrow and wide roughness and the one index eta = n_below / n_above.

    The index comes from ``haze_mapping`` with edge tint 0: eta = (1 + sqrt(r)) /
    (1 - sqrt(r)) ([Gulbrandsen2014], kappa = 0) of the global reflectivity r, which grows with
    the haziness (§5: "transmitted radiance is affected with increased haziness"). Light may
    arrive from either side (index 1 / eta below). Generalized reciprocity holds, as for
    each ``Dielectric``.

    Parameters
    ----------
    core_reflectivity : array_like in [0, 1)
        Scalar r_c (a dielectric's reflectivity is grey).
    haziness, haze_extent, alpha_x, alpha_y, haze_extent_y, smooth_weight, model,
    compound_masking : see ``HazyGloss``. The mapped r must stay below 1 (an infinite index):
        r = 1 where haziness = 1 and r_c >= p (eq. 7's energy bound reached), which raises.
    """

    def __init__(self, core_reflectivity, haziness, haze_extent, alpha_x, alpha_y=None,
                 haze_extent_y=None, smooth_weight=None, model: str = "ggx",
                 compound_masking: bool = False):
        r_c = _params.real("core_reflectivity", core_reflectivity, 0.0, 1.0, hi_open=True)
        self.mapping = haze_mapping(r_c[..., None], haziness, haze_extent, alpha_x, alpha_y,
                                    0.0, haze_extent_y, smooth_weight, model)
        m = self.mapping
        if np.any(m.reflectivity >= 1.0):
            raise ValueError(f"haziness = {haziness!r} with core_reflectivity = "
                             f"{core_reflectivity!r} maps to reflectivity 1 (an infinite "
                             "index); allowed: haziness < 1 where r_c >= p")
        eta = m.eta[..., 0]  # n_below / n_above, ``eta`` of the lobes (``Sum.eta``)
        components, weights = _narrow_and_wide(
            m, model, compound_masking, lambda d: Dielectric.over(eta, d))
        super().__init__(*components, weights=weights)
