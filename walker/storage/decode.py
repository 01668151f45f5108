"""Reading a result: the tree decoded in pure Python into its dataclass, with the types,
shapes and checksums checked, and :func:`read`.
"""

from __future__ import annotations

import dataclasses
import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from walker.status import Status
from walker.storage.checksums import _chunk_digest, _content_digest, _has_checkpoint
from walker.storage.isolated import _check_path, _load_tree
from walker.storage.loader import _first_line, _header_kind, _int_attr
from walker.storage.provenance import _check_provenance_types, _from_json
from walker.storage.schema import (
    _CHECKPOINT_GROUP,
    _CHECKSUM_ATTR,
    _CHUNK_SHA,
    _INT_RANGES,
    _RESULT_GROUP,
    _SPECS,
    KINDS,
    StorageError,
    _Corrupt,
    _shape_problem,
)


def _node_attr(node: dict, name: str, where: str) -> Any:
    if name not in node["attrs"]:
        raise _Corrupt(f"attribute '{name}' missing in '{where}'")
    return node["attrs"][name]


def _str_attr(node: dict, name: str, where: str) -> str:
    value = _node_attr(node, name, where)
    if not isinstance(value, str):
        raise _Corrupt(f"attribute '{name}' of '{where}' must be a str, got {value!r:.40}")
    return value


def _scalar_attr(node: dict, name: str, where: str, kinds: str, what: str) -> Any:
    value = _node_attr(node, name, where)
    if not (isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in kinds):
        raise _Corrupt(f"attribute '{name}' of '{where}' must be {what}, got {value!r:.40}")
    return value.item()


def _json_attr(node: dict, name: str, where: str) -> Any:
    text = _str_attr(node, name, where)
    try:
        return json.loads(text)
    except RecursionError:
        raise _Corrupt(f"attribute '{name}' of '{where}' is JSON nested too deeply") from None
    except ValueError as exc:
        raise _Corrupt(f"attribute '{name}' of '{where}' is not valid JSON ({exc})") from None


def _names_attr(node: dict, name: str, where: str) -> tuple[str, ...]:
    value = _json_attr(node, name, where)
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise _Corrupt(f"attribute '{name}' of '{where}' must be a JSON list of str")
    return tuple(value)


def _dataset(node: dict, name: str, where: str) -> np.ndarray:
    arr = node["datasets"].get(name)
    if not isinstance(arr, np.ndarray):
        raise _Corrupt(f"dataset '{where.rstrip('/')}/{name}' missing")
    return arr


def _subgroup(node: dict, name: str, where: str) -> dict:
    if name not in node["groups"]:
        raise _Corrupt(f"group '{where.rstrip('/')}/{name}' missing")
    return node["groups"][name]


def _decode(node: dict, cls: type, where: str) -> Any:
    stored = _str_attr(node, "dataclass", where)
    if stored != cls.__name__:
        raise _Corrupt(f"'{where}' holds a {stored!r:.40}, expected a {cls.__name__}")
    values = {name: _decode_field(node, name, codec, where) for name, codec in _SPECS[cls].items()}
    for name, (low, high) in _INT_RANGES.get(cls, {}).items():
        if not low <= values[name] <= high:
            raise _Corrupt(
                f"attribute '{name}' of '{where}' is {values[name]}, outside [{low}, {high}]"
            )
    problem = _shape_problem(cls, values)
    if problem is not None:
        raise _Corrupt(f"'{where.rstrip('/')}/{problem[0]}' {problem[1]}")
    return cls(**values)


