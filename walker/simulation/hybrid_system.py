"""The contract between walker's compiled integrator and a model: :class:`HybridSystem`.

A hybrid system (a walker) is a bundle of compiled functions: a vector field per phase,
guards whose zero crossings are events, a reset (impact) map and optionally the vector
field's Jacobian.  This module defines the bundle and turns its functions into the C
addresses the kernel calls; :mod:`walker.simulation.integrate` runs it (and re-exports
:class:`HybridSystem`, the name users import).

Model functions (the extension point)
-------------------------------------
The integrator calls the model through the C ABI of ``walker/_core/wk_system.h``: four C
functions ``rhs``, ``guards``, ``reset``, ``jac`` and an opaque ``ctx`` pointer handed to
every call.  Each function of a :class:`HybridSystem` may be given as

* a numba ``@njit`` function with the array signature documented in :class:`HybridSystem`
  (a user's own system; numba is the optional extra ``numba``): it is bridged once per
  system into a C callback (a ``numba.cfunc`` that views the C pointers as arrays and calls
  it);
* a ``numba.cfunc`` compiled with the C signature of ``wk_system.h``;
* a ``ctypes`` function pointer with that signature (e.g. a ``CFUNCTYPE`` Python callback:
  slow, but handy for tests);
* a plain int address of such a function (from cffi, another extension module, or
  ``walker._hybrid.models()``, walker's models compiled into the extension, which is how
  :class:`walker.models.WalkerModel` builds its systems).

A system's addresses are computed on first use (:func:`_compiled`) and kept on the instance
with the objects that keep them alive; a bridge is shared by every system built from the same
``@njit`` function and sizes.
"""

from __future__ import annotations

import ctypes
import sys
import threading
from dataclasses import dataclass

import numpy as np

__all__ = ["HybridSystem"]

_FUNCTIONS = ("rhs", "guards", "reset", "jac")
_FUNCTION_KINDS = (
    "a numba @njit function, a numba cfunc, a ctypes function pointer or an int address"
)
# Length of the parameter array a bridged @njit function sees when the system does not
# declare n_params (the array is a view of the caller's ``p``; compiled code does not check
# bounds, so only the functions' own indexing matters).
_P_UNKNOWN_LENGTH = 1 << 20

_BRIDGES: dict = {}  # (dispatcher, function, sizes) -> numba cfunc, shared across systems
_BRIDGE_LOCK = threading.Lock()


def _numba_class(module, name):
    """A numba class if numba is already imported (a numba object cannot exist otherwise)."""
    mod = sys.modules.get(module)
    return getattr(mod, name, None) if mod is not None else None


def _kind_of(fn, name):
    """How the model function ``fn`` is given: "dispatcher", "cfunc", "ctypes" or "int".

    Raises TypeError naming the argument for anything else.
    """
    if isinstance(fn, int | np.integer) and not isinstance(fn, bool | np.bool_):
        if not 0 < int(fn) < 2**64:
            raise ValueError(f"`{name}` must be a non-zero address below 2**64, got {int(fn)}")
        return "int"
    if isinstance(fn, ctypes._CFuncPtr):
        return "ctypes"
    dispatcher = _numba_class("numba.core.dispatcher", "Dispatcher")
    if dispatcher is not None and isinstance(fn, dispatcher):
        return "dispatcher"
    cfunc = _numba_class("numba.core.ccallback", "CFunc")
    if cfunc is not None and isinstance(fn, cfunc):
        return "cfunc"
    raise TypeError(f"`{name}` must be {_FUNCTION_KINDS}, got {type(fn).__name__}")


