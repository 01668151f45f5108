"""Resumable parameter sweeps of a stride map on any :class:`concurrent.futures.Executor`.

A sweep evaluates a walker at every point of a Cartesian grid of parameter values: either the
outcome of ``n_strides`` strides from a fixed section point (``kind="outcome"``) or the
period-``n_strides`` gait and its Floquet multipliers (``kind="fixed_point"``).

How the work is cut and run (DESIGN.md, decision 10):

1. The grid is flattened with the last parameter varying fastest and cut into chunks of
   ``chunk_size`` consecutive points.  A chunk is one task: :func:`sweep_chunk`, a module-level
   function of plain, picklable arguments (the stride map travels as :class:`MapSpec`, which
   rebuilds it in the worker once per process).
2. The table never depends on how the work is cut.  Outcome points are independent.  A
   fixed-point point starts from a guess that is a function of the grid only
   (:mod:`walker.analysis.sweep_chains`): the points are walked along lines of the grid, outwards
   from the point nearest the base map's parameters, each warm-started from the gait its
   neighbour on the line converged to (extrapolated along the line from up to three such
   gaits); a fixed-point task is a run of whole lines.  So
   serial, threads, a process pool, a dask cluster, any chunk size and a resumed run give
   identical tables.  A point whose gait differs from a converged neighbour's beyond
   stated thresholds is flagged in the ``jump`` column.
3. With ``out`` every chunk is written to a :class:`~walker.storage.SweepStore` checkpoint as
   soon as it finishes; running the same call again after a kill computes only the chunks not
   yet marked done.
4. Everything is validated before any work starts; expected failures of a point (a fall,
   Newton not converging) are statuses in the table, never exceptions.
5. Sizes are bounded before anything is allocated: a sweep has at most
   :data:`MAX_SWEEP_POINTS` points, and its table must fit in
   :func:`walker.results.memory_limit`.
6. The pool of ``executor="processes"`` is walker's own: its workers end when the process
   that started them dies (:func:`walker._executors.die_with_parent`), so a ``kill -9`` of a
   sweep leaves no worker computing for nobody.

Where the parts are: the grid, its checks and the table's layout in
:mod:`walker.analysis.sweep_grid` (everything public there is importable from here too); the pool
and progress policy, shared with :func:`walker.analysis.basin.basin_map`, in
:mod:`walker._executors`; here the unit of work (:func:`sweep_chunk`, :class:`MapSpec`) and the
driver (:func:`sweep`).

Examples
--------
>>> from walker import StrideMap, load_scene
>>> from walker.analysis.sweep import sweep
>>> scene = load_scene("gaits/simplest_garcia.toml")
>>> P = StrideMap("simplest", scene.params, rtol=1e-10, atol=1e-12)
>>> table = sweep(P, ["slope=0.008:0.010:3"], z0=P.project(scene.state),
...               executor="serial", progress=False)
>>> table.parameter_names, table.columns["status"].tolist()
(('slope',), [0, 0, 0])
"""

from __future__ import annotations

import concurrent.futures as cf
import dataclasses
import functools
import numbers
import os
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from walker._checks import as_vector as _as_vector
from walker._executors import die_with_parent, progress_bar, run_chunks, worker_pool
from walker.analysis.sweep_chains import (
    MapSpec,
    _fixed_point,
    _materialize,
    _retargeter,
    root_index,
    run_lines,
)
from walker.analysis.sweep_grid import (
    DEFAULT_CHUNK_POINTS,
    KINDS,
    MAX_SWEEP_POINTS,
    MIN_DEFAULT_CHUNKS,
    check_grid_size,
    check_names,
    check_points,
    default_chunk_size,
    fill_gsn,
    fill_measures,
    grid_points,
    parse_range,
    table_columns,
)
from walker.analysis.sweep_grid import (
    bytes_per_point as _bytes_per_point,  # walker.cli.sweep's name
)
from walker.results import SweepTable
from walker.simulation.sectionmap import validate_positive
from walker.simulation.stride import StrideMap, solver_settings

