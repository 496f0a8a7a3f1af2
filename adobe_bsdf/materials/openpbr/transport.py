"""OpenPBR by full light transport: the specification's slabs [Andersson2023, §Formalism,
§Model; OpenPBR2026, §Model], followed by random walks instead of approximated
(``OpenPBRSurface.reference``; every choice is in ``docs/openpbr.md``, "The structure
itself").

    PBR         = mix(ambient, surface, geometry_opacity)
    surface     = mix(coated-base, layer(coated-base, fuzz), fuzz_weight)
    coated-base = mix(base, layer(base, coat), coat_weight)
    base        = mix(mix(mix(glossy-diffuse, subsurface, S), translucent, T), metal, M)

Each ``layer`` is a ``layered.LayeredReference`` (random walks between the slab's interface
and what lies under it, through its medium) and each ``mix`` a ``layered.MixedReference``
(patches side by side). The slabs:

- fuzz: an index-matched slab of optical thickness 1 of specular fibre microflakes
  (``phase.FibreMicroflakes`` of fuzz_roughness, the ASM sheen's distribution [Kutz2021,
  §6]), grey extinction; the flakes' albedo solved per channel so that the slab's reflection
  albedo, averaged over the hemisphere, is fuzz_color times a white slab's
  (``fuzz_flake_albedo``: "fuzz_color ... E_fuzz computed with white colour");
- coat: the rough dielectric interface of coat_ior (coat roughness, anisotropy, tangent) over
  a purely absorbing slab, its optical depth solved per channel so that a coat over a white
  Lambertian base reflects s + coat_color (a_1 - s) at normal incidence, s the coat's own
  reflection and a_1 the clear coat's whole albedo (``coat_optical_depth``, multiple bounces
  included), over the base seen from inside the coat's index;
- base: the metal (the F82-tint conductor with its Kulla–Conty term, as the fast model's);
  glossy-diffuse (the dielectric interface over the EON diffuse, light bouncing between
  them, the diffuse albedo solved so that the structure reflects (1 - E_spec) base_color
  over a Lambertian: ``diffuse_albedo``); subsurface (the interface over a half-space of the
  mapped medium, ``media.openpbr_subsurface_medium``, walked position-free); translucent
  (the interface into the transmission medium, which the renderer follows, as the fast
  model's). The base interface's index is specular_ior over the index above it (1, or
  coat_ior under the coat), modulated by specular_weight [OpenPBR2026, §Dielectric base].
"""

from __future__ import annotations

import copy

import numpy as np
from scipy import optimize

from adobe_bsdf import _params, config, media
from adobe_bsdf.layered import LayeredReference, MixedReference, TwoSided, UpsideDown
from adobe_bsdf.lobes.dielectric import Dielectric
from adobe_bsdf.lobes.kulla_conty import DielectricMS
from adobe_bsdf.lobes.lambert import Lambert
from adobe_bsdf.lobes.oren_nayar import EnergyPreservingOrenNayar
from adobe_bsdf.lobes.pass_through import PassThrough
from adobe_bsdf.lobes.tinted_refraction import TintedRefraction
from adobe_bsdf.materials.openpbr import mapping
from adobe_bsdf.materials.openpbr.material import _mix, _turned
from adobe_bsdf.microfacet import GGX
from adobe_bsdf.phase import FibreMicroflakes
from adobe_bsdf.sampling import cosine_hemisphere
from adobe_bsdf.thin_film import ThinFilm

__all__ = ["reference", "OpenPBRReference", "emission_weight", "coat_optical_depth",
           "fuzz_flake_albedo", "diffuse_albedo",
           "FUZZ_ROUGHNESS_MIN", "HALF_SPACE_DEPTH", "SOLVER_WALKS"]

#: the fibres' roughness floor: fuzz_roughness 0 is a slab of vertical threads, which no
#: flake turns back (the reference then reads it at this roughness)
FUZZ_ROUGHNESS_MIN = 0.01
#: optical thickness that stands for the subsurface half-space (walks that reach its bottom
#: are absorbed; at this depth none does in practice)
HALF_SPACE_DEPTH = 1e3
#: random walks of the solvers (the coat's depth, the fuzz flakes' and the diffuse albedo)
SOLVER_WALKS = 200_000
#: bounces a solver's walk follows (what is left after them is below 1e-9 of its energy)
_SOLVER_BOUNCES = 256


