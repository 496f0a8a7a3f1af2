"""The lobe protocol shared by every lobe and material.

Public API
----------
``Flags``       bit flags of a sample or a lobe (reflection, transmission, diffuse, glossy, delta).
``BSDFSample``  the record returned by ``sample``.
``Lobe``        base class: validates and broadcasts inputs, then calls the private maths.
``HOOKS``       the private protocol: every hook a lobe may implement, with its contract.
``SupportLobe`` a lobe whose maths runs on its support only.
``finished_sample`` a sampler's raw arrays as a ``BSDFSample`` with failed samples zeroed.

Conventions (``docs/conventions.md``, ``design.md``): directions are unit vectors in the local
shading frame (normal ``+z``), ``wo`` towards the viewer, ``wi`` towards the light, both pointing
away from the surface. ``eval`` is the radiance-transport BSDF *without* the cosine factor;
``albedo`` is the *energy* albedo R + T.
"""

from __future__ import annotations

import enum
import math
from functools import partial
from typing import NamedTuple

import numpy as np

from adobe_bsdf import _memo, _params, config, quadrature
from adobe_bsdf._channels import masked, pick, put_rows, zero_rows

__all__ = ["Flags", "BSDFSample", "Hook", "HOOKS", "Lobe", "SupportLobe", "ALBEDO_METHODS",
           "luminance", "on_support", "finished_sample"]

ALBEDO_METHODS = ("quadrature", "mc", "table")
#: Rec. 709 / sRGB luminance weights of linear RGB
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def luminance(rgb) -> np.ndarray:
    """Luminance ``(...)`` of linear Rec. 709 colours ``(..., 3)``."""
    return np.asarray(rgb, dtype=np.float64) @ LUMINANCE


def _pair(wo, wi):
    """(array, elementwise check) of a (wo, wi) pair for ``Lobe._batched``."""
    return ((_params.direction_shape("wo", wo), partial(_params.check_unit, "wo")),
            (_params.direction_shape("wi", wi), partial(_params.check_unit, "wi")))


def _throughput(throughput):
    """The (array, elementwise check) entry of a path throughput for ``Lobe._batched`` (the
    check does nothing: the colour is checked whole; it carries the name for messages)."""
    return ((_params.color("throughput", throughput, 0.0, np.inf),
             partial(_checked_whole, "throughput")),)


def _checked_whole(name, arr):
    """The elementwise check of an argument validated whole already (none)."""


def _arg_name(check, index: int) -> str:
    """The argument's name in an elementwise check ``partial(f, name)`` of ``_batched``."""
    args = getattr(check, "args", ())
    return args[0] if args and isinstance(args[0], str) else f"argument {index}"


def _param_shape_of(lobe) -> tuple | None:
    """``lobe._param_shape()``; where the parameters do not broadcast together,
    ``ValueError`` naming them (``_params.parameters_error``)."""
    try:
        return lobe._param_shape()
    except ValueError as exc:
        error = _params.parameters_error(lobe)
        if error is None:
            raise
        raise error from exc


def _like(part: np.ndarray, n: int) -> np.ndarray:
    """An output for ``n`` elements shaped as the chunk result ``part``, channel-major in
    memory if ``part`` is, or is one channel broadcast (the copy of each chunk then runs
    along contiguous memory)."""
    if part.ndim == 2 and (0 < part.strides[0] < part.strides[1] or part.strides[1] == 0):
        return np.empty((part.shape[1], n), dtype=part.dtype).T
    return np.empty((n, *part.shape[1:]), dtype=part.dtype)


#: ``on_support`` gathers the pairs inside only where at most this share of them is inside
COMPACT_SHARE = 0.9


