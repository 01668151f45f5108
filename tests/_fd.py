"""Finite-difference Jacobians for the tests of the models' analytic Jacobians."""

import numpy as np


def rhs_jacobian_fd(model, phase, x, p, h=1e-6):
    """Central differences ``(f(x + h e_k) - f(x - h e_k)) / (2 h)``, column ``k``, of the
    compiled vector field ``model.rhs(phase, x, p)`` (a :class:`walker.models.WalkerModel`)."""
    n = x.shape[0]
    fd = np.empty((n, n))
    for k in range(n):
        e = np.zeros(n)
        e[k] = h
        fd[:, k] = (model.rhs(phase, x + e, p) - model.rhs(phase, x - e, p)) / (2 * h)
    return fd
