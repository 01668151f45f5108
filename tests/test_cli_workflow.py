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
