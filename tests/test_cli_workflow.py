"""The researcher's workflow on the command line (issue 31): gait measures in every output,
runs from the gait or a given state, export, provenance."""

import json
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from walker.cli import main
from walker.scene import load_scene
from walker.storage import read


def _run(capsys, argv):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


# ----------------------------------------------------------------------------------------
# gait measures


def test_find_json_and_file_carry_the_measures(tmp_path, capsys):
    out = tmp_path / "gait.h5"
    code, text, _ = _run(capsys, ["find", "gaits/kneed_hsu.toml", "--json", "--out", str(out)])
    assert code == 0
    rec = json.loads(text)
    m = rec["measures"]
    slope = rec["parameters"]["slope"]
    assert_allclose(m["cost_of_transport"], math.sin(slope), rtol=0, atol=1e-9)
    assert_allclose(m["step_time"], rec["step_time"], rtol=1e-9, atol=0)
    assert m["energy_lost_knee_lock"] > 0 and m["energy_lost_swing_foot_contact"] > 0
    fp, _ = read(out)
    # JSON writes a missing number (NaN) as null
    assert {k: None if math.isnan(v) else v for k, v in fp.measures.items()} == m


def test_find_prints_the_measures_with_units(capsys):
    code, text, _ = _run(capsys, ["find", "gaits/compass_goswami.toml"])
    assert code == 0
    assert "step_length" in text and " m/s" in text and "cost_of_transport" in text


def test_run_file_carries_the_measures(tmp_path, capsys):
    out = tmp_path / "run.h5"
    code, text, _ = _run(
        capsys, ["run", "gaits/simplest_garcia.toml", "--strides", "3", "--out", str(out)]
    )
    assert code == 0 and "speed" in text
    sol, _ = read(out)
    assert sol.measures["n_steps"] == 3
    # the scene's state is Garcia's gait to its printed digits: nearly periodic
    assert_allclose(sol.measures["cost_of_transport"], math.sin(0.009), rtol=1e-3, atol=0)


@pytest.mark.slow
def test_continue_file_and_json_carry_measure_columns(tmp_path, capsys):
    out = tmp_path / "branch.h5"
    argv = ["continue", "gaits/compass_goswami.toml", "--param", "slope", "--range"]
    code, text, _ = _run(capsys, [*argv, "0.045:0.055", "--json", "--out", str(out)])
    assert code == 0
    rec = json.loads(text)
    br, _ = read(out)
    n = len(br.parameter)
    assert set(br.measures) >= {"step_length", "speed", "cost_of_transport"}
    assert all(col.shape == (n,) for col in br.measures.values())
    assert_allclose(br.measures["cost_of_transport"], np.sin(br.parameter), rtol=0, atol=1e-9)
    assert rec["measures"]["slope"] == pytest.approx(br.parameter.tolist())


def test_fixed_point_sweep_has_measure_columns(tmp_path, capsys):
    out = tmp_path / "sweep.h5"
    argv = ["sweep", "gaits/compass_goswami.toml", "--param", "slope=0.04:0.06:4"]
    code, _, _ = _run(capsys, [*argv, "--jobs", "1", "--quiet", "--out", str(out)])
    assert code == 0
    table, _ = read(out)
    slope = table.points[:, 0]
    assert_allclose(table.columns["cost_of_transport"], np.sin(slope), rtol=0, atol=1e-9)
    assert np.all(table.columns["step_length"] > 0)
    assert np.all(np.isnan(table.columns["cost_of_transport_positive"]))


def test_scene_state_names_are_those_of_the_model():
    scene = load_scene("gaits/kneed_hsu.toml")
    assert tuple(scene.state_names) == ("q1", "q2", "q3", "qd1", "qd2", "qd3")


# ----------------------------------------------------------------------------------------
# runs from the gait or a given state


def test_run_from_gait_is_periodic(tmp_path, capsys):
    """A run from the fixed point comes back to it after each stride (the gait is a cycle),
    unlike a run from the scene's rounded digits."""
    out = tmp_path / "gait_run.h5"
    argv = ["run", "gaits/kneed_hsu.toml", "--from-gait", "--strides", "3", "--out", str(out)]
    code, text, _ = _run(capsys, argv)
    assert code == 0 and "starting from the gait" in text
    sol, prov = read(out)
    assert prov["start"] == "gait"
    x0 = np.array(prov["initial_state"])
    for x_post in sol.events.x_post[sol.events.guard == 1]:  # swing_foot_contact: heel strike
        assert_allclose(x_post, x0, rtol=0, atol=1e-9)
    slope = prov["parameters"]["slope"]["value"]
    assert_allclose(sol.measures["cost_of_transport"], math.sin(slope), rtol=0, atol=1e-9)


