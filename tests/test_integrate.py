"""Tests of the compiled hybrid integrator (walker.simulation.integrate)."""

import math

import numpy as np
import pytest
from _toy_systems import (
    BALL,
    LIFT,
    ODE,
    RAMP,
    WALKER,
    ball_impact_times,
    ode_exact,
    toy_fields,
    walker_state,
)
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

from walker.simulation.integrate import HybridSystem, _solve, hybrid_solve
from walker.status import Status

BALL_P = np.array([9.81, 0.9, 0.0])
ROT_P = np.array([0.1, 9.81])
# Garcia et al. (1998) stable gait at slope 0.009 (REFERENCES.md §1, "to 1e-10").
GARCIA_SLOPE = 0.009
GARCIA_FIXED = (0.20031090049483, -0.19983247291764)


def _fixed(method, h, phase=1, t_end=2.0):
    x0 = np.array([1.0, 0.5])
    sol = _solve(
        ODE,
        x0,
        ROT_P,
        phase0=phase,
        t0=0.0,
        t_max=t_end,
        n_strides=0,
        method=method,
        rtol=1e-10,
        atol=1e-12,
        first_step=h,
        max_step=np.inf,
        max_steps=10**7,
        output="map",
        sample_times=None,
        jacobian=False,
        n_interior=4,
        fixed_step=True,
    )
    assert sol.status == Status.COMPLETED
    return np.max(np.abs(sol.x - ode_exact(phase, t_end, x0, ROT_P)))


@pytest.mark.parametrize(
    "method, hs, order, tol",
    [
        ("DOP853", [0.3, 0.25, 0.2, 0.16], 8.0, 0.5),
        ("RK45", [0.05, 0.025, 0.0125], 5.0, 0.3),
        ("RK4", [0.1, 0.05, 0.025], 4.0, 0.3),
        ("Euler", [0.004, 0.002, 0.001], 1.0, 0.1),
    ],
)
def test_convergence_order(method, hs, order, tol):
    errs = [_fixed(method, h) for h in hs]
    assert min(errs) > 1e-13  # roundoff does not dominate the fit
    slope = np.polyfit(np.log(hs), np.log(errs), 1)[0]
    assert abs(slope - order) < tol, (slope, errs)


@pytest.mark.parametrize("method", ["DOP853", "RK45"])
@pytest.mark.parametrize("phase", [0, 1])
def test_error_in_tolerance_units_exact(method, phase):
    rtol, atol = 1e-8, 1e-10
    x0 = np.array([1.0, 0.5])
    for t_end in (0.5, 1.0, 2.0):
        sol = hybrid_solve(
            ODE,
            x0,
            ROT_P,
            phase0=phase,
            t_max=t_end,
            n_strides=0,
            method=method,
            rtol=rtol,
            atol=atol,
        )
        assert sol.status == Status.COMPLETED
        exact = ode_exact(phase, t_end, x0, ROT_P)
        err = np.abs(sol.x - exact) / (atol + rtol * np.abs(exact))
        assert err.max() < 5, err.max()


def test_pendulum_against_tight_reference():
    x0 = np.array([2.5, 0.0])
    ref = hybrid_solve(ODE, x0, ROT_P, phase0=2, t_max=2.0, n_strides=0, rtol=1e-13, atol=1e-15)
    rtol, atol = 1e-8, 1e-10
    sol = hybrid_solve(ODE, x0, ROT_P, phase0=2, t_max=2.0, n_strides=0, rtol=rtol, atol=atol)
    err = np.abs(sol.x - ref.x) / (atol + rtol * np.abs(ref.x))
    assert err.max() < 5, err.max()
    # energy conserved far below the tolerance
    energy = lambda x: 0.5 * x[1] ** 2 - ROT_P[1] * math.cos(x[0])  # noqa: E731
    assert_allclose(energy(ref.x), energy(x0), rtol=1e-11, atol=0)


