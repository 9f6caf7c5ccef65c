"""Where the robot stands to inspect a pot (spec/mission.md): ``standoff`` metres out from the
pot's centre along its ``facing``, heading ``facing + pi`` (looking back at the pot and its
tag). One definition for the patrol, the navigation trial and the perception harness."""
from __future__ import annotations

import math

from hw.odometry import Pose2D, wrap_angle

STANDOFF = 0.5
"""Approach distance from the pot centre, m (spec/mission.md default; the original's 0.5 m)."""


def approach_pose(x: float, y: float, facing: float, standoff: float = STANDOFF) -> Pose2D:
    return Pose2D(x + standoff * math.cos(facing), y + standoff * math.sin(facing), wrap_angle(facing + math.pi))
