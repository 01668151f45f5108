"""The sanitizer tier's own tests (issue 33, item 1): run by ``scripts/sanitize_tests.sh``
against walker's compiled core built with AddressSanitizer and UndefinedBehaviorSanitizer,
where any read or write outside a buffer, use after free or undefined arithmetic ends the
process with a report.  Skipped elsewhere (marker ``sanitize``).

* A hypothesis-driven fuzz of the binding's arguments: wrong lengths, shapes and dtypes,
  integers far outside int64, non-finite numbers, addresses of the wrong function.  Every
  call either answers with arrays of the sizes the model defines or raises TypeError,
  ValueError or OverflowError naming an argument; the sanitizer checks that nothing in
  between touched memory it should not have.
* Basins computed on two threads at once (the compiled batch without the GIL) equal the
  same points computed one after the other.
"""

from __future__ import annotations

import concurrent.futures as cf
import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from walker import _hybrid, load_scene
from walker.simulation._section import section_args
from walker.simulation.stride import StrideMap

pytestmark = [
    pytest.mark.sanitize,
    pytest.mark.skipif(
        os.environ.get("WALKER_SANITIZER_TIER") != "1",
        reason="the sanitizer tier: scripts/sanitize_tests.sh",
    ),
]

GAITS = Path(__file__).resolve().parents[1] / "gaits"
MODELS = _hybrid.models()
ENTRIES = sorted(MODELS)
STATE_FNS = ("energy", "points", "start_phase", "lift", "lift_jacobian")
REFUSED = (TypeError, ValueError, OverflowError)
FUZZ = settings(max_examples=150, deadline=None, suppress_health_check=list(HealthCheck))

huge_ints = st.sampled_from([-(2**70), -(2**63), -1, 0, 1, 2**31, 2**62, 2**63 - 1, 2**64, 2**70])
lengths = st.integers(min_value=0, max_value=60)
dtypes = st.sampled_from([np.float64, np.float32, np.int64, np.int32, np.complex128])


def _array(length, dtype):
    return np.ones(length, dtype=dtype)


@FUZZ
@given(
    entry=st.sampled_from(ENTRIES),
    role=st.sampled_from(STATE_FNS + ("rhs", "guards")),
    x_len=lengths,
    p_len=lengths,
    n_out=st.one_of(st.integers(-3, 200), huge_ints),
    dtype=dtypes,
)
def test_fuzz_call_state_fn(entry, role, x_len, p_len, n_out, dtype):
    address = MODELS[entry][role]
    if not address:
        return
    try:
        out = _hybrid.call_state_fn(address, _array(x_len, dtype), _array(p_len, dtype), n_out)
    except REFUSED:
        return
    assert len(out) == n_out


def _compass_section():
    scene = load_scene(GAITS / "compass_goswami.toml")
    P = StrideMap.from_scene(scene)
    run, _, _ = P._prepared(1)
    return P, run, section_args(P.model, P.t_max, P.__dict__["_run"], run)


P_COMPASS, RUN, SECTION = _compass_section()
Z0 = P_COMPASS.project(load_scene(GAITS / "compass_goswami.toml").state)
BASIN_RULE = {"target": Z0, "tol": 1e-8, "n_strides": 2, "weight": np.eye(Z0.size), "radius": 0.0}

# values of a wrong type for any argument: each is refused with a TypeError naming it (or,
# for an int where a float goes, taken as the number)
WRONG_TYPES = st.sampled_from(["f", None, [1.0, 2.0], 1.5, True, np.float32(1.0), b"\x00" * 8])
ADDRESSES = st.sampled_from(
    [
        MODELS[e][k]
        for e in ("kneed", "five_link", "simplest")
        for k in ("rhs", "jac", "energy", "lift")
    ]
)

