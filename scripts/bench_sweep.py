"""Throughput of parameter sweeps on different executors, against a plain Python loop.

Two workloads on Goswami's compass gait (gaits/compass_goswami.toml, rtol 1e-10, atol 1e-12),
over a slope x hip-mass grid:

* outcome: one stride from the scene's section point at each grid point;
* fixed_point: the period-one gait at each point (Newton, warm-started along the grid's
  lines, walker.analysis.sweep_chains).

Each runs as a plain loop (the same per-point work, no chunks, no executor), through
``sweep(executor="serial")``, a process pool of 1 and of 2 workers (created by ``sweep``, so
its start-up is included), a process pool of 2 writing an HDF5 checkpoint, and a two-worker
``dask.distributed.LocalCluster`` (started and warmed before timing).  Reported: points per
second (best of ``--repeat`` runs) and the overhead per chunk,
``(workers * wall - loop) / n_chunks``: the worker time a chunk costs beyond the plain loop's
work (negative values are timing noise).

Writes ``results/sweep/throughput.csv`` and ``results/sweep/README.md``.

With ``--overhead``: the per-point overhead of a sweep beyond its strides, re-targeted maps
against rebuilt ones (``OVERHEAD_DOC`` below), into ``results/bench/sweep.md`` and
``results/bench/sweep.csv``.

Usage::

    python scripts/bench_sweep.py            # 10,000 outcome points, 1,000 fixed points
    python scripts/bench_sweep.py --quick    # 2,000 and 200: a minute or two
    python scripts/bench_sweep.py --overhead # per-point overhead (--overhead --quick: 3 rounds)
    python scripts/bench_sweep.py --dask     # dask LocalCluster x2 against --jobs 2
"""

from __future__ import annotations

import argparse
import csv
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "scripts"))
from _bench import GAITS, OUT, machine_line, publish, write_csv_atomic  # noqa: E402

OVERHEAD_DOC = """A sweep's per-point overhead beyond its strides, against the former paths.

Two workloads, each run serially (``executor="serial"``) so that nothing but the per-point
work is timed:

* outcome: Goswami's compass gait (gaits/compass_goswami.toml, its [compute] settings), one
  stride per point over a slope x hip-mass grid; the overhead per point is the sweep's time
  per point minus the time of one stride of a prepared map (the same map called in a loop);
* fixed_point: Hsu Chen's kneed walker (gaits/kneed_hsu.toml), the period-one gait, its
  multipliers and its gait measures at each point of a slope x hip-mass grid; reported per
  point.

Contenders, interleaved round-robin (min and median over rounds, wall and CPU time): the
sweep as it is (each point's map re-targeted from the base map's prepared run,
``StrideMap._retargeted``; fixed points started from the gaits behind them on their grid
line extrapolated, ``walker.analysis.sweep_chains.predict``; gait measures by
``walker.analysis.measures.map_cycle_measures``); the same sweep with each point's map rebuilt
(``_with_params_object``, its compiled run prepared on first use), which gives the same table
bit for bit (checked here); and for fixed points the former path: each search started from
its neighbour's gait and the measures by ``walker.analysis.measures.cycle_measures`` (a run set up
anew per point), what every point did before.

Writes results/bench/sweep.md and results/bench/sweep.csv.
"""
SCENE = REPO / "gaits" / "compass_goswami.toml"
OUT_DIR = REPO / "results" / "sweep"


def build_map():
    """The compass-gait stride map and its starting section point."""
    from walker import StrideMap, load_scene

    scene = load_scene(SCENE)
    stride_map = StrideMap("compass", scene.params, rtol=1e-10, atol=1e-12)
    z0 = stride_map.project(scene.state)
    stride_map(z0, jacobian=True)  # load the compiled kernels before any timing
    return stride_map, z0


def grid(n_points: int) -> list[str]:
    """A slope x hip-mass grid of about ``n_points`` points (10 hip masses)."""
    n_slope = max(1, round(n_points / 10))
    return [f"slope=0.02:0.07:{n_slope}", "mass_hip=8:12:10"]


