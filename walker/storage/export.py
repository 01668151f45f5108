"""A stored result's tables in formats other tools read: CSV, MATLAB ``.mat`` and JSON
(``walker export``).

:func:`result_tables` turns any result (every kind :func:`walker.storage.read` returns) into
named tables of plain columns, each column a 1-D array with its unit: state columns take
the names and units of the model's state (from the file's provenance, or the model
registry for files that predate them), complex multipliers become ``_re``/``_im`` pairs,
vector columns one column per component.  :func:`export` writes them:

* ``csv``: one file per table, ``<stem>_<table>.csv``, a header row ``name [unit]``
  (``name`` alone for a dimensionless column), then one row per entry; and
  ``<stem>_provenance.json``, the file's provenance;
* ``mat``: one file (:func:`scipy.io.savemat`), a struct per table (one field per column),
  a struct ``units`` of the same shape, ``kind`` and ``provenance`` (JSON text);
* ``json``: one file, ``{"kind", "provenance", "tables": {table: {"columns": {name:
  [...]}, "units": {name: unit}}}}``, strict JSON (a missing number is ``null``).

Every file is written atomically (a temporary file moved into place).
"""

from __future__ import annotations

import io
import json
import math
import re
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["FORMATS", "export", "result_tables"]

FORMATS = ("csv", "mat", "json")

Table = dict[str, tuple[np.ndarray, str]]


def _state_units(prov: dict) -> tuple[list[str], list[str]]:
    """The state's names and units: the file's ``state_names`` and ``state_units``, else
    (a file that predates them) the model registry's for the file's ``model``."""
    names, units = prov.get("state_names"), prov.get("state_units")
    if isinstance(names, list) and isinstance(units, list) and len(names) == len(units):
        return [str(v) for v in names], [str(v) for v in units]
    from walker.params.registry import STATE_NAMES, STATE_UNITS

    model = prov.get("model")
    return list(STATE_NAMES.get(model, ())), list(STATE_UNITS.get(model, ()))


def _state_labels(prov: dict, n: int) -> tuple[list[str], list[str]]:
    """The names and units of ``n`` state columns (:func:`_state_units`), or ``x0``,
    ``x1``... without units when they do not fit."""
    names, units = _state_units(prov)
    if len(names) != n:
        return [f"x{i}" for i in range(n)], ["" for _ in range(n)]
    return names, units


def _section_labels(prov: dict, n: int | None) -> tuple[list[str], list[str]]:
    """The names and units of ``n`` section columns: the file's ``section_names``, else
    the model's, with the units of the state entries of those names; ``z0``, ``z1``...
    without units when they do not fit."""
    names = prov.get("section_names")
    if not (isinstance(names, list) and (n is None or len(names) == n)):
        try:
            from walker.models import get_model

            names = list(get_model(str(prov.get("model"))).section_names)
        except (ValueError, KeyError, TypeError, AttributeError):
            names = []
    if n is None:
        n = len(names)
    if len(names) != n:
        return [f"z{i}" for i in range(n)], ["" for _ in range(n)]
    unit_of = dict(zip(*_state_units(prov), strict=True))
    return [str(v) for v in names], [unit_of.get(str(v), "") for v in names]


def _parameter_unit(prov: dict, name: str) -> str:
    entry = (prov.get("parameters") or {}).get(name)
    return str(entry.get("unit", "")) if isinstance(entry, dict) else ""


def _vector_columns(table: Table, prefix: str, values, names, units) -> None:
    values = np.asarray(values)
    for j, (name, unit) in enumerate(zip(names, units, strict=True)):
        table[f"{prefix}{name}"] = (values[:, j], unit)


def _complex_columns(table: Table, prefix: str, values) -> None:
    values = np.asarray(values)
    values = values.reshape(values.shape[0], -1)
    for j in range(values.shape[1]):
        table[f"{prefix}{j}_re"] = (values[:, j].real.astype(float), "")
        table[f"{prefix}{j}_im"] = (values[:, j].imag.astype(float), "")


def _measure_columns(table: Table, measures: dict, rows: int) -> None:
    from walker.analysis.measures import unit_of

    for key, value in measures.items():
        column = np.asarray(value, dtype=float).reshape(rows)
        table[f"{key}"] = (column, unit_of(key))


