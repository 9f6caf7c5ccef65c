"""PathAngleCritic (seed weight 2.0): heading error against the path, only when the robot's
heading is off by more than ``max_angle_to_furthest`` (0.785 rad) and farther than 0.5 m from
the goal.

Nav2's three modes: ``forward`` compares each trajectory's yaw with the bearing from that point
to the path point ``offset_from_furthest`` (4) past the furthest reached; ``bidirectional``
takes the smaller of that and its reverse; ``path_orientation`` compares with the path's own
orientation there (which the controller sets to the goal heading for a holonomic base)."""
from __future__ import annotations

import numpy as np

from nav.mppi.critic_data import CriticData, mean_abs_angle_error, shortest_angle
from nav.mppi.critics.base import Critic


class PathAngleCritic(Critic):
    def score(self, data: CriticData) -> None:
        p = self.params
        if data.goal_distance <= p.threshold_to_consider or len(data.path) < 2:
            return
        i = min(data.furthest_reached + p.offset_from_furthest, len(data.path) - 1)
        gx, gy, gyaw = data.path[i]
        x, y, yaw = data.pose
        if p.mode == "path_orientation":
            if abs(shortest_angle(yaw, gyaw)) < p.max_angle_to_furthest:
                return
            data.costs += p.weight * mean_abs_angle_error(data.traj[2], np.float32(gyaw))
            return
        else:
            bearing_now = np.arctan2(gy - y, gx - x)
            off = abs(shortest_angle(yaw, bearing_now))
            if p.mode == "bidirectional":
                off = min(off, np.pi - off)
            if off < p.max_angle_to_furthest:
                return
            bearing = np.arctan2(gy - data.traj[1], gx - data.traj[0])
            err = np.abs(shortest_angle(data.traj[2], bearing))
            if p.mode == "bidirectional":
                err = np.minimum(err, np.pi - err)
        data.costs += p.weight * err.mean(axis=1)
