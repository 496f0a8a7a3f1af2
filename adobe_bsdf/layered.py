"""A stochastic layered BSDF: light followed between two interfaces, through an optional
scattering slab between them. It is the ground truth the albedo-scaling ``Layer`` is measured
against (``docs/layering.md``), slow on purpose.

Public API
----------
``LayeredReference(top, base, thickness=0, medium_albedo=0, g=0, n_samples=64, max_depth=256,
seed=0, phase=None)``
    position-free Monte-Carlo layered BSDF [Guo2018] in the form of pbrt-v4's
    ``LayeredBxDF`` [Pharr2023, §14.3]: ``eval`` and ``pdf`` are unbiased (``eval``) and
    approximate (``pdf``) estimates from random walks, ``sample`` follows one walk.
``MixedReference(parts, weights)``
    patches side by side, for parts that may be random walks.
``UpsideDown(lobe)``, ``TwoSided(lobe)``
    a lobe turned over (the lower face of a sheet), and a structure symmetric about its
    middle plane seen from either side (a thin wall).
``henyey_greenstein(wo, wi, g)``, ``sample_henyey_greenstein(wo, u2, g)``
    the Henyey–Greenstein phase function of the slab [Henyey1941] (from ``phase``).

The layer
---------
``top`` is the upper interface (a ``Dielectric``, rough or smooth, typically), ``base`` the
lower one (any lobe: ``Lambert``, a conductor, a dielectric that transmits out of the
bottom), both in the shading frame (normal +z); between them is a homogeneous slab of optical
thickness ``thickness`` (extinction 1 per unit length, so the transmittance along w is
exp(-thickness / |cos theta|)), single-scattering albedo ``medium_albedo`` and asymmetry g.
Its particles may instead be any ``phase`` object (``adobe_bsdf.phase``), whose extinction
may depend on the direction: a slab of fibre microflakes transmits
exp(-thickness sigma(w) / |cos theta|) along w.
A slab that only absorbs (``medium_albedo`` 0) may have a coloured thickness: a tinted
varnish, whose transmittance along w is exp(-thickness_c / |cos theta|) in each channel c.
Light from below enters through the base: the slab turned over (``LayeredReference.twin``).
"""

from __future__ import annotations

import zlib

import numpy as np

from adobe_bsdf import _params, config
from adobe_bsdf.bsdf import BSDFSample, Flags, Lobe, finished_sample
from adobe_bsdf.composition import _mirrored
from adobe_bsdf.lobes.dielectric import interface_energy_scale
from adobe_bsdf.phase import HenyeyGreenstein, henyey_greenstein, sample_henyey_greenstein

__all__ = ["LayeredReference", "MixedReference", "UpsideDown", "TwoSided", "henyey_greenstein",
           "sample_henyey_greenstein"]

_DELTA, _T = int(Flags.DELTA), int(Flags.TRANSMISSION)
#: the largest density a walk's product of densities reports (near-delta paths saturate)
_PDF_MAX = float(np.finfo(np.float64).max)
#: the share of ``pdf`` that is uniform over the sphere [Pharr2023, §14.3.2]
_UNIFORM_SHARE = 0.1


def _power(a, b):
    """The power heuristic a^2 / (a^2 + b^2) of two densities [Veach1997, §9.2.4]."""
    a2, b2 = a * a, b * b
    return np.where(a2 > 0.0, a2 / np.where(a2 + b2 > 0.0, a2 + b2, 1.0), 0.0)


def _scale_rgb(eta, wo, wi):
    """``interface_energy_scale`` per colour channel ``(..., 3)`` (or broadcasting to it), for
    one index or one per channel (a dispersive interface)."""
    eta = np.asarray(eta)
    if eta.ndim == 0:
        return interface_energy_scale(eta, wo, wi)[..., None]
    return interface_energy_scale(eta, wo[..., None, :], wi[..., None, :])


def _stochastic(lobe: Lobe) -> bool:
    """Whether ``lobe``'s values are Monte-Carlo estimates (a ``LayeredReference``, or a
    structure of them): its sample weight is an unbiased estimate, not f |cos| / pdf."""
    return not lobe.weight_is_ratio


def _draw(lobe: Lobe, wo, u) -> BSDFSample:
    """A sample of ``lobe`` for a walk: its ``_draw`` where it has one (a stochastic lobe:
    the direction and an unbiased weight, without the pdf estimate, which a walk needs only
    for its bookkeeping), else its ``_sample``."""
    draw = getattr(lobe, "_draw", None)
    return lobe._sample(wo, u) if draw is None else draw(wo, u)


#: directions (both sides) and uniforms at which ``_specular`` probes a lobe's sampler
_PROBE_MU = np.array([1.0, 0.7, 0.3, 0.05, -0.05, -0.3, -0.7, -1.0])
_PROBE_U = np.array([[0.1, 0.2, 0.3], [0.5, 0.5, 0.5], [0.9, 0.7, 0.1], [0.99, 0.05, 0.8]])


def _specular(lobe: Lobe) -> bool:
    """Whether every sample of ``lobe`` is a delta (its ``eval`` and ``pdf`` then vanish):
    its flags have no smooth kind, or (a lobe whose class can be either, as a ``Dielectric``
    of roughness 0) its sampler returns deltas only at probe directions on both sides."""
    if not lobe.flags & Flags.DELTA:
        return False
    if not lobe.flags & (Flags.GLOSSY | Flags.DIFFUSE):
        return True
    s = np.sqrt(1.0 - _PROBE_MU**2)
    wo = np.stack([s, np.zeros_like(s), _PROBE_MU], -1)[:, None]
    sample = lobe._sample(np.broadcast_to(wo, (len(wo), len(_PROBE_U), 3)).reshape(-1, 3),
                          np.tile(_PROBE_U, (len(wo), 1)))
    made = sample.flags != int(Flags.NONE)
    return bool(np.all((sample.flags[made] & int(Flags.DELTA)) != 0))


