"""Per-call cost of walker's binding into the compiled core (issue 32 item 6: the keyword
interface), on the compass gait (gaits/compass_goswami.toml, its reference fixed point).

Rows, each the min and median over interleaved repetitions of the per-call time in µs:

* ``solve, one step``: ``PreparedRun.map`` with a step budget of one (the run stops after
  its first step attempt): the binding's argument parsing and result record, the Python
  wrapper, and one DOP853 step;
* ``solve, one stride``: ``PreparedRun.map`` over a whole stride;
* ``StrideMap call``: ``StrideMap.__call__`` (one ``PreparedMap.map`` call, settings parsed
  once);
* ``PreparedMap, re-targeted``: a sweep point's set-up, ``StrideMap._retargeted`` and its
  first prepared run (the section settings parsed into a new ``PreparedMap``);
* ``basin_points, 1 point``: one basin row in one compiled call.

With ``--baseline SO``, the path of a ``_hybrid`` extension built from the tree before the
keyword interface (positional arguments, ``n_interior``'s sign the screening), the raw
binding calls are timed side by side in this process, interleaved: one-step compass runs
through the old positional ``solve``, the keyword ``solve`` (keywords spelled at the call
site, and merged from a dict) and ``PreparedSolve.run`` (the settings bound once, seven
keywords a call, as ``PreparedRun.map`` calls it), and a
``PreparedMap`` built from 32 keywords against 31 positional arguments.  Nothing here is
asserted.

Writes results/bench/binding.csv and binding.md (``--out DIR`` elsewhere).

Usage: python scripts/bench_binding.py [--quick] [--out DIR] [--baseline SO]
"""

from __future__ import annotations

import argparse
import importlib.machinery
import importlib.util
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # this tree's walker, not an installed one

from walker import _hybrid, load_scene  # noqa: E402
from walker.simulation import _section  # noqa: E402
from walker.simulation.integrate import PreparedRun  # noqa: E402
from walker.simulation.stride import StrideMap  # noqa: E402


def _per_call(fn, number: int) -> float:
    t0 = time.perf_counter()
    for _ in range(number):
        fn()
    return (time.perf_counter() - t0) / number * 1e6


