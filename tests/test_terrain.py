"""Terrain defined per step (walker/simulation/terrain.py, walker/_core/terrain.c): the rimless
wheel's stride map on random slopes against its closed form, the terrain Jacobian columns against
finite differences of whole runs, plane terrain bit for bit against the plane path, and the
geometry of a step down."""

import math

import numpy as np
import pytest

from walker import StrideMap, load_scene
from walker.simulation.terrain import Terrain
from walker.status import Status

RIMLESS = "gaits/rimless_wheel.toml"
COMPASS = "gaits/compass_goswami.toml"


def _map(path, **kw):
    scene = load_scene(path)
    P = StrideMap.from_scene(scene)
    if kw:
        P = StrideMap(P.model, P.params, rtol=kw.get("rtol", P.rtol), atol=kw.get("atol", P.atol))
    return scene, P, P.project(scene.state)


# --- the rimless wheel against its closed form ------------------------------------------


def _rimless_closed_form(p, w_plus, slopes):
    """The rimless wheel's rate magnitudes after each stride on slopes ``slopes`` (drop 0),
    from a start just after landing on the scene's plane: energy between impacts, angular
    momentum about the new foot at impacts (McGeer 1990; Byl & Tedrake 2009, section 3).

    With phi the stance spoke's angle from the vertical, a spoke that landed on a plane of
    slope gamma starts at phi = alpha - gamma (both feet on that plane) and the next impact
    on slope gamma' is at phi = -(alpha + gamma'); the hub's height is l cos(phi), so
    1/2 w-^2 = 1/2 w+^2 + (g/l)(cos(gamma_prev - alpha) - cos(gamma + alpha)),
    w+_next = cos(2 alpha) w-; the wheel passes over its stance spoke only if
    1/2 w+^2 > (g/l)(1 - cos(gamma_prev - alpha)) when gamma_prev < alpha.
    Returns the list of w+ after each completed stride and the index of the stride that
    rolled back (None if none did)."""
    alpha = math.pi / p.spokes
    gl = p.g / p.leg_length
    prev = p.slope
    out = []
    for n, gamma in enumerate(slopes):
        if prev < alpha and 0.5 * w_plus**2 <= gl * (1.0 - math.cos(prev - alpha)):
            return out, n
        w_minus = math.sqrt(
            w_plus**2 + 2.0 * gl * (math.cos(prev - alpha) - math.cos(gamma + alpha))
        )
        w_plus = math.cos(2.0 * alpha) * w_minus
        out.append(w_plus)
        prev = gamma
    return out, None


def test_rimless_wheel_random_slopes_match_the_closed_form():
    """Cases drawn here: slopes N(scene slope, 0.04^2), 6 strides each; walker's state
    after k strides (theta_dot = -w+) and its status against the closed form."""
    scene, P, z = _map(RIMLESS)
    rng = np.random.default_rng(20291)
    rolled = completed = 0
    for _ in range(12):
        slopes = scene.params.slope + 0.04 * rng.standard_normal(6)
        w0 = abs(z[0]) * rng.uniform(0.6, 1.3)
        expected, fail = _rimless_closed_form(scene.params, w0, slopes)
        rows = np.column_stack([slopes, np.zeros(6)])
        for k in range(1, 7):
            r = P(np.array([-w0]), terrain=rows[:k], n_strides=k)
            if fail is not None and k > fail:
                assert r.status == Status.ROLLED_BACK
                rolled += 1
                break
            assert r.status == Status.COMPLETED
            np.testing.assert_allclose(-r.z[0], expected[k - 1], rtol=1e-9, atol=0)
            completed += 1
    assert rolled >= 1 and completed >= 20  # both branches were exercised


