"""The ``walker`` command line: find, run, continue, basin, sweep, plot.

Every subcommand takes a scene file (``gaits/*.toml``) and only orchestrates the library.
Invalid input gives a one-line ``walker: error: ...`` and exit status 2; expected outcomes
(a fall, Newton not converging) are reported with exit status 1.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

EXIT_OK, EXIT_OUTCOME, EXIT_USAGE = 0, 1, 2


class UsageError(ValueError):
    """Bad command-line input (exit status 2)."""


def _strict(value):
    """``value`` with every non-finite float replaced by None (JSON null)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _strict(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_strict(v) for v in value]
    return value


def _json(record: dict) -> str:
    """Strict JSON (RFC 8259): a missing number (NaN, infinity) is written as null."""
    return json.dumps(_strict(record), allow_nan=False)


def _parse_set(items) -> dict:
    out = {}
    for item in items or ():
        name, sep, value = item.partition("=")
        if not sep or not name:
            raise UsageError(f"--set expects NAME=VALUE, got {item!r}")
        try:
            out[name.strip()] = float(value)
        except ValueError:
            raise UsageError(f"--set {name}: value {value!r} is not a number") from None
    return out


def _load(args):
    from walker.scene import load_scene

    return load_scene(args.scene, overrides=_parse_set(getattr(args, "set", None)))


def _stride_map(scene, parameter_name="slope"):
    from walker.stride import StrideMap

    c = scene.compute
    return StrideMap(
        scene.model,
        scene.params,
        method=c.method,
        rtol=c.rtol,
        atol=c.atol,
        t_max=c.t_max,
        first_step=c.first_step,
        parameter_name=parameter_name,
    )


def provenance(scene, extra: dict | None = None) -> dict:
    """What produced a result: scene, model, parameters with units, solver, kernel hash."""
    from walker.models import get_model
    from walker.storage import parameters_with_units

    c = scene.compute
    prov = {
        "scene": str(scene.path),
        "model": scene.model,
        "parameters": parameters_with_units(scene.params),
        "method": c.method,
        "rtol": c.rtol,
        "atol": c.atol,
        "kernel_hash": get_model(scene.model).kernel_hash,
    }
    prov.update(extra or {})
    return prov


def _complex_pairs(values) -> list:
    return [[float(np.real(v)), float(np.imag(v))] for v in values]


def _check_out(path) -> Path | None:
    if path is None:
        return None
    path = Path(path)
    if not path.parent.exists():
        raise UsageError(f"--out: directory {str(path.parent)!r} does not exist")
    return path


# ------------------------------------------------------------------------------------- find
def cmd_find(args) -> int:
    from walker.fixedpoint import find_fixed_point

    scene = _load(args)
    if not scene.model or scene.model == "double_pendulum":
        raise UsageError(f"{args.scene}: model `{scene.model}` has no gait to find")
    P = _stride_map(scene)
    period = args.period or max(1, scene.compute.strides)
    fp = find_fixed_point(
        P,
        P.project(scene.state),
        period=period,
        tol=args.tol,
        jacobian="fd" if args.fd else "exact",
    )
    record = {
        "status": fp.status.name,
        "success": bool(fp.success),
        "message": fp.message,
        "model": scene.model,
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
        "parameters": scene.params.to_dict(),
    }
    out = _check_out(args.out)
    if out is not None:
        from walker.storage import write

        write(
            out,
            fp,
            provenance=provenance(scene, {"status": fp.status.name}),
            overwrite=args.overwrite,
        )
    if args.json:
        print(_json(record))
    else:
        _print_fixed_point(scene, P, fp)
    return EXIT_OK if fp.success else EXIT_OUTCOME


def _print_fixed_point(scene, P, fp) -> None:
    print(f"scene      {scene.path}  (model {scene.model})")
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


