"""Figures of long runs: the number of artists does not grow with the number of strides, and
the display thinning of a time series keeps every pixel column's smallest and largest value.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from numpy.testing import assert_array_equal  # noqa: E402

from walker import plotting  # noqa: E402
from walker.plotting.longrun import (  # noqa: E402
    DISPLAY_COLUMNS,
    decimate_minmax,
    event_lines,
    thin_curve,
)
from walker.plotting.runs import MAX_JUMP_LABELS  # noqa: E402
from walker.plotting.terrain import plot_run_on_terrain  # noqa: E402
from walker.results import EventLog, Solution, Trajectory  # noqa: E402
from walker.status import Status  # noqa: E402

SAMPLES_PER_STRIDE = 40


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _compass_run(n_strides: int) -> Solution:
    """A compass-gait-like run held in memory: each stride a swing of the stance angle from
    0.2 to -0.2 rad and back through the reset (the legs swap), the record holding the pre-
    and post-reset samples at each heel strike, two phases alternating per stride so that
    every stride is a run of equal phase."""
    s = np.linspace(0.0, 1.0, SAMPLES_PER_STRIDE)
    step_time = 0.7  # [s]
    t = (np.arange(n_strides)[:, None] + s[None, :]).ravel() * step_time
    q_stance = np.tile(0.2 - 0.4 * s, n_strides)
    q_swing = np.tile(-0.2 + 0.4 * s, n_strides)
    x = np.column_stack(
        [q_stance, q_swing, np.full_like(t, -0.57), np.tile(0.3 * np.sin(np.pi * s), n_strides)]
    )
    phase = np.repeat(np.arange(n_strides) % 2, SAMPLES_PER_STRIDE)
    strikes = SAMPLES_PER_STRIDE * np.arange(1, n_strides) - 1  # last sample of each stride
    events = EventLog(
        t=t[strikes],
        guard=np.zeros(strikes.size, int),
        phase_before=phase[strikes],
        phase_after=phase[strikes + 1],
        x_pre=x[strikes],
        x_post=x[strikes + 1],
        impulse=np.zeros((strikes.size, 2)),
    )
    return Solution(
        status=Status.COMPLETED,
        message="",
        success=True,
        t=float(t[-1]),
        x=x[-1],
        phase=int(phase[-1]),
        n_strides=n_strides,
        events=events,
        record=Trajectory(t, x, phase),
        phase_names=("left stance", "right stance"),
    )


def _artists(fig) -> int:
    """Every artist drawn in the figure's axes (lines, collections, patches, texts)."""
    return sum(len(ax.get_children()) for ax in fig.axes)


def _figures(n_strides: int) -> dict:
    sol = _compass_run(n_strides)
    traj = sol.record
    te = sol.events.t
    kinetic = 0.5 * traj.x[:, 2] ** 2
    potential = np.cos(traj.x[:, 0])
    before = kinetic[SAMPLES_PER_STRIDE - 1] + potential[SAMPLES_PER_STRIDE - 1]
    jumps = np.column_stack([np.full(te.size, before), np.full(te.size, before - 0.1)])
    ground = np.zeros((n_strides, 2, 2))
    ground[:, 0, 0] = np.arange(n_strides) * 0.4
    ground[:, 1, 0] = np.arange(1, n_strides + 1) * 0.4
    frames = np.zeros((traj.t.size, 3, 2))
    frames[:, 1] = np.column_stack([np.sin(traj.x[:, 0]), np.cos(traj.x[:, 0])])
    frames[:, 2] = frames[:, 1] + np.column_stack([np.sin(traj.x[:, 1]), -np.cos(traj.x[:, 1])])
    anim = plotting.animate_walker(frames[::997], [(0, 1), (1, 2)], ground=ground)
    anim._draw_was_started = True  # not rendered: only its artists are counted
    return {
        "angles": plotting.plot_angles(sol),
        "energy": plotting.plot_energy(
            traj.t, kinetic, potential, event_times=te, event_energies=jumps
        ),
        "phase_portrait": plotting.plot_phase_portrait(sol, 0, 2),
        "torques": plotting.plot_torques(traj.t, traj.x[:, :2], limit=1.0, event_times=te),
        "zero_dynamics": plotting.plot_zero_dynamics(traj.x[:, 0], traj.x[:, 2]),
        "terrain": plot_run_on_terrain(frames, [(0, 1), (1, 2)], ground),
        "animation": anim._fig,
    }


