"""Regenerate the figure gallery under results/gallery/ from the shipped scenes.

One figure of each kind: joint angles with phases shaded, energy with impact losses, a phase
portrait, a stick-figure GIF (kneed walker); a continuation branch with its period doubling
and the root locus of its multipliers (simplest walker); an orbit diagram and a basin of
attraction (compass gait); actuator torques and the zero dynamics (three-link walker).
Each result is also stored as HDF5 next to its figures, and the figures are drawn from those
files (the same path ``walker plot`` takes).

Usage: python scripts/gallery.py [--quick] [JOB ...]   (JOB: a function name below)
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402

from walker import StrideMap, load_scene  # noqa: E402
from walker.basin import basin_map  # noqa: E402
from walker.cli import provenance  # noqa: E402
from walker.continuation import continue_branch, orbit_diagram  # noqa: E402
from walker.fixedpoint import find_fixed_point  # noqa: E402
from walker.gallery import plot_file  # noqa: E402
from walker.storage import write  # noqa: E402
from walker.stride import simulate  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "gallery"


def _scene(name):
    return load_scene(ROOT / "gaits" / f"{name}.toml")


def _store_and_plot(result, scene, name):
    path = OUT / f"{name}.h5"
    write(path, result, provenance=provenance(scene), overwrite=True)
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


JOBS = {
    job.__name__: job
    for job in (
        kneed_walk,
        simplest_branch,
        compass_orbits,
        compass_basin,
        three_link_walk,
        kneed_coulomb_walk,
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
