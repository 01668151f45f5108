"""Writing walker files under hostile conditions (issue 17, storage half): readers beside a
running writer, writes that survive a full or read-only disk or a file size limit, stale
temporary files removed.

Each test's docstring says what happened before these changes.  Files are crafted with
h5py in ``tests/_hostile_files.py``; the small sweep and basin checkpoints come from
``tests/_checkpoints.py``.
"""

from __future__ import annotations

import errno
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import h5py
import numpy as np
import pytest
from _checkpoints import chunk_values, half_done_sweep, sweep_store
from _hostile_files import one_line
from test_storage import RESULTS

from walker import storage
from walker.storage import StorageError, SweepStore, read, write

REPO = Path(__file__).resolve().parents[1]
COMPASS = REPO / "gaits" / "compass_goswami.toml"


# --------------------------------------------------------------------------------------------
# 1. Readers beside the running writer

_WRITER = textwrap.dedent(
    """
    import sys, time
    import numpy as np
    from walker.storage import SweepStore
    n, chunk = 60, 3
    points = np.linspace(0.0, 1.0, n)[:, None]
    store = SweepStore.create_or_open(
        {path!r}, parameter_names=("p",), points=points,
        columns={{"a": ("f8", (50,)), "b": ("i8", ())}}, chunk_size=chunk,
        provenance={{"model": "test"}})
    print("created", flush=True)
    for i in store.pending_chunks():
        sl = store.chunk_slice(i)
        store.write_chunk(i, {{"a": np.repeat(points[sl], 50, axis=1) + 1.0,
                               "b": np.arange(sl.start, sl.stop)}})
        if i < 3:  # the first chunks wait for a reader's turn: reads mid-run on any machine
            print("wrote", flush=True)
            sys.stdin.readline()
        time.sleep(0.02)
    print("finished", flush=True)
    """
)


@pytest.mark.parametrize("isolate", [True, False])
def test_readers_and_a_running_writer_coexist(tmp_path, isolate):
    """Before: ``walker plot`` of a sweep's file while the sweep ran killed the sweep
    (``cannot write chunk ... unable to lock file``) and the plot said "truncated/
    corrupted".  Now chunks are written with os.pwrite (no HDF5, no lock), and a reader
    sees a consistent snapshot: the chunks marked done, complete, the others pending."""
    path = tmp_path / "s.h5"
    proc = subprocess.Popen(
        [sys.executable, "-c", _WRITER.format(path=str(path))],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )

    def check_snapshot() -> None:
        table, _ = read(path) if isolate else read(path, isolate=False)
        b = table.columns["b"]
        done = b >= 0
        np.testing.assert_array_equal(b[done], np.arange(60)[done])
        expected = np.repeat(table.points, 50, axis=1) + 1.0
        np.testing.assert_array_equal(table.columns["a"][done], expected[done])
        assert np.isnan(table.columns["a"][~done]).all()

    try:
        assert proc.stdout.readline().strip() == "created"
        # A reader holding the file open with HDF5's own lock does not stop the writer.
        with h5py.File(path, "r") as held:
            n_reads = 0
            for _ in range(3):  # the writer waits after each of its first three chunks
                assert proc.stdout.readline().strip() == "wrote"
                check_snapshot()
                n_reads += 1
                proc.stdin.write("go\n")
                proc.stdin.flush()
            while proc.poll() is None:  # then reads run beside writes
                check_snapshot()
                n_reads += 1
            assert held["checkpoint/done"].shape == (20,)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 0, err
    assert out.strip() == "finished"
    assert n_reads >= 3
    assert storage.checkpoint_progress(path) == (20, 20)


