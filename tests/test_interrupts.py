"""Interrupting ``walker sweep`` and ``walker basin`` (SIGTERM, SIGINT) and resuming them.

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

import pytest
from _checkpoints import assert_same_file, start_python

from walker.results import BasinMap
from walker.storage import checkpoint_progress, read

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
    return start_python(["-m", "walker", *argv, "--out", str(out)], text=True)


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
    assert_same_file(out, tmp_path / "uninterrupted.h5")
    (ra, pa), (rb, pb) = read(out), read(tmp_path / "uninterrupted.h5")
    for key in ("created", "command_line"):  # the time, and the command naming its --out
        pa.pop(key), pb.pop(key)
    assert pa == pb
    return ra, rb


# ------------------------------------------------------------------- signals, end to end


# SIGINT in the default suite; SIGTERM (the same path, about 20 s) with the slow tests
@pytest.mark.parametrize(
    "signum",
    [
        pytest.param(signal.SIGTERM, marks=pytest.mark.slow),
        pytest.param(signal.SIGINT, marks=pytest.mark.slow),
    ],
    ids=["SIGTERM", "SIGINT"],
)
def test_sweep_interrupted_keeps_chunks_and_resumes_bit_for_bit(tmp_path, signum):
    resumed, fresh = _interrupt_resume_compare(tmp_path, SWEEP_ARGS, signum)
    assert (resumed.columns["status"] >= 0).all()
    for name, col in resumed.columns.items():
        assert col.tobytes() == fresh.columns[name].tobytes(), name


@pytest.mark.slow  # kill and resume: the integration tier
def test_basin_interrupted_keeps_chunks_and_resumes_bit_for_bit(tmp_path):
    resumed, fresh = _interrupt_resume_compare(tmp_path, BASIN_ARGS, signal.SIGTERM)
    assert isinstance(resumed, BasinMap) and resumed.outcome.shape == (160, 160)
    assert (resumed.outcome >= -2).all()  # every point computed
    assert resumed.outcome.tobytes() == fresh.outcome.tobytes()
    assert resumed.strides.tobytes() == fresh.strides.tobytes()


@pytest.mark.slow  # kill and resume: the integration tier
def test_process_pool_workers_are_terminated_on_interrupt(tmp_path):
    """The library with a process pool, under the CLI's handler: SIGTERM terminates the
    pool's workers, keeps the finished chunks, and the same call then completes the table."""
    out = tmp_path / "pool.h5"
    script = textwrap.dedent(
        f"""
        import concurrent.futures as cf, sys
        from walker import StrideMap, load_scene
        from walker.cli import interrupts_as_exceptions
        from walker.analysis.sweep import sweep

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
    proc = start_python(["-c", script], text=True)
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
    from walker.analysis.sweep import sweep

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