def plain_loop(stride_map, ranges, kind, z0) -> float:
    """Wall time of the same per-point work in one Python loop (no chunks, no executor)."""
    from walker.analysis.fixedpoint import find_fixed_point
    from walker.analysis.sweep import grid_points

    names, points = grid_points(ranges)
    t0 = time.perf_counter()
    guess = z0
    for row in points:
        point_map = stride_map.with_params(**dict(zip(names, row.tolist(), strict=True)))
        if kind == "outcome":
            point_map(z0)
        else:
            fp = find_fixed_point(point_map, guess, tol=1e-10)
            guess = fp.section if fp.success else z0
    return time.perf_counter() - t0


def timed_sweep(stride_map, ranges, kind, z0, **kwargs) -> tuple[float, int, int]:
    """Wall time, chunk size and number of chunks of one sweep."""
    from walker.analysis.sweep import default_chunk_size, grid_points, sweep

    n = grid_points(ranges)[1].shape[0]
    t0 = time.perf_counter()
    sweep(stride_map, ranges, kind=kind, z0=z0, progress=False, **kwargs)
    wall = time.perf_counter() - t0
    chunk = default_chunk_size(n, kind)
    return wall, chunk, -(-n // chunk)


def run(n_outcome: int, n_fixed: int, with_dask: bool = True, repeat: int = 3) -> list[dict]:
    stride_map, z0 = build_map()
    rows: list[dict] = []
    client = cluster = None
    if with_dask:
        from distributed import Client, LocalCluster

        t0 = time.perf_counter()
        cluster = LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        )
        client = Client(cluster)
        from walker.analysis.sweep import sweep

        sweep(
            stride_map,
            ["slope=0.05:0.06:4"],
            kind="fixed_point",
            z0=z0,
            chunk_size=1,
            executor=client,
            progress=False,
        )  # workers load the kernels
        print(f"dask LocalCluster start + warm-up: {time.perf_counter() - t0:.2f} s")
    try:
        for kind, n in (("outcome", n_outcome), ("fixed_point", n_fixed)):
            ranges = grid(n)
            from walker.analysis.sweep import grid_points

            n_pts = grid_points(ranges)[1].shape[0]
            loop = min(plain_loop(stride_map, ranges, kind, z0) for _ in range(repeat))
            rows.append(_row(kind, "plain loop", 1, n_pts, 0, 0, loop, loop))
            print(f"{kind}: {n_pts} points, plain loop {loop:.2f} s")
            configs = [
                ("sweep serial", 1, {"executor": "serial"}),
                ("process pool", 1, {"jobs": 1}),
                ("process pool", 2, {"jobs": 2}),
            ]
            with tempfile.TemporaryDirectory() as tmp:
                configs.append(
                    ("process pool + HDF5", 2, {"jobs": 2, "out": Path(tmp) / f"{kind}.h5"})
                )
                if client is not None:
                    configs.append(("dask LocalCluster", 2, {"executor": client}))
                for label, workers, kwargs in configs:
                    runs = [
                        timed_sweep(stride_map, ranges, kind, z0, **_fresh(kwargs, r))
                        for r in range(repeat)
                    ]
                    wall, chunk, n_chunks = min(runs)
                    rows.append(_row(kind, label, workers, n_pts, chunk, n_chunks, wall, loop))
                    print(f"  {label:22s} x{workers}: {wall:.2f} s, {n_pts / wall:.0f} points/s")
    finally:
        if client is not None:
            client.close()
            cluster.close()
    return rows


def _fresh(kwargs: dict, r: int) -> dict:
    """``kwargs`` with a new checkpoint file per repeat (a reused one would skip all work)."""
    if "out" not in kwargs:
        return kwargs
    out = Path(kwargs["out"])
    return {**kwargs, "out": out.with_name(f"{out.stem}-{r}{out.suffix}")}


def _row(kind, label, workers, n, chunk, n_chunks, wall, loop) -> dict:
    overhead = (workers * wall - loop) / n_chunks * 1e3 if n_chunks else 0.0
    return {
        "kind": kind,
        "executor": label,
        "workers": workers,
        "n_points": n,
        "chunk_size": chunk,
        "n_chunks": n_chunks,
        "wall_s": round(wall, 4),
        "points_per_s": round(n / wall, 1),
        "speedup_vs_loop": round(loop / wall, 3),
        "overhead_per_chunk_ms": round(overhead, 2),
    }


