"""Continuation, bifurcation location, branch switching and orbit diagrams on toy maps.

Closed forms for the Hénon map (x, y) -> (1 - a x^2 + y, b x), fixed point (x, b x) with
a x^2 + (1 - b) x - 1 = 0 and Jacobian J = [[-2 a x, 1], [b, 0]]:

* period doubling: det(J + I) = 1 - 2 a x - b = 0 gives x = (1 - b) / (2 a); inserted in the
  fixed-point equation, (1 - b)^2 / (4 a) + (1 - b)^2 / (2 a) = 1, so a_PD = 3 (1 - b)^2 / 4;
* fold (saddle-node): det(J - I) = 1 + 2 a x - b = 0 gives x = -(1 - b) / (2 a); inserted,
  -(1 - b)^2 / (4 a) = 1, so a_fold = -(1 - b)^2 / 4 (where the discriminant of the
  fixed-point quadratic vanishes).

The period-2 orbit is derived in ``_toy_maps.henon_two_cycle``.
"""

import numpy as np
import pytest
from _toy_maps import HenonMap, LogisticMap, henon_fixed_points, henon_two_cycle
from numpy.testing import assert_allclose

from walker.analysis.continuation import continue_branch, orbit_diagram, switch_to_period_two
from walker.results import Bifurcation
from walker.status import Status

B = 0.3
A_PD = 3 * (1 - B) ** 2 / 4  # 0.3675
A_FOLD = -((1 - B) ** 2) / 4  # -0.1225
A0 = 0.1


def _start(a=A0, **kwargs):
    return HenonMap(a, B, **kwargs), henon_fixed_points(a, B)[0]


def _distance_to_fixed_points(branch):
    """Max over branch points of the distance to the nearer closed-form fixed point."""
    d = []
    for a, z in zip(branch.parameter, branch.sections, strict=True):
        roots = henon_fixed_points(a, B)
        d.append(min(np.max(np.abs(z - r)) for r in roots))
    return max(d)


@pytest.mark.parametrize("method", ["arclength", "natural"])
def test_period_doubling_located(method):
    m, z0 = _start()
    br = continue_branch(m, z0, to=0.6, method=method)
    assert br.status == Status.COMPLETED and br.success, br.message
    assert br.parameter[0] == A0 and br.parameter[-1] == 0.6
    assert np.all(np.diff(br.parameter) > 0)
    assert br.parameter_name == "a" and br.period == 1
    # every point on the closed-form stable branch (+ root)
    for a, z in zip(br.parameter, br.sections, strict=True):
        assert_allclose(z, henon_fixed_points(a, B)[0], rtol=0, atol=1e-10)
    # stable below a_PD, unstable above
    assert np.array_equal(br.stable, br.parameter < A_PD)
    pds = [bf for bf in br.bifurcations if bf.kind == "period_doubling"]
    assert len(pds) == 1 and len(br.bifurcations) == 1
    pd = pds[0]
    assert abs(pd.parameter_value - A_PD) <= 1e-8
    assert_allclose(pd.section, henon_fixed_points(A_PD, B)[0], rtol=0, atol=1e-7)
    # multipliers there: -1 and b (product = det J = -b)
    assert_allclose(np.sort(pd.multipliers.real), [-1.0, B], rtol=0, atol=1e-8)
    assert br.multipliers.shape == (len(br.parameter), 2)
    assert_allclose(br.step_times, 1.0, rtol=0, atol=0)


def test_arclength_goes_round_the_fold():
    m, z0 = _start()
    br = continue_branch(m, z0, to=-0.5, max_points=80)
    # `to` is never reached: beyond the fold the branch heads back towards a = 0
    assert br.status == Status.MAX_STEPS and "max_points" in br.message
    assert len(br.parameter) == 80
    i = int(np.argmin(br.parameter))
    assert 5 < i < 75
    assert np.all(np.diff(br.parameter[: i + 1]) < 0)  # parameter decreases ...
    assert np.all(np.diff(br.parameter[i:]) > 0)  # ... then increases
    assert br.parameter[i] >= A_FOLD - 1e-12  # no fixed points below the fold
    assert _distance_to_fixed_points(br) <= 1e-10
    # before the fold on the + root (stable), after it on the - root (saddle)
    assert_allclose(br.sections[0], henon_fixed_points(A0, B)[0], rtol=0, atol=1e-12)
    assert_allclose(br.sections[-1], henon_fixed_points(br.parameter[-1], B)[1], rtol=0, atol=1e-10)
    assert br.stable[0] and not br.stable[-1]
    folds = [bf for bf in br.bifurcations if bf.kind == "fold"]
    assert len(folds) == 1
    assert abs(folds[0].parameter_value - A_FOLD) <= 1e-8
    # multipliers at the fold: +1 and -b (product -b)
    assert_allclose(np.sort(folds[0].multipliers.real), [-B, 1.0], rtol=0, atol=1e-6)
    x_fold = 2 / (1 - B)  # -(1 - b) / (2 a_fold)
    assert_allclose(folds[0].section, [x_fold, B * x_fold], rtol=0, atol=1e-4)


