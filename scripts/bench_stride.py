"""Work-precision benchmark of one walker stride, every contender timed side by side in one
process (round-robin repetitions, min and median per contender).

Kneed walker (gaits/kneed_hsu.toml at its reference fixed point, ``[reference] state``):

* walker ``simulate`` (DOP853) as a user calls it, and the ``StrideMap`` call the fixed-point
  search makes (``P(z)``);
* scipy ``solve_ivp`` DOP853 and RK45 on a hand-written numpy model (scripts/_contenders.py:
  derived from the Lagrangian with sympy at start-up, printed as scalar Python with the
  3x3 / 2x2 solve in closed form), terminal events for knee lock and heel strike;
* ``solve_ivp`` DOP853 on walker's compiled vector field (the model module's ``rhs`` and
  ``guards``, called from Python);
* heyoka's Taylor integrator on the same equations as heyoka expressions, terminal events for
  knee lock and heel strike, parameters (a) runtime ``heyoka.par[i]``, (b) folded in as
  numeric constants (skipped with a note when heyoka is missing).

All contenders apply walker's impact maps (the model's ``reset``) at the events.

Compass gait at Drake's default parameters (read from pydrake at run time): walker
``simulate`` / ``StrideMap`` against Drake's ``CompassGait`` in its ``Simulator`` with the
``runge_kutta5`` integrator at a target accuracy (skipped with a note when pydrake is
missing).

Error: max-norm over the state components of the post-stride state (just after the next
heel strike) minus a reference stride (walker DOP853 at rtol 3e-14, atol 1e-15; checked
against solve_ivp DOP853 at rtol = atol = 1e-13).  Each contender runs over a grid of
tolerances; at each error target the cheapest tolerance whose error meets the target is
timed again in a dedicated interleaved run.

Writes results/bench/stride.csv, stride.md, work_precision.png and README.md.

Usage: python scripts/bench_stride.py [--quick]
"""

from __future__ import annotations

import importlib.metadata
import math
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _bench as B  # noqa: E402
import _contenders as C  # noqa: E402
import _drake  # noqa: E402

from walker import load_scene  # noqa: E402
from walker.analysis.fixedpoint import find_fixed_point  # noqa: E402
from walker.models import get_model  # noqa: E402
from walker.params import CompassParams  # noqa: E402
from walker.simulation.stride import StrideMap, simulate  # noqa: E402

TARGETS = (1e-6, 1e-8, 1e-10)
REF_RTOL, REF_ATOL = 3e-14, 1e-15
T_PAST = 1e-3  # [s] the compass fixed-time problem ends this long after the heel strike


# ------------------------------------------------------------------------- contenders
class Contender:
    """``prepare(tol)`` -> zero-argument callable returning the post-stride state (or None);
    ``note`` for the table."""

    def __init__(self, name, prepare, note="", walker=False, ref=None, base="walker simulate"):
        self.name, self.prepare, self.note, self.walker = name, prepare, note, walker
        # ref: the contender's own reference state (None: the problem's post-stride state);
        # base: the walker contender solving the same problem, for the ratio column.
        self.ref, self.base = ref, base


def walker_preps(name, params, x0):
    """walker's contenders on one stride of model ``name`` from ``x0``, each as
    ``tol -> a call``: ``simulate``, the ``StrideMap`` call ``P(z)`` and ``P(z,
    jacobian=True)``."""
    z0 = get_model(name).project(x0, params.as_array())

    def sim(tol):
        return lambda: simulate(name, params, x0, rtol=tol, atol=tol).x

    def stride_map(jacobian):
        def prep(tol):
            P = StrideMap(name, params, rtol=tol, atol=tol)
            return lambda: P(z0, jacobian=jacobian).state

        return prep

    return sim, stride_map(False), stride_map(True)