class _Walks:
    """The state of a batch of random walks: each one's row in the caller's arrays (``pair``),
    its throughput, direction of travel and height in the slab; ``keep`` drops the walks that
    ended."""

    def __init__(self, pair, beta, w, z):
        self.pair, self.beta, self.w, self.z = pair, beta, w, z

    def keep(self, mask):
        self.pair, self.beta, self.w, self.z = (a[mask] for a in (self.pair, self.beta, self.w,
                                                                   self.z))

    def __len__(self):
        return len(self.pair)

    def roulette(self, rng):
        """Russian roulette [Pharr2023, §14.3.2]: where max beta < 1/4 a walk ends with
        probability q = 1 - max beta and a survivor's beta grows by 1 / (1 - q). Returns the
        survivors' mask and q (the walks are not dropped yet)."""
        m = self.beta.max(-1)
        q = np.where(m < 0.25, np.maximum(0.0, 1.0 - m), 0.0)
        survive = rng.random(len(self)) >= q
        self.beta = self.beta / np.where(survive, 1.0 - q, 1.0)[:, None]
        return survive, q

    def flight(self, rng, thickness, phase):
        """A free flight of extinction ``phase.sigma(w)`` along w: ``(zp, inside, stuck)``,
        the height reached, whether it is inside the slab (a scattering event) and whether the
        flight was too short to move."""
        with np.errstate(divide="ignore"):
            dz = -np.log1p(-rng.random(len(self))) * np.abs(self.w[:, 2]) / phase.sigma(self.w)
        zp = np.where(self.w[:, 2] > 0.0, self.z + dz, self.z - dz)
        return zp, (zp > 0.0) & (zp < thickness), zp == self.z


class _RandomWalks(Lobe):
    """What a lobe of random walks shares: scalar parameters; its sample weight an unbiased
    estimate, not f |cos| / pdf of its estimates; the energy scale of the index ``eta`` of
    what it transmits through (one per channel for a dispersive interface); no quadrature of
    its estimated ``eval``."""

    #: its sample weight is one walk's estimate, not f |cos| / pdf of its estimates
    weight_is_ratio = False

    def _param_shape(self):
        return ()

    def _energy_scale(self, wo, wi):
        if self.eta is None or np.ndim(self.eta):
            return super()._energy_scale(wo, wi)
        return interface_energy_scale(self.eta, wo, wi)

    def _energy_scale_rgb(self, wo, wi):
        if self.eta is None:
            return super()._energy_scale_rgb(wo, wi)
        return _scale_rgb(self.eta, wo, wi)

    def _albedo_quadrature(self, wo, tol):
        raise ValueError("method = 'quadrature' integrates eval, which is a Monte-Carlo "
                         f"estimate for a {type(self).__name__}; use albedo(method='mc')")

    def _estimated(self, batch, wo, s: BSDFSample, pdf) -> BSDFSample:
        """The flat sample ``s`` with ``pdf`` (a delta sample's), the non-delta samples'
        replaced by the estimate ``_pdf``, shaped to ``batch``."""
        smooth = np.flatnonzero((s.flags != 0) & ((s.flags & _DELTA) == 0))
        if len(smooth):
            pdf[smooth] = self._pdf(wo[smooth], s.wi[smooth])
        s = finished_sample(s.wi, s.weight, pdf, s.flags)
        return BSDFSample(*(a.reshape(batch + a.shape[1:]) for a in s))


