"""Probe reproductions of issue 33 about what walker writes and how its command line ends
(items 3 and 6, and the exit-code findings): figures written one way, a full disk, optional
extras missing, closed standard output, scene paths that are not files, interrupts, the
parse bound of scenes.

Each test names what happened before these changes.  No test asserts on wall-clock time.
"""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from test_storage import RESULTS

from walker.cli import main
from walker.storage import StorageError, write, write_file
from walker.storage import disk as disk_module

REPO = Path(__file__).resolve().parents[1]
COMPASS = REPO / "gaits" / "compass_goswami.toml"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def _cli(*argv, timeout=120, **kw) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "walker", *map(str, argv)],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=timeout,
        **kw,
    )


# --------------------------------------------------------------------------------------------
# Item 6: files and figures written one way


@pytest.fixture
def fixed_point_file(tmp_path):
    return write(tmp_path / "fp.h5", RESULTS["fixed_point"](), provenance={})


def test_planted_symlink_at_a_figure_is_replaced_not_followed(tmp_path, fixed_point_file, capsys):
    """Before: ``walker plot --out DIR`` wrote with ``savefig(path)``, so a symbolic link
    planted in DIR at a figure's name made walker overwrite the link's target with a PNG.
    Now the figure is renamed onto the name: the link is replaced, its target untouched (a
    dangling link's target is not created)."""
    out = tmp_path / "figs"
    out.mkdir()
    victim = tmp_path / "victim.txt"
    victim.write_bytes(b"precious\n")
    (out / "fp_multipliers.png").symlink_to(victim)
    assert main(["plot", str(fixed_point_file), "--out", str(out)]) == 0
    assert victim.read_bytes() == b"precious\n"
    figure = out / "fp_multipliers.png"
    assert not figure.is_symlink()
    assert figure.read_bytes()[:8] == PNG_MAGIC
    # a dangling link: its target must not appear
    figure.unlink()
    nowhere = tmp_path / "created-by-walker.png"
    figure.symlink_to(nowhere)
    assert main(["plot", str(fixed_point_file), "--out", str(out)]) == 0
    assert not nowhere.exists() and not figure.is_symlink()
    assert sorted(p.name for p in out.iterdir()) == ["fp_multipliers.png"]  # no temp left


def test_full_disk_during_plot_is_exit_2_without_partial_file(
    tmp_path, fixed_point_file, monkeypatch, capsys
):
    """Before: on a full disk the OSError of savefig carried no filename, so it was exit 3
    and left a truncated PNG.  Now it is exit 2, one line naming the figure, and no file."""
    out = tmp_path / "figs"
    written = []

    def full_disk(fd, data, offset=None):
        os.write(fd, bytes(memoryview(data)[:100]))  # part of it reaches the disk first
        written.append(fd)
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(disk_module, "_write_all", full_disk)
    assert main(["plot", str(fixed_point_file), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert written
    assert err.count("\n") == 1
    assert f"cannot write '{out / 'fp_multipliers.png'}'" in err
    assert "no space left on the device (ENOSPC)" in err
    assert not out.exists() or list(out.iterdir()) == []


def test_write_file_names_the_file_on_any_failure(tmp_path):
    with pytest.raises(StorageError, match=r"cannot write '.*missing/a.png': No such file"):
        write_file(tmp_path / "missing" / "a.png", b"x")
    target = tmp_path / "exists.png"
    target.write_bytes(b"old")
    with pytest.raises(FileExistsError):
        write_file(target, b"new", overwrite=False)
    assert target.read_bytes() == b"old"
    assert write_file(target, b"new").read_bytes() == b"new"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["exists.png"]


def test_animation_goes_through_the_same_writer(tmp_path):
    """The stick-figure GIF is rendered aside and renamed onto its name as well."""
    import numpy as np

    from walker.plot_runs import animate_walker

    frames = np.zeros((3, 2, 2))
    frames[:, 1, 1] = 1.0
    victim = tmp_path / "victim.gif"
    victim.write_bytes(b"precious")
    path = tmp_path / "walk.gif"
    path.symlink_to(victim)
    animate_walker(frames, [(0, 1)], slope=0.0, path=path)
    assert victim.read_bytes() == b"precious"
    assert not path.is_symlink() and path.read_bytes()[:6] in (b"GIF89a", b"GIF87a")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["victim.gif", "walk.gif"]
