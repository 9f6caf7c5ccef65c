"""Nav2's OmniMotionModel: sample how each particle moved, given the wheel odometry's motion.

The seed's reason for it: a DiffDrive model would treat the mecanum base's real lateral motion
as noise and penalise it. The odometry's step (from pose ``a`` to pose ``b``) is a translation
along a bearing plus a rotation; each particle moves by that translation along the same
bearing *in its own heading*, plus a sideways strafe, each perturbed:

    trans ~ N(d,   alpha3 d^2 + alpha1 r^2)      (as Nav2 writes the variances)
    rot   ~ N(r,   alpha4 d^2 + alpha2 r^2)
    strafe~ N(0,   alpha1 r^2 + alpha5 d^2)

with d the distance and r the rotation of the step. Vectorised over the particles.
"""
from __future__ import annotations

import math

import numpy as np

from hw.odometry import Pose2D, wrap_angle


def sample_motion(particles: np.ndarray, a: Pose2D, b: Pose2D, alphas, rng: np.random.Generator) -> None:
    """Move ``particles`` (N, 3) in place by the odometry step ``a -> b`` (odom frame)."""
    a1, a2, a3, a4, a5 = alphas
    dx, dy = b.x - a.x, b.y - a.y
    d = math.hypot(dx, dy)
    r = wrap_angle(b.yaw - a.yaw)
    n = len(particles)
    trans = d + rng.normal(0.0, math.sqrt(a3 * d * d + a1 * r * r), n)
    rot = r + rng.normal(0.0, math.sqrt(a4 * d * d + a2 * r * r), n)
    strafe = rng.normal(0.0, math.sqrt(a1 * r * r + a5 * d * d), n)
    bearing = (math.atan2(dy, dx) - a.yaw if d > 1e-9 else 0.0) + particles[:, 2]
    c, s = np.cos(bearing), np.sin(bearing)
    particles[:, 0] += trans * c + strafe * s
    particles[:, 1] += trans * s - strafe * c
    particles[:, 2] = np.remainder(particles[:, 2] + rot + math.pi, 2 * math.pi) - math.pi
