"""Physical parameters of each model: frozen dataclasses with units, bounds and validation.

Every field is a physical quantity with a unit, a one-line doc and admissible bounds, stored
in the field's ``metadata``; none has a default. The order of the fields is the canonical
order of the parameter vector ``p`` that the generated kernels take: ``params.as_array()``
builds it and ``cls.from_array(p)`` reads it back.

Validation runs in ``__post_init__``, before anything uses the values:

1. every value is a real, finite number (``TypeError`` for ``bool``, ``str``, complex and other
   non-numbers; ``ValueError`` for NaN and infinities); values are stored as ``float``;
2. every value lies inside its bounds (``ValueError`` naming the field, the rule and the unit);
3. cross-field rules of each model (a centre of mass inside its link, a foot radius smaller
   than the segment it sits on).

Published parameter sets are classmethods (``CompassParams.goswami()``), each citing its
source, and are listed in the class attribute ``PRESETS``.

Models and their state vectors (absolute angles from the vertical, counterclockwise positive,
unless stated otherwise) are listed in :data:`STATE_NAMES`; :data:`PARAMS` maps a model name
to its parameter class.

Examples
--------
>>> from walker.params import CompassParams
>>> p = CompassParams.goswami()
>>> p.names()[:3]
('mass_hip', 'mass_leg', 'com_from_foot')
>>> p.leg_length
1.0
>>> CompassParams.from_array(p.as_array()) == p
True
>>> p.replace(mass_hip=-1.0)
Traceback (most recent call last):
...
ValueError: `mass_hip` must be > 0 [kg], got -1.0
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

__all__ = [
    "PARAMS",
    "STATE_NAMES",
    "HAS_EVENTS",
    "STATE_UNITS",
    "SimplestParams",
    "CompassParams",
    "CompassCoulombParams",
    "KneedParams",
    "KneedCoulombParams",
    "DoublePendulumParams",
    "ThreeLinkParams",
    "FiveLinkParams",
    "RimlessWheelParams",
    "params_class",
]

_HALF_PI = 0.5 * math.pi


def _param(
    unit: str,
    doc: str,
    lo: float | None = None,
    hi: float | None = None,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    bounds_text: str | None = None,
) -> Any:
    """A dataclass field without default, carrying unit, doc and bounds in its metadata.

    ``bounds_text`` replaces the printed bounds in error messages (e.g. ``"pi/2"``).
    """
    return dataclasses.field(
        metadata={
            "unit": unit,
            "doc": doc,
            "bounds": (lo, hi),
            "lo_open": lo_open,
            "hi_open": hi_open,
            "bounds_text": bounds_text,
        }
    )


def _slope_field() -> Any:
    return _param(
        "rad",
        "ramp angle, positive downhill in the walking direction",
        -_HALF_PI,
        _HALF_PI,
        lo_open=True,
        hi_open=True,
        bounds_text="(-pi/2, pi/2)",
    )


def _damping_field(joint: str, rate: str) -> Any:
    return _param(
        "N m s/rad",
        f"viscous damping of the {joint} joint, torque -b ({rate}) on the distal link",
        0.0,
    )


def _check_number(name: str, value: Any) -> float:
    """Return ``value`` as a finite float, or raise naming ``name``."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise TypeError(f"`{name}` must be a real number, got {type(value).__name__} {value!r}")
    try:
        value = float(value)
    except OverflowError:
        raise ValueError(f"`{name}` must be finite, got an integer too large for a float") from None
    if not math.isfinite(value):
        raise ValueError(f"`{name}` must be finite, got {value!r}")
    return value


def _rule_text(meta: Mapping[str, Any]) -> str:
    """Human-readable bound rule, e.g. ``"> 0"`` or ``"in (-pi/2, pi/2)"``."""
    lo, hi = meta["bounds"]
    if meta.get("bounds_text"):
        return "in " + meta["bounds_text"]
    if lo is not None and hi is not None:
        left = "(" if meta["lo_open"] else "["
        right = ")" if meta["hi_open"] else "]"
        return f"in {left}{lo:g}, {hi:g}{right}"
    if lo is not None:
        return f"{'>' if meta['lo_open'] else '>='} {lo:g}"
    if hi is not None:
        return f"{'<' if meta['hi_open'] else '<='} {hi:g}"
    return ""


