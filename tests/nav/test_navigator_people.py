"""The navigator with people about (issue 28 item 2), on the real global costmap with its person
layer and the real NavFn: a person in the only aisle or on the goal makes the goal wait (zero
twist, clocks stopped, no 'no path' and no 'no progress') and it drives on once they step aside;
past ``blocked_wait`` it fails ``blocked`` (the patrol comes back later), never 'unreachable'; a
person who comes up to the robot makes it wait, not back off; with nobody about a wall still
fails 'no path' as quickly as before."""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from hw.interfaces import ZERO_TWIST, LidarScan, Twist
from hw.odometry import Pose2D
from hw.people import Person
from nav.config import NavConfig
from nav.costmap.grid import LETHAL
from nav.costmap.layered import global_costmap
from nav.localisation import OdometryOnly
from nav.navigator import LANE, Navigator, Sources, State
from nav.planner import NavfnPlanner
from nav.walks import Walks
from nav.waits import ESCAPE_AFTER, ESCAPE_TIME
from tests.nav.builders import dummy_costmap
from tests.nav.test_navigator import FakeController, FakeCostmap

RES = 0.05
CFG = NavConfig()
START, GOAL = Pose2D(0.7, 1.6, 0.0), Pose2D(5.3, 1.6, 0.0)
IN_THE_AISLE = Person(7, 3.0, 0.72, 0.0, 0.0, 0.2, 0.9)


def one_aisle(closed: bool = False) -> np.ndarray:
    """6 x 3.2 m walled floor; a block x 1.5..4.5 from y 1.4 to the north wall leaves one aisle
    (y 0.05..1.4), too narrow to pass a person in it at 0.3 m; ``closed``: a wall across it."""
    w, h = int(6.0 / RES), int(3.2 / RES)
    occ = np.zeros((h, w), dtype=np.int8)
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = 100
    occ[int(1.4 / RES):, int(1.5 / RES):int(4.5 / RES)] = 100
    if closed:
        occ[:, int(3.0 / RES):int(3.1 / RES)] = 100
    return occ


class LocalCostmap(FakeCostmap):
    """The fake local costmap, open floor with people taken out too, its 3 x 3 m window round
    the robot as the real one rolls with it."""

    def __init__(self):
        super().__init__()
        self.grid = dummy_costmap(60, 60, origin=(START.x - 1.5, START.y - 1.5))

    def without_people(self):
        return self.grid


class Rig:
    def __init__(self, people=(), closed=False, controller=None, held=False, escape=lambda speed: ZERO_TWIST):
        self.people = list(people)
        self.published: list[tuple[float, Twist]] = []
        self.t = 0.0
        self.held = held
        walks = Walks(lambda: self.people, lambda: self.t)  # as the runtime's navigation reads people
        io = Sources(lambda: START, lambda: ZERO_TWIST, self.scan, lambda tw, now: self.published.append((now, tw)),
                     lambda: False, lambda: self.held, walks, escape)
        self.glob = global_costmap(CFG.costmap, lambda: self.people)
        self.glob.set_static(one_aisle(closed), RES, 0.0, 0.0)
        self.local = LocalCostmap()
        self.nav = Navigator(CFG, io, OdometryOnly(), self.local, self.glob, NavfnPlanner(CFG.planner),
                             controller or FakeController())

    def scan(self):
        return LidarScan(self.t, np.zeros(1, np.float32), np.full(1, np.inf, np.float32))

    def run(self, until, t0=0.0):
        t = t0
        while t <= until and self.nav.active:
            self.t = t
            if round(t * 20) % 20 == 0:
                self.nav.tick_planner(t)
            self.nav.tick_control(t)
            t = round(t + 0.05, 6)
        return t


def walked_up(rig: Rig, person: Person, metres: float = 0.6) -> None:
    """``person`` walks up to where they stand along +x at 1 m/s (the rig's clock from 0 s),
    then stands: a grower who stopped for the robot, seen to walk."""
    for k in range(round(metres / 0.05), 0, -1):
        rig.t = -0.05 * k
        rig.people[:] = [replace(person, x=person.x + 0.05 * k, vx=-1.0)]
        rig.nav.people.counted()
    rig.people[:] = [person]


def test_a_person_in_the_only_aisle_is_waited_for_then_the_robot_drives_on():
    rig = Rig([IN_THE_AISLE])
    rig.nav.navigate_to(GOAL, 0.0, timeout=8.0)
    rig.run(12.0)  # past the timeout and the progress check's 10 s
    assert rig.nav.active and rig.nav.waiting_for == "a person in the only way" and rig.nav.path is None
    rig.people.clear()  # they step aside
    rig.run(14.0, t0=12.05)
    assert rig.nav.active and rig.nav.waiting_for == ""
    assert rig.published[-1][1].vx > 0  # following the plan through the aisle now


