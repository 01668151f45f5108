"""Checks of the symbolic layer: structure (skew symmetry, Hessian, energy), published closed
forms (Garcia, Goswami, Hsu Chen), limiting cases and refusal of stray symbols.

Everything is evaluated numerically through a fresh ``sympy.lambdify`` of the model's
matrices at random states and random parameters, so a wrong sign or factor anywhere in
:mod:`walker.symbolic.mechanics` or :mod:`walker.symbolic.models` shows up as a number.
"""

from __future__ import annotations

import zlib
from functools import cache

import numpy as np
import pytest
import sympy as sp
from numpy.testing import assert_allclose

from walker.symbolic import codegen, models
from walker.symbolic.mechanics import Body, derive

N_STATES = 100
TOL = 1e-12

MODEL_FACTORIES = {
    "compass": models.compass,
    "compass_extended": models.compass_extended,
    "kneed_unlocked": models.kneed_unlocked,
    "kneed_locked": models.kneed_locked,
    "kneed_extended": models.kneed_extended,
    "double_pendulum": models.double_pendulum,
}
FAMILY = {
    "compass": "compass",
    "compass_extended": "compass",
    "kneed_unlocked": "kneed",
    "kneed_locked": "kneed",
    "kneed_extended": "kneed",
    "double_pendulum": "double_pendulum",
}


# ----------------------------------------------------------------------------- helpers
def random_params(family: str, rng, *, foot_radius=None, inertia=True, offsets=True):
    """A random, physically sensible parameter vector in the canonical order of ``family``.

    Joint friction (the last entries of the compass, kneed and double-pendulum vectors) is
    zero: these tests check the conservative part (D, C, g); tests/test_damping.py and
    tests/test_double_pendulum_friction.py check the forcing."""
    if family == "compass":
        a, b = rng.uniform(0.2, 1.0, 2)
        R = rng.uniform(0.0, 0.3) if foot_radius is None else foot_radius
        return np.array(
            [
                rng.uniform(0.5, 10.0),  # mass_hip
                rng.uniform(0.5, 5.0),  # mass_leg
                a,
                b,
                rng.uniform(0.0, 0.5) if inertia else 0.0,  # inertia_leg
                R,
                rng.uniform(-0.2, 0.2),  # slope
                rng.uniform(1.0, 20.0),  # g
                0.0,  # damping_hip
                0.0,  # damping_ankle
            ]
        )
    if family == "kneed":
        a1, b1, a2, b2 = rng.uniform(0.05, 0.6, 4)
        R = rng.uniform(0.0, 0.3) if foot_radius is None else foot_radius
        return np.array(
            [
                rng.uniform(0.1, 2.0),  # mass_hip
                rng.uniform(0.1, 2.0),  # mass_thigh
                rng.uniform(0.02, 1.0),  # mass_shank
                a1,
                b1,
                a2,
                b2,
                rng.uniform(0.001, 0.1) if inertia else 0.0,  # inertia_thigh
                rng.uniform(0.001, 0.1) if inertia else 0.0,  # inertia_shank
                rng.uniform(-0.1, 0.1) if offsets else 0.0,  # offset_thigh
                rng.uniform(-0.1, 0.1) if offsets else 0.0,  # offset_shank
                R,
                rng.uniform(-0.2, 0.2),  # slope
                rng.uniform(1.0, 20.0),  # g
                0.0,  # damping_hip
                0.0,  # damping_knee
                0.0,  # damping_ankle
            ]
        )
    if family == "double_pendulum":
        l1, l2 = rng.uniform(0.3, 2.0, 2)
        return np.array(
            [
                rng.uniform(0.2, 3.0),
                rng.uniform(0.2, 3.0),
                rng.uniform(0.0, 1.0),
                rng.uniform(0.0, 1.0),
                l1,
                l2,
                rng.uniform(-0.5, 1.5) * l1,
                rng.uniform(-0.5, 1.5) * l2,
                rng.uniform(1.0, 20.0),
                0.0,  # damping_1
                0.0,  # damping_2
                0.0,  # coulomb_1
                0.0,  # coulomb_2
            ]
        )
    raise KeyError(family)