def test_bouncing_ball_impact_times():
    sol = hybrid_solve(BALL, [1.0, 0.0], BALL_P, n_strides=20, output="events")
    assert sol.status == Status.COMPLETED and sol.n_strides == 20 and sol.n_events == 20
    exact = ball_impact_times(1.0, 9.81, 0.9, 20)
    assert_allclose(sol.events.t, exact, rtol=1e-12, atol=0)
    assert sol.t == sol.events.t[-1]
    assert_allclose(sol.x[1], 9.81 * exact[0] * 0.9**20, rtol=1e-12, atol=0)
    assert_allclose(
        sol.events.impulse[:, 0], 1.9 * np.abs(sol.events.x_pre[:, 1]), rtol=1e-14, atol=0
    )


def test_two_roots_in_one_step_both_found_in_order():
    # x' = 1, guard cos(x) decreasing through 0 at pi/2 and 5pi/2, first step [0, 10]
    sol = hybrid_solve(
        RAMP, [0.0, 0.0], np.array([0.0]), n_strides=0, t_max=10.0, first_step=10.0, output="events"
    )
    assert_allclose(sol.events.t, [math.pi / 2, 5 * math.pi / 2], rtol=1e-14, atol=0)
    assert_allclose(sol.x[1], 2.0, rtol=0, atol=0)
    # the first step [0, 10] holds both roots: without interior checks one is missed
    sol0 = hybrid_solve(
        RAMP,
        [0.0, 0.0],
        np.array([0.0]),
        n_strides=0,
        t_max=10.0,
        first_step=10.0,
        n_interior=0,
        output="events",
    )
    assert len(sol0.events) < 2


def test_ignored_first_crossing_then_accepted_second_in_same_step():
    sol = hybrid_solve(
        RAMP, [0.0, 0.0], np.array([1.0]), n_strides=1, t_max=10.0, first_step=10.0, output="full"
    )
    assert sol.status == Status.COMPLETED
    assert sol.n_steps == 1 and sol.n_events == 1
    assert_allclose(sol.t, 5 * math.pi / 2, rtol=1e-14, atol=0)


def test_guard_zero_at_t0_does_not_fire():
    # ball launched upward from the ground: height guard is 0 at t0
    v0 = 3.0
    sol = hybrid_solve(BALL, [0.0, v0], BALL_P, n_strides=1, output="events")
    assert sol.status == Status.COMPLETED
    assert_allclose(sol.events.t[0], 2 * v0 / 9.81, rtol=1e-13, atol=0)
    # launched downward from the ground: it never arms, falls through, no event
    sol = hybrid_solve(BALL, [0.0, -1.0], BALL_P, n_strides=1, t_max=2.0)
    assert sol.status == Status.NO_EVENT
    # within GUARD_TOL above the ground but moving down into it: armed at once (its rate
    # points toward firing), so the crossing at t = 1e-13 is seen
    sol = hybrid_solve(BALL, [1e-13, -1.0], BALL_P, n_strides=1, t_max=2.0)
    assert sol.status == Status.COMPLETED
    assert_allclose(sol.t, 1e-13, rtol=1e-3, atol=0)
    # just beyond GUARD_TOL: armed, fires at once
    sol = hybrid_solve(BALL, [1e-9, -1.0], BALL_P, n_strides=1, t_max=2.0)
    assert sol.status == Status.COMPLETED
    assert_allclose(sol.t, 1e-9, rtol=1e-6, atol=0)


def test_statuses():
    assert hybrid_solve(BALL, [1.0, 0.0], BALL_P, t_max=0.2).status == Status.NO_EVENT
    assert (
        hybrid_solve(BALL, [1.0, 0.0], BALL_P, n_strides=50, max_steps=30).status
        == Status.MAX_STEPS
    )
    # blow-up x' = x^2 (x(t) = 1/(1-t)): fixed steps overflow, adaptive steps underflow
    sol = hybrid_solve(
        ODE, [1.0, 0.0], ROT_P, phase0=3, n_strides=0, t_max=2.0, method="RK4", first_step=0.1
    )
    assert sol.status == Status.NONFINITE
    sol = hybrid_solve(ODE, [1.0, 0.0], ROT_P, phase0=3, n_strides=0, t_max=2.0)
    assert sol.status == Status.STEP_UNDERFLOW and sol.t < 1.0 + 1e-8
    # terminal reset status passed through: impact slower than v_stop
    p = np.array([9.81, 0.5, 1.0])
    sol = hybrid_solve(BALL, [1.0, 0.0], p, n_strides=100, output="events")
    assert sol.status == Status.FELL_FORWARD and not sol.success
    assert sol.x[1] < 0 and abs(sol.x[1]) < 1.0  # the pre-event state
    assert len(sol.events) == sol.n_events + 1


