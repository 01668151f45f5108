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

With the exact Jacobian, on a :class:`~walker.simulation.stride.StrideMap` with a compiled call, the
whole search runs in one compiled call (:func:`_compiled_search`,
``walker._hybrid.PreparedMap.search``, walker/_core/newton.c) without the GIL: the same
steps, strides, statuses and messages, the constants of this module passed in.  The
Python search here (:func:`_search`) is its reference and runs for every other map (finite
differences, toy maps, wrappers, a spy on ``StrideMap.__call__``).
"""

from __future__ import annotations

import math
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
# A Newton matrix whose condition number (Frobenius, _newton_step) exceeds this is treated
# as singular.
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


def _residual(section_map, z, period, parameter, with_jacobian=False):
    """``F(z) = P^k(z) - z`` and the map result (F is None when the stride failed).

    With ``with_jacobian`` the map is evaluated with its exact Jacobian in the same call, so
    an accepted Newton trial point brings the next iteration's Jacobian with it.
    """
    if with_jacobian:
        res = section_map(z, jacobian=True, n_strides=period, parameter=parameter)
    else:
        res = map_value(section_map, z, period, parameter)
    if not res.success or not np.isfinite(res.z).all():
        return None, res
    return res.z - z, res


def _max_abs(v) -> float:
    """``max|v_i|`` of a float vector, as ``float(np.max(np.abs(v)))`` (the same number,
    without the function-wrapper overhead)."""
    return float(np.abs(v).max())


def _norm2(v) -> float:
    """The 2-norm of a real vector as ``np.linalg.norm`` computes it (``sqrt(v . v)``, the
    same number), without its general-purpose overhead."""
    return math.sqrt(float(v.dot(v)))


def _newton_step(a, f):
    """``(cond, dz)``: ``dz`` solving ``a dz = -f`` by Gaussian elimination with partial
    pivoting and the Frobenius condition number ``||a||_F ||a^-1||_F`` of the finite matrix
    ``a`` (at least its 2-norm condition number, at most ``n`` times it), in one compiled
    call (``walker._hybrid.newton_step``); ``(inf, None)`` for a singular ``a``."""
    cond, dz = _hybrid.newton_step(a, f)
    return cond, (None if dz is None else _frombuffer(dz))


def _usable_jacobian(res):
    jac = getattr(res, "jac", None)
    if jac is None:
        return None
    jac = np.asarray(jac, dtype=float)
    return jac if np.isfinite(jac).all() else None


class _OutOfBudget(Exception):
    """The search's evaluation budget is spent (internal)."""


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


class _Evaluator:
    """Counts the search's stride-map evaluations against its budget, and picks the
    tolerance of each (``COARSE_RHO``)."""

    __slots__ = ("section_map", "period", "parameter", "max_evals", "n_evals", "tol", "own", "maps")

    def __init__(self, section_map, period, parameter, max_evals, tol=0.0, coarse=False):
        self.section_map = section_map
        self.period = period
        self.parameter = parameter
        self.max_evals = max_evals
        self.n_evals = 0
        self.tol = tol
        self.own = _coarse_levels(section_map) if coarse else None
        self.maps = {}  # the coarse maps by rtol

    def _spend(self, n):
        if self.n_evals + n > self.max_evals:
            raise _OutOfBudget
        self.n_evals += n

    def _coarse_map(self, expect):
        """The map at the coarsest rtol allowed for a residual ``expect`` (None: the map's
        own tolerance is needed)."""
        if self.own is None or expect is None or not expect > 0.0:
            return None
        want = min(COARSE_RHO * expect * expect, COARSEST_RTOL)
        rtol, atol = self.own
        level = 10.0 ** math.floor(math.log10(want)) if want > rtol else 0.0
        if not level > rtol:
            return None
        coarse = self.maps.get(level)
        if coarse is None:
            coarse = self.section_map.with_tolerance(level, min(atol * level / rtol, level))
            self.maps[level] = coarse
        return coarse

    def glance(self, z):
        """``max|F(z)|`` from one stride at ``COARSEST_RTOL`` without the Jacobian (counted;
        NaN when that stride fails; None, uncounted, when no coarse map exists or when the
        budget cannot spare it besides the guess's evaluation): what the guess's first
        evaluation needs to pick its tolerance."""
        coarse = self._coarse_map(1.0)
        if coarse is None or self.n_evals + 2 > self.max_evals:
            return None
        self._spend(1)
        f, _ = _residual(coarse, z, self.period, self.parameter)
        return math.nan if f is None else _max_abs(f)

    def residual(self, z, with_jacobian=False, expect=None):
        """``F(z)`` and the map result, at the tolerance chosen for the residual ``expect``
        expected at ``z`` (None: the map's own)."""
        self._spend(1)
        coarse = self._coarse_map(expect)
        if coarse is not None:
            f, res = _residual(coarse, z, self.period, self.parameter, with_jacobian)
            if f is not None:
                r = _max_abs(f)
                if r > self.tol and coarse.rtol <= COARSE_KEEP * r * r:
                    return f, res
                self._spend(1)
                coarse = self._coarse_map(r)
                if coarse is not None and r > self.tol:
                    return _residual(coarse, z, self.period, self.parameter, with_jacobian)
            else:
                self._spend(1)  # a coarse stride that fails: the map's own says for sure
        return _residual(self.section_map, z, self.period, self.parameter, with_jacobian)

    def jacobian(self, z, mode, fd_step):
        self._spend(1 if mode == "exact" else 1 + 2 * z.shape[0])
        return map_jacobian(self.section_map, z, self.period, self.parameter, mode, fd_step)


