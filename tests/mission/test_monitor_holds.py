"""Monitor holds (mission/patrol/monitor_holds.py): each stretch of the collision monitor holding
the base back is one entry, where it began, how long the robot waited and drove slowed; a short
break does not split one; the one in progress shows in the report."""
from __future__ import annotations

from hw.collision_monitor import CLEAR, SLOWDOWN, STOP, Verdict
from hw.odometry import Pose2D
from mission.patrol.monitor_holds import MonitorHolds


def _run(timeline):
    """``timeline``: (seconds, verdict) stretches at 10 Hz from t = 100."""
    state = {"v": CLEAR}
    enc = MonitorHolds(lambda: state["v"], lambda: Pose2D(3.0, 1.5, 0.0), t0=100.0)
    t = 100.0
    for seconds, verdict in timeline:
        state["v"] = verdict
        for _ in range(round(seconds * 10)):
            enc.tick(t)
            t = round(t + 0.1, 6)
    return enc


def test_a_person_passing_is_one_encounter_with_its_wait_and_slow_times():
    slow, stop = Verdict(SLOWDOWN, 0.5, 0.55), Verdict(STOP, 0.0, 0.28)
    enc = _run([(5, CLEAR), (2, slow), (3, stop), (0.5, CLEAR), (1, stop), (2, CLEAR)])
    (e,) = enc.sections()["holds"]
    assert (e["t"], e["x"], e["y"]) == (5.0, 3.0, 1.5)
    assert abs(e["slowed_s"] - 2.0) <= 0.11 and abs(e["waited_s"] - 4.0) <= 0.11
    assert abs(e["lost_s"] - (2.0 * 0.5 + 4.0)) <= 0.11  # half the speed withheld while slowed, all while stopped
    assert e["nearest_m"] == 0.28


def test_two_encounters_apart_are_two_and_an_open_one_is_shown():
    stop = Verdict(STOP, 0.0, 0.3)
    enc = _run([(1, stop), (2, CLEAR), (1, stop)])
    assert len(enc.done) == 1 and len(enc.sections()["holds"]) == 2


def test_an_empty_run_has_none():
    assert _run([(10, CLEAR)]).sections() == {"holds": []}
