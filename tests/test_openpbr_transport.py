"""OpenPBR by full light transport (``OpenPBRSurface.reference``): the structure against
closed forms, the layered reference built by hand, its own definitions (the coat's tint, the
fuzz's colour), the white furnace and reciprocity. Expected values never come from the
reference itself: closed forms with scipy quadrature, lobes evaluated directly, or a second,
independently seeded estimate."""

import numpy as np
import pytest
from scipy import integrate

from adobe_bsdf.fresnel import _dielectric
from adobe_bsdf.layered import LayeredReference
from adobe_bsdf.lobes import DielectricMS
from adobe_bsdf.materials import OpenPBRSurface, presets
from adobe_bsdf.materials.openpbr import transport

SIGMAS = 4.0
#: the acceptance's floor on the white furnace and the exact cases
ATOL = 2e-3


def sph(mu, phi=0.0):
    mu = np.asarray(mu, dtype=float)
    s = np.sqrt(1.0 - mu * mu)
    return np.stack(np.broadcast_arrays(s * np.cos(phi), s * np.sin(phi), mu), -1)


WO = sph(np.array([1.0, 0.8, 0.5, 0.2, 0.9]), np.array([0.0, 0.0, 1.0, 2.0, 3.0]))
WI = sph(np.array([0.6, 0.95, 0.3, 0.7, 0.1]), np.array([1.0, 2.5, 0.0, 4.0, 5.0]))


def internal_average(eta):
    """2 int_0^1 F(mu, 1/eta) mu dmu: a smooth interface's reflectance, from inside, of
    cosine-distributed light (scipy quadrature)."""
    mu_c = np.sqrt(1.0 - 1.0 / eta**2)
    value, _ = integrate.quad(lambda m: 2.0 * _dielectric(m, 1.0 / eta) * m, 0.0, 1.0,
                              points=[mu_c], limit=200, epsabs=1e-13)
    return value


# -- exact cases ------------------------------------------------------------------------------
@pytest.mark.parametrize("eta, C", [(1.5, 0.5), (1.3, 1.0), (2.0, 0.2)])
def test_smooth_coat_over_a_lambertian_is_the_closed_form(eta, C):
    """A smooth clear coat over an index-matched Lambertian base of albedo C (specular_weight
    0: the base interface vanishes): f = (1 - F(wo))(1 - F(wi)) C / (pi eta^2 (1 - C Fbar))
    off the mirror direction, and the albedo F(mu) + (1 - F(mu)) C (1 - Fbar) / (1 - C Fbar),
    the internal reflections summed as a geometric series."""
    m = OpenPBRSurface(coat_weight=1.0, coat_roughness=0.0, coat_ior=eta, base_color=C,
                       specular_weight=0.0, specular_roughness=0.0)
    ref = m.reference(n_samples=2048)
    Fbar = internal_average(eta)
    f, err = ref.eval_with_error(WO, WI)
    mo, mi = WO[:, 2:3], WI[:, 2:3]
    expected = ((1.0 - _dielectric(mo, eta)) * (1.0 - _dielectric(mi, eta)) * C
                / (np.pi * eta**2 * (1.0 - C * Fbar)))
    assert np.all(np.abs(f - expected) <= SIGMAS * err + 1e-12), (f, expected, err)
    mu = np.array([1.0, 0.5, 0.1])
    E, se = ref.albedo(sph(mu), method="mc", n_samples=40_000, return_error=True)
    F = _dielectric(mu, eta)[:, None]
    expected = F + (1.0 - F) * C * (1.0 - Fbar) / (1.0 - C * Fbar)
    assert np.all(np.abs(E - expected) <= ATOL + SIGMAS * se), (E, expected, se)