def random_state(model, rng):
    """Angles in [-pi, pi], hip positions and all rates normal."""
    q = np.array(
        [
            rng.normal(0.0, 1.0) if str(s).startswith(("x_", "y_")) else rng.uniform(-np.pi, np.pi)
            for s in model.q
        ]
    )
    qd = rng.normal(0.0, 2.0, model.n)
    return q, qd


class Numeric:
    """Fresh lambdified D, dD/dq_i, C, g, energy gradient and energy rate of a model."""

    def __init__(self, model):
        self.model = model
        q, qd, p = list(model.q), list(model.qd), list(model.params)
        args = [q, qd, p]
        self._D = sp.lambdify(args, model.D, "numpy")
        self._dD = sp.lambdify(args, [model.D.diff(qi) for qi in q], "numpy")
        self._C = sp.lambdify(args, model.C, "numpy")
        self._G = sp.lambdify(args, model.G, "numpy")
        self._hess = sp.lambdify(args, sp.hessian(model.K, qd), "numpy")
        energy = model.K + model.P
        self._grad = sp.lambdify(args, [sp.diff(energy, x) for x in q + qd], "numpy")
        self.accel = sp.symbols(f"accel_0:{model.n}", real=True)
        rate = model.energy_rate(sp.Matrix(qd + list(self.accel)))
        self._rate = sp.lambdify([q, qd, list(self.accel), p], rate, "numpy")

    def D(self, q, qd, p):
        return np.asarray(self._D(q, qd, p), dtype=float)

    def dD(self, q, qd, p):
        return np.asarray(self._dD(q, qd, p), dtype=float)

    def C(self, q, qd, p):
        return np.asarray(self._C(q, qd, p), dtype=float)

    def G(self, q, qd, p):
        return np.asarray(self._G(q, qd, p), dtype=float).ravel()

    def hessian_K(self, q, qd, p):
        return np.asarray(self._hess(q, qd, p), dtype=float)

    def passive_accel(self, q, qd, p):
        """``D^-1 (-C qd - g)``, solved numerically."""
        return np.linalg.solve(self.D(q, qd, p), -self.C(q, qd, p) @ qd - self.G(q, qd, p))

    def energy_rate(self, q, qd, qdd, p):
        """``dE/dx . f`` from ``LagrangianModel.energy_rate`` and its magnitude scale."""
        grad = np.asarray(self._grad(q, qd, p), dtype=float)
        scale = np.abs(grad) @ np.abs(np.concatenate([qd, qdd]))
        return float(self._rate(q, qd, qdd, p)), scale


def _seed(name: str) -> int:
    """A seed stable across processes (``hash`` of a str is salted per process)."""
    return zlib.crc32(name.encode())


@cache
def numeric(name: str) -> Numeric:
    return Numeric(MODEL_FACTORIES[name]())


def _random_points(num, name, offset):
    """N_STATES random ``(p, q, qd)`` of model ``name`` (numeric model ``num``), drawn from
    the seed ``offset + _seed(name)``."""
    rng = np.random.default_rng(offset + _seed(name))
    for _ in range(N_STATES):
        p = random_params(FAMILY[name], rng)
        q, qd = random_state(num.model, rng)
        yield p, q, qd


# -------------------------------------------------------------------------- structure
@pytest.mark.parametrize("name", list(MODEL_FACTORIES))
def test_Ddot_minus_2C_is_skew_symmetric(name):
    """``N = D_dot - 2 C`` with ``D_dot = sum_i dD/dq_i qd_i`` is skew-symmetric (Spong et al.,
    Robot Modeling and Control, property 7.1) — true only for the Christoffel form of C."""
    num = numeric(name)
    for p, q, qd in _random_points(num, name, 0):
        Ddot = np.tensordot(qd, num.dD(q, qd, p), axes=1)
        C = num.C(q, qd, p)
        N = Ddot - 2.0 * C
        scale = np.abs(Ddot).max() + 2.0 * np.abs(C).max()
        assert_allclose(N + N.T, 0.0, rtol=0, atol=TOL * scale)


