"""The integrator's extension point: model functions given directly as C functions.

:class:`walker.simulation.integrate.HybridSystem` accepts, besides numba ``@njit`` functions of the
array form, C functions with the signatures of ``walker/_core/wk_system.h``: numba ``cfunc``
objects, ctypes function pointers and plain int addresses.  The systems here are written
entirely in this file.
"""

import ctypes
import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
from _toy_systems import toy_system

from walker import _hybrid, load_scene
from walker.models import get_model
from walker.simulation.hybrid_system import _compiled
from walker.simulation.integrate import hybrid_solve
from walker.status import (
    EVENT_CONTINUE,
    EVENT_STRIDE,
    EVENT_TERMINAL,
    METHOD_DOP853,
    OUTPUT_FULL,
    Status,
)

# HybridSystem's numba bridge (a user's own @njit or cfunc system): numba is the optional
# extra ``numba``, so this module is skipped without it.
numba = pytest.importorskip("numba")
carray, cfunc, types = numba.carray, numba.cfunc, numba.types

# ---------------------------------------------------------------------------------------------
# Bouncing ball as numba cfuncs: x = (height, velocity), p = (gravity, restitution).
# ---------------------------------------------------------------------------------------------

_F64P = types.CPointer(types.float64)
_VEC_SIG = types.void(types.int64, types.float64, _F64P, _F64P, _F64P, types.voidptr)
_RESET_SIG = types.void(
    types.int64,
    types.int64,
    types.float64,
    _F64P,
    _F64P,
    _F64P,
    _F64P,
    types.CPointer(types.int64),
    types.voidptr,
)


@cfunc(_VEC_SIG, cache=True)
def ball_rhs(phase, t, x, p, dx, ctx):
    dx[0] = x[1]
    dx[1] = -p[0]


@cfunc(_VEC_SIG, cache=True)
def ball_guards(phase, t, x, p, g, ctx):
    g[0] = x[0]


@cfunc(_RESET_SIG, cache=True)
def ball_reset(phase, k, t, x, p, x_new, impulse, out, ctx):
    # phase 0 bounces on; phase 1 counts the bounce as a stride (for the stride Jacobian)
    x_new[1] = -p[1] * x[1]
    impulse[0] = (1.0 + p[1]) * abs(x[1])
    out[0] = EVENT_CONTINUE if phase == 0 else EVENT_STRIDE
    out[1] = phase
    out[2] = 0


@cfunc(_VEC_SIG, cache=True)
def ball_jac(phase, t, x, p, J_ptr, ctx):
    J = carray(J_ptr, (2, 2))
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0] = 0.0
    J[1, 1] = 0.0


GRAVITY, RESTITUTION = 9.81, 0.8
BALL_P = np.array([GRAVITY, RESTITUTION])


def _ball(**functions):
    fields = dict(rhs=ball_rhs, guards=ball_guards, reset=ball_reset, jac=ball_jac)
    fields.update(functions)
    four = tuple(fields.pop(name) for name in ("rhs", "guards", "reset", "jac"))
    directions, phase_names = np.array([[-1], [-1]]), ("bouncing", "one bounce")
    return toy_system(
        "cfunc ball", 2, four, directions, phase_names, ("floor",), n_params=2, **fields
    )


BALL = _ball()


def _impact_times(h0, n):
    """Impact times of the ball dropped from rest at height h0."""
    t = math.sqrt(2.0 * h0 / GRAVITY)
    v = GRAVITY * t
    times = [t]
    for _ in range(n - 1):
        v *= RESTITUTION
        t += 2.0 * v / GRAVITY
        times.append(t)
    return np.array(times)


def test_cfunc_ball_impact_times_closed_form():
    h0 = 1.5
    sol = hybrid_solve(BALL, [h0, 0.0], BALL_P, t_max=4.0, n_strides=0, output="events")
    assert sol.status == Status.COMPLETED
    expected = _impact_times(h0, 12)
    expected = expected[expected < 4.0]
    assert len(sol.events) == expected.size >= 5
    np.testing.assert_allclose(sol.events.t, expected, rtol=0, atol=1e-12)
    # speed just before each impact, the reset and the impulse
    v_minus = GRAVITY * math.sqrt(2.0 * h0 / GRAVITY) * RESTITUTION ** np.arange(expected.size)
    np.testing.assert_allclose(sol.events.x_pre[:, 1], -v_minus, rtol=1e-12)
    np.testing.assert_allclose(sol.events.x_post[:, 1], RESTITUTION * v_minus, rtol=1e-12)
    np.testing.assert_allclose(sol.events.impulse[:, 0], (1 + RESTITUTION) * v_minus, rtol=1e-12)
    np.testing.assert_allclose(sol.events.x_pre[:, 0], 0.0, atol=1e-12)
    assert np.all(sol.events.guard == 0)


