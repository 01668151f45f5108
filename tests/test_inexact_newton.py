"""Coarse early strides in the gait search (``walker.analysis.newton``, ``COARSE_RHO``).

``find_fixed_point`` integrates the strides of iterates far from the fixed point at a looser
rtol than the map's own (``StrideMap.with_tolerance``), chosen from the residual expected
there.  Checked here: which tolerances a search uses (observed on the map class, never timed);
that the solution, its residual and its multipliers come from strides at the map's own
tolerance and agree with a search that never coarsens; that a guess already near the
solution, a map of another method and a wrapper map are never coarsened; and the
``with_tolerance`` copy itself.
"""

from __future__ import annotations

import math
import pickle
from pathlib import Path

import numpy as np
import pytest

import walker.analysis.newton as newton
from walker import load_scene
from walker.analysis.fixedpoint import find_fixed_point
from walker.simulation.stride import StrideMap

GAITS = Path(__file__).resolve().parents[1] / "gaits"


def _scene_map(name, **settings):
    scene = load_scene(GAITS / name)
    P = StrideMap.from_scene(scene)
    if settings:
        keep = {"rtol": P.rtol, "atol": P.atol, "t_max": P.t_max, **settings}
        P = StrideMap(P.model, P.params, **keep)
    return P, P.project(scene.state)


@pytest.fixture
def rtols(monkeypatch):
    """The (rtol, jacobian) of every StrideMap call, in order."""
    seen = []
    call = StrideMap.__call__

    def spy(self, z, **kwargs):
        seen.append((self.rtol, bool(kwargs.get("jacobian", False))))
        return call(self, z, **kwargs)

    monkeypatch.setattr(StrideMap, "__call__", spy)
    return seen


def _never_coarse(monkeypatch, P, z0):
    monkeypatch.setattr(newton, "COARSEST_RTOL", 0.0)
    try:
        return find_fixed_point(P, z0)
    finally:
        monkeypatch.undo()


@pytest.mark.parametrize("name", ["kneed_hsu.toml", "compass_goswami.toml"])
def test_far_guess_coarse_then_own_tolerance(name, rtols, monkeypatch):
    P, z0 = _scene_map(name)
    fp = find_fixed_point(P, z0)
    assert fp.success
    used = list(rtols)
    # a glance at the coarsest level, then the guess's Jacobian stride below the map's rtol
    assert used[0] == (newton.COARSEST_RTOL, False)
    assert used[1][0] > P.rtol and used[1][1]
    # the last evaluation, whose residual and Jacobian the result reports, at the map's own
    assert used[-1] == (P.rtol, True)
    # every rtol is a power of ten between the map's and the coarsest
    assert all(P.rtol <= r <= newton.COARSEST_RTOL for r, _ in used)
    rtols.clear()
    plain = _never_coarse(monkeypatch, P, z0)
    assert plain.success and all(r == P.rtol for r, _ in rtols)
    # the same gait to the stride's own error, the same multipliers to its derivative's
    assert np.max(np.abs(fp.section - plain.section)) < 1e-13
    lam, lam0 = np.sort_complex(fp.multipliers), np.sort_complex(plain.multipliers)
    assert np.max(np.abs(lam - lam0)) < 1e-9
    assert fp.residual <= 1e-12 and np.max(np.abs(P(fp.section).z - fp.section)) < 1e-11


def test_kneed_levels_follow_the_residual(rtols):
    """From the scene's guess (max|F| = 1.7e-2): 1e-6 for the guess, 1e-9 for the first
    iterate (expected residual 2.9e-4 -> 0.1 * 2.9e-4**2 = 8.4e-9), then the map's 1e-12."""
    P, z0 = _scene_map("kneed_hsu.toml")
    fp = find_fixed_point(P, z0)
    assert fp.success and fp.n_iter == 3
    assert rtols == [(1e-6, False), (1e-6, True), (1e-9, True), (1e-12, True), (1e-12, True)]


def test_guess_at_the_solution_uses_the_own_tolerance(rtols):
    P, z0 = _scene_map("kneed_hsu.toml")
    fp = find_fixed_point(P, z0)
    rtols.clear()
    again = find_fixed_point(P, fp.section)
    assert again.success and again.n_iter == 0
    # the glance shows a residual far too small for a coarse Jacobian stride
    assert rtols == [(1e-6, False), (1e-12, True)]


