"""The discretised stride-map Markov chain of a walker on random slopes and its mean
first-passage time (Byl and Tedrake, "Metastable walking machines", IJRR 28(8), 2009).

The chain's state.  On terrain of random slopes (drop 0), the state just after landing on a
plane of slope ``gamma`` is the section point ``z`` of the stride map whose scene slope is
``gamma``: the post-impact state is that map's lift of ``z`` (the compass gait's absolute
angles have ``q_swing = -2 gamma - q_stance``; the rimless wheel's stance spoke stands at
``alpha`` from that plane's normal).  So the reachable post-impact states are the pairs
``(z, gamma_prev)``, and the chain's states are the products of

* a mesh of section points ``z_i``: for ``n_z = 1`` a uniform grid over the range the sampled
  walks reach (10 % margin each side), for ``n_z > 1`` points drawn from the post-impact
  states of sampled walks (the reachable set), and
* the slope nodes ``gamma_k``, ``k < m``: the centres of ``m`` equal bins over ``slope_mean
  +- 5 slope_std``, each of probability ``w_k``, the normal law's mass of its bin (the
  quadrature over the slope distribution: the midpoint rule with exact bin masses),

plus one absorbing failure state.  From ``(z_i, gamma_j)`` the step over ``gamma_k`` is one
stride of the map of slope ``gamma_j`` from ``z_i`` over the terrain row ``(gamma_k, 0)``
(compiled, :meth:`walker.stride.StrideMap.__call__`); a failure (any status but
``COMPLETED``) goes to the absorbing state with probability ``w_k``, and a landing at ``z'``
goes to ``(., gamma_k)``, spread over the mesh by linear interpolation (``n_z = 1``: the two
neighbouring grid points; ``n_z > 1``: the barycentric weights of the Delaunay simplex
holding ``z'`` in coordinates scaled by the mesh's standard deviations, the nearest mesh
point outside the hull).

With ``Q`` the transient block of the transition matrix, ``lambda_2`` (the largest eigenvalue
of the whole chain after the absorbing state's 1) is ``Q``'s spectral radius and the
metastable mean first-passage time is ``1 / (1 - lambda_2)`` steps.  The expected steps
completed from a state, ``n = (I - Q)^-1 Q 1``, accounts for the start transient: the start
(the gait of the mean slope, the previous slope the mean) is mapped once more over the slope
nodes, ``n_start = sum_d Q_start,d (1 + n_d)``, which is what the Monte Carlo of
:func:`walker.mfpt.monte_carlo` estimates.

The mesh is refined (twice the mesh points, 1.5 times the slope nodes per level) until
``1 / (1 - lambda_2)`` moves less than ``tol`` (2 %) between levels.
"""

from __future__ import annotations

import math
import numbers
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from walker.status import Status

__all__ = ["ChainLevel", "build_chain", "markov_chain", "slope_nodes"]


SPAN = 5.0
"""The slope nodes cover ``slope_mean +- SPAN slope_std``."""


