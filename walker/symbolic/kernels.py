"""Which kernels each generated module holds: the one list shared by the generator script
and the staleness test (which re-derives them and compares by numbers).

Every module in :data:`C_MODULES` is printed in C (``walker/_generated/<name>.c``/``.h``),
with its structural variants (:data:`C_VARIANTS`, see :func:`variant_kernels`)."""

from __future__ import annotations

from dataclasses import replace

import sympy as sp

from walker.models import compass as compass_model
from walker.models import kneed as kneed_model
from walker.symbolic import models
from walker.symbolic.codegen import (
    VARIANT_SOLVE,
    AccelAndJacobianKernel,
    AccelJacobianKernel,
    AccelKernel,
    Kernel,
)
from walker.symbolic.dynamics import dynamics_kernels, hip_jacobian
from walker.symbolic.mechanics import LagrangianModel

__all__ = [
    "C_MODULES",
    "C_VARIANTS",
    "GENERATED_MODULES",
    "VARIANT_KERNELS",
    "VARIANT_SIMPLIFICATION",
    "VARIANT_SOLVE_DOCS",
    "fused_name",
    "is_variant_kernel",
    "kernels_for",
    "variant_kernels",
]


def _extended_kernels(m: LagrangianModel, prefix: str, swing_index: int) -> list[Kernel]:
    """Floating-base model: mass matrix and material contact-velocity Jacobians."""
    slope = m.params[models.MODEL_PARAMS[_model_of(m)].index("slope")]
    R = m.params[models.MODEL_PARAMS[_model_of(m)].index("foot_radius")]
    q, p = ("q", m.q), ("p", m.params)
    J_sw = models.contact_velocity_jacobian(m, "swing_center", swing_index, R, slope)
    J_st = models.contact_velocity_jacobian(m, "stance_center", 0, R, slope)
    return [
        Kernel(f"{prefix}mass_matrix", (q, p), m.D, "Floating-base mass matrix, out (n_f, n_f)."),
        Kernel(
            f"{prefix}swing_contact_jac",
            (q, p),
            J_sw,
            "Jacobian of the swing foot's material contact velocity, out (2, n_f).",
        ),
        Kernel(
            f"{prefix}stance_contact_jac",
            (q, p),
            J_st,
            "Jacobian of the stance foot's material contact velocity, out (2, n_f).",
        ),
    ]


def _model_of(m: LagrangianModel) -> str:
    return m.name.split("_")[0]


def _simplest_kernels() -> list[Kernel]:
    s = models.simplest()
    q, qd, p = ("q", s["q"]), ("qd", s["qd"]), ("p", s["params"])
    x = sp.Matrix(list(s["q"]) + list(s["qd"]))
    return [
        Kernel("accel", (q, qd, p), s["qdd"], "(theta_ddot, phi_ddot), out (2,)."),
        Kernel("daccel_dx", (q, qd, p), s["qdd"].jacobian(x), "d accel / d x, out (2, 4)."),
    ]


def kernels_for(name: str) -> list[Kernel]:
    """The kernels of generated module ``name`` (a key of :data:`GENERATED_MODULES`)."""
    if name == "simplest":
        return _simplest_kernels()
    if name == "compass":
        sw = models.compass()
        return (
            dynamics_kernels(sw, "")
            + [hip_jacobian(sw, "")]
            + _extended_kernels(models.compass_extended(), "ext_", 1)
        )
    if name == "kneed":
        un, lo = models.kneed_unlocked(), models.kneed_locked()
        return (
            dynamics_kernels(un, "unlocked_")
            + dynamics_kernels(lo, "locked_")
            + [hip_jacobian(lo, "locked_")]
            + _extended_kernels(models.kneed_extended(), "ext_", 1)
        )
    if name == "double_pendulum":
        return dynamics_kernels(models.double_pendulum(), "")
    if name == "three_link":
        from walker.symbolic import actuated

        return actuated.three_link_kernels()
    if name == "five_link":
        from walker.symbolic import five_link

        return five_link.five_link_kernels()
    raise ValueError(f"unknown generated module `{name}`; valid: {sorted(GENERATED_MODULES)}")


GENERATED_MODULES = {
    "simplest": "Garcia's simplest walker (limit of the point-mass compass gait).",
    "compass": "Compass gait: single-support dynamics and the floating-base heel-strike model.",
    "kneed": "Kneed walker: knee-free (3-DOF) and knee-locked (2-DOF) swing, floating base.",
    "double_pendulum": "The planar double pendulum (elbow-manipulator coordinates).",
    "three_link": (
        "Grizzle's three-link walker (legs and torso, hip actuators): pinned dynamics, ground "
        "reaction, floating-base heel-strike model."
    ),
    "five_link": (
        "Five-link walker (torso, femurs, tibias; hip and knee actuators; RABBIT-like): pinned "
        "dynamics, ground reaction, floating-base heel-strike model."
    ),
}


C_MODULES = tuple(GENERATED_MODULES)
"""Modules also printed in C (``walker/_generated/<name>.c``/``.h``), compiled into
``walker._hybrid``."""

C_VARIANTS = {"compass": compass_model.VARIANTS, "kneed": kneed_model.VARIANTS}
"""Structural variants printed in C as ``<name>_<variant>`` (functions
``wk_<name>_<variant>_<kernel>``, registry names ``"<name>/<variant>.<kernel>"``): the listed
parameters are exactly 0: the sets ``VARIANTS`` of walker.models.<name>, read from there (the
run-time model picks a variant by them)."""

