"""A rough dielectric whose index depends on the colour channel: dispersion [Kutz2021, §4]."""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params, fresnel
from adobe_bsdf._channels import pick
from adobe_bsdf.bsdf import Flags, Lobe, finished_sample
from adobe_bsdf.composition import choose, sample_where
from adobe_bsdf.dispersion import RGB_WAVELENGTHS_NM, cauchy, wavelengths
from adobe_bsdf.lobes.dielectric import Dielectric, interface_energy_scale
from adobe_bsdf.lobes.energy_lookup import checked_ratio
from adobe_bsdf.microfacet import distribution

__all__ = ["Dispersive", "channel_probabilities"]

_CHANNELS = range(3)
#: the default channel wavelengths, validated
_RGB_NM = wavelengths(RGB_WAVELENGTHS_NM)


def channel_probabilities(throughput, shape=()) -> np.ndarray:
    """p_c = t_c / sum_c t_c ``(..., 3)``: channel selection proportional to the path
    throughput [Kutz2021, §4]; white (``None``) or a throughput of 0 (a path that carries
    nothing) gives 1/3 each."""
    if throughput is None:
        return np.full(tuple(shape) + (3,), 1.0 / 3.0)
    total = throughput.sum(axis=-1, keepdims=True)
    return pick(total > 0.0, throughput / pick(total > 0.0, total, 1.0), 1.0 / 3.0)


def _channel_indices(eta, dispersion, wavelengths_nm):
    """eta_c per channel ``(..., 3)``: Cauchy's indices of the dense side, n_d = max(eta,
    1/eta), as seen from above (inverted where the dense medium is above, eta < 1)."""
    dense = eta >= 1.0
    n_d = pick(dense, eta, 1.0 / eta)
    n_c = cauchy(n_d, dispersion, wavelengths_nm)
    crossed = (n_c <= 1.0) & (n_d[..., None] > 1.0)
    if np.any(crossed):
        bad = np.broadcast_to(np.asarray(dispersion)[..., None], crossed.shape)[crossed][0]
        raise ValueError(f"dispersion = {bad!r} takes a channel's index to 1 or below for "
                         f"eta = {np.broadcast_to(eta[..., None], crossed.shape)[crossed][0]!r};"
                         " allowed: dispersions that keep every channel's index above 1")
    return pick(dense[..., None], n_c, 1.0 / n_c)


