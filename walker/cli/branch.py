"""``walker continue``: follow a gait as a parameter changes (a branch of fixed points).

The branch is followed from the scene's gait (period: ``--period``, else the scene's
``[compute] strides``) to both ends of the interval ``--range A:B`` (or ``--from A --to B``;
``--to B`` alone is the interval between the start and ``B``).  Each direction stops at the
first fold unless ``--through-folds``; ``--switch`` follows the period-doubled branch born at
the period doubling met first from the start, written next to ``--out`` as
``<stem>_period<2k>.h5``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from walker._suggest import did_you_mean

from ._common import (
    EXIT_OK,
    EXIT_OUTCOME,
    MAX_STRIDES,
    UsageError,
    _check_out,
    _complex_pairs,
    _json,
    _load,
    _stride_map,
    json_flag,
    out_flags,
    provenance,
    scene_cmd,
    write_result,
)


def parse_range(text: str, flag: str = "--range") -> tuple[float, float]:
    """``"A:B"`` -> ``(A, B)``: two finite, different numbers (order kept)."""
    parts = str(text).split(":")
    if len(parts) != 2:
        raise UsageError(f"{flag} expects A:B (two numbers), got {text!r}")
    try:
        a, b = (float(v) for v in parts)
    except ValueError:
        raise UsageError(f"{flag} expects A:B (two numbers), got {text!r}") from None
    if not (math.isfinite(a) and math.isfinite(b)):
        raise UsageError(f"{flag} must be finite, got {text!r}")
    if a == b:
        raise UsageError(f"{flag} needs two different values, got {text!r}")
    return a, b


def check_param(scene, name: str) -> None:
    """``--param`` names a parameter of the scene's model."""
    names = scene.params.names()
    if name not in names:
        raise UsageError(
            f"--param must be a parameter of {scene.model} ({', '.join(names)}), got {name!r}"
            f"{did_you_mean(name, names)}"
        )


def check_walker(scene, path) -> None:
    """The scene's model walks (has strides and a section)."""
    from walker.models import get_model

    if not get_model(scene.model).has_strides:
        raise UsageError(f"{path}: model `{scene.model}` has no strides (not a walker)")


def scene_period(args, scene) -> int:
    """``--period`` (>= 1), else the scene's ``[compute] strides`` for a fixed-point task."""
    if args.period is not None:
        if args.period < 1:
            raise UsageError(f"--period must be an integer >= 1, got {args.period}")
        if args.period > MAX_STRIDES:
            raise UsageError(f"--period must be <= {MAX_STRIDES:,}, got {args.period}")
        return int(args.period)
    c = scene.compute
    return max(1, int(c.strides)) if c.task == "fixed_point" else 1


def _interval(args, mu0: float, name: str) -> tuple[float, float]:
    if args.range is not None:
        if args.from_ is not None or args.to is not None:
            raise UsageError("--range excludes --from and --to; give one or the other")
        a, b = parse_range(args.range)
    else:
        for flag, v in (("--from", args.from_), ("--to", args.to)):
            if v is not None and not math.isfinite(v):
                raise UsageError(f"{flag} must be finite, got {v}")
        given = [v for v in (args.from_, args.to) if v is not None]
        if not given:
            raise UsageError(
                f"give the interval to follow the branch over: --range A:B, or --to B (from "
                f"the scene's {name} = {mu0:.10g})"
            )
        a, b = given if len(given) == 2 else (mu0, given[0])
        if a == b:
            raise UsageError(f"--from and --to must differ from each other and the start, got {a}")
    lo, hi = min(a, b), max(a, b)
    if not lo <= mu0 <= hi:
        raise UsageError(
            f"the scene's {name} = {mu0:.10g} (the start) lies outside [{lo:.10g}, {hi:.10g}]; "
            f"widen --range or start inside it with --set {name}=..."
        )
    return lo, hi


def _companion(out: Path | None, period: int) -> Path | None:
    """Where ``--switch`` stores the period-doubled branch: next to ``--out``."""
    if out is None:
        return None
    return out.with_name(f"{out.stem}_period{period}{out.suffix or '.h5'}")


