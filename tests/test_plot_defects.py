"""The plot defects of issue 14, each checked on the figure's own labels, numbers and styles.

Every test here failed before its fix: sweep plots that said "value" and "section[j]" and
drew unfinished points as failures, a two-parameter sweep collapsed onto one axis, axes
without units, impact labels read off the samples (three-link: -15/-15.1 J and a "+0"
where the events give -14.868 J), a colour bar without meaning, "slip+" in a frictionless
walker's legend, theta+ and theta- drawn alike, a work-precision legend over the data with
an undefined "error", the GIF always rendered, and "outcome -3" in a basin legend.
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.collections import LineCollection, QuadMesh  # noqa: E402
from numpy.testing import assert_allclose, assert_array_equal  # noqa: E402
from test_plotting import basin_map  # noqa: E402

from walker import plotting  # noqa: E402
from walker.cli import main  # noqa: E402
from walker.plotting import gallery  # noqa: E402
from walker.results import Branch, SweepTable  # noqa: E402
from walker.status import Status  # noqa: E402
from walker.storage import BASIN_NOT_COMPUTED, read  # noqa: E402

COMPASS_SECTION = ("q_stance", "qd_stance", "qd_swing")


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _labels(ax):
    return [line.get_label() for line in ax.get_lines()]


def _legend(ax):
    legend = ax.get_legend()
    return [] if legend is None else [t.get_text() for t in legend.get_texts()]


def _drawn(result_path, out_dir, monkeypatch, **options):
    """The figures `walker plot` draws for a stored result, by name (``kneed_energy.png``
    -> ``"energy"``), caught before they are saved."""
    figures = {}
    stem = Path(result_path).stem

    def keep(fig, path):
        figures[Path(path).stem[len(stem) + 1 :]] = fig
        return Path(path)

    monkeypatch.setattr(gallery, "_save", keep)
    gallery.plot_file(result_path, out_dir, **options)
    return figures


def _fixed_point_table(points, names=("slope",), status=None):
    """A fixed-point sweep table of the compass walker's shape with known numbers: point i
    has section (i, -i, 10 i), step time 0.5 + i, multipliers (0.1 i, -0.2 i, 0.3 + 0.4i)
    (largest modulus max(0.5, 0.2 i)); rows with status -1 hold the fill values."""
    points = np.asarray(points, dtype=float).reshape(len(points), -1)
    n = points.shape[0]
    i = np.arange(n, dtype=float)
    status = np.zeros(n, dtype=np.int64) if status is None else np.asarray(status, np.int64)
    mult = np.stack([0.1 * i + 0j, -0.2 * i + 0j, np.full(n, 0.3 + 0.4j)], axis=1)
    cols = {
        "status": status,
        "section": np.stack([i, -i, 10 * i], axis=1),
        "step_time": 0.5 + i,
        "multipliers_re": mult.real.copy(),
        "multipliers_im": mult.imag.copy(),
        "residual": np.full(n, 1e-13),
        "stable": (np.abs(mult).max(axis=1) < 1).astype(np.int64),
        "n_iter": np.full(n, 3),
    }
    missing = status == -1
    for key in ("section", "step_time", "multipliers_re", "multipliers_im", "residual"):
        cols[key][missing] = np.nan
    for key in ("stable", "n_iter"):
        cols[key][missing] = -1
    failed = (status > 0) & ~missing
    for key in ("section", "step_time", "multipliers_re", "multipliers_im"):
        cols[key][failed] = np.nan
    return SweepTable(tuple(names), points, cols)


# -- sweep: names, units and quantities against the parameter ---------------------------------


def test_sweep_plots_named_quantities_with_units_against_the_parameter():
    table = _fixed_point_table(np.linspace(0.01, 0.05, 5)[:, None])
    fig = plotting.plot_sweep(table, parameter_units=["rad"], section_names=COMPASS_SECTION)
    axes = fig.axes
    assert [ax.get_ylabel() for ax in axes] == [
        "status",
        "step time [s]",
        "largest |multiplier| [1]",
        "gait at heel strike [rad]",
        "gait at heel strike [rad/s]",
    ]
    assert axes[-1].get_xlabel() == "slope [rad]"
    for ax in axes:  # nothing is called "value" or "section[j]" any more
        assert ax.get_ylabel() != "value"
        assert not any(lab.startswith("section[") for lab in _labels(ax) + _legend(ax))
    # the section coordinates: one series per coordinate, named with its unit, in the panel
    # of its unit
    assert _legend(axes[3]) == ["q_stance [rad]"]
    assert _legend(axes[4]) == ["qd_stance [rad/s]", "qd_swing [rad/s]"]
    x = table.points[:, 0]
    (q,) = [ln for ln in axes[3].get_lines() if ln.get_label() == "q_stance [rad]"]
    assert_allclose(q.get_xdata(), x, rtol=0, atol=0)
    assert_allclose(q.get_ydata(), table.columns["section"][:, 0], rtol=0, atol=0)
    # step time and the largest |multiplier| (unit-circle limit drawn at 1)
    assert_allclose(axes[1].get_lines()[0].get_ydata(), 0.5 + np.arange(5), rtol=0, atol=0)
    largest = [ln for ln in axes[2].get_lines() if len(ln.get_xdata()) == 5]
    assert_allclose(
        np.sort(np.concatenate([ln.get_ydata() for ln in largest])),
        [0.5, 0.5, 0.5, 0.6, 0.8],
        rtol=0,
        atol=1e-15,
    )
    assert "1 (stability limit)" in _legend(axes[2])
    # status as a category
    assert [t.get_text() for t in axes[0].get_yticklabels()] == ["converged"]


def test_sweep_file_takes_units_and_section_names_from_its_provenance(tmp_path, monkeypatch):
    from walker import StrideMap, load_scene
    from walker.analysis.sweep import sweep

    scene = load_scene("gaits/simplest_garcia.toml")
    P = StrideMap("simplest", scene.params, rtol=1e-10, atol=1e-12)
    path = tmp_path / "sweep.h5"
    sweep(
        P,
        ["slope=0.008:0.010:3"],
        kind="fixed_point",
        z0=P.project(scene.state),
        executor="serial",
        progress=False,
        out=path,
    )
    fig = _drawn(path, tmp_path, monkeypatch)["sweep"]
    assert fig.axes[-1].get_xlabel() == "slope [rad]"
    legends = [t for ax in fig.axes for t in _legend(ax)]
    assert "theta [rad]" in legends and "theta_dot [rad/s]" in legends


# -- sweep: points not computed yet ----------------------------------------------------------


def test_unfinished_sweep_points_are_not_computed_not_failed():
    status = [0, 0, int(Status.NO_GAIT_NEAR_GUESS), -1, -1]
    table = _fixed_point_table(np.linspace(0.01, 0.05, 5)[:, None], status=status)
    fig = plotting.plot_sweep(table, parameter_units=["rad"], section_names=COMPASS_SECTION)
    ax = fig.axes[0]
    by_label = {ln.get_label(): ln for ln in ax.get_lines()}
    assert set(by_label) == {"not computed", "converged", "no gait near guess"}
    assert "failed" not in by_label
    assert_allclose(by_label["not computed"].get_xdata(), [0.04, 0.05], rtol=0, atol=1e-15)
    assert ax.get_title() == "5 points: 2 converged, 1 failed, 2 not computed"
    # the other panels draw the converged points only
    for other in fig.axes[1:]:
        xs = [ln.get_xdata() for ln in other.get_lines() if not ln.get_label().startswith("1 (")]
        assert_allclose(np.unique(np.concatenate(xs)), [0.01, 0.02], rtol=0, atol=1e-15)


def test_half_done_sweep_checkpoint_file(tmp_path, monkeypatch):
    """A real checkpoint with one chunk of two written: its other rows are 'not computed'."""
    from walker.storage import SweepStore

    done = _fixed_point_table(np.linspace(0.01, 0.04, 4)[:, None])
    columns = {
        name: (values.dtype.str[1:], values.shape[1:]) for name, values in done.columns.items()
    }
    store = SweepStore.create_or_open(
        tmp_path / "half.h5",
        parameter_names=("slope",),
        points=done.points,
        columns=columns,
        chunk_size=2,
        provenance={"model": "compass", "sweep_kind": "fixed_point", "n_strides": 1},
    )
    store.write_chunk(0, {name: values[:2] for name, values in done.columns.items()})
    fig = _drawn(store.path, tmp_path, monkeypatch)["sweep"]
    by_label = {ln.get_label(): ln for ln in fig.axes[0].get_lines()}
    assert_allclose(by_label["not computed"].get_xdata(), [0.03, 0.04], rtol=0, atol=1e-15)
    assert "2 not computed" in fig.axes[0].get_title()
    assert fig.axes[-1].get_xlabel() == "slope [rad]"  # unit from the model's metadata


# -- sweep: two parameters as heat maps -------------------------------------------------------


def test_two_parameter_sweep_is_a_heat_map():
    slopes, masses = np.array([0.01, 0.02, 0.03]), np.array([5.0, 10.0])
    points = np.array([(s, m) for s in slopes for m in masses])  # last varies fastest
    status = [0, 0, 0, 0, 0, -1]
    table = _fixed_point_table(points, names=("slope", "mass_hip"), status=status)
    fig = plotting.plot_sweep(table, parameter_units=["rad", "kg"])
    maps = [ax for ax in fig.axes if ax.get_title()]  # the colour bars have no title
    assert [ax.get_title() for ax in maps] == [
        "status",
        "step time [s]",
        "largest |multiplier| [1]",
    ]
    for ax in maps:
        assert any(isinstance(c, QuadMesh) for c in ax.collections)
        assert (ax.get_xlabel(), maps[0].get_ylabel()) == ("slope [rad]", "mass_hip [kg]")
    (mesh,) = [c for c in maps[2].collections if isinstance(c, QuadMesh)]
    grid = np.ma.filled(mesh.get_array().reshape(2, 3).astype(float), np.nan)
    # rows: mass_hip (y), columns: slope (x); point i = (slope[i // 2], mass[i % 2])
    expected = np.array([[0.5, 0.5, 0.8], [0.5, 0.6, np.nan]])
    assert_allclose(grid, expected, rtol=0, atol=1e-15)
    legend = _legend(maps[0])
    assert legend == ["not computed (1)", "converged (5)"]
    assert "1 not computed" in fig.get_suptitle()
    colorbars = [ax.get_ylabel() for ax in fig.axes if ax not in maps]
    assert colorbars == ["step time [s]", "largest |multiplier| [1]"]


# -- units on every axis ----------------------------------------------------------------------


def test_state_units_from_names():
    assert [plotting.state_unit(n) for n in ("q_stance", "qd_swing", "theta_dot", "q1")] == [
        "rad",
        "rad/s",
        "rad/s",
        "rad",
    ]
    assert plotting.state_unit("actuator_work") == "J"


def _compass_basin(outcome):
    """A compass gait's basin of ``outcome`` on a 3 x 2 grid of (q_stance, qd_stance)."""
    x, y = np.linspace(0.1, 0.3, 3), np.linspace(-1.5, -0.5, 2)
    return basin_map(("q_stance", "qd_stance"), x, y, outcome, np.array([0.2, -1.0, -0.3]), 20)


