"""Gait measures: step time, step length, walking speed, the energy lost at each kind of
impact and the mechanical cost of transport, from a run's events (definitions in
``docs/conventions.md``, section "Gait measures").

Everything is computed from the states walker records at the events of a run (the state just
before and just after each reset) with the model's compiled energy and drawing-point
functions (:meth:`walker.models.WalkerModel.energy`, :meth:`~walker.models.WalkerModel.points`),
and for the actuated walkers from the state's ``actuator_work`` accumulator:

* a **step** ends at each event that hands the stance to the other foot (a heel strike, a
  spoke impact of the rimless wheel).  The walker's frame (the origin of the drawing
  coordinates, which is fixed in the world during a stance) moves at such an event by
  ``before[swing foot] - after[stance foot]``; the step's length is the length of that move,
  and the stretch's distance the length of the sum of the moves (along the slope).
* the **energy lost at an impact** is the drop of the kinetic energy across the reset (the
  configuration is continuous there); between events the energy lost is the drop of the
  kinetic plus potential energy in the stance frame, plus the actuator work done meanwhile
  (what damping and dry friction took).
* the **cost of transport** is energy per weight and distance (dimensionless): the energy
  lost, and for the actuated walkers the net, positive and absolute actuator work.  On a
  periodic passive gait the energy lost equals the potential energy released,
  ``weight * distance * sin(slope)``, so the cost of transport is ``sin(slope)``.

:func:`cycle_measures` runs one cycle of a gait and measures it; :func:`run_measures`
measures a finished run; :func:`branch_measures` measures every gait of a branch.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = [
    "GaitMeasures",
    "branch_measures",
    "cycle_measures",
    "map_cycle_measures",
    "run_measures",
    "total_mass",
]

_LEG_SEGMENTS = ("leg", "thigh", "shank", "femur", "tibia")

SAMPLES_PER_CYCLE = 8000
"""Samples of an actuated walker's cycle at which :func:`cycle_measures` reads the actuator
work, for its positive and absolute parts."""


def total_mass(params) -> float:
    """Total mass [kg]: every ``mass_*`` parameter, leg segments (``leg``, ``thigh``,
    ``shank``, ``femur``, ``tibia``) twice for the two legs; 1 for a model without masses
    (simplest walker, rimless wheel), whose energies are per unit mass."""
    total = 0.0
    for name, factor in _mass_factors(type(params), tuple(params.names())):
        total += factor * float(getattr(params, name))
    return total if total > 0 else 1.0


_MASS_FACTORS: dict = {}


def _mass_factors(cls, names: tuple[str, ...]) -> tuple[tuple[str, float], ...]:
    """The ``mass_*`` parameters of a parameter class, each with its count in the walker
    (2 for a leg segment, else 1), in the order of its fields (:func:`total_mass`)."""
    key = (cls, names)
    factors = _MASS_FACTORS.get(key)
    if factors is None:
        factors = tuple(
            (name, 2.0 if any(segment in name for segment in _LEG_SEGMENTS) else 1.0)
            for name in names
            if name.startswith("mass_")
        )
        _MASS_FACTORS[key] = factors
    return factors


@dataclass(frozen=True)
class GaitMeasures:
    """Measures of a stretch of walking: a gait's cycle, or a run up to its last step.

    Energies are per step (the stretch's total over ``n_steps``), in J (J/kg for a model
    without masses); costs of transport are dimensionless. NaN where undefined (no step, or
    no actuators).

    Attributes
    ----------
    n_steps : int
        steps (foot swaps) in the stretch.
    duration : float
        time from the start to the last step [s].
    distance : float
        distance travelled along the slope [m].
    step_time, step_length : float
        ``duration / n_steps`` [s] and ``distance / n_steps`` [m].
    speed : float
        ``distance / duration`` [m/s].
    weight : float
        total mass times ``g`` [N] (:func:`total_mass`).
    impact_losses : dict of str to float
        energy lost per step at each kind of impact, by guard name (``heel_strike``,
        ``knee_lock``, ...) [J].
    energy_dissipated : float
        energy lost per step between impacts (damping, dry friction) [J].
    energy_lost : float
        the sum of the two [J].
    actuator_work, actuator_work_positive, actuator_work_absolute : float
        the actuators' net work per step, and the time integrals of the positive part and of
        the absolute value of the actuator power, per step [J]; NaN for a passive walker.
    cost_of_transport : float
        ``energy_lost / (weight * step_length)``.
    cost_of_transport_positive, cost_of_transport_absolute : float
        ``actuator_work_positive`` and ``actuator_work_absolute`` over ``weight *
        step_length``; NaN for a passive walker.
    """

    n_steps: int
    duration: float
    distance: float
    step_time: float
    step_length: float
    speed: float
    weight: float
    impact_losses: dict = field(default_factory=dict)
    energy_dissipated: float = math.nan
    energy_lost: float = math.nan
    actuator_work: float = math.nan
    actuator_work_positive: float = math.nan
    actuator_work_absolute: float = math.nan
    cost_of_transport: float = math.nan
    cost_of_transport_positive: float = math.nan
    cost_of_transport_absolute: float = math.nan

    def to_dict(self) -> dict[str, float]:
        """Plain ``{name: number}``: every attribute, the impact losses as
        ``energy_lost_<guard>``."""
        out: dict[str, float] = {}
        for name in self.__dataclass_fields__:
            if name == "impact_losses":
                for guard, value in self.impact_losses.items():
                    out[f"energy_lost_{guard}"] = float(value)
            else:
                value = getattr(self, name)
                out[name] = int(value) if name == "n_steps" else float(value)
        return out

    def __repr__(self) -> str:
        return (
            f"GaitMeasures(step_time={self.step_time:.6g} s, step_length="
            f"{self.step_length:.6g} m, speed={self.speed:.6g} m/s, energy_lost="
            f"{self.energy_lost:.6g} J, cost_of_transport={self.cost_of_transport:.6g})"
        )


UNITS = {
    "n_steps": "1",
    "duration": "s",
    "distance": "m",
    "step_time": "s",
    "step_length": "m",
    "speed": "m/s",
    "weight": "N",
    "energy_dissipated": "J",
    "energy_lost": "J",
    "actuator_work": "J",
    "actuator_work_positive": "J",
    "actuator_work_absolute": "J",
    "cost_of_transport": "1",
    "cost_of_transport_positive": "1",
    "cost_of_transport_absolute": "1",
}
"""Unit of each key of :meth:`GaitMeasures.to_dict` (``energy_lost_<guard>``: J)."""


def unit_of(key: str) -> str:
    """The unit of a :meth:`GaitMeasures.to_dict` key."""
    return UNITS.get(key, "J" if key.startswith("energy_lost_") else "1")


def _frame_shift(model, p, x_pre, x_post, swing: int) -> np.ndarray | None:
    """The move of the stance frame's origin at an event (in the old frame), or None when
    the event keeps the stance foot.  The new stance foot is the old swing foot, so the new
    origin lies at ``before[swing] - after[0]``; the event swaps the feet when the joints
    after it, moved by that, lie on the joints before it more often than unmoved.

    The joints are few (at most a dozen): the distances are taken on Python floats with the
    operations numpy's ``linalg.norm`` does on each pair (``sqrt(dx * dx + dy * dy)``), so
    the decision is numpy's, at a fraction of its cost per call."""
    before = np.asarray(model.points(x_pre, p), dtype=float)
    after = np.asarray(model.points(x_post, p), dtype=float)
    shift = before[swing] - after[0]
    b = before.tolist()
    a = after.tolist()
    flat = [v for row in b for v in row] + [v for row in a for v in row]
    if not all(map(math.isfinite, flat)):
        return _frame_shift_nonfinite(before, after, shift)
    tol = 1e-6 * max(1.0, max(abs(v) for row in b for v in row))
    if float(np.linalg.norm(shift)) <= tol:
        return None
    sx, sy = shift.tolist()

    def matches(ox: float, oy: float) -> int:
        count = 0
        for ax, ay in a:
            ax, ay = ax + ox, ay + oy
            nearest = min(math.sqrt((ax - bx) * (ax - bx) + (ay - by) * (ay - by)) for bx, by in b)
            count += nearest <= tol
        return count

    if matches(sx, sy) <= matches(0.0, 0.0):
        return None
    return shift


