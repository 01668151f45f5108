"""The three- and five-link walkers as serial chains, for the Newton–Euler checks of
``tests/test_actuated.py``, ``tests/test_five_link.py`` and ``tests/test_actuated_friction.py``.

Each walker's tree is split into serial chains that :func:`walker.symbolic.newton_euler.
inverse_dynamics` solves: A runs from the stance foot through the swing leg; B from the
stance foot to the torso through a stance leg of (almost) no mass; C is B's light stance
part alone, subtracted.  The functions give each chain's joint torques along a state and
its acceleration; the tests compare them with the model's joint torques.
"""

import math

import numpy as np
from numpy.testing import assert_allclose

from walker.symbolic.newton_euler import PlanarChain, inverse_dynamics

EPS = 1e-3  # mass of the (almost) massless stance links of chains B and C [kg]


def three_link_chains(P):
    """Chains A (stance leg with the hip mass, swing leg), B (light stance leg, torso) and
    C (the light stance leg) of the three-link walker with parameters ``P``."""
    a, b, r, L = P.com_from_foot, P.com_to_hip, P.leg_length, P.torso_length
    m_st, c_st = P.mass_leg + P.mass_hip, (P.mass_leg * a + P.mass_hip * r)
    c_st /= m_st
    I_st = P.mass_leg * (a - c_st) ** 2 + P.mass_hip * (r - c_st) ** 2
    return (
        PlanarChain([r, b], [[c_st, 0], [b, 0]], [m_st, P.mass_leg], [I_st, 0.0]),
        PlanarChain([r, L], [[a, 0], [L, 0]], [EPS, P.mass_torso], [0.0, 0.0]),
        PlanarChain([r], [[a, 0]], [EPS], [0.0]),
    )


def three_link_chain_torques(chains, x, dx, gravity):
    """Joint torques of chains A, B, C at state ``x`` (shape (8,)) with rates ``dx``.

    Relative joint angles of the two serial chains: link axes along foot -> hip,
    hip -> swing foot, hip -> torso.
    """
    chain_a, chain_b, chain_c = chains
    q, qd, qdd = x[:3], x[3:6], dx[3:6]
    phi_a = [q[0] + math.pi / 2, q[1] - q[0] - math.pi]
    phi_b = [q[0] + math.pi / 2, q[2] - q[0]]
    tau_a = inverse_dynamics(
        chain_a, phi_a, [qd[0], qd[1] - qd[0]], [qdd[0], qdd[1] - qdd[0]], gravity=gravity
    )
    tau_b = inverse_dynamics(
        chain_b, phi_b, [qd[0], qd[2] - qd[0]], [qdd[0], qdd[2] - qdd[0]], gravity=gravity
    )
    tau_c = inverse_dynamics(chain_c, phi_b[:1], qd[:1], qdd[:1], gravity=gravity)
    return tau_a, tau_b, tau_c


def assert_three_link_torques(chains, x, dx, tau, gravity):
    """The chains' torques at ``x`` with rates ``dx`` are the joint torques ``tau`` (1e-10
    N m): swing hip ``tau_2``, torso joint ``-tau_1 - tau_2`` (virtual work of
    B = [[1, 0], [0, 1], [-1, -1]]), stance foot 0."""
    tau_a, tau_b, tau_c = three_link_chain_torques(chains, x, dx, gravity)
    assert_allclose(tau_a[1], tau[1], rtol=0, atol=1e-10)
    assert_allclose(tau_b[1], -tau[0] - tau[1], rtol=0, atol=1e-10)
    assert_allclose(tau_a[0] + tau_b[0] - tau_c[0], 0.0, rtol=0, atol=1e-10)


def five_link_chains(P):
    """Chains A (stance tibia, stance femur, swing femur, swing tibia), B (light stance
    tibia and femur, torso) and C (the two light links) of the five-link walker ``P``."""
    lt, lf = P.length_tibia, P.length_femur
    mt, mf, it, i_f = P.mass_tibia, P.mass_femur, P.inertia_tibia, P.inertia_femur
    chain_a = PlanarChain(
        [lt, lf, lf, lt],
        [[lt - P.com_tibia, 0], [lf - P.com_femur, 0], [P.com_femur, 0], [P.com_tibia, 0]],
        [mt, mf, mf, mt],
        [it, i_f, i_f, it],
    )
    chain_b = PlanarChain(
        [lt, lf, P.com_torso],
        [[lt / 2, 0], [lf / 2, 0], [P.com_torso, 0]],
        [EPS, EPS, P.mass_torso],
        [0.0, 0.0, P.inertia_torso],
    )
    chain_c = PlanarChain([lt, lf], [[lt / 2, 0], [lf / 2, 0]], [EPS, EPS], [0.0, 0.0])
    return chain_a, chain_b, chain_c


# absolute angles (stance tibia, stance femur, torso, swing femur, swing tibia) from q
_T5 = np.array(
    [[1, -0.5, 0, 0, 0], [1, 0.5, 0, 0, 0], [0, 0, 1, 0, 0], [0, 0, 0, 1, 0], [0, 0, 0, 0, 1]]
)
# relative joint angles of the chains (link axes: foot -> knee -> hip -> knee -> foot;
# hip -> torso)
_REL_A = np.array([[1, 0, 0, 0, 0], [-1, 1, 0, 0, 0], [0, -1, 0, 1, 0], [0, 0, 0, -1, 1]])
_REL_B = np.array([[1, 0, 0, 0, 0], [-1, 1, 0, 0, 0], [0, -1, 1, 0, 0]])
_OFF_A = np.array([math.pi / 2, 0.0, math.pi, 0.0])
_OFF_B = np.array([math.pi / 2, 0.0, 0.0])


def five_link_chain_torques(chains, x, dx, gravity):
    """Joint torques of chains A, B, C at state ``x`` (shape (12,)) with rates ``dx``."""
    chain_a, chain_b, chain_c = chains
    a, ad, add = _T5 @ x[:5], _T5 @ x[5:10], _T5 @ dx[5:10]
    tau_a = inverse_dynamics(
        chain_a, _REL_A @ a + _OFF_A, _REL_A @ ad, _REL_A @ add, gravity=gravity
    )
    phi_b, phid_b, phidd_b = _REL_B @ a + _OFF_B, _REL_B @ ad, _REL_B @ add
    tau_b = inverse_dynamics(chain_b, phi_b, phid_b, phidd_b, gravity=gravity)
    tau_c = inverse_dynamics(chain_c, phi_b[:2], phid_b[:2], phidd_b[:2], gravity=gravity)
    return tau_a, tau_b, tau_c


def assert_five_link_torques(chains, x, dx, tau, gravity):
    """The chains' torques at ``x`` with rates ``dx`` are the joint torques ``tau`` (1e-10
    N m): swing knee ``tau_4``, swing hip ``tau_2``, torso joint ``-tau_1 - tau_2``, stance
    knee ``-tau_3`` (joint angle femur - tibia), stance foot 0."""
    tau_a, tau_b, tau_c = five_link_chain_torques(chains, x, dx, gravity)
    assert_allclose(tau_a[3], tau[3], rtol=0, atol=1e-10)
    assert_allclose(tau_a[2], tau[1], rtol=0, atol=1e-10)
    assert_allclose(tau_b[2], -tau[0] - tau[1], rtol=0, atol=1e-10)
    assert_allclose(tau_a[1] + tau_b[1] - tau_c[1], -tau[2], rtol=0, atol=1e-10)
    assert_allclose(tau_a[0] + tau_b[0] - tau_c[0], 0.0, rtol=0, atol=1e-10)
