"""Operators that combine lobes into one lobe: every one follows the lobe protocol, so the
result can be combined again.

Public API
----------
``Sum(*lobes, weights=None)``      f = sum_k w_k f_k, sampled as a mixture (one interface).
``Mix(a, b, weight)``              OpenPBR's mix, (1 - w) f_a + w f_b.
``Tinted(lobe, color)``            color f_lobe, passing the untinted remainder to a layer
                                   below (OpenPBR's specular and fuzz colours).
``Layer(top, base, coverage=1, transmittance=None, scaling="albedo", darkening=None)``
                                   ``top`` over ``base`` by albedo scaling (below).
``SCALINGS``                       its forms: "albedo", "reciprocal", "transmittance".
``reciprocal_normalisation(top, base)``
                                   C of the reciprocal scaling.
``coat_absorption(color, eta, w)`` one-way transmittance of an absorbing coat along ``w``.
``Rotated(lobe, phi)``             ``lobe`` turned about the normal.
``Flipped(lobe)``                  ``lobe`` with its scattered side mirrored through the plane
                                   (reflection <-> transmission of a thin sheet).
``Facing(lobe)``                   ``lobe`` always seen from its top side (thin walls).
``Wrapper``                        base of a lobe built around one inner lobe: forwards every
                                   hook of ``bsdf.HOOKS`` to it (``Rotated``, materials).
``choose(P, u)``                   pick a component by the first uniform, re-used inside it.
``sample_where(lobe, wo, u, throughput, chosen)``
                                   sample one component for the elements that chose it.

Layering
--------
OpenPBR layers a top lobe of coverage c over a base by albedo scaling
([Andersson2023, §Layering], with the coverage as [OpenPBR2026, §Layering] writes it; the
sheen and coat of the ASM [Kutz2021, §6-7]): the energy the top reflects, E_top(w), is taken
from what reaches the base. With a two-way transmittance tau(wo, wi) <= 1 of the top's medium
(the coat's absorption) and D(wo) <= 1 its darkening (below; 1 without), the three forms are

    "albedo"         f = c f_top + lerp(1, tau (1 - E_top(wo)) D(wo), c) f_base,
    "transmittance"  the same with tau = T_coat(wo, wi) = T^((1/mu_o^t + 1/mu_i^t) / 2),
    "reciprocal"     f = c f_top + lerp(1, C tau (1 - E_top(wi)) (1 - E_top(wo)), c) f_base.

``transmittance`` gives tau: None is 1; a colour T in [0, 1] (the two-way transmittance at
normal incidence, v1.1.1's coat_color) is the constant tau = T in "albedo" and "reciprocal";
a callable t(w) is a one-way transmittance, tau = t(wo) t(wi) (the ASM's
``CoatTransmittance``). "transmittance" is the general albedo scaling of [Andersson2023,
§Layering]: a colour T made view dependent by the path through a coat of index eta_c = the
top's ``eta``, mu^t = sqrt(1 - (1 - mu^2) / eta_c^2) the refracted cosine, so that tau = T at
normal incidence and darker at grazing angles (``coat_absorption``: t(w) = T^(1 / (2 mu^t))).

Energy: with E_top, E_base, tau, D <= 1,

    E(wo) = c E_top + (1 - c) E_base + c (1 - E_top(wo)) D(wo) int tau f_base |cos| <= 1

in "albedo" and "transmittance", and a white base with tau = 1 and no darkening keeps all the
energy (the white furnace; "transmittance" at T = 1 is "albedo", bit for bit). Neither is
reciprocal: f(wo, wi) - f(wi, wo) = c tau (E_top(wi) - E_top(wo)) f_base (tau is symmetric;
with darkening, D (1 - E_top) at wi against wo), measured in ``docs/asm_measured.md`` and by
``python -m adobe_bsdf check``. "reciprocal" is reciprocal where the base is; its
normalisation C, computed once per layer by ``reciprocal_normalisation`` from an integral of
the base weighted by 1 - E_top (no table: it differs for every base), is the largest with
which the layer never reflects more than the albedo form: over a Lambertian base of any colour
it keeps the albedo form's energy exactly (C = 1 / (1 - E_avg,top), the white furnace holds),
and over a glossy base it loses some.

"albedo" is the default: OpenPBR v1.1.1 [OpenPBR2026, §Coat] and the ASM use it, it is exact
in the white furnace over any base, and the reciprocal form loses energy over glossy bases.

Coat darkening ([OpenPBR2026, §Coat darkening; Portsmouth2025], ``darkening.Darkening``):
D(wo) = lerp(1, Delta(E_b, K(wo), T2), delta), the light the coat reflects back onto the base
and the base absorbs, with E_b the base's albedo, K(wo) the coat's internal reflectance
(``darkening.coat_reflectance`` at eta_c and |cos theta_o|) and T2 = tau at normal incidence;
over a smooth clear coat (E_top = 0 under it) the base's factor is the specification's
lerp(1, lerp(1, Delta, delta) T^2, c). The variant "dev_1.2" takes Delta from the light
transport in the coat instead (``darkening.physical_darkening``; its constants once per
layer, ``Darkening.coat_constants``), which carries the view dependence of the absorption
itself: it takes a constant colour T2 in "albedo" only. D depends on wo alone, so it is not
offered with "reciprocal": there C, recomputed with D, would cancel it (exactly over a
Lambertian base with K constant), and D(wo) alone breaks the reciprocity the form exists for.
"""

from __future__ import annotations

from functools import partial

import numpy as np

from adobe_bsdf import _memo, _params
from adobe_bsdf import darkening as dk
from adobe_bsdf._channels import (
    divided,
    masked,
    pick,
    put_rows,
    scaled,
    selected,
    take_rows,
    weighted,
)
from adobe_bsdf.bsdf import HOOKS, BSDFSample, Flags, Hook, Lobe, finished_sample, luminance
from adobe_bsdf.microfacet import saturated

__all__ = ["Sum", "Mix", "Tinted", "Layer", "SCALINGS", "reciprocal_normalisation",
           "coat_absorption", "Rotated", "Flipped", "Facing", "Wrapper", "choose", "sample_where"]

#: full coverage, the default of ``Layer``
_FULL = np.asarray(1.0)


class Wrapper(Lobe):
    """A lobe built around another, ``_inner()``, whose interface it shares; every hook of
    ``bsdf.HOOKS`` is forwarded to the inner lobe, its directions through ``_directions`` and
    samples back through ``_from_inner`` (the identity here; ``Rotated`` turns them,
    ``Flipped`` and ``Facing`` mirror them). A subclass overrides only the hooks that
    differ."""

    def _inner(self) -> Lobe:  # pragma: no cover - abstract
        raise NotImplementedError

    def _to_inner(self, w):
        """A direction of this lobe's frame in the inner lobe's frame."""
        return w

    def _directions(self, wo, wi):
        """``(wo, wi)`` of a hook in the inner lobe's frame (``wi`` None for the hooks of
        ``wo`` alone): each through ``_to_inner`` by default."""
        return self._to_inner(wo), None if wi is None else self._to_inner(wi)

    def _from_inner(self, sample: BSDFSample, wo) -> BSDFSample:
        """A sample of the inner lobe (drawn at ``wo``, this lobe's frame) in this lobe's
        frame."""
        return sample

    @property
    def eta(self):
        """The inner lobe's interface index (generalized reciprocity), or None."""
        return self._inner().eta

    @property
    def eta_per_channel(self) -> bool:
        """Whether ``eta`` has one index per colour channel (``Dispersive``)."""
        return self._inner().eta_per_channel

    @property
    def weight_is_ratio(self) -> bool:
        return self._inner().weight_is_ratio


