"""The compass gait with Coulomb friction at the stance ankle and the hip
(walker.models.compass_coulomb, on walker/models/friction.py): the frictionless limit, stick/slip
events, energy balance, gaits with friction, failure.

The model was first written with a closed-form stick phase for the hip alone; the step time
of the gait with 0.01 N m of hip friction pinned below (0.7339066619 s) was measured with
that implementation and is reproduced by the shared friction layer to 1e-9."""

import numpy as np
import pytest
from _fd import rhs_jacobian_fd
from _joint_torques import joint_torques
from numpy.testing import assert_allclose

from walker import StrideMap, simulate
from walker.analysis.fixedpoint import find_fixed_point
from walker.models import compass_coulomb as M
from walker.models import get_model
from walker.params import CompassCoulombParams, CompassParams
from walker.status import Status

# Goswami fixed point at 3 degrees as published by Spong, Holm, Lee 2007 (see
# CompassParams.goswami); the section point (q_stance, qd_stance, qd_swing).
SPONG_X = np.array([0.2187, -0.3234, -1.0918, -0.3772])
SPONG_Z = SPONG_X[[0, 2, 3]]
TIGHT = dict(rtol=1e-12, atol=1e-12)
# Constructed states (point feet, Goswami masses, 3 degree slope), F_s = 5 N m:
# legs locked, swing foot clear of the slope and ahead; the hip torque needed to stick is
# -3.41 N m and grows past -5 N m after 0.173 s.
STICK_X = np.array([-0.1, -0.2, -1.0, -1.0])
# the same configuration with the hip slipping forward (w = +0.1 rad/s).
SLIP_X = np.array([-0.1, -0.2, -1.0, -0.9])


def _params(coulomb_hip, coulomb_ankle=0.0):
    return CompassCoulombParams.goswami(coulomb_hip=coulomb_hip, coulomb_ankle=coulomb_ankle)


HIP_STICK = M.phase_of(ankle="slip-", hip="stick")


def _total_energy(model, x, p):
    kin, pot = model.energies(x, p)
    return kin + pot


def test_params_extend_compass_params():
    assert CompassCoulombParams.names() == CompassParams.names() + (
        "coulomb_ankle",
        "coulomb_hip",
    )
    p = _params(0.25, 0.5)
    n = CompassParams.n_params()
    assert_allclose(p.as_array()[:n], CompassParams.goswami().as_array(), rtol=0, atol=0)
    # the compiled phase functions read the frictions there
    assert list(p.as_array()[M.I_COULOMB : M.I_COULOMB + 2]) == [0.5, 0.25]
    assert p.coulomb_hip == 0.25
    assert CompassCoulombParams.units()["coulomb_hip"] == "N m"
    with pytest.raises(ValueError, match=r"^`coulomb_hip` must be >= 0 \[N m\], got -0.1"):
        p.replace(coulomb_hip=-0.1)
    with pytest.raises(ValueError, match=r"^`foot_radius` must be < leg length"):
        p.replace(foot_radius=1.5)
    with pytest.raises(ValueError, match=r"^`coulomb_ankle` must be >= 0 \[N m\]"):
        p.replace(coulomb_ankle=-1.0)
    names = get_model("compass_coulomb").phase_names
    assert len(names) == 9 and names[HIP_STICK] == "swing ankle=slip- hip=stick"
    for phase in range(9):
        assert M.phase_of(**M.modes_of(phase)) == phase


def test_zero_friction_is_the_compass_gait():
    compass = simulate("compass", CompassParams.goswami(), SPONG_X, **TIGHT)
    coulomb = simulate("compass_coulomb", _params(0.0), SPONG_X, output="events", **TIGHT)
    assert compass.status == coulomb.status == Status.COMPLETED
    assert_allclose(coulomb.x, compass.x, rtol=0, atol=1e-10)
    assert_allclose(coulomb.t, compass.t, rtol=0, atol=1e-10)
    # no friction: the slip_stops guards never fire, the only event is the heel strike
    assert list(coulomb.events.guard) == [0]


