"""A stride map's runs over per-step terrain (:mod:`walker.simulation.terrain`), in compiled code
(walker/_core/terrain.c): one call of :meth:`walker.simulation.stride.StrideMap.__call__` with
``terrain=`` and the Monte-Carlo batch :meth:`walker.simulation.stride.StrideMap.ensemble`.

The compiled terrain functions exist for the models listed by :func:`check_supported`'s
error; for any other model, passing terrain raises a ValueError that names it.
"""

from __future__ import annotations

import math
import numbers
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from walker._checks import as_vector
from walker.results import MapResult
from walker.simulation import _section
from walker.status import Status

__all__ = [
    "compiled_draws",
    "ensemble_drawn",
    "ensemble_method",
    "walk",
    "check_model",
    "check_supported",
    "ensemble",
    "rows_for",
    "terrain_call",
    "terrain_rows",
]

_KEY = "_terrain_args"


def _args(smap) -> tuple:
    """The compiled section settings of ``smap`` (``walker._hybrid.terrain_walk``'s head),
    checked once per prepared run: a ValueError naming the model when it has no terrain
    functions."""
    cached = smap.__dict__.get("_run")
    if cached is None:
        smap._prepared()
        cached = smap.__dict__["_run"]
    kept = smap.__dict__.get(_KEY)
    if kept is not None and kept[0] is cached:
        return kept[1]
    check_supported(smap)
    run, _, _ = smap._prepared(1)
    lift = _terrain_lift(cached[4]) if cached[6] is None else None
    args = _section.section_tuple(
        _section.section_args(smap.model, smap.t_max, cached, run, lift=lift)
    )
    smap.__dict__[_KEY] = (cached, args)
    return args


def _terrain_lift(system):
    """The addresses ``(lift, lift_jacobian)`` of the compiled section lift the terrain runs
    of ``system``'s model take when the model's registry entry has none (the five-link
    walker's, walker/_core/model_five_link.c), else None."""
    from walker import _hybrid
    from walker.simulation.hybrid_system import _compiled

    guards = _compiled(system)[1]
    return _hybrid.terrain_lift(guards) if guards else None


def check_model(model, params, system) -> None:
    """Raise a ValueError naming the model when it cannot walk on terrain: no compiled
    terrain functions for its system (walker/_core/terrain.c), or a three-link walker whose
    steps end on its controller's surface."""
    from walker import _hybrid
    from walker.simulation.hybrid_system import _compiled

    name = model.name
    guards = _compiled(system)[1]
    if not guards or _hybrid.terrain_model(guards) is None:
        raise ValueError(f"terrain is not supported for `{name}` yet")
    if getattr(params, "step_event", 0.0) == 1.0:
        raise ValueError(
            f"terrain is not supported for `{name}` with `step_event` = 1 (its steps end on "
            "the controller's impact surface, not on touching the ground)"
        )


def check_supported(smap, what: str = "terrain") -> None:
    """Raise a ValueError naming the model when ``smap`` cannot walk on terrain (``what``:
    the feature asked for, in the message) in one compiled call."""
    cached = smap.__dict__.get("_run")
    if cached is None:
        smap._prepared()
        cached = smap.__dict__["_run"]
    check_model(smap.model, smap.params, cached[4])
    # no compiled call (walker.simulation._section.compiled_call_fits) and no compiled terrain lift
    if cached[6] is None and _terrain_lift(cached[4]) is None:
        raise ValueError(f"{what} is not supported for `{smap.model.name}` yet")


def _python_call(smap, z, n_strides, rows) -> MapResult:
    """A terrain call of a map without a compiled call (its lift is neither affine nor
    compiled) and without a compiled terrain lift (:func:`_terrain_lift`): the model's
    lift, then one run of the map's system (as :func:`walker.simulation.stride.simulate` runs it),
    projected; no Jacobians."""
    from walker.simulation.integrate import _solve
    from walker.simulation.region import stride_max_steps

    cached = smap.__dict__["_run"]
    p, system, model = cached[1], cached[4], smap.model
    x0 = np.ascontiguousarray(model.lift(z, p), dtype=np.float64)
    start_phase = model.start_phase_fn()
    phase0 = 0
    if start_phase is not None and all(map(math.isfinite, x0.tolist())):
        phase0 = start_phase(x0, p)
    per_stride = stride_max_steps(smap.params, smap.t_max, smap.method, smap.first_step)
    sol = _solve(
        system,
        x0,
        p,
        phase0=phase0,
        t0=0.0,
        t_max=smap.t_max * n_strides,
        n_strides=n_strides,
        method=smap.method,
        rtol=smap.rtol,
        atol=smap.atol,
        first_step=smap.first_step,
        max_step=np.inf,
        max_steps=per_stride * n_strides,
        output="map",
        sample_times=None,
        jacobian=False,
        n_interior=4,
        fixed_step=False,
        p_checked=True,
        terrain=rows,
    )
    x = np.asarray(sol.x, dtype=np.float64)
    z_new = model.project(x, p) if sol.success else np.full(model.n_z, np.nan)
    return MapResult(sol.status, np.asarray(z_new, dtype=np.float64), None, float(sol.t), x)