def kneed_contenders(params, x0, have_heyoka, ck):
    nk = C.NumpyKneed(params)
    walker_sim, walker_map, walker_map_jac = walker_preps("kneed", params, x0)
    out = []
    out.append(Contender("walker simulate", walker_sim, "DOP853, rtol = atol = tol", True))
    out.append(Contender("walker StrideMap", walker_map, "P(z), DOP853, rtol = atol = tol", True))
    out.append(
        Contender(
            "walker StrideMap, jacobian=True",
            walker_map_jac,
            "P(z, jacobian=True), the call find_fixed_point makes at each Newton step: the "
            "stride plus its 3x3 Jacobian from the variational equations and saltation "
            "matrices (more work than the other rows)",
            True,
        )
    )

    def ivp(obj, method):
        def prep(tol):
            if method == "RK45" and tol < 1e-11:
                return None  # thousands of steps per stride: far off the front
            return lambda: obj.stride(x0, method=method, rtol=tol, atol=tol)[0]

        return prep

    out.append(
        Contender(
            "solve_ivp DOP853, numpy model",
            ivp(nk, "DOP853"),
            "hand-written scalar model, rtol = atol = tol",
        )
    )
    out.append(
        Contender(
            "solve_ivp RK45, numpy model",
            ivp(nk, "RK45"),
            "hand-written scalar model, rtol = atol = tol",
        )
    )
    if ck is not None:
        out.append(
            Contender(
                "solve_ivp DOP853, walker's compiled rhs",
                ivp(ck, "DOP853"),
                "walker.models.kneed rhs/guards from Python, rtol = atol = tol",
            )
        )
    if have_heyoka:
        compile_log = {}

        def hy_prep(runtime_pars):
            def prep(tol):
                h = C.HeyokaKneed(params, tol, runtime_pars)
                compile_log.setdefault(runtime_pars, []).append(h.compile_seconds)
                return lambda: h.stride(x0)[0]

            return prep

        out.append(Contender("heyoka, par", hy_prep(True), "Taylor, tol; parameters as heyoka.par"))
        out.append(
            Contender("heyoka, const", hy_prep(False), "Taylor, tol; parameters folded as numbers")
        )
        out[-1].compile_log = compile_log
    return out


def compass_contenders(wparams, x0, drake, t_end, ref_end, have_heyoka=False):
    """Two problems: one stride (stop at the heel strike; walker only) and a fixed-time run
    from the same state to ``t_end`` (just past the heel strike), walker against Drake.
    Drake is timed on the fixed-time run only: stopping its ``Simulator`` after one stride
    takes a Python monitor called after every step (its ``CompassGait`` witness applies the
    collision but does not end the run), which would charge Drake for Python, not for its
    integrator."""
    walker_sim, walker_map, _ = walker_preps("compass", wparams, x0)

    def walker_to_t(tol):
        return lambda: (
            simulate("compass", wparams, x0, n_strides=0, t_max=t_end, rtol=tol, atol=tol).x
        )

    fixed = "walker simulate, to t_end"
    out = [
        Contender("walker simulate", walker_sim, "one stride, DOP853, rtol = atol = tol", True),
        Contender(
            "walker StrideMap", walker_map, "one stride, P(z), DOP853, rtol = atol = tol", True
        ),
        Contender(
            fixed,
            walker_to_t,
            "fixed time t_end (n_strides = 0, t_max = t_end), DOP853, rtol = atol = tol",
            True,
            ref=ref_end,
            base=fixed,
        ),
    ]
    if have_heyoka:

        def heyoka_stride(tol):
            h = C.HeyokaCompass(wparams, tol)
            return lambda: h.stride(x0)[0]

        out.append(
            Contender(
                "heyoka, const",
                heyoka_stride,
                "one stride, Taylor, tol; parameters folded as numbers (scripts/_contenders.py "
                "`HeyokaCompass`, walker's reset at the heel strike)",
            )
        )
    if drake is not None:

        def drake_to_t(tol):
            drake.set_accuracy(tol)
            return lambda: drake.advance(x0, t_end)

        out.append(
            Contender(
                "Drake RK5, to t_end",
                drake_to_t,
                "fixed time t_end: Simulator.AdvanceTo(t_end), runge_kutta5, target accuracy = tol",
                ref=ref_end,
                base=fixed,
            )
        )
    return out