def _level(r, own):
    """The rtol the search picks for a residual r (COARSE_RHO, COARSEST_RTOL), or own."""
    want = min(newton.COARSE_RHO * r * r, newton.COARSEST_RTOL)
    level = 10.0 ** math.floor(math.log10(want)) if want > own else 0.0
    return level if level > own else own


def test_coarse_evaluation_too_coarse_for_its_residual_is_redone(monkeypatch):
    """A coarse result that is too coarse for the residual it finds (here every one: the
    rule to keep one, COARSE_KEEP, set to 0) is not kept: the point is evaluated again at
    the rtol for the residual found, and the budget counts both."""
    P, z0 = _scene_map("kneed_hsu.toml")
    seen = []  # (rtol, jacobian, z, max|P(z) - z|)
    call = StrideMap.__call__

    def spy(self, z, **kwargs):
        res = call(self, z, **kwargs)
        r = float(np.max(np.abs(res.z - z))) if res.success else math.nan
        seen.append((self.rtol, bool(kwargs.get("jacobian", False)), z.copy(), r))
        return res

    monkeypatch.setattr(StrideMap, "__call__", spy)
    monkeypatch.setattr(newton, "COARSE_KEEP", 0.0)
    fp = find_fixed_point(P, z0)
    assert fp.success and fp.residual <= 1e-12
    redone, k = 0, 1  # the glance (k = 0) is kept
    while k < len(seen) - 1:
        rtol, jac, z, r = seen[k]
        k += 1
        if rtol > P.rtol and jac:  # a coarse evaluation, and the one that replaces it
            again = seen[k]
            assert np.array_equal(again[2], z) and again[1]
            assert again[0] == _level(r, P.rtol)
            redone += 1
            k += 1
    assert redone >= 2
    n = len(seen)
    assert find_fixed_point(P, z0, max_evals=n).success
    assert find_fixed_point(P, z0, max_evals=n - 1).status.name == "BUDGET_EXHAUSTED"


def test_other_methods_and_wrappers_are_never_coarsened(rtols):
    P, z0 = _scene_map("compass_goswami.toml", method="RK45")
    assert find_fixed_point(P, z0).success
    assert {r for r, _ in rtols} == {P.rtol}
    rtols.clear()

    class Wrapper:  # forwards everything, with_tolerance included, to the StrideMap
        def __init__(self, inner):
            self.inner = inner

        def __getattr__(self, name):
            return getattr(self.inner, name)

        def __call__(self, z, **kwargs):
            return self.inner(z, **kwargs)

    Q, z0 = _scene_map("compass_goswami.toml")
    assert find_fixed_point(Wrapper(Q), z0).success
    assert {r for r, _ in rtols} == {Q.rtol}


def test_fd_jacobian_search_is_not_coarsened(rtols):
    P, z0 = _scene_map("compass_goswami.toml")
    assert find_fixed_point(P, z0, jacobian="fd").success
    assert {r for r, _ in rtols} == {P.rtol}


def test_with_tolerance_copy():
    P, _ = _scene_map("compass_goswami.toml")
    Q = P.with_tolerance(1e-8, 1e-9)
    assert (Q.rtol, Q.atol) == (1e-8, 1e-9) and (P.rtol, P.atol) == (1e-12, 1e-12)
    assert Q.params is P.params and Q.model is P.model and Q.method == P.method
    assert P.with_tolerance(1e-8, 1e-9) is Q  # kept: its compiled run is prepared once
    z = P.project(load_scene(GAITS / "compass_goswami.toml").state)
    same = StrideMap(P.model, P.params, rtol=1e-8, atol=1e-9, t_max=P.t_max)
    np.testing.assert_array_equal(Q(z).z, same(z).z)
    with pytest.raises(ValueError, match="`rtol` must be"):
        P.with_tolerance(1e-20, 1e-12)
    with pytest.raises(ValueError, match="`atol` must be"):
        P.with_tolerance(1e-8, -1.0)
    # a copy at other parameters, or a pickled map, keeps no tolerance copies of this one
    assert "_tolerances" not in P.with_parameter(0.01).__dict__
    assert "_tolerances" not in pickle.loads(pickle.dumps(P)).__dict__


