"""The course's double pendulum with joint friction (walker.models.double_pendulum, on
walker/models/friction.py): ``D qdd + C qd + g = -F_v qd - F_s sgn(qd)`` joint by joint, joint 1
between the ground and link 1 (``w1 = qd1``), joint 2 between link 1 and link 2
(``w2 = qd2``, ``q2`` being relative).

Checked here:

* the parameter layout the compiled code reads, phases and guards of the friction layer;
* without dry friction no event ever fires and the accelerations are exactly the generated
  (damped) ``accel`` kernel's; with dry friction and no joint stuck, that kernel plus
  ``D^-1`` of the slip torques equals the friction layer's augmented solve;
* viscous damping only: ``E(t) - E(0) = -int sum_j b_j w_j^2 dt`` (the power integrated by
  Simpson's rule on 20001 dense-output samples over 10 s; measured error 1.0e-10 J against
  19.9 J dissipated, asserted to 1e-9 J);
* dry friction only: between consecutive events ``E`` drops by ``sum_j F_j |delta theta_j|``
  to 1e-10 J (measured 4e-11 J at rtol = 1e-12);
* released from rest with friction that can hold it, the pendulum stays stuck to ``t_max``
  (status COMPLETED, as any run of a model without strides: ``n_strides = 0`` integrates to
  ``t_max``); with moderate friction it slips, swings and finally sticks at a rest angle
  whose gravity torques the frictions hold;
* the vector-field Jacobian is exact in all 9 phases;
* bad values raise, naming the argument.
"""

from __future__ import annotations

import numpy as np
import pytest
from _fd import rhs_jacobian_fd
from _joint_torques import joint_torques
from numpy.testing import assert_allclose
from scipy.integrate import cumulative_simpson

# The course's release state: link 1 at -0.1 rad from +x, link 2 pointing straight up, at rest.
from test_reference_runs import COURSE_STATE, release

from walker.models import double_pendulum as M
from walker.models import friction as fr
from walker.models import get_model
from walker.params import DoublePendulumParams
from walker.status import Status

TIGHT = {"rtol": 1e-12, "atol": 1e-12}
MODEL = get_model("double_pendulum")


def _params(**friction) -> DoublePendulumParams:
    return DoublePendulumParams.course().replace(**friction)


def _energy(x, params) -> float:
    return float(sum(MODEL.energy(x, params)))


def _gravity_torques(x, params) -> np.ndarray:
    """``g(q) = dP/dq`` [N m]: the torque each joint must hold to keep the pendulum at rest."""
    return MODEL.kernel("gravity", params, x[:2])


# ------------------------------------------------------------------------- layout
def test_parameter_layout_read_by_the_compiled_model():
    """The index the compiled functions read is the params class's."""
    names = DoublePendulumParams.names()
    assert names.index("coulomb_1") == M.I_COULOMB
    assert names[M.I_COULOMB :] == ("coulomb_1", "coulomb_2")
    assert names[9:11] == ("damping_1", "damping_2")
    p = _params(damping_1=0.1, damping_2=0.2, coulomb_1=0.3, coulomb_2=0.4).as_array()
    assert list(p[M.I_COULOMB : M.I_COULOMB + 2]) == [0.3, 0.4]
    # the generated kernels read the dampers where the params class puts them
    Q = MODEL.kernel("forcing", p, np.zeros(2), np.array([2.0, -3.0]))
    assert_allclose(Q, [-0.2, 0.6], rtol=1e-15, atol=0)


def test_phases_and_guards_are_the_friction_layer():
    assert len(MODEL.phase_names) == 9
    assert MODEL.phase_names[M.phase_of(joint_1="slip-", joint_2="stick")] == (
        "free joint_1=slip- joint_2=stick"
    )
    assert MODEL.guard_names == (
        "joint_1_slip_stops",
        "joint_1_stick_breaks",
        "joint_2_slip_stops",
        "joint_2_stick_breaks",
    )
    for phase in range(9):
        assert M.phase_of(**M.modes_of(phase)) == phase
        assert list(MODEL.system.directions[phase]) == fr.directions(phase, 2)
    with pytest.raises(ValueError, match=r"mode of `joint_2` must be one of"):
        M.phase_of(joint_2="sticky")
    with pytest.raises(ValueError, match=r"joint modes must be given for"):
        M.phase_of(elbow="stick")
    with pytest.raises(ValueError, match=r"`phase` must be in \[0, 9\), got 9"):
        M.modes_of(9)


