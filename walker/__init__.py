"""walker: fast, exact hybrid-dynamics simulation of biped walkers.

The pipeline, from a scene file to pictures::

    gaits/*.toml ──► scene.py        load_scene: model name, parameters, state, settings
                 ──► params/         frozen dataclasses with units and bounds; as_array()
    (by hand)    ──► symbolic/       sympy: bodies -> D, C (Christoffel), g, B, contact
                                     Jacobians, energies; Newton-Euler as the check
                 ──► symbolic/codegen.py + scripts/generate_kernels.py
                                     cse + printing -> walker/_generated/<model>.c (C kernels,
                                     general and "plain" variants with zero parameters
                                     removed) and <model>.py (the same kernels for numba),
                                     committed, stamped with a hash; symbolic/indices.py ->
                                     _generated/indices.py|.h, the named parameter, phase
                                     and guard indices every model reads
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
                                     and the whole gait search (newton.c)
    (run time)   ──► models/         per walker: names, phases, guards, section lift/project;
                                     WalkerModel.system_for(p) picks the compiled variant once
                 ──► integrate.py    hybrid_solve, PreparedRun -> Solution; the C contract
                                     HybridSystem (also for user-supplied C functions) in
                                     hybrid_system.py
                 ──► stride.py       simulate(); StrideMap: section -> section (+ Jacobian)
                     terrain.py      ground defined per step (Terrain); its walks, their
                                     Jacobians and Monte-Carlo batches in _terrain_run.py
                                     and _core/terrain*.c
                 ──► fixedpoint.py   fixed points, Floquet multipliers; sectionmap.py (map
                                     value and Jacobian, eigen-sorting, input checks),
                                     region.py (walking region), newton.py (Newton / LM)
                     continuation.py natural and pseudo-arclength (steppers.py, one stepper
                                     a method), folds, period doublings (bifurcations.py)
                     basin.py        basins of attraction (threads: strides release the GIL)
                     sweep.py        resumable parameter sweeps on threads or any Executor
                 ──► storage/        HDF5 with provenance, checksums, atomic writes
                 ──► plotting.py     figures and animations
    cli/ sits on top (``walker find|run|continue|basin|sweep|plot``, one module per command)
    and only orchestrates.

The numba versions of the models (walker/models/<name>.py, walker/friction.py and
walker/friction_phases.py, walker/control.py) are the reference the C ports are tested
against bit for bit, and what the HZD analysis tools (hzd.py) and the actuated walkers'
torque plots still call.  numba, an optional dependency, compiles them on their first call
(``walker/_jit.py``), so the compiled path (``walker find``, ``walker basin``, worker
processes) never imports it.

Only ``symbolic`` imports sympy; a simulation derives nothing.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("walker-hybrid")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0+unknown"

from walker.models import MODEL_NAMES, get_model  # noqa: E402
from walker.params import (  # noqa: E402
    CompassParams,
    DoublePendulumParams,
    KneedParams,
    SimplestParams,
)
from walker.results import FixedPoint, MapResult, Solution  # noqa: E402
from walker.scene import Scene, load_scene  # noqa: E402
from walker.status import Status  # noqa: E402
from walker.terrain import Terrain  # noqa: E402


def __getattr__(name):
    # The simulation layer loads on first use, so `import walker` stays light.
    if name in ("simulate", "StrideMap"):
        from walker import stride

        return getattr(stride, name)
    if name == "find_fixed_point":
        from walker.fixedpoint import find_fixed_point

        return find_fixed_point
    raise AttributeError(f"module 'walker' has no attribute {name!r}")


__all__ = [
    "MODEL_NAMES",
    "CompassParams",
    "DoublePendulumParams",
    "FixedPoint",
    "KneedParams",
    "MapResult",
    "Scene",
    "SimplestParams",
    "Solution",
    "Status",
    "StrideMap",
    "Terrain",
    "find_fixed_point",
    "get_model",
    "load_scene",
    "simulate",
    "__version__",
]
