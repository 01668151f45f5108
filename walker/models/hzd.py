"""Hybrid zero dynamics (HZD) of the actuated walkers under virtual constraints.

With the outputs ``y = q[1:] - b(s(theta))`` of :mod:`walker.models.control` held at zero, the
walker moves on the zero-dynamics surface ``Z = {y = 0, yd = 0}``: ``q = q_Z(theta) =
(theta, b(s(theta)))`` and ``qd = sigma(theta) theta_dot`` with ``sigma = dq_Z/dtheta``.  Its
motion is the two-dimensional zero dynamics in ``(theta, theta_dot)``, given by the
unactuated row of the Lagrangian dynamics: ``beta`` annihilates the input map ``B``
(``beta B = 0``; ``(1, 1, 1)`` for the three-link walker, ``(1, 0, 1, 1, 1)`` for the
five-link walker: a rigid rotation about the stance foot), so ``beta (D qdd + h) = 0`` with
``qdd = sigma theta_ddot + sigma' theta_dot^2`` (Westervelt, Grizzle, Koditschek 2003 [1]_).

``Z`` is *hybrid invariant* when the heel-strike impact maps ``S ∩ Z`` into ``Z``:
``h(Delta_q(q-)) = 0`` and ``L_f h(Delta(q-, qd-)) = 0`` [1]_.  Then the restricted Poincaré
map ``rho`` on ``S ∩ Z`` is one-dimensional; here it acts on ``theta_dot`` just after heel
strike.  In the coordinates ``zeta = (beta D qd)^2 / 2`` (the squared angular momentum about
the stance foot, ``beta D qd = I(theta) theta_dot``) the zero dynamics integrate in closed
form, ``zeta- = zeta+ - V(theta-)``, and the impact scales the momentum by a constant
``delta_zero``, so ``rho(zeta) = delta_zero^2 (zeta - V(theta-))`` and the multiplier of its
fixed point is ``delta_zero^2`` whatever the coordinates [1]_ (Theorem 3 / Corollary 2).

Every function takes a :class:`walker.params.ThreeLinkParams` or
:class:`walker.params.FiveLinkParams` whose controller block holds the design (the phase
variable is the model's first coordinate, the outputs its other coordinates).  The impact
surface: a step ends when the phase reaches ``theta_minus``; :func:`make_invariant` places the
swing foot on the ground there.

Joint friction (``damping_*``, ``coulomb_*`` of the parameter classes): the tools that
integrate or evaluate the zero dynamics (:func:`zero_dynamics_accel`, :func:`restricted_map`,
:func:`restricted_fixed_point`) assume a frictionless model and raise ``ValueError`` naming
the parameter when a joint friction is nonzero.  The friction torques act through ``B``
(``S = B^T``), so ``beta`` annihilates them and the dynamics *on* ``Z`` would not change; but
the controller does not compensate them, so the closed loop leaves ``Z`` (and a stuck joint
cannot follow ``y = 0`` at all): the restricted map no longer describes the walker, whose
gait is then found on the full-order stride map (:class:`walker.simulation.stride.StrideMap`).  The
geometric and impact tools (:func:`surface`, :func:`invariance_residual`,
:func:`make_invariant`, :func:`impact_momentum_ratio`) do not involve the friction (bounded
joint torques do no impulsive work) and accept any value.

References
----------
.. [1] E. R. Westervelt, J. W. Grizzle, D. E. Koditschek, "Hybrid zero dynamics of planar
   biped walkers", IEEE TAC 48(1):42-56, 2003.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from walker.models import five_link as FL
from walker.models import get_model
from walker.models import three_link as TL
from walker.models.control import BEZIER_DEGREE, bezier
from walker.params import FiveLinkParams, ThreeLinkParams
from walker.status import EVENT_IGNORE, Status

__all__ = [
    "RestrictedMap",
    "HZDOrbit",
    "surface",
    "zero_dynamics_accel",
    "invariance_residual",
    "make_invariant",
    "impact_momentum_ratio",
    "restricted_map",
    "restricted_fixed_point",
]

BETA = np.array([1.0, 1.0, 1.0])
"""Annihilator of the three-link input map: ``BETA @ B = 0``."""
BETA_FIVE_LINK = np.array([1.0, 0.0, 1.0, 1.0, 1.0])
"""Annihilator of the five-link input map (``walker.models.five_link.B_MATRIX``)."""


class _Model:
    """What the HZD routines need of a model: its module, its compiled kernels (through the
    checked :meth:`walker.models.WalkerModel.kernel`), ``beta``, the names of its
    joint-friction parameters."""

    def __init__(self, name, module, beta, friction_names):
        self.name = name
        self.module = module
        self.beta = beta
        self.n = module.N_Q
        self.offset = module.CONTROL_OFFSET
        self.friction_names = friction_names

    def mass_matrix(self, q, p) -> np.ndarray:
        """The pinned model's mass matrix ``D(q)`` (n, n)."""
        return get_model(self.name).kernel("mass_matrix", p, q)

    def bias(self, q, qd, p) -> np.ndarray:
        """``h(q, qd) = C(q, qd) qd + g(q)`` (n,)."""
        return get_model(self.name).kernel("bias", p, q, qd)


