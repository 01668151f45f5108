"""What sweep and basin checkpoints share: the chunk bookkeeping of a store
(:class:`_ChunkedStore`), chunk writes with ``os.pwrite`` at the byte offsets the file's
layout gives (:class:`_ChunkWriter`), the chunk states, the size check of a new checkpoint
and its ``/checkpoint`` group.
"""

from __future__ import annotations

import math
import numbers
import os
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from walker.storage.checksums import _chunk_digest, _flag_chunk, _fletcher32
from walker.storage.decode import _dynamic_data, _load_checked, _Loaded
from walker.storage.disk import (
    _DISK_ERRNOS,
    _PERMANENT_ERRNOS,
    _atomic_write,
    _build_image,
    _check_space,
    _disk_error,
    _ram_bytes,
    _write_all,
)
from walker.storage.encode import _chunked_dataset, _provenance_attrs
from walker.storage.isolated import _check_path
from walker.storage.loader import _dynamic_fill, _first_line, _int_attr
from walker.storage.provenance import ENVIRONMENT_KEYS
from walker.storage.schema import (
    _CHECKPOINT_GROUP,
    _CHUNK_SHA,
    _RESULT_GROUP,
    SCHEMA_VERSION,
    WRITE_ATTEMPTS,
    CheckpointMismatch,
    StorageError,
)


def _unreadable(exc: StorageError, path: Path) -> CheckpointMismatch:
    """A StorageError of reading ``path`` as the CheckpointMismatch of resuming it."""
    text = str(exc)
    prefix = f"cannot read '{path}': "
    rest = text[len(prefix) :] if text.startswith(prefix) else text
    return CheckpointMismatch(
        f"cannot resume '{path}': {rest}",
        path=path,
        reason=f"is not a walker checkpoint ({rest})",
    )


def _file_identity(path: Path) -> tuple[int, int, int]:
    st = path.stat()
    return (st.st_dev, st.st_ino, st.st_size)


