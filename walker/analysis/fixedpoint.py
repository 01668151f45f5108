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

Where the parts live: the :class:`SectionMap` protocol, map evaluation, eigen-sorting and
the input checks in :mod:`walker.simulation.sectionmap`; the walking region and the stride's step
budget in :mod:`walker.simulation.region`; the Newton / Levenberg–Marquardt solve and its constants
in :mod:`walker.analysis.newton`.  This module checks the input, runs the solve and builds the
:class:`~walker.results.FixedPoint`; the names above stay importable from here.
"""

from __future__ import annotations

import numpy as np

from walker.analysis.newton import (  # noqa: F401  (re-exported: first defined here)
    ARMIJO,
    COND_MAX,
    CORRECTOR_EVALS_PER_ITER,
    FD_EXTRA_JACOBIANS,
    LINE_FLAT,
    LM_GROW,
    LM_MAX,
    LM_SHRINK,
    LM_START,
    LM_TRIES,
    MAX_EVALS,
    MAX_HALVINGS,
    POINT_MAX_EVALS,
    STALL_ALPHA,
    STALL_RATIO,
    STALL_WINDOW,
    TR_MAX,
    TR_START,
    NewtonResult,
    default_max_evals,
    solve_fixed_point,
)
from walker.results import FixedPoint
from walker.simulation.region import (  # noqa: F401  (re-exported: first defined here)
    KINETIC_FACTOR,
    KINETIC_LIMIT,
    STEPS_PER_TIME_UNIT,
    STRIDE_MIN_STEPS,
    WalkingRegion,
    stride_max_steps,
)
from walker.simulation.sectionmap import (  # noqa: F401  (JACOBIAN_MODES re-exported)
    JACOBIAN_MODES,
    SectionMap,
    eig_sorted,
    map_jacobian,
    validate_int,
    validate_jacobian_mode,
    validate_max_evals,
    validate_period,
    validate_positive,
    validate_z,
)
from walker.status import Status

__all__ = [
    "SectionMap",
    "WalkingRegion",
    "find_fixed_point",
    "floquet",
    "classify",
    "stride_max_steps",
]


def _finish(section_map, solved: NewtonResult, *, period, parameter, mode, fd_step) -> FixedPoint:
    """Build the FixedPoint: the Jacobian at the solution (reused from the last Newton
    evaluation when it carried one), multipliers, lift."""
    z = solved.z
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
        if solved.success:
            raise
        state = np.full(int(getattr(getattr(lifter, "model", None), "n_x", 1)), np.nan)

    def failed(status, message):
        return FixedPoint.failed(
            status,
            message,
            z,
            period=period,
            parameters=parameters,
            history=solved.history,
            n_iter=solved.n_iter,
            state=np.full_like(state, np.nan),
            conventions=conventions,
        )

    if not solved.success:
        return failed(solved.status, solved.message)
    if solved.known is not None:
        res, jac, st = solved.known, np.asarray(solved.known.jac, dtype=float), Status.COMPLETED
    else:
        res, jac, st = map_jacobian(section_map, z, period, parameter, mode, fd_step)
    if jac is None:
        msg = (
            f"Converged, but the Jacobian at the solution failed ({st.name}): {st.message} "
            "Try `jacobian='fd'` or a smaller `fd_step`."
        )
        return failed(st, msg)
    lam, vec = eig_sorted(jac)
    return FixedPoint.from_status(
        Status.COMPLETED,
        solved.message,
        section=z.copy(),
        state=state,
        step_time=float(res.step_time),
        multipliers=lam,
        eigenvectors=vec,
        jacobian=jac,
        residual=float(solved.history[-1]),
        n_iter=solved.n_iter,
        history=np.asarray(solved.history, dtype=float),
        period=period,
        stable=bool((np.abs(lam) < 1.0).all()),
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
    walker ``model`` and ``params``, such as :class:`walker.simulation.stride.StrideMap`) a trial
    point outside the walking region (:meth:`WalkingRegion.outside`: stance leg past the fall
    angle, an angle wound beyond pi, kinetic energy above ``KINETIC_FACTOR`` times the
    guess's kinetic plus the walker's standing potential energy) is refused without
    integrating it.

    With the exact Jacobian, a DOP853 :class:`walker.simulation.stride.StrideMap` integrates the
    strides of iterates far from the solution at a looser rtol (inexact Newton,
    :data:`walker.analysis.newton.COARSE_RHO`): one stride at ``rtol = 1e-6`` without the Jacobian
    (counted in ``max_evals``) sizes the guess's residual ``r``, and each point is
    evaluated at the coarsest power-of-ten rtol below ``0.1 r**2`` for the residual ``r``
    expected there, so the stride error stays far below the next iterate's.  The solution,
    its residual and its multipliers always come from strides at the map's own tolerance.

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
    z0 = validate_z(section_map, z0, "z0")
    period = validate_period(period)
    tol = validate_positive(tol, "tol")
    max_iter = validate_int(max_iter, "max_iter", 1)
    mode = validate_jacobian_mode(jacobian)
    fd_step = validate_positive(fd_step, "fd_step")
    max_evals = validate_max_evals(max_evals)
    solved = solve_fixed_point(
        section_map,
        z0,
        period=period,
        parameter=parameter,
        tol=tol,
        max_iter=max_iter,
        mode=mode,
        fd_step=fd_step,
        fallback=bool(fallback),
        max_evals=max_evals,
        coarse=True,
    )
    return _finish(
        section_map, solved, period=period, parameter=parameter, mode=mode, fd_step=fd_step
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
    z = validate_z(section_map, z, "z")
    period = validate_period(period)
    mode = validate_jacobian_mode(jacobian)
    fd_step = validate_positive(fd_step, "fd_step")
    n = z.shape[0]
    _, jac, _ = map_jacobian(section_map, z, period, parameter, mode, fd_step)
    if jac is None:
        nan = np.full((n, n), np.nan)
        return np.full(n, np.nan, dtype=complex), nan.astype(complex), nan
    lam, vec = eig_sorted(jac)
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
