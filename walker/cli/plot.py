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
    from walker.plotting.gallery import FIGURES, UnknownFigure, plot_file

    if not 1 <= args.dpi <= 2400:
        raise UsageError(f"--dpi must be in [1, 2400], got {args.dpi}")
    figures = None
    if args.figure is not None:
        figures = tuple(n.strip() for n in args.figure.split(",") if n.strip())
        known = sorted({n for names in FIGURES.values() for n in names})
        unknown = [n for n in figures if n not in known]
        if unknown or not figures:
            raise UsageError(
                f"--figure: unknown figure {', '.join(unknown) or '(none given)'}; "
                f"choose from {', '.join(known)}"
            )

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
        paths = plot_file(
            args.file, out, gif=args.gif, figures=figures, fmt=args.format, dpi=args.dpi
        )
    except UnknownFigure as exc:
        if created and not any(out.iterdir()):
            out.rmdir()
        raise UsageError(f"--figure: {exc}") from None
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
    p.add_argument(
        "--figure",
        metavar="NAME[,NAME]",
        help="draw only these figures (a run: angles, energy, phase_portrait, torques, "
        "zero_dynamics; a branch: branch, bifurcation, multipliers; fixed point: multipliers; "
        "orbit_diagram; basin; sweep); default: all of the file's kind",
    )
    p.add_argument(
        "--format",
        choices=("png", "pdf", "svg"),
        default="png",
        help="file format of the figures (default: png)",
    )
    p.add_argument(
        "--dpi",
        type=int,
        default=110,
        help="resolution of raster output [dots per inch], 1 to 2400 (default: 110)",
    )
    p.set_defaults(func=cmd_plot)
