"""Small hybrid systems for the integrator tests, each built by ``toy_system`` (also the other
tests' toy systems).  Their functions have the array form of :class:`HybridSystem`; with
numba installed they are ``@njit`` functions (a user's own system, bridged by a numba
cfunc), without it plain Python functions handed to the integrator as ctypes callbacks
(:func:`ctypes_functions`), so the integrator's tests never need numba.

* ``ODE``: plain ODEs with exact solutions selected by phase (no guards).
* ``BALL``: bouncing ball with restitution, closed-form impact times.
* ``LIFT``: x' = -1, lifted back by p[0] at each zero (events that need not advance time).
* ``RAMP``: x' = 1 with a guard cos(x) that has two same-direction roots 2*pi apart.
* ``WALKER``: the simplest walking model (Garcia et al. 1998), nonlinear with a scuff.
"""

import ctypes
import math

import numpy as np

from walker.simulation.integrate import HybridSystem
from walker.status import (
    EVENT_CONTINUE,
    EVENT_IGNORE,
    EVENT_STRIDE,
    EVENT_TERMINAL,
    Status,
)

try:  # numba is optional (the extra ``numba``): without it, ctypes callbacks
    from numba import njit as _numba_njit
except ImportError:
    _numba_njit = None


def njit(*args, **options):
    """numba's ``njit`` when numba is installed, else the function unchanged (called
    through :func:`ctypes_functions`)."""
    if _numba_njit is not None:
        return _numba_njit(*args, **options)
    if args:
        return args[0]
    return lambda fn: fn


_F64 = ctypes.POINTER(ctypes.c_double)
_I64 = ctypes.POINTER(ctypes.c_int64)
_PHASE_FN = ctypes.CFUNCTYPE(
    None, ctypes.c_int64, ctypes.c_double, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p,
    ctypes.c_void_p,
)  # fmt: skip
_RESET_FN = ctypes.CFUNCTYPE(
    None, ctypes.c_int64, ctypes.c_int64, ctypes.c_double, *(6 * [ctypes.c_void_p])
)
_P_VIEW = 16  # entries of p a toy function may index (a view: only what it reads is read)


def _array(address, shape, kind=_F64):
    return np.ctypeslib.as_array(ctypes.cast(address, kind), shape)


def ctypes_functions(n_x, n_guards, n_impulse, rhs, guards, reset, jac):
    """``(rhs, guards, reset, jac)`` of the array form as ctypes callbacks with the C
    signatures of ``walker/_core/wk_system.h`` (None stays None)."""

    def phase_fn(fn, shape):
        def call(phase, t, x, p, out, ctx):
            with np.errstate(all="ignore"):  # IEEE semantics, as compiled code has them
                fn(phase, t, _array(x, (n_x,)), _array(p, (_P_VIEW,)), _array(out, shape))

        return _PHASE_FN(call)

    def reset_fn(fn):
        def call(phase, k, t, x, p, x_new, impulse, out, ctx):
            result = fn(
                phase, k, t, _array(x, (n_x,)), _array(p, (_P_VIEW,)), _array(x_new, (n_x,)),
                _array(impulse, (max(n_impulse, 1),)),
            )  # fmt: skip
            _array(out, (3,), _I64)[:] = [int(v) for v in result]

        return _RESET_FN(call)

    return (
        phase_fn(rhs, (n_x,)),
        phase_fn(guards, (max(n_guards, 1),)),
        reset_fn(reset),
        None if jac is None else phase_fn(jac, (n_x, n_x)),
    )


FELL_FORWARD = int(Status.FELL_FORWARD)
FELL_BACKWARD = int(Status.FELL_BACKWARD)


def toy_fields(name, n_x, functions, directions, phase_names, guard_names, **options) -> dict:
    """The :class:`HybridSystem` fields of a toy system: ``functions`` are its ``(rhs,
    guards, reset, jac)``, its phases and guards as many as their names, one impulse
    component unless ``options`` (more fields) say otherwise."""
    rhs, guards, reset, jac = functions
    fields = dict(n_phases=len(phase_names), n_guards=len(guard_names), n_impulse=1)
    fields.update(options)
    if _numba_njit is None:  # plain Python functions: as ctypes callbacks
        rhs, guards, reset, jac = ctypes_functions(
            n_x, fields["n_guards"], fields["n_impulse"], rhs, guards, reset, jac
        )
    fields.update(rhs=rhs, guards=guards, reset=reset, jac=jac, directions=directions)
    fields.update(phase_names=phase_names, guard_names=guard_names, **options)
    return dict(name=name, n_x=n_x, **fields)


def toy_system(name, n_x, functions, directions, phase_names, guard_names, **options):
    """The :class:`HybridSystem` of :func:`toy_fields`."""
    return HybridSystem(
        **toy_fields(name, n_x, functions, directions, phase_names, guard_names, **options)
    )


