"""Mean first-passage time (MFPT) of a walker on stochastic terrain (issue 29).

A metastable walker on rough ground falls eventually; the MFPT is the expected number of steps
it completes before it does (Byl and Tedrake, "Metastable walking machines", IJRR 28(8),
2009).  The terrain rule is :mod:`walker.simulation.terrain`'s: step ``n`` lands on the plane of
slope ``gamma_n`` [rad] through the point ``h_n`` [m] below the stance contact, with ``gamma_n ~
N(slope_mean, slope_std^2)`` and ``h_n ~ N(0, height_std^2)`` drawn for every step, the first
one included.

Two estimates:

* :func:`monte_carlo` -- runs start on the period-one gait of the mean slope (the previous
  step's slope the mean: the start map's scene slope is the mean) and walk in the compiled
  batch (:meth:`walker.simulation.stride.StrideMap.ensemble`) until the first failure: any status
  but ``COMPLETED`` (a fall, a trip, a non-physical impact, no touchdown within ``t_max``, the
  rimless wheel rolling back).  Run ``i`` draws its terrain from ``numpy.random.default_rng``
  seeded by the ``i``-th child of ``numpy.random.SeedSequence(seed).spawn(runs)``, so the
  result does not depend on ``jobs`` (threads) or on how the runs are split.  The compiled
  batch draws these rows itself, the same numbers (walker/_core/terrain_draw.c).  A run still
  walking after ``steps`` strides is walked again over twice as many (its first rows are the
  same draws) up to ``max_steps``; one still walking then is censored.
* :func:`markov_chain` -- the discretised stride-map chain (:mod:`walker.analysis.markov`).

Estimators of :func:`monte_carlo`, with ``N_i`` the steps completed by run ``i``:

* no run censored: ``mfpt = mean(N_i)``, ``mfpt_stderr = std(N_i, ddof=1) / sqrt(runs)``;
* some censored: the geometric maximum-likelihood estimate ``mfpt = sum(N_i) / failed`` with
  ``mfpt_stderr = mfpt / sqrt(failed)`` (the censored runs' steps count as exposure).

``rate`` is the fitted per-step failure probability of a geometric law,
``failed / (sum(N_i) + failed)`` (maximum likelihood, censoring included); for a metastable
gait the steps to failure are geometric after the start transient, with mean ``(1 - rate) /
rate``.

Examples
--------
>>> from walker import StrideMap, load_scene
>>> from walker.analysis.mfpt import gait_on_mean_slope, monte_carlo
>>> scene = load_scene("gaits/rimless_wheel.toml")
>>> P, z0 = gait_on_mean_slope(StrideMap.from_scene(scene), scene.state, 0.08)
>>> r = monte_carlo(P, z0, slope_std=0.05, runs=64, seed=1)
>>> r.runs, r.failed <= 64
(64, True)
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from walker.results import MfptResult
from walker.simulation.terrain import Terrain

__all__ = [
    "MfptResult",
    "draw_terrains",
    "gait_on_mean_slope",
    "monte_carlo",
    "run_seeds",
    "run_terrain",
]

ROWS_PER_BLOCK = 1 << 21
"""Terrain rows (runs x steps) drawn and walked per block: bounds the memory at 32 MiB."""

RUNS_PER_CHECKPOINT = 256
"""Runs per checkpoint chunk of :func:`monte_carlo` with a ``checkpoint`` (the default)."""


def _int(name: str, value, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"`{name}` must be an int, got {type(value).__name__}")
    if value < minimum:
        raise ValueError(f"`{name}` must be >= {minimum}, got {value}")
    return int(value)


def _std(name: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"`{name}` must be a real number, got {type(value).__name__}")
    value = float(value)
    if not (math.isfinite(value) and value >= 0.0):
        raise ValueError(f"`{name}` must be finite and >= 0, got {value!r}")
    return value


def gait_on_mean_slope(smap, guess, slope_mean: float):
    """The stride map on the mean slope and its period-one gait: the Monte-Carlo start.

    Parameters
    ----------
    smap : walker.simulation.stride.StrideMap
    guess : array_like
        a full state (shape ``(n_x,)``) or section point (``(n_z,)``) near the gait.
    slope_mean : float
        the mean slope [rad].

    Returns
    -------
    (walker.simulation.stride.StrideMap, ndarray)
        the map with ``slope = slope_mean`` (the previous step's slope of a start is the
        mean) and the gait's section point; a ValueError when no gait is found there.
    """
    from walker.analysis.fixedpoint import find_fixed_point

    if not math.isfinite(float(slope_mean)):
        raise ValueError(f"`slope_mean` must be finite, got {slope_mean!r}")
    P = smap if float(slope_mean) == smap.params.slope else smap.with_params(slope=slope_mean)
    guess = np.asarray(guess, dtype=np.float64)
    z = P.project(guess) if guess.shape == (P.model.n_x,) else guess
    fp = find_fixed_point(P, z)
    if not fp.success:
        raise ValueError(
            f"`slope_mean` = {slope_mean!r}: no period-one gait near the scene's start "
            f"({fp.status.name}: {fp.message})"
        )
    return P, np.asarray(fp.section, dtype=np.float64)


def run_seeds(seed: int, runs: int) -> list:
    """The per-run seed sequences: the children of ``SeedSequence(seed)``, one per run."""
    return np.random.SeedSequence(_int("seed", seed, 0)).spawn(_int("runs", runs, 0))


def run_terrain(child, n_steps: int, terrain: Terrain) -> np.ndarray:
    """Run ``child``'s first ``n_steps`` terrain rows ``(slope, drop)``: the same rows for
    every ``n_steps`` up to the shorter (one sequential stream of standard normals)."""
    return terrain.steps(n_steps, np.random.default_rng(child))


def draw_terrains(children, n_steps: int, terrain: Terrain) -> np.ndarray:
    """The rows of :func:`run_terrain` for every child, shape ``(len(children), n_steps,
    2)``, bit for bit, with the scaling done once for all runs."""
    draws = np.empty((len(children), n_steps, 2))
    for i, child in enumerate(children):
        draws[i] = np.random.default_rng(child).standard_normal((n_steps, 2))
    rows = np.empty_like(draws)
    rows[..., 0] = terrain.slope_mean
    rows[..., 1] = 0.0
    if terrain.slope_std > 0.0:
        rows[..., 0] += terrain.slope_std * draws[..., 0]
    if terrain.height_std > 0.0:
        rows[..., 1] = terrain.height_std * draws[..., 1]
    return rows


def monte_carlo(
    smap,
    z0,
    *,
    slope_std: float,
    height_std: float = 0.0,
    runs: int,
    seed: int,
    jobs: int = 1,
    steps: int = 256,
    max_steps: int = 1 << 16,
    checkpoint=None,
    chunk_runs: int = RUNS_PER_CHECKPOINT,
    overwrite: bool = False,
    provenance: dict | None = None,
    executor=None,
) -> MfptResult:
    """The Monte-Carlo mean first-passage time (module docstring).

    Parameters
    ----------
    smap : walker.simulation.stride.StrideMap
        the map on the mean slope (its ``slope`` parameter is the mean [rad]), from
        :func:`gait_on_mean_slope`.
    z0 : array_like, shape (n_z,)
        the start section point (the gait of the mean slope).
    slope_std : float
        the slope's standard deviation [rad], >= 0.
    height_std : float
        the drop's standard deviation [m], >= 0.
    runs : int
        runs, >= 1.
    seed : int
        the root seed, >= 0.
    jobs : int
        threads of the compiled batch (the result is the same for any).
    steps, max_steps : int
        the first horizon [steps] and the censoring horizon (doubling in between).
    checkpoint : str or os.PathLike, optional
        an HDF5 checkpoint of finished chunks of ``chunk_runs`` runs
        (:class:`walker.storage.SweepStore`: a table over the parameter ``run`` with the
        columns ``steps`` and ``status``), written as each chunk finishes.  If the file
        exists and holds this same estimate (map, start, terrain, runs, seed, horizons,
        chunk size, ``provenance``), only the chunks not yet done are walked; an interrupt
        keeps the chunks done.  Each run depends only on its own seed, so the result is the
        same for any ``jobs`` and for an interrupted and resumed estimate.  The file is left
        a checkpoint: store the result with :func:`walker.storage.write`.
    chunk_runs : int
        runs per checkpoint chunk (with ``checkpoint``), >= 1.
    overwrite : bool
        replace an existing ``checkpoint`` instead of resuming it.
    provenance : dict, optional
        extra provenance for ``checkpoint``.
    executor : concurrent.futures.Executor or dask.distributed.Client, optional
        run the chunks of ``chunk_runs`` runs as tasks there (a ``Client`` through its
        ``get_executor()``; each task walks on ``jobs`` threads); the result is the same.
        Default: the runs walk in this process.

    Returns
    -------
    MfptResult
    """
    slope_std = _std("slope_std", slope_std)
    height_std = _std("height_std", height_std)
    runs = _int("runs", runs, 1)
    seed = _int("seed", seed, 0)
    jobs = _int("jobs", jobs, 1)
    steps = _int("steps", steps, 1)
    max_steps = _int("max_steps", max_steps, steps)
    z0 = np.asarray(z0, dtype=np.float64)
    if z0.shape != (smap.model.n_z,) or not np.isfinite(z0).all():
        raise ValueError(f"`z0` must be a finite section point of shape ({smap.model.n_z},)")
    slope_mean = float(smap.params.slope)
    terrain = Terrain("random", slope_mean=slope_mean, slope_std=slope_std, height_std=height_std)
    chunk_runs = _int("chunk_runs", chunk_runs, 1)
    done = np.zeros(runs, dtype=np.int64)
    status = np.zeros(runs, dtype=np.int64)

    settings = {
        "slope_mean": slope_mean,
        "slope_std": slope_std,
        "height_std": height_std,
        "runs": runs,
        "seed": seed,
        "steps": steps,
        "max_steps": max_steps,
    }
    store = None
    if checkpoint is not None:
        store = _open_checkpoint(smap, z0, settings, checkpoint, chunk_runs, overwrite, provenance)
    walk = (z0, terrain, jobs, steps, max_steps)
    if executor is not None:
        _run_tasks(executor, smap, walk, seed, runs, min(chunk_runs, runs), store, done, status)
    elif store is None:
        _walk_runs(smap, *walk, seed, np.arange(runs), done, status)
    else:
        for i in store.pending_chunks():
            rows = store.chunk_slice(i)
            _walk_runs(smap, *walk, seed, np.arange(rows.start, rows.stop), done, status)
            store.write_chunk(i, {"steps": done[rows], "status": status[rows]})
        columns = store.table().columns
        done[:], status[:] = columns["steps"], columns["status"]
    return summarise(done, status, max_steps, slope_mean, slope_std, height_std, seed, z0)


def walk_chunk(section_map, walk, seed, runs, first, stop):
    """Runs ``first .. stop - 1`` of an estimate of ``runs`` runs with root ``seed``, walked
    on ``section_map`` (a StrideMap or a :class:`walker.analysis.sweep_chains.MapSpec`) with ``walk
    = (z0, terrain, jobs, steps, max_steps)``: ``(steps, status)``, each of shape ``(stop -
    first,)``.  The task an executor runs (picklable arguments)."""
    from walker.analysis.sweep_chains import _materialize

    smap = _materialize(section_map)
    done = np.zeros(runs, dtype=np.int64)
    status = np.zeros(runs, dtype=np.int64)
    _walk_runs(smap, *walk, seed, np.arange(first, stop), done, status)
    return done[first:stop], status[first:stop]


def _run_tasks(executor, smap, walk, seed, runs, chunk, store, done, status) -> None:
    """The chunks of ``chunk`` runs (those ``store`` has not done) as tasks on ``executor``,
    into ``done`` and ``status`` (and ``store``, each as it finishes)."""
    import concurrent.futures as cf

    from walker._executors import run_chunks
    from walker.analysis.sweep_chains import MapSpec

    if hasattr(executor, "get_executor") and not isinstance(executor, cf.Executor):
        executor = executor.get_executor()  # a dask.distributed Client
    if not isinstance(executor, cf.Executor):
        raise TypeError(
            "`executor` must be a concurrent.futures.Executor or a dask.distributed.Client, "
            f"got {type(executor).__name__}"
        )
    pending = list(range(-(-runs // chunk)))
    if store is not None:
        pending = store.pending_chunks()
        kept = store.table().columns
        done[:], status[:] = kept["steps"], kept["status"]
    spec = MapSpec.from_map(smap)

    def task(i):
        return i, (spec, walk, seed, runs, i * chunk, min((i + 1) * chunk, runs))

    def finish(i, value):
        rows = slice(i * chunk, min((i + 1) * chunk, runs))
        done[rows], status[rows] = value
        if store is not None:
            store.write_chunk(i, {"steps": done[rows], "status": status[rows]})

    run_chunks(executor, walk_chunk, (task(i) for i in pending), finish, own=False)


def _walk_runs(smap, z0, terrain, jobs, steps, max_steps, seed, idx, done, status) -> None:
    """Walk the runs ``idx`` to their first failure or ``max_steps`` (doubling the horizon
    from ``steps``), into ``done`` and ``status``: each run's result depends on its own seed
    (the child of ``SeedSequence(seed)`` at its index) only.  The rows are drawn inside the
    compiled batch where it can draw numpy's numbers (walker/_core/terrain_draw.c), else
    here (:func:`draw_terrains`), the same rows either way."""
    from walker.simulation import _terrain_run

    pending = idx
    n = min(steps, max_steps)
    compiled = _terrain_run.compiled_draws(seed, terrain)
    children = None
    while pending.size:
        if compiled is not None:
            k, st = _terrain_run.ensemble_drawn(smap, z0, compiled, pending, n, threads=jobs)
            done[pending], status[pending] = k, st
        else:
            if children is None:
                children = run_seeds(seed, int(idx.max()) + 1)
            block = max(1, ROWS_PER_BLOCK // n)
            for a in range(0, pending.size, block):
                part = pending[a : a + block]
                rows = draw_terrains([children[i] for i in part], n, terrain)
                k, st = smap.ensemble(z0, rows, threads=jobs)
                done[part], status[part] = k, st
        if n >= max_steps:
            break
        pending = pending[status[pending] == 0]
        n = min(2 * n, max_steps)


def _open_checkpoint(smap, z0, settings, path, chunk_runs, overwrite, provenance):
    """The :class:`walker.storage.SweepStore` of a Monte-Carlo estimate's runs (created, or
    opened to resume: it must hold the same estimate)."""
    import os

    from walker.simulation.stride import solver_settings
    from walker.storage import SweepStore, solver_provenance

    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"`checkpoint` must be a str or os.PathLike, got {type(path).__name__}")
    if provenance is not None and not isinstance(provenance, dict):
        raise TypeError(f"`provenance` must be a dict or None, got {type(provenance).__name__}")
    auto = {"estimate": "mfpt_monte_carlo", "start": z0.tolist(), **settings}
    auto.update(solver_provenance(smap.model, smap.params, **solver_settings(smap)))
    clash = sorted(k for k in (provenance or {}) if k in auto and provenance[k] != auto[k])
    if clash:
        raise ValueError(f"`provenance` must not contradict the estimate's own keys: {clash}")
    runs = settings["runs"]
    return SweepStore.create_or_open(
        path,
        parameter_names=("run",),
        points=np.arange(runs, dtype=np.float64)[:, None],
        columns={"steps": ("i8", ()), "status": ("i8", ())},
        chunk_size=min(chunk_runs, runs),
        provenance={**auto, **(provenance or {})},
        overwrite=bool(overwrite),
    )


def summarise(done, status, max_steps, slope_mean, slope_std, height_std, seed, z0):
    """An :class:`MfptResult` from the runs' completed steps and statuses."""
    runs = int(done.size)
    failed = int(np.count_nonzero(status))
    total = float(done.sum())
    if failed == runs:
        mfpt = float(done.mean())
        stderr = float(done.std(ddof=1) / math.sqrt(runs)) if runs > 1 else math.inf
    elif failed:
        mfpt = total / failed
        stderr = mfpt / math.sqrt(failed)
    else:
        mfpt, stderr = math.nan, math.nan
    rate = failed / (total + failed) if (total + failed) > 0 else math.nan
    return MfptResult(
        mfpt=mfpt,
        mfpt_stderr=stderr,
        runs=runs,
        failed=failed,
        steps=done,
        status=status,
        rate=rate,
        max_steps=int(max_steps),
        slope_mean=float(slope_mean),
        slope_std=float(slope_std),
        height_std=float(height_std),
        seed=int(seed),
        start=np.asarray(z0, dtype=np.float64).copy(),
    )
