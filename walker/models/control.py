"""The layout of the actuated walkers' controller block and the Bezier polynomials of their
virtual constraints.

The controllers run in the compiled vector field (``walker/_core/wk_control.c``): a model's
``rhs`` calls the controller with the pinned-model matrices ``D(q)``,
``h(q, qd) = C qd + g`` and the input map ``B``; the controller's parameters are a block of
the model's parameter vector ``p`` (for the three-link walker, ``p[CONTROL_OFFSET:]`` of
:class:`walker.params.ThreeLinkParams`).  Layout of the block ``c``:

====  =========================================================================
c[0]  mode: 0 off (zero torque), 1 joint-space PD, 2 virtual constraints (IO lin.);
      3 (finite-time controller on polynomial outputs)
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

__all__ = [
    "BEZIER_DEGREE",
    "MODE_OFF",
    "MODE_PD",
    "MODE_VIRTUAL_CONSTRAINTS",
    "bezier",
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