def _parts(branch, stable: bool) -> list[list[float]]:
    """Parameter intervals ``[low, high]`` of the runs of (un)stable points, in branch order.

    A point on a located bifurcation (marginal: a multiplier on the unit circle) counts with
    its neighbour, and where a bifurcation lies between two runs it is their common end."""
    flags = np.asarray(branch.stable, dtype=bool).copy()
    mu = np.asarray(branch.parameter, dtype=float)
    located = [b for b in branch.bifurcations if np.all(np.isfinite(b.multipliers))]
    for i in range(flags.size):
        on_bif = any(
            b.parameter_value == mu[i] and np.array_equal(b.section, branch.sections[i])
            for b in located
        )
        if on_bif and flags.size > 1:
            flags[i] = flags[i - 1] if i > 0 else flags[i + 1]
    runs = []
    i = 0
    while i < flags.size:
        j = i
        while j + 1 < flags.size and flags[j + 1] == flags[i]:
            j += 1
        runs.append([i, j, float(mu[i]), float(mu[j])])
        i = j + 1
    u = np.column_stack([branch.sections, mu])
    for left, right in zip(runs, runs[1:], strict=False):
        a, b = u[left[1]], u[right[0]]
        # on the segment between the two points, up to the curvature of the branch
        between = [
            bf.parameter_value
            for bf in located
            if np.linalg.norm(np.append(bf.section, bf.parameter_value) - a)
            + np.linalg.norm(np.append(bf.section, bf.parameter_value) - b)
            <= 1.5 * np.linalg.norm(b - a)
        ]
        if between:
            left[3] = right[2] = float(between[0])
    return [[min(lo, hi), max(lo, hi)] for i, _, lo, hi in runs if bool(flags[i]) == stable]


def _end_kind(branch, index: int, start_index: int, bounds) -> str:
    mu = float(branch.parameter[index])
    z = branch.sections[index]
    if _vanishing_end(branch, index):
        return "step_length_vanishes"
    for b in branch.bifurcations:
        if b.kind == "fold" and b.parameter_value == mu and np.array_equal(b.section, z):
            return "fold"
    if index % len(branch.parameter) == start_index:
        return "start"
    if mu in bounds:
        return "bound"
    return _stop_reason(_leg_message(branch, index))[0]


VANISHING_STEP = 0.01
"""An end of a branch where the step length is below this fraction of the longest step on
the branch, and shrinking toward the end, is reported as "the step length vanishes" (a
passive walker's gait as the slope goes to 0), not as a fold or a failure."""


def _vanishing_end(branch, index: int) -> bool:
    """Whether the branch end ``index`` (0 or -1) is a gait whose step shrinks to nothing."""
    lengths = np.asarray(branch.measures.get("step_length", ()), dtype=float)
    if lengths.size < 3 or not np.all(np.isfinite(lengths)):
        return False
    tail = lengths[:3] if index == 0 else lengths[::-1][:3]
    return bool(tail[0] <= VANISHING_STEP * np.max(lengths) and tail[0] < tail[1] < tail[2])


def _leg_message(branch, index: int) -> str:
    """The part of the branch's message about the leg that ends at ``index`` (0: the leg
    going down, -1 or n - 1: going up); the whole message for a one-way branch."""
    message = str(branch.message)
    if not message.startswith("Going "):
        return message
    down, _, up = message.partition(" Going up: ")
    down = down.removeprefix("Going down: ") if down.startswith("Going down: ") else ""
    if message.startswith("Going up: "):
        down, up = "", message.removeprefix("Going up: ")
    return down if index == 0 else up


def _stop_reason(message: str) -> tuple[str, str]:
    """Why a leg of a branch stopped, from its message: (a short key, what happened in
    the continuation's words, without the advice meant for a single run)."""
    from walker.status import Status

    if "`max_points`" in message or "--max-points" in message:
        return "max_points", "the --max-points budget ran out before the end of --range"
    if message.startswith("The corrector failed"):
        return "corrector_failed", "the corrector did not converge even with the smallest step"
    for status in Status:
        first = status.message.split(". ")[0].rstrip(".")
        if status != Status.COMPLETED and first in message:
            return status.name.lower(), f"the stride beyond it fails ({status.name}): {first}"
    return "stopped", message


