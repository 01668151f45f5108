"""An independent numpy oracle of walker's passive walkers, built from the symbolic models.

The compiled C models (walker/_core/model_*.c over the generated kernels) are compared with
this module by ``tests/test_oracle.py``.  Nothing here comes from walker's C or numba code:

- the continuous dynamics are the sympy models of :mod:`walker.symbolic.models` (mass
  matrix ``D``, bias ``h - Q``, energies, named points), turned into numpy functions by
  ``sympy.lambdify``; accelerations solve ``D qdd = -(h - Q)`` with ``numpy.linalg.solve``,
  and their Jacobian is ``dqdd/dq_k = -D^-1 (dD/dq_k qdd + d(h - Q)/dq_k)``,
  ``dqdd/dqd = -D^-1 d(h - Q)/dqd`` from the lambdified derivatives;
- guards, resets and section lifts are written from ``docs/conventions.md`` and the model
  modules' docstrings: heights and step lengths of the swing foot are projections of the
  symbolic model's points on the slope frame ``s = (cos slope, -sin slope)``,
  ``n = (sin slope, cos slope)``; plastic impacts solve
  ``[D, -J^T; J, 0] [qd+; Lambda] = [D qd-; 0]`` with ``numpy.linalg.solve`` (the knee lock
  with ``J = [0, -1, 1]``, heel strike on the floating-base model with the swing foot's
  material contact velocity ``v_centre + omega R s`` as ``J qd``), then the legs are
  relabelled; the simplest walker's heel strike is Garcia et al.'s closed-form transition;
- strides are integrated phase by phase by ``scipy.integrate.solve_ivp`` (DOP853, dense
  event location), each guard armed once it has been seen beyond ``GUARD_TOL`` on the side
  it fires from (the integrator's documented rule, walker/_core/hybrid.h).

Each model is an object with ``n_x``, ``directions`` (n_phases, n_guards), ``rhs(phase, x,
p)``, ``jac(phase, x, p)``, ``guards(phase, x, p)``, ``reset(phase, k, x, p) -> ((action,
next phase, status), x_new, impulse)``, ``energy(x, p)``, ``points(x, p)``, ``lift(z, p)``
and ``project(x)``; :func:`oracle` returns it by name (built once per process).
"""

from __future__ import annotations

import functools
import math

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

from walker.status import EVENT_CONTINUE, EVENT_IGNORE, EVENT_STRIDE, EVENT_TERMINAL, Status
from walker.symbolic import models as sym
from walker.symbolic.mechanics import Body, derive

FALL_ANGLE = math.radians(70.0)
"""A stance leg 70 degrees from the slope normal has fallen (docs/conventions.md)."""
MIN_STEP = 1e-8
"""A touchdown at most this many leg lengths ahead of the stance foot is a scuff
(walker/models/compass.py, kneed.py docstrings)."""
KNEE_TOL = 1e-6
"""|q3 - q2| [rad] within which a bent-knee foot contact counts as simultaneous with knee
lock (the kneed walker's reset)."""
TOUCH_TOL = 1e-9
"""A foot within this many leg lengths of the slope after knee lock is on it (the
integrator's guard tolerance, walker/models/kneed.py)."""
GUARD_TOL = 1e-10
"""Absolute guard tolerance for arming (walker/_core/hybrid.h)."""

_FELL = {True: int(Status.FELL_FORWARD), False: int(Status.FELL_BACKWARD)}
_SINGULAR = int(Status.LINEAR_SOLVE_FAILED)
_NONPHYSICAL = int(Status.NONPHYSICAL_IMPACT)


def _fn(args, expr, shape=None):
    """``lambdify(args, expr)`` returning float arrays (reshaped to ``shape``)."""
    f = sp.lambdify(args, expr, modules="numpy", cse=True)

    def call(*a):
        out = np.asarray(f(*a), dtype=float)
        if shape is not None:  # a zero matrix lambdifies to a scalar 0
            out = out.reshape(shape) if out.size == math.prod(shape) else np.full(shape, out)
        return out

    return call


def slope_frame(slope):
    """``(s, n)``: down the slope and its outward normal (docs/conventions.md)."""
    return (
        np.array([math.cos(slope), -math.sin(slope)]),
        np.array([math.sin(slope), math.cos(slope)]),
    )


