"""Parameters of the passive models: the simplest walker, the compass gait, the kneed walker,
the double pendulum and the rimless wheel (one frozen dataclass each; the conventions are in
:mod:`walker.params`).

Examples
--------
>>> from walker.params.passive import KneedParams
>>> KneedParams.mcgeer().leg_length
1.0
"""

from __future__ import annotations

import dataclasses
import math
from typing import ClassVar

from walker.params._base import (
    _coulomb_field,
    _damping_field,
    _param,
    _Params,
    _relation_error,
    _slope_field,
)

__all__ = [
    "SimplestParams",
    "CompassParams",
    "KneedParams",
    "DoublePendulumParams",
    "RimlessWheelParams",
]


# ------------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class SimplestParams(_Params):
    """Garcia's simplest walking model: point hip mass, massless legs, point feet (m/M -> 0).

    Attributes
    ----------
    slope : float
        ramp angle gamma [rad], in (-pi/2, pi/2).
    g : float
        gravitational acceleration [m/s^2], > 0.
    leg_length : float
        leg length l [m], > 0.
    damping_ankle : float
        viscous stance-ankle damping b [1], >= 0, dimensionless in units of
        ``M l^2 sqrt(g/l)`` (M the hip mass): the torque ``-b M l^2 sqrt(g/l) theta_dot`` acts
        on the stance leg relative to the slope, in the swing phase (not in the heel-strike
        impact), so that with g = l = 1 the stance equation reads
        ``theta'' = sin(theta - gamma) - b theta'``.  0: Garcia's passive walker.

    Notes
    -----
    Joint friction.  The legs are massless (the ``m/M -> 0`` limit), so a joint torque that
    acts on the swing leg has no finite meaning: a finite hip torque on a massless leg gives
    it an unbounded acceleration, and only torques that vanish with ``m`` survive the limit.
    There is therefore no hip damper and no hip friction in this model.  The stance ankle
    acts on the stance leg, which carries the hip mass ``M``, so a viscous ankle damper is
    admissible and provided (``damping_ankle``; derived as the limit of the compass gait's
    ``damping_ankle``, :func:`walker.symbolic.models.simplest`).  Dry (Coulomb) ankle friction
    is not provided: use the ``compass_coulomb`` model with a small leg mass
    (``CompassCoulombParams``, ``mass_leg / mass_hip`` small, ``coulomb_ankle``) for that case.

    References
    ----------
    .. [1] M. Garcia, A. Chatterjee, A. Ruina, M. Coleman, "The simplest walking model:
       stability, complexity, and scaling", J. Biomech. Eng. 120(2):281-288, 1998.
    """

    MODEL: ClassVar[str] = "simplest"
    PRESETS: ClassVar[tuple[str, ...]] = ("garcia",)

    slope: float = _slope_field()
    g: float = _param("m/s^2", "gravitational acceleration", 0.0, lo_open=True)
    leg_length: float = _param("m", "leg length, hip to foot", 0.0, lo_open=True)
    damping_ankle: float = _param(
        "1",
        "viscous stance-ankle damping in units of M l^2 sqrt(g/l): torque "
        "-b M l^2 sqrt(g/l) theta_dot on the stance leg",
        0.0,
    )

    @classmethod
    def garcia(cls, slope: float = 0.009) -> SimplestParams:
        """Dimensionless set g = l = 1 of Garcia et al. 1998 [1]_; their stable gait is at 0.009.
        The published model is undamped (``damping_ankle = 0``).

        References
        ----------
        .. [1] Garcia, Chatterjee, Ruina, Coleman, J. Biomech. Eng. 120:281, 1998.
        """
        return cls(slope=slope, g=1.0, leg_length=1.0, damping_ankle=0.0)


