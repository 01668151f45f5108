"""Fixed points of a section (stride) map, their Floquet multipliers and stability.

Everything here is generic over the :class:`SectionMap` protocol: a walker's stride map, or a
toy map in the tests.  A period-``k`` gait is a solution of ``F(z) = P^k(z) - z = 0`` on the
Poincaré section; it is found by damped Newton with a backtracking line search, with a
Levenberg–Marquardt fallback when Newton stalls.  Expected failures (no convergence, a falling
stride, a singular Jacobian) come back as statuses on the :class:`~walker.results.FixedPoint`;
only invalid input raises.

Failing fast.  Half of every sweep asks for a gait that does not exist, so a search that
cannot succeed must end about as cheaply as one that does:

* every step is confined to a trust region in scaled section coordinates (angles in rad,
  rates in units of ``sqrt(g / l)``; see :class:`WalkingRegion`);
* for a walker's stride map, a trial point outside the region where the walker can walk
  (stance leg past the fall angle, an angle wound beyond ±pi, kinetic energy above the
  scene's bound) is refused without integrating it;
* the search stops after ``max_evals`` stride-map evaluations (``BUDGET_EXHAUSTED``), when
  the residual stalls at a positive value (``NO_GAIT_NEAR_GUESS``), or when the steps keep
  leading out of the walking region (``DIVERGED``), reporting the last accepted iterate.
"""

from __future__ import annotations

import math
import numbers
from typing import Protocol, runtime_checkable

import numpy as np

from walker._checks import as_vector, time_scale
from walker.results import FixedPoint, MapResult
from walker.status import Status

__all__ = [
    "SectionMap",
    "WalkingRegion",
    "find_fixed_point",
    "floquet",
    "classify",
    "stride_max_steps",
]

JACOBIAN_MODES = ("exact", "fd")

# Line search: accept a step when the 2-norm of F drops by this fraction of the step length
# (Armijo condition on the merit ||F||), halving the step at most MAX_HALVINGS times (down to
# 1/4096 of the step cut to the trust region; shorter steps only crawl into a local minimum
# of ||F||, where Levenberg-Marquardt takes over).  The halving also stops at a trial point
# whose ||F|| lies within LINE_FLAT (relative) above the current one without dropping below
# it: ||F|| is flat along the Newton direction there, as at a local minimum of ||F||.
ARMIJO = 1e-4
MAX_HALVINGS = 12
LINE_FLAT = 1e-2
# Levenberg–Marquardt damping: start, growth on rejection, shrink on acceptance, give-up
# level; at most LM_TRIES trial points per iteration.
LM_START = 1e-3
LM_GROW = 10.0
LM_SHRINK = 0.3
LM_MAX = 1e12
LM_TRIES = 8
# A Newton matrix whose condition number exceeds this is treated as singular.
COND_MAX = 1e14

# --- Failing fast ----------------------------------------------------------------------------
# Evaluation budget: stride-map calls a search may make (any n_strides; the Jacobian at a
# converged solution, when the last Newton step did not bring it, is not counted).  The
# shipped scenes' gaits converge from their scene guesses in 1-5 evaluations (kneed: 4), and
# from guesses within +-50 % of the kneed or compass gait in at most 19.
MAX_EVALS = 60
# With finite-difference Jacobians each Jacobian costs 2 n_z evaluations more: room for ten.
FD_EXTRA_JACOBIANS = 10
# Budget of each search at a sweep point (walker.sweep.sweep_chunk: the warm start, and the
# retry from the sweep's guess): about 2-3x what a gait needs from a warm start (4-6 on the
# kneed slope sweep), so a point without a gait costs a few tens of strides at most.
POINT_MAX_EVALS = 12
# Natural-continuation correctors (walker.continuation): CORRECTOR_EVALS_PER_ITER
# evaluations per allowed corrector iteration (a Newton step and one halving).
CORRECTOR_EVALS_PER_ITER = 2
# Trust region, max-norm in scaled section coordinates (WalkingRegion.scale): start, largest.
# After an accepted full step the radius grows to twice the step (at most TR_MAX); after a
# step that had to be shortened it shrinks to that step's length.
TR_START = 0.5
TR_MAX = 2.0
# Stall: each of the last STALL_WINDOW accepted steps lowered max|F| by less than 10 %
# (Newton near a solution gains orders of magnitude per step; a search sliding into a local
# minimum of |P(z) - z|, as past a fold of the gait branch, gains almost nothing).  Measured
# on 200 guesses within +-50 % of the kneed gait: 117 converge (120 without the stall test,
# the three others after 29-302 evaluations), and the searches past the fold end after
# 10-47 evaluations instead of about 1,000.
STALL_WINDOW = 3
STALL_RATIO = 0.9
STALL_ALPHA = 1.0 / 16
# Energy bound of the walking region: kinetic energy at the section at most KINETIC_FACTOR
# times (the guess's kinetic energy + the walker's standing potential energy).  A stride
# map refuses any state above KINETIC_LIMIT times the standing potential energy.
KINETIC_FACTOR = 4.0
KINETIC_LIMIT = 50.0
# Work of one stride (adaptive methods): at most STEPS_PER_TIME_UNIT steps per natural time
# unit sqrt(l / g) of the stride map's t_max, and never fewer than STRIDE_MIN_STEPS.
STEPS_PER_TIME_UNIT = 60
STRIDE_MIN_STEPS = 1000


