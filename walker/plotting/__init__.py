"""Figures and animations of walker results (matplotlib; never ``pyplot.show``).

Every function takes result objects from :mod:`walker.results` (duck typed: any object with
the same attributes works, including results read back by :mod:`walker.storage`), computes no
physics, and returns the :class:`~matplotlib.figure.Figure` it drew on.  Pass ``ax=`` to draw
into an existing axes; otherwise a new figure is made with ``matplotlib.figure.Figure`` (not
pyplot), so nothing accumulates in pyplot's figure registry and no display is needed.

Every figure is imported from here; each lives in the module of its kind:

* this module: figures of the analysis along a parameter or a tolerance
  (:func:`plot_multipliers`, :func:`plot_bifurcation`, :func:`plot_orbit_diagram`,
  :func:`plot_work_precision`);
* :mod:`walker.plotting.runs`: figures of one run (angles, energy, phase portrait, torques, zero
  dynamics) and :func:`animate_walker`;
* :mod:`walker.plotting.maps`: heat maps over a grid (:func:`plot_basin`, :func:`plot_sweep`);
* :mod:`walker.plotting.terrain`: rough-ground measures (:func:`plot_survival`,
  :func:`plot_mfpt_roughness`, :func:`plot_gsn_sweep`, :func:`plot_walk_on_terrain`);
* :mod:`walker.plotting.common`: units and ``"name [unit]"`` labels (:func:`state_unit`,
  :func:`with_unit`) and the axes helper all of them use;
* :mod:`walker.plotting.branch`: a branch's measures (step length, speed, cost of transport).

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

from collections.abc import Mapping
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from walker.plotting.common import (
    check_rows,
    equal_runs,
    legend_outside,
    new_axes,
    state_unit,
    with_unit,
)
from walker.plotting.maps import outcome_label, plot_basin, plot_sweep
from walker.plotting.runs import (
    animate_walker,
    plot_angles,
    plot_energy,
    plot_phase_portrait,
    plot_torques,
    plot_zero_dynamics,
)
from walker.plotting.terrain import (
    plot_gsn_sweep,
    plot_mfpt_roughness,
    plot_survival,
    plot_walk_on_terrain,
)

__all__ = [
    "BIFURCATION_NAMES",
    "animate_walker",
    "outcome_label",
    "plot_angles",
    "plot_basin",
    "plot_bifurcation",
    "plot_energy",
    "plot_gsn_sweep",
    "plot_mfpt_roughness",
    "plot_multipliers",
    "plot_orbit_diagram",
    "plot_phase_portrait",
    "plot_survival",
    "plot_sweep",
    "plot_torques",
    "plot_walk_on_terrain",
    "plot_work_precision",
    "plot_zero_dynamics",
    "WORK_PRECISION_ERROR",
    "state_unit",
    "with_unit",
]


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
    check_rows("branch.multipliers", mult, param, "n_z")
    fig, ax = new_axes(ax)
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


BIFURCATION_NAMES = {"fold": "fold (LP)", "period_doubling": "period doubling (PD)"}
"""Legend names of the bifurcation kinds: the plain word and the usual abbreviation (LP,
limit point; PD, period doubling)."""


def plot_bifurcation(
    branch: Any,
    *,
    coordinate: int = 0,
    ax: Axes | None = None,
    parameter_unit: str | None = None,
    coordinate_name: str | None = None,
    coordinate_unit: str | None = None,
    cycle_sections: np.ndarray | None = None,
    color: str = "C0",
) -> Figure:
    """Section coordinate against the parameter: stable solid, unstable dashed.

    Parameters
    ----------
    branch : Branch
        uses ``parameter`` (n,), ``sections`` (n, n_z), ``stable`` (n,), ``parameter_name``,
        ``bifurcations`` (each with ``kind``, ``parameter_value``, ``section``).
    coordinate : int
        which section coordinate to plot.
    ax : Axes, optional
    parameter_unit : str, optional
        unit of the parameter, on the x axis (``"name [unit]"``).
    coordinate_name : str, optional
        name of the section coordinate, default ``"section coordinate k"``; the y axis reads
        ``"name just after heel strike [unit]"``.
    coordinate_unit : str, optional
        its unit; default :func:`state_unit` of the name (``"rad"`` without a name).
    cycle_sections : ndarray, shape (n, period, n_z), optional
        every point of each gait cycle (point 0 is ``sections``): a period-2 orbit is drawn
        as its two points, two curves.  Default ``sections`` alone.
    color : str
        colour of the branch's curves (to draw a second branch into the same ``ax``).

    Returns
    -------
    Figure
        per point of the cycle, one line per run of equal stability (neighbouring runs share
        their end point); one marker line per bifurcation kind present, labelled in words
        and abbreviation (:data:`BIFURCATION_NAMES`), each point with its abbreviation;
        the legend outside the axes.
    """
    param = np.asarray(branch.parameter, dtype=float)
    sections = np.asarray(branch.sections, dtype=float)
    stable = np.asarray(branch.stable, dtype=bool)
    if sections.ndim != 2 or not 0 <= coordinate < sections.shape[1]:
        raise ValueError(
            f"`coordinate` must be in [0, {sections.shape[1] if sections.ndim == 2 else 0}), "
            f"got {coordinate}"
        )
    if cycle_sections is None:
        cycle = sections[:, None, :]
    else:
        cycle = np.asarray(cycle_sections, dtype=float)
        if cycle.ndim != 3 or cycle.shape[0] != param.size or cycle.shape[2] != sections.shape[1]:
            raise ValueError(
                f"`cycle_sections` must have shape (n, period, n_z) = ({param.size}, period, "
                f"{sections.shape[1]}), got {cycle.shape}"
            )
    fig, ax = new_axes(ax)
    labelled = set()
    period = cycle.shape[1]
    for point in range(period):
        y = cycle[:, point, coordinate]
        for start, stop in equal_runs(stable):
            s = bool(stable[start])
            stop_incl = min(stop + 1, param.size)  # join to the next run
            label = None
            if s not in labelled:
                label = ("stable" if s else "unstable") + (
                    f" (period {period}: {period} points)" if period > 1 else ""
                )
            labelled.add(s)
            ax.plot(
                param[start:stop_incl],
                y[start:stop_incl],
                color=color,
                ls="-" if s else "--",
                label=label,
            )
    bifs = list(getattr(branch, "bifurcations", []) or [])
    markers = {"fold": ("s", "C3"), "period_doubling": ("o", "C1")}
    for kind in dict.fromkeys(b.kind for b in bifs):
        chosen = [b for b in bifs if b.kind == kind]
        bx = [float(b.parameter_value) for b in chosen]
        by = [float(np.asarray(b.section)[coordinate]) for b in chosen]
        marker, color = markers.get(kind, ("D", "C4"))
        ax.plot(
            bx,
            by,
            ls="none",
            marker=marker,
            mfc="none",
            mew=1.5,
            color=color,
            label=BIFURCATION_NAMES.get(kind, str(kind).replace("_", " ")),
        )
        short = {"period_doubling": "PD", "fold": "LP"}.get(kind, str(kind))
        for px, py in zip(bx, by, strict=True):
            ax.annotate(
                short,
                (px, py),
                textcoords="offset points",
                xytext=(5, 5),
                fontsize="small",
                color=color,
            )
    name = coordinate_name or f"section coordinate {coordinate}"
    if coordinate_unit is None:
        coordinate_unit = state_unit(coordinate_name) if coordinate_name else "rad"
    ax.set_xlabel(
        with_unit(str(getattr(branch, "parameter_name", "") or "parameter"), parameter_unit)
    )
    ax.set_ylabel(with_unit(f"{name} just after heel strike", coordinate_unit))
    legend_outside(ax)
    return fig


def plot_orbit_diagram(
    orbit_diagram: Any,
    ax: Axes | None = None,
    *,
    parameter_unit: str | None = None,
    coordinate_name: str | None = None,
    coordinate_unit: str | None = None,
) -> Figure:
    """Settled section values at each parameter value (dots; NaN where the walker fell):
    :func:`walker.plotting.branch.plot_orbit_diagram`.

    Parameters
    ----------
    orbit_diagram : OrbitDiagram
        uses ``parameter`` (n,), ``values`` (n, n_keep), ``parameter_name``, ``coordinate``.
    ax : Axes, optional
    parameter_unit : str, optional
        unit of the parameter, on the x axis.
    coordinate_name, coordinate_unit : str, optional
        the recorded section coordinate's name and unit, on the y axis (default
        ``"section coordinate k"`` in rad).

    Returns
    -------
    Figure
        one scatter (PathCollection) of the finite values, and red crosses on the x axis
        where the walker fell.
    """
    from walker.plotting.branch import plot_orbit_diagram as draw

    return draw(
        orbit_diagram,
        parameter_unit=parameter_unit or "",
        coordinate_name=coordinate_name,
        coordinate_unit=coordinate_unit
        if coordinate_unit is not None
        else (None if coordinate_name else "rad"),
        ax=ax,
    )


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
    fig, ax = new_axes(ax)
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
