"""The discretised stride-map Markov chain of a walker on random slopes and its mean
first-passage time (Byl and Tedrake, "Metastable walking machines", IJRR 28(8), 2009).

The chain's state.  On terrain of random slopes (drop 0), the state just after landing on a
plane of slope ``gamma`` is the section point ``z`` of the stride map whose scene slope is
``gamma``: the post-impact state is that map's lift of ``z`` (the compass gait's absolute
angles have ``q_swing = -2 gamma - q_stance``; the rimless wheel's stance spoke stands at
``alpha`` from that plane's normal).  So the reachable post-impact states are the pairs
``(z, gamma_prev)``, and the chain's states are the products of

* a mesh of section points over the reachable set, one for each slope node ``gamma_k``
  (the points reached by landing on ``gamma_k``): sampled walks over the slope nodes give a
  pool of states, and strides over every node from pool states give the points reached by
  landing there (``SAMPLES_PER_POINT`` per mesh point); for ``n_z = 1`` the node's mesh is a
  uniform grid over their range (10 % margin each side), for ``n_z > 1`` ``n_mesh`` of them
  picked by farthest-point sampling in the node's whitened coordinates (unit covariance),
  and
* the slope nodes ``gamma_k``, ``k < m``: the centres of ``m`` equal bins over ``slope_mean
  +- 5 slope_std``, each of probability ``w_k``, the normal law's mass of its bin (the
  quadrature over the slope distribution: the midpoint rule with exact bin masses),

plus one absorbing failure state.  From ``(z_i, gamma_j)`` the step over ``gamma_k`` is one
stride of the map of slope ``gamma_j`` from ``z_i`` over the terrain row ``(gamma_k, 0)``
(compiled, :meth:`walker.simulation.stride.StrideMap.__call__`); a failure (any status but
``COMPLETED``) goes to the absorbing state with probability ``w_k``, and a landing at ``z'``
goes to ``(., gamma_k)`` on the mesh: for ``n_z = 1`` spread over the two neighbouring grid
points by linear interpolation (clamped at the ends); for ``n_z > 1`` to the nearest mesh
point in whitened coordinates (the chain's cells are the mesh's Voronoi cells).  Barycentric
interpolation over a Delaunay triangulation, tried first, spreads probability like a
diffusion: on the compass gait at slope std 0.005 rad it put the MFPT 30-50 % low with a
few hundred mesh points, where the nearest point was within 10 %.

With ``Q`` the transient block of the transition matrix, ``lambda_2`` (the largest eigenvalue
of the whole chain after the absorbing state's 1) is ``Q``'s spectral radius and the
metastable mean first-passage time is ``1 / (1 - lambda_2)`` steps.  The expected steps
completed from a state, ``n = (I - Q)^-1 Q 1``, accounts for the start transient: the start
(the gait of the mean slope, the previous slope the mean) is mapped once more over the slope
nodes, ``n_start = sum_d Q_start,d (1 + n_d)``, which is what the Monte Carlo of
:func:`walker.analysis.mfpt.monte_carlo` estimates.

The chain is refined (1.5 times the slope nodes and the mesh points per node each level)
until both ``1 / (1 - lambda_2)`` and the expected steps from the start move less than
``tol`` (2 %) between levels, from the third level (``MIN_LEVELS``) on.

Why one mesh per slope node.  The section point reached depends strongly on the slope just
landed on (the compass gait's ``dz / d gamma`` is about 2.6 per rad), so one mesh shared by
all nodes spreads its points over the union of the nodes' reachable sets, and each node's
own set, much smaller, gets few of them.  The nearest-point placement then jitters every
landing by a large fraction of that set's spread: noise the walker does not have, which
fattens the tails and put the compass MFPT 5-20 % below the Monte Carlo.  With one mesh per
node the same points resolve each node's set, and the chain approaches the Monte Carlo
(mostly from below) as the mesh is refined.  The mesh's extent matters too: it is the sampled
points' extent (a landing outside it is placed on its edge), and with too few samples the rare
states from which the walker fails are cut off and the MFPT comes out high (5 % on the
compass gait at slope std 0.005 rad with 3 samples per mesh point).
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

SAMPLES_PER_POINT = 8
"""Section points sampled per slope node for each of its mesh points: the mesh is picked
from them, and its extent is theirs (with 3 per mesh point the compass chain's tails were
cut off and its MFPT came out 5 % high)."""

GROWTH = 1.5
"""Each refinement level has 1.5 times the slope nodes and the mesh points per node."""

MIN_LEVELS = 3
"""Levels computed before the refinement may stop: the two coarsest compass levels can agree
to 2 % by chance (at slope std 0.004 rad they gave 63.5 and 62.6 steps against 67.3 +- 0.7
from the Monte Carlo), their difference is not yet the discretisation's error."""

