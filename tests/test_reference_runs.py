"""walker's own integrator on the course's double pendulum and on a kneed-walker stride,
against energy conservation and against scipy's solve_ivp (the independent reference)."""

import numpy as np
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp

from walker import get_model, load_scene, simulate
from walker.params import DoublePendulumParams

# The course's double pendulum (its double-pendulum exercise): q1 = pi/2 - 0.1 and q2 = pi in
# the course's angles from the downward vertical with q2 absolute; walker's double pendulum
# measures q1 from +x and q2 relative to link 1 (see tests/test_generated.py).
COURSE_STATE = np.array([-0.1, np.pi / 2 + 0.1, 0.0, 0.0])


def release(params, t_max, **options):
    """The course's double pendulum ``params`` released at :data:`COURSE_STATE` and run for
    ``t_max`` seconds (``n_strides = 0``: a model without strides runs to ``t_max``)."""
    return simulate("double_pendulum", params, COURSE_STATE, n_strides=0, t_max=t_max, **options)


def test_course_double_pendulum_energy_with_walkers_integrator():
    """10 s at rtol = atol = 1e-12: total energy within 1e-9 of its start, relative."""
    params = DoublePendulumParams.course()
    times = np.linspace(0.0, 10.0, 501)
    sol = release(params, 10.0, rtol=1e-12, atol=1e-12, output="samples", sample_times=times)
    assert sol.success
    kinetic, potential = get_model("double_pendulum").energies(sol.samples.x, params)
    energy = kinetic + potential
    assert kinetic.max() > 10.0  # the motion is far from trivial
    drift = np.abs(energy - energy[0]).max() / abs(energy[0])
    assert drift <= 1e-9, drift


KNEED = get_model("kneed")


def _stride_solve_ivp(x0, p, rtol):
    """One kneed stride with solve_ivp's own event handling and walker's compiled vector
    field and impact maps: unlocked phase to knee lock, locked phase to heel strike."""
    x, t0 = np.array(x0, dtype=float), 0.0
    for phase, guard, direction in ((0, 0, 1.0), (1, 1, -1.0)):

        def f(t, y, phase=phase):
            return KNEED.rhs(phase, y, p, t)

        def event(t, y, phase=phase, guard=guard):
            return KNEED.guards(phase, y, p, t)[guard]

        event.terminal = True
        event.direction = direction
        sol = solve_ivp(f, (t0, t0 + 5.0), x, method="DOP853", rtol=rtol, atol=rtol, events=event)
        assert sol.status == 1
        te, xe = sol.t_events[0][0], sol.y_events[0][0]
        x_new = KNEED.reset(phase, guard, xe, p, te)[3]
        x, t0 = x_new, te
    return x, t0


def test_kneed_stride_agrees_with_solve_ivp():
    """At rtol = atol = 1e-12 walker's stride equals solve_ivp(DOP853)'s to 1e-9 (measured
    ~2e-13), step time included."""
    scene = load_scene("gaits/kneed_hsu.toml")
    p = scene.params.as_array()
    ours = simulate("kneed", scene.params, scene.state, rtol=1e-12, atol=1e-12)
    ref, t_ref = _stride_solve_ivp(scene.state, p, 1e-12)
    assert ours.success
    assert_allclose(ours.x, ref, atol=1e-9, rtol=0)
    assert_allclose(ours.t, t_ref, atol=1e-9, rtol=0)


def test_kneed_energy_drift_inside_each_phase():
    """Between events the walker is conservative: along every accepted step of each swing
    phase the total energy stays within 10 rtol (relative) of its value at the phase start."""
    scene = load_scene("gaits/kneed_hsu.toml")
    model = get_model("kneed")
    rtol = 1e-10
    sol = simulate(
        "kneed", scene.params, scene.state, n_strides=2, rtol=rtol, atol=1e-12, output="full"
    )
    assert sol.success
    rec = sol.record
    kinetic, potential = model.energies(rec.x, scene.params)
    energy = kinetic + potential
    # segments: runs of equal phase between events (an event repeats its time stamp)
    cuts = np.flatnonzero(np.diff(rec.t) == 0.0) + 1
    n_checked = 0
    for seg in np.split(np.arange(len(rec.t)), cuts):
        if len(seg) < 3:
            continue
        e = energy[seg]
        assert np.abs(e - e[0]).max() <= 10 * rtol * abs(e[0]), np.abs(e - e[0]).max()
        n_checked += 1
    assert n_checked >= 4  # two strides: unlocked and locked phases of each
