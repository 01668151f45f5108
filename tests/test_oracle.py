"""walker's compiled C models against the independent numpy oracle of ``tests/oracle.py``
(lambdified symbolic models, ``numpy.linalg.solve`` impacts, guards and resets written from
the documented conventions, ``solve_ivp`` strides).

The C functions are called through ctypes at the addresses of the extension's registry
``walker._hybrid.models()`` (every registry entry of the passive walkers: general, "/plain"
and "/ignore_scuff"); strides, their Jacobians and fixed points through the public
:class:`walker.StrideMap` and :func:`walker.simulation.stride.simulate`.

Tolerances (each the bound on the largest difference over the samples, relative to the
largest magnitude of the quantity compared, or 1 if that is smaller):

- ``KERNEL_RTOL`` = 1e-12: vector field, its Jacobian, guards, energy, points, and the
  post-impact states and impulses of every reset branch.  The C solves with Cholesky or the
  adjugate, the oracle with LU, so they differ by round-off times the condition number of
  the mass matrix (largest seen over these samples: in the test output, ``-s``).
- reset outcomes ``(action, next phase, status)`` must be equal.
- ``STRIDE_RTOL`` = 1e-9: a stride's section point, step time, event times and post-event
  states (both integrators at rtol = atol = 1e-12; their different step sequences differ
  by about 1e-12 per step).
- ``JACOBIAN_RTOL`` = 1e-7: the C's exact stride-map Jacobian (variational equations with
  saltation) against fourth-order central differences of oracle strides (relative step
  3e-5: truncation about 1e-9 for the simplest walker's strongly curved map, integration
  error over the step about 3e-8), relative to its largest entry.
- ``FIXED_POINT_TOL`` = 1e-9: a shipped scene's reference gait against the oracle's own
  fixed point, one Newton step from it with the finite-difference Jacobian (quadratic
  convergence makes the step's result the oracle's fixed point to O(residual^2)).
"""

from __future__ import annotations

import ctypes
import functools

import numpy as np
import oracle as O
import pytest

from walker import StrideMap, _hybrid, load_scene
from walker.models import get_model
from walker.simulation.stride import simulate
from walker.status import EVENT_CONTINUE, EVENT_IGNORE, EVENT_STRIDE, EVENT_TERMINAL, Status

KERNEL_RTOL = 1e-12
STRIDE_RTOL = 1e-9
JACOBIAN_RTOL = 1e-7
FIXED_POINT_TOL = 1e-9

_vp, _i64, _f64 = ctypes.c_void_p, ctypes.c_int64, ctypes.c_double
_RHS = ctypes.CFUNCTYPE(None, _i64, _f64, _vp, _vp, _vp, _vp)
_RESET = ctypes.CFUNCTYPE(None, _i64, _i64, _f64, _vp, _vp, _vp, _vp, _vp, _vp)
_RHS_JAC = ctypes.CFUNCTYPE(None, _i64, _f64, _vp, _vp, _vp, _vp, _vp)


class Compiled:
    """The C functions of registry entry ``entry`` (sizes from the model's HybridSystem)."""

    def __init__(self, entry):
        name = entry.split("/")[0]
        self.model = get_model(name)
        system = self.model.system
        self.n_x, self.n_guards, self.n_impulse = system.n_x, system.n_guards, system.n_impulse
        fns = _hybrid.models()[entry]
        self._rhs, self._jac, self._guards = (_RHS(fns[k]) for k in ("rhs", "jac", "guards"))
        self._reset = _RESET(fns["reset"])
        self._rhs_jac = _RHS_JAC(fns["rhs_jac"]) if fns["rhs_jac"] else None
        self.rhs_jac = self._fused if fns["rhs_jac"] else None

    def _fused(self, phase, x, p):
        dx = np.full(self.n_x, np.nan)
        J = np.full((self.n_x, self.n_x), np.nan)
        args = (x, p, dx, J)
        self._rhs_jac(phase, 0.3, *(a.ctypes.data for a in args), None)
        return dx, J

    def _call(self, fn, shape, phase, x, p):
        out = np.full(shape, np.nan)
        fn(phase, 0.3, x.ctypes.data, p.ctypes.data, out.ctypes.data, None)
        return out

    def rhs(self, phase, x, p):
        return self._call(self._rhs, self.n_x, phase, x, p)

    def jac(self, phase, x, p):
        return self._call(self._jac, (self.n_x, self.n_x), phase, x, p)

    def guards(self, phase, x, p):
        return self._call(self._guards, self.n_guards, phase, x, p)

    def reset(self, phase, k, x, p):
        x_new = x.copy()
        impulse = np.zeros(self.n_impulse)
        out = np.full(3, -1, dtype=np.int64)
        args = (x, p, x_new, impulse, out)
        self._reset(phase, k, 0.3, *(a.ctypes.data for a in args), None)
        return tuple(int(v) for v in out), x_new, impulse


