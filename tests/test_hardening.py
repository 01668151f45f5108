"""Issue 17, the command line and the Python API: every failure is one line with exit 2 (or
a clear ValueError/TypeError naming the argument), sizes are bounded before anything is
allocated, nothing invalid is accepted in silence, and pool workers end with their parent.

Each test's docstring says what happened before the fix.  The command line runs in-process
(``walker.cli.main`` with ``capsys``) unless an exit status, a signal or a closed pipe
matters; then ``python -m walker`` runs in a subprocess.  Timeouts only guard against hangs.
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from walker import StrideMap, load_scene, simulate
from walker.analysis.basin import basin_map
from walker.analysis.fixedpoint import find_fixed_point
from walker.analysis.sweep import MAX_SWEEP_POINTS, MapSpec, parse_range, sweep, sweep_chunk
from walker.cli import EXIT_BROKEN_PIPE, EXIT_INTERNAL, EXIT_USAGE, main

REPO = Path(__file__).resolve().parents[1]
SCENE = str(REPO / "gaits/compass_goswami.toml")
HANG_GUARD = 300  # seconds; only against hangs (a loaded machine, a cold start)


def _cli(capsys, argv):
    """``walker ARGV`` in-process: (exit status, stdout, stderr)."""
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def _one_error_line(err: str, *needles: str) -> str:
    """stderr is exactly one ``walker: error: ...`` line containing every needle."""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("walker: error: "), err
    assert "Traceback" not in err
    for needle in needles:
        assert needle in lines[0], (needle, lines[0])
    return lines[0]


def _walker(*argv, timeout=HANG_GUARD, **kwargs):
    """``python -m walker ARGV`` in a subprocess, from the repository."""
    return subprocess.run(
        [sys.executable, "-m", "walker", *map(str, argv)],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=timeout,
        **kwargs,
    )


@pytest.fixture
def compass():
    scene = load_scene(SCENE)
    P = StrideMap(scene.model, scene.params, rtol=1e-10, atol=1e-12)
    return scene, P, P.project(scene.state)


@pytest.fixture
def no_work(monkeypatch):
    """Make the expensive steps of the commands fail loudly: a check that must come before
    any work then shows that it does."""

    def forbidden(*args, **kwargs):
        raise AssertionError("work started before the input was checked")

    import walker.analysis.fixedpoint
    import walker.plotting.gallery
    import walker.simulation.stride

    monkeypatch.setattr(walker.analysis.fixedpoint, "find_fixed_point", forbidden)
    monkeypatch.setattr(walker.simulation.stride, "simulate", forbidden)
    monkeypatch.setattr(walker.plotting.gallery, "plot_file", forbidden)


# ---- 1. every command-line failure: one line, exit 2 ---------------------------------------


@pytest.mark.parametrize(
    "argv",
    [
        ["find", SCENE],
        ["run", SCENE],
        ["basin", SCENE, "--n", "3"],
        ["sweep", SCENE, "--param", "slope=0.05:0.06:2"],
    ],
    ids=["find", "run", "basin", "sweep"],
)
def test_out_directory_with_overwrite_is_one_line(tmp_path, capsys, no_work, argv):
    """Before: ``IsADirectoryError`` traceback (issue 17); already refused by the output
    checks of issue 13 when this was written, kept as a regression test."""
    code, _, err = _cli(capsys, [*argv, "--out", tmp_path, "--overwrite"])
    assert code == EXIT_USAGE
    _one_error_line(err, "--out", "is a directory")


@pytest.mark.parametrize("command", ["find", "run", "basin", "sweep"])
def test_out_name_too_long_names_the_flag(tmp_path, capsys, no_work, command):
    """Before: an ``OSError: [Errno 36] File name too long`` traceback, exit 1."""
    out = tmp_path / ("a" * 300 + ".h5")
    extra = ["--param", "slope=0.05:0.06:2"] if command == "sweep" else []
    code, _, err = _cli(capsys, [command, SCENE, *extra, "--out", out])
    assert code == EXIT_USAGE
    _one_error_line(err, f"--out {out}", "File name too long")


def test_a_line_longer_than_the_limit_keeps_its_reason(tmp_path, capsys, no_work):
    """Before: a message over 400 characters was cut at its end, so a long path in a deep
    directory hid the reason ("...: File name too...").  Now such a line loses its middle."""
    deep = tmp_path
    for letter in "defgh":  # 5 x 200 characters of directories
        deep = deep / (letter * 200)
    deep.mkdir(parents=True)
    out = deep / ("a" * 300 + ".h5")
    code, _, err = _cli(capsys, ["find", SCENE, "--out", out])
    assert code == EXIT_USAGE
    line = _one_error_line(err, "--out /", " ... ", ".h5: File name too long")
    assert len(line) <= len("walker: error: ") + 1000


def test_scene_and_result_names_too_long(tmp_path, capsys, no_work):
    """Before: an ``OSError`` traceback from ``Path.is_file`` / ``Path.exists``, exit 1."""
    long = tmp_path / ("s" * 300 + ".toml")
    code, _, err = _cli(capsys, ["find", long])
    assert code == EXIT_USAGE
    _one_error_line(err, f"scene file {long}", "File name too long")
    code, _, err = _cli(capsys, ["plot", tmp_path / ("r" * 300 + ".h5")])
    assert code == EXIT_USAGE
    _one_error_line(err, "result file", "File name too long")
    code, _, err = _cli(capsys, ["plot", SCENE, "--out", tmp_path / ("d" * 300)])
    assert code == EXIT_USAGE
    _one_error_line(err, "--out", "File name too long")


@pytest.mark.slow  # three dask subprocesses: the integration tier
def test_unreachable_scheduler_fails_fast_with_exit_2(tmp_path):
    """Before: dask retried for 30 s, then an ``OSError`` traceback with exit 1 (38 s in
    all).  Now a refused port is reported at once; the hang guard is generous against the
    few seconds allowed (``walker.cli.sweep.SCHEDULER_TIMEOUT``).  Needs dask (the
    ``dask`` extra; without it ``--scheduler`` is refused first: tests/test_probe_outputs)."""
    pytest.importorskip("distributed", reason="the `dask` extra is not installed")
    out = tmp_path / "sw.h5"
    args = ["sweep", SCENE, "--param", "slope=0.05:0.06:2", "--out", out]
    proc = _walker(*args, "--scheduler", "tcp://127.0.0.1:1", timeout=30)
    assert proc.returncode == EXIT_USAGE, proc.stderr
    _one_error_line(proc.stderr, "--scheduler tcp://127.0.0.1:1", "cannot connect")
    proc = _walker(*args, "--overwrite", "--scheduler", "nohost", timeout=30)
    assert proc.returncode == EXIT_USAGE, proc.stderr
    _one_error_line(proc.stderr, "--scheduler nohost", "missing port")
    # --jobs with --scheduler: one warning line in flags, then the error
    proc = _walker(*args, "--overwrite", "--jobs", "2", "--scheduler", "nohost", timeout=30)
    assert proc.returncode == EXIT_USAGE, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert lines[0] == (
        "walker: warning: --jobs has no effect with --scheduler (the cluster decides)"
    ), lines
    assert len(lines) == 2 and "missing port" in lines[1], lines


def test_scheduler_probe_accepts_a_real_scheduler():
    """The check made before connecting lets a real dask scheduler through (an in-process
    cluster)."""
    distributed = pytest.importorskip("distributed")
    from walker.cli.sweep import run_sweep_command

    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None
    ) as cluster:
        table = run_sweep_command(
            REPO / "gaits/simplest_garcia.toml",
            ["slope=0.008:0.010:3"],
            scheduler=cluster.scheduler_address,
            quiet=True,
        )
    assert table.columns["status"].tolist() == [0, 0, 0]


def _scene_text(**replace: str) -> str:
    text = Path(SCENE).read_text()
    for old, new in replace.items():
        assert old in text
        text = text.replace(old, new, 1)
    return text


def test_toml_integer_too_large_for_a_float(tmp_path, capsys):
    """Before: ``OverflowError: int too large to convert to float`` traceback, exit 1."""
    path = tmp_path / "big.toml"
    path.write_text(re.sub(r"(?m)^slope = .*$", "slope = 1" + "0" * 320, Path(SCENE).read_text()))
    code, _, err = _cli(capsys, ["find", path])
    assert code == EXIT_USAGE
    _one_error_line(err, str(path), "[parameters] `slope` must be finite", "321 digits")
    # Beyond Python's digit limit the parser itself refuses it: still one line.
    path.write_text(re.sub(r"(?m)^slope = .*$", "slope = 1" + "0" * 5000, Path(SCENE).read_text()))
    code, _, err = _cli(capsys, ["find", path])
    assert code == EXIT_USAGE
    _one_error_line(err, str(path), "invalid TOML")


def test_deeply_nested_toml_is_one_line(tmp_path):
    """Before: ``RecursionError`` with 3,000 lines of stderr, exit 1."""
    path = tmp_path / "deep.toml"
    path.write_text("x = " + "{a = " * 2000 + "1" + "}" * 2000 + "\n")
    proc = _walker("find", path)
    assert proc.returncode == EXIT_USAGE
    _one_error_line(proc.stderr, str(path), "nested too deeply")


@contextlib.contextmanager
def _read_only_directory(path: Path):
    """``path`` as a directory nobody can write, root included: a read-only tmpfs when
    running as root (which ignores permissions), else mode 0o555."""
    path.mkdir()
    if os.geteuid() != 0:
        path.chmod(0o555)
        try:
            yield path
        finally:
            path.chmod(0o755)
        return
    proc = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "ro,size=64k", "tmpfs", str(path)],
        capture_output=True,
        text=True,
    )
    if proc.returncode != 0:
        pytest.skip(f"cannot make a read-only file system as root: {proc.stderr.strip()}")
    try:
        yield path
    finally:
        subprocess.run(["umount", str(path)], check=False)


@pytest.mark.parametrize("command", ["find", "run", "basin", "plot"])
def test_read_only_output_directory_refused_before_work(tmp_path, capsys, no_work, command):
    """Before (issue 17): after the full computation, a traceback.  Already refused before
    any work by the checks of issue 13 when this was written: kept as a regression test,
    on a real read-only file system (``os.access`` says yes to root)."""
    with _read_only_directory(tmp_path / "ro") as ro:
        if command == "plot":
            argv = ["plot", SCENE, "--out", ro / "figures"]
        else:
            argv = [command, SCENE, "--out", ro / "x.h5"]
        code, _, err = _cli(capsys, argv)
    assert code == EXIT_USAGE
    _one_error_line(err, "--out", "not writable")


def test_closed_stdout_exits_quietly():
    """Before: ``walker find ... --json | head -c1`` printed a ``BrokenPipeError``
    traceback (exit 1).  Now nothing is printed and the status is 141 (128 + SIGPIPE), as
    for a tool ended by SIGPIPE."""
    for argv in (["find", SCENE, "--json"], ["find", SCENE], ["run", SCENE]):
        read_end, write_end = os.pipe()
        os.close(read_end)  # the reader is gone before anything is written
        try:
            proc = subprocess.run(
                [sys.executable, "-m", "walker", *argv],
                cwd=REPO,
                stdout=write_end,
                stderr=subprocess.PIPE,
                text=True,
                timeout=HANG_GUARD,
            )
        finally:
            os.close(write_end)
        assert proc.returncode == EXIT_BROKEN_PIPE, proc.stderr
        assert proc.stderr == ""


def test_unexpected_exception_is_an_internal_error_with_a_log(tmp_path, capsys, monkeypatch):
    """Before: ``main`` caught every ValueError and TypeError as bad input (exit 2) and let
    anything else out as a traceback with exit 1, the outcome code.  Now an exception walker
    did not raise for bad input is reported as a bug: one line, exit 3, the traceback in a
    log file."""
    import walker.cli.find

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))

    def broken(args):
        return np.linspace(0.0, 1.0, num=-1)  # a ValueError raised inside numpy

    monkeypatch.setattr(walker.cli.find, "cmd_find", broken)
    code, out, err = _cli(capsys, ["find", SCENE])
    assert code == EXIT_INTERNAL and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    match = re.fullmatch(
        r"walker: internal error \(ValueError: .*\), please report; traceback in (.+)", lines[0]
    )
    assert match, lines[0]
    log = Path(match.group(1))
    assert log.parent == tmp_path / "cache" / "walker"
    text = log.read_text()
    assert "Traceback (most recent call last)" in text and "linspace" in text
    assert "command: walker find" in text

    monkeypatch.setattr(walker.cli.find, "cmd_find", lambda args: 1 / 0)
    code, _, err = _cli(capsys, ["find", SCENE])
    assert code == EXIT_INTERNAL and "internal error (ZeroDivisionError" in err


def test_walkers_own_validation_errors_stay_exit_2(capsys):
    """The line of a ValueError raised by walker's validation (here the parameter bounds of
    ``--set``) is the message, with exit 2, not an internal error."""
    code, _, err = _cli(capsys, ["find", SCENE, "--set", "slope=5"])
    assert code == EXIT_USAGE
    _one_error_line(err, "`slope` must be in")


# ---- 2. sizes bounded before anything is allocated -----------------------------------------


def test_sweep_count_of_a_billion(tmp_path, capsys):
    """Before: ``MemoryError`` traceback (numpy.linspace of 8 GB), exit 1."""
    out = tmp_path / "sw.h5"
    code, _, err = _cli(capsys, ["sweep", SCENE, "--param", "slope=0:0.1:1000000000", "--out", out])
    assert code == EXIT_USAGE
    _one_error_line(err, "--param", "1,000,000,000", f"at most {MAX_SWEEP_POINTS:,}")
    assert not out.exists()
    with pytest.raises(ValueError, match=r"COUNT 1,000,000,000 is more than a sweep takes"):
        parse_range("slope=0:0.1:1000000000")


def test_sweep_count_of_ten_million_refused_at_once(tmp_path, capsys, compass):
    """Before: about 10 minutes validating the points one by one, in silence; a product of
    ranges (here 3,000 x 1,000) likewise."""
    out = tmp_path / "sw.h5"
    code, _, err = _cli(
        capsys, ["sweep", SCENE, "--param", "slope=0.01:0.06:10000000", "--out", out]
    )
    assert code == EXIT_USAGE
    _one_error_line(err, "--param", "10,000,000")
    args = ["sweep", SCENE, "--param", "slope=0.01:0.06:3000", "--param", "mass_hip=1:10:1000"]
    code, _, err = _cli(capsys, [*args, "--out", out])
    assert code == EXIT_USAGE
    _one_error_line(err, "--param", "3,000,000 points", "3,000 x 1,000")
    _, P, z0 = compass
    with pytest.raises(ValueError, match=r"the grid of `ranges` has 3,000,000 points"):
        sweep(P, args[3::2], z0=z0, executor="serial", progress=False)


def test_basin_grid_too_large(tmp_path, capsys, no_work, compass):
    """Before: ``MemoryError`` traceback (75 GiB for the outcome array), exit 1."""
    code, _, err = _cli(capsys, ["basin", SCENE, "--n", "100000", "--out", tmp_path / "b.h5"])
    assert code == EXIT_USAGE
    _one_error_line(err, "--n 100000", "10,000,000,000 points", "more than the limit")
    _, P, z0 = compass
    gait = find_fixed_point(P, z0)  # imported before no_work patched the module
    with pytest.raises(ValueError, match=r"`n` = \(100000, 100000\) gives a grid of"):
        basin_map(P, gait, ranges=((0.1, 0.2), (-1.2, -1.0)), n=(100000, 100000), progress=False)


def test_sample_rate_too_high(tmp_path, capsys, compass):
    """Before: ``MemoryError`` traceback (numpy.arange of the sample times), exit 1; and
    ``StrideMap.trajectory(sample_rate=0)`` raised ``ZeroDivisionError``."""
    code, _, err = _cli(capsys, ["run", SCENE, "--sample-rate", "1e9", "--out", tmp_path / "r.h5"])
    assert code == EXIT_USAGE
    _one_error_line(err, "--sample-rate", "samples", "more than the limit", "lower --sample-rate")
    assert not (tmp_path / "r.h5").exists()
    _, P, z0 = compass
    with pytest.raises(ValueError, match=r"`sample_rate` 1e\+12 Hz .* more than the limit"):
        P.trajectory(z0, sample_rate=1e12)
    for bad in (0, -1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match=r"`sample_rate` must be positive and finite \[Hz\]"):
            P.trajectory(z0, sample_rate=bad)
    with pytest.raises(TypeError, match=r"`sample_rate` must be a real number"):
        P.trajectory(z0, sample_rate="100")
    assert P.trajectory(z0, sample_rate=100.0).success


# ---- 3. Python API: ValueError/TypeError naming the argument -------------------------------


def test_numbers_too_large_for_a_float(compass):
    """Before: ``OverflowError: int too large to convert to float`` from every one of these."""
    scene, P, z0 = compass
    big = 10**400
    with pytest.raises(ValueError, match=r"`slope` must be finite"):
        P.with_params(slope=big)
    with pytest.raises(ValueError, match=r"\[overrides\] `slope` must be finite"):
        load_scene(SCENE, overrides={"slope": big})
    with pytest.raises(ValueError, match=r"All components of `x0` must be finite"):
        simulate("compass", scene.params, [big, 0, 0, 0])
    with pytest.raises(ValueError, match=r"All components of `z` must be finite"):
        P([big, 0, 0])
    with pytest.raises(ValueError, match=r"All components of `z0` must be finite"):
        find_fixed_point(P, [big, 0, 0])
    with pytest.raises(ValueError, match=r"`tol` must be positive and finite"):
        find_fixed_point(P, z0, tol=big)
    with pytest.raises(ValueError, match=r"values of `slope` in `ranges` must all be finite"):
        sweep(P, {"slope": [big]}, z0=z0, executor="serial", progress=False)


def test_load_scene_of_a_non_path():
    """Before: bare ``TypeError: expected str, bytes or os.PathLike object, not int``."""
    for bad in (123, None, 1.5):
        with pytest.raises(TypeError, match=r"`path` must be a str or os.PathLike, got"):
            load_scene(bad)


def test_project_and_lift_of_a_short_vector(compass):
    """Before: ``IndexError: index 2 is out of bounds``."""
    _, P, _ = compass
    with pytest.raises(ValueError, match=r"`x` must have shape \(4,\), got \(2,\)"):
        P.project([0.1, 0.2])
    with pytest.raises(ValueError, match=r"`z` must have shape \(3,\), got \(1,\)"):
        P.lift([0.1])
    with pytest.raises(ValueError, match=r"`z` must have shape \(3,\), got \(1,\)"):
        P.trajectory([0.1])


def test_find_fixed_point_of_a_non_map(compass):
    """Before: ``AttributeError: 'str' object has no attribute 'n_z'``."""
    _, _, z0 = compass
    with pytest.raises(TypeError, match=r"`section_map` must be a SectionMap .* got str"):
        find_fixed_point("x", z0)


def test_sweep_chunk_of_an_unknown_kind(compass):
    """Before: ``KeyError: 'residual'`` after the first point was computed."""
    _, P, z0 = compass
    with pytest.raises(
        ValueError, match=r"`kind` must be one of outcome, fixed_point, got 'weird'"
    ):
        sweep_chunk(MapSpec.from_map(P), ("slope",), np.array([[0.05]]), "weird", z0, 1, 1e-10)


# ---- 4. nothing invalid accepted in silence ------------------------------------------------


def test_basin_jobs_below_one(tmp_path, capsys, no_work, compass):
    """Already refused when this was written (``--jobs 0`` and ``-1`` ran in issue 17's
    probe): a regression test, for the command line and ``basin_map``."""
    for jobs in ("0", "-1"):
        code, _, err = _cli(capsys, ["basin", SCENE, "--jobs", jobs, "--out", tmp_path / "b.h5"])
        assert code == EXIT_USAGE
        _one_error_line(err, f"--jobs must be >= 1, got {jobs}")
    _, P, z0 = compass
    gait = find_fixed_point(P, z0)
    for jobs in (0, -1):
        with pytest.raises(ValueError, match=r"`jobs` must be an integer >= 1"):
            basin_map(P, gait, ranges=((0.1, 0.2), (-1.2, -1.0)), n=(2, 2), jobs=jobs)


def test_find_period_zero_refused(capsys, no_work):
    """Before: ``--period 0`` was read as "not given" (``args.period or ...``) and the scene's
    period used."""
    for period in ("0", "-2"):
        code, _, err = _cli(capsys, ["find", SCENE, "--period", period])
        assert code == EXIT_USAGE
        _one_error_line(err, f"--period must be an integer >= 1, got {period}")
    code, _, err = _cli(capsys, ["find", SCENE, "--tol", "0"])
    assert code == EXIT_USAGE
    _one_error_line(err, "--tol must be a finite number > 0")


def test_scene_phase_beyond_the_models_phases(tmp_path, capsys, no_work):
    """Before: ``phase = 99`` for the compass gait (one phase) was accepted by
    ``load_scene`` and by ``walker find``."""
    path = tmp_path / "phase.toml"
    path.write_text(re.sub(r"(?m)^phase = 0$", "phase = 99", Path(SCENE).read_text()))
    with pytest.raises(
        ValueError,
        match=r"\[initial\] `phase` must be < 1, the number of phases of model compass "
        r"\(0 'swing'\), got 99",
    ):
        load_scene(path)
    code, _, err = _cli(capsys, ["find", path])
    assert code == EXIT_USAGE
    _one_error_line(err, str(path), "[initial] `phase` must be < 1")


def test_complex_input_refused(compass):
    """Before: a complex ``z`` was cast to its real part (a ``ComplexWarning``) and the
    search went on."""
    scene, P, z0 = compass
    rule = r"must be real, got complex values"
    with pytest.raises(TypeError, match="`z` " + rule):
        P(z0 + 1e-3j)
    with pytest.raises(TypeError, match="`z0` " + rule):
        find_fixed_point(P, z0 + 0j)
    with pytest.raises(TypeError, match="`x0` " + rule):
        simulate("compass", scene.params, scene.state + 1e-3j)
    with pytest.raises(TypeError, match="`x` " + rule):
        P.project(scene.state.astype(complex))
    with pytest.raises(TypeError, match="`z0` " + rule):
        sweep(P, {"slope": [0.05]}, z0=z0 + 1j, executor="serial", progress=False)


def test_booleans_are_not_sweep_values(compass):
    """Before: ``True``/``False`` were swept as 1.0 and 0.0."""
    _, P, z0 = compass
    for values in ([True, False], [0.05, True], np.array([True])):
        with pytest.raises(TypeError, match=r"values of `slope` in `ranges` must be numbers"):
            sweep(P, {"slope": values}, z0=z0, executor="serial", progress=False)


def test_sweep_chunk_refuses_unknown_names_and_bad_points(compass):
    """Before: ``sweep_chunk`` ran an unknown parameter name (ignored) and returned status 0
    (COMPLETED); a point outside the bounds ran with invalid parameters."""
    _, P, z0 = compass
    spec = MapSpec.from_map(P)
    with pytest.raises(ValueError, match=r"unknown parameter `slopez` in `names`.*valid names"):
        sweep_chunk(spec, ("slopez",), np.array([[0.05]]), "outcome", z0, 1, 1e-10)
    with pytest.raises(ValueError, match=r"grid point \(slope=5.0\) is not valid: `slope` must"):
        sweep_chunk(spec, ("slope",), np.array([[5.0]]), "outcome", z0, 1, 1e-10)
    with pytest.raises(ValueError, match=r"`points` must have shape \(m, 1\)"):
        sweep_chunk(spec, ("slope",), np.array([0.05]), "outcome", z0, 1, 1e-10)
    ok = sweep_chunk(spec, ("slope",), np.array([[0.05]]), "outcome", z0, 1, 1e-10)
    assert ok["status"].tolist() == [0]


# ---- 5. pool workers end with their parent -------------------------------------------------


def _proc_stat(pid: int) -> tuple[str, int, str] | None:
    """(state, parent pid, start time) of ``pid`` from /proc, None when it is gone."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    fields = text[text.rindex(")") + 2 :].split()
    return fields[0], int(fields[1]), fields[19]


