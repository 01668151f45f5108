"""Datasets a streaming load has checked but not read (:class:`_Pending`), and the blocks
they are read in: the isolated reader's child sends a file's data on block by block, so that
it never holds a dataset whole.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

_STREAM_BLOCK = 8 << 20
"""Bytes of a dataset read from HDF5 at a time by a streaming load [bytes]."""


class _Pending:
    """A dataset a streaming load has checked but not read: its dtype and shape, and
    ``pieces()``, an iterator of arrays whose bytes, in turn, are the dataset's in C order,
    each of about :data:`_STREAM_BLOCK` bytes at most (read from the file as iterated)."""

    __slots__ = ("dtype", "pieces", "shape")

    def __init__(self, dtype: Any, shape: tuple, pieces: Any) -> None:
        self.dtype = np.dtype(dtype)
        self.shape = tuple(int(n) for n in shape)
        self.pieces = pieces


def _selections(shape: tuple, itemsize: int, prefix: tuple = ()) -> Any:
    """Index tuples that cut an array of ``shape`` into blocks of at most about
    :data:`_STREAM_BLOCK` bytes, in C order (a row larger than that is cut further)."""
    if not shape:
        yield prefix
        return
    row = math.prod(shape[1:]) * itemsize
    if row <= _STREAM_BLOCK or len(shape) == 1:
        step = max(_STREAM_BLOCK // max(row, 1), 1)
        for start in range(0, shape[0], step):
            yield (*prefix, slice(start, min(start + step, shape[0])))
        return
    for i in range(shape[0]):
        yield from _selections(shape[1:], itemsize, (*prefix, i))
