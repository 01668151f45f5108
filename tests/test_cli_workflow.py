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
