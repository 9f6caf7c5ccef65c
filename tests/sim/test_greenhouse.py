"""The greenhouse model: names, groups, tags the front camera reads, blooms the HSV classes
separate (checked on real renders, since MuJoCo's lighting changes the rendered colour)."""
from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")

import math  # noqa: E402

import cv2  # noqa: E402
import mujoco  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from arm.presets import PRESETS  # noqa: E402
from mission.patrol.config import PatrolConfig  # noqa: E402
from sim.apriltag import tag_image, write_tag_png  # noqa: E402
from sim.config import GreenhouseGeometry  # noqa: E402
from sim.greenhouse import PARKED_Z, SPARE_BOXES, build_greenhouse, greenhouse_xml  # noqa: E402
from sim.world import Floor, Obstacle, Pose2, Pot, World  # noqa: E402

ARM = ("shoulder_pan", "shoulder_lift", "elbow", "wrist")
HOME = (0.04, -0.01, 0.01, -1.57)
INSPECT = PRESETS[PatrolConfig().inspect_pose]
SOUTH, NORTH = -math.pi / 2, math.pi / 2

# A small greenhouse with one pot of each kind. The red pot faces south, the others north, so
# both lighting sides of a row are covered.
WORLD = World(
    name="test",
    floor=Floor(x=4.0, y=3.0),
    spawn=Pose2(x=0.5, y=0.5, yaw=0.0),
    pots=[
        Pot(id="RED", x=1.0, y=1.0, facing=SOUTH, tag=3, flower="red", blooms=1),
        Pot(id="WHITE", x=2.0, y=2.0, facing=NORTH, tag=17, flower="white", blooms=2),
        Pot(id="PINK", x=3.0, y=2.0, facing=NORTH, tag=21, flower="pink", blooms=3),
        Pot(id="PEST", x=3.0, y=1.0, facing=SOUTH, tag=5, flower="red", blooms=2, bug=True),
        Pot(id="BARE", x=2.0, y=1.0, facing=SOUTH, flower="none"),
    ],
    obstacles=[Obstacle(x=3.6, y=2.7, sx=0.3, sy=0.3, yaw=0.3, h=0.8)],
)


# --- the flower detector's HSV classes (reference/upstream.md; OpenCV H 0..179) ------------------
def hsv_blobs(rgb: np.ndarray) -> dict[str, list[int]]:
    """Areas of the blobs of each class, as the original sim detector found them: class mask,
    5 px morphological opening, connected components, blobs below 150 px dropped."""
    hsv = cv2.cvtColor(np.ascontiguousarray(rgb), cv2.COLOR_RGB2HSV)
    h, s, v = (hsv[..., i].astype(int) for i in range(3))
    masks = {
        "red": ((h >= 150) | (h <= 8)) & (s >= 150) & (v >= 70),
        "white": (s <= 38) & (v >= 140),
        "pink": ((h >= 140) | (h <= 14)) & (s >= 40) & (s <= 135) & (v >= 140),
        "bug": v < 50,
    }
    kernel = np.ones((5, 5), np.uint8)
    out = {}
    for name, mask in masks.items():
        opened = cv2.morphologyEx(mask.astype(np.uint8), cv2.MORPH_OPEN, kernel)
        _, _, stats, _ = cv2.connectedComponentsWithStats(opened)
        out[name] = sorted((int(a) for a in stats[1:, cv2.CC_STAT_AREA] if a >= 150), reverse=True)
    return out


def expected_classes(pot: Pot) -> set[str]:
    return ({pot.flower} if pot.flower != "none" else set()) | ({"bug"} if pot.bug else set())


# --- fixtures ------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def sim():
    model = build_greenhouse(WORLD)
    data = mujoco.MjData(model)
    renderer = mujoco.Renderer(model, 480, 640)
    yield model, data, renderer
    renderer.close()


def pot(pot_id: str) -> Pot:
    return next(p for p in WORLD.pots if p.id == pot_id)


def approach_pose(p: Pot) -> tuple[float, float, float]:
    """0.5 m out from the pot centre along its facing, looking back at it."""
    return p.x + 0.5 * math.cos(p.facing), p.y + 0.5 * math.sin(p.facing), p.facing + math.pi


def place(model, data, pose, arm=HOME, settle: float = 0.0) -> None:
    for joint, q in zip(("base_x", "base_y", "base_yaw"), pose):
        data.qpos[model.joint(joint).qposadr[0]] = q
    for joint, q in zip(ARM, arm):
        data.qpos[model.joint(joint).qposadr[0]] = q
        data.ctrl[model.actuator(joint).id] = q
    data.qvel[:] = 0.0
    mujoco.mj_forward(model, data)
    if settle:  # let the servos sag under gravity, as they do on patrol
        mujoco.mj_step(model, data, nstep=round(settle / model.opt.timestep))


def render(renderer, data, camera) -> np.ndarray:
    renderer.update_scene(data, camera=camera)
    return renderer.render()


