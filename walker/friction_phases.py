"""A friction model's phase functions, written once over its generated kernels: the
vector field, its Jacobian, the joint torques, the mode choice and the friction-event reset
of one base phase, assembled from the compiled pieces of :mod:`walker.friction` (the modes,
the augmented stick/slip system, the guards; its module docstring describes them).

A model's phase functions are assembled once over its generated kernels
(:func:`phase_solve`, :func:`phase_accelerations`, :func:`phase_jacobian`,
:func:`phase_guards`, :func:`phase_settle`, :func:`phase_switch`), which a model passes as
arguments (numba compiles one specialization per kernel set): ``dynamics(x, p) -> (D, f,
qd)`` (the model's binding of :func:`dynamics` to its ``mass_matrix(q, p, D)``, ``bias(q, qd,
p, h)`` (``C qd + g``) and ``forcing(q, qd, p, f)`` (the viscous forcing, linear in ``qd``)),
``accel(q, qd, p, qdd)`` (the fused frictionless accelerations, viscous dampers included),
``dmass(q, p, dD)``, ``dbias_dq`` and ``dbias_dqd(q, qd, p, out)``.  The coordinates are ``q =
x[0:n]`` and the rates ``qd = x[v0:v0 + n]`` of the state ``x``, ``n = S.shape[1]``.  These
functions are inlined into the caller by numba (``inline="always"``): a kernel passed on
through a call that LLVM does not inline becomes a pointer to a Python object in the machine
code, which numba cannot cache.

Over these, :func:`phase_rhs`, :func:`phase_jac`, :func:`phase_torques`, :func:`phase_start`
and :func:`phase_reset` are a model's ``rhs``, ``jac``, ``joint_torques``, mode choice and
friction-event reset in one base phase, so that a model's own functions only bind its kernels
(:func:`joints` decodes a phase's modes).
"""

from __future__ import annotations

import numpy as np

from walker._jit import njit
from walker._linalg import solve_inplace
from walker.friction import (
    STICK,
    accelerations,
    accelerations_jacobian,
    decode,
    encode,
    guards,
    settle,
    slip_force,
    switch,
)
from walker.status import EVENT_CONTINUE, EVENT_TERMINAL, Status

__all__ = [
    "dynamics",
    "phase_solve",
    "phase_accelerations",
    "phase_jacobian",
    "phase_guards",
    "phase_settle",
    "phase_switch",
    "first_order",
    "first_order_jacobian",
    "joints",
    "phase_rhs",
    "phase_jac",
    "phase_torques",
    "phase_start",
    "phase_reset",
]

_LINEAR_SOLVE_FAILED = int(Status.LINEAR_SOLVE_FAILED)

# ---------------------------------------------------------------------------------------------
# A model's phase functions over its generated kernels (the module docstring): written once for
# compass_coulomb, double_pendulum and kneed_coulomb (each base phase of the kneed walker).


@njit(cache=True, error_model="numpy", inline="always")
def dynamics(mass_matrix, bias, forcing, x, v0, p, n):
    """``(D, f, qd)`` at state ``x``: the mass matrix (n, n), ``f = Q_viscous - C qd - g``
    (n,) and a copy of the rates ``x[v0:v0 + n]``.  A model binds its kernels in a function
    ``(x, p) -> (D, f, qd)`` that calls this one, the ``dynamics`` of the functions below."""
    q = x[0:n]
    qd = x[v0 : v0 + n].copy()
    D = np.empty((n, n))
    mass_matrix(q, p, D)
    h = np.empty(n)
    bias(q, qd, p, h)
    f = np.empty(n)
    forcing(q, qd, p, f)
    for i in range(n):
        f[i] -= h[i]
    return D, f, qd


@njit(cache=True, error_model="numpy", inline="always")
def phase_solve(dynamics, S, F, modes, x, p, qdd, lam):
    """:func:`accelerations` at state ``x`` in ``modes``: ``qdd[:n]`` and ``lam[:m]`` (the
    joint torques); returns False for a singular system."""
    m, n = S.shape
    D, f, _ = dynamics(x, p)
    return accelerations(D, f, S, F, modes[:m], qdd[:n], lam[:m])


