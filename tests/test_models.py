"""The walkers: impacts conserve what they must, guards mean what they say, gaits match the
literature, limits hold."""

import importlib
import math

import numpy as np
import pytest
from _mechanics import angular_momentum, body_functions, point
from numpy.testing import assert_allclose

from walker import get_model, load_scene, simulate
from walker.models import MODEL_NAMES
from walker.models._common import BASE_EXPORTS
from walker.params import MODELS, CompassParams, KneedParams, SimplestParams
from walker.status import EVENT_CONTINUE, EVENT_IGNORE, EVENT_STRIDE, Status
from walker.symbolic import models as sym

RNG = np.random.default_rng(20261122)


# ----------------------------------------------------------------------------- the registry
@pytest.mark.parametrize("name", MODEL_NAMES)
def test_model_agrees_with_its_registry_record(name):
    """Each model's compiled description (its module and the system the integrator runs)
    matches its record in walker.params.MODELS: state names and length, parameter class,
    strides (a Poincare section exactly when it has strides)."""
    spec = MODELS[name]
    model = get_model(name)
    assert model.spec is spec
    assert model.module.STATE_NAMES == spec.state_names == model.state_names
    assert model.n_x == model.module.N_X == spec.n_x == model.system.n_x
    assert model.state_units == spec.state_units
    assert model.params_class is spec.params_class and spec.params_class.MODEL == name
    assert model.system.n_params == spec.params_class.n_params()
    assert model.has_strides is spec.has_strides
    assert (model.n_z > 0) is spec.has_strides
    assert model.is_walker is model.has_strides  # the former name


def test_model_names_are_the_registry_keys():
    assert MODEL_NAMES == tuple(MODELS)


def _heel_strike_state_compass(p, rng):
    """A random pre-impact compass state on the heel-strike surface, swing foot ahead."""
    slope = p[6]
    alpha = rng.uniform(0.1, 0.5)
    q_sw = -slope + alpha
    q_st = -slope - alpha
    return np.array([q_st, q_sw, rng.uniform(-2, -0.5), rng.uniform(-1, 1)])


COMPASS, KNEED = get_model("compass"), get_model("kneed")


# ------------------------------------------------------------------------------ compass gait
def test_compass_heel_strike_conserves_angular_momenta():
    params = CompassParams.goswami()
    p = params.as_array()
    model = sym.compass()
    bodies = body_functions(model)
    for _ in range(50):
        x = _heel_strike_state_compass(p, RNG)
        action, phase, status, x_new, imp = COMPASS.reset(0, 0, x, p)
        # Wide steps can leave the trailing foot pressed into the ground: then the reset
        # reports NONPHYSICAL_IMPACT, but the impact it solved must still conserve momenta.
        assert (action, status) in ((EVENT_STRIDE, 0), (3, Status.NONPHYSICAL_IMPACT))
        q, qd = x[:2], x[2:]
        qn, qdn = x_new[:2], x_new[2:]
        contact = point(model, "swing_contact", q, p)
        hip = point(model, "hip", q, p)
        # Whole walker about the new contact point: before (old labels) = after (new
        # labels, new stance foot at the origin).
        before = angular_momentum(bodies, q, qd, p, contact)
        after = angular_momentum(bodies, qn, qdn, p, np.zeros(2))
        assert_allclose(after, before, rtol=1e-12, atol=1e-12)
        # The trailing leg (old stance, new swing) about the hip.
        hip_new = point(model, "hip", qn, p)
        lb = angular_momentum(bodies, q, qd, p, hip, names={"stance_leg"})
        la = angular_momentum(bodies, qn, qdn, p, hip_new, names={"swing_leg"})
        assert_allclose(la, lb, rtol=1e-12, atol=1e-12)
        # Kinetic energy never increases; the normal impulse is positive.
        assert COMPASS.energy(x_new, p)[0] <= COMPASS.energy(x, p)[0]
        if action == EVENT_STRIDE:
            assert imp[1] > 0


