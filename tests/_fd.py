"""Finite-difference Jacobians for the tests of the models' analytic Jacobians."""

import numpy as np


def rhs_jacobian_fd(rhs, phase, x, p, h=1e-6):
    """Central differences ``(f(x + h e_k) - f(x - h e_k)) / (2 h)``, column ``k``, of the
    vector field ``rhs(phase, t, x, p, out)`` (a numba model's signature) at t = 0."""
    n = x.shape[0]
    fd = np.empty((n, n))
    fp, fm = np.empty(n), np.empty(n)
    for k in range(n):
        e = np.zeros(n)
        e[k] = h
        rhs(phase, 0.0, x + e, p, fp)
        rhs(phase, 0.0, x - e, p, fm)
        fd[:, k] = (fp - fm) / (2 * h)
    return fd