def test_rimless_wheel_terrain_jacobian_matches_the_closed_form():
    """d w+ / d gamma and d w+ / d h of one stride: walker's terrain_jac against the closed
    form's derivative (the landing angle on a plane h below: 2 l sin(alpha) sin(u) +
    h cos(gamma) = 0, u = phi + gamma + alpha), by central differences of the formula."""
    scene, P, z = _map(RIMLESS)
    p = scene.params
    alpha, l, gl = math.pi / p.spokes, p.leg_length, p.g / p.leg_length

    def w_next(gamma, h):
        u = -math.asin(h * math.cos(gamma) / (2.0 * l * math.sin(alpha)))
        phi_minus = u - gamma - alpha
        e = 0.5 * z[0] ** 2 + gl * (math.cos(alpha - p.slope) - math.cos(phi_minus))
        return -math.cos(2.0 * alpha) * math.sqrt(2.0 * e)

    rng = np.random.default_rng(7)
    for _ in range(4):
        gamma, h = p.slope + 0.02 * rng.standard_normal(), 0.01 * rng.standard_normal()
        r = P(z, terrain=[[gamma, h]], jacobian=True)
        assert r.status == Status.COMPLETED
        np.testing.assert_allclose(r.z[0], w_next(gamma, h), rtol=1e-10, atol=0)
        e = 1e-5
        d_gamma = (w_next(gamma + e, h) - w_next(gamma - e, h)) / (2 * e)
        d_h = (w_next(gamma, h + e) - w_next(gamma, h - e)) / (2 * e)
        np.testing.assert_allclose(r.terrain_jac[0], [d_gamma, d_h], rtol=1e-7, atol=0)


def test_rimless_wheel_walk_from_a_landed_state_matches_the_closed_form():
    """StrideMap.walk from the state just after landing on slope gamma_prev (the spoke at
    alpha - gamma_prev from the vertical: theta = alpha - gamma_prev + slope from the scene's
    normal), one stride on gamma: w+ = cos(2 alpha) sqrt(w^2 + 2 (g/l)(cos(gamma_prev -
    alpha) - cos(gamma + alpha))); its dz/dx0 against central differences of walks."""
    scene, P, z = _map(RIMLESS)
    p = scene.params
    alpha, gl = math.pi / p.spokes, p.g / p.leg_length
    rng = np.random.default_rng(11)
    for _ in range(5):
        g_prev, gamma = p.slope + 0.03 * rng.standard_normal(2)
        w = abs(z[0]) * rng.uniform(1.0, 1.4)
        x0 = np.array([alpha - g_prev + p.slope, -w])
        r = P.walk(x0, [[gamma, 0.0]], previous=(g_prev, 0.0), jacobian=True)
        assert r.status == Status.COMPLETED
        expected = math.cos(2 * alpha) * math.sqrt(
            w**2 + 2 * gl * (math.cos(g_prev - alpha) - math.cos(gamma + alpha))
        )
        np.testing.assert_allclose(-r.z[0], expected, rtol=1e-10, atol=0)
        assert r.jac.shape == (1, 2)
        e = 1e-6
        for j in range(2):
            d = np.zeros(2)
            d[j] = e
            up = P.walk(x0 + d, [[gamma, 0.0]]).z
            down = P.walk(x0 - d, [[gamma, 0.0]]).z
            np.testing.assert_allclose(r.jac[0, j], (up - down)[0] / (2 * e), rtol=1e-6, atol=1e-9)


def test_walk_continues_a_walk():
    """A walk from the state a terrain call ended in, with `previous` its last step, is the
    same walk as one call over both steps (to the tolerance: two integrations)."""
    scene, P, z = _map(COMPASS)
    s = scene.params.slope
    rows = np.array([[s + 0.004, 0.003], [s - 0.002, -0.002]])
    both = P(z, terrain=rows, n_strides=2)
    first = P(z, terrain=rows[:1])
    second = P.walk(first.state, rows[1:], previous=rows[0])
    np.testing.assert_allclose(second.z, both.z, rtol=1e-9, atol=1e-10)


# --- terrain Jacobian columns against finite differences ---------------------------------