def test_a_coat_over_a_metal_is_the_layered_reference_of_its_interfaces():
    """The same interfaces assembled by hand: the coat's DielectricMS over the material's own
    metal lobe; two independently seeded estimates agree within their errors."""
    params = dict(base_metalness=1.0, base_color=[0.9, 0.6, 0.3], specular_roughness=0.4,
                  coat_weight=1.0, coat_roughness=0.25, coat_ior=1.5)
    ref = OpenPBRSurface(**params).reference(n_samples=1024)
    metal = OpenPBRSurface(**{**params, "coat_weight": 0.0}).lobes["metal"]
    coat = DielectricMS(1.5, 0.25**2)
    by_hand = LayeredReference(coat, metal, n_samples=1024, seed=77)
    (f1, e1), (f2, e2) = ref.eval_with_error(WO, WI), by_hand.eval_with_error(WO, WI)
    assert np.all(np.abs(f1 - f2) <= SIGMAS * np.hypot(e1, e2)), (f1, f2, e1, e2)


def test_a_bare_metal_is_its_lobe():
    m = OpenPBRSurface(base_metalness=1.0, base_color=[0.9, 0.6, 0.3],
                       specular_color=[1.0, 0.9, 0.8], specular_roughness=0.35,
                       specular_roughness_anisotropy=0.5)
    ref = m.reference()
    assert len(ref.parts) == 1 and type(ref.parts[0]) is type(m.lobes["metal"])
    f, err = ref.eval_with_error(WO, WI)
    np.testing.assert_array_equal(f, m.eval(WO, WI))
    np.testing.assert_array_equal(err, 0.0)
    np.testing.assert_array_equal(ref.pdf(WO, WI), m.pdf(WO, WI))


# -- the white furnace ------------------------------------------------------------------------
WHITE = [
    dict(coat_weight=1.0, coat_roughness=0.3, specular_roughness=0.5),
    dict(coat_weight=1.0, coat_roughness=0.0, coat_ior=2.5, specular_ior=1.3,
         specular_roughness=0.2, specular_roughness_anisotropy=0.8),
    dict(coat_weight=0.6, coat_roughness=0.8, coat_roughness_anisotropy=1.0,
         fuzz_weight=1.0, fuzz_roughness=0.4, specular_roughness=0.05),
    dict(fuzz_weight=0.7, fuzz_roughness=1.0, base_diffuse_roughness=0.8,
         specular_ior=1.05),
    dict(coat_weight=1.0, coat_roughness=0.4, transmission_weight=1.0,
         specular_roughness=0.3),
]


@pytest.mark.parametrize("params", WHITE)
def test_white_structures_keep_the_energy(params):
    """White base, clear coat, white fuzz: every walk ends outside, reflected or (through a
    translucent base) transmitted; |E - 1| <= 2e-3 + 4 sigma, nothing gained."""
    m = OpenPBRSurface(base_color=1.0, **params)
    E, se = m.reference().albedo(sph(np.array([1.0, 0.6, 0.15]), 0.7), method="mc",
                                 n_samples=30_000, return_error=True)
    assert np.all(np.abs(E - 1.0) <= ATOL + SIGMAS * se), (E, se)


# -- thin walls -------------------------------------------------------------------------------
def _split(lobe, wo, n=200_000, seed=5):
    """(R, T, standard errors) of ``lobe`` at ``wo`` from ``n`` samples (RGB)."""
    u = np.random.default_rng(seed).random((n, 3))
    s = lobe.sample(np.broadcast_to(wo, (n, 3)), u)
    up = (s.wi[:, 2] > 0.0)[:, None]
    parts = [np.where(up, s.weight, 0.0), np.where(up, 0.0, s.weight)]
    return [x.mean(0) for x in parts] + [x.std(0) / np.sqrt(n) for x in parts]


