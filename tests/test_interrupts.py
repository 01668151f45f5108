"""Interrupting ``walker sweep`` and ``walker basin`` (SIGTERM, SIGINT), resuming them, and
output paths checked before any work.

The interrupt tests run the command line in a subprocess (``python -m walker ...``), wait
until its checkpoint shows progress, send the signal, and check: exit status 130, one line on
stderr and no traceback, no child process left, a readable file, and a rerun whose file equals
an uninterrupted run's bit for bit.  Timeouts only guard against hangs.
"""

from __future__ import annotations

import os
import re
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

from walker.cli import main
from walker.results import BasinMap
from walker.storage import checkpoint_progress, read, write

REPO = Path(__file__).resolve().parents[1]
SCENE = str(REPO / "gaits/compass_goswami.toml")
HANG_GUARD = 300  # seconds; a cold build of the compiled core may come first

# 3000 compass fixed points in 300 chunks: a few seconds on two threads.
SWEEP_ARGS = [
    "sweep",
    SCENE,
    "--param",
    "slope=0.005:0.15:150",
    "--param",
    "mass_hip=5:20:20",
    "--chunk-size",
    "10",
    "--jobs",
    "2",
    "--quiet",
]
# A 160 x 160 basin grid of the compass gait in 32 chunks of 5 rows: a few seconds.
BASIN_ARGS = [
    "basin",
    SCENE,
    "--n",
    "160",
    "--strides",
    "40",
    "--axes",
    "1,2",
    "--jobs",
    "2",
    "--quiet",
]
LINE = re.compile(
    r"^walker: interrupted; (\d+) of (\d+) chunks kept in (.+), rerun the same command to "
    r"resume$"
)


# ------------------------------------------------------------------------------ helpers


def _children(pid: int) -> list[int]:
    """Pids of all descendants of ``pid`` (psutil if installed, else /proc)."""
    try:
        import psutil
    except ImportError:
        psutil = None
    if psutil is not None:
        try:
            return [p.pid for p in psutil.Process(pid).children(recursive=True)]
        except psutil.NoSuchProcess:
            return []
    parents = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    parents[int(entry)] = int(f.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
    found, frontier = [], [pid]
    while frontier:
        p = frontier.pop()
        kids = [c for c, pp in parents.items() if pp == p]
        found += kids
        frontier += kids
    return found


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            state = f.read().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return False
    return state not in ("Z", "X")  # a zombie has stopped running


def _assert_gone(pids: list[int], timeout: float = 60.0) -> None:
    deadline = time.monotonic() + timeout
    while True:
        alive = [p for p in pids if _alive(p)]
        if not alive:
            return
        assert time.monotonic() < deadline, f"child processes survived: {alive}"
        time.sleep(0.05)


def _progress_of_copy(path: Path, scratch: Path) -> tuple[int, int] | None:
    """(done, total) of a checkpoint another process is writing, read from a copy."""
    if not path.exists():
        return None
    try:
        shutil.copyfile(path, scratch)
    except OSError:
        return None
    return checkpoint_progress(scratch)


def _start(argv: list[str], out: Path) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "walker", *argv, "--out", str(out)],
        cwd=REPO,
        start_new_session=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )


def _wait_for_progress(proc: subprocess.Popen, out: Path, scratch: Path) -> None:
    """Until 2 or more chunks, and at most half of them, are stored."""
    deadline = time.monotonic() + HANG_GUARD
    while True:
        if proc.poll() is not None:
            pytest.fail(
                f"the command ended (status {proc.returncode}) before it was interrupted: "
                + proc.stderr.read()[-2000:]
            )
        assert time.monotonic() < deadline, "no progress in the checkpoint (hang guard)"
        got = _progress_of_copy(out, scratch)
        if got is not None and 2 <= got[0] <= got[1] // 2:
            return
        time.sleep(0.02)


def _interrupt(proc: subprocess.Popen, signum: int) -> tuple[int, str, list[int]]:
    """Send ``signum``; returns the status, stderr and the children it had."""
    children = _children(proc.pid)
    proc.send_signal(signum)
    try:
        _, err = proc.communicate(timeout=HANG_GUARD)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        pytest.fail("the command did not stop after the signal (hang guard)")
    return proc.returncode, err, children


def _run(argv: list[str], out: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "walker", *argv, "--out", str(out)],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=HANG_GUARD,
    )