def slope_nodes(slope_mean: float, slope_std: float, m: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``m`` slope nodes [rad] and their probabilities (module docstring): the centres of
    ``m`` equal bins over ``slope_mean +- SPAN slope_std`` and the normal law's mass of each
    bin, the two tails' mass added to the end bins."""
    from scipy.special import ndtr

    edges = np.linspace(-SPAN, SPAN, m + 1)
    mass = np.diff(ndtr(edges))
    mass[0] += ndtr(-SPAN)
    mass[-1] += ndtr(-SPAN)
    return slope_mean + slope_std * 0.5 * (edges[1:] + edges[:-1]), mass / mass.sum()


class _Interp:
    """Linear interpolation weights of points onto a mesh of section points."""

    def __init__(self, mesh: np.ndarray):
        self.mesh = mesh
        n, d = mesh.shape
        self.d = d
        if d == 1:
            self.grid = mesh[:, 0]
        else:
            from scipy.spatial import Delaunay, cKDTree

            self.scale = mesh.std(axis=0)
            self.scale[self.scale == 0.0] = 1.0
            scaled = mesh / self.scale
            self.tri = Delaunay(scaled)
            self.tree = cKDTree(scaled)

    def weights(self, points: np.ndarray):
        """(index array (p, w), weight array (p, w)) for points (p, d)."""
        p = points.shape[0]
        if self.d == 1:
            g = self.grid
            x = np.clip(points[:, 0], g[0], g[-1])
            hi = np.clip(np.searchsorted(g, x), 1, g.size - 1)
            lo = hi - 1
            t = (x - g[lo]) / (g[hi] - g[lo])
            return np.stack([lo, hi], 1), np.stack([1.0 - t, t], 1)
        scaled = points / self.scale
        simplex = self.tri.find_simplex(scaled)
        idx = np.zeros((p, self.d + 1), dtype=np.int64)
        w = np.zeros((p, self.d + 1))
        inside = simplex >= 0
        if inside.any():
            T = self.tri.transform[simplex[inside]]
            b = np.einsum("pij,pj->pi", T[:, : self.d], scaled[inside] - T[:, self.d])
            idx[inside] = self.tri.simplices[simplex[inside]]
            w[inside] = np.column_stack([b, 1.0 - b.sum(axis=1)])
        if (~inside).any():
            _, near = self.tree.query(scaled[~inside])
            idx[~inside, 0] = near
            w[~inside, 0] = 1.0
        return idx, w


class ChainLevel:
    """One discretisation: its mesh, slope nodes, transient block ``Q`` and estimates.

    Attributes
    ----------
    mesh : ndarray, shape (n_mesh, n_z)
    slopes : ndarray, shape (m,)
        the slope nodes [rad].
    Q : scipy.sparse.csr_matrix, shape (n_mesh m, n_mesh m)
        state ``(i, k)`` is index ``k n_mesh + i``.
    failure : ndarray, shape (n_mesh m,)
        each state's probability of failing on its next step.
    lambda_2, mfpt, mfpt_start : float
        ``Q``'s spectral radius, ``1 / (1 - lambda_2)`` and the expected steps completed from
        the start state [steps].
    """

    def __init__(self, mesh, slopes, Q, failure, start_row):
        from scipy.sparse import identity
        from scipy.sparse.linalg import spsolve

        self.mesh, self.slopes, self.Q, self.failure = mesh, slopes, Q, failure
        self.lambda_2 = _spectral_radius(Q)
        self.mfpt = 1.0 / (1.0 - self.lambda_2) if self.lambda_2 < 1.0 else math.inf
        n_states = Q.shape[0]
        A = (identity(n_states, format="csc") - Q).tocsc()
        self.expected = spsolve(A, Q @ np.ones(n_states))
        self.mfpt_start = float(start_row @ (1.0 + self.expected))


def _spectral_radius(Q) -> float:
    n = Q.shape[0]
    if n <= 1500:
        return float(np.max(np.abs(np.linalg.eigvals(Q.toarray()))))
    from scipy.sparse.linalg import eigs

    vals = eigs(Q, k=1, which="LM", return_eigenvectors=False, tol=1e-12, maxiter=20000)
    return float(np.abs(vals).max())


def _strides(P, points, slopes):
    """One stride of map ``P`` from each point over each slope: (status (p, m), z (p, m, n_z))."""
    p, m = points.shape[0], slopes.size
    status = np.zeros((p, m), dtype=np.int64)
    out = np.full((p, m, points.shape[1]), np.nan)
    for i in range(p):
        for k in range(m):
            r = P(points[i], terrain=((slopes[k], 0.0),))
            status[i, k] = int(r.status)
            if r.status == Status.COMPLETED:
                out[i, k] = r.z
    return status, out


def _rows(interp, status, z_next, n_mesh, mass):
    """Sparse rows (one per start point) of the transitions: column index, probability."""
    p, m = status.shape[0], mass.size
    rows, cols, vals = [], [], []
    failure = np.zeros(p)
    for k in range(m):
        ok = status[:, k] == 0
        failure[~ok] += mass[k]
        if not ok.any():
            continue
        idx, w = interp.weights(z_next[ok, k])
        src = np.nonzero(ok)[0]
        rows.append(np.repeat(src, idx.shape[1]))
        cols.append((k * n_mesh + idx).ravel())
        vals.append((w * mass[k]).ravel())
    if rows:
        return np.concatenate(rows), np.concatenate(cols), np.concatenate(vals), failure
    empty = np.zeros(0, dtype=np.int64)
    return empty, empty, np.zeros(0), failure


def _sample_reachable(smap, z0, slopes, mass, n_walks, n_steps, seed):
    """Post-impact section points of walks over the slope nodes (drawn by their mass), from
    ``z0``; a failed walk stops."""
    maps = [smap.with_params(slope=float(g)) for g in slopes]
    rng = np.random.default_rng(seed)
    found = [np.asarray(z0, dtype=np.float64)]
    for _ in range(n_walks):
        z, P = np.asarray(z0, dtype=np.float64), smap
        for k in rng.choice(slopes.size, n_steps, p=mass):
            r = P(z, terrain=((slopes[k], 0.0),))
            if r.status != Status.COMPLETED:
                break
            z, P = r.z, maps[k]
            found.append(z)
    return np.array(found)


def build_chain(smap, z0, slopes, mass, mesh, *, jobs: int = 1) -> ChainLevel:
    """The chain over ``mesh`` (n_mesh, n_z) x ``slopes`` (m,) of probabilities ``mass``,
    from the map ``smap`` on the mean slope and its gait ``z0`` (module docstring)."""
    from scipy.sparse import csr_matrix

    n_mesh, m = mesh.shape[0], slopes.size
    interp = _Interp(mesh)
    maps = [smap.with_params(slope=float(g)) for g in slopes]

    def block(j):
        return _strides(maps[j], mesh, slopes)

    if jobs > 1:
        with ThreadPoolExecutor(max_workers=jobs) as pool:
            blocks = list(pool.map(block, range(m)))
    else:
        blocks = [block(j) for j in range(m)]
    R, C, V = [], [], []
    failure = np.zeros(n_mesh * m)
    for j, (status, z_next) in enumerate(blocks):
        r, c, v, f = _rows(interp, status, z_next, n_mesh, mass)
        R.append(r + j * n_mesh)
        C.append(c)
        V.append(v)
        failure[j * n_mesh : (j + 1) * n_mesh] = f
    n_states = n_mesh * m
    Q = csr_matrix(
        (np.concatenate(V), (np.concatenate(R), np.concatenate(C))), shape=(n_states, n_states)
    )
    status, z_next = _strides(smap, np.asarray(z0, dtype=np.float64)[None], slopes)
    r, c, v, _ = _rows(interp, status, z_next, n_mesh, mass)
    start = np.zeros(n_states)
    np.add.at(start, c, v)
    return ChainLevel(mesh, slopes, Q, failure, start)


def _mesh(samples: np.ndarray, n_mesh: int, rng) -> np.ndarray:
    if samples.shape[1] == 1:
        lo, hi = samples[:, 0].min(), samples[:, 0].max()
        margin = 0.1 * max(hi - lo, 1e-3 * max(abs(lo), abs(hi), 1e-12))
        return np.linspace(lo - margin, hi + margin, n_mesh)[:, None]
    unique = np.unique(samples, axis=0)
    if unique.shape[0] <= n_mesh:
        return unique
    pick = rng.choice(unique.shape[0], n_mesh, replace=False)
    return unique[np.sort(pick)]


def markov_chain(
    smap,
    z0,
    *,
    slope_std: float,
    n_mesh: int | None = None,
    n_slopes: int = 8,
    tol: float = 0.02,
    max_levels: int = 4,
    seed: int = 0,
    jobs: int = 1,
    samples: int = 200,
) -> dict:
    """The Markov-chain mean first-passage time on slopes ``N(slope, slope_std^2)`` (module
    docstring), refined until it moves less than ``tol``.

    Parameters
    ----------
    smap : walker.stride.StrideMap
        the map on the mean slope (its ``slope`` [rad] is the mean).
    z0 : array_like, shape (n_z,)
        the start (the gait of the mean slope).
    slope_std : float
        the slope's standard deviation [rad], > 0.
    n_mesh : int, optional
        the first level's mesh points (default 40 for ``n_z = 1``, 150 otherwise).
    n_slopes : int
        the first level's slope nodes, >= 2.
    tol : float
        relative change of ``1 / (1 - lambda_2)`` between levels that ends the refinement.
    max_levels : int
        levels at most, >= 2.
    seed : int
        seeds the sampled walks that find the reachable set.
    jobs : int
        threads (over the previous-slope nodes).
    samples : int
        sampled walks (of 40 steps) per level.

    Returns
    -------
    dict
        ``mfpt`` (``1 / (1 - lambda_2)`` of the finest level), ``mfpt_start`` (the expected
        steps from the start, transient included), ``lambda_2``, ``converged`` (the last
        change was below ``tol``), ``change`` and ``levels`` (each level's ``n_mesh``,
        ``n_slopes``, ``mfpt``, ``mfpt_start``).
    """
    for name, value, low in (("n_slopes", n_slopes, 2), ("max_levels", max_levels, 2)):
        if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < low:
            raise ValueError(f"`{name}` must be an int >= {low}, got {value!r}")
    if not (isinstance(slope_std, numbers.Real) and slope_std > 0 and math.isfinite(slope_std)):
        raise ValueError(f"`slope_std` must be finite and > 0, got {slope_std!r}")
    if not (0.0 < tol < 1.0):
        raise ValueError(f"`tol` must be in (0, 1), got {tol!r}")
    z0 = np.asarray(z0, dtype=np.float64)
    n_z = smap.model.n_z
    if n_mesh is None:
        n_mesh = 40 if n_z == 1 else 150
    mean = float(smap.params.slope)
    rng = np.random.default_rng(seed)
    levels, previous, change, level = [], None, math.inf, None
    for lev in range(max_levels):
        m = int(round(n_slopes * 1.5**lev))
        mesh_points = int(n_mesh * 2**lev)
        slopes, mass = slope_nodes(mean, float(slope_std), m)
        reach = _sample_reachable(smap, z0, slopes, mass, samples, 40, seed + lev)
        mesh = _mesh(reach, mesh_points, rng)
        level = build_chain(smap, z0, slopes, mass, mesh, jobs=jobs)
        levels.append(
            {
                "n_mesh": int(mesh.shape[0]),
                "n_slopes": m,
                "mfpt": float(level.mfpt),
                "mfpt_start": float(level.mfpt_start),
                "lambda_2": float(level.lambda_2),
            }
        )
        if previous is not None:
            change = abs(level.mfpt - previous) / abs(level.mfpt)
            if change < tol:
                break
        previous = level.mfpt
    return {
        "mfpt": float(level.mfpt),
        "mfpt_start": float(level.mfpt_start),
        "lambda_2": float(level.lambda_2),
        "converged": bool(change < tol),
        "change": float(change),
        "tol": float(tol),
        "levels": levels,
    }
