"""Simulating a walker from a full state: :func:`simulate` (the run behind ``walker run``,
:meth:`walker.simulation.stride.StrideMap.trajectory` and the figures), and the checks it shares
with the stride map (:mod:`walker.simulation.stride`).
"""

from __future__ import annotations

import math

import numpy as np

from walker._checks import as_vector as _as_vector
from walker._checks import time_scale as _time_scale
from walker.models import WalkerModel, get_model
from walker.results import Solution, too_large
from walker.simulation import _terrain_run
from walker.simulation.integrate import _solve

__all__ = ["check_sample_count", "simulate"]


def _resolve(model, params):
    if isinstance(model, str):
        model = get_model(model)
    if not isinstance(model, WalkerModel):
        raise TypeError(f"`model` must be a model name or WalkerModel, got {type(model).__name__}")
    # The exact class: a subclass (KneedCoulombParams is a KneedParams) has more parameters.
    if type(params) is not model.params_class:
        raise TypeError(
            f"`params` must be a {model.params_class.__name__} for model `{model.name}`, "
            f"got {type(params).__name__}"
        )
    return model


def simulate(
    model,
    params,
    x0,
    *,
    n_strides: int = 1,
    phase0: int | None = None,
    t_max: float | None = None,
    t0: float = 0.0,
    method: str = "DOP853",
    rtol: float = 1e-10,
    atol: float = 1e-12,
    first_step: float | None = None,
    output: str = "map",
    sample_times=None,
    jacobian: bool = False,
    max_steps: int = 1_000_000,
    terrain=None,
) -> Solution:
    """Simulate ``n_strides`` strides of a walker from the full state ``x0``.

    Parameters
    ----------
    model : str or WalkerModel
        ``"simplest"``, ``"compass"``, ``"kneed"`` or ``"double_pendulum"``.
    params : the model's parameter dataclass (``walker.params``)
    x0 : array_like, shape (n_x,)
        initial state in the model's state order (``get_model(name).state_names``).
    n_strides : int
        heel strikes to complete; 0 integrates to ``t_max`` (models without strides, such as
        the double pendulum).
    phase0 : int, optional
        phase to start in; default the model's phase for ``x0``
        (:meth:`walker.models.WalkerModel.start_phase`: 0, except for models with joint
        friction, whose joint modes follow from the state).
    t_max : float, optional
        final time [s]; default ``20 n_strides`` stride-times' worth: ``20 * max(1,
        n_strides) * sqrt(leg_length / g)``.
    t0 : float
        start time [s], ``< t_max`` (a run continued from where another ended: walker run's
        blocks of strides).
    method, rtol, atol, first_step, output, sample_times, jacobian, max_steps
        as in :func:`walker.simulation.integrate.hybrid_solve`.
    terrain : array_like, shape (n, 2), optional
        per-step ``(slope [rad], drop [m])`` (:mod:`walker.simulation.terrain`), the scene's plane
        past the last row; None: the plane (this path, unchanged).

    Returns
    -------
    Solution
        ``status`` says how the run ended (a fall is a status, not an exception).

    Examples
    --------
    >>> from walker import simulate, load_scene
    >>> scene = load_scene("gaits/compass_goswami.toml")
    >>> sol = simulate("compass", scene.params, scene.state, n_strides=3)
    >>> sol.status.name, sol.n_strides
    ('COMPLETED', 3)
    """
    model, p, system, time_scale, start_phase = _setup(model, params)
    if terrain is not None:
        terrain = _terrain_run.rows_for(model, params, system, terrain)
    x0 = _as_vector(x0, "x0")
    if t_max is None:
        t_max = 20.0 * max(1, n_strides) * time_scale
    if phase0 is None:
        phase0 = (
            0
            if start_phase is None
            or x0.shape != (model.n_x,)
            or not all(map(math.isfinite, x0.tolist()))
            else start_phase(np.ascontiguousarray(x0), p)
        )
    sol = _solve(
        system,
        x0,
        p,
        phase0=phase0,
        t0=t0,
        t_max=t_max,
        n_strides=n_strides,
        method=method,
        rtol=rtol,
        atol=atol,
        first_step=first_step,
        max_step=np.inf,
        max_steps=max_steps,
        output=output,
        sample_times=sample_times,
        jacobian=jacobian,
        n_interior=4,
        fixed_step=False,
        p_checked=True,
        terrain=terrain,
    )
    if model.conventions:
        sol.conventions = dict(model.conventions)
    return sol


# (model, params) -> what a run needs of them, for the last few pairs: a run after the first
# with the same objects resolves, converts and checks nothing of them again.  Keyed by the
# objects' identity; an entry holds both, so an id is not reused while its entry exists
# (parameter objects are frozen: an entry never goes stale).
_SETUP: dict = {}
_SETUP_MAX = 32


def _setup(model, params):
    """``(model, p, system, time_scale, start_phase)`` for a model (name or WalkerModel) and
    its parameter object, validated on first use: ``p`` the parameter vector (read-only,
    finite, of the model's length), ``system`` the HybridSystem specialised to it,
    ``start_phase`` None when the model always starts in phase 0, else ``(x0, p) -> int``."""
    key = (model if isinstance(model, str) else id(model), id(params))
    hit = _SETUP.get(key)
    if hit is not None and hit[0] is params and hit[1] is model:
        return hit[2]
    resolved = _resolve(model, params)
    p = np.ascontiguousarray(params.as_array(), dtype=np.float64)
    system = resolved.system_for(p)
    if system.n_params is not None and p.shape != (system.n_params,):
        raise ValueError(
            f"`p` must have length {system.n_params} for system `{system.name}`, got {p.shape[0]}"
        )
    if not np.isfinite(p).all():
        raise ValueError("All parameters `p` must be finite.")
    p.flags.writeable = False
    start_phase = resolved.start_phase_fn()  # None: every state starts in phase 0
    value = (resolved, p, system, _time_scale(params), start_phase)
    if len(_SETUP) >= _SETUP_MAX:
        _SETUP.clear()
    _SETUP[key] = (params, model, value)
    return value


def check_sample_count(duration: float, sample_rate: float, n_x: int, what: str) -> int:
    """The number of samples of a run of ``duration`` seconds at ``sample_rate`` Hz, or a
    ValueError naming ``what`` when their times, states and phases would not fit in
    :func:`walker.results.memory_limit`."""
    n = math.ceil(max(float(duration), 0.0) * sample_rate) + 1
    reason = too_large(n * (n_x + 2) * 8.0)
    if reason is not None:
        raise ValueError(
            f"{what} {sample_rate:g} Hz over the {duration:.6g} s of the run gives {n:,} "
            f"samples, which {reason}; lower {what}"
        )
    return n
