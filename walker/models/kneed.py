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
from walker._generated import kneed as K
from walker._jit import njit
from walker.models._common import (
    FALL_ANGLE,
    LINEAR_SOLVE_FAILED,
    MIN_STEP,
    TRIPPED,
    fell,
    floating_base_heel_strike,
    impact,
    passive_impact_status,
    relabel,
    stride_end,
    touchdown,
)
from walker.params import MODELS
from walker.status import (
    EVENT_CONTINUE,
    EVENT_IGNORE,
    EVENT_TERMINAL,
)

N_X = 6
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


@njit(cache=True, error_model="numpy")
def _lengths(p):
    shank = p[ix.KNEED_P_SHANK_COM_FROM_FOOT] + p[ix.KNEED_P_SHANK_COM_TO_KNEE]
    thigh = p[ix.KNEED_P_THIGH_COM_FROM_KNEE] + p[ix.KNEED_P_THIGH_COM_TO_HIP]
    return shank, thigh


@njit(cache=True, error_model="numpy")
def _min_step(p):
    """Least step length of a heel strike [m] (``MIN_STEP`` leg lengths)."""
    shank, thigh = _lengths(p)
    return MIN_STEP * (shank + thigh)


@njit(cache=True, error_model="numpy")
def rhs(phase, t, x, p, dx):
    if phase == ix.KNEED_PHASE_UNLOCKED:
        dx[0] = x[3]
        dx[1] = x[4]
        dx[2] = x[5]
        K.unlocked_accel(x[:3], x[3:], p, dx[3:])
    else:
        # Locked: (q1, q2) and (qd1, qd2) are contiguous slices of the state.
        dx[0] = x[3]
        dx[1] = x[4]
        dx[2] = x[4]
        K.locked_accel(x[:2], x[3:5], p, dx[3:5])
        dx[5] = dx[4]


@njit(cache=True, error_model="numpy")
def jac(phase, t, x, p, J):
    J[:, :] = 0.0
    if phase == ix.KNEED_PHASE_UNLOCKED:
        J[0, 3] = 1.0
        J[1, 4] = 1.0
        J[2, 5] = 1.0
        K.unlocked_accel_jac(x[:3], x[3:], p, J[3:, :])
    else:
        # Locked: rows of q3 and qd3 copy those of q2 and qd2; columns of q3, qd3 are zero.
        a = np.empty((2, 4))
        K.locked_accel_jac(x[:2], x[3:5], p, a)
        J[0, 3] = 1.0
        J[1, 4] = 1.0
        J[2, 4] = 1.0
        for i in range(2):
            J[3 + i, 0] = a[i, 0]
            J[3 + i, 1] = a[i, 1]
            J[3 + i, 3] = a[i, 2]
            J[3 + i, 4] = a[i, 3]
        for j in range(6):
            J[5, j] = J[4, j]


@njit(cache=True, error_model="numpy")
def swing_foot(x, p):
    """(height above the slope, distance ahead of the stance foot along the slope) [m]
    of the swing foot's lowest point."""
    shank, thigh = _lengths(p)
    R = p[_I_R]
    slope = p[_I_SLOPE]
    L = shank + thigh
    psi1 = x[0] + slope
    psi2 = x[1] + slope
    psi3 = x[2] + slope
    height = (L - R) * math.cos(psi1) - thigh * math.cos(psi2) - (shank - R) * math.cos(psi3)
    ahead = -(L - R) * math.sin(psi1) + thigh * math.sin(psi2) + (shank - R) * math.sin(psi3)
    return height, ahead


@njit(cache=True, error_model="numpy")
def _swing_foot_rate(x, p):
    shank, thigh = _lengths(p)
    R = p[_I_R]
    slope = p[_I_SLOPE]
    L = shank + thigh
    return (
        -(L - R) * math.sin(x[0] + slope) * x[3]
        + thigh * math.sin(x[1] + slope) * x[4]
        + (shank - R) * math.sin(x[2] + slope) * x[5]
    )


@njit(cache=True, error_model="numpy")
def guards(phase, t, x, p, g):
    psi1 = x[0] + p[_I_SLOPE]
    g[ix.KNEED_GUARD_KNEE_LOCK] = x[2] - x[1] if phase == ix.KNEED_PHASE_UNLOCKED else 1.0
    g[ix.KNEED_GUARD_SWING_FOOT_CONTACT] = swing_foot(x, p)[0]
    g[ix.KNEED_GUARD_FALL_FORWARD] = psi1 + FALL_ANGLE
    g[ix.KNEED_GUARD_FALL_BACKWARD] = psi1 - FALL_ANGLE


@njit(cache=True, error_model="numpy")
def knee_lock(x, p, x_new, impulse):
    """Plastic knee-lock impact; ``impulse[0]`` is the knee impulse [N m s]."""
    M = np.empty((3, 3))
    K.unlocked_mass_matrix(x[:3], p, M)
    J = np.array([[0.0, -1.0, 1.0]])
    qd_plus = np.empty(3)
    lam = np.empty(1)
    if not impact(M, J, x[3:], qd_plus, lam):
        return LINEAR_SOLVE_FAILED
    relabel(x, qd_plus, (0, 1, 1), x_new)  # the shank takes the thigh's angle and rate
    impulse[0] = lam[0]
    impulse[1] = 0.0
    return 0


