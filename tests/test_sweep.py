"""Parameter sweeps: grids, validation, executor independence, resume after SIGKILL, dask, and
the compass gait's fixed point along a slope sweep."""

from __future__ import annotations

import concurrent.futures as cf
import functools
import os
import shutil
import signal
import textwrap
import time
from pathlib import Path

import h5py
import numpy as np
import pytest
from _checkpoints import start_python
from numpy.testing import assert_allclose

from walker import StrideMap, load_scene
from walker.analysis.sweep import grid_points, parse_range, sweep
from walker.analysis.sweep_chains import sweep_lines
from walker.cli.sweep import run_sweep_command
from walker.status import Status
from walker.storage import StorageError, read

REPO = Path(__file__).resolve().parents[1]
TESTS = Path(__file__).resolve().parent
COMPASS_SCENE = REPO / "gaits" / "compass_goswami.toml"
SIMPLEST_SCENE = REPO / "gaits" / "simplest_garcia.toml"

# The compass gait's fixed point at slope 3 deg, g = 9.8, section (q_stance, qd_stance,
# qd_swing).  Spong, Holm, Lee, IEEE Robot. Autom. Mag. 14(2), 2007, print 4 digits
# [0.2187, -1.0918, -0.3772]; 5 digits from our own Newton solve at rtol = atol = 1e-12.
COMPASS_SECTION_SPONG = np.array([0.2187, -1.0918, -0.3772])
COMPASS_SECTION_5 = np.array([0.21867, -1.09183, -0.37718])


def _compass_map():
    scene = load_scene(COMPASS_SCENE)
    stride_map = StrideMap("compass", scene.params, rtol=1e-10, atol=1e-12)
    return stride_map, stride_map.project(scene.state)


def _simplest_map():
    scene = load_scene(SIMPLEST_SCENE)
    stride_map = StrideMap("simplest", scene.params, rtol=1e-10, atol=1e-12)
    return stride_map, stride_map.project(scene.state)


def _assert_tables_equal(a, b):
    """Bit-for-bit equality, NaN positions included."""
    assert a.parameter_names == b.parameter_names
    assert np.array_equal(a.points, b.points)
    assert list(a.columns) == list(b.columns)
    for name in a.columns:
        assert a.columns[name].dtype == b.columns[name].dtype, name
        assert np.array_equal(a.columns[name], b.columns[name], equal_nan=True), name


class RecordingExecutor(cf.Executor):
    """Runs tasks inline and records the points every task submitted computes (a
    fixed-point task's points already done, passed in ``known``, are looked up only)."""

    def __init__(self):
        self.submitted = []

    def submit(self, fn, /, *args, **kwargs):
        points = np.array(args[2])
        if fn is sweep_lines and args[5] is not None:
            points = points[~args[5]["known"]]
        self.submitted.append(points)
        future = cf.Future()
        future.set_result(fn(*args, **kwargs))
        return future


@pytest.fixture(scope="module")
def pool():
    with cf.ProcessPoolExecutor(max_workers=2) as executor:
        yield executor


# ---- grids -------------------------------------------------------------------------------