@pytest.mark.parametrize("name", list(MODEL_FACTORIES))
def test_mass_matrix_is_hessian_of_kinetic_energy(name):
    """``D = d^2 K / d qd^2``; numerically at random states (K is evaluated independently
    of D through ``sp.hessian``), plus D symmetric positive definite."""
    num = numeric(name)
    for p, q, qd in _random_points(num, name, 1):
        D = num.D(q, qd, p)
        assert_allclose(D, num.hessian_K(q, qd, p), rtol=TOL, atol=TOL * np.abs(D).max())
        assert_allclose(D, D.T, rtol=0, atol=0)
        assert np.linalg.eigvalsh(D).min() > 0


@pytest.mark.parametrize("name", list(MODEL_FACTORIES))
def test_energy_is_conserved_along_the_passive_field(name):
    """``dE/dt = dE/dx . f(x)`` with ``f = [qd; D^-1 (-C qd - g)]`` vanishes."""
    num = numeric(name)
    for p, q, qd in _random_points(num, name, 2):
        qdd = num.passive_accel(q, qd, p)
        rate, scale = num.energy_rate(q, qd, qdd, p)
        assert abs(rate) <= TOL * scale, (rate, scale)


def test_energy_rate_detects_a_wrong_field():
    """Negative control for the test above: perturbing the accelerations by 1e-6 gives a
    rate far above the tolerance."""
    num = numeric("kneed_unlocked")
    rng = np.random.default_rng(5)
    p = random_params("kneed", rng)
    q, qd = random_state(num.model, rng)
    qdd = num.passive_accel(q, qd, p) + 1e-6
    rate, scale = num.energy_rate(q, qd, qdd, p)
    assert abs(rate) > 1e3 * TOL * scale


@pytest.mark.parametrize("damped", [False, True], ids=["garcia", "ankle_damper"])
def test_simplest_walker_matches_garcia(damped):
    """Garcia, Chatterjee, Ruina, Coleman (1998), J. Biomech. Eng. 120:281, eqs. for
    m/M -> 0 with g = l = 1: theta_dd = sin(theta - gamma),
    phi_dd = sin(theta - gamma) + sin(phi) (theta_d^2 - cos(theta - gamma)).
    For general g, l (time unit sqrt(l/g)): theta_dd = (g/l) sin(theta - gamma),
    phi_dd = (g/l) sin(theta - gamma) + sin(phi) (theta_d^2 - (g/l) cos(theta - gamma)).

    With the stance-ankle damper b (dimensionless, units M l^2 sqrt(g/l)), derived by hand
    from the same limit: the stance row gains -b sqrt(g/l) theta_d, the swing row's forcing
    is zero, and the swing row's theta_dd coefficient (1 - cos phi) carries the damper into
    phi_dd: theta_dd += -b sqrt(g/l) theta_d, phi_dd += -b sqrt(g/l) (1 - cos phi) theta_d.
    b = 0 is Garcia's model exactly."""
    s = models.simplest()
    accel = sp.lambdify([list(s["q"]), list(s["qd"]), list(s["params"])], s["qdd"], "numpy")
    rng = np.random.default_rng(1998 + damped)
    for k in range(N_STATES):
        th, ph = rng.uniform(-1.5, 1.5, 2)
        thd, phd = rng.normal(0.0, 1.0, 2)
        gamma = rng.uniform(-0.1, 0.1)
        g, l = (1.0, 1.0) if k % 2 == 0 else tuple(rng.uniform(0.5, 10.0, 2))
        b = rng.uniform(0.0, 2.0) if damped else 0.0
        w2 = g / l
        damper = -b * np.sqrt(w2) * thd
        expected = [
            w2 * np.sin(th - gamma) + damper,
            w2 * np.sin(th - gamma)
            + (1.0 - np.cos(ph)) * damper
            + np.sin(ph) * (thd**2 - w2 * np.cos(th - gamma)),
        ]
        got = np.asarray(accel([th, ph], [thd, phd], [gamma, g, l, b]), dtype=float).ravel()
        assert_allclose(got, expected, rtol=TOL, atol=TOL * (1 + thd**2 + w2 + b * abs(thd)))


