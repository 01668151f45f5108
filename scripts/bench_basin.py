"""Basin-of-attraction benchmark: the compass gait (gaits/compass_goswami.toml), n x n grids on
the slice of section coordinates (q_stance, qd_stance) around the fixed point, up to 20 strides
per point, through walker's public API (``walker.analysis.basin.basin_map``).

Two grids, each ``axes 0,1`` with half-width ``span x max(|value|, 0.1)`` as ``walker basin
--span`` draws them:

* ``default``: span 0.5, ``walker basin``'s default slice; most points fall within the first
  strides (about 3.3 strides integrated per point, 2.4 of them completed);
* ``walking``: span 0.05, close around the fixed point, chosen so that most points (>= 80%)
  converge or are still walking after 20 strides (about 19 strides per point): the heavier
  grid, where the strides themselves and not the per-point bookkeeping dominate.

Measured for each grid:

1. ``basin_map`` six ways, interleaved round-robin (the starting contender rotated every
   round; wall time, min and median, and the CPU time of this process and the pool's
   workers): ``jobs=2`` (``executor=None``: 2 threads of this process,
   the compiled strides release the GIL; this is what a user gets by default, ``jobs =
   os.cpu_count()``, on a 2-CPU machine), ``executor=<a 2-worker process pool>`` (fork-server
   workers started and warmed once before any timing; the strongest alternative: the section
   map and grid rows are pickled to the workers) and ``executor="serial"`` (inline, this
   process).  All three must give the same outcome and stride grids.  Fourth, ``jobs=2``
   on the same map at rtol 1e-9 (``StrideMap.with_tolerance``, what ``walker basin --rtol
   1e-9`` runs; the fixed point at the scene's tolerance): its time, and the grid points
   whose outcome differs from the scene's tolerance.  Fifth and sixth, the early
   classification (``converge_radius="auto"``, ``walker basin``'s default, docs/basins.md)
   at the scene's rtol and at 1e-9: CPU per point, its ratio to the full runs' CPU
   (``jobs=2``, the tolerance alone) in the same round, and whether every outcome equals
   the full 20-stride run's at the scene's rtol except undecided -> converged;
2. the ``walker basin`` command line, end to end in a subprocess (``--n N --strides 20
   --span S --out <tmp>``; its default ``--jobs``: os.cpu_count() threads), once;
3. per grid point, serially on the same random sample of grid points, walker's ``StrideMap``
   against a ``scipy.integrate.solve_ivp`` DOP853 stride on walker's compiled compass vector
   field (scripts/_contenders.py ``CompiledSimple``) and, when heyoka is installed (the
   ``bench`` extra), a heyoka Taylor stride with the parameters folded in (``HeyokaCompass``),
   with the iteration rule of ``walker.analysis.basin.basin_chunk``, interleaved round-robin.

Writes results/bench/basin.csv, basin.md and README.md.

Usage: python scripts/bench_basin.py [--quick]
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _bench as B  # noqa: E402
import _contenders as C  # noqa: E402

from walker import load_scene  # noqa: E402
from walker.analysis.basin import basin_map  # noqa: E402
from walker.analysis.fixedpoint import find_fixed_point  # noqa: E402
from walker.models import get_model  # noqa: E402
from walker.results import BASIN_CONVERGED, BASIN_UNDECIDED  # noqa: E402
from walker.simulation.stride import StrideMap  # noqa: E402

SCENE = "compass_goswami.toml"
STRIDES = 20
AXES = (0, 1)  # walker basin's default --axes
GRIDS = (  # (name, span): walker basin's default --span, and a slice where most points walk
    ("default", 0.5),
    ("walking", 0.05),
)
WORKERS = 2
BASIN_TOL = 1e-6  # basin_map's default convergence tolerance
IVP = "solve_ivp DOP853, walker's compiled rhs"
WALKER = "walker StrideMap"
HEYOKA = "heyoka Taylor, folded constants, tol = rtol"
CONTENDERS = ("threads", "pool", "serial", "loose", "early", "early_loose")
SAME = CONTENDERS[:3]  # the same map: outcome and stride grids must agree bit for bit
LOOSE_RTOL = 1e-9  # `walker basin --rtol 1e-9`: the basin's strides only (atol the same)
EARLY = ("early", "early_loose")  # converge_radius="auto": `walker basin`'s default


def _warm(_):
    """Runs in a worker: import walker, load the extension, run one compass stride."""
    from walker import load_scene as ls
    from walker.simulation.stride import StrideMap as SM

    s = ls(B.GAITS / SCENE)
    P = SM(s.model, s.params)
    P(P.project(s.state))
    return os.getpid()


def workers_cpu(pids) -> float:
    """CPU seconds (user + system) used so far by the processes ``pids`` (Linux /proc; NaN
    elsewhere)."""
    try:
        tick = os.sysconf("SC_CLK_TCK")
        total = 0
        for pid in pids:
            with open(f"/proc/{pid}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
            total += int(fields[11]) + int(fields[12])  # utime, stime
        return total / tick
    except (OSError, ValueError, IndexError):
        return float("nan")


def per_point(stride_fn, z, target):
    """basin_chunk's rule for one point: iterate until within BASIN_TOL of the fixed point,
    a failed stride, or STRIDES strides."""
    done = 0
    while True:
        if np.max(np.abs(z - target)) <= BASIN_TOL:
            return "converged", done
        if done + 1 > STRIDES:
            return "undecided", done
        z = stride_fn(z)
        if z is None:
            return "fell", done
        done += 1


def ranges_for(fp, span):
    """walker basin's slice: value +- span * max(|value|, 0.1) on each axis."""
    return tuple(
        (
            fp.section[a] - span * max(abs(fp.section[a]), 0.1),
            fp.section[a] + span * max(abs(fp.section[a]), 0.1),
        )
        for a in AXES
    )


