"""walker's compiled actuated walkers in closed loop (``three_link``, ``five_link``)
against the independent numpy oracle of ``tests/oracle_actuated.py`` (controllers 0-2
written from :mod:`walker.models.control`'s docstring, the finite-time controller 3 from
:class:`walker.params.ThreeLinkParams`, over the lambdified symbolic models; joint friction
from ``tests/oracle_friction.py``).

Tolerances as in ``tests/test_oracle.py`` except the vector field's Jacobian: the C takes
it by central differences (relative step 1e-6), the oracle too, of its own vector field, so
the two differ by the round-off of the vector fields over the step (``FD_JAC_RTOL`` = 1e-7
of the largest entry; up to 6e-9 seen, with the finite-time controller, whose
``sgn(y) |y|^alpha`` steepens near ``y = 0``).  The five-link walker's derivation and its
strides are slow (slow tier), as are the three-link strides.
"""

from __future__ import annotations

import functools

import numpy as np
import oracle as O
import oracle_friction as OF
import pytest
from test_oracle import (
    FIXED_POINT_TOL,
    KERNEL_RTOL,
    STRIDE_RTOL,
    Compiled,
    Worst,
    compare_runs,
)

from walker import StrideMap, load_scene
from walker.models import get_model
from walker.simulation.stride import simulate
from walker.status import EVENT_CONTINUE, EVENT_IGNORE, EVENT_STRIDE, EVENT_TERMINAL, Status

FD_JAC_RTOL = 1e-7
ACTUATED_JACOBIAN_RTOL = 1e-6
"""The stride-map Jacobian of an actuated walker: its variational equations run on the
central-difference vector-field Jacobian, whose error (about 1e-7 of the largest entry,
gaits/five_link_hzd.toml's note) they carry (7.4e-8 seen for the five-link walker, 3.5e-9
for the three-link)."""
NAMES = get_model("three_link").params_class.names()


@functools.cache
def _scene():
    scene = load_scene("gaits/three_link_grizzle.toml")
    return scene, scene.params.as_array(), np.array(scene.reference["state"], dtype=float)


def _sample(rng):
    """A state near Grizzle's gait and parameters near the scene's: masses and lengths
    scaled by U(0.8, 1.2), a random slope, controller 0, 1 or 2, a torque limit that may
    clip, either step event, hip dampers and dry friction (zero or drawn)."""
    _, p0, x0 = _scene()
    p = p0.copy()
    p[:10] *= rng.uniform(0.8, 1.2, 10)
    p[NAMES.index("slope")] = rng.uniform(-0.1, 0.1)
    p[NAMES.index("controller")] = rng.choice([0.0, 1.0, 2.0, 3.0])
    p[NAMES.index("torque_limit")] = rng.choice([1000.0, 30.0])
    p[NAMES.index("step_event")] = rng.choice([0.0, 1.0])
    p[NAMES.index("damping_hip")] = rng.uniform(0.0, 2.0) * (rng.random() < 0.5)
    p[NAMES.index("coulomb_hip")] = rng.uniform(0.0, 20.0) * (rng.random() < 0.5)
    x = x0.copy()
    x[:3] += rng.normal(0.0, 0.2, 3)
    x[3:6] += rng.normal(0.0, 1.0, 3)
    x[6:] = rng.uniform(0.0, 1.0, 2)
    if rng.random() < 0.4:
        x[3:6] = x[3:6] - np.array([1.0, 0.0, -1.0]) * (x[3] - x[5]) / 2  # stance hip at rest
    if rng.random() < 0.4:
        x[4] = x[5]  # swing hip at rest
    return x, p


def test_phase_functions_agree_with_oracle():
    """rhs, guards (ground-reaction cone, lift-off and friction guards included), energy,
    points and the start phase at 25 samples in all 9 phases to ``KERNEL_RTOL``; the
    finite-difference Jacobian to ``FD_JAC_RTOL``."""
    c, o = Compiled("three_link"), O.oracle("three_link")
    rng = np.random.default_rng(20261128)
    worst = Worst("three_link")
    for _ in range(25):
        x, p = _sample(rng)
        assert c.model.start_phase(x, p) == o.start_phase(x, p), (x.tolist(), p.tolist())
        for phase in range(9):
            where = f"phase {phase} x {x.tolist()} p {p.tolist()}"
            worst.check("rhs", c.rhs(phase, x, p), o.rhs(phase, x, p), KERNEL_RTOL, where)
            worst.check("guards", c.guards(phase, x, p), o.guards(phase, x, p), KERNEL_RTOL, where)
            J_c, J_o = c.jac(phase, x, p), o.jac(phase, x, p)
            scale = max(1.0, np.abs(J_o).max())
            worst.check("jac", J_c / scale, J_o / scale, FD_JAC_RTOL, where)
        worst.check("energy", c.model.energy(x, p), o.energy(x, p), KERNEL_RTOL)
        worst.check("points", c.model.points(x, p), o.points(x, p), KERNEL_RTOL)
    worst.report()