def test_parse_range_forms():
    name, values = parse_range("slope=0.001:0.003:3")
    assert name == "slope"
    assert_allclose(values, [0.001, 0.002, 0.003], rtol=0, atol=1e-18)
    assert parse_range(" mass_hip = 10, 12.5 ")[0] == "mass_hip"
    assert parse_range("mass_hip=10, 12.5")[1].tolist() == [10.0, 12.5]
    assert parse_range("slope=0.01")[1].tolist() == [0.01]
    assert parse_range("slope=0.2:0.5:1")[1].tolist() == [0.2]


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("slope", r"'slope'.*start with a parameter name and '='"),
        ("=0:1:3", r"'=0:1:3'.*start with a parameter name"),
        ("2x=0:1:3", r"'2x=0:1:3'.*start with a parameter name"),
        ("slope=", r"'slope='.*no values after '='"),
        ("slope=0:1", r"'slope=0:1'.*exactly 3 parts, got 2"),
        ("slope=0:1:2:3", r"exactly 3 parts, got 4"),
        ("slope=0:1:0", r"'slope=0:1:0'.*COUNT must be an integer >= 1, got '0'"),
        ("slope=0:1:2.5", r"COUNT must be an integer >= 1, got '2.5'"),
        ("slope=0:1:-2", r"COUNT must be an integer >= 1, got '-2'"),
        ("slope=a:1:3", r"START 'a' is not a number"),
        ("slope=0:inf:3", r"STOP must be finite"),
        ("slope=0.1,x", r"'slope=0.1,x'.*value 'x' is not a number"),
        ("slope=0.1,,0.2", r"value '' is not a number"),
        ("slope=nan", r"value must be finite"),
    ],
)
def test_parse_range_errors(text, match):
    with pytest.raises(ValueError, match=match) as info:
        parse_range(text)
    assert "NAME=START:STOP:COUNT" in str(info.value)  # the rule is stated


def test_grid_points_last_parameter_fastest():
    names, points = grid_points(["a=1,2", "b=0:1:3"])
    assert names == ("a", "b")
    assert points.tolist() == [[1, 0], [1, 0.5], [1, 1], [2, 0], [2, 0.5], [2, 1]]
    names, points = grid_points({"x": [3.0], "y": np.array([1, 2])})
    assert names == ("x", "y") and points.tolist() == [[3, 1], [3, 2]]


@pytest.mark.parametrize(
    ("ranges", "error", "match"),
    [
        (["a=1,2", "a=3"], ValueError, r"at most once; repeated: \['a'\]"),
        ([], ValueError, "at least one parameter"),
        ([("a", [])], ValueError, "values of `a` in `ranges` must be a non-empty 1-D array"),
        ([("a", [1.0, np.nan])], ValueError, "values of `a` in `ranges` must all be finite"),
        ([("a b", [1.0])], ValueError, "must be identifiers, got 'a b'"),
        ([3.0], TypeError, "a 'NAME=...' text or a \\(name, values\\) pair, got 3.0"),
        (3.0, TypeError, "`ranges` must be a sequence"),
    ],
)
def test_grid_points_errors(ranges, error, match):
    with pytest.raises(error, match=match):
        grid_points(ranges)


# ---- validation before any work ---------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        (
            {"ranges": ["slop=0:1:3"]},
            ValueError,
            r"unknown parameter `slop` in `ranges` for model `simplest`; valid names: "
            r"slope, g, leg_length",
        ),
        ({"ranges": ["g=-1,1"]}, ValueError, r"grid point \(g=-1.0\) is not valid: `g` must be"),
        ({"z0": np.zeros(3)}, ValueError, r"`z0` must have shape \(2,\).*got \(3,\)"),
        ({"z0": np.array([0.2, np.nan])}, ValueError, "components of `z0` must be finite"),
        ({"kind": "orbit"}, ValueError, "`kind` must be one of outcome, fixed_point, got 'orbit'"),
        ({"chunk_size": 0}, ValueError, "`chunk_size` must be an integer >= 1, got 0"),
        ({"chunk_size": 2.0}, ValueError, "`chunk_size` must be an integer >= 1, got 2.0"),
        ({"n_strides": 0}, ValueError, "`n_strides` must be an integer >= 1, got 0"),
        ({"tol": -1.0}, ValueError, "`tol` must be positive and finite, got -1.0"),
        ({"executor": "threads"}, ValueError, "`executor` must be an Executor, 'serial' or None"),
        ({"executor": 3}, TypeError, "`executor` must be a concurrent.futures.Executor"),
    ],
)
def test_sweep_validates_before_any_work(kwargs, error, match, tmp_path):
    stride_map, z0 = _simplest_map()
    recorder = RecordingExecutor()
    args = {"ranges": ["slope=0.008:0.01:3"], "z0": z0, "executor": recorder, "progress": False}
    args.update(kwargs)
    out = tmp_path / "s.h5"
    with pytest.raises(error, match=match):
        sweep(stride_map, out=out, **args)
    assert recorder.submitted == [] and not out.exists()


