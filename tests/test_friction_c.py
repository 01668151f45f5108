"""walker's dry-friction layer in C (walker/_core/wk_friction.c, a port of
walker/friction.py) and the three models built on it (walker/_core/model_compass_coulomb.c,
model_double_pendulum.c, model_kneed_coulomb.c) against the numba functions they port.

The layer has no entry of its own in the extension: it is tested through the models, whose
functions are called through ctypes at the addresses ``walker._hybrid.models()`` reports,
at random states and parameter vectors in every phase (rhs, guards, Jacobian: every mode
combination, hence every branch of ``accelerations``, ``slip_force``,
``accelerations_jacobian`` and ``guards``), at states with joints at rest (``start_phase``:
``choose_modes`` with and without joints at rest, consistent with strict inequalities, only
with non-strict ones (a tie, built with a friction equal to the holding torque), with none;
``settle`` with and without a stuck joint), and at the friction events' and impacts'
states (the resets: ``switch`` both ways, to stick and to slip, ``project_stuck``, and the
singular systems of massless parameter vectors).  Each test asserts that its branches were
reached, classified with the numba functions of walker.friction.

Tolerance: none.  Every output must agree with numba to the bit (any NaN matching any NaN):
the C code performs the numba functions' operations in the same order, both call the same
libm, and neither contracts multiply-adds (setup.py compiles with ``-ffp-contract=off``;
numba does not contract without fastmath).

The last tests run the shipped friction scenes (and friction variants of them) through
walker.integrate with the C functions given as addresses and compare with the numba model:
final state and time, every event (time, guard, phases, post-event state, impulse), the
Jacobian and dt/dx0, bit for bit.
"""

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
from test_models_c import compass_vector, kneed_vector

from walker import friction as fr
from walker import load_scene
from walker.models import compass_coulomb, double_pendulum, get_model, kneed_coulomb
from walker.status import EVENT_CONTINUE, EVENT_IGNORE, EVENT_STRIDE, EVENT_TERMINAL, Status

_SINGULAR = int(Status.LINEAR_SOLVE_FAILED)


# --------------------------------------------------------------------------------------
# Models: random parameters, joints, states
# --------------------------------------------------------------------------------------


def _coulomb(rng, n):
    """Dry frictions: zero, small (joints slip) or large (joints at rest stick)."""
    out = np.empty(n)
    for j in range(n):
        kind = rng.integers(3)
        out[j] = 0.0 if kind == 0 else rng.uniform(0.0, 0.5) if kind == 1 else rng.uniform(1, 60)
    return out


def _kept(rng):
    """Keep an entry with probability 0.7 (else it is zero)."""
    return lambda: rng.random() < 0.7


def _compass_params(rng):
    return np.concatenate([compass_vector(rng, _kept(rng)), _coulomb(rng, 2)])


def _double_pendulum_params(rng):
    l1, l2 = rng.uniform(0.2, 2.0, 2)
    base = [
        rng.uniform(0.1, 5.0),  # mass_1
        rng.uniform(0.1, 5.0),  # mass_2
        rng.uniform(0.0, 1.0),  # inertia_1
        rng.uniform(0.0, 1.0),  # inertia_2
        l1,
        l2,
        rng.uniform(0.0, 1.0) * l1,  # com_1
        rng.uniform(0.0, 1.0) * l2,  # com_2
        rng.uniform(1.0, 12.0),  # g
        rng.uniform(0.0, 1.0) * (rng.random() < 0.7),  # damping_1
        rng.uniform(0.0, 1.0) * (rng.random() < 0.7),  # damping_2
    ]
    return np.concatenate([base, _coulomb(rng, 2)])


def _kneed_params(rng):
    return np.concatenate([kneed_vector(rng, _kept(rng)), np.asarray(_coulomb(rng, 3)) * 0.2])