_NONPHYS, _SINGULAR = int(Status.NONPHYSICAL_IMPACT), int(Status.LINEAR_SOLVE_FAILED)
REQUIRED = {
    (0, EVENT_IGNORE, 0),  # the mid-stance scuff
    (0, EVENT_STRIDE, 0),
    (0, EVENT_TERMINAL, _NONPHYS),  # outside the friction cone, or no lift-off
    (0, EVENT_TERMINAL, _SINGULAR),
    (1, EVENT_TERMINAL, int(Status.FELL_FORWARD)),
    (2, EVENT_TERMINAL, int(Status.FELL_BACKWARD)),
    *((k, EVENT_TERMINAL, _NONPHYS) for k in (3, 4, 5)),  # slip, slip back, lift-off
    *((k, EVENT_CONTINUE, 0) for k in (6, 7, 8, 9)),  # the hip joints' friction events
}


def test_reset_agrees_with_oracle_on_every_branch():
    """Heel strike at 150 touchdowns (ahead, behind, friction coefficient drawn so that
    the impulse leaves the cone, non-finite rates), falls, the force guards and the hip
    joints' friction events at their event states: equal outcomes, states and impulses
    to ``KERNEL_RTOL``."""
    c, o = Compiled("three_link"), O.oracle("three_link")
    rng = np.random.default_rng(7)
    worst = Worst("three_link reset")
    seen = set()
    cases = []
    for i in range(150):
        x, p = _sample(rng)
        p[NAMES.index("friction")] = rng.choice([0.8, 0.1, 0.02])
        x[0] = rng.uniform(-0.6, 0.6)
        x[1] = -2.0 * p[NAMES.index("slope")] - x[0]  # the swing foot on the slope
        if i % 7 == 0:
            x[1] = x[0]
        if i % 11 == 0:
            x[3 + rng.integers(3)] = np.nan
        phase = o.start_phase(x, p) if np.isfinite(x).all() else 0
        cases += [(phase, k, x, p) for k in range(6)]
        p_f = p.copy()
        p_f[NAMES.index("coulomb_hip")] = rng.uniform(1.0, 20.0)
        x_f = x.copy()
        x_f[3:6] = np.nan_to_num(x_f[3:6])
        phase = o.start_phase(x_f, p_f)
        _, modes = o.split(phase)
        for j, mode in enumerate(modes):
            if mode == OF.STICK:
                p_j = p_f.copy()
                p_j[NAMES.index("coulomb_hip")] = abs(o.closed_loop(phase, x_f, p_f)[3][j]) * (
                    1.0 - 1e-12
                )
                cases.append((phase, 6 + 2 * j + 1, x_f, p_j))
            else:
                x_j = x_f.copy()
                row = o.joint_rows(0)[j]
                x_j[3:6] -= row * (row @ x_j[3:6]) / (row @ row)
                cases.append((o.start_phase(x_j, p_f), 6 + 2 * j, x_j, p_f))
    for phase, k, x, p in cases:
        if k >= 6 and o.directions[phase][k] == 0:
            continue
        _, modes = o.split(phase)
        j = (k - 6) // 2
        if k >= 6 and ((k % 2 == 1) != (modes[j] == OF.STICK)):
            continue  # that guard is unused in this phase
        out_o, x_o, imp_o = o.reset(phase, k, x, p)
        out_c, x_c, imp_c = c.reset(phase, k, x, p)
        where = f"phase {phase} guard {k} x {x.tolist()} p {p.tolist()}"
        assert out_c == out_o, where
        if out_o[0] in (EVENT_STRIDE, EVENT_CONTINUE):
            worst.check("state", x_c, x_o, KERNEL_RTOL, where)
            worst.check("impulse", imp_c, imp_o, KERNEL_RTOL, where)
        seen.add((k, out_o[0], out_o[2]))
    missing = REQUIRED - seen
    assert not missing, f"three_link: branches not reached {sorted(missing)}"
    worst.report()


@pytest.mark.slow  # a few seconds per oracle stride through the controller
def test_book_stride_agrees_with_oracle():
    """One stride of the book's example (finite-time controller 3, the step ending where
    the stance angle falls through ``theta_minus``) from the scene's start: events, final
    state and section point to ``STRIDE_RTOL``."""
    scene = load_scene("gaits/three_link_book.toml")
    p, x0 = scene.params.as_array(), np.array(scene.state, dtype=float)
    o = O.oracle("three_link")
    worst = Worst("three_link_book")
    sol = simulate("three_link", scene.params, x0, output="events", rtol=1e-12, atol=1e-12)
    r = O.run(o, x0, p, phase=o.start_phase(x0, p))
    compare_runs(sol, r, worst, "three_link_book")
    worst.report()


