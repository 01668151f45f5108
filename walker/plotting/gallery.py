"""Figures from stored results: what ``walker plot FILE.h5`` draws.

:func:`plot_file` and :func:`plot_solution` write PNG files (and, on request, a GIF) into a
directory and return their paths; :func:`solution_figures` returns a run's figures
unsaved.  The drawing itself is done by :mod:`walker.plotting`, the physics (energies,
joint positions) by the model named in the file's provenance.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from walker import plotting
from walker.plotting.longrun import event_lines
from walker.results import Branch, Solution, Trajectory

__all__ = [
    "FIGURES",
    "FORMATS",
    "UnknownFigure",
    "figure_title",
    "phase_labels",
    "plot_file",
    "plot_solution",
    "solution_figures",
    "torque_names",
    "walker_frames",
]


FORMATS = ("png", "pdf", "svg")
"""File formats of :func:`plot_file`."""

FIGURES = {
    "solution": ("angles", "energy", "phase_portrait", "torques", "zero_dynamics"),
    "fixed_point": ("multipliers",),
    "branch": ("branch", "bifurcation", "multipliers"),
    "orbit_diagram": ("orbit_diagram",),
    "basin": ("basin",),
    "sweep": ("sweep",),
    "mfpt": ("survival",),
}
"""The figures :func:`plot_file` draws for each kind of result, by name (a run's torques
and zero dynamics only for actuated walkers); the animation (``walk``) is asked for apart
(``gif``)."""


class UnknownFigure(ValueError):
    """A figure name that :func:`plot_file` does not draw for the file's kind."""


_OUTPUT = {"dpi": 110}


def _save(fig, path: Path) -> Path:
    """Write ``fig`` to ``path`` (its format from the suffix) as every output of walker is
    written: rendered in memory, then through a temporary file in the same directory
    renamed onto ``path`` (:func:`walker.storage.write_file`), so that a symbolic link
    planted at ``path`` is replaced, not followed, and a failure (a full disk) leaves no
    partial file and is a one-line StorageError naming ``path``."""
    import io

    from walker.storage import write_file

    buffer = io.BytesIO()
    fig.savefig(buffer, format=path.suffix.lstrip(".") or "png", dpi=_OUTPUT["dpi"])
    return write_file(path, buffer.getvalue())


def figure_title(prov: dict) -> str:
    """``"model, scene STEM"``: the model and the scene (its file's stem) a result was
    computed from, read from the file's provenance (``"model"`` alone without a scene)."""
    model = str(prov.get("model") or "unknown model")
    scene = prov.get("scene")
    if isinstance(scene, str) and scene:
        return f"{model}, scene {Path(scene).stem}"
    return model


def _titled(fig, title: str):
    """Put ``title`` above ``fig``, before the figure's own title if it has one."""
    own = fig.get_suptitle()
    fig.suptitle(f"{title}: {own}" if own else title, fontsize="medium")
    return fig


FRICTION_PREFIXES = ("damping_", "coulomb_")
"""Joint-friction parameters; files written before a model had them lack them."""