def test_failed_chunk_write_is_retried(tmp_path, monkeypatch):
    """Before: one failed chunk write ended the sweep.  Now a transient error (EIO, EAGAIN,
    ...) is retried with backoff; a persistent one is a StorageError, the chunk stays
    pending and the chunks done before stay intact."""
    store = half_done_sweep(tmp_path / "s.h5")
    real = storage.checkpoint._write_all
    failures = [errno.EIO, errno.EAGAIN]
    sleeps = []

    def flaky(fd, data, offset=None):
        if failures:
            raise OSError(failures.pop(0), "simulated")
        return real(fd, data, offset)

    monkeypatch.setattr(storage.checkpoint, "_write_all", flaky)
    monkeypatch.setattr(storage.checkpoint.time, "sleep", sleeps.append)
    store.write_chunk(1, chunk_values(store.points, store.chunk_slice(1)))
    assert sleeps == [0.05, 0.2]
    assert store.pending_chunks() == [3]

    def broken(fd, data, offset=None):
        raise OSError(errno.EIO, "simulated")

    monkeypatch.setattr(storage.checkpoint, "_write_all", broken)
    with pytest.raises(StorageError, match=r"cannot write chunk 3 to '.*s\.h5'.*\(EIO\)") as info:
        store.write_chunk(3, chunk_values(store.points, store.chunk_slice(3)))
    one_line(info)
    monkeypatch.setattr(storage.checkpoint, "_write_all", real)
    assert store.pending_chunks() == [3]
    table, _ = read(tmp_path / "s.h5")
    np.testing.assert_array_equal(table.columns["status"][:9], np.arange(9))


def test_replaced_file_is_not_written(tmp_path):
    store = half_done_sweep(tmp_path / "s.h5")
    write(tmp_path / "s.h5", RESULTS["basin"](), provenance={}, overwrite=True)
    with pytest.raises(StorageError, match="the file was replaced"):
        store.write_chunk(1, chunk_values(store.points, store.chunk_slice(1)))


# --------------------------------------------------------------------------------------------
# 2. Writing survives the disk

_FULL_DISK = textwrap.dedent(
    """
    import resource, signal, sys
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, ({limit}, {limit}))
    from walker.cli import main
    sys.exit(main(sys.argv[1:]))
    """
)