def solve_impact(M, J, qd_minus):
    """``[M, -J^T; J, 0] [qd+; Lambda] = [M qd-; 0]``: returns ``(qd+, Lambda)``, or None for
    a singular or non-finite system."""
    n, m = M.shape[0], J.shape[0]
    A = np.zeros((n + m, n + m))
    A[:n, :n] = M
    A[:n, n:] = -J.T
    A[n:, :n] = J
    b = np.concatenate([M @ qd_minus, np.zeros(m)])
    if not (np.isfinite(A).all() and np.isfinite(b).all()):
        return None
    try:
        sol = np.linalg.solve(A, b)
    except np.linalg.LinAlgError:
        return None
    if not np.isfinite(sol).all() or np.linalg.cond(A) > 1e14:
        return None
    return sol[:n], sol[n:]


class Lagrangian:
    """Numeric functions of one symbolic :class:`walker.symbolic.mechanics.LagrangianModel`."""

    def __init__(self, model):
        q, qd, p = list(model.q), list(model.qd), list(model.params)
        n = model.n
        hf = model.forced_bias
        self.n = n
        self.mass = _fn([q, p], model.D, (n, n))
        self.bias = _fn([q, qd, p], hf, (n,))
        self.dmass = [_fn([q, p], model.D.diff(v), (n, n)) for v in q]
        self.dbias_dq = _fn([q, qd, p], hf.jacobian(q), (n, n))
        self.dbias_dqd = _fn([q, qd, p], hf.jacobian(qd), (n, n))
        self.kinetic = _fn([q, qd, p], model.K, ())
        self.potential = _fn([q, p], model.P, ())
        self.point = {k: _fn([q, p], v, (2,)) for k, v in model.points.items()}
        self.point_jac = {k: _fn([q, p], model.point_jacobian(k), (2, n)) for k in model.points}

    def accel(self, q, qd, p):
        return np.linalg.solve(self.mass(q, p), -self.bias(q, qd, p))

    def accel_jac(self, q, qd, p):
        """``d qdd / d(q, qd)``, shape (n, 2n)."""
        D = self.mass(q, p)
        qdd = np.linalg.solve(D, -self.bias(q, qd, p))
        dq = np.column_stack([dD @ qdd for dD in (f(q, p) for f in self.dmass)])
        dq = dq + self.dbias_dq(q, qd, p)
        return -np.linalg.solve(D, np.hstack([dq, self.dbias_dqd(q, qd, p)]))


def _falls(psi):
    """The fall guards of a stance leg ``psi`` from the slope normal."""
    return [psi + FALL_ANGLE, psi - FALL_ANGLE]


def _fell(phase, k, n_guards_before):
    """The reset of fall guard ``k`` (forward first)."""
    return (EVENT_TERMINAL, phase, _FELL[k == n_guards_before]), None, None


# ----------------------------------------------------------------------------- simplest
class Simplest:
    """Garcia's simplest walker: ``x = (theta, phi, theta_dot, phi_dot)``,
    ``p = (slope, g, leg_length, damping_ankle)``."""

    n_x = 4
    n_impulse = 1
    directions = np.array([[1, -1, 1]])

    def __init__(self):
        d = sym.simplest()
        q, qd, p = list(d["q"]), list(d["qd"]), list(d["params"])
        qdd = d["qdd"]
        self._qdd = _fn([q, qd, p], qdd, (2,))
        self._qdd_jac = _fn([q, qd, p], qdd.jacobian(q + qd), (2, 4))
        finite = d["model"]
        zero = {d["beta"]: 0}
        self._kinetic = _fn([q, qd, p], finite.K.subs(zero), ())
        self._potential = _fn([q, p], finite.P.subs(zero), ())
        self._points = [
            _fn([q, p], finite.points[k].subs(zero), (2,)) for k in ("hip", "swing_foot")
        ]

    def rhs(self, phase, x, p):
        return np.concatenate([x[2:], self._qdd(x[:2], x[2:], p)])

    def jac(self, phase, x, p):
        J = np.zeros((4, 4))
        J[0, 2] = J[1, 3] = 1.0
        J[2:] = self._qdd_jac(x[:2], x[2:], p)
        return J

    def guards(self, phase, x, p):
        theta, phi = x[0], x[1]
        return np.array([phi - 2.0 * theta, *_falls(theta)])

    def reset(self, phase, k, x, p):
        if k == 0:
            theta, theta_dot = x[0], x[2]
            if theta >= 0.0:  # the mid-stance scuff
                return (EVENT_IGNORE, phase, 0), None, None
            c = math.cos(2.0 * theta)  # Garcia et al. 1998, eq. (4)
            x_new = np.array([-theta, -2.0 * theta, c * theta_dot, c * (1.0 - c) * theta_dot])
            return (EVENT_STRIDE, 0, 0), x_new, np.zeros(1)
        return _fell(phase, k, 1)

    def energy(self, x, p):
        return np.array([self._kinetic(x[:2], x[2:], p), self._potential(x[:2], p)])

    def points(self, x, p):
        return np.array([[0.0, 0.0], *(f(x[:2], p) for f in self._points)])

    def lift(self, z, p):
        theta, theta_dot = z
        return np.array([theta, 2 * theta, theta_dot, (1 - math.cos(2 * theta)) * theta_dot])

    def project(self, x):
        return np.array([x[0], x[2]])