_MODELS = {
    ThreeLinkParams: _Model("three_link", TL, BETA, ("damping_hip", "coulomb_hip")),
    FiveLinkParams: _Model(
        "five_link",
        FL,
        BETA_FIVE_LINK,
        ("damping_hip", "damping_knee", "coulomb_hip", "coulomb_knee"),
    ),
}


def _model(params) -> _Model:
    if type(params) not in _MODELS:
        raise TypeError(
            f"`params` must be a ThreeLinkParams or FiveLinkParams, got {type(params).__name__}"
        )
    return _MODELS[type(params)]


def _check(params) -> np.ndarray:
    _model(params)
    if isinstance(params, ThreeLinkParams) and params.controller == 3.0:
        raise ValueError(
            "`controller` must be 1 or 2 (Bezier virtual constraints) for the hybrid-zero-"
            "dynamics tools; controller 3 (finite-time, polynomial outputs) is not supported "
            f"here (use walker.StrideMap), got {params.controller!r}"
        )
    return params.as_array()


def _check_frictionless(params) -> np.ndarray:
    """``_check``, and every joint friction must be zero (module docstring)."""
    p = _check(params)
    units = type(params).units()
    for name in _model(params).friction_names:
        value = getattr(params, name)
        if value != 0.0:
            raise ValueError(
                f"`{name}` must be 0 [{units[name]}] for the hybrid-zero-dynamics map (it "
                "assumes a frictionless model; use walker.StrideMap for a walker with joint "
                f"friction), got {value!r}"
            )
    return p


def _coefficients(p: np.ndarray, mdl: _Model) -> np.ndarray:
    c = mdl.offset + 6
    m1 = BEZIER_DEGREE + 1
    return p[c : c + (mdl.n - 1) * m1].reshape(mdl.n - 1, m1)


def surface(params, theta: float):
    """The zero-dynamics surface at phase ``theta``.

    Parameters
    ----------
    params : ThreeLinkParams or FiveLinkParams
    theta : float
        phase (the model's first coordinate) [rad].

    Returns
    -------
    q : ndarray, shape (n_q,)
        ``q_Z(theta)`` [rad].
    sigma : ndarray, shape (n_q,)
        ``dq_Z/dtheta``.
    dsigma : ndarray, shape (n_q,)
        ``d^2 q_Z/dtheta^2``.
    """
    p = _check(params)
    return _surface(p, float(theta), _model(params))


def _surface(p, theta, mdl):
    tp, tm = p[mdl.offset + 4], p[mdl.offset + 5]
    ds = 1.0 / (tm - tp)
    s = (theta - tp) * ds
    a = _coefficients(p, mdl)
    n = mdl.n
    q = np.zeros(n)
    q[0] = theta
    sigma = np.zeros(n)
    sigma[0] = 1.0
    dsigma = np.zeros(n)
    for i in range(n - 1):
        b, b1, b2 = bezier(np.ascontiguousarray(a[i]), s)
        q[i + 1] = b
        sigma[i + 1] = b1 * ds
        dsigma[i + 1] = b2 * ds * ds
    return q, sigma, dsigma


def _accel(p, theta, theta_dot, mdl):
    q, sigma, dsigma = _surface(p, theta, mdl)
    D = mdl.mass_matrix(q, p)
    h = mdl.bias(q, sigma * theta_dot, p)
    bD = mdl.beta @ D
    return -(bD @ dsigma * theta_dot**2 + mdl.beta @ h) / (bD @ sigma)


def zero_dynamics_accel(params, theta: float, theta_dot: float) -> float:
    """``theta_ddot`` of the zero dynamics at ``(theta, theta_dot)`` [rad/s^2].

    Raises ``ValueError`` when a joint friction of ``params`` is nonzero (module docstring).
    """
    p = _check_frictionless(params)
    return float(_accel(p, float(theta), float(theta_dot), _model(params)))


def _state(q, qd, mdl):
    return np.concatenate([q, qd, np.zeros(mdl.module.N_X - 2 * mdl.n)])