def test_run_from_a_given_state(tmp_path, capsys):
    scene = load_scene("gaits/compass_goswami.toml")
    text_state = ",".join(repr(float(v)) for v in scene.state)
    out = tmp_path / "state_run.h5"
    argv = ["run", "gaits/compass_goswami.toml", "--strides", "1"]
    code, _, _ = _run(capsys, [*argv, f"--state={text_state}", "--out", str(out)])
    assert code == 0
    sol, prov = read(out)
    assert prov["start"] == "state" and prov["initial_state"] == scene.state.tolist()
    ref = tmp_path / "scene_run.h5"
    assert _run(capsys, [*argv, "--out", str(ref)])[0] == 0
    np.testing.assert_array_equal(read(ref)[0].x, sol.x)


@pytest.mark.parametrize(
    ("value", "words"),
    [
        ("1,2,3", "--state must have 4 values"),
        ("1,2,nan,3", "--state must be finite"),
        ("1,x,2,3", "--state expects 4 comma-separated numbers"),
    ],
)
def test_run_state_errors_name_the_flag(capsys, value, words):
    code, _, err = _run(capsys, ["run", "gaits/compass_goswami.toml", f"--state={value}"])
    assert code == 2 and words in err and len(err.strip().splitlines()) == 1


def test_run_from_gait_without_a_gait(capsys):
    code, text, _ = _run(capsys, ["run", "gaits/kneed_mcgeer_roundfoot.toml", "--from-gait"])
    assert code == 1 and "no gait to start from" in text
    code, _, err = _run(capsys, ["run", "gaits/double_pendulum.toml", "--from-gait"])
    assert code == 2 and "--from-gait" in err


# ----------------------------------------------------------------------------------------
# provenance


def test_every_file_records_how_it_was_made(tmp_path, capsys):
    import shutil
    import subprocess
    from pathlib import Path

    import h5py
    import scipy

    from walker import _hybrid

    out = tmp_path / "gait.h5"
    argv = ["find", "gaits/compass_goswami.toml", "--out", str(out)]
    assert _run(capsys, argv)[0] == 0
    _, prov = read(out)
    assert prov["command_line"] == f"walker find gaits/compass_goswami.toml --out {out}"
    assert prov["scene_text"] == Path("gaits/compass_goswami.toml").read_text()
    versions = prov["versions"]
    assert versions["numpy"] == np.__version__ and versions["scipy"] == scipy.__version__
    assert versions["h5py"] == h5py.__version__
    assert prov["compiler_flags"] == _hybrid.COMPILE_FLAGS
    if "msvc" not in prov["compiler_flags"]:
        assert "-ffp-contract=off" in prov["compiler_flags"].split()
    assert prov["state_names"] == ["q_stance", "q_swing", "qd_stance", "qd_swing"]
    assert prov["state_units"] == ["rad", "rad", "rad/s", "rad/s"]
    root = Path(__import__("walker").__file__).resolve().parents[1]
    if (root / ".git").exists() and shutil.which("git"):
        head = subprocess.run(
            ["git", "-C", str(root), "rev-parse", "HEAD"], capture_output=True, text=True
        ).stdout.strip()
        assert prov["git_commit"].removesuffix("+dirty") == head


def test_no_git_is_no_commit_and_no_error(tmp_path, capsys, monkeypatch):
    from walker.storage import provenance as P

    monkeypatch.setenv("PATH", str(tmp_path))  # no git on the PATH
    monkeypatch.setattr(P, "_ENVIRONMENT", None)
    env = P.environment_provenance()
    assert "git_commit" not in env and env["versions"]["numpy"] == np.__version__
    monkeypatch.setattr(P, "_ENVIRONMENT", None)  # computed again after the test


def test_a_rerun_with_other_flags_resumes_the_checkpoint(tmp_path, capsys):
    out = tmp_path / "sweep.h5"
    base = ["sweep", "gaits/simplest_garcia.toml", "--param", "slope=0.008:0.01:3"]
    assert _run(capsys, [*base, "--jobs", "1", "--quiet", "--out", str(out)])[0] == 0
    code, text, err = _run(capsys, [*base, "--jobs", "2", "--quiet", "--out", str(out)])
    assert code == 0, err
    _, prov = read(out)
    assert "--jobs 1" in prov["command_line"]  # the file keeps the command that made it


