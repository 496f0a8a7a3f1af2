"""Conformance: a verdict on a BSDF written elsewhere (a renderer's, a port of OpenPBR, a
Mitsuba plugin) against the library's reference.

Public API
----------
``compare(reference, candidate, ...)``  every check (``compare``'s docstring), as a ``Report``.
``assert_conforms(reference, candidate, ...)``  the same as an assertion for a test suite.
``Candidate``            the protocol a candidate follows: ``eval``, ``pdf``, ``sample``.
``FunctionCandidate``    a candidate of three functions.
``CandidateLobe``, ``as_lobe``  a candidate as a ``Lobe``: every check of
                         ``adobe_bsdf.validation`` runs on it.
``Report``, ``Check``    the verdict: a table (``str``), ``markdown()``, ``to_json()``.
``figure(reference, candidate, wo)``  both polar slices and a map of the difference.
``write_request``, ``read_answers``  the file protocol (``conformance.files``): the queries
                         for a renderer without Python, and its answers as a candidate;
                         ``answer_request`` answers a request with a Python candidate.
"""

from adobe_bsdf.conformance.compare import assert_conforms, compare, default_views
from adobe_bsdf.conformance.figure import difference_map, figure
from adobe_bsdf.conformance.files import (
    AnsweredCandidate,
    answer_request,
    read_answers,
    read_request,
    write_request,
)
from adobe_bsdf.conformance.report import Check, Report
from adobe_bsdf.validation.candidate import (
    Candidate,
    CandidateError,
    CandidateLobe,
    FunctionCandidate,
    as_lobe,
)

__all__ = ["AnsweredCandidate", "Candidate", "CandidateError", "CandidateLobe", "Check",
           "FunctionCandidate", "Report", "answer_request", "as_lobe", "assert_conforms",
           "compare", "default_views", "difference_map", "figure", "read_answers",
           "read_request", "write_request"]
