"""McGeer's round-foot kneed walker (gaits/kneed_mcgeer_roundfoot.toml) has no gait for its
parameters as read: the obstruction the scene documents.

The homotopy from the point-mass gait (gaits/kneed_mcgeer_pointmass.toml, swing_scuff =
"ignore") reaches foot radius 0.2 and then folds in the shank offset; at McGeer's full set the
branch exists only above slope 0.0924 (a fold), far above McGeer's 0.0456.  The fold values
are walker's own (REGRESSION PINS), not published numbers; scripts/mcgeer_homotopy.py prints
the whole path.
"""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from walker import load_scene
from walker.analysis.continuation import continue_branch
from walker.analysis.fixedpoint import find_fixed_point
from walker.models import get_model
from walker.models.kneed import deepest_penetration
from walker.params import KneedParams
from walker.simulation.stride import StrideMap, simulate
from walker.status import Status

SCENE = "gaits/kneed_mcgeer_roundfoot.toml"
POINTMASS = "gaits/kneed_mcgeer_pointmass.toml"
IGNORE = get_model("kneed", swing_scuff="ignore")
TRIP = get_model("kneed")
MCGEER = KneedParams.mcgeer()
RTOL = 1e-11

# REGRESSION PINS (walker's own values at rtol = atol = 1e-11; scripts/mcgeer_homotopy.py).
# The fold values move by less than 1e-12 over rtol 1e-11..1e-13; the tests allow 1e-8.
# The fold of the homotopy in offset_shank at slope 0.0456 (foot radius 0.2, no inertias),
FOLD_OFFSET = 0.0030115725
# the fold in slope of the branch at McGeer's full set,
FOLD_SLOPE = 0.0923953173
# and that branch's stable gait at slope 0.1 (section q1, qd1, qd2).
GAIT_SLOPE_01 = [0.37132932, -0.44688393, -0.08689654]


def _map(params, name="slope", model=IGNORE):
    return StrideMap(model, params, rtol=RTOL, atol=RTOL, parameter_name=name)


def _pointmass_g1():
    """The point-mass gait moved to g = 1 by exact scaling: (params, section)."""
    scene = load_scene(POINTMASS)
    k = math.sqrt(1.0 / scene.params.g)
    params = scene.params.replace(g=1.0)
    return params, _map(params).project(scene.state) * np.array([1.0, k, k])


def test_scene_loads_and_says_no_gait():
    scene = load_scene(SCENE)
    assert scene.params == MCGEER
    assert scene.swing_scuff == "trip"  # walker's default; the analysis is under "ignore"
    assert "NO GAIT" in scene.description and "GUESS" in scene.description
    assert scene.reference is None or not scene.reference


def test_search_from_the_scene_guess_fails_under_both_conventions():
    """From the guess: TRIPPED under the scene's "trip"; FELL_FORWARD under "ignore" (the
    foot goes below the slope with the knee bent, the knee locks with the foot below it, no
    heel strike follows)."""
    scene = load_scene(SCENE)
    PT = StrideMap(scene.walker_model, scene.params, rtol=1e-12, atol=1e-12)
    assert find_fixed_point(PT, PT.project(scene.state)).status == Status.TRIPPED

    P = StrideMap(IGNORE, scene.params, rtol=1e-12, atol=1e-12)
    fp = find_fixed_point(P, P.project(scene.state))
    assert not fp.success
    assert fp.status == Status.FELL_FORWARD
    sol = simulate(IGNORE, scene.params, scene.state, output="full")
    assert sol.status == Status.FELL_FORWARD and sol.n_strides == 0
    assert sol.events.guard.tolist() == [0, 2]  # knee lock, then the fall: no heel strike
    assert deepest_penetration(sol, scene.params).depth > 0.0


def test_g_scaling_is_exact():
    """Stage 0 of the homotopy: g 9.81 -> 1 keeps the angles and multipliers, scales rates by
    sqrt(1/9.81) and the step time by sqrt(9.81)."""
    scene = load_scene(POINTMASS)
    params, z = _pointmass_g1()
    fp = find_fixed_point(_map(params), z, tol=1e-11)
    assert fp.success, fp.message
    assert_allclose(fp.section, z, rtol=0, atol=1e-8)
    ref = scene.reference
    assert fp.step_time == pytest.approx(ref["step_time"] * math.sqrt(9.81), rel=1e-8)
    mult = np.asarray(ref["multipliers"], dtype=complex)
    assert_allclose(np.sort_complex(fp.multipliers), np.sort_complex(mult), atol=1e-8)