def test_natural_continuation_stops_at_fold():
    m, z0 = _start()
    br = continue_branch(m, z0, to=-0.5, method="natural")
    assert br.status == Status.NOT_CONVERGED and not br.success
    assert "arclength" in br.message
    assert A_FOLD <= br.parameter[-1] <= A_FOLD + 1e-3
    assert np.all(np.diff(br.parameter) < 0)
    # near the fold z is ill-conditioned in the residual (DP - I nearly singular), so check
    # the residual tightly and the closed form loosely
    for a, z in zip(br.parameter, br.sections, strict=True):
        assert np.max(np.abs(m(z, parameter=a).z - z)) <= 1e-11
    assert _distance_to_fixed_points(br) <= 1e-7


@pytest.mark.parametrize("method", ["arclength", "natural"])
def test_branch_stops_when_walker_falls(method):
    # The stable branch reaches x = 2 at a = -0.1 (4 a + 2 (1 - b) - 1 = 0); beyond it the
    # orbit lies in the falling region max|z| > 2.
    m, z0 = _start(fall_radius=2.0)
    br = continue_branch(m, z0, to=-0.5, method=method)
    assert br.status == Status.FELL_FORWARD and not br.success
    assert -0.1 <= br.parameter[-1] <= -0.1 + 1e-4
    assert np.max(np.abs(br.sections)) <= 2.0


def test_start_failure_gives_empty_branch():
    m = HenonMap(A0, B, fall_radius=2.0)
    br = continue_branch(m, np.array([3.0, 0.0]), to=0.5)
    assert br.status == Status.FELL_FORWARD
    assert br.parameter.shape == (0,) and br.sections.shape == (0, 2)


def test_switch_to_period_two_and_continue():
    m, z0 = _start()
    br = continue_branch(m, z0, to=0.6)
    pd = next(bf for bf in br.bifurcations if bf.kind == "period_doubling")
    fp = switch_to_period_two(m, pd, amplitude=1e-3)
    assert fp.success and fp.period == 2, fp.message
    a2 = fp.parameters["a"]
    # supercritical doubling: the 2-cycle exists above a_PD, O(amplitude^2) away
    assert A_PD < a2 < A_PD + 1e-4
    assert "above" in fp.message
    m2 = m.with_parameter(a2)
    one = m2(fp.section).z
    two = m2(fp.section, n_strides=2).z
    assert_allclose(two, fp.section, rtol=0, atol=1e-10)
    assert np.max(np.abs(one - fp.section)) > 1e-4  # P(z) != z: a genuine 2-cycle
    # closed form (ill-conditioned this close to the doubling: DP^2 - I has an eigenvalue
    # ~ 5e-7, so the 1e-14 residual moves z by ~ 1e-7)
    cycle = henon_two_cycle(a2, B)
    assert min(np.max(np.abs(fp.section - c)) for c in cycle) <= 1e-6
    assert fp.stable  # the bifurcating 2-cycle is stable (supercritical)

    # continue the period-2 branch to a = 0.8 and compare with the closed form
    br2 = continue_branch(m2, fp.section, to=0.8, period=2)
    assert br2.status == Status.COMPLETED and br2.period == 2, br2.message
    assert br2.parameter[-1] == 0.8
    cycle = henon_two_cycle(0.8, B)
    assert min(np.max(np.abs(br2.sections[-1] - c)) for c in cycle) <= 1e-10
    assert_allclose(br2.step_times, 2.0, rtol=0, atol=0)
    assert br2.bifurcations == [] and np.all(br2.stable)
    # brute force: iterate from near the period-1 point at a = 0.8, it settles on the cycle
    z = henon_fixed_points(0.8, B)[0] + 1e-3
    z = HenonMap(0.8, B)(z, n_strides=1000).z
    assert min(np.max(np.abs(z - c)) for c in cycle) <= 1e-10