def _explain_ends(branch, name: str):
    """``branch`` with each leg's message in the continuation's words: a leg that ends
    where the step length vanishes says so (and the spurious fold found there, where the
    stride map degenerates, is dropped); a leg that ends because the gait stops walking
    says what happens beyond its end, without the advice meant for a single run."""
    import dataclasses

    n = len(branch.parameter)
    if not n:
        return branch
    legs = {}
    for index in (0, n - 1):
        leg = _leg_message(branch, index)
        if _vanishing_end(branch, index):
            mu = float(branch.parameter[index])
            length = float(branch.measures["step_length"][index])
            legs[index] = (
                leg,
                f"The step length vanishes toward {name} = {mu:.10g} (it is {length:.3g} m "
                "there): the gait shrinks toward standing still, where no stride is left to "
                "follow.",
            )
        else:
            key, words = _stop_reason(leg)
            if key not in ("stopped", "max_points", "corrector_failed") and ": " in leg:
                head = leg.split(": ", 1)[0]
                legs[index] = (leg, f"{head}: {words}.")
    message = str(branch.message)
    for old, new in legs.values():
        if old:
            message = message.replace(old, new, 1)

    def at_vanishing_end(b) -> bool:
        for i, third in ((0, 2), (n - 1, n - 3)):
            reach = abs(float(branch.parameter[third]) - float(branch.parameter[i]))
            near = abs(b.parameter_value - float(branch.parameter[i])) <= reach
            if _vanishing_end(branch, i) and near:
                return True
        return False

    keep = [b for b in branch.bifurcations if not at_vanishing_end(b)]
    return dataclasses.replace(branch, message=message, bifurcations=keep)


_FLAG_WORDS = (
    ("Increase `max_points` or `max_step`.", "Increase --max-points."),
    ("`max_points`", "--max-points"),
    (
        "Try a smaller `min_step`, `max_step` or a looser `tol`.",
        "Try a narrower --range, or from Python a smaller `min_step` or `max_step`.",
    ),
)


def _flag_words(message: str) -> str:
    """A continuation message in the command line's words (its flags, not Python's
    argument names)."""
    for python_words, flags in _FLAG_WORDS:
        message = message.replace(python_words, flags)
    return message


def _summary(branch, name: str, start_index: int | None, bounds) -> dict:
    n = int(len(branch.parameter))
    record = {
        "status": branch.status.name,
        "success": bool(branch.success),
        "message": _flag_words(branch.message),
        "parameter": name,
        "period": int(branch.period),
        "n_points": n,
        "parameter_range": (
            [float(branch.parameter.min()), float(branch.parameter.max())] if n else None
        ),
        "ends": [],
        "stable_parts": _parts(branch, True),
        "unstable_parts": _parts(branch, False),
        "bifurcations": [
            {
                "kind": b.kind,
                "parameter": name,
                "parameter_value": float(b.parameter_value),
                "section": [float(v) for v in b.section],
                "multipliers": _complex_pairs(b.multipliers),
            }
            for b in branch.bifurcations
        ],
    }
    if n:
        record["ends"] = [
            {
                "parameter_value": float(branch.parameter[i]),
                "at": _end_kind(branch, i, -1 if start_index is None else start_index, bounds),
            }
            for i in (0, n - 1)
        ]
    return record


def _print_summary(rec: dict, label: str = "") -> None:
    name = rec["parameter"]
    print(f"{label}status {rec['status']}: {rec['message']}")
    if not rec["n_points"]:
        return
    ends = " to ".join(f"{e['parameter_value']:.10g} ({e['at']})" for e in rec["ends"])
    print(f"{rec['n_points']} points, period {rec['period']}, {name} from {ends}")
    for key, word in (("stable_parts", "stable"), ("unstable_parts", "unstable")):
        if rec[key]:
            spans = ", ".join(f"{a:.6g}..{b:.6g}" for a, b in rec[key])
            print(f"  {word:<9s}{name} {spans}")
    for b in rec["bifurcations"]:
        mult = ", ".join(f"{re:.6f}{im:+.6f}i" for re, im in b["multipliers"])
        print(f"  {b['kind']:<16s} {name} = {b['parameter_value']:.12g}   [{mult}]")
    if any(e["at"] == "fold" for e in rec["ends"]):
        print("  stopped at the fold: pass --through-folds to follow the branch round it")