# -------------------------------------------------------------------------------------- run
def cmd_run(args) -> int:
    from walker.storage import write
    from walker.stride import simulate

    scene = _load(args)
    out = _check_out(args.out)
    c = scene.compute
    strides = c.strides if args.strides is None else args.strides
    if strides < 0:
        raise UsageError(f"--strides must be >= 0, got {strides}")
    if args.sample_rate is not None and not (
        args.sample_rate > 0 and math.isfinite(args.sample_rate)
    ):
        raise UsageError(f"--sample-rate must be a positive number, got {args.sample_rate}")
    common = dict(
        n_strides=strides,
        phase0=scene.phase,
        method=c.method,
        rtol=c.rtol,
        atol=c.atol,
        first_step=c.first_step,
        t_max=c.t_max * max(1, strides),
    )
    if args.sample_rate is None:
        sol = simulate(scene.model, scene.params, scene.state, output="full", **common)
    else:
        first = simulate(scene.model, scene.params, scene.state, output="events", **common)
        times = np.arange(0.0, first.t, 1.0 / args.sample_rate)
        sol = simulate(
            scene.model, scene.params, scene.state, output="samples", sample_times=times, **common
        )
    print(f"status {sol.status.name}: {sol.message}")
    print(
        f"t = {sol.t:.12g} s, strides {sol.n_strides}, events {sol.n_events}, "
        f"steps {sol.n_steps} ({sol.n_rejected} rejected), rhs {sol.n_rhs}"
    )
    if out is not None:
        write(
            out,
            sol,
            provenance=provenance(scene, {"status": sol.status.name}),
            overwrite=args.overwrite,
        )
        print(f"wrote {out}")
    return EXIT_OK if sol.success else EXIT_OUTCOME


# --------------------------------------------------------------------------------- continue
def cmd_continue(args) -> int:
    from walker.continuation import continue_branch
    from walker.fixedpoint import find_fixed_point

    scene = _load(args)
    P = _stride_map(scene, parameter_name=args.param)
    if not math.isfinite(args.to):
        raise UsageError(f"--to must be finite, got {args.to}")
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
    out = _check_out(args.out)
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


# ------------------------------------------------------------------------------------ basin
def cmd_basin(args) -> int:
    from walker.basin import basin_map
    from walker.fixedpoint import find_fixed_point
    from walker.storage import write

    scene = _load(args)
    out = _check_out(args.out)
    P = _stride_map(scene)
    axes = tuple(int(a) for a in args.axes.split(","))
    if len(axes) != 2 or not all(0 <= a < P.n_z for a in axes) or axes[0] == axes[1]:
        raise UsageError(f"--axes must be two distinct section indices in 0..{P.n_z - 1}")
    fp = find_fixed_point(P, P.project(scene.state))
    if not fp.success:
        print(f"status {fp.status.name}: no gait to map the basin of: {fp.message}")
        return EXIT_OUTCOME
    span = args.span
    ranges = tuple(
        (
            fp.section[a] - span * max(abs(fp.section[a]), 0.1),
            fp.section[a] + span * max(abs(fp.section[a]), 0.1),
        )
        for a in axes
    )
    bm = basin_map(
        P,
        fp,
        axes=axes,
        ranges=ranges,
        n=(args.n, args.n),
        n_strides=args.strides,
        jobs=args.jobs,
        progress=not args.quiet,
    )
    write(out, bm, provenance=provenance(scene), overwrite=args.overwrite)
    from walker.results import BASIN_CONVERGED

    frac = float(np.mean(bm.outcome == BASIN_CONVERGED))
    print(f"wrote {out}: {args.n}x{args.n} points, {frac:.1%} converge to the gait")
    return EXIT_OK


# ------------------------------------------------------------------------------------ sweep
def cmd_sweep(args) -> int:
    from walker.sweep import run_sweep_command

    _check_out(args.out)
    table = run_sweep_command(
        args.scene,
        args.param,
        kind=args.kind,
        jobs=args.jobs,
        scheduler=args.scheduler,
        out=args.out,
        quiet=args.quiet,
        strides=args.strides,
        chunk_size=args.chunk_size,
    )
    n_ok = int(np.sum(table.columns["status"] == 0))
    print(f"wrote {args.out}: {len(table.points)} points, {n_ok} completed")
    return EXIT_OK