# The search's ends as walker/_core/newton.h numbers them (WK_SEARCH_*).
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


def _compiled_settings(ev, max_iter, fallback) -> tuple:
    """The search's settings and this module's constants as walker/_core/newton.h's
    ``wk_search_settings`` reads them."""
    own = ev.own
    return (
        ev.period,
        float(ev.tol),
        max_iter,
        int(bool(fallback)),
        ev.max_evals,
        int(own is not None),
        own[0] if own is not None else 1.0,
        own[1] if own is not None else 1.0,
        ARMIJO,
        LINE_FLAT,
        COND_MAX,
        MAX_HALVINGS,
        LM_START,
        LM_GROW,
        LM_SHRINK,
        LM_MAX,
        LM_TRIES,
        TR_START,
        TR_MAX,
        STALL_WINDOW,
        STALL_RATIO,
        STALL_ALPHA,
        COARSEST_RTOL,
        COARSE_RHO,
        COARSE_KEEP,
    )


def _compiled_search(ev, z0, region, max_iter, fallback) -> NewtonResult | None:
    """:func:`_search` with the exact Jacobian in one compiled call
    (``walker._hybrid.PreparedMap.search``, walker/_core/newton.h), for a
    :class:`~walker.simulation.stride.StrideMap` with a compiled call and a region whose energy is
    compiled; None when it does not apply (the caller then runs :func:`_search`).  The
    same search: the same decisions, strides, statuses and messages."""
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
    out = search(z0, region.scale, compiled_region, _compiled_settings(ev, int(max_iter), fallback))
    if out is None:
        return None
    end, status, it, n_evals, refused, why, why_value, why_index, cond, z, history, known = out
    ev.n_evals = n_evals
    z = _frombuffer(z)
    history = _frombuffer(history).tolist()
    status = Status(status)
    period = ev.period
    if end == _C_CONVERGED:
        if known is not None:
            t, z_new, x, jac = known
            n = z.shape[0]
            jac = _frombuffer(jac).reshape(n, n)
            known = MapResult(Status.COMPLETED, _frombuffer(z_new), jac, t, _frombuffer(x))
        return _converged(ev.tol, z, history, it, known)
    if end == _C_OUTSIDE_GUESS:
        return _outside_guess(z, region.describe(why, why_value, why_index))
    if end == _C_START_FAILS:
        return _start_fails(period, status, z)
    if end == _C_BUDGET:
        return _out_of_budget(ev, z, history, it)
    if end == _C_STALL:
        return _stalled(ev, z, history, it, True, fallback, "stall")
    if end == _C_NO_DESCENT:
        return _stalled(ev, z, history, it, True, fallback, "no_descent")
    if end == _C_DIVERGED:
        why_refused = region.describe(why, why_value, why_index) if why else ""
        return _diverged(ev, z, history, it, status, why_refused, refused)
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
    ev = _Evaluator(section_map, period, parameter, int(max_evals), tol, coarse and mode == "exact")
    if mode == "exact" and region is not None:
        solved = _compiled_search(ev, z0, region, max_iter, fallback)
        if solved is not None:
            return solved
    state = {"z": z0.copy(), "history": [], "it": 0}
    try:
        return _search(ev, z0, state, region, tol, max_iter, mode, fd_step, fallback)
    except _OutOfBudget:
        return _out_of_budget(ev, state["z"], state["history"], state["it"])


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
            return _outside_guess(z, why)
    expect = ev.glance(z)
    if exact and expect is not None and math.isnan(expect):
        # the guess's stride fails at the coarsest rtol: confirmed at the map's own without
        # the Jacobian first, since a variational run costs n_z + 1 plain ones a step or far
        # more (five-link at g = 1e12: 1e5 steps of 1 ms to MAX_STEPS; plain: a fall, 244)
        f, res = ev.residual(z)
        if f is None:
            return _start_fails(period, res.status, z)
    f, res = ev.residual(z, with_jacobian=exact, expect=expect)
    jac_here = _usable_jacobian(res) if exact else None
    res_here = res
    if f is None:
        return _start_fails(period, res.status, z)
    history = state["history"]
    history.append(_max_abs(f))
    lm = LM_START
    radius = TR_START
    poor = []  # per accepted step: did it gain little (see STALL_RATIO, STALL_ALPHA)?
    for it in range(max_iter + 1):
        state["it"] = it
        if history[-1] <= tol:
            known = res_here if jac_here is not None else None
            return _converged(tol, z, history, it, known)
        if it == max_iter:
            break
        if len(poor) >= STALL_WINDOW and all(poor[-STALL_WINDOW:]):
            return _stalled(ev, z, history, it, gait, fallback, "stall")
        if jac_here is not None:
            jac_map, st = jac_here, Status.COMPLETED
        else:
            _, jac_map, st = ev.jacobian(z, mode, fd_step)
        if jac_map is None:
            return _jacobian_failed(st, z, history, it)
        a = jac_map - eye
        merit = _norm2(f)
        accepted = False
        shortened = False
        alpha = 1.0
        refused = 0  # trial points outside the walking region (not integrated)
        failed = 0  # trial strides that failed
        walked = 0  # trial strides that completed
        why_refused = ""
        # --- Newton step, cut to the trust region, with backtracking on ||F||_2 ----------
        cond, dz = _newton_step(a, f)
        full_step_status = Status.COMPLETED
        if cond < COND_MAX:
            length = _max_abs(dz / scale)
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
                # a full step should square the residual; a shortened one, less
                expect = history[-1] ** 2 if alpha == 1.0 else history[-1]
                f_try, res_try = ev.residual(z_try, exact and alpha == 1.0, expect)
                if f_try is None:
                    failed += 1
                    if alpha == 1.0:
                        full_step_status = res_try.status
                else:
                    walked += 1
                    merit_try = _norm2(f_try)
                    if merit_try <= (1 - ARMIJO * alpha) * merit:
                        accepted = True
                        shortened = alpha < 1.0
                        break
                    if merit_try <= (1 + LINE_FLAT) * merit:
                        break  # flat along the Newton direction: a local minimum of ||F||
                alpha *= 0.5
        elif not fallback:
            return _singular(period, cond, z, history, it)
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
                return NewtonResult(full_step_status, msg, z, history, it, None)
            return _stalled(ev, z, history, it, gait, fallback, "no_descent")
        step = _max_abs((z_try - z) / scale)
        radius = step if shortened else min(TR_MAX, max(radius, 2.0 * step))
        z = z_try
        state["z"] = z
        f = f_try
        jac_here = _usable_jacobian(res_try) if exact else None
        res_here = res_try
        history.append(_max_abs(f))
        poor.append(history[-1] > STALL_RATIO * history[-2] or (shortened and alpha <= STALL_ALPHA))
    return _not_converged(period, tol, z, history, max_iter)


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


# --- How a search ends: the results and messages of both searches ---------------------------


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
