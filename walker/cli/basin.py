"""``walker basin``: the basin of attraction on a 2-D slice of the section, checkpointed."""

from __future__ import annotations

import math
import sys

import numpy as np

from ._common import (
    BASIN_TOL,
    EXIT_OK,
    EXIT_OUTCOME,
    UsageError,
    _check_out,
    _load,
    _positive_flag,
    _resume_hint,
    _stride_map,
    jobs_option,
    provenance,
    resumable_options,
    say_resuming,
    scene_cmd,
)


def cmd_basin(args) -> int:
    from walker.analysis.basin import basin_map
    from walker.analysis.fixedpoint import find_fixed_point
    from walker.results import too_large
    from walker.storage import BasinStore, CheckpointMismatch, checkpoint_progress

    if args.n < 2:
        raise UsageError(f"--n must be >= 2, got {args.n}")
    # outcome and stride count (int64 each) per grid point, in memory and in the file
    reason = too_large(16.0 * args.n * args.n)
    if reason is not None:
        raise UsageError(
            f"--n {args.n} gives a grid of {args.n * args.n:,} points, which {reason}; lower --n"
        )
    _positive_flag(args.strides, "--strides", minimum=1, integer=True)
    radius = args.converge_radius.strip().lower()
    if radius != "auto":
        try:
            radius = float(radius)
        except ValueError:
            radius = -1.0
        if not (math.isfinite(radius) and radius >= 0):
            raise UsageError(
                f"--converge-radius must be 'auto' or a number >= 0, got {args.converge_radius!r}"
            )
    if not (math.isfinite(args.span) and args.span > 0):
        raise UsageError(f"--span must be a positive number, got {args.span}")
    bounds = _absolute_bounds(args.lo, args.hi)
    if args.jobs is not None and args.jobs < 1:
        raise UsageError(f"--jobs must be >= 1, got {args.jobs}")
    if args.jobs is not None and args.scheduler is not None:
        print(
            "walker: warning: --jobs has no effect with --scheduler (the cluster decides)",
            file=sys.stderr,
        )
        args.jobs = None
    if args.scheduler is not None:
        from .sweep import need_dask

        need_dask()
    scene = _load(args)
    P = _stride_map(scene)
    P_basin, extra = P, {}
    if args.rtol is not None:
        # the basin's strides at another rtol (atol scaled with it); the gait at the scene's
        if not (math.isfinite(args.rtol) and args.rtol > 0):
            raise UsageError(f"--rtol must be a positive number, got {args.rtol}")
        try:
            P_basin = P.with_tolerance(args.rtol, min(P.atol * args.rtol / P.rtol, args.rtol))
        except ValueError as exc:
            raise UsageError(f"--rtol: {exc}") from None
        extra = {"basin_rtol": P_basin.rtol, "basin_atol": P_basin.atol}
    section = list(P.section_names)
    axes = tuple(
        section.index(a.strip())
        if a.strip() in section
        else int(a)
        if a.strip().lstrip("-").isdigit()
        else -1
        for a in args.axes.split(",")
    )
    if len(axes) != 2 or not all(0 <= a < P.n_z for a in axes) or axes[0] == axes[1]:
        listed = ", ".join(f"{i} {n}" for i, n in enumerate(section))
        raise UsageError(
            f"--axes must be two distinct section coordinates, by index or name ({listed}), "
            f"such as 0,1, got {args.axes!r}"
        )
    out = _check_out(
        args.out, overwrite=args.overwrite, resumable=True, size=16 * args.n * args.n + (1 << 20)
    )
    prov = provenance(scene, extra, out=out)
    if not args.overwrite:
        # Refuse an unrelated file before the fixed point is searched for; the grid itself
        # (which needs the fixed point) is compared when the checkpoint is opened.
        names = tuple(P.section_names)
        try:
            BasinStore.check_existing(
                out,
                provenance=prov,
                axis_names=(names[axes[0]], names[axes[1]]),
                shape=(args.n, args.n),
                n_strides=args.strides,
                tol=BASIN_TOL,
            )
        except CheckpointMismatch as exc:
            raise _resume_hint(exc) from None
        progress = checkpoint_progress(out) if out.exists() else None
        if progress is not None:
            say_resuming(out, *progress)
    fp = find_fixed_point(P, P.project(scene.state))
    if not fp.success:
        print(f"status {fp.status.name}: no gait to map the basin of: {fp.message}")
        return EXIT_OUTCOME
    span = args.span
    ranges = bounds or tuple(
        (
            fp.section[a] - span * max(abs(fp.section[a]), 0.1),
            fp.section[a] + span * max(abs(fp.section[a]), 0.1),
        )
        for a in axes
    )
    run = dict(
        axes=axes,
        ranges=ranges,
        n=(args.n, args.n),
        n_strides=args.strides,
        tol=BASIN_TOL,
        converge_radius=radius,
        progress=not args.quiet,
        out=out,
        overwrite=args.overwrite,
        provenance=prov,
    )
    try:
        if args.scheduler is None:
            bm = basin_map(P_basin, fp, jobs=args.jobs, **run)
        else:  # tasks are chunks of grid rows, on the cluster's workers
            from .sweep import connect_scheduler

            with connect_scheduler(args.scheduler) as client:
                bm = basin_map(P_basin, fp, executor=client, **run)
    except CheckpointMismatch as exc:
        raise _resume_hint(exc) from None
    from walker.results import BASIN_CONVERGED

    frac = float(np.mean(bm.outcome == BASIN_CONVERGED))
    print(f"wrote {out}: {args.n}x{args.n} points, {frac:.1%} converge to the gait")
    return EXIT_OK


