"""Small walker files and checkpoints, a bit-for-bit comparison of HDF5 files and a Python
child process to interrupt, for the storage, checkpoint and interrupt tests.

A sweep of ten points over (``slope``, ``mass_ratio``) in four chunks of three rows, with
one column of each kind walker stores (float, integer, complex with a shape, boolean), a
3 x 5 basin checkpoint in chunks of two rows, and a finished 3 x 2 basin file.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

from walker.results import BasinMap
from walker.storage import SweepStore, write

REPO = Path(__file__).resolve().parents[1]

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


def small_basin_file(path):
    """A finished 3 x 2 basin result (``walker.storage.write``, no checkpoint) at ``path``."""
    bm = BasinMap(
        ("a", "b"),
        np.linspace(0, 1, 3),
        np.linspace(0, 1, 2),
        np.full((2, 3), -1),
        np.zeros((2, 3), dtype=np.int64),
        np.zeros(2),
        np.zeros(2),
        5,
    )
    return write(path, bm, provenance={"model": "toy"})


def hdf5_items(path: Path) -> dict[str, object]:
    """Every attribute and dataset of an HDF5 file, as comparable values (raw bytes for
    datasets), except the root attributes ``created`` (the time of writing), ``checksum``
    and ``command_line`` (the command that wrote the file, which names its --out), which is
    also left out of the ``provenance`` JSON."""
    items: dict[str, object] = {}
    with h5py.File(path, "r") as f:

        def attrs(name, obj):
            for key, value in obj.attrs.items():
                if name == "/" and key in ("created", "checksum", "command_line"):
                    continue
                if name == "/" and key == "provenance":
                    prov = json.loads(value)
                    prov.pop("command_line", None)
                    value = json.dumps(prov, sort_keys=True)
                v = np.asarray(value)
                items[f"{name}@{key}"] = (v.dtype.str, v.shape, v.tobytes())

        attrs("/", f)

        def visit(name, obj):
            attrs(name, obj)
            if isinstance(obj, h5py.Dataset):
                data = np.asarray(obj[()])
                items[name] = (obj.dtype.str, obj.shape, data.tobytes())

        f.visititems(visit)
    return items


def assert_same_file(a: Path, b: Path) -> None:
    """Raise AssertionError naming the items in which the HDF5 files ``a`` and ``b``
    differ (see :func:`hdf5_items`)."""
    ia, ib = hdf5_items(a), hdf5_items(b)
    assert sorted(ia) == sorted(ib)
    differ = [k for k in ia if ia[k] != ib[k]]
    assert not differ, f"{a} and {b} differ in {differ}"


def start_python(args: list[str], **options) -> subprocess.Popen:
    """``python args`` started in the repository in a session of its own (so that a signal
    can reach its whole process group), its output discarded and its errors piped;
    ``options`` go to :class:`subprocess.Popen`."""
    return subprocess.Popen(
        [sys.executable, *args],
        cwd=REPO,
        start_new_session=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        **options,
    )
