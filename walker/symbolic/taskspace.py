"""Cartesian (task-space) dynamics of two-link chains, symbolically, and its singularities.

Convention.  A chain with joint-space dynamics (:mod:`walker.symbolic.mechanics`)

    D(q) q_ddot + C(q, q_dot) q_dot + g(q) = tau + Q(q, q_dot)

carries a point whose coordinates in a task frame are ``x = h(q)`` (as many as joints).  Its
Jacobian ``J = dh/dq`` is square; ``x_dot = J q_dot`` and ``x_ddot = J q_ddot + J_dot q_dot``,
with ``J_dot q_dot = d(J q_dot)/dq q_dot`` (the convective term).  A force ``F`` at the point,
in task coordinates, does the virtual work ``F . dx = (J^T F) . dq``, so it is the joint
torque ``tau = J^T F``.  Where ``J`` is invertible, ``q_ddot = J^-1 (x_ddot - J_dot q_dot)``;
substituting into the joint-space equation and multiplying on the left by ``J^-T`` gives

    M_x(q) x_ddot + V_x(q, q_dot) + G_x(q) = F + Q_x(q, q_dot)

    M_x = J^-T D J^-1                      task-space inertia [kg]
    V_x = J^-T (C q_dot) - M_x J_dot q_dot  velocity (Coriolis, centrifugal) terms [N]
    G_x = J^-T g                            gravity terms [N]
    Q_x = J^-T Q                            the model's own forces (joint dampers) [N]

(Craig [1]_, "Formulating manipulator dynamics in Cartesian space", the standard
task-space form of the equations of motion; Khatib [2]_ for the operational-space controller).
``V_x`` is written as a function of ``(q, q_dot)``, as in [1]_; ``J^-1`` is the adjugate over
``det J``, a 2 x 2 kinematic inverse; the mass matrix ``D`` is never inverted.

Singularities.  Where ``det J = 0`` the Cartesian form does not exist (``M_x`` grows like
``1 / sigma_min(J)^2``).  Near it, rounding in ``D``, ``J`` or the state is amplified by up to
``cond(J)^2`` in ``M_x`` and in the torques ``J^T F`` it produces, so the numeric functions
refuse a configuration whose ``cond(J)`` (2-norm, ratio of the singular values) exceeds
``max_condition``, by default :data:`MAX_CONDITION` ``= eps^(-1/4) = 8192``: the
amplification ``cond(J)^2 eps`` then stays below ``sqrt(eps) = 1.5e-8``, at most half of
double precision's digits lost.  The refusal is a :class:`SingularConfiguration`
(a ``ValueError``) naming ``cond(J)``, the threshold and the joint angle that vanishes at the
singularity; :meth:`CartesianFunctions.condition_number` reports ``cond(J)`` without raising,
for callers that want a status.

The two chains walker ships:

* :func:`planar_elbow_cartesian`: the planar elbow manipulator of
  :func:`walker.symbolic.models.planar_elbow` (parameters as
  :class:`walker.params.DoublePendulumParams`), its tip in the world frame; singular when the
  elbow angle ``q2`` is 0 (arm straight) or ``pi`` (folded).  For the unit arm
  (``length_1 = length_2 = 1 m``) ``cond(J) = 8192`` at ``|q2| = 6.1e-4 rad``.
* :func:`swing_foot_cartesian`: the kneed walker's swing leg (thigh and shank of
  :func:`walker.symbolic.models.kneed_unlocked`) as a chain pinned at the hip, the swing foot
  relative to the hip in the hip's slope frame; singular when the knee is straight,
  ``q3 - q2 = 0``, which is every locked-knee phase.

Examples
--------
>>> import numpy as np
>>> from walker.params import DoublePendulumParams
>>> arm = CartesianFunctions(planar_elbow_cartesian())
>>> p = DoublePendulumParams.course().as_array()
>>> terms = arm.cartesian_terms([0.3, 1.2], [0.5, -1.0], p)
>>> bool(np.all(np.linalg.eigvalsh(terms.mass) > 0))
True
>>> try:  # the arm nearly straight
...     arm.cartesian_terms([0.3, 1e-6], [0.0, 0.0], p)
... except SingularConfiguration as err:
...     print(err.angle_name, f"{err.condition:.1e}", f"{err.max_condition:.0f}")
q2 5.0e+06 8192

References
----------
.. [1] J. J. Craig, *Introduction to Robotics: Mechanics and Control*, 3rd ed., Pearson 2005,
   chapter 6, "Formulating manipulator dynamics in Cartesian space".
.. [2] O. Khatib, "A unified approach for motion and force control of robot manipulators:
   the operational space formulation", IEEE J. Robotics and Automation 3(1):43-53, 1987.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import NamedTuple

import numpy as np
import sympy as sp

from walker.symbolic.mechanics import Body, LagrangianModel, derive, rayleigh_forcing
from walker.symbolic.models import MODEL_PARAMS, kneed_unlocked, planar_elbow

__all__ = [
    "MAX_CONDITION",
    "CartesianFunctions",
    "CartesianTerms",
    "JointTerms",
    "SingularConfiguration",
    "TaskSpaceModel",
    "cartesian",
    "planar_elbow_cartesian",
    "swing_chain",
    "swing_foot_cartesian",
]

MAX_CONDITION = float(np.finfo(np.float64).eps ** -0.25)
"""Largest ``cond(J)`` accepted by default: ``eps^(-1/4) = 8192``, so that the ``cond(J)^2``
amplification of rounding in the Cartesian form stays below ``sqrt(eps)``."""


class SingularConfiguration(ValueError):
    """The Cartesian form was asked for at (or too near) a kinematic singularity.

    Attributes
    ----------
    condition : float
        ``cond(J)`` at the configuration (``inf`` where ``J`` is exactly singular).
    max_condition : float
        the threshold it exceeded.
    angle_name : str
        the joint angle that vanishes at the singularity (``"q2"``, ``"q3 - q2"``).
    angle : float
        its value [rad].
    """

    def __init__(self, message: str, *, condition, max_condition, angle_name, angle):
        super().__init__(message)
        self.condition = condition
        self.max_condition = max_condition
        self.angle_name = angle_name
        self.angle = angle


def _of_joint(name: str, doc: str) -> property:
    """A read-only property of a :class:`TaskSpaceModel` that is its joint-space model's
    attribute ``name``."""
    return property(lambda self: getattr(self.joint, name), doc=doc)


@dataclass(frozen=True)
class TaskSpaceModel:
    """The matrices of ``M_x x_ddot + V_x + G_x = F + Q_x`` (module docstring), symbolic.

    Attributes
    ----------
    name : str
    joint : LagrangianModel
        the joint-space model (``D``, ``C``, ``G``, ``forcing``) the Cartesian form comes from.
    x : Matrix (n, 1)
        the task point in task coordinates [m], a function of ``q``.
    frame : Matrix (n, n)
        columns: the task axes in world coordinates (``x = frame^T p_world``).
    gravity : Matrix (n, 1)
        gravitational acceleration in task coordinates [m/s^2] (``frame^T (0, -g)``).
    J : Matrix (n, n)
        ``dx/dq``.
    Jdot_qd : Matrix (n, 1)
        ``J_dot q_dot`` [m/s^2].
    det_J : sympy expression
        ``det J``.
    M_x, V_x, G_x, Q_x : Matrix
        task-space inertia (n, n) [kg]; velocity, gravity and model-forcing terms (n, 1) [N].
    angle_name : str
        the joint angle whose vanishing makes ``J`` singular (for messages).
    angle : sympy expression
        that angle as a function of ``q`` [rad].
    singular_text : str
        one phrase saying where the chain is singular.
    """

    name: str
    joint: LagrangianModel
    x: sp.Matrix
    frame: sp.Matrix
    gravity: sp.Matrix
    J: sp.Matrix
    Jdot_qd: sp.Matrix
    det_J: sp.Expr
    M_x: sp.Matrix
    V_x: sp.Matrix
    G_x: sp.Matrix
    Q_x: sp.Matrix
    angle_name: str
    angle: sp.Expr
    singular_text: str

    q = _of_joint("q", "the joint coordinates (tuple of symbols)")
    qd = _of_joint("qd", "the joint rates (tuple of symbols)")
    params = _of_joint("params", "the parameter symbols (tuple)")
    n = _of_joint("n", "the number of joints, which is the number of task coordinates (int)")


def cartesian(
    model: LagrangianModel,
    point: str,
    *,
    g: sp.Expr,
    frame: sp.Matrix | None = None,
    angle: tuple[str, sp.Expr],
    singular_text: str,
    name: str | None = None,
) -> TaskSpaceModel:
    """Derive the Cartesian form of ``model`` for its named point ``point``.

    Parameters
    ----------
    model : LagrangianModel
        joint-space model with as many coordinates as the plane has (2).
    point : str
        a key of ``model.points``: the task point, in world coordinates [m].
    g : sympy expression
        the gravitational acceleration ``model`` was derived with [m/s^2] (acting along
        world ``-y``); only for :attr:`TaskSpaceModel.gravity`.
    frame : Matrix (2, 2), optional
        orthonormal columns: the task axes in world coordinates; identity when omitted.
    angle : (str, sympy expression)
        name and expression of the joint angle that vanishes at the singularity.
    singular_text : str
        where the chain is singular, for messages.
    name : str, optional
        defaults to ``"<model.name>_<point>"``.

    Returns
    -------
    TaskSpaceModel

    Raises
    ------
    ValueError
        if ``point`` is not a point of ``model``, or ``J`` is not square.
    """
    if point not in model.points:
        raise ValueError(
            f"`point` must be one of model `{model.name}`'s points "
            f"({', '.join(model.points)}), got {point!r}"
        )
    p_world = model.points[point]
    if p_world.shape != (2, 1) or model.n != 2:
        raise ValueError(
            f"the planar Cartesian form needs a square 2 x 2 Jacobian: point `{point}` has "
            f"{p_world.shape[0]} coordinates, model `{model.name}` {model.n} joints"
        )
    frame = sp.eye(2) if frame is None else sp.Matrix(frame)
    if frame.shape != (2, 2):
        raise ValueError(f"`frame` must have shape (2, 2), got {frame.shape}")
    q = sp.Matrix(model.q)
    qd = sp.Matrix(model.qd)
    x = frame.T * p_world
    J = x.jacobian(q)
    # d/dt (J q_dot) = J q_ddot + J_dot q_dot: the second term is the q_ddot-free part.
    Jdot_qd = (J * qd).jacobian(q) * qd
    # The 2 x 2 inverse as adjugate over determinant, unexpanded (a kinematic inverse; D is
    # never inverted).
    det_J = J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0]
    J_inv_T = sp.Matrix([[J[1, 1], -J[1, 0]], [-J[0, 1], J[0, 0]]]) / det_J
    M_x = J_inv_T * model.D * J_inv_T.T
    V_x = J_inv_T * (model.C * qd) - M_x * Jdot_qd
    G_x = J_inv_T * model.G
    Q_x = J_inv_T * model.forcing
    gravity = frame.T * sp.Matrix([0, -g])
    angle_name, angle_expr = angle
    return TaskSpaceModel(
        name=name or f"{model.name}_{point}",
        joint=model,
        x=x,
        frame=frame,
        gravity=gravity,
        J=J,
        Jdot_qd=Jdot_qd,
        det_J=det_J,
        M_x=M_x,
        V_x=V_x,
        G_x=G_x,
        Q_x=Q_x,
        angle_name=angle_name,
        angle=sp.sympify(angle_expr),
        singular_text=singular_text,
    )


# ---------------------------------------------------------------------- the two chains
@cache
def planar_elbow_cartesian() -> TaskSpaceModel:
    """The planar elbow manipulator's tip in the world frame (x forward, y up).

    Joint-space model: :func:`walker.symbolic.models.planar_elbow` (``q1`` from the ``+x``
    axis, ``q2`` the elbow angle relative to link 1; parameters in the order of
    :class:`walker.params.DoublePendulumParams`, joint dampers as its forcing).  The tip is
    ``l1 (cos q1, sin q1) + l2 (cos(q1 + q2), sin(q1 + q2))`` and ``det J = l1 l2 sin q2``:
    singular with the arm straight (``q2 = 0``) or folded (``q2 = pi``).

    Examples
    --------
    >>> model = planar_elbow_cartesian()
    >>> model.M_x.shape, model.V_x.shape, model.G_x.shape
    ((2, 2), (2, 1), (2, 1))
    """
    model = planar_elbow()
    g = model.params[MODEL_PARAMS["double_pendulum"].index("g")]
    return cartesian(
        model,
        "tip",
        g=g,
        angle=("q2", model.q[1]),
        singular_text="the arm is straight at q2 = 0 and folded at q2 = pi",
        name="planar_elbow_tip",
    )


@cache
def swing_chain() -> LagrangianModel:
    """The kneed walker's swing leg as a two-link chain pinned at the hip: ``(q2, q3)``.

    The bodies ``swing_thigh`` and ``swing_shank`` of
    :func:`walker.symbolic.models.kneed_unlocked`, with the hip held still at the origin
    (their positions minus the hip's): absolute angles ``q2`` (thigh) and ``q3`` (shank) from
    the vertical, counterclockwise positive, masses at ``thigh_com_to_hip`` below the hip and
    ``shank_com_to_knee`` below the knee, fore-aft offsets and inertias as in the walker.
    Parameters: the full :class:`walker.params.KneedParams` vector (those of the stance leg
    and the hip do not enter).  Gravity acts along world ``-y``.

    Its ``D`` and ``g`` are the ``(q2, q3)`` blocks of ``kneed_unlocked``'s (the hip moves
    with ``q1`` only).  The point ``foot`` is the swing foot's contact point relative to the
    hip (``kneed_unlocked``'s ``swing_contact - hip``).  Forcing: the knee damper
    (``damping_knee`` on ``qd3 - qd2``); the hip damper acts relative to the stance leg,
    which is not part of this chain, and is left out.  A hip that accelerates at ``a_hip``
    adds ``-a_hip`` to gravity in the hip's frame; this chain takes the hip at rest.
    """
    full = kneed_unlocked()
    _, q2, q3 = full.q
    _, q2d, q3d = full.qd
    params = full.params
    names = MODEL_PARAMS["kneed"]
    g = params[names.index("g")]
    damping_knee = params[names.index("damping_knee")]
    hip = full.points["hip"]
    bodies = [
        Body(b.name, b.mass, b.position - hip, b.angle, b.inertia)
        for b in full.bodies
        if b.name in ("swing_thigh", "swing_shank")
    ]
    points = {
        "knee": full.points["knee"] - hip,
        "foot": full.points["swing_contact"] - hip,
    }
    forcing = rayleigh_forcing((q2d, q3d), [(damping_knee, q3d - q2d)])
    return derive(
        "kneed_swing_chain",
        (q2, q3),
        (q2d, q3d),
        bodies,
        g,
        params,
        points=points,
        forcing=forcing,
    )


@cache
def swing_foot_cartesian() -> TaskSpaceModel:
    """The kneed walker's swing foot relative to the hip, in the hip's slope frame.

    Joint-space model: :func:`swing_chain`.  Task coordinates: the foot's contact point minus
    the hip along ``s = (cos slope, -sin slope)`` (down the slope) and ``n = (sin slope,
    cos slope)`` (the slope's normal), so ``x[1]`` is the foot's height above the hip
    measured along the normal.  Gravity in this frame is ``g (sin slope, -cos slope)``
    (:attr:`TaskSpaceModel.gravity`); ``slope = 0`` gives world axes.  ``det J`` vanishes
    with the knee straight, ``q3 - q2 = 0`` (or folded, ``pi``): the Cartesian form of the
    swing foot exists only while the knee is bent.

    Examples
    --------
    >>> model = swing_foot_cartesian()
    >>> [str(s) for s in model.q]
    ['q2', 'q3']
    """
    model = swing_chain()
    names = MODEL_PARAMS["kneed"]
    slope = model.params[names.index("slope")]
    g = model.params[names.index("g")]
    frame = sp.Matrix([[sp.cos(slope), sp.sin(slope)], [-sp.sin(slope), sp.cos(slope)]])
    q2, q3 = model.q
    return cartesian(
        model,
        "foot",
        g=g,
        frame=frame,
        angle=("q3 - q2", q3 - q2),
        singular_text="the knee is straight at q3 - q2 = 0 (every locked-knee phase)",
        name="kneed_swing_foot",
    )


# ------------------------------------------------------------------------- numerics
class JointTerms(NamedTuple):
    """``D q_ddot + C q_dot + g = tau + Q`` at one state, numerically."""

    mass_matrix: np.ndarray
    """``D``, shape (n, n)."""
    coriolis: np.ndarray
    """``C q_dot``, shape (n,)."""
    gravity: np.ndarray
    """``g``, shape (n,)."""
    forcing: np.ndarray
    """``Q``, shape (n,)."""


class CartesianTerms(NamedTuple):
    """``M_x x_ddot + V_x + G_x = F + Q_x`` at one state, numerically."""

    mass: np.ndarray
    """``M_x``, shape (n, n) [kg]."""
    velocity: np.ndarray
    """``V_x``, shape (n,) [N]."""
    gravity: np.ndarray
    """``G_x``, shape (n,) [N]."""
    forcing: np.ndarray
    """``Q_x``, shape (n,) [N]."""
    jacobian: np.ndarray
    """``J``, shape (n, n)."""
    jdot_qd: np.ndarray
    """``J_dot q_dot``, shape (n,) [m/s^2]."""
    condition: float
    """``cond(J)``."""


def _vector(name: str, value, n: int) -> np.ndarray:
    arr = np.asarray(value, dtype=np.float64)
    if arr.shape != (n,):
        raise ValueError(f"`{name}` must have shape ({n},), got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"all entries of `{name}` must be finite")
    return arr


class CartesianFunctions:
    """Numeric functions of a :class:`TaskSpaceModel`, lambdified once (numpy, with ``cse``).

    Build one per model and keep it: construction lambdifies the matrices (about a second);
    every call after that is plain numpy.  This is for examples and checks; walker's
    simulations never derive or lambdify anything.

    Parameters
    ----------
    model : TaskSpaceModel

    Examples
    --------
    >>> import numpy as np
    >>> from walker.params import KneedParams
    >>> leg = CartesianFunctions(swing_foot_cartesian())
    >>> p = KneedParams.hsu_chen().as_array()
    >>> q = [0.2, 0.2]  # knee straight: the foot one leg length from the hip
    >>> round(float(np.linalg.norm(leg.position(q, p))), 12)
    1.0
    >>> leg.condition_number(q, p) > MAX_CONDITION
    True
    """

    def __init__(self, model: TaskSpaceModel):
        if not isinstance(model, TaskSpaceModel):
            raise TypeError(f"`model` must be a TaskSpaceModel, got {type(model).__name__}")
        self.model = model
        self.n = model.n
        self.n_params = len(model.params)
        joint = model.joint
        qd = sp.Matrix(model.qd)
        args = [list(model.q), list(model.qd), list(model.params)]

        def fn(exprs):
            return sp.lambdify(args, exprs, modules="numpy", cse=True)

        self._kinematics = fn([model.x, model.J, model.Jdot_qd, model.angle])
        self._joint = fn([joint.D, joint.C * qd, joint.G, joint.forcing])
        self._cartesian = fn([model.M_x, model.V_x, model.G_x, model.Q_x])

    def _args(self, q, qd, p):
        q = _vector("q", q, self.n)
        qd = np.zeros(self.n) if qd is None else _vector("qd", qd, self.n)
        p = _vector("p", p, self.n_params)
        return q, qd, p

    def position(self, q, p) -> np.ndarray:
        """The task point ``x(q)`` [m], shape (n,)."""
        x, _, _, _ = self._kinematics(*self._args(q, None, p))
        return np.asarray(x, dtype=np.float64).reshape(self.n)

    def jacobian(self, q, p) -> np.ndarray:
        """``J = dx/dq`` [m/rad], shape (n, n)."""
        _, J, _, _ = self._kinematics(*self._args(q, None, p))
        return np.asarray(J, dtype=np.float64)

    def condition_number(self, q, p) -> float:
        """``cond(J)`` (2-norm) at ``q``; ``inf`` where ``J`` is exactly singular. Never
        raises for a valid ``q``: the status-style check."""
        return _condition(self.jacobian(q, p))

    def joint_terms(self, q, qd, p) -> JointTerms:
        """``D``, ``C q_dot``, ``g`` and ``Q`` at ``(q, q_dot)``."""
        D, Cqd, G, Q = self._joint(*self._args(q, qd, p))
        n = self.n
        return JointTerms(
            np.asarray(D, dtype=np.float64),
            np.asarray(Cqd, dtype=np.float64).reshape(n),
            np.asarray(G, dtype=np.float64).reshape(n),
            np.asarray(Q, dtype=np.float64).reshape(n),
        )

    def cartesian_terms(self, q, qd, p, *, max_condition: float = MAX_CONDITION) -> CartesianTerms:
        """``M_x``, ``V_x``, ``G_x``, ``Q_x`` (with ``J``, ``J_dot q_dot``, ``cond(J)``).

        Parameters
        ----------
        q, qd : array_like, shape (n,)
            joint angles [rad] and rates [rad/s].
        p : array_like, shape (n_params,)
            the joint model's parameter vector.
        max_condition : float, optional
            largest accepted ``cond(J)``, > 1 (default :data:`MAX_CONDITION`).

        Raises
        ------
        SingularConfiguration
            where ``cond(J) > max_condition``, naming both and the vanishing joint angle.
        ValueError
            for wrong shapes, non-finite entries or ``max_condition <= 1``.
        """
        if not max_condition > 1.0:
            raise ValueError(f"`max_condition` must be > 1, got {max_condition!r}")
        q, qd, p = self._args(q, qd, p)
        _, J, jdot_qd, angle = self._kinematics(q, qd, p)
        J = np.asarray(J, dtype=np.float64)
        condition = _condition(J)
        if not condition <= max_condition:
            m = self.model
            qs = ", ".join(f"{v:.6g}" for v in q)
            raise SingularConfiguration(
                f"Cartesian dynamics of `{m.name}` are singular at q = [{qs}] rad: "
                f"cond(J) = {condition:.3g} exceeds `max_condition` = {max_condition:.3g} "
                f"(joint angle {m.angle_name} = {float(angle):.3g} rad; {m.singular_text}). "
                f"Move away from the singular configuration, or raise `max_condition` and "
                f"accept about cond(J)^2 eps of relative error.",
                condition=condition,
                max_condition=max_condition,
                angle_name=m.angle_name,
                angle=float(angle),
            )
        M_x, V_x, G_x, Q_x = self._cartesian(q, qd, p)
        n = self.n
        return CartesianTerms(
            np.asarray(M_x, dtype=np.float64),
            np.asarray(V_x, dtype=np.float64).reshape(n),
            np.asarray(G_x, dtype=np.float64).reshape(n),
            np.asarray(Q_x, dtype=np.float64).reshape(n),
            J,
            np.asarray(jdot_qd, dtype=np.float64).reshape(n),
            condition,
        )


def _condition(J: np.ndarray) -> float:
    s = np.linalg.svd(J, compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0.0 else np.inf
