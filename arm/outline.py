"""The arm as it stands, seen from above: capsules on the floor plane for the collision monitor.

The lidar sweeps a plane 0.21 m up, under the shoulder; the arm crosses it when it reaches down
(``tuck`` hangs the forearm in front of the lidar), and reaching forward it carries the gripper
past the chassis' front, where turning swings it through the aisle. So the monitor's body is the
chassis plus this: each link from the pan axis out to the fingertips, projected straight down
(heights dropped: a person's arm or a trolley at the gripper's height is hit by it whatever the
lidar plane sees), thickened to the links' width. The chain and its signs are
``arm.kinematics``'; the hand and the width are the robot model's (mirte_master.xml).
"""
from __future__ import annotations

import math

import numpy as np

from arm.config import KinematicsConfig
from arm.kinematics import planar
from hw.robot_outline import Capsules

HAND = 0.105
"""Wrist axis -> fingertips, m (model: finger_fixed at 0.077 m along the wrist link, 0.028 m
half-length)."""
RADIUS = 0.03
"""Half the links' width seen from above, m, rounded up (model: the widest parts are the
gripper servo, 0.036 m, and the wrist camera bracket, 0.052 m long across the link)."""


def arm_capsules(q, k: KinematicsConfig) -> Capsules:
    """The arm at joint angles ``q`` (shoulder_pan, shoulder_lift, elbow, wrist) as capsules in
    base_link: pan axis -> elbow -> wrist -> fingertips, and wrist -> wrist camera."""
    pan, q1, q2, q3 = (float(v) for v in q)
    t1 = -q1
    t2 = t1 + q2
    t3 = t2 - q3
    elbow = k.upper_arm * math.sin(t1)
    wrist = elbow + k.forearm * math.sin(t2)
    tip = wrist + HAND * math.sin(t3)
    camera = planar(q1, q2, q3, k, math)[0]
    u = np.array([math.cos(pan), math.sin(pan)])
    o = np.asarray(k.pan_origin[:2], dtype=float)
    reach = np.array([0.0, elbow, wrist, tip, camera])
    p = o + reach[:, None] * u
    return Capsules(np.stack([p[[0, 1]], p[[1, 2]], p[[2, 3]], p[[2, 4]]]), RADIUS)
