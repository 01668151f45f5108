"""Regenerate the figure gallery under results/gallery/ from the shipped scenes.

One figure of each kind: joint angles with phases shaded, energy with impact losses, a phase
portrait, a stick-figure GIF (kneed walker); a continuation branch with its period doubling
and the root locus of its multipliers (simplest walker); an orbit diagram and a basin of
attraction (compass gait); actuator torques and the zero dynamics (three-link walker).
Each of these results is also stored as HDF5 next to its figures, and the figures are drawn
from those files (the same path ``walker plot`` takes).

Two figures are drawn here directly, from computed data (no HDF5): the rimless wheel rolling
onto its closed-form gait (:func:`rimless_wheel_figure`), and the elbow manipulator tracking a
circle in operational space (:func:`taskspace_figure`, the figure of
``scripts/taskspace_circle.py``).

Usage: python scripts/gallery.py [--quick] [JOB ...]   (JOB: a function name below)
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from scipy.optimize import brentq  # noqa: E402

from walker import StrideMap, load_scene  # noqa: E402
from walker.analysis.basin import basin_map  # noqa: E402
from walker.analysis.continuation import continue_branch, orbit_diagram  # noqa: E402
from walker.analysis.fixedpoint import find_fixed_point  # noqa: E402
from walker.cli import provenance  # noqa: E402
from walker.plotting.gallery import plot_file  # noqa: E402
from walker.simulation.stride import simulate  # noqa: E402
from walker.storage import write  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "gallery"
DPI = 110  # as walker.plotting.gallery's figures


def _scene(name):
    return load_scene(ROOT / "gaits" / f"{name}.toml")


def _store_and_plot(result, scene, name):
    path = OUT / f"{name}.h5"
    write(path, result, provenance=provenance(scene, out=path), overwrite=True)
    return plot_file(path, OUT, gif=True)


def kneed_walk(quick):
    scene = _scene("kneed_hsu")
    P = StrideMap("kneed", scene.params)
    fp = find_fixed_point(P, P.project(scene.state))
    first = simulate("kneed", scene.params, fp.state, n_strides=4, output="events")
    times = np.linspace(0.0, first.t, 200 if quick else 600)
    sol = simulate(
        "kneed", scene.params, fp.state, n_strides=4, output="samples", sample_times=times
    )
    return _store_and_plot(sol, scene, "kneed_walk")


def simplest_branch(quick):
    scene = _scene("simplest_garcia")
    P = StrideMap("simplest", scene.params)
    fp = find_fixed_point(P, P.project(scene.state))
    branch = continue_branch(P, fp.section, to=0.019)
    return _store_and_plot(branch, scene, "simplest_branch")


def compass_orbits(quick):
    scene = _scene("compass_goswami")
    P = StrideMap("compass", scene.params, rtol=1e-10, atol=1e-10)
    fp = find_fixed_point(P, P.project(scene.state))
    slopes = np.linspace(0.05, 0.095, 60 if quick else 200)
    od = orbit_diagram(P, fp.section, slopes, n_transient=100 if quick else 300, n_keep=32)
    return _store_and_plot(od, scene, "compass_orbit_diagram")


def compass_basin(quick):
    scene = _scene("compass_goswami")
    P = StrideMap("compass", scene.params, rtol=1e-9, atol=1e-9)
    fp = find_fixed_point(P, P.project(scene.state))
    n = 40 if quick else 100
    bm = basin_map(
        P,
        fp,
        axes=(1, 2),
        ranges=((-2.0, -0.4), (-2.0, 1.5)),
        n=(n, n),
        n_strides=40,
        progress=False,
    )
    return _store_and_plot(bm, scene, "compass_basin")


def compass_sweep(quick):
    """The compass gait's fixed points over slope and hip mass: a two-parameter sweep's heat
    maps (status, step time, largest multiplier; colour limits robust to far values, which
    are drawn as crosses)."""
    from walker.analysis.sweep import sweep

    scene = _scene("compass_goswami")
    P = StrideMap("compass", scene.params, rtol=1e-10, atol=1e-10)
    fp = find_fixed_point(P, P.project(scene.state))
    n = 8 if quick else 16
    table = sweep(
        P,
        {"slope": np.linspace(0.01, 0.09, n), "mass_hip": np.linspace(5.0, 20.0, n)},
        kind="fixed_point",
        z0=fp.section,
        executor="serial",
        progress=False,
    )
    return _store_and_plot(table, scene, "compass_sweep")


def three_link_walk(quick):
    scene = _scene("three_link_grizzle")
    first = simulate("three_link", scene.params, scene.state, n_strides=3, output="events")
    times = np.linspace(0.0, first.t, 200 if quick else 500)
    sol = simulate(
        "three_link",
        scene.params,
        scene.state,
        n_strides=3,
        output="samples",
        sample_times=times,
    )
    return _store_and_plot(sol, scene, "three_link_walk")


def kneed_coulomb_walk(quick):
    """Two strides of the kneed walker with dry knee and ankle friction: the knee sticks
    where its rate reverses (the shaded stick interval in the angle plot)."""
    scene = _scene("kneed_coulomb_hsu")
    state = scene.reference["state"]
    first = simulate("kneed_coulomb", scene.params, state, n_strides=2, output="events")
    times = np.linspace(0.0, first.t, 200 if quick else 600)
    sol = simulate(
        "kneed_coulomb",
        scene.params,
        state,
        n_strides=2,
        output="samples",
        sample_times=times,
    )
    return _store_and_plot(sol, scene, "kneed_coulomb_walk")


# ---- rimless wheel: rolling onto the closed-form gait -------------------------------------
def rimless_closed_form(params) -> tuple[float, float]:
    """The rimless wheel's rolling gait in closed form: ``(theta_dot*, multiplier)``, the
    rate just after an impact [rad/s] and the one Floquet multiplier (5 spokes or more).

    With ``alpha = pi / spokes``, ``gamma`` the slope and ``theta`` the stance spoke's angle
    from the slope normal (rolling downhill from ``alpha`` to ``-alpha``, rate ``w < 0``):

    * stance: the energy ``l^2 w^2 / 2 + g l cos(theta - gamma)`` is conserved, so the rate
      ``w-`` reaching ``-alpha`` from ``w+`` at ``alpha`` obeys
      ``w-^2 = w+^2 + K``, ``K = 2 (g/l) (cos(alpha - gamma) - cos(alpha + gamma))
      = 4 (g/l) sin(alpha) sin(gamma)``;
    * impact: the impulse acts at the new foot, so the angular momentum about it is kept;
      the hub velocity ``l w-`` (perpendicular to the old spoke, at ``2 alpha`` from the new
      one) has the moment ``l^2 w- cos(2 alpha)`` about it, so ``w+ = c w-``,
      ``c = cos(2 alpha)``;
    * the map ``P(w) = -c sqrt(w^2 + K)`` has the fixed point ``w*^2 = c^2 (w*^2 + K)``:
      ``w* = -c sqrt(K / (1 - c^2)) = -cot(2 alpha) sqrt(K)``, and
      ``P'(w*) = -c w* / sqrt(w*^2 + K) = c^2``.
    """
    alpha = math.pi / params.spokes
    c = math.cos(2.0 * alpha)
    k = 4.0 * params.g / params.leg_length * math.sin(alpha) * math.sin(params.slope)
    return -c * math.sqrt(k / (1.0 - c * c)), c * c


def _rimless_stance_rate(params, w_plus, theta):
    """Rate [rad/s] at ``theta`` of the stance that leaves ``alpha`` at ``w_plus`` (energy)."""
    alpha = math.pi / params.spokes
    gl = params.g / params.leg_length
    gamma = params.slope
    return -np.sqrt(w_plus**2 + 2.0 * gl * (np.cos(alpha - gamma) - np.cos(theta - gamma)))


def rimless_critical_slope(params) -> float:
    """The slope [rad] below which the closed-form gait does not get over the top
    (``theta = gamma``) between impacts, so the wheel only stands:
    ``w*^2 = 2 (g/l) (1 - cos(alpha - gamma))``."""
    alpha = math.pi / params.spokes
    gl = params.g / params.leg_length

    def margin(slope):
        w = rimless_closed_form(params.replace(slope=slope))[0]
        return w * w - 2.0 * gl * (1.0 - math.cos(alpha - slope))

    return brentq(margin, 1e-9, alpha, xtol=1e-15)


RIMLESS_STARTS = (-2.5, -1.0)
"""Rates just after an impact [rad/s] the gallery's runs start from: above and below the
gait's (the slower one just gets over the top)."""
RIMLESS_TIGHT = {"rtol": 1e-12, "atol": 1e-12}