def test_a_person_who_stays_in_the_only_aisle_fails_the_goal_blocked_after_the_wait_not_no_path():
    wait = CFG.navigator.person_wait
    rig = Rig([IN_THE_AISLE])
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    end = rig.run(wait + 10.0)
    assert rig.nav.state is State.FAILED and rig.nav.reason.startswith("blocked: a person in the only way")
    assert wait <= end <= wait + 0.2


def test_a_wall_across_the_only_aisle_still_fails_no_path_at_once():
    rig = Rig([Person(8, 1.0, 0.5, 0.0, 0.0, 0.2, 0.9)], closed=True)  # someone about, not in the way
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    end = rig.run(60.0)
    assert rig.nav.state is State.FAILED and rig.nav.reason.startswith("no path")
    assert end < 5.0


def test_a_person_on_the_goal_is_waited_for_at_a_distance():
    rig = Rig([Person(9, GOAL.x + 0.3, GOAL.y, 0.0, 0.0, 0.2, 0.9)])
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    rig.run(11.0)
    assert rig.nav.active and rig.nav.waiting_for == "a person at the goal"
    assert all(tw == ZERO_TWIST for _, tw in rig.published)


def test_a_person_who_comes_up_to_the_robot_is_stepped_away_from_not_a_recovery():
    person = Person(10, START.x + 0.3, START.y - 0.5, 0.0, 0.0, 0.2, 0.9)
    rig = Rig([person], controller=FakeController(fail=True))
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    rig.run(12.0)
    assert rig.nav.active and rig.local.clears == 0 and rig.nav.state is State.FOLLOWING
    steps = [tw for _, tw in rig.published if tw != ZERO_TWIST]
    assert steps
    away = np.array([START.x - person.x, START.y - person.y])
    for tw in steps:  # the robot faces +x: body frame is odom's
        assert math.hypot(tw.vx, tw.vy) <= 0.15 + 1e-9 and np.array([tw.vx, tw.vy]) @ away > 0
    rig.people.clear()
    rig.run(20.0, t0=12.05)
    assert rig.local.clears >= 1  # with nobody there, no valid control is a recovery again


def test_a_walker_coming_across_is_stepped_aside_from_not_backed_along_its_way():
    walker = Person(11, START.x, START.y + 1.0, 0.0, -0.8, 0.2, 0.9)  # 1 m north, walking south at it
    rig = Rig([walker], controller=FakeController(fail=True))
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    rig.run(0.5)
    tw = rig.published[-1][1]
    assert abs(tw.vx) > 0.1 and abs(tw.vy) < 0.05  # along x, out of its way south


def test_a_walker_coming_along_the_robots_way_is_stepped_out_of_while_still_metres_off():
    walker = Person(12, START.x + 3.0, START.y, -1.0, 0.0, 0.2, 0.9)  # 3 m ahead, walking at it at 1 m/s
    rig = Rig([walker])
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    rig.run(0.5)
    assert rig.nav.active and rig.nav.waiting_for == LANE
    tw = rig.published[-1][1]
    assert abs(tw.vy) == pytest.approx(CFG.costmap.global_costmap.people.step_speed) and abs(tw.vx) < 1e-9
    walker = Person(12, START.x + 0.9, START.y, -1.0, 0.0, 0.2, 0.9)  # within 1 m: the 0.15 m/s step
    rig.people[:] = [walker]
    rig.run(1.0, t0=0.55)
    assert math.hypot(rig.published[-1][1].vx, rig.published[-1][1].vy) == pytest.approx(0.15)


@pytest.mark.parametrize("walker", [Person(13, START.x + 3.0, START.y, 1.0, 0.0, 0.2, 0.9),    # walking away
                                    Person(14, START.x + 3.0, START.y + 1.5, -1.0, 0.0, 0.2, 0.9),  # another lane
                                    Person(15, START.x + 6.0, START.y, -1.0, 0.0, 0.2, 0.9),  # 6 m off: beyond 4 s
                                    Person(17, START.x + 0.8, START.y + 0.5, -1.0, 0.0, 0.2, 0.9)])  # near, passing by
def test_a_walker_whose_lane_the_robot_is_not_in_does_not_hold_the_goal(walker):
    rig = Rig([walker])
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    rig.run(0.5)
    assert rig.nav.waiting_for != LANE


