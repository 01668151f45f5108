"""The gait search's Newton step (walker/_core/newton.h, ``wk_newton_step``), seen through
the search (``walker._hybrid.search``) on the affine map ``P(z) = z + a z + f``, whose
residual ``F(z) = a z + f`` Newton solves in one step from ``z = 0``: the step against
numpy's solve, the Frobenius condition number against its definition and the 2-norm bounds,
and the singular and nearly singular matrices."""

from __future__ import annotations

import numpy as np
import pytest

from walker import _hybrid
from walker.analysis.newton import COND_MAX, _Search


def _newton_step(a, f):
    """``(cond, dz)`` of the search's Newton step for ``a dz = -f``: ``cond`` from a search
    that may take no step (``cond_max = 0``: it ends at once, singular, reporting the
    condition number), ``dz`` from one that takes one full step from 0 (no trust region);
    ``(inf, None)`` for a matrix the step cannot solve."""
    n = f.shape[0]
    jac = (np.eye(n) + a).reshape(-1)  # the search subtracts I again: pass a = (I + a) - I

    def evaluate(z, level, with_jacobian):
        z = np.frombuffer(z)
        return 0, z + (a @ z + f), jac, None

    settings = _Search(None, 1, None, 10, 0.0, "exact", None, False).settings(1, False, n)
    settings.update(tr_start=1e300, tr_max=1e300)
    never = lambda z: pytest.fail("the map's own Jacobian comes with each evaluation")  # noqa: E731
    common = dict(z0=np.zeros(n), scale=np.ones(n), evaluate=evaluate, jacobian=never)
    out = _hybrid.search(**common, outside=None, **{**settings, "cond_max": 0.0})
    cond = out[8]
    assert out[0] == 8  # WK_SEARCH_SINGULAR
    if not np.isfinite(cond):
        return np.inf, None
    out = _hybrid.search(**common, outside=None, **{**settings, "cond_max": np.inf})
    assert out[2] == 1  # one step taken
    return cond, np.frombuffer(out[9])


@pytest.mark.parametrize("n", [1, 2, 3, 4, 6, 10])
def test_step_and_condition_match_their_definitions(n):
    rng = np.random.default_rng(n)
    for _ in range(50):
        a = rng.normal(size=(n, n)) * 10.0 ** rng.uniform(-3, 3)
        a = (np.eye(n) + a) - np.eye(n)  # the matrix the search forms from the map's Jacobian
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
    near = (np.eye(2) + np.array([[1.0, 1.0], [1.0, 1.0 + 1e-15]])) - np.eye(2)
    cond, _ = _newton_step(near, np.ones(2))
    assert cond > COND_MAX  # the search treats it as singular