def result_tables(result: Any, provenance: dict) -> dict[str, Table]:
    """The tables of a stored result: table name -> column name -> (1-D array, unit).

    Parameters
    ----------
    result : a result dataclass of :mod:`walker.results` (any kind a file holds)
    provenance : dict
        the file's provenance (:func:`walker.storage.read`'s second value).

    Returns
    -------
    dict
        ``solution``: ``summary``, ``trajectory`` (every stored step, or the samples),
        ``events``; ``fixed_point``: ``summary``, ``history``; ``branch``: ``branch``,
        ``bifurcations``; ``orbit_diagram``: ``orbit``; ``basin``: ``basin`` (one row per
        grid point); ``sweep``: ``sweep``; ``map_result``: ``summary``.
    """
    from walker import results as R

    prov = dict(provenance or {})
    tables: dict[str, Table] = {}
    if isinstance(result, R.Solution):
        names, units = _state_labels(prov, int(result.x.shape[0]))
        summary: Table = {
            "status": (np.array([int(result.status)]), ""),
            "t": (np.array([float(result.t)]), "s"),
            "phase": (np.array([int(result.phase)]), ""),
            "n_strides": (np.array([int(result.n_strides)]), ""),
            "n_events": (np.array([int(result.n_events)]), ""),
            "n_steps": (np.array([int(result.n_steps)]), ""),
        }
        _vector_columns(summary, "final_", result.x[None, :], names, units)
        _measure_columns(summary, {f"measure_{k}": v for k, v in result.measures.items()}, 1)
        tables["summary"] = _fix_measure_units(summary)
        traj = result.record if result.record is not None else result.samples
        if traj is not None:
            trajectory: Table = {"t": (traj.t, "s"), "phase": (traj.phase, "")}
            _vector_columns(trajectory, "", traj.x, names, units)
            tables["trajectory"] = trajectory
        if result.events is not None:
            ev = result.events
            events: Table = {
                "t": (ev.t, "s"),
                "guard": (ev.guard, ""),
                "phase_before": (ev.phase_before, ""),
                "phase_after": (ev.phase_after, ""),
            }
            _vector_columns(events, "pre_", ev.x_pre, names, units)
            _vector_columns(events, "post_", ev.x_post, names, units)
            impulse = np.asarray(ev.impulse).reshape(len(ev), -1)
            for j in range(impulse.shape[1]):
                events[f"impulse_{j}"] = (impulse[:, j], "N s")
            tables["events"] = events
    elif isinstance(result, R.FixedPoint):
        z_names, z_units = _section_labels(prov, int(result.section.shape[0]))
        x_names, x_units = _state_labels(prov, int(result.state.shape[0]))
        summary = {
            "status": (np.array([int(result.status)]), ""),
            "step_time": (np.array([float(result.step_time)]), "s"),
            "residual": (np.array([float(result.residual)]), ""),
            "n_iter": (np.array([int(result.n_iter)]), ""),
            "period": (np.array([int(result.period)]), ""),
            "stable": (np.array([int(bool(result.stable))]), ""),
        }
        _vector_columns(summary, "section_", result.section[None, :], z_names, z_units)
        if result.state.shape[0] == len(x_names):
            _vector_columns(summary, "state_", result.state[None, :], x_names, x_units)
        _complex_columns(summary, "multiplier_", result.multipliers[None, :])
        _measure_columns(summary, {f"measure_{k}": v for k, v in result.measures.items()}, 1)
        tables["summary"] = _fix_measure_units(summary)
        tables["history"] = {
            "iteration": (np.arange(len(result.history)), ""),
            "residual": (np.asarray(result.history, dtype=float), ""),
        }
    elif isinstance(result, R.Branch):
        n = len(result.parameter)
        name = str(result.parameter_name)
        z_names, z_units = _section_labels(prov, int(np.asarray(result.sections).shape[1]))
        branch: Table = {name: (result.parameter, _parameter_unit(prov, name))}
        _vector_columns(branch, "section_", result.sections, z_names, z_units)
        branch["step_time"] = (result.step_times, "s")
        _complex_columns(branch, "multiplier_", result.multipliers)
        branch["stable"] = (np.asarray(result.stable).astype(np.int64), "")
        _measure_columns(branch, result.measures, n)
        tables["branch"] = branch
        bif = result.bifurcations
        bifurcations: Table = {
            "kind": (np.array([b.kind for b in bif], dtype=str), ""),
            name: (np.array([b.parameter_value for b in bif], dtype=float), branch[name][1]),
        }
        if bif:
            _vector_columns(
                bifurcations, "section_", np.array([b.section for b in bif]), z_names, z_units
            )
            _complex_columns(bifurcations, "multiplier_", np.array([b.multipliers for b in bif]))
        tables["bifurcations"] = bifurcations
    elif isinstance(result, R.OrbitDiagram):
        name = str(result.parameter_name)
        values = np.asarray(result.values, dtype=float).reshape(len(result.parameter), -1)
        z_names, z_units = _section_labels(prov, None)
        k = int(result.coordinate)
        coord = z_names[k] if 0 <= k < len(z_names) else f"z{k}"
        unit = z_units[k] if 0 <= k < len(z_units) else ""
        orbit: Table = {name: (result.parameter, _parameter_unit(prov, name))}
        for j in range(values.shape[1]):
            orbit[f"{coord}_{j}"] = (values[:, j], unit)
        tables["orbit"] = orbit
    elif isinstance(result, R.BasinMap):
        ax, ay = (str(v) for v in result.axis_names)
        gx, gy = np.meshgrid(result.x, result.y)
        z_names, z_units = _section_labels(prov, int(result.fixed_point.shape[0]))
        unit_of = dict(zip(z_names, z_units, strict=True))
        tables["basin"] = {
            ax: (gx.ravel(), unit_of.get(ax, "")),
            ay: (gy.ravel(), unit_of.get(ay, "")),
            "outcome": (np.asarray(result.outcome).ravel(), ""),
            "strides": (np.asarray(result.strides).ravel(), ""),
        }
    elif isinstance(result, R.SweepTable):
        n = int(result.points.shape[0])
        sweep: Table = {}
        for j, name in enumerate(result.parameter_names):
            sweep[str(name)] = (result.points[:, j], _parameter_unit(prov, str(name)))
        for key, column in result.columns.items():
            column = np.asarray(column)
            if column.ndim == 1:
                sweep[key] = (column, _sweep_unit(key))
            elif key == "section":
                z_names, z_units = _section_labels(prov, column.shape[1])
                _vector_columns(sweep, "section_", column, z_names, z_units)
            else:
                flat = column.reshape(n, -1)
                for j in range(flat.shape[1]):
                    sweep[f"{key}_{j}"] = (flat[:, j], "")
        tables["sweep"] = sweep
    elif isinstance(result, R.MapResult):
        z_names, z_units = _section_labels(prov, int(result.z.shape[0]))
        summary = {
            "status": (np.array([int(result.status)]), ""),
            "step_time": (np.array([float(result.step_time)]), "s"),
        }
        _vector_columns(summary, "z_", result.z[None, :], z_names, z_units)
        tables["summary"] = summary
    else:
        raise TypeError(f"`result` must be a walker result, got {type(result).__name__}")
    return tables


