"""Time ``walker plot`` on stored results: wall time and CPU time (user + system) of the whole
command, each contender run in turn in one loop (so the machine's load hits all alike).

Contenders: ``baseline`` (another checkout of walker, given by ``--baseline DIR``: the
strongest alternative is the code before the change), ``all`` (this tree, every figure of
the file) and ``one`` (this tree, ``--figure`` with the one figure named per file below).
The median over ``--repeat`` runs is written to ``results/bench/plot_times.md``, with the
load average at the start, since on a shared machine the wall time follows the load and the
CPU time does not.

Usage: python scripts/bench_plot.py [--baseline DIR] [--repeat N]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FILES = {  # file in results/gallery -> the one figure of contender "one"
    "kneed_walk.h5": "energy",
    "simplest_branch.h5": "bifurcation",
}


def _run(tree: Path, args: list[str]) -> tuple[float, float]:
    """(wall, cpu) seconds of ``python -m walker plot ARGS`` run in ``tree``."""
    env = dict(os.environ, PYTHONPATH=str(tree), MPLBACKEND="Agg")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "walker", "plot", *args],
        cwd=tree,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    if done.returncode != 0:
        raise RuntimeError(f"walker plot {' '.join(args)} in {tree}: {done.stderr.strip()}")
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", type=Path, help="another walker checkout to compare")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    load = os.getloadavg()[0]
    rows = []
    for name, one in FILES.items():
        path = str(ROOT / "results" / "gallery" / name)
        contenders = {"all": (ROOT, []), "one": (ROOT, ["--figure", one])}
        if args.baseline is not None:
            contenders = {"baseline": (args.baseline.resolve(), []), **contenders}
        times: dict[str, list[tuple[float, float]]] = {k: [] for k in contenders}
        for _ in range(args.repeat):
            for label, (tree, extra) in contenders.items():
                with tempfile.TemporaryDirectory() as out:
                    times[label].append(_run(tree, [path, "--out", out, *extra]))
        for label, samples in times.items():
            wall = statistics.median(s[0] for s in samples)
            cpu = statistics.median(s[1] for s in samples)
            what = "every figure" if label != "one" else f"--figure {one}"
            rows.append(f"| {name} | {label} ({what}) | {wall:.2f} | {cpu:.2f} |")
    text = "\n".join(
        [
            "# `walker plot` times (scripts/bench_plot.py)",
            "",
            f"Median of {args.repeat} runs, contenders interleaved; load average at the start "
            f"{load:.1f} on {os.cpu_count()} cores.  baseline: the code before the change.",
            "",
            "| file | contender | wall [s] | CPU user+sys [s] |",
            "|---|---|---|---|",
            *rows,
            "",
        ]
    )
    out = ROOT / "results" / "bench" / "plot_times.md"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    print(text)


if __name__ == "__main__":
    main()
