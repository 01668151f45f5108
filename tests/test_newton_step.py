"""The compiled Newton step of the gait search (``walker._hybrid.newton_step``): the solve
against numpy's, the Frobenius condition number against its definition and the 2-norm
bounds, and the singular and malformed inputs."""

from __future__ import annotations

import numpy as np
import pytest

from walker import _hybrid
from walker.newton import COND_MAX


def _newton_step(a, f):
    """``(cond, dz)`` of the compiled step, ``dz`` as an array (None when singular)."""
    cond, dz = _hybrid.newton_step(a, f)
    return cond, (None if dz is None else np.frombuffer(dz))


@pytest.mark.parametrize("n", [1, 2, 3, 4, 6, 10])
def test_step_and_condition_match_their_definitions(n):
    rng = np.random.default_rng(n)
    for _ in range(50):
        a = rng.normal(size=(n, n)) * 10.0 ** rng.uniform(-3, 3)
        f = rng.normal(size=n)
        cond, dz = _newton_step(a, f)
        ref = np.linalg.solve(a, -f)
        c2 = np.linalg.cond(a)
        assert np.max(np.abs(dz - ref)) <= 1e-13 * c2 * max(1.0, np.max(np.abs(ref)))
        inv = np.linalg.inv(a)
        assert cond == pytest.approx(np.linalg.norm(a) * np.linalg.norm(inv), rel=1e-10)
        assert c2 * (1 - 1e-12) <= cond <= n * c2 * (1 + 1e-12)


def test_singular_and_nearly_singular():
    cond, dz = _newton_step(np.array([[1.0, 2.0], [2.0, 4.0]]), np.ones(2))
    assert cond == np.inf and dz is None
    assert _newton_step(np.zeros((3, 3)), np.ones(3)) == (np.inf, None)
    near = np.array([[1.0, 1.0], [1.0, 1.0 + 1e-15]])
    cond, _ = _newton_step(near, np.ones(2))
    assert cond > COND_MAX  # the search treats it as singular


def test_input_is_refused_with_the_argument_named():
    with pytest.raises(ValueError, match="`a` must be"):
        _hybrid.newton_step(np.zeros((2, 3)), np.zeros(2))
    with pytest.raises(ValueError, match="`a` must be"):
        _hybrid.newton_step(np.eye(3), np.zeros(2))
    with pytest.raises((TypeError, ValueError), match="`f`"):
        _hybrid.newton_step(np.eye(2), np.zeros(2, dtype=np.int64))
    with pytest.raises(TypeError, match="2 arguments"):
        _hybrid.newton_step(np.eye(2))
