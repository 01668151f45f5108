"""What tests/test_stress.py measures: the stable gaits, long runs with their energy
bookkeeping, two toy systems whose guard dips below zero for a given time, scaled compass
parameters and the one-stride error against a tight reference.

``scripts/stress.py`` measures the same things at full size for ``results/stress/``; it keeps
its own code (a script imports from walker only), these are the short versions the tests need.
"""

from __future__ import annotations

import math
from pathlib import Path

import _toy_systems
import numpy as np
from _toy_systems import njit
from scipy.integrate import solve_ivp

from walker import load_scene
from walker.analysis.fixedpoint import find_fixed_point
from walker.models import get_model
from walker.simulation.integrate import hybrid_solve
from walker.simulation.stride import StrideMap, simulate
from walker.status import EVENT_STRIDE, Status

GAITS = Path(__file__).resolve().parents[1] / "gaits"
SCENE_OF = {"compass": "compass_goswami.toml", "kneed": "kneed_hsu.toml"}
GAIT_TOL = 1e-12  # rtol = atol of the gaits' stride maps and of the long runs


def gait(model: str):
    """``(StrideMap, FixedPoint)``: the shipped scene's stable gait of ``model`` ("compass"
    or "kneed"), Newton from the scene's state at ``rtol = atol = GAIT_TOL``."""
    scene = load_scene(GAITS / SCENE_OF[model])
    P = StrideMap(model, scene.params, rtol=GAIT_TOL, atol=GAIT_TOL)
    return P, find_fixed_point(P, P.project(scene.state), tol=1e-13)


def _walker_mass(params) -> float:
    """Total mass [kg]: the hip plus two of every leg segment."""
    segments = [k for k in params.to_dict() if k.startswith("mass_") and k != "mass_hip"]
    assert segments in (["mass_leg"], ["mass_thigh", "mass_shank"]), segments
    return params.mass_hip + 2.0 * sum(getattr(params, k) for k in segments)


def long_run(model: str, n_strides: int, chunk: int = 1000, restart_time: bool = False):
    """Walk ``n_strides`` strides from the gait, ``chunk`` per compiled call, each call from
    the last one's state and time (or from ``t = 0`` with ``restart_time``).

    Returns a dict: ``status`` (name), ``n_strides`` (heel strikes done), ``max_dev`` (the
    largest max-norm distance of a post-heel-strike state from the gait), ``released`` (total
    mass * g * the drop of the stance foot, summed over heel strikes [J]), ``lost`` (kinetic
    energy lost in all impacts [J]) and ``closure`` = ``|lost - released| / released``.
    A heel strike is the compass gait's only event; the kneed walker's is the one that ends
    in phase 0 (a knee lock ends in the locked phase 1).
    """
    P, fp = gait(model)
    m, params = P.model, P.params
    p = params.as_array()
    weight = _walker_mass(params) * params.g
    x, t = fp.state.copy(), 0.0
    done, max_dev, lost, released = 0, 0.0, 0.0, 0.0
    status = Status.COMPLETED
    while done < n_strides:
        k = min(chunk, n_strides - done)
        t_end = t + 20.0 * k * fp.step_time
        tol = {"rtol": GAIT_TOL, "atol": GAIT_TOL}
        sol = hybrid_solve(m.system, x, p, t0=t, t_max=t_end, n_strides=k, output="events", **tol)
        if not sol.success:
            status = sol.status
            break
        log = sol.events
        for pre, post, phase in zip(log.x_pre, log.x_post, log.phase_after, strict=True):
            lost += m.energy(pre, params)[0] - m.energy(post, params)[0]
            if model == "kneed" and phase != 0:
                continue  # a knee lock
            joints = m.points(pre, params)  # stance foot first, swing foot last
            released += weight * (joints[0, 1] - joints[-1, 1])
            max_dev = max(max_dev, float(np.abs(post - fp.state).max()))
            done += 1
        x = sol.x
        t = 0.0 if restart_time else sol.t
    closure = abs(lost - released) / released if released > 0 else math.nan
    return {
        "status": status.name,
        "n_strides": done,
        "max_dev": max_dev,
        "released": released,
        "lost": lost,
        "closure": closure,
    }


# ----------------------------------------------------------------------------------- grazing
# OSCILLATOR: u' = v, v' = -u; guard c - u (c = p[0]), fired downward, so from u = -cos t it
# dips below zero while u > c: for 2 arccos(c) around t = pi, at most 1 - c deep.
# PARABOLA: x' = 1 (x = t from 0); guard (x - 1)^2 - e^2 (e = p[0]), fired downward: below
# zero for |t - 1| < e.  Its motion is linear, so DOP853's error estimate is exactly zero.
# Either reset ends the run as one completed stride.


@njit(cache=True)
def _circle_rhs(phase, t, x, p, dx):
    dx[0], dx[1] = x[1], -x[0]


@njit(cache=True)
def _circle_jac(phase, t, x, p, J):
    J[0, 0], J[0, 1], J[1, 0], J[1, 1] = 0.0, 1.0, -1.0, 0.0


