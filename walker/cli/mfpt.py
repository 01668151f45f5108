"""``walker mfpt``: the mean first-passage time of a scene's gait on random terrain
(:mod:`walker.analysis.mfpt`, :mod:`walker.analysis.markov`)."""

from __future__ import annotations

import math

from ._common import (
    EXIT_OK,
    EXIT_OUTCOME,
    UsageError,
    _check_out,
    _json,
    _load,
    _positive_flag,
    _resume_hint,
    _stride_map,
    json_flag,
    provenance,
    say_resuming,
    scene_cmd,
)


def _nonnegative(value, flag):
    if value is not None and not (math.isfinite(value) and value >= 0.0):
        raise UsageError(f"{flag} must be a finite number >= 0, got {value}")
    return value


def _gait(scene, P, mean):
    """(map on the mean slope, its gait) or (None, message)."""
    from walker.analysis.fixedpoint import find_fixed_point

    Q = P if mean == P.params.slope else P.with_params(slope=mean)
    fp = find_fixed_point(Q, Q.project(scene.state))
    if not fp.success:
        return None, f"no period-one gait on the mean slope {mean:g} ({fp.status.name})"
    return Q, fp.section


def cmd_mfpt(args) -> int:
    from walker.analysis.markov import markov_chain
    from walker.analysis.mfpt import monte_carlo
    from walker.simulation._terrain_run import check_supported

    _nonnegative(args.std, "--std")
    _nonnegative(args.height_std, "--height-std")
    _positive_flag(args.runs, "--runs", minimum=1, integer=True)
    _positive_flag(args.markov_levels, "--markov-levels", minimum=2, integer=True)
    if args.seed < 0:
        raise UsageError(f"--seed must be an integer >= 0, got {args.seed}")
    if args.jobs is not None and args.jobs < 1:
        raise UsageError(f"--jobs must be an integer >= 1, got {args.jobs}")
    _positive_flag(args.max_steps, "--max-steps", minimum=1, integer=True)
    _positive_flag(args.chunk_runs, "--chunk-runs", minimum=1, integer=True)
    if args.mean is not None and not math.isfinite(args.mean):
        raise UsageError(f"--mean must be a finite number, got {args.mean}")
    if args.markov and args.height_std > 0.0:
        raise UsageError("--markov needs --height-std 0 (the chain's terrain is random slopes)")
    if args.markov and args.std == 0.0:
        raise UsageError("--markov needs --std > 0")
    scene = _load(args)
    P = _stride_map(scene)
    try:
        check_supported(P)
    except ValueError as exc:
        raise UsageError(f"{args.scene}: {exc}") from None
    out = _check_out(args.out, overwrite=args.overwrite, resumable=True)
    mean = scene.params.slope if args.mean is None else float(args.mean)
    P, z0 = _gait(scene, P, mean)
    if P is None:
        print(f"walker: {z0}")
        return EXIT_OUTCOME
    jobs = args.jobs or 1
    stored = {}
    if out is not None:
        from walker.storage import checkpoint_progress

        # The runs' checkpoint: the scene file and the command; the estimate adds the rest.
        scene_path = provenance(scene, out=out)["scene"]
        stored = {"checkpoint": out, "overwrite": args.overwrite}
        stored["provenance"] = {"scene": scene_path, "command": "mfpt"}
        progress = None if args.overwrite else checkpoint_progress(out, verify=False)
        if progress is not None:
            say_resuming(out, *progress)
    from walker.storage import CheckpointMismatch

    client = None
    if args.scheduler is not None:
        from .sweep import connect_scheduler

        client = connect_scheduler(args.scheduler)  # before any work; a UsageError if none
    try:
        result = monte_carlo(
            P,
            z0,
            slope_std=args.std,
            height_std=args.height_std,
            runs=args.runs,
            seed=args.seed,
            jobs=jobs,
            max_steps=args.max_steps,
            chunk_runs=args.chunk_runs,
            executor=client,
            **stored,
        )
    except CheckpointMismatch as exc:
        raise _resume_hint(exc) from None
    finally:
        if client is not None:
            client.close()
    if args.markov:
        result.markov = markov_chain(
            P, z0, slope_std=args.std, seed=args.seed, jobs=jobs, max_levels=args.markov_levels
        )
    record = {"scene": str(scene.path), "model": scene.model, **result.as_dict()}
    if out is not None:
        from walker.storage import write

        # The finished result replaces the runs' checkpoint (atomically).
        prov = provenance(scene, {"command": "mfpt", "jobs": jobs}, out=out)
        write(out, result, provenance=prov, overwrite=True)
    if args.json:
        print(_json(record))
    else:
        _print(record)
    return EXIT_OK


