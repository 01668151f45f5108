"""Viscous joint damping of the passive walkers (issue 8, item 4).

The compass gait carries a hip damper (``damping_hip``, on ``qd_swing - qd_stance``), the
kneed walker a hip damper (``qd2 - qd1``) and a swing-knee damper (``damping_knee``, on
``qd3 - qd2``, inactive once the knee is locked); both carry a stance-ankle damper
(``damping_ankle``, on the stance leg's rate relative to the slope, ``qd_stance`` / ``qd1``,
in every single-support phase).  Checked here:

* the energy balance ``dE/dt = -sum_j b_j w_j^2`` (the dampers' power) at random states,
  from the symbolic models and from the generated kernels, and ``dE/dt = 0`` without damping
  (also for the course's double pendulum, ``damping_1`` on ``qd1`` and ``damping_2`` on
  ``qd2``, joint 2 being relative);
* the impacts (heel strike, knee lock) do not depend on the damping;
* Goswami's compass gait continued in ``damping_hip`` and in ``damping_ankle`` from 0: how
  its walking speed changes, where the stable gait is lost and what the walker does beyond
  (an outcome, never an exception);
* Hsu Chen's kneed walker: a small knee or ankle damping changes the gait smoothly and
  slows it;
* Garcia's simplest walker (massless legs: a stance-ankle damper only, dimensionless, in
  units of ``M l^2 sqrt(g/l)``): ``dE/dt = -b l^2 sqrt(g/l) theta_dot^2`` per unit hip mass,
  and its gait continued in ``damping_ankle`` from 0.

Measured (walker DOP853; fixed points and branches at StrideMap's rtol = 1e-12, runs at
simulate's 1e-10): the hip damper makes the Goswami compass gait walk *faster*, not slower
-- speed 0.7288 m/s at b = 0 rising monotonically to 0.7909 m/s at b = 0.2530 N m s/rad,
where the stable gait is lost (natural continuation stops, the complex Floquet pair heading
for the real axis near +1: a fold); beyond it the walker falls forward.
The stance-ankle damper is the one that slows the compass gait, as the issue expects:
the speed falls monotonically, nearly linearly at first (-0.0264 m/s per N m s/rad at
b = 0; 0.7027 m/s at 1, 0.4963 at 10, 0.3350 at 20, 0.2392 at 30 N m s/rad), step length
shrinking and step time growing.  The gait stays stable up to a period doubling at
b = 32.825 N m s/rad (speed 0.2203 m/s, 30 % of the undamped one); beyond it a stable
period-two gait takes over (at b = 34, 0.031 away from the unstable period-one point),
and the period-one branch goes on, unstable and ever slower (0.1829 m/s at 40, 0.0766 at
100).  Started on the last stable gait (b = 32.25), the walker still walks 300 strides at
b = 40, 50 and 60 and falls forward after 5 strides at 70; from b = 80 on (every value
tried up to 1e4) it no longer gets over the stance foot and falls backward, within 10
strides, from 115 on before its first heel strike.  The knee damper does slow the kneed
walker (0.8370 m/s at 0 to 0.8242 m/s at 0.01), whose gait is lost before 0.015 N m s/rad,
where the bent knee trips; the ankle damper slows it too (0.8370 -> 0.8325 m/s at 0.01,
0.7926 at 0.1, 0.7497 at 0.2 N m s/rad, all stable).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from numpy.testing import assert_allclose

from walker import StrideMap
from walker.analysis.continuation import continue_branch
from walker.analysis.fixedpoint import find_fixed_point
from walker.models import get_model
from walker.params import CompassParams, DoublePendulumParams, KneedParams, SimplestParams
from walker.scene import load_scene
from walker.simulation.stride import simulate
from walker.status import EVENT_CONTINUE, EVENT_STRIDE, EVENT_TERMINAL, Status
from walker.symbolic import models

N_STATES = 50
TOL = 1e-12


def _index(family: str, name: str) -> int:
    """Position of parameter ``name`` in the ``p`` vector of ``family``."""
    return models.MODEL_PARAMS[family].index(name)


# Joint rates of each single-support model, as (parameter index, rate from qd) pairs; the
# stance ankle's rate is the stance leg's, relative to the (fixed) slope.
DAMPERS = {
    "compass": [
        (_index("compass", "damping_hip"), lambda qd: qd[1] - qd[0]),
        (_index("compass", "damping_ankle"), lambda qd: qd[0]),
    ],
    "kneed_unlocked": [
        (_index("kneed", "damping_hip"), lambda qd: qd[1] - qd[0]),
        (_index("kneed", "damping_knee"), lambda qd: qd[2] - qd[1]),
        (_index("kneed", "damping_ankle"), lambda qd: qd[0]),
    ],
    "kneed_locked": [
        (_index("kneed", "damping_hip"), lambda qd: qd[1] - qd[0]),
        (_index("kneed", "damping_ankle"), lambda qd: qd[0]),
    ],
    # the course's double pendulum: q2 is relative to link 1, so joint 2's rate is qd2
    "double_pendulum": [
        (_index("double_pendulum", "damping_1"), lambda qd: qd[0]),
        (_index("double_pendulum", "damping_2"), lambda qd: qd[1]),
    ],
}
FACTORIES = {
    "compass": models.compass,
    "kneed_unlocked": models.kneed_unlocked,
    "kneed_locked": models.kneed_locked,
    "double_pendulum": models.double_pendulum,
}
FAMILY = {
    "compass": "compass",
    "kneed_unlocked": "kneed",
    "kneed_locked": "kneed",
    "double_pendulum": "double_pendulum",
}


def double_pendulum_vector(rng, lengths, dampers) -> np.ndarray:
    """The course's double pendulum with links of ``lengths``, no dry friction: masses,
    inertias, centres of mass and g drawn in that order, then the dampers ``dampers()``."""
    l1, l2 = lengths
    drawn = dict(
        mass_1=rng.uniform(0.2, 3.0),
        mass_2=rng.uniform(0.2, 3.0),
        inertia_1=rng.uniform(0.0, 1.0),
        inertia_2=rng.uniform(0.0, 1.0),
        com_1=rng.uniform(0.0, 1.0) * l1,
        com_2=rng.uniform(0.0, 1.0) * l2,
        g=rng.uniform(1.0, 20.0),
    )
    b1, b2 = dampers()
    params = DoublePendulumParams.course().replace(
        length_1=l1, length_2=l2, damping_1=b1, damping_2=b2, **drawn
    )
    return params.as_array()


def _ground_and_dampers(rng, dampers, damped: bool) -> dict:
    """A walker's foot radius, slope and g, then the joint dampers named ``dampers`` (zero
    unless ``damped``), drawn in that order."""
    drawn = dict(
        foot_radius=rng.uniform(0.0, 0.2), slope=rng.uniform(-0.2, 0.2), g=rng.uniform(1.0, 20.0)
    )
    drawn.update({name: rng.uniform(0.0, 5.0) if damped else 0.0 for name in dampers})
    return drawn


def _random_params(name: str, rng, *, damped: bool) -> np.ndarray:
    """A random physical parameter vector (round feet, inertias, offsets, slope)."""
    if name == "double_pendulum":
        lengths = rng.uniform(0.3, 2.0, 2)
        b1, b2 = rng.uniform(0.0, 5.0, 2) if damped else (0.0, 0.0)
        return double_pendulum_vector(rng, lengths, lambda: (b1, b2))
    if name == "compass":
        base = CompassParams.goswami()
        p = base.replace(
            mass_hip=rng.uniform(0.5, 10.0),
            mass_leg=rng.uniform(0.5, 5.0),
            com_from_foot=rng.uniform(0.2, 1.0),
            com_to_hip=rng.uniform(0.2, 1.0),
            inertia_leg=rng.uniform(0.0, 0.5),
            **_ground_and_dampers(rng, ("damping_hip", "damping_ankle"), damped),
        )
    else:
        base = KneedParams.hsu_chen()
        p = base.replace(
            mass_hip=rng.uniform(0.1, 2.0),
            mass_thigh=rng.uniform(0.1, 2.0),
            mass_shank=rng.uniform(0.02, 1.0),
            inertia_thigh=rng.uniform(0.001, 0.1),
            inertia_shank=rng.uniform(0.001, 0.1),
            offset_thigh=rng.uniform(-0.1, 0.1),
            offset_shank=rng.uniform(-0.1, 0.1),
            **_ground_and_dampers(rng, ("damping_hip", "damping_knee", "damping_ankle"), damped),
        )
    return p.as_array()


def _damper_power(name: str, qd, p) -> float:
    """``-sum_j b_j w_j^2`` [W]: the rate at which the dampers remove energy."""
    return -sum(p[i] * rate(qd) ** 2 for i, rate in DAMPERS[name])


# ------------------------------------------------------------------- energy balance
class _Symbolic:
    """Fresh lambdified D, h - Q and the energy rate ``dE/dx . f`` of a model."""

    def __init__(self, model):
        q, qd, p = list(model.q), list(model.qd), list(model.params)
        self.D = sp.lambdify([q, qd, p], model.D, "numpy")
        self.h_forced = sp.lambdify([q, qd, p], model.forced_bias, "numpy")
        energy = model.K + model.P
        self.grad = sp.lambdify([q, qd, p], [sp.diff(energy, x) for x in q + qd], "numpy")
        qdd = sp.symbols(f"a_0:{model.n}", real=True)
        rate = model.energy_rate(sp.Matrix(qd + list(qdd)))
        self.rate = sp.lambdify([q, qd, list(qdd), p], rate, "numpy")


@pytest.mark.parametrize("damped", [True, False], ids=["damped", "undamped"])
@pytest.mark.parametrize("name", list(FACTORIES))
def test_symbolic_energy_rate_is_the_damper_power(name, damped):
    """Along ``qdd = -D^-1 (C qd + g - Q)``, ``dE/dt = -sum b_j w_j^2`` (zero undamped),
    to 1e-12 of the magnitude of the terms of ``dE/dx . f``."""
    model = FACTORIES[name]()
    num = _Symbolic(model)
    family = FAMILY[name]
    rng = np.random.default_rng(8 + 2 * damped + len(name))
    largest = 0.0
    for _ in range(N_STATES):
        p = _random_params(family, rng, damped=damped)
        q = rng.uniform(-np.pi, np.pi, model.n)
        qd = rng.normal(0.0, 2.0, model.n)
        D = np.asarray(num.D(q, qd, p), dtype=float)
        qdd = np.linalg.solve(D, -np.asarray(num.h_forced(q, qd, p), dtype=float).ravel())
        rate = float(num.rate(q, qd, qdd, p))
        grad = np.asarray(num.grad(q, qd, p), dtype=float)
        scale = np.abs(grad) @ np.abs(np.concatenate([qd, qdd]))
        expected = _damper_power(name, qd, p)
        assert_allclose(rate, expected, rtol=0, atol=TOL * scale)
        largest = max(largest, abs(expected))
    if damped:
        assert largest > 1.0  # the dampers did dissipate: the check above is not 0 = 0


def _generated_rate(model, prefix, q, qd, p):
    """``dE/dt = qd.(D qdd) + 1/2 qd.(D_dot qd) + qd.g`` from the generated C kernels of
    ``model`` (a :class:`walker.models.WalkerModel`), with ``qdd`` from the (damped)
    ``accel`` kernel; also ``Q.qd`` from the ``forcing`` kernel and ``qdd`` recomputed from
    ``mass_matrix``, ``bias`` and ``forcing``."""
    qdd = model.kernel(f"{prefix}accel", p, q, qd)
    D = model.kernel(f"{prefix}mass_matrix", p, q)
    dD = model.kernel(f"{prefix}dmass", p, q)
    g = model.kernel(f"{prefix}gravity", p, q)
    h = model.kernel(f"{prefix}bias", p, q, qd)
    Q = model.kernel(f"{prefix}forcing", p, q, qd)
    Ddot = np.tensordot(qd, dD, axes=1)
    terms = np.array([qd @ D @ qdd, 0.5 * qd @ Ddot @ qd, qd @ g])
    return terms.sum(), np.abs(terms).sum(), Q @ qd, qdd, np.linalg.solve(D, Q - h)


@pytest.mark.parametrize("name", list(FACTORIES))
def test_generated_kernels_dissipate_the_damper_power(name):
    """The compiled ``accel`` includes the damping exactly: ``dE/dt`` from the generated
    mass matrix, its derivatives and gravity equals ``-sum b_j w_j^2``; the ``forcing``
    kernel's power is the same; ``accel`` equals ``D^-1 (Q - h)`` from the other kernels."""
    if name in ("compass", "double_pendulum"):
        prefix, family = "", name
    else:
        prefix, family = name.split("_")[1] + "_", "kneed"
    K = get_model(family)
    n = 2 if name != "kneed_unlocked" else 3
    rng = np.random.default_rng(80 + n)
    for k in range(N_STATES):
        p = _random_params(family, rng, damped=k > 0)  # the first sample is undamped
        q = rng.uniform(-np.pi, np.pi, n)
        qd = rng.normal(0.0, 2.0, n)
        rate, scale, power, qdd, qdd_ref = _generated_rate(K, prefix, q, qd, p)
        expected = _damper_power(name, qd, p)
        assert_allclose(rate, expected, rtol=0, atol=TOL * scale)
        assert_allclose(power, expected, rtol=TOL, atol=TOL * scale)
        assert_allclose(qdd, qdd_ref, rtol=1e-10, atol=1e-10 * np.abs(qdd_ref).max())
        if k == 0:
            assert power == 0.0 and abs(rate) <= TOL * scale