def _goswami_transition(x, params):
    """Goswami, Thuilot & Espiau (1996, INRIA RR-2996) closed-form transition
    Q+(alpha) qd+ = Q-(alpha) qd-, velocities ordered (swing, stance), alpha the half
    inter-leg angle; the legs swap."""
    m, mh, a, b = params.mass_leg, params.mass_hip, params.com_from_foot, params.com_to_hip
    l = a + b
    q_st, q_sw, qd_st, qd_sw = x
    alpha = 0.5 * (q_sw - q_st)
    c = math.cos(2 * alpha)
    Qm = np.array([[-m * a * b, -m * a * b + (mh * l * l + 2 * m * a * l) * c], [0.0, -m * a * b]])
    Qp = np.array(
        [
            [m * b * (b - l * c), m * l * (l - b * c) + m * a * a + mh * l * l],
            [m * b * b, -m * b * l * c],
        ]
    )
    qd_plus = np.linalg.solve(Qp, Qm @ np.array([qd_sw, qd_st]))
    # (new swing, new stance) -> our (stance, swing)
    return np.array([q_sw, q_st, qd_plus[1], qd_plus[0]])


def test_compass_impact_equals_goswami_closed_form():
    params = CompassParams.goswami()
    p = params.as_array()
    for _ in range(50):
        x = _heel_strike_state_compass(p, RNG)
        x_new = COMPASS.reset(0, 0, x, p)[3]
        assert_allclose(x_new, _goswami_transition(x, params), rtol=1e-12, atol=1e-12)


def test_compass_scuff_behind_is_ignored_not_a_strike():
    p = CompassParams.goswami().as_array()
    # Mid-stance: legs nearly together, swing foot slightly behind the stance foot.
    x = np.array([0.02, 0.01, -1.0, 2.0])
    stance, _, swing = COMPASS.points(x, p)
    step = swing - stance  # along the slope: (cos slope, -sin slope)
    assert step[0] * math.cos(p[6]) - step[1] * math.sin(p[6]) < 0
    action = COMPASS.reset(0, 0, x, p)[0]
    assert action == EVENT_IGNORE


def test_compass_fixed_point_near_spong():
    """Spong et al. (2007, IEEE RAM) give [0.2187, -0.3234, -1.0918, -0.3772] at 3 deg,
    g = 9.8; our exact-ODE cycle agrees to their four digits (5e-5)."""
    scene = load_scene("gaits/compass_goswami.toml")
    from walker import StrideMap
    from walker.analysis.fixedpoint import find_fixed_point

    P = StrideMap("compass", scene.params)
    fp = find_fixed_point(P, P.project(scene.state))
    assert fp.success
    assert_allclose(fp.state, [0.2187, -0.3234, -1.0918, -0.3772], atol=5e-5)
    assert fp.stable


def test_energy_balance_over_one_stride_on_the_cycle():
    """Kinetic energy lost in the impacts equals the potential energy released (1e-10)."""
    for name in ("compass", "kneed"):
        scene = load_scene(f"gaits/{'compass_goswami' if name == 'compass' else 'kneed_hsu'}.toml")
        from walker import StrideMap
        from walker.analysis.fixedpoint import find_fixed_point

        P = StrideMap(name, scene.params)
        fp = find_fixed_point(P, P.project(scene.state))
        p = scene.params.as_array()
        sol = simulate(name, scene.params, fp.state, output="events", rtol=1e-12, atol=1e-12)
        assert sol.success
        model = get_model(name)
        ev = sol.events
        loss = sum(
            model.energy(ev.x_pre[i], p)[0] - model.energy(ev.x_post[i], p)[0]
            for i in range(len(ev))
        )
        # On the cycle the walker returns to the same state one step further down the
        # slope, so the impact losses equal M g times the drop from the old stance foot to
        # the new one (point feet: the contact points are material points).
        pts = model.points(ev.x_pre[-1], p)
        foot_drop = pts[0, 1] - pts[-1, 1]
        total_mass = scene.params.mass_hip + 2 * (
            scene.params.mass_leg
            if name == "compass"
            else scene.params.mass_thigh + scene.params.mass_shank
        )
        assert_allclose(loss, total_mass * scene.params.g * foot_drop, rtol=1e-10)


# ------------------------------------------------------------------------------ kneed walker
def _kneed_p(**changes):
    return KneedParams.hsu_chen().replace(**changes).as_array()