def _with_measures(P, branch):
    """``branch`` with the gait measures of each of its points
    (:func:`walker.analysis.measures.branch_measures`)."""
    import dataclasses

    from walker.analysis.measures import branch_measures

    if not len(branch.parameter):
        return branch
    return dataclasses.replace(branch, measures=branch_measures(P, branch))


def cmd_continue(args) -> int:
    from walker.analysis.continuation import continue_branch
    from walker.analysis.fixedpoint import find_fixed_point

    scene = _load(args)
    check_walker(scene, args.scene)
    check_param(scene, args.param)
    period = scene_period(args, scene)
    mu0 = float(getattr(scene.params, args.param))
    bounds = _interval(args, mu0, args.param)
    out = _check_out(args.out, overwrite=args.overwrite)
    out2 = _companion(out, 2 * period) if args.switch else None
    if out2 is not None:
        _check_out(out2, overwrite=args.overwrite)
    if args.max_points < 2:
        raise UsageError(f"--max-points must be an integer >= 2, got {args.max_points}")
    if args.step is not None and not (math.isfinite(args.step) and args.step > 0):
        raise UsageError(f"--step must be positive and finite, got {args.step}")
    P = _stride_map(scene, parameter_name=args.param)
    fp = find_fixed_point(P, P.project(scene.state), period=period)
    if not fp.success:
        rec = {
            "status": fp.status.name,
            "success": False,
            "parameter": args.param,
            "period": period,
            "message": f"no starting gait: {fp.message}",
        }
        print(_json(rec) if args.json else f"status {fp.status.name}: {rec['message']}")
        return EXIT_OUTCOME
    options = {
        "method": "natural" if args.natural else "arclength",
        "max_points": args.max_points,
        "period": period,
        "stop_at_fold": not args.through_folds,
    }
    if args.step is not None:
        options["step"] = args.step
    branch = continue_branch(P, fp.section, bounds=bounds, **options)
    branch = _with_measures(P, branch)
    start = None
    if len(branch.parameter):
        dist = np.abs(branch.parameter - mu0) + np.max(np.abs(branch.sections - fp.section), axis=1)
        start = int(np.argmin(dist))
    branch = _explain_ends(branch, args.param)
    record = _summary(branch, args.param, start, bounds)
    record["measures"] = {
        args.param: [float(v) for v in branch.parameter],
        **{key: col.tolist() for key, col in branch.measures.items()},
    }
    extra = {
        "status": branch.status.name,
        "period": period,
        "range": list(bounds),
        "start": mu0,
        "stop_at_fold": not args.through_folds,
        "ends": record["ends"],
    }

    # A branch that ends in a fold, a trip or a fall is a result: an outcome (exit 1) only
    # when no point was computed.
    ok = len(branch.parameter) > 0
    switched = None
    if args.switch:
        switched, switch_rec = _switch(P, branch, bounds, options, period, mu0, args.param)
        record["period_doubled"] = switch_rec
        ok = ok and switched is not None and len(switched.parameter) > 0
    if out is not None:
        from walker.storage import write

        if switched is not None and len(switched.parameter):
            write(
                out2,
                switched,
                provenance=provenance(
                    scene,
                    {
                        "status": switched.status.name,
                        "period": 2 * period,
                        "range": list(bounds),
                        "switched_from": out.name,
                        "doubling": record["period_doubled"]["doubling"],
                        "stop_at_fold": not args.through_folds,
                    },
                    out=out2,
                ),
                overwrite=args.overwrite,
            )
            record["period_doubled"]["out"] = str(out2)
            extra["switched_branch"] = out2.name
        write_result(out, branch, scene, args, extra)
        record["out"] = str(out)
    if args.json:
        print(_json(record))
    else:
        _print_summary(record)
        sw = record.get("period_doubled")
        if sw is not None:
            print()
            label = f"period-{sw['period']} branch: "
            if sw.get("n_points"):
                _print_summary(sw, label=label)
            elif sw["status"] is None:
                print(f"{label}not computed: {sw['message']}")
            else:
                print(f"{label}status {sw['status']}: {sw['message']}")
        for rec in (record, sw or {}):
            if "out" in rec:
                print(f"wrote {rec['out']}")
    return EXIT_OK if ok else EXIT_OUTCOME