def test_zero_friction_with_dampers_is_the_damped_compass_gait():
    """Viscous dampers (ankle and hip) act the same in both models."""
    damped = {"damping_hip": 0.3, "damping_ankle": 0.5}
    compass = simulate("compass", CompassParams.goswami().replace(**damped), SPONG_X, **TIGHT)
    coulomb = simulate("compass_coulomb", _params(0.0).replace(**damped), SPONG_X, **TIGHT)
    assert compass.status == coulomb.status == Status.COMPLETED
    assert_allclose(coulomb.x, compass.x, rtol=0, atol=1e-10)


@pytest.mark.parametrize("phase", range(9))
def test_jac_matches_finite_differences(phase):
    p = _params(0.7, 0.4).replace(damping_hip=0.2, damping_ankle=0.3).as_array()
    x = np.array([0.13, -0.21, -0.9, -0.4])
    model = get_model("compass_coulomb")
    J = model.jac(phase, x, p)
    Jfd = rhs_jacobian_fd(model, phase, x, p)
    assert_allclose(J, Jfd, rtol=0, atol=1e-7)


def test_stick_holds_then_breaks():
    params = _params(5.0)
    p = params.as_array()
    model = get_model("compass_coulomb")
    assert model.start_phase(STICK_X, params) == HIP_STICK
    lam0 = joint_torques("compass_coulomb", HIP_STICK, STICK_X, p)[1]
    assert -5.0 < lam0 < 0.0
    sol = simulate("compass_coulomb", params, STICK_X, output="events", **TIGHT)
    ev = sol.events
    assert ev.guard[0] == M.GUARD_NAMES.index("hip_stick_breaks")
    # lambda <= -F_s: the friction cannot hold the swing leg back, the hip slips forward.
    assert M.modes_of(int(ev.phase_after[0]))["hip"] == "slip+"
    assert_allclose(
        joint_torques("compass_coulomb", HIP_STICK, ev.x_pre[0], p)[1], -5.0, rtol=0, atol=1e-8
    )
    assert abs(ev.x_pre[0][3] - ev.x_pre[0][2]) < 1e-13  # locked while sticking
    t_break = ev.t[0]
    # energy is conserved while the hip sticks (the locking torque does no work)
    times = np.linspace(0.0, t_break, 9)
    samp = simulate(
        "compass_coulomb", params, STICK_X, output="samples", sample_times=times, **TIGHT
    )
    e = _total_energy(model, samp.samples.x, params)
    assert_allclose(e, e[0], rtol=1e-11, atol=0)
    assert np.all(samp.samples.phase == HIP_STICK)


def test_slip_loses_exactly_coulomb_work_then_sticks():
    params = _params(5.0)
    model = get_model("compass_coulomb")
    sol = simulate("compass_coulomb", params, SLIP_X, output="events", **TIGHT)
    ev = sol.events
    assert ev.guard[0] == M.GUARD_NAMES.index("hip_slip_stops")
    assert ev.phase_after[0] == HIP_STICK
    assert abs(ev.x_post[0][3] - ev.x_post[0][2]) < 1e-15
    assert (
        abs(joint_torques("compass_coulomb", HIP_STICK, ev.x_post[0], params.as_array())[1]) < 5.0
    )
    # slip phase [0, t_stop]: with no viscous damping dE/dt = -F_s |w| and w keeps its sign,
    # so the energy lost is F_s |delta(q_swing - q_stance)|.
    t_stop = ev.t[0]
    times = np.linspace(0.0, t_stop, 7)
    samp = simulate(
        "compass_coulomb", params, SLIP_X, output="samples", sample_times=times, **TIGHT
    )
    x = samp.samples.x
    e = _total_energy(model, x, params)
    phi = x[:, 1] - x[:, 0]
    assert np.all(np.diff(e) < 0)
    assert_allclose(e[0] - e, 5.0 * np.abs(phi - phi[0]), rtol=0, atol=1e-10)
    # and the projection onto w = 0 at the event changes the energy by O(w^2) only
    e_pre = _total_energy(model, ev.x_pre[:1], params)
    e_post = _total_energy(model, ev.x_post[:1], params)
    assert_allclose(e_post, e_pre, rtol=0, atol=1e-14)


