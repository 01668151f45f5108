"""Orbit diagrams in blocks (walker.analysis.orbit_run): one chain is
walker.analysis.orbit.orbit_diagram bit for bit whatever the block size; more chains give the same
diagram on any executor and after a resume; ``walker orbit-diagram`` checkpoints beside --out and
resumes."""

from __future__ import annotations

import concurrent.futures as cf
from pathlib import Path

import numpy as np
import pytest

from walker import StrideMap, load_scene
from walker.analysis.orbit import orbit_diagram
from walker.analysis.orbit_run import checkpoint_path, orbit_block, orbit_diagram_blocks
from walker.cli import main
from walker.storage import SweepStore, read

REPO = Path(__file__).resolve().parents[1]
SCENE = REPO / "gaits" / "simplest_garcia.toml"
SLOPES = np.linspace(0.015, 0.019, 13)
RUN = {"n_transient": 60, "n_keep": 8, "coordinate": 0}


@pytest.fixture(scope="module")
def simplest():
    scene = load_scene(SCENE)
    stride_map = StrideMap.from_scene(scene)
    return stride_map, stride_map.project(scene.state)


def test_one_chain_is_orbit_diagram_for_any_block(simplest):
    stride_map, z0 = simplest
    reference = orbit_diagram(stride_map, z0, SLOPES, **RUN)
    # the period-doubling cascade of the simplest walker is in range: rows differ in kind
    assert len({np.unique(np.round(r, 8)).size for r in reference.values}) > 1
    for block in (1, 3, None):
        d = orbit_diagram_blocks(stride_map, z0, SLOPES, block=block, executor="serial", **RUN)
        assert np.array_equal(d.values, reference.values, equal_nan=True)


def test_chains_give_one_answer_on_any_executor(simplest):
    stride_map, z0 = simplest
    serial = orbit_diagram_blocks(stride_map, z0, SLOPES, chains=3, executor="serial", **RUN)
    threads = orbit_diagram_blocks(stride_map, z0, SLOPES, chains=3, jobs=2, block=2, **RUN)
    assert np.array_equal(serial.values, threads.values, equal_nan=True)
    with cf.ProcessPoolExecutor(2) as pool:
        pooled = orbit_diagram_blocks(stride_map, z0, SLOPES, chains=3, executor=pool, **RUN)
    assert np.array_equal(serial.values, pooled.values, equal_nan=True)
    # each chain starts from z0: its first value is the one-value diagram from z0
    first = orbit_diagram(stride_map, z0, SLOPES[5:6], **RUN)
    assert np.array_equal(serial.values[5], first.values[0], equal_nan=True)


class Recording(cf.Executor):
    def __init__(self):
        self.blocks = []

    def submit(self, fn, /, *args):
        self.blocks.append(np.array(args[1]))
        future = cf.Future()
        future.set_result(fn(*args))
        return future


def test_resume_runs_only_the_pending_blocks(simplest, tmp_path):
    stride_map, z0 = simplest
    columns = {"values": ("f8", (RUN["n_keep"],)), "carry": ("f8", (z0.size,))}

    def store(name):
        return SweepStore.create_or_open(
            tmp_path / name,
            parameter_names=("slope",),
            points=SLOPES[:, None],
            columns=columns,
            chunk_size=2,
            provenance={"test": 1},
        )

    whole = orbit_diagram_blocks(
        stride_map, z0, SLOPES, chains=2, block=2, executor="serial", store=store("whole.h5"), **RUN
    )
    done = store("whole.h5").table().columns
    part = store("part.h5")
    for b in (0, 1, 4):  # chain 0 is blocks 0-3, chain 1 blocks 4-6
        sl = part.chunk_slice(b)
        part.write_chunk(b, {"values": done["values"][sl], "carry": done["carry"][sl]})
    recorder = Recording()
    resumed = orbit_diagram_blocks(
        stride_map, z0, SLOPES, chains=2, block=2, executor=recorder, store=part, **RUN
    )
    assert np.array_equal(resumed.values, whole.values, equal_nan=True)
    computed = sorted(float(v) for blk in recorder.blocks for v in blk)
    pending = [2, 3, 5, 6]
    expected = sorted(float(v) for b in pending for v in SLOPES[b * 2 : b * 2 + 2])
    assert computed == expected


def test_orbit_block_carry_is_the_next_start(simplest):
    stride_map, z0 = simplest
    a = orbit_block(stride_map, SLOPES[:4], z0, z0, **RUN)
    b = orbit_block(stride_map, SLOPES[2:4], a["carry"][1], z0, **RUN)
    assert np.array_equal(a["values"][2:], b["values"], equal_nan=True)


def test_cli_chains_jobs_and_checkpoint(tmp_path, capsys, monkeypatch):
    def argv(out, *extra):
        return [
            "orbit-diagram",
            str(SCENE),
            "--range",
            "0.015:0.019",
            "--n",
            "13",
            "--transient",
            "60",
            "--strides",
            "8",
            "--out",
            str(out),
            "--quiet",
            *extra,
        ]

    out = tmp_path / "orbit.h5"
    assert main(argv(out, "--chains", "3", "--jobs", "2")) == 0
    d, prov = read(out)
    assert prov["chains"] == 3
    assert not Path(checkpoint_path(out)).exists()  # removed once --out is written
    # an interrupted run leaves its checkpoint; the same command resumes it
    import walker.analysis.orbit_run as orbit_run

    real, calls = orbit_run.orbit_block, []

    def interrupted(*args):
        calls.append(1)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(*args)

    monkeypatch.setattr(orbit_run, "orbit_block", interrupted)
    out2 = tmp_path / "again.h5"
    assert main(argv(out2, "--chains", "3", "--jobs", "1")) == 130
    assert Path(checkpoint_path(out2)).exists() and not out2.exists()
    monkeypatch.setattr(orbit_run, "orbit_block", real)
    assert main(argv(out2, "--chains", "3")) == 0
    assert np.array_equal(read(out2)[0].values, d.values, equal_nan=True)
    assert not Path(checkpoint_path(out2)).exists()
    capsys.readouterr()
    assert main(argv(tmp_path / "x.h5", "--chains", "0")) == 2
    assert "--chains must be an integer >= 1" in capsys.readouterr().err
