"""E-stop, broken controllers and collisions on the full simulated robot."""
import numpy as np
import pytest

from hw.interfaces import Twist
from tests.fixtures import assemble, open_floor

pytestmark = pytest.mark.slow


def _drive(robot, until, twist=Twist(vx=0.3), source="manual", step=0.1):
    t = robot.scheduler.clock.now()
    while t < until - 1e-9:
        robot.mux.publish(source, twist, t)
        robot.scheduler.run_until(t + step)
        t = robot.scheduler.clock.now()


def test_button_press_zeroes_the_wheels_on_the_next_tick_and_stops_the_robot():
    sim, robot = assemble(open_floor(spawn=(1.0, 3.0, 0.0)))
    duties = []
    robot.scheduler.every("spy", 10.0, lambda t: duties.append((t, sim.drive.duties)), offset=0.0)
    _drive(robot, 2.0)
    robot.mux.publish("manual", Twist(vx=0.3), 2.0)
    robot.scheduler.run_until(2.03)
    assert np.abs(sim.drive.duties).max() > 0.05
    sim.faults.estop(True)  # pressed between ticks (at 2.03 s)
    _drive(robot, 4.0, twist=Twist(vx=0.5), source="joy")  # even the dead-man joystick
    after = [d for t, d in duties if t >= 2.1 - 1e-9]
    assert after and all(np.all(d == 0.0) for d in after)
    x = sim.truth().x
    _drive(robot, 5.0, twist=Twist(vx=0.5), source="joy")
    assert sim.truth().x == pytest.approx(x, abs=0.01)  # stopped
    assert robot.estop.events and robot.estop.events[-1][1] is True
    sim.faults.estop(False)
    _drive(robot, 6.0, twist=Twist(vx=0.3))
    assert np.abs(sim.drive.duties).max() > 0.05
    sim.close()


@pytest.mark.parametrize("controller", ["mirte_base_controller", "pid_wheels_controller"])
def test_broken_controller_at_boot_means_no_drive(controller):
    sim, robot = assemble(open_floor())
    sim.faults.controller_race([controller], "unconfigured")
    _drive(robot, 2.0)
    assert np.all(sim.drive.duties == 0.0)
    assert abs(sim.truth().x - 3.0) < 0.005


def test_a_placed_box_stops_the_chassis_while_the_wheels_spin_on():
    """The sim's contact physics, so with the collision monitor off (it would stop the wheels
    short of the box: the next test)."""
    sim, robot = assemble(open_floor(spawn=(2.0, 3.0, 0.0)), LUPIN_HW__COLLISION_MONITOR__ENABLED="false")
    sim.faults.place_box(3.0, 3.0, 0.3, 0.6)
    robot.scheduler.run_until(0.2)
    lx = sim.engine.data.site_xpos[sim.lidar._site][0]
    assert sim.hal.lidar.latest_scan().ranges[0] == pytest.approx(2.85 - lx, abs=0.04)
    _drive(robot, 8.0)
    truth_dx = sim.truth().x - 2.0
    odom_dx = robot.base.odometry.pose.x
    assert truth_dx < 0.85 - 0.15 + 0.02  # chassis front (~0.17 m) stopped at the box face
    assert odom_dx > truth_dx + 0.3  # the wheels kept turning: odometry ran away from truth


def test_the_collision_monitor_stops_the_robot_short_of_the_box():
    """Driven straight at a box, every tick, through the mux: the monitor zeroes the twist with
    the box inside the stop box, before the chassis touches it; the wheels do not spin on."""
    sim, robot = assemble(open_floor(spawn=(2.0, 3.0, 0.0)))
    sim.faults.place_box(3.0, 3.0, 0.3, 0.6)
    robot.scheduler.run_until(0.2)
    _drive(robot, 8.0)
    gap = 2.85 - sim.truth().x - 0.22  # box face to the footprint's front
    assert 0.0 < gap <= 0.08 + 0.03  # stopped in the stop box's 8 cm, not on the box
    assert not [n for n in sim.touching() if n.startswith("spare_box")]
    assert abs(robot.base.odometry.pose.x - (sim.truth().x - 2.0)) < 0.03  # no wheel spin against it
    assert robot.monitor.verdict.action == "stop"