def deviation(c, o):
    """Largest ``|c - o|`` relative to ``max(1, max |o|)``."""
    c, o = np.asarray(c, dtype=float), np.asarray(o, dtype=float)
    assert c.shape == o.shape
    return float(np.abs(c - o).max() / max(1.0, float(np.abs(o).max())))


class Worst:
    """The largest deviation seen per quantity, asserted below ``rtol`` at each sample."""

    def __init__(self, what):
        self.what, self.seen = what, {}

    def check(self, name, c, o, rtol, where=""):
        err = deviation(c, o)
        assert err <= rtol, f"{self.what} {name} {where}: deviation {err:.3g} > {rtol:g}"
        self.seen[name] = max(err, self.seen.get(name, 0.0))

    def report(self):
        print(f"\n{self.what}: " + ", ".join(f"{k} {v:.1e}" for k, v in self.seen.items()))


# --------------------------------------------------------------------------------------
# Samples near the shipped scenes
# --------------------------------------------------------------------------------------

SCENE_OF = {
    "simplest": "gaits/simplest_garcia.toml",
    "compass": "gaits/compass_goswami.toml",
    "kneed": "gaits/kneed_hsu.toml",
}
# Parameters that are zero in a "/plain" entry; drawn at random (or zero) elsewhere, with
# the range each is drawn from (foot_radius as a fraction of the leg length).
OPTIONAL = {
    "simplest": {"damping_ankle": (0.0, 0.5)},
    "compass": {
        "inertia_leg": (0.0, 0.3),
        "foot_radius": (0.0, 0.6),
        "damping_hip": (0.0, 2.0),
        "damping_ankle": (0.0, 2.0),
    },
    "kneed": {
        "inertia_thigh": (0.0, 0.05),
        "inertia_shank": (0.0, 0.05),
        "offset_thigh": (-0.05, 0.05),
        "offset_shank": (-0.05, 0.05),
        "foot_radius": (0.0, 0.6),
        "damping_hip": (0.0, 1.0),
        "damping_knee": (0.0, 1.0),
        "damping_ankle": (0.0, 1.0),
    },
}


@functools.cache
def _scene_vectors(name):
    """The scene's parameter vector and start state."""
    scene = load_scene(SCENE_OF[name])
    return scene.params.as_array(), np.array(scene.state, dtype=float)


def sample_params(name, rng, plain):
    """The scene's parameters, each positive one scaled by U(0.8, 1.2), the slope drawn in
    (-0.1, 0.1), the optional ones zero (``plain``, or at random) or drawn."""
    names = get_model(name).params_class.names()
    p = _scene_vectors(name)[0].copy()
    p[p > 0] *= rng.uniform(0.8, 1.2, int((p > 0).sum()))
    p[names.index("slope")] = rng.uniform(-0.1, 0.1)
    leg = O.oracle(name).leg_length(p) if name != "simplest" else 1.0
    for k, (lo, hi) in OPTIONAL[name].items():
        p[names.index(k)] = 0.0 if plain or rng.random() < 0.3 else rng.uniform(lo, hi)
        if k == "foot_radius":
            p[names.index(k)] *= leg
    return p