# ------------------------------------------------------------------------------------- plot
def cmd_plot(args) -> int:
    import matplotlib

    matplotlib.use("Agg")
    from walker.gallery import plot_file

    out = Path(args.out)
    if not Path(args.file).exists():
        raise FileNotFoundError(f"result file not found: {args.file}")
    if not out.parent.exists():
        raise UsageError(f"--out: directory {str(out.parent)!r} does not exist")
    out.mkdir(exist_ok=True)  # the figures' own directory is created
    paths = plot_file(args.file, out)
    for p in paths:
        print(f"wrote {p}")
    return EXIT_OK


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="walker", description="Simulate passive and actuated biped walkers."
    )
    from walker import __version__

    parser.add_argument("--version", action="version", version=f"walker {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)

    def scene_cmd(name, help_):
        p = sub.add_parser(name, help=help_)
        p.add_argument("scene", help="scene file (gaits/*.toml)")
        p.add_argument(
            "--set", action="append", metavar="NAME=VALUE", help="override a parameter (repeatable)"
        )
        return p

    p = scene_cmd("find", "find the periodic gait (fixed point of the stride map)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--period", type=int, default=None, help="strides per period")
    p.add_argument("--tol", type=float, default=1e-12, help="residual tolerance")
    p.add_argument("--fd", action="store_true", help="finite-difference Jacobian")
    p.add_argument("--out", help="also store the fixed point (HDF5)")
    p.add_argument("--overwrite", action="store_true")
    p.set_defaults(func=cmd_find)

    p = scene_cmd("run", "simulate strides and store the trajectory")
    p.add_argument("--strides", type=int, default=None)
    p.add_argument("--out", help="HDF5 file to write")
    p.add_argument(
        "--sample-rate",
        type=float,
        default=None,
        metavar="HZ",
        help="store samples at this rate instead of every step",
    )
    p.add_argument("--overwrite", action="store_true")
    p.set_defaults(func=cmd_run)

    p = scene_cmd("continue", "follow the gait as a parameter changes")
    p.add_argument("--param", default="slope")
    p.add_argument("--to", type=float, required=True)
    p.add_argument("--step", type=float, default=None)
    p.add_argument("--max-points", type=int, default=500)
    p.add_argument("--natural", action="store_true", help="natural-parameter continuation")
    p.add_argument("--json", action="store_true")
    p.add_argument("--out", help="HDF5 file to write")
    p.add_argument("--overwrite", action="store_true")
    p.set_defaults(func=cmd_continue)

    p = scene_cmd("basin", "map the basin of attraction on a 2-D slice of the section")
    p.add_argument("--out", required=True)
    p.add_argument("--axes", default="0,1", help="two section indices, e.g. 0,1")
    p.add_argument("--n", type=int, default=50, help="grid points per axis")
    p.add_argument(
        "--span",
        type=float,
        default=0.5,
        help="half-width of each axis relative to the fixed point's value",
    )
    p.add_argument("--strides", type=int, default=20)
    p.add_argument(
        "--jobs",
        type=int,
        default=None,
        help="worker threads (the compiled strides run in parallel); default: CPU count",
    )
    p.add_argument("--quiet", action="store_true")
    p.add_argument("--overwrite", action="store_true")
    p.set_defaults(func=cmd_basin)

    p = sub.add_parser("sweep", help="resumable parameter sweep")
    p.add_argument("scene")
    p.add_argument("--param", action="append", required=True, metavar="NAME=START:STOP:COUNT")
    p.add_argument("--kind", choices=("outcome", "fixed_point"), default="fixed_point")
    p.add_argument("--strides", type=int, default=1)
    p.add_argument(
        "--jobs",
        type=int,
        default=None,
        help="worker threads (the compiled strides run in parallel); default: CPU count",
    )
    p.add_argument("--scheduler", default=None, help="dask.distributed scheduler address")
    p.add_argument("--chunk-size", type=int, default=None)
    p.add_argument("--out", required=True)
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=cmd_sweep)

    p = sub.add_parser("plot", help="draw the figures of a stored result")
    p.add_argument("file")
    p.add_argument("--out", default=".", help="directory for the figures (created)")
    p.set_defaults(func=cmd_plot)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    from walker.storage import StorageError

    try:
        return args.func(args)
    except (
        UsageError,
        ValueError,
        TypeError,
        FileNotFoundError,
        FileExistsError,
        StorageError,
    ) as exc:
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        print(f"walker: error: {msg}", file=sys.stderr)
        return EXIT_USAGE


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
