"""The numpy oracle of Grizzle's three-link walker in closed loop (``three_link``), over the
lambdified symbolic model of :mod:`walker.symbolic.actuated` and the friction layer of
``tests/oracle_friction.py``.

Written from the documentation: the controller from :mod:`walker.control`'s docstring
(phase variable ``s = (theta - theta_plus) / (theta_minus - theta_plus)``, Bezier outputs
``y = q[1:] - b(s)``; mode 1 ``B[1:] u = -kp y - kd yd``, mode 2 computed torque
``u = (H D^-1 B)^-1 (v + H D^-1 h - c)``, each component clipped to the torque limit), the
model from :mod:`walker.models.three_link`'s docstring (hip joints ``S = B^T`` with viscous
``damping_hip`` and dry ``coulomb_hip``; accumulators ``u . S qd`` and the saturated time;
guards heel strike (or ``q_stance - theta_minus`` with ``step_event = 1``), falls, the
ground reaction's friction cone and lift-off, the joints' friction guards; heel strike on
the floating base with the friction-cone test, legs swapped, the torso kept).  The Bezier
polynomials are evaluated in the power basis (``numpy.polynomial``), the ground reaction is
the rate of the total momentum plus the weight, and the Jacobian of the vector field is
taken by central differences of this oracle's own vector field (the C's is too, with the
same relative step ``1e-6``).  The finite-time controller (``controller = 3``, compiled C
only) is not in the oracle.
"""

from __future__ import annotations

import math

import numpy as np
import oracle as O
import oracle_friction as OF
import sympy as sp
from numpy.polynomial import polynomial as P

from walker.status import EVENT_IGNORE, EVENT_STRIDE, EVENT_TERMINAL, Status
from walker.symbolic import actuated as sym_actuated

JAC_STEP = 1e-6
B_MATRIX = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0]])
_NAMES = (
    "mass_hip mass_leg mass_torso com_from_foot com_to_hip torso_length inertia_leg "
    "inertia_torso slope g friction controller kp kd torque_limit theta_plus theta_minus"
).split()


def bezier_power(a):
    """Power-basis coefficients of ``sum_k a_k C(M, k) s^k (1 - s)^(M - k)``."""
    M = len(a) - 1
    out = np.zeros(M + 1)
    for k, ak in enumerate(a):
        term = P.polymul([0.0] * k + [1.0], P.polypow([1.0, -1.0], M - k))
        out[: len(term)] += ak * math.comb(M, k) * term
    return out


