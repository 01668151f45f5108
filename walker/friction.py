"""Dry (Coulomb) joint friction with stick and slip as phases and events: compiled pieces
that any model assembles from its own ``D``, forcing and joint rows.

A joint ``j`` has the rate ``w_j = S_j qd`` with a constant row ``S_j`` (joints are relative
angles, so ``S`` does not depend on ``q``; the stance "ankle" between the slope and the
stance leg has ``S = e_stance``).  A torque ``tau_j`` at joint ``j`` enters the equations of
motion as the generalized force ``S_j^T tau_j``:

    D(q) qdd = f(q, qd) + sum_j S_j^T tau_j,

``f`` being everything else (``-C qd - g``, the viscous dampers, actuator torques ``B u``).
Dry friction of magnitude ``F_j >= 0`` is, per joint, in one of three modes:

* ``SLIP_POSITIVE`` (``w_j > 0``): ``tau_j = -F_j``;
* ``SLIP_NEGATIVE`` (``w_j < 0``): ``tau_j = +F_j``;
* ``STICK`` (``w_j = 0``): ``tau_j = lambda_j``, the constraint torque that keeps
  ``S_j qdd = 0``, admissible while ``|lambda_j| < F_j``.

The stuck joints make an augmented linear system, as the impacts do::

    [D, -S_k^T; S_k, 0] [qdd; lambda_k] = [f + sum_slip S_j^T tau_j; 0]

(:func:`accelerations`).  No ``tanh`` smear: a mode is a discrete state, kept in the phase
index (:func:`encode`), and a mode changes only at an event:

* ``slip_stops`` (slipping joint): ``w_j`` through zero toward zero;
* ``stick_breaks`` (stuck joint): ``|lambda_j| - F_j`` increasing through zero.

At either event the modes of every joint at rest are chosen again (:func:`choose_modes`):
joints that move slip with the sign of their rate; for the joints at rest, the one
combination of stick / slip+ / slip- that is consistent (stuck: ``|lambda| < F``; slipping
from rest with sign ``s``: ``s S_j qdd > 0``).  With a positive definite ``D`` the
accelerations of joint friction minimize a strictly convex function (maximal dissipation,
[1]_), so the consistent combination is unique when one exists with strict inequalities;
on a tie (a tangency) the first combination consistent with non-strict inequalities is
taken.  ``F_j = 0`` never sticks.  A joint that starts to stick has its velocity projected
onto ``w_j = 0`` by the plastic lock ``[D, -S^T; S, 0] [qd+; Lambda] = [D qd-; 0]``
(:func:`project_stuck`); at a ``slip_stops`` event ``|w_j|`` is rounding-small, so this
changes the energy by O(w^2).

Energy: the friction torques do the power ``sum_j tau_j w_j = -sum_slip F_j |w_j|`` and the
stuck joints none, so over a slip interval joint ``j`` dissipates ``F_j |delta theta_j|``
exactly.

The phase index of a model with friction is ``base * 3**n_joints + code`` where ``code =
sum_j mode_j 3**j`` (:func:`encode`, :func:`decode`); ``base`` is the model's own phase
(the kneed walker's ``unlocked`` / ``locked``).  Guards: two per joint, ``2 j`` slip_stops and
``2 j + 1`` stick_breaks (:func:`guards`), with directions from :func:`directions`.

A model's phase functions over these pieces and its generated kernels (``rhs``, ``jac``,
mode choice and friction reset, written once for every friction model) are in
:mod:`walker.friction_phases`.

References
----------
.. [1] F. Pfeiffer, C. Glocker, *Multibody Dynamics with Unilateral Contacts*, Wiley, 1996
   (dry friction in joints as switching conditions on the constraint force).
.. [2] D. E. Stewart, "Rigid-body dynamics with friction and impact", SIAM Review 42(1):3-39,
   2000 (maximal dissipation; uniqueness of the accelerations).
"""

from __future__ import annotations

import numpy as np

from walker._jit import njit
from walker._linalg import solve_inplace

__all__ = [
    "SLIP_POSITIVE",
    "SLIP_NEGATIVE",
    "STICK",
    "MODE_LABELS",
    "W_TOL",
    "N_MODES",
    "encode",
    "decode",
    "accelerations",
    "slip_force",
    "accelerations_jacobian",
    "choose_modes",
    "project_stuck",
    "settle",
    "switch",
    "guards",
    "directions",
    "mode_names",
    "code_of",
    "labels_of",
]

SLIP_POSITIVE, SLIP_NEGATIVE, STICK = 0, 1, 2
N_MODES = 3
MODE_LABELS = ("slip+", "slip-", "stick")
W_TOL = 1e-12
"""|w| [rad/s] at or below which a joint rate counts as zero when modes are chosen."""


