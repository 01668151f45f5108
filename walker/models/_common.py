"""Compiled pieces shared by the walkers: Lagrangian accelerations and their Jacobian,
and impacts as augmented linear systems."""

import numpy as np
from numba import njit

from walker._linalg import solve_inplace

# A stance leg this far from the slope normal [rad] (70 degrees) means the walker is falling:
# no passive gait comes near it, and stopping there saves integrating the whole fall.
FALL_ANGLE = 1.2217304763960306


@njit(cache=True)
def accelerations(D, h, qdd):
    """``qdd = -D^{-1} h`` (D and h are overwritten). Returns False if D is singular."""
    n = h.shape[0]
    for i in range(n):
        qdd[i] = -h[i]
    return solve_inplace(D, qdd)


@njit(cache=True)
def lagrange_jacobian(D, dD, dh_dq, dh_dqd, qdd, J, n, row0, col_q, col_qd):
    """Fill the acceleration rows of the state Jacobian ``J`` (``D qdd + h = 0``).

    ``d qdd / d q_k = -D^{-1} (dh/dq_k + dD/dq_k qdd)``, ``d qdd / d qd = -D^{-1} dh/dqd``.
    Rows ``row0 .. row0+n-1`` of J receive them, in the columns ``col_q[k]`` / ``col_qd[k]``
    of the state.  ``D`` is overwritten.
    """
    rhs = np.empty((n, 2 * n))
    for k in range(n):
        for i in range(n):
            s = dh_dq[i, k]
            for j in range(n):
                s += dD[k, i, j] * qdd[j]
            rhs[i, k] = -s
            rhs[i, n + k] = -dh_dqd[i, k]
    ok = solve_inplace(D, rhs)
    for i in range(n):
        for k in range(n):
            J[row0 + i, col_q[k]] += rhs[i, k]
            J[row0 + i, col_qd[k]] += rhs[i, n + k]
    return ok


@njit(cache=True)
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
