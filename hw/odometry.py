"""Wheel odometry: measured wheel speeds -> body twist -> pose in the odom frame.

The seed's ``mirte_base_controller`` publishes wheel-encoder odometry on
``/mirte_base_controller/odom``, the same in sim and on hardware, and Nav2 consumes it as its
odom source. Here the base controller feeds this integrator each control tick; the pose is the
``odom -> base_link`` transform of REP-105.

Integration is the exact SE(2) arc for a twist held constant over ``dt`` (the robot moves along
a circular arc while it rotates), which is what a 10 Hz beat with a zero-order-hold command
actually does. It reduces to the straight line when ``wz`` is ~0, and agrees with midpoint-
heading integration to second order.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from hw.interfaces import ZERO_TWIST, Twist
from hw.mecanum import Mecanum

_SMALL_ANGLE = 1e-9


@dataclass(frozen=True)
class Pose2D:
    """A planar pose: metres and radians (yaw CCW from +x, wrapped to (-pi, pi])."""

    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0


def wrap_angle(a: float) -> float:
    """Wrap to (-pi, pi]."""
    w = math.remainder(a, 2.0 * math.pi)
    return math.pi if w == -math.pi else w


def wrap_angles(a: np.ndarray) -> np.ndarray:
    """``wrap_angle`` for arrays, vectorised, the same (-pi, pi]."""
    return math.pi - np.remainder(math.pi - np.asarray(a), 2.0 * math.pi)


class WheelOdometry:
    """Dead reckoning from the four wheel speeds through the mecanum forward kinematics."""

    def __init__(self, mecanum: Mecanum):
        self.mecanum = mecanum
        self.pose = Pose2D()
        self.twist: Twist = ZERO_TWIST
        self.distance = 0.0
        """Path length driven in the plane, metres (translation only; spinning in place adds 0)."""

    def reset(self, pose: Pose2D = Pose2D()) -> None:
        self.pose = pose
        self.twist = ZERO_TWIST
        self.distance = 0.0

    def update(self, wheel_speeds: Sequence[float] | np.ndarray, dt: float) -> Pose2D:
        """Integrate measured wheel speeds (rad/s, WHEELS order) held over ``dt`` seconds."""
        return self.integrate(self.mecanum.forward(wheel_speeds), dt)

    def integrate(self, twist: Twist, dt: float) -> Pose2D:
        """Integrate a body twist held constant over ``dt`` seconds (exact arc)."""
        self.twist = twist
        if dt <= 0:
            return self.pose
        dth = twist.wz * dt
        # Body-frame displacement of the arc: V(dth) @ (vx, vy) * dt.
        if abs(dth) < _SMALL_ANGLE:
            a, b = 1.0 - dth * dth / 6.0, dth / 2.0
        else:
            a, b = math.sin(dth) / dth, (1.0 - math.cos(dth)) / dth
        dx_b = (a * twist.vx - b * twist.vy) * dt
        dy_b = (b * twist.vx + a * twist.vy) * dt
        c, s = math.cos(self.pose.yaw), math.sin(self.pose.yaw)
        self.pose = Pose2D(
            self.pose.x + c * dx_b - s * dy_b,
            self.pose.y + s * dx_b + c * dy_b,
            wrap_angle(self.pose.yaw + dth),
        )
        self.distance += math.hypot(twist.vx, twist.vy) * dt
        return self.pose