def _hdf5_items(path: Path) -> dict[str, object]:
    """Every attribute and dataset of an HDF5 file, as comparable values (raw bytes for
    datasets), except the root attribute ``created`` (the time of writing)."""
    items: dict[str, object] = {}
    with h5py.File(path, "r") as f:

        def attrs(name, obj):
            for key, value in obj.attrs.items():
                if name == "/" and key in ("created", "checksum"):
                    continue
                v = np.asarray(value)
                items[f"{name}@{key}"] = (v.dtype.str, v.shape, v.tobytes())

        attrs("/", f)

        def visit(name, obj):
            attrs(name, obj)
            if isinstance(obj, h5py.Dataset):
                data = np.asarray(obj[()])
                items[name] = (obj.dtype.str, obj.shape, data.tobytes())

        f.visititems(visit)
    return items


def _assert_same_file(a: Path, b: Path) -> None:
    ia, ib = _hdf5_items(a), _hdf5_items(b)
    assert sorted(ia) == sorted(ib)
    differ = [k for k in ia if ia[k] != ib[k]]
    assert not differ, f"{a} and {b} differ in {differ}"


def _interrupt_resume_compare(tmp_path, argv, signum):
    out = tmp_path / "interrupted.h5"
    proc = _start(argv, out)
    try:
        _wait_for_progress(proc, out, tmp_path / "copy.h5")
        code, err, children = _interrupt(proc, signum)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert code == 130, err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    match = LINE.match(lines[0])
    assert match, lines[0]
    kept, total = int(match[1]), int(match[2])
    assert match[3] == str(out)
    _assert_gone(children)

    # readable, and the line tells the truth
    assert checkpoint_progress(out) == (kept, total)
    assert 2 <= kept < total
    read(out)

    again = _run(argv, out)
    assert again.returncode == 0, again.stderr
    fresh = _run(argv, tmp_path / "uninterrupted.h5")
    assert fresh.returncode == 0, fresh.stderr
    assert again.stdout == fresh.stdout.replace("uninterrupted.h5", "interrupted.h5")
    _assert_same_file(out, tmp_path / "uninterrupted.h5")
    (ra, pa), (rb, pb) = read(out), read(tmp_path / "uninterrupted.h5")
    pa.pop("created"), pb.pop("created")
    assert pa == pb
    return ra, rb


# ------------------------------------------------------------------- signals, end to end


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_sweep_interrupted_keeps_chunks_and_resumes_bit_for_bit(tmp_path, signum):
    resumed, fresh = _interrupt_resume_compare(tmp_path, SWEEP_ARGS, signum)
    assert (resumed.columns["status"] >= 0).all()
    for name, col in resumed.columns.items():
        assert col.tobytes() == fresh.columns[name].tobytes(), name


def test_basin_interrupted_keeps_chunks_and_resumes_bit_for_bit(tmp_path):
    resumed, fresh = _interrupt_resume_compare(tmp_path, BASIN_ARGS, signal.SIGTERM)
    assert isinstance(resumed, BasinMap) and resumed.outcome.shape == (160, 160)
    assert (resumed.outcome >= -2).all()  # every point computed
    assert resumed.outcome.tobytes() == fresh.outcome.tobytes()
    assert resumed.strides.tobytes() == fresh.strides.tobytes()


