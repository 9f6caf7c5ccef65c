"""Forward kinematics of the wrist camera: where it is and where its optical axis points.

The chain (robot model, after the vendor URDF; numbers in ``KinematicsConfig``): shoulder_pan
turns about +z at ``pan_origin``; shoulder_lift, elbow and wrist all turn about the pan
plane's y axis, with zero meaning every link straight up. The signs make the seed's presets
do what the seed says: a negative lift, a positive elbow and a negative wrist all bend the arm
forward, so the links' tilts from vertical are

    t1 = -lift,   t2 = t1 + elbow,   t3 = t2 - wrist

(``inspect`` gives 0.4, 1.3 and 2.1 rad). The camera rides on the wrist link at
``camera_offset`` and looks along the link pitched ``camera_pitch`` further the same way, so its
optical axis tilts t3 + 0.40 from straight up (about 53 deg below horizontal at ``inspect``).
Everything the camera does happens in the vertical plane through the pan axis, which is what
lets the IK take the pan angle in closed form.

``planar`` is written once for both numpy floats and casadi symbols (pass the module as ``m``).
"""
from __future__ import annotations

import math

import numpy as np

from arm.config import KinematicsConfig


def planar(q1, q2, q3, k: KinematicsConfig, m=np):
    """(r, z, dr, dz): camera position and optical-axis direction in the pan plane, relative to
    the pan origin (r outward from the pan axis, z up)."""
    t1 = -q1
    t2 = t1 + q2
    t3 = t2 - q3
    r = k.upper_arm * m.sin(t1) + k.forearm * m.sin(t2)
    z = k.lift_height + k.upper_arm * m.cos(t1) + k.forearm * m.cos(t2)
    cx, cz = k.camera_offset
    r = r + cx * m.cos(t3) + cz * m.sin(t3)
    z = z - cx * m.sin(t3) + cz * m.cos(t3)
    a = t3 + k.camera_pitch
    return r, z, m.sin(a), m.cos(a)


def camera_ray(q, k: KinematicsConfig) -> tuple[np.ndarray, np.ndarray]:
    """Camera optical centre and unit optical-axis direction in base_link for joint angles
    ``q`` (joint order: shoulder_pan, shoulder_lift, elbow, wrist)."""
    pan, q1, q2, q3 = (float(v) for v in q)
    r, z, dr, dz = planar(q1, q2, q3, k, math)
    c, s = math.cos(pan), math.sin(pan)
    origin = np.asarray(k.pan_origin, dtype=float)
    return origin + np.array([r * c, r * s, z]), np.array([dr * c, dr * s, dz])


def miss_distance(q, target, k: KinematicsConfig) -> tuple[float, float]:
    """(distance from ``target`` to the optical axis, distance along it), metres. A target
    behind the camera misses by its full distance."""
    p, d = camera_ray(q, k)
    v = np.asarray(target, dtype=float) - p
    along = float(v @ d)
    if along <= 0:
        return float(np.linalg.norm(v)), along
    return float(np.linalg.norm(v - along * d)), along
