"""The five-link walker (RABBIT-like) in closed loop: hybrid invariance, the restricted
Poincaré map, the full-order gait, energy balance and Newton–Euler torques."""

import math
from functools import cache

import _hzd_gait as gait
import numpy as np
import pytest
from _chains import assert_five_link_torques, five_link_chains
from numpy.testing import assert_allclose

from walker.analysis.fixedpoint import find_fixed_point
from walker.models import five_link as FL
from walker.models import get_model, hzd
from walker.params import FiveLinkParams
from walker.simulation.stride import StrideMap, simulate
from walker.status import EVENT_STRIDE

RNG = np.random.default_rng(20260311)
# section coordinates: q_leg, q_knee, q_torso, q_femur_sw, then the five rates
PERTURBATION = np.array([0.0, 0.02, 0.02, -0.02, 0.05, 0.1, -0.1, 0.1, 0.0])


@cache
def rabbit():
    return FiveLinkParams.rabbit()


@cache
def hzd_orbit():
    return hzd.restricted_fixed_point(rabbit(), bracket=(-4.0, -0.2), n_scan=16)


@cache
def full_orbit():
    """Full-order fixed point, Newton started from a perturbed section point."""
    S = StrideMap("five_link", rabbit())
    return find_fixed_point(S, hzd_orbit().section + PERTURBATION, tol=1e-12)


# ----------------------------------------------------------------------------- the model
MODEL = get_model("five_link")


def _points(x, p):
    """The generated kernel's six points (stance contact, stance knee, hip, swing knee, swing
    contact, torso) at the coordinates of state ``x``."""
    return MODEL.kernel("points", p, x[:5])


def _swing_foot(x, p):
    """(height above the slope, distance ahead of the stance foot along it) of the swing foot
    [m], from the points in the slope frame."""
    d = _points(x, p)[4] - _points(x, p)[0]
    slope = p[FL.I_SLOPE]
    return (
        d[0] * math.sin(slope) + d[1] * math.cos(slope),
        d[0] * math.cos(slope) - d[1] * math.sin(slope),
    )


def test_rabbit_preset():
    p = rabbit()
    # Westervelt, Grizzle, Koditschek 2003, Table I (RABBIT): masses [kg], lengths and
    # centre-of-mass positions [m], inertias [kg m^2]
    assert (p.mass_torso, p.mass_femur, p.mass_tibia) == (12.0, 6.8, 3.2)
    assert (p.length_femur, p.length_tibia) == (0.4, 0.4)
    assert (p.com_torso, p.com_femur, p.com_tibia) == (0.24, 0.11, 0.24)
    assert (p.inertia_torso, p.inertia_femur, p.inertia_tibia) == (1.33, 0.47, 0.20)
    assert p.slope == 0.0 and p.controller == 2.0
    with pytest.raises(ValueError, match=r"^`com_tibia` must be <= `length_tibia` = 0.4 \[m\]"):
        p.replace(com_tibia=0.5)
    with pytest.raises(ValueError, match="^`theta_minus` must differ from `theta_plus`"):
        p.replace(theta_minus=p.theta_plus)


def test_input_map_is_the_relative_joint_angles():
    """B^T qd are the relative joint rates (hip st, hip sw, knee st, knee sw), and BETA B = 0."""
    qd = RNG.uniform(-1, 1, 5)
    tib_st, fem_st = qd[0] - qd[1] / 2, qd[0] + qd[1] / 2
    rel = [fem_st - qd[2], qd[3] - qd[2], tib_st - fem_st, qd[4] - qd[3]]
    assert_allclose(FL.B_MATRIX.T @ qd, rel, rtol=0, atol=1e-15)
    assert_allclose(hzd.BETA_FIVE_LINK @ FL.B_MATRIX, 0.0, rtol=0, atol=0)


def test_lift_puts_the_swing_foot_on_the_ground():
    P = rabbit()
    p = P.as_array()
    z = hzd_orbit().section + 0.5 * PERTURBATION
    x = FL.lift(z, p)
    height, ahead = _swing_foot(x, p)
    assert_allclose(height, 0.0, rtol=0, atol=1e-15)
    assert ahead < -0.2  # the new swing foot is the trailing one
    assert_allclose(FL.project(x, p), z, rtol=0, atol=0)
    e = 1e-6
    J = FL.lift_jacobian(z, p)
    for j in range(9):
        dz = np.zeros(9)
        dz[j] = e
        # central differences: truncation ~e^2, rounding ~1e-16/e
        assert_allclose(J[:, j], (FL.lift(z + dz, p) - FL.lift(z - dz, p)) / (2 * e), atol=1e-8)


