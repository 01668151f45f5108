"""The symbolic models walker ships, each a function returning :class:`LagrangianModel` s.

Conventions: world frame x forward, y up; the slope descends toward
+x at angle ``slope``; ``s = (cos slope, -sin slope)`` runs down the slope and
``n = (sin slope, cos slope)`` is its outward normal.  Walker angles are absolute, from the
vertical, counterclockwise positive; a leg at angle ``q`` points from foot to hip along
``u(q) = (-sin q, cos q)``, so just after heel strike the stance angle is positive.  Heel
strike on a point-foot walker happens at ``q_stance + q_swing = -2 slope``.

Round feet: each foot is an arc of radius ``R`` whose centre sits on the leg, ``R`` above the
foot's tip.  The stance foot rolls without slipping: with ``psi = q1 + slope`` the leg's angle
from the slope normal, the contact point is ``-R psi s`` and the arc centre ``-R psi s + R n``
(the stance contact is at the origin when ``psi = 0``).  ``R = 0`` gives point feet.

Joint damping: the passive walkers' joints may carry viscous dampers (the last entries of the
parameter vector; zero in every published set).  A damper of coefficient ``b`` acts on its
joint's relative rate ``w`` with equal and opposite torques ``-b w`` on the distal and
``+b w`` on the proximal link, as the model's ``forcing`` (Rayleigh dissipation
``R = 1/2 b w^2``, ``Q = -dR/dq_dot``):

* compass gait, ``damping_hip``: ``w = qd_swing - qd_stance``;
* kneed walker, ``damping_hip``: ``w = qd2 - qd1`` (swing thigh relative to the stance leg);
  ``damping_knee``: ``w = qd3 - qd2`` (swing shank relative to the swing thigh), which is
  identically zero once the knee is locked.  The stance knee is locked throughout, so it
  dissipates nothing;
* both, ``damping_ankle``: the stance "ankle" between the slope (proximal, not rotating) and
  the stance leg, ``w = qd_stance - 0`` (compass ``qd_stance``, kneed ``qd1``): a torque
  ``-b qd_stance`` on the stance leg, in every single-support phase.  A point foot cannot
  transmit a torque; the damper stands for a passive ankle with a foot flat on the slope, or
  for rolling resistance (the viscous term of ``D qdd + C qd + g = -F_v qd`` with ``F_v`` on the
  stance coordinate);
* the simplest walker, ``damping_ankle`` only (dimensionless, in units of
  ``M l^2 sqrt(g/l)``): its legs are massless, so a finite torque on the swing leg (a hip
  damper) has no limit; the stance-ankle damper acts on the stance leg carrying ``M`` and is
  derived with the limit (:func:`simplest`);
* the double pendulum, ``damping_1`` on ``w1 = qd1`` (ground to link 1) and
  ``damping_2`` on ``w2 = qd2`` (link 1 to link 2, ``q2`` being relative).  Its dry
  frictions ``coulomb_1``, ``coulomb_2`` are in the parameter vector but not in the smooth
  model: stick and slip are phases (:mod:`walker.models.double_pendulum`).

The floating-base (``*_extended``) models serve only the impulsive heel strike, where a
finite damping torque transmits no impulse; they carry no forcing (they read the parameter
vector by position up to ``g`` only, so the damping entries after it do not enter).
"""

from __future__ import annotations

from functools import cache

import sympy as sp

from walker.params import params_class
from walker.symbolic.mechanics import Body, LagrangianModel, derive, rayleigh_forcing

__all__ = [
    "simplest",
    "compass",
    "compass_extended",
    "kneed_unlocked",
    "kneed_locked",
    "kneed_extended",
    "double_pendulum",
    "planar_elbow",
    "MODEL_PARAMS",
]

# Parameter order of every model: the fields of its dataclass in walker.params, in order (the
# vector ``p`` the generated kernels take), read from there rather than written again.
MODEL_PARAMS = {
    name: params_class(name).names() for name in ("simplest", "compass", "kneed", "double_pendulum")
}


def param_symbols(model: str) -> tuple:
    """The parameter symbols of ``model`` in canonical order (all real)."""
    return tuple(sp.Symbol(name, real=True) for name in MODEL_PARAMS[model])


def _u(angle):
    """Unit vector from foot to hip of a leg at absolute angle ``angle``."""
    return sp.Matrix([-sp.sin(angle), sp.cos(angle)])


def _w(angle):
    """Unit vector perpendicular to ``_u``, pointing forward when the leg is vertical."""
    return sp.Matrix([sp.cos(angle), sp.sin(angle)])