def _c(x):
    return np.broadcast_to(np.asarray(x, dtype=np.float64), (3,))


# -- the solvers ------------------------------------------------------------------------------
def coat_optical_depth(coat, color, n_walks: int = SOLVER_WALKS, seed: int = 0) -> np.ndarray:
    """Optical depth tau (3,) of the absorbing slab under the interface ``coat`` (a lobe,
    reflection and transmission) such that the coat over a white Lambertian base reflects, at
    normal incidence,

        A(tau) = s + c (A(0) - s),   c = ``color``,

    s the interface's own reflection [OpenPBR2026, §Coat: coat_color is the observed tint of
    the base at normal incidence, multiple bounces included]. One set of ``n_walks`` walks
    gives A for every tau: a walk's weight w and its summed path length in units of the
    slab's thickness, L = sum 1 / |cos| over its crossings, give A(tau) = E[w exp(-tau L)];
    tau is the root of that monotone function (c = 0: tau = 1e3, the tint black)."""
    color = _c(_params.color("color", color, 0.0, 1.0))
    rng = np.random.default_rng(seed)
    n = _params.integer("n_walks", n_walks, 2)
    weight, length = np.zeros(n), np.zeros(n)
    up = np.broadcast_to([0.0, 0.0, 1.0], (n, 3))
    s = coat._sample(up, rng.random((n, 3)))
    out = s.wi[:, 2] > 0.0
    weight[out] = s.weight[out, 0]
    k = np.flatnonzero((s.pdf > 0.0) & (s.wi[:, 2] < 0.0))
    beta, w, L = s.weight[k, 0], s.wi[k], np.zeros(len(k))
    for _ in range(_SOLVER_BOUNCES):
        if not len(k):
            break
        L = L + 1.0 / np.abs(w[:, 2])  # down to the base
        w = cosine_hemisphere(rng.random((len(k), 2)))  # the white Lambertian, up
        L = L + 1.0 / w[:, 2]
        t = coat._sample(-w, rng.random((len(k), 3)))
        beta = beta * t.weight[:, 0]  # in and out: the radiance scales cancel
        leave = (t.pdf > 0.0) & (t.wi[:, 2] > 0.0)
        weight[k[leave]], length[k[leave]] = beta[leave], L[leave]
        stay = (t.pdf > 0.0) & (t.wi[:, 2] < 0.0)
        k, beta, w, L = k[stay], beta[stay], t.wi[stay], L[stay]
    under = length > 0.0
    specular = np.mean(np.where(under, 0.0, weight))
    through = weight[under] / n

    def excess(tau, target):
        return float(np.sum(through * np.exp(-tau * length[under]))) - target

    tau = np.zeros(3)
    for ch, c in enumerate(color):
        target = c * (np.mean(weight) - specular)
        if c >= 1.0:
            continue
        if c <= 0.0:
            tau[ch] = 1e3
            continue
        hi = 1.0
        while excess(hi, target) > 0.0:
            hi *= 2.0
        tau[ch] = optimize.brentq(excess, 0.0, hi, args=(target,), xtol=1e-12)
    return tau


def fuzz_flake_albedo(color, roughness, n_walks: int = SOLVER_WALKS,
                      seed: int = 0) -> np.ndarray:
    """Single-scattering albedo a (3,) of the fuzz's flakes such that its slab (optical
    thickness 1, ``phase.FibreMicroflakes`` of ``roughness``, over nothing) reflects
    ``color`` times what a white one reflects, averaged over the hemisphere (the light of a
    uniform sky) [OpenPBR2026, §Fuzz: f_fuzz = fuzz_color E_fuzz D, E_fuzz the albedo with a
    white colour]. A path's weight is a^k for its k scatterings, so one set of white walks
    gives R(a) = sum_k a^k P_k for every a; a is the root of R(a) = c R(1)."""
    color = _c(_params.color("color", color, 0.0, 1.0))
    phase = FibreMicroflakes(max(float(roughness), FUZZ_ROUGHNESS_MIN))
    n = _params.integer("n_walks", n_walks, 2)
    rng = np.random.default_rng(seed)
    w = -cosine_hemisphere(rng.random((n, 2)))  # travelling down into the slab
    z, order = np.ones(n), np.zeros(n, dtype=np.int64)
    orders = []
    for _ in range(_SOLVER_BOUNCES):
        if not len(w):
            break
        with np.errstate(divide="ignore"):
            dz = -np.log1p(-rng.random(len(w))) * np.abs(w[:, 2]) / phase.sigma(w)
        z = z + np.sign(w[:, 2]) * dz
        orders.append(order[z >= 1.0])  # out of the top: reflected
        inside = (z > 0.0) & (z < 1.0)
        w, z, order = w[inside], z[inside], order[inside] + 1
        w, _ = phase.sample(-w, rng.random((len(w), 2)))
    counts = np.bincount(np.concatenate(orders), minlength=2) / n

    def reflected(a):
        return float(np.polyval(counts[::-1], a))

    white = reflected(1.0)
    a = np.ones(3)
    for ch, c in enumerate(color):
        if c < 1.0:
            a[ch] = optimize.brentq(lambda x, c=c: reflected(x) - c * white, 0.0, 1.0,
                                    xtol=1e-12)
    return a


