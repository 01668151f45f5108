"""docs/tutorial.md is true: its commands run, in order, in a fresh directory (with a copy of
gaits/), each exits 0, the numbers its prose quotes are the ones the commands print or store,
and every figure it shows is one the commands make."""

from __future__ import annotations

import re
import shlex
import shutil
from pathlib import Path

import numpy as np
import pytest

from walker.cli import main

ROOT = Path(__file__).resolve().parent.parent
TUTORIAL = ROOT / "docs" / "tutorial.md"


def _commands() -> list[list[str]]:
    lines = TUTORIAL.read_text(encoding="utf-8").splitlines()
    return [shlex.split(line[2:])[1:] for line in lines if line.startswith("$ walker ")]


def _figures() -> list[str]:
    return re.findall(r"!\[[^\]]*\]\(tutorial/([^)]+)\)", TUTORIAL.read_text(encoding="utf-8"))


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    """Run every command of the tutorial once; (outputs by command line, directory)."""
    import contextlib
    import io
    import os

    work = tmp_path_factory.mktemp("tutorial")
    shutil.copytree(ROOT / "gaits", work / "gaits")
    outputs: dict[str, str] = {}
    old = os.getcwd()
    os.chdir(work)
    try:
        for argv in _commands():
            buf = io.StringIO()
            with contextlib.redirect_stdout(buf):
                code = main(argv)
            outputs[" ".join(argv)] = buf.getvalue()
            assert code == 0, (argv, buf.getvalue())
    finally:
        os.chdir(old)
    return outputs, work


def _output(outputs, prefix: str) -> str:
    (text,) = [v for k, v in outputs.items() if k.startswith(prefix)]
    return text


def test_the_tutorial_has_its_commands_and_figures():
    commands = _commands()
    assert len(commands) >= 9
    assert {c[0] for c in commands} >= {"find", "continue", "sweep", "orbit-diagram", "plot"}
    assert len(_figures()) >= 4


@pytest.mark.slow  # the tutorial's commands: the integration tier
def test_every_figure_shown_is_made_by_the_commands(session):
    _, work = session
    for name in _figures():
        assert (work / "figures" / name).is_file(), name
        assert (TUTORIAL.parent / "tutorial" / name).is_file(), name


@pytest.mark.slow  # the tutorial's commands: the integration tier
@pytest.mark.regression_pin
def test_kneed_numbers_quoted(session):
    """REGRESSION PIN: the numbers docs/tutorial.md quotes for the kneed walker are walker's own:
    this keeps the tutorial true, it does not check them against a reference.
    """
    outputs, work = session
    found = _output(outputs, "find gaits/kneed_hsu.toml")
    step_time = re.search(r"step time\s+([0-9.]+) s", found)
    assert step_time and round(float(step_time.group(1)), 4) == 0.5646
    moduli = [float(v) for v in re.findall(r"\|\.\| = ([0-9.]+)", found)]
    assert round(max(moduli), 4) == 0.6554
    branch = _output(outputs, "continue gaits/kneed_hsu.toml")
    fold = re.search(r"fold\s+slope = ([0-9.]+)", branch)
    assert fold and round(float(fold.group(1)), 5) == 0.03179
    assert "Reached slope = 0.08" in branch

    from walker import storage
    from walker.models import get_model
    from walker.plotting.branch import branch_measures
    from walker.scene import load_scene

    result, _ = storage.read(work / "kneed_branch.h5")
    scene = load_scene(work / "gaits" / "kneed_hsu.toml")
    m = branch_measures(result, get_model("kneed"), scene.params)
    order = np.argsort(result.parameter)
    step = np.asarray(m.step_time)[order, 0]
    mod = np.asarray(m.max_multiplier)[order]
    assert round(float(step[0]), 3) == 0.524 and round(float(step[-1]), 3) == 0.595
    assert round(float(mod[-1]), 2) == 0.48 and abs(float(mod[0]) - 1.0) < 1e-3
    assert np.allclose(np.asarray(m.cost_of_transport)[order], np.sin(result.parameter[order]))

    sweep = _output(outputs, "sweep gaits/kneed_hsu.toml")
    assert "25 points, 20 completed" in sweep


@pytest.mark.slow  # the tutorial's commands: the integration tier
@pytest.mark.regression_pin
def test_compass_numbers_quoted(session):
    """REGRESSION PIN: the numbers docs/tutorial.md quotes for the compass gait are walker's own:
    this keeps the tutorial true, it does not check them against a reference.
    """
    outputs, _ = session
    branch = _output(outputs, "continue gaits/compass_goswami.toml")
    doublings = [float(v) for v in re.findall(r"period_doubling\s+slope = ([0-9.]+)", branch)]
    assert [round(v, 5) for v in doublings] == [0.07664, 0.08577]
    orbits = _output(outputs, "orbit-diagram gaits/compass_goswami.toml")
    assert re.search(r"slope 0\.05\.\.0\.0755\d*\s+period 1", orbits)
    assert re.search(r"slope 0\.0771\d*\.\.0\.0852\d*\s+period 2", orbits)
    assert re.search(r"slope 0\.0861\d*\.\.\S+\s+period 4", orbits)
    assert re.search(r"period 8", orbits)
    # the first fall lies in the chaotic band: it moves with rounding (0.0909 or 0.0912)
    falls = re.search(r"slope (0\.09\d*)\.\.0\.095\s+fell", orbits)
    assert falls and 0.0900 <= float(falls.group(1)) <= 0.0920, orbits
