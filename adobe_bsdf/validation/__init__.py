"""Validation toolkit: statistical and deterministic checks of any ``Lobe``.

Reused by the test suite, by ``python -m adobe_bsdf check`` and by the notebooks. Every check
returns a result object carrying its measured figures and ``passed``; ``str(result)`` is a
one-line summary.

Public API
----------
Sampling against density (``validation.chi2``)

``chi2_test(lobe, wo, *, n_samples, n_theta, n_phi, seed, alpha, n_tests, axis, warp, ...)``
    Chi-square goodness-of-fit test of ``lobe.sample`` against ``lobe.pdf`` on a sphere grid
    (reflection and transmission), with adaptive per-cell integration of the pdf; returns a
    ``Chi2Result`` (p-value, Šidák-corrected threshold, statistic, dof, pdf mass, failed and
    delta fractions, observed and expected histograms, grid edges).
``suggest_grid(width, peak)``
    Pole ``axis`` and ring ``warp`` that spread a narrow lobe over many cells.
``SphereGrid``, ``integrate_cells``, ``integrate_pdf``, ``draw_samples``, ``classify_samples``,
``sidak_alpha``
    The building blocks: grid, vectorised adaptive Genz–Malik cubature over cells, sampling
    with classification of delta / failed / invalid samples, multiple-test correction.

Razor-thin lobes (``validation.stretch``, imported on its own)

``Stretched(lobe, matrix)``, ``ridge_stretch(phi, factor)``
    A lobe seen through the map w -> A w / |A w| of the sphere (exact Jacobian), so that
    ``chi2_test`` resolves a ridge ~1e-8 rad wide (ASM roughness 0 with anisotropy 1).

Consistency checks (``validation.checks``)

``pdf_integral(lobe, wo, *, expected, tol, ...)``
    Integral of the pdf over the sphere against the non-delta probability.
``reciprocity_error(lobe, wo, wi, eta_o=None, eta_i=None, *, rtol, atol)``
    f(wo, wi)/eta_o^2 = f(wi, wo)/eta_i^2; uses the lobe's ``eta`` attribute if it has one.
``weight_consistency(lobe, wo, n_samples, seed, *, u, rtol)``
    Sample weight and pdf against ``eval`` and ``pdf`` at the sampled direction; flags.
``furnace(lobe, wo, expected, method, tol)``
    Directional albedo against an expected value (white furnace with ``expected = 1``).
``mc_albedo_consistency(lobe, wo, *, n_samples, seed, alpha, n_tests, rtol)``
    Monte Carlo albedo against quadrature albedo, in standard errors.

Candidates written elsewhere (``validation.candidate``)

``Candidate``                a ``typing.Protocol``: ``eval(wo, wi)``, ``pdf(wo, wi)``,
                             ``sample(wo, u) -> (wi, weight, pdf)`` in the library's
                             conventions; every check above takes one where it takes a lobe.
``FunctionCandidate``        a candidate of three functions.
``CandidateLobe``, ``as_lobe``  a candidate as a ``Lobe`` (what the checks do with it).
``CandidateError``           a candidate's method raised or answered with the wrong shape.

Property-test inputs (``validation.strategies``, needs ``hypothesis``; not imported here)

``directions``, ``direction_pairs``, ``roughness``, ``alpha_pairs``, ``iors``,
``uniform_triples``.

References
----------
[Jakob2022] Mitsuba 3, ``src/python/python/chi2.py``; [Pharr2023] pbrt-v4,
``src/pbrt/bsdfs_test.cpp``: the chi-square method (histogram on a sphere grid, pooling below
5 expected, hard failure in cells of zero expectation, Šidák-corrected significance
[Sidak1967]).
[GenzMalik1980] adaptive cubature.
[Veach1997, §5.3] reciprocity of BSDFs with refraction.
"""

from adobe_bsdf.validation.candidate import (
    Candidate,
    CandidateError,
    CandidateLobe,
    FunctionCandidate,
    as_lobe,
)
from adobe_bsdf.validation.checks import (
    FurnaceResult,
    McAlbedoResult,
    PdfIntegralResult,
    ReciprocityResult,
    WeightConsistencyResult,
    furnace,
    mc_albedo_consistency,
    pdf_integral,
    reciprocity_error,
    weight_consistency,
)
from adobe_bsdf.validation.chi2 import (
    CellIntegral,
    Chi2Result,
    Draws,
    SphereGrid,
    chi2_test,
    classify_samples,
    draw_samples,
    integrate_cells,
    integrate_pdf,
    sidak_alpha,
    suggest_grid,
)

__all__ = [
    "Candidate",
    "CandidateError",
    "CandidateLobe",
    "FunctionCandidate",
    "as_lobe",
    "CellIntegral",
    "Chi2Result",
    "Draws",
    "FurnaceResult",
    "McAlbedoResult",
    "PdfIntegralResult",
    "ReciprocityResult",
    "SphereGrid",
    "WeightConsistencyResult",
    "chi2_test",
    "classify_samples",
    "draw_samples",
    "furnace",
    "integrate_cells",
    "integrate_pdf",
    "mc_albedo_consistency",
    "pdf_integral",
    "reciprocity_error",
    "sidak_alpha",
    "suggest_grid",
    "weight_consistency",
]
