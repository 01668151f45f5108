"""Operational-space control of the planar elbow manipulator: its tip tracks a circle.

The Cartesian form of the arm (:mod:`walker.symbolic.taskspace`),
``M_x x_ddot + V_x + G_x = F + Q_x``, gives the computed-torque law (Khatib 1987 [1]_)

    F   = M_x (x_ddot_d + K_d e_dot + K_p e) + V_x + G_x - Q_x,    e = x_d - x,
    tau = J^T F,

with isotropic, critically damped gains ``K_p = omega_n^2``, ``K_d = 2 omega_n``.  With the
model exact, the closed loop is ``e_ddot + 2 omega_n e_dot + omega_n^2 e = 0`` in each task
coordinate, whose solution is ``e(t) = (e0 + (e_dot0 + omega_n e0) t) exp(-omega_n t)``: the
tracking error is known in closed form from the gains and the initial error, and bounded by
``(|e0| + |e_dot0 + omega_n e0| t) exp(-omega_n t)``.  The arm starts at rest at the circle's
centre, one radius off the path.

The closed loop is integrated with scipy's DOP853, the Runge-Kutta method of ``solve_ivp``,
stepped one step at a time (an example, not walker's hybrid path); the symbolic model is
derived and lambdified once, before any integration.  A second,
short run aims at a circle that leaves the workspace: it ends with status ``singular`` (the
arm straightens) instead of blowing up.

Writes ``results/taskspace/circle.png`` (path and circle; tracking error against time) and
``results/taskspace/circle.md`` (final tracking error and the bound from the gains).
``scripts/gallery.py`` draws the same figure into the gallery through :func:`track_example`
and :func:`plot_tracking`.

Usage: python scripts/taskspace_circle.py [--natural-frequency 4] [--t-final 4] [--out DIR]

References
----------
.. [1] O. Khatib, "A unified approach for motion and force control of robot manipulators:
   the operational space formulation", IEEE J. Robotics and Automation 3(1):43-53, 1987.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
from scipy.integrate import DOP853, OdeSolution  # noqa: E402

import walker  # noqa: E402
from walker.params import DoublePendulumParams  # noqa: E402
from walker.symbolic.taskspace import (  # noqa: E402
    MAX_CONDITION,
    CartesianFunctions,
    SingularConfiguration,
    planar_elbow_cartesian,
)

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "taskspace"

# Status codes of a tracking run (as solve_ivp's: 0 done, -1 failed; plus a singular stop).
SUCCESS = 0  # reached t_final
SINGULAR = 1  # the arm reached cond(J) > max_condition
FAILED = -1  # the integrator failed


@dataclass(frozen=True)
class Circle:
    """A circle traced counterclockwise at constant speed, starting at angle 0.

    Attributes
    ----------
    center : tuple of float
        [m], world frame (x forward, y up), the arm's base at the origin.
    radius : float
        [m], > 0.
    period : float
        one lap [s], > 0.
    """

    center: tuple[float, float]
    radius: float
    period: float

    def __post_init__(self):
        if not (np.isfinite(self.radius) and self.radius > 0):
            raise ValueError(f"`radius` must be finite and > 0 [m], got {self.radius!r}")
        if not (np.isfinite(self.period) and self.period > 0):
            raise ValueError(f"`period` must be finite and > 0 [s], got {self.period!r}")

    def reference(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Desired position [m], velocity [m/s] and acceleration [m/s^2] at time ``t`` [s]."""
        w = 2.0 * np.pi / self.period
        c, s = np.cos(w * t), np.sin(w * t)
        r = self.radius
        x = np.asarray(self.center, dtype=float) + r * np.array([c, s])
        return x, r * w * np.array([-s, c]), -r * w * w * np.array([c, s])