def _impact(p, theta_minus, theta_dot_minus, mdl):
    """Heel strike from the surface point at ``theta_minus``: (x_plus, impulse, status)."""
    q, sigma, _ = _surface(p, theta_minus, mdl)
    x = _state(q, sigma * theta_dot_minus, mdl)
    # The compiled reset of the swing-foot guard (0) is the heel strike; without friction
    # (the HZD tools refuse it) the joint modes it then chooses change no rate.
    action, _, status, x_new, impulse = get_model(mdl.name).apply_reset(0, 0, x, p)
    if action == EVENT_IGNORE:  # the swing foot is not ahead of the stance foot
        status = int(Status.NONPHYSICAL_IMPACT)
    return x_new, impulse[:2], int(status)


def invariance_residual(params) -> tuple[np.ndarray, np.ndarray]:
    """How far the impact throws ``S ∩ Z`` off ``Z``.

    The pre-impact state is the surface point at ``theta_minus`` with ``theta_dot = -1``
    (``L_f h`` is linear in the rates, so this is a normalization).

    Returns
    -------
    h_plus : ndarray, shape (n_q - 1,)
        ``y`` just after the impact [rad]: ``h(Delta_q(q-))``.
    lfh_plus : ndarray, shape (n_q - 1,)
        ``yd`` just after the impact per unit ``theta_dot-`` [rad/s per rad/s].
    """
    p = _check(params)
    mdl = _model(params)
    n = mdl.n
    tm = p[mdl.offset + 5]
    x, _, _ = _impact(p, tm, -1.0, mdl)
    q, sigma, _ = _surface(p, x[0], mdl)
    return x[1:n] - q[1:], x[n + 1 : 2 * n] - sigma[1:] * x[n]


def make_invariant(params):
    """Adjust the design so that the zero-dynamics surface is hybrid invariant.

    Three-link walker: keeps ``theta_minus``, the slope, and the coefficients
    ``bezier_*_2 .. bezier_*_4`` except ``bezier_swing_4``; sets (Westervelt et al. 2003 [1]_,
    Sect. V):

    1. ``theta_plus = -theta_minus - 2 slope`` and ``bezier_swing_4 = theta_plus``: at
       ``theta_minus`` the swing foot touches the ground, and the legs swap;
    2. ``bezier_*_0 = Delta_q(q-)``: the post-impact configuration is on ``Z``
       (``bezier_swing_0 = theta_minus``, ``bezier_torso_0 = bezier_torso_4``);
    3. ``bezier_*_1 = bezier_*_0 + (qd+_i / qd+_stance) / (M ds/dtheta)``: the post-impact
       velocity is tangent to ``Z`` (``b'(0) ds/dtheta = qd+_i / qd+_stance``).

    Five-link walker: keeps ``theta_minus``, the slope, ``bezier_knee_2..4``,
    ``bezier_torso_2..4``, ``bezier_femur_2..3`` and ``bezier_tibia_2..3``; sets

    1. ``bezier_femur_4``, ``bezier_tibia_4``: at ``theta_minus`` the swing leg has the stance
       knee's flexion ``bezier_knee_4`` and its foot-to-hip line is the mirror image of the
       stance leg's about the slope normal, so the swing foot is on the slope, ahead;
    2. ``theta_plus`` and ``bezier_*_0`` from the relabelled configuration ``Delta_q(q-)``;
    3. ``bezier_*_1`` as in step 3 above.

    Joint friction does not enter (it is kept as given).

    Parameters
    ----------
    params : ThreeLinkParams or FiveLinkParams

    Returns
    -------
    ThreeLinkParams or FiveLinkParams
        the adjusted design (validated).
    """
    p = _check(params)
    if isinstance(params, FiveLinkParams):
        return _make_invariant_five_link(params)
    tm = params.theta_minus
    tp = -tm - 2.0 * params.slope
    if not tp != tm:
        raise ValueError(f"`theta_minus` must differ from -slope, got {tm!r}")
    changes = {
        "theta_plus": tp,
        "bezier_swing_4": tp,
        "bezier_swing_0": tm,
        "bezier_torso_0": params.bezier_torso_4,
    }
    p1 = params.replace(**changes)
    p = p1.as_array()
    x, _, _ = _impact(p, tm, -1.0, _MODELS[ThreeLinkParams])
    ds = 1.0 / (tm - tp)
    for i, name in enumerate(("swing", "torso")):
        a0 = changes[f"bezier_{name}_0"]
        changes[f"bezier_{name}_1"] = a0 + (x[4 + i] / x[3]) / (BEZIER_DEGREE * ds)
    return params.replace(**changes)


