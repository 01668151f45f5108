"""HDF5 storage of results with provenance: atomic writes, checked reads, sweep checkpoints.

One file holds one result (one *kind*); :func:`write` stores it and :func:`read` gives back an
equal dataclass and the provenance.  The layout is described in ``docs/storage.md``
(schema version :data:`SCHEMA_VERSION`; files of version 1 are still read and resumed).

Rules this module keeps:

1. ``read(write(path, x, provenance=p)) == (x, p + automatic keys)`` field by field: arrays
   with their dtype and shape (empty arrays too), ``None`` fields, tuples of names,
   :class:`~walker.status.Status` members, dicts of parameters.
2. :func:`write` is atomic and survives the disk: the whole file is built in memory, the free
   space is checked, then it is written under a temporary name in the target directory
   (``.<name>.tmp-<pid>-<random>``) with plain ``os.write`` calls, fsynced and moved onto the
   target with one rename.  A failure at any point leaves no target and no temporary file; a
   full disk, a quota or a read-only file system is a :class:`StorageError` (one line).
   Temporary files of the same target whose writing process is gone are removed.  An
   existing target is never replaced unless ``overwrite=True``.
3. Invalid input raises before any file is touched (``TypeError``/``ValueError`` naming the
   field and the rule; ``FileNotFoundError`` for a missing directory; ``FileExistsError``).
4. Every stored number is checked: each non-empty dataset carries the HDF5 Fletcher-32
   checksum, the root attribute ``checksum`` is a SHA-256 of everything the file holds
   (attributes, names, dtypes, shapes, data), and each chunk of a checkpoint carries the
   SHA-256 of its rows.  Reading verifies all of them.
5. Reading trusts nothing: a file that is missing, not HDF5, truncated, corrupted, from a
   newer schema, of an unknown kind, that uses an HDF5 feature walker never writes (external
   storage or links, soft links, virtual datasets, foreign filters), declares more data than
   it can hold, or whose fields have the wrong types or shapes raises :class:`StorageError`
   (a ``ValueError``) with a one-line message naming the file and the object.  By default
   :func:`read` opens the file in a child process with a time and memory budget, so that a
   crash or a hang of the HDF5 library on a damaged file is a :class:`StorageError` too.
6. :class:`SweepStore` checkpoints a parameter sweep chunk by chunk, and :class:`BasinStore`
   a basin map rows by rows; see SweepStore's docstring for the guarantee both give when the
   process is killed (SIGKILL) or interrupted, and when a reader opens the file meanwhile.

Complex arrays (Floquet multipliers, eigenvectors) are stored as complex128 (or complex64)
datasets, which h5py writes as an HDF5 compound type with float members ``r`` and ``i``.

Examples
--------
>>> import tempfile, pathlib
>>> import numpy as np
>>> from walker.results import OrbitDiagram
>>> from walker.storage import read, write
>>> d = OrbitDiagram("slope", np.array([0.01, 0.02]), np.array([[0.2, 0.2], [0.3, 0.1]]))
>>> prov = {"model": "simplest", "method": "dop853", "rtol": 1e-10, "atol": 1e-12,
...         "parameters": {"slope": {"value": 0.01, "unit": "rad"}}}
>>> path = pathlib.Path(tempfile.mkdtemp()) / "orbit.h5"
>>> _ = write(path, d, provenance=prov)
>>> d2, p2 = read(path)
>>> bool(np.array_equal(d2.values, d.values)), p2["kind"], p2["rtol"]
(True, 'orbit_diagram', 1e-10)
"""

from __future__ import annotations

import dataclasses
import errno
import hashlib
import json
import math
import numbers
import os
import secrets
import select
import shutil
import signal
import subprocess
import sys
import threading
import time
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from walker.results import (
    BasinMap,
    Bifurcation,
    Branch,
    EventLog,
    FixedPoint,
    MapResult,
    OrbitDiagram,
    Solution,
    SweepTable,
    Trajectory,
)
from walker.status import Status

__all__ = [
    "BASIN_NOT_COMPUTED",
    "KINDS",
    "MAX_COMPRESSION_RATIO",
    "READ_TIMEOUT",
    "SCHEMA_VERSION",
    "WRITE_ATTEMPTS",
    "BasinStore",
    "CheckpointMismatch",
    "StorageError",
    "SweepStore",
    "check_writable",
    "checkpoint_progress",
    "parameters_with_units",
    "read",
    "walker_version",
    "write",
]

SCHEMA_VERSION = 2
"""Version of the file layout written by this module; files with a larger one are refused.
Version 2 added the checksums (Fletcher-32 on datasets, the root ``checksum`` attribute and
``/checkpoint/chunk_sha256``); version-1 files are still read and resumed, unchecked."""

AUTOMATIC_KEYS = ("walker_version", "schema_version", "kind", "created")
"""Provenance keys set by :func:`write` itself; a caller may not pass them."""

READ_TIMEOUT = 60.0
"""Seconds a checked read may take, plus one per 50 MB of file, before it is abandoned as
a hang (:func:`read` ``timeout``)."""

MAX_COMPRESSION_RATIO = 1032
"""Largest expansion of deflate (gzip) data; a compressed dataset declaring more bytes than
this times its stored size is refused before any of it is read."""

WRITE_ATTEMPTS = 4
"""Attempts of a checkpoint chunk write that fails with a transient error (backoff 0.05 s,
0.2 s, 0.8 s) before it is a :class:`StorageError`."""

_RESULT_GROUP = "result"
_CHECKPOINT_GROUP = "checkpoint"
_CHECKSUM_ATTR = "checksum"
_CHUNK_SHA = "chunk_sha256"
_RESERVED_ATTRS = frozenset(AUTOMATIC_KEYS) | {"provenance", _CHECKSUM_ATTR}
_MAX_OBJECTS = 100_000
_MAX_DEPTH = 16
_MAX_ATTR_BYTES = 64 << 20
_STALE_TEMP_AGE = 10.0  # seconds without modification before a dead writer's temp is removed
_DISK_ERRNOS = {
    errno.ENOSPC: "no space left on the device",
    errno.EDQUOT: "disk quota exceeded",
    errno.EROFS: "read-only file system",
    errno.EFBIG: "file too large for the file system or the process limit",
    errno.EIO: "input/output error",
}
_PERMANENT_ERRNOS = frozenset(_DISK_ERRNOS) - {errno.EIO} | {
    errno.EACCES,
    errno.EPERM,
    errno.ENOENT,
    errno.EBADF,
    errno.EISDIR,
    errno.ENOTDIR,
}


class StorageError(ValueError):
    """A file cannot be read as a walker result (missing, corrupted, newer schema, ...), or
    cannot be written (full disk, read-only file system, ...)."""


class CheckpointMismatch(StorageError):
    """An existing file cannot be resumed as the requested checkpoint: it holds another
    result, a different sweep or basin, or is corrupted.

    Attributes
    ----------
    path : Path
        the file.
    reason : str
        what is wrong, as a clause (``"checkpoints a different sweep (chunk_size 2 != 1)"``).
    """

    def __init__(self, message: str, *, path: Path, reason: str) -> None:
        super().__init__(message)
        self.path = path
        self.reason = reason


class _Corrupt(Exception):
    """Internal: the file's content does not follow the schema."""


# ---------------------------------------------------------------------------------------------
# Field codecs: how each field of each result dataclass is stored.
#
#   "array"           dataset, dtype and shape kept exactly
#   "optional_array"  dataset, absent when the field is None
#   "float" / "int" / "bool" / "str"   attribute
#   "status"          attribute holding the Status member's name ("COMPLETED")
#   "names"           attribute holding a JSON list of strings (read back as a tuple)
#   "json"            attribute holding a JSON object (dict of parameters)
#   "optional_json"   the same, absent in files written before the field existed (read as {})
#   ("group", cls) / ("optional_group", cls) / ("group_list", cls)   subgroups
#   "array_dict"      subgroup with one dataset per key, key order in attribute "names"
# ---------------------------------------------------------------------------------------------