@pytest.mark.parametrize("offsets", [(0.0, 0.0), (0.02, -0.01)])
def test_knee_lock_conserves_angular_momenta(offsets):
    p = _kneed_p(
        offset_thigh=offsets[0], offset_shank=offsets[1], inertia_thigh=0.01, inertia_shank=0.003
    )
    model = sym.kneed_unlocked()
    bodies = body_functions(model)
    for _ in range(30):
        q = np.array([RNG.uniform(-0.3, 0.3), RNG.uniform(-0.3, 0.5), 0.0])
        q[2] = q[1]
        qd = np.array([RNG.uniform(-2, 0), RNG.uniform(-1, 3), RNG.uniform(0, 4)])
        qd[2] = qd[1] + abs(qd[2])  # shank catching up with the thigh
        x = np.concatenate([q, qd])
        if KNEED.guards(0, x, p)[1] <= 0:  # swing foot below: a real run trips before
            continue
        action, phase, status, x_new, imp = KNEED.reset(0, 0, x, p)
        assert (action, phase, status) == (EVENT_CONTINUE, 1, 0)
        qn, qdn = x_new[:3], x_new[3:]
        assert qdn[1] == qdn[2] and qn[1] == qn[2]
        origin = point(model, "stance_contact", q, p)
        assert_allclose(
            angular_momentum(bodies, qn, qdn, p, origin),
            angular_momentum(bodies, q, qd, p, origin),
            rtol=1e-12,
            atol=1e-12,
        )
        hip = point(model, "hip", q, p)
        swing = {"swing_thigh", "swing_shank"}
        assert_allclose(
            angular_momentum(bodies, qn, qdn, p, hip, swing),
            angular_momentum(bodies, q, qd, p, hip, swing),
            rtol=1e-12,
            atol=1e-12,
        )
        assert KNEED.energy(x_new, p)[0] <= KNEED.energy(x, p)[0]


def test_kneed_heel_strike_conserves_angular_momenta():
    p = _kneed_p(offset_thigh=0.01, inertia_thigh=0.01, inertia_shank=0.003)
    slope = p[12]
    model = sym.kneed_unlocked()
    bodies = body_functions(model)
    n_checked = 0
    for _ in range(40):
        alpha = RNG.uniform(0.1, 0.35)
        q = np.array([-slope - alpha, -slope + alpha, -slope + alpha])
        w = np.array([RNG.uniform(-1.5, -0.8), RNG.uniform(-0.5, 0.3)])
        x = np.array([q[0], q[1], q[2], w[0], w[1], w[1]])
        action, phase, status, x_new, imp = KNEED.reset(1, 1, x, p)
        assert (action, status) in ((EVENT_STRIDE, 0), (3, Status.NONPHYSICAL_IMPACT))
        n_checked += action == EVENT_STRIDE
        qn, qdn = x_new[:3], x_new[3:]
        assert qn[1] == qn[2] and qdn[1] == qdn[2]  # new swing knee straight
        contact = point(model, "swing_contact", q, p)
        assert_allclose(
            angular_momentum(bodies, qn, qdn, p, np.zeros(2)),
            angular_momentum(bodies, q, x[3:], p, contact),
            rtol=1e-12,
            atol=1e-12,
        )
        hip, hip_new = point(model, "hip", q, p), point(model, "hip", qn, p)
        assert_allclose(
            angular_momentum(bodies, qn, qdn, p, hip_new, {"swing_thigh", "swing_shank"}),
            angular_momentum(bodies, q, x[3:], p, hip, {"stance_thigh", "stance_shank"}),
            rtol=1e-12,
            atol=1e-12,
        )
        assert KNEED.energy(x_new, p)[0] <= KNEED.energy(x, p)[0]
    assert n_checked > 10


def test_kneed_fixed_point_from_thesis_digits():
    """Converges from Hsu Chen's published point; the exact-ODE cycle differs from it at the
    1e-3 level in angles and ~2e-2 in qd2 because the thesis integrates with explicit Euler
    at dt = 1e-3 (Hsu Chen 2007)."""
    scene = load_scene("gaits/kneed_hsu.toml")
    from walker import StrideMap
    from walker.analysis.fixedpoint import find_fixed_point

    P = StrideMap("kneed", scene.params)
    fp = find_fixed_point(P, P.project(scene.state))
    assert fp.success and fp.stable
    diff = np.abs(fp.state - scene.state)
    assert diff[:3].max() < 2e-3 and diff[3] < 1e-2 and diff[4] < 3e-2


