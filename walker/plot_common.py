"""What every walker figure shares: units from a coordinate's name, ``"name [unit]"`` axis
labels, a new axes without pyplot, runs of equal values (phases, stability) and the check
that an array holds one row per parameter value.

Used by :mod:`walker.plotting`, :mod:`walker.plot_runs`, :mod:`walker.plot_maps` and
:mod:`walker.plot_branch`; importing it draws nothing.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

__all__ = ["check_rows", "equal_runs", "new_axes", "state_unit", "with_unit"]


def state_unit(name: str) -> str:
    """Unit of a state or section coordinate from its name (walker's naming convention).

    Rates (``qd*``, ``dq*``, ``*_dot``) are in rad/s, ``actuator_work`` in J,
    ``saturated_time`` in s; every other coordinate is an angle in rad.

    Examples
    --------
    >>> state_unit("q_stance"), state_unit("qd1"), state_unit("theta_dot")
    ('rad', 'rad/s', 'rad/s')
    """
    if name == "actuator_work":
        return "J"
    if name == "saturated_time":
        return "s"
    if name.startswith(("qd", "dq")) or name.endswith("_dot"):
        return "rad/s"
    return "rad"


def with_unit(name: str, unit: str | None) -> str:
    """``"name [unit]"`` (just ``name`` when ``unit`` is None or empty).

    Examples
    --------
    >>> with_unit("slope", "rad")
    'slope [rad]'
    """
    return f"{name} [{unit}]" if unit else str(name)


def new_axes(ax: Axes | None, **subplot_kw: Any) -> tuple[Figure, Axes]:
    """``(figure, ax)`` for a given ``ax``, or a new 6.4 x 4.8 in figure (no pyplot) and its
    one axes."""
    if ax is None:
        fig = Figure(figsize=(6.4, 4.8), layout="constrained")
        return fig, fig.add_subplot(**subplot_kw)
    if not isinstance(ax, Axes):
        raise TypeError(f"`ax` must be a matplotlib Axes or None, got {type(ax).__name__}")
    return ax.figure, ax


def check_rows(name: str, values: np.ndarray, parameter: np.ndarray, columns: str) -> None:
    """Raise ValueError unless ``values`` (``name`` in the message) is 2-D with one row per
    entry of ``parameter``: shape ``(n, columns)``."""
    if values.ndim != 2 or values.shape[0] != parameter.shape[0]:
        raise ValueError(
            f"`{name}` must have shape (n, {columns}) with n = {parameter.shape[0]}, "
            f"got {values.shape}"
        )


def equal_runs(values: np.ndarray) -> list[tuple[int, int]]:
    """Index ranges [start, stop) of runs of equal consecutive values."""
    values = np.asarray(values)
    if values.size == 0:
        return []
    cuts = np.flatnonzero(values[1:] != values[:-1]) + 1
    starts = np.r_[0, cuts]
    stops = np.r_[cuts, values.size]
    return list(zip(starts.tolist(), stops.tolist(), strict=True))
