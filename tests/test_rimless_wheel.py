"""The rimless wheel (model ``rimless_wheel``, C only): walker against the closed form.

The closed form, derived here once and used by every test (see :func:`closed_form`)
----------------------------------------------------------------------------------
State ``(theta, theta_dot)``, ``theta`` the stance spoke's angle from the slope normal,
counterclockwise positive; rolling downhill ``theta`` runs from ``alpha`` to ``-alpha``
(``alpha = pi / n``) with ``theta_dot < 0``.  Hub mass ``m`` at ``l (-sin theta, cos theta)``
from the stance foot (slope frame), height ``l cos(theta - gamma)`` above it.

1. Stance: energy is conserved,
   ``l^2 w^2 / 2 + g l cos(theta - gamma) = const``, so from ``theta = alpha`` (rate
   ``w+``) to ``theta = -alpha`` (rate ``w-``)

       w-^2 = w+^2 + 2 (g/l) (cos(alpha - gamma) - cos(alpha + gamma))
            = w+^2 + K,        K = 4 (g/l) sin(alpha) sin(gamma).

2. Impact: the only impulse acts at the new foot, so the angular momentum about it is
   conserved.  The hub velocity ``l w-`` is perpendicular to the old spoke, at ``2 alpha``
   from the new one; its component perpendicular to the new spoke is ``l w- cos(2 alpha)``,
   whose moment about the new foot is ``m l^2 w- cos(2 alpha)``; after the impact the hub
   turns about the new foot, ``m l^2 w+``.  So ``w+ = c w-``, ``c = cos(2 alpha)``, and the
   kinetic energy drops by ``(1 - c^2) = sin^2(2 alpha)`` of its value before.

3. The rate map on the section just after impact (``w < 0``):
   ``P(w) = c w- = -c sqrt(w^2 + K)``.  Its fixed point ``w*^2 = c^2 (w*^2 + K)``:

       w* = -c sqrt(K / (1 - c^2)) = -cot(2 alpha) sqrt(4 (g/l) sin(alpha) sin(gamma)),

   and its one multiplier ``P'(w*) = -c w* / sqrt(w*^2 + K) = c^2 w* / P(w*) = c^2``
   (``= cos^2(2 alpha)``).

4. The orbit exists only if the wheel gets over the top (``theta = gamma``) between
   impacts: for ``gamma < alpha``, ``w*^2 > 2 (g/l) (1 - cos(alpha - gamma))``; the critical
   slope is where equality holds.  Below it the wheel only stands (at rest on two spokes,
   possible for ``|gamma| < alpha``); between it and ``alpha`` both equilibria exist.
"""

import ctypes
import math

import mpmath
import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.optimize import brentq

from walker import StrideMap, _hybrid, load_scene, simulate
from walker.analysis.fixedpoint import find_fixed_point
from walker.models import MODEL_NAMES, get_model
from walker.models import rimless_wheel as RW
from walker.params import PARAMS, RimlessWheelParams
from walker.status import EVENT_CONTINUE, EVENT_STRIDE, EVENT_TERMINAL, Status

MODEL = get_model("rimless_wheel")
TIGHT = {"rtol": 1e-13, "atol": 1e-13}
ROLLING, STANDING = 0, 1
IMPACT, BACK_IMPACT, IMPACT_LATE, BACK_IMPACT_LATE = 0, 1, 2, 3


def _params(spokes=8, slope=0.08, leg_length=1.0, g=9.81):
    return RimlessWheelParams(spokes=spokes, leg_length=leg_length, g=g, slope=slope)


def closed_form(p):
    """``(alpha, c, K, w_star, multiplier)`` of the module docstring's derivation."""
    alpha = math.pi / p.spokes
    c = math.cos(2.0 * alpha)
    gl = p.g / p.leg_length
    K = 4.0 * gl * math.sin(alpha) * math.sin(p.slope)
    w_star = -c * math.sqrt(K / (1.0 - c * c))
    return alpha, c, K, w_star, c * c


