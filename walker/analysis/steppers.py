"""The two ways of following a branch of orbits, as steppers with one interface.

A branch of period-``k`` orbits is the curve ``G(z, mu) = P^k(z; mu) - z = 0``.
:func:`walker.analysis.continuation.continue_branch` runs one loop over a stepper
(:data:`STEPPERS`):

* :class:`NaturalStepper` steps ``mu`` and corrects ``z`` by Newton at fixed ``mu``
  (:func:`walker.analysis.newton.solve_fixed_point`); predictor: the tangent
  ``dz/dmu = -(DP^k - I)^{-1} dP^k/dmu`` at the first point, the secant afterwards.  It cannot
  pass a fold.
* :class:`ArclengthStepper` treats ``u = (z, mu)`` as the unknown, predicts along the unit
  tangent ``t`` and corrects with the bordered Newton system (:func:`bordered_newton`), so it
  goes round folds.

Each stepper has ``step(p, h)`` (predict, correct and accept or refuse one step of length
``h`` from the point ``p``), ``accept(p, q)`` (after the loop keeps ``q``), ``fold_test``
(the test function whose sign change marks a fold for this method) and ``segment(p, q)``
(a parametrisation of the branch between two points, with a converged orbit at every trial
value, for bifurcation location in :mod:`walker.analysis.bifurcations`).

:func:`bordered_newton` is also the extended-system Newton of
:func:`walker.analysis.continuation.switch_to_period_two`.  ``dP^k/dmu`` is a finite difference in
the parameter (:func:`parameter_derivative`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from walker.analysis.newton import CORRECTOR_EVALS_PER_ITER, solve_fixed_point
from walker.results import MapResult
from walker.simulation.region import WalkingRegion
from walker.simulation.sectionmap import SectionMap, map_jacobian, map_value
from walker.status import Status

__all__ = [
    "STEPPERS",
    "ArclengthStepper",
    "BorderedResult",
    "BoundedMap",
    "Context",
    "NaturalStepper",
    "Point",
    "Step",
    "bordered_newton",
    "evaluate_point",
]

# Accept a step only when the corrector moved less than MAX_CORRECTION times the step from
# the predictor, and (arclength) the tangent turned by less than acos(MIN_TANGENT_DOT); the
# guards keep the continuation from jumping between nearby branches.
MIN_TANGENT_DOT = 0.9
MAX_CORRECTION = 0.5


@dataclass
class Point:
    """A converged orbit on the branch: section point, parameter, ``DP^k`` there, the time of
    its ``k`` strides, ``dP^k/dmu`` and (arclength) the unit tangent ``(dz, dmu)``."""

    z: np.ndarray
    mu: float
    jac: np.ndarray
    step_time: float
    pmu: np.ndarray | None = None
    tangent: np.ndarray | None = None


@dataclass
class Context:
    """The settings every corrector of one continuation shares."""

    section_map: SectionMap
    period: int
    tol: float
    mode: str
    fd_step: float
    parameter_step: float
    max_corrector_iter: int


@dataclass
class Step:
    """One attempted step: the accepted point ``q`` (None when refused, ``status`` says why),
    the corrector's iterations, and the bound the point was placed on (or None)."""

    q: Point | None
    status: Status
    n_iter: int
    finishing: float | None = None


class BoundedMap:
    """A section map whose evaluation at a parameter outside its allowed range returns a
    ``PARAMETER_OUT_OF_RANGE`` status instead of raising: a continuation step that leaves
    the range is an outcome, not an error."""

    def __init__(self, inner):
        self._inner = inner

    def __getattr__(self, name):
        return getattr(self._inner, name)

    def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
        target = self._inner
        if parameter is not None and parameter != self._inner.parameter_value:
            try:
                target = self._inner.with_parameter(parameter)
            except ValueError:
                n = np.asarray(z).shape[0]
                return MapResult(
                    Status.PARAMETER_OUT_OF_RANGE,
                    np.full(n, np.nan),
                    None,
                    np.nan,
                    np.full(n, np.nan),
                )
        return target(z, jacobian=jacobian, n_strides=n_strides)

    def with_parameter(self, value):
        return BoundedMap(self._inner.with_parameter(value))


