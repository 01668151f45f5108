"""``walker run``: simulate strides from a scene's state and store the trajectory."""

from __future__ import annotations

import argparse
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

BLOCK_STRIDES = 1000
"""Strides per block of a long ``walker run``: a run of more strides is integrated block
after block, each continuing from the last one's final state (a block ends just after a
heel strike, where the integrator restarts its step anyway), and its events, samples and
steps are streamed to ``--out`` (:class:`walker.storage.stream.SolutionStream`), so memory
stays bounded whatever ``--strides``."""

MAX_STEPS_LIMIT = 2**62
"""Largest ``--max-steps`` (the compiled loop counts steps in 64-bit integers)."""


def run_budget(scene, strides: int) -> int:
    """The default step budget of ``walker run``: the stride map's per-stride budget
    (:func:`walker.simulation.region.stride_max_steps` at the scene's ``t_max``) times the strides,
    and at least 1,000,000 (the former fixed budget)."""
    from walker.simulation.region import stride_max_steps

    c = scene.compute
    per_stride = stride_max_steps(scene.params, c.t_max, c.method, c.first_step)
    return int(min(MAX_STEPS_LIMIT, max(1_000_000, per_stride * max(1, strides))))


def cmd_run(args) -> int:
    from walker.simulation.stride import solver_settings

    if args.strides is not None and args.strides < 0:
        raise UsageError(f"--strides must be >= 0, got {args.strides}")
    if args.strides is not None and args.strides > MAX_STRIDES:
        raise UsageError(f"--strides must be <= {MAX_STRIDES:,}, got {args.strides}")
    if args.sample_rate is not None and not (
        args.sample_rate > 0 and math.isfinite(args.sample_rate)
    ):
        raise UsageError(f"--sample-rate must be a positive number, got {args.sample_rate}")
    if args.max_steps is not None and not 1 <= args.max_steps <= MAX_STEPS_LIMIT:
        raise UsageError(f"--max-steps must be an integer in [1, 2**62], got {args.max_steps}")
    scene = _load(args)
    terrain = _terrain(scene, args)
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
    budget = run_budget(scene, strides) if args.max_steps is None else args.max_steps
    depth = args.swing_depth if args.swing_depth is not None else strides <= BLOCK_STRIDES
    common = {
        **solver_settings(c),
        "t_max": c.t_max * max(1, strides),
        "phase0": scene.phase if start == "scene" else None,
        "max_steps": budget,
    }
    if not terrain.is_plane:
        # one row a stride (--strides 0: the first TERRAIN_ROWS strides, then the plane)
        common["terrain"] = terrain.steps(strides if strides > 0 else TERRAIN_ROWS)
    # A run on terrain is integrated in one piece: a block's start would not know the plane
    # the previous block's last step landed on.
    if strides <= BLOCK_STRIDES or not terrain.is_plane:
        sol = _one_block(scene, args, dict(common, n_strides=strides), "full", 0)[0]
        pen = _penetration(scene, sol) if depth else None
        if scene.walker_model.has_strides and sol.events is not None:
            from walker.analysis.measures import run_measures

            measures = run_measures(scene.walker_model, scene.params, sol, scene.state)
            sol = dataclasses.replace(sol, measures=measures.to_dict())
        if out is not None:
            extra = {"status": sol.status.name, "start": start}
            if start != "scene":
                extra["initial_state"] = [float(v) for v in scene.state]
            if not terrain.is_plane:
                extra["terrain"] = terrain.as_dict()
                # the rows of the steps the run stood on: `walker plot` draws its ground
                used = common["terrain"][: sol.n_strides + 1]
                extra["terrain_rows"] = [[float(a), float(b)] for a, b in used]
            write_result(out, sol, scene, args, extra)
    else:
        sol, pen = _blocks(scene, args, common, strides, out, depth)
    print(f"status {sol.status.name}: {sol.message}")
    print(
        f"t = {sol.t:.12g} s, strides {sol.n_strides}, events {sol.n_events}, "
        f"steps {sol.n_steps} ({sol.n_rejected} rejected), rhs {sol.n_rhs}"
    )
    if pen is not None:
        _print_penetration(scene, pen)
    print_measures(sol.measures, "gait measures up to the last step (energy per step):")
    if out is not None:
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
    from walker.analysis.fixedpoint import find_fixed_point
    from walker.simulation.stride import StrideMap

    P = StrideMap.from_scene(scene)
    period = max(1, scene.compute.strides)
    return find_fixed_point(P, P.project(scene.state), period=period, tol=scene.compute.tol)


