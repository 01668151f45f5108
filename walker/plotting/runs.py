"""Figures of one run: angles and rates, energy, a phase portrait, torques, zero dynamics, and
the walker animated.

Each takes a :class:`~walker.results.Solution` or :class:`~walker.results.Trajectory` (or
plain arrays), computes no physics, and returns the :class:`~matplotlib.figure.Figure` it drew
on; re-exported by :mod:`walker.plotting`.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib import animation
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from walker.plotting.common import legend_outside, new_axes, state_unit, with_unit
from walker.plotting.longrun import event_lines, phase_bands, plot_series, thin_curve

__all__ = [
    "animate_walker",
    "leg_roles",
    "plot_angles",
    "plot_energy",
    "plot_phase_portrait",
    "plot_torques",
    "plot_zero_dynamics",
]


def _trajectory_of(obj: Any, argname: str) -> tuple[Any, Any]:
    """(trajectory, events) from a Solution (record, else samples) or a Trajectory."""
    if (
        hasattr(obj, "t")
        and hasattr(obj, "x")
        and hasattr(obj, "phase")
        and not hasattr(obj, "record")
    ):
        return obj, None
    traj = getattr(obj, "record", None)
    if traj is None:
        traj = getattr(obj, "samples", None)
    if traj is None:
        raise ValueError(
            f"`{argname}` has neither `record` nor `samples`; run with output 'samples' or "
            "'full', or pass a Trajectory"
        )
    return traj, getattr(obj, "events", None)


def plot_angles(
    solution_or_trajectory: Any,
    *,
    state_names: Sequence[str] | None = None,
    phase_names: Sequence[str] | None = None,
    ax: Sequence[Axes] | None = None,
) -> Figure:
    """Angles (first half of the state) and rates (second half) against time.

    Parameters
    ----------
    solution_or_trajectory : Solution or Trajectory
        a Solution plots its ``record`` (else ``samples``) and marks its ``events`` as
        vertical lines; a Trajectory has ``t`` (n,), ``x`` (n, n_x) and ``phase`` (n,).
    state_names : sequence of str, length n_x, optional
        default ``x[0]``, ``x[1]``, ...
    phase_names : sequence of str, optional
        names of the phase indices, for the legend of the shaded spans; default the
        Solution's ``phase_names``, else ``phase 0``, ...  Phases with the same name share
        a colour and a legend entry; only phases that occur in the run are listed.
    ax : pair of Axes, optional
        (angles axes, rates axes).

    Returns
    -------
    Figure
        two axes; on each one line per coordinate (thinned for display to each pixel
        column's extremes on long runs, :func:`walker.plotting.longrun.decimate_minmax`),
        one PolyCollection of shaded spans (one per run of equal phase name) and, with
        events, one LineCollection of vertical lines (one per event).
    """
    traj, events = _trajectory_of(solution_or_trajectory, "solution_or_trajectory")
    t = np.asarray(traj.t, dtype=float)
    x = np.asarray(traj.x, dtype=float)
    phase = np.asarray(traj.phase)
    if x.ndim != 2 or x.shape[0] != t.shape[0] or x.shape[1] % 2:
        raise ValueError(
            f"`x` must have shape (n, n_x) with n = len(t) = {t.shape[0]} and n_x even, "
            f"got {x.shape}"
        )
    n_x = x.shape[1]
    names = list(state_names) if state_names is not None else [f"x[{i}]" for i in range(n_x)]
    if len(names) != n_x:
        raise ValueError(f"`state_names` must have {n_x} entries, got {len(names)}")
    if phase_names is None:
        phase_names = getattr(solution_or_trajectory, "phase_names", None) or ()
    phase_names = list(phase_names)
    if ax is None:
        fig = Figure(figsize=(7.0, 5.6), layout="constrained")
        ax_q, ax_v = fig.subplots(2, 1, sharex=True)
    else:
        if len(ax) != 2 or not all(isinstance(a, Axes) for a in ax):
            raise TypeError("`ax` must be a pair of Axes (angles, rates) or None")
        ax_q, ax_v = ax
        fig = ax_q.figure
    half = n_x // 2
    for i in range(half):
        plot_series(ax_q, t, x[:, i], label=names[i])
        plot_series(ax_v, t, x[:, half + i], label=names[half + i])
    # Shade each run of equal phase name, one colour (and one legend entry) per name:
    # phases that share a name (e.g. friction modes left out of the names) share a colour.
    # One collection per axes, so the figure's size does not grow with the run's length.
    codes, first, inverse = np.unique(phase, return_index=True, return_inverse=True)
    code_labels = [
        phase_names[p] if 0 <= p < len(phase_names) else f"phase {p}" for p in codes.tolist()
    ]
    seen: dict[str, Patch] = {}
    for k in np.argsort(first, kind="stable"):  # colours in order of first occurrence
        label = code_labels[k]
        if label not in seen:
            seen[label] = Patch(color=f"C{len(seen) % 10}", alpha=0.12, label=label)
    if t.size:
        labels = np.asarray(code_labels)[inverse.ravel()]
        colors = {label: patch.get_facecolor()[:3] for label, patch in seen.items()}
        for a in (ax_q, ax_v):
            phase_bands(a, t, labels, colors, alpha=0.12)
    if events is not None:
        for a in (ax_q, ax_v):
            event_lines(a, events.t, colors="k", linewidths=0.8, linestyles=":")
    ax_q.set_ylabel("angle [rad]")
    ax_v.set_ylabel("rate [rad/s]")
    ax_v.set_xlabel("time [s]")
    handles, _ = ax_q.get_legend_handles_labels()
    legend_outside(ax_q, handles=handles + list(seen.values()))
    legend_outside(ax_v)
    return fig


def plot_phase_portrait(
    trajectory: Any,
    i: int,
    j: int,
    *,
    fixed_point: Any = None,
    state_names: Sequence[str] | None = None,
    units: Sequence[str] | None = None,
    ax: Axes | None = None,
) -> Figure:
    """State coordinate ``j`` against coordinate ``i``.

    Parameters
    ----------
    trajectory : Trajectory or Solution
        a Solution contributes its ``record`` (else ``samples``).
    i, j : int
        state indices on the horizontal and vertical axes.
    fixed_point : FixedPoint or ndarray, shape (n_x,), optional
        marked with a star at ``(state[i], state[j])`` (a FixedPoint's ``state``).
    state_names : sequence of str, optional
        axis labels; default ``x[i]``.
    units : sequence of str, length n_x, optional
        units of the state coordinates, shown in the axis labels; default from the names
        (:func:`state_unit`), and for the default names rad for the first half of the state
        and rad/s for the second.
    ax : Axes, optional

    Returns
    -------
    Figure
        one line through the whole run, broken (a NaN) at each phase change and reset
        (on long runs without its repeated segments, :func:`walker.plotting.longrun.thin_curve`);
        axis labels ``"name [unit]"``.
    """
    traj, _ = _trajectory_of(trajectory, "trajectory")
    x = np.asarray(traj.x, dtype=float)
    n_x = x.shape[1]
    for name, k in (("i", i), ("j", j)):
        if not 0 <= k < n_x:
            raise ValueError(f"`{name}` must be a state index in [0, {n_x}), got {k}")
    fig, ax = new_axes(ax)
    t = np.asarray(traj.t, dtype=float)
    # A new piece at every phase change and every repeated time (a reset within a phase).
    breaks = np.asarray(traj.phase)[1:] != np.asarray(traj.phase)[:-1]
    breaks |= t[1:] <= t[:-1]
    cuts = np.flatnonzero(breaks) + 1
    # one line broken by a NaN at each cut (one artist however long the run), drawn without
    # the segments a long run repeats within a display cell
    shown = thin_curve(np.insert(x[:, i], cuts, np.nan), np.insert(x[:, j], cuts, np.nan))
    ax.plot(*shown, color="C0", lw=1.0)
    if fixed_point is not None:
        state = np.asarray(getattr(fixed_point, "state", fixed_point), dtype=float)
        ax.plot(state[i], state[j], marker="*", ms=12, color="C3", ls="none", label="fixed point")
        legend_outside(ax)
    if state_names is not None:
        names = list(state_names)
        default_units = [state_unit(n) for n in names]
    else:
        names = [f"x[{k}]" for k in range(n_x)]
        default_units = ["rad" if k < n_x // 2 else "rad/s" for k in range(n_x)]
    units = list(units) if units is not None else default_units
    ax.set_xlabel(with_unit(names[i], units[i]))
    ax.set_ylabel(with_unit(names[j], units[j]))
    return fig


def plot_energy(
    t: np.ndarray,
    kinetic: np.ndarray,
    potential: np.ndarray,
    *,
    event_times: np.ndarray | None = None,
    event_energies: np.ndarray | None = None,
    unit: str = "J",
    ax: Axes | None = None,
) -> Figure:
    """Kinetic, potential and total energy against time, with the jump at each impact.

    Parameters
    ----------
    t : ndarray, shape (n,)
        times [s], non-decreasing; a reset may appear as two samples at the same time
        (before, then after).
    kinetic, potential : ndarray, shape (n,)
        energies [J] at ``t``.
    event_times : ndarray, shape (m,), optional
        impact times [s]: a vertical segment marks the change of the total energy at each,
        labelled with its size in J (more than :data:`MAX_JUMP_LABELS` such jumps: one text
        "N impacts: smallest to largest J" instead); an event at which the energy does not
        change (to 1e-9 of the largest total energy) gets neither segment nor label.
    event_energies : ndarray, shape (m, 2), optional
        total energy [J] just before and just after each event in ``event_times``, computed
        from the event's own pre- and post-impact states (on the same reference as
        ``potential``).  Without it the change is read from the samples next to each event
        time, which also holds whatever energy flows in between (actuator work, damping)
        unless the samples bracket the reset at the same time; an event outside the
        sampled times is then left out.
    unit : str
        unit of the energies (and of the "J" above), on the axis and the labels; ``"J/kg"``
        for a model whose energies are per unit mass.
    ax : Axes, optional

    Returns
    -------
    Figure
        three lines (kinetic, potential, total; thinned for display on long runs,
        :func:`walker.plotting.longrun.decimate_minmax`), and a LineCollection of the
        jumps (label "impact loss") with their texts when any event changes the energy.
    """
    t = np.asarray(t, dtype=float)
    kinetic = np.asarray(kinetic, dtype=float)
    potential = np.asarray(potential, dtype=float)
    if t.ndim != 1 or kinetic.shape != t.shape or potential.shape != t.shape:
        raise ValueError(
            f"`t`, `kinetic` and `potential` must be 1-D of equal length, got {t.shape}, "
            f"{kinetic.shape}, {potential.shape}"
        )
    fig, ax = new_axes(ax)
    total = kinetic + potential
    plot_series(ax, t, kinetic, label="kinetic")
    plot_series(ax, t, potential, label="potential")
    plot_series(ax, t, total, label="total", color="k")
    if event_times is not None and t.size:
        te = np.asarray(event_times, dtype=float).ravel()
        if event_energies is not None:
            pairs = np.asarray(event_energies, dtype=float)
            if pairs.shape != (te.size, 2):
                raise ValueError(
                    f"`event_energies` must have shape (m, 2) with m = len(event_times) = "
                    f"{te.size}, got {pairs.shape}"
                )
            e0, e1 = pairs[:, 0], pairs[:, 1]
            keep = np.ones(te.size, dtype=bool)
        else:
            lo = np.searchsorted(t, te, side="left")
            hi = np.searchsorted(t, te, side="right")
            twice = hi - lo >= 2  # samples before and after the reset at the event time
            before = np.where(twice, lo, np.maximum(lo - 1, 0))
            after = np.where(twice, hi - 1, np.minimum(hi, t.size - 1))
            e0, e1 = total[before], total[after]
            keep = after > before  # samples on both sides of the event
        scale = float(np.max(np.abs(total))) if total.size else 1.0
        keep &= np.abs(e1 - e0) > 1e-9 * max(scale, 1e-300)
        te, e0, e1 = te[keep], e0[keep], e1[keep]
        if te.size:
            ax.vlines(
                te,
                np.minimum(e0, e1),
                np.maximum(e0, e1),
                colors="C3",
                lw=2.0,
                label="impact loss",
            )
        _label_jumps(ax, te, e0, e1, unit)
    ax.set_xlabel("time [s]")
    ax.set_ylabel(with_unit("energy", unit))
    legend_outside(ax)
    return fig


#: Most energy jumps labelled one by one in :func:`plot_energy`; a longer run's jumps are
#: summarised in one text.
MAX_JUMP_LABELS = 24


def _label_jumps(ax: Axes, times, e0, e1, unit: str) -> None:
    """One text per energy jump, in rows below the axes' top edge: each label goes into the
    first row where it does not overlap the labels already placed (its width estimated from
    its characters, in axes fractions), so labels of impacts close in time never collide.
    A thin line joins each label to the bottom of its jump.  More than
    :data:`MAX_JUMP_LABELS` jumps get one text instead: their number and the range of their
    sizes."""
    if len(times) > MAX_JUMP_LABELS:  # a long run: one summary instead of a label each
        change = np.asarray(e1, dtype=float) - np.asarray(e0, dtype=float)
        text = f"{len(times)} impacts: {change.min():+.5g} to {change.max():+.5g} {unit}"
        ax.text(0.01, 0.97, text, transform=ax.transAxes, va="top", fontsize="x-small", color="C3")
        lo, hi = ax.get_ylim()
        ax.set_ylim(lo, lo + (hi - lo) / 0.9)
        return
    t_lo, t_hi = ax.get_xlim()
    span = (t_hi - t_lo) or 1.0
    # axes width in points, and a small font's character width in points (about 0.6 em)
    width_pt = ax.figure.get_figwidth() * 72.0 * ax.get_position().width
    char = 0.65 * 7.0 / max(width_pt, 1.0)
    row_ends: list[float] = []  # right end of the last label in each row [axes fraction]
    for time, a, b in zip(times, e0, e1, strict=True):
        text = f"{b - a:+.5g} {unit}"
        left = (float(time) - t_lo) / span
        width = char * (len(text) + 1)
        left = min(left, 1.0 - width)  # inside the axes at the right end
        right = left + width
        row = next((k for k, end in enumerate(row_ends) if left > end), len(row_ends))
        if row == len(row_ends):
            row_ends.append(right)
        else:
            row_ends[row] = right
        ax.annotate(
            text,
            xy=(time, min(a, b)),
            xycoords="data",
            xytext=(left, 0.97 - 0.06 * row),
            textcoords=ax.transAxes,
            va="top",
            fontsize="x-small",
            color="C3",
            arrowprops={"arrowstyle": "-", "color": "C3", "lw": 0.5, "alpha": 0.6},
        )
    if row_ends:  # headroom above the data for the rows of labels
        lo, hi = ax.get_ylim()
        ax.set_ylim(lo, lo + (hi - lo) / (1.0 - (0.06 * len(row_ends) + 0.04)))


def _finish(fig: Figure, ax: Axes, xlabel: str, ylabel: str) -> Figure:
    """Label the axes of a one-axes figure, add its legend, and return the figure."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    legend_outside(ax)
    return fig


def plot_torques(
    t: np.ndarray,
    torques: np.ndarray,
    *,
    names: Sequence[str] | None = None,
    limit: float | None = None,
    event_times: np.ndarray | None = None,
    ax: Axes | None = None,
) -> Figure:
    """Actuator torques against time, with the torque limit and the impacts marked.

    Parameters
    ----------
    t : ndarray, shape (n,)
        time [s].
    torques : ndarray, shape (n, m)
        applied torques [N m], one column per actuator.
    names : sequence of str, length m, optional
    limit : float, optional
        saturation limit [N m]; drawn as dashed lines at +-limit.
    event_times : ndarray, optional
        impact times [s]; vertical dotted lines (one LineCollection).
    ax : Axes, optional

    Returns
    -------
    Figure
        one line per actuator (thinned for display on long runs,
        :func:`walker.plotting.longrun.decimate_minmax`), plus the limit lines.
    """
    fig, ax = new_axes(ax)
    t = np.asarray(t, dtype=float)
    torques = np.atleast_2d(np.asarray(torques, dtype=float))
    if torques.shape[0] != t.shape[0]:
        raise ValueError(
            f"`torques` must have one row per time, got {torques.shape[0]} rows for "
            f"{t.shape[0]} times"
        )
    names = list(names) if names is not None else [f"u{j}" for j in range(torques.shape[1])]
    for j in range(torques.shape[1]):
        plot_series(ax, t, torques[:, j], label=names[j])
    if limit is not None:
        for sign in (1.0, -1.0):
            ax.axhline(sign * limit, color="0.4", linestyle="--", linewidth=0.8)
    if event_times is not None:
        event_lines(ax, event_times, colors="0.6", linestyles=":", linewidths=0.8)
    return _finish(fig, ax, "time [s]", "torque [N m]")


def plot_zero_dynamics(
    theta: np.ndarray,
    theta_dot: np.ndarray,
    *,
    theta_plus: float | None = None,
    theta_minus: float | None = None,
    ax: Axes | None = None,
) -> Figure:
    """The zero dynamics' phase portrait: phase variable rate against the phase variable,
    with the section ends ``theta_plus`` (just after impact) and ``theta_minus`` (impact).

    Parameters
    ----------
    theta, theta_dot : ndarray, shape (n,)
        phase variable [rad] and its rate [rad/s] along a (closed-loop) run.
    theta_plus, theta_minus : float, optional
        drawn as two vertical lines of their own colour and style (``theta+`` dashed,
        ``theta-`` dotted), each labelled with its value.
    ax : Axes, optional

    Returns
    -------
    Figure
        the orbit (one line, broken at each impact; on long runs without its repeated
        segments, :func:`walker.plotting.longrun.thin_curve`), then a line for
        ``theta_plus`` and one for ``theta_minus`` when given.
    """
    fig, ax = new_axes(ax)
    theta = np.asarray(theta, dtype=float)
    theta_dot = np.asarray(theta_dot, dtype=float)
    # break the line at impacts (the phase variable jumps back), so the reset is not drawn
    # as a trajectory
    span = np.ptp(theta) if theta.size else 0.0
    cuts = np.flatnonzero(np.abs(np.diff(theta)) > 0.25 * span) + 1 if span > 0 else []
    theta = np.insert(theta, cuts, np.nan)
    theta_dot = np.insert(theta_dot, cuts, np.nan)
    ax.plot(*thin_curve(theta, theta_dot), label="orbit", color="C0")
    ends = (
        (theta_plus, "theta+", "step starts", "C2", "--"),
        (theta_minus, "theta-", "impact", "C3", ":"),
    )
    for value, name, meaning, color, style in ends:
        if value is not None:
            ax.axvline(
                value,
                color=color,
                linestyle=style,
                linewidth=1.5,
                label=f"{name} = {value:.4g} rad ({meaning})",
            )
    return _finish(fig, ax, "phase variable theta [rad]", "theta_dot [rad/s]")


def animate_walker(
    frames: np.ndarray,
    segments: Sequence[tuple[int, int]],
    *,
    slope: float = 0.0,
    interval_ms: float = 33.0,
    path: str | Path | None = None,
    swing_foot: int = -1,
    title: str | None = None,
    ground: np.ndarray | None = None,
) -> animation.FuncAnimation:
    """Stick-figure animation of a walker; optionally saved as GIF or MP4.

    Parameters
    ----------
    frames : ndarray, shape (n_frames, n_points, 2)
        joint positions [m] in the world frame (x horizontal, walking toward +x; y up).
    segments : sequence of (int, int)
        pairs of point indices drawn as links.
    slope : float
        ground angle [rad]; the ground is drawn through the origin as
        ``y = -tan(slope) x`` (downhill toward +x).
    interval_ms : float
        time between frames [ms]; the file's frame rate is ``1000 / interval_ms``.
    path : str or Path, optional
        ``*.gif`` (written with Pillow) or ``*.mp4`` (needs ffmpeg,
        ``matplotlib.animation.writers.is_available("ffmpeg")``).
    swing_foot : int
        index of the swing foot's point (the model's ``SWING_FOOT``; default the last); the
        stance leg (from point 0, the stance foot, to the hip) and the swing leg (from the
        hip to the swing foot) are drawn in two colours, other links (a torso) in grey
        (:func:`leg_roles`).
    title : str, optional
        drawn above the axes.
    ground : ndarray, shape (n_steps, 2, 2), optional
        the ground of a run on terrain, one plane segment ``(start, end)`` [m] per step
        (:func:`walker.plotting.terrain.terrain_ground`), drawn instead of the plane of ``slope``:
        the segments (a LineCollection labelled ``_ground``) and the risers joining one
        step's end to the next one's start (``_risers``).

    Returns
    -------
    matplotlib.animation.FuncAnimation
        its figure is ``anim._fig``; one Line2D per segment and one for the joints.
    """
    frames = np.asarray(frames, dtype=float)
    if frames.ndim != 3 or frames.shape[2] != 2 or frames.shape[0] == 0:
        raise ValueError(
            f"`frames` must have shape (n_frames, n_points, 2) with n_frames >= 1, "
            f"got {frames.shape}"
        )
    n_points = frames.shape[1]
    segs = [tuple(int(v) for v in s) for s in segments]
    for s in segs:
        if len(s) != 2 or not all(0 <= v < n_points for v in s):
            raise ValueError(
                f"`segments` must be pairs of point indices in [0, {n_points}), got {s}"
            )
    if not interval_ms > 0:
        raise ValueError(f"`interval_ms` must be positive, got {interval_ms}")
    writer_cls = None
    if path is not None:
        path = Path(path)
        suffix = path.suffix.lower()
        if suffix == ".gif":
            writer_cls = animation.PillowWriter
        elif suffix == ".mp4":
            if not animation.writers.is_available("ffmpeg"):
                raise ValueError(
                    f"`path` {str(path)!r} asks for MP4 but ffmpeg is not available; "
                    "use a .gif path"
                )
            writer_cls = animation.FFMpegWriter
        else:
            raise ValueError(f"`path` must end in .gif or .mp4, got {str(path)!r}")
        if not path.parent.is_dir():
            raise FileNotFoundError(f"directory '{path.parent}' of `path` does not exist")

    fig = Figure(figsize=(6.4, 3.6), layout="constrained")
    ax = fig.add_subplot()
    lo = np.nanmin(frames.reshape(-1, 2), axis=0)
    hi = np.nanmax(frames.reshape(-1, 2), axis=0)
    pad = 0.1 * max(float(np.max(hi - lo)), 1e-9)
    gx = np.array([lo[0] - pad, hi[0] + pad])
    if ground is None:
        ax.plot(gx, -np.tan(slope) * gx, color="0.4", lw=1.5)  # ground
        ground_lo = float(np.min(-np.tan(slope) * gx))
    else:
        ground = np.asarray(ground, dtype=float)
        if ground.ndim != 3 or ground.shape[1:] != (2, 2):
            raise ValueError(f"`ground` must have shape (n_steps, 2, 2), got {ground.shape}")
        _draw_ground(ax, ground)
        gx = np.array([min(gx[0], ground[..., 0].min()), max(gx[1], ground[..., 0].max())])
        ground_lo = float(ground[..., 1].min())
    ax.set_xlim(gx)
    ax.set_ylim(min(lo[1], ground_lo) - pad, hi[1] + pad)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if title:
        ax.set_title(title, fontsize="medium")
    roles = leg_roles(segs, n_points, swing_foot)
    colors = {"stance leg": "C0", "swing leg": "C1", "body": "0.3"}
    links = [
        ax.plot([], [], color=colors[role], lw=2.5, solid_capstyle="round")[0] for role in roles
    ]
    ax.legend(
        handles=[
            Line2D([], [], color=colors[role], lw=2.5, label=role)
            for role in colors
            if role in roles
        ],
        loc="upper right",
        fontsize="small",
    )
    joints = ax.plot([], [], ls="none", marker="o", ms=4, color="k")[0]

    def draw(k: int) -> list[Line2D]:
        pts = frames[k]
        for line, (a, b) in zip(links, segs, strict=True):
            line.set_data(pts[[a, b], 0], pts[[a, b], 1])
        joints.set_data(pts[:, 0], pts[:, 1])
        return [*links, joints]

    anim = animation.FuncAnimation(
        fig, draw, frames=frames.shape[0], interval=interval_ms, blit=False, repeat=False
    )
    if writer_cls is not None:
        _save_animation(anim, path, writer_cls(fps=1000.0 / interval_ms))
    return anim


def _draw_ground(ax: Axes, ground: np.ndarray) -> None:
    """The steps' plane segments of ``ground`` (n_steps, 2, 2) [m], one LineCollection
    labelled ``_ground`` (segment ``n`` is step ``n``'s plane), and the risers from one
    step's end to the next one's start, one LineCollection labelled ``_risers``."""
    style = {"colors": "0.4", "linewidths": 1.5}
    ax.add_collection(LineCollection(ground, label="_ground", **style))
    risers = np.stack([ground[:-1, 1], ground[1:, 0]], axis=1)
    ax.add_collection(LineCollection(risers, label="_risers", **style))


def leg_roles(
    segments: Sequence[tuple[int, int]], n_points: int, swing_foot: int = -1
) -> list[str]:
    """Which leg each link of a stick figure belongs to: ``"stance leg"``, ``"swing leg"``
    or ``"body"``.

    The legs are the path of links from point 0 (the stance foot) to ``swing_foot``; the
    hip splits it: the point of the path where a further link (a torso) branches off, else
    the path's middle point (the stance leg taking the shorter half: the kneed walker's
    stance knee is locked and not drawn).

    Examples
    --------
    >>> leg_roles([(0, 1), (1, 2), (2, 3)], 4)
    ['stance leg', 'swing leg', 'swing leg']
    >>> leg_roles([(0, 1), (1, 2), (1, 3)], 4, swing_foot=2)
    ['stance leg', 'swing leg', 'body']
    """
    segs = [(int(a), int(b)) for a, b in segments]
    target = swing_foot % n_points if n_points else 0
    neighbours: dict[int, list[int]] = {}
    for a, b in segs:
        neighbours.setdefault(a, []).append(b)
        neighbours.setdefault(b, []).append(a)
    previous = {0: -1}
    queue = [0]
    while queue:  # breadth-first search for the path 0 -> swing foot
        node = queue.pop(0)
        for other in neighbours.get(node, []):
            if other not in previous:
                previous[other] = node
                queue.append(other)
    if target not in previous:
        return ["body"] * len(segs)
    path = [target]
    while path[-1] != 0:
        path.append(previous[path[-1]])
    path.reverse()
    inner = [p for p in path[1:-1] if len(neighbours[p]) > 2]
    hip = inner[0] if inner else path[(len(path) - 1) // 2]
    stance = set(path[: path.index(hip) + 1])
    swing = set(path[path.index(hip) :])
    roles = []
    for a, b in segs:
        if a in stance and b in stance:
            roles.append("stance leg")
        elif a in swing and b in swing:
            roles.append("swing leg")
        else:
            roles.append("body")
    return roles


def _save_animation(anim: Any, path: Path, writer: Any) -> None:
    """Render ``anim`` into a private temporary directory, then write the file onto ``path``
    atomically (:func:`walker.storage.write_file`: a symbolic link at ``path`` is replaced,
    not followed; a failure leaves no partial file)."""
    import tempfile

    from walker.storage import write_file

    with tempfile.TemporaryDirectory(prefix="walker-anim-") as tmp:
        rendered = Path(tmp) / f"animation{path.suffix.lower()}"
        anim.save(str(rendered), writer=writer)
        data = rendered.read_bytes()
    write_file(path, data)