@pytest.mark.parametrize("damped", [False, True], ids=["undamped", "ankle_damper"])
def test_simplest_walker_finite_mass_energy_rate(damped):
    """The finite-beta compass from which the simplest walker is the limit conserves energy,
    and with the stance-ankle damper loses it at the rate ``-b l^2 sqrt(g/l) theta_d^2``
    (per unit hip mass), at every beta."""
    s = models.simplest()
    model = s["model"]
    D = sp.lambdify([list(model.q), list(model.qd), list(model.params)], model.D, "numpy")
    h = sp.lambdify([list(model.q), list(model.qd), list(model.params)], model.forced_bias, "numpy")
    num = Numeric(model)
    rng = np.random.default_rng(4 + damped)
    for _ in range(N_STATES):
        slope, g, l = rng.uniform(-0.1, 0.1), rng.uniform(1, 10), rng.uniform(0.5, 2)
        b = rng.uniform(0.1, 2.0) if damped else 0.0
        p = np.array([slope, g, l, b, rng.uniform(1e-3, 1.0)])
        q, qd = rng.uniform(-1, 1, 2), rng.normal(0, 1, 2)
        qdd = np.linalg.solve(np.asarray(D(q, qd, p), float), -np.asarray(h(q, qd, p), float))
        rate, scale = num.energy_rate(q, qd, qdd.ravel(), p)
        expected = -b * l**2 * np.sqrt(g / l) * qd[0] ** 2
        assert_allclose(rate, expected, rtol=0, atol=TOL * scale)


# ------------------------------------------------------------------ published closed forms
def goswami_compass(q, qd, m_h, m, a, b, g):
    """Compass gait single support (point feet, point masses).

    Goswami, Thuilot, Espiau, INRIA RR-2996 (1996), with ``theta = [theta_ns, theta_s]``:
      M = [[m b^2, -m l b cos(theta_s - theta_ns)],
           [-m l b cos(theta_s - theta_ns), (m_H + m) l^2 + m a^2]],
      N = [[0, m l b sin(theta_s - theta_ns) theta_s_dot],
           [-m l b sin(theta_s - theta_ns) theta_ns_dot, 0]],
      g(theta) = [m b g sin(theta_ns), -(m_H l + m a + m l) g sin(theta_s)],
    l = a + b.  The report itself was not reachable through the search tool; these forms are
    checked against their restatement in JongRok-Lee/Passive_Dynamic_Walking_Robot,
    ``comapss-gait model/point foot model/state_equation.m`` (which cites RR-2996; stance,
    swing order; its C q_dot vector equals N theta_dot above after the permutation).

    Mapping: Goswami's angles are from the vertical with the same sense for both legs, as
    ours, so theta_s = q_stance, theta_ns = q_swing (the forms are also invariant under
    negating both angles, so the sense of rotation cannot hide an error); only the order
    differs: ours is (stance, swing).  Returned in our order.
    """
    q_st, q_sw = q
    qd_st, qd_sw = qd
    l = a + b
    c = np.cos(q_st - q_sw)
    s = np.sin(q_st - q_sw)
    # Goswami's order (ns, s)
    M = np.array([[m * b**2, -m * l * b * c], [-m * l * b * c, (m_h + m) * l**2 + m * a**2]])
    N = np.array([[0.0, m * l * b * s * qd_st], [-m * l * b * s * qd_sw, 0.0]])
    G = np.array([m * b * g * np.sin(q_sw), -(m_h * l + m * a + m * l) * g * np.sin(q_st)])
    P = np.array([[0, 1], [1, 0]])
    return P @ M @ P, P @ N @ P, P @ G


@pytest.mark.parametrize("with_inertia", [False, True])
def test_compass_matches_goswami(with_inertia):
    """D, C, g of ``compass()`` with point feet equal Goswami's closed forms.  With a leg
    inertia I about the leg's centre of mass (not in Goswami's model) each leg's
    I * (its angular rate)^2 / 2 adds I to both diagonal entries of D and nothing else."""
    num = Numeric(models.compass())
    rng = np.random.default_rng(1996)
    for _ in range(N_STATES):
        p = random_params("compass", rng, foot_radius=0.0, inertia=with_inertia)
        m_h, m, a, b, inertia, R, slope, g = p[:8]
        q, qd = random_state(num.model, rng)
        D, C, G = goswami_compass(q, qd, m_h, m, a, b, g)
        D = D + inertia * np.eye(2)
        scale = np.abs(D).max() * (1 + np.abs(qd).max())
        assert_allclose(num.D(q, qd, p), D, rtol=TOL, atol=TOL * scale)
        assert_allclose(num.C(q, qd, p), C, rtol=TOL, atol=TOL * scale)
        assert_allclose(num.G(q, qd, p), G, rtol=TOL, atol=TOL * np.abs(G).max())


