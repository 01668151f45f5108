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
    return P, run, list(section_args(P.model, P.t_max, P.__dict__["_run"], run))


P_COMPASS, RUN, SECTION = _compass_section()
Z0 = P_COMPASS.project(load_scene(GAITS / "compass_goswami.toml").state)

# which section argument, and what to put there
SECTION_MUTATIONS = st.one_of(
    st.tuples(st.sampled_from([6, 7, 8, 16, 17, 23]), huge_ints),  # n_x .. n_q
    st.tuples(st.just(9), st.builds(_array, lengths, dtypes)),  # p
    st.tuples(st.sampled_from([18]), st.builds(lambda r, c: np.ones((r, c)), lengths, lengths)),
    st.tuples(st.sampled_from([19]), st.builds(_array, lengths, dtypes)),  # lift_b
    st.tuples(
        st.just(20),
        st.builds(
            lambda n, v: np.full(n, v, np.int64),
            lengths,
            huge_ints.filter(lambda v: -(2**63) <= v < 2**63),
        ),
    ),  # noqa: E501
    st.tuples(st.just(5), st.builds(lambda r, c: np.zeros((r, c), np.int64), lengths, lengths)),
    st.tuples(
        st.sampled_from([0, 1, 2, 3, 25, 27, 29, 30]),
        st.sampled_from(
            [
                MODELS[e][k]
                for e in ("kneed", "five_link", "simplest")
                for k in ("rhs", "jac", "energy", "lift")
            ]
        ),
    ),  # noqa: E501
    st.tuples(
        st.sampled_from([12, 13, 14, 15, 21, 22, 24, 26, 28]),
        st.sampled_from([float("nan"), float("inf"), -1.0, 0.0, 1e308, 5e-324]),
    ),
)


@FUZZ
@given(
    mutations=st.lists(SECTION_MUTATIONS, min_size=1, max_size=3),
    period=st.one_of(st.integers(1, 3), st.sampled_from([-(2**70), -1, 0, 2**62, 2**64])),
)
def test_fuzz_prepared_map_and_basin_points(mutations, period):
    args = list(SECTION)
    for index, value in mutations:
        args[index] = value
    try:
        prepared = _hybrid.PreparedMap(*args)
    except REFUSED:
        prepared = None
    if prepared is not None:
        try:
            out = prepared.map(np.ascontiguousarray(Z0), period, False)
        except REFUSED:
            out = None
        if out is not None:
            assert len(out) == 5
    z = np.ascontiguousarray(np.repeat(Z0[None, :], 2, axis=0))
    try:
        outcome, strides = _hybrid.basin_points(*args, z, Z0, 1e-8, 2, period, np.eye(Z0.size), 0.0)
    except REFUSED:
        return
    assert len(outcome) == len(strides) == 2 * 8


@FUZZ
@given(
    x_len=lengths,
    p_len=lengths,
    sizes=st.tuples(huge_ints, huge_ints, huge_ints),
    max_steps=st.one_of(st.integers(1, 50), huge_ints),
    n_strides=st.one_of(st.integers(0, 3), huge_ints),
    dtype=dtypes,
)
def test_fuzz_solve(x_len, p_len, sizes, max_steps, n_strides, dtype):
    head = list(RUN._head)
    if sizes[0] not in (0, 1):  # keep some calls with the model's own sizes
        head[6:9] = sizes
    try:
        r = _hybrid.solve(
            *head,
            _array(x_len, dtype),
            _array(p_len, dtype),
            0,
            0.0,
            2.0,
            n_strides,
            *RUN._settings[:6],
            max_steps,
            1,
            np.zeros(0),
            False,
            4,
        )
    except REFUSED:
        return
    assert len(r.x) == 8 * head[6]


def test_basins_on_two_threads_equal_the_serial_ones():
    args = SECTION
    rng = np.random.default_rng(33)
    z = Z0 + rng.normal(scale=0.05, size=(24, Z0.shape[0]))
    chunks = [np.ascontiguousarray(z[i::4]) for i in range(4)]

    def batch(chunk):
        outcome, strides = _hybrid.basin_points(*args, chunk, Z0, 1e-6, 8, 1, np.eye(Z0.size), 0.0)
        return np.frombuffer(outcome, np.int64), np.frombuffer(strides, np.int64)

    serial = [batch(chunk) for chunk in chunks]
    with cf.ThreadPoolExecutor(2) as pool:
        threaded = list(pool.map(batch, chunks))
    for (o1, s1), (o2, s2) in zip(serial, threaded, strict=True):
        np.testing.assert_array_equal(o1, o2)
        np.testing.assert_array_equal(s1, s2)
