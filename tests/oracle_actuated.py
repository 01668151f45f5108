"""The numpy oracle of the actuated walkers in closed loop: Grizzle's three-link walker
(``three_link``) and the five-link walker (``five_link``), over the lambdified symbolic
models of :mod:`walker.symbolic.actuated` and :mod:`walker.symbolic.five_link` and the
friction layer of ``tests/oracle_friction.py``.

Written from the documentation: the controller from :mod:`walker.models.control`'s docstring
(phase variable ``s = (theta - theta_plus) / (theta_minus - theta_plus)``, Bezier outputs
``y = q[1:] - b(s)``; mode 1 ``B[1:] u = -kp y - kd yd``, mode 2 computed torque
``u = (H D^-1 B)^-1 (v + H D^-1 h - c)``, each component clipped to the torque limit), the
model from :mod:`walker.models.three_link`'s docstring (hip joints ``S = B^T`` with viscous
``damping_hip`` and dry ``coulomb_hip``; accumulators ``u . S qd`` and the saturated time;
guards heel strike (or ``q_stance - theta_minus`` with ``step_event = 1``), falls, the
ground reaction's friction cone and lift-off, the joints' friction guards; heel strike on
the floating base with the friction-cone test, legs swapped, the torso kept) and from
:mod:`walker.models.five_link`'s (the fall angle of the line from the stance foot to the
hip, ``hip_down``, a touchdown behind the stance foot a trip, femurs and tibias trading
places at heel strike, the section's swing tibia putting its foot on the slope behind its
knee).  The Bezier
polynomials are evaluated in the power basis (``numpy.polynomial``), the ground reaction is
the rate of the total momentum plus the weight, and the Jacobian of the vector field is
taken by central differences of this oracle's own vector field (the C's is too, with the
same relative step ``1e-6``).  The finite-time controller (``controller = 3``) is written
from its description in :class:`walker.params.ThreeLinkParams` (``ft_alpha``,
``ft_epsilon``, ``poly_*``).
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
from walker.symbolic import five_link as sym_five_link

JAC_STEP = 1e-6
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


class ActuatedWalker(OF.FrictionLayer):
    """What the actuated walkers share: ``x = (q, qd, actuator_work, saturated_time)``,
    joints ``S = B^T``, the controller, the ground reaction and the force guards.
    Subclasses give ``names``, ``n_q``, ``n_phys`` (the physical parameters' count), the
    symbolic models and ``bezier`` (the first Bezier coefficient's name)."""

    n_impulse = 2

    def __init__(self, names, model, extended):
        self.names = list(names)
        self.pinned = O.Lagrangian(model)
        self.ext = O.Lagrangian(extended)
        self.B = np.array(model.B, dtype=float)
        q, qd = sp.Matrix(model.q), sp.Matrix(model.qd)
        qdd = sp.Matrix(sp.symbols(f"a0:{self.n_q}", real=True))
        momentum = sp.zeros(2, 1)
        for body in model.bodies:
            momentum += body.mass * body.position.jacobian(q) * qd
        rate = momentum.jacobian(q) * qd + momentum.jacobian(qd) * qdd
        args = [list(model.q), list(model.qd), list(qdd), list(model.params)]
        self._momentum_rate = O._fn(args, rate, (2,))
        self._mass = O._fn([list(model.params)], sum(b.mass for b in model.bodies), ())
        m = self.B.shape[1]
        base = [-1] * self.n_base_guards
        base[2] = 1  # fall_backward
        self.directions = np.array([base + OF.friction_directions(c, m) for c in range(3**m)])

    def _p(self, p, name):
        return p[self.names.index(name)]

    def _phys(self, p):
        return p[: self.n_phys]

    def joint_rows(self, base):
        return self.B.T

    def with_rates(self, base, x, qd):
        x = x.copy()
        x[self.n_q : 2 * self.n_q] = qd
        return x

    # --- the controller
    def _outputs(self, q, qd, p):
        """``(y, yd, H = dy/dq, c = ydd - H qdd)`` of the outputs ``y = q[1:] - b(q[0])``:
        Bezier polynomials in the normalized phase (controllers 1, 2), or plain polynomials
        in the stance angle (controller 3, ``poly_*`` coefficients)."""
        k = self.n_q - 1
        if self._p(p, "controller") == 3.0:
            i0, width, scale, theta0 = self.names.index("poly_swing_0"), 6, 1.0, 0.0
            polys = [p[i0 + width * i : i0 + width * (i + 1)] for i in range(k)]
        else:
            theta_plus, theta_minus = self._p(p, "theta_plus"), self._p(p, "theta_minus")
            i0, scale, theta0 = (
                self.names.index(self.bezier),
                1.0 / (theta_minus - theta_plus),
                theta_plus,
            )
            polys = [bezier_power(p[i0 + 5 * i : i0 + 5 * i + 5]) for i in range(k)]
        s = (q[0] - theta0) * scale
        y, yd, H, c = np.zeros(k), np.zeros(k), np.zeros((k, self.n_q)), np.zeros(k)
        for i, b in enumerate(polys):
            b1, b2 = P.polyder(b), P.polyder(b, 2)
            y[i] = q[1 + i] - P.polyval(s, b)
            yd[i] = qd[1 + i] - P.polyval(s, b1) * scale * qd[0]
            H[i, 0] = -P.polyval(s, b1) * scale
            H[i, 1 + i] = 1.0
            c[i] = -P.polyval(s, b2) * scale**2 * qd[0] ** 2
        return y, yd, H, c

    def torque(self, q, qd, D, h, p):
        """``(u, saturated)``."""
        mode = self._p(p, "controller")
        limit = self._p(p, "torque_limit")
        if mode == 0.0:
            u = np.zeros(self.B.shape[1])
        else:
            y, yd, H, c = self._outputs(q, qd, p)
            if mode == 3.0:  # Bhat and Bernstein's finite-time controller
                alpha, eps = self._p(p, "ft_alpha"), self._p(p, "ft_epsilon")

                def sig(v, e):
                    return np.sign(v) * np.abs(v) ** e

                phi = y + sig(eps * yd, 2.0 - alpha) / (2.0 - alpha)
                v = (-sig(eps * yd, alpha) - sig(phi, alpha / (2.0 - alpha))) / eps**2
            else:
                v = -self._p(p, "kp") * y - self._p(p, "kd") * yd
            if mode == 1.0:
                u = np.linalg.solve(self.B[1:], v)
            else:  # input-output linearization
                Dinv_B, Dinv_h = np.linalg.solve(D, self.B), np.linalg.solve(D, h)
                u = np.linalg.solve(H @ Dinv_B, v + H @ Dinv_h - c)
        saturated = bool((np.abs(u) > limit).any())
        return np.clip(u, -limit, limit), saturated

    def _forces(self, base, x, p):
        n = self.n_q
        q, qd, pp = x[:n], x[n : 2 * n], self._phys(p)
        D, h = self.pinned.mass(q, pp), self.pinned.bias(q, qd, pp)
        u, _ = self.torque(q, qd, D, h, p)
        S = self.B.T
        f = self.B @ u - h - S.T @ (self.damping(p) * (S @ qd))
        return q, qd, self.pinned, D, f, pp

    def closed_loop(self, phase, x, p):
        """``(qdd, u, saturated, lam)``."""
        _, modes = self.split(phase)
        q, qd, _, D, f, pp = self._forces(0, x, p)
        u, sat = self.torque(q, qd, D, self.pinned.bias(q, qd, pp), p)
        qdd, lam = OF.accelerations(D, f, self.B.T, self.F(p), modes)
        return qdd, u, sat, lam

    def rhs(self, phase, x, p):
        n = self.n_q
        qdd, u, sat, _ = self.closed_loop(phase, x, p)
        power = u @ (self.B.T @ x[n : 2 * n])
        return np.concatenate([x[n : 2 * n], qdd, [power, 1.0 if sat else 0.0]])

    def jac(self, phase, x, p):
        J = np.zeros((self.n_x, self.n_x))
        for j in range(self.n_x):
            h = JAC_STEP * max(1.0, abs(x[j]))
            xp, xm = x.copy(), x.copy()
            xp[j] += h
            xm[j] -= h
            J[:, j] = (self.rhs(phase, xp, p) - self.rhs(phase, xm, p)) / (2 * h)
        return J

    def ground_reaction(self, phase, x, p):
        """``(F_t, F_n)``: the ground's force on the stance foot along and normal to the
        slope [N]."""
        n = self.n_q
        qdd = self.closed_loop(phase, x, p)[0]
        pp = self._phys(p)
        F = self._momentum_rate(x[:n], x[n : 2 * n], qdd, pp)
        F[1] += self._mass(pp) * self._p(p, "g")
        s, n = O.slope_frame(self._p(p, "slope"))
        return F @ s, F @ n

    def _foot(self, x, p):
        """(height above the slope, distance ahead of the stance foot) of the swing foot."""
        s, n = O.slope_frame(self._p(p, "slope"))
        swing = self.pinned.point["swing_contact"](x[: self.n_q], self._phys(p))
        return n @ swing, s @ swing

    def guards(self, phase, x, p):
        ft, fn = self.ground_reaction(phase, x, p)
        mu = self._p(p, "friction")
        base = [*self.base_guards(x, p)[:3], mu * fn - ft, mu * fn + ft, fn]
        base += self.base_guards(x, p)[3:]
        return np.concatenate([base, self.friction_guards(phase, x, p)])

    def heel_strike(self, x, p):
        """``(status, x_new, impulse)`` of the floating-base heel strike, legs swapped."""
        n, pp = self.n_q, self._phys(p)
        q, qd = x[:n], x[n : 2 * n]
        qf = np.concatenate([q, self.pinned.point["hip"](q, pp)])
        qdf = np.concatenate([qd, self.pinned.point_jac["hip"](q, pp) @ qd])
        solved = O.solve_impact(
            self.ext.mass(qf, pp), self.ext.point_jac["swing_contact"](qf, pp), qdf
        )
        if solved is None:
            return int(Status.LINEAR_SOLVE_FAILED), None, None
        qdf_plus, lam = solved
        s, nn = O.slope_frame(self._p(p, "slope"))
        impulse = np.array([lam @ s, lam @ nn])
        lift = nn @ (self.ext.point_jac["stance_contact"](qf, pp) @ qdf_plus)
        mu = self._p(p, "friction")
        ok = impulse[1] > 0.0 and abs(impulse[0]) <= mu * impulse[1] and lift > 0.0
        x_new = np.concatenate([self.swap(q), self.swap(qdf_plus[:n]), x[2 * n :]])
        return (0 if ok else int(Status.NONPHYSICAL_IMPACT)), x_new, impulse

    def reset(self, phase, k, x, p):
        if k >= self.n_base_guards:
            return self.switch(phase, k - self.n_base_guards, x, p)
        if k == 1:
            return (EVENT_TERMINAL, phase, int(Status.FELL_FORWARD)), None, None
        if k == 2 or k == 6:  # fall backward, the five-link walker's hip down
            return (EVENT_TERMINAL, phase, int(Status.FELL_BACKWARD)), None, None
        if k > 2:  # the ground reaction leaves the friction cone or pulls
            return (EVENT_TERMINAL, phase, int(Status.NONPHYSICAL_IMPACT)), None, None
        if self._foot(x, p)[1] <= O.MIN_STEP * self.leg_length(p):
            return self.touchdown_behind(phase)
        status, x_new, impulse = self.heel_strike(x, p)
        if status:
            return (EVENT_TERMINAL, phase, status), None, None
        return self.after_base_event(phase, (EVENT_STRIDE, 0, 0), x_new, impulse, p)

    def energy(self, x, p):
        n, pp = self.n_q, self._phys(p)
        return np.array(
            [self.pinned.kinetic(x[:n], x[n : 2 * n], pp), self.pinned.potential(x[:n], pp)]
        )

    def points(self, x, p):
        pp = self._phys(p)
        return np.array([self.pinned.point[k](x[: self.n_q], pp) for k in self.pinned.point])


class ThreeLink(ActuatedWalker):
    """``x = (q_stance, q_swing, q_torso, qd..., actuator_work, saturated_time)``."""

    n_x, n_q, n_phys, n_base_guards = 8, 3, 11, 6
    bezier = "bezier_swing_0"

    def __init__(self, names):
        super().__init__(names, sym_actuated.three_link(), sym_actuated.three_link_extended())

    def F(self, p):
        return np.full(2, self._p(p, "coulomb_hip"))

    def damping(self, p):
        return np.full(2, self._p(p, "damping_hip"))

    def leg_length(self, p):
        return self._p(p, "com_from_foot") + self._p(p, "com_to_hip")

    def base_guards(self, x, p):
        """heel strike (or the stance angle through ``theta_minus``) and the falls."""
        if self._p(p, "step_event") == 1.0:
            step = x[0] - self._p(p, "theta_minus")
        else:
            step = self._foot(x, p)[0]
        return [step, *O._falls(x[0] + self._p(p, "slope"))]

    def touchdown_behind(self, phase):
        return (EVENT_IGNORE, phase, 0), None, None

    @staticmethod
    def swap(q):
        return q[[1, 0, 2]]  # the legs swap, the torso keeps its angle

    def lift(self, z, p):
        if self._p(p, "step_event") == 1.0:
            q_swing = self._p(p, "theta_minus")
        else:
            q_swing = -2.0 * self._p(p, "slope") - z[0]
        return np.array([z[0], q_swing, z[1], z[2], z[3], z[4], 0.0, 0.0])

    def project(self, x):
        return x[[0, 2, 3, 4, 5]]


class FiveLink(ActuatedWalker):
    """``x = (q_leg, q_knee, q_torso, q_femur_sw, q_tibia_sw, qd..., actuator_work,
    saturated_time)``; joints hip stance, hip swing, knee stance, knee swing."""

    n_x, n_q, n_phys, n_base_guards = 12, 5, 14, 7
    bezier = "bezier_knee_0"

    def __init__(self, names):
        super().__init__(names, sym_five_link.five_link(), sym_five_link.five_link_extended())

    def F(self, p):
        return np.repeat([self._p(p, "coulomb_hip"), self._p(p, "coulomb_knee")], 2)

    def damping(self, p):
        return np.repeat([self._p(p, "damping_hip"), self._p(p, "damping_knee")], 2)

    def leg_length(self, p):
        return self._p(p, "length_femur") + self._p(p, "length_tibia")

    def base_guards(self, x, p):
        """heel strike, the falls of the line from the stance foot to the hip, hip down."""
        s, n = O.slope_frame(self._p(p, "slope"))
        hip = self.pinned.point["hip"](x[:5], self._phys(p))
        psi = math.atan2(-(hip @ s), hip @ n)  # from the slope normal, as a leg angle
        return [self._foot(x, p)[0], *O._falls(psi), hip @ n]

    def touchdown_behind(self, phase):
        return (EVENT_TERMINAL, phase, int(Status.TRIPPED)), None, None

    @staticmethod
    def swap(q):
        """Femurs and tibias trade places: the new stance leg is the old swing leg."""
        leg, knee, torso, femur_sw, tibia_sw = q
        tibia_st, femur_st = leg - knee / 2, leg + knee / 2
        return np.array([(tibia_sw + femur_sw) / 2, femur_sw - tibia_sw, torso, femur_st, tibia_st])

    def lift(self, z, p):
        """The swing tibia at the angle that puts its foot on the slope behind its knee."""
        pp = self._phys(p)
        slope = self._p(p, "slope")
        _, n = O.slope_frame(slope)
        q = np.array([*z[:4], 0.0])
        knee_height = n @ self.pinned.point["swing_knee"](q, pp)
        psi = -math.acos(knee_height / self._p(p, "length_tibia"))  # foot behind the knee
        return np.array([*z[:4], psi - slope, *z[4:9], 0.0, 0.0])

    def project(self, x):
        return x[[0, 1, 2, 3, 5, 6, 7, 8, 9]]