def _slope_frame(slope):
    s = sp.Matrix([sp.cos(slope), -sp.sin(slope)])
    n = sp.Matrix([sp.sin(slope), sp.cos(slope)])
    return s, n


def _coords(names):
    q = sp.symbols(" ".join(names), real=True)
    qd = sp.symbols(" ".join(f"{n}_dot" for n in names), real=True)
    return tuple(q), tuple(qd)


def _floating_foot_points(hip, q_stance, q_swing, L, R, n):
    """Named points of a floating-base walker whose straight legs of length ``L`` (at
    ``q_stance``, ``q_swing`` from the hip at ``hip``) end in foot arcs of radius ``R``: the
    arcs' centres, their lowest points along the slope normal ``n``, and the hip."""
    stance_center = hip - (L - R) * _u(q_stance)
    swing_center = hip - (L - R) * _u(q_swing)
    return {
        "stance_center": stance_center,
        "swing_center": swing_center,
        "stance_contact": stance_center - R * n,
        "swing_contact": swing_center - R * n,
        "hip": hip,
    }


def _floating_base(name, names, params, L, bodies_of) -> LagrangianModel:
    """The floating-base model ``name`` for heel strike: coordinates ``names`` (stance and
    swing leg angles, then the hip's x and y), straight legs of length ``L`` ending in the
    feet of :func:`_floating_foot_points`, and the bodies ``bodies_of(q_stance, q_swing,
    hip, stance_center)``.  ``params`` are the model's parameter symbols; the foot radius,
    the slope and ``g`` are read from them by name."""
    by_name = {str(p): p for p in params}
    R, slope, g = by_name["foot_radius"], by_name["slope"], by_name["g"]
    (q1, q2, xh, yh), (q1d, q2d, xhd, yhd) = _coords(names)
    s, n = _slope_frame(slope)
    hip = sp.Matrix([xh, yh])
    points = _floating_foot_points(hip, q1, q2, L, R, n)
    bodies = bodies_of(q1, q2, hip, points["stance_center"])
    return derive(name, (q1, q2, xh, yh), (q1d, q2d, xhd, yhd), bodies, g, params, points=points)