@runtime_checkable
class SectionMap(Protocol):
    """What the gait search needs from a section (stride) map.

    Rules an implementation must follow:

    1. ``n_z`` is the section dimension and ``section_names`` names its coordinates (length
       ``n_z``).
    2. ``section_map(z)`` with ``z`` of shape ``(n_z,)`` applies the map ``n_strides`` times and
       returns a :class:`~walker.results.MapResult`.  A failed stride has
       ``status != Status.COMPLETED`` and a NaN ``z``; it never raises for a state that merely
       does not walk.
    3. With ``jacobian=True`` the result carries ``jac``, the ``(n_z, n_z)`` derivative of the
       returned ``z`` with respect to the input ``z`` (for ``n_strides = k``: of the k-fold
       composition).
    4. ``parameter=value`` evaluates the map at another value of the continuation parameter
       without changing the object; ``None`` means ``parameter_value``.
    5. ``lift(z)`` gives the full state at the section point ``z``.
    6. ``parameter_name`` names the scalar continuation parameter (``"slope"`` for walkers),
       ``parameter_value`` is its current value, and ``with_parameter(value)`` returns a copy
       at another value.
    7. Instances should pickle (module-level classes) so that basin maps and sweeps can run on
       process pools.
    """

    n_z: int
    section_names: tuple[str, ...]
    parameter_name: str
    parameter_value: float

    def __call__(
        self,
        z: np.ndarray,
        *,
        jacobian: bool = False,
        n_strides: int = 1,
        parameter: float | None = None,
    ) -> MapResult: ...

    def lift(self, z: np.ndarray) -> np.ndarray: ...

    def with_parameter(self, value: float) -> SectionMap: ...


# --------------------------------------------------------------------------------------------
# The walking region (walker stride maps) and the work of one stride
# --------------------------------------------------------------------------------------------

# Section coordinate 0 is the stance-leg angle of every shipped walker: name -> coefficient of
# the slope in its angle from the slope normal (Garcia's theta is measured from the normal;
# the others from the vertical, counterclockwise, so psi = q + slope).
_STANCE_ANGLE = {"theta": 0.0, "q_stance": 1.0, "q1": 1.0, "q_leg": 1.0}


def _is_rate(name: str) -> bool:
    return name.startswith("qd") or name.endswith("_dot")


