"""The golden corpus's computations, shared by its generator (``tests/golden/make_golden.py``)
and its check (``tests/test_golden.py``): the same calls record the numbers and recompute
them.

Only the compiled path is used: the functions of each registry entry of
``walker._hybrid.models()`` are called at their addresses through ctypes, and the scenes run
through the public API (``StrideMap``, ``find_fixed_point``, ``simulate``).  No numba twin
and no generated Python kernel module is called.

An entry's calls are described by its inputs (arrays named ``<what>.in``-style keys below)
and its sizes; :func:`entry_outputs` returns the outputs for those inputs, and
:func:`scene_outputs` the outputs of one scene.
"""

from __future__ import annotations

import ctypes
from pathlib import Path

import numpy as np

GOLDEN_DIR = Path(__file__).resolve().parent / "golden"
ENTRIES_FILE = GOLDEN_DIR / "entries.npz"
SCENES_FILE = GOLDEN_DIR / "scenes.npz"
REPO = Path(__file__).resolve().parents[1]

# the sizes an entry's calls need, stored with its inputs as "<entry>.sizes" in this order
SIZE_FIELDS = ("n_x", "n_p", "n_phases", "n_guards", "n_impulse", "n_points", "n_z")
# the scenes' event runs: strides (models with strides) and seconds (models without)
EVENT_STRIDES = 3
NO_STRIDE_T_MAX = 2.0
# the scenes' small basins (walker.analysis.basin.basin_map, the compiled basin loop): a BASIN_N
# grid within BASIN_HALF_WIDTH of the fixed point in the first two section coordinates, at most
# BASIN_STRIDES strides a point, converged within BASIN_TOL
BASIN_N = (3, 3)
BASIN_HALF_WIDTH = 0.02
BASIN_STRIDES = 5
BASIN_TOL = 1e-3
# sentinel written past the end of every output buffer: a C function that writes beyond its
# output's length is caught (the sentinel must come back unchanged)
PAD = 2
SENTINEL = -7.25e300

_vp = ctypes.c_void_p
_i64 = ctypes.c_int64
_f64 = ctypes.c_double
_RHS = ctypes.CFUNCTYPE(None, _i64, _f64, _vp, _vp, _vp, _vp)
_RHS_JAC = ctypes.CFUNCTYPE(None, _i64, _f64, _vp, _vp, _vp, _vp, _vp)
_RESET = ctypes.CFUNCTYPE(None, _i64, _i64, _f64, _vp, _vp, _vp, _vp, _vp, _vp)
_STATE = ctypes.CFUNCTYPE(None, _vp, _vp, _vp, _vp)


def registry() -> dict:
    """``walker._hybrid.models()``: registry entry name -> the addresses of its functions."""
    from walker import _hybrid

    return _hybrid.models()


def save(path: Path, arrays: dict) -> None:
    """Write ``arrays`` as an npz file (deflated, as ``np.savez_compressed`` does) whose bytes
    depend on the arrays alone: fixed member timestamps, so regenerating an unchanged corpus
    leaves the file unchanged."""
    import io
    import zipfile

    tmp = path.with_suffix(".tmp")
    with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        for name, value in arrays.items():
            buf = io.BytesIO()
            np.lib.format.write_array(buf, np.asanyarray(value), allow_pickle=False)
            info = zipfile.ZipInfo(name + ".npy", date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            zf.writestr(info, buf.getvalue(), compresslevel=9)
    tmp.replace(path)


def key(entry: str, what: str) -> str:
    """The npz key of array ``what`` of registry entry ``entry`` ("/" is spelled "+")."""
    return f"{entry.replace('/', '+')}.{what}"


def entry_names_in(data) -> list[str]:
    """The registry entries recorded in ``data`` (an npz file's arrays), in recorded order."""
    return [k[: -len(".sizes")].replace("+", "/") for k in data if k.endswith(".sizes")]


class _Buffer:
    """A float64 output buffer of ``n`` values followed by :data:`PAD` sentinels."""

    def __init__(self, n: int, fill: float = np.nan):
        self.n = n
        self.data = np.full(n + PAD, SENTINEL)
        self.data[:n] = fill

    @property
    def ptr(self) -> int:
        return self.data.ctypes.data

    def value(self, what: str) -> np.ndarray:
        if not (self.data[self.n :] == SENTINEL).all():
            raise AssertionError(f"{what} wrote past the end of its output ({self.n} values)")
        return self.data[: self.n].copy()


def _vec(a) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64)