# ----------------------------------------------------------------------------------------
# export: read back with independent readers (csv module, scipy.io.loadmat, json)


def _results(tmp_path, capsys):
    """One file of each kind the command line writes."""
    files = {}
    jobs = ["--jobs", "1", "--quiet"]
    commands = {
        "fixed_point": ["find", "gaits/compass_goswami.toml"],
        "solution": ["run", "gaits/compass_goswami.toml", "--strides", "2"],
        "branch": ["continue", "gaits/simplest_garcia.toml", "--range", "0.009:0.0095"],
        "orbit_diagram": [
            "orbit-diagram",
            "gaits/simplest_garcia.toml",
            "--range",
            "0.009:0.0095",
            "--n",
            "3",
            "--transient",
            "2",
            "--strides",
            "2",
        ],
        "basin": ["basin", "gaits/compass_goswami.toml", "--n", "3", "--strides", "3", *jobs],
        "sweep": ["sweep", "gaits/compass_goswami.toml", "--param", "slope=0.05:0.06:3", *jobs],
    }
    for kind, argv in commands.items():
        out = tmp_path / f"{kind}.h5"
        code, _, err = _run(capsys, [*argv, "--out", str(out)])
        assert code == 0, (kind, err)
        files[kind] = out
    return files


@pytest.fixture(scope="module")
def result_files(tmp_path_factory):
    capsys = _NoCapture()
    return _results(tmp_path_factory.mktemp("results"), capsys)


class _NoCapture:
    def readouterr(self):
        return "", ""


def _read_csv(path):
    import csv

    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def _column(header, rows, name):
    for j, label in enumerate(header):
        if label == name or label.startswith(f"{name} ["):
            return np.array([float(r[j]) if r[j] else np.nan for r in rows])
    raise KeyError(name)


@pytest.mark.slow  # every command's file: the integration tier
def test_export_csv_of_every_kind(result_files, tmp_path, capsys):
    for kind, path in result_files.items():
        out = tmp_path / f"{kind}.csv"
        code, text, err = _run(capsys, ["export", str(path), "--format", "csv", "--out", str(out)])
        assert code == 0, (kind, err)
        result, prov = read(path)
        written = [line.removeprefix("wrote ") for line in text.splitlines()]
        assert all(p.startswith(str(tmp_path / kind)) for p in written)
        with open(tmp_path / f"{kind}_provenance.json") as f:
            assert json.load(f)["kind"] == kind
        if kind == "solution":
            header, rows = _read_csv(tmp_path / "solution_trajectory.csv")
            assert header[:3] == ["t [s]", "phase", "q_stance [rad]"]
            assert_allclose(
                _column(header, rows, "qd_swing"), result.record.x[:, 3], rtol=0, atol=0
            )
            header, rows = _read_csv(tmp_path / "solution_events.csv")
            assert_allclose(_column(header, rows, "t"), result.events.t, rtol=0, atol=0)
        elif kind == "branch":
            header, rows = _read_csv(tmp_path / "branch_branch.csv")
            assert header[0] == "slope [rad]"
            assert_allclose(_column(header, rows, "slope"), result.parameter, rtol=0, atol=0)
            assert_allclose(
                _column(header, rows, "cost_of_transport"),
                np.sin(result.parameter),
                atol=1e-9,
                rtol=0,
            )
        elif kind == "basin":
            header, rows = _read_csv(tmp_path / "basin_basin.csv")
            assert len(rows) == result.outcome.size
            assert_allclose(
                _column(header, rows, "outcome"), result.outcome.ravel(), rtol=0, atol=0
            )
        elif kind == "sweep":
            header, rows = _read_csv(tmp_path / "sweep_sweep.csv")
            assert "section_qd_stance [rad/s]" in header and "speed [m/s]" in header
            assert_allclose(
                _column(header, rows, "step_time"), result.columns["step_time"], rtol=0, atol=0
            )
        elif kind == "fixed_point":
            header, rows = _read_csv(tmp_path / "fixed_point_summary.csv")
            assert_allclose(
                _column(header, rows, "state_q_stance"), result.state[:1], rtol=0, atol=0
            )
            assert "measure_speed [m/s]" in header
        elif kind == "orbit_diagram":
            header, rows = _read_csv(tmp_path / "orbit_diagram_orbit.csv")
            assert header[0] == "slope [rad]" and len(rows) == len(result.parameter)


