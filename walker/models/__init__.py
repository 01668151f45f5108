"""The walkers walker ships, each a :class:`WalkerModel`: a model compiled into the extension
(walker/_core/model_<name>.c, registered in the generated walker/_core/model_table.c) plus its
Python-side description (state, phases, guards, section coordinates).

A model module (``walker/models/<name>.py``) provides, per the contract of
:class:`walker.simulation.integrate.HybridSystem`:

1. ``N_X``, ``STATE_NAMES``: the state, the same in every phase.  ``STATE_NAMES`` is read
   from the model's record in the model registry :data:`walker.params.MODELS` (which also
   holds its parameter class, state units and whether it has strides); ``N_X`` is its
   length.  The compiled registry and the binding's size table are printed from these
   declarations (:mod:`walker.symbolic.codegen_registry`).
2. ``PHASE_NAMES``, ``GUARD_NAMES``, ``DIRECTIONS`` (n_phases, n_guards) and ``N_IMPULSE``
   of the compiled ``rhs``, ``guards``, ``reset`` and ``jac`` (the model's registry entry,
   ``walker._hybrid.models()``).
3. ``SECTION_NAMES`` and ``lift(z, p)`` / ``project(x, p)`` / ``lift_jacobian(z, p)``
   between the Poincare section just after heel strike and the full state (walkers only).
4. ``SEGMENTS``: the pairs of the compiled ``points`` drawn as links.
5. Optionally ``SWING_SCUFF``: the swing-foot scuffing conventions the model offers
   (``("trip", "ignore")``, the default first), compiled as the registry variants
   ``<model>/ignore_scuff`` and ``<model>/<variant>/ignore_scuff`` (:func:`get_model`
   ``swing_scuff``).
6. Optionally ``VARIANTS``: compiled structural variants (walker/_core/model_table.c), name ->
   parameters.  A variant runs kernels generated with these parameters fixed at exactly
   zero, so scenes that leave them at zero pay no arithmetic for them;
   :meth:`WalkerModel.variant_for` picks it.
7. Optionally ``KERNEL_MODULE``, the generated kernels it runs on when they are another
   model's (the friction variants: ``"compass"``, ``"kneed"``), and ``KERNEL_HASH`` for a
   model without generated kernels (the rimless wheel).
8. Optionally ``ACTUATED = True`` beside ``JOINTS``: the model has a controller, and its
   compiled ``torques`` returns one torque per joint of ``JOINTS``.

The compiled functions are called from Python through the checked methods of
:class:`WalkerModel` (``rhs``, ``guards``, ``jac``, ``reset``, ``energy``, ``points``,
``start_phase``, ``torques``, ``kernel``; walker/models/_compiled.py): every length and dtype
is checked before the call, and an error names the argument.  Nothing here is compiled at
run time, and numba is never imported.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from walker.models._compiled import (
    _kernel_table,
    as_index,
    as_vector,
    call_kernel,
    call_phase_fn,
    call_reset,
)
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
        """The :class:`walker.simulation.integrate.HybridSystem` specialised to parameters ``p``:
        the variant is chosen once, here, when a stride map or a run is set up (and under
        ``swing_scuff = "ignore"`` its ``/ignore_scuff`` twin)."""
        return self._system(self._with_convention(self.variant_for(p)))

    @property
    def system(self):
        """The general :class:`walker.simulation.integrate.HybridSystem` (every parameter
        honoured)."""
        return self._system(self._with_convention(""))

    def _with_convention(self, variant: str) -> str:
        if self.swing_scuff == "trip":
            return variant
        return f"{variant}/ignore_scuff" if variant else "ignore_scuff"

    def _system(self, variant: str):
        cache = self.__dict__.setdefault("_systems", {})
        if variant not in cache:
            from walker.simulation.integrate import HybridSystem

            m = self.module
            compiled = self._compiled[variant]
            fns = {k: compiled[k] for k in ("rhs", "guards", "reset", "jac")}
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
    segments = _module_attr("SEGMENTS", "Pairs of :meth:`points` rows joined for drawing.")

    @cached_property
    def kernel_hash(self) -> str:
        """Hash of the model's generated kernels (the one stamped on its generated C module,
        ``walker._hybrid.kernel_hashes()``), or of its hand-written equations (``KERNEL_HASH``
        of a model without generated kernels, the rimless wheel)."""
        declared = getattr(self.module, "KERNEL_HASH", None)
        if declared is not None:
            return declared
        from walker import _hybrid

        return _hybrid.kernel_hashes()[self._kernel_module]

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

    # -- the compiled model, called through checked interfaces (walker/models/_compiled.py):
    # every length and dtype is checked before the call, an error names the argument.

    def _state_fn(self, name: str):
        """The compiled helper ``name`` (energy, points, start_phase, lift, lift_jacobian,
        torques) of the general entry, or None when the model has no such helper."""
        address = self._compiled.get("", {}).get(name, 0)
        return address or None

    @cached_property
    def n_params(self) -> int:
        """Length of the parameter array ``p``."""
        return len(self.params_class.names())

    def _state_args(self, x, p) -> tuple[np.ndarray, np.ndarray]:
        return as_vector(x, "x", self.n_x), as_vector(p, "p", self.n_params)

    def _phase_args(self, phase, x, p):
        phase = as_index(phase, "phase", len(self.phase_names))
        return (phase, *self._state_args(x, p))

    def rhs(self, phase: int, x, p, t: float = 0.0) -> np.ndarray:
        """The vector field ``dx/dt`` (n_x,) in ``phase`` at state ``x`` (the compiled
        function the integrator runs)."""
        phase, x, p = self._phase_args(phase, x, p)
        return call_phase_fn(self.system.rhs, phase, t, x, p, (self.n_x,))

    def guards(self, phase: int, x, p, t: float = 0.0) -> np.ndarray:
        """The guard values (n_guards,) in ``phase`` at state ``x``."""
        phase, x, p = self._phase_args(phase, x, p)
        return call_phase_fn(self.system.guards, phase, t, x, p, (len(self.guard_names),))

    def jac(self, phase: int, x, p, t: float = 0.0) -> np.ndarray:
        """The Jacobian ``d(dx/dt)/dx`` (n_x, n_x) in ``phase`` at state ``x``."""
        phase, x, p = self._phase_args(phase, x, p)
        return call_phase_fn(self.system.jac, phase, t, x, p, (self.n_x, self.n_x))

    def reset(self, phase: int, k: int, x, p, t: float = 0.0):
        """Run the compiled reset map the integrator runs (under this model's conventions),
        for guard ``k`` firing at state ``x`` in ``phase``.

        Returns ``(action, next_phase, status, x_new, impulse)``: ``action`` one of the
        ``walker.status.EVENT_*`` values, ``status`` a :class:`walker.status.Status` value.
        """
        phase, x, p = self._phase_args(phase, x, p)
        k = as_index(k, "k", len(self.guard_names))
        return call_reset(self.system.reset, phase, k, t, x, p, self.module.N_IMPULSE)

    apply_reset = reset  # the former name

    def energy(self, x, p) -> tuple[float, float]:
        """(kinetic, potential) energy of one state [J]."""
        from walker import _hybrid

        kinetic, potential = _hybrid.call_state_fn(
            self._state_fn("energy"), *self._state_args(x, p), 2
        )
        return kinetic, potential

    def energies(self, x, p) -> tuple[np.ndarray, np.ndarray]:
        """Kinetic and potential energy of each row of ``x`` (n, n_x)."""
        x = np.atleast_2d(np.asarray(x, dtype=np.float64))
        out = np.array([self.energy(row, p) for row in x]).reshape(-1, 2)
        return out[:, 0], out[:, 1]

    def start_phase(self, x, p) -> int:
        """The phase consistent with state ``x`` (0 for models with one choice)."""
        address = self._state_fn("start_phase")
        x, p = self._state_args(x, p)
        if address is None:
            return 0
        from walker import _hybrid

        return int(_hybrid.call_state_fn(address, x, p, 1)[0])

    def start_phase_fn(self):
        """The phase choice for the hot path: ``(x, p) -> int`` on arrays already checked
        (C-contiguous float64 of the model's lengths), no conversion or shape check per call;
        None when every state starts in phase 0.  :meth:`start_phase` is the checked form."""
        address = self._state_fn("start_phase")
        if address is None:
            return None
        from walker import _hybrid

        call = _hybrid.call_state_fn
        return lambda x, p: int(call(address, x, p, 1)[0])

    def points(self, x, p) -> np.ndarray:
        """Joint positions (n_points, 2) for drawing the walker at state ``x``."""
        from walker import _hybrid

        n_points = 1 + max(max(segment) for segment in self.segments)
        flat = _hybrid.call_state_fn(
            self._state_fn("points"), *self._state_args(x, p), 2 * n_points
        )
        return np.array(flat).reshape(n_points, 2)

    @property
    def has_torques(self) -> bool:
        """Whether the model has actuators (:meth:`torques`)."""
        return self._state_fn("torques") is not None

    def torques(self, x, p) -> np.ndarray:
        """The controller's torques (n_inputs,) [N m] at state ``x``, as the compiled rhs
        applies them before any joint friction (actuated walkers only)."""
        address = self._state_fn("torques")
        if address is None:
            raise ValueError(f"model {self.name} has no actuators (no `torques`)")
        from walker import _hybrid

        n_inputs = len(self.module.JOINTS)
        return np.array(_hybrid.call_state_fn(address, *self._state_args(x, p), n_inputs))

    def kernel(self, name: str, p, q, qd=None, qdd=None):
        """The generated C kernel ``name`` of this model (``"mass_matrix"``, ``"bias"``,
        ``"points"``, ...; the list is :attr:`kernel_names`) at coordinates ``q`` (and rates
        ``qd``, accelerations ``qdd`` where it takes them) and parameters ``p``: an ndarray of
        the kernel's output shape, or a float (``kinetic``, ``potential``)."""
        if not isinstance(name, str):
            raise TypeError(f"`name` must be a str, got {name!r}")
        if name not in self.kernel_names:
            raise ValueError(f"`name` must be one of {list(self.kernel_names)}, got {name!r}")
        return call_kernel(f"{self._kernel_module}.{name}", _p(p), q, qd, qdd)

    @cached_property
    def _kernel_module(self) -> str:
        return getattr(self.module, "KERNEL_MODULE", self.name)

    @cached_property
    def kernel_names(self) -> tuple[str, ...]:
        """The generated C kernels of this model (:meth:`kernel`)."""
        prefix = f"{self._kernel_module}."
        return tuple(k[len(prefix) :] for k in _kernel_table() if k.startswith(prefix))


def _p(p) -> np.ndarray:
    if hasattr(p, "as_array"):
        return p.as_array()
    return np.ascontiguousarray(p, dtype=np.float64)


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
