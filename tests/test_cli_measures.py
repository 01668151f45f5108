"""``walker mfpt``, ``walker gsn`` and ``walker stepdown``: their JSON keys, the --jobs
invariance of the Monte Carlo, the stored result, and the exit status of bad input."""

import json

import numpy as np
import pytest

from walker.cli import main
from walker.storage import read

RIMLESS = "gaits/rimless_wheel.toml"
COMPASS = "gaits/compass_goswami.toml"


def _json_of(capsys, argv):
    code = main(argv)
    out = capsys.readouterr().out
    return code, json.loads(out)


def test_mfpt_json_keys_and_jobs_invariance(capsys, tmp_path):
    argv = ["mfpt", COMPASS, "--std", "0.005", "--runs", "60", "--seed", "4", "--json"]
    code1, one = _json_of(capsys, [*argv, "--jobs", "1"])
    code2, two = _json_of(capsys, [*argv, "--jobs", "2", "--out", str(tmp_path / "m.h5")])
    assert code1 == code2 == 0
    assert {"mfpt", "mfpt_stderr", "runs", "failed"} <= set(one)
    assert one == two and one["runs"] == 60
    result, prov = read(tmp_path / "m.h5")
    assert prov["kind"] == "mfpt" and prov["command"] == "mfpt"
    np.testing.assert_allclose(result.mfpt, one["mfpt"], rtol=1e-15, atol=0)
    assert result.steps.shape == (60,) and result.failed == one["failed"]
    assert main(["plot", str(tmp_path / "m.h5"), "--out", str(tmp_path)]) == 0
    assert (tmp_path / "m_survival.png").is_file()


@pytest.mark.slow
def test_mfpt_markov_key(capsys):
    argv = ["mfpt", RIMLESS, "--std", "0.02", "--runs", "40", "--seed", "1", "--markov"]
    code, record = _json_of(capsys, [*argv, "--json"])
    assert code == 0 and record["mfpt_markov"] > 1.0
    assert record["markov"]["levels"][0]["n_mesh"] >= 2


@pytest.mark.parametrize(
    "argv",
    [
        ["mfpt", COMPASS, "--std", "-1", "--runs", "4", "--seed", "1"],
        ["mfpt", COMPASS, "--std", "0.01", "--runs", "0", "--seed", "1"],
        ["mfpt", COMPASS, "--std", "0.01", "--runs", "4", "--seed", "-1"],
        ["mfpt", COMPASS, "--std", "0.01", "--runs", "4", "--seed", "1", "--jobs", "0"],
        [
            "mfpt",
            COMPASS,
            "--std",
            "0.01",
            "--runs",
            "4",
            "--seed",
            "1",
            "--height-std",
            "0.01",
            "--markov",
        ],
        ["mfpt", "gaits/double_pendulum.toml", "--std", "0.01", "--runs", "4", "--seed", "1"],
        ["gsn", "gaits/double_pendulum.toml"],
        ["stepdown", "gaits/double_pendulum.toml"],
    ],
)
def test_bad_input_exits_2_with_one_line(capsys, argv):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("walker: error:")


def test_gsn_and_stepdown_json(capsys):
    code, g = _json_of(capsys, ["gsn", COMPASS, "--json"])
    assert code == 0 and g["gsn"] > 0 and len(g["step_time_response"]) == 10
    code, s = _json_of(capsys, ["stepdown", RIMLESS, "--json"])
    assert code == 0 and 0 < s["step_up"] < s["up_fails"] <= s["step_up"] + 1e-6


def test_five_link_mfpt_runs(capsys):
    """The actuated five-link walker (its terrain entry's compiled lift): ``walker mfpt``
    gives the same runs for any --jobs, and every failure is counted under its status."""
    argv = ["mfpt", "gaits/five_link_hzd.toml", "--std", "0.02", "--runs", "4", "--seed", "2"]
    code1, one = _json_of(capsys, [*argv, "--json", "--jobs", "1"])
    code2, two = _json_of(capsys, [*argv, "--json", "--jobs", "2"])
    assert code1 == code2 == 0 and one == two
    assert one["runs"] == 4 and 0 <= one["failed"] <= 4 and one["mfpt"] > 0
    assert sum(one["failures"].values()) == one["failed"]


@pytest.mark.slow
@pytest.mark.parametrize(
    ("scene", "one_sided"),
    [("gaits/five_link_hzd.toml", False), ("gaits/three_link_grizzle.toml", True)],
)
def test_actuated_gsn_runs(capsys, scene, one_sided):
    """``walker gsn`` on the actuated walkers gives the norm of
    :func:`walker.analysis.gsn.gait_sensitivity` (checked against finite differences in
    tests/test_gsn.py); the three-link gait's is one-sided (docs/measures.md)."""
    code, g = _json_of(capsys, ["gsn", scene, "--json"])
    assert code == 0 and g["status"] == "COMPLETED" and g["gsn"] > 0
    assert g["one_sided"] == one_sided