def run_cli(n, span):
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "basin.h5"
        # this checkout's walker (cwd is the repository root), not whichever `walker` script
        # is first on PATH
        cli = [sys.executable, "-m", "walker"]
        args = ["basin", f"gaits/{SCENE}", "--n", str(n), "--strides", str(STRIDES)]
        if span != 0.5:
            args += ["--span", f"{span:g}"]
        t = time.perf_counter()
        proc = subprocess.run(
            cli + args + ["--out", str(out)], capture_output=True, text=True, cwd=B.ROOT
        )
        wall = time.perf_counter() - t
        msg = (proc.stdout.strip() or proc.stderr.strip()).splitlines()[-1:]
    return wall, proc.returncode == 0, " ".join(msg), "walker " + " ".join(args)


def main(argv=None):
    quick, cmd = B.quick_options("bench_basin.py", __doc__, "20 x 20 grids, fewer repeats", argv)
    n = 20 if quick else 100
    reps = 2 if quick else 5
    pp_reps = 2 if quick else 3
    n_sample = 6 if quick else 24
    t_start = time.perf_counter()
    load_before = os.getloadavg()[0]

    scene = load_scene(B.GAITS / SCENE)
    c = scene.compute
    P = StrideMap(
        scene.model, scene.params, method=c.method, rtol=c.rtol, atol=c.atol, t_max=c.t_max
    )
    fp = find_fixed_point(P, P.project(scene.state))
    P_loose = P.with_tolerance(LOOSE_RTOL, LOOSE_RTOL)
    model = get_model("compass")
    p = scene.params.as_array()
    ivp = C.CompiledSimple("compass", scene.params)
    try:  # optional (the bench extra)
        hey = C.HeyokaCompass(scene.params, c.rtol)
    except ImportError:
        hey = None

    def walker_stride(z):
        r = P(z)
        return r.z if r.success else None

    def ivp_stride(z):
        x, _, _ = ivp.stride(model.lift(z, p), rtol=c.rtol, atol=c.atol, t_span=c.t_max)
        return None if x is None else model.project(x, p)

    def heyoka_stride(z):
        x, _ = hey.stride(model.lift(z, p), t_span=c.t_max)
        return None if x is None else model.project(x, p)

    strides = {WALKER: (walker_stride, "walker"), IVP: (ivp_stride, "ivp")}
    if hey is not None:
        strides[HEYOKA] = (heyoka_stride, "heyoka")

    # A 2-worker fork-server process pool, started and warmed once (not in the timings).
    ctx = multiprocessing.get_context(
        "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else None
    )
    t = time.perf_counter()
    pool = cf.ProcessPoolExecutor(max_workers=WORKERS, mp_context=ctx)
    pids = set(pool.map(_warm, range(4 * WORKERS)))
    pool_start = time.perf_counter() - t
    start_method = ctx.get_start_method()

    grids = {}
    try:
        for name, span in GRIDS:
            ranges = ranges_for(fp, span)
            kw = dict(axes=AXES, ranges=ranges, n=(n, n), n_strides=STRIDES, progress=False)
            calls = {
                "threads": lambda kw=kw: basin_map(P, fp, jobs=WORKERS, **kw),
                "pool": lambda kw=kw: basin_map(P, fp, executor=pool, **kw),
                "serial": lambda kw=kw: basin_map(P, fp, executor="serial", **kw),
                "loose": lambda kw=kw: basin_map(P_loose, fp, jobs=WORKERS, **kw),
                "early": lambda kw=kw: basin_map(P, fp, jobs=WORKERS, converge_radius="auto", **kw),
                "early_loose": lambda kw=kw: basin_map(
                    P_loose, fp, jobs=WORKERS, converge_radius="auto", **kw
                ),
            }
            times = {k: [] for k in CONTENDERS}
            cpu = {k: [] for k in CONTENDERS}  # this process + the pool's workers
            results = {}
            for r in range(reps):
                k0 = r % len(CONTENDERS)
                for mode in CONTENDERS[k0:] + CONTENDERS[:k0]:
                    c0 = time.process_time() + workers_cpu(pids)
                    t = time.perf_counter()
                    results[mode] = calls[mode]()
                    times[mode].append(time.perf_counter() - t)
                    cpu[mode].append(time.process_time() + workers_cpu(pids) - c0)
                print(
                    f"{name} round {r}: "
                    + ", ".join(f"{m} {times[m][-1]:.2f} s" for m in CONTENDERS),
                    flush=True,
                )
            bm = results["serial"]
            same = all(
                np.array_equal(results[m].outcome, bm.outcome)
                and np.array_equal(results[m].strides, bm.strides)
                for m in SAME
            )
            loose = results["loose"]
            early = {}
            for mode in EARLY:
                e = results[mode]
                kept = e.outcome == bm.outcome
                to_conv = (bm.outcome == BASIN_UNDECIDED) & (e.outcome == BASIN_CONVERGED)
                conv_both = (bm.outcome == BASIN_CONVERGED) & (e.outcome == BASIN_CONVERGED)
                early[mode] = dict(
                    rule_holds=bool(np.all(kept | to_conv)),
                    other=int(np.sum(~(kept | to_conv))),
                    to_conv=int(np.sum(to_conv)),
                    falls_same=bool(np.array_equal(e.outcome > 0, bm.outcome > 0)),
                    fewer=bool(np.all(e.strides[conv_both] <= bm.strides[conv_both])),
                    strides=int(e.strides.sum()),
                    median_stop=float(np.median(e.strides[e.outcome == BASIN_CONVERGED]))
                    if np.any(e.outcome == BASIN_CONVERGED)
                    else float("nan"),
                    ball=e.classification,
                )
            n_conv = int(np.sum(bm.outcome == BASIN_CONVERGED))
            n_und = int(np.sum(bm.outcome == BASIN_UNDECIDED))
            n_fell = n * n - n_conv - n_und
            completed = int(bm.strides.sum())
            grids[name] = dict(
                span=span,
                ranges=ranges,
                axis_names=bm.axis_names,
                times={k: np.array(v) for k, v in times.items()},
                cpu={k: np.array(v) for k, v in cpu.items()},
                same=same,
                loose_diff=int(np.sum(loose.outcome != bm.outcome)),
                loose_strides=int(loose.strides.sum()),
                early=early,
                conv=n_conv / n**2,
                und=n_und / n**2,
                fell=n_fell / n**2,
                completed=completed,
                integrated=completed + n_fell,  # each fall ends in one failed stride
            )
    finally:
        pool.shutdown(wait=True)

    for name, g in grids.items():
        # 2. the CLI end to end.
        g["cli_wall"], g["cli_ok"], g["cli_msg"], g["cli_cmd"] = run_cli(n, g["span"])
        print(f"{name} CLI: {g['cli_wall']:.2f} s ({g['cli_msg']})", flush=True)

        # 3. per point, serially: walker's StrideMap vs a solve_ivp stride, same points.
        x_axis = np.linspace(*g["ranges"][0], n)
        y_axis = np.linspace(*g["ranges"][1], n)
        rng = np.random.default_rng(0)
        sample = []
        for _ in range(n_sample):
            z = fp.section.copy()
            z[AXES[0]] = x_axis[rng.integers(n)]
            z[AXES[1]] = y_axis[rng.integers(n)]
            sample.append(z)
        outcomes = {}

        def run_all(fn, key, sample=sample, outcomes=outcomes):
            def go():
                outcomes[key] = [per_point(fn, z.copy(), fp.section) for z in sample]

            return go

        for z in sample[:2]:  # warm-up (first calls: imports, caches), not timed
            for fn, _ in strides.values():
                fn(z.copy())
        pp = B.round_robin(
            {who: run_all(fn, key) for who, (fn, key) in strides.items()},
            pp_reps,
            inner=dict.fromkeys(strides, 1),
        )
        g["pp"] = {k: v / n_sample for k, v in pp.items()}
        g["agree"] = {
            key: sum(a == b for a, b in zip(outcomes["walker"], outcomes[key], strict=True))
            for _, key in list(strides.values())[1:]
        }
        g["sample_strides"] = sum(s for _, s in outcomes["walker"])
        g["sample_falls"] = sum(o == "fell" for o, _ in outcomes["walker"])
        print(
            f"{name} per point: "
            + ", ".join(f"{who} {np.median(v) * 1e3:.2f} ms" for who, v in g["pp"].items()),
            flush=True,
        )

    # ---------------------------------------------------------------------- outputs
    labels = {
        "threads": f"basin_map jobs={WORKERS} (threads)",
        "pool": f"basin_map executor={WORKERS}-worker process pool",
        "serial": 'basin_map executor="serial"',
        "loose": f"basin_map jobs={WORKERS} (threads), rtol {LOOSE_RTOL:g}",
        "early": f"basin_map jobs={WORKERS} (threads), converge_radius auto",
        "early_loose": f"basin_map jobs={WORKERS} (threads), converge_radius auto, "
        f"rtol {LOOSE_RTOL:g}",
    }
    rows = []
    for name, g in grids.items():
        for mode in CONTENDERS:
            for k, v in enumerate(g["times"][mode]):
                w = 1 if mode == "serial" else WORKERS
                cpu_k = g["cpu"][mode][k]
                rows.append([labels[mode], name, g["span"], n, w, k, f"{v:.4f}", f"{cpu_k:.3f}"])
        rows.append(
            ["walker basin CLI", name, g["span"], n, os.cpu_count(), 0, f"{g['cli_wall']:.4f}", ""]
        )
        for who, v in g["pp"].items():
            for k, t in enumerate(v):
                rows.append(
                    [f"per point sample: {who}", name, g["span"], n_sample, 1, k, f"{t:.6f}", ""]
                )
    B.write_csv_atomic(
        B.OUT / "basin.csv",
        ["what", "grid", "span", "n_or_points", "workers", "rep", "wall_s", "cpu_s"],
        rows,
    )

    def med(g, m):
        return float(np.median(g["times"][m]))

    def phrase(name):
        g = grids[name]
        th, po, se = med(g, "threads"), med(g, "pool"), med(g, "serial")
        return (
            f"{name} slice (span {g['span']:g}, {g['integrated'] / n**2:.1f} strides per point) "
            f"{th:.2f} s with `basin_map(jobs={WORKERS})` ({WORKERS} threads, the default), "
            f"{se / th:.2f}x the speed of serial ({se:.2f} s); the strongest alternative, a "
            f"started {WORKERS}-worker process pool, {po:.2f} s, {se / po:.2f}x serial; with "
            f"the basin's strides at rtol {LOOSE_RTOL:g} (`walker basin --rtol`) "
            f"{med(g, 'loose'):.2f} s on {WORKERS} threads, {g['loose_diff']} of {n * n} "
            "outcomes different"
        )

    def cpu_ratio(g, m):
        """Median over rounds of CPU(m) / CPU(threads) in the same round."""
        return float(np.median(g["cpu"][m] / g["cpu"]["threads"]))

    def early_phrase(name, mode):
        g = grids[name]
        e = g["early"][mode]
        cpu = float(np.median(g["cpu"][mode]))
        return (
            f"{name} slice{' at rtol ' + format(LOOSE_RTOL, 'g') if mode == 'early_loose' else ''}"
            f" {cpu / n**2 * 1e6:.0f} µs CPU per point against "
            f"{np.median(g['cpu']['threads']) / n**2 * 1e6:.0f} µs for the full runs "
            f"({1 / cpu_ratio(g, mode):.1f}x less CPU, per-round ratio), {cpu:.2f} s CPU in all "
            f"(CPU / 2 = {cpu / 2:.2f} s), wall median {med(g, mode):.2f} s on the loaded "
            f"machine; outcomes as the full 20-stride run at rtol {c.rtol:g} except "
            f"undecided -> converged: {'yes' if e['rule_holds'] else 'NO'} "
            f"({e['to_conv']} points undecided -> converged, {e['other']} other changes)"
        )

    gw = grids["walking"]
    summary = (
        "Early classification (`walker basin`'s default `--converge-radius auto`, "
        "docs/basins.md): " + "; ".join(early_phrase("walking", m) for m in EARLY) + ". "
        f"Compass basin {n} x {n}, up to {STRIDES} strides, wall medians: "
        + "; ".join(phrase(k) for k in grids)
        + f". Per stride walker's StrideMap is "
        f"{np.median(gw['pp'][IVP]) / np.median(gw['pp'][WALKER]):.0f}x faster than a "
        "solve_ivp DOP853 stride on walker's compiled rhs"
        + (
            f" and {np.median(gw['pp'][HEYOKA]) / np.median(gw['pp'][WALKER]):.1f}x faster "
            "than heyoka's Taylor integrator with the parameters folded in"
            if HEYOKA in gw["pp"]
            else ""
        )
        + " (walking slice, serial)."
    )
    md = [
        "# Basin of attraction",
        "",
        f"<!-- command: {cmd} -->",
        f"<!-- summary: {summary} -->",
        "",
        f"Made by `{cmd}` in {time.perf_counter() - t_start:.0f} s on {B.machine_line()}; "
        f"1-minute load average {load_before:.2f} before, {os.getloadavg()[0]:.2f} after.",
        "",
        f"Compass gait (gaits/{SCENE}, the scene's solver settings: {c.method}, rtol "
        f"{c.rtol:g}, atol {c.atol:g}), fixed point found first; {n} x {n} grids on the section "
        f"coordinates {grids['default']['axis_names'][0]} and "
        f"{grids['default']['axis_names'][1]} (the `walker basin` default axes 0,1), each axis "
        "the fixed point's value ± span x max(|value|, 0.1) (`walker basin --span`), at most "
        f"{STRIDES} strides per point, converged when within {BASIN_TOL:g} of the fixed point. "
        "Two slices: `default`, `walker basin`'s span 0.5, where most points fall within a "
        "few strides, and `walking`, span 0.05 around the fixed point, where most points "
        "converge or are still walking after 20 strides, so that nearly every point costs "
        "the full 20 strides.",
        "",
        "| slice | span | q_stance range | qd_stance range | converge | undecided | fall | "
        "strides integrated | per point |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, g in grids.items():
        (x0, x1), (y0, y1) = g["ranges"]
        md.append(
            f"| {name} | {g['span']:g} | [{x0:.4f}, {x1:.4f}] | [{y0:.4f}, {y1:.4f}] | "
            f"{g['conv']:.1%} | {g['und']:.1%} | {g['fell']:.1%} | {g['integrated']} | "
            f"{g['integrated'] / n**2:.1f} |"
        )
    md += [
        "",
        "Strides integrated: completed strides plus the failing stride of each fall.",
        "",
        summary,
        "",
        f"`basin_map` six ways, interleaved round-robin over {reps} rounds (the starting "
        "contender rotated each round), wall time, and CPU time (user + system of this "
        "process and the pool's worker processes; CPU / wall is the number of CPUs kept busy):",
        "",
        "| slice | what | wall, min | wall, median | median / threads | CPU, median | "
        "CPU / wall, per round |",
        "|---|---|---|---|---|---|---|",
    ]
    desc = {
        "threads": f"`basin_map(..., jobs={WORKERS})`: {WORKERS} threads of this process "
        f"(the default, jobs = os.cpu_count() = {os.cpu_count()} here)",
        "pool": f"`basin_map(..., executor=<{WORKERS}-worker process pool>)`, "
        f"{start_method} workers started and warmed before",
        "serial": '`basin_map(..., executor="serial")`, inline in this process',
        "loose": f"`basin_map(P.with_tolerance({LOOSE_RTOL:g}, {LOOSE_RTOL:g}), ..., "
        f"jobs={WORKERS})`: the basin's strides at rtol {LOOSE_RTOL:g} (`walker basin --rtol "
        f"{LOOSE_RTOL:g}`), the fixed point at the scene's",
        "early": f'`basin_map(..., jobs={WORKERS}, converge_radius="auto")`: early '
        "classification (below)",
        "early_loose": f"`basin_map(P.with_tolerance({LOOSE_RTOL:g}, {LOOSE_RTOL:g}), ..., "
        f'jobs={WORKERS}, converge_radius="auto")`: early classification, strides at rtol '
        f"{LOOSE_RTOL:g}",
    }
    for name, g in grids.items():
        th = med(g, "threads")
        for mode in CONTENDERS:
            v = g["times"][mode]
            busy = g["cpu"][mode] / v
            md.append(
                f"| {name} | {desc[mode]} | {v.min():.2f} s | {np.median(v):.2f} s | "
                f"{np.median(v) / th:.2f} | {np.median(g['cpu'][mode]):.2f} s | "
                f"{busy.min():.2f}-{busy.max():.2f} |"
            )
    ball = gw["early"]["early"]["ball"]
    md += [
        "",
        "**Early classification** (issue 30): a point stops as converged once inside the "
        'gait\'s contraction ball (`converge_radius="auto"`, `walker basin '
        "--converge-radius auto`, the command's default; the rule and its assumptions in "
        f"docs/basins.md). Compass ball at rtol {c.rtol:g}: radius "
        f"{ball.get('converge_radius', 0):.4g} in the weighted norm "
        f"({ball.get('weighting')}; ||A||_W {ball.get('contraction', float('nan')):.4f}, "
        f"sampled M {ball.get('lipschitz', float('nan')):.4g} x safety "
        f"{ball.get('safety', float('nan')):g}, kappa {ball.get('kappa', float('nan')):.4f}), "
        "derived inside each timed `basin_map` call. CPU time (user + system) per grid "
        "point, and its ratio to the full runs (`basin_map(jobs=2)` at the scene's tolerance, "
        "the tolerance alone: the old path) measured in the same round, median over rounds; "
        "the machine is shared with other sessions, so CPU time and the ratio are the "
        "figures, wall time only indicative (CPU / 2: the wall time of two fully busy "
        "cores):",
        "",
        "| slice | what | CPU per point, median | CPU / full runs' CPU, per round, median | "
        "CPU, median | CPU / 2 | strides completed | converged points: median stop stride | "
        "outcomes = full run except undecided -> converged |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, g in grids.items():
        md.append(
            f"| {name} | full runs, rtol {c.rtol:g} (old path) | "
            f"{np.median(g['cpu']['threads']) / n**2 * 1e6:.0f} µs | 1.00 | "
            f"{np.median(g['cpu']['threads']):.2f} s | "
            f"{np.median(g['cpu']['threads']) / 2:.2f} s | {g['completed']} | | |"
        )
        for mode in EARLY:
            e = g["early"][mode]
            cpu = float(np.median(g["cpu"][mode]))
            md.append(
                f"| {name} | early, rtol {LOOSE_RTOL if mode == 'early_loose' else c.rtol:g} | "
                f"{cpu / n**2 * 1e6:.0f} µs | {cpu_ratio(g, mode):.3f} | {cpu:.2f} s | "
                f"{cpu / 2:.2f} s | {e['strides']} | {e['median_stop']:g} | "
                f"{'yes' if e['rule_holds'] else 'NO'}: {e['to_conv']} undecided -> "
                f"converged, {e['other']} other; falls the same points: "
                f"{e['falls_same']}; converged points no later: {e['fewer']} |"
            )
    md += [
        "",
        "The first three give the same outcome and stride grids: "
        + ", ".join(f"{name} {g['same']}" for name, g in grids.items())
        + f". At rtol {LOOSE_RTOL:g} the outcome differs from the scene's rtol at "
        + ", ".join(
            f"{g['loose_diff']} of {n * n} points ({name}; strides {g['loose_strides']} against "
            f"{g['completed']})"
            for name, g in grids.items()
        )
        + f". Starting and warming the {WORKERS}-worker {start_method} pool (a new "
        f"interpreter per worker importing walker and loading its extension, one stride; "
        f"{len(pids)} worker processes seen) took {pool_start:.2f} s, not in the pool rows; "
        "the thread rows include creating and joining their threads, which `basin_map` does "
        "on every call. The compass map has a compiled batch "
        "(`StrideMap.basin_batch`): each grid row is one compiled call that releases the GIL "
        "for all its strides, so two threads keep two CPUs busy as two processes do. (Before "
        "the batch, the per-point loop between strides was Python and held the GIL: on the "
        "same machine two threads reached 1.6x serial on the walking slice and 1.25x on the "
        "default slice, against the pool's 1.9x.)",
        "",
        "The command line end to end, once each (a new process: interpreter start and "
        "imports, fixed point, the basin on `--jobs` default = os.cpu_count() = "
        f"{os.cpu_count()} threads, HDF5 output):",
        "",
        "| command | wall |",
        "|---|---|",
    ]
    for _name, g in grids.items():
        md.append(
            f"| `{g['cli_cmd']} --out <tmp>/basin.h5` | {g['cli_wall']:.2f} s"
            + ("" if g["cli_ok"] else f" FAILED: {g['cli_msg']}")
            + " |"
        )
    md += [
        "",
        f"Per grid point, serially on the same {n_sample} random grid points of each slice, "
        f"with `basin_chunk`'s iteration rule, interleaved round-robin over {pp_reps} rounds "
        "(per stride = per point x sample points / strides integrated in the sample):",
        "",
        "| slice | per point | min | median | per stride, median | median / walker |",
        "|---|---|---|---|---|---|",
    ]
    for name, g in grids.items():
        w = np.median(g["pp"][WALKER])
        k = g["sample_strides"] + g["sample_falls"]
        for who, v in g["pp"].items():
            md.append(
                f"| {name} | {who} | {B.fmt_time(v.min())} | {B.fmt_time(np.median(v))} | "
                f"{B.fmt_time(np.median(v) * n_sample / max(k, 1))} | {np.median(v) / w:.1f} |"
            )
    md += [
        "",
        "Same outcome and stride count as walker's at "
        + "; ".join(
            f"{name} sample points ({g['sample_strides']} completed strides, "
            f"{g['sample_falls']} falls): "
            + ", ".join(f"{k} {a} of {n_sample}" for k, a in g["agree"].items())
            for name, g in grids.items()
        )
        + ". The solve_ivp stride uses the same tolerances and walker's compiled compass rhs "
        "and impact map: the swing foot's height falling through zero as the heel-strike "
        "event (walker's reset tells a heel strike from a scuff; after a scuff the run goes "
        "on to the height's next rise through zero), and a terminal fall event at 70 degrees "
        "(walker's threshold). Outcomes can differ at a grazing contact, the foot dipping "
        "through the ground and back within one solve_ivp step: its end-of-step sign test "
        "misses it, walker's interior sampling and tangency check see it (the one "
        "disagreement examined while writing this script was of that kind)."
        + (
            " The heyoka stride (scripts/_contenders.py `HeyokaCompass`, compiled once "
            f"before the timings in {hey.compile_seconds:.2f} s) is the compass's equations "
            "written out by hand, integrated by heyoka's Taylor method at tol = the scene's "
            "rtol, the heel-strike and fall events as terminal events, walker's impact map; "
            "after a scuff the same integrator goes on (one more `propagate_until`)."
            if hey is not None
            else " heyoka is not installed (the `bench` extra): no heyoka row."
        ),
        "",
    ]
    B.publish("basin.md", md)


if __name__ == "__main__":
    main()
