"""Figures and animations of walker results (matplotlib; never ``pyplot.show``).

Every function takes result objects from :mod:`walker.results` (duck typed: any object with
the same attributes works, including results read back by :mod:`walker.storage`), computes no
physics, and returns the :class:`~matplotlib.figure.Figure` it drew on.  Pass ``ax=`` to draw
into an existing axes; otherwise a new figure is made with ``matplotlib.figure.Figure`` (not
pyplot), so nothing accumulates in pyplot's figure registry and no display is needed.

Examples
--------
>>> import numpy as np
>>> from walker.results import Trajectory
>>> from walker.plotting import plot_angles
>>> t = np.linspace(0.0, 2.0, 50)
>>> traj = Trajectory(t, np.stack([np.sin(t), -np.sin(t), np.cos(t), -np.cos(t)], axis=1),
...                   (t > 1.0).astype(int))
>>> fig = plot_angles(traj, state_names=["theta", "phi", "theta_dot", "phi_dot"])
>>> len(fig.axes)
2
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib import animation
from matplotlib.axes import Axes
from matplotlib.colors import ListedColormap, Normalize, TwoSlopeNorm
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

__all__ = [
    "animate_walker",
    "outcome_label",
    "plot_angles",
    "plot_basin",
    "plot_bifurcation",
    "plot_energy",
    "plot_multipliers",
    "plot_orbit_diagram",
    "plot_phase_portrait",
    "plot_sweep",
    "plot_torques",
    "plot_work_precision",
    "plot_zero_dynamics",
    "WORK_PRECISION_ERROR",
    "state_unit",
    "with_unit",
]

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


def _new_axes(ax: Axes | None, **subplot_kw: Any) -> tuple[Figure, Axes]:
    if ax is None:
        fig = Figure(figsize=(6.4, 4.8), layout="constrained")
        return fig, fig.add_subplot(**subplot_kw)
    if not isinstance(ax, Axes):
        raise TypeError(f"`ax` must be a matplotlib Axes or None, got {type(ax).__name__}")
    return ax.figure, ax


def _trajectory_of(obj: Any, argname: str) -> tuple[Any, Any]:
    """(trajectory, events) from a Solution (record, else samples) or a Trajectory."""
    if (
        hasattr(obj, "t")
        and hasattr(obj, "x")
        and hasattr(obj, "phase")
        and not hasattr(obj, "record")
    ):
        return obj, None
    traj = getattr(obj, "record", None)
    if traj is None:
        traj = getattr(obj, "samples", None)
    if traj is None:
        raise ValueError(
            f"`{argname}` has neither `record` nor `samples`; run with output 'samples' or "
            "'full', or pass a Trajectory"
        )
    return traj, getattr(obj, "events", None)


def _runs(values: np.ndarray) -> list[tuple[int, int]]:
    """Index ranges [start, stop) of runs of equal consecutive values."""
    values = np.asarray(values)
    if values.size == 0:
        return []
    cuts = np.flatnonzero(values[1:] != values[:-1]) + 1
    starts = np.r_[0, cuts]
    stops = np.r_[cuts, values.size]
    return list(zip(starts.tolist(), stops.tolist(), strict=True))


def plot_angles(
    solution_or_trajectory: Any,
    *,
    state_names: Sequence[str] | None = None,
    phase_names: Sequence[str] | None = None,
    ax: Sequence[Axes] | None = None,
) -> Figure:
    """Angles (first half of the state) and rates (second half) against time.

    Parameters
    ----------
    solution_or_trajectory : Solution or Trajectory
        a Solution plots its ``record`` (else ``samples``) and marks its ``events`` as
        vertical lines; a Trajectory has ``t`` (n,), ``x`` (n, n_x) and ``phase`` (n,).
    state_names : sequence of str, length n_x, optional
        default ``x[0]``, ``x[1]``, ...
    phase_names : sequence of str, optional
        names of the phase indices, for the legend of the shaded spans; default the
        Solution's ``phase_names``, else ``phase 0``, ...  Phases with the same name share
        a colour and a legend entry; only phases that occur in the run are listed.
    ax : pair of Axes, optional
        (angles axes, rates axes).

    Returns
    -------
    Figure
        two axes; one line per coordinate on each, one shaded span per run of equal phase,
        one vertical line per event on each.
    """
    traj, events = _trajectory_of(solution_or_trajectory, "solution_or_trajectory")
    t = np.asarray(traj.t, dtype=float)
    x = np.asarray(traj.x, dtype=float)
    phase = np.asarray(traj.phase)
    if x.ndim != 2 or x.shape[0] != t.shape[0] or x.shape[1] % 2:
        raise ValueError(
            f"`x` must have shape (n, n_x) with n = len(t) = {t.shape[0]} and n_x even, "
            f"got {x.shape}"
        )
    n_x = x.shape[1]
    names = list(state_names) if state_names is not None else [f"x[{i}]" for i in range(n_x)]
    if len(names) != n_x:
        raise ValueError(f"`state_names` must have {n_x} entries, got {len(names)}")
    if phase_names is None:
        phase_names = getattr(solution_or_trajectory, "phase_names", None) or ()
    phase_names = list(phase_names)
    if ax is None:
        fig = Figure(figsize=(7.0, 5.6), layout="constrained")
        ax_q, ax_v = fig.subplots(2, 1, sharex=True)
    else:
        if len(ax) != 2 or not all(isinstance(a, Axes) for a in ax):
            raise TypeError("`ax` must be a pair of Axes (angles, rates) or None")
        ax_q, ax_v = ax
        fig = ax_q.figure
    half = n_x // 2
    for i in range(half):
        ax_q.plot(t, x[:, i], label=names[i])
        ax_v.plot(t, x[:, half + i], label=names[half + i])
    # Shade each run of equal phase, one colour (and one legend entry) per phase name:
    # phases that share a name (e.g. friction modes left out of the names) share a colour.
    seen: dict[str, Patch] = {}
    for start, stop in _runs(phase):
        p = int(phase[start])
        label = phase_names[p] if 0 <= p < len(phase_names) else f"phase {p}"
        if label not in seen:
            seen[label] = Patch(color=f"C{len(seen) % 10}", alpha=0.12, label=label)
        t0 = t[start]
        t1 = t[stop] if stop < t.size else t[-1]
        for a in (ax_q, ax_v):
            a.axvspan(t0, t1, color=seen[label].get_facecolor()[:3], alpha=0.12, lw=0)
    if events is not None:
        for te in np.asarray(events.t, dtype=float):
            for a in (ax_q, ax_v):
                a.axvline(te, color="k", lw=0.8, ls=":")
    ax_q.set_ylabel("angle [rad]")
    ax_v.set_ylabel("rate [rad/s]")
    ax_v.set_xlabel("time [s]")
    handles, _ = ax_q.get_legend_handles_labels()
    ax_q.legend(handles=handles + list(seen.values()), loc="best", fontsize="small")
    ax_v.legend(loc="best", fontsize="small")
    return fig


def plot_phase_portrait(
    trajectory: Any,
    i: int,
    j: int,
    *,
    fixed_point: Any = None,
    state_names: Sequence[str] | None = None,
    units: Sequence[str] | None = None,
    ax: Axes | None = None,
) -> Figure:
    """State coordinate ``j`` against coordinate ``i``.

    Parameters
    ----------
    trajectory : Trajectory or Solution
        a Solution contributes its ``record`` (else ``samples``).
    i, j : int
        state indices on the horizontal and vertical axes.
    fixed_point : FixedPoint or ndarray, shape (n_x,), optional
        marked with a star at ``(state[i], state[j])`` (a FixedPoint's ``state``).
    state_names : sequence of str, optional
        axis labels; default ``x[i]``.
    units : sequence of str, length n_x, optional
        units of the state coordinates, shown in the axis labels; default from the names
        (:func:`state_unit`), and for the default names rad for the first half of the state
        and rad/s for the second.
    ax : Axes, optional

    Returns
    -------
    Figure
        one line per run of equal phase (a reset starts a new line); axis labels
        ``"name [unit]"``.
    """
    traj, _ = _trajectory_of(trajectory, "trajectory")
    x = np.asarray(traj.x, dtype=float)
    n_x = x.shape[1]
    for name, k in (("i", i), ("j", j)):
        if not 0 <= k < n_x:
            raise ValueError(f"`{name}` must be a state index in [0, {n_x}), got {k}")
    fig, ax = _new_axes(ax)
    t = np.asarray(traj.t, dtype=float)
    # A new piece at every phase change and every repeated time (a reset within a phase).
    breaks = np.asarray(traj.phase)[1:] != np.asarray(traj.phase)[:-1]
    breaks |= t[1:] <= t[:-1]
    cuts = np.r_[0, np.flatnonzero(breaks) + 1, t.size]
    for start, stop in zip(cuts[:-1], cuts[1:], strict=True):
        ax.plot(x[start:stop, i], x[start:stop, j], color="C0", lw=1.0)
    if fixed_point is not None:
        state = np.asarray(getattr(fixed_point, "state", fixed_point), dtype=float)
        ax.plot(state[i], state[j], marker="*", ms=12, color="C3", ls="none", label="fixed point")
        ax.legend(loc="best", fontsize="small")
    if state_names is not None:
        names = list(state_names)
        default_units = [state_unit(n) for n in names]
    else:
        names = [f"x[{k}]" for k in range(n_x)]
        default_units = ["rad" if k < n_x // 2 else "rad/s" for k in range(n_x)]
    units = list(units) if units is not None else default_units
    ax.set_xlabel(with_unit(names[i], units[i]))
    ax.set_ylabel(with_unit(names[j], units[j]))
    return fig


def plot_energy(
    t: np.ndarray,
    kinetic: np.ndarray,
    potential: np.ndarray,
    *,
    event_times: np.ndarray | None = None,
    event_energies: np.ndarray | None = None,
    unit: str = "J",
    ax: Axes | None = None,
) -> Figure:
    """Kinetic, potential and total energy against time, with the jump at each impact.

    Parameters
    ----------
    t : ndarray, shape (n,)
        times [s], non-decreasing; a reset may appear as two samples at the same time
        (before, then after).
    kinetic, potential : ndarray, shape (n,)
        energies [J] at ``t``.
    event_times : ndarray, shape (m,), optional
        impact times [s]: a vertical segment marks the change of the total energy at each,
        labelled with its size in J; an event at which the energy does not change (to
        1e-9 of the largest total energy) gets neither segment nor label.
    event_energies : ndarray, shape (m, 2), optional
        total energy [J] just before and just after each event in ``event_times``, computed
        from the event's own pre- and post-impact states (on the same reference as
        ``potential``).  Without it the change is read from the samples next to each event
        time, which also holds whatever energy flows in between (actuator work, damping)
        unless the samples bracket the reset at the same time; an event outside the
        sampled times is then left out.
    unit : str
        unit of the energies (and of the "J" above), on the axis and the labels; ``"J/kg"``
        for a model whose energies are per unit mass.
    ax : Axes, optional

    Returns
    -------
    Figure
        three lines (kinetic, potential, total), and a LineCollection of the jumps (label
        "impact loss") with one text per jump when any event changes the energy.
    """
    t = np.asarray(t, dtype=float)
    kinetic = np.asarray(kinetic, dtype=float)
    potential = np.asarray(potential, dtype=float)
    if t.ndim != 1 or kinetic.shape != t.shape or potential.shape != t.shape:
        raise ValueError(
            f"`t`, `kinetic` and `potential` must be 1-D of equal length, got {t.shape}, "
            f"{kinetic.shape}, {potential.shape}"
        )
    fig, ax = _new_axes(ax)
    total = kinetic + potential
    ax.plot(t, kinetic, label="kinetic")
    ax.plot(t, potential, label="potential")
    ax.plot(t, total, label="total", color="k")
    if event_times is not None and t.size:
        te = np.asarray(event_times, dtype=float).ravel()
        if event_energies is not None:
            pairs = np.asarray(event_energies, dtype=float)
            if pairs.shape != (te.size, 2):
                raise ValueError(
                    f"`event_energies` must have shape (m, 2) with m = len(event_times) = "
                    f"{te.size}, got {pairs.shape}"
                )
            e0, e1 = pairs[:, 0], pairs[:, 1]
            keep = np.ones(te.size, dtype=bool)
        else:
            lo = np.searchsorted(t, te, side="left")
            hi = np.searchsorted(t, te, side="right")
            twice = hi - lo >= 2  # samples before and after the reset at the event time
            before = np.where(twice, lo, np.maximum(lo - 1, 0))
            after = np.where(twice, hi - 1, np.minimum(hi, t.size - 1))
            e0, e1 = total[before], total[after]
            keep = after > before  # samples on both sides of the event
        scale = float(np.max(np.abs(total))) if total.size else 1.0
        keep &= np.abs(e1 - e0) > 1e-9 * max(scale, 1e-300)
        te, e0, e1 = te[keep], e0[keep], e1[keep]
        if te.size:
            ax.vlines(
                te,
                np.minimum(e0, e1),
                np.maximum(e0, e1),
                colors="C3",
                lw=2.0,
                label="impact loss",
            )
        for time, a, b in zip(te, e0, e1, strict=True):
            ax.annotate(
                f"{b - a:+.5g} {unit}",
                (time, min(a, b)),
                textcoords="offset points",
                xytext=(3, -10),
                fontsize="x-small",
                color="C3",
            )
    ax.set_xlabel("time [s]")
    ax.set_ylabel(with_unit("energy", unit))
    ax.legend(loc="best", fontsize="small")
    return fig


def plot_multipliers(
    branch: Any, ax: Axes | None = None, *, parameter_unit: str | None = None
) -> Figure:
    """Floquet multipliers in the complex plane with the unit circle: along a branch (root
    locus, coloured by the parameter) or of one gait.

    Parameters
    ----------
    branch : Branch
        uses ``parameter`` (n,), ``multipliers`` (n, n_z) complex, ``parameter_name``; a
        single gait is a branch of one point.
    ax : Axes, optional
    parameter_unit : str, optional
        unit of the parameter, shown on the colour bar's label.

    Returns
    -------
    Figure
        one scatter (PathCollection) of the multipliers and the unit circle (one line).
        When the parameter takes more than one value the points are coloured by it and a
        colour bar labelled ``"parameter_name [unit]"`` is added; otherwise there is no
        colour bar and the legend gives the largest modulus.
    """
    mult = np.asarray(branch.multipliers)
    param = np.asarray(branch.parameter, dtype=float)
    if mult.ndim != 2 or mult.shape[0] != param.shape[0]:
        raise ValueError(
            f"`branch.multipliers` must have shape (n, n_z) with n = {param.shape[0]}, "
            f"got {mult.shape}"
        )
    fig, ax = _new_axes(ax)
    angle = np.linspace(0.0, 2.0 * np.pi, 361)
    ax.plot(np.cos(angle), np.sin(angle), color="0.5", lw=0.8, ls="--", label="unit circle")
    finite = param[np.isfinite(param)]
    varies = finite.size > 1 and float(np.ptp(finite)) > 0
    if varies:
        colors = np.repeat(param, mult.shape[1])
        sc = ax.scatter(mult.real.ravel(), mult.imag.ravel(), c=colors, s=12, cmap="viridis")
        name = str(getattr(branch, "parameter_name", "") or "parameter")
        fig.colorbar(sc, ax=ax, label=with_unit(name, parameter_unit))
    else:
        modulus = np.abs(mult.ravel())
        largest = float(np.nanmax(modulus)) if np.any(np.isfinite(modulus)) else float("nan")
        ax.scatter(
            mult.real.ravel(),
            mult.imag.ravel(),
            s=18,
            color="C0",
            label=f"multipliers, largest |.| = {largest:.4g}",
        )
        ax.legend(loc="upper left", bbox_to_anchor=(0.0, -0.12), fontsize="small")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("Re(multiplier) [1]")
    ax.set_ylabel("Im(multiplier) [1]")
    return fig


def plot_bifurcation(branch: Any, *, coordinate: int = 0, ax: Axes | None = None) -> Figure:
    """Section coordinate against the parameter: stable solid, unstable dashed.

    Parameters
    ----------
    branch : Branch
        uses ``parameter`` (n,), ``sections`` (n, n_z), ``stable`` (n,), ``parameter_name``,
        ``bifurcations`` (each with ``kind``, ``parameter_value``, ``section``).
    coordinate : int
        which section coordinate to plot.
    ax : Axes, optional

    Returns
    -------
    Figure
        one line per run of equal stability (neighbouring runs share their end point), one
        marker line for the bifurcations with a text label each.
    """
    param = np.asarray(branch.parameter, dtype=float)
    sections = np.asarray(branch.sections, dtype=float)
    stable = np.asarray(branch.stable, dtype=bool)
    if sections.ndim != 2 or not 0 <= coordinate < sections.shape[1]:
        raise ValueError(
            f"`coordinate` must be in [0, {sections.shape[1] if sections.ndim == 2 else 0}), "
            f"got {coordinate}"
        )
    fig, ax = _new_axes(ax)
    y = sections[:, coordinate]
    labelled = set()
    for start, stop in _runs(stable):
        s = bool(stable[start])
        stop_incl = min(stop + 1, param.size)  # join to the next run
        label = ("stable" if s else "unstable") if s not in labelled else None
        labelled.add(s)
        ax.plot(
            param[start:stop_incl],
            y[start:stop_incl],
            color="C0",
            ls="-" if s else "--",
            label=label,
        )
    bifs = list(getattr(branch, "bifurcations", []) or [])
    if bifs:
        bx = [float(b.parameter_value) for b in bifs]
        by = [float(np.asarray(b.section)[coordinate]) for b in bifs]
        ax.plot(bx, by, ls="none", marker="o", mfc="none", color="C3", label="bifurcation")
        short = {"period_doubling": "PD", "fold": "LP"}
        for b, px, py in zip(bifs, bx, by, strict=True):
            ax.annotate(
                short.get(b.kind, b.kind),
                (px, py),
                textcoords="offset points",
                xytext=(4, 4),
                fontsize="small",
                color="C3",
            )
    ax.set_xlabel(str(getattr(branch, "parameter_name", "parameter")))
    ax.set_ylabel(f"section coordinate {coordinate}")
    ax.legend(loc="best", fontsize="small")
    return fig


def plot_orbit_diagram(orbit_diagram: Any, ax: Axes | None = None) -> Figure:
    """Settled section values at each parameter value (dots; NaN where the walker fell).

    Parameters
    ----------
    orbit_diagram : OrbitDiagram
        uses ``parameter`` (n,), ``values`` (n, n_keep), ``parameter_name``, ``coordinate``.
    ax : Axes, optional

    Returns
    -------
    Figure
        one scatter (PathCollection) of the finite values.
    """
    param = np.asarray(orbit_diagram.parameter, dtype=float)
    values = np.asarray(orbit_diagram.values, dtype=float)
    if values.ndim != 2 or values.shape[0] != param.shape[0]:
        raise ValueError(
            f"`orbit_diagram.values` must have shape (n, n_keep) with n = {param.shape[0]}, "
            f"got {values.shape}"
        )
    fig, ax = _new_axes(ax)
    px = np.repeat(param, values.shape[1])
    py = values.ravel()
    ok = np.isfinite(py)
    ax.scatter(px[ok], py[ok], s=1.5, color="k", marker=".", linewidths=0)
    ax.set_xlabel(str(getattr(orbit_diagram, "parameter_name", "parameter")))
    ax.set_ylabel(f"section coordinate {getattr(orbit_diagram, 'coordinate', 0)}")
    return fig


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
    fig, ax = _new_axes(ax)
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
    time_label = "step time [s]" if n_strides == 1 else f"time of {n_strides} strides [s]"
    codes = np.unique(status)
    colors = _status_colors(codes)
    labels = [_status_label(int(c), fixed_point) for c in codes]
    summary = _sweep_summary(status, fixed_point)
    if k == 1:
        sec = np.asarray(cols["section"], dtype=float).reshape(n, -1) if "section" in cols else None
        return _plot_sweep_1d(
            points[:, 0],
            with_unit(names[0], units[0]),
            status,
            codes,
            colors,
            labels,
            step,
            largest,
            stable & (status == 0),
            sec,
            section_names,
            section_units,
            fixed_point,
            n_strides,
            time_label,
            summary,
        )
    return _plot_sweep_2d(
        points,
        (with_unit(names[0], units[0]), with_unit(names[1], units[1])),
        status,
        codes,
        colors,
        labels,
        step,
        largest,
        time_label,
        summary,
    )


def _plot_sweep_1d(
    x,
    xlabel,
    status,
    codes,
    colors,
    labels,
    step,
    largest,
    stable,
    sec,
    section_names,
    section_units,
    fixed_point,
    n_strides,
    time_label,
    summary,
) -> Figure:
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
        draw(ax, largest, "C3")
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


def _plot_sweep_2d(
    points, labels_xy, status, codes, colors, labels, step, largest, time_label, summary
) -> Figure:
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
            finite = values[np.isfinite(values)]
            lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
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


def plot_torques(
    t: np.ndarray,
    torques: np.ndarray,
    *,
    names: Sequence[str] | None = None,
    limit: float | None = None,
    event_times: np.ndarray | None = None,
    ax: Axes | None = None,
) -> Figure:
    """Actuator torques against time, with the torque limit and the impacts marked.

    Parameters
    ----------
    t : ndarray, shape (n,)
        time [s].
    torques : ndarray, shape (n, m)
        applied torques [N m], one column per actuator.
    names : sequence of str, length m, optional
    limit : float, optional
        saturation limit [N m]; drawn as dashed lines at +-limit.
    event_times : ndarray, optional
        impact times [s]; vertical dotted lines.
    ax : Axes, optional

    Returns
    -------
    Figure
        one line per actuator (plus the limit lines).
    """
    fig, ax = _new_axes(ax)
    t = np.asarray(t, dtype=float)
    torques = np.atleast_2d(np.asarray(torques, dtype=float))
    if torques.shape[0] != t.shape[0]:
        raise ValueError(
            f"`torques` must have one row per time, got {torques.shape[0]} rows for "
            f"{t.shape[0]} times"
        )
    names = list(names) if names is not None else [f"u{j}" for j in range(torques.shape[1])]
    for j in range(torques.shape[1]):
        ax.plot(t, torques[:, j], label=names[j])
    if limit is not None:
        for sign in (1.0, -1.0):
            ax.axhline(sign * limit, color="0.4", linestyle="--", linewidth=0.8)
    for te in np.asarray(event_times if event_times is not None else [], dtype=float):
        ax.axvline(te, color="0.6", linestyle=":", linewidth=0.8)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("torque [N m]")
    ax.legend(loc="best")
    return fig


def plot_zero_dynamics(
    theta: np.ndarray,
    theta_dot: np.ndarray,
    *,
    theta_plus: float | None = None,
    theta_minus: float | None = None,
    ax: Axes | None = None,
) -> Figure:
    """The zero dynamics' phase portrait: phase variable rate against the phase variable,
    with the section ends ``theta_plus`` (just after impact) and ``theta_minus`` (impact).

    Parameters
    ----------
    theta, theta_dot : ndarray, shape (n,)
        phase variable [rad] and its rate [rad/s] along a (closed-loop) run.
    theta_plus, theta_minus : float, optional
        drawn as two vertical lines of their own colour and style (``theta+`` dashed,
        ``theta-`` dotted), each labelled with its value.
    ax : Axes, optional

    Returns
    -------
    Figure
        the orbit (one line, broken at each impact), then a line for ``theta_plus`` and
        one for ``theta_minus`` when given.
    """
    fig, ax = _new_axes(ax)
    theta = np.asarray(theta, dtype=float)
    theta_dot = np.asarray(theta_dot, dtype=float)
    # break the line at impacts (the phase variable jumps back), so the reset is not drawn
    # as a trajectory
    span = np.ptp(theta) if theta.size else 0.0
    cuts = np.flatnonzero(np.abs(np.diff(theta)) > 0.25 * span) + 1 if span > 0 else []
    theta = np.insert(theta, cuts, np.nan)
    theta_dot = np.insert(theta_dot, cuts, np.nan)
    ax.plot(theta, theta_dot, label="orbit", color="C0")
    ends = (
        (theta_plus, "theta+", "step starts", "C2", "--"),
        (theta_minus, "theta-", "impact", "C3", ":"),
    )
    for value, name, meaning, color, style in ends:
        if value is not None:
            ax.axvline(
                value,
                color=color,
                linestyle=style,
                linewidth=1.5,
                label=f"{name} = {value:.4g} rad ({meaning})",
            )
    ax.set_xlabel("phase variable theta [rad]")
    ax.set_ylabel("theta_dot [rad/s]")
    ax.legend(loc="best")
    return fig


WORK_PRECISION_ERROR = "error: max-norm of the final state minus a reference run's [rad, rad/s]"
"""Default error-axis label of :func:`plot_work_precision`: the error of a run is the largest
absolute difference, over the state's components, between its final state and that of a
reference run at a much tighter tolerance."""


def plot_work_precision(
    table: Mapping[str, tuple[np.ndarray, np.ndarray]],
    ax: Axes | None = None,
    *,
    error_label: str = WORK_PRECISION_ERROR,
) -> Figure:
    """Work-precision diagram: run time against error, log-log, one line per method.

    Parameters
    ----------
    table : mapping method name -> (errors, times)
        equal-length arrays; errors (as defined by ``error_label``) and wall times [s], one
        entry per tolerance.
    ax : Axes, optional
    error_label : str
        the error axis' label, which defines the error and gives its unit; default
        :data:`WORK_PRECISION_ERROR`.

    Returns
    -------
    Figure
        one line with markers per method; the legend is outside the axes, to the right, so
        it hides no curve.
    """
    if not isinstance(table, Mapping) or not table:
        raise ValueError("`table` must be a non-empty mapping method -> (errors, times)")
    fig, ax = _new_axes(ax)
    for k, (method, (errors, times)) in enumerate(table.items()):
        errors = np.asarray(errors, dtype=float)
        times = np.asarray(times, dtype=float)
        if errors.shape != times.shape or errors.ndim != 1:
            raise ValueError(
                f"`table[{method!r}]` must hold 1-D errors and times of equal length, "
                f"got {errors.shape} and {times.shape}"
            )
        ax.loglog(errors, times, marker="os^vD<>ph*"[k % 10], label=str(method))
    ax.set_xlabel(str(error_label))
    ax.set_ylabel("time [s]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small", frameon=False)
    return fig


def animate_walker(
    frames: np.ndarray,
    segments: Sequence[tuple[int, int]],
    *,
    slope: float = 0.0,
    interval_ms: float = 33.0,
    path: str | Path | None = None,
) -> animation.FuncAnimation:
    """Stick-figure animation of a walker; optionally saved as GIF or MP4.

    Parameters
    ----------
    frames : ndarray, shape (n_frames, n_points, 2)
        joint positions [m] in the world frame (x horizontal, walking toward +x; y up).
    segments : sequence of (int, int)
        pairs of point indices drawn as links.
    slope : float
        ground angle [rad]; the ground is drawn through the origin as
        ``y = -tan(slope) x`` (downhill toward +x).
    interval_ms : float
        time between frames [ms]; the file's frame rate is ``1000 / interval_ms``.
    path : str or Path, optional
        ``*.gif`` (written with Pillow) or ``*.mp4`` (needs ffmpeg,
        ``matplotlib.animation.writers.is_available("ffmpeg")``).

    Returns
    -------
    matplotlib.animation.FuncAnimation
        its figure is ``anim._fig``; one Line2D per segment and one for the joints.
    """
    frames = np.asarray(frames, dtype=float)
    if frames.ndim != 3 or frames.shape[2] != 2 or frames.shape[0] == 0:
        raise ValueError(
            f"`frames` must have shape (n_frames, n_points, 2) with n_frames >= 1, "
            f"got {frames.shape}"
        )
    n_points = frames.shape[1]
    segs = [tuple(int(v) for v in s) for s in segments]
    for s in segs:
        if len(s) != 2 or not all(0 <= v < n_points for v in s):
            raise ValueError(
                f"`segments` must be pairs of point indices in [0, {n_points}), got {s}"
            )
    if not interval_ms > 0:
        raise ValueError(f"`interval_ms` must be positive, got {interval_ms}")
    writer_cls = None
    if path is not None:
        path = Path(path)
        suffix = path.suffix.lower()
        if suffix == ".gif":
            writer_cls = animation.PillowWriter
        elif suffix == ".mp4":
            if not animation.writers.is_available("ffmpeg"):
                raise ValueError(
                    f"`path` {str(path)!r} asks for MP4 but ffmpeg is not available; "
                    "use a .gif path"
                )
            writer_cls = animation.FFMpegWriter
        else:
            raise ValueError(f"`path` must end in .gif or .mp4, got {str(path)!r}")
        if not path.parent.is_dir():
            raise FileNotFoundError(f"directory '{path.parent}' of `path` does not exist")

    fig = Figure(figsize=(6.4, 3.6), layout="constrained")
    ax = fig.add_subplot()
    lo = np.nanmin(frames.reshape(-1, 2), axis=0)
    hi = np.nanmax(frames.reshape(-1, 2), axis=0)
    pad = 0.1 * max(float(np.max(hi - lo)), 1e-9)
    gx = np.array([lo[0] - pad, hi[0] + pad])
    ax.plot(gx, -np.tan(slope) * gx, color="0.4", lw=1.5)  # ground
    ax.set_xlim(gx)
    ax.set_ylim(min(lo[1], float(np.min(-np.tan(slope) * gx))) - pad, hi[1] + pad)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    links = [ax.plot([], [], color="C0", lw=2.5, solid_capstyle="round")[0] for _ in segs]
    joints = ax.plot([], [], ls="none", marker="o", ms=4, color="k")[0]

    def draw(k: int) -> list[Line2D]:
        pts = frames[k]
        for line, (a, b) in zip(links, segs, strict=True):
            line.set_data(pts[[a, b], 0], pts[[a, b], 1])
        joints.set_data(pts[:, 0], pts[:, 1])
        return [*links, joints]

    anim = animation.FuncAnimation(
        fig, draw, frames=frames.shape[0], interval=interval_ms, blit=False, repeat=False
    )
    if writer_cls is not None:
        anim.save(str(path), writer=writer_cls(fps=1000.0 / interval_ms))
    return anim