def sample_state(name, rng):
    x = _scene_vectors(name)[1].copy()
    n = len(x) // 2
    x[:n] += rng.normal(0.0, 0.3, n)
    x[n:] += rng.normal(0.0, 1.0, n)
    return x


ENTRIES = sorted(k for k in _hybrid.models() if k.split("/")[0] in SCENE_OF)
"""Every registry entry of the passive walkers with a pinned stance (general, "/plain",
"/ignore_scuff")."""


def _oracle_of(entry):
    return O.oracle("kneed/ignore_scuff" if entry.endswith("ignore_scuff") else entry.split("/")[0])


# --------------------------------------------------------------------------------------
# Phase functions
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("entry", ENTRIES)
def test_phase_functions_agree_with_oracle(entry):
    """rhs, Jacobian, the guards active in each phase (nonzero direction), energy and points
    at 100 states near the scene's, to ``KERNEL_RTOL``; a "/plain" entry's fused rhs and
    Jacobian (``rhs_jac``) too, and a compiled section lift (the simplest walker's) with its
    Jacobian (against central differences of the oracle's lift, to 1e-8)."""
    name = entry.split("/")[0]
    c, o = Compiled(entry), _oracle_of(entry)
    rng = np.random.default_rng(20261128)
    worst = Worst(entry)
    for trial in range(100):
        p = sample_params(name, rng, "/plain" in entry)
        x = sample_state(name, rng)
        if name == "kneed" and trial % 4 == 0:
            x[2], x[5] = x[1], x[4]  # a locked-knee state
        for phase, directions in enumerate(o.directions):
            active = directions != 0
            where = f"phase {phase} x {x.tolist()} p {p.tolist()}"
            worst.check("rhs", c.rhs(phase, x, p), o.rhs(phase, x, p), KERNEL_RTOL, where)
            worst.check("jac", c.jac(phase, x, p), o.jac(phase, x, p), KERNEL_RTOL, where)
            g_c, g_o = c.guards(phase, x, p)[active], o.guards(phase, x, p)[active]
            worst.check("guards", g_c, g_o, KERNEL_RTOL, where)
        if c.rhs_jac is not None:  # a "/plain" entry's fused rhs and Jacobian
            for phase in range(len(o.directions)):
                dx, J = c.rhs_jac(phase, x, p)
                worst.check("fused rhs", dx, o.rhs(phase, x, p), KERNEL_RTOL)
                worst.check("fused jac", J, o.jac(phase, x, p), KERNEL_RTOL)
        if "/" not in entry:  # energy and points: the general entry's helpers
            worst.check("energy", c.model.energy(x, p), o.energy(x, p), KERNEL_RTOL)
            worst.check("points", c.model.points(x, p), o.points(x, p), KERNEL_RTOL)
        lift = _hybrid.models()[entry]["lift"]
        if lift:  # a compiled section lift and its Jacobian (the simplest walker's)
            z = o.project(x)
            got = _hybrid.call_state_fn(lift, z, p, o.n_x)
            worst.check("lift", got, o.lift(z, p), KERNEL_RTOL)
            jac_address = _hybrid.models()[entry]["lift_jacobian"]
            got = np.reshape(_hybrid.call_state_fn(jac_address, z, p, o.n_x * len(z)), (o.n_x, -1))
            worst.check("lift Jacobian", got, _central_differences(o.lift, z, p), 1e-8)
    worst.report()


def _central_differences(f, z, p, step=1e-6):
    """``df/dz`` by central differences (truncation about ``step^2``)."""
    cols = []
    for j in range(len(z)):
        e = np.zeros(len(z))
        e[j] = step
        cols.append((f(z + e, p) - f(z - e, p)) / (2 * step))
    return np.column_stack(cols)


# --------------------------------------------------------------------------------------
# Reset maps: every branch
# --------------------------------------------------------------------------------------