def on_support(kernel, inside, wo, wi, compact: bool = True):
    """``kernel(wo, wi, up)`` evaluated only where ``inside`` (a lobe's support), zero
    elsewhere; the same values as running it everywhere and masking.

    With ``compact`` (the lobe's parameters are scalars), 2-D batches ``(n, 3)`` and at most
    ``COMPACT_SHARE`` of the pairs inside, those pairs are gathered and the kernel runs on
    them alone with ``up = None``: it may then skip every test of the support. Otherwise it
    runs on the whole batch with ``up = inside`` (``None`` where every pair is inside) and
    must itself give 0 where ``up`` is False. ``kernel`` returns an array or a tuple of
    arrays with the batch as first axis.
    """
    if not compact or wo.ndim != 2 or wi.ndim != 2 or wo.shape != wi.shape:
        return kernel(wo, wi, inside)
    n = len(inside)
    index = np.flatnonzero(inside)
    if len(index) == n:
        return kernel(wo, wi, None)
    if len(index) > COMPACT_SHARE * n:  # a gather would cost more than the few pairs outside
        return kernel(wo, wi, inside)
    # (rows of wo: quantities of wo kept for the whole batch serve them, ``_memo.rows``)
    result = kernel(_memo.rows(wo, index), np.take(wi, index, axis=0), None)
    parts = result if isinstance(result, tuple) else (result,)
    out = tuple(_scatter(p, index, n) for p in parts)
    return out if isinstance(result, tuple) else out[0]


def _scatter(part: np.ndarray, index: np.ndarray, n: int) -> np.ndarray:
    """``part`` placed at rows ``index`` of a zero array of ``n`` rows (per channel, in the
    memory order of ``_like``)."""
    out = _like(part, n)
    if part.ndim == 2 and out.strides[0] < out.strides[1]:
        out_t, part_t = out.T, part.T
        for c in range(part.shape[1]):
            row = out_t[c]
            row.fill(0.0)
            row[index] = part_t[c]
    else:
        out.fill(0)
        put_rows(out, index, part)
    return out


class Flags(enum.IntFlag):
    """Bit flags of a lobe or of one sample (as pbrt-v4 ``BxDFFlags`` / Mitsuba ``BSDFFlags``)."""

    NONE = 0
    REFLECTION = 1
    TRANSMISSION = 2
    DIFFUSE = 4
    GLOSSY = 8
    DELTA = 16
    #: a pass-through event (no interface: wi = -wo, throughput 1), as Mitsuba's ``Null``
    NULL = 32


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


class Hook(NamedTuple):
    """One hook of the private protocol: ``name(*args)``, what it returns, its contract."""

    name: str
    args: tuple
    returns: str
    contract: str


#: The private protocol, declared once: every hook a lobe implements or inherits, in the order
#: the public methods use them. Arguments named ``wo``/``wi`` are directions in the lobe's
#: frame; ``composition.Wrapper`` forwards exactly this list (``tests/test_protocol.py``).
HOOKS = (
    Hook("_param_shape", (), "shape",
         "batch shape of the parameters: () if all are scalars (colours allowed), None if "
         "unknown; only () lobes run in chunks"),
    Hook("_eval", ("wo", "wi"), "rgb", "f(wo, wi) (..., 3), radiance transport, no cosine"),
    Hook("_pdf", ("wo", "wi"), "density", "solid-angle density (...) of _sample for a white path"),
    Hook("_eval_pdf", ("wo", "wi"), "pair", "(_eval, _pdf), sharing what the two have in common"),
    Hook("_sample", ("wo", "u"), "sample", "BSDFSample from uniforms (..., 3), white path"),
    Hook("_pdf_t", ("wo", "wi", "throughput"), "density",
         "_pdf for a path of throughput (..., 3) (a lobe that picks channels by it)"),
    Hook("_eval_pdf_t", ("wo", "wi", "throughput"), "pair", "(_eval, _pdf_t)"),
    Hook("_sample_t", ("wo", "u", "throughput"), "sample", "_sample for a path of throughput"),
    Hook("_sample_directions", ("wo", "u", "throughput"), "sample",
         "_sample_t's directions and flags, delta samples with their weight and pdf, the "
         "others with weight 0 (or their own) and the drawing lobe's pdf: what a mixture "
         "needs of a component, as it weighs the others by the whole mixture"),
    Hook("_delta_albedo", ("wo",), "rgb",
         "energy (..., 3) of the delta branches, on which _eval is 0 (0 without)"),
    Hook("_albedo_table", ("wo", "with_error"), "albedo",
         "(E, error) (..., 3) from baked tables; error None unless with_error; ValueError "
         "where there is no table"),
    Hook("_albedo_quadrature", ("wo", "tol"), "albedo",
         "(E, error) (..., 3) by direction-space quadrature plus _delta_albedo"),
    Hook("_top_albedo", ("wo",), "rgb",
         "E(wo) (..., 3) as the top of a Layer, never an underestimate (the layer would add "
         "energy)"),
    Hook("_sampling_weight", ("wo",), "weight",
         "positive estimate (...) of the albedo: the share with which a mixture picks the lobe"),
    Hook("_energy_scale", ("wo", "wi"), "factor",
         "radiance-to-energy factor (...): (eta_i / eta_o)^2 across an interface, else 1"),
    Hook("_energy_scale_rgb", ("wo", "wi"), "factor",
         "_energy_scale per colour channel, (..., 3) or broadcasting to it"),
)


