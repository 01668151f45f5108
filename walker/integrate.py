"""Compiled, event-driven integrator for hybrid dynamical systems.

A hybrid system (a walker) is a bundle of numba-compiled functions: a vector field per phase,
guards whose zero crossings are events, and a reset (impact) map.  :func:`hybrid_solve` runs
the whole simulation -- Runge–Kutta steps, event detection and location, resets, samples,
variational equations -- inside one ``@njit(cache=True)`` function; Python only validates the
input and packs the :class:`walker.results.Solution`.

Methods
-------
``"DOP853"``
    Dormand–Prince 8(5,3) with its 7th-order dense output [1]_ [2]_, adaptive.
``"RK45"``
    Dormand–Prince 5(4) [3]_ with Shampine's 4th-order dense output [4]_, adaptive.
``"RK4"``, ``"Euler"``
    classic Runge–Kutta and explicit Euler with a fixed step ``first_step``; cubic Hermite
    interpolation between step ends serves events and samples.

Step-size control (adaptive methods): the error estimate is measured in the scaled RMS norm
with scale ``atol + rtol * max(|y|, |y_new|)`` (components of the variational matrix
included when ``jacobian=True``); a step is accepted when that norm is <= 1; the next step is
``h * min(10, max(0.2, 0.9 * err**(-1/(q+1))))`` with ``q`` the order of the error estimate
(7 for DOP853, 4 for RK45), never growing right after a rejection.  The first step of every
phase segment (at ``t0`` and after each applied event) is chosen by Hairer's rule [2]_
(Sect. II.4) unless ``first_step`` is given, which is used at ``t0`` only.

Events
------
After each accepted step the guards are evaluated at ``n_interior`` equally spaced interior
points of the dense output and at the step end.  A tangency check adds one more point: an
armed guard that is on its pre-fire side at both ends of the step, with its rate (probed
along the vector field) pointing toward firing at the start and away at the end, has an
extremum inside; it is found on the dense output by golden-section search, and when the
guard has crossed zero there that instant is sampled too, so a dip much shorter than the
step (a grazing foot) is not walked through.  In the first sub-interval where an *armed*
guard changes sign in its direction, the root is bracketed and located on the interpolant
(Illinois regula falsi with bisection safeguard) until the bracket is a few ulps of ``t``
wide; the event time is the bracket end on the fired side and the event state is the dense
output there.  **Priority**: the earliest root wins; roots within 4 ulps of each other go to
the lower guard index.

Arming: at the start of every phase segment a guard is armed only if its value lies beyond
``GUARD_TOL`` on its pre-fire side (``g > GUARD_TOL`` for direction -1, ``g < -GUARD_TOL`` for
+1, ``|g| > GUARD_TOL`` for 0).  A disarmed guard arms once it has been seen strictly beyond
``GUARD_TOL`` on the pre-fire side at a step end or interior point.  A post-impact state that
sits on a guard therefore never fires at once.  Exception: a guard that starts within
``GUARD_TOL`` of zero but strictly on its pre-fire side *and moving toward firing* (its rate
along the vector field, probed by one extra guard evaluation) is armed at once, so a state a
hair above the ground and falling into it still sees the crossing.  A guard whose crossing
was ignored (``EVENT_IGNORE``) is disarmed in the same way; the search continues in the rest
of the same step, so a scuff followed by a heel strike inside one step is handled.  In the
step that ends at ``t_max``, an armed guard that reaches ``0 < u <= GUARD_TOL`` (pre-fire
side, within the tolerance) at ``t_max`` counts as firing at ``t_max``.

The reset receives ``x_new`` pre-filled with the pre-event state and ``impulse`` zeroed.

Time: the kernel integrates each phase segment in a local time starting at 0 and keeps the
absolute time as a compensated sum of segment durations, so after 1e5 strides event times
are still resolved to rounding of the stride, not of the elapsed time.  The ``t`` passed to
the model functions is this local time since the last applied event (every walker model is
autonomous); ``Solution.t``, event and sample times are absolute.

References
----------
.. [1] J. R. Dormand, P. J. Prince, "A family of embedded Runge-Kutta formulae",
       J. Comput. Appl. Math. 6(1):19-26, 1980.
.. [2] E. Hairer, S. P. Nørsett, G. Wanner, "Solving Ordinary Differential Equations I",
       2nd ed., Springer, 1993 (Sect. II.4 step-size selection, II.10 DOP853), and Hairer's
       Fortran code dop853.f.
.. [3] Dormand, Prince (1980), as [1].
.. [4] L. F. Shampine, "Some practical Runge-Kutta formulas", Math. Comp. 46:135-150, 1986.
.. [5] M. A. Aizerman, F. R. Gantmacher, "Determination of stability by linear approximation
       of a periodic solution of a system of differential equations with discontinuous
       right-hand sides", Q. J. Mech. Appl. Math. 11(4):385-398, 1958 (saltation matrix).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit, types
from numba.core import cgutils
from numba.core.dispatcher import Dispatcher
from numba.core.types import FunctionType
from numba.experimental.function_type import _get_jit_address, _get_wrapper_address
from numba.extending import intrinsic

from walker import _tableaux as tab
from walker.results import EventLog, Solution, Trajectory
from walker.status import (
    EVENT_IGNORE,
    EVENT_STRIDE,
    EVENT_TERMINAL,
    METHOD_DOP853,
    METHOD_DP5,
    METHOD_EULER,
    METHOD_RK4,
    OUTPUT_EVENTS,
    OUTPUT_FULL,
    OUTPUT_MAP,
    OUTPUT_SAMPLES,
    Status,
)

__all__ = [
    "GUARD_TOL",
    "HybridSystem",
    "METHODS",
    "OUTPUTS",
    "check_solver_settings",
    "hybrid_solve",
]

GUARD_TOL = 1e-10
"""Absolute guard tolerance used for arming (see the module docstring)."""

METHODS = {"DOP853": METHOD_DOP853, "RK45": METHOD_DP5, "RK4": METHOD_RK4, "Euler": METHOD_EULER}
OUTPUTS = {
    "map": OUTPUT_MAP,
    "events": OUTPUT_EVENTS,
    "samples": OUTPUT_SAMPLES,
    "full": OUTPUT_FULL,
}

# Step-size controller constants (Hairer, Nørsett, Wanner I, Sect. II.4).
SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
# Relative step of the Richardson-extrapolated central differences at events: about
# eps**(1/5), optimal for a 4th-order difference quotient.
FD_REL_STEP = 1e-3

# Internal codes (status values < 0 mean "still running").
_RUNNING = -1
_COMPLETED = int(Status.COMPLETED)
_NO_EVENT = int(Status.NO_EVENT)
_MAX_STEPS = int(Status.MAX_STEPS)
_NONFINITE = int(Status.NONFINITE)
_STEP_UNDERFLOW = int(Status.STEP_UNDERFLOW)
_DENSE_HERMITE = 0
_DENSE_RK45 = 1
_DENSE_DOP853 = 2

# Global arrays are frozen into the compiled code as constants.
_DOP853_A = tab.DOP853_A
_DOP853_B = tab.DOP853_B
_DOP853_C = tab.DOP853_C
_DOP853_E3 = tab.DOP853_E3
_DOP853_E5 = tab.DOP853_E5
_DOP853_D = tab.DOP853_D
_RK45_A = tab.RK45_A
_RK45_B = tab.RK45_B
_RK45_C = tab.RK45_C
_RK45_E = tab.RK45_E
_RK45_P = tab.RK45_P
_RK4_A = tab.RK4_A
_RK4_B = tab.RK4_B
_RK4_C = tab.RK4_C
_EULER_A = tab.EULER_A
_EULER_B = tab.EULER_B
_EULER_C = tab.EULER_C


# Signatures of the model functions as the kernel calls them.  The kernel receives each
# function as two integer addresses (its numba-native entry point and its C wrapper) and
# rebuilds a first-class function value (numba FunctionType) from them, so the kernel is
# compiled and cached on disk ONCE for all systems, its calls into the model are direct
# native calls, and passing the functions costs nothing per call.  (Passing numba
# dispatchers as arguments would make every system a new kernel specialisation that numba
# cannot reload from its cache in another process -- dispatcher types are keyed by a
# per-process identity -- i.e. ~15 s of compilation per system per process; passing cfuncs
# costs ~30 us of typing/unboxing per call.)
_A1 = types.Array(types.float64, 1, "A")
_A2 = types.Array(types.float64, 2, "A")
RHS_SIG = types.void(types.int64, types.float64, _A1, _A1, _A1)
GUARDS_SIG = types.void(types.int64, types.float64, _A1, _A1, _A1)
RESET_SIG = types.UniTuple(types.int64, 3)(
    types.int64, types.int64, types.float64, _A1, _A1, _A1, _A1
)
JAC_SIG = types.void(types.int64, types.float64, _A1, _A1, _A2)


def _fn_from_addresses(sig):
    """An intrinsic turning (c_addr, jit_addr) into a FunctionType(sig) value."""
    fnty = FunctionType(sig)

    @intrinsic
    def make(typingctx, c_addr, jit_addr):
        def codegen(context, builder, signature, args):
            sfunc = cgutils.create_struct_proxy(fnty)(context, builder)
            llvoidptr = context.get_value_type(types.voidptr)
            sfunc.c_addr = builder.inttoptr(args[0], llvoidptr)
            sfunc.py_addr = cgutils.get_null_value(llvoidptr)
            sfunc.jit_addr = builder.inttoptr(args[1], llvoidptr)
            return sfunc._getvalue()

        return fnty(types.int64, types.int64), codegen

    return make


_rhs_fn = _fn_from_addresses(RHS_SIG)
_guards_fn = _fn_from_addresses(GUARDS_SIG)
_reset_fn = _fn_from_addresses(RESET_SIG)
_jac_fn = _fn_from_addresses(JAC_SIG)


@njit(cache=True, error_model="numpy")
def _no_jac(phase, t, x, p, J):  # pragma: no cover - compiled placeholder
    """Placeholder Jacobian for systems without one (never called)."""
    J[:, :] = np.nan


def _addresses(fn, sig, name):
    if not isinstance(fn, Dispatcher):
        raise TypeError(f"`{name}` must be a numba @njit function, got {type(fn).__name__}")
    fn.compile(sig)
    return _get_wrapper_address(fn, sig), _get_jit_address(fn, sig)


def _compiled(system):
    """The (c_addr, jit_addr) pairs of the system's functions, computed on first use and
    kept on the instance (which keeps the functions alive)."""
    c = system.__dict__.get("_addrs")
    if c is None:
        c = (
            *_addresses(system.rhs, RHS_SIG, "rhs"),
            *_addresses(system.guards, GUARDS_SIG, "guards"),
            *_addresses(system.reset, RESET_SIG, "reset"),
            *(
                _addresses(system.jac, JAC_SIG, "jac")
                if system.jac is not None
                else _addresses(_no_jac, JAC_SIG, "jac")
            ),
        )
        object.__setattr__(system, "_addrs", c)
    return c


@dataclass(frozen=True)
class HybridSystem:
    """A hybrid dynamical system given by compiled functions.

    Contract (every function is a module-level ``@njit(cache=True)`` function; ``phase``,
    ``k``, ``next_phase``, ``action``, ``status`` are int, ``t`` float, arrays float64):

    1. ``rhs(phase, t, x, p, dx) -> None`` fills ``dx``, shape (n_x,), with dx/dt in ``phase``.
    2. ``guards(phase, t, x, p, g) -> None`` fills ``g``, shape (n_guards,).  A guard not used
       in a phase returns the constant 1.0 there.
    3. ``reset(phase, k, t, x, p, x_new, impulse) -> (action, next_phase, status)`` is called
       with the state ``x`` where guard ``k`` fired.  ``x_new`` arrives holding a copy of
       ``x`` and ``impulse``, shape (n_impulse,), zeros.  ``action`` is one of
       :data:`walker.status.EVENT_IGNORE` (not an event: keep integrating, state unchanged),
       ``EVENT_CONTINUE`` (apply ``x_new``, go to ``next_phase``), ``EVENT_STRIDE`` (the same
       and count one stride) or ``EVENT_TERMINAL`` (stop; ``status`` is a
       :class:`walker.status.Status` value saying why).
    4. ``jac(phase, t, x, p, J) -> None`` (optional) fills ``J``, shape (n_x, n_x), with
       df/dx; needed for ``jacobian=True``.
    5. ``directions[phase, k]`` is -1 if guard ``k`` fires when it decreases through zero, +1
       when it increases, 0 either way.

    Attributes
    ----------
    name : str
    n_x : int
        state size, the same in every phase.
    n_phases, n_guards, n_impulse : int
        number of phases, guards per phase (>= 0), length of the impulse vector (>= 1).
    rhs, guards, reset, jac : numba dispatchers (``jac`` may be None)
    directions : ndarray of int64, shape (n_phases, n_guards)
    phase_names : tuple of str, length n_phases
    guard_names : tuple of str, length n_guards
    n_params : int or None
        length of the parameter vector the functions index; when given, ``hybrid_solve``
        rejects a ``p`` of another length (compiled code does not check bounds).
    """

    name: str
    n_x: int
    n_phases: int
    n_guards: int
    n_impulse: int
    rhs: object
    guards: object
    reset: object
    jac: object | None
    directions: np.ndarray
    phase_names: tuple[str, ...]
    guard_names: tuple[str, ...]
    n_params: int | None = None

    def __post_init__(self):
        for name, low in (("n_x", 1), ("n_phases", 1), ("n_guards", 0), ("n_impulse", 1)):
            value = getattr(self, name)
            if not isinstance(value, int | np.integer) or isinstance(value, bool):
                raise TypeError(f"`{name}` must be an int, got {type(value).__name__}")
            if value < low:
                raise ValueError(f"`{name}` must be >= {low}, got {value}")
        for name in ("rhs", "guards", "reset"):
            if not callable(getattr(self, name)):
                raise TypeError(f"`{name}` must be a numba-compiled function")
        if self.jac is not None and not callable(self.jac):
            raise TypeError("`jac` must be a numba-compiled function or None")
        d = np.asarray(self.directions)
        if d.shape != (self.n_phases, self.n_guards):
            raise ValueError(
                f"`directions` must have shape (n_phases, n_guards) = "
                f"{(self.n_phases, self.n_guards)}, got {d.shape}"
            )
        if d.size and not np.all(np.isin(d, (-1, 0, 1))):
            raise ValueError("`directions` values must be -1, 0 or +1")
        d = np.ascontiguousarray(d, dtype=np.int64)
        d.flags.writeable = False
        object.__setattr__(self, "directions", d)
        if len(self.phase_names) != self.n_phases:
            raise ValueError(
                f"`phase_names` must have n_phases = {self.n_phases} entries, "
                f"got {len(self.phase_names)}"
            )
        if len(self.guard_names) != self.n_guards:
            raise ValueError(
                f"`guard_names` must have n_guards = {self.n_guards} entries, "
                f"got {len(self.guard_names)}"
            )
        object.__setattr__(self, "phase_names", tuple(self.phase_names))
        object.__setattr__(self, "guard_names", tuple(self.guard_names))


# =============================================================================================
# Compiled building blocks
# =============================================================================================


@njit(cache=True, error_model="numpy")
def _fun(rhs, jac, want_jac, phase, t, z, p, n_x, dz, J):
    """Augmented vector field: dx = f(x) and, with ``want_jac``, dPhi = J(x) Phi.

    ``Phi`` is stored row-major in ``z[n_x:]``: ``Phi[i, j] = z[n_x + i * n_x + j]``.
    """
    rhs(phase, t, z[:n_x], p, dz[:n_x])
    if want_jac:
        jac(phase, t, z[:n_x], p, J)
        for i in range(n_x):
            for j in range(n_x):
                s = 0.0
                for k in range(n_x):
                    s += J[i, k] * z[n_x + k * n_x + j]
                dz[n_x + i * n_x + j] = s


@njit(cache=True, error_model="numpy")
def _all_finite(v):
    for i in range(v.shape[0]):
        if not math.isfinite(v[i]):
            return False
    return True


@njit(cache=True, error_model="numpy")
def _rk_stages(rhs, jac, want_jac, J, phase, t, y, h, p, n_x, A, C, B, n_stages, K, y_new, tmp):
    """Stages 1..n_stages-1 (stage 0 = K[0] given), then ``y_new``, then the FSAL stage
    ``K[n_stages] = f(t + h, y_new)``.  Returns the number of rhs evaluations."""
    n = y.shape[0]
    for s in range(1, n_stages):
        for i in range(n):
            acc = 0.0
            for j in range(s):
                acc += A[s, j] * K[j, i]
            tmp[i] = y[i] + h * acc
        _fun(rhs, jac, want_jac, phase, t + C[s] * h, tmp, p, n_x, K[s], J)
    for i in range(n):
        acc = 0.0
        for s in range(n_stages):
            acc += B[s] * K[s, i]
        y_new[i] = y[i] + h * acc
    _fun(rhs, jac, want_jac, phase, t + h, y_new, p, n_x, K[n_stages], J)
    return n_stages


@njit(cache=True, error_model="numpy")
def _error_norm(method, K, h, scale):
    """Scaled RMS error estimate of the embedded pair (0 for fixed-step methods)."""
    n = scale.shape[0]
    if method == METHOD_DOP853:
        e5 = 0.0
        e3 = 0.0
        for i in range(n):
            a5 = 0.0
            a3 = 0.0
            for s in range(13):
                a5 += _DOP853_E5[s] * K[s, i]
                a3 += _DOP853_E3[s] * K[s, i]
            e5 += (a5 / scale[i]) ** 2
            e3 += (a3 / scale[i]) ** 2
        if e5 == 0.0 and e3 == 0.0:
            return 0.0
        # dop853's combination of the 5th- and 3rd-order estimates ([2], dop853.f).
        return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)
    if method == METHOD_DP5:
        e = 0.0
        for i in range(n):
            a = 0.0
            for s in range(7):
                a += _RK45_E[s] * K[s, i]
            e += (h * a / scale[i]) ** 2
        return math.sqrt(e / n)
    return 0.0


@njit(cache=True, error_model="numpy")
def _rms_scaled(v, scale):
    acc = 0.0
    for i in range(v.shape[0]):
        acc += (v[i] / scale[i]) ** 2
    return math.sqrt(acc / v.shape[0])


@njit(cache=True, error_model="numpy")
def _initial_step(
    rhs, jac, want_jac, J, phase, t, y, f0, p, n_x, order, rtol, atol, max_step, span, tmp, f1
):
    """Hairer's starting step size ([2], Sect. II.4).  Uses one rhs evaluation."""
    n = y.shape[0]
    scale = np.empty(n)
    for i in range(n):
        scale[i] = atol + rtol * abs(y[i])
    d0 = _rms_scaled(y, scale)
    d1 = _rms_scaled(f0, scale)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, span)
    for i in range(n):
        tmp[i] = y[i] + h0 * f0[i]
    _fun(rhs, jac, want_jac, phase, t + h0, tmp, p, n_x, f1, J)
    for i in range(n):
        tmp[i] = f1[i] - f0[i]
    d2 = _rms_scaled(tmp, scale) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (order + 1))
    return min(100.0 * h0, h1, max_step, span)