def _frame_shift_nonfinite(before, after, shift) -> np.ndarray | None:
    """:func:`_frame_shift` of joints not all finite, in numpy (NaN compares false)."""
    tol = 1e-6 * max(1.0, float(np.max(np.abs(before))))

    def matches(offset) -> int:
        d = np.linalg.norm((after + offset)[:, None, :] - before[None, :, :], axis=2)
        return int(np.sum(np.min(d, axis=1) <= tol))

    if float(np.linalg.norm(shift)) <= tol or matches(shift) <= matches(0.0):
        return None
    return shift


def _kinetic_potential(model, x, p) -> tuple[float, float]:
    kinetic, potential = model.energy(x, p)
    return float(kinetic), float(potential)


def _max_abs(values) -> float:
    """``float(np.max(np.abs(values)))`` of a short list of floats (NaN if any is NaN)."""
    out = max(map(abs, values))
    return math.nan if any(v != v for v in values) else out


def _work_index(model) -> int | None:
    names = tuple(model.state_names)
    return names.index("actuator_work") if "actuator_work" in names else None


def run_measures(model, params, sol, x0, *, t0: float = 0.0, work_samples=None) -> GaitMeasures:
    """Measures of the run ``sol`` (a :class:`walker.results.Solution` with events) from its
    start state ``x0`` at ``t0`` up to its last step.

    Parameters
    ----------
    model : WalkerModel
    params : the model's parameter dataclass
    sol : Solution
        a run with events (``output`` ``"events"``, ``"samples"`` or ``"full"``).
    x0 : array_like, shape (n_x,)
        the state the run started from.
    t0 : float
        its start time [s].
    work_samples : Trajectory, optional
        states at increasing times from which the positive and absolute actuator work are
        read (the ``actuator_work`` component's increments); default ``sol.samples`` or
        ``sol.record``.  Ignored for a passive walker.

    Returns
    -------
    GaitMeasures
    """
    if sol.events is None:
        raise ValueError("`sol` must carry its events (output 'events', 'samples' or 'full').")
    weight = total_mass(params) * float(params.g)
    return _measure(model, params.as_array(), weight, sol, x0, t0, work_samples)