@dataclasses.dataclass(frozen=True)
class Case:
    name: str
    module: object
    params: object  # rng -> p
    massless: tuple  # indices of p whose zeroing makes every mass matrix singular
    slope: int | None  # index of the slope in p (walkers)
    n_points: int

    @property
    def n_phases(self):
        return len(self.module.PHASE_NAMES)

    @property
    def n_q(self):
        return self.module.N_X // 2

    @property
    def n_base_guards(self):
        return len(self.module.GUARD_NAMES) - 2 * len(self.module.JOINTS)

    def c_model(self):
        models = registry()
        assert self.name in models, sorted(models)
        return CModel(models[self.name], self.module, self.n_points)

    def split(self, phase):
        """(base, S, modes of the base's joints) of a phase."""
        m = self.module
        if m is kneed_coulomb:
            if phase < m.N_UNLOCKED:
                return 0, m._S_UNLOCKED, _decode(phase, 3)
            return 1, m._S_LOCKED, _decode(phase - m.N_UNLOCKED, 2)
        return 0, m._S, _decode(phase, 2)

    def matrices(self, base, x, p):
        """(D, f, S, F, qd) of a base phase at state x, from the numba model."""
        m = self.module
        if m is kneed_coulomb:
            return m._matrices(base, x, p)
        D, f, F, qd = m._matrices(x, p)
        return D, f, m._S, F, qd


def _decode(code, m):
    modes = np.empty(m, dtype=np.int64)
    fr.decode(code, modes)
    return modes


CASES = [
    Case("compass_coulomb", compass_coulomb, _compass_params, (0, 1, 4), 6, 3),
    Case("double_pendulum", double_pendulum, _double_pendulum_params, (0, 1, 2, 3), None, 3),
    Case("kneed_coulomb", kneed_coulomb, _kneed_params, (0, 1, 2, 7, 8), 12, 4),
]
# The kneed_coulomb cases run with the slow tests: their numba reference functions take most of
# this file's time to compile on a machine without numba's cache (about half of it here), and
# the other cases check the same compiled glue.
CASE_PARAMS = [
    pytest.param(c, id=c.name, marks=pytest.mark.slow if c.name == "kneed_coulomb" else ())
    for c in CASES
]


def _rest(case, x, rest, rng, base=0):
    """Puts the rates of the joints flagged in ``rest`` at zero (or within W_TOL of it):
    the joint rows are lower bidiagonal with a unit diagonal, so qd_j follows from the
    lower joints."""
    n_q = case.n_q
    S = case.split(0 if base == 0 else case.module.N_UNLOCKED)[1]
    qd = x[n_q : n_q + S.shape[0]]
    for j in range(S.shape[0]):
        if rest[j]:
            tiny = rng.choice([0.0, 0.0, rng.uniform(-0.9, 0.9) * fr.W_TOL])
            qd[j] = tiny - sum(S[j, i] * qd[i] for i in range(j))
    if case.module is kneed_coulomb and base == 1:
        x[2], x[5] = x[1], x[4]


def _random_state(case, rng, trial):
    m = case.module
    x = rng.uniform(-1.4, 1.4, m.N_X)
    x[case.n_q :] *= 3.0
    kind = trial % 4
    if kind == 1:  # some joints at rest
        _rest(case, x, rng.random(len(m.JOINTS)) < 0.6, rng)
    elif kind == 2:  # every joint at rest
        _rest(case, x, np.ones(len(m.JOINTS), bool), rng)
    if m is kneed_coulomb and trial % 3 == 0:
        x[2], x[5] = x[1], x[4]  # locked-knee state
    return x


# --------------------------------------------------------------------------------------
# Registry
# --------------------------------------------------------------------------------------


def test_registry_lists_the_friction_models():
    models = registry()
    for case in CASES:
        assert case.name in models, sorted(models)
        entry = models[case.name]
        for key in ("rhs", "guards", "reset", "jac", "energy", "points", "start_phase"):
            assert isinstance(entry[key], int) and entry[key] != 0, (case.name, key)
        assert not entry["ctx"], case.name