def _forwarding(hook: Hook):
    """The ``Wrapper`` method that forwards ``hook`` to the inner lobe."""
    o = hook.args.index("wo") if "wo" in hook.args else None
    i = hook.args.index("wi") if "wi" in hook.args else None

    def forward(self, *args, **kwargs):
        if o is not None:
            args = list(args)
            wo = args[o]
            args[o], wi = self._directions(wo, None if i is None else args[i])
            if i is not None:
                args[i] = wi
        result = getattr(self._inner(), hook.name)(*args, **kwargs)
        return self._from_inner(result, wo) if hook.returns == "sample" else result

    forward.__name__ = forward.__qualname__ = hook.name
    forward.__doc__ = f"Forwarded to the inner lobe: {hook.contract}."
    return forward


for _hook in HOOKS:
    setattr(Wrapper, _hook.name, _forwarding(_hook))
del _hook


class Sum(Lobe):
    """f = sum_k w_k f_k of lobes that share one surface (and, for transmission, one
    interface).

    Parameters
    ----------
    *components : Lobe
    weights : sequence of colours in [0, inf), optional
        One weight w_k per component (scalar or ``(..., 3)``, a texture allowed); default 1.
        A component whose weight is 0 everywhere is dropped at construction: it is never
        evaluated or sampled (``components`` holds the active ones only).

    Notes
    -----
    Sampling picks component k with probability P_k(wo) proportional to
    lum(w_k) ``_sampling_weight_k(wo)`` (an albedo estimate), samples it, and weighs a
    non-delta sample by the whole sum, weight = f |cos| / pdf with pdf = sum_k P_k pdf_k (the
    one-sample balance heuristic, [Veach1997, §9.2.4]), so ``pdf`` and ``sample`` agree
    whatever the estimates. A delta sample of component k has probability P_k times its
    own. The first uniform is re-used inside the chosen interval, so components that branch
    on it (the dielectric's reflect/refract choice) stay stratified. Where a component's
    parameters are scalars, it is sampled only for the elements that chose it. A Sum of one
    active component (P = 1) is that component's ``pdf`` and ``eval`` times its weight, and
    samples as the component does (its own weight times w: within rounding of f |cos| / pdf).
    """

    def __init__(self, *components: Lobe, weights=None):
        if not all(isinstance(c, Lobe) for c in components):
            raise ValueError(f"components = {components!r}: a Sum takes lobes")
        if weights is None:
            weights = [None] * len(components)
        elif len(weights) != len(components):
            raise ValueError(f"weights has {len(weights)} entries for {len(components)} "
                             "components; allowed: one weight per component")
        else:
            weights = [_params.color("weights", w, 0.0, np.inf) for w in weights]
        self._init(components, weights)

    def _init(self, components, weights=None):
        """``components`` and their validated colour weights (None: all 1)."""
        if weights is None:
            weights = [None] * len(components)
        active = [(c, w) for c, w in zip(components, weights, strict=True)
                  if w is None or np.any(w != 0.0)]
        self.components = tuple(c for c, _ in active)
        #: the active components' weights (None: 1)
        self.weights = tuple(w for _, w in active)
        #: the weights that scale colours: None where 1 (a product by 1 is exact, so skipped)
        self._scales = tuple(None if w is None or (w.shape == (3,) and np.all(w == 1.0)) else w
                             for w in self.weights)
        flags = Flags.NONE
        for c in self.components:
            flags |= c.flags
        self.flags = flags
        #: (component, weight) where only one is active, else None
        self._single = (self.components[0], self._scales[0]) if len(active) == 1 else None

    def __repr__(self) -> str:
        parts = [repr(c) if w is None else f"{w!r} * {c!r}"
                 for c, w in zip(self.components, self.weights, strict=True)]
        return f"{type(self).__name__}({', '.join(parts)})"

    def _param_shape(self):
        shapes = [c._param_shape() for c in self.components]
        if any(s is None for s in shapes):
            return None
        shapes += [w.shape[:-1] for w in self.weights if w is not None]
        return np.broadcast_shapes(*shapes)

    def _terms(self, method, *args):
        """Weighted per-component results of ``method`` (a colour-valued private method)."""
        for c, w in zip(self.components, self._scales, strict=True):
            value = getattr(c, method)(*args)
            yield value if w is None else scaled(value, w)

    @staticmethod
    def _total(parts, shape):
        total = None
        for p in parts:
            total = p if total is None else total + p
        return np.zeros(shape) if total is None else total

    def _shares(self, wo):
        """Each component's sampling weight times the luminance of its weight: P_k before
        normalisation."""
        return [c._sampling_weight_at(wo) * (1.0 if k is None else luminance(k))
                for c, k in zip(self.components, self.weights, strict=True)]

    def _probabilities(self, wo):
        w = np.stack(np.broadcast_arrays(*self._shares(wo)))
        total = w.sum(axis=0)
        positive = total > 0.0
        if positive.all():  # (the selections below would keep every value)
            return w / total
        return pick(positive, w / pick(positive, total, 1.0), 1.0 / len(w))

    def _batch(self, wo, wi):
        return np.broadcast_shapes(wo.shape, wi.shape)[:-1]

    def _eval(self, wo, wi):
        with np.errstate(over="ignore"):  # saturated values may add up beyond the range
            return saturated(self._total(self._terms("_eval", wo, wi),
                                         self._batch(wo, wi) + (3,)))

    def _pdf(self, wo, wi):
        return self._pdf_t(wo, wi, None)

    def _pdf_t(self, wo, wi, throughput):
        if not self.components:
            return np.zeros(self._batch(wo, wi))
        if self._single:  # P = 1
            return self._single[0]._pdf_t(wo, wi, throughput)
        P = self._probabilities(wo)
        return sum(P[k] * c._pdf_t(wo, wi, throughput) for k, c in enumerate(self.components))

    def _eval_pdf(self, wo, wi):
        return self._eval_pdf_t(wo, wi, None)

    def _eval_pdf_t(self, wo, wi, throughput, P=None):
        """(f, pdf); ``P`` is ``_probabilities(wo)`` where the caller has it already."""
        if not self.components:
            batch = self._batch(wo, wi)
            return np.zeros(batch + (3,)), np.zeros(batch)
        if self._single:  # P = 1
            c, w = self._single
            f, pdf = c._eval_pdf_t(wo, wi, throughput)
            return saturated(f if w is None else scaled(f, w)), pdf
        if P is None:
            P = self._probabilities(wo)
        f, pdf = None, None
        for k, (c, w) in enumerate(zip(self.components, self._scales, strict=True)):
            fk, pk = c._eval_pdf_t(wo, wi, throughput)
            fk = fk if w is None else scaled(fk, w)
            with np.errstate(over="ignore"):  # saturated below
                f = fk if f is None else f + fk
            pdf = P[k] * pk if pdf is None else pdf + P[k] * pk
        return saturated(f), pdf

    def _sample(self, wo, u):
        return self._sample_t(wo, u, None)

    def _sample_t(self, wo, u, throughput):
        if not self.components:
            return self._sample_directions(wo, u, throughput)
        if self._single:
            return self._weighted_sample(self._single[0]._sample_t(wo, u, throughput))
        if _by_groups(self.components, wo, u, self.weights):
            wo, u = np.broadcast_arrays(wo, u)  # one wo for a batch of uniforms
            P = self._probabilities(wo)
            k, _, u = choose(P, u)
            return finished_sample(*_mixture_sample(self.components, k, wo, u, throughput,
                                                    partial(self._combined, P)), fresh=True)
        s, wo, P = self._drawn(wo, u, throughput)  # failed samples zeroed at the end
        delta = (s.flags & int(Flags.DELTA)) != 0
        f, mix_pdf = self._eval_pdf_t(wo, s.wi, throughput, P)
        smooth_weight = divided(weighted(f, np.abs(s.wi[..., 2])),
                                pick(mix_pdf > 0.0, mix_pdf, 1.0))
        weight = selected(delta, s.weight, masked(mix_pdf > 0.0, smooth_weight))
        return finished_sample(s.wi, weight, pick(delta, s.pdf, mix_pdf), s.flags)

    def _combined(self, P, j, index, wo, s, parts):
        """``_mixture_sample``'s (weight, pdf) of the elements ``index`` that chose component
        j: sum_k w_k f_k |cos| over sum_k P_k pdf_k; a delta sample its own weight times
        w_j / P_j and pdf P_j pdf_j."""
        with np.errstate(over="ignore"):  # saturated below
            f = self._total((fc if w is None else scaled(fc, w) for (fc, _), w
                             in zip(parts, self._scales, strict=True)), s.wi.shape)
        f = saturated(f)
        P = [take_rows(Pk, index) for Pk in P]
        pdf = sum(Pk * pk for Pk, (_, pk) in zip(P, parts, strict=True))
        positive = pdf > 0.0
        weight = (divided(f, pdf, out=f) if positive.all()
                  else masked(positive, divided(f, pick(positive, pdf, 1.0))))
        delta = (s.flags & int(Flags.DELTA)) != 0
        if not np.any(delta):
            return weight, pdf
        w, Pj = self._scales[j], P[j]
        own = divided(s.weight if w is None else scaled(s.weight, w), pick(Pj > 0, Pj, 1.0))
        return selected(delta, own, weight), pick(delta, Pj * s.pdf, pdf)

    def _sample_directions(self, wo, u, throughput):
        batch = np.broadcast_shapes(wo.shape, u.shape)[:-1]
        if not self.components:
            return BSDFSample(np.zeros(batch + (3,)), np.zeros(batch + (3,)), np.zeros(batch),
                              np.full(batch, int(Flags.NONE)))
        if self._single:
            return self._weighted_sample(self._single[0]._sample_directions(wo, u, throughput))
        return finished_sample(*self._drawn(wo, u, throughput)[0])

    def _weighted_sample(self, s: BSDFSample) -> BSDFSample:
        """The single component's sample ``s`` with its weight times w."""
        w = self._single[1]
        return s if w is None else s._replace(weight=scaled(s.weight, w))

    def _drawn(self, wo, u, throughput):
        """``(sample, wo, P)``: the components' ``_sample_directions`` for the elements that
        chose them, delta samples weighted (by 1 / P_k) and their pdf P_k pdf_k, the others
        with weight 0 and their component's pdf (failed samples not zeroed); ``wo``
        broadcast to the batch and P the probabilities."""
        batch = np.broadcast_shapes(wo.shape, u.shape)[:-1]
        wo = np.broadcast_to(wo, batch + (3,))  # one wo for a batch of uniforms
        P = self._probabilities(wo)
        k, Pk, u = choose(P, u)
        wi, weight, pdf, flags = _chosen_samples(self.components, k, wo, u, throughput,
                                                 self._scales)
        delta = (flags & int(Flags.DELTA)) != 0
        weight = masked(delta, divided(weight, pick(Pk > 0, Pk, 1.0)))
        return BSDFSample(wi, weight, pick(delta, Pk * pdf, pdf), flags), wo, P

    def _delta_albedo(self, wo):
        return self._total(self._terms("_delta_albedo", wo), wo.shape[:-1] + (3,))

    @property
    def weight_is_ratio(self) -> bool:
        return all(c.weight_is_ratio for c in self.components)

    @property
    def eta(self):
        """The shared interface's index (for generalized reciprocity): the transmitting
        component's, else None."""
        return self._interface().eta

    @property
    def eta_per_channel(self) -> bool:
        return self._interface().eta_per_channel

    def _interface(self) -> Lobe:
        """The component whose interface sets the energy scale: the first that transmits
        (the components share one interface), else any."""
        for c in self.components:
            if c.flags & Flags.TRANSMISSION:
                return c
        return self.components[0] if self.components else Lobe()

    def _energy_scale(self, wo, wi):
        return self._interface()._energy_scale(wo, wi)

    def _energy_scale_rgb(self, wo, wi):
        return self._interface()._energy_scale_rgb(wo, wi)

    def _albedo_table(self, wo, with_error=True):
        values, errors = [], []
        for c, w in zip(self.components, self._scales, strict=True):
            value, error = c._albedo_table(wo, with_error)
            values.append(value if w is None else value * w)
            errors.append(error if w is None or error is None else error * w)
        shape = wo.shape[:-1] + (3,)
        return (self._total(values, shape),
                self._total(errors, shape) if with_error else None)

    def _sampling_weight(self, wo):
        if not self.components:
            return np.zeros(wo.shape[:-1])
        return sum(self._shares(wo))