def _measure(model, p, weight, sol, x0, t0=0.0, work_samples=None) -> GaitMeasures:
    """:func:`run_measures` with the parameter vector ``p`` and the ``weight`` [N] given."""
    x0 = np.asarray(x0, dtype=float)
    events = sol.events
    work = _work_index(model)
    n_q = (model.n_x - (0 if work is None else 2)) // 2
    swing = int(getattr(model.module, "SWING_FOOT", -1))
    guard_names = tuple(model.guard_names)

    shifts = [
        _frame_shift(model, p, events.x_pre[i], events.x_post[i], swing) for i in range(len(events))
    ]
    steps = [i for i, s in enumerate(shifts) if s is not None]
    if not steps:
        nan = math.nan
        return GaitMeasures(0, nan, 0.0, nan, nan, nan, weight)
    last = steps[-1]
    moved = np.sum([shifts[i] for i in steps], axis=0)
    distance = float(np.linalg.norm(moved))
    duration = float(events.t[last]) - float(t0)
    n_steps = len(steps)

    impact: dict[str, float] = {}
    dissipated = 0.0
    start = x0
    k_start, v_start = _kinetic_potential(model, start, p)
    guards = events.guard.tolist()
    for i in range(last + 1):
        x_pre, x_post = events.x_pre[i], events.x_post[i]
        k_pre, v_pre = _kinetic_potential(model, x_pre, p)
        k_post, v_post = _kinetic_potential(model, x_post, p)
        dissipated += (k_start + v_start) - (k_pre + v_pre)
        if work is not None:
            dissipated += float(x_pre[work]) - float(start[work])
        rates_pre = x_pre[n_q : 2 * n_q].tolist()
        rates_post = x_post[n_q : 2 * n_q].tolist()
        scale = max(1.0, _max_abs(rates_pre))
        jump = _max_abs([b - a for a, b in zip(rates_pre, rates_post, strict=True)])
        if jump > 1e-9 * scale:
            name = guard_names[int(guards[i])]
            impact[name] = impact.get(name, 0.0) + (k_pre - k_post)
        else:
            dissipated += k_pre - k_post
        start, k_start, v_start = x_post, k_post, v_post
    lost = dissipated + sum(impact.values())
    per = 1.0 / n_steps
    transport = weight * distance
    measures = {
        "impact_losses": {k: v * per for k, v in impact.items()},
        "energy_dissipated": dissipated * per,
        "energy_lost": lost * per,
        "cost_of_transport": lost / transport if transport > 0 else math.nan,
    }
    if work is not None:
        net = float(events.x_post[last][work]) - float(x0[work])
        positive, absolute = _work_parts(
            sol if work_samples is None else work_samples, work, t0, events.t[last]
        )
        measures.update(
            actuator_work=net * per,
            actuator_work_positive=positive * per,
            actuator_work_absolute=absolute * per,
            cost_of_transport_positive=positive / transport if transport > 0 else math.nan,
            cost_of_transport_absolute=absolute / transport if transport > 0 else math.nan,
        )
    return GaitMeasures(
        n_steps=n_steps,
        duration=duration,
        distance=distance,
        step_time=duration * per,
        step_length=distance * per,
        speed=distance / duration if duration > 0 else math.nan,
        weight=weight,
        **measures,
    )


