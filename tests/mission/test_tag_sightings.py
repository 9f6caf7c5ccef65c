"""A pot from its tag: centre behind the tag along its normal, facing the normal; reads fused
with close ones weighing most, far and edge-on ones left out."""
from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from hw.odometry import Pose2D
from mission.patrol.tag_sightings import TagSightings, pot_from_tag
from perception.detections import TagRead

MOUNT = (0.16, 0.0, 0.15)


def read(tag: int, right: float, forward: float, turn: float = 0.0) -> TagRead:
    """A tag ``forward`` ahead of the camera and ``right`` of its axis, facing back at the
    camera turned ``turn`` rad about the vertical (positive: its normal swings to the robot's left)."""
    # tag frame in the camera: x right, y up, z out of the face; head-on it faces -z_cam
    head_on = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]])
    c, s = math.cos(turn), math.sin(turn)
    about_cam_y = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])  # camera y is down
    rvec = cv2.Rodrigues(about_cam_y @ head_on)[0].ravel()
    position = (right, 0.0, forward)
    normal = (about_cam_y @ head_on)[:, 2]
    off = math.acos(float(np.dot(normal, -np.array(position)) / np.linalg.norm(position)))
    return TagRead(tag, ((0, 0),) * 4, position, tuple(rvec), off, 0.1)


def test_a_head_on_read_puts_the_pot_behind_its_tag_facing_the_robot():
    s = pot_from_tag(read(7, 0.0, 0.3), Pose2D(1.0, 2.0, math.pi / 2), MOUNT, 0.104)
    assert s.tag == 7 and s.x == pytest.approx(1.0) and s.y == pytest.approx(2.0 + 0.16 + 0.3 + 0.104)
    assert s.facing == pytest.approx(-math.pi / 2)  # back along the robot's line of sight


def test_a_turned_tag_gives_its_facing_and_the_centre_behind_it():
    # robot at the origin facing +x; tag 0.5 m ahead, 0.1 m right (y = -0.1), normal swung 0.3 rad
    s = pot_from_tag(read(1, 0.1, 0.5, turn=0.3), Pose2D(), MOUNT, 0.1)
    assert s.facing == pytest.approx(math.pi - 0.3)  # back at the robot, swung 0.3 rad to its left
    assert s.x == pytest.approx(0.66 - 0.1 * math.cos(s.facing)) and s.y == pytest.approx(-0.1 - 0.1 * math.sin(s.facing))


def test_fusion_weighs_close_reads_and_drops_far_and_edge_on_ones():
    sightings = TagSightings(MOUNT, 0.104)
    robot = Pose2D(0.0, 0.0, 0.0)
    used = sightings.add((read(3, 0.0, 0.3), read(3, 0.02, 1.1), read(4, 0.0, 1.6), read(5, 0.3, 0.3, turn=-1.4)), robot)
    assert [u.tag for u in used] == [3, 3]  # 4 too far, 5 edge-on
    est = sightings.estimate(3)
    assert est.sightings == 2 and est.nearest == pytest.approx(0.3)
    near = pot_from_tag(read(3, 0.0, 0.3), robot, MOUNT, 0.104)
    assert abs(est.y - near.y) < 0.002  # the 1.1 m read (2 cm off) weighs 13x less
    assert [e.tag for e in sightings.estimates()] == [3] and sightings.estimate(4) is None