def _fix_measure_units(table: Table) -> Table:
    from walker.analysis.measures import unit_of

    return {
        key: (col, unit_of(key.removeprefix("measure_")) if key.startswith("measure_") else unit)
        for key, (col, unit) in table.items()
    }


def _sweep_unit(key: str) -> str:
    from walker.analysis.measures import unit_of

    if key == "step_time":
        return "s"
    if key in ("status", "stable", "n_iter", "residual"):
        return ""
    return unit_of(key)


# ---------------------------------------------------------------------------------------
# writers


def _header(name: str, unit: str) -> str:
    return name if unit in ("", "1") else f"{name} [{unit}]"


def _csv_cell(value: Any) -> str:
    if isinstance(value, str | np.str_):
        text = str(value)
        return f'"{text}"' if any(c in text for c in ',"\n') else text
    if isinstance(value, float | np.floating):
        return "" if math.isnan(value) else repr(float(value))
    return str(int(value)) if isinstance(value, int | np.integer | bool | np.bool_) else str(value)


def _csv_bytes(table: Table) -> bytes:
    names = list(table)
    lines = [",".join(_header(n, table[n][1]) for n in names)]
    columns = [table[n][0] for n in names]
    rows = len(columns[0]) if columns else 0
    for i in range(rows):
        lines.append(",".join(_csv_cell(col[i]) for col in columns))
    return ("\n".join(lines) + "\n").encode()


def _jsonable(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return [_jsonable(v) for v in value.tolist()]
    if isinstance(value, float | np.floating):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.integer | np.bool_):
        return value.item()
    if isinstance(value, complex):
        return [value.real, value.imag]
    if hasattr(value, "name") and hasattr(value, "value"):  # an enum (Status)
        return value.name
    return value


