"""Damaged and hostile files (issue 17, storage half), read in a child process: reads with
a time and memory budget (a file that crashes or hangs the reader is a storage error), and
a fuzz suite that damages every file kind walker writes.

Each test's docstring says what happened before these changes.  Files are crafted with
h5py in ``tests/_hostile_files.py``; the small sweep and basin checkpoints come from
``tests/_checkpoints.py``.
"""

from __future__ import annotations

import os
import signal
import threading
import time
from pathlib import Path

import h5py
import numpy as np
import pytest
from _checkpoints import basin_kw, chunk_values, half_done_sweep, sweep_points, sweep_store
from _hostile_files import basin_v1, flip, one_line, truncate, write_v1
from test_storage import PROVENANCE, RESULTS, assert_same

from walker import storage
from walker.storage import BasinStore, CheckpointMismatch, StorageError, read, write
from walker.storage.provenance import ENVIRONMENT_KEYS

REPO = Path(__file__).resolve().parents[1]
COMPASS = REPO / "gaits" / "compass_goswami.toml"
HANG_TIMEOUT = 20.0  # generous: a read that has not ended by then is a hang


# --------------------------------------------------------------------------------------------
# 1. Reading under a time and memory budget


@pytest.fixture(scope="module")
def issue_files(tmp_path_factory):
    """The two files of the issue, in the layout walker wrote then (schema 1): a ``find
    --out`` file and an 8x8 ``basin`` file of the compass scene."""
    from walker.cli import main

    tmp = tmp_path_factory.mktemp("issue")
    assert main(["find", str(COMPASS), "--out", str(tmp / "find.h5")]) == 0
    assert main(["basin", str(COMPASS), "--n", "8", "--out", str(tmp / "basin.h5")]) == 0
    # the provenance of then: without the keys added since (the environment, the state's
    # names), so that the files are the same bytes from any checkout and machine
    then = (*storage.AUTOMATIC_KEYS, *ENVIRONMENT_KEYS)
    fp, prov = read(tmp / "find.h5")
    prov = {k: v for k, v in prov.items() if k not in then}
    prov["scene"] = "gaits/compass_goswami.toml"
    find_v1 = write_v1(tmp / "find_v1.h5", fp, prov)
    basin, bprov = read(tmp / "basin.h5")
    bprov = {k: v for k, v in bprov.items() if k not in then}
    bprov["scene"] = "gaits/compass_goswami.toml"  # the same bytes from any checkout
    with h5py.File(tmp / "basin.h5") as f:
        k = f["checkpoint"].attrs
        tol, period, cs = float(k["tol"]), int(k["period"]), int(k["chunk_size"])
    basin_v1_path = basin_v1(
        tmp / "basin_v1.h5",
        basin,
        tol=tol,
        period=period,
        chunk_size=cs,
        provenance=bprov,
        done=range(8),
    )
    return {
        "find": find_v1,
        "basin": basin_v1_path,
        "find_v2": tmp / "find.h5",
        "basin_v2": tmp / "basin.h5",
    }


def test_segfaulting_flip_is_a_storage_error(tmp_path, issue_files):
    """Before: byte 857, bit 1 of a ``find --out`` file of the compass scene made
    ``storage.read`` (and ``walker plot``) die of SIGSEGV.  Now the read runs in a child
    process and its death is a StorageError naming the signal."""
    path = flip(issue_files["find"], tmp_path / "f.h5", 857, 1)
    with pytest.raises(StorageError, match=r"cannot read '.*f\.h5'") as info:
        read(path, timeout=HANG_TIMEOUT)
    one_line(info)


def test_hanging_flip_is_a_storage_error(tmp_path, issue_files):
    """Before: a one-bit flip of an 8x8 basin file (byte 3545 bit 2 in the issue's file;
    byte 3457 bit 1 of this one, whose provenance is the same bytes from any checkout) made
    ``storage.read`` never return.  Now the reading child is stopped at the timeout and the
    read ends in a StorageError that says so."""
    path = flip(issue_files["basin"], tmp_path / "b.h5", 3457, 1)
    with pytest.raises(StorageError, match=r"cannot read '.*b\.h5'") as info:
        read(path, timeout=3)
    assert "did not finish within 3 s" in str(info.value)
    one_line(info)


