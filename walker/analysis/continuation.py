"""Continuation of gaits in a scalar parameter, bifurcation detection, branch switching.

A branch of period-``k`` orbits of a section map ``P(z; mu)`` is the curve
``G(z, mu) = P^k(z; mu) - z = 0`` in ``(z, mu)`` space.  Two methods follow it, each a
stepper in :mod:`walker.analysis.steppers` (predictor, corrector, acceptance), run by one loop here:

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
trial point) to about 1e-10 in the parameter (:mod:`walker.analysis.bifurcations`):

* fold: the parameter component of the arclength tangent (``t_mu``) changes sign — a real
  multiplier crosses +1 with the parameter turning back.  Natural continuation watches
  ``det(DP^k - I)`` instead (it normally stops before a fold, with a status);
* period doubling: ``det(DP^k + I) = prod(lambda + 1)`` changes sign — a real multiplier
  crosses -1 (complex pairs contribute ``|lambda + 1|^2 > 0`` and never change the sign).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from walker.analysis.bifurcations import LOCATE_XTOL, bifurcations_between  # noqa: F401  (re-exported)
from walker.analysis.fixedpoint import find_fixed_point
from walker.analysis.orbit import orbit_diagram  # noqa: F401  (re-exported)
from walker.analysis.steppers import (  # noqa: F401  (MAX_CORRECTION, MIN_TANGENT_DOT re-exported)
    MAX_CORRECTION,
    MIN_TANGENT_DOT,
    STEPPERS,
    BoundedMap,
    Context,
    bordered_newton,
    evaluate_point,
)
from walker.results import Bifurcation, Branch, FixedPoint
from walker.simulation.sectionmap import (
    SectionMap,
    eig_sorted,
    map_jacobian,
    map_value,
    validate_int,
    validate_jacobian_mode,
    validate_period,
    validate_positive,
    validate_z,
)
from walker.status import Status

__all__ = ["continue_branch", "switch_to_period_two", "orbit_diagram"]

METHODS = tuple(STEPPERS)
# Step control: grow by STEP_GROW when the corrector needed at most FAST_ITER iterations.
STEP_GROW = 1.5
FAST_ITER = 3


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
    :func:`~walker.analysis.fixedpoint.find_fixed_point`).  Each later point is predicted, corrected
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
        source of ``DP^k`` (see :func:`~walker.analysis.fixedpoint.find_fixed_point`).
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
    z0 = validate_z(section_map, z0, "z0")
    period = validate_period(period)
    if method not in METHODS:
        raise ValueError(f"`method` must be one of {METHODS}, got {method!r}")
    mode = validate_jacobian_mode(jacobian)
    tol = validate_positive(tol, "tol")
    fd_step = validate_positive(fd_step, "fd_step")
    parameter_step = validate_positive(parameter_step, "parameter_step")
    max_points = validate_int(max_points, "max_points", 2)
    max_corrector_iter = validate_int(max_corrector_iter, "max_corrector_iter", 1)
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
    step = validate_positive(0.01 * span if step is None else step, "step")
    min_step = validate_positive(1e-6 * span if min_step is None else min_step, "min_step")
    max_step = validate_positive(0.1 * span if max_step is None else max_step, "max_step")
    if min_step > max_step:
        raise ValueError(f"`min_step` ({min_step}) must not exceed `max_step` ({max_step})")
    step = min(max(step, min_step), max_step)
    name = section_map.parameter_name
    ctx = Context(
        BoundedMap(section_map), period, tol, mode, fd_step, parameter_step, max_corrector_iter
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
    p0, st = evaluate_point(ctx, first.section, mu0, with_pmu=True)
    if p0 is None:
        return _make_branch(
            name, [], [], st, f"The start orbit failed to evaluate: {st.message}", period, n_z
        )
    kinds = ("fold", "period_doubling") if detect else ("fold",) if stop_at_fold else ()
    done = [
        _follow(
            STEPPERS[method](ctx, p0, direction, limits),
            direction,
            limits,
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
    stepper,
    direction: float,
    limits: tuple[float, float],
    *,
    step: float,
    min_step: float,
    max_step: float,
    max_points: int,
    kinds: tuple[str, ...],
    stop_at_fold: bool,
) -> _Leg:
    """Continue from the stepper's first point with the parameter initially moving in
    ``direction`` (+1 or -1) until the branch leaves ``limits = (lo, hi)`` (either may be
    infinite): one loop for every method, the method being the stepper's."""
    name = stepper.ctx.section_map.parameter_name
    target = limits[0] if direction < 0 else limits[1]
    points = [stepper.first]
    bifurcations: list[Bifurcation] = []
    unlocated: list[str] = []
    h = step
    last_fail = Status.NOT_CONVERGED
    status = None
    message = ""
    while len(points) < max_points:
        p = points[-1]
        attempt = stepper.step(p, h)
        q = attempt.q
        if q is None:
            last_fail = attempt.status
            h *= 0.5
            if h < min_step:
                break
            continue
        fold = None
        for kind, mu_b, z_b, lam_b, r in bifurcations_between(stepper, p, q, kinds):
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
        stepper.accept(p, q)
        points.append(q)
        if attempt.finishing is not None:
            status = Status.COMPLETED
            message = f"Reached {name} = {attempt.finishing:.10g} in {len(points)} points."
            break
        if attempt.n_iter <= FAST_ITER:
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
            message = (
                f"The corrector failed with a step below `min_step` = {min_step:.3g} at "
                f"{name} = {last:.10g}.{stepper.fail_hint}"
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
        lam = np.array([eig_sorted(p.jac)[0] for p in points])
    else:
        lam = np.empty((0, n_z), dtype=complex)
    return Branch.from_status(
        status,
        message,
        parameter_name=name,
        parameter=np.array([p.mu for p in points], dtype=float),
        sections=np.array([p.z for p in points], dtype=float).reshape(len(points), n_z),
        step_times=np.array([p.step_time for p in points], dtype=float),
        multipliers=lam,
        stable=np.all(np.abs(lam) < 1.0, axis=1) if points else np.empty(0, dtype=bool),
        bifurcations=bifurcations,
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

    started from ``(z* + amplitude v, mu*)`` (:func:`walker.analysis.steppers.bordered_newton`, the
    corrector of arclength continuation with another border row).  Fixing the displacement
    along ``v`` instead of the parameter makes Newton pick the side of ``mu*`` where the new
    orbit exists (beyond the doubling for a supercritical one, before it for a subcritical
    one); its parameter offset is ``O(amplitude^2)``.  The solution is then polished by
    :func:`~walker.analysis.fixedpoint.find_fixed_point` at that parameter (so the result carries
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
    z_star = validate_z(section_map, bifurcation.section, "bifurcation.section")
    mu_star = float(bifurcation.parameter_value)
    amplitude = validate_positive(amplitude, "amplitude")
    tol = validate_positive(tol, "tol")
    period = validate_period(period)
    mode = validate_jacobian_mode(jacobian)
    fd_step = validate_positive(fd_step, "fd_step")
    parameter_step = validate_positive(parameter_step, "parameter_step")
    max_iter = validate_int(max_iter, "max_iter", 1)
    name = section_map.parameter_name
    n = z_star.shape[0]

    def failure(status, message, z, mu):
        return FixedPoint.failed(
            status, message, z, period=2 * period, parameters={name: float(mu)}
        )

    _, jac, st = map_jacobian(section_map, z_star, period, mu_star, mode, fd_step)
    if jac is None:
        return failure(st, f"The doubling point does not walk: {st.message}", z_star, mu_star)
    lam, vec = np.linalg.eig(jac)
    i = int(np.argmin(np.abs(lam + 1.0)))
    v = np.real(vec[:, i])
    v /= np.linalg.norm(v)

    # Newton on the extended system: P^(2k)(z; mu) - z = 0 and v . (z - z*) = amplitude.
    ctx = Context(BoundedMap(section_map), 2 * period, tol, mode, fd_step, parameter_step, max_iter)
    solved = bordered_newton(
        ctx,
        np.append(z_star + amplitude * v, mu_star),
        np.append(v, 0.0),
        lambda u: float(v @ (u[:n] - z_star) - amplitude),
        max_iter=max_iter,
    )
    z, mu = solved.u[:n], float(solved.u[n])
    if solved.reason == "stride":
        st = solved.status
        return failure(st, f"A stride failed near the doubling: {st.message}", z, mu)
    if solved.reason == "singular":
        return failure(
            Status.LINEAR_SOLVE_FAILED,
            "The extended Newton system was singular. Try another `amplitude`.",
            z,
            mu,
        )
    if not solved.success:
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
    one = map_value(section_map, fp.section, period, mu)
    separation = float(np.max(np.abs(one.z - fp.section))) if one.success else float("nan")
    if not separation > amplitude / 10:
        return fp.with_status(
            Status.NOT_CONVERGED,
            f"Newton returned to the period-{period} orbit (max|P^{period}(z) - z| = "
            f"{separation:.3g}), not a period-{2 * period} orbit. Try a larger `amplitude`.",
        )
    side = "above" if mu > mu_star else "below"
    return fp.with_status(
        fp.status,
        f"Period-{2 * period} orbit at {name} = {mu:.12g} ({side} the doubling at "
        f"{mu_star:.12g}); max|P^{period}(z) - z| = {separation:.3g}. {fp.message}",
    )