def test_a_robot_boxed_in_waits_it_out_then_fails_blocked_not_no_path_in_a_blink():
    occ = one_aisle()
    cx, cy = int(START.x / RES), int(START.y / RES)
    occ[cy - 5:cy + 6, cx - 5:cx + 6] = 100  # something against it on every side
    occ[cy - 3:cy + 4, cx - 3:cx + 4] = 0
    rig = Rig()
    rig.glob.set_static(occ, RES, 0.0, 0.0)
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    rig.run(5.0)
    assert rig.nav.active and all(tw == ZERO_TWIST for _, tw in rig.published)
    end = rig.run(30.0, t0=5.05)
    assert rig.nav.state is State.FAILED and rig.nav.reason.startswith("blocked: boxed in")
    assert CFG.navigator.blocked_wait <= end <= CFG.navigator.blocked_wait + 1.5


def test_a_person_the_monitor_holds_the_robot_for_is_stepped_back_from_not_pressed_on():
    person = Person(16, START.x + 0.75, START.y, 0.0, 0.0, 0.2, 0.9)  # stopped for the robot, 0.35 m off
    rig = Rig([person], held=True)
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    rig.run(1.0)
    assert rig.nav.active and all(tw.vx < 0 and abs(tw.vy) < 1e-9 for _, tw in rig.published[1:])  # back, away
    assert math.hypot(rig.published[-1][1].vx, rig.published[-1][1].vy) == pytest.approx(0.15)
    end = rig.run(CFG.navigator.person_wait + 5.0, t0=1.05)
    assert rig.nav.state is State.FAILED and rig.nav.reason.startswith("blocked: a person close by")
    assert end >= CFG.navigator.person_wait  # a person's wait, not the 15 s for a box


def test_a_robot_held_while_it_steps_back_steps_straight_away_from_everyone_for_a_while():
    """safety.people seed 113, 675-3,074 s: its step to a refuge past a worker held by the guard
    (a cart's corner on the other side), the robot stood; held ``ESCAPE_AFTER`` on end it takes
    the guard's step away from everyone for ``ESCAPE_TIME``, then tries its own again, the whole
    a person's wait."""
    person = Person(16, START.x + 0.75, START.y, 0.0, 0.0, 0.2, 0.9)
    away = Twist(0.0, -0.15, 0.0)  # the guard's: square to the worker, away from the cart
    rig = Rig([person], held=True, escape=lambda speed: Twist(0.0, -speed, 0.0))
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    rig.run(ESCAPE_AFTER)
    assert rig.published and all(tw.vx < 0 and tw != away for _, tw in rig.published[1:])  # its own step back
    n = len(rig.published)
    rig.run(ESCAPE_AFTER + ESCAPE_TIME - 0.1, t0=ESCAPE_AFTER + 0.05)
    assert [tw for _, tw in rig.published[n:]] == [away] * (len(rig.published) - n)
    rig.run(ESCAPE_AFTER + ESCAPE_TIME + 1.0, t0=ESCAPE_AFTER + ESCAPE_TIME - 0.05)
    assert rig.published[-1][1].vx < 0  # its own step again
    rig.run(CFG.navigator.person_wait + 5.0, t0=ESCAPE_AFTER + ESCAPE_TIME + 1.05)
    assert rig.nav.state is State.FAILED and rig.nav.reason.startswith("blocked: a person close by")
    rig = Rig([person], held=True)  # no step away from everyone: its own step back throughout
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    rig.run(ESCAPE_AFTER + 1.0)
    assert all(tw.vx < 0 for _, tw in rig.published[1:])


def test_a_recovery_with_people_about_does_not_back_off_blindly():
    """Backing off away from the nearest lethal cells, a person's disc among them, once took the
    robot into a cross aisle a grower was pausing in (safety.people seed 1): with people about
    the back-off is the refuge's step, here none (the robot stands out of everyone's way)."""
    person = Person(15, START.x + 1.0, START.y + 1.6, 0.0, 0.0, 0.2, 0.9)  # 1.9 m off, standing
    rig = Rig([person], controller=FakeController(fail=True))
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    rig.run(3.0)
    assert rig.local.clears >= 1 and rig.nav.state is State.RECOVERING
    assert all(tw == ZERO_TWIST for _, tw in rig.published)
    rig.people.clear()  # with nobody about, the back-off moves the robot again
    rig.run(12.0, t0=3.05)
    assert any(tw != ZERO_TWIST for _, tw in rig.published)


