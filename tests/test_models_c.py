"""walker's hand-written C models (walker/_core/model_*.c, compiled into walker._hybrid)
against the numba model functions they port (walker/models/simplest.py, compass.py,
kneed.py).

Every C function is called through ctypes at the address ``walker._hybrid.models()``
reports, at many random states and parameter vectors, and at states built to reach every
branch of each reset map (the tests assert that each branch was reached).

Tolerance: the general entries ("simplest", "compass", "kneed") must agree with numba to the
bit (NaN where numba gives NaN): the C glue performs the numba functions' operations in the
same order, both call the same libm, and neither contracts multiply-adds (setup.py compiles
with ``-ffp-contract=off``; numba does not contract without fastmath).  The "/plain" entries
run kernels printed from expressions simplified with the zero parameters substituted, so
their arithmetic differs from the general kernels' by round-off only: they are compared to
the numba model at parameter vectors with those entries zero, to ``PLAIN_RTOL`` relative to
the size of the quantity (largest difference seen 7e-14, in the kneed rhs and Jacobian);
reset outcomes must agree exactly.

Whole strides of the shipped gaits through walker.integrate with the C functions given as
addresses agree with the numba model's stride bit for bit (general entries) or to
round-off (plain entries); see the last tests.
"""

import ctypes
import dataclasses

import numpy as np
import pytest
from _cmodel import (
    CModel,
    assert_bits,
    assert_phase_functions_agree,
    assert_reset_agrees,
    assert_same_run,
    assert_state_functions_agree,
    c_system,
    registry,
    solve_with_events,
)

from walker import load_scene
from walker.models import compass, get_model, kneed, simplest
from walker.status import EVENT_CONTINUE, EVENT_IGNORE, EVENT_STRIDE, EVENT_TERMINAL, Status

PLAIN_RTOL = 1e-12


def _assert_close(c, ref, what, rtol=PLAIN_RTOL):
    c = np.asarray(c, dtype=np.float64)
    ref = np.asarray(ref, dtype=np.float64)
    assert c.shape == ref.shape, what
    assert (np.isnan(c) == np.isnan(ref)).all(), what
    ok = ~np.isnan(ref)
    scale = max(1.0, float(np.abs(ref[ok]).max())) if ok.any() else 1.0
    err = float(np.abs(c[ok] - ref[ok]).max()) if ok.any() else 0.0
    assert err <= rtol * scale, f"{what}: max difference {err:.3g} at scale {scale:.3g}"


# --------------------------------------------------------------------------------------
# Random parameter vectors and states
# --------------------------------------------------------------------------------------


def _simplest_params(rng, plain):
    damping = 0.0 if rng.random() < 0.3 else rng.uniform(0.0, 0.5)
    return np.array(
        [rng.uniform(-0.2, 0.2), rng.uniform(0.5, 12.0), rng.uniform(0.5, 2.0), damping]
    )


def _plain_zero(name):
    """Indices in ``p`` of the parameters the "/plain" kernels fix at exactly zero."""
    model = get_model(name)
    names = model.params_class.names()
    return tuple(names.index(n) for n in model.module.VARIANTS["plain"])


_COMPASS_PLAIN_ZERO = _plain_zero("compass")  # inertia_leg, foot_radius, dampers
_KNEED_PLAIN_ZERO = _plain_zero("kneed")  # inertias, offsets, foot_radius, dampers


def _always():
    return True


def _foot_slope_g_dampers(rng, leg, damping_max, n_dampers, kept):
    """The tail of a passive walker's vector: foot radius (up to 0.9 ``leg``), slope, g and
    ``n_dampers`` dampers (up to ``damping_max``); each foot or damper entry is multiplied by
    ``kept()``, called right after it is drawn."""
    return [
        rng.uniform(0.0, 0.9) * leg * kept(),  # foot_radius
        rng.uniform(-0.2, 0.2),  # slope
        rng.uniform(1.0, 12.0),  # g
        *(rng.uniform(0.0, damping_max) * kept() for _ in range(n_dampers)),
    ]


def compass_vector(rng, kept=_always):
    """A random compass vector (also the first ten entries of compass_coulomb's): inertia,
    foot radius and dampers are each multiplied by ``kept()``, called right after it is
    drawn (``tests/test_friction_c.py`` zeroes them at random so)."""
    a, b = rng.uniform(0.1, 1.0, 2)
    return np.array(
        [
            rng.uniform(0.5, 20.0),  # mass_hip
            rng.uniform(0.5, 10.0),  # mass_leg
            a,
            b,
            rng.uniform(0.0, 1.0) * kept(),  # inertia_leg
            *_foot_slope_g_dampers(rng, a + b, 2.0, 2, kept),  # damping_hip, damping_ankle
        ]
    )