@pytest.mark.parametrize(
    ("name", "value", "error", "message"),
    [
        ("coulomb_1", -0.1, ValueError, r"^`coulomb_1` must be >= 0 \[N m\], got -0.1$"),
        ("coulomb_2", np.inf, ValueError, r"^`coulomb_2` must be finite, got inf$"),
        ("damping_1", -1.0, ValueError, r"^`damping_1` must be >= 0 \[N m s/rad\], got -1.0$"),
        ("damping_2", "0.5", TypeError, r"^`damping_2` must be a real number, got str"),
    ],
)
def test_bad_friction_values_raise_naming_the_argument(name, value, error, message):
    with pytest.raises(error, match=message):
        _params(**{name: value})


def test_parameter_vector_of_the_old_layout_is_refused():
    with pytest.raises(ValueError, match=r"^`p` must have shape \(13,\) for DoublePendulumParams"):
        DoublePendulumParams.from_array(np.ones(9))


# ------------------------------------------------------------------ no dry friction
SLIP_PHASES = [k for k in range(9) if "stick" not in M.modes_of(k).values()]


def _layer_accelerations(phase, x, p):
    """``qdd`` of a phase without stuck joints, by hand: ``D qdd = Q - h + tau`` with the
    slip torques ``tau_j = -F_j`` (slip+) or ``+F_j`` (slip-), from the generated
    ``mass_matrix``, ``bias`` and ``forcing`` kernels."""
    q, qd = x[:2], x[2:]
    D = MODEL.kernel("mass_matrix", p, q)
    h = MODEL.kernel("bias", p, q, qd)
    Q = MODEL.kernel("forcing", p, q, qd)
    modes = np.array([phase % 3, phase // 3])
    assert not (modes == 2).any()
    F = p[M.I_COULOMB : M.I_COULOMB + 2]
    tau = np.where(modes == 0, -F, F)
    return np.linalg.solve(D, Q - h + tau)


def test_slip_phases_use_the_generated_field():
    """With no joint stuck ``rhs`` is the fused generated ``accel`` kernel (viscous forcing
    included) plus ``D^-1`` of the slip torques: without dry friction exactly the kernel
    (so the course's frictionless runs are the generated model's), with it the friction
    layer's augmented solve to round-off, at random states, dampers and frictions."""
    assert len(SLIP_PHASES) == 4
    rng = np.random.default_rng(11)
    for k in range(50):
        dry = {"coulomb_1": rng.uniform(0, 5), "coulomb_2": rng.uniform(0, 5)} if k % 2 else {}
        params = _params(damping_1=rng.uniform(0, 5), damping_2=rng.uniform(0, 5), **dry)
        p = params.as_array()
        x = np.concatenate([rng.uniform(-np.pi, np.pi, 2), rng.normal(0.0, 3.0, 2)])
        kernel = MODEL.kernel("accel", p, x[:2], x[2:])
        for phase in SLIP_PHASES:
            dx = MODEL.rhs(phase, x, p)
            assert_allclose(dx[:2], x[2:], rtol=0, atol=0)
            if not dry:
                assert_allclose(dx[2:], kernel, rtol=0, atol=0)
            ref = _layer_accelerations(phase, x, p)
            assert_allclose(dx[2:], ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())
            if dry:
                assert np.abs(dx[2:] - kernel).max() > 1e-3  # the slip torques do act


@pytest.mark.parametrize("damped", [False, True], ids=["course", "viscous"])
def test_without_dry_friction_no_event_fires(damped):
    friction = {"damping_1": 0.3, "damping_2": 0.2} if damped else {}
    sol = release(_params(**friction), 10.0, output="events", **TIGHT)
    assert sol.status == Status.COMPLETED and sol.success
    assert sol.n_events == 0 and len(sol.events) == 0
    assert sol.t == 10.0


# --------------------------------------------------------------- energy balances
def test_viscous_energy_balance():
    """``E(t) - E(0) = -int_0^t (b1 w1^2 + b2 w2^2) dt`` over 10 s, at every one of 20001
    dense-output samples (DOP853 at rtol = atol = 1e-12; the power integrated by
    ``scipy.integrate.cumulative_simpson``).  Measured: max error 1.0e-10 J against 19.9 J
    dissipated (5e-12 relative); with 10001 samples Simpson's rule makes it 9e-10 J, with
    2001 samples 6e-7 J."""
    params = _params(damping_1=0.3, damping_2=0.2)
    times = np.linspace(0.0, 10.0, 20001)
    sol = release(params, 10.0, output="samples", sample_times=times, **TIGHT)
    assert sol.success and sol.n_events == 0
    x = sol.samples.x
    kinetic, potential = MODEL.energies(x, params)
    energy = kinetic + potential
    power = params.damping_1 * x[:, 2] ** 2 + params.damping_2 * x[:, 3] ** 2
    dissipated = cumulative_simpson(power, x=times, initial=0.0)
    assert dissipated[-1] > 15.0  # most of the motion's energy goes into the dampers
    assert_allclose(energy - energy[0], -dissipated, rtol=0, atol=1e-9)


@pytest.mark.parametrize(
    ("coulomb_1", "coulomb_2", "breaks"),
    [(1.0, 1.0, "joint_2_stick_breaks"), (3.0, 1.0, "joint_1_stick_breaks")],
)
def test_dry_friction_loses_exactly_the_coulomb_work_between_events(coulomb_1, coulomb_2, breaks):
    """Between consecutive events every joint keeps its mode: a slipping joint's rate keeps
    its sign and a stuck one does not move, so ``E`` drops by ``sum_j F_j |delta theta_j|``
    (``theta_j = q_j``) exactly; checked on every interval of a 20 s run from the course's
    release state, to 1e-10 J (measured 4e-11 J at rtol 1e-12, 3e-9 J at 1e-10).  The resets
    change ``E`` by O(w^2) only (measured <= 7e-15 J)."""
    params = _params(coulomb_1=coulomb_1, coulomb_2=coulomb_2)
    F = np.array([coulomb_1, coulomb_2])
    sol = release(params, 20.0, output="events", **TIGHT)
    assert sol.status == Status.COMPLETED
    ev = sol.events
    names = {MODEL.guard_names[g] for g in ev.guard}
    assert {"joint_1_slip_stops", "joint_2_slip_stops", breaks} <= names
    starts = [COURSE_STATE, *ev.x_post]
    ends = [*ev.x_pre, sol.x]
    lost = []
    for x0, x1 in zip(starts, ends, strict=True):
        dtheta = np.abs(x1[:2] - x0[:2])
        lost.append(_energy(x0, params) - _energy(x1, params))
        assert_allclose(lost[-1], F @ dtheta, rtol=0, atol=1e-10)
    assert len(lost) >= 15 and sum(lost) > 20.0
    for x_pre, x_post in zip(ev.x_pre, ev.x_post, strict=True):
        assert_allclose(_energy(x_post, params), _energy(x_pre, params), rtol=0, atol=1e-13)


# ------------------------------------------------------------------- stick and slip
def test_friction_that_can_hold_the_pendulum_keeps_it_stuck():
    """Released from rest at the course's state, joint 1 must hold the gravity torque
    ``g1 = 14.925 N m`` and joint 2 ``g2 = 0`` (link 2 points straight up).  With
    ``F1 = 15 N m`` both joints stick from the start: no event, the state does not move to
    ``t_max`` and the run completes (``n_strides = 0`` runs to ``t_max``: COMPLETED, the
    status of any run of a model without strides).  With ``F1 = 14.9 N m`` joint 1 slips."""
    params = _params(coulomb_1=15.0, coulomb_2=0.1)
    g = _gravity_torques(COURSE_STATE, params)
    assert_allclose(g, [14.925062, 0.0], rtol=0, atol=1e-6)
    both = M.phase_of(joint_1="stick", joint_2="stick")
    assert MODEL.start_phase(COURSE_STATE, params) == both
    # the holding torques are the gravity torques, inside the frictions
    assert_allclose(
        joint_torques("double_pendulum", both, COURSE_STATE, params), g, rtol=0, atol=1e-12
    )
    times = np.linspace(0.0, 5.0, 11)
    sol = release(params, 5.0, output="samples", sample_times=times)
    assert sol.status == Status.COMPLETED and sol.success
    assert (sol.t, sol.n_events, sol.n_strides, sol.phase) == (5.0, 0, 0, both)
    assert np.all(sol.samples.phase == both)
    assert_allclose(sol.samples.x, np.tile(COURSE_STATE, (11, 1)), rtol=0, atol=1e-15)

    slipping = params.replace(coulomb_1=14.9)
    assert M.modes_of(MODEL.start_phase(COURSE_STATE, slipping)) == {
        "joint_1": "slip-",
        "joint_2": "stick",
    }
    sol = release(slipping, 1.0)
    assert sol.success and sol.x[2] < 0.0 and sol.x[0] < COURSE_STATE[0] - 1e-3


@pytest.mark.regression_pin
def test_moderate_friction_slips_swings_and_sticks_at_rest():
    """REGRESSION PIN: the event count (21), the last event's time (11.622 s) and the rest angle
    (-1.6094 rad) are walker's own; the stick/slip modes and the held gravity torques are
    the checks.

    F1 = F2 = 1 N m from the course's release state (measured, rtol 1e-12): joint 1
    slips down, swings through the bottom and back (both slip directions of both joints
    occur), 21 events later (the last at t = 11.622 s) both joints stick for good with the
    pendulum hanging near the bottom, q1 = -1.6094 rad, where the gravity torques
    (-0.905, -0.325 N m) are within the frictions and are what the joints hold."""
    params = _params(coulomb_1=1.0, coulomb_2=1.0)
    sol = release(params, 30.0, output="events", **TIGHT)
    assert sol.status == Status.COMPLETED
    ev = sol.events
    assert len(ev) == 21
    assert_allclose(ev.t[-1], 11.622, rtol=0, atol=1e-3)
    seen = {(j, mode) for phase in ev.phase_after for j, mode in M.modes_of(int(phase)).items()}
    for joint in M.JOINTS:
        assert {(joint, "slip+"), (joint, "slip-"), (joint, "stick")} <= seen
    # the final state: both joints stuck, at rest, gravity held by friction
    both = M.phase_of(joint_1="stick", joint_2="stick")
    assert sol.phase == both == ev.phase_after[-1]
    assert np.abs(sol.x[2:]).max() < 1e-13
    assert_allclose(sol.x[0], -1.6094, rtol=0, atol=1e-4)
    g = _gravity_torques(sol.x, params)
    assert np.all(np.abs(g) <= [params.coulomb_1, params.coulomb_2])
    assert np.abs(g).max() > 0.1  # at rest off the equilibrium: friction does hold it
    assert_allclose(joint_torques("double_pendulum", both, sol.x, params), g, rtol=0, atol=1e-12)
    # nothing moves after the last event
    assert_allclose(sol.x[:2], ev.x_post[-1][:2], rtol=0, atol=1e-12)


# ------------------------------------------------------------------------- Jacobian
@pytest.mark.parametrize("phase", range(9), ids=lambda k: M.PHASE_NAMES[k].split(" ", 1)[1])
def test_jac_matches_central_differences(phase):
    p = _params(damping_1=0.2, damping_2=0.3, coulomb_1=0.7, coulomb_2=0.4).as_array()
    rng = np.random.default_rng(phase)
    for _ in range(5):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, 2), rng.normal(0.0, 2.0, 2)])
        J = MODEL.jac(phase, x, p)
        fd = rhs_jacobian_fd(MODEL, phase, x, p)
        assert_allclose(J, fd, rtol=1e-6, atol=1e-6)