class Dispersive(Lobe):
    """Rough dielectric boundary with one relative index eta_c per RGB channel [Kutz2021, §4].

    Channel c of f is channel c of ``Dielectric(eta_c, alpha_x, alpha_y)``, with eta_c from
    Cauchy's equation through (n_d, V_d = 20 / ``dispersion``) at the channel wavelengths of
    ``adobe_bsdf.dispersion``. Reflection keeps its direction and changes only its Fresnel
    per channel; refraction sends each channel its own way, so, as in the renderer of
    [Kutz2021, §4], "the transmission component of the specular lobe" becomes three lobes.

    Sampling follows the paper: channel c's dielectric is chosen with probability p_c
    proportional to the path throughput (``sample(wo, u, throughput)``, default white;
    ``channel_probabilities``), sampled, and the direction weighed by the one-sample balance
    heuristic [Veach1997, §9.2.4]: pdf = sum_c p_c pdf_c(wo, wi) and
    weight = f(wo, wi) |cos i| / pdf, RGB. A channel with throughput 0 is never chosen, and
    its weight is then only exact where another channel's pdf covers its support; such a
    path carries nothing in that channel. ``pdf`` must be given the same throughput.

    On a smooth interface the three reflections coincide: a reflected sample has probability
    sum_c p_c F_c and weight F_c / sum_c p_c F_c. Transmitted samples of channels with equal
    indices coincide too (all channels where dispersion is 0).

    Dispersion 0 is exactly the non-dispersive ``Dielectric``: every channel then has the
    index n_d (``cauchy_iors``), and where that holds for every element the lobe runs one
    ``Dielectric`` (``single``), bit for bit.

    Parameters
    ----------
    eta : array_like in (0, inf)
        n_d below / n above at the d line (as ``Dielectric``); the dispersive medium is the
        denser side (for eta < 1 the channel indices are 1 / Cauchy's indices of 1 / eta).
    dispersion : array_like in [0, inf)
        The Dispersion parameter of [Kutz2021, eq. 12], 20 / V_d; it may not take a
        channel's index to 1.
    alpha_x, alpha_y, masking, model
        As ``Dielectric``.
    wavelengths_nm : three floats
        The channels' wavelengths (default ``RGB_WAVELENGTHS_NM``).
    """

    flags = Dielectric.flags
    #: ``eta`` holds one index per channel (read by ``validation.checks.reciprocity_error``)
    eta_per_channel = True

    def __init__(self, eta, dispersion, alpha_x, alpha_y=None, masking: str = "correlated",
                 model: str = "ggx", wavelengths_nm=RGB_WAVELENGTHS_NM):
        eta = _params.real("eta", eta, 0.0, np.inf, lo_open=True)
        dispersion = _params.real("dispersion", dispersion, 0.0, np.inf)
        if np.shape(wavelengths_nm) != (3,):
            raise ValueError(f"wavelengths_nm = {wavelengths_nm!r}: allowed three wavelengths")
        self._init(eta, dispersion, distribution(model, alpha_x, alpha_y, masking),
                   wavelengths(wavelengths_nm))

    def _init(self, eta, dispersion, microfacets, wavelengths_nm=_RGB_NM, film=None):
        """``film``: None, or ``film(eta_c)``, the thin film over a channel's index (a
        ``fresnel.Fresnel`` model; ``Dielectric(film=)``); channel c reads channel c of its
        film's colour."""
        self.dispersion = dispersion
        #: eta_c, ``(..., 3)``
        self.eta = _channel_indices(eta, dispersion, wavelengths_nm)
        self.distribution = microfacets
        self.channels = tuple(
            Dielectric._new(self.eta[..., c], microfacets,
                            None if film is None else film(self.eta[..., c]))
            for c in _CHANNELS)
        same = (self.eta[..., 0] == self.eta[..., 1]) & (self.eta[..., 1] == self.eta[..., 2])
        #: the one ``Dielectric`` all channels share where nothing disperses, else None
        self.single = self.channels[0] if np.all(same) else None

    def __repr__(self) -> str:
        return (f"Dispersive(eta={self.eta!r}, dispersion={self.dispersion!r}, "
                f"{self.distribution!r})")

    def _param_shape(self):
        return self.channels[0]._param_shape()

    # -- per channel ----------------------------------------------------------------------
    def _each(self, method, *args):
        """Channel c of ``method`` of channel c's dielectric, stacked ``(..., 3)``."""
        return np.stack([getattr(ch, method)(*args)[..., c]
                         for c, ch in zip(_CHANNELS, self.channels, strict=True)], axis=-1)

    def _eval(self, wo, wi):
        if self.single is not None:
            return self.single._eval(wo, wi)
        return self._each("_eval", wo, wi)

    def _delta_albedo(self, wo):
        return self._each("_delta_albedo", wo)

    def _albedo_table(self, wo, with_error=True):
        # a channel's index outside the tables: a message naming the channel and dispersion
        checked_ratio(self.eta, "ggx_dielectric_outside and ggx_dielectric_inside",
                      dispersion=self.dispersion)
        parts = [ch._albedo_table(wo, with_error) for ch in self.channels]
        value = np.stack([p[0][..., c] for c, p in zip(_CHANNELS, parts, strict=True)], -1)
        error = (np.stack([p[1][..., c] for c, p in zip(_CHANNELS, parts, strict=True)], -1)
                 if with_error else None)
        return value, error

    def _albedo_quadrature(self, wo, tol):
        """Channel c integrates channel c's dielectric (each on its own edge-aligned map)."""
        parts = [ch._albedo_quadrature(wo, tol) for ch in self.channels]
        return tuple(np.stack([p[j][..., c] for c, p in zip(_CHANNELS, parts, strict=True)], -1)
                     for j in (0, 1))

    def _energy_scale_rgb(self, wo, wi):
        return np.stack([interface_energy_scale(self.eta[..., c], wo, wi) for c in _CHANNELS],
                        axis=-1)

    def _energy_scale(self, wo, wi):
        """The middle (green) channel's: where one scale must stand for all (the edges of
        ``quadrature.albedo``'s map when this lobe is part of a larger BSDF)."""
        return interface_energy_scale(self.eta[..., 1], wo, wi)

    def _sampling_weight(self, wo):
        return np.ones(wo.shape[:-1])  # lossless interface: R + T = 1 before masking

    # -- the mixture of the three channels' samplers --------------------------------------
    def _pdf(self, wo, wi):
        return self._pdf_t(wo, wi, None)

    def _eval_pdf(self, wo, wi):
        return self._eval_pdf_t(wo, wi, None)

    def _pdf_t(self, wo, wi, throughput):
        if self.single is not None:
            return self.single._pdf(wo, wi)
        p = channel_probabilities(throughput)
        return sum(p[..., c] * ch._pdf(wo, wi) for c, ch in zip(_CHANNELS, self.channels,
                                                                 strict=True))

    def _eval_pdf_t(self, wo, wi, throughput):
        if self.single is not None:
            return self.single._eval_pdf(wo, wi)
        p = channel_probabilities(throughput)
        f, pdf = [], 0.0
        for c, ch in zip(_CHANNELS, self.channels, strict=True):
            fc, pc = ch._eval_pdf(wo, wi)
            f.append(fc[..., c])
            pdf = pdf + p[..., c] * pc
        return np.stack(f, axis=-1), pdf

    def _sample(self, wo, u):
        return self._sample_t(wo, u, None)

    def _sample_t(self, wo, u, throughput):
        """Choose channel k with the first uniform (re-used inside its interval), sample its
        dielectric, weigh by the mixture (see the class docstring)."""
        if self.single is not None:
            return self.single._sample(wo, u)
        batch = np.broadcast_shapes(wo.shape, u.shape)[:-1]
        wo = np.broadcast_to(wo, batch + (3,))
        p = np.broadcast_to(channel_probabilities(throughput, batch), batch + (3,))
        k, _, u = choose(np.moveaxis(p, -1, 0), u)
        wi, flags = np.zeros(batch + (3,)), np.full(batch, int(Flags.NONE))
        for c, ch in zip(_CHANNELS, self.channels, strict=True):
            chosen = k == c
            s = sample_where(ch, wo, u, None, chosen)
            wi = pick(chosen[..., None], s.wi, wi)
            flags = pick(chosen, s.flags, flags)
        f, pdf = self._eval_pdf_t(wo, wi, throughput)
        with np.errstate(divide="ignore", invalid="ignore"):
            weight = f * np.abs(wi[..., 2:3]) / pdf[..., None]
        delta = (flags & int(Flags.DELTA)) != 0
        if np.any(delta):
            d_weight, d_pdf = self._delta_mixture(wo, k, flags, p)
            weight = pick(delta[..., None], d_weight, weight)
            pdf = pick(delta, d_pdf, pdf)
        return finished_sample(wi, weight, pdf, flags)

    def _delta_mixture(self, wo, k, flags, p):
        """(weight, probability) of delta samples of channel ``k`` (a smooth interface, or a
        channel that passes straight through, ``dielectric.passes_through``): the
        directions that several channels share are summed over them.

        Reflection: every channel's mirror direction is the same, probability
        sum_c p_c F_c, weight F_c / that. Refraction: shared by the channels with the index
        of ``k`` (and by every pass-through channel if ``k`` passes through), probability
        sum_c p_c P_c over those, weight T_c / eta_c'^2 / that (radiance: eta_c' = eta_c
        from the side of ``wo``), where a smooth channel has P_c = T_c = 1 - F_c and a
        pass-through P_c = 1, T_c its energy (``Dielectric._pass_energy``) and F_c = 0.
        F_c = ``fresnel.dielectric`` at cos theta_o (1 under total internal reflection); with a
        film, the values (not the probabilities) take its reflectance R_c in place of F_c
        and T_c = 1 - R_c.
        """
        below = (wo[..., 2] < 0.0)[..., None]
        eta = pick(below, 1.0 / self.eta, self.eta)  # far side / wo's side, per channel
        passes = np.stack(np.broadcast_arrays(*(ch.passes for ch in self.channels)), -1)
        F = fresnel.dielectric(np.abs(wo[..., 2])[..., None], eta)
        F = pick(passes, 0.0, F)
        T = 1.0 - F
        if np.any(passes):
            zo = np.abs(wo[..., 2])
            T = pick(passes, np.stack([ch._pass_energy(wo[..., 0], wo[..., 1], zo)
                                           for ch in self.channels], -1), T)
        P = pick(passes, 1.0, 1.0 - F)
        reflected = ((flags & int(Flags.REFLECTION)) != 0)[..., None]
        shape = np.broadcast_shapes(F.shape, k.shape + (1,))

        def of_k(x):
            return np.take_along_axis(np.broadcast_to(x, shape), k[..., None], -1)

        shared = (eta == of_k(eta)) | (passes & of_k(passes))
        R = F
        if self.channels[0].film is not None:  # the film's reflectance in place of F
            R = np.stack([ch.film_reflectance(wo)[..., c]
                          for c, ch in zip(_CHANNELS, self.channels, strict=True)], -1)
            R = pick(passes, 0.0, R)
            T = pick(passes, T, 1.0 - R)
        value = pick(reflected, R, pick(shared, T, 0.0) / (eta * eta))
        mass = (p * pick(reflected, F, pick(shared, P, 0.0))).sum(axis=-1)
        with np.errstate(divide="ignore", invalid="ignore"):
            return value / mass[..., None], mass