def elbow_inverse_kinematics(x, p, *, elbow: int = 1) -> np.ndarray:
    """Joint angles ``(q1, q2)`` [rad] that put the elbow manipulator's tip at ``x`` [m].

    ``elbow = +1`` takes ``q2 > 0``, ``-1`` takes ``q2 < 0``; ``p`` is a
    :class:`~walker.params.DoublePendulumParams` vector.
    """
    prm = DoublePendulumParams.from_array(p)
    l1, l2 = prm.length_1, prm.length_2
    x = np.asarray(x, dtype=float)
    c2 = (x @ x - l1**2 - l2**2) / (2.0 * l1 * l2)
    if not -1.0 <= c2 <= 1.0:
        raise ValueError(
            f"`x` = {x.tolist()} must be within the arm's reach, "
            f"{abs(l1 - l2)} <= |x| <= {l1 + l2} [m], got |x| = {np.hypot(*x):.4g}"
        )
    q2 = np.sign(elbow) * np.arccos(c2)
    q1 = np.arctan2(x[1], x[0]) - np.arctan2(l2 * np.sin(q2), l1 + l2 * np.cos(q2))
    return np.array([q1, q2])


def computed_torque(arm: CartesianFunctions, q, qd, p, desired, natural_frequency, **kw):
    """Operational-space computed torque ``tau = J^T F`` (module docstring) [N m], shape (2,).

    ``desired`` is ``(x_d, xd_d, xdd_d)``; ``kw`` goes to ``arm.cartesian_terms`` (it raises
    :class:`SingularConfiguration` near a singularity).
    """
    kp, kd = natural_frequency**2, 2.0 * natural_frequency
    x_d, xd_d, xdd_d = desired
    terms = arm.cartesian_terms(q, qd, p, **kw)
    x = arm.position(q, p)
    xd = terms.jacobian @ qd
    a = xdd_d + kd * (xd_d - xd) + kp * (x_d - x)
    force = terms.mass @ a + terms.velocity + terms.gravity - terms.forcing
    return terms.jacobian.T @ force


def error_analytic(t, e0, ed0, natural_frequency) -> np.ndarray:
    """``e(t) = (e0 + (e_dot0 + omega_n e0) t) exp(-omega_n t)`` [m], shape (len(t), 2)."""
    t = np.asarray(t, dtype=float)[:, None]
    w = natural_frequency
    return (e0 + (ed0 + w * e0) * t) * np.exp(-w * t)


def error_bound(t, e0, ed0, natural_frequency) -> np.ndarray:
    """``(|e0| + |e_dot0 + omega_n e0| t) exp(-omega_n t)`` [m]: bounds ``|e(t)|``."""
    t = np.asarray(t, dtype=float)
    w = natural_frequency
    return (np.linalg.norm(e0) + np.linalg.norm(ed0 + w * e0) * t) * np.exp(-w * t)


