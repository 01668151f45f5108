"""Compiled pieces shared by the walkers: the fall threshold, the status values a reset
returns, impacts as augmented linear systems, the floating-base heel strike, the state after
an impact (:func:`relabel`), the resets of falls and heel strikes and the reset of a model with
joint friction after its base model's events; and the public names of the models with joint
friction.  (Accelerations and their Jacobian are generated kernels: ``accel`` and
``accel_jac`` in walker/_generated.)"""

import math
import sys

import numpy as np

from walker import friction as fr
from walker._jit import njit
from walker._linalg import solve_inplace
from walker.status import EVENT_CONTINUE, EVENT_IGNORE, EVENT_STRIDE, EVENT_TERMINAL, Status

JOINT_FRICTION_EXPORTS = (
    "N_X",
    "N_IMPULSE",
    "STATE_NAMES",
    "KERNEL_HASH",
    "JOINTS",
    "PHASE_NAMES",
    "GUARD_NAMES",
    "DIRECTIONS",
    "I_COULOMB",
    "rhs",
    "jac",
    "guards",
    "reset",
    "joint_torques",
    "phase_of",
    "modes_of",
    "start_phase",
)
"""The public names of a model with dry joint friction over :mod:`walker.friction_phases`
(the start of its ``__all__``)."""
BASE_EXPORTS = (
    "LIFT_AFFINE",
    "SECTION_NAMES",
    "SEGMENTS",
    "energy",
    "lift",
    "lift_jacobian",
    "points",
    "project",
    "swing_foot",
)
"""The public names a walker with joint friction takes unchanged from its base model (the
Poincare section, the energy, the swing foot and the drawing): :func:`joint_friction_walker`."""


def joint_friction_walker(module_name: str, base):
    """The ``__all__`` and the module ``__getattr__`` and ``__dir__`` (PEP 562) of the walker
    with joint friction ``module_name`` over its base model's module ``base``: its public
    names are :data:`JOINT_FRICTION_EXPORTS` and :data:`BASE_EXPORTS`, the latter ``base``'s
    own, which ``dir()`` (and so tab completion) lists with the module's own names."""

    def __getattr__(name: str):
        if name in BASE_EXPORTS:
            return getattr(base, name)
        raise AttributeError(f"module {module_name!r} has no attribute {name!r}")

    def __dir__():
        return sorted({*vars(sys.modules[module_name]), *BASE_EXPORTS})

    return [*JOINT_FRICTION_EXPORTS, *BASE_EXPORTS], __getattr__, __dir__


# The walker.status.Status values a reset map returns, as plain integers for compiled code.
FELL_BACKWARD = int(Status.FELL_BACKWARD)
FELL_FORWARD = int(Status.FELL_FORWARD)
TRIPPED = int(Status.TRIPPED)
NONPHYSICAL_IMPACT = int(Status.NONPHYSICAL_IMPACT)
LINEAR_SOLVE_FAILED = int(Status.LINEAR_SOLVE_FAILED)

# A stance leg this far from the slope normal [rad] (70 degrees) means the walker is falling:
# no passive gait comes near it, and stopping there saves integrating the whole fall.
FALL_ANGLE = 1.2217304763960306

MIN_STEP = 1e-8
"""A heel strike needs the swing foot ahead of the stance foot by more than ``MIN_STEP`` leg
lengths.  With straight rigid legs the foot height ``L (cos psi_stance - cos psi_swing)`` also
vanishes where the legs coincide (step length zero up to round-off): a swing leg passing
through the stance leg, which is a scuff, not a step.  A walker rocking back over its stance
foot crosses that zero with the height decreasing, and round-off decides the sign of the
step length there; the threshold makes it a scuff at every tolerance."""


@njit(cache=True, error_model="numpy")
def impact(M, J, qd_minus, qd_plus, impulse):
    """Solve ``[M, -J^T; J, 0] [qd_plus; impulse] = [M qd_minus; 0]``.

    Parameters
    ----------
    M : ndarray, shape (n, n)
        mass matrix.
    J : ndarray, shape (m, n)
        Jacobian of the ``m`` contact velocities that the plastic impact brings to zero.
    qd_minus : ndarray, shape (n,)
        rates just before the impact.
    qd_plus : ndarray, shape (n,)   (output)
        rates just after it.
    impulse : ndarray, shape (>= m,)   (output, first m entries)
        the contact impulses.

    Returns
    -------
    ok : bool
        False when the augmented system is singular.
    """
    n = M.shape[0]
    m = J.shape[0]
    A = np.zeros((n + m, n + m))
    b = np.zeros(n + m)
    for i in range(n):
        s = 0.0
        for j in range(n):
            A[i, j] = M[i, j]
            s += M[i, j] * qd_minus[j]
        b[i] = s
        for c in range(m):
            A[i, n + c] = -J[c, i]
            A[n + c, i] = J[c, i]
    ok = solve_inplace(A, b)
    for i in range(n):
        qd_plus[i] = b[i]
    for c in range(m):
        impulse[c] = b[n + c]
    return ok