# ----------------------------------------------------------------------------- the run
def sweep(contenders, tols, ref, reps, batch):
    """Error and time of every contender at every tolerance; at each tolerance the
    contenders are timed round-robin.  Returns a list of row dicts."""
    rows = []
    for tol in tols:
        fns, errs = {}, {}
        for c in contenders:
            try:
                fn = c.prepare(tol)
                x = None if fn is None else fn()
            except Exception as exc:  # e.g. an integrator refusing a tolerance
                print(f"  {c.name} at tol {tol:.1e}: {type(exc).__name__}: {exc}", flush=True)
                continue
            if fn is None:
                continue
            if x is None:
                print(f"  {c.name} at tol {tol:.1e}: stride failed", flush=True)
                continue
            r = ref if c.ref is None else c.ref
            errs[c.name] = float(np.max(np.abs(np.asarray(x) - r)))
            fns[c.name] = fn
        times = B.round_robin(fns, reps, batch)
        for name in fns:
            t = times[name]
            rows.append(
                {
                    "contender": name,
                    "tolerance": tol,
                    "error": errs[name],
                    "t_min": float(t.min()),
                    "t_median": float(np.median(t)),
                    "reps": len(t),
                }
            )
        line = "  ".join(f"{n}: {errs[n]:.1e}/{B.fmt_time(np.median(times[n]))}" for n in fns)
        print(f"tol {tol:.1e}  {line}", flush=True)
    return rows


def at_targets(contenders, rows, ref, reps, batch):
    """For each target, each contender at its cheapest tolerance meeting it (sweep medians),
    all timed again round-robin.  Returns a list of row dicts."""
    by = {c.name: c for c in contenders}
    out = []
    for target in TARGETS:
        fns, chosen = {}, {}
        for c in contenders:
            ok = [r for r in rows if r["contender"] == c.name and r["error"] <= target]
            if not ok:
                chosen[c.name] = None
                continue
            best = min(ok, key=lambda r: r["t_median"])
            fn = by[c.name].prepare(best["tolerance"])
            x = fn()
            r = ref if c.ref is None else c.ref
            chosen[c.name] = (best["tolerance"], float(np.max(np.abs(np.asarray(x) - r))))
            fns[c.name] = fn
        times = B.round_robin(fns, reps, batch)
        for c in contenders:
            if chosen[c.name] is None:
                out.append(
                    {
                        "target": target,
                        "contender": c.name,
                        "tolerance": math.nan,
                        "error": math.nan,
                        "t_min": math.nan,
                        "t_median": math.nan,
                        "reps": 0,
                    }
                )
                continue
            t = times[c.name]
            out.append(
                {
                    "target": target,
                    "contender": c.name,
                    "tolerance": chosen[c.name][0],
                    "error": chosen[c.name][1],
                    "t_min": float(t.min()),
                    "t_median": float(np.median(t)),
                    "reps": len(t),
                }
            )
        print(
            f"target {target:.0e}: "
            + "  ".join(
                f"{r['contender']}: {B.fmt_time(r['t_median'])}"
                for r in out
                if r["target"] == target
            ),
            flush=True,
        )
    return out


