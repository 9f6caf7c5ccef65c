"""Two patrols' aisle gates (mission/patrol/aisle_gate.py) against the dispatcher's arbiter through
a real router (mutual TLS, the fleet's access control), on the tiny greenhouse's aisle map given
as outlines (fleet.aisles.outlines). The robots are their gates driven by synthetic poses along
straight paths; lengths are straight-line (the tree gives the planner's). The drive's filter
(``keep_out``) is checked on the real planner over the tiny greenhouse's costmap."""
from __future__ import annotations

import time

import numpy as np
import pytest

from fleet.aisle_locks import AisleLockServer, AisleTable
from fleet.aisles import find_aisles, outlines
from mission.link.aisle_client import AisleLockClient, Pending
from mission.link.wire import alive_key
from mission.patrol.aisle_gate import CLEAR, MOUTH, SIDE, AisleGate
from mission.patrol.aisle_outlines import NO_AISLE, AisleOutlines
from tests.fleet.conftest import member, wait_for
from tests.fleet.test_aisles import tiny_greenhouse
from nav.config import NavConfig
from nav.planner import NavfnPlanner
from tests.nav.builders import greenhouse_grid, straight_path


def _outlines() -> tuple[AisleOutlines, int, int]:
    """The tiny greenhouse's aisles; A between the rows at y 1 and 2, B between 2 and 3."""
    m, pots = tiny_greenhouse()
    found = find_aisles(m, pots)
    shapes = AisleOutlines(outlines(found))
    return shapes, int(found.at(3.5, 1.5)), int(found.at(3.5, 2.5))


def _path(*corners) -> np.ndarray:
    return np.vstack([straight_path(a, b) for a, b in zip(corners, corners[1:])])


def _straight(here: np.ndarray):
    return lambda points: np.hypot(*(np.asarray(points) - here).T)


def test_outlines_hold_what_the_aisle_map_does():
    m, pots = tiny_greenhouse()
    found = find_aisles(m, pots)
    shapes = AisleOutlines(outlines(found))
    x, y = np.meshgrid(np.arange(0.3, 6.8, 0.1), np.arange(0.3, 3.8, 0.1))
    truth, got = found.at(x.ravel(), y.ravel()), shapes.at(np.c_[x.ravel(), y.ravel()])
    assert len(shapes.polygons) == found.count == 4
    assert (truth == got).mean() >= 0.97  # a boundary cell's half may fall either side
    path = _path((1.0, 0.5), (6.0, 0.5), (6.0, 3.5))
    assert shapes.along(path) == found.along(path)


class SlowLink:
    """The arbiter's table behind a link whose answers land only when the test says
    (``land``), in the order the requests were sent."""

    def __init__(self, table: AisleTable, robot: str):
        self.table, self.robot, self.out = table, robot, []

    def ask_later(self, aisles: list[int]) -> Pending:
        self.out.append(Pending(aisles))
        return self.out[-1]

    def land(self, answered: bool = True) -> None:
        pending = self.out.pop(0)
        if answered:
            pending.answer = self.table.request(self.robot, pending.aisles)
        pending.answered.set()


def test_a_let_go_waits_for_the_request_in_flight_so_the_arbiter_and_the_robot_agree_on_what_it_holds():
    """A leg's request for A and B goes out from A; the robot's body leaves A before the answer
    lands. Sent then, the let-go of A (from what was held: nothing) would land after the grant
    and free A and B at the arbiter while the robot drove in; it waits, and goes once the grant
    is in."""
    shapes, a, b = _outlines()
    table = AisleTable(lambda: 0.0)
    link = SlowLink(table, "r1")
    gate = AisleGate(link, shapes)
    assert table.request("r1", [a]).granted
    gate.held = [a]
    leg = gate.ask([a, b])
    assert gate.asking and gate.ask([b]) is None  # one at a time
    gate.progress(np.array([[3.5, 2.5]]))  # clear of A: nothing sent while the leg's request is out
    assert len(link.out) == 1 and gate.held == [a]
    link.land()
    assert gate.verdict(_path((3.5, 1.5), (3.5, 2.5)), leg.aisles, leg.answer, _straight(np.array([3.5, 1.5]))).go
    assert gate.held == [a, b] and table.held() == {a: "r1", b: "r1"}
    gate.progress(np.array([[3.5, 2.5]]))  # now it goes
    link.land()
    assert gate.held == [b] and table.held() == {b: "r1"}
    assert gate.backed_out() and gate.held == [] and gate.asking
    link.land()
    assert table.held() == {} and not gate.asking


