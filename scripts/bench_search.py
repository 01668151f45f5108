"""Gait-search benchmark: a periodic gait (fixed point of the stride map) with its Floquet
multipliers, walker against the scipy pipeline a user writes without walker, timed side by
side in one process (round-robin repetitions, min and median per contender, per run over
batches of back-to-back runs of about 20 ms; and the median of single runs, each right after
the other contenders').

Jobs, each from a scene's ``[initial] state`` (section coordinates by the model's
``project``) to residual ``max|P(z) - z| <= 1e-12``:

1. the kneed walker from the thesis digits (gaits/kneed_hsu.toml);
2. the compass gait (gaits/compass_goswami.toml) and the simplest walker
   (gaits/simplest_garcia.toml).

Contenders:

* walker ``find_fixed_point`` on a ``StrideMap`` with the scene's solver settings (what
  ``walker find`` runs): Newton with the exact Jacobian from the variational equations, the
  multipliers from the Jacobian at the solution; also with ``jacobian="fd"``;
* ``scipy.optimize.root(method="hybr")`` on ``F(z) = P(z) - z`` with ``P`` a ``solve_ivp``
  DOP853 stride (kneed: the hand-written numpy model of scripts/_contenders.py; compass and
  simplest: walker's compiled vector field called from Python), then the multipliers as the
  eigenvalues of a central-difference Jacobian of ``P`` at the root.

Writes results/bench/search.csv, search.md and README.md.

Usage: python scripts/bench_search.py [--quick]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import root

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _bench as B  # noqa: E402
import _contenders as C  # noqa: E402

from walker import load_scene  # noqa: E402
from walker.analysis.fixedpoint import find_fixed_point  # noqa: E402
from walker.models import get_model  # noqa: E402
from walker.simulation.stride import StrideMap  # noqa: E402

TOL = 1e-12
IVP_TOL = 1e-13  # solve_ivp rtol = atol: the map must be good to well below the residual
FD_STEP = 1e-6  # relative central-difference step for the scipy pipeline's Jacobian
BATCH_SECONDS = 0.02  # a timed batch of back-to-back runs (see the table notes)
HEYOKA_TOLS = (1e-15, 1e-14, 1e-13, 1e-12, 1e-11, 1e-10, 1e-9)  # scanned, loosest chosen


def heyoka_ok():
    try:
        import heyoka  # noqa: F401
    except ImportError:
        return False
    return True


def sort_multipliers(m):
    m = np.asarray(m, dtype=complex)
    return m[np.lexsort((-m.imag, -np.abs(m)))]


def multiplier_error(m, ref):
    """Max distance between two multiplier sets, matched greedily (conjugates included)."""
    if ref is None or not np.all(np.isfinite(m)):
        return np.nan
    left = list(np.asarray(ref, dtype=complex))
    worst = 0.0
    for v in m:
        k = int(np.argmin([abs(v - r) for r in left]))
        worst = max(worst, abs(v - left.pop(k)))
    return worst


def scipy_pipeline(P, z0, tol=IVP_TOL):
    """root(hybr) on P(z) - z, then central-difference Jacobian eigenvalues."""
    n_eval = [0]

    def F(z):
        n_eval[0] += 1
        pz = P(z, tol, tol)
        if pz is None:  # a fall: a large residual pushes hybr back
            return np.full(len(z), 1e3)
        return pz - z

    sol = root(F, z0, method="hybr", options={"xtol": 1e-14})
    z = sol.x
    r = F(z)
    n = len(z)
    J = np.empty((n, n))
    for j in range(n):
        h = FD_STEP * max(1.0, abs(z[j]))
        e = np.zeros(n)
        e[j] = h
        pp, pm = P(z + e, tol, tol), P(z - e, tol, tol)
        n_eval[0] += 2
        if pp is None or pm is None:
            J[:] = np.nan
            break
        J[:, j] = (pp - pm) / (2 * h)
    mult = np.linalg.eigvals(J) if np.all(np.isfinite(J)) else np.full(n, np.nan)
    return {
        "z": z,
        "residual": float(np.max(np.abs(r))),
        "multipliers": sort_multipliers(mult),
        "work": f"{n_eval[0]} strides (hybr: {sol.nfev} evaluations, status {sol.status})",
        "success": float(np.max(np.abs(r))) <= TOL,
    }


def heyoka_tolerance(scene, z0, z_walker):
    """The loosest heyoka tolerance (folded parameters) whose search finds the fixed point
    as accurately as walker's.

    Reference: scipy ``root(hybr)`` (xtol 1e-15) on heyoka's stride at tolerance machine
    epsilon, a Taylor integrator independent of walker's DOP853.  "As accurately": the
    distance to the reference is at most the decade above walker's own distance
    (``10**ceil(log10(d_walker))``), and the residual on heyoka's own map meets ``TOL``.
    Returns a dict: the chosen map and tolerance, its compile time, the reference, walker's
    distance, the threshold and the scan ``[(tol, distance, residual), ...]``.
    """
    from scipy.optimize import root as _root

    def section(tol):
        t = time.perf_counter()
        hk = C.HeyokaKneed(scene.params, tol, runtime_pars=False)
        compile_s = time.perf_counter() - t

        class _S:
            def stride(self, x0, method=None, rtol=None, atol=None):
                x, t_step = hk.stride(x0)
                return x, t_step, 0

        return hk, C.section_map(scene.model, _S(), scene.params), compile_s

    _, P_ref, _ = section(float(np.finfo(float).eps))
    sol = _root(lambda z: P_ref(z, 0, 0) - z, z0, method="hybr", options={"xtol": 1e-15})
    z_ref = sol.x
    d_walker = float(np.max(np.abs(z_walker - z_ref)))
    threshold = 10.0 ** np.ceil(np.log10(max(d_walker, 1e-16)))
    scan, chosen = [], None
    for tol in HEYOKA_TOLS:
        hk, Ph, compile_s = section(tol)
        r = scipy_pipeline(Ph, z0)
        d = float(np.max(np.abs(r["z"] - z_ref)))
        scan.append((tol, d, r["residual"]))
        print(f"heyoka folded tol {tol:g}: |z - z_hp| {d:.1e}, residual {r['residual']:.1e}")
        if r["success"] and d <= threshold:
            chosen = {"map": hk, "tol": tol, "compile_s": compile_s}
    if chosen is None:  # none as accurate: the tightest, stated as such in the table
        hk, _, compile_s = section(HEYOKA_TOLS[0])
        chosen = {"map": hk, "tol": HEYOKA_TOLS[0], "compile_s": compile_s}
    residual_ref = float(np.max(np.abs(P_ref(z_ref, 0, 0) - z_ref)))
    return dict(
        chosen,
        z_ref=z_ref,
        residual_ref=residual_ref,
        d_walker=d_walker,
        threshold=threshold,
        scan=scan,
    )


def walker_pipeline(P, z0, jacobian):
    fp = find_fixed_point(P, z0, tol=TOL, jacobian=jacobian)
    return {
        "z": fp.section,
        "residual": float(fp.residual),
        "multipliers": sort_multipliers(fp.multipliers),
        "work": f"{fp.n_iter} Newton steps",
        "success": bool(fp.success),
    }


def job(name, scene_file, reps, batch):
    scene = load_scene(B.GAITS / scene_file)
    model = get_model(scene.model)
    c = scene.compute
    p = scene.params.as_array()
    P = StrideMap(
        scene.model, scene.params, method=c.method, rtol=c.rtol, atol=c.atol, t_max=c.t_max
    )
    z0 = model.project(scene.state, p)
    if scene.model == "kneed":
        stride_obj = C.NumpyKneed(scene.params)
        ivp_label = "hand-written numpy model"
    else:
        stride_obj = C.CompiledSimple(scene.model, scene.params)
        ivp_label = "walker's compiled rhs"
    Pi = C.section_map(scene.model, stride_obj, scene.params)
    z_ref = m_ref = None
    if scene.reference is not None:
        z_ref = model.project(scene.reference["state"], p)
        m_ref = scene.reference.get("multipliers")
    contenders = {
        "walker find_fixed_point": lambda: walker_pipeline(P, z0, "exact"),
        'walker find_fixed_point(jacobian="fd")': lambda: walker_pipeline(P, z0, "fd"),
        f"scipy root(hybr) + solve_ivp DOP853 ({ivp_label})": lambda: scipy_pipeline(Pi, z0),
    }
    notes = {
        "walker find_fixed_point": f"StrideMap {c.method} rtol {c.rtol:g}, atol "
        f"{c.atol:g} (the scene's settings, as `walker find`); exact Jacobian",
        'walker find_fixed_point(jacobian="fd")': "same map; central differences, step 1e-7",
        f"scipy root(hybr) + solve_ivp DOP853 ({ivp_label})": f"solve_ivp rtol = atol = "
        f"{IVP_TOL:g}; hybr xtol 1e-14; multipliers: eigenvalues of a central-difference "
        f"Jacobian, step {FD_STEP:g}",
    }
    heyoka_info = None
    if scene.model == "kneed" and heyoka_ok():
        # heyoka's Taylor integrator for the same stride, parameters folded in as numbers
        # (a search holds one parameter set, so one compile serves it): the fastest single
        # stride in bench_stride.py, so the strongest map to hand to hybr.  Its tolerance is
        # the loosest that finds the fixed point as accurately as walker's search does,
        # both measured against a high-precision reference (heyoka_tolerance).
        heyoka_info = heyoka_tolerance(scene, z0, walker_pipeline(P, z0, "exact")["z"])
        hk, tol_h, compile_s = heyoka_info["map"], heyoka_info["tol"], heyoka_info["compile_s"]

        class _HyStride:
            def stride(self, x0, method=None, rtol=None, atol=None):
                x, t_step = hk.stride(x0)
                return x, t_step, 0

        Ph = C.section_map(scene.model, _HyStride(), scene.params)
        k = f"scipy root(hybr) + heyoka Taylor stride (folded, tol {tol_h:g})"
        contenders[k] = lambda: scipy_pipeline(Ph, z0)
        notes[k] = (
            f"heyoka taylor_adaptive, parameters folded in as numbers, tol {tol_h:g} (the "
            "loosest of the scan in How measured whose fixed point is as close to the "
            "high-precision reference as walker's), events for knee lock and heel strike, "
            "walker's impact maps; hybr and multipliers as above; building the two "
            f"integrators (LLVM) took {compile_s:.2f} s once, not in the times"
        )
    results = {k: fn() for k, fn in contenders.items()}  # warm-up, and the answers
    # batches of back-to-back runs lasting about `batch` seconds (one run of the scipy
    # pipelines): the steady state of a sweep or a continuation; and single runs, each
    # right after the other contenders' (caches taken over by them)
    times = B.round_robin(contenders, reps, batch)
    single = B.round_robin(contenders, reps, 0.0, inner={k: 1 for k in contenders})
    rows = []
    for k in contenders:
        r = results[k]
        t = times[k]
        rows.append(
            {
                "job": name,
                "contender": k,
                "t_min": float(t.min()),
                "t_median": float(np.median(t)),
                "t_single_median": float(np.median(single[k])),
                "reps": len(t),
                "success": r["success"],
                "residual": r["residual"],
                "dist_ref": float(np.max(np.abs(r["z"] - z_ref))) if z_ref is not None else np.nan,
                "mult_err": multiplier_error(r["multipliers"], m_ref),
                "multipliers": r["multipliers"],
                "work": r["work"],
                "note": notes[k],
                "ref_tol": scene.reference["tolerance"] if scene.reference else np.nan,
            }
        )
        print(
            f"{name}: {k}: {B.fmt_time(np.median(t))} residual {r['residual']:.1e} "
            f"|z - z_ref| {rows[-1]['dist_ref']:.1e} mult err {rows[-1]['mult_err']:.1e} "
            f"({r['work']})",
            flush=True,
        )
    if heyoka_info is not None:
        heyoka_info["d_scene_ref"] = (
            float(np.max(np.abs(z_ref - heyoka_info["z_ref"]))) if z_ref is not None else np.nan
        )
    return rows, heyoka_info


def fmt_mult(m):
    out = []
    for v in m:
        if abs(v.imag) < 1e-14:
            out.append(f"{v.real:.10f}")
        else:
            out.append(f"{v.real:.10f}{v.imag:+.10f}i")
    return ", ".join(out)


def main(argv=None):
    quick, cmd = B.quick_options("bench_search.py", __doc__, "fewer repeats", argv)
    reps = 3 if quick else 21
    t0 = time.perf_counter()
    rows, hy_info = [], None
    load_before = B.load_line()
    for name, f in (
        ("kneed (thesis digits)", "kneed_hsu.toml"),
        ("compass", "compass_goswami.toml"),
        ("simplest", "simplest_garcia.toml"),
    ):
        r, info = job(name, f, reps, BATCH_SECONDS)
        rows += r
        hy_info = hy_info or info
    header = [
        "job",
        "contender",
        "t_min_s",
        "t_median_s",
        "t_single_median_s",
        "reps",
        "success",
        "residual",
        "dist_to_reference",
        "max_multiplier_error",
        "multipliers",
        "work",
    ]
    B.write_csv_atomic(
        B.OUT / "search.csv",
        header,
        [
            [
                r["job"],
                r["contender"],
                f"{r['t_min']:.4e}",
                f"{r['t_median']:.4e}",
                f"{r['t_single_median']:.4e}",
                r["reps"],
                r["success"],
                f"{r['residual']:.3e}",
                f"{r['dist_ref']:.3e}",
                f"{r['mult_err']:.3e}",
                fmt_mult(r["multipliers"]),
                r["work"],
            ]
            for r in rows
        ],
    )
    sentences = []
    for jobname in dict.fromkeys(r["job"] for r in rows):
        jr = [r for r in rows if r["job"] == jobname]
        w = jr[0]
        alts = [r for r in jr if not r["contender"].startswith("walker") and r["success"]]
        if not alts:
            sentences.append(f"- {jobname}: no alternative reached residual {TOL:g}.")
            continue
        s = min(alts, key=lambda r: r["t_median"])
        rel = B.speed_ratio(s["t_median"] / w["t_median"])
        sentences.append(
            f"- {jobname}: walker `find_fixed_point` {B.fmt_time(w['t_median'])} (median; min "
            f"{B.fmt_time(w['t_min'])}; a single run after the other contenders "
            f"{B.fmt_time(w['t_single_median'])}), residual {w['residual']:.1e}, {rel} the fastest "
            f"alternative, {s['contender']} with finite-difference multipliers, "
            f"{B.fmt_time(s['t_median'])} (min {B.fmt_time(s['t_min'])}; by the minima "
            f"{B.speed_ratio(s['t_min'] / w['t_min']).split(' than')[0]}), residual "
            f"{s['residual']:.1e}; multipliers within {w['mult_err']:.0e} (walker) and "
            f"{s['mult_err']:.0e} (alternative) of the reference."
        )
    how = (
        "each contender's whole pipeline (search to residual 1e-12 + multipliers) in one "
        f"process, interleaved round-robin, {reps} rounds, min and median; the machine was "
        f"shared ({load_before} before, {B.load_line()} after): under load the absolute "
        "times are inflated, and the ratios are the result. The strongest alternative is "
        "scipy `root(hybr)` on heyoka's Taylor stride (kneed walker)"
    )
    if hy_info is not None:
        how += (
            f" with the parameters folded in as compile-time constants at tolerance "
            f"{hy_info['tol']:g}, the loosest of {', '.join(f'{t:g}' for t in HEYOKA_TOLS)} "
            "whose fixed point is as accurate as walker's: its distance to a high-precision "
            "reference (hybr with xtol 1e-15 on heyoka's stride at tolerance machine epsilon, "
            f"residual {hy_info['residual_ref']:.1e}; it lies {hy_info['d_scene_ref']:.1e} "
            "from the scene's `[reference]` fixed point) is at most "
            f"{hy_info['threshold']:.0e}, the decade above walker's own distance "
            f"{hy_info['d_walker']:.1e}. Scan (tolerance: distance, residual): "
            + "; ".join(f"{t:g}: {d:.1e}, {r:.1e}" for t, d, r in hy_info["scan"])
            + ". Its multipliers come from central differences, whose error (about 1e-8) "
            "does not depend on the tolerance; walker's come from the variational equations"
        )
    else:
        how += " (not installed here: `pip install -e .[bench]`; the row is missing)"
    how += "."
    lines = [
        "# Fixed-point search with multipliers",
        "",
        f"<!-- command: {cmd} -->",
        f"<!-- summary: {sentences[0].lstrip('- ')} -->",
        f"<!-- how: {how} -->",
        "",
        f"**How measured:** {how}",
        "",
        f"Made by `{cmd}` in {time.perf_counter() - t0:.0f} s on {B.machine_line()}.",
        "",
        "Each job starts from the scene's `[initial] state` (section coordinates by the "
        f"model's `project`) and asks for residual max|P(z) - z| <= {TOL:g} plus the Floquet "
        "multipliers. Whole pipelines (search + multipliers) are timed, contenders "
        f"interleaved round-robin ({reps} rounds, starting contender rotated). *min* and "
        f"*median*: per run, over batches of back-to-back runs lasting about "
        f"{BATCH_SECONDS * 1e3:.0f} ms each (one run for a pipeline slower than that), the "
        "steady state of a sweep or a continuation; *single run*: the median of one run per "
        "round, each right after the other contenders' runs (the caches taken over by them: "
        "the first search of a script). *residual*: max|P(z) - z| at the returned "
        "point on the contender's own map; *distance to z_ref*: max-norm distance to the scene's "
        "`[reference]` fixed point (walker DOP853 at rtol 1e-13; its stated tolerance in "
        "brackets); *mult. error*: largest distance of a multiplier to the reference "
        "multipliers.",
        "",
        *sentences,
        "",
        "| job | contender | min | median | median / walker | single run | residual | "
        "distance to z_ref [tol] | mult. error | work | multipliers |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        w = next(x for x in rows if x["job"] == r["job"])
        lines.append(
            f"| {r['job']} | {r['contender']} | {B.fmt_time(r['t_min'])} | "
            f"{B.fmt_time(r['t_median'])} | {r['t_median'] / w['t_median']:.2f} | "
            f"{B.fmt_time(r['t_single_median'])} | "
            f"{r['residual']:.1e}{'' if r['success'] else ' (target missed)'} | "
            f"{r['dist_ref']:.1e} [{r['ref_tol']:.0e}] | {r['mult_err']:.1e} | {r['work']} | "
            f"{fmt_mult(r['multipliers'])} |"
        )
    lines += ["", "Contenders:", ""]
    for r in rows:
        if r["job"].startswith("kneed") or not r["contender"].startswith("walker"):
            lines.append(f"- {r['job']}, **{r['contender']}**: {r['note']}.")
    lines += [
        "",
        "The kneed scipy stride is the hand-written model of scripts/_contenders.py (scalar "
        "Python from the Lagrangian, closed-form solve, terminal events for knee lock and "
        "heel strike, walker's impact maps). Compass: the swing foot's height falling "
        "through zero, walker's reset telling heel strike from scuff; simplest: Garcia's "
        "phi - 2 theta rising through zero with theta < 0; both with walker's compiled rhs "
        "and impact map and a terminal fall event (scripts/_contenders.py `CompiledSimple`).",
        "",
    ]
    B.publish("search.md", lines)


if __name__ == "__main__":
    main()
