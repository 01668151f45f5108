"""Recursive Newton–Euler inverse dynamics against the Lagrangian models, and inertia helpers.

The two derivations share nothing but the geometry: Newton–Euler balances forces and
moments link by link (Spong et al. section 7.5, as in the course); the Lagrangian path
differentiates energies with sympy.  Equal joint torques at random states and random
parameters check both.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from numpy.testing import assert_allclose
from test_symbolic import random_params

from walker.symbolic import models
from walker.symbolic.inertia import (
    box_inertia,
    parallel_axis,
    planar_parallel_axis,
    rod_inertia,
)
from walker.symbolic.newton_euler import (
    PlanarChain,
    bias_forces,
    inverse_dynamics,
    mass_matrix,
)

N_STATES = 100
RTOL = 1e-12

# The course's double pendulum (its double-pendulum exercise):
# m1 = m2 = 1, I1 = I2 = 0.5, l = 1, a = 0.5 (joint to centre of mass), g = 10.
COURSE_DOUBLE_PENDULUM = {
    "mass_1": 1.0,
    "mass_2": 1.0,
    "inertia_1": 0.5,
    "inertia_2": 0.5,
    "length_1": 1.0,
    "length_2": 1.0,
    "com_1": 0.5,
    "com_2": 0.5,
    "g": 10.0,
}


class Lagrangian:
    """Numeric D, C, g of a symbolic model via lambdify (fresh, independent of codegen)."""

    def __init__(self, model):
        args = [list(model.q), list(model.qd), list(model.params)]
        self.model = model
        self._D = sp.lambdify(args, model.D, "numpy")
        self._C = sp.lambdify(args, model.C, "numpy")
        self._G = sp.lambdify(args, model.G, "numpy")

    def torque(self, q, qd, qdd, p):
        """``D qdd + C qd + g`` and a magnitude scale for the absolute tolerance."""
        D = np.asarray(self._D(q, qd, p), dtype=float)
        C = np.asarray(self._C(q, qd, p), dtype=float)
        G = np.asarray(self._G(q, qd, p), dtype=float).ravel()
        tau = D @ qdd + C @ qd + G
        scale = np.abs(D) @ np.abs(qdd) + np.abs(C) @ np.abs(qd) + np.abs(G)
        return tau, scale


def _random_states(rng, n, count=N_STATES):
    q = rng.uniform(-np.pi, np.pi, (count, n))
    qd = rng.normal(0.0, 2.0, (count, n))
    qdd = rng.normal(0.0, 5.0, (count, n))
    return q, qd, qdd


def _double_pendulum_chain(p: dict) -> PlanarChain:
    return PlanarChain(
        lengths=[p["length_1"], p["length_2"]],
        coms=[[p["com_1"], 0.0], [p["com_2"], 0.0]],
        masses=[p["mass_1"], p["mass_2"]],
        inertias=[p["inertia_1"], p["inertia_2"]],
    )


def _random_double_pendulum(rng) -> dict:
    l1, l2 = rng.uniform(0.3, 2.0, 2)
    return {
        "mass_1": rng.uniform(0.2, 3.0),
        "mass_2": rng.uniform(0.2, 3.0),
        "inertia_1": rng.uniform(0.0, 1.0),
        "inertia_2": rng.uniform(0.0, 1.0),
        "length_1": l1,
        "length_2": l2,
        # a centre of mass anywhere along the link, even beyond its ends
        "com_1": rng.uniform(-0.5, 1.5) * l1,
        "com_2": rng.uniform(-0.5, 1.5) * l2,
        "g": rng.uniform(1.0, 20.0),
    }


# The Newton-Euler chain has frictionless joints: the double pendulum's joint friction
# parameters (damping_1, damping_2, coulomb_1, coulomb_2) are zero in these comparisons.
FRICTIONLESS = {"damping_1": 0.0, "damping_2": 0.0, "coulomb_1": 0.0, "coulomb_2": 0.0}


def _as_vector(p: dict, model: str) -> np.ndarray:
    p = {**FRICTIONLESS, **p}
    return np.array([p[name] for name in models.MODEL_PARAMS[model]])


# ------------------------------------------------------------------ double pendulum / elbow
@pytest.mark.parametrize("factory", [models.double_pendulum, models.planar_elbow])
@pytest.mark.parametrize("params", ["course", "random"])
def test_two_link_arm_matches_lagrangian(factory, params):
    model = factory()
    lag = Lagrangian(model)
    rng = np.random.default_rng(20240501)
    q, qd, qdd = _random_states(rng, 2)
    for k in range(N_STATES):
        p = COURSE_DOUBLE_PENDULUM if params == "course" else _random_double_pendulum(rng)
        chain = _double_pendulum_chain(p)
        tau_ne = inverse_dynamics(chain, q[k], qd[k], qdd[k], gravity=(0.0, -p["g"]))
        tau_lag, scale = lag.torque(q[k], qd[k], qdd[k], _as_vector(p, "double_pendulum"))
        assert_allclose(tau_ne, tau_lag, rtol=RTOL, atol=RTOL * scale.max())


def test_planar_elbow_input_map_is_identity():
    """The elbow's joint torques enter one per joint: B = I, so tau = D qdd + C qd + g."""
    assert models.planar_elbow().B == sp.eye(2)