def test_locked_forcing_is_the_projected_unlocked_forcing():
    """With the knee locked (``qd3 = qd2``) the locked model's forcing is ``T^T Q``, ``T``
    mapping ``(qd1, qd2)`` to ``(qd1, qd2, qd2)``: the knee damper drops out exactly, the
    hip and stance-ankle dampers stay."""
    un, lo = models.kneed_unlocked(), models.kneed_locked()
    q1d, q2d, q3d = un.qd
    p1d, p2d = lo.qd
    Q = un.forcing.subs({q1d: p1d, q2d: p2d, q3d: p2d})
    T = sp.Matrix([[1, 0], [0, 1], [0, 1]])
    assert sp.expand(T.T * Q - lo.forcing) == sp.zeros(2, 1)
    knee, hip, ankle = (
        lo.params[_index("kneed", name)]
        for name in ("damping_knee", "damping_hip", "damping_ankle")
    )
    assert knee not in lo.forcing.free_symbols
    assert {hip, ankle} <= lo.forcing.free_symbols


# ----------------------------------------------------------------------------- impacts
def test_impacts_do_not_depend_on_damping():
    """Heel strike (compass, kneed) and knee lock are impulsive: the finite damping torques
    transmit no impulse, so the post-impact state and impulses are identical."""
    compass, kneed = get_model("compass"), get_model("kneed")
    xc = np.array([-0.3234, 0.2187, -1.0918, -0.3772])  # legs symmetric about the normal
    xc[0] = -2 * CompassParams.goswami().slope - xc[1]
    out = []
    for b in (0.0, 3.0):
        p = CompassParams.goswami().replace(damping_hip=b, damping_ankle=2 * b).as_array()
        action, _, status, x_new, imp = compass.reset(0, 0, xc, p)  # heel strike
        assert action == EVENT_STRIDE
        out.append((status, x_new, imp))
    assert out[0][0] == out[1][0] == 0
    assert_allclose(out[1][1], out[0][1], rtol=0, atol=0)
    assert_allclose(out[1][2], out[0][2], rtol=0, atol=0)

    xk = np.array([0.15, -0.25, -0.25, -1.0, 0.5, 1.2])
    res = []
    for bh, bk, ba in ((0.0, 0.0, 0.0), (2.0, 3.0, 4.0)):
        p = KneedParams.hsu_chen().replace(damping_hip=bh, damping_knee=bk, damping_ankle=ba)
        p = p.as_array()
        action, phase, s1, x_lock, imp_lock = kneed.reset(0, 0, xk, p)  # knee lock
        assert (action, phase) == (EVENT_CONTINUE, 1)
        xh = x_lock.copy()  # then a heel strike, the swing foot ahead on the slope
        xh[0] = -abs(xh[0]) - KneedParams.hsu_chen().slope
        xh[1] = xh[2] = -2 * KneedParams.hsu_chen().slope - xh[0]
        action, _, s2, x_hs, imp_hs = kneed.reset(1, 1, xh, p)
        assert action in (EVENT_STRIDE, EVENT_TERMINAL)
        res.append((s1, x_lock, imp_lock, s2, x_hs, imp_hs))
    assert res[0][0] == res[1][0] == 0
    for a, b in zip(res[0][1:3] + res[0][4:], res[1][1:3] + res[1][4:], strict=True):
        assert_allclose(b, a, rtol=0, atol=0)
    assert res[0][3] == res[1][3]


