"""Basin maps on a toy map whose basin and fall outcomes are known in closed form.

``CubicBasinMap``: w = z - c maps to w |w|^2, so the distance r to the centre c becomes
r^(3^k) after k strides along a fixed ray.  Inside the unit ball every point converges; outside
it the walker falls at the first stride that would end beyond r = 2, backward when the ray
has a negative first component, forward otherwise.
"""

import concurrent.futures as cf

import numpy as np
import pytest
from _toy_maps import HenonMap, cubic_basin_toy, henon_fixed_points

from walker.analysis.basin import basin_chunk, basin_map
from walker.analysis.fixedpoint import find_fixed_point
from walker.models import MODEL_NAMES
from walker.results import BASIN_CONVERGED, BASIN_UNDECIDED
from walker.status import Status

CENTER = np.array([0.3, -0.2, 0.1])
AXES = (0, 2)
# Offsets from the centre are odd multiples of 0.05, so r^2 = 0.0025 (odd^2 + odd^2) is never
# 1 (a sum of two odd squares is 2 mod 8, 400 is 0 mod 8): |r - 1| >= 0.0075 on the grid.
RANGES = ((CENTER[0] - 1.45, CENTER[0] + 1.45), (CENTER[2] - 1.45, CENTER[2] + 1.45))
N = (30, 30)


@pytest.fixture(scope="module")
def toy():
    return cubic_basin_toy(CENTER)


def expected_outcome(x, y, n_strides, tol):
    """Closed-form outcome and completed strides of one grid point (see module docstring)."""
    w = np.array([x - CENTER[0], y - CENTER[2]])
    r = float(np.hypot(*w))
    m = float(np.max(np.abs(w))) / r  # max-norm of the unit direction
    k = 0
    while True:
        if r ** (3**k) * m <= tol:
            return BASIN_CONVERGED, k
        if k + 1 > n_strides:
            return BASIN_UNDECIDED, k
        if r ** (3 ** (k + 1)) > 2.0:
            return (Status.FELL_BACKWARD if w[0] < 0 else Status.FELL_FORWARD), k
        k += 1


def expected_map(b, n_strides, tol):
    out = np.empty((len(b.y), len(b.x)), dtype=int)
    strides = np.empty_like(out)
    for i, y in enumerate(b.y):
        for j, x in enumerate(b.x):
            out[i, j], strides[i, j] = expected_outcome(x, y, n_strides, tol)
    return out, strides


def _serial_basin(m, fp, n_strides):
    """The toy's basin on the N grid over RANGES, serially, to tol 1e-6."""
    return basin_map(
        m,
        fp,
        axes=AXES,
        ranges=RANGES,
        n=N,
        n_strides=n_strides,
        tol=1e-6,
        executor="serial",
        progress=False,
    )


def test_basin_matches_closed_form(toy):
    m, fp = toy
    b = _serial_basin(m, fp, n_strides=20)
    assert b.outcome.shape == (30, 30) and b.strides.shape == (30, 30)
    assert b.axis_names == ("u", "w") and b.n_strides == 20
    np.testing.assert_allclose(b.x, np.linspace(*RANGES[0], 30), rtol=0, atol=0)
    np.testing.assert_allclose(b.fixed_point, CENTER, rtol=0, atol=1e-15)
    out, strides = expected_map(b, 20, 1e-6)
    np.testing.assert_array_equal(b.outcome, out)
    np.testing.assert_array_equal(b.strides, strides)
    # all three kinds of outcome present; with 20 strides nothing stays undecided
    values = set(np.unique(b.outcome).tolist())
    assert values == {BASIN_CONVERGED, int(Status.FELL_BACKWARD), int(Status.FELL_FORWARD)}
    # the basin is the unit disc around the centre
    xx, yy = np.meshgrid(b.x - CENTER[0], b.y - CENTER[2])
    np.testing.assert_array_equal(b.outcome == BASIN_CONVERGED, xx**2 + yy**2 < 1)


def test_undecided_with_few_strides(toy):
    m, fp = toy
    b = _serial_basin(m, fp, n_strides=2)
    out, strides = expected_map(b, 2, 1e-6)
    np.testing.assert_array_equal(b.outcome, out)
    np.testing.assert_array_equal(b.strides, strides)
    assert np.any(b.outcome == BASIN_UNDECIDED)
    assert np.all(b.strides[b.outcome == BASIN_UNDECIDED] == 2)


def test_start_on_fixed_point_takes_no_stride(toy):
    m, fp = toy
    o, k = basin_chunk(
        m, CENTER, CENTER, AXES, np.array([CENTER[0]]), np.array([CENTER[2]]), 5, 1, 1e-9
    )
    assert o.tolist() == [[BASIN_CONVERGED]] and k.tolist() == [[0]]