class _ChunkWriter:
    """Writes checkpoint chunk ``i`` of an existing file without HDF5: the rows of every
    dataset written chunk by chunk, then (version 2) the chunk's SHA-256, then its done
    flag, each with ``os.pwrite`` at the byte offset of its HDF5 chunk (version 2: the data
    followed by its Fletcher-32 checksum) or of its rows in the contiguous dataset
    (version 1).  No HDF5 metadata is ever written, so no lock is taken, a reader may have
    the file open, and a kill leaves every other byte as it was."""

    def __init__(self, path: Path, root: dict, kind: str, version: int) -> None:
        k = root["groups"][_CHECKPOINT_GROUP]
        self.path = path
        self.kind = kind
        self.version = version
        self.cs = _int_attr(k["attrs"], "chunk_size", f"/{_CHECKPOINT_GROUP}", minimum=1)
        self.data = [(p, a.dtype, a.shape) for p, a in _dynamic_data(root, kind)]
        self.n_rows = self.data[0][2][0]
        self.layout = root["extra"]["layout"]
        self.identity = _file_identity(path)

    def pieces(self, i: int, arrays: dict[str, np.ndarray]) -> list[tuple[int, bytes]]:
        rows = slice(i * self.cs, min((i + 1) * self.cs, self.n_rows))
        chunk_rows = min(self.cs, self.n_rows)
        out = []
        hashed = []
        for p, dtype, shape in self.data:
            arr = np.ascontiguousarray(arrays[p], dtype=dtype)
            hashed.append((p, arr))
            if arr.itemsize * math.prod(shape[1:]) == 0:
                continue
            if self.version < 2:
                row_bytes = arr.itemsize * math.prod(shape[1:])
                out.append((int(self.layout[p][0]) + rows.start * row_bytes, arr.tobytes()))
                continue
            if arr.shape[0] < chunk_rows:  # the last chunk: HDF5 stores a whole chunk
                fill = _dynamic_fill(self.kind, p, dtype)
                pad = np.full((chunk_rows - arr.shape[0], *shape[1:]), fill, dtype=dtype)
                arr = np.concatenate([arr, pad])
            body = arr.tobytes()
            out.append((int(self.layout[p][i]), body + _fletcher32(body).to_bytes(4, "little")))
        done = f"/{_CHECKPOINT_GROUP}/done"
        if self.version < 2:
            out.append((int(self.layout[done][0]) + i, b"\x01"))
            return out
        sha = _chunk_digest(i, hashed)
        sha_path = f"/{_CHECKPOINT_GROUP}/{_CHUNK_SHA}"
        out.append((int(self.layout[sha_path][i]), sha + _fletcher32(sha).to_bytes(4, "little")))
        out.append((int(self.layout[done][i]), _flag_chunk(True)))
        return out

    def write(self, i: int, arrays: dict[str, np.ndarray], fsync: bool) -> None:
        pieces = self.pieces(i, arrays)
        for attempt in range(WRITE_ATTEMPTS):
            try:
                self._write_pieces(pieces, fsync)
                return
            except OSError as exc:
                last = attempt == WRITE_ATTEMPTS - 1
                if exc.errno in _PERMANENT_ERRNOS or last:
                    if exc.errno in _DISK_ERRNOS:
                        raise _disk_error(exc, self.path, f"cannot write chunk {i} to") from None
                    tries = "" if exc.errno in _PERMANENT_ERRNOS else f" after {attempt + 1} tries"
                    raise StorageError(
                        f"cannot write chunk {i} to '{self.path}'{tries}: {_first_line(exc)}"
                    ) from None
                time.sleep(0.05 * 4**attempt)

    def _write_pieces(self, pieces: list[tuple[int, bytes]], fsync: bool) -> None:
        fd = os.open(self.path, os.O_WRONLY | getattr(os, "O_CLOEXEC", 0))
        try:
            st = os.fstat(fd)
            if (st.st_dev, st.st_ino, st.st_size) != self.identity:
                raise StorageError(
                    f"cannot write to '{self.path}': the file was replaced or changed size "
                    "since it was opened as a checkpoint"
                )
            for offset, data in pieces:  # rows, then the chunk's checksum, then its flag
                _write_all(fd, data, offset)
            if fsync:
                os.fsync(fd)
        finally:
            os.close(fd)