class Lobe(_params.Validated):
    """Base class of every lobe: public methods validate and broadcast, the hooks of ``HOOKS``
    compute.

    A leaf lobe implements ``_eval``, ``_pdf`` and ``_sample``; the other hooks have defaults
    (a lobe with delta branches overrides ``_delta_albedo``, one with an interface
    ``_energy_scale``, one that samples by the path throughput the ``_t`` hooks).
    ``albedo(method="quadrature")`` integrates ``_eval`` in direction space and adds
    ``_delta_albedo``. Lobes are frozen: the constructor validates and stores parameters only.

    ``eta`` (the interface's relative index n_below / n_above, or None) and
    ``eta_per_channel`` (one index per colour channel) describe the lobe's interface for
    generalized reciprocity (``validation.checks.reciprocity_error``).
    """

    #: union of the flags any sample of this lobe can carry
    flags: Flags = Flags.NONE
    #: relative index of the lobe's interface (None: no interface)
    eta = None
    #: whether ``eta`` has one index per colour channel
    eta_per_channel: bool = False
    #: whether a non-delta sample's weight is f |cos| / pdf of ``_eval_pdf_t`` (to rounding):
    #: then a mixture takes the chosen component's f |cos| as weight * pdf instead of
    #: evaluating it again (``composition.Sum``); False for a stochastic estimate
    weight_is_ratio: bool = True

    # -- public protocol -------------------------------------------------------------------
    def eval(self, wo, wi) -> np.ndarray:
        """BSDF value f(wo, wi), RGB ``(..., 3)``, without the cosine factor."""
        return self._batched(self._eval, _pair(wo, wi))

    def pdf(self, wo, wi, throughput=None) -> np.ndarray:
        """Solid-angle density ``(...)`` with which ``sample(wo, u, throughput)`` returns
        ``wi``."""
        if throughput is None:
            return self._batched(self._pdf, _pair(wo, wi))
        return self._batched(self._pdf_t, _pair(wo, wi) + _throughput(throughput))

    def eval_pdf(self, wo, wi, throughput=None) -> tuple[np.ndarray, np.ndarray]:
        """``(eval(wo, wi), pdf(wo, wi, throughput))`` in one call, sharing what the two have
        in common (half vector, masking of ``wo``, Fresnel) where the lobe can."""
        if throughput is None:
            return self._batched(self._eval_pdf, _pair(wo, wi))
        return self._batched(self._eval_pdf_t, _pair(wo, wi) + _throughput(throughput))

    def sample(self, wo, u, throughput=None) -> BSDFSample:
        """Sample ``wi`` given ``wo`` from uniforms ``u`` of shape ``(..., 3)`` in [0, 1).

        ``throughput`` (colour ``(..., 3)`` in [0, inf), default white) is the path
        throughput so far; a lobe whose channels scatter differently (``Dispersive``) picks
        among them in proportion to it [Kutz2021, §4]; every other lobe ignores it.
        """
        args = ((_params.direction_shape("wo", wo), partial(_params.check_unit, "wo")),
                (_params.uniforms_shape("u", u, 3), partial(_params.check_uniform, "u")))
        if throughput is None:
            return self._batched(self._sample, args)
        return self._batched(self._sample_t, args + _throughput(throughput))

    def albedo(
        self,
        wo,
        method: str = "quadrature",
        *,
        tol: float = 1e-8,
        n_samples: int = 100_000,
        rng: np.random.Generator | int | None = 0,
        return_error: bool = False,
    ):
        """Directional energy albedo E(wo) = R + T, RGB ``(..., 3)``.

        Parameters
        ----------
        wo : array_like (..., 3)
            Outgoing directions; the lobe's parameters may be arrays broadcasting against
            ``wo.shape[:-1]`` (a texture), and the result has the broadcast shape.
        method : {"quadrature", "mc", "table"}
            ``"quadrature"``: ``adobe_bsdf.quadrature.albedo``, adaptive Genz–Malik cubature
            of f(wo, wi) |cos theta_i| (times (eta_i / eta_o)^2 for transmission) over the
            whole sphere of ``wi``, on one horizon-aligned grid shared by the whole batch,
            with sampled directions as guard points, plus the delta branches' energy in
            closed form; deterministic; the slowest (up to 10^7 evaluations of ``eval``
            per batch). ``"mc"``: mean of ``n_samples`` sample weights (times the same
            energy factor) per direction, drawn in blocks of bounded memory; costs
            ``n_samples`` samples per direction. ``"table"``: baked tables (where a lobe
            has them): a few interpolations per direction. Where a lobe has no table of
            its own it says so (``ValueError``), with two exceptions that evaluate a
            32 x 32 Gauss rule over the visible-normal sampler, 1024 samples per distinct
            direction: a ``Conductor`` with a Fresnel model (no table of Fresnel moments
            yet) and, as a layer's top, an anisotropic dielectric reflection.
        tol : float
            ``"quadrature"`` only: target absolute error of every value, in (0, 1), met
            by the cubature's error estimate (a ``UserWarning`` if the evaluation budget ends
            first). The estimate can miss support that no node or guard point touches.
        n_samples : int
            ``"mc"`` only: samples per direction, in [2, inf).
        rng : numpy.random.Generator, int or None
            ``"mc"`` only: source of the uniforms (an integer seed in [0, inf), a
            ``numpy.random.Generator``, or None for fresh entropy).
        return_error : bool
            Also return the error estimate, ``(..., 3)``: quadrature: the cubature's estimate
            (sum over cells of ``|I7 - I5|``); mc: one standard error of the mean; table: the
            tables' node quadrature error carried through the interpolation, *not* the
            interpolation error, which is larger (measured in ``docs/tables.md``). How honest
            each estimate is, is measured in ``docs/performance.md``.

        Notes
        -----
        Every argument is checked whatever the method (``ValueError`` naming it, its value and
        what is allowed), as are the directions' batch shape against the parameters'.
        """
        _params.choice("method", method, ALBEDO_METHODS)
        tol = _params.scalar("tol", tol, 0.0, 1.0, lo_open=True, hi_open=True)
        n_samples = _params.integer("n_samples", n_samples, 2)
        return_error = _params.flag("return_error", return_error)
        rng = _params.seed("rng", rng)
        if method == "table":
            # chunked and threaded as eval (a lookup per element)
            fn = (partial(self._albedo_table, with_error=True) if return_error
                  else lambda w: self._albedo_table(w, with_error=False)[0])
            return self._batched(fn, ((_params.direction_shape("wo", wo),
                                       partial(_params.check_unit, "wo")),))
        wo = _params.direction("wo", wo)
        _params.batch_shape([("wo", wo)], _param_shape_of(self),
                            f"the {type(self).__name__}'s parameters", owner=self)
        if method == "quadrature":
            value, error = self._albedo_quadrature(wo, tol)
        else:
            value, error = _mc_albedo(self, wo, n_samples, np.random.default_rng(rng))
        return (value, error) if return_error else value

    # -- batched execution -----------------------------------------------------------------
    def _param_shape(self) -> tuple | None:
        """Batch shape of the lobe's parameters: ``()`` if they are all scalars (colours
        allowed), ``None`` if unknown. Only lobes with ``()`` are run in chunks."""
        return None

    def _batched(self, fn, args):
        """Validate ``args`` ((array, elementwise check) pairs, trailing axis kept) and return
        ``fn(*arrays)``; large batches of a lobe with scalar parameters run in chunks of
        ``config`` on its thread pool, element by element the same arithmetic.

        The arguments' batch shapes must broadcast together and with the lobe's parameter
        shape (where known); otherwise ``ValueError`` naming each argument and its shape and
        the parameters that conflict with them (``_params.broadcast_error``, which finds them
        only when building the message)."""
        arrays = [a for a, _ in args]
        shapes = [a.shape[:-1] for a in arrays]
        param_shape = _param_shape_of(self)
        if param_shape:  # () changes no batch; None (unknown) is not checked
            shapes.append(param_shape)
        try:  # one call on the fast path (the batch: only () lobes use it, to chunk)
            batch = np.broadcast_shapes(*shapes)
        except ValueError:
            named = [(_arg_name(check, i), a) for i, (a, check) in enumerate(args)]
            raise _params.broadcast_error(
                named, param_shape, f"the {type(self).__name__}'s parameters",
                owner=self) from None
        n = math.prod(batch)
        if n <= config.get_options().chunk_size or param_shape != ():
            for a, check in args:
                check(a)
            with _memo.scope():
                return fn(*arrays)
        flat = [np.broadcast_to(a, batch + a.shape[-1:]).reshape(n, a.shape[-1])
                for a in arrays]
        checks = [check for _, check in args]
        out, kind = [], []

        def run(start, stop):
            chunk = [a[start:stop] for a in flat]
            try:
                for a, check in zip(chunk, checks, strict=True):
                    check(a)
            except ValueError:  # again on the whole arguments: the message's index is theirs
                for a, check in args:
                    check(a)
                raise
            with _memo.scope():
                result = fn(*chunk)
            parts = result if isinstance(result, tuple) else (result,)
            if not out:  # the first chunk runs alone and allocates the outputs
                kind.append(type(result))
                out.extend(_like(p, n) for p in parts)
            for o, p in zip(out, parts, strict=True):
                o[start:stop] = p

        size = config.get_options().chunk_size
        run(0, size)
        config.map_chunks(lambda start, stop: run(start + size, stop + size), n - size)
        shaped = [o.reshape(batch + o.shape[1:]) for o in out]
        if kind[0] is BSDFSample:
            return BSDFSample(*shaped)
        return tuple(shaped) if kind[0] is tuple else shaped[0]

    # -- defaults --------------------------------------------------------------------------
    def _eval_pdf(self, wo, wi):
        return self._eval(wo, wi), self._pdf(wo, wi)

    def _pdf_t(self, wo, wi, throughput):
        """``_pdf`` for a path of ``throughput`` ``(..., 3)`` (see ``sample``)."""
        return self._pdf(wo, wi)

    def _eval_pdf_t(self, wo, wi, throughput):
        return self._eval_pdf(wo, wi)

    def _sample_t(self, wo, u, throughput):
        """``_sample`` for a path of ``throughput`` ``(..., 3)`` (see ``sample``)."""
        return self._sample(wo, u)

    def _sample_directions(self, wo, u, throughput):
        """``_sample_t`` whose non-delta weights may be 0: a lobe that can skip computing
        them (f and its ratio to the pdf) overrides this."""
        return self._sample_t(wo, u, throughput)

    def _albedo_quadrature(self, wo, tol):
        """``(value, error)`` of ``albedo(method="quadrature")``."""
        return quadrature.albedo(self, wo, tol=tol)

    def _energy_scale(self, wo, wi):
        """Factor from radiance to energy: (eta_i / eta_o)^2 across an interface, else 1."""
        return np.ones(np.broadcast_shapes(wo.shape, wi.shape)[:-1])

    def _top_albedo(self, wo):
        """E(wo) ``(..., 3)`` of this lobe as the top of a ``layering.Layer`` (where it must
        not underestimate: the layer would add energy): the tables by default."""
        return self._albedo_table(wo, with_error=False)[0]

    def _energy_scale_rgb(self, wo, wi):
        """``_energy_scale`` per colour channel, ``(..., 3)`` or broadcasting to it (a lobe
        whose index depends on the channel overrides it)."""
        return self._energy_scale(wo, wi)[..., None]

    def _albedo_table(self, wo, with_error=True):
        """``(E, error)`` from baked tables; ``error`` is None unless ``with_error``."""
        raise ValueError(f"method = 'table' is not available for {type(self).__name__}")

    def _eval(self, wo, wi):  # pragma: no cover - abstract
        raise NotImplementedError

    def _pdf(self, wo, wi):  # pragma: no cover - abstract
        raise NotImplementedError

    def _sample(self, wo, u):  # pragma: no cover - abstract
        raise NotImplementedError

    def _sampling_weight(self, wo):
        """Estimate ``(...)`` of the lobe's albedo at ``wo``: the share with which a ``Sum``
        picks it for sampling (any positive value is correct; closer to the albedo is
        better)."""
        return np.ones(wo.shape[:-1])

    def _sampling_weight_at(self, wo):
        """``_sampling_weight(wo)``, computed once per call for this ``wo`` (``_memo``): the
        levels of a composition above a lobe each ask for it."""
        return _memo.once(self, "sampling_weight", wo, self._sampling_weight)

    def _delta_albedo(self, wo):
        """Energy albedo ``(..., 3)`` of the lobe's delta branches (0 for a lobe without)."""
        return np.zeros(wo.shape[:-1] + (3,))