def _bridge(fn, name, n_x, n_p, n_guards, n_impulse):
    """A numba cfunc with the C signature of ``name`` (wk_system.h) that calls the @njit
    function ``fn`` on arrays viewing the C pointers."""
    key = (fn, name, n_x, n_p, n_guards, n_impulse)
    with _BRIDGE_LOCK:
        bridge = _BRIDGES.get(key)
        if bridge is not None:
            return bridge
        import numba
        from numba import carray, types

        f64p = types.CPointer(types.float64)
        if name == "reset":
            sig = types.void(
                types.int64,
                types.int64,
                types.float64,
                f64p,
                f64p,
                f64p,
                f64p,
                types.CPointer(types.int64),
                types.voidptr,
            )

            def c_reset(phase, k, t, x, p, x_new, impulse, out, ctx):
                action, next_phase, status = fn(
                    phase,
                    k,
                    t,
                    carray(x, (n_x,)),
                    carray(p, (n_p,)),
                    carray(x_new, (n_x,)),
                    carray(impulse, (n_impulse,)),
                )
                out[0] = action
                out[1] = next_phase
                out[2] = status

            py_fn = c_reset
        else:
            sig = types.void(types.int64, types.float64, f64p, f64p, f64p, types.voidptr)
            if name == "jac":

                def c_jac(phase, t, x, p, J, ctx):
                    fn(phase, t, carray(x, (n_x,)), carray(p, (n_p,)), carray(J, (n_x, n_x)))

                py_fn = c_jac
            else:
                n_out = n_x if name == "rhs" else n_guards

                def c_vector(phase, t, x, p, out, ctx):
                    fn(phase, t, carray(x, (n_x,)), carray(p, (n_p,)), carray(out, (n_out,)))

                py_fn = c_vector
        try:
            # cache=False: numba's disk cache cannot key a closure over a dispatcher.
            bridge = numba.cfunc(sig, cache=False)(py_fn)
        except Exception as exc:
            raise TypeError(
                f"`{name}`: cannot compile the C bridge of {fn!r}; it must follow the "
                f"signature in HybridSystem's docstring ({type(exc).__name__}: {exc})"
            ) from exc
        _BRIDGES[key] = bridge
        return bridge


def _compiled(system):
    """The C addresses (rhs, guards, reset, jac, ctx) of the system's functions, computed on
    first use and kept on the instance together with the objects that keep them alive."""
    c = system.__dict__.get("_addrs")
    if c is None:
        n_p = system.n_params if system.n_params is not None else _P_UNKNOWN_LENGTH
        addresses = []
        keep = []
        for name in _FUNCTIONS:
            fn = getattr(system, name)
            if fn is None:
                addresses.append(0)
                continue
            kind = _kind_of(fn, name)
            if kind == "int":
                addresses.append(int(fn))
            elif kind == "ctypes":
                addresses.append(ctypes.cast(fn, ctypes.c_void_p).value or 0)
            else:
                if kind == "dispatcher":
                    fn = _bridge(fn, name, system.n_x, n_p, system.n_guards, system.n_impulse)
                addresses.append(fn.address)
            keep.append(fn)
        c = (*addresses, system.ctx, tuple(keep))
        object.__setattr__(system, "_addrs", c)
    return c