def test_with_no_answer_the_robot_counts_only_on_what_it_held_either_way():
    shapes, a, b = _outlines()
    link = SlowLink(AisleTable(lambda: 0.0), "r1")
    gate = AisleGate(link, shapes)
    gate.held = [a]
    pending = gate.ask([b])
    link.land(answered=False)  # timed out: granted (holds B) or not (holds A), unknown
    verdict = gate.verdict(_path((6.0, 1.5), (3.5, 2.5)), pending.aisles, pending.answer, _straight(np.array([6.0, 1.5])))
    assert not verdict.go and gate.held == []


@pytest.fixture
def fleet(router, certs):
    """The arbiter on the dispatcher's session; r1 and r2 up, each asking on its own key."""
    dispatcher, r1, r2 = (member(router, certs, n) for n in ("dispatcher", "r1", "r2"))
    server = AisleLockServer(dispatcher, time.monotonic)
    tokens = [s.liveliness().declare_token(alive_key(n)) for s, n in ((r1, "r1"), (r2, "r2"))]
    assert wait_for(lambda: server.roster.robots() == ["r1", "r2"])
    shapes, a, b = _outlines()
    gates = {n: AisleGate(AisleLockClient(s, n), shapes) for s, n in ((r1, "r1"), (r2, "r2"))}
    try:
        yield server, gates, shapes, a, b
    finally:
        del tokens
        server.close()
        for s in (dispatcher, r1, r2):
            s.close()


@pytest.mark.slow
def test_two_robots_sent_into_one_aisle_from_both_ends_the_second_waits_outside_until_the_first_leaves(fleet):
    server, gates, shapes, a, _ = fleet
    east = _path((0.8, 1.5), (6.2, 1.5))  # r1, west to east through A
    west = _path((6.3, 1.5), (0.8, 1.5))  # r2, east to west through A
    assert gates["r1"].enter(east, _straight(east[0])).go
    refused = gates["r2"].enter(west, _straight(west[0]))
    assert not refused.go and not refused.back_out and refused.held_by == {a: "r1"}
    wait = refused.to
    assert shapes.at(wait)[0] == NO_AISLE and wait[0] > 5.4  # outside, at r2's own end
    off_way = np.abs(east[:, 1] - wait[1]).min()
    assert off_way >= SIDE - 1e-9  # beside the mouth: r1 leaves along y = 1.5 and passes it
    assert min(np.hypot(*(q - wait)) for q in east if shapes.at(q)[0] == a) >= MOUTH - 0.05
    from_wait = _path(tuple(wait), (6.0, 1.5), (0.8, 1.5))
    for i in range(len(east)):  # r1 drives; r2 asks again as it goes
        gates["r1"].progress(east[i:])
        now_in_a = shapes.at(east[i])[0] == a
        if now_in_a:
            assert not gates["r2"].enter(from_wait, _straight(wait)).go, f"r2 let in while r1 is in A at {east[i]}"
    assert wait_for(lambda: server.table.held() == {})  # r1 left A behind: let go
    assert gates["r2"].enter(from_wait, _straight(wait)).go and server.table.held() == {a: "r2"}