def test_sweep_out_directory_must_exist(tmp_path):
    stride_map, z0 = _simplest_map()
    recorder = RecordingExecutor()
    out = tmp_path / "missing" / "s.h5"
    with pytest.raises(FileNotFoundError, match="directory .*missing' of `out`"):
        sweep(stride_map, ["slope=0.008:0.01:3"], z0=z0, executor=recorder, out=out)
    assert recorder.submitted == []


def test_sweep_refuses_to_resume_a_different_sweep(tmp_path):
    stride_map, z0 = _simplest_map()
    out = tmp_path / "s.h5"
    common = {"z0": z0, "executor": "serial", "progress": False, "out": out}
    sweep(stride_map, ["slope=0.008,0.009,0.01"], chunk_size=2, **common)
    recorder = RecordingExecutor()
    with pytest.raises(StorageError, match=r"different sweep \(chunk_size 2 != 1\)"):
        sweep(
            stride_map, ["slope=0.008,0.009,0.01"], chunk_size=1, **{**common, "executor": recorder}
        )
    with pytest.raises(StorageError, match=r"different sweep \(1 of the points differ\)"):
        sweep(stride_map, ["slope=0.008,0.009,0.011"], chunk_size=2, **common)
    assert recorder.submitted == []


def test_jobs_with_an_executor_warns():
    stride_map, z0 = _simplest_map()
    with pytest.warns(UserWarning, match="`jobs` has no effect"):
        sweep(stride_map, ["slope=0.009"], z0=z0, executor="serial", jobs=2, progress=False)


# ---- results -------------------------------------------------------------------------------


def test_outcome_columns_match_direct_calls():
    stride_map, z0 = _simplest_map()
    table = sweep(
        stride_map,
        ["slope=0.004:0.03:7", "leg_length=1,2"],
        z0=z0,
        n_strides=5,
        executor="serial",
        chunk_size=3,
        progress=False,
    )
    assert set(table.columns) == {"status", "section", "step_time"}
    assert table.columns["section"].shape == (14, 2)
    statuses = set(table.columns["status"].tolist())
    assert Status.COMPLETED in statuses and len(statuses) > 1  # walks and falls both occur
    for i, (slope, length) in enumerate(table.points):
        r = stride_map.with_params(slope=slope, leg_length=length)(z0, n_strides=5)
        assert table.columns["status"][i] == int(r.status)
        assert np.array_equal(table.columns["section"][i], r.z, equal_nan=True)
        assert table.columns["step_time"][i] == r.step_time


def test_serial_and_process_pool_give_identical_tables(pool):
    stride_map, z0 = _compass_map()
    ranges = ["slope=0.01:0.12:11", "mass_hip=5,10,20"]
    for kind, chunk in (("outcome", 4), ("fixed_point", 5)):
        run = functools.partial(
            sweep, stride_map, ranges, kind=kind, z0=z0, chunk_size=chunk, progress=False
        )
        serial = run(executor="serial")
        pooled = run(executor=pool)
        _assert_tables_equal(serial, pooled)
    # the fixed-point sweep has failures, so NaN positions were compared too
    assert np.isnan(serial.columns["section"]).any() and (serial.columns["status"] == 0).any()


