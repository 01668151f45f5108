"""Drake's compass gait as a contender of scripts/bench_stride.py: its default parameters as
walker's :class:`walker.params.CompassParams` (:func:`drake_params`) and Drake's
``Simulator`` on it (:class:`DrakeCompass`).  pydrake is imported only when these are called.

Timed: :meth:`DrakeCompass.advance`, the run to a fixed ``t_end`` through the heel strike,
which calls no Python while Drake integrates.  Untimed: :meth:`DrakeCompass.stride`, one
stride stopped by a Python monitor after every step (Drake's ``CompassGait`` witness applies
the collision but does not end the run); its cost is Python's, so it only checks the step time.
"""

from __future__ import annotations

import math

import numpy as np

from walker.params import CompassParams


def drake_params():
    """Drake's CompassGaitParams defaults, read from pydrake, and walker's CompassParams
    for the same walker (Drake: leg length l, centre of mass ``center_of_mass_leg`` below
    the hip; walker: ``com_from_foot`` = a = l - that, ``com_to_hip`` = b = that)."""
    from pydrake.examples import CompassGaitParams

    d = CompassGaitParams()
    dp = {
        "mass_hip": d.mass_hip(),
        "mass_leg": d.mass_leg(),
        "length_leg": d.length_leg(),
        "center_of_mass_leg": d.center_of_mass_leg(),
        "gravity": d.gravity(),
        "slope": d.slope(),
    }
    wp = CompassParams(
        mass_hip=dp["mass_hip"],
        mass_leg=dp["mass_leg"],
        com_from_foot=dp["length_leg"] - dp["center_of_mass_leg"],
        com_to_hip=dp["center_of_mass_leg"],
        inertia_leg=0.0,
        foot_radius=0.0,
        slope=dp["slope"],
        g=dp["gravity"],
        damping_hip=0.0,
        damping_ankle=0.0,
    )
    return dp, wp


class DrakeCompass:
    """One compass-gait stride in Drake's Simulator.

    State conventions: Drake's ``(stance, swing, stancedot, swingdot)`` are angles from the
    vertical measured clockwise (hip at ``x = l sin(stance)``, walking toward +x downhill);
    walker's are counterclockwise, so ``x_drake = -x_walker`` component by component.

    A stride: set the post-impact state at t = 0, ``AdvanceTo`` with a monitor that ends the
    run at the step where Drake's foot-collision witness has fired (its isolation step ends
    on the zero crossing), then ``AdvanceTo`` the same time, which applies Drake's own
    collision update (impact + leg swap) and integrates nothing.
    """

    def __init__(self, max_step):
        from pydrake.examples import CompassGait
        from pydrake.systems.analysis import Simulator
        from pydrake.systems.framework import EventStatus

        self.cg = CompassGait()
        self.sim = Simulator(self.cg)
        self.ctx = self.sim.get_mutable_context()
        self.max_step = max_step
        slope2 = 2.0 * self.ctx.get_numeric_parameter(0).CopyToVector()[5]
        nothing = EventStatus.DidNothing()
        stop = EventStatus.ReachedTermination(self.cg, "foot collision")

        def monitor(c):
            # Pre-impact (toe not yet moved) and past the collision surface.
            if c.get_discrete_state_vector().GetAtIndex(0) != 0.0:
                return nothing
            v = c.get_continuous_state_vector()
            st, sw = v.GetAtIndex(0), v.GetAtIndex(1)
            if max(slope2 - st - sw, sw - st) <= 0.0:
                return stop
            return nothing

        self._monitor = monitor
        self.tol = None

    def set_accuracy(self, tol):
        from pydrake.systems.analysis import ResetIntegratorFromFlags

        integ = ResetIntegratorFromFlags(self.sim, "runge_kutta5", self.max_step)
        integ.set_target_accuracy(tol)
        self.ctx.SetAccuracy(tol)
        self.integ = integ
        self.tol = tol

    def _start(self, x_walker):
        ctx = self.ctx
        ctx.SetTime(0.0)
        ctx.SetContinuousState(-np.asarray(x_walker, dtype=float))
        ctx.SetDiscreteState(np.zeros(1))
        self.sim.Initialize()

    def stride(self, x_walker, t_span=5.0):
        """One stride: (post-impact state in walker's convention, impact time).  Calls the
        Python monitor after every step: for checks, not for timing."""
        ctx, sim = self.ctx, self.sim
        self._start(x_walker)
        sim.set_monitor(self._monitor)
        try:
            sim.AdvanceTo(t_span)
        finally:
            sim.clear_monitor()
        t = ctx.get_time()
        if t >= t_span:
            return None, math.nan
        sim.AdvanceTo(t)  # the collision update
        if ctx.get_discrete_state_vector().GetAtIndex(0) == 0.0:
            return None, t
        return -ctx.get_continuous_state_vector().CopyToVector(), t

    def advance(self, x_walker, t_end):
        """The state at ``t_end`` in walker's convention, through whatever impacts occur
        (no Python callback during the run: the timed Drake contender)."""
        self._start(x_walker)
        self.sim.AdvanceTo(t_end)
        return -self.ctx.get_continuous_state_vector().CopyToVector()
