"""PreparedRun (settings checked once) and the stride map built on it."""

import pickle

import numpy as np
import pytest

from walker import load_scene
from walker.models import get_model
from walker.simulation.integrate import PreparedRun, hybrid_solve
from walker.simulation.stride import StrideMap
from walker.status import Status


@pytest.fixture(scope="module")
def kneed():
    scene = load_scene("gaits/kneed_hsu.toml")
    return scene, np.asarray(scene.reference["state"], dtype=float)


def test_prepared_run_equals_hybrid_solve_bit_for_bit(kneed):
    scene, x0 = kneed
    model = get_model("kneed")
    p = scene.params.as_array()
    system = model.system_for(p)
    run = PreparedRun(system, rtol=1e-11, atol=1e-11)
    status, t, x, jac = run.map(x0.copy(), p, 0, 5.0, 1, True)
    sol = hybrid_solve(system, x0, p, t_max=5.0, rtol=1e-11, atol=1e-11, jacobian=True)
    assert status == sol.status == Status.COMPLETED
    assert t == sol.t
    assert np.array_equal(x, sol.x)
    assert np.array_equal(jac, sol.jac)


def test_prepared_run_negative_start_phase_is_a_status_not_a_run(kneed):
    scene, x0 = kneed
    run = PreparedRun(get_model("kneed").system)
    status, t, x, jac = run.map(x0.copy(), scene.params.as_array(), -1, 5.0, 1, False)
    assert status == Status.LINEAR_SOLVE_FAILED
    assert t == 0.0 and np.array_equal(x, x0) and jac is None


def test_prepared_run_checks_settings_once_and_refuses_pickling():
    system = get_model("compass").system
    with pytest.raises(ValueError, match="rtol"):
        PreparedRun(system, rtol=1e-20)
    with pytest.raises(TypeError, match="system"):
        PreparedRun("compass")
    with pytest.raises(TypeError, match="process-local"):
        pickle.dumps(PreparedRun(system))


def test_stride_map_picks_the_plain_variant_and_survives_pickling(kneed):
    scene, x0 = kneed
    P = StrideMap("kneed", scene.params, rtol=1e-11, atol=1e-11)
    z = P.project(x0)
    r1 = P(z, jacobian=True)
    assert P._prepared()[0].system.name == "kneed/plain"
    Q = pickle.loads(pickle.dumps(P))
    r2 = Q(z, jacobian=True)
    assert np.array_equal(r1.z, r2.z) and np.array_equal(r1.jac, r2.jac)
    # a nonzero foot radius needs the general kernels
    R = P.with_params(foot_radius=1e-3)
    assert R._prepared()[0].system.name == "kneed"
    assert R(z).status == Status.COMPLETED
