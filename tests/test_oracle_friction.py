"""walker's compiled models with dry (Coulomb) joint friction (double_pendulum,
compass_coulomb, kneed_coulomb) against the independent numpy oracle of
``tests/oracle_friction.py`` (stick/slip modes written from the rules of
:mod:`walker.models.friction`, over the lambdified symbolic models of ``tests/oracle.py``).

Tolerances as in ``tests/test_oracle.py``: ``KERNEL_RTOL`` for the phase functions in every
phase and the resets' states and impulses, equal outcomes (and equal start phases),
``STRIDE_RTOL``, ``JACOBIAN_RTOL`` and ``FIXED_POINT_TOL`` for runs, strides, Jacobians and
the scenes' reference gaits.

The resets are compared where the integrator calls them: a friction event of a joint with
``F > 0`` in a phase where it is armed (``slip_stops`` with the joint's rate zero,
``stick_breaks`` with the joint's holding torque at its friction), and the base model's
events at the states of ``tests/test_oracle.py``'s branch cases.  Exact ties of the mode
choice (a holding torque equal to the friction) are not sampled: there the rate change of a
slipping option is round-off (1e-16) and its sign decides between two equally valid
choices (the C and the oracle differ at about a quarter of such ties).
"""

from __future__ import annotations

import numpy as np
import oracle as O
import oracle_friction as OF
import pytest
from test_oracle import (
    FIXED_POINT_TOL,
    JACOBIAN_RTOL,
    KERNEL_RTOL,
    STRIDE_RTOL,
    Compiled,
    Worst,
    compare_runs,
    reset_cases,
    sample_params,
    sample_state,
)

from walker import StrideMap, load_scene
from walker.simulation.stride import simulate
from walker.status import EVENT_CONTINUE, EVENT_STRIDE

MODELS = ["double_pendulum", "compass_coulomb", "kneed_coulomb"]
BASE = {"compass_coulomb": "compass", "kneed_coulomb": "kneed"}


def _coulomb(rng, n, scale):
    """Dry frictions: zero, small (joints slip) or large (joints at rest stick)."""
    kinds = rng.integers(3, size=n)
    return np.where(kinds == 0, 0.0, np.where(kinds == 1, 0.05, 5.0) * scale * rng.uniform(0, 1, n))