_SPECS: dict[type, dict[str, Any]] = {
    EventLog: {
        "t": "array",
        "guard": "array",
        "phase_before": "array",
        "phase_after": "array",
        "x_pre": "array",
        "x_post": "array",
        "impulse": "array",
    },
    Trajectory: {"t": "array", "x": "array", "phase": "array"},
    Solution: {
        "status": "status",
        "message": "str",
        "success": "bool",
        "t": "float",
        "x": "array",
        "phase": "int",
        "n_steps": "int",
        "n_rejected": "int",
        "n_rhs": "int",
        "n_events": "int",
        "n_strides": "int",
        "events": ("optional_group", EventLog),
        "samples": ("optional_group", Trajectory),
        "record": ("optional_group", Trajectory),
        "jac": "optional_array",
        "dt_dx0": "optional_array",
        "error_estimate": "float",
        "phase_names": "names",
        "guard_names": "names",
        "conventions": "optional_json",
    },
    MapResult: {
        "status": "status",
        "z": "array",
        "jac": "optional_array",
        "step_time": "float",
        "state": "array",
    },
    FixedPoint: {
        "status": "status",
        "message": "str",
        "success": "bool",
        "section": "array",
        "state": "array",
        "step_time": "float",
        "multipliers": "array",
        "eigenvectors": "array",
        "jacobian": "array",
        "residual": "float",
        "n_iter": "int",
        "history": "array",
        "period": "int",
        "stable": "bool",
        "parameters": "json",
        "conventions": "optional_json",
    },
    Bifurcation: {
        "kind": "str",
        "parameter_value": "float",
        "section": "array",
        "multipliers": "array",
    },
    Branch: {
        "parameter_name": "str",
        "parameter": "array",
        "sections": "array",
        "step_times": "array",
        "multipliers": "array",
        "stable": "array",
        "bifurcations": ("group_list", Bifurcation),
        "status": "status",
        "message": "str",
        "success": "bool",
        "period": "int",
    },
    OrbitDiagram: {
        "parameter_name": "str",
        "parameter": "array",
        "values": "array",
        "coordinate": "int",
    },
    BasinMap: {
        "axis_names": "names",
        "x": "array",
        "y": "array",
        "outcome": "array",
        "strides": "array",
        "fixed_point": "array",
        "base": "array",
        "n_strides": "int",
    },
    SweepTable: {
        "parameter_names": "names",
        "points": "array",
        "columns": "array_dict",
    },
}

KINDS: dict[str, type] = {
    "solution": Solution,
    "fixed_point": FixedPoint,
    "branch": Branch,
    "orbit_diagram": OrbitDiagram,
    "basin": BasinMap,
    "sweep": SweepTable,
    "map_result": MapResult,
}
"""Result kinds a file can hold, and the dataclass of each."""

_KIND_OF = {cls: kind for kind, cls in KINDS.items()}


def _check_specs() -> None:
    """Every dataclass field must have a codec: a new field in results.py must not be dropped."""
    for cls, spec in _SPECS.items():
        names = [f.name for f in dataclasses.fields(cls)]
        if names != list(spec):
            raise RuntimeError(
                f"walker.storage has no schema for {cls.__name__} fields {names} "
                f"(it knows {list(spec)}); update _SPECS and docs/storage.md"
            )


_check_specs()


# ---------------------------------------------------------------------------------------------
# Provenance and small values as JSON
# ---------------------------------------------------------------------------------------------


def walker_version() -> str:
    """``walker.__version__`` if set, else the installed ``walker-hybrid`` version, else
    ``"unknown"``."""
    import walker

    version = getattr(walker, "__version__", None)
    if isinstance(version, str) and version:
        return version
    try:
        from importlib.metadata import PackageNotFoundError
        from importlib.metadata import version as dist_version

        return dist_version("walker-hybrid")
    except (ImportError, PackageNotFoundError):
        return "unknown"


def parameters_with_units(params: Any) -> dict[str, dict[str, Any]]:
    """Provenance ``parameters`` entry from a :mod:`walker.params` dataclass.

    Parameters
    ----------
    params : object with ``to_dict()`` (name -> value) and ``units()`` (name -> unit)
        e.g. ``CompassParams.goswami()``.

    Returns
    -------
    dict
        ``{name: {"value": value, "unit": unit}}`` in the parameters' canonical order.

    Examples
    --------
    >>> from walker.params import SimplestParams
    >>> parameters_with_units(SimplestParams.garcia())["slope"]["unit"]
    'rad'
    """
    if not (hasattr(params, "to_dict") and hasattr(params, "units")):
        raise TypeError(
            f"`params` must have `to_dict()` and `units()` (a walker.params dataclass), "
            f"got {type(params).__name__}"
        )
    values = params.to_dict()
    units = params.units()
    return {
        name: {"value": float(value), "unit": str(units[name])} for name, value in values.items()
    }


def _is_dunder(key: str) -> bool:
    return key.startswith("__") and key.endswith("__")