@pytest.mark.slow
def test_two_robots_each_in_the_aisle_the_other_wants_one_backs_out_and_both_get_through(fleet):
    server, gates, shapes, a, b = fleet
    in_a, in_b = np.array([4.5, 1.5]), np.array([4.5, 2.5])  # nearer the east ends
    assert gates["r1"].enter(_path(tuple(in_a), (4.0, 1.5)), _straight(in_a)).go  # each inspecting in its aisle
    assert gates["r2"].enter(_path(tuple(in_b), (4.0, 2.5)), _straight(in_b)).go
    to_b = _path(tuple(in_a), (6.0, 1.5), (6.0, 2.5), (3.0, 2.5))
    to_a = _path(tuple(in_b), (6.0, 2.5), (6.0, 1.5), (3.0, 1.5))
    first = gates["r1"].enter(to_b, _straight(in_a))
    assert not first.go and not first.back_out  # r1 waits for r2 ...
    second = gates["r2"].enter(to_a, _straight(in_b))
    assert not second.go and second.back_out  # ... and r2 waiting too would be a deadlock: it yields
    out = second.to
    assert shapes.at(out)[0] == NO_AISLE and out[0] > shapes.polygons[b][:, 0].max() + MOUTH - 0.05  # B's nearer end
    gates["r2"].backed_out()  # there: lets go of B
    assert wait_for(lambda: server.table.held() == {a: "r1"})
    assert gates["r1"].enter(to_b, _straight(in_a)).go and server.table.held() == {a: "r1", b: "r1"}
    again = gates["r2"].enter(_path(tuple(out), (6.0, 1.5), (3.0, 1.5)), _straight(out))
    assert not again.go and not again.back_out  # r2 now only waits, outside, for r1 to be through
    gates["r1"].progress(to_b[-3:])  # r1 in B at its pot: A is behind it
    assert wait_for(lambda: server.table.held() == {b: "r1"})
    assert gates["r2"].enter(_path(tuple(out), (6.0, 1.5), (3.0, 1.5)), _straight(out)).go


def test_a_drive_is_planned_around_the_aisles_the_robot_does_not_hold():
    """The navigator's filter (``keep_out``): from the west cross aisle to the east one, the
    shortest way is through A; holding only the south strip, the plan keeps out of A and B and
    takes the strip; standing inside A without holding it, the plan may still leave by A."""
    shapes, a, b = _outlines()
    m, pots = tiny_greenhouse()
    strip = int(find_aisles(m, pots).at(3.5, 0.5))
    gate = AisleGate(None, shapes)
    grid, planner = greenhouse_grid(), NavfnPlanner(NavConfig().planner)
    west, east = (0.9, 1.5), (6.1, 1.5)
    assert a in shapes.along(planner.plan(grid, west, east))  # unconstrained: straight through A
    gate.held = [strip]
    kept = planner.plan(gate.keep_out(grid, west), west, east)
    assert np.hypot(*(kept[-1] - east)) < 0.1, "the plan did not reach the goal"
    assert shapes.along(kept) == [strip]
    gate.held = []
    inside = (3.5, 1.5)
    out = planner.plan(gate.keep_out(grid, inside), inside, west)
    assert np.hypot(*(out[-1] - west)) < 0.1 and shapes.along(out) == [a]
    assert (gate.keep_out(grid, west).data >= grid.data).all()  # it only ever closes ground


@pytest.mark.slow
def test_a_robot_standing_on_an_aisles_edge_keeps_it_until_its_body_is_clear(fleet):
    """A pot's approach pose can lie a few cm either side of an outline: the aisle is let go
    only once the robot's centre is ``CLEAR`` of it, and the other robot is refused till then."""
    server, gates, shapes, a, _ = fleet
    end = shapes.polygons[a][:, 0].max()
    assert gates["r1"].enter(_path((3.5, 1.5), (end + 0.05, 1.5)), _straight(np.array([3.5, 1.5]))).go
    gates["r1"].progress(np.array([[end + 0.1, 1.5]]))  # out by its centre, not by its body
    time.sleep(0.3)
    assert server.table.held() == {a: "r1"} and gates["r1"].held == [a]
    beyond = np.array([end + CLEAR + 0.5, 1.0])
    assert not gates["r2"].enter(_path(tuple(beyond), (3.5, 1.5)), _straight(beyond)).go
    gates["r1"].progress(np.array([[end + CLEAR + 0.05, 1.5]]))
    assert wait_for(lambda: server.table.held() == {})
    assert gates["r2"].enter(_path(tuple(beyond), (3.5, 1.5)), _straight(beyond)).go
