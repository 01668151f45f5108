"""Cold-start benchmark: the first ``walker`` command a new user runs after installing, against
the same command run again (warm), each in a fresh subprocess, wall time; and, reported
separately, the install-time cost: building walker's C extension.

For every scene in gaits/: ``walker find SCENE`` when its ``[compute] task`` is
``fixed_point`` (and the model has strides), ``walker run SCENE`` otherwise.

walker's compiled core is a C extension (``walker._hybrid``) built when the package is
installed; walker has no numba functions (numba is only an optional extra for a user's own
@njit system): one more untimed run per scene under ``python -X importtime`` checks that the
command imported numba not at all.  The
method also shows any numba function a command still compiles at
run time, by name: every run gets ``NUMBA_CACHE_DIR`` set
to a new empty directory (one per scene); with it set, numba reads and writes compiled
functions only there and ignores the ``__pycache__/*.nbi|*.nbc`` files next to walker's sources
(numba's ``UserProvidedCacheLocator`` comes first in its locator list), so a numba function
called by the run would be compiled in the cold run, cached in that directory (counted in the
table) and loaded by the warm runs.  This disturbs nobody: the in-tree caches are neither read
nor written.  ``--delete-caches`` deletes every ``*.nbi``/``*.nbc`` under walker's package
directory first as well (redundant with ``NUMBA_CACHE_DIR``; do not use it while others run
walker from this tree).

"Cold" is therefore: a new process, an empty numba cache directory, and Python bytecode as a
user has it after ``pip install``: pip byte-compiles every module it installs, so before the
first timed run this script runs ``python -m compileall`` on walker's package (the tree it
imports; ``PYTHONDONTWRITEBYTECODE`` is removed from the commands' environment).  An editable
install writes no bytecode at install; its first command compiles walker's modules, timed
separately ("first run without bytecode", walker's ``.pyc`` files deleted before each such
run).  The operating system's file cache is warm (the interpreter, the libraries, walker's
sources and its extension were read by earlier runs: one untimed command runs before the
first row), not a cold disk.  Cold and warm runs alternate per scene (a new empty numba cache
directory for each cold run), min and median of each.

Build time: the files ``git ls-files`` lists are copied to a temporary directory and
``python setup.py build_ext --inplace --force`` is timed there (the C compile of the
extension, what ``pip install -e .`` runs besides setting up its build environment); the
checkout itself is not rebuilt.

Writes results/bench/coldstart.csv, coldstart.md and README.md.

Usage: python scripts/bench_coldstart.py [--quick] [--delete-caches] [--scenes a.toml,...]
       [--warm N] [--builds N]
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _bench as B  # noqa: E402

import walker  # noqa: E402
from walker import load_scene  # noqa: E402
from walker.models import get_model  # noqa: E402


def command_for(scene_path: Path) -> list[str]:
    """The subcommand a user runs for this scene (walker/cli/find.py: find needs a walker)."""
    scene = load_scene(scene_path)
    if scene.compute.task == "fixed_point" and get_model(scene.model).has_strides:
        return ["find", str(scene_path)]
    return ["run", str(scene_path)]


def walker_exe() -> list[str]:
    exe = shutil.which("walker")
    return [exe] if exe else [sys.executable, "-m", "walker.cli"]


def timed_run(argv, env, cwd):
    t = time.perf_counter()
    proc = subprocess.run(argv, env=env, cwd=cwd, capture_output=True, text=True)
    wall = time.perf_counter() - t
    out = (proc.stdout.strip() or proc.stderr.strip()).splitlines()
    # walker's first line names the outcome: "status NAME: message" (run) or
    # "status     NAME: message" (find); keep NAME.
    line = next((ln for ln in out if ln.startswith("status")), "")
    status = line.split(None, 1)[1].split(":")[0].strip() if " " in line else "?"
    return wall, proc.returncode, status


def imports_numba(exe, sub, env, cwd) -> bool:
    """Whether the command imports numba: one untimed run under ``python -X importtime``
    (whose report names every module imported, one per stderr line ending ``| <module>``)."""
    head = [sys.executable, "-X", "importtime"]
    argv = head + (exe[1:] if exe[0] == sys.executable else exe) + sub
    proc = subprocess.run(argv, env=env, cwd=cwd, capture_output=True, text=True)
    return any(
        ln.startswith("import time:") and ln.rsplit("|", 1)[-1].strip() == "numba"
        for ln in proc.stderr.splitlines()
    )


def delete_bytecode(pkg_dir: Path) -> int:
    """Delete walker's ``.pyc`` files (the state after an editable install)."""
    n = 0
    for f in pkg_dir.rglob("__pycache__/*.pyc"):
        f.unlink()
        n += 1
    return n