@njit(cache=True, error_model="numpy")
def encode(modes):
    """Mode code ``sum_j modes[j] 3**j``."""
    code = 0
    scale = 1
    for j in range(modes.shape[0]):
        code += modes[j] * scale
        scale *= N_MODES
    return code


@njit(cache=True, error_model="numpy")
def decode(code, modes):
    """Fill ``modes`` (n_joints,) from a mode code."""
    for j in range(modes.shape[0]):
        modes[j] = code % N_MODES
        code //= N_MODES


@njit(cache=True, error_model="numpy")
def _slip_torque(mode, F):
    if mode == SLIP_POSITIVE:
        return -F
    if mode == SLIP_NEGATIVE:
        return F
    return 0.0


@njit(cache=True, error_model="numpy")
def _system(D, S, modes):
    """The augmented matrix ``[D, -S_k^T; S_k, 0]`` of the stuck joints ``k``."""
    n = D.shape[0]
    k = 0
    for j in range(S.shape[0]):
        if modes[j] == STICK:
            k += 1
    A = np.zeros((n + k, n + k))
    for i in range(n):
        for c in range(n):
            A[i, c] = D[i, c]
    r = n
    for j in range(S.shape[0]):
        if modes[j] == STICK:
            for i in range(n):
                A[i, r] = -S[j, i]
                A[r, i] = S[j, i]
            r += 1
    return A


@njit(cache=True, error_model="numpy")
def accelerations(D, f, S, F, modes, qdd, lam):
    """Accelerations and stuck-joint torques in the given modes.

    Parameters
    ----------
    D : ndarray, shape (n, n)
        mass matrix.
    f : ndarray, shape (n,)
        generalized force without dry friction, ``-C qd - g + Q_v (+ B u)`` [N m].
    S : ndarray, shape (m, n)
        joint rows, ``w = S qd`` [rad/s].
    F : ndarray, shape (m,)
        dry-friction magnitudes [N m], >= 0.
    modes : ndarray of int64, shape (m,)
    qdd : ndarray, shape (n,)   (output) [rad/s^2]
    lam : ndarray, shape (m,)   (output)
        joint torque of each stuck joint [N m]; the friction torque ``-+F`` of a slipping
        one.

    Returns
    -------
    ok : bool
        False when the augmented system is singular.
    """
    n = D.shape[0]
    m = S.shape[0]
    A = _system(D, S, modes)
    b = np.zeros(A.shape[0])
    for i in range(n):
        b[i] = f[i]
    for j in range(m):
        tau = _slip_torque(modes[j], F[j])
        if tau != 0.0:
            for i in range(n):
                b[i] += S[j, i] * tau
    ok = solve_inplace(A, b)
    for i in range(n):
        qdd[i] = b[i]
    r = n
    for j in range(m):
        if modes[j] == STICK:
            lam[j] = b[r]
            r += 1
        else:
            lam[j] = _slip_torque(modes[j], F[j])
    return ok


@njit(cache=True, error_model="numpy")
def slip_force(S, F, modes, out):
    """The generalized force of the slipping joints' dry friction, ``sum_j S_j^T tau_j``,
    into ``out`` (n,); returns 0 if some joint is stuck (``out`` then unset), 1 if the force
    is nonzero, -1 if it is zero (no dry friction acts).  Lets a model with no stuck joint
    add ``D^-1 out`` to its fused frictionless accelerations instead of solving
    :func:`accelerations`."""
    for j in range(S.shape[0]):
        if modes[j] == STICK:
            return 0
    any_force = False
    for i in range(out.shape[0]):
        out[i] = 0.0
    for j in range(S.shape[0]):
        tau = _slip_torque(modes[j], F[j])
        if tau != 0.0:
            any_force = True
            for i in range(out.shape[0]):
                out[i] += S[j, i] * tau
    return 1 if any_force else -1