def _check_bounds(name: str, value: float, meta: Mapping[str, Any]) -> None:
    lo, hi = meta["bounds"]
    bad = False
    if lo is not None:
        bad |= value <= lo if meta["lo_open"] else value < lo
    if hi is not None:
        bad |= value >= hi if meta["hi_open"] else value > hi
    if bad:
        raise ValueError(f"`{name}` must be {_rule_text(meta)} [{meta['unit']}], got {value!r}")


class _Params:
    """Behaviour shared by every parameter dataclass (subclasses are frozen dataclasses).

    Subclass contract:

    1. be decorated ``@dataclasses.dataclass(frozen=True)`` with every field made by
       ``_param`` (unit, doc, bounds; no default), in the canonical kernel order;
    2. set ``MODEL`` (the key in :data:`PARAMS`) and ``PRESETS`` (names of the preset
       classmethods, each callable with no argument);
    3. put cross-field rules in ``_check_relations``, raising ``ValueError`` that names the
       fields and the rule.
    """

    MODEL: ClassVar[str] = ""
    PRESETS: ClassVar[tuple[str, ...]] = ()

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):  # type: ignore[arg-type]
            value = _check_number(f.name, getattr(self, f.name))
            _check_bounds(f.name, value, f.metadata)
            object.__setattr__(self, f.name, value)
        self._check_relations()

    def _check_relations(self) -> None:
        """Cross-field rules; the base class has none."""

    # ---- names, units, docs -------------------------------------------------------------
    @classmethod
    def names(cls) -> tuple[str, ...]:
        """Field names in the canonical order of ``p``."""
        return tuple(f.name for f in dataclasses.fields(cls))  # type: ignore[arg-type]

    @classmethod
    def units(cls) -> dict[str, str]:
        """Field name -> unit, in canonical order."""
        return {f.name: f.metadata["unit"] for f in dataclasses.fields(cls)}  # type: ignore[arg-type]

    @classmethod
    def docs(cls) -> dict[str, str]:
        """Field name -> one-line description, in canonical order."""
        return {f.name: f.metadata["doc"] for f in dataclasses.fields(cls)}  # type: ignore[arg-type]

    @classmethod
    def bounds(cls) -> dict[str, tuple[float | None, float | None]]:
        """Field name -> ``(lo, hi)`` (``None`` where unbounded); see the metadata for openness."""
        return {f.name: f.metadata["bounds"] for f in dataclasses.fields(cls)}  # type: ignore[arg-type]

    @classmethod
    def n_params(cls) -> int:
        """Length of the parameter vector ``p``."""
        return len(dataclasses.fields(cls))  # type: ignore[arg-type]

    # ---- conversions --------------------------------------------------------------------
    def as_array(self) -> np.ndarray:
        """The parameter vector ``p``, shape ``(n_params,)``, float64, canonical order."""
        return np.array([getattr(self, n) for n in self.names()], dtype=np.float64)

    @classmethod
    def from_array(cls, p: Any):
        """Build from a parameter vector ``p`` of shape ``(n_params,)`` (validated)."""
        arr = np.asarray(p)
        n = cls.n_params()
        if arr.shape != (n,):
            raise ValueError(
                f"`p` must have shape ({n},) for {cls.__name__} "
                f"({', '.join(cls.names())}), got shape {arr.shape}"
            )
        if not np.issubdtype(arr.dtype, np.number) or np.issubdtype(arr.dtype, np.complexfloating):
            raise TypeError(f"`p` must hold real numbers, got dtype {arr.dtype}")
        return cls(*(float(v) for v in arr.astype(np.float64)))

    def to_dict(self) -> dict[str, float]:
        """Field name -> value (float), in canonical order."""
        return {n: getattr(self, n) for n in self.names()}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]):
        """Build from a mapping holding every field and nothing else (validated)."""
        if not isinstance(d, Mapping):
            raise TypeError(f"`d` must be a mapping, got {type(d).__name__}")
        names = cls.names()
        unknown = [k for k in d if k not in names]
        missing = [n for n in names if n not in d]
        if unknown:
            raise ValueError(
                f"unknown {cls.__name__} key(s) {', '.join(f'`{k}`' for k in unknown)}; "
                f"valid keys: {', '.join(names)}"
            )
        if missing:
            raise ValueError(
                f"missing {cls.__name__} key(s) {', '.join(f'`{k}`' for k in missing)}"
            )
        return cls(**{n: d[n] for n in names})

    def replace(self, **changes: Any):
        """A copy with ``changes`` applied and validated; an unknown name raises ValueError."""
        names = self.names()
        unknown = [k for k in changes if k not in names]
        if unknown:
            raise ValueError(
                f"unknown {type(self).__name__} parameter(s) "
                f"{', '.join(f'`{k}`' for k in unknown)}; valid names: {', '.join(names)}"
            )
        return dataclasses.replace(self, **changes)  # type: ignore[type-var]

    def _replace_validated(self, **changes: float):
        """A copy with ``changes`` applied WITHOUT validation, for values already validated
        by :meth:`replace` (a sweep validates every grid point before any work, then its
        workers rebuild the points cheaply).  Not for user input."""
        new = object.__new__(type(self))
        for name in self.names():
            object.__setattr__(new, name, float(changes.get(name, getattr(self, name))))
        return new

    @classmethod
    def preset(cls, name: str, **changes: Any):
        """The published parameter set ``name`` (one of ``PRESETS``), with ``changes`` applied."""
        if name not in cls.PRESETS:
            raise ValueError(
                f"unknown {cls.__name__} preset `{name}`; valid presets: {', '.join(cls.PRESETS)}"
            )
        base = getattr(cls, name)()
        return base.replace(**changes) if changes else base