def table(contenders, target_rows, pairs):
    """Markdown table and the headline sentences for one problem.

    ``pairs``: (walker contender, [alternatives]) whose comparison makes a sentence; the
    table's ratio column divides by each contender's ``base`` (the walker contender solving
    the same problem)."""
    by = {c.name: c for c in contenders}
    lines = [
        "| error target | contender | tolerance | error reached | min | median "
        "| median / walker's median, same problem |",
        "|---|---|---|---|---|---|---|",
    ]
    sentences = []
    for target in TARGETS:
        rows = {r["contender"]: r for r in target_rows if r["target"] == target}
        for name, r in rows.items():
            if not np.isfinite(r["t_median"]):
                lines.append(
                    f"| {target:.0e} | {name} | — | not reached over the tolerances swept "
                    "| — | — | — |"
                )
                continue
            base = rows.get(by[name].base)
            ratio = r["t_median"] / base["t_median"] if base is not None else math.nan
            lines.append(
                f"| {target:.0e} | {name} | {r['tolerance']:.1e} | "
                f"{r['error']:.1e} | {B.fmt_time(r['t_min'])} | {B.fmt_time(r['t_median'])} "
                f"| {ratio:.2f} |"
            )
        for wname, alts in pairs:
            w = rows[wname]
            others = [rows[a] for a in alts if a in rows and np.isfinite(rows[a]["t_median"])]
            if not np.isfinite(w["t_median"]):
                sentences.append(f"- error {target:.0e}: {wname} did not reach it.")
                continue
            if not others:
                sentences.append(f"- error {target:.0e}: no alternative to {wname} reached it.")
                continue
            best = min(others, key=lambda r: r["t_median"])
            rel = B.speed_ratio(best["t_median"] / w["t_median"])
            which = "the fastest alternative, " if len(alts) > 1 else ""
            sentences.append(
                f"- error {target:.0e}: {wname} {B.fmt_time(w['t_median'])} (median; min "
                f"{B.fmt_time(w['t_min'])}), {rel} {which}{best['contender']} at tolerance "
                f"{best['tolerance']:.0e} ({B.fmt_time(best['t_median'])}; min "
                f"{B.fmt_time(best['t_min'])}); by the minima "
                f"{B.speed_ratio(best['t_min'] / w['t_min']).split(' than')[0]}."
            )
    return lines, sentences


def csv_row(problem, kind, target, r):
    """One row of stride.csv: a contender at one tolerance (``kind`` "sweep") or at an
    error target (``kind`` "target", ``target`` its text)."""
    return [
        problem,
        kind,
        target,
        r["contender"],
        f"{r['tolerance']:.3e}",
        f"{r['error']:.4e}",
        f"{r['t_min']:.4e}",
        f"{r['t_median']:.4e}",
        r["reps"],
    ]


def plot(panels, path):
    fig, axes = plt.subplots(len(panels), 1, figsize=(10, 4.6 * len(panels)), squeeze=False)
    markers = "osD^v<>px*h"
    for ax, (title, rows, contenders, xlabel, ylabel) in zip(axes[:, 0], panels, strict=True):
        for i, c in enumerate(contenders):
            rs = sorted(
                (r for r in rows if r["contender"] == c.name and r["error"] > 0),
                key=lambda r: r["tolerance"],
            )
            if not rs:
                continue
            ax.loglog(
                [r["error"] for r in rs],
                [r["t_median"] * 1e6 for r in rs],
                marker=markers[i % len(markers)],
                linestyle="-" if c.walker else "--",
                label=c.name,
            )
        for t in TARGETS:
            ax.axvline(t, color="0.7", lw=0.8, ls=":")
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    fig.tight_layout()
    B.savefig_atomic(fig, path, dpi=110)
    plt.close(fig)