def test_t_max_exactly_at_stride_end_completes():
    # drop from 0.5 g T^2 with T = 1: impact at t = 1 = t_max -> COMPLETED (documented)
    h0 = 0.5 * 9.81
    sol = hybrid_solve(BALL, [h0, 0.0], BALL_P, n_strides=1, t_max=1.0)
    assert sol.status == Status.COMPLETED
    assert_allclose(sol.t, 1.0, rtol=0, atol=2e-15)
    assert hybrid_solve(BALL, [h0, 0.0], BALL_P, n_strides=1, t_max=0.999).status == (
        Status.NO_EVENT
    )


def _fd_jac(system, x0, p, eps, **kw):
    """Richardson-extrapolated central differences of the final state and time."""
    n = len(x0)

    def central(h):
        J = np.empty((n, n))
        dt = np.empty(n)
        for j in range(n):
            xp = np.array(x0, float)
            xm = np.array(x0, float)
            xp[j] += h
            xm[j] -= h
            sp = hybrid_solve(system, xp, p, **kw)
            sm = hybrid_solve(system, xm, p, **kw)
            J[:, j] = (sp.x - sm.x) / (2 * h)
            dt[j] = (sp.t - sm.t) / (2 * h)
        return J, dt

    J1, dt1 = central(eps)
    J2, dt2 = central(eps / 2)
    return (4 * J2 - J1) / 3, (4 * dt2 - dt1) / 3


def test_variational_jacobian_ball_multi_event():
    kw = dict(n_strides=3, rtol=1e-12, atol=1e-14)
    x0 = np.array([1.0, 0.3])
    sol = hybrid_solve(BALL, x0, BALL_P, jacobian=True, **kw)
    J, dt = _fd_jac(BALL, x0, BALL_P, 1e-4, **kw)
    assert_allclose(sol.jac, J, rtol=0, atol=1e-7)
    assert_allclose(sol.dt_dx0, dt, rtol=0, atol=1e-7)


def test_variational_jacobian_walker_two_strides():
    kw = dict(n_strides=2, rtol=1e-12, atol=1e-14)
    x0 = walker_state(*GARCIA_FIXED) + np.array([0.001, -0.002, 0.001, 0.0])
    p = np.array([GARCIA_SLOPE])
    sol = hybrid_solve(WALKER, x0, p, jacobian=True, **kw)
    assert sol.status == Status.COMPLETED
    J, dt = _fd_jac(WALKER, x0, p, 1e-4, **kw)
    # relative 1e-7: the finite differences carry the 1e-12 integration error / 1e-4 step
    assert_allclose(sol.jac, J, rtol=1e-7, atol=1e-8)
    assert_allclose(sol.dt_dx0, dt, rtol=1e-7, atol=1e-8)


def test_walker_fixed_point_and_scipy_agreement():
    from scipy.integrate import solve_ivp

    gam = GARCIA_SLOPE
    x0 = walker_state(*GARCIA_FIXED)
    sol = hybrid_solve(
        WALKER, x0, np.array([gam]), n_strides=1, rtol=1e-12, atol=1e-12, output="events"
    )
    assert sol.status == Status.COMPLETED

    def f(t, x):
        s = math.sin(x[0] - gam)
        return [x[2], x[3], s, s + math.sin(x[1]) * (x[2] ** 2 - math.cos(x[0] - gam))]

    def strike(t, x):
        return x[1] - 2 * x[0]

    ref = solve_ivp(f, (0, 5), x0, method="DOP853", rtol=1e-12, atol=1e-12, events=strike)
    heel = np.flatnonzero(ref.y_events[0][:, 0] < 0)[0]  # skip the mid-swing scuff
    assert_allclose(sol.events.t[0], ref.t_events[0][heel], rtol=1e-10, atol=0)
    assert_allclose(sol.events.x_pre[0], ref.y_events[0][heel], rtol=0, atol=1e-10)