def test_mass_matrix_and_bias_split_the_torque():
    """``mass_matrix`` (unit accelerations, no gravity) and ``bias_forces`` reproduce the
    Lagrangian D and C qd + g separately, not only their sum."""
    model = models.double_pendulum()
    args = [list(model.q), list(model.qd), list(model.params)]
    D_fun = sp.lambdify(args, model.D, "numpy")
    h_fun = sp.lambdify(args, model.bias, "numpy")
    rng = np.random.default_rng(7)
    q, qd, _ = _random_states(rng, 2, 20)
    for k in range(20):
        p = _random_double_pendulum(rng)
        chain = _double_pendulum_chain(p)
        pv = _as_vector(p, "double_pendulum")
        D = np.asarray(D_fun(q[k], qd[k], pv), dtype=float)
        h = np.asarray(h_fun(q[k], qd[k], pv), dtype=float).ravel()
        D_ne = mass_matrix(chain, q[k])
        assert_allclose(D_ne, D, rtol=RTOL, atol=RTOL * np.abs(D).max())
        assert_allclose(D_ne, D_ne.T, rtol=0, atol=RTOL * np.abs(D).max())
        h_ne = bias_forces(chain, q[k], qd[k], gravity=(0.0, -p["g"]))
        assert_allclose(h_ne, h, rtol=RTOL, atol=1e-11 * (1 + np.abs(h).max()))


def test_gravity_direction_matters():
    """A sideways gravity gives different torques (the base-acceleration trick is not a no-op
    that happens to match for (0, -g) only)."""
    p = COURSE_DOUBLE_PENDULUM
    chain = _double_pendulum_chain(p)
    q, qd, qdd = np.array([0.3, -0.7]), np.array([0.2, 0.1]), np.zeros(2)
    down = inverse_dynamics(chain, q, qd, qdd, gravity=(0.0, -10.0))
    side = inverse_dynamics(chain, q, qd, qdd, gravity=(10.0, 0.0))
    # turning the whole picture by -90 degrees maps gravity (10, 0) to (0, -10) and the
    # first link's angle q1 to q1 - pi/2; the torques are unchanged
    turned = inverse_dynamics(chain, q - [np.pi / 2, 0.0], qd, qdd, gravity=(0.0, -10.0))
    assert np.abs(down - side).max() > 1.0
    assert_allclose(side, turned, rtol=1e-13, atol=1e-13)


# ---------------------------------------------------------------------------- kneed walker
def _lump(parts):
    """Combine point masses / rigid bodies fixed in one link frame into one body.

    parts : list of (mass, (x, y), inertia about own CoM).  Returns (mass, com, inertia about
    the combined CoM), the inertia by the planar parallel-axis theorem.
    """
    mass = sum(m for m, _, _ in parts)
    com = sum(m * np.asarray(r, dtype=float) for m, r, _ in parts) / mass
    inertia = sum(planar_parallel_axis(i, m, r[0] - com[0], r[1] - com[1]) for m, r, i in parts)
    return mass, com, inertia