def diffuse_albedo(interface, color, n_walks: int = SOLVER_WALKS,
                   seed: int = 0) -> np.ndarray:
    """Albedo rho (3,) of the diffuse under ``interface`` such that the glossy-diffuse slab
    reflects (1 - E_spec(mu)) ``color`` from every direction mu where the diffuse is
    Lambertian [OpenPBR2026, §Glossy-diffuse: E_diffuse = (1 - E_spec) base_color]: light
    enters with 1 - E_spec, a Lambertian reflects it with a cosine distribution, of which the
    interface sends back rbar (its reflectance averaged over that distribution, from
    inside: ``n_walks`` samples), so the slab reflects (1 - E_spec) rho (1 - rbar) /
    (1 - rho rbar), and rho = c / (1 - rbar + c rbar)."""
    color = _c(_params.color("color", color, 0.0, 1.0))
    n = _params.integer("n_walks", n_walks, 2)
    rng = np.random.default_rng(seed)
    below = cosine_hemisphere(rng.random((n, 2))) * np.array([1.0, 1.0, -1.0])
    s = interface._sample(below, rng.random((n, 3)))
    back = (s.pdf > 0.0) & (s.wi[:, 2] < 0.0)
    rbar = np.where(back[:, None], s.weight, 0.0).mean(0)
    return color / (1.0 - rbar + color * rbar)


