"""walker's actuated walkers compiled in C (walker/_core/model_three_link.c,
model_five_link.c, with the controller of walker/_core/wk_control.c and the joint friction of
wk_friction.c) against the numba model functions they port (walker/models/three_link.py,
five_link.py, walker/control.py), and the controller extension point of
walker/_core/wk_actuated.h (a user controller handed to the C model through ``ctx``).

Every C function is called through ctypes at the address ``walker._hybrid.models()``
reports, at many random states and parameter vectors (controller off, PD and computed
torque, saturating or not; joint damping and dry friction on or off) in every phase (joint
mode code), at states with joints at rest (the mode choice of ``start_phase`` and of the
resets), and at states built to reach every branch of the reset maps (the tests assert that
each branch was reached).

Tolerance: bit for bit (NaN where numba gives NaN).  The C code performs the numba
functions' operations in the same order (the Bezier powers by numba's binary exponentiation,
not ``pow``), both call the same libm, and neither contracts multiply-adds (setup.py
compiles with ``-ffp-contract=off``; numba does not contract without fastmath).
"""

import ctypes
import dataclasses
import functools

import numpy as np
import pytest
from _cmodel import (
    CModel,
    assert_bits,
    assert_phase_functions_agree,
    assert_reset_agrees,
    assert_same_run,
    assert_state_functions_agree,
    c_system,
    registry,
    solve_with_events,
)

from walker import load_scene
from walker.models import five_link, get_model, three_link
from walker.status import EVENT_CONTINUE, EVENT_IGNORE, EVENT_STRIDE, EVENT_TERMINAL, Status

_vp = ctypes.c_void_p


class Controller(ctypes.Structure):
    """``wk_controller`` of walker/_core/wk_actuated.h."""

    _fields_ = [("torque", _vp), ("user", _vp)]


def _registry():
    models = registry()
    assert "three_link" in models and "five_link" in models
    return models


# --------------------------------------------------------------------------------------
# Random parameter vectors and states
# --------------------------------------------------------------------------------------

SCENES = {
    "three_link": "gaits/three_link_grizzle.toml",
    "five_link": "gaits/five_link_hzd.toml",
}


@functools.cache
def _scene(name):
    return load_scene(SCENES[name])


def _params(name, rng):
    """The scene's parameters perturbed: body, slope and contact friction; the controller in
    a random mode (off, PD, computed torque) with random gains, limit (often saturating),
    phase range and Bezier coefficients; joint damping and dry friction each zero or not."""
    m = get_model(name).module
    p = _scene(name).params.as_array().copy()
    c0 = m.CONTROL_OFFSET
    n_body = c0 - 3  # masses, lengths, inertias (before slope, g, friction)
    p[:n_body] *= rng.uniform(0.7, 1.3, n_body)
    p[m.I_SLOPE] = rng.uniform(-0.15, 0.15)
    p[m.I_FRICTION] = rng.uniform(0.2, 1.2)
    p[c0] = float(rng.integers(3))  # mode
    p[c0 + 1] = rng.uniform(0.0, 500.0)  # kp
    p[c0 + 2] = rng.uniform(0.0, 60.0)  # kd
    p[c0 + 3] = rng.choice([rng.uniform(1.0, 20.0), rng.uniform(50.0, 400.0)])  # limit
    p[c0 + 4] += rng.normal(0.0, 0.05)  # theta_plus
    p[c0 + 5] += rng.normal(0.0, 0.05)  # theta_minus
    first_friction = len(p) - (2 if m is three_link else 4)
    p[c0 + 6 : first_friction] += rng.normal(0.0, 0.1, first_friction - c0 - 6)
    for i in range(first_friction, len(p)):
        if m is three_link:
            viscous = i == m.I_DAMPING_HIP
        else:
            viscous = i in (m.I_DAMPING_HIP, m.I_DAMPING_KNEE)
        scale = 3.0 if viscous else 40.0
        p[i] = 0.0 if rng.random() < 0.3 else rng.uniform(0.0, scale)
    return p


def _rest(module, rng, qd):
    """``qd`` with a random subset of the joints at rest (joint rate exactly zero)."""
    qd = qd.copy()
    if module is three_link:
        # w = (qd_stance - qd_torso, qd_swing - qd_torso)
        for j in range(2):
            if rng.random() < 0.6:
                qd[j] = qd[2]
        return qd
    # w = (qd0 + qd1/2 - qd2, qd3 - qd2, -qd1, qd4 - qd3): choose w, then qd from w.
    w = np.array([qd[0] + 0.5 * qd[1] - qd[2], qd[3] - qd[2], -qd[1], qd[4] - qd[3]])
    w[rng.random(4) < 0.6] = 0.0
    qd[1] = -w[2]
    qd[0] = w[0] - 0.5 * qd[1] + qd[2]
    qd[3] = w[1] + qd[2]
    qd[4] = w[3] + qd[3]
    return qd


