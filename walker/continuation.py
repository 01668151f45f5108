"""Continuation of gaits in a scalar parameter, bifurcation detection, branch switching.

A branch of period-``k`` orbits of a section map ``P(z; mu)`` is the curve
``G(z, mu) = P^k(z; mu) - z = 0`` in ``(z, mu)`` space.  Two methods follow it:

* natural-parameter continuation steps ``mu`` and corrects ``z`` by Newton at fixed ``mu``
  (predictor: the tangent ``dz/dmu = -(DP^k - I)^{-1} dP^k/dmu`` at the first point, the
  secant afterwards); it cannot pass a fold, where it stops with a status;
* pseudo-arclength continuation treats ``u = (z, mu)`` as the unknown, predicts along the unit
  tangent ``t`` of the curve and corrects with the bordered Newton system
  ``[[DP^k - I, dP^k/dmu], [t^T]] du = -[G; t.(u - u_pred)]``, so it goes round folds.

``dP^k/dmu`` is always computed by central finite differences of the map in the parameter,
with step ``parameter_step * max(1, |mu|)``; the state Jacobian ``DP^k`` comes from the map
(``jacobian="exact"``) or central differences (``"fd"``).

Along the branch two test functions are watched, and a sign change between consecutive points
is located (Brent's method on a parametrisation of the segment, with a converged orbit at every
trial point) to about 1e-10 in the parameter:

* fold: the parameter component of the arclength tangent (``t_mu``) changes sign — a real
  multiplier crosses +1 with the parameter turning back.  Natural continuation watches
  ``det(DP^k - I)`` instead (it normally stops before a fold, with a status);
* period doubling: ``det(DP^k + I) = prod(lambda + 1)`` changes sign — a real multiplier
  crosses -1 (complex pairs contribute ``|lambda + 1|^2 > 0`` and never change the sign).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from walker.fixedpoint import (
    CORRECTOR_EVALS_PER_ITER,
    SectionMap,
    WalkingRegion,
    _eig_sorted,
    _map_jacobian,
    _map_value,
    _positive,
    _solve_fixed_point,
    _validate_jacobian_mode,
    _validate_period,
    _validate_z,
    find_fixed_point,
)
from walker.results import Bifurcation, Branch, FixedPoint, MapResult, OrbitDiagram
from walker.status import Status

__all__ = ["continue_branch", "switch_to_period_two", "orbit_diagram"]

METHODS = ("arclength", "natural")
# Step control: grow by STEP_GROW when the corrector needed at most FAST_ITER iterations.
STEP_GROW = 1.5
FAST_ITER = 3
# Accept an arclength step only when the tangent turned by less than acos(MIN_TANGENT_DOT)
# and the corrector moved less than MAX_CORRECTION times the step from the predictor; the
# guards keep the continuation from jumping between nearby branches.
MIN_TANGENT_DOT = 0.9
MAX_CORRECTION = 0.5
# Bifurcation location: absolute tolerance on the segment parameter (|d mu / d s| <= 1).
LOCATE_XTOL = 1e-12


@dataclass
class _Point:
    z: np.ndarray
    mu: float
    jac: np.ndarray
    step_time: float
    pmu: np.ndarray | None = None
    tangent: np.ndarray | None = None  # unit tangent (dz, dmu) for arclength


@dataclass
class _Context:
    section_map: SectionMap
    period: int
    tol: float
    mode: str
    fd_step: float
    parameter_step: float
    max_corrector_iter: int


class _TrialFailed(Exception):
    """A trial point of bifurcation location did not converge (internal)."""


class _BoundedMap:
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
        return _BoundedMap(self._inner.with_parameter(value))


def _parameter_derivative(ctx: _Context, z, mu):
    """Finite difference of ``P^k`` in the parameter: central, ``(P(mu+h) - P(mu-h)) / 2h``,
    or one-sided where ``mu -/+ h`` lies outside the parameter's allowed range."""
    h = ctx.parameter_step * max(1.0, abs(mu))
    rp = _map_value(ctx.section_map, z, ctx.period, mu + h)
    rm = _map_value(ctx.section_map, z, ctx.period, mu - h)
    out = Status.PARAMETER_OUT_OF_RANGE
    if rp.status == out or rm.status == out:
        r0 = _map_value(ctx.section_map, z, ctx.period, mu)
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


def _bordered(jac, pmu, row):
    n = jac.shape[0]
    a = np.empty((n + 1, n + 1))
    a[:n, :n] = jac - np.eye(n)
    a[:n, n] = pmu
    a[n, :] = row
    return a


def _tangent(point: _Point, t_prev: np.ndarray) -> np.ndarray | None:
    """Unit null vector of ``[DP - I, dP/dmu]``, oriented so that ``t . t_prev > 0``."""
    n = point.z.shape[0]
    rhs = np.zeros(n + 1)
    rhs[n] = 1.0
    try:
        t = np.linalg.solve(_bordered(point.jac, point.pmu, t_prev), rhs)
    except np.linalg.LinAlgError:
        return None
    norm = np.linalg.norm(t)
    if not np.isfinite(norm) or norm == 0:
        return None
    return t / norm


