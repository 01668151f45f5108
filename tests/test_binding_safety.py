"""Memory safety at the C boundary (issue 33, item 1): every buffer the binding
``walker._hybrid`` hands to compiled code has the length that code reads or writes, and every
size it derives from a caller's number is bounded.

F1-F4 are the probe's reproductions.  On the code before this work each of them reads or
writes past a heap buffer; built with AddressSanitizer (``scripts/sanitize_tests.sh``, which
runs this file) each was reported as a heap-buffer-overflow (F1 in newton.c, F2 in
model_compass.c's points, F3 in the generated compass kinetic energy).  Now each is refused
with a ValueError naming the argument, before any compiled code runs, so under the
sanitizer the file passes without a report.

The sizes the binding checks against (``models()[name]["n_x"]`` ...) are compared with the
Python model's own description (walker.models, walker.params), which is written separately.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import walker.analysis.newton as newton
from walker import _hybrid, load_scene
from walker._checks import MAX_BUDGET
from walker.analysis.fixedpoint import find_fixed_point
from walker.models import get_model
from walker.simulation._section import section_args
from walker.simulation.region import WalkingRegion
from walker.simulation.stride import StrideMap

GAITS = Path(__file__).resolve().parents[1] / "gaits"


def _compass():
    scene = load_scene(GAITS / "compass_goswami.toml")
    P = StrideMap.from_scene(scene)
    return scene, P, P.project(scene.state)


def _prepared(P):
    """The stride map's prepared run and cache (what StrideMap builds for its compiled call)."""
    run, _, _ = P._prepared(1)
    return run, P.__dict__["_run"]


# ------------------------------------------------------------------ the sizes reported


@pytest.mark.parametrize("entry", sorted(_hybrid.models()))
def test_every_compiled_model_reports_the_sizes_of_its_python_model(entry):
    sizes = _hybrid.models()[entry]
    model = get_model(entry.partition("/")[0])
    system = model.system
    assert sizes["n_x"] == model.n_x == system.n_x
    assert sizes["n_p"] == len(model.params_class.names())
    assert sizes["n_phases"] == system.n_phases
    assert sizes["n_guards"] == system.n_guards
    assert sizes["n_impulse"] == system.n_impulse
    assert sizes["n_points"] == 1 + max(max(segment) for segment in model.segments)
    assert sizes["n_z"] == model.n_z


# ------------------------------------------------------------------ F1: the search's budgets


def test_f1_huge_search_budgets_are_refused_in_python():
    _, P, z0 = _compass()
    huge = 2**61 - 2
    with pytest.raises(ValueError, match=r"`max_iter` must be an integer >= 1 and <= 10000000"):
        find_fixed_point(P, z0, max_iter=huge, max_evals=huge)
    with pytest.raises(ValueError, match=r"`max_evals` must be None or an integer >= 1 and <="):
        find_fixed_point(P, z0, max_evals=huge)
    with pytest.raises(ValueError, match=r"`period` must be an integer >= 1 and <="):
        find_fixed_point(P, z0, period=MAX_BUDGET + 1)


def test_f1_huge_search_budgets_are_refused_by_the_binding():
    """Past the Python checks: the search's binding bounds its history's size itself, on
    the compiled map and through callbacks."""
    _, P, z0 = _compass()
    search = type(P)._compiled_search(P)
    region = WalkingRegion.of(P, None)
    region.with_guess(z0)
    for max_iter, max_evals in ((2**61 - 2, 2**61 - 2), (2**61 - 2, 60), (50, 2**61 - 2)):
        ev = newton._Search(P, 1, None, max_evals, 1e-12, "exact", None, True)
        settings = ev.settings(max_iter, True, 3)
        with pytest.raises(
            ValueError, match=r"search\(\): `max_(iter|evals)` must be in \[1, 10000000\]"
        ):
            search(z0=z0, scale=region.scale, **region.compiled(), **settings)
        with pytest.raises(
            ValueError, match=r"search\(\): `max_(iter|evals)` must be in \[1, 10000000\]"
        ):
            _hybrid.search(
                z0=z0,
                scale=region.scale,
                evaluate=ev.evaluate,
                jacobian=ev.jacobian,
                outside=None,
                **settings,
            )
    # the same call within the bounds finds the gait
    ev = newton._Search(P, 1, None, 60, 1e-12, "exact", None, True)
    out = search(z0=z0, scale=region.scale, **region.compiled(), **ev.settings(50, True, 3))
    assert out is not None and out[0] == 0  # converged


# ------------------------------------------------------------------ F2, F3: call_state_fn


