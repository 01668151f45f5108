"""Warm starts that follow the grid: where each point of a fixed-point sweep starts its gait
search, and the flag of a point that lands on another gait than its neighbours.

Every point's starting guess is a function of the grid alone, never of how the work is cut
(chunk size, ``jobs``, the executor or scheduler, a resume), so the table is too:

1. **The root** is the grid point nearest the base map's own parameters (per axis the index
   of the value nearest the base value), where the scene's state ``z0`` is a gait or close
   to one.  It starts from ``z0``.
2. **Lines, level by level** (:func:`grid_lines`), the axes taken from the shortest to the
   longest (:func:`level_axes`).  Level 0 is the line through the root along the first of
   them; level ``j`` is every line along the ``j``-th through a point done at level
   ``j - 1`` (the axes of the levels before free, the others at the root's index).  A
   line starts from its centre (the point it shares with the level before) and walks
   outwards in both directions, one grid step at a time; the lines of a level are
   independent of each other and run in parallel, a task being a run of consecutive lines
   (the unit sent to an executor, so dask tasks are chunks, never points).
3. **The guess** of a point is the *seed* its predecessor on the line passes on
   (:func:`passes_on`): the predecessor's gait when its search converged onto a gait within
   :data:`JUMP_SECTION` of its own seed, otherwise the predecessor's own seed.  When the
   points just before it on the line (up to :data:`PREDICT_POINTS`, the centre included)
   all passed their gaits on, the search starts instead from the polynomial through those
   gaits at this point's parameter value (:func:`predict`: linear from two, quadratic from
   three), which is one to two Newton steps closer: on the kneed walker's slope lines a
   guess within about 1e-6 of the gait instead of 4e-3, so 3 stride-map evaluations
   instead of 5.  A point whose start fails is tried again from the seed, then from
   ``z0``.
4. **Jumps** (:func:`jump_flags`): after the last level, a converged point is flagged
   (column ``jump`` = 1) when it differs from a converged grid neighbour (one step along
   any axis) by more than :data:`JUMP_STEP_TIME` in relative step time or
   :data:`JUMP_SECTION` in the scaled section (angles in rad, rates in units of
   ``sqrt(g / l)`` of the base parameters, :class:`walker.simulation.region.WalkingRegion`'s scale):
   the two points lie on different gaits, or the grid is too coarse there to tell.  Both
   points of such a pair are flagged, since either may be the odd one.  ``jump`` is 0 for
   the other points (failed ones included) and -1 while the sweep is not finished (a
   checkpoint part-way).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from walker._executors import run_chunks
from walker.analysis.fixedpoint import find_fixed_point
from walker.analysis.sweep_grid import fill_gsn, fill_measures, table_columns
from walker.simulation.stride import StrideMap

__all__ = [
    "JUMP_SECTION",
    "MapSpec",
    "JUMP_STEP_TIME",
    "grid_lines",
    "jump_flags",
    "level_axes",
    "passes_on",
    "predict",
    "root_index",
    "run_lines",
    "sweep_lines",
    "walk_line",
]

JUMP_STEP_TIME = 0.25
"""Relative step-time difference between two converged grid neighbours beyond which both
are flagged as a jump (0.25: a quarter of the shorter step time)."""

JUMP_SECTION = 0.25
"""Scaled section difference (max-norm; angles in rad, rates in units of ``sqrt(g / l)``)
between two converged grid neighbours beyond which both are flagged, and beyond which a
converged point does not pass its gait on as the next point's guess."""


def root_index(axes: Sequence[np.ndarray], base: Sequence[float]) -> tuple[int, ...]:
    """Per axis, the index of the value nearest ``base`` (the first of equally near ones)."""
    return tuple(
        int(np.argmin(np.abs(np.asarray(values, dtype=float) - float(b))))
        for values, b in zip(axes, base, strict=True)
    )


def level_axes(shape: Sequence[int]) -> tuple[int, ...]:
    """The grid axis each level of lines runs along (:func:`grid_lines`): the shortest axis
    first, the longest last (ties in axis order), so that most points lie on long lines,
    where the guesses are extrapolated (:func:`predict`)."""
    return tuple(sorted(range(len(shape)), key=lambda axis: (int(shape[axis]), axis)))


