"""The generated kernels' sine and cosine (walker/_core/wk_sincos.h) and their hoisted twins
(walker/symbolic/codegen_c.py, issue 30): checked against mpmath and libm, and the hoisted
kernels against the kernels they are printed from, through the extension's exported
symbols (ctypes)."""

from __future__ import annotations

import ctypes
import math

import numpy as np
import pytest
import walker._hybrid as hybrid

mpmath = pytest.importorskip("mpmath")

LIB = ctypes.CDLL(hybrid.__file__)
BOUND = math.pi / 4
_P = ctypes.c_void_p


def _sincos(x):
    check = LIB.wk_sincos_check
    check.argtypes = [_P, _P, _P, ctypes.c_int64]
    check.restype = None
    x = np.ascontiguousarray(x, dtype=np.float64)
    s, c = np.empty_like(x), np.empty_like(x)
    check(x.ctypes.data, s.ctypes.data, c.ctypes.data, x.size)
    return s, c


def _ulp_errors(values, fun, x):
    """|value - fun(x)| in ulps of the exact value, fun evaluated by mpmath at 120 bits."""
    out = np.empty(len(x))
    with mpmath.workprec(120):
        for i, (v, xi) in enumerate(zip(values, x, strict=True)):
            exact = fun(mpmath.mpf(float(xi)))
            unit = math.ulp(float(exact)) if exact != 0 else math.ulp(0.0)
            out[i] = abs(float((mpmath.mpf(float(v)) - exact) / unit))
    return out


def test_sincos_within_one_ulp_of_mpmath_up_to_pi_over_4():
    """Within 1 ulp of the exact sine and cosine (mpmath, 120 bits) over |x| <= pi/4, the
    range of every walking gait's angles: uniform samples, tiny arguments and arguments at
    the bound."""
    rng = np.random.default_rng(30)
    x = np.concatenate(
        [
            rng.uniform(-BOUND, BOUND, 6000),
            rng.uniform(-1e-3, 1e-3, 500),
            BOUND - rng.uniform(0.0, 1e-3, 500),
            -BOUND + rng.uniform(0.0, 1e-3, 500),
            [0.0, -0.0, 5e-324, 1e-300, 1e-8, np.nextafter(BOUND, 0.0)],
        ]
    )
    s, c = _sincos(x)
    assert _ulp_errors(s, mpmath.sin, x).max() <= 1.0
    assert _ulp_errors(c, mpmath.cos, x).max() <= 1.0


def test_sincos_symmetric_and_exact_at_zero():
    """sin is odd and cos even exactly, sin(0) = 0 and cos(0) = 1."""
    x = np.random.default_rng(1).uniform(0.0, 2.0, 2000)
    s, c = _sincos(x)
    sm, cm = _sincos(-x)
    np.testing.assert_array_equal(sm, -s)
    np.testing.assert_array_equal(cm, c)
    s0, c0 = _sincos(np.array([0.0]))
    assert s0[0] == 0.0 and c0[0] == 1.0


def test_sincos_beyond_the_bound_is_libm():
    """Beyond pi/4, and for infinities and NaN, libm's sin and cos (Python's math module
    calls them) bit for bit."""
    x = np.concatenate(
        [np.random.default_rng(2).uniform(BOUND, 50.0, 2000), [np.nextafter(BOUND, 1.0)]]
    )
    x = np.concatenate([x, -x])
    s, c = _sincos(x)
    np.testing.assert_array_equal(s, [math.sin(v) for v in x])
    np.testing.assert_array_equal(c, [math.cos(v) for v in x])
    s, c = _sincos(np.array([np.inf, -np.inf, np.nan]))
    assert np.isnan(s).all() and np.isnan(c).all()


# (module, kernel, n_q, output length) of every hoisted twin
HOISTED = [
    ("compass_plain", "accel", 2, 2),
    ("compass_plain", "accel_jac", 2, 8),
    ("compass_plain", "accel_and_jac", 2, 10),
    ("kneed_plain", "unlocked_accel", 3, 3),
    ("kneed_plain", "unlocked_accel_jac", 3, 18),
    ("kneed_plain", "unlocked_accel_and_jac", 3, 21),
    ("kneed_plain", "locked_accel", 2, 2),
    ("kneed_plain", "locked_accel_jac", 2, 8),
    ("kneed_plain", "locked_accel_and_jac", 2, 10),
]


@pytest.mark.parametrize(("module", "kernel", "n_q", "n_out"), HOISTED)
def test_hoisted_kernels_equal_their_kernels_bit_for_bit(module, kernel, n_q, n_out):
    """A hoisted twin, with p extended by its module's constants, returns its kernel's
    numbers bit for bit, at random parameters and states."""
    constants = getattr(LIB, f"wk_{module}_constants")
    plain = getattr(LIB, f"wk_{module}_{kernel}")
    twin = getattr(LIB, f"wk_{module}_{kernel}_hoisted")
    constants.argtypes = [_P, _P]
    plain.argtypes = twin.argtypes = [_P, _P, _P, _P]
    constants.restype = plain.restype = twin.restype = None
    n_p, slope = (10, 6) if module == "compass_plain" else (17, 12)  # indices.h
    rng = np.random.default_rng(6)
    for _ in range(50):
        p = rng.uniform(0.05, 2.0, n_p)
        p[slope] = rng.uniform(0.0, 0.3)  # [rad]
        p_ext = np.zeros(96)
        p_ext[:n_p] = p
        constants(p.ctypes.data, p_ext[n_p:].ctypes.data)
        q = rng.uniform(-1.2, 1.2, n_q)
        qd = rng.uniform(-3.0, 3.0, n_q)
        a, b = np.empty(n_out), np.empty(n_out)
        plain(q.ctypes.data, qd.ctypes.data, p.ctypes.data, a.ctypes.data)
        twin(q.ctypes.data, qd.ctypes.data, p_ext.ctypes.data, b.ctypes.data)
        np.testing.assert_array_equal(b, a)
