"""The aisle leaves (behaviours/aisles.py) on the tiny greenhouse's aisles: a drive waits outside
an aisle another robot holds and goes once it is let go; a leg with no aisle asks nothing; the
aisles behind a robot are let go. The arbiter is the dispatcher's real table; the link between
is the test's (tests/fleet/test_aisle_gate.py has it through a router)."""
from __future__ import annotations

import numpy as np
from py_trees.common import Status

from behaviours.aisles import EnterAisles, LetGoBehind
from fleet.aisle_locks import AisleTable
from hw.odometry import Pose2D
from mission.link.aisle_client import Pending
from mission.patrol.aisle_gate import RETRY, AisleGate
from mission.patrol.aisle_outlines import NO_AISLE
from nav.navigator import State
from sim.clock import SimClock
from tests.behaviours.test_leaves import FakeNav, tick_at
from tests.fleet.test_aisle_gate import _outlines
from tests.nav.builders import straight_path


class TableClient:
    """Asks the arbiter's table in this process, as ``robot``; counts the requests."""

    def __init__(self, table: AisleTable, robot: str):
        self.table, self.robot, self.asked = table, robot, []

    def ask_later(self, aisles: list[int]) -> Pending:
        pending = Pending(aisles)
        self.asked.append(pending.aisles)
        pending.answer = self.table.request(self.robot, pending.aisles)
        pending.answered.set()
        return pending


class Planner:
    def plan(self, grid, start_xy, goal_xy):
        return straight_path(start_xy, goal_xy)


class AisleNav(FakeNav):
    """FakeNav standing at ``here``, planning straight lines."""

    def __init__(self, here):
        super().__init__()
        self.here, self.planner, self.path = here, Planner(), None
        self.global_costmap = type("Costmap", (), {"grid": None})()

    def map_pose(self) -> Pose2D:
        return self.here

    @property
    def active(self) -> bool:
        return self.state in (State.FOLLOWING, State.RECOVERING)


def _straight(origin, points):
    return np.hypot(*(np.asarray(points) - origin).T)


def test_a_drive_into_an_aisle_another_holds_waits_outside_and_goes_once_it_is_let_go():
    shapes, a, _ = _outlines()
    table, clock = AisleTable(lambda: 0.0), SimClock()
    assert table.request("r1", [a]).granted
    client = TableClient(table, "r2")
    nav = AisleNav(Pose2D(6.3, 1.5, np.pi))
    gate = AisleGate(client, shapes)
    leaf = EnterAisles("aisles", gate, nav, lambda: Pose2D(0.8, 1.5, np.pi), clock, _straight, RETRY)
    assert tick_at(leaf, clock, 0.0) is Status.RUNNING and client.asked == [[a]]  # asked, not waited
    assert tick_at(leaf, clock, 0.1) is Status.RUNNING  # refused: off to wait outside
    (wait, _, _), = nav.goals
    assert shapes.at([wait.x, wait.y])[0] == NO_AISLE and wait.x > 5.4 and "(r1)" in leaf.feedback_message
    nav.here, nav.state = wait, State.SUCCEEDED
    assert tick_at(leaf, clock, 0.5) is Status.RUNNING and client.asked == [[a]]  # asks again a second on
    assert tick_at(leaf, clock, 1.2) is Status.RUNNING and client.asked == [[a], [a]]
    assert tick_at(leaf, clock, 1.3) is Status.RUNNING and len(nav.goals) == 1  # still refused: stays where it is
    table.request("r1", [])  # r1 has left the aisle
    tick_at(leaf, clock, 2.4)
    assert tick_at(leaf, clock, 2.5) is Status.SUCCESS and table.held() == {a: "r2"}
    assert gate.sections() == {"aisles": {"wait_s": 2.4, "waits": 1, "yields": 0}}  # refused at 0.1, in at 2.5


def test_a_leg_on_open_ground_asks_nothing_and_the_aisles_behind_are_let_go():
    shapes, a, _ = _outlines()
    table, clock = AisleTable(lambda: 0.0), SimClock()
    client = TableClient(table, "r1")
    gate = AisleGate(client, shapes)
    nav = AisleNav(Pose2D(6.2, 0.5, np.pi / 2))  # the east cross aisle, to its north end
    leaf = EnterAisles("aisles", gate, nav, lambda: Pose2D(6.2, 3.5, np.pi / 2), clock, _straight, RETRY)
    assert tick_at(leaf, clock, 0.0) is Status.SUCCESS and client.asked == []
    nav.here = Pose2D(0.8, 1.5, 0.0)
    leaf = EnterAisles("aisles", gate, nav, lambda: Pose2D(6.2, 1.5, 0.0), clock, _straight, RETRY)
    tick_at(leaf, clock, 0.1)
    assert tick_at(leaf, clock, 0.2) is Status.SUCCESS and gate.held == [a]
    behind = LetGoBehind("let go behind", gate, nav, clock, RETRY)
    nav.state, nav.path = State.FOLLOWING, straight_path((0.8, 1.5), (6.2, 1.5))
    nav.here = Pose2D(3.0, 1.5, 0.0)
    assert tick_at(behind, clock, 0.3) is Status.RUNNING and table.held() == {a: "r1"}  # in it: kept
    nav.here = Pose2D(6.0, 1.5, 0.0)
    assert tick_at(behind, clock, 1.0) is Status.RUNNING and table.held() == {a: "r1"}  # once a second
    assert tick_at(behind, clock, 1.3) is Status.RUNNING and table.held() == {} and gate.held == []
