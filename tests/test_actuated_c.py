"""walker's actuated walkers compiled in C (walker/_core/model_three_link.c,
model_five_link.c): their registry entries and sizes, and the controller extension point of
walker/_core/wk_actuated.h (a user controller handed to the C model through ``ctx``).

The user controllers are ctypes callbacks with the ``wk_torque_fn`` signature, written here:
a constant torque, whose effect on the dynamics has a closed form (``D^-1 B u`` on the
accelerations, ``u . (B^T qd)`` on the actuator power), and a ``wk_controller`` whose torque
is NULL, which must fall back to the built-in controller.  (The physics of the built-in
controller is checked in tests/test_actuated.py and tests/test_three_link_book.py.)
"""

import ctypes
import functools

import numpy as np
import pytest

from walker import load_scene
from walker.models import five_link, get_model, three_link
from walker.status import Status

_vp = ctypes.c_void_p


class Controller(ctypes.Structure):
    """``wk_controller`` of walker/_core/wk_actuated.h."""

    _fields_ = [("torque", _vp), ("user", _vp)]


def _registry():
    from walker import _hybrid

    models = _hybrid.models()
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


# --------------------------------------------------------------------------------------
# Registry
# --------------------------------------------------------------------------------------


def test_registry_lists_the_actuated_models():
    models = _registry()
    for name in SCENES:
        entry = models[name]
        for key in ("rhs", "guards", "reset", "jac", "energy", "points", "start_phase", "torques"):
            assert isinstance(entry[key], int) and entry[key] != 0, (name, key)
        assert not entry["ctx"], name  # the built-in controller


def test_sizes_match_the_modules():
    """The sizes the C files hard-code (wk_actuated.h) against the modules'."""
    assert (three_link.N_X, three_link.N_Q, len(three_link.GUARD_NAMES)) == (8, 3, 10)
    assert (five_link.N_X, five_link.N_Q, len(five_link.GUARD_NAMES)) == (12, 5, 15)
    assert (three_link.N_CODES, five_link.N_CODES) == (9, 81)
    assert (three_link.CONTROL_OFFSET, five_link.CONTROL_OFFSET) == (12, 15)
    assert (three_link.I_DAMPING_HIP, three_link.I_COULOMB_HIP) == (43, 44)
    assert (
        five_link.I_DAMPING_HIP,
        five_link.I_DAMPING_KNEE,
        five_link.I_COULOMB_HIP,
        five_link.I_COULOMB_KNEE,
    ) == (41, 42, 43, 44)
    assert three_link.JAC_STEP == five_link.JAC_STEP == 1e-6


# --------------------------------------------------------------------------------------
# The controller extension point (wk_actuated.h): a user controller through ctx
# --------------------------------------------------------------------------------------

TORQUE_FN = ctypes.CFUNCTYPE(ctypes.c_int, _vp, _vp, _vp, _vp, _vp, _vp, _vp, _vp)
"""``wk_torque_fn`` (wk_actuated.h): (q, qd, D, h, B, p, u, user) -> saturated."""
OFFSET = np.array([3.0, -3.0])
"""The constant torques [N m] of the user controller (hip stance, hip swing)."""


@TORQUE_FN
def _constant_torque(q, qd, D, h, B, p, u, user):
    """u = the two float64 at ``user``; never saturated."""
    out = (ctypes.c_double * 2).from_address(u)
    given = (ctypes.c_double * 2).from_address(user)
    out[0], out[1] = given[0], given[1]
    return 0


class UserController:
    """A ``wk_controller`` (kept alive with its ``user`` data) and its address for ctx."""

    def __init__(self, fn, user=None):
        self.user = None if user is None else np.ascontiguousarray(user, dtype=np.float64)
        self.struct = Controller(
            ctypes.cast(fn, _vp).value if fn is not None else None,
            None if self.user is None else self.user.ctypes.data,
        )
        self.address = ctypes.addressof(self.struct)


