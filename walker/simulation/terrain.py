"""Terrain defined per step: the ground a walker's strides land on when it is not one plane.

The rule (walker/_core/wk_terrain.h).  During step ``n`` the ground ahead of the stance
contact is the plane through the point a height ``h_n`` (the step's *drop* [m], positive
down) below the stance contact, with slope ``gamma_n`` [rad] (downhill positive, like the
scene's ``slope``).  The step ends at the first touchdown on that plane under the model's
guard and scuff conventions; the next pair belongs to the new stance contact.  The state stays
in the model's own angle frame (the scene slope's), so the phases' equations are the model's:
a step's terrain enters only through the touchdown guard and the ground-referenced quantities
of the impact (impulse directions and the normal-impulse and lift-off checks, the rimless
wheel's landing angle).  A step equal to the scene's plane (slope = the scene's slope,
drop 0) gives the plane's numbers bit for bit.

:class:`Terrain` describes a ground: ``plane`` (today's), ``steps`` (explicit lists) or
``random`` (i.i.d. normal draws); :meth:`Terrain.steps` gives the per-step pairs
``(slope, drop)`` that :meth:`walker.simulation.stride.StrideMap.__call__` (``terrain=``) and
:meth:`walker.simulation.stride.StrideMap.ensemble` take.

Examples
--------
>>> from walker.simulation.terrain import Terrain
>>> Terrain("random", slope_mean=0.01, slope_std=0.002, seed=3).steps(2).shape
(2, 2)
>>> Terrain("steps", heights=(0.01,), slope_mean=0.01).steps(3).tolist()
[[0.01, 0.01], [0.01, 0.0], [0.01, 0.0]]
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

__all__ = ["KINDS", "Terrain"]

KINDS = ("plane", "steps", "random")
"""The kinds of :class:`Terrain`."""


def _real(name: str, value, *, minimum: float | None = None) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"`{name}` must be a real number, got {type(value).__name__}")
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"`{name}` must be finite, got {value!r}")
    if minimum is not None and value < minimum:
        raise ValueError(f"`{name}` must be >= {minimum:g}, got {value!r}")
    return value


def _reals(name: str, values) -> tuple[float, ...]:
    if isinstance(values, str | bytes) or not hasattr(values, "__iter__"):
        raise TypeError(f"`{name}` must be a list of numbers, got {type(values).__name__}")
    return tuple(_real(f"{name}[{i}]", v) for i, v in enumerate(values))


@dataclass(frozen=True)
class Terrain:
    """A ground defined per step.

    Parameters
    ----------
    kind : {"plane", "steps", "random"}
        ``plane``: every step the scene's plane (slope ``slope_mean``, drop 0).
        ``steps``: explicit per-step lists ``slopes`` [rad] and/or ``heights`` (drops) [m],
        one entry per step (a missing list is ``slope_mean`` / 0 throughout; with both they
        must have the same length); past the last entry the steps are the plane.
        ``random``: i.i.d. normal draws, slope ``N(slope_mean, slope_std^2)``, drop
        ``N(0, height_std^2)``, from ``numpy.random.default_rng(seed)``.
    slopes, heights : sequence of float
        ``steps`` only: the steps' slopes [rad] and drops [m] (positive: the ground drops).
    slope_mean : float, optional
        the mean (and the plane's) slope [rad]; None: the scene's slope, passed to
        :meth:`steps` as ``slope`` (:meth:`from_table` fills it in).
    slope_std, height_std : float
        ``random`` only: standard deviations of the slope [rad] and the drop [m], >= 0.
        With both 0 the steps are the plane, bit for bit.
    seed : int, optional
        ``random`` only: the seed of the draws (>= 0); None: fresh entropy.
    """

    kind: str = "plane"
    slopes: tuple = ()
    heights: tuple = ()
    slope_mean: float | None = None
    slope_std: float = 0.0
    height_std: float = 0.0
    seed: int | None = None

    def __post_init__(self):
        if not isinstance(self.kind, str) or self.kind not in KINDS:
            raise ValueError(f"`kind` must be one of {', '.join(KINDS)}, got {self.kind!r}")
        set_ = object.__setattr__
        set_(self, "slopes", _reals("slopes", self.slopes))
        set_(self, "heights", _reals("heights", self.heights))
        if self.slope_mean is not None:
            set_(self, "slope_mean", _real("slope_mean", self.slope_mean))
        set_(self, "slope_std", _real("slope_std", self.slope_std, minimum=0.0))
        set_(self, "height_std", _real("height_std", self.height_std, minimum=0.0))
        if self.seed is not None:
            if isinstance(self.seed, bool) or not isinstance(self.seed, numbers.Integral):
                raise TypeError(f"`seed` must be an int, got {type(self.seed).__name__}")
            if self.seed < 0:
                raise ValueError(f"`seed` must be >= 0, got {self.seed}")
            set_(self, "seed", int(self.seed))
        if self.kind != "steps" and (self.slopes or self.heights):
            raise ValueError(f"`slopes` and `heights` are for kind `steps`, not `{self.kind}`")
        if self.kind != "random" and (self.slope_std or self.height_std):
            raise ValueError(
                f"`slope_std` and `height_std` are for kind `random`, not `{self.kind}`"
            )
        if self.kind == "steps":
            if not self.slopes and not self.heights:
                raise ValueError("`slopes` or `heights` must list the steps of kind `steps`")
            if self.slopes and self.heights and len(self.slopes) != len(self.heights):
                raise ValueError(
                    f"`slopes` and `heights` must have the same length, got "
                    f"{len(self.slopes)} and {len(self.heights)}"
                )

    @classmethod
    def from_table(cls, table: dict, default_slope: float) -> Terrain:
        """A terrain from a scene's ``[terrain]`` table (keys: ``kind``, ``slopes``,
        ``heights``, ``slope_mean``, ``slope_std``, ``height_std``, ``seed``), with
        ``slope_mean`` defaulting to ``default_slope`` (the scene's ``[parameters] slope``).

        Examples
        --------
        >>> Terrain.from_table({"kind": "random", "slope_std": 0.01}, 0.02).slope_mean
        0.02
        """
        if not isinstance(table, dict):
            raise TypeError(f"`table` must be a dict, got {type(table).__name__}")
        known = ("kind", "slopes", "heights", "slope_mean", "slope_std", "height_std", "seed")
        unknown = sorted(set(table) - set(known))
        if unknown:
            raise ValueError(
                f"unknown key(s) {', '.join(unknown)} in [terrain]; known: {', '.join(known)}"
            )
        values = dict(table)
        if values.get("slope_mean") is None:
            values["slope_mean"] = _real("default_slope", default_slope)
        return cls(**values)

    @property
    def is_plane(self) -> bool:
        """True when every step is the plane of slope ``slope_mean`` (``plane``, or ``random``
        with both standard deviations 0)."""
        return self.kind == "plane" or (
            self.kind == "random" and self.slope_std == 0.0 and self.height_std == 0.0
        )

    def steps(self, n: int, rng=None, *, slope: float | None = None) -> np.ndarray:
        """The first ``n`` steps' ``(slope [rad], drop [m])`` pairs, shape ``(n, 2)``.

        Parameters
        ----------
        n : int
            steps, >= 0.
        rng : numpy.random.Generator, optional
            ``random`` only: the generator to draw from; default
            ``numpy.random.default_rng(seed)`` (the same steps on every call with a seed).
            The draws are one ``(n, 2)`` standard-normal array, so the slopes do not depend on
            ``height_std``.
        slope : float, optional
            the plane's slope when ``slope_mean`` is None (the scene's slope).
        """
        if isinstance(n, bool) or not isinstance(n, numbers.Integral):
            raise TypeError(f"`n` must be an int, got {type(n).__name__}")
        if n < 0:
            raise ValueError(f"`n` must be >= 0, got {n}")
        mean = self.slope_mean
        if mean is None:
            if slope is None:
                raise ValueError("`slope` must be given for a terrain without `slope_mean`")
            mean = _real("slope", slope)
        out = np.empty((n, 2), dtype=np.float64)
        out[:, 0] = mean
        out[:, 1] = 0.0
        if self.kind == "steps":
            k = min(n, max(len(self.slopes), len(self.heights)))
            if self.slopes:
                out[: min(k, len(self.slopes)), 0] = self.slopes[:k]
            if self.heights:
                out[: min(k, len(self.heights)), 1] = self.heights[:k]
        elif self.kind == "random" and not self.is_plane:
            if rng is None:
                rng = np.random.default_rng(self.seed)
            draws = rng.standard_normal((n, 2))
            if self.slope_std > 0.0:
                out[:, 0] = mean + self.slope_std * draws[:, 0]
            if self.height_std > 0.0:
                out[:, 1] = self.height_std * draws[:, 1]
        return out

    def as_dict(self) -> dict:
        """The fields as a plain dict (provenance, JSON)."""
        return {
            "kind": self.kind,
            "slopes": list(self.slopes),
            "heights": list(self.heights),
            "slope_mean": self.slope_mean,
            "slope_std": self.slope_std,
            "height_std": self.height_std,
            "seed": self.seed,
        }
