"""Compiled pieces shared by the walkers: the fall threshold and impacts as augmented
linear systems.  (Accelerations and their Jacobian are generated kernels: ``accel`` and
``accel_jac`` in walker/_generated.)"""

import numpy as np
from numba import njit

from walker._linalg import solve_inplace

# A stance leg this far from the slope normal [rad] (70 degrees) means the walker is falling:
# no passive gait comes near it, and stopping there saves integrating the whole fall.
FALL_ANGLE = 1.2217304763960306


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