@njit(cache=True, error_model="numpy")
def accelerations_jacobian(D, dD, df_dq, df_dqd, S, modes, qdd, out):
    """``d qdd / d(q, qd)`` in the given modes, exactly.

    With ``A y = r`` the system of :func:`accelerations` (``S`` and the slip torques are
    constant), ``A dy = [df - dD qdd; 0]``.

    Parameters
    ----------
    D : ndarray, shape (n, n)
    dD : ndarray, shape (n, n, n)
        ``dD[k] = dD/dq_k``.
    df_dq, df_dqd : ndarray, shape (n, n)
        ``[i, k] = df_i/dq_k``, ``df_i/dqd_k``.
    S : ndarray, shape (m, n)
    modes : ndarray of int64, shape (m,)
    qdd : ndarray, shape (n,)
        the accelerations at this state (from :func:`accelerations`).
    out : ndarray, shape (n, 2 n)   (output)

    Returns
    -------
    ok : bool
    """
    n = D.shape[0]
    A = _system(D, S, modes)
    R = np.zeros((A.shape[0], 2 * n))
    for k in range(n):
        for i in range(n):
            s = df_dq[i, k]
            for c in range(n):
                s -= dD[k, i, c] * qdd[c]
            R[i, k] = s
            R[i, n + k] = df_dqd[i, k]
    ok = solve_inplace(A, R)
    for i in range(n):
        for c in range(2 * n):
            out[i, c] = R[i, c]
    return ok


@njit(cache=True, error_model="numpy")
def _consistent(D, f, S, F, modes, rest, strict, qdd, lam):
    if not accelerations(D, f, S, F, modes, qdd, lam):
        return False
    for j in range(S.shape[0]):
        if modes[j] == STICK:
            if strict:
                if not abs(lam[j]) < F[j]:
                    return False
            elif not abs(lam[j]) <= F[j]:
                return False
        elif rest[j]:
            wd = 0.0
            for i in range(D.shape[0]):
                wd += S[j, i] * qdd[i]
            if modes[j] == SLIP_NEGATIVE:
                wd = -wd
            if strict:
                if not wd > 0.0:
                    return False
            elif not wd >= 0.0:
                return False
    return True


@njit(cache=True, error_model="numpy")
def choose_modes(D, f, S, F, qd, free, modes):
    """Choose the modes of the joints marked ``free``; keep the others as given.

    Parameters
    ----------
    D, f, S, F
        as in :func:`accelerations`.
    qd : ndarray, shape (n,)
        velocities: a free joint with ``|S_j qd| > W_TOL`` slips with the sign of its rate;
        the free joints at rest are enumerated.
    free : ndarray of bool, shape (m,)
    modes : ndarray of int64, shape (m,)   (input and output)

    Returns
    -------
    ok : bool
        False when no combination is consistent even with non-strict inequalities, or a
        system is singular; ``modes`` then holds slip by sign (slip+ at rest).
    """
    m = S.shape[0]
    n = D.shape[0]
    rest = np.zeros(m, dtype=np.bool_)
    idx = np.empty(m, dtype=np.int64)
    r = 0
    for j in range(m):
        if not free[j]:
            continue
        w = 0.0
        for i in range(n):
            w += S[j, i] * qd[i]
        if w > W_TOL:
            modes[j] = SLIP_POSITIVE
        elif w < -W_TOL:
            modes[j] = SLIP_NEGATIVE
        else:
            rest[j] = True
            idx[r] = j
            r += 1
    if r == 0:
        return True
    qdd = np.empty(n)
    lam = np.empty(m)
    total = 1
    for _ in range(r):
        total *= N_MODES
    for strict in (True, False):
        # Stick first (digit 2 -> 0 order), so a tie prefers the joint at rest to stay.
        for c in range(total):
            code = c
            skip = False
            for a in range(r):
                mode = N_MODES - 1 - code % N_MODES
                code //= N_MODES
                j = idx[a]
                if mode == STICK and not F[j] > 0.0:
                    skip = True
                modes[j] = mode
            if skip:
                continue
            if _consistent(D, f, S, F, modes, rest, strict, qdd, lam):
                return True
    for a in range(r):
        modes[idx[a]] = SLIP_POSITIVE
    return False


@njit(cache=True, error_model="numpy")
def project_stuck(D, S, modes, qd, qd_out):
    """Velocities projected onto ``S_k qd = 0`` for the stuck joints ``k``, keeping ``D qd``
    in the directions the constraints leave free (the plastic lock
    ``[D, -S_k^T; S_k, 0] [qd+; Lambda] = [D qd; 0]``).  Returns False if singular."""
    n = D.shape[0]
    A = _system(D, S, modes)
    b = np.zeros(A.shape[0])
    for i in range(n):
        s = 0.0
        for c in range(n):
            s += D[i, c] * qd[c]
        b[i] = s
    ok = solve_inplace(A, b)
    for i in range(n):
        qd_out[i] = b[i]
    return ok


@njit(cache=True, error_model="numpy")
def settle(D, f, S, F, qd, free, modes, qd_out):
    """Choose the modes of the ``free`` joints (:func:`choose_modes`) and project the
    velocities onto the stuck joints (:func:`project_stuck`) into ``qd_out``.  Returns False
    if a system is singular."""
    choose_modes(D, f, S, F, qd, free, modes)
    for j in range(S.shape[0]):
        if modes[j] == STICK:
            return project_stuck(D, S, modes, qd, qd_out)
    for i in range(qd.shape[0]):
        qd_out[i] = qd[i]
    return True


