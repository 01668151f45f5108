"""What every walker figure shares: units from a coordinate's name, ``"name [unit]"`` axis
labels, a new axes without pyplot, runs of equal values (phases, stability) and the check
that an array holds one row per parameter value.

Used by :mod:`walker.plotting`, :mod:`walker.plotting.runs`, :mod:`walker.plotting.maps` and
:mod:`walker.plotting.branch`; importing it draws nothing.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

__all__ = [
    "OUTLIER_STYLE",
    "check_rows",
    "equal_runs",
    "legend_outside",
    "new_axes",
    "robust_limits",
    "state_unit",
    "with_unit",
]

OUTLIER_STYLE = {"marker": "x", "color": "#e6007e", "ls": "none", "ms": 6, "mew": 1.5}
"""How a value outside a figure's colour or axis range is drawn: a magenta cross, with a
legend entry that says how many there are (:func:`robust_limits`)."""


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


def robust_limits(values: np.ndarray, reach: float = 3.0) -> tuple[float, float, np.ndarray]:
    """Colour (or axis) limits that one far value cannot flatten, and which values lie
    outside them.

    Values beyond Tukey's far-out fences, more than ``reach`` interquartile ranges below
    the first or above the third quartile, are outliers; the limits are the smallest and
    largest of the other finite values.  When the quartiles coincide the 2nd to 98th
    percentile range takes the interquartile range's place, and when that is zero too no
    value is an outlier.  Outliers are drawn as such (:data:`OUTLIER_STYLE`).

    Parameters
    ----------
    values : ndarray
        any shape; NaN and inf are ignored.
    reach : float
        the fences' distance from the quartiles, in interquartile ranges.

    Returns
    -------
    (lo, hi, outside)
        ``lo < hi`` (a unit interval around a constant); ``outside`` a boolean array of
        ``values``' shape, True for the finite values below ``lo`` or above ``hi``.

    Examples
    --------
    >>> lo, hi, out = robust_limits(np.r_[np.linspace(0.2, 0.9, 8), 198.0])
    >>> round(hi, 3), int(out.sum())
    (0.9, 1)
    """
    values = np.asarray(values, dtype=float)
    finite = np.isfinite(values)
    outside = np.zeros(values.shape, dtype=bool)
    if not np.any(finite):
        return 0.0, 1.0, outside
    data = values[finite]
    q1, q3 = (float(v) for v in np.percentile(data, (25.0, 75.0)))
    spread = q3 - q1
    if not spread > 0:
        p2, p98 = (float(v) for v in np.percentile(data, (2.0, 98.0)))
        spread = p98 - p2
    if spread > 0:
        inside = data[(data >= q1 - reach * spread) & (data <= q3 + reach * spread)]
    else:
        inside = data
    lo, hi = float(inside.min()), float(inside.max())
    if not hi > lo:
        lo, hi = lo - 0.5, hi + 0.5
    with np.errstate(invalid="ignore"):
        outside = finite & ((values < lo) | (values > hi))
    return lo, hi, outside


def legend_outside(ax: Axes, handles=None, labels=None, **kwargs: Any):
    """A legend to the right of ``ax``, outside the axes, so that it hides no data, one
    entry per label; returns the legend (``None`` when there is nothing to list)."""
    if handles is None:
        handles, found = ax.get_legend_handles_labels()
        labels = found if labels is None else labels
    if not handles:
        return None
    options = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "fontsize": "small"}
    options.update(kwargs)
    if labels is None:
        labels = [h.get_label() for h in handles]
    unique: dict[str, Any] = {}
    for handle, label in zip(handles, labels, strict=True):
        unique.setdefault(str(label), handle)  # one entry per label
    return ax.legend(list(unique.values()), list(unique), **options)
