"""Loading an open HDF5 file into a plain tree, checking it on the way (links, layouts,
filters, declared sizes, the memory budget): every HDF5 call of a read happens here.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from walker.storage.blocks import _STREAM_BLOCK, _Pending, _selections
from walker.storage.checksums import _DONE_FALSE, _DONE_TRUE, _is_dynamic
from walker.storage.schema import (
    _CHECKPOINT_GROUP,
    _CHECKSUM_ATTR,
    _CHUNK_SHA,
    BASIN_NOT_COMPUTED,
    KINDS,
    MAX_COMPRESSION_RATIO,
    MAX_DECOMPRESSED_BYTES,
    SCHEMA_VERSION,
    StorageError,
    _Corrupt,
)

_MAX_OBJECTS = 100_000
MAX_CHUNK_BYTES = 4 << 20
"""Largest chunk [bytes] of a dataset smaller than its chunk (a streamed ``walker run``'s
resizable datasets end inside their last chunk of 4096 rows)."""
_MAX_DEPTH = 16
_MAX_ATTR_BYTES = 64 << 20


class _Opaque:
    """An attribute value of a type walker never writes (kept only to be checksummed)."""

    def __init__(self, what: str) -> None:
        self.what = str(what)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, _Opaque) and other.what == self.what

    def __repr__(self) -> str:
        return f"<{self.what}>"


_ALLOWED_FILTERS = {
    h5py.h5z.FILTER_FLETCHER32: "fletcher32",
    h5py.h5z.FILTER_DEFLATE: "deflate",
    h5py.h5z.FILTER_SHUFFLE: "shuffle",
}


def _refused(path: Path, what: str) -> StorageError:
    return StorageError(f"cannot read '{path}': {what}, which walker never writes; refused")


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


def _read_failure(exc: BaseException, fletcher_only: bool) -> str:
    """How a dataset read failed.  With Fletcher-32 as its only filter, a filter failure
    is a checksum mismatch (HDF5 reports only "filter returned failure")."""
    reason = _first_line(exc)
    lower = reason.lower()
    if "checksum" in lower or "fletcher" in lower or (fletcher_only and "filter" in lower):
        return f"fails its Fletcher-32 checksum ({reason})"
    return f"cannot be read ({reason})"


class _Loader:
    """Reads an open walker file into a plain tree, checking it on the way.

    The tree is ``{"attrs": {name: value}, "datasets": {name: ndarray}, "groups": {name:
    tree}, "dataset_attrs": {name: {attr: value}}}`` with str, numeric ndarray (0-d for a
    scalar) or :class:`_Opaque` attribute values; the root also has ``"extra"``: for a
    checkpoint, ``"state"`` (int8 per chunk: 0 pending, 1 done, 2 damaged) and ``"layout"``
    (byte offset of each chunk of each dataset written chunk by chunk).

    Before any data is read: links other than hard links, a second link to an object,
    committed datatypes, virtual datasets, external raw storage, filters other than
    Fletcher-32/deflate/shuffle and non-numeric dtypes are refused; every dataset's declared
    size is compared with what its storage can hold (the file size; for deflate, at most
    :data:`MAX_COMPRESSION_RATIO` times the stored size and :data:`MAX_DECOMPRESSED_BYTES`
    for the file), its chunks with its shape, and the total with the memory ``budget``.

    With ``stream=True`` every dataset becomes a :class:`_Pending`, read in blocks while the
    caller sends the tree on (the isolated reader's child): the checks above all happen
    first, and the load itself holds no dataset whole.  The root's chunk ``state`` is then a
    :class:`_Pending` too, complete once the checkpoint's datasets before it were sent.
    """

    def __init__(
        self,
        f: h5py.File,
        path: Path,
        file_size: int | None,
        budget: int | None,
        raw: Any = None,
        lazy: bool = False,
        stream: bool = False,
    ):
        self.f = f
        self.raw = raw  # raw(offset, size) -> bytes of the file
        self.lazy = lazy  # pending rows as read-only broadcasts (for a file being created)
        self.stream = stream  # datasets as _Pending, read as the tree is sent (the child)
        self.path = path
        self.file_size = file_size
        self.budget = budget
        self.spent = 0
        self.decompressed = 0  # declared bytes of the compressed datasets read so far
        self.n_objects = 0
        self.seen: set[Any] = set()
        self.deferred: dict[str, h5py.Dataset] = {}
        self.version = SCHEMA_VERSION

    # -- structure ----------------------------------------------------------------------

    def run(self) -> dict:
        f = self.f
        attrs = self.attrs(f, "/")
        version, kind = _header_kind(attrs, self.path)
        if version < 2 and _CHECKSUM_ATTR in attrs:
            raise self.downgraded("the root attribute 'checksum'")
        link = f.get(_CHECKPOINT_GROUP, getlink=True)
        self.version = version
        self.kind = kind
        self.has_checkpoint = isinstance(link, h5py.HardLink)
        self.seen.add(self.identity(f))
        root = self.group(f, "/", 0, attrs)
        root["extra"] = {}
        if self.deferred:
            self.checkpoint(root, version)
        return root

    def identity(self, obj: Any) -> Any:
        info = h5py.h5o.get_info(obj.id)
        token = getattr(info, "token", None)
        return (obj.id.fileno, token if token is not None else info.addr)

    def group(self, g: h5py.Group, path: str, depth: int, attrs: dict | None = None) -> dict:
        if depth > _MAX_DEPTH:
            raise _Corrupt(f"groups nested deeper than {_MAX_DEPTH} levels at '{path}'")
        node: dict[str, Any] = {
            "attrs": self.attrs(g, path) if attrs is None else attrs,
            "datasets": {},
            "groups": {},
            "dataset_attrs": {},
        }
        for name in g:
            p = f"{path.rstrip('/')}/{name}"
            link = g.get(name, getlink=True)
            if isinstance(link, h5py.SoftLink):
                raise _refused(self.path, f"'{p}' is a soft link (to '{link.path}')")
            if isinstance(link, h5py.ExternalLink):
                raise _refused(
                    self.path, f"'{p}' is an external link (to '{link.filename}:{link.path}')"
                )
            if not isinstance(link, h5py.HardLink):
                raise _refused(self.path, f"'{p}' is a {type(link).__name__}")
            self.n_objects += 1
            if self.n_objects > _MAX_OBJECTS:
                raise _Corrupt(f"more than {_MAX_OBJECTS} objects")
            obj = g[name]
            key = self.identity(obj)
            if key in self.seen:
                raise _refused(self.path, f"'{p}' is a second link to an object already read")
            self.seen.add(key)
            if isinstance(obj, h5py.Group):
                node["groups"][name] = self.group(obj, p, depth + 1)
            elif isinstance(obj, h5py.Dataset):
                self.check_dataset(obj, p)
                ds_attrs = self.attrs(obj, p)
                if ds_attrs:
                    node["dataset_attrs"][name] = ds_attrs
                if _is_dynamic(self.kind, self.has_checkpoint, p):
                    self.deferred[p] = obj
                    node["datasets"][name] = None  # read chunk by chunk in checkpoint()
                elif self.stream:
                    node["datasets"][name] = _Pending(
                        obj.dtype, obj.shape, functools.partial(self.blocks, obj, p)
                    )
                else:
                    node["datasets"][name] = self.read(obj, p)
            else:
                raise _refused(self.path, f"'{p}' is a {type(obj).__name__}")
        return node

    def spend(self, n_bytes: int, what: str) -> None:
        self.spent += n_bytes
        if self.budget is not None and self.spent > self.budget:
            raise StorageError(
                f"cannot read '{self.path}': {what} brings the declared data to "
                f"{self.spent} bytes, more than the read budget of {self.budget} bytes; refused"
            )

    def attrs(self, obj: Any, path: str) -> dict[str, Any]:
        out: dict[str, Any] = {}
        names = list(obj.attrs)
        if len(names) > 10_000:
            raise _Corrupt(f"'{path}' has {len(names)} attributes")
        for name in names:
            aid = h5py.h5a.open(obj.id, name.encode("utf-8", "surrogateescape"))
            shape = aid.shape or ()
            n_bytes = math.prod(shape) * max(aid.dtype.itemsize, 1)
            if n_bytes > _MAX_ATTR_BYTES or (
                self.file_size is not None and n_bytes > self.file_size + (1 << 16)
            ):
                raise StorageError(
                    f"cannot read '{self.path}': attribute '{name}' of '{path}' declares "
                    f"{n_bytes} bytes in a file of {self.file_size} bytes; refused"
                )
            self.spend(n_bytes, f"attribute '{name}' of '{path}'")
            out[name] = _attr_value(obj.attrs[name])
        return out

    def check_dataset(self, ds: h5py.Dataset, path: str) -> None:
        dcpl = ds.id.get_create_plist()
        layout = dcpl.get_layout()
        if layout == h5py.h5d.VIRTUAL or ds.is_virtual:
            raise _refused(self.path, f"dataset '{path}' is a virtual dataset")
        if dcpl.get_external_count():
            target = dcpl.get_external(0)[0]
            raise _refused(
                self.path,
                f"dataset '{path}' keeps its data in an external file ({target!r:.80})",
            )
        codes = []
        for j in range(dcpl.get_nfilters()):
            code = dcpl.get_filter(j)[0]
            if code not in _ALLOWED_FILTERS:
                raise _refused(self.path, f"dataset '{path}' uses the HDF5 filter {code}")
            codes.append(code)
        if self.version < 2 and (
            h5py.h5z.FILTER_FLETCHER32 in codes or path == f"/{_CHECKPOINT_GROUP}/{_CHUNK_SHA}"
        ):
            raise self.downgraded(f"the checksums of dataset '{path}'")
        dtype = ds.dtype
        if dtype.kind not in "biufc" or dtype.fields is not None or dtype.itemsize > 16:
            raise _refused(self.path, f"dataset '{path}' has the type {dtype}")
        shape = ds.shape
        if shape is None or len(shape) > 32:
            raise _Corrupt(f"dataset '{path}' has no valid shape")
        n_bytes = math.prod(shape) * dtype.itemsize
        if n_bytes == 0:
            return
        size = self.file_size
        if layout == h5py.h5d.COMPACT:
            limit = 1 << 16
        elif layout == h5py.h5d.CONTIGUOUS:
            offset = ds.id.get_offset()
            if offset is None:
                raise StorageError(
                    f"cannot read '{self.path}': dataset '{path}' declares {n_bytes} bytes but "
                    "stores none"
                )
            limit = n_bytes if size is None or offset + n_bytes <= size else -1
        elif layout == h5py.h5d.CHUNKED:
            chunks = ds.chunks
            if (
                chunks is None
                or len(chunks) != len(shape)
                or math.prod(chunks) * dtype.itemsize > max(n_bytes, MAX_CHUNK_BYTES)
            ):
                # HDF5 decompresses whole chunks: a chunk larger than the dataset would
                # allocate more than the declared size.  walker's own chunks are at most the
                # dataset, or at most MAX_CHUNK_BYTES in a streamed run's resizable datasets.
                raise StorageError(
                    f"cannot read '{self.path}': dataset '{path}' of shape {shape} is stored "
                    f"in chunks of {chunks}, larger than the dataset and than "
                    f"{MAX_CHUNK_BYTES} bytes; refused"
                )
            stored = ds.id.get_storage_size()
            if size is not None and stored > size:
                limit = -1
            elif h5py.h5z.FILTER_DEFLATE in codes:
                self.check_compressed(path, n_bytes, stored)
                self.check_inflated_chunks(ds, path, codes)
                limit = n_bytes
            else:
                limit = stored
        else:
            raise _refused(self.path, f"dataset '{path}' has the storage layout {layout}")
        if n_bytes > limit:
            raise StorageError(
                f"cannot read '{self.path}': dataset '{path}' declares {n_bytes} bytes (shape "
                f"{shape}, {dtype}), more than its storage in a file of {size} bytes can hold; "
                "refused"
            )
        self.spend(n_bytes, f"dataset '{path}'")

    def downgraded(self, feature: str) -> StorageError:
        """A file that says schema version 1 (read without the checksums) but carries
        ``feature`` of version 2: an edited version-2 file passing as unchecked."""
        return StorageError(
            f"cannot read '{self.path}': it says schema_version 1 but carries {feature}, "
            "which only version 2 writes (an edited file downgraded to skip the checksums?); "
            "refused"
        )

    def check_compressed(self, path: str, n_bytes: int, stored: int) -> None:
        """Refuse a compressed dataset declaring ``n_bytes`` from ``stored`` bytes whose
        expansion is above :data:`MAX_COMPRESSION_RATIO`, or that brings the file's
        compressed data above :data:`MAX_DECOMPRESSED_BYTES`: before decompressing it."""
        if n_bytes > stored * MAX_COMPRESSION_RATIO:
            raise StorageError(
                f"cannot read '{self.path}': dataset '{path}' declares {n_bytes} bytes "
                f"compressed into {stored}, an expansion above the cap of "
                f"{MAX_COMPRESSION_RATIO}:1 (a decompression bomb?); refused"
            )
        self.decompressed += n_bytes
        if self.decompressed > MAX_DECOMPRESSED_BYTES:
            raise StorageError(
                f"cannot read '{self.path}': dataset '{path}' brings the file's compressed "
                f"data to {self.decompressed} bytes decompressed, above the cap of "
                f"{MAX_DECOMPRESSED_BYTES} bytes; refused"
            )

    def check_inflated_chunks(self, ds: h5py.Dataset, path: str, codes: list[int]) -> None:
        """Inflate each stored chunk of a deflated dataset here, at most one byte beyond
        its size, and refuse one whose stream expands further: HDF5's deflate filter
        grows its output buffer until the stream ends, so a 1 MB stream in a chunk of 320
        bytes made it allocate 1 GiB (the dataset's declared size bounds nothing there).
        Memory: one chunk, compressed and inflated."""
        import zlib

        where = codes.index(h5py.h5z.FILTER_DEFLATE)
        after = codes[where + 1 :]
        if any(code != h5py.h5z.FILTER_FLETCHER32 for code in after):
            raise _refused(self.path, f"dataset '{path}' applies filters after deflate")
        chunk_bytes = math.prod(ds.chunks) * ds.dtype.itemsize
        for i in range(ds.id.get_num_chunks()):
            info = ds.id.get_chunk_info(i)
            if info.byte_offset is None or info.size > chunk_bytes + chunk_bytes // 100 + 1024:
                raise StorageError(
                    f"cannot read '{self.path}': dataset '{path}' stores {info.size} bytes for "
                    f"a chunk of {chunk_bytes}, more than deflate makes of it; refused"
                )
            mask, raw = ds.id.read_direct_chunk(info.chunk_offset)
            if mask & (1 << where):
                continue  # stored without deflate (HDF5 keeps a chunk raw when it is smaller)
            if after and not mask & (1 << (where + 1)):
                raw = raw[:-4]  # the Fletcher-32 of the compressed stream
            try:
                inflated = zlib.decompressobj().decompress(raw, chunk_bytes + 1)
            except zlib.error as exc:
                raise StorageError(
                    f"cannot read '{self.path}': dataset '{path}' has a chunk that is not "
                    f"deflate data ({exc}); refused"
                ) from None
            if len(inflated) > chunk_bytes:
                raise StorageError(
                    f"cannot read '{self.path}': dataset '{path}' has a chunk whose deflate "
                    f"stream expands beyond the chunk's {chunk_bytes} bytes (a decompression "
                    "bomb?); refused"
                )

    def read(self, ds: h5py.Dataset, path: str, sel: Any = ()) -> np.ndarray:
        try:
            data = ds[sel]
        except OSError as exc:
            dcpl = ds.id.get_create_plist()
            filters = [dcpl.get_filter(j)[0] for j in range(dcpl.get_nfilters())]
            fletcher_only = filters == [h5py.h5z.FILTER_FLETCHER32]
            raise StorageError(
                f"cannot read '{self.path}': dataset '{path}' {_read_failure(exc, fletcher_only)}"
            ) from None
        out = np.asarray(data, dtype=ds.dtype)
        return out.reshape(ds.shape) if sel == () else out

    def blocks(self, ds: h5py.Dataset, path: str) -> Any:
        """The dataset's data in blocks of at most about :data:`_STREAM_BLOCK` bytes."""
        if math.prod(ds.shape) == 0:
            return
        for sel in _selections(ds.shape, ds.dtype.itemsize):
            yield self.read(ds, path, sel)

    # -- checkpoints --------------------------------------------------------------------

    def checkpoint(self, root: dict, version: int) -> None:
        """Read the datasets written chunk by chunk: the done flags, the chunk checksums, and
        the rows of the chunks marked done (the others hold the fill value, whatever the file
        has there: a chunk being written, or killed mid-write, is pending).  A chunk whose
        flag, checksum or rows cannot be read is damaged (state 2)."""
        k = root["groups"][_CHECKPOINT_GROUP]
        cs = _int_attr(k["attrs"], "chunk_size", f"/{_CHECKPOINT_GROUP}", minimum=1)
        n_chunks = _int_attr(k["attrs"], "n_chunks", f"/{_CHECKPOINT_GROUP}", minimum=1)
        done_path = f"/{_CHECKPOINT_GROUP}/done"
        sha_path = f"/{_CHECKPOINT_GROUP}/{_CHUNK_SHA}"
        data = sorted(p for p in self.deferred if not p.startswith(f"/{_CHECKPOINT_GROUP}/"))
        if not data:
            raise _Corrupt("a checkpoint without datasets written chunk by chunk")
        rows = {self.deferred[p].shape[0] if self.deferred[p].ndim else -1 for p in data}
        n_rows = rows.pop()
        if rows or n_rows < 1:
            raise _Corrupt(f"the datasets of the checkpoint do not have the same rows: {data}")
        if n_chunks != -(-n_rows // cs):
            raise _Corrupt(
                f"'/{_CHECKPOINT_GROUP}' says {n_chunks} chunks for {n_rows} rows in chunks of {cs}"
            )
        want_paths = [done_path] + ([sha_path] if version >= 2 else [])
        for p, shape, dtype in ((done_path, (n_chunks,), "b"), (sha_path, (n_chunks, 32), "u")):
            if p not in want_paths:
                continue
            ds = self.deferred.get(p)
            if ds is None or ds.shape != shape or ds.dtype.kind != dtype:
                raise _Corrupt(f"dataset '{p}' missing, or not of shape {shape}")
        extra = set(self.deferred) - set(data) - set(want_paths)
        if extra:
            raise _Corrupt(f"unexpected datasets {sorted(extra)} in '/{_CHECKPOINT_GROUP}'")
        if version >= 2:
            layout = self.layout(version, cs, n_rows, data, want_paths)
            state = self.raw_chunks(root, layout, cs, n_chunks, data)
        else:
            state, done = self.done_flags(done_path, n_chunks)
            self.put(root, done_path, done)
            self.done_rows(root, data, cs, n_chunks, state)
            layout = self.layout(version, cs, n_rows, data, want_paths)
        root["extra"]["state"] = (
            _Pending(state.dtype, state.shape, lambda: iter((state,))) if self.stream else state
        )
        root["extra"]["layout"] = layout

    def raw_chunks(
        self, root: dict, layout: dict, cs: int, n_chunks: int, data: list[str]
    ) -> np.ndarray:
        """Version 2: the done flags are read as raw bytes at their offsets in ``layout``
        (a damaged chunk index must not turn a done flag into a missing chunk, which HDF5
        reads as the fill value False: the chunk would silently read as pending); the
        checksums and rows of the done chunks through HDF5 (Fletcher-32 checked there; a
        chunk found at the wrong place fails its SHA-256 later).  Returns the chunk states."""
        done_path = f"/{_CHECKPOINT_GROUP}/done"
        sha_path = f"/{_CHECKPOINT_GROUP}/{_CHUNK_SHA}"
        if self.raw is None:  # a file being created, in memory: read through HDF5
            state, _ = self.done_flags(done_path, n_chunks)
        else:
            state = np.zeros(n_chunks, dtype=np.int8)
            flags = self.raw_rows(layout[done_path], 5, np.arange(n_chunks))
            is_true = (flags == _DONE_TRUE).all(axis=1)
            state[is_true] = 1
            state[~(is_true | (flags == _DONE_FALSE).all(axis=1))] = 2
        self.put(root, done_path, state == 1)
        sha, bad = self.chunk_rows(sha_path, 1, n_chunks, np.flatnonzero(state == 1))
        state[bad] = 2
        self.put(root, sha_path, sha)
        self.done_rows(root, data, cs, n_chunks, state)
        return state

    def done_flags(self, done_path: str, n_chunks: int) -> tuple[np.ndarray, np.ndarray]:
        """The done flags read through HDF5, and the chunk states they give: 1 done, 0
        pending, 2 a flag that could not be read."""
        state = np.zeros(n_chunks, dtype=np.int8)
        done, bad = self.chunk_rows(done_path, 1, n_chunks, np.arange(n_chunks))
        state[done.astype(bool)] = 1
        state[bad] = 2
        return state, done

    def done_rows(self, root: dict, data: list[str], cs: int, n_chunks: int, state) -> None:
        """The rows of the done chunks of each data path into ``root``; a chunk whose rows
        cannot be read becomes 2 in ``state``."""
        for p in data:
            if self.stream:
                ds = self.deferred[p]
                blocks = functools.partial(self.chunk_blocks, p, cs, n_chunks, state)
                self.put(root, p, _Pending(ds.dtype, ds.shape, blocks))
                continue
            values, bad = self.chunk_rows(p, cs, n_chunks, np.flatnonzero(state == 1))
            state[bad] = 2
            self.put(root, p, values)

    def chunk_blocks(self, path: str, cs: int, n_chunks: int, state: np.ndarray) -> Any:
        """:meth:`chunk_rows` in blocks of whole chunks of at most about
        :data:`_STREAM_BLOCK` bytes (or one chunk): the rows of the chunks whose ``state``
        is 1, the fill value elsewhere; a chunk whose rows cannot be read becomes 2."""
        ds = self.deferred[path]
        fill = _dynamic_fill(self.kind, path, ds.dtype)
        n_rows = ds.shape[0]
        row_bytes = max(math.prod(ds.shape[1:]) * ds.dtype.itemsize, 1)
        per = max(_STREAM_BLOCK // (row_bytes * cs), 1)  # chunks per block
        for c0 in range(0, n_chunks, per):
            rows = slice(c0 * cs, min((c0 + per) * cs, n_rows))
            done = np.flatnonzero(state[c0 : c0 + per] == 1)
            block = None
            if done.size:
                try:
                    block = self.read(ds, path, rows)
                except StorageError:
                    pass  # some chunk cannot be read: chunk by chunk
            if block is not None:
                block[~np.isin(np.arange(block.shape[0]) // cs, done)] = fill
                yield block
                continue
            block = np.full((rows.stop - rows.start, *ds.shape[1:]), fill, dtype=ds.dtype)
            for j in done.tolist():
                c = c0 + j
                try:
                    block[j * cs : (j + 1) * cs] = self.read(
                        ds, path, slice(c * cs, min((c + 1) * cs, n_rows))
                    )
                except StorageError:
                    state[c] = 2
            yield block

    def raw_rows(self, offsets: np.ndarray, size: int, wanted: np.ndarray) -> np.ndarray:
        """uint8 array (len(wanted), size): the bytes at ``offsets[wanted]``."""
        out = np.zeros((wanted.size, size), dtype=np.uint8)
        for j, i in enumerate(wanted.tolist()):
            piece = self.raw(int(offsets[i]), size)
            out[j, : len(piece)] = np.frombuffer(piece, dtype=np.uint8)
        return out

    def put(self, root: dict, path: str, values: np.ndarray) -> None:
        node = root
        parts = path.strip("/").split("/")
        for part in parts[:-1]:
            node = node["groups"][part]
        node["datasets"][parts[-1]] = values

    def chunk_rows(
        self, path: str, rows_per_chunk: int, n_chunks: int, wanted: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """The dataset with the rows of the ``wanted`` chunks read and every other row set to
        the fill value; and which wanted chunks could not be read."""
        ds = self.deferred[path]
        fill = _dynamic_fill(self.kind, path, ds.dtype)
        if self.lazy and wanted.size == 0:  # a new checkpoint: no copy of its fill in memory
            return np.broadcast_to(np.array(fill, dtype=ds.dtype), ds.shape), np.zeros(
                n_chunks, dtype=bool
            )
        bad = np.zeros(n_chunks, dtype=bool)
        if wanted.size and math.prod(ds.shape):
            try:
                out = self.read(ds, path)  # read into its own array: no second copy
            except StorageError:
                pass  # some chunk cannot be read (perhaps one being written): chunk by chunk
            else:
                out[~np.isin(np.arange(ds.shape[0]) // rows_per_chunk, wanted)] = fill
                return out, bad
        out = np.full(ds.shape, fill, dtype=ds.dtype)
        if wanted.size == 0 or out.size == 0:
            return out, bad
        for i in wanted.tolist():
            rows = slice(i * rows_per_chunk, min((i + 1) * rows_per_chunk, ds.shape[0]))
            try:
                out[rows] = self.read(ds, path, rows)
            except StorageError:
                bad[i] = True
        return out, bad

    def layout(
        self, version: int, cs: int, n_rows: int, data: list[str], flags: list[str]
    ) -> dict[str, np.ndarray]:
        """Byte offset in the file of each chunk of each dataset written chunk by chunk
        (version 2: one HDF5 chunk per checkpoint chunk, checked here; version 1: the offset
        of the contiguous dataset).  No two may overlap."""
        out: dict[str, np.ndarray] = {}
        spans = []
        for p in data + flags:
            ds = self.deferred[p]
            row_bytes = math.prod(ds.shape[1:]) * ds.dtype.itemsize
            if row_bytes == 0:
                continue
            dcpl = ds.id.get_create_plist()
            if version < 2:
                offset = ds.id.get_offset()
                if dcpl.get_layout() != h5py.h5d.CONTIGUOUS or offset is None:
                    raise _Corrupt(f"dataset '{p}' is not contiguous and allocated")
                out[p] = np.array([offset], dtype=np.int64)
                spans.append((offset, offset + ds.shape[0] * row_bytes, p))
                continue
            per_chunk = 1 if p in flags else cs
            chunk_rows = min(per_chunk, ds.shape[0])
            n = -(-ds.shape[0] // chunk_rows)
            filters = [dcpl.get_filter(j)[0] for j in range(dcpl.get_nfilters())]
            if ds.chunks != (chunk_rows, *ds.shape[1:]) or filters != [h5py.h5z.FILTER_FLETCHER32]:
                raise _Corrupt(
                    f"dataset '{p}' is not stored in chunks of {chunk_rows} rows with only the "
                    "Fletcher-32 filter"
                )
            size = chunk_rows * row_bytes + 4
            infos: list[Any] = []
            ds.id.chunk_iter(infos.append)
            offsets = np.full(n, -1, dtype=np.int64)
            for info in infos[: n + 1]:
                first = info.chunk_offset
                i = first[0] // chunk_rows
                if (
                    len(infos) != n
                    or first[0] % chunk_rows
                    or any(first[1:])
                    or not 0 <= i < n
                    or offsets[i] >= 0
                    or info.filter_mask
                    or info.size != size
                    or info.byte_offset is None
                ):
                    raise _Corrupt(f"dataset '{p}' does not have one allocated chunk per row block")
                offsets[i] = info.byte_offset
                spans.append((info.byte_offset, info.byte_offset + size, p))
            if (offsets < 0).any():
                raise _Corrupt(f"dataset '{p}' does not have one allocated chunk per row block")
            out[p] = offsets
        spans.sort()
        for (_, end, p), (start, _, q) in zip(spans, spans[1:], strict=False):
            if start < end:
                raise _Corrupt(f"chunks of '{p}' and '{q}' overlap in the file")
        if self.file_size is not None and spans and spans[-1][1] > self.file_size:
            raise _Corrupt(f"chunks of '{spans[-1][2]}' lie beyond the end of the file")
        return out


def _attr_value(value: Any) -> Any:
    """An attribute value as the tree holds it: str, numeric ndarray or _Opaque."""
    if isinstance(value, str):
        return value
    if isinstance(value, bytes):
        try:
            return value.decode("utf-8")
        except UnicodeDecodeError:
            return _Opaque("bytes")
    if isinstance(value, np.ndarray | np.generic):
        arr = np.asarray(value)
        if arr.dtype.kind in "biufc" and arr.dtype.fields is None:
            return np.array(arr)
        if arr.ndim == 0 and arr.dtype.kind == "O" and isinstance(arr.item(), str):
            return arr.item()
        return _Opaque(f"array of {arr.dtype}")
    return _Opaque(type(value).__name__)


def _dynamic_fill(kind: Any, path: str, dtype: np.dtype) -> Any:
    """What a row of a checkpoint dataset holds until its chunk is written."""
    if path.endswith("/done"):
        return False
    if path.endswith(_CHUNK_SHA):
        return 0
    if kind == "basin" and path.endswith("/outcome"):
        return BASIN_NOT_COMPUTED
    return _fill_value(np.dtype(dtype))


def _fill_value(dtype: np.dtype) -> Any:
    if dtype.kind == "f":
        return dtype.type(np.nan)
    if dtype.kind == "c":
        return dtype.type(complex(np.nan, np.nan))
    if dtype.kind in "iu":
        return dtype.type(-1) if dtype.kind == "i" else dtype.type(0)
    return np.False_  # bool


def _int_attr(attrs: dict, name: str, where: str, minimum: int | None = None) -> int:
    value = attrs.get(name)
    if not (isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iu"):
        raise _Corrupt(f"attribute '{name}' of '{where}' missing or not an integer")
    value = int(value)
    if minimum is not None and value < minimum:
        raise _Corrupt(f"attribute '{name}' of '{where}' is {value} < {minimum}")
    return value


def _header_kind(attrs: dict, path: Path) -> tuple[int, str]:
    """Schema version and kind from the root attributes (StorageError when not a walker
    file, newer, or of an unknown kind)."""
    if "schema_version" not in attrs or "kind" not in attrs:
        raise StorageError(
            f"cannot read '{path}': not a walker result file (no 'schema_version'/'kind' "
            "root attribute)"
        )
    try:
        version = _int_attr(attrs, "schema_version", "/", minimum=1)
    except _Corrupt as exc:
        raise StorageError(f"cannot read '{path}': corrupted ({exc})") from None
    if version > SCHEMA_VERSION:
        raise StorageError(
            f"cannot read '{path}': schema_version {version} is newer than this walker's "
            f"{SCHEMA_VERSION}; upgrade walker"
        )
    kind = attrs["kind"]
    if not isinstance(kind, str) or kind not in KINDS:
        raise StorageError(
            f"cannot read '{path}': unknown result kind {kind!r:.60} (known: {', '.join(KINDS)})"
        )
    return version, kind
