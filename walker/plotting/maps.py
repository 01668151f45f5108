"""Heat maps over a grid: a basin of attraction (:func:`plot_basin`) and what a parameter sweep
found (:func:`plot_sweep`), both with a categorical legend of outcomes that names the points
not computed yet of a checkpoint; re-exported by :mod:`walker.plotting`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.colors import ListedColormap, Normalize, TwoSlopeNorm
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from walker.plotting.common import (
    OUTLIER_STYLE,
    new_axes,
    robust_limits,
    state_unit,
    with_unit,
)

__all__ = ["outcome_label", "plot_basin", "plot_sweep"]


# BasinMap outcome codes (walker.results.BASIN_CONVERGED / BASIN_UNDECIDED, and
# walker.storage.BASIN_NOT_COMPUTED for the rows of a basin checkpoint not yet computed).
_CONVERGED, _UNDECIDED, _BASIN_NOT_COMPUTED = -1, -2, -3
# A sweep checkpoint's rows not yet computed hold the integer fill value -1 in `status`
# (walker.storage.SweepStore); every Status value is >= 0.
_SWEEP_NOT_COMPUTED = -1
_NOT_COMPUTED_COLOR = "#f2f2f2"
_CATEGORY_COLORS = (
    "#d62728",
    "#1f77b4",
    "#ff7f0e",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#17becf",
    "#bcbd22",
    "#7f7f7f",
    "#000000",
)


def outcome_label(code: int) -> str:
    """Name of a basin outcome code: "converged", "undecided", "not computed" (a row of a
    basin checkpoint not computed yet), or the Status in words."""
    if code == _CONVERGED:
        return "converged"
    if code == _UNDECIDED:
        return "undecided"
    if code == _BASIN_NOT_COMPUTED:
        return "not computed"
    from walker.status import Status

    try:
        return Status(code).name.lower().replace("_", " ")
    except ValueError:
        return f"outcome {code}"


def plot_basin(
    basin_map: Any,
    *,
    outcome_names: Mapping[int, str] | None = None,
    coordinates: tuple[int, int] | None = None,
    axis_units: tuple[str, str] | None = None,
    ax: Axes | None = None,
) -> Figure:
    """Categorical image of a basin of attraction with a legend, fixed point marked.

    Parameters
    ----------
    basin_map : BasinMap
        uses ``x`` (nx,), ``y`` (ny,), ``outcome`` (ny, nx), ``axis_names``,
        ``fixed_point`` (n_z,).
    outcome_names : mapping int -> str, optional
        legend names of outcome codes; default :func:`outcome_label` (undecided as
        "undecided after N strides" when the map has ``n_strides``), each followed by its
        number of points.
    coordinates : (int, int), optional
        section indices of the x and y axes, to place the fixed point; default the map's
        ``coordinates`` attribute if it has one, else (0, 1) when the section has two
        coordinates; with neither, the fixed point is not marked.
    axis_units : (str, str), optional
        units of the two axes; default from ``axis_names`` (:func:`state_unit`).
    ax : Axes, optional

    Returns
    -------
    Figure
        one QuadMesh (``pcolormesh`` at the grid points), a legend with one patch per outcome
        present (points not computed yet, code -3, as "not computed"), a star at the fixed
        point, and axis labels ``"name [unit]"``.
    """
    x = np.asarray(basin_map.x, dtype=float)
    y = np.asarray(basin_map.y, dtype=float)
    outcome = np.asarray(basin_map.outcome)
    if outcome.shape != (y.size, x.size):
        raise ValueError(
            f"`basin_map.outcome` must have shape (ny, nx) = {(y.size, x.size)}, "
            f"got {outcome.shape}"
        )
    fig, ax = new_axes(ax)
    codes = np.unique(outcome)
    index = np.searchsorted(codes, outcome)
    palette = {
        _CONVERGED: "#2ca02c",
        _UNDECIDED: "#bbbbbb",
        _BASIN_NOT_COMPUTED: _NOT_COMPUTED_COLOR,
    }
    others = iter(_CATEGORY_COLORS)
    colors = [palette.get(int(c)) or next(others, "#000000") for c in codes]
    ax.pcolormesh(
        x,
        y,
        index,
        cmap=ListedColormap(colors),
        vmin=-0.5,
        vmax=len(codes) - 0.5,
        shading="nearest",
    )
    names = {int(c): outcome_label(int(c)) for c in codes}
    n_strides = getattr(basin_map, "n_strides", None)
    if n_strides is not None:
        names[_UNDECIDED] = f"undecided after {int(n_strides)} strides"
    names.update({int(k): v for k, v in dict(outcome_names or {}).items()})
    counts = {int(c): int(np.sum(outcome == c)) for c in codes}
    handles = [
        Patch(color=col, label=f"{names[int(c)]} ({counts[int(c)]})")
        for c, col in zip(codes, colors, strict=True)
    ]
    fp = np.asarray(basin_map.fixed_point, dtype=float)
    if coordinates is None:
        coordinates = getattr(basin_map, "coordinates", None)
    if coordinates is None and fp.size == 2:
        coordinates = (0, 1)
    if coordinates is not None:
        ax.plot(
            fp[coordinates[0]], fp[coordinates[1]], marker="*", ms=14, color="w", mec="k", ls="none"
        )
        handles.append(
            Line2D([], [], marker="*", ms=10, color="w", mec="k", ls="none", label="fixed point")
        )
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small")
    axis_names = tuple(getattr(basin_map, "axis_names", ("x", "y")))
    if axis_units is None:
        axis_units = (state_unit(axis_names[0]), state_unit(axis_names[1]))
    ax.set_xlabel(with_unit(axis_names[0], axis_units[0]))
    ax.set_ylabel(with_unit(axis_names[1], axis_units[1]))
    return fig


def _status_label(code: int, fixed_point: bool) -> str:
    """Category name of a sweep status code."""
    if code == _SWEEP_NOT_COMPUTED:
        return "not computed"
    if code == 0:
        return "converged" if fixed_point else "completed"
    from walker.status import Status

    try:
        return Status(code).name.lower().replace("_", " ")
    except ValueError:
        return f"status {code}"


def _status_colors(codes: np.ndarray) -> list[str]:
    others = iter(_CATEGORY_COLORS)
    fixed = {0: "#2ca02c", _SWEEP_NOT_COMPUTED: _NOT_COMPUTED_COLOR}
    return [fixed.get(int(c)) or next(others, "#000000") for c in codes]


def _edges(values: np.ndarray) -> np.ndarray:
    """Cell edges around sorted grid values (midpoints; half a step beyond the ends)."""
    if values.size == 1:  # one value: a cell 10 % of its size wide (1 wide at 0)
        half = 0.05 * abs(float(values[0])) or 0.5
        return np.array([values[0] - half, values[0] + half])
    mid = 0.5 * (values[1:] + values[:-1])
    return np.r_[2 * values[0] - mid[0], mid, 2 * values[-1] - mid[-1]]


def _sweep_summary(status: np.ndarray, fixed_point: bool) -> str:
    n = status.size
    ok = int(np.sum(status == 0))
    missing = int(np.sum(status == _SWEEP_NOT_COMPUTED))
    failed = n - ok - missing
    text = f"{n} points: {ok} {'converged' if fixed_point else 'completed'}, {failed} failed"
    if missing:
        text += f", {missing} not computed"
    return text


def plot_sweep(
    table: Any,
    *,
    parameter_units: Sequence[str] | None = None,
    section_names: Sequence[str] | None = None,
    section_units: Sequence[str] | None = None,
    n_strides: int = 1,
) -> Figure:
    """What a parameter sweep found, against the swept parameter(s).

    A one-parameter sweep is drawn as stacked panels against the parameter: the status of
    each point as a category, the step time, the largest Floquet multiplier modulus (a
    fixed-point sweep) with the stability limit 1, and the section coordinates, one panel per
    unit.  Stable gaits are filled markers, unstable ones open.  A two-parameter sweep is
    drawn as heat maps over parameter 1 (x) and parameter 2 (y): status, step time and the
    largest multiplier modulus (diverging at 1: blue stable, red unstable).  Points not yet
    computed (a sweep checkpoint still running or interrupted, ``status`` -1) are a category
    of their own, "not computed", never a failure, and the title counts them.

    Parameters
    ----------
    table : SweepTable
        uses ``parameter_names`` (k,), ``points`` (n, k) and ``columns``: ``status`` (n,),
        ``step_time`` (n,), ``section`` (n, n_z), and for a fixed-point sweep
        ``multipliers_re``, ``multipliers_im`` (n, n_z) and ``stable`` (n,).
    parameter_units : sequence of str, length k, optional
        units of the swept parameters, shown on the axes.
    section_names : sequence of str, length n_z, optional
        names of the section coordinates; default ``section[j]``.
    section_units : sequence of str, length n_z, optional
        their units; default from the names (:func:`state_unit`).
    n_strides : int
        strides per point (outcome sweep) or the gait's period (fixed-point sweep); labels
        the time axis (step time for 1, time of ``n_strides`` strides otherwise).

    Returns
    -------
    Figure
        1-D: one axes per panel, sharing the parameter axis; the first holds one Line2D per
        status category (label: the category).  2-D: one axes per heat map (a QuadMesh
        each) plus colour bars.

    Raises
    ------
    ValueError
        the sweep varies more than two parameters, or the columns do not match the points.

    Examples
    --------
    >>> import numpy as np
    >>> from walker.results import SweepTable
    >>> table = SweepTable(("slope",), np.array([[0.01], [0.02], [0.03]]), {
    ...     "status": np.array([0, 2, -1]),
    ...     "section": np.array([[0.2, -0.2], [np.nan, np.nan], [np.nan, np.nan]]),
    ...     "step_time": np.array([3.8, np.nan, np.nan])})
    >>> fig = plot_sweep(table, parameter_units=["rad"], section_names=["theta", "theta_dot"])
    >>> fig.axes[0].get_title(), fig.axes[-1].get_xlabel()
    ('3 points: 1 completed, 1 failed, 1 not computed', 'slope [rad]')
    """
    names = tuple(str(n) for n in table.parameter_names)
    points = np.asarray(table.points, dtype=float)
    k = len(names)
    if points.ndim != 2 or points.shape[1] != k:
        raise ValueError(
            f"`table.points` must have shape (n, {k}) for {k} parameter name(s), got {points.shape}"
        )
    if k not in (1, 2):
        raise ValueError(
            f"`table` must be a sweep over 1 or 2 parameters to plot, got {k} ({', '.join(names)})"
        )
    cols = table.columns
    n = points.shape[0]
    status = np.asarray(cols["status"]).astype(int).reshape(n)
    fixed_point = "multipliers_re" in cols
    step = np.asarray(cols.get("step_time", np.full(n, np.nan)), dtype=float).reshape(n)
    largest = None
    stable = np.ones(n, dtype=bool)
    if fixed_point:
        mult = np.asarray(cols["multipliers_re"], dtype=float) + 1j * np.asarray(
            cols["multipliers_im"], dtype=float
        )
        with np.errstate(invalid="ignore"):
            modulus = np.abs(mult).reshape(n, -1)
        largest = np.full(n, np.nan)
        finite = np.all(np.isfinite(modulus), axis=1) & (modulus.shape[1] > 0)
        largest[finite] = modulus[finite].max(axis=1)
        if "stable" in cols:
            stable = np.asarray(cols["stable"]).reshape(n) == 1
    units = list(parameter_units) if parameter_units is not None else [None] * k
    if len(units) != k:
        raise ValueError(f"`parameter_units` must have {k} entries, got {len(units)}")
    codes = np.unique(status)
    found = _SweepFound(
        status=status,
        codes=codes,
        colors=_status_colors(codes),
        labels=[_status_label(int(c), fixed_point) for c in codes],
        step=step,
        largest=largest,
        time_label="step time [s]" if n_strides == 1 else f"time of {n_strides} strides [s]",
        summary=_sweep_summary(status, fixed_point),
    )
    if k == 1:
        sec = np.asarray(cols["section"], dtype=float).reshape(n, -1) if "section" in cols else None
        return _plot_sweep_1d(
            points[:, 0],
            with_unit(names[0], units[0]),
            found,
            stable & (status == 0),
            sec,
            section_names,
            section_units,
            fixed_point,
            n_strides,
        )
    labels_xy = (with_unit(names[0], units[0]), with_unit(names[1], units[1]))
    return _plot_sweep_2d(points, labels_xy, found)


@dataclasses.dataclass(frozen=True)
class _SweepFound:
    """What both sweep figures draw: each point's status, its categories (``codes``, sorted,
    with their ``colors`` and ``labels``), the step time, the largest multiplier modulus
    (None: not a fixed-point sweep), the time axis' label and the title."""

    status: np.ndarray
    codes: np.ndarray
    colors: list[str]
    labels: list[str]
    step: np.ndarray
    largest: np.ndarray | None
    time_label: str
    summary: str


