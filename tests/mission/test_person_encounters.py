"""Person encounters (mission/patrol/person_encounters.py): a tracked person within 1.0 m of the
robot's body is one entry per stretch, with the monitor's waiting and slowing meanwhile and the
nearest approach; holds with no person near are not people; no tracker, no entries."""
from __future__ import annotations

from hw.collision_monitor import CLEAR, SLOWDOWN, STOP, Verdict
from hw.odometry import Pose2D
from hw.people import Person, nobody
from mission.patrol.person_encounters import PersonEncounters


def _run(timeline, source=None):
    """``timeline``: (seconds, person x or None, verdict) stretches at 10 Hz from t = 100; the
    robot stands at (1, 1) in odom, a person of radius 0.2 on y = 1."""
    state = {"x": None, "v": CLEAR}

    def people():
        return () if state["x"] is None else (Person(7, state["x"], 1.0, 0.0, 0.0, 0.2, 0.9),)

    enc = PersonEncounters(source or people, lambda: Pose2D(1.0, 1.0, 0.0), lambda: state["v"], t0=100.0)
    t = 100.0
    for seconds, x, verdict in timeline:
        state["x"], state["v"] = x, verdict
        for _ in range(round(seconds * 10)):
            enc.tick(t)
            t = round(t + 0.1, 6)
    return enc


def test_a_person_coming_near_is_one_encounter_with_the_wait_the_slowing_and_the_nearest():
    slow, stop = Verdict(SLOWDOWN, 0.5, 0.7), Verdict(STOP, 0.0, 0.5)
    enc = _run([(2, 4.0, CLEAR), (1, 2.2, slow), (2, 1.9, stop), (0.5, 2.5, CLEAR), (1, 1.8, CLEAR), (3, 4.0, CLEAR)])
    (e,) = enc.sections()["people"]
    assert (e["t"], e["x"], e["y"], e["person"]) == (2.0, 1.0, 1.0, 7)
    assert abs(e["slowed_s"] - 1.0) <= 0.11 and abs(e["waited_s"] - 2.0) <= 0.11
    assert e["nearest_m"] == 0.38  # 0.8 m centre to centre less 0.2 and the 0.22 m footprint


def test_a_hold_with_nobody_near_is_no_person_and_far_people_are_none():
    enc = _run([(3, None, Verdict(STOP, 0.0, 0.2)), (3, 2.5, Verdict(STOP, 0.0, 0.2))])  # 1.5 - 0.42 = 1.08 m away
    assert enc.sections() == {"people": []}


def test_two_visits_apart_are_two_and_one_in_progress_shows():
    enc = _run([(1, 1.8, CLEAR), (2, 4.0, CLEAR), (1, 1.8, CLEAR)])
    assert len(enc.done) == 1 and len(enc.sections()["people"]) == 2


def test_no_tracker_lists_nothing():
    assert _run([(5, 1.5, Verdict(STOP, 0.0, 0.2))], source=nobody).sections() == {"people": []}
