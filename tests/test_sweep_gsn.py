"""The ``gsn`` column of a fixed-point sweep (issue 29: "a sweep can record it as a column"):
at every point it is the gait sensitivity norm that :func:`walker.analysis.gsn.gait_sensitivity`
gives for that point's gait found on its own (a fresh gait search from the scene's start, no warm
start), NaN exactly where there is no stable period-one gait; the norm itself is checked
against finite differences of whole nonlinear runs in tests/test_gsn.py."""

import math
import subprocess
import sys

import numpy as np
import pytest

from walker import StrideMap, load_scene
from walker.analysis.fixedpoint import find_fixed_point
from walker.analysis.gsn import gait_sensitivity
from walker.analysis.sweep import sweep
from walker.storage import read


@pytest.mark.parametrize(
    ("path", "slopes"),
    [
        # slope 0: the wheel does not roll; 0.05: it rolls back (no gait); 0.08, 0.1: gaits
        ("gaits/rimless_wheel.toml", [0.0, 0.05, 0.08, 0.1]),
        # 0.2: a period-one gait that is unstable (no norm)
        ("gaits/compass_goswami.toml", [0.03, 0.05, 0.2]),
    ],
)
def test_gsn_column_equals_the_norm_of_each_points_own_gait(path, slopes, tmp_path):
    scene = load_scene(path)
    P = StrideMap.from_scene(scene)
    z0 = P.project(scene.state)
    table = sweep(
        P,
        {"slope": slopes},
        kind="fixed_point",
        z0=z0,
        executor="serial",
        progress=False,
        gsn=True,
        out=tmp_path / "s.h5",
    )
    column = table.columns["gsn"]
    stored = read(tmp_path / "s.h5")[0].columns["gsn"]
    np.testing.assert_array_equal(stored, column)
    n_norms = 0
    for slope, value in zip(slopes, column, strict=True):
        point_map = P.with_params(slope=slope)
        fp = find_fixed_point(point_map, z0, tol=1e-10)
        if not (fp.success and fp.stable):
            assert math.isnan(value), (slope, value)
            continue
        n_norms += 1
        expected = gait_sensitivity(point_map, fp.section).gsn
        # the two gait searches (warm-started vs from the scene's start) stop within 1e-10
        # of the gait; the norm's finite differences (step 1e-4) amplify that to ~1e-7.
        np.testing.assert_allclose(value, expected, rtol=1e-6, atol=0.0)
    assert n_norms == 2


def test_gsn_option_errors_name_the_argument():
    scene = load_scene("gaits/rimless_wheel.toml")
    P = StrideMap.from_scene(scene)
    z0 = P.project(scene.state)
    common = {"z0": z0, "executor": "serial", "progress": False}
    with pytest.raises(ValueError, match="`gsn` needs kind='fixed_point'"):
        sweep(P, {"slope": [0.1]}, kind="outcome", gsn=True, **common)
    with pytest.raises(TypeError, match="`gsn` must be a bool"):
        sweep(P, {"slope": [0.1]}, kind="fixed_point", gsn=1, **common)
    with pytest.raises(ValueError, match="`tol` must be <= 1e-8 with `gsn`"):
        sweep(P, {"slope": [0.1]}, kind="fixed_point", gsn=True, tol=1e-6, **common)


def test_cli_gsn_needs_a_fixed_point_sweep(tmp_path):
    out = tmp_path / "s.h5"
    cmd = [sys.executable, "-m", "walker", "sweep", "gaits/rimless_wheel.toml"]
    cmd += ["--param", "slope=0.08,0.1", "--kind", "outcome", "--gsn", "--out", str(out)]
    r = subprocess.run(cmd, capture_output=True, text=True, check=False)
    assert r.returncode == 2
    assert "--gsn needs --kind fixed_point" in r.stderr
    assert not out.exists()
