"""Cold-start benchmark: the first ``walker`` command a new user runs after installing, against
the same command run again (warm), each in a fresh subprocess, wall time.

For every scene in gaits/: ``walker find SCENE`` when its ``[compute] task`` is
``fixed_point`` (and the model has strides), ``walker run SCENE`` otherwise.

Cold: numba's on-disk cache must be empty.  Every run gets ``NUMBA_CACHE_DIR`` set to a new
empty directory (one per scene); with it set, numba reads and writes compiled functions only
there and ignores the ``__pycache__/*.nbi|*.nbc`` files next to walker's sources (numba's
``UserProvidedCacheLocator`` comes first in its locator list), so the first run compiles
everything it calls and the following runs of that scene load from that directory.  This
disturbs nobody: the in-tree caches are neither read nor written.  With ``--delete-caches``
(the full run on a quiet machine) every ``*.nbi``/``*.nbc`` under walker's package directory
is deleted first as well, as on a fresh install.  Whatever walker compiles at install time
(a C extension) is already built in both cases; that is install time, not start-up.

Writes results/bench/coldstart.csv, coldstart.md and README.md.

Usage: python scripts/bench_coldstart.py [--quick] [--delete-caches] [--scenes a.toml,...]
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
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
    """The subcommand a user runs for this scene (walker/cli.py: find needs a walker)."""
    scene = load_scene(scene_path)
    if scene.compute.task == "fixed_point" and get_model(scene.model).is_walker:
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


def delete_numba_caches(pkg_dir: Path) -> int:
    n = 0
    for pattern in ("*.nbi", "*.nbc"):
        for f in pkg_dir.rglob(f"__pycache__/{pattern}"):
            f.unlink()
            n += 1
    return n


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="kneed_hsu only, one warm run")
    parser.add_argument(
        "--delete-caches",
        action="store_true",
        help="also delete every numba cache file under walker's package directory first "
        "(do not use while others run walker from this tree)",
    )
    parser.add_argument("--scenes", default=None, help="comma-separated scene file names")
    parser.add_argument("--warm", type=int, default=None, help="warm runs per scene")
    args = parser.parse_args(argv)
    cmd = B.command_line("bench_coldstart.py", argv)
    if args.scenes:
        scenes = [B.GAITS / s.strip() for s in args.scenes.split(",")]
    elif args.quick:
        scenes = [B.GAITS / "kneed_hsu.toml"]
    else:
        scenes = sorted(B.GAITS.glob("*.toml"))
    n_warm = args.warm or (1 if args.quick else 3)
    pkg_dir = Path(walker.__file__).resolve().parent
    deleted = delete_numba_caches(pkg_dir) if args.delete_caches else None
    exe = walker_exe()
    t_start = time.perf_counter()
    rows = []
    base_env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    with tempfile.TemporaryDirectory(prefix="walker-coldstart-") as tmp:
        # The floor: interpreter start + `import walker.cli` (no command, nothing compiled).
        env = dict(base_env, NUMBA_CACHE_DIR=str(Path(tmp) / "import-only"))
        floor = [
            timed_run([sys.executable, "-c", "import walker.cli"], env, tmp)[0]
            for _ in range(n_warm + 1)
        ]
        for scene in scenes:
            sub = command_for(scene)
            cache = Path(tmp) / f"numba-{scene.stem}"
            cache.mkdir()
            env = dict(base_env, NUMBA_CACHE_DIR=str(cache))
            cold, rc_cold, status = timed_run(exe + sub, env, tmp)
            warm = []
            rc_warm = 0
            for _ in range(n_warm):
                w, rc, _ = timed_run(exe + sub, env, tmp)
                warm.append(w)
                rc_warm = rc_warm or rc
            n_files = sum(1 for _ in cache.rglob("*.nbc"))
            rows.append(
                {
                    "scene": scene.name,
                    "command": "walker " + " ".join([sub[0], f"gaits/{scene.name}"]),
                    "cold": cold,
                    "warm_min": float(np.min(warm)),
                    "warm_median": float(np.median(warm)),
                    "n_warm": n_warm,
                    "rc": f"{rc_cold}/{rc_warm}",
                    "status": status,
                    "cache_files": n_files,
                }
            )
            r = rows[-1]
            print(
                f"{r['command']}: cold {cold:.2f} s, warm {r['warm_median']:.2f} s "
                f"({cold / r['warm_median']:.1f}x), exit {r['rc']}, {status}, "
                f"{n_files} cached functions",
                flush=True,
            )
    header = [
        "scene",
        "command",
        "cold_s",
        "warm_min_s",
        "warm_median_s",
        "n_warm",
        "cold_over_warm",
        "exit_cold_warm",
        "status",
        "numba_cache_files",
    ]
    B.write_csv_atomic(
        B.OUT / "coldstart.csv",
        header,
        [
            [
                r["scene"],
                r["command"],
                f"{r['cold']:.3f}",
                f"{r['warm_min']:.3f}",
                f"{r['warm_median']:.3f}",
                r["n_warm"],
                f"{r['cold'] / r['warm_median']:.2f}",
                r["rc"],
                r["status"],
                r["cache_files"],
            ]
            for r in rows
        ],
    )
    head = next((r for r in rows if r["scene"] == "kneed_hsu.toml"), rows[0])
    summary = (
        f"`{head['command']}` on a cold numba cache: {head['cold']:.1f} s wall, "
        f"{head['cold'] / head['warm_median']:.0f}x the warm run ({head['warm_median']:.2f} s; "
        f"the interpreter + `import walker.cli` alone: {np.median(floor):.2f} s)."
    )
    how = (
        "every numba cache file under walker's package directory "
        f"({pkg_dir}) was deleted first ({deleted} files), and "
        if deleted is not None
        else ""
    )
    md = [
        "# Cold start",
        "",
        f"<!-- command: {cmd} -->",
        f"<!-- summary: {summary} -->",
        "",
        f"Made by `{cmd}` in {time.perf_counter() - t_start:.0f} s on {B.machine_line()}; "
        f"walker run as `{' '.join(Path(e).name for e in exe)}`.",
        "",
        summary,
        "",
        "Each command runs in a new subprocess (wall time, from a scratch working "
        "directory). **Cold**: the first run with `NUMBA_CACHE_DIR` set to a new, empty "
        "directory (one per scene): with it set, numba reads and writes its cache only "
        "there and ignores the `__pycache__/*.nbi|*.nbc` files beside walker's sources "
        "(its `UserProvidedCacheLocator` is tried first), so the run compiles every "
        "function it calls, as on a fresh install, without touching anyone else's caches; "
        + how
        + f"**warm**: the same command again, {n_warm} time(s), loading from that "
        "directory (min and median). Each scene has its own cache directory, so every row "
        "is a first run (walker's integrator is compiled again in each). Anything walker "
        "compiles at install time (a C extension) is built before either run.",
        "",
        "| command | cold | warm, min | warm, median | cold / warm | exit (cold/warm) | "
        "outcome | functions cached |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        md.append(
            f"| `{r['command']}` | {r['cold']:.2f} s | {r['warm_min']:.2f} s | "
            f"{r['warm_median']:.2f} s | {r['cold'] / r['warm_median']:.1f} | {r['rc']} | "
            f"{r['status']} | {r['cache_files']} |"
        )
    md += [
        "",
        f'The floor, `python -c "import walker.cli"` (interpreter start and imports, '
        f"nothing compiled): min {np.min(floor):.2f} s, median {np.median(floor):.2f} s over "
        f"{len(floor)} runs. Exit status 1 is an expected outcome (e.g. a fall), 0 success "
        "(walker/cli.py).",
        "",
    ]
    B.write_atomic(B.OUT / "coldstart.md", "\n".join(md))
    B.update_readme()
    print("\n".join(md))


if __name__ == "__main__":
    main()