def test_cfunc_ball_stride_jacobian_closed_form():
    # One bounce as a stride: x_post = (0, e s), s = sqrt(v0^2 + 2 g h0), at T = (v0 + s) / g.
    h0, v0 = 0.7, 1.3
    sol = hybrid_solve(BALL, [h0, v0], BALL_P, phase0=1, t_max=5.0, jacobian=True)
    assert sol.status == Status.COMPLETED and sol.n_strides == 1
    s = math.sqrt(v0 * v0 + 2.0 * GRAVITY * h0)
    assert abs(sol.t - (v0 + s) / GRAVITY) < 1e-12
    np.testing.assert_allclose(sol.x, [0.0, RESTITUTION * s], rtol=0, atol=1e-12)
    jac = np.array([[0.0, 0.0], [RESTITUTION * GRAVITY / s, RESTITUTION * v0 / s]])
    np.testing.assert_allclose(sol.jac, jac, rtol=0, atol=1e-8)
    np.testing.assert_allclose(sol.dt_dx0, [1.0 / s, (1.0 + v0 / s) / GRAVITY], atol=1e-8)


def test_int_addresses_run_bit_identically_to_cfunc_objects():
    by_address = _ball(
        rhs=ball_rhs.address,
        guards=ball_guards.address,
        reset=ball_reset.address,
        jac=np.uint64(ball_jac.address),
    )
    runs = [
        hybrid_solve(s, [1.0, 0.5], BALL_P, t_max=3.0, n_strides=0, output="events", jacobian=True)
        for s in (BALL, by_address)
    ]
    assert runs[0].x.tobytes() == runs[1].x.tobytes()
    assert runs[0].events.t.tobytes() == runs[1].events.t.tobytes()
    assert runs[0].jac.tobytes() == runs[1].jac.tobytes()


def test_runs_in_threads_match_sequential_runs():
    # The C kernel holds no global state and runs without the GIL.
    starts = [[0.5 + 0.25 * i, 0.1 * i] for i in range(6)]

    def run(x0):
        sol = hybrid_solve(BALL, x0, BALL_P, t_max=3.0, n_strides=0, output="full")
        return sol.record.x.tobytes(), sol.t

    sequential = [run(x0) for x0 in starts]
    with ThreadPoolExecutor(max_workers=3) as pool:
        threaded = list(pool.map(run, starts))
    assert threaded == sequential


# ---------------------------------------------------------------------------------------------
# Exponential decay as ctypes Python callbacks: x' = -k x, k read through ctx; one guard
# x - c (p = (c,)) that ends the run.
# ---------------------------------------------------------------------------------------------

_P = ctypes.POINTER(ctypes.c_double)
_VEC = ctypes.CFUNCTYPE(None, ctypes.c_int64, ctypes.c_double, _P, _P, _P, ctypes.c_void_p)
_RESET = ctypes.CFUNCTYPE(
    None,
    ctypes.c_int64,
    ctypes.c_int64,
    ctypes.c_double,
    _P,
    _P,
    _P,
    _P,
    ctypes.POINTER(ctypes.c_int64),
    ctypes.c_void_p,
)


def _rate(ctx):
    return ctypes.cast(ctx, _P)[0]


@_VEC
def decay_rhs(phase, t, x, p, dx, ctx):
    dx[0] = -_rate(ctx) * x[0]


@_VEC
def decay_guards(phase, t, x, p, g, ctx):
    g[0] = x[0] - p[0]


@_RESET
def decay_reset(phase, k, t, x, p, x_new, impulse, out, ctx):
    out[0] = EVENT_TERMINAL
    out[1] = phase
    out[2] = int(Status.COMPLETED)


@_VEC
def decay_jac(phase, t, x, p, J, ctx):
    J[0] = -_rate(ctx)


def test_ctypes_callbacks_decay_event_time():
    rate = ctypes.c_double(0.7)
    functions = (decay_rhs, decay_guards, decay_reset, decay_jac)
    ctx = ctypes.addressof(rate)
    system = toy_system(
        "ctypes decay",
        1,
        functions,
        np.array([[-1]]),
        ("decay",),
        ("threshold",),
        n_params=1,
        ctx=ctx,
    )
    x0, c = 2.0, 0.5
    sol = hybrid_solve(system, [x0], [c], t_max=10.0, output="events", jacobian=True)
    assert sol.status == Status.COMPLETED
    t_event = math.log(x0 / c) / rate.value
    assert abs(sol.t - t_event) < 1e-9
    assert abs(sol.x[0] - c) < 1e-12
    assert len(sol.events) == 1 and abs(sol.events.t[0] - t_event) < 1e-9
    # d x(t_event) / d x0 along the flow, no reset applied on a terminal event
    np.testing.assert_allclose(sol.jac, [[math.exp(-rate.value * t_event)]], rtol=1e-8)
    plain = hybrid_solve(system, [x0], [c], t_max=1.0, n_strides=0)
    assert plain.status == Status.COMPLETED
    assert abs(plain.x[0] - x0 * math.exp(-rate.value)) < 1e-9