# --------------------------------------------------------------------------------------
# rhs, guards, Jacobian in every phase; energy, points
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("case", CASE_PARAMS)
def test_continuous_functions_agree(case):
    c = case.c_model()
    m = case.module
    rng = np.random.default_rng(20240612)
    kinds = set()  # slip_force outcomes reached: 0 (a joint sticks), 1, -1
    for trial in range(150):
        p = case.params(rng)
        if trial % 10 == 9:
            p[list(case.massless)] = 0.0  # singular mass matrix
        if trial % 10 == 8:
            p[-len(m.JOINTS) :] = 0.0  # no dry friction
        x = _random_state(case, rng, trial)
        t = rng.uniform(0.0, 2.0)
        for phase in range(case.n_phases):
            what = f"{case.name} trial {trial} phase {phase}"
            assert_phase_functions_agree(c, m, phase, t, x, p, what)
            _, S, modes = case.split(phase)
            F = p[m.I_COULOMB : m.I_COULOMB + S.shape[0]].copy()
            kinds.add(int(fr.slip_force(S, F, modes, np.empty(S.shape[1]))))
        assert_state_functions_agree(c, m, x, p, f"{case.name} {trial}")
    assert kinds == {0, 1, -1}


# --------------------------------------------------------------------------------------
# start_phase: choose_modes and settle
# --------------------------------------------------------------------------------------


def _choose_branch(case, x, p):
    """Which way walker.friction.choose_modes went at state x (unlocked base)."""
    D, f, S, F, qd = case.matrices(0, x, p)
    m = S.shape[0]
    modes = np.zeros(m, dtype=np.int64)
    ok = fr.choose_modes(D, f, S, F, qd, np.ones(m, dtype=np.bool_), modes)
    rest = np.abs(S @ qd) <= fr.W_TOL
    if not rest.any():
        return "moving"
    if not ok:
        return "none consistent"
    strict = fr._consistent(D, f, S, F, modes, rest, True, np.empty(len(qd)), np.empty(m))
    return ("strict" if strict else "tie") + (" stick" if (modes == fr.STICK).any() else "")


def _tie(case, x, p):
    """Sets one joint at rest's friction equal to its holding torque with the other joints
    slipping by sign (a tangency: no combination is consistent with strict inequalities
    when the slip acceleration rounds to zero or against the slip)."""
    D, f, S, F, qd = case.matrices(0, x, p)
    w = S @ qd
    at_rest = np.flatnonzero(np.abs(w) <= fr.W_TOL)
    if len(at_rest) != 1:
        return p
    j = at_rest[0]
    modes = np.where(w > 0, fr.SLIP_POSITIVE, fr.SLIP_NEGATIVE).astype(np.int64)
    modes[j] = fr.STICK
    qdd = np.empty(len(qd))
    lam = np.empty(S.shape[0])
    if not fr.accelerations(D, f, S, F, modes, qdd, lam):
        return p
    p = p.copy()
    p[case.module.I_COULOMB + j] = abs(lam[j])
    return p


@pytest.mark.parametrize("case", CASE_PARAMS)
def test_start_phase_agrees(case):
    c = case.c_model()
    m = case.module
    rng = np.random.default_rng(99)
    seen = set()
    phases = set()
    for trial in range(1500):
        p = case.params(rng)
        x = rng.uniform(-1.4, 1.4, m.N_X)
        x[case.n_q :] *= 3.0
        rest = rng.random(len(m.JOINTS)) < 0.6
        if trial % 5 == 4:
            rest[:] = False
            rest[rng.integers(len(rest))] = True
        _rest(case, x, rest, rng)
        if trial % 5 == 4:
            p = _tie(case, x, p)
        if trial % 23 == 0:
            p[list(case.massless)] = 0.0
        x_before = x.copy()
        ref = m.start_phase(x, p)
        got = c.start_phase(x, p)
        assert got == float(ref), f"{case.name} start_phase x {x.tolist()} p {p.tolist()}"
        assert_bits(x, x_before, "start_phase must not write its input")
        seen.add(_choose_branch(case, x, p))
        phases.add(int(ref))
    required = {"moving", "strict", "strict stick", "tie stick", "none consistent"}
    assert required <= seen, f"{case.name}: choose_modes branches not reached {required - seen}"
    assert set(range(len(fr.MODE_LABELS) ** len(m.JOINTS))) <= phases, sorted(phases)


# --------------------------------------------------------------------------------------
# Resets: friction events (switch, settle, project_stuck) and the impacts
# --------------------------------------------------------------------------------------


