"""Short reprs and plain columns of walker's results, for notebooks: every result dataclass
of :mod:`walker.results` prints in a few hundred characters (arrays as shapes), and
``to_dict()`` / ``to_dataframe()`` give its table as plain 1-D columns.  Attached to the
classes when the package is imported (``walker/__init__.py``).
"""

from __future__ import annotations

import dataclasses

import numpy as np

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
from walker.status import Status

REPR_ITEMS = 6
"""Fields a result's repr shows in full before the rest are summarized."""


def _short(value, depth: int = 0) -> str:
    """A short description of one field's value: an array by its shape and dtype (its
    values when it has at most 4), a long string cut, a container by its size."""
    if isinstance(value, np.ndarray):
        if value.size <= 4 and value.ndim <= 1:
            return np.array2string(value, precision=6, separator=", ")
        return f"<{value.dtype} array {value.shape}>"
    if isinstance(value, Status):
        return value.name
    if isinstance(value, float):
        return f"{value:.10g}"
    if isinstance(value, str):
        return repr(value if len(value) <= 60 else value[:57] + "...")
    if dataclasses.is_dataclass(value) and depth == 0:
        return f"<{type(value).__name__}: {len(value) if hasattr(value, '__len__') else ''}>"
    if isinstance(value, list | tuple):
        if len(value) <= 4 and all(isinstance(v, str) for v in value):
            return repr(value)
        if value and all(isinstance(v, Bifurcation) for v in value):
            return "[" + ", ".join(f"{b.kind} at {b.parameter_value:.6g}" for b in value) + "]"
        return f"<{len(value)} items>"
    if isinstance(value, dict):
        if len(value) <= 3 and all(not isinstance(v, np.ndarray) for v in value.values()):
            return "{" + ", ".join(f"{k!r}: {_short(v, 1)}" for k, v in value.items()) + "}"
        more = ", ..." if len(value) > 4 else ""
        return f"<dict of {len(value)}: {', '.join(list(value)[:4])}{more}>"
    return repr(value)


def _short_repr(self) -> str:
    """``ClassName(field=..., ...)`` with arrays as shapes: a few hundred characters
    however large the result."""
    parts = [f"{f.name}={_short(getattr(self, f.name))}" for f in dataclasses.fields(self)]
    return f"{type(self).__name__}({', '.join(parts)})"


def _named(prefix: str, values: np.ndarray, names=None) -> dict[str, np.ndarray]:
    """The columns of a 2-D array, ``<prefix><name>`` (``<prefix><j>`` without names);
    complex columns as ``_re`` and ``_im`` pairs."""
    values = np.asarray(values)
    values = values.reshape(values.shape[0], -1)
    names = list(names) if names is not None and len(names) == values.shape[1] else None
    if names is None and not prefix:
        prefix = "x_"
    out = {}
    for j in range(values.shape[1]):
        key = f"{prefix}{names[j] if names else j}"
        if values.dtype.kind == "c":
            out[f"{key}_re"] = values[:, j].real.copy()
            out[f"{key}_im"] = values[:, j].imag.copy()
        else:
            out[key] = values[:, j].copy()
    return out


def _to_dict(self, names=None) -> dict[str, np.ndarray]:
    """The result as plain columns, ``{name: 1-D array}`` of equal lengths (one row per
    branch point, sweep point, sample, grid point...), ready for ``pandas.DataFrame``.

    Parameters
    ----------
    names : sequence of str, optional
        names of the state (Solution, Trajectory, EventLog) or section (FixedPoint, Branch,
        BasinMap) components; default their indices.
    """
    if isinstance(self, Trajectory):
        return {"t": self.t.copy(), "phase": self.phase.copy(), **_named("", self.x, names)}
    if isinstance(self, EventLog):
        return {
            "t": self.t.copy(),
            "guard": self.guard.copy(),
            "phase_before": self.phase_before.copy(),
            "phase_after": self.phase_after.copy(),
            **_named("pre_", self.x_pre, names),
            **_named("post_", self.x_post, names),
            **_named("impulse_", self.impulse),
        }
    if isinstance(self, Solution):
        traj = self.record if self.record is not None else self.samples
        if traj is None:
            return {"t": np.array([self.t]), **_named("", self.x[None, :], names)}
        return _to_dict(traj, names)
    if isinstance(self, FixedPoint | MapResult):
        z = self.section if isinstance(self, FixedPoint) else self.z
        out = {"status": np.array([int(self.status)]), "step_time": np.array([self.step_time])}
        out.update(_named("section_", z[None, :], names))
        if isinstance(self, FixedPoint):
            out.update(_named("multiplier_", self.multipliers[None, :]))
            out["stable"] = np.array([bool(self.stable)])
            out.update({k: np.array([v]) for k, v in self.measures.items()})
        return out
    if isinstance(self, Branch):
        out = {self.parameter_name: self.parameter.copy()}
        out.update(_named("section_", self.sections, names))
        out["step_time"] = self.step_times.copy()
        out.update(_named("multiplier_", self.multipliers))
        out["stable"] = np.asarray(self.stable).copy()
        out.update({k: np.asarray(v).copy() for k, v in self.measures.items()})
        return out
    if isinstance(self, OrbitDiagram):
        return {self.parameter_name: self.parameter.copy(), **_named("value_", self.values)}
    if isinstance(self, BasinMap):
        gx, gy = np.meshgrid(self.x, self.y)
        ax, ay = self.axis_names
        return {
            ax: gx.ravel(),
            ay: gy.ravel(),
            "outcome": self.outcome.ravel().copy(),
            "strides": self.strides.ravel().copy(),
        }
    if isinstance(self, SweepTable):
        out = {n: self.points[:, j].copy() for j, n in enumerate(self.parameter_names)}
        for key, column in self.columns.items():
            column = np.asarray(column)
            if column.ndim == 1:
                out[key] = column.copy()
            else:
                out.update(_named(f"{key}_", column, names if key == "section" else None))
        return out
    raise TypeError(f"no columns for {type(self).__name__}")  # pragma: no cover


def _to_dataframe(self, names=None):
    """The result's columns (:meth:`to_dict`) as a ``pandas.DataFrame``; pandas is the
    optional extra ``walker-hybrid[dataframe]``."""
    try:
        import pandas
    except ImportError:
        raise ImportError(
            "to_dataframe() needs pandas, the optional extra 'dataframe': "
            "pip install 'walker-hybrid[dataframe]' (or use to_dict())"
        ) from None
    return pandas.DataFrame(_to_dict(self, names))


for _cls in (
    EventLog,
    Trajectory,
    Solution,
    MapResult,
    FixedPoint,
    Bifurcation,
    Branch,
    OrbitDiagram,
    BasinMap,
    SweepTable,
    MfptResult,
):
    _cls.__repr__ = _short_repr
    if _cls not in (Bifurcation, MfptResult):
        _cls.to_dict = _to_dict
        _cls.to_dataframe = _to_dataframe
del _cls