def kneed_vector(rng, kept=_always):
    """A random kneed vector (also the first 17 entries of kneed_coulomb's): foot radius and
    dampers are each multiplied by ``kept()``, called right after it is drawn."""
    a1, b1, a2, b2 = rng.uniform(0.05, 0.6, 4)
    return np.array(
        [
            rng.uniform(0.05, 2.0),  # mass_hip
            rng.uniform(0.05, 2.0),  # mass_thigh
            rng.uniform(0.05, 2.0),  # mass_shank
            a1,
            b1,
            a2,
            b2,
            rng.uniform(0.0, 0.05),  # inertia_thigh
            rng.uniform(0.0, 0.05),  # inertia_shank
            rng.uniform(-0.05, 0.05),  # offset_thigh
            rng.uniform(-0.05, 0.05),  # offset_shank
            *_foot_slope_g_dampers(rng, a1 + b1, 1.0, 3, kept),  # damping_hip, _knee, _ankle
        ]
    )


def _zero_plain(p, plain_zero, plain, rng):
    """``p`` with the entries the "/plain" kernels fix at zero set to zero: all of them if
    ``plain``, else each with probability 0.3."""
    zero = plain_zero if plain else [i for i in plain_zero if rng.random() < 0.3]
    p[list(zero)] = 0.0
    return p


def _compass_params(rng, plain):
    return _zero_plain(compass_vector(rng), _COMPASS_PLAIN_ZERO, plain, rng)


def _kneed_params(rng, plain):
    return _zero_plain(kneed_vector(rng), _KNEED_PLAIN_ZERO, plain, rng)


@dataclasses.dataclass(frozen=True)
class Case:
    name: str  # registry entry
    module: object
    params: object  # (rng, plain) -> p
    n_points: int

    @property
    def plain(self):
        return "/plain" in self.name

    @property
    def ignore_scuff(self):
        """swing_scuff = "ignore" (the numba twin is ``reset_ignore_scuff``)."""
        return self.name.endswith("/ignore_scuff")

    @property
    def n_phases(self):
        return len(self.module.PHASE_NAMES)

    def c_model(self):
        models = registry()
        assert self.name in models, sorted(models)
        return CModel(models[self.name], self.module, self.n_points)


CASES = [
    Case("simplest", simplest, _simplest_params, 3),
    Case("compass", compass, _compass_params, 3),
    Case("compass/plain", compass, _compass_params, 3),
    Case("kneed", kneed, _kneed_params, 4),
    Case("kneed/plain", kneed, _kneed_params, 4),
    Case("kneed/ignore_scuff", kneed, _kneed_params, 4),
    Case("kneed/plain/ignore_scuff", kneed, _kneed_params, 4),
]
IDS = [c.name for c in CASES]


def _compare(case):
    return _assert_close if case.plain else assert_bits


# --------------------------------------------------------------------------------------
# Registry
# --------------------------------------------------------------------------------------


def test_registry_lists_the_models():
    models = registry()
    for case in CASES:
        entry = models[case.name]
        for key in ("rhs", "guards", "reset", "jac", "energy", "points"):
            assert isinstance(entry[key], int) and entry[key] != 0, (case.name, key)
        assert not entry["start_phase"], case.name  # these models start in phase 0
        assert not entry["ctx"], case.name