def _to_json(value: Any, where: str) -> Any:
    """JSON-ready form of ``value``; Status members, tuples and arrays are tagged."""
    if value is None or isinstance(value, str | bool):
        return value
    if isinstance(value, Status):
        return {"__status__": value.name}
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if isinstance(value, numbers.Complex):
        return {"__complex__": [float(value.real), float(value.imag)]}
    if isinstance(value, tuple):
        return {"__tuple__": [_to_json(v, f"{where}[{i}]") for i, v in enumerate(value)]}
    if isinstance(value, list):
        return [_to_json(v, f"{where}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in "biufc":
            raise TypeError(f"`{where}` must be a numeric array, got dtype {value.dtype}")
        arr = np.ascontiguousarray(value)
        flat = arr.view(arr.real.dtype) if arr.dtype.kind == "c" else arr
        return {
            "__ndarray__": {
                "dtype": arr.dtype.str,
                "shape": list(arr.shape),
                "data": flat.ravel().tolist(),
            }
        }
    if isinstance(value, dict):
        out = {}
        for key, v in value.items():
            if not isinstance(key, str):
                raise TypeError(f"keys of `{where}` must be str, got {key!r}")
            if _is_dunder(key):
                raise ValueError(f"keys of `{where}` must not look like '__x__', got {key!r}")
            out[key] = _to_json(v, f"{where}[{key!r}]")
        return out
    raise TypeError(
        f"`{where}` must be None, str, bool, a number, Status, list, tuple, dict or a numeric "
        f"ndarray, got {type(value).__name__}"
    )


def _is_real(value: Any) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool | np.bool_)


def _from_json(value: Any, where: str = "provenance") -> Any:
    """Inverse of :func:`_to_json` for a parsed JSON value; raises _Corrupt naming ``where``
    when a tagged object is malformed."""
    if isinstance(value, list):
        return [_from_json(v, f"{where}[{i}]") for i, v in enumerate(value)]
    if not isinstance(value, dict):
        return value
    tags = [key for key in value if _is_dunder(key)]
    if not tags:
        return {k: _from_json(v, f"{where}[{k!r}]") for k, v in value.items()}
    if len(value) != 1:
        raise _Corrupt(f"`{where}` mixes the tag {tags[0]!r} with other keys")
    ((tag, inner),) = value.items()
    if tag == "__status__":
        if not isinstance(inner, str) or inner not in Status.__members__:
            raise _Corrupt(f"`{where}` holds an unknown status {inner!r}")
        return Status[inner]
    if tag == "__tuple__":
        if not isinstance(inner, list):
            raise _Corrupt(f"`{where}`: '__tuple__' must hold a list, got {type(inner).__name__}")
        return tuple(_from_json(v, f"{where}[{i}]") for i, v in enumerate(inner))
    if tag == "__complex__":
        if not (isinstance(inner, list) and len(inner) == 2 and all(map(_is_real, inner))):
            raise _Corrupt(f"`{where}`: '__complex__' must hold [re, im], got {inner!r:.60}")
        return complex(inner[0], inner[1])
    if tag == "__ndarray__":
        return _ndarray_from_json(inner, where)
    raise _Corrupt(f"`{where}` holds an unknown tag {tag!r}")


def _ndarray_from_json(inner: Any, where: str) -> np.ndarray:
    if not isinstance(inner, dict) or set(inner) != {"dtype", "shape", "data"}:
        raise _Corrupt(f"`{where}`: '__ndarray__' must hold dtype, shape and data")
    try:
        dtype = np.dtype(inner["dtype"]) if isinstance(inner["dtype"], str) else None
    except TypeError:
        dtype = None
    if dtype is None or dtype.kind not in "biufc" or dtype.fields is not None:
        raise _Corrupt(f"`{where}`: '__ndarray__' has an invalid dtype {inner['dtype']!r:.40}")
    shape = inner["shape"]
    if not (
        isinstance(shape, list)
        and len(shape) <= 32
        and all(isinstance(s, int) and not isinstance(s, bool) and s >= 0 for s in shape)
    ):
        raise _Corrupt(f"`{where}`: '__ndarray__' has an invalid shape {shape!r:.40}")
    data = inner["data"]
    count = math.prod(shape) * (2 if dtype.kind == "c" else 1)
    if not isinstance(data, list) or len(data) != count:
        raise _Corrupt(f"`{where}`: '__ndarray__' data does not match its shape {shape}")
    if not all(isinstance(v, int | float) for v in data):  # bool is an int
        raise _Corrupt(f"`{where}`: '__ndarray__' data must be numbers")
    real = np.empty(0, dtype).real.dtype
    try:
        flat = np.array(data, dtype=real)
    except (OverflowError, ValueError, TypeError):
        raise _Corrupt(f"`{where}`: '__ndarray__' data do not fit {dtype}") from None
    if dtype.kind == "c":
        flat = flat.view(dtype)
    return flat.reshape(shape)


_PROVENANCE_RULES: dict[str, tuple[str, Any]] = {
    "scene": ("a str", lambda v: isinstance(v, str)),
    "model": ("a str", lambda v: isinstance(v, str)),
    "method": ("a str", lambda v: isinstance(v, str)),
    "kernel_hash": ("a str", lambda v: isinstance(v, str)),
    "sweep_kind": ("a str", lambda v: isinstance(v, str)),
    "rtol": ("a real number", _is_real),
    "atol": ("a real number", _is_real),
    "tol": ("a real number", _is_real),
    "t_max": ("a real number", _is_real),
    "first_step": ("a real number or null", lambda v: v is None or _is_real(v)),
    "n_strides": ("an int", lambda v: isinstance(v, int) and not isinstance(v, bool)),
    "status": ("a Status or a str", lambda v: isinstance(v, Status | str)),
    "z0": ("a list of real numbers", lambda v: isinstance(v, list) and all(map(_is_real, v))),
}
"""Provenance keys walker itself writes, and the type each must have when present."""


def _parameters_problem(parameters: Any) -> tuple[str | None, str] | None:
    """Why ``parameters`` is not ``{name: {"value": real, "unit": str}}``: (the entry's name
    or None for the whole, the rule), or None."""
    if not isinstance(parameters, dict):
        return None, (
            f"must be a dict name -> {{'value': v, 'unit': u}}, got {type(parameters).__name__}"
        )
    for name, entry in parameters.items():
        if (
            not isinstance(entry, dict)
            or set(entry) != {"value", "unit"}
            or not isinstance(entry["unit"], str)
            or not _is_real(entry["value"])
        ):
            return name, (
                "must be a dict with exactly the keys 'value' and 'unit' (a real number and a "
                f"str), got {entry!r:.80}"
            )
    return None


def _check_provenance(provenance: Any) -> dict[str, Any]:
    """Validate the caller's provenance and return its JSON-ready form."""
    if not isinstance(provenance, dict):
        raise TypeError(f"`provenance` must be a dict, got {type(provenance).__name__}")
    for key in provenance:
        if not isinstance(key, str):
            raise TypeError(f"keys of `provenance` must be str, got {key!r}")
        if key in _RESERVED_ATTRS or key.startswith("parameters."):
            raise ValueError(
                f"`provenance` must not set {key!r}: write() sets "
                f"{', '.join(AUTOMATIC_KEYS)} and {_CHECKSUM_ATTR!r} itself"
            )
    parameters = provenance.get("parameters")
    if parameters is not None:
        problem = _parameters_problem(parameters)
        if problem is not None:
            name, rule = problem
            if name is None:
                raise TypeError(f"`provenance['parameters']` {rule}")
            raise ValueError(f"`provenance['parameters'][{name!r}]` {rule}")
    prov_json = _to_json(provenance, "provenance")
    # What read() will check must hold now: a file walker writes always reads back.
    try:
        _check_provenance_types(_from_json(prov_json))
    except _Corrupt as exc:
        raise ValueError(str(exc)) from None
    return prov_json


def _check_provenance_types(provenance: dict[str, Any]) -> None:
    """Raise _Corrupt naming the first known provenance key with a wrong type."""
    for key, (rule, ok) in _PROVENANCE_RULES.items():
        if key in provenance and not ok(provenance[key]):
            raise _Corrupt(f"provenance key {key!r} must be {rule}, got {provenance[key]!r:.60}")
    if provenance.get("parameters") is not None:
        problem = _parameters_problem(provenance["parameters"])
        if problem is not None:
            name, rule = problem
            entry = "" if name is None else f" entry {name!r}"
            raise _Corrupt(f"provenance key 'parameters'{entry} {rule}")


# ---------------------------------------------------------------------------------------------
# Encoding a dataclass into a tree, then emitting the tree into an HDF5 group
# ---------------------------------------------------------------------------------------------


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
    elif codec == "array_dict":
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


def _shape_problem(cls: type, v: dict[str, Any]) -> tuple[str, str] | None:
    """The first field of a ``cls`` instance (field values ``v``, already of the right types)
    whose shape or dtype breaks the class's contract, as (field, rule), or None.  The rules
    are those of the class docstrings in :mod:`walker.results`."""

    def vector(name: str, n: int | None = None, kinds: str = "biufc") -> tuple[str, str] | None:
        a = v[name]
        if a.ndim != 1 or (n is not None and a.shape[0] != n):
            want = "1-D" if n is None else f"of shape ({n},)"
            return name, f"must be {want}, got shape {a.shape}"
        if a.dtype.kind not in kinds:
            return name, f"must have a dtype of kind {kinds!r}, got {a.dtype}"
        return None

    def matrix(name: str, rows: int | None = None, cols: int | None = None, kinds: str = "biufc"):
        a = v[name]
        if a is None:
            return None
        if a.ndim != 2 or (rows is not None and a.shape[0] != rows):
            want = "2-D" if rows is None else f"2-D with {rows} rows"
            return name, f"must be {want}, got shape {a.shape}"
        if cols is not None and a.shape[1] != cols:
            return name, f"must have {cols} columns, got shape {a.shape}"
        if a.dtype.kind not in kinds:
            return name, f"must have a dtype of kind {kinds!r}, got {a.dtype}"
        return None

    def first(*checks: Any) -> tuple[str, str] | None:
        for check in checks:
            problem = check()
            if problem is not None:
                return problem
        return None

    if cls is EventLog:
        if v["t"].ndim != 1:
            return "t", f"must be 1-D, got shape {v['t'].shape}"
        n = v["t"].shape[0]
        return first(
            *(lambda k=k: vector(k, n, "iu") for k in ("guard", "phase_before", "phase_after")),
            lambda: matrix("x_pre", n),
            lambda: matrix("x_post", n, v["x_pre"].shape[1]),
            lambda: matrix("impulse", n),
        )
    if cls is Trajectory:
        if v["t"].ndim != 1:
            return "t", f"must be 1-D, got shape {v['t'].shape}"
        n = v["t"].shape[0]
        return first(lambda: matrix("x", n), lambda: vector("phase", n, "iu"))
    if cls is Solution:
        if v["x"].ndim != 1:
            return "x", f"must be 1-D, got shape {v['x'].shape}"
        n_x = v["x"].shape[0]
        for group, field in (("events", "x_pre"), ("samples", "x"), ("record", "x")):
            sub = v[group]
            if sub is not None and getattr(sub, field).shape[1] != n_x:
                shape = getattr(sub, field).shape
                return f"{group}/{field}", f"must have n_x = {n_x} columns (as `x`), got {shape}"
        return first(
            lambda: matrix("jac", n_x, n_x),
            lambda: None if v["dt_dx0"] is None else vector("dt_dx0", n_x),
        )
    if cls is MapResult:
        if v["z"].ndim != 1:
            return "z", f"must be 1-D, got shape {v['z'].shape}"
        n_z = v["z"].shape[0]
        return first(lambda: matrix("jac", n_z, n_z), lambda: vector("state"))
    if cls is FixedPoint:
        if v["section"].ndim != 1:
            return "section", f"must be 1-D, got shape {v['section'].shape}"
        n_z = v["section"].shape[0]
        return first(
            lambda: vector("state"),
            lambda: vector("multipliers", n_z),
            lambda: matrix("eigenvectors", n_z, n_z),
            lambda: matrix("jacobian", n_z, n_z),
            lambda: vector("history"),
        )
    if cls is Bifurcation:
        return first(lambda: vector("section"), lambda: vector("multipliers"))
    if cls is Branch:
        if v["parameter"].ndim != 1:
            return "parameter", f"must be 1-D, got shape {v['parameter'].shape}"
        n = v["parameter"].shape[0]
        return first(
            lambda: matrix("sections", n),
            lambda: vector("step_times", n),
            lambda: matrix("multipliers", n),
            lambda: vector("stable", n, "b"),
        )
    if cls is OrbitDiagram:
        if v["parameter"].ndim != 1:
            return "parameter", f"must be 1-D, got shape {v['parameter'].shape}"
        return matrix("values", v["parameter"].shape[0])
    if cls is BasinMap:
        if len(v["axis_names"]) != 2:
            return "axis_names", f"must be two names, got {len(v['axis_names'])}"
        problem = first(lambda: vector("x"), lambda: vector("y"), lambda: vector("fixed_point"))
        if problem is not None:
            return problem
        grid = (v["y"].shape[0], v["x"].shape[0])
        for name in ("outcome", "strides"):
            if v[name].shape != grid or v[name].dtype.kind not in "iu":
                return (
                    name,
                    f"must be integers of shape (ny, nx) = {grid}, got {v[name].dtype} "
                    f"{v[name].shape}",
                )
        return vector("base", v["fixed_point"].shape[0])
    if cls is SweepTable:
        k = len(v["parameter_names"])
        points = v["points"]
        if points.ndim != 2 or points.shape[1] != k:
            return (
                "points",
                f"must have shape (n, {k}) (one column per parameter), got {points.shape}",
            )
        for name, col in v["columns"].items():
            if col.ndim < 1 or col.shape[0] != points.shape[0]:
                return f"columns/{name}", (
                    f"must have {points.shape[0]} rows (one per point), got shape {col.shape}"
                )
        return None
    return None  # pragma: no cover - every class in _SPECS is handled above


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
    for name, entry in (provenance_json.get("parameters") or {}).items():
        if isinstance(entry["value"], int | float) and not isinstance(entry["value"], bool):
            attrs[f"parameters.{name}"] = entry["value"]
            attrs[f"parameters.{name}.unit"] = entry["unit"]
    return attrs


# ---------------------------------------------------------------------------------------------
# Checksums
# ---------------------------------------------------------------------------------------------


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


class _Opaque:
    """An attribute value of a type walker never writes (kept only to be checksummed)."""

    def __init__(self, what: str) -> None:
        self.what = str(what)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, _Opaque) and other.what == self.what

    def __repr__(self) -> str:
        return f"<{self.what}>"


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
            data = b"" if _is_dynamic(kind, has_checkpoint, p) else arr.tobytes()
            _feed(h, b"D", p, f"{arr.dtype.str}{arr.shape}", data)
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


