"""docs/own_system.md is true: its code blocks run, in order, and the numbers it quotes are
the closed form of the kicked bouncing ball (``P(v) = e v + k``: fixed point ``k / (1 - e)``,
multiplier ``e``, stride time ``2 v* / g``), with no numba and nothing compiled."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import walker
from walker.status import Status

DOC = Path(__file__).resolve().parents[1] / "docs" / "own_system.md"


@pytest.fixture(scope="module")
def page():
    """The namespace after running every ``python`` block of the page, in order."""
    namespace: dict = {}
    for block in re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), re.S):
        exec(compile(block, str(DOC), "exec"), namespace)  # noqa: S102 - our own docs
    return namespace


def test_the_page_has_its_code_blocks():
    assert len(re.findall(r"```python\n", DOC.read_text(encoding="utf-8"))) == 3


def test_kicked_ball_fixed_point_is_the_closed_form(page):
    g, e, kick, gait = page["g"], page["e"], page["kick"], page["gait"]
    v_star = kick / (1.0 - e)
    assert gait.success
    assert_allclose(gait.section, [v_star], rtol=0, atol=1e-9)
    assert_allclose(gait.multipliers, [e], rtol=0, atol=1e-9)
    assert_allclose(gait.step_time, 2.0 * v_star / g, rtol=0, atol=1e-9)
    # the numbers the prose quotes
    text = DOC.read_text(encoding="utf-8")
    assert "`v* = 1 / (1 - 0.8) = 5` m/s" in text and "1.01937" in text
    assert_allclose(2.0 * v_star / g, 1.01937, rtol=0, atol=5e-6)


def test_kicked_ball_branch_is_the_line_v_equals_k_over_1_minus_e(page):
    branch, e = page["branch"], page["e"]
    assert branch.success and branch.parameter.size >= 5
    assert_allclose(branch.parameter[-1], 2.0, rtol=0, atol=1e-9)
    assert_allclose(branch.sections[:, 0], branch.parameter / (1.0 - e), rtol=0, atol=1e-8)
    assert_allclose(np.abs(branch.multipliers[:, 0]), e, rtol=0, atol=1e-8)


def test_map_result_fields_of_one_bounce(page):
    res, g, e = page["res"], page["g"], page["e"]
    assert res.status == Status.COMPLETED and res.success
    assert_allclose(res.z, [e * 5.0 + 1.0], rtol=0, atol=1e-9)
    assert_allclose(res.jac, [[e]], rtol=0, atol=1e-9)
    assert_allclose(res.step_time, 2 * 5.0 / g, rtol=0, atol=1e-9)
    assert_allclose(res.state, [0.0, 5.0], rtol=0, atol=1e-9)


def test_finite_difference_lift_and_projection_give_the_same_multiplier(page):
    P = walker.SystemSectionMap(
        page["ball"],
        [page["g"], 0.5, 2.0],
        lift=lambda z, p: np.array([0.0, z[0]]),
        project=lambda x, p: np.array([x[1]]),
        section_names=("v",),
    )
    res = P([3.0], jacobian=True)
    assert_allclose(res.jac, [[0.5]], rtol=0, atol=1e-6)
    assert np.isnan(P.parameter_value)


def test_a_start_that_never_lands_is_a_status_not_an_exception(page):
    P = walker.SystemSectionMap(
        page["ball"],
        [page["g"], 0.8, 1.0],
        lift=lambda z, p: np.array([0.0, z[0]]),
        project=lambda x, p: np.array([x[1]]),
        section_names=("v",),
        t_max=0.1,
    )
    res = P([5.0])
    assert res.status != Status.COMPLETED and np.all(np.isnan(res.z))


@pytest.mark.parametrize(
    ("change", "exc", "match"),
    [
        ({"system": "ball"}, TypeError, "`system` must be a walker.integrate.HybridSystem"),
        ({"lift": 3}, TypeError, "`lift` must be callable"),
        ({"params": [np.nan, 0.8, 1.0]}, ValueError, "`params` must be a finite"),
        ({"section_names": ()}, ValueError, "`section_names` must name"),
        ({"parameter_index": 3}, ValueError, r"`parameter_index` must be in \[0, 3\)"),
    ],
)
def test_bad_input_names_the_argument(page, change, exc, match):
    args = dict(
        system=page["ball"],
        params=[9.81, 0.8, 1.0],
        lift=lambda z, p: np.array([0.0, z[0]]),
        project=lambda x, p: np.array([x[1]]),
        section_names=("v",),
    )
    args.update(change)
    with pytest.raises(exc, match=match):
        walker.SystemSectionMap(**args)


def test_everything_the_route_needs_is_public():
    for name in ("HybridSystem", "SystemSectionMap", "MapResult", "EVENT_STRIDE", "Status"):
        assert name in walker.__all__ and getattr(walker, name) is not None