@njit(cache=True, error_model="numpy")
def _dense_prepare(kind, rhs, jac, want_jac, J, phase, t, y_old, y_new, h, p, n_x, K, Q, tmp):
    """Fill the dense-output coefficients ``Q`` of the step (t, y_old) -> (t + h, y_new).

    ``K[0]`` is f at the step start and ``K[n_stages]`` f at the step end.  Returns the
    number of extra rhs evaluations (3 for DOP853, else 0).
    """
    n = y_old.shape[0]
    if kind == _DENSE_DOP853:
        for s in range(13, 16):
            for i in range(n):
                acc = 0.0
                for j in range(s):
                    acc += _DOP853_A[s, j] * K[j, i]
                tmp[i] = y_old[i] + h * acc
            _fun(rhs, jac, want_jac, phase, t + _DOP853_C[s] * h, tmp, p, n_x, K[s], J)
        for i in range(n):
            dy = y_new[i] - y_old[i]
            Q[0, i] = dy
            Q[1, i] = h * K[0, i] - dy
            Q[2, i] = 2.0 * dy - h * (K[12, i] + K[0, i])
            for r in range(4):
                acc = 0.0
                for s in range(16):
                    acc += _DOP853_D[r, s] * K[s, i]
                Q[3 + r, i] = h * acc
        return 3
    if kind == _DENSE_RK45:
        for i in range(n):
            for r in range(4):
                acc = 0.0
                for s in range(7):
                    acc += _RK45_P[s, r] * K[s, i]
                Q[r, i] = h * acc
        return 0
    # Hermite: K[0] = f at start, K[1] = f at end (see the caller).
    for i in range(n):
        Q[0, i] = y_new[i] - y_old[i]
        Q[1, i] = h * K[0, i]
        Q[2, i] = h * K[1, i]
    return 0


