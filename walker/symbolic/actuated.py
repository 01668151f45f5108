"""Symbolic models of actuated walkers (sympy only): Grizzle's three-link walker.

The three-link walker of Grizzle, Abba and Plestan [1]_ has two rigid legs of length ``r``
joined at the hip and a torso hinged at the hip; two actuators sit at the hip, one between
the torso and each leg.  Conventions are those of :mod:`walker.symbolic.models`: world frame
x forward, y up; absolute angles from the vertical, counterclockwise positive; a leg at angle
``q`` points from foot to hip along ``u(q) = (-sin q, cos q)``; the torso at angle ``q_torso``
points from the hip to its mass along ``u(q_torso)`` (upright at 0, leaning forward when
negative).  Where the masses sit (Westervelt et al.'s example code [2]_, file
``model_params_three_link.m``: r = 1, m = 5, M_H = 15, M_T = 10, L = 0.5, g = 9.8):

* a point mass ``mass_leg`` on each leg, ``com_from_foot`` above the foot and ``com_to_hip``
  below the hip (``r/2`` each in [2]_), with an optional rotational inertia ``inertia_leg``;
* a point mass ``mass_hip`` at the hip;
* the torso mass ``mass_torso`` at ``torso_length`` (``L``) from the hip along the torso,
  with an optional rotational inertia ``inertia_torso``;
* optionally, each hip actuator's rotor: geared with ratio N to the relative angle
  ``q_leg - q_torso`` it drives, it adds ``N^2 J_rotor w^2 / 2`` to the kinetic energy
  (``w`` the joint rate), ``rotor_inertia`` = N^2 J_rotor (0 in [2]_: the example model has
  no rotors).  A rotor is a massless body whose angle is the relative joint angle; its own
  rotation with the link carrying it (and its gyroscopic coupling) is neglected, as in
  RABBIT's model (Chevallereau et al., IEEE Control Systems Magazine 23(5), 2003).

Coordinates of the pinned (single-support) model: ``(q_stance, q_swing, q_torso)``, stance
foot at the origin.  Inputs ``tau = (tau_stance_hip, tau_swing_hip)``: the torque the torso
exerts on the stance leg and on the swing leg; by virtual work on the relative angles
``q_stance - q_torso`` and ``q_swing - q_torso``, ``B = [[1, 0], [0, 1], [-1, -1]]``.

The floating-base model ``(q_stance, q_swing, q_torso, x_hip, y_hip)`` serves the heel-strike
impact (augmented linear system with the swing foot's contact Jacobian); the leg relabelling
happens in :mod:`walker.models.three_link`.

References
----------
.. [1] J. W. Grizzle, G. Abba, F. Plestan, "Asymptotically stable walking for biped robots:
   analysis via systems with impulse effects", IEEE TAC 46(1):51-64, 2001.
.. [2] E. R. Westervelt, J. W. Grizzle, C. Chevallereau, J.-H. Choi, B. Morris, *Feedback
   Control of Dynamic Bipedal Robot Locomotion*, CRC Press 2007; its three-link example code
   (``model_params_three_link.m``, ``control_params_three_link.m``).
"""

from __future__ import annotations

from functools import cache

import sympy as sp

from walker.params import params_class
from walker.symbolic.codegen import Kernel
from walker.symbolic.mechanics import Body, LagrangianModel, derive
from walker.symbolic.models import _coords, _u

__all__ = [
    "THREE_LINK_PARAMS",
    "three_link",
    "three_link_extended",
    "three_link_kernels",
    "actuated_kernels",
]

_names = params_class("three_link").names()
THREE_LINK_PARAMS = _names[: _names.index("rotor_inertia") + 1]
"""The physical parameters the generated kernels take: ``ThreeLinkParams``'s fields up to
``rotor_inertia``, the last physical one (read from the class, in its order)."""


def _symbols():
    return tuple(sp.Symbol(n, real=True) for n in THREE_LINK_PARAMS)


def _bodies(q1, q2, q3, hip, params):
    m_h, m, m_t, a, b, L, I_l, I_t, slope, g, I_r = params
    return [
        Body("hip", m_h, hip),
        Body("stance_leg", m, hip - b * _u(q1), q1, I_l),
        Body("swing_leg", m, hip - b * _u(q2), q2, I_l),
        Body("torso", m_t, hip + L * _u(q3), q3, I_t),
        # massless rotors turning with the relative hip angles (reflected inertia N^2 J)
        Body("rotor_stance", sp.S.Zero, hip, q1 - q3, I_r),
        Body("rotor_swing", sp.S.Zero, hip, q2 - q3, I_r),
    ]


B_MATRIX = sp.Matrix([[1, 0], [0, 1], [-1, -1]])