def _sample(name, rng):
    """(x, p): a state (some joints at rest) and a parameter vector of model ``name``."""
    if name == "double_pendulum":
        l1, l2 = rng.uniform(0.2, 2.0, 2)
        masses_lengths = [*rng.uniform(0.1, 5.0, 2), *rng.uniform(0.0, 1.0, 2), l1, l2]
        coms = [rng.uniform(0.0, 1.0) * l1, rng.uniform(0.0, 1.0) * l2, rng.uniform(1.0, 12.0)]
        dampers = rng.uniform(0.0, 1.0, 2) * (rng.random(2) < 0.7)
        p = np.concatenate([masses_lengths, coms, dampers, _coulomb(rng, 2, 10.0)])
        x = rng.uniform(-3.0, 3.0, 4)
    else:
        base = BASE[name]
        n_joints = 2 if base == "compass" else 3
        p = np.concatenate([sample_params(base, rng, False), _coulomb(rng, n_joints, 1.0)])
        x = sample_state(base, rng)
    o = O.oracle(name)
    S = o.joint_rows(0)
    for j in range(len(S)):  # some joints at rest
        if rng.random() < 0.4:
            x[o.n_x // 2 :] = _at_rest(S[j], x[o.n_x // 2 :])
    return x, p


def _at_rest(row, qd):
    """``qd`` with the joint of rate row ``row`` at rest (the least change)."""
    return qd - row * (row @ qd) / (row @ row)


@pytest.mark.parametrize("name", MODELS)
def test_phase_functions_and_start_phase_agree_with_oracle(name):
    """rhs, Jacobian and guards in every phase, energy, points and the start phase (the
    modes of the joints at rest) at 60 samples, to ``KERNEL_RTOL``."""
    c, o = Compiled(name), O.oracle(name)
    rng = np.random.default_rng(20261128)
    worst = Worst(name)
    for _ in range(60):
        x, p = _sample(name, rng)
        assert c.model.start_phase(x, p) == o.start_phase(x, p), (x.tolist(), p.tolist())
        for phase in range(len(o.directions)):
            where = f"phase {phase} x {x.tolist()} p {p.tolist()}"
            worst.check("rhs", c.rhs(phase, x, p), o.rhs(phase, x, p), KERNEL_RTOL, where)
            worst.check("jac", c.jac(phase, x, p), o.jac(phase, x, p), KERNEL_RTOL, where)
            worst.check("guards", c.guards(phase, x, p), o.guards(phase, x, p), KERNEL_RTOL, where)
        worst.check("energy", c.model.energy(x, p), o.energy(x, p), KERNEL_RTOL)
        worst.check("points", c.model.points(x, p), o.points(x, p), KERNEL_RTOL)
    worst.report()


def _friction_events(o, x, p):
    """(phase, guard, x, p) of the friction events armed at a consistent phase near ``x``."""
    n = o.n_x // 2
    phase = o.start_phase(x, p)
    base, modes = o.split(phase)
    S = o.joint_rows(base)
    first = len(o.directions[0]) - 2 * len(o.joint_rows(0))
    for j, mode in enumerate(modes):
        pj = p.copy()
        xj = x.copy()
        i_f = len(p) - len(o.joint_rows(0)) + j
        if mode == OF.STICK:  # its holding torque at the friction: the stick breaks
            _, lam = o._accel(phase, xj, pj)
            pj[i_f] = abs(lam[j]) * (1.0 - 1e-12)
            yield phase, first + 2 * j + 1, xj, pj
        elif p[i_f] > 0.0:  # the joint's rate reaches zero: the slip stops
            xj[n : n + len(S[j])] = _at_rest(S[j], xj[n : n + len(S[j])])
            yield phase, first + 2 * j, xj, pj


@pytest.mark.parametrize("name", MODELS)
def test_resets_agree_with_oracle(name):
    """Friction events (slip stops, stick breaks) at 200 samples and, for the walkers, the
    base model's events (heel strike, knee lock, trip, falls) at 200 branch cases each
    followed by the choice of every joint's mode: equal outcomes, states and impulses to
    ``KERNEL_RTOL``."""
    c, o = Compiled(name), O.oracle(name)
    rng = np.random.default_rng(11)
    worst = Worst(f"{name} reset")
    seen = set()
    cases = []
    for _ in range(200):
        x, p = _sample(name, rng)
        cases += list(_friction_events(o, x, p))
    if name in BASE:
        base = BASE[name]
        n_f = len(o.joint_rows(0))
        for phase, k, x, p in reset_cases(base, rng, 200):
            pf = np.concatenate([p, _coulomb(rng, n_f, 1.0)])
            cases.append((phase * 3**n_f + o.start_phase(x, pf) * (phase == 0), k, x, pf))
    for phase, k, x, p in cases:
        out_o, x_o, imp_o = o.reset(phase, k, x, p)
        out_c, x_c, imp_c = c.reset(phase, k, x, p)
        where = f"phase {phase} guard {k} x {x.tolist()} p {p.tolist()}"
        assert out_c == out_o, where
        if out_o[0] in (EVENT_STRIDE, EVENT_CONTINUE):
            worst.check("state", x_c, x_o, KERNEL_RTOL, where)
            worst.check("impulse", imp_c, imp_o, KERNEL_RTOL, where)
        seen.add((k, out_o[0]))
    worst.report()
    print(f"{name}: (guard, action) reached {sorted(seen)}")
    n_guards = len(o.directions[0])
    friction_guards = range(n_guards - 2 * len(o.joint_rows(0)), n_guards)
    assert {(k, EVENT_CONTINUE) for k in friction_guards} <= seen
    if name in BASE:
        assert (0 if name == "compass_coulomb" else 1, EVENT_STRIDE) in seen


SCENES = {
    "compass_coulomb_goswami": None,
    "kneed_coulomb_hsu": None,
    # stick and slip in a swinging double pendulum, to t_max
    "double_pendulum": {"coulomb_1": 2.0, "coulomb_2": 0.6, "damping_1": 0.1},
}


# the kneed walker's 36 friction phases in solve_ivp take the longest: the integration tier
@pytest.mark.parametrize(
    "key",
    [pytest.param(k, marks=pytest.mark.slow) if k.startswith("kneed") else k for k in SCENES],
)
def test_scene_runs_agree_with_oracle(key):
    """The scene's run (one stride from its reference gait; the double pendulum with dry
    friction to t = 4 s): every event, the final state and time to ``STRIDE_RTOL``; for the
    walkers the stride map's Jacobian to ``JACOBIAN_RTOL`` and the reference gait against
    the oracle's fixed point to ``FIXED_POINT_TOL``."""
    scene = load_scene(f"gaits/{key}.toml")
    model = scene.walker_model
    o = O.oracle(model.name)
    params = scene.params.replace(**SCENES[key]) if SCENES[key] else scene.params
    p = params.as_array()
    worst = Worst(key)
    if model.has_strides:
        x0 = np.array(scene.reference["state"], dtype=float)
        kw = {"n_strides": 1, "t_max": 20.0}
    else:
        x0 = np.array(scene.state, dtype=float)
        kw = {"n_strides": 0, "t_max": 4.0}
    sol = simulate(model, params, x0, output="events", rtol=1e-12, atol=1e-12, **kw)
    r = O.run(o, x0, p, phase=o.start_phase(x0, p), **kw)
    compare_runs(sol, r, worst, key)
    assert len(r.events) >= 1
    if model.has_strides:
        z = o.project(x0)
        res = StrideMap(model, params, rtol=1e-12, atol=1e-12)(z, jacobian=True)
        z_o, t_o, _ = O.stride(o, z, p)
        worst.check("section point", res.z, z_o, STRIDE_RTOL)
        scale = np.abs(res.jac).max()
        J = O.stride_jacobian(o, z, p)
        worst.check("Jacobian", res.jac / scale, J / scale, JACOBIAN_RTOL)
        z_fixed = z - np.linalg.solve(J - np.eye(len(z)), z_o - z)
        worst.check("fixed point", z, z_fixed, FIXED_POINT_TOL)
        worst.check("step time", scene.reference["step_time"], t_o, FIXED_POINT_TOL)
    worst.report()
