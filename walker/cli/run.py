"""``walker run``: simulate strides from a scene's state and store the trajectory."""

from __future__ import annotations

import math

import numpy as np

from ._common import (
    EXIT_OK,
    EXIT_OUTCOME,
    MAX_STRIDES,
    UsageError,
    _check_out,
    _load,
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
    terrain = _terrain(scene, args)
    out = _check_out(args.out, overwrite=args.overwrite)
    c = scene.compute
    strides = c.strides if args.strides is None else args.strides
    common = {
        **solver_settings(c),
        "t_max": c.t_max * max(1, strides),
        "n_strides": strides,
        "phase0": scene.phase,
    }
    if not terrain.is_plane:
        # one row a stride (--strides 0: the first TERRAIN_ROWS strides, then the plane)
        common["terrain"] = terrain.steps(strides if strides > 0 else TERRAIN_ROWS)
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
    print(f"status {sol.status.name}: {sol.message}")
    print(
        f"t = {sol.t:.12g} s, strides {sol.n_strides}, events {sol.n_events}, "
        f"steps {sol.n_steps} ({sol.n_rejected} rejected), rhs {sol.n_rhs}"
    )
    _print_penetration(scene, sol)
    if out is not None:
        extra = {"status": sol.status.name}
        if not terrain.is_plane:
            extra["terrain"] = terrain.as_dict()
        write_result(out, sol, scene, args, extra)
        print(f"wrote {out}")
    return EXIT_OK if sol.success else EXIT_OUTCOME


TERRAIN_ROWS = 10_000
"""Steps of terrain drawn for ``walker run --strides 0`` (the plane after them)."""


def _terrain(scene, args):
    """The run's ground: the scene's ``[terrain]`` with the command line's ``--terrain-std``,
    ``--terrain-height-std`` and ``--seed`` on top (either std makes it ``random``); a
    random ground without a seed gets a fresh one, printed and recorded."""
    from walker.terrain import Terrain

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
        from walker._terrain_run import check_model

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
