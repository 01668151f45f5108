"""The interior guard samples skipped in a step where every guard stays far from zero
(``HybridSystem.autonomous_guards``; walker.simulation.integrate, section Events).

Skipping must not change a result: a step with a sign change or a guard near zero keeps its
samples, so the bracket each event is located in is the same.  These tests run every
shipped walker scene with the built-in system (screened) and with the same system declared
``autonomous_guards=False`` (every step sampled) and compare the runs bit for bit.  A guard
that reads ``t`` is why screening is opt-in: the last tests show a time-dependent dip that
only the interior samples see.
"""

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from _toy_systems import njit, toy_system

from walker import load_scene
from walker.simulation.integrate import hybrid_solve
from walker.status import EVENT_TERMINAL, Status

GAITS = Path(__file__).resolve().parents[1] / "gaits"
WALKER_SCENES = sorted(
    path.name for path in GAITS.glob("*.toml") if load_scene(path).walker_model.is_walker
)


def _run(system, scene, method, jacobian):
    model = scene.walker_model
    p = np.asarray(scene.params.as_array(), dtype=np.float64)
    x0 = np.asarray(scene.state, dtype=np.float64)
    kw = {"first_step": 2e-3} if method == "RK4" else {"rtol": 1e-10, "atol": 1e-12}
    return hybrid_solve(
        system,
        x0,
        p,
        phase0=model.start_phase(x0, scene.params),
        t_max=6.0,
        n_strides=3,
        method=method,
        output="events",
        jacobian=jacobian,
        **kw,
    )


@pytest.mark.parametrize("method", ["DOP853", "RK45", "RK4"])
@pytest.mark.parametrize("name", WALKER_SCENES)
def test_screening_changes_no_result(name, method):
    scene = load_scene(GAITS / name)
    p = scene.params.as_array()
    screened = scene.walker_model.system_for(p)
    assert screened.autonomous_guards
    sampled = dataclasses.replace(screened, autonomous_guards=False)
    jacobian = screened.jac is not None
    a = _run(screened, scene, method, jacobian)
    b = _run(sampled, scene, method, jacobian)
    assert a.status == b.status
    assert (a.t, a.n_steps, a.n_rejected, a.n_events) == (b.t, b.n_steps, b.n_rejected, b.n_events)
    np.testing.assert_array_equal(a.x, b.x)
    np.testing.assert_array_equal(a.events.t, b.events.t)
    np.testing.assert_array_equal(a.events.x_pre, b.events.x_pre)
    np.testing.assert_array_equal(a.events.x_post, b.events.x_post)
    if jacobian:
        np.testing.assert_array_equal(a.jac, b.jac)
    # DOP853 pays three extra right-hand sides for a step's dense output; a screened step
    # does not build it
    if method == "DOP853" and a.n_steps > 3 * max(a.n_events, 1):
        assert a.n_rhs < b.n_rhs
    else:
        assert a.n_rhs <= b.n_rhs


# A time-dependent guard over a state that does not move: g(t) = 1 - 1.5 sin^2(pi t) is 1
# with zero slope at every integer t and dips below zero between, first at
# t* = asin(sqrt(2/3)) / pi.  One RK4 step of length 1 sees g = 1 and rate 0 at both ends.


@njit(cache=True)
def _still_rhs(phase, t, x, p, dx):
    dx[0] = 0.0


@njit(cache=True)
def _dip_guards(phase, t, x, p, g):
    s = math.sin(math.pi * t)
    g[0] = 1.0 - 1.5 * s * s


@njit(cache=True)
def _stop_reset(phase, k, t, x, p, x_new, impulse):
    return EVENT_TERMINAL, phase, 0


def _dip_system(autonomous_guards):
    functions = (_still_rhs, _dip_guards, _stop_reset, None)
    return toy_system(
        "timed dip",
        1,
        functions,
        np.array([[-1]]),
        ("still",),
        ("dip",),
        autonomous_guards=autonomous_guards,
    )


def _dip_run(system):
    return hybrid_solve(
        system,
        [0.0],
        [0.0],
        t_max=1.0,
        n_strides=0,
        method="RK4",
        first_step=1.0,
        output="events",
    )


def test_time_dependent_guard_is_sampled_by_default():
    sol = _dip_run(_dip_system(False))
    assert sol.status == Status.COMPLETED  # the reset's status 0
    assert sol.n_events == 0 and sol.events.t.shape == (1,)
    assert sol.events.t[0] == pytest.approx(math.asin(math.sqrt(2.0 / 3.0)) / math.pi, abs=1e-12)


def test_a_wrong_autonomous_declaration_skips_the_samples():
    # The declaration is the caller's promise: for this guard it is false, the step is
    # judged far from zero from its ends alone and the dip is walked through.
    sol = _dip_run(_dip_system(True))
    assert sol.events.t.shape == (0,)


def test_autonomous_guards_must_be_a_bool():
    with pytest.raises(TypeError, match="autonomous_guards"):
        _dip_system(1)