def hsu_chen_kneed(q, qd, pv):
    """Kneed walker, point feet, five point masses: Hsu Chen (2007), "Passive dynamic walking
    with knees: a point foot model", MIT M.Eng. thesis, H, C (as B q_dot), G of the 3-link
    (knee free) and 2-link (knee locked) phases.

    The thesis PDF was not reachable; these forms were (a) derived by hand from the five-mass
    geometry for this test (velocities of the masses as sums of L, l_t, b1, b2 times the
    perpendiculars w(q_i), then D_ij the coefficient of q_i_dot q_j_dot; C from the
    Christoffel symbols of D_ij = k_ij cos(q_i - q_j), which gives
    C_kj = k_kj sin(q_k - q_j) q_j_dot) and (b) checked entry by entry against two public
    restatements of the thesis' matrices: JongRok-Lee/Passive_Dynamic_Walking_Robot,
    ``knee model/state_equation1.m`` (which cites the thesis) and a Julia port found by the
    search tool (``H_matrix_3link``, ``B_matrix_3link``, ``G_matrix_3link``, ``*_2link``).
    Thesis notation: l_s = a1 + b1, l_t = a2 + b2, L = l_s + l_t; angles as ours.

    Returns D3, C3, G3 for q of length 3, or D2, C2, G2 for length 2 (locked knee).
    """
    (m_h, m_t, m_s, a1, b1, a2, b2, I_t, I_s, off_t, off_s, R, slope, g) = pv[:14]
    l_s, l_t = a1 + b1, a2 + b2
    L = l_s + l_t
    h11 = m_s * a1**2 + m_t * (l_s + a2) ** 2 + (m_h + m_s + m_t) * L**2
    g1 = -(m_s * a1 + m_t * (l_s + a2) + (m_h + m_s + m_t) * L) * g * np.sin(q[0])
    if len(q) == 3:
        k12 = -(m_t * b2 + m_s * l_t) * L
        k13 = -m_s * b1 * L
        k23 = m_s * l_t * b1
        K = np.array(
            [[h11, k12, k13], [k12, m_t * b2**2 + m_s * l_t**2, k23], [k13, k23, m_s * b1**2]]
        )
        G = np.array([g1, (m_t * b2 + m_s * l_t) * g * np.sin(q[1]), m_s * b1 * g * np.sin(q[2])])
    else:
        k12 = -(m_t * b2 + m_s * (l_t + b1)) * L
        K = np.array([[h11, k12], [k12, m_t * b2**2 + m_s * (l_t + b1) ** 2]])
        G = np.array([g1, (m_t * b2 + m_s * (l_t + b1)) * g * np.sin(q[1])])
    diff = np.subtract.outer(q, q)  # q_i - q_j
    cos = np.where(np.eye(len(q), dtype=bool), 1.0, np.cos(diff))
    D = K * cos
    C = np.where(np.eye(len(q), dtype=bool), 0.0, K * np.sin(diff) * qd[None, :])
    return D, C, G


@pytest.mark.parametrize("phase", ["unlocked", "locked"])
@pytest.mark.parametrize("with_inertia", [False, True])
def test_kneed_matches_hsu_chen(phase, with_inertia):
    """D, C, g of the kneed walker (point feet, no offsets) equal Hsu Chen's closed forms.
    Inertias (not in the thesis' point-mass model) add to the diagonal of D only:
    I_s + I_t on the stance leg, I_t (3-link) / I_t + I_s (2-link) on the swing thigh/leg,
    I_s on the swing shank."""
    model = models.kneed_unlocked() if phase == "unlocked" else models.kneed_locked()
    num = Numeric(model)
    rng = np.random.default_rng(2007 + 10 * with_inertia + (phase == "locked"))
    for _ in range(N_STATES):
        p = random_params("kneed", rng, foot_radius=0.0, inertia=with_inertia, offsets=False)
        q, qd = random_state(model, rng)
        D, C, G = hsu_chen_kneed(q, qd, p)
        I_t, I_s = p[7], p[8]
        extra = [I_t + I_s, I_t, I_s] if phase == "unlocked" else [I_t + I_s, I_t + I_s]
        D = D + np.diag(extra)
        scale = np.abs(D).max() * (1 + np.abs(qd).max())
        assert_allclose(num.D(q, qd, p), D, rtol=TOL, atol=TOL * scale)
        assert_allclose(num.C(q, qd, p), C, rtol=TOL, atol=TOL * scale)
        assert_allclose(num.G(q, qd, p), G, rtol=TOL, atol=TOL * np.abs(G).max())


