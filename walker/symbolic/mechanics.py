"""Lagrangian mechanics of planar multibody systems, symbolically (sympy only).

A model is a list of :class:`Body` objects (point masses or rigid links) whose centre-of-mass
positions and absolute angles are expressions in the generalized coordinates ``q``.  From them
:func:`derive` builds, by the textbook Lagrangian route (Spong et al.),

* centre-of-mass velocities through Jacobians, ``v_i = (dp_i/dq) q_dot``,
* kinetic energy ``K = sum 1/2 m_i v_i.v_i + 1/2 I_i omega_i^2`` and potential energy
  ``P = sum m_i g y_i``,
* the mass matrix ``D(q) = d^2 K / d q_dot^2``,
* the Coriolis matrix from the Christoffel symbols,
  ``c_kj = sum_i 1/2 (d d_kj/d q_i + d d_ki/d q_j - d d_ij/d q_k) q_dot_i``,
* the gravity vector ``g(q) = dP/dq``,
* the input map ``B`` and contact Jacobians of named points,

so that ``D(q) q_ddot + C(q, q_dot) q_dot + g(q) = B tau - F_v q_dot - F_s sgn(q_dot) + J^T F``.

Forces that belong to the model itself (viscous joint damping of a passive walker) are kept
as the model's ``forcing`` ``Q(q, q_dot)``: :func:`rayleigh_forcing` builds it from a
Rayleigh dissipation function ``R = sum_j 1/2 b_j w_j^2`` of joint rates ``w_j`` (each
linear in ``q_dot``), ``Q = -dR/dq_dot``, whose power is ``Q . q_dot = -sum_j b_j w_j^2``.
``bias`` stays ``C q_dot + g``; ``forced_bias = bias - Q`` is what the accelerations solve,
``D q_ddot = -forced_bias``.
Everything stops at matrices: the mass matrix is never inverted symbolically and nothing is
simplified (code generation applies common-subexpression elimination instead).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp


@dataclass(frozen=True)
class Body:
    """A rigid body of a planar model.

    Parameters
    ----------
    name : str
    mass : sympy expression
        mass [kg].
    position : sympy Matrix, shape (2, 1)
        centre of mass in the world frame (x forward, y up) [m], a function of ``q``.
    angle : sympy expression or None
        absolute orientation [rad] (its time derivative is the angular velocity); ``None``
        for a point mass.
    inertia : sympy expression
        rotational inertia about the centre of mass [kg m^2]; ignored for a point mass.
    """

    name: str
    mass: sp.Expr
    position: sp.Matrix
    angle: sp.Expr | None = None
    inertia: sp.Expr = sp.S.Zero


@dataclass(frozen=True)
class LagrangianModel:
    """The matrices of ``D(q) q_ddot + C(q, q_dot) q_dot + g(q) = B tau + ...``.

    Attributes
    ----------
    name : str
    q, qd : tuple of sympy Symbol, length n
        generalized coordinates and their rates.
    params : tuple of sympy Symbol
        parameter symbols in the canonical order of the model's parameter vector ``p``.
    bodies : tuple of Body
    D : Matrix (n, n)
        mass (inertia) matrix.
    C : Matrix (n, n)
        Coriolis/centrifugal matrix (Christoffel symbols of the first kind).
    G : Matrix (n, 1)
        gravity vector ``dP/dq``.
    B : Matrix (n, m)
        input map (joint torques to generalized forces).
    K, P : sympy expressions
        kinetic and potential energy.
    points : dict of str -> Matrix (2, 1)
        named points (feet, hip, knee) in the world frame.
    forcing : Matrix (n, 1)
        generalized forces that are part of the model (joint damping), on the right-hand
        side: ``D q_ddot + C q_dot + g = Q``; zero for a conservative model.
    """

    name: str
    q: tuple
    qd: tuple
    params: tuple
    bodies: tuple
    D: sp.Matrix
    C: sp.Matrix
    G: sp.Matrix
    B: sp.Matrix
    K: sp.Expr
    P: sp.Expr
    points: dict = field(default_factory=dict)
    forcing: sp.Matrix | None = None

    def __post_init__(self) -> None:
        if self.forcing is None:
            object.__setattr__(self, "forcing", sp.zeros(len(self.q), 1))

    @property
    def n(self) -> int:
        return len(self.q)

    @property
    def bias(self) -> sp.Matrix:
        """``h(q, q_dot) = C q_dot + g``: everything but the inertial term (no forcing)."""
        return self.C * sp.Matrix(self.qd) + self.G

    @property
    def forced_bias(self) -> sp.Matrix:
        """``h - Q = C q_dot + g - Q``: the accelerations solve ``D q_ddot = -(h - Q)``.

        Equals :attr:`bias` for a conservative model (``Q = 0``).
        """
        return self.bias - self.forcing

    @property
    def has_forcing(self) -> bool:
        """Whether ``forcing`` is not identically zero (structurally)."""
        return any(e != 0 for e in self.forcing)

    def point_jacobian(self, name: str) -> sp.Matrix:
        """Contact Jacobian ``dp/dq`` of a named point, shape (2, n)."""
        return self.points[name].jacobian(sp.Matrix(self.q))

    def generalized_force(
        self, tau=None, viscous=None, coulomb=None, contact: dict | None = None
    ) -> sp.Matrix:
        """Right-hand side ``B tau - F_v q_dot - F_s sgn(q_dot) + sum J_c^T F_c``.

        Parameters
        ----------
        tau : sequence, length m, optional
            actuator torques.
        viscous, coulomb : sequence, length n, optional
            diagonals of ``F_v`` [N m s] and ``F_s`` [N m].
        contact : dict of point name -> sequence of 2 forces, optional
            world-frame forces applied at named points [N].
        """
        n = self.n
        qd = sp.Matrix(self.qd)
        out = sp.zeros(n, 1)
        if tau is not None:
            out += self.B * sp.Matrix(tau)
        if viscous is not None:
            out -= sp.diag(*viscous) * qd
        if coulomb is not None:
            out -= sp.diag(*coulomb) * qd.applyfunc(sp.sign)
        for name, force in (contact or {}).items():
            out += self.point_jacobian(name).T * sp.Matrix(force)
        return out

    def energy_rate(self, xdot: sp.Matrix) -> sp.Expr:
        """``dE/dt = dE/dx . f`` for the state ``x = (q, q_dot)`` along the field ``xdot``."""
        E = self.K + self.P
        x = list(self.q) + list(self.qd)
        return sum(sp.diff(E, xi) * fi for xi, fi in zip(x, xdot, strict=True))


def rayleigh_forcing(qd, dampers) -> sp.Matrix:
    """Generalized forces ``Q = -dR/dq_dot`` of viscous dampers, ``R = sum_j 1/2 b_j w_j^2``.

    Parameters
    ----------
    qd : sequence of sympy Symbol, length n
        generalized rates.
    dampers : sequence of (coefficient, rate)
        each a damping coefficient ``b_j`` [N m s/rad] and the joint's relative angular rate
        ``w_j`` [rad/s], an expression linear in ``qd`` (e.g. ``qd_swing - qd_stance`` for a
        hip between two legs at absolute angles).

    Returns
    -------
    Matrix (n, 1)
        ``Q``; its power is ``Q . qd = -sum_j b_j w_j^2 <= 0`` for ``b_j >= 0``.

    Notes
    -----
    A damper between links at absolute angles ``q_a`` (parent) and ``q_b`` (child) applies
    ``-b w`` to the child and ``+b w`` to the parent, ``w = qd_b - qd_a``: equal and opposite
    joint torques, so the total angular momentum about the joint is untouched
    (Goldstein, *Classical Mechanics*, 3rd ed., section 1.5, the dissipation function).
    """
    qd = list(qd)
    R = sum((sp.Rational(1, 2) * b * w**2 for b, w in dampers), sp.S.Zero)
    return sp.Matrix([-sp.expand(sp.diff(R, v)) for v in qd])


def christoffel_coriolis(D: sp.Matrix, q, qd) -> sp.Matrix:
    """Coriolis matrix from the Christoffel symbols of the first kind of ``D``.

    ``C[k, j] = sum_i 1/2 (dD[k, j]/dq_i + dD[k, i]/dq_j - dD[i, j]/dq_k) qd_i``
    (Spong, Hutchinson, Vidyasagar, Robot Modeling and Control, eq. 7.61).
    """
    n = len(q)
    dD = [D.diff(qi) for qi in q]  # dD[i][k, j] = dD_kj / dq_i
    C = sp.zeros(n, n)
    for k in range(n):
        for j in range(n):
            C[k, j] = sum(
                sp.Rational(1, 2) * (dD[i][k, j] + dD[j][k, i] - dD[k][i, j]) * qd[i]
                for i in range(n)
            )
    return C


def derive(
    name: str,
    q,
    qd,
    bodies,
    g: sp.Symbol,
    params,
    *,
    points: dict | None = None,
    B: sp.Matrix | None = None,
    forcing: sp.Matrix | None = None,
) -> LagrangianModel:
    """Derive the Lagrangian model of a planar system of bodies.

    Parameters
    ----------
    name : str
    q, qd : sequence of sympy Symbol, length n
    bodies : sequence of Body
    g : sympy expression
        gravitational acceleration [m/s^2], acting along -y.
    params : sequence of sympy Symbol
        canonical parameter order; every free symbol of the model other than ``q``, ``qd``
        must be in it.
    points : dict of str -> Matrix (2, 1), optional
        named points to keep (feet, hip, knee).
    B : Matrix (n, m), optional
        input map; zero columns when omitted.
    forcing : Matrix (n, 1), optional
        generalized forces of the model itself (e.g. :func:`rayleigh_forcing` of joint
        dampers), functions of ``q``, ``qd`` and ``params``; zero when omitted.

    Returns
    -------
    LagrangianModel
    """
    q = tuple(q)
    qd = tuple(qd)
    qv = sp.Matrix(q)
    qdv = sp.Matrix(qd)
    n = len(q)
    D = sp.zeros(n, n)
    K = sp.S.Zero
    P = sp.S.Zero
    for body in bodies:
        Jv = body.position.jacobian(qv)
        D += body.mass * (Jv.T * Jv)
        v = Jv * qdv
        K += sp.Rational(1, 2) * body.mass * (v.T * v)[0, 0]
        if body.angle is not None and body.inertia != 0:
            jw = sp.Matrix([[sp.diff(body.angle, qi) for qi in q]])
            D += body.inertia * (jw.T * jw)
            K += sp.Rational(1, 2) * body.inertia * (jw * qdv)[0, 0] ** 2
        P += body.mass * g * body.position[1]
    D = D.applyfunc(sp.expand)
    C = christoffel_coriolis(D, q, qd)
    G = sp.Matrix([sp.diff(P, qi) for qi in q])
    if B is None:
        B = sp.zeros(n, 0)
    model = LagrangianModel(
        name=name,
        q=q,
        qd=qd,
        params=tuple(params),
        bodies=tuple(bodies),
        D=D,
        C=C,
        G=G,
        B=B,
        K=K,
        P=P,
        points=dict(points or {}),
        forcing=None if forcing is None else sp.Matrix(forcing),
    )
    if model.forcing.shape != (n, 1):
        raise ValueError(f"`forcing` must have shape ({n}, 1), got {model.forcing.shape}")
    check_free_symbols(model)
    return model


def stray_symbols(exprs, allowed: set) -> list[str]:
    """Names of the free symbols of ``exprs`` that are not in ``allowed``, sorted."""
    free = set().union(*(e.free_symbols for e in exprs))
    return sorted(str(s) for s in free - allowed)


def check_free_symbols(model: LagrangianModel) -> None:
    """Raise ``ValueError`` naming any symbol that is neither a coordinate nor a parameter."""
    allowed = set(model.q) | set(model.qd) | set(model.params)
    exprs = [model.D, model.C, model.G, model.B, model.forcing, sp.Matrix([model.K, model.P])]
    exprs += list(model.points.values())
    stray = stray_symbols(exprs, allowed)
    if stray:
        raise ValueError(
            f"model `{model.name}`: symbols {stray} are neither coordinates nor parameters; "
            f"add them to `params`"
        )
