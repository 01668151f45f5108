"""Figures of gait branches and orbit diagrams: what a gait does as a parameter changes.

Two steps, kept apart (plot functions compute no physics):

1. :func:`branch_measures` turns a :class:`~walker.results.Branch` into the quantities a
   researcher asks about, per branch point: step time, step length, walking speed, cost of
   transport and the largest Floquet multiplier modulus.  It runs the model (one stride per
   step of the gait cycle, from each fixed point) to get the steps' lengths and times.
2. :func:`plot_branch` draws them against the continued parameter, and
   :func:`plot_orbit_diagram` draws an :class:`~walker.results.OrbitDiagram`; both return
   a :class:`~matplotlib.figure.Figure` (made without pyplot) and put units on every axis
   (the parameter's from :mod:`walker.params`).

:func:`result_figures` (:func:`stored_figures` for a file) does both for a result of
``walker continue`` or ``walker orbit-diagram``, for ``walker plot``; the period-doubled
branch that ``walker continue --switch`` writes next to its ``--out`` is drawn with its
parent.

Definitions (each gait cycle of ``period`` strides; step ``j`` is stride ``j`` of it):

* **step time** ``T_j`` [s]: time from one heel strike to the next.
* **step length** ``d_j`` [m]: distance, along the slope, by which the walker advances in
  the step: from the stance foot's ground contact just after the heel strike that starts
  the step to the swing foot's ground contact at the heel strike that ends it, both taken in
  the stance leg's frame (``points`` of the model: row 0 the stance contact, row
  ``SWING_FOOT`` (default the last) the swing contact).  For point feet this is the distance
  between the feet at heel strike; with round feet it includes the stance foot's roll.
* **walking speed** ``v = sum_j d_j / sum_j T_j`` [m/s], the cycle's mean.
* **mechanical cost of transport** ``c = E / (m g d)`` [1]: the energy ``E`` the walker
  dissipates (impacts and joint dampers) per step over its weight ``m g`` (``m`` the total
  mass) times the distance ``d`` it travels, summed over the cycle.  On a periodic gait of a
  passive walker the configuration and the velocities repeat, shifted by ``d`` along the
  slope, so the kinetic energy returns and every joule dissipated is potential energy
  released: the centre of mass descends ``d sin(slope)`` per step, ``E = m g d sin(slope)``,
  hence ``c = sin(slope)`` exactly, whatever the masses, the step or the dissipation (with
  ``d`` measured horizontally it would be ``tan(slope)``).  Walkers with actuators (models
  ``three_link``, ``five_link``) are not passive: their ``c`` is the positive actuator work
  per weight and distance when the branch carries its measures (``Branch.measures``,
  :mod:`walker.analysis.measures`, written by ``walker continue``), else NaN.  A passive branch
  with measures draws its stored cost of transport, the energy lost per weight and
  distance (``sin(slope)`` again, now computed from the energies).
* **largest |multiplier|** [1]: the modulus of the largest Floquet multiplier; the gait is
  stable where it is below 1.

Examples
--------
>>> import numpy as np
>>> from walker.results import Branch
>>> from walker.status import Status
>>> from walker.plotting.branch import BranchMeasures, plot_branch
>>> mu = np.linspace(0.01, 0.02, 5)
>>> lam = np.array([[0.5, 0.2], [0.7, 0.2], [0.9, 0.2], [1.1, 0.2], [1.3, 0.2]], complex)
>>> br = Branch("slope", mu, np.zeros((5, 2)), np.full(5, 1.0), lam, abs(lam[:, 0]) < 1, [],
...             Status.COMPLETED, "", True)
>>> m = BranchMeasures.from_arrays(br, step_time=np.ones((5, 1)), step_length=np.ones((5, 1)),
...                                parameter_unit="rad")
>>> fig = plot_branch(br, m)
>>> fig.axes[0].get_xlabel() == "" and fig.axes[-1].get_xlabel()
'slope [rad]'
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from walker.plotting.common import check_rows, equal_runs, legend_outside, with_unit

__all__ = [
    "BranchMeasures",
    "branch_measures",
    "companion_branch",
    "plot_branch",
    "plot_orbit_diagram",
    "result_figures",
    "section_unit",
    "stored_figures",
]


BIFURCATION_LABELS = {"fold": "fold", "period_doubling": "period doubling"}
_SHORT = {"fold": "LP", "period_doubling": "PD"}


@dataclass
class BranchMeasures:
    """Gait quantities along a branch (see the module docstring for the definitions).

    Attributes
    ----------
    parameter_name : str
    parameter_unit : str
    parameter : ndarray, shape (n,)
    step_time : ndarray, shape (n, period)
        time of each step of the cycle [``time_unit``]; NaN where a stride failed.
    step_length : ndarray, shape (n, period)
        advance of each step along the slope [``length_unit``].
    speed : ndarray, shape (n,)
        mean walking speed over the cycle [``length_unit``/``time_unit``].
    cost_of_transport : ndarray, shape (n,)
        mechanical cost of transport [1] (NaN for actuated walkers).
    max_multiplier : ndarray, shape (n,)
        largest Floquet multiplier modulus [1].
    stable : ndarray of bool, shape (n,)
    period : int
    time_unit, length_unit : str
    notes : list of str
    cycle_sections : ndarray, shape (n, period, n_z), optional
        the section point at the start of each step of the cycle (step 0: the branch's
        section; NaN after a failed stride), for drawing every point of a period-k orbit.
    """

    parameter_name: str
    parameter_unit: str
    parameter: np.ndarray
    step_time: np.ndarray
    step_length: np.ndarray
    speed: np.ndarray
    cost_of_transport: np.ndarray
    max_multiplier: np.ndarray
    stable: np.ndarray
    period: int = 1
    time_unit: str = "s"
    length_unit: str = "m"
    notes: list[str] = field(default_factory=list)
    cycle_sections: np.ndarray | None = None

    @classmethod
    def from_arrays(
        cls,
        branch: Any,
        *,
        step_time: np.ndarray,
        step_length: np.ndarray,
        parameter_unit: str = "",
        cost_of_transport: np.ndarray | None = None,
    ) -> BranchMeasures:
        """Measures from given per-step times and lengths (shape (n, period)): the speed
        and the largest multiplier follow; ``cost_of_transport`` defaults to NaN."""
        param = np.asarray(branch.parameter, dtype=float)
        times = np.asarray(step_time, dtype=float).reshape(param.size, -1)
        lengths = np.asarray(step_length, dtype=float).reshape(param.size, -1)
        cot = (
            np.full(param.size, np.nan)
            if cost_of_transport is None
            else np.asarray(cost_of_transport, dtype=float)
        )
        return cls(
            parameter_name=str(branch.parameter_name),
            parameter_unit=parameter_unit,
            parameter=param,
            step_time=times,
            step_length=lengths,
            speed=lengths.sum(axis=1) / times.sum(axis=1),
            cost_of_transport=cot,
            max_multiplier=_max_modulus(branch.multipliers, param.size),
            stable=np.asarray(branch.stable, dtype=bool),
            period=int(getattr(branch, "period", 1)),
        )


def _max_modulus(multipliers, n: int) -> np.ndarray:
    lam = np.asarray(multipliers)
    if lam.size == 0:
        return np.full(n, np.nan)
    return np.max(np.abs(lam.reshape(n, -1)), axis=1)


def branch_measures(
    branch: Any,
    model: Any,
    params: Any,
    *,
    rtol: float = 1e-10,
    atol: float = 1e-12,
) -> BranchMeasures:
    """Step time, step length, speed, cost of transport and largest |multiplier| along a
    branch (definitions in the module docstring).

    From each branch point ``z`` the model runs the ``branch.period`` strides of the cycle
    (:func:`walker.simulation.stride.simulate`, one stride at a time, with the branch's parameter
    set to the point's value), starting from ``lift(z)``.

    Parameters
    ----------
    branch : Branch
    model : str or WalkerModel
        the model the branch belongs to.
    params : the model's parameter dataclass
        the other parameters (the branch's parameter is replaced point by point).
    rtol, atol : float
        tolerances of the runs.

    Returns
    -------
    BranchMeasures

    Raises
    ------
    ValueError
        when ``branch.parameter_name`` is not a parameter of ``params``.
    """
    from walker.models import get_model
    from walker.simulation.stride import simulate

    model = get_model(model) if isinstance(model, str) else model
    name = str(branch.parameter_name)
    units = params.units()
    if name not in units:
        raise ValueError(
            f"`branch.parameter_name` must be a parameter of {model.name} "
            f"({', '.join(units)}), got {name!r}"
        )
    param = np.asarray(branch.parameter, dtype=float)
    sections = np.asarray(branch.sections, dtype=float).reshape(param.size, -1)
    period = int(getattr(branch, "period", 1))
    swing = int(getattr(model.module, "SWING_FOOT", -1))
    times = np.full((param.size, period), np.nan)
    lengths = np.full((param.size, period), np.nan)
    cycle = np.full((param.size, period, sections.shape[1]), np.nan)
    for i, (mu, z) in enumerate(zip(param, sections, strict=True)):
        p_i = params.replace(**{name: float(mu)})
        p = p_i.as_array()
        x = model.lift(z, p)
        cycle[i, 0] = z
        for j in range(period):
            if j > 0:
                cycle[i, j] = np.asarray(model.project(x, p), dtype=float)
            sol = simulate(model, p_i, x, n_strides=1, output="events", rtol=rtol, atol=atol)
            if not sol.success or sol.events is None or len(sol.events) == 0:
                break
            start = model.points(x, p)[0]
            landing = model.points(sol.events.x_pre[-1], p)[swing]
            times[i, j] = sol.t
            lengths[i, j] = float(np.linalg.norm(landing - start))
            x = sol.x
    stored = getattr(branch, "measures", None) or {}
    if model.has_torques or "slope" not in units:  # actuated: no passive cost of transport
        cot = np.asarray(stored.get("cost_of_transport_positive", np.full(param.size, np.nan)))
        notes = (
            ["cost of transport: positive actuator work per weight and distance"]
            if "cost_of_transport_positive" in stored
            else [f"{model.name} is actuated: no passive cost of transport"]
        )
    elif "cost_of_transport" in stored:
        # energy lost per weight and distance (walker.analysis.measures), stored by `walker
        # continue`
        cot = np.asarray(stored["cost_of_transport"], dtype=float)
        notes = []
    else:
        slope = param if name == "slope" else np.full(param.size, float(params.slope))
        cot = np.sin(slope)
        notes = []
    measures = BranchMeasures.from_arrays(
        branch,
        step_time=times,
        step_length=lengths,
        parameter_unit=units[name],
        cost_of_transport=cot,
    )
    return replace(
        measures, length_unit=units.get("leg_length", "m"), notes=notes, cycle_sections=cycle
    )


def plot_branch(
    branches: Any | Sequence[Any],
    measures: BranchMeasures | Sequence[BranchMeasures],
    *,
    fig: Figure | None = None,
) -> Figure:
    """Step time, walking speed, step length, cost of transport and the largest |multiplier|
    against the continued parameter, one panel each (shared x axis).

    Stable parts of a branch are drawn solid, unstable parts dashed (neighbouring runs share
    their end point), one colour per branch (``C0`` for the first).  A branch of period
    ``k`` draws ``k`` step-time and step-length curves, one per step of its cycle.  Every
    bifurcation of every branch is marked by a vertical dotted line through all panels and,
    on the multiplier panel, a circle at its largest |multiplier| (1 up to the location
    error) labelled with its kind (``fold``, ``period doubling``) and parameter value; the
    multiplier panel has a grey line at 1.

    Parameters
    ----------
    branches : Branch or sequence of Branch
        e.g. a period-one branch and the period-two branch switched to at its doubling.
    measures : BranchMeasures or sequence of BranchMeasures
        one per branch (:func:`branch_measures`), same order.
    fig : Figure, optional
        figure to draw into (must be empty); default a new one.

    Returns
    -------
    Figure
        five axes, top to bottom: step time, walking speed, step length, cost of transport,
        largest |multiplier|; the parameter (with unit) labels the bottom x axis.

    Raises
    ------
    ValueError
        when ``branches`` and ``measures`` differ in number or a measure does not match its
        branch's length.
    """
    branches = list(branches) if isinstance(branches, list | tuple) else [branches]
    measures = list(measures) if isinstance(measures, list | tuple) else [measures]
    if len(branches) != len(measures) or not branches:
        raise ValueError(
            f"`measures` must hold one BranchMeasures per branch: got {len(branches)} "
            f"branches and {len(measures)} measures"
        )
    for k, (br, m) in enumerate(zip(branches, measures, strict=True)):
        if np.asarray(br.parameter).shape != m.parameter.shape:
            raise ValueError(
                f"`measures[{k}]` has {m.parameter.size} points, its branch "
                f"{np.asarray(br.parameter).size}"
            )
    if fig is None:
        fig = Figure(figsize=(7.0, 10.0), layout="constrained")
    axes = fig.subplots(5, 1, sharex=True)
    m0 = measures[0]
    speed_unit = f"{m0.length_unit}/{m0.time_unit}"
    panels = [
        ("step_time", with_unit("step time", m0.time_unit)),
        ("speed", with_unit("walking speed", speed_unit)),
        ("step_length", with_unit("step length", m0.length_unit)),
        ("cost_of_transport", with_unit("cost of transport", "1")),
        ("max_multiplier", with_unit("largest |multiplier|", "1")),
    ]
    for ax, (_, ylabel) in zip(axes, panels, strict=True):
        ax.set_ylabel(ylabel)
        ax.grid(True, lw=0.3, alpha=0.5)
    axes[-1].axhline(1.0, color="0.5", lw=0.8, label="|multiplier| = 1")
    n_labels = 0
    for k, (br, m) in enumerate(zip(branches, measures, strict=True)):
        color = f"C{k}"
        stable = _stability(br, m)
        for ax, (key, _) in zip(axes, panels, strict=True):
            y = np.asarray(getattr(m, key), dtype=float)
            y = y.reshape(m.parameter.size, -1)
            for start, stop in equal_runs(stable):
                s = bool(stable[start])
                stop_incl = min(stop + 1, m.parameter.size)
                for col in range(y.shape[1]):
                    label = None
                    if ax is axes[0] and col == 0:
                        label = f"period {m.period}, {'stable' if s else 'unstable'}"
                    ax.plot(
                        m.parameter[start:stop_incl],
                        y[start:stop_incl, col],
                        color=color,
                        ls="-" if s else "--",
                        label=label,
                    )
        for b in br.bifurcations:
            mu = float(b.parameter_value)
            kind = BIFURCATION_LABELS.get(b.kind, b.kind)
            for ax in axes:
                ax.axvline(mu, color="C3", ls=":", lw=0.9)
            lam = np.asarray(b.multipliers)
            r = float(np.max(np.abs(lam))) if lam.size and np.all(np.isfinite(lam)) else 1.0
            axes[-1].plot([mu], [r], ls="none", marker="o", mfc="none", color="C3")
            n_labels += 1
            axes[-1].annotate(
                f"{kind}\n{m.parameter_name} = {mu:.5g}",
                (mu, r),
                textcoords="offset points",
                xytext=(4, 6 if n_labels % 2 else -18),
                fontsize="x-small",
                color="C3",
            )
    axes[-1].set_xlabel(with_unit(m0.parameter_name, m0.parameter_unit))
    _dedupe_legend(axes[0])
    periods = ", ".join(str(m.period) for m in measures)
    fig.suptitle(f"gait branch{'es' if len(measures) > 1 else ''} (period {periods})")
    return fig


def _stability(branch, measures: BranchMeasures) -> np.ndarray:
    """Stability flags, a point on a located bifurcation (marginal, a multiplier on the unit
    circle) taking its neighbour's so that it does not make a run of its own."""
    flags = np.asarray(measures.stable, dtype=bool).copy()
    sections = np.asarray(branch.sections, dtype=float).reshape(flags.size, -1)
    for b in branch.bifurcations:
        if not np.all(np.isfinite(np.asarray(b.multipliers))) or flags.size < 2:
            continue
        hit = np.flatnonzero(
            (measures.parameter == b.parameter_value)
            & np.all(sections == np.asarray(b.section), axis=1)
        )
        for i in hit:
            flags[i] = flags[i - 1] if i > 0 else flags[i + 1]
    return flags


def _dedupe_legend(ax) -> None:
    handles, labels = ax.get_legend_handles_labels()
    seen: dict[str, Any] = {}
    for h, lab in zip(handles, labels, strict=True):
        seen.setdefault(lab, h)
    order = sorted(seen)  # "period 1, stable" before "period 1, unstable" before "period 2..."
    legend_outside(ax, [seen[lab] for lab in order], order)


def section_unit(name: str) -> str:
    """Unit of a section coordinate from its name: rates (``qd*``, ``*_dot``) rad/s, angles
    rad."""
    return "rad/s" if name.startswith("qd") or name.endswith("_dot") else "rad"


def plot_orbit_diagram(
    diagram: Any,
    *,
    parameter_unit: str = "",
    coordinate_name: str | None = None,
    coordinate_unit: str | None = None,
    ax: Any = None,
) -> Figure:
    """Where the walker settles: the recorded section values (dots) at each parameter value.

    Parameters
    ----------
    diagram : OrbitDiagram
        uses ``parameter`` (n,), ``values`` (n, n_keep), ``parameter_name``, ``coordinate``.
    parameter_unit : str
        unit of the parameter (e.g. ``"rad"``).
    coordinate_name : str, optional
        name of the recorded section coordinate; default ``"section coordinate k"``.
    coordinate_unit : str, optional
        its unit; default :func:`section_unit` of the name (when a name is given).
    ax : Axes, optional

    Returns
    -------
    Figure
        one scatter of the finite values; the values where the walker fell are marked on the
        x axis with red crosses (labelled ``fell``) when there are any.
    """
    param = np.asarray(diagram.parameter, dtype=float)
    values = np.asarray(diagram.values, dtype=float)
    check_rows("diagram.values", values, param, "n_keep")
    if ax is None:
        fig = Figure(figsize=(7.0, 4.8), layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = ax.figure
    px = np.repeat(param, values.shape[1])
    py = values.ravel()
    ok = np.isfinite(py)
    ax.scatter(px[ok], py[ok], s=2.0, color="k", marker=".", linewidths=0, label="settled")
    fell = ~np.all(np.isfinite(values), axis=1)
    if np.any(fell):
        ax.plot(
            param[fell],
            np.full(int(fell.sum()), 0.0),
            ls="none",
            marker="x",
            color="C3",
            transform=ax.get_xaxis_transform(),
            clip_on=False,
            label="fell",
        )
        legend_outside(ax)
    k = int(getattr(diagram, "coordinate", 0))
    name = coordinate_name or f"section coordinate {k}"
    unit = (
        coordinate_unit
        if coordinate_unit is not None
        else (section_unit(coordinate_name) if coordinate_name else "")
    )
    ax.set_xlabel(with_unit(str(diagram.parameter_name), parameter_unit))
    ax.set_ylabel(with_unit(f"{name} just after heel strike", unit))
    ax.set_title("orbit diagram")
    return fig


def stored_figures(path: str | Path) -> dict[str, Figure]:
    """The figures of a stored branch or orbit diagram, by name (``"branch"``,
    ``"orbit_diagram"``): :func:`result_figures` of the file's result.

    Raises
    ------
    walker.storage.StorageError
        the file is missing, damaged or not a walker result.
    ValueError
        the file holds neither a branch nor an orbit diagram.
    """
    from walker.storage import read

    result, prov = read(path)
    return result_figures(result, prov, directory=Path(path).parent, source=str(path))


def _bare_file_name(name: Any) -> bool:
    """``name`` is a plain file name: no directory part, not ``.``/``..``, no NUL."""
    return (
        isinstance(name, str)
        and name not in ("", ".", "..")
        and "\0" not in name
        and "/" not in name
        and (os.sep == "/" or os.sep not in name)
        and Path(name).name == name
    )


def companion_branch(provenance: dict, directory: str | Path | None, source: str = "result"):
    """The period-doubled branch a ``walker continue --switch`` file names
    (``switched_branch``), read from ``directory``; None without one or when its file is not
    there.

    Raises
    ------
    walker.storage.StorageError
        ``switched_branch`` is not a bare file name (a file beside the branch's).
    """
    companion = provenance.get("switched_branch")
    if not companion or directory is None:
        return None
    if not _bare_file_name(companion):
        from walker.storage import StorageError

        raise StorageError(
            f"{source}: provenance key 'switched_branch' must name a file in the same "
            f"directory (walker writes a bare file name), got {companion!r:.80}"
        )
    other = Path(directory) / companion
    if not other.is_file():
        return None
    from walker.storage import read

    return read(other)[0]


def result_figures(
    result: Any,
    provenance: dict,
    *,
    model: Any = None,
    params: Any = None,
    directory: str | Path | None = None,
    source: str = "result",
) -> dict[str, Figure]:
    """The figures of a branch (``{"branch": ...}``) or an orbit diagram
    (``{"orbit_diagram": ...}``) read with :func:`walker.storage.read`.

    A branch whose provenance names a ``switched_branch`` (``walker continue --switch``)
    draws that period-doubled branch with it when its file is in ``directory``.

    Parameters
    ----------
    result : Branch or OrbitDiagram
    provenance : dict
        the file's provenance (``model``, ``parameters``, ``kind``; ``rtol``/``atol`` for the
        runs of :func:`branch_measures`).
    model, params : optional
        the model and its parameters; default from ``provenance``.
    directory : path, optional
        where to look for the period-doubled branch's file.
    source : str
        name of the result in error messages.

    Raises
    ------
    ValueError
        the result is neither a branch nor an orbit diagram.
    """
    from walker.models import get_model

    kind = provenance.get("kind")
    if kind not in ("branch", "orbit_diagram"):
        raise ValueError(f"{source}: holds a `{kind}`, not a branch or an orbit diagram")
    if model is None:
        from walker.models import MODEL_NAMES
        from walker.storage import StorageError

        if provenance.get("model") not in MODEL_NAMES:
            raise StorageError(
                f"{source}: provenance key 'model' is {provenance.get('model')!r}; plotting "
                f"needs one of {', '.join(MODEL_NAMES)}"
            )
        model = get_model(provenance["model"])
    if params is None:
        values = {k: v["value"] for k, v in provenance["parameters"].items()}
        params = model.params_class.from_dict(values)
    if kind == "orbit_diagram":
        names = model.section_names
        k = int(result.coordinate)
        fig = plot_orbit_diagram(
            result,
            parameter_unit=params.units().get(result.parameter_name, ""),
            coordinate_name=names[k] if k < len(names) else None,
        )
        return {"orbit_diagram": fig}
    branches = [result]
    other = companion_branch(provenance, directory, source)
    if other is not None:
        branches.append(other)
    tolerances = {k: float(provenance[k]) for k in ("rtol", "atol") if k in provenance}
    measures = [branch_measures(b, model, params, **tolerances) for b in branches]
    return {"branch": plot_branch(branches, measures)}