def parameter_derivative(ctx: Context, z, mu):
    """Finite difference of ``P^k`` in the parameter: central, ``(P(mu+h) - P(mu-h)) / 2h``,
    or one-sided where ``mu -/+ h`` lies outside the parameter's allowed range.
    Returns ``(dP/dmu or None, status)``."""
    h = ctx.parameter_step * max(1.0, abs(mu))
    rp = map_value(ctx.section_map, z, ctx.period, mu + h)
    rm = map_value(ctx.section_map, z, ctx.period, mu - h)
    out = Status.PARAMETER_OUT_OF_RANGE
    if rp.status == out or rm.status == out:
        r0 = map_value(ctx.section_map, z, ctx.period, mu)
        if not r0.success:
            return None, r0.status
        if rm.status == out and rp.success:
            return (rp.z - r0.z) / h, Status.COMPLETED
        if rp.status == out and rm.success:
            return (r0.z - rm.z) / h, Status.COMPLETED
    if not rp.success:
        return None, rp.status
    if not rm.success:
        return None, rm.status
    return (rp.z - rm.z) / (2.0 * h), Status.COMPLETED


def bordered_matrix(jac, pmu, row):
    """``[[DP^k - I, dP^k/dmu], [row]]``."""
    n = jac.shape[0]
    a = np.empty((n + 1, n + 1))
    a[:n, :n] = jac - np.eye(n)
    a[:n, n] = pmu
    a[n, :] = row
    return a


@dataclass
class BorderedResult:
    """How :func:`bordered_newton` ended.

    ``u``: the solution; else the iterate where a stride or the linear solve failed, or,
    after ``max_iter`` iterations, the next iterate (not evaluated).  ``reason``:
    ``"converged"``, ``"outside"`` (the iterate left the walking region), ``"stride"`` (a
    stride failed: ``status`` says how), ``"singular"`` (the bordered matrix was singular or
    gave a non-finite step) or ``"max_iter"``.  ``map_result`` and ``jac`` are the map and
    ``DP^k`` at the solution.
    """

    status: Status
    u: np.ndarray
    n_iter: int
    reason: str
    map_result: MapResult | None = None
    jac: np.ndarray | None = None

    @property
    def success(self) -> bool:
        return self.status == Status.COMPLETED


def bordered_newton(
    ctx: Context,
    u0,
    row: np.ndarray,
    constraint: Callable[[np.ndarray], float],
    *,
    max_iter: int,
    region: WalkingRegion | None = None,
) -> BorderedResult:
    """Newton on ``P^k(z; mu) - z = 0`` and ``constraint(u) = 0`` for ``u = (z, mu)``.

    ``constraint`` is linear in ``u`` with gradient ``row``: the last row of the bordered
    matrix (:func:`bordered_matrix`).  Converged when ``max|P^k(z) - z| <= ctx.tol`` and
    ``|constraint(u)| <= ctx.tol``; at most ``max_iter + 1`` evaluations of the map with its
    Jacobian, each followed (unless converged) by ``dP^k/dmu`` and a Newton step.  An iterate
    outside ``region`` (a walker's walking region) is not evaluated (``NOT_CONVERGED``).
    """
    u = np.array(u0, dtype=float)
    n = u.shape[0] - 1
    for it in range(max_iter + 1):
        z, mu = u[:n], float(u[n])
        if region is not None and region.outside(z) is not None:
            return BorderedResult(Status.NOT_CONVERGED, u, it, "outside")
        res, jac, st = map_jacobian(ctx.section_map, z, ctx.period, mu, ctx.mode, ctx.fd_step)
        if jac is None:
            return BorderedResult(st, u, it, "stride")
        g = res.z - z
        c = constraint(u)
        if np.max(np.abs(g)) <= ctx.tol and abs(c) <= ctx.tol:
            return BorderedResult(Status.COMPLETED, u, it, "converged", res, jac)
        pmu, st = parameter_derivative(ctx, z, mu)
        if pmu is None:
            return BorderedResult(st, u, it, "stride")
        try:
            du = np.linalg.solve(bordered_matrix(jac, pmu, row), -np.append(g, c))
        except np.linalg.LinAlgError:
            return BorderedResult(Status.LINEAR_SOLVE_FAILED, u, it, "singular")
        if not np.all(np.isfinite(du)):
            return BorderedResult(Status.LINEAR_SOLVE_FAILED, u, it, "singular")
        u = u + du
    return BorderedResult(Status.NOT_CONVERGED, u, max_iter, "max_iter")


def tangent(point: Point, t_prev: np.ndarray) -> np.ndarray | None:
    """Unit null vector of ``[DP - I, dP/dmu]``, oriented so that ``t . t_prev > 0``."""
    n = point.z.shape[0]
    rhs = np.zeros(n + 1)
    rhs[n] = 1.0
    try:
        t = np.linalg.solve(bordered_matrix(point.jac, point.pmu, t_prev), rhs)
    except np.linalg.LinAlgError:
        return None
    norm = np.linalg.norm(t)
    if not np.isfinite(norm) or norm == 0:
        return None
    return t / norm