def gets_over_the_top(p, w):
    """Item 4: a wheel leaving ``theta = alpha`` at rate ``w`` reaches ``theta = -alpha``."""
    alpha = math.pi / p.spokes
    if p.slope >= alpha:
        return True
    return w * w > 2.0 * p.g / p.leg_length * (1.0 - math.cos(alpha - p.slope))


def critical_slope(spokes, leg_length=1.0, g=9.81):
    """The slope where the closed-form orbit just gets over the top (item 4)."""

    def margin(slope):
        p = _params(spokes, slope, leg_length, g)
        alpha = math.pi / spokes
        w = closed_form(p)[3]
        return w * w - 2.0 * g / leg_length * (1.0 - math.cos(alpha - slope))

    return brentq(margin, 1e-9, math.pi / spokes, xtol=1e-15)


def step_time(p, w):
    """Time from ``alpha`` to ``-alpha`` leaving at rate ``w``: the quadrature of
    ``dt = dtheta / |theta_dot(theta)|`` along the energy integral of item 1 (mpmath, 30
    digits; split at the top, where the rate is smallest)."""
    with mpmath.workdps(30):
        alpha = mpmath.pi / int(p.spokes)
        gl = mpmath.mpf(p.g) / mpmath.mpf(p.leg_length)
        slope, w = mpmath.mpf(p.slope), mpmath.mpf(w)

        def rate(theta):
            return mpmath.sqrt(
                w * w + 2 * gl * (mpmath.cos(alpha - slope) - mpmath.cos(theta - slope))
            )

        nodes = [-alpha, slope, alpha] if -alpha < slope < alpha else [-alpha, alpha]
        return float(mpmath.quad(lambda th: 1 / rate(th), nodes))


def _kinetic(x, p):
    return MODEL.energy(x, p)[0]


def _total(x, p):
    kinetic, potential = MODEL.energy(x, p)
    return kinetic + potential


# ---- parameters and registration --------------------------------------------------------
def test_parameters_and_registration():
    p = RimlessWheelParams.drake()
    assert p.names() == ("spokes", "leg_length", "g", "slope")
    assert (p.spokes, p.leg_length, p.g, p.slope) == (8.0, 1.0, 9.81, 0.08)
    assert type(p.spokes) is float
    assert_allclose(p.as_array(), [8.0, 1.0, 9.81, 0.08], rtol=0, atol=0)
    assert RimlessWheelParams.from_array(p.as_array()) == p
    assert PARAMS["rimless_wheel"] is RimlessWheelParams
    assert "rimless_wheel" in MODEL_NAMES
    assert MODEL.state_names == ("theta", "theta_dot")
    assert MODEL.section_names == ("theta_dot",) and MODEL.n_z == 1
    assert MODEL.phase_names == ("rolling", "standing")
    with pytest.raises(ValueError, match=r"^`spokes` must be an integer \(a whole number of "):
        p.replace(spokes=7.5)
    with pytest.raises(ValueError, match=r"^`spokes` must be >= 3 \[1\], got 2.0$"):
        p.replace(spokes=2)
    with pytest.raises(TypeError, match=r"^`spokes` must be a real number"):
        p.replace(spokes="8")
    assert p.replace(spokes=12).spokes == 12.0


def test_written_in_c_only():
    """Every phase function and helper comes from the extension; the module has no numba
    functions to fall back on."""
    entry = _hybrid.models()["rimless_wheel"]
    for key in ("rhs", "guards", "reset", "jac", "energy", "points", "start_phase"):
        assert isinstance(entry[key], int) and entry[key] != 0, key
    for name in ("rhs", "guards", "reset", "jac", "energy", "points", "start_phase"):
        assert not hasattr(RW, name), name
    assert MODEL.system.rhs == entry["rhs"]
    assert len(MODEL.kernel_hash) == 64


