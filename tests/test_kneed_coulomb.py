"""The kneed walker with Coulomb joint friction (model ``kneed_coulomb``, issue 8 item 4).

Stick and slip are phases and events (walker/models/friction.py), so the checks are exact:

* with zero friction the stride is the kneed walker's (state, step time, Jacobian);
* the vector-field Jacobian is exact in stick and slip, unlocked and locked;
* between consecutive events, the energy lost is ``sum_j F_j |delta theta_j|`` (dry friction
  does the power ``-F |w|`` while slipping and none while stuck) to 1e-10;
* a stuck joint keeps ``w = 0`` with a holding torque within the friction and breaks free
  exactly when the torque reaches it;
* the stride map's exact Jacobian (variational equations, saltation at every friction event)
  agrees with central differences on a gait that sticks.

Measured on Hsu Chen's walker (DOP853, rtol = atol = 1e-11), the period-one gait followed
from the frictionless one: knee friction slows it (0.8370 m/s at 0, 0.8357 at 0.001,
0.8308 at 0.005, 0.8261 at 0.01 N m; from 0.012 N m the knee sticks for ~9 ms where its
rate reverses, and at 0.02 N m the bent knee trips before the first knee lock); ankle
friction slows it too (0.8314 m/s at 0.01, 0.7795 at 0.1 N m; at 1 N m the stance leg sticks
in the second step and the walker falls backward); hip friction speeds it up (0.8547 m/s at
0.01 N m), as the viscous hip damper does for the compass gait (tests/test_damping.py).
"""

from __future__ import annotations

import numpy as np
import pytest
from _fd import rhs_jacobian_fd
from _joint_torques import joint_torques
from numpy.testing import assert_allclose

from walker import StrideMap, find_fixed_point, simulate
from walker.models import friction as fr
from walker.models import get_model
from walker.models import kneed_coulomb as KC
from walker.params import KneedCoulombParams, KneedParams
from walker.scene import load_scene
from walker.status import Status

TIGHT = {"rtol": 1e-11, "atol": 1e-11}
SCENE = load_scene("gaits/kneed_hsu.toml")
X_GAIT = np.array(SCENE.reference["state"])
MODEL = get_model("kneed_coulomb")
# Joint rows in the unlocked coordinates (ankle, hip, knee).
S = np.array([[1.0, 0.0, 0.0], [-1.0, 1.0, 0.0], [0.0, -1.0, 1.0]])


def _params(**coulomb) -> KneedCoulombParams:
    return KneedCoulombParams.hsu_chen(**coulomb)


def _speed(fp) -> float:
    """Walking speed [m/s]: step length 2 L sin(inter-leg angle / 2) over the step time
    (point feet, leg length L = 1 m)."""
    x = fp.state
    return 2.0 * np.sin(0.5 * (x[0] - x[1])) / fp.step_time


def test_parameter_layout():
    names = KneedCoulombParams.names()
    assert names[: len(KneedParams.names())] == KneedParams.names()
    assert names.index("coulomb_ankle") == KC.I_COULOMB
    assert names[KC.I_COULOMB :] == ("coulomb_ankle", "coulomb_hip", "coulomb_knee")
    with pytest.raises(ValueError, match=r"`coulomb_knee` must be >= 0 \[N m\]"):
        _params(coulomb_knee=-0.1)


def test_phase_names_round_trip():
    assert len(MODEL.phase_names) == 27 + 9
    assert MODEL.system.directions.shape == (36, len(MODEL.guard_names))
    for phase in range(36):
        base, modes = KC.modes_of(phase)
        assert KC.phase_of(base, **modes) == phase
    assert KC.phase_of("unlocked", knee="stick") == 18
    with pytest.raises(ValueError, match="mode of `hip`"):
        KC.phase_of("locked", hip="sticky")
    with pytest.raises(ValueError, match="joint modes must be given for"):
        KC.phase_of("locked", knee="stick")


def test_zero_friction_is_the_kneed_walker():
    """Without dry friction the friction guards never fire: the same events, and the
    accelerations agree to round-off (another elimination of the same matrices)."""
    p = KneedParams.hsu_chen()
    z = get_model("kneed").project(X_GAIT, p)
    a = StrideMap("kneed", p, **TIGHT)(z, jacobian=True)
    b = StrideMap("kneed_coulomb", _params(), **TIGHT)(z, jacobian=True)
    assert a.success and b.success
    assert_allclose(b.z, a.z, rtol=0, atol=5e-11)
    assert_allclose(b.step_time, a.step_time, rtol=0, atol=1e-12)
    assert_allclose(b.jac, a.jac, rtol=0, atol=5e-9)