def test_heel_strike_conserves_momentum_about_the_new_foot():
    """Across the impact the angular momentum about the new stance foot is conserved (the
    only impulse acts there); the old stance foot lifts off and the knees swap."""
    P = rabbit()
    p = P.as_array()
    q, sigma, _ = hzd.surface(P, P.theta_minus)
    x = np.r_[q, -1.3 * sigma, 0.0, 0.0]
    action, _, status, x_new, impulse = MODEL.reset(MODEL.start_phase(x, p), 0, x, p)
    assert (action, status) == (EVENT_STRIDE, 0)
    assert impulse[1] > 0
    foot = _points(x, p)[4]
    momentum_before = _angular_momentum(x, P, foot)
    momentum_after = _angular_momentum(x_new, P, _points(x_new, p)[0])
    assert_allclose(momentum_after, momentum_before, rtol=1e-13)
    assert_allclose(x_new[1], x[3] - x[4], rtol=0, atol=1e-15)  # new knee: old swing leg's


def _angular_momentum(x, P, about):
    """Angular momentum [kg m^2/s] about ``about``, from the segments' centres of mass (the
    kernel's joint positions) and their velocities written out by hand."""
    p = P.as_array()
    q, qd = x[:5], x[5:10]
    tst, fst = q[0] - q[1] / 2, q[0] + q[1] / 2
    tstd, fstd = qd[0] - qd[1] / 2, qd[0] + qd[1] / 2
    pts = _points(x, p)
    hip, ks, ksw = pts[2], pts[1], pts[3]
    lt, lf = P.length_tibia, P.length_femur
    u = lambda a: np.array([-math.sin(a), math.cos(a)])  # noqa: E731
    du = lambda a, w: w * np.array([-math.cos(a), -math.sin(a)])  # noqa: E731
    v_ks = lt * du(tst, tstd)
    v_hip = v_ks + lf * du(fst, fstd)
    v_ksw = v_hip - lf * du(q[3], qd[3])
    bodies = [
        (P.mass_torso, hip + P.com_torso * u(q[2]), v_hip + P.com_torso * du(q[2], qd[2])),
        (P.mass_femur, hip - P.com_femur * u(fst), v_hip - P.com_femur * du(fst, fstd)),
        (P.mass_tibia, ks - P.com_tibia * u(tst), v_ks - P.com_tibia * du(tst, tstd)),
        (P.mass_femur, hip - P.com_femur * u(q[3]), v_hip - P.com_femur * du(q[3], qd[3])),
        (P.mass_tibia, ksw - P.com_tibia * u(q[4]), v_ksw - P.com_tibia * du(q[4], qd[4])),
    ]
    inertia = P.inertia_torso * qd[2] + P.inertia_femur * (fstd + qd[3])
    inertia += P.inertia_tibia * (tstd + qd[4])
    orbital = sum(m * ((c - about)[0] * v[1] - (c - about)[1] * v[0]) for m, c, v in bodies)
    return orbital + inertia


# ------------------------------------------------------------------------ hybrid zero dynamics
def test_make_invariant_gives_hybrid_invariance():
    """h(Delta(q-)) = 0 and L_f h(Delta(q-, qd-)) = 0 after the adjustment (1e-12), and not
    before it, for random free coefficients, steps and slopes."""
    raw = rabbit().replace(bezier_knee_1=0.3, bezier_torso_0=0.0, bezier_femur_1=0.0)
    gait.assert_not_invariant(raw)
    for k in range(3):
        free = RNG.uniform(-0.1, 0.1, 6)
        design = gait.invariant_design(
            raw.replace(
                theta_minus=-0.18 - 0.03 * k,
                slope=0.01 * k,
                bezier_knee_3=0.2 + free[0],
                bezier_knee_4=0.2 + free[1],
                bezier_torso_2=free[2],
                bezier_femur_2=0.2 + free[3],
                bezier_tibia_2=-0.6 + free[4],
                bezier_tibia_3=0.2 + free[5],
            )
        )
        # the swing foot is on the slope at theta_minus
        q, _, _ = hzd.surface(design, design.theta_minus)
        x = np.r_[q, np.zeros(7)]
        assert_allclose(_swing_foot(x, design.as_array())[0], 0.0, rtol=0, atol=1e-15)


def test_zero_dynamics_equals_closed_loop_on_the_surface():
    P = rabbit()
    thetas = np.linspace(P.theta_plus, P.theta_minus, 4)
    gait.assert_zero_dynamics_on_surface(FL, P, thetas, lambda: RNG.uniform(-1.5, -0.5))