@pytest.mark.slow  # 21 oracle strides through the controller
def test_grizzle_stride_jacobian_and_gait_agree_with_oracle():
    """One stride of Grizzle's gait (controller 2): events, final state (accumulators
    included), section point to ``STRIDE_RTOL``; the stride-map Jacobian against oracle
    central differences to ``ACTUATED_JACOBIAN_RTOL``; the scene's gait against the oracle's
    fixed point to ``FIXED_POINT_TOL``."""
    scene, p, x0 = _scene()
    o = O.oracle("three_link")
    worst = Worst("three_link_grizzle")
    sol = simulate("three_link", scene.params, x0, output="events", rtol=1e-12, atol=1e-12)
    r = O.run(o, x0, p, phase=o.start_phase(x0, p))
    compare_runs(sol, r, worst, "three_link_grizzle")
    z = o.project(x0)
    res = StrideMap("three_link", scene.params, rtol=1e-12, atol=1e-12)(z, jacobian=True)
    z_o, t_o, _ = O.stride(o, z, p)
    worst.check("section point", res.z, z_o, STRIDE_RTOL)
    J = O.stride_jacobian(o, z, p)
    scale = np.abs(res.jac).max()
    worst.check("Jacobian", res.jac / scale, J / scale, ACTUATED_JACOBIAN_RTOL)
    z_fixed = z - np.linalg.solve(J - np.eye(len(z)), z_o - z)
    worst.check("fixed point", z, z_fixed, FIXED_POINT_TOL)
    worst.check("step time", scene.reference["step_time"], t_o, FIXED_POINT_TOL)
    worst.report()


# --------------------------------------------------------------------------------------
# The five-link walker (its derivation and lambdification take about 4 s: slow tier)
# --------------------------------------------------------------------------------------

FIVE_NAMES = get_model("five_link").params_class.names()


@functools.cache
def _five_scene():
    scene = load_scene("gaits/five_link_hzd.toml")
    return scene, scene.params.as_array(), np.array(scene.reference["state"], dtype=float)


def _five_sample(rng):
    """A state near the HZD gait and parameters near the scene's (as :func:`_sample`)."""
    _, p0, x0 = _five_scene()
    p = p0.copy()
    p[:13] *= rng.uniform(0.8, 1.2, 13)
    p[FIVE_NAMES.index("slope")] = rng.uniform(-0.1, 0.1)
    p[FIVE_NAMES.index("controller")] = rng.choice([0.0, 1.0, 2.0])
    p[FIVE_NAMES.index("torque_limit")] = rng.choice([1000.0, 40.0])
    for k in ("damping_hip", "damping_knee"):
        p[FIVE_NAMES.index(k)] = rng.uniform(0.0, 2.0) * (rng.random() < 0.5)
    for k in ("coulomb_hip", "coulomb_knee"):
        p[FIVE_NAMES.index(k)] = rng.uniform(0.0, 20.0) * (rng.random() < 0.5)
    x = x0.copy()
    x[:5] += rng.normal(0.0, 0.1, 5)
    x[5:10] += rng.normal(0.0, 0.5, 5)
    x[10:] = rng.uniform(0.0, 1.0, 2)
    S = O.oracle("five_link").joint_rows(0)
    for j in range(4):
        if rng.random() < 0.3:  # joint j at rest
            x[5:10] -= S[j] * (S[j] @ x[5:10]) / (S[j] @ S[j])
    return x, p


@pytest.mark.slow
def test_five_link_phase_functions_agree_with_oracle():
    """rhs, guards, energy, points and the start phase at 12 samples in 8 random phases
    each (of 81) to ``KERNEL_RTOL``; the finite-difference Jacobian to ``FD_JAC_RTOL``."""
    c, o = Compiled("five_link"), O.oracle("five_link")
    rng = np.random.default_rng(20261128)
    worst = Worst("five_link")
    for _ in range(12):
        x, p = _five_sample(rng)
        assert c.model.start_phase(x, p) == o.start_phase(x, p), (x.tolist(), p.tolist())
        for phase in rng.choice(81, 8, replace=False):
            where = f"phase {phase} x {x.tolist()} p {p.tolist()}"
            worst.check("rhs", c.rhs(phase, x, p), o.rhs(phase, x, p), KERNEL_RTOL, where)
            worst.check("guards", c.guards(phase, x, p), o.guards(phase, x, p), KERNEL_RTOL, where)
            J_c, J_o = c.jac(phase, x, p), o.jac(phase, x, p)
            scale = max(1.0, np.abs(J_o).max())
            worst.check("jac", J_c / scale, J_o / scale, FD_JAC_RTOL, where)
        worst.check("energy", c.model.energy(x, p), o.energy(x, p), KERNEL_RTOL)
        worst.check("points", c.model.points(x, p), o.points(x, p), KERNEL_RTOL)
    worst.report()