_FF, _FB = int(Status.FELL_FORWARD), int(Status.FELL_BACKWARD)
_NONPHYS, _SINGULAR = int(Status.NONPHYSICAL_IMPACT), int(Status.LINEAR_SOLVE_FAILED)
_TRIP = (1, 0, EVENT_TERMINAL, 0, int(Status.TRIPPED))
# (guard, phase, action, next phase, status) each reset must reach at least once.
REQUIRED = {
    "simplest": {
        (0, 0, EVENT_IGNORE, 0, 0),  # theta >= 0: the mid-stance scuff
        (0, 0, EVENT_STRIDE, 0, 0),
        (1, 0, EVENT_TERMINAL, 0, _FF),
        (2, 0, EVENT_TERMINAL, 0, _FB),
    },
    "compass": {
        (0, 0, EVENT_IGNORE, 0, 0),  # a scuff: the swing foot behind
        (0, 0, EVENT_STRIDE, 0, 0),
        (0, 0, EVENT_TERMINAL, 0, _NONPHYS),
        (0, 0, EVENT_TERMINAL, 0, _SINGULAR),
        (1, 0, EVENT_TERMINAL, 0, _FF),
        (2, 0, EVENT_TERMINAL, 0, _FB),
    },
    "kneed": {
        (0, 0, EVENT_CONTINUE, 1, 0),  # knee lock
        (0, 0, EVENT_STRIDE, 0, 0),  # knee lock and heel strike in one reset
        (0, 0, EVENT_TERMINAL, 1, _NONPHYS),  # knee lock, then a nonphysical heel strike
        (0, 0, EVENT_TERMINAL, 0, _SINGULAR),  # singular knee lock
        _TRIP,
        (1, 0, EVENT_STRIDE, 0, 0),  # contact a hair before knee lock: lock and strike
        (1, 0, EVENT_CONTINUE, 1, 0),  # the same, the foot moving up: lock only
        (1, 1, EVENT_IGNORE, 1, 0),  # a scuff
        (1, 1, EVENT_STRIDE, 0, 0),  # heel strike
        (1, 1, EVENT_TERMINAL, 1, _NONPHYS),
        (1, 1, EVENT_TERMINAL, 1, _SINGULAR),
        (2, 0, EVENT_TERMINAL, 0, _FF),
        (3, 1, EVENT_TERMINAL, 1, _FB),
    },
}
REQUIRED["kneed/ignore_scuff"] = (REQUIRED["kneed"] - {_TRIP}) | {(1, 0, EVENT_IGNORE, 0, 0)}
MASSES = {
    "compass": ("mass_hip", "mass_leg", "inertia_leg"),
    "kneed": ("mass_hip", "mass_thigh", "mass_shank", "inertia_thigh", "inertia_shank"),
}