@pytest.mark.parametrize(
    ("path", "size", "e"),
    [
        (COMPASS, 1.0, 1e-6),
        (RIMLESS, 1.0, 1e-6),
        ("gaits/kneed_hsu.toml", 0.3, 1e-6),
        ("gaits/kneed_mcgeer_pointmass.toml", 0.3, 1e-6),
        ("gaits/simplest_garcia.toml", 0.03, 1e-7),
        ("gaits/compass_coulomb_goswami.toml", 0.3, 1e-6),
        ("gaits/kneed_coulomb_hsu.toml", 0.3, 1e-6),
        ("gaits/three_link_grizzle.toml", -0.2, 1e-6),
        ("gaits/five_link_hzd.toml", 0.3, 1e-6),
    ],
)
def test_terrain_jacobian_columns_match_finite_differences(path, size, e):
    """Three strides over rough steps: d z_3 / d(slope_k, drop_k) for every step k against
    central differences of whole runs (steps ``e``, the scenes' rtol).  The three-link
    walker's steps go up (``size`` < 0): its rigid swing foot dips under the ground just past
    the stance foot, so a plane dropped by less than that dip is touched there."""
    scene, P, z = _map(path)
    slope = scene.params.slope
    rows = np.array([[slope + 0.01 * size, 0.01 * size], [slope, 0.0]])
    rows = np.vstack([rows, [[slope - 0.008 * size, -0.004 * abs(size)]]])
    if size < 0:
        rows[1, 1] = -0.005
    r = P(z, terrain=rows, n_strides=3, jacobian=True)
    assert r.status == Status.COMPLETED and r.terrain_jac.shape == (P.n_z, 6)
    fd = np.empty((P.n_z, 6))
    for k in range(6):
        d = np.zeros(6)
        d[k] = e
        up = P(z, terrain=rows + d.reshape(3, 2), n_strides=3).z
        down = P(z, terrain=rows - d.reshape(3, 2), n_strides=3).z
        fd[:, k] = (up - down) / (2 * e)
    scale = np.abs(fd).max()
    np.testing.assert_allclose(r.terrain_jac, fd, rtol=2e-6, atol=2e-7 * scale)
    # and the state columns of the same call
    plain = P(z, terrain=rows, n_strides=3)
    np.testing.assert_allclose(r.z, plain.z, rtol=1e-9, atol=1e-11)


# --- plane terrain is the plane path, bit for bit ----------------------------------------


@pytest.mark.parametrize(
    "path",
    [
        COMPASS,
        RIMLESS,
        "gaits/simplest_garcia.toml",
        "gaits/kneed_mcgeer_pointmass.toml",
        "gaits/compass_coulomb_goswami.toml",
        "gaits/kneed_coulomb_hsu.toml",
        "gaits/three_link_grizzle.toml",
        "gaits/five_link_hzd.toml",
    ],
)
def test_plane_terrain_is_bit_identical(path):
    scene, P, z = _map(path)
    slope = scene.params.slope
    for kind in (Terrain("plane"), Terrain("random", slope_std=0.0, height_std=0.0, seed=1)):
        for n in (1, 4):
            rows = kind.steps(n, slope=slope)
            a, b = P(z, n_strides=n), P(z, n_strides=n, terrain=rows)
            assert a.status == b.status == Status.COMPLETED
            assert np.array_equal(a.z, b.z) and np.array_equal(a.state, b.state)
            assert a.step_time == b.step_time
    a = P(z, jacobian=True)
    b = P(z, jacobian=True, terrain=[[slope, 0.0]])
    assert np.array_equal(a.z, b.z) and np.array_equal(a.jac, b.jac)
    assert b.terrain_jac.shape == (P.n_z, 2)


def test_rimless_wheel_turning_back_is_rolled_back_on_terrain_only():
    """Too slow to get over the top (1/2 w^2 < (g/l)(1 - cos(alpha - slope)), the closed
    form's condition): on the plane path the wheel rocks to rest and the run ends NO_EVENT
    at t_max, as before; on terrain, plane rows included, ROLLED_BACK."""
    scene, P, z = _map(RIMLESS)
    p = scene.params
    alpha = math.pi / p.spokes
    w_top = math.sqrt(2.0 * p.g / p.leg_length * (1.0 - math.cos(alpha - p.slope)))
    slow = np.array([-0.9 * w_top])
    assert P(slow).status == Status.NO_EVENT
    assert P(slow, terrain=[[p.slope, 0.0]]).status == Status.ROLLED_BACK
    steps, status = P.ensemble(slow, np.array([[[p.slope, 0.0]] * 3]))
    assert steps[0] == 0 and status[0] == Status.ROLLED_BACK
    fast = np.array([-1.1 * w_top])
    assert P(fast, terrain=[[p.slope, 0.0]]).status == Status.COMPLETED


def test_ensemble_matches_single_walks_for_any_thread_count():
    scene, P, z = _map(COMPASS)
    rng = np.random.default_rng(3)
    ter = np.zeros((7, 5, 2))
    ter[..., 0] = scene.params.slope + 0.004 * rng.standard_normal((7, 5))
    one, st1 = P.ensemble(z, ter, threads=1)
    two, st2 = P.ensemble(z, ter, threads=3)
    assert np.array_equal(one, two) and np.array_equal(st1, st2)
    for i in range(7):
        r = P(z, terrain=ter[i], n_strides=5)
        assert st1[i] == r.status
        if r.status == Status.COMPLETED:
            assert one[i] == 5