def _state(name, rng, rest=False):
    m = get_model(name).module
    x = _scene(name).state.copy()
    n_q = m.N_Q
    x[:n_q] += rng.normal(0.0, 0.3, n_q)
    x[n_q : 2 * n_q] += rng.normal(0.0, 1.5, n_q)
    x[2 * n_q :] = rng.uniform(-5.0, 5.0, 2)
    if rest:
        x[n_q : 2 * n_q] = _rest(m, rng, x[n_q : 2 * n_q])
    return x


@dataclasses.dataclass(frozen=True)
class Case:
    name: str
    module: object
    n_points: int
    trials: int

    @property
    def n_phases(self):
        return len(self.module.PHASE_NAMES)

    def c_model(self, ctx=0):
        return CModel(_registry()[self.name], self.module, self.n_points, ctx)


CASES = [Case("three_link", three_link, 4, 1000), Case("five_link", five_link, 6, 150)]
# The five_link cases run with the slow tests: their numba reference functions take most of
# this file's time to compile on a machine without numba's cache (about half of it here), and
# the other cases check the same compiled glue.
CASE_PARAMS = [
    pytest.param(c, id=c.name, marks=pytest.mark.slow if c.name == "five_link" else ())
    for c in CASES
]


# --------------------------------------------------------------------------------------
# Registry
# --------------------------------------------------------------------------------------


def test_registry_lists_the_actuated_models():
    models = _registry()
    for case in CASES:
        entry = models[case.name]
        for key in ("rhs", "guards", "reset", "jac", "energy", "points", "start_phase"):
            assert isinstance(entry[key], int) and entry[key] != 0, (case.name, key)
        assert not entry["ctx"], case.name  # the built-in controller


def test_sizes_match_the_modules():
    """The sizes the C files hard-code (wk_actuated.h) against the modules'."""
    assert (three_link.N_X, three_link.N_Q, len(three_link.GUARD_NAMES)) == (8, 3, 10)
    assert (five_link.N_X, five_link.N_Q, len(five_link.GUARD_NAMES)) == (12, 5, 15)
    assert (three_link.N_CODES, five_link.N_CODES) == (9, 81)
    assert (three_link.CONTROL_OFFSET, five_link.CONTROL_OFFSET) == (11, 14)
    assert (three_link.I_DAMPING_HIP, three_link.I_COULOMB_HIP) == (42, 43)
    assert (
        five_link.I_DAMPING_HIP,
        five_link.I_DAMPING_KNEE,
        five_link.I_COULOMB_HIP,
        five_link.I_COULOMB_KNEE,
    ) == (40, 41, 42, 43)
    assert three_link.JAC_STEP == five_link.JAC_STEP == 1e-6


# --------------------------------------------------------------------------------------
# Vector field, guards, Jacobian, energy, points, start phase
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("case", CASE_PARAMS)
def test_continuous_functions_agree(case):
    c = case.c_model()
    m = case.module
    rng = np.random.default_rng(20240612)
    saturated = 0
    for trial in range(case.trials):
        p = _params(case.name, rng)
        x = _state(case.name, rng, rest=trial % 3 == 0)
        t = rng.uniform(0.0, 2.0)
        for phase in range(case.n_phases):
            what = f"{case.name} trial {trial} phase {phase}"
            dx = assert_phase_functions_agree(c, m, phase, t, x, p, what)
            saturated += dx[-1] == 1.0
        assert_state_functions_agree(c, m, x, p, f"{case.name} {trial}")
        assert c.start_phase(x, p) == float(m.start_phase(x, p)), f"{case.name} {trial}"
    assert saturated > 0  # the saturation branch was reached