def test_homotopy_reaches_the_round_foot_and_folds_in_the_shank_offset():
    """At McGeer's slope the branch follows foot_radius 0 -> 0.2 and then ends at a fold at
    offset_shank = 0.0030116 < 0.01 (REGRESSION PIN): a multiplier reaches +1."""
    params, z = _pointmass_g1()
    br = continue_branch(_map(params, "foot_radius"), z, to=0.2, stop_at_fold=True)
    assert br.success and br.parameter[-1] == pytest.approx(0.2, abs=1e-14), br.message
    assert not br.bifurcations
    assert np.all(br.stable)
    params = params.replace(foot_radius=0.2)

    br = continue_branch(
        _map(params, "offset_shank"), br.sections[-1], to=MCGEER.offset_shank, stop_at_fold=True
    )
    folds = [b for b in br.bifurcations if b.kind == "fold"]
    assert len(folds) == 1, br.message
    assert folds[0].parameter_value == pytest.approx(FOLD_OFFSET, abs=1e-8)
    assert folds[0].parameter_value < MCGEER.offset_shank
    assert np.abs(folds[0].multipliers).max() == pytest.approx(1.0, abs=1e-6)
    # the branch does not go further at the target: no gait near its last point there
    P = _map(params.replace(offset_shank=MCGEER.offset_shank))
    assert not find_fixed_point(P, br.sections[-1]).success


def test_at_mcgeers_set_the_branch_starts_above_his_slope():
    """McGeer's full set walks on steeper slopes: the stable gait at slope 0.1 (REGRESSION
    PIN), continued down in slope, folds at 0.092395 (REGRESSION PIN), above 0.0456; its swing
    foot clears the ground, so "trip" has the same gait."""
    params = MCGEER.replace(slope=0.1)
    fp = find_fixed_point(_map(params), np.array(GAIT_SLOPE_01), tol=1e-11)
    assert fp.success, fp.message
    assert_allclose(fp.section, GAIT_SLOPE_01, rtol=0, atol=1e-7)
    assert fp.stable
    sol = simulate(IGNORE, params, fp.state, output="full")
    assert deepest_penetration(sol, params).depth < 1e-12
    assert _map(params, model=TRIP)(fp.section).status == Status.COMPLETED

    br = continue_branch(_map(params), fp.section, to=0.005, stop_at_fold=True)
    folds = [b for b in br.bifurcations if b.kind == "fold"]
    assert len(folds) == 1, br.message
    assert folds[0].parameter_value == pytest.approx(FOLD_SLOPE, abs=1e-8)
    assert folds[0].parameter_value > MCGEER.slope
    # the fold gait, put on McGeer's slope, is no gait there
    P = _map(MCGEER)
    assert not find_fixed_point(P, folds[0].section).success


def test_at_mcgeers_slope_only_a_backward_shank_offset_walks():
    """With McGeer's other values at slope 0.0456 the gait exists for offset_shank <=
    -0.0070139 only (REGRESSION PIN): at -0.01 a stable gait (REGRESSION PIN, reached by the
    same homotopy with the offset reversed; scripts/mcgeer_homotopy.py --reversed-offset),
    continued toward McGeer's +0.01, folds there."""
    params = MCGEER.replace(offset_shank=-0.01)
    fp = find_fixed_point(_map(params), np.array([0.31569052, -0.3779209, -0.19441095]), tol=1e-11)
    assert fp.success, fp.message
    assert fp.stable
    assert fp.step_time == pytest.approx(2.66284377, abs=1e-7)
    br = continue_branch(_map(params, "offset_shank"), fp.section, to=0.01, stop_at_fold=True)
    folds = [b for b in br.bifurcations if b.kind == "fold"]
    assert len(folds) == 1, br.message
    assert folds[0].parameter_value == pytest.approx(-0.0070138640, abs=1e-8)


def test_the_description_gives_the_trip_time_walker_computes():
    """The scene's description says when the swing foot first goes below the slope from the
    scene's guess (issue 31: it said 1.24 s; walker and an independent model both trip at
    1.1727 s).  Under "trip" walker ends the run there (its swing-contact guard); under
    "ignore" the drawn swing foot's height above the slope (sampled every 10 us near there)
    first turns
    negative at the same time; the knee then locks at 1.50 s with the foot 21 mm below."""
    import re

    scene = load_scene(SCENE)
    said = float(re.search(r"below the slope at t = ([0-9.]+)", scene.description)[1])
    tripped = simulate(TRIP, scene.params, scene.state, n_strides=1, rtol=RTOL, atol=RTOL)
    assert tripped.status == Status.TRIPPED
    assert abs(tripped.t - said) < 5e-5
    p = scene.params.as_array()
    normal = np.array([math.sin(scene.params.slope), math.cos(scene.params.slope)])
    run = simulate(
        IGNORE, scene.params, scene.state, n_strides=1, output="events", rtol=RTOL, atol=RTOL
    )
    # every 1 ms, and every 10 us near the trip
    fine = np.arange(said - 0.01, said + 0.01, 1e-5)
    times = np.union1d(np.arange(0.0, run.events.t[0], 1e-3), fine)
    sampled = simulate(
        IGNORE,
        scene.params,
        scene.state,
        n_strides=1,
        output="samples",
        sample_times=times,
        rtol=RTOL,
        atol=RTOL,
    )
    height = np.array([IGNORE.points(x, p)[-1] @ normal for x in sampled.samples.x])
    first_below = sampled.samples.t[np.argmax(height < 0)]
    assert abs(first_below - tripped.t) <= 1e-5
    lock = run.events
    assert IGNORE.guard_names[lock.guard[0]] == "knee_lock" and abs(lock.t[0] - 1.50) < 5e-3
    depth = -(IGNORE.points(lock.x_pre[0], p)[-1] @ normal)
    assert abs(depth - 0.021) < 5e-4