# ----------------------------------------------------------------- the compass gait
def _ankle_damping_branch(scene_name, model, *, to, step, max_step):
    """The scene's gait (checked against its recorded digits) continued in ``damping_ankle``
    from 0 to ``to`` by natural continuation, through exactly one period doubling, with the
    gait stable exactly before it.  Returns (params, StrideMap, fp0, branch, flip)."""
    scene = load_scene(f"gaits/{scene_name}.toml")
    base = scene.params
    assert base.damping_ankle == 0.0
    P0 = StrideMap(model, base, parameter_name="damping_ankle")
    fp0 = find_fixed_point(P0, P0.project(scene.state))
    assert fp0.success
    assert_allclose(fp0.state, scene.reference["state"], rtol=0, atol=1e-9)
    P = P0.with_parameter(1e-6)
    branch = continue_branch(P, fp0.section, to=to, method="natural", step=step, max_step=max_step)
    assert branch.status == Status.COMPLETED, branch.message
    assert branch.parameter[-1] == to
    [flip] = branch.bifurcations
    assert flip.kind == "period_doubling"
    assert np.array_equal(branch.stable, branch.parameter < flip.parameter_value)
    return base, P, fp0, branch, flip


def _period_two_past(model, params, near):
    """Past a period doubling: the unstable period-one point near ``near`` and the stable
    period-two gait reached by iterating from a 1e-3 kick off it until it settles."""
    P = StrideMap(model, params)
    one = find_fixed_point(P, near)
    assert one.success and not one.stable, one.message
    z = one.section.copy()
    z[0] += 1e-3
    for _ in range(300):
        z = P(z).z
    two = find_fixed_point(P, z, period=2)
    assert two.success and two.stable, two.message
    return one, two