TERRAIN_ROWS = 10_000
"""Steps of terrain drawn for ``walker run --strides 0`` (the plane after them)."""


def _terrain(scene, args):
    """The run's ground: the scene's ``[terrain]`` with the command line's ``--terrain-std``,
    ``--terrain-height-std`` and ``--seed`` on top (either std makes it ``random``); a
    random ground without a seed gets a fresh one, printed and recorded."""
    from walker.simulation.terrain import Terrain

    terrain = scene.terrain
    std, height_std, seed = args.terrain_std, args.terrain_height_std, args.seed
    for flag, value in (("--terrain-std", std), ("--terrain-height-std", height_std)):
        if value is not None and not (math.isfinite(value) and value >= 0):
            raise UsageError(f"{flag} must be a finite number >= 0, got {value}")
    if seed is not None and seed < 0:
        raise UsageError(f"--seed must be >= 0, got {seed}")
    if std is not None or height_std is not None:
        base = terrain if terrain.kind == "random" else None
        terrain = Terrain(
            "random",
            slope_mean=terrain.slope_mean,
            slope_std=std if std is not None else (base.slope_std if base else 0.0),
            height_std=height_std if height_std is not None else (base.height_std if base else 0.0),
            seed=seed if seed is not None else (base.seed if base else None),
        )
    elif seed is not None and terrain.kind == "random":
        terrain = Terrain(**{**terrain.as_dict(), "seed": seed})
    if terrain.kind == "random" and not terrain.is_plane and terrain.seed is None:
        terrain = Terrain(
            **{**terrain.as_dict(), "seed": int(np.random.SeedSequence().entropy % 2**63)}
        )
    if not terrain.is_plane:
        from walker.simulation._terrain_run import check_model

        model = scene.walker_model
        try:
            check_model(model, scene.params, model.system_for(scene.params.as_array()))
        except ValueError as exc:
            raise UsageError(str(exc)) from None
        print(f"terrain: {terrain.kind}, {_terrain_summary(terrain)}")
    return terrain


def _terrain_summary(terrain) -> str:
    if terrain.kind == "steps":
        return f"{max(len(terrain.slopes), len(terrain.heights))} steps, then the plane"
    return (
        f"slope N({terrain.slope_mean:.6g}, {terrain.slope_std:.3g}^2) rad, drop "
        f"N(0, {terrain.height_std:.3g}^2) m, seed {terrain.seed}"
    )


def _one_block(scene, args, run: dict, output: str, first_sample: int):
    """One run of ``run`` (simulate's settings) with ``output`` (``--sample-rate``: samples
    ``first_sample, first_sample + 1, ...`` of the run's grid of sample times up to where it
    ends, found by a first run with events only).  Returns the Solution and the index of the
    next sample."""
    from walker.simulation.stride import check_sample_count, simulate

    model, params, x0 = scene.walker_model, scene.params, run.pop("x0", scene.state)
    if args.sample_rate is None:
        return simulate(model, params, x0, output=output, **run), first_sample
    first = simulate(model, params, x0, output="events", **run)
    step = 1.0 / args.sample_rate
    t0 = run.get("t0", 0.0)
    try:
        check_sample_count(first.t - t0, args.sample_rate, len(scene.state), "--sample-rate")
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    if first_sample == 0:
        times = np.arange(0.0, first.t, step)  # as a run in one piece
    else:
        last = int(math.ceil(first.t / step))
        times = np.arange(first_sample, max(first_sample, last)) * step
        times = times[times < first.t]
    sol = simulate(model, params, x0, output="samples", sample_times=times, **run)
    return sol, first_sample + (0 if sol.samples is None else len(sol.samples))


