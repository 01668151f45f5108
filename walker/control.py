"""Feedback controllers that run inside the compiled vector field of an actuated walker.

A model's ``rhs`` calls :func:`controller_torque` with the pinned-model matrices ``D(q)``,
``h(q, qd) = C qd + g`` and the input map ``B``; the controller's parameters are a block of
the model's parameter vector ``p`` (for the three-link walker, ``p[CONTROL_OFFSET:]`` of
:class:`walker.params.ThreeLinkParams`).  Layout of the block ``c``:

====  =========================================================================
c[0]  mode: 0 off (zero torque), 1 joint-space PD, 2 virtual constraints (IO lin.);
      3 (finite-time controller on polynomial outputs) is compiled C only
      (``walker/_core/wk_control.c``); here it gives NaN torques
c[1]  ``kp``;  c[2] ``kd``
c[3]  torque limit [N m]: every component is clipped to ``[-limit, limit]``
c[4]  ``theta_plus``;  c[5] ``theta_minus`` (phase variable range)
c[6:] Bezier coefficients, ``BEZIER_DEGREE + 1`` per output, output after output
====  =========================================================================

Phase variable and virtual constraints (Westervelt, Grizzle, Koditschek 2003 [1]_): the
phase is the stance angle ``theta = q[0]``, monotone over a step, normalized to
``s = (theta - theta_plus) / (theta_minus - theta_plus)`` (0 just after heel strike, 1 at the
designed heel strike).  The outputs are ``y = h(q) = q[1:] - h_d(s)`` with ``h_d`` Bezier
polynomials ``b(s) = sum_k a_k C(M, k) s^k (1 - s)^(M - k)``.

Mode 2, input-output linearization (computed torque): with ``qdd = D^{-1} (B u - h)``,
``ydd = H qdd + c`` where ``H = dh/dq`` and ``c = -b''(s) ds/dtheta^2 qd[0]^2``; solving
``ydd = v`` with ``v = -kp y - kd yd`` gives ``u = (H D^{-1} B)^{-1} (v + H D^{-1} h - c)``
(``L_g L_f h = H D^{-1} B``).  Mode 1, joint-space PD (no model): the actuators apply the
generalized forces ``-kp y - kd yd`` on the controlled coordinates ``q[1:]``, i.e.
``B[1:, :] u = -kp y - kd yd``.  Both are then saturated.

References
----------
.. [1] E. R. Westervelt, J. W. Grizzle, D. E. Koditschek, "Hybrid zero dynamics of planar
   biped walkers", IEEE TAC 48(1):42-56, 2003.
.. [2] J. W. Grizzle, G. Abba, F. Plestan, IEEE TAC 46(1):51-64, 2001.
"""

from __future__ import annotations

import numpy as np

from walker._jit import njit
from walker._linalg import solve_inplace

__all__ = [
    "BEZIER_DEGREE",
    "MODE_OFF",
    "MODE_PD",
    "MODE_VIRTUAL_CONSTRAINTS",
    "bezier",
    "outputs",
    "controller_torque",
]

BEZIER_DEGREE = 4
MODE_OFF = 0
MODE_PD = 1
MODE_VIRTUAL_CONSTRAINTS = 2
I_MODE, I_KP, I_KD, I_LIMIT, I_THETA_PLUS, I_THETA_MINUS, I_BEZIER = 0, 1, 2, 3, 4, 5, 6

# Binomial coefficients C(4, k), C(3, k), C(2, k).
_BINOM4 = np.array([1.0, 4.0, 6.0, 4.0, 1.0])
_BINOM3 = np.array([1.0, 3.0, 3.0, 1.0])
_BINOM2 = np.array([1.0, 2.0, 1.0])


@njit(cache=True, error_model="numpy")
def bezier(a, s):
    """Bezier polynomial of degree 4 and its first two derivatives in ``s``.

    ``b(s) = sum_k a_k C(4, k) s^k (1 - s)^(4 - k)``; the derivatives are Bezier polynomials
    of the forward differences of the coefficients.

    Parameters
    ----------
    a : ndarray, shape (5,)
        coefficients.
    s : float
        the normalized phase (any real; [0, 1] over a step).

    Returns
    -------
    (b, db/ds, d2b/ds2) : tuple of float
    """
    b = 0.0
    for k in range(5):
        b += a[k] * _BINOM4[k] * s**k * (1.0 - s) ** (4 - k)
    db = 0.0
    for k in range(4):
        db += 4.0 * (a[k + 1] - a[k]) * _BINOM3[k] * s**k * (1.0 - s) ** (3 - k)
    d2b = 0.0
    for k in range(3):
        d2b += 12.0 * (a[k + 2] - 2.0 * a[k + 1] + a[k]) * _BINOM2[k] * s**k * (1.0 - s) ** (2 - k)
    return b, db, d2b


