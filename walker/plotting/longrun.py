"""Drawing helpers whose artist count does not grow with the length of a run.

A run of thousands of strides has tens of thousands of phase runs and events, and millions
of samples.  One matplotlib artist per event or per phase run makes a figure take minutes
and gigabytes to draw; these helpers draw each kind of mark as one collection per axes, and
thin a time series for display to the smallest and largest sample of each pixel column
(:func:`decimate_minmax`), so that no extremum is lost while the caller's data stay as they
are.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection, PolyCollection

__all__ = [
    "DENSE_EVENTS",
    "DISPLAY_COLUMNS",
    "decimate_minmax",
    "event_lines",
    "phase_bands",
    "plot_series",
    "thin_curve",
]

#: Number of pixel columns a time series is thinned to for display: above the width in
#: pixels of a 7 inch figure at 500 dots per inch, so that the thinning is never visible.
DISPLAY_COLUMNS = 4096

#: Number of event lines above which :func:`event_lines` draws them solid and translucent.
DENSE_EVENTS = 500


def decimate_minmax(
    t: np.ndarray, y: np.ndarray, columns: int = DISPLAY_COLUMNS
) -> tuple[np.ndarray, np.ndarray]:
    """A time series thinned to the smallest and largest sample of each column.

    The time span ``[t[0], t[-1]]`` is cut into ``columns`` columns of equal width; each
    column keeps its first and last sample and the samples of its smallest and largest
    value (in their time order), so the line drawn through the result covers, in every
    column, exactly the values range the full series covers there.  Series of at most
    ``4 * columns`` samples are returned unchanged (as copies' views: the inputs are never
    modified).  NaN samples (breaks in a line) are kept.

    Parameters
    ----------
    t : ndarray, shape (n,)
        times [s], non-decreasing.
    y : ndarray, shape (n,)
        values at ``t`` (any unit).
    columns : int
        number of columns, at least 1.

    Returns
    -------
    t_shown, y_shown : ndarray, shape (k,)
        the kept samples, ``k <= 4 * columns`` plus the NaN samples.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 1001)
    >>> ts, ys = decimate_minmax(t, np.sin(40 * t), columns=10)
    >>> len(ts) <= 40, float(ys.max()) == float(np.sin(40 * t).max())
    (True, True)
    """
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    if t.ndim != 1 or y.shape != t.shape:
        raise ValueError(f"`t` and `y` must be 1-D of equal length, got {t.shape}, {y.shape}")
    if int(columns) < 1:
        raise ValueError(f"`columns` must be at least 1, got {columns}")
    columns = int(columns)
    n = t.size
    if n <= 4 * columns:
        return t, y
    span = t[-1] - t[0]
    if not span > 0:
        column = np.zeros(n, dtype=np.intp)
    else:
        column = np.minimum(((t - t[0]) / span * columns).astype(np.intp), columns - 1)
    starts = np.r_[0, np.flatnonzero(np.diff(column)) + 1]
    stops = np.r_[starts[1:], n]
    finite = np.where(np.isnan(y), np.inf, y)
    lowest = starts + _argreduce(finite, starts, np.minimum)
    finite = np.where(np.isnan(y), -np.inf, y)
    highest = starts + _argreduce(finite, starts, np.maximum)
    keep = np.zeros(n, dtype=bool)
    keep[starts] = keep[stops - 1] = True
    keep[lowest] = keep[highest] = True
    keep |= np.isnan(y)
    return t[keep], y[keep]


def _argreduce(values: np.ndarray, starts: np.ndarray, ufunc: Any) -> np.ndarray:
    """Offset within each segment ``values[starts[k]:starts[k + 1]]`` of its first extremum
    under ``ufunc`` (``np.minimum`` or ``np.maximum``)."""
    extreme = ufunc.reduceat(values, starts)
    stops = np.r_[starts[1:], values.size]
    segment = np.repeat(np.arange(starts.size), stops - starts)
    hit = values == extreme[segment]
    # first hit in each segment: the smallest index where hit holds
    index = np.where(hit, np.arange(values.size), values.size)
    return np.minimum.reduceat(index, starts) - starts


def thin_curve(
    x: np.ndarray, y: np.ndarray, cells: int = DISPLAY_COLUMNS
) -> tuple[np.ndarray, np.ndarray]:
    """A curve in the plane (a phase portrait) without its repeated segments, for display.

    The bounding box of the curve is cut into ``cells`` by ``cells`` cells; a segment (two
    consecutive points) is left out when an earlier segment joins the same two cells, so
    an orbit traversed thousands of times is drawn about once, every drawn segment within a
    cell of one of the curve's.  Consecutive kept segments stay joined; a NaN separates the
    others (and a NaN point of the input, a break in the line, is never joined over).
    Curves of at most ``4 * cells`` points are returned unchanged; the inputs are never
    modified.

    Parameters
    ----------
    x, y : ndarray, shape (n,)
        the curve's points (any units), NaN where the line is broken.
    cells : int
        cells along each axis, at least 1.

    Returns
    -------
    x_shown, y_shown : ndarray
        the kept points, with NaN between pieces.
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if x.ndim != 1 or y.shape != x.shape:
        raise ValueError(f"`x` and `y` must be 1-D of equal length, got {x.shape}, {y.shape}")
    if int(cells) < 1:
        raise ValueError(f"`cells` must be at least 1, got {cells}")
    cells = int(cells)
    finite = np.isfinite(x) & np.isfinite(y)
    if x.size <= 4 * cells or not finite.any():
        return x, y
    cell = np.zeros((x.size, 2), dtype=np.int64)
    for axis, values in enumerate((x, y)):
        lo, hi = values[finite].min(), values[finite].max()
        scaled = (np.where(finite, values, lo) - lo) / ((hi - lo) or 1.0) * cells
        cell[:, axis] = np.minimum(scaled.astype(np.int64), cells - 1)
    key = cell[:, 0] * cells + cell[:, 1]  # one integer per cell
    segments = np.flatnonzero(finite[:-1] & finite[1:])  # segment k joins points k, k + 1
    pairs = np.stack([key[segments], key[segments + 1]], axis=1)
    _, first = np.unique(pairs, axis=0, return_index=True)
    kept = segments[np.sort(first)]
    joined = np.r_[False, kept[1:] == kept[:-1] + 1]  # starts where the previous one ended
    # each kept segment contributes its end point, and, when it does not continue the
    # previous one, a NaN (but the first) and its start point before it
    n_new = int(np.count_nonzero(~joined))
    index = np.empty(kept.size + 2 * n_new - 1, dtype=np.int64)
    slot = np.arange(kept.size) + 2 * np.cumsum(~joined) - 1  # position of each end point
    index[slot] = kept + 1
    index[slot[~joined] - 1] = kept[~joined]
    index[(slot[~joined] - 2)[1:]] = -1  # the NaN separators
    shown_x = np.where(index >= 0, x[index], np.nan)
    shown_y = np.where(index >= 0, y[index], np.nan)
    return shown_x, shown_y