# -- the structure ----------------------------------------------------------------------------
class _Builder:
    """The slabs of one material (scalar parameters ``p``). ``fasts`` maps the index above
    the base (1, and coat_ior where there is a coat) to a fast model of the same inputs
    without coat, fuzz or opacity at that index (coat_weight 1 with a smooth coat, which
    roughens nothing): its metal lobe, and its film, haze and glass, are the base's own."""

    def __init__(self, p, fasts, seed):
        self.p, self.fasts, self.seed = p, fasts, seed

    def layer(self, top, base, **kwargs):
        """A ``LayeredReference``; an inner one (under another) takes one walk per call,
        which the enclosing walks average (``reference`` sets the outermost ones')."""
        self.seed += 1
        return LayeredReference(top, base, n_samples=1, seed=self.seed, **kwargs)

    @staticmethod
    def turned(lobe, tangent):
        """``lobe`` turned to the tangent (the fast model's ``_turned``)."""
        return _turned(lobe, mapping.tangent_rotation(np.asarray(tangent)))

    def dielectric_interface(self, n_above):
        """``(lobe, eta)``: the base's rough dielectric interface, reflection and
        transmission, at eta = specular_ior / n_above modulated by specular_weight, with the
        thin film (mixed by thin_film_weight), the haze and the retroreflectivity of the
        fast model's, its first reflection from above tinted by specular_color."""
        p, fast = self.p, self.fasts[n_above]
        eta = np.asarray(mapping.specular_ior_modulation(p["specular_ior"] / n_above,
                                                         p["specular_weight"]))
        r = p["specular_roughness"]
        lobe = fast._hazed(lambda alphas: DielectricMS._new(eta, GGX._new(*alphas)), r)
        if fast._film is not None:
            w, d, n_film = fast._film
            film = ThinFilm(d, n_film, eta, model=fast.thin_film_model)
            lobe = _mix(lobe, fast._hazed(
                lambda alphas: DielectricMS._new(eta, GGX._new(*alphas), film), r), w)
        lobe = fast._retro(lobe)
        color = p["specular_color"]
        if np.any(color != 1.0):
            lobe = TintedRefraction._new(lobe, np.ones(3), color, fast.spec == "dev_1.2")
        return self.turned(lobe, p["geometry_tangent"]), eta

    def shares(self):
        """(M, T, S): base_metalness, transmission_weight and subsurface_weight."""
        return tuple(float(self.p[k]) for k in ("base_metalness", "transmission_weight",
                                                 "subsurface_weight"))

    def glossy_diffuse(self, interface):
        """``interface`` over the EON diffuse of the albedo ``diffuse_albedo`` solves."""
        p = self.p
        rho = diffuse_albedo(interface, float(p["base_weight"]) * p["base_color"],
                             seed=self.seed)
        return self.layer(interface,
                          EnergyPreservingOrenNayar(rho, float(p["base_diffuse_roughness"])))

    def base(self, n_above):
        p, fast = self.p, self.fasts[n_above]
        M, T, S = self.shares()
        parts = []
        if M < 1.0:
            interface, eta = self.dielectric_interface(n_above)
            if (1.0 - T) * (1.0 - S) > 0.0:
                parts.append((self.glossy_diffuse(interface), (1 - M) * (1 - T) * (1 - S)))
            if (1.0 - T) * S > 0.0:
                m = media.openpbr_subsurface_medium(
                    p["subsurface_radius"], p["subsurface_radius_scale"],
                    p["subsurface_color"], p["subsurface_scatter_anisotropy"])
                parts.append((self.layer(interface, Lambert(0.0), thickness=HALF_SPACE_DEPTH,
                                         medium_albedo=m.sigma_s / m.sigma_t, g=float(m.g),
                                         max_depth=100_000), (1 - M) * (1 - T) * S))
            if T > 0.0:
                glass = fast._retro(fast._bulk_glass(eta, p["specular_roughness"]))
                parts.append((self.turned(glass, p["geometry_tangent"]), (1 - M) * T))
        if M > 0.0:
            parts.append((fast.lobes["metal"], M))
        return _mixed(parts)

    def sheet(self, n_above):
        """The thin wall's base [OpenPBR2026, §Thin-walled mode]: sheets the same from both
        faces (``TwoSided``), side by side as the bulk base's slabs. The metal and the
        glossy-diffuse slab stay, double-sided and opaque; the translucent base is a slab of
        the dielectric between two faces of its interface (the lower one ``UpsideDown``),
        of no thickness but the absorption -ln(transmission_color) per crossing at normal
        incidence, so that light goes through without net refraction; the subsurface is
        that slab with a sheet of dense scatterers in its middle, reflecting
        S (1 - g) / 2 and transmitting S (1 + g) / 2 of what reaches it, each as a unit-albedo
        EON diffuse (the fast model's ``_thin_subsurface``)."""
        p, fast = self.p, self.fasts[n_above]
        M, T, S = self.shares()
        parts = []
        if M < 1.0:
            interface, _ = self.dielectric_interface(n_above)
            lower = UpsideDown(interface)
            if (1.0 - T) * (1.0 - S) > 0.0:
                parts.append((TwoSided(self.glossy_diffuse(interface)),
                              (1 - M) * (1 - T) * (1 - S)))
            if (1.0 - T) * S > 0.0:
                scatterers = TwoSided(fast._thin_subsurface(float(p["base_diffuse_roughness"])))
                parts.append((TwoSided(self.layer(interface, self.layer(scatterers, lower))),
                              (1 - M) * (1 - T) * S))
            if T > 0.0:
                tint = np.clip(_c(p["transmission_color"]), 1e-300, 1.0)
                slab = self.layer(interface, lower, thickness=0.0 - np.log(tint))
                parts.append((TwoSided(slab), (1 - M) * T))
        if M > 0.0:
            parts.append((TwoSided(fast.lobes["metal"]), M))
        return _mixed(parts)

    def coat_top(self):
        """``(interface, tau)``: the coat's rough dielectric interface and the optical depth
        of its absorbing slab (``coat_optical_depth``)."""
        p = self.p
        n_c = float(p["coat_ior"])
        alphas = mapping.anisotropic_alphas(p["coat_roughness"], p["coat_roughness_anisotropy"])
        top = self.turned(DielectricMS._new(np.asarray(n_c),
                                            GGX._new(*(np.asarray(a) for a in alphas))),
                          p["geometry_coat_tangent"])
        return top, coat_optical_depth(top, p["coat_color"], seed=self.seed)

    def coat(self):
        top, tau = self.coat_top()
        n_c = float(self.p["coat_ior"])
        return _over_emitter(self.layer(top, self.base(n_c), thickness=tau))

    def thin_coat(self):
        """The coated thin wall: the coat's slab on both faces of the sheet, mirrored."""
        top, tau = self.coat_top()
        n_c = float(self.p["coat_ior"])
        under = self.layer(self.sheet(n_c), UpsideDown(top), thickness=tau)
        return TwoSided(_over_emitter(self.layer(top, under, thickness=tau)))

    def surface(self, thin_walled: bool = False):
        p = self.p
        C, F = float(p["coat_weight"]), float(p["fuzz_weight"])
        base, coat = (self.sheet, self.thin_coat) if thin_walled else (self.base, self.coat)
        coated = _mixed([(base(1.0) if C < 1.0 else None, 1.0 - C),
                         (coat() if C > 0.0 else None, C)])
        if F > 0.0:
            r = float(p["fuzz_roughness"])
            a = fuzz_flake_albedo(p["fuzz_color"], r, seed=self.seed)
            fibres = FibreMicroflakes(max(r, FUZZ_ROUGHNESS_MIN))
            matched = Dielectric(1.0, 0.0)
            under = coated
            if thin_walled:  # the fuzz's slab on both faces: below, over nothing
                under = self.layer(coated, matched, thickness=1.0, medium_albedo=a,
                                   phase=fibres)
                under.emits_from_top = True  # the emitter is in the sheet, above it
            fuzz = _over_emitter(self.layer(matched, under, thickness=1.0, medium_albedo=a,
                                            phase=fibres))
            if thin_walled:
                fuzz = TwoSided(fuzz)
            coated = _mixed([(coated if F < 1.0 else None, 1.0 - F), (fuzz, F)])
        alpha = float(p["geometry_opacity"])
        return _mixed([(PassThrough() if alpha < 1.0 else None, 1.0 - alpha),
                       (coated, alpha)])