# --- a step down: later, lower, on the given plane ---------------------------------------


def test_compass_step_down_lands_on_the_plane_later_and_lower():
    """The touchdown foot, from the post-impact angles (absolute, from the vertical; the old
    stance foot at the origin, x downhill): hip = L(-sin q_old, cos q_old), new foot = hip -
    L(-sin q_new, cos q_new).  It lies on the plane h below with slope gamma to 1e-12, and a
    step down lands later and lower than on the plane."""
    scene, P, z = _map(COMPASS)
    p = scene.params
    L = p.com_from_foot + p.com_to_hip
    flat = P(z, terrain=[[p.slope, 0.0]])
    previous = flat
    for h in (0.002, 0.01, 0.03):
        gamma = p.slope + 0.005
        r = P(z, terrain=[[gamma, h]])
        assert r.status == Status.COMPLETED
        q_new, q_old = r.state[0], r.state[1]
        X = -L * math.sin(q_old) + L * math.sin(q_new)
        Y = L * math.cos(q_old) - L * math.cos(q_new)
        assert abs(X * math.sin(gamma) + (Y + h) * math.cos(gamma)) < 1e-12
        assert r.step_time > previous.step_time
        Y_prev = L * math.cos(previous.state[1]) - L * math.cos(previous.state[0])
        assert Y < Y_prev
        previous = r


# --- round feet -----------------------------------------------------------------------------


def _round_compass():
    scene = load_scene(COMPASS)
    params = scene.params.replace(foot_radius=0.1)
    P = StrideMap("compass", params, rtol=1e-12, atol=1e-12)
    from walker import find_fixed_point

    gait = find_fixed_point(P, P.project(scene.state))
    assert gait.status == Status.COMPLETED
    return params, P, gait.section


def test_round_feet_touch_down_on_the_plane():
    """Round feet (radius R): the stance foot's centre starts R above the contact it landed
    at and rolls R (q_land - q) along its plane; the swing foot's centre sits (L - R)(sin q_sw
    - sin q_st, cos q_st - cos q_sw) from it (angles from the vertical).  At touchdown the
    swing foot's lowest point, R below its centre, lies on the step's plane (1e-12), and the
    plane rows give the plane's numbers bit for bit."""
    params, P, z = _round_compass()
    g0, R = params.slope, params.foot_radius
    L = params.com_from_foot + params.com_to_hip
    a, b = P(z, n_strides=2), P(z, n_strides=2, terrain=[[g0, 0.0], [g0, 0.0]])
    assert np.array_equal(a.z, b.z) and a.step_time == b.step_time
    q_land = P.lift(z)[0]
    for gamma, h in [(g0 + 0.01, 0.005), (g0 - 0.02, -0.003), (g0 + 0.03, 0.0)]:
        r = P(z, terrain=[[gamma, h]])
        assert r.status == Status.COMPLETED
        q_new, q_old = r.state[0], r.state[1]  # the legs swapped at touchdown
        t_s = np.array([math.cos(g0), -math.sin(g0)])
        n_s = np.array([math.sin(g0), math.cos(g0)])
        centre = R * (q_land - q_old) * t_s + R * n_s
        swing = centre + (L - R) * np.array(
            [math.sin(q_new) - math.sin(q_old), math.cos(q_old) - math.cos(q_new)]
        )
        normal = np.array([math.sin(gamma), math.cos(gamma)])
        assert abs(swing @ normal + h * math.cos(gamma) - R) < 1e-12


def test_round_feet_roll_on_the_plane_they_landed_on():
    """In the second step the stance foot rolls on the first step's plane: the walker's
    energy (the model's, its slope parameter that plane's) is conserved there to the
    tolerance, and not with the scene's slope."""
    from walker import simulate
    from walker.models import get_model

    params, P, z = _round_compass()
    g1 = params.slope + 0.05
    sol = simulate(
        "compass", params, P.lift(z), n_strides=2, output="full", terrain=[[g1, 0.0], [g1, 0.0]]
    )
    assert sol.status == Status.COMPLETED
    t_event = sol.events.t[0]
    energy = get_model("compass").energy
    t = sol.record.t
    second = sol.record.x[(t > t_event + 1e-9) & (t < sol.events.t[1] - 1e-9)]
    assert len(second) > 10
    on_plane = [sum(energy(x, params.replace(slope=g1))) for x in second]
    on_scene = [sum(energy(x, params)) for x in second]
    assert np.ptp(on_plane) < 1e-9 * abs(np.mean(on_plane))
    assert np.ptp(on_scene) > 1e-4 * abs(np.mean(on_scene))