def _relation_error(rule: str, got: str) -> ValueError:
    return ValueError(f"{rule}, got {got}")


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
        """Defaults of Drake's compass gait [1]_: m_H = 10, m = 5, l = 1, centre of mass 0.5
        from the hip (point-mass legs), g = 9.81, slope 0.0525 rad; undamped
        (``damping_hip = damping_ankle = 0``).

        References
        ----------
        .. [1] Drake, ``examples/compass_gait/compass_gait_params_named_vector.yaml``.
        """
        return cls(
            mass_hip=10.0,
            mass_leg=5.0,
            com_from_foot=0.5,
            com_to_hip=0.5,
            inertia_leg=0.0,
            foot_radius=0.0,
            slope=0.0525,
            g=9.81,
            damping_hip=0.0,
            damping_ankle=0.0,
        )


# ------------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class CompassCoulombParams(_Params):
    """Compass-gait walker with Coulomb (dry) friction at the stance ankle and the hip (model
    ``compass_coulomb``).

    The fields of :class:`CompassParams`, in the same order (so ``p[:10]`` is a compass
    parameter vector, viscous dampers included), then ``coulomb_ankle`` and ``coulomb_hip``.
    Stick and slip are phases and events (:mod:`walker.models.compass_coulomb`), not a smooth
    approximation of ``sgn``.

    Attributes
    ----------
    mass_hip, mass_leg, com_from_foot, com_to_hip, inertia_leg, foot_radius, slope, g, \
damping_hip, damping_ankle : float
        as in :class:`CompassParams`.
    coulomb_ankle : float
        Coulomb friction torque magnitude F_s of the stance ankle (slope to stance leg) [N m],
        >= 0: ``-F_s sgn(qd_stance)`` on the stance leg while it slips, whatever torque up to
        F_s holds it while it sticks.
    coulomb_hip : float
        F_s of the hip [N m], >= 0: while the hip slips, a torque ``-F_s sgn(qd_swing -
        qd_stance)`` on the swing leg and its opposite on the stance leg; while it sticks,
        whatever torque up to F_s keeps it locked.

    Both zero is the compass gait.

    References
    ----------
    .. [1] Goswami, Thuilot, Espiau, INRIA RR-2996, 1996; IJRR 17(12), 1998.
    """

    MODEL: ClassVar[str] = "compass_coulomb"
    PRESETS: ClassVar[tuple[str, ...]] = ("goswami",)

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
    coulomb_ankle: float = _param(
        "N m",
        "Coulomb friction torque of the stance ankle, -F_s sgn(qd_stance) on the stance leg",
        0.0,
    )
    coulomb_hip: float = _param(
        "N m",
        "Coulomb friction torque of the hip joint, -F_s sgn(qd_swing - qd_stance) on the swing leg",
        0.0,
    )

    leg_length = CompassParams.leg_length

    def _check_relations(self) -> None:
        CompassParams._check_relations(self)  # type: ignore[arg-type]

    @classmethod
    def goswami(
        cls,
        slope: float = math.radians(3.0),
        coulomb_hip: float = 0.0,
        coulomb_ankle: float = 0.0,
    ) -> CompassCoulombParams:
        """:meth:`CompassParams.goswami` (Goswami et al. 1996 [1]_) with dry friction at the
        hip and the stance ankle [N m] (default 0: the published, frictionless model).

        References
        ----------
        .. [1] Goswami, Thuilot, Espiau, INRIA RR-2996, 1996; IJRR 17(12), 1998.
        """
        return cls(
            **CompassParams.goswami(slope).to_dict(),
            coulomb_ankle=coulomb_ankle,
            coulomb_hip=coulomb_hip,
        )


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


