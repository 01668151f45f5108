"""Fixed points, Floquet multipliers and classification on toy section maps."""

import numpy as np
import pytest
from _toy_maps import CubicBasinMap, HenonMap, LogisticMap, ShiftMap, henon_fixed_points
from numpy.testing import assert_allclose

from walker.analysis.fixedpoint import SectionMap, classify, find_fixed_point, floquet
from walker.status import Status

B = 0.3


def test_toy_maps_satisfy_protocol():
    for m in (HenonMap(), LogisticMap(), ShiftMap(), CubicBasinMap()):
        assert isinstance(m, SectionMap)


@pytest.mark.parametrize("a", [0.05, 0.2, 0.35])
@pytest.mark.parametrize("mode", ["exact", "fd"])
def test_henon_fixed_point_matches_closed_form(a, mode):
    exact = henon_fixed_points(a, B)[0]
    fp = find_fixed_point(HenonMap(a, B), exact + [0.1, -0.05], jacobian=mode)
    assert fp.status == Status.COMPLETED and fp.success
    assert "Converged" in fp.message
    assert_allclose(fp.section, exact, rtol=0, atol=1e-12)
    assert fp.residual <= 1e-12
    assert fp.parameters == {"a": a}
    assert fp.period == 1
    assert_allclose(fp.state, np.append(fp.section, 0.0), rtol=0, atol=0)
    # Multipliers: roots of lambda^2 + 2 a x lambda - b = 0 (characteristic polynomial of
    # J = [[-2 a x, 1], [b, 0]]), sorted by decreasing modulus.
    x = exact[0]
    roots = np.roots([1.0, 2 * a * x, -B])
    roots = roots[np.argsort(-np.abs(roots))]
    assert_allclose(fp.multipliers, roots, rtol=0, atol=1e-7 if mode == "fd" else 1e-12)
    assert np.all(np.diff(np.abs(fp.multipliers)) <= 0)
    assert fp.stable == bool(np.all(np.abs(roots) < 1))
    # eigenvector columns match the multipliers
    for k in range(2):
        v = fp.eigenvectors[:, k]
        assert_allclose(fp.jacobian @ v, fp.multipliers[k] * v, rtol=0, atol=1e-7)


def test_newton_converges_quadratically():
    a = 0.2
    exact = henon_fixed_points(a, B)[0]
    fp = find_fixed_point(HenonMap(a, B), exact + [0.3, -0.1])
    h = fp.history
    assert fp.success and fp.n_iter == len(h) - 1
    assert h[0] > 0.1 and h[-1] <= 1e-12
    # e_{k+1} <= C e_k^2 once in the asymptotic range (e_k < 1e-2), C of order |F''|/|F'|.
    tail = [(h[k], h[k + 1]) for k in range(len(h) - 1) if 1e-12 < h[k] < 1e-2]
    assert len(tail) >= 2
    for e0, e1 in tail:
        assert e1 <= 5.0 * e0**2
    # and superlinear: each of those steps gains more than a factor 30
    assert all(e1 < e0 / 30 for e0, e1 in tail)


def test_exact_and_fd_jacobians_agree():
    a = 0.3
    z = henon_fixed_points(a, B)[0]
    lam_e, _, j_e = floquet(HenonMap(a, B), z, 1, jacobian="exact")
    lam_f, _, j_f = floquet(HenonMap(a, B), z, 1, jacobian="fd")
    assert_allclose(j_f, j_e, rtol=0, atol=1e-7)
    assert_allclose(lam_f, lam_e, rtol=0, atol=1e-7)
    # period 3: the exact Jacobian of the composition vs central differences of P^3
    _, _, j3e = floquet(HenonMap(a, B), z + 0.05, 3, jacobian="exact")
    _, _, j3f = floquet(HenonMap(a, B), z + 0.05, 3, jacobian="fd")
    assert_allclose(j3f, j3e, rtol=0, atol=1e-7)


def test_floquet_of_failing_point_is_nan():
    lam, vec, jac = floquet(HenonMap(fall_radius=1.0), np.array([2.0, 0.0]))
    assert np.all(np.isnan(lam)) and np.all(np.isnan(jac)) and np.all(np.isnan(vec))


