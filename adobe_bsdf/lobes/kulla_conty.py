"""Kulla–Conty multiple scattering for GGX conductors and dielectrics [Kutz2021, §1.2].

Public API
----------
``ConductorMultipleScattering``   the separable term restoring the energy a GGX conductor
                                  loses to single scattering, times base_color^2.
``ConductorMS``                   ``Conductor`` + that term.
``DielectricMultipleScattering``  reflection and transmission terms for a rough dielectric
                                  interface, both sides.
``DielectricMS``                  ``Dielectric`` + that term.
``DispersiveMS``                  ``Dispersive`` + that term of each channel's index.

The conductor term reads E(wo) from "ggx_conductor" where isotropic and from
"ggx_conductor_anisotropic" (a function of wo's azimuth) where alpha_x != alpha_y; with E_avg
the hemispherical average (1 / pi) int E(w) cos d w of the same interpolant, the term
restores exactly 1 - E(wo) for anisotropic roughness too, and stays separable and reciprocal.
The dielectric terms' tables are isotropic: an anisotropic pair of alphas is looked up at
alpha = sqrt(alpha_x alpha_y) (an approximation, its white furnace in ``docs/tables.md``),
unless the lobe is built under ``config.options(anisotropic_energy="exact")``: then each
anisotropic element reads E(mu, phi) and its averages from its own slice
(``tables.dielectric_slices``), and the terms restore 1 - E(wo) exactly up to the slice's
interpolation error, with the same reciprocity.
Averages are exact averages of the interpolated E, so a white furnace measures the tables'
interpolation error (``docs/tables.md``).

References: [KullaConty2017] the separable energy-compensation terms; [Kutz2021, §1.2] their
use for metals (times base_color^2) and refractive dielectrics.
"""

from __future__ import annotations

import numpy as np

from adobe_bsdf import _memo, _params, tables
from adobe_bsdf._channels import pick
from adobe_bsdf.bsdf import Flags, Lobe, finished_sample, luminance
from adobe_bsdf.composition import Sum
from adobe_bsdf.lobes.dielectric import (
    Dielectric,
    _eta,
    _film,
    _mirror_z,
    interface_energy_scale,
)
from adobe_bsdf.lobes.dispersive import Dispersive
from adobe_bsdf.lobes.energy_lookup import (
    checked_ratio,
    conductor_average,
    conductor_energy,
    dielectric_energy,
    grey,
    is_anisotropic,
    lookup,
    sides,
    slice_average,
    slice_source,
    table_alpha,
    within_tables,
)
from adobe_bsdf.lobes.reflection import Conductor, _fresnel_model
from adobe_bsdf.lobes.separable import Separable
from adobe_bsdf.microfacet import GGX

__all__ = ["ConductorMultipleScattering", "ConductorMS", "DielectricMultipleScattering",
           "SeparableDielectricMS", "DielectricMultipleReflection", "DielectricMS",
           "DispersiveMS", "GLOSSY_SHARE"]

#: the share of the light side's multiply reflected energy that ``DielectricMultipleReflection``
#: carries where the roughness is isotropic (the rest: ``SeparableDielectricMS``), fitted to
#: the microsurface random walk [Heitz2016ms] by ``benchmarks/ms_reflection.py``
#: (``docs/energy_models.md``)
GLOSSY_SHARE = 0.95
_MS_TABLE = "ggx_dielectric_ms_reflection"


def _inverse_loss(E_avg):
    """1 / (pi (1 - E_avg)), 0 where nothing is lost (smooth interface)."""
    loss = 1.0 - E_avg
    return pick(loss > 1e-12, 1.0 / (np.pi * pick(loss > 1e-12, loss, 1.0)), 0.0)


