"""The walkers walker ships, each a :class:`WalkerModel`: compiled phase functions plus the
Python-side description (state, phases, guards, section coordinates).

A model module (``walker/models/<name>.py``) provides, per the contract of
:class:`walker.integrate.HybridSystem`:

1. ``N_X``, ``STATE_NAMES``: the state, the same in every phase.  ``STATE_NAMES`` is read
   from the model's record in the model registry :data:`walker.params.MODELS` (which also
   holds its parameter class, state units and whether it has strides); ``N_X``, its length,
   is written out for the compiled code (``tests/test_models.py`` checks that they agree).
2. ``PHASE_NAMES``, ``GUARD_NAMES``, ``DIRECTIONS`` (n_phases, n_guards) and compiled
   ``rhs``, ``guards``, ``reset``, ``jac`` (vector field Jacobian for the variational
   equations), ``N_IMPULSE``.
3. ``SECTION_NAMES`` and ``lift(z, p)`` / ``project(x, p)`` / ``lift_jacobian(z, p)``
   between the Poincare section just after heel strike and the full state (walkers only).
4. ``energy(x, p) -> (kinetic, potential)``, ``points(x, p)`` and ``SEGMENTS`` for drawing.
5. Optionally ``start_phase(x, p) -> int``: the phase a run from state ``x`` starts in, for
   models whose phase depends on the state (joint friction modes: a joint at rest sticks or
   slips depending on the forces).  Without it a run starts in phase 0.
6. Optionally ``SWING_SCUFF``: the swing-foot scuffing conventions the model offers
   (``("trip", "ignore")``, the default first) and ``reset_ignore_scuff``, the reset map
   under ``"ignore"``, compiled as the registry variants ``<model>/ignore_scuff`` and
   ``<model>/<variant>/ignore_scuff`` (:func:`get_model` ``swing_scuff``).
7. Optionally ``VARIANTS``: compiled structural variants (walker/_core/models.c), name ->
   parameters.  A variant runs kernels generated with these parameters fixed at exactly
   zero, so scenes that leave them at zero pay no arithmetic for them;
   :meth:`WalkerModel.variant_for` picks it.

Importing a model compiles nothing; a compass-gait run never loads the kneed kernels.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from walker.params import MODELS, ModelSpec

__all__ = ["WalkerModel", "get_model", "MODEL_NAMES"]

MODEL_NAMES = tuple(MODELS)
"""The models walker ships: the keys of the model registry :data:`walker.params.MODELS`."""


def _spec_attr(name: str, doc: str) -> property:
    """A read-only property of :class:`WalkerModel`: attribute ``name`` of the model's
    registry record (:attr:`WalkerModel.spec`)."""
    return property(lambda self: getattr(self.spec, name), doc=doc)


def _module_attr(name: str, doc: str) -> property:
    """A read-only property of :class:`WalkerModel`: attribute ``name`` of the model's
    module."""
    return property(lambda self: getattr(self.module, name), doc=doc)


@dataclass(frozen=True, eq=False)
class WalkerModel:
    """A model: its compiled functions (module) and their description.

    Use :func:`get_model` rather than constructing one.

    Attributes
    ----------
    name : str
    swing_scuff : str
        swing-foot scuffing convention, ``"trip"`` (default) or ``"ignore"`` (models whose
        module declares ``SWING_SCUFF``; see :mod:`walker.models.kneed`).
    """

    name: str
    swing_scuff: str = "trip"

    def __reduce__(self):
        # Pickle by name and convention: the receiving process looks the model up again (its
        # compiled functions are the extension's), so models and stride maps travel to worker
        # processes.
        return (get_model, (self.name, self.swing_scuff))

    @cached_property
    def module(self):
        return importlib.import_module(f"walker.models.{self.name}")

    @cached_property
    def conventions(self) -> dict[str, str]:
        """The modelling conventions this model offers and the ones it runs under, e.g.
        ``{"swing_scuff": "ignore"}`` (empty for a model with none); results carry them
        (:attr:`walker.results.Solution.conventions`)."""
        if getattr(self.module, "SWING_SCUFF", ()):
            return {"swing_scuff": self.swing_scuff}
        return {}

    @cached_property
    def _compiled(self) -> dict:
        """This model's entries in the extension's registry, by variant ("" is general)."""
        from walker import _hybrid

        out = {}
        for key, addresses in _hybrid.models().items():
            name, _, variant = key.partition("/")
            if name == self.name:
                out[variant] = addresses
        return out

    @property
    def variants(self) -> dict[str, tuple[str, ...]]:
        """Structural variants compiled for this model: name -> the parameters that must be
        exactly zero for it (see :meth:`variant_for`)."""
        declared = getattr(self.module, "VARIANTS", {})
        return {k: v for k, v in declared.items() if k in self._compiled}

    @cached_property
    def _variant_indices(self) -> tuple[tuple[str, tuple[int, ...]], ...]:
        names = self.params_class.names()
        return tuple(
            (variant, tuple(names.index(n) for n in zeros))
            for variant, zeros in self.variants.items()
        )

    def variant_for(self, p) -> str:
        """The cheapest compiled variant valid at parameters ``p``: one whose zero
        parameters are all exactly zero in ``p`` ("" for the general kernels)."""
        values = _p(p).tolist()
        for variant, indices in self._variant_indices:
            if all(values[i] == 0.0 for i in indices):
                return variant
        return ""

    def system_for(self, p):
        """The :class:`walker.integrate.HybridSystem` specialised to parameters ``p``: the
        variant is chosen once, here, when a stride map or a run is set up (and under
        ``swing_scuff = "ignore"`` its ``/ignore_scuff`` twin)."""
        return self._system(self._with_convention(self.variant_for(p)))

    @property
    def system(self):
        """The general :class:`walker.integrate.HybridSystem` (every parameter honoured)."""
        return self._system(self._with_convention(""))

    def _with_convention(self, variant: str) -> str:
        if self.swing_scuff == "trip":
            return variant
        return f"{variant}/ignore_scuff" if variant else "ignore_scuff"

    def _system(self, variant: str):
        cache = self.__dict__.setdefault("_systems", {})
        if variant not in cache:
            from walker.integrate import HybridSystem

            m = self.module
            compiled = self._compiled.get(variant)
            if compiled is not None:
                fns = {k: compiled[k] for k in ("rhs", "guards", "reset", "jac")}
            else:  # a model still written with numba: bridged to the C integrator
                reset = m.reset_ignore_scuff if variant.endswith("ignore_scuff") else m.reset
                fns = {"rhs": m.rhs, "guards": m.guards, "reset": reset, "jac": m.jac}
            cache[variant] = HybridSystem(
                name=self.name if not variant else f"{self.name}/{variant}",
                n_x=m.N_X,
                n_phases=len(m.PHASE_NAMES),
                n_guards=len(m.GUARD_NAMES),
                n_impulse=m.N_IMPULSE,
                directions=m.DIRECTIONS,
                phase_names=m.PHASE_NAMES,
                guard_names=m.GUARD_NAMES,
                n_params=len(self.params_class.names()),
                autonomous_guards=True,  # no model's guards read t
                **fns,
            )
        return cache[variant]

    @property
    def spec(self) -> ModelSpec:
        """This model's record in the model registry :data:`walker.params.MODELS`."""
        return MODELS[self.name]

    params_class = _spec_attr("params_class", "The model's parameter class.")
    state_names = _spec_attr("state_names", "Name of each component of the full state.")
    state_units = _spec_attr(
        "state_units",
        "Unit of each component of the full state, parallel to :attr:`state_names`.",
    )
    has_strides = _spec_attr(
        "has_strides",
        "Whether the model walks: heel strikes end strides, and it has a Poincare section "
        "(its registry record's ``has_strides``).",
    )
    is_walker = _spec_attr(
        "has_strides", "The former name of :attr:`has_strides`, kept for code that reads it."
    )
    n_x = _module_attr("N_X", "Length of the full state.")
    section_names = _module_attr("SECTION_NAMES", "Names of the section coordinates.")
    phase_names = _module_attr("PHASE_NAMES", "Name of each phase.")
    guard_names = _module_attr("GUARD_NAMES", "Name of each guard, in priority order.")
    kernel_hash = _module_attr("KERNEL_HASH", "Hash of the model's generated kernels.")
    segments = _module_attr("SEGMENTS", "Pairs of :meth:`points` rows joined for drawing.")

    @cached_property
    def n_z(self) -> int:
        return len(self.module.SECTION_NAMES)

    def lift(self, z, p) -> np.ndarray:
        """Section coordinates -> full state just after heel strike."""
        return self.module.lift(np.asarray(z, dtype=float), _p(p))

    def lift_jacobian(self, z, p) -> np.ndarray:
        return self.module.lift_jacobian(np.asarray(z, dtype=float), _p(p))

    def project(self, x, p) -> np.ndarray:
        """Full state -> section coordinates."""
        return self.module.project(np.asarray(x, dtype=float), _p(p))

    def _state_fn(self, name: str):
        """The compiled helper ``name`` (energy, points, start_phase, lift, lift_jacobian)
        of the general entry, or None when the model has no C entry or no such helper."""
        address = self._compiled.get("", {}).get(name, 0)
        return address or None

    def _state_args(self, x, p) -> tuple[np.ndarray, np.ndarray]:
        x = np.ascontiguousarray(x, dtype=np.float64)
        pp = _p(p)
        if x.shape != (self.n_x,):
            raise ValueError(f"`x` must have shape ({self.n_x},), got {x.shape}")
        n_p = len(self.params_class.names())
        if pp.shape != (n_p,):
            raise ValueError(f"`p` must have shape ({n_p},), got {pp.shape}")
        return x, pp

    def energy(self, x, p) -> tuple[float, float]:
        """(kinetic, potential) energy of one state [J]."""
        address = self._state_fn("energy")
        if address is None:
            return self.module.energy(np.ascontiguousarray(x, dtype=np.float64), _p(p))
        from walker import _hybrid

        kinetic, potential = _hybrid.call_state_fn(address, *self._state_args(x, p), 2)
        return kinetic, potential

    def energies(self, x, p) -> tuple[np.ndarray, np.ndarray]:
        """Kinetic and potential energy of each row of ``x`` (n, n_x)."""
        x = np.atleast_2d(np.asarray(x, dtype=np.float64))
        out = np.array([self.energy(row, p) for row in x]).reshape(-1, 2)
        return out[:, 0], out[:, 1]

    def start_phase(self, x, p) -> int:
        """The phase consistent with state ``x`` (0 for models with one choice)."""
        address = self._state_fn("start_phase")
        if address is not None:
            from walker import _hybrid

            return int(_hybrid.call_state_fn(address, *self._state_args(x, p), 1)[0])
        fn = getattr(self.module, "start_phase", None)
        if fn is None:
            return 0
        return int(fn(np.ascontiguousarray(x, dtype=np.float64), _p(p)))

    def start_phase_fn(self):
        """The phase choice for the hot path: ``(x, p) -> int`` on arrays already checked
        (C-contiguous float64 of the model's lengths), no conversion or shape check per call;
        None when every state starts in phase 0.  :meth:`start_phase` is the checked form."""
        address = self._state_fn("start_phase")
        if address is not None:
            from walker import _hybrid

            call = _hybrid.call_state_fn
            return lambda x, p: int(call(address, x, p, 1)[0])
        fn = getattr(self.module, "start_phase", None)
        if fn is None:
            return None
        return lambda x, p: int(fn(x, p))

    def apply_reset(self, phase: int, k: int, x, p, t: float = 0.0):
        """Run the compiled reset map the integrator runs, for guard ``k`` firing at state
        ``x`` in ``phase`` (analysis tools; the integrator calls it itself).

        Returns ``(action, next_phase, status, x_new, impulse)``: ``action`` one of the
        ``walker.status.EVENT_*`` values, ``status`` a :class:`walker.status.Status` value.
        """
        import ctypes

        from walker.integrate import _compiled

        x, pp = self._state_args(x, p)
        system = self.system
        if not (0 <= phase < system.n_phases and 0 <= k < system.n_guards):
            raise ValueError(
                f"`phase` must be in [0, {system.n_phases}) and `k` in [0, {system.n_guards}), "
                f"got {phase}, {k}"
            )
        dbl = ctypes.POINTER(ctypes.c_double)
        i64 = ctypes.POINTER(ctypes.c_int64)
        fn = _RESET_TYPE(_compiled(system)[2])
        x_new = x.copy()
        impulse = np.zeros(system.n_impulse)
        out = np.zeros(3, dtype=np.int64)
        fn(
            phase,
            k,
            float(t),
            x.ctypes.data_as(dbl),
            pp.ctypes.data_as(dbl),
            x_new.ctypes.data_as(dbl),
            impulse.ctypes.data_as(dbl),
            out.ctypes.data_as(i64),
            None,
        )
        return int(out[0]), int(out[1]), int(out[2]), x_new, impulse

    def points(self, x, p) -> np.ndarray:
        """Joint positions (n_points, 2) for drawing the walker at state ``x``."""
        address = self._state_fn("points")
        if address is None:
            return self.module.points(np.asarray(x, dtype=float), _p(p))
        from walker import _hybrid

        n_points = 1 + max(max(segment) for segment in self.segments)
        flat = _hybrid.call_state_fn(address, *self._state_args(x, p), 2 * n_points)
        return np.array(flat).reshape(n_points, 2)