class Mix(Sum):
    """OpenPBR's mix [Andersson2023, §Mixing; OpenPBR2026, §Mixing]: patches of two materials
    side by side on one microsurface, ``b`` covering the fraction ``weight``,

        f = (1 - w) f_a + w f_b.

    Energy and reciprocity follow from linearity: E = (1 - w) E_a + w E_b (so two white
    lobes mix to a white lobe) and the mix is reciprocal where both components are.
    Sampling, pdf and weights are those of ``Sum`` with weights (1 - w, w): a component is
    picked in proportion to its weight times its albedo estimate, and w = 0 or 1 leaves only
    one component (eval, pdf and sampled directions bit for bit; sample weights to rounding).

    Parameters
    ----------
    a, b : Lobe
    weight : colour in [0, 1]
        w, scalar or per channel (``(..., 3)``, a texture allowed).
    """

    def __init__(self, a: Lobe, b: Lobe, weight):
        for name, lobe in (("a", a), ("b", b)):
            if not isinstance(lobe, Lobe):
                raise ValueError(f"{name} = {lobe!r}: a Mix takes two lobes")
        w = _params.color("weight", weight, 0.0, 1.0)
        self.weight = w
        self._init((a, b), [1.0 - w, w])


class Tinted(Sum):
    """f = color f_lobe, seen by a ``Layer`` below it as the untinted lobe: as a layer's
    top, its E_top is the lobe's own, so the light the tint takes is absorbed, not passed
    on. OpenPBR's ``specular_color`` on the dielectric ("tints only the first reflection
    from above; the transmitted light is unaffected", [OpenPBR2026, §Dielectric base]) and
    ``fuzz_color`` ("E_fuzz is computed with white colour, so the base is not tinted",
    [OpenPBR2026, §Fuzz]) are this.

    Parameters
    ----------
    lobe : Lobe
    color : colour in [0, 1]
        The tint, scalar or ``(..., 3)`` (a texture allowed).
    """

    def __init__(self, lobe: Lobe, color):
        if not isinstance(lobe, Lobe):
            raise ValueError(f"lobe = {lobe!r}: Tinted takes a lobe")
        self._init_tinted(lobe, _params.color("color", color, 0.0, 1.0))

    @classmethod
    def _new(cls, lobe, color):
        self = cls.__new__(cls)
        self._init_tinted(lobe, color)
        return self

    def _init_tinted(self, lobe, color):
        self.lobe, self.color = lobe, color
        self._init((lobe,), [color])

    def __repr__(self) -> str:
        return f"Tinted({self.lobe!r}, color={self.color!r})"

    def _top_albedo(self, wo):
        return self.lobe._top_albedo(wo)