@pytest.mark.parametrize("mu", [1.0, 0.6, 0.2])
def test_a_smooth_thin_sheet_is_the_closed_form(mu):
    """A smooth translucent thin wall is a slab of the dielectric with parallel faces: per
    channel, with Fresnel F at mu and t = transmission_color^(1 / cos theta_t) per crossing,
    R = F + (1 - F)^2 F t^2 / (1 - F^2 t^2) and T = (1 - F)^2 t / (1 - F^2 t^2), the same
    from below; within 4 sigma and 2e-3."""
    color = np.array([1.0, 0.7, 0.3])
    m = OpenPBRSurface(geometry_thin_walled=True, transmission_weight=1.0,
                       transmission_color=color, specular_roughness=0.0, specular_ior=1.5)
    F = _dielectric(mu, 1.5)
    cos_t = np.sqrt(1.0 - (1.0 - mu * mu) / 1.5**2)
    t = color ** (1.0 / cos_t)
    R = F + (1.0 - F) ** 2 * F * t * t / (1.0 - (F * t) ** 2)
    T = (1.0 - F) ** 2 * t / (1.0 - (F * t) ** 2)
    ref = m.reference(n_samples=4)
    for side in (1.0, -1.0):
        got_r, got_t, se_r, se_t = _split(ref, sph(mu, 0.4) * [1.0, 1.0, side])
        if side < 0.0:
            got_r, got_t, se_r, se_t = got_t, got_r, se_t, se_r
        assert np.all(np.abs(got_r - R) <= ATOL + SIGMAS * se_r), (got_r, R, se_r)
        assert np.all(np.abs(got_t - T) <= ATOL + SIGMAS * se_t), (got_t, T, se_t)


def test_an_unbounded_thin_subsurface_sheet_splits_by_its_anisotropy():
    """With an index-matched interface (specular_ior 1) the thin subsurface is its sheet of
    scatterers alone: R = S (1 - g) / 2 and T = S (1 + g) / 2 [OpenPBR v1.1.1, thin-walled
    mode], from either face."""
    S, g = np.array([0.6, 0.9, 0.2]), 0.4
    m = OpenPBRSurface(geometry_thin_walled=True, subsurface_weight=1.0, subsurface_color=S,
                       subsurface_scatter_anisotropy=g, specular_ior=1.0)
    ref = m.reference(n_samples=4)
    for side in (1.0, -1.0):
        R, T, se_r, se_t = _split(ref, sph(0.7, 1.0) * [1.0, 1.0, side], n=100_000)
        if side < 0.0:
            R, T, se_r, se_t = T, R, se_t, se_r
        assert np.all(np.abs(R - S * (1 - g) / 2) <= ATOL + SIGMAS * se_r), (R, se_r)
        assert np.all(np.abs(T - S * (1 + g) / 2) <= ATOL + SIGMAS * se_t), (T, se_t)


#: white thin walls with smooth interfaces: every walk's weight is exactly 1 (delta samples
#: of unit-albedo lobes), so the furnace is exact, not statistical, and a lost walk shows.
#: Rough interfaces weigh their samples by f cos / pdf, with tails that a long walk
#: compounds (a thin wall's light bounces between its faces): their furnace needs far more
#: walks than a test can afford, and the bulk structures' (above) cover them.
THIN_WHITE = [
    dict(subsurface_weight=1.0, subsurface_color=1.0, coat_weight=1.0, coat_roughness=0.0,
         fuzz_weight=1.0, fuzz_roughness=0.5, specular_roughness=0.0),
    dict(transmission_weight=1.0, coat_weight=0.5, coat_roughness=0.0, fuzz_weight=0.5,
         specular_roughness=0.0, base_metalness=0.3),
]


@pytest.mark.parametrize("params", THIN_WHITE)
def test_white_thin_walls_keep_the_energy_from_both_faces(params):
    """A white thin wall (white sheet, clear coat and white fuzz on both faces) reflects and
    transmits all it receives, seen from above or below: |E - 1| <= 2e-3 + 4 sigma."""
    m = OpenPBRSurface(geometry_thin_walled=True, base_color=1.0, **params)
    wo = sph(np.array([0.8, 0.3, -0.8, -0.3]), 0.7)
    E, se = m.reference().albedo(wo, method="mc", n_samples=4_000, return_error=True)
    assert np.all(np.abs(E - 1.0) <= ATOL + SIGMAS * se), (E, se)