# --------------------------------------------------------------------------- limiting cases
def lumped_compass_params(pv):
    """The compass gait whose legs carry the kneed walker's thigh + shank as one rigid body:
    mass m_t + m_s at the combined centre of mass (from the foot), inertia about it by the
    parallel-axis theorem."""
    (m_h, m_t, m_s, a1, b1, a2, b2, I_t, I_s, off_t, off_s, R, slope, g) = pv[:14]
    assert off_t == 0 and off_s == 0, "the compass leg has no fore-aft offset"
    l_s = a1 + b1
    L = l_s + a2 + b2
    m = m_t + m_s
    a = (m_s * a1 + m_t * (l_s + a2)) / m
    inertia = I_s + I_t + m_s * (a1 - a) ** 2 + m_t * (l_s + a2 - a) ** 2
    # the same hip and ankle damping (kneed p[14], p[16] -> compass p[8], p[9])
    return np.array([m_h, m, a, L - a, inertia, R, slope, g, pv[14], pv[16]])


@pytest.mark.parametrize("foot_radius", [0.0, None], ids=["point_feet", "round_feet"])
def test_locked_kneed_walker_is_a_compass_gait(foot_radius):
    """kneed_locked equals compass with the lumped leg (D, C, g), with point and round feet."""
    kneed = Numeric(models.kneed_locked())
    compass = Numeric(models.compass())
    rng = np.random.default_rng(1990)
    for _ in range(N_STATES):
        pk = random_params("kneed", rng, foot_radius=foot_radius, offsets=False)
        pc = lumped_compass_params(pk)
        q, qd = random_state(kneed.model, rng)
        Dk = kneed.D(q, qd, pk)
        scale = np.abs(Dk).max() * (1 + np.abs(qd).max())
        assert_allclose(Dk, compass.D(q, qd, pc), rtol=TOL, atol=TOL * scale)
        assert_allclose(kneed.C(q, qd, pk), compass.C(q, qd, pc), rtol=TOL, atol=TOL * scale)
        Gk = kneed.G(q, qd, pk)
        assert_allclose(Gk, compass.G(q, qd, pc), rtol=TOL, atol=TOL * np.abs(Gk).max())


@pytest.mark.parametrize("damped", [False, True], ids=["undamped", "ankle_damper"])
def test_compass_with_vanishing_leg_mass_is_the_simplest_walker(damped):
    """Compass with leg masses beta at the feet (com_from_foot = 0), hip mass 1, no inertia,
    point feet: as beta -> 0 its accelerations, in Garcia's coordinates theta = q_stance +
    slope, phi = q_stance - q_swing, approach the simplest walker's.  The error is O(beta):
    with beta = 1e-9 the tolerance is 1e-7 relative.

    Damped: the compass gait's ``damping_ankle`` [N m s/rad] set to ``b M l^2 sqrt(g/l)``
    (M = 1) is the simplest walker's dimensionless ``damping_ankle = b``, in both rows --
    the swing equation's ``-b (1 - cos phi) theta_d`` included; the hip damper stays 0 (a
    finite hip torque on the massless swing leg has no limit)."""
    compass = models.compass()
    args = [list(compass.q), list(compass.qd), list(compass.params)]
    D = sp.lambdify(args, compass.D, "numpy")
    h = sp.lambdify(args, compass.forced_bias, "numpy")
    s = models.simplest()
    accel = sp.lambdify([list(s["q"]), list(s["qd"]), list(s["params"])], s["qdd"], "numpy")
    rng = np.random.default_rng(9 + damped)
    beta = 1e-9
    largest = 0.0
    for _ in range(N_STATES):
        slope, g, l = rng.uniform(-0.1, 0.1), rng.uniform(1, 10), rng.uniform(0.5, 2)
        b = rng.uniform(0.1, 2.0) if damped else 0.0
        pc = np.array([1.0, beta, 0.0, l, 0.0, 0.0, slope, g, 0.0, b * l**2 * np.sqrt(g / l)])
        q, qd = rng.uniform(-1, 1, 2), rng.normal(0, 1, 2)
        qdd = np.linalg.solve(np.asarray(D(q, qd, pc), float), -np.asarray(h(q, qd, pc), float))
        qdd = qdd.ravel()
        got = [qdd[0], qdd[0] - qdd[1]]
        theta = [q[0] + slope, q[0] - q[1]]
        theta_d = [qd[0], qd[0] - qd[1]]
        expected = np.asarray(accel(theta, theta_d, [slope, g, l, b]), dtype=float).ravel()
        scale = g / l + qd[0] ** 2 + b * np.sqrt(g / l) * abs(qd[0])
        assert_allclose(got, expected, rtol=1e-7, atol=1e-7 * scale)
        largest = max(largest, b * np.sqrt(g / l) * abs(qd[0]))
    if damped:
        assert largest > 1.0  # the damper term is far above the tolerance


