"""Terrain drawn in compiled code (walker/_core/terrain_draw.c): the Monte Carlo's per-run
rows against numpy's own (``numpy.random.default_rng(child).standard_normal``, the children
of ``numpy.random.SeedSequence(seed)``) bit for bit, and the Monte Carlo on them run for run
equal to the one on rows drawn in Python."""

import numpy as np
import pytest

from walker import StrideMap, _hybrid, load_scene
from walker.analysis.mfpt import draw_terrains, gait_on_mean_slope, monte_carlo, run_seeds
from walker.simulation import _terrain_run
from walker.simulation.terrain import Terrain

pytestmark = pytest.mark.skipif(
    _terrain_run.compiled_draws(0, Terrain("random", slope_mean=0.0)) is None,
    reason="this build or numpy cannot draw terrain in compiled code",
)


@pytest.mark.parametrize("seed", [0, 1, 12345, 2**32 - 1, 2**32 + 7, 2**64 - 1, 2**100 + 3])
def test_compiled_draws_are_numpys(seed):
    rng = np.random.default_rng(seed % 1000)
    runs = np.sort(rng.choice(5000, size=40, replace=False)).astype(np.int64)
    for terrain in (
        Terrain("random", slope_mean=0.05, slope_std=0.005),
        Terrain("random", slope_mean=-0.01, slope_std=0.02, height_std=0.003),
        Terrain("random", slope_mean=0.0, height_std=0.01),
    ):
        children = run_seeds(seed, int(runs.max()) + 1)
        want = draw_terrains([children[i] for i in runs], 37, terrain)
        draws = _terrain_run.compiled_draws(seed, terrain)
        got = np.frombuffer(_hybrid.terrain_draws(*draws, runs, 37), dtype=np.float64)
        assert np.array_equal(got.reshape(want.shape), want)


def test_seeds_beyond_128_bits_draw_in_python():
    assert _terrain_run.compiled_draws(2**128, Terrain("random", slope_mean=0.0)) is None


def test_monte_carlo_on_compiled_draws_equals_python_draws(monkeypatch):
    scene = load_scene("gaits/compass_goswami.toml")
    P, z0 = gait_on_mean_slope(StrideMap.from_scene(scene), scene.state, scene.params.slope)
    kw = {"slope_std": 0.005, "height_std": 0.0005, "runs": 60, "seed": 9, "steps": 8}
    a = monte_carlo(P, z0, jobs=2, **kw)
    monkeypatch.setattr(_terrain_run, "compiled_draws", lambda seed, terrain: None)
    b = monte_carlo(P, z0, jobs=1, **kw)
    assert np.array_equal(a.steps, b.steps) and np.array_equal(a.status, b.status)
    assert a.failed > 0 and a.steps.max() > 8  # some runs fell, some outlived the horizon


def test_draw_input_errors_name_the_argument():
    draws = _terrain_run.compiled_draws(1, Terrain("random", slope_mean=0.0, slope_std=0.1))
    runs = np.arange(2, dtype=np.int64)
    with pytest.raises(ValueError, match="entropy"):
        _hybrid.terrain_draws(np.zeros(5, np.int64), *draws[1:], runs, 3)
    with pytest.raises(ValueError, match="runs"):
        _hybrid.terrain_draws(*draws, np.array([-1], np.int64), 3)
    with pytest.raises(ValueError, match="n_steps"):
        _hybrid.terrain_draws(*draws, runs, 0)
    with pytest.raises(ValueError, match="slope_std"):
        _hybrid.terrain_draws(draws[0], draws[1], 0.0, -1.0, 0.0, runs, 3)
