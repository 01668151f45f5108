"""The compiled dry-friction layer (walker/friction.py) on random systems.

Checked against direct numpy linear algebra: the accelerations with stuck joints satisfy
``D qdd = f + S^T tau`` with ``S_k qdd = 0``; their Jacobian matches central differences;
the chosen modes at rest are the consistent ones (and the only consistent ones, found by
brute force); the plastic lock conserves the momentum the constraints leave free and never
adds kinetic energy.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from numpy.testing import assert_allclose

from walker import friction as fr

N_CASES = 40


def _random_system(rng, n=3, m=3):
    """A random SPD mass matrix (n, n), force f, joint rows S (m, n), frictions F."""
    A = rng.normal(size=(n, n))
    D = A @ A.T + n * np.eye(n)
    f = rng.normal(size=n) * 3.0
    S = np.zeros((m, n))
    S[0, 0] = 1.0  # an "ankle"
    for j in range(1, m):  # relative joints
        S[j, j - 1] = -1.0
        S[j, j] = 1.0
    F = rng.uniform(0.0, 2.0, size=m)
    return D, f, S, F


def _reference(D, f, S, F, modes):
    """qdd and joint torques by numpy: the augmented system of the stuck joints."""
    n = D.shape[0]
    stuck = [j for j, md in enumerate(modes) if md == fr.STICK]
    rhs = f.copy()
    for j, md in enumerate(modes):
        if md == fr.SLIP_POSITIVE:
            rhs -= F[j] * S[j]
        elif md == fr.SLIP_NEGATIVE:
            rhs += F[j] * S[j]
    k = len(stuck)
    A = np.zeros((n + k, n + k))
    A[:n, :n] = D
    for r, j in enumerate(stuck):
        A[:n, n + r] = -S[j]
        A[n + r, :n] = S[j]
    y = np.linalg.solve(A, np.concatenate([rhs, np.zeros(k)]))
    return y[:n], dict(zip(stuck, y[n:], strict=True))


def test_encode_decode_round_trip():
    modes = np.empty(3, dtype=np.int64)
    for code in range(27):
        fr.decode(code, modes)
        assert fr.encode(modes) == code
    assert fr.mode_names(2 + 3 * 1 + 9 * 0, ("ankle", "hip", "knee")) == (
        "ankle=stick hip=slip- knee=slip+"
    )


@pytest.mark.parametrize("seed", range(N_CASES))
def test_accelerations_solve_the_constrained_equations(seed):
    rng = np.random.default_rng(seed)
    D, f, S, F = _random_system(rng)
    modes = rng.integers(0, 3, size=3).astype(np.int64)
    qdd = np.empty(3)
    lam = np.empty(3)
    assert fr.accelerations(D, f, S, F, modes, qdd, lam)
    ref_qdd, ref_lam = _reference(D, f, S, F, modes)
    assert_allclose(qdd, ref_qdd, rtol=1e-12, atol=1e-12)
    for j, md in enumerate(modes):
        if md == fr.STICK:
            assert_allclose(lam[j], ref_lam[j], rtol=1e-12, atol=1e-12)
            assert abs(S[j] @ qdd) < 1e-12
        else:
            assert lam[j] == (-F[j] if md == fr.SLIP_POSITIVE else F[j])
    # Newton's law with every joint torque: D qdd = f + S^T lam.
    assert_allclose(D @ qdd, f + S.T @ lam, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("seed", range(10))
def test_accelerations_jacobian_matches_differences(seed):
    """A q-dependent toy: D(q) = D0 + diag(sin q) stays SPD; f = -K q - B qd + c q0 qd1."""
    rng = np.random.default_rng(100 + seed)
    n = 3
    D0, _, S, F = _random_system(rng)
    Kq = rng.normal(size=(n, n))
    Bq = rng.normal(size=(n, n))

    def parts(x):
        q, qd = x[:n], x[n:]
        D = D0 + np.diag(np.sin(q))
        dD = np.zeros((n, n, n))
        for k in range(n):
            dD[k, k, k] = np.cos(q[k])
        f = -Kq @ q - Bq @ qd + np.array([q[0] * qd[1], 0.0, 0.0])
        df_dq = -Kq.copy()
        df_dq[0, 0] += qd[1]
        df_dqd = -Bq.copy()
        df_dqd[0, 1] += q[0]
        return D, dD, f, df_dq, df_dqd

    modes = rng.integers(0, 3, size=3).astype(np.int64)
    x = rng.normal(size=2 * n)
    D, dD, f, df_dq, df_dqd = parts(x)
    qdd = np.empty(n)
    lam = np.empty(3)
    fr.accelerations(D, f, S, F, modes, qdd, lam)
    J = np.empty((n, 2 * n))
    assert fr.accelerations_jacobian(D, dD, df_dq, df_dqd, S, modes, qdd, J)

    def accel(x):
        D, _, f, _, _ = parts(x)
        out = np.empty(n)
        fr.accelerations(D, f, S, F, modes, out, np.empty(3))
        return out

    h = 1e-6
    fd = np.column_stack([(accel(x + h * e) - accel(x - h * e)) / (2 * h) for e in np.eye(2 * n)])
    assert_allclose(J, fd, rtol=1e-7, atol=1e-8)


def _consistent(D, f, S, F, modes, rest):
    qdd, lam = _reference(D, f, S, F, modes)
    for j, md in enumerate(modes):
        if md == fr.STICK and not abs(lam[j]) < F[j]:
            return False
        if md != fr.STICK and rest[j]:
            sign = 1.0 if md == fr.SLIP_POSITIVE else -1.0
            if not sign * (S[j] @ qdd) > 0:
                return False
    return True


@pytest.mark.parametrize("seed", range(N_CASES))
def test_choose_modes_finds_the_unique_consistent_modes(seed):
    """Joints at rest: the chosen combination is consistent, and brute force over all 27
    finds no other (maximal dissipation makes it unique)."""
    rng = np.random.default_rng(200 + seed)
    D, f, S, F = _random_system(rng)
    # Velocities with some joints at rest: w = S qd, choose w and solve for qd.
    w = rng.normal(size=3)
    rest = rng.random(3) < 0.7
    w[rest] = 0.0
    qd = np.linalg.solve(S, w)
    modes = np.zeros(3, dtype=np.int64)
    ok = fr.choose_modes(D, f, S, F, qd, np.ones(3, dtype=np.bool_), modes)
    for j in np.flatnonzero(~rest):
        assert modes[j] == (fr.SLIP_POSITIVE if w[j] > 0 else fr.SLIP_NEGATIVE)
    found = []
    for combo in itertools.product(range(3), repeat=int(rest.sum())):
        trial = modes.copy()
        trial[rest] = combo
        if any(trial[j] == fr.STICK and F[j] == 0.0 for j in range(3)):
            continue
        if _consistent(D, f, S, F, trial, rest):
            found.append(tuple(trial))
    assert ok
    assert found == [tuple(modes)]


def test_zero_friction_never_sticks():
    rng = np.random.default_rng(7)
    D, f, S, _ = _random_system(rng)
    F = np.zeros(3)
    modes = np.zeros(3, dtype=np.int64)
    assert fr.choose_modes(D, f, S, F, np.zeros(3), np.ones(3, dtype=np.bool_), modes)
    assert fr.STICK not in modes
    # The frictionless accelerations decide the directions.
    qdd = np.linalg.solve(D, f)
    for j in range(3):
        assert modes[j] == (fr.SLIP_POSITIVE if S[j] @ qdd > 0 else fr.SLIP_NEGATIVE)


def test_large_friction_sticks_every_joint_at_rest():
    rng = np.random.default_rng(8)
    D, f, S, _ = _random_system(rng)
    F = np.full(3, 1e6)
    modes = np.zeros(3, dtype=np.int64)
    assert fr.choose_modes(D, f, S, F, np.zeros(3), np.ones(3, dtype=np.bool_), modes)
    assert list(modes) == [fr.STICK] * 3


def test_fixed_joints_keep_their_mode():
    rng = np.random.default_rng(9)
    D, f, S, F = _random_system(rng)
    modes = np.array([fr.SLIP_NEGATIVE, 0, 0], dtype=np.int64)
    free = np.array([False, True, True])
    fr.choose_modes(D, f, S, F, np.zeros(3), free, modes)
    assert modes[0] == fr.SLIP_NEGATIVE


@pytest.mark.parametrize("seed", range(N_CASES))
def test_plastic_lock_keeps_free_momentum_and_loses_energy(seed):
    rng = np.random.default_rng(300 + seed)
    D, _, S, _ = _random_system(rng)
    modes = rng.integers(0, 3, size=3).astype(np.int64)
    qd = rng.normal(size=3)
    out = np.empty(3)
    assert fr.project_stuck(D, S, modes, qd, out)
    stuck = modes == fr.STICK
    assert_allclose(S[stuck] @ out, 0.0, atol=1e-12)
    # D (qd+ - qd-) = S_k^T Lambda: no momentum change along directions with S_k v = 0.
    free_dirs = np.linalg.svd(S[stuck])[2][stuck.sum() :] if stuck.any() else np.eye(3)
    assert_allclose(free_dirs @ (D @ (out - qd)), 0.0, atol=1e-12)
    assert out @ D @ out <= qd @ D @ qd + 1e-12


def test_guards_and_directions():
    S = np.array([[1.0, 0.0], [-1.0, 1.0]])
    F = np.array([0.5, 0.3])
    modes = np.array([fr.SLIP_NEGATIVE, fr.STICK], dtype=np.int64)
    g = np.empty(4)
    fr.guards(S, F, modes, np.array([-2.0, -2.0]), np.array([0.5, -0.1]), g)
    assert_allclose(g, [-2.0, 1.0, 1.0, 0.1 - 0.3], rtol=0, atol=1e-15)
    code = fr.encode(modes)
    assert fr.directions(code, 2) == [1, 1, -1, 1]