def _params_from_provenance(prov: dict):
    """The model and parameters a file was computed with.

    A file written before a joint-friction parameter (``damping_*``, ``coulomb_*``) was added
    to its model lacks it; it was computed without that friction, so it reads as 0, with a
    warning naming the parameters.  Fields a parameter class lists in ``ADDED_FIELDS`` (the
    three-link book controller's, the actuated walkers' rotor inertia) read as its first
    preset's values, which reproduce the model such a file was computed with.  Any other
    missing parameter is an error.
    """
    from walker.models import MODEL_NAMES, get_model
    from walker.storage import StorageError

    name = prov.get("model")
    if name not in MODEL_NAMES:
        raise StorageError(
            f"provenance key 'model' is {name!r}; plotting needs one of {', '.join(MODEL_NAMES)}"
        )
    if not isinstance(prov.get("parameters"), dict):
        raise StorageError("provenance key 'parameters' is missing; plotting needs it")
    model = get_model(name)
    values = {k: v["value"] for k, v in prov["parameters"].items()}
    later = getattr(model.params_class, "ADDED_FIELDS", ())
    missing_later = [n for n in later if n not in values]
    if missing_later:
        # computed before these fields existed: the values that reproduce that model
        preset = getattr(model.params_class, model.params_class.PRESETS[0])()
        values.update({n: getattr(preset, n) for n in missing_later})
    added = [
        n for n in model.params_class.names() if n not in values and n.startswith(FRICTION_PREFIXES)
    ]
    if added:
        warnings.warn(
            f"the stored parameters predate {', '.join(f'`{n}`' for n in added)}: read as 0 "
            "(the frictionless model the file was computed with)",
            UserWarning,
            stacklevel=3,
        )
        values.update(dict.fromkeys(added, 0.0))
    return model, model.params_class.from_dict(values)


def _foot_steps(model, params, events) -> list[np.ndarray | None]:
    """For each event, the displacement of the stance foot (world frame) when the event
    hands the stance to the other foot (a heel strike, a rimless wheel's spoke impact),
    else None.

    The configuration is continuous across an impact; only its coordinates are relabelled.
    So an event is a foot swap when more of the drawn joints after it coincide with joints
    before it once shifted by the old swing foot's position relative to the old stance foot
    than without the shift (a model may draw a joint of one leg only, e.g. the swing knee).
    """
    if events is None:
        return []
    if not model.has_strides:
        return [None] * len(events)
    p = params.as_array()
    swing = getattr(model.module, "SWING_FOOT", -1)
    steps: list[np.ndarray | None] = []
    for i in range(len(events)):
        before = np.asarray(model.points(events.x_pre[i], p), dtype=float)
        after = np.asarray(model.points(events.x_post[i], p), dtype=float)
        step = before[swing] - before[0]
        tol = 1e-6 * max(1.0, float(np.max(np.abs(before))))

        def matches(shift, before=before, after=after, tol=tol) -> int:
            # joints after the event (shifted) that lie on a joint before it
            d = np.linalg.norm((after + shift)[:, None, :] - before[None, :, :], axis=2)
            return int(np.sum(np.min(d, axis=1) <= tol))

        swapped = float(np.linalg.norm(step)) > tol and matches(step) > matches(0.0)
        steps.append(step if swapped else None)
    return steps


def walker_frames(model, params, t, x, events=None, rows=None) -> np.ndarray:
    """Joint positions in the world frame for each sample, following the walker down the
    slope: after every foot swap in ``events`` (a heel strike, see :func:`_foot_steps`) the
    new stance foot is placed where the swing foot landed.

    Parameters
    ----------
    model : WalkerModel
    params : the model's parameter dataclass
    t : ndarray, shape (n,)
    x : ndarray, shape (n, n_x)
    events : EventLog, optional
        without events the stance foot stays at the origin.
    rows : array_like of int, optional
        only these samples' frames (``walker_frames(...)[rows]``, without computing the
        others); default all.

    Returns
    -------
    ndarray, shape (n, n_points, 2)
        (``(len(rows), n_points, 2)`` with ``rows``)
    """
    p = params.as_array()
    t = np.asarray(t, dtype=float)
    # each foot swap moves the stance foot by its step from one sample on: the offsets are
    # the running sum of the steps placed at those samples (linear in the run's length)
    jumps = np.zeros((len(t) + 1, 2))
    if events is not None:
        for te, step in zip(events.t, _foot_steps(model, params, events), strict=True):
            if step is not None:
                # a record holds the state before and after a reset at the same time: the
                # new stance foot applies from the second of those samples on
                lo = np.searchsorted(t, te, side="left")
                hi = np.searchsorted(t, te, side="right")
                jumps[lo + 1 if hi - lo >= 2 else hi] += step
    offsets = np.cumsum(jumps[:-1], axis=0)
    x = np.asarray(x, dtype=float)
    rows = np.arange(len(t)) if rows is None else np.asarray(rows, dtype=np.intp)
    n_points = 1 + max(max(segment) for segment in model.segments)
    frames = np.empty((rows.size, n_points, 2))  # filled in place: no list of small arrays
    for k, row in enumerate(rows):
        frames[k] = model.points(x[row], p)
    frames += offsets[rows, None, :]
    return frames


