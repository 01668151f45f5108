"""Basins and parameter loops on a :class:`walker.SystemMap`, checked against closed forms.

The system is the kicked bouncing ball of docs/own_system.md, written here as ``ctypes``
callbacks (no numba): height ``h``, upward velocity ``v``, ``h' = v``, ``v' = -g``; at
``h = 0`` falling, ``v+ = -e v- + k`` ends a stride.  The section is the full state
``(h, v)`` at a bounce, so a stride from ``(h, v)`` lands at ``(0, v1)`` with
``v1 = e sqrt(v^2 + 2 g h) + k`` when the ball reaches the ground from above, and then
``v_n - v* = e^(n - 1) (v1 - v*)`` with ``v* = k / (1 - e)``.  Hence the basin of the fixed
point ``(0, v*)`` in closed form: every start above the ground (``h > 0``), and a start below
it that rises through it (``v > 0`` and ``v^2 + 2 g h > 0``); every other start never comes
down through ``h = 0`` (``Status.NO_EVENT``).  The number of strides to come within ``tol``
follows from the geometric decay.
"""

import ctypes
import math

import numpy as np
import pytest

from walker import EVENT_STRIDE, HybridSystem, Status, SystemMap, find_fixed_point
from walker.analysis.basin import basin_map
from walker.results import BASIN_CONVERGED, BASIN_UNDECIDED

G, E, KICK = 9.81, 0.8, 1.0
V_STAR = KICK / (1 - E)

_dp = ctypes.POINTER(ctypes.c_double)
_i64 = ctypes.c_int64
_VECTOR = ctypes.CFUNCTYPE(None, _i64, ctypes.c_double, _dp, _dp, _dp, ctypes.c_void_p)
_RESET = ctypes.CFUNCTYPE(
    None, _i64, _i64, ctypes.c_double, _dp, _dp, _dp, _dp, ctypes.POINTER(_i64), ctypes.c_void_p
)


@_VECTOR
def _rhs(phase, t, x, p, dx, ctx):
    dx[0] = x[1]
    dx[1] = -p[0]


@_VECTOR
def _jac(phase, t, x, p, J, ctx):
    J[0], J[1], J[2], J[3] = 0.0, 1.0, 0.0, 0.0


@_VECTOR
def _guards(phase, t, x, p, g, ctx):
    g[0] = x[0]


@_RESET
def _reset(phase, k, t, x, p, x_new, impulse, out, ctx):
    x_new[0] = 0.0
    x_new[1] = -p[1] * x[1] + p[2]
    impulse[0] = x_new[1] - x[1]
    out[0], out[1], out[2] = EVENT_STRIDE, 0, 0


BALL = HybridSystem(
    name="kicked_ball_ctypes",
    n_x=2,
    n_phases=1,
    n_guards=1,
    n_impulse=1,
    rhs=_rhs,
    guards=_guards,
    reset=_reset,
    jac=_jac,
    directions=np.array([[-1]]),
    phase_names=("flight",),
    guard_names=("bounce",),
    n_params=3,
)


def _map(**kw):
    """The section map on the full state (h, v) at a bounce."""
    return SystemMap(
        BALL,
        params=[G, E, KICK],
        to_state=lambda z, p: np.array(z, dtype=float),
        to_section=[0, 1],
        section_names=("h", "v"),
        lift_jacobian=lambda z, p: np.eye(2),
        parameter_index=2,
        parameter_name="kick",
        t_max=5.0,
        **kw,
    )


def _expected(h, v, tol, n_strides):
    """Closed-form outcome and stride count of a start (h, v), and whether it lies too close
    to a boundary of the rule (apex at the ground, a stride count at a rounding edge) for
    an integrator's 1e-10 to decide."""
    reach = v * v + 2 * G * h
    if h > 0 or (v > 0 and reach > 0):
        v1 = E * math.sqrt(reach) + KICK
        d = abs(v1 - V_STAR)
        if d <= tol:
            n, edge = 1, abs(d / tol - 1) < 1e-3
        else:
            exact = 1 + math.log(tol / d) / math.log(E)  # e^(n-1) d <= tol
            n, edge = math.ceil(exact), abs(exact - round(exact)) < 1e-2
        if n > n_strides:
            return BASIN_UNDECIDED, n_strides, edge
        return BASIN_CONVERGED, n, edge or (h < 0 and reach < 0.1)
    return int(Status.NO_EVENT), 0, h < 0 and abs(reach) < 0.1