@njit(cache=True, error_model="numpy")
def switch(D, f, S, F, qd, j, breaks, modes, qd_out):
    """The reset of joint ``j``'s friction event: new ``modes`` (in place) and velocities.

    ``breaks`` False (``slip_stops``): joint ``j``'s rate is made exactly zero by the plastic
    lock (it is rounding-small at the event) and every joint's mode is chosen again at that
    state.  ``breaks`` True (``stick_breaks``): joint ``j`` slips against its holding torque
    (``lambda > 0`` slips negative) and the other joints' modes are chosen again (the stuck
    ones' torques jump when a constraint goes).  Returns False if a system is singular.
    """
    m = S.shape[0]
    free = np.ones(m, dtype=np.bool_)
    if not breaks:
        only = np.full(m, SLIP_POSITIVE, dtype=np.int64)
        only[j] = STICK
        locked = np.empty(qd.shape[0])
        if not project_stuck(D, S, only, qd, locked):
            return False
        return settle(D, f, S, F, locked, free, modes, qd_out)
    qdd = np.empty(D.shape[0])
    lam = np.empty(m)
    if not accelerations(D, f, S, F, modes, qdd, lam):
        return False
    modes[j] = SLIP_NEGATIVE if lam[j] > 0.0 else SLIP_POSITIVE
    free[j] = False
    return settle(D, f, S, F, qd, free, modes, qd_out)


@njit(cache=True, error_model="numpy")
def guards(S, F, modes, qd, lam, g):
    """The two guards per joint: ``g[2 j] = w_j`` while slipping (slip_stops),
    ``g[2 j + 1] = |lambda_j| - F_j`` while stuck (stick_breaks); 1.0 where unused.

    A slipping joint without dry friction (``F_j = 0``) has no slip_stops guard either: its
    mode cannot change the dynamics (the slip torque is 0 either way) and it can never
    stick, so a frictionless model runs with the same events, bit for bit, as the model
    without this layer.  Its mode label may then disagree with the sign of its rate.
    """
    n = qd.shape[0]
    for j in range(S.shape[0]):
        if modes[j] == STICK:
            g[2 * j] = 1.0
            g[2 * j + 1] = abs(lam[j]) - F[j]
        elif not F[j] > 0.0:
            g[2 * j] = 1.0
            g[2 * j + 1] = 1.0
        else:
            w = 0.0
            for i in range(n):
                w += S[j, i] * qd[i]
            g[2 * j] = w
            g[2 * j + 1] = 1.0


def directions(code: int, n_joints: int) -> list[int]:
    """Guard directions (2 per joint) in the modes of ``code`` (Python side, for a model's
    ``DIRECTIONS`` table)."""
    out = []
    for _ in range(n_joints):
        mode = code % N_MODES
        code //= N_MODES
        out.append(1 if mode == SLIP_NEGATIVE else -1)  # slip_stops
        out.append(1)  # stick_breaks
    return out


def mode_names(code: int, joints: tuple[str, ...]) -> str:
    """``"hip=slip+ knee=stick"`` for a mode code (Python side, for phase names)."""
    parts = []
    for name in joints:
        parts.append(f"{name}={MODE_LABELS[code % N_MODES]}")
        code //= N_MODES
    return " ".join(parts)


def code_of(joints: tuple[str, ...], modes: dict[str, str]) -> int:
    """Mode code from ``{joint: label}`` (labels ``"slip+"``, ``"slip-"``, ``"stick"``;
    a joint not given is ``"slip+"``), validated (Python side, for a model's ``phase_of``)."""
    unknown = set(modes) - set(joints)
    if unknown:
        raise ValueError(f"joint modes must be given for {joints}, got {sorted(unknown)}")
    code = 0
    for i, name in enumerate(joints):
        label = modes.get(name, "slip+")
        if label not in MODE_LABELS:
            raise ValueError(f"mode of `{name}` must be one of {MODE_LABELS}, got {label!r}")
        code += MODE_LABELS.index(label) * N_MODES**i
    return code


def labels_of(code: int, joints: tuple[str, ...]) -> dict[str, str]:
    """``{joint: label}`` of a mode code: the inverse of :func:`code_of`."""
    if not 0 <= code < N_MODES ** len(joints):
        raise ValueError(f"`phase` must be in [0, {N_MODES ** len(joints)}), got {code}")
    out = {}
    for name in joints:
        out[name] = MODE_LABELS[code % N_MODES]
        code //= N_MODES
    return out