def _event_energies(model, params, events) -> np.ndarray:
    """Total energy [J] (J/kg for a model without masses) just before and just after each
    event, shape (m, 2), from the event's own pre- and post-event states; for a walker the
    potential energy is referred to the first stance foot (the world frame), as in
    :func:`solution_figures`' energy plot."""
    kin_pre, pot_pre = model.energies(np.asarray(events.x_pre), params)
    kin_post, pot_post = model.energies(np.asarray(events.x_post), params)
    drop_pre = np.zeros(len(events))
    drop_post = np.zeros(len(events))
    if model.has_strides:
        weight = _total_mass(params) * params.g
        height = 0.0  # of the current stance foot above the first one
        for i, step in enumerate(_foot_steps(model, params, events)):
            drop_pre[i] = weight * height
            if step is not None:
                height += float(step[1])
            drop_post[i] = weight * height
    return np.stack([kin_pre + pot_pre + drop_pre, kin_post + pot_post + drop_post], axis=1)


def _impact_mask(events, n_q: int) -> np.ndarray:
    """Which events change the rates (impacts), leaving out mode switches such as a joint
    that starts or stops sticking, where the state is continuous."""
    pre = np.asarray(events.x_pre)[:, n_q : 2 * n_q]
    post = np.asarray(events.x_post)[:, n_q : 2 * n_q]
    if not len(pre):
        return np.zeros(0, dtype=bool)
    scale = np.maximum(1.0, np.max(np.abs(pre), axis=1))
    jumps = np.max(np.abs(post - pre), axis=1)
    return jumps > 1e-9 * scale


def _impact_times(events, n_q: int) -> np.ndarray | None:
    """Times of the events that change the rates (impacts), leaving out mode switches such
    as a joint that starts or stops sticking, where the state is continuous."""
    if events is None:
        return None
    return np.asarray(events.t)[_impact_mask(events, n_q)]


def phase_labels(model, params) -> list[str]:
    """Legend names of the model's phases, showing only the friction modes that matter.

    A phase name such as ``"stance hip_stance=slip+ hip_swing=slip+"`` lists the mode of
    every joint that can have dry friction; a joint whose Coulomb friction is zero in
    ``params`` has no stick or slip modes, so its part is left out (``"stance"`` for a
    frictionless walker).
    """
    labels = []
    for name in model.phase_names:
        kept = []
        for token in str(name).split():
            joint, sep, _mode = token.partition("=")
            if sep and not _has_dry_friction(params, joint):
                continue
            kept.append(token)
        labels.append(" ".join(kept) or str(name))
    return labels


def _has_dry_friction(params, joint: str) -> bool:
    """Whether ``joint`` (a friction-layer joint name: ``ankle``, ``hip_stance``,
    ``joint_1``, ...) has a nonzero ``coulomb_*`` parameter; True when none matches."""
    parts = joint.split("_")
    for key in dict.fromkeys((joint, parts[0], parts[-1])):
        value = getattr(params, f"coulomb_{key}", None)
        if value is not None:
            return float(value) != 0.0
    return True


