"""A thin-walled translucent sheet: an infinitesimally thin, absorbing, non-scattering dielectric
slab with two parallel faces, seen the same from both sides.

Public API
----------
``sheet_coefficients(cos2, eta, transmittance)``  reflectance R and transmittance T of a
                                                  smooth sheet, summed over its internal
                                                  reflections.
``SheetReflectance(eta, transmittance)``          R as a ``fresnel.Fresnel`` model.
``SheetTransmittance(eta, transmittance)``        T as a ``fresnel.Fresnel`` model.
``ThinDielectric(eta, alpha_x, alpha_y=None, transmittance=1, film=None)``
                                                  the sheet as a lobe, smooth or rough,
                                                  with a thin film on its faces or not.

The smooth sheet
----------------
Light meets the first face at cos theta, is reflected with the exact dielectric Fresnel
F = F(cos theta, eta) [BornWolf1980, §1.5.2] or enters at cos theta_t = sqrt(1 - (1 - cos^2
theta) / eta^2), crosses the sheet with the one-pass transmittance tau = A^(1 / cos theta_t)
(Beer's law along the refracted path, A its value at normal incidence), and meets the second
face at the same theta_t. There the Fresnel reflectance from inside equals F (the Fresnel
equations are symmetric under exchanging the incident and refracted angles), and by Snell's
law sin theta_out = eta sin theta_t = sin theta <= 1: light that entered a parallel sheet
always leaves it, total internal reflection is impossible inside (for eta < 1 the only total
reflection is at the entry, beyond the critical angle, where F = 1). Summing the paths with
2k internal reflections, the geometric series [OpenPBR2026, §Thin-walled mode] is

    T = (1 - F)^2 tau sum_k (F tau)^(2k)          = (1 - F)^2 tau / (1 - F^2 tau^2),
    R = F + (1 - F)^2 F tau^2 sum_k (F tau)^(2k)  = F + F tau T,

reflected to the mirror direction and transmitted straight through to -wo (the faces are
parallel: the ray leaves at the angle it came in). For a clear sheet (A = 1) R + T = 1; for
A < 1 R + T < 1. ``eta`` = 1 has no interfaces: R = 0, T = tau = A^(1 / cos theta).

The rough sheet
---------------
Roughened as [KullaConty2017] do: reflection is GGX microfacet reflection (``Conductor``)
whose Fresnel is the sheet's R(cos theta_h), transmission the same lobe with Fresnel
T(cos theta_h) mirrored through the surface plane (``composition.Flipped``: centred on -wo),
and the energy the microfacets lose to single scattering is restored by the white
Kulla–Conty term (``ConductorMultipleScattering``, F = 1), split between reflection and
flipped transmission with the weights R_avg = 2 int R mu dmu and T_avg = 2 int T mu dmu
(Gauss–Legendre). A clear sheet has R + T = 1 at every angle, so its single scattering
is that of the F = 1 lobe and the two terms add up to its loss: R + T = 1 to the energy
tables' accuracy (the white furnace). An absorbing sheet has R_avg + T_avg < 1 and never
gains. The whole lobe is ``composition.Facing``: a ``wo`` below the sheet sees the mirrored
configuration, so both sides are the same sheet.
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _params, quadrature
from adobe_bsdf._channels import pick
from adobe_bsdf.composition import Facing, Flipped, Sum
from adobe_bsdf.fresnel import Fresnel, _dielectric_k, _k_of_indices
from adobe_bsdf.lobes.dielectric import _film
from adobe_bsdf.lobes.energy_lookup import conductor_energy, grey
from adobe_bsdf.lobes.kulla_conty import ConductorMultipleScattering
from adobe_bsdf.lobes.reflection import Conductor
from adobe_bsdf.microfacet import GGX

__all__ = ["sheet_coefficients", "SheetReflectance", "SheetTransmittance", "ThinDielectric",
           "AVERAGE_NODES"]

#: Gauss–Legendre nodes of the hemispherical averages R_avg, T_avg (on the cosines where the
#: sheet is entered; the exact rule for a polynomial of degree 2 AVERAGE_NODES - 1)
AVERAGE_NODES = 64


def _eta(eta) -> np.ndarray:
    return _params.real("eta", eta, 0.0, np.inf, lo_open=True)


def _transmittance(transmittance) -> np.ndarray:
    return _params.color("transmittance", transmittance, 0.0, 1.0)


def sheet_coefficients(cos2, eta, transmittance, film=None) -> tuple[np.ndarray, np.ndarray]:
    """``(R, T)``, each ``(..., 3)`` in [0, 1], of a smooth sheet of relative index ``eta``
    (validated, (0, inf)) and normal-incidence one-pass transmittance ``transmittance``
    (a validated colour ``(..., 3)`` in [0, 1]) entered at cos^2 theta = ``cos2`` in [0, 1]
    (module docstring).

    Computed free of cancellation: 1 - F^2 tau^2 = ((1 - F) + F (1 - tau)) (1 + F tau),
    both factors sums of non-negative terms, and 1 - tau = -expm1(ln(A) / cos theta_t).
    Degenerate cases, explicitly: F = 1 and tau = 1 (total reflection at the entry of a clear
    sheet, or a grazing cosine) give R = 1, T = 0; A = 1 gives tau = 1 even where
    cos theta_t = 0; A = 0 gives tau = 0.

    With ``film`` (a ``fresnel.Fresnel`` model of the film on the sheet's face, e.g.
    ``thin_film.ThinFilm(d, n_film, eta)``) the face the light meets first reflects
    F_1 = film(cos theta) (the same from inside: a non-absorbing film reflects alike from
    both sides at corresponding angles), the other face F_2 = F:

        T = (1 - F_1)(1 - F_2) tau / (1 - F_1 F_2 tau^2),
        R = F_1 + (1 - F_1)^2 F_2 tau^2 / (1 - F_1 F_2 tau^2),

    so R + T = 1 for a clear sheet, T is the same from either face (reciprocity), and at
    eta = 1 (no faces of its own) the sheet is the film alone: R = F_1, T = 1 - F_1 (a soap
    bubble) [OpenPBR2026, §Thin-film iridescence].
    """
    cos2 = np.asarray(cos2, dtype=np.float64)
    k, eta2 = _k_of_indices(eta), eta * eta
    F = _dielectric_k(np.sqrt(cos2), k, eta2)[..., None]
    inside = np.maximum((k + cos2) / eta2, 0.0)[..., None]  # cos^2 theta_t (0: no entry)
    with np.errstate(divide="ignore", invalid="ignore"):  # 0 / 0 where A = 1: masked
        log_a = np.log(transmittance)  # -inf where A = 0
        exponent = pick(transmittance == 1.0, 0.0, log_a / np.sqrt(inside))
    tau, loss = np.exp(exponent), -np.expm1(exponent)  # tau and 1 - tau
    if film is not None:
        return _filmed(np.asarray(film.from_cos2(cos2), dtype=np.float64), F, tau, exponent)
    den = ((1.0 - F) + F * loss) * (1.0 + F * tau)  # 1 - F^2 tau^2
    with np.errstate(divide="ignore", invalid="ignore"):
        T = pick(den > 0.0, np.square(1.0 - F) * tau / den, 0.0)
    T = np.minimum(T, 1.0)
    return np.minimum(F + F * tau * T, 1.0), T


def _filmed(F1, F2, tau, exponent):
    """``(R, T)`` of the sheet whose first face reflects ``F1`` (the film) and second ``F2``
    (``sheet_coefficients``), free of cancellation: 1 - F_1 F_2 tau^2 = (1 - F_1) +
    F_1 ((1 - F_2) + F_2 (1 - tau^2)), every term >= 0; where it is 0, F_1 = 1: R = 1,
    T = 0."""
    loss2 = -np.expm1(2.0 * exponent)  # 1 - tau^2
    den = (1.0 - F1) + F1 * ((1.0 - F2) + F2 * loss2)
    ok = den > 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        T = pick(ok, (1.0 - F1) * (1.0 - F2) * tau / den, 0.0)
        R = F1 + pick(ok, np.square(1.0 - F1) * F2 * (tau * tau) / den, 0.0)
    return np.minimum(R, 1.0), np.minimum(T, 1.0)


class _Sheet(Fresnel):
    """One of the sheet's coefficients (``_part``: 0 for R, 1 for T) as a Fresnel model."""

    _part = 0

    def __init__(self, eta, transmittance=1.0, film=None):
        self._init(_eta(eta), _transmittance(transmittance), _film(film))

    def _init(self, eta, transmittance, film=None):
        self.eta, self.transmittance, self.film = eta, transmittance, film
        #: batch shape of the parameters (beyond the colour axis)
        self.param_shape = np.broadcast_shapes(eta.shape, transmittance.shape[:-1],
                                               () if film is None else film.param_shape)

    def __repr__(self) -> str:
        film = "" if self.film is None else f", film={self.film!r}"
        return (f"{type(self).__name__}(eta={self.eta}, transmittance={self.transmittance}"
                f"{film})")

    def from_cos2(self, c2) -> np.ndarray:
        return sheet_coefficients(c2, self.eta, self.transmittance, self.film)[self._part]