_FIVE_LINK_OUTPUTS = ("knee", "torso", "femur", "tibia")


def _make_invariant_five_link(params: FiveLinkParams) -> FiveLinkParams:
    mdl = _MODELS[FiveLinkParams]
    tm, s = params.theta_minus, params.slope
    lf, lt = params.length_femur, params.length_tibia
    knee = params.bezier_knee_4
    # stance foot -> hip at theta_minus, in the slope frame; delta: its angle minus the mean
    psi_t, psi_f = tm - 0.5 * knee + s, tm + 0.5 * knee + s
    hx = -lt * np.sin(psi_t) - lf * np.sin(psi_f)
    hy = lt * np.cos(psi_t) + lf * np.cos(psi_f)
    phi = float(np.arctan2(-hx, hy))
    delta = phi - (tm + s)
    mean_swing = -phi - delta - s
    q_minus = np.array(
        [tm, knee, params.bezier_torso_4, mean_swing + 0.5 * knee, mean_swing - 0.5 * knee]
    )
    q_plus = FL.RELABEL @ q_minus
    tp = float(q_plus[0])
    if not tp != tm:
        raise ValueError(f"`theta_minus` must differ from -slope, got {tm!r}")
    changes = {"theta_plus": tp, "bezier_femur_4": q_minus[3], "bezier_tibia_4": q_minus[4]}
    for i, name in enumerate(_FIVE_LINK_OUTPUTS):
        changes[f"bezier_{name}_0"] = float(q_plus[i + 1])
    p = params.replace(**changes).as_array()
    x, _, _ = _impact(p, tm, -1.0, mdl)
    ds = 1.0 / (tm - tp)
    for i, name in enumerate(_FIVE_LINK_OUTPUTS):
        a0 = changes[f"bezier_{name}_0"]
        changes[f"bezier_{name}_1"] = a0 + (x[6 + i] / x[5]) / (BEZIER_DEGREE * ds)
    return params.replace(**changes)


def impact_momentum_ratio(params) -> float:
    """``delta_zero``: angular momentum about the new stance foot just after the impact over
    that about the old one just before, on ``S ∩ Z`` (a constant of the design) [1]_."""
    p = _check(params)
    mdl = _model(params)
    n = mdl.n
    tm = p[mdl.offset + 5]
    q, sigma, _ = _surface(p, tm, mdl)
    x, _, _ = _impact(p, tm, -1.0, mdl)
    before = mdl.beta @ mdl.mass_matrix(q, p) @ (-sigma)
    D = mdl.mass_matrix(x[:n], p)
    after = mdl.beta @ D @ x[n : 2 * n]
    return float(after / before)


@dataclass
class RestrictedMap:
    """One step of the restricted Poincaré map.

    Attributes
    ----------
    status : Status
        COMPLETED, FELL_BACKWARD (``theta_dot`` reached zero before ``theta_minus``),
        NO_EVENT, or NONPHYSICAL_IMPACT (the impact on Z is not physical).
    theta_dot_plus : float
        next post-impact stance rate [rad/s] (NaN on failure).
    theta_dot_minus : float
        pre-impact stance rate [rad/s].
    step_time : float
        [s].
    impulse : ndarray, shape (2,)
        impact impulse (tangential, normal) [N s].
    """

    status: Status
    theta_dot_plus: float
    theta_dot_minus: float
    step_time: float
    impulse: np.ndarray