def test_jacobian_matches_finite_differences():
    fn = ctypes.CFUNCTYPE(None, ctypes.c_int64, ctypes.c_double, *(4 * [ctypes.c_void_p]))
    entry = _hybrid.models()["rimless_wheel"]
    rhs, jac = fn(entry["rhs"]), fn(entry["jac"])
    rng = np.random.default_rng(7)
    for _ in range(20):
        p = _params(rng.integers(3, 20), rng.uniform(-0.5, 0.5), rng.uniform(0.3, 2), 9.81)
        pa = p.as_array()
        x = np.array([rng.uniform(-1, 1), rng.uniform(-3, 3)])
        for phase in (ROLLING, STANDING):
            J = np.empty(4)
            jac(phase, 0.0, x.ctypes.data, pa.ctypes.data, J.ctypes.data, None)
            fd = np.empty((2, 2))
            for j in range(2):
                h = 1e-6
                plus, minus, f1, f2 = x.copy(), x.copy(), np.empty(2), np.empty(2)
                plus[j] += h
                minus[j] -= h
                rhs(phase, 0.0, plus.ctypes.data, pa.ctypes.data, f1.ctypes.data, None)
                rhs(phase, 0.0, minus.ctypes.data, pa.ctypes.data, f2.ctypes.data, None)
                fd[:, j] = (f1 - f2) / (2 * h)
            assert_allclose(J.reshape(2, 2), fd, rtol=0, atol=1e-8)


# ---- the rolling gait against the closed form -------------------------------------------
# (spokes, slope, leg_length, g): from 5 spokes (cos 2 alpha = 0.31) to 20 (0.95); slopes
# below alpha (both equilibria exist) and above it (5 spokes at 0.7, 8 at 0.5: no standing).
CASES = [
    (5, 0.4, 1.0, 9.81),
    (5, 0.7, 1.0, 9.81),
    (6, 0.2, 1.0, 9.81),
    (8, 0.08, 1.0, 9.81),
    (8, 0.5, 1.0, 9.81),
    (8, 0.1, 0.5, 1.62),
    (12, 0.05, 2.0, 9.81),
    (20, 0.02, 1.0, 1.0),
]


@pytest.mark.parametrize(("spokes", "slope", "leg_length", "g"), CASES)
def test_fixed_point_and_multiplier_equal_the_closed_form(spokes, slope, leg_length, g):
    p = _params(spokes, slope, leg_length, g)
    alpha, c, K, w_star, multiplier = closed_form(p)
    assert gets_over_the_top(p, w_star)
    P = StrideMap("rimless_wheel", p, **TIGHT)
    fp = find_fixed_point(P, np.array([1.2 * w_star]), tol=1e-14)
    assert fp.success, fp.message
    assert fp.section.shape == (1,) and fp.multipliers.shape == (1,)
    assert abs(fp.section[0] - w_star) <= 1e-12
    assert abs(fp.multipliers[0] - multiplier) <= 1e-12
    assert fp.stable
    # the full state is the section's lift: theta = alpha exactly
    assert fp.state[0] == alpha and fp.state[1] == fp.section[0]
    assert_allclose(fp.step_time, step_time(p, w_star), rtol=1e-11, atol=0)


def test_stride_map_is_the_closed_form_rate_map():
    """Off the fixed point too: P(w) = -c sqrt(w^2 + K) and P'(w) = c^2 w / P(w)."""
    p = _params(8, 0.08)
    _, c, K, w_star, _ = closed_form(p)
    P = StrideMap("rimless_wheel", p, **TIGHT)
    for w in (1.5 * w_star, 1.1 * w_star, 0.95 * w_star, -4.0):
        r = P(np.array([w]), jacobian=True)
        assert r.status == Status.COMPLETED
        expected = -c * math.sqrt(w * w + K)
        assert abs(r.z[0] - expected) <= 1e-12
        assert abs(r.jac[0, 0] - c * c * w / expected) <= 1e-12


# ---- energy: conserved in stance, the impact's loss --------------------------------------
def test_energy_is_conserved_along_the_stance_phase():
    p = _params(8, 0.08)
    alpha, _, _, w_star, _ = closed_form(p)
    T = step_time(p, w_star)
    times = np.linspace(0.0, T * (1 - 1e-9), 201)
    sol = simulate(
        "rimless_wheel", p, [alpha, w_star], output="samples", sample_times=times, **TIGHT
    )
    assert sol.status == Status.COMPLETED and sol.n_strides == 1
    x = sol.samples.x
    assert np.all(x[:, 0] >= -alpha) and np.all(x[:, 0] <= alpha)
    energy = np.array([_total(row, p) for row in x])
    assert np.abs(energy / energy[0] - 1.0).max() <= 1e-12


