"""Compiled, event-driven integrator for hybrid dynamical systems.

A hybrid system (a walker) is a bundle of compiled functions: a vector field per phase,
guards whose zero crossings are events, a reset (impact) map and optionally the vector
field's Jacobian.  :func:`hybrid_solve` runs the whole simulation -- Runge–Kutta steps,
event detection and location, resets, samples, variational equations -- in one call of
walker's compiled C core (``walker/_core/hybrid*.c``, built into the extension module
``walker._hybrid`` when the package is installed), with the GIL released, so several threads
may integrate at once; Python only validates the input and packs the
:class:`walker.results.Solution`.

Model functions
---------------
A :class:`HybridSystem` (defined in :mod:`walker.simulation.hybrid_system`, re-exported here)
bundles the model's compiled functions; the integrator calls them through the C ABI of
``walker/_core/wk_system.h``.  Each may be a numba ``@njit`` function, a ``numba.cfunc``, a
``ctypes`` function pointer or an int address (see :mod:`walker.simulation.hybrid_system`).

Methods
-------
``"DOP853"``
    Dormand–Prince 8(5,3) with its 7th-order dense output [1]_ [2]_, adaptive.
``"RK45"``
    Dormand–Prince 5(4) [3]_ with Shampine's 4th-order dense output [4]_, adaptive.
``"RK4"``, ``"Euler"``
    classic Runge–Kutta and explicit Euler with a fixed step ``first_step``; cubic Hermite
    interpolation between step ends serves events and samples.

The coefficients live in :mod:`walker.simulation._tableaux`; ``scripts/generate_tableaux.py`` prints
them into the C header ``walker/_core/tableaux.h`` bit for bit.

Step-size control (adaptive methods): the error estimate is measured in the scaled RMS norm
with scale ``atol + rtol * max(|y|, |y_new|)`` (components of the variational matrix
included when ``jacobian=True``; with a seed of ``m < n_x`` columns, see :func:`_solve`, their
squared errors count ``n_x / m`` times and the mean is taken over ``n_x + n_x**2``
components, as if the columns not carried erred like those carried); a step is accepted
when that norm is <= 1; the next step is ``h * min(10, max(0.2, 0.9 * err**(-1/(q+1))))``
with ``q`` the order of the error estimate (7 for DOP853, 4 for RK45), never growing right
after a rejection.  The first step of every
phase segment (at ``t0`` and after each applied event) is chosen by Hairer's rule [2]_
(Sect. II.4) unless ``first_step`` is given, which is used at ``t0`` only.

Events
------
After each accepted step the guards are evaluated at ``n_interior`` equally spaced interior
points of the dense output and at the step end.  For a system with ``autonomous_guards``
(guards that do not read ``t``: every built-in model) the interior points are skipped in a
step where no guard can come near zero: every guard keeps one strict sign at both ends and
exceeds there, in magnitude, four times the bound ``max(|h r_a - D|, |h r_b - D|) / 4`` on
how far its cubic Hermite interpolant strays from the chord (``r_a``, ``r_b`` its rates along
the vector field at the ends, ``D`` its change over the step; the factor four is the
margin for the interpolant's own error).  A step with a sign change, or with a guard near
zero, keeps its points, so the bracket an event is located in is unchanged; what is saved
is the dense output the points need (three right-hand-side evaluations per DOP853 step)
and their guard calls.  A tangency check adds one more point: an
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

With ``jacobian=True`` the variational equations ride along (``Phi' = J(x) Phi``) and every
applied event multiplies ``Phi`` by its saltation matrix [5]_, built from the guard's
gradient and the reset's Jacobian (Richardson-extrapolated central differences) and the
vector fields before and after the event.

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

import numpy as np

from walker import _hybrid
from walker.results import EventLog, Solution, Trajectory
from walker.simulation.hybrid_system import HybridSystem, _compiled
from walker.status import (
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

# =============================================================================================
# Python entry point
# =============================================================================================

_EMPTY = np.empty(0)
_STATUSES = {int(s): s for s in Status}  # status code -> Status, without the enum call
_RTOL_MIN = 100 * np.finfo(float).eps


def _floats(buf, n_cols=None):
    """A float64 array viewing a bytearray returned by walker._hybrid (no copy)."""
    a = np.frombuffer(buf, dtype=np.float64)
    return a if n_cols is None else a.reshape(-1, n_cols)


def _ints(buf):
    return np.frombuffer(buf, dtype=np.int64)


def _check_positive_float(name, value, allow_inf=False):
    if type(value) is float and value > 0.0 and (allow_inf or value != math.inf):
        return value  # the common case, a valid Python float, without the checks below
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
        raise TypeError(f"`{name}` must be a real number, got {type(value).__name__}")
    value = float(value)
    if not (value > 0.0) or (not allow_inf and not math.isfinite(value)):
        raise ValueError(
            f"`{name}` must be positive{'' if allow_inf else ' and finite'}, got {value!r}"
        )
    return value


def _check_int(name, value, low):
    if type(value) is int and value >= low:
        return value  # the common case, a valid Python int, without the checks below
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
        raise ValueError(f"`method` must be one of {', '.join(METHODS)}, got {method!r}")
    code = METHODS[method]
    rtol = _check_positive_float("rtol", rtol)
    atol = _check_positive_float("atol", atol)
    if rtol < _RTOL_MIN:
        raise ValueError(f"`rtol` must be >= 100 * eps = {_RTOL_MIN:.3g}, got {rtol!r}")
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


def _solver_head(system: HybridSystem) -> dict:
    """The keywords of ``_hybrid.solve`` that describe ``system``: its compiled functions
    and context, the guards' directions, ``n_x``, ``n_guards`` and ``n_impulse``."""
    rhs, guards, reset, jac, ctx, _ = _compiled(system)
    return {
        "rhs": rhs,
        "guards": guards,
        "reset": reset,
        "jac": jac,
        "ctx": ctx,
        "directions": system.directions,
        "n_x": system.n_x,
        "n_guards": system.n_guards,
        "n_impulse": system.n_impulse,
    }


