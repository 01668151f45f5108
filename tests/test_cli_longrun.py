"""``walker run`` over many strides: a step budget that grows with the strides and a flag to
set it; runs longer than a block are integrated block by block and streamed to the file, and
give the one-piece run's states (the reference: one ``simulate`` call over all strides)."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import walker.cli.run as run_module
from walker import load_scene
from walker.cli import main
from walker.simulation.stride import simulate, solver_settings
from walker.status import Status
from walker.storage import read

KNEED = "gaits/kneed_hsu.toml"


def _one_piece(scene_path, strides, **kw):
    scene = load_scene(scene_path)
    c = scene.compute
    settings = solver_settings(c)
    settings.pop("t_max", None)
    return simulate(
        scene.walker_model,
        scene.params,
        scene.state,
        n_strides=strides,
        t_max=c.t_max * strides,
        phase0=scene.phase,
        max_steps=10**8,
        **settings,
        **kw,
    )


@pytest.mark.parametrize("sample_rate", [None, 50.0])
def test_blocks_streamed_to_the_file_give_the_one_piece_run(
    tmp_path, capsys, monkeypatch, sample_rate
):
    """Blocks of 4 strides over 11 strides: the stored steps, events and final state are
    those of one run over all 11, bit for bit; the times agree to rounding (each block starts
    its clock from the last one's end, without the one-piece run's compensation term)."""
    monkeypatch.setattr(run_module, "BLOCK_STRIDES", 4)
    out = tmp_path / "run.h5"
    argv = ["run", KNEED, "--strides", "11", "--out", str(out)]
    if sample_rate is not None:
        argv += ["--sample-rate", str(sample_rate)]
    assert main(argv) == 0
    sol, prov = read(out)  # checksum verified
    assert prov["status"] == "COMPLETED"
    if sample_rate is None:
        one = _one_piece(KNEED, 11, output="full")
        assert np.array_equal(sol.record.x, one.record.x)
        assert np.array_equal(sol.record.phase, one.record.phase)
        assert_allclose(sol.record.t, one.record.t, rtol=0, atol=1e-12)
    else:
        first = _one_piece(KNEED, 11, output="events")
        times = np.arange(0.0, first.t, 1.0 / sample_rate)
        one = _one_piece(KNEED, 11, output="samples", sample_times=times)
        assert np.array_equal(sol.samples.t, one.samples.t)
        assert_allclose(sol.samples.x, one.samples.x, rtol=0, atol=1e-10)
    assert np.array_equal(sol.events.x_post, one.events.x_post)
    assert np.array_equal(sol.events.guard, one.events.guard)
    assert np.array_equal(sol.x, one.x)
    for name in ("n_strides", "n_events", "n_steps", "n_rejected", "n_rhs"):
        assert getattr(sol, name) == getattr(one, name), name
    assert sol.status == Status.COMPLETED


def test_step_budget_grows_with_the_strides():
    """The former fixed budget of 1,000,000 steps ended a kneed run after about 21.7k strides
    (46 steps each): the default now allows the stride map's per-stride budget each."""
    scene = load_scene(KNEED)
    assert run_module.run_budget(scene, 100_000) >= 46 * 100_000 * 10
    assert run_module.run_budget(scene, 1) == 1_000_000


def test_max_steps_flag_sets_the_budget_and_the_message_names_it(capsys):
    assert main(["run", KNEED, "--strides", "3", "--max-steps", "20"]) == 1
    out = capsys.readouterr().out
    assert "MAX_STEPS" in out and "--max-steps" in out


@pytest.mark.parametrize("value", ["0", "-5", str(2**63)])
def test_max_steps_out_of_range_is_exit_2(capsys, value):
    assert main(["run", KNEED, "--strides", "3", "--max-steps", value]) == 2
    assert "--max-steps" in capsys.readouterr().err


def test_swing_depth_is_reported_when_asked(capsys, monkeypatch):
    monkeypatch.setattr(run_module, "BLOCK_STRIDES", 2)
    assert main(["run", KNEED, "--strides", "3"]) == 0
    assert "swing foot" not in capsys.readouterr().out  # a long run: not by default
    assert main(["run", KNEED, "--strides", "3", "--swing-depth"]) == 0
    assert "swing foot" in capsys.readouterr().out
    assert main(["run", KNEED, "--strides", "2"]) == 0  # a short run: by default
    assert "swing foot" in capsys.readouterr().out
