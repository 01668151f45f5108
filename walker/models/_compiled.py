"""Checked calls into the compiled model functions of walker._hybrid: a registry entry's
phase functions (rhs, guards, jac, reset), its state functions (energy, points, start_phase,
torques) and the generated kernels (mass matrix, bias, ...), on numpy arrays.

Every length and dtype is checked here, before the call, and a wrong one raises an error
naming the argument: the C reads exactly the lengths its model declares and cannot check
them itself.  :class:`walker.models.WalkerModel` exposes these as methods (``model.rhs``,
``model.guards``, ``model.kernel``, ...); the analysis tools, the figures and the tests
call the compiled model through them.
"""

from __future__ import annotations

import ctypes
import functools
import math
import operator

import numpy as np

__all__ = ["as_vector", "as_index", "call_phase_fn", "call_reset", "call_kernel", "kernel_info"]

_vp = ctypes.c_void_p
_i64 = ctypes.c_int64
_f64 = ctypes.c_double
_PHASE_FN = ctypes.CFUNCTYPE(None, _i64, _f64, _vp, _vp, _vp, _vp)
_RESET_FN = ctypes.CFUNCTYPE(None, _i64, _i64, _f64, _vp, _vp, _vp, _vp, _vp, _vp)
_KERNELS = {
    "qqdp_v": ctypes.CFUNCTYPE(None, _vp, _vp, _vp, _vp),
    "qp_v": ctypes.CFUNCTYPE(None, _vp, _vp, _vp),
    "qqdp_s": ctypes.CFUNCTYPE(_f64, _vp, _vp, _vp),
    "qp_s": ctypes.CFUNCTYPE(_f64, _vp, _vp),
    "qqdqddp_v": ctypes.CFUNCTYPE(None, _vp, _vp, _vp, _vp, _vp),
}
_KERNEL_ARGS = {
    "qqdp_v": ("q", "qd"),
    "qp_v": ("q",),
    "qqdp_s": ("q", "qd"),
    "qp_s": ("q",),
    "qqdqddp_v": ("q", "qd", "qdd"),
}


def as_vector(value, name: str, length: int, *, at_least: bool = False) -> np.ndarray:
    """``value`` as a C-contiguous float64 vector of ``length`` entries (``at_least``: of at
    least ``length``); ValueError/TypeError naming ``name`` otherwise."""
    if hasattr(value, "as_array"):  # a parameter dataclass
        value = value.as_array()
    try:
        array = np.asarray(value)
    except Exception as exc:  # a ragged sequence
        raise ValueError(f"`{name}` must be a 1-dimensional array of floats.") from exc
    if array.dtype.kind not in "biuf":
        raise TypeError(f"`{name}` must hold real numbers, got dtype {array.dtype}")
    if array.ndim != 1:
        raise ValueError(f"`{name}` must be 1-dimensional, got shape {array.shape}")
    if (array.shape[0] < length) if at_least else (array.shape[0] != length):
        rule = f"at least {length}" if at_least else f"{length}"
        raise ValueError(f"`{name}` must have {rule} entries, got {array.shape[0]}")
    return np.ascontiguousarray(array, dtype=np.float64)


def as_index(value, name: str, count: int) -> int:
    """``value`` as an int in ``[0, count)``; TypeError/ValueError naming ``name``."""
    try:
        index = operator.index(value)
    except TypeError as exc:
        raise TypeError(f"`{name}` must be an int, got {value!r}") from exc
    if not 0 <= index < count:
        raise ValueError(f"`{name}` must be in [0, {count}), got {index}")
    return index


def _as_time(t) -> float:
    t = float(t)
    if not math.isfinite(t):
        raise ValueError(f"`t` must be finite, got {t!r}")
    return t


def call_phase_fn(address: int, phase: int, t, x: np.ndarray, p: np.ndarray, shape, ctx=None):
    """Call a phase function (rhs, guards, jac: ``f(phase, t, x, p, out, ctx)``) on checked
    arrays; ``out`` of ``shape``, filled with NaN first."""
    out = np.full(shape, np.nan)
    _PHASE_FN(address)(phase, _as_time(t), x.ctypes.data, p.ctypes.data, out.ctypes.data, ctx)
    return out


def call_reset(address: int, phase: int, k: int, t, x, p, n_impulse: int, ctx=None):
    """Call a reset map on checked arrays: ``(action, next_phase, status, x_new, impulse)``."""
    x_new = x.copy()
    impulse = np.zeros(n_impulse)
    out = np.full(3, -1, dtype=np.int64)
    _RESET_FN(address)(
        phase,
        k,
        _as_time(t),
        x.ctypes.data,
        p.ctypes.data,
        x_new.ctypes.data,
        impulse.ctypes.data,
        out.ctypes.data,
        ctx,
    )
    return int(out[0]), int(out[1]), int(out[2]), x_new, impulse


def kernel_info(key: str):
    """``(signature, address, n_q, n_p, shape)`` of generated kernel ``key`` ("<model>.<name>",
    variants "<model>/<variant>.<name>"), or None."""
    return _kernel_table().get(key)


@functools.cache
def _kernel_table() -> dict:
    from walker import _hybrid

    return _hybrid.kernels()


def call_kernel(key: str, p, q, qd=None, qdd=None):
    """Call generated C kernel ``key`` at ``q`` (and ``qd``, ``qdd`` if it takes them) and
    the parameters ``p`` (at least the ``n_p`` it reads); returns its output, an ndarray of
    the kernel's shape, or a float for a kernel that returns one."""
    info = kernel_info(key)
    if info is None:
        raise ValueError(f"`name` must name a generated kernel, got {key!r}")
    sig, address, n_q, n_p, shape = info
    given = {"q": q, "qd": qd, "qdd": qdd}
    wanted = _KERNEL_ARGS[sig]
    for name, value in given.items():
        if (value is None) != (name not in wanted):
            rule = "is required" if value is None else "is not taken"
            raise TypeError(f"`{name}` {rule} by kernel {key} (arguments {', '.join(wanted)}, p)")
    arrays = [as_vector(given[name], name, n_q) for name in wanted]
    pp = as_vector(p, "p", n_p, at_least=True)
    fn = _KERNELS[sig](address)
    if not shape:
        return float(fn(*(a.ctypes.data for a in arrays), pp.ctypes.data))
    out = np.full(shape, np.nan)
    fn(*(a.ctypes.data for a in arrays), pp.ctypes.data, out.ctypes.data)
    return out
