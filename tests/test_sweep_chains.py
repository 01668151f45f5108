"""Warm starts that follow the grid (walker.analysis.sweep_chains): every point's guess is a
function of the grid only, so a fixed-point sweep's table is the same however the work is cut
(chunk size, jobs, executor, resume); a point on another gait than its neighbours is
flagged in the ``jump`` column; a re-targeted stride map gives the rebuilt map's numbers."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from walker import StrideMap, load_scene
from walker.analysis.sweep import sweep
from walker.analysis.sweep_chains import (
    JUMP_SECTION,
    JUMP_STEP_TIME,
    grid_lines,
    jump_flags,
    level_axes,
    predict,
    walk_line,
)
from walker.simulation.region import WalkingRegion

REPO = Path(__file__).resolve().parents[1]


def _map(scene_name):
    scene = load_scene(REPO / "gaits" / scene_name)
    stride_map = StrideMap.from_scene(scene)
    return stride_map, stride_map.project(scene.state)


def _equal(a, b):
    assert list(a.columns) == list(b.columns)
    for name in a.columns:
        assert np.array_equal(a.columns[name], b.columns[name], equal_nan=True), name


@pytest.mark.parametrize("shape, root", [((5,), (2,)), ((4, 3), (0, 2)), ((3, 2, 4), (1, 1, 0))])
@pytest.mark.parametrize("ordered", [False, True], ids=["axis order", "shortest first"])
def test_grid_lines_visit_every_point_once_from_a_neighbour(shape, root, ordered):
    """Each point is walked exactly once, the root first, and every other point right after
    a grid neighbour done before it (its predecessor on its line); in the axes' order and
    in the sweep's (level_axes: shortest axis first)."""
    axes = level_axes(shape) if ordered else None
    if ordered:
        assert [shape[a] for a in axes] == sorted(shape)
    seen = {}
    order = 0
    for level in grid_lines(shape, root, axes):
        for centre, first, down, up in level:
            if first:
                assert np.unravel_index(centre, shape) == root and not seen
                seen[centre] = order
                order += 1
            else:
                assert centre in seen
            for half in (down, up):
                previous = centre
                for index in half:
                    assert index not in seen
                    a = np.array(np.unravel_index(previous, shape))
                    b = np.array(np.unravel_index(index, shape))
                    assert np.abs(a - b).sum() == 1  # one grid step
                    seen[index] = order
                    order += 1
                    previous = index
    assert sorted(seen) == list(range(int(np.prod(shape))))


def test_jump_flags_mark_both_sides_of_a_jump_and_nothing_else():
    """A 1-D table with one point on another gait (step time 1.8 s among 0.7 s): that point
    and its two neighbours are flagged; a failed point is never flagged."""
    n_z = 2
    step_time = np.array([0.70, 0.71, 1.80, 0.72, 0.73, np.nan, 0.74])
    status = np.array([0, 0, 0, 0, 0, 9, 0])
    section = np.tile([0.2, -1.0], (7, 1))
    section[5] = np.nan
    flags = jump_flags(status, section, step_time, (7,), np.ones(n_z))
    assert flags.tolist() == [0, 1, 1, 1, 0, 0, 0]
    # the section alone: one component moved by more than JUMP_SECTION (scaled) at index 4
    section[4, 1] += 2 * JUMP_SECTION
    step_time[2] = 0.715
    flags = jump_flags(status, section, step_time, (7,), np.ones(n_z))
    assert flags.tolist() == [0, 0, 0, 1, 1, 0, 0]
    # the scale: the same move in a rate with scale 4 is within the threshold
    assert jump_flags(status, section, step_time, (7,), np.array([1.0, 4.0])).sum() == 0


def test_predict_is_exact_on_polynomials_and_refuses_what_it_cannot_use():
    """The extrapolated guess is the Lagrange polynomial through the gaits behind: exact
    (to rounding) for a line (two gaits) and a parabola (three), on unevenly spaced values;
    none from one gait, from repeated values, or beyond JUMP_SECTION of the seed."""
    scale = np.ones(2)

    def line(t):
        return np.array([0.2 + 0.5 * t, -1.0 - 0.25 * t])

    def parabola(t):
        return np.array([0.2 + 0.5 * t - 3.0 * t * t, -1.0 + 2.0 * t * t])

    ts = [0.01, 0.03, 0.04]
    at = 0.07
    guess = predict([(t, line(t)) for t in ts[1:]], at, line(ts[-1]), scale)
    np.testing.assert_allclose(guess, line(at), rtol=0, atol=1e-13)
    guess = predict([(t, parabola(t)) for t in ts], at, parabola(ts[-1]), scale)
    np.testing.assert_allclose(guess, parabola(at), rtol=0, atol=1e-13)
    assert predict([(0.04, line(0.04))], at, line(0.04), scale) is None
    assert predict([(0.04, line(0.03)), (0.04, line(0.04))], at, line(0.04), scale) is None
    far = [(0.0, np.zeros(2)), (0.1, np.full(2, 2 * JUMP_SECTION))]
    assert predict(far, 0.2, far[-1][1], scale) is None


