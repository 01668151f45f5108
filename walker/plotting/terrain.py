"""Figures of rough-ground measures (issue 29): the survival curve of a Monte-Carlo MFPT run,
MFPT against terrain roughness, the gait sensitivity norm against a swept parameter, and a
walk drawn over the terrain it walked on.  Each returns a matplotlib Figure."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from walker.plotting.common import new_axes

__all__ = [
    "plot_gsn_sweep",
    "plot_mfpt_roughness",
    "plot_run_on_terrain",
    "plot_survival",
    "plot_walk_on_terrain",
    "terrain_ground",
]


def plot_survival(result, *, ax=None) -> Figure:
    """The fraction of runs still walking after ``k`` steps (log y) of a
    :class:`walker.results.MfptResult`, with the fitted geometric law ``(1 - rate)^k``."""
    k, alive = result.survival()
    fig, ax = new_axes(ax)
    ax.step(k, alive, where="post", color="C0", label=f"Monte Carlo, {result.runs} runs")
    if np.isfinite(result.rate) and 0 < result.rate < 1:
        ax.plot(
            k,
            (1.0 - result.rate) ** k,
            color="C1",
            ls="--",
            label=f"geometric, rate {result.rate:.3g}",
        )
    ax.set_yscale("log")
    ax.set_xlabel("steps k [1]")
    ax.set_ylabel("fraction still walking [1]")
    ax.set_title(
        f"slope N({result.slope_mean:.4g}, {result.slope_std:.3g}$^2$) rad: "
        f"MFPT {result.mfpt:.4g} $\\pm$ {result.mfpt_stderr:.2g} steps"
    )
    ax.legend()
    return fig


def plot_mfpt_roughness(curves, *, ax=None) -> Figure:
    """MFPT [steps] against the slope's standard deviation [rad], log y.

    Parameters
    ----------
    curves : dict
        label -> dict with ``std`` (rad), ``mfpt`` and ``stderr`` (steps) arrays and,
        optionally, ``markov`` (steps; drawn as open markers).
    """
    fig, ax = new_axes(ax)
    for i, (label, c) in enumerate(curves.items()):
        std = np.asarray(c["std"], dtype=float)
        mfpt = np.asarray(c["mfpt"], dtype=float)
        ax.errorbar(
            std,
            mfpt,
            yerr=np.asarray(c["stderr"], dtype=float),
            color=f"C{i}",
            marker="o",
            ms=4,
            capsize=2,
            label=f"{label}, Monte Carlo",
        )
        if "markov" in c:
            ax.plot(
                std,
                np.asarray(c["markov"], dtype=float),
                ls="none",
                marker="s",
                mfc="none",
                color=f"C{i}",
                label=f"{label}, Markov chain",
            )
    ax.set_yscale("log")
    ax.set_xlabel("slope standard deviation [rad]")
    ax.set_ylabel("mean first-passage time [steps]")
    ax.legend()
    return fig


def plot_gsn_sweep(values, gsn, name: str, unit: str, *, ax=None) -> Figure:
    """The gait sensitivity norm against a swept parameter ``name`` [``unit``]."""
    fig, ax = new_axes(ax)
    ax.plot(np.asarray(values, dtype=float), np.asarray(gsn, dtype=float), marker="o", ms=3)
    ax.set_xlabel(f"{name} [{unit}]")
    ax.set_ylabel("gait sensitivity norm [s/m, m/m]")
    return fig


def walk_over_terrain(P, z0, rows):
    """Contacts, hip and stick figures of a walk of the map ``P`` from ``z0`` over terrain
    ``rows`` ``(n, 2)``: (contacts (k + 1, 2) [m], figures list of (n_points, 2) at each
    touchdown, strides completed k).  World frame, x horizontal toward the walking direction,
    y up, the first stance contact at the origin."""
    from walker.analysis.gsn import _SWING_CONTACT_ROW
    from walker.status import Status

    rows = np.asarray(rows, dtype=float)
    p = P._p()
    contacts, figures = [np.zeros(2)], []
    row = None
    for k in range(1, rows.shape[0] + 1):
        r = P(z0, terrain=rows[:k], n_strides=k)
        if r.status != Status.COMPLETED:
            break
        pts = np.asarray(P.model.points(r.state, p))
        row = _SWING_CONTACT_ROW.get(P.model.name, pts.shape[0] - 1) if row is None else row
        new = contacts[-1] - (pts[row] - pts[0])
        contacts.append(new)
        figures.append(pts - pts[0] + new)
    return np.array(contacts), figures, len(contacts) - 1


def plot_walk_on_terrain(P, z0, rows, *, ax=None) -> Figure:
    """A walk drawn over the terrain it walked on: the ground of each step (the plane of
    slope ``rows[n, 0]`` through the point ``rows[n, 1]`` below the stance contact), the
    contacts, and the walker at each touchdown."""
    rows = np.asarray(rows, dtype=float)
    contacts, figures, done = walk_over_terrain(P, z0, rows)
    fig, ax = new_axes(ax)
    for n in range(min(done + 1, rows.shape[0])):
        c = contacts[n]
        slope, drop = rows[n]
        x_end = contacts[n + 1][0] if n + 1 < contacts.shape[0] else c[0] + 0.5
        x = np.array([c[0], x_end])
        ax.plot([c[0], c[0]], [c[1], c[1] - drop], color="0.3", lw=1.2)
        ax.plot(x, c[1] - drop - np.tan(slope) * (x - c[0]), color="0.3", lw=1.2)
    segments = P.model.segments
    for i, pts in enumerate(figures):
        for a, b in segments:
            ax.plot(
                pts[[a, b], 0],
                pts[[a, b], 1],
                color="C0",
                lw=1,
                alpha=0.35 + 0.65 * (i + 1) / len(figures),
            )
    ax.plot(contacts[:, 0], contacts[:, 1], ls="none", marker="o", ms=3, color="k")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{done} of {rows.shape[0]} steps completed")
    return fig


def terrain_ground(contact, steps, rows) -> np.ndarray:
    """The ground of a run on terrain, one plane segment per step.

    Parameters
    ----------
    contact : array_like, shape (2,)
        the first stance contact [m] (world frame: x horizontal toward the walking
        direction, y up).
    steps : sequence of array_like, shape (2,)
        each touchdown's displacement [m] from the stance contact to the new one (the foot
        swaps of the run, in order).
    rows : array_like, shape (n, 2)
        the terrain rows ``(slope [rad], drop [m])`` of the run's steps
        (:mod:`walker.simulation.terrain`).

    Returns
    -------
    ndarray, shape (n_steps, 2, 2)
        for each step ``n`` the run stood on (at most ``len(steps) + 1`` and ``n``), the
        segment ``(start, end)`` [m] of its plane: from the point ``drop`` below the stance
        contact to the step's touchdown point; for a step that ends without one (the last),
        1 m along its plane.
    """
    rows = np.asarray(rows, dtype=float).reshape(-1, 2)
    contact = np.asarray(contact, dtype=float)
    out = []
    for n, (slope, drop) in enumerate(rows[: len(steps) + 1]):
        start = contact + np.array([0.0, -drop])
        if n < len(steps):
            end = contact + np.asarray(steps[n], dtype=float)
            contact = end
        else:
            end = start + np.array([np.cos(slope), -np.sin(slope)])
        out.append([start, end])
    return np.array(out).reshape(-1, 2, 2)


def plot_run_on_terrain(frames, segments, ground, *, n_figures: int = 12, ax=None) -> Figure:
    """A run drawn over the ground it walked on: the ground's segments ``ground``
    (:func:`terrain_ground`), and the stick figure ``frames`` (n, n_points, 2) [m] (world
    frame, :func:`walker.plotting.gallery.walker_frames`) at ``n_figures`` evenly spaced samples,
    its stance contacts' path in black."""
    from walker.plotting.runs import _draw_ground

    frames = np.asarray(frames, dtype=float)
    fig, ax = new_axes(ax)
    _draw_ground(ax, np.asarray(ground, dtype=float))
    picks = np.unique(np.linspace(0, len(frames) - 1, max(1, n_figures)).astype(int))
    for i, k in enumerate(picks):
        for a, b in segments:
            ax.plot(
                frames[k, [a, b], 0],
                frames[k, [a, b], 1],
                color="C0",
                lw=1,
                alpha=0.35 + 0.65 * (i + 1) / len(picks),
            )
    # the stance contacts' path: one marker per place the contact moves to (a fixed foot's
    # contact repeats over all the samples of its stride)
    contacts = frames[:, 0]
    moved = np.r_[True, np.any(contacts[1:] != contacts[:-1], axis=1)]
    ax.plot(contacts[moved, 0], contacts[moved, 1], ls="none", marker=".", ms=2, color="k")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    return fig
