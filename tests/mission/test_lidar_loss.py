"""A lost lidar holds the mission after ``lost_after`` and gives the patrol up after
``give_up_after``, on the runtime clock."""
from mission.patrol.lidar_loss import LidarLoss


class Clock:
    t = 0.0

    def now(self) -> float:
        return self.t


def test_holds_only_after_a_few_seconds_and_lets_go_when_scans_return():
    clock, since = Clock(), {"t": None}
    loss = LidarLoss(lambda: since["t"], clock.now, lost_after=3.0, give_up_after=30.0)
    assert loss.reason() is None
    since["t"], clock.t = 10.0, 12.9
    assert loss.reason() is None  # a glint, a hand: the monitor rides it out
    clock.t = 13.0
    assert loss.reason() == "lidar lost for 3 s: paused until scans return" and loss.lost_for() == 3.0
    since["t"] = None
    assert loss.reason() is None and not loss.given_up


def test_gives_up_once_and_says_why():
    clock = Clock()
    loss = LidarLoss(lambda: 0.0, clock.now, lost_after=3.0, give_up_after=30.0)
    clock.t = 29.9
    loss.reason()
    assert not loss.given_up
    clock.t = 30.0
    assert loss.reason() is not None
    assert loss.given_up.startswith("lidar lost for 30 s")
    first = loss.given_up
    clock.t = 40.0
    loss.reason()
    assert loss.given_up == first  # latched


def test_a_lidar_never_seen_is_the_start_up_gates_to_name():
    clock = Clock()
    armed = {"on": False}
    loss = LidarLoss(lambda: 0.0, clock.now, lost_after=3.0, give_up_after=30.0, armed=lambda: armed["on"])
    clock.t = 60.0
    assert loss.reason() is None and not loss.given_up
    armed["on"] = True
    assert loss.reason() is not None and loss.given_up
