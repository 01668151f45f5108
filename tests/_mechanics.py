"""Test helpers: angular momenta of the symbolic walkers' bodies, evaluated numerically."""

import numpy as np
import sympy as sp


def body_functions(model):
    """For each body: (name, mass(p), pos(q, p) -> (2,), jac(q, p) -> (2, n), dangle (n,),
    inertia(p)), lambdified from a LagrangianModel."""
    q = sp.Matrix(model.q)
    out = []
    for b in model.bodies:
        pos = sp.lambdify((model.q, model.params), b.position, "numpy")
        jac = sp.lambdify((model.q, model.params), b.position.jacobian(q), "numpy")
        if b.angle is None:
            dang = [0] * len(model.q)
        else:
            dang = [sp.diff(b.angle, qi) for qi in model.q]
        dang_f = sp.lambdify((model.q, model.params), sp.Matrix([dang]), "numpy")
        mass = sp.lambdify((model.params,), b.mass, "numpy")
        inertia = sp.lambdify((model.params,), b.inertia, "numpy")
        out.append((b.name, mass, pos, jac, dang_f, inertia))
    return out


def angular_momentum(bodies, q, qd, p, about, names=None):
    """Angular momentum (z) about the point ``about`` of the named bodies (all if None)."""
    total = 0.0
    for name, mass, pos, jac, dang, inertia in bodies:
        if names is not None and name not in names:
            continue
        r = np.asarray(pos(q, p), dtype=float).ravel() - about
        v = np.asarray(jac(q, p), dtype=float) @ qd
        w = float((np.asarray(dang(q, p), dtype=float) @ qd).ravel()[0])
        m = float(mass(p))
        total += m * (r[0] * v[1] - r[1] * v[0]) + float(inertia(p)) * w
    return total


def point(model, name, q, p):
    f = sp.lambdify((model.q, model.params), model.points[name], "numpy")
    return np.asarray(f(q, p), dtype=float).ravel()
