"""The gait search on a walker's stride map in one compiled call (``PreparedMap.search``)
against the same search (walker/_core/newton.c) evaluating the map through Python callbacks
(``walker._hybrid.search``), the path of every map without a compiled call.

For a :class:`~walker.simulation.stride.StrideMap` with a compiled call, ``find_fixed_point`` with
the exact Jacobian runs the whole search in C; here the callbacks are forced by making the
compiled call decline.  Both paths run one search on strides that ``StrideMap.__call__``
integrates with the same compiled run, so they must end the same way from the same guess,
bit for bit: the same status, message, iterations, history, solution and multipliers.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import walker.analysis.newton as newton
from walker import load_scene
from walker.analysis.fixedpoint import find_fixed_point
from walker.simulation.stride import StrideMap
from walker.status import Status

GAITS = Path(__file__).resolve().parents[1] / "gaits"


def _scene_map(name):
    scene = load_scene(GAITS / name)
    P = StrideMap.from_scene(scene)
    return P, P.project(scene.state)


def _both(monkeypatch, P, z, **kwargs):
    """(compiled, callbacks) results of find_fixed_point from z."""
    compiled = find_fixed_point(P, z, **kwargs)
    with monkeypatch.context() as m:
        m.setattr(newton, "_compiled_search", lambda *a, **k: None)
        python = find_fixed_point(P, z, **kwargs)
    return compiled, python


def _assert_same(a, b):
    assert a.status == b.status
    assert a.n_iter == b.n_iter
    assert a.message == b.message
    assert np.array_equal(a.section, b.section)
    assert np.array_equal(a.history, b.history)
    assert np.array_equal(a.multipliers, b.multipliers, equal_nan=True)
    if a.success:
        assert a.step_time == b.step_time


def test_the_compiled_search_runs_for_a_scene_map():
    for name in ("simplest_garcia.toml", "compass_goswami.toml"):
        assert _scene_map(name)[0]._compiled_search() is not None
    P, z0 = _scene_map("kneed_hsu.toml")
    assert P._compiled_search() is not None
    ev = newton._Search(P, 1, None, 60, 1e-12, "exact", None, True)
    region = newton.WalkingRegion.of(P)
    region.with_guess(z0)
    out = newton._compiled_search(ev, z0, region, ev.settings(50, True, 3))
    assert out is not None and out[0] == newton._C_CONVERGED
    assert out[3] == 5  # the coarse glance and four Jacobian strides (test_inexact_newton)
    solved = newton._ended(ev, out, region, 50, True)
    assert solved.success and solved.known is not None and solved.known.jac.shape == (3, 3)


@pytest.mark.parametrize(
    "name, kinds",
    [
        # statuses the 40 guesses reach: convergence, falls, a trip, the budget
        ("kneed_hsu.toml", {"COMPLETED", "TRIPPED", "FELL_BACKWARD", "BUDGET_EXHAUSTED"}),
        ("compass_goswami.toml", {"COMPLETED", "FELL_FORWARD", "FELL_BACKWARD"}),
        # a lift that is not affine, compiled (walker/_core/model_simplest.c)
        ("simplest_garcia.toml", {"COMPLETED", "FELL_FORWARD", "FELL_BACKWARD"}),
    ],
)
def test_random_guesses_end_as_through_callbacks(name, kinds, monkeypatch):
    P, z0 = _scene_map(name)
    gait = find_fixed_point(P, z0).section
    rng = np.random.default_rng(1)
    guesses = [z0] + [gait * (1 + rng.uniform(-0.5, 0.5, gait.shape)) for _ in range(40)]
    seen = set()
    for z in guesses:
        for kwargs in ({}, {"fallback": False}, {"max_evals": 7}, {"max_iter": 2}, {"period": 2}):
            a, b = _both(monkeypatch, P, z, **kwargs)
            _assert_same(a, b)
            seen.add(a.status.name)
    assert kinds <= seen


def test_a_guess_outside_the_region_is_refused_on_both_paths(monkeypatch):
    P, z0 = _scene_map("kneed_hsu.toml")
    past_fall = z0.copy()
    past_fall[0] = -1.5  # the stance leg beyond 70 degrees from the slope normal
    fast = z0.copy()
    fast[1:] *= 40.0  # rates far beyond any gait's
    for z, words in [(past_fall, "fall angle"), (fast, "kinetic energy")]:
        a, b = _both(monkeypatch, P, z)
        assert a.status == Status.OUTSIDE_WALKING_REGION
        assert words in a.message
        _assert_same(a, b)


def test_a_search_at_another_parameter_value(monkeypatch):
    P, z0 = _scene_map("compass_goswami.toml")
    slope = P.parameter_value * 1.05
    a, b = _both(monkeypatch, P, z0, parameter=slope)
    assert a.success
    _assert_same(a, b)
    assert a.parameters[P.parameter_name] == slope


def test_a_subclass_or_a_spy_on_the_map_is_searched_through_callbacks(monkeypatch):
    P, z0 = _scene_map("compass_goswami.toml")

    class Counted(StrideMap):
        calls = 0

        def __call__(self, z, **kwargs):
            type(self).calls += 1
            return super().__call__(z, **kwargs)

    counted = Counted(P.model, P.params, rtol=P.rtol, atol=P.atol, t_max=P.t_max)
    assert counted._compiled_search() is None
    assert find_fixed_point(counted, z0).success
    assert Counted.calls > 0

    seen = []
    call = StrideMap.__call__

    def spy(self, z, **kwargs):
        seen.append(z)
        return call(self, z, **kwargs)

    monkeypatch.setattr(StrideMap, "__call__", spy)
    assert P._compiled_search() is None
    assert find_fixed_point(P, z0).success
    assert seen


@pytest.mark.parametrize(
    "name, z, status",
    [
        # guesses 105 and 49 of the 200 within +-50 % of the compass gait (numpy seed 1), 82
        # of the kneed gait's: a Newton step leading out of the walking region, and a
        # residual stalling at a positive value
        (
            "compass_goswami.toml",
            [0.3164151067628023, -1.2543459016842904, -0.4092292603909765],
            "DIVERGED",
        ),
        (
            "compass_goswami.toml",
            [0.27744080194216353, -1.1198096746094885, -0.2448089449334543],
            "NO_GAIT_NEAR_GUESS",
        ),
        (
            "kneed_hsu.toml",
            [0.14833625116026924, -0.6628351593526126, -0.07162461674751226],
            "NO_GAIT_NEAR_GUESS",
        ),
    ],
)
def test_searches_that_find_no_gait_end_as_through_callbacks(name, z, status, monkeypatch):
    P, _ = _scene_map(name)
    a, b = _both(monkeypatch, P, np.array(z))
    assert a.status.name == status
    _assert_same(a, b)


def test_searches_on_two_threads_end_as_serial_ones():
    # the compiled search releases the GIL: two threads searching at once on one map get
    # the results one thread gets
    import threading

    P, z0 = _scene_map("kneed_hsu.toml")
    rng = np.random.default_rng(7)
    guesses = [z0 * (1 + rng.uniform(-0.2, 0.2, z0.shape)) for _ in range(24)]
    serial = [find_fixed_point(P, z) for z in guesses]
    results = [None] * len(guesses)

    def work(k0):
        for k in range(k0, len(guesses), 2):
            results[k] = find_fixed_point(P, guesses[k])

    threads = [threading.Thread(target=work, args=(k,)) for k in (0, 1)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(results, serial, strict=True):
        assert a.status == b.status and a.n_iter == b.n_iter
        assert np.array_equal(a.section, b.section)
        assert np.array_equal(a.multipliers, b.multipliers, equal_nan=True)
    assert sum(r.success for r in serial) >= 12
