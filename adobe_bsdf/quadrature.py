"""Energy albedo by adaptive cubature over a lobe's sample space.

A lobe whose ``sample`` maps two uniforms ``u2 in [0, 1]^2`` to a direction has directional
albedo E(wo) = integral over the unit square of the energy of the generated sample
(f |cos| / pdf times the pdf of ``u2``, which is 1). The integrand is smooth where the
sampling is good (for GGX visible-normal sampling it is F G2 / G1), so Genz–Malik /
Gauss–Kronrod cubature (``scipy.integrate.cubature``) converges quickly; its error estimate
is returned. Discrete branches (reflection vs refraction) are summed inside the integrand, so
the lobe-selection uniform is integrated exactly.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import cubature

#: cubature rule; "gk21" is the tensor Gauss–Kronrod 21-point rule, adaptive
RULE = "gk21"


def sample_space_albedo(integrand, wo: np.ndarray, *, rtol: float = 1e-9,
                        atol: float = 1e-12, max_subdivisions: int = 10_000):
    """Integrate ``integrand(wo, u2) -> (..., 3)`` over ``u2 in [0, 1]^2`` for every ``wo``.

    Returns ``(estimate, error)``, both of shape ``(..., 3)`` (the batch of ``wo`` broadcast
    with the lobe's parameters). All directions of the batch
    share one adaptive subdivision (refined where any of them needs it).
    """
    batch = wo.shape[:-1]
    expand = (slice(None),) + (None,) * len(batch)

    def f(x):  # x: (npoints, 2) -> (npoints, *batch, 3)
        u2 = np.broadcast_to(x[expand], (x.shape[0], *batch, 2))
        value = integrand(np.broadcast_to(wo, (x.shape[0], *wo.shape)), u2)
        return np.broadcast_to(value, np.broadcast_shapes(value.shape, (x.shape[0], *batch, 3)))

    res = cubature(f, [0.0, 0.0], [1.0, 1.0], rule=RULE, rtol=rtol, atol=atol,
                   max_subdivisions=max_subdivisions)
    return res.estimate, res.error
