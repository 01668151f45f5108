"""Gait measures (walker/analysis/measures.py) against independent references.

* Passive gaits: on a periodic gait the energy lost (sum of the kinetic energy lost at each
  impact, from the compiled energy function, plus what damping and friction take between
  impacts) must equal the potential energy released, ``weight * distance * sin(slope)``,
  where the distance comes from the drawn geometry (compiled points) and the weight from the
  parameters: so the cost of transport equals ``sin(slope)``.  Checked on every shipped
  passive gait, and on round-footed variants (the rolling contact moves the stance frame).
* The rimless wheel against its closed form (derived in tests/test_rimless_wheel.py): step
  length ``2 l sin(alpha)``, impact loss ``sin^2(2 alpha)`` of the kinetic energy before,
  with the pre-impact rate ``w* / cos(2 alpha)``.
* Actuated gaits: the net, positive and absolute actuator work are checked against the time
  integral of the actuator power, evaluated by the compiled right-hand side at the samples
  of a separate, densely sampled run and integrated with scipy (Simpson's rule for the
  net work, the trapezoid rule for the positive part and the absolute value).  And energy
  balance: net actuator work plus the potential energy released equals the energy lost.
"""

import ctypes
import glob
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import simpson, trapezoid

from walker.analysis.fixedpoint import find_fixed_point
from walker.analysis.measures import (
    GaitMeasures,
    branch_measures,
    cycle_measures,
    map_cycle_measures,
    total_mass,
)
from walker.scene import load_scene
from walker.simulation.stride import StrideMap, simulate, solver_settings

SCENES = sorted(glob.glob("gaits/*.toml"))


def _gait(path, overrides=None):
    scene = load_scene(path, overrides=overrides)
    P = StrideMap.from_scene(scene)
    fp = find_fixed_point(P, P.project(scene.state), period=max(1, scene.compute.strides))
    return scene, P, fp


def _passive_scenes():
    out = []
    for path in SCENES:
        scene = load_scene(path)
        model = scene.walker_model
        if model.has_strides and "actuator_work" not in model.state_names:
            out.append(path)
    return out


@pytest.mark.parametrize("path", _passive_scenes())
def test_passive_cost_of_transport_is_sin_slope(path):
    scene, P, fp = _gait(path)
    if not fp.success:
        # the one shipped passive scene without a gait says so in its description
        assert "NO GAIT" in scene.description, (path, fp.status)
        return
    m = cycle_measures(P.model, P.params, fp.state, period=fp.period, settings=solver_settings(P))
    slope = float(scene.params.slope)
    assert m.n_steps == fp.period
    assert_allclose(m.cost_of_transport, math.sin(slope), rtol=0, atol=1e-9)
    assert_allclose(m.step_time * m.n_steps, fp.step_time, rtol=1e-9, atol=0)
    assert_allclose(m.speed, m.step_length / m.step_time, rtol=1e-12, atol=0)
    assert m.energy_lost == pytest.approx(
        sum(m.impact_losses.values()) + m.energy_dissipated, rel=1e-12, abs=1e-15
    )
    assert all(v > 0 for v in m.impact_losses.values())
    assert math.isnan(m.cost_of_transport_positive)


@pytest.mark.parametrize(
    "path", ["gaits/compass_goswami.toml", "gaits/kneed_hsu.toml", "gaits/three_link_book.toml"]
)
def test_map_cycle_measures_is_cycle_measures(path):
    """What a fixed-point sweep measures per point (map_cycle_measures: the cycle run on the
    map's prepared system) is cycle_measures at the map's settings, bit for bit, at the
    scene's gait and at a nearby slope; passive gaits cost sin(slope) (the energy balance
    of the module docstring), an actuated one takes cycle_measures itself."""
    scene, P, fp = _gait(path)
    assert fp.success, fp.message
    other = P._retargeted(P.params.replace(slope=float(P.params.slope) * 1.03))
    for smap in (P, other):
        gait = find_fixed_point(smap, fp.section, period=fp.period, tol=1e-10)
        assert gait.success, gait.message
        settings = solver_settings(smap)
        ref = cycle_measures(
            smap.model, smap.params, gait.state, period=gait.period, settings=settings
        )
        fast = map_cycle_measures(smap, gait.state, period=gait.period)
        a, b = ref.to_dict(), fast.to_dict()
        assert list(a) == list(b)
        for key in a:
            assert a[key] == b[key] or (math.isnan(a[key]) and math.isnan(b[key])), key
        if "actuator_work" not in smap.model.state_names:
            slope = float(smap.params.slope)
            assert_allclose(fast.cost_of_transport, math.sin(slope), rtol=0, atol=1e-9)
    nan_state = np.full(P.model.n_x, np.nan)
    assert math.isnan(map_cycle_measures(P, nan_state).step_length)


@pytest.mark.parametrize(
    "path", ["gaits/compass_goswami.toml", "gaits/kneed_hsu.toml"], ids=["compass", "kneed"]
)
def test_round_feet_cost_of_transport_is_sin_slope(path):
    """A rolling foot moves the stance contact during the stance; the distance must follow
    the stance frame, not the foot's contact point at the strike."""
    scene, P, fp = _gait(path, {"foot_radius": 0.05})
    assert fp.success, fp.message
    m = cycle_measures(P.model, P.params, fp.state, settings=solver_settings(P))
    assert_allclose(m.cost_of_transport, math.sin(scene.params.slope), rtol=0, atol=1e-9)


