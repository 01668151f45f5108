"""The file format: the schema version, the limits, the errors, and how each field of each
result dataclass is stored (``_SPECS``), with the shape rules of each class
(``_shape_problem``).  ``docs/storage.md`` describes the layout; this module checks at
import that ``_SPECS`` covers every field of every class in :mod:`walker.results`.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

from walker.results import (
    BasinMap,
    Bifurcation,
    Branch,
    EventLog,
    FixedPoint,
    MapResult,
    MfptResult,
    OrbitDiagram,
    Solution,
    SweepTable,
    Trajectory,
)

SCHEMA_VERSION = 2
"""Version of the file layout written by walker.storage; files with a larger one are refused.
Version 2 added the checksums (Fletcher-32 on datasets, the root ``checksum`` attribute and
``/checkpoint/chunk_sha256``); version-1 files are still read and resumed, unchecked."""

AUTOMATIC_KEYS = ("walker_version", "schema_version", "kind", "created")
"""Provenance keys set by :func:`write` itself; a caller may not pass them."""

READ_TIMEOUT = 60.0
"""Seconds a checked read may take, plus one per 50 MB of file, before it is abandoned as
a hang (:func:`read` ``timeout``)."""

MAX_COMPRESSION_RATIO = 64
"""Largest expansion allowed of a compressed (deflate) dataset: one declaring more bytes than
this times its stored size is refused before any of it is decompressed.  walker itself never
compresses; deflate (up to 1032:1) is read only from files repacked by other tools, and
walker's numbers (floats) compress far less than 64:1, while a decompression bomb needs
about 1000:1."""

MAX_DECOMPRESSED_BYTES = 32 << 20
"""Largest total of declared bytes of a file's compressed datasets [bytes] (32 MiB): beyond it
a file is refused before any of them is decompressed, so that reading a small compressed file
stays within about 200 MiB of memory whatever its compressed datasets declare."""

MAX_PERIOD = 1_000_000
"""Largest ``period`` (strides of a gait cycle) of a stored fixed point or branch: the
command line's and the scenes' limit on strides (``walker.scene.MAX_STRIDES``).  A file
declaring more is refused on read: the figures of a branch run ``period`` strides per
point and size arrays by it."""

MAX_SECTION_COORDINATES = 256
"""A stored section coordinate index (an orbit diagram's ``coordinate``) must be below this:
walker's models have sections of at most a few dozen coordinates."""

_COUNT_MAX = 1 << 62  # a counter of steps, evaluations, strides, iterations

_INT_RANGES: dict[type, dict[str, tuple[int, int]]] = {
    Solution: {
        "phase": (0, 1 << 31),
        **{k: (0, _COUNT_MAX) for k in ("n_steps", "n_rejected", "n_rhs", "n_events")},
        "n_strides": (0, _COUNT_MAX),
    },
    FixedPoint: {"n_iter": (0, _COUNT_MAX), "period": (1, MAX_PERIOD)},
    Branch: {"period": (1, MAX_PERIOD)},
    OrbitDiagram: {"coordinate": (0, MAX_SECTION_COORDINATES - 1)},
    BasinMap: {"n_strides": (0, _COUNT_MAX)},
}
"""The range of each integer field walker writes, checked on read before the value is used
(``(lowest, highest)``, both allowed)."""

WRITE_ATTEMPTS = 4
"""Attempts of a checkpoint chunk write that fails with a transient error (backoff 0.05 s,
0.2 s, 0.8 s) before it is a :class:`StorageError`."""

_RESULT_GROUP = "result"
_CHECKPOINT_GROUP = "checkpoint"
_CHECKSUM_ATTR = "checksum"
_CHUNK_SHA = "chunk_sha256"
_RESERVED_ATTRS = frozenset(AUTOMATIC_KEYS) | {"provenance", _CHECKSUM_ATTR}

BASIN_NOT_COMPUTED = -3
"""Outcome held by the grid points of a :class:`BasinStore` whose rows are not computed yet
(a :class:`~walker.results.BasinMap`'s codes are ``BASIN_CONVERGED`` (-1),
``BASIN_UNDECIDED`` (-2) and :class:`~walker.status.Status` values, all >= -2)."""


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
#   "optional_array_dict"  the same, absent in files written before the field existed
#                     (read as {}) and when the dict is empty
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
        "measures": "optional_json",
    },
    MapResult: {
        "status": "status",
        "z": "array",
        "jac": "optional_array",
        "step_time": "float",
        "state": "array",
        "terrain_jac": "optional_array",
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
        "measures": "optional_json",
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
        "measures": "optional_array_dict",
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
        "classification": "optional_json",
    },
    SweepTable: {
        "parameter_names": "names",
        "points": "array",
        "columns": "array_dict",
    },
    MfptResult: {
        "mfpt": "float",
        "mfpt_stderr": "float",
        "runs": "int",
        "failed": "int",
        "steps": "array",
        "status": "array",
        "rate": "float",
        "max_steps": "int",
        "slope_mean": "float",
        "slope_std": "float",
        "height_std": "float",
        "seed": "int",
        "start": "array",
        "markov": "json",
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
    "mfpt": MfptResult,
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

    def along(name: str, *checks: Any) -> tuple[str, str] | None:
        """``first`` of ``check(n)`` for each of ``checks``, once the field ``name`` (whose
        length n sizes the others) is 1-D."""
        a = v[name]
        if a.ndim != 1:
            return name, f"must be 1-D, got shape {a.shape}"
        return first(*(lambda check=check: check(a.shape[0]) for check in checks))

    if cls is EventLog:
        return along(
            "t",
            *(lambda n, k=k: vector(k, n, "iu") for k in ("guard", "phase_before", "phase_after")),
            lambda n: matrix("x_pre", n),
            lambda n: matrix("x_post", n, v["x_pre"].shape[1]),
            lambda n: matrix("impulse", n),
        )
    if cls is Trajectory:
        return along("t", lambda n: matrix("x", n), lambda n: vector("phase", n, "iu"))
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
        return along("z", lambda n_z: matrix("jac", n_z, n_z), lambda n_z: vector("state"))
    if cls is FixedPoint:
        return along(
            "section",
            lambda n_z: vector("state"),
            lambda n_z: vector("multipliers", n_z),
            lambda n_z: matrix("eigenvectors", n_z, n_z),
            lambda n_z: matrix("jacobian", n_z, n_z),
            lambda n_z: vector("history"),
        )
    if cls is Bifurcation:
        return first(lambda: vector("section"), lambda: vector("multipliers"))
    if cls is Branch:
        return along(
            "parameter",
            lambda n: matrix("sections", n),
            lambda n: vector("step_times", n),
            lambda n: matrix("multipliers", n),
            lambda n: vector("stable", n, "b"),
            lambda n: next(
                (
                    (f"measures/{key}", f"must be of shape ({n},), got shape {col.shape}")
                    for key, col in v["measures"].items()
                    if col.shape != (n,) or col.dtype.kind not in "biuf"
                ),
                None,
            ),
        )
    if cls is OrbitDiagram:
        return along("parameter", lambda n: matrix("values", n))
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
    if cls is MfptResult:
        return first(
            lambda: vector("start"),
            lambda: along(
                "steps",
                lambda n: vector("status", n, "iu"),
                lambda n: None if v["steps"].dtype.kind in "iu" else ("steps", "must be integers"),
            ),
            lambda: (
                None
                if v["steps"].shape[0] == v["runs"]
                else ("steps", f"must have `runs` = {v['runs']} entries, got {v['steps'].shape[0]}")
            ),
        )
    return None  # pragma: no cover - every class in _SPECS is handled above