def _coulomb_field(joint: str, rate: str) -> Any:
    return _param(
        "N m",
        f"Coulomb (dry) friction torque of the {joint} joint: -F_s sgn({rate}) while it slips, "
        "up to F_s while it sticks",
        0.0,
    )


# ------------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class KneedCoulombParams(KneedParams):
    """Kneed walker with Coulomb (dry) joint friction (model ``kneed_coulomb``).

    The fields of :class:`KneedParams`, in the same order (so ``p[:17]`` is a kneed
    parameter vector, viscous dampers included), then one dry-friction magnitude per joint.
    Stick and slip are phases and events (:mod:`walker.models.kneed_coulomb`), not a smooth
    approximation of ``sgn``.

    Attributes
    ----------
    coulomb_ankle : float
        F_s of the stance ankle (slope to stance leg, rate ``qd1``) [N m], >= 0.
    coulomb_hip : float
        F_s of the hip (rate ``qd2 - qd1``) [N m], >= 0.
    coulomb_knee : float
        F_s of the swing knee while unlocked (rate ``qd3 - qd2``) [N m], >= 0.

    All zero is the frictionless kneed walker (the dampers of :class:`KneedParams` apply as
    given).
    """

    MODEL: ClassVar[str] = "kneed_coulomb"
    PRESETS: ClassVar[tuple[str, ...]] = ("hsu_chen", "mcgeer")

    coulomb_ankle: float = _coulomb_field("stance ankle", "qd1")
    coulomb_hip: float = _coulomb_field("hip", "qd2 - qd1")
    coulomb_knee: float = _coulomb_field("swing knee", "qd3 - qd2")

    @classmethod
    def hsu_chen(
        cls, coulomb_ankle: float = 0.0, coulomb_hip: float = 0.0, coulomb_knee: float = 0.0
    ) -> KneedCoulombParams:
        """:meth:`KneedParams.hsu_chen` with the given dry frictions [N m] (default 0)."""
        return cls(
            **KneedParams.hsu_chen().to_dict(),
            coulomb_ankle=coulomb_ankle,
            coulomb_hip=coulomb_hip,
            coulomb_knee=coulomb_knee,
        )

    @classmethod
    def mcgeer(
        cls, coulomb_ankle: float = 0.0, coulomb_hip: float = 0.0, coulomb_knee: float = 0.0
    ) -> KneedCoulombParams:
        """:meth:`KneedParams.mcgeer` with the given dry frictions [N m] (default 0)."""
        return cls(
            **KneedParams.mcgeer().to_dict(),
            coulomb_ankle=coulomb_ankle,
            coulomb_hip=coulomb_hip,
            coulomb_knee=coulomb_knee,
        )


