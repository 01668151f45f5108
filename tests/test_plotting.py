"""Plot functions: each returns a Figure with the expected axes, labels and artists."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.collections import (  # noqa: E402
    LineCollection,
    PathCollection,
    PolyCollection,
    QuadMesh,
)
from matplotlib.figure import Figure  # noqa: E402

from walker import plotting  # noqa: E402
from walker.results import (  # noqa: E402
    BASIN_CONVERGED,
    BASIN_UNDECIDED,
    BasinMap,
    Bifurcation,
    Branch,
    EventLog,
    FixedPoint,
    OrbitDiagram,
    Solution,
    Trajectory,
)
from walker.status import Status  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _two_stride_solution():
    """Two swing phases of a 4-state walker separated by one impact at t = 1."""
    t = np.r_[np.linspace(0.0, 1.0, 30), np.linspace(1.0, 2.0, 30)]
    x = np.stack([np.cos(t), np.sin(t), -np.sin(t), np.cos(t)], axis=1)
    phase = np.r_[np.zeros(30, int), np.ones(30, int)]
    events = EventLog(
        t=np.array([1.0]),
        guard=np.array([0]),
        phase_before=np.array([0]),
        phase_after=np.array([1]),
        x_pre=x[29:30],
        x_post=x[30:31],
        impulse=np.zeros((1, 2)),
    )
    return Solution(
        status=Status.COMPLETED,
        message="",
        success=True,
        t=2.0,
        x=x[-1],
        phase=1,
        events=events,
        record=Trajectory(t, x, phase),
        phase_names=("unlocked", "locked"),
    )


def _branch():
    param = np.linspace(0.001, 0.019, 10)
    stable = param < 0.015
    mult = np.stack([np.linspace(-0.3, -1.3, 10) + 0j, np.full(10, 0.2 + 0.1j)], axis=1)
    sections = np.stack([param ** (1 / 3), -(param ** (1 / 3))], axis=1)
    bif = Bifurcation("period_doubling", 0.015, np.array([0.246, -0.246]), mult[7])
    return Branch(
        "slope", param, sections, np.ones(10), mult, stable, [bif], Status.COMPLETED, "", True
    )


def _line_labels(ax):
    return [ln.get_label() for ln in ax.get_lines()]


def test_plot_angles_from_solution():
    sol = _two_stride_solution()
    fig = plotting.plot_angles(sol, state_names=["q1", "q2", "dq1", "dq2"])
    assert isinstance(fig, Figure) and len(fig.axes) == 2
    ax_q, ax_v = fig.axes
    # two coordinate lines, one collection of shaded spans and one of event lines per axes
    assert _line_labels(ax_q) == ["q1", "q2"] and _line_labels(ax_v) == ["dq1", "dq2"]
    for ax in (ax_q, ax_v):
        bands, events = ax.collections
        assert isinstance(bands, PolyCollection) and isinstance(events, LineCollection)
        (event,) = events.get_segments()
        assert event[0, 0] == event[1, 0] == 1.0
        # one shaded span per phase run: [0, 1) unlocked, [1, end] locked
        spans = [path.vertices[:, 0] for path in bands.get_paths()]
        assert [(min(x), max(x)) for x in spans] == [(0.0, 1.0), (1.0, float(sol.record.t[-1]))]
    legend = [tx.get_text() for tx in ax_q.get_legend().get_texts()]
    assert legend == ["q1", "q2", "unlocked", "locked"]
    assert ax_q.get_ylabel() == "angle [rad]" and ax_v.get_xlabel() == "time [s]"
    np.testing.assert_array_equal(ax_v.get_lines()[0].get_ydata(), sol.record.x[:, 2])


def test_plot_angles_trajectory_and_errors():
    sol = _two_stride_solution()
    fig = plotting.plot_angles(sol.record)  # no events, default names
    assert [len(a.get_lines()) for a in fig.axes] == [2, 2]
    assert [len(a.collections) for a in fig.axes] == [1, 1]  # the spans, no events
    assert _line_labels(fig.axes[0]) == ["x[0]", "x[1]"]
    with pytest.raises(ValueError, match="`state_names` must have 4 entries"):
        plotting.plot_angles(sol, state_names=["a"])
    bare = Solution(Status.COMPLETED, "", True, 0.0, np.zeros(4), 0)
    with pytest.raises(ValueError, match="neither `record` nor `samples`"):
        plotting.plot_angles(bare)


def test_plot_angles_on_given_axes():
    fig, axes = plt.subplots(2, 1)
    out = plotting.plot_angles(_two_stride_solution(), ax=axes)
    assert out is fig and len(fig.axes) == 2


def test_plot_phase_portrait():
    sol = _two_stride_solution()
    fp = np.array([0.5, 0.2, -0.1, 0.9])
    fig = plotting.plot_phase_portrait(
        sol.record, 0, 2, fixed_point=fp, state_names=["q1", "q2", "dq1", "dq2"]
    )
    ax = fig.axes[0]
    assert len(fig.axes) == 1
    assert len(ax.get_lines()) == 2  # the orbit (broken between phases) + the fixed point
    assert np.isnan(ax.get_lines()[0].get_xdata()).sum() == 1  # two phase pieces
    assert ax.get_lines()[-1].get_xdata()[0] == 0.5 and ax.get_lines()[-1].get_ydata()[0] == -0.1
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("q1 [rad]", "dq1 [rad/s]")
    with pytest.raises(ValueError, match=r"`j` must be a state index in \[0, 4\)"):
        plotting.plot_phase_portrait(sol, 0, 4)


def test_plot_energy_marks_impact_losses():
    # before/after samples at each impact time: total drops by 0.3 at t=1 and 0.2 at t=2
    t = np.array([0.0, 0.5, 1.0, 1.0, 1.5, 2.0, 2.0, 2.5])
    total = np.array([1.0, 1.0, 1.0, 0.7, 0.7, 0.7, 0.5, 0.5])
    potential = 0.3 * np.sin(t)
    fig = plotting.plot_energy(t, total - potential, potential, event_times=[1.0, 2.0])
    ax = fig.axes[0]
    assert _line_labels(ax) == ["kinetic", "potential", "total"]
    (drops,) = [c for c in ax.collections if isinstance(c, LineCollection)]
    segs = drops.get_segments()
    assert len(segs) == 2
    np.testing.assert_allclose(
        [s[:, 1] for s in segs], [[0.7, 1.0], [0.5, 0.7]], rtol=0, atol=1e-12
    )
    assert [tx.get_text() for tx in ax.texts] == ["-0.3 J", "-0.2 J"]
    fig2 = plotting.plot_energy(t, total, 0 * t)
    assert not fig2.axes[0].collections
    with pytest.raises(ValueError, match="1-D of equal length"):
        plotting.plot_energy(t, total[:3], potential)


def test_plot_multipliers():
    fig = plotting.plot_multipliers(_branch())
    assert len(fig.axes) == 2  # the plot and its colorbar
    ax = fig.axes[0]
    (sc,) = [c for c in ax.collections if isinstance(c, PathCollection)]
    assert sc.get_offsets().shape == (20, 2)
    np.testing.assert_allclose(sc.get_array(), np.repeat(_branch().parameter, 2), rtol=0, atol=0)
    (circle,) = ax.get_lines()
    np.testing.assert_allclose(
        np.hypot(circle.get_xdata(), circle.get_ydata()), 1.0, rtol=0, atol=1e-12
    )
    assert fig.axes[1].get_ylabel() == "slope"


def test_plot_bifurcation():
    fig = plotting.plot_bifurcation(_branch(), coordinate=0, parameter_unit="rad")
    ax = fig.axes[0]
    lines = ax.get_lines()
    assert len(lines) == 3  # stable run, unstable run, bifurcation markers
    assert lines[0].get_linestyle() == "-" and lines[1].get_linestyle() == "--"
    assert lines[0].get_xdata()[-1] == lines[1].get_xdata()[0]  # runs are joined
    assert [tx.get_text() for tx in ax.texts] == ["PD"]
    assert ax.get_xlabel() == "slope [rad]"
    assert ax.get_ylabel() == "section coordinate 0 just after heel strike [rad]"
    with pytest.raises(ValueError, match=r"`coordinate` must be in \[0, 2\)"):
        plotting.plot_bifurcation(_branch(), coordinate=2)


def test_plot_orbit_diagram():
    values = np.tile([[0.2, 0.3, 0.2, 0.3]], (6, 1))
    values[5] = np.nan
    fig = plotting.plot_orbit_diagram(
        OrbitDiagram("slope", np.linspace(0.01, 0.02, 6), values), parameter_unit="rad"
    )
    (sc,) = fig.axes[0].collections
    assert sc.get_offsets().shape == (20, 2)  # NaN row dropped
    assert fig.axes[0].get_xlabel() == "slope [rad]"
    assert fig.axes[0].get_ylabel() == "section coordinate 0 just after heel strike [rad]"


def basin_map(axis_names, x, y, outcome, fixed_point, n_strides):
    """A :class:`BasinMap` of ``outcome`` on the grid ``x`` by ``y`` whose points took no
    strides, with the fixed point ``fixed_point`` also its base state."""
    strides = np.zeros(outcome.shape, int)
    return BasinMap(axis_names, x, y, outcome, strides, fixed_point, fixed_point.copy(), n_strides)


def test_plot_basin():
    outcome = np.array(
        [
            [BASIN_CONVERGED, BASIN_CONVERGED, int(Status.FELL_BACKWARD)],
            [BASIN_UNDECIDED, BASIN_CONVERGED, int(Status.FELL_FORWARD)],
        ]
    )
    basin = basin_map(
        ("theta", "theta_dot"),
        np.linspace(0.15, 0.25, 3),
        np.linspace(-0.25, -0.15, 2),
        outcome,
        np.array([0.2, -0.2]),
        50,
    )
    fig = plotting.plot_basin(basin, outcome_names={int(Status.FELL_FORWARD): "forward"})
    ax = fig.axes[0]
    assert len(fig.axes) == 1
    (mesh,) = [c for c in ax.collections if isinstance(c, QuadMesh)]
    assert mesh.get_array().shape == (2, 3)
    legend = [tx.get_text() for tx in ax.get_legend().get_texts()]
    assert legend == [
        "undecided after 50 strides (1)",
        "converged (3)",
        "fell backward (1)",
        "forward (1)",
        "fixed point",
    ]
    (star,) = ax.get_lines()
    assert (star.get_xdata()[0], star.get_ydata()[0]) == (0.2, -0.2)
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("theta [rad]", "theta_dot [rad/s]")


def test_plot_work_precision():
    table = {
        "dop853": (np.array([1e-6, 1e-9, 1e-12]), np.array([1e-4, 2e-4, 4e-4])),
        "rk45": (np.array([1e-5, 1e-8]), np.array([2e-4, 9e-4])),
    }
    fig = plotting.plot_work_precision(table)
    ax = fig.axes[0]
    assert _line_labels(ax) == ["dop853", "rk45"]
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    with pytest.raises(ValueError, match=r"`table\['x'\]` must hold 1-D errors and times"):
        plotting.plot_work_precision({"x": ([1, 2], [1])})


def test_plots_accept_fixed_point_object():
    fp = FixedPoint(
        Status.COMPLETED,
        "",
        True,
        np.zeros(2),
        np.array([0.5, 0.2, -0.1, 0.9]),
        1.0,
        np.zeros(2, complex),
        np.zeros((2, 2), complex),
        np.zeros((2, 2)),
        0.0,
        0,
        np.zeros(1),
    )
    fig = plotting.plot_phase_portrait(_two_stride_solution(), 0, 2, fixed_point=fp)
    assert fig.axes[0].get_lines()[-1].get_xdata()[0] == 0.5


def _compass_frames(n_frames=12):
    """Stance foot at the origin, hip swinging over it, swing foot on a circle."""
    angle = np.linspace(0.3, -0.3, n_frames)
    hip = np.stack([-np.sin(angle), np.cos(angle)], axis=1)
    swing = hip + np.stack([np.sin(-angle), -np.cos(angle)], axis=1)
    foot = np.zeros_like(hip)
    return np.stack([foot, hip, swing], axis=1)


@pytest.mark.slow  # an animation: the integration tier
def test_animate_walker_gif(tmp_path):
    from PIL import Image

    frames = _compass_frames(12)
    path = tmp_path / "walk.gif"
    anim = plotting.animate_walker(frames, [(0, 1), (1, 2)], slope=0.05, interval_ms=50, path=path)
    assert path.stat().st_size > 0
    with Image.open(path) as im:
        assert im.n_frames == 12
        assert im.info["duration"] == 50
    ax = anim._fig.axes[0]
    assert len(ax.get_lines()) == 4  # ground, two links, joints
    np.testing.assert_allclose(
        ax.get_lines()[2].get_xydata(), frames[-1][[1, 2]], rtol=0, atol=1e-15
    )


def test_animate_walker_errors(tmp_path):
    frames = _compass_frames(3)
    with pytest.raises(ValueError, match=r"`frames` must have shape \(n_frames, n_points, 2\)"):
        plotting.animate_walker(frames[:, :, :1], [(0, 1)])
    with pytest.raises(ValueError, match=r"`segments` must be pairs"):
        plotting.animate_walker(frames, [(0, 3)])
    with pytest.raises(ValueError, match=r"`path` must end in .gif or .mp4"):
        plotting.animate_walker(frames, [(0, 1)], path=tmp_path / "a.avi")
    if not matplotlib.animation.writers.is_available("ffmpeg"):
        with pytest.raises(ValueError, match="ffmpeg is not available"):
            plotting.animate_walker(frames, [(0, 1)], path=tmp_path / "a.mp4")
    assert list(tmp_path.iterdir()) == []


def test_plot_torques_draws_each_actuator_and_the_limit():
    t = np.linspace(0.0, 1.0, 50)
    u = np.column_stack([np.sin(t), np.cos(t)])
    fig = plotting.plot_torques(t, u, names=["hip", "knee"], limit=2.0, event_times=[0.5])
    ax = fig.axes[0]
    labels = [line.get_label() for line in ax.get_lines()]
    assert "hip" in labels and "knee" in labels
    assert ax.get_ylabel() == "torque [N m]"
    assert len(ax.get_lines()) == 2 + 2  # actuators, +-limit
    ((impact,),) = [c.get_segments() for c in ax.collections]  # one impact line
    assert impact[0, 0] == impact[1, 0] == 0.5
    with pytest.raises(ValueError, match="one row per time"):
        plotting.plot_torques(t, u[:10])


def test_plot_zero_dynamics_breaks_the_line_at_impacts():
    theta = np.concatenate([np.linspace(0.4, -0.4, 30), np.linspace(0.4, -0.4, 30)])
    theta_dot = -1.0 - 0.1 * theta
    fig = plotting.plot_zero_dynamics(theta, theta_dot, theta_plus=0.4, theta_minus=-0.4)
    line = fig.axes[0].get_lines()[0]
    x = np.asarray(line.get_xdata(), dtype=float)
    assert np.isnan(x).sum() == 1  # one impact, one break
    assert len(fig.axes[0].get_lines()) == 3


def test_files_from_before_joint_friction_still_plot(tmp_path):
    """A file whose stored parameters lack a joint-friction field added later (here the
    kneed walker's `damping_ankle`) reads it as 0, with a warning naming it; any other
    missing parameter is still an error."""
    from walker.cli import provenance
    from walker.plotting.gallery import plot_file
    from walker.scene import load_scene
    from walker.simulation.stride import simulate
    from walker.storage import write

    scene = load_scene("gaits/kneed_hsu.toml")
    sol = simulate("kneed", scene.params, scene.state, output="full")
    prov = provenance(scene)
    del prov["parameters"]["damping_ankle"]
    old = write(tmp_path / "old.h5", sol, provenance=prov)
    with pytest.warns(UserWarning, match=r"predate `damping_ankle`: read as 0"):
        paths = plot_file(old, tmp_path)
    assert paths
    del prov["parameters"]["mass_hip"]
    bad = write(tmp_path / "bad.h5", sol, provenance=prov)
    with (
        pytest.warns(UserWarning, match="damping_ankle"),
        pytest.raises(ValueError, match="missing KneedParams key\\(s\\) `mass_hip`"),
    ):
        plot_file(bad, tmp_path)
