"""Calling walker's compiled C models through ctypes, for the tests that compare them with
the numba models they port (``tests/test_models_c.py``, ``tests/test_friction_c.py``,
``tests/test_actuated_c.py``; ``tests/test_generated_c.py`` uses :func:`assert_bits`).

The functions of a registry entry of ``walker._hybrid.models()`` are called at their
addresses on numpy arrays (:class:`CModel`); a model's ``HybridSystem`` can take the C
functions in place of the numba ones (:func:`c_system`) and be run through
``walker.integrate.hybrid_solve`` (:func:`solve_with_events`), and two such runs compared
bit for bit (:func:`assert_same_run`).
"""

from __future__ import annotations

import ctypes
import dataclasses

import numpy as np

from walker.models import get_model
from walker.status import Status

_vp = ctypes.c_void_p
_i64 = ctypes.c_int64
_f64 = ctypes.c_double
RHS = ctypes.CFUNCTYPE(None, _i64, _f64, _vp, _vp, _vp, _vp)
RESET = ctypes.CFUNCTYPE(None, _i64, _i64, _f64, _vp, _vp, _vp, _vp, _vp, _vp)
STATE = ctypes.CFUNCTYPE(None, _vp, _vp, _vp, _vp)


def registry():
    """``walker._hybrid.models()``: registry entry name -> the addresses of its functions."""
    from walker import _hybrid

    return _hybrid.models()


def _ptr(a):
    return a.ctypes.data


class CModel:
    """The functions of one registry entry, called through ctypes on numpy arrays.

    ``module`` is the numba model module (its ``N_X``, ``GUARD_NAMES`` and ``N_IMPULSE``
    give the sizes), ``n_points`` the number of points ``points`` returns, ``ctx`` an int
    address (0: NULL) passed to every call.  ``start_phase`` exists when the entry has one.
    """

    def __init__(self, entry, module, n_points, ctx=0):
        self.entry = entry
        self.n_x = module.N_X
        self.n_guards = len(module.GUARD_NAMES)
        self.n_impulse = module.N_IMPULSE
        self.n_points = n_points
        self.ctx = ctx or None
        self._rhs = RHS(entry["rhs"])
        self._guards = RHS(entry["guards"])
        self._jac = RHS(entry["jac"])
        self._reset = RESET(entry["reset"])
        self._energy = STATE(entry["energy"])
        self._points = STATE(entry["points"])
        self._start_phase = STATE(entry["start_phase"]) if entry.get("start_phase") else None

    def rhs(self, phase, t, x, p):
        dx = np.full(self.n_x, np.nan)
        self._rhs(phase, t, _ptr(x), _ptr(p), _ptr(dx), self.ctx)
        return dx

    def guards(self, phase, t, x, p):
        g = np.full(self.n_guards, np.nan)
        self._guards(phase, t, _ptr(x), _ptr(p), _ptr(g), self.ctx)
        return g

    def jac(self, phase, t, x, p):
        J = np.full((self.n_x, self.n_x), np.nan)
        self._jac(phase, t, _ptr(x), _ptr(p), _ptr(J), self.ctx)
        return J

    def reset(self, phase, k, t, x, p):
        x_new = x.copy()
        impulse = np.zeros(self.n_impulse)
        out = np.full(3, -1, dtype=np.int64)
        self._reset(phase, k, t, _ptr(x), _ptr(p), _ptr(x_new), _ptr(impulse), _ptr(out), self.ctx)
        return tuple(int(v) for v in out), x_new, impulse

    def energy(self, x, p):
        out = np.full(2, np.nan)
        self._energy(_ptr(x), _ptr(p), _ptr(out), self.ctx)
        return out

    def points(self, x, p):
        out = np.full((self.n_points, 2), np.nan)
        self._points(_ptr(x), _ptr(p), _ptr(out), self.ctx)
        return out

    def start_phase(self, x, p):
        out = np.full(1, np.nan)
        self._start_phase(_ptr(x), _ptr(p), _ptr(out), self.ctx)
        return out[0]


def numba_reset(module, phase, k, t, x, p, ignore_scuff=False):
    """The numba model's reset, returned as :meth:`CModel.reset` returns the C one."""
    x_new = x.copy()
    impulse = np.zeros(module.N_IMPULSE)
    reset = module.reset_ignore_scuff if ignore_scuff else module.reset
    action, next_phase, status = reset(phase, k, t, x, p, x_new, impulse)
    return (int(action), int(next_phase), int(status)), x_new, impulse