@dataclass(frozen=True)
class Tracking:
    """A tracking run: samples, status and counters.

    ``status`` is ``SUCCESS`` (0), ``SINGULAR`` (1) or ``FAILED`` (-1), ``message`` says why.
    Arrays are sampled at ``t`` (shape ``(n,)`` [s]): ``q``, ``qd`` ``(n, 2)`` [rad], [rad/s];
    ``x``, ``x_desired``, ``error`` ``(n, 2)`` [m]; ``tau`` ``(n, 2)`` [N m]; ``condition``
    ``(n,)``.  ``e0``, ``ed0``: the initial task error [m] and its rate [m/s].
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    x: np.ndarray
    x_desired: np.ndarray
    error: np.ndarray
    tau: np.ndarray
    condition: np.ndarray
    e0: np.ndarray
    ed0: np.ndarray
    natural_frequency: float
    status: int
    message: str
    nfev: int
    rtol: float
    atol: float

    @property
    def success(self) -> bool:
        return self.status == SUCCESS


def track_circle(
    arm: CartesianFunctions,
    p,
    circle: Circle,
    *,
    natural_frequency: float,
    q0,
    qd0=(0.0, 0.0),
    t_final: float,
    n_samples: int = 801,
    rtol: float = 1e-11,
    atol: float = 1e-12,
    max_condition: float = MAX_CONDITION,
) -> Tracking:
    """Simulate the closed loop ``D q_ddot + C q_dot + g = tau + Q`` under
    :func:`computed_torque` with scipy's DOP853 from ``(q0, qd0)`` to ``t_final``.

    A configuration with ``cond(J) > max_condition`` ends the run with status ``SINGULAR``
    and the :class:`SingularConfiguration` message; the samples stop there.
    """
    if not natural_frequency > 0:
        raise ValueError(f"`natural_frequency` must be > 0 [rad/s], got {natural_frequency!r}")
    if not t_final > 0:
        raise ValueError(f"`t_final` must be > 0 [s], got {t_final!r}")
    p = np.asarray(p, dtype=float)
    q0 = np.asarray(q0, dtype=float)
    qd0 = np.asarray(qd0, dtype=float)
    kw = {"max_condition": max_condition}

    def rhs(t, y):
        q, qd = y[:2], y[2:]
        tau = computed_torque(arm, q, qd, p, circle.reference(t), natural_frequency, **kw)
        jt = arm.joint_terms(q, qd, p)
        qdd = np.linalg.solve(jt.mass_matrix, tau + jt.forcing - jt.coriolis - jt.gravity)
        return np.concatenate([qd, qdd])

    # scipy's DOP853 (what ``solve_ivp(method="DOP853")`` runs), stepped here one step at a
    # time so that a refused step (SingularConfiguration at a stage point) ends the run with
    # its samples so far and a status, instead of losing them in an exception.
    solver = DOP853(rhs, 0.0, np.concatenate([q0, qd0]), t_final, rtol=rtol, atol=atol)
    ts, pieces = [0.0], []
    status, message = SUCCESS, "reached t_final"
    while solver.status == "running":
        try:
            failure = solver.step()
        except SingularConfiguration as err:
            status, message = SINGULAR, str(err)
            break
        if solver.status == "failed":
            status, message = FAILED, f"DOP853 failed: {failure}"
            break
        ts.append(solver.t)
        pieces.append(solver.dense_output())
    t = np.linspace(0.0, t_final, n_samples)
    t = t[t <= ts[-1]]
    if t[-1] < ts[-1]:  # stopped early: keep the last accepted step as the last sample
        t = np.append(t, ts[-1])
    y = OdeSolution(ts, pieces)(t).T if pieces else np.concatenate([q0, qd0])[None, :]
    nfev = solver.nfev
    n = len(t)
    x = np.array([arm.position(yi[:2], p) for yi in y]).reshape(n, 2)
    ref = [circle.reference(ti) for ti in t]
    x_desired = np.array([r[0] for r in ref]).reshape(n, 2)
    # The samples lie on accepted steps (cond(J) <= max_condition at their ends); an
    # interpolated sample a hair past the threshold is still reported, not refused.
    tau = np.array(
        [
            computed_torque(arm, yi[:2], yi[2:], p, r, natural_frequency, max_condition=np.inf)
            for yi, r in zip(y, ref, strict=True)
        ]
    ).reshape(n, 2)
    cond = np.array([arm.condition_number(yi[:2], p) for yi in y])
    x0_d, xd0_d, _ = circle.reference(0.0)
    e0 = x0_d - arm.position(q0, p)
    ed0 = xd0_d - arm.jacobian(q0, p) @ qd0
    return Tracking(
        t=t,
        q=y[:, :2],
        qd=y[:, 2:],
        x=x,
        x_desired=x_desired,
        error=x_desired - x,
        tau=tau,
        condition=cond,
        e0=e0,
        ed0=ed0,
        natural_frequency=natural_frequency,
        status=status,
        message=message,
        nfev=nfev,
        rtol=rtol,
        atol=atol,
    )


CIRCLE = Circle(center=(1.0, 0.6), radius=0.3, period=2.0)
"""The example's circle: well inside the reach of ``DoublePendulumParams.course()``."""