def test_compass_fixed_points_along_slope():
    stride_map, z0 = _compass_map()
    degrees = np.array([2.5, 2.75, 3.0, 3.25, 3.5])
    table = sweep(
        stride_map,
        [("slope", np.radians(degrees))],
        kind="fixed_point",
        z0=z0,
        executor="serial",
        chunk_size=2,
        progress=False,
    )
    cols = table.columns
    assert cols["status"].tolist() == [0] * 5
    assert cols["stable"].tolist() == [1] * 5
    assert np.all(cols["residual"] <= 1e-10)
    moduli = np.hypot(cols["multipliers_re"], cols["multipliers_im"])
    assert np.all(moduli < 1.0)
    (i3,) = np.flatnonzero(degrees == 3.0)
    assert table.points[i3, 0] == load_scene(COMPASS_SCENE).params.slope
    assert_allclose(cols["section"][i3], COMPASS_SECTION_5, rtol=0, atol=1e-4)
    # Spong et al. round to 4 decimals: within half a unit of their last digit.
    assert_allclose(cols["section"][i3], COMPASS_SECTION_SPONG, rtol=0, atol=5e-5)
    # The gait speeds up as the slope steepens (stance rate more negative).
    assert np.all(np.diff(cols["section"][:, 1]) < 0)


def test_fixed_point_start_is_a_function_of_the_grid():
    """A point's guess follows the grid from the point nearest the scene's parameters (here
    3 degrees in both grids), never the chunks: the rows from the root outwards agree."""
    stride_map, z0 = _compass_map()
    ranges = [("slope", np.radians([2.0, 2.5, 3.0, 3.5]))]
    whole = sweep(
        stride_map,
        ranges,
        kind="fixed_point",
        z0=z0,
        executor="serial",
        chunk_size=2,
        progress=False,
    )
    second = sweep(
        stride_map,
        [("slope", np.radians([3.0, 3.5]))],
        kind="fixed_point",
        z0=z0,
        executor="serial",
        chunk_size=2,
        progress=False,
    )
    for name in whole.columns:
        assert np.array_equal(whole.columns[name][2:], second.columns[name], equal_nan=True)


def test_run_sweep_command_writes_provenance(tmp_path):
    out = tmp_path / "cmd.h5"
    table = run_sweep_command(
        SIMPLEST_SCENE,
        ["slope=0.008:0.010:3"],
        kind="outcome",
        jobs=1,
        scheduler=None,
        out=out,
        quiet=True,
        strides=2,
        chunk_size=2,
    )
    stored, prov = read(out)
    _assert_tables_equal(table, stored)
    scene = load_scene(SIMPLEST_SCENE)
    # the scene relative to the file's directory: no directory of this machine recorded
    assert not os.path.isabs(prov["scene"])
    assert (out.parent / prov["scene"]).resolve() == Path(SIMPLEST_SCENE).resolve()
    assert prov["model"] == "simplest" and prov["sweep_kind"] == "outcome"
    assert prov["parameters"]["slope"] == {"value": 0.009, "unit": "rad"}  # the scene's
    assert prov["swept"] == {"slope": {"unit": "rad", "start": 0.008, "stop": 0.01, "count": 3}}
    assert (prov["method"], prov["rtol"], prov["atol"]) == (
        scene.compute.method,
        scene.compute.rtol,
        scene.compute.atol,
    )
    from walker.models import get_model

    assert prov["kernel_hash"] == get_model("simplest").kernel_hash
    assert prov["walker_version"] and prov["n_strides"] == 2
    assert table.columns["status"].tolist() == [0, 0, 0]


def test_run_sweep_command_rejects_unknown_name_before_connecting():
    with pytest.raises(ValueError, match="unknown parameter `mass` .*valid names: slope"):
        run_sweep_command(SIMPLEST_SCENE, ["mass=1,2"], scheduler="tcp://127.0.0.1:1")


# ---- resume after SIGKILL ------------------------------------------------------------------

# failures on the steep end; 2,400 points, so that the sweep (about 1 ms a point since its
# warm starts extrapolate) cannot finish between two looks at its checkpoint
KILL_RANGES = ["slope=0.005:0.25:60", "mass_hip=5:20:40"]
KILL_CHUNK = 10