__all__ = [
    "DASK_TASK_POINTS",
    "DEFAULT_CHUNK_POINTS",
    "KINDS",
    "MAX_SWEEP_POINTS",
    "MIN_DEFAULT_CHUNKS",
    "MapSpec",
    "check_grid_size",
    "default_chunk_size",
    "die_with_parent",
    "grid_points",
    "parse_range",
    "sweep",
    "sweep_chunk",
    "sweep_chunks",
]


# ---------------------------------------------------------------------------------------------
# The unit of work
# ---------------------------------------------------------------------------------------------


def sweep_chunk(
    section_map: MapSpec | Any,
    names: tuple[str, ...],
    points: np.ndarray,
    kind: str,
    z0: np.ndarray,
    n_strides: int,
    tol: float,
    *,
    checked: bool = False,
    gsn: bool = False,
) -> dict[str, np.ndarray]:
    """Evaluate one chunk of a sweep (the task sent to an executor).

    Module-level, with picklable arguments.  The rows depend only on the arguments, never on
    other chunks.

    Parameters
    ----------
    section_map : MapSpec or StrideMap
        the base map; each point uses ``map.with_params(**point)``.
    names : tuple of str, length k
    points : ndarray, shape (m, k)
    kind : {"outcome", "fixed_point"}
    z0 : ndarray, shape (n_z,)
        section point (outcome) or initial guess (fixed_point).
    n_strides : int
        strides per point (outcome) or the gait's period (fixed_point).
    tol : float
        Newton tolerance, max-norm of ``P^k(z) - z`` (fixed_point).
    checked : bool
        the arguments were checked already (:func:`sweep` checks every grid point before
        any work and passes True): they are not checked again.
    gsn : bool
        (fixed_point) also the ``gsn`` column (:func:`walker.analysis.sweep_grid.fill_gsn`).

    Returns
    -------
    dict
        column name -> ndarray of shape ``(m, *shape)`` (see :func:`sweep`).

    Raises
    ------
    ValueError, TypeError
        an unknown ``kind`` or parameter name, ``points`` not of shape ``(m, k)`` or a point
        outside the parameters' bounds, a bad ``z0``, ``n_strides`` or ``tol``; before any
        work.

    Notes
    -----
    Each fixed-point search has a budget of
    :data:`walker.analysis.fixedpoint.POINT_MAX_EVALS` stride-map evaluations (the warm start, and
    the retry from ``z0`` again), so a point without a gait costs a few tens of strides at
    most and a point whose guess does not walk one or two; a gait converges from a warm
    start in 4-6.
    """

    if kind not in KINDS:
        raise ValueError(f"`kind` must be one of {', '.join(KINDS)}, got {kind!r}")
    base = _materialize(section_map)
    if not (hasattr(base, "params") and hasattr(base, "_with_params_object")):
        raise TypeError(
            f"`section_map` must be a walker.StrideMap or a MapSpec, got {type(base).__name__}"
        )
    if not checked:
        names, points, z0, n_strides, tol = _chunk_arguments(
            base, names, points, z0, n_strides, tol
        )
    n_z = int(base.n_z)
    m = points.shape[0]
    out = {
        name: np.full((m, *shape), -1 if dtype == "i8" else np.nan, dtype=dtype)
        for name, (dtype, shape) in table_columns(kind, n_z, gsn).items()
    }
    z_guess = z0
    retarget = _retargeter(base)
    for i in range(m):
        # Every grid point was validated by `sweep` before any work was submitted.
        values = dict(zip(names, points[i].tolist(), strict=True))
        point_map = retarget(base.params._replace_validated(**values))
        if kind == "outcome":
            r = point_map(z0, n_strides=n_strides)
            out["status"][i] = int(r.status)
            out["section"][i] = r.z
            out["step_time"][i] = r.step_time
            continue
        fp = _fixed_point(point_map, z_guess, z0, n_strides, tol)
        out["status"][i] = int(fp.status)
        out["residual"][i] = fp.residual
        out["n_iter"][i] = fp.n_iter
        out["stable"][i] = int(bool(fp.stable) and fp.success)
        if fp.success:
            z_guess = fp.section
            out["section"][i] = fp.section
            out["step_time"][i] = fp.step_time
            out["multipliers_re"][i] = fp.multipliers.real
            out["multipliers_im"][i] = fp.multipliers.imag
            fill_measures(point_map, fp, out, i)
            if gsn:
                fill_gsn(point_map, fp, out, i)
    return out