class SheetReflectance(_Sheet):
    """The reflectance R(cos theta) ``(..., 3)`` of a smooth sheet (``sheet_coefficients``)
    as a ``fresnel.Fresnel`` model; the same for cos theta and -cos theta (both faces).

    Parameters
    ----------
    eta : array_like in (0, inf)
        Index of the sheet over that of its surroundings.
    transmittance : colour in [0, 1]
        One-pass internal transmittance at normal incidence (1: clear).
    film : fresnel.Fresnel, optional
        The thin film on the face met first (``sheet_coefficients``).
    """


class SheetTransmittance(_Sheet):
    """The transmittance T(cos theta) ``(..., 3)`` of a smooth sheet (``sheet_coefficients``)
    as a ``fresnel.Fresnel`` model; parameters as ``SheetReflectance``."""

    _part = 1


def _hemispherical_averages(eta, transmittance, film=None):
    """``(R_avg, T_avg)`` ``(..., 3)``: 2 int_0^1 X(mu) mu dmu of the sheet's coefficients.

    Where eta < 1 the cosines below the critical one, mu_c = sqrt(1 - eta^2), reflect totally
    (R = 1, T = 0: mu_c^2 of R_avg exactly); the Gauss–Legendre rule runs over [mu_c, 1],
    where the coefficients are smooth."""
    ndim = max(np.ndim(eta), transmittance.ndim - 1)
    x, w = np.polynomial.legendre.leggauss(AVERAGE_NODES)
    x, w = (a.reshape((-1,) + (1,) * ndim) for a in (0.5 * (x + 1.0), 0.5 * w))
    mu_c = np.sqrt(np.maximum(-_k_of_indices(eta), 0.0))  # 0 where eta >= 1
    mu = mu_c + (1.0 - mu_c) * x
    R, T = sheet_coefficients(mu * mu, eta, transmittance, film)
    weight = (2.0 * w * mu * (1.0 - mu_c))[..., None]
    total = mu_c * mu_c
    return (weight * R).sum(0) + total[..., None], (weight * T).sum(0)