def grid_lines(
    shape: Sequence[int], root: Sequence[int], axes: Sequence[int] | None = None
) -> list[list[tuple]]:
    """The lines of the warm-start order, level by level.

    Parameters
    ----------
    shape : sequence of int
        the grid's shape.
    root : sequence of int
        the root's index per axis.
    axes : sequence of int, optional
        the axis each level runs along, a permutation of the axes (default their order):
        level ``j`` is every line along ``axes[j]`` through a point done at level ``j - 1``
        (the axes ``axes[:j]`` free, the others at the root's index).

    Returns
    -------
    list of levels; each a list of lines ``(centre, first, down, up)``: flat indices (C order,
    last axis fastest) of the line's centre, whether the line computes the centre itself
    (level 0 only: the root), and the points walked from the centre towards index 0 and
    towards the end of the axis, nearest first.
    """
    shape = tuple(int(n) for n in shape)
    axes = tuple(range(len(shape))) if axes is None else tuple(int(a) for a in axes)
    if sorted(axes) != list(range(len(shape))):
        raise ValueError(f"`axes` must be a permutation of 0..{len(shape) - 1}, got {axes}")
    levels = []
    for j, axis in enumerate(axes):
        lines = []
        free = axes[:j]
        for head in np.ndindex(*[shape[a] for a in free]) if free else [()]:
            index = list(root)
            for a, i in zip(free, head, strict=True):
                index[a] = i

            def flat(i, index=index, axis=axis):
                index[axis] = i
                return int(np.ravel_multi_index(tuple(index), shape))

            centre = flat(root[axis])
            down = tuple(flat(i) for i in range(root[axis] - 1, -1, -1))
            up = tuple(flat(i) for i in range(root[axis] + 1, shape[axis]))
            lines.append((centre, j == 0, down, up))
        levels.append(lines)
    return levels


def passes_on(status: int, section: np.ndarray, guess: np.ndarray, scale: np.ndarray):
    """The seed a point passes on to the next point of its line: its gait when it converged
    within :data:`JUMP_SECTION` of its guess (scaled), else its guess."""
    return _passes_on(status, section, guess, scale)[0]


def _passes_on(status, section, guess, scale) -> tuple[np.ndarray, bool]:
    """:func:`passes_on`, and whether the seed is the point's own gait."""
    if status == 0 and np.all(np.isfinite(section)):
        if float(np.max(np.abs(section - guess) / scale)) <= JUMP_SECTION:
            return section, True
    return guess, False


def predict(
    gaits: Sequence[tuple[float, np.ndarray]], at: float, seed: np.ndarray, scale: np.ndarray
) -> np.ndarray | None:
    """The guess of the next point of a line from the gaits just before it on the line.

    Parameters
    ----------
    gaits : sequence of (float, ndarray)
        the parameter value (along the line's axis) and the gait of each of the last
        :data:`PREDICT_POINTS` points of the line, in order, all converged, the last one
        the point just before this one; fewer when the line has fewer or when one of them
        did not converge.
    at : float
        this point's parameter value.
    seed : ndarray, shape (n_z,)
        the seed the point before passes on (its gait).
    scale : ndarray, shape (n_z,)
        the section's scale.

    Returns
    -------
    ndarray or None
        the polynomial through the gaits (Lagrange, degree ``len(gaits) - 1``: linear from
        two, quadratic from three) at ``at``; None with one gait, equal parameter values,
        a non-finite result, or one farther than :data:`JUMP_SECTION` (scaled) from
        ``seed`` (the line turns too fast there for an extrapolation to help).
    """
    if len(gaits) < 2:
        return None
    ts = [t for t, _ in gaits]
    if len(set(ts)) < len(ts):
        return None
    guess = np.zeros_like(seed)
    for j, (tj, gj) in enumerate(gaits):
        weight = 1.0
        for m, tm in enumerate(ts):
            if m != j:
                weight *= (at - tm) / (tj - tm)
        guess = guess + weight * gj
    if not np.all(np.isfinite(guess)):
        return None
    if float(np.max(np.abs(guess - seed) / scale)) > JUMP_SECTION:
        return None
    return guess


