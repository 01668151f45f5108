"""An orbit diagram run in blocks: in parallel, with progress, checkpointed and resumable.

:func:`walker.analysis.orbit.orbit_diagram` walks the parameter values in order, each starting from
where the previous one ended (it follows one attractor).  :func:`orbit_diagram_blocks` gives
the same diagram, cut two ways:

* **chains** (``chains``, part of the result): the values are split into ``chains``
  stretches of consecutive values, each started from ``z0`` and warm-started along itself.
  One chain (the default) is :func:`~walker.analysis.orbit.orbit_diagram` bit for bit; more chains
  can run in parallel (a chain's start does not depend on another chain), at the price of a
  restart from ``z0`` at each chain's first value.
* **blocks** (``block`` values, the unit of work and of checkpointing, never of the result):
  a chain runs block after block, each block starting from the section point the block
  before it passed on (its ``carry``, stored in the checkpoint), so a resumed run continues
  every chain exactly where it stopped.

The result depends on the values, ``z0``, the strides and ``chains`` only: never on the
block size, ``jobs``, the executor or scheduler, or a resume.  A checkpoint is a
:class:`walker.storage.SweepStore` over the parameter values with the columns ``values``
(the recorded coordinates) and ``carry``.
"""

from __future__ import annotations

import concurrent.futures as cf
import os
from typing import Any

import numpy as np

from walker._executors import progress_bar, stop_workers, worker_pool
from walker.analysis.orbit import settle
from walker.analysis.sweep_chains import MapSpec, _materialize
from walker.results import OrbitDiagram

__all__ = [
    "chain_starts",
    "checkpoint_path",
    "default_block",
    "orbit_block",
    "orbit_diagram_blocks",
]


