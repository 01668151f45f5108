"""Grizzle's three-link walker in closed loop: virtual constraints, hybrid zero dynamics, the
full-order gait, energy balance, the compass-gait limit and Newton–Euler torques."""

import math
from functools import cache

import _hzd_gait as gait
import numpy as np
import pytest
from _chains import assert_three_link_torques, three_link_chains
from numpy.testing import assert_allclose

from walker.analysis.fixedpoint import find_fixed_point
from walker.models import get_model, hzd
from walker.models import three_link as TL
from walker.models.control import bezier
from walker.params import CompassParams, ThreeLinkParams
from walker.simulation.stride import StrideMap, simulate
from walker.status import Status

RNG = np.random.default_rng(20260308)
PERTURBATION = np.array([0.0, 0.02, 0.05, -0.05, 0.1])


@cache
def grizzle():
    return ThreeLinkParams.grizzle()


@cache
def hzd_orbit():
    return hzd.restricted_fixed_point(grizzle())


@cache
def full_orbit():
    """Full-order fixed point, Newton started from a perturbed section point."""
    S = StrideMap("three_link", grizzle())
    return find_fixed_point(S, hzd_orbit().section + PERTURBATION, tol=1e-12)


# ----------------------------------------------------------------------------- control pieces
def test_bezier_derivatives_match_differences():
    a = RNG.uniform(-1, 1, 5)
    e = 1e-4
    for s in (-0.1, 0.0, 0.37, 1.0):
        b, b1, b2 = bezier(a, s)
        fp, fm = bezier(a, s + e)[0], bezier(a, s - e)[0]
        # central differences: truncation e^2 b'''/6 ~ 1e-7 relative here; round-off of the
        # second difference eps/e^2 ~ 1e-8
        assert_allclose(b1, (fp - fm) / (2 * e), rtol=1e-6, atol=1e-9)
        assert_allclose(b2, (fp - 2 * b + fm) / e**2, rtol=1e-5, atol=1e-5)
    # end points interpolate the first and last coefficients
    assert_allclose(bezier(a, 0.0)[0], a[0], rtol=0, atol=1e-15)
    assert_allclose(bezier(a, 1.0)[0], a[4], rtol=0, atol=1e-15)


def test_params_validation():
    with pytest.raises(ValueError, match="`controller` must be 0, 1, 2 or 3"):
        grizzle().replace(controller=1.5)
    with pytest.raises(ValueError, match="`theta_minus` must differ"):
        grizzle().replace(theta_minus=grizzle().theta_plus)


# ------------------------------------------------------------------------ hybrid zero dynamics
def test_make_invariant_gives_hybrid_invariance():
    """Invariance h(Delta(q-)) = 0 and L_f h(Delta(q-, qd-)) = 0 after the adjustment (1e-12),
    and not before it."""
    raw = grizzle().replace(bezier_swing_1=0.0, bezier_torso_0=0.0, bezier_torso_1=0.0)
    gait.assert_not_invariant(raw)
    for seed_shift in range(3):
        free = RNG.uniform(-0.2, 0.2, 3)
        gait.invariant_design(
            raw.replace(
                theta_minus=-0.3 - 0.05 * seed_shift,
                slope=0.01 * seed_shift,
                bezier_swing_2=free[0],
                bezier_swing_3=0.3 + free[1],
                bezier_torso_2=free[2],
            )
        )


def test_restricted_map_multiplier_is_delta_zero_squared():
    """The numerical derivative of rho equals the closed form delta_zero^2 (Westervelt et al.
    2003): central differences with step 1e-5 on a map integrated at rtol 1e-12 -> ~1e-9."""
    gait.assert_restricted_map_multiplier(grizzle(), hzd_orbit())


def test_zero_dynamics_equals_closed_loop_on_the_surface():
    """On Z the closed-loop stance accelerations equal the zero dynamics' (y = 0 exactly)."""
    P = grizzle()
    thetas = np.linspace(P.theta_plus, P.theta_minus, 5)
    gait.assert_zero_dynamics_on_surface(TL, P, thetas, lambda: RNG.uniform(-2.0, -0.5))


# ------------------------------------------------------------------------- full-order gait
def test_closed_loop_converges_to_period_one_gait():
    """From a perturbed start the walker converges to the HZD orbit on level ground."""
    # contraction 0.52 per stride: 0.52^25 * 0.1 ~ 1e-8
    start = hzd_orbit().section + PERTURBATION
    gait.converged_run("three_link", grizzle(), start, 25, hzd_orbit().section)