def _descendants(root: int) -> dict[int, str]:
    """Every live descendant of ``root``: pid -> start time (so a reused pid is not it)."""
    children: dict[int, list[int]] = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit() and (stat := _proc_stat(int(entry))) is not None:
            children.setdefault(stat[1], []).append(int(entry))
    found: dict[int, str] = {}
    todo = [root]
    while todo:
        for child in children.get(todo.pop(), []):
            stat = _proc_stat(child)
            if stat is not None and stat[0] not in "ZX":
                found[child] = stat[2]
                todo.append(child)
    return found


def _alive(pid: int, start: str) -> bool:
    stat = _proc_stat(pid)
    return stat is not None and stat[2] == start and stat[0] not in "ZX"


KILL_SWEEP = """
from walker import StrideMap, load_scene
from walker.analysis.sweep import sweep

if __name__ == "__main__":
    scene = load_scene({scene!r})
    P = StrideMap("compass", scene.params, rtol=1e-10, atol=1e-12)
    sweep(P, ["slope=0.01:0.07:4000"], kind="fixed_point", z0=P.project(scene.state),
          executor="processes", jobs=2, chunk_size=4, progress=False)
"""

KILL_BASIN = """
import concurrent.futures as cf
import multiprocessing
import os
import time
from pathlib import Path

import numpy as np

from walker.analysis.basin import basin_map
from walker.analysis.fixedpoint import find_fixed_point
from walker.results import MapResult
from walker.status import Status

MARKS = Path({marks!r})


class SlowShrink:
    # z -> z / 2, slowly; each worker process marks its first stride
    n_z, section_names, parameter_name, parameter_value = 2, ("x", "y"), "c", 0.0

    def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
        (MARKS / str(os.getpid())).touch()
        time.sleep(0.01)
        jac = np.eye(2) * 0.5**n_strides if jacobian else None
        return MapResult(Status.COMPLETED, z * 0.5**n_strides, jac, 1.0, z)

    def lift(self, z):
        return z

    def with_parameter(self, value):
        return self


if __name__ == "__main__":
    gait = find_fixed_point(SlowShrink(), np.array([0.1, 0.1]))
    # a pool made by the caller, without walker's initializer, on a forkserver (with its
    # resource tracker): walker makes its workers end with this process on their first chunk
    pool = cf.ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("forkserver"))
    basin_map(SlowShrink(), gait, ranges=((-1, 1), (-1, 1)), n=(40, 200), n_strides=60,
              tol=1e-12, executor=pool, chunk_size=1, progress=False)
"""