def test_a_robot_centimetres_from_its_goal_finishes_its_approach_while_the_walker_comes():
    """safety.people seed 1, 105 s: 7 cm from its goal, the robot stepped out of a cart's lane
    as the cart turned 3 m off, every time; seed 107, 881 s: 0.14 m from its goal, as a walker
    turned 1 m off. Within ``FINISH`` it arrives and stands there (a walker who yields stops for
    it; the people guard binds its last centimetres), someone within ``wait_clearance`` or not."""
    near_goal = Pose2D(START.x + 0.1, START.y, 0.0)
    for gap in (3.0, 0.9):
        rig = Rig([Person(12, START.x + gap, START.y, -1.0, 0.0, 0.2, 0.9)])
        rig.nav.navigate_to(near_goal, 0.0, timeout=60.0)
        rig.run(0.5)
        assert rig.nav.waiting_for == "" and rig.nav.state in (State.FOLLOWING, State.SUCCEEDED)
    far = Rig([Person(12, START.x + 3.0, START.y, -1.0, 0.0, 0.2, 0.9)])
    far.nav.navigate_to(GOAL, 0.0, timeout=60.0)  # 4.6 m off its goal: steps out of the lane as before
    far.run(0.5)
    assert far.nav.waiting_for == LANE


def test_a_robot_inside_a_persons_keep_out_plans_its_way_out_never_nearer_them():
    """Seed 107, 470 s: a cart pusher stopped for the robot at arm's length, the robot inside
    their keep-out had no start to plan from, and the two waited for each other for 400 s. The
    way out is the head of a plan no step of which comes nearer them than the robot stands,
    ending once it is out of every keep-out; the goal past them then waits as before."""
    person = Person(18, START.x + 0.6, START.y, 0.0, 0.0, 0.2, 0.9)  # keep-out 0.72 m: the robot is inside
    rig = Rig([person])
    walked_up(rig, person)
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    rig.run(0.5)
    assert rig.nav.active and rig.nav.waiting_for == "" and rig.published[-1][1] != ZERO_TWIST
    gaps = np.hypot(rig.nav.path[:, 0] - person.x, rig.nav.path[:, 1] - person.y)
    assert gaps.min() >= 0.6 - RES - 1e-9
    keep_out = person.radius + CFG.costmap.global_costmap.people.clearance + CFG.costmap.robot_radius
    assert gaps[-1] >= keep_out and (gaps[:-1] < keep_out).all()


def test_with_no_refuge_in_reach_the_robot_steps_along_the_way_out_of_a_keep_out():
    """Seed 104, 736-880 s: MPPI found no control inside a cart pusher's keep-out, no refuge
    was in reach, and the robot stood while the pusher, stopped for it, waited too. With none,
    it steps at 0.15 m/s along the way out, away from them; with no way out it stands."""
    person = Person(19, START.x + 0.6, START.y, 0.0, 0.0, 0.2, 0.9)
    rig = Rig([person], controller=FakeController(fail=True))
    walked_up(rig, person)
    walled = dummy_costmap(60, 60, value=LETHAL, origin=(START.x - 1.5, START.y - 1.5))
    walled.data[28:33, 28:33] = 0  # the refuge's view: nowhere to go but where it stands
    rig.local.grid = walled
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    rig.run(1.0)
    steps = [tw for _, tw in rig.published[1:]]
    assert steps and all(math.hypot(tw.vx, tw.vy) == pytest.approx(0.15) for tw in steps)
    assert all(tw.vx < 0.5 * 0.15 and tw.vy < 0 for tw in steps)  # round them (+x) by the aisle south, not at them
    rig.glob.set_static(np.full_like(one_aisle(), 100), RES, 0.0, 0.0)  # walls all round: no way out
    rig.published.clear()
    rig.run(3.0, t0=1.05)
    later = [tw for t, tw in rig.published if t >= 1.05 + 0.5]  # the way out is planned afresh every 0.5 s
    assert later and all(tw == ZERO_TWIST for tw in later)


def test_inside_the_keep_out_of_someone_never_seen_to_walk_the_robot_waits_as_before():
    """A worker who stands, or a crate on an approach pose taken for a person, does not walk on
    once the robot leaves: no way out is planned round them (test_blocked_approach: the crate's
    pot is then inspected from beside it)."""
    rig = Rig([Person(20, START.x + 0.6, START.y, 0.0, 0.0, 0.2, 0.9)])
    rig.nav.navigate_to(GOAL, 0.0, timeout=60.0)
    rig.run(0.5)
    assert rig.nav.active and rig.nav.waiting_for == "a person in the only way" and rig.nav.path is None
