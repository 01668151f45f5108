"""``walker plot``: the figures of a stored result."""

from __future__ import annotations

from pathlib import Path

from ._common import (
    EXIT_OK,
    UsageError,
    _check_figure_dir,
)
from ._help import add_parser


def cmd_plot(args) -> int:
    import matplotlib

    matplotlib.use("Agg")
    from walker.gallery import plot_file

    try:
        found = Path(args.file).exists()
    except OSError as exc:  # a name too long, ...
        raise UsageError(f"result file {args.file}: {exc.strerror or exc}") from None
    if not found:
        raise FileNotFoundError(f"result file not found: {args.file}")
    out = _check_figure_dir(args.out)
    created = not out.exists()
    out.mkdir(exist_ok=True)  # the figures' own directory is created ...
    try:
        paths = plot_file(args.file, out, gif=args.gif)
    except BaseException:
        if created and not any(out.iterdir()):
            out.rmdir()  # ... and removed again when the file could not be plotted
        raise
    for p in paths:
        print(f"wrote {p}")
    return EXIT_OK


def register(sub) -> None:
    p = add_parser(sub, "plot", "draw the figures of a stored result")
    p.add_argument("file", help="HDF5 result of find, run, continue, orbit-diagram, basin or sweep")
    p.add_argument("--out", default=".", metavar="DIR", help="directory for the figures (created)")
    p.add_argument(
        "--gif",
        action="store_true",
        help="also render a stored run as a stick-figure animation (slow; default: off)",
    )
    p.set_defaults(func=cmd_plot)