def _plot_sweep_1d(
    x, xlabel, found, stable, sec, section_names, section_units, fixed_point, n_strides
) -> Figure:
    status, codes, colors, labels = found.status, found.codes, found.colors, found.labels
    step, largest, time_label, summary = found.step, found.largest, found.time_label, found.summary
    n_z = 0 if sec is None else sec.shape[1]
    sec_names = (
        list(section_names) if section_names is not None else [f"section[{j}]" for j in range(n_z)]
    )
    if len(sec_names) != n_z:
        raise ValueError(f"`section_names` must have {n_z} entries, got {len(sec_names)}")
    sec_units = (
        list(section_units) if section_units is not None else [state_unit(s) for s in sec_names]
    )
    if len(sec_units) != n_z:
        raise ValueError(f"`section_units` must have {n_z} entries, got {len(sec_units)}")
    groups = list(dict.fromkeys(sec_units))
    n_panels = 2 + (largest is not None) + len(groups)
    fig = Figure(figsize=(7.4, 1.2 + 1.9 * n_panels), layout="constrained")
    axes = fig.subplots(
        n_panels, 1, sharex=True, height_ratios=[0.25 + 0.2 * len(codes)] + [1] * (n_panels - 1)
    )
    ok = status == 0

    def draw(ax, y, color, label=None):
        """Filled markers at stable points, open at unstable ones (fixed-point sweeps)."""
        good = ok & np.isfinite(y)
        ax.plot(x[good & stable], y[good & stable], "o", ms=4, color=color, label=label)
        rest = good & ~stable
        if np.any(rest):
            ax.plot(x[rest], y[rest], "o", ms=4, mfc="none", color=color)

    ax = axes[0]
    for i, (code, color, label) in enumerate(zip(codes, colors, labels, strict=True)):
        sel = status == code
        if code == _SWEEP_NOT_COMPUTED:
            ax.plot(x[sel], np.full(sel.sum(), i), "o", ms=5, mfc="none", color="0.6", label=label)
        else:
            ax.plot(x[sel], np.full(sel.sum(), i), "s", ms=5, color=color, label=label)
    ax.set_yticks(range(len(codes)), labels, fontsize="small")
    ax.set_ylim(-0.6, len(codes) - 0.4)
    ax.set_ylabel("status")
    ax.set_title(summary, fontsize="medium")
    panel = 1
    ax = axes[panel]
    draw(ax, step, "C0")
    ax.set_ylabel(time_label)
    if fixed_point and np.any(ok & ~stable):
        ax.legend(
            handles=[
                Line2D([], [], ls="none", marker="o", ms=4, color="k", label="stable"),
                Line2D(
                    [], [], ls="none", marker="o", ms=4, mfc="none", color="k", label="unstable"
                ),
            ],
            loc="upper left",
            bbox_to_anchor=(1.01, 1.0),
            fontsize="small",
            frameon=False,
        )
    if largest is not None:
        panel += 1
        ax = axes[panel]
        ax.axhline(1.0, color="0.5", ls="--", lw=0.8, label="1 (stability limit)")
        lo, hi, outside = robust_limits(np.where(ok, largest, np.nan))
        shown = np.where(outside, np.nan, largest)
        draw(ax, shown, "C3")
        pad = 0.08 * (max(hi, 1.0) - min(lo, 1.0))
        ax.set_ylim(min(lo, 1.0) - pad, max(hi, 1.0) + pad)
        if np.any(outside):
            # drawn at the panel's edge they leave, as crosses, counted in the legend
            edge = np.where(largest[outside] > hi, max(hi, 1.0) + pad, min(lo, 1.0) - pad)
            ax.plot(
                x[outside],
                edge,
                clip_on=False,
                **OUTLIER_STYLE,
                label=f"off scale ({int(outside.sum())}): {_span(largest[outside])}",
            )
        ax.set_ylabel("largest |multiplier| [1]")
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", frameon=False)
    where = "gait at heel strike" if fixed_point else f"state after {n_strides} strides"
    for unit in groups:
        panel += 1
        ax = axes[panel]
        for j in range(n_z):
            if sec_units[j] == unit:
                draw(ax, sec[:, j], f"C{j % 10}", label=with_unit(sec_names[j], unit))
        ax.set_ylabel(with_unit(where, unit), fontsize="small")
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", frameon=False)
    axes[-1].set_xlabel(xlabel)
    return fig