class WalkingRegion:
    """Where a walker's stride map is worth evaluating, from the model's own functions.

    Built from a walker model and its parameters (``WalkingRegion.of(stride_map)``):

    * ``scale`` (n_z,): the unit of each section coordinate for the search's trust region:
      1 for an angle [rad], ``sqrt(g / l)`` for a rate [rad/s] (``l`` the leg length, as in
      :func:`walker._checks.time_scale`), so a step of 1 is one radian or one natural rate.
    * stance leg: section coordinate 0 is the stance-leg angle (``theta``, ``q_stance``,
      ``q1``, ``q_leg``); a point whose stance leg lies at ``FALL_ANGLE``
      (walker/models/_common.py, 70 degrees) or more from the slope normal has fallen.
    * wound angles: every angle of the lifted state (its first ``n_q`` components) must lie
      within ``pi + |slope|`` of zero, i.e. within pi of the slope normal for the absolute
      angles (relative angles, such as a knee's, are held to the same bound).
    * energy: ``potential_up`` is the potential energy of ``lift(0)`` — the walker standing
      straight over its stance foot, datum at the foot (``energy(lift(0))[1]``; 11.9 J for
      Hsu Chen's kneed walker).  It is about what the walker would release falling flat, more
      than one step down the slope releases (``M g s sin(slope)``, step ``s < 2 l``) on any
      slope a passive gait exists on.  A search allows a kinetic energy at the section of at
      most ``KINETIC_FACTOR * (KE(lift(z0)) + potential_up)`` (the guess's kinetic energy
      covers the actuated walkers' work per step), :meth:`with_guess`; a stride map refuses
      any state above ``KINETIC_LIMIT * potential_up`` (there the stance foot would have
      left the ground long before: the centripetal demand exceeds gravity from about
      ``potential_up / 2``).

    A point outside is refused with a reason (:meth:`outside`) and never integrated.
    """

    def __init__(self, model, params):
        from walker.models._common import FALL_ANGLE

        self.model = model
        self.params = params
        self.p = np.ascontiguousarray(params.as_array(), dtype=np.float64)
        self.slope = float(getattr(params, "slope", 0.0))
        names = tuple(model.section_names)
        rate = 1.0 / time_scale(params)
        self.scale = np.array([rate if _is_rate(n) else 1.0 for n in names])
        self.stance = _STANCE_ANGLE.get(names[0]) if names else None
        self.fall_angle = FALL_ANGLE
        self.n_q = int(getattr(model.module, "N_Q", model.n_x // 2))
        self.wound_limit = math.pi + abs(self.slope)
        self.energy_address = model._state_fn("energy")
        try:
            up = self.kinetic_potential(model.lift(np.zeros(len(names)), self.p))[1]
        except (ValueError, ArithmeticError):
            up = float("nan")
        self.potential_up = float(up) if math.isfinite(up) and up > 0 else float("nan")
        self.kinetic_limit = (
            KINETIC_LIMIT * self.potential_up if math.isfinite(self.potential_up) else math.inf
        )
        self.kinetic_max = self.kinetic_limit

    @classmethod
    def of(cls, section_map, parameter: float | None = None) -> WalkingRegion | None:
        """The region of a walker's stride map (at ``parameter`` of its continuation
        parameter when given), or None for a map without a walker model."""
        from walker.models import WalkerModel

        model = getattr(section_map, "model", None)
        params = getattr(section_map, "params", None)
        if not isinstance(model, WalkerModel) or not model.is_walker:
            return None
        if not hasattr(params, "as_array"):
            return None
        if parameter is not None and float(parameter) != float(section_map.parameter_value):
            try:
                params = params.replace(**{section_map.parameter_name: float(parameter)})
            except (ValueError, TypeError):
                return None
        return cls(model, params)

    def kinetic_potential(self, x) -> tuple[float, float]:
        """(kinetic, potential) energy of the full state ``x`` [J]."""
        if self.energy_address is not None:
            from walker import _hybrid

            x = np.ascontiguousarray(x, dtype=np.float64)
            kinetic, potential = _hybrid.call_state_fn(self.energy_address, x, self.p, 2)
            return float(kinetic), float(potential)
        kinetic, potential = self.model.energy(x, self.p)
        return float(kinetic), float(potential)

    def with_guess(self, z0) -> WalkingRegion:
        """Set the search's energy bound from the guess ``z0`` (see the class docstring)."""
        try:
            kinetic0 = self.kinetic_potential(self.model.lift(z0, self.p))[0]
        except (ValueError, ArithmeticError):
            kinetic0 = float("nan")
        if math.isfinite(kinetic0) and math.isfinite(self.potential_up):
            bound = KINETIC_FACTOR * (kinetic0 + self.potential_up)
            self.kinetic_max = min(bound, self.kinetic_limit)
        return self

    def outside(self, z) -> str | None:
        """Why the section point ``z`` lies outside the walking region, or None (inside)."""
        if self.stance is not None:
            psi = float(z[0]) + self.stance * self.slope
            if not abs(psi) < self.fall_angle:
                return (
                    f"the stance leg is {psi:.4g} rad from the slope normal, beyond the fall "
                    f"angle {self.fall_angle:.4g} rad"
                )
        try:
            x = self.model.lift(z, self.p)
        except (ValueError, ArithmeticError) as exc:
            return f"it has no full state ({exc})"
        if not np.all(np.isfinite(x)):
            return "its full state is not finite"
        q = np.abs(x[: self.n_q])
        i = int(np.argmax(q))
        if q[i] > self.wound_limit:
            name = self.model.state_names[i]
            return f"the angle {name} = {x[i]:.4g} rad is wound beyond pi from the slope normal"
        kinetic = self.kinetic_potential(x)[0]
        if not kinetic <= self.kinetic_max:
            return (
                f"its kinetic energy {kinetic:.4g} J exceeds the bound {self.kinetic_max:.4g} J "
                "(rates far beyond any gait's)"
            )
        return None


def stride_max_steps(params, t_max: float, method: str, first_step: float | None) -> int:
    """Integration steps (accepted + rejected) one stride of a stride map may take.

    Adaptive methods: ``max(STRIDE_MIN_STEPS, ceil(STEPS_PER_TIME_UNIT * t_max / T))`` with
    ``T = sqrt(l / g)`` (:func:`walker._checks.time_scale`).  Measured on the shipped scenes'
    gaits with DOP853 at rtol = atol = 1e-12: a stride takes 17 (simplest) to 62 (five-link)
    steps over 1.7-3.9 T, i.e. 4-36 steps per T (83 steps, 49 per T, for the five-link walker
    at 1e-13); the kneed walker 37 steps.  With the scenes' ``t_max = 20 s`` (62.6 T) a stride
    may take 3757 steps, about 100 kneed strides; with the default ``t_max = 20 T``, 1200.  A
    walker swinging without a heel strike until ``t_max`` takes about 20 steps per T, well
    inside the budget; only states with rates far beyond any gait's (step sizes shrinking
    with the rates) run into it.  Fixed-step methods take ``ceil(t_max / first_step)``
    steps at most anyway; their budget is that plus two.
    """
    from walker.integrate import check_solver_settings

    _, _, _, first_step, adaptive = check_solver_settings(method, 1e-6, 1e-6, first_step)
    if not adaptive:
        return int(math.ceil(t_max / first_step)) + 2
    return max(STRIDE_MIN_STEPS, int(math.ceil(STEPS_PER_TIME_UNIT * t_max / time_scale(params))))


# --------------------------------------------------------------------------------------------
# Evaluation helpers (shared with continuation.py)
# --------------------------------------------------------------------------------------------


def _validate_section_map(section_map) -> None:
    """A TypeError naming ``section_map`` when it lacks what :class:`SectionMap` requires."""
    missing = [
        name
        for name in ("n_z", "section_names", "lift", "with_parameter")
        if not hasattr(section_map, name)
    ]
    if not callable(section_map):
        missing.insert(0, "__call__")
    if missing:
        raise TypeError(
            f"`section_map` must be a SectionMap (such as walker.stride.StrideMap), got "
            f"{type(section_map).__name__} without {', '.join(missing)}"
        )


def _validate_z(section_map: SectionMap, z: np.ndarray, name: str) -> np.ndarray:
    _validate_section_map(section_map)
    z = as_vector(z, name)
    n_z = int(section_map.n_z)
    if z.shape != (n_z,):
        raise ValueError(f"`{name}` must have shape ({n_z},) (the map's n_z), got {z.shape}")
    if not np.all(np.isfinite(z)):
        raise ValueError(f"All components of `{name}` must be finite, got {z}")
    return z


def _validate_period(period) -> int:
    if isinstance(period, bool) or not isinstance(period, int | np.integer) or period < 1:
        raise ValueError(f"`period` must be an integer >= 1, got {period!r}")
    return int(period)


def _validate_jacobian_mode(jacobian) -> str:
    if jacobian not in JACOBIAN_MODES:
        raise ValueError(f"`jacobian` must be one of {JACOBIAN_MODES}, got {jacobian!r}")
    return jacobian


def _validate_max_evals(max_evals) -> int | None:
    if max_evals is None:
        return None
    if isinstance(max_evals, bool) or not isinstance(max_evals, int | np.integer) or max_evals < 1:
        raise ValueError(f"`max_evals` must be None or an integer >= 1, got {max_evals!r}")
    return int(max_evals)


def _positive(value, name: str) -> float:
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise TypeError(f"`{name}` must be a real number, got {type(value).__name__} {value!r}")
    try:
        value = float(value)
    except OverflowError:
        raise ValueError(
            f"`{name}` must be positive and finite, got an integer too large for a float"
        ) from None
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"`{name}` must be positive and finite, got {value}")
    return value


def _map_value(section_map, z, period, parameter) -> MapResult:
    return section_map(z, jacobian=False, n_strides=period, parameter=parameter)


def _map_jacobian(section_map, z, period, parameter, mode, fd_step):
    """The ``period``-fold map at ``z`` and its Jacobian.

    Returns ``(result, jac, status)``; ``jac`` is None when a stride failed (``status`` says
    which).  ``mode="fd"`` uses central differences with step ``fd_step * max(1, |z_i|)``.
    """
    if mode == "exact":
        res = section_map(z, jacobian=True, n_strides=period, parameter=parameter)
        if not res.success:
            return res, None, res.status
        jac = np.asarray(res.jac, dtype=float)
        if not np.all(np.isfinite(jac)):
            return res, None, Status.NONFINITE
        return res, jac, Status.COMPLETED
    res = _map_value(section_map, z, period, parameter)
    if not res.success:
        return res, None, res.status
    n = z.shape[0]
    jac = np.empty((n, n))
    for i in range(n):
        h = fd_step * max(1.0, abs(z[i]))
        zp = z.copy()
        zm = z.copy()
        zp[i] += h
        zm[i] -= h
        rp = _map_value(section_map, zp, period, parameter)
        rm = _map_value(section_map, zm, period, parameter)
        if not (rp.success and rm.success):
            return res, None, rp.status if not rp.success else rm.status
        jac[:, i] = (rp.z - rm.z) / (2.0 * h)
    return res, jac, Status.COMPLETED


def _eig_sorted(jac: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (complex) sorted by decreasing modulus and the matching eigenvector columns."""
    lam, vec = np.linalg.eig(jac)
    order = np.argsort(-np.abs(lam), kind="stable")
    return lam[order].astype(complex), vec[:, order].astype(complex)


def _nan_fixed_point(n_z, status, message, z, history, n_iter, period, parameters, state=None):
    nan_c = np.full(n_z, np.nan, dtype=complex)
    return FixedPoint(
        status=status,
        message=message,
        success=False,
        section=np.asarray(z, dtype=float).copy(),
        state=np.full(1, np.nan) if state is None else state,
        step_time=float("nan"),
        multipliers=nan_c,
        eigenvectors=np.full((n_z, n_z), np.nan, dtype=complex),
        jacobian=np.full((n_z, n_z), np.nan),
        residual=float(history[-1]) if len(history) else float("nan"),
        n_iter=n_iter,
        history=np.asarray(history, dtype=float),
        period=period,
        stable=False,
        parameters=parameters,
    )


def _residual(section_map, z, period, parameter, with_jacobian=False):
    """``F(z) = P^k(z) - z`` and the map result (F is None when the stride failed).

    With ``with_jacobian`` the map is evaluated with its exact Jacobian in the same call, so
    an accepted Newton trial point brings the next iteration's Jacobian with it.
    """
    if with_jacobian:
        res = section_map(z, jacobian=True, n_strides=period, parameter=parameter)
    else:
        res = _map_value(section_map, z, period, parameter)
    if not res.success or not np.all(np.isfinite(res.z)):
        return None, res
    return res.z - z, res


def _usable_jacobian(res):
    jac = getattr(res, "jac", None)
    if jac is None:
        return None
    jac = np.asarray(jac, dtype=float)
    return jac if np.all(np.isfinite(jac)) else None


class _OutOfBudget(Exception):
    """The search's evaluation budget is spent (internal)."""


class _Evaluator:
    """Counts the search's stride-map evaluations against its budget."""

    __slots__ = ("section_map", "period", "parameter", "max_evals", "n_evals")

    def __init__(self, section_map, period, parameter, max_evals):
        self.section_map = section_map
        self.period = period
        self.parameter = parameter
        self.max_evals = max_evals
        self.n_evals = 0

    def _spend(self, n):
        if self.n_evals + n > self.max_evals:
            raise _OutOfBudget
        self.n_evals += n

    def residual(self, z, with_jacobian=False):
        self._spend(1)
        return _residual(self.section_map, z, self.period, self.parameter, with_jacobian)

    def jacobian(self, z, mode, fd_step):
        self._spend(1 if mode == "exact" else 1 + 2 * z.shape[0])
        return _map_jacobian(self.section_map, z, self.period, self.parameter, mode, fd_step)


def default_max_evals(n_z: int, mode: str) -> int:
    """The default evaluation budget: ``MAX_EVALS`` with the exact Jacobian, plus room for
    ``FD_EXTRA_JACOBIANS`` central-difference Jacobians (``2 n_z`` evaluations each) with
    ``jacobian="fd"``."""
    return MAX_EVALS + (0 if mode == "exact" else FD_EXTRA_JACOBIANS * 2 * int(n_z))


def _hint(section_map, parameter, *, budget=False) -> str:
    """What a user can change, on the command line and from Python."""
    name = getattr(section_map, "parameter_name", "parameter")
    value = section_map.parameter_value if parameter is None else parameter
    py = "raise `max_evals`, or pass another `z0`" if budget else "pass another `z0`"
    return (
        f"On the command line: try `--set {name}=...` closer to a value where a gait is known "
        f"(here {name} = {float(value):.6g}), or a better `[initial] state` in the scene file; "
        f"from Python: {py}, or follow a known gait with `continue_branch`."
    )


def _solve_fixed_point(
    section_map,
    z0,
    *,
    period,
    parameter,
    tol,
    max_iter,
    mode,
    fd_step,
    fallback,
    max_evals=None,
    region=None,
):
    """Damped Newton + LM on ``P^k(z) - z`` at a fixed parameter, in a trust region.

    ``max_evals`` bounds the stride-map evaluations (None: :func:`default_max_evals`);
    ``region`` is the walking region (None: :meth:`WalkingRegion.of` the map, which is None
    for a map without a walker model).  Returns ``(status, message, z, history, n_iter,
    known)`` where ``z`` is the last accepted iterate and ``known`` the map result at ``z``
    when it was computed there with its exact Jacobian (else None), so the Jacobian at the
    solution is not computed twice.
    """
    if region is None:
        region = WalkingRegion.of(section_map, parameter)
        if region is not None:
            region.with_guess(z0)
    if max_evals is None:
        max_evals = default_max_evals(z0.shape[0], mode)
    ev = _Evaluator(section_map, period, parameter, int(max_evals))
    state = {"z": z0.copy(), "history": [], "it": 0}
    try:
        return _search(ev, z0, state, region, tol, max_iter, mode, fd_step, fallback)
    except _OutOfBudget:
        history = state["history"]
        last = (
            f"max|F| = {history[-1]:.3g} at the last accepted iterate"
            if history
            else "before the first stride was evaluated"
        )
        msg = (
            f"No period-{period} orbit within the budget of {ev.max_evals} stride-map "
            f"evaluations (`max_evals`): {last}, iterate {state['it']}. "
            + _hint(section_map, parameter, budget=True)
        )
        return Status.BUDGET_EXHAUSTED, msg, state["z"], history, state["it"], None


def _search(ev, z0, state, region, tol, max_iter, mode, fd_step, fallback):
    period = ev.period
    z = z0.copy()
    n = z.shape[0]
    eye = np.eye(n)
    exact = mode == "exact"
    gait = region is not None  # a walker's stride map: gait statuses and messages
    scale = region.scale if gait else np.maximum(1.0, np.abs(z0))
    if gait:
        why = region.outside(z)
        if why is not None:
            msg = (
                f"The initial guess lies outside the region where the walker can walk: {why}. "
                "It was not integrated. Start from a state near a gait: on the command line "
                "the scene's `[initial] state`, from Python `z0`."
            )
            return Status.OUTSIDE_WALKING_REGION, msg, z, [], 0, None
    f, res = ev.residual(z, with_jacobian=exact)
    jac_here = _usable_jacobian(res) if exact else None
    res_here = res
    if f is None:
        msg = (
            f"The starting point fails within {period} stride(s): {res.status.message} "
            "Start from a state that walks."
        )
        return res.status, msg, z, [], 0, None
    history = state["history"]
    history.append(float(np.max(np.abs(f))))
    lm = LM_START
    radius = TR_START
    poor = []  # per accepted step: did it gain little (see STALL_RATIO, STALL_ALPHA)?
    for it in range(max_iter + 1):
        state["it"] = it
        if history[-1] <= tol:
            known = res_here if jac_here is not None else None
            return Status.COMPLETED, _converged_message(tol, it, history), z, history, it, known
        if it == max_iter:
            break
        if len(poor) >= STALL_WINDOW and all(poor[-STALL_WINDOW:]):
            return _stalled(ev, z, history, it, gait, fallback, "stall")
        if jac_here is not None:
            jac_map, st = jac_here, Status.COMPLETED
        else:
            _, jac_map, st = ev.jacobian(z, mode, fd_step)
        if jac_map is None:
            msg = (
                f"Computing the Jacobian at iterate {it} failed ({st.name}): {st.message} "
                "Try `jacobian='exact'` or a better initial guess."
            )
            return st, msg, z, history, it, None
        a = jac_map - eye
        merit = float(np.linalg.norm(f))
        accepted = False
        shortened = False
        alpha = 1.0
        refused = 0  # trial points outside the walking region (not integrated)
        failed = 0  # trial strides that failed
        walked = 0  # trial strides that completed
        why_refused = ""
        # --- Newton step, cut to the trust region, with backtracking on ||F||_2 ----------
        cond = np.linalg.cond(a)
        full_step_status = Status.COMPLETED
        if np.isfinite(cond) and cond < COND_MAX:
            dz = np.linalg.solve(a, -f)
            length = float(np.max(np.abs(dz) / scale))
            if length > radius:
                dz *= radius / length
            alpha = 1.0
            for _ in range(MAX_HALVINGS):
                z_try = z + alpha * dz
                why = region.outside(z_try) if gait else None
                if why is not None:
                    refused += 1
                    why_refused = why_refused or why
                    if alpha == 1.0:
                        full_step_status = Status.OUTSIDE_WALKING_REGION
                    alpha *= 0.5
                    continue
                f_try, res_try = ev.residual(z_try, with_jacobian=exact and alpha == 1.0)
                if f_try is None:
                    failed += 1
                    if alpha == 1.0:
                        full_step_status = res_try.status
                else:
                    walked += 1
                    merit_try = float(np.linalg.norm(f_try))
                    if merit_try <= (1 - ARMIJO * alpha) * merit:
                        accepted = True
                        shortened = alpha < 1.0
                        break
                    if merit_try <= (1 + LINE_FLAT) * merit:
                        break  # flat along the Newton direction: a local minimum of ||F||
                alpha *= 0.5
        elif not fallback:
            msg = (
                f"The Newton matrix DP^{period} - I is singular (condition number {cond:.3g}) "
                f"at iterate {it}; the orbit may sit at a fold or the map may have no fixed "
                "point here. Try `fallback=True`, another initial guess, or continuation."
            )
            return Status.LINEAR_SOLVE_FAILED, msg, z, history, it, None
        # --- Levenberg–Marquardt fallback when Newton stalls, in the same trust region ----
        if not accepted and fallback:
            jtj = a.T @ a
            g = a.T @ f
            lm_scale = np.diag(np.maximum(np.diag(jtj), 1e-12))
            tries = 0
            while lm <= LM_MAX and tries < LM_TRIES:
                tries += 1
                try:
                    dz = np.linalg.solve(jtj + lm * lm_scale, -g)
                except np.linalg.LinAlgError:
                    lm *= LM_GROW
                    continue
                length = float(np.max(np.abs(dz) / scale))
                if not np.isfinite(length):
                    lm *= LM_GROW
                    continue
                if length > radius:
                    dz *= radius / length
                z_try = z + dz
                why = region.outside(z_try) if gait else None
                if why is not None:
                    refused += 1
                    why_refused = why_refused or why
                    lm *= LM_GROW
                    continue
                f_try, res_try = ev.residual(z_try)
                if f_try is None:
                    failed += 1
                elif np.linalg.norm(f_try) < merit:
                    accepted = True
                    lm = max(lm * LM_SHRINK, 1e-12)
                    break
                else:
                    walked += 1
                lm *= LM_GROW
            if not accepted and lm > LM_MAX:
                lm = LM_START
        if not accepted:
            if gait and full_step_status != Status.COMPLETED and walked == 0:
                return _diverged(ev, z, history, it, full_step_status, why_refused, refused)
            if full_step_status not in (Status.COMPLETED, Status.NONFINITE) and not gait:
                msg = (
                    f"Newton stalled at iterate {it} (max|F| = {history[-1]:.3g}) because the "
                    f"full Newton step leads to a state that fails: {full_step_status.message} "
                    "The orbit sought may not walk; try another initial guess or parameter."
                )
                return full_step_status, msg, z, history, it, None
            return _stalled(ev, z, history, it, gait, fallback, "no_descent")
        step = float(np.max(np.abs(z_try - z) / scale))
        radius = step if shortened else min(TR_MAX, max(radius, 2.0 * step))
        z = z_try
        state["z"] = z
        f = f_try
        jac_here = _usable_jacobian(res_try) if exact else None
        res_here = res_try
        history.append(float(np.max(np.abs(f))))
        poor.append(history[-1] > STALL_RATIO * history[-2] or (shortened and alpha <= STALL_ALPHA))
    msg = (
        f"Newton did not reach max|P^{period}(z) - z| <= {tol:.3g} in {max_iter} iterations "
        f"(last residual {history[-1]:.3g}). Try more `max_iter`, a looser `tol`, or a better "
        "initial guess."
    )
    return Status.NOT_CONVERGED, msg, z, history, max_iter, None


def _stalled(ev, z, history, it, gait, fallback, why):
    """The residual stalls at a positive value: a local minimum of ``|P^k(z) - z|``."""
    period = ev.period
    what = "Newton and Levenberg-Marquardt" if fallback else "Newton"
    if why == "stall":
        how = (
            f"max|P^{period}(z) - z| stalled at {history[-1]:.3g} (each of the last "
            f"{STALL_WINDOW} steps lowered it by less than {1 - STALL_RATIO:.0%}) at iterate {it}"
        )
    else:
        how = (
            f"{what} could not reduce ||P^{period}(z) - z|| below {history[-1]:.3g} at iterate {it}"
        )
    if not gait:
        msg = (
            f"{how}; there may be no period-{period} orbit near the guess. Try a better initial "
            "guess (e.g. from continuation or brute-force iteration)"
            + ("." if fallback else ", or `fallback=True`.")
        )
        return Status.NOT_CONVERGED, msg, z, history, it, None
    msg = (
        f"No period-{period} gait near the initial guess: {how}, after {ev.n_evals} stride-map "
        "evaluations. This is what a search sees past a fold of the gait branch, where the gait "
        "ceases to exist. " + _hint(ev.section_map, ev.parameter)
    )
    return Status.NO_GAIT_NEAR_GUESS, msg, z, history, it, None


def _diverged(ev, z, history, it, full_step_status, why_refused, refused):
    """Every trial step leads out of the walking region (refused or falling)."""
    if full_step_status == Status.OUTSIDE_WALKING_REGION:
        lead = f"leads outside the region where the walker can walk ({why_refused})"
    else:
        lead = f"leads to a stride that fails ({full_step_status.name})"
    msg = (
        f"The search diverged at iterate {it} (max|F| = {history[-1]:.3g}): the Newton step "
        f"{lead}, and no shorter step walks and reduces the residual ({refused} trial point(s) "
        f"refused without integrating them; {ev.n_evals} stride-map evaluations in all). "
        + _hint(ev.section_map, ev.parameter)
    )
    return Status.DIVERGED, msg, z, history, it, None


def _converged_message(tol, n_iter, history):
    return (
        f"Converged: max|P^k(z) - z| = {history[-1]:.3g} <= tol = {tol:.3g} (absolute, section "
        f"units) after {n_iter} iteration(s)."
    )


def _finish(
    section_map,
    z,
    *,
    period,
    parameter,
    mode,
    fd_step,
    status,
    message,
    history,
    n_iter,
    known=None,
):
    """Build the FixedPoint: the Jacobian at the solution (reused from the last Newton
    evaluation when it carried one), multipliers, lift."""
    n_z = z.shape[0]
    pvalue = section_map.parameter_value if parameter is None else parameter
    parameters = {section_map.parameter_name: float(pvalue)}
    model = getattr(section_map, "model", None)
    conventions = getattr(model, "conventions", None)
    conventions = dict(conventions) if isinstance(conventions, dict) else {}
    # lift may depend on the parameter (e.g. the slope fixes the swing angle at heel strike)
    lifter = section_map
    if parameter is not None and float(parameter) != float(section_map.parameter_value):
        lifter = section_map.with_parameter(float(parameter))
    try:
        state = np.asarray(lifter.lift(z), dtype=float)
    except ValueError:  # a guess outside the walking region may have no full state
        if status == Status.COMPLETED:
            raise
        state = np.full(int(getattr(getattr(lifter, "model", None), "n_x", 1)), np.nan)
    if status != Status.COMPLETED:
        fp = _nan_fixed_point(
            n_z,
            status,
            message,
            z,
            history,
            n_iter,
            period,
            parameters,
            np.full_like(state, np.nan),
        )
        fp.conventions = conventions
        return fp
    if known is not None:
        res, jac, st = known, np.asarray(known.jac, dtype=float), Status.COMPLETED
    else:
        res, jac, st = _map_jacobian(section_map, z, period, parameter, mode, fd_step)
    if jac is None:
        msg = (
            f"Converged, but the Jacobian at the solution failed ({st.name}): {st.message} "
            "Try `jacobian='fd'` or a smaller `fd_step`."
        )
        fp = _nan_fixed_point(
            n_z, st, msg, z, history, n_iter, period, parameters, np.full_like(state, np.nan)
        )
        fp.conventions = conventions
        return fp
    lam, vec = _eig_sorted(jac)
    return FixedPoint(
        status=Status.COMPLETED,
        message=message,
        success=True,
        section=z.copy(),
        state=state,
        step_time=float(res.step_time),
        multipliers=lam,
        eigenvectors=vec,
        jacobian=jac,
        residual=float(history[-1]),
        n_iter=n_iter,
        history=np.asarray(history, dtype=float),
        period=period,
        stable=bool(np.all(np.abs(lam) < 1.0)),
        parameters=parameters,
        conventions=conventions,
    )


# --------------------------------------------------------------------------------------------
# Public API
# --------------------------------------------------------------------------------------------


def find_fixed_point(
    section_map: SectionMap,
    z0: np.ndarray,
    *,
    period: int = 1,
    tol: float = 1e-12,
    max_iter: int = 50,
    jacobian: str = "exact",
    fd_step: float = 1e-7,
    fallback: bool = True,
    parameter: float | None = None,
    max_evals: int | None = None,
) -> FixedPoint:
    """Find a period-``period`` orbit of a section map by damped Newton.

    Solves ``F(z) = P^k(z) - z = 0`` with ``k = period``.  Each iteration takes the Newton
    step ``(DP^k - I) dz = -F``, cut to the trust region, and backtracks (halving) until the
    2-norm of ``F`` drops (Armijo condition).  When the Newton matrix is singular or the line
    search fails and ``fallback`` is True, Levenberg–Marquardt steps
    ``(A^T A + mu diag(A^T A)) dz = -A^T F`` with adaptive damping ``mu``, cut to the same
    trust region, are tried instead.

    The trust region is a max-norm ball in scaled section coordinates: for a walker's stride
    map angles in rad and rates in units of ``sqrt(g / l)`` (:class:`WalkingRegion`), for
    another section map each coordinate in units of ``max(1, |z0_i|)``.  Its radius starts at
    ``TR_START = 0.5``, grows to twice an accepted full step (at most ``TR_MAX = 2``) and
    shrinks to a step that had to be shortened.  For a walker's stride map (a map with a
    walker ``model`` and ``params``, such as :class:`walker.stride.StrideMap`) a trial point
    outside the walking region (:meth:`WalkingRegion.outside`: stance leg past the fall
    angle, an angle wound beyond pi, kinetic energy above ``KINETIC_FACTOR`` times the
    guess's kinetic plus the walker's standing potential energy) is refused without
    integrating it.

    Parameters
    ----------
    section_map : SectionMap
        the stride map.
    z0 : ndarray, shape (n_z,)
        initial guess in section coordinates.
    period : int
        number of strides per orbit (the map is called with ``n_strides=period``).
    tol : float
        convergence when ``max|P^k(z) - z| <= tol`` (absolute, in section units).
    max_iter : int
        maximum number of accepted Newton / LM steps.
    jacobian : {"exact", "fd"}
        ``"exact"``: the map's own Jacobian (``jacobian=True``; for walkers from the
        variational equations and saltation matrices); ``"fd"``: central finite differences
        with step ``fd_step * max(1, |z_i|)``.
    fd_step : float
        relative finite-difference step (``jacobian="fd"`` only).
    fallback : bool
        use Levenberg–Marquardt when Newton stalls or its matrix is singular.
    parameter : float, optional
        evaluate the map at this value of its continuation parameter (default: the map's
        ``parameter_value``).
    max_evals : int, optional
        evaluation budget: the most section-map calls the search may make (each call counts
        once whatever ``period``; a finite-difference Jacobian counts ``2 n_z + 1``).
        Default ``MAX_EVALS = 60`` with the exact Jacobian, ``60 + 20 n_z`` with
        ``jacobian="fd"``.  The gaits of the shipped scenes converge from their scene
        guesses in 1-5 evaluations.  The Jacobian at a converged solution is computed
        outside the budget when the last Newton step did not bring it.

    Returns
    -------
    FixedPoint
        ``status`` is ``Status.COMPLETED`` on convergence; otherwise it says why the search
        ended (never an exception):

        * ``BUDGET_EXHAUSTED``: ``max_evals`` evaluations without convergence;
        * ``NO_GAIT_NEAR_GUESS`` (walker stride maps): the residual stalls at a positive
          value (each of 3 steps lowered it by less than 10 %, or no step in the trust region
          reduces it): a local minimum of ``|P^k(z) - z|``, as past a fold of the branch;
          ``NOT_CONVERGED`` for other section maps;
        * ``DIVERGED`` (walker stride maps): the Newton step leads out of the walking region
          (refused, or a stride that fails) and no shorter step walks and reduces the
          residual; for other section maps the failing stride's status (e.g.
          ``FELL_FORWARD``);
        * ``OUTSIDE_WALKING_REGION``: the guess itself lies outside the walking region (it
          is not integrated);
        * ``NOT_CONVERGED`` after ``max_iter`` iterations; ``LINEAR_SOLVE_FAILED`` for a
          singular Newton matrix without fallback; the failing stride's status when the
          walker falls from the guess or during a Jacobian evaluation.

        The message names what to change, on the command line (``--set``, the scene's
        ``[initial] state``) and from Python.  ``history`` holds ``max|F|`` at each accepted
        iterate.  On success the Jacobian of ``P^k`` is recomputed at the solution;
        ``multipliers`` are its eigenvalues sorted by decreasing modulus, ``eigenvectors``
        the matching columns, ``stable`` is True when all ``|multiplier| < 1``.  On failure
        ``section`` is the last accepted iterate (finite, inside the walking region unless
        the guess was outside) and the multipliers are NaN.

    Raises
    ------
    ValueError
        for a ``z0`` of the wrong shape or with non-finite entries, ``period < 1``,
        ``tol <= 0``, ``max_iter < 1``, ``max_evals < 1``, ``fd_step <= 0`` or an unknown
        ``jacobian`` mode.

    Examples
    --------
    >>> import numpy as np
    >>> from walker.results import MapResult
    >>> from walker.status import Status
    >>> class Halve:  # z -> z / 2 + 1, fixed point z = 2
    ...     n_z, section_names, parameter_name, parameter_value = 1, ("z",), "c", 1.0
    ...     def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
    ...         for _ in range(n_strides):
    ...             z = z / 2 + 1
    ...         jac = np.array([[0.5**n_strides]]) if jacobian else None
    ...         return MapResult(Status.COMPLETED, z, jac, float(n_strides), z)
    ...     def lift(self, z):
    ...         return z
    ...     def with_parameter(self, value):
    ...         return self
    >>> fp = find_fixed_point(Halve(), np.array([0.0]))
    >>> fp.success, float(fp.section[0]), complex(fp.multipliers[0]).real
    (True, 2.0, 0.5)
    """
    z0 = _validate_z(section_map, z0, "z0")
    period = _validate_period(period)
    tol = _positive(tol, "tol")
    if isinstance(max_iter, bool) or not isinstance(max_iter, int | np.integer) or max_iter < 1:
        raise ValueError(f"`max_iter` must be an integer >= 1, got {max_iter!r}")
    mode = _validate_jacobian_mode(jacobian)
    fd_step = _positive(fd_step, "fd_step")
    max_evals = _validate_max_evals(max_evals)
    status, message, z, history, n_iter, jac_at_z = _solve_fixed_point(
        section_map,
        z0,
        period=period,
        parameter=parameter,
        tol=tol,
        max_iter=int(max_iter),
        mode=mode,
        fd_step=fd_step,
        fallback=bool(fallback),
        max_evals=max_evals,
    )
    return _finish(
        section_map,
        z,
        known=jac_at_z,
        period=period,
        parameter=parameter,
        mode=mode,
        fd_step=fd_step,
        status=status,
        message=message,
        history=history,
        n_iter=n_iter,
    )


def floquet(
    section_map: SectionMap,
    z: np.ndarray,
    period: int = 1,
    *,
    jacobian: str = "exact",
    fd_step: float = 1e-7,
    parameter: float | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Floquet multipliers of the period-``period`` map at ``z``.

    Parameters
    ----------
    section_map : SectionMap
    z : ndarray, shape (n_z,)
        the (fixed) point in section coordinates.
    period : int
        the map is composed ``period`` times.
    jacobian : {"exact", "fd"}
        as in :func:`find_fixed_point`.
    fd_step : float
        relative finite-difference step (``jacobian="fd"``).
    parameter : float, optional
        map parameter (default: its ``parameter_value``).

    Returns
    -------
    multipliers : ndarray of complex, shape (n_z,)
        eigenvalues of ``J``, sorted by decreasing modulus.
    eigenvectors : ndarray of complex, shape (n_z, n_z)
        columns match ``multipliers``.
    J : ndarray, shape (n_z, n_z)
        Jacobian of ``P^period`` at ``z``.
        All three are NaN when a stride fails from ``z`` (a status, not an exception).

    Examples
    --------
    >>> import numpy as np
    >>> from walker.results import MapResult
    >>> from walker.status import Status
    >>> class Linear:
    ...     n_z, section_names, parameter_name, parameter_value = 2, ("x", "y"), "c", 0.0
    ...     A = np.array([[0.5, 0.0], [0.0, -2.0]])
    ...     def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
    ...         a = np.linalg.matrix_power(self.A, n_strides)
    ...         return MapResult(Status.COMPLETED, a @ z, a if jacobian else None, 1.0, z)
    ...     def lift(self, z):
    ...         return z
    ...     def with_parameter(self, value):
    ...         return self
    >>> lam, vec, J = floquet(Linear(), np.zeros(2))
    >>> lam.real.tolist()
    [-2.0, 0.5]
    """
    z = _validate_z(section_map, z, "z")
    period = _validate_period(period)
    mode = _validate_jacobian_mode(jacobian)
    fd_step = _positive(fd_step, "fd_step")
    n = z.shape[0]
    _, jac, _ = _map_jacobian(section_map, z, period, parameter, mode, fd_step)
    if jac is None:
        nan = np.full((n, n), np.nan)
        return np.full(n, np.nan, dtype=complex), nan.astype(complex), nan
    lam, vec = _eig_sorted(jac)
    return lam, vec, jac


def classify(multipliers: np.ndarray) -> str:
    """Stability type of an orbit from its Floquet multipliers.

    Rule: ``"stable"`` when every ``|lambda| < 1``; ``"unstable"`` when every
    ``|lambda| >= 1`` (a repeller, or a marginal orbit with a multiplier on the unit circle and
    none inside); ``"saddle"`` when some are strictly inside and some on or outside the unit
    circle.

    Parameters
    ----------
    multipliers : array_like of complex, shape (n,)

    Returns
    -------
    str
        ``"stable"``, ``"unstable"`` or ``"saddle"``.

    Raises
    ------
    ValueError
        when ``multipliers`` is empty, not 1-D or not finite (e.g. from a failed search).

    Examples
    --------
    >>> classify([0.5, -0.2j]), classify([2.0, 1.5]), classify([0.5, 1.2])
    ('stable', 'unstable', 'saddle')
    """
    lam = np.asarray(multipliers, dtype=complex)
    if lam.ndim != 1 or lam.size == 0:
        raise ValueError(f"`multipliers` must be a non-empty 1-D array, got shape {lam.shape}")
    if not np.all(np.isfinite(lam)):
        raise ValueError("All `multipliers` must be finite (did the fixed-point search fail?)")
    inside = np.abs(lam) < 1.0
    if np.all(inside):
        return "stable"
    if not np.any(inside):
        return "unstable"
    return "saddle"
