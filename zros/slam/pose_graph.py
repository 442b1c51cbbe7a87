"""A 2D pose graph and its least-squares solution with scipy's sparse solver.

Nodes are poses x_i = (x, y, yaw) in the map frame. An edge (i, j, z, Ω) says "seen from x_i,
x_j is at z" with information matrix Ω (inverse covariance). The solution minimises

    sum over edges of  ρ(e_ijᵀ Ω e_ij),  e_ij = (x_i⁻¹ ∘ x_j) ⊖ z

by Gauss-Newton with Levenberg-Marquardt damping: each iteration stacks every edge's Jacobian
blocks (analytic, 3x3 per node) into one sparse matrix, forms the normal equations JᵀWJ Δ =
-JᵀWe, and solves them with scipy.sparse.linalg.spsolve (SuperLU), the first node held fixed.
`robust` edges (zros.slam.Slam makes every edge robust) are weighted by a Cauchy kernel of the
Mahalanobis error (iteratively reweighted), so one wrong edge among many that agree is outvoted
instead of tearing the graph; its error stays in it rather than spreading along the chain.
No loop over edges or nodes in Python: everything is vectorised over edge arrays.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from zros.rotations import wrap_angle
from zros.slam.geometry import relative

__all__ = ['PoseGraph', 'Edge', 'OptimizationResult']


class Edge(NamedTuple):
    """i, j: node ids; measurement: (3,) pose of j seen from i; information: (3, 3);
    robust: whether a Cauchy kernel down-weights it when it disagrees with the rest of the graph."""
    i: int
    j: int
    measurement: np.ndarray
    information: np.ndarray
    robust: bool = False


class OptimizationResult(NamedTuple):
    iterations: int
    initial_cost: float
    final_cost: float


class PoseGraph:
    """Nodes and edges; `optimize()` moves the nodes (module docstring).

    Args:
        robust_scale: Cauchy kernel scale, in units of the Mahalanobis distance.
    """

    def __init__(self, *, robust_scale: float = 3.0) -> None:
        self.robust_scale = float(robust_scale)
        self._poses = np.zeros((0, 3))
        self.edges: list[Edge] = []

    @property
    def poses(self) -> np.ndarray:
        """(N, 3) node poses (a view: do not modify)."""
        return self._poses

    def __len__(self) -> int:
        return len(self._poses)

    def add_node(self, pose: np.ndarray) -> int:
        self._poses = np.vstack([self._poses, np.asarray(pose, dtype=np.float64)[None, :]])
        return len(self._poses) - 1

    def set_poses(self, poses: np.ndarray) -> None:
        poses = np.asarray(poses, dtype=np.float64)
        if poses.shape != self._poses.shape:
            raise ValueError(f'expected {self._poses.shape} poses, got {poses.shape}')
        self._poses = poses.copy()

    def add_edge(self, i: int, j: int, measurement: np.ndarray, information: np.ndarray, *,
                 robust: bool = False) -> None:
        n = len(self._poses)
        if not (0 <= i < n and 0 <= j < n) or i == j:
            raise ValueError(f'edge ({i}, {j}) needs two different nodes among {n}')
        self.edges.append(Edge(i, j, np.asarray(measurement, dtype=np.float64),
                               np.asarray(information, dtype=np.float64), robust))

    def errors(self, poses: np.ndarray | None = None) -> np.ndarray:
        """(E, 3) edge errors at `poses` (default: the current ones)."""
        poses = self._poses if poses is None else poses
        i, j, z, _, _ = self._arrays()
        error = relative(poses[i], poses[j]) - z
        error[:, 2] = wrap_angle(error[:, 2])
        return error

    def _arrays(self) -> tuple[np.ndarray, ...]:
        i = np.array([e.i for e in self.edges], dtype=np.int64)
        j = np.array([e.j for e in self.edges], dtype=np.int64)
        z = np.array([e.measurement for e in self.edges]).reshape(-1, 3)
        info = np.array([e.information for e in self.edges]).reshape(-1, 3, 3)
        robust = np.array([e.robust for e in self.edges], dtype=bool)
        return i, j, z, info, robust

    def _weights(self, error: np.ndarray, info: np.ndarray, robust: np.ndarray) -> tuple[np.ndarray, float]:
        """Per-edge IRLS weights and the robust total cost."""
        squared = np.einsum('ea,eab,eb->e', error, info, error)
        c2 = self.robust_scale ** 2
        weight = np.where(robust, 1.0 / (1.0 + squared / c2), 1.0)
        cost = np.where(robust, c2 * np.log1p(squared / c2), squared)
        return weight, float(cost.sum())

    def optimize(self, *, iterations: int = 20, tolerance: float = 1e-6) -> OptimizationResult:
        """Move every node but the first to minimise the (robust) weighted squared errors."""
        n = len(self._poses)
        if n < 2 or not self.edges:
            return OptimizationResult(0, 0.0, 0.0)
        i, j, z, info, robust = self._arrays()
        poses = self._poses.copy()
        weight, cost = self._weights(self.errors(poses), info, robust)
        initial_cost = cost
        damping = 1e-4
        done = 0
        for done in range(1, iterations + 1):
            error = self.errors(poses)
            a_block, b_block = _jacobians(poses[i], poses[j])
            omega = info * weight[:, None, None]
            jacobian = _stack(i, j, a_block, b_block, n)                   # (3E, 3N)
            weights = _block_diag(omega)
            hessian = (jacobian.T @ weights @ jacobian).tocsc()
            gradient = jacobian.T @ (weights @ error.ravel())
            free = slice(3, 3 * n)                                        # node 0 is the anchor
            h = hessian[free, free]
            h = h + sp.diags(damping * (h.diagonal() + 1e-9))
            delta = np.zeros(3 * n)
            delta[free] = -spsolve(h.tocsc(), gradient[free])
            trial = poses + delta.reshape(n, 3)
            trial[:, 2] = wrap_angle(trial[:, 2])
            trial_weight, trial_cost = self._weights(self.errors(trial), info, robust)
            if trial_cost <= cost:
                poses, cost, weight = trial, trial_cost, trial_weight
                damping = max(damping * 0.3, 1e-9)
                if np.abs(delta).max() < tolerance:
                    break
            else:
                damping *= 10.0
                if damping > 1e4:
                    break
        self._poses = poses
        return OptimizationResult(done, initial_cost, cost)


def _jacobians(xi: np.ndarray, xj: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """d e / d x_i and d e / d x_j for e = x_i⁻¹ ∘ x_j ⊖ z: (E, 3, 3) each."""
    c, s = np.cos(xi[:, 2]), np.sin(xi[:, 2])
    dx, dy = xj[:, 0] - xi[:, 0], xj[:, 1] - xi[:, 1]
    count = len(xi)
    a = np.zeros((count, 3, 3))
    a[:, 0, 0], a[:, 0, 1], a[:, 0, 2] = -c, -s, -s * dx + c * dy
    a[:, 1, 0], a[:, 1, 1], a[:, 1, 2] = s, -c, -c * dx - s * dy
    a[:, 2, 2] = -1.0
    b = np.zeros((count, 3, 3))
    b[:, 0, 0], b[:, 0, 1] = c, s
    b[:, 1, 0], b[:, 1, 1] = -s, c
    b[:, 2, 2] = 1.0
    return a, b


def _stack(i: np.ndarray, j: np.ndarray, a: np.ndarray, b: np.ndarray, n: int) -> sp.csr_matrix:
    """The (3E, 3N) sparse Jacobian with block a at (edge, i) and b at (edge, j)."""
    count = len(i)
    rows = np.repeat(3 * np.arange(count), 9) + np.tile(np.repeat(np.arange(3), 3), count)
    cols_local = np.tile(np.tile(np.arange(3), 3), count)
    data = np.concatenate([a.reshape(-1), b.reshape(-1)])
    row = np.concatenate([rows, rows])
    col = np.concatenate([np.repeat(3 * i, 9) + cols_local, np.repeat(3 * j, 9) + cols_local])
    return sp.csr_matrix((data, (row, col)), shape=(3 * count, 3 * n))


def _block_diag(blocks: np.ndarray) -> sp.csr_matrix:
    """(E, 3, 3) blocks on the diagonal of a (3E, 3E) sparse matrix."""
    count = len(blocks)
    base = 3 * np.arange(count)
    rows = np.repeat(base, 9) + np.tile(np.repeat(np.arange(3), 3), count)
    cols = np.repeat(base, 9) + np.tile(np.tile(np.arange(3), 3), count)
    return sp.csr_matrix((blocks.reshape(-1), (rows, cols)), shape=(3 * count, 3 * count))