def test_the_number_of_artists_does_not_grow_with_the_strides():
    """20 strides (under MAX_JUMP_LABELS impacts) and 2,000 strides: every run figure holds
    the same artists but for the energy labels, which become one summary text."""
    assert 20 - 1 < MAX_JUMP_LABELS < 2000 - 1
    short, long = _figures(20), _figures(2000)
    counts = {name: (_artists(short[name]), _artists(long[name])) for name in short}
    for name, (few, many) in counts.items():
        if name == "energy":  # 19 labels, then one text for 1,999 impacts
            assert many == few - (20 - 1) + 1, counts
        else:
            assert many == few, (name, counts)
    (summary,) = long["energy"].axes[0].texts
    assert summary.get_text() == "1999 impacts: -0.1 to -0.1 J"


def test_long_lines_are_thinned_but_keep_their_extremes():
    sol = _compass_run(2000)  # 80,000 samples
    x = sol.record.x.copy()
    fig = plotting.plot_angles(sol)
    assert_array_equal(sol.record.x, x)  # the data are left as they were
    for line, column in zip(fig.axes[0].get_lines(), (0, 1), strict=True):
        shown = np.asarray(line.get_ydata())
        assert shown.size <= 4 * DISPLAY_COLUMNS < x.shape[0]
        assert (shown.min(), shown.max()) == (x[:, column].min(), x[:, column].max())