@njit(cache=True, error_model="numpy")
def floating_base_state(q, qd, hip, hip_J, qf, qdf):
    """Floating-base coordinates ``(q, hip)`` and rates ``(qd, hip_J qd)`` from the pinned
    model's state, the hip position (2,) and its Jacobian (2, n)."""
    n = q.shape[0]
    for i in range(n):
        qf[i] = q[i]
        qdf[i] = qd[i]
    for r in range(2):
        qf[n + r] = hip[r]
        s = 0.0
        for j in range(n):
            s += hip_J[r, j] * qd[j]
        qdf[n + r] = s


@njit(cache=True, error_model="numpy")
def heel_strike_impact(M, J_swing, J_stance, qdf, slope, qdf_plus, impulse):
    """Plastic heel strike on the floating-base model.

    Solves ``[M, -J_sw^T; J_sw, 0] [qdf+; Lambda] = [M qdf-; 0]`` (the swing foot's material
    contact velocity vanishes), writes the impulse on the new stance foot in the slope frame
    ``(along the slope, normal to it)`` [N s] into ``impulse[:2]``, and returns
    ``(ok, lift)``: ``ok`` False for a singular system, ``lift`` the trailing (old stance)
    foot's contact velocity along the slope normal after the impact (> 0: it leaves the
    ground).
    """
    lam = np.empty(2)
    if not impact(M, J_swing, qdf, qdf_plus, lam):
        return False, 0.0
    s0, s1 = math.cos(slope), -math.sin(slope)
    n0, n1 = math.sin(slope), math.cos(slope)
    impulse[0] = lam[0] * s0 + lam[1] * s1
    impulse[1] = lam[0] * n0 + lam[1] * n1
    v0 = 0.0
    v1 = 0.0
    for j in range(qdf_plus.shape[0]):
        v0 += J_stance[0, j] * qdf_plus[j]
        v1 += J_stance[1, j] * qdf_plus[j]
    return True, v0 * n0 + v1 * n1


@njit(cache=True, error_model="numpy", inline="always")
def floating_base_heel_strike(
    points,
    hip_jac,
    ext_mass_matrix,
    ext_swing_contact_jac,
    ext_stance_contact_jac,
    q,
    qd,
    p,
    n_points,
    hip_row,
    slope,
    qdf_plus,
    impulse,
):
    """The plastic heel strike of a pinned model of ``n = q.shape[0]`` coordinates on its
    floating-base extension (``n + 2`` coordinates: ``q`` and the hip position).

    The generated kernels are passed as arguments: ``points(q, p, pts)`` (``n_points`` rows,
    the hip at row ``hip_row``), ``hip_jac(q, p, J)`` (2, n), and the floating-base
    ``ext_mass_matrix``, ``ext_swing_contact_jac`` and ``ext_stance_contact_jac`` (qf, p,
    out).  Writes the post-impact floating-base rates into ``qdf_plus`` (n + 2,) and the
    impulse on the new stance foot, ``(along the slope, normal to it)`` [N s], into
    ``impulse[:2]``; returns ``(ok, lift)`` as :func:`heel_strike_impact`.  The caller swaps
    the legs and judges the impact (normal impulse and lift-off positive, friction cone).
    """
    n = q.shape[0]
    pts = np.empty((n_points, 2))
    points(q, p, pts)
    hip_J = np.empty((2, n))
    hip_jac(q, p, hip_J)
    qf = np.empty(n + 2)
    qdf = np.empty(n + 2)
    floating_base_state(q, qd, pts[hip_row], hip_J, qf, qdf)
    M = np.empty((n + 2, n + 2))
    ext_mass_matrix(qf, p, M)
    Jsw = np.empty((2, n + 2))
    ext_swing_contact_jac(qf, p, Jsw)
    Jst = np.empty((2, n + 2))
    ext_stance_contact_jac(qf, p, Jst)
    return heel_strike_impact(M, Jsw, Jst, qdf, slope, qdf_plus, impulse)


