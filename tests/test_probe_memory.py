"""Memory of a read (issue 33): a large legitimate file is read holding its data about once.

Before, the isolated reader's child loaded the whole file and the parent collected the pipe
into a list of pieces and then copied them into one buffer: a 80 MiB run file took the
parent to 2x its data (213 MiB resident) and the child to 1x more.  Now the child reads
each dataset in blocks of a few MiB as it sends it (walker.storage.blocks) and the parent
receives the bytes straight into one buffer sized from the header (walker.storage.isolated).

Peaks are measured in a fresh interpreter: its own from ``VmHWM`` (``ru_maxrss`` of a
process started by fork + exec keeps the forking process's peak), the reading child's from
``RUSAGE_CHILDREN``, which counts the pages it shares with the parent at the fork.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from walker.storage import blocks

REPO = Path(__file__).resolve().parents[1]
MIB = 1 << 20
CAP = 200 * MIB  # issue 33: a read stays within 200 MiB

_MEASURE = r"""
import json, resource, sys
def status(key):
    for line in open("/proc/self/status"):
        if line.startswith(key + ":"):
            return int(line.split()[1]) * 1024
import numpy as np
from walker.storage import read
before = status("VmRSS")
result, _ = read(sys.argv[1], isolate=sys.argv[2] == "1")
arrays = [result.record.t, result.record.x, result.record.phase, result.events.t,
          result.events.x_pre, result.events.x_post, result.events.impulse,
          result.events.guard, result.events.phase_before, result.events.phase_after]
print(json.dumps({
    "before": before,
    "peak": status("VmHWM"),
    "child": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024,
    "data": sum(int(a.nbytes) for a in arrays),
}))
"""


def _measure(path: Path, isolate: bool) -> dict:
    done = subprocess.run(
        [sys.executable, "-c", _MEASURE, str(path), "1" if isolate else "0"],
        cwd=REPO,
        capture_output=True,
        text=True,
        check=True,
        timeout=600,
    )
    return json.loads(done.stdout.splitlines()[-1])


@pytest.fixture(scope="module")
def large_run(tmp_path_factory) -> Path:
    """``walker run gaits/kneed_hsu.toml --strides 30000 --out``: an 84 MB file, 80 MiB of
    arrays (every accepted step stored), so that 3x its data would pass the cap."""
    path = tmp_path_factory.mktemp("memory") / "kneed_30k.h5"
    argv = ["run", "gaits/kneed_hsu.toml", "--strides", "30000", "--out", str(path)]
    subprocess.run([sys.executable, "-m", "walker", *argv], cwd=REPO, check=True, timeout=600)
    return path


@pytest.mark.slow
def test_a_large_run_file_is_read_holding_its_data_once(large_run):
    m = _measure(large_run, isolate=True)
    assert 3 * m["data"] > CAP  # the file is large enough to tell 1x from 3x
    assert m["peak"] <= CAP, m
    # the parent: the data once, plus the JSON header and small blocks
    assert m["peak"] - m["before"] <= m["data"] + 24 * MIB, m
    # the child: what it shares with the parent at the fork plus HDF5's caches (its
    # metadata cache is at most 32 MiB) and a block or two, never the data (before: 1x)
    assert m["child"] - m["before"] <= 0.75 * m["data"], m


@pytest.mark.slow
def test_a_large_run_file_read_in_this_process_holds_its_data_once(large_run):
    m = _measure(large_run, isolate=False)
    assert m["peak"] <= CAP, m
    assert m["peak"] - m["before"] <= m["data"] + 48 * MIB, m


@pytest.mark.parametrize(
    "shape",
    [(), (0,), (5,), (1000,), (7, 3), (64, 5, 3), (3, 40, 2), (2, 0, 4)],
    ids=str,
)
def test_blocks_cut_an_array_in_c_order(monkeypatch, shape):
    """The blocks a streaming load sends, concatenated, are the array's bytes in C order
    (numpy's ``tobytes``), each within the block size, rows larger than a block cut too."""
    monkeypatch.setattr(blocks, "_STREAM_BLOCK", 64)  # bytes: 8 float64
    arr = np.arange(int(np.prod(shape)), dtype=np.float64).reshape(shape)
    pieces = [arr[sel] for sel in blocks._selections(arr.shape, arr.itemsize)]
    assert b"".join(np.ascontiguousarray(p).tobytes() for p in pieces) == arr.tobytes()
    assert all(p.nbytes <= 64 for p in pieces)