def _walking_speed(z, step_time, params):
    """Walking speed [m/s]: step length ``2 L sin(half inter-leg angle)`` over step time;
    just after heel strike the half inter-leg angle is ``q_stance + slope`` (``z[0]``: the
    compass gait's ``q_stance``, the kneed walker's ``q1``, both legs straight)."""
    return 2.0 * params.leg_length * math.sin(z[0] + params.slope) / step_time


@pytest.mark.regression_pin
def test_hip_damping_continuation_of_the_compass_gait():
    """REGRESSION PIN: the undamped speed 0.728774 m/s and the fold at b = 0.2530 are walker's own;
    the monotone trends and outcomes are the checks.

    Goswami's 3 degree gait (gaits/compass_goswami.toml) followed in ``damping_hip``.

    Natural continuation (the parameter is bounded below by 0 and ``continue_branch`` takes
    a central difference in it, so the branch starts at 1e-6, next to the exact b = 0 fixed
    point).  Measured: every point is stable; step length and step time both shrink, the
    step time faster, so the walking speed *rises* monotonically (0.7288 -> 0.7909 m/s, +8.5%);
    the continuation stops (NOT_CONVERGED) at b = 0.2530 N m s/rad with the complex Floquet
    pair near the real axis at |m| = 0.84 -- the stable gait is lost in a fold.  Past it, the
    walker started on the last gait falls forward: a status, not an exception."""
    scene = load_scene("gaits/compass_goswami.toml")
    base = scene.params
    assert base.damping_hip == 0.0
    P0 = StrideMap("compass", base, parameter_name="damping_hip")
    fp0 = find_fixed_point(P0, P0.project(scene.state))
    assert fp0.success
    assert_allclose(fp0.state, scene.reference["state"], rtol=0, atol=1e-9)

    P = P0.with_parameter(1e-6)
    branch = continue_branch(P, fp0.section, to=0.4, method="natural", step=0.01, max_step=0.02)
    assert branch.status == Status.NOT_CONVERGED, branch.message
    b_lost = branch.parameter[-1]
    assert 0.25 < b_lost < 0.26, b_lost
    assert branch.stable.all()
    assert np.abs(branch.multipliers[-1]).max() > 0.8  # approaching the fold at +1

    bs = np.concatenate([[0.0], branch.parameter])
    zs = np.vstack([fp0.section, branch.sections])
    ts = np.concatenate([[fp0.step_time], branch.step_times])
    speed = np.array([_walking_speed(z, t, base) for z, t in zip(zs, ts, strict=True)])
    length = 2.0 * base.leg_length * np.sin(zs[:, 0] + base.slope)
    assert np.all(np.diff(bs) > 0)
    assert np.all(np.diff(length) < 0) and np.all(np.diff(ts) < 0)
    assert np.all(np.diff(speed) > 0)
    assert_allclose(speed[0], 0.728774, rtol=1e-5, atol=0)
    assert speed[-1] / speed[0] - 1.0 > 0.08

    x_last = P.lift(branch.sections[-1])
    for b in (0.26, 1.0, 50.0):
        sol = simulate("compass", base.replace(damping_hip=b), x_last, n_strides=30)
        assert not sol.success
        assert sol.status == Status.FELL_FORWARD, (b, sol.message)