def _base_state(case, rng, i, p):
    """A state at an impact of the walker (swing foot on the slope), as in
    tests/test_models_c.py."""
    m = case.module
    slope = p[case.slope]
    x = rng.uniform(-1.2, 1.2, m.N_X)
    x[case.n_q :] *= 3.0
    x[0] = rng.uniform(-0.6, 0.6)
    x[1] = -2.0 * slope - x[0]
    if m is compass_coulomb:
        if i % 7 == 0:
            x[1] = x[0]
    else:
        kind = i % 4
        if kind == 0:
            x[2] = x[1]
            x[5] = x[4]
        elif kind == 1:
            x[2] = x[1] + rng.uniform(-1e-6, 1e-6)
        elif kind == 2:
            x[2] = x[1] + rng.uniform(-0.5, 0.5)
    return x


def _event_state(case, rng, phase, j, breaks, p):
    """A state of a friction event of joint j in ``phase``: slip_stops with joint j's rate
    rounding-small, stick_breaks with the stuck joints at rest and joint j's friction near
    its holding torque."""
    m = case.module
    base, S, modes = case.split(phase)
    x = rng.uniform(-1.4, 1.4, m.N_X)
    x[case.n_q :] *= 3.0
    if m is kneed_coulomb and base == 1:
        x[2], x[5] = x[1], x[4]
    rest = modes == fr.STICK
    if not breaks:
        rest[j] = True
    _rest(case, x, rest, rng, base)
    if breaks and rng.random() < 0.7:
        D, f, S, F, qd = case.matrices(base, x, p)
        qdd = np.empty(len(qd))
        lam = np.empty(S.shape[0])
        if fr.accelerations(D, f, S, F, modes, qdd, lam) and np.isfinite(lam[j]):
            p = p.copy()
            p[m.I_COULOMB + j] = abs(lam[j]) * (1.0 + rng.choice([-1e-12, 0.0, 1e-12]))
    return x, p


def _reset_cases(case, rng, n):
    nb = case.n_base_guards
    for i in range(n):
        p = case.params(rng)
        if i % 17 == 0:
            p[list(case.massless)] = 0.0  # singular systems
        phase = int(rng.integers(case.n_phases))
        base, S, modes = case.split(phase)
        if case.slope is not None and i % 3 == 0:
            x = _base_state(case, rng, i, p)
            if i % 11 == 0:
                x[case.n_q + rng.integers(case.n_q)] = np.nan
            for k in range(nb):
                yield phase, k, x.copy(), p
            continue
        j = int(rng.integers(S.shape[0]))
        breaks = bool(modes[j] == fr.STICK) if rng.random() < 0.8 else bool(rng.integers(2))
        x, p = _event_state(case, rng, phase, j, breaks, p)
        yield phase, nb + 2 * j + int(breaks), x, p


def _outcome(case, phase, k, out):
    """A label for the branch a reset took."""
    action, next_phase, status = out
    nb = case.n_base_guards
    if action == EVENT_TERMINAL:
        return ("terminal", k < nb, status)
    if k < nb:
        base, _, modes = case.split(next_phase)
        return ("impact", action, base, bool((modes == fr.STICK).any()))
    j, breaks = divmod(k - nb, 2)
    _, _, before = case.split(phase)
    _, _, modes = case.split(next_phase)
    kind = "stick_breaks" if breaks else "slip_stops"
    return (kind, fr.MODE_LABELS[modes[j]], fr.MODE_LABELS[before[j]])