def rows_for(model, params, system, terrain) -> np.ndarray:
    """:func:`walker.simulation.stride.simulate`'s ``terrain``: the model checked, the rows as an
    ``(n, 2)`` float64 array (n >= 1)."""
    check_model(model, params, system)
    return terrain_rows(terrain, None)


def terrain_rows(terrain, n_strides: int | None, name: str = "terrain") -> np.ndarray:
    """``terrain`` as a C-contiguous float64 array of shape ``(n_strides, 2)`` (any number
    of rows >= 1 for None), finite."""
    rows = np.array(terrain, dtype=np.float64, order="C")
    if rows.ndim != 2 or rows.shape[1] != 2 or rows.shape[0] < 1:
        raise ValueError(f"`{name}` must have shape (n, 2) of (slope, drop) rows, got {rows.shape}")
    if n_strides is not None and rows.shape[0] != n_strides:
        raise ValueError(
            f"`{name}` must have shape (n_strides, 2) = ({n_strides}, 2) of (slope, drop) "
            f"per step, got {rows.shape}"
        )
    if not np.isfinite(rows).all():
        raise ValueError(f"All values of `{name}` must be finite.")
    return rows


def _check_walk_args(jacobian, previous):
    if not isinstance(jacobian, bool | np.bool_ | numbers.Integral):
        raise TypeError(f"`jacobian` must be a bool, got {type(jacobian).__name__}")
    if previous is not None:
        previous = np.array(previous, dtype=np.float64)
        if previous.shape != (2,) or not np.isfinite(previous).all():
            raise ValueError(
                f"`previous` must be 2 finite values (slope, drop), got {previous.tolist()}"
            )
    return bool(jacobian), previous


def terrain_call(smap, z, jacobian, n_strides, terrain, previous=None) -> MapResult:
    """:meth:`walker.simulation.stride.StrideMap.__call__` with ``terrain``: the checks, then one
    compiled walk (``walker._hybrid.terrain_walk``)."""
    z = as_vector(z, "z", smap.model.n_z)
    if not all(map(math.isfinite, z.tolist())):
        raise ValueError("All components of the section point `z` must be finite.")
    if isinstance(n_strides, bool) or not isinstance(n_strides, numbers.Integral):
        raise TypeError(f"`n_strides` must be an int, got {type(n_strides).__name__}")
    if n_strides < 1:
        raise ValueError(f"`n_strides` must be >= 1, got {n_strides}")
    jacobian, previous = _check_walk_args(jacobian, previous)
    rows = terrain_rows(terrain, int(n_strides))
    cached = smap.__dict__.get("_run")
    if cached is None:
        smap._prepared()
        cached = smap.__dict__["_run"]
    if cached[6] is None:
        check_model(smap.model, smap.params, cached[4])
        if _terrain_lift(cached[4]) is None:
            if jacobian or previous is not None:
                check_supported(smap, "the terrain Jacobian (and `previous`)")
            return _python_call(smap, z, int(n_strides), rows)
        smap.model.lift(z, cached[1])  # the model's checks of z (a ValueError naming it)
    return _walk(smap, z, False, rows, jacobian, previous)


def _walk(smap, start, from_state, rows, jacobian, previous) -> MapResult:
    from walker import _hybrid

    args = _args(smap)
    start = np.ascontiguousarray(start, dtype=np.float64)
    status, _, t, x, z_new, jz, tj = _hybrid.terrain_walk(
        *args, start, rows, jacobian, from_state, previous
    )
    n_z = smap.model.n_z
    z_new = np.frombuffer(z_new, dtype=np.float64).copy()
    x = np.frombuffer(x, dtype=np.float64).copy()
    jac = terrain_jac = None
    if jz is not None and status == 0:
        jac = np.frombuffer(jz, dtype=np.float64).reshape(n_z, start.shape[0]).copy()
        terrain_jac = np.frombuffer(tj, dtype=np.float64).reshape(n_z, -1).copy()
    return MapResult(Status(status), z_new, jac, float(t), x, terrain_jac)