@pytest.mark.parametrize("limit", [2000, 40_000])
def test_sweep_on_a_full_disk_exits_2(tmp_path, limit):
    """Before: ``walker sweep ... --out SMALL/sw.h5`` on a full 1 MiB tmpfs died of
    SIGSEGV (exit 139) in h5py's flush under ``_atomic_create`` and left ``.sw.h5.tmp-*``.
    A full disk is simulated with RLIMIT_FSIZE (SIGXFSZ ignored: writes beyond the limit
    fail with EFBIG, as they fail with ENOSPC on a full disk); the same segfault was seen
    so before this change.  Now: exit 2, one line, no file, no temporary file."""
    out = tmp_path / "sw.h5"
    proc = subprocess.run(
        [
            sys.executable,
            "-c",
            _FULL_DISK.format(limit=limit),
            "sweep",
            str(COMPASS),
            "--param",
            "slope=0.04:0.06:500",
            "--jobs",
            "1",
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert lines == [
        f"walker: error: cannot write '{out}': file too large for the file "
        "system or the process limit (EFBIG)"
    ]
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("code", [errno.ENOSPC, errno.EDQUOT, errno.EROFS])
def test_disk_errors_while_writing_are_storage_errors(tmp_path, monkeypatch, code):
    """ENOSPC, EDQUOT and EROFS while a file is written: a one-line StorageError, no file,
    no temporary file; an existing target is kept."""
    old = write(tmp_path / "b.h5", RESULTS["basin"](), provenance={"model": "old"})

    def failing(fd, data, offset=None):
        raise OSError(code, os.strerror(code))

    monkeypatch.setattr(storage.disk, "_write_all", failing)
    name = errno.errorcode[code]
    for target in (tmp_path / "new.h5", old):
        with pytest.raises(StorageError, match=rf"cannot write '.*'.*\({name}\)$") as info:
            write(target, RESULTS["basin"](), provenance={"model": "new"}, overwrite=True)
        one_line(info)
    with pytest.raises(StorageError, match=name):
        sweep_store(tmp_path / "s.h5")
    monkeypatch.undo()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.h5"]
    assert read(old)[1]["model"] == "old"


def test_chunk_write_on_a_full_disk_keeps_the_checkpoint(tmp_path, monkeypatch):
    store = half_done_sweep(tmp_path / "s.h5")

    def full(fd, data, offset=None):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(storage.checkpoint, "_write_all", full)
    with pytest.raises(StorageError, match=r"cannot write chunk 1 to '.*s\.h5'.*\(ENOSPC\)"):
        store.write_chunk(1, chunk_values(store.points, store.chunk_slice(1)))
    monkeypatch.undo()
    assert store.pending_chunks() == [1, 3]
    table, _ = read(tmp_path / "s.h5")
    np.testing.assert_array_equal(table.columns["status"][6:9], [6, 7, 8])


def test_free_space_is_checked_before_creating(tmp_path, monkeypatch):
    real = shutil.disk_usage
    monkeypatch.setattr(storage.disk.shutil, "disk_usage", lambda p: real(p)._replace(free=10_000))
    with pytest.raises(StorageError, match=r"needs about \d+ bytes, only 10000 are free"):
        write(tmp_path / "s.h5", RESULTS["solution"](), provenance={})
    with pytest.raises(StorageError, match="only 10000 are free"):
        storage.check_writable(tmp_path / "x.h5", 1_000_000)
    assert list(tmp_path.iterdir()) == []


def test_read_only_file_system_is_reported(tmp_path, monkeypatch):
    real = os.statvfs

    class ReadOnly:
        def __init__(self, st):
            self.st = st

        def __getattr__(self, name):
            return os.ST_RDONLY if name == "f_flag" else getattr(self.st, name)

    monkeypatch.setattr(storage.disk.os, "statvfs", lambda p: ReadOnly(real(p)))
    with pytest.raises(StorageError, match=r"cannot write '.*': read-only file system"):
        write(tmp_path / "s.h5", RESULTS["basin"](), provenance={})
    with pytest.raises(StorageError, match="read-only"):
        storage.check_writable(tmp_path / "x.h5")


def test_write_under_a_file_size_limit(tmp_path):
    """write() itself (as ``find``/``run``/``basin`` use it) under RLIMIT_FSIZE."""
    code = textwrap.dedent(
        f"""
        import resource, signal, sys
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (3000, 3000))
        sys.path.insert(0, {str(REPO / "tests")!r})
        from test_storage import RESULTS
        from walker.storage import StorageError, write
        try:
            write({str(tmp_path / "s.h5")!r}, RESULTS["solution"](), provenance={{}})
        except StorageError as exc:
            print(exc)
        """
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "(EFBIG)" in proc.stdout
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------------------------
# 3. Stale temporary files


def test_stale_temporary_files_are_removed(tmp_path):
    """Before: temporary files of a killed or crashed create were never removed (one was
    192 MB).  Now a create removes those of the same target whose writer is gone."""
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    alive = os.getppid()
    stale = tmp_path / f".b.h5.tmp-{dead.pid}-0123abcd"
    live = tmp_path / f".b.h5.tmp-{alive}-0123abcd"
    other = tmp_path / f".c.h5.tmp-{dead.pid}-0123abcd"
    fresh = tmp_path / f".b.h5.tmp-{dead.pid}-fedc4321"
    for p in (stale, live, other, fresh):
        p.write_bytes(b"x" * 1000)
    old = time.time() - 3600
    for p in (stale, live, other):
        os.utime(p, (old, old))
    write(tmp_path / "b.h5", RESULTS["basin"](), provenance={})
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == sorted(["b.h5", live.name, other.name, fresh.name])


def test_killed_create_leaves_a_temp_that_the_next_create_removes(tmp_path):
    path = tmp_path / "s.h5"
    code = textwrap.dedent(
        f"""
        import os, signal
        from walker.storage import disk
        real = disk._write_all
        def killed(fd, data, offset=None):
            real(fd, memoryview(data)[:100])
            os.kill(os.getpid(), signal.SIGKILL)
        disk._write_all = killed
        from walker.storage import SweepStore
        import numpy as np
        SweepStore.create_or_open({str(path)!r}, parameter_names=("p",),
            points=np.zeros((4, 1)), columns={{"a": ("f8", ())}}, chunk_size=2,
            provenance={{}})
        """
    )
    proc = subprocess.run([sys.executable, "-c", code], timeout=120)
    assert proc.returncode == -signal.SIGKILL
    (temp,) = tmp_path.iterdir()
    assert temp.name.startswith(".s.h5.tmp-")
    os.utime(temp, (time.time() - 60, time.time() - 60))
    store = SweepStore.create_or_open(
        path,
        parameter_names=("p",),
        points=np.zeros((4, 1)),
        columns={"a": ("f8", ())},
        chunk_size=2,
        provenance={},
    )
    assert store.pending_chunks() == [0, 1]
    assert [p.name for p in tmp_path.iterdir()] == ["s.h5"]