def test_walk_line_predicts_from_converged_gaits_only():
    """Along a line each point is offered the extrapolation of the gaits just before it on
    the line (the centre's seed counts when it is the centre's gait); a point that fails
    passes its seed on unchanged and the next point is offered no extrapolation."""
    offered = {}

    def gait(t):
        return np.array([t, 2.0 * t])

    def solve(index, seed, predicted):
        offered[index] = predicted
        if index == 3:
            return 9, np.full(2, np.nan)
        return 0, gait(float(index))

    centre, down, up = -1, (), (0, 1, 2, 3, 4, 5)
    seeds = walk_line(
        (centre, False, down, up), gait(-1.0), solve, np.full(2, 100.0), float, seed_is_gait=True
    )
    assert offered[0] is None  # one gait behind: the seed itself
    np.testing.assert_allclose(offered[1], gait(1.0), rtol=0, atol=1e-14)
    np.testing.assert_allclose(offered[2], gait(2.0), rtol=0, atol=1e-14)
    np.testing.assert_array_equal(seeds[3], seeds[2])  # the failed point passes its seed on
    assert offered[4] is None  # the line behind was broken at 3
    assert offered[5] is None  # one gait behind again (4): the seed itself
    np.testing.assert_array_equal(seeds[5], gait(5.0))


def test_kneed_sweep_identical_for_any_chunk_size_and_jobs(tmp_path):
    """Issue 33 item 8: the same table for chunk sizes 1, 10, 50 and the default, on threads
    and serially, and resumed from a checkpoint."""
    stride_map, z0 = _map("kneed_hsu.toml")
    ranges = ["slope=0.03:0.07:12", "mass_hip=4:6:3"]
    run = dict(kind="fixed_point", z0=z0, progress=False)
    reference = sweep(stride_map, ranges, executor="serial", **run)
    assert (reference.columns["status"] == 0).sum() >= 30
    assert np.all(reference.columns["jump"] >= 0)
    for chunk in (1, 10, 50):
        _equal(reference, sweep(stride_map, ranges, chunk_size=chunk, executor="serial", **run))
    _equal(reference, sweep(stride_map, ranges, chunk_size=7, jobs=2, **run))
    # a checkpoint with some chunks done (written by a sweep over the same grid), resumed
    out = tmp_path / "resumed.h5"
    sweep(stride_map, ranges, chunk_size=5, jobs=2, out=out, **run)
    _equal(reference, sweep(stride_map, ranges, chunk_size=5, jobs=2, out=out, **run))


def _no_unflagged_jump(table, shape, scale):
    """Independently of jump_flags: every pair of converged grid neighbours that differ by
    more than the thresholds has both points flagged."""
    cols = table.columns
    ok = (cols["status"] == 0).reshape(shape)
    z = cols["section"].reshape((*shape, -1)) / scale
    t = cols["step_time"].reshape(shape)
    flag = cols["jump"].reshape(shape)
    for index in np.ndindex(*shape):
        for axis in range(len(shape)):
            other = list(index)
            other[axis] += 1
            other = tuple(other)
            if other[axis] >= shape[axis] or not (ok[index] and ok[other]):
                continue
            dz = np.max(np.abs(z[index] - z[other]))
            dt = abs(t[index] - t[other]) / min(t[index], t[other])
            if dz > JUMP_SECTION or dt > JUMP_STEP_TIME:
                assert flag[index] == 1 and flag[other] == 1, (index, other)


