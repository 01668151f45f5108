"""The Markov-chain mean first-passage time (walker/analysis/markov.py) against Monte Carlo
(walker/analysis/mfpt.py) for the rimless wheel and the compass gait at several roughnesses: each
chain's refinement levels and the Monte-Carlo estimate with its standard error.  Writes
results/bench/markov_mfpt.md (rewritten atomically after each case).

    python scripts/markov_vs_mc.py [--runs-rimless 6000] [--runs-compass 8000]

The Monte Carlo counts the steps completed before the first failure from the gait of the
mean slope; the chain's ``mfpt_start`` is the same quantity (its ``mfpt``, ``1 / (1 -
lambda_2)``, is the metastable rate's, without the start transient).  ``tail`` is the
Monte-Carlo estimate of the latter: the mean steps to failure (the failing one counted) of
the runs still walking at step 10.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from walker import StrideMap, load_scene  # noqa: E402
from walker.analysis.markov import markov_chain  # noqa: E402
from walker.analysis.mfpt import gait_on_mean_slope, monte_carlo  # noqa: E402

CASES = (
    ("rimless wheel", "gaits/rimless_wheel.toml", 0.08, (0.01, 0.015, 0.02)),
    ("compass gait", "gaits/compass_goswami.toml", None, (0.004, 0.005, 0.006, 0.008)),
)


def write(path: Path, lines: list[str]) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, path)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs-rimless", type=int, default=6000)
    parser.add_argument("--runs-compass", type=int, default=8000)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--only", choices=("rimless", "compass"), help="one model only")
    parser.add_argument("--stds", type=str, default=None, help="comma-separated slope stds")
    parser.add_argument("--out", type=Path, default=ROOT / "results" / "bench" / "markov_mfpt.md")
    args = parser.parse_args()
    lines = [
        "# Markov-chain MFPT against Monte Carlo",
        "",
        "`python scripts/markov_vs_mc.py` (walker/analysis/markov.py defaults: refinement by",
        "1.5x slope nodes and mesh points per node until both estimates move < 2 %). Steps",
        "completed before the first failure from the gait of the mean slope; `z` = (chain",
        "start - MC) / MC standard error. `tail`: MC mean steps to failure of the runs alive at",
        "step 10,",
        "to compare with the chain's `1/(1-lambda_2)`.",
        "",
        "| model | slope std [rad] | MC steps | runs | MC tail | chain levels"
        " (slope nodes x mesh/node: start, 1/(1-lambda_2)) | last change | chain start | z |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, path, mean, stds in CASES:
        if args.only and args.only not in path:
            continue
        scene = load_scene(ROOT / path)
        P = StrideMap.from_scene(scene)
        if "rimless" in path:
            P = P.with_tolerance(1e-10, 1e-10)
        P, z0 = gait_on_mean_slope(P, scene.state, scene.params.slope if mean is None else mean)
        runs = args.runs_rimless if "rimless" in path else args.runs_compass
        if args.stds:
            stds = [float(x) for x in args.stds.split(",")]
        for std in stds:
            t = time.perf_counter()
            mc = monte_carlo(P, z0, slope_std=std, runs=runs, seed=args.seed, jobs=args.jobs)
            alive = mc.steps[mc.steps >= 10] - 10
            tail = (alive.sum() + alive.size) / alive.size
            mk = markov_chain(P, z0, slope_std=std, jobs=args.jobs, seed=args.seed)
            levels = "; ".join(
                f"{lv['n_slopes']}x{lv['n_mesh']}: {lv['mfpt_start']:.2f}, {lv['mfpt']:.2f}"
                for lv in mk["levels"]
            )
            z = (mk["mfpt_start"] - mc.mfpt) / mc.mfpt_stderr
            lines.append(
                f"| {name} | {std:g} | {mc.mfpt:.2f} +- {mc.mfpt_stderr:.2f} | {runs} | "
                f"{tail:.2f} +- {tail / math.sqrt(alive.size):.2f} | {levels} | "
                f"{100 * mk['change']:.1f} %{'' if mk['converged'] else ' (not converged)'} | "
                f"{mk['mfpt_start']:.2f} | {z:+.1f} |"
            )
            print(lines[-1], f"{time.perf_counter() - t:.0f} s", flush=True)
            write(args.out, lines)


if __name__ == "__main__":
    main()