@pytest.mark.regression_pin
def test_ankle_damping_slows_the_compass_gait():
    """REGRESSION PIN: the undamped speed 0.728774 m/s and the period doubling at b = 32.825 are
    walker's own; the monotone trends and outcomes are the checks.

    Goswami's 3 degree gait (gaits/compass_goswami.toml) followed in ``damping_ankle``.

    Natural continuation from 1e-6 (as for the hip damper) to 40 N m s/rad.  Measured: the
    walking speed falls monotonically along the whole period-one branch (0.7288 m/s at 0,
    0.2203 at the period doubling, 0.1829 at 40), step length shrinking and step time
    growing; every point before the period doubling at b = 32.825 (multiplier -1; located
    to 1e-10 N m s/rad for any continuation step from 0.25 to 4) is stable, every point
    after it unstable, and the last stable point (b = 32.25) walks at 31 % of the undamped speed.
    At b = 34 the stable gait has period two (0.031 from the unstable period-one point).
    Large damping stops the walker: started on the last stable gait, at b = 150 and 1000
    the hip no longer gets over the stance foot and the walker falls backward before its
    first heel strike -- a status, not an exception.
    """
    base, P, fp0, branch, flip = _ankle_damping_branch(
        "compass_goswami", "compass", to=40.0, step=0.5, max_step=1.0
    )
    assert 32.8 < flip.parameter_value < 32.85, flip.parameter_value
    assert branch.stable.sum() > 20  # the stable part is resolved, not one or two points

    bs = np.concatenate([[0.0], branch.parameter])
    zs = np.vstack([fp0.section, branch.sections])
    ts = np.concatenate([[fp0.step_time], branch.step_times])
    speed = np.array([_walking_speed(z, t, base) for z, t in zip(zs, ts, strict=True)])
    length = 2.0 * base.leg_length * np.sin(zs[:, 0] + base.slope)
    assert np.all(np.diff(bs) > 0)
    assert np.all(np.diff(length) < 0) and np.all(np.diff(ts) > 0)
    assert np.all(np.diff(speed) < 0)
    assert_allclose(speed[0], 0.728774, rtol=1e-5, atol=0)
    last_stable = np.flatnonzero(branch.stable)[-1]
    assert speed[1 + last_stable] / speed[0] < 1.0 / 3.0

    # past the period doubling: a stable period-two gait, away from the period-one point
    # (iterated from a 1e-3 kick off the unstable period-one point, which grows by
    # |m| = 1.025 per stride, until it settles)
    one, two = _period_two_past("compass", base.replace(damping_ankle=34.0), flip.section)
    assert np.abs(two.section - one.section).max() > 0.01

    x_last = P.lift(branch.sections[last_stable])
    for b in (150.0, 1000.0):
        sol = simulate("compass", base.replace(damping_ankle=b), x_last, n_strides=30)
        assert not sol.success
        assert sol.status == Status.FELL_BACKWARD, (b, sol.message)