def _compass_grid(n):
    stride_map, z0 = _map("compass_goswami.toml")
    ranges = [f"slope=0.01:0.15:{n}", f"mass_leg=1:10:{n}"]
    scale = WalkingRegion(stride_map.model, stride_map.params).scale
    warm = sweep(stride_map, ranges, kind="fixed_point", z0=z0, progress=False)
    # each point from the scene's gait (chunks of one point: today's sweep_chunk, no warm
    # start), the comparison for the failures
    from walker.analysis.sweep import sweep_chunk
    from walker.analysis.sweep_grid import grid_points

    names, points = grid_points(ranges)
    cold = np.array(
        [
            sweep_chunk(stride_map, names, points[i : i + 1], "fixed_point", z0, 1, 1e-10)[
                "status"
            ][0]
            for i in range(points.shape[0])
        ]
    )
    return warm, cold, scale


def test_compass_slope_mass_leg_grid_has_no_unflagged_jump():
    warm, cold, scale = _compass_grid(8)
    _no_unflagged_jump(warm, (8, 8), scale)
    assert (warm.columns["status"] != 0).sum() <= (cold != 0).sum()


@pytest.mark.slow
def test_compass_40x40_has_no_unflagged_jump_and_fewer_failures():
    """Issue 30: the 40 x 40 compass sweep (slope x mass_leg) has no unflagged jump and
    fewer failures than points started from the scene's gait."""
    warm, cold, scale = _compass_grid(40)
    _no_unflagged_jump(warm, (40, 40), scale)
    assert (warm.columns["status"] != 0).sum() < (cold != 0).sum()


@pytest.mark.parametrize("scene", ["kneed_mcgeer_pointmass.toml", "compass_goswami.toml"])
def test_map_spec_keeps_the_scenes_conventions(scene):
    """The map a worker process or a dask worker builds from a MapSpec runs under the
    scene's swing-foot convention (McGeer's scenes let the swing foot pass through the
    ground): the same stride, bit for bit, as the map it was made from."""
    from walker.analysis.sweep_chains import MapSpec

    stride_map, z0 = _map(scene)
    built = MapSpec.from_map(stride_map).build()
    assert built.model.conventions == stride_map.model.conventions
    a, b = stride_map(z0), built(z0)
    assert a.status == b.status and np.array_equal(a.z, b.z, equal_nan=True)


@pytest.mark.parametrize("scene", ["compass_goswami.toml", "kneed_hsu.toml"])
def test_retargeted_map_gives_the_rebuilt_maps_numbers(scene):
    """StrideMap._retargeted shares the compiled run instead of rebuilding it; a map built
    from scratch at the same parameters is the reference, bit for bit (value, Jacobian,
    step time, the gait search)."""
    from walker.analysis.fixedpoint import find_fixed_point

    stride_map, z0 = _map(scene)
    stride_map(z0)
    for changes in ({"slope": stride_map.params.slope * 1.05}, {"mass_hip": 7.5}):
        params = stride_map.params.replace(**changes)
        fresh = StrideMap(
            stride_map.model,
            params,
            rtol=stride_map.rtol,
            atol=stride_map.atol,
            t_max=stride_map.t_max,
        )
        moved = stride_map._retargeted(params)
        assert "_run" in moved.__dict__  # re-targeted, not left to be rebuilt
        a, b = fresh(z0, jacobian=True), moved(z0, jacobian=True)
        assert a.status == b.status and a.step_time == b.step_time
        assert np.array_equal(a.z, b.z) and np.array_equal(a.jac, b.jac)
        for tol in (1e-6, 1e-9):  # the gait search's coarse copies are re-targeted too
            ca, cb = fresh.with_tolerance(tol, tol), moved.with_tolerance(tol, tol)
            assert "_run" in cb.__dict__ and cb.rtol == tol
            a, b = ca(z0, jacobian=True), cb(z0, jacobian=True)
            assert np.array_equal(a.z, b.z) and np.array_equal(a.jac, b.jac)
        fa, fb = find_fixed_point(fresh, z0), find_fixed_point(moved, z0)
        assert np.array_equal(fa.section, fb.section)
        assert np.array_equal(fa.multipliers, fb.multipliers)
    # outside the walking region and a fall: the start checks moved with the parameters
    steep = stride_map._retargeted(stride_map.params.replace(slope=0.3))
    fresh = StrideMap(
        stride_map.model,
        stride_map.params.replace(slope=0.3),
        rtol=stride_map.rtol,
        atol=stride_map.atol,
        t_max=stride_map.t_max,
    )
    far = z0 + np.r_[1.0, np.zeros(z0.size - 1)]
    assert steep(far).status == fresh(far).status
