"""The simulated devices behind the HAL: lidar, IMU, battery, cameras, servos, LEDs."""

import numpy as np
import pytest

from hw.interfaces import DeviceError, Twist
from hw.leds import PALETTE
from tests.fixtures import assemble, open_floor

pytestmark = pytest.mark.slow

FLOOR = (8.0, 6.0)


@pytest.fixture
def rig():
    """The sim devices with the runtime's services, minus the arm controller: these tests write
    the servo bus raw, which the controller (rightly) overwrites."""
    sim, robot = assemble(open_floor(spawn=(3.0, 3.0, 0.0), size=FLOOR))
    robot.scheduler.cancel("arm")
    yield sim, robot
    sim.close()


def test_lidar_measures_the_walls(rig):
    sim, robot = rig
    robot.scheduler.run_until(0.2)
    scan = sim.hal.lidar.latest_scan()
    assert scan.ranges.shape == (500,) and scan.ranges.dtype == np.float32
    lx, ly = sim.engine.data.site_xpos[sim.lidar._site][:2]
    east = scan.ranges[0]
    north = scan.ranges[125]  # 90 deg, counter-clockwise (REP-103)
    west = scan.ranges[250]
    assert east == pytest.approx(FLOOR[0] - lx, abs=0.04)
    assert north == pytest.approx(FLOOR[1] - ly, abs=0.04)
    assert west == pytest.approx(lx, abs=0.04)
    assert np.isfinite(scan.ranges).sum() > 450  # closed room: nearly every ray returns


def test_lidar_revolutions_at_10hz_and_dropout(rig):
    sim, robot = rig
    robot.scheduler.run_until(0.15)
    a = sim.hal.lidar.latest_scan()
    assert sim.hal.lidar.latest_scan() is a  # same revolution, same object
    robot.scheduler.run_until(0.25)
    b = sim.hal.lidar.latest_scan()
    assert b.stamp == pytest.approx(a.stamp + 0.1)
    assert not np.array_equal(a.ranges, b.ranges)  # fresh noise per revolution
    sim.faults.lidar_dropout(1.0)
    robot.scheduler.run_until(1.0)
    assert sim.hal.lidar.latest_scan() is None
    robot.scheduler.run_until(1.3)
    assert sim.hal.lidar.latest_scan() is not None


def test_imu_at_rest_and_turning(rig):
    sim, robot = rig
    robot.scheduler.run_until(0.5)
    rest = sim.hal.imu.read()
    assert rest.accel[2] == pytest.approx(9.81, abs=0.15)
    assert abs(rest.gyro[2]) < 0.02
    for t in np.arange(0.5, 3.0, 0.1):
        robot.mux.publish("manual", Twist(wz=0.6), t)
        robot.scheduler.run_until(t + 0.1)
    assert sim.hal.imu.read().gyro[2] == pytest.approx(0.6, abs=0.1)


def test_battery_sags_under_load_and_can_be_forced(rig):
    sim, robot = rig
    robot.scheduler.run_until(0.5)
    idle = sim.hal.power.read()
    assert 11.1 < idle.voltage <= 12.6
    for t in np.arange(0.5, 5.0, 0.1):
        robot.mux.publish("manual", Twist(wz=1.5), t)
        robot.scheduler.run_until(t + 0.1)
    busy = sim.hal.power.read()
    assert busy.current > idle.current + 0.5
    assert busy.voltage < idle.voltage - 0.05
    sim.faults.battery(11.0)
    assert sim.hal.power.read().voltage == 11.0
    sim.faults.battery(None)
    assert sim.hal.power.read().voltage > 11.0


def test_cameras_render_bgr_frames_on_request(rig):
    sim, _ = rig
    for name in ("front", "wrist"):
        frame = sim.hal.cameras[name].capture()
        assert frame.shape == (480, 640, 3) and frame.dtype == np.uint8
        assert frame.std() > 3.0  # not a blank image
    rgb = sim.renderers.render("front_camera", 640, 480)
    assert np.array_equal(sim.hal.cameras["front"].capture(), rgb[:, :, ::-1])


def _servo_rig(rig):
    sim, robot = rig
    bus = sim.hal.servos
    calib = robot.config.hw.servos.joints["shoulder_pan"]
    return sim, robot, bus, calib


def test_servo_move_follows_the_hiwonder_ramp(rig):
    sim, robot, bus, calib = _servo_rig(rig)
    robot.scheduler.run_until(0.5)
    start = bus.read_position(calib.id)
    target = start + 120  # +28.8 deg
    bus.move(calib.id, target, 1000)
    robot.scheduler.run_until(1.0)
    half = bus.read_position(calib.id)
    assert start + 30 < half < start + 90  # moving, roughly halfway along the ramp
    robot.scheduler.run_until(2.5)
    assert abs(bus.read_position(calib.id) - target) <= 3
    status = bus.read_status(calib.id)
    assert status.loaded and 11000 < status.vin_mv < 12700