def entry_outputs(entry: str, addresses: dict, inputs: dict) -> dict[str, np.ndarray]:
    """Every output of registry entry ``entry`` (addresses ``addresses``) on ``inputs``.

    ``inputs`` holds (by the names used below, without the entry prefix): ``sizes``;
    ``x`` (n, n_x) states, ``p`` (n, n_p) parameter vectors, ``t`` (n,) times;
    ``phase_calls`` (m, 2) rows (sample, phase) for rhs, jac and guards; ``reset_calls``
    (r, 3) rows (sample, phase, guard); ``z`` (n_lift, n_z) and ``z_p`` (n_lift,) sample
    rows for the lift when the entry has one.

    Returns the outputs by name: ``rhs`` (m, n_x), ``jac`` (m, n_x, n_x), ``guards``
    (m, n_guards), ``rhs_jac_dx`` (m, n_x) and ``rhs_jac_J`` (m, n_x, n_x) of the fused rhs
    and Jacobian where the entry has one, ``reset_out`` (r, 3) int64 (action, next phase,
    status), ``reset_x`` (r, n_x), ``reset_impulse`` (r, n_impulse), ``energy`` (n, 2), ``points``
    (n, n_points, 2), ``start_phase`` (n,), ``lift`` (n_lift, n_x) and ``lift_jacobian``
    (n_lift, n_x, n_z) for the entries that have them.
    """
    sizes = dict(zip(SIZE_FIELDS, (int(v) for v in inputs["sizes"]), strict=True))
    n_x, n_g, n_imp = sizes["n_x"], sizes["n_guards"], sizes["n_impulse"]
    X, P, T = inputs["x"], inputs["p"], inputs["t"]
    rhs_fn, guards_fn, jac_fn = (_RHS(addresses[k]) for k in ("rhs", "guards", "jac"))
    reset_fn = _RESET(addresses["reset"])
    out: dict[str, list] = {k: [] for k in ("rhs", "jac", "guards")}
    rhs_jac_fn = None
    if addresses.get("rhs_jac"):
        rhs_jac_fn = _RHS_JAC(addresses["rhs_jac"])
        out.update(rhs_jac_dx=[], rhs_jac_J=[])
    for sample, phase in inputs["phase_calls"].tolist():
        x, p, t = _vec(X[sample]), _vec(P[sample]), float(T[sample])
        where = f"{entry} phase {phase} sample {sample}"
        for name, fn, n in (("rhs", rhs_fn, n_x), ("guards", guards_fn, n_g)):
            buf = _Buffer(n)
            fn(phase, t, x.ctypes.data, p.ctypes.data, buf.ptr, None)
            out[name].append(buf.value(f"{name} of {where}"))
        buf = _Buffer(n_x * n_x)
        jac_fn(phase, t, x.ctypes.data, p.ctypes.data, buf.ptr, None)
        out["jac"].append(buf.value(f"jac of {where}").reshape(n_x, n_x))
        if rhs_jac_fn is not None:
            dx, J = _Buffer(n_x), _Buffer(n_x * n_x)
            rhs_jac_fn(phase, t, x.ctypes.data, p.ctypes.data, dx.ptr, J.ptr, None)
            out["rhs_jac_dx"].append(dx.value(f"rhs_jac dx of {where}"))
            out["rhs_jac_J"].append(J.value(f"rhs_jac J of {where}").reshape(n_x, n_x))
    resets: dict[str, list] = {"reset_out": [], "reset_x": [], "reset_impulse": []}
    for sample, phase, k in inputs["reset_calls"].tolist():
        x, p, t = _vec(X[sample]), _vec(P[sample]), float(T[sample])
        where = f"reset of {entry} phase {phase} guard {k} sample {sample}"
        x_new = _Buffer(n_x)
        x_new.data[:n_x] = x  # the integrator hands the reset a copy of the state
        impulse = _Buffer(n_imp, 0.0)
        action = np.full(3 + PAD, -99, dtype=np.int64)
        reset_fn(
            phase,
            k,
            t,
            x.ctypes.data,
            p.ctypes.data,
            x_new.ptr,
            impulse.ptr,
            action.ctypes.data,
            None,
        )
        if not (action[3:] == -99).all():
            raise AssertionError(f"{where} wrote past its (action, phase, status) output")
        resets["reset_out"].append(action[:3].copy())
        resets["reset_x"].append(x_new.value(where))
        resets["reset_impulse"].append(impulse.value(where))
    state_fns = [("energy", 2), ("points", 2 * sizes["n_points"]), ("start_phase", 1)]
    result = {k: np.array(v, dtype=np.float64) for k, v in out.items()}
    result["reset_out"] = np.array(resets["reset_out"], dtype=np.int64).reshape(-1, 3)
    result["reset_x"] = np.array(resets["reset_x"], dtype=np.float64)
    result["reset_impulse"] = np.array(resets["reset_impulse"], dtype=np.float64)
    for name, n in state_fns:
        if not addresses.get(name):
            continue
        fn = _STATE(addresses[name])
        rows = []
        for sample in range(len(X)):
            x, p = _vec(X[sample]), _vec(P[sample])
            buf = _Buffer(n)
            fn(x.ctypes.data, p.ctypes.data, buf.ptr, None)
            rows.append(buf.value(f"{name} of {entry} sample {sample}"))
        result[name] = np.array(rows, dtype=np.float64)
    result["points"] = result["points"].reshape(len(X), sizes["n_points"], 2)
    if "start_phase" in result:
        result["start_phase"] = result["start_phase"].reshape(len(X))
    n_z = sizes["n_z"]
    for name, n in (("lift", n_x), ("lift_jacobian", n_x * n_z)):
        if not addresses.get(name):
            continue
        fn = _STATE(addresses[name])
        rows = []
        for z, sample in zip(inputs["z"], inputs["z_p"].tolist(), strict=True):
            z, p = _vec(z), _vec(P[sample])
            buf = _Buffer(n)
            fn(z.ctypes.data, p.ctypes.data, buf.ptr, None)
            rows.append(buf.value(f"{name} of {entry} at z {z}"))
        result[name] = np.array(rows, dtype=np.float64)
    if "lift_jacobian" in result:
        result["lift_jacobian"] = result["lift_jacobian"].reshape(-1, n_x, n_z)
    return result


