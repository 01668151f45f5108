"""The gait search through Python callbacks (``walker._hybrid.search``, walker/_core/newton.c):
the one search of :mod:`walker.analysis.newton` on a map without a compiled path.

Checked here: the fixed points of the Hénon map against their closed form, with the exact
and the finite-difference Jacobian; that an exception raised by the map (a ValueError, a
KeyboardInterrupt) ends the search and propagates unchanged, holding no reference; that a
callback's malformed answer is refused naming what is wrong; and that the binding takes its
settings by keyword only.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest
from _toy_maps import HenonMap, henon_fixed_points

import walker.analysis.newton as newton
from walker import _hybrid
from walker.analysis.fixedpoint import find_fixed_point
from walker.status import Status


def _settings(z0, max_evals=60):
    ev = newton._Search(HenonMap(), 1, None, max_evals, 1e-12, "exact", None, False)
    return ev, ev.settings(50, True, z0.shape[0])


@pytest.mark.parametrize("jacobian", ["exact", "fd"])
def test_henon_fixed_point_matches_its_closed_form(jacobian):
    P = HenonMap(a=0.2, b=0.3)
    want = henon_fixed_points(0.2, 0.3)[0]
    fp = find_fixed_point(P, want + np.array([0.05, -0.02]), jacobian=jacobian)
    assert fp.status == Status.COMPLETED
    np.testing.assert_allclose(fp.section, want, rtol=0, atol=1e-11)


class _Raises(HenonMap):
    """A Hénon map whose third evaluation raises ``error``."""

    def __init__(self, error):
        super().__init__()
        object.__setattr__(self, "error", error)
        object.__setattr__(self, "calls", [0])

    def __call__(self, z, **kwargs):
        self.calls[0] += 1
        if self.calls[0] == 3:
            raise self.error
        return super().__call__(z, **kwargs)


@pytest.mark.parametrize("error", [ValueError("the map broke"), KeyboardInterrupt()])
def test_an_exception_in_the_map_propagates(error):
    P = _Raises(error)
    z0 = henon_fixed_points(0.2, 0.3)[0] + 0.1
    with pytest.raises(type(error)) as caught:
        find_fixed_point(P, z0, jacobian="exact")
    assert caught.value is error
    assert P.calls[0] == 3


def test_a_failing_search_holds_no_reference():
    z0 = henon_fixed_points(0.2, 0.3)[0] + 0.1
    ev, settings = _settings(z0)
    held = object()  # the result object every evaluation hands back
    calls = [0]

    def evaluate(z, level, with_jacobian):
        calls[0] += 1
        if calls[0] == 3:
            raise RuntimeError("third")
        status, z_next, jac, _ = ev.evaluate(z, level, with_jacobian)
        return status, z_next, jac, held

    before = sys.getrefcount(held)
    for _ in range(50):
        calls[0] = 0
        with pytest.raises(RuntimeError, match="third"):
            _hybrid.search(
                z0=z0,
                scale=np.ones(2),
                evaluate=evaluate,
                jacobian=ev.jacobian,
                outside=None,
                **settings,
            )
    assert sys.getrefcount(held) == before
    # a search that converges hands the last result back, once
    out = _hybrid.search(
        z0=z0,
        scale=np.ones(2),
        evaluate=lambda z, level, jac: (*ev.evaluate(z, level, jac)[:3], held),
        jacobian=ev.jacobian,
        outside=None,
        **settings,
    )
    assert out[0] == newton._C_CONVERGED and out[-1] is held
    del out
    assert sys.getrefcount(held) == before


@pytest.mark.parametrize(
    "answer, error, words",
    [
        (None, TypeError, r"a callback must return \(status, z, jac, result\)"),
        ((0, np.zeros(3), None, None), ValueError, r"`z` must have length 2"),
        ((0, np.zeros(2, dtype=np.float32), None, None), TypeError, r"`z` must be a C-contig"),
        (("0", np.zeros(2), None, None), TypeError, r"`status`"),
    ],
)
def test_a_malformed_answer_is_refused(answer, error, words):
    z0 = np.array([0.5, 0.1])
    ev, settings = _settings(z0)
    with pytest.raises(error, match=words):
        _hybrid.search(
            z0=z0,
            scale=np.ones(2),
            evaluate=lambda *args: answer,
            jacobian=ev.jacobian,
            outside=None,
            **settings,
        )


def test_the_binding_takes_keywords_only():
    z0 = np.array([0.5, 0.1])
    ev, settings = _settings(z0)
    kwargs = dict(z0=z0, scale=np.ones(2), evaluate=ev.evaluate, jacobian=ev.jacobian, outside=None)
    with pytest.raises(TypeError, match="keyword arguments only"):
        _hybrid.search(z0, **{k: v for k, v in kwargs.items() if k != "z0"}, **settings)
    missing = dict(settings)
    del missing["armijo"]
    with pytest.raises(TypeError, match="missing required keyword argument 'armijo'"):
        _hybrid.search(**kwargs, **missing)
    with pytest.raises(TypeError, match="unexpected keyword argument 'typo'"):
        _hybrid.search(**kwargs, **settings, typo=1.0)
    with pytest.raises(ValueError, match=r"`max_iter` must be in \[1, 10000000\], got 0"):
        _hybrid.search(**kwargs, **{**settings, "max_iter": 0})
    with pytest.raises(ValueError, match=r"`scale` finite and > 0"):
        _hybrid.search(**{**kwargs, "scale": np.zeros(2)}, **settings)