def test_period_two_logistic_fixed_point():
    # 2-cycle of r x (1 - x): roots of r^2 x^2 - r (r + 1) x + (r + 1) = 0, i.e.
    # x = ((r + 1) -+ sqrt((r + 1)(r - 3))) / (2 r) (f(f(x)) = x divided by the fixed-point
    # factor); its multiplier is f'(x1) f'(x2) = 4 + 2 r - r^2.
    r = 3.2
    x_lo = ((r + 1) - np.sqrt((r + 1) * (r - 3))) / (2 * r)
    fp = find_fixed_point(LogisticMap(r), np.array([x_lo + 0.01]), period=2)
    assert fp.success and fp.period == 2
    assert_allclose(fp.section, [x_lo], rtol=0, atol=1e-12)
    assert_allclose(fp.multipliers.real, [4 + 2 * r - r * r], rtol=0, atol=1e-12)
    assert fp.stable
    assert fp.step_time == 2.0


def test_no_fixed_point_is_not_converged():
    fp = find_fixed_point(ShiftMap(shift=1.0, wiggle=0.1), np.array([0.0]))
    assert fp.status == Status.NOT_CONVERGED and not fp.success
    assert "initial guess" in fp.message
    assert fp.residual >= 0.9 - 1e-12  # |F| = |1 + 0.1 sin z| >= 0.9 everywhere
    assert np.all(np.isnan(fp.multipliers)) and not fp.stable
    assert len(fp.history) == fp.n_iter + 1


def test_singular_jacobian_status():
    # z -> z + 1: DP - I = 0 everywhere.
    fp = find_fixed_point(ShiftMap(shift=1.0), np.array([0.0]), fallback=False)
    assert fp.status == Status.LINEAR_SOLVE_FAILED
    assert "fallback=True" in fp.message
    fp = find_fixed_point(ShiftMap(shift=1.0), np.array([0.0]), fallback=True)
    assert fp.status == Status.NOT_CONVERGED
    assert "Levenberg-Marquardt" in fp.message


def test_max_iter_exhausted():
    exact = henon_fixed_points(0.2, B)[0]
    fp = find_fixed_point(HenonMap(0.2, B), exact + 0.3, max_iter=1)
    assert fp.status == Status.NOT_CONVERGED
    assert "max_iter" in fp.message and fp.n_iter == 1


def test_falling_start_passes_status_through():
    fp = find_fixed_point(HenonMap(0.2, B, fall_radius=2.0), np.array([3.0, 0.0]))
    assert fp.status == Status.FELL_FORWARD and not fp.success
    assert "walks" in fp.message
    # a guess inside the walking region converges normally
    fp = find_fixed_point(HenonMap(0.2, B, fall_radius=2.0), np.array([1.0, 0.3]))
    assert fp.success


def test_lm_fallback_rescues_singular_newton():
    # det(DP - I) = 1 + 2 a x - b vanishes on the line x = -(1 - b) / (2 a) (here x = -1.75):
    # Newton cannot start there, Levenberg-Marquardt can.
    a = 0.2
    z0 = np.array([-(1 - B) / (2 * a), 0.0])
    fp = find_fixed_point(HenonMap(a, B), z0, fallback=False)
    assert fp.status == Status.LINEAR_SOLVE_FAILED
    fp = find_fixed_point(HenonMap(a, B), z0, fallback=True)
    assert fp.success
    roots = henon_fixed_points(a, B)
    assert min(np.max(np.abs(fp.section - r)) for r in roots) <= 1e-12


def test_classify_rule():
    assert classify([0.9, -0.5 + 0.3j, -0.5 - 0.3j]) == "stable"
    assert classify([1.5, -1.2]) == "unstable"
    assert classify([1.0, 0.5]) == "saddle"  # on the unit circle counts as not inside
    assert classify([2.0, 0.1]) == "saddle"
    assert classify(np.array([1.0, 1.0])) == "unstable"
    with pytest.raises(ValueError, match="`multipliers` must be finite|All `multipliers`"):
        classify([np.nan, 0.5])
    with pytest.raises(ValueError, match="non-empty 1-D"):
        classify([])


