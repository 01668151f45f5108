"""Checksums: HDF5's Fletcher-32 (for the checkpoint chunks written without HDF5), the root
``checksum`` (SHA-256 of a file's content as walker reads it) and the SHA-256 of each
checkpoint chunk.
"""

from __future__ import annotations

import hashlib
from typing import Any

import numpy as np

from walker.storage.schema import _CHECKPOINT_GROUP, _CHECKSUM_ATTR, _CHUNK_SHA, _RESULT_GROUP


def _fletcher32(data: bytes | memoryview) -> int:
    """HDF5's Fletcher-32 checksum of ``data`` (the filter ``H5Z_FILTER_FLETCHER32``).

    The 16-bit words are read big-endian, summed in blocks of 360 with the end-around carry
    of HDF5's ``H5_checksum_fletcher32``, a trailing odd byte counts as a high byte; the
    filter stores the result after the chunk's data, little-endian.  Checkpoint chunks are
    written with this (and ``os.pwrite``) instead of through HDF5; the tests compare it with
    the checksums HDF5 itself stores.
    """
    data = memoryview(data).cast("B")
    n_words = len(data) // 2
    words = np.frombuffer(data, dtype=">u2", count=n_words).astype(np.int64)
    sum1 = sum2 = 0
    n_blocks = n_words // 360
    if n_blocks:
        blocks = words[: n_blocks * 360].reshape(n_blocks, 360)
        totals = blocks.sum(axis=1).tolist()
        weighted = (blocks @ np.arange(360, 0, -1, dtype=np.int64)).tolist()
        for total, weight in zip(totals, weighted, strict=True):
            sum2 = (sum2 + 360 * sum1 + weight) & 0xFFFFFFFF  # C: uint32 arithmetic
            sum1 += total
            sum1 = (sum1 & 0xFFFF) + (sum1 >> 16)
            sum2 = (sum2 & 0xFFFF) + (sum2 >> 16)
    rest = words[n_blocks * 360 :]
    if rest.size:
        weight = int(rest @ np.arange(rest.size, 0, -1, dtype=np.int64))
        sum2 = (sum2 + rest.size * sum1 + weight) & 0xFFFFFFFF
        sum1 += int(rest.sum())
        sum1 = (sum1 & 0xFFFF) + (sum1 >> 16)
        sum2 = (sum2 & 0xFFFF) + (sum2 >> 16)
    if len(data) % 2:
        sum1 += data[-1] << 8
        sum2 = (sum2 + sum1) & 0xFFFFFFFF
        sum1 = (sum1 & 0xFFFF) + (sum1 >> 16)
        sum2 = (sum2 & 0xFFFF) + (sum2 >> 16)
    sum1 = (sum1 & 0xFFFF) + (sum1 >> 16)
    sum2 = (sum2 & 0xFFFF) + (sum2 >> 16)
    return (sum2 << 16) | sum1


def _flag_chunk(value: bool) -> bytes:
    """The stored bytes of one done flag: the bool and its Fletcher-32."""
    body = b"\x01" if value else b"\x00"
    return body + _fletcher32(body).to_bytes(4, "little")


_DONE_TRUE = np.frombuffer(_flag_chunk(True), dtype=np.uint8)
_DONE_FALSE = np.frombuffer(_flag_chunk(False), dtype=np.uint8)


def _is_dynamic(kind: Any, has_checkpoint: bool, path: str) -> bool:
    """Is ``path`` a dataset of a checkpoint that is written chunk by chunk after creation?
    (Those are covered chunk by chunk by ``/checkpoint/chunk_sha256``, not by ``checksum``.)"""
    if not has_checkpoint:
        return False
    if path in (f"/{_CHECKPOINT_GROUP}/done", f"/{_CHECKPOINT_GROUP}/{_CHUNK_SHA}"):
        return True
    if kind == "sweep":
        head, _, name = path.rpartition("/")
        return head == f"/{_RESULT_GROUP}/columns" and bool(name)
    if kind == "basin":
        return path in (f"/{_RESULT_GROUP}/outcome", f"/{_RESULT_GROUP}/strides")
    return False


def _has_checkpoint(root: dict) -> bool:
    return _CHECKPOINT_GROUP in root["groups"]


