"""What a sweep covers: its parameter grid and the table it fills.

* the grid: ``NAME=START:STOP:COUNT`` / ``NAME=V1,V2,...`` texts (:func:`parse_range`), pairs or
  mappings made into a Cartesian product, last parameter fastest (:func:`grid_points`);
* the checks made before any work: the names against the model's parameters
  (:func:`check_names`), every point against the parameters' bounds and rules
  (:func:`check_points`), and the grid's size against :data:`MAX_SWEEP_POINTS` and
  :func:`walker.results.memory_limit` (:func:`check_grid_size`);
* the table: its columns per kind (:func:`table_columns`), its bytes per point
  (:func:`bytes_per_point`) and the default chunk size (:func:`default_chunk_size`).

:func:`walker.analysis.sweep.sweep` runs the grid; ``walker sweep`` checks its ``--param`` texts
here before it loads anything large.  Everything public here is importable from
:mod:`walker.analysis.sweep` too.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from walker.results import too_large

__all__ = [
    "DEFAULT_CHUNK_POINTS",
    "KINDS",
    "MAX_SWEEP_POINTS",
    "MIN_DEFAULT_CHUNKS",
    "bytes_per_point",
    "check_grid_size",
    "check_names",
    "check_points",
    "default_chunk_size",
    "grid_points",
    "parse_range",
    "table_columns",
]

KINDS = ("outcome", "fixed_point")
"""Valid values of ``kind``."""

DEFAULT_CHUNK_POINTS = {"outcome": 256, "fixed_point": 16}
"""Largest default chunk per kind: a chunk takes roughly 0.1-0.3 s on a 2020s CPU, so the
per-chunk overhead (submit, pickle, one HDF5 write with fsync: a few ms) stays small."""

MIN_DEFAULT_CHUNKS = 16
"""The default chunk size gives at least this many chunks (when there are as many points),
so that a pool of a few workers is balanced and a killed sweep loses little."""

MAX_SWEEP_POINTS = 1_000_000
"""Most points one sweep takes (a 1000 x 1000 grid): hours of work at a few ms per point, a
table of tens of MB.  Cut a larger study into several sweeps."""

_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_RANGE_RULE = (
    "expected NAME=START:STOP:COUNT (COUNT an integer >= 1, values evenly spaced from START "
    "to STOP inclusive) or NAME=V1,V2,... (finite numbers)"
)


# ---------------------------------------------------------------------------------------------
# Grids
# ---------------------------------------------------------------------------------------------


def _finite_float(text: str, what: str, full: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ValueError(
            f"bad parameter range {full!r}: {what} {text!r} is not a number; {_RANGE_RULE}"
        ) from None
    if not math.isfinite(value):
        raise ValueError(
            f"bad parameter range {full!r}: {what} must be finite, got {text!r}; {_RANGE_RULE}"
        )
    return value


def parse_range(text: str) -> tuple[str, np.ndarray]:
    """Parse one parameter range of the command line.

    Parameters
    ----------
    text : str
        ``"NAME=START:STOP:COUNT"``: ``COUNT`` values evenly spaced from ``START`` to ``STOP``
        inclusive (``numpy.linspace``; ``COUNT = 1`` gives ``START``); or ``"NAME=V1,V2,..."``:
        the listed values in the given order (one value is allowed).  Values in the
        parameter's own unit (``walker.params``); whitespace around parts is ignored.

    Returns
    -------
    name : str
    values : ndarray, shape (COUNT,)

    Raises
    ------
    ValueError
        the text does not follow either form; the message quotes it and states the rule.

    Examples
    --------
    >>> parse_range("slope=0.001:0.003:3")
    ('slope', array([0.001, 0.002, 0.003]))
    >>> parse_range("mass_hip=10, 12")
    ('mass_hip', array([10., 12.]))
    """
    if not isinstance(text, str):
        raise TypeError(f"a parameter range must be a str, got {type(text).__name__}")
    name, sep, spec = text.partition("=")
    name = name.strip()
    if not sep or not _NAME.match(name):
        raise ValueError(
            f"bad parameter range {text!r}: it must start with a parameter name and '='; "
            f"{_RANGE_RULE}"
        )
    spec = spec.strip()
    if not spec:
        raise ValueError(f"bad parameter range {text!r}: no values after '='; {_RANGE_RULE}")
    if ":" in spec:
        parts = [s.strip() for s in spec.split(":")]
        if len(parts) != 3:
            raise ValueError(
                f"bad parameter range {text!r}: START:STOP:COUNT needs exactly 3 parts, got "
                f"{len(parts)}; {_RANGE_RULE}"
            )
        start = _finite_float(parts[0], "START", text)
        stop = _finite_float(parts[1], "STOP", text)
        if not re.fullmatch(r"[0-9]+", parts[2]) or int(parts[2]) < 1:
            raise ValueError(
                f"bad parameter range {text!r}: COUNT must be an integer >= 1, got "
                f"{parts[2]!r}; {_RANGE_RULE}"
            )
        count = int(parts[2])
        if count > MAX_SWEEP_POINTS:
            raise ValueError(
                f"bad parameter range {text!r}: COUNT {count:,} is more than a sweep takes "
                f"(at most {MAX_SWEEP_POINTS:,} points); cut the range into several sweeps"
            )
        return name, np.linspace(start, stop, count)
    values = [_finite_float(v.strip(), "value", text) for v in spec.split(",")]
    return name, np.array(values, dtype=np.float64)


def _normalize_ranges(ranges: Any) -> list[tuple[str, np.ndarray]]:
    """``ranges`` as a list of (name, 1-D float array); accepts texts, pairs or a mapping."""
    if isinstance(ranges, str):
        ranges = [ranges]
    if isinstance(ranges, Mapping):
        items = list(ranges.items())
    elif isinstance(ranges, Sequence) or isinstance(ranges, np.ndarray):
        items = list(ranges)
    else:
        raise TypeError(
            "`ranges` must be a sequence of 'NAME=...' texts or (name, values) pairs, or a "
            f"mapping name -> values, got {type(ranges).__name__}"
        )
    if not items:
        raise ValueError("`ranges` must name at least one parameter, got none")
    out: list[tuple[str, np.ndarray]] = []
    for item in items:
        if isinstance(item, str):
            name, values = parse_range(item)
        else:
            try:
                name, values = item
            except (TypeError, ValueError):
                raise TypeError(
                    f"each entry of `ranges` must be a 'NAME=...' text or a (name, values) "
                    f"pair, got {item!r}"
                ) from None
            if not isinstance(name, str) or not _NAME.match(name):
                raise ValueError(f"parameter names in `ranges` must be identifiers, got {name!r}")
            values = _real_values(name, values)
            if not np.all(np.isfinite(values)):
                raise ValueError(f"values of `{name}` in `ranges` must all be finite")
        out.append((name, values))
    names = [n for n, _ in out]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ValueError(f"`ranges` names each parameter at most once; repeated: {dup}")
    check_grid_size([len(v) for _, v in out], "`ranges`")
    return out


def _real_values(name: str, values: Any) -> np.ndarray:
    """The values of one parameter of ``ranges`` as a 1-D float array, or an error naming
    it: booleans, complex numbers and numbers too large for a float are refused."""
    if isinstance(values, np.ndarray) and values.dtype.kind != "O":
        has_bool = values.dtype.kind == "b"
    elif isinstance(values, Sequence | np.ndarray) and not isinstance(values, str):
        flat = np.ravel(np.asarray(values, dtype=object))
        has_bool = any(isinstance(v, bool | np.bool_) for v in flat.tolist())
    else:
        has_bool = isinstance(values, bool | np.bool_)
    if has_bool:
        raise TypeError(f"values of `{name}` in `ranges` must be numbers, got a bool")
    rule = f"values of `{name}` in `ranges` must be a non-empty 1-D array of real numbers"
    try:
        arr = np.asarray(values)
    except (TypeError, ValueError):
        raise ValueError(f"{rule}, got {type(values).__name__}") from None
    if arr.ndim == 0:
        arr = arr[None]
    if arr.dtype.kind == "O" and arr.ndim == 1:
        try:
            arr = np.asarray(values, dtype=np.float64).reshape(-1)
        except OverflowError:
            raise ValueError(
                f"values of `{name}` in `ranges` must all be finite; one is too large for a float"
            ) from None
        except (TypeError, ValueError):
            raise ValueError(f"{rule}, got {values!r}"[:300]) from None
    if arr.ndim != 1 or arr.shape[0] == 0 or arr.dtype.kind not in "iuf":
        raise ValueError(f"{rule}, got shape {arr.shape} dtype {arr.dtype}")
    return arr.astype(np.float64)


def check_grid_size(lengths: Sequence[int], what: str, bytes_per_point: int = 0) -> int:
    """The number of points of a grid with these range ``lengths``, or a ValueError naming
    ``what`` (``"`ranges`"``, ``"--param"``) when it is more than :data:`MAX_SWEEP_POINTS`
    or its table of ``bytes_per_point`` per point does not fit in
    :func:`walker.results.memory_limit`.  Nothing is allocated."""
    n_points = math.prod(int(n) for n in lengths)
    shape = " x ".join(f"{int(n):,}" for n in lengths)
    if n_points > MAX_SWEEP_POINTS:
        raise ValueError(
            f"the grid of {what} has {n_points:,} points ({shape}), more than a sweep takes "
            f"(at most {MAX_SWEEP_POINTS:,}); cut it into several sweeps"
        )
    reason = too_large(n_points * float(bytes_per_point))
    if reason is not None:
        raise ValueError(
            f"the grid of {what} has {n_points:,} points ({shape}), whose table {reason}; "
            "sweep fewer points"
        )
    return n_points


def grid_points(ranges: Any) -> tuple[tuple[str, ...], np.ndarray]:
    """The Cartesian product of parameter ranges, last parameter varying fastest.

    Parameters
    ----------
    ranges : sequence or mapping
        ``"NAME=..."`` texts (:func:`parse_range`), ``(name, values)`` pairs, or a mapping
        ``name -> values``; each name at most once.

    Returns
    -------
    names : tuple of str, length k
    points : ndarray, shape (n, k)
        ``n`` is the product of the range lengths; row ``i`` is one parameter point, in
        C order of the grid (``itertools.product`` order).

    Examples
    --------
    >>> names, pts = grid_points(["a=1,2", "b=0:1:3"])
    >>> names, pts.tolist()
    (('a', 'b'), [[1.0, 0.0], [1.0, 0.5], [1.0, 1.0], [2.0, 0.0], [2.0, 0.5], [2.0, 1.0]])
    """
    items = _normalize_ranges(ranges)
    names = tuple(n for n, _ in items)
    mesh = np.meshgrid(*[v for _, v in items], indexing="ij")
    points = np.stack([m.ravel() for m in mesh], axis=1)
    return names, np.ascontiguousarray(points, dtype=np.float64)


# ---------------------------------------------------------------------------------------------
# Checks of a grid against the model's parameters
# ---------------------------------------------------------------------------------------------


def check_names(stride_map: Any, names: Sequence[str], what: str) -> None:
    valid = tuple(stride_map.params.names())
    for name in names:
        if name not in valid:
            raise ValueError(
                f"unknown parameter `{name}` in {what} for model "
                f"`{getattr(stride_map.model, 'name', stride_map.model)}`; valid names: "
                f"{', '.join(valid)}"
            )


def _point_error(names: Sequence[str], row: np.ndarray, exc: Exception) -> ValueError:
    point = ", ".join(f"{n}={v!r}" for n, v in zip(names, row.tolist(), strict=True))
    return ValueError(f"grid point ({point}) is not valid: {exc}")


def check_points(params: Any, names: Sequence[str], points: np.ndarray) -> None:
    """Every row of ``points`` (values of ``names``) is a valid change of ``params``, or a
    ValueError naming the first bad point and the rule.

    The bounds of each parameter are checked once per distinct value, the cross-field rules
    (``_check_relations``) once per point without building validated copies, so a million
    points take seconds, not minutes.
    """
    from walker.params import _check_bounds, _Params

    if not isinstance(params, _Params) or not dataclasses.is_dataclass(params):
        for row in points:  # a parameter object of another kind: its own validation
            try:
                params.replace(**dict(zip(names, row.tolist(), strict=True)))
            except (TypeError, ValueError) as exc:
                raise _point_error(names, row, exc) from None
        return
    fields = {f.name: f for f in dataclasses.fields(params)}
    for j, name in enumerate(names):
        for value in np.unique(points[:, j]).tolist():
            try:
                _check_bounds(name, value, fields[name].metadata)
            except ValueError as exc:
                row = points[int(np.argmax(points[:, j] == value))]
                raise _point_error(names, row, exc) from None
    if type(params)._check_relations is _Params._check_relations:
        return
    for row in points:
        candidate = params._replace_validated(**dict(zip(names, row.tolist(), strict=True)))
        try:
            candidate._check_relations()
        except (TypeError, ValueError) as exc:
            raise _point_error(names, row, exc) from None


# ---------------------------------------------------------------------------------------------
# The table
# ---------------------------------------------------------------------------------------------


def bytes_per_point(kind: str, n_z: int, n_names: int, gsn: bool = False) -> int:
    """Bytes of one point of a sweep's table: its parameter values and its columns."""
    columns = table_columns(kind, n_z, gsn)
    return 8 * (n_names + sum(math.prod(shape) for _, shape in columns.values()))


