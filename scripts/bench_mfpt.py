"""Monte-Carlo throughput on random slopes (issue 29): walker's compiled ensemble
(:func:`walker.analysis.mfpt.monte_carlo`, 2 threads) against a per-stride Python loop over
``scipy.integrate.solve_ivp`` on a hand-written compass model, side by side in one process,
both at rtol = atol = 1e-9 (DOP853), both from the gait of the mean slope, a slope drawn per
step; the kneed walker's Monte Carlo too (no hand-written contender); and the share of
walker's Monte-Carlo time spent on terrain draws (drawn in C since issue 29's throughput
item, walker/_core/terrain_draw.c) and outside the compiled walks altogether.  Strides per
wall second and per CPU second of the process (all its threads: the steadier measure on a
shared machine), with the load average.

The hand-written compass (point masses: hip ``mass_hip``, legs ``mass_leg`` at
``com_from_foot`` from the foot; absolute angles from the vertical) is written here from its
Lagrangian and checked against walker's vector field at random states before timing; its
heel strike is the swing foot's signed distance from the step's plane falling through zero
(a scuff, the foot not ahead, continues), its impact walker's (the impact is not what is
compared), its fall the stance leg 70 degrees from the vertical.

Writes results/bench/mfpt.md and results/bench/mfpt.csv.
"""

from __future__ import annotations

import math
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _bench import OUT, ROOT, publish, write_csv_atomic  # noqa: E402

RTOL = 1e-9
STD = 0.005  # slope standard deviation [rad]; MFPT about 30 steps for the compass
THREADS = 2
CONTENDER_WALKS = 10  # walks of the solve_ivp loop a round (about 300 strides)
KNEED_STD = 0.008  # the kneed walker's slope standard deviation [rad]
KNEED_RUNS = 1000


def hand_written_compass(params):
    """(f(t, y), heel(slope) -> event, fall event) of the compass: M(q) q'' = -h - G with
    M11 = m a^2 + (m_H + m) L^2, M12 = -m L b cos(q1 - q2), M22 = m b^2,
    h = (-m L b sin(q1 - q2) q2'^2, m L b sin(q1 - q2) q1'^2),
    G = (-(m a + (m_H + m) L) g sin q1, m b g sin q2)."""
    m, mh, a, b, g = (
        params.mass_leg,
        params.mass_hip,
        params.com_from_foot,
        params.com_to_hip,
        params.g,
    )
    L = a + b
    m11 = m * a * a + (mh + m) * L * L
    m22 = m * b * b
    mlb = m * L * b
    g1 = (m * a + (mh + m) * L) * g
    g2 = m * b * g
    sin, cos = math.sin, math.cos

    def f(t, y):
        q1, q2, u1, u2 = y
        s, c = sin(q1 - q2), cos(q1 - q2)
        m12 = -mlb * c
        r1 = mlb * s * u2 * u2 + g1 * sin(q1)
        r2 = -mlb * s * u1 * u1 - g2 * sin(q2)
        det = m11 * m22 - m12 * m12
        return np.array([u1, u2, (m22 * r1 - m12 * r2) / det, (m11 * r2 - m12 * r1) / det])

    def heel(slope):
        """(down, up): the swing foot's signed distance from the step's plane falling and
        rising through zero."""

        def down(t, y):
            # the swing foot from the stance foot: L(sin q2 - sin q1, cos q1 - cos q2)
            dx = L * (sin(y[1]) - sin(y[0]))
            dy = L * (cos(y[0]) - cos(y[1]))
            return dx * sin(slope) + dy * cos(slope)

        def up(t, y):
            return down(t, y)

        down.terminal, down.direction = True, -1.0
        up.terminal, up.direction = True, 1.0
        return down, up

    def fall(t, y):
        return abs(y[0]) - math.radians(70.0)

    fall.terminal, fall.direction = True, 1.0
    return f, heel, fall


