"""``walker run``: simulate strides from a scene's state and store the trajectory."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ._common import (
    EXIT_OK,
    EXIT_OUTCOME,
    MAX_STRIDES,
    UsageError,
    _check_out,
    _load,
    print_measures,
    scene_cmd,
    write_result,
)


def cmd_run(args) -> int:
    from walker.stride import check_sample_count, simulate, solver_settings

    if args.strides is not None and args.strides < 0:
        raise UsageError(f"--strides must be >= 0, got {args.strides}")
    if args.strides is not None and args.strides > MAX_STRIDES:
        raise UsageError(f"--strides must be <= {MAX_STRIDES:,}, got {args.strides}")
    if args.sample_rate is not None and not (
        args.sample_rate > 0 and math.isfinite(args.sample_rate)
    ):
        raise UsageError(f"--sample-rate must be a positive number, got {args.sample_rate}")
    scene = _load(args)
    out = _check_out(args.out, overwrite=args.overwrite)
    c = scene.compute
    strides = c.strides if args.strides is None else args.strides
    common = {
        **solver_settings(c),
        "t_max": c.t_max * max(1, strides),
        "n_strides": strides,
        "phase0": scene.phase,
    }
    if args.sample_rate is None:
        sol = simulate(scene.walker_model, scene.params, scene.state, output="full", **common)
    else:
        first = simulate(scene.walker_model, scene.params, scene.state, output="events", **common)
        try:
            check_sample_count(first.t, args.sample_rate, len(scene.state), "--sample-rate")
        except ValueError as exc:
            raise UsageError(str(exc)) from None
        times = np.arange(0.0, first.t, 1.0 / args.sample_rate)
        sol = simulate(
            scene.walker_model,
            scene.params,
            scene.state,
            output="samples",
            sample_times=times,
            **common,
        )
    if scene.walker_model.has_strides and sol.events is not None:
        from walker.measures import run_measures

        measures = run_measures(scene.walker_model, scene.params, sol, scene.state)
        sol = dataclasses.replace(sol, measures=measures.to_dict())
    print(f"status {sol.status.name}: {sol.message}")
    print(
        f"t = {sol.t:.12g} s, strides {sol.n_strides}, events {sol.n_events}, "
        f"steps {sol.n_steps} ({sol.n_rejected} rejected), rhs {sol.n_rhs}"
    )
    _print_penetration(scene, sol)
    print_measures(sol.measures, "gait measures up to the last step (energy per step):")
    if out is not None:
        write_result(out, sol, scene, args, {"status": sol.status.name})
        print(f"wrote {out}")
    return EXIT_OK if sol.success else EXIT_OUTCOME


def _print_penetration(scene, sol) -> None:
    """For models that report it (kneed), how deep the swing foot went below the slope: what
    the swing-foot scuffing convention let pass."""
    deepest = getattr(scene.walker_model.module, "deepest_penetration", None)
    if deepest is None:
        return
    convention = f"swing_scuff = {scene.swing_scuff}"
    pen = deepest(sol, scene.params)
    if pen.depth == 0.0:
        print(f"swing foot never below the slope ({convention})")
        return
    where = f"{abs(pen.ahead):.4g} m {'ahead of' if pen.ahead >= 0 else 'behind'}"
    knee = (
        "knee locked"
        if pen.phase == 1
        else "knee straight, unlocked"
        if pen.knee_bend == 0.0
        else f"knee bent {pen.knee_bend:.4g} rad"
    )
    print(
        f"swing foot at most {pen.depth * 1e3:.4g} mm below the slope, at t = {pen.t:.6g} s, "
        f"{where} the stance foot, {knee} ({convention})"
    )


def register(sub) -> None:
    p = scene_cmd(sub, "run", "simulate strides and store the trajectory")
    p.add_argument(
        "--strides",
        type=int,
        default=None,
        help="strides to run, 0 = integrate to t_max (default: the scene's [compute] strides)",
    )
    p.add_argument(
        "--out", metavar="FILE", help="HDF5 file to write the run to (default: none, summary only)"
    )
    p.add_argument(
        "--sample-rate",
        type=float,
        default=None,
        metavar="HZ",
        help="store samples at this rate [1/s] instead of every step (default: every step)",
    )
    p.add_argument("--overwrite", action="store_true", help="replace an existing --out")
    p.set_defaults(func=cmd_run)
