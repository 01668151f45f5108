"""``walker continue``: follow a gait as a parameter changes (a branch of fixed points)."""

from __future__ import annotations

import math

from ._common import (
    EXIT_OK,
    EXIT_OUTCOME,
    UsageError,
    _check_out,
    _complex_pairs,
    _json,
    _load,
    _stride_map,
    provenance,
    scene_cmd,
)


def cmd_continue(args) -> int:
    from walker.continuation import continue_branch
    from walker.fixedpoint import find_fixed_point

    scene = _load(args)
    P = _stride_map(scene, parameter_name=args.param)
    if not math.isfinite(args.to):
        raise UsageError(f"--to must be finite, got {args.to}")
    out = _check_out(args.out, overwrite=args.overwrite)
    fp = find_fixed_point(P, P.project(scene.state))
    if not fp.success:
        print(f"status {fp.status.name}: no starting gait: {fp.message}")
        return EXIT_OUTCOME
    kwargs = {}
    if args.step is not None:
        kwargs["step"] = args.step
    branch = continue_branch(
        P,
        fp.section,
        to=args.to,
        method="natural" if args.natural else "arclength",
        max_points=args.max_points,
        **kwargs,
    )
    if out is not None:
        from walker.storage import write

        write(
            out,
            branch,
            provenance=provenance(scene, {"status": branch.status.name}),
            overwrite=args.overwrite,
        )
    bifs = [
        {
            "kind": b.kind,
            "parameter": args.param,
            "parameter_value": float(b.parameter_value),
            "section": [float(v) for v in b.section],
            "multipliers": _complex_pairs(b.multipliers),
        }
        for b in branch.bifurcations
    ]
    if args.json:
        print(
            _json(
                {
                    "status": branch.status.name,
                    "message": branch.message,
                    "parameter": args.param,
                    "n_points": int(len(branch.parameter)),
                    "parameter_range": [
                        float(branch.parameter.min()),
                        float(branch.parameter.max()),
                    ],
                    "bifurcations": bifs,
                }
            )
        )
    else:
        print(f"status {branch.status.name}: {branch.message}")
        print(
            f"{len(branch.parameter)} points, {args.param} from "
            f"{branch.parameter[0]:.10g} to {branch.parameter[-1]:.10g}"
        )
        for b in bifs:
            mult = ", ".join(f"{re:.6f}{im:+.6f}i" for re, im in b["multipliers"])
            print(f"  {b['kind']:<16s} {args.param} = {b['parameter_value']:.12g}   [{mult}]")
    return EXIT_OK if branch.success else EXIT_OUTCOME


def register(sub) -> None:
    p = scene_cmd(sub, "continue", "follow the gait as a parameter changes")
    p.add_argument("--param", default="slope")
    p.add_argument("--to", type=float, required=True)
    p.add_argument("--step", type=float, default=None)
    p.add_argument("--max-points", type=int, default=500)
    p.add_argument("--natural", action="store_true", help="natural-parameter continuation")
    p.add_argument("--json", action="store_true")
    p.add_argument("--out", help="HDF5 file to write")
    p.add_argument("--overwrite", action="store_true")
    p.set_defaults(func=cmd_continue)