class LayeredReference(_RandomWalks):
    """``top`` over ``base`` with the light followed between them (module docstring): the
    position-free Monte-Carlo layered BSDF of [Guo2018] as [Pharr2023, §14.3] writes it.

    ``eval(wo, wi)`` averages ``n_samples`` random walks per pair: each enters through the
    top (a sample of its transmission), bounces between the interfaces and through the slab
    (free flights of the extinction, scattering by the phase function, Russian roulette after 4
    bounces where the throughput is below 1/4), and at every vertex connects to ``wi``
    through the exit interface (next-event estimation) by two strategies, a sample of the exit
    from ``wi`` and a sample of the vertex, weighed by the power heuristic. It is unbiased
    up to the walks cut at ``max_depth`` bounces; ``eval_with_error`` gives its standard
    error. Reflection by the top alone, f_top(wo, wi), is added exactly.

    ``sample`` follows one walk from ``wo`` until it leaves the layer: its weight is an
    unbiased estimate of f |cos| / pdf (the walk's product of interface weights), its ``pdf``
    the estimate of ``pdf``. ``pdf`` is pbrt-v4's estimate: the top's reflection density
    plus, per walk, the density of the paths that cross the slab once each way (TRT) or
    once (TT), mixed with 1/(4 pi) (a tenth): positive wherever ``eval`` can be, not the exact
    density of ``sample``. The random numbers of a call are seeded by ``seed`` and the
    directions' bytes: the same call gives the same result.

    Parameters
    ----------
    top, base : Lobe, with scalar parameters
    thickness : float in [0, inf), or a colour where ``medium_albedo`` is 0
        Optical thickness of the slab (per channel: an absorbing slab's).
    medium_albedo : colour in [0, 1]
        Single-scattering albedo of the slab (0: it only absorbs, exp(-thickness / |cos|)).
    g : float in (-1, 1)
        Henyey–Greenstein asymmetry of the slab's scattering.
    phase : a phase object (``adobe_bsdf.phase``), or None for ``HenyeyGreenstein(g)``
        The slab's particles; with one, ``g`` stays 0.
    n_samples : int >= 1
        Walks per evaluated pair (``eval``, ``pdf``).
    max_depth : int >= 1
        Bounces after which a walk stops.
    seed : int >= 0
    """

    def __init__(self, top: Lobe, base: Lobe, thickness=0.0, medium_albedo=0.0, g=0.0,
                 n_samples: int = 64, max_depth: int = 256, seed: int = 0, phase=None):
        for name, lobe in (("top", top), ("base", base)):
            if not isinstance(lobe, Lobe):
                raise ValueError(f"{name} = {lobe!r}: a LayeredReference takes two lobes")
            if lobe._param_shape() != ():
                raise ValueError(f"{name} = {lobe!r} has parameters of shape "
                                 f"{lobe._param_shape()}; allowed: scalar parameters")
        albedo = _params.color("medium_albedo", medium_albedo, 0.0, 1.0)
        tau = _params.color("thickness", thickness, 0.0, np.inf)
        for name, value in (("medium_albedo", albedo), ("thickness", tau)):
            if value.ndim > 1:
                raise ValueError(f"{name} has shape {value.shape}; allowed: a single "
                                 "colour, () or (3,)")
        if not np.all(np.isfinite(tau)):
            raise ValueError(f"thickness = {thickness!r} is not finite; allowed: [0, inf)")
        if np.any(tau != tau[0]) and np.any(albedo > 0.0):
            raise ValueError(f"thickness = {thickness!r} is a colour; allowed: a colour only "
                             f"where the slab does not scatter (medium_albedo = {medium_albedo!r}"
                             " is not 0)")
        self.top, self.base = top, base
        #: the optical thickness per channel, and the slab's height (the largest of them)
        self._tau = tau
        self.thickness = float(tau[0]) if np.all(tau == tau[0]) else tau
        self._height = float(tau.max())
        self.medium_albedo = np.broadcast_to(albedo, (3,))
        self.g = _params.scalar("g", g, -1.0, 1.0, lo_open=True, hi_open=True)
        if phase is None:
            phase = HenyeyGreenstein(self.g)
        elif not all(callable(getattr(phase, k, None)) for k in ("sigma", "eval", "sample")):
            raise ValueError(f"phase = {phase!r}: allowed: None or a phase object with sigma, "
                             "eval and sample (adobe_bsdf.phase)")
        elif self.g != 0.0:
            raise ValueError(f"g = {g!r} with phase = {phase!r}; allowed: g = 0 where a phase "
                             "object is given (it carries its own asymmetry)")
        self.phase = phase
        self.n_samples = _params.integer("n_samples", n_samples, 1)
        self.max_depth = _params.integer("max_depth", max_depth, 1)
        self.seed = _params.integer("seed", seed, 0)
        #: whether the interfaces are smooth (every sample a delta)
        self._top_smooth, self._base_smooth = _specular(top), _specular(base)
        #: whether every path is a delta (smooth interfaces, no scattering): eval is 0
        self._all_delta = self._top_smooth and self._base_smooth and not self._scatters
        flags = Flags.REFLECTION
        if base.flags & Flags.TRANSMISSION:
            flags |= Flags.TRANSMISSION
        if top.flags & Flags.DELTA or self._all_delta:
            flags |= Flags.DELTA
        if not self._all_delta:
            flags |= Flags.GLOSSY
        self.flags = flags

    def __repr__(self) -> str:
        thickness = np.asarray(self.thickness).tolist()
        return (f"LayeredReference({self.top!r}, {self.base!r}, thickness={thickness}, "
                f"medium_albedo={self.medium_albedo.tolist()}, phase={self.phase!r}, "
                f"n_samples={self.n_samples})")

    @property
    def _scatters(self) -> bool:
        """Whether the slab scatters (else it only absorbs, or is empty)."""
        return self._height > 0.0 and bool(np.any(self.medium_albedo > 0.0))

    @property
    def eta(self):
        """n below the base / n above the top, where the base transmits; else None."""
        if self.top.eta is None or self.base.eta is None:
            return None
        return self.top.eta * self.base.eta

    def _rng(self, *arrays) -> np.random.Generator:
        """The generator of one call: ``seed`` and a checksum of its arguments."""
        return np.random.default_rng(
            [self.seed] + [zlib.crc32(np.ascontiguousarray(a).tobytes()) for a in arrays])

    @property
    def twin(self) -> LayeredReference:
        """The same slab turned over, its base on top: light entering this one from below
        is the twin's entering from above, f(wo, wi) = twin.f(M wo, M wi), M = diag(1, 1, -1)
        (the phase functions here are symmetric under M)."""
        key = (self.n_samples, self.max_depth, self.seed)
        if getattr(self, "_twin_key", None) != key:
            self._twin = LayeredReference(
                UpsideDown(self.base), UpsideDown(self.top), thickness=self._tau,
                medium_albedo=self.medium_albedo, g=self.g, n_samples=self.n_samples,
                max_depth=self.max_depth, seed=self.seed,
                phase=None if isinstance(self.phase, HenyeyGreenstein) else self.phase)
            self._twin_key = key
        return self._twin

    def _transmittance(self, dz, w):
        """exp(-|dz| sigma(w) / |cos theta|) along ``w`` (0 in the tangent plane),
        ``(..., 1)``."""
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.exp(-np.abs(dz) * self.phase.sigma(w) / np.abs(w[..., 2]))
        return np.where(np.isnan(t), 0.0, t)[..., None]  # 0 sigma / 0 cosine: blocked

    def _crossing(self, w):
        """exp(-thickness_c sigma(w) / |cos theta|) of a crossing of the whole slab along
        ``w``, per channel ``(..., 3)`` (0 in the tangent plane)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.exp(-self._tau * (self.phase.sigma(w) / np.abs(w[..., 2]))[..., None])
        return np.where(np.isnan(t), 0.0, t)

    @staticmethod
    def _flat(a, b):
        """``(batch, a, b)``: two arrays ``(..., 3)`` broadcast together, flattened to
        ``(n, 3)``."""
        batch = np.broadcast_shapes(a.shape, b.shape)[:-1]
        return (batch, *(np.broadcast_to(x, batch + (3,)).reshape(-1, 3) for x in (a, b)))

    def _exit_blocks(self, wo, wi, sides=(True, False)):
        """``(exits_top, index)``: the pairs entering through the top whose ``wi`` leaves
        through the top (True) or the base (False), for each of ``sides``, in ``_blocks``."""
        entering = wo[:, 2] > 0.0
        for exits_top in sides:
            chosen = np.flatnonzero(entering & ((wi[:, 2] > 0.0) == exits_top)
                                    & (wi[:, 2] != 0.0))
            for a, b in self._blocks(len(chosen)):
                yield exits_top, chosen[a:b]

    def _blocks(self, n):
        """Ranges of pairs whose walks fit in about ``config`` ``chunk_size`` elements."""
        step = max(1, config.get_options().chunk_size // self.n_samples)
        return [(a, min(a + step, n)) for a in range(0, n, step)]

    # -- eval -------------------------------------------------------------------------------
    def eval_with_error(self, wo, wi) -> tuple[np.ndarray, np.ndarray]:
        """``(eval(wo, wi), standard error)``, RGB ``(..., 3)`` each."""
        return self._batched(self._eval_error, (
            (_params.direction_shape("wo", wo), lambda a: _params.check_unit("wo", a)),
            (_params.direction_shape("wi", wi), lambda a: _params.check_unit("wi", a))))

    def _eval(self, wo, wi):
        return self._eval_error(wo, wi)[0]

    def _eval_error(self, wo, wi):
        batch, wo, wi = self._flat(wo, wi)
        rng = self._rng(wo, wi)
        f = np.zeros((len(wo), 3))
        err = np.zeros((len(wo), 3))
        below = np.flatnonzero(wo[:, 2] < 0.0)
        if len(below):
            f[below], err[below] = self.twin._eval_error(_mirrored(wo[below]), _mirrored(wi[below]))
        blocks = list(self._exit_blocks(wo, wi))
        for exits_top, index in config.progress(blocks, len(blocks), "LayeredReference.eval"):
            f[index], err[index] = self._walk_eval(wo[index], wi[index], exits_top, rng)
        up = np.flatnonzero((wo[:, 2] > 0.0) & (wi[:, 2] > 0.0))
        if len(up):
            f[up] += self.top._eval(wo[up], wi[up])
        return f.reshape(batch + (3,)), err.reshape(batch + (3,))

    def _walk_eval(self, wo, wi, exits_top: bool, rng):
        """Mean and standard error ``(n, 3)`` of ``n_samples`` walks per pair whose ``wi`` leaves
        through the top (``exits_top``) or the base: [Pharr2023, §14.3.2]'s
        ``LayeredBxDF::f`` entered through the top."""
        n, S = len(wo), self.n_samples
        exit_, other = (self.top, self.base) if exits_top else (self.base, self.top)
        exit_z = self._height if exits_top else 0.0
        top_z = self._height
        pair = np.repeat(np.arange(n), S)
        wo_w, wi_w = wo[pair], wi[pair]
        contribution = np.zeros((n * S, 3))
        # the way in: a transmission sample of the top from wo
        s = _draw(self.top, wo_w, rng.random((n * S, 3)))
        # the way out: a transmission sample of the exit from wi (light's direction, adjoint)
        x = _draw(exit_, wi_w, rng.random((n * S, 3)))
        x_w = x.weight * exit_._energy_scale_rgb(wi_w, x.wi)  # f(x.wi, wi) |cos| / pdf
        with np.errstate(divide="ignore", invalid="ignore"):
            x_f = x_w / np.abs(x.wi[:, 2:3])  # f(x.wi, wi) / pdf: a slab vertex has no cosine
        # a walk goes on whatever x: only the next events along x need it (a reflected x
        # weighs 0; conditioning the walk on x would bias the other strategy)
        x_ok = (x.pdf > 0.0) & (x.wi[:, 2] * wi_w[:, 2] < 0.0)
        x_w, x_f = (np.where(x_ok[:, None], a, 0.0) for a in (x_w, x_f))
        idx = np.flatnonzero((s.pdf > 0.0) & (s.wi[:, 2] < 0.0))
        walks = _Walks(idx, s.weight[idx], s.wi[idx], np.full(len(idx), top_z))
        into = np.zeros_like(wi_w)
        into[:, 2] = -np.sign(wi_w[:, 2])  # a stand-in direction where x failed (weight 0)
        x_wi, x_pdf = np.where(x_ok[:, None], x.wi, into), np.where(x_ok, x.pdf, 0.0)
        x_delta = (x.flags & _DELTA) != 0
        exit_smooth, other_smooth = ((self._top_smooth, self._base_smooth) if exits_top else
                                      (self._base_smooth, self._top_smooth))
        # a stochastic lobe's densities are estimates, which would not weigh the two
        # strategies consistently: next events then take the exit sample alone (weight 1)
        exit_only = _stochastic(exit_) or _stochastic(other)
        if not exits_top:  # the entry is the first vertex that connects to the exit
            self._entry_events(wo_w, wi_w, s, idx, x_wi, x_w, x_pdf, x_delta, exit_only,
                               contribution)
        albedo = self.medium_albedo
        for depth in range(self.max_depth):
            if not len(walks):
                break
            if depth > 3:
                walks.keep(walks.roulette(rng)[0])
            walks.keep(walks.w[:, 2] != 0.0)
            if not len(walks):
                break
            k = walks.pair
            if self._scatters:
                zp, inside, stuck = walks.flight(rng, self._height, self.phase)
                if np.any(inside):
                    j = np.flatnonzero(inside)
                    kj, w, beta = k[j], walks.w[j], walks.beta[j]
                    # next event through the exit along the presampled direction
                    p = self.phase.eval(-w, -x_wi[kj])
                    wt = np.where(x_delta[kj] | _stochastic(exit_), 1.0, _power(x_pdf[kj], p))
                    np.add.at(contribution, kj, beta * albedo * (p * wt)[:, None]
                              * self._transmittance(zp[j] - exit_z, x_wi[kj]) * x_f[kj])
                    w_new, p_new = self.phase.sample(-w, rng.random((len(j), 2)))
                    beta = beta * albedo * (p_new > 0.0)[:, None]  # p / pdf = 1
                    if not (exit_smooth or _stochastic(exit_)):
                        h = np.flatnonzero((w_new[:, 2] > 0.0) == exits_top)  # to the exit
                        if len(h):
                            kh = kj[h]
                            f_exit = exit_._eval(-w_new[h], wi_w[kh])
                            exit_pdf = exit_._pdf(wi_w[kh], -w_new[h])
                            wt = _power(p_new[h], exit_pdf)
                            np.add.at(contribution, kh,
                                      beta[h] * self._transmittance(zp[j][h] - exit_z, w_new[h])
                                      * f_exit * wt[:, None])
                    walks.beta[j], walks.w[j], walks.z[j] = beta, w_new, zp[j]
                walks.z = np.where(inside, walks.z, np.clip(zp, 0.0, self._height))
                at = ~inside & ~stuck
            else:
                walks.z = np.where(walks.w[:, 2] > 0.0, top_z, 0.0)
                walks.beta = walks.beta * self._crossing(walks.w)
                at = np.ones(len(walks), dtype=bool)
            # scattering by the interface reached: the top going up, the base going down
            at_exit = at & ((walks.w[:, 2] > 0.0) == exits_top)
            at_other = at & ~at_exit
            alive = ~at  # walks scattered in the slab go on
            for mask, lobe, is_other in ((at_exit, exit_, False), (at_other, other, True)):
                j = np.flatnonzero(mask)
                if not len(j):
                    continue
                kj, w, beta = k[j], walks.w[j], walks.beta[j]
                if is_other and not other_smooth:  # next event along the presampled wi
                    if exit_only:
                        f_o, wt = other._eval(-w, -x_wi[kj]), np.ones(len(j))
                    else:
                        f_o, p_o = other._eval_pdf(-w, -x_wi[kj])
                        wt = np.where(x_delta[kj], 1.0, _power(x_pdf[kj], p_o))
                    np.add.at(contribution, kj, beta * f_o * wt[:, None]
                              * self._crossing(x_wi[kj]) * x_w[kj])
                bs = _draw(lobe, -w, rng.random((len(j), 3)))
                back = (bs.pdf > 0.0) & (bs.wi[:, 2] * w[:, 2] < 0.0)  # reflected, not out
                beta = beta * bs.weight
                # next event along bs.wi: where the exit is rough and either both densities
                # are exact or the other interface is smooth (then the only strategy)
                if is_other and not exit_smooth and (other_smooth or not exit_only):
                    h = np.flatnonzero(back)
                    if len(h):
                        kh, w_new = kj[h], bs.wi[h]
                        f_exit = exit_._eval(-w_new, wi_w[kh])
                        wt = np.ones(len(h)) if other_smooth else _power(
                            bs.pdf[h], exit_._pdf(wi_w[kh], -w_new))
                        wt = np.where((bs.flags[h] & _DELTA) != 0, 1.0, wt)
                        np.add.at(contribution, kh, beta[h] * f_exit * wt[:, None]
                                  * self._crossing(w_new))
                walks.beta[j], walks.w[j] = beta, bs.wi
                alive[j] = back
            walks.keep(alive & np.all(np.isfinite(walks.beta), -1))
        c = contribution.reshape(n, S, 3)
        mean = c.mean(1)
        se = c.std(1, ddof=1) / np.sqrt(S) if S > 1 else np.zeros_like(mean)
        return mean, se

    def _entry_events(self, wo, wi, s, idx, x_wi, x_w, x_pdf, x_delta, exit_only, out):
        """Adds to ``out`` the paths that cross the slab once, from the top to the exit in the
        base (T T, attenuated by one crossing): by the exit's sample from ``wi`` (x), where
        the top is rough, and by the top's sample from ``wo`` (s, the walks' first step,
        rows ``idx``), where the exit is rough, weighed by the power heuristic where both
        densities are exact (else the one strategy that applies, or x's)."""
        top, exit_ = self.top, self.base
        if not self._top_smooth:
            wt = np.ones(len(wo))
            if not exit_only:
                wt = np.where(x_delta, 1.0, _power(x_pdf, top._pdf(wo, -x_wi)))
            out += top._eval(wo, -x_wi) * wt[:, None] * self._crossing(x_wi) * x_w
        if not self._base_smooth and (self._top_smooth or not exit_only) and len(idx):
            w_new = s.wi[idx]
            wt = np.ones(len(idx)) if self._top_smooth else _power(
                s.pdf[idx], exit_._pdf(wi[idx], -w_new))
            wt = np.where((s.flags[idx] & _DELTA) != 0, 1.0, wt)
            out[idx] += (s.weight[idx] * exit_._eval(-w_new, wi[idx]) * wt[:, None]
                         * self._crossing(w_new))

    # -- pdf --------------------------------------------------------------------------------
    def _pdf(self, wo, wi):
        batch, wo, wi = self._flat(wo, wi)
        rng = self._rng(wo, wi, np.array([1]))
        pdf = np.zeros(len(wo))
        sides = (True, False) if self.base.flags & Flags.TRANSMISSION else (True,)
        for exits_top, index in self._exit_blocks(wo, wi, sides):
            estimate = self._walk_pdf(wo[index], wi[index], exits_top, rng)
            if exits_top:
                estimate = estimate + self.top._pdf(wo[index], wi[index])
            pdf[index] = _UNIFORM_SHARE / (4.0 * np.pi) + (1.0 - _UNIFORM_SHARE) * estimate
        below = np.flatnonzero(wo[:, 2] < 0.0)
        if len(below):
            pdf[below] = self.twin._pdf(_mirrored(wo[below]), _mirrored(wi[below]))
        return pdf.reshape(batch)

    def _eval_pdf(self, wo, wi):
        return self._eval(wo, wi), self._pdf(wo, wi)

    def _walk_pdf(self, wo, wi, exits_top: bool, rng):
        """pbrt-v4's ``LayeredBxDF::PDF`` estimate of the paths through the slab, ``(n,)``."""
        n, S = len(wo), self.n_samples
        pair = np.repeat(np.arange(n), S)
        wo_w, wi_w = wo[pair], wi[pair]
        top, base = self.top, self.base
        s = _draw(top, wo_w, rng.random((n * S, 3)))
        total = np.zeros(n * S)
        if exits_top:  # top-base-top
            x = _draw(top, wi_w, rng.random((n * S, 3)))
            ok = (s.pdf > 0) & (s.wi[:, 2] < 0) & (x.pdf > 0) & (x.wi[:, 2] < 0)
            j = np.flatnonzero(ok)
            a, b = -s.wi[j], -x.wi[j]
            if self._top_smooth:
                total[j] = base._pdf(a, b)
            else:
                r = _draw(base, a, rng.random((len(j), 3)))
                good = (r.pdf > 0) & (r.wi[:, 2] > 0)
                t_pdf = top._pdf(-r.wi, wi_w[j])
                if self._base_smooth:
                    total[j] = np.where(good, t_pdf, 0.0)
                else:
                    r_pdf = base._pdf(a, b)
                    total[j] = np.where(good, _power(x.pdf[j], r_pdf) * r_pdf
                                        + _power(r.pdf, t_pdf) * t_pdf, 0.0)
        else:  # top-base, out of the bottom
            x = _draw(base, wi_w, rng.random((n * S, 3)))
            ok = (s.pdf > 0) & (s.wi[:, 2] < 0) & (x.pdf > 0) & (x.wi[:, 2] > 0)
            j = np.flatnonzero(ok)
            if self._top_smooth:
                total[j] = base._pdf(-s.wi[j], wi_w[j])
            elif self._base_smooth:
                total[j] = top._pdf(wo_w[j], -x.wi[j])
            else:
                total[j] = 0.5 * (top._pdf(wo_w[j], -x.wi[j]) + base._pdf(-s.wi[j], wi_w[j]))
        return total.reshape(n, S).mean(1)

    # -- sample -----------------------------------------------------------------------------
    def _sample(self, wo, u):
        batch, wo, s = self._walked(wo, u)
        return self._estimated(batch, wo, s, s.pdf.copy())

    def walk(self, wo, u) -> BSDFSample:
        """``sample`` without its ``pdf`` estimate: the same walks, directions and weights (an
        unbiased estimate of f |cos| / pdf, for Monte-Carlo energies), with ``pdf`` the product
        of the interfaces' densities along the walk (the discrete probability of a delta
        path). Cheaper than ``sample`` by the ``n_samples`` walks of each estimate."""
        return self._batched(self._draw, (
            (_params.direction_shape("wo", wo), lambda a: _params.check_unit("wo", a)),
            (_params.uniforms_shape("u", u, 3), lambda a: _params.check_uniform("u", a))))

    def _draw(self, wo, u) -> BSDFSample:
        """``walk`` of validated arrays: how an enclosing walk, a mixture of walks or the
        Monte-Carlo albedo samples this one."""
        batch, _, s = self._walked(wo, u)
        return BSDFSample(*(a.reshape(batch + a.shape[1:]) for a in s))

    def _walked(self, wo, u):
        """``(batch, wo (n, 3), BSDFSample (n, ...))`` of ``_walk_sample`` on the flattened
        batch, failed walks zeroed."""
        batch, wo, u = self._flat(wo, u)
        return batch, wo, finished_sample(*self._walk_sample(wo, u))

    def _walk_sample(self, wo, u):
        """``(wi, weight, pdf, flags)`` of one walk per ``wo`` [Pharr2023, §14.3.2]'s
        ``LayeredBxDF::Sample_f``; ``pdf`` is the product of the interfaces' densities (the
        discrete probability of a delta path). A ``wo`` below enters through the base
        (``twin``)."""
        below = np.flatnonzero(wo[:, 2] < 0.0)
        if len(below):
            out = self._walk_sample_above(wo, u)
            twin = self.twin._walk_sample_above(_mirrored(wo[below]), u[below])
            for a, b in zip(out, twin, strict=True):
                a[below] = b
            out[0][below] = _mirrored(out[0][below])
            return out
        return self._walk_sample_above(wo, u)

    def _walk_sample_above(self, wo, u, arrivals=None):
        """``_walk_sample`` of walks entering through the top (0 where ``wo`` is below);
        ``arrivals(rows, beta, w)``, if given, is told of every arrival at the base from
        above (the walks' rows in ``wo``, their throughputs and directions of travel)."""
        rng = self._rng(wo, u)
        s = _draw(self.top, wo, u)
        wi, weight, pdf, flags = s.wi.copy(), s.weight.copy(), s.pdf.copy(), s.flags.copy()
        through = (s.pdf > 0.0) & (s.wi[:, 2] < 0.0) & (wo[:, 2] > 0.0)
        wi[through], weight[through], pdf[through], flags[through] = 0.0, 0.0, 0.0, 0
        flags[wo[:, 2] <= 0.0] = 0
        idx = np.flatnonzero(through)
        walks = _Walks(idx, s.weight[idx], s.wi[idx], np.full(len(idx), self._height))
        path_pdf = s.pdf[idx]
        delta = (s.flags[idx] & _DELTA) != 0
        albedo = self.medium_albedo
        for depth in range(self.max_depth):
            if not len(walks):
                break
            if depth > 3:
                survive, q = walks.roulette(rng)
                path_pdf = (path_pdf * (1.0 - q))[survive]
                delta = delta[survive]
                walks.keep(survive)
            moving = walks.w[:, 2] != 0.0
            path_pdf, delta = path_pdf[moving], delta[moving]
            walks.keep(moving)
            if not len(walks):
                break
            if self._scatters:
                zp, inside, stuck = walks.flight(rng, self._height, self.phase)
                j = np.flatnonzero(inside)
                if len(j):
                    w_new, p_new = self.phase.sample(-walks.w[j], rng.random((len(j), 2)))
                    walks.beta[j] = walks.beta[j] * albedo * (p_new > 0.0)[:, None]
                    walks.w[j] = w_new
                    with np.errstate(over="ignore"):
                        path_pdf[j] = np.minimum(path_pdf[j] * p_new, _PDF_MAX)
                    delta[j] = False
                walks.z = np.where(inside, zp, np.clip(zp, 0.0, self._height))
                at = ~inside & ~stuck
            else:
                walks.z = np.where(walks.w[:, 2] > 0.0, self._height, 0.0)
                walks.beta = walks.beta * self._crossing(walks.w)
                at = np.ones(len(walks), dtype=bool)
            alive = ~at
            up = walks.w[:, 2] > 0.0  # the interface reached: the top going up
            for mask, lobe in ((at & up, self.top), (at & ~up, self.base)):
                j = np.flatnonzero(mask)
                if not len(j):
                    continue
                w = walks.w[j]
                if arrivals is not None and lobe is self.base:
                    arrivals(walks.pair[j], walks.beta[j], w)
                bs = _draw(lobe, -w, rng.random((len(j), 3)))
                good = bs.pdf > 0.0
                out = good & (bs.wi[:, 2] * w[:, 2] > 0.0)  # transmitted: out of the layer
                beta = walks.beta[j] * bs.weight
                with np.errstate(over="ignore"):  # a near-delta path's density saturates
                    p = np.minimum(path_pdf[j] * bs.pdf, _PDF_MAX)
                d = delta[j] & ((bs.flags & _DELTA) != 0)
                o = np.flatnonzero(out)
                if len(o):
                    e = walks.pair[j[o]]
                    wi[e], weight[e], pdf[e] = bs.wi[o], beta[o], p[o]
                    side = np.where(bs.wi[o][:, 2] > 0.0, int(Flags.REFLECTION), _T)
                    flags[e] = side | np.where(d[o], _DELTA, int(Flags.GLOSSY))
                walks.beta[j], walks.w[j] = beta, bs.wi
                path_pdf[j], delta[j] = p, d
                alive[j] = good & ~out
            keep = alive & np.all(np.isfinite(walks.beta), -1)
            path_pdf, delta = path_pdf[keep], delta[keep]
            walks.keep(keep)
        return wi, weight, pdf, flags

    def emitted(self, wo, below) -> np.ndarray:
        """One walk per direction ``wo`` ``(n, 3)`` (above): an unbiased estimate ``(n, 3)`` of
        the radiance the layer sends towards ``wo`` where its base emits radiance
        ``below(w)`` ``(m, 3)`` towards every upward direction w: the sum, over the walk's
        arrivals at the base from above, of its throughput times ``below`` of the direction
        back up (the walk from ``wo`` is the light's path reversed, its throughput the
        radiance carried [Veach1997, §3.7])."""
        total = np.zeros((len(wo), 3))

        def arrive(rows, beta, w):
            np.add.at(total, rows, beta * below(-w))
        u = self._rng(wo, np.array([2])).random((len(wo), 3))
        self._walk_sample_above(wo, u, arrivals=arrive)
        return total

    # -- energy -----------------------------------------------------------------------------
    def _delta_albedo(self, wo):
        """The energy of the delta walks (the top's mirror reflection; where every path can be
        a delta, those through the slab too), from ``n_samples`` walks per direction."""
        flat = wo.reshape(-1, 3)
        E = np.zeros((len(flat), 3))
        below = flat[:, 2] < 0.0
        if np.any(below):  # entering through the base
            E[below] = self.twin._delta_albedo(_mirrored(flat[below]))
        above = np.flatnonzero(~below) if self.flags & Flags.DELTA else np.zeros(0, int)
        for a, b in self._blocks(len(above)):
            w = np.repeat(flat[above[a:b]], self.n_samples, axis=0)
            wi, weight, _, flags = self._walk_sample(w, self._rng(w).random((len(w), 3)))
            energy = weight * self._energy_scale_rgb(w, wi)
            energy = np.where(((flags & _DELTA) != 0)[:, None], energy, 0.0)
            E[above[a:b]] = energy.reshape(-1, self.n_samples, 3).mean(1)
        return E.reshape(wo.shape[:-1] + (3,))




class MixedReference(_RandomWalks):
    """Patches side by side [Andersson2023, §Mixing], for parts that may be random walks:

        f = sum_k w_k f_k,   weights w_k > 0 summing to 1.

    ``eval`` and ``pdf`` are the weighted sums of the parts' (their estimates where they are
    ``LayeredReference``s; ``eval_with_error`` combines the standard errors). ``sample``
    picks part k with probability w_k (the first uniform, rescaled) and keeps its sample:
    its weight is then an unbiased estimate of f |cos| / pdf of the mixture, as a walk's is;
    its ``pdf`` is the mixture's, sum_k w_k pdf_k (w_k pdf_k for a delta sample). The
    composition of ``composition.Mix`` instead weighs every sample by f / pdf of all the
    parts, which for random walks would cost an estimate of each.

    Parameters
    ----------
    parts : sequence of Lobe, with scalar parameters
    weights : sequence of float in (0, 1], summing to 1
    """

    def __init__(self, parts, weights):
        parts, weights = list(parts), np.asarray(weights, dtype=np.float64)
        if not parts or weights.shape != (len(parts),):
            raise ValueError(f"weights = {weights.tolist()!r}: allowed one weight per part "
                             f"({len(parts)} parts)")
        for k, lobe in enumerate(parts):
            if not isinstance(lobe, Lobe) or lobe._param_shape() != ():
                raise ValueError(f"parts[{k}] = {lobe!r}: allowed a lobe with scalar "
                                 "parameters")
        if (not np.all((weights > 0.0) & (weights <= 1.0))
                or abs(weights.sum() - 1.0) > 1e-12):
            raise ValueError(f"weights = {weights.tolist()!r}: allowed weights in (0, 1] "
                             "summing to 1")
        self.parts, self.weights = parts, weights
        self._edges = np.concatenate([[0.0], np.cumsum(weights)[:-1]])
        flags = Flags.NONE
        for lobe in parts:
            flags |= lobe.flags
        self.flags = flags

    def __repr__(self) -> str:
        return f"MixedReference({self.parts!r}, {self.weights.tolist()!r})"

    @property
    def eta(self):
        """The index of the parts that transmit (they share it), else None."""
        return next((lobe.eta for lobe in self.parts if lobe.eta is not None), None)

    def _sum(self, method, *args):
        parts = zip(self.weights, self.parts, strict=True)
        return sum(w * getattr(lobe, method)(*args) for w, lobe in config.progress(
            parts, len(self.parts), f"MixedReference.{method.strip('_')}"))

    def _eval(self, wo, wi):
        return self._sum("_eval", wo, wi)

    def eval_with_error(self, wo, wi) -> tuple[np.ndarray, np.ndarray]:
        """``(eval(wo, wi), standard error)``, RGB ``(..., 3)`` each; a part without
        ``eval_with_error`` is exact."""
        f, var = 0.0, 0.0
        for w, lobe in zip(self.weights, self.parts, strict=True):
            if hasattr(lobe, "eval_with_error"):
                fk, ek = lobe.eval_with_error(wo, wi)
            else:
                fk = lobe.eval(wo, wi)
                ek = np.zeros_like(fk)
            f, var = f + w * fk, var + (w * ek) ** 2
        return f, np.sqrt(var)

    def _pdf(self, wo, wi):
        return self._sum("_pdf", wo, wi)

    def _eval_pdf(self, wo, wi):
        return self._eval(wo, wi), self._pdf(wo, wi)

    def _delta_albedo(self, wo):
        return self._sum("_delta_albedo", wo)

    def _picked(self, wo, u, draw: bool):
        """Part k's sample (``_draw`` or ``_sample``) for each element, k drawn by u_0."""
        batch = np.broadcast_shapes(wo.shape, u.shape)[:-1]
        wo = np.broadcast_to(wo, batch + (3,)).reshape(-1, 3)
        u = np.broadcast_to(u, batch + (3,)).reshape(-1, 3).copy()
        k = np.searchsorted(self._edges, u[:, 0], side="right") - 1
        u[:, 0] = np.clip((u[:, 0] - self._edges[k]) / self.weights[k], 0.0, np.nextafter(1, 0))
        wi, weight = np.zeros_like(wo), np.zeros_like(wo)
        pdf, flags = np.zeros(len(wo)), np.zeros(len(wo), dtype=np.int64)
        for j, lobe in enumerate(self.parts):
            idx = np.flatnonzero(k == j)
            if len(idx):
                s = _draw(lobe, wo[idx], u[idx]) if draw else lobe._sample(wo[idx], u[idx])
                wi[idx], weight[idx], pdf[idx], flags[idx] = s.wi, s.weight, s.pdf, s.flags
        return batch, wo, k, BSDFSample(wi, weight, pdf, flags)

    def _sample(self, wo, u):
        batch, wo, k, s = self._picked(wo, u, draw=False)
        return self._estimated(batch, wo, s, self.weights[k] * s.pdf)

    def _draw(self, wo, u) -> BSDFSample:
        """A sample without the mixture's pdf (w_k times the part's own stand-in)."""
        batch, _, k, s = self._picked(wo, u, draw=True)
        s = finished_sample(s.wi, s.weight, self.weights[k] * s.pdf, s.flags)
        return BSDFSample(*(a.reshape(batch + a.shape[1:]) for a in s))


class _Mirror(_RandomWalks):
    """``lobe`` seen through the mirror M = diag(1, 1, -1) of its surface plane where
    ``_turned(wo)`` says: f(wo, wi) = lobe.f(M wo, M wi) there, samples mirrored back. M keeps
    solid angles and the magnitudes of cosines, so pdfs, sample weights and albedos are the
    lobe's at M wo; walks and their estimates pass through (``_draw``,
    ``eval_with_error``)."""

    def __init__(self, lobe: Lobe):
        if not isinstance(lobe, Lobe) or lobe._param_shape() != ():
            raise ValueError(f"lobe = {lobe!r}: allowed a lobe with scalar parameters")
        self.lobe = lobe
        self.flags = lobe.flags
        #: a ratio f |cos| / pdf where the lobe's is
        self.weight_is_ratio = lobe.weight_is_ratio

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.lobe!r})"

    def _turned(self, wo):  # pragma: no cover - abstract
        raise NotImplementedError

    def _both(self, wo, wi):
        t = self._turned(wo)
        return _mirrored(wo, t), _mirrored(wi, t)

    def facing(self, wo):
        """``wo`` as the lobe sees it (mirrored where ``_turned``)."""
        return _mirrored(wo, self._turned(wo))

    def _eval(self, wo, wi):
        return self.lobe._eval(*self._both(wo, wi))

    def _pdf(self, wo, wi):
        return self.lobe._pdf(*self._both(wo, wi))

    def _eval_pdf(self, wo, wi):
        return self.lobe._eval_pdf(*self._both(wo, wi))

    def eval_with_error(self, wo, wi) -> tuple[np.ndarray, np.ndarray]:
        """``(eval(wo, wi), standard error)``, RGB ``(..., 3)`` each (0 error for an exact
        lobe)."""
        wo, wi = _params.direction("wo", wo), _params.direction("wi", wi)
        wo, wi = self._both(*np.broadcast_arrays(wo, wi))
        if hasattr(self.lobe, "eval_with_error"):
            return self.lobe.eval_with_error(wo, wi)
        f = self.lobe.eval(wo, wi)
        return f, np.zeros_like(f)

    def _energy_scale(self, wo, wi):
        return self.lobe._energy_scale(*self._both(wo, wi))

    def _energy_scale_rgb(self, wo, wi):
        return self.lobe._energy_scale_rgb(*self._both(wo, wi))

    def _back(self, s: BSDFSample, wo) -> BSDFSample:
        t = np.broadcast_to(self._turned(wo), s.pdf.shape)
        return BSDFSample(_mirrored(s.wi, t), s.weight, s.pdf, s.flags)

    def _sample(self, wo, u):
        return self._back(self.lobe._sample(self.facing(wo), u), wo)

    def _draw(self, wo, u) -> BSDFSample:
        return self._back(_draw(self.lobe, self.facing(wo), u), wo)

    def _delta_albedo(self, wo):
        return self.lobe._delta_albedo(self.facing(wo))


class UpsideDown(_Mirror):
    """``lobe`` turned over, f(wo, wi) = lobe.f(M wo, M wi) for every pair: the lower face
    of a sheet, the same interface as its upper one seen from the other side (light going
    down from inside a slab meets the interface as the lobe's light from below). Its index
    is the lobe's inverse.

    Parameters
    ----------
    lobe : Lobe, with scalar parameters
    """

    @property
    def eta(self):
        return None if self.lobe.eta is None else 1.0 / self.lobe.eta

    def _turned(self, wo):
        return np.ones(wo.shape[:-1], dtype=bool)


class TwoSided(_Mirror):
    """A structure symmetric about its middle plane, which a ``LayeredReference`` follows
    only from above, seen from either side: for wo below the surface both directions are
    mirrored, f(wo, wi) = lobe.f(M wo, M wi) [OpenPBR2026, §Thin-walled mode: the bulk
    structure mirrored about the base]. Exact for such a structure (a sheet with the same
    faces up and down); its index is the lobe's (1 for a sheet).

    Parameters
    ----------
    lobe : Lobe, with scalar parameters
    """

    @property
    def eta(self):
        return self.lobe.eta

    def _turned(self, wo):
        return wo[..., 2] < 0.0