@settings(max_examples=25, deadline=None)
@given(
    theta=st.floats(-1.5, 1.5),
    theta_dot=st.floats(-3.0, 3.0),
    slope=st.floats(-0.1, 0.1),
)
def test_random_walker_states_always_return_a_status(theta, theta_dot, slope):
    sol = hybrid_solve(
        WALKER,
        walker_state(theta, theta_dot),
        np.array([slope]),
        n_strides=3,
        t_max=20.0,
        max_steps=20_000,
    )
    assert isinstance(sol.status, Status)
    assert np.all(np.isfinite(sol.x)) or sol.status == Status.NONFINITE


def test_samples_equal_dense_output_and_full_record_monotone():
    ts = np.array([0.0, 0.1, 0.45, 0.7, 1.3])
    sol = hybrid_solve(
        WALKER,
        walker_state(*GARCIA_FIXED),
        np.array([GARCIA_SLOPE]),
        n_strides=1,
        output="samples",
        sample_times=ts,
    )
    assert len(sol.samples) == 5
    for t_s, x_s in zip(ts[1:], sol.samples.x[1:], strict=True):
        stop = hybrid_solve(
            WALKER, walker_state(*GARCIA_FIXED), np.array([GARCIA_SLOPE]), n_strides=0, t_max=t_s
        )
        assert_allclose(x_s, stop.x, rtol=0, atol=1e-9)
    assert_allclose(sol.samples.x[0], walker_state(*GARCIA_FIXED), rtol=0, atol=1e-15)
    full = hybrid_solve(BALL, [1.0, 0.0], BALL_P, n_strides=3, output="full")
    assert np.all(np.diff(full.record.t) >= 0)
    assert full.record.t[-1] == full.t and len(full.record) > full.n_steps


def test_sample_at_event_time_takes_pre_event_state():
    first = hybrid_solve(BALL, [1.0, 0.0], BALL_P, n_strides=1)
    sol = hybrid_solve(
        BALL, [1.0, 0.0], BALL_P, n_strides=2, output="samples", sample_times=[first.t]
    )
    assert sol.samples.x[0, 1] < 0 and sol.samples.phase[0] == 0


@pytest.mark.parametrize(
    "kwargs, exc, match",
    [
        (dict(x0=[1.0]), ValueError, "`x0` must be 1-D of length n_x = 2"),
        (dict(x0=[np.nan, 0.0]), ValueError, "`x0` must be finite"),
        (dict(p=[np.inf, 0.9, 0.0]), ValueError, "parameters `p` must be finite"),
        (dict(rtol=-1.0), ValueError, "`rtol` must be positive"),
        (dict(rtol=1e-16), ValueError, r"`rtol` must be >= 100 \* eps"),
        (dict(atol=0.0), ValueError, "`atol` must be positive"),
        (dict(t_max=0.0), ValueError, "`t_max` must be greater than `t0`"),
        (
            dict(method="rk45"),
            ValueError,
            r"`method` must be one of DOP853, RK45, RK4, Euler, got 'rk45'$",
        ),
        (dict(n_strides=-1), ValueError, "`n_strides` must be >= 0"),
        (dict(n_strides=1.5), TypeError, "`n_strides` must be an int"),
        (dict(output="all"), ValueError, "`output` must be one of"),
        (dict(output="samples", sample_times=[0.2, 0.1]), ValueError, "must be sorted"),
        (dict(output="samples", sample_times=[np.nan]), ValueError, "must be finite"),
        (dict(method="RK4"), ValueError, "`first_step` must be given"),
        (dict(method="Euler", first_step=-0.1), ValueError, "`first_step` must be positive"),
        (dict(jacobian=True, system=RAMP, x0=[0.0, 0.0]), ValueError, "system.jac is None"),
        (dict(system="ball"), TypeError, "`system` must be a HybridSystem"),
        (dict(phase0=1), ValueError, "`phase0` must be < n_phases"),
    ],
)
def test_validation_messages(kwargs, exc, match):
    args = dict(system=BALL, x0=[1.0, 0.0], p=BALL_P)
    args.update(kwargs)
    with pytest.raises(exc, match=match):
        hybrid_solve(args.pop("system"), args.pop("x0"), args.pop("p"), **args)


