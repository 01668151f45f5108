"""The gallery figure of issue 29: mean first-passage time against terrain roughness for the
rimless wheel and the compass gait, results/gallery/mfpt_roughness.png (and its numbers in
results/gallery/mfpt_roughness.csv).

Monte Carlo (walker.analysis.mfpt.monte_carlo, seeded) for both walkers, the refined Markov chain
(walker.analysis.markov.markov_chain, its expected steps from the start state) for the rimless wheel
and, with --compass-markov, for the compass gait (minutes per point).

Usage: python scripts/gallery_mfpt.py [--runs N] [--compass-markov]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _bench import ROOT, savefig_atomic, write_csv_atomic  # noqa: E402

from walker import StrideMap, load_scene  # noqa: E402
from walker.analysis.markov import markov_chain  # noqa: E402
from walker.analysis.mfpt import gait_on_mean_slope, monte_carlo  # noqa: E402
from walker.plotting.terrain import plot_mfpt_roughness  # noqa: E402

OUT = ROOT / "results" / "gallery"
CASES = {
    "rimless wheel": ("rimless_wheel.toml", (0.01, 0.0125, 0.015, 0.0175, 0.02, 0.025), True),
    "compass gait": ("compass_goswami.toml", (0.003, 0.004, 0.005, 0.006, 0.008), False),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=2000, help="runs per point (default 2000)")
    parser.add_argument(
        "--compass-markov", action="store_true", help="also the compass chain (slow)"
    )
    args = parser.parse_args()
    curves, rows = {}, []
    for label, (file, stds, markov) in CASES.items():
        scene = load_scene(ROOT / "gaits" / file)
        P = StrideMap.from_scene(scene).with_tolerance(1e-10, 1e-10)
        P, z0 = gait_on_mean_slope(P, scene.state, scene.params.slope)
        markov = markov or args.compass_markov
        c = {"std": [], "mfpt": [], "stderr": [], "markov": []}
        for std in stds:
            r = monte_carlo(P, z0, slope_std=std, runs=args.runs, seed=1, jobs=2)
            mk = markov_chain(P, z0, slope_std=std, jobs=2) if markov else None
            c["std"].append(std)
            c["mfpt"].append(r.mfpt)
            c["stderr"].append(r.mfpt_stderr)
            c["markov"].append(np.nan if mk is None else mk["mfpt_start"])
            rows.append(
                [
                    label,
                    std,
                    r.mfpt,
                    r.mfpt_stderr,
                    r.runs,
                    r.failed,
                    "" if mk is None else mk["mfpt_start"],
                    "" if mk is None else mk["converged"],
                ]
            )
            print(rows[-1], flush=True)
        if not markov:
            del c["markov"]
        curves[label] = c
    fig = plot_mfpt_roughness(curves)
    fig.axes[0].set_title("MFPT on random slopes (slope std per step), mean slope the scene's")
    savefig_atomic(fig, OUT / "mfpt_roughness.png", dpi=120)
    write_csv_atomic(
        OUT / "mfpt_roughness.csv",
        [
            "walker",
            "slope_std_rad",
            "mfpt",
            "mfpt_stderr",
            "runs",
            "failed",
            "markov_mfpt_start",
            "markov_converged",
        ],
        rows,
    )


if __name__ == "__main__":
    main()