@pytest.mark.slow  # every command's file: the integration tier
def test_export_mat_of_every_kind(result_files, tmp_path, capsys):
    from scipy.io import loadmat

    for kind, path in result_files.items():
        out = tmp_path / f"{kind}.mat"
        code, _, err = _run(capsys, ["export", str(path), "--format", "mat", "--out", str(out)])
        assert code == 0, (kind, err)
        mat = loadmat(out, squeeze_me=True, struct_as_record=False)
        assert mat["kind"] == kind
        assert json.loads(mat["provenance"])["model"]
        result, _ = read(path)
        if kind == "solution":
            assert_allclose(mat["trajectory"].q_swing, result.record.x[:, 1], rtol=0, atol=0)
            assert mat["units"].trajectory.q_swing == "rad"
        elif kind == "branch":
            assert_allclose(mat["branch"].slope, result.parameter, rtol=0, atol=0)
            assert_allclose(mat["branch"].multiplier_0_re, result.multipliers[:, 0].real, atol=0)
        elif kind == "sweep":
            assert_allclose(mat["sweep"].status, result.columns["status"], rtol=0, atol=0)


@pytest.mark.slow  # every command's file: the integration tier
def test_export_json_of_every_kind(result_files, tmp_path, capsys):
    for kind, path in result_files.items():
        out = tmp_path / f"{kind}.json"
        code, _, err = _run(capsys, ["export", str(path), "--format", "json", "--out", str(out)])
        assert code == 0, (kind, err)
        with open(out) as f:
            rec = json.load(f)
        assert rec["kind"] == kind and rec["tables"]
        if kind == "fixed_point":
            summary = rec["tables"]["summary"]
            result, _ = read(path)
            assert summary["columns"]["step_time"] == [result.step_time]
            assert summary["units"]["step_time"] == "s"


def test_export_refuses_to_overwrite_and_names_the_flag(result_files, tmp_path, capsys):
    out = tmp_path / "gait.json"
    argv = ["export", str(result_files["fixed_point"]), "--format", "json", "--out", str(out)]
    assert _run(capsys, argv)[0] == 0
    code, _, err = _run(capsys, argv)
    assert code == 2 and "--out" in err
    assert _run(capsys, [*argv, "--overwrite"])[0] == 0
    code, _, err = _run(capsys, ["export", str(tmp_path / "missing.h5")])
    assert code == 2


def test_export_of_a_file_without_state_names_uses_the_model(tmp_path):
    """Files written before `state_names` existed still export with named columns."""
    from walker.results import Trajectory
    from walker.storage.export import result_tables

    scene = load_scene("gaits/compass_goswami.toml")
    from walker.simulation.stride import simulate

    sol = simulate("compass", scene.params, scene.state, n_strides=1, output="full")
    tables = result_tables(sol, {"model": "compass"})
    assert list(tables["trajectory"])[2:4] == ["q_stance", "q_swing"]
    assert tables["trajectory"]["qd_swing"][1] == "rad/s"
    assert isinstance(sol.record, Trajectory)


# ----------------------------------------------------------------------------------------
# continuation results that say what happened


@pytest.mark.slow
def test_branch_to_slope_zero_reports_the_vanishing_step(tmp_path, capsys):
    out = tmp_path / "to_zero.h5"
    argv = ["continue", "gaits/compass_goswami.toml", "--range", "0:0.06", "--json"]
    code, text, _ = _run(capsys, [*argv, "--out", str(out)])
    rec = json.loads(text)
    assert code == 0
    assert rec["ends"][0]["at"] == "step_length_vanishes" and rec["ends"][1]["at"] == "bound"
    assert "step length vanishes" in rec["message"] and "Fold" not in rec["message"]
    assert not any(b["kind"] == "fold" for b in rec["bifurcations"])
    br, prov = read(out)
    assert prov["ends"][0]["at"] == "step_length_vanishes"
    lengths = br.measures["step_length"]
    assert lengths[0] < 0.01 * lengths.max() and br.parameter[0] < 1e-6


@pytest.mark.slow
def test_branch_ending_in_a_trip_is_a_result(tmp_path, capsys):
    out = tmp_path / "trip.h5"
    argv = ["continue", "gaits/kneed_hsu.toml", "--range", "0:0.3"]
    code, text, _ = _run(capsys, [*argv, "--out", str(out)])
    assert code == 0
    assert "(tripped)" in text and "Try a state" not in text
    _, prov = read(out)
    assert prov["ends"][1]["at"] == "tripped"


# ----------------------------------------------------------------------------------------
# finding your way