class ThreeLink(OF.FrictionLayer):
    """``x = (q_stance, q_swing, q_torso, qd..., actuator_work, saturated_time)``."""

    n_x = 8
    n_impulse = 2
    n_base_guards = 6

    def __init__(self, names):
        self.names = list(names)
        self.pinned = O.Lagrangian(sym_actuated.three_link())
        ext = sym_actuated.three_link_extended()
        self.ext = O.Lagrangian(ext)
        m = sym_actuated.three_link()
        q, qd = sp.Matrix(m.q), sp.Matrix(m.qd)
        qdd = sp.Matrix(sp.symbols("a0:3", real=True))
        momentum = sp.zeros(2, 1)
        for body in m.bodies:
            momentum += body.mass * body.position.jacobian(q) * qd
        rate = momentum.jacobian(q) * qd + momentum.jacobian(qd) * qdd
        self._momentum_rate = O._fn([list(m.q), list(m.qd), list(qdd), list(m.params)], rate, (2,))
        self._total_mass = sum(b.mass for b in m.bodies)
        self._mass = O._fn([list(m.params)], self._total_mass, ())
        self.directions = np.array(
            [[-1, -1, 1, -1, -1, -1] + OF.friction_directions(c, 2) for c in range(9)]
        )

    def _p(self, p, name):
        return p[self.names.index(name)]

    def _phys(self, p):
        return p[:10]

    def joint_rows(self, base):
        return B_MATRIX.T

    def F(self, p):
        return np.full(2, self._p(p, "coulomb_hip"))

    def with_rates(self, base, x, qd):
        x = x.copy()
        x[3:6] = qd
        return x

    # --- the controller
    def torque(self, q, qd, D, h, p):
        """``(u, saturated)``."""
        mode = self._p(p, "controller")
        limit = self._p(p, "torque_limit")
        if mode == 0.0:
            u = np.zeros(2)
        else:
            theta_plus, theta_minus = self._p(p, "theta_plus"), self._p(p, "theta_minus")
            ds = 1.0 / (theta_minus - theta_plus)
            s = (q[0] - theta_plus) * ds
            i0 = self.names.index("bezier_swing_0")
            y, yd, H, c = np.zeros(2), np.zeros(2), np.zeros((2, 3)), np.zeros(2)
            for i in range(2):
                b = bezier_power(p[i0 + 5 * i : i0 + 5 * i + 5])
                b1, b2 = P.polyder(b), P.polyder(b, 2)
                y[i] = q[1 + i] - P.polyval(s, b)
                yd[i] = qd[1 + i] - P.polyval(s, b1) * ds * qd[0]
                H[i, 0] = -P.polyval(s, b1) * ds
                H[i, 1 + i] = 1.0
                c[i] = -P.polyval(s, b2) * ds**2 * qd[0] ** 2
            v = -self._p(p, "kp") * y - self._p(p, "kd") * yd
            if mode == 1.0:
                u = np.linalg.solve(B_MATRIX[1:], v)
            elif mode == 2.0:
                Dinv_B, Dinv_h = np.linalg.solve(D, B_MATRIX), np.linalg.solve(D, h)
                u = np.linalg.solve(H @ Dinv_B, v + H @ Dinv_h - c)
            else:
                raise ValueError("the oracle has controllers 0, 1 and 2 only")
        saturated = bool((np.abs(u) > limit).any())
        return np.clip(u, -limit, limit), saturated

    def _forces(self, base, x, p):
        q, qd, pp = x[:3], x[3:6], self._phys(p)
        D, h = self.pinned.mass(q, pp), self.pinned.bias(q, qd, pp)
        u, _ = self.torque(q, qd, D, h, p)
        S = B_MATRIX.T
        f = B_MATRIX @ u - h - self._p(p, "damping_hip") * S.T @ (S @ qd)
        return q, qd, self.pinned, D, f, pp

    def closed_loop(self, phase, x, p):
        """``(qdd, u, saturated, lam)``."""
        _, modes = self.split(phase)
        q, qd, _, D, f, pp = self._forces(0, x, p)
        u, sat = self.torque(q, qd, D, self.pinned.bias(q, qd, pp), p)
        qdd, lam = OF.accelerations(D, f, B_MATRIX.T, self.F(p), modes)
        return qdd, u, sat, lam

    def rhs(self, phase, x, p):
        qdd, u, sat, _ = self.closed_loop(phase, x, p)
        power = u @ (B_MATRIX.T @ x[3:6])
        return np.concatenate([x[3:6], qdd, [power, 1.0 if sat else 0.0]])

    def jac(self, phase, x, p):
        J = np.zeros((8, 8))
        for j in range(8):
            h = JAC_STEP * max(1.0, abs(x[j]))
            xp, xm = x.copy(), x.copy()
            xp[j] += h
            xm[j] -= h
            J[:, j] = (self.rhs(phase, xp, p) - self.rhs(phase, xm, p)) / (2 * h)
        return J

    def ground_reaction(self, phase, x, p):
        """``(F_t, F_n)``: the ground's force on the stance foot along and normal to the
        slope [N]."""
        qdd = self.closed_loop(phase, x, p)[0]
        pp = self._phys(p)
        F = self._momentum_rate(x[:3], x[3:6], qdd, pp)
        F[1] += self._mass(pp) * self._p(p, "g")
        s, n = O.slope_frame(self._p(p, "slope"))
        return F @ s, F @ n

    def _foot(self, x, p):
        s, n = O.slope_frame(self._p(p, "slope"))
        swing = self.pinned.point["swing_contact"](x[:3], self._phys(p))
        return n @ swing, s @ swing

    def guards(self, phase, x, p):
        if self._p(p, "step_event") == 1.0:
            step = x[0] - self._p(p, "theta_minus")
        else:
            step = self._foot(x, p)[0]
        ft, fn = self.ground_reaction(phase, x, p)
        mu = self._p(p, "friction")
        base = [step, *O._falls(x[0] + self._p(p, "slope")), mu * fn - ft, mu * fn + ft, fn]
        return np.concatenate([base, self.friction_guards(phase, x, p)])

    def heel_strike(self, x, p):
        """``(status, x_new, impulse)`` of the floating-base heel strike, legs swapped."""
        pp = self._phys(p)
        q, qd = x[:3], x[3:6]
        qf = np.concatenate([q, self.pinned.point["hip"](q, pp)])
        qdf = np.concatenate([qd, self.pinned.point_jac["hip"](q, pp) @ qd])
        solved = O.solve_impact(
            self.ext.mass(qf, pp), self.ext.point_jac["swing_contact"](qf, pp), qdf
        )
        if solved is None:
            return int(Status.LINEAR_SOLVE_FAILED), None, None
        qdf_plus, lam = solved
        s, n = O.slope_frame(self._p(p, "slope"))
        impulse = np.array([lam @ s, lam @ n])
        lift = n @ (self.ext.point_jac["stance_contact"](qf, pp) @ qdf_plus)
        mu = self._p(p, "friction")
        ok = impulse[1] > 0.0 and abs(impulse[0]) <= mu * impulse[1] and lift > 0.0
        x_new = np.concatenate([q[[1, 0, 2]], qdf_plus[[1, 0, 2]], x[6:]])
        return (0 if ok else int(Status.NONPHYSICAL_IMPACT)), x_new, impulse

    def reset(self, phase, k, x, p):
        if k >= self.n_base_guards:
            return self.switch(phase, k - self.n_base_guards, x, p)
        if k in (1, 2):
            return (EVENT_TERMINAL, phase, O._FELL[k == 1]), None, None
        if k > 2:  # the ground reaction leaves the friction cone or pulls
            return (EVENT_TERMINAL, phase, int(Status.NONPHYSICAL_IMPACT)), None, None
        leg = self._p(p, "com_from_foot") + self._p(p, "com_to_hip")
        if self._foot(x, p)[1] <= O.MIN_STEP * leg:
            return (EVENT_IGNORE, phase, 0), None, None
        status, x_new, impulse = self.heel_strike(x, p)
        if status:
            return (EVENT_TERMINAL, phase, status), None, None
        return self.after_base_event(phase, (EVENT_STRIDE, 0, 0), x_new, impulse, p)

    def energy(self, x, p):
        pp = self._phys(p)
        return np.array([self.pinned.kinetic(x[:3], x[3:6], pp), self.pinned.potential(x[:3], pp)])

    def points(self, x, p):
        pp = self._phys(p)
        keys = ("stance_contact", "hip", "swing_contact", "torso")
        return np.array([self.pinned.point[k](x[:3], pp) for k in keys])

    def lift(self, z, p):
        if self._p(p, "step_event") == 1.0:
            q_swing = self._p(p, "theta_minus")
        else:
            q_swing = -2.0 * self._p(p, "slope") - z[0]
        return np.array([z[0], q_swing, z[1], z[2], z[3], z[4], 0.0, 0.0])

    def project(self, x):
        return x[[0, 2, 3, 4, 5]]