DASK_TASK_POINTS = 500
"""Fewest points of an outcome sweep's task on a dask cluster: a task there carries whole
chunks, as many as make this many points (a dask task costs a few ms of scheduling and
messages, about what 50 compass strides take; a chunk of the default size may hold 16)."""


def sweep_chunks(chunks: list[tuple]) -> list[dict[str, np.ndarray]]:
    """:func:`sweep_chunk` of each argument tuple of ``chunks`` (checked already), in order:
    the task of an outcome sweep on a dask cluster (:data:`DASK_TASK_POINTS`)."""
    return [sweep_chunk(*args, checked=True) for args in chunks]


def _is_dask(executor: Any) -> bool:
    """Whether ``executor`` is a ``dask.distributed`` client's executor."""
    return type(executor).__module__.split(".")[0] == "distributed"


def _chunk_arguments(base, names, points, z0, n_strides, tol):
    """The arguments of :func:`sweep_chunk` checked (it is public: nothing is assumed)."""
    if isinstance(names, str) or not all(isinstance(n, str) for n in names):
        raise TypeError(f"`names` must be a tuple of parameter names, got {names!r}")
    names = tuple(names)
    check_names(base, names, "`names`")
    try:
        points = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise TypeError("`points` must be an array of real numbers, shape (m, k)") from None
    if points.ndim != 2 or points.shape[1] != len(names):
        raise ValueError(
            f"`points` must have shape (m, {len(names)}) (one column per name), got {points.shape}"
        )
    if not np.all(np.isfinite(points)):
        raise ValueError("All values in `points` must be finite")
    check_points(base.params, names, points)
    n_z = int(base.n_z)
    z0 = np.asarray(z0)
    if z0.dtype.kind not in "iuf" or z0.shape != (n_z,) or not np.all(np.isfinite(z0)):
        raise ValueError(
            f"`z0` must be {n_z} finite real numbers (the map's n_z), got shape {z0.shape} "
            f"dtype {z0.dtype}"
        )
    n_strides = _positive_int(n_strides, "n_strides")
    return names, points, z0.astype(np.float64), n_strides, validate_positive(tol, "tol")


# ---------------------------------------------------------------------------------------------
# The driver
# ---------------------------------------------------------------------------------------------