def write_results(rows: list[dict], out_dir: Path, command: str) -> None:
    out_dir.mkdir(parents=True, exist_ok=True)
    with open(out_dir / "throughput.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    lines = [
        "# Sweep throughput",
        "",
        f"Written by `{command}` on {platform.platform()}, {os.cpu_count()} CPUs, Python "
        f"{platform.python_version()}, numpy {np.__version__}; "
        f"1-minute load average when done: {os.getloadavg()[0]:.2f} (other jobs on the "
        "machine inflate the multi-worker times).",
        "",
        "Compass gait (Goswami parameters), DOP853 at rtol 1e-10, atol 1e-12, slope x hip-mass "
        "grid. *outcome*: one stride per point; *fixed_point*: Newton with exact Jacobians, "
        "warm-started within a chunk. Process pools are created by `sweep` (start-up "
        "included); the dask LocalCluster (2 worker processes) is started and warmed before "
        "timing. Each time is the best of several runs. Overhead per chunk = (workers x wall - "
        "plain loop) / chunks.",
        "",
        "| kind | executor | workers | points | chunk | chunks | wall [s] | points/s | "
        "speed-up vs loop | overhead/chunk [ms] |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(
            f"| {r['kind']} | {r['executor']} | {r['workers']} | {r['n_points']} | "
            f"{r['chunk_size'] or '-'} | {r['n_chunks'] or '-'} | {r['wall_s']:.3f} | "
            f"{r['points_per_s']:.0f} | {r['speedup_vs_loop']:.2f} | "
            f"{r['overhead_per_chunk_ms'] if r['n_chunks'] else '-'} |"
        )
    (out_dir / "README.md").write_text("\n".join(lines) + "\n")


def _setup(scene_name):
    """A scene's stride map (its [compute] settings), prepared, and its section point."""
    from walker import StrideMap, load_scene

    scene = load_scene(GAITS / scene_name)
    stride_map = StrideMap.from_scene(scene)
    z0 = stride_map.project(scene.state)
    stride_map(z0, jacobian=True)
    return stride_map, z0


def _rebuilt(base):
    return base._with_params_object


def _former_measures(point_map, fp, out, i):
    """The gait measures of a sweep point as every point computed them before
    ``map_cycle_measures``: :func:`walker.analysis.measures.cycle_measures` (a run set up anew)."""
    from walker.analysis.measures import cycle_measures
    from walker.analysis.sweep_grid import MEASURE_COLUMNS
    from walker.simulation.stride import solver_settings

    measures = cycle_measures(
        point_map.model,
        point_map.params,
        fp.state,
        period=int(fp.period),
        settings=solver_settings(point_map),
    ).to_dict()
    for name in MEASURE_COLUMNS:
        out[name][i] = measures[name]


def _contender(name):
    """``(retargeter, predict, fill_measures)`` of a contender of :func:`overhead`."""
    import walker.analysis.sweep_chains as chains

    own = (chains._retargeter, chains.predict, chains.fill_measures)
    if name == "re-targeted":
        return own
    if name == "rebuilt":
        return (_rebuilt, own[1], own[2])
    return (own[0], lambda *args: None, _former_measures)  # "former path"