@njit(cache=True, error_model="numpy", inline="always")
def phase_accelerations(dynamics, mass_matrix, accel, S, F, modes, x, v0, p, qdd):
    """Accelerations ``qdd[:n]`` for the vector field: with no joint stuck the fused
    ``accel`` kernel plus ``D^-1`` of the slip torques (nothing more without dry friction, so
    a frictionless model runs on its generated kernel alone); with a joint stuck, the
    augmented system (:func:`phase_solve`)."""
    m, n = S.shape
    Q = np.empty(n)
    kind = slip_force(S, F, modes[:m], Q)
    if kind == 0:
        lam = np.empty(m)
        phase_solve(dynamics, S, F, modes, x, p, qdd, lam)
        return
    accel(x[0:n], x[v0 : v0 + n], p, qdd[:n])
    if kind > 0:
        D = np.empty((n, n))
        mass_matrix(x[0:n], p, D)
        solve_inplace(D, Q)
        for i in range(n):
            qdd[i] += Q[i]


@njit(cache=True, error_model="numpy", inline="always")
def phase_jacobian(dynamics, forcing, dmass, dbias_dq, dbias_dqd, S, F, modes, x, p, a):
    """``d qdd / d(q, qd)`` (n, 2 n) into ``a``, exactly (:func:`accelerations_jacobian`).

    The forcing Jacobian: ``df/dq = -dh/dq`` and ``df/dqd = V - dh/dqd``, ``h = C qd + g``
    and ``V`` the viscous forcing's matrix (linear in ``qd`` and independent of ``q``), whose
    columns are probed with unit rates.
    """
    m, n = S.shape
    D, f, qd = dynamics(x, p)
    qdd = np.empty(n)
    lam = np.empty(m)
    accelerations(D, f, S, F, modes[:m], qdd, lam)
    q = x[0:n]
    dD = np.empty((n, n, n))
    dmass(q, p, dD)
    df_dq = np.empty((n, n))
    dbias_dq(q, qd, p, df_dq)
    dh_dqd = np.empty((n, n))
    dbias_dqd(q, qd, p, dh_dqd)
    df_dqd = np.empty((n, n))
    unit = np.zeros(n)
    col = np.empty(n)
    for k in range(n):
        unit[:] = 0.0
        unit[k] = 1.0
        forcing(q, unit, p, col)
        for i in range(n):
            df_dqd[i, k] = col[i] - dh_dqd[i, k]
            df_dq[i, k] = -df_dq[i, k]
    accelerations_jacobian(D, dD, df_dq, df_dqd, S, modes[:m], qdd, a)


@njit(cache=True, error_model="numpy", inline="always")
def phase_guards(dynamics, S, F, modes, x, v0, p, g):
    """The friction guards (:func:`guards`) into ``g[:2 m]``; the holding torques are solved
    for only when a joint sticks (otherwise the guards need the rates only)."""
    m, n = S.shape
    lam = np.zeros(m)
    stuck = False
    for j in range(m):
        stuck |= modes[j] == STICK
    if stuck:
        qdd = np.empty(n)
        phase_solve(dynamics, S, F, modes, x, p, qdd, lam)
    guards(S, F, modes[:m], x[v0 : v0 + n], lam, g)


@njit(cache=True, error_model="numpy", inline="always")
def phase_settle(dynamics, S, F, modes, x, v0, p):
    """Choose every joint's mode at state ``x`` (``modes[:m]`` in place, :func:`settle`)
    and write the rates, projected onto the stuck joints, into ``x[v0:v0 + n]``.  Returns
    False (``x`` unchanged) if a system is singular."""
    m, n = S.shape
    D, f, qd = dynamics(x, p)
    qd_new = np.empty(n)
    if not settle(D, f, S, F, qd, np.ones(m, dtype=np.bool_), modes[:m], qd_new):
        return False
    for i in range(n):
        x[v0 + i] = qd_new[i]
    return True