def test_full_order_fixed_point_agrees_with_hzd():
    """Z is invariant under the closed loop, so the full-order orbit IS the HZD orbit and
    rho' = delta_zero^2 is an eigenvalue of the full-order Jacobian; with kp = 100, kd = 20
    the transverse multipliers (~1e-4) are far smaller, so it is the dominant one.  The
    orbit agrees to the integration tolerance (1e-10); the multiplier to 1e-7, the accuracy of
    the central-difference vector-field Jacobian (step 1e-6) in the variational equations."""
    gait.assert_full_order_is_hzd(full_orbit(), hzd_orbit(), section_atol=1e-10)


@pytest.mark.regression_pin
def test_scene_reference_is_the_orbit_regression_pin():
    """REGRESSION PIN: the scene's [reference] multipliers of the three-link HZD orbit are
    walker's own (gaits/three_link_grizzle.toml: "reference values below: walker's own").
    """
    gait.assert_scene_reference("gaits/three_link_grizzle.toml", grizzle(), full_orbit(), TL.N_Q)


def test_actuator_work_equals_impact_loss():
    """Level ground, periodic orbit: the actuators' work over one stride replaces the kinetic
    energy lost at heel strike (1e-9 relative)."""
    gait.assert_work_pays_impact("three_link", TL, grizzle(), full_orbit().state)


def test_ground_reaction_is_newton_law():
    """The stance-foot force equals the total momentum rate minus gravity (finite differences
    of the centre-of-mass velocity along the closed-loop flow)."""
    P = grizzle()
    p = P.as_array()
    x = full_orbit().state.copy()
    x[3:6] *= 1.1
    dx = get_model("three_link").rhs(0, x, p)
    masses = np.array([P.mass_hip, P.mass_leg, P.mass_leg, P.mass_torso])

    def momentum(xx):
        return masses.sum() * _com_velocity(xx[:3], xx[3:6], P)

    # Fourth-order central differences along the flow of the exact momentum (a nested
    # finite difference here loses ~5e-5 to rounding).
    h = 1e-3
    dp = (
        -momentum(x + 2 * h * dx)
        + 8 * momentum(x + h * dx)
        - 8 * momentum(x - h * dx)
        + momentum(x - 2 * h * dx)
    ) / (12 * h)
    F = np.array(TL.ground_reaction(x, p))
    assert_allclose(F, dp + np.array([0.0, masses.sum() * P.g]), rtol=1e-5, atol=1e-4)


def _com_velocity(q, qd, P):
    """Exact centre-of-mass velocity: the derivative of :func:`_com` along ``qd``."""
    r = P.leg_length
    du = lambda a, w: w * np.array([-math.cos(a), -math.sin(a)])  # noqa: E731
    hip = r * du(q[0], qd[0])
    vel = [
        hip,
        hip - P.com_to_hip * du(q[0], qd[0]),
        hip - P.com_to_hip * du(q[1], qd[1]),
        hip + P.torso_length * du(q[2], qd[2]),
    ]
    m = np.array([P.mass_hip, P.mass_leg, P.mass_leg, P.mass_torso])
    return (m[:, None] * np.array(vel)).sum(axis=0) / m.sum()


def _com(q, P):
    r = P.leg_length
    u = lambda a: np.array([-math.sin(a), math.cos(a)])  # noqa: E731
    hip = r * u(q[0])
    pts = [
        hip,
        hip - P.com_to_hip * u(q[0]),
        hip - P.com_to_hip * u(q[1]),
        hip + P.torso_length * u(q[2]),
    ]
    m = np.array([P.mass_hip, P.mass_leg, P.mass_leg, P.mass_torso])
    return (m[:, None] * np.array(pts)).sum(axis=0) / m.sum()


# ------------------------------------------------------------------------------ outcomes
def test_saturation_is_reported():
    """A torque limit below the gait's peak torque (~50 N m) clips the torque: the
    saturated time grows and the applied torque never exceeds the limit."""
    gait.assert_saturates(
        "three_link", TL, grizzle().replace(torque_limit=30.0), full_orbit().state
    )


def test_slip_is_an_outcome():
    """Friction 0.2 is below the impact's |P_t|/P_n ~ 0.49: the run ends with a status."""
    gait.assert_slips("three_link", grizzle().replace(friction=0.2), full_orbit().state)


def test_joint_pd_walks_some_strides():
    """Joint-space PD (no model inversion) to the same references: a status, not a crash,
    and with stiff gains it tracks well enough to keep walking."""
    P = grizzle().replace(controller=1.0, kp=1000.0, kd=100.0)
    sol = simulate("three_link", P, full_orbit().state, n_strides=10)
    assert sol.status == Status.COMPLETED
    assert sol.x[6] > 0.0  # the actuators did positive work