def test_rimless_wheel_closed_form():
    scene, P, fp = _gait("gaits/rimless_wheel.toml")
    p = scene.params
    alpha = math.pi / p.spokes
    c = math.cos(2 * alpha)
    cot = c / math.sin(2 * alpha)
    w_star = -cot * math.sqrt(4 * p.g / p.leg_length * math.sin(alpha) * math.sin(p.slope))
    w_before = w_star / c
    kinetic_before = 0.5 * p.leg_length**2 * w_before**2  # per unit hub mass
    m = cycle_measures(P.model, p, fp.state, settings=solver_settings(P))
    assert_allclose(m.step_length, 2 * p.leg_length * math.sin(alpha), rtol=1e-12, atol=0)
    assert_allclose(
        m.impact_losses["impact"], math.sin(2 * alpha) ** 2 * kinetic_before, rtol=1e-9, atol=0
    )
    assert_allclose(m.weight, p.g, rtol=0, atol=0)  # energies are per unit hub mass


def test_total_mass_counts_both_legs():
    scene = load_scene("gaits/kneed_hsu.toml")
    p = scene.params
    assert total_mass(p) == pytest.approx(p.mass_hip + 2 * (p.mass_thigh + p.mass_shank))


RHS = ctypes.CFUNCTYPE(
    None,
    ctypes.c_int64,
    ctypes.c_double,
    ctypes.c_void_p,
    ctypes.c_void_p,
    ctypes.c_void_p,
    ctypes.c_void_p,
)


def _power(model, params, t, x, phase):
    """Actuator power [W] at each sample: the ``actuator_work`` component of the compiled
    right-hand side of the variant that runs these parameters."""
    p = params.as_array()
    rhs = RHS(model.system_for(p).rhs)
    k = model.state_names.index("actuator_work")
    out = np.empty(len(t))
    dx = np.empty(model.n_x)
    for i in range(len(t)):
        xi = np.ascontiguousarray(x[i], dtype=np.float64)
        rhs(int(phase[i]), float(t[i]), xi.ctypes.data, p.ctypes.data, dx.ctypes.data, None)
        out[i] = dx[k]
    return out


@pytest.mark.parametrize(
    "path", ["gaits/three_link_grizzle.toml", "gaits/five_link_hzd.toml"], ids=["three", "five"]
)
def test_actuated_work_equals_integrated_power(path):
    scene, P, fp = _gait(path)
    assert fp.success, fp.message
    settings = solver_settings(P)
    m = cycle_measures(P.model, P.params, fp.state, settings=settings)
    # an independent run sampled at 40001 points, the power from the right-hand side
    first = simulate(P.model, P.params, fp.state, n_strides=1, output="events", **settings)
    times = np.linspace(0.0, first.t, 40001)
    sol = simulate(
        P.model, P.params, fp.state, n_strides=1, output="samples", sample_times=times, **settings
    )
    s = sol.samples
    power = _power(P.model, P.params, s.t, s.x, s.phase)
    net = simpson(power, x=s.t)
    positive = trapezoid(np.maximum(power, 0.0), x=s.t)
    absolute = trapezoid(np.abs(power), x=s.t)
    assert_allclose(m.actuator_work, net, rtol=1e-6, atol=1e-9)
    assert_allclose(m.actuator_work_positive, positive, rtol=1e-4, atol=0)
    assert_allclose(m.actuator_work_absolute, absolute, rtol=1e-4, atol=0)
    transport = m.weight * m.step_length
    assert_allclose(m.cost_of_transport_positive, positive / transport, rtol=1e-4, atol=0)
    # energy balance over the cycle: work in + potential energy released = energy lost
    released = transport * math.sin(scene.params.slope)
    assert_allclose(m.actuator_work + released, m.energy_lost, rtol=1e-8, atol=1e-9)
    assert m.actuator_work_absolute >= m.actuator_work_positive >= m.actuator_work


def test_failed_start_gives_nan_measures():
    scene = load_scene("gaits/compass_goswami.toml")
    model = scene.walker_model
    bad = np.full(model.n_x, np.nan)
    m = cycle_measures(model, scene.params, bad)
    assert m.n_steps == 0 and math.isnan(m.step_length) and math.isnan(m.cost_of_transport)
    with pytest.raises(ValueError, match="`period`"):
        cycle_measures(model, scene.params, scene.state, period=0)


def test_to_dict_and_repr():
    scene, P, fp = _gait("gaits/kneed_hsu.toml")
    m = cycle_measures(P.model, P.params, fp.state, settings=solver_settings(P))
    d = m.to_dict()
    assert set(d) >= {"step_time", "step_length", "speed", "cost_of_transport"}
    assert d["energy_lost_knee_lock"] == m.impact_losses["knee_lock"]
    assert all(isinstance(v, int | float) for v in d.values())
    assert len(repr(m)) < 200 and isinstance(m, GaitMeasures)


def test_branch_measures_columns():
    from walker.analysis.continuation import continue_branch

    scene, P, fp = _gait("gaits/compass_goswami.toml")
    branch = continue_branch(P, fp.section, to=0.06, step=0.004, max_points=4)
    cols = branch_measures(P, branch)
    n = len(branch.parameter)
    assert all(col.shape == (n,) for col in cols.values())
    assert_allclose(cols["cost_of_transport"], np.sin(branch.parameter), rtol=0, atol=1e-9)
