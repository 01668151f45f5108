"""StrideMap.__call__ in one compiled call (issue 12, walker._hybrid.PreparedMap): for a
model whose lift is affine or compiled (the simplest walker's) the lift, the start checks,
the stride(s) and the projection run in C with the operations of the checked Python path
(StrideMap._checked_call), so every result is the same bit for bit: status, section point,
state, step time and Jacobian.
"""

import pickle
import threading
from pathlib import Path

import numpy as np
import pytest

from walker import load_scene
from walker.results import MapResult
from walker.simulation.stride import StrideMap
from walker.status import Status

ROOT = Path(__file__).resolve().parent.parent

# every shipped scene of a model whose lift is declared affine (LIFT_AFFINE) or compiled
COMPILED_SCENES = [
    "gaits/simplest_garcia.toml",  # a lift that is not affine, compiled (model_simplest.c)
    "gaits/kneed_hsu.toml",
    "gaits/compass_goswami.toml",
    "gaits/compass_coulomb_goswami.toml",  # joint friction: the start phase from the state
    "gaits/kneed_coulomb_hsu.toml",
    "gaits/kneed_mcgeer_pointmass.toml",
    "gaits/kneed_mcgeer_roundfoot.toml",  # its start state trips: a failing stride
    "gaits/rimless_wheel.toml",
    "gaits/three_link_grizzle.toml",  # hybrid zero dynamics
    "gaits/three_link_book.toml",
]


def _map_and_start(scene_file):
    scene = load_scene(ROOT / scene_file)
    P = StrideMap.from_scene(scene)
    reference = (scene.reference or {}).get("state")
    x = np.asarray(reference if reference is not None else scene.state, dtype=float)
    return P, P.project(x)


def _starts(P, z_star):
    """The fixed point (or start), perturbations of it, a start past the fall angle on
    either side and one whose rates put it outside the walking region."""
    rng = np.random.default_rng(12)
    starts = [z_star]
    for scale in (1e-6, 1e-3, 3e-2, 0.3):
        starts.append(z_star + scale * rng.standard_normal(z_star.shape))
    for angle in (3.0, -3.0):  # beyond any fall angle (a stance leg lying on the slope)
        z = z_star.copy()
        z[0] = angle
        starts.append(z)
    if P.n_z > 1:
        z = z_star.copy()
        z[1:] = 1e3  # rates far beyond any gait's
        starts.append(z)
    return starts


def _same(new: MapResult, old: MapResult):
    assert type(new) is MapResult
    assert new.status is old.status and type(new.status) is Status
    assert type(new.step_time) is float and new.step_time == old.step_time
    for a, b in ((new.z, old.z), (new.state, old.state)):
        assert type(a) is np.ndarray and a.dtype == np.float64 and a.shape == b.shape
        np.testing.assert_array_equal(a, b)
    if old.jac is None:
        assert new.jac is None
    else:
        assert new.jac.dtype == np.float64 and new.jac.shape == old.jac.shape
        assert new.jac.flags.c_contiguous
        np.testing.assert_array_equal(new.jac, old.jac)


# the three-link walkers' checked paths run their controller through Python: the integration tier
@pytest.mark.parametrize(
    "scene_file",
    [pytest.param(f, marks=pytest.mark.slow) if "three_link" in f else f for f in COMPILED_SCENES],
)
def test_compiled_call_equals_the_checked_path_bit_for_bit(scene_file):
    P, z_star = _map_and_start(scene_file)
    P(z_star)
    call = P.__dict__["_run"][6]  # PreparedMap.map: None would mean the checked path
    statuses = set()
    for z in _starts(P, z_star):
        for n_strides in (1, 2):
            for jacobian in (False, True):
                assert call(z, n_strides, jacobian) is not None  # it answers this call
                new = P(z, jacobian=jacobian, n_strides=n_strides)
                old = P._checked_call(z, jacobian, n_strides)
                _same(new, old)
                statuses.add(new.status)
    # the starts reach completed strides and starts that are not integrated
    assert Status.COMPLETED in statuses or "roundfoot" in scene_file
    assert statuses & {Status.FELL_FORWARD, Status.FELL_BACKWARD}