def _kill_and_watch(tmp_path, script: str, ready) -> None:
    path = tmp_path / "main.py"
    path.write_text(textwrap.dedent(script))
    proc = subprocess.Popen(
        [sys.executable, str(path)], cwd=REPO, stderr=subprocess.PIPE, text=True
    )
    try:
        deadline = time.monotonic() + HANG_GUARD
        while not ready(proc.pid):
            assert proc.poll() is None, proc.stderr.read()
            assert time.monotonic() < deadline, "the pool workers never started"
            time.sleep(0.1)
        before = _descendants(proc.pid)
        assert before, "no child processes to watch"
    except BaseException:
        proc.kill()
        proc.wait()
        raise
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    deadline = time.monotonic() + 5.0  # the bound: nothing survives 5 s
    while time.monotonic() < deadline and any(_alive(p, s) for p, s in before.items()):
        time.sleep(0.05)
    left = {p: s for p, s in before.items() if _alive(p, s)}
    for pid in left:  # clean up after a failure
        with contextlib.suppress(ProcessLookupError):
            os.kill(pid, signal.SIGKILL)
    assert not left, f"processes alive 5 s after kill -9 of their parent: {sorted(left)}"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc")
def test_kill_9_of_a_process_pool_sweep_leaves_no_worker(tmp_path):
    """Before: after ``kill -9`` of a sweep's main process its pool workers (blocked on the
    call queue, whose write end they hold themselves) ran on for minutes, reparented to
    init.  Now ``sweep(executor="processes", jobs=2)`` makes workers that end with it."""

    def ready(pid):  # both workers forked and their initializer run (it starts a thread)
        kids = _descendants(pid)
        return len(kids) == 2 and all(
            len(os.listdir(f"/proc/{k}/task")) >= 2 for k in kids if Path(f"/proc/{k}").exists()
        )

    _kill_and_watch(tmp_path, KILL_SWEEP.format(scene=SCENE), ready)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc")
