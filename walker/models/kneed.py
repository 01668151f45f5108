"""The kneed walker with point or round feet (McGeer 1990; Hsu Chen 2007): compiled phase
functions for the hybrid integrator.

State ``x = (q1, q2, q3, qd1, qd2, qd3)``: stance leg, swing thigh, swing shank, absolute
angles from the vertical, counterclockwise positive.  Phases:

0. ``unlocked``: 3-DOF swing, knee free.
1. ``locked``: 2-DOF swing, knee locked; ``q3 = q2`` and ``qd3 = qd2`` are kept exactly.

Guards, in priority order (a lower index wins when two fire at the same instant):

0. ``knee_lock`` (phase 0): ``q3 - q2`` increasing through zero, the shank catching the thigh.
   Reset: ``[D, -J^T; J, 0] [qd+; F] = [D qd-; 0]`` with ``J = [0, -1, 1]``, then phase 1.
   If the swing foot is on the ground and moving down at that same instant, heel strike is
   applied in the same reset (knee lock first, then heel strike).
1. ``swing_foot_contact``: swing-foot height above the slope decreasing through zero.  In
   phase 0 (knee bent) it is a trip (``TRIPPED``) under the convention
   ``swing_scuff = "trip"``, and ignored under ``"ignore"`` (see below).  In phase 1 it is
   the heel strike when the swing foot is ahead of the stance foot by more than
   ``MIN_STEP`` leg lengths (a scuff behind it, or the swing leg passing through the stance
   leg, is ignored under both conventions): floating-base impact as an augmented linear
   system, legs swapped, new swing knee straight and unlocked.
2. ``fall_forward`` / 3. ``fall_backward``: the stance leg passes ``FALL_ANGLE`` from the
   slope normal.

Swing-foot scuffing convention (:data:`SWING_SCUFF`, scene key ``[model] swing_scuff``):

- ``"trip"`` (default, :func:`reset`): the swing foot touching the ground while the knee is
  bent ends the run ``TRIPPED``.
- ``"ignore"`` (:func:`reset_ignore_scuff`): the swing foot passes through the ground while
  the knee is bent, as in McGeer's analysis (his machines had foot clearance) and in most
  published kneed-walker codes, which look for heel strike only once the knee has locked.
  A knee lock with the foot on the ground (within the guard tolerance), ahead of the
  stance foot and moving down, is followed by heel strike in the same reset (as under
  ``"trip"``); a knee lock with the foot below the ground is not: heel strike is the foot's
  next descent through the ground ahead of the stance foot.
  :func:`deepest_penetration` reports how deep the foot went.

Both are compiled: ``"ignore"`` is the registry variant ``kneed/ignore_scuff`` (and
``kneed/plain/ignore_scuff``), chosen by :meth:`walker.models.WalkerModel.system_for` for a
model from ``get_model("kneed", swing_scuff="ignore")``; a run under ``"trip"`` does not
look at the convention.
"""

import dataclasses
import math

import numpy as np

from walker._generated import indices as ix
from walker.params import MODELS

N_X = len(MODELS["kneed"].state_names)
N_IMPULSE = 2
PHASE_NAMES = ("unlocked", "locked")
GUARD_NAMES = ("knee_lock", "swing_foot_contact", "fall_forward", "fall_backward")
DIRECTIONS = np.array([[1, -1, -1, 1], [0, -1, -1, 1]], dtype=np.int64)
STATE_NAMES = MODELS["kneed"].state_names  # the model registry (walker.params)
SWING_SCUFF = ("trip", "ignore")
"""Swing-foot scuffing conventions (module docstring); the first is the default."""
SECTION_NAMES = ("q1", "qd1", "qd2")
VARIANTS = {
    "plain": (
        "inertia_thigh",
        "inertia_shank",
        "offset_thigh",
        "offset_shank",
        "foot_radius",
        "damping_hip",
        "damping_knee",
        "damping_ankle",
    )
}
"""Compiled structural variants (:mod:`walker.models`, item 7): ``plain`` is the kneed walker
of point masses on the segments' axes, with point feet and no dampers."""

_I_R, _I_SLOPE = ix.KNEED_P_FOOT_RADIUS, ix.KNEED_P_SLOPE
# |q3 - q2| [rad] below which a foot contact with the knee unlocked counts as simultaneous
# with knee lock rather than as a trip.
_KNEE_TOL = 1e-6


@dataclasses.dataclass(frozen=True)
class Penetration:
    """The swing foot's deepest point below the slope along a trajectory
    (:func:`deepest_penetration`).

    Attributes
    ----------
    depth : float
        how far the swing foot's lowest point went below the slope [m]; 0 when it never
        went below.
    t : float
        when [s] (NaN when ``depth`` is 0).
    ahead : float
        the foot's distance ahead of the stance foot along the slope then [m] (negative:
        behind).
    knee_bend : float
        ``q2 - q3`` then [rad] (0: knee straight).
    phase : int
        the phase then (0 unlocked, 1 locked; -1 when ``depth`` is 0).
    """

    depth: float
    t: float
    ahead: float
    knee_bend: float
    phase: int


