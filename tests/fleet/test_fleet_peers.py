"""Robots keep out of each other's footprints (issue 34), on ``lupin fleet sim``'s robots: one
MuJoCo world, a runtime each in lock-step, each link on the TLS router under its certificate.
r2 stands e-stopped at its dock, straight in r1's way north along the greenhouse's west end; r1
is sent past it. Its lidar sees only r2's lidar puck and arm (the chassis is below the scan
plane): r2 says where it is through the router, r1 plans round its footprint, gets there, and
judged on ground truth the chassis never touch and keep a body's gap."""
from __future__ import annotations

import math

import pytest

from fleet.certs import member_files
from hw.odometry import Pose2D
from mission.jobs.fleet_sim import start_fleet_sim
from mission.runtime.config import LupinConfig, with_overrides
from nav.navigator import State
from sim.generate import generate_world
from tests.fleet.conftest import wait_for

pytestmark = pytest.mark.slow

GOAL = Pose2D(1.0, 2.6, math.pi / 2)
"""World frame: the west end of the third aisle, 1.1 m north of r2's dock at (1.0, 1.5); r1
docks 1 m south of r2, both facing east, so the straight way runs through r2."""
GAP = 0.15
"""Chassis to chassis, m, r1 keeps at least (two 0.21 m corner radii from centre to centre):
the layer's 0.1 m margin less what the two robots' beliefs of where they are may differ by."""


def test_a_robot_plans_round_a_stopped_robot_in_its_way_and_never_touches_it(router, certs, tmp_path):
    world = generate_world(3, 4, 1, robots=2)
    config = with_overrides(LupinConfig(), {"sim": {"realtime": False, "seed": 1}})
    fleet = start_fleet_sim(world, config, ["r1", "r2"], tmp_path, lambda: 0.0)
    try:
        fleet.join(router, lambda name: member_files(certs, name), None)
        r1, r2 = fleet.services["r1"], fleet.services["r2"]
        r2.estop(True)
        touches, gaps = [], []

        def judge(now: float) -> None:  # ground truth, judging only
            touches.extend(fleet.scene.robot_contacts())
            a, b = fleet.scene.truths()["r1"], fleet.scene.truths()["r2"]
            gaps.append(math.hypot(a.x - b.x, a.y - b.y))

        r1.robot.scheduler.every("judge", 20.0, judge)
        peers = fleet.links[0].peers
        assert wait_for(lambda: (fleet.step(), r1.nav.readiness.active and peers.around())[1], 60)
        (seen,) = peers.around()
        assert seen.name == "r2" and math.hypot(seen.x - 0.0, seen.y - 1.0) < 0.1  # r2's belief, r1's map frame
        spawn = world.spawn_poses[0]
        goal = Pose2D(GOAL.x - spawn.x, GOAL.y - spawn.y, GOAL.yaw)  # r1's map frame (its dock faces east)
        r1.nav.navigate_to(goal, r1.now, timeout=120.0)
        while r1.nav.active:
            fleet.step()
        assert r1.nav.state is State.SUCCEEDED, r1.nav.reason
        truth = fleet.scene.truths()["r1"]
        assert math.hypot(truth.x - GOAL.x, truth.y - GOAL.y) < 0.3
        assert touches == [], f"r1 touched r2 {len(touches)} times"
        assert min(gaps) >= 2 * 0.21 + GAP, f"r1 came within {min(gaps):.2f} m of r2's centre"
        assert max(gaps) > 1.0  # it did drive past r2, not stop short
    finally:
        fleet.close()