# --------------------------------------------------------------------------- simplest walker
@cache
def simplest() -> dict:
    """Garcia's simplest walker, derived as the limit of a point-mass compass gait.

    The compass gait with hip mass ``M``, foot masses ``m`` and massless legs of length ``l``
    is written in Garcia's coordinates (``theta``: stance leg from the slope normal,
    ``phi``: swing leg relative to the stance leg), then the stance row is divided by ``M``
    and the swing row by ``m``, and ``beta = m/M -> 0`` (Garcia, Chatterjee, Ruina, Coleman
    1998, J. Biomech. Eng. 120:281).  Both rows are exactly linear in ``beta`` after the
    scaling, so the limit is a substitution.

    Stance-ankle damper: the finite model carries the compass gait's stance-ankle damper,
    the Rayleigh forcing of ``R = 1/2 c theta_dot^2`` with ``c = b M l^2 sqrt(g/l)`` (``b`` the
    dimensionless ``damping_ankle``, ``M = 1``): a torque ``-c theta_dot`` on the stance leg
    relative to the slope, so ``Q = (-c theta_dot, 0)``.  In the stance row it survives the
    limit, ``theta_ddot = (g/l) sin(theta - gamma) - b sqrt(g/l) theta_dot``.  The swing row
    carries no forcing (``Q_phi = 0``: the damper does no work on ``phi``), so after the
    division by ``m`` it is the undamped swing row; the damper enters ``phi_ddot`` only
    through ``theta_ddot`` (the hip's acceleration drives the massless swing leg's foot):
    ``phi_ddot = (1 - cos phi) theta_ddot + sin(theta - phi - gamma) (g/l)
    + sin(phi) theta_dot^2``, i.e. with ``g = l = 1``
    ``phi_ddot = sin(theta - gamma) - b (1 - cos phi) theta_dot
    + sin(phi) (theta_dot^2 - cos(theta - gamma))``.  A forcing on the swing row that does
    not vanish with ``m`` (a finite hip torque on the massless swing leg) has no limit; the
    derivation refuses it.

    Returns
    -------
    dict with keys ``q``, ``qd``, ``params`` (``slope, g, leg_length, damping_ankle``),
    ``qdd`` (Matrix (2, 1), the accelerations ``(theta_ddot, phi_ddot)``), ``model`` (the
    finite-``beta`` LagrangianModel, parameters ``slope, g, leg_length, damping_ankle,
    beta``), ``beta``.
    """
    theta, phi = sp.symbols("theta phi", real=True)
    thetad, phid = sp.symbols("theta_dot phi_dot", real=True)
    slope, g, l, damping_ankle = param_symbols("simplest")
    beta = sp.Symbol("beta", positive=True)
    # Work in the slope frame rotated into the world: stance foot at the origin.
    s, n = _slope_frame(slope)
    # Garcia's theta > 0 just after heel strike with the stance leg leaning back: the leg
    # from foot to hip is -sin(theta) s + cos(theta) n.
    hip = l * (-sp.sin(theta) * s + sp.cos(theta) * n)
    swing_angle = theta - phi  # swing leg from the normal
    foot = hip - l * (-sp.sin(swing_angle) * s + sp.cos(swing_angle) * n)
    bodies = [Body("hip", sp.S.One, hip), Body("swing_foot", beta, foot)]
    # The stance ankle's rate is theta_dot (the slope does not rotate); its coefficient in
    # N m s/rad per unit hip mass is b l^2 sqrt(g/l) = b l sqrt(g l).
    forcing = rayleigh_forcing((thetad, phid), [(damping_ankle * l * sp.sqrt(g * l), thetad)])
    model = derive(
        "simplest_finite",
        (theta, phi),
        (thetad, phid),
        bodies,
        g,
        (slope, g, l, damping_ankle, beta),
        points={"hip": hip, "swing_foot": foot},
        forcing=forcing,
    )
    # D qdd + (h - Q) = 0.  Stance row: take beta -> 0.  Swing row: divide by beta, then
    # beta -> 0; its forcing must vanish with beta for the limit to exist.
    D0 = model.D.subs(beta, 0)
    h0 = model.forced_bias.subs(beta, 0)
    Dsw = (model.D[1, :] / beta).applyfunc(sp.expand).subs(beta, 0)
    hsw = sp.expand(model.forced_bias[1] / beta).subs(beta, 0)
    if hsw.has(sp.zoo, sp.oo, sp.nan):
        raise ValueError(
            "simplest walker: the swing row's forcing must vanish with beta = m/M (a finite "
            "torque on the massless swing leg has no limit)"
        )
    # Row 0 (beta = 0) involves theta_ddot only; row 1 then gives phi_ddot.
    thdd = sp.Symbol("theta_ddot")
    phdd = sp.Symbol("phi_ddot")
    sol = sp.solve(
        [D0[0, 0] * thdd + D0[0, 1] * phdd + h0[0], Dsw[0] * thdd + Dsw[1] * phdd + hsw],
        [thdd, phdd],
        dict=True,
    )[0]
    qdd = sp.Matrix([sol[thdd], sol[phdd]])
    return {
        "q": (theta, phi),
        "qd": (thetad, phid),
        "params": (slope, g, l, damping_ankle),
        "qdd": qdd,
        "model": model,
        "beta": beta,
    }


# ------------------------------------------------------------------------------ compass gait
def _compass_bodies(q1, q2, hip, params, contact_center):
    m_h, m, a, b, inertia, R = params[:6]
    u1, u2 = _u(q1), _u(q2)
    stance_mass = contact_center + (a - R) * u1
    swing_mass = hip - b * u2
    bodies = [
        Body("hip", m_h, hip),
        Body("stance_leg", m, stance_mass, q1, inertia),
        Body("swing_leg", m, swing_mass, q2, inertia),
    ]
    return bodies


@cache
def compass() -> LagrangianModel:
    """Compass gait in single support (stance foot pinned, or rolling when R > 0).

    Coordinates ``(q_stance, q_swing)``, absolute from the vertical, counterclockwise
    positive (Goswami, Thuilot, Espiau, INRIA RR-2996, 1996).  Leg mass ``m`` at ``a`` from
    the foot (``b`` below the hip), rotational inertia ``I`` about it, hip mass ``m_H``.
    Forcing: the hip damper, ``-damping_hip (qd_swing - qd_stance)`` on the swing leg and its
    opposite on the stance leg, and the stance-ankle damper, ``-damping_ankle qd_stance`` on
    the stance leg (relative to the slope).
    """
    params = param_symbols("compass")
    m_h, m, a, b, inertia, R, slope, g, damping_hip, damping_ankle = params
    (q1, q2), (q1d, q2d) = _coords(("q_stance", "q_swing"))
    s, n = _slope_frame(slope)
    L = a + b
    center = -R * (q1 + slope) * s + R * n
    hip = center + (L - R) * _u(q1)
    swing_center = hip - (L - R) * _u(q2)
    points = {
        "stance_contact": center - R * n,
        "hip": hip,
        "swing_center": swing_center,
        "swing_contact": swing_center - R * n,
    }
    bodies = _compass_bodies(q1, q2, hip, params, center)
    forcing = rayleigh_forcing((q1d, q2d), [(damping_hip, q2d - q1d), (damping_ankle, q1d)])
    return derive(
        "compass", (q1, q2), (q1d, q2d), bodies, g, params, points=points, forcing=forcing
    )


