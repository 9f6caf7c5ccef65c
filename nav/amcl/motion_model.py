"""Nav2's OmniMotionModel: sample where each particle went, given the wheel odometry's step.

The seed picks it because a DiffDrive model would treat the mecanum base's real lateral
motion as noise. The odometry step from pose ``a`` to pose ``b`` (odom frame) is a
translation ``d`` along a bearing taken relative to ``a``'s heading, plus a rotation ``r``.
Each particle replays that translation along the same relative bearing in its *own* heading,
plus a sideways strafe, all three perturbed by zero-mean Gaussians whose variances grow with
the step, as Nav2 writes them:

    trans  = d + N(0, alpha3 d^2 + alpha4 r^2)
    rot    = r + N(0, alpha1 r^2 + alpha2 d^2)
    strafe = 0 + N(0, alpha4 r^2 + alpha5 d^2)

    x += trans cos(bearing) + strafe sin(bearing)
    y += trans sin(bearing) - strafe cos(bearing)
    yaw += rot

``d`` being the straight chord of the step, a step that curves is replayed as its chord,
which is what Nav2 does too (the filter updates every 0.25 m, where the difference is nil).
Vectorised over the particles; the caller owns the random generator, so a run repeats.
"""
from __future__ import annotations

import math

import numpy as np

from hw.odometry import Pose2D, wrap_angle, wrap_angles


def sample_motion(particles: np.ndarray, a: Pose2D, b: Pose2D, alphas, rng: np.random.Generator) -> np.ndarray:
    """Move ``particles`` (N, 3: x, y, yaw in the map frame) in place by the odometry step
    ``a -> b`` (two odom-frame poses) and return them."""
    a1, a2, a3, a4, a5 = alphas
    dx, dy = b.x - a.x, b.y - a.y
    d2 = dx * dx + dy * dy
    r = wrap_angle(b.yaw - a.yaw)
    n = len(particles)
    trans = math.sqrt(d2) + rng.normal(0.0, 1.0, n) * math.sqrt(a3 * d2 + a4 * r * r)
    rot = r + rng.normal(0.0, 1.0, n) * math.sqrt(a1 * r * r + a2 * d2)
    strafe = rng.normal(0.0, 1.0, n) * math.sqrt(a4 * r * r + a5 * d2)
    bearing = wrap_angle(math.atan2(dy, dx) - a.yaw) + particles[:, 2]
    c, s = np.cos(bearing), np.sin(bearing)
    particles[:, 0] += trans * c + strafe * s
    particles[:, 1] += trans * s - strafe * c
    particles[:, 2] = wrap_angles(particles[:, 2] + rot)
    return particles