def _over_emitter(layer):
    """``layer`` marked as lying over the emission [OpenPBR2026, §Emission: under the coat
    and the fuzz] (``emission_weight``)."""
    layer.over_emitter = True
    return layer


def emission_weight(lobe, wo) -> np.ndarray:
    """One walk per direction ``wo`` ``(n, 3)``: an unbiased estimate ``(n, 3)`` of the
    radiance the structure ``lobe`` sends towards ``wo`` per unit radiance that its base
    emits (Lambertian, upwards, into whatever medium lies above it: the same power under a
    coat as bare): 1 for a bare base, the coat and fuzz walked (``LayeredReference.emitted``)
    where they lie over it, light reflected back down by them and up again by the base
    included; 0 where there is no surface (``PassThrough``) or wo is below a bulk
    material."""
    if isinstance(lobe, MixedReference):
        return sum(w * emission_weight(part, wo)
                   for w, part in zip(lobe.weights, lobe.parts, strict=True))
    if isinstance(lobe, PassThrough):
        return np.zeros((len(wo), 3))
    if isinstance(lobe, TwoSided):
        return emission_weight(lobe.lobe, lobe.facing(wo))
    if isinstance(lobe, LayeredReference):
        if getattr(lobe, "emits_from_top", False):
            return emission_weight(lobe.top, wo)
        if getattr(lobe, "over_emitter", False):
            return lobe.emitted(wo, lambda w: emission_weight(lobe.base, w))
    return np.broadcast_to(np.where(wo[:, 2:3] > 0.0, 1.0, 0.0), (len(wo), 3))