def solution_figures(
    sol: Solution, model, params, names: tuple[str, ...] | None = None
) -> dict[str, Figure]:
    """The figures of a run, by name: ``angles``; when it holds at least two samples also
    ``energy`` and ``phase_portrait``, and for actuated walkers ``torques`` and
    ``zero_dynamics``.

    Parameters
    ----------
    sol : Solution
        its ``record`` (else ``samples``) is drawn (``ValueError`` without either, from
        :func:`walker.plotting.plot_angles`); its ``events`` give the impacts, whose
        energy jumps are computed from each event's pre- and post-event states.
    model : WalkerModel
    params : the model's parameter dataclass
    names : tuple of str, optional
        draw only these of the figures above (the others are not computed); default all.

    Returns
    -------
    dict of str -> matplotlib.figure.Figure
    """
    wanted = FIGURES["solution"] if names is None else tuple(names)
    figures: dict[str, Figure] = {}
    traj = sol.record if sol.record is not None else sol.samples
    n_q = n_q_of(model)
    if "angles" in wanted:
        # angles and rates only (actuated models carry accumulators after them)
        shown = traj if traj is None else Trajectory(traj.t, traj.x[:, : 2 * n_q], traj.phase)
        angles = plotting.plot_angles(
            shown if shown is not None else sol,
            state_names=model.state_names[: 2 * n_q],
            phase_names=phase_labels(model, params),
        )
        if shown is not None and sol.events is not None:
            for ax in angles.axes:
                event_lines(ax, sol.events.t, colors="0.5", linestyles=":", linewidths=0.8)
        figures["angles"] = angles
    if traj is None or len(traj) < 2:
        return figures
    events = _impact_times(sol.events, n_q)
    if "energy" in wanted:
        figures["energy"] = _energy_figure(sol, traj, model, params, n_q, events)
    if "phase_portrait" in wanted:
        figures["phase_portrait"] = plotting.plot_phase_portrait(
            traj, 0, n_q, state_names=model.state_names
        )
    if model.has_torques and "torques" in wanted:
        pp = params.as_array()
        u = np.array([model.torques(row, pp) for row in traj.x])
        limit = getattr(params, "torque_limit", None)
        figures["torques"] = plotting.plot_torques(
            traj.t, u, names=torque_names(model, u.shape[1]), limit=limit, event_times=events
        )
    if model.has_torques and "zero_dynamics" in wanted:
        tp, tm = getattr(params, "theta_plus", None), getattr(params, "theta_minus", None)
        figures["zero_dynamics"] = plotting.plot_zero_dynamics(
            traj.x[:, 0], traj.x[:, n_q], theta_plus=tp, theta_minus=tm
        )
    return figures


def torque_names(model, n_torques: int) -> list[str]:
    """Legend names of a model's actuator torques: the joint each acts at (the model's
    ``JOINTS``, e.g. ``"hip_stance"``: between the torso and the stance leg), else
    ``u0, u1, ...``."""
    joints = tuple(getattr(model.module, "JOINTS", ()))
    if len(joints) == n_torques:
        return [f"{joint} joint" for joint in joints]
    return [f"u{j}" for j in range(n_torques)]


def _energy_figure(sol, traj, model, params, n_q: int, events):
    """The energy figure of :func:`solution_figures`."""
    kinetic, potential = model.energies(traj.x, params)
    if model.has_strides:
        # Potential energy relative to the current stance foot jumps at each heel strike;
        # refer it to the world frame by the accumulated drop of the stance foot.
        frames = walker_frames(model, params, traj.t, traj.x, sol.events)
        total_mass = _total_mass(params)
        potential = potential + total_mass * params.g * (frames[:, 0, 1] - frames[0, 0, 1])
    event_energies = None
    if sol.events is not None:
        event_energies = _event_energies(model, params, sol.events)[_impact_mask(sol.events, n_q)]
    return plotting.plot_energy(
        traj.t,
        kinetic,
        potential,
        event_times=events,
        event_energies=event_energies,
        unit="J" if _has_masses(params) else "J/kg",
    )