def initial_tangent(point: Point, direction: float) -> np.ndarray:
    """Unit null vector of ``[DP - I, dP/dmu]`` with its parameter component along
    ``direction``."""
    n = point.z.shape[0]
    a = np.empty((n, n + 1))
    a[:, :n] = point.jac - np.eye(n)
    a[:, n] = point.pmu
    t = np.linalg.svd(a)[2][-1]
    if t[-1] * direction < 0:
        t = -t
    return t / np.linalg.norm(t)


def evaluate_point(ctx: Context, z, mu, *, with_pmu: bool):
    """The :class:`Point` at a converged orbit ``(z, mu)``, or ``(None, status)``."""
    res, jac, st = map_jacobian(ctx.section_map, z, ctx.period, mu, ctx.mode, ctx.fd_step)
    if jac is None:
        return None, st
    point = Point(z=z.copy(), mu=float(mu), jac=jac, step_time=float(res.step_time))
    if with_pmu:
        point.pmu, st = parameter_derivative(ctx, z, mu)
        if point.pmu is None:
            return None, st
    return point, Status.COMPLETED


# A corrector that ends with one of these did not converge at this step: the step halves.
_SEARCH_ENDS = (
    Status.NO_GAIT_NEAR_GUESS,
    Status.DIVERGED,
    Status.BUDGET_EXHAUSTED,
    Status.OUTSIDE_WALKING_REGION,
)


def correct_natural(ctx: Context, z_guess, mu, *, with_pmu=False):
    """Newton in ``z`` at fixed ``mu``. Returns ``(point or None, status, n_iter)``.

    Budget: ``CORRECTOR_EVALS_PER_ITER * max_corrector_iter`` map evaluations, in the
    walking region of a walker's map (:func:`~walker.analysis.fixedpoint.find_fixed_point`)."""
    solved = solve_fixed_point(
        ctx.section_map,
        np.asarray(z_guess, dtype=float),
        period=ctx.period,
        parameter=mu,
        tol=ctx.tol,
        max_iter=ctx.max_corrector_iter,
        mode=ctx.mode,
        fd_step=ctx.fd_step,
        fallback=False,
        max_evals=CORRECTOR_EVALS_PER_ITER * ctx.max_corrector_iter,
    )
    status = solved.status
    if status in _SEARCH_ENDS:
        status = Status.NOT_CONVERGED
    if status != Status.COMPLETED:
        return None, status, solved.n_iter
    point, st = evaluate_point(ctx, solved.z, mu, with_pmu=with_pmu)
    return point, st, solved.n_iter


def correct_arclength(ctx: Context, u_start, t, u_ref, s):
    """Bordered Newton for ``G(u) = 0`` and ``t . (u - u_ref) = s``.

    Returns ``(point or None, status, n_iter)``; the point carries ``pmu`` (not the tangent).
    At most ``max_corrector_iter + 1`` iterations of three map evaluations each; an iterate
    outside the walking region of a walker's map is not evaluated (``NOT_CONVERGED``: the
    step halves).
    """
    u = np.array(u_start, dtype=float)
    n = u.shape[0] - 1
    region = WalkingRegion.of(ctx.section_map, float(u[n]))
    if region is not None:
        region.with_guess(u[:n])
    solved = bordered_newton(
        ctx,
        u,
        t,
        lambda v: float(t @ (v - u_ref) - s),
        max_iter=ctx.max_corrector_iter,
        region=region,
    )
    if not solved.success:
        return None, solved.status, solved.n_iter
    z, mu = solved.u[:n], float(solved.u[n])
    pmu, st = parameter_derivative(ctx, z, mu)
    if pmu is None:
        return None, st, solved.n_iter
    step_time = float(solved.map_result.step_time)
    point = Point(z=z.copy(), mu=mu, jac=solved.jac, step_time=step_time, pmu=pmu)
    return point, Status.COMPLETED, solved.n_iter


