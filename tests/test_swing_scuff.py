"""The swing-foot scuffing convention (``[model] swing_scuff``, walker.models.kneed).

Under "trip" (default) a swing foot reaching the ground with the knee bent ends the run
TRIPPED; under "ignore" it passes through, as in McGeer's analysis and most published
kneed-walker codes.  The swing foot's height and position come from the compiled model
(its swing-foot guard and drawing points), independently of the numpy formulas of
``walker.models.kneed.deepest_penetration``.
"""

import functools
import json
import math
import subprocess
import sys

import numpy as np
import pytest
from numpy.testing import assert_allclose

from walker import load_scene
from walker.analysis.fixedpoint import find_fixed_point
from walker.models import get_model
from walker.models.kneed import deepest_penetration
from walker.simulation.stride import StrideMap, simulate
from walker.status import Status
from walker.storage import read, write

POINTMASS = "gaits/kneed_mcgeer_pointmass.toml"
TOL = dict(rtol=1e-12, atol=1e-12)


def _scene():
    return load_scene(POINTMASS)


def test_scene_asks_for_ignore_and_the_model_carries_it():
    scene = _scene()
    assert scene.swing_scuff == "ignore"
    model = scene.walker_model
    assert model is get_model("kneed", swing_scuff="ignore")
    assert model.conventions == {"swing_scuff": "ignore"}
    assert model.system_for(scene.params).name == "kneed/plain/ignore_scuff"
    assert get_model("kneed").conventions == {"swing_scuff": "trip"}
    assert get_model("compass").conventions == {}


@pytest.mark.regression_pin
def test_pointmass_gait_under_ignore_regression_pin():
    """REGRESSION PIN: the gait shipped in the scene's [reference] (walker's own, DOP853 at
    1e-13), found again from the scene's rounded state; the result records the convention."""
    scene = _scene()
    P = StrideMap(scene.walker_model, scene.params, **TOL)
    fp = find_fixed_point(P, P.project(scene.state), tol=1e-12)
    assert fp.success, fp.message
    ref = scene.reference
    assert_allclose(fp.state, ref["state"], rtol=0, atol=ref["tolerance"])
    assert fp.step_time == pytest.approx(ref["step_time"], abs=ref["tolerance"])
    assert_allclose(fp.multipliers, ref["multipliers"], rtol=0, atol=1e-8)
    assert fp.stable
    assert fp.conventions == {"swing_scuff": "ignore"}


def swing_foot(x, p):
    """(height above the slope, distance ahead of the stance foot along it) [m] of the swing
    foot's lowest point: the compiled model's swing-foot guard and drawing points (the
    numpy formulas of ``deepest_penetration`` are the ones under test)."""
    model = get_model("kneed")
    pts = model.points(x, p)
    d = pts[3] - pts[0]
    slope = p[model.params_class.names().index("slope")]
    return model.guards(0, x, p)[1], d[0] * math.cos(slope) - d[1] * math.sin(slope)


@pytest.mark.regression_pin
def test_the_same_state_trips_under_trip_where_the_foot_meets_the_ground():
    """REGRESSION PIN: the trip instant 0.31073722720505237 s is walker's own.

    Under "trip" the gait's own state ends TRIPPED, at the instant the bent-knee swing
    foot reaches the slope (checked from the geometry, not from the integrator's event)."""
    scene = _scene()
    x0 = scene.reference["state"]
    sol = simulate(get_model("kneed"), scene.params, x0, n_strides=1, output="full", **TOL)
    assert sol.status == Status.TRIPPED
    assert sol.conventions == {"swing_scuff": "trip"}
    p = scene.params.as_array()
    height, ahead = swing_foot(sol.x, p)
    assert abs(height) < 1e-9
    assert sol.x[1] - sol.x[2] > 1e-3  # knee bent
    assert ahead < 0  # behind the stance foot, mid-swing
    # REGRESSION PIN: the trip instant of this scene's gait (walker, DOP853 at 1e-12)
    assert sol.t == pytest.approx(0.31073722720505237, abs=1e-9)
    # ... and the same run under "ignore" passes that instant in phase 0 and completes
    ign = simulate(scene.walker_model, scene.params, x0, n_strides=1, output="full", **TOL)
    assert ign.status == Status.COMPLETED
    assert ign.conventions == {"swing_scuff": "ignore"}
    rec = ign.record
    i = np.searchsorted(rec.t, sol.t)
    assert rec.phase[i] == 0


