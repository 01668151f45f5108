"""Result containers shared by the integrator, the gait search, storage and plotting.

Every result that can fail carries ``status`` (:class:`walker.status.Status`), ``message`` and
``success``; expected failures (a fall, Newton not converging) are statuses, not exceptions.
``success`` is ``status == Status.COMPLETED``: it stays a stored field, because the file
schema writes every field (:mod:`walker.storage.schema`), and walker's analysis code sets it
only through :meth:`Outcome.from_status` and :meth:`Outcome.with_status`.
Arrays use SI units and the state order of the model that produced them.

The size of a result is checked before it is allocated (:func:`memory_limit`): a sweep table,
a basin grid or a sampled trajectory that would take more than :data:`MEMORY_FRACTION` of the
memory available to the process is refused with a ``ValueError`` naming the argument.
"""

from __future__ import annotations

import dataclasses
import os
import resource
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from walker.status import Status

MEMORY_FRACTION = 0.25
"""Largest share of the memory available to the process (physical memory, or a lower cgroup
or ``RLIMIT_AS`` limit) that one result may take: the rest is left for the copies a run makes
(checkpoint buffers, the table returned, HDF5) and for everything else on the machine."""

_CGROUP_LIMITS = (
    "/sys/fs/cgroup/memory.max",  # cgroup v2, as seen from inside a container
    "/sys/fs/cgroup/memory/memory.limit_in_bytes",  # cgroup v1
)