def test_a_thin_wall_looks_the_same_from_both_faces():
    """The wall is its structure mirrored about the sheet: f(M wo, M wi) = f(wo, wi) for
    reflection and transmission, M = diag(1, 1, -1), within the walks' error."""
    m = OpenPBRSurface(geometry_thin_walled=True, base_color=[0.8, 0.5, 0.3],
                       subsurface_weight=0.5, transmission_weight=0.3, coat_weight=1.0,
                       coat_roughness=0.3, coat_color=[0.9, 0.8, 0.6], fuzz_weight=0.5,
                       specular_roughness=0.4)
    ref = m.reference(n_samples=96)
    wi = WI * np.array([1.0, 1.0, -1.0])[None] ** np.arange(5)[:, None]  # both sides
    mirror = np.array([1.0, 1.0, -1.0])
    (f1, e1), (f2, e2) = ref.eval_with_error(WO, wi), ref.eval_with_error(WO * mirror,
                                                                          wi * mirror)
    assert np.all(f1 > 0.0)
    assert np.all(np.abs(f1 - f2) <= SIGMAS * np.hypot(e1, e2)), (f1, f2, e1, e2)


# -- reciprocity ------------------------------------------------------------------------------
def test_the_structure_reflects_reciprocally():
    m = OpenPBRSurface(base_color=[0.8, 0.5, 0.3], coat_weight=1.0, coat_roughness=0.3,
                       coat_color=[0.9, 0.8, 0.6], fuzz_weight=0.5, specular_roughness=0.4)
    ref = m.reference(n_samples=512)
    rng = np.random.default_rng(3)
    mu = rng.uniform(0.15, 1.0, (2, 6))
    a, b = sph(mu[0], rng.uniform(0, 2 * np.pi, 6)), sph(mu[1], rng.uniform(0, 2 * np.pi, 6))
    (f1, e1), (f2, e2) = ref.eval_with_error(a, b), ref.eval_with_error(b, a)
    assert np.all(np.abs(f1 - f2) <= SIGMAS * np.hypot(e1, e2)), (f1, f2, e1, e2)


# -- the definitions of the coat's colour and the fuzz's -------------------------------------
@pytest.mark.parametrize("roughness", [0.0, 0.5])
def test_the_coat_tints_a_white_base_by_its_colour(roughness):
    """At normal incidence a coat over a white base reflects s + c (a_1 - s), s the coat's
    own reflection and a_1 the clear coat's albedo, within 0.01."""
    c = np.array([0.9, 0.5, 0.1])
    params = dict(coat_weight=1.0, coat_roughness=roughness, coat_ior=1.6, base_color=1.0,
                  specular_weight=0.0, specular_roughness=0.0)
    up = np.array([0.0, 0.0, 1.0])
    tinted = OpenPBRSurface(coat_color=c, **params).reference()
    clear = OpenPBRSurface(**params).reference()
    E, _ = tinted.albedo(up, method="mc", n_samples=100_000, return_error=True)
    a1, _ = clear.albedo(up, method="mc", n_samples=100_000, return_error=True)
    s = _reflected(DielectricMS(1.6, roughness**2), up)
    assert np.all(np.abs(E - (s + c * (a1 - s))) <= 0.01), (E, s + c * (a1 - s))


def _reflected(interface, wo, n=1_000_000):
    """The share of the light from ``wo`` that ``interface`` reflects (its own samples)."""
    s = interface.sample(np.broadcast_to(wo, (n, 3)), np.random.default_rng(9).random((n, 3)))
    return np.where((s.wi[:, 2] > 0.0)[:, None], s.weight, 0.0).mean(0)


