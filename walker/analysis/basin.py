"""Basins of attraction of a gait on a 2-D slice of the Poincaré section.

Each grid point starts from the fixed point with two chosen section coordinates replaced and
is iterated by the section map until it comes within ``tol`` of the fixed point or, with
``converge_radius``, enters the ball around it where convergence is guaranteed
(:mod:`walker.analysis.basin_radius`; converged, either way), falls (the failing stride's
:class:`~walker.status.Status`, at its event or at a start outside the walking region), or
runs out of strides (undecided).  The rule and what the file records: docs/basins.md.
Rows of the grid are grouped into chunks, and the chunks run on any
:class:`concurrent.futures.Executor`: threads of this process by default (a walker's grid
row is one compiled call without the GIL, :meth:`walker.simulation.stride.StrideMap.basin_batch`, so
two threads reach about 1.9x one, as a started process pool does, see
results/bench/basin.md), a process pool, or a ``dask.distributed`` cluster through
``Client.get_executor()``.

With ``out`` the map is a checkpoint (:class:`walker.storage.BasinStore`): each chunk of rows
is written as it finishes, and the same call after an interruption (or a kill) computes only
the chunks not yet stored; the finished file is the same as an uninterrupted run's.  On
``KeyboardInterrupt`` (or any interrupt raised while the chunks run) the chunks not started
are cancelled, threads stop between grid points, a process pool's workers are terminated,
the chunks already finished are kept in ``out``, and the interrupt propagates.
"""

from __future__ import annotations

import concurrent.futures as cf
import functools
import math
import numbers
import os
import threading

import numpy as np

from walker._executors import Abandoned, progress_bar, run_chunks, worker_pool
from walker.results import BASIN_CONVERGED, BASIN_UNDECIDED, BasinMap, FixedPoint, too_large
from walker.simulation.sectionmap import SectionMap, map_value
from walker.storage import BASIN_NOT_COMPUTED

__all__ = ["BASIN_NOT_COMPUTED", "basin_map", "basin_chunk"]

MAX_N_STRIDES = 2**62
"""Largest ``n_strides`` of :func:`basin_map` (the compiled loop counts in 64 bits)."""