class _ChunkedStore:
    """The chunks of a checkpointed store (:class:`~walker.storage.SweepStore`,
    :class:`~walker.storage.BasinStore`): ``n_rows`` rows (sweep points, basin grid rows) cut
    into ``n_chunks`` chunks of ``chunk_size`` consecutive rows, the last one shorter; which
    are done is read from the file at ``path``."""

    KIND: str
    """The kind of result the file holds (``"sweep"``, ``"basin"``)."""
    DATACLASS: str
    """The name of its result dataclass."""

    def __init__(self, path: Path, n_rows: int, chunk_size: int, fsync: bool) -> None:
        self.path = path
        self.chunk_size = int(chunk_size)
        self.fsync = fsync
        self._n_rows = int(n_rows)
        self.n_chunks = -(-self._n_rows // self.chunk_size)
        self._writer: _ChunkWriter | None = None

    @staticmethod
    def _refused(path: Path, reason: str, advice: str) -> CheckpointMismatch:
        """The CheckpointMismatch of resuming ``path``, which ``reason`` (what it holds or
        checkpoints) refuses; ``advice`` says what to do instead."""
        return CheckpointMismatch(
            f"cannot resume '{path}': it {reason}; {advice}", path=path, reason=reason
        )

    @staticmethod
    def _store_path(path: Any) -> Path:
        """The ``path`` argument of a store's ``create_or_open``, checked, as a Path."""
        if not isinstance(path, str | os.PathLike):
            raise TypeError(f"`path` must be a str or os.PathLike, got {type(path).__name__}")
        return Path(path)

    @staticmethod
    def _check_directory(path: Path) -> None:
        """A new checkpoint at ``path`` needs its directory."""
        parent = path.parent if str(path.parent) else Path(".")
        if not parent.is_dir():
            raise FileNotFoundError(f"directory '{parent}' of `path` '{path}' does not exist")

    @staticmethod
    def _load_checkpoint(path: Path) -> _Loaded:
        """``path`` read in a child process, every checksum verified, to be resumed; a file
        that cannot be read is a CheckpointMismatch."""
        try:
            return _load_checked(path, isolate=True)
        except StorageError as exc:
            raise _unreadable(exc, path) from None

    @staticmethod
    def _provenance_diffs(stored: dict, wanted: dict) -> list[str]:
        """What a checkpoint's stored provenance JSON differs in from the caller's (a list of
        one line, or empty)."""
        if stored == wanted:
            return []
        keys = sorted(
            k
            for k in set(stored) | set(wanted)
            if stored.get(k) != wanted.get(k) and k not in ENVIRONMENT_KEYS
        )
        if not keys:
            return []
        return [f"provenance differs in {keys}"]

    def _resume(self, loaded: _Loaded) -> None:
        """Write the chunks to the existing file ``loaded`` was read from."""
        self._writer = _ChunkWriter(self.path, loaded.root, self.KIND, loaded.version)

    def _write_new(
        self,
        provenance_json: dict,
        sizes: tuple[int, int],
        fill_result: Callable[[h5py.Group], None],
        checkpoint_attrs: dict[str, Any],
        overwrite: bool,
    ) -> None:
        """Create the file, atomically: the root attributes of ``provenance_json``, the
        result group (filled by ``fill_result``), then ``/checkpoint`` with
        ``checkpoint_attrs``; ``sizes`` are the bytes of the file and of a chunk (checked
        first)."""
        root_attrs = _provenance_attrs(provenance_json, self.KIND)
        _check_checkpoint_size(self.path, *sizes)

        def fill(f: h5py.File) -> None:
            f.attrs.update(root_attrs)
            g = f.create_group(_RESULT_GROUP)
            g.attrs["dataclass"] = self.DATACLASS
            fill_result(g)
            k = _checkpoint_group(f, self.chunk_size, self.n_chunks)
            k.attrs.update(checkpoint_attrs)

        image, tree = _build_image(fill)
        _atomic_write(self.path, image, overwrite=overwrite)
        self._writer = _ChunkWriter(self.path, tree, self.KIND, SCHEMA_VERSION)

    def _check_chunk(self, i: Any) -> int:
        if isinstance(i, bool) or not isinstance(i, numbers.Integral):
            raise TypeError(f"chunk index `i` must be an int, got {i!r}")
        if not 0 <= i < self.n_chunks:
            raise ValueError(f"chunk index `i` must be in [0, {self.n_chunks}), got {i}")
        return int(i)

    def chunk_slice(self, i: int) -> slice:
        """Rows of chunk ``i``: ``slice(i * chunk_size, min((i + 1) * chunk_size, n_rows))``."""
        i = self._check_chunk(i)
        return slice(i * self.chunk_size, min((i + 1) * self.chunk_size, self._n_rows))

    @property
    def done(self) -> np.ndarray:
        """ndarray of bool, shape (n_chunks,): which chunks are stored (read from the file;
        a chunk whose checksum fails is not done)."""
        return _checkpoint_state(self.path) == 1

    def pending_chunks(self) -> list[int]:
        """Indices of the chunks not yet written, ascending."""
        return [int(i) for i in np.flatnonzero(~self.done)]

    @property
    def complete(self) -> bool:
        """True when every chunk is written."""
        return bool(np.all(self.done))


def _checkpoint_state(path: Path) -> np.ndarray:
    """State of each chunk of a checkpoint (0 pending, 1 done, 2 damaged), read here."""
    loaded = _load_checked(_check_path(path), isolate=False)
    if loaded.state is None:
        raise StorageError(f"cannot read '{path}': not a checkpoint")
    return loaded.state


def checkpoint_progress(path: str | os.PathLike, *, verify: bool = True) -> tuple[int, int] | None:
    """``(chunks done, chunks)`` of a sweep or basin checkpoint file, or None when ``path``
    is not one (missing, unreadable, or a result written by :func:`write`).

    Parameters
    ----------
    path : str or os.PathLike
    verify : bool
        read the whole file and check every checksum: a chunk whose checksum fails does not
        count as done.  False reads only the bookkeeping (``/checkpoint``'s chunk count and
        done flags), in time independent of the rows, falling back to the full check only
        when those cannot be read: what the command line's message after an interrupt uses
        (a full check of a 1e6-point checkpoint took 28-55 s).
    """
    if not verify:
        fast = _done_flags(path)
        if fast is not None:
            return fast  # else (a flag that cannot be read, ...) the full check decides
    try:
        state = _checkpoint_state(Path(path))
    except (StorageError, OSError, TypeError):
        return None
    return int(np.sum(state == 1)), int(state.size)


def _done_flags(path: Any) -> tuple[int, int] | None:
    """``(done flags set, chunks)`` read from ``/checkpoint`` alone, or None."""
    try:
        path = _check_path(path)
        file_size = path.stat().st_size
        with h5py.File(path, "r", locking=False) as f:
            if f.attrs.get("kind") not in ("sweep", "basin"):
                return None
            k = f.get(_CHECKPOINT_GROUP, getlink=True)
            if not isinstance(k, h5py.HardLink):
                return None
            n_chunks = int(f[_CHECKPOINT_GROUP].attrs["n_chunks"])
            done = f.get(f"{_CHECKPOINT_GROUP}/done", getlink=True)
            if not isinstance(done, h5py.HardLink):
                return None
            done = f[f"{_CHECKPOINT_GROUP}/done"]
            if (
                not 1 <= n_chunks <= file_size
                or not isinstance(done, h5py.Dataset)
                or done.shape != (n_chunks,)
                or done.dtype != np.bool_
            ):
                return None
            flags = done[...]
    except Exception:  # noqa: BLE001 - a file that is not a readable checkpoint
        return None
    return int(np.count_nonzero(flags)), n_chunks


def _check_checkpoint_size(path: Path, n_bytes: int, chunk_bytes: int) -> None:
    """A new checkpoint of about ``n_bytes`` must fit in memory (it is built there) and on
    the disk (it is built in memory first: about twice its size), and each chunk within
    HDF5's 4 GiB per chunk."""
    if chunk_bytes + 4 >= 1 << 32:
        raise ValueError(
            f"`chunk_size` gives chunks of {chunk_bytes} bytes, more than HDF5's 4 GiB limit "
            "per chunk; use a smaller chunk_size"
        )
    limit = int(0.4 * _ram_bytes())
    if n_bytes > limit:
        raise StorageError(
            f"cannot create '{path}': the checkpoint would take {n_bytes} bytes, more than "
            f"the {limit} bytes it may use in memory while it is created"
        )
    parent = path.parent if str(path.parent) else Path(".")
    _check_space(parent, n_bytes, path)


def _checkpoint_group(f: h5py.File, chunk_size: int, n_chunks: int) -> h5py.Group:
    """``/checkpoint``: chunk size and count, a done flag and a SHA-256 per chunk (each in
    its own HDF5 chunk, so that setting one is one small write)."""
    k = f.create_group(_CHECKPOINT_GROUP)
    k.attrs["chunk_size"] = np.int64(chunk_size)
    k.attrs["n_chunks"] = np.int64(n_chunks)
    _chunked_dataset(k, "done", (n_chunks,), 1, bool, False)
    _chunked_dataset(k, _CHUNK_SHA, (n_chunks, 32), 1, np.uint8, 0)
    return k