def test_basin_and_multiplier_axes_carry_units():
    basin = _compass_basin(np.full((2, 3), -1))
    ax = plotting.plot_basin(basin).axes[0]
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("q_stance [rad]", "qd_stance [rad/s]")
    fig = plotting.plot_multipliers(_branch(), parameter_unit="rad")
    assert fig.axes[0].get_xlabel() == "Re(multiplier) [1]"
    assert fig.axes[1].get_ylabel() == "slope [rad]"


# -- a run's figures: the three-link walker -----------------------------------------------


@pytest.fixture(scope="module")
def three_link_run(tmp_path_factory):
    """Three strides of gaits/three_link_grizzle.toml sampled at 300 Hz, as `walker run
    --sample-rate 300` stores them (the samples miss the impact instants)."""
    path = tmp_path_factory.mktemp("three_link") / "run.h5"
    argv = ["run", "gaits/three_link_grizzle.toml", "--strides", "3", "--sample-rate", "300"]
    code = main([*argv, "--out", str(path)])
    assert code == 0
    sol, prov = read(path)
    model, params = gallery._params_from_provenance(prov)
    with pytest.MonkeyPatch.context() as monkeypatch:
        figures = _drawn(path, path.parent, monkeypatch)
    return sol, model, params, figures


@pytest.mark.regression_pin
def test_three_link_impact_labels_are_the_event_losses(three_link_run):
    """REGRESSION PIN: the impact loss -14.86789 J is walker's own; the labels and jump lengths
    are checked against the event log.
    """
    sol, model, params, figures = three_link_run
    ax = figures["energy"].axes[0]
    events = sol.events
    assert len(events) == 3
    kin_pre, _ = model.energies(np.asarray(events.x_pre), params)
    kin_post, _ = model.energies(np.asarray(events.x_post), params)
    loss = kin_post - kin_pre  # the configuration is continuous: all of it is kinetic
    assert_allclose(loss, -14.86789, rtol=0, atol=1e-5)
    # one label per impact, the event's loss; no "+0" where nothing happens
    assert [t.get_text() for t in ax.texts] == ["-14.868 J"] * 3
    (jumps,) = [c for c in ax.collections if isinstance(c, LineCollection)]
    lengths = [np.ptp(seg[:, 1]) for seg in jumps.get_segments()]
    assert_allclose(lengths, -loss, rtol=1e-12, atol=0)
    assert_allclose([seg[0, 0] for seg in jumps.get_segments()], events.t, rtol=0, atol=0)


