"""HDF5 storage of results with provenance: atomic writes, strict reads, sweep checkpoints.

One file holds one result (one *kind*); :func:`write` stores it and :func:`read` gives back an
equal dataclass and the provenance.  The layout is described in ``docs/storage.md``
(schema version :data:`SCHEMA_VERSION`).

Rules this module keeps:

1. ``read(write(path, x, provenance=p)) == (x, p + automatic keys)`` field by field: arrays
   with their dtype and shape (empty arrays too), ``None`` fields, tuples of names,
   :class:`~walker.status.Status` members, dicts of parameters.
2. :func:`write` is atomic: the file is built under a temporary name in the target directory
   (``.<name>.tmp-<pid>-<random>``), flushed, fsynced and moved onto the target with one
   rename.  A failure at any point leaves no target and no temporary file.  An existing
   target is never replaced unless ``overwrite=True``.
3. Invalid input raises before any file is touched (``TypeError``/``ValueError`` naming the
   field and the rule; ``FileNotFoundError`` for a missing directory; ``FileExistsError``).
4. Reading a file that is missing, not HDF5, truncated or corrupted, from a newer schema or of
   an unknown kind raises :class:`StorageError` (a ``ValueError``) with a one-line message
   naming the file and the problem.
5. :class:`SweepStore` checkpoints a parameter sweep chunk by chunk, and :class:`BasinStore`
   a basin map rows by rows; see SweepStore's docstring for the guarantee both give when the
   process is killed (SIGKILL) or interrupted (KeyboardInterrupt at any point).

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
import json
import numbers
import os
import secrets
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
    "SCHEMA_VERSION",
    "BasinStore",
    "CheckpointMismatch",
    "StorageError",
    "SweepStore",
    "checkpoint_progress",
    "parameters_with_units",
    "read",
    "walker_version",
    "write",
]

SCHEMA_VERSION = 1
"""Version of the file layout written by this module; files with a larger one are refused."""

AUTOMATIC_KEYS = ("walker_version", "schema_version", "kind", "created")
"""Provenance keys set by :func:`write` itself; a caller may not pass them."""

_RESULT_GROUP = "result"
_CHECKPOINT_GROUP = "checkpoint"
_RESERVED_ATTRS = frozenset(AUTOMATIC_KEYS) | {"provenance"}


class StorageError(ValueError):
    """A file cannot be read as a walker result (missing, corrupted, newer schema, ...)."""


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


# ---------------------------------------------------------------------------------------------
# Field codecs: how each field of each result dataclass is stored.
#
#   "array"           dataset, dtype and shape kept exactly
#   "optional_array"  dataset, absent when the field is None
#   "float" / "int" / "bool" / "str"   attribute
#   "status"          attribute holding the Status member's name ("COMPLETED")
#   "names"           attribute holding a JSON list of strings (read back as a tuple)
#   "json"            attribute holding a JSON object (dict of parameters)
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


def _from_json(value: Any) -> Any:
    if isinstance(value, list):
        return [_from_json(v) for v in value]
    if not isinstance(value, dict):
        return value
    if len(value) == 1:
        ((tag, inner),) = value.items()
        if tag == "__status__":
            return Status[inner]
        if tag == "__tuple__":
            return tuple(_from_json(v) for v in inner)
        if tag == "__complex__":
            return complex(inner[0], inner[1])
        if tag == "__ndarray__":
            dtype = np.dtype(inner["dtype"])
            real = np.empty(0, dtype).real.dtype
            flat = np.array(inner["data"], dtype=real)
            if dtype.kind == "c":
                flat = flat.view(dtype)
            return flat.reshape(inner["shape"])
    return {k: _from_json(v) for k, v in value.items()}


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
                f"{', '.join(AUTOMATIC_KEYS)} itself"
            )
    parameters = provenance.get("parameters")
    if parameters is not None:
        if not isinstance(parameters, dict):
            raise TypeError(
                "`provenance['parameters']` must be a dict name -> {'value': v, 'unit': u}, "
                f"got {type(parameters).__name__}"
            )
        for name, entry in parameters.items():
            if (
                not isinstance(entry, dict)
                or set(entry) != {"value", "unit"}
                or not isinstance(entry["unit"], str)
            ):
                raise ValueError(
                    f"`provenance['parameters'][{name!r}]` must be a dict with exactly the keys "
                    f"'value' and 'unit' (a str), got {entry!r}"
                )
    return _to_json(provenance, "provenance")


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
    elif codec == "json":
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


def _emit(tree: dict, group: h5py.Group) -> None:
    for name, value in tree["attrs"].items():
        group.attrs[name] = value
    for name, arr in tree["datasets"].items():
        group.create_dataset(name, data=arr)
    for name, sub in tree["groups"].items():
        _emit(sub, group.create_group(name))


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
# Atomic file creation
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


def _atomic_create(path: Path, fill: Any, overwrite: bool) -> Path:
    """Build the file with ``fill(h5file)`` under a temporary name, then move it onto ``path``."""
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}-{secrets.token_hex(4)}")
    try:
        # libver "earliest" keeps the oldest superblock, which has no "open for writing" flag:
        # a writer killed while holding a SweepStore file open leaves it openable.
        with h5py.File(tmp, "w", libver="earliest") as f:
            fill(f)
            f.flush()
        _fsync_path(tmp)
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
            except OSError:  # no hard links on this file system
                if path.exists():
                    raise FileExistsError(
                        f"'{path}' exists; pass overwrite=True to replace it"
                    ) from None
                os.replace(tmp, path)
            else:
                os.unlink(tmp)
        _fsync_path(path.parent if str(path.parent) else Path("."), directory=True)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    return path


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
    provenance : dict
        what produced the result, e.g. ``scene``, ``model``, ``parameters`` (as
        ``{name: {"value": v, "unit": u}}``, see :func:`parameters_with_units`), ``method``,
        ``rtol``, ``atol``, ``status``, ``kernel_hash``.  Values may be None, str, bool,
        numbers, Status, lists, tuples, dicts and numeric arrays; it is stored as the JSON root
        attribute ``provenance`` and each top-level entry also as its own root attribute.  The
        keys ``walker_version``, ``schema_version``, ``kind`` and ``created`` are added here.
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
# Reading
# ---------------------------------------------------------------------------------------------


class _Corrupt(Exception):
    """Internal: the file's content does not follow the schema."""