# ---------------------------------------------------------------------------------------------
# Plain ODEs (n_x = 2).  phase 0: damped rotation x' = [[-a, -1], [1, -a]] x (a = p[0]);
# phase 1: x0' = -2 t x0^2 (x0 = 1/(1+t^2) from 1), x1' = x1 (1 - x1) (logistic);
# phase 2: pendulum x0'' = -p[1] sin x0; phase 3: blow-up x0' = x0^2.
# ---------------------------------------------------------------------------------------------


@njit(cache=True)
def ode_rhs(phase, t, x, p, dx):
    if phase == 0:
        dx[0] = -p[0] * x[0] - x[1]
        dx[1] = x[0] - p[0] * x[1]
    elif phase == 1:
        dx[0] = -2.0 * t * x[0] * x[0]
        dx[1] = x[1] * (1.0 - x[1])
    elif phase == 2:
        dx[0] = x[1]
        dx[1] = -p[1] * math.sin(x[0])
    else:
        dx[0] = x[0] * x[0]
        dx[1] = 0.0


@njit(cache=True)
def ode_jac(phase, t, x, p, J):
    J[:, :] = 0.0
    if phase == 0:
        J[0, 0] = -p[0]
        J[0, 1] = -1.0
        J[1, 0] = 1.0
        J[1, 1] = -p[0]
    elif phase == 1:
        J[0, 0] = -4.0 * t * x[0]
        J[1, 1] = 1.0 - 2.0 * x[1]
    elif phase == 2:
        J[0, 1] = 1.0
        J[1, 0] = -p[1] * math.cos(x[0])
    else:
        J[0, 0] = 2.0 * x[0]


@njit(cache=True)
def no_guards(phase, t, x, p, g):
    pass


@njit(cache=True)
def no_reset(phase, k, t, x, p, x_new, impulse):
    return EVENT_IGNORE, phase, 0


ODE = toy_system(
    "ode",
    2,
    (ode_rhs, no_guards, no_reset, ode_jac),
    np.zeros((4, 0), dtype=np.int64),
    ("rotation", "nonlinear", "pendulum", "blowup"),
    (),
)


def ode_exact(phase, t, x0, p):
    """Exact solution of ODE phases 0 and 1 at times ``t`` (shape (n_t, 2))."""
    t = np.asarray(t, dtype=float)
    if phase == 0:
        a = p[0]
        c, s = np.cos(t), np.sin(t)
        e = np.exp(-a * t)
        return np.stack([e * (c * x0[0] - s * x0[1]), e * (s * x0[0] + c * x0[1])], axis=-1)
    if phase == 1:
        y0 = 1.0 / (1.0 / x0[0] + t**2)
        y1 = 1.0 / (1.0 + (1.0 / x0[1] - 1.0) * np.exp(-t))
        return np.stack([y0, y1], axis=-1)
    raise ValueError(phase)


# ---------------------------------------------------------------------------------------------
# Bouncing ball: x = [height, velocity], p = [gravity, restitution, v_stop].  Guard: height,
# direction -1.  Reset: v -> -e v (EVENT_STRIDE), or EVENT_TERMINAL with FELL_FORWARD when the
# impact speed is below v_stop (a stand-in for a model's own terminal outcome).
# ---------------------------------------------------------------------------------------------


@njit(cache=True)
def ball_rhs(phase, t, x, p, dx):
    dx[0] = x[1]
    dx[1] = -p[0]


@njit(cache=True)
def ball_jac(phase, t, x, p, J):
    J[:, :] = 0.0
    J[0, 1] = 1.0


@njit(cache=True)
def ball_guards(phase, t, x, p, g):
    g[0] = x[0]


@njit(cache=True)
def ball_reset(phase, k, t, x, p, x_new, impulse):
    if abs(x[1]) < p[2]:
        return EVENT_TERMINAL, phase, FELL_FORWARD
    x_new[1] = -p[1] * x[1]
    impulse[0] = (1.0 + p[1]) * abs(x[1])
    return EVENT_STRIDE, phase, 0


BALL = toy_system(
    "ball",
    2,
    (ball_rhs, ball_guards, ball_reset, ball_jac),
    np.array([[-1]]),
    ("flight",),
    ("height",),
)


def ball_impact_times(h0, gravity, e, n):
    """Closed-form times of the first ``n`` impacts of a ball dropped from rest at ``h0``."""
    t1 = math.sqrt(2.0 * h0 / gravity)
    v1 = gravity * t1
    times = [t1]
    for k in range(1, n):
        times.append(times[-1] + 2.0 * e**k * v1 / gravity)
    return np.array(times)