@njit(cache=True, error_model="numpy")
def _dense_eval(kind, Q, y_old, theta, m, out):
    """Dense output at ``t_old + theta * h``, first ``m`` components into ``out``."""
    if kind == _DENSE_DOP853:
        s = theta
        s1 = 1.0 - theta
        for i in range(m):
            v = Q[5, i] + s * Q[6, i]
            v = Q[4, i] + s1 * v
            v = Q[3, i] + s * v
            v = Q[2, i] + s1 * v
            v = Q[1, i] + s * v
            v = Q[0, i] + s1 * v
            out[i] = y_old[i] + s * v
    elif kind == _DENSE_RK45:
        for i in range(m):
            v = Q[3, i]
            v = Q[2, i] + theta * v
            v = Q[1, i] + theta * v
            v = Q[0, i] + theta * v
            out[i] = y_old[i] + theta * v
    else:
        # cubic Hermite: y0 + th*D + th(th-1)[(1-2th)D + (th-1) h f0 + th h f1]
        for i in range(m):
            d = Q[0, i]
            out[i] = (
                y_old[i]
                + theta * d
                + theta
                * (theta - 1.0)
                * ((1.0 - 2.0 * theta) * d + (theta - 1.0) * Q[1, i] + theta * Q[2, i])
            )


@njit(cache=True, error_model="numpy")
def _pre_side(direction, g):
    """+1 if ``g`` lies beyond GUARD_TOL on the pre-fire side of ``direction``, else 0."""
    if direction < 0:
        return g > GUARD_TOL
    if direction > 0:
        return g < -GUARD_TOL
    return abs(g) > GUARD_TOL


@njit(cache=True, error_model="numpy")
def _crosses(direction, ga, gb):
    if direction <= 0 and ga > 0.0 and gb <= 0.0:
        return True
    if direction >= 0 and ga < 0.0 and gb >= 0.0:
        return True
    return False


@njit(cache=True, error_model="numpy")
def _guard_at(guards, kind, Q, y_old, t_old, h, phase, tau, p, n_x, xbuf, gbuf, i):
    _dense_eval(kind, Q, y_old, (tau - t_old) / h, n_x, xbuf)
    guards(phase, tau, xbuf, p, gbuf)
    return gbuf[i]


@njit(cache=True, error_model="numpy")
def _locate(guards, kind, Q, y_old, t_old, h, phase, p, n_x, xbuf, gbuf, i, a, b, ga, gb):
    """Root of guard ``i`` in [a, b] on the dense output; returns the fired-side end."""
    sgn = 1.0 if ga > 0.0 else -1.0
    ua = sgn * ga  # > 0 (pre-fire side)
    ub = sgn * gb  # <= 0 (fired side)
    if ub == 0.0:
        return b
    side = 0
    width_old = b - a
    slow = 0
    for _ in range(200):
        width = b - a
        if width <= 4.0 * np.spacing(max(abs(a), abs(b))):
            break
        if slow >= 2:
            c = 0.5 * (a + b)
            slow = 0
        else:
            c = b - ub * (b - a) / (ub - ua)
        if not (a < c < b):
            c = 0.5 * (a + b)
        uc = sgn * _guard_at(guards, kind, Q, y_old, t_old, h, phase, c, p, n_x, xbuf, gbuf, i)
        if uc <= 0.0:
            b = c
            ub = uc
            if uc == 0.0:
                break
            if side == -1:
                ua *= 0.5  # Illinois modification
            side = -1
        else:
            a = c
            ua = uc
            if side == 1:
                ub *= 0.5
            side = 1
        if b - a > 0.5 * width_old:
            slow += 1
        else:
            slow = 0
        width_old = b - a
    return b