# ---------------------------------------------------------------- compass and kneed walkers
class _Walker:
    """What the compass gait and the kneed walker share: the floating-base heel strike
    (``self.ext``: coordinates ``(q_stance, q_swing, x_hip, y_hip)``, ``self.locked``: the
    pinned two-leg model whose ``hip`` point and Jacobian give the hip's state)."""

    def _p(self, p, name):
        return p[self.names.index(name)]

    def heel_strike(self, q, qd, p):
        """Plastic heel strike of the two straight legs at ``(q, qd)`` (2,): returns
        ``(status, qd+ of the legs, impulse on the new stance foot (along s, along n))``."""
        radius, slope = self._p(p, "foot_radius"), self._p(p, "slope")
        s, n = slope_frame(slope)
        hip = self.locked.point["hip"](q, p)
        hip_rate = self.locked.point_jac["hip"](q, p) @ qd
        qf = np.concatenate([q, hip])
        qdf = np.concatenate([qd, hip_rate])
        M = self.ext.mass(qf, p)

        def contact_jac(centre, angle):  # material velocity of the foot at its contact
            J = self.ext.point_jac[centre](qf, p).copy()
            J[:, angle] += radius * s
            return J

        solved = solve_impact(M, contact_jac("swing_center", 1), qdf)
        if solved is None:
            return _SINGULAR, None, None
        qdf_plus, impulse = solved
        impulse = np.array([impulse @ s, impulse @ n])
        lift = n @ (contact_jac("stance_center", 0) @ qdf_plus)
        status = 0 if impulse[1] > 0.0 and lift > 0.0 else _NONPHYSICAL
        return status, qdf_plus[:2], impulse

    def _foot(self, x, p):
        """(height above the slope, distance ahead of the stance contact) of the swing foot's
        lowest point."""
        s, n = slope_frame(self._p(p, "slope"))
        pts = self.pinned.point
        q = x[: self.pinned.n]
        swing = pts["swing_contact"](q, p)
        return n @ swing, s @ (swing - pts["stance_contact"](q, p))

    def energy(self, x, p):
        m, k = self.pinned, self.pinned.n
        return np.array([m.kinetic(x[:k], x[k : 2 * k], p), m.potential(x[:k], p)])

    def points(self, x, p):
        q = x[: self.pinned.n]
        return np.array([self.pinned.point[k](q, p) for k in self.POINTS])


class Compass(_Walker):
    """The compass gait: ``x = (q_stance, q_swing, qd_stance, qd_swing)``."""

    n_x = 4
    n_impulse = 2
    directions = np.array([[-1, -1, 1]])
    POINTS = ("stance_contact", "hip", "swing_contact")

    def __init__(self):
        self.names = sym.MODEL_PARAMS["compass"]
        self.pinned = self.locked = Lagrangian(sym.compass())
        self.ext = Lagrangian(sym.compass_extended())

    def leg_length(self, p):
        return self._p(p, "com_from_foot") + self._p(p, "com_to_hip")

    def rhs(self, phase, x, p):
        return np.concatenate([x[2:], self.pinned.accel(x[:2], x[2:], p)])

    def jac(self, phase, x, p):
        J = np.zeros((4, 4))
        J[0, 2] = J[1, 3] = 1.0
        J[2:] = self.pinned.accel_jac(x[:2], x[2:], p)
        return J

    def guards(self, phase, x, p):
        return np.array([self._foot(x, p)[0], *_falls(x[0] + self._p(p, "slope"))])

    def reset(self, phase, k, x, p):
        if k > 0:
            return _fell(phase, k, 1)
        if self._foot(x, p)[1] <= MIN_STEP * self.leg_length(p):
            return (EVENT_IGNORE, phase, 0), None, None
        status, qd_plus, impulse = self.heel_strike(x[:2], x[2:], p)
        if status:
            return (EVENT_TERMINAL, phase, status), None, None
        # the legs swap: the swing leg is the new stance leg
        return (EVENT_STRIDE, 0, 0), np.array([x[1], x[0], qd_plus[1], qd_plus[0]]), impulse

    def lift(self, z, p):
        return np.array([z[0], -2.0 * self._p(p, "slope") - z[0], z[1], z[2]])

    def project(self, x):
        return x[[0, 2, 3]]


