"""Joint friction (viscous and Coulomb) at the actuated joints of the three-link and five-link
walkers (walker.models.three_link, walker.models.five_link): the frictionless limit, the
energy balance per segment, a gait with friction, a stuck hip, Newton–Euler torques and
bad parameters.

Measured (DOP853, rtol = atol = 1e-12, from the shipped scenes' states):

* zero friction: in every slip phase the compiled vector field solves ``D qdd = B u - h``
  (the generated kernels and the compiled controller's torques) to 1e-12.
* Coulomb friction only (three-link ``coulomb_hip = 2``; five-link ``coulomb_hip =
  coulomb_knee = 2`` N m), three strides: per segment between events ``E(end) - E(start) =
  W - sum_slip F |delta theta_j|`` to <= 1e-12 (three-link, 6 segments) and <= 3e-10
  (five-link, 27 segments) of the segment's actuator work ``W``; the five-link knees stick
  and break loose in every stride.
* ``damping_hip = 0.5`` N m s/rad, ``coulomb_hip = 1`` N m: the three-link closed loop has a
  stable period-one gait near the frictionless one (Newton from the scene's state, 3
  iterations; step time 1.0919 -> 0.9027 s; multipliers 0.5222 -> 0.5636 and 5.1e-3, the
  rest < 3e-5; exact and finite-difference Jacobians agree to 1e-8); over its stride the
  actuators' work 17.388 J = impact loss 14.886 J + Coulomb 1.626 J + viscous 0.876 J to
  6e-13 relative.
* a hip at rest with ``coulomb_hip = 50`` N m and the controller on starts stuck (holding
  torque 1.13 N m) and stays stuck for 0.438 s (|w| <= 4e-15) until its holding torque
  reaches 50 N m, through two mode changes of the other hip; with the controller off
  (passive) and 20 N m the stance hip sticks for 0.485 s (holding torque 1.97 N m at first).
* Newton–Euler inverse dynamics along strides with friction (stick phases included)
  reproduces ``u + joint friction torque`` to 1e-10 N m.
"""

from functools import cache

import numpy as np
import pytest
from _chains import (
    assert_five_link_torques,
    assert_three_link_torques,
    five_link_chains,
    three_link_chains,
)
from _joint_torques import joint_torques
from numpy.testing import assert_allclose

from walker.analysis.fixedpoint import find_fixed_point
from walker.models import five_link as FL
from walker.models import friction as fr
from walker.models import get_model, hzd
from walker.models import three_link as TL
from walker.params import FiveLinkParams, ThreeLinkParams
from walker.scene import load_scene
from walker.simulation.stride import StrideMap, simulate
from walker.status import Status

TIGHT = dict(rtol=1e-12, atol=1e-12)
RNG = np.random.default_rng(20260412)
MODELS = {"three_link": TL, "five_link": FL}
SCENES = {"three_link": "gaits/three_link_grizzle.toml", "five_link": "gaits/five_link_hzd.toml"}
COULOMB_ONLY = {
    "three_link": {"coulomb_hip": 2.0},
    "five_link": {"coulomb_hip": 2.0, "coulomb_knee": 2.0},
}
SMALL_FRICTION = {"damping_hip": 0.5, "coulomb_hip": 1.0}


@cache
def _scene(name):
    return load_scene(SCENES[name])


def _dry(name, params):
    """Dry-friction magnitude of each joint (the model's ``JOINTS`` order) [N m]."""
    if name == "three_link":
        return np.array([params.coulomb_hip] * 2)
    return np.array([params.coulomb_hip] * 2 + [params.coulomb_knee] * 2)


def _energy(module, x, p):
    kinetic, potential = get_model(module.__name__.rsplit(".", 1)[1]).energy(x, p)
    return kinetic + potential


