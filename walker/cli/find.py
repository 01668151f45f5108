"""``walker find``: the periodic gait (fixed point of the stride map) of a scene."""

from __future__ import annotations

from ._common import (
    EXIT_OK,
    EXIT_OUTCOME,
    UsageError,
    _check_out,
    _complex_pairs,
    _json,
    _load,
    _positive_flag,
    _stride_map,
    json_flag,
    out_flags,
    print_measures,
    scene_cmd,
    write_result,
)

MAX_PERIOD = 100_000
"""Longest period ``find`` searches: a search evaluates the period-fold map tens of times
(with the Jacobian), about a minute of strides at this period, so a longer one cannot finish
in reasonable time and is refused before any work (exit 2)."""


def cmd_find(args) -> int:
    import dataclasses

    from walker.analysis.fixedpoint import find_fixed_point
    from walker.analysis.measures import cycle_measures
    from walker.simulation.stride import solver_settings

    _positive_flag(args.period, "--period", minimum=1, integer=True)
    if args.tol is not None:
        _positive_flag(args.tol, "--tol")
    scene = _load(args)
    if not scene.model or scene.model == "double_pendulum":
        raise UsageError(f"{args.scene}: model `{scene.model}` has no gait to find")
    out = _check_out(args.out, overwrite=args.overwrite)
    P = _stride_map(scene)
    period = max(1, scene.compute.strides) if args.period is None else args.period
    if period > MAX_PERIOD:
        source = "--period" if args.period is not None else f"{args.scene}: [compute] strides"
        raise UsageError(
            f"{source} (the period searched) must be <= {MAX_PERIOD:,} for find, got "
            f"{period:,}: a search evaluates the {period:,}-stride map tens of times"
        )
    fp = find_fixed_point(
        P,
        P.project(scene.state),
        period=period,
        tol=scene.compute.tol if args.tol is None else args.tol,
        jacobian="fd" if args.fd else "exact",
    )
    if fp.success:
        measures = cycle_measures(
            P.model, P.params, fp.state, period=int(fp.period), settings=solver_settings(P)
        )
        fp = dataclasses.replace(fp, measures=measures.to_dict())
    record = {
        "status": fp.status.name,
        "success": bool(fp.success),
        "message": fp.message,
        "model": scene.model,
        "conventions": dict(fp.conventions),
        "section_names": list(P.section_names),
        "section": [float(v) for v in fp.section],
        "state_names": list(scene.state_names),
        "state": [float(v) for v in fp.state],
        "step_time": float(fp.step_time),
        "multipliers": _complex_pairs(fp.multipliers),
        "stable": bool(fp.stable),
        "residual": float(fp.residual),
        "n_iter": int(fp.n_iter),
        "period": int(fp.period),
        "measures": dict(fp.measures),
        "parameters": scene.params.to_dict(),
    }
    if out is not None:
        write_result(out, fp, scene, args, {"status": fp.status.name})
    if args.json:
        print(_json(record))
    else:
        _print_fixed_point(scene, P, fp)
    return EXIT_OK if fp.success else EXIT_OUTCOME


def _print_fixed_point(scene, P, fp) -> None:
    print(f"scene      {scene.path}  (model {scene.model})")
    for key, value in fp.conventions.items():
        print(f"convention {key} = {value}")
    print(f"status     {fp.status.name}: {fp.message}")
    if not fp.success:
        return
    print(f"residual   {fp.residual:.2e} after {fp.n_iter} Newton iterations")
    print(f"step time  {fp.step_time:.15g} s")
    print("state just after heel strike:")
    for name, v in zip(scene.state_names, fp.state, strict=True):
        print(f"  {name:<10s} {v: .15f}")
    print("Floquet multipliers:")
    for m in fp.multipliers:
        print(f"  {m.real: .12f} {m.imag:+.12f}i   |.| = {abs(m):.12f}")
    print(f"stable     {fp.stable}")
    print_measures(fp.measures)


def register(sub) -> None:
    p = scene_cmd(sub, "find", "find the periodic gait (fixed point of the stride map)")
    json_flag(p)
    p.add_argument(
        "--period",
        type=int,
        default=None,
        help="strides per period, >= 1 (default: the scene's [compute] strides)",
    )
    p.add_argument(
        "--tol",
        type=float,
        default=None,
        help="residual tolerance, max|P^k(z) - z| in section units (default: the scene's "
        "[compute] tol, 1e-12 unless set)",
    )
    p.add_argument(
        "--fd",
        action="store_true",
        help="finite-difference Jacobian instead of the exact one (variational equations)",
    )
    out_flags(p, "also store the fixed point in this HDF5 file (default: none)")
    p.set_defaults(func=cmd_find)
