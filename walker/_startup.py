"""Ctrl-C while the ``walker`` command starts: exit 130 quietly, not with a traceback.

The command line imports numpy, scipy, h5py and matplotlib before its own handling of
interrupts (:func:`walker.cli.main`) is in place, which takes about a second; a SIGINT then
printed the 18-21-line traceback of whatever import it hit.  :func:`quiet_interrupts` is
called first thing by ``walker/__init__.py``: when this process is the ``walker`` command
(the console script, or ``python -m walker``) and SIGINT still has Python's default
handler, it installs one that prints ``walker: interrupted`` and exits with status 130.
:func:`walker.cli.main` hands SIGINT back to Python's default handler (KeyboardInterrupt)
once its own handling covers it.  A program importing walker as a library keeps its
handlers untouched.

What this cannot cover: a SIGINT while the interpreter imports ``site`` (and runs the
environment's ``.pth`` files), after Python has installed its own handler but before this
module can run, still prints Python's traceback; docs/signals.md says why and measures it.
"""

from __future__ import annotations

import os
import signal
import sys

EXIT_INTERRUPTED = 130


def _is_walker_command() -> bool:
    """This process runs the ``walker`` console script or ``python -m walker``, judged from
    the command line it was started with (``sys.orig_argv``): a worker process that
    multiprocessing started for it (``python -c ...``) is not, although its ``sys.argv``
    is copied from the parent's."""
    orig = list(getattr(sys, "orig_argv", []))[1:]
    for i, arg in enumerate(orig):
        if arg == "-m":
            return orig[i + 1 : i + 2] == ["walker"]
        if arg == "-c":
            return False
        if not arg.startswith("-"):  # the script
            return os.path.basename(arg) in ("walker", "walker.exe", "walker-script.py")
    return False


def _interrupted_while_starting(signum, frame) -> None:  # noqa: ARG001 - a signal handler
    try:
        os.write(2, b"walker: interrupted\n")
    except OSError:
        pass
    os._exit(EXIT_INTERRUPTED)


def quiet_interrupts() -> None:
    """Install the start-up SIGINT handler when this process is the ``walker`` command."""
    try:
        if _is_walker_command() and signal.getsignal(signal.SIGINT) is signal.default_int_handler:
            signal.signal(signal.SIGINT, _interrupted_while_starting)
    except (ValueError, OSError):  # not the main thread, or no signals here
        pass


def restore_interrupts() -> None:
    """SIGINT back to Python's default handler (KeyboardInterrupt), if the start-up handler
    holds it."""
    try:
        if signal.getsignal(signal.SIGINT) is _interrupted_while_starting:
            signal.signal(signal.SIGINT, signal.default_int_handler)
    except (ValueError, OSError):
        pass