def _p(p) -> np.ndarray:
    if hasattr(p, "as_array"):
        return p.as_array()
    return np.ascontiguousarray(p, dtype=np.float64)


def _reset_type():
    import ctypes

    dbl = ctypes.POINTER(ctypes.c_double)
    return ctypes.CFUNCTYPE(
        None,
        ctypes.c_int64,
        ctypes.c_int64,
        ctypes.c_double,
        dbl,
        dbl,
        dbl,
        dbl,
        ctypes.POINTER(ctypes.c_int64),
        ctypes.c_void_p,
    )


_RESET_TYPE = _reset_type()
"""ctypes prototype of a reset map (walker/_core/wk_system.h)."""

_CACHE: dict[tuple[str, str], WalkerModel] = {}


def get_model(name: str, swing_scuff: str = "trip") -> WalkerModel:
    """The model called ``name``; one of :data:`MODEL_NAMES`.

    Parameters
    ----------
    name : str
    swing_scuff : str
        swing-foot scuffing convention: ``"trip"`` (default; a swing foot touching the
        ground with the knee bent ends the run ``TRIPPED``) or ``"ignore"`` (it passes
        through the ground, as in McGeer's analysis and most published kneed-walker codes),
        for models that offer it (``kneed``).

    Examples
    --------
    >>> from walker.models import get_model
    >>> get_model("kneed", swing_scuff="ignore").system.name
    'kneed/ignore_scuff'
    """
    if name not in MODEL_NAMES:
        raise ValueError(f"`model` must be one of {list(MODEL_NAMES)}, got {name!r}")
    if not isinstance(swing_scuff, str):
        raise TypeError(f"`swing_scuff` must be a str, got {swing_scuff!r}")
    key = (name, swing_scuff)
    model = _CACHE.get(key)
    if model is None:
        if swing_scuff != "trip":
            offered = getattr(importlib.import_module(f"walker.models.{name}"), "SWING_SCUFF", ())
            if swing_scuff not in offered:
                with_option = [n for n in MODEL_NAMES if _offers_ignore(n)]
                raise ValueError(
                    f"`swing_scuff` must be one of {list(offered or ('trip',))} for model "
                    f"{name} ('ignore' is offered by {', '.join(with_option)}), got "
                    f"{swing_scuff!r}"
                )
        model = _CACHE[key] = WalkerModel(name, swing_scuff)
    return model


def _offers_ignore(name: str) -> bool:
    module = importlib.import_module(f"walker.models.{name}")
    return "ignore" in getattr(module, "SWING_SCUFF", ())