def _kill_sweep(out, executor=None, jobs=2):
    """The sweep the SIGKILL test runs: 2,400 compass fixed points, 240 chunks, a few seconds."""
    stride_map, z0 = _compass_map()
    return sweep(
        stride_map,
        KILL_RANGES,
        kind="fixed_point",
        z0=z0,
        chunk_size=KILL_CHUNK,
        executor=executor,
        jobs=jobs if executor is None else None,
        out=out,
        progress=False,
    )


def _done_flags(path, scratch):
    """The done flags of a checkpoint another process is writing (read from a copy)."""
    try:
        shutil.copyfile(path, scratch)
        with h5py.File(scratch, "r") as f:
            return np.array(f["checkpoint/done"][()], dtype=bool)
    except (OSError, KeyError):
        return None


@pytest.mark.slow  # kill and resume: the integration tier
def test_sigkill_then_resume_gives_the_uninterrupted_table(tmp_path, pool):
    out = tmp_path / "killed.h5"
    script = textwrap.dedent(
        f"""
        import sys
        sys.path.insert(0, {str(TESTS)!r})
        from test_sweep import _kill_sweep
        _kill_sweep({str(out)!r})
        """
    )
    proc = start_python(["-c", script])
    deadline = time.monotonic() + 180  # generous: the machine may be busy
    try:
        while True:
            assert proc.poll() is None, (
                "the sweep finished before it could be killed: "
                + (proc.stderr.read().decode()[-2000:])
            )
            assert time.monotonic() < deadline, "no chunk finished within 180 s"
            flags = _done_flags(out, tmp_path / "copy.h5") if out.exists() else None
            if flags is not None and 3 <= flags.sum() <= flags.size // 2:
                break
            time.sleep(0.02)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)  # the sweep and its pool workers
        proc.wait()
    assert proc.returncode == -signal.SIGKILL

    done_before = _stored_done(out)
    table_before = read(out)[0]
    pending_before = np.flatnonzero(~done_before)
    assert 0 < done_before.sum() < done_before.size

    recorder = RecordingExecutor()
    resumed = _kill_sweep(out, executor=recorder)
    points = resumed.points
    computed = sorted(
        int(np.flatnonzero(np.all(points == point, axis=1))[0])
        for task in recorder.submitted
        for point in task
    )
    # exactly the points of the pending chunks were computed, each once; the done ones were
    # looked up (as the seeds of their lines' next points), not computed
    pending_rows = [
        i for c in pending_before.tolist() for i in range(c * KILL_CHUNK, (c + 1) * KILL_CHUNK)
    ]
    assert computed == pending_rows
    assert _stored_done(out).all()  # no gaps
    assert not np.any(resumed.columns["status"] == -1)
    for i in np.flatnonzero(done_before):
        rows = slice(i * KILL_CHUNK, (i + 1) * KILL_CHUNK)
        for name, col in resumed.columns.items():
            if name == "jump":  # flagged once every point is done: -1 until then
                assert np.all(table_before.columns[name][rows] == -1)
                continue
            assert np.array_equal(col[rows], table_before.columns[name][rows], equal_nan=True)

    fresh = _kill_sweep(None, executor=pool)
    _assert_tables_equal(resumed, fresh)
    assert np.isnan(fresh.columns["section"]).any()  # failures (NaN rows) were compared too


def _stored_done(path):
    with h5py.File(path, "r") as f:
        return np.array(f["checkpoint/done"][()], dtype=bool)


# ---- dask ----------------------------------------------------------------------------------


@pytest.mark.slow  # a local cluster: the integration tier
def test_dask_local_cluster_matches_process_pool(pool):
    distributed = pytest.importorskip("distributed")
    stride_map, z0 = _compass_map()
    ranges = ["slope=0.01:0.12:11", "mass_hip=5,10,20"]
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        for kind, chunk in (("outcome", 4), ("fixed_point", 5)):
            run = functools.partial(
                sweep, stride_map, ranges, kind=kind, z0=z0, chunk_size=chunk, progress=False
            )
            on_dask = run(executor=client)
            pooled = run(executor=pool)
            _assert_tables_equal(on_dask, pooled)
