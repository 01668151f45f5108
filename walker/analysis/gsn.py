"""The gait sensitivity norm and the largest recoverable step (issue 29).

Gait sensitivity norm (Hobbelen and Wisse, "A disturbance rejection measure for limit cycle
walkers: the gait sensitivity norm", IEEE T-RO 23(6), 2007).  The disturbance ``e`` is the
drop ``h`` [m] of one step (a step down of ``e``; :mod:`walker.simulation.terrain`), the walker on
its period-one gait before it; the gait indicators of stride ``k`` (``k = 0`` the disturbed
stride) are its step time ``T_k`` [s] and step length ``S_k`` [m] (the distance between the
two contact points just after its touchdown: stance contact and the previous one).  With
``y_k = (T_k, S_k)``,

    GSN = || dy / de ||_2 = sqrt( sum_{k >= 0} (dT_k / de)^2 + (dS_k / de)^2 ),

the 2-norm of the indicators' response over all the following strides (the paper's
equation (6) with its linearisation ``x_{k+1} = A x_k + B e_k``, ``y_k = C x_k + D e_k``;
units mixed as in the paper: s/m and m/m).

How it is computed.  The disturbed stride lands off the plane's section (a step changes the
feet's relative height), so the first two strides' indicators are functions of ``e`` through
the whole state; from stride 2 on, the walker is back on the plane's section at ``z_2``.
Hence

* ``dy_0/de`` and ``dy_1/de`` (the paper's ``D`` and ``C B``): Richardson-extrapolated central
  differences (steps ``FD_STEP`` and half of it) of one- and two-stride terrain runs;
* ``dz_2/de`` (the paper's ``B`` carried over stride 1): exact, the terrain run's variational
  equations with the saltation terms of the guard's and the reset's dependence on the step
  (``terrain_jac`` of :meth:`walker.simulation.stride.StrideMap.__call__`);
* ``A``: the plane stride map's Jacobian at the gait (variational equations, exact);
* ``C = d(T, S)/dz`` of a plane stride: Richardson-extrapolated central differences of
  single strides;
* the tail ``sum_{k >= 2} |C A^(k-2) dz_2/de|^2 = dz_2' W dz_2`` with ``W`` the solution of
  the discrete Lyapunov equation ``A' W A - W + C' C = 0`` (exact for a stable gait).

Largest recoverable step (:func:`largest_step`): the largest single drop (step down) and rise
(step up) ``h`` [m] such that, from the gait, one step of drop ``+h`` (``-h``) followed by 99
plane steps ends within ``tol`` (max-norm, section units) of the gait: bisection to
``resolution`` between the largest height known to recover and the smallest known not to.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from walker.status import Status

__all__ = ["FD_STEP", "GaitSensitivity", "StepLimits", "gait_sensitivity", "largest_step"]

FD_STEP = 1e-4
"""The central differences' step (drop [m]; section coordinates, relative to max(1, |z_i|))."""

_SWING_CONTACT_ROW = {"rimless_wheel": 3, "three_link": 2, "five_link": 4}
"""The row of :meth:`walker.models.WalkerModel.points` holding the previous stance contact
just after a touchdown; other models: the last row."""


def step_length(model, x, p) -> float:
    """The distance [m] between the two contact points of the post-impact state ``x``."""
    pts = np.asarray(model.points(x, p))
    row = _SWING_CONTACT_ROW.get(model.name, pts.shape[0] - 1)
    return float(math.hypot(*(pts[row] - pts[0])))


@dataclass
class GaitSensitivity:
    """The gait sensitivity norm and its parts.

    Attributes
    ----------
    gsn : float
        the norm (module docstring) [s/m and m/m combined].
    response : ndarray, shape (n_shown, 2)
        ``(dT_k/de [s/m], dS_k/de [1])`` for strides ``k = 0 .. n_shown - 1``.
    tail : float
        the part of ``gsn**2`` from strides ``k >= n_shown`` (Lyapunov sum).
    section : ndarray
        the gait's section point.
    multipliers : ndarray
        the gait's Floquet multipliers (eigenvalues of ``A``).
    status : Status
        ``COMPLETED``; else the failure of a stride the linearisation needs (the disturbed
        stride fails for the smallest steps of both signs: the norm does not exist), ``gsn``
        NaN.
    message : str
        which stride failed, when one did; with ``one_sided``, why.
    one_sided : bool
        the small steps down fail (module docstring, "One-sided"): the finite-difference
        parts are one-sided, from steps up.
    """

    gsn: float
    response: np.ndarray
    tail: float
    section: np.ndarray
    multipliers: np.ndarray
    status: Status = Status.COMPLETED
    message: str = ""
    one_sided: bool = False

    def as_dict(self) -> dict:
        return {
            "status": self.status.name,
            "message": self.message,
            "gsn": float(self.gsn),
            "step_time_response": [float(v) for v in self.response[:, 0]],
            "step_length_response": [float(v) for v in self.response[:, 1]],
            "tail": float(self.tail),
            "section": [float(v) for v in self.section],
            "multipliers_abs": [float(abs(m)) for m in self.multipliers],
            "one_sided": bool(self.one_sided),
        }


