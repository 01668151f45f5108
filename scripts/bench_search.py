"""Gait-search benchmark: walker against a straightforward solve_ivp + finite-difference
implementation, timed side by side in one run.

Three jobs on the shipped scenes:

1. the kneed walker's fixed point from the thesis digits to residual 1e-12;
2. a 200-point slope continuation of the simplest walker's gait;
3. a 100 x 100 basin map of the compass gait, 20 strides per point.

The baseline is what a user writes without walker: each stride by solve_ivp(DOP853) with
terminal events and the same impact maps, Newton with a central-difference Jacobian, natural
continuation warm-started point to point, the basin by a plain loop.  Where the baseline
would take too long it is run on a sample and extrapolated (marked so in the table).

Writes results/bench/search.csv and results/bench/search.md.

Usage: python scripts/bench_search.py [--quick]
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from walker import StrideMap, load_scene
from walker.basin import basin_map
from walker.continuation import continue_branch
from walker.fixedpoint import find_fixed_point

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "bench"


def _scene(name):
    return load_scene(ROOT / "gaits" / f"{name}.toml")


# ------------------------------------------------------------------------ the baseline
def make_baseline_stride(model):
    """A stride map by solve_ivp: one phase after another with terminal events, the same
    compiled vector fields and resets as walker (so only the loop differs)."""
    m = model.module
    n_g = len(m.GUARD_NAMES)

    def stride(x0, p, rtol=1e-10):
        x = np.array(x0, dtype=float)
        phase, t0 = 0, 0.0
        for _ in range(8):  # phases per stride, bounded
            g = np.empty(n_g)

            def f(t, y, phase=phase):
                dy = np.empty_like(y)
                m.rhs(phase, t, y, p, dy)
                return dy

            events = []
            for k in range(n_g):

                def ev(t, y, k=k, phase=phase, g=g):
                    m.guards(phase, t, y, p, g)
                    return g[k]

                ev.terminal = True
                ev.direction = float(m.DIRECTIONS[phase, k])
                events.append(ev)
            sol = solve_ivp(
                f, (t0, t0 + 20.0), x, method="DOP853", rtol=rtol, atol=rtol, events=events
            )
            hits = [(te[0], k) for k, te in enumerate(sol.t_events) if len(te)]
            if not hits:
                return None
            te, k = min(hits)
            xe = sol.y_events[k][0]
            x_new = np.empty_like(xe)
            action, nxt, status = m.reset(phase, k, te, xe, p, x_new, np.zeros(4))
            if action == 0:  # a scuff: continue just past it
                x, t0 = xe, te + 1e-9
                continue
            if action == 3:
                return None
            x, t0, phase = x_new, te, nxt
            if action == 2:
                return x
        return None

    return stride


def baseline_fixed_point(model, params, z0, tol=1e-12, max_iter=30, rtol=1e-10):
    stride = make_baseline_stride(model)
    p = params.as_array()

    def F(z):
        x = stride(model.lift(z, p), p, rtol=rtol)
        return None if x is None else model.project(x, p) - z

    z = np.array(z0, dtype=float)
    for it in range(max_iter):
        f = F(z)
        if f is None:
            return z, it, False
        if np.max(np.abs(f)) <= tol:
            return z, it, True
        J = np.empty((len(z), len(z)))
        for j in range(len(z)):
            h = 1e-7 * max(1.0, abs(z[j]))
            e = np.zeros(len(z))
            e[j] = h
            fp_, fm_ = F(z + e), F(z - e)
            if fp_ is None or fm_ is None:
                return z, it, False
            J[:, j] = (fp_ - fm_) / (2 * h)
        z = z - np.linalg.solve(J - np.eye(len(z)), f)
    return z, max_iter, False


# ------------------------------------------------------------------------------- jobs
def job_fixed_point(reps):
    scene = _scene("kneed_hsu")
    P = StrideMap("kneed", scene.params)
    z0 = P.project(scene.state)
    find_fixed_point(P, z0)  # JIT
    t = time.perf_counter()
    for _ in range(reps):
        fp = find_fixed_point(P, z0, tol=1e-12)
    ours = (time.perf_counter() - t) / reps
    # The baseline at rtol 1e-12 too; with central differences of step 1e-7 its Jacobian is
    # good to ~1e-5 only, so it stops at the residual its stride noise allows (1e-11).
    t = time.perf_counter()
    zb, n_it, ok = baseline_fixed_point(P.model, scene.params, z0, tol=1e-11, rtol=1e-12)
    base = time.perf_counter() - t
    agree = float(np.max(np.abs(zb - fp.section)))
    return {
        "job": "kneed fixed point, residual 1e-12",
        "walker_s": ours,
        "baseline_s": base,
        "extrapolated": False,
        "note": f"{fp.n_iter} Newton steps (exact Jacobian) vs {n_it} (central differences, "
        f"{'reached' if ok else 'did not reach'} 1e-11: event-location noise of the "
        f"solve_ivp stride); sections agree to {agree:.1e}",
    }


def job_continuation(n_points, baseline_points):
    scene = _scene("simplest_garcia")
    P = StrideMap("simplest", scene.params, rtol=1e-10, atol=1e-10)
    fp = find_fixed_point(P, P.project(scene.state))
    continue_branch(P, fp.section, to=0.0095, method="natural", max_points=5)  # JIT
    slopes = np.linspace(0.009, 0.015, n_points)
    step = slopes[1] - slopes[0]
    t = time.perf_counter()
    br = continue_branch(
        P,
        fp.section,
        to=0.015,
        method="natural",
        step=step,
        min_step=step,
        max_step=step,
        max_points=n_points + 10,
    )
    ours = time.perf_counter() - t
    z = fp.section.copy()
    t = time.perf_counter()
    for s in slopes[:baseline_points]:
        z, _, _ = baseline_fixed_point(P.model, scene.params.replace(slope=s), z, tol=1e-10)
    base = (time.perf_counter() - t) * n_points / baseline_points
    return {
        "job": f"{n_points}-point slope continuation (simplest)",
        "walker_s": ours,
        "baseline_s": base,
        "extrapolated": baseline_points < n_points,
        "note": f"walker: {len(br.parameter)} points with multipliers and "
        f"bifurcation detection; baseline: Newton+FD per point, "
        f"{baseline_points} points timed",
    }


def job_basin(n, baseline_points):
    scene = _scene("compass_goswami")
    P = StrideMap("compass", scene.params, rtol=1e-10, atol=1e-10)
    fp = find_fixed_point(P, P.project(scene.state))
    ranges = ((-2.0, -0.4), (-2.0, 1.5))
    basin_map(P, fp, axes=(1, 2), ranges=ranges, n=(4, 4), n_strides=20, progress=False)
    t = time.perf_counter()
    bm = basin_map(P, fp, axes=(1, 2), ranges=ranges, n=(n, n), n_strides=20, progress=False)
    ours = time.perf_counter() - t
    stride = make_baseline_stride(P.model)
    p = scene.params.as_array()
    rng = np.random.default_rng(0)
    t = time.perf_counter()
    for _ in range(baseline_points):
        z = fp.section.copy()
        z[1] = rng.uniform(*ranges[0])
        z[2] = rng.uniform(*ranges[1])
        x = P.model.lift(z, p)
        for _ in range(20):
            x = stride(x, p)
            if x is None:
                break
    base = (time.perf_counter() - t) * n * n / baseline_points
    conv = float(np.mean(bm.outcome == -1))
    return {
        "job": f"{n}x{n} basin map, 20 strides (compass)",
        "walker_s": ours,
        "baseline_s": base,
        "extrapolated": True,
        "note": f"walker on a 2-worker process pool; {conv:.0%} of points converge; "
        f"baseline: {baseline_points} random points timed, serial",
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args(argv)
    OUT.mkdir(parents=True, exist_ok=True)
    rows = [
        job_fixed_point(reps=5 if args.quick else 20),
        job_continuation(50 if args.quick else 200, 3 if args.quick else 10),
        job_basin(30 if args.quick else 100, 10 if args.quick else 40),
    ]
    with open(OUT / "search.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    lines = [
        "# Gait-search benchmark",
        "",
        "Generated by `python scripts/bench_search.py`; one run, one machine (2 cores, "
        "shared): read the ratios.",
        "",
        "| job | walker | baseline (solve_ivp + FD) | ratio | notes |",
        "|---|---|---|---|---|",
    ]
    for r in rows:
        star = " (extrapolated)" if r["extrapolated"] else ""
        lines.append(
            f"| {r['job']} | {r['walker_s']:.3g} s | {r['baseline_s']:.3g} s{star} | "
            f"{r['baseline_s'] / r['walker_s']:.0f}x | {r['note']} |"
        )
    (OUT / "search.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