@pytest.mark.parametrize("path", [COMPASS, "gaits/kneed_hsu.toml"])
def test_round_feet_jacobians_match_finite_differences(path):
    """Round feet: a step's slope also moves the next step's rolling flow and touchdown (the
    stance foot rolls on it), and the landing angle the guard; dz/dz0 and the terrain
    columns of three strides against central differences of whole walks."""
    from walker import find_fixed_point

    scene = load_scene(path)
    params = scene.params.replace(foot_radius=0.1 if path == COMPASS else 0.05)
    P = StrideMap(scene.walker_model, params, rtol=1e-12, atol=1e-12)
    z = find_fixed_point(P, P.project(scene.state)).section
    s = params.slope
    rows = np.array([[s + 0.004, 0.002], [s - 0.003, -0.001], [s + 0.002, 0.001]])
    r = P(z, terrain=rows, n_strides=3, jacobian=True)
    assert r.status == Status.COMPLETED
    e = 1e-6
    fd = np.empty((P.n_z, 6))
    for k in range(6):
        d = np.zeros(6)
        d[k] = e
        up = P(z, terrain=rows + d.reshape(3, 2), n_strides=3).z
        down = P(z, terrain=rows - d.reshape(3, 2), n_strides=3).z
        fd[:, k] = (up - down) / (2 * e)
    np.testing.assert_allclose(r.terrain_jac, fd, rtol=1e-6, atol=1e-7 * np.abs(fd).max())
    fz = np.empty((P.n_z, P.n_z))
    for k in range(P.n_z):
        d = np.zeros(P.n_z)
        d[k] = e
        fz[:, k] = (
            P(z + d, terrain=rows, n_strides=3).z - P(z - d, terrain=rows, n_strides=3).z
        ) / (2 * e)
    np.testing.assert_allclose(r.jac, fz, rtol=1e-6, atol=1e-7 * np.abs(fz).max())


# --- input errors ---------------------------------------------------------------------------


def test_terrain_input_errors_name_the_argument():
    scene, P, z = _map(COMPASS)
    with pytest.raises(ValueError, match="terrain"):
        P(z, terrain=[[0.0, 0.0], [0.0, 0.0]])  # n_strides = 1
    with pytest.raises(ValueError, match="finite"):
        P(z, terrain=[[np.nan, 0.0]])
    with pytest.raises(ValueError, match="kind"):
        Terrain("bumpy")
    with pytest.raises(ValueError, match="slope_std"):
        Terrain("random", slope_std=-1.0)
    with pytest.raises(ValueError, match="same length"):
        Terrain("steps", slopes=(0.1, 0.2), heights=(0.0,))
    five = load_scene("gaits/five_link_hzd.toml")
    F = StrideMap.from_scene(five)
    z_far = F.project(five.state)
    z_far[3] = 1.5  # the swing femur so far forward that the foot cannot reach the slope
    with pytest.raises(ValueError, match="`z` must leave the swing foot able to reach"):
        F(z_far, terrain=[[five.params.slope, 0.0]], jacobian=True)
    book = load_scene("gaits/three_link_book.toml")
    B = StrideMap.from_scene(book)
    with pytest.raises(ValueError, match="`three_link` with `step_event` = 1"):
        B(B.project(book.state), terrain=[[book.params.slope, 0.0]])


def test_five_link_walks_on_terrain_without_a_compiled_map():
    """The five-link walker's map has no compiled call (its lift solves for the tibia
    angle); its terrain runs take the compiled lift of its terrain entry
    (walker/_core/model_five_link.c): plane rows give the map's numbers bit for bit, rough
    rows a different walk."""
    five = load_scene("gaits/five_link_hzd.toml")
    F = StrideMap.from_scene(five)
    z, slope = F.project(five.state), five.params.slope
    a = F(z, n_strides=2)
    b = F(z, n_strides=2, terrain=[[slope, 0.0], [slope, 0.0]])
    assert a.status == b.status == Status.COMPLETED and np.array_equal(a.z, b.z)
    c = F(z, n_strides=2, terrain=[[slope + 0.01, -0.005], [slope, 0.0]])
    assert c.status == Status.COMPLETED and not np.allclose(c.z, a.z, rtol=1e-6, atol=1e-6)


