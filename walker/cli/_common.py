"""Shared pieces of the command line: exit codes, usage errors, signal handling, strict JSON,
scene loading, provenance and the checks of output paths made before any work."""

from __future__ import annotations

import argparse
import contextlib
import functools
import json
import math
import os
import signal
import sys
import tempfile
import threading
from pathlib import Path

import numpy as np

from ._help import HelpFormatter, _error_with_suggestion

EXIT_OK, EXIT_OUTCOME, EXIT_USAGE = 0, 1, 2
EXIT_INTERNAL = 3
"""Exit status of an internal error (a bug in walker: an exception it did not expect)."""
EXIT_INTERRUPTED = 130
"""Exit status after SIGINT or SIGTERM (128 + SIGINT, the shell's convention for Ctrl-C)."""
EXIT_BROKEN_PIPE = 141
"""Exit status when the reader of standard output went away (``walker ... | head``): 128 +
SIGPIPE, what the shell reports for a tool the signal ended."""

BASIN_TOL = 1e-6
"""Convergence tolerance of ``walker basin`` (section units, max-norm)."""

MAX_STRIDES = 1_000_000
"""Most strides a command takes per run, per point or per period (``--strides``,
``--period``): far beyond any study, and within what the compiled loop counts."""


class UsageError(ValueError):
    """Bad command-line input (exit status 2)."""


class Interrupted(KeyboardInterrupt):
    """Raised in the main thread by the CLI's SIGINT/SIGTERM handler."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


@contextlib.contextmanager
def interrupts_as_exceptions():
    """While active (main thread only), SIGINT and SIGTERM raise :class:`Interrupted` in the
    main thread, once; a second signal exits the process at once (status 130) without
    waiting for running work.  The previous handlers are restored on exit.

    An exception raised by a signal handler lands wherever the main thread is; where Python
    cannot propagate it (a weakref callback, ``__del__``, the garbage collector) it is
    reported to ``sys.unraisablehook`` and dropped.  The hook installed here raises it again
    at the next opportunity instead, so an interrupt is never lost.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    import _thread

    received: list[int] = []
    redeliver: list[int] = []
    pid = os.getpid()

    def handler(signum, frame):
        if os.getpid() != pid:
            # A forked worker (a process pool's) inherits the handler: it gets the default
            # behaviour, so the pool's shutdown can terminate it.
            if signum == signal.SIGINT:
                raise KeyboardInterrupt
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)
            return
        if redeliver:
            raise Interrupted(redeliver.pop())
        received.append(signum)
        if len(received) == 1:
            raise Interrupted(signum)
        # A second signal while the first one's clean-up runs: leave now.  Checkpoints stay
        # consistent (they survive SIGKILL); only the chunks still running are lost.
        try:
            os.write(2, b"walker: interrupted again; exiting without waiting for the workers\n")
        finally:
            os._exit(EXIT_INTERRUPTED)

    previous_hook = sys.unraisablehook
    active = [True]
    lock = threading.Lock()

    def trigger(signum):
        with lock:
            if active[0] and redeliver:
                _thread.interrupt_main(signum)  # the handler runs again in the main thread

    def unraisable(info):
        if isinstance(info.exc_value, Interrupted) and os.getpid() == pid:
            # Not from here (the hook runs inside the context that drops exceptions): a
            # moment later, from another thread.
            redeliver.append(info.exc_value.signum)
            timer = threading.Timer(0.02, trigger, args=(info.exc_value.signum,))
            timer.daemon = True
            timer.start()
            return
        previous_hook(info)

    previous = {sig: signal.signal(sig, handler) for sig in (signal.SIGINT, signal.SIGTERM)}
    sys.unraisablehook = unraisable
    try:
        yield
    finally:
        with lock:
            active[0] = False
        sys.unraisablehook = previous_hook
        for sig, old in previous.items():
            signal.signal(sig, old)
        if redeliver:  # dropped, and the work ended before it was raised again
            raise Interrupted(redeliver.pop())