# ------------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class CompassParams(_Params):
    """Compass-gait walker: hip point mass, two rigid legs, optional round feet.

    Lengths follow Goswami et al.: a leg's centre of mass sits ``com_from_foot`` (a) from the
    foot and ``com_to_hip`` (b) from the hip, so the leg length is a + b.

    Attributes
    ----------
    mass_hip : float
        point mass at the hip m_H [kg], > 0.
    mass_leg : float
        mass of each leg m [kg], > 0.
    com_from_foot : float
        a: foot to the leg's centre of mass [m], >= 0.
    com_to_hip : float
        b: leg's centre of mass to the hip [m], >= 0; a + b > 0.
    inertia_leg : float
        moment of inertia of a leg about its centre of mass [kg m^2], >= 0.
    foot_radius : float
        radius of the arc foot R [m], >= 0 and < a + b (0: point foot).
    slope : float
        ramp angle [rad], in (-pi/2, pi/2).
    g : float
        gravitational acceleration [m/s^2], > 0.
    damping_hip : float
        viscous hip damping b [N m s/rad], >= 0: torque ``-b (qd_swing - qd_stance)`` on the
        swing leg and its opposite on the stance leg (0: the passive, conservative walker).
    damping_ankle : float
        viscous stance-ankle damping b [N m s/rad], >= 0: torque ``-b qd_stance`` on the
        stance leg, relative to the slope, in single support (not in the impacts).  A point
        foot cannot transmit a torque: the damper models a passive ankle with a foot flat on
        the slope, or rolling resistance (``D qdd + C qd + g = -F_v qd`` with ``F_v`` acting
        on the stance coordinate).  0: the passive, conservative walker.

    References
    ----------
    .. [1] A. Goswami, B. Thuilot, B. Espiau, "Compass-like biped robot part I: stability
       and bifurcation of passive gaits", INRIA RR-2996, 1996; IJRR 17(12), 1998.
    .. [2] M. W. Spong, J. K. Holm, D. Lee, "Passivity-based control of bipedal locomotion",
       IEEE Robotics & Automation Magazine 14(2), 2007.
    """

    MODEL: ClassVar[str] = "compass"
    PRESETS: ClassVar[tuple[str, ...]] = ("goswami", "drake")

    mass_hip: float = _param("kg", "point mass at the hip", 0.0, lo_open=True)
    mass_leg: float = _param("kg", "mass of each leg", 0.0, lo_open=True)
    com_from_foot: float = _param("m", "a: foot to the leg's centre of mass", 0.0)
    com_to_hip: float = _param("m", "b: leg's centre of mass to the hip", 0.0)
    inertia_leg: float = _param("kg m^2", "leg inertia about its centre of mass", 0.0)
    foot_radius: float = _param("m", "radius of the arc foot (0: point foot)", 0.0)
    slope: float = _slope_field()
    g: float = _param("m/s^2", "gravitational acceleration", 0.0, lo_open=True)
    damping_hip: float = _damping_field("hip", "qd_swing - qd_stance")
    damping_ankle: float = _param(
        "N m s/rad",
        "viscous damping of the stance ankle (slope to stance leg), torque -b qd_stance on "
        "the stance leg",
        0.0,
    )

    @property
    def leg_length(self) -> float:
        """Leg length a + b [m]."""
        return self.com_from_foot + self.com_to_hip

    def _check_relations(self) -> None:
        length = self.leg_length
        if not length > 0.0:
            raise _relation_error(
                "leg length `com_from_foot + com_to_hip` must be > 0 [m]", f"{length!r}"
            )
        if not self.foot_radius < length:
            raise _relation_error(
                f"`foot_radius` must be < leg length `com_from_foot + com_to_hip` = {length!r} [m]",
                f"{self.foot_radius!r}",
            )

    @classmethod
    def goswami(cls, slope: float = math.radians(3.0)) -> CompassParams:
        """Goswami, Thuilot, Espiau 1996/1998 [1]_: m_H = 10, m = 5, a = b = 0.5, point masses.

        g = 9.8 as in Spong et al. 2007 [2]_, whose fixed point at 3 degrees is
        [0.2187, -0.3234, -1.0918, -0.3772].  The published model is undamped:
        ``damping_hip = damping_ankle = 0``.

        References
        ----------
        .. [1] Goswami, Thuilot, Espiau, INRIA RR-2996, 1996; IJRR 17(12), 1998.
        .. [2] Spong, Holm, Lee, IEEE Robot. Autom. Mag. 14(2), 2007.
        """
        return cls(
            mass_hip=10.0,
            mass_leg=5.0,
            com_from_foot=0.5,
            com_to_hip=0.5,
            inertia_leg=0.0,
            foot_radius=0.0,
            slope=slope,
            g=9.8,
            damping_hip=0.0,
            damping_ankle=0.0,
        )

    @classmethod
    def drake(cls) -> CompassParams:
        """Defaults of Drake's compass gait [1]_: :meth:`goswami`'s walker (m_H = 10, m = 5,
        l = 1, centre of mass 0.5 from the hip, point-mass legs, undamped) with g = 9.81 on
        the slope 0.0525 rad.

        References
        ----------
        .. [1] Drake, ``examples/compass_gait/compass_gait_params_named_vector.yaml``.
        """
        return cls.goswami(slope=0.0525).replace(g=9.81)