def reset_cases(name, rng, n):
    """(phase, guard, x, p) built to reach every branch: the swing foot on the slope (ahead:
    heel strike, behind: scuff), legs together, knee straight, about to lock or bent,
    non-finite rates and massless walkers (singular impacts)."""
    o = O.oracle(name)
    names = get_model(name).params_class.names()
    for i in range(n):
        p = sample_params(name, rng, False)
        x = sample_state(name, rng)
        x[: o.n_x // 2] = rng.uniform(-1.2, 1.2, o.n_x // 2)
        if name == "simplest":
            x[1] = 2.0 * x[0] + rng.choice([0.0, rng.normal(0.0, 1e-3)])
            yield from ((0, k, x, p) for k in range(3))
            continue
        slope = p[names.index("slope")]
        x[0] = rng.uniform(-0.6, 0.6)
        x[1] = -2.0 * slope - x[0]  # swing foot on the slope (point feet; near it otherwise)
        if name == "kneed":
            kind = i % 4
            if kind == 0:
                x[2], x[5] = x[1], x[4]
            elif kind == 1:
                x[2] = x[1] + rng.uniform(-1e-6, 1e-6)
            elif kind == 2:
                x[2] = x[1] + rng.uniform(-0.5, 0.5)
        elif i % 7 == 0:
            x[1] = x[0]  # legs together: a step of length zero, a scuff
        if i % 11 == 0:
            x[o.n_x // 2 + rng.integers(o.n_x // 2)] = np.nan  # a non-finite impact system
        if i % 13 == 0:
            p = p.copy()
            p[[names.index(k) for k in MASSES[name]]] = 0.0  # massless: singular
        for phase, directions in enumerate(o.directions):
            yield from ((phase, k, x, p) for k in range(len(directions)) if directions[k])


@pytest.mark.parametrize("entry", ENTRIES)
def test_reset_agrees_with_oracle_on_every_branch(entry):
    """The C reset and the oracle's give the same outcome ``(action, next phase, status)``
    at 600 states reaching every branch; after a stride or a knee lock the same state and
    impulse to ``KERNEL_RTOL``."""
    name = entry.split("/")[0]
    c, o = Compiled(entry), _oracle_of(entry)
    rng = np.random.default_rng(7)
    seen = set()
    worst = Worst(f"{entry} reset")
    for phase, k, x, p in reset_cases(name, rng, 600):
        if "/plain" in entry:
            p = p.copy()
            p[[get_model(name).params_class.names().index(n) for n in OPTIONAL[name]]] = 0.0
        out_o, x_o, imp_o = o.reset(phase, k, x, p)
        out_c, x_c, imp_c = c.reset(phase, k, x, p)
        where = f"phase {phase} guard {k} x {x.tolist()} p {p.tolist()}"
        assert out_c == out_o, where
        if out_o[0] in (EVENT_STRIDE, EVENT_CONTINUE):
            worst.check("state", x_c, x_o, KERNEL_RTOL, where)
            worst.check("impulse", imp_c, imp_o, KERNEL_RTOL, where)
        seen.add((k, phase, *out_o))
    key = "kneed/ignore_scuff" if entry.endswith("ignore_scuff") else name
    missing = REQUIRED[key] - seen
    assert not missing, f"{entry}: branches not reached {sorted(missing)}"
    worst.report()


# --------------------------------------------------------------------------------------
# Strides, their Jacobians and fixed points
# --------------------------------------------------------------------------------------

STRIDE_SCENES = {
    "simplest_garcia": {},
    "compass_goswami": {},
    "kneed_hsu": {},
    "kneed_mcgeer_pointmass": {},  # swing_scuff = "ignore"
    "rimless_wheel": {},
    # round feet, inertias, offsets and dampers from the scenes' gaits (one stride each)
    "compass_goswami round": {
        "foot_radius": 0.15,
        "inertia_leg": 0.1,
        "damping_hip": 0.05,
        "damping_ankle": 0.05,
    },
    "kneed_hsu round": {
        "foot_radius": 0.1,
        "inertia_thigh": 0.002,
        "inertia_shank": 0.0005,
        "offset_thigh": 0.01,
        "offset_shank": -0.01,
        "damping_hip": 0.01,
        "damping_knee": 0.01,
        "damping_ankle": 0.01,
    },
}


def _scene_setup(key):
    """The scene's walker model, oracle, parameters and start state (``key``: a scene name
    and optionally " round", its parameters then changed as :data:`STRIDE_SCENES` says)."""
    scene = load_scene(f"gaits/{key.split()[0]}.toml")
    model = scene.walker_model
    params = scene.params
    if STRIDE_SCENES[key]:
        params = scene.params.replace(**STRIDE_SCENES[key])
    x0 = np.array(scene.reference["state"] if scene.reference else scene.state, dtype=float)
    ignore = model.swing_scuff == "ignore"
    o = O.oracle(f"{model.name}/ignore_scuff" if ignore else model.name)
    return scene, model, o, params, x0


def compare_runs(sol, r, worst, what):
    """A C run (walker Solution with events) against an oracle run: status, the events
    (guard, phase after, time, post-event state, impulse), final time and state."""
    assert int(sol.status) == r.status, what
    assert len(sol.events) == len(r.events), what
    for i, (t, k, phase, x_post, impulse) in enumerate(r.events):
        assert int(sol.events.guard[i]) == k and int(sol.events.phase_after[i]) == phase, what
        worst.check("event times", sol.events.t[i], t, STRIDE_RTOL, what)
        if x_post is None:  # the terminal event
            continue
        worst.check("event states", sol.events.x_post[i], x_post, STRIDE_RTOL, what)
        worst.check("impulses", sol.events.impulse[i], impulse, STRIDE_RTOL, what)
    worst.check("final time", sol.t, r.t, STRIDE_RTOL, what)
    worst.check("final state", sol.x, r.x, STRIDE_RTOL, what)


@pytest.mark.parametrize("key", list(STRIDE_SCENES))
def test_stride_and_jacobian_agree_with_oracle(key):
    """One stride from the scene's gait: every event, the final state and time (C
    ``simulate`` with events) and the section point and step time (``StrideMap``) to
    ``STRIDE_RTOL``; the C's exact stride-map Jacobian against central differences of
    oracle strides to ``JACOBIAN_RTOL``."""
    scene, model, o, params, x0 = _scene_setup(key)
    p = params.as_array()
    worst = Worst(key)
    sol = simulate(model, params, x0, output="events", rtol=1e-12, atol=1e-12)
    r = O.run(o, x0, p)
    assert r.status == 0 and len(r.events) >= 1
    compare_runs(sol, r, worst, key)
    stride_map = StrideMap(model, params, rtol=1e-12, atol=1e-12)
    z = o.project(x0)
    res = stride_map(z, jacobian=True)
    z_o, t_o, _ = O.stride(o, z, p)
    worst.check("section point", res.z, z_o, STRIDE_RTOL)
    worst.check("step time", res.step_time, t_o, STRIDE_RTOL)
    worst.check(
        "Jacobian",
        res.jac / np.abs(res.jac).max(),
        O.stride_jacobian(o, z, p) / np.abs(res.jac).max(),
        JACOBIAN_RTOL,
    )
    worst.report()


@pytest.mark.parametrize(
    "name",
    ["simplest_garcia", "compass_goswami", "kneed_hsu", "kneed_mcgeer_pointmass", "rimless_wheel"],
)
def test_reference_gait_is_the_oracles_fixed_point(name):
    """The scene's ``[reference]`` gait against the oracle's fixed point (one Newton step
    from it with the oracle's finite-difference Jacobian) to ``FIXED_POINT_TOL``, and its
    step time against the oracle's stride."""
    scene, model, o, params, x0 = _scene_setup(name)
    p = params.as_array()
    z = o.project(x0)
    z_next, t, _ = O.stride(o, z, p)
    J = O.stride_jacobian(o, z, p)
    z_fixed = z - np.linalg.solve(J - np.eye(len(z)), z_next - z)
    worst = Worst(f"{name} fixed point")
    worst.check("fixed point", z, z_fixed, FIXED_POINT_TOL)
    worst.check("step time", scene.reference["step_time"], t, FIXED_POINT_TOL)
    worst.report()


@pytest.mark.parametrize("swing_scuff", ["trip", "ignore"])
def test_roundfoot_mcgeer_failure_agrees_with_oracle(swing_scuff):
    """McGeer's round-foot scene has no gait: from its guess the C run ends TRIPPED under
    "trip" and FELL_FORWARD under "ignore" (gaits/kneed_mcgeer_roundfoot.toml); the oracle
    ends the same way, at the same time and state, after the same events."""
    scene = load_scene("gaits/kneed_mcgeer_roundfoot.toml")
    model = get_model("kneed", swing_scuff=swing_scuff)
    o = O.oracle("kneed/ignore_scuff" if swing_scuff == "ignore" else "kneed")
    x0 = np.array(scene.state, dtype=float)
    sol = simulate(model, scene.params, x0, output="events", rtol=1e-12, atol=1e-12, n_strides=3)
    expected = Status.TRIPPED if swing_scuff == "trip" else Status.FELL_FORWARD
    assert sol.status == expected
    r = O.run(o, x0, scene.params.as_array(), n_strides=3, t_max=sol.t + 10.0)
    worst = Worst(f"kneed_mcgeer_roundfoot {swing_scuff}")
    compare_runs(sol, r, worst, swing_scuff)
    worst.report()


# --------------------------------------------------------------------------------------
# The rimless wheel
# --------------------------------------------------------------------------------------

# (guard, action, next phase, status) the rolling wheel's reset must reach.
REQUIRED_RIMLESS = (
    {
        (k, EVENT_STRIDE, phase, 0)
        for k in (0, 2)
        for phase in (0, 1)  # roll on, or stop
    }
    | {
        (k, EVENT_CONTINUE, phase, 0)
        for k in (1, 3)
        for phase in (0, 1)  # back step, or rest
    }
    | {(k, EVENT_TERMINAL, 0, _FB) for k in range(4)}
)


def _rimless_sample(rng):
    spokes = float(rng.choice([3, 4, 5, 6, 8, 10, 12]))
    alpha = np.pi / spokes
    p = np.array([spokes, rng.uniform(0.5, 2.0), rng.uniform(1.0, 12.0), 0.0])
    p[3] = rng.uniform(-0.08, 0.12) if rng.random() < 0.6 else rng.uniform(-1.5, 1.5) * alpha
    return p, alpha


def test_rimless_wheel_agrees_with_oracle():
    """Phase functions in both phases, energy, points and the start phase at 400 random
    wheels and states, to ``KERNEL_RTOL``; the rolling wheel's reset on every branch (rolling
    on, stopping on 3 or 4 spokes, tipping forward, stepping back, coming to rest, falling
    back), outcomes equal, states and impulses to ``KERNEL_RTOL``."""
    c, o = Compiled("rimless_wheel"), O.oracle("rimless_wheel")
    rng = np.random.default_rng(20261128)
    worst = Worst("rimless_wheel")
    seen = set()
    for _ in range(400):
        p, alpha = _rimless_sample(rng)
        x = np.array([rng.uniform(-alpha, alpha), rng.normal(0.0, 2.0)])
        for phase in range(2):
            worst.check("rhs", c.rhs(phase, x, p), o.rhs(phase, x, p), KERNEL_RTOL)
            worst.check("jac", c.jac(phase, x, p), o.jac(phase, x, p), KERNEL_RTOL)
            worst.check("guards", c.guards(phase, x, p), o.guards(phase, x, p), KERNEL_RTOL)
        worst.check("energy", c.model.energy(x, p), o.energy(x, p), KERNEL_RTOL)
        worst.check("points", c.model.points(x, p), o.points(x, p), KERNEL_RTOL)
        for state in ([alpha, 0.0], [-alpha, 0.0], [alpha, 1e-3], x):
            state = np.array(state)
            assert c.model.start_phase(state, p) == o.start_phase(state, p), (state, p)
        for k in range(4):
            forward = k in (0, 2)
            rate = abs(x[1]) * rng.choice([0.05, 0.3, 1.0])
            state = np.array([-alpha, -rate] if forward else [alpha, rate])
            out_o, x_o, imp_o = o.reset(0, k, state, p)
            out_c, x_c, imp_c = c.reset(0, k, state, p)
            assert out_c == out_o, (k, state, p)
            if x_o is not None:
                worst.check("reset state", x_c, x_o, KERNEL_RTOL)
                worst.check("impulse", imp_c, imp_o, KERNEL_RTOL)
            seen.add((k, *out_o))
    missing = REQUIRED_RIMLESS - seen
    assert not missing, f"rimless_wheel: branches not reached {sorted(missing)}"
    worst.report()


def test_rimless_wheel_below_the_critical_slope_comes_to_rest_like_the_oracle():
    """Below the critical slope the wheel rolls back and comes to rest standing: the C run
    and the oracle's take the same events and end ``NO_EVENT`` at ``t_max`` in phase 1."""
    scene = load_scene("gaits/rimless_wheel.toml")
    params = scene.params.replace(slope=0.03)
    x0 = np.array([np.pi / 8, -0.4])
    sol = simulate("rimless_wheel", params, x0, output="events", rtol=1e-12, atol=1e-12, t_max=6.0)
    r = O.run(O.oracle("rimless_wheel"), x0, params.as_array(), t_max=6.0)
    assert sol.status == Status.NO_EVENT and r.phase == 1
    worst = Worst("rimless_wheel at rest")
    compare_runs(sol, r, worst, "rimless_wheel at rest")
    worst.report()
