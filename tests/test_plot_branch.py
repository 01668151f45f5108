"""Branch measures (step time, step length, speed, cost of transport) and the branch and
orbit-diagram figures of :mod:`walker.plotting.branch`.

Physics checks: on a periodic gait of a passive walker without dampers, the kinetic energy
lost at heel strike equals the potential energy released by the step, ``m g d sin(slope)``
(the configuration repeats shifted by the step ``d`` along the slope), so the impact loss
over ``m g d`` is the cost of transport ``sin(slope)``: this ties the measured step length
to an energy computed by the model.  For point feet the step is also the chord between the
legs at heel strike, ``2 L sin(q_stance + slope)`` (``tests/test_damping.py``).
"""

import math

import matplotlib
import numpy as np
import pytest
from matplotlib.colors import same_color
from numpy.testing import assert_allclose

from walker import load_scene
from walker.analysis.continuation import continue_branch
from walker.analysis.fixedpoint import find_fixed_point
from walker.cli import main
from walker.models import get_model
from walker.plotting.branch import (
    BranchMeasures,
    branch_measures,
    plot_branch,
    plot_orbit_diagram,
    section_unit,
    stored_figures,
)
from walker.results import Bifurcation, Branch, OrbitDiagram
from walker.simulation.stride import StrideMap, simulate
from walker.status import Status

matplotlib.use("Agg")

COMPASS_PD = 0.0766356316  # measured (tests/test_cli_continue.py)
Y_LABELS = [
    "step time [s]",
    "walking speed [m/s]",
    "step length [m]",
    "cost of transport [1]",
    "largest |multiplier| [1]",
]


@pytest.fixture(scope="module")
def compass():
    """Goswami's compass gait branch over slopes 0.07..0.08 (through its doubling), and the
    period-two branch born there."""
    scene = load_scene("gaits/compass_goswami.toml")
    P = StrideMap("compass", scene.params, parameter_name="slope")
    fp = find_fixed_point(P, P.project(scene.state))
    P = P.with_parameter(0.07)
    one = continue_branch(P, find_fixed_point(P, fp.section).section, bounds=(0.07, 0.08))
    assert one.success and len(one.bifurcations) == 1, one.message
    from walker.analysis.continuation import switch_to_period_two

    fp2 = switch_to_period_two(P, one.bifurcations[0])
    mu2 = fp2.parameters["slope"]
    two = continue_branch(P.with_parameter(mu2), fp2.section, bounds=(mu2, 0.08), period=2)
    assert two.success and two.period == 2, two.message
    return scene, one, two


def test_impact_loss_is_the_cost_of_transport(compass):
    scene, one, _ = compass
    model = get_model("compass")
    m = branch_measures(one, model, scene.params)
    params = scene.params
    mass = params.mass_hip + 2.0 * params.mass_leg
    assert not np.any(np.isnan(m.step_length))
    for i in range(0, len(one.parameter), 7):
        p_i = params.replace(slope=float(one.parameter[i]))
        sol = simulate(model, p_i, model.lift(one.sections[i], p_i.as_array()), output="events")
        k_pre = model.energy(sol.events.x_pre[-1], p_i.as_array())[0]
        k_post = model.energy(sol.events.x_post[-1], p_i.as_array())[0]
        lost = (k_pre - k_post) / (mass * params.g * m.step_length[i, 0])
        assert_allclose(lost, math.sin(one.parameter[i]), rtol=1e-8, atol=0)
        assert_allclose(m.cost_of_transport[i], math.sin(one.parameter[i]), rtol=1e-15, atol=0)