@pytest.mark.parametrize("columns", [1, 7, 64])
def test_decimation_keeps_each_columns_min_and_max(columns):
    """Each of ``columns`` equal time columns holds, after thinning, the same smallest and
    largest value as the full series (computed column by column from the definition), and
    its first and last sample; the kept samples are a subsequence of the series."""
    rng = np.random.default_rng(3)
    n = 40 * columns + 13
    t = np.sort(rng.uniform(0.0, 5.0, n))
    t[n // 3 : n // 3 + 5] = t[n // 3]  # repeated times (resets)
    y = rng.normal(size=n)
    y[rng.integers(0, n, 5)] = rng.normal(scale=50.0, size=5)  # spikes
    t_in, y_in = t.copy(), y.copy()
    ts, ys = decimate_minmax(t, y, columns=columns)
    assert_array_equal(t, t_in)
    assert_array_equal(y, y_in)
    assert ts.size <= 4 * columns < n
    edges = np.linspace(t[0], t[-1], columns + 1)
    for k in range(columns):
        upper = t <= edges[k + 1] if k == columns - 1 else t < edges[k + 1]
        inside = (t >= edges[k]) & upper
        shown = (ts >= edges[k]) & (ts <= edges[k + 1] if k == columns - 1 else ts < edges[k + 1])
        if not inside.any():
            assert not shown.any()
            continue
        assert ys[shown].min() == y[inside].min() and ys[shown].max() == y[inside].max()
        assert ys[shown][0] == y[inside][0] and ys[shown][-1] == y[inside][-1]
    # a subsequence: every kept (t, y) pair is one of the series', in order
    index = np.flatnonzero(np.isin(y, ys))
    assert_array_equal(y[index], ys)
    assert_array_equal(t[index], ts)


def test_decimation_keeps_breaks_and_short_series():
    t = np.linspace(0.0, 1.0, 100)
    y = np.sin(t)
    ts, ys = decimate_minmax(t, y, columns=25)
    assert_array_equal(ts, t)  # 100 <= 4 * 25: unchanged
    assert_array_equal(ys, y)
    y = np.sin(50 * np.linspace(0.0, 1.0, 1000))
    y[[100, 500]] = np.nan
    ts, ys = decimate_minmax(np.linspace(0.0, 1.0, 1000), y, columns=10)
    assert np.isnan(ys).sum() == 2  # the breaks of the line stay
    assert np.nanmax(ys) == np.nanmax(y) and np.nanmin(ys) == np.nanmin(y)


def test_decimation_rejects_bad_input():
    with pytest.raises(ValueError, match="`t` and `y` must be 1-D of equal length"):
        decimate_minmax(np.zeros(3), np.zeros(4))
    with pytest.raises(ValueError, match="`columns` must be at least 1"):
        decimate_minmax(np.zeros(3), np.zeros(3), columns=0)


def test_event_lines_leave_the_limits_and_span_the_axes():
    fig, ax = plt.subplots()
    ax.plot([0.0, 10.0], [2.0, 3.0])
    limits = ax.get_xlim(), ax.get_ylim()
    lines = event_lines(ax, [1.0, 4.5])
    assert (ax.get_xlim(), ax.get_ylim()) == limits
    segments = np.array(lines.get_segments())
    assert_array_equal(segments[:, :, 0], [[1.0, 1.0], [4.5, 4.5]])
    assert_array_equal(segments[:, :, 1], [[0.0, 1.0], [0.0, 1.0]])  # axes fractions


def test_walker_frames_of_chosen_rows(tmp_path):
    """``walker_frames(..., rows=...)`` computes only the frames asked for, equal to those of
    the whole run; across a heel strike the new stance foot is where the swing foot landed."""
    from walker.cli import main
    from walker.plotting.gallery import _params_from_provenance, walker_frames
    from walker.storage import read

    path = tmp_path / "run.h5"
    assert main(["run", "gaits/compass_goswami.toml", "--strides", "3", "--out", str(path)]) == 0
    sol, prov = read(path)
    model, params = _params_from_provenance(prov)
    traj = sol.record
    full = walker_frames(model, params, traj.t, traj.x, sol.events)
    strike = sol.events.t[1]  # the second heel strike
    pre, post = np.flatnonzero(traj.t == strike)  # the record holds both sides of the reset
    rows = np.array([0, pre, post, len(traj) - 1])
    chosen = walker_frames(model, params, traj.t, traj.x, sol.events, rows=rows)
    assert_array_equal(chosen, full[rows])
    swing = int(getattr(model.module, "SWING_FOOT", -1))
    np.testing.assert_allclose(full[post, 0], full[pre, swing], rtol=0, atol=1e-12)
    assert full[post, 0, 0] > 0.3  # two steps down the slope from the origin [m]


def _cells(x, y, box, cells):
    """Cell (column, row) of each point in ``box`` = (x_lo, x_hi, y_lo, y_hi) cut into
    ``cells`` by ``cells``."""
    column = np.minimum(((x - box[0]) / (box[1] - box[0]) * cells).astype(int), cells - 1)
    row = np.minimum(((y - box[2]) / (box[3] - box[2]) * cells).astype(int), cells - 1)
    return column * cells + row


def test_thinned_curve_draws_every_segment_of_the_orbit_once():
    """An orbit traversed 500 times (with a slow drift, and NaN breaks at each reset): the
    thinned curve joins exactly the pairs of cells the full curve joins, its points are the
    curve's own (in order), and no piece runs over a break."""
    cells = 64
    s = np.linspace(0.0, 2.0 * np.pi, 60)
    x = np.concatenate([np.cos(s) * (1 + 1e-4 * k) for k in range(500)])
    y = np.concatenate([np.sin(2 * s) for _ in range(500)])
    breaks = np.arange(1, 500) * 60
    x, y = np.insert(x, breaks, np.nan), np.insert(y, breaks, np.nan)
    xs, ys = thin_curve(x, y, cells=cells)
    assert xs.size < x.size / 20
    finite = np.isfinite(x)
    box = (x[finite].min(), x[finite].max(), y[finite].min(), y[finite].max())
    key = _cells(np.nan_to_num(x), np.nan_to_num(y), box, cells)
    ok = finite[:-1] & finite[1:]
    full_pairs = set(zip(key[:-1][ok].tolist(), key[1:][ok].tolist(), strict=True))
    shown_finite = np.isfinite(xs)
    shown_key = _cells(np.nan_to_num(xs), np.nan_to_num(ys), box, cells)
    ok_shown = shown_finite[:-1] & shown_finite[1:]
    shown_pairs = set(
        zip(shown_key[:-1][ok_shown].tolist(), shown_key[1:][ok_shown].tolist(), strict=True)
    )
    assert shown_pairs == full_pairs
    # the shown points are the curve's, and joined points are consecutive points of it
    where = {(a, b): k for k, (a, b) in enumerate(zip(x.tolist(), y.tolist(), strict=True))}
    index = np.array([where.get((a, b), -1) for a, b in zip(xs.tolist(), ys.tolist(), strict=True)])
    assert np.all(index[shown_finite] >= 0) and np.all(index[~shown_finite] == -1)
    assert np.all(np.diff(index)[ok_shown] == 1)


def test_thin_curve_leaves_short_curves_and_rejects_bad_input():
    x = np.linspace(0.0, 1.0, 40)
    xs, ys = thin_curve(x, x**2, cells=10)
    assert_array_equal(xs, x)
    assert_array_equal(ys, x**2)
    with pytest.raises(ValueError, match="`x` and `y` must be 1-D of equal length"):
        thin_curve(x, x[:3])
    with pytest.raises(ValueError, match="`cells` must be at least 1"):
        thin_curve(x, x, cells=0)