class Kneed(_Walker):
    """The kneed walker: ``x = (q1, q2, q3, qd1, qd2, qd3)``, phases unlocked (0) and locked
    (1); ``ignore_scuff`` selects the ``swing_scuff = "ignore"`` convention."""

    n_x = 6
    n_impulse = 2
    directions = np.array([[1, -1, -1, 1], [0, -1, -1, 1]])
    POINTS = ("stance_contact", "hip", "knee", "swing_contact")

    def __init__(self, ignore_scuff=False):
        self.names = sym.MODEL_PARAMS["kneed"]
        self.ignore_scuff = ignore_scuff
        self.pinned = Lagrangian(sym.kneed_unlocked())
        self.locked = Lagrangian(sym.kneed_locked())
        self.ext = Lagrangian(sym.kneed_extended())

    def leg_length(self, p):
        return sum(
            self._p(p, k)
            for k in (
                "shank_com_from_foot",
                "shank_com_to_knee",
                "thigh_com_from_knee",
                "thigh_com_to_hip",
            )
        )

    def rhs(self, phase, x, p):
        if phase == 0:
            return np.concatenate([x[3:], self.pinned.accel(x[:3], x[3:], p)])
        a = self.locked.accel(x[:2], x[3:5], p)  # q3 = q2, qd3 = qd2 kept exactly
        return np.array([x[3], x[4], x[4], a[0], a[1], a[1]])

    def jac(self, phase, x, p):
        J = np.zeros((6, 6))
        if phase == 0:
            J[0, 3] = J[1, 4] = J[2, 5] = 1.0
            J[3:] = self.pinned.accel_jac(x[:3], x[3:], p)
            return J
        a = self.locked.accel_jac(x[:2], x[3:5], p)  # columns q1, q2, qd1, qd2
        J[0, 3] = J[1, 4] = J[2, 4] = 1.0
        J[3:5][:, [0, 1, 3, 4]] = a
        J[5] = J[4]
        return J

    def guards(self, phase, x, p):
        knee = x[2] - x[1] if phase == 0 else 1.0
        return np.array([knee, self._foot(x, p)[0], *_falls(x[0] + self._p(p, "slope"))])

    def _foot_rate(self, x, p):
        """d(height of the swing foot's lowest point)/dt."""
        _, n = slope_frame(self._p(p, "slope"))
        return n @ (self.pinned.point_jac["swing_contact"](x[:3], p) @ x[3:])

    def _strike(self, phase, x, p):
        status, qd_plus, impulse = self.heel_strike(x[:2], x[3:5], p)
        if status:
            return (EVENT_TERMINAL, phase, status), None, None
        # legs swap; the new swing knee straight (its shank takes the thigh's angle and rate)
        x_new = np.array([x[1], x[0], x[0], qd_plus[1], qd_plus[0], qd_plus[0]])
        return (EVENT_STRIDE, 0, 0), x_new, impulse

    def _knee_lock(self, phase, x, p):
        """Plastic knee lock, then heel strike in the same reset when the swing foot is on
        the ground, ahead and moving down."""
        solved = solve_impact(self.pinned.mass(x[:3], p), np.array([[0.0, -1.0, 1.0]]), x[3:])
        if solved is None:
            return (EVENT_TERMINAL, phase, _SINGULAR), None, None
        qd_plus, impulse = solved
        x_new = np.array([x[0], x[1], x[1], qd_plus[0], qd_plus[1], qd_plus[1]])
        L = self.leg_length(p)
        height, ahead = self._foot(x_new, p)
        touching = height <= TOUCH_TOL * L and (not self.ignore_scuff or height >= -TOUCH_TOL * L)
        if touching and ahead > MIN_STEP * L and self._foot_rate(x_new, p) < 0.0:
            return self._strike(1, x_new, p)
        return (EVENT_CONTINUE, 1, 0), x_new, np.array([impulse[0], 0.0])

    def reset(self, phase, k, x, p):
        if k >= 2:
            return _fell(phase, k, 2)
        if k == 0:
            return self._knee_lock(phase, x, p)
        ahead = self._foot(x, p)[1]
        min_step = MIN_STEP * self.leg_length(p)
        if phase == 0:
            if abs(x[2] - x[1]) <= KNEE_TOL and ahead > min_step:
                return self._knee_lock(phase, x, p)
            if self.ignore_scuff:
                return (EVENT_IGNORE, phase, 0), None, None
            return (EVENT_TERMINAL, phase, int(Status.TRIPPED)), None, None
        if ahead <= min_step:
            return (EVENT_IGNORE, phase, 0), None, None
        return self._strike(phase, x, p)

    def lift(self, z, p):
        q2 = -2.0 * self._p(p, "slope") - z[0]
        return np.array([z[0], q2, q2, z[1], z[2], z[2]])

    def project(self, x):
        return x[[0, 3, 4]]