def shipped_scenes() -> list[Path]:
    """The scene files walker ships (``gaits/*.toml``), sorted by name."""
    return sorted((REPO / "gaits").glob("*.toml"))


def scene_outputs(path: Path) -> dict[str, np.ndarray]:
    """One scene's recorded outputs, by name.

    For a scene whose model has strides: ``stride_*`` (one stride of the scene's
    :class:`walker.StrideMap` from the section point of its state, with the Jacobian:
    ``stride_z0``, ``stride_z``, ``stride_jac``, ``stride_t``, ``stride_x``,
    ``stride_status``) and ``fp_*`` (:func:`walker.analysis.fixedpoint.find_fixed_point` from there
    with its defaults: ``fp_section``, ``fp_state``, ``fp_jacobian``, ``fp_multipliers``,
    ``fp_step_time``, ``fp_residual``, ``fp_history``, ``fp_n_iter``, ``fp_status``) and,
    when it converged and the section has two coordinates or more, ``basin_*`` (a small
    basin around it, :data:`BASIN_N`: ``basin_x``, ``basin_y``, ``basin_outcome``,
    ``basin_strides``).  For
    every scene ``run_*``: ``simulate(..., output="events")`` from the scene's state with
    its solver settings, :data:`EVENT_STRIDES` strides (or :data:`NO_STRIDE_T_MAX` seconds
    for a model without strides); for walkers also ``jac_run_*``, one stride of it with the
    full sensitivities (``jacobian=True``: ``jac_run_jac``, ``jac_run_dt_dx0``; one stride
    only, as three strides of the five-link walker's full sensitivities take seconds).
    """
    from walker import StrideMap, load_scene, simulate
    from walker.analysis.fixedpoint import find_fixed_point
    from walker.simulation.stride import solver_settings

    scene = load_scene(path)
    model = scene.walker_model
    out: dict[str, np.ndarray] = {}
    settings = solver_settings(scene.compute)
    if model.has_strides:
        smap = StrideMap.from_scene(scene)
        z0 = smap.project(scene.state)
        r = smap(z0, jacobian=True)
        out["stride_z0"] = np.asarray(z0, dtype=np.float64)
        out["stride_z"] = np.asarray(r.z, dtype=np.float64)
        out["stride_jac"] = np.asarray(r.jac, dtype=np.float64)
        out["stride_t"] = np.float64(r.step_time)
        out["stride_x"] = np.asarray(r.state, dtype=np.float64)
        out["stride_status"] = np.int64(int(r.status))
        fp = find_fixed_point(smap, z0)
        out["fp_section"] = np.asarray(fp.section, dtype=np.float64)
        out["fp_state"] = np.asarray(fp.state, dtype=np.float64)
        out["fp_jacobian"] = np.asarray(fp.jacobian, dtype=np.float64)
        out["fp_multipliers"] = np.asarray(fp.multipliers, dtype=np.complex128)
        out["fp_step_time"] = np.float64(fp.step_time)
        out["fp_residual"] = np.float64(fp.residual)
        out["fp_history"] = np.asarray(fp.history, dtype=np.float64)
        out["fp_n_iter"] = np.int64(fp.n_iter)
        out["fp_status"] = np.int64(int(fp.status))
        if fp.success and smap.n_z >= 2:
            out.update(_basin_record(smap, fp))
        sol = simulate(
            model,
            scene.params,
            scene.state,
            n_strides=1,
            phase0=scene.phase,
            output="events",
            jacobian=True,
            **settings,
        )
        out.update(_run_record("jac_run", sol))
        out["jac_run_jac"] = np.asarray(sol.jac, dtype=np.float64)
        out["jac_run_dt_dx0"] = np.asarray(sol.dt_dx0, dtype=np.float64)
        settings["t_max"] = settings["t_max"] * EVENT_STRIDES
        n_strides = EVENT_STRIDES
    else:
        settings["t_max"] = NO_STRIDE_T_MAX
        n_strides = 0
    sol = simulate(
        model,
        scene.params,
        scene.state,
        n_strides=n_strides,
        phase0=scene.phase,
        output="events",
        **settings,
    )
    out.update(_run_record("run", sol))
    return out