def test_three_link_figures_have_units_and_no_friction_modes(three_link_run):
    _, model, params, figures = three_link_run
    assert params.coulomb_hip == 0.0
    assert set(figures) == {"angles", "energy", "phase_portrait", "torques", "zero_dynamics"}
    for name, fig in figures.items():
        for ax in fig.axes:
            for label in (ax.get_xlabel(), ax.get_ylabel()):
                if label:
                    assert label.endswith("]") and "[" in label, (name, label)
    ax = figures["phase_portrait"].axes[0]
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("q_stance [rad]", "qd_stance [rad/s]")
    # a frictionless walker: its one phase, without stick/slip modes
    legend = _legend(figures["angles"].axes[0])
    assert legend == ["q_stance", "q_swing", "q_torso", "stance"]
    assert not any("slip" in t or "stick" in t for t in legend)


def test_friction_modes_shown_only_for_joints_with_dry_friction():
    from walker.models import get_model
    from walker.params import CompassCoulombParams

    model = get_model("compass_coulomb")
    ankle_only = CompassCoulombParams.goswami().replace(coulomb_ankle=1.0, coulomb_hip=0.0)
    labels = gallery.phase_labels(model, ankle_only)
    assert labels[model.phase_names.index("swing ankle=stick hip=slip-")] == "swing ankle=stick"
    assert not any("hip" in lab for lab in labels)
    both = ankle_only.replace(coulomb_hip=0.5)
    assert gallery.phase_labels(model, both) == list(model.phase_names)
    none = ankle_only.replace(coulomb_ankle=0.0)
    assert set(gallery.phase_labels(model, none)) == {"swing"}