def _switch(P, branch, bounds, options, period, mu0, name):
    """Period-doubled branch at the doubling met first from the start (nearest in the
    parameter), followed away from the doubling to the end of ``bounds``.

    Returns ``(branch or None, record)``."""
    from walker.analysis.continuation import continue_branch, switch_to_period_two

    def failed(status, message, doubling=None):
        return None, {
            "status": status,
            "success": False,
            "period": 2 * period,
            "message": message,
            "doubling": doubling,
        }

    pds = [
        b
        for b in branch.bifurcations
        if b.kind == "period_doubling" and np.all(np.isfinite(b.multipliers))
    ]
    if not pds:
        return failed(None, "no period doubling located on the branch: nothing to switch at")
    pd = min(pds, key=lambda b: abs(b.parameter_value - mu0))
    mu_pd = float(pd.parameter_value)
    fp2 = switch_to_period_two(P, pd, period=period)
    if not fp2.success:
        return failed(
            fp2.status.name, f"switching at {name} = {mu_pd:.10g} failed: {fp2.message}", mu_pd
        )
    mu2 = float(fp2.parameters[name])
    lo, hi = bounds
    side = (mu2, hi) if mu2 > mu_pd else (lo, mu2)
    if not side[0] < side[1]:
        return failed(
            None,
            f"the period-{2 * period} orbit appears at {name} = {mu2:.10g}, outside "
            f"[{lo:.10g}, {hi:.10g}]: widen --range",
            mu_pd,
        )
    br2 = continue_branch(
        P.with_parameter(mu2), fp2.section, bounds=side, **dict(options, period=2 * period)
    )
    br2 = _explain_ends(_with_measures(P, br2), name)
    start = 0 if mu2 == side[0] else len(br2.parameter) - 1
    rec = _summary(br2, name, start, side)
    rec["doubling"] = mu_pd
    return br2, rec


def register(sub) -> None:
    p = scene_cmd(sub, "continue", "follow the gait as a parameter changes")
    p.add_argument(
        "--param", default="slope", help="parameter to vary (`walker params MODEL` lists them)"
    )
    p.add_argument(
        "--range",
        metavar="A:B",
        help="follow the branch both ways from the scene's gait to A and to B (default: none; "
        "give --range, or --from/--to)",
    )
    p.add_argument(
        "--from",
        dest="from_",
        type=float,
        metavar="A",
        help="one end of the interval (default: the scene's value)",
    )
    p.add_argument(
        "--to",
        type=float,
        metavar="B",
        help="other end of the interval (default: the scene's value)",
    )
    p.add_argument(
        "--period",
        type=int,
        default=None,
        help="strides per gait cycle, >= 1 (default: the scene's [compute] strides)",
    )
    p.add_argument(
        "--through-folds",
        action="store_true",
        help="follow the branch round a fold onto the other branch (default: stop at a fold)",
    )
    p.add_argument(
        "--switch",
        action="store_true",
        help="also follow the period-doubled branch born at the first period doubling, "
        "stored in <out stem>_period<2k>.h5 (default: off)",
    )
    p.add_argument(
        "--step",
        type=float,
        default=None,
        help="first continuation step, in the parameter (--natural) or in arclength "
        "(default: 0.01 of the interval's length)",
    )
    p.add_argument(
        "--max-points", type=int, default=500, help="most branch points in each direction"
    )
    p.add_argument(
        "--natural",
        action="store_true",
        help="natural-parameter continuation, which stops before a fold (default: off, "
        "pseudo-arclength)",
    )
    json_flag(p)
    out_flags(p, "HDF5 file to write the branch to (default: none)")
    p.set_defaults(func=cmd_continue)
