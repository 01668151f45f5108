"""Compiled pieces shared by the walkers: the fall threshold, the status values a reset
returns, impacts as augmented linear systems, the floating-base heel strike and the reset of a
model with joint friction after its base model's events.  (Accelerations and their Jacobian
are generated kernels: ``accel`` and ``accel_jac`` in walker/_generated.)"""

import math

import numpy as np
from numba import njit

from walker._linalg import solve_inplace
from walker.status import EVENT_IGNORE, EVENT_TERMINAL, Status

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
    J : ndarray, shape (m, n)
    qd_minus : ndarray, shape (n,)
    qd_plus : ndarray, shape (n,)   (output)
    impulse : ndarray, shape (>= m,)   (output, first m entries)

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