def test_executors_agree(toy):
    m, fp = toy
    kwargs = dict(axes=AXES, ranges=RANGES, n=(20, 17), n_strides=20, tol=1e-6, progress=False)
    serial = basin_map(m, fp, executor="serial", **kwargs)
    with cf.ProcessPoolExecutor(max_workers=2) as pool:
        pooled = basin_map(m, fp, executor=pool, chunk_size=3, **kwargs)
    default = basin_map(m, fp, executor=None, **kwargs)
    with cf.ThreadPoolExecutor(max_workers=2) as pool:
        threaded = basin_map(m, fp, executor=pool, chunk_size=1, **kwargs)
    for other in (pooled, default, threaded):
        np.testing.assert_array_equal(other.outcome, serial.outcome)
        np.testing.assert_array_equal(other.strides, serial.strides)
        np.testing.assert_array_equal(other.y, serial.y)


@pytest.mark.slow
def test_dask_executor_agrees(toy):
    distributed = pytest.importorskip("distributed")
    m, fp = toy
    kwargs = dict(axes=AXES, ranges=RANGES, n=(12, 9), n_strides=20, tol=1e-6, progress=False)
    serial = basin_map(m, fp, executor="serial", **kwargs)
    with distributed.Client(
        processes=False, n_workers=1, threads_per_worker=2, dashboard_address=None
    ) as client:
        via_executor = basin_map(m, fp, executor=client.get_executor(), **kwargs)
        via_client = basin_map(m, fp, executor=client, **kwargs)
    np.testing.assert_array_equal(via_executor.outcome, serial.outcome)
    np.testing.assert_array_equal(via_client.strides, serial.strides)


def test_period_two_fixed_point_basin():
    # Hénon 2-cycle at a = 0.8 (stable, b = 0.3): points near one cycle point converge to it
    # under P^2; map falls far away.
    m = HenonMap(0.8, 0.3, fall_radius=10.0)
    z1 = henon_fixed_points(0.8, 0.3)[0]
    p1 = m(z1 + 1e-2, n_strides=500).z  # settle on the 2-cycle
    fp = find_fixed_point(m, p1, period=2)
    assert fp.success and fp.period == 2
    b = basin_map(
        m,
        fp,
        ranges=((fp.section[0] - 1e-2, fp.section[0] + 1e-2), (-20.0, -15.0)),
        n=(3, 2),
        n_strides=40,
        executor="serial",
        progress=False,
    )
    assert np.all(b.outcome[:, :] == int(Status.FELL_FORWARD))  # |y| > 10 falls at once
    b = basin_map(
        m,
        fp,
        ranges=(
            (fp.section[0] - 1e-2, fp.section[0] + 1e-2),
            (fp.section[1] - 1e-2, fp.section[1] + 1e-2),
        ),
        n=(3, 3),
        n_strides=200,
        tol=1e-8,
        executor="serial",
        progress=False,
    )
    assert np.all(b.outcome == BASIN_CONVERGED)
    assert np.all(b.strides % 2 == 0)  # whole periods


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"axes": (0, 0)}, r"`axes` must be two distinct indices"),
        ({"axes": (0, 3)}, r"`axes` must be two distinct indices"),
        ({"ranges": ((1.0, 0.0), (0.0, 1.0))}, r"`ranges` must be finite with lo < hi"),
        ({"ranges": (1.0, 2.0)}, r"`ranges` must be \(\(x_lo, x_hi\), \(y_lo, y_hi\)\)"),
        ({"n": (1, 5)}, r"`n` must be at least \(2, 2\)"),
        ({"n_strides": 0}, r"`n_strides` must be an integer >= 1"),
        ({"tol": -1.0}, r"`tol` must be positive"),
        ({"chunk_size": 0}, r"`chunk_size` must be an integer >= 1"),
        ({"executor": "threads"}, r"`executor` must be an Executor, 'serial' or None"),
        ({"executor": 3}, r"`executor` must be a concurrent.futures.Executor"),
    ],
)
def test_basin_validation(toy, kwargs, match):
    m, fp = toy
    args = {"ranges": RANGES, "n": (3, 3), "executor": "serial", "progress": False} | kwargs
    with pytest.raises(ValueError, match=match):
        basin_map(m, fp, **args)


def test_basin_rejects_failed_fixed_point(toy):
    m, _ = toy
    from _toy_maps import ShiftMap

    bad = find_fixed_point(ShiftMap(wiggle=0.1), np.array([0.0]))
    with pytest.raises(ValueError, match="`fixed_point` must be a converged FixedPoint"):
        basin_map(m, bad, ranges=RANGES, executor="serial")