# ---------------------------------------------------------------------------------------------
# Bad input
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "name,value,exc,match",
    [
        ("rhs", "ball_rhs", TypeError, "`rhs` must be a numba @njit function, a numba cfunc"),
        ("guards", 1.5, TypeError, "`guards` must be"),
        ("reset", lambda *a: None, TypeError, "`reset` must be"),
        ("jac", True, TypeError, "`jac` must be"),
        ("rhs", 0, ValueError, "`rhs` must be a non-zero address"),
        ("guards", -4, ValueError, "`guards` must be a non-zero address"),
    ],
)
def test_bad_function_is_rejected_naming_the_argument(name, value, exc, match):
    with pytest.raises(exc, match=match):
        _ball(**{name: value})


def test_bad_ctx_is_rejected():
    with pytest.raises(TypeError, match="`ctx` must be an int address"):
        _ball(ctx=ctypes.c_double(1.0))


def test_binding_rejects_bad_arguments_naming_them():
    args = dict(
        rhs=ball_rhs.address,
        guards=ball_guards.address,
        reset=ball_reset.address,
        jac=0,
        ctx=0,
        directions=np.array([[-1]], dtype=np.int64),
        n_x=2,
        n_guards=1,
        n_impulse=1,
        x0=np.array([1.0, 0.0]),
        p=BALL_P,
        phase0=0,
        t0=0.0,
        t_max=1.0,
        n_strides=0,
        method=3,
        adaptive=True,
        rtol=1e-10,
        atol=1e-12,
        first_step=0.0,
        max_step=math.inf,
        max_steps=1000,
        n_interior=4,
        screen_interior=False,
        output=0,
        want_jac=False,
    )
    sol = _hybrid.solve(**args)
    assert sol.status == 0 and sol.t == 1.0 and len(sol.x) == 16

    def bad(name, value, exc, match):
        with pytest.raises(exc, match=match):
            _hybrid.solve(**{**args, name: value})

    bad("rhs", "f", TypeError, "`rhs` must be an int address")
    bad("rhs", 0, ValueError, "`rhs` must be a non-zero function address")
    bad("directions", np.array([[-1.0]]), TypeError, "`directions` must be a C-contiguous int64")
    bad("directions", np.array([[-2]]), ValueError, "`directions` values")
    bad("x0", np.array([1.0, 0.0, 0.0]), ValueError, "`x0` must have length n_x = 2")
    bad("x0", np.array([1.0, 5.0, 0.0])[::2], TypeError, "`x0` must be a C-contiguous float64")
    bad("p", [9.81, 0.8], TypeError, "`p` must be a C-contiguous float64 array")
    bad("phase0", 2, ValueError, "`phase0` must be in")
    bad("method", 7, ValueError, "`method` must be a code")
    bad("want_jac", True, ValueError, "`want_jac` needs a Jacobian")
    bad("n_interior", -4, ValueError, r"`n_interior` must be in \[0, 2\*\*24\]")
    bad("screen_interior", 1.0, TypeError, "`screen_interior` must be a bool")
    bad("terrain", np.zeros((1, 2)), TypeError, "unexpected keyword argument 'terrain'")
    bad("n_p", 3, ValueError, r"`p` must have length n_p = 3, got 2")  # a user's declared count
    bad("n_p", 2.0, TypeError, "`n_p` must be an int")
    assert _hybrid.solve(**args, n_p=2).x == sol.x
    with pytest.raises(TypeError, match="takes keyword arguments only, got 1 positional"):
        _hybrid.solve(ball_rhs.address, **{k: v for k, v in args.items() if k != "rhs"})
    with pytest.raises(TypeError, match="missing required keyword argument `x0`"):
        _hybrid.solve(**{k: v for k, v in args.items() if k != "x0"})
    # the settings bound once: the same run, the same checks
    prepared = _hybrid.PreparedSolve(**{k: v for k, v in args.items() if k not in ("x0", "p")})
    assert prepared.run(x0=args["x0"], p=BALL_P) == sol
    with pytest.raises(ValueError, match="`x0` must have length n_x = 2"):
        prepared.run(x0=np.zeros(3), p=BALL_P)
    with pytest.raises(TypeError, match="got multiple values for argument `t0`"):
        prepared.run(x0=args["x0"], p=BALL_P, t0=0.5)
    with pytest.raises(TypeError, match="missing required keyword argument `p`"):
        prepared.run(x0=args["x0"])
    with pytest.raises(TypeError, match="`method` must be an int"):
        _hybrid.PreparedSolve(**{**args, "method": "DOP853"}).run()
    optional = {"sample_times", "jacobian_seed", "n_p", "terrain"}
    assert set(args) | optional == set(_hybrid.SOLVE_FIELDS)
    # terrain_solve shares solve's names (and solve has run above): its own is found
    with pytest.raises(TypeError, match="missing required keyword argument `terrain`"):
        _hybrid.terrain_solve(**args)
    with pytest.raises(ValueError, match="terrain is not supported for this system's model"):
        _hybrid.terrain_solve(**args, terrain=np.zeros((1, 2)))