# ------------------------------------------------------------------------------- layout
@pytest.mark.parametrize("name", ["three_link", "five_link"])
def test_layout_and_phase_table(name):
    M = MODELS[name]
    cls = _scene(name).params.__class__
    names = cls.names()
    # friction appended after the controller block: the block's offset and layout unchanged
    assert names[M.CONTROL_OFFSET] == "controller"
    assert names[M.I_DAMPING_HIP] == "damping_hip"
    assert names[M.I_COULOMB_HIP] == "coulomb_hip"
    if name == "five_link":
        assert names[M.I_DAMPING_KNEE] == "damping_knee"
        assert names[M.I_COULOMB_KNEE] == "coulomb_knee"
    # before the friction: the Bezier block (three_link: then the finite-time block)
    assert names[M.I_DAMPING_HIP - 1].startswith("poly_" if name == "three_link" else "bezier_")
    # joints are the actuated ones: S = B^T; 3**n_joints phases, 2 more guards per joint
    assert_allclose(M.S_MATRIX, M.B_MATRIX.T, rtol=0, atol=0)
    assert M.N_CODES == fr.N_MODES**M.N_JOINTS == len(M.PHASE_NAMES)
    assert len(M.GUARD_NAMES) == M.N_BASE_GUARDS + 2 * M.N_JOINTS
    assert M.DIRECTIONS.shape == (M.N_CODES, len(M.GUARD_NAMES))
    for code in range(M.N_CODES):
        assert M.phase_of(**M.modes_of(code)) == code
        assert M.PHASE_NAMES[code] == f"stance {fr.mode_names(code, M.JOINTS)}"
    stuck = M.phase_of(hip_swing="stick")
    assert M.modes_of(stuck)["hip_swing"] == "stick"
    with pytest.raises(ValueError, match=r"^mode of `hip_swing` must be one of"):
        M.phase_of(hip_swing="stuck")


# ------------------------------------------------------------------ the frictionless limit
@pytest.mark.parametrize("name", ["three_link", "five_link"])
def test_zero_friction_vector_field_is_the_frictionless_closed_loop(name):
    """At random states, in every slip phase: ``D qdd = B u - h`` (1e-12, with ``D``, ``h``
    the generated kernels and ``u`` the compiled controller's torques), the rates integrate
    to the coordinates and the actuator power is ``u . (B^T qd)``."""
    M = MODELS[name]
    model = get_model(name)
    scene = _scene(name)
    p = scene.params.as_array()
    n = M.N_Q
    for _ in range(5):
        x = scene.state + np.r_[RNG.normal(0.0, 0.1, 2 * n), 0.0, 0.0]
        q, qd = x[:n], x[n : 2 * n]
        u = model.torques(x, p)
        D = model.kernel("mass_matrix", p, q)
        force = M.B_MATRIX @ u - model.kernel("bias", p, q, qd)
        slip_codes = [c for c in range(M.N_CODES) if "stick" not in M.modes_of(c).values()]
        assert len(slip_codes) == 2**M.N_JOINTS
        for code in slip_codes:
            dx = model.rhs(code, x, p)
            assert_allclose(dx[:n], qd, rtol=0, atol=0)
            scale = np.abs(force).max()
            assert_allclose(D @ dx[n : 2 * n], force, rtol=1e-12, atol=1e-12 * scale)
            assert_allclose(dx[2 * n], u @ (M.S_MATRIX @ qd), rtol=1e-12, atol=1e-12)
        tau = joint_torques(name, model.start_phase(x, p), x, p)
        assert_allclose(tau, 0.0, rtol=0, atol=1e-9 * np.abs(force).max())


# ------------------------------------------------------------------------ energy balance
def _segments(name, params, x0, n_strides):
    """(x_start, x_end, phase) of each segment between events of a closed-loop run."""
    sol = simulate(name, params, x0, n_strides=n_strides, output="events", **TIGHT)
    assert sol.status == Status.COMPLETED, sol.message
    ev = sol.events
    starts = [np.asarray(x0, dtype=float)] + list(ev.x_post[:-1])
    return list(zip(starts, ev.x_pre, ev.phase_before, strict=True)), sol