_MAT_NAME = re.compile(r"[^A-Za-z0-9_]")


def _mat_name(name: str, taken: set[str]) -> str:
    """A MATLAB field name for ``name``: letters, digits and underscores, starting with a
    letter, at most 63 characters, not one already ``taken``."""
    field = _MAT_NAME.sub("_", name) or "x"
    if not field[0].isalpha():
        field = "x" + field
    field = field[:63]
    base, k = field, 1
    while field in taken:
        suffix = f"_{k}"
        field, k = base[: 63 - len(suffix)] + suffix, k + 1
    taken.add(field)
    return field


def _mat_bytes(kind: str, provenance: dict, tables: dict[str, Table]) -> bytes:
    from scipy.io import savemat

    content: dict[str, Any] = {"kind": kind, "provenance": json.dumps(_jsonable(provenance))}
    units: dict[str, Any] = {}
    taken_tables = {"kind", "provenance", "units"}
    for table_name, table in tables.items():
        field = _mat_name(table_name, taken_tables)
        taken: set[str] = set()
        struct, struct_units = {}, {}
        for name, (column, unit) in table.items():
            key = _mat_name(name, taken)
            col = np.asarray(column)
            struct[key] = col.astype(object) if col.dtype.kind in "US" else col
            struct_units[key] = unit
        content[field] = struct
        units[field] = struct_units
    content["units"] = units
    buffer = io.BytesIO()
    savemat(buffer, content, long_field_names=True, do_compression=True, oned_as="column")
    return buffer.getvalue()


def _json_bytes(kind: str, provenance: dict, tables: dict[str, Table]) -> bytes:
    record = {
        "kind": kind,
        "provenance": _jsonable(provenance),
        "tables": {
            name: {
                "columns": {col: _jsonable(np.asarray(v)) for col, (v, _) in table.items()},
                "units": {col: unit for col, (_, unit) in table.items()},
            }
            for name, table in tables.items()
        },
    }
    return json.dumps(record, allow_nan=False).encode()


def export_paths(out: Path, fmt: str, tables) -> list[Path]:
    """The files :func:`export` writes for ``out``: ``out`` itself for ``mat`` and
    ``json``; for ``csv`` ``<stem>_<table>.csv`` per table and ``<stem>_provenance.json``
    next to ``out`` (``out`` with or without its ``.csv``)."""
    if fmt != "csv":
        return [out]
    stem = out.name[: -len(".csv")] if out.name.endswith(".csv") else out.name
    names = [*tables, "provenance"]
    return [
        out.with_name(f"{stem}_{t}.json" if t == "provenance" else f"{stem}_{t}.csv") for t in names
    ]


def export(
    result: Any,
    provenance: dict,
    out: str | Path,
    fmt: str,
    *,
    overwrite: bool = False,
) -> list[Path]:
    """Write the tables of ``result`` (:func:`result_tables`) as ``fmt`` to ``out``.

    Parameters
    ----------
    result : a result dataclass
    provenance : dict
        the file's provenance; stored with the tables.
    out : str or Path
        the file to write (``mat``, ``json``), or for ``csv`` the stem of the files
        (:func:`export_paths`).
    fmt : {"csv", "mat", "json"}
    overwrite : bool
        replace existing files.

    Returns
    -------
    list of Path
        the files written.

    Raises
    ------
    ValueError
        an unknown ``fmt``.
    FileExistsError
        a target exists and ``overwrite`` is False (nothing is written then).
    """
    from walker.storage.disk import _atomic_write

    if fmt not in FORMATS:
        raise ValueError(f"`fmt` must be one of {', '.join(FORMATS)}, got {fmt!r}")
    kind = str(provenance.get("kind", type(result).__name__))
    tables = result_tables(result, provenance)
    paths = export_paths(Path(out), fmt, tables)
    if not overwrite:
        existing = [p for p in paths if p.exists()]
        if existing:
            raise FileExistsError(f"'{existing[0]}' exists; pass overwrite=True to replace it")
    if fmt == "csv":
        images = [_csv_bytes(t) for t in tables.values()]
        images.append(json.dumps(_jsonable(provenance), allow_nan=False, indent=1).encode())
    elif fmt == "mat":
        images = [_mat_bytes(kind, provenance, tables)]
    else:
        images = [_json_bytes(kind, provenance, tables)]
    for path, image in zip(paths, images, strict=True):
        _atomic_write(path, image, overwrite)
    return paths