# ------------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class KneedParams(_Params):
    """Kneed walker: hip mass, thigh and shank on each leg, optional round feet.

    Shank: centre of mass ``shank_com_from_foot`` (a1) above the foot and ``shank_com_to_knee``
    (b1) below the knee; thigh: ``thigh_com_from_knee`` (a2) above the knee and
    ``thigh_com_to_hip`` (b2) below the hip (Hsu Chen 2007 names). ``offset_*`` moves a
    segment's centre of mass perpendicular to the segment, positive forward.

    Attributes
    ----------
    mass_hip, mass_thigh, mass_shank : float
        [kg], > 0.
    shank_com_from_foot, shank_com_to_knee, thigh_com_from_knee, thigh_com_to_hip : float
        a1, b1, a2, b2 [m], >= 0; a1 + b1 > 0 and a2 + b2 > 0.
    inertia_thigh, inertia_shank : float
        about each segment's centre of mass [kg m^2], >= 0.
    offset_thigh, offset_shank : float
        fore-aft offset of the segment's centre of mass [m]; |offset| <= segment length.
    foot_radius : float
        radius of the arc foot [m], >= 0 and < shank length.
    slope : float
        [rad], in (-pi/2, pi/2).
    g : float
        [m/s^2], > 0.
    damping_hip : float
        viscous hip damping [N m s/rad], >= 0: torque ``-b (qd2 - qd1)`` on the swing thigh
        and its opposite on the stance leg.
    damping_knee : float
        viscous swing-knee damping [N m s/rad], >= 0: torque ``-b (qd3 - qd2)`` on the swing
        shank and its opposite on the swing thigh; acts only while the knee is unlocked (a
        locked knee does not move, and the stance knee is always locked).
    damping_ankle : float
        viscous stance-ankle damping [N m s/rad], >= 0: torque ``-b qd1`` on the stance leg,
        relative to the slope, with the knee unlocked and locked (not in the impacts).  A
        point foot cannot transmit a torque: the damper models a passive ankle with a foot
        flat on the slope, or rolling resistance (``D qdd + C qd + g = -F_v qd`` with ``F_v``
        acting on the stance coordinate).

    References
    ----------
    .. [1] Hsu Chen, "Passive Dynamic Walking with Knees: A Point Foot Model", M.Eng. thesis,
       MIT, 2007.
    .. [2] T. McGeer, "Passive walking with knees", Proc. IEEE ICRA, 1990.
    """

    MODEL: ClassVar[str] = "kneed"
    PRESETS: ClassVar[tuple[str, ...]] = ("hsu_chen", "mcgeer")

    mass_hip: float = _param("kg", "point mass at the hip", 0.0, lo_open=True)
    mass_thigh: float = _param("kg", "mass of each thigh", 0.0, lo_open=True)
    mass_shank: float = _param("kg", "mass of each shank", 0.0, lo_open=True)
    shank_com_from_foot: float = _param("m", "a1: foot to the shank's centre of mass", 0.0)
    shank_com_to_knee: float = _param("m", "b1: shank's centre of mass to the knee", 0.0)
    thigh_com_from_knee: float = _param("m", "a2: knee to the thigh's centre of mass", 0.0)
    thigh_com_to_hip: float = _param("m", "b2: thigh's centre of mass to the hip", 0.0)
    inertia_thigh: float = _param("kg m^2", "thigh inertia about its centre of mass", 0.0)
    inertia_shank: float = _param("kg m^2", "shank inertia about its centre of mass", 0.0)
    offset_thigh: float = _param("m", "fore-aft offset of the thigh's centre of mass")
    offset_shank: float = _param("m", "fore-aft offset of the shank's centre of mass")
    foot_radius: float = _param("m", "radius of the arc foot (0: point foot)", 0.0)
    slope: float = _slope_field()
    g: float = _param("m/s^2", "gravitational acceleration", 0.0, lo_open=True)
    damping_hip: float = _damping_field("hip", "qd2 - qd1")
    damping_knee: float = _damping_field("swing knee", "qd3 - qd2")
    damping_ankle: float = _param(
        "N m s/rad",
        "viscous damping of the stance ankle (slope to stance leg), torque -b qd1 on the "
        "stance leg",
        0.0,
    )

    @property
    def shank_length(self) -> float:
        """Shank length a1 + b1 [m]."""
        return self.shank_com_from_foot + self.shank_com_to_knee

    @property
    def thigh_length(self) -> float:
        """Thigh length a2 + b2 [m]."""
        return self.thigh_com_from_knee + self.thigh_com_to_hip

    @property
    def leg_length(self) -> float:
        """Leg length, foot to hip with the knee straight [m]."""
        return self.shank_length + self.thigh_length

    def _check_relations(self) -> None:
        ls, lt = self.shank_length, self.thigh_length
        if not ls > 0.0:
            raise _relation_error(
                "shank length `shank_com_from_foot + shank_com_to_knee` must be > 0 [m]",
                f"{ls!r}",
            )
        if not lt > 0.0:
            raise _relation_error(
                "thigh length `thigh_com_from_knee + thigh_com_to_hip` must be > 0 [m]",
                f"{lt!r}",
            )
        if not abs(self.offset_thigh) <= lt:
            raise _relation_error(
                f"|`offset_thigh`| must be <= thigh length {lt!r} [m] (centre of mass near "
                "its link)",
                f"{self.offset_thigh!r}",
            )
        if not abs(self.offset_shank) <= ls:
            raise _relation_error(
                f"|`offset_shank`| must be <= shank length {ls!r} [m] (centre of mass near "
                "its link)",
                f"{self.offset_shank!r}",
            )
        if not self.foot_radius < ls:
            raise _relation_error(
                f"`foot_radius` must be < shank length {ls!r} [m]", f"{self.foot_radius!r}"
            )

    @classmethod
    def hsu_chen(cls) -> KneedParams:
        """Hsu Chen 2007 [1]_ point-foot kneed walker (point masses; g = 9.8 as in the
        thesis's MATLAB code; slope asin(7.25/144)).  The published model is undamped:
        ``damping_hip = damping_knee = damping_ankle = 0``.

        References
        ----------
        .. [1] Hsu Chen, "Passive Dynamic Walking with Knees: A Point Foot Model", M.Eng.
           thesis, MIT, 2007.
        """
        return cls(
            mass_hip=0.5,
            mass_thigh=0.5,
            mass_shank=0.05,
            shank_com_from_foot=0.375,
            shank_com_to_knee=0.125,
            thigh_com_from_knee=0.175,
            thigh_com_to_hip=0.325,
            inertia_thigh=0.0,
            inertia_shank=0.0,
            offset_thigh=0.0,
            offset_shank=0.0,
            foot_radius=0.0,
            slope=math.asin(7.25 / 144.0),
            g=9.8,
            damping_hip=0.0,
            damping_knee=0.0,
            damping_ankle=0.0,
        )

    @classmethod
    def mcgeer(cls) -> KneedParams:
        """McGeer 1990 [1]_ dimensionless round-foot kneed walker (total mass 1, g = 1).

        Thigh: mass 0.1, radius of gyration 0.135, length 0.46, centre of mass 0.20 below the
        hip. Shank: mass 0.062, radius of gyration 0.186, length 0.54, centre of mass 0.24
        below the knee, fore-aft offset 0.01. Foot radius 0.2, hip mass 0.676, slope 0.0456.
        Inertias are m r^2 with r the radius of gyration.  The published model is undamped:
        ``damping_hip = damping_knee = damping_ankle = 0``.

        References
        ----------
        .. [1] T. McGeer, "Passive walking with knees", Proc. IEEE ICRA, 1990.
        """
        return cls(
            mass_hip=0.676,
            mass_thigh=0.1,
            mass_shank=0.062,
            shank_com_from_foot=0.30,  # shank length 0.54 - 0.24
            shank_com_to_knee=0.24,
            thigh_com_from_knee=0.26,  # thigh length 0.46 - 0.20
            thigh_com_to_hip=0.20,
            inertia_thigh=0.1 * 0.135**2,
            inertia_shank=0.062 * 0.186**2,
            offset_thigh=0.0,
            offset_shank=0.01,
            foot_radius=0.2,
            slope=0.0456,
            g=1.0,
            damping_hip=0.0,
            damping_knee=0.0,
            damping_ankle=0.0,
        )


