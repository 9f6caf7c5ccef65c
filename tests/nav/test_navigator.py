"""The navigator's state machine on fakes: recovery, planning failures, timeout, cancel, e-stop.
(The whole stack in the simulator is test_navigation_sim.py.)"""
from __future__ import annotations

import numpy as np

from hw.interfaces import ZERO_TWIST, LidarScan, Twist
from hw.odometry import Pose2D
from nav.config import NavConfig
from nav.localisation import OdometryOnly
from nav.mppi.controller import NoValidControl
from nav.navigator import Navigator, Sources, State
from nav.planner import PlanningError
from tests.nav.builders import dummy_costmap, straight_path


class FakeCostmap:
    def __init__(self):
        self.grid = dummy_costmap(60, 60, origin=(-1.5, -1.5))
        self.clears = 0
        self.updates = 0

    def update(self, scan, sensor_pose, robot_xy):
        self.updates += 1

    def clear(self):
        self.clears += 1

    def cover(self, x0, y0, x1, y1):
        self.covered = (x0, y0, x1, y1)


class FakePlanner:
    def __init__(self, fail=False):
        self.fail, self.calls = fail, 0

    def plan(self, grid, start, goal):
        self.calls += 1
        if self.fail:
            raise PlanningError("no path to the goal")
        return straight_path(start, goal)


class FakeController:
    def __init__(self, fail=False):
        self.fail, self.resets = fail, 0

    def compute(self, pose, velocity, path, goal, grid):
        if self.fail:
            raise NoValidControl("every trajectory collides")
        return (0.3, 0.0, 0.0)

    def reset(self):
        self.resets += 1


class Rig:
    def __init__(self, planner=None, controller=None):
        self.pose, self.twist, self.estopped = Pose2D(), ZERO_TWIST, False
        self.published: list[tuple[float, Twist]] = []
        self.t = 0.0
        self.scans = True
        """False: the lidar stops delivering (the last scan ages)."""
        self.last_scan = LidarScan(0.0, np.zeros(1, np.float32), np.full(1, np.inf, np.float32))
        self.held = False
        """True: the collision monitor holds the base (someone in the way)."""
        io = Sources(lambda: self.pose, lambda: self.twist, self.scan,
                     lambda t, now: self.published.append((now, t)), lambda: self.estopped, lambda: self.held)
        self.local, self.glob = FakeCostmap(), FakeCostmap()
        self.planner = planner or FakePlanner()
        self.controller = controller or FakeController()
        self.nav = Navigator(NavConfig(), io, OdometryOnly(), self.local, self.glob, self.planner, self.controller)

    def scan(self):
        if self.scans:
            self.last_scan = LidarScan(self.t, self.last_scan.angles, self.last_scan.ranges)
        return self.last_scan

    def tick(self, t):
        self.t = t
        self.nav.tick_control(t)

    def run(self, until, t0=0.0):
        t = t0
        while t <= until and self.nav.active:
            self.t = t
            self.nav.tick_control(t)
            if round(t * 20) % 20 == 0:
                self.nav.tick_planner(t)
            t = round(t + 0.05, 6)
        return t


def test_recovery_clears_the_local_costmap_backs_off_and_gives_up_after_the_bound():
    rig = Rig(controller=FakeController(fail=True))
    rig.nav.navigate_to(Pose2D(2.0, 0.0, 0.0), 0.0, timeout=60.0)
    rig.run(30.0)
    assert rig.nav.state is State.FAILED and "no valid control after 3 recoveries" in rig.nav.reason
    assert rig.local.clears == 3
    backing = [t for _, t in rig.published if t.vx < 0]
    assert backing and all(t.vx >= -0.1 - 1e-9 for t in backing)  # slow back-off, open space behind
    assert rig.published[-1][1] == ZERO_TWIST


def test_repeated_planning_failures_fail_with_the_reason_and_hold_still():
    rig = Rig(planner=FakePlanner(fail=True))
    rig.nav.navigate_to(Pose2D(2.0, 0.0, 0.0), 0.0, timeout=60.0)
    t = rig.run(30.0)
    assert rig.nav.state is State.FAILED and rig.nav.reason == "no path: no path to the goal"
    assert t < 5.0  # three failures at the 1 Hz replan, not the 60 s timeout
    assert all(tw == ZERO_TWIST for _, tw in rig.published)


def test_a_lidar_dropout_holds_the_goal_still_without_spending_its_time():
    rig = Rig()
    rig.nav.navigate_to(Pose2D(5.0, 0.0, 0.0), 0.0, timeout=4.0)
    rig.run(1.0)
    assert rig.published[-1][1].vx > 0
    rig.scans = False
    end = rig.run(13.0, t0=1.05)  # 12 s blind: longer than the timeout and the progress window
    assert rig.nav.active and rig.nav.blind and end > 13.0
    held = [tw for t, tw in rig.published if t > 1.0 + NavConfig().navigator.scan_timeout + 0.05]
    assert held and all(tw == ZERO_TWIST for tw in held)
    rig.scans = True
    rig.run(13.5, t0=13.05)
    assert rig.nav.active and not rig.nav.blind and rig.published[-1][1].vx > 0
    rig.run(30.0, t0=13.55)  # the deadline was pushed by the blind time, not dropped
    assert rig.nav.state is State.FAILED and rig.nav.reason.startswith("timeout")


