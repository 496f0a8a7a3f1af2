"""Hypothesis sweeps in two sizes: a default run that draws a few hundred examples, and the
exhaustive sweep behind ``@pytest.mark.slow`` (``python -m pytest -m slow``), both from one
body.

    def _finite(params, wo): ...
    test_finite = sweep(_finite, 300, _parameters(), _COSINE)
    test_finite_exhaustively = sweep(_finite, 2000, _parameters(), _COSINE, slow=True)

Why: a sweep over a material's whole parameter range builds a new material per example, and
an anisotropic one may compute its energy slice (seconds, once per interface); 2000 of them
are most of the default run's time. The default size still draws every parameter at once,
ends of the ranges included (the strategies' ``sampled_from`` ends); the exhaustive size is
the thorough search.
"""

from __future__ import annotations

import types

import pytest
from hypothesis import HealthCheck, example, given, settings


def sweep(body, max_examples: int, *strategies, slow: bool = False, examples=(), **named):
    """A test: ``body`` under ``given(*strategies, **named)`` with ``max_examples`` draws (no
    deadline, no health checks), each of ``examples`` (argument tuples) tried first, marked
    slow where ``slow``. ``body`` is copied, so one body makes several tests."""
    test = types.FunctionType(body.__code__, body.__globals__, body.__name__,
                              body.__defaults__, body.__closure__)
    test.__doc__ = body.__doc__
    for args in examples:
        test = example(*args)(test)
    test = settings(max_examples=max_examples, deadline=None,
                    suppress_health_check=list(HealthCheck))(given(*strategies, **named)(test))
    return pytest.mark.slow(test) if slow else test
