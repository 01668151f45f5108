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
    state = _given_state(args.state, scene) if args.state is not None else None
    if args.from_gait and not scene.walker_model.has_strides:
        raise UsageError(f"--from-gait: model `{scene.model}` has no gait (no strides)")
    out = _check_out(args.out, overwrite=args.overwrite)
    c = scene.compute
    strides = c.strides if args.strides is None else args.strides
    start = "scene"
    if args.from_gait:
        fp = _gait(scene)
        if not fp.success:
            print(f"status {fp.status.name}: no gait to start from: {fp.message}")
            return EXIT_OUTCOME
        state, start = fp.state, "gait"
        print(f"starting from the gait found by `walker find` (residual {fp.residual:.2e})")
    elif state is not None:
        start = "state"
    if state is not None:
        scene = dataclasses.replace(scene, state=np.asarray(state, dtype=float))
    common = {
        **solver_settings(c),
        "t_max": c.t_max * max(1, strides),
        "n_strides": strides,
        "phase0": scene.phase if start == "scene" else None,
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
        extra = {"status": sol.status.name, "start": start}
        if start != "scene":
            extra["initial_state"] = [float(v) for v in scene.state]
        write_result(out, sol, scene, args, extra)
        print(f"wrote {out}")
    return EXIT_OK if sol.success else EXIT_OUTCOME


def _given_state(text: str, scene) -> np.ndarray:
    """``--state v1,v2,...``: as many finite numbers as the model has state entries."""
    names = tuple(scene.state_names)
    try:
        values = [float(v) for v in str(text).split(",")]
    except ValueError:
        raise UsageError(
            f"--state expects {len(names)} comma-separated numbers ({', '.join(names)}), "
            f"got {text!r}"
        ) from None
    if len(values) != len(names):
        raise UsageError(
            f"--state must have {len(names)} values for model {scene.model} "
            f"({', '.join(names)}), got {len(values)}"
        )
    bad = [name for name, v in zip(names, values, strict=True) if not math.isfinite(v)]
    if bad:
        raise UsageError(f"--state must be finite, got {text!r} (at {', '.join(bad)})")
    return np.array(values)


def _gait(scene):
    """The scene's gait, as ``walker find`` gives it (period: the scene's strides)."""
    from walker.fixedpoint import find_fixed_point
    from walker.stride import StrideMap

    P = StrideMap.from_scene(scene)
    period = max(1, scene.compute.strides)
    return find_fixed_point(P, P.project(scene.state), period=period, tol=scene.compute.tol)


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
    start = p.add_mutually_exclusive_group()
    start.add_argument(
        "--from-gait",
        action="store_true",
        help="start from the scene's gait, the fixed point `walker find` gives, instead of "
        "the scene's [initial] state (default: the scene's state)",
    )
    start.add_argument(
        "--state",
        metavar="V1,V2,...",
        default=None,
        help="start from this full state, one number per state entry in the model's order "
        "(`walker models MODEL`); write --state=-0.1,... when the first is negative "
        "(default: the scene's [initial] state)",
    )
    p.add_argument("--overwrite", action="store_true", help="replace an existing --out")
    p.set_defaults(func=cmd_run)
