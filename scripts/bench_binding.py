"""Per-call cost of walker's binding into the compiled core (issue 32 item 6: the keyword
interface), on the compass gait (gaits/compass_goswami.toml, its reference fixed point).

Rows, each the min and median over interleaved repetitions of the per-call time in µs:

* ``solve, one step``: ``PreparedRun.map`` with a step budget of one (the run stops after
  its first step attempt): the binding's argument parsing and result record, the Python
  wrapper, and one DOP853 step;
* ``solve, one stride``: ``PreparedRun.map`` over a whole stride;
* ``StrideMap call``: ``StrideMap.__call__`` (one ``PreparedMap.map`` call, settings parsed
  once);
* ``PreparedMap, re-targeted``: a sweep point's set-up, ``StrideMap._retargeted`` and its
  first prepared run (the section settings parsed into a new ``PreparedMap``);
* ``basin_points, 1 point``: one basin row in one compiled call.

The same script ran on the tree before and after the change gives the binding's cost as a
difference of two runs on one machine (stated in the table's note); nothing here is
asserted.

Writes results/bench/binding.csv and binding.md (``--out DIR`` elsewhere).

Usage: python scripts/bench_binding.py [--quick] [--out DIR]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # this tree's walker, not an installed one

from walker import load_scene  # noqa: E402
from walker.integrate import PreparedRun  # noqa: E402
from walker.stride import StrideMap  # noqa: E402


def _per_call(fn, number: int) -> float:
    t0 = time.perf_counter()
    for _ in range(number):
        fn()
    return (time.perf_counter() - t0) / number * 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", type=Path, default=ROOT / "results" / "bench")
    args = ap.parse_args()
    rounds = 5 if args.quick else 15

    scene = load_scene(ROOT / "gaits" / "compass_goswami.toml")
    smap = StrideMap.from_scene(scene)
    x0 = np.ascontiguousarray(scene.reference["state"], dtype=np.float64)
    run, p, _ = smap._prepared(1)
    z = np.ascontiguousarray(smap.model.project(x0, p), dtype=np.float64)
    assert smap(z).status == 0
    one_step = PreparedRun(run.system, max_steps=1)
    params = smap.params
    basin = smap.basin_batch()
    z_rows = z[None, :].copy()

    def retargeted():
        smap._retargeted(params)._prepared(1)

    cases = {
        "solve, one step": (lambda: one_step.map(x0, p, 0, 10.0, 1, False), 2000),
        "solve, one stride": (lambda: run.map(x0, p, 0, 10.0, 1, False), 300),
        "StrideMap call": (lambda: smap(z), 300),
        "PreparedMap, re-targeted": (retargeted, 300),
        "basin_points, 1 point": (lambda: basin(z_rows, z, 1e-8, 2), 300),
    }
    times: dict[str, list[float]] = {k: [] for k in cases}
    for r in range(rounds):
        order = list(cases)[r % len(cases) :] + list(cases)[: r % len(cases)]
        for name in order:
            fn, number = cases[name]
            times[name].append(_per_call(fn, number))

    load = os.getloadavg()[0]
    rows = [(k, min(v), statistics.median(v)) for k, v in times.items()]
    csv = "case,min_us,median_us\n" + "".join(f"{k},{a:.3f},{b:.3f}\n" for k, a, b in rows)
    md = [
        "# Binding call cost (compass, gaits/compass_goswami.toml)",
        "",
        f"Per call, min and median of {rounds} interleaved rounds; load average {load:.2f}"
        " on a machine shared by other sessions. Measured by scripts/bench_binding.py.",
        "",
        "| case | min [µs] | median [µs] |",
        "|---|---:|---:|",
        *(f"| {k} | {a:.2f} | {b:.2f} |" for k, a, b in rows),
        "",
    ]
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "binding.csv").write_text(csv, encoding="utf-8")
    (args.out / "binding.md").write_text("\n".join(md), encoding="utf-8")
    print("\n".join(md))


if __name__ == "__main__":
    main()
