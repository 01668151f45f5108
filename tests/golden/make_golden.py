"""Record walker's golden corpus: today's exact outputs of the compiled C core.

Run from the repository root::

    python tests/golden/make_golden.py

It writes, next to this file:

- ``entries.npz``: for every registry entry of the compiled extension
  (``walker._hybrid.models()``, structural variants included), the inputs (states,
  parameter vectors, times, which phase and guard each call used, section points) and the
  outputs of every phase's rhs, Jacobian and guards, every guard's reset (action, next
  phase, status, post-reset state, impulse), energy, points, start phase and, where
  compiled, the section lift and its Jacobian.  The inputs are drawn with a fixed seed near
  the gait states of the model's shipped scenes (states just before each event of a run,
  states along the run, those perturbed, and perturbed start states with some rates set to
  exactly zero, where joint friction sticks), at the scenes' parameters (a general entry
  also at parameters that its cheaper variants fix at zero, made nonzero).
- ``scenes.npz``: for every shipped scene (``gaits/*.toml``) whose model has strides, one
  stride of its stride map from its state and the stride's Jacobian, and the fixed point
  (section, state, Jacobian, multipliers, step time, residual history); for every scene a
  run with events (a few strides, or a short run for a model without strides).
- ``manifest.json``: what each entry and scene holds (sizes, scenes drawn from, counts, the
  reset outcomes reached), for a reader; the test does not need it.

Every float is stored as the float64 (or complex128) the C core returned, unrounded;
``tests/test_golden.py`` recomputes each array and compares it bit for bit.

When to regenerate
------------------
Only in a commit that changes numbers on purpose, and whose message says which numbers
moved and why (a fixed bug, a deliberate change of an algorithm or a kernel), after the
independent tests (closed forms, conservation laws, literature values, the oracle) have
shown the new numbers are right.  A refactoring, a build change or a port must leave the
corpus untouched: if ``tests/test_golden.py`` fails after one, the change moved a number,
and regenerating to make it pass hides exactly what the corpus is for.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import _golden as G  # noqa: E402

SEED = 20261128
N_SAMPLES = 16
# phases evaluated per sample: all of them when a model has at most this many, else the
# state's own phase (its start phase) and EXTRA_PHASES others drawn at random
ALL_PHASES_UP_TO = 4
EXTRA_PHASES = 2


def _entry_sizes(entry: str) -> dict[str, int]:
    from walker.models import get_model

    model = get_model(entry.partition("/")[0])
    system = model.system
    return {
        "n_x": system.n_x,
        "n_p": len(model.params_class.names()),
        "n_phases": system.n_phases,
        "n_guards": system.n_guards,
        "n_impulse": system.n_impulse,
        "n_points": 1 + max(max(segment) for segment in model.segments),
        "n_z": model.n_z if model.has_strides else 0,
    }


def _scene_pool(base: str, rng) -> list[dict]:
    """For each shipped scene of model ``base``: its parameter vector, and states with times
    (just before each event of a run, along the run, perturbed, perturbed starts)."""
    from walker import load_scene, simulate
    from walker.stride import solver_settings

    pool = []
    for path in G.shipped_scenes():
        scene = load_scene(path)
        if scene.model != base:
            continue
        model = scene.walker_model
        settings = solver_settings(scene.compute)
        if model.has_strides:
            n_strides = 2
            settings["t_max"] *= n_strides
        else:
            n_strides, settings["t_max"] = 0, G.NO_STRIDE_T_MAX
        common = {"n_strides": n_strides, "phase0": scene.phase, **settings}
        run = simulate(model, scene.params, scene.state, output="events", **common)
        times = np.linspace(0.0, run.t, 9)[1:-1]
        samples = simulate(
            model, scene.params, scene.state, output="samples", sample_times=times, **common
        )
        pool.append(
            {
                "scene": scene.name,
                "p": scene.params.as_array().copy(),
                "state": np.array(scene.state, dtype=np.float64),
                "events": (np.asarray(run.events.t), np.asarray(run.events.x_pre)),
                "samples": (np.asarray(samples.samples.t), np.asarray(samples.samples.x)),
            }
        )
    if not pool:
        raise RuntimeError(f"no shipped scene of model {base}")
    return pool


def _entry_inputs(entry: str, rng) -> dict[str, np.ndarray]:
    from walker.models import get_model

    base, _, variant = entry.partition("/")
    model = get_model(base)
    sizes = _entry_sizes(entry)
    pool = _scene_pool(base, rng)
    names = model.params_class.names()
    # the parameters the entry's variant (or, for a general entry, its cheaper variants) fix
    # at exactly zero
    zero_sets = model.variants
    plain = variant.split("/")[0] if variant and variant != "ignore_scuff" else ""
    fixed_zero = {names.index(n) for n in zero_sets.get(plain, ())}
    free_zero = set() if plain else {names.index(n) for v in zero_sets.values() for n in v}
    n_x = sizes["n_x"]
    n_q = (n_x // 2) if base not in ("three_link", "five_link") else (n_x - 2) // 2
    X, P, T = [], [], []
    for i in range(N_SAMPLES):
        src = pool[i % len(pool)]
        kind = (i // len(pool)) % 4
        p = src["p"].copy()
        if kind == 0 and len(src["events"][0]):
            j = rng.integers(len(src["events"][0]))
            t, x = src["events"][0][j], src["events"][1][j].copy()
        elif kind in (1, 2) or not len(src["events"][0]):
            j = rng.integers(len(src["samples"][0]))
            t, x = src["samples"][0][j], src["samples"][1][j].copy()
            if kind == 2:
                x[: 2 * n_q] += rng.normal(0.0, 0.02, 2 * n_q)
        else:
            t = rng.uniform(0.0, 1.0)
            x = src["state"].copy()
            x[: 2 * n_q] += rng.normal(0.0, 0.05, 2 * n_q)
            rates = rng.random(n_q) < 0.5
            x[n_q : 2 * n_q][rates] = 0.0  # joints at rest: friction sticks or slips
        for index in fixed_zero:
            p[index] = 0.0
        if free_zero and i % 2 == 1:
            for index in sorted(free_zero):
                p[index] = rng.uniform(0.01, 0.1)
        X.append(x)
        P.append(p)
        T.append(t)
    X, P, T = np.array(X), np.array(P), np.array(T, dtype=np.float64)
    addresses = G.registry()[entry]
    start = None
    if addresses["start_phase"]:
        start = G.entry_outputs(
            entry,
            addresses,
            {
                "sizes": np.array([sizes[k] for k in G.SIZE_FIELDS], dtype=np.int64),
                "x": X,
                "p": P,
                "t": T,
                "phase_calls": np.zeros((0, 2), dtype=np.int64),
                "reset_calls": np.zeros((0, 3), dtype=np.int64),
                "z": np.zeros((0, sizes["n_z"])),
                "z_p": np.zeros(0, dtype=np.int64),
            },
        )["start_phase"]
    n_phases, n_guards = sizes["n_phases"], sizes["n_guards"]
    phase_calls = []
    for i in range(N_SAMPLES):
        if n_phases <= ALL_PHASES_UP_TO:
            phases = list(range(n_phases))
        else:
            own = int(start[i]) if start is not None else 0
            others = [ph for ph in range(n_phases) if ph != own]
            phases = [own, *rng.choice(others, EXTRA_PHASES, replace=False).tolist()]
        phase_calls.extend((i, ph) for ph in phases)
    reset_calls = [(i, ph, k) for i, ph in phase_calls for k in range(n_guards)]
    z = np.zeros((0, sizes["n_z"]))
    z_p = np.zeros(0, dtype=np.int64)
    if addresses.get("lift"):
        section = [model.state_names.index(n) for n in model.section_names]
        z = X[:, section].copy()
        z_p = np.arange(N_SAMPLES, dtype=np.int64)
    return {
        "sizes": np.array([sizes[k] for k in G.SIZE_FIELDS], dtype=np.int64),
        "x": X,
        "p": P,
        "t": T,
        "phase_calls": np.array(phase_calls, dtype=np.int64).reshape(-1, 2),
        "reset_calls": np.array(reset_calls, dtype=np.int64).reshape(-1, 3),
        "z": z,
        "z_p": z_p,
        "scenes": np.array(sorted({src["scene"] for src in pool})),
    }


def main() -> None:
    rng = np.random.default_rng(SEED)
    registry = G.registry()
    entries: dict[str, np.ndarray] = {}
    manifest: dict = {"seed": SEED, "entries": {}, "scenes": {}}
    for entry in registry:
        inputs = _entry_inputs(entry, rng)
        outputs = G.entry_outputs(entry, registry[entry], inputs)
        for name, value in inputs.items():
            entries[G.key(entry, "in_" + name if name != "sizes" else name)] = value
        for name, value in outputs.items():
            entries[G.key(entry, name)] = value
        triples = {
            (int(k), int(a), int(ph), int(s))
            for (_, _, k), (a, ph, s) in zip(
                inputs["reset_calls"], outputs["reset_out"], strict=True
            )
        }
        manifest["entries"][entry] = {
            "sizes": dict(zip(G.SIZE_FIELDS, inputs["sizes"].tolist(), strict=True)),
            "scenes": inputs["scenes"].tolist(),
            "samples": len(inputs["x"]),
            "phase_calls": len(inputs["phase_calls"]),
            "reset_calls": len(inputs["reset_calls"]),
            "outputs": sorted(outputs),
            "arrays": len(inputs) + len(outputs),
            "reset_outcomes_guard_action_phase_status": sorted(triples),
        }
    scenes: dict[str, np.ndarray] = {}
    for path in G.shipped_scenes():
        out = G.scene_outputs(path)
        for name, value in out.items():
            scenes[f"{path.stem}.{name}"] = value
        manifest["scenes"][path.stem] = sorted(out)
    G.GOLDEN_DIR.mkdir(exist_ok=True)
    G.save(G.ENTRIES_FILE, entries)
    G.save(G.SCENES_FILE, scenes)
    (G.GOLDEN_DIR / "manifest.json").write_text(json.dumps(manifest, indent=1) + "\n")
    for f in (G.ENTRIES_FILE, G.SCENES_FILE):
        print(f"wrote {f.name}: {f.stat().st_size} bytes")


if __name__ == "__main__":
    main()