def track_example(
    arm: CartesianFunctions | None = None,
    *,
    natural_frequency: float = 4.0,
    t_final: float = 4.0,
    n_samples: int = 801,
) -> tuple[Tracking, Circle, DoublePendulumParams]:
    """The example's run: the course's arm (``DoublePendulumParams.course()``), at rest with
    its tip at :data:`CIRCLE`'s centre (elbow up), tracks :data:`CIRCLE` under
    :func:`computed_torque`.  ``arm`` defaults to a fresh ``planar_elbow_cartesian()``.
    Returns ``(run, circle, params)``; what the script and the gallery draw."""
    if arm is None:
        arm = CartesianFunctions(planar_elbow_cartesian())
    params = DoublePendulumParams.course()
    p = params.as_array()
    q0 = elbow_inverse_kinematics(CIRCLE.center, p, elbow=1)
    run = track_circle(
        arm,
        p,
        CIRCLE,
        natural_frequency=natural_frequency,
        q0=q0,
        t_final=t_final,
        n_samples=n_samples,
    )
    return run, CIRCLE, params


# ------------------------------------------------------------------------------ output
def plot_tracking(run: Tracking, circle: Circle):
    """Path against the circle, and the tracking error against time; returns the Figure."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 4.2), layout="constrained")
    ax_path, ax_err = fig.subplots(1, 2)
    theta = np.linspace(0.0, 2.0 * np.pi, 400)
    cx, cy = circle.center
    ax_path.plot(run.x[:, 0], run.x[:, 1], "C0", lw=1.5, label="tip path")
    ax_path.plot(
        cx + circle.radius * np.cos(theta),
        cy + circle.radius * np.sin(theta),
        "C1--",
        lw=1.2,
        zorder=3,
        label="desired circle",
    )
    ax_path.plot(*run.x[0], "C0o", label="start (at rest)")
    ax_path.plot(0.0, 0.0, "ks", label="arm base")
    ax_path.set_aspect("equal")
    ax_path.set_xlabel("x [m]")
    ax_path.set_ylabel("y [m]")
    ax_path.set_title("tip path, operational-space computed torque")
    ax_path.legend(loc="upper left", fontsize=8)

    err = np.linalg.norm(run.error, axis=1)
    exact = np.linalg.norm(error_analytic(run.t, run.e0, run.ed0, run.natural_frequency), axis=1)
    bound = error_bound(run.t, run.e0, run.ed0, run.natural_frequency)
    ax_err.semilogy(run.t, err, "C0", lw=1.5, label="simulated |e|")
    ax_err.semilogy(run.t, exact, "C1:", lw=1.5, label="closed form (linear error dynamics)")
    ax_err.semilogy(run.t, bound, "k--", lw=1.0, label="bound from the gains")
    ax_err.set_xlabel("t [s]")
    ax_err.set_ylabel("tracking error |x_d - x| [m]")
    ax_err.set_title(f"omega_n = {run.natural_frequency:g} rad/s, critically damped")
    ax_err.legend(fontsize=8)
    return fig


def summary(run: Tracking) -> dict:
    """The numbers of the table: final error, the bound, agreement with the closed form."""
    err = np.linalg.norm(run.error, axis=1)
    exact = error_analytic(run.t, run.e0, run.ed0, run.natural_frequency)
    below = np.nonzero(err >= 1e-3)[0]
    return {
        "final error ‖e(t_f)‖ [m]": err[-1],
        "bound from the gains at t_f [m]": error_bound(
            run.t[-1:], run.e0, run.ed0, run.natural_frequency
        )[0],
        "closed-form ‖e(t_f)‖ [m]": np.linalg.norm(exact[-1]),
        "max ‖e − e_closed_form‖ over the run [m]": np.max(
            np.linalg.norm(run.error - exact, axis=1)
        ),
        "initial error ‖e0‖ [m]": np.linalg.norm(run.e0),
        "time to ‖e‖ < 1 mm for good [s]": run.t[below[-1] + 1] if below.size else 0.0,
        "peak joint torque [N m]": np.max(np.abs(run.tau)),
        "max cond(J)": np.max(run.condition),
    }


def table(
    run: Tracking,
    circle: Circle,
    params: DoublePendulumParams,
    timings: dict,
    stop: Tracking,
    far: Circle,
) -> str:
    """Markdown: the final tracking error and its bound, with provenance; ``stop`` is the
    run on the circle ``far`` beyond reach."""
    rows = "\n".join(f"| {k} | {v:.3g} |" for k, v in summary(run).items())
    units = params.units()
    prm = ", ".join(f"{k} = {v:g} {units[k]}" for k, v in params.to_dict().items())
    omega = run.natural_frequency
    return f"""# Operational-space tracking of a circle: planar elbow manipulator

