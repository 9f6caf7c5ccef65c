"""Where the ``map -> odom`` transform comes from.

Navigation asks a ``Localisation`` for ``map -> odom`` and never looks at ground truth. This
first implementation, ``OdometryOnly``, holds it at identity: the map frame is the robot's pose
when the runtime started (spec/mission.md: in SLAM mode too, the map origin is the dock), so the
robot's map pose is its wheel odometry. The SLAM issue replaces it with a live transform (scan
matching, loop closure) and a localisation-on-a-saved-map twin; both keep this interface, so the
navigator does not change.
"""
from __future__ import annotations

from typing import Protocol

from hw.odometry import Pose2D


class Localisation(Protocol):
    def map_to_odom(self) -> Pose2D:
        """The current ``map -> odom`` transform."""

    def ready(self) -> bool:
        """True once ``map -> odom`` resolves (the readiness cascade's last stage)."""


class OdometryOnly:
    """``map -> odom`` held at identity: the map frame is the start pose."""

    def map_to_odom(self) -> Pose2D:
        return Pose2D()

    def ready(self) -> bool:
        return True