def test_classify_henon_branches():
    a = 0.2
    stable_fp, saddle_fp = henon_fixed_points(a, B)
    fp1 = find_fixed_point(HenonMap(a, B), stable_fp)
    fp2 = find_fixed_point(HenonMap(a, B), saddle_fp)
    assert classify(fp1.multipliers) == "stable" and fp1.stable
    assert classify(fp2.multipliers) == "saddle" and not fp2.stable


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"z0": np.zeros(3)}, r"`z0` must have shape \(2,\)"),
        ({"z0": np.array([np.nan, 0.0])}, r"`z0` must be finite"),
        ({"period": 0}, r"`period` must be an integer >= 1"),
        ({"period": 1.5}, r"`period` must be an integer >= 1"),
        ({"tol": 0.0}, r"`tol` must be positive"),
        ({"tol": -1e-3}, r"`tol` must be positive"),
        ({"jacobian": "analytic"}, r"`jacobian` must be one of"),
        ({"max_iter": 0}, r"`max_iter` must be an integer >= 1"),
        ({"fd_step": 0.0}, r"`fd_step` must be positive"),
    ],
)
def test_validation(kwargs, match):
    args = {"z0": np.array([1.0, 0.3])} | kwargs
    z0 = args.pop("z0")
    with pytest.raises(ValueError, match=match):
        find_fixed_point(HenonMap(), z0, **args)


def test_floquet_validation():
    with pytest.raises(ValueError, match=r"`z` must have shape \(2,\)"):
        floquet(HenonMap(), np.zeros(1))
    with pytest.raises(ValueError, match=r"`period` must be an integer >= 1"):
        floquet(HenonMap(), np.zeros(2), 0)


# --- StrideMap and simulate resolve the model once (issue 12): same numbers as the
# --- model's own lift / project / start phase and as hybrid_solve -----------------------


@pytest.mark.parametrize(
    "scene_file",
    ["gaits/kneed_hsu.toml", "gaits/compass_goswami.toml", "gaits/simplest_garcia.toml"],
)
def test_stride_map_prepared_parts_match_model(scene_file):
    from pathlib import Path

    from walker import load_scene
    from walker.simulation.stride import StrideMap

    scene = load_scene(Path(__file__).resolve().parent.parent / scene_file)
    P = StrideMap(scene.model, scene.params, rtol=1e-10, atol=1e-10)
    model, p = P.model, scene.params.as_array()
    z = P.project(scene.state)
    r = P(z, jacobian=True)
    assert r.success
    # the slow path, written out: the model's own functions (the run carries the lift's
    # Jacobian as the seed of the variational equations)
    x0 = model.lift(z, p)
    run, _, _ = P._prepared(1)
    seed = np.ascontiguousarray(model.lift_jacobian(z, p), dtype=np.float64)
    status, t, x, jac = run.map(x0, p, model.start_phase(x0, p), P.t_max, 1, True, seed)
    assert status == 0
    np.testing.assert_array_equal(r.z, model.project(x, p))
    np.testing.assert_array_equal(r.state, x)
    assert r.step_time == t
    np.testing.assert_array_equal(r.jac, P._proj @ jac)
    # a list, an int array and a float array of the same point give the same stride
    np.testing.assert_array_equal(P(list(z)).z, P(z).z)


def test_simulate_parameter_cache_follows_the_objects():
    from walker.models import get_model
    from walker.params import CompassParams
    from walker.simulation.integrate import hybrid_solve
    from walker.simulation.stride import simulate

    model = get_model("compass")
    x0 = np.array([0.2187, -0.3234, -1.0918, -0.3772])
    for slope in (0.0525, 0.055, 0.0525):
        params = CompassParams.drake().replace(slope=slope)
        p = params.as_array()
        sol = simulate("compass", params, x0, rtol=1e-9, atol=1e-9)
        ref = hybrid_solve(
            model.system_for(p),
            x0,
            p,
            phase0=model.start_phase(x0, p),
            t_max=20.0 * np.sqrt(params.leg_length / params.g),
            rtol=1e-9,
            atol=1e-9,
        )
        assert sol.status == ref.status
        np.testing.assert_array_equal(sol.x, ref.x)
        assert sol.t == ref.t


# --- The stride map's Jacobian from the seeded variational equations (issue 12): the run
# --- carries only the n_z columns (d x / d x0) . lift_jacobian, not all of d x / d x0 ------

SEEDED_SCENES = [
    "gaits/kneed_hsu.toml",
    "gaits/compass_goswami.toml",
    "gaits/simplest_garcia.toml",  # a lift that is not affine: lift_jacobian(z) per call
    "gaits/rimless_wheel.toml",
    "gaits/three_link_grizzle.toml",  # hybrid zero dynamics
    "gaits/kneed_coulomb_hsu.toml",  # joint friction: phases by joint mode
]


