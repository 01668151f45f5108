"""Per-point overhead of a sweep beyond its strides, re-targeted maps against rebuilt ones.

Two workloads, each run serially (``executor="serial"``) so that nothing but the per-point
work is timed:

* outcome: Goswami's compass gait (gaits/compass_goswami.toml, its [compute] settings), one
  stride per point over a slope x hip-mass grid; the overhead per point is the sweep's time
  per point minus the time of one stride of a prepared map (the same map called in a loop);
* fixed_point: Hsu Chen's kneed walker (gaits/kneed_hsu.toml), the period-one gait and its
  multipliers at each point of a slope x hip-mass grid; reported per point.

Contenders, interleaved round-robin (min and median over rounds): the sweep as it is (each
point's map re-targeted from the base map's prepared run, ``StrideMap._retargeted``) and the
strongest alternative, the same sweep with each point's map rebuilt (``_with_params_object``,
its compiled run prepared on first use: what every sweep point did before).  Both give the
same table bit for bit (checked here).

Writes results/bench/sweep.md and results/bench/sweep.csv.

Usage::

    python scripts/bench_sweep_overhead.py            # 400 outcome, 100 fixed points, 7 rounds
    python scripts/bench_sweep_overhead.py --quick    # 3 rounds
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _bench import GAITS, OUT, machine_line, publish, quick_options, write_csv_atomic  # noqa: E402


def _setup(scene_name):
    from walker import StrideMap, load_scene

    scene = load_scene(GAITS / scene_name)
    stride_map = StrideMap.from_scene(scene)
    z0 = stride_map.project(scene.state)
    stride_map(z0, jacobian=True)
    return stride_map, z0


def _rebuilt(base):
    return base._with_params_object


def main(argv=None) -> None:
    quick, command = quick_options(
        "bench_sweep_overhead.py", __doc__, "3 rounds instead of 7", argv
    )
    import walker.sweep as sweep_module
    import walker.sweep_chains as chains
    from walker.sweep import sweep

    rounds = 3 if quick else 7
    own = chains._retargeter
    cases = [
        ("outcome", "compass_goswami.toml", ["slope=0.03:0.07:40", "mass_hip=8:12:10"]),
        ("fixed_point", "kneed_hsu.toml", ["slope=0.045:0.055:20", "mass_hip=4.5:5.5:5"]),
    ]
    rows = []
    for kind, scene_name, ranges in cases:
        stride_map, z0 = _setup(scene_name)
        n = 1
        for text in ranges:
            n *= int(text.rsplit(":", 1)[1])
        times = {"re-targeted": [], "rebuilt": [], "stride": []}
        tables = {}
        for r in range(rounds):
            order = ["re-targeted", "rebuilt", "stride"]
            order = order[r % 3 :] + order[: r % 3]
            for name in order:
                t0 = time.perf_counter()
                if name == "stride":
                    for _ in range(n):
                        stride_map(z0)
                else:
                    chains._retargeter = own if name == "re-targeted" else _rebuilt
                    sweep_module._retargeter = chains._retargeter
                    try:
                        tables[name] = sweep(
                            stride_map,
                            ranges,
                            kind=kind,
                            z0=z0,
                            executor="serial",
                            progress=False,
                        )
                    finally:
                        chains._retargeter = sweep_module._retargeter = own
                times[name].append((time.perf_counter() - t0) / n)
        same = all(
            np.array_equal(
                tables["re-targeted"].columns[c], tables["rebuilt"].columns[c], equal_nan=True
            )
            for c in tables["rebuilt"].columns
        )
        stride = np.array(times["stride"])
        for name in ("re-targeted", "rebuilt"):
            t = np.array(times[name])
            rows.append(
                {
                    "kind": kind,
                    "scene": scene_name,
                    "points": n,
                    "maps": name,
                    "per_point_min_ms": t.min() * 1e3,
                    "per_point_median_ms": float(np.median(t)) * 1e3,
                    "stride_median_ms": float(np.median(stride)) * 1e3,
                    "overhead_median_ms": float(np.median(t - stride)) * 1e3,
                    "same_table": same,
                    "completed": int(np.sum(tables[name].columns["status"] == 0)),
                }
            )
    header = list(rows[0])
    write_csv_atomic(OUT / "sweep.csv", header, [[r[h] for h in header] for r in rows])
    out = {(r["kind"], r["maps"]): r for r in rows}
    o, f = out[("outcome", "re-targeted")], out[("fixed_point", "re-targeted")]
    ob, fb = out[("outcome", "rebuilt")], out[("fixed_point", "rebuilt")]
    summary = (
        f"Sweep per point, serial, medians: compass outcome sweep (1 stride) "
        f"{o['overhead_median_ms']:.3f} ms of overhead beyond its stride "
        f"({o['stride_median_ms']:.3f} ms) with re-targeted maps, against "
        f"{ob['overhead_median_ms']:.3f} ms with maps rebuilt per point (target <= 0.1 ms); "
        f"kneed fixed-point sweep {f['per_point_median_ms']:.3f} ms per point, against "
        f"{fb['per_point_median_ms']:.3f} ms rebuilt (target <= 0.6 ms); identical tables: "
        f"{o['same_table'] and f['same_table']}."
    )
    lines = [
        "# Sweep overhead per point",
        "",
        f"<!-- command: {command} -->",
        f"<!-- summary: {summary} -->",
        "",
        f"Made by `{command}` on {machine_line()}.",
        "",
        __doc__.split("\n\n")[1].replace("\n", " "),
        "",
        "| kind | scene | points | maps | per point min [ms] | per point median [ms] | "
        "stride median [ms] | overhead median [ms] | same table | completed |",
        "|---|---|---:|---|---:|---:|---:|---:|---|---:|",
    ]
    for r in rows:
        lines.append(
            f"| {r['kind']} | {r['scene']} | {r['points']} | {r['maps']} | "
            f"{r['per_point_min_ms']:.3f} | {r['per_point_median_ms']:.3f} | "
            f"{r['stride_median_ms']:.3f} | {r['overhead_median_ms']:.3f} | {r['same_table']} "
            f"| {r['completed']} |"
        )
    lines += [
        "",
        "Overhead = sweep time per point minus one stride of a prepared map, per round. The "
        "fixed-point rows' stride column is one plain stride at the scene's parameters, for "
        "scale (a gait search takes several strides with Jacobians).",
        "",
        summary,
        "",
    ]
    publish("sweep.md", lines)


if __name__ == "__main__":
    main()