def test_kill_9_of_a_basin_on_a_users_forkserver_pool_leaves_nothing(tmp_path):
    """Before: the workers, the forkserver and the resource tracker of a basin's process pool
    stayed alive for minutes after ``kill -9`` of the main process.  Now the workers of any
    ``ProcessPoolExecutor`` given to walker end with their parent from their first chunk on,
    and the forkserver and the resource tracker follow."""
    marks = tmp_path / "marks"
    marks.mkdir()

    def ready(pid):  # two worker processes have run a stride (so the guard is installed)
        return len([m for m in marks.iterdir() if m.name != str(pid)]) >= 2

    _kill_and_watch(tmp_path, KILL_BASIN.format(marks=str(marks)), ready)


def test_sweep_processes_flag_gives_the_threads_table(tmp_path, capsys):
    """`walker sweep --processes` (worker processes that die with walker) computes the same
    table as the default threads (before: no command-line way to select processes)."""
    from walker import storage

    tables = []
    for extra, name in (([], "threads.h5"), (["--processes"], "processes.h5")):
        out = tmp_path / name
        argv = ["sweep", SCENE, "--param", "slope=0.04:0.06:6", "--jobs", "2", "--quiet"]
        assert main([*argv, *extra, "--out", str(out)]) == 0
        tables.append(storage.read(out)[0])
    capsys.readouterr()
    a, b = tables
    assert a.columns.keys() == b.columns.keys()
    for key in a.columns:
        np.testing.assert_array_equal(a.columns[key], b.columns[key])


@pytest.mark.parametrize(
    ("args", "flag", "rule"),
    [
        (["--n", "100000000"], "--n", "must be <= 1,000,000"),
        (["--n", "500000", "--strides", "100000"], "--n 500000 values", "lower --n or --strides"),
        (["--transient", "2000000"], "--transient", "must be <= 1,000,000"),
        (["--strides", "0"], "--strides", "must be an integer >= 1"),
    ],
)
def test_orbit_diagram_sizes_are_checked_before_work(tmp_path, args, flag, rule):
    proc = _walker(
        "orbit-diagram", SCENE, "--range", "0.05:0.06", *args, "--out", tmp_path / "o.h5"
    )
    assert proc.returncode == EXIT_USAGE, proc.stderr
    _one_error_line(proc.stderr, flag, rule)
    assert not (tmp_path / "o.h5").exists()