def test_the_fuzz_reflects_its_colour_times_a_white_fuzz():
    """Over a black base, the fuzz's reflection averaged over the hemisphere (a Gauss rule in
    cos theta, azimuth averaged by the samples) is fuzz_color times a white fuzz's, within
    0.01."""
    color = np.array([0.9, 0.6, 0.2])
    params = dict(fuzz_weight=1.0, fuzz_roughness=0.5, base_color=0.0, specular_weight=0.0,
                  specular_roughness=0.0)
    x, w = np.polynomial.legendre.leggauss(6)
    mu = 0.5 * (x + 1.0)
    wo = sph(mu, 0.3)

    def average(material):
        E = material.reference().albedo(wo, method="mc", n_samples=40_000)
        return (w * mu) @ E  # 2 int E mu dmu, the rule on [0, 1] (weights halved, times 2)

    ratio = average(OpenPBRSurface(fuzz_color=color, **params)) / average(
        OpenPBRSurface(**params))
    assert np.all(np.abs(ratio - color) <= 0.01), ratio


# -- the solvers, on their own ----------------------------------------------------------------
def test_coat_depth_is_zero_for_a_clear_coat_and_grows_as_the_tint_darkens():
    coat = DielectricMS(1.5, 0.1)
    tau = transport.coat_optical_depth(coat, [1.0, 0.5, 0.0], n_walks=20_000)
    assert tau[0] == 0.0 and 0.0 < tau[1] < tau[2] == 1e3


def test_diffuse_albedo_under_a_smooth_interface_is_the_closed_form():
    """rho = C / (1 - Fbar + C Fbar) with Fbar the internal average by scipy quadrature."""
    rho = transport.diffuse_albedo(DielectricMS(1.5, 0.0), [0.2, 0.5, 1.0], n_walks=400_000)
    Fbar = internal_average(1.5)
    C = np.array([0.2, 0.5, 1.0])
    np.testing.assert_allclose(rho, C / (1.0 - Fbar + C * Fbar), atol=1e-3)


# -- bad input --------------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs, message", [({"n_samples": 0}, "n_samples = 0"),
                                             ({"seed": -1}, "seed = -1"),
                                             ({"n_samples": 2.5}, "n_samples = 2.5")])
def test_bad_arguments_name_themselves(kwargs, message):
    with pytest.raises(ValueError, match=message):
        OpenPBRSurface().reference(**kwargs)


def test_a_textured_or_unsupported_material_is_refused_by_name():
    with pytest.raises(ValueError, match=r"base_color has shape \(4, 3\)"):
        OpenPBRSurface(base_color=np.full((4, 3), 0.5)).reference()
    with pytest.warns(DeprecationWarning):
        hazy = OpenPBRSurface(spec="dev_1.2", specular_haze=0.5, haze_model="barla2018")
    with pytest.raises(ValueError, match="haze_model = 'barla2018'"):
        hazy.reference()


def test_a_film_on_a_bare_metal_is_the_fast_models_film():
    """The film lies on the interface, so a bare filmed metal's structure is its lobe."""
    m = OpenPBRSurface(**presets.openpbr["iridescent metal"])
    np.testing.assert_array_equal(m.reference().eval(WO, WI), m.eval(WO, WI))


# -- emission ---------------------------------------------------------------------------------
@pytest.mark.parametrize("rho", [0.0, 0.8])
def test_emission_through_a_smooth_clear_coat_is_the_closed_form(rho):
    """A Lambertian emitter of radiance L_e (its power fixed: the same into the coat as
    bare) under a smooth clear coat of index n over a Lambertian base of albedo rho (no base
    interface): the radiance inside is L_e / (1 - rho rbar) (the coat sends back rbar of it),
    and n^-2 (1 - F(mu_o)) of it leaves: L(wo) = L_e (1 - F(mu_o)) / (n^2 (1 - rho rbar)),
    rbar by scipy quadrature; within 4 sigma and 2e-3 relative."""
    mu = np.array([1.0, 0.6, 0.2])
    params = dict(emission_luminance=2.0, base_color=rho, specular_weight=0.0,
                  base_diffuse_roughness=0.0, coat_ior=1.5, coat_roughness=0.0)
    bare = OpenPBRSurface(**params).emission(sph(mu))
    ref = OpenPBRSurface(coat_weight=1.0, **params).reference()
    L, se = ref.emission_with_error(sph(mu), n_samples=4000)
    want = bare * ((1.0 - _dielectric(mu, 1.5))
                   / (1.5**2 * (1.0 - rho * internal_average(1.5))))[:, None]
    assert np.all(np.abs(L - want) <= ATOL * want + SIGMAS * se), (L, want, se)


