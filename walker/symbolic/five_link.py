"""Symbolic model of the five-link walker (sympy only): torso, two femurs, two tibias.

The planar five-link biped of Westervelt, Grizzle and Koditschek [1]_ (the RABBIT testbed
[2]_): a torso hinged at the hip, two legs each made of a femur (hip to knee) and a tibia
(knee to foot), point feet, four actuators (two hips, two knees) and one degree of
underactuation (the stance foot).  Conventions are those of :mod:`walker.symbolic.models`:
world frame x forward, y up; absolute angles from the vertical, counterclockwise positive; a
segment at angle ``q`` points along ``u(q) = (-sin q, cos q)`` from its lower end (foot or
knee) to its upper end (knee or hip); the torso at angle ``q_torso`` points from the hip to
its mass along ``u(q_torso)``.

Generalized coordinates of the pinned (single-support) model, chosen so that the first one
is the phase variable and the others are the controlled outputs of :mod:`walker.models.control`::

    q_leg      = (q_tibia_st + q_femur_st) / 2   mean stance-leg angle (phase variable)
    q_knee     = q_femur_st - q_tibia_st         stance-knee flexion (> 0: knee forward)
    q_torso, q_femur_sw, q_tibia_sw              absolute angles

With equal femur and tibia lengths (RABBIT [2]_) ``q_leg`` is exactly the angle of the line
from the stance foot to the hip, the phase variable of [1]_; otherwise it is a linear phase
variable ``c q`` close to it, as [1]_ allows.

Masses: each segment is a rigid body with mass, centre-of-mass position (``com_torso`` and
``com_femur`` measured from the hip, ``com_tibia`` from the knee, as in [1]_, Table I) and
rotational inertia about its centre of mass.  Each actuator's rotor, geared with ratio N to
its joint, turns at N times the joint's relative rate ``w`` and adds ``N^2 J_rotor w^2 / 2``
to the kinetic energy: ``rotor_inertia`` = N^2 J_rotor, the same at the four joints (RABBIT
[2]_: N = 50, J_rotor = 3.32e-4 kg m^2).  The rotors are massless bodies whose angle is the
relative joint angle; the rotor's own rotation with the link carrying it (J_rotor times the
link's rate, N times smaller than the geared term, and its gyroscopic coupling) is neglected,
as in RABBIT's model [2]_.

Inputs ``tau = (tau_hip_st, tau_hip_sw, tau_knee_st, tau_knee_sw)``: the torque the torso
exerts on each femur and each femur on its tibia, conjugate (by virtual work) to the relative
angles ``q_femur_st - q_torso``, ``q_femur_sw - q_torso``, ``q_tibia_st - q_femur_st`` and
``q_tibia_sw - q_femur_sw``: ``B = d(relative angles)/dq ^T``, constant.

The floating-base model appends the hip position ``(x_hip, y_hip)``; it serves the
heel-strike impact (augmented linear system with the swing foot's contact Jacobian); the leg
relabelling happens in :mod:`walker.models.five_link`.

References
----------
.. [1] E. R. Westervelt, J. W. Grizzle, D. E. Koditschek, "Hybrid zero dynamics of planar
   biped walkers", IEEE TAC 48(1):42-56, 2003 (Table I: RABBIT's parameters).
.. [2] C. Chevallereau, G. Abba, Y. Aoustin, F. Plestan, E. R. Westervelt, C. Canudas de Wit,
   J. W. Grizzle, "RABBIT: a testbed for advanced control theory", IEEE Control Systems
   Magazine 23(5):57-79, 2003.
"""

from __future__ import annotations

from functools import cache

import sympy as sp

from walker.params import params_class
from walker.symbolic.codegen import Kernel
from walker.symbolic.mechanics import Body, LagrangianModel, derive
from walker.symbolic.models import _coords, _u

__all__ = [
    "FIVE_LINK_PARAMS",
    "COORDINATES",
    "B_MATRIX",
    "five_link",
    "five_link_extended",
    "five_link_kernels",
]

_names = params_class("five_link").names()
FIVE_LINK_PARAMS = _names[: _names.index("rotor_inertia") + 1]
"""The physical parameters the generated kernels take: ``FiveLinkParams``'s fields up to
``rotor_inertia``, the last physical one (read from the class, in its order)."""

COORDINATES = ("q_leg", "q_knee", "q_torso", "q_femur_sw", "q_tibia_sw")