def _span(values: np.ndarray) -> str:
    """``"a to b"`` (or ``"a"``) of the values, 3 significant digits."""
    lo, hi = float(np.min(values)), float(np.max(values))
    return f"{lo:.3g}" if lo == hi else f"{lo:.3g} to {hi:.3g}"


def _plot_sweep_2d(points, labels_xy, found) -> Figure:
    status, codes, colors, labels = found.status, found.codes, found.colors, found.labels
    step, largest, time_label, summary = found.step, found.largest, found.time_label, found.summary
    u1, i1 = np.unique(points[:, 0], return_inverse=True)
    u2, i2 = np.unique(points[:, 1], return_inverse=True)
    cells = i2 * u1.size + i1
    on_grid = u1.size * u2.size == points.shape[0] and np.unique(cells).size == cells.size
    maps = [("status", np.searchsorted(codes, status).astype(float))]
    maps.append((time_label, step))
    if largest is not None:
        maps.append(("largest |multiplier| [1]", largest))
    fig = Figure(figsize=(4.6 * len(maps) + 1.4, 4.4), layout="constrained")
    axes = fig.subplots(1, len(maps), sharex=True, sharey=True, squeeze=False)[0]
    cat_cmap = ListedColormap(colors)
    for ax, (name, values) in zip(axes, maps, strict=True):
        if name == "status":
            cmap, norm = cat_cmap, Normalize(-0.5, len(codes) - 0.5)
        else:
            # robust limits: one far point (|lambda| 198) must not flatten the map; the
            # points outside are drawn as crosses and counted in a legend entry
            lo, hi, outside = robust_limits(values)
            if name.startswith("largest") and lo < 1.0 < hi:
                cmap, norm = "coolwarm", TwoSlopeNorm(1.0, lo, hi)
            else:
                cmap, norm = "viridis", Normalize(lo, hi if hi > lo else lo + 1.0)
        if on_grid:
            grid = np.full((u2.size, u1.size), np.nan)
            grid[i2, i1] = values
            mesh = ax.pcolormesh(
                _edges(u1), _edges(u2), np.ma.masked_invalid(grid), cmap=cmap, norm=norm
            )
        else:
            good = np.isfinite(values)
            mesh = ax.scatter(
                points[good, 0], points[good, 1], c=values[good], cmap=cmap, norm=norm, s=25
            )
        if name != "status" and np.any(outside):
            ax.plot(points[outside, 0], points[outside, 1], **OUTLIER_STYLE)
            ax.legend(
                handles=[
                    Line2D(
                        [],
                        [],
                        **OUTLIER_STYLE,
                        label=f"outside colour range ({int(outside.sum())}): "
                        f"{_span(values[outside])}",
                    )
                ],
                loc="upper center",
                bbox_to_anchor=(0.5, -0.14),
                fontsize="small",
            )
        if name == "status":
            ax.legend(
                handles=[
                    Patch(color=c, label=f"{lab} ({int(np.sum(status == code))})")
                    for code, c, lab in zip(codes, colors, labels, strict=True)
                ],
                loc="upper center",
                bbox_to_anchor=(0.5, -0.14),
                fontsize="small",
                ncols=2,
            )
        else:
            bar = fig.colorbar(mesh, ax=ax, label=name)
            if isinstance(norm, TwoSlopeNorm):  # ticks on both sides of 1
                low, high = float(norm.vmin), float(norm.vmax)
                bar.set_ticks(np.unique(np.r_[np.linspace(low, 1, 4), np.linspace(1, high, 4)]))
        ax.set_title(name, fontsize="medium")
        ax.set_xlabel(labels_xy[0])
    axes[0].set_ylabel(labels_xy[1])
    fig.suptitle(summary, fontsize="medium")
    return fig