# which section argument, and what to put there
SECTION_MUTATIONS = st.one_of(
    st.tuples(
        st.sampled_from(["n_x", "n_guards", "n_impulse", "max_steps", "n_interior", "n_q"]),
        huge_ints,
    ),
    st.tuples(st.just("p"), st.builds(_array, lengths, dtypes)),
    st.tuples(st.just("lift_a"), st.builds(lambda r, c: np.ones((r, c)), lengths, lengths)),
    st.tuples(st.just("lift_b"), st.builds(_array, lengths, dtypes)),
    st.tuples(
        st.just("proj"),
        st.builds(
            lambda n, v: np.full(n, v, np.int64),
            lengths,
            huge_ints.filter(lambda v: -(2**63) <= v < 2**63),
        ),
    ),
    st.tuples(
        st.just("directions"), st.builds(lambda r, c: np.zeros((r, c), np.int64), lengths, lengths)
    ),
    st.tuples(
        st.sampled_from(
            ["rhs", "guards", "reset", "jac", "energy", "start_phase", "lift", "lift_jacobian"]
        ),
        ADDRESSES,
    ),
    st.tuples(
        st.sampled_from(
            [
                "rtol",
                "atol",
                "first_step",
                "max_step",
                "offset",
                "fall_angle",
                "wound",
                "kinetic_limit",
                "t_max",
            ]
        ),
        st.sampled_from([float("nan"), float("inf"), -1.0, 0.0, 1e308, 5e-324]),
    ),
    st.tuples(st.sampled_from(_hybrid.SECTION_FIELDS), WRONG_TYPES),
)


def _refused_naming_it(call, name=None):
    """call() answers, or raises TypeError/ValueError/OverflowError (naming ``name``, when
    given, in backquotes or quotes); returns the answer or None."""
    try:
        return call()
    except REFUSED as e:
        if name is not None:
            assert f"`{name}" in str(e) or f"'{name}'" in str(e), (name, str(e))
        return None


@FUZZ
@given(
    mutations=st.lists(SECTION_MUTATIONS, min_size=1, max_size=3),
    period=st.one_of(st.integers(1, 3), st.sampled_from([-(2**70), -1, 0, 2**62, 2**64])),
)
def test_fuzz_prepared_map_and_basin_points(mutations, period):
    args = dict(SECTION)
    for name, value in mutations:
        args[name] = value
    prepared = _refused_naming_it(lambda: _hybrid.PreparedMap(**args))
    if prepared is not None:
        out = _refused_naming_it(lambda: prepared.map(np.ascontiguousarray(Z0), period, False))
        if out is not None:
            assert len(out) == 5
    z = np.ascontiguousarray(np.repeat(Z0[None, :], 2, axis=0))
    answer = _refused_naming_it(
        lambda: _hybrid.basin_points(**args, **BASIN_RULE, z0=z, period=period)
    )
    if answer is not None:
        outcome, strides = answer
        assert len(outcome) == len(strides) == 2 * 8


@FUZZ
@given(name=st.sampled_from(_hybrid.SECTION_FIELDS), value=WRONG_TYPES)
def test_fuzz_section_argument_of_a_wrong_type(name, value):
    """One section argument of a wrong type: refused, naming it, or (a number where a number
    goes, a bool where an int or bool goes) answered."""
    args = {**SECTION, name: value}
    _refused_naming_it(lambda: _hybrid.PreparedMap(**args), name)


def test_prepared_solve_keeps_its_settings_alive():
    """PreparedSolve holds the objects it was given: the arrays outlive the caller's names."""
    args = {**RUN._head, **RUN._settings, **SOLVE_START, "n_strides": 1}
    args["directions"] = np.array(args["directions"])  # a copy only the PreparedSolve holds
    run = _hybrid.PreparedSolve(**args).run
    del args
    x0 = np.ascontiguousarray(P_COMPASS.lift(Z0))
    for _ in range(3):
        assert run(x0=x0, p=SECTION["p"]).status == 0