@dataclass(frozen=True)
class HybridSystem:
    """A hybrid dynamical system given by compiled functions.

    Contract of the array form (module-level numba ``@njit(cache=True)`` functions;
    ``phase``, ``k``, ``next_phase``, ``action``, ``status`` are int, ``t`` float, arrays
    float64):

    1. ``rhs(phase, t, x, p, dx) -> None`` fills ``dx``, shape (n_x,), with dx/dt in ``phase``.
    2. ``guards(phase, t, x, p, g) -> None`` fills ``g``, shape (n_guards,).  A guard not used
       in a phase returns the constant 1.0 there.
    3. ``reset(phase, k, t, x, p, x_new, impulse) -> (action, next_phase, status)`` is called
       with the state ``x`` where guard ``k`` fired.  ``x_new`` arrives holding a copy of
       ``x`` and ``impulse``, shape (n_impulse,), zeros.  ``action`` is one of
       :data:`walker.status.EVENT_IGNORE` (not an event: keep integrating, state unchanged),
       ``EVENT_CONTINUE`` (apply ``x_new``, go to ``next_phase``), ``EVENT_STRIDE`` (the same
       and count one stride) or ``EVENT_TERMINAL`` (stop; ``status`` is a
       :class:`walker.status.Status` value saying why).
    4. ``jac(phase, t, x, p, J) -> None`` (optional) fills ``J``, shape (n_x, n_x), with
       df/dx; needed for ``jacobian=True``.
    5. ``directions[phase, k]`` is -1 if guard ``k`` fires when it decreases through zero, +1
       when it increases, 0 either way.

    The integrator itself is C and calls the functions through the C ABI of
    ``walker/_core/wk_system.h`` (contiguous float64, row-major ``J``, ``ctx`` the opaque
    pointer below)::

        void rhs(int64_t phase, double t, const double *x, const double *p, double *dx,
                 void *ctx);
        void guards(int64_t phase, double t, const double *x, const double *p, double *g,
                    void *ctx);
        void reset(int64_t phase, int64_t k, double t, const double *x, const double *p,
                   double *x_new, double *impulse, int64_t *out, void *ctx);
                   /* out[0..2] = action, next_phase, status */
        void jac(int64_t phase, double t, const double *x, const double *p, double *J,
                 void *ctx);

    This is the extension point: each of ``rhs``, ``guards``, ``reset``, ``jac`` may be an
    ``@njit`` function of the array form above (bridged to the C ABI once per system with a
    ``numba.cfunc``; numba is imported only then), or already a C function: a
    ``numba.cfunc`` with the C signature, a ``ctypes`` function pointer (``CFUNCTYPE``), or
    an int address.  The caller keeps whatever an int address points to alive.

    Attributes
    ----------
    name : str
    n_x : int
        state size, the same in every phase.
    n_phases, n_guards, n_impulse : int
        number of phases, guards per phase (>= 0), length of the impulse vector (>= 1).
    rhs, guards, reset, jac : model functions (see above; ``jac`` may be None)
    directions : ndarray of int64, shape (n_phases, n_guards)
    phase_names : tuple of str, length n_phases
    guard_names : tuple of str, length n_guards
    n_params : int or None
        length of the parameter vector the functions index; when given, ``hybrid_solve``
        rejects a ``p`` of another length (compiled code does not check bounds).
    ctx : int
        address handed unchanged to every C call as ``ctx`` (0: NULL); bridged ``@njit``
        functions ignore it.
    autonomous_guards : bool
        True declares that ``guards`` does not read ``t`` (the built-in models'): the
        integrator may then skip a step's interior guard samples when every guard stays
        far from zero over the step, judged from its values and rates at the step's ends
        (see walker.simulation.integrate, section Events).  False (the default) samples every step.
    """

    name: str
    n_x: int
    n_phases: int
    n_guards: int
    n_impulse: int
    rhs: object
    guards: object
    reset: object
    jac: object | None
    directions: np.ndarray
    phase_names: tuple[str, ...]
    guard_names: tuple[str, ...]
    n_params: int | None = None
    ctx: int = 0
    autonomous_guards: bool = False

    def __post_init__(self):
        for name, low in (("n_x", 1), ("n_phases", 1), ("n_guards", 0), ("n_impulse", 1)):
            value = getattr(self, name)
            if not isinstance(value, int | np.integer) or isinstance(value, bool):
                raise TypeError(f"`{name}` must be an int, got {type(value).__name__}")
            if value < low:
                raise ValueError(f"`{name}` must be >= {low}, got {value}")
        for name in _FUNCTIONS:
            fn = getattr(self, name)
            if name == "jac" and fn is None:
                continue
            _kind_of(fn, name)
        if isinstance(self.ctx, bool) or not isinstance(self.ctx, int | np.integer):
            raise TypeError(
                f"`ctx` must be an int address (0: NULL), got {type(self.ctx).__name__}"
            )
        if not 0 <= int(self.ctx) < 2**64:
            raise ValueError(f"`ctx` must be an address in [0, 2**64), got {int(self.ctx)}")
        object.__setattr__(self, "ctx", int(self.ctx))
        if not isinstance(self.autonomous_guards, bool | np.bool_):
            raise TypeError(
                f"`autonomous_guards` must be a bool, got {type(self.autonomous_guards).__name__}"
            )
        object.__setattr__(self, "autonomous_guards", bool(self.autonomous_guards))
        d = np.asarray(self.directions)
        if d.shape != (self.n_phases, self.n_guards):
            raise ValueError(
                f"`directions` must have shape (n_phases, n_guards) = "
                f"{(self.n_phases, self.n_guards)}, got {d.shape}"
            )
        if d.size and not np.all(np.isin(d, (-1, 0, 1))):
            raise ValueError("`directions` values must be -1, 0 or +1")
        d = np.ascontiguousarray(d, dtype=np.int64)
        d.flags.writeable = False
        object.__setattr__(self, "directions", d)
        if len(self.phase_names) != self.n_phases:
            raise ValueError(
                f"`phase_names` must have n_phases = {self.n_phases} entries, "
                f"got {len(self.phase_names)}"
            )
        if len(self.guard_names) != self.n_guards:
            raise ValueError(
                f"`guard_names` must have n_guards = {self.n_guards} entries, "
                f"got {len(self.guard_names)}"
            )
        object.__setattr__(self, "phase_names", tuple(self.phase_names))
        object.__setattr__(self, "guard_names", tuple(self.guard_names))

    def __getstate__(self):
        # The compiled addresses belong to this process: a copy in another process bridges
        # its functions anew.
        state = dict(self.__dict__)
        state.pop("_addrs", None)
        return state