PREDICT_POINTS = 3
"""Converged points of a line that :func:`predict` extrapolates from (3: quadratic)."""


def walk_line(
    line: tuple,
    seed: np.ndarray,
    solve: Callable[[int, np.ndarray, np.ndarray | None], tuple[int, np.ndarray]],
    scale: np.ndarray,
    position: Callable[[int], float] | None = None,
    seed_is_gait: bool = False,
) -> dict[int, np.ndarray]:
    """Walk one line from its centre outwards; ``solve(index, seed, predicted) -> (status,
    section)`` computes (or looks up) a point, from the guess ``predicted`` when it is not
    None (:func:`predict`) and else, or when that fails, from ``seed``.  ``seed`` is the
    centre's guess on a first line, else the seed the centre passed on (``seed_is_gait``:
    the centre's own gait).  ``position(index)``: a point's parameter value along the line
    (None: no prediction).  Returns the seed each point walked passes on, by index (the
    centre's too on a first line)."""
    centre, first, down, up = line
    seeds = {}
    start = seed
    behind: list[tuple[float, np.ndarray]] = []
    if first:
        status, section = solve(centre, seed, None)
        start, own = _passes_on(status, section, seed, scale)
        seeds[centre] = start
        seed_is_gait = own
    if seed_is_gait and position is not None:
        behind = [(position(centre), start)]
    for half in (down, up):
        guess = start
        gaits = list(behind)
        for index in half:
            at = None if position is None else position(index)
            predicted = None if at is None else predict(gaits, at, guess, scale)
            status, section = solve(index, guess, predicted)
            guess, own = _passes_on(status, section, guess, scale)
            seeds[index] = guess
            gaits = [*gaits[1 - PREDICT_POINTS :], (at, guess)] if own else []
    return seeds


def jump_flags(
    status: np.ndarray,
    section: np.ndarray,
    step_time: np.ndarray,
    shape: Sequence[int],
    scale: np.ndarray,
) -> np.ndarray:
    """The ``jump`` column (int64, 0 or 1) of a finished fixed-point sweep: 1 for a
    converged point that differs from a converged neighbour along any grid axis by more
    than :data:`JUMP_STEP_TIME` (relative step time) or :data:`JUMP_SECTION` (scaled
    section)."""
    shape = tuple(int(n) for n in shape)
    n_z = section.shape[1]
    ok = (np.asarray(status) == 0).reshape(shape)
    z = np.asarray(section, dtype=float).reshape((*shape, n_z)) / np.asarray(scale, dtype=float)
    t = np.asarray(step_time, dtype=float).reshape(shape)
    flag = np.zeros(shape, dtype=bool)
    for axis in range(len(shape)):
        if shape[axis] < 2:
            continue
        lo = [slice(None)] * len(shape)
        hi = [slice(None)] * len(shape)
        lo[axis], hi[axis] = slice(None, -1), slice(1, None)
        lo, hi = tuple(lo), tuple(hi)
        both = ok[lo] & ok[hi]
        with np.errstate(invalid="ignore"):
            dz = np.max(np.abs(z[lo] - z[hi]), axis=-1)
            dt = np.abs(t[lo] - t[hi]) / np.minimum(np.abs(t[lo]), np.abs(t[hi]))
        jump = both & ((dz > JUMP_SECTION) | ~(dt <= JUMP_STEP_TIME))
        flag[lo] |= jump
        flag[hi] |= jump
    return flag.reshape(-1).astype(np.int64)


