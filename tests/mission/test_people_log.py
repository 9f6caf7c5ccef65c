"""The people judge's ground truth (mission/jobs/people_log.py) on real physics: clearance and
contacts count only while the robot moves, the arm counts as body, and every time a walker comes
within 1.0 m is an encounter. The robot is carried by the test (teleported along a line each
10 ms chunk), so the judge sees true motion without the control stack."""
from __future__ import annotations

import math

import pytest

from arm.presets import PRESETS, ARM_JOINTS
from hw.config import HwConfig
from mission.jobs.people_log import PeopleLog, arm_points
from arm.config import KinematicsConfig
from sim.backend import SimRobot
from sim.config import SimConfig
from sim.world import Floor, Pose2, Walker, World

pytestmark = pytest.mark.slow


class _Carry:
    """Moves the robot east at ``speed`` from ``x0`` until ``until`` (then it stands)."""

    def __init__(self, sim, x0, speed, until):
        self.sim, self.x0, self.speed, self.until = sim, x0, speed, until

    def pre_chunk(self, t):
        self.sim.place(self.x0 + self.speed * min(t, self.until), 1.0, 0.0)


def _sim(walker: dict, x0: float, speed: float, until: float, driving=None) -> tuple[SimRobot, PeopleLog]:
    w = Walker(**{"id": "W1", **walker})
    world = World(name="judge", floor=Floor(x=8.0, y=2.0), spawn=Pose2(x=x0, y=1.0), pots=[], walkers=[w])
    sim = SimRobot(world, SimConfig(), HwConfig())
    sim.engine.attach(_Carry(sim, x0, speed, until))
    return sim, PeopleLog(sim, driving=driving).attach()


def test_a_walker_walking_into_a_robot_standing_still_is_not_the_robots_doing():
    sim, log = _sim({"path": [[5.0, 1.0], [0.5, 1.0]], "speed": 1.0, "yields": False}, 1.0, 0.0, 0.0)
    sim.engine.advance_to(3.8)
    assert log.least_any < 0 and log.contacts.onsets          # it walked right into the robot
    assert log.moving_contacts == [] and math.isinf(log.clearance)  # but the robot never moved
    assert len(log.encounters) == 1 and log.encounters[0]["nearest_m"] < 0


def test_a_robot_driving_past_a_worker_is_judged_and_met_once():
    sim, log = _sim({"path": [[4.0, 1.6]]}, 1.0, 0.5, 10.0)  # the worker 0.6 m north of its line
    sim.engine.advance_to(10.0)                                # driven from x = 1 to 6
    body = 0.6 - 0.1125 - 0.07 - 0.22                           # legs across the heading (+x): 0.1125 m off
    assert log.clearance == pytest.approx(body, abs=0.02)      # the arm, folded, stays over the footprint
    assert len(log.encounters) == 1 and log.moving_contacts == []
    assert log.close_at["W1"][1] == pytest.approx(4.0, abs=0.1)
    met = log.encounters[0]  # the encounter keeps where and when its least while moving was
    assert met["nearest_moving_m"] == pytest.approx(log.clearance) and met["moving_at"][1] == pytest.approx(4.0, abs=0.1)


def test_a_robot_driving_into_a_worker_is_a_contact_while_moving():
    sim, log = _sim({"path": [[4.0, 1.0]], "posture": "crouching"}, 1.0, 0.5, 10.0)
    sim.engine.advance_to(6.0)
    assert log.moving_contacts and log.moving_contacts[0][1].startswith("walker_W1_body")
    assert log.clearance < 0 and len(log.encounters) == 1


def test_a_robot_carried_while_its_wheels_are_told_to_stand_is_not_moving():
    """A cart pusher who walks on shoves the robot along: it moves, but not of its own drive."""
    told = {"turn": True}
    sim, log = _sim({"path": [[4.0, 1.0]], "posture": "crouching"}, 1.0, 0.5, 10.0, lambda: told["turn"])
    sim.engine.advance_to(2.0)                      # driving: judged
    assert log.clearance < math.inf and not log.moving_contacts
    told["turn"] = False
    sim.engine.advance_to(6.0)                      # carried into the worker with its wheels told to stand
    assert log.contacts.onsets and log.moving_contacts == []
    assert log.clearance > 0.5                      # the last judged moment was 0.5 s after it stopped driving


def test_the_arm_reaching_out_is_part_of_the_body():
    k = KinematicsConfig()
    folded, reaching = arm_points(PRESETS["home"], k), arm_points(PRESETS["inspect"], k)
    assert max(math.hypot(*p) for p in reaching) > max(math.hypot(*p) for p in folded) + 0.1
    assert len(ARM_JOINTS) == 4