# ------------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class DoublePendulumParams(_Params):
    """Planar double pendulum (the elbow manipulator of [1]_); link 1 hinged at the origin.

    Attributes
    ----------
    mass_1, mass_2 : float
        link masses [kg], > 0.
    inertia_1, inertia_2 : float
        link inertias about their centres of mass [kg m^2], >= 0.
    length_1, length_2 : float
        link lengths [m], > 0.
    com_1, com_2 : float
        proximal joint to the link's centre of mass [m], in [0, length_i].
    g : float
        gravitational acceleration [m/s^2], >= 0.
    damping_1, damping_2 : float
        viscous damping F_v of joint 1 (ground to link 1, rate ``w1 = qd1``) and joint 2
        (link 1 to link 2, rate ``w2 = qd2``, ``q2`` being relative) [N m s/rad], >= 0: the
        torque ``-b_j w_j`` on the distal link and its opposite on the proximal one.
    coulomb_1, coulomb_2 : float
        Coulomb (dry) friction torque F_s of joint 1 and joint 2 [N m], >= 0: ``-F_s sgn(w_j)``
        while the joint slips, whatever torque up to F_s holds it while it sticks; stick and
        slip are phases and events (:mod:`walker.models.double_pendulum`), not a smooth
        approximation of ``sgn``.

    All four zero (the ``course`` preset: the classic energy-check exercise) is the
    conservative double pendulum.

    References
    ----------
    .. [1] M. W. Spong, S. Hutchinson, M. Vidyasagar, *Robot Modeling and Control*, Wiley,
       2006, ch. 7 (the planar elbow manipulator).
    """

    MODEL: ClassVar[str] = "double_pendulum"
    PRESETS: ClassVar[tuple[str, ...]] = ("course",)

    mass_1: float = _param("kg", "mass of link 1", 0.0, lo_open=True)
    mass_2: float = _param("kg", "mass of link 2", 0.0, lo_open=True)
    inertia_1: float = _param("kg m^2", "link 1 inertia about its centre of mass", 0.0)
    inertia_2: float = _param("kg m^2", "link 2 inertia about its centre of mass", 0.0)
    length_1: float = _param("m", "length of link 1", 0.0, lo_open=True)
    length_2: float = _param("m", "length of link 2", 0.0, lo_open=True)
    com_1: float = _param("m", "origin to link 1's centre of mass", 0.0)
    com_2: float = _param("m", "elbow to link 2's centre of mass", 0.0)
    g: float = _param("m/s^2", "gravitational acceleration", 0.0)
    damping_1: float = _damping_field("first (ground to link 1)", "qd1")
    damping_2: float = _damping_field("second (link 1 to link 2)", "qd2")
    coulomb_1: float = _coulomb_field("first (ground to link 1)", "qd1")
    coulomb_2: float = _coulomb_field("second (link 1 to link 2)", "qd2")

    def _check_relations(self) -> None:
        for i in (1, 2):
            com, length = getattr(self, f"com_{i}"), getattr(self, f"length_{i}")
            if not com <= length:
                raise _relation_error(
                    f"`com_{i}` must be <= `length_{i}` = {length!r} [m] (centre of mass "
                    "inside its link)",
                    f"{com!r}",
                )

    @classmethod
    def course(cls) -> DoublePendulumParams:
        """The classic energy-check pendulum (the name is the preset's, kept for stored
        files and scenes): m = 1, I = 0.5, l = 1, a = 0.5, g = 10; frictionless joints
        (``damping_* = coulomb_* = 0``), so its total energy is conserved, the check the
        exercise makes (the elbow-manipulator dynamics of Spong, Hutchinson and Vidyasagar,
        *Robot Modeling and Control*, 2006, ch. 7).
        """
        return cls(
            mass_1=1.0,
            mass_2=1.0,
            inertia_1=0.5,
            inertia_2=0.5,
            length_1=1.0,
            length_2=1.0,
            com_1=0.5,
            com_2=0.5,
            g=10.0,
            damping_1=0.0,
            damping_2=0.0,
            coulomb_1=0.0,
            coulomb_2=0.0,
        )


