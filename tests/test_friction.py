"""The compiled dry-friction layer (walker/_core/wk_friction.c) through a model that uses it
with three joints: the kneed walker with Coulomb joint friction (walker.models.kneed_coulomb)
in its unlocked phases, at random parameters and states.

Checked against direct numpy linear algebra on the generated mass matrix ``D`` and force
``f = Q - h``: in every phase the compiled accelerations satisfy ``D qdd = f + S^T tau`` with
``S_k qdd = 0`` for the stuck joints and ``tau_j = -/+ F_j`` for the slipping ones (the
augmented system solved by numpy), and the stuck joints' guards are ``|tau_j| - F_j``; the
phase chosen for joints at rest is consistent (and the only consistent one, found by brute
force); a plastic lock conserves the momentum the constraints leave free and never adds
kinetic energy.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from numpy.testing import assert_allclose

from walker.models import friction as fr
from walker.models import get_model
from walker.models import kneed_coulomb as KC
from walker.params import KneedCoulombParams

N_CASES = 40
MODEL = get_model("kneed_coulomb")
S = np.array([[1.0, 0.0, 0.0], [-1.0, 1.0, 0.0], [0.0, -1.0, 1.0]])
"""Joint rows of the unlocked phases: the stance ankle, the hip and the knee."""
N_BASE = 4  # knee_lock, swing_foot_contact, fall_forward, fall_backward


def _random_case(rng, friction=None):
    """Parameters (dampers and Coulomb frictions random) and a state near the walker's."""
    P = KneedCoulombParams.preset(KneedCoulombParams.PRESETS[0])
    F = rng.uniform(0.0, 2.0, 3) if friction is None else np.asarray(friction, dtype=float)
    P = P.replace(
        coulomb_ankle=F[0],
        coulomb_hip=F[1],
        coulomb_knee=F[2],
        damping_hip=rng.uniform(0.0, 0.5),
        damping_knee=rng.uniform(0.0, 0.5),
        damping_ankle=rng.uniform(0.0, 0.5),
    )
    x = np.concatenate([rng.uniform(-0.4, 0.4, 3), rng.normal(0.0, 2.0, 3)])
    return P.as_array(), F, x


def _system(p, x):
    """The generated ``D`` and ``f = Q - h`` of the unlocked phases at ``x``."""
    q, qd = x[:3], x[3:]
    D = MODEL.kernel("unlocked_mass_matrix", p, q)
    f = MODEL.kernel("unlocked_forcing", p, q, qd) - MODEL.kernel("unlocked_bias", p, q, qd)
    return D, f