# ---------------------------------------------------------------------------- simplest walker
def test_garcia_gaits_are_fixed_points_to_1e9():
    """Garcia et al. (1998) list both gaits at gamma = 0.009 "to 1e-10": the stable
    (0.20031090049483, -0.19983247291764) and the unstable (0.19393736960624,
    -0.20386692731962).  Both map to themselves to 1e-9 under our stride map."""
    from walker import StrideMap

    P = StrideMap("simplest", SimplestParams.garcia(), rtol=1e-13, atol=1e-13)
    for z in ([0.20031090049483, -0.19983247291764], [0.19393736960624, -0.20386692731962]):
        r = P(np.array(z))
        assert r.success
        assert_allclose(r.z, z, atol=1e-9, rtol=0)


@pytest.mark.parametrize("damping_ankle", [0.0, 0.05])
def test_compass_approaches_simplest_walker_as_leg_mass_vanishes(damping_ankle):
    """Compass gait with point masses (a = l, all leg mass at the foot, l = g = 1, hip mass
    M = 1) and beta = m/M -> 0: the fixed point approaches the simplest walker's, with a
    difference proportional to beta.  With a stance-ankle damper the compass gait's
    ``damping_ankle`` [N m s/rad] equals the simplest walker's dimensionless one
    (``M l^2 sqrt(g/l) = 1``); measured at b = 0.05: differences 1.32e-4 and 1.32e-5."""
    from walker import StrideMap
    from walker.analysis.fixedpoint import find_fixed_point

    gamma = 0.009
    z_garcia = find_fixed_point(
        StrideMap("simplest", SimplestParams.garcia(gamma)), np.array([0.2003, -0.1998])
    ).section
    simplest = SimplestParams.garcia(gamma).replace(damping_ankle=damping_ankle)
    fs = find_fixed_point(StrideMap("simplest", simplest), z_garcia)
    assert fs.success
    zs = fs.section
    if damping_ankle > 0:
        assert np.abs(zs - z_garcia).max() > 0.04  # the damper moves the gait far
    diffs = []
    betas = (1e-3, 1e-4)
    for beta in betas:
        # Goswami's point-mass legs (no inertia, point feet, no hip damper) with Garcia's
        # masses: the leg's mass beta at its foot, unit hip mass, leg length and g
        garcia = dict(mass_hip=1.0, mass_leg=beta, com_from_foot=0.0, com_to_hip=1.0, g=1.0)
        params = CompassParams.goswami(gamma).replace(**garcia, damping_ankle=damping_ankle)
        assert (params.inertia_leg, params.foot_radius, params.damping_hip) == (0.0, 0.0, 0.0)
        P = StrideMap("compass", params)
        # Garcia's theta, theta - phi: legs from the slope normal;
        # qd_swing = cos(2 theta) theta_dot.
        z0 = np.array([zs[0] - gamma, zs[1], math.cos(2 * zs[0]) * zs[1]])
        fp = find_fixed_point(P, z0)
        assert fp.success
        theta, thetad = fp.state[0] + gamma, fp.state[2]
        diffs.append(max(abs(theta - zs[0]), abs(thetad - zs[1])))
    assert diffs[1] < diffs[0] / 5  # shrinks with beta
    assert_allclose(diffs[0] / diffs[1], 10.0, rtol=0.2)  # proportionally


# ------------------------------------------------------------------------------------ limits
def test_round_feet_reduce_to_point_feet():
    from walker import StrideMap

    for name, params in (("compass", CompassParams.goswami()), ("kneed", KneedParams.hsu_chen())):
        scene_state = (
            load_scene("gaits/compass_goswami.toml").state
            if name == "compass"
            else load_scene("gaits/kneed_hsu.toml").state
        )
        P0 = StrideMap(name, params)
        Pr = StrideMap(name, params.replace(foot_radius=1e-9))
        z = P0.project(scene_state)
        assert_allclose(Pr(z).z, P0(z).z, atol=1e-7, rtol=0)


