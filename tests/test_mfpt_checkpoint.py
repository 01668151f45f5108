"""The resumable Monte-Carlo MFPT (``monte_carlo(..., checkpoint=FILE)``, ``walker mfpt
--out``): finished chunks of runs are kept when the estimate is interrupted, the same call
walks only the chunks left, and the result is the same run for run as an estimate walked in
one go, for any ``jobs`` (each run depends only on its own seed)."""

import numpy as np
import pytest

from walker import StrideMap, load_scene
from walker.analysis.mfpt import gait_on_mean_slope, monte_carlo
from walker.cli import main
from walker.storage import CheckpointMismatch, SweepStore, read

RIMLESS = "gaits/rimless_wheel.toml"
ARGS = {"slope_std": 0.015, "runs": 50, "seed": 3}


@pytest.fixture(scope="module")
def rimless():
    scene = load_scene(RIMLESS)
    return gait_on_mean_slope(StrideMap.from_scene(scene), scene.state, 0.08)


def _interrupt_after(monkeypatch, k):
    """Ctrl-C (a KeyboardInterrupt) right after the ``k``-th chunk is written, once; the
    chunks written are listed in the list returned."""
    written = []
    original = SweepStore.write_chunk
    interrupted = []

    def write_chunk(self, i, values):
        original(self, i, values)
        written.append(i)
        if len(written) == k and not interrupted:
            interrupted.append(i)
            raise KeyboardInterrupt

    monkeypatch.setattr(SweepStore, "write_chunk", write_chunk)
    return written


def test_an_interrupted_estimate_resumes_to_the_same_result(rimless, tmp_path, monkeypatch):
    P, z0 = rimless
    whole = monte_carlo(P, z0, jobs=1, **ARGS)
    path = tmp_path / "m.h5"
    written = _interrupt_after(monkeypatch, 3)
    with pytest.raises(KeyboardInterrupt):
        monte_carlo(P, z0, jobs=1, checkpoint=path, chunk_runs=8, **ARGS)
    assert written == [0, 1, 2]
    written.clear()
    resumed = monte_carlo(P, z0, jobs=2, checkpoint=path, chunk_runs=8, **ARGS)
    assert written == [3, 4, 5, 6]  # only the chunks left: 50 runs in chunks of 8
    np.testing.assert_array_equal(resumed.steps, whole.steps)
    np.testing.assert_array_equal(resumed.status, whole.status)
    assert resumed.mfpt == whole.mfpt and resumed.mfpt_stderr == whole.mfpt_stderr


def test_a_checkpoint_of_another_estimate_is_refused(rimless, tmp_path):
    P, z0 = rimless
    path = tmp_path / "m.h5"
    monte_carlo(P, z0, checkpoint=path, chunk_runs=16, **ARGS)
    with pytest.raises(CheckpointMismatch):
        monte_carlo(P, z0, checkpoint=path, chunk_runs=16, **{**ARGS, "seed": 4})
    other = monte_carlo(
        P, z0, checkpoint=path, chunk_runs=16, overwrite=True, **{**ARGS, "seed": 4}
    )
    assert other.seed == 4


def test_cli_mfpt_out_resumes_after_an_interrupt(rimless, tmp_path, monkeypatch, capsys):
    out = tmp_path / "m.h5"
    argv = ["mfpt", RIMLESS, "--mean", "0.08", "--std", "0.015", "--runs", "50", "--seed", "3"]
    argv += ["--out", str(out), "--chunk-runs", "8", "--json"]
    assert main(argv[:10] + ["--json"]) == 0  # no --out: walked in one go
    whole = capsys.readouterr().out
    written = _interrupt_after(monkeypatch, 2)
    assert main([*argv, "--jobs", "1"]) == 130
    capsys.readouterr()
    assert read(out)[1]["kind"] == "sweep"  # the checkpoint of the runs
    written.clear()
    assert main([*argv, "--jobs", "2"]) == 0
    captured = capsys.readouterr()
    assert "resuming" in captured.err
    assert written == [2, 3, 4, 5, 6]
    assert captured.out == whole
    result, prov = read(out)
    assert prov["kind"] == "mfpt" and prov["command"] == "mfpt"
    assert result.runs == 50


def test_chunks_as_executor_tasks_give_the_same_runs(rimless, tmp_path, monkeypatch):
    """Chunks of runs as tasks of an executor (a thread pool here, a dask cluster in the
    slow test below), resuming a checkpoint interrupted in this process."""
    import concurrent.futures as cf

    P, z0 = rimless
    whole = monte_carlo(P, z0, jobs=1, **ARGS)
    path = tmp_path / "m.h5"
    written = _interrupt_after(monkeypatch, 2)
    with pytest.raises(KeyboardInterrupt):
        monte_carlo(P, z0, checkpoint=path, chunk_runs=8, **ARGS)
    written.clear()
    with cf.ThreadPoolExecutor(2) as pool:
        resumed = monte_carlo(P, z0, checkpoint=path, chunk_runs=8, executor=pool, **ARGS)
        fresh = monte_carlo(P, z0, chunk_runs=7, executor=pool, **ARGS)
    assert sorted(written) == [2, 3, 4, 5, 6]
    for r in (resumed, fresh):
        np.testing.assert_array_equal(r.steps, whole.steps)
        np.testing.assert_array_equal(r.status, whole.status)


@pytest.mark.slow
def test_a_dask_cluster_gives_the_same_runs(rimless):
    distributed = pytest.importorskip("distributed")
    P, z0 = rimless
    whole = monte_carlo(P, z0, jobs=1, **ARGS)
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        on_dask = monte_carlo(P, z0, chunk_runs=8, executor=client, **ARGS)
    np.testing.assert_array_equal(on_dask.steps, whole.steps)
    np.testing.assert_array_equal(on_dask.status, whole.status)


def test_cli_unreachable_scheduler_is_exit_2(tmp_path, capsys):
    pytest.importorskip("distributed")
    argv = ["mfpt", RIMLESS, "--mean", "0.08", "--std", "0.015", "--runs", "8", "--seed", "1"]
    assert main([*argv, "--scheduler", "tcp://127.0.0.1:1"]) == 2
    assert "--scheduler tcp://127.0.0.1:1" in capsys.readouterr().err
