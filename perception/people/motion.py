"""The constant-velocity Kalman filter every track runs, batched over the tracks.

State (x, y, vx, vy) in the odom frame; the motion model is constant velocity with white
acceleration noise (``accel_std``: people start and stop within about half a second), the
measurement a body's centre (``measurement_std``). A new track starts at its first detection
with an unknown velocity (1 m/s standard deviation: anything from standing to a brisk walk).
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np

H = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]])
EYE2, EYE4 = np.eye(2), np.eye(4)
UNKNOWN_SPEED_STD = 1.0
"""A new track's velocity standard deviation, m/s."""


def start(z: np.ndarray, measurement_std: float) -> tuple[np.ndarray, np.ndarray]:
    """States and covariances of tracks born at the (M, 2) detections ``z``."""
    m = len(z)
    x = np.zeros((m, 4))
    x[:, :2] = z
    p = np.zeros((m, 4, 4))
    p[:, [0, 1], [0, 1]] = measurement_std ** 2
    p[:, [2, 3], [2, 3]] = UNKNOWN_SPEED_STD ** 2
    return x, p


@lru_cache(maxsize=8)
def transition(dt: float, accel_std: float) -> tuple[np.ndarray, np.ndarray]:
    """The motion model over ``dt`` and its process noise, (F, Q), kept for the next scan with
    the same ``dt`` (the sim's scans come every 0.1 s to the bit; the robot's stamps jitter, and
    a miss costs what building them always did). Read-only: they are shared."""
    f = np.eye(4)
    f[0, 2] = f[1, 3] = dt
    g = np.array([[dt * dt / 2, 0.0], [0.0, dt * dt / 2], [dt, 0.0], [0.0, dt]])
    q = accel_std ** 2 * g @ g.T
    f.setflags(write=False)
    q.setflags(write=False)
    return f, q


def predict(x: np.ndarray, p: np.ndarray, dt: float, accel_std: float) -> tuple[np.ndarray, np.ndarray]:
    """Every track moved on by ``dt`` seconds."""
    f, q = transition(dt, accel_std)
    return x @ f.T, f @ p @ f.T + q


def correct(x: np.ndarray, p: np.ndarray, z: np.ndarray, measurement_std: float) -> tuple[np.ndarray, np.ndarray]:
    """Tracks (K of them) updated by their (K, 2) detections."""
    s = p[:, :2, :2] + measurement_std ** 2 * EYE2
    k = p[:, :, :2] @ np.linalg.inv(s)
    x = x + np.einsum("kij,kj->ki", k, z - x[:, :2])
    p = (EYE4 - k @ H) @ p
    return x, p