def _work_parts(source, work: int, t0: float, t1: float) -> tuple[float, float]:
    """The positive and absolute actuator work [J] from ``t0`` to ``t1``: the sums of the
    positive increments and of the absolute increments of the ``actuator_work`` component
    between consecutive samples; NaN without samples."""
    traj = source
    if hasattr(source, "samples"):
        traj = source.samples if source.samples is not None else source.record
    if traj is None or len(traj) < 2:
        return math.nan, math.nan
    t = np.asarray(traj.t, dtype=float)
    keep = (t >= t0) & (t <= t1)
    w = np.asarray(traj.x, dtype=float)[keep, work]
    dw = np.diff(w)
    return float(np.sum(np.maximum(dw, 0.0))), float(np.sum(np.abs(dw)))


def cycle_measures(
    model,
    params,
    state,
    *,
    period: int = 1,
    settings: dict | None = None,
    samples: int = SAMPLES_PER_CYCLE,
) -> GaitMeasures:
    """Run ``period`` strides from a gait's state just after heel strike and measure them.

    Parameters
    ----------
    model : WalkerModel
    params : the model's parameter dataclass
    state : array_like, shape (n_x,)
        the gait's full state (``FixedPoint.state``).
    period : int
        strides in the cycle, >= 1.
    settings : dict, optional
        solver settings (``method``, ``rtol``, ``atol``, ``t_max``, ``first_step``:
        :func:`walker.simulation.stride.solver_settings`); default those of :func:`walker.simulate`.
    samples : int
        samples of the cycle at which an actuated walker's work is read (>= 2).

    Returns
    -------
    GaitMeasures
        NaN measures when the run does not complete its strides.
    """
    from walker.simulation.stride import simulate
    from walker.status import Status

    if isinstance(period, bool) or not isinstance(period, int | np.integer) or period < 1:
        raise ValueError(f"`period` must be an int >= 1, got {period!r}")
    state = np.asarray(state, dtype=float)
    settings = dict(settings or {})
    if "t_max" in settings:
        settings["t_max"] = float(settings["t_max"]) * period
    weight = total_mass(params) * float(params.g)
    failed = GaitMeasures(0, math.nan, math.nan, math.nan, math.nan, math.nan, weight)
    if state.shape != (model.n_x,) or not np.all(np.isfinite(state)):
        return failed
    first = simulate(model, params, state, n_strides=period, output="events", **settings)
    if first.status != Status.COMPLETED:
        return failed
    if _work_index(model) is None:
        return run_measures(model, params, first, state)
    times = np.linspace(0.0, float(first.t), max(2, int(samples)))
    sol = simulate(
        model, params, state, n_strides=period, output="samples", sample_times=times, **settings
    )
    if sol.status != Status.COMPLETED:
        return failed
    return run_measures(model, params, sol, state)