# ------------------------------------------------------------------ the kneed walker
@pytest.mark.regression_pin
def test_small_knee_damping_changes_the_kneed_gait_smoothly():
    """REGRESSION PIN: the undamped speed 0.837009 m/s is walker's own (Hsu Chen's thesis digits
    come from explicit Euler, see tests/test_gaits.py).

    Hsu Chen's gait (gaits/kneed_hsu.toml) at ``damping_knee`` = 0 .. 0.01 N m s/rad,
    each fixed point warm-started from the previous one: all stable; the shift of the fixed
    point is linear in b for small b (from 1e-4 to 2e-4 it doubles, to 3 %; the curvature
    is strong: from 1e-3 to 2e-3 it grows only 1.78 times); the knee damper slows
    the walker monotonically (0.8370 -> 0.8242 m/s).  At 0.015 the knee no longer straightens
    before the foot reaches the ground: the walker, started on the 0.01 gait, trips."""
    scene = load_scene("gaits/kneed_hsu.toml")
    base = scene.params
    assert (base.damping_hip, base.damping_knee) == (0.0, 0.0)
    z = StrideMap("kneed", base).project(scene.state)
    values = (0.0, 1e-4, 2e-4, 0.001, 0.002, 0.005, 0.01)
    sections, speeds = [], []
    for b in values:
        P = StrideMap("kneed", base.replace(damping_knee=b))
        fp = find_fixed_point(P, z)
        assert fp.success and fp.stable, (b, fp.message)
        z = fp.section
        sections.append(z)
        speeds.append(_walking_speed(z, fp.step_time, base))
    sections = np.array(sections)
    assert_allclose(
        sections[0], StrideMap("kneed", base).project(scene.reference["state"]), rtol=0, atol=1e-9
    )
    d1 = np.linalg.norm(sections[1] - sections[0])
    d2 = np.linalg.norm(sections[2] - sections[0])
    assert d1 > 1e-5  # the damping does move the gait
    assert_allclose(d2 / d1, 2.0, rtol=0.03, atol=0)
    assert np.all(np.diff(speeds) < 0)
    assert_allclose(speeds[0], 0.837009, rtol=1e-5, atol=0)

    x_last = P.lift(sections[-1])
    sol = simulate("kneed", base.replace(damping_knee=0.015), x_last, n_strides=30)
    assert sol.status == Status.TRIPPED, sol.message