# ------------------------------------------------------------------------ rimless wheel
class RimlessWheel:
    """The rimless wheel: ``x = (theta, theta_dot)``, ``p = (spokes, leg_length, g,
    slope)``, energies and impulses per unit hub mass; phases rolling (0) and standing (1).

    The stance dynamics are derived here (a point-mass hub on a massless spoke, with
    :func:`walker.symbolic.mechanics.derive`; walker has no symbolic model of the wheel), the
    impact on the floating hub (the new spoke's length held: ``J`` its unit vector)."""

    n_x = 2
    n_impulse = 2
    directions = np.array([[-1, 1, -1, 1], [-1, 1, -1, 1]])

    def __init__(self):
        spokes, l, g, slope = sp.symbols("spokes leg_length g slope", real=True)
        theta, theta_dot = sp.symbols("theta theta_dot", real=True)
        s = sp.Matrix([sp.cos(slope), -sp.sin(slope)])
        n = sp.Matrix([sp.sin(slope), sp.cos(slope)])
        hub = l * (-sp.sin(theta) * s + sp.cos(theta) * n)
        m = derive(
            "rimless_wheel",
            (theta,),
            (theta_dot,),
            [Body("hub", sp.S.One, hub)],
            g,
            (spokes, l, g, slope),
            points={"hub": hub},
        )
        self.wheel = Lagrangian(m)

    @staticmethod
    def alpha(p):
        return math.pi / p[0]

    def rhs(self, phase, x, p):
        if phase == 1:
            return np.zeros(2)
        return np.array([x[1], self.wheel.accel(x[:1], x[1:], p)[0]])

    def jac(self, phase, x, p):
        J = np.zeros((2, 2))
        if phase == 0:
            J[0, 1] = 1.0
            J[1] = self.wheel.accel_jac(x[:1], x[1:], p)[0]
        return J

    def guards(self, phase, x, p):
        if phase == 1:
            return np.ones(4)
        a, late = self.alpha(p), 2.0 * GUARD_TOL
        return np.array([x[0] + a, x[0] - a, x[0] + a + late, x[0] - a - late])

    def _hub_velocity(self, theta, theta_dot, p):
        return self.wheel.point_jac["hub"](np.array([theta]), p)[:, 0] * theta_dot

    def _strike(self, theta, theta_dot, new_theta, p):
        """Plastic impact of the spoke at ``new_theta`` (its foot at the hub minus ``l
        u(new_theta)``) on the hub moving about the old foot: ``(rate after about the new
        foot, hub velocity change in the slope frame)``."""
        s, n = slope_frame(p[3])
        l = p[1]
        v_minus = self._hub_velocity(theta, theta_dot, p)
        u_new = -math.sin(new_theta) * s + math.cos(new_theta) * n  # new foot -> hub
        v_plus, _ = solve_impact(np.eye(2), u_new[None, :], v_minus)
        rate = (v_plus @ (-math.cos(new_theta) * s - math.sin(new_theta) * n)) / l
        dv = v_plus - v_minus
        return rate, np.array([dv @ s, dv @ n])

    def _stop(self, x, p):
        """The impulse ``v+ - v- = -v-`` that stops the hub."""
        return -np.array([self._hub_velocity(x[0], x[1], p) @ v for v in slope_frame(p[3])])

    def _at_rest(self, p):
        return np.array([self.alpha(p), 0.0])

    def reset(self, phase, k, x, p):
        a, slope, g_l = self.alpha(p), p[3], p[2] / p[1]
        if phase == 1:
            return (EVENT_IGNORE, phase, 0), None, None
        if k in (0, 2):  # the leading spoke strikes: it becomes the stance spoke
            rate, impulse = self._strike(x[0], x[1], x[0] + 2 * a, p)
            if p[0] > 4:  # cos(2 alpha) > 0: 5 spokes or more
                return (EVENT_STRIDE, 0, 0), np.array([a, rate]), impulse
            # 3 or 4 spokes: the old foot cannot leave the ground; the wheel stops
            impulse = self._stop(x, p)
            if slope <= -a:
                return (EVENT_TERMINAL, phase, _FELL[False]), None, None
            return (EVENT_STRIDE, 0 if slope >= a else 1, 0), self._at_rest(p), impulse
        # the trailing spoke strikes: the wheel rolled back
        if p[0] <= 4:  # 3 or 4 spokes: it stops on both feet, then falls, stands or tips on
            if slope <= -a:
                return (EVENT_TERMINAL, phase, _FELL[False]), None, None
            return (EVENT_CONTINUE, int(slope < a), 0), self._at_rest(p), self._stop(x, p)
        w, impulse = self._strike(x[0], x[1], x[0] - 2 * a, p)
        if w * w >= 2 * g_l * (1 - math.cos(a + slope)) or slope <= -a:
            return (EVENT_TERMINAL, phase, _FELL[False]), None, None
        over = math.cos(2 * a) ** 2 * w * w >= 2 * g_l * (1 - math.cos(a - slope))
        if not over and slope < a:  # it rocks to rest (not integrated): v+ = 0
            return (EVENT_CONTINUE, 1, 0), self._at_rest(p), self._stop(x, p)
        return (EVENT_CONTINUE, 0, 0), np.array([-a, w]), impulse

    def energy(self, x, p):
        return np.array([self.wheel.kinetic(x[:1], x[1:], p), self.wheel.potential(x[:1], p)])

    def points(self, x, p):
        """Stance foot, hub, leading foot, trailing foot."""
        s, n = slope_frame(p[3])
        hub = self.wheel.point["hub"](x[:1], p)
        a = self.alpha(p)
        feet = [
            hub - p[1] * (-math.sin(x[0] + d) * s + math.cos(x[0] + d) * n) for d in (2 * a, -2 * a)
        ]
        return np.array([[0.0, 0.0], hub, *feet])

    def start_phase(self, x, p):
        a = self.alpha(p)
        return int(x[1] == 0.0 and abs(x[0]) == a and abs(p[3]) < a)

    def lift(self, z, p):
        return np.array([self.alpha(p), z[0]])

    def project(self, x):
        return x[1:]


