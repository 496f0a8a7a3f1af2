"""The whole Adobe Standard Material over its documented parameter ranges: every parameter
drawn at once, directions and sample numbers including the extremes (subnormal and zero
cosines, the tangent plane, u at 0 and 1 - 2^-53), RuntimeWarnings as errors.

Values: eval, pdf and samples finite and never negative; albedo by table and by Monte Carlo
at most 1 + 1e-3 (colours <= 1), anisotropic materials included (their metal and diffuse
read the anisotropic energy tables). The default run draws a few hundred materials per
property; ``-m slow`` the exhaustive 2000 (``tests.sweeps``)."""

import warnings

import numpy as np
from hypothesis import assume
from hypothesis import strategies as st

from adobe_bsdf.materials import AdobeStandardMaterial
from adobe_bsdf.materials.asm import PARAMETERS
from tests.sweeps import sweep

#: finite stand-ins for the unbounded ranges (soft ranges are advice, not limits)
_FINITE = {"dispersion": (0.0, 5.0), "scattering_distance": (0.0, 1e6),
           "scattering_distance_scale": (0.0, 1e6), "scatter_rayleigh": (-1e3, 1e3),
           "emissive_intensity": (0.0, 1e6)}
_EXTREME_COSINES = [0.0, -0.0, 5e-324, -5e-324, 2.2e-311, 1e-300, -1e-300, 1e-100, 1e-8,
                    1.0, -1.0, 1.0 - 2.0**-53]
_U = st.one_of(st.floats(0.0, 1.0, exclude_max=True), st.just(0.0), st.just(1.0 - 2.0**-53))


def _value(p, lo, hi):
    number = st.one_of(st.floats(lo, hi), st.sampled_from([lo, hi]))
    return st.one_of(number, st.tuples(number, number, number)) if p.kind == "color" else number


def _parameters():
    optional = {}
    for p in PARAMETERS:
        if p.name == "scattering_color":  # a colour or None (the default: base_color)
            optional[p.name] = st.one_of(st.none(), _value(p, *p.hard))
        else:
            optional[p.name] = _value(p, *_FINITE.get(p.name, p.hard))
    return st.fixed_dictionaries({}, optional=optional)


def _material(params):
    """The material, or a rejected example where dispersion spreads the channel indices out
    of the tables' range (a documented ValueError naming ior and dispersion)."""
    try:
        return AdobeStandardMaterial(**params)
    except ValueError as error:
        assume("dispersion" not in str(error))
        raise


def _direction(z, phi):
    s = np.sqrt(max(0.0, (1.0 - z) * (1.0 + z)))
    return np.array([s * np.cos(phi), s * np.sin(phi), z])


_COSINE = st.one_of(st.floats(-1.0, 1.0), st.sampled_from(_EXTREME_COSINES))
_AZIMUTH = st.one_of(st.floats(0.0, 2.0 * np.pi), st.sampled_from([0.0, np.pi]))


def _finite(params, zo, phi_o, zi, phi_i, u):
    material = _material(params)
    wo, wi = _direction(zo, phi_o), _direction(zi, phi_i)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        f, pdf = material.eval(wo, wi), material.pdf(wo, wi)
        s = material.sample(wo, np.array(u))
    for name, value in (("eval", f), ("pdf", pdf), ("weight", s.weight), ("sample pdf", s.pdf)):
        assert np.all(np.isfinite(value)) and np.all(value >= 0.0), (name, value)
    if s.pdf > 0.0:
        assert abs(np.linalg.norm(s.wi) - 1.0) < 1e-12


_FINITE_ARGS = (_parameters(), _COSINE, _AZIMUTH, _COSINE, _AZIMUTH, st.tuples(_U, _U, _U))
test_values_are_finite_and_never_negative = sweep(_finite, 100, *_FINITE_ARGS)
test_values_are_finite_and_never_negative_exhaustively = sweep(_finite, 2000, *_FINITE_ARGS,
                                                               slow=True)

_ALBEDO_COSINES = np.array([1.0, 0.5, 0.02, 1e-4, 1e-8, 5e-324])


def _table_albedo(params, phi):
    material = _material(params)
    wo = np.array([_direction(z, phi) for z in _ALBEDO_COSINES])
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        try:
            albedo = material.albedo(wo, method="table")
        except ValueError as error:  # channel indices beyond the tables (documented)
            assume("dispersion" not in str(error))
            raise
    assert np.all(np.isfinite(albedo)) and np.all(albedo >= 0.0)
    assert np.all(albedo <= 1.0 + 1e-3), albedo


test_table_albedo_is_at_most_one = sweep(_table_albedo, 60, _parameters(), _AZIMUTH)
test_table_albedo_is_at_most_one_exhaustively = sweep(_table_albedo, 2000, _parameters(),
                                                      _AZIMUTH, slow=True)


def _monte_carlo_albedo(params, phi, seed):
    material = _material(params)
    wo = np.array([_direction(z, phi) for z in (0.9, 0.1, 1e-3)])
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        albedo, sigma = material.albedo(wo, method="mc", n_samples=4000, rng=seed,
                                        return_error=True)
    assert np.all(np.isfinite(albedo)) and np.all(albedo >= 0.0)
    assert np.all(albedo <= 1.0 + 1e-3 + 5.0 * sigma), (albedo, sigma)


_MC_ARGS = (_parameters(), _AZIMUTH, st.integers(0, 2**32 - 1))
#: a nearly smooth anisotropic coat: it gained 0.0076
_MC_EXAMPLES = [({"roughness": 0.0, "coat_opacity": 1.0, "coat_anisotropy_level": 0.03125,
                  "base_color": 0.0}, 0.3, 1)]
test_monte_carlo_albedo_is_at_most_one = sweep(_monte_carlo_albedo, 30, *_MC_ARGS,
                                               examples=_MC_EXAMPLES)
test_monte_carlo_albedo_is_at_most_one_exhaustively = sweep(
    _monte_carlo_albedo, 150, *_MC_ARGS, examples=_MC_EXAMPLES, slow=True)