def _richardson(f, h):
    """Richardson-extrapolated central difference of ``f`` at 0 with steps ``h``, ``h / 2``."""

    def central(step):
        return (np.asarray(f(step)) - np.asarray(f(-step))) / (2.0 * step)

    return (4.0 * central(0.5 * h) - central(h)) / 3.0


def _one_sided(f, h):
    """The derivative of ``f`` at 0 from the side of ``h`` only: forward differences
    ``(f(s) - f(0)) / s`` at ``s = h, h/2, h/4``, Richardson-extrapolated twice (error of
    order ``h**3``)."""
    f0 = np.asarray(f(0.0))

    def forward(step):
        return (np.asarray(f(step)) - f0) / step

    d1, d2, d4 = forward(h), forward(0.5 * h), forward(0.25 * h)
    first, second = 2.0 * d2 - d1, 2.0 * d4 - d2
    return (4.0 * second - first) / 3.0


class _ProbeFailed(Exception):
    """A stride the linearisation needs failed (an outcome, returned as a status)."""

    def __init__(self, status, what, drop=0.0):
        super().__init__(f"{what} failed ({status.name})")
        self.status = status
        self.drop = drop  # the disturbance [m] of the probe that failed


def _ok(r, what, drop=0.0):
    if r.status != Status.COMPLETED:
        raise _ProbeFailed(r.status, what, drop)
    return r


def _plane_indicators(P, z):
    r = _ok(P(z), "plane stride")
    return np.array([r.step_time, step_length(P.model, r.state, P._p())])


def gait_sensitivity(P, z_star, *, n_shown: int = 10) -> GaitSensitivity:
    """The gait sensitivity norm of the gait ``z_star`` of the stride map ``P`` to one step's
    drop (module docstring).

    Parameters
    ----------
    P : walker.simulation.stride.StrideMap
        a map whose model walks on terrain (:mod:`walker.simulation._terrain_run`).
    z_star : array_like, shape (n_z,)
        its period-one gait (a fixed point).
    n_shown : int
        strides whose response is listed (>= 2); the rest enter through the tail sum.
    """
    from walker.simulation._terrain_run import check_supported

    check_supported(P)
    if isinstance(n_shown, bool) or not isinstance(n_shown, numbers.Integral) or n_shown < 2:
        raise ValueError(f"`n_shown` must be an int >= 2, got {n_shown!r}")
    z = np.asarray(z_star, dtype=np.float64)
    plane = P(z, jacobian=True)
    if plane.status != Status.COMPLETED or not np.allclose(plane.z, z, rtol=1e-8, atol=1e-8):
        raise ValueError("`z_star` must be a fixed point of the stride map (P(z) = z)")
    A = plane.jac
    multipliers = np.linalg.eigvals(A)
    if np.max(np.abs(multipliers)) >= 1.0:
        raise ValueError("the gait is unstable (a multiplier on or outside the unit circle)")
    try:
        return _linearised(P, z, A, multipliers, n_shown)
    except _ProbeFailed as failed:
        return GaitSensitivity(
            math.nan,
            np.full((0, 2), math.nan),
            math.nan,
            z.copy(),
            multipliers,
            failed.status,
            str(failed),
        )