def restricted_map(
    params, theta_dot_plus: float, *, rtol: float = 1e-12, atol: float = 1e-12
) -> RestrictedMap:
    """The restricted Poincaré map ``rho`` on ``S ∩ Z``, by integrating the zero dynamics.

    Integrates ``(theta, theta_dot)`` from ``(theta_plus, theta_dot_plus)`` with DOP853 until
    ``theta = theta_minus``, then applies the heel-strike impact from the surface point there
    and reads the new stance rate.  Exact on an invariant design; on a non-invariant one it
    is the map of the zero dynamics with the impact projected back to ``theta_dot``.

    Parameters
    ----------
    params : ThreeLinkParams or FiveLinkParams
        a frictionless design: a nonzero joint friction (``damping_*``, ``coulomb_*``)
        raises ``ValueError`` (module docstring).
    theta_dot_plus : float
        post-impact stance rate [rad/s], < 0 for forward walking.
    rtol, atol : float
        integration tolerances.

    Returns
    -------
    RestrictedMap
    """
    p = _check_frictionless(params)
    mdl = _model(params)
    if not np.isfinite(theta_dot_plus):
        raise ValueError(f"`theta_dot_plus` must be finite, got {theta_dot_plus!r}")
    tp, tm = p[mdl.offset + 4], p[mdl.offset + 5]

    def f(t, z):
        return [z[1], _accel(p, z[0], z[1], mdl)]

    def end(t, z):
        return z[0] - tm

    end.terminal = True
    end.direction = -1.0 if tm < tp else 1.0

    def stall(t, z):
        return z[1]

    stall.terminal = True
    t_max = 20.0 * np.sqrt(params.leg_length / params.g)
    sol = solve_ivp(
        f,
        (0.0, t_max),
        [tp, float(theta_dot_plus)],
        method="DOP853",
        rtol=rtol,
        atol=atol,
        events=(end, stall),
    )
    nan = float("nan")
    if sol.t_events[1].size:
        return RestrictedMap(Status.FELL_BACKWARD, nan, nan, float(sol.t[-1]), np.full(2, nan))
    if not sol.t_events[0].size:
        return RestrictedMap(Status.NO_EVENT, nan, nan, float(sol.t[-1]), np.full(2, nan))
    thd_minus = float(sol.y_events[0][0][1])
    x, impulse, status = _impact(p, tm, thd_minus, mdl)
    st = Status.COMPLETED if status == 0 else Status(status)
    return RestrictedMap(st, float(x[mdl.n]), thd_minus, float(sol.t_events[0][0]), impulse)


@dataclass
class HZDOrbit:
    """Fixed point of the restricted Poincaré map.

    Attributes
    ----------
    success : bool
    theta_dot_plus : float
        post-impact stance rate on the orbit [rad/s].
    multiplier : float
        ``rho'`` at the fixed point, by central differences.
    multiplier_closed_form : float
        ``delta_zero^2`` (module docstring).
    section : ndarray, shape (n_z,)
        the orbit's point in the full model's section coordinates.
    step_time : float
        [s].
    """

    success: bool
    theta_dot_plus: float
    multiplier: float
    multiplier_closed_form: float
    section: np.ndarray
    step_time: float


def restricted_fixed_point(
    params,
    bracket: tuple[float, float] = (-4.0, -0.2),
    *,
    n_scan: int = 40,
    fd_step: float = 1e-5,
) -> HZDOrbit:
    """Fixed point of :func:`restricted_map` by Brent's method on ``rho(w) - w``.

    ``rho(w) - w`` is sampled at ``n_scan`` points of ``bracket``; the sign change nearest
    ``bracket[1]`` (among walking steps) is refined.

    Parameters
    ----------
    params : ThreeLinkParams or FiveLinkParams
        a frictionless design (as for :func:`restricted_map`).
    bracket : (float, float)
        range of post-impact stance rates [rad/s] to search.
    n_scan : int
        number of samples of the bracket (>= 2).
    fd_step : float
        step of the central difference for the multiplier [rad/s].

    Returns
    -------
    HZDOrbit
        ``success`` False when the bracket holds no sign change of walking steps.
    """
    _check_frictionless(params)
    lo, hi = (float(b) for b in bracket)
    if not lo < hi:
        raise ValueError(f"`bracket` must be increasing, got {bracket!r}")
    if isinstance(n_scan, bool) or not isinstance(n_scan, int) or n_scan < 2:
        raise ValueError(f"`n_scan` must be an int >= 2, got {n_scan!r}")

    def F(w):
        r = restricted_map(params, w)
        return r.theta_dot_plus - w if r.status == Status.COMPLETED else np.nan

    grid = np.linspace(lo, hi, n_scan)
    values = np.array([F(w) for w in grid])
    nan = float("nan")
    change = np.flatnonzero(
        np.isfinite(values[:-1]) & np.isfinite(values[1:]) & (values[:-1] * values[1:] < 0)
    )
    mdl = _model(params)
    n_z = len(mdl.module.SECTION_NAMES)
    if change.size == 0:
        return HZDOrbit(False, nan, nan, nan, np.full(n_z, nan), nan)
    i = change[-1]  # the slowest walking gait in the bracket
    w = brentq(F, grid[i], grid[i + 1], xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
    rp = restricted_map(params, w + fd_step).theta_dot_plus
    rm = restricted_map(params, w - fd_step).theta_dot_plus
    r = restricted_map(params, w)
    p = params.as_array()
    q, sigma, _ = _surface(p, params.theta_plus, mdl)
    section = mdl.module.project(_state(q, sigma * w, mdl), p)
    return HZDOrbit(
        True,
        float(w),
        float((rp - rm) / (2 * fd_step)),
        impact_momentum_ratio(params) ** 2,
        section,
        r.step_time,
    )
