"""A 2D pose graph optimised with casadi (the original's slam_toolbox used Ceres).

Nodes are keyframe poses (x, y, yaw) in ``map``; edges are measured relative poses between two
nodes with an information matrix (diagonal: the inverse variances of x, y and yaw in the first
node's frame). Consecutive keyframes are joined by lidar odometry; loop closures join a
revisit to the keyframe it matched. The first node is held fixed (it anchors the map frame to
the dock), and the rest minimise the sum of squared, information-weighted residuals

    e_ij = [ R(z)^T (R(x_i)^T (t_j - t_i) - t_z) ;  wrap(th_j - th_i - th_z) ]

with IPOPT, the nonlinear solver casadi ships with (exact Hessian from casadi's automatic
differentiation; a few iterations for a graph that starts close). The residuals are built with
column-wise vector operations over all edges at once, so building the problem costs one pass
over numpy arrays, not a Python loop per edge.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from hw.odometry import Pose2D, wrap_angles

SOLVER_OPTIONS = {"ipopt.print_level": 0, "ipopt.sb": "yes", "print_time": 0, "ipopt.max_iter": 100,
                  "ipopt.tol": 1e-10}


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

    def optimize(self) -> float:
        """Move every node but the first to minimise the objective; returns its final value."""
        n = len(self.poses)
        if n < 2 or not self.edges:
            return 0.0
        free = ca.SX.sym("x", 3, n - 1)
        nodes = ca.horzcat(ca.DM(self.poses[0]), free)
        cost = _residual_cost(nodes, self.edges, ca)
        solver = ca.nlpsol("pose_graph", "ipopt", {"x": ca.vec(free), "f": cost}, SOLVER_OPTIONS)
        sol = solver(x0=ca.DM(self.poses[1:].T.ravel(order="F")))
        x = np.array(sol["x"]).reshape((3, n - 1), order="F").T
        x[:, 2] = wrap_angles(x[:, 2])
        self.poses = np.vstack([self.poses[:1], x])
        return float(sol["f"])


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
