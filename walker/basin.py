"""Basins of attraction of a gait on a 2-D slice of the Poincaré section.

Each grid point starts from the fixed point with two chosen section coordinates replaced and
is iterated by the section map until it comes within ``tol`` of the fixed point (converged),
falls (the failing stride's :class:`~walker.status.Status`), or runs out of strides
(undecided).  Rows of the grid are grouped into chunks, and the chunks run on any
:class:`concurrent.futures.Executor`: threads of this process by default (the compiled
strides release the GIL; the per-point loop between them is Python and holds it, so two
threads reach about 1.6x one, and a started process pool about 1.9x, see
results/bench/basin.md), a process pool, or a ``dask.distributed`` cluster through
``Client.get_executor()``.
"""

from __future__ import annotations

import concurrent.futures as cf
import math
import os
import sys

import numpy as np

from walker.fixedpoint import SectionMap, _map_value
from walker.results import BASIN_CONVERGED, BASIN_UNDECIDED, BasinMap, FixedPoint

__all__ = ["basin_map", "basin_chunk"]


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
) -> tuple[np.ndarray, np.ndarray]:
    """Classify the grid rows ``y_rows`` (the unit of work sent to an executor).

    Module-level so that it pickles.  Each point ``z = base`` with ``z[axes[0]] = x[j]`` and
    ``z[axes[1]] = y_rows[i]`` is iterated with ``period`` strides per map call.

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
    for i, yv in enumerate(y_rows):
        for j, xv in enumerate(x):
            z = np.array(base, dtype=float)
            z[ax] = xv
            z[ay] = yv
            done = 0
            while True:
                if np.max(np.abs(z - target)) <= tol:
                    outcome[i, j] = BASIN_CONVERGED
                    break
                if done + period > n_strides:
                    break
                res = _map_value(section_map, z, period, None)
                if not res.success:
                    outcome[i, j] = int(res.status)
                    break
                z = res.z
                done += period
            strides[i, j] = done
    return outcome, strides


def _default_pool(n_workers: int) -> cf.ThreadPoolExecutor:
    """Threads in this process: a stride runs in walker's compiled kernel with the GIL
    released, so ``n_workers`` threads run ``n_workers`` strides at once, with no process
    start-up and nothing to pickle.  (A section map written in Python holds the GIL and gains
    nothing from threads: pass a ``ProcessPoolExecutor`` for it.)"""
    return cf.ThreadPoolExecutor(max_workers=n_workers, thread_name_prefix="walker-basin")


def _use_progress(progress: bool) -> bool:
    if not progress:
        return False
    try:
        return bool(sys.stderr.isatty())
    except (AttributeError, ValueError):
        return False


def basin_map(
    section_map: SectionMap,
    fixed_point: FixedPoint,
    *,
    axes: tuple[int, int] = (0, 1),
    ranges: tuple[tuple[float, float], tuple[float, float]],
    n: tuple[int, int] = (41, 41),
    n_strides: int = 20,
    tol: float = 1e-6,
    executor: cf.Executor | str | None = None,
    jobs: int | None = None,
    chunk_size: int | None = None,
    progress: bool = True,
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
    executor : Executor, "serial" or None
        where the chunks run.  ``None``: ``jobs`` threads of this process (the compiled
        strides release the GIL), created and shut down here, inline when ``jobs`` is 1;
        ``"serial"``: inline; any ``concurrent.futures.Executor`` (a process pool, or a
        ``dask.distributed.Client``'s ``get_executor()``; a ``Client`` itself is accepted and
        its ``get_executor()`` used).
    jobs : int, optional
        number of workers when ``executor`` is None; default ``os.cpu_count()``.
    chunk_size : int, optional
        grid rows per task; default about four tasks per worker.
    progress : bool
        a tqdm progress bar over chunks, shown only when stderr is a terminal.

    Returns
    -------
    BasinMap
        ``outcome[iy, ix]`` is ``BASIN_CONVERGED`` (-1), ``BASIN_UNDECIDED`` (-2) or the
        :class:`~walker.status.Status` value of the fall; ``strides`` counts completed strides.

    Raises
    ------
    ValueError
        for a failed ``fixed_point``, invalid ``axes``, ``ranges``, ``n``, ``n_strides``,
        ``tol``, ``jobs``, ``chunk_size`` or ``executor``.

    Examples
    --------
    >>> import numpy as np
    >>> from walker.fixedpoint import find_fixed_point
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
    except (TypeError, ValueError):
        raise ValueError(f"`axes` must be two integers, got {axes!r}") from None
    if not (0 <= ax < n_z and 0 <= ay < n_z) or ax == ay:
        raise ValueError(f"`axes` must be two distinct indices in [0, {n_z}), got {axes!r}")
    try:
        (x_lo, x_hi), (y_lo, y_hi) = ((float(a), float(b)) for a, b in ranges)
    except (TypeError, ValueError):
        raise ValueError(f"`ranges` must be ((x_lo, x_hi), (y_lo, y_hi)), got {ranges!r}") from None
    if not all(np.isfinite([x_lo, x_hi, y_lo, y_hi])) or x_lo >= x_hi or y_lo >= y_hi:
        raise ValueError(f"`ranges` must be finite with lo < hi on both axes, got {ranges!r}")
    try:
        nx, ny = (int(k) for k in n)
    except (TypeError, ValueError):
        raise ValueError(f"`n` must be two integers (nx, ny), got {n!r}") from None
    if nx < 2 or ny < 2:
        raise ValueError(f"`n` must be at least (2, 2), got {n!r}")
    if isinstance(n_strides, bool) or int(n_strides) != n_strides or n_strides < 1:
        raise ValueError(f"`n_strides` must be an integer >= 1, got {n_strides!r}")
    n_strides = int(n_strides)
    tol = float(tol)
    if not (np.isfinite(tol) and tol > 0):
        raise ValueError(f"`tol` must be positive and finite, got {tol}")
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

    period = int(fixed_point.period)
    x = np.linspace(x_lo, x_hi, nx)
    y = np.linspace(y_lo, y_hi, ny)
    base = target.copy()
    n_cpu = int(jobs) if jobs is not None else (os.cpu_count() or 1)
    serial = executor == "serial" or (executor is None and n_cpu == 1)
    n_workers = 1 if serial else getattr(executor, "_max_workers", None) or n_cpu
    if chunk_size is None:
        chunk_size = max(1, math.ceil(ny / (4 * n_workers)))
    starts = list(range(0, ny, int(chunk_size)))
    chunks = [y[s : s + int(chunk_size)] for s in starts]
    outcome = np.empty((ny, nx), dtype=np.int64)
    strides = np.empty((ny, nx), dtype=np.int64)
    args = (base, target, (ax, ay), x)

    bar = None
    if _use_progress(progress):
        from tqdm import tqdm

        bar = tqdm(total=len(chunks), desc="basin", unit="chunk")
    try:
        if serial:
            for s, rows in zip(starts, chunks, strict=True):
                o, k = basin_chunk(section_map, *args, rows, n_strides, period, tol)
                outcome[s : s + len(rows)] = o
                strides[s : s + len(rows)] = k
                if bar is not None:
                    bar.update(1)
        else:
            own = executor is None
            pool = _default_pool(n_cpu) if own else executor
            try:
                futures = {
                    pool.submit(basin_chunk, section_map, *args, rows, n_strides, period, tol): s
                    for s, rows in zip(starts, chunks, strict=True)
                }
                for fut in cf.as_completed(futures):
                    s = futures[fut]
                    o, k = fut.result()
                    outcome[s : s + o.shape[0]] = o
                    strides[s : s + o.shape[0]] = k
                    if bar is not None:
                        bar.update(1)
            finally:
                if own:
                    pool.shutdown(wait=True, cancel_futures=True)
    finally:
        if bar is not None:
            bar.close()
    names = tuple(section_map.section_names)
    return BasinMap(
        axis_names=(names[ax], names[ay]),
        x=x,
        y=y,
        outcome=outcome,
        strides=strides,
        fixed_point=target.copy(),
        base=base,
        n_strides=n_strides,
    )
