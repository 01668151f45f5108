"""Mean first-passage time (walker/analysis/mfpt.py, walker/analysis/markov.py) against the rimless
wheel's closed form on random slopes (McGeer 1990; Byl & Tedrake, IJRR 28(8), 2009, section 3):

    1/2 w-^2 = 1/2 w+^2 + (g/l)(cos(g_prev - a) - cos(g + a)),   w+_next = cos(2a) w-,

and the wheel passes over its stance spoke only if 1/2 w+^2 > (g/l)(1 - cos(g_prev - a)) when
g_prev < a (else it rolls back: the failure).  The closed-form Monte Carlo and the
closed-form Markov chain below are pure numpy, written here from these formulas."""

import math

import numpy as np
import pytest

from walker import StrideMap, load_scene
from walker.analysis.markov import build_chain, markov_chain, slope_nodes
from walker.analysis.mfpt import gait_on_mean_slope, monte_carlo, run_seeds, run_terrain
from walker.simulation.terrain import Terrain
from walker.status import Status

RIMLESS = "gaits/rimless_wheel.toml"
MEAN = 0.08


@pytest.fixture(scope="module")
def rimless():
    scene = load_scene(RIMLESS)
    P = StrideMap.from_scene(scene).with_tolerance(1e-10, 1e-10)
    P, z0 = gait_on_mean_slope(P, scene.state, MEAN)
    return scene.params, P, z0


def _closed_form_step(p, w, prev, gamma):
    """(completed, w+ next) of one stride from rate magnitude ``w`` landed on ``prev``."""
    a, gl = math.pi / p.spokes, p.g / p.leg_length
    if prev < a and 0.5 * w * w <= gl * (1.0 - math.cos(prev - a)):
        return False, math.nan
    w_minus = math.sqrt(w * w + 2.0 * gl * (math.cos(prev - a) - math.cos(gamma + a)))
    return True, math.cos(2.0 * a) * w_minus


def _closed_form_steps(p, w, slopes):
    prev = MEAN
    for n, gamma in enumerate(slopes):
        ok, w = _closed_form_step(p, w, prev, gamma)
        if not ok:
            return n
        prev = gamma
    return len(slopes)


def test_monte_carlo_matches_the_closed_form_run_by_run(rimless):
    """Every run's completed steps against the closed form walked over the same draws (the
    per-run seeds of :func:`run_seeds`)."""
    p, P, z0 = rimless
    std, runs, seed = 0.02, 300, 11
    r = monte_carlo(P, z0, slope_std=std, runs=runs, seed=seed)
    assert r.failed == runs and set(r.failures_by_status()) == {"ROLLED_BACK"}
    terrain = Terrain("random", slope_mean=MEAN, slope_std=std)
    children = run_seeds(seed, runs)
    expected = np.array(
        [
            _closed_form_steps(
                p, -z0[0], run_terrain(children[i], int(r.steps[i]) + 1, terrain)[:, 0]
            )
            for i in range(runs)
        ]
    )
    np.testing.assert_array_equal(r.steps, expected)
    np.testing.assert_allclose(r.mfpt, expected.mean(), rtol=1e-15, atol=0)
    np.testing.assert_allclose(
        r.mfpt_stderr, expected.std(ddof=1) / math.sqrt(runs), rtol=1e-12, atol=0
    )


def test_monte_carlo_is_the_same_for_any_jobs_and_horizon(rimless):
    """Threads and the doubling horizon (a survivor walked again over longer terrain whose
    first rows are the same draws) change nothing."""
    _, P, z0 = rimless
    a = monte_carlo(P, z0, slope_std=0.015, runs=120, seed=5, jobs=1, steps=256)
    b = monte_carlo(P, z0, slope_std=0.015, runs=120, seed=5, jobs=2, steps=2)
    np.testing.assert_array_equal(a.steps, b.steps)
    np.testing.assert_array_equal(a.status, b.status)


def test_monte_carlo_censoring_uses_the_geometric_estimate(rimless):
    """Runs still walking at ``max_steps`` are censored: mfpt = sum of steps / failures."""
    _, P, z0 = rimless
    r = monte_carlo(P, z0, slope_std=0.01, runs=50, seed=2, steps=4, max_steps=8)
    censored = r.status == Status.COMPLETED
    assert censored.any() and r.failed < r.runs
    assert (r.steps[censored] == 8).all()
    np.testing.assert_allclose(r.mfpt, r.steps.sum() / r.failed, rtol=1e-15, atol=0)


def _closed_form_chain(p, meshes_w, slopes, mass, w0):
    """The product chain (rate grid of each slope node x slope nodes) of the closed-form map,
    pure numpy: its transient block's spectral radius and the expected steps from the
    start.  ``meshes_w``: one rate grid per slope node (or one array for all)."""
    m = slopes.size
    if isinstance(meshes_w, np.ndarray):
        meshes_w = [meshes_w] * m
    sizes = [w.size for w in meshes_w]
    offset = np.concatenate([[0], np.cumsum(sizes)])
    Q = np.zeros((offset[-1], offset[-1]))

    def spread(row, w, k, weight):
        order = np.argsort(meshes_w[k])
        grid = meshes_w[k][order]
        x = min(max(w, grid[0]), grid[-1])
        hi = min(max(int(np.searchsorted(grid, x)), 1), grid.size - 1)
        t = (x - grid[hi - 1]) / (grid[hi] - grid[hi - 1])
        row[offset[k] + order[hi - 1]] += weight * (1.0 - t)
        row[offset[k] + order[hi]] += weight * t

    for j in range(m):
        for i, w_i in enumerate(meshes_w[j]):
            for k in range(m):
                ok, w = _closed_form_step(p, w_i, slopes[j], slopes[k])
                if ok:
                    spread(Q[offset[j] + i], w, k, mass[k])
    start = np.zeros(offset[-1])
    for k in range(m):
        ok, w = _closed_form_step(p, w0, MEAN, slopes[k])
        if ok:
            spread(start, w, k, mass[k])
    lam = np.max(np.abs(np.linalg.eigvals(Q)))
    expected = np.linalg.solve(np.eye(offset[-1]) - Q, Q.sum(axis=1))
    return lam, start @ (1.0 + expected)


