"""``walker gsn`` and ``walker stepdown``: the gait sensitivity norm of a scene's gait and the
largest single step down and up it recovers from (:mod:`walker.analysis.gsn`)."""

from __future__ import annotations

from ._common import (
    EXIT_OK,
    EXIT_OUTCOME,
    UsageError,
    _json,
    _load,
    _stride_map,
    json_flag,
    scene_cmd,
)


def _gait(args):
    """(scene, map, gait section point) or (scene, None, message): the scene's period-one gait
    on a model that walks on terrain."""
    from walker.analysis.fixedpoint import find_fixed_point
    from walker.simulation._terrain_run import check_supported

    scene = _load(args)
    if not scene.model or scene.model == "double_pendulum":
        raise UsageError(f"{args.scene}: model `{scene.model}` has no gait")
    P = _stride_map(scene)
    try:
        check_supported(P)
    except ValueError as exc:
        raise UsageError(f"{args.scene}: {exc}") from None
    fp = find_fixed_point(P, P.project(scene.state))
    if not fp.success:
        return scene, None, f"no period-one gait near the scene's start ({fp.status.name})"
    if not fp.stable:
        return scene, None, "the gait is unstable: it has no sensitivity norm or step limits"
    return scene, P, fp.section


def cmd_gsn(args) -> int:
    from walker.analysis.gsn import gait_sensitivity

    scene, P, z = _gait(args)
    if P is None:
        print(f"walker: {z}")
        return EXIT_OUTCOME
    g = gait_sensitivity(P, z)
    record = {"scene": str(scene.path), "model": scene.model, **g.as_dict()}
    code = EXIT_OK if g.status.name == "COMPLETED" else EXIT_OUTCOME
    if args.json:
        print(_json(record))
        return code
    if code != EXIT_OK:
        print(f"walker: no gait sensitivity norm: {g.message}")
        return code
    print(f"scene   {scene.path}  (model {scene.model})")
    print(f"GSN     {g.gsn:.10g}  (step time [s/m] and step length [m/m] per unit step down)")
    if g.one_sided:
        print(f"note    {g.message}")
    print("stride  dT/dh [s/m]     dS/dh [1]")
    for k, (t, s) in enumerate(g.response):
        print(f"{k:>6d}  {t: .6e}  {s: .6e}")
    print(f"tail    {g.tail:.3e} (sum of squares past stride {len(g.response) - 1})")
    return EXIT_OK


def cmd_stepdown(args) -> int:
    from walker.analysis.gsn import largest_step

    scene, P, z = _gait(args)
    if P is None:
        print(f"walker: {z}")
        return EXIT_OUTCOME
    limits = largest_step(P, z)
    record = {"scene": str(scene.path), "model": scene.model, **limits.as_dict()}
    if args.json:
        print(_json(record))
        return EXIT_OK
    print(f"scene      {scene.path}  (model {scene.model})")
    print(f"step down  {limits.step_down:.6f} m  (fails at {limits.down_fails:.6f} m)")
    print(f"step up    {limits.step_up:.6f} m  (fails at {limits.up_fails:.6f} m)")
    print(
        f"recovery   within {limits.tol:g} of the gait after {limits.strides} strides; "
        f"resolution {limits.resolution:g} m"
    )
    return EXIT_OK


def register(sub) -> None:
    p = scene_cmd(sub, "gsn", "gait sensitivity norm to a step down (Hobbelen & Wisse 2007)")
    json_flag(p)
    p.set_defaults(func=cmd_gsn)
    p = scene_cmd(sub, "stepdown", "largest single step down and up the gait recovers from")
    json_flag(p)
    p.set_defaults(func=cmd_stepdown)