def test_system_validation():
    functions = (BALL.rhs, BALL.guards, BALL.reset, None)
    base = toy_fields("b", 2, functions, np.array([[-1]]), ("a",), ("g",))
    with pytest.raises(ValueError, match=r"`directions` must have shape"):
        HybridSystem(**{**base, "directions": np.array([-1])})
    with pytest.raises(ValueError, match=r"`directions` values must be -1, 0 or \+1"):
        HybridSystem(**{**base, "directions": np.array([[2]])})
    with pytest.raises(ValueError, match="`guard_names` must have n_guards = 1"):
        HybridSystem(**{**base, "guard_names": ()})


@pytest.mark.parametrize("e", [0.99, 0.9, 0.5, 0.1, 0.03])
def test_chattering_ends_with_its_own_status(e):
    # A ball bouncing with restitution e makes infinitely many impacts before the Zeno time
    # t1 (1 + 2e/(1 - e)) (t1 the first impact; the intervals shrink by e per impact).  The
    # run must stop there with CHATTERING, on the ground, not step through the accumulation
    # (before this status the ball sank through the floor and the run ended NO_EVENT).
    gravity = 9.81
    sol = hybrid_solve(
        BALL,
        [1.0, 0.0],
        np.array([gravity, e, 0.0]),
        n_strides=10**6,
        t_max=1e3,
        output="events",
    )
    t1 = np.sqrt(2.0 / gravity)
    t_zeno = t1 * (1.0 + 2.0 * e / (1.0 - e))
    assert sol.status == Status.CHATTERING and not sol.success
    assert t1 < sol.t < t_zeno
    assert abs(sol.x[0]) < 1e-15 and sol.x[1] >= 0.0
    assert_allclose(sol.events.t, ball_impact_times(1.0, gravity, e, sol.n_events), rtol=1e-9)


def test_chattering_test_leaves_gaits_alone():
    # a bouncing ball with constant intervals (e = 1) never forms a shrinking chain (the
    # walkers' gaits, with alternating heel-strike / knee-lock intervals, run in every scene
    # test)
    sol = hybrid_solve(BALL, [1.0, 0.0], BALL_P * [1, 1 / 0.9, 1], n_strides=200, t_max=1e3)
    assert sol.status == Status.COMPLETED and sol.n_events == 200


def test_events_that_do_not_advance_time_end_as_chattering():
    # x' = -1 from x0 = 1 reaches its guard x = 0 at t = 1; each reset lifts it by 1e-300,
    # so every later event comes 1e-300 s after the one before, far below the spacing of
    # t = 1 (2.2e-16): the absolute time never advances.  The run must stop at t = 1 as
    # chattering after a few events, not loop through its step budget (MAX_STEPS, before).
    sol = hybrid_solve(
        LIFT, [1.0], np.array([1e-300]), n_strides=10**6, t_max=10.0, output="events"
    )
    assert sol.status == Status.CHATTERING and not sol.success
    assert_allclose(sol.t, 1.0, rtol=1e-12, atol=0.0)  # where the first event was located
    assert 2 <= sol.n_events <= 64
    assert_allclose(sol.events.t, np.ones(sol.n_events), rtol=1e-12, atol=0.0)