def _positive_int(value: Any, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 1:
        raise ValueError(f"`{name}` must be an integer >= 1, got {value!r}")
    return int(value)


def _sweep_provenance(stride_map: StrideMap, kind, z0, n_strides, tol, provenance, gsn) -> dict:
    from walker.storage import solver_provenance

    auto: dict[str, Any] = {"sweep_kind": kind, "n_strides": n_strides, "z0": z0.tolist()}
    if kind == "fixed_point":
        auto["tol"] = tol
    if gsn:
        auto["gsn_disturbance"] = "step height (walker.analysis.gsn)"
    if isinstance(stride_map, StrideMap):
        settings = solver_settings(stride_map)
        auto.update(solver_provenance(stride_map.model, stride_map.params, **settings))
    if provenance is None:
        return auto
    if not isinstance(provenance, dict):
        raise TypeError(f"`provenance` must be a dict or None, got {type(provenance).__name__}")
    clash = sorted(k for k in provenance if k in auto and provenance[k] != auto[k])
    if clash:
        raise ValueError(
            f"`provenance` must not contradict what the sweep records itself; differing keys: "
            f"{clash}"
        )
    return {**auto, **provenance}


def _validate(stride_map, ranges, kind, z0, n_strides, chunk_size, jobs, tol, gsn=False):
    """Check the arguments of :func:`sweep`; returns the grid and the normalized values."""
    if not (hasattr(stride_map, "with_params") and hasattr(stride_map, "params")):
        raise TypeError(f"`stride_map` must be a walker.StrideMap, got {type(stride_map).__name__}")
    if kind not in KINDS:
        raise ValueError(f"`kind` must be one of {', '.join(KINDS)}, got {kind!r}")
    n_z = int(stride_map.n_z)
    z0 = _as_vector(z0, "z0")
    if z0.shape != (n_z,):
        raise ValueError(f"`z0` must have shape ({n_z},) (the map's n_z), got {z0.shape}")
    if not np.all(np.isfinite(z0)):
        raise ValueError(f"All components of `z0` must be finite, got {z0.tolist()}")
    n_strides = _positive_int(n_strides, "n_strides")
    if chunk_size is not None:
        chunk_size = _positive_int(chunk_size, "chunk_size")
    if jobs is not None:
        jobs = _positive_int(jobs, "jobs")
    tol = validate_positive(tol, "tol")
    if gsn is not False:
        _check_gsn(stride_map, kind, gsn, tol)
    names, points = grid_points(ranges)
    check_names(stride_map, names, "`ranges`")
    n_points = points.shape[0]
    check_grid_size([n_points], "`ranges`", _bytes_per_point(kind, n_z, len(names), gsn))
    check_points(stride_map.params, names, points)
    chunk = default_chunk_size(n_points, kind) if chunk_size is None else chunk_size
    return names, points, z0, n_strides, chunk, jobs, tol


def _check_gsn(stride_map, kind, gsn, tol) -> None:
    """The ``gsn`` option of :func:`sweep`: a fixed-point sweep of a map that walks on terrain,
    with a Newton tolerance the norm's fixed-point check (1e-8) accepts."""
    if gsn is not True:
        raise TypeError(f"`gsn` must be a bool, got {gsn!r}")
    if kind != "fixed_point":
        raise ValueError(f"`gsn` needs kind='fixed_point' (the norm of a gait), got {kind!r}")
    if tol > 1e-8:
        raise ValueError(f"`tol` must be <= 1e-8 with `gsn` (the norm's gait check), got {tol!r}")
    from walker.simulation._terrain_run import check_supported

    check_supported(stride_map, "the gait sensitivity norm (`gsn`)")


def sweep(
    stride_map: StrideMap,
    ranges: Any,
    *,
    kind: str = "outcome",
    z0: Any,
    n_strides: int = 1,
    chunk_size: int | None = None,
    executor: cf.Executor | str | None = None,
    jobs: int | None = None,
    out: str | os.PathLike | None = None,
    progress: bool = True,
    provenance: dict | None = None,
    tol: float = 1e-10,
    overwrite: bool = False,
    gsn: bool = False,
) -> SweepTable:
    """Evaluate a stride map over a parameter grid, chunk by chunk, on an executor.

    Parameters
    ----------
    stride_map : StrideMap
        the base map: the walker, its base parameters and solver settings.  Each grid point
        runs ``stride_map.with_params(**point)``.
    ranges : sequence or mapping
        parameters to vary: ``"NAME=START:STOP:COUNT"`` / ``"NAME=V1,V2"`` texts
        (:func:`parse_range`), ``(name, values)`` pairs, or a mapping ``name -> values``.
        The grid is their Cartesian product, last parameter fastest (:func:`grid_points`).
    kind : {"outcome", "fixed_point"}
        ``"outcome"``: the map applied ``n_strides`` times from ``z0`` at each point.
        ``"fixed_point"``: the period-``n_strides`` gait by :func:`~walker.analysis.fixedpoint.
        find_fixed_point` (tolerance ``tol``), warm-started from a converged grid neighbour
        along lines of the grid (:mod:`walker.analysis.sweep_chains`; the point nearest the base
        parameters starts from ``z0``), retried from ``z0`` if that fails.
    z0 : array_like, shape (n_z,)
        section point (outcome) or initial guess (fixed_point).
    n_strides : int
        strides per point (outcome) or period of the gait (fixed_point), >= 1.
    chunk_size : int, optional
        points per checkpoint chunk and per task (a fixed-point task is a run of whole
        lines of about that many points; on a dask cluster an outcome task carries as many
        chunks as make :data:`DASK_TASK_POINTS` points), >= 1; it never changes the table.  Default
        :func:`default_chunk_size` (at most 256 for outcome, 16 for fixed_point, and at
        least 16 chunks when there are 16 points).  A resumed sweep must use the chunk size
        it started with.
    executor : concurrent.futures.Executor, dask.distributed.Client, "serial", "processes" or None
        ``None``: ``jobs or os.cpu_count()`` threads of this process (the compiled strides
        release the GIL) created and shut down here; ``"processes"``: as many worker
        processes, created and shut down here, which end when this process dies
        (:func:`walker._executors.process_pool`); ``"serial"``: run inline; an ``Executor``
        is used as is (and left running; the workers of a ``ProcessPoolExecutor`` are made
        to end with this process from their first chunk on); a
        ``dask.distributed.Client`` through its ``get_executor()``.
    jobs : int, optional
        workers of the default pool or of ``"processes"`` (>= 1); ignored with a warning
        when another ``executor`` is given.
    out : str or os.PathLike, optional
        HDF5 checkpoint (:class:`walker.storage.SweepStore`).  Each chunk is written as it
        finishes; if the file exists and holds this same sweep (grid, columns, chunk size,
        provenance), only the chunks not yet done are computed.
    progress : bool
        tqdm bar over points on stderr (only when stderr is a terminal).
    provenance : dict, optional
        extra provenance for ``out`` (e.g. the scene path).  The sweep records
        ``sweep_kind``, ``n_strides``, ``z0`` (and ``tol`` for fixed points) and the
        :func:`walker.storage.solver_provenance` of the map itself (``model``,
        ``parameters`` (base values with units), ``method``, ``rtol``, ``atol``, ``t_max``,
        ``first_step``, ``kernel_hash`` and the model's conventions, e.g. ``swing_scuff``);
        the walker version is added by storage.
    tol : float
        Newton tolerance (fixed_point), > 0.
    overwrite : bool
        with ``out``: replace an existing file by a new checkpoint instead of resuming it.
    gsn : bool
        (fixed_point) also a column ``gsn``: the gait sensitivity norm of each point's gait
        (:func:`walker.analysis.gsn.gait_sensitivity`; NaN where there is no stable period-one gait
        or no norm).  It makes a sweep 3 to 5 times slower (20-point slope sweeps of the
        compass, kneed and rimless walkers), hence optional.  Needs a map that walks on
        terrain and ``tol <= 1e-8``.

    Returns
    -------
    SweepTable
        ``points`` shape (n, k); ``columns``: ``status`` (int, :class:`Status` codes),
        ``section`` (n, n_z), ``step_time`` [s]; for fixed points also ``multipliers_re``,
        ``multipliers_im`` (n, n_z, sorted by decreasing modulus), ``residual``, ``stable``
        (int 0/1), ``n_iter``, ``jump`` (int 0/1: :func:`walker.analysis.sweep_chains.jump_flags`;
        -1 in a checkpoint not finished).  Where a point failed, its section, step time and
        multipliers are NaN (an outcome's ``step_time`` is then the time of the failure).

    Raises
    ------
    ValueError
        unknown parameter names (the message lists the valid ones), a grid point outside
        the parameters' bounds, a bad ``z0``, ``kind``, ``n_strides``, ``chunk_size``,
        ``jobs`` or ``tol``; all before any work.
    FileNotFoundError
        the directory of ``out`` does not exist.
    walker.storage.CheckpointMismatch
        ``out`` exists (and ``overwrite`` is False) but checkpoints a different sweep, or is
        corrupted; raised before any work.

    Notes
    -----
    On ``KeyboardInterrupt`` (or any interrupt raised in the calling thread while the chunks
    run) the chunks not started are cancelled (on dask too), running threads finish their
    chunk, a process pool is shut down and its workers terminated, every finished chunk is
    written to ``out``, and the interrupt propagates; the same call then resumes.

    Examples
    --------
    >>> from walker import StrideMap, load_scene
    >>> scene = load_scene("gaits/compass_goswami.toml")
    >>> P = StrideMap("compass", scene.params, rtol=1e-10, atol=1e-12)
    >>> t = sweep(P, {"slope": [0.05, 0.0523598775598]}, kind="fixed_point",
    ...           z0=P.project(scene.state), executor="serial", progress=False)
    >>> t.columns["status"].tolist(), t.columns["stable"].tolist()
    ([0, 0], [1, 1])
    """
    plan = _prepare(
        stride_map,
        ranges,
        kind=kind,
        z0=z0,
        n_strides=n_strides,
        chunk_size=chunk_size,
        executor=executor,
        jobs=jobs,
        out=out,
        overwrite=overwrite,
        provenance=provenance,
        tol=tol,
        gsn=gsn,
    )
    return _execute(plan, executor, progress)


@dataclasses.dataclass
class _Plan:
    """A validated sweep with its checkpoint opened (or created): what is left is the work."""

    stride_map: Any
    names: tuple[str, ...]
    points: np.ndarray
    kind: str
    z0: np.ndarray
    n_strides: int
    chunk: int
    jobs: int | None
    tol: float
    columns: dict
    store: Any
    pending: list[int]
    shape: tuple[int, ...] = ()
    root: tuple[int, ...] = ()
    scale: np.ndarray | None = None
    gsn: bool = False


def _check_executor(executor: Any, jobs: int | None) -> Any:
    if isinstance(executor, str) and executor not in ("serial", "processes"):
        raise ValueError(
            f"`executor` must be an Executor, 'serial' or None, or 'processes' (worker "
            f"processes), got {executor!r}"
        )
    if hasattr(executor, "get_executor") and not isinstance(executor, cf.Executor):
        executor = executor.get_executor()  # a dask.distributed Client
    if executor is not None and not isinstance(executor, str | cf.Executor):
        raise TypeError(
            "`executor` must be a concurrent.futures.Executor, a dask.distributed.Client, "
            f"'serial' or None, got {type(executor).__name__}"
        )
    if executor not in (None, "processes") and jobs is not None:
        warnings.warn("`jobs` has no effect when `executor` is given", stacklevel=4)
    return executor


def _prepare(
    stride_map,
    ranges,
    *,
    kind,
    z0,
    n_strides,
    chunk_size,
    executor,
    jobs,
    out,
    overwrite,
    provenance,
    tol,
    gsn=False,
) -> _Plan:
    """Everything :func:`sweep` does before the work: validation, then the checkpoint."""
    names, points, z0, n_strides, chunk, jobs, tol = _validate(
        stride_map, ranges, kind, z0, n_strides, chunk_size, jobs, tol, gsn
    )
    n_points = points.shape[0]
    n_z = int(stride_map.n_z)
    _check_executor(executor, jobs)
    columns = table_columns(kind, n_z, gsn)
    n_chunks = -(-n_points // chunk)
    store = None
    if out is not None:
        from walker.storage import SweepStore

        if not isinstance(out, str | os.PathLike):
            raise TypeError(f"`out` must be a str or os.PathLike, got {type(out).__name__}")
        parent = Path(out).parent
        if not parent.is_dir():
            raise FileNotFoundError(f"directory '{parent}' of `out` '{out}' does not exist")
        prov = _sweep_provenance(stride_map, kind, z0, n_strides, tol, provenance, gsn)
        store = SweepStore.create_or_open(
            out,
            parameter_names=names,
            points=points,
            columns=columns,
            chunk_size=chunk,
            provenance=prov,
            overwrite=bool(overwrite),
        )
        pending = store.pending_chunks()
    else:
        if provenance is not None and not isinstance(provenance, dict):
            raise TypeError(f"`provenance` must be a dict or None, got {type(provenance).__name__}")
        pending = list(range(n_chunks))
    plan = _Plan(
        stride_map, names, points, kind, z0, n_strides, chunk, jobs, tol, columns, store, pending
    )
    plan.gsn = bool(gsn)
    if kind == "fixed_point":
        _plan_lines(plan, ranges)
    return plan


def _plan_lines(plan: _Plan, ranges: Any) -> None:
    """The grid's shape, the root of its warm-start lines and the section's scale
    (:mod:`walker.analysis.sweep_chains`)."""
    from walker.analysis.sweep_grid import _normalize_ranges
    from walker.simulation.region import WalkingRegion

    axes = [values for _, values in _normalize_ranges(ranges)]
    plan.shape = tuple(len(v) for v in axes)
    base = [float(getattr(plan.stride_map.params, name)) for name in plan.names]
    plan.root = root_index(axes, base)
    scale = np.ones(int(plan.stride_map.n_z))
    model = getattr(plan.stride_map, "model", None)
    if getattr(model, "section_names", None) is not None:
        scale = np.asarray(WalkingRegion(model, plan.stride_map.params).scale, dtype=float)
    plan.scale = scale


def _execute(plan: _Plan, executor: Any, progress: bool) -> SweepTable:
    """Run the pending chunks of ``plan`` on ``executor`` (see :func:`sweep`)."""
    executor = _check_executor(executor, None)
    names, points, kind, columns = plan.names, plan.points, plan.kind, plan.columns
    store, pending, chunk = plan.store, plan.pending, plan.chunk
    stride_map = plan.stride_map
    n_points = points.shape[0]
    table = {
        name: np.full((n_points, *shape), -1 if dtype == "i8" else np.nan, dtype=dtype)
        for name, (dtype, shape) in columns.items()
    }
    task_map = MapSpec.from_map(stride_map) if isinstance(stride_map, StrideMap) else stride_map

    def rows(i: int) -> slice:
        return slice(i * chunk, min((i + 1) * chunk, n_points))

    def args(i: int) -> tuple:
        return (task_map, names, points[rows(i)], kind, plan.z0, plan.n_strides, plan.tol)

    def finish(i: int, values: dict[str, np.ndarray]) -> None:
        if store is not None:
            store.write_chunk(i, values)
        else:
            for name in columns:
                table[name][rows(i)] = values[name]
        bar.update(rows(i).stop - rows(i).start)

    def finish_bundle(bundle: tuple[int, ...], values: list[dict[str, np.ndarray]]) -> None:
        for i, chunk_values in zip(bundle, values, strict=True):
            finish(i, chunk_values)

    own_pool = None
    if pending and (executor is None or executor == "processes"):
        # Threads of this process by default: the compiled strides release the GIL, so the
        # workers run in parallel with no process start-up and the map needs no pickling.
        # "processes": worker processes that end with this one (a kill -9 of the sweep
        # leaves none).
        processes = executor == "processes"
        own_pool = worker_pool(plan.jobs, len(pending), name="sweep", processes=processes)
        executor = own_pool
        if not processes:
            task_map = stride_map
    n_done = n_points - sum(rows(i).stop - rows(i).start for i in pending)
    if kind == "fixed_point":
        try:
            with progress_bar(
                progress, total=n_points, initial=n_done, desc=f"sweep {kind}", unit="pt"
            ) as bar:
                run_lines(plan, executor, own_pool, task_map, table, bar)
        finally:
            if own_pool is not None:
                own_pool.shutdown(wait=True, cancel_futures=True)
        if store is not None:
            return store.table()
        return SweepTable(parameter_names=names, points=points, columns=table)
    try:
        # An interrupted run leaves no progress bar behind (progress_bar).
        with progress_bar(
            progress, total=n_points, initial=n_done, desc=f"sweep {kind}", unit="pt"
        ) as bar:
            if executor == "serial":
                for i in pending:
                    finish(i, sweep_chunk(*args(i), checked=True))
            elif pending and _is_dask(executor):
                # a dask task costs milliseconds of scheduling: several chunks per task
                size = -(-DASK_TASK_POINTS // chunk)
                bundles = [tuple(pending[k : k + size]) for k in range(0, len(pending), size)]
                run_chunks(
                    executor,
                    sweep_chunks,
                    ((bundle, ([args(i) for i in bundle],)) for bundle in bundles),
                    finish_bundle,
                    own=False,
                )
            elif pending:
                # On an interrupt: chunks not started are cancelled, running threads finish
                # their (short) chunk, a process pool's workers are terminated, and every
                # chunk that finished is written before the interrupt propagates.
                run_chunks(
                    executor,
                    functools.partial(sweep_chunk, checked=True),
                    ((i, args(i)) for i in pending),
                    finish,
                    own=own_pool is not None,
                )
    finally:
        if own_pool is not None:
            own_pool.shutdown(wait=True, cancel_futures=True)
    if store is not None:
        return store.table()
    return SweepTable(parameter_names=names, points=points, columns=table)