def test_f2_points_output_is_sized_by_the_binding():
    scene, _, _ = _compass()
    entry = _hybrid.models()["compass"]
    x = np.ascontiguousarray(scene.state, dtype=np.float64)
    p = scene.params.as_array()
    # n_out = 1 asks for a prefix; the compiled function still writes its 6 values
    first = _hybrid.call_state_fn(entry["points"], x, p, 1)
    whole = _hybrid.call_state_fn(entry["points"], x, p, 2 * entry["n_points"])
    assert len(first) == 1 and first[0] == whole[0]
    # the stance foot is at the origin, the hip one leg length (1 m) away from it
    np.testing.assert_allclose(whole[:2], [0.0, 0.0], rtol=0, atol=1e-15)
    np.testing.assert_allclose(np.hypot(whole[2], whole[3]), 1.0, rtol=1e-14, atol=0)
    with pytest.raises(ValueError, match=r"`n_out` must be in \[0, 6\]"):
        _hybrid.call_state_fn(entry["points"], x, p, 7)


@pytest.mark.parametrize(
    ("x_len", "p_len", "message"),
    [
        (1, 10, r"`x` must have length 4"),
        (4, 1, r"`p` must have length at least n_p = 10"),
        (40, 10, r"`x` must have length 4"),
        (4, 0, r"`p` must have length at least n_p = 10"),
    ],
)
def test_f3_state_function_lengths_are_checked(x_len, p_len, message):
    entry = _hybrid.models()["compass"]
    with pytest.raises(ValueError, match=message):
        _hybrid.call_state_fn(entry["energy"], np.zeros(x_len), np.ones(p_len), 2)


def test_call_state_fn_takes_only_compiled_state_functions():
    entry = _hybrid.models()["compass"]
    for address in (entry["rhs"], 12345):
        with pytest.raises(ValueError, match=r"`address` must be the energy, points"):
            _hybrid.call_state_fn(address, np.zeros(4), np.ones(10), 1)
    lift = _hybrid.models()["simplest"]["lift"]
    p = load_scene(GAITS / "simplest_garcia.toml").params.as_array()
    x = _hybrid.call_state_fn(lift, np.array([0.2, -0.2]), p, 4)  # z has n_z = 2 values
    assert len(x) == 4
    with pytest.raises(ValueError, match=r"`x` must have length 2"):
        _hybrid.call_state_fn(lift, np.zeros(4), p, 4)


# ------------------------------------------------------------------ F4: len(p)


def test_f4_solve_checks_the_parameter_count():
    scene, P, _ = _compass()
    run, cached = _prepared(P)
    x0 = np.ascontiguousarray(scene.state, dtype=np.float64)
    start = dict(x0=x0, phase0=0, t0=0.0, t_max=5.0, n_strides=1, output=0, want_jac=False)
    for p in (np.ones(1), np.ones(11)):
        with pytest.raises(ValueError, match=r"`p` must have length n_p = 10 for the compiled"):
            _hybrid.solve(**run._head, **run._settings, **start, p=p)
    r = _hybrid.solve(**run._head, **run._settings, **start, p=cached[1])
    assert r.status == 0


def test_f4_prepared_map_and_basin_points_check_the_parameter_count():
    _, P, z0 = _compass()
    run, cached = _prepared(P)
    args = section_args(P.model, P.t_max, cached, run)
    assert args["p"] is cached[1]
    args["p"] = np.ones(2)
    z = np.ascontiguousarray(z0[None, :])
    rule = dict(z0=z, target=z0, tol=1e-8, n_strides=2, period=1, weight=np.eye(z0.size))
    with pytest.raises(ValueError, match=r"`p` must have length n_p = 10"):
        _hybrid.basin_points(**args, **rule, radius=0.0)
    with pytest.raises(ValueError, match=r"`p` must have length n_p = 10"):
        _hybrid.PreparedMap(**args).map(z0, 1, False)


def test_functions_of_different_models_are_not_mixed():
    _, P, _ = _compass()
    run, cached = _prepared(P)
    args = section_args(P.model, P.t_max, cached, run)
    kneed = _hybrid.models()["kneed"]
    # a 6-state Jacobian for a 4-state system
    with pytest.raises(ValueError, match=r"`n_x` must be 6 for the compiled model 'kneed'"):
        _hybrid.PreparedMap(**{**args, "jac": kneed["jac"]})
    swapped = {**args, "rhs": _hybrid.models()["compass"]["energy"]}
    with pytest.raises(ValueError, match=r"`rhs` is the energy function of the compiled model"):
        _hybrid.PreparedMap(**swapped)
    # n_guards: the model writes 3
    short_guards = {**args, "n_guards": 1, "directions": np.zeros((1, 1), dtype=np.int64)}
    with pytest.raises(ValueError, match=r"`n_guards` must be 3 for the compiled model"):
        _hybrid.PreparedMap(**short_guards)
    with pytest.raises(ValueError, match=r"`energy` belongs to the compiled model 'kneed'"):
        _hybrid.PreparedMap(**{**args, "energy": kneed["energy"]})
