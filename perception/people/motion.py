"""The constant-velocity Kalman filter every track runs, batched over the tracks.

State (x, y, vx, vy) in the odom frame; the motion model is constant velocity with white
acceleration noise (``accel_std``: people start and stop within about half a second), the
measurement a body's centre (``measurement_std``). A new track starts at its first detection
with an unknown velocity (1 m/s standard deviation: anything from standing to a brisk walk).
"""
from __future__ import annotations

import numpy as np
from numba import njit

UNKNOWN_SPEED_STD = 1.0
"""A new track's velocity standard deviation, m/s."""


@njit(cache=True)
def start(z, measurement_std):
    """States and covariances of tracks born at the (M, 2) detections ``z``."""
    m = z.shape[0]
    x, p = np.zeros((m, 4)), np.zeros((m, 4, 4))
    for t in range(m):
        x[t, 0], x[t, 1] = z[t, 0], z[t, 1]
        p[t, 0, 0] = p[t, 1, 1] = measurement_std ** 2
        p[t, 2, 2] = p[t, 3, 3] = UNKNOWN_SPEED_STD ** 2
    return x, p


@njit(cache=True)
def predict(x, p, dt, accel_std):
    """Every track moved on by ``dt`` seconds: x F^T and F P F^T + Q, F the constant-velocity
    model and Q its white-acceleration noise (a^2 G G^T, G = [dt^2/2 I; dt I]), written out:
    a handful of tracks cost less in loops than in batched matmuls."""
    x, p = x.copy(), p.copy()
    a2, h = accel_std ** 2, dt * dt / 2.0
    for t in range(x.shape[0]):
        x[t, 0] += dt * x[t, 2]
        x[t, 1] += dt * x[t, 3]
        for row in range(2):  # F P: position rows take dt times their velocity rows
            for col in range(4):
                p[t, row, col] += dt * p[t, row + 2, col]
        for row in range(4):  # (F P) F^T: the same on the columns
            for col in range(2):
                p[t, row, col] += dt * p[t, row, col + 2]
        for axis in range(2):
            v = axis + 2
            p[t, axis, axis] += a2 * h * h
            p[t, axis, v] += a2 * h * dt
            p[t, v, axis] += a2 * h * dt
            p[t, v, v] += a2 * dt * dt
    return x, p


@njit(cache=True)
def correct(x, p, z, r2):
    """The Kalman update of each track by its detection (``r2``: the measurement variance), the
    2x2 innovation inverted in closed form (a batched ``inv`` and ``einsum`` cost more than the
    arithmetic for a handful)."""
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