DIRECT_SOLVE = 4000
"""Chains of at most this many states solve ``(I - Q) n = Q 1`` by sparse LU, larger ones
by preconditioned GMRES."""


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


def _whitening(points: np.ndarray):
    """(centre, matrix) mapping ``points`` to coordinates of unit covariance (directions of
    negligible spread kept at 1e-6 of the largest)."""
    if points.shape[0] < 2:
        return points.mean(axis=0), np.eye(points.shape[1])
    center = points.mean(axis=0)
    values, vectors = np.linalg.eigh(np.cov((points - center).T))
    values = np.maximum(values, 1e-12 * max(values.max(), 1e-300))
    return center, vectors / np.sqrt(values)


class _Interp:
    """Linear interpolation weights of points onto a 1-D grid (clamped at its ends)."""

    def __init__(self, mesh: np.ndarray):
        self.grid = mesh[:, 0]

    def weights(self, points: np.ndarray):
        """(index array (p, 2), weight array (p, 2)) for points (p, 1)."""
        g = self.grid
        x = np.clip(points[:, 0], g[0], g[-1])
        hi = np.clip(np.searchsorted(g, x), 1, g.size - 1)
        lo = hi - 1
        t = (x - g[lo]) / (g[hi] - g[lo])
        return np.stack([lo, hi], 1), np.stack([1.0 - t, t], 1)


class ChainLevel:
    """One discretisation: its mesh, slope nodes, transient block ``Q`` and estimates.

    Attributes
    ----------
    mesh : list of ndarray, shapes (n_k, n_z)
        the section points of each slope node.
    slopes : ndarray, shape (m,)
        the slope nodes [rad].
    Q : scipy.sparse.csr_matrix, shape (n, n), n = sum of n_k
        state ``(i, k)`` (point ``i`` of node ``k``'s mesh) is index ``n_0 + .. + n_(k-1) + i``.
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
        b = Q @ np.ones(n_states)
        if n_states <= DIRECT_SOLVE:
            self.expected = spsolve(A, b)
        else:
            self.expected = _iterative_solve(A, b)
        self.mfpt_start = float(start_row @ (1.0 + self.expected))


def _iterative_solve(A, b) -> np.ndarray:
    """``A^-1 b`` by GMRES to a residual of 1e-11 relative (a sparse LU of ``I - Q`` fills
    in badly once the chain has tens of thousands of states); sparse LU if GMRES stalls."""
    from scipy.sparse.linalg import gmres, spsolve

    x, info = gmres(A, b, rtol=1e-11, atol=0.0, restart=80, maxiter=500)
    if info != 0:
        x = spsolve(A, b)
    return np.asarray(x, dtype=np.float64)


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


def _rows(interps, offsets, status, z_next, mass):
    """Sparse rows (one per start point) of the transitions: column index, probability."""
    p, m = status.shape[0], mass.size
    rows, cols, vals = [], [], []
    failure = np.zeros(p)
    for k in range(m):
        ok = status[:, k] == 0
        failure[~ok] += mass[k]
        if not ok.any():
            continue
        idx, w = interps[k].weights(z_next[ok, k])
        src = np.nonzero(ok)[0]
        rows.append(np.repeat(src, idx.shape[1]))
        cols.append((offsets[k] + idx).ravel())
        vals.append((w * mass[k]).ravel())
    if rows:
        return np.concatenate(rows), np.concatenate(cols), np.concatenate(vals), failure
    empty = np.zeros(0, dtype=np.int64)
    return empty, empty, np.zeros(0), failure


def _sample_reachable(smap, z0, slopes, mass, n_walks, n_steps, n_per_node, seed):
    """Post-impact section points reached on each slope node: walks over the slope nodes
    (drawn by their mass) from ``z0`` give a pool of states (a failed walk stops); then, for
    every node, strides over it from up to ``n_per_node`` pool states.  Returns one array
    (n_k, n_z) per node."""
    maps = [smap.with_params(slope=float(g)) for g in slopes]
    rng = np.random.default_rng(seed)
    z0 = np.asarray(z0, dtype=np.float64)
    pool = [(z0, -1)]
    for _ in range(n_walks):
        z, j = z0, -1
        for k in rng.choice(slopes.size, n_steps, p=mass):
            r = (smap if j < 0 else maps[j])(z, terrain=((slopes[k], 0.0),))
            if r.status != Status.COMPLETED:
                break
            z, j = r.z, int(k)
            pool.append((z, j))
    found = [[z for z, j in pool if j == k] for k in range(slopes.size)]
    for k in range(slopes.size):
        for i in rng.choice(len(pool), min(n_per_node, len(pool)), replace=False):
            z, j = pool[i]
            r = (smap if j < 0 else maps[j])(z, terrain=((slopes[k], 0.0),))
            if r.status == Status.COMPLETED:
                found[k].append(r.z)
        if not found[k]:
            found[k].append(z0)
    return [np.array(f) for f in found]


class _Nearest:
    """Nearest-mesh-point weights in the mesh's whitened coordinates (its Voronoi cells)."""

    def __init__(self, mesh):
        from scipy.spatial import cKDTree

        self.center, self.transform = _whitening(mesh)
        self.tree = cKDTree((mesh - self.center) @ self.transform)

    def weights(self, points):
        _, near = self.tree.query((points - self.center) @ self.transform)
        return np.asarray(near, dtype=np.int64)[:, None], np.ones((points.shape[0], 1))