class Layer(Lobe):
    """``top`` over ``base`` by albedo scaling, in one of the forms of ``SCALINGS`` (module
    docstring):

        "albedo"         c f_top + lerp(1, tau (1 - E_top(wo)) D(wo), c) f_base,
        "transmittance"  the same with tau = T_coat(wo, wi) = T^((1/mu_o^t + 1/mu_i^t) / 2),
        "reciprocal"     c f_top + lerp(1, C tau (1 - E_top(wi)) (1 - E_top(wo)), c) f_base.

    "albedo" (the default: OpenPBR v1.1.1 and the ASM) and "transmittance" keep all the
    energy of a white base under a clear coat (the white furnace) and are not reciprocal;
    "reciprocal" is, and loses energy over a glossy base. No form gains energy.

    Parameters
    ----------
    top, base : Lobe
        E_top(wo) is the top's ``_top_albedo`` on every call: its albedo tables, or where
        they would underestimate (an anisotropic coat), a quadrature.
    coverage : array_like in [0, 1]
        c, how much of the surface the top layer covers (the ASM coat's opacity).
    transmittance : None, colour in [0, 1] or callable
        tau: None is 1; a colour T (scalar or ``(..., 3)``) the two-way transmittance at
        normal incidence (constant in "albedo" and "reciprocal", T_coat in
        "transmittance", which requires one); a callable ``t(w) -> (..., 3)`` in [0, 1] a
        one-way transmittance, tau = t(wo) t(wi).
    scaling : one of ``SCALINGS``
        "reciprocal" needs scalar lobe parameters (C is one colour per layer) and has no
        table albedo; "transmittance" and ``darkening`` need the top's index eta_c
        (``top.eta``, one per point).
    darkening : darkening.Darkening or None
        Coat darkening D(wo) (module docstring); not with "reciprocal".

    Notes
    -----
    Sampling picks the top with probability proportional to c lum(E_top(wo)) and the base
    with lum(W(wo, wo')) times the base's albedo estimate (wo' the mirror of wo), and weighs
    non-delta samples by the one-sample balance heuristic, as ``Sum``. The base's delta
    branches (a smooth interface) carry W at their own direction; their closed-form energy
    (``albedo``) uses tau(wo, wo), exact for mirror reflection. The table albedo makes the
    same approximation for the base's whole lobe (a view-dependent tau of "transmittance" or
    a callable); it is exact where tau is constant (T = 1 included). ``exit_weight`` (emission
    from below) passes the top once: one-way t(wo), or sqrt(T) for a constant colour, and no
    darkening.
    """

    def __init__(self, top: Lobe, base: Lobe, coverage=1.0, transmittance=None,
                 scaling: str = "albedo", darkening=None):
        if not isinstance(top, Lobe) or not isinstance(base, Lobe):
            raise ValueError(f"top = {top!r}, base = {base!r}: a Layer takes two lobes")
        _params.choice("scaling", scaling, SCALINGS)
        if transmittance is not None and not callable(transmittance):
            transmittance = _params.color("transmittance", transmittance, 0.0, 1.0)
        if scaling == "transmittance" and (transmittance is None or callable(transmittance)):
            raise ValueError(f"transmittance = {transmittance!r} with scaling = "
                             "'transmittance': allowed a colour in [0, 1] (the coat's two-way "
                             "transmittance at normal incidence)")
        if darkening is not None and not isinstance(darkening, dk.Darkening):
            raise ValueError(f"darkening = {darkening!r}: allowed None or a "
                             "darkening.Darkening")
        if scaling == "transmittance" or darkening is not None:
            if top.eta is None or top.eta_per_channel:
                raise ValueError(f"top = {top!r} has no single interface index (eta = "
                                 f"{top.eta!r}); scaling = 'transmittance' and darkening "
                                 "need the coat's index: allowed a top with an interface "
                                 "(e.g. DielectricReflection)")
        if (darkening is not None and darkening.variant == dk.PHYSICAL
                and (scaling == "transmittance" or callable(transmittance))):
            raise ValueError(f"darkening = {darkening!r} with a view-dependent transmittance "
                             f"(scaling = {scaling!r}, transmittance = {transmittance!r}): "
                             "its Delta carries the view dependence of the absorption "
                             "itself; allowed: a constant colour T2 with scaling 'albedo'")
        if scaling == "reciprocal":
            if darkening is not None:
                raise ValueError(f"darkening = {darkening!r} with scaling = 'reciprocal': "
                                 "D(wo) depends on wo alone, which breaks reciprocity, and "
                                 "the normalisation C recomputed with it would cancel it; "
                                 "allowed: darkening with scaling 'albedo' or "
                                 "'transmittance'")
            for name, lobe in (("top", top), ("base", base)):
                if lobe._param_shape() != ():
                    raise ValueError(f"scaling = 'reciprocal' with {name} = {lobe!r}: its "
                                     "normalisation C is one number per layer; allowed: lobes "
                                     "whose parameters are scalars (not textures)")
        self._init(top, base, _params.real("coverage", coverage, 0.0, 1.0), transmittance,
                   scaling, darkening)

    def _init(self, top, base, coverage=_FULL, transmittance=None, scaling="albedo",
              darkening=None):
        self.top, self.base = top, base
        self.coverage = coverage
        #: coverage 1 (a scalar): the products by c and the sums with 1 - c are skipped
        #: (x * 1 and x + 0 are x, up to the sign of a zero)
        self._full = coverage.ndim == 0 and coverage == 1.0
        self.transmittance = transmittance
        self.scaling = scaling
        self.darkening = darkening
        #: the one-way transmittance t(w) (None: 1) and the constant two-way one T (None: 1)
        self._one_way, self._T = None, None
        if callable(transmittance):
            self._one_way = transmittance
        elif transmittance is not None and scaling == "transmittance":
            self._one_way = partial(coat_absorption, transmittance, np.asarray(top.eta))
        else:
            self._T = transmittance
        #: the reciprocal form's normalisation C ``(3,)`` and its standard error (None
        #: until first needed; ``reciprocal_normalisation``)
        self._C = None
        #: the darkening's constants (eta_c, ``Darkening.coat_constants``, E_b, T2), once
        #: per layer
        self._dark = None if darkening is None else self._darkening_constants()
        self.flags = top.flags | base.flags

    def __repr__(self) -> str:
        extra = "" if self.scaling == "albedo" else f", scaling={self.scaling!r}"
        if self.transmittance is not None:
            extra += f", transmittance={self.transmittance!r}"
        if self.darkening is not None:
            extra += f", darkening={self.darkening!r}"
        return f"Layer({self.top!r}, {self.base!r}, coverage={self.coverage!r}{extra})"

    @property
    def normalisation(self) -> tuple[np.ndarray, np.ndarray]:
        """``(C, error)`` of the reciprocal form, ``(3,)`` each (``reciprocal_normalisation``;
        computed once per layer)."""
        if self._C is None:
            self._C = reciprocal_normalisation(self.top, self.base)
        return self._C

    @property
    def eta(self):
        """The base's interface index: the top reflects only."""
        return self.base.eta

    @property
    def eta_per_channel(self) -> bool:
        return self.base.eta_per_channel

    def exit_weight(self, wo):
        """(1 - c) + c t(wo) (1 - E_top(wo)) ``(..., 3)``: the share of light leaving the base
        towards ``wo`` that passes the top layer once (emission from below it); t is sqrt(T)
        for a constant colour T, and darkening does not enter."""
        one_way = self._t(wo) if self._T is None else self._t(wo) * np.sqrt(self._T)
        return ((1.0 - self.coverage)[..., None]
                + self.coverage[..., None] * one_way * (1.0 - self._top_energy(wo)))

    def _param_shape(self):
        shapes = [self.top._param_shape(), self.base._param_shape()]
        if callable(self.transmittance):  # its own shape where it declares one
            shapes.append(getattr(self.transmittance, "param_shape", None))
        elif self.transmittance is not None:
            shapes.append(self.transmittance.shape[:-1])
        if any(s is None for s in shapes):
            return None
        shapes.append(self.coverage.shape)
        if self.darkening is not None:
            d = self.darkening
            shapes += [d.delta.shape, d.base_roughness.shape, d.coat_alpha.shape,
                       self._dark[2].shape[:-1]]
        return np.broadcast_shapes(*shapes)

    # -- the weights ------------------------------------------------------------------------
    def _t(self, w):
        """The one-way transmittance t(w) (1 without one), once per call for this ``w``: the
        base's weight and the probabilities both take t(wo)."""
        return 1.0 if self._one_way is None else _memo.once(self, "t", w, self._one_way)

    def _darkening_constants(self):
        """(eta_c, the darkening's ``coat_constants``, E_b, T2): E_b the given base albedo
        or the base's own at normal incidence (its table, else a quadrature to
        ``DARKENING_ALBEDO_TOL``), at most 1; T2 = tau at normal incidence; the constants
        the internal reflectance of a rough base (``darkening.internal_reflectance(eta_c)``)
        or, for "dev_1.2", the coat's ``darkening.CoatTransport``."""
        eta = np.asarray(self.top.eta, dtype=np.float64)
        E_b = self.darkening.base_albedo
        if E_b is None:
            try:
                E_b = self.base.albedo(_NORMAL, method="table")
            except ValueError:
                E_b = self.base.albedo(_NORMAL, tol=DARKENING_ALBEDO_TOL)
            E_b = np.clip(E_b, 0.0, 1.0)  # interpolation or quadrature overshoot
        if self._one_way is None:
            T2 = 1.0 if self._T is None else self._T
        elif self.scaling == "transmittance":
            T2 = self.transmittance  # T_coat at normal incidence
        else:
            T2 = np.minimum(self._one_way(_NORMAL) ** 2, 1.0)
        return eta, self.darkening.coat_constants(eta, E_b, T2), E_b, T2

    def _top_energy(self, wo):
        """E_top(wo), at most 1 (a top albedo above 1 is rounding or interpolation overshoot;
        the base then gets nothing, never a negative weight)."""
        return np.minimum(self.top._top_albedo(wo), 1.0)

    def _top_share(self, f):
        """c f for the top's ``f`` ``(..., 3)``."""
        return f if self._full else self.coverage[..., None] * f

    def _covered(self, wo, t, E_top):
        """c t (1 - E_top) T D(wo) ``(..., 3)``: the covered share of the base's weight at
        ``wo`` before the transmittance towards wi (``t`` the one-way one at wo)."""
        scaled = 1.0 - E_top
        if self._one_way is not None:  # (else t = 1)
            scaled = t * scaled if self._full else (self.coverage[..., None] * t) * scaled
        elif not self._full:
            scaled = self.coverage[..., None] * scaled
        if self._T is not None:
            scaled = scaled * self._T
        if self.darkening is not None:
            eta, coat, E_b, T2 = self._dark
            scaled = scaled * self.darkening.factor(eta, np.abs(wo[..., 2]), E_b, T2, coat)
        return scaled

    def _scaled(self, wo):
        """``_covered`` at wo and E_top(wo) (once per call for this ``wo``)."""
        return _memo.once(self, "scaled", wo, self._scaled_now)

    def _scaled_now(self, wo):
        E_top = self._top_energy(wo)
        return self._covered(wo, self._t(wo), E_top), E_top

    def _weight(self, wo, wi, scaled, E_top_i=None):
        """W(wo, wi) = (1 - c) + scaled t(wi) ``(..., 3)``, times C (1 - E_top(wi)) in the
        reciprocal form; ``E_top_i`` is E_top(wi) where the caller has it (wi = wo or its
        mirror, whose albedo is wo's)."""
        base = scaled if self._one_way is None else scaled * self._t(wi)
        if self.scaling == "reciprocal":
            if E_top_i is None:
                E_top_i = self._top_energy(wi)
            base = base * self.normalisation[0] * (1.0 - E_top_i)
        return base if self._full else (1.0 - self.coverage)[..., None] + base

    def _shares(self, wo, scaled, E_top):
        """(top, base): c E_top and the base's weight at wo times its sampling weight, the
        probabilities before normalisation."""
        return (self.coverage * luminance(E_top),
                luminance(self._weight(wo, wo, scaled, E_top)) * self.base._sampling_weight_at(wo))

    def _probabilities(self, wo, scaled, E_top):
        top, base = np.broadcast_arrays(*self._shares(wo, scaled, E_top))
        total = top + base
        positive = total > 0.0
        P_top = (top / total if positive.all()
                 else pick(positive, top / pick(positive, total, 1.0), 0.5))
        return np.stack([P_top, 1.0 - P_top])

    # -- protocol ---------------------------------------------------------------------------
    def _eval(self, wo, wi):
        scaled, _ = self._scaled(wo)
        with np.errstate(over="ignore"):  # saturated values may add up beyond the range
            return saturated(self._top_share(self.top._eval(wo, wi))
                             + self._weight(wo, wi, scaled) * self.base._eval(wo, wi))

    def _pdf(self, wo, wi):
        return self._pdf_t(wo, wi, None)

    def _eval_pdf(self, wo, wi):
        return self._eval_pdf_t(wo, wi, None)

    def _pdf_t(self, wo, wi, throughput):
        P = self._probabilities(wo, *self._scaled(wo))
        return (P[0] * self.top._pdf_t(wo, wi, throughput)
                + P[1] * self.base._pdf_t(wo, wi, throughput))

    def _eval_pdf_t(self, wo, wi, throughput, scaled_top=None, P=None):
        """(f, pdf); ``scaled_top`` is ``_scaled(wo)`` and ``P`` the probabilities where the
        caller has them already (the top's albedo can be a quadrature per direction: an
        anisotropic coat; the base's sampling weight a table lookup)."""
        scaled, E_top = self._scaled(wo) if scaled_top is None else scaled_top
        if P is None:
            P = self._probabilities(wo, scaled, E_top)
        f_top, p_top = self.top._eval_pdf_t(wo, wi, throughput)
        f_base, p_base = self.base._eval_pdf_t(wo, wi, throughput)
        with np.errstate(over="ignore"):  # saturated below
            f = self._top_share(f_top) + self._weight(wo, wi, scaled) * f_base
        return saturated(f), P[0] * p_top + P[1] * p_base

    def _sample(self, wo, u):
        return self._sample_t(wo, u, None)

    def _sample_t(self, wo, u, throughput):
        if _by_groups((self.top, self.base), wo, u):
            wo, u = np.broadcast_arrays(wo, u)  # one wo for a batch of uniforms
            scaled, E_top = self._scaled(wo)
            P = self._probabilities(wo, scaled, E_top)
            k, _, u = choose(P, u)
            return finished_sample(*_mixture_sample(
                (self.top, self.base), k, wo, u, throughput,
                partial(self._combined, np.broadcast_to(scaled, wo.shape), P)), fresh=True)
        s, wo, scaled_top, P = self._drawn(wo, u, throughput)  # failures zeroed at the end
        delta = (s.flags & int(Flags.DELTA)) != 0
        f, pdf = self._eval_pdf_t(wo, s.wi, throughput, scaled_top, P)
        with np.errstate(divide="ignore", invalid="ignore"):
            weight = divided(weighted(f, np.abs(s.wi[..., 2])), pdf)
        weight = selected(delta, s.weight, weight)
        return finished_sample(s.wi, weight, pick(delta, s.pdf, pdf), s.flags)

    def _combined(self, scaled, P, j, index, wo, s, parts):
        """``_mixture_sample``'s (weight, pdf) of the elements ``index`` that chose the top
        (j = 0) or the base: (c f_top + W f_base) |cos| over P_top pdf_top + P_base pdf_base;
        a delta sample its own weight times c or W, over P_j, and pdf P_j pdf_j."""
        W = self._weight(wo, s.wi, take_rows(scaled, index))
        (f_top, p_top), (f_base, p_base) = parts
        with np.errstate(over="ignore"):  # saturated below
            f = saturated(self._top_share(f_top) + W * f_base)
        P_top, P_base = (take_rows(Pk, index) for Pk in P)
        pdf = P_top * p_top + P_base * p_base
        with np.errstate(divide="ignore", invalid="ignore"):  # pdf 0: zeroed by the caller
            weight = divided(f, pdf)
        delta = (s.flags & int(Flags.DELTA)) != 0
        if not np.any(delta):
            return weight, pdf
        Pj = P_top if j == 0 else P_base
        share = self.coverage[..., None] if j == 0 else W
        with np.errstate(divide="ignore", invalid="ignore"):
            own = divided(share * s.weight, Pj)
        return selected(delta, own, weight), pick(delta, Pj * s.pdf, pdf)

    def _sample_directions(self, wo, u, throughput):
        return finished_sample(*self._drawn(wo, u, throughput)[0])

    def _drawn(self, wo, u, throughput):
        """``(sample, wo, (scaled, E_top), P)`` as ``Sum._drawn``: the top's or the base's
        ``_sample_directions``, delta samples weighted by their share over P_k."""
        batch = np.broadcast_shapes(wo.shape, u.shape)[:-1]
        wo = np.broadcast_to(wo, batch + (3,))
        scaled, E_top = self._scaled(wo)
        P = self._probabilities(wo, scaled, E_top)
        k, P_k, u = choose(P, u)
        wi, weight, pdf, flags = _chosen_samples((self.top, self.base), k, wo, u, throughput)
        delta = (flags & int(Flags.DELTA)) != 0
        if np.any(delta):
            with np.errstate(divide="ignore", invalid="ignore"):
                own = pick((k == 0)[..., None], self.coverage[..., None] * weight,
                               self._weight(wo, wi, scaled) * weight) / P_k[..., None]
            weight = masked(delta, own)
        else:  # (a component's default _sample_directions weighs every sample)
            weight = np.zeros_like(weight)
        sample = BSDFSample(wi, weight, pick(delta, P_k * pdf, pdf), flags)
        return sample, wo, (scaled, E_top), P

    def _delta_albedo(self, wo):
        scaled, E_top = self._scaled(wo)
        return (self.coverage[..., None] * self.top._delta_albedo(wo)
                + self._weight(wo, wo, scaled, E_top) * self.base._delta_albedo(wo))

    def _albedo_table(self, wo, with_error=True):
        if self.scaling == "reciprocal":
            raise ValueError("scaling = 'reciprocal': the layer's albedo needs the base "
                             "weighted by 1 - E_top(wi), which no table holds; use albedo "
                             "method 'quadrature' or 'mc'")
        E_top, err_top = self.top._albedo_table(wo, with_error)
        E_top = np.minimum(E_top, 1.0)  # as ``_top_energy``
        E_base, err_base = self.base._albedo_table(wo, with_error)
        c = self.coverage[..., None]
        # the base's weight from what the top passes on: a ``Tinted`` top reflects E_top but
        # passes on 1 - its untinted albedo, as in eval
        passed = (np.minimum(self.top.lobe._albedo_table(wo, False)[0], 1.0)
                  if isinstance(self.top, Tinted) else E_top)
        W = (1.0 - c) + self._covered(wo, self._t(wo) ** 2, passed)
        value = c * E_top + W * E_base
        # |d value / d E_top| = c |1 - tau T D E_base| <= c
        return value, (c * err_top + W * err_base) if with_error else None

    def _sampling_weight(self, wo):
        top, base = self._shares(wo, *self._scaled(wo))
        return top + base

    @property
    def weight_is_ratio(self) -> bool:
        return self.top.weight_is_ratio and self.base.weight_is_ratio

    def _energy_scale(self, wo, wi):
        return self.base._energy_scale(wo, wi)  # the top reflects only

    def _energy_scale_rgb(self, wo, wi):
        return self.base._energy_scale_rgb(wo, wi)


