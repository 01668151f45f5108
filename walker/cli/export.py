"""``walker export``: a stored result's tables as CSV, MATLAB ``.mat`` or JSON."""

from __future__ import annotations

from pathlib import Path

from ._common import EXIT_OK, UsageError, _check_out
from ._help import add_parser

_SUFFIX = {"csv": ".csv", "mat": ".mat", "json": ".json"}


def cmd_export(args) -> int:
    from walker.storage import read
    from walker.storage.export import export, export_paths, result_tables

    try:
        found = Path(args.file).is_file()
    except OSError as exc:  # a name too long, ...
        raise UsageError(f"result file {args.file}: {exc.strerror or exc}") from None
    if not found:
        raise FileNotFoundError(f"result file not found: {args.file}")
    out = Path(args.out) if args.out else Path(args.file).with_suffix(_SUFFIX[args.format])
    if out.resolve() == Path(args.file).resolve():
        raise UsageError(f"--out {out}: is the result file itself; choose another --out")
    _check_out(out, overwrite=args.overwrite)
    result, provenance = read(args.file)
    for path in export_paths(out, args.format, result_tables(result, provenance)):
        _check_out(path, overwrite=args.overwrite)
    for path in export(result, provenance, out, args.format, overwrite=args.overwrite):
        print(f"wrote {path}")
    return EXIT_OK


def register(sub) -> None:
    p = add_parser(sub, "export", "write a stored result's tables as CSV, MATLAB or JSON")
    p.add_argument("file", help="HDF5 result of find, run, continue, orbit-diagram, basin or sweep")
    p.add_argument(
        "--format",
        choices=("csv", "mat", "json"),
        default="csv",
        help="csv: one file per table, <stem>_<table>.csv, and <stem>_provenance.json; mat: "
        "one MATLAB file (a struct per table); json: one file (default: csv)",
    )
    p.add_argument(
        "--out",
        metavar="PATH",
        default=None,
        help="file to write (csv: the stem of the files) (default: FILE with the format's suffix)",
    )
    p.add_argument("--overwrite", action="store_true", help="replace existing files")
    p.set_defaults(func=cmd_export)