def table_columns(kind: str, n_z: int, gsn: bool = False) -> dict[str, tuple[str, tuple[int, ...]]]:
    """Column name -> (dtype, per-point shape) of a sweep table (``gsn``: a fixed-point
    sweep's ``gsn`` column, :func:`fill_gsn`)."""
    cols: dict[str, tuple[str, tuple[int, ...]]] = {
        "status": ("i8", ()),
        "section": ("f8", (n_z,)),
        "step_time": ("f8", ()),
    }
    if kind == "fixed_point":
        cols.update(
            multipliers_re=("f8", (n_z,)),
            multipliers_im=("f8", (n_z,)),
            residual=("f8", ()),
            stable=("i8", ()),
            n_iter=("i8", ()),
            jump=("i8", ()),
            **dict.fromkeys(MEASURE_COLUMNS, ("f8", ())),
        )
        if gsn:
            cols["gsn"] = ("f8", ())
    return cols


MEASURE_COLUMNS = (
    "step_length",
    "speed",
    "energy_lost",
    "cost_of_transport",
    "cost_of_transport_positive",
    "cost_of_transport_absolute",
)
"""The gait measures a fixed-point sweep's table holds per point
(:meth:`walker.analysis.measures.GaitMeasures.to_dict`; NaN where there is no gait)."""