@pytest.mark.parametrize("name", ["three_link", "five_link"])
def test_coulomb_friction_dissipates_f_times_joint_travel(name):
    """Coulomb friction only: on every segment between events, E(end) - E(start) = actuator
    work - sum over slipping joints of F_j |delta theta_j| (1e-9 of the work)."""
    M = MODELS[name]
    scene = _scene(name)
    params = scene.params.replace(**COULOMB_ONLY[name])
    p = params.as_array()
    F = _dry(name, params)
    n = M.N_Q
    segments, sol = _segments(name, params, scene.state, 3)
    friction_events = [g for g in sol.events.guard if g >= M.N_BASE_GUARDS]
    assert len(friction_events) >= 3  # the joints reverse (and for five_link, stick)
    if name == "five_link":
        assert any("stick" in M.modes_of(int(ph)).values() for _, _, ph in segments)
    for xs, xe, phase in segments:
        modes = M.modes_of(int(phase))
        travel = M.S_MATRIX @ (xe[:n] - xs[:n])
        dissipated = sum(
            F[j] * abs(travel[j]) for j, joint in enumerate(M.JOINTS) if modes[joint] != "stick"
        )
        work = xe[2 * n] - xs[2 * n]
        change = _energy(M, xe, p) - _energy(M, xs, p)
        assert_allclose(change, work - dissipated, rtol=0, atol=1e-9 * abs(work))
        for j, joint in enumerate(M.JOINTS):
            if modes[joint] == "stick":
                assert abs(travel[j]) < 1e-12


# ------------------------------------------------------------------ a gait with friction
@cache
def _friction_gait():
    params = _scene("three_link").params.replace(**SMALL_FRICTION)
    S = StrideMap("three_link", params, **TIGHT)
    return params, S, find_fixed_point(S, S.project(_scene("three_link").state))


def test_small_friction_keeps_a_stable_period_one_gait():
    params, S, fp = _friction_gait()
    assert fp.success, fp.message
    assert fp.stable and np.all(np.abs(fp.multipliers) < 1.0)
    # the gait moved: friction is not negligible
    frictionless = S.project(_scene("three_link").state)
    assert np.max(np.abs(fp.section - frictionless)) > 1e-2
    # the exact Jacobian (variational equations, saltation at the friction events) agrees
    # with central differences of the stride map
    fd = find_fixed_point(S, fp.section, jacobian="fd")
    assert fd.success
    assert_allclose(fd.section, fp.section, rtol=0, atol=1e-10)
    assert_allclose(np.abs(fd.multipliers[:2]), np.abs(fp.multipliers[:2]), rtol=0, atol=1e-6)
    # the closed loop from the scene's (frictionless) gait converges to it
    sol = simulate("three_link", params, _scene("three_link").state, n_strides=30, **TIGHT)
    assert sol.status == Status.COMPLETED
    assert_allclose(S.project(sol.x), fp.section, rtol=0, atol=1e-6)


def test_actuator_work_pays_impact_and_friction_on_the_cycle():
    """On the periodic gait (level ground): actuator work per stride = impact loss +
    Coulomb dissipation (F |delta theta| per slip segment) + viscous dissipation
    (F_v int |w|^2 dt by 30-point Gauss–Legendre per segment) to 1e-9 relative."""
    params, _, fp = _friction_gait()
    p = params.as_array()
    segments, sol = _segments("three_link", params, fp.state, 1)
    ev = sol.events
    assert ev.guard[-1] == 0 and len(ev.t) >= 2  # friction events before the heel strike
    nodes, weights = np.polynomial.legendre.leggauss(30)
    bounds = np.r_[0.0, ev.t]
    coulomb = viscous = 0.0
    for (xs, xe, phase), a, b in zip(segments, bounds[:-1], bounds[1:], strict=True):
        modes = TL.modes_of(int(phase))
        travel = TL.S_MATRIX @ (xe[:3] - xs[:3])
        coulomb += sum(
            params.coulomb_hip * abs(travel[j])
            for j, joint in enumerate(TL.JOINTS)
            if modes[joint] != "stick"
        )
        times = 0.5 * (b - a) * nodes + 0.5 * (a + b)
        samples = simulate(
            "three_link", params, fp.state, output="samples", sample_times=times, **TIGHT
        ).samples
        w = samples.x[:, 3:6] @ TL.S_MATRIX.T
        viscous += 0.5 * (b - a) * np.sum(weights * params.damping_hip * np.sum(w**2, axis=1))
    impact_loss = _energy(TL, ev.x_pre[-1], p) - _energy(TL, ev.x_post[-1], p)
    work = sol.x[6]
    assert coulomb > 0.0 and viscous > 0.0 and impact_loss > 1.0
    assert_allclose(work, impact_loss + coulomb + viscous, rtol=1e-9, atol=0)