def _modes(code):
    return [(code // 3**j) % 3 for j in range(3)]


def _reference(D, f, F, modes):
    """qdd and the stuck joints' torques by numpy: the augmented system of the stuck joints."""
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


def test_mode_names_and_codes():
    assert fr.mode_names(2 + 3 * 1 + 9 * 0, KC.JOINTS) == "ankle=stick hip=slip- knee=slip+"
    for code in range(27):
        labels = fr.labels_of(code, KC.JOINTS)
        assert fr.code_of(KC.JOINTS, labels) == code
        assert [fr.MODE_LABELS.index(labels[j]) for j in KC.JOINTS] == _modes(code)


@pytest.mark.parametrize("seed", range(N_CASES))
def test_accelerations_solve_the_constrained_equations(seed):
    """In every unlocked phase the compiled ``rhs`` is the numpy solution of the augmented
    system (1e-10 of the accelerations' scale), and each stuck joint's ``stick_breaks`` guard is
    ``|tau_j| - F_j`` with its holding torque ``tau_j``."""
    rng = np.random.default_rng(seed)
    p, F, x = _random_case(rng)
    D, f = _system(p, x)
    free = np.abs(np.linalg.solve(D, f)).max()  # the scale of the accelerations
    for code in range(27):
        modes = _modes(code)
        dx = MODEL.rhs(code, x, p)
        assert_allclose(dx[:3], x[3:], rtol=0, atol=0)
        qdd, lam = _reference(D, f, F, modes)
        scale = max(np.abs(qdd).max(), free)
        assert_allclose(dx[3:], qdd, rtol=1e-10, atol=1e-10 * scale)
        g = MODEL.guards(code, x, p)[N_BASE:]
        for j, md in enumerate(modes):
            if md == fr.STICK:
                assert abs(S[j] @ dx[3:]) <= 1e-10 * scale
                assert_allclose(g[2 * j + 1], abs(lam[j]) - F[j], rtol=1e-10, atol=1e-10)
                assert g[2 * j] == 1.0
            elif F[j] > 0:
                assert_allclose(g[2 * j], S[j] @ x[3:], rtol=1e-14, atol=1e-14)
                assert g[2 * j + 1] == 1.0


def _consistent(D, f, F, modes, rest):
    qdd, lam = _reference(D, f, F, modes)
    for j, md in enumerate(modes):
        if md == fr.STICK and not abs(lam[j]) < F[j]:
            return False
        if md != fr.STICK and rest[j]:
            sign = 1.0 if md == fr.SLIP_POSITIVE else -1.0
            if not sign * (S[j] @ qdd) > 0:
                return False
    return True


@pytest.mark.parametrize("seed", range(N_CASES))
def test_start_phase_finds_the_unique_consistent_modes(seed):
    """Joints at rest: the compiled start phase is consistent, and brute force over all 27
    finds no other (maximal dissipation makes it unique); moving joints slip with the sign
    of their rate."""
    rng = np.random.default_rng(200 + seed)
    p, F, x = _random_case(rng)
    w = rng.normal(size=3)
    rest = rng.random(3) < 0.7
    w[rest] = 0.0
    x[3:] = np.linalg.solve(S, w)
    modes = _modes(MODEL.start_phase(x, p))
    for j in np.flatnonzero(~rest):
        assert modes[j] == (fr.SLIP_POSITIVE if w[j] > 0 else fr.SLIP_NEGATIVE)
    D, f = _system(p, x)
    found = []
    for combo in itertools.product(range(3), repeat=int(rest.sum())):
        trial = np.array(modes)
        trial[rest] = combo
        if any(trial[j] == fr.STICK and F[j] == 0.0 for j in range(3)):
            continue
        if _consistent(D, f, F, trial, rest):
            found.append(tuple(int(m) for m in trial))
    assert found == [tuple(modes)]


def test_zero_friction_never_sticks():
    rng = np.random.default_rng(7)
    p, _, x = _random_case(rng, friction=np.zeros(3))
    x[3:] = 0.0
    modes = _modes(MODEL.start_phase(x, p))
    assert fr.STICK not in modes
    # The frictionless accelerations decide the directions.
    D, f = _system(p, x)
    qdd = np.linalg.solve(D, f)
    for j in range(3):
        assert modes[j] == (fr.SLIP_POSITIVE if S[j] @ qdd > 0 else fr.SLIP_NEGATIVE)


def test_large_friction_sticks_every_joint_at_rest():
    rng = np.random.default_rng(8)
    p, _, x = _random_case(rng, friction=np.full(3, 1e6))
    x[3:] = 0.0
    assert _modes(MODEL.start_phase(x, p)) == [fr.STICK] * 3


@pytest.mark.parametrize("seed", range(N_CASES))
def test_plastic_lock_keeps_free_momentum_and_loses_energy(seed):
    """The reset of a slipping joint's ``slip_stops`` guard locks it plastically and chooses
    the modes again: afterwards the locked and the stuck joints are at rest, ``D (qd+ -
    qd-)`` lies in the span of their rows (no momentum change along the free directions), and
    the kinetic energy does not increase."""
    rng = np.random.default_rng(300 + seed)
    p, F, x = _random_case(rng, friction=rng.uniform(0.1, 2.0, 3))
    j = int(rng.integers(3))
    modes = [int(m) for m in rng.integers(0, 2, size=3)]  # slipping joints
    code = sum(m * 3**i for i, m in enumerate(modes))
    action, after, status, x_new, _ = MODEL.reset(code, N_BASE + 2 * j, x, p)
    assert status == 0
    new_modes = _modes(after)
    locked = sorted({j} | {i for i in range(3) if new_modes[i] == fr.STICK})
    qd, qd_new = x[3:], x_new[3:]
    assert_allclose(S[locked] @ qd_new, 0.0, rtol=0, atol=1e-12)
    D, _ = _system(p, x)
    free_dirs = np.linalg.svd(S[locked])[2][len(locked) :]
    assert_allclose(free_dirs @ (D @ (qd_new - qd)), 0.0, rtol=0, atol=1e-12)
    assert qd_new @ D @ qd_new <= qd @ D @ qd + 1e-12
    assert_allclose(x_new[:3], x[:3], rtol=0, atol=0)


def test_directions():
    """Guard directions (2 per joint): slip_stops toward zero rate, stick_breaks upward."""
    code = fr.code_of(("ankle", "hip"), {"ankle": "slip-", "hip": "stick"})
    assert fr.directions(code, 2) == [1, 1, -1, 1]
    for code in range(27):
        assert list(MODEL.system.directions[code, N_BASE:]) == fr.directions(code, 3)