@functools.cache
def oracle(name):
    """The oracle of model ``name`` ("simplest", "compass", "kneed", "kneed/ignore_scuff")."""
    if name == "simplest":
        return Simplest()
    if name == "compass":
        return Compass()
    if name in ("three_link", "five_link"):
        import oracle_actuated

        from walker.params import MODELS

        cls = oracle_actuated.ThreeLink if name == "three_link" else oracle_actuated.FiveLink
        return cls(MODELS[name].params_class.names())
    if name == "rimless_wheel":
        return RimlessWheel()
    if name in ("double_pendulum", "compass_coulomb", "kneed_coulomb"):
        import oracle_friction

        return {
            "double_pendulum": oracle_friction.DoublePendulum,
            "compass_coulomb": oracle_friction.CompassCoulomb,
            "kneed_coulomb": oracle_friction.KneedCoulomb,
        }[name]()
    if name in ("kneed", "kneed/ignore_scuff"):
        return Kneed(ignore_scuff=name.endswith("ignore_scuff"))
    raise ValueError(f"`name` must be a model the oracle knows, got {name!r}")


# ----------------------------------------------------------------------------- strides
class Run:
    """One oracle run: ``status``, final ``t``, ``x``, ``phase`` and the ``events``
        ``(t, guard, phase_after, x_post, impulse)`` of the real (not ignored) events (a terminal
    event's ``x_post`` and ``impulse`` None)."""

    def __init__(self, status, t, x, phase, events):
        self.status, self.t, self.x, self.phase, self.events = status, t, x, phase, events


