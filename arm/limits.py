"""The arm's joint windows and the gripper's sign: the single source of truth.

Seed ("Joint limits and gripper direction"): the per-joint command windows are the
intersection of each servo's raw Hiwonder software limit with the +-90 deg URDF envelope,
rounded *inward* so Lupin never commands a pose the servo silently rejects. The original kept
them in one module (lupin_hmi/arm_limits.py) that the HMI, the preset server, teleop and the
gripper bridge all clamped through; so does this one. Presets, teleop, the console, the
gripper path, the trajectory controller and the IK clamp or check here and nowhere else.

The gripper is inverted on Mirte-247264: the operator's -30 deg is OPEN and +30 deg is CLOSED.
The +-30 deg operator window is a conservative guess (the servo reaches about -43.6..+37 deg),
hence ``GRIPPER_RANGE_UNVERIFIED``: widen it only after a live GetServoRange pass. Operator
degrees map linearly onto the URDF ``gripper_joint`` range [-0.20, 0.25] rad, so -30 deg lands
on -0.20 (wide open) and +30 deg on +0.25 (closed), as the sim model's jaw does.
"""
from __future__ import annotations

import math

import numpy as np

from arm.presets import ARM_JOINTS

#: Command windows, degrees, in joint order (seed table "Joint limits and gripper direction").
JOINT_LIMITS_DEG: dict[str, tuple[float, float]] = {
    "shoulder_pan": (-86.0, 90.0),  # servo stops at +90 but only reaches -86
    "shoulder_lift": (-86.0, 85.0),  # both ends tighter than 90 at the servo
    "elbow": (-90.0, 90.0),  # servo reaches past 90, kept at the URDF envelope
    "wrist": (-90.0, 88.0),  # -90 conservative, +88 is the servo stop
}
#: The same windows in radians.
JOINT_LIMITS: dict[str, tuple[float, float]] = {
    j: (math.radians(lo), math.radians(hi)) for j, (lo, hi) in JOINT_LIMITS_DEG.items()
}
#: (4,) lower and upper bounds in joint order, for vectorised clamps and the IK.
LOWER = np.array([JOINT_LIMITS[j][0] for j in ARM_JOINTS])
UPPER = np.array([JOINT_LIMITS[j][1] for j in ARM_JOINTS])

#: URDF gripper_joint range, rad (seed: [-0.20, 0.25], max_effort 2.0).
GRIPPER_LIMITS: tuple[float, float] = (-0.20, 0.25)
#: The operator's gripper window, degrees (seed: HMI +-30 deg).
GRIPPER_WINDOW_DEG: tuple[float, float] = (-30.0, 30.0)
#: Inverted sign on Mirte-247264 (seed): -30 deg is OPEN, +30 deg is CLOSED.
GRIPPER_OPEN_DEG = -30.0
GRIPPER_CLOSED_DEG = 30.0
#: The +-30 deg window is a guess pending a live GetServoRange pass (seed).
GRIPPER_RANGE_UNVERIFIED = True


def clamp_joint(joint: str, rad: float) -> float:
    """``rad`` clamped into ``joint``'s window (gripper: the URDF range). KeyError if unknown."""
    if joint == "gripper":
        lo, hi = GRIPPER_LIMITS
    else:
        try:
            lo, hi = JOINT_LIMITS[joint]
        except KeyError:
            raise KeyError(f"unknown arm joint {joint!r}; known: {', '.join((*ARM_JOINTS, 'gripper'))}") from None
    return min(max(float(rad), lo), hi)


def clamp_arm(q) -> np.ndarray:
    """Four joint angles (joint order) clamped into their windows, vectorised."""
    return np.clip(np.asarray(q, dtype=float), LOWER, UPPER)


def within(q, tol: float = 1e-9) -> bool:
    """True when all four joint angles (joint order) lie inside their windows."""
    q = np.asarray(q, dtype=float)
    return bool(np.all(q >= LOWER - tol) and np.all(q <= UPPER + tol))


def gripper_deg_to_rad(deg: float) -> float:
    """Operator degrees (-30 OPEN .. +30 CLOSED) -> URDF gripper radians, clamped first."""
    lo_d, hi_d = GRIPPER_WINDOW_DEG
    d = min(max(float(deg), lo_d), hi_d)
    lo, hi = GRIPPER_LIMITS
    return lo + (d - lo_d) * (hi - lo) / (hi_d - lo_d)


def gripper_rad_to_deg(rad: float) -> float:
    """URDF gripper radians -> operator degrees (the inverse map, clamped to the window)."""
    lo, hi = GRIPPER_LIMITS
    lo_d, hi_d = GRIPPER_WINDOW_DEG
    r = min(max(float(rad), lo), hi)
    return lo_d + (r - lo) * (hi_d - lo_d) / (hi - lo)
