"""The kernels every single-support model prints: accelerations (and their Jacobian), mass
matrix, Coriolis, gravity and bias terms, their derivatives, energies and points, and the hip
Jacobian.  Used by :mod:`walker.symbolic.kernels` (the passive models) and by
:mod:`walker.symbolic.actuated` and :mod:`walker.symbolic.five_link`, which import this
module rather than the registry so that no import cycle forms."""

from __future__ import annotations

import sympy as sp

from walker.symbolic.codegen import AccelJacobianKernel, AccelKernel, Kernel
from walker.symbolic.mechanics import LagrangianModel

__all__ = ["dynamics_kernels", "hip_jacobian"]


def dynamics_kernels(m: LagrangianModel, prefix: str) -> list[Kernel]:
    """Kernels of a single-support model.

    The accelerations include the model's own forcing ``Q`` (joint damping): ``accel`` and
    ``accel_jac`` solve ``D qdd = -(h - Q)``.  ``bias``, ``dbias_dq`` and ``dbias_dqd`` keep
    the conservative ``h = C qd + g``; a model with forcing also gets a ``forcing`` kernel.
    """
    q, qd, p = ("q", m.q), ("qd", m.qd), ("p", m.params)
    h = m.bias
    h_forced = m.forced_bias
    qv, qdv = sp.Matrix(m.q), sp.Matrix(m.qd)
    if m.has_forcing:
        accel_doc = (
            "Accelerations qdd = -D^-1 (h - Q), Q the joint-damping forcing, by unrolled "
            "Cholesky, out (>= n,)."
        )
        forcing = [
            Kernel(
                f"{prefix}forcing",
                (q, qd, p),
                m.forcing,
                "Generalized joint-damping forces Q(q, qd), out (n,); power Q.qd <= 0.",
            )
        ]
    else:
        accel_doc = "Accelerations qdd = -D^-1 h by unrolled Cholesky, out (>= n,)."
        forcing = []
    return [
        AccelKernel(f"{prefix}accel", (q, qd, p), m.D, h_forced, accel_doc),
        AccelJacobianKernel(
            f"{prefix}accel_jac",
            (q, qd, p),
            m.D,
            h_forced,
            "d qdd / d (q, qd), out (n, 2n), fused with the Cholesky solve.",
        ),
        Kernel(f"{prefix}mass_matrix", (q, p), m.D, "Mass matrix D(q), out (n, n)."),
        Kernel(f"{prefix}coriolis", (q, qd, p), m.C, "Coriolis matrix C(q, qd), out (n, n)."),
        Kernel(f"{prefix}gravity", (q, p), m.G, "Gravity vector g(q) = dP/dq, out (n,)."),
        Kernel(f"{prefix}bias", (q, qd, p), h, "h(q, qd) = C(q, qd) qd + g(q), out (n,)."),
        *forcing,
        Kernel(
            f"{prefix}dmass",
            (q, p),
            [m.D.diff(qi) for qi in m.q],
            "dD/dq_k for every k, out (n, n, n): out[k] = dD/dq_k.",
        ),
        Kernel(f"{prefix}dbias_dq", (q, qd, p), h.jacobian(qv), "dh/dq, out (n, n)."),
        Kernel(f"{prefix}dbias_dqd", (q, qd, p), h.jacobian(qdv), "dh/dqd, out (n, n)."),
        Kernel(f"{prefix}kinetic", (q, qd, p), m.K, "Kinetic energy [J]."),
        Kernel(f"{prefix}potential", (q, p), m.P, "Potential energy [J] (y = 0 at the origin)."),
        Kernel(
            f"{prefix}points",
            (q, p),
            sp.Matrix([[v[0], v[1]] for v in m.points.values()]),
            f"Named points in the world frame, out (n_points, 2); names in {prefix.upper()}POINTS.",
        ),
    ]


def hip_jacobian(m: LagrangianModel, prefix: str) -> Kernel:
    """The hip position's Jacobian kernel ``<prefix>hip_jac``."""
    return Kernel(
        f"{prefix}hip_jac",
        (("q", m.q), ("p", m.params)),
        m.point_jacobian("hip"),
        "Jacobian of the hip position, out (2, n).",
    )