def default_block(n_values: int) -> int:
    """The block size used when none is given (a function of the number of values only, so
    a resumed run finds the same blocks): about 32 blocks, at most 16 values each."""
    return max(1, min(16, -(-n_values // 32)))


def orbit_block(section_map, mus, z_start, z0, n_transient, n_keep, coordinate, restart=None):
    """One block of values (the task sent to an executor): ``values`` (m, n_keep) and
    ``carry`` (m, n_z), the section point each value passes on to the next.  A value where
    ``restart`` (bool, (m,)) is set starts a chain: it starts from ``z0``."""
    base = _materialize(section_map)
    mus = np.asarray(mus, dtype=float)
    values = np.full((mus.size, n_keep), np.nan)
    carry = np.empty((mus.size, np.asarray(z0).size))
    z_start = np.asarray(z_start, dtype=float)
    for i, mu in enumerate(mus.tolist()):
        if restart is not None and restart[i]:
            z_start = z0
        z, fell = settle(base, z_start, mu, n_transient, n_keep, coordinate, values[i])
        z_start = z0 if fell else z
        carry[i] = z_start
    return {"values": values, "carry": carry}


def chain_starts(n_values: int, chains: int) -> np.ndarray:
    """Where each chain starts (bool, (n_values,)): ``chains`` stretches as even as can be
    (:func:`numpy.array_split`), a function of the number of values and chains only."""
    starts = np.zeros(n_values, dtype=bool)
    for part in np.array_split(np.arange(n_values), min(chains, n_values)):
        starts[part[0]] = True
    return starts


def orbit_diagram_blocks(
    section_map,
    z0,
    parameters,
    *,
    n_transient: int = 200,
    n_keep: int = 32,
    coordinate: int = 0,
    chains: int = 1,
    block: int | None = None,
    executor: Any = None,
    jobs: int | None = None,
    store: Any = None,
    progress: bool = False,
) -> OrbitDiagram:
    """:func:`walker.analysis.orbit.orbit_diagram` (with its warm start) in blocks, on an executor.

    Parameters
    ----------
    section_map, z0, parameters, n_transient, n_keep, coordinate
        as :func:`walker.analysis.orbit.orbit_diagram` (checked by it; call that first for the
        checks, or pass checked values).
    chains : int
        stretches of consecutive values each started from ``z0`` (>= 1); 1: the diagram of
        :func:`~walker.analysis.orbit.orbit_diagram` bit for bit.
    block : int, optional
        values per task and per checkpoint chunk (default :func:`default_block`).
    executor : None, "serial", "processes", an Executor or a dask Client
        as :func:`walker.analysis.sweep.sweep`'s (None: ``jobs`` threads).
    jobs : int, optional
        workers of the default pool.
    store : SweepStore, optional
        the checkpoint (its chunk size must be ``block``); blocks done there are not run.
    progress : bool
        tqdm bar over values on stderr (when it is a terminal).

    Returns
    -------
    OrbitDiagram
    """
    params = np.asarray(parameters, dtype=float)
    z0 = np.asarray(z0, dtype=float)
    n = params.size
    block = default_block(n) if block is None else int(block)
    if isinstance(chains, bool) or not isinstance(chains, int | np.integer) or chains < 1:
        raise ValueError(f"`chains` must be an integer >= 1, got {chains!r}")
    values = np.full((n, n_keep), np.nan)
    carry = np.full((n, z0.size), np.nan)
    done = np.zeros(-(-n // block), dtype=bool)
    if store is not None:
        done[:] = True
        done[store.pending_chunks()] = False
        table = store.table().columns
        rows = np.repeat(done, block)[:n]
        values[rows], carry[rows] = table["values"][rows], table["carry"][rows]

    def rows_of(b: int) -> slice:
        return slice(b * block, min((b + 1) * block, n))

    starts = chain_starts(n, chains)

    def task(b):
        spec = MapSpec.from_map(section_map) if processes else section_map
        sl = rows_of(b)
        start = z0 if starts[sl.start] else carry[sl.start - 1]
        return (spec, params[sl], start, z0, n_transient, n_keep, coordinate, starts[sl])

    def finish(b: int, out: dict) -> None:
        sl = rows_of(b)
        values[sl], carry[sl] = out["values"], out["carry"]
        done[b] = True
        if store is not None:
            store.write_chunk(b, {"values": values[sl], "carry": carry[sl]})
        bar.update(sl.stop - sl.start)

    # block b waits for block b - 1 unless a chain starts with it
    after = [b - 1 if b > 0 and not starts[b * block] else None for b in range(done.size)]
    todo = [b for b in range(done.size) if not done[b]]
    own = None
    processes = executor == "processes" or isinstance(executor, cf.ProcessPoolExecutor)
    if executor is None or executor == "processes":
        n_tasks = max(1, sum(1 for b in todo if after[b] is None or done[after[b]]))
        own = worker_pool(jobs, n_tasks, name="orbit", processes=processes)
        executor = own
    elif hasattr(executor, "get_executor") and not isinstance(executor, cf.Executor):
        executor, processes = executor.get_executor(), True  # a dask Client
    n_done = int(sum(rows_of(b).stop - rows_of(b).start for b in np.flatnonzero(done)))
    try:
        with progress_bar(
            progress, total=n, initial=n_done, desc="orbit diagram", unit="value"
        ) as bar:
            if executor == "serial":
                for b in todo:
                    finish(b, orbit_block(*task(b)))
            else:
                _run_blocks(executor, todo, after, task, finish, done, own is not None)
    finally:
        if own is not None:
            own.shutdown(wait=True, cancel_futures=True)
    return OrbitDiagram(
        parameter_name=section_map.parameter_name,
        parameter=params,
        values=values,
        coordinate=int(coordinate),
    )


def _run_blocks(executor, todo, after, task, finish, done, own) -> None:
    """Submit each pending block once the block it waits for (``after``) is done; collect
    in this thread.  On an interrupt, stop the work (:func:`walker._executors.stop_workers`)
    and keep the blocks that finished."""
    running: dict[cf.Future, int] = {}
    waiting = list(todo)

    def submit_ready() -> None:
        for b in [b for b in waiting if after[b] is None or done[after[b]]]:
            waiting.remove(b)
            running[executor.submit(orbit_block, *task(b))] = b

    try:
        submit_ready()
        while running:
            finished, _ = cf.wait(running, return_when=cf.FIRST_COMPLETED)
            for fut in finished:
                finish(running.pop(fut), fut.result())
            submit_ready()
    except BaseException:
        stop_workers(executor, list(running), own)
        for fut, b in running.items():
            if fut.done() and not fut.cancelled() and fut.exception() is None:
                try:
                    finish(b, fut.result())
                except Exception:  # keeping more is best effort
                    pass
        raise


def checkpoint_path(out: os.PathLike | str) -> str:
    """The checkpoint of ``walker orbit-diagram --out OUT``: ``.OUT.checkpoint.h5`` beside
    it, removed once ``OUT`` is written."""
    head, tail = os.path.split(os.fspath(out))
    return os.path.join(head, f".{tail}.checkpoint.h5")
