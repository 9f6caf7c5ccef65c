"""The tracker's people on the link: the fast beat's ``state`` message carries them in the map
frame (through ``map -> odom``), rounded, and leaves them out when nobody is tracked; a console
folds them into its view over a real Zenoh session on loopback."""
from __future__ import annotations

import json
import math
from types import SimpleNamespace

import pytest
import zenoh

from hw.odometry import Pose2D
from hw.people import Person
from mission.link.client import LinkClient
from mission.link.server import free_endpoint, session_config
from mission.link.telemetry import PERSON_FIELDS, Telemetry
from mission.link.wire import tel_key
from tests.link.sim_service import wait_for

MAP_TO_ODOM = Pose2D(2.0, -1.0, math.pi / 2)
"""SLAM's correction: odom is 2 m east, 1 m south of map and turned a quarter left."""


class Walkers:
    """A ``robot.people`` stand-in: every track, and the ones the rules act on."""

    def __init__(self, tracks=(), walked=()):
        self.tracks, self.walked = tuple(tracks), set(walked)

    def current(self):
        return self.tracks

    def confident(self):
        return tuple(p for p in self.tracks if p.id in self.walked)


class Posts:
    """An outbox that builds each payload at once and keeps it by key."""

    def __init__(self):
        self.sent: dict[str, bytes] = {}

    def post(self, key, payload):
        self.sent[key] = payload()


def service(people) -> SimpleNamespace:
    """What ``Telemetry.fast`` reads of a runtime, standing still at the map's origin."""
    power = SimpleNamespace(reading=None, state=SimpleNamespace(percentage=80.0, low=False))
    monitor = SimpleNamespace(verdict=SimpleNamespace(action="none", nearest=math.inf), fault=None,
                              config=SimpleNamespace(enabled=True))
    odometry = SimpleNamespace(twist=SimpleNamespace(vx=0.0, vy=0.0, wz=0.0))
    robot = SimpleNamespace(power=power, monitor=monitor, people=people,
                            base=SimpleNamespace(odometry=odometry, source="idle"),
                            estop=SimpleNamespace(engaged=lambda: False, held_since_start=""))
    nav = SimpleNamespace(map_pose=lambda: Pose2D(0.0, 0.0, 0.0),
                          localisation=SimpleNamespace(map_to_odom=lambda: MAP_TO_ODOM))
    return SimpleNamespace(robot=robot, nav=nav, run=None)


def state(people) -> tuple[bytes, dict]:
    posts = Posts()
    Telemetry(service(people), posts, "mirte").fast(12.5)
    data = posts.sent[tel_key("mirte", "state")]
    return data, json.loads(data)


def test_the_state_carries_the_tracks_in_the_map_frame_rounded():
    walker = Person(4, 1.0, 0.5, 0.8, 0.0, 0.234, 0.876)  # odom: 1 m ahead, walking along odom's x
    crate = Person(9, -0.3333, 0.0, 0.0, 0.0, 0.2, 0.5)
    _, msg = state(Walkers([walker, crate], walked={4}))
    assert len(msg["people"][0]) == len(PERSON_FIELDS)
    rows = {r[0]: dict(zip(PERSON_FIELDS, r)) for r in msg["people"]}
    # odom (1, 0.5) turned a quarter left is (-0.5, 1), then moved by (2, -1); odom's x is map's y
    assert rows[4] == {"id": 4, "x": 1.5, "y": 0.0, "vx": 0.0, "vy": 0.8, "radius": 0.23, "confidence": 0.88,
                       "walked": 1}
    assert rows[9] == {"id": 9, "x": 2.0, "y": -1.33, "vx": 0.0, "vy": 0.0, "radius": 0.2, "confidence": 0.5,
                       "walked": 0}


@pytest.mark.parametrize("people", [None, Walkers()], ids=["no tracker", "nobody tracked"])
def test_nobody_tracked_costs_no_bytes(people):
    bare, msg = state(people)
    assert "people" not in msg
    one, _ = state(Walkers([Person(1, 0.0, 0.0, 0.0, 0.0, 0.2, 0.5)]))
    assert 0 < len(one) - len(bare) < 60  # one person is a few dozen bytes; nobody is none


def test_a_console_sees_the_people_and_loses_them_when_the_tracker_does():
    endpoint = free_endpoint()
    robot = zenoh.open(session_config("listen", endpoint))
    client = LinkClient(endpoint, "mirte", clock=lambda: 0.0)
    try:
        walking, _ = state(Walkers([Person(4, 1.0, 0.5, 0.8, 0.0, 0.25, 0.9)], walked={4}))
        assert wait_for(lambda: (robot.put(tel_key("mirte", "state"), walking), client.view().people)[1])
        (p,) = client.view().people
        seen = (p.id, p.x, p.y, p.vx, p.vy, p.radius, p.confidence, p.walked)
        assert seen == (4, 1.5, 0.0, 0.0, 0.8, 0.25, 0.9, True)
        assert p.speed == pytest.approx(0.8)
        nobody, _ = state(Walkers())
        # the walking messages still in flight may land first: wait for the one without people
        assert wait_for(lambda: (robot.put(tel_key("mirte", "state"), nobody), client.view().people == [])[1])
        assert client.bad_messages == 0
    finally:
        client.close()
        robot.close()
