"""Mecanum kinematics: one body twist <-> four wheel angular velocities.

This is the first stage of the seed's two-stage base chain (``mirte_base_controller``, a
``MecanumDriveController``): it decomposes a body velocity into per-wheel speeds using
``wheels_radius: 0.051`` and ``sum_of_robot_center_projection_on_X_Y_axis: 0.225``
(0.18/2 + 0.27/2). The second stage, the per-wheel PID, lives in ``hw.pid``.

Layout: the standard X-roller arrangement (rollers form an X seen from above), wheels in
``hw.interfaces.WHEELS`` order (front_left, front_right, rear_left, rear_right), REP-103 body
axes (x forward, y left, z up, CCW positive). With ``k = lx + ly`` and wheel radius ``r``::

    w_fl = (vx - vy - k wz) / r        w_fr = (vx + vy + k wz) / r
    w_rl = (vx + vy - k wz) / r        w_rr = (vx - vy + k wz) / r

The map is 4 x 3, so not every wheel vector is a rigid body motion; ``forward`` is its exact
left inverse (the least-squares body twist, the ``r/4`` sums), which round-trips ``inverse``
exactly and averages out wheel slip disagreement when fed measured speeds (odometry).

Why a non-zero ``vy`` is feasible at all, and why Nav2's MPPI uses the Omni motion model on this
robot, falls straight out of this matrix (seed, "the base").
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

from hw.config import BaseConfig
from hw.interfaces import Twist


class Mecanum:
    """Inverse and forward kinematics of the MIRTE Master mecanum base."""

    def __init__(self, wheel_radius: float, lx_plus_ly: float):
        if wheel_radius <= 0 or lx_plus_ly <= 0:
            raise ValueError(f"wheel_radius and lx_plus_ly must be positive, got {wheel_radius}, {lx_plus_ly}")
        self.wheel_radius = float(wheel_radius)
        self.lx_plus_ly = float(lx_plus_ly)
        k = self.lx_plus_ly
        #: rows: wheels in WHEELS order; columns: (vx, vy, wz). Wheel speeds = J @ twist.
        self.jacobian = np.array(
            [
                [1.0, -1.0, -k],
                [1.0, 1.0, k],
                [1.0, 1.0, -k],
                [1.0, -1.0, k],
            ]
        ) / self.wheel_radius
        # Exact left inverse of the jacobian (the columns are orthogonal): twist = F @ wheels.
        self._forward = np.linalg.pinv(self.jacobian)

    @classmethod
    def from_config(cls, config: BaseConfig) -> "Mecanum":
        return cls(config.wheel_radius, config.lx_plus_ly)

    def inverse(self, twist: Twist) -> np.ndarray:
        """Wheel angular velocities (rad/s, WHEELS order) that realise ``twist``."""
        return self.jacobian @ np.array([twist.vx, twist.vy, twist.wz], dtype=float)

    def forward(self, wheel_speeds: Sequence[float] | np.ndarray) -> Twist:
        """Body twist from four wheel angular velocities (least squares if inconsistent)."""
        w = np.asarray(wheel_speeds, dtype=float)
        if w.shape != (4,):
            raise ValueError(f"expected 4 wheel speeds in WHEELS order, got shape {w.shape}")
        vx, vy, wz = self._forward @ w
        return Twist(float(vx), float(vy), float(wz))
