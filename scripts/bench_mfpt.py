"""Monte-Carlo throughput on random slopes (issue 29): walker's compiled ensemble
(:func:`walker.analysis.mfpt.monte_carlo`, 2 threads) against a per-stride Python loop over
``scipy.integrate.solve_ivp`` on a hand-written compass model, side by side in one process,
both at rtol = atol = 1e-9 (DOP853), both from the gait of the mean slope, a slope drawn per
step; and the share of walker's Monte-Carlo time spent outside the compiled walks (terrain
draws, per-run seeds, bookkeeping).

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
    x_new = np.empty(4)

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
            action, _, status = model.module.reset(0, 0, te, xe, p, x_new, np.zeros(2))
            if action == 2 and status == 0:
                x = x_new.copy()
                break
            if action != 0:
                return n  # a non-physical impact
            t0, x = until(up, te, xe)  # a scuff (the foot not ahead): go on past it
            if t0 is None:
                return n
        else:
            return n
    return max_steps


def main() -> None:
    from walker import StrideMap, load_scene
    from walker.analysis.mfpt import draw_terrains, gait_on_mean_slope, monte_carlo, run_seeds
    from walker.simulation.terrain import Terrain

    scene = load_scene(ROOT / "gaits" / "compass_goswami.toml")
    P = StrideMap.from_scene(scene).with_tolerance(RTOL, RTOL)
    P, z0 = gait_on_mean_slope(P, scene.state, scene.params.slope)
    f, heel, fall = hand_written_compass(scene.params)
    rng = np.random.default_rng(0)
    pv = scene.params.as_array()
    for _ in range(20):  # the contender computes walker's vector field
        y = rng.uniform(-0.6, 0.6, 4)
        dy = np.empty(4)
        P.model.module.rhs(0, 0.0, y, pv, dy)
        np.testing.assert_allclose(f(0.0, y), dy, rtol=1e-12, atol=1e-12)
    x0 = P.lift(z0)

    load_before = os.getloadavg()[0]
    rounds, runs = 5, 4000
    walker_rate, walker_share, draw_share, contender_rate = [], [], [], []
    terrain = Terrain("random", slope_mean=scene.params.slope, slope_std=STD)
    for r in range(rounds):
        t = time.perf_counter()
        res = monte_carlo(P, z0, slope_std=STD, runs=runs, seed=r, jobs=THREADS)
        total = time.perf_counter() - t
        walker_rate.append(res.steps.sum() / total)
        # the same walks' terrain drawn as monte_carlo draws it (seeds, draws), then the
        # walks alone: the compiled part
        t = time.perf_counter()
        rows = draw_terrains(run_seeds(r, runs), 256, terrain)
        draws = time.perf_counter() - t
        t = time.perf_counter()
        P.ensemble(z0, rows, threads=THREADS)
        walks = time.perf_counter() - t
        walker_share.append(max(0.0, total - walks) / total)
        draw_share.append(draws / total)
        t = time.perf_counter()
        rng = np.random.default_rng(r)
        strides = sum(
            contender_run(P.model, scene.params, x0, rng, 256, f, heel, fall)
            for _ in range(CONTENDER_WALKS)
        )
        contender_rate.append(strides / (time.perf_counter() - t))
    w, c, s = np.array(walker_rate), np.array(contender_rate), np.array(walker_share)
    d = np.array(draw_share)
    header = ["contender", "strides_per_s_min", "strides_per_s_median", "rounds"]
    rows_out = [
        [
            "walker monte_carlo (compiled ensemble, 2 threads)",
            f"{w.min():.0f}",
            f"{np.median(w):.0f}",
            rounds,
        ],
        [
            "solve_ivp loop, hand-written compass (1 thread)",
            f"{c.min():.0f}",
            f"{np.median(c):.0f}",
            rounds,
        ],
    ]
    write_csv_atomic(OUT / "mfpt.csv", header, rows_out)
    md = [
        "# Monte-Carlo MFPT throughput (compass gait on random slopes)",
        "",
        f"<!-- summary: walker's Monte Carlo walks {np.median(w):.0f} compass strides/s on "
        f"{THREADS} threads, {np.median(w) / np.median(c):.0f}x a per-stride solve_ivp loop "
        f"on a hand-written compass ({np.median(c):.0f}/s); terrain draws "
        f"{100 * np.median(d):.1f} % of its time (medians). -->",
        "",
        f"`python scripts/bench_mfpt.py`: gaits/compass_goswami.toml at rtol = atol = {RTOL:g} "
        f"(DOP853), slope N(3 deg, {STD:g}^2 rad^2) per step, from the gait of the mean slope; "
        f"{rounds} rounds, walker {runs} runs a round on {THREADS} threads, the contender "
        f"{CONTENDER_WALKS} walks a round (one thread: solve_ivp holds the GIL). Strides per "
        "second (completed strides / wall time), min and median over rounds.",
        "",
        "| contender | strides/s min | strides/s median |",
        "|---|---|---|",
        *(f"| {a} | {b} | {m} |" for a, b, m, _ in rows_out),
        "",
        f"walker / contender (medians): {np.median(w) / np.median(c):.0f}x.",
        "",
        "Share of walker's Monte-Carlo wall time spent drawing the terrain (the per-run seed "
        "sequences and draws, timed alone as monte_carlo makes them): median "
        f"{100 * np.median(d):.1f} %, max {100 * d.max():.1f} % (target < 5 %). Outside the "
        "compiled walks altogether (the same walks timed alone on the drawn terrain, "
        "subtracted from the whole Monte Carlo; noisy on a shared machine): median "
        f"{100 * np.median(s):.1f} %, max {100 * s.max():.1f} %.",
        "",
        "The machine's 2 cores are shared with other jobs (load average "
        f"{load_before:.1f} before, {os.getloadavg()[0]:.1f} after); the numbers are side by "
        "side in one process, not absolute.",
        "",
    ]
    publish("mfpt.md", md)


if __name__ == "__main__":
    main()