def _rimless_run(params, w0, n_strides, n_per_stride):
    """``n_strides`` strides from ``(alpha, w0)``: the stance arcs (one array of
    ``(theta, theta_dot)`` per stride, from the exact post-impact to the exact pre-impact
    state) and the rates just after each impact, ``w0`` first."""
    alpha = math.pi / params.spokes
    x0 = [alpha, w0]
    sol = simulate(
        "rimless_wheel", params, x0, n_strides=n_strides, output="events", **RIMLESS_TIGHT
    )
    if sol.n_strides != n_strides:
        raise RuntimeError(f"rimless wheel from {w0} rad/s: {sol.status.name} ({sol.message})")
    ev = sol.events
    times = np.linspace(0.0, ev.t[-1], n_strides * n_per_stride)
    samples = simulate(
        "rimless_wheel",
        params,
        x0,
        n_strides=n_strides,
        output="samples",
        sample_times=times,
        **RIMLESS_TIGHT,
    ).samples
    arcs, start, t_start = [], np.asarray(x0, dtype=float), 0.0
    for t_end, pre, post in zip(ev.t, ev.x_pre, ev.x_post, strict=True):
        inside = (samples.t > t_start) & (samples.t < t_end)
        arcs.append(np.vstack([start, samples.x[inside], pre]))
        start, t_start = np.asarray(post, dtype=float), t_end
    return arcs, np.concatenate([[w0], ev.x_post[:, 1]]), np.asarray(ev.x_pre[:, 1])