def _initial_tangent(point: _Point, direction: float) -> np.ndarray:
    n = point.z.shape[0]
    a = np.empty((n, n + 1))
    a[:, :n] = point.jac - np.eye(n)
    a[:, n] = point.pmu
    t = np.linalg.svd(a)[2][-1]
    if t[-1] * direction < 0:
        t = -t
    return t / np.linalg.norm(t)


def _evaluate_point(ctx: _Context, z, mu, *, with_pmu: bool):
    res, jac, st = _map_jacobian(ctx.section_map, z, ctx.period, mu, ctx.mode, ctx.fd_step)
    if jac is None:
        return None, st
    point = _Point(z=z.copy(), mu=float(mu), jac=jac, step_time=float(res.step_time))
    if with_pmu:
        point.pmu, st = _parameter_derivative(ctx, z, mu)
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


def _correct_natural(ctx: _Context, z_guess, mu, *, with_pmu=False):
    """Newton in ``z`` at fixed ``mu``. Returns ``(point or None, status, n_iter)``.

    Budget: ``CORRECTOR_EVALS_PER_ITER * max_corrector_iter`` map evaluations, in the
    walking region of a walker's map (:func:`~walker.fixedpoint.find_fixed_point`)."""
    status, _, z, _, n_iter, _ = _solve_fixed_point(
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
    if status in _SEARCH_ENDS:
        status = Status.NOT_CONVERGED
    if status != Status.COMPLETED:
        return None, status, n_iter
    point, st = _evaluate_point(ctx, z, mu, with_pmu=with_pmu)
    return point, st, n_iter


def _correct_arclength(ctx: _Context, u_start, t, u_ref, s):
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
    for it in range(ctx.max_corrector_iter + 1):
        z, mu = u[:n], float(u[n])
        if region is not None and region.outside(z) is not None:
            return None, Status.NOT_CONVERGED, it
        res, jac, st = _map_jacobian(ctx.section_map, z, ctx.period, mu, ctx.mode, ctx.fd_step)
        if jac is None:
            return None, st, it
        g = res.z - z
        c = float(t @ (u - u_ref) - s)
        pmu, st = _parameter_derivative(ctx, z, mu)
        if pmu is None:
            return None, st, it
        if np.max(np.abs(g)) <= ctx.tol and abs(c) <= ctx.tol:
            point = _Point(z=z.copy(), mu=mu, jac=jac, step_time=float(res.step_time), pmu=pmu)
            return point, Status.COMPLETED, it
        if it == ctx.max_corrector_iter:
            break
        a = _bordered(jac, pmu, t)
        try:
            du = np.linalg.solve(a, -np.append(g, c))
        except np.linalg.LinAlgError:
            return None, Status.LINEAR_SOLVE_FAILED, it
        if not np.all(np.isfinite(du)):
            return None, Status.LINEAR_SOLVE_FAILED, it
        u = u + du
    return None, Status.NOT_CONVERGED, ctx.max_corrector_iter


def _psi_pd(point: _Point) -> float:
    n = point.jac.shape[0]
    return float(np.linalg.det(point.jac + np.eye(n)))


def _psi_fold_natural(point: _Point) -> float:
    n = point.jac.shape[0]
    return float(np.linalg.det(point.jac - np.eye(n)))


def _psi_fold_arclength(point: _Point) -> float:
    return float(point.tangent[-1])


def _locate(ctx: _Context, method: str, p: _Point, q: _Point, test):
    """Root of ``test`` on the segment p -> q, with a converged orbit at every trial point."""
    cache: dict[float, _Point] = {}
    if method == "natural":
        s1 = q.mu - p.mu

        def trial(s):
            z_guess = p.z + (s / s1) * (q.z - p.z)
            r, _, _ = _correct_natural(ctx, z_guess, p.mu + s)
            return r

    else:
        u_p = np.append(p.z, p.mu)
        u_q = np.append(q.z, q.mu)
        s1 = float(p.tangent @ (u_q - u_p))

        def trial(s):
            u_guess = u_p + (s / s1) * (u_q - u_p)
            r, _, _ = _correct_arclength(ctx, u_guess, p.tangent, u_p, s)
            if r is not None:
                r.tangent = _tangent(r, p.tangent)
                if r.tangent is None:
                    return None
            return r

    def f(s):
        if s == 0.0:
            return test(p)
        if s == s1:
            return test(q)
        r = trial(s)
        if r is None:
            raise _TrialFailed
        cache[s] = r
        return test(r)

    lo, hi = sorted((0.0, s1))
    try:
        s_star = brentq(f, lo, hi, xtol=LOCATE_XTOL, rtol=4 * np.finfo(float).eps, maxiter=200)
    except (_TrialFailed, ValueError, RuntimeError):
        return None
    if s_star in cache:
        return cache[s_star]
    if s_star == 0.0:
        return p
    if s_star == s1:
        return q
    return trial(s_star)


def _detect(ctx, method, p, q, kinds=("fold", "period_doubling")):
    """Bifurcations of the given ``kinds`` between consecutive branch points p and q, in
    order of occurrence: ``(kind, mu, z, multipliers, point)`` with ``point`` the converged
    orbit at the bifurcation, or None when it could not be located (then ``mu`` and ``z``
    are linear interpolations of the test function and the multipliers NaN)."""
    found = []
    fold_test = _psi_fold_arclength if method == "arclength" else _psi_fold_natural
    tests = {"fold": fold_test, "period_doubling": _psi_pd}
    for kind in kinds:
        test = tests[kind]
        a, b = test(p), test(q)
        if not (np.isfinite(a) and np.isfinite(b)) or a * b >= 0:
            continue
        r = _locate(ctx, method, p, q, test)
        if r is None:
            # Fall back to linear interpolation of the test function (not located).
            w = a / (a - b)
            mu = p.mu + w * (q.mu - p.mu)
            z = p.z + w * (q.z - p.z)
            found.append((kind, mu, z, np.full(z.shape[0], np.nan, dtype=complex), None))
            continue
        lam, _ = _eig_sorted(r.jac)
        found.append((kind, r.mu, r.z.copy(), lam, r))
    found.sort(key=lambda item: abs(item[1] - p.mu))
    return found


def _validate_positive_int(value, name, minimum):
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < minimum:
        raise ValueError(f"`{name}` must be an integer >= {minimum}, got {value!r}")
    return int(value)


@dataclass
class _Leg:
    """One direction of a continuation: its points (the start first) and how it ended."""

    points: list
    bifurcations: list
    status: Status
    message: str


def continue_branch(
    section_map: SectionMap,
    z0: np.ndarray,
    *,
    to: float | None = None,
    bounds: tuple[float, float] | None = None,
    stop_at_fold: bool = False,
    step: float | None = None,
    method: str = "arclength",
    min_step: float | None = None,
    max_step: float | None = None,
    max_points: int = 500,
    period: int = 1,
    tol: float = 1e-11,
    detect: bool = True,
    jacobian: str = "exact",
    fd_step: float = 1e-7,
    parameter_step: float = 1e-6,
    max_corrector_iter: int = 8,
) -> Branch:
    """Follow a branch of period-``period`` orbits from the map's parameter value: one way to
    ``to``, or both ways to the ends of ``bounds``.

    The first point is the orbit near ``z0`` at ``section_map.parameter_value`` (found with
    :func:`~walker.fixedpoint.find_fixed_point`).  Each later point is predicted, corrected
    (Newton at fixed parameter for ``"natural"``, bordered Newton with the pseudo-arclength
    constraint for ``"arclength"``) and accepted when the corrector converges to
    ``max|P^k(z) - z| <= tol``.  The step grows by 1.5 (up to ``max_step``) after a corrector
    that needed at most 3 iterations, and halves after a failure; below ``min_step`` the
    continuation stops.  ``dP^k/dmu`` is a central finite difference in the parameter.

    With ``bounds = (lo, hi)`` the branch is followed from the start toward ``lo`` and toward
    ``hi`` (each direction on its own, ``max_points`` each) and the two halves are joined into
    one branch ordered along the curve: from the end reached going down, through the start,
    to the end reached going up.  A direction ends where the branch leaves ``[lo, hi]`` at
    either end (the last point placed exactly on the bound: past a fold the branch may leave
    through the other end), at a fold when ``stop_at_fold``, after ``max_points`` points, or
    when the corrector or the walker fails.

    With ``stop_at_fold`` a direction ends at the first fold (limit point, a real multiplier
    through +1 with the parameter turning back): the located fold orbit is its last point,
    and the status is ``COMPLETED`` with a message saying the fold was reached.  Without it,
    arclength continuation goes round the fold onto the other (usually unstable) branch.
    Natural continuation cannot pass a fold: it stops before it with ``NOT_CONVERGED``
    either way.

    Parameters
    ----------
    section_map : SectionMap
    z0 : ndarray, shape (n_z,)
        guess of the first orbit, at ``section_map.parameter_value``.
    to : float, optional
        parameter value to reach going one way; the last point is placed exactly there.
        Give ``to`` or ``bounds``, not both.
    bounds : (float, float), optional
        ``(lo, hi)`` with ``lo < hi`` containing the start value: go both ways (only one
        way when the start sits on a bound).
    stop_at_fold : bool
        end each direction at its first fold (folds are detected even with
        ``detect=False``).
    step : float, optional
        initial step: in the parameter (``"natural"``) or in arclength of ``(z, mu)``
        (``"arclength"``); default ``0.01`` times the span (``|to - mu0|``, or ``hi - lo``).
    method : {"arclength", "natural"}
    min_step, max_step : float, optional
        step bounds; defaults ``1e-6`` and ``0.1`` times the span.
    max_points : int
        maximum number of branch points in each direction (including the first).
    period : int
        strides per orbit.
    tol : float
        corrector tolerance on ``max|P^k(z) - z|`` (absolute, section units).
    detect : bool
        detect and locate folds and period doublings.
    jacobian : {"exact", "fd"}
        source of ``DP^k`` (see :func:`~walker.fixedpoint.find_fixed_point`).
    fd_step : float
        relative step of the state finite differences (``jacobian="fd"``).
    parameter_step : float
        relative step of the central difference ``dP^k/dmu``.
    max_corrector_iter : int
        Newton iterations per corrector before the step is halved.

    Returns
    -------
    Branch
        ``status``: ``COMPLETED`` when ``to`` (every bound aimed at) or, with
        ``stop_at_fold``, a fold was reached; ``MAX_STEPS`` after ``max_points`` points;
        ``NOT_CONVERGED`` (or ``LINEAR_SOLVE_FAILED``) when the step fell below
        ``min_step`` — for natural continuation usually a fold (try ``"arclength"``); a fall
        status (e.g. ``FELL_FORWARD``) when the walker stops walking along the branch; the
        first orbit's status when it could not be found (then the branch is empty).  Going
        both ways, the status is the first direction's (toward ``lo``) unless that one
        completed, and the message tells how each direction ended.
        ``bifurcations`` lists located folds and period doublings in branch order.

    Raises
    ------
    ValueError
        for an invalid ``z0``, neither or both of ``to`` and ``bounds``, a non-finite ``to``
        or ``to`` equal to the start value, ``bounds`` not finite, not increasing or not
        containing the start value, an unknown ``method`` or ``jacobian``, non-positive steps
        or tolerances, ``min_step > max_step``, ``max_points < 2`` or ``period < 1``.

    Examples
    --------
    >>> import numpy as np
    >>> from walker.results import MapResult
    >>> from walker.status import Status
    >>> class Affine:  # z -> z / 2 + c, fixed point z = 2 c
    ...     n_z, section_names, parameter_name = 1, ("z",), "c"
    ...     def __init__(self, c=1.0):
    ...         self.parameter_value = c
    ...     def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
    ...         c = self.parameter_value if parameter is None else parameter
    ...         for _ in range(n_strides):
    ...             z = z / 2 + c
    ...         jac = np.array([[0.5**n_strides]]) if jacobian else None
    ...         return MapResult(Status.COMPLETED, z, jac, 1.0, z)
    ...     def lift(self, z):
    ...         return z
    ...     def with_parameter(self, value):
    ...         return Affine(value)
    >>> branch = continue_branch(Affine(1.0), np.array([2.0]), to=2.0)
    >>> branch.status.name, float(branch.parameter[-1]), round(float(branch.sections[-1, 0]), 9)
    ('COMPLETED', 2.0, 4.0)
    >>> both = continue_branch(Affine(1.0), np.array([2.0]), bounds=(0.0, 2.0))
    >>> lo, hi = float(both.parameter[0]), float(both.parameter[-1])
    >>> lo, hi, bool(np.all(np.diff(both.parameter) > 0))
    (0.0, 2.0, True)
    """
    z0 = _validate_z(section_map, z0, "z0")
    period = _validate_period(period)
    if method not in METHODS:
        raise ValueError(f"`method` must be one of {METHODS}, got {method!r}")
    mode = _validate_jacobian_mode(jacobian)
    tol = _positive(tol, "tol")
    fd_step = _positive(fd_step, "fd_step")
    parameter_step = _positive(parameter_step, "parameter_step")
    max_points = _validate_positive_int(max_points, "max_points", 2)
    max_corrector_iter = _validate_positive_int(max_corrector_iter, "max_corrector_iter", 1)
    mu0 = float(section_map.parameter_value)
    if (to is None) == (bounds is None):
        raise ValueError(
            "Give exactly one of `to` (continue one way) and `bounds` (both ways), got "
            f"to={to!r}, bounds={bounds!r}"
        )
    if to is not None:
        to = float(to)
        if not np.isfinite(to):
            raise ValueError(f"`to` must be finite, got {to}")
        span = abs(to - mu0)
        if span == 0:
            raise ValueError(f"`to` must differ from the map's parameter value {mu0}, got {to}")
        direction = 1.0 if to > mu0 else -1.0
        # One way: the branch ends where it crosses `to`, on whichever side of the start.
        legs = [(direction, (to, np.inf) if direction < 0 else (-np.inf, to))]
    else:
        lo, hi = _validate_bounds(bounds, mu0)
        span = hi - lo
        legs = [(d, (lo, hi)) for d, end in ((-1.0, lo), (1.0, hi)) if end != mu0]
    step = _positive(0.01 * span if step is None else step, "step")
    min_step = _positive(1e-6 * span if min_step is None else min_step, "min_step")
    max_step = _positive(0.1 * span if max_step is None else max_step, "max_step")
    if min_step > max_step:
        raise ValueError(f"`min_step` ({min_step}) must not exceed `max_step` ({max_step})")
    step = min(max(step, min_step), max_step)
    name = section_map.parameter_name
    ctx = _Context(
        _BoundedMap(section_map), period, tol, mode, fd_step, parameter_step, max_corrector_iter
    )

    first = find_fixed_point(
        section_map, z0, period=period, tol=tol, jacobian=mode, fd_step=fd_step
    )
    n_z = z0.shape[0]
    if not first.success:
        return _make_branch(
            name,
            [],
            [],
            first.status,
            f"No orbit at the start ({name} = {mu0}): {first.message}",
            period,
            n_z,
        )
    p0, st = _evaluate_point(ctx, first.section, mu0, with_pmu=True)
    if p0 is None:
        return _make_branch(
            name, [], [], st, f"The start orbit failed to evaluate: {st.message}", period, n_z
        )
    kinds = ("fold", "period_doubling") if detect else ("fold",) if stop_at_fold else ()
    done = [
        _follow(
            ctx,
            p0,
            direction,
            limits,
            method=method,
            step=step,
            min_step=min_step,
            max_step=max_step,
            max_points=max_points,
            kinds=kinds,
            stop_at_fold=stop_at_fold,
        )
        for direction, limits in legs
    ]
    if len(done) == 1:
        leg = done[0]
        if to is not None:
            return _make_branch(
                name, leg.points, leg.bifurcations, leg.status, leg.message, period, n_z
            )
        # Both ways, but the start sits on a bound: the one half, in the same order (from
        # the end reached going down, through the start, to the end reached going up).
        empty = _Leg([p0], [], Status.COMPLETED, "")
        done = [leg, empty] if legs[0][0] < 0 else [empty, leg]
    down, up = done
    status = next((leg.status for leg in done if leg.status != Status.COMPLETED), up.status)
    message = " ".join(
        f"Going {word}: {leg.message}"
        for word, leg in zip(("down", "up"), done, strict=True)
        if leg.message
    )
    return _make_branch(
        name,
        down.points[::-1] + up.points[1:],
        down.bifurcations[::-1] + up.bifurcations,
        status,
        message,
        period,
        n_z,
    )


def _validate_bounds(bounds, mu0: float) -> tuple[float, float]:
    try:
        lo, hi = (float(v) for v in bounds)
    except (TypeError, ValueError):
        raise ValueError(f"`bounds` must be two numbers (lo, hi), got {bounds!r}") from None
    if not (np.isfinite(lo) and np.isfinite(hi)):
        raise ValueError(f"`bounds` must be finite, got ({lo}, {hi})")
    if not lo < hi:
        raise ValueError(f"`bounds` must satisfy lo < hi, got ({lo}, {hi})")
    if not lo <= mu0 <= hi:
        raise ValueError(
            f"`bounds` ({lo}, {hi}) must contain the map's parameter value {mu0} (the start)"
        )
    return lo, hi


def _follow(
    ctx: _Context,
    p0: _Point,
    direction: float,
    limits: tuple[float, float],
    *,
    method: str,
    step: float,
    min_step: float,
    max_step: float,
    max_points: int,
    kinds: tuple[str, ...],
    stop_at_fold: bool,
) -> _Leg:
    """Continue from ``p0`` with the parameter initially moving in ``direction`` (+1 or -1)
    until the branch leaves ``limits = (lo, hi)`` (either may be infinite)."""
    name = ctx.section_map.parameter_name
    lo, hi = limits
    target = lo if direction < 0 else hi
    n_z = p0.z.shape[0]
    p0 = _Point(z=p0.z, mu=p0.mu, jac=p0.jac, step_time=p0.step_time, pmu=p0.pmu)
    if method == "arclength":
        p0.tangent = _initial_tangent(p0, direction)
        dz_dmu = None
    else:
        try:
            dz_dmu = -np.linalg.solve(p0.jac - np.eye(n_z), p0.pmu)
        except np.linalg.LinAlgError:
            dz_dmu = np.zeros(n_z)

    points = [p0]
    bifurcations: list[Bifurcation] = []
    unlocated: list[str] = []
    h = step
    last_fail = Status.NOT_CONVERGED
    status = None
    message = ""
    while len(points) < max_points:
        p = points[-1]
        finishing = None  # the bound the last point was placed on
        if method == "natural":
            mu_new = p.mu + direction * h
            if direction * (mu_new - target) >= 0:
                mu_new, finishing = target, target
            z_pred = p.z + dz_dmu * (mu_new - p.mu)
            q, st, n_iter = _correct_natural(ctx, z_pred, mu_new)
            ok = q is not None
            if ok:
                jump = np.linalg.norm(np.append(q.z - z_pred, 0.0))
                scale = np.linalg.norm(np.append(z_pred - p.z, mu_new - p.mu))
                ok = jump <= MAX_CORRECTION * scale + 100 * ctx.tol
                if not ok:
                    st = Status.NOT_CONVERGED
        else:
            u_p = np.append(p.z, p.mu)
            u_pred = u_p + h * p.tangent
            q, st, n_iter = _correct_arclength(ctx, u_pred, p.tangent, u_p, h)
            ok = q is not None
            if ok:
                q.tangent = _tangent(q, p.tangent)
                u_q = np.append(q.z, q.mu)
                ok = (
                    q.tangent is not None
                    and float(q.tangent @ p.tangent) >= MIN_TANGENT_DOT
                    and np.linalg.norm(u_q - u_pred) <= MAX_CORRECTION * h + 100 * ctx.tol
                )
                if not ok:
                    st = Status.NOT_CONVERGED
            if ok:
                crossed = hi if q.mu >= hi > p.mu else lo if q.mu <= lo < p.mu else None
                if crossed is not None:
                    # Crossed a bound: place the last point exactly there.
                    w = (crossed - p.mu) / (q.mu - p.mu)
                    r, _, _ = _correct_natural(ctx, p.z + w * (q.z - p.z), crossed, with_pmu=True)
                    if r is not None:
                        r.tangent = _tangent(r, p.tangent)
                        if r.tangent is not None:
                            q = r
                    finishing = crossed
        if not ok:
            last_fail = st
            h *= 0.5
            if h < min_step:
                break
            continue
        fold = None
        for kind, mu_b, z_b, lam_b, r in _detect(ctx, method, p, q, kinds):
            bifurcations.append(Bifurcation(kind, float(mu_b), z_b, lam_b))
            if r is None:
                unlocated.append(f"{kind} near {name} = {mu_b:.6g}")
            if kind == "fold" and stop_at_fold:
                fold = (float(mu_b), r)
                break
        if fold is not None:
            mu_f, r = fold
            if r is not None and r is not p:
                points.append(r)
            status = Status.COMPLETED
            message = (
                f"Fold reached at {name} = {mu_f:.10g} after {len(points)} points: the branch "
                "turns back there (continue through folds to follow it)."
            )
            break
        if method == "natural":
            dz_dmu = (q.z - p.z) / (q.mu - p.mu)
        points.append(q)
        if finishing is not None:
            status = Status.COMPLETED
            message = f"Reached {name} = {finishing:.10g} in {len(points)} points."
            break
        if n_iter <= FAST_ITER:
            h = min(h * STEP_GROW, max_step)
    if status is None:
        last = points[-1].mu
        if len(points) >= max_points:
            status = Status.MAX_STEPS
            message = (
                f"Stopped after `max_points` = {max_points} points at {name} = {last:.10g} "
                f"before reaching {target:.10g}. Increase `max_points` or `max_step`."
            )
        elif last_fail in (Status.NOT_CONVERGED, Status.LINEAR_SOLVE_FAILED):
            status = last_fail
            hint = (
                " A fold is likely here: try method='arclength'."
                if method == "natural"
                else " Try a smaller `min_step`, `max_step` or a looser `tol`."
            )
            message = (
                f"The corrector failed with a step below `min_step` = {min_step:.3g} at "
                f"{name} = {last:.10g}.{hint}"
            )
        else:
            status = last_fail
            message = (
                f"The orbit stopped existing as a walking gait beyond {name} = {last:.10g}: "
                f"{last_fail.message}"
            )
    if unlocated:
        message += " Not located to full accuracy (interpolated): " + "; ".join(unlocated) + "."
    return _Leg(points, bifurcations, status, message)


def _make_branch(name, points, bifurcations, status, message, period, n_z) -> Branch:
    if points:
        lam = np.array([_eig_sorted(p.jac)[0] for p in points])
    else:
        lam = np.empty((0, n_z), dtype=complex)
    return Branch(
        parameter_name=name,
        parameter=np.array([p.mu for p in points], dtype=float),
        sections=np.array([p.z for p in points], dtype=float).reshape(len(points), n_z),
        step_times=np.array([p.step_time for p in points], dtype=float),
        multipliers=lam,
        stable=np.all(np.abs(lam) < 1.0, axis=1) if points else np.empty(0, dtype=bool),
        bifurcations=bifurcations,
        status=status,
        message=message,
        success=status == Status.COMPLETED,
        period=period,
    )


def switch_to_period_two(
    section_map: SectionMap,
    bifurcation: Bifurcation,
    *,
    amplitude: float = 1e-3,
    period: int = 1,
    tol: float = 1e-11,
    max_iter: int = 30,
    jacobian: str = "exact",
    fd_step: float = 1e-7,
    parameter_step: float = 1e-6,
) -> FixedPoint:
    """Period-two orbit born at a period doubling of a period-``period`` branch.

    Let ``z*`` be the orbit at the doubling, ``mu*`` its parameter and ``v`` the real
    eigenvector of the multiplier nearest -1.  The period-``2 period`` orbit near the doubling
    is found by Newton on the extended system, unknowns ``(z, mu)``::

        P^(2k)(z; mu) - z = 0,      v . (z - z*) = amplitude,

    started from ``(z* + amplitude v, mu*)``.  Fixing the displacement along ``v`` instead of
    the parameter makes Newton pick the side of ``mu*`` where the new orbit exists (beyond the
    doubling for a supercritical one, before it for a subcritical one); its parameter offset is
    ``O(amplitude^2)``.  The solution is then polished by
    :func:`~walker.fixedpoint.find_fixed_point` at that parameter (so the result carries
    multipliers and stability), and checked to be a genuine period-two orbit:
    ``max|P^k(z) - z| > amplitude / 10``.  Continue it further with
    ``continue_branch(section_map.with_parameter(mu), fp.section, period=2 * period, ...)``.
    ``dP/dmu`` is a central finite difference in the parameter.

    Parameters
    ----------
    section_map : SectionMap
    bifurcation : Bifurcation
        a ``"period_doubling"`` from :func:`continue_branch`.
    amplitude : float
        displacement along the critical eigenvector (section units).
    period : int
        period of the branch on which the doubling was found.
    tol : float
        tolerance on ``max|P^(2k)(z) - z|``.
    max_iter : int
        Newton iterations on the extended system.
    jacobian : {"exact", "fd"}
    fd_step, parameter_step : float
        relative finite-difference steps in the state and in the parameter.

    Returns
    -------
    FixedPoint
        with ``period = 2 * period`` and ``parameters = {name: mu}`` at the parameter where it
        was found.  ``NOT_CONVERGED`` when Newton fails or lands back on the period-one orbit
        (the message says so: try another ``amplitude``); a fall status when a stride fails.

    Raises
    ------
    ValueError
        when ``bifurcation.kind`` is not ``"period_doubling"``, its section has the wrong
        shape, or ``amplitude``/``tol`` are not positive.

    Examples
    --------
    >>> import numpy as np
    >>> from walker.results import Bifurcation, MapResult
    >>> from walker.status import Status
    >>> class Logistic:
    ...     n_z, section_names, parameter_name = 1, ("x",), "r"
    ...     def __init__(self, r=3.0):
    ...         self.parameter_value = r
    ...     def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
    ...         r = self.parameter_value if parameter is None else parameter
    ...         x, d = float(z[0]), 1.0
    ...         for _ in range(n_strides):
    ...             d, x = d * r * (1 - 2 * x), r * x * (1 - x)
    ...         jac = np.array([[d]]) if jacobian else None
    ...         return MapResult(Status.COMPLETED, np.array([x]), jac, 1.0, np.array([x]))
    ...     def lift(self, z):
    ...         return z
    ...     def with_parameter(self, value):
    ...         return Logistic(value)
    >>> pd = Bifurcation("period_doubling", 3.0, np.array([2 / 3]), np.array([-1.0 + 0j]))
    >>> fp = switch_to_period_two(Logistic(), pd, amplitude=1e-2)
    >>> fp.success, fp.period, fp.parameters["r"] > 3.0
    (True, 2, True)
    """
    if getattr(bifurcation, "kind", None) != "period_doubling":
        raise ValueError(
            "`bifurcation` must be a period doubling (kind 'period_doubling'), got "
            f"{getattr(bifurcation, 'kind', bifurcation)!r}"
        )
    z_star = _validate_z(section_map, bifurcation.section, "bifurcation.section")
    mu_star = float(bifurcation.parameter_value)
    amplitude = _positive(amplitude, "amplitude")
    tol = _positive(tol, "tol")
    period = _validate_period(period)
    mode = _validate_jacobian_mode(jacobian)
    fd_step = _positive(fd_step, "fd_step")
    parameter_step = _positive(parameter_step, "parameter_step")
    max_iter = _validate_positive_int(max_iter, "max_iter", 1)
    name = section_map.parameter_name
    n = z_star.shape[0]

    def failure(status, message, z, mu):
        return _nan_result(n, status, message, z, 2 * period, {name: float(mu)})

    _, jac, st = _map_jacobian(section_map, z_star, period, mu_star, mode, fd_step)
    if jac is None:
        return failure(st, f"The doubling point does not walk: {st.message}", z_star, mu_star)
    lam, vec = np.linalg.eig(jac)
    i = int(np.argmin(np.abs(lam + 1.0)))
    v = np.real(vec[:, i])
    v /= np.linalg.norm(v)

    ctx = _Context(
        _BoundedMap(section_map), 2 * period, tol, mode, fd_step, parameter_step, max_iter
    )
    u = np.append(z_star + amplitude * v, mu_star)
    converged = False
    for _ in range(max_iter + 1):
        z, mu = u[:n], float(u[n])
        res, jac2, st = _map_jacobian(section_map, z, 2 * period, mu, mode, fd_step)
        if jac2 is None:
            return failure(st, f"A stride failed near the doubling: {st.message}", z, mu)
        g = res.z - z
        c = float(v @ (z - z_star) - amplitude)
        if np.max(np.abs(g)) <= tol and abs(c) <= tol:
            converged = True
            break
        pmu, st = _parameter_derivative(ctx, z, mu)
        if pmu is None:
            return failure(st, f"A stride failed near the doubling: {st.message}", z, mu)
        a = _bordered(jac2, pmu, np.append(v, 0.0))
        try:
            du = np.linalg.solve(a, -np.append(g, c))
        except np.linalg.LinAlgError:
            return failure(
                Status.LINEAR_SOLVE_FAILED,
                "The extended Newton system was singular. Try another `amplitude`.",
                z,
                mu,
            )
        u = u + du
    z, mu = u[:n], float(u[n])
    if not converged:
        return failure(
            Status.NOT_CONVERGED,
            f"Newton on the period-{2 * period} extended system did not converge in {max_iter} "
            "iterations. Try a smaller `amplitude` or more `max_iter`.",
            z,
            mu,
        )
    fp = find_fixed_point(
        section_map.with_parameter(mu),
        z,
        period=2 * period,
        tol=tol,
        jacobian=mode,
        fd_step=fd_step,
    )
    if not fp.success:
        return fp
    one = _map_value(section_map, fp.section, period, mu)
    separation = float(np.max(np.abs(one.z - fp.section))) if one.success else float("nan")
    if not separation > amplitude / 10:
        fp.status = Status.NOT_CONVERGED
        fp.success = False
        fp.message = (
            f"Newton returned to the period-{period} orbit (max|P^{period}(z) - z| = "
            f"{separation:.3g}), not a period-{2 * period} orbit. Try a larger `amplitude`."
        )
        return fp
    side = "above" if mu > mu_star else "below"
    fp.message = (
        f"Period-{2 * period} orbit at {name} = {mu:.12g} ({side} the doubling at "
        f"{mu_star:.12g}); max|P^{period}(z) - z| = {separation:.3g}. {fp.message}"
    )
    return fp


def _nan_result(n, status, message, z, period, parameters) -> FixedPoint:
    return FixedPoint(
        status=status,
        message=message,
        success=False,
        section=np.asarray(z, dtype=float).copy(),
        state=np.full(1, np.nan),
        step_time=float("nan"),
        multipliers=np.full(n, np.nan, dtype=complex),
        eigenvectors=np.full((n, n), np.nan, dtype=complex),
        jacobian=np.full((n, n), np.nan),
        residual=float("nan"),
        n_iter=0,
        history=np.empty(0),
        period=period,
        stable=False,
        parameters=parameters,
    )


def orbit_diagram(
    section_map: SectionMap,
    z0: np.ndarray,
    parameters: np.ndarray,
    *,
    n_transient: int = 200,
    n_keep: int = 32,
    coordinate: int = 0,
    warm_start: bool = True,
) -> OrbitDiagram:
    """Brute-force orbit (bifurcation) diagram: where iteration settles at each parameter.

    At each value ``parameters[i]`` (in the given order) the map is iterated ``n_transient``
    strides (one call with ``n_strides=n_transient``), then ``n_keep`` more strides whose
    coordinate ``coordinate`` is recorded.  A fall leaves the rest of the row NaN.

    Parameters
    ----------
    section_map : SectionMap
    z0 : ndarray, shape (n_z,)
        starting section point.
    parameters : array_like, shape (n,)
        parameter values.
    n_transient : int
        strides discarded before recording (>= 0).
    n_keep : int
        strides recorded (>= 1).
    coordinate : int
        index of the section coordinate recorded.
    warm_start : bool
        start each parameter from the last point of the previous one when that one did not
        fall (follows an attractor through the sweep); otherwise always from ``z0``.

    Returns
    -------
    OrbitDiagram
        ``values`` of shape ``(n, n_keep)``.

    Raises
    ------
    ValueError
        for an invalid ``z0``, non-finite or non-1-D ``parameters``, negative ``n_transient``,
        ``n_keep < 1`` or ``coordinate`` out of range.

    Examples
    --------
    >>> import numpy as np
    >>> from walker.results import MapResult
    >>> from walker.status import Status
    >>> class Logistic:
    ...     n_z, section_names, parameter_name, parameter_value = 1, ("x",), "r", 3.2
    ...     def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
    ...         x = float(z[0])
    ...         for _ in range(n_strides):
    ...             x = parameter * x * (1 - x)
    ...         return MapResult(Status.COMPLETED, np.array([x]), None, 1.0, np.array([x]))
    ...     def lift(self, z):
    ...         return z
    ...     def with_parameter(self, value):
    ...         return self
    >>> d = orbit_diagram(Logistic(), np.array([0.3]), [2.5, 3.2], n_keep=4)
    >>> [len(np.unique(np.round(row, 8))) for row in d.values]
    [1, 2]
    """
    z0 = _validate_z(section_map, z0, "z0")
    params = np.asarray(parameters, dtype=float)
    if params.ndim != 1 or params.size == 0:
        raise ValueError(f"`parameters` must be a non-empty 1-D array, got shape {params.shape}")
    if not np.all(np.isfinite(params)):
        raise ValueError("All `parameters` must be finite")
    n_transient = _validate_positive_int(n_transient, "n_transient", 0)
    n_keep = _validate_positive_int(n_keep, "n_keep", 1)
    n_z = z0.shape[0]
    if (
        isinstance(coordinate, bool)
        or not isinstance(coordinate, int | np.integer)
        or not (0 <= coordinate < n_z)
    ):
        raise ValueError(f"`coordinate` must be an integer in [0, {n_z}), got {coordinate!r}")
    values = np.full((params.size, n_keep), np.nan)
    z_start = z0
    for i, mu in enumerate(params):
        z = z_start
        fell = False
        if n_transient > 0:
            res = _map_value(section_map, z, n_transient, float(mu))
            fell = not res.success
            z = res.z
        if not fell:
            for k in range(n_keep):
                res = _map_value(section_map, z, 1, float(mu))
                if not res.success:
                    fell = True
                    break
                z = res.z
                values[i, k] = z[coordinate]
        z_start = z if (warm_start and not fell) else z0
    return OrbitDiagram(
        parameter_name=section_map.parameter_name,
        parameter=params,
        values=values,
        coordinate=int(coordinate),
    )