def plot_solution(
    sol: Solution,
    model,
    params,
    out: Path,
    stem: str,
    *,
    gif: bool = False,
    names: tuple[str, ...] | None = None,
    fmt: str = "png",
    title: str | None = None,
    terrain: np.ndarray | None = None,
) -> list[Path]:
    """Write the figures of :func:`solution_figures` (only ``names``, default all) as
    ``{stem}_{name}.{fmt}`` into ``out``, each titled ``title`` when given, and with ``gif``
    (walkers and the double pendulum) a stick-figure animation ``{stem}_walk.gif``, which
    takes most of the time.  ``terrain``: the terrain rows ``(slope, drop)`` of a run on
    terrain: the run is then drawn over its ground (``{stem}_terrain.{fmt}``, and the
    animation's ground is :func:`walker.plotting.terrain.terrain_ground`)."""
    paths = []
    for name, fig in solution_figures(sol, model, params, names).items():
        if title:
            _titled(fig, title)
        paths.append(_save(fig, out / f"{stem}_{name}.{fmt}"))
    traj = sol.record if sol.record is not None else sol.samples
    ground = None
    if terrain is not None and traj is not None and len(traj) >= 1 and model.has_strides:
        from walker.plotting.terrain import plot_run_on_terrain, terrain_ground

        steps = [s for s in _foot_steps(model, params, sol.events) if s is not None]
        ground = terrain_ground(model.points(traj.x[0], params.as_array())[0], steps, terrain)
        fig = plot_run_on_terrain(
            walker_frames(model, params, traj.t, traj.x, sol.events), model.segments, ground
        )
        paths.append(_save(_titled(fig, title) if title else fig, out / f"{stem}_terrain.{fmt}"))
    if gif and traj is not None and len(traj) >= 2:
        if model.has_strides or model.name == "double_pendulum":
            t_frames = np.linspace(traj.t[0], traj.t[-1], min(120, len(traj)))
            idx = np.searchsorted(traj.t, t_frames).clip(0, len(traj) - 1)
            if model.has_strides:  # the frames' samples only, not the whole run
                frames = walker_frames(model, params, traj.t, traj.x, sol.events, rows=idx)
            else:
                frames = np.array([model.points(traj.x[i], params) for i in idx])
            slope = float(getattr(params, "slope", 0.0))
            anim_path = out / f"{stem}_walk.gif"
            plotting.animate_walker(
                frames,
                model.segments,
                slope=slope,
                path=anim_path,
                swing_foot=int(getattr(model.module, "SWING_FOOT", -1)),
                title=title,
                ground=ground,
            )
            paths.append(anim_path)
    return paths


def n_q_of(model) -> int:
    """Number of configuration coordinates: states are (q, qd[, extra accumulators])."""
    names = model.state_names
    return (
        sum(
            1
            for n in names
            if not n.startswith(("qd", "theta_dot", "phi_dot"))
            and n not in ("actuator_work", "saturated_time")
        )
        if names
        else 0
    )


_LEG_SEGMENTS = ("leg", "thigh", "shank", "femur", "tibia")


def _has_masses(params) -> bool:
    """Whether the model has masses; without (simplest walker, rimless wheel) its
    energies are per unit mass [J/kg]."""
    return any(name.startswith("mass_") for name in params.names())


def _total_mass(params) -> float:
    """Total mass [kg]: every ``mass_*`` field, leg segments twice (two legs); 1 for the
    simplest walker, whose energies are per unit hip mass."""
    total = 0.0
    for name in params.names():
        if name.startswith("mass_"):
            twice = any(seg in name for seg in _LEG_SEGMENTS)
            total += (2.0 if twice else 1.0) * getattr(params, name)
    return total if total > 0 else 1.0