_STICK, _SP, _SM = "stick", "slip+", "slip-"
# every model with dry friction: each slip stops (to stick, or reverses), each stick breaks
# either way, and a friction event at a singular mass matrix is terminal
_FRICTION_EVENTS = {
    ("slip_stops", _STICK, _SP),
    ("slip_stops", _STICK, _SM),
    ("slip_stops", _SP, _SM),
    ("slip_stops", _SM, _SP),
    ("stick_breaks", _SP, _STICK),
    ("stick_breaks", _SM, _STICK),
    ("terminal", False, _SINGULAR),
}
REQUIRED = {
    "compass_coulomb": {
        *_FRICTION_EVENTS,
        ("impact", EVENT_STRIDE, 0, False),
        ("terminal", True, _SINGULAR),
        ("terminal", True, int(Status.NONPHYSICAL_IMPACT)),
        ("terminal", True, int(Status.FELL_FORWARD)),
    },
    "double_pendulum": _FRICTION_EVENTS,
    "kneed_coulomb": {
        *_FRICTION_EVENTS,
        ("impact", EVENT_STRIDE, 0, True),  # the new swing knee, at rest, sticks
        ("impact", EVENT_STRIDE, 0, False),
        ("impact", EVENT_CONTINUE, 1, False),  # knee lock
        ("terminal", True, _SINGULAR),
        ("terminal", True, int(Status.TRIPPED)),
        ("terminal", True, int(Status.NONPHYSICAL_IMPACT)),
    },
}


@pytest.mark.parametrize("case", CASE_PARAMS)
def test_reset_agrees_on_every_branch(case):
    c = case.c_model()
    m = case.module
    rng = np.random.default_rng(7)
    seen = set()
    for phase, k, x, p in _reset_cases(case, rng, 3000):
        what = f"{case.name} reset phase {phase} k {k} x {x.tolist()} p {p.tolist()}"
        ref_out = assert_reset_agrees(c, m, phase, k, x, p, what)
        if ref_out[0] != EVENT_IGNORE:
            seen.add(_outcome(case, phase, k, ref_out))
    missing = REQUIRED[case.name] - seen
    assert not missing, f"{case.name}: branches not reached {sorted(missing)}"


# --------------------------------------------------------------------------------------
# Whole runs through the integrator
# --------------------------------------------------------------------------------------

RUNS = {
    # name: (scene, overrides, n_strides, events at least, status)
    "compass_coulomb": ("gaits/compass_coulomb_goswami.toml", None, 1, 2, Status.COMPLETED),
    # the stance ankle sticks, breaks free, sticks again; the walker falls back
    "compass_coulomb/stick": (
        "gaits/compass_coulomb_goswami.toml",
        {"coulomb_ankle": 20.0},
        1,
        5,
        Status.FELL_BACKWARD,
    ),
    "kneed_coulomb": ("gaits/kneed_coulomb_hsu.toml", None, 1, 4, Status.COMPLETED),
    "double_pendulum": ("gaits/double_pendulum.toml", None, 0, 0, Status.COMPLETED),
    # both joints stick and slip, one at a time and together
    "double_pendulum/friction": (
        "gaits/double_pendulum.toml",
        {"coulomb_1": 2.0, "coulomb_2": 1.0, "damping_1": 0.2},
        0,
        10,
        Status.COMPLETED,
    ),
}


@pytest.mark.parametrize(
    "run",
    [pytest.param(r, marks=pytest.mark.slow if r == "kneed_coulomb" else ()) for r in RUNS],
)
def test_run_with_c_model_matches_numba(run):
    """The scene's stride (walkers) or run to t_max (the pendulum) with the C model, bit for
    bit: final state and time, every event (time, guard, phases, post-event state,
    impulse), the Jacobian and dt/dx0; the start phase from the C start_phase agrees."""
    path, overrides, n_strides, min_events, status = RUNS[run]
    name = run.split("/")[0]
    scene = load_scene(path, overrides)
    model = get_model(name)
    x0 = np.ascontiguousarray(scene.state, dtype=np.float64)
    p = scene.params.as_array()
    phase0 = model.start_phase(x0, p)
    c = CModel(registry()[name], model.module, 1)
    assert c.start_phase(x0, p) == float(phase0)
    run_kw = dict(phase0=phase0, n_strides=n_strides, status=status)
    ref = solve_with_events(model.system, scene, **run_kw)
    sol = solve_with_events(c_system(name), scene, **run_kw)
    assert_same_run(sol, ref, run, min_events=min_events, jacobian="Jacobian")
    np.testing.assert_array_equal(sol.events.phase_before, ref.events.phase_before)
    if run.endswith(("/stick", "/friction")):
        modes = [model.module.modes_of(int(ph)) for ph in ref.events.phase_after]
        assert any("stick" in m.values() for m in modes), "the run must reach a stuck joint"
