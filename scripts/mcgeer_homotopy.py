"""Homotopy from the point-mass McGeer gait (gaits/kneed_mcgeer_pointmass.toml) to McGeer's
round-foot kneed walker (gaits/kneed_mcgeer_roundfoot.toml, preset ``mcgeer``), under the
swing-foot convention ``"ignore"``.

The path, one parameter at a time (arclength continuation with ``stop_at_fold``, a located
fold ends a stage):

0. ``g`` 9.81 -> 1: exact scaling (angles kept, rates times ``sqrt(1/9.81)``, times times
   ``sqrt(9.81)``), confirmed by Newton;
1. ``foot_radius`` 0 -> 0.2;
2. ``offset_shank`` 0 -> 0.01;
3. ``inertia_thigh`` 0 -> 0.1 * 0.135**2;
4. ``inertia_shank`` 0 -> 0.062 * 0.186**2.

At McGeer's slope 0.0456 the path ends at a fold in stage 2.  The script then follows the
same path at the steeper slope 0.12, where it reaches McGeer's full parameter set, and after
each stage continues that gait down in slope to the fold (the least slope of the branch):
the fold climbs past 0.0456 as the shank offset and the inertias come in.  Printed per
point: parameter, section (q1, qd1, qd2), step time, max |multiplier|.

``--reversed-offset`` also runs the path at 0.0456 with the shank offset taken backward
(``offset_shank`` 0 -> -0.01), which does reach a gait.  ``--grid N`` searches for gaits at
McGeer's full set and slope 0.0456 from N**3 seeds on a box around the branch.

Usage: python scripts/mcgeer_homotopy.py [--every K] [--reversed-offset] [--grid N]
"""

from __future__ import annotations

import argparse
import itertools
import math
from pathlib import Path

import numpy as np

from walker import load_scene
from walker.analysis.continuation import continue_branch
from walker.analysis.fixedpoint import find_fixed_point
from walker.models import get_model
from walker.params import KneedParams
from walker.simulation.stride import StrideMap

ROOT = Path(__file__).resolve().parents[1]
MODEL = get_model("kneed", swing_scuff="ignore")
MCGEER = KneedParams.mcgeer()
STAGES = ("foot_radius", "offset_shank", "inertia_thigh", "inertia_shank")
RTOL = 1e-11


def stride_map(params, name="slope", rtol=RTOL):
    return StrideMap(MODEL, params, rtol=rtol, atol=rtol, parameter_name=name)


def pointmass_gait_g1():
    """The point-mass gait scaled to g = 1: (params, section, FixedPoint)."""
    scene = load_scene(ROOT / "gaits" / "kneed_mcgeer_pointmass.toml")
    k = math.sqrt(1.0 / scene.params.g)
    params = scene.params.replace(g=1.0)
    P = stride_map(params)
    z = P.project(scene.state) * np.array([1.0, k, k])
    fp = find_fixed_point(P, z)
    return params, fp.section, fp


def continue_in(params, z, name, target, **kw):
    """Continue the gait near ``z`` at ``params`` in parameter ``name`` to ``target``,
    stopping at the first fold."""
    P = stride_map(params, name)
    return continue_branch(P, z, to=target, stop_at_fold=True, **kw)


def reached(branch, target):
    return branch.success and math.isclose(branch.parameter[-1], target, abs_tol=1e-14)


def print_branch(branch, every=1):
    n = len(branch.parameter)
    for i, (mu, z, T, m) in enumerate(
        zip(branch.parameter, branch.sections, branch.step_times, branch.multipliers, strict=True)
    ):
        if i % every == 0 or i == n - 1:
            zs = ", ".join(f"{v: .6f}" for v in z)
            print(
                f"  {branch.parameter_name} = {mu:.6g}  z = [{zs}]  T = {T:.6f}"
                f"  max|lambda| = {np.abs(m).max():.4f}"
            )
    for b in branch.bifurcations:
        print(f"  {b.kind} at {branch.parameter_name} = {b.parameter_value:.10g}")


