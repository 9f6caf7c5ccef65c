"""The control sequence's post-processing (reference step 8).

A 9-point Savitzky-Golay filter (quadratic, coefficients [-21, 14, 39, 54, 59, 54, 39, 14,
-21] / 231) over each axis, with the last four *applied* commands as its history at the front
and the final value held at the back, so the first command out is smooth against what the robot
actually did. Then every step is clipped to the velocity limits and the sequence is walked once
to respect the acceleration limits between consecutive steps (a sequential walk: numba, 56
steps x 3 axes, instead of 56 numpy calls).
"""
from __future__ import annotations

import numba
import numpy as np

SG = (np.array([-21, 14, 39, 54, 59, 54, 39, 14, -21], dtype=np.float32) / 231.0).astype(np.float32)
HISTORY = 4


def savitzky_golay(u: np.ndarray, history: np.ndarray) -> np.ndarray:
    """u (T, 3), history (4, 3) oldest first -> smoothed (T, 3)."""
    padded = np.vstack([history, u, np.repeat(u[-1:], HISTORY, axis=0)])
    out = np.empty_like(u)
    for a in range(u.shape[1]):
        out[:, a] = np.convolve(padded[:, a], SG[::-1], mode="valid")
    return out


def enforce_limits(u: np.ndarray, lo: np.ndarray, hi: np.ndarray, acc: np.ndarray, dt: float,
                   first_from: np.ndarray) -> np.ndarray:
    """Clip to [lo, hi], then walk the sequence so |u[t] - u[t-1]| <= acc * dt (u[-1] = first_from)."""
    u = np.clip(u, lo, hi).astype(np.float32)
    _walk(u, (acc * np.float32(dt)).astype(np.float32), first_from.astype(np.float32))
    return u


@numba.njit(cache=True)
def _walk(u, step, prev):
    """In place: each step within ``step`` of the one before (sequential, 56 x 3)."""
    for t in range(u.shape[0]):
        for a in range(u.shape[1]):
            u[t, a] = min(max(u[t, a], prev[a] - step[a]), prev[a] + step[a])
            prev[a] = u[t, a]