def _absolute_bounds(lo, hi):
    """``--lo A,B`` and ``--hi C,D``: the two axes' ranges ``((A, C), (B, D))``, or None
    when neither is given (``--span`` then sets them)."""
    if lo is None and hi is None:
        return None
    if lo is None or hi is None:
        given, missing = ("--lo", "--hi") if hi is None else ("--hi", "--lo")
        raise UsageError(f"{given} needs {missing} too (one value per axis each)")
    parsed = []
    for flag, text in (("--lo", lo), ("--hi", hi)):
        try:
            values = [float(v) for v in str(text).split(",")]
        except ValueError:
            raise UsageError(
                f"{flag} expects two numbers A,B (one per axis), got {text!r}"
            ) from None
        if len(values) != 2 or not all(math.isfinite(v) for v in values):
            raise UsageError(f"{flag} expects two finite numbers A,B (one per axis), got {text!r}")
        parsed.append(values)
    (lo_x, lo_y), (hi_x, hi_y) = parsed
    for k, (a, b) in enumerate(((lo_x, hi_x), (lo_y, hi_y))):
        if not a < b:
            raise UsageError(
                f"--lo must be below --hi on each axis, got {a:g} >= {b:g} on axis {k}"
            )
    return ((lo_x, hi_x), (lo_y, hi_y))


def register(sub) -> None:
    p = scene_cmd(sub, "basin", "map the basin of attraction on a 2-D slice of the section")
    p.add_argument(
        "--out",
        metavar="FILE",
        required=True,
        help="HDF5 checkpoint and result; rerunning the same command resumes it (required)",
    )
    p.add_argument(
        "--axes",
        default="0,1",
        metavar="I,J",
        help="the two section coordinates to vary, by index or name; `walker models MODEL` "
        "lists a model's section coordinates with their indices (compass: 0 q_stance, "
        "1 qd_stance, 2 qd_swing)",
    )
    p.add_argument("--n", type=int, default=50, help="grid points per axis, >= 2")
    p.add_argument(
        "--span",
        type=float,
        default=0.5,
        help="half-width of each axis: SPAN times the size of the fixed point's coordinate "
        "(its magnitude, or 0.1 where that is smaller); --lo/--hi replace it",
    )
    p.add_argument(
        "--lo",
        metavar="A,B",
        default=None,
        help="absolute lower ends of the two axes, in --axes order and the coordinates' units "
        "(with --hi; write --lo=-1,0 when the first is negative) (default: from --span)",
    )
    p.add_argument(
        "--hi",
        metavar="A,B",
        default=None,
        help="absolute upper ends of the two axes (with --lo) (default: from --span)",
    )
    p.add_argument(
        "--strides",
        type=int,
        default=40,
        help="most strides per grid point; a point neither converged nor fallen by then is "
        "undecided (convergence to 1e-6 from the --span offsets takes about 25 strides at a "
        "largest |multiplier| of 0.6)",
    )
    p.add_argument(
        "--converge-radius",
        default="auto",
        metavar="R",
        help="a point is converged when within 1e-6 of the gait (max norm), or, stopping "
        "early, inside the ball where the stride map is a contraction: 'auto' derives that "
        "ball from the gait's Jacobian and a sampled bound on the map's second derivative "
        "(docs/basins.md); a number R > 0 uses radius R in the same norm (a ball inside "
        "max|z - z*| <= R); 0 turns the early stop off. The file records it "
        "(classification); default: auto",
    )
    jobs_option(p)
    p.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="dask.distributed scheduler address, e.g. tcp://host:8786: the chunks of grid rows "
        "run on that cluster (default: none, run on this machine)",
    )
    p.add_argument(
        "--rtol",
        type=float,
        default=None,
        help="relative tolerance of the basin's strides, atol scaled with it (stored in the "
        "file as basin_rtol, basin_atol); the gait is still found at the scene's [compute] "
        "tolerances. A basin decides convergence at 1e-6: on the compass walking slice "
        "(results/bench/basin.md) --rtol 1e-9 gave the same outcome at every grid point as "
        "the scene's 1e-12, in about half the time; default: the scene's",
    )
    resumable_options(p)
    p.set_defaults(func=cmd_basin)