def _kneed_chain(pv) -> tuple[PlanarChain, float]:
    """The kneed walker's single-support phase as a 3-link chain rooted at the stance foot.

    Link 1: the whole stance leg (foot to hip, along ``u(q1)``), carrying the stance shank,
    the stance thigh and the hip mass, lumped into one rigid body.  Link 2: the swing thigh
    (hip to knee, along ``-u(q2)``).  Link 3: the swing shank (knee to foot, ``-u(q3)``).
    In each link frame ``x`` runs along the link and ``y = z x x``: for link 1 ``y = -w(q1)``,
    for links 2 and 3 ``y = +w`` (``u = (-sin q, cos q)``, ``w = (cos q, sin q)`` as in
    :mod:`walker.symbolic.models`), so a fore-aft offset ``off * w`` has ``y = -off`` on the
    stance leg and ``+off`` on the swing leg.
    """
    (m_h, m_t, m_s, a1, b1, a2, b2, I_t, I_s, off_t, off_s, R, slope, g) = pv[:14]
    assert R == 0.0, "the chain has a pinned point foot"
    l_s, l_t = a1 + b1, a2 + b2
    L = l_s + l_t
    stance = _lump(
        [
            (m_s, (a1, -off_s), I_s),
            (m_t, (L - b2, -off_t), I_t),
            (m_h, (L, 0.0), 0.0),
        ]
    )
    chain = PlanarChain(
        lengths=[L, l_t, l_s],
        coms=[stance[1], [b2, off_t], [b1, off_s]],
        masses=[stance[0], m_t, m_s],
        inertias=[stance[2], I_t, I_s],
    )
    return chain, g


# theta = T q + c maps the models' absolute angles to the chain's relative joint angles:
# link 1 points along u(q1), at q1 + pi/2 from +x; links 2, 3 along -u, at q - pi/2.
KNEED_T = np.array([[1.0, 0.0, 0.0], [-1.0, 1.0, 0.0], [0.0, -1.0, 1.0]])
KNEED_C = np.array([np.pi / 2, -np.pi, 0.0])


@pytest.mark.parametrize("offsets", [False, True], ids=["no_offsets", "offsets"])
def test_kneed_walker_matches_newton_euler(offsets):
    """Newton–Euler on the 3-link chain equals D qdd + C qd + g of ``kneed_unlocked`` after
    mapping the angles (theta = T q + c) and the torques back (tau_abs = T^T tau_rel: the
    power tau_rel . theta_dot = tau_rel . T q_dot)."""
    lag = Lagrangian(models.kneed_unlocked())
    rng = np.random.default_rng(1998 + offsets)
    q, qd, qdd = _random_states(rng, 3)
    for k in range(N_STATES):
        # point feet (the slope does not enter with them), no joint friction
        pv = random_params("kneed", rng, foot_radius=0.0, offsets=offsets)
        chain, g = _kneed_chain(pv)
        theta = KNEED_T @ q[k] + KNEED_C
        tau_rel = inverse_dynamics(
            chain, theta, KNEED_T @ qd[k], KNEED_T @ qdd[k], gravity=(0.0, -g)
        )
        tau_lag, scale = lag.torque(q[k], qd[k], qdd[k], pv)
        assert_allclose(KNEED_T.T @ tau_rel, tau_lag, rtol=RTOL, atol=RTOL * scale.max())


def test_kneed_chain_mapping_places_the_knee():
    """The chain's joint 3 (end of link 2) is the model's knee: checks the angle map and the
    link-frame conventions that the torque comparison relies on."""
    model = models.kneed_unlocked()
    knee_fun = sp.lambdify([list(model.q), list(model.params)], model.points["knee"])
    rng = np.random.default_rng(3)
    pv = random_params("kneed", rng, foot_radius=0.0)
    chain, _ = _kneed_chain(pv)
    q = rng.uniform(-1, 1, 3)
    th = KNEED_T @ q + KNEED_C
    knee = chain.lengths[0] * np.array([np.cos(th[0]), np.sin(th[0])]) + chain.lengths[1] * (
        np.array([np.cos(th[0] + th[1]), np.sin(th[0] + th[1])])
    )
    assert_allclose(knee, np.asarray(knee_fun(q, pv), float).ravel(), rtol=1e-14, atol=1e-14)


# ------------------------------------------------------------------------------- validation
def test_chain_validation_names_the_field():
    good = {"lengths": [1.0], "coms": [[0.5, 0.0]], "masses": [1.0], "inertias": [0.1]}
    with pytest.raises(ValueError, match="`masses` must be > 0"):
        PlanarChain(**{**good, "masses": [0.0]})
    with pytest.raises(ValueError, match="`coms` must have shape"):
        PlanarChain(**{**good, "coms": [0.5, 0.0]})
    with pytest.raises(ValueError, match="`inertias` must be >= 0"):
        PlanarChain(**{**good, "inertias": [-1.0]})
    with pytest.raises(ValueError, match="`lengths` must be finite|entries of `lengths`"):
        PlanarChain(**{**good, "lengths": [np.nan]})
    chain = PlanarChain(**good)
    with pytest.raises(ValueError, match="`qd` must have shape"):
        inverse_dynamics(chain, [0.0], [0.0, 1.0], [0.0], gravity=(0, -1))
    with pytest.raises(ValueError, match="`gravity` must have shape"):
        inverse_dynamics(chain, [0.0], [0.0], [0.0], gravity=-9.81)
    with pytest.raises(TypeError, match="`chain` must be a PlanarChain"):
        inverse_dynamics(good, [0.0], [0.0], [0.0], gravity=(0, -1))


