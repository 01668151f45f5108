"""Writing a result: the dataclass encoded into a plain tree, the tree emitted into an HDF5
group, the root attributes from the provenance, and :func:`write`.
"""

from __future__ import annotations

import json
import math
import numbers
import os
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from walker.status import Status
from walker.storage.disk import _atomic_create, _check_target
from walker.storage.provenance import _check_provenance, _to_json, walker_version
from walker.storage.schema import (
    _INT_RANGES,
    _KIND_OF,
    _RESULT_GROUP,
    _SPECS,
    KINDS,
    SCHEMA_VERSION,
    _shape_problem,
)


def _new_tree() -> dict[str, dict]:
    return {"attrs": {}, "datasets": {}, "groups": {}}


def _check_name(name: Any, where: str) -> None:
    if not isinstance(name, str) or not name or "/" in name or name in (".", ".."):
        raise ValueError(f"`{where}` names must be non-empty str without '/', got {name!r}")


def _encode(obj: Any, cls: type, where: str) -> dict[str, dict]:
    if type(obj) is not cls:
        raise TypeError(f"`{where}` must be a {cls.__name__}, got {type(obj).__name__}")
    tree = _new_tree()
    tree["attrs"]["dataclass"] = cls.__name__
    for name, codec in _SPECS[cls].items():
        _encode_field(tree, name, getattr(obj, name), codec, f"{where}.{name}")
    for name, (low, high) in _INT_RANGES.get(cls, {}).items():
        if not low <= int(getattr(obj, name)) <= high:
            raise ValueError(
                f"`{where}.{name}` must be in [{low}, {high}] to be stored, got "
                f"{getattr(obj, name)!r}"
            )
    problem = _shape_problem(cls, {name: getattr(obj, name) for name in _SPECS[cls]})
    if problem is not None:
        raise ValueError(f"`{where}.{problem[0]}` {problem[1]}")
    return tree


def _encode_field(tree: dict, name: str, value: Any, codec: Any, where: str) -> None:
    attrs, datasets, groups = tree["attrs"], tree["datasets"], tree["groups"]
    if isinstance(codec, tuple):
        how, sub = codec
        if how == "optional_group":
            if value is not None:
                groups[name] = _encode(value, sub, where)
        elif how == "group":
            groups[name] = _encode(value, sub, where)
        else:  # group_list
            if not isinstance(value, list | tuple):
                raise TypeError(f"`{where}` must be a list, got {type(value).__name__}")
            items = _new_tree()
            items["attrs"]["length"] = np.int64(len(value))
            for i, item in enumerate(value):
                items["groups"][str(i)] = _encode(item, sub, f"{where}[{i}]")
            groups[name] = items
        return
    if codec == "optional_array" and value is None:
        return
    if codec in ("array", "optional_array"):
        if not isinstance(value, np.ndarray):
            raise TypeError(f"`{where}` must be an ndarray, got {type(value).__name__}")
        if value.dtype.kind not in "biufc":
            raise TypeError(f"`{where}` must have a numeric or bool dtype, got {value.dtype}")
        datasets[name] = value
    elif codec == "float":
        if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
            raise TypeError(f"`{where}` must be a real number, got {value!r}")
        attrs[name] = np.float64(value)
    elif codec == "int":
        if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Integral):
            raise TypeError(f"`{where}` must be an int, got {value!r}")
        attrs[name] = np.int64(value)
    elif codec == "bool":
        if not isinstance(value, bool | np.bool_):
            raise TypeError(f"`{where}` must be a bool, got {value!r}")
        attrs[name] = np.bool_(value)
    elif codec == "str":
        if not isinstance(value, str):
            raise TypeError(f"`{where}` must be a str, got {type(value).__name__}")
        attrs[name] = value
    elif codec == "status":
        if not isinstance(value, Status):
            raise TypeError(f"`{where}` must be a walker.status.Status, got {value!r}")
        attrs[name] = value.name
    elif codec == "names":
        if not isinstance(value, tuple | list) or not all(isinstance(v, str) for v in value):
            raise TypeError(f"`{where}` must be a tuple of str, got {value!r}")
        attrs[name] = json.dumps(list(value))
    elif codec in ("json", "optional_json"):
        if not isinstance(value, dict):
            raise TypeError(f"`{where}` must be a dict, got {type(value).__name__}")
        attrs[name] = json.dumps(_to_json(value, where))
    elif codec == "optional_array_dict" and isinstance(value, dict) and not value:
        pass
    elif codec in ("array_dict", "optional_array_dict"):
        if not isinstance(value, dict):
            raise TypeError(f"`{where}` must be a dict name -> ndarray, got {type(value).__name__}")
        sub = _new_tree()
        for key, arr in value.items():
            _check_name(key, where)
            _encode_field(sub, key, arr, "array", f"{where}[{key!r}]")
        sub["attrs"]["names"] = json.dumps(list(value))
        groups[name] = sub
    else:  # pragma: no cover - a typo in _SPECS
        raise RuntimeError(f"unknown codec {codec!r} for {where}")


def _dataset_options(shape: tuple[int, ...]) -> dict[str, Any]:
    """Storage of a dataset of ``shape``: chunked with the Fletcher-32 checksum, unless it
    holds no data (empty) or cannot be chunked (a scalar; its bytes are covered by the
    file's ``checksum`` attribute)."""
    if len(shape) == 0 or math.prod(shape) == 0:
        return {}
    return {"chunks": True, "fletcher32": True}


