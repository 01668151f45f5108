"""Folds and period doublings between consecutive points of a continued branch.

Two test functions are watched along the branch, and a sign change between consecutive points
is located (Brent's method on the stepper's parametrisation of the segment, with a converged
orbit at every trial point) to about 1e-10 in the parameter:

* fold: the stepper's ``fold_test`` (:mod:`walker.analysis.steppers`): the parameter component of
the
  arclength tangent, or ``det(DP^k - I)`` for natural continuation;
* period doubling: ``det(DP^k + I) = prod(lambda + 1)`` changes sign — a real multiplier
  crosses -1 (complex pairs contribute ``|lambda + 1|^2 > 0`` and never change the sign).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from walker.analysis.steppers import Point
from walker.simulation.sectionmap import eig_sorted

__all__ = ["bifurcations_between", "period_doubling_test"]

# Bifurcation location: absolute tolerance on the segment parameter (|d mu / d s| <= 1).
LOCATE_XTOL = 1e-12


class _TrialFailed(Exception):
    """A trial point of bifurcation location did not converge (internal)."""


def period_doubling_test(point: Point) -> float:
    """``det(DP^k + I)``."""
    n = point.jac.shape[0]
    return float(np.linalg.det(point.jac + np.eye(n)))


def _locate(stepper, p: Point, q: Point, test):
    """Root of ``test`` on the segment p -> q, with a converged orbit at every trial point."""
    cache: dict[float, Point] = {}
    s1, trial = stepper.segment(p, q)

    def f(s):
        if s == 0.0:
            return test(p)
        if s == s1:
            return test(q)
        r = trial(s)
        if r is None:
            raise _TrialFailed
        cache[s] = r
        return test(r)

    lo, hi = sorted((0.0, s1))
    try:
        s_star = brentq(f, lo, hi, xtol=LOCATE_XTOL, rtol=4 * np.finfo(float).eps, maxiter=200)
    except (_TrialFailed, ValueError, RuntimeError):
        return None
    if s_star in cache:
        return cache[s_star]
    if s_star == 0.0:
        return p
    if s_star == s1:
        return q
    return trial(s_star)


def bifurcations_between(stepper, p: Point, q: Point, kinds=("fold", "period_doubling")):
    """Bifurcations of the given ``kinds`` between consecutive branch points p and q, in
    order of occurrence: ``(kind, mu, z, multipliers, point)`` with ``point`` the converged
    orbit at the bifurcation, or None when it could not be located (then ``mu`` and ``z``
    are linear interpolations of the test function and the multipliers NaN)."""
    found = []
    tests = {"fold": stepper.fold_test, "period_doubling": period_doubling_test}
    for kind in kinds:
        test = tests[kind]
        a, b = test(p), test(q)
        if not (np.isfinite(a) and np.isfinite(b)) or a * b >= 0:
            continue
        r = _locate(stepper, p, q, test)
        if r is None:
            # Fall back to linear interpolation of the test function (not located).
            w = a / (a - b)
            mu = p.mu + w * (q.mu - p.mu)
            z = p.z + w * (q.z - p.z)
            found.append((kind, mu, z, np.full(z.shape[0], np.nan, dtype=complex), None))
            continue
        lam, _ = eig_sorted(r.jac)
        found.append((kind, r.mu, r.z.copy(), lam, r))
    found.sort(key=lambda item: abs(item[1] - p.mu))
    return found
