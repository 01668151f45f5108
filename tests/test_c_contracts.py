"""The promises of walker/_core/wk_system.h that the compiled core keeps (issue 33, item 4).

* A guard is a function of ``t`` and ``x``: the tangency search inside a step (a guard that
  dips past zero and back between two step ends) evaluates it at each trial point's own
  time.  Before, it used the step's start time for every trial point, so a dip that only
  the time-dependence creates was walked through.
* ``ctx`` is handed unchanged to every call: the section's energy test (and its lift and
  start phase) received NULL before.
"""

from __future__ import annotations

import ctypes
import math
from pathlib import Path

import numpy as np
import pytest
from _toy_systems import njit, toy_system  # numba's njit, else ctypes callbacks
from scipy.optimize import brentq

from walker import _hybrid, load_scene
from walker.simulation._section import section_args
from walker.simulation.integrate import hybrid_solve
from walker.simulation.stride import StrideMap
from walker.status import EVENT_TERMINAL, Status

GAITS = Path(__file__).resolve().parents[1] / "gaits"

# x' = 1 from x = 0, one RK4 step of length 1 (exact for this field), no interior samples.
# g(t, x) = 0.2 + (x - 1/2)^2 - 0.5 sin^2(pi t): 0.45 with rate -1 along the flow at the
# step's start, 0.45 with rate +1 at its end (sin^2 has zero slope at integers), so the
# tangency check searches for an extremum inside.  Along the trajectory x = t it falls to
# -0.3 at t = 1/2; at the start time t = 0 the same search would see 0.2 + (x - 1/2)^2 > 0.


@njit(cache=True)
def _unit_rhs(phase, t, x, p, dx):
    dx[0] = 1.0


@njit(cache=True)
def _timed_guard(phase, t, x, p, g):
    s = math.sin(math.pi * t)
    g[0] = 0.2 + (x[0] - 0.5) ** 2 - 0.5 * s * s


@njit(cache=True)
def _stop(phase, k, t, x, p, x_new, impulse):
    return EVENT_TERMINAL, phase, 0


def test_a_time_dependent_dip_is_found_at_the_trial_time():
    system = toy_system(
        "timed tangency",
        1,
        (_unit_rhs, _timed_guard, _stop, None),
        np.array([[-1]]),
        ("moving",),
        ("dip",),
        autonomous_guards=False,
    )
    sol = hybrid_solve(
        system,
        [0.0],
        [0.0],
        t_max=1.0,
        n_strides=0,
        method="RK4",
        first_step=1.0,
        output="events",
        n_interior=0,
    )
    # independent: the first root of g(t, t) on (0, 1/2) by Brent's method
    expected = brentq(
        lambda t: 0.2 + (t - 0.5) ** 2 - 0.5 * math.sin(math.pi * t) ** 2,
        0.0,
        0.5,
        xtol=1e-15,
    )
    assert sol.status == Status.COMPLETED  # the terminal reset's status 0
    assert sol.events.t.shape == (1,)
    np.testing.assert_allclose(sol.events.t[0], expected, rtol=0, atol=1e-9)


# ---------------------------------------------------------------- ctx reaches the energy

_STATE_FN = ctypes.CFUNCTYPE(
    None,
    ctypes.POINTER(ctypes.c_double),
    ctypes.POINTER(ctypes.c_double),
    ctypes.POINTER(ctypes.c_double),
    ctypes.c_void_p,
)
_SEEN: list = []


@_STATE_FN
def _energy_from_ctx(x, p, out, ctx):
    """A user's energy function: its kinetic energy is the double ``ctx`` points to."""
    _SEEN.append(ctx)
    out[0] = ctypes.cast(ctx, ctypes.POINTER(ctypes.c_double))[0] if ctx else 0.0
    out[1] = 0.0


def test_ctx_reaches_the_sections_energy_test():
    scene = load_scene(GAITS / "compass_goswami.toml")
    P = StrideMap.from_scene(scene)
    z0 = P.project(scene.state)
    run, _, _ = P._prepared(1)
    args = section_args(P.model, P.t_max, P.__dict__["_run"], run)
    kinetic = (ctypes.c_double * 1)()
    args["ctx"] = ctypes.addressof(kinetic)  # the compass functions ignore it
    args["energy"] = ctypes.cast(_energy_from_ctx, ctypes.c_void_p).value
    args["kinetic_limit"] = 10.0  # [J]
    prepared = _hybrid.PreparedMap(**args)
    z = np.ascontiguousarray(z0, dtype=np.float64)

    _SEEN.clear()
    kinetic[0] = 1e6  # far above the limit: the start is refused without a run
    status, t, *_ = prepared.map(z, 1, False)
    assert _SEEN == [ctypes.addressof(kinetic)]
    assert status == Status.OUTSIDE_WALKING_REGION and t == 0.0

    kinetic[0] = 0.0  # below it: the stride runs, to about the gait's step time (the
    # scene's start is the gait's state to four digits)
    status, t, *_ = prepared.map(z, 1, False)
    assert status == Status.COMPLETED
    assert _SEEN == [ctypes.addressof(kinetic)] * 2
    reference = scene.reference["step_time"]
    np.testing.assert_allclose(t, reference, rtol=1e-3, atol=0)


@pytest.mark.parametrize("name", ["energy", "points"])
def test_call_state_fn_hands_ctx_on(name):
    """The binding's own call of a state function passes its ``ctx`` argument (the compiled
    models ignore it; the call must not fail with one)."""
    entry = _hybrid.models()["kneed"]
    scene = load_scene(GAITS / "kneed_hsu.toml")
    x = np.ascontiguousarray(scene.state, dtype=np.float64)
    p = scene.params.as_array()
    dummy = (ctypes.c_double * 1)()
    assert _hybrid.call_state_fn(entry[name], x, p, 1, ctypes.addressof(dummy)) == (
        _hybrid.call_state_fn(entry[name], x, p, 1)
    )