`python scripts/taskspace_circle.py` (walker {walker.__version__}); figure `circle.png`.

Computed torque in Cartesian space, tau = J^T F, F = M_x (xdd_d + K_d e_dot + K_p e) + V_x +
G_x - Q_x, K_p = {omega**2:g} 1/s^2, K_d = {2 * omega:g} 1/s (omega_n = {omega:g} rad/s,
critically damped). With the model exact the error obeys e_ddot + K_d e_dot + K_p e = 0, so
‖e(t)‖ <= (‖e0‖ + ‖e_dot0 + omega_n e0‖ t) exp(-omega_n t): the bound from the gains.

| quantity | value |
|---|---|
{rows}

- circle: centre {list(circle.center)} m, radius {circle.radius:g} m, period {circle.period:g} s,
  counterclockwise; the arm starts at rest at the circle's centre.
- arm: `DoublePendulumParams.course()`: {prm}.
- integrator: scipy DOP853, rtol = {run.rtol:g}, atol = {run.atol:g}; status {run.status}
  ({run.message}); {run.nfev} right-hand-side evaluations; t_f = {run.t[-1]:g} s.
- singularity threshold: cond(J) <= {MAX_CONDITION:g} (walker.symbolic.taskspace.MAX_CONDITION).
  A circle beyond reach (centre {list(far.center)} m, radius {far.radius:g} m) ends with
  status {stop.status} (singular) after its last accepted step at t = {stop.t[-1]:.6g} s
  (cond(J) = {stop.condition[-1]:.3g} there), on the refused step: "{stop.message}"
- timings [s]: {", ".join(f"{k} {v:.2f}" for k, v in timings.items())}.
"""


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--natural-frequency", type=float, default=4.0, help="omega_n [rad/s]")
    parser.add_argument("--t-final", type=float, default=4.0, help="duration [s]")
    parser.add_argument("--out", type=Path, default=OUT, help="output directory (results/...)")
    args = parser.parse_args(argv)

    timings = {}
    t0 = time.perf_counter()
    arm = CartesianFunctions(planar_elbow_cartesian())
    timings["derive and lambdify"] = time.perf_counter() - t0
    print(f"derived and lambdified the Cartesian form in {timings['derive and lambdify']:.2f} s")

    t0 = time.perf_counter()
    run, circle, params = track_example(
        arm, natural_frequency=args.natural_frequency, t_final=args.t_final
    )
    p = params.as_array()
    timings["closed loop"] = time.perf_counter() - t0
    print(
        f"closed loop: status {run.status} ({run.message}), {run.nfev} evaluations, "
        f"{timings['closed loop']:.2f} s"
    )

    # A circle partly beyond the arm's reach (|x| up to 2.3 m > 2 m): the arm straightens.
    t0 = time.perf_counter()
    far = Circle(center=(1.5, 0.0), radius=0.8, period=2.0)
    stop = track_circle(
        arm,
        p,
        far,
        natural_frequency=args.natural_frequency,
        q0=elbow_inverse_kinematics(far.center, p, elbow=1),
        t_final=args.t_final,
    )
    timings["singular run"] = time.perf_counter() - t0
    print(
        f"circle beyond reach: status {stop.status}, last accepted step at t = "
        f"{stop.t[-1]:.6g} s (cond(J) = {stop.condition[-1]:.3g}): {stop.message}"
    )

    t0 = time.perf_counter()
    args.out.mkdir(parents=True, exist_ok=True)
    fig = plot_tracking(run, circle)
    fig.savefig(args.out / "circle.png", dpi=130)
    timings["plot"] = time.perf_counter() - t0
    text = table(run, circle, params, timings, stop, far)
    (args.out / "circle.md").write_text(text)
    print(text)
    print(f"wrote {args.out / 'circle.png'} and {args.out / 'circle.md'}")
    return 0 if run.success else 1


if __name__ == "__main__":
    raise SystemExit(main())