def _interp(mesh):
    if mesh.shape[1] == 1 and mesh.shape[0] >= 2:
        return _Interp(mesh)
    return _Nearest(mesh)


def build_chain(smap, z0, slopes, mass, meshes, *, jobs: int = 1) -> ChainLevel:
    """The chain over the section points ``meshes[k]`` (n_k, n_z) of each slope node
    ``slopes[k]`` of probability ``mass[k]`` (one array: the same mesh for every node), from
    the map ``smap`` on the mean slope and its gait ``z0`` (module docstring)."""
    from scipy.sparse import csr_matrix

    m = slopes.size
    if isinstance(meshes, np.ndarray):
        meshes = [meshes] * m
    sizes = np.array([mesh.shape[0] for mesh in meshes])
    offsets = np.concatenate([[0], np.cumsum(sizes)])
    interps = [_interp(mesh) for mesh in meshes]
    maps = [smap.with_params(slope=float(g)) for g in slopes]

    def block(j):
        return _strides(maps[j], meshes[j], slopes)

    if jobs > 1:
        with ThreadPoolExecutor(max_workers=jobs) as pool:
            blocks = list(pool.map(block, range(m)))
    else:
        blocks = [block(j) for j in range(m)]
    R, C, V = [], [], []
    n_states = int(offsets[-1])
    failure = np.zeros(n_states)
    for j, (status, z_next) in enumerate(blocks):
        r, c, v, f = _rows(interps, offsets, status, z_next, mass)
        R.append(r + offsets[j])
        C.append(c)
        V.append(v)
        failure[offsets[j] : offsets[j + 1]] = f
    Q = csr_matrix(
        (np.concatenate(V), (np.concatenate(R), np.concatenate(C))), shape=(n_states, n_states)
    )
    status, z_next = _strides(smap, np.asarray(z0, dtype=np.float64)[None], slopes)
    r, c, v, _ = _rows(interps, offsets, status, z_next, mass)
    start = np.zeros(n_states)
    np.add.at(start, c, v)
    return ChainLevel(meshes, slopes, Q, failure, start)


def _mesh(samples: np.ndarray, n_mesh: int) -> np.ndarray:
    """The mesh of one slope node: ``n_z = 1``, a uniform grid over the samples' range and a
    10 % margin each side; else ``n_mesh`` of the samples picked by farthest-point sampling in
    whitened coordinates (the first sample first)."""
    if samples.shape[1] == 1:
        lo, hi = samples[:, 0].min(), samples[:, 0].max()
        margin = 0.1 * max(hi - lo, 1e-3 * max(abs(lo), abs(hi), 1e-12))
        return np.linspace(lo - margin, hi + margin, n_mesh)[:, None]
    _, first = np.unique(samples, axis=0, return_index=True)
    unique = samples[np.sort(first)]
    if unique.shape[0] <= n_mesh:
        return unique
    center, transform = _whitening(unique)
    w = (unique - center) @ transform
    pick = [0]
    distance = np.sum((w - w[0]) ** 2, axis=1)
    for _ in range(n_mesh - 1):
        i = int(np.argmax(distance))
        pick.append(i)
        distance = np.minimum(distance, np.sum((w - w[i]) ** 2, axis=1))
    return unique[np.sort(pick)]


