"""The ``walker`` command line: find, run, continue, basin, sweep, plot.

One module per subcommand (``find.py`` ... ``plot.py``: its ``cmd_*`` function and its
``register`` that adds the parser); the shared checks live in ``_common.py``.

Every subcommand takes a scene file (``gaits/*.toml``) and only orchestrates the library.

Exit status:

* 0: done.
* 1: an outcome, not an error: the walker fell, no gait was found (``EXIT_OUTCOME``).
* 2: invalid input, one line ``walker: error: ...`` naming the flag, or the file and key
  (``EXIT_USAGE``).  These are exactly the errors walker raises for bad input: a
  :class:`UsageError` of the command line, a ``ValueError`` or ``TypeError`` raised by
  walker's own validation (raised in walker's code: the innermost frame of its traceback
  is in the package; the library's messages name the argument), a
  :class:`walker.storage.StorageError`, an ``OSError`` of a named file (the line names
  the path, and the flag it came from), and a missing optional dependency (the line names
  the extra that installs it: ``walker/cli/_extras.py``).
* 3: an internal error, a bug (``EXIT_INTERNAL``): any other exception, an ``OSError``
  without a file or a ``ValueError`` raised inside another library included.  One line
  ``walker: internal error (<type>: <message>), please report; traceback in <file>``; the
  traceback goes to a new file under ``$XDG_CACHE_HOME/walker/`` (``~/.cache/walker/``; the
  temporary directory when that cannot be written).
* 130: interrupted (SIGINT, SIGTERM; below), also while the command starts (a handler
  installed first thing by ``walker/__init__.py``: ``walker/_startup.py``).
* 141: standard output was closed by its reader (``walker find ... | head -c1``) or closed
  before the start (``>&-``): the rest of the output is dropped, nothing is printed, as for
  a tool ended by SIGPIPE.

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
import os
import platform
import select
import sys
import tempfile
import time
import traceback
import warnings
from pathlib import Path

from walker._startup import restore_interrupts

from . import basin, branch, export, find, gsn, info, mfpt, orbit, plot, run, sweep
from ._common import (
    BASIN_TOL,
    EXIT_BROKEN_PIPE,
    EXIT_INTERNAL,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_OUTCOME,
    EXIT_USAGE,
    Interrupted,
    UsageError,
    interrupts_as_exceptions,
    provenance,
)
from ._extras import missing_extra_line

__all__ = [
    "BASIN_TOL",
    "EXIT_BROKEN_PIPE",
    "EXIT_INTERNAL",
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

_COMMANDS = (find, run, branch, basin, sweep, plot, export, orbit, mfpt, gsn, info)


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


_CHECKPOINTING = ("sweep", "basin", "mfpt")


def _file_id(path) -> tuple | None:
    try:
        st = os.stat(path)
    except (OSError, TypeError, ValueError):
        return None
    return (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)


def _interrupted_line(args, before: tuple | None) -> str:
    """The one line printed after an interrupt."""
    if args.command not in _CHECKPOINTING or getattr(args, "out", None) is None:
        return "walker: interrupted"
    from walker.storage import checkpoint_progress

    progress = checkpoint_progress(args.out, verify=False)  # bookkeeping only: fast
    replaced = before is None or _file_id(args.out) != before
    if progress is None or (args.overwrite and not replaced):
        return f"walker: interrupted before anything was stored in {args.out}"
    done, total = progress
    return (
        f"walker: interrupted; {done} of {total} chunks kept in {args.out}, rerun the same "
        "command to resume"
    )


def main(argv=None) -> int:
    stdout_closed = _open_standard_streams()
    from walker.storage.provenance import set_command_line

    parser = build_parser()
    args = parser.parse_args(argv)
    set_command_line(sys.argv[1:] if argv is None else argv)  # recorded in every file

    try:
        restore_interrupts()  # from here on, Ctrl-C is a KeyboardInterrupt handled below
        before = _file_id(args.out) if args.command in _CHECKPOINTING else None
        # every command: SIGTERM like SIGINT (one line, 130), also inside compiled work
        with interrupts_as_exceptions(), warnings.catch_warnings():
            warnings.showwarning = _one_line_warning
            try:
                code = args.func(args)
                sys.stdout.flush()  # a closed pipe shows here, not at interpreter exit
                if stdout_closed and code in (EXIT_OK, EXIT_OUTCOME):
                    return EXIT_BROKEN_PIPE  # its output went nowhere
                return code
            except KeyboardInterrupt:  # Ctrl-C, or SIGTERM/SIGINT (interrupts_as_exceptions)
                # Still under the handler: a second signal now exits at once.
                print(_interrupted_line(args, before), file=sys.stderr)
                return EXIT_INTERRUPTED
    except KeyboardInterrupt:  # a signal just after the command's own handling
        print("walker: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError as exc:
        if _stdout_closed():
            return _drop_stdout()
        return _internal_error(exc, argv)
    except Exception as exc:
        line = _input_error_line(args, exc)
        if line is None:
            return _internal_error(exc, argv)
        print(f"walker: error: {line}", file=sys.stderr)
        return EXIT_USAGE


def _open_standard_streams() -> bool:
    """Standard input, output and error that are closed (``walker find ... >&-``) are opened
    on the null device, so that no file walker opens later gets their descriptor (and a
    ``print`` into it) and printing works.  Returns whether standard output was closed: the
    command then ends with ``EXIT_BROKEN_PIPE``, its output dropped."""
    closed = {}
    for fd in (0, 1, 2):
        try:
            os.fstat(fd)
            closed[fd] = False
        except OSError:
            closed[fd] = True
            try:
                null = os.open(os.devnull, os.O_RDWR)
                if null != fd:
                    os.dup2(null, fd)
                    os.close(null)
            except OSError:  # pragma: no cover - no null device
                pass
    for fd, name in ((1, "stdout"), (2, "stderr")):
        if closed[fd] or getattr(sys, name) is None:
            setattr(sys, name, open(os.devnull, "w", encoding="utf-8"))  # noqa: SIM115
    return closed[1] or sys.__stdout__ is None


def _one_line_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning on the command line: one line, no source location."""
    text = " ".join(str(message).split())
    print(f"walker: warning: {text}", file=sys.stderr if file is None else file)