def _strict(value):
    """``value`` with every non-finite float replaced by None (JSON null)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _strict(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_strict(v) for v in value]
    return value


def _json(record: dict) -> str:
    """Strict JSON (RFC 8259): a missing number (NaN, infinity) is written as null."""
    return json.dumps(_strict(record), allow_nan=False)


def _parse_set(items) -> dict:
    out = {}
    for item in items or ():
        name, sep, value = item.partition("=")
        if not sep or not name:
            raise UsageError(f"--set expects NAME=VALUE, got {item!r}")
        try:
            out[name.strip()] = float(value)
        except ValueError:
            raise UsageError(f"--set {name}: value {value!r} is not a number") from None
        if not math.isfinite(out[name.strip()]):
            raise UsageError(f"--set {name}: value {value!r} must be a finite number")
    return out


def _positive_flag(value, flag: str, *, minimum: float = 0.0, integer: bool = False):
    """``value`` of ``flag`` when it is finite and above ``minimum`` (at least ``minimum`` for
    an ``integer``), else a UsageError naming the flag."""
    if value is None:
        return None
    if integer:
        if value < minimum:
            raise UsageError(f"{flag} must be an integer >= {minimum:g}, got {value}")
        if value > MAX_STRIDES:
            raise UsageError(f"{flag} must be <= {MAX_STRIDES:,}, got {value}")
        return value
    if not (math.isfinite(value) and value > minimum):
        raise UsageError(f"{flag} must be a finite number > {minimum:g}, got {value}")
    return value


def _load(args):
    from walker.scene import load_scene

    overrides = _parse_set(getattr(args, "set", None))
    try:
        return load_scene(args.scene, overrides=overrides)
    except ValueError as exc:
        if not overrides:
            raise
        # the scene loader names its argument `overrides`; on the command line it is --set
        text = str(exc).replace("[overrides] ", "--set: ")
        text = text.replace("(with overrides ", "(with --set ")
        raise type(exc)(text) from None


def _stride_map(scene, parameter_name="slope"):
    from walker.simulation.stride import StrideMap

    return StrideMap.from_scene(scene, parameter_name=parameter_name)


def provenance(scene, extra: dict | None = None, *, out=None) -> dict:
    """What produced a result: :func:`walker.storage.scene_provenance` of ``scene`` (scene
    path, relative to the directory of ``out`` when given; model, parameters with units,
    solver settings, kernel hash, the model's conventions), then the keys of ``extra``."""
    from walker.storage import scene_provenance

    where = None if out is None else Path(out).parent
    return scene_provenance(scene, relative_to=where, **(extra or {}))


def write_result(out, result, scene, args, extra: dict | None = None) -> None:
    """Store ``result`` in ``out`` with :func:`provenance` of ``scene`` and ``extra``,
    replacing an existing file when ``args.overwrite``."""
    from walker.storage import write

    write(out, result, provenance=provenance(scene, extra, out=out), overwrite=args.overwrite)


def _complex_pairs(values) -> list:
    return [[float(np.real(v)), float(np.imag(v))] for v in values]


def _writable_dir(directory: Path) -> bool:
    """``directory`` accepts new files: os.access, then a real test write (read-only file
    systems, ACLs and root's permissions fool os.access), removed at once."""
    if not os.access(directory, os.W_OK | os.X_OK):
        return False
    try:
        fd, probe = tempfile.mkstemp(dir=directory, prefix=".walker-write-test-")
    except OSError:
        return False
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(probe)
    return True


def _check_out(
    path, *, overwrite: bool = False, resumable: bool = False, size: int = 1 << 20
) -> Path | None:
    """``--out`` checked before any work: not a directory, in an existing, writable
    directory, and not an existing file unless ``overwrite`` (or ``resumable``: a checkpoint
    the command may resume, which must then be a writable file).  A path the system refuses
    (a name too long, a loop of links, ...) is a UsageError naming ``--out`` and the reason.
    With ``size`` > 0 the file system must also take a file of about ``size`` bytes (not
    read-only, enough free space: :func:`walker.storage.check_writable`)."""
    if path is None:
        return None
    try:
        out = _check_out_path(Path(path), path, overwrite, resumable)
    except OSError as exc:
        raise UsageError(f"--out {path}: {exc.strerror or exc}; choose another --out") from None
    if size > 0:
        from walker.storage import StorageError, check_writable

        try:
            check_writable(out, size)
        except (StorageError, OSError) as exc:
            raise UsageError(f"--out {path}: {exc}; choose another --out") from None
    return out


def _check_parent_dir(out: Path, path) -> None:
    """The directory ``--out`` goes in exists and is writable."""
    parent = out.parent if str(out.parent) else Path(".")
    if not parent.is_dir():
        raise UsageError(f"--out {path}: directory '{parent}' does not exist; create it first")
    if not _writable_dir(parent):
        raise UsageError(
            f"--out {path}: directory '{parent}' is not writable; choose another --out"
        )


def _check_out_path(out: Path, path, overwrite: bool, resumable: bool) -> Path:
    if out.is_dir():
        raise UsageError(f"--out {path} is a directory; give a file name")
    _check_parent_dir(out, path)
    if out.exists() or out.is_symlink():
        if not out.is_file():
            raise UsageError(f"--out {path} exists and is not a regular file; choose another --out")
        if not overwrite and not resumable:
            raise UsageError(f"--out {path} exists; pass --overwrite to replace it")
        if not overwrite and not os.access(out, os.R_OK | os.W_OK):
            raise UsageError(
                f"--out {path} exists and is not writable, so it cannot be resumed; pass "
                "--overwrite to replace it"
            )
    return out


def _check_figure_dir(path) -> Path:
    """``plot --out``: a writable directory, or a new one in a writable directory."""
    try:
        return _check_figure_path(Path(path), path)
    except OSError as exc:
        raise UsageError(f"--out {path}: {exc.strerror or exc}; choose another --out") from None


def _check_figure_path(out: Path, path) -> Path:
    if out.exists() and not out.is_dir():
        raise UsageError(f"--out {path} exists and is not a directory; choose another --out")
    if out.is_dir():
        if not _writable_dir(out):
            raise UsageError(f"--out {path}: directory is not writable; choose another --out")
        return out
    _check_parent_dir(out, path)
    return out


def say_resuming(out, done: int, total: int) -> None:
    """Tell (on standard error) that a rerun resumes the checkpoint ``out``."""
    left = total - done
    tail = "nothing left to compute" if not left else f"{left} left to compute"
    print(
        f"walker: resuming {out}: {done} of {total} chunks kept from the earlier run, {tail}",
        file=sys.stderr,
        flush=True,
    )


def _resume_hint(exc, flag: str = "--out") -> UsageError:
    """A CheckpointMismatch as the one-line usage error naming --overwrite."""
    return UsageError(f"{flag} {exc.path} exists and {exc.reason}; pass --overwrite to replace it")


def jobs_option(p) -> None:
    """``--jobs``: the worker threads of a grid command (basin, sweep)."""
    p.add_argument(
        "--jobs",
        type=int,
        default=None,
        help="worker threads (the compiled strides run in parallel); default: CPU count",
    )


def resumable_options(p) -> None:
    """``--quiet`` and ``--overwrite`` of a command whose ``--out`` checkpoint resumes."""
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument(
        "--overwrite", action="store_true", help="replace an existing --out instead of resuming"
    )


def json_flag(p: argparse.ArgumentParser) -> None:
    """``--json``: print one strict-JSON object instead of the text summary."""
    p.add_argument(
        "--json",
        action="store_true",
        help="print one JSON object (strict JSON: null for a missing number)",
    )


def out_flags(p: argparse.ArgumentParser, help_: str) -> None:
    """``--out FILE`` (what is written there: ``help_``) and ``--overwrite``."""
    p.add_argument("--out", metavar="FILE", help=help_)
    p.add_argument("--overwrite", action="store_true", help="replace an existing --out")


def scene_cmd(sub, name: str, help_: str) -> argparse.ArgumentParser:
    """A subcommand that takes a scene file and ``--set NAME=VALUE`` overrides."""
    p = sub.add_parser(name, help=help_, formatter_class=HelpFormatter)
    p.error = functools.partial(_error_with_suggestion, p)
    p.add_argument("scene", help="scene file (gaits/*.toml)")
    p.add_argument(
        "--set", action="append", metavar="NAME=VALUE", help="override a parameter (repeatable)"
    )
    return p


def print_measures(
    measures: dict, title: str = "gait measures (energies and costs per step):"
) -> None:
    """Print the gait measures of a result (:meth:`walker.analysis.measures.GaitMeasures.to_dict`),
    each with its unit; nothing when there are none."""
    import math

    from walker.analysis.measures import unit_of

    if not measures or not measures.get("n_steps"):
        return
    print(title)
    for key, value in measures.items():
        if key in ("n_steps", "weight") or (isinstance(value, float) and math.isnan(value)):
            continue
        unit = unit_of(key)
        print(f"  {key:<32s} {value:.10g}{'' if unit == '1' else ' ' + unit}")