def overhead(quick: bool, command: str) -> None:
    """The per-point overhead tables (see OVERHEAD_DOC)."""
    import walker.analysis.sweep as sweep_module
    import walker.analysis.sweep_chains as chains
    from walker.analysis.sweep import sweep

    rounds = 3 if quick else 7
    own = _contender("re-targeted")
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
        contenders = ["re-targeted", "rebuilt"] + (["former path"] if kind == "fixed_point" else [])
        times = {name: [] for name in [*contenders, "stride"]}
        cpu = {name: [] for name in times}
        tables = {}
        for r in range(rounds):
            order = list(times)
            order = order[r % len(order) :] + order[: r % len(order)]
            for name in order:
                t0, c0 = time.perf_counter(), time.process_time()
                if name == "stride":
                    for _ in range(n):
                        stride_map(z0)
                else:
                    parts = _contender(name)
                    chains._retargeter, chains.predict, chains.fill_measures = parts
                    sweep_module._retargeter = parts[0]
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
                        chains._retargeter, chains.predict, chains.fill_measures = own
                        sweep_module._retargeter = own[0]
                times[name].append((time.perf_counter() - t0) / n)
                cpu[name].append((time.process_time() - c0) / n)
        now = tables["re-targeted"].columns
        stride = np.array(times["stride"])
        stride_cpu = np.array(cpu["stride"])
        for name in contenders:
            t = np.array(times[name])
            c = np.array(cpu[name])
            cols = tables[name].columns
            same = all(np.array_equal(now[k], cols[k], equal_nan=True) for k in now)
            both = (now["status"] == 0) & (cols["status"] == 0)
            differ = np.max(np.abs(now["section"][both] - cols["section"][both]), initial=0.0)
            rows.append(
                {
                    "kind": kind,
                    "scene": scene_name,
                    "points": n,
                    "maps": name,
                    "per_point_min_ms": t.min() * 1e3,
                    "per_point_median_ms": float(np.median(t)) * 1e3,
                    "cpu_per_point_median_ms": float(np.median(c)) * 1e3,
                    "stride_median_ms": float(np.median(stride)) * 1e3,
                    "overhead_median_ms": float(np.median(t - stride)) * 1e3,
                    "overhead_cpu_median_ms": float(np.median(c - stride_cpu)) * 1e3,
                    "same_table": same,
                    "max_section_difference": float(differ),
                    "completed": int(np.sum(cols["status"] == 0)),
                }
            )
    header = list(rows[0])
    write_csv_atomic(OUT / "sweep.csv", header, [[r[h] for h in header] for r in rows])
    out = {(r["kind"], r["maps"]): r for r in rows}
    o, f = out[("outcome", "re-targeted")], out[("fixed_point", "re-targeted")]
    ob, fb = out[("outcome", "rebuilt")], out[("fixed_point", "rebuilt")]
    ff = out[("fixed_point", "former path")]
    summary = (
        f"Sweep per point, serial, medians: compass outcome sweep (1 stride) "
        f"{o['overhead_median_ms']:.3f} ms of overhead beyond its stride "
        f"({o['stride_median_ms']:.3f} ms; CPU time {o['overhead_cpu_median_ms']:.3f} ms) with "
        f"re-targeted maps, against {ob['overhead_median_ms']:.3f} ms with maps rebuilt per "
        f"point (target <= 0.1 ms); kneed fixed-point sweep {f['per_point_median_ms']:.3f} ms "
        f"per point (CPU time {f['cpu_per_point_median_ms']:.3f} ms), against "
        f"{ff['per_point_median_ms']:.3f} ms by the former path (no extrapolated guesses, "
        f"measures by cycle_measures) and {fb['per_point_median_ms']:.3f} ms rebuilt (target "
        f"<= 0.6 ms); tables identical to rebuilt maps: {o['same_table'] and fb['same_table']}."
    )
    lines = [
        "# Sweep overhead per point",
        "",
        f"<!-- command: {command} -->",
        f"<!-- summary: {summary} -->",
        "",
        f"Made by `{command}` on {machine_line()}; 1-minute load average "
        f"{os.getloadavg()[0]:.2f} when done (a shared machine: absolute times are inflated by "
        "the load, the ratios, measured interleaved, much less; CPU time (process time) is "
        "less affected than wall time).",
        "",
        OVERHEAD_DOC.split("\n\n")[1].replace("\n", " "),
        "",
        "| kind | scene | points | path | per point min [ms] | per point median [ms] | "
        "CPU per point median [ms] | stride median [ms] | overhead median [ms] | "
        "overhead CPU median [ms] | same table | max section difference | completed |",
        "|---|---|---:|---|---:|---:|---:|---:|---:|---:|---|---:|---:|",
    ]
    for r in rows:
        lines.append(
            f"| {r['kind']} | {r['scene']} | {r['points']} | {r['maps']} | "
            f"{r['per_point_min_ms']:.3f} | {r['per_point_median_ms']:.3f} | "
            f"{r['cpu_per_point_median_ms']:.3f} | {r['stride_median_ms']:.3f} | "
            f"{r['overhead_median_ms']:.3f} | {r['overhead_cpu_median_ms']:.3f} | "
            f"{r['same_table']} | {r['max_section_difference']:.1e} | {r['completed']} |"
        )
    lines += [
        "",
        "Overhead = sweep time per point minus one stride of a prepared map, per round. The "
        "fixed-point rows' stride column is one plain stride at the scene's parameters, for "
        "scale (a gait search takes several strides with Jacobians). Same table: bit for bit "
        "the table of the sweep as it is (re-targeted); max section difference: the largest "
        "difference of a gait's section point between the two (the former path starts each "
        "Newton search elsewhere, so its gaits agree to the Newton tolerance, 1e-10).",
        "",
        summary,
        "",
    ]
    publish("sweep.md", lines)