# ------------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class DoublePendulumParams(_Params):
    """Planar double pendulum (the course's elbow manipulator); link 1 hinged at the origin.

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

    All four zero (the course's preset) is the conservative double pendulum.

    References
    ----------
    .. [1] The course's double-pendulum exercise (point masses on massless links, energy check).
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
        """The course's energy-check pendulum [1]_: m = 1, I = 0.5, l = 1, a = 0.5, g = 10;
        frictionless joints (``damping_* = coulomb_* = 0``).

        References
        ----------
        .. [1] The course's double-pendulum exercise (point masses on massless links, energy check).
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
_BEZIER_DEGREE = 4  # must equal walker.control.BEZIER_DEGREE (checked there)


def _bezier_field(output: str, k: int) -> Any:
    return _param("rad", f"Bezier coefficient {k} of the desired {output} angle")


_POLY_DEGREE = 5  # must equal WK_CONTROL_POLY_DEGREE in walker/_core/wk_control.h


def _poly_field(output: str, k: int) -> Any:
    unit = {0: "rad", 1: "1"}.get(k, f"1/rad^{k - 1}")
    return _param(unit, f"coefficient of q_stance^{k} in the desired {output} angle (controller 3)")


@dataclasses.dataclass(frozen=True)
class ThreeLinkParams(_Params):
    """Grizzle's three-link walker (two legs, torso, two hip actuators) and its controller.

    The first ten fields are the physical parameters the generated kernels take (order of
    :data:`walker.symbolic.actuated.THREE_LINK_PARAMS`); ``friction`` is the ground's Coulomb
    coefficient; then the controller block read by :mod:`walker.control` (layout in its
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
    hip friction (indices 27..41; ``walker.models.three_link`` names them).

    References
    ----------
    .. [1] J. W. Grizzle, G. Abba, F. Plestan, IEEE TAC 46(1):51-64, 2001.
    .. [2] E. R. Westervelt, J. W. Grizzle, D. E. Koditschek, "Hybrid zero dynamics of planar
       biped walkers", IEEE TAC 48(1):42-56, 2003.
    .. [3] Westervelt, Grizzle, Chevallereau, Choi, Morris, *Feedback Control of Dynamic
       Bipedal Robot Locomotion*, CRC Press 2007, example code
       ``model_params_three_link.m``: r = 1, m = 5, Mh = 15, Mt = 10, L = 0.5, g = 9.8.
    """

    MODEL: ClassVar[str] = "three_link"
    PRESETS: ClassVar[tuple[str, ...]] = ("grizzle",)
    ADDED_FIELDS: ClassVar[tuple[str, ...]] = (
        "step_event",
        "ft_alpha",
        "ft_epsilon",
        *(f"poly_{o}_{k}" for o in ("swing", "torso") for k in range(_POLY_DEGREE + 1)),
    )
    """Fields added after three-link files were first written: a file without them was
    computed with heel strike ending the step and no finite-time controller, the values the
    ``grizzle`` preset gives them (:func:`walker.gallery` reads such a file with those)."""

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
        :func:`walker.hzd.make_invariant` (see ``gaits/three_link_grizzle.toml``); the
        invariant values are stored here as numbers (``_GRIZZLE_INVARIANT``; a test checks
        them against ``make_invariant``), so this module imports no analysis code.

        ``changes`` may set what the impact does not depend on (controller, gains, torque
        limit, friction, ``g``, the book controller's fields); a change of the mechanics, the
        slope or the design makes the Bezier coefficients non-invariant, and is refused: pass
        ``ThreeLinkParams.grizzle().replace(...)`` through :func:`walker.hzd.make_invariant`.

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


_GRIZZLE_DEFAULTS: dict[str, float] = {
    # Westervelt et al. 2007, model_params_three_link.m
    "mass_hip": 15.0,
    "mass_leg": 5.0,
    "mass_torso": 10.0,
    "com_from_foot": 0.5,
    "com_to_hip": 0.5,
    "torso_length": 0.5,
    "inertia_leg": 0.0,
    "inertia_torso": 0.0,
    "slope": 0.0,
    "g": 9.8,
    # walker's choices: ground friction, output gains (Westervelt's epsilon = 0.1 gives
    # kp = 1/eps^2, kd = 2/eps), a torque limit that the gait never reaches
    "friction": 0.8,
    "controller": 2.0,
    "kp": 100.0,
    "kd": 20.0,
    "torque_limit": 150.0,
    # step angle pi/8 (control_params_three_link.m: th1d = pi/8); theta_plus, the first two
    # coefficients of each output and bezier_swing_4 are set by make_invariant
    "theta_plus": math.pi / 8,
    "theta_minus": -math.pi / 8,
    "bezier_swing_0": 0.0,
    "bezier_swing_1": 0.0,
    "bezier_swing_2": -0.1,
    "bezier_swing_3": 0.4,
    "bezier_swing_4": 0.0,
    # torso leaning forward by pi/6 (th3d = pi/6 in [3]_'s clockwise convention)
    "bezier_torso_0": 0.0,
    "bezier_torso_1": 0.0,
    "bezier_torso_2": -math.pi / 6,
    "bezier_torso_3": -math.pi / 6,
    "bezier_torso_4": -math.pi / 6,
    # walker's heel strike; the finite-time controller's settings are those of
    # control_params_three_link.m (alpha = 0.9, epsilon = 0.1), unused by controller 2
    "step_event": 0.0,
    "ft_alpha": 0.9,
    "ft_epsilon": 0.1,
    **{f"poly_{o}_{k}": 0.0 for o in ("swing", "torso") for k in range(_POLY_DEGREE + 1)},
    # the published model is frictionless
    "damping_hip": 0.0,
    "coulomb_hip": 0.0,
}

_GRIZZLE_INVARIANT: dict[str, float] = {
    # walker.hzd.make_invariant(ThreeLinkParams(**_GRIZZLE_DEFAULTS)), printed with repr
    # (tests/test_params.py recomputes them)
    "bezier_swing_0": -0.39269908169872414,
    "bezier_swing_1": -0.30240495072649726,
    "bezier_swing_4": 0.39269908169872414,
    "bezier_torso_0": -0.5235987755982988,
    "bezier_torso_1": -1.0141912081225373,
}

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
            "walker.hzd.make_invariant for an HZD-invariant design"
        )