def main(argv=None):
    quick, cmd = B.quick_options("bench_stride.py", __doc__, "fewer tolerances and repeats", argv)
    if quick:
        tols = [1e-4, 1e-6, 1e-8, 1e-10, 1e-12]
        reps_sweep, reps_target, batch = 3, 5, 0.005
    else:
        tols = [10.0 ** (-k / 2) for k in range(6, 28)]  # 1e-3 ... 3.2e-14, half decades
        reps_sweep, reps_target, batch = 7, 31, 0.02
    t_start = time.perf_counter()
    load_before = B.load_line()
    notes = []

    try:
        import heyoka

        have_heyoka = True
        heyoka_version = heyoka.__version__
    except ImportError:
        have_heyoka = False
        heyoka_version = None
        notes.append("heyoka is not installed (`pip install -e .[bench]`): its rows are skipped.")
    try:
        from pydrake.examples import CompassGait  # noqa: F401

        have_drake = True
        drake_version = importlib.metadata.version("drake")
    except ImportError:
        have_drake = False
        drake_version = None
        notes.append(
            "pydrake is not installed (`pip install -e .[bench]`): the Drake comparison is skipped."
        )

    # ------------------------------------------------------------------ kneed walker
    scene = load_scene(B.GAITS / "kneed_hsu.toml")
    params = scene.params
    x0 = np.array(scene.reference["state"], dtype=float)
    ref_sol = simulate("kneed", params, x0, rtol=REF_RTOL, atol=REF_ATOL)
    ref = ref_sol.x.copy()
    nk = C.NumpyKneed(params)
    chk, t_chk, _ = nk.stride(x0, "DOP853", 1e-13, 1e-13)
    ref_check = float(np.max(np.abs(chk - ref)))
    try:
        ck = C.CompiledKneed(params)
        chk2, _, _ = ck.stride(x0, "DOP853", 1e-13, 1e-13)
        ref_check2 = float(np.max(np.abs(chk2 - ref)))
    except (AttributeError, TypeError) as exc:  # the model module's functions changed
        ck, ref_check2 = None, math.nan
        notes.append(
            "walker.models.kneed offers no Python-callable `rhs`/`guards` as this script "
            f"expects ({type(exc).__name__}: {exc}): the solve_ivp-on-walker's-rhs rows are "
            "skipped."
        )
    print(
        f"kneed reference (walker DOP853 rtol {REF_RTOL}) vs solve_ivp DOP853 1e-13: "
        f"numpy model {ref_check:.1e}, compiled rhs {ref_check2:.1e}; step time "
        f"{ref_sol.t:.15f} vs {t_chk:.15f}",
        flush=True,
    )
    kc = kneed_contenders(params, x0, have_heyoka, ck)
    k_rows = sweep(kc, tols, ref, reps_sweep, batch)
    k_target = at_targets(kc, k_rows, ref, reps_target, batch)
    heyoka_compile = None
    for c in kc:
        if hasattr(c, "compile_log"):
            heyoka_compile = c.compile_log

    # ------------------------------------------------------------------ compass vs Drake
    c_rows, c_target, cc, drake_info = [], [], None, None
    if have_drake:
        dp, wp = _drake.drake_params()
        same_as_preset = wp == CompassParams.drake()
        cscene = load_scene(B.GAITS / "compass_goswami.toml")
        P = StrideMap("compass", wp, rtol=1e-13, atol=1e-13)
        fp = find_fixed_point(P, P.project(cscene.state), tol=1e-12)
        xc = fp.state.copy()
        cref_sol = simulate("compass", wp, xc, rtol=REF_RTOL, atol=REF_ATOL)
        cref = cref_sol.x.copy()
        t_end = cref_sol.t + T_PAST
        cref_end = simulate(
            "compass", wp, xc, n_strides=0, t_max=t_end, rtol=REF_RTOL, atol=REF_ATOL
        ).x.copy()
        drake = _drake.DrakeCompass(max_step=1.0)
        drake.set_accuracy(1e-12)
        xd, td = drake.stride(xc)
        xd_end = drake.advance(xc, t_end)
        drake_info = {
            "params": dp,
            "same_as_preset": same_as_preset,
            "fixed_point": xc,
            "step_time": cref_sol.t,
            "t_end": t_end,
            "drake_step_time": td,
            "drake_state_diff": float(np.max(np.abs(xd - cref))),
            "drake_end_diff": float(np.max(np.abs(xd_end - cref_end))),
        }
        print(
            f"compass at Drake's defaults {dp}: walker step time {cref_sol.t:.15f}, Drake "
            f"(accuracy 1e-12) {td:.15f}; post-stride states differ by "
            f"{drake_info['drake_state_diff']:.1e}, states at t_end by "
            f"{drake_info['drake_end_diff']:.1e}",
            flush=True,
        )
        cc = compass_contenders(wp, xc, drake, t_end, cref_end, have_heyoka)
        c_rows = sweep(cc, tols, cref, reps_sweep, batch)
        c_target = at_targets(cc, c_rows, cref, reps_target, batch)

    # ------------------------------------------------------------------ outputs
    B.OUT.mkdir(parents=True, exist_ok=True)
    header = [
        "problem",
        "kind",
        "error_target",
        "contender",
        "tolerance",
        "error",
        "t_min_s",
        "t_median_s",
        "reps",
    ]
    csv_rows = []
    for problem, rows, trows in (("kneed", k_rows, k_target), ("compass", c_rows, c_target)):
        csv_rows += [csv_row(problem, "sweep", "", r) for r in rows]
        csv_rows += [csv_row(problem, "target", f"{r['target']:.0e}", r) for r in trows]
    B.write_csv_atomic(B.OUT / "stride.csv", header, csv_rows)

    panels = [
        (
            "one kneed-walker stride (kneed_hsu.toml, reference fixed point)",
            k_rows,
            kc,
            "error: max-norm of the post-stride state minus the reference stride's [rad, rad/s]",
            "time per stride, median [µs]",
        )
    ]
    if cc is not None:
        panels.append(
            (
                "one compass-gait stride at Drake's default parameters",
                c_rows,
                cc,
                "error: max-norm of the final state (post-stride, or at t_end) minus the "
                "reference's [rad, rad/s]",
                "time per run (one stride, or to t_end), median [µs]",
            )
        )
    plot(panels, B.OUT / "work_precision.png")

    k_pairs = [("walker simulate", [c.name for c in kc if not c.walker])]
    if have_heyoka:
        k_pairs.append(("walker StrideMap", ["heyoka, const"]))
    k_lines, k_sent = table(kc, k_target, k_pairs)
    summary = "Kneed walker, " + k_sent[len(k_pairs)].lstrip("- ")
    if have_heyoka:
        summary += " Kneed walker, " + k_sent[-1].lstrip("- ")
    if cc is not None:
        c_pairs = [("walker simulate, to t_end", ["Drake RK5, to t_end"])]
        if have_heyoka:
            c_pairs.append(("walker StrideMap", ["heyoka, const"]))
        c_lines, c_sent = table(cc, c_target, c_pairs)
        c_main = next((x for x in c_sent if "error 1e-08" in x), c_sent[0])
        summary += " Compass gait at Drake's defaults, " + c_main.lstrip("- ")
        if have_heyoka:
            summary += " Compass gait, " + c_sent[-1].lstrip("- ")
    how = (
        "every contender in one process, interleaved round-robin at each error target "
        f"({reps_target} rounds, starting contender rotated), min and median per contender; "
        f"the machine is shared ({load_before} before, {B.load_line()} after): under load "
        "absolute times are inflated, and the ratios are the result. Equal error, not "
        "equal tolerance: each contender at its cheapest tolerance meeting the target. "
        "Strongest alternative, kneed walker: heyoka's Taylor integrator with the parameters "
        "folded in as compile-time constants (LLVM compile not in the times), also set "
        "against walker's `StrideMap` (integrator, events and impact map in both) for the "
        "kneed walker and the compass gait. Compass gait: "
        "Drake's `Simulator` with `runge_kutta5` on the run to a fixed t_end (step time + "
        f"{T_PAST * 1e3:g} ms, through the heel strike by Drake's own witness and collision "
        "update) against walker's `simulate` to the same t_end; no Python runs during "
        "Drake's timed calls (a one-stride stop would need a Python monitor after every "
        "step, about 60% of Drake's time, so it is not timed)"
        + ("" if have_drake else " (pydrake not installed here: the Drake rows are missing)")
        + "."
    )
    md = [
        "# One stride at equal error",
        "",
        f"<!-- command: {cmd} -->",
        f"<!-- summary: {summary} -->",
        f"<!-- how: {how} -->",
        "",
        f"**How measured:** {how}",
        "",
        f"Made by `{cmd}` in {time.perf_counter() - t_start:.0f} s on {B.machine_line()}"
        + (f", heyoka {heyoka_version}" if heyoka_version else "")
        + (f", drake {drake_version}" if drake_version else "")
        + ".",
        "",
        "**Error** = max-norm over the state components (angles [rad], rates [rad/s]) of the "
        "state just after the next heel strike minus that of a reference stride: walker "
        f"DOP853 at rtol {REF_RTOL:g}, atol {REF_ATOL:g}, which agrees with scipy "
        f"`solve_ivp` DOP853 at rtol = atol = 1e-13 to {ref_check:.1e} (numpy model) and "
        f"{ref_check2:.1e} (walker's compiled rhs). Each contender runs over tolerances "
        + ", ".join(f"{t:.0e}" for t in tols[:: (1 if quick else 2)])
        + ("" if quick else " (and the half decades between)")
        + "; at each error target the cheapest tolerance whose error meets it (by the "
        "sweep's medians) is timed again, all contenders interleaved round-robin "
        f"({reps_target} rounds, batches of ~{batch * 1e3:.0f} ms per contender per round, "
        "the starting contender rotated). Times are per stride; min and median over rounds.",
        "",
        "## Kneed walker (gaits/kneed_hsu.toml, `[reference] state`)",
        "",
        *k_sent,
        "",
        *k_lines,
        "",
        "Contenders (all apply walker's impact maps, `reset` of walker.models.kneed, at the "
        "events; the scipy and heyoka ones detect only knee lock and heel strike, walker "
        "also watches trip and fall guards):",
        "",
    ]
    for c in kc:
        md.append(f"- **{c.name}**: {c.note}.")
    md += [
        "",
        "The numpy model is the kneed walker's Lagrangian derived with sympy once at start-up "
        "and printed as scalar Python (scripts/_contenders.py `kneed_source`): parameter-only "
        "coefficients computed once, 6 trig calls per unlocked evaluation, the 3x3 (2x2 "
        "locked) solve by cofactors, no numpy.linalg; it matches walker's compiled vector "
        "field to round-off and costs about half a walker-rhs call from Python.",
    ]
    if heyoka_compile:
        for k, label in ((True, "par"), (False, "const")):
            v = heyoka_compile.get(k, [])
            if v:
                md.append(
                    f"heyoka ({label}) builds (LLVM compile) its two integrators once per "
                    f"tolerance{'' if k else ' and parameter set'}: median "
                    f"{np.median(v):.2f} s, not included in the per-stride times."
                )
    md.append("")
    if cc is not None:
        di = drake_info
        pd = ", ".join(f"{k} = {v:g}" for k, v in di["params"].items())
        md += [
            "## Compass gait: walker vs Drake",
            "",
            f"Drake's `CompassGaitParams` defaults read from pydrake: {pd}. Mapped onto "
            "walker's `CompassParams`: mass_hip, mass_leg, g, slope as they are; "
            "com_to_hip = center_of_mass_leg (Drake measures it from the hip), "
            "com_from_foot = length_leg - center_of_mass_leg; point masses, point feet "
            f"(equal to walker's `CompassParams.drake()` preset: {di['same_as_preset']}). "
            "Drake's angles are clockwise from the vertical, walker's counterclockwise: "
            "x_Drake = -x_walker componentwise. The stride starts at walker's fixed point "
            "for these parameters (found from gaits/compass_goswami.toml's initial state). "
            f"Same stride: walker's step time {di['step_time']:.12f} s, Drake's at accuracy "
            f"1e-12 {di['drake_step_time']:.12f} s; post-stride states differ by "
            f"{di['drake_state_diff']:.1e}, states at t_end by {di['drake_end_diff']:.1e}.",
            "",
            "Two problems from the same state: **one stride** (stop just after the heel "
            "strike; error against walker's reference stride; walker's rows only) and **to "
            f"t_end** = step time + {T_PAST * 1e3:g} ms (a fixed-time run through the heel "
            "strike, error against walker's reference state at t_end), the problem Drake is "
            "timed on, because Drake's `AdvanceTo(t_end)` runs without any Python callback. "
            "The ratio column divides by walker's time on the same problem.",
            "",
            *c_sent,
            "",
            *c_lines,
            "",
            "Drake runs `Simulator.AdvanceTo` with the `runge_kutta5` integrator "
            "(`ResetIntegratorFromFlags`, maximum step 1 s, so only error control sets the "
            "step) and `set_target_accuracy(tol)`; its own witness function and collision "
            "update do the heel strike. Stopping after exactly one stride would need a Python "
            "monitor called after every step (`Simulator.set_monitor`; the witness applies "
            "the collision but does not end the run); an earlier version of this table timed "
            "that, and the monitor was about 60% of Drake's time, so Drake's one-stride run "
            "is used here only, untimed, for the step-time check above.",
            "",
        ]
    if notes:
        md += ["## Notes", "", *[f"- {n}" for n in notes], ""]
    md += ["![work-precision](work_precision.png)", ""]
    B.publish("stride.md", md)


if __name__ == "__main__":
    main()