class NaturalStepper:
    """Natural-parameter continuation from ``p0`` with ``mu`` moving in ``direction`` (+1 or
    -1) toward the end of ``limits = (lo, hi)`` it points at."""

    fail_hint = " A fold is likely here: try method='arclength'."

    def __init__(self, ctx: Context, p0: Point, direction: float, limits):
        self.ctx = ctx
        self.direction = direction
        self.target = limits[0] if direction < 0 else limits[1]
        n_z = p0.z.shape[0]
        self.first = Point(z=p0.z, mu=p0.mu, jac=p0.jac, step_time=p0.step_time, pmu=p0.pmu)
        try:
            self.dz_dmu = -np.linalg.solve(self.first.jac - np.eye(n_z), self.first.pmu)
        except np.linalg.LinAlgError:
            self.dz_dmu = np.zeros(n_z)

    def step(self, p: Point, h: float) -> Step:
        """``mu + direction h`` (the target when that passes it), ``z`` along ``dz/dmu``."""
        ctx = self.ctx
        finishing = None
        mu_new = p.mu + self.direction * h
        if self.direction * (mu_new - self.target) >= 0:
            mu_new, finishing = self.target, self.target
        z_pred = p.z + self.dz_dmu * (mu_new - p.mu)
        q, st, n_iter = correct_natural(ctx, z_pred, mu_new)
        if q is not None:
            jump = np.linalg.norm(np.append(q.z - z_pred, 0.0))
            scale = np.linalg.norm(np.append(z_pred - p.z, mu_new - p.mu))
            if not jump <= MAX_CORRECTION * scale + 100 * ctx.tol:
                q, st = None, Status.NOT_CONVERGED
        return Step(q, st, n_iter, finishing)

    def accept(self, p: Point, q: Point) -> None:
        """The secant through the last two points predicts the next."""
        self.dz_dmu = (q.z - p.z) / (q.mu - p.mu)

    @staticmethod
    def fold_test(point: Point) -> float:
        """``det(DP^k - I)``: natural continuation normally stops before a fold."""
        n = point.jac.shape[0]
        return float(np.linalg.det(point.jac - np.eye(n)))

    def segment(self, p: Point, q: Point):
        """``(s1, trial)``: the parameter offset from ``p`` to ``q``, and the orbit at offset
        ``s`` (None when it does not converge)."""
        s1 = q.mu - p.mu

        def trial(s):
            z_guess = p.z + (s / s1) * (q.z - p.z)
            r, _, _ = correct_natural(self.ctx, z_guess, p.mu + s)
            return r

        return s1, trial


class ArclengthStepper:
    """Pseudo-arclength continuation from ``p0``, the parameter initially moving in
    ``direction``; a step that crosses an end of ``limits = (lo, hi)`` is placed on it."""

    fail_hint = " Try a smaller `min_step`, `max_step` or a looser `tol`."

    def __init__(self, ctx: Context, p0: Point, direction: float, limits):
        self.ctx = ctx
        self.lo, self.hi = limits
        self.first = Point(z=p0.z, mu=p0.mu, jac=p0.jac, step_time=p0.step_time, pmu=p0.pmu)
        self.first.tangent = initial_tangent(self.first, direction)

    def step(self, p: Point, h: float) -> Step:
        """Predict ``u_p + h t``, correct on the hyperplane ``t . (u - u_p) = h``."""
        ctx = self.ctx
        u_p = np.append(p.z, p.mu)
        u_pred = u_p + h * p.tangent
        q, st, n_iter = correct_arclength(ctx, u_pred, p.tangent, u_p, h)
        if q is None:
            return Step(None, st, n_iter)
        q.tangent = tangent(q, p.tangent)
        u_q = np.append(q.z, q.mu)
        ok = (
            q.tangent is not None
            and float(q.tangent @ p.tangent) >= MIN_TANGENT_DOT
            and np.linalg.norm(u_q - u_pred) <= MAX_CORRECTION * h + 100 * ctx.tol
        )
        if not ok:
            return Step(None, Status.NOT_CONVERGED, n_iter)
        lo, hi = self.lo, self.hi
        crossed = hi if q.mu >= hi > p.mu else lo if q.mu <= lo < p.mu else None
        if crossed is None:
            return Step(q, st, n_iter)
        # Crossed a bound: place the last point exactly there.
        w = (crossed - p.mu) / (q.mu - p.mu)
        r, _, _ = correct_natural(ctx, p.z + w * (q.z - p.z), crossed, with_pmu=True)
        if r is not None:
            r.tangent = tangent(r, p.tangent)
            if r.tangent is not None:
                q = r
        return Step(q, st, n_iter, crossed)

    def accept(self, p: Point, q: Point) -> None:
        """Nothing to carry: each point holds its tangent."""

    @staticmethod
    def fold_test(point: Point) -> float:
        """The parameter component of the tangent, ``t_mu``."""
        return float(point.tangent[-1])

    def segment(self, p: Point, q: Point):
        """``(s1, trial)``: the arclength from ``p`` to ``q`` along ``p``'s tangent, and the
        orbit at arclength ``s`` (None when it does not converge)."""
        u_p = np.append(p.z, p.mu)
        u_q = np.append(q.z, q.mu)
        s1 = float(p.tangent @ (u_q - u_p))

        def trial(s):
            u_guess = u_p + (s / s1) * (u_q - u_p)
            r, _, _ = correct_arclength(self.ctx, u_guess, p.tangent, u_p, s)
            if r is not None:
                r.tangent = tangent(r, p.tangent)
                if r.tangent is None:
                    return None
            return r

        return s1, trial


STEPPERS = {"arclength": ArclengthStepper, "natural": NaturalStepper}
"""The continuation methods, by name (the order of ``continue_branch``'s error message)."""