def walk(self, x0, terrain, *, jacobian: bool = False, previous=None) -> MapResult:
    """Walk over ``terrain`` (shape ``(n, 2)``, per step ``(slope [rad], drop [m])``) from
    the full state ``x0`` (shape ``(n_x,)``, in the model's state order, just after a
    touchdown: e.g. a previous result's ``state``), in one compiled call.

    As :meth:`__call__` with ``terrain`` but for the start: the map's start checks apply to
    ``x0``; ``previous`` is the ``(slope, drop)`` of the step ``x0`` landed on (None: the
    scene's plane), the ground the trailing foot stands on in the first step.  With
    ``jacobian=True`` the result's ``jac`` is ``dz / dx0``, shape ``(n_z, n_x)``, and
    ``terrain_jac`` as for :meth:`__call__`.  A Markov chain over post-touchdown states
    (the rimless wheel's ``(theta, theta_dot)`` carries the plane it landed on) steps with
    ``n = 1``."""
    x0 = as_vector(x0, "x0", self.model.n_x)
    if not all(map(math.isfinite, x0.tolist())):
        raise ValueError("All components of the state `x0` must be finite.")
    jacobian, previous = _check_walk_args(jacobian, previous)
    rows = terrain_rows(terrain, None)
    check_supported(self, "`walk`")
    return _walk(self, x0, True, rows, jacobian, previous)


def ensemble_method(self, z0, terrains, *, threads: int = 1):
    """Walk from ``z0`` (shape ``(n_z,)`` or ``(n_runs, n_z)``) over each run's terrain
    ``terrains`` (shape ``(n_runs, n_steps, 2)``, per step ``(slope, drop)``), in compiled
    code without the GIL, ``threads`` threads over contiguous blocks of runs (the same
    result for any number).  Returns ``(steps_completed, status)``, int64 arrays
    ``(n_runs,)``: the strides completed before the first failure (``n_steps`` and status 0
    when none failed) and the failure's :class:`walker.status.Status` value."""
    return ensemble(self, z0, terrains, threads)


def ensemble(smap, z0, terrains, threads: int = 1):
    """Many walks of ``smap`` over terrain in compiled code: the Monte-Carlo batch of
    :meth:`walker.simulation.stride.StrideMap.ensemble` (its documentation)."""
    from walker import _hybrid

    n_z = smap.model.n_z
    terrains = np.asarray(terrains, dtype=np.float64)
    if terrains.ndim != 3 or terrains.shape[2] != 2 or terrains.shape[1] < 1:
        raise ValueError(
            f"`terrains` must have shape (n_runs, n_steps, 2) with n_steps >= 1, got "
            f"{terrains.shape}"
        )
    if not np.isfinite(terrains).all():
        raise ValueError("All values of `terrains` must be finite.")
    terrains = np.ascontiguousarray(terrains)
    m = terrains.shape[0]
    z0 = np.asarray(z0, dtype=np.float64)
    if z0.shape == (n_z,):
        z0 = np.broadcast_to(z0, (m, n_z))
    if z0.shape != (m, n_z):
        raise ValueError(f"`z0` must have shape ({n_z},) or ({m}, {n_z}), got {z0.shape}")
    if not np.isfinite(z0).all():
        raise ValueError("All section points `z0` must be finite.")
    z0 = np.ascontiguousarray(z0)
    if isinstance(threads, bool) or not isinstance(threads, numbers.Integral):
        raise TypeError(f"`threads` must be an int, got {type(threads).__name__}")
    if threads < 1:
        raise ValueError(f"`threads` must be >= 1, got {threads}")
    args = _args(smap)
    bounds = np.linspace(0, m, min(int(threads), max(m, 1)) + 1).astype(int)
    chunks = [(a, b) for a, b in zip(bounds[:-1], bounds[1:], strict=True) if b > a]

    def run(chunk):
        a, b = chunk
        status, strides = _hybrid.terrain_ensemble(*args, z0[a:b], terrains[a:b])
        return np.frombuffer(status, dtype=np.int64), np.frombuffer(strides, dtype=np.int64)

    if len(chunks) <= 1:
        parts = [run(c) for c in chunks]
    else:
        with ThreadPoolExecutor(max_workers=len(chunks)) as pool:
            parts = list(pool.map(run, chunks))
    if not parts:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    status = np.concatenate([p[0] for p in parts])
    strides = np.concatenate([p[1] for p in parts])
    return strides, status


