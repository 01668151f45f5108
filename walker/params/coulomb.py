"""Parameters of the models with Coulomb (dry) joint friction as phases: the compass gait's
and the kneed walker's fields, in the same order, followed by one friction magnitude per
joint (the double pendulum's dry friction is among its own fields, in
:mod:`walker.params.passive`; the actuated walkers' in :mod:`walker.params.actuated`).
"""

from __future__ import annotations

import dataclasses
import math
from typing import ClassVar

from walker.params._base import _coulomb_field, _param
from walker.params.passive import CompassParams, KneedParams

__all__ = ["CompassCoulombParams", "KneedCoulombParams"]


# ------------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class CompassCoulombParams(CompassParams):
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

    @classmethod
    def drake(cls, coulomb_hip: float = 0.0, coulomb_ankle: float = 0.0) -> CompassCoulombParams:
        """:meth:`CompassParams.drake` with dry friction at the hip and the stance ankle [N m]
        (default 0); not one of ``PRESETS``: no scene of this model starts from it."""
        friction = {"coulomb_ankle": coulomb_ankle, "coulomb_hip": coulomb_hip}
        return cls(**CompassParams.drake().to_dict(), **friction)


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
        return cls._rubbing(KneedParams.hsu_chen(), coulomb_ankle, coulomb_hip, coulomb_knee)

    @classmethod
    def mcgeer(
        cls, coulomb_ankle: float = 0.0, coulomb_hip: float = 0.0, coulomb_knee: float = 0.0
    ) -> KneedCoulombParams:
        """:meth:`KneedParams.mcgeer` with the given dry frictions [N m] (default 0)."""
        return cls._rubbing(KneedParams.mcgeer(), coulomb_ankle, coulomb_hip, coulomb_knee)

    @classmethod
    def _rubbing(
        cls, base: KneedParams, coulomb_ankle: float, coulomb_hip: float, coulomb_knee: float
    ) -> KneedCoulombParams:
        """``base`` with the given dry frictions [N m]."""
        return cls(
            **base.to_dict(),
            coulomb_ankle=coulomb_ankle,
            coulomb_hip=coulomb_hip,
            coulomb_knee=coulomb_knee,
        )