class ThinDielectric(Facing):
    """A thin, absorbing, non-scattering dielectric sheet, smooth or rough, the same from
    both sides: reflection R to the mirror direction and straight-through transmission T of
    ``sheet_coefficients`` (module docstring; [OpenPBR2026, §Thin-walled mode]), roughened as
    [KullaConty2017] with their multiple-scattering term.

    ``Facing(Sum(Conductor(R), Flipped(Conductor(T)), R_avg f_ms, T_avg Flipped(f_ms)))``
    over one GGX distribution, f_ms the white ``ConductorMultipleScattering``. Smooth (both
    alphas below ``microfacet.ALPHA_MIN``): a delta reflection of energy R(cos theta_o) and a
    delta transmission of energy T(cos theta_o), sampled in proportion to their luminances
    (``Sum`` picks by ``Conductor``'s sampling weight, the luminance of its Fresnel). Where
    ``eta`` = 1 there are no faces to scatter at: the sheet is smooth whatever the alphas,
    a straight transmission of energy tau = A^(1 / cos theta_o).

    The sheet has the same medium on both sides: no radiance scaling across it, ``eta`` (the
    protocol's interface index n_below / n_above) is None, reciprocity is
    f(wo, wi) = f(wi, wo) on either side and across. ``albedo(method="table")`` (also the
    albedo as a layer's top) reads the F = 1 energy table and scales its single-scattering
    part by a 32 x 32 Gauss rule over the visible normals (``_albedo_table``): 3 x 1024
    samples per distinct direction; exactly 1 for a clear sheet.

    Parameters
    ----------
    eta : array_like in (0, inf)
        Index of the sheet over that of its surroundings (``sheet_eta``).
    alpha_x, alpha_y : array_like in [0, tables.ALPHA_MAX]
        GGX roughness of both faces (``alpha_y`` defaults to ``alpha_x``).
    transmittance : colour in [0, 1]
        One-pass internal transmittance at normal incidence; 1 is a clear sheet.
    film : fresnel.Fresnel, optional
        A thin film on the faces (``thin_film.ThinFilm(d, n_film, eta)``), met first from
        either side (``sheet_coefficients``): it colours both the reflection and the
        transmission, and a clear sheet keeps R + T = 1. With a film, an index-1 sheet has
        faces (the film's): a soap bubble, rough where the alphas are.
    """

    def __init__(self, eta, alpha_x, alpha_y=None, transmittance=1.0, film=None):
        eta = _eta(eta)
        transmittance = _transmittance(transmittance)
        self._init_sheet(eta, GGX(alpha_x, alpha_y), transmittance, _film(film))

    def _init_sheet(self, eta, distribution: GGX, transmittance, film=None):
        #: the sheet's relative index (n_sheet / n_surroundings)
        self.sheet_eta = eta
        self.transmittance = transmittance
        #: the film on its faces (None: none)
        self.film = film
        if film is None and np.any(eta == 1.0):  # no faces: smooth where eta is 1
            distribution = GGX._new(*(pick(eta == 1.0, 0.0, a) for a in
                                      (distribution.alpha_x, distribution.alpha_y)),
                                    distribution.masking)
        self.distribution = distribution
        #: the single-scattering reflection and (unflipped) transmission lobes
        self.single = tuple(Conductor._new(distribution, part._new(eta, transmittance, film))
                            for part in (SheetReflectance, SheetTransmittance))
        components, weights = [self.single[0], Flipped._new(self.single[1])], [None, None]
        if not np.all(distribution.smooth):
            ms = ConductorMultipleScattering._new(distribution, np.ones(3))
            averages = _hemispherical_averages(eta, transmittance, film)
            components += [ms, Flipped._new(ms)]
            weights += list(averages)
            self._multiple = (ms, averages[0] + averages[1])
        self._init(Sum._new(components, weights))

    def _albedo_table(self, wo, with_error=True):
        """E(wo) = E_1(wo) (Q_R + Q_T) / Q_1 + (R_avg + T_avg) (1 - E_1(wo)) at the
        directions seen from the top: E_1 the F = 1 single-scattering table
        ("ggx_conductor"), Q_X the 32 x 32 Gauss rule over the visible-normal sampler of the
        lobe with Fresnel X (``quadrature.sampled_albedo``; Q_1 for F = 1), the second term
        the multiple-scattering table. The ratio keeps a clear sheet at E = 1 exactly (R + T
        = 1, so Q_R + Q_T = Q_1), where the additive rule of ``Conductor`` on each lobe
        would add the rule's own error at grazing angles twice. Smooth elements: the delta
        albedo R + T. Error: the change of the ratio term at order 16 plus the table's node
        error."""
        wo = self._directions(wo, None)[0]
        delta = self.lobe._delta_albedo(wo)
        d = self.distribution
        if np.all(d.smooth):
            return delta, np.zeros(delta.shape)
        white = Conductor._new(d, None)

        def ratio(order):
            q = [quadrature.sampled_albedo(lobe, wo, order) for lobe in (white, *self.single)]
            with np.errstate(divide="ignore", invalid="ignore"):
                return pick(q[0] > 0.0, (q[1] + q[2]) / q[0], 0.0)

        E, error = conductor_energy(d, wo, with_error)
        ms, averages = self._multiple
        share = ratio(32)
        value = grey(E) * share + averages * ms._albedo_table(wo, False)[0]
        smooth = d.smooth[..., None]
        value = pick(smooth, delta, value)
        if with_error:
            error = pick(smooth, 0.0, grey(E) * np.abs(share - ratio(16)) + grey(error))
        return value, error

    def _top_albedo(self, wo):
        """As the top of a layer: the table albedo above."""
        return self._albedo_table(wo, with_error=False)[0]

    def __repr__(self) -> str:
        d = self.distribution
        film = "" if self.film is None else f", film={self.film!r}"
        return (f"ThinDielectric(eta={self.sheet_eta}, alpha_x={d.alpha_x}, "
                f"alpha_y={d.alpha_y}, transmittance={self.transmittance}{film})")
