"""The lobe protocol shared by every lobe and material.

Public API
----------
``Flags``       bit flags of a sample or a lobe (reflection, transmission, diffuse, glossy, delta).
``BSDFSample``  the record returned by ``sample``.
``Lobe``        base class: validates and broadcasts inputs, then calls the private maths.

Conventions (``docs/conventions.md``, ``design.md``): directions are unit vectors in the local
shading frame (normal ``+z``), ``wo`` towards the viewer, ``wi`` towards the light, both pointing
away from the surface. ``eval`` is the radiance-transport BSDF *without* the cosine factor;
``albedo`` is the *energy* albedo R + T.
"""

from __future__ import annotations

import enum
from typing import NamedTuple

import numpy as np

from adobe_bsdf import _params
from adobe_bsdf.quadrature import sample_space_albedo

__all__ = ["Flags", "BSDFSample", "Lobe", "ALBEDO_METHODS"]

ALBEDO_METHODS = ("quadrature", "mc", "table")


class Flags(enum.IntFlag):
    """Bit flags of a lobe or of one sample (as pbrt-v4 ``BxDFFlags`` / Mitsuba ``BSDFFlags``)."""

    NONE = 0
    REFLECTION = 1
    TRANSMISSION = 2
    DIFFUSE = 4
    GLOSSY = 8
    DELTA = 16


class BSDFSample(NamedTuple):
    """Result of ``Lobe.sample``.

    Attributes
    ----------
    wi : ndarray (..., 3)
        Sampled incident direction (unit vector; zero vector where the sample failed).
    weight : ndarray (..., 3)
        ``f(wo, wi) |cos theta_i| / pdf``; for delta samples, the ratio of the delta
        lobe's throughput to its discrete selection probability. 0 where the sample failed.
    pdf : ndarray (...)
        Solid-angle density of ``wi`` (for delta samples: the discrete probability of the
        chosen delta branch). 0 where the sample failed.
    flags : ndarray (...) of int
        ``Flags`` of the sampled branch per element; ``Flags.NONE`` where the sample failed.
    """

    wi: np.ndarray
    weight: np.ndarray
    pdf: np.ndarray
    flags: np.ndarray


class Lobe:
    """Base class of every lobe: public methods validate and broadcast, ``_eval`` etc. compute.

    Subclasses implement ``_eval(wo, wi) -> (..., 3)``, ``_pdf(wo, wi) -> (...)``,
    ``_sample(wo, u) -> BSDFSample`` and ``_albedo_integrand(wo, u2) -> (..., 3)``: the energy
    carried by the sample generated from the two direction uniforms ``u2``, summed over the
    lobe's discrete branches (so that the energy albedo is its integral over the unit square,
    which ``albedo(method="quadrature")`` computes with adaptive cubature).
    Lobes are frozen: the constructor validates and stores parameters only.
    """

    #: union of the flags any sample of this lobe can carry
    flags: Flags = Flags.NONE

    # -- public protocol -------------------------------------------------------------------
    def eval(self, wo, wi) -> np.ndarray:
        """BSDF value f(wo, wi), RGB ``(..., 3)``, without the cosine factor."""
        wo = _params.direction("wo", wo)
        wi = _params.direction("wi", wi)
        return self._eval(wo, wi)

    def pdf(self, wo, wi) -> np.ndarray:
        """Solid-angle density ``(...)`` with which ``sample(wo, u)`` returns ``wi``."""
        wo = _params.direction("wo", wo)
        wi = _params.direction("wi", wi)
        return self._pdf(wo, wi)

    def sample(self, wo, u) -> BSDFSample:
        """Sample ``wi`` given ``wo`` from uniforms ``u`` of shape ``(..., 3)`` in [0, 1)."""
        wo = _params.direction("wo", wo)
        u = _params.uniforms("u", u, 3)
        return self._sample(wo, u)

    def albedo(
        self,
        wo,
        method: str = "quadrature",
        *,
        rtol: float = 1e-9,
        n_samples: int = 100_000,
        rng: np.random.Generator | int | None = 0,
        return_error: bool = False,
    ):
        """Directional energy albedo E(wo) = R + T, RGB ``(..., 3)``.

        Parameters
        ----------
        wo : array_like (..., 3)
        method : {"quadrature", "mc", "table"}
            ``"quadrature"``: adaptive Genz–Malik/Gauss–Kronrod cubature
            (``scipy.integrate.cubature``) of ``_albedo_integrand`` over the lobe's sample
            space ``[0, 1]^2``, to relative tolerance ``rtol``; ``"mc"``: mean of ``n_samples``
            sample weights per direction; ``"table"``: baked tables (where a lobe has them).
        return_error : bool
            Also return the error estimate (quadrature: cubature's estimate; mc: one standard
            error of the mean).
        """
        wo = _params.direction("wo", wo)
        if method == "quadrature":
            value, error = sample_space_albedo(self._albedo_integrand, wo, rtol=rtol)
        elif method == "mc":
            value, error = self._albedo_mc(wo, n_samples, rng)
        elif method == "table":
            value, error = self._albedo_table(wo)
        else:
            raise ValueError(f"method = {method!r} is not one of {ALBEDO_METHODS}")
        return (value, error) if return_error else value

    # -- defaults --------------------------------------------------------------------------
    def _albedo_mc(self, wo, n_samples, rng):
        if not (isinstance(n_samples, (int, np.integer)) and n_samples >= 2):
            raise ValueError(f"n_samples = {n_samples!r} must be an integer in [2, inf)")
        rng = np.random.default_rng(rng)
        batch = wo.shape[:-1]
        u = rng.random((n_samples, *batch, 3))
        wo = np.broadcast_to(wo, u.shape)
        s = self._sample(wo, u)
        weight = s.weight * self._energy_scale(wo, s.wi)[..., None]
        mean = weight.mean(axis=0)
        return mean, weight.std(axis=0, ddof=1) / np.sqrt(n_samples)

    def _energy_scale(self, wo, wi):
        """Factor from radiance to energy: (eta_i / eta_o)^2 across an interface, else 1."""
        return np.ones(np.broadcast_shapes(wo.shape, wi.shape)[:-1])

    def _albedo_table(self, wo):
        raise ValueError(f"method = 'table' is not available for {type(self).__name__}")

    def _eval(self, wo, wi):  # pragma: no cover - abstract
        raise NotImplementedError

    def _pdf(self, wo, wi):  # pragma: no cover - abstract
        raise NotImplementedError

    def _sample(self, wo, u):  # pragma: no cover - abstract
        raise NotImplementedError

    def _albedo_integrand(self, wo, u2):
        """Energy of the sample drawn from ``u2``; lobes with several branches override it."""
        u = np.concatenate([np.zeros(u2.shape[:-1] + (1,)), u2], axis=-1)
        s = self._sample(wo, u)
        return s.weight * self._energy_scale(wo, s.wi)[..., None]