def test_terrain_steps_kinds():
    t = Terrain("steps", slopes=(0.1, 0.2), slope_mean=0.05)
    np.testing.assert_array_equal(t.steps(3), [[0.1, 0.0], [0.2, 0.0], [0.05, 0.0]])
    r = Terrain("random", slope_mean=0.01, slope_std=0.1, height_std=0.01, seed=5)
    np.testing.assert_array_equal(r.steps(4), r.steps(4))  # seeded
    draws = np.random.default_rng(5).standard_normal((4, 2))
    np.testing.assert_allclose(r.steps(4)[:, 0], 0.01 + 0.1 * draws[:, 0], rtol=1e-15, atol=0)
    assert Terrain.from_table({"kind": "plane"}, 0.03).steps(1).tolist() == [[0.03, 0.0]]


def test_docs_terrain_md_examples_run():
    """docs/terrain.md's examples, run as doctests."""
    import doctest
    from pathlib import Path

    path = Path(__file__).resolve().parent.parent / "docs" / "terrain.md"
    text = path.read_text(encoding="utf-8")
    parser = doctest.DocTestParser()
    test = parser.get_doctest(text, {}, "terrain.md", str(path), 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    import os

    old = os.getcwd()
    os.chdir(path.parent.parent)
    try:
        runner.run(test)
    finally:
        os.chdir(old)
    result = runner.summarize(verbose=False)
    assert result.attempted >= 8 and result.failed == 0


# --- scenes and the command line -------------------------------------------------------------


def test_walker_run_walks_on_terrain_and_records_it(tmp_path, capsys):
    from walker.cli import main
    from walker.storage import read

    out = tmp_path / "run.h5"
    code = main(
        [
            "run",
            COMPASS,
            "--strides",
            "4",
            "--terrain-std",
            "0.001",
            "--seed",
            "3",
            "--out",
            str(out),
        ]
    )
    text = capsys.readouterr().out
    assert code == 0 and "terrain: random" in text and "seed 3" in text
    sol, prov = read(out)
    assert prov["terrain"]["slope_std"] == 0.001 and prov["terrain"]["seed"] == 3
    # the same walk from Python: simulate over the same draws
    from walker import simulate

    scene = load_scene(COMPASS)
    rows = Terrain("random", slope_mean=scene.params.slope, slope_std=0.001, seed=3).steps(4)
    c = scene.compute
    again = simulate(
        scene.walker_model,
        scene.params,
        scene.state,
        n_strides=4,
        t_max=c.t_max * 4,
        method=c.method,
        rtol=c.rtol,
        atol=c.atol,
        first_step=c.first_step,
        terrain=rows,
    )
    assert np.array_equal(again.x, sol.x)
    # zero standard deviations: the plane's run, bit for bit
    main(["run", COMPASS, "--strides", "4", "--out", str(tmp_path / "a.h5")])
    main(["run", COMPASS, "--strides", "4", "--terrain-std", "0", "--out", str(tmp_path / "b.h5")])
    assert np.array_equal(read(tmp_path / "a.h5")[0].x, read(tmp_path / "b.h5")[0].x)


def test_walker_run_refuses_bad_terrain_flags(capsys):
    from walker.cli import main

    assert main(["run", COMPASS, "--terrain-std", "-1"]) == 2
    assert "--terrain-std" in capsys.readouterr().err
    assert main(["run", "gaits/three_link_book.toml", "--terrain-std", "0.01"]) == 2
    assert "step_event" in capsys.readouterr().err


def test_scene_terrain_table(tmp_path):
    text = open(COMPASS, encoding="utf-8").read()
    path = tmp_path / "s.toml"
    path.write_text(text + '\n[terrain]\nkind = "steps"\nheights = [0.01, 0.0]\n', encoding="utf-8")
    scene = load_scene(path)
    assert scene.terrain.kind == "steps" and scene.terrain.slope_mean == scene.params.slope
    np.testing.assert_array_equal(scene.terrain.steps(3)[:, 1], [0.01, 0.0, 0.0])
    path.write_text(text + '\n[terrain]\nkind = "random"\nseed = -1\n', encoding="utf-8")
    with pytest.raises(ValueError, match=r"\[terrain\] `seed` must be >= 0"):
        load_scene(path)
