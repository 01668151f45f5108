"""Extreme but valid inputs (issue 33's probe): parameters at the bounds ``walker params``
allows, huge ``t_max``, tiny fixed steps and huge periods.  Before, these ended in an
internal error (exit 3: ``max_steps`` overflowing an int64, ``int(inf)``) or ran for
minutes.  Each must now end with an outcome (exit 0 or 1) or be refused up front naming
the setting (exit 2): step budgets are computed in floating point and clamped
(walker.simulation.region.stride_max_steps), a fixed step that needs more than
``walker._checks.MAX_FIXED_STEPS`` steps per stride and a period above
``walker.cli.find.MAX_PERIOD`` are refused.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from walker._checks import MAX_FIXED_STEPS
from walker.cli import main

GAITS = Path(__file__).resolve().parents[1] / "gaits"
COMPASS = str(GAITS / "compass_goswami.toml")
SIMPLEST = str(GAITS / "simplest_garcia.toml")


def _scene(tmp_path, base: str, **compute) -> str:
    """A copy of gaits/<base>.toml with [compute] keys replaced or added."""
    text = (GAITS / f"{base}.toml").read_text()
    for key, value in compute.items():
        text, n = re.subn(rf"(?m)^{key}\s*=.*$", f"{key} = {value}", text)
        if n == 0:
            text = text.replace("[compute]\n", f"[compute]\n{key} = {value}\n", 1)
    path = tmp_path / f"{base}_extreme.toml"
    path.write_text(text)
    return str(path)


def _find(capsys, argv):
    code = main(["find", *argv])
    return code, capsys.readouterr().err


@pytest.mark.parametrize(
    ("argv", "codes"),
    [
        ([COMPASS, "--set", "g=1e300"], (1,)),
        ([SIMPLEST, "--set", "leg_length=5e-324"], (1,)),
        (
            [SIMPLEST, "--set", "g=1e12", "--set", "damping_ankle=1e6", "--set", "leg_length=1e-6"],
            (1,),
        ),
        # found by tests/test_probe_stress.py: leg_length / g underflows to 0, so the time
        # scale (the unit of the step budgets) is 0 s; refused naming both keys
        ([SIMPLEST, "--set", "g=1.8e233", "--set", "leg_length=4.3e-208"], (2,)),
    ],
    ids=["compass_g_1e300", "simplest_leg_5e-324", "simplest_runaway", "simplest_scale_0"],
)
def test_parameters_at_their_bounds_end_with_an_outcome(capsys, argv, codes):
    code, err = _find(capsys, argv)
    assert code in codes, err
    assert "internal error" not in err


def test_the_double_pendulum_without_gravity_runs(capsys):
    """g = 0 is allowed for the double pendulum (found by tests/test_probe_stress.py: a
    ZeroDivisionError, exit 3, in the time scale sqrt(length / g), now infinite)."""
    scene = str(GAITS / "double_pendulum.toml")
    code = main(["run", scene, "--strides", "3", "--set", "g=0.0", "--set", "com_2=0.0"])
    out, err = capsys.readouterr()
    assert code in (0, 1), err
    assert "internal error" not in err


def test_a_huge_t_max_runs(tmp_path, capsys):
    code, err = _find(capsys, [_scene(tmp_path, "compass_goswami", t_max="1e308")])
    assert code == 0, err  # the budget is clamped; the gait's stride ends long before


@pytest.mark.parametrize("first_step", ["5e-324", "1e-9"])
def test_a_tiny_euler_step_is_refused_before_any_work(tmp_path, capsys, first_step):
    scene = _scene(tmp_path, "compass_goswami", method='"Euler"', first_step=first_step)
    code, err = _find(capsys, [scene])
    assert code == 2
    assert err.startswith("walker: error: `first_step` = ") and err.count("\n") == 1
    assert f"more than the {MAX_FIXED_STEPS} a stride may take" in err


def test_a_period_of_a_million_strides_is_refused(tmp_path, capsys):
    code, err = _find(capsys, [_scene(tmp_path, "compass_goswami", strides="1000000")])
    assert code == 2
    assert "[compute] strides (the period searched) must be <= 100,000" in err
    code, err = _find(capsys, [COMPASS, "--period", "100001"])
    assert code == 2
    assert err.startswith("walker: error: --period (the period searched) must be <= 100,000")


def test_a_starting_step_that_is_nan_ends_the_run(capsys):
    """g = 6.8e113 with a Bezier coefficient of 2.7e207 (found by tests/test_probe_stress.py)
    gives a non-finite starting rate, hence a NaN starting step, which ``h < min_step`` let
    through: 1e6 rejected steps at t = 0 until MAX_STEPS.  It now ends at once in NONFINITE
    (walker/_core/hybrid.c)."""
    five_link = str(GAITS / "five_link_hzd.toml")
    sets = ["--set", "g=6.81234928876103e+113", "--set", "bezier_tibia_1=2.655330579761565e+207"]
    code = main(["run", five_link, "--strides", "3", *sets])
    out, err = capsys.readouterr()
    assert code == 1, err
    assert "status NONFINITE" in out
    assert "(0 rejected)" in out


@pytest.mark.slow
def test_the_five_link_walker_at_g_1e12_ends_with_an_outcome(capsys):
    """Ends with the plain stride's fall (FELL_BACKWARD, exit 1): the guess's stride fails
    at the coarsest tolerance, so the search confirms it at the scene's own tolerance
    without the Jacobian (244 steps) before any variational run, which here runs to its
    clamped budget of 1e5 steps at about 1 ms a step (walker/_core/newton.c, here through
    callbacks: the five-link lift is in Python)."""
    code = main(["find", str(GAITS / "five_link_hzd.toml"), "--set", "g=1e12"])
    out, err = capsys.readouterr()
    assert code == 1, err
    assert "FELL_BACKWARD" in out


def test_events_that_do_not_advance_time_end_the_run(capsys):
    """The Coulomb kneed walker with a shank's centre of mass 7.4e37 m from the knee: after
    its first event the stick-slip reset's state slips again at the same instant, so every
    step found an event at one time (6.4e-19 s) and the run took about 60 s to reach
    MAX_STEPS through 1e6 such events.  Sixteen events in a row that do not advance time
    now end it as CHATTERING (walker/_core/hybrid.c), after a few hundred steps."""
    scene = str(GAITS / "kneed_coulomb_hsu.toml")
    sets = ["--set", "shank_com_from_foot=0", "--set", "damping_ankle=0"]
    code = main(["run", scene, "--strides", "3", *sets, "--set", "shank_com_to_knee=7.4e37"])
    out, err = capsys.readouterr()
    assert code == 1, err
    assert "status CHATTERING" in out
    events = int(re.search(r"events (\d+), steps", out).group(1))
    assert events <= 64, out