def _with_ctx(name, ctx):
    """Model ``name``'s compiled functions with ``ctx`` handed to every call."""
    from walker.models._compiled import call_phase_fn

    entry = _registry()[name]
    model = get_model(name)

    def call(fn, phase, x, p, shape):
        return call_phase_fn(entry[fn], phase, 0.0, x, p, shape, ctx)

    return model, call


def _controller_off(name, rng):
    """Random parameters with the built-in controller off (mode 0: zero torque) and no joint
    friction, so that the user's constant torque is the only input."""
    p = _params(name, rng)
    m = get_model(name).module
    p[m.CONTROL_OFFSET] = 0.0
    first_friction = len(p) - (2 if m is three_link else 4)
    p[first_friction:] = 0.0
    return p


def test_null_user_torque_falls_back_to_the_builtin_controller():
    """A ``wk_controller`` whose torque is NULL runs the built-in controller: every phase
    function equals the one called without ctx, bit for bit, in every phase."""
    null = UserController(None)
    rng = np.random.default_rng(3)
    model, call = _with_ctx("three_link", null.address)
    for trial in range(30):
        p = _params("three_link", rng)
        x = _state("three_link", rng, rest=trial % 3 == 0)
        for phase in range(len(model.phase_names)):
            n_x, n_g = model.n_x, len(model.guard_names)
            np.testing.assert_array_equal(call("rhs", phase, x, p, (n_x,)), model.rhs(phase, x, p))
            np.testing.assert_array_equal(
                call("guards", phase, x, p, (n_g,)), model.guards(phase, x, p)
            )
            np.testing.assert_array_equal(
                call("jac", phase, x, p, (n_x, n_x)), model.jac(phase, x, p)
            )


@pytest.mark.parametrize("name", ["three_link"])
def test_user_torque_acts_on_the_dynamics(name):
    """A constant user torque ``u`` with the built-in controller off and no joint friction:
    the accelerations change by ``D^-1 B u`` against the unactuated model (to round-off),
    the actuator power is ``u . (B^T qd)`` and nothing saturates."""
    ctl = UserController(_constant_torque, OFFSET)
    model, call = _with_ctx(name, ctl.address)
    m = model.module
    n = m.N_Q
    rng = np.random.default_rng(5)
    for _ in range(40):
        p = _controller_off(name, rng)
        x = _state(name, rng)
        d = call("rhs", 0, x, p, (model.n_x,)) - model.rhs(0, x, p)
        expected = np.linalg.solve(model.kernel("mass_matrix", p, x[:n]), m.B_MATRIX @ OFFSET)
        np.testing.assert_allclose(d[n : 2 * n], expected, rtol=1e-8, atol=1e-10)
        w = m.S_MATRIX @ x[n : 2 * n]
        np.testing.assert_allclose(d[2 * n], OFFSET @ w, rtol=1e-9, atol=1e-9)
        assert d[2 * n + 1] == 0.0


def test_stride_with_user_controller():
    """The three-link gait with a user controller through ctx: a ``wk_controller`` with a
    NULL torque walks the built-in controller's stride bit for bit; a constant torque
    replacing the controller changes it."""
    import dataclasses

    from walker.simulation.integrate import hybrid_solve

    scene = _scene("three_link")
    model = get_model("three_link")
    p = scene.params.as_array()
    phase0 = model.start_phase(scene.state, p)
    c = scene.compute

    def stride(ctx):
        system = dataclasses.replace(model.system, ctx=ctx)
        return hybrid_solve(
            system,
            scene.state,
            p,
            phase0=phase0,
            t_max=c.t_max,
            n_strides=1,
            method=c.method,
            rtol=c.rtol,
            atol=c.atol,
            output="events",
            jacobian=True,
        )

    ref = stride(0)
    assert ref.status == Status.COMPLETED, ref.status
    null = UserController(None)
    same = stride(null.address)
    np.testing.assert_array_equal(same.x, ref.x)
    np.testing.assert_array_equal(same.jac, ref.jac)
    np.testing.assert_array_equal(same.events.t, ref.events.t)
    other = UserController(_constant_torque, OFFSET)
    changed = stride(other.address)
    assert np.abs(changed.x[:6] - ref.x[:6]).max() > 1e-3 or changed.status != ref.status
