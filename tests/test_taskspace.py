"""Cartesian (task-space) dynamics of the planar elbow manipulator and the kneed walker's
swing leg (:mod:`walker.symbolic.taskspace`), and the operational-space circle tracking of
``scripts/taskspace_circle.py``.

The task accelerations and Jacobians that feed the checks are written by hand here (tip and
foot kinematics in closed form), and the torques are also compared with the recursive
Newton-Euler algorithm of :mod:`walker.symbolic.newton_euler`, so a wrong ``J``,
``J_dot q_dot`` or sign in ``M_x``, ``V_x``, ``G_x`` or ``Q_x`` shows up as a number rather
than cancelling out.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from numpy.testing import assert_allclose
from scipy.optimize import brentq
from test_damping import double_pendulum_vector

from walker.params import DoublePendulumParams, KneedParams
from walker.symbolic import models
from walker.symbolic.newton_euler import PlanarChain, inverse_dynamics
from walker.symbolic.taskspace import (
    MAX_CONDITION,
    CartesianFunctions,
    SingularConfiguration,
    planar_elbow_cartesian,
    swing_foot_cartesian,
)

_SPEC = importlib.util.spec_from_file_location(
    "walker_taskspace_circle",
    Path(__file__).resolve().parents[1] / "scripts" / "taskspace_circle.py",
)
circle_script = importlib.util.module_from_spec(_SPEC)
sys.modules[_SPEC.name] = circle_script  # its dataclasses look their module up
_SPEC.loader.exec_module(circle_script)

EPS = np.finfo(np.float64).eps
N_STATES = 100
TORQUE_RTOL = 1e-12  # the gate: joint-space and Cartesian torques agree to 1e-12
WELL_CONDITIONED = 20.0  # random states keep cond(J) <= 20: cond^2 eps <= 1e-13
CHAINS = ("elbow", "swing_foot")


@pytest.fixture(scope="module")
def functions():
    return {
        "elbow": CartesianFunctions(planar_elbow_cartesian()),
        "swing_foot": CartesianFunctions(swing_foot_cartesian()),
    }


# ------------------------------------------------------------------ parameters, states
def random_elbow_params(rng, *, damped=True) -> np.ndarray:
    """DoublePendulumParams vector; joint dampers on unless ``damped=False`` (Newton-Euler
    has frictionless joints)."""
    lengths = rng.uniform(0.3, 2.0, 2)

    def dampers():
        return (rng.uniform(0.0, 2.0), rng.uniform(0.0, 2.0)) if damped else (0.0, 0.0)

    return double_pendulum_vector(rng, lengths, dampers)


def random_kneed_params(rng, *, damped=True) -> np.ndarray:
    """KneedParams vector with round feet, offsets, inertias, a slope and a knee damper."""
    a1, b1, a2, b2 = rng.uniform(0.05, 0.6, 4)
    base = KneedParams.hsu_chen().to_dict()
    base.update(
        mass_thigh=rng.uniform(0.1, 2.0),
        mass_shank=rng.uniform(0.02, 1.0),
        shank_com_from_foot=a1,
        shank_com_to_knee=b1,
        thigh_com_from_knee=a2,
        thigh_com_to_hip=b2,
        inertia_thigh=rng.uniform(0.001, 0.1),
        inertia_shank=rng.uniform(0.001, 0.1),
        offset_thigh=rng.uniform(-0.1, 0.1),
        offset_shank=rng.uniform(-0.1, 0.1),
        foot_radius=rng.uniform(0.0, 0.9) * a1,
        slope=rng.uniform(-0.3, 0.3),
        g=rng.uniform(1.0, 20.0),
        damping_knee=rng.uniform(0.0, 2.0) if damped else 0.0,
    )
    return KneedParams(**base).as_array()


RANDOM_PARAMS = {"elbow": random_elbow_params, "swing_foot": random_kneed_params}


def well_conditioned_states(fn, rng, params, count=N_STATES):
    """``count`` random (q, qd, qdd, p) with cond(J) <= WELL_CONDITIONED."""
    out = []
    while len(out) < count:
        p = params(rng)
        q = rng.uniform(-np.pi, np.pi, 2)
        if fn.condition_number(q, p) <= WELL_CONDITIONED:
            out.append((q, rng.normal(0.0, 2.0, 2), rng.normal(0.0, 5.0, 2), p))
    return out


# ---------------------------------------------------------------- kinematics by hand
def _e(a):
    return np.array([np.cos(a), np.sin(a)])


def elbow_kinematics(q, qd, p):
    """Tip position, Jacobian and convective acceleration ``J_dot q_dot``, in closed form."""
    prm = DoublePendulumParams.from_array(p)
    l1, l2 = prm.length_1, prm.length_2
    q1, q12 = q[0], q[0] + q[1]
    x = l1 * _e(q1) + l2 * _e(q12)
    perp1, perp12 = np.array([-np.sin(q1), np.cos(q1)]), np.array([-np.sin(q12), np.cos(q12)])
    J = np.column_stack([l1 * perp1 + l2 * perp12, l2 * perp12])
    jdot_qd = -l1 * qd[0] ** 2 * _e(q1) - l2 * (qd[0] + qd[1]) ** 2 * _e(q12)
    return x, J, jdot_qd


def swing_foot_kinematics(q, qd, p):
    """Foot contact point relative to the hip in the slope frame, with ``J``, ``J_dot q_dot``.

    Thigh along ``-u(q2)`` for ``l_t``, shank along ``-u(q3)`` to the arc centre, ``R`` below
    it along the slope normal; ``u = (-sin, cos)``, ``w = (cos, sin)``.
    """
    prm = KneedParams.from_array(p)
    l_t = prm.thigh_com_from_knee + prm.thigh_com_to_hip
    l_s = prm.shank_com_from_foot + prm.shank_com_to_knee
    R, slope = prm.foot_radius, prm.slope

    def u(a):
        return np.array([-np.sin(a), np.cos(a)])

    to_slope = np.array([[np.cos(slope), -np.sin(slope)], [np.sin(slope), np.cos(slope)]])
    normal = np.array([np.sin(slope), np.cos(slope)])
    foot = -l_t * u(q[0]) - (l_s - R) * u(q[1]) - R * normal
    J = np.column_stack([l_t * _e(q[0]), (l_s - R) * _e(q[1])])
    jdot_qd = l_t * qd[0] ** 2 * u(q[0]) + (l_s - R) * qd[1] ** 2 * u(q[1])
    return to_slope @ foot, to_slope @ J, to_slope @ jdot_qd


KINEMATICS = {"elbow": elbow_kinematics, "swing_foot": swing_foot_kinematics}


def joint_torque(fn, q, qd, qdd, p):
    """``tau = D q_ddot + C q_dot + g - Q``."""
    jt = fn.joint_terms(q, qd, p)
    return jt.mass_matrix @ qdd + jt.coriolis + jt.gravity - jt.forcing


def cartesian_torque(fn, kinematics, q, qd, qdd, p):
    """``tau = J^T (M_x x_ddot + V_x + G_x - Q_x)``, ``x_ddot = J q_ddot + J_dot q_dot`` with
    ``J`` and ``J_dot q_dot`` from the hand-written kinematics."""
    _, J, jdot_qd = kinematics(q, qd, p)
    ct = fn.cartesian_terms(q, qd, p)
    xdd = J @ qdd + jdot_qd
    return J.T @ (ct.mass @ xdd + ct.velocity + ct.gravity - ct.forcing)


# ---------------------------------------------------------------------------- tests
@pytest.mark.parametrize("chain", CHAINS)
def test_kinematics_match_closed_form(functions, chain):
    """Task point, Jacobian and ``J_dot q_dot`` of the derivation equal the hand-written
    closed forms (so the torque comparison below does not reuse the derivation's own)."""
    fn, rng = functions[chain], np.random.default_rng(16_4_1)
    for q, qd, _, p in well_conditioned_states(fn, rng, RANDOM_PARAMS[chain], 30):
        x, J, jdot_qd = KINEMATICS[chain](q, qd, p)
        assert_allclose(fn.position(q, p), x, rtol=0, atol=1e-14)
        assert_allclose(fn.jacobian(q, p), J, rtol=0, atol=1e-14)
        assert_allclose(fn.cartesian_terms(q, qd, p).jdot_qd, jdot_qd, rtol=0, atol=1e-13)


def test_swing_foot_is_the_kneed_walkers_swing_contact_relative_to_the_hip(functions):
    """The chain reuses the walker's model: its foot is ``kneed_unlocked``'s
    ``swing_contact - hip`` in the slope frame, and its ``D`` and ``g`` are the ``(q2, q3)``
    blocks of the walker's (the hip moves with ``q1`` only)."""
    full = models.kneed_unlocked()
    args = [list(full.q), list(full.qd), list(full.params)]
    rel = sp.lambdify(args, full.points["swing_contact"] - full.points["hip"], cse=True)
    blocks = sp.lambdify(args, [full.D[1:, 1:], full.G[1:, :]], cse=True)
    fn, rng = functions["swing_foot"], np.random.default_rng(16_4_2)
    for _ in range(20):
        p = random_kneed_params(rng)
        q = rng.uniform(-np.pi, np.pi, 3)
        qd = rng.normal(0.0, 2.0, 3)
        slope = KneedParams.from_array(p).slope
        to_slope = np.array([[np.cos(slope), -np.sin(slope)], [np.sin(slope), np.cos(slope)]])
        foot = to_slope @ np.asarray(rel(q, qd, p), dtype=float).ravel()
        assert_allclose(fn.position(q[1:], p), foot, rtol=0, atol=1e-14)
        D, G = blocks(q, qd, p)
        jt = fn.joint_terms(q[1:], qd[1:], p)
        assert_allclose(jt.mass_matrix, np.asarray(D, dtype=float), rtol=1e-14, atol=1e-15)
        assert_allclose(jt.gravity, np.asarray(G, dtype=float).ravel(), rtol=1e-14, atol=1e-14)


@pytest.mark.parametrize("chain", CHAINS)
def test_joint_and_cartesian_forms_give_the_same_torques(functions, chain):
    """``D q_ddot + C q_dot + g - Q = J^T (M_x x_ddot + V_x + G_x - Q_x)`` to 1e-12 relative
    (max-norm over the torque vector) at random well-conditioned states, dampers on."""
    fn, rng = functions[chain], np.random.default_rng(16_4_3)
    worst = 0.0
    for q, qd, qdd, p in well_conditioned_states(fn, rng, RANDOM_PARAMS[chain]):
        tau = joint_torque(fn, q, qd, qdd, p)
        tau_x = cartesian_torque(fn, KINEMATICS[chain], q, qd, qdd, p)
        worst = max(worst, np.max(np.abs(tau_x - tau)) / np.max(np.abs(tau)))
    assert worst <= TORQUE_RTOL, f"max relative torque difference {worst:.2e}"


@pytest.mark.parametrize("chain", CHAINS)
def test_cartesian_torques_match_newton_euler(functions, chain):
    """The Cartesian form against the recursive Newton-Euler algorithm (no Lagrangian, no
    energy): frictionless joints, world gravity ``(0, -g)``."""
    fn, rng = functions[chain], np.random.default_rng(16_4_4)

    def params(r):
        return RANDOM_PARAMS[chain](r, damped=False)

    for q, qd, qdd, p in well_conditioned_states(fn, rng, params, 30):
        if chain == "elbow":
            prm = DoublePendulumParams.from_array(p)
            nodes = PlanarChain(
                lengths=[prm.length_1, prm.length_2],
                coms=[[prm.com_1, 0.0], [prm.com_2, 0.0]],
                masses=[prm.mass_1, prm.mass_2],
                inertias=[prm.inertia_1, prm.inertia_2],
            )
            tau = inverse_dynamics(nodes, q, qd, qdd, gravity=(0.0, -prm.g))
        else:
            # Rooted at the hip: thigh then shank along -u(q), at q - pi/2 from +x; relative
            # joint angles theta = T q + c, torques on q are T^T tau_theta.
            prm = KneedParams.from_array(p)
            nodes = PlanarChain(
                lengths=[
                    prm.thigh_com_from_knee + prm.thigh_com_to_hip,
                    prm.shank_com_from_foot + prm.shank_com_to_knee,
                ],
                coms=[
                    [prm.thigh_com_to_hip, prm.offset_thigh],
                    [prm.shank_com_to_knee, prm.offset_shank],
                ],
                masses=[prm.mass_thigh, prm.mass_shank],
                inertias=[prm.inertia_thigh, prm.inertia_shank],
            )
            T = np.array([[1.0, 0.0], [-1.0, 1.0]])
            theta = T @ q + np.array([-np.pi / 2, 0.0])
            tau = T.T @ inverse_dynamics(nodes, theta, T @ qd, T @ qdd, gravity=(0.0, -prm.g))
        tau_x = cartesian_torque(fn, KINEMATICS[chain], q, qd, qdd, p)
        assert_allclose(tau_x, tau, rtol=1e-11, atol=1e-11 * np.max(np.abs(tau)))


@pytest.mark.parametrize("chain", CHAINS)
def test_task_space_inertia_is_symmetric_positive_definite(functions, chain):
    """``M_x`` is symmetric, positive definite, equals Khatib's ``(J D^-1 J^T)^-1`` and
    carries the kinetic energy: ``x_dot^T M_x x_dot = q_dot^T D q_dot``."""
    fn, rng = functions[chain], np.random.default_rng(16_4_5)
    for q, qd, _, p in well_conditioned_states(fn, rng, RANDOM_PARAMS[chain], 50):
        ct = fn.cartesian_terms(q, qd, p)
        D = fn.joint_terms(q, qd, p).mass_matrix
        M = ct.mass
        scale = np.max(np.abs(M))
        assert_allclose(M, M.T, rtol=0, atol=1e-14 * scale)
        assert np.min(np.linalg.eigvalsh(0.5 * (M + M.T))) > 0.0
        J = ct.jacobian
        assert_allclose(M, np.linalg.inv(J @ np.linalg.solve(D, J.T)), rtol=1e-11, atol=0)
        xd = J @ qd
        assert_allclose(xd @ M @ xd, qd @ D @ qd, rtol=1e-12, atol=0)


def test_point_mass_limit_has_trivial_cartesian_dynamics(functions):
    """All mass in one point at the task point: ``M_x = m I``, ``V_x = 0`` and ``G_x`` holds
    the mass against gravity, ``-m g_vec``; for the swing foot ``g_vec`` is gravity in the hip's
    slope frame, ``g (sin slope, -cos slope)``."""
    rng = np.random.default_rng(16_4_6)
    elbow = DoublePendulumParams.course().to_dict()
    elbow.update(mass_1=1e-300, inertia_1=0.0, inertia_2=0.0, com_2=elbow["length_2"], g=9.81)
    p = DoublePendulumParams(**elbow).as_array()
    slope = 0.2
    kneed = KneedParams.hsu_chen().to_dict()
    kneed.update(
        mass_thigh=1e-300,
        inertia_thigh=0.0,
        inertia_shank=0.0,
        offset_thigh=0.0,
        offset_shank=0.0,
        shank_com_to_knee=kneed["shank_com_from_foot"] + kneed["shank_com_to_knee"],
        shank_com_from_foot=0.0,
        foot_radius=0.0,
        slope=slope,
        g=9.81,
    )
    pk = KneedParams(**kneed).as_array()
    cases = [
        ("elbow", p, elbow["mass_2"], np.array([0.0, -9.81])),
        ("swing_foot", pk, kneed["mass_shank"], 9.81 * np.array([np.sin(slope), -np.cos(slope)])),
    ]
    for chain, pv, m, g_vec in cases:
        fn = functions[chain]
        for _ in range(10):
            q = rng.uniform(-np.pi, np.pi, 2)
            if fn.condition_number(q, pv) > WELL_CONDITIONED:
                continue
            ct = fn.cartesian_terms(q, rng.normal(0.0, 2.0, 2), pv)
            assert_allclose(ct.mass, m * np.eye(2), rtol=0, atol=1e-12 * m)
            assert_allclose(ct.velocity, 0.0, rtol=0, atol=1e-11 * m)
            assert_allclose(ct.gravity, -m * g_vec, rtol=0, atol=1e-12 * m * 9.81)


def _elbow_angle_at_threshold(fn, p):
    """The elbow angle where cond(J) = MAX_CONDITION (cond grows monotonically as q2 -> 0)."""
    return brentq(lambda a: fn.condition_number([0.3, a], p) - MAX_CONDITION, 1e-9, 0.5)


def test_singular_elbow_raises_naming_condition_and_angle(functions):
    """Straight (q2 = 0) and folded (q2 = pi) arms, exactly and nearly, raise
    SingularConfiguration naming cond(J), the threshold and q2; the threshold is where the
    docstring puts it (|q2| = 6.1e-4 rad for the course's arm)."""
    fn = functions["elbow"]
    p = DoublePendulumParams.course().as_array()
    for q2 in (0.0, 1e-9, -1e-7, np.pi, np.pi - 1e-7, 5e-4):
        with pytest.raises(
            SingularConfiguration,
            match=r"cond\(J\) = .* exceeds "
            r"`max_condition` = 8\.19e\+03 \(joint angle q2 = ",
        ) as info:
            fn.cartesian_terms([0.3, q2], [0.1, 0.2], p)
        assert info.value.condition > MAX_CONDITION
        assert info.value.angle_name == "q2"
        assert info.value.angle == pytest.approx(q2, abs=1e-15)
        assert isinstance(info.value, ValueError)
        assert fn.condition_number([0.3, q2], p) > MAX_CONDITION  # the status-style check
    edge = _elbow_angle_at_threshold(fn, p)
    assert edge == pytest.approx(6.1e-4, rel=1e-2)
    with pytest.raises(SingularConfiguration):
        fn.cartesian_terms([0.3, 0.99 * edge], [0.0, 0.0], p)
    fn.cartesian_terms([0.3, 1.01 * edge], [0.0, 0.0], p)  # accepted
    # a caller may accept worse conditioning explicitly
    fn.cartesian_terms([0.3, 0.5 * edge], [0.0, 0.0], p, max_condition=4 * MAX_CONDITION)


def test_accepted_near_singular_states_lose_at_most_cond_squared_eps(functions):
    """Just inside the threshold the Cartesian form is finite and the torque identity holds to
    the ``cond(J)^2 eps`` the threshold is built on, not worse: no silent blow-up."""
    fn = functions["elbow"]
    rng = np.random.default_rng(16_4_7)
    p = DoublePendulumParams.course().as_array()
    edge = _elbow_angle_at_threshold(fn, p)
    for _ in range(20):
        q = np.array(
            [rng.uniform(-np.pi, np.pi), rng.choice([-1, 1]) * edge * rng.uniform(1.01, 3)]
        )
        qd, qdd = rng.normal(0.0, 2.0, 2), rng.normal(0.0, 5.0, 2)
        ct = fn.cartesian_terms(q, qd, p)
        assert np.all(np.isfinite(ct.mass)) and np.all(np.isfinite(ct.velocity))
        tau = joint_torque(fn, q, qd, qdd, p)
        tau_x = cartesian_torque(fn, elbow_kinematics, q, qd, qdd, p)
        rel = np.max(np.abs(tau_x - tau)) / np.max(np.abs(tau))
        assert rel <= 10 * ct.condition**2 * EPS, f"{rel:.2e} at cond(J) = {ct.condition:.3g}"


def test_straight_knee_is_singular_for_the_swing_foot(functions):
    """The swing foot's Cartesian form is refused with the knee straight, ``q3 - q2 = 0`` (the
    locked-knee phase), naming that angle; a bent knee is accepted."""
    fn = functions["swing_foot"]
    p = KneedParams.hsu_chen().as_array()
    for q in ([0.2, 0.2], [-0.3, -0.3 + 1e-7], [0.1, 0.1 + np.pi]):
        with pytest.raises(
            SingularConfiguration, match=r"joint angle q3 - q2 = .*knee is straight"
        ):
            fn.cartesian_terms(q, [0.0, 0.0], p)
    assert fn.cartesian_terms([0.2, -0.3], [0.0, 0.0], p).condition < 10.0


def test_invalid_input_names_the_argument(functions):
    fn = functions["elbow"]
    p = DoublePendulumParams.course().as_array()
    with pytest.raises(ValueError, match=r"`q` must have shape \(2,\)"):
        fn.cartesian_terms([0.1, 0.2, 0.3], [0.0, 0.0], p)
    with pytest.raises(ValueError, match="all entries of `qd` must be finite"):
        fn.cartesian_terms([0.1, 0.2], [np.nan, 0.0], p)
    with pytest.raises(ValueError, match=r"`p` must have shape \(13,\)"):
        fn.cartesian_terms([0.1, 0.2], [0.0, 0.0], p[:9])
    with pytest.raises(ValueError, match="`max_condition` must be > 1"):
        fn.cartesian_terms([0.1, 1.0], [0.0, 0.0], p, max_condition=1.0)
    with pytest.raises(TypeError, match="`model` must be a TaskSpaceModel"):
        CartesianFunctions(models.planar_elbow())


# ------------------------------------------------------------ the circle-tracking example
def test_circle_tracking_converges_as_the_gains_predict(functions):
    """Computed torque in Cartesian space makes the error obey ``e'' + 2 w e' + w^2 e = 0``
    (critically damped, ``w = omega_n``), so ``|e(t)| <= (|e0| + |e'0 + w e0| t) exp(-w t)``:
    the final error is below that bound, and the whole error history follows the closed form
    to the integrator's accuracy.  ``delta`` allows for integration error: DOP853's local
    error control at rtol 1e-10 on angles and rates of order 1 over a few hundred steps
    keeps the tip within 1e-8 m, and delta = 1e-7 m is ten times that, still 1/15 of the
    bound at t_final."""
    arm = functions["elbow"]
    p = DoublePendulumParams.course().as_array()
    circle = circle_script.Circle(center=(1.0, 0.6), radius=0.3, period=2.0)
    q0 = circle_script.elbow_inverse_kinematics(circle.center, p, elbow=1)
    w, t_final, delta = 10.0, 1.5, 1e-7
    run = circle_script.track_circle(
        arm,
        p,
        circle,
        natural_frequency=w,
        q0=q0,
        t_final=t_final,
        n_samples=151,
        rtol=1e-10,
        atol=1e-12,
    )
    assert run.status == circle_script.SUCCESS, run.message
    assert run.t[-1] == t_final
    e0 = run.e0
    assert np.linalg.norm(e0) == pytest.approx(circle.radius, rel=1e-12)  # starts off the path
    bound = circle_script.error_bound(run.t, e0, run.ed0, w)
    assert 15 * delta < bound[-1] < 1e-5 * np.linalg.norm(e0)
    err = np.linalg.norm(run.error, axis=1)
    assert err[-1] <= bound[-1] + delta
    assert np.all(err <= bound + delta)
    assert_allclose(
        run.error, circle_script.error_analytic(run.t, e0, run.ed0, w), rtol=0, atol=delta
    )


def test_circle_beyond_reach_stops_with_a_singular_status(functions):
    """A circle that leaves the workspace drives the arm straight: the run ends with status
    SINGULAR and the SingularConfiguration message, its samples finite and within the
    threshold, instead of blowing up or raising."""
    arm = functions["elbow"]
    p = DoublePendulumParams.course().as_array()
    far = circle_script.Circle(center=(1.5, 0.0), radius=0.8, period=2.0)
    q0 = circle_script.elbow_inverse_kinematics(far.center, p, elbow=1)
    run = circle_script.track_circle(
        arm, p, far, natural_frequency=4.0, q0=q0, t_final=4.0, n_samples=201, rtol=1e-8, atol=1e-10
    )
    assert run.status == circle_script.SINGULAR
    assert not run.success
    assert "cond(J)" in run.message and "q2" in run.message
    assert 0.5 < run.t[-1] < 4.0
    assert np.all(np.isfinite(run.q)) and np.all(np.isfinite(run.tau))
    assert np.all(run.condition <= MAX_CONDITION)
    assert run.condition[-1] > 0.1 * MAX_CONDITION  # it stopped near the singularity