def rimless_wheel_figure(out, *, n_strides=10, n_slopes=12, n_per_stride=60):
    """The rimless wheel of ``gaits/rimless_wheel.toml`` rolling onto its gait, written as
    ``rimless_wheel_rolling.png`` into ``out``: (1) the stance phase portrait of runs from
    :data:`RIMLESS_STARTS`, ``n_strides`` strides each, with the closed-form gait
    (:func:`rimless_closed_form`) marked; (2) the distance of each post-impact rate from the
    closed form against the stride, next to the closed-form multiplier ``cos^2(2 alpha)``;
    (3) the rate just after and just before impact against the slope: the closed form, and
    walker's fixed points (``find_fixed_point``) at ``n_slopes`` slopes.

    Returns ``(path, data)``: ``data`` holds what is plotted (``fixed_point_rate``, the
    closed-form rate marked in (1); ``walker_rates`` at ``walker_slopes`` in (3); ...).
    """
    scene = _scene("rimless_wheel")
    prm = scene.params
    alpha = math.pi / prm.spokes
    c = math.cos(2.0 * alpha)
    w_star, multiplier = rimless_closed_form(prm)
    P = StrideMap("rimless_wheel", prm, **RIMLESS_TIGHT)
    fp = find_fixed_point(P, np.array([RIMLESS_STARTS[0]]), tol=1e-13)
    if not fp.success:
        raise RuntimeError(f"rimless wheel: no gait found at the scene's slope: {fp.message}")
    runs = []
    for w0 in RIMLESS_STARTS:
        arcs, post, pre = _rimless_run(prm, w0, n_strides, n_per_stride)
        runs.append(
            {"start_rate": w0, "arcs": arcs, "post_impact_rates": post, "pre_impact_rates": pre}
        )

    critical = rimless_critical_slope(prm)
    top = 0.35  # [rad], below alpha: the wheel can also stand
    slopes = np.linspace(critical, top, 200)
    curve = np.array([rimless_closed_form(prm.replace(slope=g))[0] for g in slopes])
    walker_slopes = np.linspace(critical + 0.1 * (top - critical), top, n_slopes)
    walker_rates, walker_pre, guess = [], [], fp.section
    for g in walker_slopes:
        pg = prm.replace(slope=float(g))
        gait = find_fixed_point(StrideMap("rimless_wheel", pg, **RIMLESS_TIGHT), guess, tol=1e-13)
        if not gait.success:
            raise RuntimeError(f"rimless wheel: no gait found at slope {g}: {gait.message}")
        stride = simulate(
            "rimless_wheel", pg, gait.state, n_strides=1, output="events", **RIMLESS_TIGHT
        )
        walker_rates.append(gait.section[0])
        walker_pre.append(stride.events.x_pre[0][1])
        guess = gait.section
    walker_rates, walker_pre = np.array(walker_rates), np.array(walker_pre)

    td = r"$\dot\theta$"
    fig = Figure(figsize=(15.0, 4.8), layout="constrained")
    ax_pp, ax_conv, ax_slope = fig.subplots(1, 3)
    for i, run in enumerate(runs):
        color = f"C{i}"
        for k, arc in enumerate(run["arcs"]):
            label = f"from {td} = {run['start_rate']:g} rad/s" if k == 0 else None
            ax_pp.plot(arc[:, 0], arc[:, 1], color=color, lw=1.0, label=label)
            after = run["post_impact_rates"][k + 1]
            ax_pp.plot([arc[-1, 0], alpha], [arc[-1, 1], after], color=color, lw=0.6, ls=":")
    theta = np.linspace(-alpha, alpha, 200)
    ax_pp.plot(
        theta, _rimless_stance_rate(prm, w_star, theta), "k--", lw=1.4, label="closed-form gait"
    )
    ax_pp.plot(
        [alpha],
        [w_star],
        "k*",
        ms=12,
        label=rf"{td}* = $-\cot 2\alpha\,\sqrt{{4 (g/l) \sin\alpha \sin\gamma}}$"
        f" = {w_star:.6f} rad/s (after impact)",
    )
    ax_pp.plot(
        [-alpha],
        [w_star / c],
        "ko",
        mfc="none",
        ms=7,
        label=rf"{td}*$/\cos 2\alpha$ = {w_star / c:.6f} rad/s (before impact)",
    )
    low = min(float(np.min(arc[:, 1])) for run in runs for arc in run["arcs"])
    ax_pp.set_ylim(low - 0.1, 1.2)
    ax_pp.set_xlabel(r"stance spoke angle $\theta$ from the slope normal [rad]")
    ax_pp.set_ylabel(f"{td} [rad/s]")
    ax_pp.set_title(f"stance phase portrait, {n_strides} strides (dotted: impacts)")
    ax_pp.legend(fontsize=7, loc="upper center")

    strides = np.arange(n_strides + 1)
    for i, run in enumerate(runs):
        errors = np.abs(run["post_impact_rates"] - w_star)
        ax_conv.semilogy(
            strides, errors, f"C{i}o-", ms=4, label=f"from {td} = {run['start_rate']:g} rad/s"
        )
        # the closed-form multiplier's slope, through the last stride
        ax_conv.semilogy(strides, errors[-1] * multiplier ** (strides - n_strides), "k:", lw=1.0)
    ax_conv.plot(
        [], [], "k:", label=rf"$\times \cos^2 2\alpha$ = {multiplier:.6g} per stride (closed form)"
    )
    ax_conv.plot([], [], " ", label=f"walker's multiplier: {fp.multipliers[0].real:.12f}")
    ax_conv.set_xlabel("stride k")
    ax_conv.set_ylabel(r"$|\dot\theta_k - \dot\theta^*|$ just after impact k [rad/s]")
    ax_conv.set_title("convergence to the closed-form rate")
    ax_conv.legend(fontsize=7)

    ax_slope.plot(slopes, curve, "k-", lw=1.2, label="just after impact, closed form")
    ax_slope.plot(slopes, curve / c, "k--", lw=1.2, label="just before impact, closed form")
    ax_slope.plot(
        walker_slopes, walker_rates, "C3o", ms=5, mfc="none", label="walker's fixed points (after)"
    )
    ax_slope.plot(
        walker_slopes, walker_pre, "C2s", ms=5, mfc="none", label="walker's fixed points (before)"
    )
    ax_slope.axvspan(
        0.0, critical, color="0.9", label=f"below {critical:.4f} rad: the wheel only stands"
    )
    ax_slope.axvline(
        prm.slope, color="0.5", lw=0.8, ls=":", label=f"slope {prm.slope:g} rad (left panels)"
    )
    ax_slope.set_xlim(0.0, top)
    ax_slope.set_xlabel(r"slope $\gamma$ [rad]")
    ax_slope.set_ylabel(f"rolling gait's {td} at impact [rad/s]")
    ax_slope.set_title(f"rate at impact against slope ({prm.spokes:g} spokes)")
    ax_slope.legend(fontsize=7, loc="lower left")

    fig.suptitle(
        f"rimless wheel ({prm.spokes:g} spokes, l = {prm.leg_length:g} m, "
        f"slope {prm.slope:g} rad): rolling converges to the closed-form gait"
    )
    path = Path(out) / "rimless_wheel_rolling.png"
    fig.savefig(path, dpi=DPI)
    data = {
        "params": prm,
        "fixed_point_rate": w_star,
        "multiplier": multiplier,
        "walker_fixed_point_rate": float(fp.section[0]),
        "walker_multiplier": complex(fp.multipliers[0]),
        "runs": runs,
        "critical_slope": critical,
        "slopes": slopes,
        "closed_form_rates": curve,
        "walker_slopes": walker_slopes,
        "walker_rates": walker_rates,
        "walker_pre_impact_rates": walker_pre,
    }
    return path, data