@pytest.mark.regression_pin
def test_small_friction_still_walks():
    """REGRESSION PIN: the step time 0.7339066619 s at 0.01 N m of hip friction is walker's own
    (DOP853, rtol 1e-12; see the module docstring); the rest is checked against the
    frictionless gait and central differences.
    """
    compass = find_fixed_point(StrideMap("compass", CompassParams.goswami()), SPONG_Z)
    P = StrideMap("compass_coulomb", _params(0.01))
    fp = find_fixed_point(P, SPONG_Z)
    fd = find_fixed_point(P, SPONG_Z, jacobian="fd")
    assert fp.success and fd.success and fp.stable
    assert_allclose(fp.section, fd.section, rtol=0, atol=1e-10)
    # measured (DOP853, rtol 1e-12): step time 0.734721 s -> 0.733907 s, section point
    # moves by ~2e-3; the multipliers barely change (0.57995 -> 0.58148).
    assert_allclose(fp.step_time, 0.7339066619, rtol=0, atol=1e-8)
    assert fp.step_time < compass.step_time
    assert 0 < np.max(np.abs(fp.section - compass.section)) < 5e-3
    assert_allclose(np.abs(fp.multipliers), np.abs(compass.multipliers), rtol=0, atol=5e-3)
    # the exact Jacobian (variational equations + saltation) agrees with central differences
    r = P(fp.section, jacobian=True)
    jfd = np.empty((3, 3))
    for k in range(3):
        e = np.zeros(3)
        e[k] = 1e-6
        jfd[:, k] = (P(fp.section + e).z - P(fp.section - e).z) / 2e-6
    assert_allclose(r.jac, jfd, rtol=0, atol=1e-7)


def test_large_friction_is_a_fall_not_an_exception():
    params = _params(100.0)
    sol = simulate("compass_coulomb", params, SPONG_X, n_strides=3, output="events")
    assert sol.status == Status.FELL_FORWARD
    assert sol.n_strides == 0
    # the hip stopped slipping and stuck before the fall
    assert M.modes_of(int(sol.events.phase_after[0]))["hip"] == "stick"
    r = StrideMap("compass_coulomb", params)(SPONG_Z)
    assert r.status == Status.FELL_FORWARD
    assert np.all(np.isnan(r.z))


@pytest.mark.regression_pin
def test_ankle_friction_slows_the_gait_and_large_friction_stops_it():
    """REGRESSION PIN: the three speeds (0.7288, 0.6922, 0.5149 m/s) are walker's own.

    Dry friction at the stance ankle: the gait slows (measured 0.7288 m/s at 0, 0.6922 at
    1, 0.5149 at 5 N m, all stable); at 10 N m the stance leg sticks mid-stride, and once it
    breaks loose the heel strike is not physical (the trailing foot would not lift off):
    an outcome, not an exception."""
    z = SPONG_Z
    speeds = []
    for F in (0.0, 1.0, 5.0):
        P = StrideMap("compass_coulomb", _params(0.0, coulomb_ankle=F))
        fp = find_fixed_point(P, z)
        assert fp.success and fp.stable
        z = fp.section
        x = fp.state
        speeds.append(2.0 * np.sin(0.5 * (x[0] - x[1])) / fp.step_time)  # leg length 1 m
    assert_allclose(speeds, [0.7288, 0.6922, 0.5149], rtol=0, atol=1e-4)
    params = _params(0.0, coulomb_ankle=10.0)
    sol = simulate(
        "compass_coulomb",
        params,
        StrideMap("compass_coulomb", params).lift(z),
        n_strides=5,
        output="events",
    )
    assert sol.status == Status.NONPHYSICAL_IMPACT
    names = [M.GUARD_NAMES[g] for g in sol.events.guard]
    assert "ankle_slip_stops" in names and "ankle_stick_breaks" in names