# --------------------------------------------------------------------------------------
# Vector field, guards, Jacobian, energy, points
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_continuous_functions_agree(case):
    c = case.c_model()
    m = case.module
    same = _compare(case)
    rng = np.random.default_rng(20240611)
    n_x = m.N_X
    for trial in range(400):
        p = case.params(rng, case.plain)
        x = rng.uniform(-1.4, 1.4, n_x)
        x[n_x // 2 :] *= 3.0
        if trial % 5 == 0 and case.module is kneed:
            x[2], x[5] = x[1], x[4]  # locked-knee state
        t = rng.uniform(0.0, 2.0)
        for phase in range(case.n_phases):
            what = f"{case.name} trial {trial} phase {phase}"
            assert_phase_functions_agree(c, m, phase, t, x, p, what, same)
        assert_state_functions_agree(c, m, x, p, f"{case.name} {trial}", same)


_RHS_JAC = ctypes.CFUNCTYPE(
    None, ctypes.c_int64, ctypes.c_double, *([ctypes.c_void_p] * 5)
)  # (phase, t, x, p, dx, J, ctx)


def test_only_plain_entries_have_a_fused_rhs_jac():
    """Only the "/plain" entries have a fused rhs and Jacobian (``rhs_jac``, which the
    integrator calls for their (rhs, jac) pair when a run wants the Jacobian)."""
    for name, entry in registry().items():
        assert isinstance(entry["rhs_jac"], int), name
        assert bool(entry["rhs_jac"]) == ("/plain" in name), name


@pytest.mark.parametrize("case", [c for c in CASES if c.plain], ids=lambda c: c.name)
def test_fused_rhs_jac_is_rhs_and_jac(case):
    """A "/plain" entry's rhs_jac at 200 random states in each phase: J the entry's jac to
    the bit (the accel_and_jac kernels are accel_jac's lowering), dx its rhs to
    ``PLAIN_RTOL`` (the accelerations the Jacobian's solve computes, not accel's) and the
    rates exactly."""
    c = case.c_model()
    m = case.module
    fused = _RHS_JAC(registry()[case.name]["rhs_jac"])
    rng = np.random.default_rng(20260611)
    n_x = m.N_X
    for trial in range(200):
        p = case.params(rng, True)
        x = rng.uniform(-1.4, 1.4, n_x)
        x[n_x // 2 :] *= 3.0
        if trial % 5 == 0 and m is kneed:
            x[2], x[5] = x[1], x[4]  # locked-knee state
        t = rng.uniform(0.0, 2.0)
        for phase in range(case.n_phases):
            what = f"{case.name} trial {trial} phase {phase}"
            dx = np.full(n_x, np.nan)
            J = np.full((n_x, n_x), np.nan)
            fused(phase, t, x.ctypes.data, p.ctypes.data, dx.ctypes.data, J.ctypes.data, None)
            assert_bits(J, c.jac(phase, t, x, p), f"{what}: J")
            rhs = c.rhs(phase, t, x, p)
            assert_bits(dx[: n_x // 2], rhs[: n_x // 2], f"{what}: rates")
            _assert_close(dx, rhs, f"{what}: dx")


# --------------------------------------------------------------------------------------
# Reset maps: every branch
# --------------------------------------------------------------------------------------


def _reset_states(case, rng, n):
    """(phase, k, x, p) tuples reaching every branch of the case's reset map."""
    m = case.module
    out = []
    for i in range(n):
        p = case.params(rng, case.plain)
        slope = p[0] if m is simplest else p[6] if m is compass else p[12]
        x = rng.uniform(-1.2, 1.2, m.N_X)
        x[m.N_X // 2 :] *= 3.0
        if m is simplest:
            x[1] = 2.0 * x[0] + rng.choice([0.0, rng.normal(0.0, 1e-3)])
            for k in range(3):
                out.append((0, k, x.copy(), p))
        elif m is compass:
            # Swing foot on the slope: q_swing = -2 slope - q_stance (ahead for q_stance
            # + slope < 0, a scuff behind otherwise).
            x[0] = rng.uniform(-0.6, 0.6)
            x[1] = -2.0 * slope - x[0]
            if i % 7 == 0:
                x[1] = x[0]  # legs together: step length zero, ignored
            if i % 11 == 0:
                x[2 + rng.integers(2)] = np.nan  # non-finite impact system: singular
            if i % 13 == 0:
                p = p.copy()
                p[[0, 1, 4]] = 0.0  # massless: the impact system is singular
            for k in range(3):
                out.append((0, k, x.copy(), p))
        else:
            # Swing foot on the slope with the knee straight (psi2 = psi3 = -psi1), or about
            # to lock, or bent.
            x[0] = rng.uniform(-0.6, 0.6)
            x[1] = -2.0 * slope - x[0]
            kind = i % 4
            if kind == 0:
                x[2] = x[1]
                x[5] = x[4]
            elif kind == 1:
                x[2] = x[1] + rng.uniform(-1e-6, 1e-6)
            elif kind == 2:
                x[2] = x[1] + rng.uniform(-0.5, 0.5)
            if i % 11 == 0:
                x[3 + rng.integers(3)] = np.nan
            if i % 13 == 0:
                p = p.copy()
                p[[0, 1, 2, 7, 8]] = 0.0  # massless: singular impact systems
            for phase in range(2):
                for k in range(4):
                    out.append((phase, k, x.copy(), p))
    return out


# Outcomes (k, phase, action, next phase, status) each reset must reach at least once.
_NONPHYS = int(Status.NONPHYSICAL_IMPACT)
_SINGULAR = int(Status.LINEAR_SOLVE_FAILED)
_FF, _FB = int(Status.FELL_FORWARD), int(Status.FELL_BACKWARD)
REQUIRED = {
    simplest: {
        (0, 0, EVENT_IGNORE, 0, 0),  # theta >= 0: the mid-stance scuff
        (0, 0, EVENT_STRIDE, 0, 0),
        (1, 0, EVENT_TERMINAL, 0, _FF),
        (2, 0, EVENT_TERMINAL, 0, _FB),
    },
    compass: {
        (0, 0, EVENT_IGNORE, 0, 0),  # scuff: swing foot behind
        (0, 0, EVENT_STRIDE, 0, 0),
        (0, 0, EVENT_TERMINAL, 0, _NONPHYS),
        (0, 0, EVENT_TERMINAL, 0, _SINGULAR),
        (1, 0, EVENT_TERMINAL, 0, _FF),
        (2, 0, EVENT_TERMINAL, 0, _FB),
    },
    kneed: {
        (0, 0, EVENT_CONTINUE, 1, 0),  # knee lock
        (0, 0, EVENT_STRIDE, 0, 0),  # knee lock + heel strike in one reset
        (0, 0, EVENT_TERMINAL, 1, _NONPHYS),  # knee lock, then a nonphysical heel strike
        (0, 0, EVENT_TERMINAL, 0, _SINGULAR),  # singular knee lock
        (1, 0, EVENT_TERMINAL, 0, int(Status.TRIPPED)),
        (1, 0, EVENT_STRIDE, 0, 0),  # contact a hair before knee lock: lock + strike
        (1, 0, EVENT_CONTINUE, 1, 0),  # the same without the strike (foot moving up)
        (1, 1, EVENT_IGNORE, 1, 0),  # scuff
        (1, 1, EVENT_STRIDE, 0, 0),  # heel strike
        (1, 1, EVENT_TERMINAL, 1, _NONPHYS),
        (1, 1, EVENT_TERMINAL, 1, _SINGULAR),
        (2, 0, EVENT_TERMINAL, 0, _FF),
        (3, 1, EVENT_TERMINAL, 1, _FB),
    },
}


# swing_scuff = "ignore": the bent-knee contact is ignored instead of a trip; the rest alike.
_TRIP = (1, 0, EVENT_TERMINAL, 0, int(Status.TRIPPED))
REQUIRED_IGNORE_SCUFF = (REQUIRED[kneed] - {_TRIP}) | {(1, 0, EVENT_IGNORE, 0, 0)}


@pytest.mark.parametrize("case", CASES, ids=IDS)
def test_reset_agrees_on_every_branch(case):
    c = case.c_model()
    m = case.module
    same = _compare(case)
    rng = np.random.default_rng(7)
    seen = set()
    for phase, k, x, p in _reset_states(case, rng, 600):
        what = f"{case.name} reset phase {phase} k {k} x {x.tolist()}"
        ref_out = assert_reset_agrees(c, m, phase, k, x, p, what, same, case.ignore_scuff)
        seen.add((k, phase, *ref_out))
    required = REQUIRED_IGNORE_SCUFF if case.ignore_scuff else REQUIRED[m]
    missing = required - seen
    assert not missing, f"{case.name}: branches not reached {sorted(missing)}"


# --------------------------------------------------------------------------------------
# Whole strides through the integrator
# --------------------------------------------------------------------------------------

SCENES = {
    "simplest": "gaits/simplest_garcia.toml",
    "compass": "gaits/compass_goswami.toml",
    "kneed": "gaits/kneed_hsu.toml",
}


@pytest.mark.parametrize("name", list(SCENES))
def test_stride_with_c_model_matches_numba(name):
    """One stride of the scene's gait, bit for bit: final state and time, every event
    (time, guard, post-event state, impulse), the stride's Jacobian and dt/dx0."""
    scene = load_scene(SCENES[name])
    ref = solve_with_events(get_model(name).system, scene)
    sol = solve_with_events(c_system(name), scene)
    assert_same_run(sol, ref, name)


@pytest.mark.parametrize("name", ["compass", "kneed"])
def test_stride_with_plain_c_model_matches_numba(name):
    """The "/plain" entry on the same scenes (their plain parameters are zero): states and
    event times to 1e-13 (they differ by a few ulps); the Jacobian to 1e-9 of its largest
    entry, because the saltation matrices come from finite differences of the reset and
    guards (relative step 1e-3), which magnify the kernels' round-off differences (1e-11
    seen)."""
    scene = load_scene(SCENES[name])
    p = scene.params.as_array()
    assert not p[list(_plain_zero(name))].any()
    ref = solve_with_events(get_model(name).system, scene)
    sol = solve_with_events(c_system(name, name + "/plain"), scene)
    assert len(sol.events) == len(ref.events) >= 1
    np.testing.assert_array_equal(sol.events.guard, ref.events.guard)
    np.testing.assert_allclose(sol.x, ref.x, rtol=0, atol=1e-13)
    np.testing.assert_allclose(sol.t, ref.t, rtol=0, atol=1e-13)
    np.testing.assert_allclose(sol.events.t, ref.events.t, rtol=0, atol=1e-13)
    np.testing.assert_allclose(sol.events.x_post, ref.events.x_post, rtol=0, atol=1e-13)
    scale = np.abs(ref.jac).max()
    np.testing.assert_allclose(sol.jac, ref.jac, rtol=0, atol=1e-9 * scale)