def test_failing_coarse_stride_is_redone_at_the_own_tolerance(monkeypatch):
    """A coarse stride that fails decides nothing: the map's own tolerance says for sure,
    at the same point, and the budget counts both."""
    from walker.results import MapResult
    from walker.status import Status

    P, z0 = _scene_map("kneed_hsu.toml")
    call = StrideMap.__call__
    seen = []

    def coarse_falls(self, z, **kwargs):
        seen.append((self.rtol, z.copy()))
        if self.rtol != P.rtol:
            nan = np.full(3, np.nan)
            return MapResult(Status.FELL_FORWARD, nan, None, 0.0, np.full(6, np.nan))
        return call(self, z, **kwargs)

    monkeypatch.setattr(StrideMap, "__call__", coarse_falls)
    fp = find_fixed_point(P, z0)
    assert fp.success and fp.residual <= 1e-12
    assert seen[0][0] == 1e-6  # the glance fails: the guess gets the map's own
    coarse = [k for k, (rtol, _) in enumerate(seen) if rtol != P.rtol]
    assert len(coarse) >= 2
    for k in coarse:
        assert seen[k + 1][0] == P.rtol and np.array_equal(seen[k + 1][1], seen[k][1])
    n = len(seen)
    assert find_fixed_point(P, z0, max_evals=n).success
    assert find_fixed_point(P, z0, max_evals=n - 1).status.name == "BUDGET_EXHAUSTED"


def test_a_guess_whose_strides_fail_ends_without_a_jacobian_run(monkeypatch):
    """When the glance's coarse stride fails, the search confirms the failure at the map's
    own tolerance without the Jacobian and ends there (START_FAILS with that stride's
    status): no variational run, which can cost far more (issue 33: the five-link walker at
    g = 1e12).  Seen through the callbacks; the compiled map does the same
    (tests/test_compiled_search.py, tests/test_probe_extreme.py)."""
    from walker.results import MapResult
    from walker.status import Status

    P, z0 = _scene_map("kneed_hsu.toml")
    calls = []

    def falls(self, z, **kwargs):
        calls.append((self.rtol, bool(kwargs.get("jacobian", False))))
        nan = np.full(3, np.nan)
        return MapResult(Status.FELL_FORWARD, nan, None, 0.0, np.full(6, np.nan))

    monkeypatch.setattr(StrideMap, "__call__", falls)
    res = find_fixed_point(P, z0, max_evals=10)
    assert res.status == Status.FELL_FORWARD and not res.success
    assert calls == [(1e-6, False), (P.rtol, False)]


def test_glance_counts_and_is_skipped_on_a_tight_budget(rtols):
    """The glance at the guess is one evaluation of the budget, and is left out when the
    budget could not also pay for the guess's own evaluation."""
    P, z0 = _scene_map("kneed_hsu.toml")
    assert not find_fixed_point(P, z0, max_evals=2).success
    assert rtols[0] == (1e-6, False) and len(rtols) == 2
    rtols.clear()
    assert not find_fixed_point(P, z0, max_evals=1).success
    assert rtols == [(P.rtol, True)]
    rtols.clear()
    fp = find_fixed_point(P, z0, max_evals=5)  # the glance and four Jacobian strides
    assert fp.success and len(rtols) == 5
    fp = find_fixed_point(P, z0, max_evals=4)
    assert not fp.success and fp.status.name == "BUDGET_EXHAUSTED"


@pytest.mark.parametrize("name", ["kneed_hsu.toml", "compass_goswami.toml"])
def test_guesses_far_from_the_gait_end_as_without_coarse_strides(name, monkeypatch):
    """On 40 seeded guesses within +-50 % of the gait, coarse early strides change no status
    and no gait found (the same fixed point to the stride's own error)."""
    P, z0 = _scene_map(name)
    ref = find_fixed_point(P, z0).section
    rng = np.random.default_rng(1)
    guesses = [ref * (1 + rng.uniform(-0.5, 0.5, ref.shape)) for _ in range(40)]
    coarse = [find_fixed_point(P, z) for z in guesses]
    monkeypatch.setattr(newton, "COARSEST_RTOL", 0.0)
    fine = [find_fixed_point(P, z) for z in guesses]
    assert [c.status for c in coarse] == [f.status for f in fine]
    assert sum(c.success for c in coarse) >= 10  # the set exercises converging searches
    for c, f in zip(coarse, fine, strict=True):
        if c.success:
            assert np.max(np.abs(c.section - f.section)) < 1e-12