@pytest.mark.parametrize(("spokes", "slope"), [(5, 0.4), (8, 0.08), (12, 0.05)])
def test_impact_map_conserves_angular_momentum_about_the_new_foot(spokes, slope):
    p = _params(spokes, slope)
    alpha, c, _, _, _ = closed_form(p)
    l = p.leg_length
    for w_minus in (-0.3, -1.1, -2.7):
        x = np.array([-alpha, w_minus])
        action, phase, status, x_new, impulse = MODEL.apply_reset(ROLLING, IMPACT, x, p)
        assert (action, phase, status) == (EVENT_STRIDE, ROLLING, 0)
        assert x_new[0] == alpha
        assert_allclose(x_new[1], c * w_minus, rtol=1e-15, atol=0)
        # hub velocity before (about the old foot) and after (about the new one); the new
        # foot lies 2 l sin(alpha) downhill of the old one
        v_minus = -l * w_minus * np.array([math.cos(-alpha), math.sin(-alpha)])
        v_plus = -l * x_new[1] * np.array([math.cos(alpha), math.sin(alpha)])
        assert_allclose(impulse, v_plus - v_minus, rtol=0, atol=1e-15)
        hub = l * np.array([math.sin(alpha), math.cos(alpha)])  # from the old foot
        r = hub - np.array([2 * l * math.sin(alpha), 0.0])  # from the new foot
        h_minus = r[0] * v_minus[1] - r[1] * v_minus[0]
        h_plus = r[0] * v_plus[1] - r[1] * v_plus[0]
        assert_allclose(h_plus, h_minus, rtol=1e-14, atol=0)
        assert impulse[1] > 0.0  # the ground pushes
        # the kinetic energy lost is sin^2(2 alpha) of the kinetic energy before
        lost = _kinetic(x, p) - _kinetic(x_new, p)
        assert_allclose(lost, math.sin(2 * alpha) ** 2 * _kinetic(x, p), rtol=1e-14, atol=0)


def test_energy_lost_at_every_impact_of_a_run_is_the_closed_form():
    p = _params(8, 0.08)
    alpha, c, _, w_star, _ = closed_form(p)
    sol = simulate("rimless_wheel", p, [alpha, 1.5 * w_star], n_strides=6, output="events", **TIGHT)
    assert sol.status == Status.COMPLETED and sol.n_strides == 6
    ev = sol.events
    assert list(ev.guard) == [IMPACT] * 6
    for pre, post in zip(ev.x_pre, ev.x_post, strict=True):
        assert abs(pre[0] + alpha) <= 1e-14 and post[0] == alpha
        before = _kinetic(pre, p)
        assert_allclose(before - _kinetic(post, p), (1 - c * c) * before, rtol=1e-14, atol=0)
    # the rates approach the fixed point geometrically, by c^2 per stride
    errors = np.abs(ev.x_post[:, 1] - w_star)
    assert_allclose(errors[1:] / errors[:-1], c * c, rtol=0.1)


# ---- the standing equilibrium and the critical slope -------------------------------------
@pytest.mark.parametrize("slope", [0.03, 0.08, -0.2])
def test_standing_still_is_an_equilibrium(slope):
    """At rest on two spokes, below the critical slope (0.03), between it and alpha (0.08,
    where the wheel also rolls) and uphill: the run stays put until t_max, NO_EVENT."""
    p = _params(8, slope)
    alpha = math.pi / 8
    x0 = np.array([alpha, 0.0])
    assert MODEL.start_phase(x0, p) == STANDING
    sol = simulate("rimless_wheel", p, x0, n_strides=1, t_max=50.0, output="events", **TIGHT)
    assert sol.status == Status.NO_EVENT
    assert sol.t == 50.0 and sol.phase == STANDING and len(sol.events.t) == 0
    assert sol.x[0] == alpha and sol.x[1] == 0.0
    # not standing: moving, off the boundary, or on a slope the wheel cannot stand on
    assert MODEL.start_phase([alpha, -1e-300], p) == ROLLING
    assert MODEL.start_phase([0.1, 0.0], p) == ROLLING
    assert MODEL.start_phase(x0, p.replace(slope=0.5)) == ROLLING