@pytest.mark.regression_pin
@pytest.mark.parametrize("scene_file", ["gaits/compass_goswami.toml", "gaits/kneed_hsu.toml"])
def test_point_foot_step_is_the_chord_between_the_legs(scene_file):
    """REGRESSION PIN: the kneed speed 0.83701 m/s (the README's 0.8370) is walker's own; the
    step length, time and speed are checked against the chord between the legs.
    """
    scene = load_scene(scene_file)
    P = StrideMap(scene.model, scene.params, parameter_name="slope")
    fp = find_fixed_point(P, P.project(scene.state))
    br = continue_branch(P, fp.section, to=scene.params.slope + 0.004, max_points=6)
    m = branch_measures(br, scene.model, scene.params)
    assert m.step_length.shape == (len(br.parameter), 1)
    leg = scene.params.leg_length
    chord = 2.0 * leg * np.sin(br.sections[:, 0] + br.parameter)
    assert_allclose(m.step_length[:, 0], chord, rtol=0, atol=1e-9)
    assert_allclose(m.step_time[:, 0], br.step_times, rtol=1e-9, atol=0)
    assert_allclose(m.speed, chord / br.step_times, rtol=1e-9, atol=0)
    assert_allclose(m.max_multiplier, np.abs(br.multipliers).max(axis=1), rtol=0, atol=0)
    assert m.parameter_unit == "rad" and m.time_unit == "s" and m.length_unit == "m"
    if scene.model == "kneed":  # README: Hsu Chen's gait walks at 0.8370 m/s
        assert_allclose(m.speed[0], 0.83701, rtol=0, atol=1e-5)


def test_period_two_measures_have_two_steps(compass):
    scene, _, two = compass
    m = branch_measures(two, "compass", scene.params)
    assert m.step_time.shape == (len(two.parameter), 2) and m.period == 2
    assert_allclose(m.step_time.sum(axis=1), two.step_times, rtol=1e-9, atol=0)
    # a limp: the two steps differ, more so away from the doubling
    gap = np.abs(m.step_time[:, 0] - m.step_time[:, 1])
    assert gap[0] < 1e-2 and gap[-1] > 5e-2
    assert_allclose(m.speed, m.step_length.sum(axis=1) / two.step_times, rtol=1e-9, atol=0)


def _lines(ax, color):
    return [
        ln for ln in ax.get_lines() if same_color(ln.get_color(), color) and len(ln.get_xdata()) > 1
    ]


def test_branch_figure_labels_units_styles_and_bifurcations(compass):
    scene, one, two = compass
    measures = [branch_measures(b, "compass", scene.params) for b in (one, two)]
    fig = plot_branch([one, two], measures)
    axes = fig.axes
    assert [ax.get_ylabel() for ax in axes] == Y_LABELS
    assert axes[-1].get_xlabel() == "slope [rad]"
    assert all(ax.get_xlabel() == "" for ax in axes[:-1])
    pd = one.bifurcations[0].parameter_value
    for ax in axes:
        # the stable part of the period-one branch is solid and below the doubling, its
        # unstable part dashed and above it (runs share their end point)
        solid, dashed = [], []
        for ln in _lines(ax, "C0"):
            x = np.asarray(ln.get_xdata())
            (solid if ln.get_linestyle() == "-" else dashed).append(x)
            assert ln.get_linestyle() in ("-", "--")
        assert solid and dashed
        assert max(x[:-1].max() for x in solid) < pd < min(x.min() for x in dashed) + 1e-3
        # the doubling: a dotted vertical line in every panel
        vlines = [ln for ln in ax.get_lines() if ln.get_linestyle() == ":"]
        assert any(np.all(np.asarray(ln.get_xdata()) == pd) for ln in vlines)
    # period two (C1): two curves (one per step) in the step-time panel, stable: solid
    two_lines = _lines(axes[0], "C1")
    assert len(two_lines) == 2 and all(ln.get_linestyle() == "-" for ln in two_lines)
    legend = [t.get_text() for t in axes[0].get_legend().get_texts()]
    assert legend == ["period 1, stable", "period 1, unstable", "period 2, stable"]
    texts = [t.get_text() for t in axes[-1].texts]
    assert texts == [f"period doubling\nslope = {pd:.5g}"]
    assert abs(pd - COMPASS_PD) <= 1e-8
    assert any(
        np.all(np.asarray(ln.get_ydata()) == 1.0) and ln.get_linestyle() == "-"
        for ln in axes[-1].get_lines()
    )