# -- impact losses: physics of the labels --------------------------------------------------


def test_rimless_wheel_impact_label_is_the_closed_form_loss(tmp_path, monkeypatch):
    """Each impact of the rimless wheel keeps cos(2 alpha) of the rate: it loses
    (1 - cos^2(2 alpha)) l^2 theta_dot-^2 / 2 per unit hub mass (McGeer 1990)."""
    path = tmp_path / "wheel.h5"
    assert main(["run", "gaits/rimless_wheel.toml", "--strides", "2", "--out", str(path)]) == 0
    sol, prov = read(path)
    model, params = gallery._params_from_provenance(prov)
    ax = _drawn(path, tmp_path, monkeypatch)["energy"].axes[0]
    alpha = math.pi / params.spokes
    rate = np.asarray(sol.events.x_pre)[:, 1]
    expected = -0.5 * params.leg_length**2 * rate**2 * (1 - math.cos(2 * alpha) ** 2)
    (jumps,) = [c for c in ax.collections if isinstance(c, LineCollection)]
    assert_allclose([-np.ptp(s[:, 1]) for s in jumps.get_segments()], expected, rtol=1e-12)
    assert [t.get_text() for t in ax.texts] == [f"{e:+.5g} J/kg" for e in expected]
    assert ax.get_ylabel() == "energy [J/kg]"