def test_process_pool_workers_are_terminated_on_interrupt(tmp_path):
    """The library with a process pool, under the CLI's handler: SIGTERM terminates the
    pool's workers, keeps the finished chunks, and the same call then completes the table."""
    out = tmp_path / "pool.h5"
    script = textwrap.dedent(
        f"""
        import concurrent.futures as cf, sys
        from walker import StrideMap, load_scene
        from walker.cli import interrupts_as_exceptions
        from walker.sweep import sweep

        scene = load_scene({SCENE!r})
        P = StrideMap("compass", scene.params, rtol=1e-10, atol=1e-12)
        pool = cf.ProcessPoolExecutor(max_workers=2)
        try:
            with interrupts_as_exceptions():
                sweep(P, ["slope=0.005:0.15:150", "mass_hip=5:20:20"], kind="fixed_point",
                      z0=P.project(scene.state), chunk_size=10, executor=pool,
                      out={str(out)!r}, progress=False)
        except KeyboardInterrupt:
            print("interrupted", file=sys.stderr)
            sys.exit(130)
        """
    )
    proc = subprocess.Popen(
        [sys.executable, "-c", script],
        cwd=REPO,
        start_new_session=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        _wait_for_progress(proc, out, tmp_path / "copy.h5")
        code, err, children = _interrupt(proc, signal.SIGTERM)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert code == 130 and err.strip() == "interrupted", err
    assert len(children) >= 2  # the pool's workers (and possibly a resource tracker)
    _assert_gone(children)
    kept, total = checkpoint_progress(out)
    assert 2 <= kept < total

    from walker import StrideMap, load_scene
    from walker.sweep import sweep

    scene = load_scene(SCENE)
    P = StrideMap("compass", scene.params, rtol=1e-10, atol=1e-12)
    kw = dict(kind="fixed_point", z0=P.project(scene.state), chunk_size=10, progress=False)
    ranges = ["slope=0.005:0.15:150", "mass_hip=5:20:20"]
    resumed = sweep(P, ranges, out=out, **kw)
    fresh = sweep(P, ranges, **kw)
    assert checkpoint_progress(out) == (total, total)
    for name, col in resumed.columns.items():
        assert col.tobytes() == fresh.columns[name].tobytes(), name


_DASK_CALLS: list[int] = []


def _slow_chunk(i):
    """A chunk for an in-process dask worker (module level: dask pickles it by reference)."""
    _DASK_CALLS.append(i)
    time.sleep(0.1)
    return i


def test_dask_futures_are_cancelled_on_interrupt():
    """An interrupt while chunks run on dask cancels the chunks not started."""
    distributed = pytest.importorskip("distributed")
    from walker._executors import run_chunks

    calls = _DASK_CALLS
    calls.clear()
    slow = _slow_chunk

    def on_result(key, value):
        raise KeyboardInterrupt  # as the CLI's handler would, while results come in

    with distributed.Client(
        processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None
    ) as client:
        with pytest.raises(KeyboardInterrupt):
            run_chunks(
                client.get_executor(), slow, ((i, (i,)) for i in range(30)), on_result, own=False
            )
        deadline = time.monotonic() + 60
        while client.run_on_scheduler(lambda dask_scheduler: len(dask_scheduler.tasks)):
            assert time.monotonic() < deadline, "the scheduler still holds the chunks"
            time.sleep(0.05)
        time.sleep(0.3)
    assert 1 <= len(calls) <= 5, calls  # the rest never started


# ------------------------------------------------------------ output paths, before any work


@pytest.fixture
def no_simulation(monkeypatch):
    """Every way into a simulation raises: the commands must stop before one."""

    def refuse(*args, **kwargs):
        raise AssertionError("a simulation started before the output path was checked")

    import walker.basin
    import walker.fixedpoint
    import walker.gallery
    import walker.stride
    import walker.sweep

    monkeypatch.setattr(walker.stride.StrideMap, "__call__", refuse)
    monkeypatch.setattr(walker.stride, "_solve", refuse)  # simulate's way into the integrator
    monkeypatch.setattr(walker.stride, "simulate", refuse)
    monkeypatch.setattr(walker.fixedpoint, "find_fixed_point", refuse)
    monkeypatch.setattr(walker.basin, "basin_chunk", refuse)
    monkeypatch.setattr(walker.sweep, "sweep_chunk", refuse)
    monkeypatch.setattr(walker.gallery, "plot_file", refuse)


def _usage_error(capsys, argv) -> str:
    code = main(argv)
    captured = capsys.readouterr()
    assert code == 2, captured
    lines = [ln for ln in captured.err.splitlines() if ln.strip()]
    assert len(lines) == 1, captured.err
    assert lines[0].startswith("walker: error: ")
    return lines[0]


def _probe_fails(directory: Path) -> bool:
    try:
        fd = os.open(directory / ".probe", os.O_CREAT | os.O_WRONLY | os.O_EXCL, 0o600)
    except OSError:
        return True
    os.close(fd)
    os.unlink(directory / ".probe")
    return False


@pytest.fixture
def unwritable_dir(tmp_path):
    """A directory nobody can create files in: mode 0o555, or (as root, whom modes do not
    stop) the immutable attribute."""
    d = tmp_path / "readonly"
    d.mkdir()
    d.chmod(0o555)
    immutable = False
    if not _probe_fails(d) and shutil.which("chattr"):
        immutable = subprocess.run(["chattr", "+i", str(d)], capture_output=True).returncode == 0
    try:
        if not _probe_fails(d):
            pytest.skip("cannot make a directory unwritable here")
        yield d
        assert sorted(os.listdir(d)) == []  # the checks left nothing behind
    finally:
        if immutable:
            subprocess.run(["chattr", "-i", str(d)], check=True)
        d.chmod(0o755)


COMMANDS = {
    "find": ["find", SCENE],
    "run": ["run", SCENE, "--strides", "2"],
    "continue": ["continue", SCENE, "--to", "0.06"],
    "basin": ["basin", SCENE, "--n", "4", "--strides", "3", "--quiet"],
    "sweep": ["sweep", SCENE, "--param", "slope=0.01:0.02:2", "--quiet"],
}
ALL = list(COMMANDS)


@pytest.mark.parametrize("cmd", ALL)
def test_existing_file_needs_overwrite(capsys, tmp_path, no_simulation, cmd):
    out = tmp_path / "exists.h5"
    out.write_bytes(b"not a result")
    line = _usage_error(capsys, [*COMMANDS[cmd], "--out", str(out)])
    assert f"--out {out} exists" in line and "pass --overwrite to replace it" in line
    assert out.read_bytes() == b"not a result"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["exists.h5"]


@pytest.mark.parametrize("cmd", ALL)
def test_missing_directory(capsys, tmp_path, no_simulation, cmd):
    out = tmp_path / "nowhere" / "x.h5"
    line = _usage_error(capsys, [*COMMANDS[cmd], "--out", str(out)])
    assert f"--out {out}" in line and "does not exist" in line
    assert not (tmp_path / "nowhere").exists()


@pytest.mark.parametrize("cmd", ALL)
def test_unwritable_directory(capsys, unwritable_dir, no_simulation, cmd):
    out = unwritable_dir / "x.h5"
    line = _usage_error(capsys, [*COMMANDS[cmd], "--out", str(out)])
    assert f"--out {out}" in line and "not writable" in line and "--out" in line


@pytest.mark.parametrize("cmd", ALL)
def test_out_is_a_directory(capsys, tmp_path, no_simulation, cmd):
    line = _usage_error(capsys, [*COMMANDS[cmd], "--out", str(tmp_path)])
    assert f"--out {tmp_path} is a directory" in line


def _basin_file(path: Path) -> Path:
    bm = BasinMap(
        ("a", "b"),
        np.linspace(0, 1, 3),
        np.linspace(0, 1, 2),
        np.full((2, 3), -1),
        np.zeros((2, 3), dtype=np.int64),
        np.zeros(2),
        np.zeros(2),
        5,
    )
    return write(path, bm, provenance={"model": "toy"})


@pytest.mark.parametrize("cmd", ["basin", "sweep"])
def test_other_result_is_not_resumed(capsys, tmp_path, no_simulation, cmd):
    """A finished result (no checkpoint) or another computation's checkpoint is refused
    before any work, with a message naming --overwrite."""
    out = _basin_file(tmp_path / "old.h5")
    before = out.read_bytes()
    line = _usage_error(capsys, [*COMMANDS[cmd], "--out", str(out)])
    assert f"--out {out} exists and " in line and "pass --overwrite to replace it" in line
    assert out.read_bytes() == before


def test_sweep_with_other_grid_is_refused_then_overwritten(capsys, tmp_path, monkeypatch):
    out = tmp_path / "s.h5"
    assert main([*COMMANDS["sweep"], "--out", str(out)]) == 0
    capsys.readouterr()
    other = ["sweep", SCENE, "--param", "slope=0.01:0.03:3", "--quiet", "--out", str(out)]
    import walker.sweep

    real_chunk = walker.sweep.sweep_chunk

    def refuse(*args, **kwargs):
        raise AssertionError("work started")

    monkeypatch.setattr(walker.sweep, "sweep_chunk", refuse)
    line = _usage_error(capsys, other)
    assert "checkpoints a different sweep" in line and "pass --overwrite" in line
    assert read(out)[0].points.shape == (2, 1)
    monkeypatch.setattr(walker.sweep, "sweep_chunk", real_chunk)
    assert main([*other, "--overwrite"]) == 0
    assert read(out)[0].points.shape == (3, 1)


def test_basin_with_other_settings_is_refused_before_the_fixed_point(capsys, tmp_path, monkeypatch):
    out = tmp_path / "b.h5"
    assert main([*COMMANDS["basin"], "--jobs", "1", "--out", str(out)]) == 0
    capsys.readouterr()
    first = read(out)[0]
    import walker.fixedpoint

    def refuse(*args, **kwargs):
        raise AssertionError("the fixed point was searched for")

    real = walker.fixedpoint.find_fixed_point
    monkeypatch.setattr(walker.fixedpoint, "find_fixed_point", refuse)
    other = ["basin", SCENE, "--n", "4", "--strides", "4", "--quiet", "--out", str(out)]
    line = _usage_error(capsys, other)
    assert "checkpoints a different basin map (n_strides 3 != 4)" in line
    assert "pass --overwrite" in line
    monkeypatch.setattr(walker.fixedpoint, "find_fixed_point", real)
    # the same command again resumes a finished map: nothing to do, same file content
    assert main([*COMMANDS["basin"], "--out", str(out)]) == 0
    again = read(out)[0]
    assert again.outcome.tobytes() == first.outcome.tobytes()
    assert main([*other, "--overwrite"]) == 0
    assert read(out)[0].n_strides == 4


def test_plot_output_directory_checked_before_plotting(capsys, tmp_path, unwritable_dir):
    import walker.gallery

    def refuse(*args, **kwargs):
        raise AssertionError("plotting started")

    src = _basin_file(tmp_path / "basin.h5")
    orig = walker.gallery.plot_file
    walker.gallery.plot_file = refuse
    try:
        line = _usage_error(capsys, ["plot", str(src), "--out", str(unwritable_dir)])
        assert "not writable" in line and "--out" in line
        line = _usage_error(capsys, ["plot", str(src), "--out", str(unwritable_dir / "figs")])
        assert "not writable" in line
        line = _usage_error(capsys, ["plot", str(src), "--out", str(tmp_path / "no" / "figs")])
        assert "does not exist" in line and "--out" in line
        line = _usage_error(capsys, ["plot", str(src), "--out", str(src)])
        assert "is not a directory" in line
    finally:
        walker.gallery.plot_file = orig
    assert not (tmp_path / "no").exists()


# ------------------------------------------------- the library: basin checkpoints, in-process

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
    from _toy_maps import CubicBasinMap

    from walker.fixedpoint import find_fixed_point

    m = CubicBasinMap(center=tuple(CENTER))
    fp = find_fixed_point(m, CENTER + 0.1)
    assert fp.success
    return m, fp


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
    from walker.basin import basin_map
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
    _assert_same_file(out, fresh)


def test_finished_basin_checkpoint_is_what_write_stores(tmp_path, toy):
    """The finished checkpoint holds the /result group write() makes, plus /checkpoint: old
    readers and `walker plot` see an ordinary basin file."""
    from walker.basin import basin_map

    m, fp = toy
    stored = basin_map(m, fp, out=tmp_path / "c.h5", executor="serial", **TOY_KW)
    write(tmp_path / "w.h5", stored, provenance={})
    ca, wa = _hdf5_items(tmp_path / "c.h5"), _hdf5_items(tmp_path / "w.h5")
    result_items = {k: v for k, v in ca.items() if not k.startswith("checkpoint")}
    assert result_items == wa
    assert main(["plot", str(tmp_path / "c.h5"), "--out", str(tmp_path / "figs")]) == 0
    assert (tmp_path / "figs" / "c_basin.png").exists()


def _toy_store(path, **changes):
    from walker.storage import BasinStore

    kw = dict(
        axis_names=("u", "w"),
        x=np.linspace(0, 1, 3),
        y=np.linspace(0, 1, 5),
        fixed_point=np.array([0.3, -0.2, 0.1]),
        base=np.array([0.3, -0.2, 0.1]),
        n_strides=10,
        tol=1e-6,
        period=1,
        provenance={"model": "toy"},
        chunk_size=2,
    )
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

    old = _basin_file(tmp_path / "old.h5")
    with pytest.raises(CheckpointMismatch, match="finished 'basin' result without a checkpoint"):
        _toy_store(old)
    garbage = tmp_path / "garbage.h5"
    garbage.write_bytes(b"x" * 100)
    with pytest.raises(CheckpointMismatch, match="not an HDF5 file"):
        _toy_store(garbage)
    from walker.storage import SweepStore

    sweep_file = tmp_path / "s.h5"
    SweepStore.create_or_open(
        sweep_file,
        parameter_names=("a",),
        points=np.zeros((2, 1)),
        columns={"status": ("i8", ())},
        chunk_size=1,
        provenance={},
    )
    with pytest.raises(CheckpointMismatch, match="holds a 'sweep' result"):
        _toy_store(sweep_file)
    with pytest.raises(CheckpointMismatch, match="holds a 'basin' result, not a sweep"):
        SweepStore.create_or_open(
            path,
            parameter_names=("a",),
            points=np.zeros((2, 1)),
            columns={"status": ("i8", ())},
            chunk_size=1,
            provenance={},
        )
