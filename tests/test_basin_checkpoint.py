"""Basin checkpoints in the library, in one process: ``basin_map`` interrupted
(``KeyboardInterrupt``, serially or in threads) keeps its done chunks and resumes to the
uninterrupted map bit for bit; a finished checkpoint holds what ``write`` stores; a
``BasinStore`` refuses a different map and files that are not its checkpoint.  The end-to-end
interrupts of the command line are in ``tests/test_interrupts.py``.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest
from _checkpoints import assert_same_file, basin_kw, hdf5_items, small_basin_file
from _toy_maps import cubic_basin_toy

from walker.cli import main
from walker.storage import checkpoint_progress, read, write

CENTER = np.array([0.3, -0.2, 0.1])
TOY_KW = dict(
    axes=(0, 2),
    ranges=((CENTER[0] - 1.45, CENTER[0] + 1.45), (CENTER[2] - 1.45, CENTER[2] + 1.45)),
    n=(12, 20),
    n_strides=20,
    tol=1e-6,
    progress=False,
)


@pytest.fixture(scope="module")
def toy():
    return cubic_basin_toy(CENTER)


class _InterruptOnCall:
    """A section map that raises KeyboardInterrupt on its ``n``-th call (in whatever thread
    makes it), as Ctrl-C would in the middle of the work."""

    def __init__(self, inner, n):
        import threading

        self._inner, self._n, self._calls, self._lock = inner, n, 0, threading.Lock()

    def __getattr__(self, name):
        return getattr(self._inner, name)

    def __call__(self, z, **kwargs):
        with self._lock:
            self._calls += 1
            hit = self._calls == self._n
        if hit:
            raise KeyboardInterrupt
        return self._inner(z, **kwargs)


@pytest.mark.parametrize("where", ["serial", "threads"])
def test_basin_map_interrupted_then_resumed(tmp_path, toy, where):
    from walker.analysis.basin import basin_map
    from walker.storage import BASIN_NOT_COMPUTED

    m, fp = toy
    out = tmp_path / "basin.h5"
    run = dict(TOY_KW, executor="serial") if where == "serial" else dict(TOY_KW, jobs=2)
    with pytest.raises(KeyboardInterrupt):
        basin_map(_InterruptOnCall(m, 150), fp, out=out, chunk_size=2, provenance={"m": 1}, **run)
    done, total = checkpoint_progress(out)
    assert 0 < done < total == 10
    partial, prov = read(out)  # readable, pending rows marked
    with h5py.File(out, "r") as f:
        flags = f["checkpoint/done"][()]
    full = basin_map(m, fp, executor="serial", **TOY_KW)
    for i, ok in enumerate(flags):
        rows = slice(2 * i, 2 * i + 2)
        if ok:
            assert partial.outcome[rows].tobytes() == full.outcome[rows].tobytes()
        else:
            assert (partial.outcome[rows] == BASIN_NOT_COMPUTED).all()

    resumed = basin_map(m, fp, out=out, provenance={"m": 1}, **run)  # the stored chunk size
    assert checkpoint_progress(out) == (10, 10)
    assert resumed.outcome.tobytes() == full.outcome.tobytes()
    assert resumed.strides.tobytes() == full.strides.tobytes()
    assert resumed.x.tobytes() == full.x.tobytes() and resumed.y.tobytes() == full.y.tobytes()
    fresh = tmp_path / "fresh.h5"
    basin_map(m, fp, out=fresh, chunk_size=2, provenance={"m": 1}, **run)
    assert_same_file(out, fresh)


def test_finished_basin_checkpoint_is_what_write_stores(tmp_path, toy):
    """The finished checkpoint holds the /result group write() makes, plus /checkpoint: old
    readers and `walker plot` see an ordinary basin file."""
    from walker.analysis.basin import basin_map

    m, fp = toy
    stored = basin_map(m, fp, out=tmp_path / "c.h5", executor="serial", **TOY_KW)
    write(tmp_path / "w.h5", stored, provenance={})
    ca, wa = hdf5_items(tmp_path / "c.h5"), hdf5_items(tmp_path / "w.h5")
    result_items = {k: v for k, v in ca.items() if not k.startswith("checkpoint")}
    assert result_items == wa
    assert main(["plot", str(tmp_path / "c.h5"), "--out", str(tmp_path / "figs")]) == 0
    assert (tmp_path / "figs" / "c_basin.png").exists()


def _toy_store(path, **changes):
    from walker.storage import BasinStore

    kw = dict(basin_kw(), axis_names=("u", "w"), fixed_point=CENTER.copy(), base=CENTER.copy())
    kw.update(changes)
    return BasinStore.create_or_open(path, **kw)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"x": np.linspace(0, 1.5, 3)}, "x differs"),
        ({"y": np.linspace(0, 1, 6)}, "y differs"),
        ({"axis_names": ("u", "v")}, "axis_names"),
        ({"fixed_point": np.array([0.3, -0.2, 0.2])}, "fixed_point differs"),
        ({"n_strides": 11}, "n_strides 10 != 11"),
        ({"tol": 1e-7}, "tol 1e-06 != 1e-07"),
        ({"period": 2}, "period 1 != 2"),
        ({"chunk_size": 3}, "chunk_size 2 != 3"),
        ({"provenance": {"model": "other"}}, r"provenance differs in \['model'\]"),
    ],
)
def test_basin_store_refuses_a_different_map(tmp_path, change, message):
    from walker.storage import CheckpointMismatch, StorageError

    path = tmp_path / "b.h5"
    _toy_store(path)
    with pytest.raises(CheckpointMismatch, match=f"different basin map .*{message}") as info:
        _toy_store(path, **change)
    assert isinstance(info.value, StorageError) and info.value.path == path
    assert _toy_store(path, **change, overwrite=True).pending_chunks() != []


def test_basin_store_reopens_and_refuses_other_files(tmp_path):
    from walker.storage import BasinStore, CheckpointMismatch

    path = tmp_path / "b.h5"
    store = _toy_store(path)
    assert store.n_chunks == 3 and store.chunk_slice(2) == slice(4, 5)
    store.write_chunk(1, np.full((2, 3), 4), np.full((2, 3), 7))
    again = _toy_store(path, chunk_size=None)  # the stored chunk size
    assert again.chunk_size == 2 and again.pending_chunks() == [0, 2]
    with pytest.raises(ValueError, match=r"must have shape \(2, 3\) for chunk 0"):
        again.write_chunk(0, np.zeros((1, 3), int), np.zeros((1, 3), int))
    BasinStore.check_existing(path, shape=(5, 3), n_strides=10, provenance={"model": "toy"})
    with pytest.raises(CheckpointMismatch, match=r"grid shape \(5, 3\) != \(4, 4\)"):
        BasinStore.check_existing(path, shape=(4, 4))
    BasinStore.check_existing(tmp_path / "none.h5", shape=(4, 4))  # nothing to resume

    old = small_basin_file(tmp_path / "old.h5")
    with pytest.raises(CheckpointMismatch, match="finished 'basin' result without a checkpoint"):
        _toy_store(old)
    garbage = tmp_path / "garbage.h5"
    garbage.write_bytes(b"x" * 100)
    with pytest.raises(CheckpointMismatch, match="not an HDF5 file"):
        _toy_store(garbage)
    from walker.storage import SweepStore

    sweep_file = tmp_path / "s.h5"
    one_column = dict(
        parameter_names=("a",),
        points=np.zeros((2, 1)),
        columns={"status": ("i8", ())},
        chunk_size=1,
        provenance={},
    )
    SweepStore.create_or_open(sweep_file, **one_column)
    with pytest.raises(CheckpointMismatch, match="holds a 'sweep' result"):
        _toy_store(sweep_file)
    with pytest.raises(CheckpointMismatch, match="holds a 'basin' result, not a sweep"):
        SweepStore.create_or_open(path, **one_column)
