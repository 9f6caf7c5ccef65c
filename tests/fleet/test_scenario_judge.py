"""The fleet scenario's judge on ground truth written by hand: two robots in one aisle closing on
each other is a head-on meeting, one following another that drives off is a meeting only, a
touch counts once, and how far the others drove while one was held. (The judge on real runs:
tests/scenarios/fleet-*.yaml.)"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from hw.odometry import Pose2D
from mission.patrol.aisle_outlines import AisleOutlines
from fleet.scenario_judge import FleetWatch, fleet_checks
from mission.scenario.scenario_file import FleetExpect

AISLE = AisleOutlines({0: np.array([[0.0, 0.0], [5.0, 0.0], [5.0, 1.0], [0.0, 1.0]])})
"""One aisle, 5 m long along x, 1 m wide."""


@dataclass
class Truth:
    """What the judge reads of a scene: where each robot truly is, which touch."""

    where: dict[str, tuple[float, float]]
    touching: list[tuple[str, str]] = field(default_factory=list)

    @property
    def robots(self) -> dict[str, None]:
        return dict.fromkeys(self.where)

    def truths(self) -> dict[str, Pose2D]:
        return {n: Pose2D(x, y, 0.0) for n, (x, y) in self.where.items()}

    def robot_contacts(self) -> list[tuple[str, str]]:
        return self.touching


def play(start: dict[str, tuple[float, float]], speed: dict[str, float], seconds: float = 5.0) -> FleetWatch:
    """Robots driving along x at constant speeds from ``start``, sampled at 20 Hz."""
    scene = Truth(dict(start))
    watch = FleetWatch(scene, AISLE)
    for k in range(int(seconds * 20) + 1):
        t = k / 20
        scene.where = {n: (x + speed[n] * t, y) for n, (x, y) in start.items()}
        watch.sample(t)
    return watch


def test_two_robots_driving_at_each_other_in_one_aisle_meet_head_on_once():
    w = play({"r1": (0.5, 0.5), "r2": (4.5, 0.5)}, {"r1": 0.2, "r2": -0.2})
    assert [(m.robots, m.aisle, m.head_on) for m in w.meetings] == [(("r1", "r2"), 0, True)]
    assert round(w.meetings[0].nearest_m, 2) == 2.0
    [check] = fleet_checks(FleetExpect(head_on_in_aisle=0), w, {}, {}, 0.0)
    assert not check.passed and check.actual.startswith("1 (r1-r2 in aisle 0 at 0.0 s (2.00 m))")


def test_a_robot_driving_at_one_standing_in_the_aisle_is_head_on_too():
    w = play({"r1": (0.5, 0.5), "r2": (4.5, 0.5)}, {"r1": 0.3, "r2": 0.0})
    assert [m.head_on for m in w.meetings] == [True]


def test_following_one_that_drives_off_and_standing_apart_are_meetings_not_head_on():
    follow = play({"r1": (0.5, 0.5), "r2": (2.0, 0.5)}, {"r1": 0.3, "r2": 0.2})
    apart = play({"r1": (0.5, 0.5), "r2": (4.5, 0.5)}, {"r1": 0.0, "r2": 0.0})
    assert [m.head_on for m in follow.meetings] == [False] and [m.head_on for m in apart.meetings] == [False]
    [check] = fleet_checks(FleetExpect(head_on_in_aisle=0), follow, {}, {}, 0.0)
    assert check.passed and check.actual == "0 (none); 1 time(s) two robots shared an aisle"


def test_one_in_the_aisle_and_one_outside_closing_is_no_meeting():
    w = play({"r1": (0.5, 0.5), "r2": (5.5, 2.0)}, {"r1": 0.2, "r2": -0.2})
    assert w.meetings == []


def test_each_touch_counts_once_from_its_onset():
    scene = Truth({"r1": (0.0, 0.0), "r2": (0.3, 0.0)})
    watch = FleetWatch(scene, AISLE)
    for t, touching in enumerate([[], [("r1", "r2")], [("r1", "r2")], [], [("r1", "r2")]]):
        scene.touching = touching
        watch.pre_chunk(float(t))
    assert watch.contacts == [(1.0, "r1", "r2"), (4.0, "r1", "r2")]
    [check] = fleet_checks(FleetExpect(robot_contacts=0), watch, {}, {}, 0.0)
    assert not check.passed and check.actual == "2 (r1-r2 at 1.0 s, r1-r2 at 4.0 s)"


def test_the_others_must_drive_while_a_robot_is_held():
    w = play({"r1": (0.5, 0.5), "r2": (0.5, 3.0)}, {"r1": 0.2, "r2": 0.0}, seconds=10.0)
    assert abs(w.driven("r1", 2.0, 7.0) - 1.0) < 1e-6 and w.driven("r2", 2.0, 7.0) == 0.0
    x = FleetExpect(others_drive_while_stopped=0.5)
    [held_r2] = fleet_checks(x, w, {}, {"r1": [], "r2": [(2.0, 7.0)]}, 0.0)
    [held_r1] = fleet_checks(x, w, {}, {"r1": [(2.0, 7.0)], "r2": []}, 0.0)
    [nobody] = fleet_checks(x, w, {}, {"r1": [], "r2": []}, 0.0)
    assert held_r2.passed and held_r2.actual == "r1 1.00 m while r2 was held from 2.0 s"
    assert not held_r1.passed and not nobody.passed and nobody.actual == "no robot was held by an e-stop"


def test_pots_of_the_fleet_count_every_robot_s_inspections():
    summary = {"pots": {"total": 3, "inspected": 2, "not_inspected": ["P3"]},
               "robots": {"r1": {"done": ["P1"]}, "r2": {"done": ["P2"]}}}
    checks = [fleet_checks(FleetExpect(pots=want), FleetWatch(Truth({}), AISLE), summary, {}, 0.0)[0]
              for want in ("all", 2, ["P1", "P2"], ["P3"])]
    assert [c.passed for c in checks] == [False, True, True, False]
    assert checks[0].actual == "2 of 3 inspected (r1 1, r2 1); not inspected: P3"