def test_critical_slope_is_where_the_closed_form_gets_over_the_top():
    assert_allclose(critical_slope(8), 0.06822945245228713, rtol=1e-12)
    assert critical_slope(5) > critical_slope(8) > critical_slope(20) > 0


@pytest.mark.parametrize("spokes", [6, 8, 12])
def test_below_the_critical_slope_the_wheel_only_stands(spokes):
    slope = 0.8 * critical_slope(spokes)
    p = _params(spokes, slope)
    alpha, c, _, w_star, _ = closed_form(p)
    assert not gets_over_the_top(p, w_star)
    # from the closed form's (unreachable) rate the wheel rolls up, back onto its trailing
    # spoke and comes to rest on both spokes
    sol = simulate("rimless_wheel", p, [alpha, w_star], n_strides=1, t_max=20.0, output="events")
    assert sol.status == Status.NO_EVENT and sol.phase == STANDING
    assert list(sol.events.guard) == [BACK_IMPACT]
    assert (sol.events.phase_before[0], sol.events.phase_after[0]) == (ROLLING, STANDING)
    assert abs(sol.events.x_pre[0][0] - alpha) <= 1e-14 and sol.events.x_pre[0][1] > 0
    assert sol.x[0] == alpha and sol.x[1] == 0.0
    # the stride map fails there, and the search for a rolling gait fails with a status
    P = StrideMap("rimless_wheel", p, **TIGHT)
    assert P(np.array([w_star])).status == Status.NO_EVENT
    for guess in (w_star, 1.5 * w_star, 3.0 * w_star):
        fp = find_fixed_point(P, np.array([guess]))
        assert not fp.success and fp.status != Status.COMPLETED, fp.message
    # just above it the rolling gait exists: both equilibria at one slope
    p_up = p.replace(slope=1.1 * critical_slope(spokes))
    P_up = StrideMap("rimless_wheel", p_up, **TIGHT)
    fp = find_fixed_point(P_up, np.array([1.2 * closed_form(p_up)[3]]), tol=1e-14)
    assert fp.success and abs(fp.section[0] - closed_form(p_up)[3]) <= 1e-12
    rest = simulate("rimless_wheel", p_up, [alpha, 0.0], t_max=20.0)
    assert rest.status == Status.NO_EVENT and rest.x[1] == 0.0


# ---- the other outcomes of the impacts --------------------------------------------------
def test_rolling_back_over_the_trailing_spoke_is_a_fall_backward():
    p = _params(8, -0.05)  # uphill: rolling back is rolling downhill
    sol = simulate("rimless_wheel", p, [0.0, 3.0], n_strides=1, output="events", **TIGHT)
    assert sol.status == Status.FELL_BACKWARD
    assert list(sol.events.guard) == [BACK_IMPACT]
    # on the threshold's other side it comes to rest instead
    alpha = math.pi / 8
    c = math.cos(2 * alpha)
    limit = math.sqrt(2 * p.g * (1 - math.cos(alpha + p.slope))) / c  # rate before impact
    for w, expected in ((1.001 * limit, EVENT_TERMINAL), (0.999 * limit, EVENT_CONTINUE)):
        action, phase, status, x_new, _ = MODEL.apply_reset(ROLLING, BACK_IMPACT, [alpha, w], p)
        assert action == expected
        if expected == EVENT_TERMINAL:
            assert status == Status.FELL_BACKWARD
        else:
            assert phase == STANDING and list(x_new) == [alpha, 0.0]


def test_a_back_step_that_rolls_forward_again_is_integrated():
    """On a slope steeper than alpha the wheel cannot stand: pushed back onto its trailing
    spoke it swings on that spoke (not a stride), falls forward onto the old one (a stride)
    and rolls on."""
    p = _params(8, 0.5)
    alpha, c, _, _, _ = closed_form(p)
    sol = simulate("rimless_wheel", p, [0.0, 2.5], n_strides=2, output="events", **TIGHT)
    assert sol.status == Status.COMPLETED
    assert list(sol.events.guard[:2]) == [BACK_IMPACT, IMPACT]
    pre, post = sol.events.x_pre[0], sol.events.x_post[0]
    assert post[0] == -alpha and post[1] == c * pre[1]
    # the swing on the trailing spoke conserves energy: it comes back at the same rate
    assert_allclose(sol.events.x_pre[1][1], -post[1], rtol=1e-11)


