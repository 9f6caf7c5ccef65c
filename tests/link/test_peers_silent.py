"""A robot not heard from for ``SILENT`` s of the wall clock (the link's) is still where it last
said it was, and ``silent`` (it stands still there: kept out of by less, ``nav.costmap.robots``);
heard from again, it is not. A fleet sim waits for a robot's poses while it is still talking
(``behind``)."""
from __future__ import annotations

import threading
from types import SimpleNamespace

from hw.odometry import Pose2D
from mission.link.peers import SILENT, Peers


def sample(robot: str, x: float, t: float = 0.0) -> SimpleNamespace:
    payload = f'{{"t": {t}, "pose": [{x}, 0.0, 0.0]}}'.encode()
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


def test_a_robot_is_behind_when_its_last_pose_is_older_than_the_lag_and_not_once_it_is_silent():
    wall = [100.0]
    session = SimpleNamespace(declare_subscriber=lambda key, on: SimpleNamespace(undeclare=lambda: None))
    peers = Peers(session, SimpleNamespace(post=lambda key, make: None), "r1", Pose2D(), clock=lambda: wall[0])
    assert not peers.behind(5.0, 0.3)  # no one heard yet: no one to wait for
    peers._on_sample(sample("r2", 1.0, t=5.0))
    assert not peers.behind(5.25, 0.3) and peers.behind(5.35, 0.3)
    peers._on_sample(sample("r2", 1.1, t=5.2))
    assert not peers.behind(5.35, 0.3)
    wall[0] += SILENT + 0.1  # its link is down: waited for no longer
    assert not peers.behind(9.0, 0.3)


def test_hear_wakes_on_the_pose_it_waits_for_and_gives_up_after_its_timeout():
    session = SimpleNamespace(declare_subscriber=lambda key, on: SimpleNamespace(undeclare=lambda: None))
    peers = Peers(session, SimpleNamespace(post=lambda key, make: None), "r1", Pose2D(), clock=lambda: 100.0)
    peers._on_sample(sample("r2", 1.0, t=5.0))
    assert peers.hear(5.2, 0.3, timeout=0.0)  # not behind: no wait
    assert not peers.hear(6.0, 0.3, timeout=0.05)  # nothing comes: given up
    later = threading.Timer(0.05, lambda: peers._on_sample(sample("r2", 1.1, t=5.9)))
    later.start()
    assert peers.hear(6.0, 0.3, timeout=10.0)  # woken by the pose, long before the timeout
    later.join()