@njit(cache=True, error_model="numpy")
def _fd_step(v):
    return FD_REL_STEP * max(1.0, abs(v))


@njit(cache=True, error_model="numpy")
def _event_derivatives(guards, reset, phase, k, t, x, p, n_x, n_guards, n_impulse):
    """Gradient of guard ``k`` and Jacobian of the reset at (t, x), with their t-partials.

    Richardson-extrapolated central differences: D = (4 D(h/2) - D(h)) / 3 (4th order).
    Returns (grad_g (n_x,), dg_dt, DR (n_x, n_x), dR_dt (n_x,)).
    """
    grad = np.empty(n_x)
    DR = np.empty((n_x, n_x))
    dRdt = np.empty(n_x)
    gbuf = np.empty(n_guards)
    xp = x.copy()
    xn = np.empty(n_x)
    imp = np.zeros(n_impulse)
    col = np.empty(n_x)
    colh = np.empty(n_x)
    dgdt = 0.0
    for j in range(n_x + 1):  # j == n_x: time
        base = t if j == n_x else x[j]
        hh = _fd_step(base)
        gd = 0.0
        gdh = 0.0
        for level in range(2):
            step = hh if level == 0 else 0.5 * hh
            gsum = 0.0
            for sgn in (1.0, -1.0):
                tt = t
                for i in range(n_x):
                    xp[i] = x[i]
                if j == n_x:
                    tt = t + sgn * step
                else:
                    xp[j] = x[j] + sgn * step
                guards(phase, tt, xp, p, gbuf)
                gsum += sgn * gbuf[k]
                for i in range(n_x):
                    xn[i] = xp[i]
                imp[:] = 0.0
                reset(phase, k, tt, xp, p, xn, imp)
                for i in range(n_x):
                    if level == 0:
                        if sgn > 0:
                            col[i] = xn[i]
                        else:
                            col[i] = (col[i] - xn[i]) / (2.0 * step)
                    else:
                        if sgn > 0:
                            colh[i] = xn[i]
                        else:
                            colh[i] = (colh[i] - xn[i]) / (2.0 * step)
            if level == 0:
                gd = gsum / (2.0 * step)
            else:
                gdh = gsum / (2.0 * step)
        gval = (4.0 * gdh - gd) / 3.0
        if j == n_x:
            dgdt = gval
            for i in range(n_x):
                dRdt[i] = (4.0 * colh[i] - col[i]) / 3.0
        else:
            grad[j] = gval
            for i in range(n_x):
                DR[i, j] = (4.0 * colh[i] - col[i]) / 3.0
    return grad, dgdt, DR, dRdt


@njit(cache=True, error_model="numpy")
def _grow_rows(a, n):
    """Copy of ``a`` (1-D or 2-D) with room for at least ``n`` rows (capacity doubles)."""
    cap = a.shape[0]
    while cap < n:
        cap = 2 * cap + 1
    return cap


@njit(cache=True, error_model="numpy")
def _grow1f(a, n):
    if n <= a.shape[0]:
        return a
    b = np.empty(_grow_rows(a, n))
    b[: a.shape[0]] = a
    return b


@njit(cache=True, error_model="numpy")
def _grow1i(a, n):
    if n <= a.shape[0]:
        return a
    b = np.empty(_grow_rows(a, n), dtype=np.int64)
    b[: a.shape[0]] = a
    return b


@njit(cache=True, error_model="numpy")
def _grow2f(a, n):
    if n <= a.shape[0]:
        return a
    b = np.empty((_grow_rows(a, n), a.shape[1]))
    b[: a.shape[0]] = a
    return b


@njit(cache=True, error_model="numpy")
def _init_arming(directions, phase, g, armed):
    for i in range(g.shape[0]):
        armed[i] = _pre_side(directions[phase, i], g[i])


@njit(cache=True, error_model="numpy")
def _arm_approaching(guards, directions, phase, t, x, f, p, g, armed, xbuf, gbuf):
    """Arm a guard that starts within GUARD_TOL of zero, strictly on its pre-fire side, and
    is moving toward firing (its rate along ``f``, probed by one guard evaluation).

    A post-impact state sits on a guard moving away from it and stays disarmed; a state a
    hair above the ground and moving into it must still see the crossing.
    """
    probed = False
    eps = 1e-9
    for i in range(g.shape[0]):
        if armed[i] or abs(g[i]) > GUARD_TOL or g[i] == 0.0:
            continue
        if not probed:
            for k in range(x.shape[0]):
                xbuf[k] = x[k] + eps * f[k]
            guards(phase, t, xbuf, p, gbuf)
            probed = True
        rate = gbuf[i] - g[i]
        d = directions[phase, i]
        if d <= 0 and g[i] > 0.0 and rate < 0.0:
            armed[i] = True
        elif d >= 0 and g[i] < 0.0 and rate > 0.0:
            armed[i] = True


# =============================================================================================
# The kernel: one call = one whole run
# =============================================================================================


@njit(cache=True, error_model="numpy")
def _guard_rates(guards, phase, t, x, f, p, g, rate, xbuf):
    """Signs of the guards' rates along ``f``: ``g(x + eps f) - g(x)`` (one guard call)."""
    eps = 1e-9
    for k in range(x.shape[0]):
        xbuf[k] = x[k] + eps * f[k]
    guards(phase, t, xbuf, p, rate)
    for i in range(g.shape[0]):
        rate[i] = rate[i] - g[i]


@njit(cache=True, error_model="numpy")
def _dip(guards, kind, Q, y_old, phase, t, p, n_x, xbuf, gbuf, i, sign):
    """Extremum of guard ``i`` over the step on the dense output (golden section).

    ``sign`` = +1 looks for a minimum, -1 for a maximum.  Returns ``(theta, value)`` with
    ``theta`` in (0, 1) the step fraction of the extremum found and ``value`` the guard
    there.
    """
    invphi = 0.6180339887498949
    a = 0.0
    b = 1.0
    c = b - invphi * (b - a)
    d = a + invphi * (b - a)
    _dense_eval(kind, Q, y_old, c, n_x, xbuf)
    guards(phase, t, xbuf, p, gbuf)
    fc = sign * gbuf[i]
    _dense_eval(kind, Q, y_old, d, n_x, xbuf)
    guards(phase, t, xbuf, p, gbuf)
    fd = sign * gbuf[i]
    for _ in range(40):
        if fc < fd:
            b = d
            d = c
            fd = fc
            c = b - invphi * (b - a)
            _dense_eval(kind, Q, y_old, c, n_x, xbuf)
            guards(phase, t, xbuf, p, gbuf)
            fc = sign * gbuf[i]
        else:
            a = c
            c = d
            fc = fd
            d = a + invphi * (b - a)
            _dense_eval(kind, Q, y_old, d, n_x, xbuf)
            guards(phase, t, xbuf, p, gbuf)
            fd = sign * gbuf[i]
        if fc <= 0.0 or fd <= 0.0:
            break
    if fc < fd:
        return c, sign * fc
    return d, sign * fd


@njit(cache=True, error_model="numpy")
def _two_sum(hi, lo, x):
    """Add ``x`` to the compensated sum ``hi + lo`` (Knuth's two-sum)."""
    s = hi + x
    bp = s - hi
    err = (hi - (s - bp)) + (x - bp)
    return s, lo + err