class OpenPBRReference(MixedReference):
    """The lobe of ``reference``: the structure's patches (``MixedReference``) and the
    radiance its base emits (``radiance``, RGB: emission_luminance times emission_color,
    ``mapping.emission_radiance``)."""

    def __init__(self, parts, weights, radiance):
        super().__init__(parts, weights)
        self.radiance = np.asarray(radiance, dtype=np.float64)

    def emission_with_error(self, wo, n_samples: int = 256) -> tuple[np.ndarray, np.ndarray]:
        """``(emission(wo), standard error)``, RGB ``(..., 3)`` each: the radiance leaving
        towards ``wo`` from the emitting base through the coat and the fuzz, averaged over
        ``n_samples`` walks per direction (``emission_weight``), in blocks of bounded
        memory."""
        wo = _params.direction("wo", wo)
        n_samples = _params.integer("n_samples", n_samples, 2)
        flat = wo.reshape(-1, 3)
        mean, se = np.zeros((len(flat), 3)), np.zeros((len(flat), 3))
        step = max(1, config.get_options().chunk_size // n_samples)
        blocks = range(0, len(flat), step)
        for a in config.progress(blocks, len(blocks), "OpenPBRReference.emission"):
            w = np.repeat(flat[a:a + step], n_samples, axis=0)
            x = (emission_weight(self, w) * self.radiance).reshape(-1, n_samples, 3)
            mean[a:a + step] = x.mean(1)
            se[a:a + step] = x.std(1, ddof=1) / np.sqrt(n_samples)
        shape = wo.shape[:-1] + (3,)
        return mean.reshape(shape), se.reshape(shape)

    def emission(self, wo, n_samples: int = 256) -> np.ndarray:
        """The emitted radiance towards ``wo`` (``emission_with_error``'s estimate)."""
        return self.emission_with_error(wo, n_samples)[0]


def _mixed(parts):
    """One lobe of weighted parts (those of weight 0, or None, left out)."""
    parts = [(lobe, w) for lobe, w in parts if lobe is not None and w > 0.0]
    if len(parts) == 1:
        return parts[0][0]
    return MixedReference([lobe for lobe, _ in parts], [w for _, w in parts])


def reference(surface, n_samples: int = 64, seed: int = 0):
    """The OpenPBR material ``surface`` (an ``OpenPBRSurface`` of scalar parameters) as the
    structure the specification describes, followed by random walks (module docstring): a
    lobe whose ``eval`` averages ``n_samples`` walks per pair (``eval_with_error`` gives
    its standard error), ``sample`` follows one walk, ``albedo(method="mc")`` averages
    walks. Slow on purpose."""
    n_samples = _params.integer("n_samples", n_samples, 1)
    seed = _params.integer("seed", seed, 0)
    shaped = {k: np.shape(v) for k, v in surface.params.items()
              if isinstance(v, np.ndarray) and v.shape not in ((), (3,))}
    if shaped:
        name, shape = next(iter(shaped.items()))
        raise ValueError(f"{name} has shape {shape}: the reference follows one material; "
                         "allowed: scalar parameters (a colour (3,))")
    p = surface.params
    if surface._hazy and surface.haze_model == "barla2018":
        raise ValueError("haze_model = 'barla2018': the reference follows the specification's "
                         "haze only; allowed: 'dev_1.2'")

    def fast(coat_weight):
        return type(surface)(spec=surface.spec, thin_film_model=surface.thin_film_model,
                             **{**p, "coat_weight": coat_weight, "coat_roughness": 0.0,
                                "fuzz_weight": 0.0, "geometry_opacity": 1.0})

    fasts = {1.0: fast(0.0)}
    if float(p["coat_weight"]) > 0.0:
        fasts[float(p["coat_ior"])] = fast(1.0)
    lobe = _outermost(_Builder(p, fasts, seed).surface(surface.thin_walled), n_samples)
    radiance = mapping.emission_radiance(p["emission_luminance"] * p.get("emission_weight", 1.0),
                                         p["emission_color"])
    # always a random-walk lobe (``eval_with_error``, ``_draw``), a bare slab's exactly
    if isinstance(lobe, MixedReference):
        return OpenPBRReference(lobe.parts, lobe.weights, radiance)
    return OpenPBRReference([lobe], [1.0], radiance)


def _outermost(lobe, n_samples):
    """``lobe`` with ``n_samples`` walks per evaluated pair for the layers no other layer
    encloses (copies: a patch can also lie under the fuzz, where it keeps its one walk)."""
    if isinstance(lobe, LayeredReference):
        lobe = copy.copy(lobe)
        lobe.n_samples = n_samples
    elif isinstance(lobe, MixedReference):
        lobe = MixedReference([_outermost(part, n_samples) for part in lobe.parts],
                              lobe.weights)
    elif isinstance(lobe, TwoSided):
        lobe = TwoSided(_outermost(lobe.lobe, n_samples))
    return lobe
