"""``OpenPBRSurface(spec=...)``: the released v1.1.1 by default, the development branch
dev_1.2 on request (``docs/openpbr.md``, the versions). Expected values are the
specification's definitions and closed forms."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from adobe_bsdf import fresnel, media
from adobe_bsdf.materials import OpenPBRSurface
from adobe_bsdf.materials.openpbr import DEV_1_2, SPECS

NORMAL = np.array([0.0, 0.0, 1.0])


def _sph(mu, phi):
    s = np.sqrt(1.0 - mu * mu)
    return np.array([s * np.cos(phi), s * np.sin(phi), mu])


def test_the_default_is_the_release():
    assert SPECS == ("1.1.1", "dev_1.2")
    assert OpenPBRSurface().spec == "1.1.1"
    assert OpenPBRSurface(spec="dev_1.2").spec == "dev_1.2"
    assert set(OpenPBRSurface().params) & set(DEV_1_2) == set()
    assert set(DEV_1_2) <= set(OpenPBRSurface(spec="dev_1.2").params)


# -- the coat's tint under v1.1.1 ---------------------------------------------------------------
@settings(max_examples=25, deadline=None)
@given(c=st.tuples(*[st.floats(0.05, 1.0)] * 3), delta=st.sampled_from([0.0, 1.0]),
       coat_roughness=st.sampled_from([0.0, 0.05]) | st.floats(0.0, 0.6),
       coat_ior=st.floats(1.2, 2.2), base_color=st.floats(0.0, 1.0),
       roughness=st.floats(0.1, 1.0), metalness=st.sampled_from([0.0, 1.0]))
def test_the_tint_at_normal_incidence_is_coat_color(c, delta, coat_roughness, coat_ior,
                                                    base_color, roughness, metalness):
    """v1.1.1 [OpenPBR2026, §Coat] (and the draft's "observed tint of the underlying base at
    normal incidence"): (f_c - f_s) / (f_1 - f_s) at wo = wi = n is coat_color, f_s the coat
    alone, f_1 the same coat clear, whatever the darkening."""
    p = dict(base_color=base_color, specular_roughness=roughness, base_metalness=metalness,
             coat_weight=1.0, coat_roughness=coat_roughness, coat_ior=coat_ior,
             coat_darkening=delta)
    tinted = OpenPBRSurface(coat_color=c, **p)
    clear = OpenPBRSurface(**p)
    f_s = tinted.lobes["coat"].eval(NORMAL, NORMAL)
    f_c, f_1 = tinted.eval(NORMAL, NORMAL), clear.eval(NORMAL, NORMAL)
    # a base that reflects nothing at normal incidence has no tint to observe (a black
    # dielectric whose index the coat matches: no interface below it)
    assume(np.all(f_1 - f_s > 1e-9 * np.abs(f_1)))
    np.testing.assert_allclose((f_c - f_s) / (f_1 - f_s), c, atol=0.01)


def test_the_tint_of_a_white_base_is_the_peer_s():
    """A white base under coat_color (0.4, 0.6, 0.8) reflects about the colour at mu 0.9
    (Adobe's OpenPBR implementation: 0.4056, 0.5986, 0.7970), not the darker dev_1.2 one."""
    m = OpenPBRSurface(base_color=1.0, specular_color=1.0, specular_roughness=0.3,
                       coat_weight=1.0, coat_color=(0.4, 0.6, 0.8), coat_roughness=0.1)
    E = m.albedo(_sph(0.9, 0.7), tol=1e-6)
    np.testing.assert_allclose(E, (0.4056, 0.5986, 0.7970), atol=0.01)


# -- the switch and its aliases -----------------------------------------------------------------
def test_the_deprecated_options_are_aliases_of_spec():
    wo, wi = _sph(0.7, 0.2), _sph(0.5, 2.0)
    p = dict(coat_weight=1.0, coat_color=(0.5, 0.7, 0.9), base_color=0.6)
    for option, value, spec in (("darkening_variant", "v1.1.1", "1.1.1"),
                                ("darkening_variant", "pr253", "dev_1.2"),
                                ("haze_model", "dev_1.2", "dev_1.2")):
        with pytest.warns(DeprecationWarning, match=f"{option} = '{value}'.*spec = '{spec}'"):
            old = OpenPBRSurface(**{option: value}, **p)
        assert old.spec == spec
        np.testing.assert_array_equal(old.eval(wo, wi), OpenPBRSurface(spec=spec, **p)
                                      .eval(wo, wi))


@pytest.mark.parametrize(("kwargs", "message"), [
    (dict(spec="1.1.1", darkening_variant="pr253"), "darkening_variant = 'pr253' means spec "
                                                    "= 'dev_1.2', against spec = '1.1.1'"),
    (dict(darkening_variant="v1.1.1", haze_model="dev_1.2"), "haze_model = 'dev_1.2'"),
    (dict(spec="1.2"), "spec = '1.2'"),
    (dict(specular_haze=0.2), "specular_haze = 0.2 is an input of dev_1.2"),
    (dict(emission_weight=1.0), "emission_weight = 1.0 is an input of dev_1.2"),
    (dict(spec="1.1.1", specular_retroreflectivity=0.0), "specular_retroreflectivity"),
    (dict(spec="dev_1.2", specular_retroreflectivity=1.5), "specular_retroreflectivity"),
])
def test_bad_versions(kwargs, message):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
            OpenPBRSurface(**kwargs)


# -- what the version changes -------------------------------------------------------------------
def test_transmission_scatter_by_version():
    """v1.1.1: sigma_s = S / d, shifted where sigma_a < 0; dev_1.2 (PR 286): S is the
    single-scattering albedo, sigma_s = S sigma_t."""
    T, d, S = np.array([0.5, 0.7, 0.9]), 2.0, np.array([0.2, 0.4, 0.6])
    sigma_t = -np.log(T) / d
    p = dict(transmission_weight=1.0, transmission_color=T, transmission_depth=d,
             transmission_scatter=S)
    released = OpenPBRSurface(**p).medium()
    sigma_a = sigma_t - S / d
    np.testing.assert_allclose(released.sigma_s, S / d, rtol=1e-14)
    np.testing.assert_allclose(released.sigma_a, sigma_a - min(sigma_a.min(), 0.0), rtol=1e-14)
    dev = OpenPBRSurface(spec="dev_1.2", **p).medium()
    np.testing.assert_allclose(dev.sigma_s, S * sigma_t, rtol=1e-14)
    np.testing.assert_allclose(dev.sigma_a, (1.0 - S) * sigma_t, rtol=1e-14)
    with pytest.raises(ValueError, match="spec = 'v2'"):
        media.openpbr_transmission_medium(T, d, S, spec="v2")


def test_metal_specular_weight_above_one():
    """v1.1.1 limits the metal's specular_weight to 1; dev_1.2 lets it scale the Fresnel,
    clamped to 1 [OpenPBR2026dev, §Metal]."""
    wo = np.stack([_sph(mu, 0.3) for mu in (0.9, 0.5, 0.2)])
    p = dict(base_metalness=1.0, base_color=(0.5, 0.3, 0.2), specular_roughness=0.3)
    E1 = OpenPBRSurface(**p).albedo(wo, tol=1e-6)
    np.testing.assert_array_equal(OpenPBRSurface(**p, specular_weight=1.5).albedo(wo, tol=1e-6),
                                  E1)
    E = OpenPBRSurface(spec="dev_1.2", **p, specular_weight=1.5).albedo(wo, tol=1e-6)
    assert np.all(E > E1 + 0.05) and np.all(E <= 1.0)
    # the Fresnel itself: clamp(xi F82, 0, 1) against the closed form
    mu = np.linspace(0.0, 1.0, 11)
    F = fresnel.f82_tint(mu, (0.5, 0.3, 0.9), 1.0)
    np.testing.assert_allclose(fresnel.Weighted(fresnel.F82Tint((0.5, 0.3, 0.9), 1.0), 1.5)(mu),
                               np.clip(1.5 * F, 0.0, 1.0), rtol=1e-15)


def test_specular_color_on_glass_by_version():
    """The glass's reflection is tinted by specular_color from above (v1.1.1) or from both
    sides (dev_1.2); its refraction never: E = r E_R + E_T."""
    tint = np.array([1.0, 0.5, 0.2])
    p = dict(transmission_weight=1.0, specular_roughness=0.3)
    wo = _sph(0.6, 0.4)
    for side in (1.0, -1.0):
        w = wo * [1.0, 1.0, side]
        E = OpenPBRSurface(**p).albedo(w, tol=1e-7)
        E_T = OpenPBRSurface(**p, specular_color=0.0, spec="dev_1.2").albedo(w, tol=1e-7)
        E_R = E - E_T
        for spec in SPECS:
            tinted = OpenPBRSurface(**p, specular_color=tint, spec=spec).albedo(w, tol=1e-7)
            r = tint if side > 0 or spec == "dev_1.2" else 1.0
            np.testing.assert_allclose(tinted, r * E_R + E_T, atol=2e-6)


def test_emission_weight():
    wo = _sph(0.8, 0.1)
    p = dict(emission_luminance=500.0, emission_color=(1.0, 0.5, 0.25))
    full = OpenPBRSurface(**p).emission(wo)
    np.testing.assert_allclose(full, np.array([1.0, 0.5, 0.25]) * 500.0 / 683.0, rtol=1e-14)
    np.testing.assert_array_equal(OpenPBRSurface(spec="dev_1.2", **p).emission(wo), 0.0)
    np.testing.assert_allclose(OpenPBRSurface(spec="dev_1.2", emission_weight=0.3, **p)
                               .emission(wo), 0.3 * full, rtol=1e-14)


# -- the coat darkening of dev_1.2 ---------------------------------------------------------------
@pytest.mark.parametrize(("coat_ior", "coat_roughness", "E_b"), [
    (1.3, 0.0, 1.0), (1.5, 0.3, 0.5), (2.0, 0.5, 1.0), (2.0, 0.0, 0.5), (1.3, 0.5, 0.5)])
def test_dev_darkening_is_the_random_walk(coat_ior, coat_roughness, E_b):
    """spec "dev_1.2", coat_darkening 1: a white or grey Lambertian base (no specular
    interface: specular_weight 0, sigma 0) under a tinted coat reflects, near normal
    incidence, what random walks through the absorbing coat reflect (within 0.02)
    [Portsmouth2025]."""
    from tests.test_darkening_physical import TINT, _walk

    mu = 0.95
    m = OpenPBRSurface(spec="dev_1.2", base_color=E_b, specular_weight=0.0,
                       base_diffuse_roughness=0.0, coat_weight=1.0, coat_color=TINT,
                       coat_ior=coat_ior, coat_roughness=coat_roughness)
    walk, sigma = _walk(coat_ior, coat_roughness**2, E_b, mu)
    E = m.albedo(_sph(mu, 0.0), tol=1e-6)
    assert np.all(np.abs(E - walk) <= 0.02), (E, walk, sigma)


@pytest.mark.parametrize("coat_roughness", [0.0, 0.3])
def test_dev_without_darkening_is_the_naive_albedo(coat_roughness):
    """coat_darkening 0 under dev_1.2: E_coat + T^2 E_b (1 - E_coat) [Portsmouth2025], E_coat
    the coat's own albedo and E_b the Lambertian base's."""
    T2, E_b = np.array([0.3, 0.55, 0.85]), 0.6
    m = OpenPBRSurface(spec="dev_1.2", base_color=E_b, specular_weight=0.0,
                       base_diffuse_roughness=0.0, coat_weight=1.0, coat_color=T2,
                       coat_roughness=coat_roughness, coat_darkening=0.0)
    wo = np.stack([_sph(mu, 0.3) for mu in (0.95, 0.9)])
    E_coat = m.lobes["coat"].albedo(wo, tol=1e-7)
    np.testing.assert_allclose(m.albedo(wo, tol=1e-7), E_coat + T2 * E_b * (1.0 - E_coat),
                               atol=1e-5)