_BOOK_A = (0.512, 0.073, 0.035, -0.819, -2.27, 3.26, 3.11, 1.89)
"""The output coefficients ``a`` of Westervelt et al. 2007's three-link example (the book's
example code, ``walker_main.m``: ``a = [0.512 0.073 0.035 -0.819 -2.27 3.26 3.11 1.89]``)."""

_BOOK_DEFAULTS: dict[str, float] = {
    **_GRIZZLE_DEFAULTS,
    # the book's controller and event (control_params_three_link.m: th1d = pi/8,
    # alpha = 0.9, epsilon = 0.1); the poly_* coefficients come from _BOOK_A
    "controller": 3.0,
    "step_event": 1.0,
    "theta_plus": math.pi / 8,
    "theta_minus": -math.pi / 8,
    "ft_alpha": 0.9,
    "ft_epsilon": 0.1,
    # the book's code has no torque limit and does not check the ground reaction: a limit
    # the gait never reaches, and walker's friction cone mu = 0.8 (which the gait satisfies)
    "torque_limit": 1000.0,
}


@dataclasses.dataclass(frozen=True)
class FiveLinkParams(_Params):
    """The five-link walker (torso, femurs, tibias; hip and knee actuators) and its controller.

    The first thirteen fields are the physical parameters the generated kernels take (order
    of :data:`walker.symbolic.five_link.FIVE_LINK_PARAMS`); ``friction`` is the ground's
    Coulomb coefficient; the rest is the controller block read by :mod:`walker.control`
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
    """

    MODEL: ClassVar[str] = "five_link"
    PRESETS: ClassVar[tuple[str, ...]] = ("rabbit",)

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
        ``gaits/five_link_hzd.toml``), made HZD-invariant by :func:`walker.hzd.make_invariant`
        and stored here as numbers (``_RABBIT_INVARIANT``; a test checks them against it).
        ``changes`` may set what the impact does not depend on (controller, gains, torque
        limit, friction, ``g``); a change of the mechanics, the slope or the design is refused:
        pass ``FiveLinkParams.rabbit().replace(...)`` through :func:`walker.hzd.make_invariant`.

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