def _old_module(path: Path):
    """The extension at ``path`` loaded beside this tree's, under another package name."""
    loader = importlib.machinery.ExtensionFileLoader("walker_baseline._hybrid", str(path))
    spec = importlib.util.spec_from_file_location(loader.name, str(path), loader=loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def _baseline_cases(old, run, x0, p, smap) -> dict:
    """Raw binding calls, the old positional ones against the keyword ones (one DOP853 step:
    max_steps = 1), and the PreparedMap constructions."""
    head, settings = dict(run._head), dict(run._settings)
    settings["max_steps"] = 1
    entry = next(k for k, v in _hybrid.models().items() if v["rhs"] == head["rhs"])
    theirs = old.models()[entry]
    old_head = (
        *(theirs[k] or 0 for k in ("rhs", "guards", "reset", "jac")),
        head["ctx"],
        head["directions"],
        head["n_x"],
        head["n_guards"],
        head["n_impulse"],
    )
    code = -settings["n_interior"] if settings["screen_interior"] else settings["n_interior"]
    s = settings
    old_args = (*old_head, x0, p, 0, 0.0, 10.0, 1, s["method"], s["adaptive"], s["rtol"])
    old_args += (s["atol"], s["first_step"], s["max_step"], 1, 0, np.empty(0), False, code)
    rhs, guards, reset, jac, ctx, directions, n_x, n_guards, n_impulse = head.values()
    method, adaptive, rtol, atol, first_step, max_step, _, n_interior, screen = s.values()

    def spelled():
        return _hybrid.solve(
            rhs=rhs, guards=guards, reset=reset, jac=jac, ctx=ctx, directions=directions,
            n_x=n_x, n_guards=n_guards, n_impulse=n_impulse, x0=x0, p=p, phase0=0, t0=0.0,
            t_max=10.0, n_strides=1, method=method, adaptive=adaptive, rtol=rtol, atol=atol,
            first_step=first_step, max_step=max_step, max_steps=1, n_interior=n_interior,
            screen_interior=screen, output=0, want_jac=False,
        )  # fmt: skip

    fixed = {**head, **settings, "t0": 0.0, "output": 0}
    prepared = _hybrid.PreparedSolve(**fixed).run

    def merged():
        return _hybrid.solve(
            **fixed, x0=x0, p=p, phase0=0, t_max=10.0, n_strides=1, want_jac=False,
            jacobian_seed=None,
        )  # fmt: skip

    def bound():
        return prepared(
            x0=x0, p=p, phase0=0, t_max=10.0, n_strides=1, want_jac=False, jacobian_seed=None
        )

    assert old.solve(*old_args).x == spelled().x == merged().x == bound().x
    cached = smap.__dict__["_run"]
    section = _section.section_args(smap.model, smap.t_max, cached, run)
    old_section = [section[k] for k in _hybrid.SECTION_FIELDS if k != "screen_interior"]
    old_section[:4] = old_head[:4]
    old_section[17] = code
    old_section[25] = (theirs["energy"] or 0) if section["energy"] else 0
    old_section[27] = (theirs["start_phase"] or 0) if section["start_phase"] else 0
    return {
        "raw solve, one step: positional (before)": (lambda: old.solve(*old_args), 3000),
        "raw solve, one step: keywords spelled out": (spelled, 3000),
        "raw solve, one step: keywords merged from a dict": (merged, 3000),
        "raw solve, one step: PreparedSolve.run (PreparedRun.map)": (bound, 3000),
        "PreparedMap(): positional (before)": (lambda: old.PreparedMap(*old_section), 3000),
        "PreparedMap(): keywords": (lambda: _hybrid.PreparedMap(**section), 3000),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", type=Path, default=ROOT / "results" / "bench")
    ap.add_argument("--baseline", type=Path, default=None)
    ap.add_argument("--baseline-label", default="the positional build")
    args = ap.parse_args()
    rounds = 5 if args.quick else 15

    scene = load_scene(ROOT / "gaits" / "compass_goswami.toml")
    smap = StrideMap.from_scene(scene)
    x0 = np.ascontiguousarray(scene.reference["state"], dtype=np.float64)
    run, p, _ = smap._prepared(1)
    z = np.ascontiguousarray(smap.model.project(x0, p), dtype=np.float64)
    assert smap(z).status == 0
    one_step = PreparedRun(run.system, max_steps=1)
    params = smap.params
    basin = smap.basin_batch()
    z_rows = z[None, :].copy()

    def retargeted():
        smap._retargeted(params)._prepared(1)

    cases = {
        "solve, one step": (lambda: one_step.map(x0, p, 0, 10.0, 1, False), 2000),
        "solve, one stride": (lambda: run.map(x0, p, 0, 10.0, 1, False), 300),
        "StrideMap call": (lambda: smap(z), 300),
        "PreparedMap, re-targeted": (retargeted, 300),
        "basin_points, 1 point": (lambda: basin(z_rows, z, 1e-8, 2), 300),
    }
    if args.baseline is not None:
        cases.update(_baseline_cases(_old_module(args.baseline), run, x0, p, smap))
    times: dict[str, list[float]] = {k: [] for k in cases}
    for r in range(rounds):
        order = list(cases)[r % len(cases) :] + list(cases)[: r % len(cases)]
        for name in order:
            fn, number = cases[name]
            times[name].append(_per_call(fn, number))

    load = os.getloadavg()[0]
    rows = [(k, min(v), statistics.median(v)) for k, v in times.items()]
    csv = "case,min_us,median_us\n" + "".join(f"{k},{a:.3f},{b:.3f}\n" for k, a, b in rows)
    md = [
        "# Binding call cost (compass, gaits/compass_goswami.toml)",
        "",
        f"Per call, min and median of {rounds} interleaved rounds; load average {load:.2f}"
        " on a machine shared by other sessions. Measured by scripts/bench_binding.py.",
        "",
        "| case | min [µs] | median [µs] |",
        "|---|---:|---:|",
        *(f"| {k} | {a:.2f} | {b:.2f} |" for k, a, b in rows),
        "",
    ]
    if args.baseline is not None:
        best = {k: a for k, a, _ in rows}
        old = best["raw solve, one step: positional (before)"]
        md += [
            f"Baseline (before): {args.baseline_label}, loaded beside this tree's extension.",
            "Raw one-step solve, by the minima, against the positional call: "
            + ", ".join(
                f"{k.split(': ')[1]} {best[k] - old:+.2f} µs"
                for k in best
                if k.startswith("raw solve") and "before" not in k
            )
            + ".",
            "",
        ]
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "binding.csv").write_text(csv, encoding="utf-8")
    (args.out / "binding.md").write_text("\n".join(md), encoding="utf-8")
    print("\n".join(md))


if __name__ == "__main__":
    main()
