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

    from walker.plotting.runs import animate_walker

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


# --------------------------------------------------------------------------------------------
# Exit codes


def _closed_stdout():
    os.close(1)


def test_closed_stdout_is_141(tmp_path):
    """Before: ``walker find gaits/kneed_hsu.toml >&-`` ended in exit 3 (AttributeError:
    ``sys.stdout`` is None), where the exit-status table promises 141.  Now the output goes
    nowhere and the status is 141; files are still written, and a later file never gets
    descriptor 1."""
    out = tmp_path / "fp.h5"
    done = subprocess.run(
        [sys.executable, "-m", "walker", "find", str(COMPASS), "--out", str(out)],
        cwd=REPO,
        stderr=subprocess.PIPE,
        text=True,
        timeout=300,
        preexec_fn=_closed_stdout,
    )
    assert done.returncode == 141, done.stderr
    assert done.stderr == ""
    from walker.storage import read

    result, _ = read(out)
    assert result.success


@pytest.mark.parametrize("what", ["character-device", "fifo", "directory"])
def test_scene_path_that_is_not_a_file_says_what_it_is(tmp_path, what, capsys):
    """Before: ``walker find /dev/zero`` (or a FIFO, or a directory) said "scene file not
    found".  Now the line says what the path is; a FIFO is not opened (which would block)."""
    if what == "character-device":
        path, kind = Path(os.devnull), "a character device"
    elif what == "fifo":
        path, kind = tmp_path / "scene.toml", "a FIFO"
        os.mkfifo(path)
    else:
        path, kind = tmp_path, "a directory"
    assert main(["find", str(path)]) == 2
    err = capsys.readouterr().err
    assert err == f"walker: error: scene file {path}: is {kind}, not a regular file\n"


def test_missing_scene_still_says_not_found(tmp_path, capsys):
    assert main(["find", str(tmp_path / "none.toml")]) == 2
    assert "scene file not found" in capsys.readouterr().err


