""":class:`BasinStore`: a basin map checkpointed rows by rows in one HDF5 file."""

from __future__ import annotations

import json
import numbers
import os
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from walker.results import BasinMap
from walker.storage.checkpoint import _ChunkedStore
from walker.storage.decode import _Loaded, _scalar_attr, read
from walker.storage.encode import _chunked_dataset, _dataset_options
from walker.storage.loader import _int_attr
from walker.storage.provenance import _check_provenance, _to_json
from walker.storage.schema import (
    _CHECKPOINT_GROUP,
    _RESULT_GROUP,
    BASIN_NOT_COMPUTED,
    CheckpointMismatch,
    _Corrupt,
)

BASIN_DEFAULT_CHUNKS = 32
"""A new :class:`BasinStore` without a given chunk size cuts the grid into about this many
chunks of whole rows (fewer when there are fewer rows)."""


def _same_array(a: Any, b: Any) -> bool:
    """Same dtype, shape and bytes."""
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _finite_vector(value: Any, name: str) -> np.ndarray:
    arr = np.asarray(value)
    if arr.ndim != 1 or arr.size == 0 or arr.dtype.kind not in "biuf":
        raise ValueError(f"`{name}` must be a non-empty 1-D array of real numbers")
    arr = np.array(arr, dtype=np.float64)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"`{name}` must be finite")
    return arr


def _positive(value: Any, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"`{name}` must be an int, got {value!r}")
    if value < 1:
        raise ValueError(f"`{name}` must be >= 1, got {value}")
    return int(value)