def _basin_record(smap, fp) -> dict[str, np.ndarray]:
    """A small basin of ``fp`` (see :data:`BASIN_N`), serial, by name ``basin_<what>``."""
    from walker.analysis.basin import basin_map

    z, h = fp.section, BASIN_HALF_WIDTH
    bm = basin_map(
        smap,
        fp,
        ranges=((z[0] - h, z[0] + h), (z[1] - h, z[1] + h)),
        n=BASIN_N,
        n_strides=BASIN_STRIDES,
        tol=BASIN_TOL,
        executor="serial",
        progress=False,
    )
    return {
        "basin_x": np.asarray(bm.x, dtype=np.float64),
        "basin_y": np.asarray(bm.y, dtype=np.float64),
        "basin_outcome": np.asarray(bm.outcome, dtype=np.int64),
        "basin_strides": np.asarray(bm.strides, dtype=np.int64),
    }


def _run_record(prefix: str, sol) -> dict[str, np.ndarray]:
    """A run's outcome, counts and events, by name ``<prefix>_<what>``."""
    ev = sol.events
    out = {
        "status": np.int64(int(sol.status)),
        "t": np.float64(sol.t),
        "x": np.asarray(sol.x, dtype=np.float64),
        "counts": np.array(
            [sol.n_strides, sol.n_events, sol.n_steps, sol.n_rejected, sol.n_rhs],
            dtype=np.int64,
        ),
        "event_t": np.asarray(ev.t, dtype=np.float64),
        "event_guard": np.asarray(ev.guard, dtype=np.int64),
        "event_phase_after": np.asarray(ev.phase_after, dtype=np.int64),
        "event_x_pre": np.asarray(ev.x_pre, dtype=np.float64),
        "event_x_post": np.asarray(ev.x_post, dtype=np.float64),
        "event_impulse": np.asarray(ev.impulse, dtype=np.float64),
    }
    return {f"{prefix}_{k}": v for k, v in out.items()}


def same_bits(a, b) -> bool:
    """``a`` and ``b`` have the same dtype, shape and values bit for bit, except that any NaN
    matches any NaN at the same position (a NaN's payload is not part of the record)."""
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype != b.dtype or a.shape != b.shape:
        return False
    if a.dtype.kind not in "fc":
        return bool(np.array_equal(a, b))
    ra = a.view(np.float64) if a.dtype.kind == "c" else a
    rb = b.view(np.float64) if b.dtype.kind == "c" else b
    nan_a, nan_b = np.isnan(ra), np.isnan(rb)
    bits = ra.view(np.uint64) == rb.view(np.uint64)
    return bool(((bits & ~nan_a & ~nan_b) | (nan_a & nan_b)).all())


def deviation(got, want) -> str:
    """A line saying where and how much ``got`` differs from the recorded ``want``."""
    got, want = np.asarray(got), np.asarray(want)
    if got.dtype != want.dtype or got.shape != want.shape:
        return f"dtype/shape {got.dtype}{got.shape} vs recorded {want.dtype}{want.shape}"
    if want.dtype.kind not in "fc":
        bad = np.argwhere(got != want)
        return f"{len(bad)} values differ, first at index {bad[0].tolist()}" if len(bad) else ""
    g = got.view(np.float64) if got.dtype.kind == "c" else got
    w = want.view(np.float64) if want.dtype.kind == "c" else want
    nan_mismatch = np.isnan(g) != np.isnan(w)
    with np.errstate(invalid="ignore", over="ignore"):
        diff = np.where(np.isnan(g) | np.isnan(w), 0.0, np.abs(g - w))
    differ = (diff > 0) | nan_mismatch
    first = np.argwhere(differ)[0].tolist() if differ.any() else []
    parts = " (complex as float64 pairs)" if want.dtype.kind == "c" else ""
    return (
        f"{int(differ.sum())} of {g.size} values{parts} differ (first at index {first}); max "
        f"absolute deviation {diff.max():.3g}, NaN positions differ at "
        f"{int(nan_mismatch.sum())} values"
    )
