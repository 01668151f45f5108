"""``walker sweep``: a resumable parameter sweep."""

from __future__ import annotations

import numpy as np

from ._common import (
    EXIT_OK,
    _check_out,
    _resume_hint,
)


def cmd_sweep(args) -> int:
    from walker.storage import CheckpointMismatch
    from walker.sweep import run_sweep_command

    _check_out(args.out, overwrite=args.overwrite, resumable=True)
    try:
        table = run_sweep_command(
            args.scene,
            args.param,
            kind=args.kind,
            jobs=args.jobs,
            scheduler=args.scheduler,
            out=args.out,
            quiet=args.quiet,
            strides=args.strides,
            chunk_size=args.chunk_size,
            overwrite=args.overwrite,
        )
    except CheckpointMismatch as exc:
        raise _resume_hint(exc) from None
    n_ok = int(np.sum(table.columns["status"] == 0))
    print(f"wrote {args.out}: {len(table.points)} points, {n_ok} completed")
    return EXIT_OK


def register(sub) -> None:
    p = sub.add_parser("sweep", help="resumable parameter sweep")
    p.add_argument("scene")
    p.add_argument("--param", action="append", required=True, metavar="NAME=START:STOP:COUNT")
    p.add_argument("--kind", choices=("outcome", "fixed_point"), default="fixed_point")
    p.add_argument("--strides", type=int, default=1)
    p.add_argument(
        "--jobs",
        type=int,
        default=None,
        help="worker threads (the compiled strides run in parallel); default: CPU count",
    )
    p.add_argument("--scheduler", default=None, help="dask.distributed scheduler address")
    p.add_argument("--chunk-size", type=int, default=None)
    p.add_argument(
        "--out", required=True, help="HDF5 checkpoint; rerunning the same command resumes it"
    )
    p.add_argument("--quiet", action="store_true")
    p.add_argument(
        "--overwrite", action="store_true", help="replace an existing --out instead of resuming"
    )
    p.set_defaults(func=cmd_sweep)