@cache
def three_link() -> LagrangianModel:
    """Pinned three-link walker ``(q_stance, q_swing, q_torso)`` with the hip actuators ``B``.

    Returns
    -------
    LagrangianModel
        points ``stance_contact`` (origin), ``hip``, ``swing_contact``, ``torso``.
    """
    params = _symbols()
    m_h, m, m_t, a, b, L, I_l, I_t, slope, g, I_r = params
    (q1, q2, q3), (q1d, q2d, q3d) = _coords(("q_stance", "q_swing", "q_torso"))
    r = a + b
    hip = r * _u(q1)
    points = {
        "stance_contact": sp.Matrix([0, 0]),
        "hip": hip,
        "swing_contact": hip - r * _u(q2),
        "torso": hip + L * _u(q3),
    }
    return derive(
        "three_link",
        (q1, q2, q3),
        (q1d, q2d, q3d),
        _bodies(q1, q2, q3, hip, params),
        g,
        params,
        points=points,
        B=B_MATRIX,
    )


@cache
def three_link_extended() -> LagrangianModel:
    """Floating-base three-link walker ``(q_stance, q_swing, q_torso, x_hip, y_hip)``."""
    params = _symbols()
    m_h, m, m_t, a, b, L, I_l, I_t, slope, g, I_r = params
    names = ("q_stance", "q_swing", "q_torso", "x_hip", "y_hip")
    (q1, q2, q3, xh, yh), qd = _coords(names)
    r = a + b
    hip = sp.Matrix([xh, yh])
    points = {
        "stance_contact": hip - r * _u(q1),
        "swing_contact": hip - r * _u(q2),
        "hip": hip,
    }
    B = sp.Matrix([[1, 0], [0, 1], [-1, -1], [0, 0], [0, 0]])
    return derive(
        "three_link_extended",
        (q1, q2, q3, xh, yh),
        qd,
        _bodies(q1, q2, q3, hip, params),
        g,
        params,
        points=points,
        B=B,
    )


def ground_reaction(m: LagrangianModel, qdd) -> sp.Matrix:
    """World-frame force of the ground on the pinned stance foot, shape (2, 1) [N].

    Newton's law for the whole walker: ``F = sum_i m_i a_i + (sum_i m_i) (0, g)`` with the
    centre-of-mass accelerations ``a_i = J_i qdd + (d J_i/dt) qd``.
    """
    q, qd = sp.Matrix(m.q), sp.Matrix(m.qd)
    g = m.params[[str(s) for s in m.params].index("g")]  # any model with a parameter `g`
    F = sp.zeros(2, 1)
    for body in m.bodies:
        J = body.position.jacobian(q)
        v = J * qd
        a = J * sp.Matrix(qdd) + v.jacobian(q) * qd
        F += body.mass * a
        F[1] += body.mass * g
    return F.applyfunc(sp.expand)


def three_link_kernels() -> list[Kernel]:
    """The kernels of ``walker/_generated/three_link.py``.

    Pinned model: the dynamics kernels of the passive walkers (``mass_matrix``, ``bias``,
    ``dmass``, ...), ``hip_jac``, ``ground_reaction(q, qd, qdd, p)``; floating base:
    ``ext_mass_matrix``, ``ext_swing_contact_jac``, ``ext_stance_contact_jac``.
    """
    qdd = sp.symbols("q_stance_ddot q_swing_ddot q_torso_ddot", real=True)
    return actuated_kernels(three_link(), three_link_extended(), qdd)


def actuated_kernels(m: LagrangianModel, ext: LagrangianModel, qdd) -> list[Kernel]:
    """The kernels of an actuated walker's generated module from its pinned model ``m``, its
    floating-base model ``ext`` and the symbols ``qdd`` of the accelerations: the dynamics
    kernels of the passive walkers (``mass_matrix``, ``bias``, ``dmass``, ...), ``hip_jac``,
    ``ground_reaction(q, qd, qdd, p)``, ``ext_mass_matrix``, ``ext_swing_contact_jac`` and
    ``ext_stance_contact_jac``."""
    from walker.symbolic.dynamics import dynamics_kernels, hip_jacobian

    q, p = ("q", ext.q), ("p", ext.params)
    n = len(ext.q)
    return dynamics_kernels(m, "") + [
        hip_jacobian(m, ""),
        Kernel(
            "ground_reaction",
            (("q", m.q), ("qd", m.qd), ("qdd", qdd), ("p", m.params)),
            ground_reaction(m, qdd),
            "World-frame ground force on the stance foot (F_x, F_y) [N], out (2,).",
        ),
        Kernel("ext_mass_matrix", (q, p), ext.D, f"Floating-base mass matrix, out ({n}, {n})."),
        Kernel(
            "ext_swing_contact_jac",
            (q, p),
            ext.point_jacobian("swing_contact"),
            f"Jacobian of the swing foot position, out (2, {n}).",
        ),
        Kernel(
            "ext_stance_contact_jac",
            (q, p),
            ext.point_jacobian("stance_contact"),
            f"Jacobian of the stance foot position, out (2, {n}).",
        ),
    ]