def _attr(group: h5py.Group, name: str) -> Any:
    if name not in group.attrs:
        raise _Corrupt(f"attribute '{name}' missing in '{group.name}'")
    value = group.attrs[name]
    return value.decode() if isinstance(value, bytes) else value


def _decode(group: h5py.Group, cls: type) -> Any:
    stored = _attr(group, "dataclass")
    if stored != cls.__name__:
        raise _Corrupt(f"'{group.name}' holds a {stored}, expected a {cls.__name__}")
    values = {name: _decode_field(group, name, codec) for name, codec in _SPECS[cls].items()}
    return cls(**values)


def _read_dataset(group: h5py.Group, name: str) -> np.ndarray:
    if name not in group or not isinstance(group[name], h5py.Dataset):
        raise _Corrupt(f"dataset '{group.name}/{name}' missing")
    ds = group[name]
    return np.asarray(ds[()], dtype=ds.dtype).reshape(ds.shape)


def _decode_field(group: h5py.Group, name: str, codec: Any) -> Any:
    if isinstance(codec, tuple):
        how, sub = codec
        if name not in group:
            if how == "optional_group":
                return None
            raise _Corrupt(f"group '{group.name}/{name}' missing")
        if how in ("group", "optional_group"):
            return _decode(group[name], sub)
        items = group[name]
        n = int(_attr(items, "length"))
        return [_decode(items[str(i)], sub) for i in range(n)]
    if codec == "optional_array":
        return _read_dataset(group, name) if name in group else None
    if codec == "array":
        return _read_dataset(group, name)
    if codec == "array_dict":
        if name not in group:
            raise _Corrupt(f"group '{group.name}/{name}' missing")
        sub = group[name]
        return {key: _read_dataset(sub, key) for key in json.loads(_attr(sub, "names"))}
    value = _attr(group, name)
    if codec == "float":
        return float(value)
    if codec == "int":
        return int(value)
    if codec == "bool":
        return bool(value)
    if codec == "str":
        return str(value)
    if codec == "status":
        try:
            return Status[value]
        except KeyError:
            raise _Corrupt(f"unknown status {value!r} in '{group.name}'") from None
    if codec == "names":
        return tuple(json.loads(value))
    if codec == "json":
        return _from_json(json.loads(value))
    raise RuntimeError(f"unknown codec {codec!r}")  # pragma: no cover