def _swing_foot_rows(x, p):
    """The swing foot's height above the slope, its distance ahead of the stance foot and the
    height's rate over the rows of ``x`` (n, 6), in numpy (the same
    formulas as the compiled guard, walker/_core/model_kneed.c, over many rows at once):
    (height, ahead, d height / dt), each (n,)."""
    shank = p[ix.KNEED_P_SHANK_COM_FROM_FOOT] + p[ix.KNEED_P_SHANK_COM_TO_KNEE]
    thigh = p[ix.KNEED_P_THIGH_COM_FROM_KNEE] + p[ix.KNEED_P_THIGH_COM_TO_HIP]
    R = p[_I_R]
    L = shank + thigh
    psi = x[:, :3] + p[_I_SLOPE]
    c, s = np.cos(psi), np.sin(psi)
    height = (L - R) * c[:, 0] - thigh * c[:, 1] - (shank - R) * c[:, 2]
    ahead = -(L - R) * s[:, 0] + thigh * s[:, 1] + (shank - R) * s[:, 2]
    rate = (
        -(L - R) * s[:, 0] * x[:, 3] + thigh * s[:, 1] * x[:, 4] + (shank - R) * s[:, 2] * x[:, 5]
    )
    return height, ahead, rate


def deepest_penetration(solution, p) -> Penetration:
    """How deep the swing foot went below the slope along a stored trajectory: what the
    ``"ignore"`` scuffing convention let pass (and, under ``"trip"``, the locked-knee scuffs
    behind the stance foot that both conventions ignore).

    Between two stored states of one phase the foot height is the cubic Hermite interpolant
    of its value and rate at both ends, minimised on a grid of 64 points per interval, so
    the depth is accurate to the fourth power of the step (about 1e-7 m, 0.01 % of the
    depth, for the McGeer point-mass scene at ``rtol = 1e-12``; tests/test_swing_scuff.py).

    Parameters
    ----------
    solution : walker.results.Solution
        a kneed run with stored states (``output="full"`` or ``"samples"``).
    p : KneedParams or ndarray, shape (17,)
        its parameters.

    Returns
    -------
    Penetration

    Examples
    --------
    >>> from walker import load_scene
    >>> from walker.simulation.stride import simulate
    >>> from walker.models.kneed import deepest_penetration
    >>> scene = load_scene("gaits/kneed_hsu.toml")
    >>> sol = simulate("kneed", scene.params, scene.reference["state"], output="full")
    >>> deepest_penetration(sol, scene.params).depth  # Hsu Chen's gait clears the ground
    0.0
    """
    traj = solution.record if solution.record is not None else solution.samples
    if traj is None:
        raise ValueError(
            "`solution` must hold stored states: simulate with output='full' or 'samples'"
        )
    pa = p.as_array() if hasattr(p, "as_array") else np.ascontiguousarray(p, dtype=np.float64)
    x = np.asarray(traj.x, dtype=np.float64)
    height, ahead, rate = _swing_foot_rows(x, pa)
    best = Penetration(0.0, math.nan, math.nan, math.nan, -1)
    s = np.linspace(0.0, 1.0, 65)
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
    h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
    for i in range(len(traj) - 1):
        t0, t1 = float(traj.t[i]), float(traj.t[i + 1])
        if not t1 > t0 or traj.phase[i] != traj.phase[i + 1]:
            continue  # an event between the two states
        if min(height[i], height[i + 1]) >= 0.0 and rate[i] >= 0.0:
            continue  # above the slope at both ends and not moving down at the first
        dt = t1 - t0
        h = h00 * height[i] + h10 * dt * rate[i] + h01 * height[i + 1] + h11 * dt * rate[i + 1]
        j = int(np.argmin(h))
        if -h[j] > best.depth:
            w = s[j]
            best = Penetration(
                depth=float(-h[j]),
                t=float(t0 + w * dt),
                ahead=float((1 - w) * ahead[i] + w * ahead[i + 1]),
                knee_bend=float((1 - w) * (x[i, 1] - x[i, 2]) + w * (x[i + 1, 1] - x[i + 1, 2])),
                phase=int(traj.phase[i]),
            )
    return best


LIFT_AFFINE = True
"""``lift`` is ``lift(0, p) + lift_jacobian(0, p) z``, each row one term (basin batches,
:meth:`walker.simulation.stride.StrideMap.basin_batch`, rely on it; tests/test_basin.py checks
it)."""


def lift(z, p):
    """Section point ``(q1, qd1, qd2)`` -> full state just after heel strike (knee straight)."""
    q2 = -2.0 * p[_I_SLOPE] - z[0]
    return np.array([z[0], q2, q2, z[1], z[2], z[2]])


def lift_jacobian(z, p):
    return np.array(
        [[1.0, 0, 0], [-1.0, 0, 0], [-1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0], [0, 0, 1.0]]
    )


def project(x, p):
    return np.array([x[0], x[3], x[4]])


SEGMENTS = ((0, 1), (1, 2), (2, 3))