def assert_bits(c, ref, what):
    """Same float64 bit patterns (any NaN matches any NaN)."""
    c = np.asarray(c, dtype=np.float64)
    ref = np.asarray(ref, dtype=np.float64)
    assert c.shape == ref.shape, what
    nan_c, nan_r = np.isnan(c), np.isnan(ref)
    same = (c.view(np.uint64) == ref.view(np.uint64)) | (nan_c & nan_r)
    assert same.all(), f"{what}: C {c[~same]} vs numba {ref[~same]}"


def c_system(name, entry_name=None, **changes):
    """Model ``name``'s HybridSystem with the C functions of registry entry ``entry_name``
    (default ``name``); ``changes`` replace further fields (e.g. ``ctx``)."""
    entry = registry()[entry_name or name]
    return dataclasses.replace(
        get_model(name).system,
        rhs=entry["rhs"],
        guards=entry["guards"],
        reset=entry["reset"],
        jac=entry["jac"],
        **changes,
    )


def solve_with_events(system, scene, *, phase0=0, n_strides=1, status=Status.COMPLETED):
    """``hybrid_solve`` of ``system`` from the scene's state with its parameters and compute
    settings, with events and the Jacobian; the result's status is checked to be ``status``
    (unless None)."""
    from walker.integrate import hybrid_solve

    c = scene.compute
    sol = hybrid_solve(
        system,
        scene.state,
        scene.params.as_array(),
        phase0=phase0,
        t_max=c.t_max,
        n_strides=n_strides,
        method=c.method,
        rtol=c.rtol,
        atol=c.atol,
        output="events",
        jacobian=True,
    )
    if status is not None:
        assert sol.status == status, sol.status
    return sol


def assert_same_run(sol, ref, what, *, min_events=1, jacobian="stride Jacobian"):
    """Two runs agree bit for bit: at least ``min_events`` events, each with the same guard,
    phase after, time, post-event state and impulse; final state and time; the Jacobian
    (named ``jacobian`` in the message) and dt/dx0."""
    assert len(sol.events) == len(ref.events) >= min_events, what
    np.testing.assert_array_equal(sol.events.guard, ref.events.guard)
    np.testing.assert_array_equal(sol.events.phase_after, ref.events.phase_after)
    assert_bits(sol.x, ref.x, f"{what} final state")
    assert_bits(sol.t, ref.t, f"{what} final time")
    assert_bits(sol.events.t, ref.events.t, f"{what} event times")
    assert_bits(sol.events.x_post, ref.events.x_post, f"{what} post-event states")
    assert_bits(sol.events.impulse, ref.events.impulse, f"{what} impulses")
    assert_bits(sol.jac, ref.jac, f"{what} {jacobian}")
    assert_bits(sol.dt_dx0, ref.dt_dx0, f"{what} dt/dx0")


def assert_phase_functions_agree(c, m, phase, t, x, p, what, same=assert_bits):
    """The C model ``c`` and the numba module ``m`` agree on rhs and Jacobian (compared
    with ``same``) and on the guards (bit for bit) in ``phase``; return the numba rhs."""
    n_x = m.N_X
    dx = np.full(n_x, np.nan)
    m.rhs(phase, t, x, p, dx)
    same(c.rhs(phase, t, x, p), dx, f"rhs {what}")
    g = np.full(len(m.GUARD_NAMES), np.nan)
    m.guards(phase, t, x, p, g)
    assert_bits(c.guards(phase, t, x, p), g, f"guards {what}")
    J = np.full((n_x, n_x), np.nan)
    m.jac(phase, t, x, p, J)
    same(c.jac(phase, t, x, p), J, f"jac {what}")
    return dx


def assert_state_functions_agree(c, m, x, p, what, same=assert_bits):
    """The C model ``c`` and the numba module ``m`` agree on energy and points."""
    same(c.energy(x, p), np.array(m.energy(x, p)), f"energy {what}")
    same(c.points(x, p), m.points(x, p), f"points {what}")


def assert_reset_agrees(c, m, phase, k, x, p, what, same=assert_bits, ignore_scuff=False):
    """The C and numba resets at t = 0.3 give the same outcome ``(action, next phase,
    status)`` and the same post-reset state and impulse (compared with ``same``); return
    the outcome."""
    ref_out, ref_x, ref_imp = numba_reset(m, phase, k, 0.3, x, p, ignore_scuff)
    out, x_new, impulse = c.reset(phase, k, 0.3, x, p)
    assert out == ref_out, what
    same(x_new, ref_x, what)
    same(impulse, ref_imp, what)
    return ref_out