def run_path(params, z, targets, every):
    """Follow the stages in order; returns (params, z, ended) with ``ended`` the stage name
    where a fold ended the path (None when it reached McGeer's set)."""
    for name, target in targets:
        print(f"{name}: {getattr(params, name):g} -> {target:g} (slope {params.slope:g})")
        br = continue_in(params, z, name, target)
        print_branch(br, every)
        if not reached(br, target):
            print(f"  ENDS: {br.status.name}: {br.message}")
            return params.replace(**{name: float(br.parameter[-1])}), br.sections[-1], name
        params, z = params.replace(**{name: target}), br.sections[-1]
    return params, z, None


def slope_fold(params, z):
    """Continue the gait at ``params`` (section ``z``) down in slope to its fold."""
    br = continue_in(params, z, "slope", 0.005)
    folds = [b for b in br.bifurcations if b.kind == "fold"]
    return (folds[0].parameter_value if folds else math.nan), br


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--every", type=int, default=5, help="print every K-th point (5)")
    parser.add_argument("--reversed-offset", action="store_true")
    parser.add_argument("--grid", type=int, default=0, help="seeds per axis (0: no search)")
    args = parser.parse_args(argv)

    p1, z1, fp = pointmass_gait_g1()
    print(
        f"point-mass gait at g = 1: z = {z1}, T = {fp.step_time:.10f} "
        f"(= 0.801217323 s * sqrt(9.81)), max|lambda| = {np.abs(fp.multipliers).max():.6f}"
    )
    targets = [(n, getattr(MCGEER, n)) for n in STAGES]

    print("\n== the path at McGeer's slope 0.0456")
    run_path(p1, z1, targets, args.every)

    print("\n== the path at slope 0.12, and the least slope of the branch after each stage")
    br = continue_in(p1, z1, "slope", 0.12)
    params, z = p1.replace(slope=0.12), br.sections[-1]
    fold, _ = slope_fold(params, z)
    print(f"point masses, g = 1: fold at slope {fold:.6f}")
    for name, target in targets:
        br = continue_in(params, z, name, target)
        if not reached(br, target):
            print(f"{name}: ENDS at {br.parameter[-1]:.6g}: {br.message}")
            return
        params, z = params.replace(**{name: target}), br.sections[-1]
        fold, _ = slope_fold(params, z)
        print(f"+ {name} = {target:g}: fold at slope {fold:.6f}")
    print(f"McGeer's set (slope 0.12): z = {z}")
    _, down = slope_fold(params, z)
    print("its branch down in slope:")
    print_branch(down, args.every)

    if args.reversed_offset:
        print("\n== the path at slope 0.0456 with offset_shank -> -0.01 (reversed)")
        rev = [(n, -t if n == "offset_shank" else t) for n, t in targets]
        params, z, ended = run_path(p1, z1, rev, args.every)
        if ended is None:
            fp = find_fixed_point(stride_map(params, rtol=1e-12), z)
            print(
                f"gait: state = {fp.state}, T = {fp.step_time:.8f}, "
                f"|lambda| = {np.abs(fp.multipliers)}"
            )

    if args.grid:
        n = args.grid
        print(f"\n== {n}**3 seeds at McGeer's set, slope 0.0456")
        P = stride_map(MCGEER, rtol=1e-10)
        counts, found = {}, []
        box = (np.linspace(0.08, 0.45, n), np.linspace(-0.7, -0.1, n), np.linspace(-0.8, 0.4, n))
        for seed in itertools.product(*box):
            r = find_fixed_point(P, np.array(seed), tol=1e-9)
            counts[r.status.name] = counts.get(r.status.name, 0) + 1
            if r.success and not any(np.abs(r.section - f).max() < 1e-6 for f in found):
                found.append(r.section)
                print(f"  gait {r.section}, T = {r.step_time:.6f}")
        print(f"  outcomes: {counts}; distinct gaits: {len(found)}")


if __name__ == "__main__":
    main()