# ---------------------------------------------------------------------------------------------
# Writing files: in memory first, then plain os.write; disk errors; stale temporary files
# ---------------------------------------------------------------------------------------------


def _check_target(path: Any, overwrite: bool) -> Path:
    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"`path` must be a str or os.PathLike, got {type(path).__name__}")
    path = Path(path)
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise FileNotFoundError(f"directory '{parent}' of `path` '{path}' does not exist")
    if path.exists() and not overwrite:
        raise FileExistsError(f"'{path}' exists; pass overwrite=True to replace it")
    return path


def _disk_error(exc: OSError, path: Path, what: str) -> StorageError:
    """The StorageError of a disk error ``exc`` (ENOSPC, EDQUOT, EROFS, EFBIG, EIO)."""
    name = errno.errorcode.get(exc.errno or 0, str(exc.errno))
    return StorageError(f"{what} '{path}': {_DISK_ERRNOS[exc.errno]} ({name})")


def check_writable(path: str | os.PathLike, n_bytes: int = 0) -> None:
    """Check, before any work, that a file of about ``n_bytes`` can be created at ``path``.

    Parameters
    ----------
    path : str or os.PathLike
        the file to be written; its directory must exist.
    n_bytes : int
        estimated size of the file [bytes].

    Raises
    ------
    FileNotFoundError
        the directory does not exist.
    StorageError
        the directory is on a read-only file system, or its file system has fewer than
        ``n_bytes`` (plus 64 KiB) bytes free.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> check_writable(pathlib.Path(tempfile.mkdtemp()) / "x.h5", 10_000)
    """
    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"`path` must be a str or os.PathLike, got {type(path).__name__}")
    if isinstance(n_bytes, bool) or not isinstance(n_bytes, numbers.Integral) or n_bytes < 0:
        raise ValueError(f"`n_bytes` must be a non-negative int, got {n_bytes!r}")
    path = Path(path)
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise FileNotFoundError(f"directory '{parent}' of `path` '{path}' does not exist")
    _check_space(parent, int(n_bytes), path)


def _check_space(directory: Path, n_bytes: int, path: Path) -> None:
    try:
        flags = os.statvfs(directory).f_flag
    except (OSError, AttributeError):
        flags = 0
    if flags & getattr(os, "ST_RDONLY", 1):
        raise StorageError(f"cannot write '{path}': read-only file system (EROFS)")
    try:
        free = shutil.disk_usage(directory).free
    except OSError:
        return
    if free < n_bytes + (1 << 16):
        raise StorageError(
            f"cannot write '{path}': it needs about {n_bytes} bytes, only {free} are free on "
            "its file system (ENOSPC)"
        )


