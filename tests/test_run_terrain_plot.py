"""A run on terrain drawn over its actual ground (issue 29): ``walker run --terrain-std ...
--out`` records the rows of the steps it stood on, and ``walker plot`` draws each step's plane
segment under the walker, in the static figure and in the animation.  The check is on the
numbers: every drawn segment starts ``drop`` below the stance contact and ends at the
simulated touchdown point, which lies on the plane of slope ``slope`` of that step's row
(the run's guard, seen through the world-frame drawing)."""

import math

import numpy as np
import pytest

from walker import plotting
from walker.cli import main
from walker.plotting.gallery import plot_file
from walker.plotting.runs import animate_walker
from walker.simulation.terrain import Terrain
from walker.storage import read

COMPASS = "gaits/compass_goswami.toml"
STD, HEIGHT_STD, SEED = 0.003, 0.002, 2


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("run") / "run.h5"
    argv = ["run", COMPASS, "--strides", "15", "--terrain-std", str(STD)]
    argv += ["--terrain-height-std", str(HEIGHT_STD), "--seed", str(SEED), "--out", str(path)]
    main(argv)  # exit 1: this draw of the terrain makes the compass gait fall
    return path


def _segments(ax):
    """The drawn ground: the segments of the one collection labelled ``_ground``."""
    (ground,) = [c for c in ax.collections if c.get_label() == "_ground"]
    return np.array(ground.get_segments())


def test_the_run_records_the_rows_of_its_steps(run_file):
    sol, prov = read(run_file)
    rows = np.asarray(prov["terrain_rows"])
    slope = prov["parameters"]["slope"]["value"]  # [rad]
    terrain = Terrain("random", slope_mean=slope, slope_std=STD, height_std=HEIGHT_STD, seed=SEED)
    assert rows.shape == (sol.n_strides + 1, 2)
    np.testing.assert_array_equal(rows, terrain.steps(15)[: sol.n_strides + 1])


def test_the_drawn_ground_is_the_terrain_rows_planes(run_file, tmp_path, monkeypatch):
    sol, prov = read(run_file)
    rows = np.asarray(prov["terrain_rows"])
    captured = {}

    def fake_animate(frames, segments, **kwargs):  # the GIF itself is not encoded here
        captured.update(kwargs, frames=frames, segments=segments)

    monkeypatch.setattr(plotting, "animate_walker", fake_animate)
    paths = plot_file(run_file, tmp_path, gif=True)
    assert tmp_path / "run_terrain.png" in paths
    ground = np.asarray(captured["ground"])
    assert ground.shape == (sol.n_strides + 1, 2, 2) and sol.n_strides >= 3
    contact = np.zeros(2)  # the first stance contact: the world frame's origin
    for n, ((slope, drop), (start, end)) in enumerate(zip(rows, ground, strict=True)):
        np.testing.assert_allclose(start, contact - [0.0, drop], rtol=0, atol=1e-12)
        # the end is the touchdown point: on the plane of this step's row
        rise = end[1] - start[1]
        np.testing.assert_allclose(rise, -math.tan(slope) * (end[0] - start[0]), rtol=0, atol=1e-9)
        if n < sol.n_strides:
            assert end[0] - start[0] > 0.1  # a real step forward, not a degenerate segment
        contact = end
    # the animation draws exactly these segments
    anim = animate_walker(captured["frames"], captured["segments"], ground=ground)
    anim._draw_was_started = True  # only its lines are read: matplotlib need not warn
    np.testing.assert_array_equal(_segments(anim._fig.axes[0]), ground)


def test_ground_must_be_segments():
    frames = np.zeros((2, 3, 2))
    with pytest.raises(ValueError, match="`ground` must have shape"):
        animate_walker(frames, [(0, 1)], ground=np.zeros((3, 2)))