def save(name: str, rgb: np.ndarray) -> None:
    """Keep the picture for people to look at (best effort, never fails a test)."""
    try:
        os.makedirs("/tmp/lupin_renders", exist_ok=True)
        cv2.imwrite(f"/tmp/lupin_renders/{name}.png", cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))
    except OSError:  # pragma: no cover
        pass


DETECTOR = cv2.aruco.ArucoDetector(
    cv2.aruco.getPredefinedDictionary(cv2.aruco.DICT_APRILTAG_36h11), cv2.aruco.DetectorParameters()
)


def read_tags(rgb: np.ndarray) -> list[tuple[int, float]]:
    """(id, area in px) of every tag found, biggest first."""
    corners, ids, _ = DETECTOR.detectMarkers(cv2.cvtColor(rgb, cv2.COLOR_RGB2GRAY))
    if ids is None:
        return []
    found = [(int(i), float(cv2.contourArea(c.reshape(-1, 2)))) for i, c in zip(ids.ravel(), corners)]
    return sorted(found, key=lambda f: -f[1])


# --- tags --------------------------------------------------------------------------------------
@pytest.mark.parametrize("tag_id", [0, 1, 21, 586])
def test_tag_image_is_the_36h11_marker_in_its_margin(tag_id):
    image = tag_image(tag_id, pixels_per_module=10)
    assert image.shape == (112, 112, 3)  # 8 modules + 1.6 modules of margin on each side
    assert read_tags(image)[0][0] == tag_id
    margin = image[:16]
    assert np.all(margin == margin[0, 0])  # quiet zone: card colour only


def test_tag_image_rejects_ids_outside_the_family():
    with pytest.raises(ValueError):
        tag_image(587)


