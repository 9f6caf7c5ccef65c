"""A 2D pose graph optimised by sparse Gauss-Newton (the original's slam_toolbox used Ceres).

Nodes are keyframe poses (x, y, yaw) in ``map``; edges are measured relative poses between two
nodes with an information matrix (diagonal: the inverse variances of x, y and yaw in the first
node's frame). Consecutive keyframes are joined by lidar odometry; loop closures join a
revisit to the keyframe it matched. The first node is held fixed (it anchors the map frame to
the dock), and the rest minimise the sum of squared, information-weighted residuals

    e_ij = [ R(z)^T (R(x_i)^T (t_j - t_i) - t_z) ;  wrap(th_j - th_i - th_z) ]

Each Gauss-Newton step linearises every edge at once with numpy (the residual's Jacobians in
x_i and x_j are 3 x 3 blocks, as in g2o's 2D SLAM), sums the blocks into the sparse normal
matrix J^T W J, and solves it with CSparse's sparse Cholesky-free LU through casadi, the
solver library already on board: the matrix has a block per keyframe and two per edge, so a
solve costs milliseconds for thousands of keyframes where IPOPT (the first version) took
0.6 s for 2,000 and grew with the graph. A graph that starts close (lidar odometry is good to
centimetres) converges in a few steps.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from hw.odometry import Pose2D, wrap_angles

MAX_ITERATIONS = 20
"""Gauss-Newton steps at most (a graph that starts close converges in two to five)."""
CONVERGED = 1e-6
"""A step that lowers the objective by less than this share of it has converged (past the
first few steps, the steps only creep along the graph's long, stiff chain by 0.1 mm)."""


@dataclass(frozen=True)
class Edge:
    i: int
    j: int
    z: Pose2D
    """Node j as seen from node i."""
    information: tuple[float, float, float]
    """Inverse variances of the (x, y, yaw) residuals."""


class PoseGraph:
    def __init__(self) -> None:
        self.poses = np.zeros((0, 3))
        """(N, 3) node poses (x, y, yaw) in ``map``."""
        self.edges: list[Edge] = []

    def __len__(self) -> int:
        return len(self.poses)

    def add_node(self, pose: Pose2D) -> int:
        self.poses = np.vstack([self.poses, [pose.x, pose.y, pose.yaw]])
        return len(self.poses) - 1

    def add_edge(self, i: int, j: int, z: Pose2D, information: tuple[float, float, float]) -> None:
        self.edges.append(Edge(i, j, z, information))

    def node(self, k: int) -> Pose2D:
        x, y, yaw = self.poses[k]
        return Pose2D(float(x), float(y), float(yaw))

    def error(self, poses: np.ndarray | None = None) -> float:
        """The weighted squared residual sum (the objective), at ``poses`` or the current nodes."""
        return float(_residual_cost(np.asarray(self.poses if poses is None else poses), self.edges, np))

    def optimize(self, iterations: int = MAX_ITERATIONS) -> float:
        """Move every node but the first to minimise the objective; returns its final value."""
        n = len(self.poses)
        if n < 2 or not self.edges:
            return 0.0
        i = np.array([e.i for e in self.edges])
        j = np.array([e.j for e in self.edges])
        z = np.array([[e.z.x, e.z.y, e.z.yaw] for e in self.edges])
        w = np.array([e.information for e in self.edges])
        x = self.poses.copy()
        cost = self.error(x)
        for _ in range(iterations):
            step = _gauss_newton_step(x, i, j, z, w)
            x[1:] += step.reshape(n - 1, 3)
            x[:, 2] = wrap_angles(x[:, 2])
            before, cost = cost, self.error(x)
            if before - cost <= CONVERGED * before or np.abs(step).max() < 1e-9:
                break
        self.poses = x
        return cost


def _gauss_newton_step(x: np.ndarray, i: np.ndarray, j: np.ndarray, z: np.ndarray, w: np.ndarray) -> np.ndarray:
    """The step (for nodes 1..N-1, flattened) solving J^T W J dx = -J^T W e at poses ``x``."""
    n = len(x)
    ci, si = np.cos(x[i, 2]), np.sin(x[i, 2])
    cz, sz = np.cos(z[:, 2]), np.sin(z[:, 2])
    dx, dy = x[j, 0] - x[i, 0], x[j, 1] - x[i, 1]
    lx, ly = ci * dx + si * dy - z[:, 0], -si * dx + ci * dy - z[:, 1]
    e = np.column_stack([cz * lx + sz * ly, -sz * lx + cz * ly, wrap_angles(x[j, 2] - x[i, 2] - z[:, 2])])
    # d(R_i^T dt)/d(t_i) = -R_i^T, /d(th_i) = [-s c; -c -s] dt, /d(t_j) = R_i^T; then R_z^T in front
    rz = np.stack([np.stack([cz, sz], -1), np.stack([-sz, cz], -1)], -2)  # (E, 2, 2) R_z^T
    ri = np.stack([np.stack([ci, si], -1), np.stack([-si, ci], -1)], -2)  # (E, 2, 2) R_i^T
    dri = np.stack([-si * dx + ci * dy, -ci * dx - si * dy], -1)  # (E, 2) d(R_i^T)/d(th_i) dt
    a, b = np.zeros((len(i), 3, 3)), np.zeros((len(i), 3, 3))
    a[:, :2, :2] = -rz @ ri
    a[:, :2, 2] = np.einsum("eab,eb->ea", rz, dri)
    a[:, 2, 2] = -1.0
    b[:, :2, :2] = rz @ ri
    b[:, 2, 2] = 1.0
    wa, wb = w[:, :, None] * a, w[:, :, None] * b  # W is diagonal
    blocks = {(0, 0): np.einsum("eki,ekj->eij", a, wa), (0, 1): np.einsum("eki,ekj->eij", a, wb),
              (1, 0): np.einsum("eki,ekj->eij", b, wa), (1, 1): np.einsum("eki,ekj->eij", b, wb)}
    nodes = (i, j)
    rows, cols, vals = [], [], []
    k = np.arange(3)
    for (p, q), blk in blocks.items():
        r = (nodes[p][:, None, None] * 3 + k[None, :, None]) + 0 * k[None, None, :]
        c = (nodes[q][:, None, None] * 3 + k[None, None, :]) + 0 * k[None, :, None]
        rows.append(r.ravel()), cols.append(c.ravel()), vals.append(blk.ravel())
    g = np.zeros(3 * n)
    np.add.at(g, (i[:, None] * 3 + k).ravel(), np.einsum("eki,ek->ei", a, w * e).ravel())
    np.add.at(g, (j[:, None] * 3 + k).ravel(), np.einsum("eki,ek->ei", b, w * e).ravel())
    rows, cols, vals = np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)
    keep = (rows >= 3) & (cols >= 3)  # node 0 is held fixed: drop its rows and columns
    rows, cols, vals = rows[keep] - 3, cols[keep] - 3, vals[keep]
    m = 3 * (n - 1)
    flat, inverse = np.unique(rows * m + cols, return_inverse=True)  # sum the blocks that meet
    summed = np.bincount(inverse, weights=vals)
    h = ca.DM.triplet((flat // m).tolist(), (flat % m).tolist(), ca.DM(summed), m, m)
    solver = ca.Linsol("pose_graph", "csparse", h.sparsity())
    return -np.array(solver.solve(h, ca.DM(g[3:]))).ravel()


def _residual_cost(nodes, edges: list[Edge], m):
    """Sum of weighted squared residuals; ``nodes`` is (N, 3) numpy with ``m = np`` or a 3 x N
    casadi matrix with ``m = ca`` (the same formula serves the solver and the check)."""
    i = [e.i for e in edges]
    j = [e.j for e in edges]
    row = (lambda a: a) if m is np else (lambda a: ca.DM(a).T)
    z = [row(r) for r in np.array([[e.z.x, e.z.y, e.z.yaw] for e in edges]).T]
    w = [row(r) for r in np.array([e.information for e in edges]).T]
    if m is np:
        ni, nj = nodes[i].T, nodes[j].T
    else:
        ni, nj = nodes[:, i], nodes[:, j]
    dx, dy = nj[0, :] - ni[0, :], nj[1, :] - ni[1, :]
    ci, si = m.cos(ni[2, :]), m.sin(ni[2, :])
    lx, ly = ci * dx + si * dy - z[0], -si * dx + ci * dy - z[1]
    cz, sz = m.cos(z[2]), m.sin(z[2])
    ex, ey = cz * lx + sz * ly, -sz * lx + cz * ly
    dth = nj[2, :] - ni[2, :] - z[2]
    eth = m.arctan2(m.sin(dth), m.cos(dth)) if m is np else ca.atan2(ca.sin(dth), ca.cos(dth))
    total = w[0] * ex ** 2 + w[1] * ey ** 2 + w[2] * eth ** 2
    return np.sum(total) if m is np else ca.sum2(total)
