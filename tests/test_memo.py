"""``adobe_bsdf._memo``: a quantity of one direction array is computed once per call, and only
within the call; cached values cannot be changed in place."""

import threading

import numpy as np
import pytest

from adobe_bsdf import _memo
from adobe_bsdf.materials import AdobeStandardMaterial
from adobe_bsdf.materials.asm.diffuse import ASMDiffuse


class _Counter:
    def __init__(self):
        self.calls = 0

    def __call__(self, w):
        self.calls += 1
        return w[..., 2] * 2.0


def test_once_per_scope_per_array_object():
    owner, count = object(), _Counter()
    w = np.ones((4, 3))
    assert _memo.once(owner, "x", w, count) is not _memo.once(owner, "x", w, count)
    assert count.calls == 2  # outside a scope: every time
    with _memo.scope():
        first = _memo.once(owner, "x", w, count)
        assert _memo.once(owner, "x", w, count) is first
        assert count.calls == 3
        _memo.once(owner, "x", w.copy(), count)  # equal values, another array: computed
        _memo.once(owner, "y", w, count)  # another name
        _memo.once(object(), "x", w, count)  # another owner
        assert count.calls == 6
        with pytest.raises(ValueError, match="read-only"):
            first[0] = 1.0
        with _memo.scope():  # a nested call starts afresh
            _memo.once(owner, "x", w, count)
            assert count.calls == 7
        assert _memo.once(owner, "x", w, count) is first
    _memo.once(owner, "x", w, count)
    assert count.calls == 8


def test_scopes_are_per_thread():
    owner, count, w = object(), _Counter(), np.ones((2, 3))
    seen = []
    with _memo.scope():
        _memo.once(owner, "x", w, count)
        thread = threading.Thread(target=lambda: seen.append(_memo.once(owner, "x", w, count)))
        thread.start()
        thread.join()
    assert count.calls == 2 and len(seen) == 1


def test_a_layered_material_computes_its_diffuse_energy_once_per_direction(monkeypatch):
    """The fully loaded ASM's diffuse needs 1 - L at wo for the sampling weights of three
    levels (coat, sheen, base) and for f: with the memo, one lookup at wo and one at wi
    per chunk, and the same values as without it."""
    calls = []
    original = ASMDiffuse._X

    def counted(self, w):
        calls.append(w.shape)
        return original(self, w)

    material = AdobeStandardMaterial(base_color=(0.8, 0.5, 0.2), roughness=0.4,
                                     anisotropy_level=0.5, coat_opacity=0.7, sheen_opacity=0.5)
    rng = np.random.default_rng(0)
    wo, wi = (np.abs(rng.normal(size=(2, 1000, 3))) / np.sqrt(3.0))
    wo /= np.linalg.norm(wo, axis=-1, keepdims=True)
    wi /= np.linalg.norm(wi, axis=-1, keepdims=True)
    monkeypatch.setattr(ASMDiffuse, "_X", counted)
    f, pdf = material.eval_pdf(wo, wi)
    assert len(calls) == 2
    calls.clear()
    with monkeypatch.context() as m:
        m.setattr(_memo, "once", lambda owner, name, w, compute: compute(w))
        f_plain, pdf_plain = material.eval_pdf(wo, wi)
    assert len(calls) > 2, "the memo did not remove anything"
    np.testing.assert_array_equal(f, f_plain)
    np.testing.assert_array_equal(pdf, pdf_plain)


def test_rows_of_an_array_take_the_rows_of_its_kept_value():
    """``rows(w, index)`` links the gathered array to ``w``: ``once`` on it takes the rows of
    the value kept for ``w`` (each part of a tuple; a part that broadcasts as is) without
    computing; outside a scope, or below ``ROWS_MIN`` rows, it computes."""
    owner, count = object(), _Counter()
    rng = np.random.default_rng(2)
    w = rng.normal(size=(200, 3))
    index = np.array([5, 0, 199, 17])

    def pair(w):
        count.calls += 1
        return w[..., 2] * 2.0, np.ones(3)

    with _memo.scope():
        part = _memo.rows(w, index)
        np.testing.assert_array_equal(part, w[index])
        assert _memo.once(owner, "x", part, pair)[0].tolist() == (w[index, 2] * 2.0).tolist()
        assert count.calls == 1  # nothing kept for w yet: computed on the rows
        full = _memo.once(owner, "x", w, pair)
        again = _memo.rows(w, index)
        value = _memo.once(owner, "x", again, pair)
        assert count.calls == 2
        np.testing.assert_array_equal(value[0], full[0][index])
        assert value[1] is full[1]
        many = np.arange(199, 99, -1)  # rows of rows (each at least ROWS_MIN long)
        nested = _memo.rows(_memo.rows(w, many), np.array([3, 1]))
        np.testing.assert_array_equal(_memo.once(owner, "x", nested, pair)[0],
                                      full[0][many[[3, 1]]])
        assert count.calls == 2
        small = w[:_memo.ROWS_MIN - 1]
        _memo.once(owner, "x", small, pair)
        _memo.once(owner, "x", _memo.rows(small, [0, 1]), pair)
        assert count.calls == 4
    _memo.once(owner, "x", _memo.rows(w, index), pair)
    assert count.calls == 5


def test_rows_of_a_kept_value_serve_what_is_kept_for_that_value(monkeypatch):
    """A value served as rows of the one kept for ``w`` (a ``Rotated`` lobe's turned ``wo``)
    is itself linked to the kept value: what is kept for the whole turned batch serves its
    rows. The rotated, anisotropic ASM's diffuse then looks 1 - L up at wo once per
    chunk in ``sample`` (and at each group's sampled directions), and the samples are the
    bits they are without the memo."""
    owner, count = object(), _Counter()
    w = np.random.default_rng(4).normal(size=(300, 3))
    index = np.arange(250, 50, -1)

    def turned(w):
        return w[..., ::-1].copy()

    with _memo.scope():
        kept = _memo.once(owner, "turn", w, turned)
        full = _memo.once(owner, "x", kept, count)
        part = _memo.once(owner, "turn", _memo.rows(w, index), turned)
        assert _memo.once(owner, "x", part, count).tolist() == full[index].tolist()
        assert count.calls == 1  # the rows of the turned batch were not computed again

    at = []
    original = ASMDiffuse._X

    def counted(self, w):
        at.append(w)
        return original(self, w)

    material = AdobeStandardMaterial(base_color=(0.8, 0.5, 0.2), roughness=0.4,
                                     anisotropy_level=0.5, anisotropy_angle=0.3,
                                     coat_opacity=0.7, sheen_opacity=0.5)
    rng = np.random.default_rng(1)
    wo = np.abs(rng.normal(size=(3000, 3)))
    wo /= np.linalg.norm(wo, axis=-1, keepdims=True)
    u = rng.random((3000, 3))
    monkeypatch.setattr(ASMDiffuse, "_X", counted)
    s = material.sample(wo, u)
    assert sum(len(w) for w in at) < 2 * len(wo)  # wo once, each sampled direction at most once
    assert len(at[0]) == len(wo)
    with monkeypatch.context() as m:
        m.setattr(_memo, "once", lambda owner, name, w, compute: compute(w))
        plain = material.sample(wo, u)
    for a, b in zip(s, plain, strict=True):
        np.testing.assert_array_equal(a, b)