class ConductorMultipleScattering(Separable):
    """f_ms = base_color^2 (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg)) [Kutz2021, §1.2].

    E is the F = 1 directional albedo of the GGX lobe and E_avg its cosine-weighted average
    over the hemisphere [KullaConty2017]; base_color^2 stands for the at-least-two bounces
    of every path this term represents. Anisotropic roughness: E = E(mu, phi) and the
    average runs over azimuth too, which keeps the term exact per direction (the
    construction of [KullaConty2017] needs only E_avg = (1 / pi) int E cos).
    Reciprocal and separable; cosine-sampled; one-sided.

    Parameters
    ----------
    alpha_x, alpha_y : array_like in [0, 2]
        GGX roughness of the single-scattering lobe.
    base_color : colour in [0, 1]
        The metal's base colour (F0); 1 restores all energy of a white metal.
    """

    flags = Flags.REFLECTION | Flags.DIFFUSE

    def __init__(self, alpha_x, alpha_y=None, base_color=1.0):
        self._init(GGX(alpha_x, alpha_y), _params.color("base_color", base_color, 0.0, 1.0))

    def _init(self, distribution: GGX, base_color):
        self.distribution = distribution
        self.alpha = table_alpha(distribution)
        self.base_color = base_color
        self._scale = self.base_color ** 2 * _inverse_loss(conductor_average(distribution))[
            ..., None]

    def __repr__(self) -> str:
        d = self.distribution
        return (f"ConductorMultipleScattering(alpha_x={d.alpha_x}, alpha_y={d.alpha_y}, "
                f"base_color={self.base_color})")

    def _param_shape(self):
        return np.broadcast_shapes(self.distribution.param_shape, self.base_color.shape[:-1])

    def _X(self, w):
        """1 - E(w) (clamped at 0 against interpolation overshoot above E = 1)."""
        return np.maximum(1.0 - conductor_energy(self.distribution, w)[0], 0.0)

    def _coefficient(self, wo, wi):
        return self._scale

    def _albedo_table(self, wo, with_error=True):
        """base_color^2 (1 - E(wo)), exact for the tabulated E."""
        E, error = conductor_energy(self.distribution, wo, with_error)
        loss = pick(wo[..., 2] > 0.0, np.maximum(1.0 - E, 0.0), 0.0)
        scale = self.base_color ** 2
        return scale * loss[..., None], None if error is None else scale * error[..., None]

    def _sampling_weight(self, wo):
        return luminance(self.base_color ** 2) * pick(wo[..., 2] > 0.0, self._X_at(wo), 0.0)


class ConductorMS(Sum):
    """GGX conductor with Kulla–Conty multiple scattering: ``Conductor`` +
    ``ConductorMultipleScattering`` [Kutz2021, §1.2]. Height-correlated masking (the
    tables' G2).

    Parameters
    ----------
    alpha_x, alpha_y : array_like in [0, 2]
    fresnel : callable or None
        As for ``Conductor`` (None: F = 1).
    base_color : colour in [0, 1]
        Scales the multiple-scattering term by its square.
    """

    def __init__(self, alpha_x, alpha_y=None, fresnel=None, base_color=1.0):
        self._init(GGX(alpha_x, alpha_y), _fresnel_model(fresnel),
                   _params.color("base_color", base_color, 0.0, 1.0))

    def _init(self, distribution: GGX, fresnel, base_color):
        """Both terms over the one ``distribution``."""
        super()._init((Conductor._new(distribution, fresnel),
                       ConductorMultipleScattering._new(distribution, base_color)))


