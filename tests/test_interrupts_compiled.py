"""Signals reach compiled work (issue 33, item 5).

``walker find gaits/compass_goswami.toml --period 100000`` spends minutes in one compiled
call (the gait search, walker/_core/newton.c) with the GIL released.  Before, SIGINT waited
for that call to end and SIGTERM killed the process with 143.  Now the binding's handler
(walker/_core/_hybridsignals.c) stops the call within a step, Python's handler runs, and
the command line ends with one line and exit 130 for both signals.

The child is signalled once it has spent a few seconds of CPU time (so it is inside the
search, past its imports).  The timeouts are hang guards only: without the handler the
search runs far past them (about a minute here at this period, several on a loaded machine).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SCENE = str(REPO / "gaits/compass_goswami.toml")
HANG_GUARD = 30  # seconds after the signal

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc"),
]


def _cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _interrupted(argv: list[str], signum: int) -> tuple[int, str]:
    """``walker *argv`` sent ``signum`` once it has used 4 s of CPU: its exit code and
    stderr (killed, and the test failed, when it is still running ``HANG_GUARD`` s later)."""
    child = subprocess.Popen(
        [sys.executable, "-m", "walker", *argv],
        cwd=REPO,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        deadline = time.monotonic() + 300
        while _cpu_seconds(child.pid) < 4.0:
            assert child.poll() is None, child.communicate()
            assert time.monotonic() < deadline, "the child never got going"
            time.sleep(0.1)
        child.send_signal(signum)
        out, err = child.communicate(timeout=HANG_GUARD)
    finally:
        if child.poll() is None:
            child.kill()
            child.communicate()
    return child.returncode, err


def _interrupted_find(signum: int, scene: str = SCENE) -> tuple[int, str]:
    return _interrupted(["find", scene, "--period", "100000"], signum)


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_signal_stops_the_compiled_search(signum):
    code, err = _interrupted_find(signum)
    assert code == 130, err
    assert err == "walker: interrupted\n"


def test_sigint_stops_the_search_through_callbacks():
    """The five-link walker's lift is in Python, so its search (the same one, newton.c)
    evaluates the map through Python callbacks: SIGINT there ends it as well."""
    code, err = _interrupted_find(signal.SIGINT, str(REPO / "gaits/five_link_hzd.toml"))
    assert code == 130, err
    assert err == "walker: interrupted\n"


def _interrupted_mfpt(signum: int, jobs: int) -> tuple[int, str]:
    """``walker mfpt`` on a gait that almost never falls at this roughness: its compiled
    Monte-Carlo batch (walker/_core/terrain.c, ``terrain_ensemble``) walks each block for
    far longer than the hang guard without the poll."""
    argv = ["mfpt", SCENE, "--std", "0.001", "--runs", "200000", "--seed", "1"]
    return _interrupted([*argv, "--jobs", str(jobs)], signum)


@pytest.mark.parametrize(
    ("signum", "jobs"), [(signal.SIGINT, 1), (signal.SIGTERM, 2)], ids=["SIGINT-1", "SIGTERM-2"]
)
def test_a_signal_stops_the_compiled_monte_carlo(signum, jobs):
    code, err = _interrupted_mfpt(signum, jobs)
    assert code == 130, err
    assert err == "walker: interrupted\n"
