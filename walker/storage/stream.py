""":class:`SolutionStream`: a long run written to its HDF5 file block by block, in bounded
memory.

The file has the layout :func:`walker.storage.write` gives a :class:`~walker.results.Solution`
(so :func:`walker.storage.read` reads it, its checksum included): the same groups, datasets,
dtypes and attributes.  The one difference is in storage, not in content: the datasets that
grow with the run (the event log, the samples, the stored steps) are created resizable
(``maxshape`` ``None`` along their rows, chunked, Fletcher-32) and extended as each block of
strides arrives.  The file is written under a temporary name next to its target, its
``checksum`` attribute computed by reading it back chunk by chunk, fsynced, then moved onto
the target (never replacing an existing file unless ``overwrite``), so a killed run leaves
no partial file under the target's name.
"""

from __future__ import annotations

import errno
import hashlib
import os
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from walker.storage.checksums import _feed, _value_bytes
from walker.storage.disk import (
    _DISK_ERRNOS,
    _check_space,
    _check_target,
    _disk_error,
    _fsync_path,
    _remove_stale_temps,
    _temp_name,
)
from walker.storage.encode import _encode, _provenance_attrs
from walker.storage.loader import _attr_value
from walker.storage.provenance import _check_provenance
from walker.storage.schema import _CHECKSUM_ATTR, _RESULT_GROUP

__all__ = ["SolutionStream"]

ROWS_PER_CHUNK = 4096
"""Rows per HDF5 chunk of a growing dataset (a few hundred kB for a walker's state)."""

_GROWING = ("events", "samples", "record")
_READ_ROWS = 1 << 16  # rows read at once when the checksum is computed


class SolutionStream:
    """Write a :class:`~walker.results.Solution` block by block.

    Parameters
    ----------
    path : str or os.PathLike
        target file; its directory must exist.
    first : Solution
        the run's first block: its arrays are written, and the kinds of record it holds
        (events, samples, stored steps) are those of every block.
    provenance : dict
        as for :func:`walker.storage.write`.
    overwrite : bool
        replace an existing file.

    Notes
    -----
    :meth:`append` adds a block that continues the run (it starts where the last one ended);
    :meth:`finish` writes the run's final state and counters (a Solution whose arrays are
    ignored), the checksum, and moves the file onto ``path``; :meth:`abort` removes the
    temporary file.  Use as a context manager: leaving the block without :meth:`finish`
    aborts.
    """

    def __init__(self, path: Any, first: Any, *, provenance: dict, overwrite: bool = False):
        from walker.results import Solution

        if type(first) is not Solution:
            raise TypeError(f"`first` must be a walker.results.Solution, got {type(first)}")
        self.prov = _check_provenance(provenance)
        self.path = _check_target(path, overwrite)
        self.overwrite = bool(overwrite)
        parent = self.path.parent if str(self.path.parent) else Path(".")
        _remove_stale_temps(self.path)
        _check_space(parent, 1 << 20, self.path)
        self.tmp = _temp_name(self.path)
        self.f = h5py.File(self.tmp, "w", libver="earliest")
        self.rows = {}
        try:
            self.f.attrs.update(_provenance_attrs(self.prov, "solution"))
            tree = _encode(first, Solution, "Solution")
            group = self.f.create_group(_RESULT_GROUP)
            self._emit(tree, group, "")
            self.group = group
        except BaseException:
            self.abort()
            raise

    # -- writing -------------------------------------------------------------------------

    def _emit(self, tree: dict, group: h5py.Group, where: str) -> None:
        for name, value in tree["attrs"].items():
            group.attrs[name] = value
        growing = where in _GROWING
        for name, arr in tree["datasets"].items():
            if growing:
                shape = arr.shape
                group.create_dataset(
                    name,
                    data=arr,
                    maxshape=(None, *shape[1:]),
                    chunks=(ROWS_PER_CHUNK, *shape[1:]) if all(shape[1:]) else True,
                    fletcher32=True,
                )
                self.rows[f"{where}/{name}"] = shape[0]
            else:
                from walker.storage.encode import _dataset_options

                group.create_dataset(name, data=arr, **_dataset_options(arr.shape))
        for name, sub in tree["groups"].items():
            self._emit(sub, group.create_group(name), name if not where else f"{where}/{name}")

    def append(self, block: Any) -> None:
        """Add the rows of ``block``, a Solution continuing the run from the last block's
        end (the first stored step of ``block``, its start state, is the last block's final
        state, so it is not stored again)."""
        for where in _GROWING:
            sub = getattr(block, where)
            if sub is None:
                continue
            skip = 1 if where == "record" else 0
            for name in self._fields(where):
                arr = np.asarray(getattr(sub, name))[skip:]
                key = f"{where}/{name}"
                ds = self.group[where][name]
                n = self.rows[key]
                ds.resize(n + arr.shape[0], axis=0)
                if arr.shape[0]:
                    ds[n : n + arr.shape[0]] = arr
                self.rows[key] = n + arr.shape[0]

    def _fields(self, where: str) -> list[str]:
        return [k.split("/", 1)[1] for k in self.rows if k.split("/", 1)[0] == where]

    def finish(self, final: Any) -> Path:
        """Write the run's final state and counters from ``final`` (a Solution: its status,
        message, ``t``, ``x``, phase, counters; its arrays are not used), the checksum, and
        move the file onto ``path``.  Returns ``path``."""
        from walker.results import Solution

        try:
            tree = _encode(final, Solution, "Solution")
            for name, value in tree["attrs"].items():
                self.group.attrs[name] = value
            for name, arr in tree["datasets"].items():  # x, and jac / dt_dx0 when present
                if name in self.group:
                    del self.group[name]
                from walker.storage.encode import _dataset_options

                self.group.create_dataset(name, data=arr, **_dataset_options(arr.shape))
            self.f.flush()
            self.f.attrs[_CHECKSUM_ATTR] = _streamed_digest(self.f)
            self.f.close()
            self._commit()
        except BaseException:
            self.abort()
            raise
        return self.path

    def _commit(self) -> None:
        fd = os.open(self.tmp, os.O_RDONLY | getattr(os, "O_CLOEXEC", 0))
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
        try:
            if self.overwrite:
                os.replace(self.tmp, self.path)
            else:
                try:
                    os.link(self.tmp, self.path)
                except FileExistsError:
                    raise FileExistsError(
                        f"'{self.path}' exists; pass overwrite=True to replace it"
                    ) from None
                os.unlink(self.tmp)
            parent = self.path.parent if str(self.path.parent) else Path(".")
            _fsync_path(parent, directory=True)
        except OSError as exc:
            if exc.errno in _DISK_ERRNOS and exc.errno != errno.EIO:
                raise _disk_error(exc, self.path, "cannot write") from None
            raise

    def abort(self) -> None:
        """Close and remove the temporary file (nothing is left under ``path``)."""
        try:
            if self.f.id.valid:
                self.f.close()
        except Exception:
            pass
        try:
            os.unlink(self.tmp)
        except OSError:
            pass

    def __enter__(self) -> SolutionStream:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if os.path.exists(self.tmp):
            self.abort()


