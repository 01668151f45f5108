"""Stress measurements of walker's hybrid integrator: long runs, grazing contacts, scaling
laws, extreme parameters and a tolerance sweep.

Writes, under ``results/stress/``:

* ``long_runs.csv``: per chunk of strides, the largest distance from the fixed point and the
  running energy bookkeeping (impact losses against potential energy released);
* ``grazing.csv``: for each dip duration and tolerance, whether the guard crossing was found;
* ``scaling.csv``: compass-gait fixed points with all lengths scaled by ``lambda`` and ``g``
  by ``kappa``, against the predictions of dimensional analysis;
* ``tolerance_sweep.csv``: stride-map error and the integrator's ``error_estimate`` against a
  reference run, for ``rtol = atol`` from 1e-3 to 1e-13;
* ``README.md``: the numbers, in words and tables.

``tests/test_stress.py`` runs short versions of these measurements with its own helpers
(``tests/_stress.py``); this script imports from walker only.

Usage: python scripts/stress.py [--strides 100000] [--chunk 1000] [--quick]
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit  # the graze toy below is a user's own @njit system

from walker import load_scene
from walker.analysis.fixedpoint import find_fixed_point
from walker.models import get_model
from walker.simulation.integrate import HybridSystem, hybrid_solve
from walker.simulation.stride import StrideMap
from walker.status import EVENT_STRIDE, EVENT_TERMINAL, Status

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _stress_readme import write_readme  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "stress"
SCENES = {
    "compass": ROOT / "gaits" / "compass_goswami.toml",
    "kneed": ROOT / "gaits" / "kneed_hsu.toml",
}
FP_TOL = 1e-12


# =============================================================================================
# Fixed points and long runs
# =============================================================================================


def fixed_point(model: str, rtol: float = FP_TOL, params=None):
    """The stable gait of ``model`` ("compass" or "kneed") at ``rtol = atol``.

    Returns ``(StrideMap, FixedPoint)``; the Newton seed is the scene's ``[initial]`` state.
    """
    scene = load_scene(SCENES[model])
    P = StrideMap(model, params if params is not None else scene.params, rtol=rtol, atol=rtol)
    fp = find_fixed_point(P, P.project(scene.state), tol=1e-13)
    return P, fp


def total_mass(params) -> float:
    """Total mass of a compass (two legs + hip) or kneed walker (two thighs, shanks + hip)
    [kg]."""
    if hasattr(params, "mass_leg"):
        return params.mass_hip + 2.0 * params.mass_leg
    return params.mass_hip + 2.0 * (params.mass_thigh + params.mass_shank)


def energy_bookkeeping(model, params, events) -> tuple[float, float, int]:
    """Impact losses and potential energy released over the events of a run.

    Parameters
    ----------
    model : WalkerModel
    params : its parameter dataclass
    events : EventLog

    Returns
    -------
    loss : float
        sum over every applied event of ``K(x_pre) - K(x_post)`` [J] (kinetic energy with the
        stance foot pinned, before and after the reset; a heel strike changes the pinned
        foot, which is at rest on either side).
    released : float
        total mass * g * the vertical drop of the stance foot, summed over heel strikes [J]:
        the new stance foot lies below the old one by the swing foot's height difference at
        the strike.
    n_strides : int
        heel strikes in ``events``.
    """
    loss = 0.0
    released = 0.0
    n = 0
    mg = total_mass(params) * params.g
    for i in range(len(events)):
        k_pre, _ = model.energy(events.x_pre[i], params)
        k_post, _ = model.energy(events.x_post[i], params)
        loss += k_pre - k_post
        if _is_stride(model, events, i):
            pts = model.points(events.x_pre[i], params)
            released += mg * (pts[0, 1] - pts[-1, 1])
            n += 1
    return loss, released, n


def _is_stride(model, events, i) -> bool:
    """A heel strike: the event whose reset relabels the legs (phase 0 afterwards, from the
    locked phase for the kneed walker; the only non-terminal event of the compass gait)."""
    if model.name == "kneed":
        # knee lock: 0 -> 1; heel strike: 1 -> 0; knee lock with simultaneous strike: 0 -> 0
        return events.phase_after[i] == 0
    return True


def long_run(
    model_name: str,
    n_strides: int,
    chunk: int = 1000,
    rtol: float = FP_TOL,
    *,
    rows: list | None = None,
    time_limit: float = np.inf,
    restart_time: bool = False,
):
    """Walk ``n_strides`` strides from the fixed point, ``chunk`` strides per compiled call.

    Each chunk continues from the previous chunk's final state and time (``t0`` accumulates,
    so late strides run at large ``t``), or from ``t = 0`` with ``restart_time`` (the
    equations are autonomous, so only the floating-point resolution of ``t`` differs).
    Memory stays bounded by one chunk's event log.

    Returns
    -------
    dict
        ``n_strides`` done, ``max_dev`` (largest max-norm distance of a post-heel-strike state
        from the fixed point over all strides), ``final_dev``, ``loss``, ``released``,
        ``closure`` = ``|loss - released| / released``, ``seconds``, ``t_final``, ``status``.
    """
    P, fp = fixed_point(model_name, rtol)
    model = P.model
    params = P.params
    system = model.system
    p = params.as_array()
    x = fp.state.copy()
    t = 0.0
    done = 0
    max_dev = 0.0
    loss = released = 0.0
    status = Status.COMPLETED
    start = time.perf_counter()
    while done < n_strides and time.perf_counter() - start < time_limit:
        k = min(chunk, n_strides - done)
        sol = hybrid_solve(
            system,
            x,
            p,
            t0=t,
            t_max=t + 20.0 * k * fp.step_time,
            n_strides=k,
            rtol=rtol,
            atol=rtol,
            output="events",
        )
        if not sol.success:
            status = sol.status
            break
        ev = sol.events
        strides = np.array([_is_stride(model, ev, i) for i in range(len(ev))])
        post = ev.x_post[strides]
        dev = float(np.max(np.abs(post - fp.state)))
        max_dev = max(max_dev, dev)
        dl, dr, n = energy_bookkeeping(model, params, ev)
        loss += dl
        released += dr
        done += n
        x = sol.x
        t = 0.0 if restart_time else sol.t
        if rows is not None:
            rows.append(
                {
                    "model": model_name,
                    "restart_time": restart_time,
                    "strides_done": done,
                    "t": t,
                    "chunk_max_dev": dev,
                    "loss": loss,
                    "released": released,
                    "closure": abs(loss - released) / released,
                }
            )
    return {
        "model": model_name,
        "restart_time": restart_time,
        "n_strides": done,
        "max_dev": max_dev,
        "final_dev": float(np.max(np.abs(x - fp.state))),
        "loss": loss,
        "released": released,
        "closure": abs(loss - released) / released if released > 0 else math.nan,
        "seconds": time.perf_counter() - start,
        "t_final": t,
        "status": status.name,
        "fp_residual": fp.residual,
    }


# =============================================================================================
# Grazing: toy systems whose guard dips below zero for a short time
# =============================================================================================
# OSCILLATOR: u' = v, v' = -u from (u, v) = (-1, 0) at t = 0, so u = -cos t; guard
# g = (1 - delta) - u... written as g = c - u with c = p[0] < 1, direction -1: g < 0 while
# u > c, i.e. for |t - pi| < arccos(c) ... around u's maximum at t = pi.  The dip lasts
# 2 arccos(c) and is at most 1 - c deep.  The reset stops the run (a "heel strike").
#
# PARABOLA: x' = 1 from x = 0 (x = t); guard g = (x - 1)^2 - eps^2 with eps = p[0],
# direction -1: below zero for |t - 1| < eps (the brief's example).  The vector field is
# constant, so the error estimate is exactly zero and the step grows by the maximal factor.


@njit(cache=False)  # run as __main__ or loaded by file path: no disk cache for this module
def _osc_rhs(phase, t, x, p, dx):
    if phase == 0:
        dx[0] = x[1]
        dx[1] = -x[0]
    else:
        dx[0] = 1.0
        dx[1] = 0.0


@njit(cache=False)
def _osc_jac(phase, t, x, p, J):
    J[:, :] = 0.0
    if phase == 0:
        J[0, 1] = 1.0
        J[1, 0] = -1.0


@njit(cache=False)
def _osc_guards(phase, t, x, p, g):
    if phase == 0:
        g[0] = p[0] - x[0]
    else:
        d = x[0] - 1.0
        g[0] = d * d - p[0] * p[0]


@njit(cache=False)
def _osc_reset(phase, k, t, x, p, x_new, impulse):
    return EVENT_STRIDE, phase, 0


GRAZE = HybridSystem(
    name="graze",
    n_x=2,
    n_phases=2,
    n_guards=1,
    n_impulse=1,
    rhs=_osc_rhs,
    guards=_osc_guards,
    reset=_osc_reset,
    jac=_osc_jac,
    directions=np.array([[-1], [-1]], dtype=np.int64),
    phase_names=("oscillator", "parabola"),
    guard_names=("contact",),
)
_ = EVENT_TERMINAL  # (the toy's reset ends the run by completing its one stride)


def oscillator_dip(duration: float) -> float:
    """Guard constant ``c`` whose dip below zero lasts ``duration`` [s] (oscillator toy)."""
    return math.cos(0.5 * duration)


def graze_found(kind: str, duration: float, tol: float, n_interior: int = 4) -> tuple[bool, float]:
    """Run a toy through a dip of ``duration``; return (event found, event time).

    ``kind`` is "oscillator" (dip centred at t = pi) or "parabola" (centred at t = 1).
    """
    if kind == "oscillator":
        p = np.array([oscillator_dip(duration)])
        sol = hybrid_solve(
            GRAZE, [-1.0, 0.0], p, t_max=2.0 * math.pi, rtol=tol, atol=tol, n_interior=n_interior
        )
    else:
        p = np.array([0.5 * duration])
        sol = hybrid_solve(
            GRAZE, [0.0, 0.0], p, phase0=1, t_max=3.0, rtol=tol, atol=tol, n_interior=n_interior
        )
    return sol.status == Status.COMPLETED, float(sol.t)


def grazing_table(tols, durations, kinds=("oscillator", "parabola"), rows=None):
    """For each kind and tolerance: the smallest dip duration found, and whether every dip
    at least that long was found (``reliable``: no miss among longer dips)."""
    summary = []
    for kind in kinds:
        for tol in tols:
            found = []
            for d in durations:
                ok, t_ev = graze_found(kind, d, tol)
                found.append(ok)
                if rows is not None:
                    rows.append(
                        {
                            "kind": kind,
                            "rtol": tol,
                            "dip_duration": d,
                            "found": int(ok),
                            "t_event": t_ev,
                        }
                    )
            found = np.array(found)
            # smallest duration such that it and every longer one were found
            order = np.argsort(durations)
            durs = np.asarray(durations)[order]
            f = found[order]
            reliable = math.nan
            for i in range(len(durs)):
                if f[i:].all():
                    reliable = float(durs[i])
                    break
            summary.append(
                {
                    "kind": kind,
                    "rtol": tol,
                    "smallest_reliable": reliable,
                    "n_found": int(found.sum()),
                    "n": len(found),
                }
            )
    return summary


def compass_scuff_outcomes(tols):
    """The compass gait's mid-stance scuff (the rigid swing leg passes through the ground
    behind the stance foot, ignored by construction): the stride from the fixed point at
    each tolerance.  Returns rows (rtol, status, max |z - z*|)."""
    P, fp = fixed_point("compass")
    out = []
    for tol in tols:
        Q = StrideMap("compass", P.params, rtol=tol, atol=tol)
        r = Q(fp.section)
        out.append(
            {"rtol": tol, "status": r.status.name, "dev": float(np.max(np.abs(r.z - fp.section)))}
        )
    return out


# =============================================================================================
# Scaling laws (compass gait)
# =============================================================================================


def scaled_compass(params, lam: float, kappa: float, mu: float = 1.0):
    """Compass parameters with every length times ``lam``, ``g`` times ``kappa`` and every
    mass times ``mu`` (inertia times ``mu lam^2``): the same dimensionless walker."""
    return params.replace(
        mass_hip=params.mass_hip * mu,
        mass_leg=params.mass_leg * mu,
        com_from_foot=params.com_from_foot * lam,
        com_to_hip=params.com_to_hip * lam,
        inertia_leg=params.inertia_leg * mu * lam**2,
        foot_radius=params.foot_radius * lam,
        g=params.g * kappa,
    )


def scaling_errors(lams=(1e-3, 1e-1, 1e1, 1e3), kappas=(1 / 9.8, 100 / 9.8), mus=(1e-4, 1e4)):
    """Fixed points of scaled compass gaits against the base gait.

    Dimensional analysis: angles and Floquet multipliers do not change; angular rates scale
    with ``sqrt(kappa / lam)``; the step time with ``sqrt(lam / kappa)``; masses (all scaled
    together) change nothing.  Returns one row per (lam, kappa, mu) with the relative errors.
    """
    P0, fp0 = fixed_point("compass")
    base = P0.params
    rows = []
    cases = [(lam, kap, 1.0) for lam in lams for kap in kappas] + [(1.0, 1.0, m) for m in mus]
    for lam, kap, mu in cases:
        prm = scaled_compass(base, lam, kap, mu)
        P = StrideMap("compass", prm, rtol=FP_TOL, atol=FP_TOL)
        w = math.sqrt(kap / lam)
        guess = fp0.section * np.array([1.0, w, w])
        fp = find_fixed_point(P, guess, tol=1e-12 * max(1.0, w))
        if not fp.success:
            rows.append({"lam": lam, "kappa": kap, "mu": mu, "status": fp.status.name})
            continue
        ang = abs(fp.section[0] - fp0.section[0])
        rate = float(np.max(np.abs(fp.section[1:] / w - fp0.section[1:]) / np.abs(fp0.section[1:])))
        step = abs(fp.step_time * w - fp0.step_time) / fp0.step_time
        mult = float(
            np.max(np.abs(np.sort_complex(fp.multipliers) - np.sort_complex(fp0.multipliers)))
        )
        rows.append(
            {
                "lam": lam,
                "kappa": kap,
                "g": prm.g,
                "mu": mu,
                "status": fp.status.name,
                "angle_abs_err": ang,
                "rate_rel_err": rate,
                "step_time_rel_err": step,
                "multiplier_abs_err": mult,
            }
        )
    return rows


# =============================================================================================
# Extreme parameters: defined outcomes
# =============================================================================================


def extreme_compass_cases():
    """(label, CompassParams) over mass ratios, leg lengths, slopes and g."""
    base = load_scene(SCENES["compass"]).params
    cases = []
    for ratio in (1e-4, 1e-2, 1.0, 1e2, 1e4):  # m_H / m
        cases.append((f"mass_ratio={ratio:g}", base.replace(mass_hip=base.mass_leg * ratio)))
    for lam in (1e-3, 1e-1, 1e1, 1e3):
        cases.append((f"length*{lam:g}", scaled_compass(base, lam, 1.0)))
    for slope in (0.0, 0.02, 0.1, 0.3, 0.6, 1.0, 1.5):
        cases.append((f"slope={slope:g}", base.replace(slope=slope)))
    for g in (1.0, 100.0):
        cases.append((f"g={g:g}", base.replace(g=g)))
    return cases


def run_case(model, params, x0, n_strides=10, rtol=1e-10):
    """Simulate and time one run; returns (Solution, seconds)."""
    from walker.simulation.stride import simulate

    t = time.perf_counter()
    sol = simulate(model, params, x0, n_strides=n_strides, rtol=rtol, atol=rtol)
    return sol, time.perf_counter() - t


# =============================================================================================
# Tolerance sweep
# =============================================================================================


def scipy_stride(model_name, params, x0, rtol):
    """One compass stride with scipy's DOP853 (events on the swing-foot height, the scuff
    behind the stance foot skipped), the model's own compiled reset.  Returns the state just
    after heel strike."""
    from scipy.integrate import solve_ivp

    model = get_model(model_name)
    p = params.as_array()

    def f(t, y):
        return model.rhs(0, y, p, t)

    def heel(t, y):
        return model.guards(0, y, p, t)[0]

    heel.direction = -1
    t0 = 0.0
    y = np.array(x0, dtype=float)
    # leave the post-impact zero of the guard first
    first = solve_ivp(f, (0.0, 1e-3), y, method="DOP853", rtol=rtol, atol=rtol)
    t0, y = first.t[-1], first.y[:, -1]
    while True:
        heel.terminal = True
        sol = solve_ivp(f, (t0, t0 + 10.0), y, method="DOP853", rtol=rtol, atol=rtol, events=heel)
        te, ye = sol.t_events[0][0], sol.y_events[0][0]
        action, _, _, x_new, _ = model.reset(0, 0, ye, p, te)
        if action == EVENT_STRIDE:  # else a scuff behind the stance foot
            return x_new, te
        # scuff behind the stance foot: continue past it
        t0, y = te + 1e-9, sol.sol(te + 1e-9) if sol.sol is not None else ye
        step = solve_ivp(f, (te, te + 1e-3), ye, method="DOP853", rtol=rtol, atol=rtol)
        t0, y = step.t[-1], step.y[:, -1]


def tolerance_sweep(model_name="compass", tols=None, ref_rtol=3e-14):
    """Error of one stride from the fixed point against a run at ``ref_rtol``, per tolerance.

    Returns (rows, info): rows with ``rtol``, ``err`` (max-norm state error just after heel
    strike), ``err_t`` (step-time error), ``estimate`` (``Solution.error_estimate``),
    ``ratio`` = estimate / err, ``n_rhs``; info with the reference's cross-check against
    scipy DOP853 at rtol = atol = 1e-13.
    """
    from walker.simulation.stride import simulate

    if tols is None:
        tols = [10.0**-k for k in range(3, 14)]
    P, fp = fixed_point(model_name)
    x0 = fp.state
    ref = simulate(model_name, P.params, x0, rtol=ref_rtol, atol=ref_rtol)
    info = {"ref_rtol": ref_rtol}
    if model_name == "compass":
        xs, ts = scipy_stride(model_name, P.params, x0, 1e-13)
        info["scipy_state_diff"] = float(np.max(np.abs(xs - ref.x)))
        info["scipy_time_diff"] = abs(ts - ref.t)
    rows = []
    for tol in tols:
        sol = simulate(model_name, P.params, x0, rtol=tol, atol=tol)
        err = float(np.max(np.abs(sol.x - ref.x)))
        rows.append(
            {
                "rtol": tol,
                "status": sol.status.name,
                "err": err,
                "err_t": abs(sol.t - ref.t),
                "estimate": sol.error_estimate,
                "ratio": sol.error_estimate / err if err > 0 else math.inf,
                "n_rhs": sol.n_rhs,
            }
        )
    return rows, info


# =============================================================================================
# main
# =============================================================================================


def _write_csv(path: Path, rows: list[dict]) -> None:
    keys = []
    for r in rows:
        for k in r:
            if k not in keys:
                keys.append(k)
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--strides", type=int, default=100_000)
    ap.add_argument("--chunk", type=int, default=1000)
    ap.add_argument(
        "--time-limit",
        type=float,
        default=600.0,
        help="seconds per long run (stops at a chunk boundary)",
    )
    ap.add_argument("--quick", action="store_true", help="2000 strides, coarse grids")
    args = ap.parse_args(argv)
    if args.quick:
        args.strides = 2000
    OUT.mkdir(parents=True, exist_ok=True)
    report = {}

    # --- long runs
    t = time.perf_counter()
    rows: list[dict] = []
    report["long"] = [
        long_run(m, args.strides, args.chunk, rows=rows, time_limit=args.time_limit, restart_time=r)
        for r in (False, True)
        for m in ("compass", "kneed")
    ]
    _write_csv(OUT / "long_runs.csv", rows)
    print(f"long runs: {time.perf_counter() - t:.1f} s", report["long"])

    # --- grazing
    t = time.perf_counter()
    tols = [10.0**-k for k in range(3, 13)]
    durations = list(np.logspace(-8, 0, 33))
    grows: list[dict] = []
    report["graze"] = grazing_table(tols, durations, rows=grows)
    _write_csv(OUT / "grazing.csv", grows)
    report["scuff"] = compass_scuff_outcomes(tols)
    print(f"grazing: {time.perf_counter() - t:.1f} s")

    # --- scaling and extremes
    t = time.perf_counter()
    report["scaling"] = scaling_errors()
    _write_csv(OUT / "scaling.csv", report["scaling"])
    P, fp = fixed_point("compass")
    ext = []
    for label, prm in extreme_compass_cases():
        x0 = fp.state
        if label.startswith("length"):  # rates scale with sqrt(g / l)
            lam = float(label.split("*")[1])
            x0 = fp.state * np.array([1, 1, lam**-0.5, lam**-0.5])
        sol, sec = run_case("compass", prm, x0)
        ext.append(
            {
                "case": label,
                "status": sol.status.name,
                "strides": sol.n_strides,
                "seconds": sec,
                "finite": bool(np.all(np.isfinite(sol.x))),
            }
        )
    report["extreme"] = ext
    _write_csv(OUT / "extreme.csv", ext)
    print(f"scaling/extremes: {time.perf_counter() - t:.1f} s")

    # --- tolerance sweep
    t = time.perf_counter()
    sweep_rows, info = tolerance_sweep("compass")
    k_rows, k_info = tolerance_sweep("kneed")
    for r in sweep_rows:
        r["model"] = "compass"
    for r in k_rows:
        r["model"] = "kneed"
    _write_csv(OUT / "tolerance_sweep.csv", sweep_rows + k_rows)
    report["sweep"] = (sweep_rows, info, k_rows)
    print(f"tolerance sweep: {time.perf_counter() - t:.1f} s", info)
    write_readme(OUT / "README.md", report, args)


if __name__ == "__main__":
    main()