class SeparableDielectricMS(Separable):
    """The separable Kulla–Conty terms of a rough dielectric interface [Kutz2021, §1.2],
    both sides (``DielectricMultipleScattering`` adds the glossy share of the light side's
    reflection).

    With E_s(mu) = E_R + E_T the single-scattering energy seen from side s (L: less dense,
    D: dense), E_avg,s its average, eta = n_D / n_L >= 1 and r_s the share of side s's
    multiply-scattered energy that is reflected:

        reflection on s:  r_s (1 - E_s(mu_o)) (1 - E_s(mu_i)) / (pi (1 - E_avg,s))
        L -> D:           (1 - r_L) (1 - E_L(mu_o)) (1 - E_D(mu_i)) / (pi eta^2 (1 - E_avg,D))
        D -> L:           eta^2 (1 - r_D) (1 - E_D(mu_o)) (1 - E_L(mu_i)) / (pi (1 - E_avg,L))

    Each side then scatters exactly 1 - E_s(mu_o) more energy, and generalized reciprocity
    f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2 holds iff
    (1 - r_L)(1 - E_avg,L) = eta^2 (1 - r_D)(1 - E_avg,D). We take r_L from the single
    scattering, r_L = E_R,avg,L / E_avg,L, and r_D from that condition (if it would leave
    [0, 1], r_D = 0 and r_L follows from the condition instead). ``docs/tables.md``.

    Of the light side's reflection this term keeps the share 1 - g, g = ``GLOSSY_SHARE``
    where the roughness is isotropic (0 elsewhere): ``glossy_weight`` g r_L is what
    ``DielectricMultipleReflection`` reflects instead.
    """

    flags = Flags.REFLECTION | Flags.TRANSMISSION | Flags.DIFFUSE
    two_sided = True

    def __init__(self, eta, alpha_x, alpha_y=None):
        self._init(_eta(eta), GGX(alpha_x, alpha_y))

    def _init(self, eta, distribution: GGX, film=None, interface_eta=None):
        """``film``: None, or ``(energy, channel)``: a ``film_energy.FilmEnergy`` of the
        interface and the colour channel whose Delta this term restores as well (it
        restores 1 - E - Delta; no glossy share then). ``interface_eta``: the interface's own
        index where ``eta`` is only the one its energy is read at (a channel beyond the
        tables, ``energy_lookup.within_tables``): generalized reciprocity follows the
        interface's."""
        self.eta = eta
        self.distribution = distribution
        self._film = film
        alpha = table_alpha(self.distribution)
        ratio = checked_ratio(self.eta)
        self._light_above = sides(self.eta)[0]
        avg_L = tables.get("ggx_dielectric_outside_avg")(alpha, ratio)
        avg_D = tables.get("ggx_dielectric_inside_avg")(alpha, ratio)
        #: whether anisotropic elements read their slices (``config`` anisotropic_energy)
        self.slices = slice_source(self.distribution)
        if self.slices:
            aniso = is_anisotropic(self.distribution)[..., None]
            slice_L, slice_D = slice_average(self.eta, self.distribution, self.slices)
            avg_L, avg_D = pick(aniso, slice_L, avg_L), pick(aniso, slice_D, avg_D)
        E_avg_L, E_avg_D = avg_L.sum(-1), avg_D.sum(-1)
        if film is not None:
            energy, c = film
            E_avg_L, E_avg_D = E_avg_L + energy.average_light[c], E_avg_D + energy.average_dense[c]
        # the split is a free choice in [0, 1] (clipped against interpolation overshoot of a
        # near-zero E_R near eta = 1; conservation and reciprocity hold for any value)
        t_L = np.clip(pick(E_avg_L > 0.0, avg_L[..., 1] / pick(E_avg_L > 0, E_avg_L, 1.0),
                               0.0), 0.0, 1.0)
        loss_L, loss_D = 1.0 - E_avg_L, 1.0 - E_avg_D
        eta2 = ratio * ratio if interface_eta is None else sides(interface_eta)[1] ** 2
        # 1 - r_D from the reciprocity condition; if above 1, cap it and lower 1 - r_L instead
        t_D = np.maximum(t_L * loss_L / pick(eta2 * loss_D > 0.0, eta2 * loss_D, 1.0), 0.0)
        capped = t_D > 1.0
        t_L = pick(capped, eta2 * loss_D / pick(loss_L > 0.0, loss_L, 1.0), t_L)
        t_D = pick(capped, 1.0, t_D)
        self.transmitted_share = (t_L, t_D)
        active = ~self.distribution.smooth & (self.eta != 1.0)
        g = pick(active & ~is_anisotropic(self.distribution) & (film is None), GLOSSY_SHARE,
                 0.0)
        #: g r_L: the share of the light side's multiply scattered energy reflected glossily
        self.glossy_weight = g * (1.0 - t_L)
        #: what this term keeps of the light side's energy X_L, 1 - g r_L
        self._kept = 1.0 - self.glossy_weight
        inv_L, inv_D = _inverse_loss(E_avg_L), _inverse_loss(E_avg_D)
        # L -> D: t_L / (pi eta^2 loss_D), which the condition makes t_D / (pi loss_L); where
        # the dense side loses nothing that 1 / loss_D resolves (``_inverse_loss`` 0), that
        # second form keeps the pair reciprocal (D -> L stays eta^2 t_D / (pi loss_L))
        self._c = {  # coefficient of each (side of wo, side of wi) pair
            ("L", "L"): (1.0 - g) * (1.0 - t_L) * inv_L, ("D", "D"): (1.0 - t_D) * inv_D,
            ("L", "D"): pick(inv_D > 0.0, t_L * inv_D / eta2, t_D * inv_L),
            ("D", "L"): eta2 * t_D * inv_L}
        self._c = {k: pick(active, v, 0.0) for k, v in self._c.items()}
        self._t = (pick(active, t_L, 0.0), pick(active, t_D, 0.0))

    def __repr__(self) -> str:
        d = self.distribution
        return (f"SeparableDielectricMS(eta={self.eta}, alpha_x={d.alpha_x}, "
                f"alpha_y={d.alpha_y})")

    def _param_shape(self):
        return np.broadcast_shapes(self.eta.shape, self.distribution.param_shape)

    def _on_light(self, w):
        return (w[..., 2] > 0.0) == self._light_above

    def _E(self, w, with_error=False):
        """(E_s(mu), error) on the side of ``w``, plus the film's Delta where it has one
        (the three channels' terms share one lookup per call: ``_memo``)."""
        if self._film is None or with_error:
            E, error = dielectric_energy(self.eta, self.distribution, w, with_error,
                                         self.slices)
            if self._film is not None:
                energy, c = self._film
                E = E + energy(np.abs(w[..., 2]), self._on_light(w))[..., c]
            return E, error
        energy, c = self._film

        def filmed(w):
            E = dielectric_energy(self.eta, self.distribution, w, slices=self.slices)[0]
            return E[..., None] + energy(np.abs(w[..., 2]), self._on_light(w))
        return _memo.once(energy, "E", w, filmed)[..., c], None

    def _X(self, w):
        """1 - E_s(mu) on the side of ``w`` (clamped at 0 against interpolation overshoot)."""
        return np.maximum(1.0 - self._E(w)[0], 0.0)

    def _coefficient(self, wo, wi):
        o_light, i_light = self._on_light(wo), self._on_light(wi)
        c = 0.0
        for (so, si), coefficient in self._c.items():
            here = (o_light == (so == "L")) & (i_light == (si == "L"))
            c = c + pick(here, coefficient, 0.0)
        c = np.asarray(c)[..., None]
        return np.broadcast_to(c, c.shape[:-1] + (3,))  # grey: f is (..., 3) as for any lobe

    def _reflect_probability(self, wo):
        """This term's own: on the light side (1 - g) r_L / (1 - g r_L)."""
        t_L, t_D = self._t
        kept = self._kept
        light = pick(kept > 0.0, (kept - t_L) / pick(kept > 0.0, kept, 1.0), 0.0)
        return pick(self._on_light(wo), light, 1.0 - t_D)

    def _light_share(self, wo):
        """1 - g r_L on the light side, 1 on the dense side."""
        return pick(self._on_light(wo), self._kept, 1.0)

    def _energy_scale(self, wo, wi):
        return interface_energy_scale(self.eta, wo, wi)

    def _albedo_table(self, wo, with_error=True):
        """(1 - E_s(mu_o)) times ``_light_share``: what this term adds, exactly, for the
        tabulated E."""
        E, error = self._E(wo, with_error)
        active = ~self.distribution.smooth & (self.eta != 1.0) & (wo[..., 2] != 0.0)
        share = self._light_share(wo)
        return (grey(pick(active, np.maximum(1.0 - E, 0.0), 0.0) * share),
                grey(None if error is None else error * share))

    def _sampling_weight(self, wo):
        return self._X_at(wo) * self._light_share(wo)