@pytest.mark.regression_pin
def test_small_ankle_damping_slows_the_kneed_walker():
    """REGRESSION PIN: the undamped speed 0.837009 m/s is walker's own.

    Hsu Chen's gait (gaits/kneed_hsu.toml) at ``damping_ankle`` = 0, 0.01, 0.1 N m s/rad,
    each fixed point warm-started from the previous one: all stable, and the ankle damper
    slows the walker (measured 0.8370 -> 0.8325 -> 0.7926 m/s, nearly linearly: the drop
    at 0.1 is 9.85 times that at 0.01)."""
    scene = load_scene("gaits/kneed_hsu.toml")
    base = scene.params
    assert base.damping_ankle == 0.0
    z = StrideMap("kneed", base).project(scene.state)
    speeds = []
    for b in (0.0, 0.01, 0.1):
        P = StrideMap("kneed", base.replace(damping_ankle=b))
        fp = find_fixed_point(P, z)
        assert fp.success and fp.stable, (b, fp.message)
        z = fp.section
        speeds.append(_walking_speed(z, fp.step_time, base))
    assert_allclose(speeds[0], 0.837009, rtol=1e-5, atol=0)
    drops = speeds[0] - np.array(speeds[1:])
    assert drops[0] > 1e-3  # 0.01 N m s/rad already costs more than 1 mm/s
    assert drops[1] > 5 * drops[0]  # and the speed keeps falling


# ----------------------------------------------------------------- the simplest walker
def test_simplest_walker_energy_rate_is_the_ankle_damper_power():
    """Garcia's walker with the stance-ankle damper, at random states and parameters:
    ``walker.models.simplest.energy`` is ``(l^2 theta_dot^2 / 2, g l cos(theta - gamma))``
    per unit hip mass, and along the compiled vector field (the generated ``accel``
    kernel, through the model's ``rhs``) ``dE/dt = -b l^2 sqrt(g/l) theta_dot^2``, to 1e-12
    of the magnitude of the terms; zero for b = 0.  With g = l = 1: ``-b theta_dot^2``."""
    simplest = get_model("simplest")
    rng = np.random.default_rng(1998)
    largest = 0.0
    for k in range(N_STATES):
        slope, g, l = rng.uniform(-0.1, 0.1), rng.uniform(0.5, 10.0), rng.uniform(0.5, 2.0)
        if k % 2 == 0:
            g = l = 1.0
        b = 0.0 if k < 5 else rng.uniform(0.0, 2.0)
        p = SimplestParams(slope=slope, g=g, leg_length=l, damping_ankle=b).as_array()
        x = np.concatenate([rng.uniform(-1.0, 1.0, 2), rng.normal(0.0, 1.0, 2)])
        theta, theta_d = x[0], x[2]
        kinetic, potential = simplest.energy(x, p)
        assert_allclose(kinetic, 0.5 * l * l * theta_d**2, rtol=1e-15, atol=0)
        assert_allclose(potential, g * l * math.cos(theta - slope), rtol=1e-15, atol=1e-15)
        dx = simplest.rhs(0, x, p)
        terms = np.array([l * l * theta_d * dx[2], -g * l * math.sin(theta - slope) * theta_d])
        expected = -b * l * l * math.sqrt(g / l) * theta_d**2
        assert_allclose(terms.sum(), expected, rtol=0, atol=TOL * np.abs(terms).sum())
        largest = max(largest, abs(expected))
    assert largest > 0.5  # the damper did dissipate: the check is not 0 = 0


def _simplest_speed(z, step_time):
    """Walking speed [l sqrt(g/l)]: step length ``2 l sin(theta*)`` over step time (the legs
    at +-theta* from the slope normal at heel strike), with g = l = 1."""
    return 2.0 * math.sin(z[0]) / step_time