def test_fold_is_labelled():
    # a branch stopped at its fold (walker continue's default): the fold orbit is the last
    # point, its multiplier 1 up to the location error
    mu = np.array([0.03, 0.025, 0.02, 0.015])
    lam = np.array([[0.5], [0.7], [0.9], [1.0 + 1e-9]], dtype=complex)
    sections = np.arange(4.0)[:, None]
    fold = Bifurcation("fold", 0.015, sections[3], lam[3])
    stable = np.abs(lam[:, 0]) < 1
    br = Branch(
        "damping_hip", mu, sections, np.ones(4), lam, stable, [fold], Status.COMPLETED, "", True
    )
    m = BranchMeasures.from_arrays(
        br, step_time=np.ones(4), step_length=np.ones(4), parameter_unit="N m s/rad"
    )
    fig = plot_branch(br, m)
    assert fig.axes[-1].get_xlabel() == "damping_hip [N m s/rad]"
    assert [t.get_text() for t in fig.axes[-1].texts] == ["fold\ndamping_hip = 0.015"]
    # the marginal fold point does not start an "unstable" run of its own
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert legend == ["period 1, stable"]
    (line,) = _lines(fig.axes[0], "C0")
    assert line.get_linestyle() == "-" and list(line.get_xdata()) == list(mu)


def test_plot_branch_validation(compass):
    scene, one, _ = compass
    m = BranchMeasures.from_arrays(one, step_time=one.step_times, step_length=one.step_times)
    with pytest.raises(ValueError, match="`measures` must hold one BranchMeasures per branch"):
        plot_branch(one, [m, m])
    with pytest.raises(ValueError, match="`branch.parameter_name` must be a parameter of"):
        bad = Branch(
            "slop",
            one.parameter,
            one.sections,
            one.step_times,
            one.multipliers,
            one.stable,
            [],
            Status.COMPLETED,
            "",
            True,
        )
        branch_measures(bad, "compass", scene.params)


def test_orbit_diagram_figure_has_units_and_marks_falls():
    values = np.array([[0.2, 0.2, 0.2], [0.19, 0.23, 0.19], [np.nan] * 3])
    d = OrbitDiagram("slope", np.array([0.05, 0.08, 0.1]), values, coordinate=0)
    fig = plot_orbit_diagram(d, parameter_unit="rad", coordinate_name="q_stance")
    ax = fig.axes[0]
    assert ax.get_xlabel() == "slope [rad]"
    assert ax.get_ylabel() == "q_stance just after heel strike [rad]"
    (dots,) = ax.collections
    assert dots.get_offsets().shape == (6, 2)
    (fell,) = [ln for ln in ax.get_lines() if ln.get_label() == "fell"]
    assert list(fell.get_xdata()) == [0.1] and fell.get_marker() == "x"
    fig = plot_orbit_diagram(d, parameter_unit="rad", coordinate_name="qd_stance")
    assert fig.axes[0].get_ylabel() == "qd_stance just after heel strike [rad/s]"
    assert section_unit("theta_dot") == "rad/s" and section_unit("q1") == "rad"


def test_stored_figures_of_cli_files(tmp_path, capsys):
    branch = tmp_path / "compass.h5"
    code = main(
        [
            "continue",
            "gaits/compass_goswami.toml",
            "--set",
            "slope=0.072",
            "--range",
            "0.07:0.08",
            "--switch",
            "--out",
            str(branch),
        ]
    )
    orbits = tmp_path / "orbits.h5"
    code2 = main(
        [
            "orbit-diagram",
            "gaits/compass_goswami.toml",
            "--range",
            "0.07:0.08",
            "--n",
            "3",
            "--transient",
            "20",
            "--strides",
            "4",
            "--out",
            str(orbits),
        ]
    )
    capsys.readouterr()
    assert code == 0 and code2 == 0
    fig = stored_figures(branch)["branch"]
    assert [ax.get_ylabel() for ax in fig.axes] == Y_LABELS
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert "period 2, stable" in legend  # the switched branch, read from compass_period2.h5
    fig = stored_figures(orbits)["orbit_diagram"]
    assert fig.axes[0].get_xlabel() == "slope [rad]"
    assert fig.axes[0].get_ylabel() == "q_stance just after heel strike [rad]"
    with pytest.raises(ValueError, match="not a branch or an orbit diagram"):
        main_out = tmp_path / "fp.h5"
        assert main(["find", "gaits/compass_goswami.toml", "--out", str(main_out)]) == 0
        stored_figures(main_out)