def _temp_name(path: Path) -> Path:
    return path.with_name(f".{path.name}.tmp-{os.getpid()}-{secrets.token_hex(4)}")


def _process_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # EPERM: it exists, owned by someone else
        return True
    return True


def _remove_stale_temps(path: Path) -> list[Path]:
    """Remove ``.<name>.tmp-<pid>-<hex>`` files of ``path`` whose writing process is gone
    (and that were not modified for ``_STALE_TEMP_AGE`` seconds); returns them."""
    parent = path.parent if str(path.parent) else Path(".")
    prefix = f".{path.name}.tmp-"
    removed = []
    try:
        entries = list(os.scandir(parent))
    except OSError:
        return removed
    now = time.time()
    for entry in entries:
        if not entry.name.startswith(prefix):
            continue
        pid_text, _, token = entry.name[len(prefix) :].partition("-")
        if not (
            pid_text.isdigit() and len(token) == 8 and all(c in "0123456789abcdef" for c in token)
        ):
            continue
        pid = int(pid_text)
        if pid == os.getpid() or pid <= 0 or _process_alive(pid):
            continue
        try:
            if not entry.is_file(follow_symlinks=False):
                continue
            if now - entry.stat(follow_symlinks=False).st_mtime < _STALE_TEMP_AGE:
                continue
            os.unlink(entry.path)
        except OSError:
            continue
        removed.append(Path(entry.path))
    return removed


def _fsync_path(path: Path, directory: bool = False) -> None:
    flags = os.O_RDONLY | (getattr(os, "O_DIRECTORY", 0) if directory else 0)
    try:
        fd = os.open(path, flags)
    except OSError:
        if directory:  # some platforms cannot open directories; the data itself is synced
            return
        raise
    try:
        os.fsync(fd)
    except OSError:
        if not directory:
            raise
    finally:
        os.close(fd)


def _write_all(fd: int, data: Any, offset: int | None = None) -> None:
    """Write every byte of ``data`` to ``fd`` (at ``offset`` with pwrite, else at the current
    position); a short write is continued, an error raises OSError."""
    view = memoryview(data).cast("B")
    done = 0
    while done < len(view):
        if offset is None:
            n = os.write(fd, view[done:])
        else:
            n = os.pwrite(fd, view[done:], offset + done)
        if n <= 0:
            raise OSError(errno.EIO, "write returned no progress")
        done += n


def _build_image(fill: Any) -> tuple[bytes, dict]:
    """The bytes of a new file built by ``fill(h5file)`` in memory (HDF5 core driver, no
    backing store), with its ``checksum`` attribute; and the tree walker reads from it."""
    name = f"walker-{os.getpid()}-{secrets.token_hex(8)}.h5"
    # libver "earliest" keeps the oldest superblock, which has no "open for writing" flag.
    f = h5py.File(name, "w", driver="core", backing_store=False, libver="earliest")
    try:
        fill(f)
        f.flush()
        tree = _Loader(f, Path(name), None, None, raw=None, lazy=True).run()
        f.attrs[_CHECKSUM_ATTR] = _content_digest(tree)
        f.flush()
        image = f.id.get_file_image()
    finally:
        f.close()
    return image, tree


def _atomic_write(path: Path, image: bytes, overwrite: bool) -> Path:
    """Write ``image`` under a temporary name next to ``path``, fsync it and move it onto
    ``path`` (never replacing an existing file unless ``overwrite``)."""
    parent = path.parent if str(path.parent) else Path(".")
    _remove_stale_temps(path)
    _check_space(parent, len(image), path)
    tmp = _temp_name(path)
    fd = None
    try:
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o666)
        _write_all(fd, image)
        os.fsync(fd)
        os.close(fd)
        fd = None
        if overwrite:
            os.replace(tmp, path)
        else:
            # link() refuses an existing target atomically, unlike an exists() check.
            try:
                os.link(tmp, path)
            except FileExistsError:
                raise FileExistsError(
                    f"'{path}' exists; pass overwrite=True to replace it"
                ) from None
            except OSError as exc:  # no hard links on this file system
                if exc.errno in _DISK_ERRNOS and exc.errno != errno.EIO:
                    raise
                if path.exists():
                    raise FileExistsError(
                        f"'{path}' exists; pass overwrite=True to replace it"
                    ) from None
                os.replace(tmp, path)
            else:
                os.unlink(tmp)
        _fsync_path(parent, directory=True)
    except BaseException as exc:
        if fd is not None:
            try:
                os.close(fd)
            except OSError:
                pass
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(exc, OSError) and exc.errno in _DISK_ERRNOS:
            raise _disk_error(exc, path, "cannot write") from None
        raise
    return path


def _atomic_create(path: Path, fill: Any, overwrite: bool) -> Path:
    """Build the file with ``fill(h5file)`` in memory, then write it onto ``path``."""
    image, _ = _build_image(fill)
    return _atomic_write(path, image, overwrite)


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


