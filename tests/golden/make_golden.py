"""Record walker's golden corpus: today's exact outputs of the compiled C core.

Run from the repository root::

    python tests/golden/make_golden.py

It writes, next to this file:

- ``entries.npz``: for every registry entry of the compiled extension
  (``walker._hybrid.models()``, structural variants included), the inputs (states,
  parameter vectors, times, which phase and guard each call used, section points) and the
  outputs of every phase's rhs, Jacobian (and the fused rhs and Jacobian of the entries that
  have one) and guards, every guard's reset (action, next
  phase, status, post-reset state, impulse), energy, points, start phase and, where
  compiled, the section lift and its Jacobian.  The inputs are drawn with a fixed seed near
  the gait states of the model's shipped scenes (states just before each event of a run,
  states along the run, those perturbed, and perturbed start states with some rates set to
  exactly zero, where joint friction sticks, and start states far off, where the walkers
  fall, trip or strike without a physical impact), at the scenes' parameters (a general
  entry also at parameters that its cheaper variants fix at zero, made nonzero; the far-off
  states also uphill, and the rimless wheel with 3 and 4 spokes).
- ``scenes.npz``: for every shipped scene (``gaits/*.toml``) whose model has strides, one
  stride of its stride map from its state and the stride's Jacobian, and the fixed point
  (section, state, Jacobian, multipliers, step time, residual history); for every scene a
  run with events (a few strides, or a short run for a model without strides).
- ``manifest.json``: what each entry and scene holds (sizes, scenes drawn from, samples of
  each kind, counts, the reset outcomes reached: guard, action ``walker.status.EVENT_*``,
  status ``walker.status.Status``), for a reader; the test does not need it.

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
N_SAMPLES = 20
# Candidates are drawn in turn of KINDS (and the model's EXTRA_KINDS): a state just before an
# event of a run, a state along the run, that perturbed, the start state perturbed with some
# joint rates exactly zero, and (twice as often) the start state far off: angles and rates
# widely spread, the slope's sign drawn at random, and the parameters in WIDE_PARAMS drawn
# from their lists, which reaches falls, trips and non-physical impacts.  N_SAMPLES are
# kept of CANDIDATES_PER_SAMPLE * N_SAMPLES: one of each kind, then those that reach reset
# outcomes the others do not (_select).
KINDS = ("event", "along", "along_perturbed", "rest", "wide", "wide")
CANDIDATES_PER_SAMPLE = 10
# the kneed walkers also at states with the knee exactly straight (the swing-foot contact
# of an unlocked knee at the lock angle locks it first)
EXTRA_KINDS = {"kneed": ("knee_straight",), "kneed_coulomb": ("knee_straight",)}
WIDE_PARAMS = {"rimless_wheel": {"spokes": (3.0, 4.0, 8.0)}}
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
    from walker.simulation.stride import solver_settings

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


def _draw(kind, src, names, base, n_q, rng):
    """One sample (state, parameters, time) of ``kind`` near the scene ``src``."""
    p = src["p"].copy()
    event_t, event_x = src["events"]
    if kind in ("event", "knee_straight") and len(event_t):
        j = rng.integers(len(event_t))
        t, x = event_t[j], event_x[j].copy()
        if kind == "knee_straight":  # the knee exactly straight, its rate not yet matched
            x[2] = x[1]
    elif kind in ("event", "along", "along_perturbed", "knee_straight"):
        j = rng.integers(len(src["samples"][0]))
        t, x = src["samples"][0][j], src["samples"][1][j].copy()
        if kind == "along_perturbed":
            x[: 2 * n_q] += rng.normal(0.0, 0.02, 2 * n_q)
        if kind == "knee_straight":
            x[2] = x[1]
    elif kind == "rest":
        t = rng.uniform(0.0, 1.0)
        x = src["state"].copy()
        x[: 2 * n_q] += rng.normal(0.0, 0.05, 2 * n_q)
        rates = rng.random(n_q) < 0.5
        x[n_q : 2 * n_q][rates] = 0.0  # joints at rest: friction sticks or slips
    else:  # "wide"
        t = rng.uniform(0.0, 1.0)
        x = src["state"].copy()
        rate_scale = max(1.0, float(np.abs(x[n_q : 2 * n_q]).max()))
        x[:n_q] += rng.normal(0.0, 0.3, n_q)
        x[n_q : 2 * n_q] += rng.normal(0.0, rate_scale, n_q)
        if "slope" in names and rng.random() < 0.5:
            p[names.index("slope")] *= -1.0
        for name, values in WIDE_PARAMS.get(base, {}).items():
            p[names.index(name)] = rng.choice(values)
    return x, p, float(t)


def _calls(sizes, start, rng):
    """The phases evaluated at each sample: all, or its own and EXTRA_PHASES others."""
    n_phases = sizes["n_phases"]
    phase_calls = []
    for i, own in enumerate(start):
        if n_phases <= ALL_PHASES_UP_TO:
            phases = list(range(n_phases))
        else:
            others = [ph for ph in range(n_phases) if ph != own]
            phases = [own, *rng.choice(others, EXTRA_PHASES, replace=False).tolist()]
        phase_calls.extend((i, ph) for ph in phases)
    reset_calls = [(i, ph, k) for i, ph in phase_calls for k in range(sizes["n_guards"])]
    return (
        np.array(phase_calls, dtype=np.int64).reshape(-1, 2),
        np.array(reset_calls, dtype=np.int64).reshape(-1, 3),
    )


def _select(kinds, outcomes):
    """N_SAMPLES candidates: the first of each kind, then greedily the ones that reach reset
    outcomes (guard, action, status) not reached yet, then the rest in order."""
    chosen, reached = [], set()
    for kind in dict.fromkeys(kinds):
        chosen.append(kinds.index(kind))
    for i in chosen:
        reached |= outcomes[i]
    while len(chosen) < N_SAMPLES:
        gains = [len(o - reached) if i not in chosen else -1 for i, o in enumerate(outcomes)]
        best = int(np.argmax(gains))
        if gains[best] <= 0:
            break
        chosen.append(best)
        reached |= outcomes[best]
    rest = [i for i in range(len(kinds)) if i not in chosen]
    return sorted(chosen + rest[: N_SAMPLES - len(chosen)])


def _entry_inputs(entry: str, rng) -> dict[str, np.ndarray]:
    from walker.models import get_model

    base, _, variant = entry.partition("/")
    model = get_model(base)
    sizes = _entry_sizes(entry)
    size_vector = np.array([sizes[k] for k in G.SIZE_FIELDS], dtype=np.int64)
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
    kinds_cycle = KINDS + EXTRA_KINDS.get(base, ())
    X, P, T, kinds = [], [], [], []
    for i in range(CANDIDATES_PER_SAMPLE * N_SAMPLES):
        src = pool[i % len(pool)]
        kind = kinds_cycle[(i // len(pool)) % len(kinds_cycle)]
        x, p, t = _draw(kind, src, names, base, n_q, rng)
        for index in fixed_zero:
            p[index] = 0.0
        if free_zero and i % 2 == 1:
            for index in sorted(free_zero):
                p[index] = rng.uniform(0.01, 0.1)
        X.append(x)
        P.append(p)
        T.append(t)
        kinds.append(kind)
    X, P, T = np.array(X), np.array(P), np.array(T, dtype=np.float64)
    addresses = G.registry()[entry]
    empty = {
        "sizes": size_vector,
        "x": X,
        "p": P,
        "t": T,
        "phase_calls": np.zeros((0, 2), dtype=np.int64),
        "reset_calls": np.zeros((0, 3), dtype=np.int64),
        "z": np.zeros((0, sizes["n_z"])),
        "z_p": np.zeros(0, dtype=np.int64),
    }
    start = np.zeros(len(X), dtype=np.int64)
    if addresses["start_phase"]:
        start = G.entry_outputs(entry, addresses, empty)["start_phase"].astype(np.int64)
    # the reset outcomes each candidate reaches, for the selection
    phase_calls, reset_calls = _calls(sizes, start, rng)
    reached = G.entry_outputs(entry, addresses, {**empty, "reset_calls": reset_calls})
    outcomes = [set() for _ in range(len(X))]
    for (i, _, k), (action, _, status) in zip(
        reset_calls.tolist(), reached["reset_out"].tolist(), strict=True
    ):
        outcomes[i].add((k, action, status))
    keep = _select(kinds, outcomes)
    X, P, T, start = X[keep], P[keep], T[keep], start[keep]
    phase_calls, reset_calls = _calls(sizes, start, rng)
    z = np.zeros((0, sizes["n_z"]))
    z_p = np.zeros(0, dtype=np.int64)
    if addresses.get("lift"):
        section = [model.state_names.index(n) for n in model.section_names]
        z = X[:, section].copy()
        z_p = np.arange(len(X), dtype=np.int64)
    return {
        "sizes": size_vector,
        "x": X,
        "p": P,
        "t": T,
        "phase_calls": phase_calls,
        "reset_calls": reset_calls,
        "z": z,
        "z_p": z_p,
        "kinds": np.array([kinds[i] for i in keep]),
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
        reached = sorted(
            {
                f"guard {k} action {a} status {st}"
                for (_, _, k), (a, _, st) in zip(
                    inputs["reset_calls"].tolist(), outputs["reset_out"].tolist(), strict=True
                )
            }
        )
        kinds = inputs["kinds"].tolist()
        manifest["entries"][entry] = {
            "sizes": dict(zip(G.SIZE_FIELDS, inputs["sizes"].tolist(), strict=True)),
            "scenes": inputs["scenes"].tolist(),
            "samples": {kind: kinds.count(kind) for kind in dict.fromkeys(kinds)},
            "phase_calls": len(inputs["phase_calls"]),
            "reset_calls": len(inputs["reset_calls"]),
            "outputs": sorted(outputs),
            "arrays": len(inputs) + len(outputs),
            "reset_outcomes_reached": reached,
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