# ---------------------------------------------------------------------------------------------
# Lift: x' = -1, guard x (direction -1), reset x -> p[0] (EVENT_STRIDE).  Events at
# t = x0 + k p[0]; a lift far below the spacing of t (1e-300 at t = 1) gives events that do
# not advance time.
# ---------------------------------------------------------------------------------------------


@njit(cache=True)
def lift_rhs(phase, t, x, p, dx):
    dx[0] = -1.0


@njit(cache=True)
def lift_guards(phase, t, x, p, g):
    g[0] = x[0]


@njit(cache=True)
def lift_reset(phase, k, t, x, p, x_new, impulse):
    x_new[0] = p[0]
    impulse[0] = 0.0
    return EVENT_STRIDE, phase, 0


LIFT = toy_system(
    "lift", 1, (lift_rhs, lift_guards, lift_reset, None), np.array([[-1]]), ("fall",), ("x",)
)


# ---------------------------------------------------------------------------------------------
# Ramp: x = [s, c], s' = 1, c' = 0.  Guard cos(s), direction -1: roots at pi/2, 5pi/2, ...
# p[0] = 0: every crossing is EVENT_CONTINUE; p[0] = 1: crossings with s < pi are ignored and
# later ones are strides.
# ---------------------------------------------------------------------------------------------


@njit(cache=True)
def ramp_rhs(phase, t, x, p, dx):
    dx[0] = 1.0
    dx[1] = 0.0


@njit(cache=True)
def ramp_guards(phase, t, x, p, g):
    g[0] = math.cos(x[0])


@njit(cache=True)
def ramp_reset(phase, k, t, x, p, x_new, impulse):
    if p[0] == 0.0:
        x_new[1] = x[1] + 1.0
        return EVENT_CONTINUE, phase, 0
    if x[0] < math.pi:
        return EVENT_IGNORE, phase, 0
    return EVENT_STRIDE, phase, 0


RAMP = toy_system(
    "ramp", 2, (ramp_rhs, ramp_guards, ramp_reset, None), np.array([[-1]]), ("ramp",), ("cos",)
)

# ---------------------------------------------------------------------------------------------
# Simplest walking model, Garcia, Chatterjee, Ruina, Coleman, J. Biomech. Eng. 120:281 (1998):
# x = [theta, phi, theta_dot, phi_dot], p = [slope].  Guards: 0 heel strike phi - 2 theta
# (either direction; the reset ignores the mid-swing scuff with theta >= 0), 1 fall forward
# theta + 1.2 (decreasing), 2 fall backward theta_dot (increasing through 0).
# ---------------------------------------------------------------------------------------------


@njit(cache=True)
def walker_rhs(phase, t, x, p, dx):
    th, ph, thd = x[0], x[1], x[2]
    s = math.sin(th - p[0])
    dx[0] = thd
    dx[1] = x[3]
    dx[2] = s
    dx[3] = s + math.sin(ph) * (thd * thd - math.cos(th - p[0]))


@njit(cache=True)
def walker_jac(phase, t, x, p, J):
    th, ph, thd = x[0], x[1], x[2]
    J[:, :] = 0.0
    J[0, 2] = 1.0
    J[1, 3] = 1.0
    c = math.cos(th - p[0])
    J[2, 0] = c
    J[3, 0] = c + math.sin(ph) * math.sin(th - p[0])
    J[3, 1] = math.cos(ph) * (thd * thd - c)
    J[3, 2] = 2.0 * thd * math.sin(ph)


@njit(cache=True)
def walker_guards(phase, t, x, p, g):
    g[0] = x[1] - 2.0 * x[0]
    g[1] = x[0] + 1.2
    g[2] = x[2]


@njit(cache=True)
def walker_reset(phase, k, t, x, p, x_new, impulse):
    if k == 1:
        return EVENT_TERMINAL, phase, FELL_FORWARD
    if k == 2:
        return EVENT_TERMINAL, phase, FELL_BACKWARD
    th, thd = x[0], x[2]
    if th >= 0.0:
        return EVENT_IGNORE, phase, 0  # mid-swing scuff
    c2 = math.cos(2.0 * th)
    x_new[0] = -th
    x_new[1] = -2.0 * th
    x_new[2] = c2 * thd
    x_new[3] = c2 * (1.0 - c2) * thd
    return EVENT_STRIDE, phase, 0


WALKER = toy_system(
    "simplest_walker",
    4,
    (walker_rhs, walker_guards, walker_reset, walker_jac),
    np.array([[0, -1, 1]]),
    ("swing",),
    ("heel_strike", "fall_forward", "fall_backward"),
)


def walker_state(theta, theta_dot):
    """Full state just after heel strike from the section point (theta, theta_dot)."""
    c2 = math.cos(2.0 * theta)
    return np.array([theta, 2.0 * theta, theta_dot, c2 * (1.0 - c2) * theta_dot])