def _streamed_digest(f: h5py.File) -> str:
    """The file's ``checksum`` (walker.storage.checksums._content_digest of the tree walker
    reads from it), with each dataset's data fed to the hash in slices of rows rather than
    read whole."""
    h = hashlib.sha256(b"walker file checksum 1\0")

    def attrs(obj) -> dict:
        return {name: _attr_value(obj.attrs[name]) for name in obj.attrs}

    def walk(g: h5py.Group, path: str) -> None:
        node_attrs = attrs(g)
        for name in sorted(node_attrs):
            if path == "/" and name == _CHECKSUM_ATTR:
                continue
            _feed(h, b"A", path, name, *_value_bytes(node_attrs[name]))
        datasets = sorted(n for n in g if isinstance(g[n], h5py.Dataset))
        for name in datasets:
            p = f"{path.rstrip('/')}/{name}"
            ds = g[name]
            dtype = np.dtype(ds.dtype)
            h.update(b"D")
            for part in (p, f"{dtype.str}{ds.shape}"):
                raw = part.encode("utf-8", "surrogatepass")
                h.update(len(raw).to_bytes(8, "little"))
                h.update(raw)
            n_bytes = int(np.prod(ds.shape, dtype=np.int64)) * dtype.itemsize
            h.update(n_bytes.to_bytes(8, "little"))
            if ds.shape == ():
                h.update(np.asarray(ds[()], dtype=dtype).tobytes())
            else:
                for start in range(0, ds.shape[0], _READ_ROWS):
                    h.update(np.ascontiguousarray(ds[start : start + _READ_ROWS]).tobytes())
            ds_attrs = attrs(ds)
            for attr in sorted(ds_attrs):
                _feed(h, b"a", p, attr, *_value_bytes(ds_attrs[attr]))
        for name in sorted(n for n in g if isinstance(g[n], h5py.Group)):
            p = f"{path.rstrip('/')}/{name}"
            _feed(h, b"G", p)
            walk(g[name], p)

    walk(f, "/")
    return "sha256:" + h.hexdigest()