#: the albedo-scaling forms of ``Layer`` (module docstring)
SCALINGS = ("albedo", "reciprocal", "transmittance")
#: the normal, where ``Layer`` takes the darkening's base albedo and T2
_NORMAL = np.array([0.0, 0.0, 1.0])
#: ``tol`` of the quadrature of the darkening's base albedo E_b (a base without a table)
DARKENING_ALBEDO_TOL = 1e-6

#: Gauss–Legendre cosines and azimuths of wo, and scrambled-Sobol samples of wi per wo, of
#: ``reciprocal_normalisation``
NORMALISATION_MU, NORMALISATION_PHI, NORMALISATION_SAMPLES = 24, 8, 1024


def reciprocal_normalisation(top: Lobe, base: Lobe, seed: int = 0):
    """``(C, error)``, ``(3,)`` each: the normalisation of the reciprocal albedo scaling
    [Andersson2023, §Layering], f = f_top + C tau (1 - E_top(wi)) (1 - E_top(wo)) f_base.

    Its albedo is E(wo) = E_top(wo) + (1 - E_top(wo)) C I(wo) with tau = 1 and
    I(wo) = int (1 - E_top(wi)) f_base |cos theta_i| d wi. C = min_wo E_base(wo) / I(wo) (per
    channel) is the largest constant with which the layer never reflects more than the
    albedo form's E_top + (1 - E_top) E_base <= 1, whatever the base's colour: over a
    Lambertian base of any albedo rho, I = rho (1 - E_avg,top) and E_base = rho at every wo, so
    C = 1 / (1 - E_avg,top) [Kelemen2001], and the layer keeps the base's albedo (a white base
    keeps all the energy: the white furnace); over a glossy base it loses some where
    E_base / I is above its minimum. A transmittance tau <= 1 only lowers E, so C does not
    depend on it. The minimum is taken over ``NORMALISATION_MU`` Gauss–Legendre cosines times
    ``NORMALISATION_PHI`` azimuths of wo, E_base and I from the same ``NORMALISATION_SAMPLES``
    scrambled-Sobol samples of the base's own sampler, averaged over 4 independent
    scramblings; ``error`` is their spread in C divided by 2 (one standard error). A channel
    the base never reflects has C = 1 (it multiplies 0)."""
    from scipy.stats import qmc

    x, _ = np.polynomial.legendre.leggauss(NORMALISATION_MU)
    mu = 0.5 * (x + 1.0)
    phi = (np.arange(NORMALISATION_PHI) + 0.5) * (2.0 * np.pi / NORMALISATION_PHI)
    M, P = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1.0 - M * M)
    wo = np.stack([s * np.cos(P), s * np.sin(P), M], -1).reshape(-1, 1, 3)
    wo = np.broadcast_to(wo, (len(wo), NORMALISATION_SAMPLES, 3))
    energy, inner = [], []  # E_base(wo), I(wo)
    for k in range(4):
        u = qmc.Sobol(3, scramble=True, seed=seed + k).random(NORMALISATION_SAMPLES)
        sample = base.sample(wo, u)  # (wo, sample)
        g = sample.weight * base._energy_scale_rgb(wo, sample.wi)
        energy.append(g.mean(1))
        inner.append((g * (1.0 - np.minimum(top._top_albedo(sample.wi), 1.0))).mean(1))
    energy, inner = np.array(energy), np.array(inner)  # (scrambling, wo, 3)

    def smallest_ratio(E, inside):
        """min over wo (axis -2) of E / I (``inside``), ignoring directions where I = 0; 1 if
        none."""
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = pick(inside > 0.0, E / pick(inside > 0.0, inside, 1.0), np.inf)
        least = ratio.min(-2)
        return pick(np.isfinite(least), least, 1.0)

    C = smallest_ratio(energy.mean(0), inner.mean(0))
    return C, smallest_ratio(energy, inner).std(0, ddof=1) / 2.0