def rimless_wheel(quick):
    return [rimless_wheel_figure(OUT, n_slopes=6 if quick else 12)[0]]


# ---- task space: the elbow manipulator tracks a circle ------------------------------------
def _taskspace_script():
    """``scripts/taskspace_circle.py`` as a module (scripts/ is not a package)."""
    name = "walker_taskspace_circle"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(
            name, ROOT / "scripts" / "taskspace_circle.py"
        )
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module  # its dataclasses look their module up
        spec.loader.exec_module(module)
    return sys.modules[name]


def taskspace_figure(out, *, t_final=4.0, n_samples=801):
    """The figure of ``scripts/taskspace_circle.py`` (its :func:`track_example` run, drawn
    by its :func:`plot_tracking`) under a title, written as ``taskspace_circle_tracking.png``
    into ``out``.  Returns ``(path, run)``."""
    script = _taskspace_script()
    run, circle, _ = script.track_example(t_final=t_final, n_samples=n_samples)
    fig = script.plot_tracking(run, circle)
    fig.suptitle("planar elbow manipulator: its tip tracks a circle (operational space)")
    path = Path(out) / "taskspace_circle_tracking.png"
    fig.savefig(path, dpi=DPI)
    return path, run


def taskspace_circle(quick):
    return [taskspace_figure(OUT, n_samples=401 if quick else 801)[0]]


JOBS = {
    job.__name__: job
    for job in (
        kneed_walk,
        simplest_branch,
        compass_orbits,
        compass_basin,
        compass_sweep,
        three_link_walk,
        kneed_coulomb_walk,
        rimless_wheel,
        taskspace_circle,
    )
}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="coarser grids")
    parser.add_argument(
        "jobs", nargs="*", choices=[[], *JOBS], default=[], help="figures to redo (default all)"
    )
    args = parser.parse_args(argv)
    OUT.mkdir(parents=True, exist_ok=True)
    for job in [JOBS[name] for name in args.jobs] or JOBS.values():
        t = time.perf_counter()
        paths = job(args.quick)
        print(
            f"{job.__name__}: {time.perf_counter() - t:.1f} s -> "
            + ", ".join(p.name for p in paths)
        )


if __name__ == "__main__":
    main()