def test_a_bare_emitter_is_the_fast_models_and_opacity_scales_it():
    """Without coat or fuzz the structure emits the fast model's radiance (to rounding: the
    patches' weights sum to 1); at
    geometry_opacity 0.4 (the rest no surface) 0.4 of it; a thin wall the same from both
    faces."""
    params = dict(emission_luminance=3.0, emission_color=[1.0, 0.5, 0.2], base_color=0.3)
    wo = sph(np.array([0.9, 0.3]))
    fast = OpenPBRSurface(**params)
    np.testing.assert_allclose(fast.reference().emission(wo), fast.emission(wo), rtol=1e-12,
                               atol=0.0)
    half = OpenPBRSurface(geometry_opacity=0.4, **params).reference().emission(wo)
    np.testing.assert_allclose(half, 0.4 * fast.emission(wo), rtol=1e-12, atol=0.0)
    thin = OpenPBRSurface(geometry_thin_walled=True, coat_weight=1.0, coat_roughness=0.3,
                          **params).reference()
    (a, ea), (b, eb) = (thin.emission_with_error(w, 2000) for w in (wo, wo * [1, 1, -1]))
    assert np.all(a > 0.0) and np.all(np.abs(a - b) <= SIGMAS * np.hypot(ea, eb)), (a, b)


# -- resources --------------------------------------------------------------------------------
def test_the_reference_runs_in_bounded_memory_whatever_the_batch():
    """A structure (a coat over a metal) evaluated and sampled in blocks of about ``config``
    ``chunk_size`` (one thread): four times the pairs, the same peak."""
    import tracemalloc

    from adobe_bsdf import config

    m = OpenPBRSurface(base_color=0.6, coat_weight=1.0, coat_roughness=0.3,
                       base_metalness=1.0, specular_roughness=0.4)
    ref = m.reference(n_samples=8)
    rng = np.random.default_rng(0)
    peaks = []
    with config.options(chunk_size=512, threads=1):
        for n in (500, 2000):
            wo, wi = (sph(rng.uniform(0.1, 1.0, n), 2.0 * np.pi * rng.random(n))
                      for _ in range(2))
            tracemalloc.start()
            ref.eval(wo, wi)
            ref.albedo(wo[:4], method="mc", n_samples=n)
            peaks.append(tracemalloc.get_traced_memory()[1])
            tracemalloc.stop()
    assert peaks[1] < 1.2 * peaks[0] + 2e6, peaks


def test_a_long_call_shows_one_progress_bar(monkeypatch, capsys):
    """A call that runs past ``config.PROGRESS_DELAY`` (here 0) shows a bar of its blocks;
    the layers inside it, evaluated by the same call, show none."""
    from adobe_bsdf import config

    monkeypatch.setattr(config, "PROGRESS_DELAY", 0.0)
    m = OpenPBRSurface(base_color=0.6, coat_weight=1.0, coat_roughness=0.3)
    ref = m.reference(n_samples=4)
    with config.options(chunk_size=64):
        ref.albedo(sph(np.array([0.9, 0.5]), 0.0), method="mc", n_samples=200)
        err = capsys.readouterr().err
        assert "OpenPBRReference.albedo" in err and "LayeredReference.eval" not in err
        ref.eval(*(sph(np.full(40, 0.5), np.arange(40.0)) for _ in range(2)))
        err = capsys.readouterr().err
        assert "LayeredReference.eval" in err and "albedo" not in err
    # a call shorter than the delay shows nothing
    monkeypatch.setattr(config, "PROGRESS_DELAY", 60.0)
    ref.albedo(sph(np.array([0.9]), 0.0), method="mc", n_samples=50)
    assert capsys.readouterr().err == ""