class DielectricMultipleReflection(Lobe):
    """The glossy share of the light a rough dielectric interface reflects after more than one
    scattering, on its light side:

        f = w a(mu_o) a(mu_i) D(h) G2(wo, wi) / (4 |cos theta_o| |cos theta_i|),

    the F = 1 GGX reflection of the interface's own roughness scaled by a(mu), the
    symmetric scaling of ``tables`` "ggx_dielectric_ms_reflection", with which it reflects
    exactly w (1 - E_L(mu_o)) (1 - E_L the light side's single-scattering loss) [Sinkhorn1967;
    KullaConty2017]. Symmetric in (wo, wi): reciprocal. Sampled by the visible normals of
    that reflection [Heitz2018], the weight times w a(mu_o) a(mu_i).

    The microsurface random walk [Heitz2016ms] reflects multiply scattered light into a lobe
    about the mirror direction, not a separable one: ``docs/energy_models.md`` measures both
    against it. 0 where the roughness is anisotropic (the table's kernel is isotropic).

    Parameters
    ----------
    eta : array_like, max(eta, 1/eta) in [1, 3]
        n_below / n_above (the light side: above where eta >= 1).
    alpha_x, alpha_y : array_like in [0, 2]
    weight : array_like in [0, 1]
        w, the share of the light side's multiply scattered energy reflected so.
    """

    flags = Flags.REFLECTION | Flags.GLOSSY

    def __init__(self, eta, alpha_x, alpha_y=None, weight=1.0):
        self._init(_eta(eta), GGX(alpha_x, alpha_y),
                   _params.real("weight", weight, 0.0, 1.0))

    def _init(self, eta, distribution: GGX, weight):
        self.eta_ = eta
        self.distribution = distribution
        alpha = table_alpha(distribution, _MS_TABLE)
        ratio = checked_ratio(eta, _MS_TABLE)
        active = ~distribution.smooth & (eta != 1.0) & ~is_anisotropic(distribution)
        #: w, 0 where the term is inactive (smooth, index-matched or anisotropic)
        self.weight = pick(active, weight, 0.0)
        self._coords = {"alpha": alpha, "eta": ratio}
        #: +1 where the light side is above, -1 below
        self._side = pick(sides(eta)[0], 1.0, -1.0)
        self._white = Conductor._new(distribution, None)

    def __repr__(self) -> str:
        d = self.distribution
        return (f"DielectricMultipleReflection(eta={self.eta_}, alpha_x={d.alpha_x}, "
                f"alpha_y={d.alpha_y}, weight={self.weight})")

    def _param_shape(self):
        return np.broadcast_shapes(self.eta_.shape, self.distribution.param_shape,
                                   np.shape(self.weight))

    def _a(self, w):
        """a(|cos theta|) of the table."""
        mu = np.abs(w[..., 2])
        return lookup(_MS_TABLE, mu, **self._coords)[0]

    def _scale(self, wo, wi):
        return self.weight * (self._a(wo) * self._a(wi))

    def _up(self, w):
        """``w`` mirrored so that the light side is above (the white reflection's side)."""
        return _mirror_z(w, self._side)

    def _eval(self, wo, wi):
        f = self._white._eval(self._up(wo), self._up(wi))
        return f * self._scale(wo, wi)[..., None]

    def _pdf(self, wo, wi):
        return self._white._pdf(self._up(wo), self._up(wi))

    def _eval_pdf(self, wo, wi):
        f, pdf = self._white._eval_pdf(self._up(wo), self._up(wi))
        return f * self._scale(wo, wi)[..., None], pdf

    def _sample(self, wo, u):
        s = self._white._sample(self._up(wo), u)
        wi = self._up(s.wi)
        weight = s.weight * pick(s.pdf > 0.0, self._scale(wo, wi), 0.0)[..., None]
        flags = pick(s.pdf > 0.0, int(Flags.REFLECTION | Flags.GLOSSY), int(Flags.NONE))
        return finished_sample(wi, weight, s.pdf, flags)

    def _albedo_table(self, wo, with_error=True):
        """w (1 - E_L(mu_o)) on the light side: what the table's scaling makes it reflect
        (exact at the table's nodes; the interpolation error in ``docs/energy_models.md``)."""
        E, error = dielectric_energy(self.eta_, self.distribution, wo, with_error)
        light = (wo[..., 2] * self._side > 0.0) & (self.weight > 0.0)
        X = pick(light, np.maximum(1.0 - E, 0.0) * self.weight, 0.0)
        return grey(X), grey(None if error is None else pick(light, error * self.weight, 0.0))

    def _sampling_weight(self, wo):
        return self._albedo_table(wo, with_error=False)[0][..., 0]


