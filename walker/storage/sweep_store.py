""":class:`SweepStore`: a parameter sweep checkpointed chunk by chunk in one HDF5 file."""

from __future__ import annotations

import json
import math
import numbers
import os
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from walker.results import SweepTable
from walker.storage.checkpoint import _ChunkedStore
from walker.storage.decode import _load_checked, read
from walker.storage.encode import _check_name, _chunked_dataset, _dataset_options
from walker.storage.loader import _fill_value, _int_attr
from walker.storage.provenance import _check_provenance
from walker.storage.schema import _CHECKPOINT_GROUP, _RESULT_GROUP


class SweepStore(_ChunkedStore):
    """Chunked, resumable storage of a parameter sweep in one HDF5 file.

    The file has the layout of a ``"sweep"`` result (so :func:`read` returns its
    :class:`~walker.results.SweepTable`), with every column preallocated and filled with NaN
    (float, complex), -1 (signed int) or False (bool), plus ``/checkpoint/done``, one bool per
    chunk of ``chunk_size`` consecutive points, and ``/checkpoint/chunk_sha256``, the SHA-256
    of each done chunk's rows.  Each column is stored in one HDF5 chunk (with its Fletcher-32
    checksum) per checkpoint chunk.

    Contract with the caller (the sweep engine):

    1. ``create_or_open`` either creates the file (atomically, like :func:`write`) or opens an
       existing one, which must describe the same sweep: same parameter names, points, column
       names/dtypes/shapes, chunk size and caller provenance; otherwise :class:`StorageError`
       says what differs.
    2. Compute the chunks in ``pending_chunks()``; rows of chunk ``i`` are ``chunk_slice(i)``.
    3. ``write_chunk(i, values)`` writes every column's rows, then the chunk's SHA-256, then
       ``done[i]``, with ``os.pwrite`` at the byte offsets of their HDF5 chunks (found when the
       file was created or opened), then fsyncs.  No HDF5 call writes to the file after its
       creation.  A write failing with a transient error is retried (:data:`WRITE_ATTEMPTS`);
       a full disk, a read-only file system or a replaced file is a :class:`StorageError`,
       and the chunks already done stay intact.  Writing a chunk again overwrites it
       (idempotent).  One process writes a given file at a time.

    Guarantee when the writing process is killed (SIGKILL, not a power cut or OS crash):
    all chunks are allocated at creation, so a chunk write changes raw data at fixed offsets
    only, and no HDF5 metadata; a chunk marked done has all its rows written (they reached the
    OS before the flag); a chunk killed mid-write stays pending and may hold partial rows
    (which fail their checksum), which its recomputation overwrites.  After ``write_chunk``
    returns, the chunk has also been fsynced.  A kill during creation leaves no file (only
    possibly a ``.<name>.tmp-*`` file, removed by the next creation of the same file).  Not
    guaranteed: anything under a concurrent second writer, or after a crash of the OS or
    storage device in the middle of a write.

    Checks: opening an existing file reads it in a child process (as :func:`read`) and
    verifies every checksum.  A chunk marked done whose rows, checksum or flag is damaged is
    pending again (``pending_chunks`` lists it and recomputing it repairs the file); damage
    anywhere else (attributes, points, the layout) refuses the file with
    :class:`CheckpointMismatch`.  So a resumed sweep never keeps a damaged row.

    Readers: :func:`read` may open the file while a sweep writes it (no lock is involved);
    it sees the chunks marked done when it reads the flags, the other rows hold the fill
    values.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import numpy as np
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "sweep.h5"
    >>> points = np.linspace(0.001, 0.01, 5)[:, None]
    >>> store = SweepStore.create_or_open(
    ...     path, parameter_names=("slope",), points=points,
    ...     columns={"step_time": ("f8", ()), "status": ("i8", ())}, chunk_size=2,
    ...     provenance={"model": "simplest"})
    >>> store.pending_chunks(), store.chunk_slice(2)
    ([0, 1, 2], slice(4, 5, None))
    >>> store.write_chunk(0, {"step_time": np.array([3.1, 3.2]), "status": np.array([0, 0])})
    >>> store.pending_chunks()
    [1, 2]
    >>> store.table().columns["status"]
    array([ 0,  0, -1, -1, -1])
    """

    KIND = "sweep"
    DATACLASS = "SweepTable"

    def __init__(
        self,
        path: Path,
        parameter_names: tuple[str, ...],
        points: np.ndarray,
        columns: dict[str, tuple[np.dtype, tuple[int, ...]]],
        chunk_size: int,
        fsync: bool = True,
    ) -> None:
        """Use :meth:`create_or_open`."""
        super().__init__(path, points.shape[0], chunk_size, fsync)
        self.parameter_names = parameter_names
        self.points = points
        self.columns = columns
        self.n_points = int(points.shape[0])

    # -- construction ---------------------------------------------------------------------

    @classmethod
    def create_or_open(
        cls,
        path: str | os.PathLike,
        *,
        parameter_names: tuple[str, ...] | list[str],
        points: np.ndarray,
        columns: dict[str, tuple[Any, tuple[int, ...]]],
        chunk_size: int,
        provenance: dict,
        fsync: bool = True,
        overwrite: bool = False,
    ) -> SweepStore:
        """Create the checkpoint file, or open an existing one for the same sweep.

        Parameters
        ----------
        path : str or os.PathLike
        parameter_names : sequence of str, length k
        points : ndarray, shape (n, k)
            parameter values of each point (finite; stored as float64).
        columns : dict
            name -> (dtype, per-point shape); dtypes float, complex, signed int or bool.
            Column ``name`` is stored with shape ``(n, *shape)``.
        chunk_size : int
            points per chunk (the last chunk may be shorter).
        provenance : dict
            as for :func:`write`; an existing file must hold the same.
        fsync : bool
            fsync the file after each chunk (durability across power loss; costs a few ms).
        overwrite : bool
            replace an existing file (whatever it holds) by a new, empty checkpoint instead
            of resuming it.

        Returns
        -------
        SweepStore

        Raises
        ------
        CheckpointMismatch
            ``path`` exists (and ``overwrite`` is False) but is not a checkpoint of this
            sweep, or is corrupted.
        StorageError
            the new file would not fit in memory or on the disk, or the disk is full or
            read-only.
        FileNotFoundError
            the directory of ``path`` does not exist.
        """
        path = cls._store_path(path)
        if isinstance(parameter_names, str) or not all(isinstance(n, str) for n in parameter_names):
            raise TypeError(f"`parameter_names` must be a sequence of str, got {parameter_names!r}")
        names = tuple(parameter_names)
        pts = np.asarray(points)
        if pts.ndim != 2 or pts.shape[1] != len(names) or pts.shape[0] == 0:
            raise ValueError(
                f"`points` must have shape (n, {len(names)}) with n >= 1 (one column per "
                f"parameter name), got {pts.shape}"
            )
        if pts.dtype.kind not in "biuf" or not np.all(np.isfinite(pts)):
            raise ValueError("`points` must be real and finite")
        pts = np.array(pts, dtype=np.float64)
        pts.setflags(write=False)
        if isinstance(chunk_size, bool) or not isinstance(chunk_size, numbers.Integral):
            raise TypeError(f"`chunk_size` must be an int, got {chunk_size!r}")
        if chunk_size < 1:
            raise ValueError(f"`chunk_size` must be >= 1, got {chunk_size}")
        if not isinstance(columns, dict) or not columns:
            raise ValueError("`columns` must be a non-empty dict name -> (dtype, shape)")
        cols: dict[str, tuple[np.dtype, tuple[int, ...]]] = {}
        for name, spec in columns.items():
            _check_name(name, "columns")
            try:
                dtype, shape = spec
                dtype = np.dtype(dtype)
                shape = tuple(int(s) for s in shape)
            except (TypeError, ValueError):
                raise ValueError(
                    f"`columns[{name!r}]` must be (dtype, per-point shape), got {spec!r}"
                ) from None
            if dtype.kind not in "fcib" or any(s < 0 for s in shape):
                raise ValueError(
                    f"`columns[{name!r}]` must have a float, complex, signed int or bool dtype "
                    f"and a non-negative shape, got ({dtype}, {shape})"
                )
            cols[name] = (dtype, shape)
        prov_json = _check_provenance(provenance)
        store = cls(path, names, pts, cols, int(chunk_size), fsync=bool(fsync))
        if path.exists() and not overwrite:
            store._check_existing(prov_json)
        else:
            cls._check_directory(path)
            store._create(prov_json, overwrite=bool(overwrite))
        return store

    def _create(self, prov_json: dict, overwrite: bool = False) -> None:
        n, cs = self.n_points, self.chunk_size
        row_bytes = sum(d.itemsize * math.prod(s) for d, s in self.columns.values())

        def fill_result(g: h5py.Group) -> None:
            g.attrs["parameter_names"] = json.dumps(list(self.parameter_names))
            g.create_dataset("points", data=self.points, **_dataset_options(self.points.shape))
            cg = g.create_group("columns")
            cg.attrs["names"] = json.dumps(list(self.columns))
            for name, (dtype, shape) in self.columns.items():
                _chunked_dataset(cg, name, (n, *shape), cs, dtype, _fill_value(dtype))

        self._write_new(
            prov_json,
            (n * row_bytes + self.points.nbytes + 50 * self.n_chunks, cs * row_bytes),
            fill_result,
            {},
            overwrite,
        )

    def _check_existing(self, prov_json: dict) -> None:
        path = self.path
        loaded = self._load_checkpoint(path)
        if loaded.kind != "sweep" or loaded.state is None:
            raise self._refused(
                path, f"holds a {loaded.kind!r} result, not a sweep checkpoint", "use a new path"
            )
        table = loaded.result
        diffs = []
        if table.parameter_names != self.parameter_names:
            diffs.append(f"parameter_names {table.parameter_names} != {self.parameter_names}")
        stored_points = table.points
        if stored_points.shape != self.points.shape:
            diffs.append(f"points shape {stored_points.shape} != {self.points.shape}")
        elif not np.array_equal(stored_points, self.points):
            n_diff = int(np.sum(np.any(stored_points != self.points, axis=1)))
            diffs.append(f"{n_diff} of the points differ")
        stored_cols = {name: (col.dtype, col.shape[1:]) for name, col in table.columns.items()}
        if stored_cols != self.columns:
            show = {k: (str(d), s) for k, (d, s) in stored_cols.items()}
            want = {k: (str(d), s) for k, (d, s) in self.columns.items()}
            diffs.append(f"columns {show} != {want}")
        k = loaded.root["groups"][_CHECKPOINT_GROUP]
        stored_cs = _int_attr(k["attrs"], "chunk_size", f"/{_CHECKPOINT_GROUP}")
        if stored_cs != self.chunk_size:
            diffs.append(f"chunk_size {stored_cs} != {self.chunk_size}")
        diffs += self._provenance_diffs(loaded.provenance_json, prov_json)
        if diffs:
            raise self._refused(
                path,
                f"checkpoints a different sweep ({'; '.join(diffs)})",
                "use a new path or delete the file",
            )
        self._resume(loaded)

    # -- use --------------------------------------------------------------------------------

    def write_chunk(self, i: int, values: dict[str, np.ndarray]) -> None:
        """Write the rows of chunk ``i`` for every column, then mark the chunk done.

        Parameters
        ----------
        i : int
            chunk index.
        values : dict
            column name -> array of shape ``(rows, *shape)`` (``rows`` = length of
            ``chunk_slice(i)``), castable to the column's dtype ("same_kind").
        """
        i = self._check_chunk(i)
        sl = self.chunk_slice(i)
        rows = sl.stop - sl.start
        if not isinstance(values, dict):
            raise TypeError(f"`values` must be a dict name -> ndarray, got {type(values).__name__}")
        missing = [k for k in self.columns if k not in values]
        extra = [k for k in values if k not in self.columns]
        if missing or extra:
            raise ValueError(
                f"`values` must have exactly the columns {list(self.columns)}; "
                f"missing {missing}, unknown {extra}"
            )
        arrays = {}
        for name, (dtype, shape) in self.columns.items():
            arr = np.asarray(values[name])
            if arr.shape != (rows, *shape):
                raise ValueError(
                    f"`values[{name!r}]` must have shape {(rows, *shape)} for chunk {i}, "
                    f"got {arr.shape}"
                )
            if not np.can_cast(arr.dtype, dtype, casting="same_kind"):
                raise TypeError(
                    f"`values[{name!r}]` of dtype {arr.dtype} cannot be stored as {dtype}"
                )
            arrays[f"/{_RESULT_GROUP}/columns/{name}"] = arr.astype(dtype, copy=False)
        self._writer.write(i, arrays, self.fsync)

    def table(self, *, damaged_ok: bool = False) -> SweepTable:
        """The whole table (unwritten rows hold the fill values).  ``damaged_ok``: a chunk
        whose checksum fails is no error (its rows are whatever the file holds): for a
        resume, which recomputes such chunks and reads only the others' rows."""
        if damaged_ok:
            return _load_checked(Path(self.path), isolate=False).result
        result, _ = read(self.path, isolate=False)
        return result
