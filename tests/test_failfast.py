"""Failing fast: a gait search that cannot succeed ends cheaply, with a status that says why.

Pinned here: the new statuses and their messages; iterates outside the walking region are
refused without integrating them; the evaluation budget of ``find_fixed_point``, of sweep
points and of continuation correctors holds (counted evaluations, never wall-clock); the
stress set of the issue (kneed at slopes 0.02 and 0.025, compass at 0 and 0.3, random guesses
around the kneed gait) ends within the budget; a stride's work is bounded (hypothesis: the
worst stride costs at most 100x the median stride, in integration steps and vector-field
evaluations).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import walker.analysis.steppers as steppers_module
import walker.analysis.sweep_chains as sweep_chains_module
from walker import load_scene, simulate
from walker.analysis.continuation import continue_branch
from walker.analysis.fixedpoint import (
    CORRECTOR_EVALS_PER_ITER,
    KINETIC_FACTOR,
    MAX_EVALS,
    POINT_MAX_EVALS,
    WalkingRegion,
    default_max_evals,
    find_fixed_point,
    stride_max_steps,
)
from walker.analysis.sweep import MapSpec, sweep_chunk
from walker.cli import build_parser
from walker.cli import main as cli_main
from walker.models._common import FALL_ANGLE
from walker.params import CompassParams, KneedParams, SimplestParams, ThreeLinkParams
from walker.results import MapResult
from walker.simulation.stride import StrideMap, _time_scale
from walker.status import Status

GAITS = Path(__file__).resolve().parents[1] / "gaits"
KNEED = GAITS / "kneed_hsu.toml"
COMPASS = GAITS / "compass_goswami.toml"
SEARCH_ENDS = {Status.NO_GAIT_NEAR_GUESS, Status.DIVERGED, Status.BUDGET_EXHAUSTED}
# The wound-up iterate (1074 rad, 19745 rad/s, 78954 rad/s).
WOUND = np.array([1074.0, 19745.0, 78954.0])


class Counting:
    """A section map that records every evaluation of the map it wraps (everything else,
    ``model`` and ``params`` included, is forwarded)."""

    def __init__(self, inner, calls=None):
        self.inner = inner
        self.calls = [] if calls is None else calls

    def __getattr__(self, name):
        return getattr(self.inner, name)

    def __call__(self, z, **kwargs):
        self.calls.append(np.array(z, dtype=float))
        return self.inner(z, **kwargs)

    def with_parameter(self, value):
        return Counting(self.inner.with_parameter(value), self.calls)


def scene_map(path, **overrides):
    """The scene, and its stride map as ``walker find`` builds it."""
    from walker.cli._common import _stride_map

    scene = load_scene(path, overrides=overrides)
    return scene, _stride_map(scene)


# ------------------------------------------------------------------------- statuses


def test_status_values_are_appended_never_renumbered():
    old = [
        "COMPLETED",
        "FELL_BACKWARD",
        "FELL_FORWARD",
        "TRIPPED",
        "NONPHYSICAL_IMPACT",
        "NO_EVENT",
        "STEP_UNDERFLOW",
        "NONFINITE",
        "MAX_STEPS",
        "NOT_CONVERGED",
        "LINEAR_SOLVE_FAILED",
        "PARAMETER_OUT_OF_RANGE",
    ]
    assert [Status[name].value for name in old] == list(range(12))
    assert Status.NO_GAIT_NEAR_GUESS == 12
    assert Status.DIVERGED == 13
    assert Status.BUDGET_EXHAUSTED == 14
    assert Status.OUTSIDE_WALKING_REGION == 15
    assert Status.CHATTERING == 16


def _cli_options() -> set[str]:
    options = set()
    parser = build_parser()
    for action in parser._subparsers._group_actions:
        for sub in action.choices.values():
            for a in sub._actions:
                options.update(a.option_strings)
    return options


def test_messages_name_what_a_command_line_user_can_change():
    options = _cli_options()
    assert "--set" in options and "--max-steps" in options and "--max-evals" not in options
    for status in SEARCH_ENDS | {Status.OUTSIDE_WALKING_REGION}:
        msg = status.message
        assert "[initial] state" in msg, status
        assert "command line" in msg, status
    for status in SEARCH_ENDS:
        assert "--set" in status.message, status
    assert "max_evals" in Status.BUDGET_EXHAUSTED.message
    msg = Status.MAX_STEPS.message
    # the Python argument is named, and what a CLI user can do (walker run --max-steps)
    assert "`max_steps`" in msg and "command line" in msg and "rtol" in msg
    assert "walker run --max-steps" in msg and not msg.endswith("Increase `max_steps`.")


# ------------------------------------------------------------------- walking region


def test_walking_region_comes_from_the_model():
    scene, P = scene_map(KNEED)
    region = WalkingRegion.of(P)
    rate = 1.0 / _time_scale(scene.params)
    np.testing.assert_allclose(region.scale, [1.0, rate, rate])
    kinetic0, _ = P.model.energy(P.lift(np.zeros(3)), scene.params.as_array())
    assert kinetic0 == 0.0
    assert region.potential_up == P.model.energy(P.lift(np.zeros(3)), scene.params)[1] > 0
    z0 = P.project(scene.state)
    region.with_guess(z0)
    ke0 = P.model.energy(P.lift(z0), scene.params)[0]
    assert region.kinetic_max == pytest.approx(KINETIC_FACTOR * (ke0 + region.potential_up))
    assert region.outside(z0) is None
    slope = scene.params.slope
    assert "fall angle" in region.outside([FALL_ANGLE - slope + 1e-3, -1.1, 0.0])
    assert "fall angle" in region.outside([-FALL_ANGLE - slope - 1e-3, -1.1, 0.0])
    assert region.outside([FALL_ANGLE - slope - 1e-3, -1.1, 0.0]) is None
    assert "kinetic energy" in region.outside([0.19, -30.0, 0.0])
    assert "fall angle" in region.outside(WOUND)
    # a wound torso (three-link section: q_stance, q_torso, rates)
    P3 = StrideMap("three_link", ThreeLinkParams.grizzle())
    r3 = WalkingRegion.of(P3)
    assert "wound" in r3.outside([0.2, 4.0, -1.0, 0.0, 0.0])
    # a map without a walker model has no region
    assert WalkingRegion.of(object()) is None


def test_walking_region_of_a_stride_map_is_a_fresh_copy_each_time():
    """WalkingRegion.of keeps one region per (immutable) stride map and parameter value and
    hands out copies: a guess set on one search's region does not reach the next, and a
    copy equals a region built anew."""
    scene, P = scene_map(KNEED)
    z0 = P.project(scene.state)
    a = WalkingRegion.of(P).with_guess(z0)
    b = WalkingRegion.of(P)
    assert b is not a and b.kinetic_max == b.kinetic_limit > a.kinetic_max
    fresh = WalkingRegion(P.model, P.params)
    assert vars(b).keys() == vars(fresh).keys()
    for name, value in vars(fresh).items():
        if isinstance(value, np.ndarray):
            np.testing.assert_array_equal(getattr(b, name), value)
        elif isinstance(value, float) and math.isnan(value):
            assert math.isnan(getattr(b, name))
        else:
            assert getattr(b, name) == value, name
    steeper = WalkingRegion.of(P, parameter=scene.params.slope * 1.5)
    assert steeper.slope == pytest.approx(scene.params.slope * 1.5)
    assert WalkingRegion.of(P).slope == scene.params.slope


def test_a_guess_outside_the_region_is_not_integrated():
    _, P = scene_map(KNEED)
    m = Counting(P)
    for z0 in (WOUND, np.array([0.19, 19745.0, 78954.0])):
        fp = find_fixed_point(m, z0)
        assert fp.status == Status.OUTSIDE_WALKING_REGION and not fp.success
        assert "[initial] state" in fp.message
        np.testing.assert_array_equal(fp.section, z0)
    assert m.calls == []


class AffineWalker:
    """``P(z) = z* + (z - z*) / 2`` on the kneed walker's section (its model and
    parameters, so the search knows the walking region): the only fixed point ``z*`` lies
    past the fall angle, so the Newton step from a guess inside points out of the region."""

    def __init__(self, z_star):
        self.inner = StrideMap("kneed", KneedParams.hsu_chen())
        self.z_star = np.asarray(z_star, dtype=float)
        self.calls = []

    model = property(lambda self: self.inner.model)
    params = property(lambda self: self.inner.params)
    n_z = property(lambda self: self.inner.n_z)
    section_names = property(lambda self: self.inner.section_names)
    parameter_name = property(lambda self: self.inner.parameter_name)
    parameter_value = property(lambda self: self.inner.parameter_value)

    def lift(self, z):
        return self.inner.lift(z)

    def with_parameter(self, value):
        return self

    def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
        self.calls.append(np.array(z, dtype=float))
        out = self.z_star + 0.5 * (np.asarray(z) - self.z_star)
        jac = 0.5 * np.eye(3) if jacobian else None
        return MapResult(Status.COMPLETED, out, jac, 1.0, self.lift(out))


def test_trial_points_outside_the_region_are_refused_without_a_stride(monkeypatch):
    refused = []
    outside = WalkingRegion.outside

    def recording(self, z):
        why = outside(self, z)
        if why is not None:
            refused.append(np.array(z, dtype=float))
        return why

    monkeypatch.setattr(WalkingRegion, "outside", recording)
    m = AffineWalker([1.6, -1.1, -0.05])
    z0 = np.array([1.1, -1.1, -0.05])
    fp = find_fixed_point(m, z0)
    assert not fp.success and fp.status in SEARCH_ENDS, fp.message
    assert len(refused) >= 3  # the full Newton step and its first halvings
    region = WalkingRegion.of(m).with_guess(z0)
    assert all(region.outside(z) is None for z in m.calls)  # nothing outside was evaluated
    assert not any(any(np.array_equal(r, c) for c in m.calls) for r in refused)
    assert len(m.calls) <= MAX_EVALS
    assert np.all(np.isfinite(fp.section)) and region.outside(fp.section) is None


# ---------------------------------------------------------------------------- budget


@pytest.mark.parametrize("budget", [1, 2, 5, 13, 30])
def test_the_evaluation_budget_holds(budget):
    _, P = scene_map(KNEED, slope=0.02)
    m = Counting(P)
    z0 = P.project(load_scene(KNEED).state)
    fp = find_fixed_point(m, z0, max_evals=budget)
    assert len(m.calls) <= budget
    assert not fp.success
    assert np.all(np.isfinite(fp.section))
    if fp.status == Status.BUDGET_EXHAUSTED:
        assert f"{budget} stride-map evaluations" in fp.message and "max_evals" in fp.message


@pytest.mark.parametrize("jacobian", ["exact", "fd"])
def test_the_default_budget_holds(jacobian):
    _, P = scene_map(KNEED, slope=0.02)
    m = Counting(P)
    fp = find_fixed_point(m, P.project(load_scene(KNEED).state), jacobian=jacobian)
    assert not fp.success
    assert len(m.calls) <= default_max_evals(3, jacobian)
    assert default_max_evals(3, "exact") == MAX_EVALS == 60
    assert default_max_evals(3, "fd") == 60 + 20 * 3


@pytest.mark.parametrize("bad", [0, -1, 2.5, True, "10"])
def test_invalid_budget_raises_before_any_work(bad):
    _, P = scene_map(KNEED)
    m = Counting(P)
    with pytest.raises(ValueError, match="`max_evals` must be None or an integer >= 1"):
        find_fixed_point(m, P.project(load_scene(KNEED).state), max_evals=bad)
    assert m.calls == []


# ------------------------------------------------------------------------ stress set

STRESS = [(KNEED, 0.02), (KNEED, 0.025), (COMPASS, 0.0), (COMPASS, 0.3)]


@pytest.mark.parametrize(("path", "slope"), STRESS, ids=lambda v: str(getattr(v, "stem", v)))
def test_stress_set_ends_with_a_status_within_the_budget(path, slope):
    scene, P = scene_map(path, slope=slope)
    m = Counting(P)
    z0 = P.project(scene.state)
    fp = find_fixed_point(m, z0)
    assert fp.status in SEARCH_ENDS, fp.message
    assert len(m.calls) <= MAX_EVALS
    assert "--set slope=" in fp.message and "[initial] state" in fp.message
    assert np.all(np.isfinite(fp.section))
    region = WalkingRegion.of(P).with_guess(z0)
    assert all(region.outside(z) is None for z in m.calls)
    assert region.outside(fp.section) is None
    # no iterate strays far from the guess (the search reached 1074 rad)
    assert max(np.max(np.abs(z - z0) / region.scale) for z in m.calls) < 10


def test_stress_set_through_the_command_line(capsys):
    rc = cli_main(["find", str(KNEED), "--set", "slope=0.02", "--json"])
    record = json.loads(capsys.readouterr().out)
    assert rc == 1
    assert Status[record["status"]] in SEARCH_ENDS
    assert all(math.isfinite(v) for v in record["section"])


def test_random_guesses_around_the_kneed_gait_stay_within_the_budget():
    scene, P = scene_map(KNEED)
    z_ref = P.project(np.array(scene.reference["state"]))
    rng = np.random.default_rng(20240611)
    outcomes = set()
    for _ in range(10):
        z0 = z_ref * (1.0 + rng.uniform(-0.5, 0.5, 3))
        m = Counting(P)
        fp = find_fixed_point(m, z0)
        outcomes.add(fp.status)
        assert len(m.calls) <= MAX_EVALS
        assert np.all(np.isfinite(fp.section))
        if fp.success:
            assert fp.residual <= 1e-12
            np.testing.assert_allclose(P(fp.section).z, fp.section, rtol=0, atol=1e-11)
    assert Status.COMPLETED in outcomes and len(outcomes) > 1


# ---------------------------------------------------------------- sweeps, continuation


def test_each_sweep_point_has_a_budget(monkeypatch):
    records = []

    def budgeted(section_map, z0, **kwargs):
        m = Counting(section_map)
        fp = find_fixed_point(m, z0, **kwargs)
        records.append((kwargs.get("max_evals"), len(m.calls), fp.status))
        return fp

    monkeypatch.setattr(sweep_chains_module, "find_fixed_point", budgeted)  # the point search
    scene, P = scene_map(KNEED)
    points = np.array([[0.05], [0.02], [0.025], [0.06]])
    out = sweep_chunk(
        MapSpec.from_map(P), ("slope",), points, "fixed_point", P.project(scene.state), 1, 1e-10
    )
    statuses = [Status(int(s)) for s in out["status"]]
    assert statuses[0] == statuses[3] == Status.COMPLETED
    assert statuses[1] != Status.COMPLETED and statuses[2] != Status.COMPLETED
    assert all(budget == POINT_MAX_EVALS for budget, _, _ in records)
    assert all(n <= POINT_MAX_EVALS for _, n, _ in records)
    assert len(records) <= 2 * len(points)


def test_each_natural_corrector_has_a_budget(monkeypatch):
    records = []
    solve = steppers_module.solve_fixed_point

    def budgeted(section_map, z0, **kwargs):
        m = Counting(section_map)
        out = solve(m, z0, **kwargs)
        records.append((kwargs.get("max_evals"), len(m.calls)))
        return out

    monkeypatch.setattr(steppers_module, "solve_fixed_point", budgeted)
    scene, P = scene_map(KNEED)
    branch = continue_branch(P, P.project(scene.state), to=0.02, method="natural")
    # past the fold at slope ~0.0319 there is no gait: the continuation stops there
    assert branch.status == Status.NOT_CONVERGED
    assert 0.031 < branch.parameter[-1] < 0.033
    budget = CORRECTOR_EVALS_PER_ITER * 8
    assert records and all(b == budget and n <= budget for b, n in records)


# -------------------------------------------------------------------- stride's work


def test_stride_step_budget_is_tied_to_t_max():
    params = KneedParams.hsu_chen()
    T = _time_scale(params)
    assert stride_max_steps(params, 20.0, "DOP853", None) == math.ceil(60 * 20.0 / T) == 3757
    assert stride_max_steps(params, 20.0 * T, "DOP853", None) == 1200
    assert stride_max_steps(params, 0.5, "DOP853", None) == 1000
    assert stride_max_steps(params, 2.0, "Euler", 1e-3) == 2002
    # the compiled run of a stride map carries it, times the strides asked for
    P = StrideMap("kneed", params, t_max=20.0)
    for n in (1, 3):
        assert P._prepared(n)[0]._settings["max_steps"] == 3757 * n


def test_stride_map_does_not_integrate_states_outside_the_region():
    _, P = scene_map(KNEED)
    r = P(WOUND)  # the stance leg is past the fall angle (wound round 171 times)
    assert r.status == Status.FELL_BACKWARD and r.step_time == 0.0
    r = P(-WOUND)
    assert r.status == Status.FELL_FORWARD and r.step_time == 0.0
    r = P(np.array([0.19, 19745.0, 78954.0]))  # rates far beyond any gait's
    assert r.status == Status.OUTSIDE_WALKING_REGION and r.step_time == 0.0
    assert np.all(np.isnan(r.z))
    np.testing.assert_array_equal(r.state, P.lift([0.19, 19745.0, 78954.0]))
    P3 = StrideMap("three_link", ThreeLinkParams.grizzle())
    r = P3(np.array([0.2, 4.0, -1.0, 0.0, 0.0]))  # torso wound beyond pi
    assert r.status == Status.OUTSIDE_WALKING_REGION and r.step_time == 0.0
    # the gait itself still walks
    scene, P = scene_map(KNEED)
    assert P(P.project(np.array(scene.reference["state"]))).success


_PARAMS = {
    "kneed": lambda slope, g: KneedParams.hsu_chen().replace(slope=slope, g=g),
    "compass": lambda slope, g: CompassParams.goswami().replace(slope=slope, g=g),
    "simplest": lambda slope, g: SimplestParams.garcia().replace(slope=slope, g=g),
}

_CASES = st.tuples(
    st.sampled_from(sorted(_PARAMS)),
    st.floats(0.0, 0.12),  # slope [rad]
    st.floats(1.0, 30.0),  # g [m/s^2]
    st.floats(-1.4, 1.4),  # stance angle [rad], past the fall angle too
    st.tuples(st.floats(-8.0, 8.0), st.floats(-8.0, 8.0)),  # rates [sqrt(g/l)]
    st.sampled_from([1.0, 1.0, 1.0, 30.0, 1e4]),  # some states far beyond any gait
    st.sampled_from([20.0, None]),  # the scenes' t_max [s], or the default 20 sqrt(l/g)
)


def _stride_work(case):
    """(steps, rhs) of the stride the stride map runs for ``case``; None when the stride map
    does not integrate it (outside the walking region)."""
    model, slope, g, angle, rates, blow_up, t_max = case
    params = _PARAMS[model](slope, g)
    P = StrideMap(model, params, rtol=1e-12, atol=1e-12, t_max=t_max)
    z = np.array([angle, *rates[: P.n_z - 1]])
    z[1:] *= blow_up / _time_scale(params)
    r = P(z)
    if not r.success and r.step_time == 0.0:
        return None
    sol = simulate(
        model,
        params,
        P.lift(z),
        t_max=P.t_max,
        rtol=1e-12,
        atol=1e-12,
        max_steps=stride_max_steps(params, P.t_max, "DOP853", None),
    )
    assert sol.status == r.status  # the same run as the stride map's
    return sol.n_steps + sol.n_rejected, sol.n_rhs


def _check_stride_work(n_examples):
    work = []

    @settings(
        max_examples=n_examples,
        deadline=None,
        derandomize=True,
        database=None,
        suppress_health_check=list(HealthCheck),
    )
    @given(case=_CASES)
    def run(case):
        w = _stride_work(case)
        if w is not None:
            work.append(w)

    run()
    work = np.array(work, dtype=float)
    assert len(work) >= n_examples // 4
    median = np.median(work, axis=0)
    worst = work.max(axis=0)
    assert np.all(worst <= 100 * median), (worst, median)


@pytest.mark.slow  # a stress set: the integration tier
def test_worst_stride_costs_at_most_100_median_strides():
    _check_stride_work(1000)


@pytest.mark.slow
def test_worst_stride_costs_at_most_100_median_strides_10k():
    _check_stride_work(10_000)