class SupportLobe(Lobe):
    """A lobe whose ``eval``, ``pdf`` and ``eval_pdf`` are kernels ``(wo, wi, up)`` run on its
    support only (``on_support``): subclasses define ``_support(wo, wi) -> bool (...)`` and
    ``_eval_kernel``, ``_pdf_kernel``, ``_eval_pdf_kernel``."""

    def _support(self, wo, wi):  # pragma: no cover - abstract
        raise NotImplementedError

    def _on_support(self, kernel, wo, wi):
        return on_support(kernel, self._support(wo, wi), wo, wi,
                          compact=self._param_shape() == ())

    def _eval(self, wo, wi):
        return self._on_support(self._eval_kernel, wo, wi)

    def _pdf(self, wo, wi):
        return self._on_support(self._pdf_kernel, wo, wi)

    def _eval_pdf(self, wo, wi):
        return self._on_support(self._eval_pdf_kernel, wo, wi)


def _mc_albedo(lobe: Lobe, wo, n_samples, rng):
    """``(mean, standard error)`` of ``n_samples`` energy-scaled sample weights per direction
    (``albedo(method="mc")``; a stochastic lobe's ``_draw``, its sample without the pdf
    estimate, where it has one).

    The samples are drawn in blocks of about ``config`` ``chunk_size`` pairs (the same
    uniforms, in the same order, as one draw of all of them), and the mean and variance are
    combined block by block [Chan1983], so memory stays bounded whatever ``n_samples`` and the
    number of directions. ``n_samples`` (>= 2) and the Generator ``rng`` are validated by
    ``albedo``.
    """
    batch = wo.shape[:-1]
    step = max(1, config.get_options().chunk_size // max(1, math.prod(batch)))
    count, mean, m2 = 0, 0.0, 0.0
    # a stochastic lobe's walks without their pdf estimates (the same directions and weights)
    draw = getattr(lobe, "_draw", lobe._sample)
    starts = range(0, n_samples, step)
    for start in config.progress(starts, len(starts), f"{type(lobe).__name__}.albedo"):
        k = min(step, n_samples - start)
        u = rng.random((k, *batch, 3))
        w = np.broadcast_to(wo, u.shape)
        s = draw(w, u)
        weight = s.weight * lobe._energy_scale_rgb(w, s.wi)
        block_mean = weight.mean(axis=0)
        block_m2 = np.square(weight - block_mean).sum(axis=0)
        delta = block_mean - mean
        total = count + k
        mean = mean + delta * (k / total)
        m2 = m2 + block_m2 + np.square(delta) * (count * k / total)
        count = total
    return mean, np.sqrt(m2 / (n_samples - 1)) / np.sqrt(n_samples)


def finished_sample(wi, weight, pdf, flags, fresh: bool = False) -> BSDFSample:
    """The ``BSDFSample`` of a sampler's raw arrays, with the failed elements (no flags, or
    pdf 0) zeroed as the protocol requires; ``weight`` None is 0 (``_sample_directions`` of
    a lobe without delta samples). ``fresh``: the four arrays are the caller's own, of the
    batch's shape, and are zeroed in place (no copies)."""
    ok = (flags != int(Flags.NONE)) & (pdf > 0.0)
    if (fresh and ok.ndim == 1 and weight is not None and wi.shape == weight.shape
            == ok.shape + (3,) and pdf.shape == flags.shape == ok.shape):
        failed = np.flatnonzero(~ok)
        for rows in (wi, weight, pdf, flags):  # (Flags.NONE is 0)
            zero_rows(rows, failed)
        return BSDFSample(wi, weight, pdf, flags)
    return BSDFSample(
        wi=masked(ok, wi),
        weight=np.zeros(ok.shape + (3,)) if weight is None else masked(ok, weight),
        pdf=pick(ok, pdf, 0.0),
        flags=pick(ok, flags, int(Flags.NONE)),
    )