def test_markov_chain_matches_the_closed_form_chain(rimless):
    """walker's chain (strides of the compiled map) against the same discretisation of the
    closed-form map: lambda_2 and the expected steps from the start."""
    p, P, z0 = rimless
    slopes, mass = slope_nodes(MEAN, 0.02, 7)
    mesh = np.linspace(-1.6, -0.5, 30)[:, None]
    level = build_chain(P, z0, slopes, mass, mesh)
    lam, start = _closed_form_chain(p, -mesh[:, 0], slopes, mass, -z0[0])
    np.testing.assert_allclose(level.lambda_2, lam, rtol=1e-7, atol=0)
    np.testing.assert_allclose(level.mfpt_start, start, rtol=1e-6, atol=0)
    assert 0.5 < lam < 1.0  # a metastable chain, not a trivial one


def test_markov_chain_with_a_mesh_per_slope_node_matches_the_closed_form_chain(rimless):
    """The chain over a different rate grid for each slope node (as `markov_chain` builds
    it) against the closed-form chain over the same grids."""
    p, P, z0 = rimless
    slopes, mass = slope_nodes(MEAN, 0.02, 6)
    rng = np.random.default_rng(5)
    meshes = [
        np.linspace(-1.7 + 0.1 * rng.random(), -0.6 - 0.1 * rng.random(), 12 + k)[:, None]
        for k in range(slopes.size)
    ]
    level = build_chain(P, z0, slopes, mass, meshes)
    lam, start = _closed_form_chain(p, [-mesh[:, 0] for mesh in meshes], slopes, mass, -z0[0])
    np.testing.assert_allclose(level.lambda_2, lam, rtol=1e-7, atol=0)
    np.testing.assert_allclose(level.mfpt_start, start, rtol=1e-6, atol=0)
    assert 0.5 < lam < 1.0


def _agrees(mc, mk):
    """The refined chain's expected steps from the start against the Monte Carlo: within 3
    standard errors plus the chain's last refinement change; and the metastable rate: past
    the start transient the survival decays like lambda_2^k, so the runs alive at step 10
    fail at the per-step rate 1 - lambda_2 (1 / (1 - lambda_2) steps)."""
    assert mk["converged"] and mk["change"] < 0.02
    allowed = 3.0 * mc.mfpt_stderr + 2.0 * mk["change"] * mk["mfpt_start"]
    assert abs(mk["mfpt_start"] - mc.mfpt) < allowed
    alive = mc.steps[mc.steps >= 10] - 10
    tail_mean = (alive.sum() + alive.size) / alive.size  # steps to failure, failing one too
    stderr = tail_mean / math.sqrt(alive.size)
    assert abs(tail_mean - mk["mfpt"]) < 3.0 * stderr + 2.0 * mk["change"] * mk["mfpt"]


@pytest.mark.slow
@pytest.mark.parametrize("std", [0.01, 0.02])
def test_markov_mfpt_agrees_with_monte_carlo(rimless, std):
    """The rimless wheel's refined chain against 4000 Monte-Carlo runs (standard error about
    1.3 %)."""
    _, P, z0 = rimless
    mc = monte_carlo(P, z0, slope_std=std, runs=4000, seed=3, jobs=2)
    _agrees(mc, markov_chain(P, z0, slope_std=std, jobs=2, samples=30))


@pytest.mark.slow
def test_compass_markov_mfpt_agrees_with_monte_carlo():
    """The compass gait's refined chain (a 3-D section: one nearest-point mesh per slope
    node) against 4000 Monte-Carlo runs (standard error about 1.3 %).  On one mesh shared by
    all slope nodes it came out 5-20 % low (results/bench/markov_mfpt.md has the table)."""
    scene = load_scene("gaits/compass_goswami.toml")
    P, z0 = gait_on_mean_slope(StrideMap.from_scene(scene), scene.state, scene.params.slope)
    std = 0.006
    mc = monte_carlo(P, z0, slope_std=std, runs=4000, seed=3, jobs=2)
    _agrees(mc, markov_chain(P, z0, slope_std=std, jobs=2))


def test_input_errors_name_the_argument(rimless):
    _, P, z0 = rimless
    with pytest.raises(ValueError, match="runs"):
        monte_carlo(P, z0, slope_std=0.01, runs=0, seed=1)
    with pytest.raises(ValueError, match="slope_std"):
        monte_carlo(P, z0, slope_std=-0.01, runs=2, seed=1)
    with pytest.raises(TypeError, match="seed"):
        monte_carlo(P, z0, slope_std=0.01, runs=2, seed=1.5)
    with pytest.raises(ValueError, match="slope_std"):
        markov_chain(P, z0, slope_std=0.0)
