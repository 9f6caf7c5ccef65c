"""Several robots in one greenhouse (``sim.scene``): each on its own prefixed parts, each seeing
the others on its lidar and cameras, driven through its own HAL only; their contacts counted for
the judges; walkers stopping short of whichever robot is nearest. One robot alone keeps the
robot file's own names."""
from __future__ import annotations

import math
import re

import mujoco
import numpy as np
import pytest

from hw.config import HwConfig
from mission.jobs.contacts import robot_contact_log
from sim.backend import SimRobot
from sim.config import SimConfig
from sim.generate import generate_world
from sim.greenhouse import ROBOT_SETTINGS, ROBOT_XML, build_greenhouse
from sim.scene import SimScene
from sim.world import Pose2, Walker

pytestmark = pytest.mark.slow  # every test builds a MuJoCo model

LIDAR_AHEAD, PUCK_RADIUS = 0.115, 0.028
"""The lidar's place ahead of the base and its puck's radius, m (sim/models/mirte_master)."""


def fleet(spawns, walkers=()):
    """A generated 3 x 4 greenhouse with a robot at each of ``spawns`` ((x, y, yaw) each)."""
    world = generate_world(3, 4, 1).model_copy(update={
        "spawns": [Pose2(x=x, y=y, yaw=yaw) for x, y, yaw in spawns], "walkers": list(walkers)})
    world = world.model_copy(update={"spawn": world.spawns[0]})
    sc = SimConfig()
    scene = SimScene(world, sc, [f"r{k + 1}" for k in range(len(spawns))])
    robots = [SimRobot(world, sc, HwConfig(), scene=scene, name=name) for name in scene.names]
    return scene, robots


def ahead(robot: SimRobot, half_width: float = 0.1) -> float:
    """The nearest lidar return within ``half_width`` rad of straight ahead, m."""
    scan = robot.lidar.latest_scan()
    bearing = np.angle(np.exp(1j * np.asarray(scan.angles)))
    return float(np.min(np.where(np.abs(bearing) < half_width, scan.ranges, np.inf)))


def test_a_fleet_model_holds_each_robot_under_its_name_and_one_robot_keeps_the_file_names():
    world = generate_world(3, 4, 1, robots=2)
    names = lambda m: {mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, i) for i in range(m.ngeom)}  # noqa: E731
    one, two = build_greenhouse(world), build_greenhouse(world, robots=("r1/", "r2/"))
    assert "chassis" in names(one) and not any(n and n.startswith("r1/") for n in names(one))
    assert {"r1/chassis", "r2/chassis", "r1/led_strip", "r2/led_strip"} <= names(two) and "chassis" not in names(two)
    assert two.nu == 2 * one.nu and two.nsensor == 2 * one.nsensor and two.ncam == 2 * one.ncam - 1  # one overview
    assert two.opt.integrator == one.opt.integrator and two.opt.timestep == one.opt.timestep
    # the robot file's compiler and option lines, which a fleet's world states itself
    robot_file = ROBOT_XML.read_text()
    assert all(line.strip() in robot_file for line in ROBOT_SETTINGS.splitlines())


def test_each_robots_lidar_sees_the_other_at_its_range_and_not_without_it():
    scene, (r1, r2) = fleet([(1.0, 0.5, 0.0), (2.5, 0.5, math.pi)])
    r1.clock.wait_until(0.2)
    r2.clock.wait_until(0.2)
    facing = 1.5 - 2 * LIDAR_AHEAD - PUCK_RADIUS  # lidar to the other's lidar puck, the nearest part at its height
    assert ahead(r1) == pytest.approx(facing, abs=0.04)
    assert ahead(r2) == pytest.approx(facing, abs=0.04)
    alone, (only,) = fleet([(1.0, 0.5, 0.0)])
    only.clock.wait_until(0.2)
    assert ahead(only) > facing + 1.0  # the aisle ahead is open without r2
    scene.close()
    alone.close()


def test_each_robots_front_camera_sees_the_other():
    scene, (r1, r2) = fleet([(1.0, 0.5, 0.0), (1.8, 0.5, math.pi)])
    seen = r1.hal.cameras["front"].capture().astype(int)
    r2.place(1.8, 3.5, math.pi)  # r2 out of r1's view: the north aisle
    empty = r1.hal.cameras["front"].capture().astype(int)
    changed = np.any(np.abs(seen - empty) > 30, axis=2)
    assert changed.mean() > 0.05  # r2 fills part of r1's view
    scene.close()


def test_driving_r1_through_its_hal_moves_r1_and_not_r2():
    scene, (r1, r2) = fleet([(1.0, 0.5, 0.0), (1.0, 1.5, 0.0)])
    r1.hal.wheels.set_duties([0.5] * 4)
    r1.clock.wait_until(2.0)
    t = scene.truths()
    assert t["r1"].x > 1.3 and abs(t["r1"].y - 0.5) < 0.05
    assert math.hypot(t["r2"].x - 1.0, t["r2"].y - 1.5) < 0.005
    assert (r2.dock.x, r2.dock.y) == (1.0, 1.5) and r2._on_dock() and not r1._on_dock()  # each charges at its own dock
    assert max(map(abs, r2.hal.encoders.read_ticks())) <= 1 and min(r1.hal.encoders.read_ticks()) > 100
    assert scene.engine.warnings() == {}
    scene.close()


def test_robots_driven_into_each_other_touch_and_every_contact_is_counted():
    scene, (r1, r2) = fleet([(1.0, 0.5, 0.0), (2.0, 0.5, 0.0)])
    log = robot_contact_log(scene)
    r1.clock.wait_until(0.5)
    assert log.onsets == []
    r1.hal.wheels.set_duties([0.6] * 4)
    r1.clock.wait_until(3.0)
    assert [name for _, name in log.onsets] == ["r1-r2"]
    assert r1.touching() == ["r2/chassis"] and r2.touching() == ["r1/chassis"]
    r1.hal.wheels.set_duties([-0.6] * 4)
    r1.clock.wait_until(4.0)
    r1.hal.wheels.set_duties([0.6] * 4)
    r1.clock.wait_until(7.0)
    assert [name for _, name in log.onsets] == ["r1-r2", "r1-r2"]  # touching again is a second contact
    assert scene.engine.warnings() == {}
    scene.close()


def test_a_walker_stops_short_of_the_robot_in_its_way_not_only_of_the_first():
    walker = Walker(id="W1", path=[[6.0, 1.5], [0.3, 1.5]], speed=1.0)
    scene, (r1, r2) = fleet([(1.0, 0.5, 0.0), (1.0, 1.5, 0.0)], walkers=[walker])
    closest = math.inf
    for k in range(1, 81):
        r1.clock.wait_until(k * 0.1)
        closest = min(closest, scene.walkers.gap("W1", 1.0, 1.5))
    x, _, _ = scene.walkers.positions()["W1"]
    assert x > 1.4  # it stopped in front of r2 (and stays there while r2 stands in its way)
    assert 0.25 < closest - 0.22 < 0.35  # its KEEP_CLEAR of r2's body (ROBOT_RADIUS 0.22)
    scene.close()


def test_a_world_with_fewer_spawns_than_robots_is_refused():
    with pytest.raises(ValueError, match=re.escape("3 robots but the world")):
        SimScene(generate_world(3, 4, 1, robots=2), SimConfig(), ["r1", "r2", "r3"])