_RABBIT_DEFAULTS: dict[str, float] = {
    # Westervelt, Grizzle, Koditschek 2003, Table I (RABBIT; also Chevallereau et al. 2003):
    # M_T = 12, M_f = 6.8, M_t = 3.2 kg; L_f = L_t = 0.4 m; p_MT = 0.24 (from the hip),
    # p_Mf = 0.11 (from the hip), p_Mt = 0.24 m (from the knee); I_T = 1.33, I_f = 0.47,
    # I_t = 0.20 kg m^2 (taken about the centres of mass); g = 9.81
    "mass_torso": 12.0,
    "mass_femur": 6.8,
    "mass_tibia": 3.2,
    "length_femur": 0.4,
    "length_tibia": 0.4,
    "com_torso": 0.24,
    "com_femur": 0.11,
    "com_tibia": 0.24,
    "inertia_torso": 1.33,
    "inertia_femur": 0.47,
    "inertia_tibia": 0.20,
    "slope": 0.0,
    "g": 9.81,
    # walker's choices: ground friction, output gains, a torque limit (RABBIT's motors give
    # about 150 N m at the joints, Chevallereau et al. 2003) and the Bezier design below
    "friction": 0.8,
    "controller": 2.0,
    "kp": 400.0,
    "kd": 40.0,
    "torque_limit": 150.0,
    # theta_plus and the first two coefficients of every output, and the last two of the
    # swing femur and tibia, are set by make_invariant
    "theta_plus": 0.2,
    "theta_minus": -0.2,
    "bezier_knee_0": 0.0,
    "bezier_knee_1": 0.0,
    "bezier_knee_2": 0.3,
    "bezier_knee_3": 0.2,
    "bezier_knee_4": 0.2,
    "bezier_torso_0": 0.0,
    "bezier_torso_1": 0.0,
    "bezier_torso_2": -0.1,
    "bezier_torso_3": -0.1,
    "bezier_torso_4": -0.1,
    "bezier_femur_0": 0.0,
    "bezier_femur_1": 0.0,
    "bezier_femur_2": 0.2,
    "bezier_femur_3": 0.45,
    "bezier_femur_4": 0.0,
    "bezier_tibia_0": 0.0,
    "bezier_tibia_1": 0.0,
    "bezier_tibia_2": -0.6,
    "bezier_tibia_3": 0.2,
    "bezier_tibia_4": 0.0,
    # the published model is frictionless
    "damping_hip": 0.0,
    "damping_knee": 0.0,
    "coulomb_hip": 0.0,
    "coulomb_knee": 0.0,
}


_RABBIT_INVARIANT: dict[str, float] = {
    # walker.hzd.make_invariant(FiveLinkParams(**_RABBIT_DEFAULTS)), printed with repr
    # (tests/test_params.py recomputes them)
    "bezier_knee_0": 0.20000000000000004,
    "bezier_knee_1": 0.26191304879112004,
    "bezier_torso_0": -0.1,
    "bezier_torso_1": -0.12078909628878046,
    "bezier_femur_0": -0.1,
    "bezier_femur_1": -0.19440104689560306,
    "bezier_femur_4": 0.30000000000000004,
    "bezier_tibia_0": -0.30000000000000004,
    "bezier_tibia_1": -0.3911584631046911,
    "bezier_tibia_4": 0.1,
}


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


# ------------------------------------------------------------------------------------------
PARAMS: dict[str, type[_Params]] = {
    "simplest": SimplestParams,
    "compass": CompassParams,
    "kneed": KneedParams,
    "double_pendulum": DoublePendulumParams,
    "three_link": ThreeLinkParams,
    "five_link": FiveLinkParams,
    "compass_coulomb": CompassCoulombParams,
    "kneed_coulomb": KneedCoulombParams,
    "rimless_wheel": RimlessWheelParams,
}
"""Model name -> parameter class."""