def test_servo_offsets_and_unknown_ids(rig):
    sim, robot, bus, calib = _servo_rig(rig)
    robot.scheduler.run_until(0.3)
    before = np.mean([bus.read_position(calib.id) for _ in range(20)])
    bus.adjust_offset(calib.id, 10)
    assert bus.read_offset(calib.id) == 10
    after = np.mean([bus.read_position(calib.id) for _ in range(20)])
    assert after == pytest.approx(before - 10, abs=1.0)
    with pytest.raises(DeviceError):
        bus.read_position(42)


def test_gravity_sags_an_unloaded_shoulder_and_a_latched_servo_ignores_moves(rig):
    sim, robot = rig
    lift = robot.config.hw.servos.joints["shoulder_lift"].id
    sim.servos.place({"shoulder_pan": 0.0, "shoulder_lift": -0.6, "elbow": 0.2, "wrist": 0.0})
    robot.scheduler.run_until(1.0)
    held = sim.servos.joint_position("shoulder_lift")
    assert held == pytest.approx(-0.6, abs=0.1)  # holds against gravity, with a little sag
    sim.faults.servo_stall("shoulder_lift")
    assert not sim.hal.servos.read_status(lift).loaded
    robot.scheduler.run_until(3.0)
    assert abs(sim.servos.joint_position("shoulder_lift") - held) > 0.15  # went limp and fell
    sagged = sim.servos.joint_position("shoulder_lift")
    sim.hal.servos.set_load(lift, True)
    sim.faults.servo_stall("elbow", mode="latch")
    elbow = robot.config.hw.servos.joints["elbow"].id
    before = sim.servos.joint_position("elbow")
    sim.hal.servos.move(elbow, sim.hal.servos.read_position(elbow) + 150, 200)
    robot.scheduler.run_until(4.0)
    assert sim.servos.joint_position("elbow") == pytest.approx(before, abs=0.05)
    assert sim.servos.joint_position("shoulder_lift") == pytest.approx(sagged, abs=0.1)  # re-loaded: holds, no jump


@pytest.mark.parametrize("order, matches", [("BRG", True), ("GRB", False)])
def test_led_strip_shows_the_status_colour_only_with_the_right_order(order, matches):
    sim, robot = assemble(open_floor(), LUPIN_HW__LEDS__COLOR_ORDER=order)
    robot.scheduler.run_until(0.5)
    shown = sim.leds.pixel(0)
    assert (shown == PALETTE["standby"]) is matches
    rgba = sim.engine.model.geom_rgba[sim.leds._geom]
    assert np.allclose(rgba[:3] * 255, shown, atol=1)
    sim.close()


def test_lidar_sees_the_robots_own_arm(rig):
    """Like the original sim: the arm's returns are in the scan, closer than the 0.25 m that
    consumers filter (seed), and they move when the arm moves."""
    from arm.presets import preset

    sim, robot = rig
    sim.servos.place(preset("home"))
    robot.scheduler.run_until(0.2)
    home = sim.lidar.cast()
    sim.servos.place(preset("tuck"))
    sim.engine.forward()
    tuck = sim.lidar.cast()
    assert (home < 0.25).sum() > 5
    front = np.abs(np.degrees(np.arctan2(np.sin(sim.lidar.angles), np.cos(sim.lidar.angles)))) < 30
    assert (tuck[front] < 0.25).sum() > (home[front] < 0.25).sum()  # tucked arm crosses the front


def test_the_robots_cameras_draw_only_what_lies_within_their_draw_distance():
    """At the 4 m draw distance a crate 2 m ahead is drawn; one 11 m ahead, and the hall's end
    wall 13 m ahead, are left out of the front frame, and nothing else changes; the model is as
    it was."""
    from sim.world import Floor, Obstacle, Pose2, World

    world = World(name="long", floor=Floor(x=14.0, y=4.0), spawn=Pose2(x=1.0, y=2.0, yaw=0.0), pots=[],
                  obstacles=[Obstacle(x=3.0, y=1.6, sx=0.3, sy=0.3, h=0.8), Obstacle(x=12.0, y=2.3, sx=0.6, sy=0.6, h=1.6)])
    sim, _ = assemble(world)
    try:
        rgba = sim.engine.model.geom_rgba.copy()
        limited = sim.hal.cameras["front"].capture().astype(int)
        everything = sim.renderers.render("front_camera", 640, 480)[:, :, ::-1].astype(int)
        assert sim.hal.cameras["front"].draw_distance == 4.0
        assert np.array_equal(sim.engine.model.geom_rgba, rgba)
        changed = np.abs(limited - everything).sum(axis=2) > 30
        rows, cols = np.nonzero(changed)
        assert changed.sum() > 2000  # the far end of the hall is missing from the limited frame ...
        assert rows.max() < 250 and 200 < cols.min() and cols.max() < 480  # ... and only there, at the horizon
        assert np.array_equal(limited[100:250, 400:480], everything[100:250, 400:480])  # the near crate
        near = sim.renderers.render("front_camera", 640, 480, draw_distance=1.0)[:, :, ::-1].astype(int)
        assert (np.abs(near - limited)[100:250, 400:480].sum(axis=2) > 30).mean() > 0.5  # at 1 m the near crate goes
        assert np.array_equal(near[400:], limited[400:])  # the floor never does (a plane has no bounding sphere)
    finally:
        sim.close()