VARIANT_KERNELS = (
    "accel",
    "accel_jac",
    "mass_matrix",
    "points",
    "hip_jac",
    "swing_contact_jac",
    "stance_contact_jac",
)
"""Kernels a structural variant keeps, by name without the ``unlocked_``/``locked_``/
``ext_`` prefix: the dynamics and what the impact maps read."""


def is_variant_kernel(name: str) -> bool:
    """Whether a structural variant keeps kernel ``name`` (see :data:`VARIANT_KERNELS`)."""
    for prefix in ("unlocked_", "locked_", "ext_"):
        if name.startswith(prefix):
            name = name[len(prefix) :]
            break
    return name in VARIANT_KERNELS


def fused_name(name: str) -> str:
    """Name of the fused kernel a structural variant prints beside its ``accel_jac`` kernel
    ``name`` (``unlocked_accel_jac`` -> ``unlocked_accel_and_jac``; see
    :func:`variant_kernels`)."""
    if not name.endswith("accel_jac"):
        raise ValueError(f"`name` must name an accel_jac kernel, got {name!r}")
    return name[: -len("accel_jac")] + "accel_and_jac"


VARIANT_SIMPLIFICATION = "trigsimp; polynomial in sin/cos and qd with factored coefficients"
"""How :func:`variant_kernels` simplifies (part of a variant's input hash)."""


VARIANT_SOLVE_DOCS = {
    AccelKernel: (
        "Accelerations qdd = -D^-1 h (h including any forcing) as -adj(D) h / det(D), "
        "cofactors and one division, out (>= n,)."
    ),
    AccelJacobianKernel: (
        "d qdd / d (q, qd), out (n, 2n), fused with the solve: D^-1 = adj(D) / det(D) "
        "(one division) applied to every column."
    ),
    AccelAndJacobianKernel: (
        "accel_jac and the accelerations in one call, out (n, 2n+1): columns 0..2n-1 "
        "d qdd / d (q, qd), bit for bit those of accel_jac (the same lowering), column 2n "
        "qdd = -D^-1 h as the Jacobian's solve computes it (accel's to round-off)."
    ),
}
"""Docs of a structural variant's fused kernels, which solve as :data:`VARIANT_SOLVE` says
(the general kernels' docs name their Cholesky solve)."""


def _compact(e, rates):
    """``e`` with ``sin^2 + cos^2 = 1`` and the like applied (``sympy.trigsimp``), then
    written as a polynomial in its sines, cosines and the rates ``rates``, whose
    coefficients (functions of the parameters only) are factored."""
    e = sp.trigsimp(sp.sympify(e))
    gens = sorted(e.atoms(sp.sin, sp.cos), key=sp.default_sort_key)
    gens += [s for s in rates if s in e.free_symbols]
    if not gens:
        return sp.factor(e)
    try:
        poly = sp.Poly(e, *gens)
    except sp.PolynomialError:
        return e
    return sp.Add(
        *(
            sp.factor(c) * sp.Mul(*(g**k for g, k in zip(gens, m, strict=True)))
            for m, c in poly.terms()
        )
    )


def variant_kernels(name: str, variant: str, kernels=None, *, simplify: bool = True) -> list:
    """The kernels of structural variant ``variant`` of module ``name``: those of
    :data:`VARIANT_KERNELS` from ``kernels`` (default :func:`kernels_for`), with the
    variant's parameters replaced by exact zeros (before any differentiation or cse, so
    they contribute no arithmetic) and, with ``simplify``, every entry (of ``D`` and ``h``
    for the fused kernels, before differentiation) simplified by :func:`_compact`.  The
    fused kernels solve in closed form (:data:`walker.symbolic.codegen.VARIANT_SOLVE`, one
    division; their docs :data:`VARIANT_SOLVE_DOCS`).  Each ``accel_jac`` kernel is
    followed by an :class:`~walker.symbolic.codegen.AccelAndJacobianKernel` of the same
    ``D`` and ``h``, named :func:`fused_name` (the integrator's rhs and Jacobian in one
    call).  Arguments are unchanged: the full parameter vector, whose
    zeroed entries are never read."""
    zeros = set(C_VARIANTS[name][variant])
    kernels = kernels_for(name) if kernels is None else kernels
    out = []
    for k in kernels:
        if not is_variant_kernel(k.name):
            continue
        args = dict(k.args)
        sub = {s: sp.S.Zero for s in args["p"] if str(s) in zeros}
        rates = args.get("qd", ())

        def f(e, sub=sub, rates=rates):
            e = sp.sympify(e).xreplace(sub)
            return _compact(e, rates) if simplify else e

        if isinstance(k, (AccelKernel, AccelJacobianKernel)):
            v = replace(
                k,
                D=k.D.applyfunc(f),
                h=k.h.applyfunc(f),
                doc=VARIANT_SOLVE_DOCS[type(k)],
                solve=VARIANT_SOLVE,
            )
            out.append(v)
            if isinstance(k, AccelJacobianKernel):
                out.append(
                    AccelAndJacobianKernel(
                        name=fused_name(k.name),
                        args=v.args,
                        D=v.D,
                        h=v.h,
                        doc=VARIANT_SOLVE_DOCS[AccelAndJacobianKernel],
                        solve=v.solve,
                    )
                )
        elif isinstance(k.expr, (list, tuple)):
            out.append(replace(k, expr=[m.applyfunc(f) for m in k.expr]))
        elif isinstance(k.expr, sp.MatrixBase):
            out.append(replace(k, expr=k.expr.applyfunc(f)))
        else:
            out.append(replace(k, expr=f(k.expr)))
    return out