def basin_chunk(
    section_map: SectionMap,
    base: np.ndarray,
    target: np.ndarray,
    axes: tuple[int, int],
    x: np.ndarray,
    y_rows: np.ndarray,
    n_strides: int,
    period: int,
    tol: float,
    stop: threading.Event | None = None,
    weight: np.ndarray | None = None,
    radius: float = 0.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Classify the grid rows ``y_rows`` (the unit of work sent to an executor).

    Module-level so that it pickles.  Each point ``z = base`` with ``z[axes[0]] = x[j]`` and
    ``z[axes[1]] = y_rows[i]`` is iterated with ``period`` strides per map call.  A map with
    a compiled batch (:meth:`walker.simulation.stride.StrideMap.basin_batch`: every shipped walker
    but the five-link one, whose lift solves for its tibia angle in Python) runs a row per
    compiled call without the GIL, with the same outcomes; any other :class:`SectionMap`
    runs the Python loop.

    Parameters
    ----------
    section_map : SectionMap
    base : ndarray, shape (n_z,)
        section point whose other coordinates are held fixed.
    target : ndarray, shape (n_z,)
        the fixed point.
    axes : (int, int)
        indices of the coordinates along ``x`` and ``y``.
    x : ndarray, shape (nx,)
    y_rows : ndarray, shape (m,)
    n_strides : int
        maximum number of strides per point.
    period : int
        strides per map call (the fixed point's period).
    tol : float
        convergence when ``max|z - target| <= tol``.
    stop : threading.Event, optional
        (threads only) when set, the chunk is abandoned before its next grid point
        (``walker._executors.Abandoned`` is raised).
    weight : ndarray, shape (n_z, n_z), optional
        the norm of the convergence ball (default the identity).
    radius : float
        also converged when ``||weight (z - target)||_2 <= radius`` (the ball where the
        map is a contraction, :func:`walker.analysis.basin_radius.contraction_ball`); 0: off.

    Returns
    -------
    outcome : ndarray of int, shape (m, nx)
        ``BASIN_CONVERGED``, ``BASIN_UNDECIDED`` or the failing stride's status value.
    strides : ndarray of int, shape (m, nx)
        completed strides before convergence, the fall, or the limit.
    """
    outcome = np.full((len(y_rows), len(x)), BASIN_UNDECIDED, dtype=np.int64)
    strides = np.zeros((len(y_rows), len(x)), dtype=np.int64)
    ax, ay = axes
    batch_of = getattr(section_map, "basin_batch", None)
    batch = batch_of(period) if batch_of is not None else None
    if batch is not None:
        # A row per compiled call (without the GIL): the same outcomes as the loop below.
        target = np.asarray(target, dtype=float)
        for i, yv in enumerate(y_rows):
            if stop is not None and stop.is_set():
                raise Abandoned("basin chunk abandoned")
            z0 = np.repeat(np.asarray(base, dtype=float)[None, :], len(x), axis=0)
            z0[:, ax] = x
            z0[:, ay] = yv
            if radius > 0:
                outcome[i], strides[i] = batch(z0, target, tol, n_strides, weight, radius)
            else:
                outcome[i], strides[i] = batch(z0, target, tol, n_strides)
        return outcome, strides
    for i, yv in enumerate(y_rows):
        for j, xv in enumerate(x):
            if stop is not None and stop.is_set():
                raise Abandoned("basin chunk abandoned")
            z = np.array(base, dtype=float)
            z[ax] = xv
            z[ay] = yv
            done = 0
            while True:
                if np.max(np.abs(z - target)) <= tol or (
                    radius > 0 and np.sum((weight @ (z - target)) ** 2) <= radius * radius
                ):
                    outcome[i, j] = BASIN_CONVERGED
                    break
                if done + period > n_strides:
                    break
                res = map_value(section_map, z, period, None)
                if not res.success:
                    outcome[i, j] = int(res.status)
                    break
                z = res.z
                done += period
            strides[i, j] = done
    return outcome, strides


def basin_map(
    section_map: SectionMap,
    fixed_point: FixedPoint,
    *,
    axes: tuple[int, int] = (0, 1),
    ranges: tuple[tuple[float, float], tuple[float, float]],
    n: tuple[int, int] = (41, 41),
    n_strides: int = 20,
    tol: float = 1e-6,
    converge_radius: float | str = 0.0,
    executor: cf.Executor | str | None = None,
    jobs: int | None = None,
    chunk_size: int | None = None,
    progress: bool = True,
    out: str | os.PathLike | None = None,
    overwrite: bool = False,
    provenance: dict | None = None,
) -> BasinMap:
    """Basin of attraction of ``fixed_point`` on the slice spanned by two section coordinates.

    Parameters
    ----------
    section_map : SectionMap
        must pickle when the executor runs in other processes.
    fixed_point : FixedPoint
        a converged orbit; its ``section`` supplies the coordinates held fixed, its ``period``
        the strides per map call.
    axes : (int, int)
        distinct indices of the section coordinates varied along x and y.
    ranges : ((float, float), (float, float))
        ``((x_lo, x_hi), (y_lo, y_hi))`` in section units, *absolute* values of the two
        coordinates (not offsets from the fixed point), ``lo < hi``.
    n : (int, int)
        grid size ``(nx, ny)``, each >= 2; ``x = linspace(x_lo, x_hi, nx)``.
    n_strides : int
        strides per point before it is called undecided.
    tol : float
        converged when ``max|z - fixed_point.section| <= tol`` (section units).
    converge_radius : float or "auto"
        also converged, stopped early, when ``||W (z - fixed_point.section)||_2 <= r``:
        ``"auto"`` derives ``W`` and ``r`` from the gait's Jacobian and a sampled bound on
        the map's second derivative (:func:`walker.analysis.basin_radius.contraction_ball`, the ball
        where convergence is guaranteed; ``walker basin``'s default); a number ``r > 0``
        uses that radius with the same ``W`` (smallest singular value 1, so the ball lies
        within ``max|z - z*| <= r``); 0 (the default here): the tolerance alone.  The
        result's ``classification`` records ``tol``, the radius, ``W`` and the rule.
    executor : Executor, "serial" or None
        where the chunks run.  ``None``: ``jobs`` threads of this process (the compiled
        strides release the GIL), created and shut down here, inline when ``jobs`` is 1;
        ``"serial"``: inline; any ``concurrent.futures.Executor`` (a process pool, or a
        ``dask.distributed.Client``'s ``get_executor()``; a ``Client`` itself is accepted and
        its ``get_executor()`` used).
    jobs : int, optional
        number of workers when ``executor`` is None; default ``os.cpu_count()``.
    chunk_size : int, optional
        grid rows per task; default about four tasks per worker, or with ``out`` the
        existing checkpoint's chunk size, else about ``ny / 32`` rows
        (:data:`walker.storage.BASIN_DEFAULT_CHUNKS`).
    progress : bool
        a tqdm progress bar over chunks, shown only when stderr is a terminal.
    out : str or os.PathLike, optional
        HDF5 checkpoint and result file (:class:`walker.storage.BasinStore`, kind
        ``"basin"``, read by :func:`walker.storage.read`).  Each chunk of rows is written as
        it finishes; if the file exists and checkpoints this same map (grid, fixed point,
        ``n_strides``, ``tol``, period, ``provenance``), only the chunks not yet done are
        computed.
    overwrite : bool
        with ``out``: start a new checkpoint over an existing file instead of resuming it.
    provenance : dict, optional
        provenance stored in ``out`` (e.g. the scene, model, parameters and solver), which a
        resumed run must repeat.

    Returns
    -------
    BasinMap
        ``outcome[iy, ix]`` is ``BASIN_CONVERGED`` (-1), ``BASIN_UNDECIDED`` (-2) or the
        :class:`~walker.status.Status` value of the fall; ``strides`` counts completed strides.

    Raises
    ------
    ValueError
        for a failed ``fixed_point``, invalid ``axes``, ``ranges``, ``n``, ``n_strides``,
        ``tol``, ``converge_radius``, ``jobs``, ``chunk_size`` or ``executor``.
    FileNotFoundError
        the directory of ``out`` does not exist.
    walker.storage.CheckpointMismatch
        ``out`` exists (and ``overwrite`` is False) but checkpoints a different map, or is
        not a basin checkpoint; raised before any work.

    Examples
    --------
    >>> import numpy as np
    >>> from walker.analysis.fixedpoint import find_fixed_point
    >>> from walker.results import MapResult
    >>> from walker.status import Status
    >>> class Shrink:  # converges to 0 inside |z| < 1, falls outside
    ...     n_z, section_names, parameter_name, parameter_value = 2, ("x", "y"), "c", 0.0
    ...     def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
    ...         if np.max(np.abs(z)) >= 1:
    ...             return MapResult(Status.FELL_FORWARD, np.full(2, np.nan), None, 0.0, z)
    ...         jac = np.eye(2) * 0.5**n_strides if jacobian else None
    ...         return MapResult(Status.COMPLETED, z * 0.5**n_strides, jac, 1.0, z)
    ...     def lift(self, z):
    ...         return z
    ...     def with_parameter(self, value):
    ...         return self
    >>> fp = find_fixed_point(Shrink(), np.array([0.1, 0.1]))
    >>> b = basin_map(Shrink(), fp, ranges=((-1.5, 1.5), (-0.5, 0.5)), n=(3, 2),
    ...               executor="serial", progress=False)
    >>> b.outcome.tolist()
    [[2, -1, 2], [2, -1, 2]]
    """
    if not getattr(fixed_point, "success", False):
        raise ValueError("`fixed_point` must be a converged FixedPoint (success=True)")
    target = np.asarray(fixed_point.section, dtype=float)
    n_z = int(section_map.n_z)
    if target.shape != (n_z,) or not np.all(np.isfinite(target)):
        raise ValueError(f"`fixed_point.section` must be finite with shape ({n_z},)")
    try:
        ax, ay = (int(a) for a in axes)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"`axes` must be two integers, got {axes!r}") from None
    if not (0 <= ax < n_z and 0 <= ay < n_z) or ax == ay:
        raise ValueError(f"`axes` must be two distinct indices in [0, {n_z}), got {axes!r}")
    try:
        (x_lo, x_hi), (y_lo, y_hi) = ((float(a), float(b)) for a, b in ranges)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"`ranges` must be ((x_lo, x_hi), (y_lo, y_hi)), got {ranges!r}") from None
    if not all(np.isfinite([x_lo, x_hi, y_lo, y_hi])) or x_lo >= x_hi or y_lo >= y_hi:
        raise ValueError(f"`ranges` must be finite with lo < hi on both axes, got {ranges!r}")
    try:
        nx, ny = (int(k) for k in n)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"`n` must be two integers (nx, ny), got {n!r}") from None
    if nx < 2 or ny < 2:
        raise ValueError(f"`n` must be at least (2, 2), got {n!r}")
    reason = too_large(16.0 * nx * ny)  # outcome and stride count, int64 each
    if reason is not None:
        raise ValueError(f"`n` = ({nx}, {ny}) gives a grid of {nx * ny:,} points, which {reason}")
    if (
        isinstance(n_strides, bool)
        or not isinstance(n_strides, numbers.Real)
        or not 1 <= n_strides <= MAX_N_STRIDES
        or int(n_strides) != n_strides
    ):
        raise ValueError(
            f"`n_strides` must be an integer >= 1 (at most {MAX_N_STRIDES}), got {n_strides!r}"
        )
    n_strides = int(n_strides)
    try:
        tol = float(tol)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"`tol` must be a positive finite number, got {tol!r}") from None
    if not (np.isfinite(tol) and tol > 0):
        raise ValueError(f"`tol` must be positive and finite, got {tol}")
    auto = isinstance(converge_radius, str)
    if auto and converge_radius != "auto":
        raise ValueError(
            f"`converge_radius` must be 'auto' or a number >= 0, got {converge_radius!r}"
        )
    if not auto:
        try:
            radius = float(converge_radius)
        except (TypeError, ValueError, OverflowError):
            raise ValueError(
                f"`converge_radius` must be 'auto' or a number >= 0, got {converge_radius!r}"
            ) from None
        if not (np.isfinite(radius) and radius >= 0):
            raise ValueError(f"`converge_radius` must be finite and >= 0, got {radius}")
    if jobs is not None and (
        isinstance(jobs, bool) or not isinstance(jobs, int | np.integer) or jobs < 1
    ):
        raise ValueError(f"`jobs` must be an integer >= 1, got {jobs!r}")
    if jobs is not None and executor is not None:
        raise ValueError("`jobs` applies to the default executor only: give one or the other")
    if chunk_size is not None and (int(chunk_size) != chunk_size or chunk_size < 1):
        raise ValueError(f"`chunk_size` must be an integer >= 1, got {chunk_size!r}")
    if isinstance(executor, str) and executor != "serial":
        raise ValueError(f"`executor` must be an Executor, 'serial' or None, got {executor!r}")
    if hasattr(executor, "get_executor") and not isinstance(executor, cf.Executor):
        executor = executor.get_executor()  # a dask.distributed Client
    if executor is not None and not isinstance(executor, str | cf.Executor):
        raise ValueError(
            f"`executor` must be a concurrent.futures.Executor, 'serial' or None, got "
            f"{type(executor).__name__}"
        )

    if out is not None and not isinstance(out, str | os.PathLike):
        raise TypeError(f"`out` must be a str or os.PathLike, got {type(out).__name__}")
    if provenance is not None and not isinstance(provenance, dict):
        raise TypeError(f"`provenance` must be a dict or None, got {type(provenance).__name__}")

    period = int(fixed_point.period)
    weight, classification = np.eye(n_z), {"tol": tol, "converge_radius": 0.0}
    if auto or radius > 0:
        from walker.analysis.basin_radius import contraction_ball

        weight, found, info = contraction_ball(section_map, fixed_point)
        radius = found if auto else radius
        classification = {
            "tol": tol,
            "converge_radius": radius,
            "converge_radius_rule": "auto" if auto else "given",
            "certified_radius": found,
            "weight": weight.tolist(),
            **info,
        }
    x = np.linspace(x_lo, x_hi, nx)
    y = np.linspace(y_lo, y_hi, ny)
    base = target.copy()
    names = tuple(section_map.section_names)
    axis_names = (names[ax], names[ay])
    n_cpu = int(jobs) if jobs is not None else (os.cpu_count() or 1)
    serial = executor == "serial" or (executor is None and n_cpu == 1)
    n_workers = 1 if serial else getattr(executor, "_max_workers", None) or n_cpu
    store = None
    if out is not None:
        from walker.storage import BasinStore

        store = BasinStore.create_or_open(
            out,
            axis_names=axis_names,
            x=x,
            y=y,
            fixed_point=target,
            base=base,
            n_strides=n_strides,
            tol=tol,
            period=period,
            provenance=provenance or {},
            classification=classification,
            chunk_size=None if chunk_size is None else int(chunk_size),
            overwrite=bool(overwrite),
        )
        chunk_size = store.chunk_size
        pending = store.pending_chunks()
        classification = store.classification  # a resumed automatic ball: the file's
        radius = float(classification.get("converge_radius", 0.0))
        if radius > 0:
            weight = np.array(classification["weight"], dtype=float)
    elif chunk_size is None:
        chunk_size = max(1, math.ceil(ny / (4 * n_workers)))
    chunk_size = int(chunk_size)
    n_chunks = -(-ny // chunk_size)
    if store is None:
        pending = list(range(n_chunks))
    outcome = np.empty((ny, nx), dtype=np.int64)
    strides = np.empty((ny, nx), dtype=np.int64)
    args = (base, target, (ax, ay), x)
    ball = {"weight": weight, "radius": radius} if radius > 0 else {}

    def rows(i: int) -> np.ndarray:
        return y[i * chunk_size : (i + 1) * chunk_size]

    def finish(i: int, result: tuple[np.ndarray, np.ndarray]) -> None:
        o, k = result
        if store is not None:
            store.write_chunk(i, o, k)
        else:
            outcome[i * chunk_size : i * chunk_size + o.shape[0]] = o
            strides[i * chunk_size : i * chunk_size + o.shape[0]] = k
        bar.update(1)

    # The progress policy of walker._executors (a bar only on a terminal, none left behind
    # by an interrupt), drawn only when there is work.
    with progress_bar(
        progress and bool(pending),
        total=n_chunks,
        initial=n_chunks - len(pending),
        desc="basin",
        unit="chunk",
    ) as bar:
        if serial:
            for i in pending:
                finish(i, basin_chunk(section_map, *args, rows(i), n_strides, period, tol, **ball))
        elif pending:
            own = executor is None
            pool = worker_pool(n_cpu, len(pending), name="basin") if own else executor
            stop = None
            fn = functools.partial(basin_chunk, **ball) if ball else basin_chunk
            if isinstance(pool, cf.ThreadPoolExecutor):
                # Threads cannot be killed: on an interrupt they stop between grid points.
                stop = threading.Event()
                fn = functools.partial(basin_chunk, stop=stop, **ball)
            try:
                run_chunks(
                    pool,
                    fn,
                    ((i, (section_map, *args, rows(i), n_strides, period, tol)) for i in pending),
                    finish,
                    own=own,
                    stop=stop,
                )
            finally:
                if own:
                    pool.shutdown(wait=True, cancel_futures=True)
    if store is not None:
        return store.result()
    return BasinMap(
        axis_names=axis_names,
        x=x,
        y=y,
        outcome=outcome,
        strides=strides,
        fixed_point=target.copy(),
        base=base,
        n_strides=n_strides,
        classification=classification,
    )