def plot_series(ax: Axes, t: np.ndarray, y: np.ndarray, **kwargs: Any):
    """``ax.plot(t, y, **kwargs)`` of a time series thinned by :func:`decimate_minmax`
    (unchanged up to ``4 * DISPLAY_COLUMNS`` samples); returns the Line2D."""
    shown_t, shown_y = decimate_minmax(t, y)
    return ax.plot(shown_t, shown_y, **kwargs)[0]


def event_lines(ax: Axes, times: Sequence[float] | np.ndarray, **kwargs: Any) -> LineCollection:
    """One vertical line across the whole height of ``ax`` at each of ``times`` [s], drawn
    as one LineCollection under the data lines (keyword arguments such as ``colors``,
    ``linestyles``, ``linewidths``, ``label`` go to it); it does not change the axes'
    limits.  More than :data:`DENSE_EVENTS` lines are drawn solid and translucent: dotted
    lines closer than a pixel would line their dots up into horizontal stripes."""
    times = np.asarray(times, dtype=float).ravel()
    segments = np.zeros((times.size, 2, 2))
    segments[:, :, 0] = times[:, None]
    segments[:, 1, 1] = 1.0
    if times.size > DENSE_EVENTS:
        kwargs = {**kwargs, "linestyles": "-", "alpha": 0.25}
    kwargs.setdefault("zorder", 1.5)
    lines = LineCollection(segments, transform=ax.get_xaxis_transform(), **kwargs)
    ax.add_collection(lines, autolim=False)
    return lines


def phase_bands(
    ax: Axes, t: np.ndarray, labels: Sequence[str], colors: dict[str, Any], alpha: float = 0.12
) -> PolyCollection:
    """Shade each run of equal label across the whole height of ``ax``, as one
    PolyCollection of rectangles (one per run, in time order), each in ``colors[label]``.

    Parameters
    ----------
    ax : Axes
    t : ndarray, shape (n,)
        sample times [s].
    labels : sequence of str, length n
        the label of each sample (phases that share a name form one run).
    colors : dict of str -> colour
        the colour of each label.
    alpha : float
        opacity of the shading.

    Returns
    -------
    PolyCollection
        run ``k`` spans from its first sample's time to the next run's first sample's time
        (the last run to ``t[-1]``); the axes' limits are left as they are.
    """
    t = np.asarray(t, dtype=float)
    labels = np.asarray(labels)
    if t.size == 0:
        starts = np.zeros(0, dtype=np.intp)
    else:
        starts = np.r_[0, np.flatnonzero(labels[1:] != labels[:-1]) + 1]
    t0 = t[starts]
    t1 = np.r_[t[starts[1:]], t[-1:]] if t.size else t0
    verts = np.zeros((starts.size, 4, 2))
    verts[:, 0, 0] = verts[:, 1, 0] = t0
    verts[:, 2, 0] = verts[:, 3, 0] = t1
    verts[:, 1, 1] = verts[:, 2, 1] = 1.0
    facecolors = [colors[str(label)] for label in labels[starts]]
    bands = PolyCollection(
        verts,
        facecolors=facecolors,
        alpha=alpha,
        linewidths=0,
        transform=ax.get_xaxis_transform(),
    )
    ax.add_collection(bands, autolim=False)
    return bands
