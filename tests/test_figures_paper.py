"""Figures fit for a paper (issue 31 item 7), checked on labels, legend texts, colour limits,
titles and text positions rather than pixels (as tests/test_plot_defects.py does).

Every figure kind ``walker plot`` draws is rendered here from a stored result and each of its
axis labels is checked to carry a unit; the figure's title names the model and the scene.
"""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.collections import LineCollection, QuadMesh  # noqa: E402
from matplotlib.text import Text  # noqa: E402
from numpy.testing import assert_allclose  # noqa: E402
from test_plot_defects import _drawn, _fixed_point_table, _legend  # noqa: E402

from walker import plotting  # noqa: E402
from walker.cli import main  # noqa: E402
from walker.models import get_model  # noqa: E402
from walker.plotting import gallery  # noqa: E402
from walker.plotting.common import robust_limits  # noqa: E402
from walker.results import Bifurcation, Branch  # noqa: E402
from walker.status import Status  # noqa: E402
from walker.storage import read  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
GALLERY = ROOT / "results" / "gallery"
UNIT = re.compile(r"\[[^\[\]]+\]$")


def _unit_labels_ok(fig) -> list[str]:
    """Every non-empty axis label of ``fig`` (colour bars included) ends in ``[unit]``,
    except a categorical "status" axis; returns the labels checked."""
    labels = []
    for ax in fig.axes:
        for label in (ax.get_xlabel(), ax.get_ylabel()):
            if label and label != "status":
                assert UNIT.search(label), f"axis label without a unit: {label!r}"
                labels.append(label)
    return labels