@pytest.mark.parametrize("case", CASE_PARAMS)
def test_start_phase_agrees_at_rest(case):
    """States with joints at rest, where ``start_phase`` chooses stick or slip from the
    forces: the C choice equals numba's, and sticking and slipping from rest both occur."""
    c = case.c_model()
    m = case.module
    rng = np.random.default_rng(99)
    n_joints = len(m.JOINTS)
    seen = set()
    for trial in range(20 * case.trials):
        p = _params(case.name, rng)
        x = _state(case.name, rng, rest=True)
        ref = int(m.start_phase(x, p))
        assert c.start_phase(x, p) == float(ref), f"{case.name} trial {trial}"
        modes = [(ref // 3**j) % 3 for j in range(n_joints)]
        qd = x[m.N_Q : 2 * m.N_Q]
        for j in range(n_joints):
            w = float(m.S_MATRIX[j] @ qd)
            if abs(w) <= 1e-12:
                seen.add(("rest", modes[j]))
    assert {("rest", 0), ("rest", 1), ("rest", 2)} <= seen, seen


# --------------------------------------------------------------------------------------
# Reset maps: every branch
# --------------------------------------------------------------------------------------


def _foot_down_three_link(rng, p, x):
    """Swing foot on the slope (ahead, behind, or legs together)."""
    slope = p[three_link.I_SLOPE]
    kind = rng.integers(4)
    if kind < 2:
        x[0] = -slope - rng.uniform(0.05, 0.6)  # ahead
    elif kind == 2:
        x[0] = -slope + rng.uniform(0.05, 0.6)  # behind: a scuff
    x[1] = -2.0 * slope - x[0]
    if kind == 3:
        x[1] = x[0]  # legs together: step length zero, a scuff
    return x


def _foot_down_five_link(rng, p, x):
    """Swing foot on the slope: the post-impact configuration of a random section point
    (``lift``, trailing foot on the ground) relabelled, so that the swing foot is ahead; or
    the lifted configuration itself (swing foot behind: a trip)."""
    m = five_link
    ref = _scene("five_link").state
    for _ in range(100):
        z = m.project(ref, p) + np.concatenate([rng.normal(0.0, 0.1, 4), rng.normal(0.0, 0.5, 5)])
        try:
            y = m.lift(z, p)
        except ValueError:
            continue
        break
    else:  # pragma: no cover
        raise AssertionError("no section point reaches the slope")
    q = y[:5] if rng.random() < 0.25 else m.RELABEL @ y[:5]
    x[:5] = q
    return x


def _reset_states(case, rng, n):
    """(phase, k, x, p) tuples reaching every branch of the case's reset map."""
    m = case.module
    n_q = m.N_Q
    out = []
    for i in range(n):
        p = _params(case.name, rng)
        x = _state(case.name, rng, rest=i % 2 == 0)
        xs = x.copy()
        if m is three_link:
            xs = _foot_down_three_link(rng, p, xs)
            xs[n_q : 2 * n_q] = rng.normal(0.0, 1.0, n_q) + np.array([-1.0, 0.5, -1.0])
        else:
            xs = _foot_down_five_link(rng, p, xs)
            xs[n_q : 2 * n_q] = rng.normal(0.0, 1.0, n_q) + np.array([-1.0, 0.5, 0.0, 0.5, 0.5])
        if i % 5 == 0:
            xs[n_q : 2 * n_q] = _rest(m, rng, xs[n_q : 2 * n_q])
        if i % 11 == 0:
            xs[n_q + rng.integers(n_q)] = np.nan  # non-finite impact system: singular
            x[n_q + rng.integers(n_q)] = np.nan  # non-finite friction systems
        phase = int(rng.integers(case.n_phases))
        out.append((phase, 0, xs, p))
        for k in range(1, len(m.GUARD_NAMES)):
            out.append((phase, k, x.copy(), p))
    return out


_NONPHYS = int(Status.NONPHYSICAL_IMPACT)
_SINGULAR = int(Status.LINEAR_SOLVE_FAILED)
_FF, _FB = int(Status.FELL_FORWARD), int(Status.FELL_BACKWARD)
_TRIPPED = int(Status.TRIPPED)


def _outcome(m, k, out):
    """(guard kind, action, status, stuck joints after) of a reset outcome."""
    action, next_phase, status = out
    kind = min(k, m.N_BASE_GUARDS)
    stuck = any((next_phase // 3**j) % 3 == 2 for j in range(len(m.JOINTS)))
    if action != EVENT_CONTINUE:
        stuck = None
    return kind, action, status, stuck


def _required(module, *own):
    """Outcomes (guard or N_BASE_GUARDS for a friction guard, action, status, stuck joints
    after) the reset of ``module`` must reach at least once: those of both walkers (a
    stride, the heel strike's and the friction cone's failures, the falls, a friction event
    with some joint stuck after or every joint slipping, or a singular solve) and ``own``."""
    friction = module.N_BASE_GUARDS
    return {
        (0, EVENT_STRIDE, 0, None),
        (0, EVENT_TERMINAL, _NONPHYS, None),
        (0, EVENT_TERMINAL, _SINGULAR, None),
        (1, EVENT_TERMINAL, _FF, None),
        (2, EVENT_TERMINAL, _FB, None),
        *((k, EVENT_TERMINAL, _NONPHYS, None) for k in (3, 4, 5)),
        (friction, EVENT_CONTINUE, 0, True),
        (friction, EVENT_CONTINUE, 0, False),
        (friction, EVENT_TERMINAL, _SINGULAR, None),
        *own,
    }


REQUIRED = {
    three_link: _required(three_link, (0, EVENT_IGNORE, 0, None)),  # scuff
    five_link: _required(
        five_link,
        (0, EVENT_TERMINAL, _TRIPPED, None),
        (6, EVENT_TERMINAL, _FB, None),  # hip_down
    ),
}


@pytest.mark.parametrize("case", CASE_PARAMS)
def test_reset_agrees_on_every_branch(case):
    c = case.c_model()
    m = case.module
    rng = np.random.default_rng(7)
    seen = set()
    for phase, k, x, p in _reset_states(case, rng, 1000):
        what = f"{case.name} reset phase {phase} k {k} x {x.tolist()}"
        ref_out = assert_reset_agrees(c, m, phase, k, x, p, what)
        seen.add(_outcome(m, k, ref_out))
    missing = REQUIRED[m] - seen
    assert not missing, f"{case.name}: branches not reached {sorted(missing, key=str)}"


# --------------------------------------------------------------------------------------
# The controller extension point (wk_actuated.h): a user controller through ctx
# --------------------------------------------------------------------------------------


def _user_controllers():
    """Two numba cfuncs with the ``wk_torque_fn`` signature (wk_actuated.h), defined here,
    for the three-link walker: ``same``, the built-in controller (walker's numba
    ``controller_torque`` on the controller block of ``p``), and ``offset``, the same plus
    the constant torques read from ``user`` (a float64 array of 2)."""
    from numba import carray, cfunc, njit, types

    from walker.control import controller_torque

    dp = types.CPointer(types.float64)
    sig = types.int32(dp, dp, dp, dp, dp, dp, dp, types.voidptr)
    n, m = three_link.N_Q, three_link.N_Q - 1
    n_p = len(_scene("three_link").params.as_array())
    c0 = three_link.CONTROL_OFFSET

    @njit
    def builtin(q_, qd_, D_, h_, B_, p_, u_):
        """The built-in controller on the arrays behind the pointers; True if saturated."""
        q = carray(q_, (n,))
        qd = carray(qd_, (n,))
        D = carray(D_, (n, n))
        h = carray(h_, (n,))
        B = carray(B_, (n, m))
        p = carray(p_, (n_p,))
        u = carray(u_, (m,))
        return controller_torque(q, qd, D, h, B, p[c0:], u)

    @cfunc(sig)
    def same(q_, qd_, D_, h_, B_, p_, u_, user):
        return 1 if builtin(q_, qd_, D_, h_, B_, p_, u_) else 0

    @cfunc(sig)
    def offset(q_, qd_, D_, h_, B_, p_, u_, user):
        sat = builtin(q_, qd_, D_, h_, B_, p_, u_)
        u = carray(u_, (m,))
        extra = carray(user, (m,), dtype=np.float64)
        for i in range(m):
            u[i] += extra[i]
        return 1 if sat else 0

    return same, offset


class UserController:
    """A ``wk_controller`` (kept alive with its ``user`` data) and its address for ctx."""

    def __init__(self, fn, user=None):
        self.fn = fn
        self.user = None if user is None else np.ascontiguousarray(user, dtype=np.float64)
        self.struct = Controller(
            fn.address if fn is not None else None,
            None if self.user is None else self.user.ctypes.data,
        )
        self.address = ctypes.addressof(self.struct)


OFFSET = np.array([3.0, -3.0])
"""Torque offset [N m] of the ``offset`` controller (hip stance, hip swing)."""


def test_user_controller_reproduces_the_builtin_one():
    """Every function of the C three-link model with ``ctx`` pointing at the ``same`` cfunc
    (or at a wk_controller whose torque is NULL) equals the built-in controller's, bit for
    bit, at random states and parameters in every phase."""
    same, _ = _user_controllers()
    case = CASES[0]
    m = case.module
    builtin = case.c_model()
    ctl = UserController(same)
    user = case.c_model(ctl.address)
    null = UserController(None)
    fallback = case.c_model(null.address)
    rng = np.random.default_rng(3)
    for trial in range(60):
        p = _params(case.name, rng)
        x = _state(case.name, rng, rest=trial % 3 == 0)
        for model in (user, fallback):
            for phase in range(case.n_phases):
                what = f"trial {trial} phase {phase}"
                assert_bits(model.rhs(phase, 0.0, x, p), builtin.rhs(phase, 0.0, x, p), what)
                assert_bits(model.guards(phase, 0.0, x, p), builtin.guards(phase, 0.0, x, p), what)
                assert_bits(model.jac(phase, 0.0, x, p), builtin.jac(phase, 0.0, x, p), what)
                for k in range(m.N_BASE_GUARDS, len(m.GUARD_NAMES)):
                    a, b = model.reset(phase, k, 0.0, x, p), builtin.reset(phase, k, 0.0, x, p)
                    assert a[0] == b[0], what
                    assert_bits(a[1], b[1], what)
            assert model.start_phase(x, p) == builtin.start_phase(x, p)


def test_user_controller_offset_acts_on_the_dynamics():
    """The ``offset`` cfunc adds ``B OFFSET`` to the generalized forces: with every joint
    slipping the accelerations change by ``D^-1 B OFFSET`` (to round-off), and the actuator
    power by ``OFFSET . (B^T qd)``."""
    _, offset = _user_controllers()
    case = CASES[0]
    m = case.module
    builtin = case.c_model()
    ctl = UserController(offset, OFFSET)
    user = case.c_model(ctl.address)
    from walker._generated import three_link as K

    rng = np.random.default_rng(5)
    for _ in range(40):
        p = _params(case.name, rng)
        x = _state(case.name, rng)
        phase = int(rng.choice([0, 1, 3, 4]))  # both hips slipping (no joint stuck)
        d = user.rhs(phase, 0.0, x, p) - builtin.rhs(phase, 0.0, x, p)
        D = np.empty((3, 3))
        K.mass_matrix(x[:3], p, D)
        expected = np.linalg.solve(D, m.B_MATRIX @ OFFSET)
        np.testing.assert_allclose(d[3:6], expected, rtol=1e-8, atol=1e-10)
        w = m.S_MATRIX @ x[3:6]
        np.testing.assert_allclose(d[6], OFFSET @ w, rtol=1e-9, atol=1e-9)
        assert d[7] == 0.0


# --------------------------------------------------------------------------------------
# Whole strides through the integrator
# --------------------------------------------------------------------------------------


def _c_system(name, ctx=0):
    """The model's HybridSystem with the C functions of its registry entry."""
    _registry()
    return c_system(name, ctx=ctx)


def _stride(system, scene, name, check=True):
    """One stride from the phase the numba model's ``start_phase`` gives."""
    p = scene.params.as_array()
    phase0 = int(get_model(name).module.start_phase(scene.state, p))
    return solve_with_events(
        system, scene, phase0=phase0, status=Status.COMPLETED if check else None
    )


def _needs_int_addresses():
    _c_system("three_link")  # HybridSystem takes C addresses


@pytest.mark.parametrize(
    "name",
    [pytest.param(n, marks=pytest.mark.slow if n == "five_link" else ()) for n in SCENES],
)
def test_stride_with_c_model_matches_numba(name):
    """One stride of the scene's gait, bit for bit: final state and time, every event
    (time, guard, post-event state and phase, impulse), the stride's Jacobian and dt/dx0."""
    _needs_int_addresses()
    scene = _scene(name)
    ref = _stride(get_model(name).system, scene, name)
    sol = _stride(_c_system(name), scene, name)
    assert_same_run(sol, ref, name)


def test_stride_with_user_controller():
    """The three-link gait with a user controller through ctx: the ``same`` cfunc
    reproduces the numba model's stride bit for bit; the ``offset`` cfunc changes it (it
    still walks one stride, to another state, with its actuator work changed)."""
    _needs_int_addresses()
    same, offset = _user_controllers()
    scene = _scene("three_link")
    ref = _stride(get_model("three_link").system, scene, "three_link")
    ctl = UserController(same)
    sol = _stride(_c_system("three_link", ctl.address), scene, "three_link")
    assert_same_run(sol, ref, "three_link, user controller")
    other = UserController(offset, OFFSET)
    sol = _stride(_c_system("three_link", other.address), scene, "three_link", check=False)
    assert sol.status == Status.COMPLETED, sol.status
    assert np.abs(sol.x[:6] - ref.x[:6]).max() > 1e-3
    assert abs(sol.x[6] - ref.x[6]) > 1e-3  # actuator work
