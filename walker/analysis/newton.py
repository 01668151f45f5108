"""The gait search at a fixed parameter: damped Newton with a Levenberg–Marquardt fallback.

:func:`solve_fixed_point` solves ``F(z) = P^k(z) - z = 0`` on the Poincaré section and
returns a :class:`NewtonResult` (how the search ended, where, and the map result at the
solution when the last step brought its Jacobian).
:func:`walker.analysis.fixedpoint.find_fixed_point` checks the input, calls it and builds the
:class:`~walker.results.FixedPoint`; the natural continuation corrector
(:mod:`walker.analysis.steppers`) calls it with a small budget.

Each step is confined to a trust region in scaled section coordinates
(:class:`~walker.simulation.region.WalkingRegion`), a trial point outside the walking region of a
walker's map is refused without integrating it, and the search stops after ``max_evals``
map evaluations, when the residual stalls, or when the steps keep leading out of the
walking region (see :mod:`walker.analysis.fixedpoint` for the statuses).

The search itself is written once, in C (walker/_core/newton.c, ``walker._hybrid.search``):
on a :class:`~walker.simulation.stride.StrideMap` with a compiled call and the exact Jacobian it
runs in one compiled call without the GIL (``PreparedMap.search``); on every other map (a
:class:`walker.SystemMap`, a user's map, finite differences, wrappers, a spy on
``StrideMap.__call__``) the same search evaluates the map through Python callbacks
(:class:`_Search`).  This module passes its constants in, and builds the result and its
message from how the search ended.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from walker import _hybrid
from walker.results import MapResult
from walker.simulation.region import WalkingRegion
from walker.simulation.sectionmap import map_jacobian, map_value
from walker.status import Status

__all__ = ["NewtonResult", "default_max_evals", "solve_fixed_point"]

_frombuffer = np.frombuffer  # a float64 array on a bytearray of walker._hybrid, no copy

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
# A Newton matrix whose condition number (Frobenius, newton.c's newton_step) exceeds this
# is treated as singular.
COND_MAX = 1e14
# Coarse early strides (inexact Newton, find_fixed_point only): far from the fixed point a
# stride need not be integrated to the map's own rtol.  A point whose residual is expected
# to be r is evaluated at the coarsest power-of-ten rtol <= COARSE_RHO * r**2 (and <=
# COARSEST_RTOL): DOP853's stride error at rtol t is about 0.05 t on the walkers (kneed:
# 7.6e-8 at 1e-6, 3e-10 at 1e-8, 4e-11 at 1e-9), so what it adds to the next Newton iterate
# stays far below that iterate's own error, about r**2.  A coarse evaluation is kept only when
# its residual r' > tol and its rtol <= COARSE_KEEP * r'**2; else the point is evaluated
# again (counted) at the rtol for r', or the map's own.  A converged solution is always one
# evaluated at the map's own tolerance.  From the kneed scene's guess (max|F| 1.7e-2) the
# first two of the four Jacobian strides run at 1e-6 and 1e-9 instead of 1e-12.
COARSEST_RTOL = 1e-6
COARSE_RHO = 0.1
COARSE_KEEP = 1.0

# --- Failing fast ----------------------------------------------------------------------------
# Evaluation budget: stride-map calls a search may make (any n_strides; the Jacobian at a
# converged solution, when the last Newton step did not bring it, is not counted).  The
# shipped scenes' gaits converge from their scene guesses in 1-5 evaluations (kneed: 5, the
# coarse glance at the guess included, COARSE_RHO), and from 200 guesses within +-50 % of
# the kneed or the compass gait (numpy seed 1) in at most 20 and 30 (25 and 39 for any end).
MAX_EVALS = 60
# With finite-difference Jacobians each Jacobian costs 2 n_z evaluations more: room for ten.
FD_EXTRA_JACOBIANS = 10
# Budget of each search at a sweep point (walker.analysis.sweep.sweep_chunk: the warm start, and the
# retry from the sweep's guess): about 2x what a gait needs from a warm start (5-7 on the
# kneed slope sweep, the coarse glance included), so a point without a gait costs a few tens
# of strides at most.
POINT_MAX_EVALS = 12
# Natural-continuation correctors (walker.analysis.continuation): CORRECTOR_EVALS_PER_ITER
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


@dataclass
class NewtonResult:
    """How :func:`solve_fixed_point` ended.

    Attributes
    ----------
    status : Status
        ``COMPLETED`` on convergence, else why the search ended.
    message : str
        what happened, and what to change.
    z : ndarray, shape (n_z,)
        the solution, or the last accepted iterate.
    history : list of float
        ``max|F|`` at each accepted iterate (empty when the guess was not evaluated).
    n_iter : int
        accepted iterations.
    known : MapResult or None
        the map at ``z`` with its exact Jacobian when the last step computed it there (so the
        Jacobian at the solution is not computed twice), else None.
    """

    status: Status
    message: str
    z: np.ndarray
    history: list
    n_iter: int
    known: MapResult | None = None

    @property
    def success(self) -> bool:
        return self.status == Status.COMPLETED


def _coarse_levels(section_map):
    """``(rtol, atol)`` of a map whose strides the search may integrate more coarsely (a
    DOP853 map with ``with_tolerance`` and an rtol finer than ``COARSEST_RTOL``), else None."""
    # with_tolerance defined by the map's class (a wrapper forwarding attributes to a
    # StrideMap is not bypassed)
    if getattr(section_map, "method", None) != "DOP853" or not hasattr(
        type(section_map), "with_tolerance"
    ):
        return None
    rtol, atol = float(section_map.rtol), float(section_map.atol)
    return (rtol, atol) if 10.0 * rtol <= COARSEST_RTOL else None


def _answer(res, with_jacobian):
    """A map result as the C search reads it: ``(status, z or None, jac or None, res)``."""
    if not res.success:
        return int(res.status), None, None, res
    z = np.ascontiguousarray(res.z, dtype=np.float64)
    jac = getattr(res, "jac", None) if with_jacobian else None
    if jac is not None:
        jac = np.ascontiguousarray(jac, dtype=np.float64).reshape(-1)
    return int(res.status), z, jac, res


# The constants above that the C search reads, each as the keyword of its lowercase name
# (read at each search: a test may change one).
_CONSTANTS = (
    "ARMIJO LINE_FLAT COND_MAX MAX_HALVINGS LM_START LM_GROW LM_SHRINK LM_MAX LM_TRIES "
    "TR_START TR_MAX STALL_WINDOW STALL_RATIO STALL_ALPHA COARSEST_RTOL COARSE_RHO COARSE_KEEP"
).split()


class _Search:
    """One search's map and settings, and the callbacks through which the C search
    (``walker._hybrid.search``) evaluates a map without a compiled path: ``evaluate`` (the
    ``period``-fold map at a point, at the map's own rtol or a coarser one), ``jacobian``
    (the map's own or central differences, :func:`~walker.simulation.sectionmap.map_jacobian`) and
    ``outside`` (the walking region's refusals, numbered in ``reasons``)."""

    def __init__(self, section_map, period, parameter, max_evals, tol, mode, fd_step, coarse):
        self.section_map = section_map
        self.period = period
        self.parameter = parameter
        self.max_evals = max_evals
        self.n_evals = 0
        self.tol = tol
        self.mode = mode
        self.fd_step = fd_step
        self.own = _coarse_levels(section_map) if coarse and mode == "exact" else None
        self.maps = {}  # the coarse maps by rtol
        self.region = None
        self.reasons = []

    def settings(self, max_iter, fallback, n_z) -> dict:
        """The search's settings and this module's constants, as the binding's keywords."""
        own = self.own
        return {
            "period": self.period,
            "tol": float(self.tol),
            "max_iter": int(max_iter),
            "fallback": bool(fallback),
            "max_evals": self.max_evals,
            "exact": self.mode == "exact",
            "jac_cost": 1 if self.mode == "exact" else 1 + 2 * n_z,
            "coarse": own is not None,
            "own_rtol": own[0] if own is not None else 1.0,
            "own_atol": own[1] if own is not None else 1.0,
            **{name.lower(): globals()[name] for name in _CONSTANTS},
        }

    def evaluate(self, z, level, with_jacobian):
        """The map at ``z`` at rtol ``level`` (0: the map's own), as :func:`_answer`."""
        z = _frombuffer(z)
        section_map = self.section_map
        if level > 0.0:  # StrideMap.with_tolerance(level, min(atol * level / rtol, level))
            section_map = self.maps.get(level)
            if section_map is None:
                rtol, atol = self.own
                section_map = self.section_map.with_tolerance(
                    level, min(atol * level / rtol, level)
                )
                self.maps[level] = section_map
        if with_jacobian:
            res = section_map(z, jacobian=True, n_strides=self.period, parameter=self.parameter)
        else:
            res = map_value(section_map, z, self.period, self.parameter)
        return _answer(res, with_jacobian)

    def jacobian(self, z):
        """The Jacobian at ``z`` (``mode``), as ``(status, None, jac or None, None)``."""
        z = _frombuffer(z)
        _, jac, st = map_jacobian(
            self.section_map, z, self.period, self.parameter, self.mode, self.fd_step
        )
        if jac is not None:
            jac = np.ascontiguousarray(jac, dtype=np.float64).reshape(-1)
        return int(st), None, jac, None

    def outside(self, z) -> int:
        """0 when ``z`` lies in the walking region, else the number of its reason."""
        why = self.region.outside(_frombuffer(z))
        if why is None:
            return 0
        self.reasons.append(why)
        return len(self.reasons)


# The search's ends as walker/_core/newton.h numbers them (WK_SEARCH_*), and its code for a
# reason of the map's own (WK_OUT_OTHER).
(
    _C_CONVERGED,
    _C_OUTSIDE_GUESS,
    _C_START_FAILS,
    _C_BUDGET,
    _C_STALL,
    _C_NO_DESCENT,
    _C_DIVERGED,
    _C_JACOBIAN_FAILED,
    _C_SINGULAR,
    _C_MAX_ITER,
) = range(10)
_C_OUT_OTHER = 5


def _compiled_search(ev, z0, region, settings) -> tuple | None:
    """The search in one compiled call (``walker._hybrid.PreparedMap.search``), for a
    :class:`~walker.simulation.stride.StrideMap` with a compiled call and a region whose energy is
    compiled; None when it does not apply (the caller then searches through callbacks)."""
    section_map, parameter = ev.section_map, ev.parameter
    finder = getattr(type(section_map), "_compiled_search", None)
    if finder is None:
        return None
    if parameter is not None and parameter != section_map.parameter_value:
        section_map = section_map.with_parameter(parameter)
    search = finder(section_map)
    compiled_region = region.compiled()
    if search is None or compiled_region is None:
        return None
    out = search(z0=z0, scale=region.scale, **compiled_region, **settings)
    if out is not None and out[-1] is not None:
        t, z_new, x, jac = out[-1]
        n = z0.shape[0]
        jac = _frombuffer(jac).reshape(n, n)
        known = MapResult(Status.COMPLETED, _frombuffer(z_new), jac, t, _frombuffer(x))
        out = (*out[:-1], known)
    return out


def _ended(ev, out, region, max_iter, fallback) -> NewtonResult:
    """The :class:`NewtonResult` of the search's answer ``out`` (walker._hybrid.search)."""
    end, status, it, n_evals, refused, why, why_value, why_index, cond, z, history, known = out
    ev.n_evals = n_evals
    z = _frombuffer(z)
    history = _frombuffer(history).tolist()
    status = Status(status)
    period = ev.period
    gait = region is not None

    def reason():
        if why == _C_OUT_OTHER:
            return ev.reasons[why_index - 1]
        return region.describe(why, why_value, why_index)

    if end == _C_CONVERGED:
        return _converged(ev.tol, z, history, it, known)
    if end == _C_OUTSIDE_GUESS:
        return _outside_guess(z, reason())
    if end == _C_START_FAILS:
        return _start_fails(period, status, z)
    if end == _C_BUDGET:
        return _out_of_budget(ev, z, history, it)
    if end == _C_STALL:
        return _stalled(ev, z, history, it, gait, fallback, "stall")
    if end == _C_DIVERGED and gait:
        return _diverged(ev, z, history, it, status, reason() if why else "", refused)
    if end in (_C_DIVERGED, _C_NO_DESCENT):
        if not gait and status not in (Status.COMPLETED, Status.NONFINITE):
            msg = (
                f"Newton stalled at iterate {it} (max|F| = {history[-1]:.3g}) because the "
                f"full Newton step leads to a state that fails: {status.message} "
                "The orbit sought may not walk; try another initial guess or parameter."
            )
            return NewtonResult(status, msg, z, history, it, None)
        return _stalled(ev, z, history, it, gait, fallback, "no_descent")
    if end == _C_JACOBIAN_FAILED:
        return _jacobian_failed(status, z, history, it)
    if end == _C_SINGULAR:
        return _singular(period, cond, z, history, it)
    return _not_converged(period, ev.tol, z, history, max_iter)


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


def solve_fixed_point(
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
    coarse=False,
) -> NewtonResult:
    """Damped Newton + LM on ``P^k(z) - z`` at a fixed parameter, in a trust region.

    The input is taken as checked (:func:`walker.analysis.fixedpoint.find_fixed_point` checks it):
    ``z0`` a finite vector, ``period`` and ``max_iter`` ints, ``mode`` in
    :data:`~walker.simulation.sectionmap.JACOBIAN_MODES`.  ``max_evals`` bounds the stride-map
    evaluations (None: :func:`default_max_evals`); ``region`` is the walking region (None:
    :meth:`WalkingRegion.of` the map, which is None for a map without a walker model).
    With ``coarse`` and the exact Jacobian, strides far from the solution are integrated
    more coarsely (``COARSE_RHO``).
    """
    if region is None:
        region = WalkingRegion.of(section_map, parameter)
        if region is not None:
            region.with_guess(z0)
    if max_evals is None:
        max_evals = default_max_evals(z0.shape[0], mode)
    z0 = np.ascontiguousarray(z0, dtype=np.float64)
    ev = _Search(section_map, period, parameter, int(max_evals), tol, mode, fd_step, coarse)
    settings = ev.settings(max_iter, fallback, z0.shape[0])
    out = None
    if mode == "exact" and region is not None:
        out = _compiled_search(ev, z0, region, settings)
    if out is None:
        ev.region = region
        out = _hybrid.search(
            z0=z0,
            scale=region.scale if region is not None else np.maximum(1.0, np.abs(z0)),
            evaluate=ev.evaluate,
            jacobian=ev.jacobian,
            outside=None if region is None else ev.outside,
            **settings,
        )
    return _ended(ev, out, region, max_iter, fallback)


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
        return NewtonResult(Status.NOT_CONVERGED, msg, z, history, it, None)
    msg = (
        f"No period-{period} gait near the initial guess: {how}, after {ev.n_evals} stride-map "
        "evaluations. This is what a search sees past a fold of the gait branch, where the gait "
        "ceases to exist. " + _hint(ev.section_map, ev.parameter)
    )
    return NewtonResult(Status.NO_GAIT_NEAR_GUESS, msg, z, history, it, None)


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
    return NewtonResult(Status.DIVERGED, msg, z, history, it, None)


# --- How a search ends: the results and their messages ------------------------------------


def _converged(tol, z, history, it, known) -> NewtonResult:
    msg = (
        f"Converged: max|P^k(z) - z| = {history[-1]:.3g} <= tol = {tol:.3g} (absolute, section "
        f"units) after {it} iteration(s)."
    )
    return NewtonResult(Status.COMPLETED, msg, z, history, it, known)


def _out_of_budget(ev, z, history, it) -> NewtonResult:
    last = (
        f"max|F| = {history[-1]:.3g} at the last accepted iterate"
        if history
        else "before the first stride was evaluated"
    )
    msg = (
        f"No period-{ev.period} orbit within the budget of {ev.max_evals} stride-map "
        f"evaluations (`max_evals`): {last}, iterate {it}. "
        + _hint(ev.section_map, ev.parameter, budget=True)
    )
    return NewtonResult(Status.BUDGET_EXHAUSTED, msg, z, history, it, None)


def _outside_guess(z, why) -> NewtonResult:
    msg = (
        f"The initial guess lies outside the region where the walker can walk: {why}. "
        "It was not integrated. Start from a state near a gait: on the command line "
        "the scene's `[initial] state`, from Python `z0`."
    )
    return NewtonResult(Status.OUTSIDE_WALKING_REGION, msg, z, [], 0, None)


def _start_fails(period, status, z) -> NewtonResult:
    msg = (
        f"The starting point fails within {period} stride(s): {status.message} "
        "Start from a state that walks."
    )
    return NewtonResult(status, msg, z, [], 0, None)


def _jacobian_failed(st, z, history, it) -> NewtonResult:
    what = f"Computing the Jacobian at iterate {it} failed ({st.name}): {st.message}"
    try_ = "Try `jacobian='exact'` or a better initial guess."
    return NewtonResult(st, f"{what} {try_}", z, history, it, None)


def _singular(period, cond, z, history, it) -> NewtonResult:
    msg = (
        f"The Newton matrix DP^{period} - I is singular (condition number {cond:.3g}) "
        f"at iterate {it}; the orbit may sit at a fold or the map may have no fixed "
        "point here. Try `fallback=True`, another initial guess, or continuation."
    )
    return NewtonResult(Status.LINEAR_SOLVE_FAILED, msg, z, history, it, None)


def _not_converged(period, tol, z, history, max_iter) -> NewtonResult:
    what = f"Newton did not reach max|P^{period}(z) - z| <= {tol:.3g} in {max_iter} iterations"
    last = f"(last residual {history[-1]:.3g})"
    try_ = "Try more `max_iter`, a looser `tol`, or a better initial guess."
    return NewtonResult(Status.NOT_CONVERGED, f"{what} {last}. {try_}", z, history, max_iter, None)