@pytest.mark.parametrize(
    ("argv", "suggestion"),
    [
        (["find", "gaits/kneed_hsu.toml", "--set", "slpe=0.05"], "did you mean `slope`?"),
        (["continue", "gaits/kneed_hsu.toml", "--param", "slop", "--range", "0:1"], "`slope`"),
        (["params", "kneeed"], "did you mean 'kneed'?"),
        (["scene", "new", "kneed", "--preset", "mcger"], "did you mean `mcgeer`?"),
        (
            [
                "sweep",
                "gaits/kneed_hsu.toml",
                "--kind",
                "fixed_pont",
                "--param",
                "slope=0:1:2",
                "--out",
                "x.h5",
            ],
            "did you mean 'fixed_point'?",
        ),
    ],
)
def test_misspelt_names_get_a_suggestion(capsys, argv, suggestion):
    code, _, err = _run_exit(capsys, argv)
    assert code == 2 and suggestion in err


def _run_exit(capsys, argv):
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse's own errors
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


def test_misspelt_scene_keys_get_a_suggestion(tmp_path, capsys):
    scene = tmp_path / "typo.toml"
    scene.write_text(
        '[scene]\nmodel = "compas"\n[parameters]\npreset = "goswami"\n'
        "[initial]\nstate = [0.2, -0.3, -1.0, -0.4]\n"
    )
    code, _, err = _run(capsys, ["find", str(scene)])
    assert code == 2 and "did you mean `compass`?" in err
    scene.write_text(scene.read_text().replace("compas", "compass").replace("preset", "prest"))
    code, _, err = _run(capsys, ["find", str(scene)])
    assert code == 2 and "did you mean `preset`?" in err


def test_set_errors_name_set(capsys):
    code, _, err = _run(capsys, ["find", "gaits/kneed_hsu.toml", "--set", "slope=5"])
    assert code == 2 and "--set" in err and "overrides" not in err
    code, _, err = _run(capsys, ["find", "gaits/kneed_hsu.toml", "--set", "slpe=0.05"])
    assert code == 2 and "--set" in err and "overrides" not in err


def test_a_rerun_says_it_resumes(tmp_path, capsys):
    out = tmp_path / "sweep.h5"
    argv = ["sweep", "gaits/simplest_garcia.toml", "--param", "slope=0.008:0.01:3"]
    argv += ["--jobs", "1", "--quiet", "--out", str(out)]
    code, _, err = _run(capsys, argv)
    assert code == 0 and "resuming" not in err
    code, _, err = _run(capsys, argv)
    assert code == 0 and "resuming" in err and "3 of 3 chunks kept" in err


def test_basin_takes_absolute_bounds_per_axis(tmp_path, capsys):
    out = tmp_path / "basin.h5"
    argv = ["basin", "gaits/compass_goswami.toml", "--n", "3", "--strides", "2", "--jobs", "1"]
    code, _, err = _run(
        capsys, [*argv, "--quiet", "--lo=0.2,-1.2", "--hi=0.25,-1.0", "--out", str(out)]
    )
    assert code == 0, err
    basin, _ = read(out)
    assert basin.x.tolist() == [0.2, 0.225, 0.25] and basin.y.tolist() == [-1.2, -1.1, -1.0]
    for extra, words in (
        (["--lo=0.2,-1.2"], "--lo needs --hi"),
        (["--lo=0.3,-1.2", "--hi=0.25,-1.0"], "--lo must be below --hi"),
        (["--lo=0.2", "--hi=0.25,-1.0"], "--lo expects two finite numbers"),
    ):
        code, _, err = _run(capsys, [*argv, *extra, "--out", str(tmp_path / "other.h5")])
        assert code == 2 and words in err


def test_a_file_written_from_python_names_its_state_columns(tmp_path):
    """storage.write with a caller's provenance that names only the model: the file still
    carries the state's names and units, read here with h5py alone."""
    import h5py

    from walker.results import OrbitDiagram
    from walker.storage import write

    path = tmp_path / "orbit.h5"
    result = OrbitDiagram("slope", np.array([0.01]), np.array([[0.2]]))
    write(path, result, provenance={"model": "kneed"})
    with h5py.File(path, "r") as f:
        assert json.loads(f.attrs["state_names"]) == ["q1", "q2", "q3", "qd1", "qd2", "qd3"]
        assert json.loads(f.attrs["state_units"])[3] == "rad/s"
    _, prov = read(path)
    assert "state_names" not in prov  # the caller's provenance reads back unchanged