@njit(cache=True, error_model="numpy")
def relabel(q, qd, order, x_new):
    """The state ``x_new`` with coordinates ``q[order]`` and rates ``qd[order]``: ``x_new[i] =
    q[order[i]]``, ``x_new[n + i] = qd[order[i]]`` for the ``n = len(order)`` coordinates (a
    leg swap, or a locked knee copying its thigh)."""
    n = len(order)
    for i in range(n):
        x_new[i] = q[order[i]]
        x_new[n + i] = qd[order[i]]


@njit(cache=True, error_model="numpy")
def fell(phase, forward):
    """The reset of a fall guard: the run ends ``FELL_FORWARD`` (``forward`` true) or
    ``FELL_BACKWARD``; returns ``(action, next phase, status)``."""
    return EVENT_TERMINAL, phase, FELL_FORWARD if forward else FELL_BACKWARD


@njit(cache=True, error_model="numpy")
def stride_end(phase, status):
    """The reset's ``(action, next phase, status)`` after a heel strike that returned
    ``status``: the stride ends (next phase 0), or the run on a nonzero status."""
    if status != 0:
        return EVENT_TERMINAL, phase, status
    return EVENT_STRIDE, 0, 0


@njit(cache=True, error_model="numpy", inline="always")
def touchdown(swing_foot, heel_strike, leg_length, phase, x, p, x_new, impulse):
    """The reset of a walker whose swing foot touches the slope at ``x``: a touchdown no more
    than ``MIN_STEP`` leg lengths (``leg_length``) ahead of the stance foot is a scuff
    (ignored), any other the heel strike ``heel_strike(x, p, x_new, impulse)`` that ends the
    stride (:func:`stride_end`).  ``swing_foot(x, p)`` returns (height, distance ahead)."""
    if swing_foot(x, p)[1] <= MIN_STEP * leg_length:
        return EVENT_IGNORE, phase, 0
    return stride_end(phase, heel_strike(x, p, x_new, impulse))


@njit(cache=True, error_model="numpy")
def passive_impact_status(impulse, lift):
    """The judgement of a heel strike without a friction cone: 0 when the normal impulse
    ``impulse[1]`` is positive and the trailing foot lifts off (``lift > 0``),
    ``NONPHYSICAL_IMPACT`` otherwise."""
    if not (impulse[1] > 0.0) or not (lift > 0.0):
        return NONPHYSICAL_IMPACT
    return 0


@njit(cache=True, error_model="numpy", inline="always")
def after_base_reset(start, phase, action, new_base, status, x_new, p):
    """The reset of a model with joint friction at one of its base model's events (heel
    strike, knee lock, falls): ``(action, new_base, status)`` is the base model's reset at
    ``x_new``; after a real event every joint's mode is chosen afresh there by
    ``start(new_base, x_new, p)`` (the new phase, rates projected in place; -1 if singular).
    Returns the reset's ``(action, next phase, status)``."""
    if action == EVENT_IGNORE or action == EVENT_TERMINAL:
        return action, phase, status
    new_phase = start(new_base, x_new, p)
    if new_phase < 0:
        return EVENT_TERMINAL, phase, LINEAR_SOLVE_FAILED
    return action, new_phase, status


# ---------------------------------------------------------------------------------------------
# The actuated walkers with joint friction (three_link, five_link), written once over the
# model's ``forces(x, p, D, f, u)`` (mass matrix D (n, n), generalized force without dry
# friction f (n,) and controller torque u (m,) at state ``x``; returns True when the torque
# saturated), its joint rows ``S`` (m, n) (``S = B^T``: the joints are the actuated ones, so
# there are as many torques as joints) and the joints' dry-friction magnitudes ``F`` (m,).
# The coordinates are ``x[:n]``, the rates ``x[n:2 n]``.  model_three_link.c and
# model_five_link.c call their C ports in walker/_core/wk_actuated.c.