def test_a_person_in_the_way_stops_the_goals_clocks_for_the_bounded_wait_then_it_fails_blocked():
    """The base never moves while held (the fake odometry stays put): without the wait the goal
    would fail 'no progress' after 10 s; with it, it waits 15 s, then fails ``blocked``."""
    rig = Rig()
    rig.nav.navigate_to(Pose2D(5.0, 0.0, 0.0), 0.0, timeout=12.0)
    rig.held = True
    end = rig.run(40.0)
    wait = NavConfig().navigator.blocked_wait
    assert rig.nav.state is State.FAILED and rig.nav.reason.startswith("blocked")
    assert wait <= end <= wait + 0.2
    assert rig.planner.calls >= wait - 1  # replanning (another way round) all along


def test_a_short_wait_for_a_person_costs_the_goal_nothing():
    rig = Rig()
    rig.nav.navigate_to(Pose2D(5.0, 0.0, 0.0), 0.0, timeout=12.0)
    rig.held = True
    rig.run(8.0)
    rig.held = False
    rig.run(17.5, t0=8.05)  # 8 s held: past the 12 s deadline, which moved by 8 s, and no progress failure
    assert rig.nav.active, rig.nav.reason
    end = rig.run(25.0, t0=17.55)  # the fake base never moves: the progress window restarted at the release
    assert rig.nav.state is State.FAILED and rig.nav.reason.startswith("no progress") and 18.0 <= end <= 18.3


def test_holds_that_come_and_go_add_up_and_do_not_renew_the_progress_check():
    """Stop-and-go (held one tick in two) with the base never getting anywhere: the progress
    check counts only the free half, so 10 s of it fail the goal at ~20 s; and blocked_wait
    counts the held half."""
    rig = Rig()
    rig.nav.navigate_to(Pose2D(5.0, 0.0, 0.0), 0.0, timeout=120.0)
    t = 0.0
    while rig.nav.active and t < 60.0:
        rig.held = round(t * 20) % 2 == 0
        rig.tick(t)
        t = round(t + 0.05, 6)
    assert rig.nav.state is State.FAILED and rig.nav.reason.startswith("no progress"), rig.nav.reason
    assert 19.5 <= t <= 21.0
    assert 9.5 <= rig.nav.held_for <= 10.5


def test_no_back_off_while_someone_is_close():
    rig = Rig(controller=FakeController(fail=True))
    rig.nav.navigate_to(Pose2D(2.0, 0.0, 0.0), 0.0, timeout=60.0)
    rig.held = True
    rig.run(10.0)
    assert rig.nav.active and rig.local.clears == 0
    assert all(tw == ZERO_TWIST for _, tw in rig.published)


def test_timeout_cancel_and_estop_all_zero_the_auto_source():
    rig = Rig()
    rig.nav.navigate_to(Pose2D(5.0, 0.0, 0.0), 0.0, timeout=2.0)
    rig.run(10.0)
    assert rig.nav.state is State.FAILED and rig.nav.reason.startswith("timeout")
    assert rig.published[-1][1] == ZERO_TWIST

    rig.nav.navigate_to(Pose2D(5.0, 0.0, 0.0), 10.0)
    rig.tick(10.05)
    assert rig.published[-1][1].vx > 0
    rig.nav.cancel(10.07)
    assert rig.nav.state is State.CANCELED and rig.published[-1] == (10.07, ZERO_TWIST)

    rig.nav.navigate_to(Pose2D(5.0, 0.0, 0.0), 11.0)
    rig.estopped = True
    rig.tick(11.05)
    assert rig.nav.state is State.CANCELED and rig.nav.reason == "e-stop engaged"
    rig.estopped = False
    rig.tick(11.10)
    assert rig.nav.state is State.CANCELED  # a release does not restart the goal


def test_success_needs_the_robot_at_rest_inside_the_tolerances():
    rig = Rig()
    rig.nav.navigate_to(Pose2D(0.1, 0.0, 0.05), 0.0)
    rig.twist = Twist(0.2, 0.0, 0.0)
    rig.tick(0.05)
    assert rig.nav.state is State.FOLLOWING  # inside 0.25 m / 0.12 rad but still moving
    rig.twist = ZERO_TWIST
    rig.tick(0.10)
    assert rig.nav.state is State.SUCCEEDED
    fb = rig.nav.feedback(0.1)
    assert fb.state is State.SUCCEEDED and fb.distance_remaining < 0.15


def test_a_robot_that_stops_short_fails_for_lack_of_progress_not_at_the_timeout():
    rig = Rig()
    rig.nav.navigate_to(Pose2D(2.0, 0.0, 0.0), 0.0, timeout=60.0)
    t = rig.run(60.0)  # the fake base never moves
    assert rig.nav.state is State.FAILED and rig.nav.reason.startswith("no progress")
    assert "2.00 m from the goal" in rig.nav.reason
    assert 10.0 <= t <= 10.5
    rig.nav.navigate_to(Pose2D(2.0, 0.0, 0.0), 20.0, timeout=60.0)
    for k in range(1, 400):  # now it creeps 0.1 m/s: 0.5 m every 5 s renews the checkpoint
        rig.pose = Pose2D(0.0, -0.005 * k, 0.0)
        rig.tick(20.0 + 0.05 * k)
        if not rig.nav.active:
            break
    # ~20 s of creeping, twice the progress window and well inside the 60 s deadline: still going
    assert k == 399 and rig.nav.state is State.FOLLOWING, rig.nav.reason
