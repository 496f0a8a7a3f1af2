"""A BSDF written elsewhere, as the library sees it: the ``Candidate`` protocol, a function
adapter, and the lobe that runs a candidate through the library's checks.

Conventions (``docs/conventions.md``): directions are unit vectors in the local shading
frame (normal +z), ``wo`` towards the viewer, ``wi`` towards the light, both pointing away
from the surface; ``eval`` is f without the cosine; ``sample(wo, u)`` draws ``wi`` from
uniforms ``u`` ``(..., 3)`` in [0, 1) and returns the direction, the weight
f |cos theta_i| / pdf and the solid-angle pdf.
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np

from adobe_bsdf.bsdf import BSDFSample, Flags, Lobe

__all__ = ["Candidate", "FunctionCandidate", "CandidateError", "CandidateLobe", "as_lobe"]


@runtime_checkable
class Candidate(Protocol):
    """What a candidate BSDF offers, batched over the leading axes of its arguments.

    ``eval(wo, wi)``: f(wo, wi) without the cosine, ``(..., 3)`` RGB or ``(...)`` grey.
    ``pdf(wo, wi)``: the solid-angle density ``(...)`` with which ``sample`` returns ``wi``.
    ``sample(wo, u)``: ``(wi, weight, pdf)`` (a tuple, or an object with those attributes,
    such as the library's ``BSDFSample``); ``weight`` ``(..., 3)`` or ``(...)``; a failed
    sample has pdf 0.
    """

    def eval(self, wo: np.ndarray, wi: np.ndarray) -> Any: ...

    def pdf(self, wo: np.ndarray, wi: np.ndarray) -> Any: ...

    def sample(self, wo: np.ndarray, u: np.ndarray) -> Any: ...


class FunctionCandidate:
    """A ``Candidate`` of three functions: ``eval(wo, wi)``, ``pdf(wo, wi)``, ``sample(wo,
    u)``, with the protocol's arguments and results; ``name`` appears in reports; ``eta``
    is the relative index of its interface (n below / n above) where it refracts."""

    def __init__(self, eval, pdf, sample, name: str = "candidate", eta=None):
        for label, fn in (("eval", eval), ("pdf", pdf), ("sample", sample)):
            if not callable(fn):
                raise ValueError(f"{label} = {fn!r}: allowed a function (see Candidate)")
        self._fns = {"eval": eval, "pdf": pdf, "sample": sample}
        self.name, self.eta = str(name), eta

    def eval(self, wo, wi):
        return self._fns["eval"](wo, wi)

    def pdf(self, wo, wi):
        return self._fns["pdf"](wo, wi)

    def sample(self, wo, u):
        return self._fns["sample"](wo, u)

    def __repr__(self) -> str:
        return f"FunctionCandidate({self.name!r})"


class CandidateError(ValueError):
    """A candidate's method raised, or answered with the wrong shape or type: the message
    names the method, what was asked and what came back."""


def _numbers(name: str, value) -> np.ndarray:
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise CandidateError(f"{name} returned {type(value).__name__}, not numbers: "
                             f"{exc}") from None


def _rgb(name: str, value, batch: tuple) -> np.ndarray:
    """``value`` as float64 ``(*batch, 3)``: grey ``(*batch)`` or ``(*batch, 1)`` widened."""
    v = _numbers(name, value)
    if v.shape == batch:
        v = v[..., None]
    if v.shape == batch + (1,):
        return np.repeat(v, 3, axis=-1)
    if v.shape != batch + (3,):
        raise CandidateError(f"{name} returned shape {v.shape} for a batch of {batch}: "
                             f"allowed {batch + (3,)} (RGB) or {batch} (grey)")
    return v


def _grey(name: str, value, batch: tuple) -> np.ndarray:
    """``value`` as float64 ``(*batch)`` (``(*batch, 1)`` accepted)."""
    v = _numbers(name, value)
    if v.shape == batch + (1,):
        v = v[..., 0]
    if v.shape != batch:
        raise CandidateError(f"{name} returned shape {v.shape} for a batch of {batch}: "
                             f"allowed {batch}")
    return v


def _call(candidate, method: str, *args):
    try:
        return getattr(candidate, method)(*args)
    except CandidateError:
        raise
    except Exception as exc:  # the candidate's own failure, named
        raise CandidateError(f"{method}() of {candidate!r} raised {type(exc).__name__}: "
                             f"{exc} (asked for a batch of {args[0].shape[:-1]})") from exc


def _parts(result):
    """(wi, weight, pdf) of a sample: a tuple of 3 (or more: the first three), or an object
    with the attributes ``wi``, ``weight``, ``pdf``."""
    if all(hasattr(result, k) for k in ("wi", "weight", "pdf")):
        return result.wi, result.weight, result.pdf
    if isinstance(result, (tuple, list)) and len(result) >= 3:
        return result[0], result[1], result[2]
    raise CandidateError(f"sample() returned {type(result).__name__}: allowed a tuple "
                         "(wi, weight, pdf) or an object with the attributes wi, weight, pdf")


def _same_shape(a, b):
    """``a``, ``b`` broadcast against each other as contiguous arrays: a candidate is asked
    for one batch, whatever it broadcasts."""
    a, b = np.broadcast_arrays(a, b)
    return np.ascontiguousarray(a), np.ascontiguousarray(b)


class CandidateLobe(Lobe):
    """A ``Candidate`` as a ``Lobe``: every check of ``adobe_bsdf.validation`` and
    ``conformance.compare`` runs on it, ``albedo`` included (by quadrature of ``eval`` or
    Monte Carlo over ``sample``; there is no table). Results are checked for shape and
    converted to float64; a grey result is widened to RGB. A sample's flags are read off its
    direction (reflection or transmission; none where its pdf is 0). ``eta`` (the relative
    index, for the energy factor of transmission and for generalized reciprocity) is the
    candidate's ``eta`` attribute unless given."""

    flags = Flags.REFLECTION | Flags.TRANSMISSION | Flags.GLOSSY

    def __init__(self, candidate, eta=None, needs=("eval", "pdf", "sample")):
        for method in needs:
            if not callable(getattr(candidate, method, None)):
                raise ValueError(f"candidate = {candidate!r} has no method {method}(): a "
                                 "candidate offers eval(wo, wi), pdf(wo, wi) and sample(wo, "
                                 "u) (conformance.Candidate), or use FunctionCandidate")
        self.candidate = candidate
        self.eta = getattr(candidate, "eta", None) if eta is None else eta

    def __repr__(self) -> str:
        return f"CandidateLobe({self.candidate!r})"

    def _param_shape(self):
        return ()

    def _eval(self, wo, wi):
        wo, wi = _same_shape(wo, wi)
        return _rgb("eval()", _call(self.candidate, "eval", wo, wi), wo.shape[:-1])

    def _pdf(self, wo, wi):
        wo, wi = _same_shape(wo, wi)
        return _grey("pdf()", _call(self.candidate, "pdf", wo, wi), wo.shape[:-1])

    def _eval_pdf(self, wo, wi):
        return self._eval(wo, wi), self._pdf(wo, wi)

    def _sample(self, wo, u):
        wo, u = _same_shape(wo, u)
        batch = wo.shape[:-1]
        wi, weight, pdf = _parts(_call(self.candidate, "sample", wo, u))
        wi = np.asarray(wi, dtype=np.float64)
        if wi.shape != batch + (3,):
            raise CandidateError(f"sample() returned directions of shape {wi.shape} for a "
                                 f"batch of {batch}: allowed {batch + (3,)}")
        weight = _rgb("sample()'s weight", weight, batch)
        pdf = _grey("sample()'s pdf", pdf, batch)
        ok = pdf > 0.0
        side = wi[..., 2] * wo[..., 2] > 0.0
        flags = np.where(ok, np.where(side, int(Flags.REFLECTION), int(Flags.TRANSMISSION))
                         | int(Flags.GLOSSY), int(Flags.NONE))
        return BSDFSample(wi, weight, pdf, flags)

    def _energy_scale(self, wo, wi):
        if self.eta is None:
            return np.ones(np.broadcast_shapes(wo.shape[:-1], wi.shape[:-1]))
        eta = np.asarray(self.eta, dtype=np.float64)
        eta_o = np.where(wo[..., 2] >= 0.0, 1.0, eta)
        eta_i = np.where(wi[..., 2] >= 0.0, 1.0, eta)
        return (eta_i / eta_o) ** 2

    def _energy_scale_rgb(self, wo, wi):
        return self._energy_scale(wo, wi)[..., None]


def as_lobe(candidate, eta=None, needs=("eval", "pdf", "sample")) -> Lobe:
    """``candidate`` itself where it is a library ``Lobe``, else ``CandidateLobe(candidate,
    eta)``, checked to have the methods a check ``needs`` (a sampler's chi-square needs
    only ``pdf`` and ``sample``)."""
    if isinstance(candidate, Lobe):
        return candidate
    return CandidateLobe(candidate, eta, needs)