@pytest.mark.regression_pin
def test_ankle_damping_slows_the_simplest_walker_until_it_stops():
    """REGRESSION PIN: the speeds 0.10249884 .. 0.06016216, the period doubling at b =
    0.2221955396 and the last stable point 0.205 are walker's own.

    Garcia's gait at gamma = 0.009 (gaits/simplest_garcia.toml) followed in
    ``damping_ankle`` (dimensionless, units of M l^2 sqrt(g/l)) from 0.

    Natural continuation from 1e-6 to 0.3.  Measured: the walking speed (step length
    ``2 sin(theta*)`` over step time, g = l = 1) falls monotonically along the whole
    period-one branch, step length shrinking and step time growing: 0.10249884 at b = 0
    (Garcia's gait), 0.09785630 at 0.01, 0.07976322 at 0.05, 0.06016216 at 0.1.  Every point
    before a period doubling at b = 0.2221955396 (multiplier -1; the same to 2e-12 for
    continuation steps 0.005 to 0.05) is stable, every point after it unstable; at the last
    stable point (b = 0.205) the walker moves at 34 % of Garcia's speed.  At b = 0.25 a stable
    period-two gait (0.0038 from the unstable period-one point) takes over; further on
    (0.27 .. 0.29) the period-two gait doubles again and the attractor becomes chaotic
    (from the b = 0.22 gait, some values walk 1000 strides and others, 0.288 and 0.294,
    fall forward).  Started on the last stable period-one gait of this branch
    (b = 0.205), the walker still walks 30 strides at b = 0.23 and 0.25, falls forward
    after 2 strides at 0.28 and after 1 at 0.3 (t = 10.956), and from b = 0.34 on (every
    value tried up to 100) it no longer gets over its stance foot and falls backward
    before its first heel strike -- the same outcome, stride count and time (to 2e-6) at
    rtol 1e-8, 1e-10 and 1e-12: a status, not an exception.
    """
    base, P, fp0, branch, flip = _ankle_damping_branch(
        "simplest_garcia", "simplest", to=0.3, step=0.01, max_step=0.02
    )
    assert_allclose(flip.parameter_value, 0.2221955396, rtol=0, atol=1e-8)
    assert branch.stable.sum() > 10  # the stable part is resolved, not one or two points

    bs = np.concatenate([[0.0], branch.parameter])
    zs = np.vstack([fp0.section, branch.sections])
    ts = np.concatenate([[fp0.step_time], branch.step_times])
    speed = np.array([_simplest_speed(z, t) for z, t in zip(zs, ts, strict=True)])
    assert np.all(np.diff(bs) > 0)
    assert np.all(np.diff(zs[:, 0]) < 0) and np.all(np.diff(ts) > 0)
    assert np.all(np.diff(speed) < 0)
    assert_allclose(speed[0], 0.10249884, rtol=1e-7, atol=0)
    last_stable = np.flatnonzero(branch.stable)[-1]
    assert speed[1 + last_stable] / speed[0] < 0.36

    # fixed points at given damping, warm-started along the branch: the measured speeds
    z = fp0.section
    for b, expected in ((0.01, 0.09785630), (0.05, 0.07976322), (0.1, 0.06016216)):
        fp = find_fixed_point(StrideMap("simplest", base.replace(damping_ankle=b)), z)
        assert fp.success and fp.stable, (b, fp.message)
        z = fp.section
        assert_allclose(_simplest_speed(z, fp.step_time), expected, rtol=1e-6, atol=0)

    # past the period doubling: a stable period-two gait, away from the period-one point
    # (iterated from a 1e-3 kick off the unstable period-one point until it settles)
    one, two = _period_two_past("simplest", base.replace(damping_ankle=0.25), flip.section)
    assert np.abs(two.section - one.section).max() > 2e-3

    # large damping: the walker no longer walks (an outcome, not an exception)
    x_last = P.lift(branch.sections[last_stable])
    assert_allclose(branch.parameter[last_stable], 0.205, rtol=0, atol=1e-5)
    sol = simulate("simplest", base.replace(damping_ankle=0.3), x_last, n_strides=30)
    assert sol.status == Status.FELL_FORWARD and sol.n_strides == 1, sol.message
    for b in (0.35, 1.0, 100.0):
        sol = simulate("simplest", base.replace(damping_ankle=b), x_last, n_strides=30)
        assert not sol.success
        assert sol.status == Status.FELL_BACKWARD, (b, sol.message)
        assert sol.n_strides == 0
