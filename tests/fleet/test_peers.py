"""Robots telling each other where they are (``mission.link.peers``) through the real TLS router and
its access control: each robot's pose in the fleet frame from its own dock, placed in the other's
map frame; nobody says where another robot is; a robot whose link died still stands where it last
said until it is heard from again."""
from __future__ import annotations

import math
import time

from hw.odometry import Pose2D
from mission.link.outbox import Outbox
from mission.link.peers import Peers, where_key
from tests.fleet.conftest import member, wait_for

DOCK1, DOCK2 = Pose2D(0.0, 0.0, 0.0), Pose2D(0.0, 2.0, -math.pi / 2)
"""r2 docked 2 m north of r1, facing south."""


def _peers(router, certs, name: str, dock: Pose2D):
    session = member(router, certs, name)
    outbox = Outbox(session.put, 16)
    return session, outbox, Peers(session, outbox, name, dock, time.monotonic)


def _close(session, outbox) -> None:
    outbox.close()
    session.close()


def test_each_robot_sees_the_other_in_its_own_map_frame_and_nobody_speaks_for_another(router, certs):
    s1, o1, p1 = _peers(router, certs, "r1", DOCK1)
    s2, o2, p2 = _peers(router, certs, "r2", DOCK2)
    try:
        assert wait_for(lambda: (p1.tell(Pose2D(1.0, 0.5, 0.0), 0.0), p2.around())[1])
        (r1,) = p2.around()
        # fleet (1, 0.5) is, from r2's dock at (0, 2) facing south, 1.5 m ahead and 1 m to its left
        assert r1.name == "r1" and math.isclose(r1.x, 1.5, abs_tol=1e-3) and math.isclose(r1.y, 1.0, abs_tol=1e-3)
        assert wait_for(lambda: (p2.tell(Pose2D(0.0, 0.0, 0.0), 0.0), p1.around())[1])
        assert [(p.name, round(p.x, 3), round(p.y, 3)) for p in p1.around()] == [("r2", 0.0, 2.0)]
        s2.put(where_key("r1"), b'{"pose": [9.0, 9.0, 0.0]}')  # r2 forging r1's place: the router drops it
        s2.put(where_key("r3"), b'{"pose": [9.0, 9.0, 0.0]}')
        p2.tell(Pose2D(0.5, 0.0, 0.0), 1.0)
        assert wait_for(lambda: p1.around()[0].y == 1.5)
        assert [p.name for p in p1.around()] == ["r2"] and p1.around()[0].x == 0.0
        assert all(p.name != "r2" for p in p2.around())  # never itself
    finally:
        _close(s1, o1)
        _close(s2, o2)


def test_a_robot_whose_link_died_stands_where_it_last_said_until_heard_from_again(router, certs):
    s1, o1, p1 = _peers(router, certs, "r1", DOCK1)
    s2, o2, p2 = _peers(router, certs, "r2", DOCK2)
    try:
        assert wait_for(lambda: (p2.tell(Pose2D(1.0, 0.0, 0.0), 0.0), p1.around())[1])
        _close(s2, o2)  # its computer died: its token and its link gone
        assert [(p.name, round(p.x, 3), round(p.y, 3)) for p in p1.around()] == [("r2", 0.0, 1.0)]
        s2, o2, p2 = _peers(router, certs, "r2", DOCK2)  # back, and somewhere else
        assert wait_for(lambda: (p2.tell(Pose2D(0.0, 0.0, 0.0), 5.0), p1.around()[0].y == 2.0)[1])
    finally:
        _close(s1, o1)
        _close(s2, o2)