def compile_bytecode(pkg_dir: Path) -> int:
    """Byte-compile walker's package as ``pip install`` does; the number of ``.pyc`` files."""
    subprocess.run([sys.executable, "-m", "compileall", "-q", str(pkg_dir)], check=True)
    return sum(1 for _ in pkg_dir.rglob("__pycache__/*.pyc"))


def delete_numba_caches(pkg_dir: Path) -> int:
    n = 0
    for pattern in ("*.nbi", "*.nbc"):
        for f in pkg_dir.rglob(f"__pycache__/{pattern}"):
            f.unlink()
            n += 1
    return n


def time_build(n_builds: int, env) -> tuple[list[float], int, str, int]:
    """Copy the tracked files to a temporary directory and time ``python setup.py build_ext
    --inplace --force`` there ``n_builds`` times.  Returns (wall times, number of C sources,
    compiler, return code of the last build)."""
    files = subprocess.run(
        ["git", "-C", str(B.ROOT), "ls-files", "-z"], capture_output=True, check=True
    ).stdout.split(b"\0")
    walls, rc = [], 0
    with tempfile.TemporaryDirectory(prefix="walker-build-") as tmp:
        for f in filter(None, files):
            src = B.ROOT / os.fsdecode(f)
            if not src.is_file():  # deleted in the work tree, not yet committed
                continue
            dst = Path(tmp) / os.fsdecode(f)
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dst)
        n_c = len(list(Path(tmp).glob("walker/_core/*.c")))
        n_c += len(list(Path(tmp).glob("walker/_generated/*.c")))
        for k in range(n_builds):
            t = time.perf_counter()
            proc = subprocess.run(
                [sys.executable, "setup.py", "build_ext", "--inplace", "--force"],
                cwd=tmp,
                env=env,
                capture_output=True,
                text=True,
            )
            walls.append(time.perf_counter() - t)
            rc = proc.returncode
            built = list(Path(tmp).glob("walker/_hybrid*" + sysconfig.get_config_var("EXT_SUFFIX")))
            print(
                f"build {k}: {walls[-1]:.1f} s, exit {rc}, "
                f"{'extension built' if built else 'NO EXTENSION'}",
                flush=True,
            )
            if rc != 0 or not built:
                print(proc.stderr[-2000:], flush=True)
                rc = rc or 1
                break
    return walls, n_c, sysconfig.get_config_var("CC") or "?", rc


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="kneed_hsu only, one warm run")
    parser.add_argument(
        "--delete-caches",
        action="store_true",
        help="also delete every numba cache file under walker's package directory first "
        "(redundant with the per-scene NUMBA_CACHE_DIR; do not use while others run walker "
        "from this tree)",
    )
    parser.add_argument("--scenes", default=None, help="comma-separated scene file names")
    parser.add_argument("--warm", type=int, default=None, help="warm runs per scene")
    parser.add_argument("--builds", type=int, default=None, help="timed extension builds (0: skip)")
    args = parser.parse_args(argv)
    cmd = B.command_line("bench_coldstart.py", argv)
    if args.scenes:
        scenes = [B.GAITS / s.strip() for s in args.scenes.split(",")]
    elif args.quick:
        scenes = [B.GAITS / "kneed_hsu.toml"]
    else:
        scenes = sorted(B.GAITS.glob("*.toml"))
    n_warm = args.warm or (1 if args.quick else 3)
    n_builds = args.builds if args.builds is not None else (1 if args.quick else 2)
    pkg_dir = Path(walker.__file__).resolve().parent
    deleted = delete_numba_caches(pkg_dir) if args.delete_caches else None
    exe = walker_exe()
    t_start = time.perf_counter()
    load_before = os.getloadavg()[0]
    rows = []
    drop = ("NUMBA_CACHE_DIR", "PYTHONDONTWRITEBYTECODE")
    base_env = {k: v for k, v in os.environ.items() if k not in drop}
    # the commands import the same walker as this script (its package directory first)
    base_env["PYTHONPATH"] = os.pathsep.join(
        [str(pkg_dir.parent), *filter(None, [os.environ.get("PYTHONPATH")])]
    )
    with tempfile.TemporaryDirectory(prefix="walker-coldstart-") as tmp:
        walker_pyc = compile_bytecode(pkg_dir)  # as after `pip install`
        # The floor: interpreter start + `import walker.cli` (no command).
        env = dict(base_env, NUMBA_CACHE_DIR=str(Path(tmp) / "import-only"))
        floor = [
            timed_run([sys.executable, "-c", "import walker.cli"], env, tmp)[0]
            for _ in range(n_warm + 1)
        ]
        # One untimed command (own throwaway numba cache) so that the OS file cache holds
        # what the commands read (numba, scipy, the extension) for the first row as for the
        # others.
        env = dict(base_env, NUMBA_CACHE_DIR=str(Path(tmp) / "file-cache-warm-up"))
        timed_run(exe + command_for(scenes[0]), env, tmp)
        # First run after an editable install: no walker bytecode yet (deleted before each).
        no_bytecode = []
        for i in range(n_warm):
            delete_bytecode(pkg_dir)
            env = dict(base_env, NUMBA_CACHE_DIR=str(Path(tmp) / f"no-bytecode-{i}"))
            no_bytecode.append(timed_run(exe + command_for(scenes[0]), env, tmp)[0])
        # As after `pip install`: every module byte-compiled.
        walker_pyc = compile_bytecode(pkg_dir)
        for scene in scenes:
            sub = command_for(scene)
            cache = Path(tmp) / f"numba-{scene.stem}"
            cache.mkdir()
            env = dict(base_env, NUMBA_CACHE_DIR=str(cache))
            # the first cold run also fills `cache`, read by the warm runs
            c, rc_cold, status = timed_run(exe + sub, env, tmp)
            colds, warm, rc_warm = [c], [], 0
            for i in range(n_warm):
                fresh = dict(base_env, NUMBA_CACHE_DIR=str(Path(tmp) / f"c-{scene.stem}-{i}"))
                runs = [("cold", fresh), ("warm", env)]
                for kind, e in runs if i % 2 else runs[::-1]:
                    w, rc, _ = timed_run(exe + sub, e, tmp)
                    if kind == "cold":
                        colds.append(w)
                        rc_cold = rc_cold or rc
                    else:
                        warm.append(w)
                        rc_warm = rc_warm or rc
            cold = float(np.median(colds))
            numba_in = imports_numba(exe, sub, env, tmp)
            n_files = sum(1 for _ in cache.rglob("*.nbc"))
            # index files are named <module>.<function>-<line>.py<ver>.nbi
            compiled = sorted({f.name.split("-")[0] for f in cache.rglob("*.nbi")})
            rows.append(
                {
                    "scene": scene.name,
                    "command": "walker " + " ".join([sub[0], f"gaits/{scene.name}"]),
                    "cold": cold,
                    "cold_min": float(np.min(colds)),
                    "warm_min": float(np.min(warm)),
                    "warm_median": float(np.median(warm)),
                    "n_warm": n_warm,
                    "rc": f"{rc_cold}/{rc_warm}",
                    "status": status,
                    "cache_files": n_files,
                    "compiled": compiled,
                    "numba": numba_in,
                }
            )
            r = rows[-1]
            print(
                f"{r['command']}: cold {cold:.2f} s, warm {r['warm_median']:.2f} s "
                f"({cold / r['warm_median']:.2f}x), exit {r['rc']}, {status}, "
                f"numba imported: {numba_in}, {n_files} numba functions cached {compiled}",
                flush=True,
            )
    builds, n_c, cc, build_rc = time_build(n_builds, base_env) if n_builds else ([], 0, "", 0)
    t_all = time.perf_counter() - t_start
    load_after = os.getloadavg()[0]

    header = [
        "scene",
        "command",
        "cold_s",
        "cold_min_s",
        "warm_min_s",
        "warm_median_s",
        "n_warm",
        "cold_over_warm",
        "exit_cold_warm",
        "status",
        "numba_imported",
        "numba_cache_files",
        "numba_functions",
    ]
    csv_rows = [
        [
            r["scene"],
            r["command"],
            f"{r['cold']:.3f}",
            f"{r['cold_min']:.3f}",
            f"{r['warm_min']:.3f}",
            f"{r['warm_median']:.3f}",
            r["n_warm"],
            f"{r['cold'] / r['warm_median']:.2f}",
            r["rc"],
            r["status"],
            int(r["numba"]),
            r["cache_files"],
            ";".join(r["compiled"]),
        ]
        for r in rows
    ]
    csv_rows.append(
        [
            "(floor)",
            "python -c 'import walker.cli'",
            "",
            f"{np.min(floor):.3f}",
            f"{np.median(floor):.3f}",
            len(floor),
            "",
            "",
            "",
            "",
            "",
            "",
        ]
    )
    for k, b in enumerate(builds):
        csv_rows.append(
            [
                f"(build {k})",
                "python setup.py build_ext --inplace --force",
                f"{b:.3f}",
                "",
                "",
                "",
                "",
                build_rc if k == len(builds) - 1 else 0,
                "",
                "",
                "",
                "",
            ]
        )
    B.write_csv_atomic(B.OUT / "coldstart.csv", header, csv_rows)

    head = next((r for r in rows if r["scene"] == "kneed_hsu.toml"), rows[0])
    jit_rows = [r for r in rows if r["cache_files"]]
    jit_names = sorted({n for r in jit_rows for n in r["compiled"]})
    if jit_rows:
        jit_txt = (
            f"numba still compiles {', '.join(f'`{n}`' for n in jit_names)} at run time in "
            f"{len(jit_rows)} of {len(rows)} scene(s) ("
            + ", ".join(
                f"{r['scene']}: cold {r['cold'] - r['warm_median']:+.2f} s over warm"
                for r in jit_rows
            )
            + "); the other scenes compile nothing"
        )
    else:
        jit_txt = f"no numba function is compiled in any of the {len(rows)} scene(s)"
    with_numba = [r["scene"] for r in rows if r["numba"]]
    numba_txt = (
        f"numba is imported by {len(with_numba)} of {len(rows)} command(s) "
        f"({', '.join(with_numba)})"
        if with_numba
        else f"none of the {len(rows)} commands imports numba"
    )
    ratios = [r["cold"] / r["warm_median"] for r in rows]
    build_txt = (
        f" Install-time cost, separately: building the C extension (`python setup.py "
        f"build_ext --inplace --force`, {n_c} C files) takes {np.median(builds):.1f} s."
        if builds and build_rc == 0
        else ""
    )
    summary = (
        f"`{head['command']}` cold (new process, empty numba cache, bytecode as after "
        "`pip install`): "
        f"{head['cold']:.2f} s wall, {head['cold'] / head['warm_median']:.2f}x the warm run "
        f"({head['warm_median']:.2f} s; the interpreter + `import walker.cli` alone: "
        f"{np.median(floor):.2f} s); cold/warm {min(ratios):.2f}-{max(ratios):.2f} (median "
        f"{np.median(ratios):.2f}) over "
        f"{len(rows)} scene(s); {numba_txt}; {jit_txt}." + build_txt
    )
    how = (
        "every numba cache file under walker's package directory "
        f"({pkg_dir}) was deleted first ({deleted} files); "
        if deleted is not None
        else ""
    )
    pyc = (
        f"walker's modules byte-compiled as `pip install` leaves them ({walker_pyc} `.pyc` "
        "files by `python -m compileall`; `PYTHONDONTWRITEBYTECODE` removed from the "
        "commands' environment)"
    )
    how_measured = (
        "**cold** = a new process, an empty numba cache directory (a new one per cold run) "
        f"and {pyc}; the operating system's file cache warm, not a cold disk; **warm** = the "
        "same command again with the numba cache the first cold run filled. Cold and warm "
        f"runs alternate, {n_warm + 1} cold and {n_warm} warm per scene (the cold column is "
        "their median), wall time of the whole subprocess. After an editable install "
        "(`pip install -e .`, no bytecode written) the first command also compiles walker's "
        f"modules: `{head['command']}` with walker's `.pyc` files deleted before each run "
        f"took min {np.min(no_bytecode):.2f} s, median {np.median(no_bytecode):.2f} s "
        f"({len(no_bytecode)} runs), {np.median(no_bytecode) / head['warm_median']:.2f}x "
        "the warm run. The alternative compared against is the warm run of the same "
        "command (there is no other program doing walker's job from a cold start). The "
        f"machine was shared and loaded (1-minute load average {load_before:.1f} before, "
        f"{load_after:.1f} after, on {os.cpu_count()} logical CPUs), which spreads the "
        "single-run times; compare the medians."
    )
    md = [
        "# Cold start",
        "",
        f"<!-- command: {cmd} -->",
        f"<!-- summary: {summary} -->",
        f"<!-- how: {how_measured.replace('**', '')} -->",
        "",
        f"**How measured:** {how_measured}",
        "",
        f"Made by `{cmd}` in {t_all:.0f} s on {B.machine_line()}; "
        f"walker run as `{' '.join(Path(e).name for e in exe)}`; 1-minute load average "
        f"{load_before:.2f} before, {load_after:.2f} after.",
        "",
        summary,
        "",
        "walker's compiled core is the C extension `walker._hybrid`, built when the package "
        "is installed; walker has no numba functions (numba is only the optional extra for a "
        "user's own @njit system): "
        "the column *numba imported* comes from one more untimed run of each command under "
        "`python -X importtime`. The method below also shows, by name, any numba function a "
        "command still compiles at run time (last column).",
        "",
        "Each command runs in a new subprocess (wall time, from a scratch working "
        "directory). **Cold**: the first run with `NUMBA_CACHE_DIR` set to a new, empty "
        "directory (one per scene): with it set, numba reads and writes its cache only "
        "there and ignores the `__pycache__/*.nbi|*.nbc` files beside walker's sources "
        "(its `UserProvidedCacheLocator` is tried first), so any numba function the run "
        "called would be compiled there and counted in the last column; "
        + how
        + f"**warm**: the same command again, {n_warm} time(s) (min and median), alternating "
        "with the cold runs. Cold means a new process, an empty numba cache and bytecode as "
        "after `pip install`, not a cold disk: the operating system's file cache is warm "
        "(interpreter, libraries, walker's sources and extension were read by the runs "
        "before; one untimed command runs before the first row).",
        "",
        "| command | cold, median | cold, min | warm, min | warm, median | cold / warm | "
        "exit (cold/warm) | "
        "outcome | numba imported | numba functions compiled |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        md.append(
            f"| `{r['command']}` | {r['cold']:.2f} s | {r['cold_min']:.2f} s | "
            f"{r['warm_min']:.2f} s | "
            f"{r['warm_median']:.2f} s | {r['cold'] / r['warm_median']:.2f} | {r['rc']} | "
            f"{r['status']} | {'yes' if r['numba'] else 'no'} | {r['cache_files']}"
            + (f" ({', '.join(f'`{n}`' for n in r['compiled'])})" if r["compiled"] else "")
            + " |"
        )
    md += [
        "",
        f'The floor, `python -c "import walker.cli"` (interpreter start and the CLI module '
        "with numpy; scipy and the extension are imported by the commands, not by "
        f"it): min {np.min(floor):.2f} s, median {np.median(floor):.2f} s over "
        f"{len(floor)} runs. Exit status 1 is an expected outcome (e.g. a fall), 0 success "
        "(walker/cli/).",
        "",
    ]
    if builds:
        md += [
            "## Install time: building the extension",
            "",
            f"The {n_c} C files of `walker/_core` and `walker/_generated` compiled into "
            f"`walker._hybrid` by `python setup.py build_ext --inplace --force` (compiler "
            f"`{cc}`, one file at a time, as `pip install` does) in a temporary copy of the "
            "files `git ls-files` lists (work-tree versions), run "
            f"{len(builds)} time(s): "
            + (
                f"min {np.min(builds):.1f} s, median {np.median(builds):.1f} s wall."
                if build_rc == 0
                else f"FAILED (exit {build_rc})."
            )
            + " This is paid once, at `pip install` (which also creates its isolated build "
            "environment, not timed here), and is in neither column above.",
            "",
        ]
    B.publish("coldstart.md", md)


if __name__ == "__main__":
    main()