def test_the_checked_path_serves_models_without_a_compiled_lift():
    P, z = _map_and_start("gaits/five_link_hzd.toml")  # its lift solves for the tibia angle
    r = P(z, jacobian=True)
    assert P.__dict__["_run"][6] is None
    assert P._compiled_search() is None and P.basin_batch() is None
    _same(r, P._checked_call(z, True, 1))


@pytest.mark.parametrize(
    ("z", "n_strides", "jacobian", "error", "match"),
    [
        ([0.1, 0.2], 1, False, ValueError, r"`z` must have shape \(3,\), got \(2,\)"),
        (np.zeros((1, 3)), 1, False, ValueError, r"`z` must have shape \(3,\), got \(1, 3\)"),
        ([0.1, np.nan, 0.0], 1, False, ValueError, "section point `z` must be finite"),
        (np.array([0.1, np.inf, 0.0]), 1, False, ValueError, "`z` must be finite"),
        ("abc", 1, False, TypeError, "`z` must be an array of real numbers"),
        (None, 0, False, ValueError, r"`n_strides` must be >= 1, got 0"),
        (None, 1.0, False, TypeError, "`n_strides` must be an int, got float"),
        (None, True, False, TypeError, "`n_strides` must be an int, got bool"),
        (None, 1, "yes", TypeError, "`jacobian` must be a bool, got str"),
        (None, 1, None, TypeError, "`jacobian` must be a bool, got NoneType"),
    ],
)
def test_input_the_compiled_call_declines_gets_the_checked_errors(
    z, n_strides, jacobian, error, match
):
    P, z_star = _map_and_start("gaits/compass_goswami.toml")
    with pytest.raises(error, match=match):
        P(z_star if z is None else z, n_strides=n_strides, jacobian=jacobian)


def test_plain_input_of_other_kinds_takes_the_checked_path_with_the_same_numbers():
    P, z = _map_and_start("gaits/kneed_hsu.toml")
    ref = P(z, jacobian=True)
    for other, n_strides, jacobian in (
        (list(z), 1, True),  # a list
        (z.tolist(), 1, True),  # a list of floats
        (np.array(z, order="F"), 1, True),  # a copy
        (np.stack([z, z])[:, ::1][0], 1, True),  # a row of a matrix
        (np.repeat(z, 2)[::2], 1, True),  # a strided view: not C-contiguous
        (z, np.int64(1), True),  # a numpy int
        (z, 1, 1),  # an int as a bool
        (z, 1, np.True_),  # numpy's bool
    ):
        _same(P(other, jacobian=jacobian, n_strides=n_strides), ref)


def test_compiled_call_survives_pickling_and_parameter_changes():
    P, z = _map_and_start("gaits/compass_goswami.toml")
    ref = P(z, jacobian=True)
    Q = pickle.loads(pickle.dumps(P))
    assert "_run" not in Q.__dict__
    _same(Q(z, jacobian=True), ref)
    assert Q.__dict__["_run"][6] is not None
    R = P.with_parameter(P.parameter_value * 1.01)
    r = R(z)
    assert R.__dict__["_run"][6] is not None
    _same(r, R._checked_call(z, False, 1))
    assert not np.array_equal(r.z, ref.z)


def test_compiled_calls_from_threads_give_the_same_results():
    P, z_star = _map_and_start("gaits/kneed_hsu.toml")
    starts = _starts(P, z_star)
    expected = [P(z, jacobian=True) for z in starts]
    got = [None] * (2 * len(starts))

    def work(offset):
        for i, z in enumerate(starts):
            got[offset + i] = P(z, jacobian=True)

    threads = [threading.Thread(target=work, args=(k * len(starts),)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for i, r in enumerate(got):
        _same(r, expected[i % len(starts)])
