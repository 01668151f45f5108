"""``walker sweep``: a resumable parameter sweep (:func:`run_sweep_command`, on the library's
:func:`walker.analysis.sweep.sweep`), locally or on a ``dask.distributed`` cluster."""

from __future__ import annotations

import concurrent.futures as cf
import os
import sys
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ._common import (
    EXIT_OK,
    UsageError,
    _check_out,
    _parse_set,
    _positive_flag,
    _resume_hint,
    _stride_map,
    jobs_option,
    resumable_options,
    say_resuming,
)
from ._extras import require
from ._help import add_parser

if TYPE_CHECKING:
    from walker.results import SweepTable

SCHEDULER_TIMEOUT = 5.0
"""Seconds allowed to connect to a ``dask.distributed`` scheduler (:func:`run_sweep_command`)."""


def cmd_sweep(args) -> int:
    from walker.analysis.sweep import _bytes_per_point, check_grid_size, parse_range
    from walker.models import get_model
    from walker.scene import load_scene
    from walker.storage import CheckpointMismatch

    for flag in ("--jobs", "--chunk-size"):
        value = getattr(args, flag[2:].replace("-", "_"))
        if value is not None and value < 1:
            raise UsageError(f"{flag} must be an integer >= 1, got {value}")
    _positive_flag(args.strides, "--strides", minimum=1, integer=True)
    if args.gsn and args.kind != "fixed_point":
        raise UsageError("--gsn needs --kind fixed_point (the norm of each point's gait)")
    overrides = _parse_set(args.set)
    scene = load_scene(args.scene, overrides=overrides)
    # The grid's size before anything is allocated for it, in the flag's words.
    lengths = []
    for text in args.param:
        try:
            lengths.append(len(parse_range(text)[1]))
        except ValueError as exc:
            raise UsageError(f"--param: {exc}") from None
    swept = {text.partition("=")[0].strip() for text in args.param}
    both = sorted(swept & set(overrides))
    if both:
        raise UsageError(f"--set {both[0]}: the parameter is swept by --param; set it in one only")
    n_z = get_model(scene.model).n_z
    try:
        check_grid_size(
            lengths, "--param", _bytes_per_point(args.kind, n_z, len(lengths), args.gsn)
        )
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    _check_out(args.out, overwrite=args.overwrite, resumable=True, size=0)  # the store checks
    if args.scheduler is not None:
        require("distributed", "--scheduler")  # the `dask` extra, before any work
    jobs = args.jobs
    if jobs is not None and args.scheduler is not None:
        print(
            "walker: warning: --jobs has no effect with --scheduler (the cluster decides)",
            file=sys.stderr,
        )
        jobs = None
    try:
        table = run_sweep_command(
            args.scene,
            args.param,
            kind=args.kind,
            jobs=jobs,
            scheduler=args.scheduler,
            out=args.out,
            quiet=args.quiet,
            strides=args.strides,
            chunk_size=args.chunk_size,
            overwrite=args.overwrite,
            processes=getattr(args, "processes", False),
            overrides=overrides,
            gsn=args.gsn,
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
        if "`gsn`" in message:
            raise UsageError(f"--gsn: {message}") from None
        raise
    n_ok = int(np.sum(table.columns["status"] == 0))
    jumps = ""
    if "jump" in table.columns:  # a fixed-point sweep: points on another gait than a neighbour
        jumps = f", {int(np.sum(table.columns['jump'] == 1))} flagged as jumps (column jump)"
    print(f"wrote {args.out}: {len(table.points)} points, {n_ok} completed{jumps}")
    return EXIT_OK


def run_sweep_command(
    scene_path: str | os.PathLike,
    param_texts: Sequence[str],
    *,
    kind: str = "outcome",
    jobs: int | None = None,
    scheduler: str | None = None,
    out: str | os.PathLike | None = None,
    quiet: bool = False,
    strides: int | None = None,
    chunk_size: int | None = None,
    overwrite: bool = False,
    processes: bool = False,
    overrides: Mapping[str, float] | None = None,
    gsn: bool = False,
) -> SweepTable:
    """``walker sweep SCENE --param NAME=START:STOP:COUNT ... --out FILE.h5``.

    Loads the scene, builds its stride map from ``[compute]`` (method, rtol, atol, t_max,
    first_step), starts from the section of the scene's initial state, and runs
    :func:`~walker.analysis.sweep.sweep`.

    Parameters
    ----------
    scene_path : str or os.PathLike
        scene file (``gaits/*.toml``) of a walker.
    param_texts : sequence of str
        ``"NAME=START:STOP:COUNT"`` or ``"NAME=V1,V2,..."``, one per varied parameter.
    kind : {"outcome", "fixed_point"}
    jobs : int, optional
        local workers (default: all CPUs): threads, or processes with ``processes``; not used
        with ``scheduler``.
    scheduler : str, optional
        address of a ``dask.distributed`` scheduler (``"tcp://host:8786"``); the sweep runs
        on that cluster through ``Client(scheduler).get_executor()``.  A scheduler that
        does not answer within :data:`SCHEDULER_TIMEOUT` seconds raises ``ConnectionError``.
    out : str or os.PathLike, optional
        HDF5 checkpoint; rerunning the same command resumes.  Its provenance is
        :func:`walker.storage.scene_provenance` of the scene (the scene path, the model, the
        base parameters with units, method, rtol, atol, t_max, first_step, the kernel hash,
        the model's conventions) plus what :func:`walker.analysis.sweep.sweep` records itself, and
        the walker version.
    quiet : bool
        no progress bar.
    strides : int, optional
        strides per point / period of the gait; default the scene's ``[compute].strides``.
    chunk_size : int, optional
        as in :func:`~walker.analysis.sweep.sweep`.
    overwrite : bool
        replace an existing ``out`` instead of resuming it.
    processes : bool
        run on ``jobs`` worker processes (``executor="processes"`` of
        :func:`~walker.analysis.sweep.sweep`) instead of threads.
    overrides : mapping of str to float, optional
        parameters set for the whole sweep (``--set NAME=VALUE``), as in
        :func:`walker.scene.load_scene`; the provenance records them among the base
        parameters.
    gsn : bool
        a fixed-point sweep's ``gsn`` column, as in :func:`~walker.analysis.sweep.sweep`.

    Returns
    -------
    SweepTable

    Raises
    ------
    ValueError, TypeError
        bad input (as :func:`~walker.analysis.sweep.sweep`); before any work.
    ConnectionError
        ``scheduler`` cannot be reached within :data:`SCHEDULER_TIMEOUT` seconds; the
        checkpoint ``out`` exists then, and the same call resumes it.

    Everything, the checkpoint ``out`` included, is checked before any work and before
    connecting to ``scheduler``.
    """
    from walker.analysis.sweep import _execute, _prepare
    from walker.scene import load_scene
    from walker.storage import scene_provenance

    if isinstance(param_texts, str) or not isinstance(param_texts, Sequence) or not param_texts:
        raise ValueError(
            f"`param_texts` must be a non-empty list of 'NAME=START:STOP:COUNT' texts, got "
            f"{param_texts!r}"
        )
    if scheduler is not None and not isinstance(scheduler, str):
        raise TypeError(f"`scheduler` must be an address str, got {type(scheduler).__name__}")
    scene = load_scene(scene_path, overrides=overrides)
    if strides is None:
        strides = max(1, scene.compute.strides)
    stride_map = _stride_map(scene)
    z0 = stride_map.project(scene.state)
    provenance = scene_provenance(scene, relative_to=None if out is None else Path(out).parent)
    provenance["swept"] = _swept(scene, param_texts)
    if scheduler is not None and jobs is not None:
        warnings.warn("`jobs` has no effect with `scheduler` (the cluster decides)", stacklevel=2)
        jobs = None
    resuming = out is not None and not overwrite and Path(out).exists()
    # Validate and open (or create) the checkpoint before any work or connection.
    plan = _prepare(
        stride_map,
        list(param_texts),
        kind=kind,
        z0=z0,
        n_strides=strides,
        chunk_size=chunk_size,
        executor=None,
        jobs=jobs,
        out=out,
        overwrite=overwrite,
        provenance=provenance,
        tol=1e-10,
        gsn=gsn,
    )
    if resuming:
        total = -(-len(plan.points) // plan.chunk)
        say_resuming(out, total - len(plan.pending), total)
    if scheduler is None or not plan.pending:
        return _execute(plan, "processes" if processes else None, not quiet)
    with _connect(scheduler) as client:
        return _execute(plan, client, not quiet)


def _swept(scene, param_texts) -> dict:
    """The swept values for the provenance, by parameter: ``start``, ``stop``, ``count`` for
    a range, ``values`` for a list; with the unit.  (``parameters`` keeps the scene's
    values; each point's own are in the table's ``points``.)  A text that does not parse
    is left to the sweep's own check, which names it."""
    from walker.analysis.sweep import parse_range

    units = scene.params.units()
    swept = {}
    for text in param_texts:
        try:
            name, values = parse_range(text)
        except (TypeError, ValueError):
            continue
        entry: dict[str, Any] = {"unit": units.get(name, "")}
        if ":" in str(text).partition("=")[2]:
            entry.update(start=float(values[0]), stop=float(values[-1]), count=len(values))
        else:
            entry["values"] = [float(v) for v in values]
        swept[name] = entry
    return swept


def need_dask() -> None:
    """``--scheduler`` without dask.distributed installed: one line naming the extra
    (:func:`walker.cli._extras.require`), raised before any work."""
    require("distributed", "--scheduler")


def connect_scheduler(address: str) -> Any:
    """``--scheduler ADDRESS`` of a command: a ``dask.distributed.Client`` (:func:`_connect`),
    or the one-line UsageError saying why not (dask not installed, no scheduler there)."""
    need_dask()
    try:
        return _connect(address)
    except (ConnectionError, ValueError) as exc:
        raise UsageError(f"--scheduler {address}: {exc}") from None


def _connect(scheduler: str) -> Any:
    """A ``dask.distributed.Client`` of ``scheduler``, or a ConnectionError saying why not
    within about :data:`SCHEDULER_TIMEOUT` seconds (a ValueError for an address that is
    none).

    Before a ``Client`` is made, a host and port are tried with a plain TCP connection (a
    port nobody listens on fails at once, not after dask's retries) and the server is asked
    who it is: what answers but is no scheduler is refused with its reason, and no half-made
    ``Client`` is left to complain when it is collected.
    """
    import socket

    from distributed import Client
    from distributed.comm import get_address_host_port, parse_address

    try:
        scheme = parse_address(scheduler)[0]
        tcp = scheme in ("tcp", "tls", "ws", "wss")
        host, port = get_address_host_port(scheduler) if tcp else (None, None)
    except ValueError as exc:
        raise ValueError(
            f"`scheduler` must be a scheduler address such as 'tcp://host:8786', got "
            f"{scheduler!r}: {str(exc).splitlines()[0] if str(exc) else 'invalid'}"
        ) from None

    def fail(reason: str) -> ConnectionError:
        return ConnectionError(
            f"cannot connect to the dask scheduler {scheduler!r} within "
            f"{SCHEDULER_TIMEOUT:g} s: {reason}"
        )

    if tcp:
        try:
            with socket.create_connection((host, port), timeout=SCHEDULER_TIMEOUT):
                pass
        except OSError as exc:
            raise fail(exc.strerror or str(exc) or type(exc).__name__) from None
    try:
        identity = _ask_identity(scheduler)
    except Exception as exc:  # whatever the server sent: hostile bytes are not a bug of ours
        raise fail(f"no dask scheduler answers there ({type(exc).__name__}: {exc})"[:300]) from None
    if not (isinstance(identity, dict) and identity.get("type") == "Scheduler"):
        raise fail("the server there is not a dask scheduler")
    try:
        return Client(scheduler, timeout=SCHEDULER_TIMEOUT, set_as_default=False)
    except (OSError, TimeoutError) as exc:
        raise fail(str(exc).splitlines()[0] if str(exc) else type(exc).__name__) from None


def _ask_identity(scheduler: str) -> Any:
    """The reply of the server at ``scheduler`` to dask's ``identity`` request, asked on a
    thread of its own (so a running event loop of the caller is no obstacle)."""
    import asyncio

    from distributed.comm import connect

    async def ask():
        comm = await connect(scheduler, timeout=SCHEDULER_TIMEOUT)
        try:
            await comm.write({"op": "identity", "reply": True})
            return await asyncio.wait_for(comm.read(), SCHEDULER_TIMEOUT)
        finally:
            comm.abort()

    with cf.ThreadPoolExecutor(1, thread_name_prefix="walker-scheduler") as pool:
        return pool.submit(asyncio.run, ask()).result()


def register(sub) -> None:
    p = add_parser(sub, "sweep", "resumable parameter sweep")
    p.add_argument("scene", help="scene file (gaits/*.toml)")
    p.add_argument(
        "--set",
        action="append",
        metavar="NAME=VALUE",
        help="override a parameter for the whole sweep (repeatable; not one that --param sweeps)",
    )
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
        "--gsn",
        action="store_true",
        help="fixed_point: also a column gsn, the gait sensitivity norm of each point's gait "
        "(NaN where there is no stable period-one gait); makes the sweep 3-5 times slower",
    )
    jobs_option(p)
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
    resumable_options(p)
    p.set_defaults(func=cmd_sweep)