def _renderer(fig):
    """An Agg renderer of ``fig`` after a layout and draw (figures are made without pyplot)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
    canvas.draw()
    return canvas.get_renderer()


def _overlap(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def _legends_off_the_data(fig) -> None:
    """Each legend lies outside the data area of its axes (display coordinates)."""
    renderer = _renderer(fig)
    for ax in fig.axes:
        legend = ax.get_legend()
        if legend is not None:
            box = legend.get_window_extent(renderer)
            assert not _overlap(box, ax.get_window_extent(renderer)), _legend(ax)


SHIPPED = [
    ("kneed_walk.h5", "kneed, scene kneed_hsu", ("angles", "energy", "phase_portrait")),
    ("simplest_branch.h5", "simplest, scene simplest_garcia", gallery.FIGURES["branch"]),
    ("compass_basin.h5", "compass, scene compass_goswami", ("basin",)),
    ("compass_orbit_diagram.h5", "compass, scene compass_goswami", ("orbit_diagram",)),
]


@pytest.mark.filterwarnings("ignore:the stored parameters predate")
@pytest.mark.parametrize(("name", "title", "kinds"), SHIPPED)
def test_every_figure_of_a_shipped_result_has_units_a_title_and_legends_off_the_data(
    name, title, kinds, tmp_path, monkeypatch
):
    figures = _drawn(GALLERY / name, tmp_path, monkeypatch)
    assert tuple(figures) == tuple(kinds)
    for fig in figures.values():
        assert fig.get_suptitle().startswith(title)
        assert _unit_labels_ok(fig)
        _legends_off_the_data(fig)


def test_fixed_point_and_sweep_figures_have_units_and_titles(tmp_path, monkeypatch):
    fp = tmp_path / "fp.h5"
    assert main(["find", "gaits/simplest_garcia.toml", "--out", str(fp)]) == 0
    (fig,) = _drawn(fp, tmp_path, monkeypatch).values()
    assert fig.get_suptitle() == "simplest, scene simplest_garcia"
    assert _unit_labels_ok(fig) == ["Re(multiplier) [1]", "Im(multiplier) [1]"]
    for points, names in (
        (np.linspace(0.01, 0.05, 5)[:, None], ("slope",)),
        ([[a, b] for b in (1.0, 2.0) for a in (0.01, 0.02, 0.03)], ("slope", "mass_hip")),
    ):
        table = _fixed_point_table(points, names=names)
        fig = gallery._plot_sweep(table, {"model": "compass", "parameters": {}})
        assert len(_unit_labels_ok(fig)) >= 3


def test_figure_title_names_model_and_scene_stem():
    assert gallery.figure_title({"model": "kneed", "scene": "gaits/kneed_hsu.toml"}) == (
        "kneed, scene kneed_hsu"
    )
    assert gallery.figure_title({"model": "kneed"}) == "kneed"


# -- bifurcation diagrams ---------------------------------------------------------------------


def _two_kind_branch(period=1):
    param = np.linspace(0.01, 0.02, 6)
    sections = np.stack([param, -param], axis=1)
    mult = np.tile([0.5 + 0j, -0.2 + 0j], (6, 1))
    bifs = [
        Bifurcation("fold", 0.012, np.array([0.012, -0.012]), np.array([1.0 + 0j, 0.2])),
        Bifurcation("period_doubling", 0.018, np.array([0.018, -0.018]), np.array([-1.0, 0.2])),
    ]
    return Branch(
        "slope",
        param,
        sections,
        np.ones(6),
        mult,
        param < 0.018,
        bifs,
        Status.COMPLETED,
        "",
        True,
        period,
    )


def test_bifurcation_legend_says_fold_and_period_doubling_in_words():
    fig = plotting.plot_bifurcation(
        _two_kind_branch(), parameter_unit="rad", coordinate_name="theta"
    )
    ax = fig.axes[0]
    assert _legend(ax) == ["stable", "unstable", "fold (LP)", "period doubling (PD)"]
    assert [t.get_text() for t in ax.texts] == ["LP", "PD"]
    assert (ax.get_xlabel(), ax.get_ylabel()) == (
        "slope [rad]",
        "theta just after heel strike [rad]",
    )


def test_period_two_branch_draws_both_points_of_its_orbit():
    branch = _two_kind_branch(period=2)
    second = np.asarray(branch.sections) * np.array([1.5, 0.5])
    cycle = np.stack([branch.sections, second], axis=1)
    ax = plotting.plot_bifurcation(branch, cycle_sections=cycle).axes[0]
    curves = [ln for ln in ax.get_lines() if ln.get_linestyle() in ("-", "--")]
    drawn_y = np.concatenate([ln.get_ydata() for ln in curves])
    # every point of both orbits is on a curve
    assert np.all(np.isin(cycle[:, 0, 0], drawn_y)) and np.all(np.isin(cycle[:, 1, 0], drawn_y))
    assert _legend(ax)[0] == "stable (period 2: 2 points)"


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore:the stored parameters predate")
def test_branch_measures_cycle_points_close_the_period_two_orbit():
    """The two points of a period-2 gait of the simplest walker (switched to at the period
    doubling of the shipped branch): the stride map takes point 1 to point 2 and point 2
    back to point 1 (independent check: a fresh stride from point 2)."""
    from walker import StrideMap
    from walker.analysis.continuation import switch_to_period_two
    from walker.plotting.branch import branch_measures

    branch, prov = read(GALLERY / "simplest_branch.h5")
    model, params = gallery._params_from_provenance(prov)
    (pd,) = [b for b in branch.bifurcations if b.kind == "period_doubling"]
    fp = switch_to_period_two(StrideMap("simplest", params), pd)
    assert fp.success
    p2 = params.replace(slope=float(fp.parameters["slope"]))
    two = Branch(
        "slope",
        np.array([p2.slope]),
        fp.section[None, :],
        np.array([fp.step_time]),
        fp.multipliers[None, :],
        np.array([fp.stable]),
        [],
        Status.COMPLETED,
        "",
        True,
        2,
    )
    cycle = branch_measures(two, model, p2).cycle_sections
    assert cycle.shape == (1, 2, 2)
    a, b = cycle[0]
    assert np.max(np.abs(a - b)) > 1e-3  # a genuine period-two orbit
    back = StrideMap("simplest", p2)(b)
    assert back.success
    assert_allclose(back.z, a, rtol=0, atol=1e-8)


# -- energy labels ---------------------------------------------------------------------------


def test_impact_loss_labels_do_not_collide_and_stay_in_the_axes(tmp_path, monkeypatch):
    """Four strides of the kneed walker: eight impacts (knee lock, heel strike) 0.1-0.5 s
    apart, each labelled with its loss; no two labels overlap and all are inside the axes."""
    fig = _drawn(GALLERY / "kneed_walk.h5", tmp_path, monkeypatch, figures=["energy"])["energy"]
    ax = fig.axes[0]
    renderer = _renderer(fig)
    # the texts' own boxes (an Annotation's extent includes its connecting line)
    boxes = [Text.get_window_extent(t, renderer) for t in ax.texts]
    assert (
        len(boxes)
        == len(next(c for c in ax.collections if isinstance(c, LineCollection)).get_segments())
        == 8
    )
    for a, b in itertools.combinations(boxes, 2):
        assert not _overlap(a, b)
    frame = ax.get_window_extent(renderer)
    assert all(frame.x0 <= b.x0 and b.x1 <= frame.x1 + 0.5 for b in boxes)
    # the data stay below the labels
    lowest_label = min(b.y0 for b in boxes)
    top_of_data = ax.transData.transform((0, max(ln.get_ydata().max() for ln in ax.lines)))[1]
    assert top_of_data < lowest_label


# -- heat maps: robust colour limits, outliers drawn as such ---------------------------------


def test_robust_limits_leave_out_only_the_outlier():
    values = np.r_[np.linspace(0.3, 0.9, 40), 198.0, np.nan]
    lo, hi, outside = robust_limits(values)
    assert (lo, hi) == (0.3, 0.9)
    assert np.flatnonzero(outside).tolist() == [40]
    # no outlier: the full range, also for a skewed spread and for many equal values
    for values in (np.linspace(1.0, 2.0, 11), np.geomspace(1.0, 50.0, 30), np.r_[[0.5] * 9, 2]):
        lo, hi, outside = robust_limits(values)
        assert (lo, hi, outside.any()) == (values.min(), values.max(), False)


def test_one_large_multiplier_does_not_flatten_the_sweep_map():
    points = [[a, b] for b in (1.0, 2.0, 3.0) for a in (0.01, 0.02, 0.03)]
    table = _fixed_point_table(points, names=("slope", "mass_hip"))
    # point 4 gets |lambda| = 198; the others are 0.5 .. 1.6 (max(0.5, 0.2 i))
    table.columns["multipliers_re"][4, 0] = 198.0
    fig = plotting.plot_sweep(table, parameter_units=["rad", "kg"])
    ax = next(a for a in fig.axes if a.get_title().startswith("largest"))
    (mesh,) = [c for c in ax.collections if isinstance(c, QuadMesh)]
    assert mesh.norm.vmax == pytest.approx(1.6, abs=1e-12)
    assert _legend(ax) == ["outside colour range (1): 198"]
    (cross,) = [ln for ln in ax.get_lines() if ln.get_marker() == "x"]
    assert (cross.get_xdata()[0], cross.get_ydata()[0]) == (0.02, 2.0)
    # the one-parameter sweep: the axis is not stretched to 198 either
    table = _fixed_point_table(np.linspace(0.01, 0.09, 9)[:, None])
    table.columns["multipliers_re"][4, 0] = 198.0
    fig = plotting.plot_sweep(table, parameter_units=["rad"])
    ax = next(a for a in fig.axes if a.get_ylabel() == "largest |multiplier| [1]")
    assert ax.get_ylim()[1] < 3.0
    assert "off scale (1): 198" in _legend(ax)


# -- torques, animation ----------------------------------------------------------------------


def test_torques_are_named_by_their_joints():
    model = get_model("three_link")
    names = gallery.torque_names(model, 2)
    assert names == ["hip_stance joint", "hip_swing joint"]
    t = np.linspace(0.0, 1.0, 5)
    fig = plotting.plot_torques(t, np.zeros((5, 2)), names=names, limit=10.0)
    assert _legend(fig.axes[0]) == names
    assert _unit_labels_ok(fig) == ["time [s]", "torque [N m]"]
    _legends_off_the_data(fig)
    assert gallery.torque_names(get_model("compass"), 3) == ["u0", "u1", "u2"]


@pytest.mark.parametrize("name", ["compass", "kneed", "three_link", "five_link"])
def test_animation_draws_stance_and_swing_legs_in_two_colours(name):
    model = get_model(name)
    swing = int(getattr(model.module, "SWING_FOOT", -1))
    n_points = 1 + max(max(s) for s in model.segments)
    frames = np.random.default_rng(0).normal(size=(2, n_points, 2))
    anim = plotting.animate_walker(frames, model.segments, swing_foot=swing)
    anim._draw_was_started = True  # not rendered: only its lines are checked
    ax = anim._fig.axes[0]
    links = ax.get_lines()[1 : 1 + len(model.segments)]
    colours = {}
    for (a, b), line in zip(model.segments, links, strict=True):
        colours.setdefault(line.get_color(), set()).update((a, b))
    # the stance foot (point 0) and the swing foot are in links of different colours
    stance = [c for c, pts in colours.items() if 0 in pts]
    swing_c = [c for c, pts in colours.items() if swing % n_points in pts]
    assert len(stance) == 1 and len(swing_c) == 1 and stance != swing_c
    assert _legend(ax)[:2] == ["stance leg", "swing leg"]


# -- the command line ------------------------------------------------------------------------


@pytest.mark.slow  # every figure through the command: the integration tier
def test_plot_draws_only_the_figures_asked_in_the_format_asked(tmp_path, capsys):
    out = tmp_path / "figs"
    code = main(
        [
            "plot",
            str(GALLERY / "kneed_walk.h5"),
            "--out",
            str(out),
            "--figure",
            "energy,angles",
            "--format",
            "svg",
            "--dpi",
            "50",
        ]
    )
    assert code == 0
    assert sorted(p.name for p in out.iterdir()) == [
        "kneed_walk_angles.svg",
        "kneed_walk_energy.svg",
    ]
    assert (out / "kneed_walk_energy.svg").read_text()[:200].lstrip().startswith("<?xml")
    png = tmp_path / "png"
    assert (
        main(
            [
                "plot",
                str(GALLERY / "kneed_walk.h5"),
                "--out",
                str(png),
                "--figure",
                "angles",
                "--dpi",
                "50",
            ]
        )
        == 0
    )
    from PIL import Image

    with Image.open(png / "kneed_walk_angles.png") as image:
        assert image.size == (350, 280)  # the 7.0 x 5.6 in figure at 50 dots per inch
    pdf = tmp_path / "pdf"
    assert (
        main(["plot", str(GALLERY / "compass_basin.h5"), "--out", str(pdf), "--format", "pdf"]) == 0
    )
    assert (pdf / "compass_basin_basin.pdf").read_bytes()[:5] == b"%PDF-"
    capsys.readouterr()


@pytest.mark.parametrize(
    ("extra", "flag"),
    [
        (["--figure", "energy,nonsense"], "--figure"),
        (["--figure", "bifurcation"], "--figure"),  # not a figure of a run
        (["--dpi", "0"], "--dpi"),
    ],
)
def test_plot_bad_figure_options_exit_2_naming_the_flag(extra, flag, tmp_path, capsys):
    out = tmp_path / "figs"
    code = main(["plot", str(GALLERY / "kneed_walk.h5"), "--out", str(out), *extra])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and flag in err
    assert not out.exists()


def test_plot_file_checks_format_and_dpi_before_reading(tmp_path):
    with pytest.raises(ValueError, match="`fmt` must be one of png, pdf, svg"):
        gallery.plot_file(tmp_path / "missing.h5", tmp_path, fmt="jpg")
    with pytest.raises(ValueError, match=r"`dpi` must be an integer in \[1, 2400\]"):
        gallery.plot_file(tmp_path / "missing.h5", tmp_path, dpi=72.5)


def test_the_other_figure_kinds_have_units_on_every_axis():
    """The figures drawn from plain arrays: zero dynamics, work-precision, orbit diagram,
    the animation's frame and a run's angles and phase portrait from a Trajectory."""
    from walker.results import OrbitDiagram, Trajectory

    theta = np.linspace(-0.2, 0.2, 30)
    figs = {
        "zero_dynamics": plotting.plot_zero_dynamics(
            theta, 1.0 + theta**2, theta_plus=-0.2, theta_minus=0.2
        ),
        "work_precision": plotting.plot_work_precision(
            {"DOP853": (np.array([1e-6, 1e-9]), np.array([0.01, 0.02]))}
        ),
        "orbit_diagram": plotting.plot_orbit_diagram(
            OrbitDiagram("slope", np.linspace(0.01, 0.02, 4), np.ones((4, 3))),
            parameter_unit="rad",
        ),
    }
    anim = plotting.animate_walker(
        np.zeros((2, 3, 2)) + np.arange(3)[None, :, None], ((0, 1), (1, 2))
    )
    anim._draw_was_started = True  # not rendered: only its axes are checked
    figs["animation"] = anim._fig
    t = np.linspace(0.0, 1.0, 20)
    traj = Trajectory(t, np.stack([t, -t, np.ones(20), -np.ones(20)], axis=1), np.zeros(20, int))
    figs["angles"] = plotting.plot_angles(traj, state_names=["q1", "q2", "qd1", "qd2"])
    figs["phase_portrait"] = plotting.plot_phase_portrait(
        traj, 0, 2, state_names=["q1", "q2", "qd1", "qd2"]
    )
    for name, fig in figs.items():
        labels = _unit_labels_ok(fig)
        assert len(labels) >= 2, name
    assert _unit_labels_ok(figs["zero_dynamics"]) == [
        "phase variable theta [rad]",
        "theta_dot [rad/s]",
    ]
    _legends_off_the_data(figs["zero_dynamics"])
    _legends_off_the_data(figs["angles"])