def contender_run(model, params, x0, rng, max_steps, f, heel, fall):
    """Steps completed by one walk of the solve_ivp loop, a slope N(mean, STD^2) per step."""
    from scipy.integrate import solve_ivp

    p = params.as_array()
    x = np.array(x0, dtype=float)

    def until(event, t0, x):
        sol = solve_ivp(
            f, (t0, 20.0), x, method="DOP853", rtol=RTOL, atol=RTOL, events=[event, fall]
        )
        if sol.status != 1 or len(sol.t_events[1]) or not len(sol.t_events[0]):
            return None, None
        return sol.t_events[0][0], sol.y_events[0][0]

    for n in range(max_steps):
        down, up = heel(params.slope + STD * rng.standard_normal())
        t0 = 0.0
        for _ in range(4):
            te, xe = until(down, t0, x)
            if te is None:
                return n
            action, _, status, x_new, _ = model.reset(0, 0, xe, p, te)
            if action == 2 and status == 0:
                x = np.array(x_new, dtype=float)
                break
            if action != 0:
                return n  # a non-physical impact
            t0, x = until(up, te, xe)  # a scuff (the foot not ahead): go on past it
            if t0 is None:
                return n
        else:
            return n
    return max_steps


def _drawn_rows(steps, horizon):
    """The rows the compiled batch draws for runs that completed ``steps`` (it draws 16,
    then doubles, as the walk reaches each step, up to ``horizon``)."""
    need = np.minimum(steps + 1, horizon)
    drawn = np.full(steps.shape, 16)
    while np.any(drawn < need):
        drawn = np.where(drawn < need, 2 * drawn, drawn)
    return np.minimum(drawn, horizon)


def _walker_round(P, z0, scene, std, r, runs):
    """One round of walker's Monte Carlo (seed ``r``): strides per wall s, strides per CPU
    s, draw share of CPU, outside-walk share of wall and of CPU, and the share of CPU the
    same rows drawn in Python (seed sequences and draws, as before) would add."""
    from walker import _hybrid
    from walker.analysis.mfpt import draw_terrains, monte_carlo, run_seeds
    from walker.simulation import _terrain_run
    from walker.simulation.terrain import Terrain

    terrain = Terrain("random", slope_mean=scene.params.slope, slope_std=std)
    c, t = time.process_time(), time.perf_counter()
    res = monte_carlo(P, z0, slope_std=std, runs=runs, seed=r, jobs=THREADS)
    cpu, wall = time.process_time() - c, time.perf_counter() - t
    strides = res.steps.sum()
    # the draws alone: the same rows the batch drew, drawn by the same C code
    draws = _terrain_run.compiled_draws(r, terrain)
    idx = np.arange(runs, dtype=np.int64)
    counts = _drawn_rows(res.steps, 256)
    c = time.process_time()
    for n in np.unique(counts):
        _hybrid.terrain_draws(*draws, idx[counts == n], int(n))
    draw_cpu = time.process_time() - c
    # the walks alone on the same rows, drawn beforehand in Python as the path before the
    # draws moved into C drew them (seeds and draws timed: their share as before)
    c = time.process_time()
    rows = draw_terrains(run_seeds(r, runs), 256, terrain)
    python_draw_cpu = time.process_time() - c
    c, t = time.process_time(), time.perf_counter()
    P.ensemble(z0, rows, threads=THREADS)
    walks_cpu, walks_wall = time.process_time() - c, time.perf_counter() - t
    return (
        strides / wall,
        strides / cpu,
        draw_cpu / cpu,
        (wall - walks_wall) / wall,
        (cpu - walks_cpu) / cpu,
        python_draw_cpu / cpu,
    )


def _python_draws_round(P, z0, std, r, runs):
    """Strides per wall s and per CPU s of the same Monte Carlo with its rows drawn in
    Python (the path before the draws moved into C, and the fallback)."""
    from walker.analysis.mfpt import monte_carlo
    from walker.simulation import _terrain_run

    compiled = _terrain_run.compiled_draws
    _terrain_run.compiled_draws = lambda seed, terrain: None
    try:
        c, t = time.process_time(), time.perf_counter()
        res = monte_carlo(P, z0, slope_std=std, runs=runs, seed=r, jobs=THREADS)
        cpu, wall = time.process_time() - c, time.perf_counter() - t
    finally:
        _terrain_run.compiled_draws = compiled
    return res.steps.sum() / wall, res.steps.sum() / cpu