class DielectricMultipleScattering(Sum):
    """Kulla–Conty terms of a rough dielectric interface [Kutz2021, §1.2], both sides: they
    restore exactly the energy 1 - E_s(mu_o) that single scattering loses on each side s, and
    are reciprocal. ``SeparableDielectricMS`` transmits and reflects it as separable terms;
    of the light side's reflection the share ``GLOSSY_SHARE`` goes instead to the glossy
    ``DielectricMultipleReflection`` (isotropic roughness), as the microsurface random walk
    [Heitz2016ms] sends it (``docs/energy_models.md``).

    Parameters
    ----------
    eta : array_like, max(eta, 1/eta) in [1, 3]
        n_below / n_above.
    alpha_x, alpha_y : array_like in [0, 2]
    """

    def __init__(self, eta, alpha_x, alpha_y=None):
        self._init(_eta(eta), GGX(alpha_x, alpha_y))

    def _init(self, eta, distribution: GGX, interface_eta=None):
        separable = SeparableDielectricMS._new(eta, distribution, None, interface_eta)
        parts = [separable]
        if np.any(separable.glossy_weight > 0.0):  # a material pays only for what it uses
            parts.append(DielectricMultipleReflection._new(eta, distribution,
                                                           separable.glossy_weight))
        self.distribution = distribution
        self.separable = separable
        #: (t_L, t_D): the share of each side's multiply scattered energy transmitted
        self.transmitted_share = separable.transmitted_share
        super()._init(tuple(parts))

    def __repr__(self) -> str:
        d = self.distribution
        return (f"DielectricMultipleScattering(eta={self.separable.eta}, "
                f"alpha_x={d.alpha_x}, alpha_y={d.alpha_y})")

    def _reflect_probability(self, wo):
        """The share of the multiply scattered energy at ``wo`` reflected, 1 - t_s."""
        t_L, t_D = self.separable._t
        return 1.0 - pick(self.separable._on_light(wo), t_L, t_D)