def test_child_crash_is_reported_by_signal(tmp_path, monkeypatch):
    path = write(tmp_path / "m.h5", RESULTS["map_result"](), provenance={})

    def crash(*args, **kwargs):
        os.kill(os.getpid(), signal.SIGSEGV)

    monkeypatch.setattr(storage.isolated, "_load_here", crash)  # the forked child inherits it
    # the forked child inherits the patch: fork even when an earlier test left a thread
    monkeypatch.setattr(storage.isolated, "_can_fork", lambda: True)
    with pytest.raises(StorageError, match=r"crashed reading it .*killed by SIGSEGV") as info:
        read(path)
    one_line(info)


def test_child_hang_is_reported_after_timeout(tmp_path, monkeypatch):
    path = write(tmp_path / "m.h5", RESULTS["map_result"](), provenance={})
    monkeypatch.setattr(storage.isolated, "_load_here", lambda *args, **kwargs: time.sleep(600))
    # the forked child inherits the patch: fork even when an earlier test left a thread
    monkeypatch.setattr(storage.isolated, "_can_fork", lambda: True)
    with pytest.raises(StorageError, match=r"did not finish within 1 s"):
        read(path, timeout=1)  # the child sleeps 600 s: the timeout stopped it


def test_child_memory_is_limited(tmp_path, monkeypatch):
    path = write(tmp_path / "m.h5", RESULTS["map_result"](), provenance={})

    def greedy(path, file_size, budget, **kwargs):
        return {"x": np.ones(budget + (3 << 30), dtype=np.uint8)}

    monkeypatch.setattr(storage.isolated, "_load_here", greedy)
    # the forked child inherits the patch: fork even when an earlier test left a thread
    monkeypatch.setattr(storage.isolated, "_can_fork", lambda: True)
    with pytest.raises(StorageError, match="more than the memory budget of 100000000 bytes"):
        read(path, memory=100_000_000)


def test_isolated_read_with_threads_uses_a_new_interpreter(tmp_path):
    """With other threads running, fork is unsafe: the child is a new interpreter."""
    path = write(tmp_path / "b.h5", RESULTS["branch"](), provenance=PROVENANCE)
    stop = threading.Event()
    thread = threading.Thread(target=stop.wait)
    thread.start()
    try:
        assert not storage._can_fork()
        back, prov = read(path)
    finally:
        stop.set()
        thread.join()
    assert_same(back, RESULTS["branch"]())
    assert prov["model"] == "simplest"