def _decode_field(node: dict, name: str, codec: Any, where: str) -> Any:
    sub_where = f"{where.rstrip('/')}/{name}"
    if isinstance(codec, tuple):
        how, sub = codec
        if name not in node["groups"]:
            if how == "optional_group":
                return None
            raise _Corrupt(f"group '{sub_where}' missing")
        if how in ("group", "optional_group"):
            return _decode(node["groups"][name], sub, sub_where)
        items = node["groups"][name]
        n = _scalar_attr(items, "length", sub_where, "iu", "an int")
        if not 0 <= n <= len(items["groups"]):
            raise _Corrupt(f"'{sub_where}' says length {n} but holds {len(items['groups'])}")
        return [
            _decode(_subgroup(items, str(i), sub_where), sub, f"{sub_where}/{i}") for i in range(n)
        ]
    if codec == "optional_array":
        return _dataset(node, name, where) if name in node["datasets"] else None
    if codec == "array":
        return _dataset(node, name, where)
    if codec == "optional_array_dict" and name not in node["groups"]:
        return {}
    if codec in ("array_dict", "optional_array_dict"):
        sub = _subgroup(node, name, where)
        keys = _names_attr(sub, "names", sub_where)
        if len(set(keys)) != len(keys):
            raise _Corrupt(f"attribute 'names' of '{sub_where}' repeats a name")
        return {key: _dataset(sub, key, sub_where) for key in keys}
    if codec == "float":
        return float(_scalar_attr(node, name, where, "fiu", "a real number"))
    if codec == "int":
        return int(_scalar_attr(node, name, where, "iu", "an int"))
    if codec == "bool":
        return bool(_scalar_attr(node, name, where, "b", "a bool"))
    if codec == "str":
        return _str_attr(node, name, where)
    if codec == "status":
        value = _str_attr(node, name, where)
        if value not in Status.__members__:
            raise _Corrupt(f"unknown status {value!r:.40} in '{where}'")
        return Status[value]
    if codec == "names":
        return _names_attr(node, name, where)
    if codec == "optional_json" and name not in node["attrs"]:
        return {}
    if codec in ("json", "optional_json"):
        value = _from_json(_json_attr(node, name, where), f"{sub_where}")
        if not isinstance(value, dict):
            raise _Corrupt(f"attribute '{name}' of '{where}' must be a JSON object")
        return value
    raise RuntimeError(f"unknown codec {codec!r}")  # pragma: no cover


@dataclasses.dataclass
class _Loaded:
    """A file as read: its kind, version, provenance (decoded, and as stored JSON), the
    result, the tree, and for a checkpoint the state of each chunk (0 pending, 1 done and
    verified, 2 damaged)."""

    path: Path
    kind: str
    version: int
    provenance: dict[str, Any]
    provenance_json: dict[str, Any]
    result: Any
    root: dict
    state: np.ndarray | None


def _decode_file(path: Path, root: dict) -> _Loaded:
    attrs = root["attrs"]
    version, kind = _header_kind(attrs, path)
    prov_json = _json_attr(root, "provenance", "/")
    if not isinstance(prov_json, dict):
        raise _Corrupt(f"the provenance must be a JSON object, got {type(prov_json).__name__}")
    provenance = _from_json(prov_json)
    _check_provenance_types(provenance)
    provenance.update(
        walker_version=_str_attr(root, "walker_version", "/"),
        schema_version=version,
        kind=kind,
        created=_str_attr(root, "created", "/"),
    )
    result = _decode(_subgroup(root, _RESULT_GROUP, "/"), KINDS[kind], f"/{_RESULT_GROUP}")
    if version >= 2:
        stored = _str_attr(root, _CHECKSUM_ATTR, "/")
        if stored != _content_digest(root):
            raise _Corrupt(
                "the content does not match the root 'checksum' attribute (a damaged or "
                "edited file)"
            )
    state = root["extra"].get("state")
    if _has_checkpoint(root) and kind in ("sweep", "basin"):
        if state is None:
            raise _Corrupt("a checkpoint without its chunk state")
        state = state.copy()
        if version >= 2:
            _verify_chunks(root, kind, state)
    else:
        state = None
    return _Loaded(path, kind, version, provenance, prov_json, result, root, state)


def _dynamic_data(root: dict, kind: str) -> list[tuple[str, np.ndarray]]:
    """(path, array) of the datasets a checkpoint writes chunk by chunk, sorted by path."""
    g = root["groups"][_RESULT_GROUP]
    if kind == "sweep":
        cols = g["groups"].get("columns", {"datasets": {}})["datasets"]
        out = [(f"/{_RESULT_GROUP}/columns/{n}", a) for n, a in cols.items()]
    else:
        out = [(f"/{_RESULT_GROUP}/{n}", g["datasets"][n]) for n in ("outcome", "strides")]
    return sorted(out)