# ---------------------------------------------------------------------------- stick
STUCK_CASES = [
    # (controller, coulomb_hip [N m], joint at rest)
    (2.0, 50.0, "hip_swing"),
    (0.0, 20.0, "hip_stance"),
]


def _stuck_state(joint):
    """The scene's state with ``joint`` at rest (its leg moving with the torso)."""
    x = _scene("three_link").state.copy()
    x[3 + TL.JOINTS.index(joint)] = x[5]
    return x


@pytest.mark.parametrize(("controller", "coulomb", "joint"), STUCK_CASES)
def test_hip_at_rest_sticks_until_its_holding_torque_reaches_f(controller, coulomb, joint):
    params = _scene("three_link").params.replace(controller=controller, coulomb_hip=coulomb)
    p = params.as_array()
    j = TL.JOINTS.index(joint)
    x0 = _stuck_state(joint)
    phase0 = get_model("three_link").start_phase(x0, p)
    assert TL.modes_of(phase0)[joint] == "stick"
    holding = joint_torques("three_link", phase0, x0, p)[j]
    assert 0.0 < abs(holding) < coulomb
    sol = simulate("three_link", params, x0, output="events", **TIGHT)
    ev = sol.events
    # the first event that takes the joint out of stick is its own stick_breaks
    leaves = next(
        i for i, ph in enumerate(ev.phase_after) if TL.modes_of(int(ph))[joint] != "stick"
    )
    assert all(TL.modes_of(int(ph))[joint] == "stick" for ph in ev.phase_before[: leaves + 1])
    assert TL.GUARD_NAMES[ev.guard[leaves]] == f"{joint}_stick_breaks"
    assert_allclose(
        abs(joint_torques("three_link", int(ev.phase_before[leaves]), ev.x_pre[leaves], p)[j]),
        coulomb,
        rtol=0,
        atol=1e-8,
    )
    t_break = ev.t[leaves]
    assert t_break > 0.1
    # w stays zero while stuck
    times = np.linspace(0.0, t_break, 41)
    samples = simulate(
        "three_link", params, x0, output="samples", sample_times=times, **TIGHT
    ).samples
    w = samples.x[:, 3:6] @ TL.S_MATRIX[j]
    assert_allclose(w, 0.0, rtol=0, atol=1e-12)
    # and it slips afterwards, against the direction its holding torque resisted
    after = TL.modes_of(int(ev.phase_after[leaves]))[joint]
    assert after == (
        "slip-"
        if joint_torques("three_link", int(ev.phase_before[leaves]), ev.x_pre[leaves], p)[j] > 0
        else "slip+"
    )


# --------------------------------------------------------------------------- Newton–Euler
def _check_three_link_newton_euler(P, samples):
    """tests/test_actuated.py::test_newton_euler_reproduces_applied_torques with the joint
    torques u + friction: swing hip tau_2, torso joint -tau_1 - tau_2, stance foot 0."""
    p = P.as_array()
    chains = three_link_chains(P)
    gravity = (0.0, -P.g)
    for x, phase in zip(samples.x, samples.phase, strict=True):
        model = get_model("three_link")
        dx = model.rhs(int(phase), x, p)
        tau = model.torques(x, p) + joint_torques("three_link", int(phase), x, p)
        assert_three_link_torques(chains, x, dx, tau, gravity)


def test_newton_euler_three_link_gait_with_friction():
    params, _, fp = _friction_gait()
    times = np.linspace(0.0, fp.step_time * 0.999, 13)
    x0 = fp.state + np.r_[0, 0, 0.02, 0.1, 0, 0, 0, 0]
    samples = simulate(
        "three_link", params, x0, output="samples", sample_times=times, **TIGHT
    ).samples
    assert len(set(samples.phase)) >= 2  # slip+ and slip- of a hip
    _check_three_link_newton_euler(params, samples)


def test_newton_euler_three_link_stuck_hip():
    controller, coulomb, joint = STUCK_CASES[0]
    params = _scene("three_link").params.replace(
        controller=controller, coulomb_hip=coulomb, damping_hip=0.3
    )
    times = np.linspace(0.0, 0.6, 13)
    samples = simulate(
        "three_link", params, _stuck_state(joint), output="samples", sample_times=times, **TIGHT
    ).samples
    stuck = [TL.modes_of(int(ph))[joint] == "stick" for ph in samples.phase]
    assert any(stuck) and not all(stuck)
    _check_three_link_newton_euler(params, samples)