def test_output_created_meanwhile_says_the_flag(tmp_path, monkeypatch, capsys):
    """Before: of two sweeps started together on one ``--out``, the loser said "pass
    overwrite=True" (the library's wording).  Now it names ``--out`` and ``--overwrite``.
    The race is made certain: the file appears between the command's check of ``--out``
    and its creation."""
    out = tmp_path / "sweep.h5"
    original = disk_module._atomic_write

    def winner_first(path, image, overwrite):
        Path(path).write_bytes(b"the other sweep's file")
        return original(path, image, overwrite)

    monkeypatch.setattr(disk_module, "_atomic_write", winner_first)
    from walker.storage import checkpoint as checkpoint_module

    monkeypatch.setattr(checkpoint_module, "_atomic_write", winner_first)
    argv = ["sweep", str(COMPASS), "--param", "slope=0.01:0.02:2", "--out", str(out), "--quiet"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err == f"walker: error: --out {out} exists; pass --overwrite to replace it\n"
    assert out.read_bytes() == b"the other sweep's file"


# --------------------------------------------------------------------------------------------
# Ctrl-C while the command starts


@pytest.mark.parametrize("after", ["import walker", "import walker.cli", "parse"])
def test_interrupt_while_starting_is_quiet_130(tmp_path, after):
    """Before: SIGINT in the first ~1.5 s of any command printed an 18-21-line traceback
    of the import it hit.  Now the ``walker`` command installs a handler first thing in
    ``walker/__init__.py``: one line, status 130.  The process is a script named ``walker``
    (as the console script is) that sends SIGINT to itself at a fixed point of its start,
    so the test does not depend on timing."""
    script = tmp_path / "walker"
    script.write_text(
        f"""
import os, signal, sys
sys.path.insert(0, {str(REPO)!r})
import walker
if {after!r} == "import walker":
    os.kill(os.getpid(), signal.SIGINT)
import walker.cli
if {after!r} == "import walker.cli":
    os.kill(os.getpid(), signal.SIGINT)
parser = walker.cli.build_parser()
if {after!r} == "parse":
    os.kill(os.getpid(), signal.SIGINT)
sys.exit(walker.cli.main(["find", {str(COMPASS)!r}]))
"""
    )
    done = subprocess.run(
        [sys.executable, str(script)], cwd=REPO, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 130, done.stderr
    assert done.stderr == "walker: interrupted\n"


def test_worker_processes_keep_the_interrupt_handler():
    """A process started as ``python -c`` (how multiprocessing starts a worker), whose
    ``sys.argv`` names the walker script, keeps Python's own SIGINT handler."""
    code = (
        "import signal, sys\n"
        "sys.argv = ['/usr/bin/walker', 'sweep']\n"
        "import walker\n"
        "print(signal.getsignal(signal.SIGINT) is signal.default_int_handler)"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=120
    )
    assert done.stdout == "True\n", done.stderr


def test_library_import_keeps_the_interrupt_handler():
    code = (
        "import signal, walker\n"
        "print(signal.getsignal(signal.SIGINT) is signal.default_int_handler)"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=120
    )
    assert done.stdout == "True\n", done.stderr


def _numpy_loaded(pid: int) -> bool:
    try:
        return "_multiarray_umath" in Path(f"/proc/{pid}/maps").read_text()
    except OSError:
        return False


@pytest.mark.skipif(not Path("/proc/self/maps").exists(), reason="needs /proc/<pid>/maps")
def test_real_ctrl_c_during_imports_is_quiet_130():
    """A real SIGINT to ``python -m walker find`` as soon as numpy's extension is mapped
    (walker's own imports have begun, after the start-up handler): one line, 130."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "walker", "find", str(COMPASS)],
        cwd=REPO,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        deadline = time.monotonic() + 60  # a hang guard, not a measurement
        while not _numpy_loaded(proc.pid) and proc.poll() is None:
            if time.monotonic() > deadline:
                pytest.fail("numpy was never loaded")
            time.sleep(0.001)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 130, err
    assert err == "walker: interrupted\n"


# --------------------------------------------------------------------------------------------
# Parsing cost of scenes


@pytest.mark.parametrize(
    "text, line",
    [
        ("a" + ".a" * 10_000 + " = 1\n", 1),  # the probe's 20 KB scene (41 s to refuse)
        ("[scene]\nmodel = 'compass'\n" + "a" + ".a" * 32 + " = 1\n", 3),
        ('"x"' + '."y"' * 40 + " = 1\n", 1),
        ("[" + "t." * 40 + "t]\n", 1),
        ("x = {" + "k . " * 40 + "k = 1}\n", 1),
    ],
    ids=["20KB-dotted-key", "33-parts", "quoted-parts", "table-header", "inline-spaces"],
)
def test_long_dotted_key_is_refused_before_parsing(tmp_path, text, line, monkeypatch):
    """Before: TOML dotted keys parse in time growing with the square of their parts; a
    20 KB scene of ``a.a.a...`` took 41 s to refuse, and the 1 MiB limit allowed hours.
    Now a key of more than ``MAX_KEY_PARTS`` parts is refused by a linear scan, before the
    parser runs (the parser is replaced by one that fails, to show it is never called)."""
    from walker import scene as scene_module

    path = tmp_path / "deep.toml"
    path.write_text(text)

    def never(_text):
        raise AssertionError("the TOML parser ran")

    monkeypatch.setattr(scene_module.tomllib, "loads", never)
    with pytest.raises(ValueError, match=rf"more than 32 parts at line {line}; refused") as info:
        scene_module.load_scene(path)
    assert str(path) in str(info.value) and "\n" not in str(info.value)


def test_keys_of_at_most_32_parts_reach_the_parser(tmp_path):
    """The bound refuses nothing a scene can hold: the shipped scenes load, and a 32-part
    key is left to the parser and the scene rules (an unknown table)."""
    from walker.scene import load_scene

    for scene in sorted((REPO / "gaits").glob("*.toml")):
        load_scene(scene)
    path = tmp_path / "ok.toml"
    path.write_text("a" + ".a" * 31 + " = 1\nversion = '1.2.3.4.5'\n")
    with pytest.raises(ValueError, match=r"unknown tables \[a\], \[version\]"):
        load_scene(path)


# --------------------------------------------------------------------------------------------
# Item 3: optional dependencies


def test_scheduler_without_dask_is_one_line_exit_2(tmp_path, monkeypatch, capsys):
    """Before: ``walker sweep --scheduler ...`` without dask printed "internal error ...
    please report" and exited 3.  Now it is one line naming the ``dask`` extra, exit 2,
    before any work (no file).  dask is hidden from this process (``sys.modules`` entries
    of None make its import fail as if it were not installed)."""
    for name in ("distributed", "dask"):
        monkeypatch.setitem(sys.modules, name, None)
    out = tmp_path / "sw.h5"
    argv = ["sweep", str(COMPASS), "--param", "slope=0.05:0.06:2", "--out", str(out)]
    assert main([*argv, "--scheduler", "tcp://127.0.0.1:1"]) == 2
    err = capsys.readouterr().err
    assert err == (
        "walker: error: the optional extra `dask` is not installed (no module 'distributed'); "
        "install it with pip install 'walker-hybrid[dask]'\n"
    )
    assert not out.exists()


@pytest.mark.parametrize(
    "module, extra",
    [("heyoka", "`bench`"), ("pydrake", "`bench`"), ("numba", "`numba`"), ("pandas", None)],
)
def test_any_missing_optional_module_is_one_line_exit_2(module, extra, monkeypatch, capsys):
    """Whatever command meets a missing optional module: one line naming what installs it
    (the command is replaced by one whose import fails)."""
    from walker.cli import find as find_module

    def needs_it(args):
        raise ModuleNotFoundError(f"No module named '{module}'", name=module)

    monkeypatch.setattr(find_module, "cmd_find", needs_it)
    assert main(["find", str(COMPASS)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"(no module '{module}')" in err
    if extra is None:
        assert f"the optional package `{module}`" in err and f"pip install {module}\n" in err
    else:
        assert f"the optional extra {extra} is not installed" in err


def test_a_missing_required_module_is_still_an_internal_error(monkeypatch, capsys, tmp_path):
    from walker.cli import find as find_module

    def broken(args):
        raise ModuleNotFoundError("No module named 'scipy'", name="scipy")

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setattr(find_module, "cmd_find", broken)
    assert main(["find", str(COMPASS)]) == 3
    assert "internal error" in capsys.readouterr().err
