"""The private protocol is declared once (``bsdf.HOOKS``) and ``composition.Wrapper`` forwards
exactly that list; a material layered under another sees its lobe tree's hooks."""

from __future__ import annotations

import numpy as np
import pytest

import adobe_bsdf as ab
from adobe_bsdf.bsdf import HOOKS, BSDFSample, Lobe
from adobe_bsdf.composition import Rotated, Wrapper
from adobe_bsdf.materials import Material

HOOK_NAMES = [h.name for h in HOOKS]
#: private methods of ``Lobe`` that are machinery, not hooks a lobe implements
MACHINERY = {"_batched", "_sampling_weight_at"}


def test_every_private_method_of_lobe_is_a_declared_hook():
    private = {name for name, value in vars(Lobe).items()
               if name.startswith("_") and not name.startswith("__") and callable(value)}
    assert private - MACHINERY == set(HOOK_NAMES)
    assert len(HOOK_NAMES) == len(set(HOOK_NAMES))
    assert all(h.contract for h in HOOKS)


def test_wrapper_defines_a_forwarding_method_for_every_hook():
    missing = [name for name in HOOK_NAMES if name not in vars(Wrapper)]
    assert not missing


class _Recorder(Lobe):
    """Answers every hook with a token naming it and records the arguments."""

    def __init__(self):
        self.calls = []

    def __getattribute__(self, name):
        if name in HOOK_NAMES:
            def hook(*args, **kwargs):
                self.calls.append((name, args, kwargs))
                if name.startswith("_sample"):
                    wi = np.array([[1.0, 0.0, 0.0]])
                    return BSDFSample(wi, np.ones((1, 3)), np.ones(1), np.ones(1, dtype=int))
                return f"from {name}"
            return hook
        return super().__getattribute__(name)


class _Around(Wrapper):
    def __init__(self, inner):
        self.inner = inner

    def _inner(self):
        return self.inner


_W = np.array([[0.6, 0.0, 0.8]])


def _arguments(hook):
    values = {"wo": _W, "wi": -_W, "u": np.full((1, 3), 0.5), "throughput": np.ones((1, 3)),
              "with_error": False, "tol": 1e-6}
    return tuple(values[a] for a in hook.args)


@pytest.mark.parametrize("hook", HOOKS, ids=HOOK_NAMES)
def test_wrapper_forwards_each_hook_with_its_arguments(hook):
    inner = _Recorder()
    arguments = _arguments(hook)
    result = getattr(_Around(inner), hook.name)(*arguments)
    (name, args, kwargs), = inner.calls
    assert name == hook.name and kwargs == {}
    for value, given in zip(args, arguments, strict=True):
        assert value is given
    if not hook.name.startswith("_sample"):
        assert result == f"from {hook.name}"


@pytest.mark.parametrize("hook", [h for h in HOOKS if h.args], ids=lambda h: h.name)
def test_rotated_turns_directions_in_and_samples_out(hook):
    """``Rotated`` forwards through the same list, with its frame change on every direction
    argument (a quarter turn takes +x to -y in the inner frame) and on sampled ``wi``; only
    ``_param_shape`` is its own (the rotation's shape joins the lobe's)."""
    inner = _Recorder()
    rotated = Rotated(inner, np.pi / 2)
    result = getattr(rotated, hook.name)(*_arguments(hook))
    (name, args, _), = inner.calls
    assert name == hook.name
    for arg, value, given in zip(hook.args, args, _arguments(hook), strict=True):
        if arg in ("wo", "wi"):
            np.testing.assert_allclose(value, rotated._turn(given, -1.0), atol=1e-15)
            assert not np.allclose(value, given)
    if hook.name.startswith("_sample"):
        np.testing.assert_allclose(result.wi, [[0.0, 1.0, 0.0]], atol=1e-15)


def _grazing(cos_theta=0.05, phi=0.0):
    s = np.sqrt(1.0 - cos_theta**2)
    return np.array([s * np.cos(phi), s * np.sin(phi), cos_theta])


def test_material_forwards_the_top_albedo_of_an_anisotropic_coat():
    """Regression: ``Material`` once did not forward ``_top_albedo`` and fell back to the
    coat's isotropic table, 0.234 at grazing where the coat's own answer is 0.143."""
    with ab.config.options(anisotropic_energy="isotropic"):  # a table that is wrong here
        coat = ab.materials.asm.asm_coat(1.6, 0.2, 1.0, 0.0)
    wo = _grazing()
    quadrature = coat.albedo(wo, method="quadrature", tol=1e-7)
    table = coat.albedo(wo, method="table")
    assert np.all(np.abs(table - quadrature) > 0.02)  # the table would be wrong here
    material = Material(coat)
    np.testing.assert_array_equal(material._top_albedo(wo), coat._top_albedo(wo))
    np.testing.assert_allclose(material._top_albedo(wo), quadrature, atol=2e-3)


def test_material_layered_under_another_uses_the_coats_top_albedo():
    """A layer whose top is a ``Material`` around that coat scales its base by the coat's
    true albedo: its white furnace stays at or below 1."""
    coat = Material(ab.materials.asm.asm_coat(1.6, 0.2, 1.0, 0.0))
    layer = ab.composition.Layer(coat, ab.lobes.Lambert(1.0))
    wo = _grazing()
    value = layer.albedo(wo, method="quadrature", tol=1e-6)
    assert np.all(value <= 1.0 + 2e-3)


def _case_ids():
    from adobe_bsdf.validation.cases import cases

    return [c.name for c in cases()]


@pytest.mark.parametrize("name", _case_ids())
def test_sample_directions_is_the_sample_without_the_non_delta_weights(name):
    """``_sample_directions`` (what a mixture asks of a component) draws what ``_sample_t``
    draws: the same directions and flags bit for bit, the delta samples' weights and pdfs,
    and elsewhere a weight of 0 (a lobe that skips it) or the sample's own, and a pdf that
    is positive where the sample's is (a mixture's: its drawing component's), for every
    check case, from both sides, with and without a path throughput."""
    from adobe_bsdf.bsdf import Flags
    from adobe_bsdf.validation.cases import cases

    lobe = next(c for c in cases() if c.name == name).make()
    rng = np.random.default_rng(11)
    wo = rng.standard_normal((600, 3))
    wo /= np.linalg.norm(wo, axis=-1, keepdims=True)
    u = rng.random((600, 3))
    for throughput in (None, np.array([0.2, 0.5, 0.9])):
        full = lobe._sample_t(wo, u, throughput)
        drawn = lobe._sample_directions(wo, u, throughput)
        for field in ("wi", "flags"):
            np.testing.assert_array_equal(getattr(drawn, field), getattr(full, field))
        delta = (full.flags & int(Flags.DELTA)) != 0
        np.testing.assert_array_equal(drawn.weight[delta], full.weight[delta])
        np.testing.assert_array_equal(drawn.pdf[delta], full.pdf[delta])
        np.testing.assert_array_equal(drawn.pdf > 0.0, full.pdf > 0.0)
        other = np.broadcast_to(drawn.weight, full.weight.shape)[~delta]
        assert np.all((other == 0.0) | (other == full.weight[~delta]))