@pytest.mark.parametrize(
    "base,modes",
    [
        ("unlocked", {}),
        ("unlocked", {"ankle": "slip-", "knee": "stick"}),
        ("unlocked", {"ankle": "stick", "hip": "stick", "knee": "slip-"}),
        ("locked", {"ankle": "slip-"}),
        ("locked", {"ankle": "stick", "hip": "slip-"}),
    ],
)
def test_jac_matches_differences(base, modes):
    rng = np.random.default_rng(5)
    p = _params(coulomb_ankle=0.3, coulomb_hip=0.02, coulomb_knee=0.05)
    pa = p.as_array()
    pa = np.concatenate([pa[:14], [0.01, 0.02, 0.03], pa[17:]])  # viscous dampers on too
    phase = KC.phase_of(base, **modes)
    for _ in range(5):
        x = X_GAIT + rng.normal(scale=0.2, size=6)
        if base == "locked":
            x[2], x[5] = x[1], x[4]
        J = MODEL.jac(phase, x, pa)
        fd = rhs_jacobian_fd(MODEL, phase, x, pa)
        if base == "locked":
            fd[:, 2] = fd[:, 5] = 0.0  # the locked model ignores q3, qd3
        assert_allclose(J, fd, rtol=1e-6, atol=1e-6)


def _joint_angles(x, base):
    q = np.array([x[0], x[1], x[2] if base == "unlocked" else x[1]])
    return S @ q


def test_energy_lost_between_events_is_the_coulomb_work():
    """Three strides with all three joints rubbing (the knee sticks once per step)."""
    F = np.array([0.05, 0.004, 0.012])
    p = _params(coulomb_ankle=F[0], coulomb_hip=F[1], coulomb_knee=F[2])
    sol = simulate("kneed_coulomb", p, X_GAIT, n_strides=3, output="events", **TIGHT)
    assert sol.status == Status.COMPLETED
    ev = sol.events
    assert "knee_stick_breaks" in {MODEL.guard_names[g] for g in ev.guard}
    starts = [X_GAIT] + list(ev.x_post[:-1])
    phases = [MODEL.start_phase(X_GAIT, p)] + list(ev.phase_after[:-1])
    n_checked = 0
    for x0, x1, phase in zip(starts, ev.x_pre, phases, strict=True):
        base, _ = KC.modes_of(int(phase))
        dtheta = np.abs(_joint_angles(x1, base) - _joint_angles(x0, base))
        if base == "locked":
            dtheta[2] = 0.0
        e0 = sum(MODEL.energy(x0, p))
        e1 = sum(MODEL.energy(x1, p))
        assert_allclose(e0 - e1, F @ dtheta, rtol=0, atol=1e-10 * max(1.0, abs(e0)))
        n_checked += 1
    assert n_checked == len(ev.t) >= 12


def test_knee_sticks_while_the_torque_is_within_the_friction():
    F_knee = 0.012
    p = _params(coulomb_knee=F_knee)
    pa = p.as_array()
    events = simulate("kneed_coulomb", p, X_GAIT, output="events", **TIGHT).events
    names = [MODEL.guard_names[g] for g in events.guard]
    i_stick = names.index("knee_slip_stops")
    i_break = names.index("knee_stick_breaks")
    assert i_break == i_stick + 1
    stuck_phase = int(events.phase_after[i_stick])
    assert KC.modes_of(stuck_phase)[1]["knee"] == "stick"
    assert KC.modes_of(int(events.phase_after[i_break]))[1]["knee"] == "slip+"
    t0, t1 = events.t[i_stick], events.t[i_break]
    assert 5e-3 < t1 - t0 < 2e-2
    times = np.linspace(t0, t1, 12)[1:-1]
    sol = simulate("kneed_coulomb", p, X_GAIT, output="samples", sample_times=times, **TIGHT)
    for x, phase in zip(sol.samples.x, sol.samples.phase, strict=True):
        assert phase == stuck_phase
        assert abs(x[5] - x[4]) < 1e-12  # w_knee = 0
        assert abs(joint_torques("kneed_coulomb", stuck_phase, x, pa)[2]) < F_knee
    # The break: the holding torque reaches the friction exactly.
    lam = joint_torques("kneed_coulomb", stuck_phase, events.x_pre[i_break], pa)[2]
    assert_allclose(abs(lam), F_knee, rtol=1e-8, atol=0)


def test_start_phase_follows_the_friction():
    """Just after heel strike the new swing knee is straight and at rest: it sticks when the
    friction can hold it, else it flexes (slips negative)."""
    x = X_GAIT.copy()
    free = KC.modes_of(MODEL.start_phase(x, _params()))
    held = KC.modes_of(MODEL.start_phase(x, _params(coulomb_knee=10.0)))
    assert free == ("unlocked", {"ankle": "slip-", "hip": "slip+", "knee": "slip-"})
    assert held == ("unlocked", {"ankle": "slip-", "hip": "slip+", "knee": "stick"})