DASK_DOC = """A 2-worker dask LocalCluster against ``--jobs 2`` on 2,000-point sweeps.

Two sweeps of 2,000 points each, in chunks of the default size (what ``walker sweep``
sends; a task is a run of whole grid lines for fixed points, and on dask several chunks of
at least ``walker.analysis.sweep.DASK_TASK_POINTS`` points for outcomes): Goswami's compass
(gaits/compass_goswami.toml), one stride per point over a slope x
hip-mass grid (outcome), and Hsu Chen's kneed walker (gaits/kneed_hsu.toml), the period-one
gait and its multipliers at each point of a slope x hip-mass grid (fixed_point).  Contenders,
interleaved round-robin (min and median wall time over rounds): ``jobs=2`` (two threads of
this process, what ``walker sweep --jobs 2`` runs) and a ``dask.distributed.LocalCluster``
of 2 worker processes with one thread each, started and warmed (one sweep of the same kind)
before any timing, through its ``Client`` (what ``walker sweep --scheduler`` runs).  Both
give the same table bit for bit (checked here).

Writes results/bench/sweep_dask.md and results/bench/sweep_dask.csv.
"""


def _workers_cpu(client) -> float:
    """The CPU time [s] the dask workers of ``client`` have used so far, summed."""
    return float(sum(client.run(time.process_time).values()))