# ---------------------------------------------------------------------------------------------
# The unit of work
# ---------------------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class MapSpec:
    """A picklable recipe for a :class:`~walker.simulation.stride.StrideMap`.

    A ``StrideMap`` holds its model's compiled kernels and module, which do not pickle; this
    holds the model name and the map's other fields (parameters dataclass, method,
    tolerances, ...), and :meth:`build` makes the map again in a worker.  Workers keep the
    last map they built, so a worker rebuilds it (and prepares its compiled run) once, not
    once per chunk.

    Attributes
    ----------
    model : str
        model name.
    fields : tuple of (str, object)
        the other ``StrideMap`` fields, by name.
    swing_scuff : str
        the model's swing-foot convention (:func:`walker.models.get_model`), so a worker's
        map runs under the scene's conventions, as the map it was made from.
    """

    model: str
    fields: tuple[tuple[str, Any], ...]
    swing_scuff: str = "trip"

    @classmethod
    def from_map(cls, stride_map: StrideMap) -> MapSpec:
        fields = tuple(
            (f.name, getattr(stride_map, f.name))
            for f in dataclasses.fields(stride_map)
            if f.name != "model"
        )
        scuff = str(getattr(stride_map.model, "swing_scuff", "trip"))
        return cls(stride_map.model.name, fields, scuff)

    def build(self) -> StrideMap:
        from walker.models import get_model

        return StrideMap(get_model(self.model, self.swing_scuff), **dict(self.fields))


_WORKER_MAP: dict[MapSpec, Any] = {}


def _materialize(section_map: Any) -> Any:
    """The stride map a chunk runs on (built once per worker process from a MapSpec)."""
    if not isinstance(section_map, MapSpec):
        return section_map
    cached = _WORKER_MAP.get(section_map)
    if cached is None:
        _WORKER_MAP.clear()
        cached = section_map.build()
        _WORKER_MAP[section_map] = cached
    return cached


def _retargeter(base):
    """``params -> map``: the base map re-targeted to a grid point's parameters
    (``StrideMap._retargeted``: its compiled run is shared, not rebuilt), or a plain copy
    for a map without it."""
    if hasattr(base, "_retargeted") and hasattr(base, "_prepared"):
        base._prepared()
        return base._retargeted
    return base._with_params_object


def _fixed_point(point_map, guess, z0, n_strides, tol, predicted=None):
    """The gait search of one point: from ``predicted`` when given (:func:`predict`), from
    ``guess`` when there is none or it fails, and again from ``z0`` if that fails; each
    start at most once."""
    from walker.analysis.fixedpoint import POINT_MAX_EVALS

    tried: list[np.ndarray] = []
    for start in (predicted, guess, z0):
        if start is None or any(start is t or np.array_equal(start, t) for t in tried):
            continue
        fp = find_fixed_point(
            point_map, start, period=n_strides, tol=tol, max_evals=POINT_MAX_EVALS
        )
        if fp.success:
            return fp
        tried.append(start)
    return fp