def test_events_that_advance_time_little_by_little_are_not_chattering():
    # the same system lifted by 1e-6 (4.5e9 ulps of t = 1): events every 1e-6 s at the exact
    # times 1 + k 1e-6, none a shrinking chain and none at one instant
    n = 200
    sol = hybrid_solve(LIFT, [1.0], np.array([1e-6]), n_strides=n, t_max=10.0, output="events")
    assert sol.status == Status.COMPLETED and sol.n_events == n
    assert_allclose(sol.events.t, 1.0 + 1e-6 * np.arange(n), rtol=1e-12, atol=0.0)


# --- Seeded variational equations (issue 12): jacobian_seed S propagates (d x / d x0) S -----


def _seeded(system, x0, p, seed, **kw):
    args = dict(
        phase0=0,
        t0=0.0,
        t_max=100.0,
        n_strides=2,
        method="DOP853",
        rtol=1e-10,
        atol=1e-12,
        first_step=None,
        max_step=np.inf,
        max_steps=1_000_000,
        output="events",
        sample_times=None,
        jacobian=True,
        n_interior=4,
        fixed_step=False,
    )
    args.update(kw)
    return _solve(system, x0, p, jacobian_seed=seed, **args)


def test_identity_seed_is_the_run_without_a_seed_bit_for_bit():
    x0 = walker_state(*GARCIA_FIXED) + np.array([0.001, -0.002, 0.001, 0.0])
    p = np.array([GARCIA_SLOPE])
    plain = _seeded(WALKER, x0, p, None)
    eye = _seeded(WALKER, x0, p, np.eye(4))
    assert plain.status == eye.status == Status.COMPLETED
    np.testing.assert_array_equal(eye.jac, plain.jac)
    np.testing.assert_array_equal(eye.dt_dx0, plain.dt_dx0)
    np.testing.assert_array_equal(eye.x, plain.x)
    assert (eye.t, eye.n_steps, eye.n_rhs) == (plain.t, plain.n_steps, plain.n_rhs)


@pytest.mark.parametrize("columns", [1, 2, 3])
def test_seed_columns_are_the_full_sensitivities_times_the_seed(columns):
    """On fixed steps (RK4) the seeded and the full run take the same steps and locate the
    same events, so jac and dt_dx0 are the full ones times the seed up to rounding; with
    adaptive steps (the control measures the columns carried) to the integration error."""
    x0 = walker_state(*GARCIA_FIXED) + np.array([0.001, -0.002, 0.001, 0.0])
    p = np.array([GARCIA_SLOPE])
    seed = np.random.default_rng(columns).normal(size=(4, columns))
    for kw, tol in ((dict(method="RK4", first_step=1e-2), 1e-13), (dict(), 1e-7)):
        full = _seeded(WALKER, x0, p, None, **kw)
        part = _seeded(WALKER, x0, p, seed, **kw)
        assert part.jac.shape == (4, columns) and part.dt_dx0.shape == (columns,)
        scale = np.max(np.abs(full.jac @ seed))
        assert np.max(np.abs(part.jac - full.jac @ seed)) <= tol * scale
        assert_allclose(part.dt_dx0, full.dt_dx0 @ seed, rtol=0, atol=tol * scale)
        if "method" in kw:
            np.testing.assert_array_equal(part.x, full.x)
            np.testing.assert_array_equal(part.events.t, full.events.t)


@pytest.mark.parametrize(
    ("seed", "kw", "match"),
    [
        (np.ones((3, 2)), {}, r"`jacobian_seed` must have shape \(n_x = 4, m\)"),
        (np.ones(4), {}, r"`jacobian_seed` must have shape"),
        (np.ones((4, 5)), {}, r"1 <= m <= n_x = 4"),
        (np.ones((4, 0)), {}, r"1 <= m <= n_x = 4"),
        (np.full((4, 2), np.nan), {}, "`jacobian_seed` must be finite"),
        (np.ones((4, 2)), dict(jacobian=False), "only used with `jacobian=True`"),
    ],
)
def test_seed_validation(seed, kw, match):
    x0 = walker_state(*GARCIA_FIXED)
    with pytest.raises(ValueError, match=match):
        _seeded(WALKER, x0, np.array([GARCIA_SLOPE]), seed, **kw)