# ---------------------------------------------------------------------------- inertia helpers
def test_rod_inertia_and_about_its_end():
    """Thin rod: m L^2 / 12 about the centre, m L^2 / 3 about an end (parallel axis)."""
    m, L = 2.5, 1.3
    rod = rod_inertia(m, L)
    assert_allclose(rod, np.diag([0.0, m * L**2 / 12, m * L**2 / 12]), rtol=1e-15, atol=0)
    end = parallel_axis(rod, m, [L / 2, 0.0, 0.0])
    assert_allclose(end, np.diag([0.0, m * L**2 / 3, m * L**2 / 3]), rtol=1e-15, atol=1e-15)


def test_box_inertia_course_example():
    """The course's box (Craig, Introduction to Robotics, Example 6.1): width w along x,
    length l along y, height h along z; about the centre ^C I = m/12 diag(l^2 + h^2,
    w^2 + h^2, l^2 + w^2), about a corner ^A I with diagonal m/3 (...) and products of
    inertia -m/4 (w l, h w, h l)."""
    m, w, l, h = 3.0, 0.4, 1.1, 0.7
    centre = box_inertia(m, w, l, h)
    assert_allclose(
        centre,
        m / 12 * np.diag([l**2 + h**2, w**2 + h**2, l**2 + w**2]),
        rtol=1e-15,
        atol=0,
    )
    corner = np.array(
        [
            [m / 3 * (l**2 + h**2), -m / 4 * w * l, -m / 4 * h * w],
            [-m / 4 * w * l, m / 3 * (w**2 + h**2), -m / 4 * h * l],
            [-m / 4 * h * w, -m / 4 * h * l, m / 3 * (l**2 + w**2)],
        ]
    )
    assert_allclose(parallel_axis(centre, m, [w / 2, l / 2, h / 2]), corner, rtol=1e-14, atol=0)


def test_parallel_axis_scalar_forms():
    """The course's component forms: ^A I_zz = ^C I_zz + m (x_c^2 + y_c^2) and, for the
    tensor's off-diagonal entry, ^A I_xy = ^C I_xy - m x_c y_c; planar_parallel_axis agrees."""
    rng = np.random.default_rng(11)
    a = rng.normal(size=(3, 3))
    inertia = a @ a.T
    m = 1.7
    p = rng.normal(size=3)
    moved = parallel_axis(inertia, m, p)
    assert_allclose(moved[2, 2], inertia[2, 2] + m * (p[0] ** 2 + p[1] ** 2), rtol=1e-14)
    assert_allclose(moved[0, 1], inertia[0, 1] - m * p[0] * p[1], rtol=1e-14)
    assert_allclose(planar_parallel_axis(inertia[2, 2], m, p[0], p[1]), moved[2, 2], rtol=1e-14)
    # moving back by -p from the new point is not the inverse: only the CoM is special
    assert not np.allclose(parallel_axis(moved, m, -p), inertia, rtol=1e-6)


def test_inertia_validation_names_the_argument():
    with pytest.raises(ValueError, match="`mass` must be a finite number > 0"):
        rod_inertia(0.0, 1.0)
    with pytest.raises(ValueError, match="`length` must be a finite number >= 0"):
        rod_inertia(1.0, -1.0)
    with pytest.raises(ValueError, match="`lz`"):
        box_inertia(1.0, 1.0, 1.0, np.inf)
    with pytest.raises(ValueError, match="`offset` must have shape"):
        parallel_axis(np.eye(3), 1.0, [1.0, 2.0])
    with pytest.raises(ValueError, match="`inertia_com` must be symmetric"):
        parallel_axis(np.triu(np.ones((3, 3))), 1.0, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="`mass`"):
        planar_parallel_axis(1.0, -2.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="`i_zz`"):
        planar_parallel_axis(-1.0, 2.0, 0.0, 0.0)