def sweep_lines(
    section_map: MapSpec | Any,
    names: tuple[str, ...],
    points: np.ndarray,
    lines: list[tuple],
    seeds: list[np.ndarray],
    known: dict[str, np.ndarray] | None,
    z0: np.ndarray,
    n_strides: int,
    tol: float,
    scale: np.ndarray,
    gsn: bool = False,
    axis: int | None = None,
    centres: np.ndarray | None = None,
    seed_gaits: Sequence[bool] | None = None,
) -> dict[str, np.ndarray]:
    """Evaluate a run of lines of a fixed-point sweep (the task :func:`sweep` sends to an
    executor for ``kind="fixed_point"``; the order and the warm starts are those of
    :mod:`walker.analysis.sweep_chains`).

    Parameters
    ----------
    section_map : MapSpec or StrideMap
        the base map.
    names : tuple of str, length k
    points : ndarray, shape (m, k)
        the task's points, indexed ``0 .. m - 1`` by ``lines``.
    lines : list of (centre, first, down, up)
        :func:`walker.analysis.sweep_chains.grid_lines` lines in the task's indices (``centre``
        unused unless ``first``).
    seeds : list of ndarray, shape (n_z,)
        per line, the centre's guess (``first``) or the seed its centre passed on.
    known : dict, optional
        the columns of the points already done (a resumed sweep), with ``"known"`` (bool,
        shape (m,)) saying which: those are looked up, not computed.
    z0 : ndarray, shape (n_z,)
        the guess a point whose warm start fails starts again from.
    n_strides : int
        the gait's period.
    tol : float
        Newton tolerance.
    scale : ndarray, shape (n_z,)
        the section's scale (:func:`walker.analysis.sweep_chains.passes_on`).
    gsn : bool
        also the ``gsn`` column (:func:`walker.analysis.sweep_grid.fill_gsn`).
    axis : int, optional
        the grid axis the lines run along (the parameter ``names[axis]``); with
        ``centres``, a point's guess is extrapolated from the gaits before it on its line
        (:func:`walker.analysis.sweep_chains.predict`).  None: each point starts from the seed
        before it.
    centres : ndarray, shape (n_lines, k), optional
        per line, its centre's parameter values.
    seed_gaits : sequence of bool, optional
        per line, whether its seed is its centre's own gait (first lines: unused).

    Returns
    -------
    dict
        the table's columns for the ``m`` points (``jump`` -1: flagged after the last
        level), and ``"seed"`` (m, n_z), the seed each point passes on.
    """
    base = _materialize(section_map)
    retarget = _retargeter(base)
    n_z = int(base.n_z)
    m = points.shape[0]
    columns = table_columns("fixed_point", n_z, gsn)
    out = {
        name: np.full((m, *shape), -1 if dtype == "i8" else np.nan, dtype=dtype)
        for name, (dtype, shape) in columns.items()
    }
    out["seed"] = np.full((m, n_z), np.nan)
    is_known = np.zeros(m, dtype=bool) if known is None else known["known"]

    def solve(i: int, guess: np.ndarray, predicted: np.ndarray | None) -> tuple[int, np.ndarray]:
        if is_known[i]:
            for name in columns:
                out[name][i] = known[name][i]
            return int(out["status"][i]), out["section"][i]
        values = dict(zip(names, points[i].tolist(), strict=True))
        point_map = retarget(base.params._replace_validated(**values))
        fp = _fixed_point(point_map, guess, z0, n_strides, tol, predicted)
        out["status"][i] = int(fp.status)
        out["residual"][i] = fp.residual
        out["n_iter"][i] = fp.n_iter
        out["stable"][i] = int(bool(fp.stable) and fp.success)
        if fp.success:
            out["section"][i] = fp.section
            out["step_time"][i] = fp.step_time
            out["multipliers_re"][i] = fp.multipliers.real
            out["multipliers_im"][i] = fp.multipliers.imag
            fill_measures(point_map, fp, out, i)
            if gsn:
                fill_gsn(point_map, fp, out, i)
        return int(out["status"][i]), out["section"][i]

    along = points[:, axis].tolist() if axis is not None and centres is not None else None
    for k, (line, seed) in enumerate(zip(lines, seeds, strict=True)):
        position = None
        if along is not None:
            centre_value = float(centres[k][axis])

            def position(i: int, centre_value=centre_value) -> float:
                return along[i] if i >= 0 else centre_value

        is_gait = bool(seed_gaits[k]) if seed_gaits is not None else False
        walked = walk_line(line, np.asarray(seed, dtype=float), solve, scale, position, is_gait)
        for i, passed in walked.items():
            out["seed"][i] = passed
    return out


# ---------------------------------------------------------------------------------------------
# The driver of a fixed-point sweep
# ---------------------------------------------------------------------------------------------