def test_keywords_missing_unknown_or_positional_are_refused():
    z = np.ascontiguousarray(Z0[None, :])
    for name in _hybrid.SECTION_FIELDS:
        short = {k: v for k, v in SECTION.items() if k != name}
        with pytest.raises(TypeError, match=f"missing required keyword argument `{name}`"):
            _hybrid.PreparedMap(**short)
        with pytest.raises(TypeError, match=f"missing required keyword argument `{name}`"):
            _hybrid.basin_points(**short, **BASIN_RULE, z0=z, period=1)
    with pytest.raises(TypeError, match="unexpected keyword argument 'n_p'"):
        _hybrid.PreparedMap(**SECTION, n_p=10)
    with pytest.raises(TypeError, match="keyword arguments only, got 1 positional"):
        _hybrid.PreparedMap(SECTION["rhs"], **{k: v for k, v in SECTION.items() if k != "rhs"})


SOLVE_START = {"phase0": 0, "t0": 0.0, "t_max": 2.0, "output": 1, "want_jac": False}
SOLVER = {k: v for k, v in RUN._settings.items() if k != "max_steps"}


@FUZZ
@given(
    x_len=lengths,
    p_len=lengths,
    sizes=st.tuples(huge_ints, huge_ints, huge_ints),
    max_steps=st.one_of(st.integers(1, 50), huge_ints),
    n_strides=st.one_of(st.integers(0, 3), huge_ints),
    dtype=dtypes,
    wrong=st.one_of(st.none(), st.tuples(st.sampled_from(_hybrid.SOLVE_FIELDS), WRONG_TYPES)),
)
def test_fuzz_solve(x_len, p_len, sizes, max_steps, n_strides, dtype, wrong):
    head = dict(RUN._head)
    if sizes[0] not in (0, 1):  # keep some calls with the model's own sizes
        head.update(n_x=sizes[0], n_guards=sizes[1], n_impulse=sizes[2])
    args = {
        **head,
        **SOLVER,
        **SOLVE_START,
        "x0": _array(x_len, dtype),
        "p": _array(p_len, dtype),
        "n_strides": n_strides,
        "max_steps": max_steps,
    }
    if wrong is not None:
        args[wrong[0]] = wrong[1]
    call = _hybrid.terrain_solve if "terrain" in args else _hybrid.solve
    r = _refused_naming_it(lambda: call(**args))
    if r is not None:
        assert len(r.x) == 8 * head["n_x"]


@FUZZ
@given(name=st.sampled_from(_hybrid.SOLVE_FIELDS), value=WRONG_TYPES)
def test_fuzz_solve_argument_of_a_wrong_type(name, value):
    """One argument of a valid compass run of a wrong type: refused, naming it, or (a number
    where a number goes, a bool where an int or bool goes) answered."""
    args = {**RUN._head, **RUN._settings, **SOLVE_START, "n_strides": 1}
    args.update(x0=np.ascontiguousarray(P_COMPASS.lift(Z0)), p=SECTION["p"], output=0)
    args[name] = value
    call = _hybrid.terrain_solve if name == "terrain" else _hybrid.solve
    r = _refused_naming_it(lambda: call(**args), name)
    if r is not None:
        assert len(r.x) == 8 * 4
    if name != "terrain":  # the same, bound once (walker.simulation.integrate.PreparedRun's way)
        start = {"x0": args.pop("x0"), "p": args.pop("p")}
        run = _hybrid.PreparedSolve(**args).run
        r = _refused_naming_it(lambda: run(**start), name)
        if r is not None:
            assert len(r.x) == 8 * 4


def test_basins_on_two_threads_equal_the_serial_ones():
    args = SECTION
    rng = np.random.default_rng(33)
    z = Z0 + rng.normal(scale=0.05, size=(24, Z0.shape[0]))
    chunks = [np.ascontiguousarray(z[i::4]) for i in range(4)]

    def batch(chunk):
        rule = {**BASIN_RULE, "tol": 1e-6, "n_strides": 8, "period": 1}
        outcome, strides = _hybrid.basin_points(**args, **rule, z0=chunk)
        return np.frombuffer(outcome, np.int64), np.frombuffer(strides, np.int64)

    serial = [batch(chunk) for chunk in chunks]
    with cf.ThreadPoolExecutor(2) as pool:
        threaded = list(pool.map(batch, chunks))
    for (o1, s1), (o2, s2) in zip(serial, threaded, strict=True):
        np.testing.assert_array_equal(o1, o2)
        np.testing.assert_array_equal(s1, s2)