def main() -> None:
    from walker import StrideMap, load_scene
    from walker.analysis.mfpt import gait_on_mean_slope

    scene = load_scene(ROOT / "gaits" / "compass_goswami.toml")
    P = StrideMap.from_scene(scene).with_tolerance(RTOL, RTOL)
    P, z0 = gait_on_mean_slope(P, scene.state, scene.params.slope)
    f, heel, fall = hand_written_compass(scene.params)
    rng = np.random.default_rng(0)
    pv = scene.params.as_array()
    for _ in range(20):  # the contender computes walker's vector field
        y = rng.uniform(-0.6, 0.6, 4)
        dy = P.model.rhs(0, y, pv)
        np.testing.assert_allclose(f(0.0, y), dy, rtol=1e-12, atol=1e-12)
    x0 = P.lift(z0)
    kneed = load_scene(ROOT / "gaits" / "kneed_hsu.toml")
    K = StrideMap.from_scene(kneed).with_tolerance(RTOL, RTOL)
    K, k0 = gait_on_mean_slope(K, kneed.state, kneed.params.slope)

    load_before = os.getloadavg()
    rounds, runs = 5, 4000
    compass_rows, kneed_rows, contender_rate, contender_cpu = [], [], [], []
    python_draws = []
    for r in range(rounds):
        compass_rows.append(_walker_round(P, z0, scene, STD, r, runs))
        python_draws.append(_python_draws_round(P, z0, STD, r, runs))
        kneed_rows.append(_walker_round(K, k0, kneed, KNEED_STD, r, KNEED_RUNS))
        c, t = time.process_time(), time.perf_counter()
        rng = np.random.default_rng(r)
        strides = sum(
            contender_run(P.model, scene.params, x0, rng, 256, f, heel, fall)
            for _ in range(CONTENDER_WALKS)
        )
        contender_rate.append(strides / (time.perf_counter() - t))
        contender_cpu.append(strides / (time.process_time() - c))
    load_after = os.getloadavg()
    w, k = np.array(compass_rows), np.array(kneed_rows)
    c, cc = np.array(contender_rate), np.array(contender_cpu)
    pd = np.array(python_draws)
    med = np.median
    header = [
        "contender",
        "strides_per_wall_s_min",
        "strides_per_wall_s_median",
        "strides_per_cpu_s_median",
        "draw_share_cpu_median",
        "outside_walks_share_cpu_median",
        "rounds",
    ]

    def line(label, a):
        return [
            label,
            f"{a[:, 0].min():.0f}",
            f"{med(a[:, 0]):.0f}",
            f"{med(a[:, 1]):.0f}",
            f"{med(a[:, 2]):.4f}",
            f"{med(a[:, 4]):.4f}",
            rounds,
        ]

    rows_out = [
        line(f"walker monte_carlo, compass (compiled ensemble, {THREADS} threads)", w),
        line(f"walker monte_carlo, kneed (compiled ensemble, {THREADS} threads)", k),
        [
            f"walker monte_carlo, compass, rows drawn in Python (before; {THREADS} threads)",
            f"{pd[:, 0].min():.0f}",
            f"{med(pd[:, 0]):.0f}",
            f"{med(pd[:, 1]):.0f}",
            "",
            "",
            rounds,
        ],
        [
            "solve_ivp loop, hand-written compass (1 thread)",
            f"{c.min():.0f}",
            f"{med(c):.0f}",
            f"{med(cc):.0f}",
            "",
            "",
            rounds,
        ],
    ]
    write_csv_atomic(OUT / "mfpt.csv", header, rows_out)
    md = [
        "# Monte-Carlo MFPT throughput (compass gait and kneed walker on random slopes)",
        "",
        f"<!-- summary: walker's Monte Carlo walks {med(w[:, 0]):.0f} compass strides per wall "
        f"s on {THREADS} threads ({med(w[:, 1]):.0f} per CPU s), "
        f"{med(w[:, 0]) / med(c):.0f}x a per-stride solve_ivp loop on a hand-written compass "
        f"({med(c):.0f}/s), and {med(k[:, 0]):.0f} kneed strides per wall s "
        f"({med(k[:, 1]):.0f} per CPU s); terrain draws {100 * med(w[:, 2]):.2f} % of its CPU "
        f"time, everything outside the compiled walks {100 * med(w[:, 4]):.1f} % (medians; "
        f"load average {load_before[0]:.1f}). -->",
        "",
        f"`python scripts/bench_mfpt.py`: rtol = atol = {RTOL:g} (DOP853), from the gait of the "
        "mean slope, a slope drawn per step. Compass: gaits/compass_goswami.toml, slope "
        f"N(3 deg, {STD:g}^2 rad^2), {runs} runs a round. Kneed: gaits/kneed_hsu.toml, slope "
        f"std {KNEED_STD:g} rad, {KNEED_RUNS} runs a round. {rounds} rounds, walker on "
        f"{THREADS} threads; the contender {CONTENDER_WALKS} walks a round on one thread "
        "(solve_ivp holds the GIL), interleaved with walker's in each round. Strides per wall "
        "second (completed strides / wall time) and per CPU second (/ CPU time of the process, "
        "all threads).",
        "",
        "| contender | strides/wall s min | strides/wall s median | strides/CPU s median |",
        "|---|---|---|---|",
        *(f"| {a} | {b} | {m} | {cpu} |" for a, b, m, cpu, *_ in rows_out),
        "",
        "Rows drawn in C against rows drawn in Python, the same runs (compass, medians): "
        f"{med(w[:, 1]) / med(pd[:, 1]):.2f}x per CPU second, "
        f"{med(w[:, 0]) / med(pd[:, 0]):.2f}x per wall second.",
        "",
        f"walker / contender, compass (medians): {med(w[:, 0]) / med(c):.0f}x per wall second "
        f"(walker on {THREADS} threads, the contender on 1), {med(w[:, 1]) / med(cc):.0f}x per "
        "CPU second.",
        "",
        "Terrain draws: the rows the compiled batch drew (on demand, as each walk reached its "
        "steps), drawn again alone by the same C code and timed, as a share of the Monte "
        f"Carlo's CPU time: compass median {100 * med(w[:, 2]):.2f} %, max "
        f"{100 * w[:, 2].max():.2f} %; kneed median {100 * med(k[:, 2]):.2f} % (target < 5 %). "
        "The same rows drawn in Python as before (per-run seed sequences and 256 rows a run, "
        "timed alone): compass median "
        f"{100 * med(w[:, 5]):.2f} %, kneed {100 * med(k[:, 5]):.2f} % of the same CPU time. "
        "Everything outside the compiled walks (the whole Monte "
        "Carlo minus the same walks timed alone on rows drawn beforehand; noisy on a shared "
        f"machine): compass median {100 * med(w[:, 4]):.1f} % of CPU time, "
        f"{100 * med(w[:, 3]):.1f} % of wall time; kneed {100 * med(k[:, 4]):.1f} % of CPU time, "
        f"{100 * med(k[:, 3]):.1f} % of wall time.",
        "",
        "The machine's 2 cores are shared with other jobs (load average 1/5/15 min "
        f"{load_before[0]:.1f} / {load_before[1]:.1f} / {load_before[2]:.1f} before, "
        f"{load_after[0]:.1f} / {load_after[1]:.1f} / {load_after[2]:.1f} after): per wall "
        "second the 2 threads get a fraction of 2 cores; per CPU second is the work rate, and "
        "2 quiet cores would give about twice it per wall second.",
        "",
    ]
    publish("mfpt.md", md)


if __name__ == "__main__":
    main()
