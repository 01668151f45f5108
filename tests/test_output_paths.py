"""Output paths checked before any work: ``walker find``, ``run``, ``continue``, ``basin``
and ``sweep`` refuse an existing file without ``--overwrite``, a missing or unwritable
directory and a directory given as ``--out`` with one usage line and no simulation started;
``basin`` and ``sweep`` refuse a file of another result or another grid before computing;
``walker plot`` checks its output directory before plotting.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest
from _checkpoints import small_basin_file

from walker.cli import main
from walker.storage import read

REPO = Path(__file__).resolve().parents[1]
SCENE = str(REPO / "gaits/compass_goswami.toml")


@pytest.fixture
def no_simulation(monkeypatch):
    """Every way into a simulation raises: the commands must stop before one."""

    def refuse(*args, **kwargs):
        raise AssertionError("a simulation started before the output path was checked")

    import walker.analysis.basin
    import walker.analysis.fixedpoint
    import walker.analysis.sweep
    import walker.plotting.gallery
    import walker.simulation.stride
    import walker.simulation.trajectory

    monkeypatch.setattr(walker.simulation.stride.StrideMap, "__call__", refuse)
    monkeypatch.setattr(
        walker.simulation.trajectory, "_solve", refuse
    )  # simulate's way into the integrator
    monkeypatch.setattr(walker.simulation.trajectory, "simulate", refuse)
    monkeypatch.setattr(walker.simulation.stride, "simulate", refuse)
    monkeypatch.setattr(walker.analysis.fixedpoint, "find_fixed_point", refuse)
    monkeypatch.setattr(walker.analysis.basin, "basin_chunk", refuse)
    monkeypatch.setattr(walker.analysis.sweep, "sweep_chunk", refuse)
    monkeypatch.setattr(walker.plotting.gallery, "plot_file", refuse)


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


@pytest.mark.parametrize("cmd", ["basin", "sweep"])
def test_other_result_is_not_resumed(capsys, tmp_path, no_simulation, cmd):
    """A finished result (no checkpoint) or another computation's checkpoint is refused
    before any work, with a message naming --overwrite."""
    out = small_basin_file(tmp_path / "old.h5")
    before = out.read_bytes()
    line = _usage_error(capsys, [*COMMANDS[cmd], "--out", str(out)])
    assert f"--out {out} exists and " in line and "pass --overwrite to replace it" in line
    assert out.read_bytes() == before


def test_sweep_with_other_grid_is_refused_then_overwritten(capsys, tmp_path, monkeypatch):
    out = tmp_path / "s.h5"
    assert main([*COMMANDS["sweep"], "--out", str(out)]) == 0
    capsys.readouterr()
    other = ["sweep", SCENE, "--param", "slope=0.01:0.03:3", "--quiet", "--out", str(out)]
    import walker.analysis.sweep

    real_chunk = walker.analysis.sweep.sweep_chunk

    def refuse(*args, **kwargs):
        raise AssertionError("work started")

    monkeypatch.setattr(walker.analysis.sweep, "sweep_chunk", refuse)
    line = _usage_error(capsys, other)
    assert "checkpoints a different sweep" in line and "pass --overwrite" in line
    assert read(out)[0].points.shape == (2, 1)
    monkeypatch.setattr(walker.analysis.sweep, "sweep_chunk", real_chunk)
    assert main([*other, "--overwrite"]) == 0
    assert read(out)[0].points.shape == (3, 1)


def test_basin_with_other_settings_is_refused_before_the_fixed_point(capsys, tmp_path, monkeypatch):
    out = tmp_path / "b.h5"
    assert main([*COMMANDS["basin"], "--jobs", "1", "--out", str(out)]) == 0
    capsys.readouterr()
    first = read(out)[0]
    import walker.analysis.fixedpoint

    def refuse(*args, **kwargs):
        raise AssertionError("the fixed point was searched for")

    real = walker.analysis.fixedpoint.find_fixed_point
    monkeypatch.setattr(walker.analysis.fixedpoint, "find_fixed_point", refuse)
    other = ["basin", SCENE, "--n", "4", "--strides", "4", "--quiet", "--out", str(out)]
    line = _usage_error(capsys, other)
    assert "checkpoints a different basin map (n_strides 3 != 4)" in line
    assert "pass --overwrite" in line
    monkeypatch.setattr(walker.analysis.fixedpoint, "find_fixed_point", real)
    # the same command again resumes a finished map: nothing to do, same file content
    assert main([*COMMANDS["basin"], "--out", str(out)]) == 0
    again = read(out)[0]
    assert again.outcome.tobytes() == first.outcome.tobytes()
    assert main([*other, "--overwrite"]) == 0
    assert read(out)[0].n_strides == 4


def test_plot_output_directory_checked_before_plotting(capsys, tmp_path, unwritable_dir):
    import walker.plotting.gallery

    def refuse(*args, **kwargs):
        raise AssertionError("plotting started")

    src = small_basin_file(tmp_path / "basin.h5")
    orig = walker.plotting.gallery.plot_file
    walker.plotting.gallery.plot_file = refuse
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
        walker.plotting.gallery.plot_file = orig
    assert not (tmp_path / "no").exists()
