"""Throughput of walks on per-step terrain (walker/simulation/terrain.py, walker/_core/terrain.c):
the compiled Monte-Carlo batch ``StrideMap.ensemble`` against the plane's fastest path.

For the compass gait (gaits/compass_goswami.toml) and the kneed walker (gaits/kneed_hsu.toml)
at rtol = atol = 1e-9, from the gait's fixed point, ``RUNS`` walks of ``STEPS`` strides on
random slopes (std 0.0005 rad about the scene's: nearly every walk completes, so every
contender integrates the same strides), timed interleaved round-robin (scripts/_bench.py):

* ``ensemble, 2 threads`` and ``ensemble, 1 thread``: ``P.ensemble(z, terrains, threads=...)``;
* ``ensemble, plane rows``: the same batch on rows equal to the scene's plane (the terrain
  path's bookkeeping: the stride hook, the terrain guards' plane branch);
* ``plane map, 1 thread`` (the strongest alternative on the plane): ``P(z, n_strides=STEPS)``
  for each run, walker's compiled stride map in one call per walk;
* ``draws``: ``Terrain("random", ...).steps`` for every run (the terrain draws).

Strides per second are the completed strides over the wall time (median of the rounds), and
over the CPU time of this process (all threads; the steadier measure on a shared machine).
Writes results/bench/terrain.csv, terrain.md and README.md.

Usage: python scripts/bench_terrain.py [--quick]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _bench as B  # noqa: E402

from walker import StrideMap, load_scene  # noqa: E402
from walker.analysis.fixedpoint import find_fixed_point  # noqa: E402
from walker.simulation.terrain import Terrain  # noqa: E402

SCENES = (("compass", "gaits/compass_goswami.toml"), ("kneed", "gaits/kneed_hsu.toml"))
STD = 0.0005


def _case(path, runs, steps):
    scene = load_scene(path)
    P = StrideMap(scene.walker_model, scene.params, rtol=1e-9, atol=1e-9)
    z = find_fixed_point(P, P.project(scene.state)).section
    rough = Terrain("random", slope_mean=scene.params.slope, slope_std=STD, seed=1)
    rng = np.random.default_rng(1)
    terrains = np.stack([rough.steps(steps, rng=rng) for _ in range(runs)])
    plane = np.tile([scene.params.slope, 0.0], (runs, steps, 1))

    def draws():
        g = np.random.default_rng(2)
        return [rough.steps(steps, rng=g) for _ in range(runs)]

    fns = {
        "ensemble, 2 threads": lambda: P.ensemble(z, terrains, threads=2),
        "ensemble, 1 thread": lambda: P.ensemble(z, terrains, threads=1),
        "ensemble, plane rows": lambda: P.ensemble(z, plane, threads=1),
        "plane map, 1 thread": lambda: [P(z, n_strides=steps) for _ in range(runs)],
        "draws": draws,
    }
    done = int(P.ensemble(z, terrains)[0].sum())
    c0, t0 = time.process_time(), time.perf_counter()
    P.ensemble(z, terrains, threads=2)
    cpu_ratio = (time.process_time() - c0) / (time.perf_counter() - t0)
    return fns, done, runs * steps, cpu_ratio


def _cpu_seconds(fn, reps: int) -> float:
    """Median CPU time of this process (all its threads) per call of ``fn``: on a shared
    machine the steadier measure of the work done."""
    out = []
    for _ in range(reps):
        c = time.process_time()
        fn()
        out.append(time.process_time() - c)
    return float(np.median(out))


def main(argv=None) -> int:
    quick, command = B.quick_options(
        "bench_terrain.py", __doc__, "fewer walks and rounds (a smoke run)", argv
    )
    runs, steps, reps = (20, 50, 3) if quick else (100, 200, 7)
    rows, summary = [], []
    lines = [
        "# Walks on per-step terrain: the compiled Monte-Carlo batch",
        "",
        f"<!-- command: {command} -->",
        "",
        f"Machine: {B.machine_line()}. {runs} walks x {steps} strides, random slopes "
        f"(std {STD} rad), rtol = atol = 1e-9, from the gait's fixed point; wall time per "
        f"batch, {reps} interleaved rounds.",
        "",
        "| model | contender | median | min | strides/s (median) | strides per CPU s |",
        "|---|---|---|---|---|---|",
    ]
    for name, path in SCENES:
        fns, done, total, cpu_ratio = _case(path, runs, steps)
        times = B.round_robin(fns, reps, batch_seconds=0.05)
        cpu = {label: _cpu_seconds(fn, reps) for label, fn in fns.items()}
        for label, t in times.items():
            med, best = float(np.median(t)), float(np.min(t))
            rate = done / med if label != "draws" else float("nan")
            cpu_rate = done / cpu[label] if label != "draws" else float("nan")
            rows.append([name, label, med, best, rate, cpu_rate])
            shown = f"{rate:,.0f} | {cpu_rate:,.0f}" if np.isfinite(rate) else "— | —"
            lines.append(f"| {name} | {label} | {B.fmt_time(med)} | {B.fmt_time(best)} | {shown} |")
        med = {label: float(np.median(t)) for label, t in times.items()}
        plane_speed = med["plane map, 1 thread"] / med["ensemble, plane rows"]
        draws = 100 * med["draws"] / med["ensemble, 1 thread"]
        summary.append(
            f"{name}: {done / med['ensemble, 2 threads']:,.0f} strides/s on 2 threads "
            f"({done} of {total} strides completed; CPU/wall {cpu_ratio:.2f}), the terrain "
            f"path on plane rows {plane_speed:.2f}x the speed of the plane map, draws "
            f"{draws:.2f}% of the 1-thread batch"
        )
    lines += ["", "<!-- summary: " + "; ".join(summary) + ". -->", ""]
    lines += ["; ".join(summary) + "."]
    B.write_csv_atomic(
        B.OUT / "terrain.csv",
        ["model", "contender", "median_s", "min_s", "strides_per_s", "strides_per_cpu_s"],
        rows,
    )
    B.publish("terrain.md", lines)
    return 0


if __name__ == "__main__":
    sys.exit(main())