def markov_chain(
    smap,
    z0,
    *,
    slope_std: float,
    n_mesh: int | None = None,
    n_slopes: int = 12,
    tol: float = 0.02,
    max_levels: int = 4,
    seed: int = 0,
    jobs: int = 1,
    samples: int = 200,
    per_node: int = 400,
) -> dict:
    """The Markov-chain mean first-passage time on slopes ``N(slope, slope_std^2)`` (module
    docstring), refined until it moves less than ``tol``.

    Parameters
    ----------
    smap : walker.simulation.stride.StrideMap
        the map on the mean slope (its ``slope`` [rad] is the mean).
    z0 : array_like, shape (n_z,)
        the start (the gait of the mean slope).
    slope_std : float
        the slope's standard deviation [rad], > 0.
    n_mesh : int, optional
        the first level's mesh points per slope node (default 40 for ``n_z = 1``, 200
        otherwise).
    n_slopes : int
        the first level's slope nodes, >= 2.
    tol : float
        relative change of ``1 / (1 - lambda_2)`` between levels that ends the refinement.
    max_levels : int
        levels at most, >= 2 (the refinement stops no earlier than ``MIN_LEVELS`` levels,
        when ``max_levels`` allows).
    seed : int
        seeds the sampled walks that find the reachable set.
    jobs : int
        threads (over the previous-slope nodes).
    samples : int
        sampled walks (of 40 steps) per level, at least (more when ``per_node`` needs a
        larger pool: one walk per 20 strides).
    per_node : int
        strides over each slope node from the walks' states, per level, at least
        ``SAMPLES_PER_POINT`` times the level's mesh points: the section points reached on
        that node, from which its mesh is picked.

    Returns
    -------
    dict
        ``mfpt`` (``1 / (1 - lambda_2)`` of the finest level), ``mfpt_start`` (the expected
        steps from the start, transient included), ``lambda_2``, ``converged`` (the last
        change was below ``tol``), ``change`` (the larger relative change of ``mfpt`` and
        ``mfpt_start`` at the last level) and ``levels`` (each level's ``n_mesh`` per node,
        ``n_slopes``, ``n_states``, ``mfpt``, ``mfpt_start``, ``lambda_2``).
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
        n_mesh = 40 if n_z == 1 else 200
    mean = float(smap.params.slope)
    levels, previous, change, level = [], None, math.inf, None
    for lev in range(max_levels):
        m = int(round(n_slopes * GROWTH**lev))
        mesh_points = int(round(n_mesh * GROWTH**lev))
        slopes, mass = slope_nodes(mean, float(slope_std), m)
        strides_per_node = max(per_node, SAMPLES_PER_POINT * mesh_points)
        walks = max(samples, -(-strides_per_node // 20))
        reach = _sample_reachable(smap, z0, slopes, mass, walks, 40, strides_per_node, seed)
        meshes = [_mesh(points, mesh_points) for points in reach]
        level = build_chain(smap, z0, slopes, mass, meshes, jobs=jobs)
        levels.append(
            {
                "n_mesh": mesh_points,
                "n_slopes": m,
                "n_states": int(level.Q.shape[0]),
                "mfpt": float(level.mfpt),
                "mfpt_start": float(level.mfpt_start),
                "lambda_2": float(level.lambda_2),
            }
        )
        if previous is not None:
            change = max(
                abs(level.mfpt - previous[0]) / abs(level.mfpt),
                abs(level.mfpt_start - previous[1]) / abs(level.mfpt_start),
            )
            if change < tol and lev + 1 >= MIN_LEVELS:
                break
        previous = (level.mfpt, level.mfpt_start)
    return {
        "mfpt": float(level.mfpt),
        "mfpt_start": float(level.mfpt_start),
        "lambda_2": float(level.lambda_2),
        "converged": bool(change < tol),
        "change": float(change),
        "tol": float(tol),
        "levels": levels,
    }