def test_kneed_with_massless_shank_and_locked_knee_is_the_compass_gait():
    """Knee held locked from the start (phase 1) and shank mass -> 0: one stride of the
    kneed walker equals the compass gait with the thigh mass as leg mass."""
    kp = KneedParams.hsu_chen().replace(mass_shank=1e-12)
    cp = CompassParams(
        mass_hip=kp.mass_hip,
        mass_leg=kp.mass_thigh,
        com_from_foot=kp.shank_com_from_foot + kp.shank_com_to_knee + kp.thigh_com_from_knee,
        com_to_hip=kp.thigh_com_to_hip,
        inertia_leg=0.0,
        foot_radius=0.0,
        slope=kp.slope,
        g=kp.g,
        damping_hip=0.0,
        damping_ankle=0.0,
    )
    xc = np.array([0.19, -0.29, -1.1, -0.2])
    slope = kp.slope
    xc[1] = -2 * slope - xc[0]
    xk = np.array([xc[0], xc[1], xc[1], xc[2], xc[3], xc[3]])
    sk = simulate("kneed", kp, xk, phase0=1, rtol=1e-12, atol=1e-12, output="events")
    sc = simulate("compass", cp, xc, rtol=1e-12, atol=1e-12, output="events")
    assert sk.success and sc.success
    assert_allclose(sk.events.t[0], sc.events.t[0], rtol=1e-9)
    pre_k = sk.events.x_pre[0]
    assert_allclose(pre_k[[0, 1, 3, 4]], sc.events.x_pre[0], atol=1e-9)


# ---------------------------------------------------------------------------- long runs, fails
def test_drake_start_walks_into_the_compass_cycle():
    """Drake's compass-gait example starts from [stance, swing, stancedot, swingdot] =
    [0, 0, 0.4, -2] in its mirrored convention (slope 0.0525, g = 9.81); mirrored to ours
    (angles and rates change sign) it walks into the stable cycle."""
    from walker import StrideMap
    from walker.analysis.fixedpoint import find_fixed_point

    params = CompassParams.drake()
    x0 = np.array([0.0, 0.0, -0.4, 2.0])
    sol = simulate("compass", params, x0, n_strides=1000, t_max=2000.0, rtol=1e-10)
    assert sol.success, sol.message
    P = StrideMap("compass", params)
    fp = find_fixed_point(P, P.project(sol.x))
    assert fp.success and fp.stable
    assert_allclose(sol.x, fp.state, atol=1e-8)


def test_failure_outcomes_are_statuses_with_times():
    compass = CompassParams.goswami()
    # Too slow: the stance leg cannot vault over the foot -> falls backward.
    slow = simulate("compass", compass, [0.2, -0.3, -0.3, 0.0])
    assert slow.status == Status.FELL_BACKWARD
    # Far too fast: falls forward before the swing leg comes through.
    fast = simulate("compass", compass, [0.2, -0.3, -4.0, 0.0])
    assert fast.status == Status.FELL_FORWARD
    # Swing leg thrown forward hard: at heel strike the trailing foot is pushed into the
    # ground -> non-physical impact.
    bad = simulate("compass", compass, [0.2, -0.3, -3.0, 3.0])
    assert bad.status == Status.NONPHYSICAL_IMPACT
    # Kneed walker too slow: the shank drops back and the bent-knee foot hits the ground.
    trip = simulate("kneed", KneedParams.hsu_chen(), [0.19, -0.29, -0.29, -0.3, 0.0, 0.0])
    assert trip.status == Status.TRIPPED
    for s in (slow, fast, bad, trip):
        assert not s.success and s.message
        assert 0.1 < s.t < 2.0  # the time it happened
        assert np.all(np.isfinite(s.x))


