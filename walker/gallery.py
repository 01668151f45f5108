"""Figures from stored results: what ``walker plot FILE.h5`` draws.

Each function writes PNG (and GIF) files into a directory and returns their paths; the
drawing itself is done by :mod:`walker.plotting`, the physics (energies, joint positions) by
the model named in the file's provenance.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from walker import plotting
from walker.results import Branch, Solution, Trajectory

__all__ = ["plot_file", "plot_solution", "walker_frames"]


def _save(fig, path: Path) -> Path:
    fig.savefig(path, dpi=110)
    return path


FRICTION_PREFIXES = ("damping_", "coulomb_")
"""Joint-friction parameters; files written before a model had them lack them."""


def _params_from_provenance(prov: dict):
    """The model and parameters a file was computed with.

    A file written before a joint-friction parameter (``damping_*``, ``coulomb_*``) was added
    to its model lacks it; it was computed without that friction, so it reads as 0, with a
    warning naming the parameters.  Any other missing parameter is an error.
    """
    from walker.models import get_model

    model = get_model(prov["model"])
    values = {k: v["value"] for k, v in prov["parameters"].items()}
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


def walker_frames(model, params, t, x, events=None) -> np.ndarray:
    """Joint positions in the world frame for each sample, following the walker down the
    slope: after every heel strike in ``events`` the new stance foot is placed where the
    swing foot landed.

    Parameters
    ----------
    model : WalkerModel
    params : the model's parameter dataclass
    t : ndarray, shape (n,)
    x : ndarray, shape (n, n_x)
    events : EventLog, optional
        a heel strike is an event after which the legs have swapped (the new stance angle
        is the old swing angle); without events the stance foot stays at the origin.

    Returns
    -------
    ndarray, shape (n, n_points, 2)
    """
    p = params.as_array()
    strike_t, steps = [], []
    if events is not None:
        for i in range(len(events)):
            pre, post = events.x_pre[i], events.x_post[i]
            if post[0] == pre[1] and post[0] != pre[0]:
                pts = model.points(pre, p)
                swing = getattr(model.module, "SWING_FOOT", -1)
                strike_t.append(events.t[i])
                steps.append(pts[swing] - pts[0])
    offsets = np.zeros((len(t), 2))
    for te, step in zip(strike_t, steps, strict=True):
        offsets[np.asarray(t) > te] += step
    return np.array([model.points(row, p) for row in x]) + offsets[:, None, :]


def _impact_times(events, n_q: int) -> np.ndarray | None:
    """Times of the events that change the rates (impacts), leaving out mode switches such
    as a joint that starts or stops sticking, where the state is continuous."""
    if events is None:
        return None
    pre = np.asarray(events.x_pre)[:, n_q : 2 * n_q]
    post = np.asarray(events.x_post)[:, n_q : 2 * n_q]
    scale = np.maximum(1.0, np.max(np.abs(pre), axis=1)) if len(pre) else np.ones(0)
    jumps = np.max(np.abs(post - pre), axis=1) if len(pre) else np.zeros(0)
    return np.asarray(events.t)[jumps > 1e-9 * scale]


def plot_solution(sol: Solution, model, params, out: Path, stem: str) -> list[Path]:
    """Angles, energy, a phase portrait, (for actuated walkers) torques and the zero
    dynamics, and (for walkers) a stick-figure GIF."""
    traj = sol.record if sol.record is not None else sol.samples
    n_q = n_q_of(model)
    # angles and rates only (actuated models carry accumulators after them)
    shown = traj if traj is None else Trajectory(traj.t, traj.x[:, : 2 * n_q], traj.phase)
    angles = plotting.plot_angles(
        shown if shown is not None else sol,
        state_names=model.state_names[: 2 * n_q],
        phase_names=model.phase_names,
    )
    if shown is not None and sol.events is not None:
        for ax in angles.axes:
            for te in sol.events.t:
                ax.axvline(te, color="0.5", linestyle=":", linewidth=0.8)
    paths = [_save(angles, out / f"{stem}_angles.png")]
    if traj is None or len(traj) < 2:
        return paths
    kinetic, potential = model.energies(traj.x, params)
    if model.is_walker:
        # Potential energy relative to the current stance foot jumps at each heel strike;
        # refer it to the world frame by the accumulated drop of the stance foot.
        frames = walker_frames(model, params, traj.t, traj.x, sol.events)
        total_mass = _total_mass(params)
        potential = potential + total_mass * params.g * (frames[:, 0, 1] - frames[0, 0, 1])
    events = _impact_times(sol.events, n_q)
    paths.append(
        _save(
            plotting.plot_energy(traj.t, kinetic, potential, event_times=events),
            out / f"{stem}_energy.png",
        )
    )
    paths.append(
        _save(
            plotting.plot_phase_portrait(traj, 0, n_q, state_names=model.state_names),
            out / f"{stem}_phase_portrait.png",
        )
    )
    if hasattr(model.module, "torques"):
        pp = params.as_array()
        u = np.array([model.module.torques(np.ascontiguousarray(row), pp) for row in traj.x])
        limit = getattr(params, "torque_limit", None)
        paths.append(
            _save(
                plotting.plot_torques(traj.t, u, limit=limit, event_times=events),
                out / f"{stem}_torques.png",
            )
        )
        tp, tm = getattr(params, "theta_plus", None), getattr(params, "theta_minus", None)
        paths.append(
            _save(
                plotting.plot_zero_dynamics(
                    traj.x[:, 0], traj.x[:, n_q_of(model)], theta_plus=tp, theta_minus=tm
                ),
                out / f"{stem}_zero_dynamics.png",
            )
        )
    if model.is_walker or model.name == "double_pendulum":
        t_frames = np.linspace(traj.t[0], traj.t[-1], min(120, len(traj)))
        idx = np.searchsorted(traj.t, t_frames).clip(0, len(traj) - 1)
        if model.is_walker:
            frames = walker_frames(model, params, traj.t, traj.x, sol.events)[idx]
        else:
            frames = np.array([model.points(traj.x[i], params) for i in idx])
        slope = float(getattr(params, "slope", 0.0))
        anim_path = out / f"{stem}_walk.gif"
        plotting.animate_walker(frames, model.segments, slope=slope, path=anim_path)
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


def _total_mass(params) -> float:
    """Total mass [kg]: every ``mass_*`` field, leg segments twice (two legs); 1 for the
    simplest walker, whose energies are per unit hip mass."""
    total = 0.0
    for name in params.names():
        if name.startswith("mass_"):
            twice = any(seg in name for seg in _LEG_SEGMENTS)
            total += (2.0 if twice else 1.0) * getattr(params, name)
    return total if total > 0 else 1.0


def plot_file(path, out_dir=".") -> list[Path]:
    """Draw every figure that fits the result stored in ``path`` into ``out_dir``.

    Raises
    ------
    walker.storage.StorageError
        the file is missing, damaged or not a walker result.
    FileNotFoundError
        ``out_dir`` does not exist.
    """
    from walker.storage import read

    out = Path(out_dir)
    if not out.is_dir():
        raise FileNotFoundError(f"--out: directory {str(out)!r} does not exist")
    result, prov = read(path)
    stem = Path(path).stem
    kind = prov["kind"]
    if kind == "solution":
        model, params = _params_from_provenance(prov)
        return plot_solution(result, model, params, out, stem)
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
        return [_save(plotting.plot_multipliers(branch), out / f"{stem}_multipliers.png")]
    if kind == "branch":
        fig = plotting.plot_bifurcation(result)
        _label_section(fig, prov, 0)
        return [
            _save(fig, out / f"{stem}_bifurcation.png"),
            _save(plotting.plot_multipliers(result), out / f"{stem}_multipliers.png"),
        ]
    if kind == "orbit_diagram":
        fig = plotting.plot_orbit_diagram(result)
        _label_section(fig, prov, result.coordinate)
        return [_save(fig, out / f"{stem}_orbit_diagram.png")]
    if kind == "basin":
        return [_save(plotting.plot_basin(result), out / f"{stem}_basin.png")]
    if kind == "sweep":
        return [_save(_plot_sweep(result), out / f"{stem}_sweep.png")]
    raise ValueError(f"{path}: nothing to plot for a `{kind}` result")


def _label_section(fig, prov, coordinate):
    """Name the section coordinate on the y axis when the model is known."""
    from walker.models import MODEL_NAMES, get_model

    if prov.get("model") in MODEL_NAMES:
        names = get_model(prov["model"]).section_names
        if coordinate < len(names):
            fig.axes[0].set_ylabel(f"{names[coordinate]} just after heel strike")


def _plot_sweep(table):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.8), layout="constrained")
    ax = fig.add_subplot()
    x = table.points[:, 0]
    status = table.columns["status"]
    ok = status == 0
    if "section" in table.columns:
        sec = table.columns["section"]
        for j in range(sec.shape[1]):
            ax.plot(x[ok], sec[ok, j], ".", label=f"section[{j}]")
    ax.plot(x[~ok], np.zeros(np.sum(~ok)), "x", color="red", label="failed")
    ax.set_xlabel(table.parameter_names[0])
    ax.set_ylabel("value")
    ax.legend()
    return fig