@njit(cache=True, error_model="numpy")
def _local(t_abs, t_off, t_off_c):
    """Absolute time -> local time of the current segment."""
    return (t_abs - t_off) - t_off_c


@njit(cache=True, error_model="numpy")
def _kernel(
    rhs_c,
    rhs_j,
    guards_c,
    guards_j,
    reset_c,
    reset_j,
    jac_c,
    jac_j,
    directions,
    n_x,
    n_guards,
    n_impulse,
    x0,
    p,
    phase0,
    t0,
    t_max,
    n_strides,
    method,
    adaptive,
    rtol,
    atol,
    first_step,
    max_step,
    max_steps,
    output,
    sample_times,
    want_jac,
    n_interior,
):
    rhs = _rhs_fn(rhs_c, rhs_j)
    guards = _guards_fn(guards_c, guards_j)
    reset = _reset_fn(reset_c, reset_j)
    jac = _jac_fn(jac_c, jac_j)
    n_z = n_x + n_x * n_x if want_jac else n_x
    # ---- method set-up ----------------------------------------------------------------
    if method == METHOD_DOP853:
        A = _DOP853_A
        B = _DOP853_B
        C = _DOP853_C
        n_stages = 12
        kind = _DENSE_DOP853
        err_order = 7
        order = 8
    elif method == METHOD_DP5:
        A = _RK45_A
        B = _RK45_B
        C = _RK45_C
        n_stages = 6
        kind = _DENSE_RK45
        err_order = 4
        order = 5
    elif method == METHOD_RK4:
        A = _RK4_A
        B = _RK4_B
        C = _RK4_C
        n_stages = 4
        kind = _DENSE_HERMITE
        err_order = 3
        order = 4
    else:
        A = _EULER_A
        B = _EULER_B
        C = _EULER_C
        n_stages = 1
        kind = _DENSE_HERMITE
        err_order = 0
        order = 1
    exponent = -1.0 / (err_order + 1)

    # ---- work arrays ------------------------------------------------------------------
    z = np.zeros(n_z)
    z[:n_x] = x0
    if want_jac:
        for i in range(n_x):
            z[n_x + i * n_x + i] = 1.0
    y_new = np.empty(n_z)
    tmp = np.empty(n_z)
    f0 = np.empty(n_z)
    f1 = np.empty(n_z)
    K = np.empty((16, n_z))
    Q = np.empty((7, n_z))
    scale = np.empty(n_z)
    J = np.zeros((n_x, n_x))
    xbuf = np.empty(n_x)
    zev = np.empty(n_z)
    x_new = np.empty(n_x)
    impulse = np.zeros(n_impulse)
    ga = np.empty(n_guards)
    gb = np.empty(n_guards)
    gbuf = np.empty(n_guards)
    armed = np.zeros(n_guards, dtype=np.bool_)
    rate_a = np.zeros(n_guards)
    rate_b = np.zeros(n_guards)
    g_end = np.empty(n_guards)
    frac = np.empty(n_interior + 2)
    fm = np.empty(n_x)
    fp = np.empty(n_x)
    jac_out = np.zeros((n_x, n_x))
    dt_dx0 = np.zeros(n_x)
    has_dt = False

    # ---- storage ----------------------------------------------------------------------
    store_events = output >= OUTPUT_EVENTS
    cap_e = 8 if store_events else 0
    ev_t = np.empty(cap_e)
    ev_g = np.empty(cap_e, dtype=np.int64)
    ev_pb = np.empty(cap_e, dtype=np.int64)
    ev_pa = np.empty(cap_e, dtype=np.int64)
    ev_xm = np.empty((cap_e, n_x))
    ev_xp = np.empty((cap_e, n_x))
    ev_imp = np.empty((cap_e, n_impulse))
    n_log = 0
    n_samp_total = sample_times.shape[0] if output == OUTPUT_SAMPLES else 0
    s_x = np.empty((n_samp_total, n_x))
    s_ph = np.empty(n_samp_total, dtype=np.int64)
    n_samp = 0
    cap_r = 64 if output == OUTPUT_FULL else 0
    r_t = np.empty(cap_r)
    r_x = np.empty((cap_r, n_x))
    r_ph = np.empty(cap_r, dtype=np.int64)
    n_rec = 0

    # ---- counters ---------------------------------------------------------------------
    n_steps = 0
    n_rej = 0
    n_rhs = 0
    n_events = 0
    n_done = 0
    err_sum = 0.0
    status = _RUNNING

    # Time is kept as a compensated absolute offset (at the start of the current segment)
    # plus a local time from 0: event times stay resolved to ~1e-16 of a stride even after
    # 1e5 strides, where absolute times lose 1e-11 s to rounding.
    t_off = t0
    t_off_c = 0.0
    t = 0.0
    t_end = t_max - t0
    phase = phase0
    if output == OUTPUT_FULL:
        r_t[0] = t_off
        r_x[0] = z[:n_x]
        r_ph[0] = phase
        n_rec = 1

    # ---- segment start ----------------------------------------------------------------
    _fun(rhs, jac, want_jac, phase, t, z, p, n_x, f0, J)
    n_rhs += 1
    if n_guards > 0:
        guards(phase, t, z[:n_x], p, ga)
        _init_arming(directions, phase, ga, armed)
        _arm_approaching(guards, directions, phase, t, z[:n_x], f0, p, ga, armed, xbuf, gbuf)
        _guard_rates(guards, phase, t, z[:n_x], f0, p, ga, rate_a, xbuf)
    if adaptive:
        if first_step > 0.0:
            h = min(first_step, max_step, t_end - t)
        else:
            h = _initial_step(
                rhs,
                jac,
                want_jac,
                J,
                phase,
                t,
                z,
                f0,
                p,
                n_x,
                order,
                rtol,
                atol,
                max_step,
                t_end - t,
                tmp,
                f1,
            )
            n_rhs += 1
    else:
        h = first_step
    nonfinite_seen = False
    rejected_now = False
    m_sub = n_interior + 1

    while status == _RUNNING:
        if t >= t_end:
            status = _COMPLETED if n_strides == 0 else _NO_EVENT
            break
        if n_steps + n_rej >= max_steps:
            status = _MAX_STEPS
            break
        h = min(h, max_step)
        last = False
        if t + 1.01 * h >= t_end:
            h = t_end - t
            last = True
        min_step = 10.0 * np.spacing(abs(t))
        if adaptive and h < min_step:
            status = _NONFINITE if nonfinite_seen else _STEP_UNDERFLOW
            break
        # ---- one step ----
        K[0] = f0
        n_rhs += _rk_stages(
            rhs, jac, want_jac, J, phase, t, z, h, p, n_x, A, C, B, n_stages, K, y_new, tmp
        )
        t_new = t_end if last else t + h
        err = 0.0
        if adaptive:
            for i in range(n_z):
                scale[i] = atol + rtol * max(abs(z[i]), abs(y_new[i]))
            err = _error_norm(method, K, h, scale)
        finite = _all_finite(y_new) and _all_finite(K[n_stages]) and math.isfinite(err)
        if not finite:
            if not adaptive:
                status = _NONFINITE
                break
            nonfinite_seen = True
            n_rej += 1
            rejected_now = True
            h *= 0.25
            continue
        if adaptive and err > 1.0:
            n_rej += 1
            rejected_now = True
            h *= max(MIN_FACTOR, SAFETY * err**exponent)
            continue
        # ---- accepted ----
        n_steps += 1
        nonfinite_seen = False
        err_sum += err * rtol
        if kind == _DENSE_HERMITE:
            K[1] = K[n_stages]
        dense_ready = False
        event_applied = False
        ta = t
        j = 1
        n_frac = m_sub
        for q in range(m_sub):
            frac[q] = (q + 1.0) / m_sub
        if n_guards > 0:
            # Tangency check: an armed guard on its pre-fire side at both ends of the step
            # whose rate turns from "toward firing" to "away" has an extremum inside; find
            # it on the dense output, and if the guard dips past zero there, sample that
            # instant too, so a dip far shorter than the step is not walked through.
            guards(phase, t_new, y_new[:n_x], p, g_end)
            _guard_rates(guards, phase, t_new, y_new[:n_x], K[n_stages], p, g_end, rate_b, xbuf)
            theta_dip = 2.0
            for i in range(n_guards):
                if not armed[i]:
                    continue
                d = directions[phase, i]
                sign = 0.0
                if d <= 0 and ga[i] > 0.0 and g_end[i] > 0.0 and rate_a[i] < 0.0 < rate_b[i]:
                    sign = 1.0
                elif d >= 0 and ga[i] < 0.0 and g_end[i] < 0.0 and rate_a[i] > 0.0 > rate_b[i]:
                    sign = -1.0
                if sign != 0.0:
                    if not dense_ready:
                        n_rhs += _dense_prepare(
                            kind, rhs, jac, want_jac, J, phase, t, z, y_new, h, p, n_x, K, Q, tmp
                        )
                        dense_ready = True
                    th, gv = _dip(guards, kind, Q, z, phase, t, p, n_x, xbuf, gbuf, i, sign)
                    if sign * gv <= 0.0 and th < theta_dip:
                        theta_dip = th
            if theta_dip < 1.0:
                q = n_frac
                while q > 0 and frac[q - 1] > theta_dip:
                    frac[q] = frac[q - 1]
                    q -= 1
                frac[q] = theta_dip
                n_frac += 1
        while n_guards > 0 and j <= n_frac:
            if j == n_frac:
                tb = t_new
                guards(phase, tb, y_new[:n_x], p, gb)
            else:
                if not dense_ready:
                    n_rhs += _dense_prepare(
                        kind, rhs, jac, want_jac, J, phase, t, z, y_new, h, p, n_x, K, Q, tmp
                    )
                    dense_ready = True
                tb = t + frac[j - 1] * h
                _dense_eval(kind, Q, z, frac[j - 1], n_x, xbuf)
                guards(phase, tb, xbuf, p, gb)
            best_t = np.inf
            best_i = -1
            for i in range(n_guards):
                if not armed[i]:
                    continue
                d = directions[phase, i]
                troot = np.inf
                if _crosses(d, ga[i], gb[i]):
                    if not dense_ready:
                        n_rhs += _dense_prepare(
                            kind,
                            rhs,
                            jac,
                            want_jac,
                            J,
                            phase,
                            t,
                            z,
                            y_new,
                            h,
                            p,
                            n_x,
                            K,
                            Q,
                            tmp,
                        )
                        dense_ready = True
                    troot = _locate(
                        guards,
                        kind,
                        Q,
                        z,
                        t,
                        h,
                        phase,
                        p,
                        n_x,
                        xbuf,
                        gbuf,
                        i,
                        ta,
                        tb,
                        ga[i],
                        gb[i],
                    )
                elif last and j == n_frac:
                    # at t_max: an armed guard within GUARD_TOL on its pre-fire side fires.
                    u = gb[i] if ga[i] > 0.0 else -gb[i]
                    if abs(ga[i]) > 0.0 and 0.0 < u <= GUARD_TOL:
                        troot = tb
                if troot < best_t - 4.0 * np.spacing(abs(troot)):
                    best_t = troot
                    best_i = i
            if best_i < 0:
                for i in range(n_guards):
                    if not armed[i]:
                        armed[i] = _pre_side(directions[phase, i], gb[i])
                    ga[i] = gb[i]
                ta = tb
                j += 1
                continue
            # ---- an event at best_t ----
            if not dense_ready:
                n_rhs += _dense_prepare(
                    kind, rhs, jac, want_jac, J, phase, t, z, y_new, h, p, n_x, K, Q, tmp
                )
                dense_ready = True
            theta = (best_t - t) / h
            _dense_eval(kind, Q, z, theta, n_z, zev)
            for i in range(n_x):
                x_new[i] = zev[i]
            impulse[:] = 0.0
            action, nxt, st = reset(phase, best_i, best_t, zev[:n_x], p, x_new, impulse)
            if action == EVENT_IGNORE:
                armed[best_i] = False
                ta = best_t
                guards(phase, best_t, zev[:n_x], p, ga)
                for i in range(n_guards):
                    if i != best_i and not armed[i]:
                        armed[i] = _pre_side(directions[phase, i], ga[i])
                continue
            # samples up to and including the event time come from the pre-event segment
            while n_samp < n_samp_total and _local(sample_times[n_samp], t_off, t_off_c) <= best_t:
                _dense_eval(
                    kind,
                    Q,
                    z,
                    (_local(sample_times[n_samp], t_off, t_off_c) - t) / h,
                    n_x,
                    s_x[n_samp],
                )
                s_ph[n_samp] = phase
                n_samp += 1
            if store_events:
                n_log += 1
                ev_t = _grow1f(ev_t, n_log)
                ev_g = _grow1i(ev_g, n_log)
                ev_pb = _grow1i(ev_pb, n_log)
                ev_pa = _grow1i(ev_pa, n_log)
                ev_xm = _grow2f(ev_xm, n_log)
                ev_xp = _grow2f(ev_xp, n_log)
                ev_imp = _grow2f(ev_imp, n_log)
                ev_t[n_log - 1] = t_off + (best_t + t_off_c)
                ev_g[n_log - 1] = best_i
                ev_pb[n_log - 1] = phase
                ev_xm[n_log - 1] = zev[:n_x]
                if action == EVENT_TERMINAL:
                    ev_pa[n_log - 1] = phase
                    ev_xp[n_log - 1] = zev[:n_x]
                    ev_imp[n_log - 1] = 0.0
                else:
                    ev_pa[n_log - 1] = nxt
                    ev_xp[n_log - 1] = x_new
                    ev_imp[n_log - 1] = impulse
            if action == EVENT_TERMINAL:
                status = st
                t = best_t
                for i in range(n_z):
                    z[i] = zev[i]
                if output == OUTPUT_FULL:
                    n_rec += 1
                    r_t = _grow1f(r_t, n_rec)
                    r_x = _grow2f(r_x, n_rec)
                    r_ph = _grow1i(r_ph, n_rec)
                    r_t[n_rec - 1] = t_off + (t + t_off_c)
                    r_x[n_rec - 1] = z[:n_x]
                    r_ph[n_rec - 1] = phase
                event_applied = True
                break
            # ---- apply the reset ----
            phase_before = phase
            n_events += 1
            finishing = False
            if action == EVENT_STRIDE:
                n_done += 1
                finishing = n_strides > 0 and n_done >= n_strides
            if want_jac:
                grad, dgdt, DR, dRdt = _event_derivatives(
                    guards,
                    reset,
                    phase,
                    best_i,
                    best_t,
                    zev[:n_x],
                    p,
                    n_x,
                    n_guards,
                    n_impulse,
                )
                rhs(phase, best_t, zev[:n_x], p, fm)
                rhs(nxt, best_t, x_new, p, fp)
                n_rhs += 2
                den = dgdt
                for i in range(n_x):
                    den += grad[i] * fm[i]
                # w = f+ - DR f- - dR/dt (saltation) or DR f- + dR/dt (map)
                w = np.empty(n_x)
                for i in range(n_x):
                    acc = 0.0
                    for k in range(n_x):
                        acc += DR[i, k] * fm[k]
                    w[i] = acc + dRdt[i]
                if finishing:
                    for i in range(n_x):
                        w[i] = -w[i]
                else:
                    for i in range(n_x):
                        w[i] = fp[i] - w[i]
                # M = DR + w grad^T / den; Phi <- M Phi
                Phi_m = np.empty((n_x, n_x))
                for r in range(n_x):
                    for c in range(n_x):
                        Phi_m[r, c] = zev[n_x + r * n_x + c]
                gPhi = np.zeros(n_x)
                for c in range(n_x):
                    acc = 0.0
                    for k in range(n_x):
                        acc += grad[k] * Phi_m[k, c]
                    gPhi[c] = acc
                for r in range(n_x):
                    for c in range(n_x):
                        acc = w[r] * gPhi[c] / den
                        for k in range(n_x):
                            acc += DR[r, k] * Phi_m[k, c]
                        z[n_x + r * n_x + c] = acc
                if finishing:
                    for c in range(n_x):
                        dt_dx0[c] = -gPhi[c] / den
                    has_dt = True
            phase = nxt
            t = best_t
            for i in range(n_x):
                z[i] = x_new[i]
            if output == OUTPUT_FULL:
                n_rec += 2
                r_t = _grow1f(r_t, n_rec)
                r_x = _grow2f(r_x, n_rec)
                r_ph = _grow1i(r_ph, n_rec)
                r_t[n_rec - 2] = t_off + (t + t_off_c)
                r_x[n_rec - 2] = zev[:n_x]
                r_ph[n_rec - 2] = phase_before
                r_t[n_rec - 1] = t_off + (t + t_off_c)
                r_x[n_rec - 1] = z[:n_x]
                r_ph[n_rec - 1] = phase
            event_applied = True
            # re-base local time at the event
            t_off, t_off_c = _two_sum(t_off, t_off_c, t)
            t = 0.0
            t_end = (t_max - t_off) - t_off_c
            if finishing:
                status = _COMPLETED
                break
            # ---- restart the method at the event ----
            _fun(rhs, jac, want_jac, phase, t, z, p, n_x, f0, J)
            n_rhs += 1
            guards(phase, t, z[:n_x], p, ga)
            _init_arming(directions, phase, ga, armed)
            _arm_approaching(guards, directions, phase, t, z[:n_x], f0, p, ga, armed, xbuf, gbuf)
            _guard_rates(guards, phase, t, z[:n_x], f0, p, ga, rate_a, xbuf)
            if adaptive:
                if t < t_end:
                    h = _initial_step(
                        rhs,
                        jac,
                        want_jac,
                        J,
                        phase,
                        t,
                        z,
                        f0,
                        p,
                        n_x,
                        order,
                        rtol,
                        atol,
                        max_step,
                        t_end - t,
                        tmp,
                        f1,
                    )
                    n_rhs += 1
            else:
                h = first_step
            rejected_now = False
            break
        if event_applied:
            continue
        # ---- no event in this step: samples, record, advance ----
        if n_samp < n_samp_total and _local(sample_times[n_samp], t_off, t_off_c) <= t_new:
            if not dense_ready:
                n_rhs += _dense_prepare(
                    kind, rhs, jac, want_jac, J, phase, t, z, y_new, h, p, n_x, K, Q, tmp
                )
                dense_ready = True
            while n_samp < n_samp_total and _local(sample_times[n_samp], t_off, t_off_c) <= t_new:
                _dense_eval(
                    kind,
                    Q,
                    z,
                    (_local(sample_times[n_samp], t_off, t_off_c) - t) / h,
                    n_x,
                    s_x[n_samp],
                )
                s_ph[n_samp] = phase
                n_samp += 1
        t = t_new
        for i in range(n_z):
            z[i] = y_new[i]
            f0[i] = K[n_stages, i]
        for i in range(n_guards):
            rate_a[i] = rate_b[i]
        if output == OUTPUT_FULL:
            n_rec += 1
            r_t = _grow1f(r_t, n_rec)
            r_x = _grow2f(r_x, n_rec)
            r_ph = _grow1i(r_ph, n_rec)
            r_t[n_rec - 1] = t_off + (t + t_off_c)
            r_x[n_rec - 1] = z[:n_x]
            r_ph[n_rec - 1] = phase
        if last:
            status = _COMPLETED if n_strides == 0 else _NO_EVENT
            break
        if adaptive:
            if err == 0.0:
                factor = MAX_FACTOR
            else:
                factor = min(MAX_FACTOR, SAFETY * err**exponent)
            if rejected_now:
                factor = min(1.0, factor)
            h *= factor
        rejected_now = False

    if want_jac:
        for r in range(n_x):
            for c in range(n_x):
                jac_out[r, c] = z[n_x + r * n_x + c]
    counters = np.array([n_steps, n_rej, n_rhs, n_events, n_done, n_log, n_samp, n_rec])
    return (
        int(status),
        t_off + (t + t_off_c),
        z[:n_x].copy(),
        phase,
        counters,
        err_sum,
        ev_t[:n_log],
        ev_g[:n_log],
        ev_pb[:n_log],
        ev_pa[:n_log],
        ev_xm[:n_log],
        ev_xp[:n_log],
        ev_imp[:n_log],
        s_x[:n_samp],
        s_ph[:n_samp],
        r_t[:n_rec],
        r_x[:n_rec],
        r_ph[:n_rec],
        jac_out,
        dt_dx0,
        has_dt,
    )