@pytest.mark.parametrize("name", ["kneed_coulomb", "compass_coulomb"])
def test_friction_walker_lists_its_base_models_names(name):
    """The names a friction walker takes from its base model (a module ``__getattr__``) are
    in ``__all__``, reachable as attributes, and listed by ``dir()`` (tab completion), which
    used to show only the module's own."""
    module = importlib.import_module(f"walker.models.{name}")
    listed = dir(module)
    assert listed == sorted(listed)
    for attr in BASE_EXPORTS:
        assert attr in module.__all__ and attr in listed, attr
        assert getattr(module, attr) is not None
    for attr in module.__all__:
        assert attr in listed, attr
    assert "__getattr__" in listed and "np" in listed  # the module's own names stay


# ------------------------------------------------------------ the checked compiled calls
@pytest.mark.parametrize(
    ("call", "error", "message"),
    [
        (lambda m, x, p: m.rhs(0, x[:3], p), ValueError, r"^`x` must have 6 entries, got 3$"),
        (lambda m, x, p: m.guards(0, x, p[:-1]), ValueError, r"^`p` must have 17 entries"),
        (lambda m, x, p: m.jac(2, x, p), ValueError, r"^`phase` must be in \[0, 2\), got 2$"),
        (lambda m, x, p: m.rhs(0.0, x, p), TypeError, r"^`phase` must be an int"),
        (lambda m, x, p: m.reset(0, 4, x, p), ValueError, r"^`k` must be in \[0, 4\)"),
        (lambda m, x, p: m.energy(x.reshape(2, 3), p), ValueError, r"^`x` must be 1-dim"),
        (lambda m, x, p: m.points(x.astype(str), p), TypeError, r"^`x` must hold real"),
        (lambda m, x, p: m.rhs(0, x, p, t=float("nan")), ValueError, r"^`t` must be finite"),
        (lambda m, x, p: m.kernel("bias", p, x[:3]), ValueError, r"^`name` must be one of"),
        (
            lambda m, x, p: m.kernel("unlocked_bias", p, x[:3]),
            TypeError,
            r"^`qd` is required by kernel kneed\.unlocked_bias",
        ),
        (
            lambda m, x, p: m.kernel("unlocked_mass_matrix", p, x[:3], x[3:]),
            TypeError,
            r"^`qd` is not taken by kernel kneed\.unlocked_mass_matrix",
        ),
        (
            lambda m, x, p: m.kernel("locked_mass_matrix", p, x[:3]),
            ValueError,
            r"^`q` must have 2 entries, got 3$",
        ),
        (lambda m, x, p: m.kernel("locked_kinetic", p[:5], x[:2], x[3:5]), ValueError, r"^`p`"),
        (lambda m, x, p: m.torques(x, p), ValueError, r"^model kneed has no actuators"),
    ],
)
def test_compiled_calls_check_every_argument(call, error, message):
    """Every call into the compiled model checks lengths, dtypes and indices first and names
    the argument (the C reads the model's lengths unchecked)."""
    scene = load_scene("gaits/kneed_hsu.toml")
    with pytest.raises(error, match=message):
        call(KNEED, scene.state, scene.params.as_array())


def test_compiled_calls_are_the_integrators_functions():
    """The checked calls reach the functions the integrator runs: a run's final state is a
    heel strike where the swing-foot guard is zero, the reset maps the event's pre-state to
    its post-state (to round-off: the run took the scene's ``plain`` variant, the checked
    calls the general kernels), and the kernels agree with the energy (kinetic + potential
    of the unlocked kernels)."""
    scene = load_scene("gaits/kneed_hsu.toml")
    p = scene.params.as_array()
    sol = simulate("kneed", scene.params, scene.state, output="events")
    ev = sol.events
    last = len(ev) - 1
    assert abs(KNEED.guards(int(ev.phase_before[last]), ev.x_pre[last], p)[1]) < 1e-9
    action, phase, status, x_new, _ = KNEED.reset(
        int(ev.phase_before[last]), int(ev.guard[last]), ev.x_pre[last], p, float(ev.t[last])
    )
    assert (action, phase, status) == (EVENT_STRIDE, int(ev.phase_after[last]), 0)
    np.testing.assert_allclose(x_new, ev.x_post[last], rtol=1e-13, atol=1e-13)
    x = scene.state
    kinetic = KNEED.kernel("unlocked_kinetic", p, x[:3], x[3:])
    potential = KNEED.kernel("unlocked_potential", p, x[:3])
    assert KNEED.energy(x, p) == (kinetic, potential)
