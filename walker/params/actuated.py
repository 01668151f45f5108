"""Parameters of the actuated walkers, each with its controller block: Grizzle's three-link
walker and the five-link walker (RABBIT); their presets' numbers are in
:mod:`walker.params._actuated_presets`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

from walker.params._actuated_presets import (
    _BOOK_A,
    _BOOK_DEFAULTS,
    _GRIZZLE_DEFAULTS,
    _GRIZZLE_INVARIANT,
    _POLY_DEGREE,
    _RABBIT_DEFAULTS,
    _RABBIT_INVARIANT,
)
from walker.params._base import _check_number, _param, _Params, _relation_error, _slope_field

__all__ = ["ThreeLinkParams", "FiveLinkParams"]


# ------------------------------------------------------------------------------------------
_BEZIER_DEGREE = 4  # must equal walker.models.control.BEZIER_DEGREE (tests/test_params.py checks)


def _bezier_field(output: str, k: int) -> Any:
    return _param("rad", f"Bezier coefficient {k} of the desired {output} angle")


def _poly_field(output: str, k: int) -> Any:
    unit = {0: "rad", 1: "1"}.get(k, f"1/rad^{k - 1}")
    return _param(unit, f"coefficient of q_stance^{k} in the desired {output} angle (controller 3)")


@dataclasses.dataclass(frozen=True)
class ThreeLinkParams(_Params):
    """Grizzle's three-link walker (two legs, torso, two hip actuators) and its controller.

    The first eleven fields are the physical parameters the generated kernels take (order of
    :data:`walker.symbolic.actuated.THREE_LINK_PARAMS`); ``friction`` is the ground's Coulomb
    coefficient; then the controller block read by :mod:`walker.models.control` (layout in its
    docstring): the mode, gains, torque limit, the phase range and the Bezier coefficients
    (degree 4) of the desired swing-leg and torso angles; last the joint friction of the two
    hip joints (appended after the controller block, so ``CONTROL_OFFSET`` and every other
    index are those of the frictionless layout).  The hip joint rates are ``w = B^T qd =
    (qd_stance - qd_torso, qd_swing - qd_torso)``; a joint torque acts on the leg and its
    opposite on the torso, like the actuator's.

    Attributes
    ----------
    mass_hip, mass_leg : float
        hip point mass, mass of each leg [kg], > 0.
    mass_torso : float
        torso point mass [kg], >= 0 (0 only with the controller off: a massless torso).
    com_from_foot, com_to_hip : float
        leg mass position: above the foot, below the hip [m], >= 0; leg length their sum.
    torso_length : float
        hip to the torso mass [m], >= 0.
    inertia_leg, inertia_torso : float
        about the segment's centre of mass [kg m^2], >= 0.
    slope : float
        [rad], in (-pi/2, pi/2); 0 is level ground.
    g : float
        [m/s^2], > 0.
    rotor_inertia : float
        actuator rotor inertia reflected at each hip joint [kg m^2], >= 0: a rotor geared
        with ratio N to a joint's relative angle adds ``N^2 J_rotor w^2 / 2`` to the kinetic
        energy (``w`` the joint rate, below); the rotor's own rotation with the link it sits on
        is neglected, as in RABBIT's model [4]_.  0 in the presets: the book's example model
        (``model_params_three_link.m`` [3]_) has no rotors.
    friction : float
        ground friction coefficient mu [-], > 0: the ground reaction must stay in the cone
        ``|F_t| <= mu F_n`` at impact and during stance.
    controller : float
        0: off (passive); 1: joint-space PD to the Bezier references; 2: virtual constraints
        by input-output linearization (computed torque) with PD on the outputs; 3: the
        finite-time controller of Bhat and Bernstein on polynomial outputs, by input-output
        linearization (Westervelt et al. 2007 [3]_; compiled C only, see ``ft_alpha``).
    kp, kd : float
        output (or joint) gains [1/s^2], [1/s] for mode 2; [N m/rad], [N m s/rad] for mode 1;
        unused by mode 3.
    torque_limit : float
        actuator saturation |tau_i| <= torque_limit [N m], > 0.
    theta_plus, theta_minus : float
        stance angle at the start and the end of a step [rad] (the phase variable is the
        stance angle, normalized to s = (q_stance - theta_plus)/(theta_minus - theta_plus)).
    bezier_swing_0 .. bezier_swing_4, bezier_torso_0 .. bezier_torso_4 : float
        Bezier coefficients [rad] of the desired absolute swing-leg and torso angles (modes
        1 and 2).
    step_event : float
        where a step ends: 0, heel strike where the swing foot reaches the ground (walker's
        default); 1, where the stance angle falls through ``theta_minus``, wherever the swing
        foot is (the impact surface of [3]_'s example code; the impact map is the same).
    ft_alpha, ft_epsilon : float
        controller 3: the exponent alpha in (0, 1) and the time scale epsilon [s], > 0, of
        the finite-time controller: each output's acceleration is set to
        ``psi(y, epsilon yd) / epsilon^2`` with ``phi = y + sig(epsilon yd, 2 - alpha) / (2 -
        alpha)``, ``psi = -sig(epsilon yd, alpha) - sig(phi, alpha / (2 - alpha))`` and
        ``sig(x, e) = sgn(x) |x|^e`` (``walker/_core/wk_control.h``).
    poly_swing_0 .. poly_swing_5, poly_torso_0 .. poly_torso_5 : float
        controller 3: the outputs are ``y = q_swing - sum_k poly_swing_k q_stance^k`` and
        ``y = q_torso - sum_k poly_torso_k q_stance^k`` (plain polynomials of degree 5 in the
        stance angle, walker's counterclockwise angles; :meth:`westervelt_book` converts the
        book's coefficients).
    damping_hip : float
        viscous friction F_v of each hip joint [N m s/rad], >= 0: torque ``-F_v w_j``
        (0 in the preset: the published model is frictionless).
    coulomb_hip : float
        Coulomb (dry) friction F_s of each hip joint [N m], >= 0: torque ``-F_s sgn(w_j)``
        while the joint slips, up to ``F_s`` holding it while it sticks (stick and slip are
        phases of :mod:`walker.models.three_link`; 0 in the preset).  The controller does not
        know about either friction: it is a disturbance its PD on the outputs rejects.

    The fields ``step_event`` .. ``poly_torso_5`` sit between the Bezier coefficients and the
    hip friction (indices 28..42; ``walker.models.three_link`` names them).

    References
    ----------
    .. [1] J. W. Grizzle, G. Abba, F. Plestan, IEEE TAC 46(1):51-64, 2001.
    .. [2] E. R. Westervelt, J. W. Grizzle, D. E. Koditschek, "Hybrid zero dynamics of planar
       biped walkers", IEEE TAC 48(1):42-56, 2003.
    .. [3] Westervelt, Grizzle, Chevallereau, Choi, Morris, *Feedback Control of Dynamic
       Bipedal Robot Locomotion*, CRC Press 2007, example code
       ``model_params_three_link.m``: r = 1, m = 5, Mh = 15, Mt = 10, L = 0.5, g = 9.8.
    .. [4] C. Chevallereau et al., "RABBIT: a testbed for advanced control theory", IEEE
       Control Systems Magazine 23(5):57-79, 2003.
    """

    MODEL: ClassVar[str] = "three_link"
    PRESETS: ClassVar[tuple[str, ...]] = ("grizzle",)
    ADDED_FIELDS: ClassVar[tuple[str, ...]] = (
        "rotor_inertia",
        "step_event",
        "ft_alpha",
        "ft_epsilon",
        *(f"poly_{o}_{k}" for o in ("swing", "torso") for k in range(_POLY_DEGREE + 1)),
    )
    """Fields added after three-link files were first written: a file without them was
    computed with heel strike ending the step, no finite-time controller and no rotor inertia,
    the values the ``grizzle`` preset gives them (:func:`walker.plotting.gallery` reads such a file
    with those)."""

    mass_hip: float = _param("kg", "point mass at the hip", 0.0, lo_open=True)
    mass_leg: float = _param("kg", "point mass of each leg", 0.0, lo_open=True)
    mass_torso: float = _param("kg", "point mass of the torso", 0.0)
    com_from_foot: float = _param("m", "foot to the leg's mass", 0.0)
    com_to_hip: float = _param("m", "leg's mass to the hip", 0.0)
    torso_length: float = _param("m", "hip to the torso's mass", 0.0)
    inertia_leg: float = _param("kg m^2", "leg inertia about its centre of mass", 0.0)
    inertia_torso: float = _param("kg m^2", "torso inertia about its centre of mass", 0.0)
    slope: float = _slope_field()
    g: float = _param("m/s^2", "gravitational acceleration", 0.0, lo_open=True)
    rotor_inertia: float = _param(
        "kg m^2",
        "actuator rotor inertia reflected at each actuated joint, N^2 J_rotor (0: no rotors)",
        0.0,
    )
    friction: float = _param("1", "ground friction coefficient mu", 0.0, lo_open=True)
    controller: float = _param(
        "1", "0 off, 1 joint PD, 2 virtual constraints, 3 finite-time (book)", 0.0, 3.0
    )
    kp: float = _param("1/s^2", "proportional gain", 0.0)
    kd: float = _param("1/s", "derivative gain", 0.0)
    torque_limit: float = _param("N m", "actuator torque limit", 0.0, lo_open=True)
    theta_plus: float = _param("rad", "stance angle at the start of a step")
    theta_minus: float = _param("rad", "stance angle at the end of a step")
    bezier_swing_0: float = _bezier_field("swing-leg", 0)
    bezier_swing_1: float = _bezier_field("swing-leg", 1)
    bezier_swing_2: float = _bezier_field("swing-leg", 2)
    bezier_swing_3: float = _bezier_field("swing-leg", 3)
    bezier_swing_4: float = _bezier_field("swing-leg", 4)
    bezier_torso_0: float = _bezier_field("torso", 0)
    bezier_torso_1: float = _bezier_field("torso", 1)
    bezier_torso_2: float = _bezier_field("torso", 2)
    bezier_torso_3: float = _bezier_field("torso", 3)
    bezier_torso_4: float = _bezier_field("torso", 4)
    step_event: float = _param(
        "1",
        "step ends: 0 swing foot reaches the ground, 1 stance angle reaches theta_minus",
        0.0,
        1.0,
    )
    ft_alpha: float = _param(
        "1",
        "finite-time controller exponent alpha (controller 3)",
        0.0,
        1.0,
        lo_open=True,
        hi_open=True,
    )
    ft_epsilon: float = _param(
        "s", "finite-time controller time scale epsilon (controller 3)", 0.0, lo_open=True
    )
    poly_swing_0: float = _poly_field("swing-leg", 0)
    poly_swing_1: float = _poly_field("swing-leg", 1)
    poly_swing_2: float = _poly_field("swing-leg", 2)
    poly_swing_3: float = _poly_field("swing-leg", 3)
    poly_swing_4: float = _poly_field("swing-leg", 4)
    poly_swing_5: float = _poly_field("swing-leg", 5)
    poly_torso_0: float = _poly_field("torso", 0)
    poly_torso_1: float = _poly_field("torso", 1)
    poly_torso_2: float = _poly_field("torso", 2)
    poly_torso_3: float = _poly_field("torso", 3)
    poly_torso_4: float = _poly_field("torso", 4)
    poly_torso_5: float = _poly_field("torso", 5)
    damping_hip: float = _param(
        "N m s/rad",
        "viscous friction of each hip joint, torque -F_v w on the leg (w = leg rate - torso rate)",
        0.0,
    )
    coulomb_hip: float = _param(
        "N m",
        "Coulomb friction of each hip joint, torque -F_s sgn(w) on the leg while slipping",
        0.0,
    )

    @property
    def leg_length(self) -> float:
        """Leg length ``com_from_foot + com_to_hip`` [m]."""
        return self.com_from_foot + self.com_to_hip

    def _check_relations(self) -> None:
        if not self.leg_length > 0.0:
            raise _relation_error(
                "leg length `com_from_foot + com_to_hip` must be > 0 [m]", f"{self.leg_length!r}"
            )
        if self.controller not in (0.0, 1.0, 2.0, 3.0):
            raise _relation_error("`controller` must be 0, 1, 2 or 3", f"{self.controller!r}")
        if self.step_event not in (0.0, 1.0):
            raise _relation_error("`step_event` must be 0 or 1", f"{self.step_event!r}")
        if self.controller != 0.0 and not self.theta_minus != self.theta_plus:
            raise _relation_error(
                "`theta_minus` must differ from `theta_plus` when the controller is on",
                f"{self.theta_minus!r}",
            )
        if self.controller != 0.0 and not (self.mass_torso > 0.0 or self.inertia_torso > 0.0):
            raise _relation_error(
                "`mass_torso` or `inertia_torso` must be > 0 when the controller is on",
                f"{self.mass_torso!r}",
            )

    @classmethod
    def grizzle(cls, **changes: Any) -> ThreeLinkParams:
        """Westervelt et al.'s three-link example [3]_ with walker's virtual-constraint design.

        Masses and lengths from ``model_params_three_link.m`` [3]_ (legs' point masses at
        r/2). The step angle pi/8 and the forward-leaning torso (pi/6 in [3]_'s clockwise
        convention, -pi/6 here) are those of ``control_params_three_link.m``; the Bezier
        coefficients are walker's own, made HZD-invariant by
        :func:`walker.models.hzd.make_invariant` (see ``gaits/three_link_grizzle.toml``); the
        invariant values are stored as numbers (``_GRIZZLE_INVARIANT`` in
        :mod:`walker.params._actuated_presets`; a test checks them against
        ``make_invariant``), so :mod:`walker.params` imports no analysis code.

        ``changes`` may set what the impact does not depend on (controller, gains, torque
        limit, friction, ``g``, the book controller's fields); a change of the mechanics, the
        slope or the design makes the Bezier coefficients non-invariant, and is refused: pass
        ``ThreeLinkParams.grizzle().replace(...)`` through :func:`walker.models.hzd.make_invariant`.

        References
        ----------
        .. [3] Westervelt, Grizzle, Chevallereau, Choi, Morris, CRC Press 2007.
        """
        _impact_neutral(cls, "grizzle", changes)
        return cls(**{**_GRIZZLE_DEFAULTS, **_GRIZZLE_INVARIANT, **changes})

    @classmethod
    def westervelt_book(cls, a: Any = None, **changes: Any) -> ThreeLinkParams:
        """The three-link example of Westervelt et al. [3]_ as its example code runs it: the
        finite-time controller (``controller = 3``) on the book's polynomial outputs, and the
        step ending where the stance angle reaches the switching angle (``step_event = 1``).
        Not one of ``PRESETS`` (``gaits/three_link_book.toml`` writes every value out).

        The code measures angles clockwise, walker counterclockwise: ``theta_i = -q_i``
        (stance, swing, torso; rates alike; the hip torques are the same numbers).  Its outputs
        are ``h1 = theta3 - (a01 + a11 theta1 + a21 theta1^2 + a31 theta1^3)`` and ``h2 =
        theta2 + theta1 - (a02 + a12 theta1 + a22 theta1^2 + a32 theta1^3) (theta1 - th1d)
        (theta1 + th1d)`` (``dynamics_three_link.m``); in walker's angles the desired torso
        angle is ``sum_k (-1)^(k+1) a_k1 q_stance^k`` and the desired swing angle ``-q_stance
        + (q_stance^2 - th1d^2) sum_k (-1)^(k+1) a_k2 q_stance^k``, expanded here into the
        ``poly_*`` coefficients.  The step ends at ``theta1 = th1d``, i.e. ``q_stance =
        theta_minus = -th1d``.

        Parameters
        ----------
        a : sequence of 8 floats, optional
            the book's ``[a01, a11, a21, a31, a02, a12, a22, a32]``; default the published
            ``[0.512, 0.073, 0.035, -0.819, -2.27, 3.26, 3.11, 1.89]`` (``walker_main.m``).
        **changes
            any other field (e.g. ``theta_minus``, ``ft_alpha``), applied before the
            coefficients are expanded (``th1d = -theta_minus``).

        References
        ----------
        .. [3] Westervelt, Grizzle, Chevallereau, Choi, Morris, CRC Press 2007, example code
           (``WGCCM_three_link_walker_example``): ``model_params_three_link.m`` (the model),
           ``control_params_three_link.m`` (th3d = pi/6, th1d = pi/8, alpha = 0.9,
           epsilon = 0.1), ``walker_main.m`` (a, omega_1 = 1.55).
        """
        if a is None:
            a = _BOOK_A
        a = [_check_number(f"a[{i}]", v) for i, v in enumerate(np.asarray(a, dtype=object).ravel())]
        if len(a) != 8:
            raise ValueError(f"`a` must hold 8 coefficients (a01..a31, a02..a32), got {len(a)}")
        base = cls(**{**_BOOK_DEFAULTS, **changes})
        th1d2 = base.theta_minus**2
        torso = [(-1.0) ** (k + 1) * a[k] for k in range(4)] + [0.0, 0.0]
        b = [(-1.0) ** (k + 1) * a[4 + k] for k in range(4)]
        swing = [
            -th1d2 * b[0],
            -1.0 - th1d2 * b[1],
            b[0] - th1d2 * b[2],
            b[1] - th1d2 * b[3],
            b[2],
            b[3],
        ]
        coefficients = {f"poly_torso_{k}": v for k, v in enumerate(torso)}
        coefficients.update({f"poly_swing_{k}": v for k, v in enumerate(swing)})
        return base.replace(**coefficients)


_IMPACT_NEUTRAL = ("g", "friction", "controller", "kp", "kd", "torque_limit", "step_event")
_IMPACT_NEUTRAL_PREFIXES = ("damping_", "coulomb_", "ft_", "poly_")


def _impact_neutral(cls: type, preset: str, changes: Mapping[str, Any]) -> None:
    """Refuse preset ``changes`` that would leave its Bezier design non-invariant."""
    bad = [
        k
        for k in changes
        if k not in _IMPACT_NEUTRAL and not k.startswith(_IMPACT_NEUTRAL_PREFIXES)
    ]
    if bad:
        listed = ", ".join(f"`{k}`" for k in bad)
        raise ValueError(
            f"`{preset}()` changes may only set what the impact does not depend on "
            f"({', '.join(_IMPACT_NEUTRAL)}, {', '.join(p + '*' for p in _IMPACT_NEUTRAL_PREFIXES)}"
            f"), got {listed}: use {cls.__name__}.{preset}().replace(...) and "
            "walker.models.hzd.make_invariant for an HZD-invariant design"
        )


@dataclasses.dataclass(frozen=True)
class FiveLinkParams(_Params):
    """The five-link walker (torso, femurs, tibias; hip and knee actuators) and its controller.

    The first fourteen fields are the physical parameters the generated kernels take (order
    of :data:`walker.symbolic.five_link.FIVE_LINK_PARAMS`); ``friction`` is the ground's
    Coulomb coefficient; the rest is the controller block read by :mod:`walker.models.control`
    (layout in its docstring): mode, gains, torque limit, the phase range and the Bezier
    coefficients (degree 4) of the four outputs, in the order of the model's coordinates
    ``q[1:]``: stance-knee flexion ``q_femur_st - q_tibia_st``, torso, swing femur and swing
    tibia (absolute angles).  The phase variable is ``q_leg = (q_tibia_st + q_femur_st)/2``.
    Last the joint friction of the hips and knees (appended after the controller block, so
    ``CONTROL_OFFSET`` and every other index are those of the frictionless layout).  The
    joint rates are ``w = B^T qd``: hips ``q_femur - q_torso``, knees ``q_tibia - q_femur``
    (rates; stance then swing); a joint torque acts on the distal link (femur, tibia) and
    its opposite on the proximal one, like the actuator's.

    Attributes
    ----------
    mass_torso, mass_femur, mass_tibia : float
        segment masses [kg], > 0.
    length_femur, length_tibia : float
        hip to knee, knee to foot [m], > 0.
    com_torso : float
        hip to the torso's centre of mass [m], >= 0.
    com_femur : float
        hip to the femur's centre of mass [m], in [0, length_femur].
    com_tibia : float
        knee to the tibia's centre of mass [m], in [0, length_tibia].
    inertia_torso, inertia_femur, inertia_tibia : float
        about the segment's centre of mass [kg m^2], >= 0.
    slope : float
        [rad], in (-pi/2, pi/2); 0 is level ground.
    g : float
        [m/s^2], > 0.
    rotor_inertia : float
        actuator rotor inertia reflected at each of the four joints [kg m^2], >= 0: a rotor
        geared with ratio N to a joint's relative angle adds ``N^2 J_rotor w^2 / 2`` to the
        kinetic energy (``w`` the joint rate, below); the rotor's own rotation with the link
        it sits on (its gyroscopic coupling) is neglected, as in RABBIT's model [2]_.  RABBIT
        as published [2]_ [3]_ has N = 50 and J_rotor = 3.32e-4 kg m^2, so 0.83 kg m^2
        (``walker.params._actuated_presets.RABBIT_ROTOR_INERTIA``); the ``rabbit`` preset
        sets 0, because its gait is for the link table of [1]_ without rotors.
    friction : float
        ground friction coefficient mu [-], > 0.
    controller : float
        0: off (passive); 1: joint-space PD to the Bezier references; 2: virtual constraints
        by input-output linearization (computed torque) with PD on the outputs.
    kp, kd : float
        output gains [1/s^2], [1/s] (mode 2); joint gains [N m/rad], [N m s/rad] (mode 1).
    torque_limit : float
        actuator saturation |tau_i| <= torque_limit [N m], > 0.
    theta_plus, theta_minus : float
        phase ``q_leg`` at the start and the end of a step [rad].
    bezier_knee_0 .. 4, bezier_torso_0 .. 4, bezier_femur_0 .. 4, bezier_tibia_0 .. 4 : float
        Bezier coefficients [rad] of the desired stance-knee flexion, torso, swing-femur and
        swing-tibia angles.
    damping_hip, damping_knee : float
        viscous friction F_v of each hip, each knee joint [N m s/rad], >= 0: torque
        ``-F_v w_j`` (0 in the preset: the published model is frictionless).
    coulomb_hip, coulomb_knee : float
        Coulomb (dry) friction F_s of each hip, each knee joint [N m], >= 0: torque
        ``-F_s sgn(w_j)`` while the joint slips, up to ``F_s`` holding it while it sticks
        (stick and slip are phases of :mod:`walker.models.five_link`; 0 in the preset).  The
        controller does not know about either friction: it is a disturbance its PD on the
        outputs rejects.

    References
    ----------
    .. [1] E. R. Westervelt, J. W. Grizzle, D. E. Koditschek, "Hybrid zero dynamics of planar
       biped walkers", IEEE TAC 48(1):42-56, 2003, Table I (RABBIT).
    .. [2] C. Chevallereau et al., "RABBIT: a testbed for advanced control theory", IEEE
       Control Systems Magazine 23(5):57-79, 2003.
    .. [3] Westervelt, Grizzle, Chevallereau, Choi, Morris, *Feedback Control of Dynamic
       Bipedal Robot Locomotion*, CRC Press 2007 (RABBIT's parameters).
    """

    MODEL: ClassVar[str] = "five_link"
    PRESETS: ClassVar[tuple[str, ...]] = ("rabbit",)
    ADDED_FIELDS: ClassVar[tuple[str, ...]] = ("rotor_inertia",)
    """Fields added after five-link files were first written: a file without them was
    computed without rotor inertia, the value the ``rabbit`` preset gives it."""

    mass_torso: float = _param("kg", "torso mass", 0.0, lo_open=True)
    mass_femur: float = _param("kg", "mass of each femur", 0.0, lo_open=True)
    mass_tibia: float = _param("kg", "mass of each tibia", 0.0, lo_open=True)
    length_femur: float = _param("m", "hip to knee", 0.0, lo_open=True)
    length_tibia: float = _param("m", "knee to foot", 0.0, lo_open=True)
    com_torso: float = _param("m", "hip to the torso's centre of mass", 0.0)
    com_femur: float = _param("m", "hip to the femur's centre of mass", 0.0)
    com_tibia: float = _param("m", "knee to the tibia's centre of mass", 0.0)
    inertia_torso: float = _param("kg m^2", "torso inertia about its centre of mass", 0.0)
    inertia_femur: float = _param("kg m^2", "femur inertia about its centre of mass", 0.0)
    inertia_tibia: float = _param("kg m^2", "tibia inertia about its centre of mass", 0.0)
    slope: float = _slope_field()
    g: float = _param("m/s^2", "gravitational acceleration", 0.0, lo_open=True)
    rotor_inertia: float = _param(
        "kg m^2",
        "actuator rotor inertia reflected at each actuated joint, N^2 J_rotor (0: no rotors)",
        0.0,
    )
    friction: float = _param("1", "ground friction coefficient mu", 0.0, lo_open=True)
    controller: float = _param("1", "0 off, 1 joint PD, 2 virtual constraints", 0.0, 2.0)
    kp: float = _param("1/s^2", "proportional gain", 0.0)
    kd: float = _param("1/s", "derivative gain", 0.0)
    torque_limit: float = _param("N m", "actuator torque limit", 0.0, lo_open=True)
    theta_plus: float = _param("rad", "mean stance-leg angle at the start of a step")
    theta_minus: float = _param("rad", "mean stance-leg angle at the end of a step")
    bezier_knee_0: float = _bezier_field("stance-knee flexion", 0)
    bezier_knee_1: float = _bezier_field("stance-knee flexion", 1)
    bezier_knee_2: float = _bezier_field("stance-knee flexion", 2)
    bezier_knee_3: float = _bezier_field("stance-knee flexion", 3)
    bezier_knee_4: float = _bezier_field("stance-knee flexion", 4)
    bezier_torso_0: float = _bezier_field("torso", 0)
    bezier_torso_1: float = _bezier_field("torso", 1)
    bezier_torso_2: float = _bezier_field("torso", 2)
    bezier_torso_3: float = _bezier_field("torso", 3)
    bezier_torso_4: float = _bezier_field("torso", 4)
    bezier_femur_0: float = _bezier_field("swing-femur", 0)
    bezier_femur_1: float = _bezier_field("swing-femur", 1)
    bezier_femur_2: float = _bezier_field("swing-femur", 2)
    bezier_femur_3: float = _bezier_field("swing-femur", 3)
    bezier_femur_4: float = _bezier_field("swing-femur", 4)
    bezier_tibia_0: float = _bezier_field("swing-tibia", 0)
    bezier_tibia_1: float = _bezier_field("swing-tibia", 1)
    bezier_tibia_2: float = _bezier_field("swing-tibia", 2)
    bezier_tibia_3: float = _bezier_field("swing-tibia", 3)
    bezier_tibia_4: float = _bezier_field("swing-tibia", 4)
    damping_hip: float = _param(
        "N m s/rad",
        "viscous friction of each hip joint, torque -F_v w on the femur (w = femur - torso rate)",
        0.0,
    )
    damping_knee: float = _param(
        "N m s/rad",
        "viscous friction of each knee joint, torque -F_v w on the tibia (w = tibia - femur rate)",
        0.0,
    )
    coulomb_hip: float = _param(
        "N m",
        "Coulomb friction of each hip joint, torque -F_s sgn(w) on the femur while slipping",
        0.0,
    )
    coulomb_knee: float = _param(
        "N m",
        "Coulomb friction of each knee joint, torque -F_s sgn(w) on the tibia while slipping",
        0.0,
    )

    @property
    def leg_length(self) -> float:
        """Straight-leg length ``length_femur + length_tibia`` [m]."""
        return self.length_femur + self.length_tibia

    def _check_relations(self) -> None:
        if self.com_femur > self.length_femur:
            raise _relation_error(
                f"`com_femur` must be <= `length_femur` = {self.length_femur!r} [m] (centre of "
                "mass inside its link)",
                f"{self.com_femur!r}",
            )
        if self.com_tibia > self.length_tibia:
            raise _relation_error(
                f"`com_tibia` must be <= `length_tibia` = {self.length_tibia!r} [m] (centre of "
                "mass inside its link)",
                f"{self.com_tibia!r}",
            )
        if self.controller not in (0.0, 1.0, 2.0):
            raise _relation_error("`controller` must be 0, 1 or 2", f"{self.controller!r}")
        if self.controller != 0.0 and not self.theta_minus != self.theta_plus:
            raise _relation_error(
                "`theta_minus` must differ from `theta_plus` when the controller is on",
                f"{self.theta_minus!r}",
            )

    @classmethod
    def rabbit(cls, **changes: Any) -> FiveLinkParams:
        """RABBIT's masses, lengths and inertias [1]_ with walker's virtual-constraint design.

        The Bezier coefficients are walker's own (a level-ground gait, see
        ``gaits/five_link_hzd.toml``), made HZD-invariant by
        :func:`walker.models.hzd.make_invariant` and stored as numbers (``_RABBIT_INVARIANT`` in
        :mod:`walker.params._actuated_presets`; a test checks them against it).
        ``changes`` may set what the impact does not depend on (controller, gains, torque
        limit, friction, ``g``); a change of the mechanics, the slope or the design is refused:
        pass ``FiveLinkParams.rabbit().replace(...)`` through
        :func:`walker.models.hzd.make_invariant`.

        Which parameter set, and why.  walker ships the published table [1]_ [2]_: masses
        12 / 6.8 / 3.2 kg (torso, femur, tibia; 32 kg in all), centres of mass 0.24 m above
        the hip, 0.11 m below the hip, 0.24 m below the knee, inertias 1.33 / 0.47 / 0.20
        kg m^2 about the centres of mass.  A second public set with a 20 kg torso is NOT
        shipped, because it is not RABBIT as published:

        - Its source is Westervelt and Grizzle's five-link model-generation MATLAB script (header
          "Copyright (c) 2001 by Eric Westervelt and Jessy Grizzle", dated 6 August 2001): M =
          20 / 6.8 / 3.2 kg, MZ = 0.2 / 0.163 / 0.128 kg m, XX = 2.22 / 1.08 / 0.93 kg m^2,
          torso length 0.625 m.  There the kinetic energy of a link is
          ``M |v_O|^2 / 2 + MZ (omega x e) . v_O + XX omega^2 / 2`` and its centre of mass
          ``O + (MZ / M) e`` (O its proximal joint, e the unit vector along it): MZ is the first
          moment and XX the inertia about the joint (the script's own comment on MZ reads
          "center of mass offsets (times mass??)").  The script does not name RABBIT.
        - By the parallel-axis theorem the centres of mass are MZ / M = 0.010 / 0.024 / 0.040 m
          from the joint and the inertias about them XX - MZ^2 / M = 2.218 / 1.076 / 0.925
          kg m^2 (positive: a valid mass matrix).  That is another robot than [1]_: 40 kg in
          all, leg centres of mass 2.4 and 4 cm from the hip and the knee, and radii of
          gyration 0.398 m (femur) and 0.538 m (tibia) about the centres of mass, against links
          0.4 m long.  No change of convention maps one set to the other: [1]_ in the
          script's form is MZ = 2.88 / 0.748 / 0.768 kg m, XX = 2.021 / 0.552 / 0.384 kg m^2.
          Only the torso's radius of gyration agrees (0.333 m: 2.22 = 1.33 * 20 / 12 to the
          digits given).
        - M. P. Kelly's OptimTraj example (repository MatthewPeterKelly/OptimTraj, file
          ``demo/fiveLinkBiped/getPhysicalParameters.m``, 2015) carries the same digits, cites
          [1]_, and reads them as distances [m] from a joint to the centre of mass and
          inertias about the centre of mass (its ``Derive_Equations.m``: tibia and femur from
          the knee and the hip, the torso's 0.2 m from its top end).  That reading
          mis-transcribes the script's MZ (kg m, not m) and gives a third robot.

        ``tests/test_rabbit_params.py`` checks these numbers.

        References
        ----------
        .. [1] Westervelt, Grizzle, Koditschek, IEEE TAC 48(1), 2003, Table I.
        .. [2] Chevallereau et al., IEEE Control Systems Magazine 23(5), 2003.
        """
        _impact_neutral(cls, "rabbit", changes)
        return cls(**{**_RABBIT_DEFAULTS, **_RABBIT_INVARIANT, **changes})
