"""``walker orbit-diagram``: where the walker settles as a parameter changes (brute force).

At each of ``--n`` values from A to B (in that order, so ``B < A`` sweeps downward) the
stride map is iterated ``--transient`` strides from the last point of the previous value (the
first value starts from the scene's gait), then ``--strides`` more whose section coordinate
``--coordinate`` is recorded (:func:`walker.analysis.continuation.orbit_diagram`).  The result is
written atomically to ``--out``; the summary names the period the walker settled on over
each stretch of the range.
"""

from __future__ import annotations

import sys

import numpy as np

from walker.results import too_large

from ._common import (
    EXIT_OK,
    EXIT_OUTCOME,
    UsageError,
    _check_out,
    _json,
    _load,
    _positive_flag,
    _stride_map,
    jobs_option,
    scene_cmd,
    write_result,
)
from .branch import check_param, check_walker, parse_range

PERIOD_TOL = 1e-8
"""Two recorded values closer than this (section units, absolute) count as the same point."""

DECAY = 0.9
"""An alternation whose amplitude shrinks below this fraction over half the recorded strides
is a transient, not a period (see :func:`settled_period`)."""


def settled_period(row: np.ndarray, tol: float = PERIOD_TOL) -> int | None:
    """Smallest ``k <= len(row) // 2`` with ``|row[i + k] - row[i]| <= tol`` for every ``i``;
    0 when the walker fell (a NaN in the row); None when there is none (chaotic,
    quasi-periodic, or not settled within the transient).

    Near a period doubling the walker approaches its period-``j`` orbit slowly, alternating
    about it with a shrinking amplitude that looks like period ``2 j``: a row whose distance
    from period ``j`` (a divisor of ``k``) shrinks by more than ``DECAY`` from its first half
    to its second counts as not settled (None)."""
    row = np.asarray(row, dtype=float)
    if not np.all(np.isfinite(row)):
        return 0
    half = row.size // 2
    for k in range(1, half + 1):
        if np.max(np.abs(row[k:] - row[:-k])) > tol:
            continue
        for j in (j for j in range(1, k) if k % j == 0):
            gap = np.abs(row[j:] - row[:-j])
            if np.max(gap[half:]) < DECAY * np.max(gap[: half - j + 1]):
                return None
        return k
    return None


def _runs(parameter: np.ndarray, periods: list) -> list[dict]:
    runs: list[dict] = []
    for mu, k in zip(parameter.tolist(), periods, strict=True):
        if runs and runs[-1]["_k"] == k:
            runs[-1]["to"] = mu
            runs[-1]["n_values"] += 1
            continue
        kind = "fell" if k == 0 else "aperiodic" if k is None else "periodic"
        runs.append(
            {
                "from": mu,
                "to": mu,
                "n_values": 1,
                "kind": kind,
                "period": k if kind == "periodic" else None,
                "_k": k,
            }
        )
    for run in runs:
        del run["_k"]
    return runs


def _describe(run: dict, n_keep: int) -> str:
    if run["kind"] == "fell":
        return "fell"
    if run["kind"] == "aperiodic":
        return f"no period <= {n_keep // 2} (chaotic, or still settling near a bifurcation)"
    return f"period {run['period']}"


def cmd_orbit_diagram(args) -> int:
    from walker.analysis.fixedpoint import find_fixed_point

    scene = _load(args)
    check_walker(scene, args.scene)
    check_param(scene, args.param)
    a, b = parse_range(args.range)
    _positive_flag(args.n, "--n", minimum=2, integer=True)
    _positive_flag(args.transient, "--transient", minimum=0, integer=True)
    _positive_flag(args.strides, "--strides", minimum=1, integer=True)
    reason = too_large(8.0 * args.n * (args.strides + 2))
    if reason is not None:
        raise UsageError(
            f"--n {args.n} values x --strides {args.strides} recorded {reason}; lower --n or "
            "--strides"
        )
    P = _stride_map(scene, parameter_name=args.param)
    names = list(P.section_names)
    coord = args.coordinate
    if coord in names:
        coordinate = names.index(coord)
    elif coord.isdigit() and int(coord) < len(names):
        coordinate = int(coord)
    else:
        raise UsageError(
            f"--coordinate must be a section coordinate of {scene.model} "
            f"({', '.join(names)}) or its index 0..{len(names) - 1}, got {coord!r}"
        )
    for value, end in ((a, "A"), (b, "B")):
        try:
            P.with_parameter(value)
        except ValueError as exc:
            raise UsageError(f"--range {end} = {value}: {exc}") from None
    for flag in ("--jobs", "--chains"):
        value = getattr(args, flag[2:])
        if value is not None and value < 1:
            raise UsageError(f"{flag} must be an integer >= 1, got {value}")
    if args.scheduler is not None:
        from .sweep import need_dask

        need_dask()
        if args.jobs is not None:
            print(
                "walker: warning: --jobs has no effect with --scheduler (the cluster decides)",
                file=sys.stderr,
            )
    out = _check_out(args.out, overwrite=args.overwrite)
    fp = find_fixed_point(P, P.project(scene.state))
    z0 = fp.section if fp.success else P.project(scene.state)
    values = np.linspace(a, b, args.n)
    chains = args.chains or 1
    diagram = _blocks(args, scene, P, z0, values, coordinate, chains, names, bool(fp.success))
    periods = [settled_period(row) for row in diagram.values]
    runs = _runs(diagram.parameter, periods)
    n_fell = sum(k == 0 for k in periods)
    status = "COMPLETED" if n_fell < len(periods) else "FELL"
    write_prov = {
        "range": [a, b],
        "n": int(args.n),
        "n_transient": int(args.transient),
        "n_keep": int(args.strides),
        "coordinate_name": names[coordinate],
        "start_gait": bool(fp.success),
        "warm_start": True,
        "chains": chains,
    }
    write_result(out, diagram, scene, args, write_prov)
    _remove_checkpoint(out)
    record = {
        "status": status,
        "parameter": args.param,
        "range": [a, b],
        "n": int(args.n),
        "coordinate": names[coordinate],
        "n_transient": int(args.transient),
        "n_keep": int(args.strides),
        "start_gait": bool(fp.success),
        "periods": [None if k is None else int(k) for k in periods],
        "n_fell": int(n_fell),
        "runs": runs,
        "out": str(out),
    }
    if args.json:
        print(_json(record))
    else:
        print(
            f"orbit diagram of {names[coordinate]}: {args.n} values of {args.param} from "
            f"{a:.10g} to {b:.10g}, {args.transient} + {args.strides} strides each"
        )
        if not fp.success:
            print(f"  (no gait at the scene's {args.param}; started from its initial state)")
        for run in runs:
            span = f"{run['from']:.6g}..{run['to']:.6g}"
            print(f"  {args.param} {span:<22s} {_describe(run, args.strides)}")
        print(f"wrote {out}")
    if status != "COMPLETED":
        print(f"walker: the walker fell at every value of {args.param}", file=sys.stderr)
        return EXIT_OUTCOME
    return EXIT_OK


