"""Running independent chunks on a :class:`concurrent.futures.Executor`, and stopping them.

Used by :func:`walker.analysis.sweep.sweep` and :func:`walker.analysis.basin.basin_map`, which
share here their pool policy (:func:`worker_pool`: threads of this process unless asked for
processes) and their progress policy (:func:`progress_bar`: a tqdm bar on stderr only when it is a
terminal, erased after an interrupt).  Nothing here touches
signals: an interrupt reaches :func:`run_chunks` as an exception (``KeyboardInterrupt``, or
whatever a caller's signal handler raises) in the thread that collects the results, and
:func:`run_chunks` then stops the work before re-raising it:

* every chunk not started is cancelled (a ``dask.distributed`` future's task with it);
* threads cannot be stopped: the running chunks are asked to stop through ``stop`` (when the
  chunk function looks at it) or run to their end, which is waited for;
* a ``ProcessPoolExecutor`` is shut down (``cancel_futures=True``) and its worker processes
  terminated, so no worker outlives an interrupted run computing a chunk nobody collects;
* the chunks that finished meanwhile are handed to ``on_result`` (so a checkpoint keeps them).

A process pool's workers must not outlive the process that started them (after a
``kill -9`` of a sweep nobody collects what they compute): :func:`process_pool` makes a pool
whose workers run :func:`die_with_parent` first, and :func:`run_chunks` runs it in the
workers of any other ``ProcessPoolExecutor`` before their first chunk.  On Linux the kernel
then kills a worker the moment its parent ends (``prctl(PR_SET_PDEATHSIG, SIGKILL)``), and a
watchdog thread the moment the pool's process ends (a pidfd; it polls every
:data:`WATCHDOG_INTERVAL` seconds where there is none).  A pool's forkserver ends when its
last worker has, and its resource tracker after that.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import ctypes
import functools
import multiprocessing
import os
import select
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterable
from typing import Any

__all__ = [
    "Abandoned",
    "die_with_parent",
    "process_pool",
    "progress_bar",
    "run_chunks",
    "stop_workers",
    "use_progress",
    "worker_pool",
]

WATCHDOG_INTERVAL = 0.5
"""Seconds between two looks of a pool worker's watchdog at its parent process."""

_PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
_guarded_pid: int | None = None  # the process in which die_with_parent has run


def _parent_death_signal(signum: int) -> bool:
    """Ask Linux to send ``signum`` to this process when its parent ends; False elsewhere
    or when it cannot."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(_PR_SET_PDEATHSIG, signum, 0, 0, 0) == 0
    except (OSError, AttributeError):  # pragma: no cover - no libc prctl
        return False


def _exists(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # pragma: no cover - someone else's process now
        return True
    return True


def _watch(parent: int, origin: int, pidfd: int | None) -> None:
    """Kill this process when its parent changes (it died) or ``origin`` ends."""
    while True:
        if pidfd is not None:  # readable once ``origin`` has ended
            if select.select([pidfd], [], [], WATCHDOG_INTERVAL)[0]:
                break
        else:
            time.sleep(WATCHDOG_INTERVAL)
            if not _exists(origin):
                break
        if os.getppid() != parent:
            break
    os.kill(os.getpid(), signal.SIGKILL)


def die_with_parent() -> None:
    """End this process (SIGKILL) when the process that started it ends: the initializer of
    walker's process pools, and usable as ``ProcessPoolExecutor(initializer=die_with_parent)``.

    "The process that started it" is ``multiprocessing.parent_process()``, the process that
    made the pool; with the ``forkserver`` start method the worker's parent is the
    forkserver, which waits for its workers before it ends, so both are watched.  On Linux
    the kernel sends the signal when the parent ends (``PR_SET_PDEATHSIG``; it counts the
    *thread* that started the process, so create the pool in a thread that outlives it, as
    walker does) and a daemon thread waits on a pidfd of the pool's process; elsewhere that
    thread polls every :data:`WATCHDOG_INTERVAL` seconds.  Runs once per process; does
    nothing in a process that multiprocessing did not start.
    """
    global _guarded_pid
    pid = os.getpid()
    origin = multiprocessing.parent_process()
    if _guarded_pid == pid or origin is None or origin.pid is None:
        return
    _guarded_pid = pid
    parent = os.getppid()
    _parent_death_signal(signal.SIGKILL)
    pidfd = None
    with contextlib.suppress(AttributeError, OSError):  # no pidfd: poll instead
        pidfd = os.pidfd_open(origin.pid)
    if os.getppid() != parent or not _exists(origin.pid):  # it ended before we watched it
        os.kill(pid, signal.SIGKILL)
    threading.Thread(
        target=_watch, args=(parent, origin.pid, pidfd), name="walker-watch-parent", daemon=True
    ).start()


def _guarded(fn: Callable[..., Any], *args: Any) -> Any:
    """``fn(*args)`` in a pool worker that has run :func:`die_with_parent`."""
    die_with_parent()
    return fn(*args)


def process_pool(max_workers: int, mp_context: Any = None) -> cf.ProcessPoolExecutor:
    """A ``ProcessPoolExecutor`` of ``max_workers`` processes that end with their parent
    (:func:`die_with_parent`)."""
    return cf.ProcessPoolExecutor(
        max_workers=max_workers, mp_context=mp_context, initializer=die_with_parent
    )


def worker_pool(
    jobs: int | None, n_tasks: int, *, name: str, processes: bool = False
) -> cf.Executor:
    """The pool a run makes for itself (and shuts down when done): ``jobs`` workers (default
    ``os.cpu_count()``), no more than the ``n_tasks`` chunks to run.

    Threads of this process by default: a stride runs in walker's compiled kernel with the GIL
    released, so ``n`` threads run ``n`` strides at once, with no process start-up and nothing
    to pickle (a map written in Python holds the GIL and gains nothing from threads: pass a
    ``ProcessPoolExecutor`` for it).  Their names start with ``walker-<name>``.  With
    ``processes``: a :func:`process_pool`, whose workers end with this process.
    """
    n_workers = min(jobs or os.cpu_count() or 1, n_tasks)
    if processes:
        return process_pool(n_workers)
    return cf.ThreadPoolExecutor(max_workers=n_workers, thread_name_prefix=f"walker-{name}")


def use_progress(progress: bool) -> bool:
    """Whether a run draws a progress bar: asked for (``progress``) and stderr is a terminal."""
    if not progress:
        return False
    try:
        return bool(sys.stderr.isatty())
    except (AttributeError, ValueError):
        return False


@contextlib.contextmanager
def progress_bar(progress: bool, *, total: int, initial: int, desc: str, unit: str):
    """A tqdm bar on stderr for the ``with`` block, drawn only when :func:`use_progress`
    (otherwise a disabled bar, whose ``update`` does nothing).  It is closed on the way out,
    and an interrupted run (``KeyboardInterrupt``) leaves no bar behind."""
    from tqdm.auto import tqdm

    bar = tqdm(
        total=total, initial=initial, unit=unit, desc=desc, disable=not use_progress(progress)
    )
    try:
        yield bar
    except KeyboardInterrupt:
        bar.leave = False
        raise
    finally:
        bar.close()


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
    if isinstance(executor, cf.ProcessPoolExecutor):
        # A pool made elsewhere: its workers end with this process too, from their first chunk.
        fn = functools.partial(_guarded, fn)
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