@njit(cache=True, error_model="numpy", inline="always")
def central_difference_jac(rhs, phase, t, x, p, J, rel_step):
    """``df/dx`` of ``rhs(phase, t, x, p, dx)`` in ``phase`` by central differences, step
    ``rel_step * max(1, |x_j|)``, into ``J`` (n, n)."""
    n = x.shape[0]
    xp = x.copy()
    fp = np.empty(n)
    fm = np.empty(n)
    for j in range(n):
        hstep = rel_step * max(1.0, abs(x[j]))
        xp[j] = x[j] + hstep
        rhs(phase, t, xp, p, fp)
        xp[j] = x[j] - hstep
        rhs(phase, t, xp, p, fm)
        xp[j] = x[j]
        for i in range(n):
            J[i, j] = (fp[i] - fm[i]) / (2.0 * hstep)


@njit(cache=True, error_model="numpy", inline="always")
def actuated_closed_loop(forces, S, F, phase, x, p, qdd, u, lam):
    """Closed-loop accelerations ``qdd`` (n,), torques ``u`` (m,) and dry-friction torques
    ``lam`` (m,) at ``x`` in ``phase`` (the joint-mode code); returns True when the controller
    saturated."""
    n = S.shape[1]
    D = np.empty((n, n))
    f = np.empty(n)
    sat = forces(x, p, D, f, u)
    modes = np.empty(S.shape[0], dtype=np.int64)
    fr.decode(phase, modes)
    fr.accelerations(D, f, S, F, modes, qdd, lam)
    return sat


@njit(cache=True, error_model="numpy", inline="always")
def actuated_torques(forces, S, x, p):
    """The controller's torques (m,) at ``x`` (the controller does not see the friction)."""
    n = S.shape[1]
    D = np.empty((n, n))
    f = np.empty(n)
    u = np.empty(S.shape[0])
    forces(x, p, D, f, u)
    return u


@njit(cache=True, error_model="numpy")
def slope_frame(v, slope):
    """(along the slope, normal to it) components of a world vector ``v`` (2,)."""
    return (
        v[0] * math.cos(slope) - v[1] * math.sin(slope),
        v[0] * math.sin(slope) + v[1] * math.cos(slope),
    )


@njit(cache=True, error_model="numpy", inline="always")
def slope_frame_force(ground_reaction, x, p, qdd, slope):
    """Ground force on the stance foot ``(F_t, F_n)`` [N] for the accelerations ``qdd`` (n,),
    from the generated ``ground_reaction(q, qd, qdd, p, F)`` (world frame)."""
    n = qdd.shape[0]
    F = np.empty(2)
    ground_reaction(x[:n], x[n : 2 * n], qdd, p, F)
    return slope_frame(F, slope)


@njit(cache=True, error_model="numpy", inline="always")
def actuated_ground_reaction(forces, ground_reaction, S, F, phase, x, p, slope):
    """Ground force on the stance foot ``(F_t, F_n)`` [N] in ``phase``."""
    qdd = np.empty(S.shape[1])
    u = np.empty(S.shape[0])
    lam = np.empty(S.shape[0])
    actuated_closed_loop(forces, S, F, phase, x, p, qdd, u, lam)
    return slope_frame_force(ground_reaction, x, p, qdd, slope)


@njit(cache=True, error_model="numpy", inline="always")
def actuated_force_guards(
    forces, ground_reaction, S, F, phase, x, p, mu, slope, g_contact, g_joints
):
    """The guards on forces in ``phase``: ``g_contact`` (3,) = ``(mu F_n - F_t, mu F_n + F_t,
    F_n)`` (slip forward, slip backward, lift-off) from the ground reaction on the stance foot
    for the closed-loop accelerations, ``g_joints`` (2 m,) the joints' friction guards
    (:func:`walker.friction.guards`)."""
    n = S.shape[1]
    qdd = np.empty(n)
    u = np.empty(S.shape[0])
    lam = np.empty(S.shape[0])
    actuated_closed_loop(forces, S, F, phase, x, p, qdd, u, lam)
    ft, fn = slope_frame_force(ground_reaction, x, p, qdd, slope)
    g_contact[0] = mu * fn - ft
    g_contact[1] = mu * fn + ft
    g_contact[2] = fn
    modes = np.empty(S.shape[0], dtype=np.int64)
    fr.decode(phase, modes)
    fr.guards(S, F, modes, x[n : 2 * n], lam, g_joints)


