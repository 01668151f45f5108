"""The ``walker`` command line: find, run, continue, basin, sweep, plot.

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
import json
import math
import os
import signal
import sys
import tempfile
import threading
from pathlib import Path

import numpy as np

EXIT_OK, EXIT_OUTCOME, EXIT_USAGE = 0, 1, 2
EXIT_INTERRUPTED = 130
"""Exit status after SIGINT or SIGTERM (128 + SIGINT, the shell's convention for Ctrl-C)."""

BASIN_TOL = 1e-6
"""Convergence tolerance of ``walker basin`` (section units, max-norm)."""


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
    return out


def _load(args):
    from walker.scene import load_scene

    return load_scene(args.scene, overrides=_parse_set(getattr(args, "set", None)))


def _stride_map(scene, parameter_name="slope"):
    from walker.stride import StrideMap

    c = scene.compute
    return StrideMap(
        scene.model,
        scene.params,
        method=c.method,
        rtol=c.rtol,
        atol=c.atol,
        t_max=c.t_max,
        first_step=c.first_step,
        parameter_name=parameter_name,
    )


def provenance(scene, extra: dict | None = None) -> dict:
    """What produced a result: scene, model, parameters with units, solver, kernel hash."""
    from walker.models import get_model
    from walker.storage import parameters_with_units

    c = scene.compute
    prov = {
        "scene": str(scene.path),
        "model": scene.model,
        "parameters": parameters_with_units(scene.params),
        "method": c.method,
        "rtol": c.rtol,
        "atol": c.atol,
        "kernel_hash": get_model(scene.model).kernel_hash,
    }
    prov.update(extra or {})
    return prov


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


def _check_out(path, *, overwrite: bool = False, resumable: bool = False) -> Path | None:
    """``--out`` checked before any work: not a directory, in an existing, writable
    directory, and not an existing file unless ``overwrite`` (or ``resumable``: a checkpoint
    the command may resume, which must then be a writable file)."""
    if path is None:
        return None
    out = Path(path)
    if out.is_dir():
        raise UsageError(f"--out {path} is a directory; give a file name")
    parent = out.parent if str(out.parent) else Path(".")
    if not parent.is_dir():
        raise UsageError(f"--out {path}: directory '{parent}' does not exist; create it first")
    if not _writable_dir(parent):
        raise UsageError(
            f"--out {path}: directory '{parent}' is not writable; choose another --out"
        )
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
    out = Path(path)
    if out.exists() and not out.is_dir():
        raise UsageError(f"--out {path} exists and is not a directory; choose another --out")
    if out.is_dir():
        if not _writable_dir(out):
            raise UsageError(f"--out {path}: directory is not writable; choose another --out")
        return out
    parent = out.parent if str(out.parent) else Path(".")
    if not parent.is_dir():
        raise UsageError(f"--out {path}: directory '{parent}' does not exist; create it first")
    if not _writable_dir(parent):
        raise UsageError(
            f"--out {path}: directory '{parent}' is not writable; choose another --out"
        )
    return out


def _resume_hint(exc, flag: str = "--out") -> UsageError:
    """A CheckpointMismatch as the one-line usage error naming --overwrite."""
    return UsageError(f"{flag} {exc.path} exists and {exc.reason}; pass --overwrite to replace it")


# ------------------------------------------------------------------------------------- find
def cmd_find(args) -> int:
    from walker.fixedpoint import find_fixed_point

    scene = _load(args)
    if not scene.model or scene.model == "double_pendulum":
        raise UsageError(f"{args.scene}: model `{scene.model}` has no gait to find")
    out = _check_out(args.out, overwrite=args.overwrite)
    P = _stride_map(scene)
    period = args.period or max(1, scene.compute.strides)
    fp = find_fixed_point(
        P,
        P.project(scene.state),
        period=period,
        tol=args.tol,
        jacobian="fd" if args.fd else "exact",
    )
    record = {
        "status": fp.status.name,
        "success": bool(fp.success),
        "message": fp.message,
        "model": scene.model,
        "section_names": list(P.section_names),
        "section": [float(v) for v in fp.section],
        "state_names": list(scene.state_names),
        "state": [float(v) for v in fp.state],
        "step_time": float(fp.step_time),
        "multipliers": _complex_pairs(fp.multipliers),
        "stable": bool(fp.stable),
        "residual": float(fp.residual),
        "n_iter": int(fp.n_iter),
        "period": int(fp.period),
        "parameters": scene.params.to_dict(),
    }
    if out is not None:
        from walker.storage import write

        write(
            out,
            fp,
            provenance=provenance(scene, {"status": fp.status.name}),
            overwrite=args.overwrite,
        )
    if args.json:
        print(_json(record))
    else:
        _print_fixed_point(scene, P, fp)
    return EXIT_OK if fp.success else EXIT_OUTCOME


def _print_fixed_point(scene, P, fp) -> None:
    print(f"scene      {scene.path}  (model {scene.model})")
    print(f"status     {fp.status.name}: {fp.message}")
    if not fp.success:
        return
    print(f"residual   {fp.residual:.2e} after {fp.n_iter} Newton iterations")
    print(f"step time  {fp.step_time:.15g} s")
    print("state just after heel strike:")
    for name, v in zip(scene.state_names, fp.state, strict=True):
        print(f"  {name:<10s} {v: .15f}")
    print("Floquet multipliers:")
    for m in fp.multipliers:
        print(f"  {m.real: .12f} {m.imag:+.12f}i   |.| = {abs(m):.12f}")
    print(f"stable     {fp.stable}")


# -------------------------------------------------------------------------------------- run
def cmd_run(args) -> int:
    from walker.storage import write
    from walker.stride import simulate

    scene = _load(args)
    out = _check_out(args.out, overwrite=args.overwrite)
    c = scene.compute
    strides = c.strides if args.strides is None else args.strides
    if strides < 0:
        raise UsageError(f"--strides must be >= 0, got {strides}")
    if args.sample_rate is not None and not (
        args.sample_rate > 0 and math.isfinite(args.sample_rate)
    ):
        raise UsageError(f"--sample-rate must be a positive number, got {args.sample_rate}")
    common = dict(
        n_strides=strides,
        phase0=scene.phase,
        method=c.method,
        rtol=c.rtol,
        atol=c.atol,
        first_step=c.first_step,
        t_max=c.t_max * max(1, strides),
    )
    if args.sample_rate is None:
        sol = simulate(scene.model, scene.params, scene.state, output="full", **common)
    else:
        first = simulate(scene.model, scene.params, scene.state, output="events", **common)
        times = np.arange(0.0, first.t, 1.0 / args.sample_rate)
        sol = simulate(
            scene.model, scene.params, scene.state, output="samples", sample_times=times, **common
        )
    print(f"status {sol.status.name}: {sol.message}")
    print(
        f"t = {sol.t:.12g} s, strides {sol.n_strides}, events {sol.n_events}, "
        f"steps {sol.n_steps} ({sol.n_rejected} rejected), rhs {sol.n_rhs}"
    )
    if out is not None:
        write(
            out,
            sol,
            provenance=provenance(scene, {"status": sol.status.name}),
            overwrite=args.overwrite,
        )
        print(f"wrote {out}")
    return EXIT_OK if sol.success else EXIT_OUTCOME


# --------------------------------------------------------------------------------- continue
def cmd_continue(args) -> int:
    from walker.continuation import continue_branch
    from walker.fixedpoint import find_fixed_point

    scene = _load(args)
    P = _stride_map(scene, parameter_name=args.param)
    if not math.isfinite(args.to):
        raise UsageError(f"--to must be finite, got {args.to}")
    out = _check_out(args.out, overwrite=args.overwrite)
    fp = find_fixed_point(P, P.project(scene.state))
    if not fp.success:
        print(f"status {fp.status.name}: no starting gait: {fp.message}")
        return EXIT_OUTCOME
    kwargs = {}
    if args.step is not None:
        kwargs["step"] = args.step
    branch = continue_branch(
        P,
        fp.section,
        to=args.to,
        method="natural" if args.natural else "arclength",
        max_points=args.max_points,
        **kwargs,
    )
    if out is not None:
        from walker.storage import write

        write(
            out,
            branch,
            provenance=provenance(scene, {"status": branch.status.name}),
            overwrite=args.overwrite,
        )
    bifs = [
        {
            "kind": b.kind,
            "parameter": args.param,
            "parameter_value": float(b.parameter_value),
            "section": [float(v) for v in b.section],
            "multipliers": _complex_pairs(b.multipliers),
        }
        for b in branch.bifurcations
    ]
    if args.json:
        print(
            _json(
                {
                    "status": branch.status.name,
                    "message": branch.message,
                    "parameter": args.param,
                    "n_points": int(len(branch.parameter)),
                    "parameter_range": [
                        float(branch.parameter.min()),
                        float(branch.parameter.max()),
                    ],
                    "bifurcations": bifs,
                }
            )
        )
    else:
        print(f"status {branch.status.name}: {branch.message}")
        print(
            f"{len(branch.parameter)} points, {args.param} from "
            f"{branch.parameter[0]:.10g} to {branch.parameter[-1]:.10g}"
        )
        for b in bifs:
            mult = ", ".join(f"{re:.6f}{im:+.6f}i" for re, im in b["multipliers"])
            print(f"  {b['kind']:<16s} {args.param} = {b['parameter_value']:.12g}   [{mult}]")
    return EXIT_OK if branch.success else EXIT_OUTCOME


# ------------------------------------------------------------------------------------ basin
def cmd_basin(args) -> int:
    from walker.basin import basin_map
    from walker.fixedpoint import find_fixed_point
    from walker.storage import BasinStore, CheckpointMismatch

    scene = _load(args)
    P = _stride_map(scene)
    axes = tuple(int(a) for a in args.axes.split(","))
    if len(axes) != 2 or not all(0 <= a < P.n_z for a in axes) or axes[0] == axes[1]:
        raise UsageError(f"--axes must be two distinct section indices in 0..{P.n_z - 1}")
    if args.n < 2:
        raise UsageError(f"--n must be >= 2, got {args.n}")
    if args.strides < 1:
        raise UsageError(f"--strides must be >= 1, got {args.strides}")
    if not (math.isfinite(args.span) and args.span > 0):
        raise UsageError(f"--span must be a positive number, got {args.span}")
    if args.jobs is not None and args.jobs < 1:
        raise UsageError(f"--jobs must be >= 1, got {args.jobs}")
    out = _check_out(args.out, overwrite=args.overwrite, resumable=True)
    c = scene.compute
    prov = provenance(scene, {"t_max": c.t_max, "first_step": c.first_step})
    if not args.overwrite:
        # Refuse an unrelated file before the fixed point is searched for; the grid itself
        # (which needs the fixed point) is compared when the checkpoint is opened.
        names = tuple(P.section_names)
        try:
            BasinStore.check_existing(
                out,
                provenance=prov,
                axis_names=(names[axes[0]], names[axes[1]]),
                shape=(args.n, args.n),
                n_strides=args.strides,
                tol=BASIN_TOL,
            )
        except CheckpointMismatch as exc:
            raise _resume_hint(exc) from None
    fp = find_fixed_point(P, P.project(scene.state))
    if not fp.success:
        print(f"status {fp.status.name}: no gait to map the basin of: {fp.message}")
        return EXIT_OUTCOME
    span = args.span
    ranges = tuple(
        (
            fp.section[a] - span * max(abs(fp.section[a]), 0.1),
            fp.section[a] + span * max(abs(fp.section[a]), 0.1),
        )
        for a in axes
    )
    try:
        bm = basin_map(
            P,
            fp,
            axes=axes,
            ranges=ranges,
            n=(args.n, args.n),
            n_strides=args.strides,
            tol=BASIN_TOL,
            jobs=args.jobs,
            progress=not args.quiet,
            out=out,
            overwrite=args.overwrite,
            provenance=prov,
        )
    except CheckpointMismatch as exc:
        raise _resume_hint(exc) from None
    from walker.results import BASIN_CONVERGED

    frac = float(np.mean(bm.outcome == BASIN_CONVERGED))
    print(f"wrote {out}: {args.n}x{args.n} points, {frac:.1%} converge to the gait")
    return EXIT_OK


# ------------------------------------------------------------------------------------ sweep
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


# ------------------------------------------------------------------------------------- plot
def cmd_plot(args) -> int:
    import matplotlib

    matplotlib.use("Agg")
    from walker.gallery import plot_file

    if not Path(args.file).exists():
        raise FileNotFoundError(f"result file not found: {args.file}")
    out = _check_figure_dir(args.out)
    out.mkdir(exist_ok=True)  # the figures' own directory is created
    paths = plot_file(args.file, out)
    for p in paths:
        print(f"wrote {p}")
    return EXIT_OK


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="walker", description="Simulate passive and actuated biped walkers."
    )
    from walker import __version__

    parser.add_argument("--version", action="version", version=f"walker {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)

    def scene_cmd(name, help_):
        p = sub.add_parser(name, help=help_)
        p.add_argument("scene", help="scene file (gaits/*.toml)")
        p.add_argument(
            "--set", action="append", metavar="NAME=VALUE", help="override a parameter (repeatable)"
        )
        return p

    p = scene_cmd("find", "find the periodic gait (fixed point of the stride map)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--period", type=int, default=None, help="strides per period")
    p.add_argument("--tol", type=float, default=1e-12, help="residual tolerance")
    p.add_argument("--fd", action="store_true", help="finite-difference Jacobian")
    p.add_argument("--out", help="also store the fixed point (HDF5)")
    p.add_argument("--overwrite", action="store_true")
    p.set_defaults(func=cmd_find)

    p = scene_cmd("run", "simulate strides and store the trajectory")
    p.add_argument("--strides", type=int, default=None)
    p.add_argument("--out", help="HDF5 file to write")
    p.add_argument(
        "--sample-rate",
        type=float,
        default=None,
        metavar="HZ",
        help="store samples at this rate instead of every step",
    )
    p.add_argument("--overwrite", action="store_true")
    p.set_defaults(func=cmd_run)

    p = scene_cmd("continue", "follow the gait as a parameter changes")
    p.add_argument("--param", default="slope")
    p.add_argument("--to", type=float, required=True)
    p.add_argument("--step", type=float, default=None)
    p.add_argument("--max-points", type=int, default=500)
    p.add_argument("--natural", action="store_true", help="natural-parameter continuation")
    p.add_argument("--json", action="store_true")
    p.add_argument("--out", help="HDF5 file to write")
    p.add_argument("--overwrite", action="store_true")
    p.set_defaults(func=cmd_continue)

    p = scene_cmd("basin", "map the basin of attraction on a 2-D slice of the section")
    p.add_argument("--out", required=True, help="HDF5 checkpoint and result; rerunning resumes it")
    p.add_argument("--axes", default="0,1", help="two section indices, e.g. 0,1")
    p.add_argument("--n", type=int, default=50, help="grid points per axis")
    p.add_argument(
        "--span",
        type=float,
        default=0.5,
        help="half-width of each axis relative to the fixed point's value",
    )
    p.add_argument("--strides", type=int, default=20)
    p.add_argument(
        "--jobs",
        type=int,
        default=None,
        help="worker threads (the compiled strides run in parallel); default: CPU count",
    )
    p.add_argument("--quiet", action="store_true")
    p.add_argument(
        "--overwrite", action="store_true", help="replace an existing --out instead of resuming"
    )
    p.set_defaults(func=cmd_basin)

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

    p = sub.add_parser("plot", help="draw the figures of a stored result")
    p.add_argument("file")
    p.add_argument("--out", default=".", help="directory for the figures (created)")
    p.set_defaults(func=cmd_plot)
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