@cache
def compass_extended() -> LagrangianModel:
    """Floating-base compass gait for heel strike: ``(q_stance, q_swing, x_hip, y_hip)``.

    Points ``stance_contact`` and ``swing_contact`` are the lowest points of the two foot
    arcs; their *material* velocities (used as impact constraints) are returned by
    :func:`contact_velocity_jacobian`.
    """
    params = param_symbols("compass")
    a, b = params[2], params[3]
    return _floating_base(
        "compass_extended",
        ("q_stance", "q_swing", "x_hip", "y_hip"),
        params,
        a + b,
        lambda q1, q2, hip, center: _compass_bodies(q1, q2, hip, params, center),
    )


def contact_velocity_jacobian(model: LagrangianModel, center: str, angle_index: int, R, slope):
    """Jacobian of the velocity of the foot's material point at the contact, shape (2, n).

    The contact point is ``R`` below the arc centre along the slope normal; for a foot
    rotating at ``omega`` its material velocity is ``v_center + omega R s``.
    """
    s, _ = _slope_frame(slope)
    J = model.point_jacobian(center)
    e = sp.zeros(1, model.n)
    e[0, angle_index] = 1
    return J + R * s * e


# ---------------------------------------------------------------------------- kneed walker
def _kneed_bodies(q1, q2, q3, hip, params, stance_center):
    (m_h, m_t, m_s, a1, b1, a2, b2, I_t, I_s, off_t, off_s, R) = params[:12]
    del a2
    l_t = sp.Symbol("thigh_com_from_knee", real=True) + b2
    u1, u2, u3 = _u(q1), _u(q2), _u(q3)
    w1, w2, w3 = _w(q1), _w(q2), _w(q3)
    knee = hip - l_t * u2
    return [
        Body("hip", m_h, hip),
        Body("stance_shank", m_s, stance_center + (a1 - R) * u1 + off_s * w1, q1, I_s),
        Body("stance_thigh", m_t, hip - b2 * u1 + off_t * w1, q1, I_t),
        Body("swing_thigh", m_t, hip - b2 * u2 + off_t * w2, q2, I_t),
        Body("swing_shank", m_s, knee - b1 * u3 + off_s * w3, q3, I_s),
    ], knee


def _kneed_geometry(params):
    (m_h, m_t, m_s, a1, b1, a2, b2) = params[:7]
    l_s = a1 + b1
    l_t = a2 + b2
    return l_s, l_t, l_s + l_t


@cache
def kneed_unlocked() -> LagrangianModel:
    """Kneed walker, knee free: ``(q1 stance leg, q2 swing thigh, q3 swing shank)``.

    Five masses as in Hsu Chen (2007, MIT M.Eng. thesis) and McGeer (1990): hip ``m_H``; on
    each leg a thigh mass ``m_t`` at ``b2`` below the hip (``a2`` above the knee) and a shank
    mass ``m_s`` at ``b1`` below the knee (``a1`` above the foot), with optional inertias and
    fore-aft offsets (McGeer).  The stance leg is rigid (its knee is locked).  Forcing: the
    hip damper on ``qd2 - qd1``, the swing-knee damper on ``qd3 - qd2`` and the stance-ankle
    damper on ``qd1`` (the stance leg relative to the slope).
    """
    params = param_symbols("kneed")
    R, slope, g = params[11], params[12], params[13]
    damping_hip, damping_knee, damping_ankle = params[14], params[15], params[16]
    (q1, q2, q3), (q1d, q2d, q3d) = _coords(("q1", "q2", "q3"))
    s, n = _slope_frame(slope)
    l_s, l_t, L = _kneed_geometry(params)
    center = -R * (q1 + slope) * s + R * n
    hip = center + (L - R) * _u(q1)
    bodies, knee = _kneed_bodies(q1, q2, q3, hip, params, center)
    swing_center = knee - (l_s - R) * _u(q3)
    points = {
        "stance_contact": center - R * n,
        "hip": hip,
        "knee": knee,
        "swing_center": swing_center,
        "swing_contact": swing_center - R * n,
    }
    forcing = rayleigh_forcing(
        (q1d, q2d, q3d),
        [(damping_hip, q2d - q1d), (damping_knee, q3d - q2d), (damping_ankle, q1d)],
    )
    return derive(
        "kneed_unlocked",
        (q1, q2, q3),
        (q1d, q2d, q3d),
        bodies,
        g,
        params,
        points=points,
        forcing=forcing,
    )