@njit(cache=True, error_model="numpy")
def heel_strike(x, p, x_new, impulse):
    """Floating-base heel strike (knee locked) and leg swap; the new swing knee is straight
    and unlocked.  ``impulse`` = (along slope, normal) on the new stance foot [N s]."""
    # the knee is locked: the 2-link kernels, the hip at row 1 of the 5 locked points
    qdf_plus = np.empty(4)
    ok, lift = floating_base_heel_strike(
        K.locked_points,
        K.locked_hip_jac,
        K.ext_mass_matrix,
        K.ext_swing_contact_jac,
        K.ext_stance_contact_jac,
        x[0:2],
        x[3:5],
        p,
        5,
        1,
        p[_I_SLOPE],
        qdf_plus,
        impulse,
    )
    if not ok:
        return LINEAR_SOLVE_FAILED
    relabel(x, qdf_plus, (1, 0, 0), x_new)  # the legs swap, the new swing knee straight
    return passive_impact_status(impulse, lift)


@njit(cache=True, error_model="numpy")
def _knee_lock_event(phase, x, p, x_new, impulse, ignore_scuff):
    """Knee lock, followed in the same reset by heel strike when the swing foot is on the
    ground (within the integrator's guard tolerance), ahead and moving down.  Under
    ``"trip"`` a foot below the ground counts as on it (it cannot be deeper than the guard
    tolerance with the knee bent); under ``"ignore"`` a foot deeper than that tolerance is
    passing through the ground and heel strike waits for its next descent."""
    status = knee_lock(x, p, x_new, impulse)
    if status != 0:
        return EVENT_TERMINAL, phase, status
    shank, thigh = _lengths(p)
    height, ahead = swing_foot(x_new, p)
    touching = height <= 1e-9 * (shank + thigh)
    if ignore_scuff:
        touching = touching and height >= -1e-9 * (shank + thigh)
    if touching and ahead > MIN_STEP * (shank + thigh) and _swing_foot_rate(x_new, p) < 0:
        locked = x_new.copy()
        return stride_end(1, heel_strike(locked, p, x_new, impulse))
    return EVENT_CONTINUE, 1, 0


@njit(cache=True, error_model="numpy")
def _reset(phase, k, x, p, x_new, impulse, ignore_scuff):
    for i in range(x.shape[0]):
        x_new[i] = x[i]
    impulse[0] = 0.0
    impulse[1] = 0.0
    if k == 0:
        return _knee_lock_event(phase, x, p, x_new, impulse, ignore_scuff)
    if k == 1:
        if phase == ix.KNEED_PHASE_UNLOCKED:
            if abs(x[2] - x[1]) <= _KNEE_TOL and swing_foot(x, p)[1] > _min_step(p):
                # The knee locks at this same instant (its guard a hair behind): knee lock
                # first, then heel strike, as when the knee-lock guard fires first.
                return _knee_lock_event(phase, x, p, x_new, impulse, ignore_scuff)
            if ignore_scuff:
                # swing_scuff = "ignore": the bent-knee swing foot passes through the ground.
                return EVENT_IGNORE, phase, 0
            return EVENT_TERMINAL, phase, TRIPPED
        shank, thigh = _lengths(p)
        return touchdown(swing_foot, heel_strike, shank + thigh, phase, x, p, x_new, impulse)
    return fell(phase, k == 2)


@njit(cache=True, error_model="numpy")
def reset(phase, k, t, x, p, x_new, impulse):
    """Reset map, ``swing_scuff = "trip"``: a swing foot reaching the ground with the knee
    bent ends the run ``TRIPPED``."""
    return _reset(phase, k, x, p, x_new, impulse, False)


@njit(cache=True, error_model="numpy")
def reset_ignore_scuff(phase, k, t, x, p, x_new, impulse):
    """Reset map, ``swing_scuff = "ignore"``: a swing foot reaching the ground with the knee
    bent is ignored (``EVENT_IGNORE``); everything else as :func:`reset`."""
    return _reset(phase, k, x, p, x_new, impulse, True)


@njit(cache=True, error_model="numpy")
def energy(x, p):
    """(kinetic, potential) [J]; valid in both phases (locked: q3 = q2, qd3 = qd2)."""
    return K.unlocked_kinetic(x[:3], x[3:], p), K.unlocked_potential(x[:3], p)


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
    """:func:`swing_foot` and its rate over the rows of ``x`` (n, 6), in numpy (the same
    formulas, so that ``walker run`` checks a stored run without importing numba):
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
    >>> from walker.stride import simulate
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
:meth:`walker.stride.StrideMap.basin_batch`, rely on it; tests/test_basin.py checks it)."""


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


def points(x, p):
    """Joint positions for drawing: stance contact, hip, knee, swing contact [m]."""
    pts = np.empty((5, 2))
    K.unlocked_points(np.ascontiguousarray(x[:3], dtype=np.float64), p, pts)
    return pts[[0, 1, 2, 4]]


SEGMENTS = ((0, 1), (1, 2), (2, 3))
KERNEL_HASH = K.KERNEL_HASH