def _verify_chunks(root: dict, kind: str, state: np.ndarray) -> None:
    """Mark damaged (2) each done chunk whose rows do not have the stored SHA-256."""
    k = root["groups"][_CHECKPOINT_GROUP]
    cs = _int_attr(k["attrs"], "chunk_size", f"/{_CHECKPOINT_GROUP}", minimum=1)
    sha = k["datasets"][_CHUNK_SHA]
    data = _dynamic_data(root, kind)
    for i in np.flatnonzero(state == 1).tolist():
        rows = slice(i * cs, (i + 1) * cs)
        digest = _chunk_digest(i, [(p, a[rows]) for p, a in data])
        if sha[i].tobytes() != digest:
            state[i] = 2


def _load_checked(
    path: Path, *, isolate: bool, timeout: float | None = None, memory: int | None = None
) -> _Loaded:
    root = _load_tree(path, isolate=isolate, timeout=timeout, memory=memory)
    try:
        return _decode_file(path, root)
    except StorageError:
        raise
    except (_Corrupt, KeyError, TypeError, ValueError, RecursionError) as exc:
        reason = _first_line(exc)
        if not isinstance(exc, _Corrupt):
            reason = f"{type(exc).__name__}: {reason}"
        raise StorageError(f"cannot read '{path}': corrupted or incomplete ({reason})") from None


def read(
    path: str | os.PathLike,
    *,
    isolate: bool = True,
    timeout: float | None = None,
    memory: int | None = None,
) -> tuple[Any, dict[str, Any]]:
    """Read a result written by :func:`write` (or a :class:`SweepStore` or
    :class:`BasinStore` file, also while it is being written).

    Parameters
    ----------
    path : str or os.PathLike
    isolate : bool
        open the file in a child process (forked when this process runs one thread, about
        10 ms; else a new interpreter, about 0.25 s), so that a crash or a hang of the HDF5
        library on a damaged file is a :class:`StorageError`.  Pass False only for a file
        this process wrote itself.
    timeout : float, optional
        seconds the child may take [s]; default :data:`READ_TIMEOUT` plus one per 50 MB.
    memory : int, optional
        bytes the read may use: the data a file declares are refused beyond it (before
        anything is read), and the child's address space is limited to it; default 4x the
        file size, at least 2 GiB, at most 80% of the RAM.

    Returns
    -------
    result : dataclass
        equal, field by field, to what was written.  For a checkpoint, the rows of chunks
        not yet done hold the fill values (NaN, -1, False; ``BASIN_NOT_COMPUTED`` for a
        basin's outcome).
    provenance : dict
        the caller's provenance plus ``walker_version``, ``schema_version``, ``kind`` and
        ``created`` (UTC, ISO 8601).

    Raises
    ------
    StorageError
        the file is missing, not HDF5, truncated or corrupted (a checksum fails, a field
        has the wrong type or shape, HDF5 crashed or hung on it), from a newer schema, of an
        unknown kind, uses an HDF5 feature walker never writes, declares more data than it
        can hold or than ``memory``, or a checkpoint chunk marked done fails its checksum;
        the one-line message names the file and the object.
    TypeError
        ``path`` is not a str or os.PathLike.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import numpy as np
    >>> from walker.results import MapResult
    >>> from walker.status import Status
    >>> from walker.storage import write
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "map.h5"
    >>> _ = write(path, MapResult(Status.COMPLETED, np.ones(2), None, 1.5, np.ones(4)),
    ...           provenance={"model": "compass"})
    >>> result, prov = read(path)
    >>> result.step_time, prov["model"], prov["schema_version"]
    (1.5, 'compass', 2)
    """
    path = _check_path(path)
    try:
        loaded = _load_checked(path, isolate=bool(isolate), timeout=timeout, memory=memory)
    except StorageError as exc:
        raise exc from None  # one line, no chained traceback
    if loaded.state is not None and (loaded.state == 2).any():
        bad = np.flatnonzero(loaded.state == 2)
        raise StorageError(
            f"cannot read '{path}': checkpoint chunk {int(bad[0])} fails its checksum "
            f"({bad.size} damaged chunk(s)); resuming the {loaded.kind} recomputes them"
        )
    return loaded.result, loaded.provenance