# =============================================================================================
# Python entry point
# =============================================================================================

_EMPTY = np.empty(0)


def _check_positive_float(name, value, allow_inf=False):
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
        raise TypeError(f"`{name}` must be a real number, got {type(value).__name__}")
    value = float(value)
    if not (value > 0.0) or (not allow_inf and not math.isfinite(value)):
        raise ValueError(
            f"`{name}` must be positive{'' if allow_inf else ' and finite'}, got {value!r}"
        )
    return value


def _check_int(name, value, low):
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise TypeError(f"`{name}` must be an int, got {type(value).__name__}")
    if value < low:
        raise ValueError(f"`{name}` must be >= {low}, got {value}")
    return int(value)


def check_solver_settings(method, rtol, atol, first_step, *, fixed_step=False):
    """Validate solver settings; returns ``(method_code, rtol, atol, first_step, adaptive)``.

    Raises ``ValueError``/``TypeError`` naming the argument: an unknown ``method``,
    non-positive or non-finite ``rtol``/``atol``, ``rtol < 100 eps``, a fixed-step method
    without a positive ``first_step``.  ``first_step`` is returned as 0.0 when it is None
    (adaptive methods choose their own).
    """
    if method not in METHODS:
        raise ValueError(f"`method` must be one of {sorted(METHODS)}, got {method!r}")
    code = METHODS[method]
    rtol = _check_positive_float("rtol", rtol)
    atol = _check_positive_float("atol", atol)
    if rtol < 100 * np.finfo(float).eps:
        raise ValueError(
            f"`rtol` must be >= 100 * eps = {100 * np.finfo(float).eps:.3g}, got {rtol!r}"
        )
    adaptive = code in (METHOD_DOP853, METHOD_DP5) and not fixed_step
    if first_step is None:
        if not adaptive:
            raise ValueError(
                f"`first_step` must be given (a positive fixed step) for method {method!r}"
            )
        first_step = 0.0
    else:
        first_step = _check_positive_float("first_step", first_step)
    return code, rtol, atol, first_step, adaptive