def test_world_potential_is_continuous_across_every_event(tmp_path):
    """Knee lock and heel strike of the kneed walker: the energy jump at each event, from its
    pre/post states with the potential referred to the first stance foot, is all kinetic."""
    path = tmp_path / "kneed.h5"
    assert main(["run", "gaits/kneed_hsu.toml", "--strides", "2", "--out", str(path)]) == 0
    sol, prov = read(path)
    model, params = gallery._params_from_provenance(prov)
    events = sol.events
    steps = gallery._foot_steps(model, params, events)
    names = [model.guard_names[g] for g in events.guard]
    assert [s is not None for s in steps] == [n == "swing_foot_contact" for n in names]
    energies = gallery._event_energies(model, params, events)
    kin_pre, _ = model.energies(np.asarray(events.x_pre), params)
    kin_post, _ = model.energies(np.asarray(events.x_post), params)
    assert_allclose(energies[:, 1] - energies[:, 0], kin_post - kin_pre, rtol=0, atol=1e-12)
    assert np.all(kin_post < kin_pre)  # every impact loses energy


# -- multipliers: the colour bar ------------------------------------------------------------


def _branch(n=10):
    param = np.linspace(0.001, 0.019, n)
    mult = np.stack([np.linspace(-0.3, -1.3, n) + 0j, np.full(n, 0.2 + 0.1j)], axis=1)
    sections = np.stack([param, -param], axis=1)
    return Branch(
        "slope", param, sections, np.ones(n), mult, param < 0.015, [], Status.COMPLETED, "", True
    )


@pytest.mark.regression_pin
def test_multipliers_of_one_gait_have_no_colour_bar(tmp_path, monkeypatch):
    """REGRESSION PIN: the largest multiplier modulus 0.6554 of Hsu Chen's gait is walker's own
    (gaits/kneed_hsu.toml [reference]).
    """
    path = tmp_path / "gait.h5"
    assert main(["find", "gaits/kneed_hsu.toml", "--out", str(path)]) == 0
    gait, _ = read(path)
    fig = _drawn(path, tmp_path, monkeypatch)["multipliers"]
    assert len(fig.axes) == 1  # no colour bar over a single, meaningless value
    largest = np.max(np.abs(gait.multipliers))
    assert_allclose(largest, 0.6554, rtol=0, atol=1e-4)
    assert _legend(fig.axes[0])[-1] == f"multipliers, largest |.| = {largest:.4g}"


def test_multipliers_along_a_branch_have_a_labelled_colour_bar():
    fig = plotting.plot_multipliers(_branch(), parameter_unit="rad")
    assert len(fig.axes) == 2 and fig.axes[1].get_ylabel() == "slope [rad]"


# -- zero dynamics ---------------------------------------------------------------------------


def test_zero_dynamics_draws_theta_plus_and_minus_apart():
    theta = np.linspace(0.4, -0.4, 30)
    fig = plotting.plot_zero_dynamics(theta, -1 - 0.1 * theta, theta_plus=0.4, theta_minus=-0.4)
    orbit, plus, minus = fig.axes[0].get_lines()
    assert_array_equal(plus.get_xdata(), [0.4, 0.4])
    assert_array_equal(minus.get_xdata(), [-0.4, -0.4])
    assert plus.get_color() != minus.get_color()
    assert plus.get_linestyle() != minus.get_linestyle()
    assert orbit.get_color() not in (plus.get_color(), minus.get_color())
    assert _legend(fig.axes[0])[1:] == [
        "theta+ = 0.4 rad (step starts)",
        "theta- = -0.4 rad (impact)",
    ]


