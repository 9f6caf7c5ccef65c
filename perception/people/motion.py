"""The constant-velocity Kalman filter every track runs, batched over the tracks.

State (x, y, vx, vy) in the odom frame; the motion model is constant velocity with white
acceleration noise (``accel_std``: people start and stop within about half a second), the
measurement a body's centre (``measurement_std``). A new track starts at its first detection
with an unknown velocity (1 m/s standard deviation: anything from standing to a brisk walk).
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np
from numba import njit

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


@njit(cache=True)
def _correct(x, p, z, r2):
    """The Kalman update of each track by its detection, the 2x2 innovation inverted in closed
    form (a batched ``inv`` and ``einsum`` cost more than the arithmetic for a handful)."""
    x, p = x.copy(), p.copy()
    for t in range(x.shape[0]):
        a, b, d = p[t, 0, 0] + r2, p[t, 0, 1], p[t, 1, 1] + r2
        c = p[t, 1, 0]
        det = a * d - b * c
        i00, i01, i10, i11 = d / det, -b / det, -c / det, a / det
        gain = np.empty((4, 2))
        for row in range(4):
            gain[row, 0] = p[t, row, 0] * i00 + p[t, row, 1] * i10
            gain[row, 1] = p[t, row, 0] * i01 + p[t, row, 1] * i11
        e0, e1 = z[t, 0] - x[t, 0], z[t, 1] - x[t, 1]
        for row in range(4):
            x[t, row] += gain[row, 0] * e0 + gain[row, 1] * e1
        top = p[t, :2, :].copy()  # (I - K H) P = P - K (H P), and H P is P's first two rows
        for row in range(4):
            for col in range(4):
                p[t, row, col] -= gain[row, 0] * top[0, col] + gain[row, 1] * top[1, col]
    return x, p


def correct(x: np.ndarray, p: np.ndarray, z: np.ndarray, measurement_std: float) -> tuple[np.ndarray, np.ndarray]:
    """Tracks (K of them) updated by their (K, 2) detections."""
    return _correct(np.ascontiguousarray(x, dtype=np.float64), np.ascontiguousarray(p, dtype=np.float64),
                    np.ascontiguousarray(z, dtype=np.float64), float(measurement_std) ** 2)