@njit(cache=True, error_model="numpy")
def outputs(q, qd, c, y, yd, H, cterm):
    """Virtual-constraint outputs and their derivatives.

    Parameters
    ----------
    q, qd : ndarray, shape (n,)
    c : ndarray
        controller block (module docstring).
    y, yd : ndarray, shape (n - 1,)   (output)
        ``y = q[1:] - b(s)`` and its time derivative.
    H : ndarray, shape (n - 1, n)   (output)
        ``dy/dq``.
    cterm : ndarray, shape (n - 1,)   (output)
        ``ydd - H qdd = -b''(s) (ds/dtheta)^2 qd[0]^2``.
    """
    n = q.shape[0]
    M1 = BEZIER_DEGREE + 1
    ds = 1.0 / (c[I_THETA_MINUS] - c[I_THETA_PLUS])
    s = (q[0] - c[I_THETA_PLUS]) * ds
    for i in range(n - 1):
        b, b1, b2 = bezier(c[I_BEZIER + i * M1 : I_BEZIER + (i + 1) * M1], s)
        y[i] = q[i + 1] - b
        yd[i] = qd[i + 1] - b1 * ds * qd[0]
        for j in range(n):
            H[i, j] = 0.0
        H[i, 0] = -b1 * ds
        H[i, i + 1] = 1.0
        cterm[i] = -b2 * ds * ds * qd[0] * qd[0]


@njit(cache=True, error_model="numpy")
def controller_torque(q, qd, D, h, B, c, u):
    """Torque of the controller in block ``c``, saturated; returns True if it saturated.

    Parameters
    ----------
    q, qd : ndarray, shape (n,)
    D : ndarray, shape (n, n)
        mass matrix (not modified).
    h : ndarray, shape (n,)
        ``C qd + g`` (not modified).
    B : ndarray, shape (n, n - 1)
    c : ndarray
        controller block.
    u : ndarray, shape (n - 1,)   (output) [N m]
    """
    n = q.shape[0]
    m = n - 1
    mode = int(c[I_MODE])
    if mode == MODE_OFF:
        for i in range(m):
            u[i] = 0.0
        return False
    if mode > MODE_VIRTUAL_CONSTRAINTS:
        # mode 3 (finite-time, polynomial outputs) is compiled C only: wk_control.c
        for i in range(m):
            u[i] = np.nan
        return False
    y = np.empty(m)
    yd = np.empty(m)
    H = np.empty((m, n))
    cterm = np.empty(m)
    outputs(q, qd, c, y, yd, H, cterm)
    kp, kd = c[I_KP], c[I_KD]
    if mode == MODE_PD:
        # generalized PD forces on the controlled coordinates q[1:], realized by the
        # actuators: B[1:, :] u = -kp y - kd yd
        Ba = np.empty((m, m))
        for i in range(m):
            u[i] = -kp * y[i] - kd * yd[i]
            for j in range(m):
                Ba[i, j] = B[i + 1, j]
        solve_inplace(Ba, u)
    else:
        # X = D^{-1} [B | h]
        X = np.empty((n, m + 1))
        for i in range(n):
            for j in range(m):
                X[i, j] = B[i, j]
            X[i, m] = h[i]
        Dc = D.copy()
        solve_inplace(Dc, X)
        A = np.zeros((m, m))
        rhs = np.empty(m)
        for i in range(m):
            r = -kp * y[i] - kd * yd[i] - cterm[i]
            for k in range(n):
                for j in range(m):
                    A[i, j] += H[i, k] * X[k, j]
                r += H[i, k] * X[k, m]
            rhs[i] = r
        solve_inplace(A, rhs)
        for i in range(m):
            u[i] = rhs[i]
    limit = c[I_LIMIT]
    saturated = False
    for i in range(m):
        if u[i] > limit:
            u[i] = limit
            saturated = True
        elif u[i] < -limit:
            u[i] = -limit
            saturated = True
    return saturated
