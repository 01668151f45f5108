"""Checks of an HZD walker's gait, for the three-link (``tests/test_actuated.py``) and the
five-link walker (``tests/test_five_link.py``): the restricted map, the zero dynamics, the
full-order orbit, its scene, its energy balance and its outcomes.

``name`` is the walker's model name, ``model`` its module in :mod:`walker.models`
(``N_Q`` joint angles; the state is ``q``, ``qd``, then the actuators' work and the
saturated time), ``o`` the orbit of :func:`walker.models.hzd.restricted_fixed_point` and ``fp``
the full-order fixed point of :func:`walker.analysis.fixedpoint.find_fixed_point`.
"""

import numpy as np
from numpy.testing import assert_allclose

from walker.models import hzd
from walker.scene import load_scene
from walker.simulation.stride import StrideMap, simulate
from walker.status import Status


def assert_not_invariant(raw):
    """The Bezier design ``raw`` is not hybrid invariant: a residual over 1e-2."""
    h0, lfh0 = hzd.invariance_residual(raw)
    assert np.max(np.abs(np.r_[h0, lfh0])) > 1e-2


def invariant_design(params):
    """:func:`walker.models.hzd.make_invariant` of ``params``, checked: invariance h(Delta(q-)) = 0
    and L_f h(Delta(q-, qd-)) = 0 (1e-12)."""
    design = hzd.make_invariant(params)
    h, lfh = hzd.invariance_residual(design)
    assert_allclose(h, 0.0, rtol=0, atol=1e-12)
    assert_allclose(lfh, 0.0, rtol=0, atol=1e-12)
    return design


def assert_restricted_map_multiplier(params, o):
    """The multiplier of the restricted map is the closed form delta_zero^2 (1e-8), inside
    (0, 1); one map from the orbit returns to it (1e-12) with the impact impulse inside the
    friction cone."""
    assert o.success
    assert_allclose(o.multiplier, o.multiplier_closed_form, rtol=0, atol=1e-8)
    assert 0.0 < o.multiplier < 1.0
    r = hzd.restricted_map(params, o.theta_dot_plus)
    assert r.status == Status.COMPLETED
    assert_allclose(r.theta_dot_plus, o.theta_dot_plus, rtol=0, atol=1e-12)
    # the impact impulse is inside the friction cone with margin
    assert r.impulse[1] > 0 and abs(r.impulse[0]) < params.friction * r.impulse[1]


def _compiled(module):
    """The :class:`walker.models.WalkerModel` of a model module (its compiled functions)."""
    from walker.models import get_model

    return get_model(module.__name__.rsplit(".", 1)[1])


def assert_zero_dynamics_on_surface(model, P, thetas, thd_draw):
    """At each ``theta`` of ``thetas`` and a rate ``thd_draw()`` the closed-loop stance
    accelerations on the surface equal the zero dynamics' (1e-11)."""
    p = P.as_array()
    n = model.N_Q
    for theta in thetas:
        thd = thd_draw()
        q, sigma, dsigma = hzd.surface(P, theta)
        x = np.r_[q, sigma * thd, 0.0, 0.0]
        dx = _compiled(model).rhs(0, x, p)
        thdd = hzd.zero_dynamics_accel(P, theta, thd)
        assert_allclose(dx[n : 2 * n], sigma * thdd + dsigma * thd**2, rtol=1e-11, atol=1e-11)


def converged_run(name, P, start, n_strides, orbit_section):
    """The run of ``n_strides`` strides from the lifted section point ``start``: it
    completes, ends on ``orbit_section`` (1e-6) and never saturates."""
    S = StrideMap(name, P)
    sol = simulate(name, P, S.lift(start), n_strides=n_strides)
    assert sol.status == Status.COMPLETED, sol.message
    assert_allclose(S.project(sol.x), orbit_section, rtol=0, atol=1e-6)
    assert sol.x[-1] == 0.0  # never saturated
    return sol


def assert_full_order_is_hzd(fp, o, section_atol):
    """The full-order orbit is the HZD orbit (``section_atol``), stable, with the dominant
    multiplier delta_zero^2 (1e-7, real), the transverse ones < 1e-3, the same step time
    (1e-9 relative)."""
    assert fp.success, fp.message
    assert fp.stable and np.all(np.abs(fp.multipliers) < 1.0)
    assert_allclose(fp.section, o.section, rtol=0, atol=section_atol)
    assert_allclose(fp.multipliers[0].real, o.multiplier_closed_form, rtol=0, atol=1e-7)
    assert fp.multipliers[0].imag == 0.0
    assert np.all(np.abs(fp.multipliers[1:]) < 1e-3)
    assert_allclose(fp.step_time, o.step_time, rtol=1e-9)


def assert_scene_reference(path, params, fp, n_q):
    """The scene at ``path`` holds ``params``, the orbit's angles and rates (1e-10) and its
    multipliers to the scene's own tolerance."""
    scene = load_scene(path)
    assert scene.params == params
    assert_allclose(scene.state[: 2 * n_q], fp.state[: 2 * n_q], rtol=0, atol=1e-10)
    ref = scene.reference
    mult = np.asarray(ref["multipliers"], dtype=complex)
    assert_allclose(mult, fp.multipliers, rtol=0, atol=ref["tolerance"])


def assert_work_pays_impact(name, model, P, state):
    """Over one stride from ``state`` the actuators' work equals the heel strike's kinetic
    energy loss (1e-9 relative), which is over a joule."""
    p = P.as_array()
    sol = simulate(name, P, state, n_strides=1, output="events")
    assert sol.status == Status.COMPLETED
    x_pre, x_post = sol.events.x_pre[-1], sol.events.x_post[-1]
    loss = _compiled(model).energy(x_pre, p)[0] - _compiled(model).energy(x_post, p)[0]
    assert loss > 1.0  # joules: the impact is not trivial
    assert_allclose(sol.x[2 * model.N_Q], loss, rtol=1e-9)


def assert_saturates(name, model, P, state):
    """Over one stride from ``state`` the torque saturates and never exceeds the limit."""
    p = P.as_array()
    sol = simulate(name, P, state, n_strides=1, output="full")
    assert sol.x[2 * model.N_Q + 1] > 0.0
    u = np.array([_compiled(model).torques(x, p) for x in sol.record.x])
    assert np.max(np.abs(u)) <= P.torque_limit


def assert_slips(name, P, state):
    """Two strides from ``state`` end in a nonphysical impact at a heel strike or a friction
    guard: a status, not a crash."""
    sol = simulate(name, P, state, n_strides=2, output="events")
    assert sol.status == Status.NONPHYSICAL_IMPACT
    assert sol.events.guard[-1] in (0, 3, 4)