def default_chunk_size(n_points: int, kind: str) -> int:
    """Chunk size used when none is given: depends only on the grid size and ``kind``.

    (Not on the number of workers, so a sweep resumed with other ``jobs`` or another
    executor finds the same chunks.)
    """
    return max(1, min(DEFAULT_CHUNK_POINTS[kind], -(-n_points // MIN_DEFAULT_CHUNKS)))


def fill_measures(point_map, fp, out: dict, i: int) -> None:
    """The gait measures of the gait ``fp`` of ``point_map`` into row ``i`` of a fixed-point
    sweep's table columns ``out`` (:data:`MEASURE_COLUMNS`;
    :func:`walker.analysis.measures.map_cycle_measures`, the numbers of
    :func:`walker.analysis.measures.cycle_measures` at the map's solver settings)."""
    from walker.analysis.measures import map_cycle_measures

    measures = map_cycle_measures(point_map, fp.state, period=int(fp.period))
    for name in MEASURE_COLUMNS:
        out[name][i] = getattr(measures, name)


def fill_gsn(point_map, fp, out: dict, i: int) -> None:
    """The gait sensitivity norm (:func:`walker.analysis.gsn.gait_sensitivity`) of the gait ``fp``
    of ``point_map`` into ``out["gsn"][i]``; left NaN for a gait of period > 1 or one that is not
    stable (the norm is defined for a stable period-one gait), and where a stride the
    linearisation needs fails (its status is not ``COMPLETED``)."""
    from walker.analysis.gsn import gait_sensitivity

    if not (fp.success and bool(fp.stable) and int(fp.period) == 1):
        return
    try:
        out["gsn"][i] = gait_sensitivity(point_map, fp.section).gsn
    except ValueError:
        # The map walks on terrain (the sweep checked it before any work), so this is the
        # norm's own rejection of the gait: a multiplier within rounding of the unit circle,
        # recomputed at the section, says unstable.  No norm: NaN, as documented.
        return
