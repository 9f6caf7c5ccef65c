"""Where a pot is, from its tag: one read gives the pot's centre and facing in the map, many
reads of the same tag are fused into one estimate.

A tag plate sits on its pot's inspection side, the printed square facing the aisle; the tag
reader gives the tag's pose in the front camera (OpenCV axes: x right, y down, z forward; the
camera looks along ``base_link`` +x). The tag's normal (its z axis, out of the face) is the
pot's ``facing``, and the pot's centre lies ``plate_offset`` behind the tag's centre along it.
With the robot's map pose at the frame, that puts the pot in the map.

A read is only as good as its view: the tag's corners are a few pixels wide at 1.5 m, and seen
edge-on the pose's yaw is poor. Reads farther than ``max_distance`` or more off-axis than
``max_off_axis`` are not used, and the rest are averaged with weights falling with distance
squared (the pixel error's effect on the pose grows with it), so a close, head-on read settles
the estimate and a glimpse down the aisle barely moves it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import cv2
import numpy as np

from hw.odometry import Pose2D
from nav.frames import compose
from perception.detections import TagRead


@dataclass(frozen=True)
class PotSighting:
    tag: int
    x: float
    y: float
    """The pot's centre, map frame, m."""
    facing: float
    """The pot's facing (the tag's normal), map frame, rad."""
    distance: float
    """Camera to tag, m."""
    off_axis: float
    """The tag seen this far off head-on, rad."""


def pot_from_tag(read: TagRead, robot: Pose2D, mount: tuple[float, float, float], plate_offset: float) -> PotSighting:
    """The pot a tag read puts in the map, from the robot's map pose when the frame was taken."""
    right, _, forward = read.position
    tag = compose(robot, Pose2D(mount[0] + forward, mount[1] - right, 0.0))
    normal = cv2.Rodrigues(np.asarray(read.rotation, np.float64))[0][:, 2]  # camera frame
    facing = robot.yaw + math.atan2(-normal[0], normal[2])  # base_link: x = camera z, y = -camera x
    return PotSighting(read.id, tag.x - plate_offset * math.cos(facing), tag.y - plate_offset * math.sin(facing),
                       math.atan2(math.sin(facing), math.cos(facing)), read.distance, read.off_axis)


@dataclass(frozen=True)
class PotEstimate:
    tag: int
    x: float
    y: float
    facing: float
    sightings: int
    nearest: float
    """The closest read's distance, m (how good the best view was)."""


@dataclass
class TagSightings:
    mount: tuple[float, float, float]
    plate_offset: float
    max_distance: float = 1.2
    """Reads of tags farther than this are not used, m."""
    max_off_axis: float = 1.0
    """... nor reads more than this off head-on, rad (57 deg)."""
    by_tag: dict[int, list[PotSighting]] = field(default_factory=dict)

    def add(self, reads: tuple[TagRead, ...], robot: Pose2D) -> list[PotSighting]:
        """Take a frame's reads (robot: the map pose the frame was taken at); the ones used."""
        used = []
        for read in reads:
            if read.distance <= self.max_distance and read.off_axis <= self.max_off_axis:
                s = pot_from_tag(read, robot, self.mount, self.plate_offset)
                self.by_tag.setdefault(s.tag, []).append(s)
                used.append(s)
        return used

    def estimate(self, tag: int) -> PotEstimate | None:
        seen = self.by_tag.get(tag)
        if not seen:
            return None
        w = np.array([1.0 / max(s.distance, 0.1) ** 2 for s in seen])
        x = float(np.average([s.x for s in seen], weights=w))
        y = float(np.average([s.y for s in seen], weights=w))
        facing = math.atan2(float(np.average([math.sin(s.facing) for s in seen], weights=w)),
                            float(np.average([math.cos(s.facing) for s in seen], weights=w)))
        return PotEstimate(tag, x, y, facing, len(seen), min(s.distance for s in seen))

    def estimates(self) -> list[PotEstimate]:
        return [e for e in (self.estimate(t) for t in sorted(self.by_tag)) if e is not None]