def dask_vs_jobs(quick: bool, command: str) -> None:
    """The dask-against-threads table (see DASK_DOC)."""
    from distributed import Client, LocalCluster

    from walker.analysis.sweep import default_chunk_size, grid_points, sweep

    rounds = 3 if quick else 5
    cases = [
        ("outcome", "compass_goswami.toml", ["slope=0.03:0.07:200", "mass_hip=8:12:10"]),
        ("fixed_point", "kneed_hsu.toml", ["slope=0.045:0.055:100", "mass_hip=4.5:5.5:20"]),
    ]
    t0 = time.perf_counter()
    cluster = LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    client = Client(cluster)
    start_up = time.perf_counter() - t0
    rows = []
    try:
        for kind, scene_name, ranges in cases:
            stride_map, z0 = _setup(scene_name)
            n = grid_points(ranges)[1].shape[0]
            chunk = default_chunk_size(n, kind)
            run = dict(kind=kind, z0=z0, progress=False)
            sweep(stride_map, ranges[:1], executor=client, **run)  # workers load the kernels
            contenders = {
                "jobs=2 (threads)": {"jobs": 2},
                "dask LocalCluster x2": {"executor": client},
            }
            times = {name: [] for name in contenders}
            cpu = {name: [] for name in contenders}
            tables = {}
            for r in range(rounds):
                names = list(contenders)
                for name in names[r % 2 :] + names[: r % 2]:
                    w1, c1, t1 = _workers_cpu(client), time.process_time(), time.perf_counter()
                    tables[name] = sweep(stride_map, ranges, **run, **contenders[name])
                    times[name].append(time.perf_counter() - t1)
                    # CPU time of this process (threads, dask client and scheduler) and of
                    # the dask workers (idle while the threads run)
                    cpu[name].append(time.process_time() - c1 + _workers_cpu(client) - w1)
            a, b = tables.values()
            same = all(
                np.array_equal(a.columns[c], b.columns[c], equal_nan=True) for c in a.columns
            )
            base = np.array(times["jobs=2 (threads)"])
            base_cpu = np.array(cpu["jobs=2 (threads)"])
            for name, t in times.items():
                t = np.array(t)
                c = np.array(cpu[name])
                rows.append(
                    {
                        "kind": kind,
                        "scene": scene_name,
                        "points": n,
                        "chunk": chunk,
                        "chunks": -(-n // chunk),
                        "executor": name,
                        "wall_min_s": float(t.min()),
                        "wall_median_s": float(np.median(t)),
                        "points_per_s_median": n / float(np.median(t)),
                        "ratio_min": float(t.min() / base.min()),
                        "ratio_median": float(np.median(t) / np.median(base)),
                        "cpu_median_s": float(np.median(c)),
                        "cpu_ratio_median": float(np.median(c) / np.median(base_cpu)),
                        "same_table": same,
                    }
                )
    finally:
        client.close()
        cluster.close()
    header = list(rows[0])
    write_csv_atomic(OUT / "sweep_dask.csv", header, [[r[h] for h in header] for r in rows])
    dask_rows = [r for r in rows if r["executor"].startswith("dask")]
    summary = "Dask LocalCluster (2 workers) against --jobs 2 (2 threads), 2,000-point sweeps: " + (
        "; ".join(
            f"{r['kind']} {r['ratio_median']:.2f}x the time by medians "
            f"({r['ratio_min']:.2f}x by minima, {r['cpu_ratio_median']:.2f}x the CPU time)"
            for r in dask_rows
        )
        + f" (target <= 1.3x); identical tables: {all(r['same_table'] for r in rows)}."
    )
    lines = [
        "# Sweeps on a dask LocalCluster against threads",
        "",
        f"<!-- command: {command} -->",
        f"<!-- summary: {summary} -->",
        "",
        f"Made by `{command}` on {machine_line()}; 1-minute load average "
        f"{os.getloadavg()[0]:.2f} when done (a shared machine: absolute times are inflated by "
        "the load, the ratio, measured interleaved, much less). Cluster start-up "
        f"{start_up:.2f} s, not timed.",
        "",
        DASK_DOC.split("\n\n")[1].replace("\n", " "),
        "",
        "| kind | scene | points | chunk | chunks | executor | wall min [s] | wall median [s] | "
        "points/s (median) | time ratio min | time ratio median | CPU median [s] | "
        "CPU ratio median | same table |",
        "|---|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['kind']} | {r['scene']} | {r['points']} | {r['chunk']} | {r['chunks']} | "
            f"{r['executor']} | {r['wall_min_s']:.3f} | {r['wall_median_s']:.3f} | "
            f"{r['points_per_s_median']:.0f} | {r['ratio_min']:.2f} | {r['ratio_median']:.2f} | "
            f"{r['cpu_median_s']:.3f} | {r['cpu_ratio_median']:.2f} | {r['same_table']} |"
        )
    lines += [
        "",
        "Time ratio: the contender's wall time over that of `jobs=2`. CPU: the CPU time of "
        "this process (its threads, the dask client and scheduler) plus that of the dask "
        "workers during the sweep; on a machine loaded beyond its cores the wall time follows "
        "it.",
        "",
        summary,
        "",
    ]
    publish("sweep_dask.md", lines)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2,000 outcome and 200 fixed points")
    parser.add_argument("--outcome-points", type=int, default=None)
    parser.add_argument("--fixed-points", type=int, default=None)
    parser.add_argument("--no-dask", action="store_true", help="skip the LocalCluster runs")
    parser.add_argument("--out-dir", type=Path, default=OUT_DIR)
    parser.add_argument("--repeat", type=int, default=3, help="runs per case; the best is kept")
    parser.add_argument(
        "--overhead", action="store_true", help="the per-point overhead tables instead"
    )
    parser.add_argument(
        "--dask",
        action="store_true",
        help="a 2-worker dask LocalCluster against --jobs 2 (results/bench/sweep_dask.md)",
    )
    args = parser.parse_args(argv)
    if args.dask:
        command = "python scripts/bench_sweep.py " + " ".join(
            sys.argv[1:] if argv is None else argv
        )
        dask_vs_jobs(args.quick, command.strip())
        return
    if args.overhead:
        command = "python scripts/bench_sweep.py " + " ".join(
            sys.argv[1:] if argv is None else argv
        )
        overhead(args.quick, command.strip())
        return
    n_outcome = args.outcome_points or (2_000 if args.quick else 10_000)
    n_fixed = args.fixed_points or (200 if args.quick else 1_000)
    rows = run(n_outcome, n_fixed, with_dask=not args.no_dask, repeat=args.repeat)
    command = "python scripts/bench_sweep.py " + " ".join(sys.argv[1:] if argv is None else argv)
    write_results(rows, args.out_dir, command.strip())
    print(f"wrote {args.out_dir / 'throughput.csv'} and README.md")


if __name__ == "__main__":
    main()
