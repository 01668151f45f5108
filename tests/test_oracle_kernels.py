"""Every generated C kernel the extension lists (``walker._hybrid.kernels()``: name ->
(signature, address)) against the lambdified expression of the symbolic model it was printed
from (:mod:`walker.symbolic.models`, :mod:`walker.symbolic.actuated`,
:mod:`walker.symbolic.five_link`), at 20 random arguments.

The expressions are taken from the Lagrangian models directly: ``mass_matrix`` is ``D``,
``coriolis`` ``C``, ``gravity`` ``g``, ``bias`` ``C qd + g``, ``forcing`` ``Q``, ``dmass``
``dD/dq_k``, ``dbias_dq(d)`` the Jacobians of ``C qd + g``, ``kinetic``/``potential`` the
energies, ``points`` the named points, ``hip_jac`` the hip's Jacobian, the floating-base
``ext_*`` kernels its mass matrix and the feet's contact Jacobians (the material velocity of
a round foot's contact, ``v_centre + omega R s``), ``ground_reaction`` the rate of the total
momentum plus the weight; ``accel`` and ``accel_jac`` (and a variant's fused
``accel_and_jac``, its Jacobian then its accelerations) are the oracle's
``numpy.linalg.solve`` of ``D qdd = -(h - Q)`` (``tests/oracle.py``).  A structural variant
("compass/plain", ...) is sampled with its zeroed parameters at 0.

Tolerance ``KERNEL_RTOL`` relative to the largest entry (or 1).  The five-link kernels are in
the slow tier (their derivation and lambdification take about 4 s).
"""

from __future__ import annotations

import ctypes
import functools

import numpy as np
import oracle as O
import pytest
import sympy as sp
from test_oracle import KERNEL_RTOL, Worst

from walker import _hybrid
from walker.symbolic import actuated, five_link
from walker.symbolic import models as sym
from walker.symbolic.kernels import C_VARIANTS

_P = ctypes.POINTER(ctypes.c_double)
_CTYPES = {
    "qqdp_v": ctypes.CFUNCTYPE(None, _P, _P, _P, _P),
    "qp_v": ctypes.CFUNCTYPE(None, _P, _P, _P),
    "qqdp_s": ctypes.CFUNCTYPE(ctypes.c_double, _P, _P, _P),
    "qp_s": ctypes.CFUNCTYPE(ctypes.c_double, _P, _P),
    "qqdqddp_v": ctypes.CFUNCTYPE(None, _P, _P, _P, _P, _P),
}


def _round_foot_jac(ext, centre, angle):
    """The material velocity Jacobian of a round foot's contact (walker.symbolic.models)."""
    by_name = {str(s): s for s in ext.params}
    R, slope = by_name["foot_radius"], by_name["slope"]
    J = ext.point_jacobian(centre)
    J[:, angle] += R * sp.Matrix([sp.cos(slope), -sp.sin(slope)])
    return J


@functools.cache
def _models(model):
    """``{kernel prefix: (kind, LagrangianModel)}`` of a generated module."""
    if model == "compass":
        return {"": ("pinned", sym.compass()), "ext_": ("round", sym.compass_extended())}
    if model == "kneed":
        return {
            "unlocked_": ("pinned", sym.kneed_unlocked()),
            "locked_": ("pinned", sym.kneed_locked()),
            "ext_": ("round", sym.kneed_extended()),
        }
    if model == "double_pendulum":
        return {"": ("pinned", sym.double_pendulum())}
    if model == "three_link":
        return {
            "": ("pinned", actuated.three_link()),
            "ext_": ("point", actuated.three_link_extended()),
        }
    if model == "five_link":
        return {
            "": ("pinned", five_link.five_link()),
            "ext_": ("point", five_link.five_link_extended()),
        }
    raise ValueError(model)


def _momentum_rate_plus_weight(m, qdd):
    q, qd = sp.Matrix(m.q), sp.Matrix(m.qd)
    momentum = sp.zeros(2, 1)
    for body in m.bodies:
        momentum += body.mass * body.position.jacobian(q) * qd
    g = m.params[[str(s) for s in m.params].index("g")]
    weight = sp.Matrix([0, sum(b.mass for b in m.bodies) * g])
    return momentum.jacobian(q) * qd + momentum.jacobian(qd) * sp.Matrix(qdd) + weight