@njit(cache=True)
def _circle_guard(phase, t, x, p, g):
    g[0] = p[0] - x[0]


@njit(cache=True)
def _line_rhs(phase, t, x, p, dx):
    dx[0], dx[1] = 1.0, 0.0


@njit(cache=True)
def _line_jac(phase, t, x, p, J):
    J[:, :] = 0.0


@njit(cache=True)
def _line_guard(phase, t, x, p, g):
    g[0] = (x[0] - 1.0) ** 2 - p[0] ** 2


@njit(cache=True)
def _one_stride(phase, k, t, x, p, x_new, impulse):
    return EVENT_STRIDE, phase, 0


def _toy(name, rhs, jac, guard):
    """A toy HybridSystem (tests/_toy_systems.py: numba's or ctypes' bridge)."""
    down = np.full((1, 1), -1, dtype=np.int64)
    return _toy_systems.toy_system(name, 2, (rhs, guard, _one_stride, jac), down, (name,), ("dip",))


def toy_system(kind: str):
    """The ``kind`` toy ("oscillator" or "parabola")."""
    if kind == "oscillator":
        return _toy("oscillator", _circle_rhs, _circle_jac, _circle_guard)
    return _toy("parabola", _line_rhs, _line_jac, _line_guard)


def graze_found(kind: str, duration: float, tol: float) -> tuple[bool, float]:
    """(guard crossing found, its time) for a dip of ``duration`` [s] of the ``kind`` toy
    ("oscillator": centred at t = pi; "parabola": at t = 1), at ``rtol = atol = tol``."""
    system = toy_system(kind)
    if kind == "oscillator":
        x0, c, t_max = [-1.0, 0.0], math.cos(duration / 2), 2 * math.pi
    else:
        x0, c, t_max = [0.0, 0.0], duration / 2, 3.0
    sol = hybrid_solve(system, x0, [c], t_max=t_max, rtol=tol, atol=tol, n_interior=4)
    return sol.status == Status.COMPLETED, float(sol.t)


# ----------------------------------------------------------------------------------- scaling

# (mass, length) exponents of the compass parameters that carry a dimension (g: see below)
_COMPASS_DIMENSIONS = {
    "mass_hip": (1, 0),
    "mass_leg": (1, 0),
    "com_from_foot": (0, 1),
    "com_to_hip": (0, 1),
    "inertia_leg": (1, 2),
    "foot_radius": (0, 1),
}


def scaled_compass(params, lam: float, kappa: float, mu: float = 1.0):
    """The same dimensionless compass walker with lengths times ``lam``, masses times ``mu``
    and ``g`` times ``kappa``.  Only for walkers without dampers or friction."""
    assert params.damping_hip == params.damping_ankle == 0.0
    fields = {k: getattr(params, k) * mu**a * lam**b for k, (a, b) in _COMPASS_DIMENSIONS.items()}
    return params.replace(g=params.g * kappa, **fields)


# ------------------------------------------------------------------------- tolerance sweep


def scipy_compass_stride(params, x0, tol: float):
    """(state just after heel strike, step time) of one compass stride from ``x0`` with
    scipy's DOP853 at ``rtol = atol = tol``: the first downward zero of the swing foot's
    height while it is ahead of the stance foot (the mid-stance scuff behind it is no heel
    strike: the compiled reset ignores it), then the model's own compiled reset."""
    m = get_model("compass")
    p = params.as_array()

    def rhs(t, y):
        return m.rhs(0, y, p, t)

    def height(t, y):
        return m.guards(0, y, p, t)[0]

    height.direction = -1
    run = solve_ivp(rhs, (0.0, 5.0), x0, method="DOP853", rtol=tol, atol=tol, events=height)
    for te, ye in zip(run.t_events[0], run.y_events[0], strict=True):
        action, _, _, x_new, _ = m.reset(0, 0, ye, p, te)
        if action == EVENT_STRIDE:
            return x_new, float(te)
    raise AssertionError("scipy found no heel strike")


def tolerance_sweep(model: str, tols, ref_tol: float = 3e-14):
    """One stride from the gait at each ``rtol = atol`` in ``tols`` against the stride at
    ``ref_tol``.  Returns (rows, scipy_diff): rows of ``rtol``, ``status`` (name), ``err``
    (max-norm state error after the heel strike) and ``estimate``
    (``Solution.error_estimate``); for the compass gait, the max-norm difference of the
    reference from scipy's DOP853 stride at 1e-13 (else None)."""
    P, fp = gait(model)
    ref = simulate(model, P.params, fp.state, rtol=ref_tol, atol=ref_tol)
    scipy_diff = None
    if model == "compass":
        x_scipy, _ = scipy_compass_stride(P.params, fp.state, 1e-13)
        scipy_diff = float(np.abs(x_scipy - ref.x).max())
    rows = []
    for tol in tols:
        sol = simulate(model, P.params, fp.state, rtol=tol, atol=tol)
        rows.append(
            {
                "rtol": tol,
                "status": sol.status.name,
                "err": float(np.abs(sol.x - ref.x).max()),
                "estimate": sol.error_estimate,
            }
        )
    return rows, scipy_diff