# ------------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class RimlessWheelParams(_Params):
    """The rimless wheel: a point mass at the hub on ``spokes`` massless spokes (the classical
    planar model of McGeer [1]_ and Coleman, Chatterjee, Ruina [2]_).

    Attributes
    ----------
    spokes : float
        number of spokes n [1], an integer >= 3 stored as a float; the angle between
        neighbouring spokes is ``2 alpha``, ``alpha = pi / n`` the half-angle.
    leg_length : float
        spoke length l, hub to foot [m], > 0.
    g : float
        gravitational acceleration [m/s^2], > 0.
    slope : float
        ramp angle gamma [rad], in (-pi/2, pi/2), positive downhill in the rolling direction.

    Notes
    -----
    All the mass sits at the hub, so the wheel has no mass parameter: energies and impulses
    are per unit hub mass (:mod:`walker.models.rimless_wheel`).  With 3 or 4 spokes
    (``cos 2 alpha <= 0``) every impact stops the wheel; it rolls only with 5 spokes or
    more.

    References
    ----------
    .. [1] T. McGeer, "Passive dynamic walking", Int. J. Robotics Research 9(2):62-82, 1990.
    .. [2] M. J. Coleman, A. Chatterjee, A. Ruina, "Motions of a rimless spoked wheel: a
       simple three-dimensional system with impacts", Dynamics and Stability of Systems
       12(3):139-159, 1997.
    """

    MODEL: ClassVar[str] = "rimless_wheel"
    PRESETS: ClassVar[tuple[str, ...]] = ("drake",)

    spokes: float = _param("1", "number of spokes, an integer >= 3 (half-angle pi/spokes)", 3.0)
    leg_length: float = _param("m", "spoke length, hub to foot", 0.0, lo_open=True)
    g: float = _param("m/s^2", "gravitational acceleration", 0.0, lo_open=True)
    slope: float = _slope_field()

    def _check_relations(self) -> None:
        if not self.spokes.is_integer():
            raise _relation_error(
                "`spokes` must be an integer (a whole number of spokes)", f"{self.spokes!r}"
            )

    @classmethod
    def drake(cls, slope: float = 0.08) -> RimlessWheelParams:
        """The defaults of Drake's rimless wheel example [1]_: 8 spokes of 1 m, g = 9.81,
        slope 0.08 rad (its mass, 1 kg, does not enter the motion).

        References
        ----------
        .. [1] Drake, drake/examples/rimless_wheel (RimlessWheelParams defaults).
        """
        return cls(spokes=8.0, leg_length=1.0, g=9.81, slope=slope)