# -------------------------------------------------------------------------- compass limit
def _massless_torso(compass: CompassParams, **extra):
    return ThreeLinkParams(
        mass_hip=compass.mass_hip,
        mass_leg=compass.mass_leg,
        mass_torso=0.0,
        com_from_foot=compass.com_from_foot,
        com_to_hip=compass.com_to_hip,
        torso_length=0.5,
        inertia_leg=compass.inertia_leg,
        inertia_torso=0.0,
        slope=compass.slope,
        g=compass.g,
        rotor_inertia=0.0,  # rotors would couple the legs through the torso
        friction=1.0,
        controller=0.0,
        kp=0.0,
        kd=0.0,
        torque_limit=1.0,
        theta_plus=0.2,
        theta_minus=-0.2,
        **{f"bezier_{o}_{k}": 0.0 for o in ("swing", "torso") for k in range(5)},
        step_event=0.0,
        ft_alpha=0.9,
        ft_epsilon=0.1,
        **{f"poly_{o}_{k}": 0.0 for o in ("swing", "torso") for k in range(6)},
        damping_hip=0.0,
        coulomb_hip=0.0,
    ).replace(**extra)


def test_massless_torso_reduces_to_compass_matrices():
    compass = CompassParams.goswami().replace(inertia_leg=0.02)
    pc = compass.as_array()
    p3 = _massless_torso(compass).as_array()
    for _ in range(20):
        q = RNG.uniform(-1, 1, 3)
        qd = RNG.uniform(-2, 2, 3)
        three, two = get_model("three_link"), get_model("compass")
        D3 = three.kernel("mass_matrix", p3, q)
        C3 = three.kernel("coriolis", p3, q, qd)
        G3 = three.kernel("gravity", p3, q)
        D2 = two.kernel("mass_matrix", pc, q[:2])
        C2 = two.kernel("coriolis", pc, q[:2], qd[:2])
        G2 = two.kernel("gravity", pc, q[:2])
        assert_allclose(D3[:2, :2], D2, rtol=1e-14, atol=1e-14)
        assert_allclose(C3[:2, :2], C2, rtol=1e-14, atol=1e-14)
        assert_allclose(G3[:2], G2, rtol=1e-14, atol=1e-13)
        assert_allclose(D3[2], 0.0, rtol=0, atol=0)
        assert_allclose(G3[2], 0.0, rtol=0, atol=0)


def test_torso_rotor_reproduces_passive_compass_gait():
    """Controller off, torso mass at the hip (torso_length 0) with an inertia: the torso is a
    free rotor that the legs do not feel, so the compass gait's passive fixed point (Goswami,
    3 degrees, split hip mass) is a three-link stride too (to the tolerance 1e-9)."""
    compass = CompassParams.goswami()
    fp = find_fixed_point(StrideMap("compass", compass), np.array([0.2187, -1.0918, -0.3772]))
    assert fp.success
    P = _massless_torso(compass, mass_hip=6.0, mass_torso=4.0, torso_length=0.0, inertia_torso=0.3)
    x0 = np.r_[fp.state[0], fp.state[1], 0.0, fp.state[2], fp.state[3], 0.0, 0.0, 0.0]
    sol = simulate("three_link", P, x0, n_strides=1)
    assert sol.status == Status.COMPLETED
    assert_allclose(sol.x[[0, 1, 3, 4]], fp.state, rtol=0, atol=1e-9)
    assert_allclose(sol.t, fp.step_time, rtol=1e-9)
    assert sol.x[6] == 0.0


# --------------------------------------------------------------------------- Newton–Euler
def test_newton_euler_reproduces_applied_torques():
    """Inverse dynamics of the tree (stance leg -> swing leg, stance leg -> torso) along a
    closed-loop stride gives the controller's torques: swing hip joint u_2, torso joint
    -u_1 - u_2 (virtual work of B = [[1, 0], [0, 1], [-1, -1]]), stance foot 0 (1e-10 N m)."""
    P = grizzle()
    p = P.as_array()
    times = np.linspace(0.0, full_orbit().step_time * 0.999, 9)
    sol = simulate(
        "three_link",
        P,
        full_orbit().state + np.r_[0, 0, 0.02, 0.1, 0, 0, 0, 0],
        n_strides=1,
        output="samples",
        sample_times=times,
    )
    chains = three_link_chains(P)
    gravity = (0.0, -P.g)
    n_checked = 0
    for x in sol.samples.x:
        model = get_model("three_link")
        dx = model.rhs(0, x, p)
        assert_three_link_torques(chains, x, dx, model.torques(x, p), gravity)
        n_checked += 1
    assert n_checked == len(times)