def test_ball_fixed_point_on_the_full_state_section():
    """Fixed point (0, v*); Jacobian [[0, 0], [e g / v*, e]], so multipliers e and 0."""
    fp = find_fixed_point(_map(), np.array([0.5, 3.0]))
    assert fp.success, fp.message
    np.testing.assert_allclose(fp.section, [0.0, V_STAR], rtol=0, atol=1e-9)
    mult = np.sort(np.abs(fp.multipliers))
    np.testing.assert_allclose(mult, [0.0, E], rtol=0, atol=1e-8)


@pytest.mark.parametrize("executor", ["serial", None])
def test_basin_of_a_system_map_is_the_closed_form(executor):
    """basin_map on a SystemMap (the Python loop: a SystemMap has no compiled batch), on
    threads and serially: every grid point's outcome and stride count as the closed form."""
    P = _map()
    fp = find_fixed_point(P, np.array([0.0, 4.0]))
    assert fp.success, fp.message
    tol, n_strides = 1e-4, 45
    jobs = 2 if executor is None else None
    b = basin_map(
        P,
        fp,
        ranges=((-1.0, 1.0), (-4.0, 4.0)),
        n=(12, 10),
        n_strides=n_strides,
        tol=tol,
        executor=executor,
        jobs=jobs,
        progress=False,
    )
    assert b.axis_names == ("h", "v")
    checked = 0
    kinds = set()
    for iy, v in enumerate(b.y):
        for ix, h in enumerate(b.x):
            outcome, strides, edge = _expected(h, v, tol, n_strides)
            if edge:
                continue
            checked += 1
            kinds.add(outcome)
            assert b.outcome[iy, ix] == outcome, (h, v, b.outcome[iy, ix], outcome)
            assert b.strides[iy, ix] == strides, (h, v, b.strides[iy, ix], strides)
    # the grid meets every kind of start: converged, undecided (slow decay), never lands
    assert checked > 100
    assert kinds == {BASIN_CONVERGED, BASIN_UNDECIDED, int(Status.NO_EVENT)}, kinds


def test_parameter_loop_on_a_system_map():
    """A sweep of the kick on a SystemMap by its parameter: with_parameter and
    find_fixed_point at each value give v* = k / (1 - e) and the stride time 2 v* / g."""
    P = _map()
    z = np.array([0.0, 4.0])
    for kick in np.linspace(0.5, 2.0, 4):
        fp = find_fixed_point(P.with_parameter(kick), z)
        assert fp.success, fp.message
        v_star = kick / (1 - E)
        np.testing.assert_allclose(fp.section, [0.0, v_star], rtol=0, atol=1e-9)
        np.testing.assert_allclose(fp.step_time, 2 * v_star / G, rtol=1e-10, atol=0)
        z = fp.section


def test_basin_with_the_automatic_ball_on_a_system_map():
    """converge_radius="auto" on a SystemMap (the contraction ball from its Jacobian): the
    same outcomes as the closed form, each in no more strides than the tolerance needs."""
    P = _map()
    fp = find_fixed_point(P, np.array([0.0, 4.0]))
    tol, n_strides = 1e-4, 60
    b = basin_map(
        P,
        fp,
        ranges=((-1.0, 1.0), (-4.0, 4.0)),
        n=(8, 6),
        n_strides=n_strides,
        tol=tol,
        converge_radius="auto",
        executor="serial",
        progress=False,
    )
    assert b.classification["converge_radius"] > 0
    for iy, v in enumerate(b.y):
        for ix, h in enumerate(b.x):
            outcome, strides, edge = _expected(h, v, tol, n_strides)
            if edge:
                continue
            assert b.outcome[iy, ix] == outcome, (h, v)
            assert b.strides[iy, ix] <= strides, (h, v)


def test_the_grid_sweep_names_what_it_takes():
    """walker.analysis.sweep.sweep varies a walker's named parameters (StrideMap.with_params): a
    SystemMap is refused before any work with a TypeError naming the argument (its sweep is
    the loop above, or continue_branch)."""
    from walker.analysis.sweep import sweep

    with pytest.raises(TypeError, match=r"`stride_map` must be a walker.StrideMap"):
        sweep(_map(), {"kick": [0.5, 1.0]}, z0=np.array([0.0, 4.0]), progress=False)
