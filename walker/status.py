"""Outcomes of a simulation and the event actions a reset map can request.

Both are plain integers inside compiled code; :class:`Status` gives them names and messages
on the Python side.  Expected outcomes (a fall, no heel strike before ``t_max``) are statuses
on a result, never exceptions.
"""

from enum import IntEnum

# What a model's reset map tells the hybrid loop to do with a located guard crossing.
EVENT_IGNORE = 0  # not a real event (e.g. a scuff with the swing foot behind): keep integrating
EVENT_CONTINUE = 1  # apply the reset, continue in the returned phase
EVENT_STRIDE = 2  # apply the reset, continue, and count one completed stride
EVENT_TERMINAL = 3  # stop: the returned status says why

# Output modes of the hybrid integrator.
OUTPUT_MAP = 0  # final state only
OUTPUT_EVENTS = 1  # plus every event (time, guard, pre/post state, impulses)
OUTPUT_SAMPLES = 2  # plus states at requested times, from the dense output
OUTPUT_FULL = 3  # plus every accepted step

# Integration methods.
METHOD_EULER = 0
METHOD_RK4 = 1
METHOD_DP5 = 2
METHOD_DOP853 = 3


class Status(IntEnum):
    """Outcome of a run.  ``Status.COMPLETED`` is the only success."""

    COMPLETED = 0
    FELL_BACKWARD = 1
    FELL_FORWARD = 2
    TRIPPED = 3
    NONPHYSICAL_IMPACT = 4
    NO_EVENT = 5
    STEP_UNDERFLOW = 6
    NONFINITE = 7
    MAX_STEPS = 8
    NOT_CONVERGED = 9
    LINEAR_SOLVE_FAILED = 10
    PARAMETER_OUT_OF_RANGE = 11
    # Appended: values are stored in files, never renumber.
    NO_GAIT_NEAR_GUESS = 12
    DIVERGED = 13
    BUDGET_EXHAUSTED = 14
    OUTSIDE_WALKING_REGION = 15
    CHATTERING = 16
    INTERRUPTED = 17
    ROLLED_BACK = 18

    @property
    def message(self) -> str:
        return _MESSAGES[self]


_MESSAGES = {
    Status.COMPLETED: "Completed the requested number of strides.",
    Status.FELL_BACKWARD: (
        "The walker fell backward (the hip moved back over the stance foot). "
        "Try a faster initial stance-leg rate or a steeper slope."
    ),
    Status.FELL_FORWARD: (
        "The walker fell forward (hip below the fall threshold / stance leg past horizontal). "
        "Try a smaller initial rate or a shallower slope."
    ),
    Status.TRIPPED: (
        "The swing foot struck the ground with the knee still bent (a trip). "
        "Try a state with more swing-leg clearance, or check the knee-lock guard."
    ),
    Status.NONPHYSICAL_IMPACT: (
        "An impact was not physical (non-positive normal impulse, or the trailing foot did "
        "not leave the ground). The walker cannot continue from this state."
    ),
    Status.NO_EVENT: (
        "No stride-ending event before t_max. Increase `t_max`, or check that the initial "
        "state walks at all."
    ),
    Status.STEP_UNDERFLOW: (
        "The step size fell below the resolvable limit. Loosen `rtol`/`atol` or check the "
        "model for a singularity."
    ),
    Status.NONFINITE: "The state became NaN or infinite. Check the parameters and initial state.",
    Status.MAX_STEPS: (
        "Reached the step budget before finishing: the state is far from any gait (rates so "
        "high that the steps shrink) or the tolerance is very tight. On the command line, "
        "start nearer a gait (the scene's `[initial] state`, `--set`) or loosen `rtol` in the "
        "scene's [compute] table, or raise the budget (`walker run --max-steps N`); from "
        "Python, raise `max_steps` (simulate, hybrid_solve) or "
        "`t_max` (a StrideMap allows a number of steps proportional to `t_max`, see "
        "walker.analysis.fixedpoint.stride_max_steps)."
    ),
    Status.NOT_CONVERGED: (
        "Newton iteration did not converge. Try a better initial guess, more iterations, or "
        "the Levenberg-Marquardt fallback."
    ),
    Status.LINEAR_SOLVE_FAILED: "A linear solve was singular (degenerate configuration).",
    Status.PARAMETER_OUT_OF_RANGE: (
        "The continuation stepped outside the parameter's allowed range (see its bounds in "
        "walker.params). Continue toward the other side, or stop before the bound."
    ),
    Status.NO_GAIT_NEAR_GUESS: (
        "No gait near the initial guess: the residual |P(z) - z| stalls at a positive value "
        "(as past a fold of the gait branch, where the gait ceases to exist). On the command "
        "line, try `--set slope=...` (or the parameter swept) closer to a value where a gait "
        "is known, or a better `[initial] state` in the scene file; from Python, another `z0` "
        "or continue_branch from a known gait."
    ),
    Status.DIVERGED: (
        "The gait search diverged: its steps lead out of the region where the walker can walk "
        "(stance leg past the fall angle, rates far beyond a gait's, or strides that fall). On "
        "the command line, try `--set slope=...` closer to a value where a gait is known, or a "
        "better `[initial] state` in the scene file; from Python, another `z0`."
    ),
    Status.BUDGET_EXHAUSTED: (
        "The gait search used its budget of stride-map evaluations without converging. On the "
        "command line, try `--set slope=...` closer to a value where a gait is known, or a "
        "better `[initial] state` in the scene file; from Python, raise `max_evals` of "
        "find_fixed_point or pass a better `z0`."
    ),
    Status.OUTSIDE_WALKING_REGION: (
        "The state lies outside the region where the walker can walk (an angle wound beyond "
        "pi from the slope normal, the stance leg past the fall angle, or kinetic energy far "
        "above what the scene supplies), so it was not integrated. Start from a state near a "
        "gait: on the command line the scene's `[initial] state`, from Python `z0` or `x0`."
    ),
    Status.ROLLED_BACK: (
        "The rimless wheel did not get over its stance spoke and turned back (on per-step "
        "terrain, walker/simulation/terrain.py): a failure of the walk. Try a faster start or a "
        "steeper or smoother ground."
    ),
    Status.CHATTERING: (
        "Events accumulated: the same event fired at three or more shrinking intervals in a "
        "row, the last under 1% of the first, or 16 events in a row fired without time "
        "advancing (chattering, a Zeno sequence such as a foot bouncing to rest or a joint "
        "switching between stick and slip ever faster), so the run stopped at that event "
        "instead of stepping through the accumulation. The model has no mode for the limit "
        "it approaches (e.g. resting contact)."
    ),
    Status.INTERRUPTED: (
        "A signal (SIGINT, Ctrl-C, or SIGTERM) arrived while the compiled integrator ran, so "
        "the run stopped where it was. Python's handler for the signal normally raises "
        "(KeyboardInterrupt) instead; this status is what a run reports when the handler "
        "returned."
    ),
}