SOLVE_RESULT_FIELDS = (
    "status",
    "t",
    "x",
    "phase",
    "n_steps",
    "n_rejected",
    "n_rhs",
    "n_events",
    "n_strides",
    "n_logged",
    "n_samples",
    "n_recorded",
    "error_estimate",
    "event_t",
    "event_guard",
    "event_phase_before",
    "event_phase_after",
    "event_x_pre",
    "event_x_post",
    "event_impulse",
    "sample_x",
    "sample_phase",
    "record_t",
    "record_x",
    "record_phase",
    "jac",
    "dt_dx0",
    "has_dt_dx0",
)


def test_solve_returns_a_named_record_whose_fields_are_its_positions():
    """``_hybrid.solve`` returns a ``SolveResult``: a tuple whose every field, read by name,
    is the entry at its position; one kneed stride read through the names is the stride
    ``hybrid_solve`` returns, bit for bit."""
    scene = load_scene("gaits/kneed_hsu.toml")
    p = scene.params.as_array()
    system = get_model("kneed").system_for(p)
    x0 = np.asarray(scene.reference["state"], dtype=float)
    n_x = system.n_x
    rhs, guards, reset, jac, ctx, _ = _compiled(system)
    sol = _hybrid.solve(
        rhs=rhs, guards=guards, reset=reset, jac=jac, ctx=ctx, directions=system.directions,
        n_x=n_x, n_guards=system.n_guards, n_impulse=system.n_impulse, x0=x0, p=p, phase0=0,
        t0=0.0, t_max=5.0, n_strides=1, method=METHOD_DOP853, adaptive=True, rtol=1e-11,
        atol=1e-11, first_step=0.0, max_step=math.inf, max_steps=1_000_000, n_interior=4,
        screen_interior=system.autonomous_guards, output=OUTPUT_FULL, want_jac=True,
    )  # fmt: skip
    assert type(sol) is _hybrid.SolveResult and isinstance(sol, tuple)
    assert _hybrid.SolveResult.__match_args__ == SOLVE_RESULT_FIELDS
    assert len(sol) == len(SOLVE_RESULT_FIELDS)
    for i, name in enumerate(SOLVE_RESULT_FIELDS):
        assert getattr(sol, name) is sol[i], name

    ref = hybrid_solve(
        system, x0, p, t_max=5.0, rtol=1e-11, atol=1e-11, output="full", jacobian=True
    )
    assert sol.status == ref.status == Status.COMPLETED
    assert (sol.t, sol.phase, sol.error_estimate) == (ref.t, ref.phase, ref.error_estimate)
    counters = (sol.n_steps, sol.n_rejected, sol.n_rhs, sol.n_events, sol.n_strides)
    assert counters == (ref.n_steps, ref.n_rejected, ref.n_rhs, ref.n_events, 1)
    assert (sol.n_logged, sol.n_samples, sol.n_recorded) == (
        len(ref.events),
        0,
        len(ref.record.t),
    )

    def floats(buf, *shape):
        return np.frombuffer(buf, dtype=np.float64).reshape(shape or (-1,))

    assert np.array_equal(floats(sol.x), ref.x)
    assert np.array_equal(floats(sol.jac, n_x, n_x), ref.jac)
    assert sol.has_dt_dx0 and np.array_equal(floats(sol.dt_dx0), ref.dt_dx0)
    assert np.array_equal(floats(sol.event_x_post, -1, n_x), ref.events.x_post)
    assert np.array_equal(np.frombuffer(sol.event_guard, dtype=np.int64), ref.events.guard)
    assert np.array_equal(floats(sol.record_x, -1, n_x), ref.record.x)
    assert sol.sample_x == sol.sample_phase == bytearray()


@cfunc(_RESET_SIG, cache=True)
def lost_reset(phase, k, t, x, p, x_new, impulse, out, ctx):
    out[0] = EVENT_CONTINUE
    out[1] = 5  # no such phase
    out[2] = 0


def test_reset_to_a_missing_phase_is_an_error():
    with pytest.raises(ValueError, match=r"`reset` returned next phase 5, outside \[0, n_phases"):
        hybrid_solve(_ball(reset=lost_reset), [1.0, 0.0], BALL_P, t_max=2.0, n_strides=0)
