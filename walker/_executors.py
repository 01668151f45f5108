"""Running independent chunks on a :class:`concurrent.futures.Executor`, and stopping them.

Used by :func:`walker.sweep.sweep` and :func:`walker.basin.basin_map`.  Nothing here touches
signals: an interrupt reaches :func:`run_chunks` as an exception (``KeyboardInterrupt``, or
whatever a caller's signal handler raises) in the thread that collects the results, and
:func:`run_chunks` then stops the work before re-raising it:

* every chunk not started is cancelled (a ``dask.distributed`` future's task with it);
* threads cannot be stopped: the running chunks are asked to stop through ``stop`` (when the
  chunk function looks at it) or run to their end, which is waited for;
* a ``ProcessPoolExecutor`` is shut down (``cancel_futures=True``) and its worker processes
  terminated, so no worker outlives an interrupted run computing a chunk nobody collects;
* the chunks that finished meanwhile are handed to ``on_result`` (so a checkpoint keeps them).
"""

from __future__ import annotations

import concurrent.futures as cf
import threading
from collections.abc import Callable, Iterable
from typing import Any

__all__ = ["Abandoned", "run_chunks", "stop_workers"]


class Abandoned(Exception):
    """Raised by a chunk running in a thread when it was asked to stop."""


def stop_workers(executor: Any, futures: Iterable[cf.Future], own: bool) -> None:
    """Cancel ``futures`` not started and stop ``executor``'s work on the others.

    Parameters
    ----------
    executor : Executor
        the executor the futures came from.
    futures : iterable of Future
    own : bool
        the executor was created by the caller of this function (a thread pool is then shut
        down; an executor passed in by a user is left running, except a process pool, whose
        workers are terminated in any case).
    """
    futures = list(futures)
    for fut in futures:
        fut.cancel()
    if isinstance(executor, cf.ProcessPoolExecutor):
        processes = list((getattr(executor, "_processes", None) or {}).values())
        executor.shutdown(wait=False, cancel_futures=True)
        for proc in processes:
            if proc.is_alive():
                proc.terminate()
        for proc in processes:
            proc.join(timeout=10)
            if proc.is_alive():
                proc.kill()
                proc.join(timeout=10)
        return
    if own:
        executor.shutdown(wait=True, cancel_futures=True)
    else:
        # Threads of a user's pool cannot be stopped: wait for the chunks they are running.
        # (Cancelled dask futures are done already.)
        cf.wait(futures)


def run_chunks(
    executor: cf.Executor,
    fn: Callable[..., Any],
    tasks: Iterable[tuple[Any, tuple]],
    on_result: Callable[[Any, Any], None],
    *,
    own: bool,
    stop: threading.Event | None = None,
) -> None:
    """Submit ``fn(*args)`` for each ``(key, args)`` of ``tasks`` and call
    ``on_result(key, value)`` in this thread as each finishes.

    On any exception (a failing chunk, ``on_result`` failing, or an interrupt raised in this
    thread) the chunks not started are cancelled.  On an interrupt (an exception that is not
    an ``Exception``: ``KeyboardInterrupt``, ``SystemExit``) ``stop`` is set, the workers are
    stopped (:func:`stop_workers`) and the chunks that finished meanwhile are passed to
    ``on_result`` before the interrupt is re-raised.
    """
    futures: dict[cf.Future, Any] = {}
    handled: set[cf.Future] = set()
    try:
        for key, args in tasks:
            futures[executor.submit(fn, *args)] = key
        for fut in cf.as_completed(futures):
            handled.add(fut)
            on_result(futures[fut], fut.result())
    except Exception:
        for fut in futures:
            fut.cancel()
        raise
    except BaseException:
        if stop is not None:
            stop.set()
        stop_workers(executor, futures, own)
        for fut, key in futures.items():
            if fut in handled or not fut.done() or fut.cancelled():
                continue
            if fut.exception() is not None:
                continue
            try:
                on_result(key, fut.result())
            except Exception:  # keeping more is best effort; the interrupt goes on
                pass
        raise