_PACKAGE_DIR = Path(__file__).resolve().parent.parent


_LINE_MAX = 1000
"""Longest error line; a longer one (a path of thousands of characters) is cut in the middle."""


def _raised_by_walker(exc: BaseException) -> bool:
    """``exc`` was raised in walker's own code (its innermost frame is in the package), not
    inside another library walker called."""
    tb = exc.__traceback__
    if tb is None:
        return False
    while tb.tb_next is not None:
        tb = tb.tb_next
    try:
        return Path(tb.tb_frame.f_code.co_filename).resolve().is_relative_to(_PACKAGE_DIR)
    except (OSError, ValueError):  # pragma: no cover - a strange code object
        return False


def _first_line(exc: BaseException) -> str:
    """The first line of ``exc``'s message, at most ``_LINE_MAX`` characters: a longer one
    loses its middle, not its end, where the reason follows a long path."""
    text = str(exc).strip()
    line = text.splitlines()[0] if text else type(exc).__name__
    if len(line) <= _LINE_MAX:
        return line
    keep = (_LINE_MAX - 5) // 2
    return f"{line[:keep]} ... {line[-keep:]}"


def _path_label(args, filename) -> str:
    """The flag (or role) a path given on the command line came from, for messages."""
    try:
        name = os.fspath(filename)
    except TypeError:
        return ""
    for attr, label in (("out", "--out "), ("scene", "scene file "), ("file", "result file ")):
        value = getattr(args, attr, None)
        if isinstance(value, str) and value and os.fspath(value) == name:
            return label
    return ""


def _input_error_line(args, exc: Exception) -> str | None:
    """The one line for an error of the input, or None for an internal error."""
    from walker.storage import StorageError

    if isinstance(exc, UsageError | StorageError):
        return _first_line(exc)
    missing = missing_extra_line(exc)
    if missing is not None:  # an optional dependency (dask, numba, ...) is not installed
        return missing
    if isinstance(exc, FileExistsError) and exc.filename is not None and hasattr(args, "overwrite"):
        # Created meanwhile (two commands on one --out): the command line's wording.
        label = _path_label(args, exc.filename) or "--out "
        return f"{label}{os.fsdecode(exc.filename)} exists; pass --overwrite to replace it"
    if isinstance(exc, OSError) and exc.filename is not None:
        # An OSError of a named file: the path, the flag it came from and the reason.
        reason = exc.strerror or _first_line(exc)
        return f"{_path_label(args, exc.filename)}{os.fsdecode(exc.filename)}: {reason}"
    if isinstance(exc, ValueError | TypeError | OSError) and _raised_by_walker(exc):
        return _first_line(exc)
    return None


def _crash_log(exc: BaseException, argv) -> str | None:
    """Write ``exc``'s traceback to a new log file; its path, or None when none could be
    written."""
    from walker import __version__

    cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    stamp = time.strftime("%Y%m%d-%H%M%S")
    for directory in (Path(cache) / "walker", Path(tempfile.gettempdir())):
        try:
            directory.mkdir(parents=True, exist_ok=True)
            fd, path = tempfile.mkstemp(prefix=f"crash-{stamp}-", suffix=".log", dir=directory)
            with os.fdopen(fd, "w", encoding="utf-8", errors="replace") as fh:
                fh.write(
                    f"walker {__version__}, Python {platform.python_version()}, "
                    f"{platform.platform()}\n"
                )
                shown = sys.argv[1:] if argv is None else list(argv)
                fh.write(f"command: walker {' '.join(map(str, shown))}\n\n")
                fh.write("".join(traceback.format_exception(exc)))
            return path
        except OSError:
            continue
    return None


def _internal_error(exc: BaseException, argv) -> int:
    """Report ``exc`` as the bug it is: one line, the traceback in a log file."""
    path = _crash_log(exc, argv)
    where = f"traceback in {path}" if path else "traceback follows"
    print(
        f"walker: internal error ({type(exc).__name__}: {_first_line(exc)}), please report; "
        f"{where}",
        file=sys.stderr,
    )
    if path is None:
        traceback.print_exception(exc, file=sys.stderr)
    return EXIT_INTERNAL


def _stdout_closed() -> bool:
    """Standard output is a pipe whose reader is gone (True also when that cannot be told:
    printing is what walker does with a pipe)."""
    try:
        poller = select.poll()
        poller.register(sys.stdout.fileno(), 0)
        events = poller.poll(0)
    except (AttributeError, OSError, ValueError):
        return True
    return any(ev & (select.POLLERR | select.POLLHUP) for _, ev in events)


def _drop_stdout() -> int:
    """After EPIPE on standard output: send what is still buffered nowhere (so the flush at
    exit does not complain) and exit quietly."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (AttributeError, OSError, ValueError):
        pass
    return EXIT_BROKEN_PIPE


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
