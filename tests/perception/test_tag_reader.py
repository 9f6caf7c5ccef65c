"""The AprilTag reader: ids and poses on sim renders at the approach pose (truth from the
sim's camera and plate geometry) and on plates warped into a frame at an exactly known pose,
black on white and navy on pale blue; the whitelist; garbage frames."""
from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from perception.config import TagConfig
from perception.evaluation import rotation_error
from perception.tag_reader import TagReader
from sim.apriltag import tag_image
from tests.perception.conftest import POTS

READ = TagReader()
K = TagConfig().camera.matrix()
PLATE = 0.14


def _rot(yaw: float, pitch: float = 0.0) -> np.ndarray:
    """Tag orientation in the camera (OpenCV axes): facing the camera, then turned by yaw about
    the camera's y axis and pitch about its x axis."""
    facing = np.diag([1.0, -1.0, -1.0])  # tag x right, y up, z towards the camera
    ry = cv2.Rodrigues(np.array([0.0, yaw, 0.0]))[0]
    rx = cv2.Rodrigues(np.array([pitch, 0.0, 0.0]))[0]
    return rx @ ry @ facing


def _warped(tag_id: int, rot: np.ndarray, pos: np.ndarray, paper=(255, 255, 255), ink=(0, 0, 0),
            background=(90, 95, 90)) -> np.ndarray:
    """A 640x480 BGR frame showing the plate of ``tag_id`` at pose (rot, pos) in the camera."""
    plate = cv2.cvtColor(tag_image(tag_id, pixels_per_module=40, paper=paper, ink=ink), cv2.COLOR_RGB2BGR)
    n = plate.shape[0]
    h = PLATE / 2
    corners3 = np.array([[-h, h, 0], [h, h, 0], [h, -h, 0], [-h, -h, 0]]) @ rot.T + pos
    uv = (corners3 @ K.T)[:, :2] / corners3[:, 2:]
    src = np.array([[-0.5, -0.5], [n - 0.5, -0.5], [n - 0.5, n - 0.5], [-0.5, n - 0.5]], np.float32)
    hmat = cv2.getPerspectiveTransform(src, uv.astype(np.float32))
    frame = np.empty((480, 640, 3), np.uint8)
    frame[:] = background
    return cv2.warpPerspective(plate, hmat, (640, 480), dst=frame, flags=cv2.INTER_AREA,
                               borderMode=cv2.BORDER_TRANSPARENT)


def _errors(read, rot, pos) -> tuple[float, float]:
    return float(np.linalg.norm(np.subtract(read.position, pos))), math.degrees(rotation_error(read.rotation, rot))


@pytest.mark.slow
@pytest.mark.parametrize("pot_id", list(POTS))
def test_sim_tag_at_the_approach_pose(scenes, pot_id):
    scene = scenes[pot_id]
    reads = READ(scene.front)
    assert scene.tag_in_view
    assert reads and reads[0].id == scene.tag
    dpos, drot = _errors(reads[0], scene.tag_rotation, scene.tag_position)
    assert dpos < 0.02 and drot < 3.0
    assert reads[0].off_axis < math.radians(3)  # head-on, and the reader says so
    assert reads[0].distance == pytest.approx(0.234, abs=0.01)  # 0.5 standoff - camera - pot - plate


@pytest.mark.slow
def test_off_axis_angle_follows_a_turned_approach(studio):
    """Turned 0.12 rad (the yaw tolerance) at the approach pose: still read, and the off-axis
    angle is the tag's view angle from the displaced camera (not zero, not the full turn)."""
    scene = studio.shoot("P03", noise=(0.0, 0.0, 0.12))
    (read, *_) = READ(scene.front)
    assert read.id == scene.tag
    dpos, drot = _errors(read, scene.tag_rotation, scene.tag_position)
    assert dpos < 0.02 and drot < 3.0
    true_normal = scene.tag_rotation[:, 2]
    true_off = math.acos(float(true_normal @ -scene.tag_position / np.linalg.norm(scene.tag_position)))
    assert read.off_axis == pytest.approx(true_off, abs=math.radians(1))
    assert 0.03 < read.off_axis < 0.12


@pytest.mark.parametrize("colours", ["black_on_white", "navy_on_blue"])
@pytest.mark.parametrize("yaw,pitch,pos", [
    (0.0, 0.0, (0.0, 0.0, 0.234)),
    (0.35, 0.0, (0.03, -0.01, 0.30)),
    (-0.25, 0.15, (-0.05, 0.02, 0.45)),
    (0.5, -0.1, (0.2, 0.05, 1.0)),
])
def test_printed_plates_at_known_poses(colours, yaw, pitch, pos):
    paper, ink = {"black_on_white": ((255, 255, 255), (0, 0, 0)),
                  "navy_on_blue": ((160, 195, 240), (20, 35, 110))}[colours]
    rot, pos = _rot(yaw, pitch), np.array(pos)
    reads = READ(_warped(11, rot, pos, paper, ink))
    assert [r.id for r in reads] == [11]
    dpos, drot = _errors(reads[0], rot, pos)
    assert dpos < 0.02 and drot < 3.0
    assert reads[0].off_axis == pytest.approx(
        math.acos(float(rot[:, 2] @ -pos / np.linalg.norm(pos))), abs=math.radians(3))


def test_ids_outside_the_whitelist_are_ignored():
    frame = _warped(100, _rot(0.0), np.array([0.0, 0.0, 0.3]))
    assert READ(frame) == ()
    assert [r.id for r in TagReader(TagConfig(whitelist=(100,)))(frame)] == [100]
    assert TagReader(TagConfig(whitelist=(0,)))(_warped(21, _rot(0.0), np.array([0.0, 0.0, 0.3]))) == ()


def test_nearest_tag_first():
    near = _warped(4, _rot(0.0), np.array([-0.12, 0.0, 0.5]))
    both = _warped(9, _rot(0.0), np.array([0.25, 0.0, 1.2]))
    frame = np.where(np.all(near == (90, 95, 90), axis=2)[..., None], both, near)
    assert [r.id for r in READ(frame)] == [4, 9]


def test_a_resized_frame_keeps_its_metric_pose():
    rot, pos = _rot(0.2), np.array([0.02, 0.0, 0.3])
    frame = cv2.resize(_warped(7, rot, pos), (1280, 960), interpolation=cv2.INTER_CUBIC)
    (read,) = READ(frame)
    dpos, drot = _errors(read, rot, pos)
    assert read.id == 7 and dpos < 0.02 and drot < 3.0


@pytest.mark.parametrize("garbage", [
    None, np.zeros((0, 0, 3), np.uint8), np.zeros((480, 640, 3), np.uint8),
    np.full((480, 640, 3), 255, np.uint8), np.zeros((480, 640, 3), np.float64),
    np.random.default_rng(3).integers(0, 256, (480, 640, 3), dtype=np.uint8),
    np.random.default_rng(4).integers(0, 256, (480, 640), dtype=np.uint8),
    np.zeros((3, 640), np.uint8), np.zeros((480, 640, 2), np.uint8), b"\xff\xd8garbage",
])
def test_empty_black_or_garbage_frames_read_nothing(garbage):
    assert READ(garbage) == ()