def test_switch_rejects_wrong_kind():
    m, z0 = _start()
    with pytest.raises(ValueError, match="`bifurcation` must be a period doubling"):
        switch_to_period_two(m, Bifurcation("fold", A_FOLD, z0, np.zeros(2, complex)))
    pd = Bifurcation("period_doubling", A_PD, henon_fixed_points(A_PD, B)[0], np.zeros(2))
    with pytest.raises(ValueError, match="`amplitude` must be positive"):
        switch_to_period_two(m, pd, amplitude=0.0)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"to": A0}, r"`to` must differ"),
        ({"to": np.inf}, r"`to` must be finite"),
        ({"method": "pseudo"}, r"`method` must be one of"),
        ({"step": -0.1}, r"`step` must be positive"),
        ({"min_step": 0.1, "max_step": 0.01}, r"`min_step` .* must not exceed `max_step`"),
        ({"max_points": 1}, r"`max_points` must be an integer >= 2"),
        ({"period": 0}, r"`period` must be an integer >= 1"),
        ({"tol": 0.0}, r"`tol` must be positive"),
        ({"jacobian": "sym"}, r"`jacobian` must be one of"),
        ({"z0": np.zeros(3)}, r"`z0` must have shape \(2,\)"),
    ],
)
def test_continue_validation(kwargs, match):
    m, z0 = _start()
    args = {"to": 0.5, "z0": z0} | kwargs
    z = args.pop("z0")
    with pytest.raises(ValueError, match=match):
        continue_branch(m, z, **args)


def test_orbit_diagram_logistic():
    # Logistic map r x (1 - x): stable fixed point 1 - 1/r for 1 < r < 3, stable 2-cycle for
    # 3 < r < 1 + sqrt(6) = 3.449..., period 4 just above (May 1976, Nature 261:459).
    below = [2.2, 2.6, 2.9]
    between = [3.1, 3.3, 3.4, 3.44]
    above = [3.5]
    rs = np.array(below + between + above + [4.5])
    d = orbit_diagram(LogisticMap(2.0), np.array([0.3]), rs, n_transient=2000, n_keep=16)
    assert d.values.shape == (len(rs), 16) and d.parameter_name == "r"
    assert_allclose(d.parameter, rs, rtol=0, atol=0)

    def n_distinct(row):
        return len(np.unique(np.round(row, 6)))

    for i, r in enumerate(rs[: len(below)]):
        assert n_distinct(d.values[i]) == 1
        assert_allclose(d.values[i], 1 - 1 / r, rtol=0, atol=1e-9)
    for i, r in enumerate(between, start=len(below)):
        assert n_distinct(d.values[i]) == 2
        # the 2-cycle: x = ((r + 1) -+ sqrt((r + 1)(r - 3))) / (2 r)
        root = np.sqrt((r + 1) * (r - 3))
        assert_allclose(
            np.sort(np.unique(np.round(d.values[i], 9))),
            [(r + 1 - root) / (2 * r), (r + 1 + root) / (2 * r)],
            rtol=0,
            atol=1e-8,
        )
    assert n_distinct(d.values[len(below) + len(between)]) == 4
    # r = 4.5 maps [0, 1] outside itself: the "walker" falls, the row is NaN
    assert np.all(np.isnan(d.values[-1]))


def test_orbit_diagram_warm_start_and_validation():
    # Without warm start a fall does not poison later rows either way; with warm start the
    # row after a fall restarts from z0.
    rs = np.array([4.5, 2.5])
    for warm in (True, False):
        d = orbit_diagram(LogisticMap(), np.array([0.3]), rs, n_keep=4, warm_start=warm)
        assert np.all(np.isnan(d.values[0]))
        assert_allclose(d.values[1], 0.6, rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="`coordinate` must be an integer in"):
        orbit_diagram(LogisticMap(), np.array([0.3]), rs, coordinate=1)
    with pytest.raises(ValueError, match="`n_keep` must be an integer >= 1"):
        orbit_diagram(LogisticMap(), np.array([0.3]), rs, n_keep=0)
    with pytest.raises(ValueError, match="`parameters` must be a non-empty 1-D"):
        orbit_diagram(LogisticMap(), np.array([0.3]), [])


def test_period_two_branch_doubles_again():
    # The 2-cycle's stride-2 Jacobian M = J(x2) J(x1) has trace 4 a^2 x1 x2 + 2 b and
    # det b^2; det(M + I) = 1 + trace + b^2 = 0 with x1 x2 = ((1 - b)^2 - a) / a^2 gives the
    # period-4 onset a = (1 - b)^2 + (1 + b)^2 / 4 (0.9125 for b = 0.3).
    a_pd2 = (1 - B) ** 2 + (1 + B) ** 2 / 4
    m = HenonMap(0.6, B)
    br = continue_branch(m, henon_two_cycle(0.6, B)[0], to=1.0, period=2)
    assert br.status == Status.COMPLETED, br.message
    pds = [bf for bf in br.bifurcations if bf.kind == "period_doubling"]
    assert len(pds) == 1
    assert abs(pds[0].parameter_value - a_pd2) <= 1e-8
    assert np.array_equal(br.stable, br.parameter < a_pd2)
    fp4 = switch_to_period_two(m, pds[0], period=2)
    assert fp4.success and fp4.period == 4, fp4.message
    m4 = m.with_parameter(fp4.parameters["a"])
    assert np.max(np.abs(m4(fp4.section, n_strides=4).z - fp4.section)) <= 1e-10
    assert np.max(np.abs(m4(fp4.section, n_strides=2).z - fp4.section)) > 1e-4