class BasinStore(_ChunkedStore):
    """Chunked, resumable storage of a basin map in one HDF5 file: chunk ``i`` is the grid
    rows ``i*chunk_size : min((i+1)*chunk_size, ny)`` (points ``y[rows] x x``).

    The file is a ``"basin"`` result (``read`` returns its :class:`~walker.results.BasinMap`,
    and a finished file is what :func:`write` would store, plus the ``/checkpoint`` group):
    ``x``, ``y``, ``fixed_point``, ``base``, ``axis_names`` and ``n_strides`` are written at
    creation; ``outcome`` and ``strides`` (int64, ``(ny, nx)``) are allocated then with
    :data:`BASIN_NOT_COMPUTED` and -1, and each chunk's rows are filled by
    :meth:`write_chunk`.  ``/checkpoint`` holds ``chunk_size``, ``n_chunks``, ``tol`` and
    ``period`` (attributes), ``done`` (bool per chunk) and ``chunk_sha256`` (the SHA-256 of
    each done chunk's rows).

    The contract, the checks and the guarantee under SIGKILL (and under an exception such as
    ``KeyboardInterrupt`` at any point) are those of :class:`SweepStore`: creation is atomic,
    a chunk marked done holds all its rows, a chunk interrupted mid-write stays pending, a
    chunk whose checksum fails is pending again, chunks are written with ``os.pwrite`` and a
    reader may open the file meanwhile.
    Reopening requires the same grid (``x``, ``y`` bitwise), ``axis_names``, ``fixed_point``,
    ``base``, ``n_strides``, ``tol``, ``period`` and caller provenance; the chunk size is
    the stored one unless a different one is asked for (then :class:`CheckpointMismatch`).
    The outcome of a grid point does not depend on the chunking, so neither does the file.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import numpy as np
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "basin.h5"
    >>> kw = dict(axis_names=("a", "b"), x=np.linspace(0, 1, 3), y=np.linspace(0, 1, 5),
    ...           fixed_point=np.zeros(2), base=np.zeros(2), n_strides=10, tol=1e-6,
    ...           period=1, provenance={"model": "toy"})
    >>> store = BasinStore.create_or_open(path, chunk_size=2, **kw)
    >>> store.pending_chunks(), store.chunk_slice(2)
    ([0, 1, 2], slice(4, 5, None))
    >>> store.write_chunk(0, np.full((2, 3), -1), np.full((2, 3), 4))
    >>> BasinStore.create_or_open(path, **kw).pending_chunks()
    [1, 2]
    >>> read(path)[0].outcome[:, 0].tolist()
    [-1, -1, -3, -3, -3]
    """

    KIND = "basin"
    DATACLASS = "BasinMap"

    def __init__(self, path: Path, ny: int, nx: int, chunk_size: int, fsync: bool = True):
        """Use :meth:`create_or_open`."""
        super().__init__(path, ny, chunk_size, fsync)
        self.shape = (int(ny), int(nx))

    # -- construction ---------------------------------------------------------------------

    @classmethod
    def create_or_open(
        cls,
        path: str | os.PathLike,
        *,
        axis_names: tuple[str, str],
        x: Any,
        y: Any,
        fixed_point: Any,
        base: Any,
        n_strides: int,
        tol: float,
        period: int,
        provenance: dict,
        chunk_size: int | None = None,
        overwrite: bool = False,
        fsync: bool = True,
        classification: dict | None = None,
    ) -> BasinStore:
        """Create the checkpoint file, or open an existing one for the same basin map.

        Parameters
        ----------
        path : str or os.PathLike
        axis_names : (str, str)
        x, y : array_like, shape (nx,), (ny,)
            the grid, finite.
        fixed_point, base : array_like, shape (n_z,)
        n_strides : int
            strides per point, >= 1.
        tol : float
            convergence tolerance of the map (> 0).
        period : int
            strides per map call (the fixed point's period), >= 1.
        provenance : dict
            as for :func:`write`; an existing file must hold the same.
        chunk_size : int, optional
            grid rows per chunk; default: the existing file's, else about
            ``ny / BASIN_DEFAULT_CHUNKS``.
        overwrite : bool
            replace an existing file (whatever it holds) by a new, empty checkpoint.
        fsync : bool
            fsync the file after each chunk.
        classification : dict, optional
            the map's classification rule (:attr:`BasinMap.classification`), stored with the
            result; an existing file must hold the same (a file without one: the tolerance
            alone, ``{"tol": tol, "converge_radius": 0.0}``), except that two automatic
            balls (``converge_radius_rule`` "auto") match: the store's
            ``classification`` is then the file's, which the resumed chunks must use.

        Returns
        -------
        BasinStore

        Raises
        ------
        CheckpointMismatch, StorageError, FileNotFoundError
            as :meth:`SweepStore.create_or_open` does, for a checkpoint of this basin map.
        """
        path = cls._store_path(path)
        if (
            not isinstance(axis_names, tuple | list)
            or len(axis_names) != 2
            or not all(isinstance(n, str) for n in axis_names)
        ):
            raise TypeError(f"`axis_names` must be two str, got {axis_names!r}")
        names = tuple(axis_names)
        x = _finite_vector(x, "x")
        y = _finite_vector(y, "y")
        fixed_point = _finite_vector(fixed_point, "fixed_point")
        base = _finite_vector(base, "base")
        if base.shape != fixed_point.shape:
            raise ValueError(
                f"`base` must have the shape of `fixed_point` {fixed_point.shape}, got {base.shape}"
            )
        n_strides = _positive(n_strides, "n_strides")
        period = _positive(period, "period")
        if isinstance(tol, bool) or not isinstance(tol, numbers.Real):
            raise TypeError(f"`tol` must be a real number, got {tol!r}")
        tol = float(tol)
        if not (np.isfinite(tol) and tol > 0):
            raise ValueError(f"`tol` must be positive and finite, got {tol}")
        if chunk_size is not None:
            chunk_size = _positive(chunk_size, "chunk_size")
        prov_json = _check_provenance(provenance)
        if classification is None:
            classification = {"tol": tol, "converge_radius": 0.0}
        if not isinstance(classification, dict):
            raise TypeError(f"`classification` must be a dict, got {type(classification).__name__}")
        ny, nx = y.size, x.size
        want = dict(
            provenance_json=prov_json,
            axis_names=names,
            x=x,
            y=y,
            fixed_point=fixed_point,
            base=base,
            n_strides=n_strides,
            tol=tol,
            period=period,
            chunk_size=chunk_size,
            classification=classification,
        )
        if path.exists() and not overwrite:  # (self.classification: the file's)
            stored_chunk, loaded = cls._compare(path, want)
            store = cls(path, ny, nx, stored_chunk, fsync=bool(fsync))
            store._resume(loaded)
            store.classification = loaded.result.classification or classification
            return store
        cls._check_directory(path)
        if chunk_size is None:
            chunk_size = max(1, -(-ny // BASIN_DEFAULT_CHUNKS))
        store = cls(path, ny, nx, chunk_size, fsync=bool(fsync))
        store._create(want, overwrite=bool(overwrite))
        store.classification = classification
        return store

    @classmethod
    def check_existing(
        cls,
        path: str | os.PathLike,
        *,
        provenance: dict | None = None,
        axis_names: tuple[str, str] | None = None,
        shape: tuple[int, int] | None = None,
        n_strides: int | None = None,
        tol: float | None = None,
    ) -> None:
        """Check, without computing the grid, that ``path`` is a basin checkpoint agreeing with
        what is given (None: not checked).  Lets a caller refuse an unrelated file before the
        work that :meth:`create_or_open` needs (finding the fixed point).

        ``shape`` is ``(ny, nx)``.  Raises :class:`CheckpointMismatch` as ``create_or_open``
        would; a missing file passes.
        """
        path = Path(path)
        if not path.exists():
            return
        want: dict[str, Any] = {
            "axis_names": None if axis_names is None else tuple(axis_names),
            "shape": None if shape is None else tuple(int(s) for s in shape),
            "n_strides": n_strides,
            "tol": None if tol is None else float(tol),
        }
        if provenance is not None:
            want["provenance_json"] = _check_provenance(provenance)
        cls._compare(path, {k: v for k, v in want.items() if v is not None})

    @classmethod
    def _compare(cls, path: Path, want: dict[str, Any]) -> tuple[int, _Loaded]:
        """Raise CheckpointMismatch unless ``path`` is a basin checkpoint agreeing with every
        entry of ``want``; returns its chunk size and the file as read (in a child process,
        every checksum verified)."""
        loaded = cls._load_checkpoint(path)
        if loaded.kind != "basin" or loaded.state is None:
            what = (
                "a finished 'basin' result without a checkpoint"
                if loaded.kind == "basin"
                else f"a {loaded.kind!r} result"
            )
            raise cls._refused(path, f"holds {what}, not a basin checkpoint", "use a new path")
        basin = loaded.result
        k = loaded.root["groups"][_CHECKPOINT_GROUP]
        try:
            stored_cs = _int_attr(k["attrs"], "chunk_size", f"/{_CHECKPOINT_GROUP}", minimum=1)
            stored_tol = float(_scalar_attr(k, "tol", f"/{_CHECKPOINT_GROUP}", "f", "a float"))
            stored_period = _int_attr(k["attrs"], "period", f"/{_CHECKPOINT_GROUP}", minimum=1)
        except _Corrupt as exc:
            raise CheckpointMismatch(
                f"cannot resume '{path}': corrupted ({exc})",
                path=path,
                reason=f"is corrupted ({exc})",
            ) from None
        diffs: list[str] = []
        if "axis_names" in want and basin.axis_names != want["axis_names"]:
            diffs.append(f"axis_names {basin.axis_names} != {want['axis_names']}")
        if "shape" in want:
            shape = (basin.y.size, basin.x.size)
            if shape != want["shape"]:
                diffs.append(f"grid shape {shape} != {want['shape']}")
        for name in ("x", "y", "fixed_point", "base"):
            if name in want and not _same_array(getattr(basin, name), want[name]):
                diffs.append(f"{name} differs")
        if "n_strides" in want and basin.n_strides != want["n_strides"]:
            diffs.append(f"n_strides {basin.n_strides} != {want['n_strides']}")
        for name, stored in (("tol", stored_tol), ("period", stored_period)):
            if name in want and stored != want[name]:
                diffs.append(f"{name} {stored} != {want[name]}")
        if "classification" in want:
            stored_cls = basin.classification or {"tol": stored_tol, "converge_radius": 0.0}
            new = want["classification"]
            # an automatic ball is derived again on resume: the stored one is kept (its last
            # bits could differ elsewhere), the rule must be the same
            both_auto = all(
                c.get("converge_radius_rule") == "auto" and c.get("tol") == stored_tol
                for c in (stored_cls, new)
            )
            if not both_auto and _to_json(stored_cls, "classification") != _to_json(
                new, "classification"
            ):
                diffs.append(
                    f"converge_radius {stored_cls.get('converge_radius')} != "
                    f"{want['classification'].get('converge_radius')} (or its rule)"
                )
        if want.get("chunk_size") is not None and want["chunk_size"] != stored_cs:
            diffs.append(f"chunk_size {stored_cs} != {want['chunk_size']}")
        if "provenance_json" in want:
            diffs += cls._provenance_diffs(loaded.provenance_json, want["provenance_json"])
        if diffs:
            raise cls._refused(
                path,
                f"checkpoints a different basin map ({'; '.join(diffs)})",
                "use a new path or delete the file",
            )
        return stored_cs, loaded

    def _create(self, want: dict[str, Any], overwrite: bool) -> None:
        ny, nx = self.shape
        cs = self.chunk_size

        def fill_result(g: h5py.Group) -> None:
            g.attrs["axis_names"] = json.dumps(list(want["axis_names"]))
            g.attrs["n_strides"] = np.int64(want["n_strides"])
            g.attrs["classification"] = json.dumps(
                _to_json(want["classification"], "classification")
            )
            for name in ("x", "y", "fixed_point", "base"):
                g.create_dataset(name, data=want[name], **_dataset_options(want[name].shape))
            for name, fillv in (("outcome", BASIN_NOT_COMPUTED), ("strides", -1)):
                _chunked_dataset(g, name, (ny, nx), cs, np.int64, fillv)

        self._write_new(
            want["provenance_json"],
            (16 * ny * nx + 50 * self.n_chunks, 16 * cs * nx),
            fill_result,
            {"tol": np.float64(want["tol"]), "period": np.int64(want["period"])},
            overwrite,
        )

    # -- use --------------------------------------------------------------------------------

    def write_chunk(self, i: int, outcome: Any, strides: Any) -> None:
        """Write the rows of chunk ``i`` (``outcome`` and ``strides``, integer arrays of shape
        ``(rows, nx)``), then mark the chunk done."""
        i = self._check_chunk(i)
        sl = self.chunk_slice(i)
        arrays = {}
        for name, value in (("outcome", outcome), ("strides", strides)):
            arr = np.asarray(value)
            if arr.shape != (sl.stop - sl.start, self.shape[1]):
                raise ValueError(
                    f"`{name}` must have shape {(sl.stop - sl.start, self.shape[1])} for chunk "
                    f"{i}, got {arr.shape}"
                )
            if arr.dtype.kind not in "iu":
                raise TypeError(f"`{name}` must be an integer array, got dtype {arr.dtype}")
            arrays[f"/{_RESULT_GROUP}/{name}"] = arr.astype(np.int64, copy=False)
        self._writer.write(i, arrays, self.fsync)

    def result(self) -> BasinMap:
        """The basin map (rows not yet written hold :data:`BASIN_NOT_COMPUTED` and -1)."""
        result, _ = read(self.path, isolate=False)
        return result