# rows: d(relative joint angle)/dq; B is its transpose (virtual work)
_RELATIVE = sp.Matrix(
    [
        [1, sp.Rational(1, 2), -1, 0, 0],  # q_femur_st - q_torso
        [0, 0, -1, 1, 0],  # q_femur_sw - q_torso
        [0, -1, 0, 0, 0],  # q_tibia_st - q_femur_st
        [0, 0, 0, -1, 1],  # q_tibia_sw - q_femur_sw
    ]
)
B_MATRIX = _RELATIVE.T


def _symbols():
    return tuple(sp.Symbol(n, real=True) for n in FIVE_LINK_PARAMS)


def _absolute(q):
    """(tibia_st, femur_st, torso, femur_sw, tibia_sw) absolute angles from the coordinates."""
    leg, knee, torso, fsw, tsw = q
    return leg - knee / 2, leg + knee / 2, torso, fsw, tsw


def _geometry(q, hip, params):
    """Bodies and named points with the hip at ``hip``."""
    m_T, m_f, m_t, l_f, l_t, p_T, p_f, p_t, I_T, I_f, I_t, slope, g, I_r = params
    tst, fst, tor, fsw, tsw = _absolute(q)
    knee_st = hip - l_f * _u(fst)
    knee_sw = hip - l_f * _u(fsw)
    bodies = [
        Body("torso", m_T, hip + p_T * _u(tor), tor, I_T),
        Body("femur_st", m_f, hip - p_f * _u(fst), fst, I_f),
        Body("tibia_st", m_t, knee_st - p_t * _u(tst), tst, I_t),
        Body("femur_sw", m_f, hip - p_f * _u(fsw), fsw, I_f),
        Body("tibia_sw", m_t, knee_sw - p_t * _u(tsw), tsw, I_t),
        # massless rotors turning with the relative joint angles (reflected inertia N^2 J)
        Body("rotor_hip_st", sp.S.Zero, hip, fst - tor, I_r),
        Body("rotor_hip_sw", sp.S.Zero, hip, fsw - tor, I_r),
        Body("rotor_knee_st", sp.S.Zero, knee_st, tst - fst, I_r),
        Body("rotor_knee_sw", sp.S.Zero, knee_sw, tsw - fsw, I_r),
    ]
    points = {
        "stance_contact": knee_st - l_t * _u(tst),
        "stance_knee": knee_st,
        "hip": hip,
        "swing_knee": knee_sw,
        "swing_contact": knee_sw - l_t * _u(tsw),
        "torso": hip + p_T * _u(tor),
    }
    return bodies, points


@cache
def five_link() -> LagrangianModel:
    """Pinned five-link walker in :data:`COORDINATES` with the actuators ``B``.

    Returns
    -------
    LagrangianModel
        points ``stance_contact`` (origin), ``stance_knee``, ``hip``, ``swing_knee``,
        ``swing_contact``, ``torso`` (the torso's centre of mass).
    """
    params = _symbols()
    l_f, l_t = params[3], params[4]
    q, qd = _coords(COORDINATES)
    tst, fst = _absolute(q)[:2]
    hip = l_t * _u(tst) + l_f * _u(fst)
    bodies, points = _geometry(q, hip, params)
    points["stance_contact"] = sp.Matrix([0, 0])
    return derive("five_link", q, qd, bodies, params[12], params, points=points, B=B_MATRIX)


@cache
def five_link_extended() -> LagrangianModel:
    """Floating-base five-link walker: :data:`COORDINATES` then ``(x_hip, y_hip)``."""
    params = _symbols()
    names = (*COORDINATES, "x_hip", "y_hip")
    qq, qd = _coords(names)
    hip = sp.Matrix([qq[5], qq[6]])
    bodies, points = _geometry(qq[:5], hip, params)
    B = B_MATRIX.col_join(sp.zeros(2, 4))
    return derive("five_link_extended", qq, qd, bodies, params[12], params, points=points, B=B)


def five_link_kernels() -> list[Kernel]:
    """The kernels of ``walker/_generated/five_link.py``.

    Pinned model: the dynamics kernels of the passive walkers (``mass_matrix``, ``bias``,
    ``dmass``, ...), ``hip_jac``, ``ground_reaction(q, qd, qdd, p)``; floating base:
    ``ext_mass_matrix``, ``ext_swing_contact_jac``, ``ext_stance_contact_jac``.
    """
    from walker.symbolic.actuated import actuated_kernels

    qdd = sp.symbols(" ".join(f"{n}_ddot" for n in COORDINATES), real=True)
    return actuated_kernels(five_link(), five_link_extended(), qdd)
