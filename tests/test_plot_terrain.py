"""Figures of the rough-ground measures (walker/plotting/terrain.py): labels with units, the
numbers drawn, and the geometry of a walk drawn over its terrain (every touchdown on its
step's plane)."""

import math

import matplotlib
import numpy as np

matplotlib.use("Agg")

from walker import StrideMap, load_scene  # noqa: E402
from walker.analysis.mfpt import gait_on_mean_slope, monte_carlo  # noqa: E402
from walker.plotting.terrain import (  # noqa: E402
    plot_gsn_sweep,
    plot_mfpt_roughness,
    plot_survival,
    plot_walk_on_terrain,
    walk_over_terrain,
)
from walker.simulation.terrain import Terrain  # noqa: E402


def _compass():
    scene = load_scene("gaits/compass_goswami.toml")
    P = StrideMap.from_scene(scene).with_tolerance(1e-10, 1e-10)
    return (scene, *gait_on_mean_slope(P, scene.state, scene.params.slope))


def test_survival_curve_draws_the_runs_fraction_on_a_log_axis():
    _, P, z0 = _compass()
    r = monte_carlo(P, z0, slope_std=0.006, runs=80, seed=2)
    ax = plot_survival(r).axes[0]
    assert ax.get_yscale() == "log"
    assert "[1]" in ax.get_xlabel() and "[1]" in ax.get_ylabel()
    x, y = ax.lines[0].get_data()
    expected = np.array([np.mean(r.steps >= k) for k in range(int(r.steps.max()) + 1)])
    np.testing.assert_allclose(y, expected, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(x, np.arange(expected.size))


def test_mfpt_roughness_and_gsn_sweep_labels():
    curves = {"compass": {"std": [0.004, 0.006], "mfpt": [60.0, 20.0], "stderr": [4.0, 1.0]}}
    ax = plot_mfpt_roughness(curves).axes[0]
    assert ax.get_yscale() == "log"
    assert ax.get_xlabel() == "slope standard deviation [rad]"
    assert ax.get_ylabel() == "mean first-passage time [steps]"
    ax = plot_gsn_sweep([0.01, 0.02], [10.0, 12.0], "slope", "rad").axes[0]
    assert ax.get_xlabel() == "slope [rad]" and "gait sensitivity norm" in ax.get_ylabel()


def test_a_walk_touches_down_on_each_steps_plane():
    """Contact n + 1 lies on the plane of step n: slope gamma_n through the point h_n below
    contact n (y = y_n - h_n - tan(gamma_n) (x - x_n)), to 1e-9 m; and the figure shows the
    contacts."""
    scene, P, z0 = _compass()
    rows = Terrain(
        "random", slope_mean=scene.params.slope, slope_std=0.004, height_std=0.002, seed=5
    ).steps(6)
    contacts, figures, done = walk_over_terrain(P, z0, rows)
    assert done >= 3 and len(figures) == done
    for n in range(done):
        (x0, y0), (x1, y1) = contacts[n], contacts[n + 1]
        slope, drop = rows[n]
        assert abs(y1 - (y0 - drop - math.tan(slope) * (x1 - x0))) < 1e-9
        assert x1 > x0
    ax = plot_walk_on_terrain(P, z0, rows).axes[0]
    assert ax.get_xlabel() == "x [m]" and ax.get_ylabel() == "y [m]"
    dots = ax.lines[-1].get_data()
    np.testing.assert_allclose(np.column_stack(dots), contacts, rtol=0, atol=1e-15)