class PreparedRun:
    """A :class:`HybridSystem` with its solver settings checked once, for callers that run
    it many times (a stride map, a basin, a sweep): :meth:`map` goes straight to the
    compiled kernel with no per-call validation.

    The caller guarantees what :func:`hybrid_solve` would check: ``x0`` and ``p`` C-contiguous
    float64 arrays of lengths ``n_x`` and ``n_params``, finite; ``0 <= phase0 < n_phases``;
    ``t_max > 0``; ``n_strides >= 0``.  Not picklable (it holds process-local addresses):
    build one per process.
    """

    # _head: the system's keywords of _hybrid.solve (_solver_head); _settings: the solver
    # settings' keywords (method, adaptive, rtol, atol, first_step, max_step, max_steps,
    # n_interior, screen_interior); _run: the run of a _hybrid.PreparedSolve holding both,
    # and map()'s fixed t0 and output, so that a call passes only the keywords that change
    # (a call with more than 15 keywords makes the interpreter build a dict)
    __slots__ = ("system", "_head", "_settings", "_run")

    def __init__(
        self,
        system: HybridSystem,
        *,
        method: str = "DOP853",
        rtol: float = 1e-10,
        atol: float = 1e-12,
        first_step: float | None = None,
        max_step: float = np.inf,
        max_steps: int = 1_000_000,
        n_interior: int = 4,
    ):
        if not isinstance(system, HybridSystem):
            raise TypeError(f"`system` must be a HybridSystem, got {type(system).__name__}")
        code, rtol, atol, first_step, adaptive = check_solver_settings(
            method, rtol, atol, first_step
        )
        self.system = system
        self._head = _solver_head(system)
        self._settings = {
            "method": code,
            "adaptive": adaptive,
            "rtol": rtol,
            "atol": atol,
            "first_step": first_step,
            "max_step": _check_positive_float("max_step", max_step, allow_inf=True),
            "max_steps": _check_int("max_steps", max_steps, 1),
            "n_interior": _check_int("n_interior", n_interior, 0),
            "screen_interior": system.autonomous_guards,
        }
        self._run = _hybrid.PreparedSolve(
            **self._head,
            **self._settings,
            t0=0.0,
            output=OUTPUT_MAP,
            n_p=system.n_params,  # None: the system does not declare it
        ).run

    def __reduce__(self):
        raise TypeError("a PreparedRun holds process-local addresses: build one per process")

    def map(
        self,
        x0,
        p,
        phase0: int,
        t_max: float,
        n_strides: int,
        jacobian: bool,
        jacobian_seed=None,
    ):
        """One run from ``(t0 = 0, x0)``: ``(status, t, x, jac)``, ``status`` an int
        (:class:`walker.status.Status` value), ``jac`` None unless ``jacobian``.  A negative
        ``phase0`` (a model's start phase that could not be chosen) gives
        ``LINEAR_SOLVE_FAILED`` without a run.

        ``jacobian_seed`` (with ``jacobian``): None, or a C-contiguous float64 array ``S`` of
        shape ``(n_x, m)``, ``1 <= m <= n_x``, finite (the caller guarantees it); the run
        then propagates only the ``m`` columns of ``(d x / d x0) S`` and ``jac`` is that
        ``(n_x, m)`` product (see :func:`_solve`)."""
        if jacobian and self.system.jac is None:
            raise ValueError("`jacobian=True` needs a system with `jac` (system.jac is None)")
        if phase0 < 0:
            # a model's start_phase reports -1 when the joint modes cannot be chosen (a
            # singular system): no run, the outcome says why
            return int(Status.LINEAR_SOLVE_FAILED), 0.0, x0.copy(), None
        r = self._run(
            x0=x0,
            p=p,
            phase0=phase0,
            t_max=t_max,
            n_strides=n_strides,
            want_jac=jacobian,
            jacobian_seed=jacobian_seed,
        )
        # r: a walker._hybrid.SolveResult, read by field (see _solve)
        if not jacobian:
            return r.status, r.t, _floats(r.x), None
        m = self._head["n_x"] if jacobian_seed is None else jacobian_seed.shape[1]
        return r.status, r.t, _floats(r.x), _floats(r.jac, m)


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
        number of interior dense-output points per step where guards are checked (>= 0);
        skipped in a step where every guard stays far from zero when the system declares
        ``autonomous_guards`` (module docstring, section Events).

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
    p_checked=False,
    jacobian_seed=None,
    terrain=None,
):
    """:func:`hybrid_solve` with an extra ``fixed_step`` switch that runs the adaptive
    methods (DOP853, RK45) with the fixed step ``first_step`` and no error control (used to
    measure convergence orders).  ``p_checked``: the caller guarantees that ``p`` is a
    C-contiguous, finite float64 vector of the system's length (checked once, when it was
    made: :func:`walker.simulation.stride.simulate`'s parameter cache).

    ``jacobian_seed`` (with ``jacobian=True``): None (the identity: ``Solution.jac`` is the
    full ``(n_x, n_x)`` derivative of the final state with respect to ``x0``) or an array
    ``S`` of shape ``(n_x, m)``, ``1 <= m <= n_x``: the variational equations, saltation
    matrices and resets then carry only the ``m`` columns of ``Phi = (d x / d x0) S`` (a
    stride map needs ``d x / d x0`` times its lift's Jacobian, ``m = n_z`` columns), and
    ``Solution.jac`` has shape ``(n_x, m)``, ``Solution.dt_dx0`` shape ``(m,)``
    (``(d t / d x0) S``).  The step-size control measures the components carried, so the
    steps taken, and the results to within the integration tolerance, depend on the
    seed; the identity seed gives the run without one bit for bit.

    ``terrain``: None (the model's plane), or a C-contiguous float64 array ``(n_steps, 2)``
    of per-step ``(slope, drop)`` (:mod:`walker.simulation.terrain`, checked by the caller): the run
    takes the model's compiled terrain guards and resets (``_hybrid.terrain_solve``)."""
    if not isinstance(system, HybridSystem):
        raise TypeError(f"`system` must be a HybridSystem, got {type(system).__name__}")
    n_x = system.n_x
    x0 = np.array(x0, dtype=np.float64)  # copy: the caller's array is never touched
    if x0.ndim != 1 or x0.shape[0] != n_x:
        raise ValueError(f"`x0` must be 1-D of length n_x = {n_x}, got shape {x0.shape}")
    if not all(map(math.isfinite, x0.tolist())):
        raise ValueError("All components of the initial state `x0` must be finite.")
    if not p_checked:
        p = np.ascontiguousarray(p, dtype=np.float64)
        if p.ndim != 1:
            raise ValueError(f"`p` must be 1-D, got shape {p.shape}")
        if system.n_params is not None and p.shape[0] != system.n_params:
            raise ValueError(
                f"`p` must have length {system.n_params} for system `{system.name}`, "
                f"got {p.shape[0]}"
            )
        if not np.isfinite(p).all():
            raise ValueError("All parameters `p` must be finite.")
    phase0 = _check_int("phase0", phase0, 0)
    if phase0 >= system.n_phases:
        raise ValueError(f"`phase0` must be < n_phases = {system.n_phases}, got {phase0}")
    for name, v in (("t0", t0), ("t_max", t_max)):
        if type(v) is float and math.isfinite(v):
            continue  # the common case, a finite Python float
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
    if jacobian is not False and jacobian is not True and not isinstance(jacobian, np.bool_):
        raise TypeError(f"`jacobian` must be a bool, got {type(jacobian).__name__}")
    jacobian = bool(jacobian)
    if jacobian and system.jac is None:
        raise ValueError("`jacobian=True` needs a system with `jac` (system.jac is None)")
    n_interior = _check_int("n_interior", n_interior, 0)
    n_c = n_x
    if jacobian_seed is not None:
        if not jacobian:
            raise ValueError("`jacobian_seed` is only used with `jacobian=True`")
        jacobian_seed = np.array(jacobian_seed, dtype=np.float64, order="C")
        if jacobian_seed.ndim != 2 or jacobian_seed.shape[0] != n_x:
            raise ValueError(
                f"`jacobian_seed` must have shape (n_x = {n_x}, m), got {jacobian_seed.shape}"
            )
        n_c = jacobian_seed.shape[1]
        if not 1 <= n_c <= n_x:
            raise ValueError(f"`jacobian_seed` must have 1 <= m <= n_x = {n_x} columns, got {n_c}")
        if not np.isfinite(jacobian_seed).all():
            raise ValueError("`jacobian_seed` must be finite")

    solve, where = (
        (_hybrid.solve, {}) if terrain is None else (_hybrid.terrain_solve, {"terrain": terrain})
    )
    res = solve(
        **_solver_head(system),
        x0=x0,
        p=p,
        phase0=phase0,
        t0=t0,
        t_max=t_max,
        n_strides=n_strides,
        method=code,
        adaptive=adaptive,
        rtol=rtol,
        atol=atol,
        first_step=first_step,
        max_step=max_step,
        max_steps=max_steps,
        n_interior=n_interior,
        screen_interior=system.autonomous_guards,
        output=out_code,
        want_jac=jacobian,
        sample_times=st,
        jacobian_seed=jacobian_seed,
        n_p=system.n_params,
        **where,
    )
    # res is a walker._hybrid.SolveResult (walker/_core/_hybridresult.c), a tuple read by
    # field: status (int), t (float), x, phase; the counters n_steps, n_rejected, n_rhs,
    # n_events, n_strides and the row counts n_logged, n_samples, n_recorded (ints);
    # error_estimate (float); the event log event_t, event_guard, event_phase_before,
    # event_phase_after, event_x_pre, event_x_post, event_impulse (output "events" or
    # richer); sample_x, sample_phase ("samples"); record_t, record_x, record_phase ("full");
    # jac (n_x, n_c), dt_dx0 (n_c,) and has_dt_dx0 (with `jacobian`).  Arrays come as
    # bytearrays of native float64 / int64, row-major, viewed here without a copy.
    status = _STATUSES.get(res.status) or Status(res.status)
    events = samples = record = None
    if out_code >= OUTPUT_EVENTS:
        events = EventLog(
            _floats(res.event_t),
            _ints(res.event_guard),
            _ints(res.event_phase_before),
            _ints(res.event_phase_after),
            _floats(res.event_x_pre, n_x),
            _floats(res.event_x_post, n_x),
            _floats(res.event_impulse, system.n_impulse),
        )
    if out_code == OUTPUT_SAMPLES:
        s_x = _floats(res.sample_x, n_x)
        samples = Trajectory(st[: s_x.shape[0]].copy(), s_x, _ints(res.sample_phase))
    if out_code == OUTPUT_FULL:
        record = Trajectory(
            _floats(res.record_t), _floats(res.record_x, n_x), _ints(res.record_phase)
        )
    return Solution(
        status=status,
        message=status.message,
        success=status == Status.COMPLETED,
        t=res.t,
        x=_floats(res.x),
        phase=res.phase,
        n_steps=res.n_steps,
        n_rejected=res.n_rejected,
        n_rhs=res.n_rhs,
        n_events=res.n_events,
        n_strides=res.n_strides,
        events=events,
        samples=samples,
        record=record,
        jac=_floats(res.jac, n_c) if jacobian else None,
        dt_dx0=_floats(res.dt_dx0) if (jacobian and res.has_dt_dx0) else None,
        error_estimate=res.error_estimate,
        phase_names=system.phase_names,
        guard_names=system.guard_names,
    )