@pytest.mark.slow
def test_five_link_reset_agrees_with_oracle_on_every_branch():
    """Heel strike at 60 touchdowns ahead (the gait's configuration with the legs swapped,
    random rates and friction coefficients: strides and nonphysical impacts) and behind
    (trips), the falls, hip down, the force guards, and every joint's friction events:
    equal outcomes, states and impulses to ``KERNEL_RTOL``."""
    c, o = Compiled("five_link"), O.oracle("five_link")
    rng = np.random.default_rng(7)
    worst = Worst("five_link reset")
    seen = set()
    cases = []
    for _ in range(60):
        x, p = _five_sample(rng)
        p[FIVE_NAMES.index("friction")] = rng.choice([0.8, 0.1, 0.02])
        try:
            after = o.lift(o.project(x), p)  # the swing foot on the slope behind
        except ValueError:  # the swing foot cannot reach the slope
            continue
        before = after.copy()
        before[:5] = o.swap(after[:5])  # the swing foot on the slope ahead
        for state in (before, after):
            phase = o.start_phase(state, p)
            cases += [(phase, k, state, p) for k in range(7)]
        phase = o.start_phase(x, p)
        _, modes = o.split(phase)
        for j, mode in enumerate(modes):
            F = o.F(p)[j]
            if mode == OF.STICK:
                cases.append((phase, 7 + 2 * j + 1, x, p))
            elif F > 0.0:
                row = o.joint_rows(0)[j]
                x_j = x.copy()
                x_j[5:10] -= row * (row @ x_j[5:10]) / (row @ row)
                cases.append((phase, 7 + 2 * j, x_j, p))
    for phase, k, x, p in cases:
        out_o, x_o, imp_o = o.reset(phase, k, x, p)
        out_c, x_c, imp_c = c.reset(phase, k, x, p)
        where = f"phase {phase} guard {k} x {x.tolist()} p {p.tolist()}"
        assert out_c == out_o, where
        if out_o[0] in (EVENT_STRIDE, EVENT_CONTINUE):
            worst.check("state", x_c, x_o, KERNEL_RTOL, where)
            worst.check("impulse", imp_c, imp_o, KERNEL_RTOL, where)
        seen.add((k, out_o[0], out_o[2]))
    required = {
        (0, EVENT_STRIDE, 0),
        (0, EVENT_TERMINAL, _NONPHYS),
        (0, EVENT_TERMINAL, int(Status.TRIPPED)),
        (1, EVENT_TERMINAL, int(Status.FELL_FORWARD)),
        (2, EVENT_TERMINAL, int(Status.FELL_BACKWARD)),
        (6, EVENT_TERMINAL, int(Status.FELL_BACKWARD)),
        *((k, EVENT_TERMINAL, _NONPHYS) for k in (3, 4, 5)),
        *((k, EVENT_CONTINUE, 0) for k in range(7, 15)),
    }
    missing = required - seen
    assert not missing, f"five_link: branches not reached {sorted(missing)}"
    worst.report()


@pytest.mark.slow
def test_five_link_stride_jacobian_and_gait_agree_with_oracle():
    """One stride of the HZD gait (controller 2): events, final state, section point to
    ``STRIDE_RTOL``; the stride-map Jacobian (its vector-field Jacobian by central
    differences) against oracle central differences to ``ACTUATED_JACOBIAN_RTOL``; the
    scene's gait against the oracle's fixed point to ``FIXED_POINT_TOL``."""
    scene, p, x0 = _five_scene()
    o = O.oracle("five_link")
    worst = Worst("five_link_hzd")
    sol = simulate("five_link", scene.params, x0, output="events", rtol=1e-12, atol=1e-12)
    r = O.run(o, x0, p, phase=o.start_phase(x0, p))
    compare_runs(sol, r, worst, "five_link_hzd")
    z = o.project(x0)
    res = StrideMap("five_link", scene.params, rtol=1e-12, atol=1e-12)(z, jacobian=True)
    z_o, t_o, _ = O.stride(o, z, p)
    worst.check("section point", res.z, z_o, STRIDE_RTOL)
    J = O.stride_jacobian(o, z, p)
    scale = np.abs(res.jac).max()
    worst.check("Jacobian", res.jac / scale, J / scale, ACTUATED_JACOBIAN_RTOL)
    z_fixed = z - np.linalg.solve(J - np.eye(len(z)), z_o - z)
    worst.check("fixed point", z, z_fixed, FIXED_POINT_TOL)
    worst.check("step time", scene.reference["step_time"], t_o, FIXED_POINT_TOL)
    worst.report()
