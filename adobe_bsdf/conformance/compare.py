"""``compare(reference, candidate)``: a verdict on a BSDF written elsewhere, against one of
the library's lobes or materials; ``assert_conforms`` for a renderer's own test suite.

The checks (each a ``report.Check`` with its statistic, threshold, p-value where
statistical, worst case and likely cause):

* ``finite``: NaN, Inf and negative values in ``eval``, ``pdf`` and ``sample``, and sampled
  directions off the sphere: none allowed.
* ``eval``, ``pdf``: pointwise at stratified pairs (per view, ``STRATA`` x ``STRATA`` cells of
  (cos theta_i, phi_i) over the sphere, one jittered direction each), relative to the
  reference with a floor of ``FLOOR`` times its largest value at that view.
* ``weight``: the candidate's sample weight against f |cos theta_i| / pdf of its own
  ``eval`` and ``pdf``, and its sample pdf against ``pdf``.
* ``chi2 (own pdf)``: the candidate's samples against its own pdf; ``chi2 (reference
  pdf)``: against the reference's (``validation.chi2.chi2_test``), both at the family-wise
  false-alarm rate ``alpha`` over all views (Šidák).
* ``albedo``: the directional energy albedo by angle, Monte Carlo over each one's sampler, a
  z-test at ``alpha`` with an absolute tolerance ``albedo_atol``.
* ``reciprocity``: the candidate's generalized reciprocity where the reference's holds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats

from adobe_bsdf.bsdf import Flags, Lobe
from adobe_bsdf.conformance.report import Check, Report
from adobe_bsdf.validation.candidate import CandidateError, as_lobe
from adobe_bsdf.validation.checks import reciprocity_error, weight_cause
from adobe_bsdf.validation.chi2 import chi2_test, sidak_alpha

__all__ = ["compare", "assert_conforms", "default_views", "make_plan", "Plan", "STRATA",
           "FLOOR"]

#: per view, STRATA x STRATA stratified directions wi for the pointwise checks
STRATA = 24
#: the pointwise checks' floor: relative errors are taken against |reference| + FLOOR times
#: the reference's largest value at that view (values far below the lobe's peak compare
#: absolutely)
FLOOR = 1e-3
COSINES = (0.9, 0.5, 0.15)
AZIMUTHS = (0.3, 1.2)


def _direction(cos_theta, phi):
    s = math.sqrt(max(0.0, 1.0 - cos_theta * cos_theta))
    return np.array([s * math.cos(phi), s * math.sin(phi), cos_theta])


def default_views(reference: Lobe) -> np.ndarray:
    """``(n, 3)`` views: cos theta_o in ``COSINES`` at azimuths ``AZIMUTHS`` (two, so that an
    anisotropic lobe is seen along and across its axes), and from below where the reference
    transmits."""
    views = [_direction(c, p) for c in COSINES for p in AZIMUTHS]
    if Flags.TRANSMISSION in Flags(int(getattr(reference, "flags", 0))):
        views += [v * np.array([1.0, 1.0, -1.0]) for v in views]
    return np.stack(views)


def _stratified(n: int, rng) -> np.ndarray:
    """``(n * n, 3)`` directions, one jittered in each cell of (cos theta, phi) over the
    sphere: uniform in solid angle."""
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    z = -1.0 + 2.0 * (i.ravel() + rng.random(n * n)) / n
    phi = 2.0 * np.pi * (j.ravel() + rng.random(n * n)) / n
    s = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    return np.stack([s * np.cos(phi), s * np.sin(phi), z], -1)


def _view(wo) -> tuple:
    return (float(wo[2]), float(math.atan2(wo[1], wo[0])))


def _pairs(views, rng):
    wi = np.concatenate([_stratified(STRATA, rng) for _ in views])
    wo = np.repeat(views, STRATA * STRATA, axis=0)
    keep = wi[:, 2] != 0.0
    return wo[keep], wi[keep]


@dataclass(frozen=True)
class Plan:
    """What a comparison asks of a candidate: the ``views``, the pairs (``wo``, ``wi``) of
    the pointwise and reciprocity checks (``keep``: those well conditioned in float32, or
    None), and per view ``n_samples`` samples from the uniforms ``uniforms(k)``."""

    views: np.ndarray
    wo: np.ndarray
    wi: np.ndarray
    keep: np.ndarray | None
    n_samples: int
    seed: int
    float32: bool = False

    def uniforms(self, k: int) -> np.ndarray:
        """The uniforms ``(n_samples, 3)`` of view ``k``: those ``chi2_test`` draws with the
        seed ``seed + 1 + k``."""
        return np.random.default_rng(self.seed + 1 + k).random((self.n_samples, 3))


def make_plan(reference: Lobe, views=None, n_samples: int = 100_000, seed: int = 0,
              float32: bool = False) -> Plan:
    """The ``Plan`` of a comparison with ``reference`` (``compare``'s arguments)."""
    views = default_views(reference) if views is None else np.atleast_2d(
        np.asarray(views, dtype=np.float64))
    wo, wi = _pairs(views, np.random.default_rng(seed))
    keep = None
    if float32:
        from adobe_bsdf.validation.mitsuba import float32_directions, well_conditioned

        wo, wi = float32_directions(wo), float32_directions(wi)
        eta = getattr(reference, "eta", None)
        keep = well_conditioned(wo, wi, None if eta is None else float(np.max(eta)))
    return Plan(views, wo, wi, keep, int(n_samples), int(seed), bool(float32))


def _bad(values) -> tuple[int, int, int]:
    v = np.asarray(values)
    finite = np.isfinite(v)
    return int(np.isnan(v).sum()), int((~finite & ~np.isnan(v)).sum()), int(
        (finite & (v < 0.0)).sum())


def _finite_check(wo, wi, f, pdf, samples) -> Check:
    counts = {}
    first = {}
    for name, values, where in (("eval", f, (wo, wi)), ("pdf", pdf, (wo, wi)),
                                ("sample weight", samples["weight"], None),
                                ("sample pdf", samples["pdf"], None)):
        nan, inf, neg = _bad(values)
        counts[name] = (nan, inf, neg)
        if nan + inf + neg and not first:
            bad = ~np.isfinite(values) | (np.nan_to_num(values, nan=0.0) < 0.0)
            row = int(np.flatnonzero(bad.reshape(len(bad), -1).any(-1))[0])
            if where is not None:
                first = {"view": _view(where[0][row]), "wi": tuple(where[1][row]), name:
                         np.asarray(values)[row].tolist()}
            else:
                first = {"view": _view(samples["wo"][row]), name:
                         np.asarray(values)[row].tolist()}
    off = np.abs(np.linalg.norm(samples["wi"][samples["pdf"] > 0], axis=-1) - 1.0) > 1e-5
    counts["sampled directions off the sphere"] = (int(off.sum()),)
    total = sum(sum(c) for c in counts.values())
    note = "; ".join(f"{k}: " + ", ".join(f"{n} {w}" for n, w in zip(
        c, ("NaN", "Inf", "negative") if len(c) == 3 else ("",), strict=True) if n)
                     for k, c in counts.items() if sum(c))
    cause = ""
    bad_pairs = np.zeros(len(wo), dtype=bool)
    for values in (f, pdf):
        v = np.asarray(values).reshape(len(wo), -1)
        bad_pairs |= (~np.isfinite(v) | (np.nan_to_num(v) < 0.0)).any(-1)
    if bad_pairs.any():
        grazing = np.minimum(np.abs(wo[bad_pairs, 2]), np.abs(wi[bad_pairs, 2])).max()
        if grazing < 0.1:
            cause = f"only at grazing angles: min(|cos theta_o|, |cos theta_i|) <= {grazing:.2g}"
    return Check("finite", total == 0, "bad values", float(total), 0.0, worst=first,
                 cause=(note + (f" ({cause})" if cause else "")) if total else "")


def _pointwise(name: str, reference, candidate, wo, wi, views, rtol: float,
               keep=None, noise=None, alpha: float = 0.01) -> Check:
    """Relative error of ``candidate`` against ``reference`` (``(n, k)``) at the pairs
    (those of ``keep`` only, where given: the others are named in the note). Where the
    reference is a Monte-Carlo estimate with standard errors ``noise``, the part of each
    difference within z of them is its error, z the two-sided normal quantile at ``alpha``
    shared by all the values (Bonferroni)."""
    r = np.atleast_2d(np.asarray(reference, dtype=np.float64).reshape(len(wo), -1))
    c = np.atleast_2d(np.asarray(candidate, dtype=np.float64).reshape(len(wo), -1))
    e = 0.0 if noise is None else np.asarray(noise, dtype=np.float64).reshape(r.shape)
    note = ""
    if keep is not None and not keep.all():
        note = (f"{int((~keep).sum())} of {len(keep)} pairs ill-conditioned in float32 left "
                "out (validation.mitsuba.well_conditioned)")
        r, c, wo, wi = r[keep], c[keep], wo[keep], wi[keep]
        e = e if noise is None else e[keep]
    z = 0.0
    if noise is not None:
        z = float(stats.norm.isf(alpha / (2.0 * r.size)))
        note = (note + "; " if note else "") + (
            f"the reference is a Monte-Carlo estimate: differences within {z:.2f} of its "
            f"standard errors are its own (Bonferroni over {r.size} values at {alpha:g})")
    view_index = _view_index(wo, views)
    peak = np.zeros((len(views), r.shape[1]))
    np.maximum.at(peak, view_index, np.abs(np.nan_to_num(r)))
    floor = FLOOR * peak[view_index] + 1e-300
    error = np.maximum(np.abs(c - r) - z * e, 0.0) / (np.abs(r) + floor)
    error = np.where(np.isfinite(error), error, np.inf)
    k = np.unravel_index(int(np.argmax(error)), error.shape)
    worst = float(error[k])
    row = int(k[0])
    where = {"view": _view(wo[row]), "wi": tuple(float(x) for x in wi[row]),
             "reference": float(r[k]), "candidate": float(c[k])}
    return Check(name, worst <= rtol, "max relative error", worst, rtol, worst=where,
                 cause="" if worst <= rtol else _cause(name, r, c, wo, wi, floor), note=note)


#: why a random-walk reference's pdf is not compared
_WALKS_PDF = ("the reference follows random walks: its pdf is an estimate, not the density "
              "of its samples, so the candidate's sampling is judged by its own pdf only")


def _view_index(wo, views) -> np.ndarray:
    return np.argmin(np.linalg.norm(wo[:, None, :] - views[None], axis=-1), axis=1)


def _cause(name: str, r, c, wo, wi, floor) -> str:
    """The likely cause of a pointwise difference, where a simple one fits."""
    big = (np.abs(r) > 30.0 * floor) & np.isfinite(c) & np.isfinite(r)
    if not big.any():
        return ""
    ratio = c[big] / r[big]
    cos_i = np.broadcast_to(np.abs(wi[:, 2:3]), r.shape)[big]
    if name == "eval" and np.median(np.abs(ratio - cos_i)) < 1e-3 * np.median(cos_i):
        return "f has the cosine folded in: candidate = reference x |cos theta_i|"
    scale = np.median(ratio)
    if np.median(np.abs(ratio - scale)) < 1e-3 * abs(scale) and abs(scale - 1.0) > 1e-3:
        return f"scaled: candidate = {scale:.4g} x reference everywhere"
    grazing = np.minimum(np.abs(wo[:, 2]), np.abs(wi[:, 2]))
    bad = np.abs(c - r).max(-1) > 0.1 * np.abs(r).max(-1)
    if bad.any() and np.median(grazing[bad]) < 0.1 < np.median(grazing):
        return "wrong mostly at grazing angles (masking, or the horizon)"
    return ""


def _draw(lobe: Lobe, plan: Plan, n: int):
    """The candidate's first ``n`` samples of each view of ``plan``, in one batch."""
    wo = np.repeat(plan.views, n, axis=0)
    u = np.concatenate([plan.uniforms(k)[:n] for k in range(len(plan.views))])
    s = lobe.sample(wo, u)
    return {"wo": wo, "wi": s.wi, "weight": s.weight, "pdf": s.pdf}


def _weight_check(lobe: Lobe, samples, rtol: float) -> Check:
    ok = (samples["pdf"] > 0.0) & np.isfinite(samples["pdf"])
    wo, wi = samples["wo"][ok], samples["wi"][ok]
    if not len(wo):
        return Check("weight", False, "max relative error", None, rtol,
                     cause="every sample failed (pdf 0)")
    f, pdf = lobe.eval(wo, wi), lobe.pdf(wo, wi)
    cos_i = np.abs(wi[:, 2:3])
    expected = f * cos_i / np.where(pdf > 0.0, pdf, np.inf)[:, None]
    weight = samples["weight"][ok]
    error = np.abs(weight - expected) / np.maximum(np.abs(expected), 1e-12)
    pdf_error = np.abs(samples["pdf"][ok] - pdf) / np.maximum(pdf, 1e-300)
    worst = np.nan_to_num(np.maximum(error.max(-1), pdf_error), nan=np.inf)
    row = int(np.argmax(worst))
    value = float(worst[row])
    cause = ("" if value <= rtol else
             weight_cause(weight, expected, cos_i, samples["pdf"][ok], pdf, rtol))
    return Check("weight", value <= rtol, "max relative error", value, rtol,
                 worst={"view": _view(wo[row]), "wi": tuple(float(x) for x in wi[row]),
                        "weight": float(weight[row].max()),
                        "f cos / pdf": float(expected[row].max())}, cause=cause)


class _SampledBy(Lobe):
    """Samples of ``sampler`` with the pdf of ``density``: the chi-square of one's draws
    against the other's distribution."""

    flags = Flags.REFLECTION | Flags.TRANSMISSION | Flags.GLOSSY

    def __init__(self, sampler: Lobe, density: Lobe):
        self.sampler, self.density = sampler, density

    def _param_shape(self):
        return ()

    def _eval(self, wo, wi):
        return self.density._eval(wo, wi)

    def _pdf(self, wo, wi):
        return self.density._pdf(wo, wi)

    def _sample(self, wo, u):
        return self.sampler._sample(wo, u)


def _chi2_check(name: str, lobe: Lobe, plan: Plan, alpha: float) -> Check:
    views = plan.views
    results = [chi2_test(lobe, v, n_samples=plan.n_samples, seed=plan.seed + 1 + k,
                         alpha=alpha, n_tests=len(views)) for k, v in enumerate(views)]
    k = int(np.argmin([r.p_value for r in results]))
    worst = results[k]
    threshold = sidak_alpha(alpha, len(views))
    passed = all(r.passed for r in results)
    note = (f"family of {len(views)} views at a false-alarm rate of {alpha:g} (Šidák: "
            f"{threshold:.2g} each)")
    cause = ""
    if not passed:
        cause = (f"p = {worst.p_value:.2g} < {threshold:.2g}: a correct sampler fails this "
                 f"family with probability {alpha:g}")
        if worst.n_invalid:
            cause += f"; {worst.n_invalid} invalid samples"
    return Check(name, passed, "smallest p-value", worst.p_value, threshold, worst.p_value,
                 worst={"view": _view(views[k]), "statistic": float(worst.statistic),
                        "dof": int(worst.dof)}, cause=cause, note="" if cause else note)


def _sampled_albedo(lobe: Lobe, plan: Plan) -> tuple[np.ndarray, np.ndarray]:
    """``(mean, standard error)`` ``(views, 3)`` of the energy-scaled sample weights of the
    plan's samples (the uniforms of the chi-square tests)."""
    means, errors = [], []
    for k, view in enumerate(plan.views):
        u = plan.uniforms(k)
        wo = np.broadcast_to(view, u.shape)
        s = lobe.sample(wo, u)
        w = s.weight * lobe._energy_scale_rgb(wo, s.wi)
        means.append(w.mean(0))
        errors.append(w.std(0, ddof=1) / np.sqrt(len(w)))
    return np.stack(means), np.stack(errors)


def _albedo_check(reference: Lobe, candidate: Lobe, plan: Plan, alpha: float,
                  atol: float) -> Check:
    views, n_samples = plan.views, plan.n_samples
    E_r, s_r = reference.albedo(views, "mc", n_samples=n_samples, rng=plan.seed + 2000,
                                return_error=True)
    E_c, s_c = _sampled_albedo(candidate, plan)
    diff = np.abs(E_c - E_r)
    sigma = np.sqrt(s_r ** 2 + s_c ** 2)
    z = np.where(sigma > 0, diff / np.where(sigma > 0, sigma, 1.0), np.where(diff > 0,
                                                                             np.inf, 0.0))
    p = 2.0 * stats.norm.sf(z)
    threshold = sidak_alpha(alpha, diff.size)
    failed = (p < threshold) & (diff > atol)
    k = np.unravel_index(int(np.argmax(np.where(diff > atol, z, -1.0))), diff.shape)
    row = int(k[0])
    return Check("albedo", not failed.any(), "largest |difference|", float(diff.max()), atol,
                 float(p.min()), worst={"view": _view(views[row]),
                                        "reference": float(E_r[k]), "candidate": float(E_c[k]),
                                        "sigma": float(sigma[k])},
                 cause=(f"differs by {diff[k]:.3g} ({z[k]:.1f} sigma) beyond {atol:g}"
                        if failed.any() else ""),
                 note=f"{n_samples} samples per view each; z-test at {alpha:g} (Šidák)")


def _reciprocity_check(reference: Lobe, candidate: Lobe, wo, wi, rtol: float,
                       scale: float, keep=None) -> Check:
    """Generalized reciprocity at the pairs (of ``keep``), values below ``FLOOR`` x
    ``scale`` (the reference's largest f) compared absolutely, as the pointwise checks do."""
    atol = FLOOR * scale
    if keep is not None:
        wo, wi = wo[keep], wi[keep]
    # a random-walk reference (None here) is reciprocal by physics, not to its estimates
    ref = None if reference is None else reciprocity_error(reference, wo, wi, rtol=1e-6,
                                                           atol=atol)
    if ref is not None and not ref.passed:
        return Check("reciprocity", None, "max relative error", None, rtol,
                     note=f"the reference is not reciprocal ({ref.max_error:.2g})")
    cand = reciprocity_error(candidate, wo, wi, rtol=rtol, atol=atol)
    return Check("reciprocity", cand.passed, "max relative error", float(cand.max_error),
                 rtol, worst={"wo": tuple(float(x) for x in cand.worst_wo),
                              "wi": tuple(float(x) for x in cand.worst_wi)},
                 cause="" if cand.passed else "f(wo, wi) and f(wi, wo) differ")


def compare(reference, candidate, *, views=None, n_samples: int = 100_000,
            alpha: float = 0.01, rtol: float = 1e-3, albedo_atol: float = 2e-3,
            same_sampling: bool = True, float32: bool = False, seed: int = 0,
            progress: bool = True) -> Report:
    """Judge ``candidate`` (a ``Candidate``: ``eval``, ``pdf``, ``sample`` in the library's
    conventions) against ``reference`` (a lobe or material of the library, or a structure
    followed by random walks such as ``OpenPBRSurface(...).reference()``: its ``eval`` is
    then compared within its Monte-Carlo error, its ``pdf``, an estimate, not at all, and
    it is reciprocal by physics, not by its estimates).

    Parameters
    ----------
    views : array_like (n, 3), optional
        Outgoing directions (default ``default_views(reference)``).
    n_samples : int
        Samples per view of each chi-square test and each albedo.
    alpha : float
        Family-wise false-alarm rate of each statistical test, in (0, 1).
    rtol : float
        Allowed relative error of ``eval``, ``pdf``, weights and reciprocity.
    albedo_atol : float
        Albedo differences below this never fail.
    same_sampling : bool
        Whether the candidate samples the reference's distribution (as two VNDF samplers
        do): then its ``pdf`` and its samples are held to the reference's; otherwise those
        two checks do not apply.
    float32 : bool
        The candidate computes in float32 (a GPU, Mitsuba's scalar variants): the pairs are
        float32 directions (``validation.mitsuba.float32_directions``), and those where
        float32 is ill-conditioned (``validation.mitsuba.well_conditioned``: near the
        critical angle, grazing microfacets, horizons) are left out of the pointwise and
        reciprocity checks, their count stated.
    seed : int
        Seed of every random choice (pairs, uniforms).
    progress : bool
        A progress bar over the checks (on a terminal; never in a log or a notebook's
        captured output).
    """
    from tqdm import tqdm

    ref = reference
    if not isinstance(ref, Lobe):
        raise ValueError(f"reference = {reference!r}: allowed a lobe or material of "
                         "adobe_bsdf")
    cand = as_lobe(candidate, getattr(ref, "eta", None) if getattr(candidate, "eta", None)
                   is None and not isinstance(candidate, Lobe) else None)
    plan = getattr(candidate, "plan", None)  # a file's answers: the request's plan
    if plan is None:
        plan = make_plan(ref, views, n_samples, seed, float32)
    answers_only = plan is getattr(candidate, "plan", None)
    views, wo, wi, keep = plan.views, plan.wo, plan.wi, plan.keep
    checks = []
    steps = ["pointwise", "samples", "chi2", "albedo", "reciprocity"]
    bar = tqdm(steps, desc="conformance", disable=None if progress else True, leave=False)
    # a random-walk reference (``OpenPBRSurface.reference``): eval an estimate with its
    # error, its pdf an estimate that is not its sampler's density, reciprocal by physics
    walks = not ref.weight_is_ratio and hasattr(ref, "eval_with_error")
    try:
        if walks:
            (f_r, e_r), pdf_r = ref.eval_with_error(wo, wi), None
        else:
            f_r, e_r, pdf_r = ref.eval(wo, wi), None, ref.pdf(wo, wi)
        f_c, pdf_c = cand.eval(wo, wi), cand.pdf(wo, wi)
        bar.update()
        samples = _draw(cand, plan, min(plan.n_samples, 20_000))
        checks.append(_finite_check(wo, wi, f_c, pdf_c, samples))
        checks.append(_pointwise("eval", f_r, f_c, wo, wi, views, rtol, keep, e_r, alpha))
        if walks:
            checks.append(Check("pdf", None, "max relative error", note=_WALKS_PDF))
        elif same_sampling:
            checks.append(_pointwise("pdf", pdf_r, pdf_c, wo, wi, views, rtol, keep))
        else:
            checks.append(Check("pdf", None, "max relative error", note="same_sampling "
                                "is False: the candidate's own strategy"))
        checks.append(_weight_check(cand, samples, rtol))
        bar.update()
        if answers_only:
            checks.append(Check("chi2 (own pdf)", None, "smallest p-value", note="a file "
                                "answers pdf at the requested pairs only"))
        else:
            checks.append(_chi2_check("chi2 (own pdf)", cand, plan, alpha))
        if walks:
            checks.append(Check("chi2 (reference pdf)", None, "smallest p-value",
                                note=_WALKS_PDF))
        elif same_sampling:
            checks.append(_chi2_check("chi2 (reference pdf)", _SampledBy(cand, ref), plan,
                                      alpha))
        else:
            checks.append(Check("chi2 (reference pdf)", None, "smallest p-value",
                                note="same_sampling is False"))
        bar.update()
        checks.append(_albedo_check(ref, cand, plan, alpha, albedo_atol))
        bar.update()
        scale = float(np.nanmax(np.abs(f_r))) if np.size(f_r) else 1.0
        checks.append(_reciprocity_check(None if walks else ref, cand, wo, wi, rtol, scale,
                                         keep))
        bar.update()
    except CandidateError as exc:
        checks.append(Check("candidate", False, "error", cause=str(exc)))
    finally:
        bar.close()
    settings = {"views": len(views), "n_samples": plan.n_samples, "alpha": alpha,
                "rtol": rtol, "albedo_atol": albedo_atol, "same_sampling": same_sampling,
                "float32": plan.float32, "seed": plan.seed}
    return Report(repr(reference), _name(candidate), checks, settings)


def _name(candidate) -> str:
    """A candidate's ``name`` attribute, else its repr where it defines one, else its
    class's name."""
    name = getattr(candidate, "name", None)
    if isinstance(name, str):
        return name
    if type(candidate).__repr__ is not object.__repr__:
        return repr(candidate)
    return type(candidate).__name__


def assert_conforms(reference, candidate, **options) -> Report:
    """``compare`` as an assertion, in the manner of ``numpy.testing``: ``AssertionError``
    whose message is the report's table where any check fails; the report otherwise."""
    report = compare(reference, candidate, **options)
    if not report.passed:
        raise AssertionError("\n" + str(report))
    return report