@njit(cache=True, error_model="numpy")
def impact_status(impulse, lift, mu):
    """The judgement of a heel strike on a floor with friction coefficient ``mu``: 0 when the
    normal impulse ``impulse[1]`` is positive, the impulse inside the friction cone
    ``|impulse[0]| <= mu impulse[1]`` and the trailing foot lifts off (``lift > 0``),
    ``NONPHYSICAL_IMPACT`` otherwise (:func:`passive_impact_status` within the cone)."""
    if not (abs(impulse[0]) <= mu * impulse[1]):
        return NONPHYSICAL_IMPACT
    return passive_impact_status(impulse, lift)


@njit(cache=True, error_model="numpy", inline="always")
def actuated_settle(forces, S, F, modes, free, x, p):
    """Choose the modes of the ``free`` joints at state ``x`` (in place), project the
    velocities of the stuck joints (in ``x``; :func:`walker.friction.settle`) and return the
    phase; -1 if singular."""
    n = S.shape[1]
    D = np.empty((n, n))
    f = np.empty(n)
    u = np.empty(S.shape[0])
    forces(x, p, D, f, u)
    qd_new = np.empty(n)
    if not fr.settle(D, f, S, F, x[n : 2 * n].copy(), free, modes, qd_new):
        return -1
    for i in range(n):
        x[n + i] = qd_new[i]
    return fr.encode(modes)


@njit(cache=True, error_model="numpy", inline="always")
def actuated_after_heel_strike(forces, S, F, phase, status, x_new, p):
    """The reset's ``(action, next phase, status)`` after a heel strike that returned
    ``status`` with the post-impact state ``x_new``: every joint's mode afresh there (rates
    projected in place), the stride ends; the run ends on a nonzero status or a singular
    system."""
    if status != 0:
        return EVENT_TERMINAL, phase, status
    m = S.shape[0]
    new_phase = actuated_settle(
        forces, S, F, np.zeros(m, dtype=np.int64), np.ones(m, dtype=np.bool_), x_new, p
    )
    if new_phase < 0:
        return EVENT_TERMINAL, phase, LINEAR_SOLVE_FAILED
    return EVENT_STRIDE, new_phase, 0


@njit(cache=True, error_model="numpy", inline="always")
def actuated_joint_event(forces, S, F, phase, event, x, p, x_new):
    """The reset of joint friction event ``event`` = ``2 j`` (joint j's slip_stops: plastic
    lock, then every joint's mode chosen again) or ``2 j + 1`` (its stick_breaks: it slips
    against its holding torque, the others chosen again) (:func:`walker.friction.switch`):
    writes the rates into ``x_new`` and returns ``(action, next phase, status)``."""
    n = S.shape[1]
    modes = np.empty(S.shape[0], dtype=np.int64)
    fr.decode(phase, modes)
    D = np.empty((n, n))
    f = np.empty(n)
    u = np.empty(S.shape[0])
    forces(x, p, D, f, u)
    qd_new = np.empty(n)
    j = event // 2
    breaks = event % 2 == 1
    if not fr.switch(D, f, S, F, x[n : 2 * n].copy(), j, breaks, modes, qd_new):
        return EVENT_TERMINAL, phase, LINEAR_SOLVE_FAILED
    for i in range(n):
        x_new[n + i] = qd_new[i]
    return EVENT_CONTINUE, fr.encode(modes), 0


@njit(cache=True, error_model="numpy", inline="always")
def actuated_start_phase(forces, S, F, x, p):
    """The phase consistent with state ``x``: the joints that move slip with the sign of
    their rate, the joints at rest stick or slip as the forces decide
    (:func:`walker.friction.choose_modes`)."""
    n = S.shape[1]
    D = np.empty((n, n))
    f = np.empty(n)
    u = np.empty(S.shape[0])
    forces(x, p, D, f, u)
    modes = np.zeros(S.shape[0], dtype=np.int64)
    fr.choose_modes(D, f, S, F, x[n : 2 * n].copy(), np.ones(S.shape[0], dtype=np.bool_), modes)
    return fr.encode(modes)


def ground_reaction_at(ground_reaction_in_phase, start_phase, x, p, phase):
    """The public ``ground_reaction(x, p, phase=None)`` of an actuated walker over its
    compiled ``ground_reaction_in_phase(phase, x, p)``: ``phase`` None is the phase consistent
    with ``x`` (``start_phase(x, p)``)."""
    x = np.ascontiguousarray(x, dtype=np.float64)
    p = np.ascontiguousarray(p, dtype=np.float64)
    if phase is None:
        phase = start_phase(x, p)
    return ground_reaction_in_phase(int(phase), x, p)
