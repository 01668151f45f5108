"""The random-parameter stress of issue 33 ("Extreme but valid inputs"): for every model,
parameter sets drawn with a fixed seed at or near the bounds ``walker params MODEL --json``
allows, through ``walker find`` and ``walker run --strides 3``.  Each call must end with an
outcome or a refusal (exit 0, 1 or 2), never an internal error (exit 3) and never run past
its budgets: each call runs ``walker.cli.main`` in a child process killed after
``CALL_LIMIT`` seconds (a runaway, not a speed measurement: a healthy call takes about a
second)."""

from __future__ import annotations

import json
import math
import random
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]
GAITS = ROOT / "gaits"


def _scenes() -> dict[str, str]:
    """Every model of the registry -> one shipped scene of it: the first by name with a
    ``[reference]`` table, else the first by name."""
    from walker.models import MODEL_NAMES

    out = {}
    for path in sorted(GAITS.glob("*.toml")):
        data = tomllib.loads(path.read_text(encoding="utf-8"))
        model, has_reference = data["scene"]["model"], "reference" in data
        if model not in out or (has_reference and not out[model][1]):
            out[model] = (path.stem, has_reference)
    assert set(out) == set(MODEL_NAMES), "every model needs a shipped scene"
    return {model: out[model][0] for model in MODEL_NAMES}


SCENES = _scenes()
DRAWS = 8  # parameter sets per model
KEYS_PER_DRAW = 2  # parameters moved to a bound in each set
# s; a call still running then is a runaway.  The slowest healthy call found, the kneed
# walker with thigh_com_to_hip = 0 run for 3 strides, ends in MAX_STEPS after its budget of
# 1e6 steps in about 9 s alone, and on 2 cores shared with other jobs past 20 s.
CALL_LIMIT = 60.0
SEED = 33

_CHILD = "import sys; from walker.cli import main; sys.exit(main(sys.argv[1:]))"


def _bounds(model: str) -> list[dict]:
    out = subprocess.run(
        [sys.executable, "-m", "walker", "params", model, "--json"],
        capture_output=True,
        text=True,
        check=True,
        cwd=ROOT,
    )
    return json.loads(out.stdout)["parameters"]


def _near_bound(spec: dict, rng: random.Random) -> float:
    """A value at or near one of the bounds of ``spec`` (``walker params --json``'s entry),
    or an extreme one where a side is unbounded."""
    low, high = spec["min"], spec["max"]
    if rng.random() < 0.5:  # the lower side
        if low is None:
            return -(10.0 ** rng.uniform(2.0, 300.0))
        if spec["min_inclusive"]:
            return float(low)
        if low == 0.0:
            return 10.0 ** rng.uniform(-323.0, -3.0)
        return math.nextafter(low, math.inf) if rng.random() < 0.5 else low + abs(low) * 1e-9
    if high is None:
        return 10.0 ** rng.uniform(2.0, 300.0)
    if spec["max_inclusive"]:
        return float(high)
    return math.nextafter(high, -math.inf) if rng.random() < 0.5 else high - abs(high) * 1e-9


def _draws(model: str) -> list[list[str]]:
    """``DRAWS`` lists of ``--set key=value`` arguments, seeded by the model's name."""
    rng = random.Random(f"{SEED}-{model}")
    specs = _bounds(model)
    sets = []
    for _ in range(DRAWS):
        chosen = rng.sample(specs, KEYS_PER_DRAW)
        argv = []
        for spec in chosen:
            argv += ["--set", f"{spec['name']}={_near_bound(spec, rng)!r}"]
        sets.append(argv)
    return sets


def _call(argv: list[str]) -> tuple[int | None, str]:
    """Exit code of ``walker.cli.main(argv)`` in a child process (None: still running after
    ``CALL_LIMIT`` s, killed) and its stderr."""
    try:
        done = subprocess.run(
            [sys.executable, "-c", _CHILD, *argv],
            capture_output=True,
            text=True,
            timeout=CALL_LIMIT,
            cwd=ROOT,
        )
    except subprocess.TimeoutExpired:
        return None, ""
    return done.returncode, done.stderr


@pytest.mark.parametrize("model", sorted(SCENES))
def test_parameters_near_their_bounds_end_with_an_outcome_or_a_refusal(model):
    scene = str(GAITS / f"{SCENES[model]}.toml")
    failures = []
    for sets in _draws(model):
        for command in (["find", scene], ["run", scene, "--strides", "3"]):
            argv = [*command, *sets]
            code, err = _call(argv)
            if code is None:
                failures.append(f"ran past {CALL_LIMIT:g} s: walker {' '.join(argv)}")
            elif code not in (0, 1, 2) or "internal error" in err:
                failures.append(f"exit {code}: walker {' '.join(argv)}\n{err[-600:]}")
    assert not failures, "\n".join(failures)