@pytest.mark.parametrize("name", ["compass", "kneed_unlocked", "kneed_locked"])
def test_round_feet_reduce_to_point_feet(name):
    """R -> 0: D, C, g at R = 1e-9 differ from R = 0 by O(1e-9) (no 1/R anywhere), and at
    R = 0 the slope does not enter the single-support dynamics (it enters only through the
    rolling contact)."""
    num = numeric(name)
    family = FAMILY[name]
    i_R = models.MODEL_PARAMS[family].index("foot_radius")
    i_slope = models.MODEL_PARAMS[family].index("slope")
    rng = np.random.default_rng(17)
    for _ in range(N_STATES):
        p0 = random_params(family, rng, foot_radius=0.0)
        q, qd = random_state(num.model, rng)
        p_small = p0.copy()
        p_small[i_R] = 1e-9
        p_slope = p0.copy()
        p_slope[i_slope] += 0.3
        for f in (num.D, num.C, num.G):
            ref = f(q, qd, p0)
            scale = np.abs(ref).max() * (1 + np.abs(qd).max()) + 1.0
            assert_allclose(f(q, qd, p_small), ref, rtol=0, atol=1e-7 * scale)
            assert_allclose(f(q, qd, p_slope), ref, rtol=TOL, atol=TOL * scale)


def test_round_feet_change_the_dynamics():
    """Control for the test above: a 0.1 foot radius changes D by much more than 1e-7."""
    num = numeric("compass")
    rng = np.random.default_rng(18)
    p0 = random_params("compass", rng, foot_radius=0.0)
    p1 = p0.copy()
    p1[5] = 0.1
    q, qd = random_state(num.model, rng)
    assert np.abs(num.D(q, qd, p1) - num.D(q, qd, p0)).max() > 1e-3


# ------------------------------------------------------------------------- stray symbols
def test_derive_refuses_a_stray_symbol():
    x = sp.Symbol("x", real=True)
    xd = sp.Symbol("x_dot", real=True)
    m, g = sp.symbols("m g", positive=True)
    stray = sp.Symbol("stray_length", real=True)
    body = Body("bob", m, sp.Matrix([stray * sp.sin(x), -stray * sp.cos(x)]))
    with pytest.raises(ValueError, match=r"stray_length.*add them to `params`"):
        derive("pendulum", (x,), (xd,), [body], g, (m, g))
    # with the symbol declared the same model derives
    model = derive("pendulum", (x,), (xd,), [body], g, (m, g, stray))
    assert model.D[0, 0] == sp.expand(m * stray**2 * (sp.sin(x) ** 2 + sp.cos(x) ** 2))


def test_lowering_refuses_a_stray_symbol():
    q1 = sp.Symbol("q1", real=True)
    k = sp.Symbol("stray_k", real=True)
    kernel = codegen.Kernel("bad", (("q", (q1,)),), sp.Matrix([k * q1]))
    with pytest.raises(ValueError, match=r"kernel `bad`: symbols \['stray_k'\]"):
        codegen.lower(kernel)
    ok = codegen.Kernel("good", (("q", (q1,)), ("p", (k,))), sp.Matrix([k * q1]))
    assert codegen.lower(ok).name == "good"