def _open_for_read(path: Path, mode: str = "r") -> h5py.File:
    if not path.exists():
        raise StorageError(f"cannot read '{path}': no such file")
    if not path.is_file():
        raise StorageError(f"cannot read '{path}': not a regular file")
    try:
        return h5py.File(path, mode)
    except OSError as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise StorageError(
            f"cannot read '{path}': not an HDF5 file, or truncated/corrupted ({reason})"
        ) from None


def _check_header(f: h5py.File, path: Path) -> tuple[str, dict[str, Any]]:
    """Schema version and kind checks; returns the kind and the full provenance."""
    if "schema_version" not in f.attrs or "kind" not in f.attrs:
        raise StorageError(
            f"cannot read '{path}': not a walker result file (no 'schema_version'/'kind' "
            "root attribute)"
        )
    version = int(f.attrs["schema_version"])
    if version > SCHEMA_VERSION:
        raise StorageError(
            f"cannot read '{path}': schema_version {version} is newer than this walker's "
            f"{SCHEMA_VERSION}; upgrade walker"
        )
    kind = str(_attr(f, "kind"))
    if kind not in KINDS:
        raise StorageError(
            f"cannot read '{path}': unknown result kind {kind!r} (known: {', '.join(KINDS)})"
        )
    provenance = _from_json(json.loads(_attr(f, "provenance")))
    provenance.update(
        walker_version=str(_attr(f, "walker_version")),
        schema_version=version,
        kind=kind,
        created=str(_attr(f, "created")),
    )
    return kind, provenance


def read(path: str | os.PathLike) -> tuple[Any, dict[str, Any]]:
    """Read a result written by :func:`write` (or a :class:`SweepStore` file).

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    result : dataclass
        equal, field by field, to what was written.
    provenance : dict
        the caller's provenance plus ``walker_version``, ``schema_version``, ``kind`` and
        ``created`` (UTC, ISO 8601).

    Raises
    ------
    StorageError
        the file is missing, not HDF5, truncated or corrupted, from a newer schema, or of an
        unknown kind; the one-line message names the file and the problem.
    """
    path = Path(path)
    f = _open_for_read(path)
    try:
        with f:
            kind, provenance = _check_header(f, path)
            if _RESULT_GROUP not in f:
                raise _Corrupt(f"group '/{_RESULT_GROUP}' missing")
            result = _decode(f[_RESULT_GROUP], KINDS[kind])
    except StorageError:
        raise
    except (_Corrupt, OSError, KeyError, ValueError, TypeError, RuntimeError) as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise StorageError(f"cannot read '{path}': corrupted or incomplete ({reason})") from None
    return result, provenance


# ---------------------------------------------------------------------------------------------
# Sweep checkpoints
# ---------------------------------------------------------------------------------------------


def _fill_value(dtype: np.dtype) -> Any:
    if dtype.kind == "f":
        return dtype.type(np.nan)
    if dtype.kind == "c":
        return dtype.type(complex(np.nan, np.nan))
    if dtype.kind == "i":
        return dtype.type(-1)
    return np.False_  # bool


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


def _read_done(path: Path) -> np.ndarray:
    """The ``/checkpoint/done`` flags of a checkpoint file."""
    f = _open_for_read(path)
    try:
        with f:
            return np.asarray(f[_CHECKPOINT_GROUP]["done"][()], dtype=bool)
    except (OSError, KeyError) as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise StorageError(f"cannot read '{path}': corrupted ({reason})") from None


def _write_rows(
    path: Path, group: str, arrays: dict[str, np.ndarray], rows: slice, i: int, fsync: bool
) -> None:
    """Write ``arrays[name]`` into rows ``rows`` of the datasets ``group/name``, flush, then
    set ``/checkpoint/done[i]``, flush, close and (``fsync``) fsync.

    Only raw data at fixed offsets changes (the datasets are contiguous and allocated at
    creation), so a kill or an exception at any point leaves a readable file in which chunk
    ``i`` is either marked done with all its rows, or pending."""
    try:
        with h5py.File(path, "r+") as f:
            g = f[group]
            for name, arr in arrays.items():
                g[name][rows] = arr
            f.flush()
            f[_CHECKPOINT_GROUP]["done"][i] = True
            f.flush()
    except (OSError, KeyError) as exc:
        reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise StorageError(f"cannot write chunk {i} to '{path}': {reason}") from None
    if fsync:
        _fsync_path(path)


