"""The golden corpus (``tests/golden/``): walker's compiled C core gives today's numbers, bit
for bit.

These are REGRESSION PINS, not correctness proofs: the recorded numbers are walker's own
output (``tests/golden/make_golden.py``), so a test here fails when a number moves, not when
it is wrong.  Correctness is checked elsewhere, against closed forms, conservation laws,
literature values and independent oracles.  The corpus is what lets a refactoring of the C
core, its binding or the code generation prove that nothing moved.

Each test recomputes one part of the corpus through the compiled path only (the functions
of ``walker._hybrid.models()`` called at their addresses, and the public ``StrideMap``,
``find_fixed_point`` and ``simulate``; no numba) with the recorded inputs, by the same code
that recorded it (``tests/_golden.py``), and compares every array bit for bit (a NaN matches
a NaN at the same position).  What is recorded, and when regenerating is legitimate, is in
the docstring of ``tests/golden/make_golden.py``.
"""

import numpy as np
import pytest
from _golden import (
    ENTRIES_FILE,
    SCENES_FILE,
    deviation,
    entry_names_in,
    entry_outputs,
    key,
    registry,
    same_bits,
    scene_outputs,
    shipped_scenes,
)

REGENERATE = (
    "if the change is meant to move numbers, regenerate with `python "
    "tests/golden/make_golden.py` in a commit that says which numbers moved and why"
)

with np.load(ENTRIES_FILE) as _data:
    ENTRIES = entry_names_in(_data)
with np.load(SCENES_FILE) as _data:
    SCENES = sorted({k.split(".")[0] for k in _data})

# which calls the rows of each recorded output come from: the input that lists them
_ROWS = {
    "rhs": "in_phase_calls",
    "jac": "in_phase_calls",
    "guards": "in_phase_calls",
    "rhs_jac_dx": "in_phase_calls",
    "rhs_jac_J": "in_phase_calls",
    "reset_out": "in_reset_calls",
    "reset_x": "in_reset_calls",
    "reset_impulse": "in_reset_calls",
    "lift": "in_z",
    "lift_jacobian": "in_z",
}
_ROW_NAMES = {"in_phase_calls": "(sample, phase)", "in_reset_calls": "(sample, phase, guard)"}


def _first_bad_row(got, want) -> int:
    for row in range(min(len(got), len(want))):
        if not same_bits(got[row], want[row]):
            return row
    return -1


def _where(data, entry, name, got, want) -> str:
    """The call behind the first differing row of output ``name``, for the message."""
    if got.shape != want.shape or got.ndim == 0:
        return ""
    row = _first_bad_row(got, want)
    if row < 0:
        return ""
    source = _ROWS.get(name)
    if source is None:  # energy, points, start_phase: one row per sample
        x = data[key(entry, "in_x")][row]
        return f"; first at sample {row}, x = {x.tolist()}"
    call = data[key(entry, source)][row]
    return f"; first at row {row}, {_ROW_NAMES.get(source, 'z')} = {call.tolist()}"


@pytest.mark.regression_pin
def test_every_registry_entry_is_recorded():
    """The corpus covers exactly the extension's registry entries."""
    current = sorted(registry())
    assert sorted(ENTRIES) == current, (
        f"registry entries {current} but the golden corpus records {sorted(ENTRIES)}; " + REGENERATE
    )


@pytest.mark.regression_pin
def test_every_shipped_scene_is_recorded():
    """The corpus covers exactly the shipped scenes (gaits/*.toml)."""
    current = sorted(path.stem for path in shipped_scenes())
    assert SCENES == current, (
        f"shipped scenes {current} but the golden corpus records {SCENES}; " + REGENERATE
    )


@pytest.mark.regression_pin
@pytest.mark.parametrize("entry", ENTRIES)
def test_registry_entry_outputs_bit_for_bit(entry):
    """Every rhs, Jacobian, fused rhs and Jacobian, guard vector, reset (outcome, state,
    impulse), energy, points, start phase and lift of one registry entry at its recorded
    inputs."""
    addresses = registry().get(entry)
    assert addresses is not None, f"registry entry {entry!r} is gone; " + REGENERATE
    with np.load(ENTRIES_FILE) as data:
        data = dict(data)
    prefix = key(entry, "")
    inputs = {k[len(prefix) + 3 :]: v for k, v in data.items() if k.startswith(prefix + "in_")}
    inputs["sizes"] = data[key(entry, "sizes")]
    recorded = {
        k[len(prefix) :]: v
        for k, v in data.items()
        if k.startswith(prefix) and not k.startswith(prefix + "in_") and k != prefix + "sizes"
    }
    got = entry_outputs(entry, addresses, inputs)
    assert sorted(got) == sorted(recorded), (
        f"{entry}: outputs {sorted(got)}, recorded {sorted(recorded)}; " + REGENERATE
    )
    failures = [
        f"{entry} {name}: {deviation(got[name], want)}"
        f"{_where(data, entry, name, np.asarray(got[name]), want)}"
        for name, want in recorded.items()
        if not same_bits(got[name], want)
    ]
    assert not failures, "\n".join(failures) + "\n" + REGENERATE


@pytest.mark.regression_pin
@pytest.mark.parametrize("scene", SCENES)
def test_scene_strides_fixed_point_and_run_bit_for_bit(scene):
    """One stride and its Jacobian, the fixed point and the event runs of one scene."""
    with np.load(SCENES_FILE) as data:
        recorded = {k.split(".", 1)[1]: v for k, v in data.items() if k.split(".")[0] == scene}
    path = next(p for p in shipped_scenes() if p.stem == scene)
    got = scene_outputs(path)
    assert sorted(got) == sorted(recorded), (
        f"scene {scene}: outputs {sorted(got)}, recorded {sorted(recorded)}; " + REGENERATE
    )
    failures = [
        f"scene {scene} {name}: {deviation(got[name], want)}"
        for name, want in recorded.items()
        if not same_bits(got[name], want)
    ]
    assert not failures, "\n".join(failures) + "\n" + REGENERATE


def test_the_comparison_sees_one_ulp_and_nan_positions():
    """The bit-for-bit comparison the pins use catches a one-ulp change and a moved NaN, and
    lets a NaN match a NaN (a check of the comparison itself, not a pin)."""
    a = np.array([1.0, np.nan, -0.0, 2.5])
    assert same_bits(a, a.copy())
    b = a.copy()
    b[0] = np.nextafter(1.0, 2.0)
    assert not same_bits(b, a)
    assert "max absolute deviation 2.22e-16" in deviation(b, a)
    c = a.copy()
    c[1], c[3] = 3.0, np.nan
    assert not same_bits(c, a)
    assert not same_bits(np.array([0.0]), np.array([-0.0]))  # the sign bit counts
    assert not same_bits(a.astype(np.float32), a)
    assert not same_bits(np.array([1, 2]), np.array([1, 3]))