def plot_file(
    path,
    out_dir=".",
    *,
    gif: bool = False,
    figures: Sequence[str] | None = None,
    fmt: str = "png",
    dpi: int = 110,
) -> list[Path]:
    """Draw the figures that fit the result stored in ``path`` into ``out_dir``, each titled
    with the model and the scene (:func:`figure_title`).

    Parameters
    ----------
    path : str or Path
        a walker result file.
    out_dir : str or Path
        an existing directory; the figures are ``{stem}_{name}.{fmt}``.
    gif : bool
        also render a stored run as a stick-figure animation (``*_walk.gif``), which takes
        most of the time; by default it is not made.
    figures : sequence of str, optional
        which figures to draw, by name (:data:`FIGURES` lists them for each kind); only
        these are computed.  Default: every figure of the file's kind.
    fmt : {"png", "pdf", "svg"}
        file format of the figures.
    dpi : int
        resolution [dots per inch] of raster output (and of raster parts of PDF and SVG),
        1 to 2400.

    Raises
    ------
    walker.storage.StorageError
        the file is missing, damaged or not a walker result.
    FileNotFoundError
        ``out_dir`` does not exist.
    ValueError
        ``fmt`` or ``dpi`` is out of range; :class:`UnknownFigure` (a ValueError) when a
        name in ``figures`` is not a figure of the file's kind.
    """
    from walker.storage import read

    if fmt not in FORMATS:
        raise ValueError(f"`fmt` must be one of {', '.join(FORMATS)}, got {fmt!r}")
    if isinstance(dpi, bool) or not isinstance(dpi, int | np.integer) or not 1 <= dpi <= 2400:
        raise ValueError(f"`dpi` must be an integer in [1, 2400], got {dpi!r}")
    if figures is not None:
        figures = tuple(figures)
        known = {n for names in FIGURES.values() for n in names}
        unknown = [n for n in figures if n not in known]
        if unknown or not figures:
            raise UnknownFigure(
                f"unknown figure {', '.join(map(repr, unknown)) or '(none given)'}; "
                f"the figures are {', '.join(sorted(known))}"
            )
    out = Path(out_dir)
    if not out.is_dir():
        raise FileNotFoundError(f"--out: directory {str(out)!r} does not exist")
    result, prov = read(path)
    stem = Path(path).stem
    kind = prov["kind"]
    if kind not in FIGURES:
        raise ValueError(f"{path}: nothing to plot for a `{kind}` result")
    if figures is not None:
        wrong = [n for n in figures if n not in FIGURES[kind]]
        if wrong:
            raise UnknownFigure(
                f"a `{kind}` file has no figure {', '.join(map(repr, wrong))}; its figures "
                f"are {', '.join(FIGURES[kind])}"
            )
    names = FIGURES[kind] if figures is None else figures
    title = figure_title(prov)
    _OUTPUT["dpi"] = int(dpi)  # for this call's figures only
    try:
        if kind == "solution":
            model, params = _params_from_provenance(prov)
            rows = prov.get("terrain_rows") if figures is None else None
            return plot_solution(
                result,
                model,
                params,
                out,
                stem,
                gif=gif,
                names=names,
                fmt=fmt,
                title=title,
                terrain=rows,
            )
        drawn = _result_figures(result, prov, kind, names, Path(path).parent)
        return [_save(_titled(fig, title), out / f"{stem}_{name}.{fmt}") for name, fig in drawn]
    finally:
        _OUTPUT["dpi"] = 110


def _result_figures(result, prov: dict, kind: str, names, directory: Path):
    """``(name, figure)`` of each of ``names`` for a stored result other than a run, drawn
    one at a time (a generator: each figure is saved before the next is drawn)."""
    if kind == "fixed_point":
        branch = Branch(
            "",
            np.zeros(1),
            result.section[None, :],
            np.array([result.step_time]),
            result.multipliers[None, :],
            np.array([result.stable]),
            [],
            result.status,
            result.message,
            result.success,
            result.period,
        )
        yield "multipliers", plotting.plot_multipliers(branch)
    elif kind == "branch":
        model, params = _params_from_provenance(prov)
        for name in names:
            if name == "branch":
                from walker.plotting.branch import result_figures

                yield (
                    name,
                    result_figures(result, prov, model=model, params=params, directory=directory)[
                        "branch"
                    ],
                )
            elif name == "bifurcation":
                yield name, _bifurcation_figure(result, prov, model, params, directory)
            else:
                yield (
                    name,
                    plotting.plot_multipliers(
                        result, parameter_unit=_parameter_unit(prov, result.parameter_name)
                    ),
                )
    elif kind == "orbit_diagram":
        from walker.plotting.branch import result_figures

        model, params = _params_from_provenance(prov)
        yield (
            "orbit_diagram",
            result_figures(result, prov, model=model, params=params)["orbit_diagram"],
        )
    elif kind == "basin":
        yield "basin", _plot_basin(result, prov)
    elif kind == "mfpt":
        yield "survival", plotting.plot_survival(result)
    else:
        yield "sweep", _plot_sweep(result, prov)