def test_restricted_map_multiplier_is_delta_zero_squared():
    """Central differences (step 1e-5) of rho at rtol 1e-12 vs the closed form delta_zero^2
    (Westervelt et al. 2003, Theorem 3)."""
    gait.assert_restricted_map_multiplier(rabbit(), hzd_orbit())


# ------------------------------------------------------------------------- full-order gait
def test_closed_loop_converges_to_period_one_gait():
    """From a perturbed start (knee, torso, femur, rates) the walker converges to the HZD
    orbit on level ground: contraction 0.815 per stride, 0.815^80 * 0.1 ~ 1e-8."""
    start = hzd_orbit().section + PERTURBATION
    sol = gait.converged_run("five_link", rabbit(), start, 80, hzd_orbit().section)
    assert sol.x[10] > 0.0  # the actuators did positive work


def test_full_order_fixed_point_agrees_with_hzd():
    """The full-order orbit is the HZD orbit (to the integration tolerance) and its dominant
    multiplier is delta_zero^2 (to 1e-7, the accuracy of the central-difference vector-field
    Jacobian in the variational equations); the transverse multipliers are < 1e-3."""
    gait.assert_full_order_is_hzd(full_orbit(), hzd_orbit(), section_atol=1e-9)


@pytest.mark.regression_pin
def test_scene_reference_is_the_orbit_regression_pin():
    """REGRESSION PIN: the scene's [reference] multipliers of the five-link HZD orbit are walker's
    own (gaits/five_link_hzd.toml: "reference values below: walker's own").
    """
    gait.assert_scene_reference("gaits/five_link_hzd.toml", rabbit(), full_orbit(), FL.N_Q)


def test_actuator_work_equals_impact_loss():
    """Level ground, periodic orbit: the actuators' work over one stride replaces the kinetic
    energy lost at heel strike (1e-9 relative)."""
    gait.assert_work_pays_impact("five_link", FL, rabbit(), full_orbit().state)


# ------------------------------------------------------------------------------ outcomes
def test_saturation_is_reported():
    """A limit below the gait's peak torque (~104 N m at the hips) clips the torque."""
    gait.assert_saturates("five_link", FL, rabbit().replace(torque_limit=80.0), full_orbit().state)


def test_slip_is_an_outcome():
    """Friction 0.2 is below the stance phase's peak |F_t|/F_n ~ 0.36: a status, not a crash."""
    gait.assert_slips("five_link", rabbit().replace(friction=0.2), full_orbit().state)


# --------------------------------------------------------------------------- Newton–Euler
def test_newton_euler_reproduces_applied_torques():
    """Inverse dynamics of the tree split into serial chains (A: stance tibia, stance femur,
    swing femur, swing tibia; B: stance tibia and femur of negligible mass, torso; C: those
    two light links alone, subtracted) along a closed-loop stride gives the controller's
    torques (1e-10 N m): swing knee u_4, swing hip u_2, torso joint -u_1 - u_2 (virtual
    work of B), stance knee -u_3 (joint angle femur - tibia), stance foot 0."""
    P = rabbit()
    p = P.as_array()
    times = np.linspace(0.0, full_orbit().step_time * 0.999, 7)
    x0 = full_orbit().state + np.r_[0, 0, 0.02, 0, 0, 0.05, 0, 0, 0, 0, 0, 0]
    sol = simulate("five_link", P, x0, n_strides=1, output="samples", sample_times=times)
    chains = five_link_chains(P)
    gravity = (0.0, -P.g)
    assert sol.samples.x.shape[0] == len(times)
    for x in sol.samples.x:
        dx = MODEL.rhs(0, x, p)
        assert_five_link_torques(chains, x, dx, MODEL.torques(x, p), gravity)


def test_generated_points_match_the_geometry():
    """The kernels' points at a random configuration, from the segment angles by hand."""
    P = rabbit()
    p = P.as_array()
    q = RNG.uniform(-0.5, 0.5, 5)
    pts = MODEL.kernel("points", p, q)
    u = lambda a: np.array([-math.sin(a), math.cos(a)])  # noqa: E731
    tst, fst = q[0] - q[1] / 2, q[0] + q[1] / 2
    knee = P.length_tibia * u(tst)
    hip = knee + P.length_femur * u(fst)
    swing_knee = hip - P.length_femur * u(q[3])
    expected = [
        [0, 0],
        knee,
        hip,
        swing_knee,
        swing_knee - P.length_tibia * u(q[4]),
        hip + P.com_torso * u(q[2]),
    ]
    assert_allclose(pts, expected, rtol=0, atol=1e-15)