def test_newton_euler_five_link_with_friction():
    """As tests/test_five_link.py::test_newton_euler_reproduces_applied_torques, with joint
    torques u + friction (the knees stick on this stride): swing knee tau_4, swing hip
    tau_2, torso joint -tau_1 - tau_2, stance knee -tau_3, stance foot 0 (1e-10 N m)."""
    scene = _scene("five_link")
    P = scene.params.replace(damping_hip=0.5, damping_knee=0.3, **COULOMB_ONLY["five_link"])
    p = P.as_array()
    step_time = simulate("five_link", P, scene.state, **TIGHT).t
    times = np.linspace(0.0, 0.999 * step_time, 17)
    samples = simulate(
        "five_link", P, scene.state, output="samples", sample_times=times, **TIGHT
    ).samples
    assert any("stick" in FL.modes_of(int(ph)).values() for ph in samples.phase)
    chains = five_link_chains(P)
    gravity = (0.0, -P.g)
    for x, phase in zip(samples.x, samples.phase, strict=True):
        model = get_model("five_link")
        dx = model.rhs(int(phase), x, p)
        tau = model.torques(x, p) + joint_torques("five_link", int(phase), x, p)
        assert_five_link_torques(chains, x, dx, tau, gravity)


# ------------------------------------------------------------------------------ bad input
# every joint damper and friction of the actuated walkers, below its bound (>= 0); here
# also through from_dict
BAD_FRICTION = [
    (cls, name, -0.1, rf"`{name}` must be >= 0 \[")
    for cls in (ThreeLinkParams, FiveLinkParams)
    for name in cls.names()
    if name.startswith(("damping_", "coulomb_"))
]


@pytest.mark.parametrize(("cls", "field", "value", "message"), BAD_FRICTION)
def test_negative_friction_raises_naming_the_argument(cls, field, value, message):
    preset = cls.grizzle() if cls is ThreeLinkParams else cls.rabbit()
    with pytest.raises(ValueError, match="^" + message):
        preset.replace(**{field: value})
    with pytest.raises(ValueError, match="^" + message):
        cls.from_dict({**preset.to_dict(), field: value})


def test_presets_are_frictionless_and_accept_friction():
    for preset in (ThreeLinkParams.grizzle(), FiveLinkParams.rabbit()):
        names = [n for n in preset.names() if n.startswith(("damping_", "coulomb_"))]
        assert names and all(getattr(preset, n) == 0.0 for n in names)
    # the HZD design (make_invariant) does not involve the friction: it is kept as given
    rough = ThreeLinkParams.grizzle(coulomb_hip=1.0, damping_hip=0.5)
    smooth = ThreeLinkParams.grizzle()
    assert rough.coulomb_hip == 1.0 and rough.damping_hip == 0.5
    assert rough.replace(coulomb_hip=0.0, damping_hip=0.0) == smooth
    assert FiveLinkParams.rabbit(coulomb_knee=2.0).coulomb_knee == 2.0


@pytest.mark.parametrize(
    ("cls", "field", "value"),
    [
        (ThreeLinkParams, "coulomb_hip", 1.0),
        (ThreeLinkParams, "damping_hip", 0.5),
        (FiveLinkParams, "damping_knee", 0.2),
        (FiveLinkParams, "coulomb_knee", 0.2),
    ],
)
def test_hzd_maps_refuse_joint_friction(cls, field, value):
    params = _scene("three_link" if cls is ThreeLinkParams else "five_link").params
    params = params.replace(**{field: value})
    message = rf"^`{field}` must be 0 \[N m( s/rad)?\] for the hybrid-zero-dynamics map"
    with pytest.raises(ValueError, match=message):
        hzd.restricted_map(params, -1.0)
    with pytest.raises(ValueError, match=message):
        hzd.restricted_fixed_point(params)
    with pytest.raises(ValueError, match=message):
        hzd.zero_dynamics_accel(params, params.theta_plus, -1.0)
    # the impact and the geometry do not involve the friction
    frictionless = params.replace(**{field: 0.0})
    assert_allclose(
        hzd.impact_momentum_ratio(params), hzd.impact_momentum_ratio(frictionless), rtol=0, atol=0
    )