def test_walker_plot_of_a_crashing_file_exits_2(tmp_path, issue_files, capsys):
    """Before: ``walker plot`` died of SIGSEGV on the flipped find file."""
    from walker.cli import main

    path = flip(issue_files["find"], tmp_path / "f.h5", 857, 1)
    assert main(["plot", str(path), "--out", str(tmp_path / "figs")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("walker: error: cannot read") and "\n" not in err


# --------------------------------------------------------------------------------------------
# 2. Fuzz: deterministic damage of every file kind (the slow suite below: random)


@pytest.fixture(scope="module")
def file_kinds(tmp_path_factory):
    """One file of each kind walker writes: every result of ``write`` and a half-done sweep
    and basin checkpoint."""
    tmp = tmp_path_factory.mktemp("kinds")
    files = {
        name: write(tmp / f"{name}.h5", make(), provenance=PROVENANCE)
        for name, make in RESULTS.items()
    }
    half_done_sweep(tmp / "sweep_checkpoint.h5")
    files["sweep_checkpoint"] = tmp / "sweep_checkpoint.h5"
    store = BasinStore.create_or_open(tmp / "basin_checkpoint.h5", **basin_kw())
    store.write_chunk(1, np.full((2, 3), -1), np.full((2, 3), 7))
    files["basin_checkpoint"] = tmp / "basin_checkpoint.h5"
    return files


def _mutate(data: bytes, rng, how: str) -> bytes:
    data = bytearray(data)
    if how == "flip":
        data[int(rng.integers(len(data)))] ^= 1 << int(rng.integers(8))
    elif how == "byte":
        data[int(rng.integers(len(data)))] = int(rng.integers(256))
    else:
        data = data[: int(rng.integers(len(data)))]
    return bytes(data)


def _check_mutant(path, reference, timeout):
    """A mutated file either is refused with a one-line StorageError, or reads back exactly
    the reference."""
    try:
        got = read(path, timeout=timeout)
    except StorageError as exc:
        text = str(exc)
        assert "\n" not in text and text.startswith("cannot read"), text
        return "refused"
    assert_same(got[0], reference[0])
    assert_same(got[1], reference[1])
    return "same"


# storage fuzzing, every kind about 30 s: the integration tier (the slow tests)
@pytest.mark.parametrize(
    "how",
    [
        pytest.param("flip", marks=pytest.mark.slow),
        pytest.param("byte", marks=pytest.mark.slow),
        pytest.param("truncate", marks=pytest.mark.slow),
    ],
)
def test_deterministic_damage_of_every_kind(tmp_path, file_kinds, how):
    """A handful of fixed bit flips, byte overwrites and truncations of each file kind:
    each ends in a StorageError or reads back unchanged, within the time limit."""
    rng = np.random.default_rng({"flip": 1, "byte": 2, "truncate": 3}[how])
    outcomes = []
    for name, path in sorted(file_kinds.items()):
        reference = read(path)
        original = path.read_bytes()
        for k in range(4):
            mutant = tmp_path / f"{name}-{k}.h5"
            mutant.write_bytes(_mutate(original, rng, how))
            outcomes.append(_check_mutant(mutant, reference, timeout=HANG_TIMEOUT))
    assert "refused" in outcomes


@pytest.mark.parametrize("keep", [0.0, 0.1, 0.5, 0.99])
def test_truncated_checkpoints_are_refused_on_resume(tmp_path, keep):
    """(Passed before too: it guards the new resume path, which reads in a child.)"""
    path = tmp_path / "s.h5"
    half_done_sweep(path)
    truncate(path, path, keep)
    with pytest.raises(CheckpointMismatch, match=r"cannot resume '.*s\.h5'"):
        sweep_store(path)


# --------------------------------------------------------------------------------------------
# Slow: random damage


@pytest.mark.slow
def test_fuzz_read_many_mutated_files(tmp_path, file_kinds):
    """Before: of 1,206 mutated files 233 read back with changed numbers and no error, and
    some crashed or hung the reader.  Now 1,200 random bit flips, byte overwrites and
    truncations over every file kind each end in a StorageError or read back unchanged;
    none crashes or hangs the test process."""
    rng = np.random.default_rng(17)
    counts = {"refused": 0, "same": 0}
    kinds = sorted(file_kinds.items())
    for k in range(1200):
        name, path = kinds[k % len(kinds)]
        how = ("flip", "byte", "truncate")[(k // len(kinds)) % 3]
        mutant = tmp_path / "mutant.h5"
        mutant.write_bytes(_mutate(path.read_bytes(), rng, how))
        counts[_check_mutant(mutant, read(path), timeout=10)] += 1
    assert counts["refused"] > 300 and sum(counts.values()) == 1200


@pytest.mark.slow
def test_fuzz_resume_bit_flipped_half_done_sweeps(tmp_path):
    """Before: 12 of 150 bit-flipped half-done sweep files resumed to exit 0 with a wrong
    row.  Now, over 300 single bit flips of a half-done sweep, a resume either is refused
    (CheckpointMismatch, exit 2 in the CLI) or finishes with every row right."""
    clean = tmp_path / "clean.h5"
    half_done_sweep(clean)
    data = clean.read_bytes()
    expected = {name: v for name, v in chunk_values(sweep_points(), slice(0, 10)).items()}
    rng = np.random.default_rng(150)
    counts = {"refused": 0, "resumed": 0}
    for k in range(300):
        path = tmp_path / f"flip-{k}.h5"
        byte = int(rng.integers(len(data)))
        flip(clean, path, byte, int(rng.integers(8)))
        try:
            store = sweep_store(path)
            for i in store.pending_chunks():
                store.write_chunk(i, chunk_values(store.points, store.chunk_slice(i)))
            table = store.table()
        except StorageError:
            counts["refused"] += 1
            path.unlink()
            continue
        counts["resumed"] += 1
        for name, col in table.columns.items():
            np.testing.assert_array_equal(col, expected[name], err_msg=f"flip at {byte}")
        path.unlink()
    assert counts["resumed"] > 0 and counts["refused"] > 0