def coat_absorption(color, eta, w) -> np.ndarray:
    """One-way transmittance t(w) = color ** (1 / (2 mu_t)) ``(..., 3)`` of an absorbing coat
    of index ``eta`` along the validated direction ``w``, mu_t = sqrt(1 - (1 - mu^2) / eta^2)
    the refracted cosine of |mu| = |cos theta| (0 beyond a critical angle, eta < 1: there t
    is 0 unless ``color`` is 1).

    Beer's law exp(-sigma d / mu_t) with sigma d fixed so that the way in and out at normal
    incidence gives ``color`` (the two-way transmittance T, in [0, 1], already validated): the
    pair t(wo) t(wi) = T^((1/mu_o^t + 1/mu_i^t) / 2) is T at normal incidence, darker at
    grazing angles, symmetric in wo and wi [Kutz2021, §7; Andersson2023, §Layering]. Where T
    is 1 (or 0), t is exactly 1 (or 0). A constant colour is raised channel by channel as
    exp(exponent ln T), four times faster than the power and within (1 + |ln t|) eps of it
    (the rounding of the optical depth); a textured one by the power itself."""
    mu = np.abs(np.asarray(w)[..., 2])
    mu_t = np.sqrt(np.maximum(1.0 - (1.0 - mu * mu) / (eta * eta), 0.0))
    with np.errstate(divide="ignore"):
        exponent = pick(mu_t > 0.0, 0.5 / mu_t, np.inf)  # mu_t = 0: grazing, eta <= 1
    color = np.asarray(color)
    if color.shape == (3,):
        t = np.empty(exponent.shape + (3,))
        for k, T in enumerate(color.tolist()):
            if T in (0.0, 1.0):
                t[..., k] = T
            else:
                np.exp(exponent * np.log(T), out=t[..., k])
        return t
    with np.errstate(divide="ignore", invalid="ignore"):
        t = color ** exponent[..., None]
    return pick(color == 1.0, 1.0, pick(color == 0.0, 0.0, t))


