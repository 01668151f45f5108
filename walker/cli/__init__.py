"""The ``walker`` command line: find, run, continue, basin, sweep, plot.

One module per subcommand (``find.py`` ... ``plot.py``: its ``cmd_*`` function and its
``register`` that adds the parser); the shared checks live in ``_common.py``.

Every subcommand takes a scene file (``gaits/*.toml``) and only orchestrates the library.
Invalid input gives a one-line ``walker: error: ...`` and exit status 2; expected outcomes
(a fall, Newton not converging) are reported with exit status 1.

Output paths are checked before any work: ``--out`` naming a directory, in a missing or
unwritable directory, or an existing file without ``--overwrite`` (``sweep`` and ``basin``:
unless it checkpoints the same computation, which is then resumed) is an error (exit 2).

``sweep`` and ``basin`` run with a handler for SIGINT and SIGTERM (installed here only; the
library sees an ordinary ``KeyboardInterrupt``): the workers are stopped, the finished chunks
stay in the checkpoint ``--out``, one line says so, and the exit status is 130; the same
command resumes.  A second signal exits at once.  Ctrl-C on the other commands also ends
with one line and status 130 (their files are written atomically, so nothing half-written
is left).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys

from . import basin, branch, find, orbit, plot, run, sweep
from ._common import (
    BASIN_TOL,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_OUTCOME,
    EXIT_USAGE,
    Interrupted,
    UsageError,
    interrupts_as_exceptions,
    provenance,
)

__all__ = [
    "BASIN_TOL",
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "EXIT_OUTCOME",
    "EXIT_USAGE",
    "Interrupted",
    "UsageError",
    "build_parser",
    "interrupts_as_exceptions",
    "main",
    "provenance",
]

_COMMANDS = (find, run, branch, basin, sweep, plot, orbit)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="walker", description="Simulate passive and actuated biped walkers."
    )
    from walker import __version__

    parser.add_argument("--version", action="version", version=f"walker {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    for command in _COMMANDS:
        command.register(sub)
    return parser


_CHECKPOINTING = ("sweep", "basin")


def _file_id(path) -> tuple | None:
    try:
        st = os.stat(path)
    except (OSError, TypeError, ValueError):
        return None
    return (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)


def _interrupted_line(args, before: tuple | None) -> str:
    """The one line printed after an interrupt."""
    if args.command not in _CHECKPOINTING:
        return "walker: interrupted"
    from walker.storage import checkpoint_progress

    progress = checkpoint_progress(args.out)
    replaced = before is None or _file_id(args.out) != before
    if progress is None or (args.overwrite and not replaced):
        return f"walker: interrupted before anything was stored in {args.out}"
    done, total = progress
    return (
        f"walker: interrupted; {done} of {total} chunks kept in {args.out}, rerun the same "
        "command to resume"
    )


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    from walker.storage import StorageError

    before = _file_id(args.out) if args.command in _CHECKPOINTING else None
    guard = (
        interrupts_as_exceptions() if args.command in _CHECKPOINTING else contextlib.nullcontext()
    )
    try:
        with guard:
            try:
                return args.func(args)
            except KeyboardInterrupt:  # Ctrl-C, or SIGTERM/SIGINT (interrupts_as_exceptions)
                # Still under the handler: a second signal now exits at once.
                print(_interrupted_line(args, before), file=sys.stderr)
                return EXIT_INTERRUPTED
    except KeyboardInterrupt:  # a signal just after the command's own handling
        print("walker: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except (
        UsageError,
        ValueError,
        TypeError,
        FileNotFoundError,
        FileExistsError,
        PermissionError,
        IsADirectoryError,
        NotADirectoryError,
        StorageError,
    ) as exc:
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        print(f"walker: error: {msg}", file=sys.stderr)
        return EXIT_USAGE


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