def _print(r: dict) -> None:
    print(f"scene       {r['scene']}  (model {r['model']})")
    print(
        f"terrain     slope N({r['slope_mean']:g}, {r['slope_std']:g}^2) rad, drop "
        f"N(0, {r['height_std']:g}^2) m, every step"
    )
    print(
        f"runs        {r['runs']} (seed {r['seed']}), failed {r['failed']}, censored at "
        f"{r['max_steps']} steps: {r['censored']}"
    )
    print(f"MFPT        {r['mfpt']:.6g} +- {r['mfpt_stderr']:.2g} steps (Monte Carlo)")
    print(f"rate        {r['rate']:.6g} failures per step (geometric fit)")
    for name, count in r["failures"].items():
        print(f"  {name:<20s} {count}")
    if "mfpt_markov" in r:
        m = r["markov"]
        print(
            f"Markov      1/(1 - lambda_2) = {r['mfpt_markov']:.6g} steps, from the start "
            f"{r['mfpt_markov_start']:.6g} (last change {m['change']:.2%}, "
            f"{'converged' if m['converged'] else 'NOT converged: raise --markov-levels'})"
        )


def register(sub) -> None:
    p = scene_cmd(sub, "mfpt", "mean first-passage time on random terrain (Monte Carlo, Markov)")
    p.add_argument(
        "--std", type=float, required=True, help="slope standard deviation [rad], >= 0 (required)"
    )
    p.add_argument(
        "--mean", type=float, default=None, help="mean slope [rad] (default: the scene's slope)"
    )
    p.add_argument(
        "--height-std",
        type=float,
        default=0.0,
        help="drop standard deviation [m], >= 0 (default: 0)",
    )
    p.add_argument("--runs", type=int, required=True, help="Monte-Carlo runs, >= 1 (required)")
    p.add_argument("--seed", type=int, required=True, help="root seed, >= 0 (required)")
    p.add_argument(
        "--jobs", type=int, default=None, help="threads; the result is the same (default: 1)"
    )
    p.add_argument(
        "--max-steps",
        type=int,
        default=1 << 16,
        help="censoring horizon [steps] (default: 65536)",
    )
    p.add_argument(
        "--markov",
        action="store_true",
        help="also the Markov-chain MFPT 1/(1 - lambda_2) (slopes only; default: off)",
    )
    p.add_argument(
        "--markov-levels",
        type=int,
        default=4,
        help="refinement levels of the chain at most, each 1.5x the slope nodes and mesh "
        "points of the one before; it stops once both estimates move < 2 %% (default: 4)",
    )
    p.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="dask.distributed scheduler address, e.g. tcp://host:8786: chunks of --chunk-runs "
        "runs are its tasks, each on --jobs threads; the result is the same (default: none)",
    )
    p.add_argument(
        "--chunk-runs",
        type=int,
        default=256,
        help="runs per checkpoint chunk of --out and per --scheduler task (default: 256)",
    )
    json_flag(p)
    p.add_argument(
        "--out",
        metavar="FILE",
        help="also store the result (HDF5, kind mfpt) in this file; while the runs walk it is "
        "their checkpoint: Ctrl-C keeps the finished chunks and the same command resumes "
        "(default: none)",
    )
    p.add_argument(
        "--overwrite", action="store_true", help="replace an existing --out instead of resuming"
    )
    p.set_defaults(func=cmd_mfpt)