def _emit(tree: dict, group: h5py.Group) -> None:
    for name, value in tree["attrs"].items():
        group.attrs[name] = value
    for name, arr in tree["datasets"].items():
        group.create_dataset(name, data=arr, **_dataset_options(arr.shape))
    for name, sub in tree["groups"].items():
        _emit(sub, group.create_group(name))


def _chunked_dataset(
    group: h5py.Group, name: str, shape: tuple[int, ...], chunk_rows: int, dtype: Any, fill: Any
) -> None:
    """A checkpoint dataset filled chunk by chunk later: one HDF5 chunk of ``chunk_rows``
    rows per checkpoint chunk, each with its Fletcher-32 checksum, all allocated and filled
    with ``fill`` now, so that writing a chunk later overwrites bytes at a fixed offset."""
    if math.prod(shape) == 0:  # no bytes to check or to write
        group.create_dataset(name, shape=shape, dtype=dtype)
        return
    dcpl = h5py.h5p.create(h5py.h5p.DATASET_CREATE)
    dcpl.set_alloc_time(h5py.h5d.ALLOC_TIME_EARLY)
    group.create_dataset(
        name,
        shape=shape,
        dtype=dtype,
        chunks=(min(chunk_rows, shape[0]), *shape[1:]),
        fletcher32=True,
        fillvalue=fill,
        fill_time="alloc",
        dcpl=dcpl,
    )


def _provenance_attrs(provenance_json: dict, kind: str) -> dict[str, Any]:
    """Root attributes: automatic keys, the full provenance as JSON, readable copies."""
    attrs: dict[str, Any] = {
        "walker_version": walker_version(),
        "schema_version": np.int64(SCHEMA_VERSION),
        "kind": kind,
        "created": datetime.now(UTC).isoformat(timespec="microseconds"),
        "provenance": json.dumps(provenance_json),
    }
    # Readable copies for h5ls/h5dump users; read() uses only the "provenance" attribute.
    for key, value in provenance_json.items():
        if isinstance(value, str | bool | int | float):
            attrs[key] = value
        elif value is not None:
            attrs[key] = json.dumps(value)
    if "state_names" not in provenance_json:
        # a caller's provenance without them: the model's, as readable attributes only
        from walker.params.registry import STATE_NAMES, STATE_UNITS

        model = provenance_json.get("model")
        if isinstance(model, str) and model in STATE_NAMES:
            attrs["state_names"] = json.dumps(list(STATE_NAMES[model]))
            attrs["state_units"] = json.dumps(list(STATE_UNITS[model]))
    for name, entry in (provenance_json.get("parameters") or {}).items():
        if isinstance(entry["value"], int | float) and not isinstance(entry["value"], bool):
            attrs[f"parameters.{name}"] = entry["value"]
            attrs[f"parameters.{name}.unit"] = entry["unit"]
    return attrs


def write(
    path: str | os.PathLike, result: Any, *, provenance: dict, overwrite: bool = False
) -> Path:
    """Store one result and its provenance in a new HDF5 file, atomically.

    Parameters
    ----------
    path : str or os.PathLike
        target file; its directory must exist.
    result : Solution, FixedPoint, Branch, OrbitDiagram, BasinMap, SweepTable or MapResult
        the result; its kind (see :data:`KINDS`) is stored in the root attribute ``kind``.
        Its arrays must have the shapes its class documents (``Solution.record.x`` has
        ``len(x)`` columns, ...).
    provenance : dict
        what produced the result, e.g. ``scene``, ``model``, ``parameters`` (as
        ``{name: {"value": v, "unit": u}}``, see :func:`parameters_with_units`), ``method``,
        ``rtol``, ``atol``, ``status``, ``kernel_hash``.  Values may be None, str, bool,
        numbers, Status, lists, tuples, dicts and numeric arrays; it is stored as the JSON root
        attribute ``provenance`` and each top-level entry also as its own root attribute.  The
        keys ``walker_version``, ``schema_version``, ``kind``, ``created`` and ``checksum``
        are added here.
    overwrite : bool
        replace an existing file.

    Returns
    -------
    Path
        the written file.

    Raises
    ------
    FileNotFoundError
        the directory of `path` does not exist.
    FileExistsError
        `path` exists and `overwrite` is False.
    TypeError, ValueError
        `result` or `provenance` cannot be stored (the message names the field).
    StorageError
        the disk is full, over quota or read-only (no file is left behind).
    """
    kind = _KIND_OF.get(type(result))
    if kind is None:
        raise TypeError(
            f"`result` must be one of {', '.join(c.__name__ for c in KINDS.values())}, "
            f"got {type(result).__name__}"
        )
    prov_json = _check_provenance(provenance)
    path = _check_target(path, overwrite)
    tree = _encode(result, type(result), type(result).__name__)
    root_attrs = _provenance_attrs(prov_json, kind)

    def fill(f: h5py.File) -> None:
        f.attrs.update(root_attrs)
        _emit(tree, f.create_group(_RESULT_GROUP))

    return _atomic_create(path, fill, overwrite)