@pytest.mark.regression_pin
def test_knee_friction_slows_the_gait():
    """REGRESSION PIN: the speeds 0.83701, 0.83082, 0.82612 m/s (knee friction 0, 0.005, 0.01 N m)
    are walker's own (module docstring); the monotone fall is the check.
    """
    z = MODEL.project(X_GAIT, None)
    speeds = []
    for F in (0.0, 0.005, 0.01):
        P = StrideMap("kneed_coulomb", _params(coulomb_knee=F), **TIGHT)
        fp = find_fixed_point(P, z)
        assert fp.success and fp.stable
        z = fp.section
        speeds.append(_speed(fp))
    assert np.all(np.diff(speeds) < 0)
    assert_allclose(speeds, [0.83701, 0.83082, 0.82612], rtol=0, atol=2e-5)


def test_stride_jacobian_through_stick_and_slip():
    p = _params(coulomb_ankle=0.05, coulomb_knee=0.012)
    P = StrideMap("kneed_coulomb", p, **TIGHT)
    fp = find_fixed_point(P, MODEL.project(X_GAIT, None))
    assert fp.success
    r = P(fp.section, jacobian=True)
    h = 1e-6
    fd = np.column_stack(
        [(P(fp.section + h * e).z - P(fp.section - h * e).z) / (2 * h) for e in np.eye(3)]
    )
    assert_allclose(r.jac, fd, rtol=0, atol=1e-6)


def test_large_ankle_friction_stops_the_walker_as_an_outcome():
    """The stance leg sticks in the second step; the walker then rocks back over its stance
    foot and falls backward -- the same outcome and time at every tolerance (before the
    MIN_STEP rule, the locked swing leg passing through the stance leg was taken for a
    zero-length heel strike at some tolerances: round-off chose the sign of the step)."""
    p = _params(coulomb_ankle=1.0)
    times = []
    for rtol in (1e-9, 1e-10, 1e-11, 1e-12):
        sol = simulate("kneed_coulomb", p, X_GAIT, n_strides=3, output="events", t_max=5, rtol=rtol)
        assert sol.status == Status.FELL_BACKWARD
        assert sol.n_strides == 1
        names = [MODEL.guard_names[g] for g in sol.events.guard]
        assert "ankle_slip_stops" in names and "ankle_stick_breaks" in names
        times.append(sol.t)
    assert_allclose(times, times[-1], rtol=0, atol=1e-8)


@pytest.mark.parametrize("name", ["compass", "kneed", "kneed_coulomb"])
def test_swing_leg_through_the_stance_leg_is_not_a_step(name):
    """Legs coinciding: foot height zero, step length round-off; the reset must ignore it."""
    model = get_model(name)
    if name == "compass":
        p = get_model(name).params_class.goswami().as_array()
        x = np.array([0.1, 0.1 + 1e-17, 0.5, 1.0])
        phase = 0
    else:
        p = model.params_class.hsu_chen().as_array()
        x = np.array([0.1, 0.1, 0.1, -0.5, 0.3, 0.3])
        phase = 1 if name == "kneed" else KC.phase_of("locked", ankle="slip-")
    for tiny in (-4e-16, 0.0, 4e-16):
        y = x.copy()
        y[1] += tiny
        if name != "compass":
            y[2] = y[1]
        # the reset the integrator runs (whatever its backend)
        action, *_ = model.apply_reset(phase, 1 if name != "compass" else 0, y, p)
        assert action == 0  # EVENT_IGNORE


def test_stuck_knee_trips():
    sol = simulate("kneed_coulomb", _params(coulomb_knee=0.02), X_GAIT, output="events")
    assert sol.status == Status.TRIPPED
    assert sol.n_strides == 0


def test_friction_modes_layer_is_shared():
    """The model's guard layout is the friction layer's: two guards per joint."""
    assert MODEL.guard_names[4:] == tuple(
        f"{j}_{k}" for j in KC.JOINTS for k in ("slip_stops", "stick_breaks")
    )
    code = KC.phase_of("unlocked", ankle="stick", hip="slip-", knee="slip+")
    assert list(MODEL.system.directions[code, 4:]) == fr.directions(code, 3)


def test_energy_plot_marks_impacts_not_mode_switches():
    """The gallery's energy plot labels the energy jump at impacts; at a friction event
    the state is continuous, so it is not marked."""
    from walker.plotting.gallery import _impact_times

    sol = simulate("kneed_coulomb", _params(coulomb_knee=0.012), X_GAIT, output="events", **TIGHT)
    names = [MODEL.guard_names[g] for g in sol.events.guard]
    expected = [t for t, n in zip(sol.events.t, names, strict=True) if n in IMPACTS]
    assert {"knee_slip_stops", "knee_stick_breaks"} <= set(names)
    assert_allclose(_impact_times(sol.events, 3), expected, rtol=0, atol=0)


IMPACTS = ("knee_lock", "swing_foot_contact")
