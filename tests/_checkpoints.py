"""A small sweep checkpoint and basin checkpoint for the storage tests
(``tests/test_storage.py`` and the ``tests/test_storage_*`` files on damaged files).

A sweep of ten points over (``slope``, ``mass_ratio``) in four chunks of three rows, with
one column of each kind walker stores (float, integer, complex with a shape, boolean), and
a 3 x 5 basin checkpoint in chunks of two rows.
"""

from __future__ import annotations

import numpy as np

from walker.storage import SweepStore

COLUMNS = {"value": ("f8", ()), "status": ("i8", ()), "mult": ("c16", (2,)), "ok": ("?", ())}


def sweep_points(n=10):
    """``n`` points: slope from 0.001 to 0.010, mass ratio 2."""
    return np.stack([np.linspace(0.001, 0.010, n), np.full(n, 2.0)], axis=1)


def chunk_values(points, sl):
    """The column values of the rows ``sl`` of ``points`` (``status`` is the row index)."""
    p = points[sl, 0]
    return {
        "value": 1000 * p,
        "status": np.arange(sl.start, sl.stop),
        "mult": np.stack([p + 1j * p, p - 1j * p], axis=1),
        "ok": np.ones(len(p), bool),
    }


def sweep_store(path, **changes):
    """Create or reopen the sweep checkpoint at ``path``; ``changes`` override the
    arguments of :meth:`walker.storage.SweepStore.create_or_open`."""
    kw = dict(
        parameter_names=("slope", "mass_ratio"),
        points=sweep_points(),
        columns=COLUMNS,
        chunk_size=3,
        provenance={"model": "compass"},
    )
    kw.update(changes)
    return SweepStore.create_or_open(path, **kw)


def half_done_sweep(path):
    """A sweep checkpoint with chunks 0 and 2 of 4 done."""
    store = sweep_store(path)
    for i in (0, 2):
        store.write_chunk(i, chunk_values(store.points, store.chunk_slice(i)))
    return store


def basin_kw():
    """Arguments of :meth:`walker.storage.BasinStore.create_or_open` for a 3 x 5 basin."""
    return dict(
        axis_names=("a", "b"),
        x=np.linspace(0, 1, 3),
        y=np.linspace(0, 1, 5),
        fixed_point=np.zeros(2),
        base=np.zeros(2),
        n_strides=10,
        tol=1e-6,
        period=1,
        provenance={"model": "toy"},
        chunk_size=2,
    )