def memory_limit() -> int:
    """Bytes one result may take: :data:`MEMORY_FRACTION` of the memory available.

    The memory available is the smallest of the physical memory
    (``SC_PHYS_PAGES * SC_PAGE_SIZE``), the cgroup memory limit and ``RLIMIT_AS``, where
    these are known.
    """
    limits = []
    try:
        limits.append(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - not POSIX
        pass
    for path in _CGROUP_LIMITS:
        try:
            text = Path(path).read_text().strip()
        except OSError:
            continue
        if text.isdigit():
            limits.append(int(text))
    try:
        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
        if soft not in (resource.RLIM_INFINITY, -1) and soft > 0:
            limits.append(soft)
    except (ValueError, OSError):  # pragma: no cover
        pass
    available = min((v for v in limits if v > 0), default=8 << 30)
    return int(available * MEMORY_FRACTION)


def format_bytes(n_bytes: float) -> str:
    """``n_bytes`` for a message: ``"74.5 GiB"``."""
    value = float(n_bytes)
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if value < 1024 or unit == "PiB":
            return f"{value:.0f} {unit}" if unit == "B" else f"{value:.3g} {unit}"
        value /= 1024
    raise AssertionError("unreachable")  # pragma: no cover


def too_large(n_bytes: float) -> str | None:
    """None when ``n_bytes`` fit in :func:`memory_limit`; else the end of an error message,
    ``"needs 74.5 GiB, more than the limit of 5.8 GiB (a quarter of the memory)"``."""
    limit = memory_limit()
    if n_bytes <= limit:
        return None
    return (
        f"needs {format_bytes(n_bytes)}, more than the limit of {format_bytes(limit)} "
        f"({MEMORY_FRACTION:.0%} of the memory available)"
    )


@dataclass
class EventLog:
    """Every located event of a run, in time order.

    Attributes
    ----------
    t : ndarray, shape (n,)
        event times [s].
    guard : ndarray of int, shape (n,)
        index of the guard that fired (the model's ``guard_names`` give its name).
    phase_before, phase_after : ndarray of int, shape (n,)
        phase index before and after the reset.
    x_pre, x_post : ndarray, shape (n, n_x)
        state just before and just after the reset.
    impulse : ndarray, shape (n, n_impulse)
        impulses of the reset (zeros where an event has none) [N s or N m s].
    """

    t: np.ndarray
    guard: np.ndarray
    phase_before: np.ndarray
    phase_after: np.ndarray
    x_pre: np.ndarray
    x_post: np.ndarray
    impulse: np.ndarray

    def __len__(self) -> int:
        return int(self.t.shape[0])


@dataclass
class Trajectory:
    """Sampled states: ``x[i]`` is the state at ``t[i]`` in phase ``phase[i]``.

    Attributes
    ----------
    t : ndarray, shape (n,)
    x : ndarray, shape (n, n_x)
    phase : ndarray of int, shape (n,)
    """

    t: np.ndarray
    x: np.ndarray
    phase: np.ndarray

    def __len__(self) -> int:
        return int(self.t.shape[0])


class Outcome:
    """What the results that can fail share (:class:`Solution`, :class:`FixedPoint`,
    :class:`Branch`): ``status``, ``message`` and ``success``.

    ``success`` is derived, ``status == Status.COMPLETED``, but kept as a dataclass field:
    the file schema stores every field by name, so turning it into a property would change
    the files.  Build a result with :meth:`from_status` and re-label one with
    :meth:`with_status`, so that no code sets ``success`` by hand.
    """

    @classmethod
    def from_status(cls, status: Status, message: str, **fields):
        """A result with ``status``, ``message``, ``success`` derived, and the other fields."""
        return cls(status=status, message=message, success=status == Status.COMPLETED, **fields)

    def with_status(self, status: Status, message: str):
        """A copy with another ``status`` and ``message`` (``success`` follows)."""
        return dataclasses.replace(
            self, status=status, message=message, success=status == Status.COMPLETED
        )


@dataclass
class Solution(Outcome):
    """Result of one run of the hybrid integrator.

    Attributes
    ----------
    status : Status
    message : str
    success : bool
        ``status == Status.COMPLETED``.
    t : float
        final time [s]; the time of the last event when the run ended on one.
    x : ndarray, shape (n_x,)
        final state (after the reset of the last event when the run ended on one).
    phase : int
        final phase index.
    n_steps, n_rejected, n_rhs, n_events, n_strides : int
        accepted steps, rejected steps, vector-field evaluations, applied events
        (reset maps), completed strides.
    events : EventLog or None
        with output ``"events"`` or richer.
    samples : Trajectory or None
        states at the requested ``sample_times`` (output ``"samples"``).
    record : Trajectory or None
        every accepted step (output ``"full"``).
    jac : ndarray, shape (n_x, n_x), or None
        derivative of the final state with respect to the initial state, through every
        phase and event (variational equations and saltation matrices).
    dt_dx0 : ndarray, shape (n_x,), or None
        derivative of the final event time with respect to the initial state.
    error_estimate : float
        sum over accepted steps of the local error norms the method reported (in units of
        the tolerance-scaled norm times ``rtol``); a rough global error indicator.
    phase_names, guard_names : tuple of str
    conventions : dict of str to str
        the modelling conventions the run used, e.g. ``{"swing_scuff": "ignore"}`` for a
        kneed walker (:attr:`walker.models.WalkerModel.conventions`); empty when the model
        has none or the run came from :func:`walker.simulation.integrate.hybrid_solve` directly.
    measures : dict of str to float
        gait measures of the run up to its last step
        (:meth:`walker.analysis.measures.GaitMeasures.to_dict`: step time, step length, speed,
        energy lost at each impact, cost of transport); empty when not computed (``walker run``
        computes them).
    """

    status: Status
    message: str
    success: bool
    t: float
    x: np.ndarray
    phase: int
    n_steps: int = 0
    n_rejected: int = 0
    n_rhs: int = 0
    n_events: int = 0
    n_strides: int = 0
    events: EventLog | None = None
    samples: Trajectory | None = None
    record: Trajectory | None = None
    jac: np.ndarray | None = None
    dt_dx0: np.ndarray | None = None
    error_estimate: float = 0.0
    phase_names: tuple[str, ...] = ()
    guard_names: tuple[str, ...] = ()
    conventions: dict = field(default_factory=dict)
    measures: dict = field(default_factory=dict)


@dataclass
class MapResult:
    """One application of a section (stride) map: what :class:`walker.simulation.stride.StrideMap`
    and :class:`walker.simulation.system_map.SystemMap` return for ``P(z, jacobian=...,
    n_strides=k)``.

    A stride that fails is a status, never an exception: ``z`` is then NaN and ``jac`` None.

    Attributes
    ----------
    status : Status
        ``Status.COMPLETED`` when all ``k`` strides ended at the section; otherwise why the
        run stopped (a fall, a non-physical impact, ``NO_EVENT`` when no stride event came
        before ``t_max``, ``OUTSIDE_WALKING_REGION`` for a walker's start off its region).
    z : ndarray, shape (n_z,)
        the section point after ``k`` strides, in the map's section coordinates
        (``section_names``); NaN where a stride failed.
    jac : ndarray, shape (n_z, n_z), or None
        ``dz_next/dz`` when requested with ``jacobian=True`` and the strides completed;
        None otherwise.
    step_time : float
        duration of the ``k`` strides [s]; after a failure, the time at which the run
        stopped (0 for a start refused before integrating).
    state : ndarray, shape (n_x,)
        full state at the section (just after the last heel strike, or the stride event of
        a :class:`~walker.simulation.system_map.SystemMap`); after a failure, the state where the
        run stopped (the start state for a start refused before integrating).
    terrain_jac : ndarray, shape (n_z, 2 n_strides), or None
        with per-step terrain and ``jacobian=True``
        (:meth:`walker.simulation.stride.StrideMap.__call__`):
        ``dz_next / d(slope_k, drop_k)``, columns ``2k`` (slope [1/rad]) and ``2k + 1``
        (drop [1/m]) for step ``k``; None otherwise.
    """

    status: Status
    z: np.ndarray
    jac: np.ndarray | None
    step_time: float
    state: np.ndarray
    terrain_jac: np.ndarray | None = None

    @property
    def success(self) -> bool:
        """``status == Status.COMPLETED``."""
        return self.status == Status.COMPLETED


@dataclass
class FixedPoint(Outcome):
    """A period-``period`` orbit of a section map and its stability.

    Attributes
    ----------
    status, message, success
    section : ndarray, shape (n_z,)
        fixed point in section coordinates.
    state : ndarray, shape (n_x,)
        full state there (just after heel strike for walkers).
    step_time : float
        duration of the ``period`` strides [s].
    multipliers : ndarray of complex, shape (n_z,)
        Floquet multipliers (eigenvalues of ``jacobian``), sorted by decreasing modulus.
    eigenvectors : ndarray of complex, shape (n_z, n_z)
        columns match ``multipliers``.
    jacobian : ndarray, shape (n_z, n_z)
    residual : float
        max-norm of ``P^k(z) - z`` at the returned point.
    n_iter : int
    history : ndarray, shape (n_iter + 1,)
        residual at each iterate.
    period : int
    stable : bool
        all multipliers strictly inside the unit circle.
    parameters : dict
        parameter name -> value used.
    conventions : dict of str to str
        the modelling conventions of the stride map's model, e.g.
        ``{"swing_scuff": "ignore"}`` (:attr:`walker.models.WalkerModel.conventions`).
    measures : dict of str to float
        the gait's measures over its cycle (:meth:`walker.analysis.measures.GaitMeasures.to_dict`);
        empty when not computed (``walker find`` computes them, as does
        :func:`walker.analysis.measures.cycle_measures`).
    """

    status: Status
    message: str
    success: bool
    section: np.ndarray
    state: np.ndarray
    step_time: float
    multipliers: np.ndarray
    eigenvectors: np.ndarray
    jacobian: np.ndarray
    residual: float
    n_iter: int
    history: np.ndarray
    period: int = 1
    stable: bool = False
    parameters: dict = field(default_factory=dict)
    conventions: dict = field(default_factory=dict)
    measures: dict = field(default_factory=dict)

    @classmethod
    def failed(
        cls,
        status: Status,
        message: str,
        section,
        *,
        period: int,
        parameters: dict,
        history=(),
        n_iter: int = 0,
        state: np.ndarray | None = None,
        conventions: dict | None = None,
    ) -> FixedPoint:
        """A search that ended without an orbit: ``section`` is where it ended, the
        multipliers, eigenvectors, Jacobian and step time are NaN, ``stable`` is False."""
        n_z = np.asarray(section).shape[0]
        return cls.from_status(
            status,
            message,
            section=np.asarray(section, dtype=float).copy(),
            state=np.full(1, np.nan) if state is None else state,
            step_time=float("nan"),
            multipliers=np.full(n_z, np.nan, dtype=complex),
            eigenvectors=np.full((n_z, n_z), np.nan, dtype=complex),
            jacobian=np.full((n_z, n_z), np.nan),
            residual=float(history[-1]) if len(history) else float("nan"),
            n_iter=n_iter,
            history=np.asarray(history, dtype=float),
            period=period,
            stable=False,
            parameters=parameters,
            conventions={} if conventions is None else conventions,
        )


@dataclass
class Bifurcation:
    """A detected bifurcation on a branch: ``kind`` is ``"fold"`` or ``"period_doubling"``."""

    kind: str
    parameter_value: float
    section: np.ndarray
    multipliers: np.ndarray


@dataclass
class Branch(Outcome):
    """A continued branch of period-``period`` orbits.

    Attributes
    ----------
    parameter_name : str
    parameter : ndarray, shape (n,)
    sections : ndarray, shape (n, n_z)
    step_times : ndarray, shape (n,)
    multipliers : ndarray of complex, shape (n, n_z)
    stable : ndarray of bool, shape (n,)
    bifurcations : list of Bifurcation
    status, message, success
    period : int
    measures : dict of str to ndarray
        the gait measures of each point (:func:`walker.analysis.measures.branch_measures`), one
        column per measure; empty when not computed (``walker continue`` computes them).
    """

    parameter_name: str
    parameter: np.ndarray
    sections: np.ndarray
    step_times: np.ndarray
    multipliers: np.ndarray
    stable: np.ndarray
    bifurcations: list[Bifurcation]
    status: Status
    message: str
    success: bool
    period: int = 1
    measures: dict = field(default_factory=dict)


@dataclass
class OrbitDiagram:
    """Where the walker settles, by brute-force iteration at each parameter value.

    ``values[i]`` holds the last ``n_keep`` values of section coordinate ``coordinate`` at
    ``parameter[i]`` (NaN where the walker fell).
    """

    parameter_name: str
    parameter: np.ndarray
    values: np.ndarray
    coordinate: int = 0


@dataclass
class BasinMap:
    """Basin of attraction on a 2-D slice of the section.

    Attributes
    ----------
    axis_names : tuple of str
        names of the two section coordinates varied (x then y).
    x, y : ndarray, shape (nx,), (ny,)
    outcome : ndarray of int, shape (ny, nx)
        ``BASIN_CONVERGED`` (-1), ``BASIN_UNDECIDED`` (-2), or a :class:`Status` value
        saying how the walker failed.
    strides : ndarray of int, shape (ny, nx)
        strides taken before convergence or failure.
    fixed_point : ndarray, shape (n_z,)
    base : ndarray, shape (n_z,)
        section point whose other coordinates are held fixed.
    n_strides : int
    classification : dict
        how a point was called converged: ``tol`` (``max|z - fixed_point| <= tol``),
        ``converge_radius`` (also converged inside ``||W (z - fixed_point)||_2 <=
        converge_radius``; 0: off), with a radius the weight ``W`` (``weight``, nested
        lists) and how it was derived (:func:`walker.analysis.basin.basin_map`); empty in files
        written before it was recorded (there: the tolerance alone).
    """

    axis_names: tuple[str, str]
    x: np.ndarray
    y: np.ndarray
    outcome: np.ndarray
    strides: np.ndarray
    fixed_point: np.ndarray
    base: np.ndarray
    n_strides: int
    classification: dict = field(default_factory=dict)


BASIN_CONVERGED = -1
BASIN_UNDECIDED = -2


@dataclass
class SweepTable:
    """Results over a parameter grid: ``columns[name][i]`` belongs to ``points[i]``."""

    parameter_names: tuple[str, ...]
    points: np.ndarray
    columns: dict[str, np.ndarray]


@dataclass
class MfptResult:
    """A mean first-passage time estimate.

    Attributes
    ----------
    mfpt : float
        the mean number of steps completed before the first failure (Monte Carlo, from the
        start state); NaN when no run failed and some were censored.
    mfpt_stderr : float
        its standard error (module docstring).
    runs, failed : int
        runs, and runs that failed within ``max_steps``.
    steps : ndarray of int64, shape (runs,)
        steps completed by each run (``max_steps`` for a censored run).
    status : ndarray of int64, shape (runs,)
        each run's :class:`walker.status.Status` value (0: censored, still walking).
    rate : float
        the fitted per-step failure probability of a geometric law (module docstring).
    max_steps : int
        the censoring horizon [steps].
    slope_mean, slope_std, height_std : float
        the terrain: slope mean and standard deviation [rad], drop standard deviation [m].
    seed : int
    start : ndarray
        the start section point (the period-one gait of the mean slope).
    markov : dict
        with :func:`walker.analysis.markov.markov_chain`: its ``mfpt`` (``1 / (1 - lambda_2)``),
        ``mfpt_start`` (expected steps from the start state), ``lambda_2``, mesh sizes and
        the refinement history; empty otherwise.
    """

    mfpt: float
    mfpt_stderr: float
    runs: int
    failed: int
    steps: np.ndarray
    status: np.ndarray
    rate: float
    max_steps: int
    slope_mean: float
    slope_std: float
    height_std: float
    seed: int
    start: np.ndarray
    markov: dict = field(default_factory=dict)

    def failures_by_status(self) -> dict[str, int]:
        """How many runs ended with each failure status, by name."""
        values, counts = np.unique(self.status[self.status != 0], return_counts=True)
        return {Status(int(v)).name: int(c) for v, c in zip(values, counts, strict=True)}

    def survival(self) -> tuple[np.ndarray, np.ndarray]:
        """The survival curve: steps ``k = 0 .. max(steps)`` and the fraction of runs that
        completed at least ``k`` steps (censored runs count as walking up to ``max_steps``)."""
        k = np.arange(int(self.steps.max(initial=0)) + 1)
        counts = np.bincount(self.steps, minlength=k.size)
        at_least = counts[::-1].cumsum()[::-1]
        return k, at_least / max(self.runs, 1)

    def as_dict(self) -> dict:
        """The summary as plain JSON-able values (no per-run arrays)."""
        out = {
            "mfpt": float(self.mfpt),
            "mfpt_stderr": float(self.mfpt_stderr),
            "runs": int(self.runs),
            "failed": int(self.failed),
            "censored": int(self.runs - self.failed),
            "rate": float(self.rate),
            "max_steps": int(self.max_steps),
            "slope_mean": float(self.slope_mean),
            "slope_std": float(self.slope_std),
            "height_std": float(self.height_std),
            "seed": int(self.seed),
            "failures": self.failures_by_status(),
            "start": [float(v) for v in self.start],
        }
        if self.markov:
            out["mfpt_markov"] = float(self.markov["mfpt"])
            out["mfpt_markov_start"] = float(self.markov["mfpt_start"])
            out["markov"] = {
                k: v for k, v in self.markov.items() if k not in ("mfpt", "mfpt_start")
            }
        return out