# ---------------------------------------------------------------------------------------------
# Loading a file into a plain tree: every HDF5 call of a read happens here
# ---------------------------------------------------------------------------------------------

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
    size is compared with what its storage can hold (the file size, times
    :data:`MAX_COMPRESSION_RATIO` for deflate) and the total with the memory ``budget``.
    """

    def __init__(
        self,
        f: h5py.File,
        path: Path,
        file_size: int | None,
        budget: int | None,
        raw: Any = None,
        lazy: bool = False,
    ):
        self.f = f
        self.raw = raw  # raw(offset, size) -> bytes of the file
        self.lazy = lazy  # pending rows as read-only broadcasts (for a file being created)
        self.path = path
        self.file_size = file_size
        self.budget = budget
        self.spent = 0
        self.n_objects = 0
        self.seen: set[Any] = set()
        self.deferred: dict[str, h5py.Dataset] = {}

    # -- structure ----------------------------------------------------------------------

    def run(self) -> dict:
        f = self.f
        attrs = self.attrs(f, "/")
        version, kind = _header_kind(attrs, self.path)
        link = f.get(_CHECKPOINT_GROUP, getlink=True)
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
            stored = ds.id.get_storage_size()
            ratio = MAX_COMPRESSION_RATIO if h5py.h5z.FILTER_DEFLATE in codes else 1
            if size is not None and stored > size:
                limit = -1
            else:
                limit = stored * ratio
        else:
            raise _refused(self.path, f"dataset '{path}' has the storage layout {layout}")
        if n_bytes > limit:
            raise StorageError(
                f"cannot read '{self.path}': dataset '{path}' declares {n_bytes} bytes (shape "
                f"{shape}, {dtype}), more than its storage in a file of {size} bytes can hold; "
                "refused"
            )
        self.spend(n_bytes, f"dataset '{path}'")

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
            state = np.zeros(n_chunks, dtype=np.int8)
            done, bad = self.chunk_rows(done_path, 1, n_chunks, np.arange(n_chunks))
            state[done.astype(bool)] = 1
            state[bad] = 2
            self.put(root, done_path, done)
            for p in data:
                values, bad = self.chunk_rows(p, cs, n_chunks, np.flatnonzero(state == 1))
                state[bad] = 2
                self.put(root, p, values)
            layout = self.layout(version, cs, n_rows, data, want_paths)
        root["extra"]["state"] = state
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
        state = np.zeros(n_chunks, dtype=np.int8)
        if self.raw is None:  # a file being created, in memory: read through HDF5
            done, bad = self.chunk_rows(done_path, 1, n_chunks, np.arange(n_chunks))
            state[done.astype(bool)] = 1
            state[bad] = 2
        else:
            flags = self.raw_rows(layout[done_path], 5, np.arange(n_chunks))
            is_true = (flags == _DONE_TRUE).all(axis=1)
            state[is_true] = 1
            state[~(is_true | (flags == _DONE_FALSE).all(axis=1))] = 2
        self.put(root, done_path, state == 1)
        sha, bad = self.chunk_rows(sha_path, 1, n_chunks, np.flatnonzero(state == 1))
        state[bad] = 2
        self.put(root, sha_path, sha)
        for p in data:
            values, bad = self.chunk_rows(p, cs, n_chunks, np.flatnonzero(state == 1))
            state[bad] = 2
            self.put(root, p, values)
        return state

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
        out = np.full(ds.shape, fill, dtype=ds.dtype)
        bad = np.zeros(n_chunks, dtype=bool)
        if wanted.size == 0 or out.size == 0:
            return out, bad
        chunk_of_row = np.arange(ds.shape[0]) // rows_per_chunk
        keep = np.isin(chunk_of_row, wanted)
        try:
            whole = self.read(ds, path)
        except StorageError:
            pass  # some chunk cannot be read (perhaps one being written): chunk by chunk
        else:
            out[keep] = whole[keep]
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


# ---------------------------------------------------------------------------------------------
# Running the load in a child process: a crash or a hang of HDF5 becomes a StorageError
# ---------------------------------------------------------------------------------------------


def _check_path(path: Any) -> Path:
    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"`path` must be a str or os.PathLike, got {type(path).__name__}")
    path = Path(path)
    if not path.exists():
        raise StorageError(f"cannot read '{path}': no such file")
    if not path.is_file():
        raise StorageError(f"cannot read '{path}': not a regular file")
    return path


def _ram_bytes() -> int:
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):  # pragma: no cover - not on Linux
        return 16 << 30


def _default_budget(file_size: int) -> int:
    """Memory a read may use [bytes]: 4x the file (at least 2 GiB), at most 80% of RAM."""
    return int(min(max(2 << 30, 4 * file_size), 0.8 * _ram_bytes()))


def _load_here(path: Path, file_size: int, budget: int) -> dict:
    """Open and load ``path`` in this process (StorageError on any problem)."""
    try:
        try:
            # No lock: the writer of a checkpoint takes none either (it uses os.pwrite).
            f = h5py.File(path, "r", locking=False)
        except OSError as exc:
            if "locking" not in str(exc):
                raise
            # This process has the file open already, with HDF5's lock: share that.
            f = h5py.File(path, "r")
    except Exception as exc:  # noqa: BLE001 - any failure to open is a bad file
        raise StorageError(
            f"cannot read '{path}': not an HDF5 file, or truncated/corrupted ({_first_line(exc)})"
        ) from None
    fd = None
    try:
        with f:
            fd = os.open(path, os.O_RDONLY | getattr(os, "O_CLOEXEC", 0))
            raw = lambda offset, size: os.pread(fd, size, offset)  # noqa: E731
            return _Loader(f, path, file_size, budget, raw).run()
    except StorageError:
        raise
    except MemoryError:
        raise StorageError(
            f"cannot read '{path}': reading it needs more memory than is available"
        ) from None
    except RecursionError:
        raise StorageError(f"cannot read '{path}': corrupted (nested too deeply)") from None
    except Exception as exc:  # noqa: BLE001 - h5py raises many types on damaged files
        reason = _first_line(exc)
        if not isinstance(exc, _Corrupt):
            reason = f"{type(exc).__name__}: {reason}"
        raise StorageError(f"cannot read '{path}': corrupted or incomplete ({reason})") from None
    finally:
        if fd is not None:
            os.close(fd)


def _pack(tree: dict) -> list[Any]:
    """The tree as bytes a parent can read back without unpickling: a JSON header (arrays
    as references) and the arrays' raw bytes."""
    blobs: list[np.ndarray] = []

    def encode(value: Any) -> Any:
        if isinstance(value, dict):
            return {str(k): encode(v) for k, v in value.items()}
        if isinstance(value, np.ndarray):
            arr = value if value.flags.c_contiguous else value.copy(order="C")
            blobs.append(arr)
            return {"__a": [arr.dtype.str, list(arr.shape)]}
        if isinstance(value, _Opaque):
            return {"__o": value.what}
        if value is None or isinstance(value, str | int | float):
            return value
        raise TypeError(f"cannot pack {type(value).__name__}")

    header = json.dumps(encode(tree)).encode("ascii")
    views = [memoryview(a.reshape(-1).view(np.uint8)) for a in blobs]
    return [len(header).to_bytes(8, "little"), header, *views]


def _unpack(buf: memoryview) -> dict:
    """Inverse of :func:`_pack` (``buf`` a writable buffer the arrays then share); every
    dtype and shape is checked before use."""
    n = int.from_bytes(buf[:8], "little")
    header = json.loads(bytes(buf[8 : 8 + n]).decode("ascii"))
    pos = 8 + n

    def decode(value: Any) -> Any:
        nonlocal pos
        if isinstance(value, dict):
            if set(value) == {"__a"}:
                dtype_text, shape = value["__a"]
                dtype = np.dtype(dtype_text)
                if dtype.kind not in "biufc" or dtype.fields is not None:
                    raise ValueError(f"bad dtype {dtype_text!r}")
                if not all(isinstance(s, int) and s >= 0 for s in shape):
                    raise ValueError(f"bad shape {shape!r}")
                size = math.prod(shape) * dtype.itemsize
                if pos + size > len(buf):
                    raise ValueError("truncated")
                arr = np.frombuffer(buf, dtype=dtype, count=math.prod(shape), offset=pos)
                pos += size
                return arr.reshape(shape)
            if set(value) == {"__o"}:
                return _Opaque(str(value["__o"]))
            return {k: decode(v) for k, v in value.items()}
        return value

    return decode(header)


def _limit_memory(budget: int) -> None:
    """In the child: no core files, and an address-space limit of what is mapped now plus
    ``budget`` plus 1 GiB."""
    try:
        import resource
    except ImportError:  # pragma: no cover - not on POSIX
        return
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    try:
        with open("/proc/self/statm") as fh:
            mapped = int(fh.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    limit = mapped + budget + (1 << 30)
    if hard != resource.RLIM_INFINITY:
        limit = min(limit, hard)
    resource.setrlimit(resource.RLIMIT_AS, (limit, hard))


def _child_load(path: str, fd: int, file_size: int, budget: int) -> None:
    """Body of the reading child: load, send the packed tree (``T``) or a StorageError's
    message (``E``) through ``fd``, exit.  Never returns."""
    code = 0
    try:
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        import faulthandler

        faulthandler.disable()  # a crash is reported by the parent, in one line
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 2)
        os.close(devnull)
        _limit_memory(budget)
        try:
            pieces = [b"T", *_pack(_load_here(Path(path), file_size, budget))]
        except StorageError as exc:
            pieces = [b"E", str(exc).encode("utf-8", "replace")]
        except MemoryError:
            pieces = [b"M"]
        for piece in pieces:
            _write_all(fd, piece)
    except BaseException:  # noqa: BLE001 - the parent reports the exit status
        code = 70
    finally:
        os._exit(code)


def _isolated_main(argv: list[str]) -> None:
    """Entry point of a spawned reading child: ``path fd file_size budget``."""
    path, fd, file_size, budget = argv
    _child_load(path, int(fd), int(file_size), int(budget))


def _can_fork() -> bool:
    """Fork is cheap (about 10 ms) but safe only while this process runs one thread."""
    return (
        hasattr(os, "fork") and sys.platform.startswith("linux") and threading.active_count() == 1
    )


