"""A robot not heard from for ``SILENT`` s of the wall clock (the link's) is still where it last
said it was, and ``silent`` (it stands still there: kept out of by less, ``nav.costmap.robots``);
heard from again, it is not."""
from __future__ import annotations

from types import SimpleNamespace

from hw.odometry import Pose2D
from mission.link.peers import SILENT, Peers


def sample(robot: str, x: float) -> SimpleNamespace:
    payload = f'{{"t": 0.0, "pose": [{x}, 0.0, 0.0]}}'.encode()
    return SimpleNamespace(key_expr=f"lupin/{robot}/where", payload=SimpleNamespace(to_bytes=lambda: payload))


def test_a_robot_not_heard_from_for_a_while_is_silent_where_it_last_was():
    wall = [100.0]
    session = SimpleNamespace(declare_subscriber=lambda key, on: SimpleNamespace(undeclare=lambda: None))
    peers = Peers(session, SimpleNamespace(post=lambda key, make: None), "r1", Pose2D(), clock=lambda: wall[0])
    peers._on_sample(sample("r2", 1.0))
    wall[0] += SILENT - 0.1
    assert [(p.name, p.x, p.silent) for p in peers.around()] == [("r2", 1.0, False)]
    wall[0] += 0.2
    assert [(p.name, p.x, p.silent) for p in peers.around()] == [("r2", 1.0, True)]
    peers._on_sample(sample("r2", 1.5))
    assert [(p.name, p.x, p.silent) for p in peers.around()] == [("r2", 1.5, False)]