# --------------------------------------------------------------- the compiled batch path
_COMPILED_SCENES = {
    "simplest": "gaits/simplest_garcia.toml",  # its lift compiled, not affine
    "compass": "gaits/compass_goswami.toml",
    "kneed": "gaits/kneed_hsu.toml",
    "three_link": "gaits/three_link_grizzle.toml",
}


def _walker_map(path):
    """The scene, and its stride map as ``walker basin`` builds it."""
    from walker import load_scene
    from walker.cli._common import _stride_map

    scene = load_scene(path)
    return scene, _stride_map(scene)


class _PythonLoop:
    """The same map without ``basin_batch``: basin_chunk runs its Python loop."""

    def __init__(self, section_map):
        self._map = section_map

    def __call__(self, z, **kwargs):
        return self._map(z, **kwargs)


@pytest.mark.parametrize("model", sorted(_COMPILED_SCENES))
def test_compiled_batch_gives_the_python_loops_outcomes(model):
    # Every outcome kind of a real walker (falls, trips, converged, undecided) on a grid
    # around its gait: the compiled row loop and the Python loop agree point for point.
    scene, P = _walker_map(_COMPILED_SCENES[model])
    fp = find_fixed_point(P, P.project(scene.state))
    assert fp.success
    assert P.basin_batch(1) is not None
    z = fp.section
    x = np.linspace(z[0] - 0.6 * abs(z[0]) - 0.05, z[0] + 0.6 * abs(z[0]) + 0.05, 9)
    y = np.linspace(z[1] - 0.6 * abs(z[1]) - 0.05, z[1] + 0.6 * abs(z[1]) + 0.05, 5)
    compiled = basin_chunk(P, z, z, (0, 1), x, y, 12, 1, 1e-6)
    python = basin_chunk(_PythonLoop(P), z, z, (0, 1), x, y, 12, 1, 1e-6)
    np.testing.assert_array_equal(compiled[0], python[0])
    np.testing.assert_array_equal(compiled[1], python[1])
    assert len(np.unique(python[0])) >= 2  # not a trivially uniform grid


def _declares_affine_lift(name: str) -> bool:
    import importlib

    return getattr(importlib.import_module(f"walker.models.{name}"), "LIFT_AFFINE", False)


@pytest.mark.parametrize("module", [m for m in MODEL_NAMES if _declares_affine_lift(m)])
def test_lift_affine_declarations_hold(module):
    # LIFT_AFFINE promises lift(z) = lift(0) + lift_jacobian(0) z with one term per row,
    # bit for bit (the batch's lift in walker/_core/batch.c relies on it)
    import importlib

    mod = importlib.import_module(f"walker.models.{module}")
    assert mod.LIFT_AFFINE
    from walker.models import get_model

    m = get_model(module)
    rng = np.random.default_rng(3)
    p = rng.uniform(0.05, 2.0, len(m.params_class.names()))  # lift reads only a few
    a = np.asarray(mod.lift_jacobian(np.zeros(m.n_z), p))
    b = np.asarray(mod.lift(np.zeros(m.n_z), p))
    assert np.all(np.count_nonzero(a, axis=1) <= 1)
    for _ in range(50):
        z = rng.normal(0.0, 2.0, m.n_z)
        want = np.asarray(mod.lift(z, p))
        got = np.array(
            [
                (b[r] + a[r] @ z) if b[r] != 0 else (a[r] @ z if a[r].any() else b[r])
                for r in range(m.n_x)
            ]
        )
        np.testing.assert_array_equal(got, want)
        np.testing.assert_array_equal(mod.lift_jacobian(z, p), a)


def test_the_compiled_simplest_lift_is_the_python_lift_bit_for_bit():
    # the simplest walker's lift is not affine: walker/_core/model_simplest.c compiles it
    # and its Jacobian (the seed of the variational equations) with the Python operations
    import walker.models.simplest as simplest
    from walker import _hybrid
    from walker.models import get_model

    m = get_model("simplest")
    lift, lift_jac = m._state_fn("lift"), m._state_fn("lift_jacobian")
    assert lift is not None and lift_jac is not None
    rng = np.random.default_rng(5)
    p = np.array([0.009, 1.0, 1.0, 0.0])
    for _ in range(200):
        z = rng.normal(0.0, 1.5, 2)
        assert _hybrid.call_state_fn(lift, z, p, 4) == simplest.lift(z, p).tolist()
        want = np.asarray(simplest.lift_jacobian(z, p), dtype=np.float64).ravel().tolist()
        assert _hybrid.call_state_fn(lift_jac, z, p, 8) == want
