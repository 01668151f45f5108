"""The numpy oracle of walker's models with dry (Coulomb) joint friction: the double
pendulum, the compass gait and the kneed walker with stick and slip as phases
(``tests/oracle.py`` holds the smooth models this module builds on).

Written from the rules documented in :mod:`walker.models.friction` and the models' docstrings,
not from their code: per joint ``j`` with rate ``w_j = S_j qd`` and friction ``F_j``, slip+
(``w_j > 0``, torque ``-F_j``), slip- (torque ``+F_j``) or stick (``S_j qdd = 0`` held by
``lambda_j``, admissible while ``|lambda_j| < F_j``); the stuck joints make the augmented
system ``[D, -S_k^T; S_k, 0] [qdd; lambda_k] = [f + sum_slip S_j^T tau_j; 0]`` (``f = -(h -
Q)`` from the symbolic model), solved with ``numpy.linalg.solve``.  Phase index ``base *
3**n_joints + sum_j mode_j 3**j`` (mode 0 slip+, 1 slip-, 2 stick).  Guards per joint:
``w_j`` while slipping with ``F_j > 0`` (slip_stops), ``|lambda_j| - F_j`` while stuck
(stick_breaks), 1.0 where unused.  Modes of the joints at rest are the combination that is
consistent with strict inequalities (stuck: ``|lambda| < F``, slipping from rest with sign
``s``: ``s S_j qdd > 0``), else the first consistent with non-strict ones; joints moving
faster than ``W_TOL`` slip with the sign of their rate; ``F_j = 0`` never sticks.  A joint
that starts to stick has its rates projected by the plastic lock.
"""

from __future__ import annotations

import itertools

import numpy as np
import oracle as O

from walker.status import EVENT_CONTINUE, EVENT_IGNORE, EVENT_TERMINAL, Status
from walker.symbolic import models as sym

W_TOL = 1e-12
"""|w| [rad/s] at or below which a joint counts as at rest (walker.models.friction)."""
SLIP_POS, SLIP_NEG, STICK = 0, 1, 2
_SINGULAR = int(Status.LINEAR_SOLVE_FAILED)


