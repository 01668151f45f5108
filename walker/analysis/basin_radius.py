"""The ball around a stable gait where a basin point is certain to converge.

A basin point stops as converged once it enters the ball

    B = { z : ||W (z - z*)||_2 <= r }

around the fixed point ``z*`` of the ``period``-fold stride map ``F``.  The rule, and what it
assumes (the derivation is in docs/basins.md):

1. **The weighting.**  ``A = DF(z*)`` is the gait's Jacobian.  When its eigenvectors are well
   conditioned, ``W = T^-1`` with ``T`` the real eigenbasis (a real eigenvector per real
   multiplier, the real and imaginary parts of one eigenvector per complex pair); then
   ``W A W^-1`` is block diagonal with blocks ``lambda`` and ``[[a, b], [-b, a]]`` and
   ``||A||_W = ||W A W^-1||_2`` equals the spectral radius.  Otherwise (a defective or nearly
   defective ``A``) ``W`` is the Cholesky factor of the solution ``P`` of the discrete
   Lyapunov equation ``A^T P A - P = -I``, for which ``||A||_W < 1`` too.  ``W`` is scaled so
   that its smallest singular value is 1: ``||e||_inf <= ||e||_2 <= ||W e||_2``, so the ball
   lies inside the box ``max|z - z*| <= r`` (section units).
2. **The bound on the second derivative.**  ``M`` bounds the Lipschitz constant of ``DF`` in
   the ``W`` norm on the ball: ``||DF(z) - A||_W <= M ||z - z*||_W``.  It is estimated from
   Jacobians at sample points around ``z*`` (along every eigen-direction, both signs, and
   random directions, at the sample radius and half of it) as the largest ratio seen, times
   the safety factor ``safety`` (default 4).  This is an estimate, not a proof: it assumes
   ``DF`` varies no faster between the samples than at them, which holds when ``F`` is
   smooth on the sample ball (every sample stride completes with the event sequence of the
   gait; a sample that fails gives no ball).
3. **The radius.**  ``r = (1 - ||A||_W) / M``, at most the sample radius (the region where
   ``M`` was measured).  For ``e = z - z*`` in the ball, ``F(z) - z* = int_0^1 DF(z* + t e)
   e dt`` (the ball is convex), so ``||F(z) - z*||_W <= (||A||_W + M ||e||_W / 2) ||e||_W
   <= kappa ||e||_W`` with ``kappa = ||A||_W + M r / 2 = (1 + ||A||_W) / 2 < 1``: ``F`` maps
   the ball into itself and every point of it converges to ``z*`` geometrically at rate
   ``kappa``.  At every sample point on the final radius and half of it, the map itself is
   checked: ``||F(z) - z*||_W <= kappa ||z - z*||_W``.
4. **Integration error.**  A computed stride differs from ``F`` by about the solver's
   tolerance ``delta``; the perturbed iterates stay in the ball when ``delta <= (1 - kappa)
   r``.  The radius is refused (0) when ``(1 - kappa) r`` is below ``1e3`` times the map's
   ``rtol`` (or ``atol``), so that this holds with a wide margin.

An unstable gait (spectral radius >= 1) has no such ball: the radius is 0 and points are
classified by the tolerance alone.
"""

from __future__ import annotations

import numpy as np

from walker.simulation.sectionmap import map_jacobian

__all__ = ["contraction_ball", "DEFAULT_SAFETY"]

DEFAULT_SAFETY = 4.0
"""Factor applied to the largest sampled Lipschitz ratio of the map's Jacobian."""

SAMPLE_RADIUS = 5e-2
"""Largest sample radius (``W`` norm, section units) at which ``M`` is first estimated."""

N_RANDOM = 8
"""Random sample directions, besides the ``2 n_z`` signed eigen-directions."""

_MAX_CONDITION = 1e6  # eigenbasis condition number above which the Lyapunov weighting is used


def _norm_w(weight: np.ndarray, mat: np.ndarray) -> float:
    """``||mat||_W = ||W mat W^-1||_2``."""
    return float(np.linalg.norm(weight @ mat @ np.linalg.inv(weight), 2))


def _weighting(jac: np.ndarray) -> tuple[np.ndarray, str]:
    """The weight ``W`` of rule 1 (smallest singular value 1) and its name."""
    n = jac.shape[0]
    values, vectors = np.linalg.eig(jac)
    cols, k = [], 0
    order = np.argsort(-np.abs(values), kind="stable")
    done = np.zeros(n, dtype=bool)
    for i in order:
        if done[i]:
            continue
        done[i] = True
        v = vectors[:, i]
        if abs(values[i].imag) > 1e-12 * max(1.0, abs(values[i])):
            # its conjugate partner: the unused eigenvalue nearest conj(lambda)
            rest = [j for j in range(n) if not done[j]]
            j = min(rest, key=lambda j: abs(values[j] - np.conj(values[i])))
            done[j] = True
            cols += [v.real, v.imag]
            k += 2
        else:
            cols.append(v.real)
            k += 1
    basis = np.array(cols).T
    kind = "eigenbasis"
    if (
        basis.shape != (n, n)
        or not np.all(np.isfinite(basis))
        or np.linalg.cond(basis) > _MAX_CONDITION
    ):
        # discrete Lyapunov A^T P A - P = -I, by its Kronecker form (n_z is small)
        lhs = np.eye(n * n) - np.kron(jac.T, jac.T)
        p = np.linalg.solve(lhs, np.eye(n).ravel()).reshape(n, n)
        p = 0.5 * (p + p.T)
        weight = np.linalg.cholesky(p).T  # P = W^T W
        kind = "lyapunov"
    else:
        weight = np.linalg.inv(basis)
    return weight / np.linalg.svd(weight, compute_uv=False).min(), kind