@pytest.mark.slow
def test_greenhouse_xml_writes_one_texture_per_tag(tmp_path):
    xml = greenhouse_xml(WORLD, GreenhouseGeometry(), tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tag_17.png", "tag_21.png", "tag_3.png", "tag_5.png"]
    assert str(tmp_path / "tag_3.png") in xml
    assert read_tags(cv2.imread(str(tmp_path / "tag_3.png")))[0][0] == 3
    assert write_tag_png(9, tmp_path / "x.png").exists()
    mujoco.MjModel.from_xml_string(xml)  # compiles from the text alone


@pytest.mark.slow
@pytest.mark.parametrize("pot_id", ["RED", "WHITE", "PINK"])
def test_front_camera_reads_the_tag_at_the_approach_pose(sim, pot_id):
    model, data, renderer = sim
    p = pot(pot_id)
    place(model, data, approach_pose(p))
    rgb = render(renderer, data, "front_camera")
    if pot_id == "RED":
        save("front_camera_approach", rgb)
    tags = read_tags(rgb)
    assert tags, "no tag found"
    assert tags[0][0] == p.tag  # the pot's own tag is the biggest in view
    assert tags[0][1] > 0.1 * rgb.shape[0] * rgb.shape[1]


# --- blooms ------------------------------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("pot_id", ["RED", "WHITE", "PINK", "PEST", "BARE"])
def test_blooms_from_above_fall_in_their_class_only(sim, pot_id):
    """A free camera straight above the pot: the bloom colours land in their own HSV class and
    in no other; only the pest is dark."""
    model, data, renderer = sim
    p = pot(pot_id)
    place(model, data, (WORLD.spawn.x, WORLD.spawn.y, WORLD.spawn.yaw))
    cam = mujoco.MjvCamera()
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE
    cam.lookat[:] = (p.x, p.y, 0.3)
    cam.distance, cam.azimuth, cam.elevation = 0.5, 90.0, -90.0
    rgb = render(renderer, data, cam)
    blobs = hsv_blobs(rgb)
    found = {name for name, areas in blobs.items() if areas}
    assert found == expected_classes(p), blobs
    if p.flower != "none":
        assert len(blobs[p.flower]) == p.blooms, blobs


@pytest.mark.slow
@pytest.mark.parametrize("pot_id", ["RED", "WHITE", "PINK", "PEST", "BARE"])
def test_wrist_camera_at_inspect_sees_the_blooms(sim, pot_id):
    """The patrol's view: at the approach pose, arm at its inspect preset (sagged under gravity), the
    wrist camera frames the pot from above; its blooms, and nothing else, are classified."""
    model, data, renderer = sim
    p = pot(pot_id)
    place(model, data, approach_pose(p), arm=INSPECT, settle=1.0)
    rgb = render(renderer, data, "wrist_camera")
    if pot_id in ("PINK", "PEST"):
        save(f"wrist_camera_inspect_{pot_id.lower()}", rgb)
    blobs = hsv_blobs(rgb)
    found = {name for name, areas in blobs.items() if areas}
    assert found == expected_classes(p), blobs
    if p.flower != "none":
        assert len(blobs[p.flower]) == p.blooms and min(blobs[p.flower]) > 2000, blobs


# --- the rest of the world ------------------------------------------------------------------------
@pytest.mark.slow
def test_overview_camera_shows_the_whole_floor(sim):
    model, data, renderer = sim
    place(model, data, (WORLD.spawn.x, WORLD.spawn.y, WORLD.spawn.yaw))
    width, height = 640, round(640 * WORLD.floor.y / WORLD.floor.x)
    with mujoco.Renderer(model, height, width) as overview:
        rgb = render(overview, data, "overview")
    save("overview", rgb)
    assert rgb.std() > 10
    # Orthographic, north up: a world point maps linearly to a pixel.
    scale = height / (1.06 * WORLD.floor.y)

    def pixel(x, y):
        return (round(height / 2 - (y - WORLD.floor.y / 2) * scale),
                round(width / 2 + (x - WORLD.floor.x / 2) * scale))

    for p in WORLD.pots:
        r, c = pixel(p.x, p.y)
        zoom = np.kron(rgb[r - 10:r + 11, c - 10:c + 11], np.ones((4, 4, 1), np.uint8))  # blooms ~10 px
        patch = hsv_blobs(np.ascontiguousarray(zoom))
        assert p.flower == "none" or patch[p.flower], (p.id, patch)
    corner = rgb[pixel(0.05, 0.05)]  # inside the floor, near the south-west corner
    outside = rgb[pixel(-0.05, -0.05)]  # on the walls
    assert not np.array_equal(corner, outside)


@pytest.mark.slow
def test_names_groups_and_collision_bits(sim):
    model, _, _ = sim
    assert model.geom("tag_RED").id > 0
    assert model.geom("pot_RED_geom").bodyid[0] == model.geom("tag_RED").bodyid[0] == 0  # static: the world's
    with pytest.raises(KeyError):
        model.geom("tag_BARE")  # no tag, no plate
    pot_geom, tag_geom = model.geom("pot_RED_geom"), model.geom("tag_RED")
    assert pot_geom.group[0] == 0 and pot_geom.contype[0] & model.geom("chassis").conaffinity[0]
    assert tag_geom.group[0] == 2 and tag_geom.contype[0] == 0 and tag_geom.conaffinity[0] == 0
    assert model.geom("pot_RED_bloom_0").group[0] == 2
    assert model.geom("obstacle_0").group[0] == 0
    for wall in ("wall_south", "wall_north", "wall_west", "wall_east"):
        assert model.geom(wall).group[0] == 0
    # The chassis meets world statics but never the floor.
    chassis, floor = model.geom("chassis"), model.geom("floor")
    assert not (chassis.contype[0] & floor.conaffinity[0] or floor.contype[0] & chassis.conaffinity[0])
    # Spare boxes: mocap bodies parked under the floor, one colliding box geom each.
    data = mujoco.MjData(model)
    for k in range(SPARE_BOXES):
        body = model.body(f"spare_box_{k}")
        assert body.mocapid[0] >= 0
        assert data.mocap_pos[body.mocapid[0]][2] == PARKED_Z
        geom = model.geom(f"spare_box_{k}_geom")
        assert geom.bodyid[0] == body.id and geom.group[0] == 0 and geom.contype[0] & chassis.conaffinity[0]
    # The plate centre is at the front camera's optical height, on the facing side.
    mujoco.mj_forward(model, data)
    p = pot("RED")
    plate = data.geom_xpos[model.geom("tag_RED").id]
    assert plate[2] == pytest.approx(GreenhouseGeometry().plate_height)
    outward = (plate[0] - p.x, plate[1] - p.y)
    assert math.atan2(outward[1], outward[0]) == pytest.approx(p.facing, abs=1e-6)
    place(model, data, approach_pose(p))
    assert data.cam_xpos[model.camera("front_camera").id][2] == pytest.approx(plate[2])


@pytest.mark.slow
def test_robot_contract_names():
    """The names the backend relies on (sim/backend.py and friends)."""
    model = build_greenhouse(WORLD)
    joints = [model.joint(i).name for i in range(model.njnt)]
    assert joints[:3] == ["base_x", "base_y", "base_yaw"]
    for name in ("wheel_front_left", "wheel_front_right", "wheel_rear_left", "wheel_rear_right",
                 "drive_vx", "drive_vy", "drive_wz", *ARM, "gripper"):
        assert model.actuator(name).id >= 0
    for name in ("base_site", "lidar_site", "imu_site"):
        assert model.site(name).id >= 0
    for name in ("imu_accel", "imu_gyro"):
        assert model.sensor(name).id >= 0
    for name in ("front_camera", "wrist_camera", "overview"):
        assert model.camera(name).id >= 0
    assert model.body("lidar").id >= 0 and model.geom("led_strip").id >= 0
    assert model.jnt_range[model.joint("gripper").id] == pytest.approx((-0.20, 0.25))
    assert model.actuator("drive_vx").gainprm[0] == 300 and model.actuator("drive_wz").gainprm[0] == 8