def checkpoint_progress(path: str | os.PathLike) -> tuple[int, int] | None:
    """``(chunks done, chunks)`` of a sweep or basin checkpoint file, or None when ``path``
    is not one (missing, unreadable, or a result written by :func:`write`)."""
    path = Path(path)
    try:
        with h5py.File(path, "r") as f:
            if _CHECKPOINT_GROUP not in f or "done" not in f[_CHECKPOINT_GROUP]:
                return None
            done = np.asarray(f[_CHECKPOINT_GROUP]["done"][()], dtype=bool)
    except (OSError, KeyError, ValueError):
        return None
    return int(done.sum()), int(done.size)


class SweepStore:
    """Chunked, resumable storage of a parameter sweep in one HDF5 file.

    The file has the layout of a ``"sweep"`` result (so :func:`read` returns its
    :class:`~walker.results.SweepTable`), with every column preallocated and filled with NaN
    (float, complex), -1 (signed int) or False (bool), plus ``/checkpoint/done``, one bool per
    chunk of ``chunk_size`` consecutive points.

    Contract with the caller (the sweep engine):

    1. ``create_or_open`` either creates the file (atomically, like :func:`write`) or opens an
       existing one, which must describe the same sweep: same parameter names, points, column
       names/dtypes/shapes, chunk size and caller provenance; otherwise :class:`StorageError`
       says what differs.
    2. Compute the chunks in ``pending_chunks()``; rows of chunk ``i`` are ``chunk_slice(i)``.
    3. ``write_chunk(i, values)`` opens the file, writes every column's rows, flushes, then sets
       ``done[i]``, flushes, closes and fsyncs.  Writing a chunk again overwrites it
       (idempotent).  One process writes a given file at a time.

    Guarantee when the writing process is killed (SIGKILL, not a power cut or OS crash):
    all datasets are contiguous and allocated at creation, so a chunk write changes raw data
    at fixed offsets only, and no HDF5 metadata; a chunk marked done has all its rows written
    (they reached the OS before the flag); a chunk killed mid-write stays pending and may hold
    partial rows, which its recomputation overwrites.  After ``write_chunk`` returns, the
    chunk has also been fsynced.  A kill during creation leaves no file (only possibly a
    ``.<name>.tmp-*`` file).  Not guaranteed: anything under a concurrent second writer, or
    after a crash of the OS or storage device in the middle of a write.

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

        def fill(f: h5py.File) -> None:
            f.attrs.update(root_attrs)
            g = f.create_group(_RESULT_GROUP)
            g.attrs["dataclass"] = "SweepTable"
            g.attrs["parameter_names"] = json.dumps(list(self.parameter_names))
            g.create_dataset("points", data=self.points)
            cg = g.create_group("columns")
            cg.attrs["names"] = json.dumps(list(self.columns))
            for name, (dtype, shape) in self.columns.items():
                fillv = _fill_value(dtype)
                ds = cg.create_dataset(name, shape=(n, *shape), dtype=dtype, fillvalue=fillv)
                # Write the fill explicitly, block by block: contiguous storage allocated now,
                # so later chunk writes touch raw data only.
                for start in range(0, n, cs):
                    stop = min(start + cs, n)
                    ds[start:stop] = np.full((stop - start, *shape), fillv, dtype=dtype)
            k = f.create_group(_CHECKPOINT_GROUP)
            k.attrs["chunk_size"] = np.int64(cs)
            k.attrs["n_chunks"] = np.int64(self.n_chunks)
            k.create_dataset("done", data=np.zeros(self.n_chunks, dtype=bool))

        _atomic_create(self.path, fill, overwrite=overwrite)

    def _check_existing(self, prov_json: dict) -> None:
        path = self.path
        try:
            f = _open_for_read(path)
        except StorageError as exc:
            raise _unreadable(exc, path) from None
        try:
            with f:
                kind, _ = _check_header(f, path)
                if kind != "sweep" or _CHECKPOINT_GROUP not in f:
                    raise CheckpointMismatch(
                        f"cannot resume '{path}': it holds a {kind!r} result, not a sweep "
                        "checkpoint; use a new path",
                        path=path,
                        reason=f"holds a {kind!r} result, not a sweep checkpoint",
                    )
                g = f[_RESULT_GROUP]
                diffs = []
                stored_names = tuple(json.loads(_attr(g, "parameter_names")))
                if stored_names != self.parameter_names:
                    diffs.append(f"parameter_names {stored_names} != {self.parameter_names}")
                stored_points = _read_dataset(g, "points")
                if stored_points.shape != self.points.shape:
                    diffs.append(f"points shape {stored_points.shape} != {self.points.shape}")
                elif not np.array_equal(stored_points, self.points):
                    n_diff = int(np.sum(np.any(stored_points != self.points, axis=1)))
                    diffs.append(f"{n_diff} of the points differ")
                cg = g["columns"]
                stored_cols = {
                    name: (cg[name].dtype, cg[name].shape[1:])
                    for name in json.loads(_attr(cg, "names"))
                }
                if stored_cols != self.columns:
                    show = {k: (str(d), s) for k, (d, s) in stored_cols.items()}
                    want = {k: (str(d), s) for k, (d, s) in self.columns.items()}
                    diffs.append(f"columns {show} != {want}")
                stored_cs = int(_attr(f[_CHECKPOINT_GROUP], "chunk_size"))
                if stored_cs != self.chunk_size:
                    diffs.append(f"chunk_size {stored_cs} != {self.chunk_size}")
                stored_prov = json.loads(_attr(f, "provenance"))
                if stored_prov != prov_json:
                    keys = sorted(
                        k
                        for k in set(stored_prov) | set(prov_json)
                        if stored_prov.get(k) != prov_json.get(k)
                    )
                    diffs.append(f"provenance differs in {keys}")
        except StorageError as exc:
            if isinstance(exc, CheckpointMismatch):
                raise
            raise _unreadable(exc, path) from None
        except (_Corrupt, OSError, KeyError, ValueError, TypeError) as exc:
            reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise CheckpointMismatch(
                f"cannot resume '{path}': corrupted ({reason})",
                path=path,
                reason=f"is corrupted ({reason})",
            ) from None
        if diffs:
            raise CheckpointMismatch(
                f"cannot resume '{path}': it checkpoints a different sweep ({'; '.join(diffs)});"
                " use a new path or delete the file",
                path=path,
                reason=f"checkpoints a different sweep ({'; '.join(diffs)})",
            )

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
        """ndarray of bool, shape (n_chunks,): which chunks are stored (read from the file)."""
        return _read_done(self.path)

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
            arrays[name] = arr.astype(dtype, copy=False)
        _write_rows(self.path, f"{_RESULT_GROUP}/columns", arrays, sl, i, self.fsync)

    def table(self) -> SweepTable:
        """The whole table (unwritten rows hold the fill values)."""
        result, _ = read(self.path)
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
    ``period`` (attributes) and ``done`` (bool per chunk).

    The contract and the guarantee under SIGKILL (and under an exception such as
    ``KeyboardInterrupt`` at any point) are those of :class:`SweepStore`: creation is atomic,
    a chunk marked done holds all its rows, a chunk interrupted mid-write stays pending.
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
            stored_chunk = cls._compare(path, want)
            return cls(path, ny, nx, stored_chunk, fsync=bool(fsync))
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
    def _compare(path: Path, want: dict[str, Any]) -> int:
        """Raise CheckpointMismatch unless ``path`` is a basin checkpoint agreeing with every
        entry of ``want``; returns its chunk size."""
        try:
            f = _open_for_read(path)
        except StorageError as exc:
            raise _unreadable(exc, path) from None
        diffs: list[str] = []
        try:
            with f:
                kind, _ = _check_header(f, path)
                if kind != "basin" or _CHECKPOINT_GROUP not in f:
                    what = (
                        "a finished 'basin' result without a checkpoint"
                        if kind == "basin"
                        else f"a {kind!r} result"
                    )
                    raise CheckpointMismatch(
                        f"cannot resume '{path}': it holds {what}, not a basin checkpoint; "
                        "use a new path",
                        path=path,
                        reason=f"holds {what}, not a basin checkpoint",
                    )
                g = f[_RESULT_GROUP]
                k = f[_CHECKPOINT_GROUP]
                stored_cs = int(_attr(k, "chunk_size"))
                stored_y = _read_dataset(g, "y")
                stored_x = _read_dataset(g, "x")
                if "axis_names" in want:
                    names = tuple(json.loads(_attr(g, "axis_names")))
                    if names != want["axis_names"]:
                        diffs.append(f"axis_names {names} != {want['axis_names']}")
                if "shape" in want:
                    shape = (stored_y.size, stored_x.size)
                    if shape != want["shape"]:
                        diffs.append(f"grid shape {shape} != {want['shape']}")
                for name, stored in (("x", stored_x), ("y", stored_y)):
                    if name in want and not _same_array(stored, want[name]):
                        diffs.append(f"{name} differs")
                for name in ("fixed_point", "base"):
                    if name in want and not _same_array(_read_dataset(g, name), want[name]):
                        diffs.append(f"{name} differs")
                if "n_strides" in want:
                    stored = int(_attr(g, "n_strides"))
                    if stored != want["n_strides"]:
                        diffs.append(f"n_strides {stored} != {want['n_strides']}")
                for name, conv in (("tol", float), ("period", int)):
                    if name in want:
                        stored = conv(_attr(k, name))
                        if stored != want[name]:
                            diffs.append(f"{name} {stored} != {want[name]}")
                if want.get("chunk_size") is not None and want["chunk_size"] != stored_cs:
                    diffs.append(f"chunk_size {stored_cs} != {want['chunk_size']}")
                if "provenance_json" in want:
                    stored_prov = json.loads(_attr(f, "provenance"))
                    prov = want["provenance_json"]
                    if stored_prov != prov:
                        keys = sorted(
                            key
                            for key in set(stored_prov) | set(prov)
                            if stored_prov.get(key) != prov.get(key)
                        )
                        diffs.append(f"provenance differs in {keys}")
                for name in ("outcome", "strides"):
                    ds = g[name]
                    if ds.shape != (stored_y.size, stored_x.size) or ds.dtype != np.int64:
                        raise _Corrupt(f"dataset '{ds.name}' has shape {ds.shape} {ds.dtype}")
                done = k["done"]
                if done.shape != (-(-stored_y.size // stored_cs),):
                    raise _Corrupt(f"'/checkpoint/done' has shape {done.shape}")
        except StorageError as exc:
            if isinstance(exc, CheckpointMismatch):
                raise
            raise _unreadable(exc, path) from None
        except (_Corrupt, OSError, KeyError, ValueError, TypeError) as exc:
            reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise CheckpointMismatch(
                f"cannot resume '{path}': corrupted ({reason})",
                path=path,
                reason=f"is corrupted ({reason})",
            ) from None
        if diffs:
            raise CheckpointMismatch(
                f"cannot resume '{path}': it checkpoints a different basin map "
                f"({'; '.join(diffs)}); use a new path or delete the file",
                path=path,
                reason=f"checkpoints a different basin map ({'; '.join(diffs)})",
            )
        return stored_cs

    def _create(self, want: dict[str, Any], overwrite: bool) -> None:
        root_attrs = _provenance_attrs(want["provenance_json"], "basin")
        ny, nx = self.shape
        cs = self.chunk_size

        def fill(f: h5py.File) -> None:
            f.attrs.update(root_attrs)
            g = f.create_group(_RESULT_GROUP)
            g.attrs["dataclass"] = "BasinMap"
            g.attrs["axis_names"] = json.dumps(list(want["axis_names"]))
            g.attrs["n_strides"] = np.int64(want["n_strides"])
            for name in ("x", "y", "fixed_point", "base"):
                g.create_dataset(name, data=want[name])
            for name, fillv in (("outcome", BASIN_NOT_COMPUTED), ("strides", -1)):
                ds = g.create_dataset(name, shape=(ny, nx), dtype=np.int64, fillvalue=fillv)
                # Written explicitly: contiguous storage allocated now, so chunk writes touch
                # raw data only.
                for start in range(0, ny, cs):
                    stop = min(start + cs, ny)
                    ds[start:stop] = np.full((stop - start, nx), fillv, dtype=np.int64)
            k = f.create_group(_CHECKPOINT_GROUP)
            k.attrs["chunk_size"] = np.int64(cs)
            k.attrs["n_chunks"] = np.int64(self.n_chunks)
            k.attrs["tol"] = np.float64(want["tol"])
            k.attrs["period"] = np.int64(want["period"])
            k.create_dataset("done", data=np.zeros(self.n_chunks, dtype=bool))

        _atomic_create(self.path, fill, overwrite=overwrite)

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
        """ndarray of bool, shape (n_chunks,): which chunks are stored (read from the file)."""
        return _read_done(self.path)

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
            arrays[name] = arr.astype(np.int64, copy=False)
        _write_rows(self.path, _RESULT_GROUP, arrays, sl, i, self.fsync)

    def result(self) -> BasinMap:
        """The basin map (rows not yet written hold :data:`BASIN_NOT_COMPUTED` and -1)."""
        result, _ = read(self.path)
        return result