class Rotated(Wrapper):
    """``lobe`` with its tangent x axis (alpha_x) turned by ``phi`` about the normal.

    f(wo, wi) = lobe.f(R(-phi) wo, R(-phi) wi), with R(t) the rotation by t about z; samples
    are drawn in the lobe's frame and turned back by R(phi). A rotation about the normal keeps
    cosines, solid angles and the side of every direction, so the pdf, the sample weights,
    the albedo and (generalized) reciprocity carry over unchanged.

    Parameters
    ----------
    lobe : Lobe
    phi : array_like, radians (any real; ``materials.asm.anisotropy_rotation`` maps the ASM's
        anisotropy angle).
    """

    def __init__(self, lobe: Lobe, phi):
        if not isinstance(lobe, Lobe):
            raise ValueError(f"lobe = {lobe!r}: allowed a Lobe")
        self._init(lobe, _params.real("phi", phi))

    def _init(self, lobe, phi):
        self.lobe = lobe
        self.phi = phi
        self.flags = lobe.flags
        self._cos, self._sin = np.cos(self.phi), np.sin(self.phi)

    def __repr__(self) -> str:
        return f"Rotated({self.lobe!r}, phi={self.phi})"

    def _inner(self):
        return self.lobe

    def _param_shape(self):
        shape = self.lobe._param_shape()
        return None if shape is None else np.broadcast_shapes(shape, self.phi.shape)

    def _turn(self, w, sign):
        """R(sign phi) w."""
        c, s = self._cos, sign * self._sin
        x, y = w[..., 0], w[..., 1]
        return np.stack(np.broadcast_arrays(c * x - s * y, s * x + c * y, w[..., 2]), axis=-1)

    @property
    def _identity(self) -> bool:
        """phi = 0: directions pass unturned (the rotation's products would change nothing
        but the sign of a zero component)."""
        return self.phi.ndim == 0 and self.phi == 0.0

    def _to_inner(self, w):
        if self._identity:
            return w
        return _memo.once(self, "to_inner", w, lambda w: self._turn(w, -1.0))

    def _from_inner(self, sample, wo):
        if self._identity:
            return sample
        return BSDFSample(self._turn(sample.wi, 1.0), sample.weight, sample.pdf, sample.flags)


def _mirrored(w, where=True):
    """``w`` mirrored through the surface plane (z -> -z) where ``where``."""
    z = w[..., 2]
    return np.stack(np.broadcast_arrays(w[..., 0], w[..., 1], pick(where, -z, z)), axis=-1)


_R, _TR = int(Flags.REFLECTION), int(Flags.TRANSMISSION)
_SIDES = _R | _TR


class _Mirroring(Wrapper):
    """Base of ``Flipped`` and ``Facing``: one inner lobe seen through the mirror
    M = diag(1, 1, -1) of the surface plane (the subclass says which directions it mirrors)."""

    def __init__(self, lobe: Lobe):
        if not isinstance(lobe, Lobe):
            raise ValueError(f"lobe = {lobe!r}: allowed a Lobe")
        self._init(lobe)

    def _init(self, lobe):
        self.lobe = lobe
        self.flags = self._flags(lobe.flags)

    @staticmethod
    def _flags(flags):
        """The flags of the mirrored lobe."""
        return flags

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.lobe!r})"

    def _inner(self):
        return self.lobe

    def _param_shape(self):
        return self.lobe._param_shape()


class Flipped(_Mirroring):
    """``lobe`` with its scattered side mirrored through the surface plane,
    f(wo, wi) = lobe.f(wo, M wi), M = diag(1, 1, -1): a reflection lobe becomes a transmission
    lobe into the other hemisphere (and the reverse), as in a thin sheet whose two faces are
    one surface [OpenPBR2026, §Thin-walled mode] (the unit-albedo diffuse f_- of the
    thin-walled subsurface, the straight-through transmission of a thin dielectric).

    M keeps |cos theta_i| and solid angles, so pdfs, sample weights and the albedo carry over
    (no index changes across the sheet: no radiance scaling); sampled directions are mirrored
    and their REFLECTION and TRANSMISSION flags swapped. Reciprocity: f(wi, wo) = f(wo, wi)
    where the lobe is reciprocal and symmetric under M applied to both directions; for a lobe
    of one side only, evaluate it under ``Facing``, which makes wo face it.

    Parameters
    ----------
    lobe : Lobe
    """

    @staticmethod
    def _flags(flags):
        return Flags(_swap_sides(int(flags)))

    def _directions(self, wo, wi):
        return wo, None if wi is None else _mirrored(wi)

    def _from_inner(self, sample, wo):
        return BSDFSample(_mirrored(sample.wi), sample.weight, sample.pdf,
                          _swap_sides(sample.flags))


def _swap_sides(flags):
    """``flags`` with REFLECTION and TRANSMISSION exchanged."""
    both = _R | _TR
    swapped = ((flags & _R) != 0) * _TR | ((flags & _TR) != 0) * _R
    return (flags & ~both) | swapped


class Facing(_Mirroring):
    """``lobe`` always seen from its top side: where wo is below the surface both directions
    are mirrored through the plane, f(wo, wi) = lobe.f(M wo, M wi), and samples mirrored back
    (the "always facing" sheet of [Andersson2023, §Thin-walled case] that OpenPBR v1.1.1
    recommends for thin walls: the ray enters from the top whichever side it hits).

    M keeps cosines' magnitudes and solid angles: pdfs, weights and albedos are the lobe's at
    M wo, the flags unchanged. Where the lobe is reciprocal, so is the facing sheet for pairs
    on one side; across the sheet f(wo, wi) = f(M wi, M wo) relates the two sides, which is
    reciprocity where the lobe is symmetric under M (``Flipped`` lobes of reciprocal
    ones).

    Parameters
    ----------
    lobe : Lobe
    """

    def _directions(self, wo, wi):
        below = wo[..., 2] < 0.0
        return _mirrored(wo, below), None if wi is None else _mirrored(wi, below)

    def _from_inner(self, sample, wo):
        below = np.broadcast_to(wo[..., 2] < 0.0, sample.pdf.shape)
        return BSDFSample(_mirrored(sample.wi, below), sample.weight, sample.pdf, sample.flags)