def _blocks(scene, args, common: dict, strides: int, out, depth: bool):
    """A long run, :data:`BLOCK_STRIDES` strides at a time, streamed to ``out``.  Returns
    the run's Solution (final state and summed counters, no arrays) and the deepest swing
    foot penetration (``depth``) or None."""
    import dataclasses

    from walker.cli._common import provenance

    output = "full" if out is not None or depth else "map"
    x, phase, t, done, used, next_sample = scene.state, scene.phase, 0.0, 0, 0, 0
    totals = dict.fromkeys(("n_steps", "n_rejected", "n_rhs", "n_events", "n_strides"), 0)
    error = 0.0
    pen = stream = None
    try:
        while True:
            k = min(BLOCK_STRIDES, strides - done)
            run = dict(common, n_strides=k, phase0=phase, t0=t, x0=x)
            run["max_steps"] = common["max_steps"] - used
            block, next_sample = _one_block(scene, args, run, output, next_sample)
            if out is not None and stream is None:
                from walker.storage.stream import SolutionStream

                prov = provenance(scene, {"status": "RUNNING"}, out=out)
                stream = SolutionStream(out, block, provenance=prov, overwrite=args.overwrite)
            elif stream is not None:
                stream.append(block)
            if depth:
                here = _penetration(scene, block)
                if here is not None and (pen is None or here.depth > pen.depth):
                    pen = here
            for name in totals:
                totals[name] += getattr(block, name)
            error += block.error_estimate
            used += block.n_steps + block.n_rejected
            done += block.n_strides
            x, phase, t = block.x, block.phase, block.t
            if not block.success or done >= strides:
                break
        sol = dataclasses.replace(
            block, events=None, samples=None, record=None, error_estimate=error, **totals
        )
        if stream is not None:
            stream.prov["status"] = sol.status.name
            stream.f.attrs.update(_status_attrs(stream, sol))
            stream.finish(sol)
    finally:
        if stream is not None:
            stream.__exit__(None, None, None)
    return sol, pen


def _status_attrs(stream, sol) -> dict:
    """The root attributes that carry the final status (written ``RUNNING`` at the start)."""
    import json

    stream.prov["status"] = sol.status.name
    return {"status": sol.status.name, "provenance": json.dumps(stream.prov)}


def _penetration(scene, sol):
    """For models that report it (kneed), how deep the swing foot went below the slope in
    ``sol``; None for other models or a run without stored states."""
    deepest = getattr(scene.walker_model.module, "deepest_penetration", None)
    if deepest is None or (sol.record is None and sol.samples is None):
        return None
    return deepest(sol, scene.params)


def _print_penetration(scene, pen) -> None:
    """How deep the swing foot went below the slope (:func:`_penetration`): what the
    swing-foot scuffing convention let pass."""
    convention = f"swing_scuff = {scene.swing_scuff}"
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
    p.add_argument(
        "--max-steps",
        type=int,
        default=None,
        metavar="N",
        help="step budget of the whole run (accepted + rejected steps; default: the stride "
        "map's per-stride budget times --strides, at least 1,000,000)",
    )
    p.add_argument(
        "--swing-depth",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="report how deep the kneed walker's swing foot went below the slope (default: "
        f"for runs of at most {BLOCK_STRIDES} strides)",
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
    p.add_argument(
        "--terrain-std",
        type=float,
        default=None,
        metavar="RAD",
        help="walk on random terrain: the per-step slope's standard deviation [rad] about the "
        "scene's slope (default: the scene's [terrain], the plane without one)",
    )
    p.add_argument(
        "--terrain-height-std",
        type=float,
        default=None,
        metavar="M",
        help="random terrain: the per-step drop's standard deviation [m] (default: the "
        "scene's [terrain], 0)",
    )
    p.add_argument(
        "--seed",
        type=int,
        default=None,
        help="seed of the random terrain's draws (default: the scene's [terrain] seed, else a "
        "fresh one, printed and recorded)",
    )
    p.add_argument("--overwrite", action="store_true", help="replace an existing --out")
    p.set_defaults(func=cmd_run)
