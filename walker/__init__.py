"""walker: fast, exact hybrid-dynamics simulation of biped walkers.

The pipeline, from a scene file to pictures::

    gaits/*.toml ──► scene.py        load_scene: model name, parameters, state, settings
                 ──► params/         frozen dataclasses with units and bounds; as_array()
    (by hand)    ──► symbolic/       sympy: bodies -> D, C (Christoffel), g, B, contact
                                     Jacobians, energies; Newton-Euler as the check
                 ──► symbolic/codegen.py + scripts/generate_kernels.py
                                     cse + printing -> walker/_generated/<model>.c (C kernels,
                                     general and "plain" variants with zero parameters
                                     removed), committed, stamped with a hash;
                                     symbolic/indices.py -> _generated/indices.py|.h, the
                                     named parameter, phase and guard indices every model
                                     reads
    (install)    ──► setup.py        compiles walker/_core/*.c + walker/_generated/*.c into the
                                     extension walker._hybrid:
                     _core/hybrid*.c the integrator: the hybrid loop (hybrid.c), DOP853 / RK45 /
                                     RK4 / Euler steps (_step), dense output (_dense), event
                                     location (_events), saltation (_saltation)
                     _core/model_*.c each walker's rhs, guards, resets (impacts as augmented
                                     linear systems), Jacobian, energy, points, start phase;
                                     wk_friction.c (dry joint friction: stick/slip modes),
                                     wk_control.c (virtual-constraint controller)
                     _core/_hybrid*  the Python binding: the methods and the module's init
                                     (_hybridmodule.c), argument conversion (_hybridargs.c),
                                     SolveResult, the named record solve returns
                                     (_hybridresult.c), PreparedMap, one stride-map call
                                     (_hybridmap.c; lift, start checks, run in batch.c)
                                     and the gait search, written once (newton.c; its
                                     binding, compiled or through callbacks, _hybridsearch.c)
    (run time)   ──► models/         per walker: names, phases, guards, section lift/project;
                                     WalkerModel.system_for(p) picks the compiled variant once;
                                     WalkerModel.rhs/guards/reset/energy/torques/kernel call
                                     the compiled model with every argument checked; also
                                     friction modes, controllers (control.py) and HZD (hzd.py)
                 ──► simulation/
                     integrate.py    hybrid_solve, PreparedRun -> Solution; the C contract
                                     HybridSystem (also for user-supplied C functions) in
                                     hybrid_system.py
                     trajectory.py   simulate(): a run from a full state
                     stride.py       StrideMap: section -> section (+ Jacobian); the walking
                                     region and step budget in region.py; the SectionMap
                                     protocol in sectionmap.py
                     terrain.py      ground defined per step (Terrain); its walks, their
                                     Jacobians and Monte-Carlo batches in _terrain_run.py
                                     and _core/terrain*.c
                     system_map.py   SystemMap: a section map of your own HybridSystem
                 ──► analysis/
                     fixedpoint.py   fixed points, Floquet multipliers; newton.py (the search's
                                     settings, result and messages; the search is newton.c)
                     continuation.py natural and pseudo-arclength (steppers.py, one stepper
                                     a method), folds, period doublings (bifurcations.py),
                                     orbit diagrams (orbit.py, orbit_run.py)
                     basin.py        basins of attraction (threads: strides release the GIL;
                                     a point stops inside the gait's contraction ball,
                                     basin_radius.py)
                     sweep.py        resumable parameter sweeps on threads or any Executor,
                                     warm-started along grid lines (sweep_chains.py)
                     measures.py     step length, speed, impact losses, cost of transport
                     mfpt.py         robustness on rough ground: mean first-passage time by
                     markov.py       Monte Carlo and by the stride map's Markov chain; the
                     gsn.py          gait sensitivity norm and the largest recoverable step
                 ──► storage/        HDF5 with provenance, checksums, atomic writes; export
                 ──► plotting/       figures and animations (runs, maps, branch, terrain), the
                                     gallery
    cli/ sits on top (``walker find|run|continue|basin|sweep|orbit-diagram|mfpt|gsn|
    stepdown|export|plot``, one module per command) and only orchestrates.

Each model is implemented once, in C; the analysis tools (hzd.py), the figures and the
tests call it through the checked methods of WalkerModel.  numba is an optional extra, only
for a user's own ``@njit`` system bridged through HybridSystem; walker never imports it.

Only ``symbolic`` imports sympy; a simulation derives nothing.
"""

from walker._startup import quiet_interrupts as _quiet_interrupts

_quiet_interrupts()  # the `walker` command: Ctrl-C during the imports below exits 130 quietly

from importlib.metadata import PackageNotFoundError, version  # noqa: E402

try:
    __version__ = version("walker-hybrid")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0+unknown"

from walker import _result_views  # noqa: E402, F401  (reprs, to_dict of the results)
from walker.models import MODEL_NAMES, get_model  # noqa: E402
from walker.params import (  # noqa: E402
    CompassParams,
    DoublePendulumParams,
    KneedParams,
    SimplestParams,
)
from walker.results import FixedPoint, MapResult, Solution  # noqa: E402
from walker.scene import Scene, load_scene  # noqa: E402
from walker.simulation.terrain import Terrain  # noqa: E402
from walker.status import EVENT_CONTINUE, EVENT_STRIDE, EVENT_TERMINAL, Status  # noqa: E402


def __getattr__(name):
    # The simulation layer loads on first use, so `import walker` stays light.
    if name in ("simulate", "StrideMap"):
        from walker.simulation import stride

        return getattr(stride, name)
    if name == "find_fixed_point":
        from walker.analysis.fixedpoint import find_fixed_point

        return find_fixed_point
    if name == "continue_branch":
        from walker.analysis.continuation import continue_branch

        return continue_branch
    if name == "HybridSystem":
        from walker.simulation.hybrid_system import HybridSystem

        return HybridSystem
    if name == "hybrid_solve":
        from walker.simulation.integrate import hybrid_solve

        return hybrid_solve
    if name == "SystemMap":
        from walker.simulation.system_map import SystemMap

        return SystemMap
    raise AttributeError(f"module 'walker' has no attribute {name!r}")


__all__ = [
    "EVENT_CONTINUE",
    "EVENT_STRIDE",
    "EVENT_TERMINAL",
    "MODEL_NAMES",
    "CompassParams",
    "DoublePendulumParams",
    "FixedPoint",
    "HybridSystem",
    "KneedParams",
    "MapResult",
    "Scene",
    "SimplestParams",
    "Solution",
    "Status",
    "StrideMap",
    "SystemMap",
    "Terrain",
    "continue_branch",
    "find_fixed_point",
    "get_model",
    "hybrid_solve",
    "load_scene",
    "simulate",
    "__version__",
]
