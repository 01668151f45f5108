"""Print walker's own high-accuracy gaits for the shipped scenes as TOML [reference] tables
(the values recorded in gaits/*.toml), with the spread over tolerances 1e-11..1e-13 as the
defensible accuracy.

Usage: python scripts/reference_values.py [SCENE ...]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from walker import StrideMap, load_scene
from walker.analysis.fixedpoint import find_fixed_point
from walker.models import get_model

ROOT = Path(__file__).resolve().parents[1]
SCENES = (
    "simplest_garcia",
    "compass_goswami",
    "kneed_hsu",
    "kneed_mcgeer_roundfoot",
    "kneed_mcgeer_pointmass",
    "kneed_coulomb_hsu",
    "compass_coulomb_goswami",
)


def reference(scene_name: str) -> str:
    scene = load_scene(ROOT / "gaits" / f"{scene_name}.toml")
    results = []
    for tol in (1e-11, 1e-12, 1e-13):
        model = get_model(scene.model, swing_scuff=scene.swing_scuff)
        P = StrideMap(model, scene.params, rtol=tol, atol=tol)
        fp = find_fixed_point(P, P.project(scene.state), tol=1e-13)
        if not fp.success:
            return f"# {scene_name}: {fp.status.name}: {fp.message}"
        results.append(fp)
    best = results[-1]
    spread = max(np.abs(r.state - best.state).max() for r in results[:-1])
    mspread = max(np.abs(r.multipliers - best.multipliers).max() for r in results[:-1])
    tol = float(f"{max(spread, mspread, 1e-13) * 10:.0e}")
    fmt = ", ".join(f"{v:.15g}" for v in best.state)
    mult = ", ".join(f"[{m.real:.13g}, {m.imag:.13g}]" for m in best.multipliers)
    return "\n".join(
        [
            f"# {scene_name}",
            "[reference]",
            f"state = [{fmt}]",
            f"multipliers = [{mult}]",
            f"step_time = {best.step_time:.15g}",
            f"tolerance = {tol:g}",
            f'note = "walker DOP853 at rtol = atol = 1e-13, Newton residual {best.residual:.1e}; '
            f'tolerance = 10x the spread over rtol 1e-11..1e-13 (scripts/reference_values.py)"',
        ]
    )


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("scenes", nargs="*", default=SCENES)
    args = parser.parse_args(argv)
    for name in args.scenes:
        print(reference(name))
        print()


if __name__ == "__main__":
    main()
