"""Small dense linear solves for compiled code (no LAPACK call, no allocation per solve).

The systems solved on the hot path are tiny (mass matrices of 2-4 coordinates, impact
systems of up to 6 unknowns), where a plain Gaussian elimination with partial pivoting beats
a LAPACK call by its overhead alone.
"""

import numpy as np

from walker._jit import njit


@njit(cache=True, error_model="numpy")
def solve_inplace(A, b):
    """Solve ``A x = b`` by Gaussian elimination with partial pivoting, overwriting both.

    Parameters
    ----------
    A : ndarray, shape (n, n)
        destroyed.
    b : ndarray, shape (n,) or (n, k)
        overwritten with the solution.

    Returns
    -------
    ok : bool
        False when a pivot is zero or not finite (singular system); ``b`` is then garbage.
    """
    n = A.shape[0]
    scale = 0.0
    for i in range(n):
        for j in range(n):
            v = abs(A[i, j])
            if v > scale:
                scale = v
    tiny = scale * 1e-300 if scale > 0 else 1e-300
    for k in range(n):
        p = k
        big = abs(A[k, k])
        for i in range(k + 1, n):
            v = abs(A[i, k])
            if v > big:
                big = v
                p = i
        if not (big > tiny):
            return False
        if p != k:
            for j in range(n):
                A[k, j], A[p, j] = A[p, j], A[k, j]
            if b.ndim == 1:
                b[k], b[p] = b[p], b[k]
            else:
                for j in range(b.shape[1]):
                    b[k, j], b[p, j] = b[p, j], b[k, j]
        piv = A[k, k]
        for i in range(k + 1, n):
            f = A[i, k] / piv
            if f != 0.0:
                for j in range(k + 1, n):
                    A[i, j] -= f * A[k, j]
                if b.ndim == 1:
                    b[i] -= f * b[k]
                else:
                    for j in range(b.shape[1]):
                        b[i, j] -= f * b[k, j]
    for k in range(n - 1, -1, -1):
        if b.ndim == 1:
            s = b[k]
            for j in range(k + 1, n):
                s -= A[k, j] * b[j]
            b[k] = s / A[k, k]
        else:
            for c in range(b.shape[1]):
                s = b[k, c]
                for j in range(k + 1, n):
                    s -= A[k, j] * b[j, c]
                b[k, c] = s / A[k, k]
    return np.isfinite(b).all()