def hybrid_solve(
    system: HybridSystem,
    x0,
    p,
    *,
    phase0: int = 0,
    t0: float = 0.0,
    t_max: float = 100.0,
    n_strides: int = 1,
    method: str = "DOP853",
    rtol: float = 1e-10,
    atol: float = 1e-12,
    first_step: float | None = None,
    max_step: float = np.inf,
    max_steps: int = 1_000_000,
    output: str = "map",
    sample_times=None,
    jacobian: bool = False,
    n_interior: int = 4,
) -> Solution:
    """Integrate a hybrid system through its phases and events, in one compiled call.

    Parameters
    ----------
    system : HybridSystem
    x0 : array_like, shape (n_x,)
        initial state (finite).
    p : array_like, shape (n_p,)
        parameters passed unchanged to every model function (finite).
    phase0 : int
        initial phase index.
    t0, t_max : float
        start and end time [s], ``t_max > t0``.
    n_strides : int
        stop with ``Status.COMPLETED`` just after the reset of the ``n_strides``-th
        ``EVENT_STRIDE`` event (reaching ``t_max`` first gives ``Status.NO_EVENT``).
        ``0``: integrate to ``t_max`` and report ``COMPLETED`` there.  A stride event located
        at ``t_max`` itself (within ``GUARD_TOL`` in the guard) counts: the run is
        ``COMPLETED``.
    method : {"DOP853", "RK45", "RK4", "Euler"}
        see the module docstring.  "RK4" and "Euler" use the fixed step ``first_step``.
    rtol, atol : float
        relative and absolute tolerance of the adaptive methods.  ``rtol`` must be at least
        ``100 * eps`` (about 2.2e-14); ``atol`` positive.
    first_step : float or None
        initial step [s] (adaptive methods: at ``t0`` only; ``None``: Hairer's estimate at
        every segment start); the fixed step of "RK4" and "Euler" (required, used throughout,
        the last step shortened to end at ``t_max``; after an event the grid restarts at the
        event time).
    max_step : float
        largest step [s].
    max_steps : int
        bound on step attempts (accepted plus rejected) before ``Status.MAX_STEPS``.
    output : {"map", "events", "samples", "full"}
        "map": final state only; "events": plus an :class:`EventLog` of every located event
        (applied ones and a terminal one; ignored crossings are not logged); "samples":
        plus states at ``sample_times`` from the dense output (a sample at an event time gets
        the pre-event state); "full": plus the initial state, every accepted step end, and
        the pre- and post-event states of every applied event (``t`` non-decreasing).
    sample_times : array_like, shape (n_s,), optional
        sorted, finite, within ``[t0, t_max]``; required with ``output="samples"``.
        Samples after the run stopped (a fall, the last stride) are not returned.
    jacobian : bool
        integrate the variational equations and return ``Solution.jac`` (the derivative of
        the final state with respect to ``x0``, with saltation matrices [5]_ at every
        applied event) and, when the run ends on an event, ``Solution.dt_dx0``.
    n_interior : int
        number of interior dense-output points per step where guards are checked (>= 0).

    Returns
    -------
    Solution
        On ``EVENT_TERMINAL`` the returned ``x`` and ``t`` are the pre-event state and the
        event time.  ``jac`` is None unless ``jacobian=True``.

    Raises
    ------
    ValueError, TypeError
        for invalid input only; expected failures are statuses.

    Examples
    --------
    A plain ODE is a hybrid system with one phase and no guards; see
    ``tests/test_integrate.py`` for bouncing balls and a walker.
    """
    return _solve(
        system,
        x0,
        p,
        phase0=phase0,
        t0=t0,
        t_max=t_max,
        n_strides=n_strides,
        method=method,
        rtol=rtol,
        atol=atol,
        first_step=first_step,
        max_step=max_step,
        max_steps=max_steps,
        output=output,
        sample_times=sample_times,
        jacobian=jacobian,
        n_interior=n_interior,
        fixed_step=False,
    )