def _linearised(P, z, A, multipliers, n_shown):
    from scipy.linalg import solve_discrete_lyapunov

    slope = float(P.params.slope)
    p = P._p()

    def first_two(h):
        rows = np.array([[slope, h], [slope, 0.0]])
        r1 = _ok(P(z, terrain=rows[:1]), "the disturbed stride", h)
        r2 = _ok(P(z, terrain=rows, n_strides=2), "the stride after the disturbance", h)
        s1 = step_length(P.model, r1.state, p)
        s2 = step_length(P.model, r2.state, p)
        return [r1.step_time, s1, r2.step_time - r1.step_time, s2]

    one_sided, message = False, ""
    try:
        d01 = _richardson(first_two, FD_STEP)
    except _ProbeFailed as down:
        if not down.drop > 0.0:
            raise
        # small steps down fail (the swing foot meets the lowered plane before the end of
        # its swing): the derivative of the touchdown at the end of the swing, from steps up
        d01 = _one_sided(first_two, -FD_STEP)
        one_sided = True
        message = f"one-sided (steps up): {down} for a step down of {down.drop:.3g} m"
    rows = np.array([[slope, 0.0], [slope, 0.0]])
    dz2 = _ok(P(z, terrain=rows, n_strides=2, jacobian=True), "the terrain run").terrain_jac[:, 1]
    C = np.empty((2, z.size))
    for i in range(z.size):
        unit = np.zeros(z.size)
        unit[i] = 1.0
        C[:, i] = _richardson(
            lambda t, u=unit: _plane_indicators(P, z + t * u), FD_STEP * max(1.0, abs(z[i]))
        )
    response = np.empty((n_shown, 2))
    response[0], response[1] = d01[:2], d01[2:]
    dz = dz2.copy()
    for k in range(2, n_shown):
        response[k] = C @ dz
        dz = A @ dz
    W = solve_discrete_lyapunov(A.T, C.T @ C)
    tail = float(dz @ W @ dz)
    gsn = math.sqrt(float(np.sum(response**2)) + tail)
    return GaitSensitivity(
        gsn, response, tail, z.copy(), multipliers, message=message, one_sided=one_sided
    )


@dataclass
class StepLimits:
    """The largest recoverable single step.

    Attributes
    ----------
    step_down, step_up : float
        the largest drop and rise [m] the gait recovers from (module docstring); each within
        ``resolution`` below the smallest height found not to recover.
    down_fails, up_fails : float
        the smallest drop and rise found not to recover [m] (``step + resolution`` at most).
    resolution, tol : float
        the bisection's resolution [m] and the recovery tolerance (section units).
    strides : int
        strides of each trial run (the disturbed one included).
    """

    step_down: float
    step_up: float
    down_fails: float
    up_fails: float
    resolution: float
    tol: float
    strides: int

    def as_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


def recovers(P, z_star, h, *, strides: int = 100, tol: float = 1e-6) -> bool:
    """True when one step of drop ``h`` [m] (negative: a rise) from the gait ``z_star``
    followed by plane steps ends, after ``strides`` strides in all, within ``tol`` (max-norm)
    of the gait."""
    rows = np.zeros((strides, 2))
    rows[:, 0] = P.params.slope
    rows[0, 1] = h
    r = P(z_star, terrain=rows, n_strides=strides)
    return bool(r.status == Status.COMPLETED and np.max(np.abs(r.z - z_star)) < tol)


def _bisect(P, z, sign, resolution, strides, tol, h_max):
    good, bad = 0.0, resolution
    while recovers(P, z, sign * bad, strides=strides, tol=tol):
        good, bad = bad, 2.0 * bad
        if bad > h_max:
            return good, math.inf
    while bad - good > resolution:
        mid = 0.5 * (good + bad)
        if recovers(P, z, sign * mid, strides=strides, tol=tol):
            good = mid
        else:
            bad = mid
    return good, bad


def largest_step(
    P,
    z_star,
    *,
    strides: int = 100,
    tol: float = 1e-6,
    resolution: float = 1e-6,
    h_max: float = 10.0,
) -> StepLimits:
    """The largest step down and up the gait ``z_star`` of ``P`` recovers from (module
    docstring).  The search doubles from ``resolution`` until a height fails (at most
    ``h_max`` [m]: beyond it the limit is reported infinite), then bisects."""
    from walker.simulation._terrain_run import check_supported

    check_supported(P)
    for name, value in (("tol", tol), ("resolution", resolution), ("h_max", h_max)):
        if not (isinstance(value, numbers.Real) and math.isfinite(value) and value > 0):
            raise ValueError(f"`{name}` must be a finite number > 0, got {value!r}")
    if isinstance(strides, bool) or not isinstance(strides, numbers.Integral) or strides < 2:
        raise ValueError(f"`strides` must be an int >= 2, got {strides!r}")
    z = np.asarray(z_star, dtype=np.float64)
    if not recovers(P, z, 0.0, strides=strides, tol=tol):
        raise ValueError("`z_star` must be a stable gait of the map (it does not return)")
    down, down_bad = _bisect(P, z, 1.0, resolution, strides, tol, h_max)
    up, up_bad = _bisect(P, z, -1.0, resolution, strides, tol, h_max)
    return StepLimits(down, up, down_bad, up_bad, resolution, tol, strides)