def _full_and_seeded(P, z):
    """The map's Jacobian both ways on the same compiled run: ``project . (d x / d x0) .
    lift_jacobian`` from the full sensitivity matrix, and ``P(z, jacobian=True).jac`` (the
    seeded run); plus both runs' final states and times."""
    run, p, _ = P._prepared(1)
    model = P.model
    x0 = np.ascontiguousarray(model.lift(z, p), dtype=np.float64)
    lift_jac = model.lift_jacobian(z, p)
    status, t, x, jac = run.map(x0, p, model.start_phase(x0, p), P.t_max, 1, True)
    assert status == 0
    r = P(z, jacobian=True)
    assert r.success
    return P._proj @ jac @ lift_jac, r.jac, (x, t), (r.state, r.step_time)


def _scene_map(scene_file, **settings):
    from pathlib import Path

    from walker import load_scene
    from walker.simulation.stride import StrideMap

    scene = load_scene(Path(__file__).resolve().parent.parent / scene_file)
    P = StrideMap(scene.model, scene.params, **settings)
    return P, P.project(scene.state)


@pytest.mark.parametrize("scene_file", SEEDED_SCENES)
def test_seeded_jacobian_equals_full_jacobian_times_seed_on_the_same_steps(scene_file):
    """With a fixed step (RK4) both runs take the same steps and locate the same events (the
    guards read the state only), so the seeded run's Jacobian is the full one times the seed
    up to rounding of the reassociated products: within 1e-12 relative to the largest
    entry (measured: 5e-14 at most)."""
    P, z = _scene_map(scene_file, method="RK4", first_step=2e-3)
    full, seeded, (x, t), (x_s, t_s) = _full_and_seeded(P, z)
    np.testing.assert_array_equal(x_s, x)
    assert t_s == t
    assert seeded.shape == full.shape == (P.n_z, P.n_z)
    assert np.max(np.abs(seeded - full)) <= 1e-12 * np.max(np.abs(full))


@pytest.mark.parametrize("scene_file", [f for f in SEEDED_SCENES if "three_link" not in f])
def test_seeded_jacobian_with_adaptive_steps_agrees_to_the_integration_error(scene_file):
    """With the scene's adaptive settings (DOP853, rtol = atol = 1e-12) the step control
    measures the components each run carries, so the steps differ and the two Jacobians
    agree to the integration error, not to rounding: measured 5e-11 relative at most over
    these scenes; gated at 1e-9.  (The three-link scene's Jacobian at its initial state is
    not resolved to better than O(1) between tolerances, full or seeded, so it is checked on
    equal steps only.)"""
    P, z = _scene_map(scene_file, rtol=1e-12, atol=1e-12)
    full, seeded, (x, t), (x_s, t_s) = _full_and_seeded(P, z)
    assert np.max(np.abs(seeded - full)) <= 1e-9 * np.max(np.abs(full))
    assert np.max(np.abs(x_s - x)) <= 1e-11
    assert abs(t_s - t) <= 1e-11


def test_eig_sorted_gives_the_values_of_numpy_eig(monkeypatch):
    """eig_sorted calls numpy's eigen kernel directly for a finite float64 matrix: the same
    eigenvalues and eigenvectors, bit for bit, as through np.linalg.eig (real and complex
    spectra, 1 x 1 to 6 x 6), and a matrix with a NaN still raises as np.linalg.eig does."""
    import walker.simulation.sectionmap as sectionmap

    rng = np.random.default_rng(0)
    matrices = []
    for k in range(300):
        a = rng.normal(size=(1 + k % 6, 1 + k % 6))
        matrices.append(a + a.T if k % 2 else a)  # symmetric: every eigenvalue real
    fast = [sectionmap.eig_sorted(a) for a in matrices]
    monkeypatch.setattr(sectionmap, "_EIG", None)
    for a, (lam, vec) in zip(matrices, fast, strict=True):
        lam_ref, vec_ref = sectionmap.eig_sorted(a)
        assert lam.dtype == lam_ref.dtype == np.complex128
        assert np.array_equal(lam, lam_ref) and np.array_equal(vec, vec_ref)
    monkeypatch.undo()
    with pytest.raises(np.linalg.LinAlgError):
        sectionmap.eig_sorted(np.array([[np.nan, 0.0], [0.0, 1.0]]))