@pytest.mark.parametrize(("spokes", "slope"), [(3, 0.5), (4, 0.3)])
def test_three_or_four_spokes_stop_at_every_impact(spokes, slope):
    """cos(2 alpha) <= 0: the trailing foot cannot leave the ground; the wheel stops on two
    spokes and, on a slope below alpha, stands."""
    p = _params(spokes, slope)
    alpha = math.pi / spokes
    sol = simulate("rimless_wheel", p, [alpha, -6.0], n_strides=2, output="events", **TIGHT)
    assert sol.status == Status.NO_EVENT and sol.n_strides == 1 and sol.phase == STANDING
    assert list(sol.events.guard) == [IMPACT]
    assert list(sol.events.x_post[0]) == [alpha, 0.0]


def test_three_spokes_steeper_than_alpha_tip_forward_from_rest():
    """Each step starts from rest: the stride map is P(w) = 0, fixed point 0, multiplier 0."""
    p = _params(3, 1.2)
    P = StrideMap("rimless_wheel", p, **TIGHT)
    fp = find_fixed_point(P, np.array([-1.0]))
    assert fp.success and fp.section[0] == 0.0 and fp.multipliers[0] == 0.0


def test_a_start_on_the_boundary_moving_out_is_caught_by_the_late_guard():
    """Starting at theta = alpha rolling back, guard 1 is never armed; guard 3, 2e-10 rad
    beyond, fires with the same reset."""
    p = _params(8, 0.08)
    alpha = math.pi / 8
    sol = simulate("rimless_wheel", p, [alpha, 0.5], n_strides=1, t_max=5.0, output="events")
    assert list(sol.events.guard) == [BACK_IMPACT_LATE]
    assert 0 < sol.events.x_pre[0][0] - alpha <= 2.1e-10
    assert sol.status == Status.NO_EVENT and sol.phase == STANDING


# ---- drawing ------------------------------------------------------------------------------
def test_points_put_every_foot_a_spoke_length_from_the_hub():
    p = _params(8, 0.08)
    alpha = math.pi / 8
    pts = MODEL.points([-alpha, -1.0], p)  # the leading spoke touching
    assert pts.shape == (4, 2) and RW.SEGMENTS == ((0, 1), (1, 2), (1, 3))
    assert_allclose(np.linalg.norm(pts[1:] - pts[1], axis=1)[1:], 1.0, rtol=1e-15)
    assert_allclose(np.linalg.norm(pts[1] - pts[0]), 1.0, rtol=1e-15)
    step = 2 * math.sin(alpha) * np.array([math.cos(0.08), -math.sin(0.08)])
    assert_allclose(pts[RW.SWING_FOOT], step, rtol=0, atol=1e-15)


# ---- the scene ------------------------------------------------------------------------------
def test_scene_reference_is_the_closed_form_and_walker_finds_it():
    scene = load_scene("gaits/rimless_wheel.toml")
    assert scene.params == RimlessWheelParams.drake()
    ref = scene.reference
    alpha, _, _, w_star, multiplier = closed_form(scene.params)
    assert_allclose(ref["state"], [alpha, w_star], rtol=0, atol=1e-15)
    assert_allclose(ref["multipliers"], [multiplier], rtol=0, atol=1e-15)
    assert_allclose(ref["step_time"], step_time(scene.params, w_star), rtol=0, atol=1e-13)
    P = StrideMap(scene.model, scene.params, **TIGHT)
    fp = find_fixed_point(P, P.project(scene.state), tol=1e-13)
    assert fp.success
    assert_allclose(fp.state, ref["state"], atol=ref["tolerance"], rtol=0)
    assert_allclose(fp.multipliers, ref["multipliers"], atol=ref["tolerance"], rtol=0)
    assert_allclose(fp.step_time, ref["step_time"], atol=ref["tolerance"], rtol=0)