STATE_NAMES: dict[str, tuple[str, ...]] = {
    # Garcia et al. 1998: theta stance angle from the slope normal, phi swing relative to stance.
    "simplest": ("theta", "phi", "theta_dot", "phi_dot"),
    # absolute angles from vertical, counterclockwise positive
    "compass": ("q_stance", "q_swing", "qd_stance", "qd_swing"),
    # q1 stance leg, q2 swing thigh, q3 swing shank; absolute, counterclockwise positive
    "kneed": ("q1", "q2", "q3", "qd1", "qd2", "qd3"),
    # q1 link 1, q2 link 2 (the model module states whether q2 is absolute or relative)
    "double_pendulum": ("q1", "q2", "qd1", "qd2"),
    # stance leg, swing leg, torso (absolute, counterclockwise positive); then the actuator
    # work since t0 [J] and the time spent with a saturated torque [s]
    "three_link": (
        "q_stance",
        "q_swing",
        "q_torso",
        "qd_stance",
        "qd_swing",
        "qd_torso",
        "actuator_work",
        "saturated_time",
    ),
    # mean stance-leg angle, stance-knee flexion, torso, swing femur, swing tibia
    # (walker.symbolic.five_link); then the actuator work [J] and saturated time [s]
    "five_link": (
        "q_leg",
        "q_knee",
        "q_torso",
        "q_femur_sw",
        "q_tibia_sw",
        "qd_leg",
        "qd_knee",
        "qd_torso",
        "qd_femur_sw",
        "qd_tibia_sw",
        "actuator_work",
        "saturated_time",
    ),
    # as the compass gait; the hip's stick/slip state is the phase, not a state component
    "compass_coulomb": ("q_stance", "q_swing", "qd_stance", "qd_swing"),
    "kneed_coulomb": ("q1", "q2", "q3", "qd1", "qd2", "qd3"),
    # stance spoke's angle from the slope normal (counterclockwise positive) and its rate
    "rimless_wheel": ("theta", "theta_dot"),
}
"""Model name -> names of the full state's components, in order."""


def _angles_and_rates(n_angles: int, extra: tuple[str, ...] = ()) -> tuple[str, ...]:
    return ("rad",) * n_angles + ("rad/s",) * n_angles + extra


STATE_UNITS: dict[str, tuple[str, ...]] = {
    "simplest": _angles_and_rates(2),
    "compass": _angles_and_rates(2),
    "kneed": _angles_and_rates(3),
    "double_pendulum": _angles_and_rates(2),
    # the two accumulators: actuator work [J] and time with a saturated torque [s]
    "three_link": _angles_and_rates(3, ("J", "s")),
    "five_link": _angles_and_rates(5, ("J", "s")),
    "compass_coulomb": _angles_and_rates(2),
    "kneed_coulomb": _angles_and_rates(3),
    "rimless_wheel": _angles_and_rates(1),
}
"""Model name -> unit of each component of the full state, parallel to :data:`STATE_NAMES`
(angles [rad], their rates [rad/s]; the simplest walker's time unit is ``sqrt(l/g)`` when
``g = leg_length = 1``, as in its ``garcia`` preset)."""

HAS_EVENTS: dict[str, bool] = {
    "simplest": True,
    "compass": True,
    "kneed": True,
    "double_pendulum": False,
    "three_link": True,
    "five_link": True,
    "compass_coulomb": True,
    "kneed_coulomb": True,
    "rimless_wheel": True,
}
"""Model name -> whether the model walks: it has heel strikes, so runs count strides (the
double pendulum has events too, its joint-friction mode switches, but no strides)."""


def params_class(model_name: str) -> type[_Params]:
    """The parameter class of ``model_name`` (a key of :data:`PARAMS`).

    Examples
    --------
    >>> params_class("compass").__name__
    'CompassParams'
    """
    try:
        return PARAMS[model_name]
    except (KeyError, TypeError):
        raise ValueError(
            f"unknown model {model_name!r}; valid models: {', '.join(PARAMS)}"
        ) from None