def _blocks(args, scene, P, z0, values, coordinate, chains, names, start_gait):
    """The diagram through :func:`walker.analysis.orbit_run.orbit_diagram_blocks`, checkpointed
    beside ``--out`` (:func:`walker.analysis.orbit_run.checkpoint_path`): rerunning the same command
    resumes it; ``--overwrite`` starts afresh."""
    from walker.analysis.orbit_run import checkpoint_path, default_block, orbit_diagram_blocks
    from walker.storage import CheckpointMismatch, SweepStore

    from ._common import _resume_hint, provenance

    block = default_block(values.size)
    ckpt = checkpoint_path(args.out)
    prov = provenance(
        scene,
        {
            "range": [float(values[0]), float(values[-1])],
            "n": int(values.size),
            "n_transient": int(args.transient),
            "n_keep": int(args.strides),
            "coordinate_name": names[coordinate],
            "start_gait": start_gait,
            "chains": chains,
            "z0": [float(v) for v in z0],
        },
        out=args.out,
    )
    try:
        store = SweepStore.create_or_open(
            ckpt,
            parameter_names=(args.param,),
            points=values[:, None],
            columns={"values": ("f8", (args.strides,)), "carry": ("f8", (len(z0),))},
            chunk_size=block,
            provenance=prov,
            overwrite=bool(args.overwrite),
        )
    except CheckpointMismatch as exc:
        raise _resume_hint(exc) from None

    def run(executor, jobs=None):
        return orbit_diagram_blocks(
            P,
            z0,
            values,
            n_transient=args.transient,
            n_keep=args.strides,
            coordinate=coordinate,
            chains=chains,
            block=block,
            executor=executor,
            jobs=jobs,
            store=store,
            progress=not args.quiet,
        )

    if args.scheduler is not None:
        from .sweep import connect_scheduler

        with connect_scheduler(args.scheduler) as client:
            return run(client)
    return run(None, args.jobs)


def _remove_checkpoint(out) -> None:
    import contextlib
    import os

    from walker.analysis.orbit_run import checkpoint_path

    with contextlib.suppress(FileNotFoundError):
        os.unlink(checkpoint_path(out))


def register(sub) -> None:
    p = scene_cmd(sub, "orbit-diagram", "where the walker settles as a parameter changes")
    p.add_argument("--param", default="slope", help="parameter to vary (default: slope)")
    p.add_argument(
        "--range",
        required=True,
        metavar="A:B",
        help="values from A to B, in that order (B < A sweeps downward) (required)",
    )
    p.add_argument("--n", type=int, default=100, help="number of values (default: 100)")
    p.add_argument(
        "--transient",
        type=int,
        default=200,
        help="strides discarded at each value before recording (default: 200)",
    )
    p.add_argument(
        "--strides", type=int, default=32, help="strides recorded at each value (default: 32)"
    )
    p.add_argument(
        "--coordinate",
        default="0",
        help="section coordinate recorded, by name or index (default: 0, the first)",
    )
    p.add_argument(
        "--chains",
        type=int,
        default=None,
        help="stretches of consecutive values, each started from the scene's gait, that --jobs "
        "runs in parallel (default: 1, one stretch following the attractor over the whole "
        "range)",
    )
    jobs_option(p)
    p.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="dask.distributed scheduler address, e.g. tcp://host:8786 (default: none, run "
        "on this machine)",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object (default: text)")
    p.add_argument(
        "--out",
        required=True,
        help="HDF5 file to write (required); until it is written, a checkpoint .OUT.checkpoint.h5 "
        "beside it, which rerunning the same command resumes",
    )
    p.add_argument(
        "--quiet", action="store_true", help="no progress bar (default: a bar on a terminal)"
    )
    p.add_argument(
        "--overwrite",
        action="store_true",
        help="replace --out and its checkpoint (default: refuse --out, resume the checkpoint)",
    )
    p.set_defaults(func=cmd_orbit_diagram)