class DielectricMS(Sum):
    """Rough dielectric with Kulla–Conty multiple scattering: ``Dielectric`` +
    ``DielectricMultipleScattering`` [Kutz2021, §1.2]; height-correlated masking.

    Parameters
    ----------
    eta : array_like, max(eta, 1/eta) in [1, 3]
        n_below / n_above.
    alpha_x, alpha_y : array_like in [0, 2]
    film : fresnel.Fresnel, optional
        A thin film on the interface (``thin_film.ThinFilm(d, n_film, eta)``), seen from the
        less dense side: it colours reflection and refraction, and a white glass keeps its
        energy (scalar parameters).
    """

    def __init__(self, eta, alpha_x, alpha_y=None, film=None):
        self._init(_eta(eta), GGX(alpha_x, alpha_y), _film(film))

    def _init(self, eta, distribution: GGX, film=None):
        """Both terms over the one ``distribution``; with a ``film``, the interface's
        reflectance is the film's (``Dielectric(film=)``) and, for each colour channel c, a
        separable term restores 1 - E - Delta_c (``film_energy.FilmEnergy``)."""
        single = Dielectric._new(eta, distribution, film)
        if film is None or np.all(distribution.smooth) or np.all(eta == 1.0):
            super()._init((single, DielectricMultipleScattering._new(eta, distribution)))
            return
        energy = single.film_energy()  # (a ValueError where the parameters are arrays)
        channels = tuple(SeparableDielectricMS._new(eta, distribution, (energy, c))
                         for c in range(3))
        super()._init((single, *channels), [None, *np.eye(3)])


class DispersiveMS(Sum):
    """A dispersive rough dielectric with Kulla–Conty multiple scattering per channel:
    ``Dispersive`` (one index per RGB channel by Cauchy's equation [Kutz2021, §4]) plus, for
    each channel c, the ``DielectricMultipleScattering`` of its index masked to channel c, so
    that every channel keeps the energy of its own ``DielectricMS``. The interface (energy
    scale, generalized reciprocity) is the ``Dispersive`` one, per channel.

    Parameters
    ----------
    eta, dispersion : as ``Dispersive`` (n_d below / n above, the Dispersion 20 / V_d).
    alpha_x, alpha_y : array_like in [0, 2]
    film : callable, optional
        ``film(eta_c)``: the thin film over a channel's index, e.g.
        ``lambda eta: thin_film.ThinFilm(d, n_film, eta)`` (``DielectricMS(film=)``, per
        channel).
    """

    def __init__(self, eta, dispersion, alpha_x, alpha_y=None, film=None):
        if film is not None and not callable(film):
            raise ValueError(f"film = {film!r}: allowed None or a function of a channel's "
                             "index returning its film, e.g. lambda eta: "
                             "thin_film.ThinFilm(d, n_film, eta)")
        self._init(_eta(eta), _params.real("dispersion", dispersion, 0.0, np.inf),
                   GGX(alpha_x, alpha_y), film)

    def _init(self, eta, dispersion, distribution: GGX, film=None):
        glass = Dispersive._new(eta, dispersion, distribution, film=film)
        #: the multiple-scattering term of each channel's index (``within_tables``)
        eta_c = within_tables(glass.eta, dispersion)
        if film is None or np.all(distribution.smooth):
            self.channels = tuple(DielectricMultipleScattering._new(
                eta_c[..., c], distribution, glass.eta[..., c]) for c in range(3))
        else:  # each restores 1 - E - Delta_c of its channel's film (``DielectricMS``)
            self.channels = tuple(SeparableDielectricMS._new(
                eta_c[..., c], distribution, (glass.channels[c].film_energy(), c),
                glass.eta[..., c])
                for c in range(3))
        super()._init((glass, *self.channels), [None, *np.eye(3)])