@njit(cache=True, error_model="numpy", inline="always")
def phase_switch(dynamics, S, F, modes, k, x, v0, p, x_new):
    """The reset of friction guard ``k`` (``2 j`` joint ``j``'s slip_stops, ``2 j + 1`` its
    stick_breaks; :func:`switch`) at state ``x``: new ``modes[:m]`` in place, the new rates
    into ``x_new[v0:v0 + n]``.  Returns False (``x_new`` unchanged) if a system is
    singular."""
    m, n = S.shape
    D, f, qd = dynamics(x, p)
    qd_new = np.empty(n)
    if not switch(D, f, S, F, qd, k // 2, k % 2 == 1, modes[:m], qd_new):
        return False
    for i in range(n):
        x_new[v0 + i] = qd_new[i]
    return True


@njit(cache=True, error_model="numpy")
def first_order(x, qdd, n, dx):
    """``dx = (qd, qdd)`` for a state ``x = (q, qd)`` of ``n`` coordinates."""
    for i in range(n):
        dx[i] = x[n + i]
        dx[n + i] = qdd[i]


@njit(cache=True, error_model="numpy")
def first_order_jacobian(a, n, J):
    """The state Jacobian ``[0, I; a]`` (2 n, 2 n) of ``dx = (qd, qdd)`` from ``a = d qdd /
    d(q, qd)`` (n, 2 n)."""
    J[:, :] = 0.0
    for i in range(n):
        J[i, n + i] = 1.0
        for c in range(2 * n):
            J[n + i, c] = a[i, c]


# ---------------------------------------------------------------------------------------------
# A model's rhs, jac, joint_torques, mode choice and friction reset over the phase functions
# above: each model's own functions bind its kernels and call these (inlined likewise).


@njit(cache=True, error_model="numpy")
def joints(code, p, i_coulomb, m):
    """``(modes, F)``: the modes (m,) of mode code ``code`` and the dry frictions
    ``p[i_coulomb:i_coulomb + m]`` [N m] (a view of ``p``)."""
    modes = np.empty(m, dtype=np.int64)
    decode(code, modes)
    return modes, p[i_coulomb : i_coulomb + m]


@njit(cache=True, error_model="numpy", inline="always")
def phase_rhs(dynamics, mass_matrix, accel, S, F, modes, x, p, dx):
    """The vector field ``dx = (qd, qdd)`` (:func:`phase_accelerations`,
    :func:`first_order`) of a model whose state is ``x = (q, qd)``, ``n = S.shape[1]``
    coordinates."""
    n = S.shape[1]
    qdd = np.empty(n)
    phase_accelerations(dynamics, mass_matrix, accel, S, F, modes, x, n, p, qdd)
    first_order(x, qdd, n, dx)


@njit(cache=True, error_model="numpy", inline="always")
def phase_jac(dynamics, forcing, dmass, dbias_dq, dbias_dqd, S, F, modes, x, p, J):
    """The Jacobian ``J`` (2 n, 2 n) of :func:`phase_rhs` (:func:`phase_jacobian`,
    :func:`first_order_jacobian`)."""
    n = S.shape[1]
    a = np.empty((n, 2 * n))
    phase_jacobian(dynamics, forcing, dmass, dbias_dq, dbias_dqd, S, F, modes, x, p, a)
    first_order_jacobian(a, n, J)


@njit(cache=True, error_model="numpy", inline="always")
def phase_torques(dynamics, S, F, modes, x, p):
    """The friction torque (m,) at each joint [N m] (:func:`phase_solve`): ``-+F`` while
    slipping, the holding torque while stuck."""
    m, n = S.shape
    qdd = np.empty(n)
    lam = np.empty(m)
    phase_solve(dynamics, S, F, modes, x, p, qdd, lam)
    return lam


@njit(cache=True, error_model="numpy", inline="always")
def phase_start(dynamics, S, F, modes, offset, x, v0, p):
    """Choose every joint's mode at state ``x`` (:func:`phase_settle`: ``modes[:m]`` in
    place, the rates projected in place) and return the phase ``offset + encode(modes[:m])``
    (``offset`` the first phase of the model's base phase); -1 if a system is singular."""
    m = S.shape[0]
    if not phase_settle(dynamics, S, F, modes, x, v0, p):
        return -1
    return offset + encode(modes[:m])


@njit(cache=True, error_model="numpy", inline="always")
def phase_reset(dynamics, S, F, modes, phase, offset, k, x, v0, p, x_new):
    """The reset ``(action, next phase, status)`` of friction guard ``k`` in ``phase``
    (:func:`phase_switch`; ``modes`` the phase's, changed in place): continue in ``offset +
    encode(modes[:m])``; a singular system ends the run (``LINEAR_SOLVE_FAILED``)."""
    m = S.shape[0]
    if not phase_switch(dynamics, S, F, modes, k, x, v0, p, x_new):
        return EVENT_TERMINAL, phase, _LINEAR_SOLVE_FAILED
    return EVENT_CONTINUE, offset + encode(modes[:m]), 0