def run_lines(plan, executor, own_pool, task_map, table, bar) -> None:
    """Run a fixed-point sweep (a ``walker.analysis.sweep._Plan``) level by level of its lines, each
    level's lines in tasks of about ``plan.chunk`` points, filling ``table``; with a
    checkpoint, each chunk is written once all its points are done, and the ``jump`` column
    after the last level."""
    store, chunk, columns = plan.store, plan.chunk, plan.columns
    n_points, n_z = plan.points.shape[0], int(plan.stride_map.n_z)
    done = np.zeros(n_points, dtype=bool)
    passed = np.full((n_points, n_z), np.nan)
    if store is not None:
        stored = store.table(damaged_ok=True).columns  # damaged chunks are pending
        for i in sorted(set(range(store.n_chunks)) - set(plan.pending)):
            done[store.chunk_slice(i)] = True
        for name in columns:
            table[name][done] = stored[name][done]
    n_chunks = -(-n_points // chunk)
    left = np.bincount(np.flatnonzero(~done) // chunk, minlength=n_chunks)

    def write(i: int) -> None:
        sl = slice(i * chunk, min((i + 1) * chunk, n_points))
        store.write_chunk(i, {name: table[name][sl] for name in columns})

    def finish(rows: np.ndarray, values: dict[str, np.ndarray]) -> None:
        for name in columns:
            table[name][rows] = values[name]
        passed[rows] = values["seed"]
        new = rows[~done[rows]]
        done[new] = True
        bar.update(len(new))
        if store is not None:
            counts = np.bincount(new // chunk, minlength=n_chunks)
            left[:] -= counts
            for i in np.flatnonzero((left == 0) & (counts > 0)):
                write(int(i))

    axes = level_axes(plan.shape)
    for axis, level in zip(axes, grid_lines(plan.shape, plan.root, axes), strict=True):
        tasks, group, size = [], [], 0
        for line in level:
            group.append(line)
            size += len(line[2]) + len(line[3]) + int(line[1])
            if size >= chunk:
                tasks.append(group)
                group, size = [], 0
        if group:
            tasks.append(group)
        work = [_line_task(plan, task_map, group, passed, done, table, axis) for group in tasks]
        inline = [(rows, args) for rows, args in work if done[rows].all()]
        for rows, args in inline:  # nothing to compute: the seeds of points looked up
            finish(rows, sweep_lines(*args))
        todo = [(rows, args) for rows, args in work if not done[rows].all()]
        if executor == "serial":
            for rows, args in todo:
                finish(rows, sweep_lines(*args))
        elif todo:
            run_chunks(
                executor,
                sweep_lines,
                ((k, args) for k, (_, args) in enumerate(todo)),
                lambda k, values, todo=todo: finish(todo[k][0], values),
                own=own_pool is not None,
            )
    table["jump"][:] = jump_flags(
        table["status"], table["section"], table["step_time"], plan.shape, plan.scale
    )
    if store is not None and np.any(store.table().columns["jump"] != table["jump"]):
        fsync, store.fsync = store.fsync, False
        try:
            for i in range(n_chunks):
                if i == n_chunks - 1:
                    store.fsync = fsync
                write(i)
        finally:
            store.fsync = fsync


def _line_task(plan, task_map, group, passed, done, table, axis=None) -> tuple:
    """``(rows, args)``: the grid rows of a task of lines (along grid axis ``axis``) and the
    arguments of :func:`sweep_lines` for it, in the task's own indices."""
    rows, local_lines, seeds, centres, seed_gaits = [], [], [], [], []
    for centre, first, down, up in group:
        start = len(rows)
        if first:
            rows.append(centre)
        rows.extend(down)
        rows.extend(up)
        k = start + int(first)
        local_lines.append(
            (
                start if first else -1,
                first,
                tuple(range(k, k + len(down))),
                tuple(range(k + len(down), k + len(down) + len(up))),
            )
        )
        seeds.append(plan.z0 if first else passed[centre])
        centres.append(plan.points[centre])
        # the seed the centre passed on is its own gait (walker.analysis.sweep_chains.passes_on)
        seed_gaits.append(
            not first
            and int(table["status"][centre]) == 0
            and np.array_equal(passed[centre], table["section"][centre])
        )
    rows = np.asarray(rows, dtype=np.intp)
    known = None
    if done[rows].any():
        known = {name: table[name][rows] for name in plan.columns}
        known["known"] = done[rows].copy()
    args = (
        task_map,
        plan.names,
        plan.points[rows],
        local_lines,
        seeds,
        known,
        plan.z0,
        plan.n_strides,
        plan.tol,
        plan.scale,
        plan.gsn,
        axis,
        np.asarray(centres, dtype=float),
        seed_gaits,
    )
    return rows, args