def _armed(model, phase, x, p):
    """Guards beyond ``GUARD_TOL`` on the side they fire from."""
    g = model.guards(phase, x, p)
    d = model.directions[phase]
    return [
        (dk < 0 and gk > GUARD_TOL) or (dk > 0 and gk < -GUARD_TOL)
        for gk, dk in zip(g, d, strict=True)
    ]


def run(model, x0, p, *, phase=0, n_strides=1, t_max=20.0, rtol=1e-12, atol=1e-12):
    """Integrate ``model`` from ``x0`` until ``n_strides`` strides, a terminal event or
    ``t_max`` (status ``NO_EVENT``; ``n_strides = 0``: integrate to ``t_max``, status 0)."""
    t, x = 0.0, np.array(x0, dtype=float)
    armed = _armed(model, phase, x, p)
    strides = 0
    events = []
    while True:
        d = model.directions[phase]
        fns, which = [], []
        for k, dk in enumerate(d):
            if dk == 0:
                continue
            shift = 0.0 if armed[k] else dk * GUARD_TOL  # arm: cross -dk*TOL away from zero

            def ev(_t, y, k=k, shift=shift, ph=phase):
                return model.guards(ph, y, p)[k] + shift

            ev.terminal = True
            ev.direction = dk if armed[k] else -dk
            fns.append(ev)
            which.append(k)
        sol = solve_ivp(
            lambda _t, y, ph=phase: model.rhs(ph, y, p),
            (t, t_max),
            x,
            method="DOP853",
            rtol=rtol,
            atol=atol,
            events=fns,
        )
        t, x = float(sol.t[-1]), sol.y[:, -1].copy()
        if sol.status != 1:  # t_max: the end of a run without strides, else NO_EVENT
            status = (0 if n_strides == 0 else int(Status.NO_EVENT)) if sol.status == 0 else -1
            return Run(status, t, x, phase, events)
        hits = [(te[0], k) for te, k in zip(sol.t_events, which, strict=True) if len(te)]
        _, k = min(hits)
        if not armed[k]:
            armed[k] = True
            continue
        (action, next_phase, status), x_new, impulse = model.reset(phase, k, x, p)
        if action == EVENT_IGNORE:
            armed[k] = False
            continue
        if action == EVENT_TERMINAL:
            events.append((t, k, phase, None, None))
            return Run(status, t, x, phase, events)
        events.append((t, k, next_phase, x_new, impulse))
        phase, x = next_phase, x_new
        armed = _armed(model, phase, x, p)
        if action == EVENT_STRIDE:
            strides += 1
            if strides == n_strides:
                return Run(0, t, x, phase, events)


def stride(model, z, p, **kw):
    """The stride map on the section: ``(z_next, step_time, run)``; the run starts in the
    phase consistent with the lifted state (``start_phase``) when the model has one."""
    x0 = model.lift(np.asarray(z, dtype=float), p)
    if hasattr(model, "start_phase"):
        kw = {"phase": model.start_phase(x0, p), **kw}
    r = run(model, x0, p, **kw)
    return model.project(r.x), r.t, r


def stride_jacobian(model, z, p, step=3e-5, **kw):
    """Fourth-order central differences of :func:`stride` (the stencil ``(f(-2h) - 8 f(-h)
    + 8 f(h) - f(2h)) / 12 h``), step ``h = step max(1, |z_j|)``: truncation O(h^4), the
    integration error over the step about ``rtol / h``."""
    z = np.asarray(z, dtype=float)
    cols = []
    for j in range(len(z)):
        h = step * max(1.0, abs(z[j]))
        f = {}
        for k in (-2, -1, 1, 2):
            zk = z.copy()
            zk[j] += k * h
            f[k] = stride(model, zk, p, **kw)[0]
        cols.append((f[-2] - 8.0 * f[-1] + 8.0 * f[1] - f[2]) / (12.0 * h))
    return np.column_stack(cols)