def _solve(
    system,
    x0,
    p,
    *,
    phase0,
    t0,
    t_max,
    n_strides,
    method,
    rtol,
    atol,
    first_step,
    max_step,
    max_steps,
    output,
    sample_times,
    jacobian,
    n_interior,
    fixed_step,
):
    """:func:`hybrid_solve` with an extra ``fixed_step`` switch that runs the adaptive
    methods (DOP853, RK45) with the fixed step ``first_step`` and no error control (used to
    measure convergence orders)."""
    if not isinstance(system, HybridSystem):
        raise TypeError(f"`system` must be a HybridSystem, got {type(system).__name__}")
    n_x = system.n_x
    x0 = np.array(x0, dtype=np.float64)  # copy: the caller's array is never touched
    if x0.ndim != 1 or x0.shape[0] != n_x:
        raise ValueError(f"`x0` must be 1-D of length n_x = {n_x}, got shape {x0.shape}")
    if not np.all(np.isfinite(x0)):
        raise ValueError("All components of the initial state `x0` must be finite.")
    p = np.ascontiguousarray(p, dtype=np.float64)
    if p.ndim != 1:
        raise ValueError(f"`p` must be 1-D, got shape {p.shape}")
    if system.n_params is not None and p.shape[0] != system.n_params:
        raise ValueError(
            f"`p` must have length {system.n_params} for system `{system.name}`, got {p.shape[0]}"
        )
    if not np.all(np.isfinite(p)):
        raise ValueError("All parameters `p` must be finite.")
    phase0 = _check_int("phase0", phase0, 0)
    if phase0 >= system.n_phases:
        raise ValueError(f"`phase0` must be < n_phases = {system.n_phases}, got {phase0}")
    for name, v in (("t0", t0), ("t_max", t_max)):
        if isinstance(v, bool) or not isinstance(v, int | float | np.floating | np.integer):
            raise TypeError(f"`{name}` must be a real number, got {type(v).__name__}")
        if not math.isfinite(v):
            raise ValueError(f"`{name}` must be finite, got {v!r}")
    t0 = float(t0)
    t_max = float(t_max)
    if not t_max > t0:
        raise ValueError(f"`t_max` must be greater than `t0` = {t0}, got {t_max}")
    n_strides = _check_int("n_strides", n_strides, 0)
    code, rtol, atol, first_step, adaptive = check_solver_settings(
        method, rtol, atol, first_step, fixed_step=fixed_step
    )
    max_step = _check_positive_float("max_step", max_step, allow_inf=True)
    max_steps = _check_int("max_steps", max_steps, 1)
    if output not in OUTPUTS:
        raise ValueError(f"`output` must be one of {list(OUTPUTS)}, got {output!r}")
    out_code = OUTPUTS[output]
    if out_code == OUTPUT_SAMPLES:
        if sample_times is None:
            raise ValueError('`sample_times` is required with output="samples"')
        st = np.ascontiguousarray(sample_times, dtype=np.float64)
        if st.ndim != 1:
            raise ValueError(f"`sample_times` must be 1-D, got shape {st.shape}")
        if not np.all(np.isfinite(st)):
            raise ValueError("`sample_times` must be finite")
        if st.size > 1 and np.any(np.diff(st) < 0):
            raise ValueError("`sample_times` must be sorted (non-decreasing)")
        if st.size and (st[0] < t0 or st[-1] > t_max):
            raise ValueError(f"`sample_times` must lie within [t0, t_max] = [{t0}, {t_max}]")
    else:
        if sample_times is not None:
            raise ValueError('`sample_times` is only used with output="samples"')
        st = _EMPTY
    if not isinstance(jacobian, bool | np.bool_):
        raise TypeError(f"`jacobian` must be a bool, got {type(jacobian).__name__}")
    jacobian = bool(jacobian)
    if jacobian and system.jac is None:
        raise ValueError("`jacobian=True` needs a system with `jac` (system.jac is None)")
    n_interior = _check_int("n_interior", n_interior, 0)

    res = _kernel(
        *_compiled(system),
        system.directions,
        n_x,
        system.n_guards,
        system.n_impulse,
        x0,
        p,
        phase0,
        t0,
        t_max,
        n_strides,
        code,
        adaptive,
        rtol,
        atol,
        first_step,
        max_step,
        max_steps,
        out_code,
        st,
        jacobian,
        n_interior,
    )
    (
        status,
        t,
        x,
        phase,
        counters,
        err_sum,
        ev_t,
        ev_g,
        ev_pb,
        ev_pa,
        ev_xm,
        ev_xp,
        ev_imp,
        s_x,
        s_ph,
        r_t,
        r_x,
        r_ph,
        jac_out,
        dt_dx0,
        has_dt,
    ) = res
    status = Status(status)
    events = samples = record = None
    if out_code >= OUTPUT_EVENTS:
        events = EventLog(ev_t, ev_g, ev_pb, ev_pa, ev_xm, ev_xp, ev_imp)
    if out_code == OUTPUT_SAMPLES:
        samples = Trajectory(st[: s_x.shape[0]].copy(), s_x, s_ph)
    if out_code == OUTPUT_FULL:
        record = Trajectory(r_t, r_x, r_ph)
    return Solution(
        status=status,
        message=status.message,
        success=status == Status.COMPLETED,
        t=t,
        x=x,
        phase=int(phase),
        n_steps=int(counters[0]),
        n_rejected=int(counters[1]),
        n_rhs=int(counters[2]),
        n_events=int(counters[3]),
        n_strides=int(counters[4]),
        events=events,
        samples=samples,
        record=record,
        jac=jac_out if jacobian else None,
        dt_dx0=dt_dx0 if (jacobian and has_dt) else None,
        error_estimate=float(err_sum),
        phase_names=system.phase_names,
        guard_names=system.guard_names,
    )