def _start_child(path: Path, fd: int, file_size: int, budget: int) -> Any:
    if _can_fork():
        pid = os.fork()
        if pid == 0:  # pragma: no cover - runs in the child, which exits
            _child_load(str(path), fd, file_size, budget)
        return pid
    import walker

    env = dict(os.environ)
    root = str(Path(walker.__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join(p for p in (root, env.get("PYTHONPATH")) if p)
    code = "import sys; from walker.storage import _isolated_main; _isolated_main(sys.argv[1:])"
    return subprocess.Popen(
        [sys.executable, "-c", code, str(path), str(fd), str(file_size), str(budget)],
        pass_fds=(fd,),
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        env=env,
    )


def _reap(child: Any, block: bool) -> int | None:
    """Exit code of the child (negative: killed by that signal), None while it runs."""
    if isinstance(child, subprocess.Popen):
        return child.wait() if block else child.poll()
    pid, status = os.waitpid(child, 0 if block else os.WNOHANG)
    return None if pid == 0 else os.waitstatus_to_exitcode(status)


def _kill(child: Any) -> None:
    try:
        if isinstance(child, subprocess.Popen):
            child.kill()
        else:
            os.kill(child, signal.SIGKILL)
    except OSError:  # already gone
        pass
    try:
        _reap(child, block=True)
    except ChildProcessError:  # already reaped
        pass


def _load_isolated(path: Path, file_size: int, budget: int, timeout: float) -> dict:
    """Load ``path`` in a child process (forked when this process has one thread, else a
    new interpreter) that has ``timeout`` seconds and ``budget`` bytes; its crash, hang or
    memory exhaustion is a StorageError naming what it died of."""
    r, w = os.pipe()
    try:
        child = _start_child(path, w, file_size, budget)
    except BaseException:
        os.close(r)
        os.close(w)
        raise
    os.close(w)
    deadline = time.monotonic() + timeout
    pieces: list[bytes] = []
    received = 0
    status = None
    try:
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise StorageError(
                    f"cannot read '{path}': reading did not finish within {timeout:g} s (a "
                    "damaged file makes the HDF5 library loop; pass a larger `timeout` if "
                    "the file is just large)"
                )
            ready, _, _ = select.select([r], [], [], min(remaining, 1.0))
            if not ready:
                continue
            piece = os.read(r, 1 << 20)
            if not piece:
                break
            received += len(piece)
            if received > budget + (1 << 24):
                raise StorageError(f"cannot read '{path}': the reader sent more than its budget")
            pieces.append(piece)
        while status is None:
            status = _reap(child, block=False)
            if status is None:
                if time.monotonic() > deadline:
                    raise StorageError(
                        f"cannot read '{path}': reading did not finish within {timeout:g} s"
                    )
                time.sleep(0.001)
    except BaseException:  # a timeout, or an interrupt of this process: no orphan left
        if status is None:
            _kill(child)
        raise
    finally:
        os.close(r)
    data = bytearray(received)
    at = 0
    for piece in pieces:
        data[at : at + len(piece)] = piece
        at += len(piece)
    del pieces
    if status < 0:
        try:
            name = signal.Signals(-status).name
        except ValueError:
            name = f"signal {-status}"
        raise StorageError(
            f"cannot read '{path}': the HDF5 library crashed reading it (the reading process "
            f"was killed by {name}); the file is damaged"
        )
    if status != 0 or not data:
        raise StorageError(f"cannot read '{path}': the reading process failed (exit {status})")
    if data[:1] == b"E":
        raise StorageError(bytes(data[1:]).decode("utf-8", "replace"))
    if data[:1] == b"M":
        raise StorageError(
            f"cannot read '{path}': reading it needs more than the memory budget of {budget} "
            "bytes; pass a larger `memory`"
        )
    try:
        return _unpack(memoryview(data)[1:])
    except (ValueError, TypeError, KeyError, UnicodeDecodeError) as exc:
        raise StorageError(
            f"cannot read '{path}': the reading process sent a malformed answer ({exc})"
        ) from None


def _load_tree(
    path: Path, *, isolate: bool, timeout: float | None = None, memory: int | None = None
) -> dict:
    file_size = path.stat().st_size
    budget = _default_budget(file_size) if memory is None else int(memory)
    if not isolate:
        return _load_here(path, file_size, budget)
    if timeout is None:
        timeout = READ_TIMEOUT + file_size / 50e6
    return _load_isolated(path, file_size, budget, float(timeout))


# ---------------------------------------------------------------------------------------------
# Decoding the tree (pure Python): types, shapes, checksums
# ---------------------------------------------------------------------------------------------


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
    if codec == "array_dict":
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


# ---------------------------------------------------------------------------------------------
# Checkpoints: chunk writes with os.pwrite at the offsets the file's layout gives
# ---------------------------------------------------------------------------------------------


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


def _checkpoint_state(path: Path) -> np.ndarray:
    """State of each chunk of a checkpoint (0 pending, 1 done, 2 damaged), read here."""
    loaded = _load_checked(_check_path(path), isolate=False)
    if loaded.state is None:
        raise StorageError(f"cannot read '{path}': not a checkpoint")
    return loaded.state


def checkpoint_progress(path: str | os.PathLike) -> tuple[int, int] | None:
    """``(chunks done, chunks)`` of a sweep or basin checkpoint file, or None when ``path``
    is not one (missing, unreadable, or a result written by :func:`write`).  A chunk whose
    checksum fails does not count as done."""
    try:
        state = _checkpoint_state(Path(path))
    except (StorageError, OSError, TypeError):
        return None
    return int(np.sum(state == 1)), int(state.size)


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


class SweepStore:
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
        self.path = path
        self.parameter_names = parameter_names
        self.points = points
        self.columns = columns
        self.chunk_size = chunk_size
        self.fsync = fsync
        self.n_points = int(points.shape[0])
        self.n_chunks = -(-self.n_points // chunk_size)
        self._writer: _ChunkWriter | None = None

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
        """
        if not isinstance(path, str | os.PathLike):
            raise TypeError(f"`path` must be a str or os.PathLike, got {type(path).__name__}")
        path = Path(path)
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
            parent = path.parent if str(path.parent) else Path(".")
            if not parent.is_dir():
                raise FileNotFoundError(f"directory '{parent}' of `path` '{path}' does not exist")
            store._create(prov_json, overwrite=bool(overwrite))
        return store

    def _create(self, prov_json: dict, overwrite: bool = False) -> None:
        root_attrs = _provenance_attrs(prov_json, "sweep")
        n, cs = self.n_points, self.chunk_size
        row_bytes = sum(d.itemsize * math.prod(s) for d, s in self.columns.values())
        _check_checkpoint_size(
            self.path, n * row_bytes + self.points.nbytes + 50 * self.n_chunks, cs * row_bytes
        )

        def fill(f: h5py.File) -> None:
            f.attrs.update(root_attrs)
            g = f.create_group(_RESULT_GROUP)
            g.attrs["dataclass"] = "SweepTable"
            g.attrs["parameter_names"] = json.dumps(list(self.parameter_names))
            g.create_dataset("points", data=self.points, **_dataset_options(self.points.shape))
            cg = g.create_group("columns")
            cg.attrs["names"] = json.dumps(list(self.columns))
            for name, (dtype, shape) in self.columns.items():
                _chunked_dataset(cg, name, (n, *shape), cs, dtype, _fill_value(dtype))
            _checkpoint_group(f, cs, self.n_chunks)

        image, tree = _build_image(fill)
        _atomic_write(self.path, image, overwrite=overwrite)
        self._writer = _ChunkWriter(self.path, tree, "sweep", SCHEMA_VERSION)

    def _check_existing(self, prov_json: dict) -> None:
        path = self.path
        try:
            loaded = _load_checked(path, isolate=True)
        except StorageError as exc:
            raise _unreadable(exc, path) from None
        if loaded.kind != "sweep" or loaded.state is None:
            raise CheckpointMismatch(
                f"cannot resume '{path}': it holds a {loaded.kind!r} result, not a sweep "
                "checkpoint; use a new path",
                path=path,
                reason=f"holds a {loaded.kind!r} result, not a sweep checkpoint",
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
        stored_prov = loaded.provenance_json
        if stored_prov != prov_json:
            keys = sorted(
                k
                for k in set(stored_prov) | set(prov_json)
                if stored_prov.get(k) != prov_json.get(k)
            )
            diffs.append(f"provenance differs in {keys}")
        if diffs:
            raise CheckpointMismatch(
                f"cannot resume '{path}': it checkpoints a different sweep ({'; '.join(diffs)});"
                " use a new path or delete the file",
                path=path,
                reason=f"checkpoints a different sweep ({'; '.join(diffs)})",
            )
        self._writer = _ChunkWriter(path, loaded.root, "sweep", loaded.version)

    # -- use --------------------------------------------------------------------------------

    def _check_chunk(self, i: Any) -> int:
        if isinstance(i, bool) or not isinstance(i, numbers.Integral):
            raise TypeError(f"chunk index `i` must be an int, got {i!r}")
        if not 0 <= i < self.n_chunks:
            raise ValueError(f"chunk index `i` must be in [0, {self.n_chunks}), got {i}")
        return int(i)

    def chunk_slice(self, i: int) -> slice:
        """Rows of chunk ``i``: ``slice(i * chunk_size, min((i + 1) * chunk_size, n))``."""
        i = self._check_chunk(i)
        return slice(i * self.chunk_size, min((i + 1) * self.chunk_size, self.n_points))

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

    def table(self) -> SweepTable:
        """The whole table (unwritten rows hold the fill values)."""
        result, _ = read(self.path, isolate=False)
        return result


# ---------------------------------------------------------------------------------------------
# Basin checkpoints
# ---------------------------------------------------------------------------------------------

BASIN_NOT_COMPUTED = -3
"""Outcome held by the grid points of a :class:`BasinStore` whose rows are not computed yet
(a :class:`~walker.results.BasinMap`'s codes are ``BASIN_CONVERGED`` (-1),
``BASIN_UNDECIDED`` (-2) and :class:`~walker.status.Status` values, all >= -2)."""

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


class BasinStore:
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

    def __init__(self, path: Path, ny: int, nx: int, chunk_size: int, fsync: bool = True):
        """Use :meth:`create_or_open`."""
        self.path = path
        self.shape = (int(ny), int(nx))
        self.chunk_size = int(chunk_size)
        self.fsync = fsync
        self.n_chunks = -(-self.shape[0] // self.chunk_size)
        self._writer: _ChunkWriter | None = None

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

        Returns
        -------
        BasinStore

        Raises
        ------
        CheckpointMismatch
            ``path`` exists (and ``overwrite`` is False) but is not a checkpoint of this
            basin map, or is corrupted.
        StorageError
            the new file would not fit in memory or on the disk, or the disk is full or
            read-only.
        FileNotFoundError
            the directory of ``path`` does not exist.
        """
        if not isinstance(path, str | os.PathLike):
            raise TypeError(f"`path` must be a str or os.PathLike, got {type(path).__name__}")
        path = Path(path)
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
        )
        if path.exists() and not overwrite:
            stored_chunk, loaded = cls._compare(path, want)
            store = cls(path, ny, nx, stored_chunk, fsync=bool(fsync))
            store._writer = _ChunkWriter(path, loaded.root, "basin", loaded.version)
            return store
        parent = path.parent if str(path.parent) else Path(".")
        if not parent.is_dir():
            raise FileNotFoundError(f"directory '{parent}' of `path` '{path}' does not exist")
        if chunk_size is None:
            chunk_size = max(1, -(-ny // BASIN_DEFAULT_CHUNKS))
        store = cls(path, ny, nx, chunk_size, fsync=bool(fsync))
        store._create(want, overwrite=bool(overwrite))
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

    @staticmethod
    def _compare(path: Path, want: dict[str, Any]) -> tuple[int, _Loaded]:
        """Raise CheckpointMismatch unless ``path`` is a basin checkpoint agreeing with every
        entry of ``want``; returns its chunk size and the file as read (in a child process,
        every checksum verified)."""
        try:
            loaded = _load_checked(path, isolate=True)
        except StorageError as exc:
            raise _unreadable(exc, path) from None
        if loaded.kind != "basin" or loaded.state is None:
            what = (
                "a finished 'basin' result without a checkpoint"
                if loaded.kind == "basin"
                else f"a {loaded.kind!r} result"
            )
            raise CheckpointMismatch(
                f"cannot resume '{path}': it holds {what}, not a basin checkpoint; use a new path",
                path=path,
                reason=f"holds {what}, not a basin checkpoint",
            )
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
        if want.get("chunk_size") is not None and want["chunk_size"] != stored_cs:
            diffs.append(f"chunk_size {stored_cs} != {want['chunk_size']}")
        if "provenance_json" in want:
            stored_prov = loaded.provenance_json
            prov = want["provenance_json"]
            if stored_prov != prov:
                keys = sorted(
                    key
                    for key in set(stored_prov) | set(prov)
                    if stored_prov.get(key) != prov.get(key)
                )
                diffs.append(f"provenance differs in {keys}")
        if diffs:
            raise CheckpointMismatch(
                f"cannot resume '{path}': it checkpoints a different basin map "
                f"({'; '.join(diffs)}); use a new path or delete the file",
                path=path,
                reason=f"checkpoints a different basin map ({'; '.join(diffs)})",
            )
        return stored_cs, loaded

    def _create(self, want: dict[str, Any], overwrite: bool) -> None:
        root_attrs = _provenance_attrs(want["provenance_json"], "basin")
        ny, nx = self.shape
        cs = self.chunk_size
        _check_checkpoint_size(self.path, 16 * ny * nx + 50 * self.n_chunks, 16 * cs * nx)

        def fill(f: h5py.File) -> None:
            f.attrs.update(root_attrs)
            g = f.create_group(_RESULT_GROUP)
            g.attrs["dataclass"] = "BasinMap"
            g.attrs["axis_names"] = json.dumps(list(want["axis_names"]))
            g.attrs["n_strides"] = np.int64(want["n_strides"])
            for name in ("x", "y", "fixed_point", "base"):
                g.create_dataset(name, data=want[name], **_dataset_options(want[name].shape))
            for name, fillv in (("outcome", BASIN_NOT_COMPUTED), ("strides", -1)):
                _chunked_dataset(g, name, (ny, nx), cs, np.int64, fillv)
            k = _checkpoint_group(f, cs, self.n_chunks)
            k.attrs["tol"] = np.float64(want["tol"])
            k.attrs["period"] = np.int64(want["period"])

        image, tree = _build_image(fill)
        _atomic_write(self.path, image, overwrite=overwrite)
        self._writer = _ChunkWriter(self.path, tree, "basin", SCHEMA_VERSION)

    # -- use --------------------------------------------------------------------------------

    def _check_chunk(self, i: Any) -> int:
        if isinstance(i, bool) or not isinstance(i, numbers.Integral):
            raise TypeError(f"chunk index `i` must be an int, got {i!r}")
        if not 0 <= i < self.n_chunks:
            raise ValueError(f"chunk index `i` must be in [0, {self.n_chunks}), got {i}")
        return int(i)

    def chunk_slice(self, i: int) -> slice:
        """Grid rows of chunk ``i``."""
        i = self._check_chunk(i)
        return slice(i * self.chunk_size, min((i + 1) * self.chunk_size, self.shape[0]))

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
