"""Fixed points of a section (stride) map, their Floquet multipliers and stability.

Everything here is generic over the :class:`SectionMap` protocol: a walker's stride map, or a
toy map in the tests.  A period-``k`` gait is a solution of ``F(z) = P^k(z) - z = 0`` on the
Poincaré section; it is found by damped Newton with a backtracking line search, with a
Levenberg–Marquardt fallback when Newton stalls.  Expected failures (no convergence, a falling
stride, a singular Jacobian) come back as statuses on the :class:`~walker.results.FixedPoint`;
only invalid input raises.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from walker.results import FixedPoint, MapResult
from walker.status import Status

__all__ = ["SectionMap", "find_fixed_point", "floquet", "classify"]

JACOBIAN_MODES = ("exact", "fd")

# Line search: accept a step when the 2-norm of F drops by this fraction of the step length
# (Armijo condition on the merit ||F||), halving the step at most MAX_HALVINGS times.
ARMIJO = 1e-4
MAX_HALVINGS = 30
# Levenberg–Marquardt damping: start, growth on rejection, shrink on acceptance, give-up level.
LM_START = 1e-3
LM_GROW = 10.0
LM_SHRINK = 0.3
LM_MAX = 1e12
# A Newton matrix whose condition number exceeds this is treated as singular.
COND_MAX = 1e14


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
# Evaluation helpers (shared with continuation.py)
# --------------------------------------------------------------------------------------------


def _validate_z(section_map: SectionMap, z: np.ndarray, name: str) -> np.ndarray:
    z = np.asarray(z, dtype=float)
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


def _positive(value, name: str) -> float:
    value = float(value)
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
):
    """Damped Newton + LM on ``P^k(z) - z`` at a fixed parameter.

    Returns ``(status, message, z, history, n_iter, known)`` where ``known`` is the map
    result at the returned ``z`` when it was computed there with its exact Jacobian (else
    None), so the Jacobian at the solution is not computed twice.
    """
    z = z0.copy()
    n = z.shape[0]
    eye = np.eye(n)
    exact = mode == "exact"
    f, res = _residual(section_map, z, period, parameter, with_jacobian=exact)
    jac_here = _usable_jacobian(res) if exact else None
    res_here = res
    if f is None:
        msg = (
            f"The starting point fails within {period} stride(s): {res.status.message} "
            "Start from a state that walks."
        )
        return res.status, msg, z, [], 0, None
    history = [float(np.max(np.abs(f)))]
    lm = LM_START
    for it in range(max_iter + 1):
        if history[-1] <= tol:
            known = res_here if jac_here is not None else None
            return Status.COMPLETED, _converged_message(tol, it, history), z, history, it, known
        if it == max_iter:
            break
        if jac_here is not None:
            jac_map, st = jac_here, Status.COMPLETED
        else:
            _, jac_map, st = _map_jacobian(section_map, z, period, parameter, mode, fd_step)
        if jac_map is None:
            msg = (
                f"Computing the Jacobian at iterate {it} failed ({st.name}): {st.message} "
                "Try `jacobian='exact'` or a better initial guess."
            )
            return st, msg, z, history, it, None
        a = jac_map - eye
        merit = float(np.linalg.norm(f))
        accepted = False
        # --- Newton step with backtracking on ||F||_2 -------------------------------------
        cond = np.linalg.cond(a)
        full_step_status = Status.COMPLETED
        if np.isfinite(cond) and cond < COND_MAX:
            dz = np.linalg.solve(a, -f)
            alpha = 1.0
            for _ in range(MAX_HALVINGS):
                z_try = z + alpha * dz
                f_try, res_try = _residual(
                    section_map, z_try, period, parameter, with_jacobian=exact and alpha == 1.0
                )
                if alpha == 1.0 and f_try is None:
                    full_step_status = res_try.status
                if f_try is not None and np.linalg.norm(f_try) <= (1 - ARMIJO * alpha) * merit:
                    accepted = True
                    break
                alpha *= 0.5
        elif not fallback:
            msg = (
                f"The Newton matrix DP^{period} - I is singular (condition number {cond:.3g}) "
                f"at iterate {it}; the orbit may sit at a fold or the map may have no fixed "
                "point here. Try `fallback=True`, another initial guess, or continuation."
            )
            return Status.LINEAR_SOLVE_FAILED, msg, z, history, it, None
        # --- Levenberg–Marquardt fallback when Newton stalls ------------------------------
        if not accepted and fallback:
            jtj = a.T @ a
            g = a.T @ f
            scale = np.diag(np.maximum(np.diag(jtj), 1e-12))
            while lm <= LM_MAX:
                try:
                    dz = np.linalg.solve(jtj + lm * scale, -g)
                except np.linalg.LinAlgError:
                    lm *= LM_GROW
                    continue
                z_try = z + dz
                f_try, res_try = _residual(section_map, z_try, period, parameter)
                if f_try is not None and np.linalg.norm(f_try) < merit:
                    accepted = True
                    lm = max(lm * LM_SHRINK, 1e-12)
                    break
                lm *= LM_GROW
            else:
                lm = LM_START
        if not accepted and full_step_status not in (Status.COMPLETED, Status.NONFINITE):
            msg = (
                f"Newton stalled at iterate {it} (max|F| = {history[-1]:.3g}) because the "
                f"full Newton step leads to a state that fails: {full_step_status.message} "
                "The orbit sought may not walk; try another initial guess or parameter."
            )
            return full_step_status, msg, z, history, it, None
        if not accepted:
            what = "Newton and Levenberg-Marquardt" if fallback else "Newton"
            msg = (
                f"{what} could not reduce ||P^{period}(z) - z|| below {history[-1]:.3g} at "
                f"iterate {it}; there may be no period-{period} orbit near the guess. "
                "Try a better initial guess (e.g. from continuation or brute-force iteration)"
                + ("." if fallback else ", or `fallback=True`.")
            )
            return Status.NOT_CONVERGED, msg, z, history, it, None
        z = z_try
        f = f_try
        jac_here = _usable_jacobian(res_try) if exact else None
        res_here = res_try
        history.append(float(np.max(np.abs(f))))
    msg = (
        f"Newton did not reach max|P^{period}(z) - z| <= {tol:.3g} in {max_iter} iterations "
        f"(last residual {history[-1]:.3g}). Try more `max_iter`, a looser `tol`, or a better "
        "initial guess."
    )
    return Status.NOT_CONVERGED, msg, z, history, max_iter, None


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
    # lift may depend on the parameter (e.g. the slope fixes the swing angle at heel strike)
    lifter = section_map
    if parameter is not None and float(parameter) != float(section_map.parameter_value):
        lifter = section_map.with_parameter(float(parameter))
    state = np.asarray(lifter.lift(z), dtype=float)
    if status != Status.COMPLETED:
        return _nan_fixed_point(
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
    if known is not None:
        res, jac, st = known, np.asarray(known.jac, dtype=float), Status.COMPLETED
    else:
        res, jac, st = _map_jacobian(section_map, z, period, parameter, mode, fd_step)
    if jac is None:
        msg = (
            f"Converged, but the Jacobian at the solution failed ({st.name}): {st.message} "
            "Try `jacobian='fd'` or a smaller `fd_step`."
        )
        return _nan_fixed_point(
            n_z, st, msg, z, history, n_iter, period, parameters, np.full_like(state, np.nan)
        )
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
) -> FixedPoint:
    """Find a period-``period`` orbit of a section map by damped Newton.

    Solves ``F(z) = P^k(z) - z = 0`` with ``k = period``.  Each iteration takes the Newton
    step ``(DP^k - I) dz = -F`` and backtracks (halving) until the 2-norm of ``F`` drops
    (Armijo condition).  When the Newton matrix is singular or the line search fails and
    ``fallback`` is True, Levenberg–Marquardt steps ``(A^T A + mu diag(A^T A)) dz = -A^T F``
    with adaptive damping ``mu`` are tried instead.

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

    Returns
    -------
    FixedPoint
        ``status`` is ``Status.COMPLETED`` on convergence; ``Status.NOT_CONVERGED`` when the
        iteration stalls or runs out of iterations; ``Status.LINEAR_SOLVE_FAILED`` for a
        singular Newton matrix without fallback; the failing stride's status (e.g.
        ``FELL_FORWARD``) when the walker falls at the start, during a Jacobian evaluation,
        or when the iteration stalls because the full Newton step lands on a falling state
        (the orbit sought likely does not walk).
        ``history`` holds ``max|F|`` at each accepted iterate.  On success the Jacobian of
        ``P^k`` is recomputed at the solution; ``multipliers`` are its eigenvalues sorted by
        decreasing modulus, ``eigenvectors`` the matching columns, ``stable`` is True when all
        ``|multiplier| < 1``.  On failure ``section`` is the last iterate and the multipliers
        are NaN.

    Raises
    ------
    ValueError
        for a ``z0`` of the wrong shape or with non-finite entries, ``period < 1``,
        ``tol <= 0``, ``max_iter < 1``, ``fd_step <= 0`` or an unknown ``jacobian`` mode.

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
