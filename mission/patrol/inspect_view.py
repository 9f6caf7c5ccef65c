"""Where the arm holds the wrist camera at a pot: the patrol's preset, or the IK look at the plant.

From the ideal approach pose the patrol takes its ``inspect_pose`` (``inspect_plant``: the
whole plant top in the frame under the arm's sag, arm/presets.py). A robot that stopped more
than ``aim_xy`` / ``aim_yaw`` off that pose, by its own belief, would see the plant off-centre
or not at all: it aims the camera with IK (``arm.aim``) at the spot the preset frames from the
ideal pose, from about the preset's own range if it can (else from any range the IK allows), a
pose nearest the preset, and takes the preset again only when no pose inside the joint windows
can. The patrol tree and the ``perception.flower`` benchmark choose through this
one class, so the benchmark scores the view the patrol takes.

Public API: :class:`InspectView`.
"""
from __future__ import annotations

import math

import numpy as np

from arm.aim import CameraAim, view_target
from arm.kinematics import camera_ray
from arm.config import ArmConfig
from arm.presets import PRESETS, preset
from hw.odometry import Pose2D
from mission.patrol.config import PatrolConfig
from nav.frames import compose, inverse


RANGE_BAND = 0.03
"""The IK look sees the spot from the preset's own range +- this, m, when it can: the plant then
fills the frame as it does from the ideal pose (nearer, it overfills it; farther, a bloom
shrinks and the look goes flat enough to take in the pot's side and the wall behind)."""


class InspectView:
    def __init__(self, arm: ArmConfig, config: PatrolConfig):
        self.config = config
        self.pose = config.inspect_pose
        self.spot = view_target(PRESETS[self.pose], arm.kinematics, config.bloom_height)
        """Where the preset's optical axis meets the bloom plane, in base_link at the ideal pose."""
        reach = float(np.linalg.norm(self.spot - camera_ray(PRESETS[self.pose], arm.kinematics)[0]))
        band = arm.ik.model_copy(update={"min_range": max(arm.ik.min_range, reach - RANGE_BAND),
                                         "max_range": min(arm.ik.max_range, reach + RANGE_BAND)})
        self.aims = (CameraAim(arm.kinematics, band, reference=self.pose),
                     CameraAim(arm.kinematics, arm.ik, reference=self.pose))
        """The look from the preset's range, then from any range the IK allows."""

    def goal(self, ideal: Pose2D, here: Pose2D) -> tuple[object, str]:
        """(joint goal, label) for a robot at ``here`` whose ideal approach pose is ``ideal``
        (both in one frame): the preset (labelled with its name) or the IK look ('aim')."""
        off = compose(inverse(ideal), here)
        if math.hypot(off.x, off.y) > self.config.aim_xy or abs(off.yaw) > self.config.aim_yaw:
            spot = compose(inverse(here), compose(ideal, Pose2D(self.spot[0], self.spot[1], 0.0)))
            for aim in self.aims:
                aimed = aim.aim(np.array([spot.x, spot.y, self.spot[2]]))
                if aimed.ok:
                    return aimed.q, "aim"
        return preset(self.pose), self.pose


__all__ = ["InspectView"]