def decode(code, m):
    return [(code // 3**j) % 3 for j in range(m)]


def encode(modes):
    return sum(int(mode) * 3**j for j, mode in enumerate(modes))


def _system(D, S, modes):
    stuck = [j for j, mode in enumerate(modes) if mode == STICK]
    n, k = D.shape[0], len(stuck)
    A = np.zeros((n + k, n + k))
    A[:n, :n] = D
    A[:n, n:] = -S[stuck].T
    A[n:, :n] = S[stuck]
    return A, stuck


def _solve(A, b):
    try:
        out = np.linalg.solve(A, b)
    except np.linalg.LinAlgError:
        return None
    return out if np.isfinite(out).all() and np.linalg.cond(A) < 1e14 else None


def accelerations(D, f, S, F, modes):
    """``(qdd, lam)`` in ``modes`` (``lam``: stuck joints' torques, the slip torques of the
    others), or None if singular."""
    n = D.shape[0]
    tau = np.array(
        [
            -F[j] if mode == SLIP_POS else F[j] if mode == SLIP_NEG else 0.0
            for j, mode in enumerate(modes)
        ]
    )
    A, stuck = _system(D, S, modes)
    y = _solve(A, np.concatenate([f + S.T @ tau, np.zeros(len(stuck))]))
    if y is None:
        return None
    lam = tau.copy()
    lam[stuck] = y[n:]
    return y[:n], lam


def accelerations_jacobian(D, dD, df_dq, df_dqd, S, modes, qdd):
    """``d qdd / d(q, qd)`` (n, 2n): ``A [dqdd; dlam] = [df - dD qdd; 0]``."""
    n = D.shape[0]
    A, stuck = _system(D, S, modes)
    rhs = np.hstack([df_dq - np.column_stack([d @ qdd for d in dD]), df_dqd])
    return np.linalg.solve(A, np.vstack([rhs, np.zeros((len(stuck), 2 * n))]))[:n]


def friction_guards(S, F, modes, qd, lam):
    g = np.ones(2 * len(modes))
    for j, mode in enumerate(modes):
        if mode == STICK:
            g[2 * j + 1] = abs(lam[j]) - F[j]
        elif F[j] > 0.0:
            g[2 * j] = S[j] @ qd
    return g


def friction_directions(code, m):
    """Per joint: slip_stops toward zero (down for slip+, up for slip-; unused while stuck),
    stick_breaks increasing."""
    return [d for mode in decode(code, m) for d in (1 if mode == SLIP_NEG else -1, 1)]


def choose_modes(D, f, S, F, qd, free, modes):
    """The modes of the ``free`` joints (the others kept): ``(ok, modes)``."""
    modes = list(modes)
    w = S @ qd
    rest = []
    for j in free:
        if abs(w[j]) > W_TOL:
            modes[j] = SLIP_POS if w[j] > 0 else SLIP_NEG
        else:
            rest.append(j)
    if not rest:
        return True, modes
    options = [(STICK, SLIP_POS, SLIP_NEG) if F[j] > 0.0 else (SLIP_POS, SLIP_NEG) for j in rest]
    for strict in (True, False):
        for combo in itertools.product(*options):
            trial = list(modes)
            for j, mode in zip(rest, combo, strict=True):
                trial[j] = mode
            solved = accelerations(D, f, S, F, trial)
            if solved is None:
                return False, modes
            qdd, lam = solved
            ok = True
            for j, mode in zip(rest, combo, strict=True):
                if mode == STICK:
                    ok &= abs(lam[j]) < F[j] if strict else abs(lam[j]) <= F[j]
                else:
                    rate = (1.0 if mode == SLIP_POS else -1.0) * (S[j] @ qdd)
                    ok &= rate > 0.0 if strict else rate >= 0.0
            if ok:
                return True, trial
    return False, modes


def project_stuck(D, S, modes, qd):
    stuck = [j for j, mode in enumerate(modes) if mode == STICK]
    if not stuck:
        return qd.copy()
    solved = O.solve_impact(D, S[stuck], qd)
    return None if solved is None else solved[0]


class FrictionLayer:
    """Phase functions of a model with joint friction over its smooth base: subclasses give
    ``n_base``, ``base``, ``joints(base)`` (rows ``S``), ``dynamics(base, x, p)`` ->
    ``(q, qd, Lagrangian)``, ``F(p)``, ``n_base_guards``, ``expand(base, rates)``."""

    def split(self, phase):
        m = 3 ** len(self.joint_rows(0))
        if phase < m:
            return 0, decode(phase, len(self.joint_rows(0)))
        return 1, decode(phase - m, len(self.joint_rows(1)))

    def phase_of(self, base, modes):
        return encode(modes) + (0 if base == 0 else 3 ** len(self.joint_rows(0)))

    def _forces(self, base, x, p):
        q, qd, lag = self.dynamics(base, x, p)
        pb = p[: self.n_base_params]
        return q, qd, lag, lag.mass(q, pb), -lag.bias(q, qd, pb), pb

    def _accel(self, phase, x, p):
        base, modes = self.split(phase)
        q, qd, lag, D, f, pb = self._forces(base, x, p)
        return accelerations(
            D, f, self.joint_rows(base), self.F(p)[: len(self.joint_rows(base))], modes
        )

    def friction_rhs(self, phase, x, p):
        base, _ = self.split(phase)
        q, qd, *_ = self._forces(base, x, p)
        qdd, _ = self._accel(phase, x, p)
        return self.expand(base, qd, qdd)

    def friction_jac(self, phase, x, p):
        base, modes = self.split(phase)
        q, qd, lag, D, f, pb = self._forces(base, x, p)
        qdd, _ = accelerations(
            D, f, self.joint_rows(base), self.F(p)[: len(self.joint_rows(base))], modes
        )
        dD = [d(q, pb) for d in lag.dmass]
        a = accelerations_jacobian(
            D,
            dD,
            -lag.dbias_dq(q, qd, pb),
            -lag.dbias_dqd(q, qd, pb),
            self.joint_rows(base),
            modes,
            qdd,
        )
        return self.expand_jac(base, a)

    def friction_guards(self, phase, x, p):
        base, modes = self.split(phase)
        q, qd, *_ = self._forces(base, x, p)
        _, lam = self._accel(phase, x, p)
        g = friction_guards(
            self.joint_rows(base), self.F(p)[: len(self.joint_rows(base))], modes, qd, lam
        )
        missing = 2 * (len(self.joint_rows(0)) - len(modes))
        return np.concatenate([g, np.ones(missing)])

    def settle(self, base, x, p, free=None, modes=None):
        """Modes chosen for the ``free`` joints (all) at ``x`` and the stuck joints' rates
        projected: ``(phase, x_new)`` or None if singular."""
        S = self.joint_rows(base)
        q, qd, lag, D, f, pb = self._forces(base, x, p)
        free = range(len(S)) if free is None else free
        ok, modes = choose_modes(
            D, f, S, self.F(p)[: len(self.joint_rows(base))], qd, free, modes or [0] * len(S)
        )
        if not ok:
            return None
        qd_new = project_stuck(D, S, modes, qd)
        if qd_new is None:
            return None
        return self.phase_of(base, modes), self.with_rates(base, x, qd_new)

    def start_phase(self, x, p):
        base = 0
        S = self.joint_rows(base)
        q, qd, lag, D, f, pb = self._forces(base, x, p)
        _, modes = choose_modes(
            D, f, S, self.F(p)[: len(self.joint_rows(base))], qd, range(len(S)), [0] * len(S)
        )
        return self.phase_of(base, modes)

    def switch(self, phase, event, x, p):
        """The reset of friction event ``event`` (``2 j`` slip_stops, ``2 j + 1``
        stick_breaks)."""
        base, modes = self.split(phase)
        S = self.joint_rows(base)
        j, breaks = event // 2, event % 2 == 1
        q, qd, lag, D, f, pb = self._forces(base, x, p)
        if breaks:
            solved = accelerations(D, f, S, self.F(p)[: len(self.joint_rows(base))], modes)
            if solved is None:
                return (EVENT_TERMINAL, phase, _SINGULAR), None, None
            modes = list(modes)
            modes[j] = SLIP_NEG if solved[1][j] > 0.0 else SLIP_POS
            settled = self.settle(base, x, p, [i for i in range(len(S)) if i != j], modes)
        else:
            locked = O.solve_impact(D, S[j : j + 1], qd)
            if locked is None:
                return (EVENT_TERMINAL, phase, _SINGULAR), None, None
            settled = self.settle(base, self.with_rates(base, x, locked[0]), p)
        if settled is None:
            return (EVENT_TERMINAL, phase, _SINGULAR), None, None
        new_phase, x_new = settled
        return (EVENT_CONTINUE, new_phase, 0), x_new, np.zeros(self.n_impulse)

    def after_base_event(self, phase, outcome, x_new, impulse, p):
        """Every joint's mode chosen afresh after a base event that continues."""
        action, next_base, status = outcome
        if action in (EVENT_IGNORE, EVENT_TERMINAL):
            return (action, phase, status), x_new, impulse
        settled = self.settle(next_base, x_new, p)
        if settled is None:
            return (EVENT_TERMINAL, phase, _SINGULAR), None, None
        new_phase, x_settled = settled
        return (action, new_phase, status), x_settled, impulse


# --------------------------------------------------------------------------- double pendulum
class DoublePendulum(FrictionLayer):
    """The double pendulum, ``x = (q1, q2, qd1, qd2)``, joints ``w = qd`` (``S = I``)."""

    n_x = 4
    n_impulse = 1
    n_base_params = 13

    def __init__(self):
        self.lag = O.Lagrangian(sym.double_pendulum())
        self.directions = np.array([self._directions(c) for c in range(9)])

    @staticmethod
    def _directions(code):
        return friction_directions(code, 2)

    def joint_rows(self, base):
        return np.eye(2)

    def dynamics(self, base, x, p):
        return x[:2], x[2:], self.lag

    def F(self, p):
        return p[11:13]  # coulomb_1, coulomb_2

    def expand(self, base, qd, qdd):
        return np.concatenate([qd, qdd])

    def expand_jac(self, base, a):
        J = np.zeros((4, 4))
        J[0, 2] = J[1, 3] = 1.0
        J[2:] = a
        return J

    def with_rates(self, base, x, qd):
        return np.concatenate([x[:2], qd])

    rhs = FrictionLayer.friction_rhs
    jac = FrictionLayer.friction_jac
    guards = FrictionLayer.friction_guards

    def reset(self, phase, k, x, p):
        return self.switch(phase, k, x, p)

    def energy(self, x, p):
        return np.array([self.lag.kinetic(x[:2], x[2:], p), self.lag.potential(x[:2], p)])

    def points(self, x, p):
        return np.array([[0.0, 0.0], *(self.lag.point[k](x[:2], p) for k in ("elbow", "tip"))])


# ---------------------------------------------------------------------- walkers with friction
class CompassCoulomb(FrictionLayer):
    """The compass gait with dry friction at the stance ankle (``w = qd_stance``) and the
    hip (``w = qd_swing - qd_stance``); ``p``: the compass gait's, ``coulomb_ankle``,
    ``coulomb_hip``."""

    n_x = 4
    n_impulse = 2
    n_base_params = 10
    n_base_guards = 3

    def __init__(self):
        self.walker = O.oracle("compass")
        self.directions = np.array(
            [list(self.walker.directions[0]) + friction_directions(c, 2) for c in range(9)]
        )

    def joint_rows(self, base):
        return np.array([[1.0, 0.0], [-1.0, 1.0]])

    def dynamics(self, base, x, p):
        return x[:2], x[2:], self.walker.pinned

    def F(self, p):
        return p[10:12]

    def expand(self, base, qd, qdd):
        return np.concatenate([qd, qdd])

    def expand_jac(self, base, a):
        J = np.zeros((4, 4))
        J[0, 2] = J[1, 3] = 1.0
        J[2:] = a
        return J

    def with_rates(self, base, x, qd):
        return np.concatenate([x[:2], qd])

    rhs = FrictionLayer.friction_rhs
    jac = FrictionLayer.friction_jac

    def guards(self, phase, x, p):
        base = self.walker.guards(0, x, p[:10])
        return np.concatenate([base, self.friction_guards(phase, x, p)])

    def reset(self, phase, k, x, p):
        if k >= self.n_base_guards:
            return self.switch(phase, k - self.n_base_guards, x, p)
        return self.after_base_event(phase, *self.walker.reset(0, k, x, p[:10]), p)

    def energy(self, x, p):
        return self.walker.energy(x, p[:10])

    def points(self, x, p):
        return self.walker.points(x, p[:10])

    def lift(self, z, p):
        return self.walker.lift(z, p[:10])

    def project(self, x):
        return self.walker.project(x)


class KneedCoulomb(FrictionLayer):
    """The kneed walker with dry friction at the stance ankle (``qd1``), the hip (``qd2 -
    qd1``) and, while unlocked, the swing knee (``qd3 - qd2``); phases 0..26 unlocked,
    27..35 locked (the knee is no joint then)."""

    n_x = 6
    n_impulse = 2
    n_base_params = 17
    n_base_guards = 4

    def __init__(self):
        self.walker = O.oracle("kneed")
        d = self.walker.directions
        self.directions = np.array(
            [list(d[0]) + friction_directions(c, 3) for c in range(27)]
            + [list(d[1]) + friction_directions(c, 2) + [-1, 1] for c in range(9)]
        )

    def joint_rows(self, base):
        if base == 0:
            return np.array([[1.0, 0.0, 0.0], [-1.0, 1.0, 0.0], [0.0, -1.0, 1.0]])
        return np.array([[1.0, 0.0], [-1.0, 1.0]])

    def dynamics(self, base, x, p):
        if base == 0:
            return x[:3], x[3:], self.walker.pinned
        return x[:2], x[3:5], self.walker.locked

    def F(self, p):
        return p[17:20]

    def expand(self, base, qd, qdd):
        if base == 0:
            return np.concatenate([qd, qdd])
        return np.array([qd[0], qd[1], qd[1], qdd[0], qdd[1], qdd[1]])

    def expand_jac(self, base, a):
        J = np.zeros((6, 6))
        if base == 0:
            J[0, 3] = J[1, 4] = J[2, 5] = 1.0
            J[3:] = a
            return J
        J[0, 3] = J[1, 4] = J[2, 4] = 1.0
        J[3:5][:, [0, 1, 3, 4]] = a
        J[5] = J[4]
        return J

    def with_rates(self, base, x, qd):
        if base == 0:
            return np.concatenate([x[:3], qd])
        return np.array([x[0], x[1], x[2], qd[0], qd[1], qd[1]])

    rhs = FrictionLayer.friction_rhs
    jac = FrictionLayer.friction_jac

    def guards(self, phase, x, p):
        base, _ = self.split(phase)
        g = self.walker.guards(base, x, p[:17])
        return np.concatenate([g, self.friction_guards(phase, x, p)])

    def reset(self, phase, k, x, p):
        if k >= self.n_base_guards:
            return self.switch(phase, k - self.n_base_guards, x, p)
        base, _ = self.split(phase)
        return self.after_base_event(phase, *self.walker.reset(base, k, x, p[:17]), p)

    def energy(self, x, p):
        return self.walker.energy(x, p[:17])

    def points(self, x, p):
        return self.walker.points(x, p[:17])

    def lift(self, z, p):
        return self.walker.lift(z, p[:17])

    def project(self, x):
        return self.walker.project(x)
