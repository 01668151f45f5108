"""Recursive Newton–Euler inverse dynamics of a planar serial chain (numeric, numpy only).

An independent check on the Lagrangian derivation in :mod:`walker.symbolic.mechanics`: the
joint torques of a prescribed motion computed link by link, with no energy and no
differentiation, must equal ``D(q) q_ddot + C(q, q_dot) q_dot + g(q)``.

The recursion is the textbook one (Spong, Hutchinson, Vidyasagar, *Robot Modeling and Control*,
section 7.5 [1]_):

Forward pass, ``i = 1 .. n``, every vector expressed in frame ``i`` and 3-D (``z`` out of the
plane), ``R_i = R_i^{i-1}`` the rotation from frame ``i`` to frame ``i - 1``, ``b_i = z``::

    omega_i = R_i^T omega_{i-1} + b_i q_dot_i
    alpha_i = R_i^T alpha_{i-1} + b_i q_ddot_i + omega_i x b_i q_dot_i
    a_c,i   = R_i^T a_e,{i-1} + alpha_i x r_{i,ci} + omega_i x (omega_i x r_{i,ci})
    a_e,i   = R_i^T a_e,{i-1} + alpha_i x r_{i,i+1} + omega_i x (omega_i x r_{i,i+1})

(some lecture notes print ``a_c,{i-1}`` in the ``a_c,i`` line; the book, and the physics, use
the acceleration of the *end* of link ``i - 1``, which is where joint ``i`` sits).

Backward pass, ``i = n .. 1``, with ``f_{n+1} = tau_{n+1} = 0`` and ``R_{i+1}`` from frame
``i + 1`` to frame ``i``::

    f_i   = R_{i+1} f_{i+1} + m_i a_c,i - m_i g_i
    tau_i = R_{i+1} tau_{i+1} - f_i x r_{i,ci} + (R_{i+1} f_{i+1}) x r_{i+1,ci}
            + I_i alpha_i + omega_i x (I_i omega_i)

and the joint torque is the ``z`` component of ``tau_i``.

Gravity enters by the base-acceleration trick (Craig [2]_: "set the
acceleration of the base to ``-G``"): ``a_e,0 = -gravity`` and the ``- m_i g_i`` term is
dropped, so every ``a_c,i`` below is the centre-of-mass acceleration *minus* gravity.

References
----------
.. [1] M. W. Spong, S. Hutchinson, M. Vidyasagar, *Robot Modeling and Control*, Wiley 2006,
   section 7.5 "Newton–Euler formulation" (the planar elbow example of section 7.5.1).
.. [2] J. J. Craig, *Introduction to Robotics*, 3rd ed., section 6.5, "Inclusion of gravity
   forces in the dynamics algorithm".

Examples
--------
A single uniform rod of mass 2 kg and length 1 m hanging from the origin, held horizontal
(``q = 0`` along ``+x``) and at rest, needs ``m g L / 2`` of joint torque:

>>> import numpy as np
>>> chain = PlanarChain(lengths=[1.0], coms=[[0.5, 0.0]], masses=[2.0], inertias=[1 / 6])
>>> inverse_dynamics(chain, [0.0], [0.0], [0.0], gravity=(0.0, -9.81))
array([9.81])
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["PlanarChain", "inverse_dynamics", "mass_matrix", "bias_forces"]

_Z = np.array([0.0, 0.0, 1.0])


def _rot_z(angle: float) -> np.ndarray:
    """Rotation matrix about ``z`` by ``angle`` [rad], shape (3, 3)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@dataclass(frozen=True)
class PlanarChain:
    """A planar serial chain of rigid links joined by revolute joints about ``z``.

    Joint 1 sits at the origin of the world frame (frame 0) and turns link 1; joint ``i + 1``
    sits at the end of link ``i``, ``lengths[i]`` along the link's ``x`` axis.  The joint
    angle ``q_i`` is *relative*: the angle from the ``x`` axis of frame ``i - 1`` to that of
    frame ``i`` (for ``i = 1`` from the world ``x`` axis), counterclockwise positive.

    Parameters
    ----------
    lengths : array_like, shape (n,)
        distance from joint ``i`` to joint ``i + 1`` along link ``i``'s ``x`` axis [m], >= 0
        (the last link's length only places its end point).
    coms : array_like, shape (n, 2)
        centre of mass of each link in its own frame (origin at its joint) [m].
    masses : array_like, shape (n,)
        [kg], > 0.
    inertias : array_like, shape (n,)
        moment of inertia about the centre of mass, about ``z`` [kg m^2], >= 0.

    Raises
    ------
    ValueError
        naming the field, for wrong shapes, non-finite entries or out-of-range values.
    """

    lengths: np.ndarray
    coms: np.ndarray
    masses: np.ndarray
    inertias: np.ndarray

    def __post_init__(self):
        lengths = np.array(self.lengths, dtype=float, ndmin=1)
        if lengths.ndim != 1 or lengths.size == 0:
            raise ValueError(f"`lengths` must have shape (n,) with n >= 1, got {lengths.shape}")
        n = lengths.size
        coms = np.array(self.coms, dtype=float)
        masses = np.array(self.masses, dtype=float, ndmin=1)
        inertias = np.array(self.inertias, dtype=float, ndmin=1)
        for name, arr, shape in (
            ("coms", coms, (n, 2)),
            ("masses", masses, (n,)),
            ("inertias", inertias, (n,)),
        ):
            if arr.shape != shape:
                raise ValueError(f"`{name}` must have shape {shape}, got {arr.shape}")
        arrays = {"lengths": lengths, "coms": coms, "masses": masses, "inertias": inertias}
        for name, arr in arrays.items():
            if not np.all(np.isfinite(arr)):
                raise ValueError(f"all entries of `{name}` must be finite")
        if np.any(lengths < 0):
            raise ValueError(f"`lengths` must be >= 0 [m], got {lengths.tolist()}")
        if np.any(masses <= 0):
            raise ValueError(f"`masses` must be > 0 [kg], got {masses.tolist()}")
        if np.any(inertias < 0):
            raise ValueError(f"`inertias` must be >= 0 [kg m^2], got {inertias.tolist()}")
        for name, arr in arrays.items():
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    @property
    def n_links(self) -> int:
        """Number of links (= joints)."""
        return self.lengths.size