def contraction_ball(
    section_map,
    fixed_point,
    *,
    safety: float = DEFAULT_SAFETY,
    seed: int = 0,
) -> tuple[np.ndarray, float, dict]:
    """The weight ``W`` and radius ``r`` of the ball where ``fixed_point`` attracts surely.

    Parameters
    ----------
    section_map : SectionMap
        the map the basin iterates (its Jacobians are computed here, ``period``-fold).
    fixed_point : FixedPoint
        a converged gait (``section``, ``period``).
    safety : float
        factor (>= 1) applied to the sampled bound on the second derivative.
    seed : int
        seed of the random sample directions (the result is reproducible).

    Returns
    -------
    weight : ndarray, shape (n_z, n_z)
        ``W`` (rule 1 of this module), smallest singular value 1.
    radius : float
        ``r`` in the ``W`` norm (section units); 0 when there is no ball: an unstable gait,
        a failed sample stride or a ball too small for the solver's tolerance.
    info : dict
        ``rule``, ``weighting`` ("eigenbasis" or "lyapunov"), ``contraction``
        (``||A||_W``), ``lipschitz`` (the sampled ``M`` before ``safety``), ``safety``,
        ``kappa`` (the guaranteed contraction factor towards ``z*`` in the ball),
        ``sample_radius``, ``sampled_contraction`` (the largest ``||F(z) - z*||_W /
        ||z - z*||_W`` at the samples), and ``reason`` when the radius is 0.
    """
    if not (np.isfinite(safety) and safety >= 1):
        raise ValueError(f"`safety` must be a finite number >= 1, got {safety!r}")
    z_star = np.asarray(fixed_point.section, dtype=float)
    period = int(fixed_point.period)
    n = z_star.size
    info: dict = {
        "rule": "contraction ball (walker/analysis/basin_radius.py)",
        "safety": float(safety),
    }
    res, jac, status = map_jacobian(section_map, z_star, period, None, "exact", 0.0)
    if jac is None:
        return np.eye(n), 0.0, {**info, "reason": f"no Jacobian at the gait: {status.name}"}
    rho = float(np.max(np.abs(np.linalg.eigvals(jac))))
    if not rho < 1:
        return np.eye(n), 0.0, {**info, "reason": f"unstable gait (|multiplier| {rho:.6g})"}
    weight, kind = _weighting(jac)
    inv = np.linalg.inv(weight)
    a = _norm_w(weight, jac)
    info.update(weighting=kind, contraction=a)
    if not a < 1:
        return weight, 0.0, {**info, "reason": f"||A||_W = {a:.6g} >= 1"}
    rng = np.random.default_rng(seed)
    dirs = [s * np.eye(n)[i] for i in range(n) for s in (1.0, -1.0)]
    dirs += [d / np.linalg.norm(d) for d in rng.standard_normal((N_RANDOM, n))]

    def worst(radius):
        """Largest ||DF(z) - A||_W / ||z - z*||_W and ||F(z) - z*||_W / ||z - z*||_W over
        the samples."""
        ratio = shrink = 0.0
        for frac in (1.0, 0.5):
            for d in dirs:  # d in W coordinates: z = z* + W^-1 (frac r d), ||.||_W = frac r
                z = z_star + inv @ (frac * radius * d)
                rz, jz, st = map_jacobian(section_map, z, period, None, "exact", 0.0)
                if jz is None:
                    return None, f"a sample stride failed ({st.name})"
                ratio = max(ratio, _norm_w(weight, jz - jac) / (frac * radius))
                step = np.linalg.norm(weight @ (np.asarray(rz.z) - z_star))
                shrink = max(shrink, float(step) / (frac * radius))
        return (ratio, shrink), None

    sample = SAMPLE_RADIUS
    for _ in range(8):
        got, why = worst(sample)
        if got is None:
            sample /= 10.0
            continue
        lip = got[0]
        radius = sample if lip == 0 else min(sample, (1.0 - a) / (safety * lip))
        if radius >= sample:
            break
        sample = radius  # re-measure M on the ball actually used
    else:
        return weight, 0.0, {**info, "reason": why or "the sample radius did not settle"}
    if got is None:
        return weight, 0.0, {**info, "reason": why}
    kappa = 0.5 * (1.0 + a)
    info.update(lipschitz=lip, kappa=kappa, sample_radius=sample, sampled_contraction=got[1])
    if got[1] > kappa:
        return weight, 0.0, {**info, "reason": f"sampled contraction {got[1]:.6g} > kappa"}
    floor = 1e3 * max(float(getattr(section_map, "rtol", 0.0)), 0.0)
    floor = max(floor, 1e3 * max(float(getattr(section_map, "atol", 0.0)), 0.0))
    if (1.0 - kappa) * radius < floor:
        return weight, 0.0, {**info, "reason": "ball too small for the solver tolerance"}
    return weight, float(radius), info