@functools.cache
def oracle_kernel(model, kernel):
    """``f(*args) -> ndarray``: the oracle of kernel ``kernel`` of module ``model``."""
    if model == "simplest":
        d = sym.simplest()
        q, qd, p = list(d["q"]), list(d["qd"]), list(d["params"])
        expr = d["qdd"] if kernel == "accel" else d["qdd"].jacobian(q + qd)
        return O._fn([q, qd, p], expr)
    prefix = next(k for k in sorted(_models(model), key=len, reverse=True) if kernel.startswith(k))
    kind, m = _models(model)[prefix]
    name = kernel[len(prefix) :]
    q, qd, p = list(m.q), list(m.qd), list(m.params)
    if name in ("accel", "accel_jac", "accel_and_jac"):
        lag = O.Lagrangian(m)
        if name == "accel":
            return lag.accel
        if name == "accel_jac":
            return lag.accel_jac
        return lambda *a: np.column_stack([lag.accel_jac(*a), lag.accel(*a)])
    if kind != "pinned":  # floating base
        contact = {
            "mass_matrix": m.D,
            "swing_contact_jac": m.point_jacobian("swing_contact"),
            "stance_contact_jac": m.point_jacobian("stance_contact"),
        }
        if kind == "round":
            contact["swing_contact_jac"] = _round_foot_jac(m, "swing_center", 1)
            contact["stance_contact_jac"] = _round_foot_jac(m, "stance_center", 0)
        return O._fn([q, p], contact[name])
    if name == "ground_reaction":
        qdd = list(sp.symbols(f"a0:{m.n}", real=True))
        return O._fn([q, qd, qdd, p], _momentum_rate_plus_weight(m, qdd))
    h = m.C * sp.Matrix(qd) + m.G
    with_rates = {
        "coriolis": m.C,
        "bias": h,
        "forcing": m.forcing,
        "dbias_dq": h.jacobian(q),
        "dbias_dqd": h.jacobian(qd),
        "kinetic": m.K,
    }
    if name in with_rates:
        return O._fn([q, qd, p], with_rates[name])
    without = {
        "mass_matrix": lambda: m.D,
        "gravity": lambda: m.G,
        "potential": lambda: m.P,
        "points": lambda: sp.Matrix([[v[0], v[1]] for v in m.points.values()]),
        "hip_jac": lambda: m.point_jacobian("hip"),
    }
    if name == "dmass":
        fns = [O._fn([q, p], m.D.diff(v)) for v in q]
        return lambda *a: np.array([f(*a) for f in fns])
    return O._fn([q, p], without[name]())


def _arguments(model, kernel, sig, rng, zeros):
    """Random (q, [qd, [qdd]], p): angles and rates in (-pi, pi), parameters near 1 (the
    structural variant's ``zeros`` at 0), the slope in (-0.2, 0.2)."""
    if model == "simplest":
        names, n = sym.MODEL_PARAMS["simplest"], 2
    else:
        prefix = next(
            k for k in sorted(_models(model), key=len, reverse=True) if kernel.startswith(k)
        )
        m = _models(model)[prefix][1]
        names, n = [str(s) for s in m.params], m.n
    p = rng.uniform(0.3, 1.5, len(names))
    for i, name in enumerate(names):
        if name == "slope":
            p[i] = rng.uniform(-0.2, 0.2)
        elif name.startswith(("offset", "damping")):
            p[i] = rng.uniform(-0.05, 0.05) if name.startswith("offset") else rng.uniform(0, 1)
        if name in zeros:
            p[i] = 0.0
    q = rng.uniform(-np.pi, np.pi, n)
    args = [q]
    if sig.startswith("qqd"):
        args.append(rng.uniform(-np.pi, np.pi, n))
    if sig.startswith("qqdqdd"):
        args.append(rng.uniform(-np.pi, np.pi, n))
    return [np.ascontiguousarray(a) for a in args], np.ascontiguousarray(p)


def _registry():
    return _hybrid.kernels()


def _params():
    out = []
    for name in sorted(_registry()):
        model = name.split(".")[0].split("/")[0]
        marks = [pytest.mark.slow] if model == "five_link" else []
        out.append(pytest.param(name, marks=marks, id=name))
    return out


@pytest.mark.parametrize("registry_name", _params())
def test_c_kernel_agrees_with_symbolic_model(registry_name):
    sig, address = _registry()[registry_name][:2]  # (signature, address, lengths...)
    module, kernel = registry_name.split(".")
    model, _, variant = module.partition("/")
    zeros = set(C_VARIANTS.get(model, {}).get(variant, ())) if variant else set()
    fn = oracle_kernel(model, kernel)
    c_fun = _CTYPES[sig](address)
    rng = np.random.default_rng(sum(map(ord, registry_name)))
    worst = Worst(registry_name)
    for _ in range(20):
        args, p = _arguments(model, kernel, sig, rng, zeros)
        ref = np.asarray(fn(*args, p), dtype=float)
        ptrs = [a.ctypes.data_as(_P) for a in (*args, p)]
        if sig.endswith("_s"):
            got = np.float64(c_fun(*ptrs))
        else:
            got = np.full(ref.shape, np.nan)
            c_fun(*ptrs, got.ctypes.data_as(_P))
        worst.check(
            "value", got, ref, KERNEL_RTOL, f"args {[a.tolist() for a in args]} p {p.tolist()}"
        )
    worst.report()