def choose(P, u):
    """Pick component k with probability ``P[k]`` (``P`` (K, ...), summing to 1 over its
    first axis) by the first uniform of ``u`` (..., 3), and re-use that uniform inside the
    chosen interval (so a component that branches on it stays stratified).

    Returns ``(k (...), P_k (...), u (..., 3))``, broadcast over ``P.shape[1:]`` and
    ``u.shape[:-1]``.
    """
    batch = np.broadcast_shapes(P.shape[1:], u.shape[:-1])
    u0 = u[..., 0]
    # interval j is [cdf_{j-1}, cdf_j), cdf_j = P_0 + ... + P_j summed in order (the last
    # one open: rounding may leave cdf_{K-1} below 1)
    k = np.zeros(batch, dtype=np.intp)
    lo, Pk = np.zeros(batch), np.broadcast_to(P[0], batch)
    cdf = P[0]
    for j in range(1, len(P)):
        beyond = u0 >= cdf
        k += beyond
        lo = pick(beyond, cdf, lo)
        Pk = pick(beyond, P[j], Pk)
        if j + 1 < len(P):
            cdf = cdf + P[j]
    out = np.array(np.broadcast_to(u, batch + (3,)))  # u1, u2 as they are
    with np.errstate(divide="ignore", invalid="ignore"):
        np.clip((u0 - lo) / pick(Pk > 0.0, Pk, 1.0), 0.0, np.nextafter(1.0, 0),
                out=out[..., 0])
    return k, np.array(Pk), out


def _by_groups(components, wo, u, weights=()) -> bool:
    """Whether a mixture of ``components`` samples by ``_mixture_sample``: a flat batch,
    scalar parameters and weights, and sample weights that are f |cos| / pdf."""
    return (len(np.broadcast_shapes(wo.shape, u.shape)) == 2
            and all(c._param_shape() == () and c.weight_is_ratio for c in components)
            and all(w is None or w.shape[:-1] == () for w in weights))


def _mixture_sample(components, k, wo, u, throughput, combine):
    """``(wi, weight, pdf, flags)`` of a mixture's sample, failures not zeroed, group by
    group: the elements that chose component j (``k`` (n,)) are sampled by its ``_sample_t``
    and every other component is evaluated (``_eval_pdf_t``) on them only, at the sampled
    directions; component j's own f |cos| is its sample's weight times pdf (not evaluated
    again). ``combine(j, index, wo_j, s_j, parts)`` gives the group's (weight, pdf) from
    ``parts[i] = (f_i |cos|, pdf_i)``. ``wo``, ``u`` (n, 3); ``throughput`` None or
    broadcastable to them."""
    n = k.shape[0]
    wi, weight = np.empty((n, 3)), np.empty((n, 3))
    pdf, flags = np.empty(n), np.empty(n, dtype=np.int64)
    paths = None if throughput is None else np.broadcast_to(throughput, u.shape)
    for j, c in enumerate(components):
        index = np.flatnonzero(k == j)
        if not len(index):
            continue
        wo_j = _memo.rows(wo, index)  # quantities of wo kept for the batch serve its rows
        t = None if paths is None else take_rows(paths, index)
        s = c._sample_t(wo_j, take_rows(u, index), t)
        cos = np.abs(s.wi[:, 2])
        parts = []
        for i, other in enumerate(components):
            if i == j:
                parts.append((weighted(s.weight, s.pdf), s.pdf))
            else:
                f, p = _on_its_side(other, wo_j, s.wi, t)
                parts.append((weighted(f, cos), p))
        w, p = combine(j, index, wo_j, s, parts)
        put_rows(wi, index, s.wi)
        put_rows(weight, index, w)
        pdf[index], flags[index] = p, s.flags
    return wi, weight, pdf, flags


def _on_its_side(lobe, wo, wi, throughput):
    """``lobe._eval_pdf_t(wo, wi, throughput)`` at directions another component sampled
    (``wo``, ``wi`` (m, 3)): a ``Sum`` or ``Layer`` that only reflects (only transmits) is
    evaluated on the pairs not on opposite sides (on the same side) alone, and is 0 on the
    others, where every lobe of it is 0; its levels would otherwise each weigh and combine
    those pairs (its leaf lobes restrict themselves to their support)."""
    sides = lobe.flags & _SIDES
    if sides in (0, _SIDES) or not isinstance(lobe, (Sum, Layer)):
        return lobe._eval_pdf_t(wo, wi, throughput)
    product = wo[:, 2] * wi[:, 2]
    outside = product < 0.0 if sides == _R else product > 0.0
    if not outside.any():
        return lobe._eval_pdf_t(wo, wi, throughput)
    m = len(wo)
    f, pdf = np.zeros((m, 3)), np.zeros(m)
    index = np.flatnonzero(~outside)
    if len(index):
        t = None if throughput is None else take_rows(np.broadcast_to(throughput, (m, 3)),
                                                      index)
        fi, pi = lobe._eval_pdf_t(_memo.rows(wo, index), take_rows(wi, index), t)
        put_rows(f, index, np.broadcast_to(fi, (len(index), 3)))
        pdf[index] = pi
    return f, pdf


def _chosen_samples(components, k, wo, u, throughput, weights=None):
    """``(wi, weight, pdf, flags)`` of every element sampled by the component ``k`` it chose
    (``_sample_directions``; weights times ``weights[k]`` where given), zero where the
    component failed. Where the parameters and weights are scalars and the batch flat, each
    component runs on the elements that chose it, written into the outputs in place."""
    batch = k.shape
    weights = [None] * len(components) if weights is None else weights
    flat = (wo.ndim == 2 and u.ndim == 2 and all(c._param_shape() == () for c in components)
            and all(w is None or w.shape[:-1] == () for w in weights))
    wi, weight = np.zeros(batch + (3,)), np.zeros(batch + (3,))
    pdf, flags = np.zeros(batch), np.full(batch, int(Flags.NONE))
    for j, (c, w) in enumerate(zip(components, weights, strict=True)):
        if not flat:
            chosen = k == j
            s = c._sample_directions(wo, u, throughput)
            wi = pick(chosen[..., None], s.wi, wi)
            weight = pick(chosen[..., None], s.weight if w is None else s.weight * w,
                              weight)
            pdf = pick(chosen, s.pdf, pdf)
            flags = pick(chosen, s.flags, flags)
            continue
        index = np.flatnonzero(k == j)
        if not len(index):
            continue
        t = None if throughput is None else take_rows(np.broadcast_to(throughput, u.shape),
                                                      index)
        s = c._sample_directions(take_rows(wo, index), take_rows(u, index), t)
        put_rows(wi, index, s.wi)
        put_rows(weight, index, s.weight if w is None else scaled(s.weight, w))
        pdf[index], flags[index] = s.pdf, s.flags
    return wi, weight, pdf, flags


def sample_where(lobe: Lobe, wo, u, throughput, chosen) -> BSDFSample:
    """``lobe._sample_t(wo, u, throughput)`` computed for the elements ``chosen`` only (for
    all of them if the lobe's parameters are not scalars or the batch is not flat), scattered
    into full-size arrays (zero elsewhere)."""
    if lobe._param_shape() != () or wo.ndim != 2 or u.ndim != 2:
        return lobe._sample_t(wo, u, throughput)
    index = np.flatnonzero(chosen)
    if throughput is not None:
        throughput = take_rows(np.broadcast_to(throughput, u.shape), index)
    part = lobe._sample_t(take_rows(np.broadcast_to(wo, u.shape), index), take_rows(u, index),
                          throughput)
    n = u.shape[0]
    full = []
    for field in part:
        out = np.zeros((n,) + field.shape[1:], dtype=field.dtype)
        put_rows(out, index, field)
        full.append(out)
    return BSDFSample(*full)