def _feed(h: Any, tag: bytes, *parts: bytes | str) -> None:
    """Length-prefixed items, so that no two different trees hash the same sequence."""
    h.update(tag)
    for part in parts:
        raw = part.encode("utf-8", "surrogatepass") if isinstance(part, str) else part
        h.update(len(raw).to_bytes(8, "little"))
        h.update(raw)


_HASH_BLOCK = 8 << 20  # bytes of an array hashed at a time [bytes]


def _feed_array(h: Any, tag: bytes, path: str, arr: np.ndarray) -> None:
    """:func:`_feed` of ``(path, dtype and shape, arr.tobytes())`` without the copy: the
    bytes (in C order) are hashed in blocks of rows of about ``_HASH_BLOCK`` bytes, so
    that verifying a large array takes no memory beyond it (a read-only broadcast array,
    a constant of any shape, takes none at all)."""
    arr = np.asarray(arr)
    _feed(h, tag, path, f"{arr.dtype.str}{arr.shape}")
    h.update(int(arr.nbytes).to_bytes(8, "little"))
    _hash_c_order(h, arr)


def _hash_c_order(h: Any, arr: np.ndarray) -> None:
    """``h.update(arr.tobytes())`` in blocks of at most about ``_HASH_BLOCK`` bytes."""
    if arr.ndim == 0 or arr.size == 0 or arr.nbytes <= _HASH_BLOCK:
        h.update(np.ascontiguousarray(arr).tobytes() if not arr.flags.c_contiguous else arr.data)
        return
    row_bytes = arr.nbytes // arr.shape[0]
    if row_bytes > _HASH_BLOCK and arr.ndim > 1:
        for row in arr:
            _hash_c_order(h, row)
        return
    step = max(_HASH_BLOCK // max(row_bytes, 1), 1)
    for start in range(0, arr.shape[0], step):
        block = np.ascontiguousarray(arr[start : start + step])  # a view when contiguous
        h.update(block.data)


def _value_bytes(value: Any) -> tuple[str, bytes]:
    if isinstance(value, str):
        return "s", value.encode("utf-8", "surrogatepass")
    if isinstance(value, np.ndarray):
        return f"a{value.dtype.str}{value.shape}", np.ascontiguousarray(value).tobytes()
    return "x", repr(value).encode()


def _content_digest(root: dict) -> str:
    """SHA-256 of everything a file holds as walker reads it: every group, attribute (name,
    type, value), dataset (name, dtype, shape and data) and, for a checkpoint, the byte
    offsets of the chunks written later; the data of those chunks and the root ``checksum``
    attribute itself are left out."""
    kind = root["attrs"].get("kind")
    has_checkpoint = _has_checkpoint(root)
    h = hashlib.sha256(b"walker file checksum 1\0")

    def walk(node: dict, path: str) -> None:
        for name in sorted(node["attrs"]):
            if path == "/" and name == _CHECKSUM_ATTR:
                continue
            _feed(h, b"A", path, name, *_value_bytes(node["attrs"][name]))
        for name in sorted(node["datasets"]):
            p = f"{path.rstrip('/')}/{name}"
            arr = node["datasets"][name]
            if _is_dynamic(kind, has_checkpoint, p):
                _feed(h, b"D", p, f"{arr.dtype.str}{arr.shape}", b"")
            else:
                _feed_array(h, b"D", p, arr)
            for attr in sorted(node.get("dataset_attrs", {}).get(name, {})):
                value = node["dataset_attrs"][name][attr]
                _feed(h, b"a", p, attr, *_value_bytes(value))
        for name in sorted(node["groups"]):
            p = f"{path.rstrip('/')}/{name}"
            _feed(h, b"G", p)
            walk(node["groups"][name], p)

    walk(root, "/")
    for p, offsets in sorted(root.get("extra", {}).get("layout", {}).items()):
        _feed(h, b"L", p, np.ascontiguousarray(offsets, dtype="<i8").tobytes())
    return "sha256:" + h.hexdigest()


def _chunk_digest(i: int, rows: list[tuple[str, np.ndarray]]) -> bytes:
    """SHA-256 of checkpoint chunk ``i``: its index and, for each dataset path in ``rows``,
    the path, dtype, shape and bytes of the chunk's rows."""
    h = hashlib.sha256(b"walker chunk checksum 1\0")
    h.update(int(i).to_bytes(8, "little"))
    for path, arr in rows:
        arr = np.ascontiguousarray(arr)
        _feed(h, b"R", path, f"{arr.dtype.str}{arr.shape}", arr.tobytes())
    return h.digest()