@cache
def kneed_locked() -> LagrangianModel:
    """Kneed walker with the swing knee locked: ``(q1 stance leg, q2 swing leg)``.

    Forcing: the hip damper on ``qd2 - qd1`` and the stance-ankle damper on ``qd1``; the
    knee's relative rate is zero.
    """
    full = kneed_unlocked()
    q1, q2, q3 = full.q
    q1d, q2d, q3d = full.qd
    params = full.params
    g = params[13]
    damping_hip, damping_knee, damping_ankle = params[14], params[15], params[16]
    (p1, p2), (p1d, p2d) = _coords(("q1", "q2"))
    # The knee-locked rates: qd3 = qd2.  Substituting them into the dampers' rates gives the
    # projection T^T Q of the unlocked forcing (T maps (p1d, p2d) to (p1d, p2d, p2d)).
    rate_sub = {q1d: p1d, q2d: p2d, q3d: p2d}
    dampers = [(damping_hip, q2d - q1d), (damping_knee, q3d - q2d), (damping_ankle, q1d)]
    forcing = rayleigh_forcing((p1d, p2d), [(b, w.subs(rate_sub)) for b, w in dampers])
    sub = {q1: p1, q2: p2, q3: p2}
    bodies = [
        Body(
            b.name,
            b.mass,
            b.position.subs(sub),
            None if b.angle is None else b.angle.subs(sub),
            b.inertia,
        )
        for b in full.bodies
    ]
    points = {k: v.subs(sub) for k, v in full.points.items()}
    return derive(
        "kneed_locked", (p1, p2), (p1d, p2d), bodies, g, params, points=points, forcing=forcing
    )


@cache
def kneed_extended() -> LagrangianModel:
    """Floating-base kneed walker with the swing knee locked, for heel strike.

    Coordinates ``(q1, q2, x_hip, y_hip)``: both legs straight (heel strike is accepted only
    with the knee locked), the hip free.
    """
    params = param_symbols("kneed")
    return _floating_base(
        "kneed_extended",
        ("q1", "q2", "x_hip", "y_hip"),
        params,
        _kneed_geometry(params)[2],
        lambda q1, q2, hip, center: _kneed_bodies(q1, q2, q2, hip, params, center)[0],
    )


# ------------------------------------------------------------------ two-link arms
@cache
def double_pendulum() -> LagrangianModel:
    """The planar double pendulum: link 1 hinged at the origin, ``q1`` from the +x axis,
    ``q2`` relative to link 1 (the planar elbow manipulator's coordinates, Spong et al.)."""
    params = param_symbols("double_pendulum")
    m1, m2, I1, I2, l1, l2, c1, c2, g, damping_1, damping_2 = params[:11]
    (q1, q2), (q1d, q2d) = _coords(("q1", "q2"))
    e1 = sp.Matrix([sp.cos(q1), sp.sin(q1)])
    e12 = sp.Matrix([sp.cos(q1 + q2), sp.sin(q1 + q2)])
    elbow = l1 * e1
    bodies = [
        Body("link_1", m1, c1 * e1, q1, I1),
        Body("link_2", m2, elbow + c2 * e12, q1 + q2, I2),
    ]
    points = {"elbow": elbow, "tip": elbow + l2 * e12}
    # joint 1: link 1 relative to the ground, w1 = q1d; joint 2: link 2 relative to link 1,
    # w2 = q2d (q2 is already relative).  The dry frictions (coulomb_1, coulomb_2) are not
    # part of the smooth model: stick and slip are phases of walker.models.double_pendulum.
    forcing = rayleigh_forcing((q1d, q2d), [(damping_1, q1d), (damping_2, q2d)])
    return derive(
        "double_pendulum",
        (q1, q2),
        (q1d, q2d),
        bodies,
        g,
        params,
        points=points,
        forcing=forcing,
    )


@cache
def planar_elbow() -> LagrangianModel:
    """The planar elbow manipulator: the double pendulum with a torque at each joint (and
    the double pendulum's viscous joint dampers)."""
    dp = double_pendulum()
    g = dp.params[MODEL_PARAMS["double_pendulum"].index("g")]
    return derive(
        "planar_elbow",
        dp.q,
        dp.qd,
        dp.bodies,
        g,
        dp.params,
        points=dp.points,
        B=sp.eye(2),
        forcing=dp.forcing,
    )