def test_deepest_penetration_reports_what_ignore_let_pass():
    scene = _scene()
    p = scene.params.as_array()
    run = functools.partial(
        simulate, scene.walker_model, scene.params, scene.reference["state"], n_strides=1, **TOL
    )
    sol = run(output="full")
    pen = deepest_penetration(sol, scene.params)
    # Independent check: the foot height on a dense sample of the same run.
    times = np.linspace(0.0, sol.t, 20001)[1:-1]
    dense = run(output="samples", sample_times=times)
    heights = np.array([swing_foot(x, p)[0] for x in dense.samples.x])
    j = int(np.argmin(heights))
    # the cubic Hermite interpolant between DOP853's long steps: about 1e-7 m
    assert pen.depth == pytest.approx(-heights[j], rel=2e-4)
    assert pen.t == pytest.approx(times[j], abs=2 * (times[1] - times[0]))
    assert pen.ahead == pytest.approx(swing_foot(dense.samples.x[j], p)[1], abs=1e-4)
    assert pen.phase == dense.samples.phase[j]
    assert 1e-4 < pen.depth < 1e-2  # millimetres: a scuff, not a fall through the floor


def test_hsu_gait_clears_the_ground_and_is_the_same_under_both_conventions():
    scene = load_scene("gaits/kneed_hsu.toml")
    x0 = scene.reference["state"]
    runs = [
        simulate(
            get_model("kneed", swing_scuff=c), scene.params, x0, n_strides=2, output="full", **TOL
        )
        for c in ("trip", "ignore")
    ]
    assert all(r.status == Status.COMPLETED for r in runs)
    assert np.array_equal(runs[0].x, runs[1].x) and runs[0].t == runs[1].t
    assert deepest_penetration(runs[0], scene.params).depth == 0.0


def test_deepest_penetration_needs_stored_states():
    scene = _scene()
    sol = simulate(scene.walker_model, scene.params, scene.state, n_strides=1, output="events")
    with pytest.raises(ValueError, match="`solution` must hold stored states"):
        deepest_penetration(sol, scene.params)


def test_convention_round_trips_through_storage(tmp_path):
    scene = _scene()
    P = StrideMap(scene.walker_model, scene.params, **TOL)
    fp = find_fixed_point(P, P.project(scene.state))
    write(tmp_path / "fp.h5", fp, provenance={})
    assert read(tmp_path / "fp.h5")[0].conventions == {"swing_scuff": "ignore"}
    sol = simulate(scene.walker_model, scene.params, scene.state, n_strides=1)
    write(tmp_path / "sol.h5", sol, provenance={})
    assert read(tmp_path / "sol.h5")[0].conventions == {"swing_scuff": "ignore"}


def test_stride_maps_keep_the_convention_across_processes():
    import pickle

    scene = _scene()
    P = StrideMap(scene.walker_model, scene.params)
    Q = pickle.loads(pickle.dumps(P))
    assert Q.model.swing_scuff == "ignore"


def test_cli_find_and_run_report_the_convention(tmp_path):
    def walker(*args):
        return subprocess.run(
            [sys.executable, "-m", "walker", *args], capture_output=True, text=True, check=False
        )

    out = walker("find", POINTMASS, "--json", "--out", str(tmp_path / "fp.h5"))
    assert out.returncode == 0, out.stderr
    record = json.loads(out.stdout)
    assert record["conventions"] == {"swing_scuff": "ignore"}
    assert math.isclose(record["step_time"], _scene().reference["step_time"], abs_tol=1e-9)
    result, prov = read(tmp_path / "fp.h5")
    assert result.conventions == {"swing_scuff": "ignore"}
    assert prov["swing_scuff"] == "ignore"
    run = walker("run", POINTMASS, "--strides", "1")
    assert run.returncode == 0, run.stderr
    assert "mm below the slope" in run.stdout and "swing_scuff = ignore" in run.stdout
