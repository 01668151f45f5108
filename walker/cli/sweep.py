"""``walker sweep``: a resumable parameter sweep."""

from __future__ import annotations

import numpy as np

from ._common import (
    EXIT_OK,
    UsageError,
    _check_out,
    _positive_flag,
    _resume_hint,
)
from .info import HelpFormatter


def cmd_sweep(args) -> int:
    from walker.models import get_model
    from walker.scene import load_scene
    from walker.storage import CheckpointMismatch
    from walker.sweep import _bytes_per_point, check_grid_size, parse_range, run_sweep_command

    for flag in ("--jobs", "--chunk-size"):
        value = getattr(args, flag[2:].replace("-", "_"))
        if value is not None and value < 1:
            raise UsageError(f"{flag} must be an integer >= 1, got {value}")
    _positive_flag(args.strides, "--strides", minimum=1, integer=True)
    scene = load_scene(args.scene)
    # The grid's size before anything is allocated for it, in the flag's words.
    lengths = []
    for text in args.param:
        try:
            lengths.append(len(parse_range(text)[1]))
        except ValueError as exc:
            raise UsageError(f"--param: {exc}") from None
    n_z = get_model(scene.model).n_z
    try:
        check_grid_size(lengths, "--param", _bytes_per_point(args.kind, n_z, len(lengths)))
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    _check_out(args.out, overwrite=args.overwrite, resumable=True, size=0)  # the store checks
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
            processes=getattr(args, "processes", False),
        )
    except CheckpointMismatch as exc:
        raise _resume_hint(exc) from None
    except ConnectionError as exc:
        raise UsageError(f"--scheduler {args.scheduler}: {exc}") from None
    except ValueError as exc:
        message = str(exc)
        if args.scheduler is not None and message.startswith("`scheduler`"):
            raise UsageError(f"--scheduler {args.scheduler}: {message}") from None
        if "`ranges`" in message:  # the library's name for what --param gives
            raise UsageError(message.replace("`ranges`", "--param")) from None
        if message.startswith("grid point"):
            raise UsageError(f"--param: {message}") from None
        raise
    n_ok = int(np.sum(table.columns["status"] == 0))
    print(f"wrote {args.out}: {len(table.points)} points, {n_ok} completed")
    return EXIT_OK


def register(sub) -> None:
    p = sub.add_parser(
        "sweep",
        help="resumable parameter sweep",
        description="resumable parameter sweep",
        formatter_class=HelpFormatter,
    )
    p.add_argument("scene", help="scene file (gaits/*.toml)")
    p.add_argument(
        "--param",
        action="append",
        required=True,
        metavar="NAME=START:STOP:COUNT",
        help="a parameter and its COUNT values from START to STOP (or NAME=V1,V2,...); repeat "
        "for a grid (required)",
    )
    p.add_argument(
        "--kind",
        choices=("outcome", "fixed_point"),
        default="fixed_point",
        help="fixed_point: the gait and its multipliers at each point; outcome: how --strides "
        "strides from the scene's state end",
    )
    p.add_argument(
        "--strides",
        type=int,
        default=1,
        help="fixed_point: the gait's period; outcome: strides run at each point",
    )
    p.add_argument(
        "--jobs",
        type=int,
        default=None,
        help="worker threads (the compiled strides run in parallel); default: CPU count",
    )
    p.add_argument(
        "--processes",
        action="store_true",
        help="run on --jobs worker processes instead of threads (they end with this process; "
        "default: threads)",
    )
    p.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="dask.distributed scheduler address, e.g. tcp://host:8786 (default: none, run "
        "on this machine)",
    )
    p.add_argument(
        "--chunk-size",
        type=int,
        default=None,
        help="grid points per chunk, the unit of work and of checkpointing (default: from the "
        "grid's size)",
    )
    p.add_argument(
        "--out",
        metavar="FILE",
        required=True,
        help="HDF5 checkpoint; rerunning the same command resumes it (required)",
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument(
        "--overwrite", action="store_true", help="replace an existing --out instead of resuming"
    )
    p.set_defaults(func=cmd_sweep)