def _vector(name: str, value, n: int) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.shape != (n,):
        raise ValueError(f"`{name}` must have shape ({n},), got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"all entries of `{name}` must be finite")
    return arr


def inverse_dynamics(chain: PlanarChain, q, qd, qdd, *, gravity) -> np.ndarray:
    """Joint torques that produce the motion ``(q, qd, qdd)``, by recursive Newton–Euler.

    Parameters
    ----------
    chain : PlanarChain
    q : array_like, shape (n,)
        relative joint angles [rad].
    qd : array_like, shape (n,)
        joint rates [rad/s].
    qdd : array_like, shape (n,)
        joint accelerations [rad/s^2].
    gravity : array_like, shape (2,)
        gravitational acceleration in the world frame [m/s^2], e.g. ``(0, -9.81)``; no
        default, a physical quantity.

    Returns
    -------
    ndarray, shape (n,)
        torque exerted by link ``i - 1`` on link ``i`` about joint ``i`` [N m]; equal to
        ``D(q) qdd + C(q, qd) qd + g(q)`` of the chain's Lagrangian model.

    Notes
    -----
    Gravity enters through the base acceleration, ``a_e,0 = -gravity`` (module docstring).
    """
    if not isinstance(chain, PlanarChain):
        raise TypeError(f"`chain` must be a PlanarChain, got {type(chain).__name__}")
    n = chain.n_links
    q = _vector("q", q, n)
    qd = _vector("qd", qd, n)
    qdd = _vector("qdd", qdd, n)
    grav = _vector("gravity", gravity, 2)

    rotations = [_rot_z(angle) for angle in q]  # R_i^{i-1}
    r_joint = [np.array([L, 0.0, 0.0]) for L in chain.lengths]  # r_{i,i+1}
    r_com = [np.array([c[0], c[1], 0.0]) for c in chain.coms]  # r_{i,ci}
    inertia = [np.diag([0.0, 0.0, i_zz]) for i_zz in chain.inertias]  # planar: only I_zz acts

    # Forward pass (base: at rest, accelerating "upward" by -gravity).
    omega_prev = np.zeros(3)
    alpha_prev = np.zeros(3)
    a_end_prev = np.array([-grav[0], -grav[1], 0.0])
    omega, alpha, a_com = [], [], []
    for i in range(n):
        Rt = rotations[i].T
        w = Rt @ omega_prev + _Z * qd[i]
        al = Rt @ alpha_prev + _Z * qdd[i] + np.cross(w, _Z * qd[i])
        base = Rt @ a_end_prev
        ac = base + np.cross(al, r_com[i]) + np.cross(w, np.cross(w, r_com[i]))
        ae = base + np.cross(al, r_joint[i]) + np.cross(w, np.cross(w, r_joint[i]))
        omega.append(w)
        alpha.append(al)
        a_com.append(ac)
        omega_prev, alpha_prev, a_end_prev = w, al, ae

    # Backward pass.
    f_next = np.zeros(3)  # f_{i+1}, in frame i+1
    tau_next = np.zeros(3)
    tau = np.empty(n)
    for i in range(n - 1, -1, -1):
        R_next = rotations[i + 1] if i + 1 < n else np.eye(3)  # R_{i+1}^i
        f_child = R_next @ f_next
        f_i = f_child + chain.masses[i] * a_com[i]
        r_next_com = r_com[i] - r_joint[i]  # r_{i+1,ci}: from joint i+1 to the CoM
        tau_i = (
            R_next @ tau_next
            - np.cross(f_i, r_com[i])
            + np.cross(f_child, r_next_com)
            + inertia[i] @ alpha[i]
            + np.cross(omega[i], inertia[i] @ omega[i])
        )
        tau[i] = tau_i[2]
        f_next, tau_next = f_i, tau_i
    return tau


def bias_forces(chain: PlanarChain, q, qd, *, gravity) -> np.ndarray:
    """``h(q, qd) = C(q, qd) qd + g(q)``: the inverse dynamics at zero acceleration.

    Parameters
    ----------
    chain : PlanarChain
    q, qd : array_like, shape (n,)
        relative joint angles [rad] and rates [rad/s].
    gravity : array_like, shape (2,)
        [m/s^2], world frame.

    Returns
    -------
    ndarray, shape (n,)
        [N m].
    """
    n = chain.n_links
    return inverse_dynamics(chain, q, qd, np.zeros(n), gravity=gravity)


def mass_matrix(chain: PlanarChain, q) -> np.ndarray:
    """Mass matrix ``D(q)`` column by column: ``D e_j`` is the inverse dynamics at rest,
    without gravity, with unit acceleration of joint ``j`` (the usual numerical recipe).

    Parameters
    ----------
    chain : PlanarChain
    q : array_like, shape (n,)
        relative joint angles [rad].

    Returns
    -------
    ndarray, shape (n, n)
        [kg m^2].
    """
    n = chain.n_links
    zero = np.zeros(n)
    columns = [inverse_dynamics(chain, q, zero, np.eye(n)[j], gravity=(0.0, 0.0)) for j in range(n)]
    return np.column_stack(columns)