def _bifurcation_figure(branch, prov: dict, model, params, directory: Path):
    """The bifurcation diagram of a stored branch, section coordinate 0 with its name and
    unit against the parameter with its unit; a branch of period k (and the period-doubled
    branch a ``walker continue --switch`` file names, drawn with it) shows all k points of
    its cycle, which :func:`walker.plotting.branch.branch_measures` computes."""
    from walker.plotting.branch import branch_measures, companion_branch

    names = tuple(model.section_names)
    options = {
        "parameter_unit": _parameter_unit(prov, branch.parameter_name),
        "coordinate_name": names[0] if names else None,
    }
    tolerances = {k: float(prov[k]) for k in ("rtol", "atol") if k in prov}

    def cycle(b):
        if int(getattr(b, "period", 1)) < 2:
            return None
        return branch_measures(b, model, params, **tolerances).cycle_sections

    fig = plotting.plot_bifurcation(branch, cycle_sections=cycle(branch), **options)
    other = companion_branch(prov, directory)
    if other is not None:
        plotting.plot_bifurcation(
            other, ax=fig.axes[0], cycle_sections=cycle(other), color="C2", **options
        )
    return fig


def _plot_basin(basin, prov: dict):
    """The basin figure, with the fixed point placed by the section coordinates the axes
    name (the model's ``section_names``)."""
    from walker.models import MODEL_NAMES, get_model

    coordinates = None
    if prov.get("model") in MODEL_NAMES:
        names = tuple(get_model(prov["model"]).section_names)
        axes = tuple(basin.axis_names)
        if len(names) == np.asarray(basin.fixed_point).size and all(a in names for a in axes):
            coordinates = (names.index(axes[0]), names.index(axes[1]))
    return plotting.plot_basin(basin, coordinates=coordinates)


def _parameter_unit(prov: dict, name: str) -> str | None:
    """Unit of parameter ``name`` from a file's provenance (or its model's metadata)."""
    entry = prov.get("parameters", {}).get(name)
    if isinstance(entry, dict) and entry.get("unit"):
        return str(entry["unit"])
    from walker.models import MODEL_NAMES, get_model

    if prov.get("model") in MODEL_NAMES:
        return get_model(prov["model"]).params_class.units().get(name)
    return None


def _plot_sweep(table, prov: dict):
    """The sweep figure (:func:`walker.plotting.plot_sweep`) with the parameters' units and
    the section coordinates' names from the file's provenance."""
    from walker.models import MODEL_NAMES, get_model
    from walker.storage import StorageError

    if "status" not in table.columns:
        raise StorageError("the sweep has no 'status' column; plotting needs it")
    section_names = None
    if prov.get("model") in MODEL_NAMES and "section" in table.columns:
        names = tuple(get_model(prov["model"]).section_names)
        if (
            len(names)
            == np.asarray(table.columns["section"]).reshape(len(table.points), -1).shape[1]
        ):
            section_names = names
    return plotting.plot_sweep(
        table,
        parameter_units=[_parameter_unit(prov, n) for n in table.parameter_names],
        section_names=section_names,
        n_strides=int(prov.get("n_strides", 1)),
    )