# --- terrain drawn in compiled code (walker/_core/terrain_draw.c) -------------------------

_NORMAL: list = []  # [address or None]: numpy's random_standard_normal, looked up once


def _normal_address():
    """The address of numpy's ``random_standard_normal(bitgen_t *)`` (exported by
    ``numpy.random._generator``), checked once against numpy's own draws; None when it
    cannot be found or does not give numpy's numbers (walker then draws in Python)."""
    if _NORMAL:
        return _NORMAL[0]
    import ctypes

    from walker import _hybrid

    address = None
    try:
        import numpy.random._generator as generator

        symbol = ctypes.CDLL(generator.__file__).random_standard_normal
        address = ctypes.cast(symbol, ctypes.c_void_p).value
        runs = np.arange(3, dtype=np.int64)
        got = _hybrid.terrain_draws(np.array([7], np.int64), address, 0.0, 1.0, 1.0, runs, 5)
        children = np.random.SeedSequence(7).spawn(3)
        want = np.stack([np.random.default_rng(c).standard_normal((5, 2)) for c in children])
        if not np.array_equal(np.frombuffer(got, dtype=np.float64).reshape(3, 5, 2), want):
            address = None
    except (OSError, AttributeError, ImportError, ValueError):
        address = None
    _NORMAL.append(address)
    return address


def compiled_draws(seed: int, terrain) -> tuple | None:
    """The draw settings of ``walker._hybrid.terrain_ensemble_drawn`` for runs seeded by the
    children of ``numpy.random.SeedSequence(seed)`` over ``terrain`` (kind ``random``, its
    ``slope_mean`` set): ``(entropy, normal, slope_mean, slope_std, height_std)``; None when
    this build or this numpy cannot draw them in C, or the seed has more than 128 bits."""
    seed = int(seed)
    if seed < 0 or seed >= 1 << 128 or terrain.slope_mean is None:
        return None
    normal = _normal_address()
    if normal is None:
        return None
    words = []
    while True:
        words.append(seed & 0xFFFFFFFF)
        seed >>= 32
        if not seed:
            break
    entropy = np.array(words, dtype=np.int64)
    return (
        entropy,
        normal,
        float(terrain.slope_mean),
        float(terrain.slope_std),
        float(terrain.height_std),
    )


def ensemble_drawn(smap, z0, draws, runs, n_steps: int, threads: int = 1):
    """Walks of ``smap`` from ``z0`` (shape ``(n_z,)``) over the first ``n_steps`` rows of
    each run in ``runs`` (int64 indices of the seed's children), the rows drawn in compiled
    code as :func:`walker.analysis.mfpt.draw_terrains` draws them (``draws`` from
    :func:`compiled_draws`), ``threads`` threads over contiguous blocks of runs.  Returns
    ``(steps_completed, status)`` as :meth:`walker.simulation.stride.StrideMap.ensemble` does."""
    from walker import _hybrid

    z0 = np.ascontiguousarray(z0, dtype=np.float64)
    runs = np.ascontiguousarray(runs, dtype=np.int64)
    args = _args(smap)
    m = runs.shape[0]
    bounds = np.linspace(0, m, min(int(threads), max(m, 1)) + 1).astype(int)
    chunks = [(a, b) for a, b in zip(bounds[:-1], bounds[1:], strict=True) if b > a]

    def run(chunk):
        a, b = chunk
        status, strides = _hybrid.terrain_ensemble_drawn(*args, z0, *draws, runs[a:b], int(n_steps))
        return np.frombuffer(status, dtype=np.int64), np.frombuffer(strides, dtype=np.int64)

    if len(chunks) <= 1:
        parts = [run(c) for c in chunks]
    else:
        with ThreadPoolExecutor(max_workers=len(chunks)) as pool:
            parts = list(pool.map(run, chunks))
    if not parts:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    status = np.concatenate([p[0] for p in parts])
    strides = np.concatenate([p[1] for p in parts])
    return strides, status