# -- work-precision ----------------------------------------------------------------------------


def test_work_precision_legend_is_off_the_data_and_error_is_defined():
    table = {
        f"method {k}": (np.logspace(-12, -4, 5) * (k + 1), np.logspace(-4, -3, 5) / (k + 1))
        for k in range(6)
    }
    fig = plotting.plot_work_precision(table)
    ax = fig.axes[0]
    fig.canvas.draw()
    legend_box = ax.get_legend().get_window_extent()
    axes_box = ax.get_window_extent()
    assert legend_box.x0 >= axes_box.x1  # to the right of the axes: hides no curve
    assert _legend(ax) == list(table)
    assert ax.get_xlabel() == plotting.WORK_PRECISION_ERROR
    assert "max-norm" in ax.get_xlabel() and "reference" in ax.get_xlabel()
    custom = plotting.plot_work_precision(table, error_label="error: |dx| [m]")
    assert custom.axes[0].get_xlabel() == "error: |dx| [m]"


# -- walker plot: the animation on request -----------------------------------------------------


@pytest.mark.slow  # an animation: the integration tier
def test_plot_renders_the_animation_only_with_gif(tmp_path, capsys):
    run = tmp_path / "simplest.h5"
    assert main(["run", "gaits/simplest_garcia.toml", "--strides", "1", "--out", str(run)]) == 0
    plain, with_gif = tmp_path / "plain", tmp_path / "gif"
    assert main(["plot", str(run), "--out", str(plain)]) == 0
    assert not list(plain.glob("*.gif"))
    assert {p.name for p in plain.iterdir()} == {
        "simplest_angles.png",
        "simplest_energy.png",
        "simplest_phase_portrait.png",
    }
    assert main(["plot", str(run), "--out", str(with_gif), "--gif"]) == 0
    assert [p.name for p in with_gif.glob("*.gif")] == ["simplest_walk.gif"]
    capsys.readouterr()
    with pytest.raises(SystemExit):
        main(["plot", "--help"])
    help_text = " ".join(capsys.readouterr().out.split())
    assert "--gif" in help_text and "default: off" in help_text


# -- basin: points not computed yet -------------------------------------------------------------


def test_basin_points_not_computed_are_named_so():
    outcome = np.array([[-1, -1, int(Status.FELL_FORWARD)], [BASIN_NOT_COMPUTED] * 3])
    basin = _compass_basin(outcome)
    assert plotting.outcome_label(BASIN_NOT_COMPUTED) == "not computed"
    legend = _legend(plotting.plot_basin(basin, coordinates=(0, 1)).axes[0])
    assert legend == ["not computed (3)", "converged (2)", "fell forward (1)", "fixed point"]
    assert not any("outcome" in t for t in legend)


def test_basin_checkpoint_half_done(tmp_path, monkeypatch):
    """A real basin checkpoint with the first of two row chunks written: the rest is 'not
    computed', and the fixed point is placed by the axes' section coordinates."""
    from walker.storage import BasinStore

    fixed_point = np.array([0.2187, -1.0918, -0.3772])
    store = BasinStore.create_or_open(
        tmp_path / "basin.h5",
        axis_names=("qd_stance", "qd_swing"),
        x=np.linspace(-1.5, -0.5, 3),
        y=np.linspace(-1.0, 0.5, 4),
        fixed_point=fixed_point,
        base=fixed_point,
        n_strides=20,
        tol=1e-6,
        period=1,
        provenance={"model": "compass"},
        chunk_size=2,
    )
    store.write_chunk(0, np.full((2, 3), -1), np.full((2, 3), 5))
    ax = _drawn(store.path, tmp_path, monkeypatch)["basin"].axes[0]
    assert _legend(ax) == ["not computed (6)", "converged (6)", "fixed point"]
    (star,) = ax.get_lines()
    assert (star.get_xdata()[0], star.get_ydata()[0]) == (-1.0918, -0.3772)
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("qd_stance [rad/s]", "qd_swing [rad/s]")