def map_cycle_measures(stride_map, state, *, period: int = 1) -> GaitMeasures:
    """:func:`cycle_measures` of a gait of ``stride_map`` at the map's solver settings, the
    same numbers bit for bit, at less cost per call: what a fixed-point sweep measures at
    each point (:func:`walker.analysis.sweep_grid.fill_measures`).

    The cycle is run as :func:`walker.simulation.stride.simulate` runs it (the same solver call and
    settings), on the parameter vector and system the map has prepared already, so no run
    is set up again per gait.  An actuated walker (its cycle is sampled for the work) and a
    map that is not a :class:`~walker.simulation.stride.StrideMap` take :func:`cycle_measures`
    itself.

    Parameters
    ----------
    stride_map : walker.simulation.stride.StrideMap
    state : ndarray, shape (n_x,)
        the gait's full state (``FixedPoint.state``).
    period : int
        strides in the cycle, >= 1.

    Returns
    -------
    GaitMeasures
        NaN measures when the run does not complete its strides.
    """
    from walker.simulation.integrate import _solve
    from walker.simulation.stride import solver_settings
    from walker.status import Status

    model, params = stride_map.model, stride_map.params
    if _work_index(model) is not None or not hasattr(stride_map, "_prepared"):
        settings = solver_settings(stride_map)
        return cycle_measures(model, params, state, period=period, settings=settings)
    if isinstance(period, bool) or not isinstance(period, int | np.integer) or period < 1:
        raise ValueError(f"`period` must be an int >= 1, got {period!r}")
    state = np.ascontiguousarray(state, dtype=float)
    weight = total_mass(params) * float(params.g)
    if state.shape != (model.n_x,) or not all(map(math.isfinite, state.tolist())):
        return GaitMeasures(0, math.nan, math.nan, math.nan, math.nan, math.nan, weight)
    run, p, _ = stride_map._prepared()
    start_phase = model.start_phase_fn()
    first = _solve(
        run.system,
        state,
        p,
        phase0=0 if start_phase is None else start_phase(state, p),
        t0=0.0,
        t_max=float(stride_map.t_max) * period,
        n_strides=period,
        method=stride_map.method,
        rtol=stride_map.rtol,
        atol=stride_map.atol,
        first_step=stride_map.first_step,
        max_step=np.inf,
        max_steps=_simulate_max_steps(),
        output="events",
        sample_times=None,
        jacobian=False,
        n_interior=4,
        fixed_step=False,
        p_checked=True,
    )
    if first.status != Status.COMPLETED:
        return GaitMeasures(0, math.nan, math.nan, math.nan, math.nan, math.nan, weight)
    return _measure(model, p, weight, first, state)


def _simulate_max_steps() -> int:
    """The step budget :func:`walker.simulation.stride.simulate` runs with by default (what
    :func:`cycle_measures` runs a cycle with)."""
    import inspect

    from walker.simulation.stride import simulate

    global _SIMULATE_MAX_STEPS
    if _SIMULATE_MAX_STEPS is None:
        _SIMULATE_MAX_STEPS = int(inspect.signature(simulate).parameters["max_steps"].default)
    return _SIMULATE_MAX_STEPS


_SIMULATE_MAX_STEPS: int | None = None


def branch_measures(stride_map, branch) -> dict[str, np.ndarray]:
    """Measures of every gait of ``branch``, as columns (one row per branch point): the keys
    of :meth:`GaitMeasures.to_dict`, an impact kind missing at some point counting 0 there.

    Parameters
    ----------
    stride_map : walker.simulation.stride.StrideMap
        the map the branch was continued on.
    branch : walker.results.Branch
    """
    from walker.simulation.stride import solver_settings

    settings = solver_settings(stride_map)
    rows = []
    for value, z in zip(branch.parameter, branch.sections, strict=True):
        smap = stride_map.with_parameter(float(value))
        try:
            x = smap.lift(z)
        except (ValueError, ArithmeticError):
            x = np.full(smap.model.n_x, np.nan)
        rows.append(
            cycle_measures(
                smap.model, smap.params, x, period=int(branch.period), settings=settings
            ).to_dict()
        )
    keys: dict[str, None] = {}
    for row in rows:
        keys.update(dict.fromkeys(row))
    columns = {}
    for key in keys:
        values = [
            row.get(key, 0.0 if key.startswith("energy_lost_") and row["n_steps"] else math.nan)
            for row in rows
        ]
        dtype = np.int64 if key == "n_steps" else np.float64
        columns[key] = np.asarray(values, dtype=dtype)
    return columns
