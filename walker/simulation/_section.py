"""A walker's stride map as the compiled core takes it: what
:class:`walker.simulation.stride.StrideMap` resolves once of its model to run a call in one compiled
call (``walker._hybrid.PreparedMap``, a basin's rows in ``walker._hybrid.basin_points``).

* :func:`fast_parts`: the lift, the projection's indices, the lift's constant Jacobian and
  the start phase, for the checked Python path as well;
* :func:`compiled_call_fits`: whether one compiled call can do what ``StrideMap.__call__``
  does with the same operations;
* :func:`section_args`: the section settings the compiled map takes, by keyword
  (``walker._hybrid.SECTION_FIELDS``, ``WKPY_SECTION_FIELDS`` in
  walker/_core/_hybridbinding.h); :func:`section_tuple` the same in that order, the head of
  the terrain calls' positional arguments.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "compiled_call_fits",
    "compiled_lift",
    "fast_parts",
    "retarget",
    "section_args",
    "section_tuple",
    "selected_components",
]


def selected_components(model, p):
    """The indices (intp) of the state components the model's projection selects, or None
    when it does more than select them."""
    n_x = model.n_x
    idx = model.project(np.arange(n_x, dtype=np.float64), p)
    probe = np.linspace(-0.75, 0.5, n_x) + 0.1
    if (
        idx.shape == (model.n_z,)
        and np.array_equal(idx, np.round(idx))
        and np.array_equal(model.project(probe, p), probe[idx.astype(np.int64)])
    ):
        return idx.astype(np.intp)
    return None


def fast_parts(model, p):
    """What a call needs of the model besides the run, resolved once: ``(lift, project,
    lift_jacobian, start_phase)``.  ``lift(z, p)`` is the model module's own function (the
    wrapper's conversions are done: ``z`` is a float array and ``p`` the parameter vector);
    for a model whose lift is declared affine (``LIFT_AFFINE``) ``project`` is the index
    array of the components it selects and ``lift_jacobian`` the constant Jacobian, else
    None (the model's own functions are called); ``start_phase`` None when every state
    starts in phase 0.  The constant ``lift_jacobian`` (C-contiguous float64,
    ``(n_x, n_z)``) is also the seed of the variational equations for ``jacobian=True``."""
    module = model.module
    project = lift_jac = None
    if getattr(module, "LIFT_AFFINE", False):
        project = selected_components(model, p)
        if project is not None:
            lift_jac = np.array(
                model.lift_jacobian(np.zeros(model.n_z), p), dtype=np.float64, order="C"
            )
            lift_jac.flags.writeable = False
    return module.lift, project, lift_jac, model.start_phase_fn()


def compiled_lift(model):
    """``(lift, lift_jacobian)``, the addresses of the model's compiled section lift and its
    Jacobian where the lift is not affine (the simplest walker's), else None."""
    lift, lift_jac = model._state_fn("lift"), model._state_fn("lift_jacobian")
    return (lift, lift_jac) if lift is not None and lift_jac is not None else None


def compiled_call_fits(model, p, t_max, fast) -> bool:
    """Can one compiled call (``walker._hybrid.PreparedMap``) do what
    ``StrideMap.__call__`` does, with the same operations?  It can for a model whose
    projection selects components and whose lift is affine (``fast``, :func:`fast_parts`) or
    compiled (:func:`compiled_lift`), and a ``t_max`` that a double times ``n_strides``
    gives as the Python product does (a float, or an int below 2**53)."""
    lift_fits = fast[1] is not None or (
        compiled_lift(model) is not None and selected_components(model, p) is not None
    )
    return lift_fits and (isinstance(t_max, float) or (type(t_max) is int and abs(t_max) < 2**53))


def section_args(model, t_max, cached, run, lift_a=None, proj=None, lift=None) -> dict:
    """The settings of the compiled stride map, the keywords that
    ``walker._hybrid.basin_points`` and ``walker._hybrid.PreparedMap`` take
    (``walker._hybrid.SECTION_FIELDS``): the system and solver settings of ``run`` (a
    PreparedRun of the map), the per-stride step budget, the affine lift
    ``x = lift_a z + lift_b``, the projection's indices, the start checks' guard, the
    compiled start phase, the per-stride ``t_max`` and the compiled lift's addresses (0 for
    the affine lift).  ``cached`` is the map's prepared run (``StrideMap._prepared``);
    ``lift_a`` (the affine lift's matrix) and ``proj`` (the projection's indices, int64)
    when the caller has them already; ``lift``: the addresses ``(lift, lift_jacobian)`` of a
    compiled lift to take in place of the model's (a terrain run's, ``_hybrid.terrain_lift``)."""
    p = cached[1]
    (offset, fall_angle), n_q, wound, _, energy_address, kinetic_limit = cached[2]
    n_z, n_x = model.n_z, model.n_x
    if lift is None:
        lift = compiled_lift(model) if cached[5][1] is None else None
    if lift is None:  # the affine lift x = lift_a z + lift_b
        if lift_a is None:
            lift_a = model.lift_jacobian(np.zeros(n_z), p)
        lift_a = np.ascontiguousarray(lift_a, dtype=np.float64)
        lift_b = np.ascontiguousarray(model.lift(np.zeros(n_z), p), dtype=np.float64)
        lift = (0, 0)
    else:  # the model's compiled lift; lift_a and lift_b unused
        lift_a, lift_b = np.zeros((n_x, n_z)), np.zeros(n_x)
    if proj is None:
        proj = model.project(np.arange(n_x, dtype=np.float64), p).astype(np.int64)
    return {
        **run._head,
        "p": p,
        **run._settings,
        "max_steps": cached[3],  # per stride
        "lift_a": lift_a,
        "lift_b": lift_b,
        "proj": proj,
        "offset": float(offset),
        "fall_angle": float(fall_angle),
        "n_q": int(n_q),
        "wound": float(wound),
        "energy": energy_address or 0,
        "kinetic_limit": float(kinetic_limit),
        "start_phase": model._state_fn("start_phase") or 0,
        "t_max": float(t_max),
        "lift": lift[0],
        "lift_jacobian": lift[1],
    }


def section_tuple(settings: dict) -> tuple:
    """The section settings ``settings`` (:func:`section_args`) as the positional head of
    ``walker._hybrid.terrain_walk`` and ``terrain_ensemble``, in the order of
    ``walker._hybrid.SECTION_FIELDS``."""
    from walker import _hybrid

    return tuple(settings[name] for name in _hybrid.SECTION_FIELDS)


def retarget(new, cached, region):
    """The prepared run (``StrideMap._prepared``'s tuple) of the map ``new`` from ``cached``,
    the prepared run of a map that differs from it in its parameters only
    (``StrideMap._retargeted``), and ``region``, that map's walking region: what does not
    depend on the parameters (the system and its compiled kernels, the solver settings, the
    runs per stride count, the projection's indices) is shared, what does is computed again
    (the parameter vector, the start checks, the lift); None when the parameters change what
    is shared (another kernel variant, another step budget, another projection)."""
    from walker import _hybrid
    from walker.simulation.region import WalkingRegion, stride_max_steps

    model, params = new.model, new.params
    p = np.ascontiguousarray(params.as_array(), dtype=np.float64)
    if model.system_for(p) is not cached[4]:
        return None
    region = WalkingRegion(model, params) if region is None else region.at(params, p)
    per_stride = cached[3]
    if region.time_scale != getattr(region, "_base_time_scale", None):  # the budget's unit
        per_stride = stride_max_steps(params, new.t_max, new.method, new.first_step)
        if per_stride != cached[3]:
            return None
    lift, project, lift_jac, start_phase = cached[5]
    proj = model.project(np.arange(model.n_x, dtype=np.float64), p)
    if project is not None:
        if proj.tolist() != project.tolist():
            return None
        lift_jac = model.lift_jacobian(np.zeros(model.n_z), p)
        lift_jac = np.array(lift_jac, dtype=np.float64, order="C")
        lift_jac.flags.writeable = False
    fast = (lift, project, lift_jac, start_phase)
    fresh = [cached[0], p, new._guard(region, own=True), per_stride, cached[4], fast, None]
    if cached[6] is not None:
        run = cached[0].get(1) or next(iter(cached[0].values()), None)
        if run is None:
            return None
        args = section_args(model, new.t_max, fresh, run, lift_jac, proj.astype(np.int64))
        fresh[6] = _hybrid.PreparedMap(**args).map
    return tuple(fresh)
